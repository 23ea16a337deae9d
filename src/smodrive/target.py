"""The real-time core on a Cortex-M4F: the vector runner (core/target) built
for the host and for QEMU's ``mps2-an386`` board, test vectors, a bit-for-bit
comparison of the two builds, processor-in-the-loop runs against the host
plant, and cycle counts from the emulator's instruction trace.

The runner is the same C for both (``core/target/smd_vec.c``); the host
build is the simulator's float core (same sources, ``-ffp-contract=off``).
Two math variants: ``libm`` (each platform's C library: glibc on the host,
newlib on the target) and ``fmath`` (the core's portable float math,
``smodrive/smd_fmath.h``, on both), see :data:`FMATH_DEFINES`.

Needs ``arm-none-eabi-gcc`` (Debian: gcc-arm-none-eabi, libnewlib-arm-none-eabi)
and ``qemu-system-arm`` (Debian: qemu-system-arm); ``make toolchain``
installs them.
"""

from __future__ import annotations

import ctypes as ct
import dataclasses
import hashlib
import os
import shutil
import struct
import subprocess
import tempfile
import threading
from pathlib import Path

import numpy as np

from . import _ffi
from .params import ParameterError

MAGIC = 0x56444D53
VERSION = 1
CASE_END, CASE_DRIVE, CASE_TABLES, CASE_BLOCK = 0, 1, 2, 3
BLOCKS = {"transforms": 1, "svm": 2, "pi": 3, "dbpc": 4, "smdo": 5, "emf_pos": 6, "pll": 7,
          "bandpass": 8, "lcl_smo": 9, "linobs": 10, "math": 11, "table6": 12}
#: the math block's outputs per step, in order
MATH_FUNCS = ("sin", "cos", "atan2", "exp", "expm1", "floor", "sqrt", "fabs")
#: the core's math hooks mapped to its portable float math
FMATH_DEFINES = ['-DSMD_MATH_HEADER="smodrive/smd_fmath.h"', "-DSMD_SINF=smd_sinf",
                 "-DSMD_COSF=smd_cosf", "-DSMD_SINCOSF=smd_sincosf", "-DSMD_ATAN2F=smd_atan2f",
                 "-DSMD_EXPF=smd_expf", "-DSMD_EXPM1F=smd_expm1f"]
M4_FLAGS = ["-mcpu=cortex-m4", "-mthumb", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard"]
COMMON_FLAGS = ["-std=c99", "-O2", "-ffp-contract=off", "-Wall", "-Wextra", "-Werror"]
IN_WORDS = ct.sizeof(_ffi.DriveIn) // 4
VIEW_BYTES = ct.sizeof(_ffi.DriveView)
OUT_BYTES = ct.sizeof(_ffi.DriveOut)  # d_abc, fault, pwm_off
SAMPLE_BYTES = 4 + OUT_BYTES + VIEW_BYTES  # status, smd_drive_out, view


class TargetError(RuntimeError):
    """The target toolchain is missing, a build failed or the emulator did."""


# ---------------------------------------------------------------- sources --

def c_root() -> Path:
    """The folder holding core/include, core/src and core/target: the source
    tree this package was built from, or the copy installed with it."""
    here = Path(__file__).resolve().parent
    for cand in (here / "c_src", here.parents[1]):
        if (cand / "core" / "target" / "smd_vec.c").is_file():
            return cand
    raise TargetError("the C sources of the core are not installed with this package; "
                      "run from a source checkout")


def _tool(name: str, debian: str) -> str:
    path = shutil.which(name)
    if path is None:
        raise TargetError(f"{name} not found: install Debian's {debian} (make toolchain)")
    return path


def _sources(root: Path, kind: str) -> list[Path]:
    core = sorted((root / "core" / "src").glob("*.c"))
    tgt = root / "core" / "target"
    if kind == "host":
        return core + [tgt / "smd_vec.c", tgt / "host_io.c"]
    return core + [tgt / "smd_vec.c", tgt / "m4" / "semihost_io.c", tgt / "m4" / "startup.c"]


def _cache_dir() -> Path:
    base = os.environ.get("SMODRIVE_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "smodrive")
    return Path(base) / "target"


def build(kind: str, math: str = "fmath", out_dir: Path | None = None,
          extra: tuple[str, ...] = ()) -> Path:
    """The runner for `kind` ("host" or "m4") with `math` ("libm" or
    "fmath"), built once per content of its sources and flags; `extra`
    flags go last (tests build deliberately wrong variants with them)."""
    if kind not in ("host", "m4") or math not in ("libm", "fmath"):
        raise ValueError(f"build({kind!r}, {math!r})")
    root = c_root()
    srcs = _sources(root, kind)
    headers = sorted((root / "core").glob("*/**/*.h")) + [root / "core/target/m4/mps2_an386.ld"]
    flags = list(COMMON_FLAGS) + (FMATH_DEFINES if math == "fmath" else [])
    tail_flags = list(extra)
    if kind == "host":
        cc = shutil.which("gcc") or shutil.which("cc")
        if cc is None:
            raise TargetError("no host C compiler (gcc)")
        cmd_tail = ["-lm"]
    else:
        cc = _tool("arm-none-eabi-gcc", "gcc-arm-none-eabi")
        flags = M4_FLAGS + flags + ["-g", "-ffunction-sections", "-fdata-sections"]
        cmd_tail = ["-nostartfiles", "-T", str(root / "core/target/m4/mps2_an386.ld"),
                    "-Wl,--gc-sections", "-lm", "-lc", "-lgcc"]
    flags += tail_flags
    h = hashlib.sha256(" ".join([cc, kind, math] + flags + cmd_tail).encode())
    for f in srcs + headers:
        h.update(f.read_bytes())
    out_dir = Path(out_dir) if out_dir else _cache_dir()
    exe = out_dir / f"smd_vec_{kind}_{math}_{h.hexdigest()[:12]}{'.elf' if kind == 'm4' else ''}"
    if exe.exists():
        return exe
    out_dir.mkdir(parents=True, exist_ok=True)
    tmp = exe.with_suffix(exe.suffix + f".tmp{os.getpid()}")
    cmd = [cc, *flags, f"-I{root / 'core/include'}", f"-I{root / 'core/target'}",
           *map(str, srcs), "-o", str(tmp), *cmd_tail]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        raise TargetError(f"building the {kind} runner failed:\n{res.stderr[-3000:]}")
    os.replace(tmp, exe)
    return exe


# ----------------------------------------------------------------- vectors --

def _config_words(obj: ct.Structure) -> bytes:
    """A config struct as the runner reads it (core/target/smd_cfg_read.h):
    each scalar a 4-byte little-endian word in declaration order, pointers
    skipped."""
    out = bytearray()
    for name, typ in obj._fields_:
        val = getattr(obj, name)
        if typ is ct.c_void_p or (isinstance(typ, type) and issubclass(typ, ct._Pointer)):
            continue
        if isinstance(typ, type) and issubclass(typ, ct.Structure):
            out += _config_words(val)
        elif isinstance(typ, type) and issubclass(typ, ct.Array):
            for x in val:
                out += _config_words(x) if isinstance(x, ct.Structure) else _scalar(typ._type_, x)
        else:
            out += _scalar(typ, val)
    return bytes(out)


def _scalar(typ, val) -> bytes:
    if typ is ct.c_float:
        return struct.pack("<f", val)
    if typ in (ct.c_int, ct.c_int32):
        return struct.pack("<i", val)
    raise TypeError(f"no 4-byte wire form for {typ}")


def _tables_bytes(tables) -> bytes:
    if tables is None:
        return struct.pack("<ii", 0, 0)
    m, lin = np.ascontiguousarray(tables[0], "<f4"), np.ascontiguousarray(tables[1], "<f4")
    return (struct.pack("<i", m.shape[0]) + m.tobytes()
            + struct.pack("<i", lin.shape[0]) + lin.tobytes())


@dataclasses.dataclass
class DriveCase:
    """The whole drive step on a recorded or synthetic input sequence."""
    name: str
    config: _ffi.DriveConfig
    tables: tuple | None
    start: tuple[float, float, float]  # theta0, w0 (electrical), i_q0
    inputs: np.ndarray  # (n, 10) float32, smd_drive_in per sample

    def encode(self) -> bytes:
        x = np.ascontiguousarray(self.inputs, dtype="<f4")
        if x.ndim != 2 or x.shape[1] != IN_WORDS:
            raise ValueError(f"{self.name}: inputs must be (n, {IN_WORDS})")
        return (struct.pack("<i", CASE_DRIVE) + _config_words(self.config)
                + _tables_bytes(self.tables) + struct.pack("<fff", *self.start)
                + struct.pack("<i", x.shape[0]) + x.tobytes())


@dataclasses.dataclass
class BlockCase:
    """One block of the core on the runner's PRNG inputs (core/target/smd_vec.c)."""
    name: str
    block: str
    n: int
    seed: int

    def encode(self) -> bytes:
        return struct.pack("<iiiI", CASE_BLOCK, BLOCKS[self.block], self.n, self.seed)


@dataclasses.dataclass
class TablesCase:
    """The LCL observer tables the later lcl_smo / linobs block cases use."""
    name: str
    tables: tuple

    def encode(self) -> bytes:
        return (struct.pack("<i", CASE_TABLES) + _tables_bytes(self.tables)
                + struct.pack("<ff", self.tables[2], self.tables[3]))


def write_vectors(path: Path, cases) -> None:
    with open(path, "wb") as f:
        f.write(struct.pack("<II", MAGIC, VERSION))
        for c in cases:
            f.write(c.encode())
        f.write(struct.pack("<i", CASE_END))


def read_outputs(path: Path) -> list[tuple[int, bytes]]:
    """(kind, outputs) of each case of a runner's output file."""
    data = Path(path).read_bytes()
    if len(data) < 4 or struct.unpack_from("<I", data)[0] != MAGIC:
        raise TargetError(f"{path}: not an output of the runner")
    pos, out = 4, []
    while True:
        if pos + 4 > len(data):
            raise TargetError(f"{path}: truncated after {len(out)} cases")
        kind = struct.unpack_from("<i", data, pos)[0]
        if kind == CASE_END:
            n, err = struct.unpack_from("<ii", data, pos + 4)
            if err or n != len(out):
                raise TargetError(f"{path}: the runner reported an output error")
            return out
        size = struct.unpack_from("<i", data, pos + 4)[0]
        out.append((kind, data[pos + 8:pos + 8 + size]))
        pos += 8 + size


def drive_outputs(body: bytes) -> dict[str, np.ndarray]:
    """A drive case's outputs: init status, then per sample status, duties
    and the controller's view (smd_drive_view) as named arrays."""
    init = struct.unpack_from("<i", body)[0]
    n = (len(body) - 4) // SAMPLE_BYTES
    dt = np.dtype([("status", "<i4"), ("d_abc", "<f4", 3), ("fault", "<u4"), ("pwm_off", "<i4"),
                   ("view", "V%d" % VIEW_BYTES)])
    rec = np.frombuffer(body, dtype=dt, count=n, offset=4)
    view = np.frombuffer(rec["view"].tobytes(), dtype=np.dtype(
        [(f, "<f4", 2) if t is _ffi.Cplx else
         (f, {ct.c_int: "<i4", ct.c_uint32: "<u4"}.get(t, "<f4"))
         for f, t in _ffi.DriveView._fields_]))
    out = {"init": np.array(init), "status": rec["status"], "d_abc": rec["d_abc"],
           "fault": rec["fault"], "pwm_off": rec["pwm_off"]}
    for f in view.dtype.names:
        out[f] = view[f]
    return out


# --------------------------------------------------------------- running --

def run_host(exe: Path, vec: Path, out: Path) -> None:
    res = subprocess.run([str(exe), str(vec), str(out)], capture_output=True, text=True,
                         timeout=600)
    if res.returncode != 0:
        raise TargetError(f"host runner failed ({res.returncode}): {res.stderr.strip()}")


def qemu_command(elf: Path, *args: str, trace: Path | None = None) -> list[str]:
    qemu = _tool("qemu-system-arm", "qemu-system-arm")
    arg = ",".join(f"arg={a}" for a in ("smd_vec", *args))
    cmd = [qemu, "-M", "mps2-an386", "-nographic", "-monitor", "none", "-serial", "none",
           "-semihosting-config", f"enable=on,target=native,{arg}", "-kernel", str(elf)]
    if trace is not None:
        # one instruction a translation block, each logged as it executes
        cmd += ["-singlestep", "-d", "exec,nochain", "-D", str(trace)]
    return cmd


def run_m4(elf: Path, vec: Path, out: Path, timeout: float = 600.0) -> None:
    for p in (elf, vec, out):
        if "," in str(p) or " " in str(p):
            raise TargetError(f"QEMU's semihosting command line cannot carry {p}")
    res = subprocess.run(qemu_command(elf, str(vec), str(out)), capture_output=True,
                         text=True, timeout=timeout)
    if res.returncode != 0:
        raise TargetError(f"the Cortex-M4F runner failed under QEMU ({res.returncode}): "
                          f"{(res.stdout + res.stderr).strip()[-2000:]}")


def ulp_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """|a - b| in units in the last place of float32 (0 for two NaNs)."""
    ia = a.view("<i4").astype(np.int64)
    ib = b.view("<i4").astype(np.int64)
    ia = np.where(ia < 0, -(ia & 0x7FFFFFFF), ia)
    ib = np.where(ib < 0, -(ib & 0x7FFFFFFF), ib)
    d = np.abs(ia - ib)
    return np.where(np.isnan(a) & np.isnan(b), 0, d)


@dataclasses.dataclass
class CaseDiff:
    name: str
    words: int
    differ: int      # words that are not bit-identical (NaN = NaN)
    max_ulp: int


def compare(cases, host_out: Path, m4_out: Path) -> list[CaseDiff]:
    """Per case: how many 4-byte output words differ between the builds."""
    a, b = read_outputs(host_out), read_outputs(m4_out)
    if len(a) != len(b) or len(a) != len(cases):
        raise TargetError(f"case count differs: {len(cases)} written, host {len(a)}, "
                          f"target {len(b)}")
    out = []
    for c, (ka, xa), (kb, xb) in zip(cases, a, b):
        if ka != kb or len(xa) != len(xb):
            out.append(CaseDiff(c.name, max(len(xa), len(xb)) // 4, -1, -1))
            continue
        wa = np.frombuffer(xa, "<u4")
        wb = np.frombuffer(xb, "<u4")
        fa, fb = wa.view("<f4"), wb.view("<f4")
        diff = (wa != wb) & ~(np.isnan(fa) & np.isnan(fb))
        u = ulp_distance(fa[diff], fb[diff]) if diff.any() else np.zeros(1, np.int64)
        out.append(CaseDiff(c.name, wa.size, int(diff.sum()), int(u.max())))
    return out


def run_both(cases, math: str, work: Path, m4_extra: tuple[str, ...] = ()) -> tuple[Path, Path]:
    """Write `cases`, run them on the host and on the emulated M4F; returns
    the two output files."""
    work.mkdir(parents=True, exist_ok=True)
    tag = math + ("_" + hashlib.sha256(" ".join(m4_extra).encode()).hexdigest()[:6]
                  if m4_extra else "")
    vec, ho, mo = work / f"vectors_{tag}.bin", work / f"host_{tag}.bin", work / f"m4_{tag}.bin"
    write_vectors(vec, cases)
    run_host(build("host", math), vec, ho)
    run_m4(build("m4", math, extra=m4_extra), vec, mo)
    return ho, mo


# ----------------------------------------------------- recorded scenarios --

def record(s, n: int):
    """Run scenario `s` for n samples with the host controller, through the
    split engine step; returns (drive case inputs (n, 10) float32, outputs:
    duties (n, 3), status (n,), views (list), log (n, channels))."""
    from .simulate import Engine

    eng = Engine(s)
    buf = eng._buf
    lib = _ffi.lib
    ins = np.zeros((n, IN_WORDS), np.float32)
    duty = np.zeros((n, 3), np.float32)
    log = np.zeros((n, lib_channels()), float)
    din, dout, view = _ffi.DriveIn(), _ffi.DriveOut(), _ffi.DriveView()
    row = (ct.c_double * lib_channels())()
    for k in range(n):
        lib.smd_engine_ext_inputs(buf, ct.byref(din))
        ins[k] = np.frombuffer(bytes(din), "<f4")
        st = lib.smd_engine_host_step(buf, ct.byref(din), ct.byref(dout), ct.byref(view))
        duty[k] = dout.d_abc[:]
        lib.smd_engine_ext_apply(buf, ct.byref(dout), st, ct.byref(view), row)
        log[k] = row[:]
    return ins, duty, log, eng


def lib_channels() -> int:
    from .simulate import CHANNELS
    return len(CHANNELS)


def _start_of(eng) -> tuple[float, float, float]:
    from .simulate import _wrap_pi
    st = eng._st
    return (_wrap_pi(st.theta0), st.w0, st.i_q0)


def drive_case(name: str, s, n: int) -> DriveCase:
    """Scenario `s`'s drive on its first n recorded samples."""
    ins, _, _, eng = record(s, n)
    return DriveCase(name, eng._dc, eng._tables, _start_of(eng), ins)


def mode_scenarios() -> list[tuple[str, object]]:
    """Every composition of the one drive (smd_drive.h) on a scenario that
    exercises it: the yang2018 motor (current pi/dbpc/robust_dbpc x
    position encoder/smdo_emf x start running/handover/if) at 1500 r/min
    with the rated load (from standstill for I/f), and the yao2022 LCL drive
    (pi x encoder/lcl_smo_pll/lcl_linear x the three starts, and the two
    reference reaching laws) at 60 kr/min."""
    import itertools

    from .scenarios import drive, yao2022

    out = []
    for cur, pos, start in itertools.product(("pi", "dbpc", "robust_dbpc"),
                                             ("encoder", "smdo_emf"),
                                             ("running", "handover", "if")):
        base = drive.if_start() if start == "if" else drive._table1_steady("x")
        out.append((f"{cur}.{pos}.{start}",
                    base.with_controller(current=cur, position=pos, start=start)))
    for pos, start in itertools.product(("encoder", "lcl_smo_pll", "lcl_linear"),
                                        ("running", "handover", "if")):
        out.append((f"lcl.pi.{pos}.{start}",
                    yao2022.steady(60e3).with_controller(position=pos, start=start)))
    for law in ("tde17", "tde18"):
        out.append((f"lcl.pi.lcl_smo_pll.running.{law}",
                    yao2022.steady(60e3).with_controller(law=law)))
    return out


#: the input columns of smd_drive_in
IN_COLS = ("i_a", "i_b", "i1_a", "i1_b", "theta_enc", "w_enc", "u_dc", "w_ref", "i_d_ref",
           "i_q_ref")


def variants(case: DriveCase) -> list[DriveCase]:
    """Edge cases of a recorded drive case: the same run mirrored (negative
    speed: phases b and c swapped, angles and speeds negated), standstill
    (zero speed, constant inputs), saturation (current and speed references
    far beyond the limits, a quarter of the DC link) and faults (NaN, +-inf
    and 1e30 at single samples of each input, u_dc = 0 for ten samples)."""
    c = {k: i for i, k in enumerate(IN_COLS)}
    x = case.inputs.astype(np.float32)
    th0, w0, iq0 = case.start
    m = x.copy()
    m[:, c["i_b"]] = -x[:, c["i_a"]] - x[:, c["i_b"]]
    m[:, c["i1_b"]] = -x[:, c["i1_a"]] - x[:, c["i1_b"]]
    for col in ("theta_enc", "w_enc", "w_ref", "i_q_ref"):
        m[:, c[col]] = -x[:, c[col]]
    z = np.repeat(x[:1], x.shape[0], axis=0)
    z[:, c["w_enc"]] = z[:, c["w_ref"]] = 0.0
    sat = x.copy()
    sat[:, c["i_q_ref"]] *= 50.0
    sat[:, c["i_d_ref"]] += 30.0
    sat[:, c["w_ref"]] *= 5.0
    sat[:, c["u_dc"]] *= 0.25
    f = x.copy()
    bad = (np.nan, np.inf, 1e30, -np.inf)
    for j, col in enumerate(IN_COLS):
        for q, v in enumerate(bad):
            k = 40 + 11 * (4 * j + q)
            if k < f.shape[0]:
                f[k, c[col]] = v
    f[min(30, f.shape[0] - 1):min(40, f.shape[0]), c["u_dc"]] = 0.0
    return [
        DriveCase(case.name + ".mirrored", case.config, case.tables, (-th0, -w0, -iq0), m),
        DriveCase(case.name + ".standstill", case.config, case.tables, (th0, 0.0, 0.0), z),
        DriveCase(case.name + ".saturated", case.config, case.tables, case.start, sat),
        DriveCase(case.name + ".faults", case.config, case.tables, case.start, f),
    ]


#: the paper scenarios whose recorded inputs the vectors replay at length
PAPER_CASES = ("yang2018.fig7a", "yao2022.steady.100k")


def standard_cases(samples: int = 600, paper_samples: int = 3000) -> list:
    """The vector set of the target test: every block of the core on its
    PRNG inputs (with non-finite values in the last tenth), every drive
    composition recorded from its scenario with the edge-case variants,
    the paper scenarios' recorded inputs, and a rejected composition."""
    from .scenarios import catalogue
    from .simulate import drive_config

    cases: list = [BlockCase(f"block.{b}", b, 3000, 1000 + i)
                   for i, b in enumerate(("transforms", "svm", "pi", "dbpc", "smdo", "emf_pos",
                                          "pll", "bandpass", "math"))]
    tables = None
    for name, s in mode_scenarios():
        rec = drive_case("drive." + name, s, samples)
        cases += [rec, *variants(rec)]
        tables = tables or rec.tables
    cases += [TablesCase("tables", tables),
              BlockCase("block.lcl_smo.a", "lcl_smo", 3000, 3000),  # seed % 3: the law
              BlockCase("block.lcl_smo.b", "lcl_smo", 3000, 3001),
              BlockCase("block.lcl_smo.c", "lcl_smo", 3000, 3002),
              BlockCase("block.linobs", "linobs", 3000, 3003),
              BlockCase("block.table6", "table6", 1000, 3004)]
    cat = catalogue()
    for name in PAPER_CASES:
        cases.append(drive_case("paper." + name, cat[name](), paper_samples))
    # a composition the drive rejects (DBPC through the LCL filter): both
    # builds must answer SMD_ERR_COMBINATION
    bad = cat["yao2022.steady.100k"]()
    cfg = drive_config(bad, tables)
    cfg.current = 1
    cases.append(DriveCase("drive.rejected.dbpc_lcl", cfg, tables, (0.0, 0.0, 0.0),
                           np.zeros((5, IN_WORDS), np.float32)))
    return cases


# ------------------------------------------------------------------- PIL --

class _Link:
    """A controller in another process, fed sample by sample through a FIFO
    pair: the runner on the emulated M4F (semihosting files) or on the
    host. Speaks the streamed drive case of core/target/smd_vec.h."""

    def __init__(self, kind: str, math: str, case: DriveCase, work: Path):
        self.dir = Path(tempfile.mkdtemp(prefix="smd_pil_", dir=work))
        fin, fout = self.dir / "in", self.dir / "out"
        os.mkfifo(fin)
        os.mkfifo(fout)
        exe = build(kind, math)
        cmd = (qemu_command(exe, str(fin), str(fout)) if kind == "m4"
               else [str(exe), str(fin), str(fout)])
        self.proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        self.timer = threading.Timer(600.0, self.proc.kill)
        self.timer.start()
        # the runner opens its input first, then its output: the same order
        self.w = open(fin, "wb", buffering=0)
        self.r = open(fout, "rb", buffering=0)
        head = DriveCase(case.name, case.config, case.tables, case.start,
                         np.zeros((0, IN_WORDS), np.float32)).encode()
        self.w.write(struct.pack("<II", MAGIC, VERSION) + head[:-4] + struct.pack("<i", -1))
        magic, kind_, size, init = struct.unpack("<Iiii", self._read(16))
        if magic != MAGIC or kind_ != CASE_DRIVE or size != -1:
            raise TargetError("PIL: unexpected answer from the runner")
        self.init = init

    def _read(self, n: int) -> bytes:
        out = b""
        while len(out) < n:
            chunk = self.r.read(n - len(out))
            if not chunk:
                self.proc.kill()
                msg = (self.proc.stdout.read() or b"").decode(errors="replace")
                raise TargetError(f"PIL: the runner stopped: {msg.strip()[-500:]}")
            out += chunk
        return out

    def step(self, din: bytes) -> bytes:
        self.w.write(din)
        return self._read(SAMPLE_BYTES)

    def close(self) -> None:
        try:
            self.w.close()
            self.r.read()
            self.r.close()
            self.proc.wait(timeout=60)
        finally:
            self.timer.cancel()
            if self.proc.poll() is None:
                self.proc.kill()
            shutil.rmtree(self.dir, ignore_errors=True)


def _closed_loop(s, n: int, controller: str, math: str, work: Path, progress=None) -> dict:
    """Scenario `s` for n samples through the split engine step with the
    controller `controller`: "sim" (the simulator's own, libm), "host" or
    "m4" (the runner on the FIFO link, with `math`). Returns the raw answers
    (status, duties, view per sample), the duties and the log."""
    from .simulate import CHANNELS, Engine, _wrap_pi

    nch = len(CHANNELS)
    lib = _ffi.lib
    eng = Engine(s)
    din, dout, view = _ffi.DriveIn(), _ffi.DriveOut(), _ffi.DriveView()
    row = (ct.c_double * nch)()
    log = np.zeros((n, nch))
    duty = np.zeros((n, 3), np.float32)
    raw = []
    link = None
    if controller != "sim":
        st0 = eng._st
        case = DriveCase(s.name, eng._dc, eng._tables,
                         (_wrap_pi(st0.theta0), st0.w0, st0.i_q0),
                         np.zeros((0, IN_WORDS), np.float32))
        link = _Link(controller, math, case, work)
    try:
        if link is not None and link.init != 0:
            raise TargetError(f"PIL: the drive's init on the {controller} runner returned "
                              f"{link.init} ({_ffi.status_str(link.init)})")
        for k in range(n):
            lib.smd_engine_ext_inputs(eng._buf, ct.byref(din))
            if link is None:
                st = lib.smd_engine_host_step(eng._buf, ct.byref(din), ct.byref(dout),
                                              ct.byref(view))
                ans = struct.pack("<i", st) + bytes(dout) + bytes(view)
            else:
                ans = link.step(bytes(din))
                st = struct.unpack_from("<i", ans)[0]
                ct.memmove(ct.addressof(dout), ans[4:4 + OUT_BYTES], OUT_BYTES)
                ct.memmove(ct.addressof(view), ans[4 + OUT_BYTES:], VIEW_BYTES)
            raw.append(ans)
            duty[k] = dout.d_abc[:]
            lib.smd_engine_ext_apply(eng._buf, ct.byref(dout), st, ct.byref(view), row)
            log[k] = row[:]
            if progress is not None and k % 256 == 0:
                progress(k / n)
    finally:
        if link is not None:
            link.close()
    if progress is not None:
        progress(1.0)
    return {"raw": b"".join(raw), "duty": duty.astype(float), "log": log}


@dataclasses.dataclass
class PilResult:
    scenario: str
    samples: int
    math: str
    reference: str              # the host-only controller compared with
    max_duty_diff: float        # largest |d_M4F - d_host| over phases and samples
    max_theta_diff_rad: float   # controller angle, wrapped
    max_w_diff: float           # controller speed, electrical rad/s
    max_view_ulp: int           # over every word of status, duties and view
    identical: bool             # status, duties and view bit for bit
    log_host: np.ndarray
    log_pil: np.ndarray


def pil(s, seconds: float, math: str = "fmath", progress=None,
        work: Path | None = None) -> PilResult:
    """Processor in the loop: scenario `s` for `seconds` with the controller
    compiled for the Cortex-M4F on QEMU against the host plant, sample by
    sample, beside the host-only run of the same controller on its own copy
    of the plant: with math "fmath" the host build of the runner (both sides
    the portable float math: expected identical), with "libm" the
    simulator's own controller (glibc against newlib: bounded, not equal)."""
    n = int(round(seconds / s.T_sp))
    work = Path(work) if work else _cache_dir()
    work.mkdir(parents=True, exist_ok=True)
    ref_kind = "host" if math == "fmath" else "sim"
    half = (lambda f: progress(0.5 * f)) if progress else None
    rest = (lambda f: progress(0.5 + 0.5 * f)) if progress else None
    ref = _closed_loop(s, n, ref_kind, math, work, half)
    tgt = _closed_loop(s, n, "m4", math, work, rest)
    from .simulate import CHANNELS

    wa = np.frombuffer(tgt["raw"], "<u4")
    wb = np.frombuffer(ref["raw"], "<u4")
    fa, fb = wa.view("<f4"), wb.view("<f4")
    same = (wa == wb) | (np.isnan(fa) & np.isnan(fb))
    i_th, i_w = CHANNELS.index("theta_hat"), CHANNELS.index("w_hat")
    dth = np.abs(np.angle(np.exp(1j * (tgt["log"][:, i_th] - ref["log"][:, i_th]))))
    return PilResult(
        scenario=s.name, samples=n, math=math,
        reference="host runner (fmath)" if ref_kind == "host" else "simulator (glibc libm)",
        max_duty_diff=float(np.max(np.abs(tgt["duty"] - ref["duty"]))),
        max_theta_diff_rad=float(dth.max()),
        max_w_diff=float(np.max(np.abs(tgt["log"][:, i_w] - ref["log"][:, i_w]))),
        max_view_ulp=int(ulp_distance(fa, fb).max()),
        identical=bool(same.all()), log_host=ref["log"], log_pil=tgt["log"])


# ---------------------------------------------------------------- cycles --

#: Cortex-M4 cycle timings (ARM Cortex-M4 TRM r0p1, sect. 3.3.1, and the FPU
#: TRM's VFP instruction table) as (min, nominal, max) per instruction class;
#: P, the pipeline refill of a taken branch, is 1..3 (nominal 2); a load or
#: store directly after another one pipelines to 1 cycle (nominal and min);
#: SDIV/UDIV take 2..12 (nominal 7). Zero-wait-state memory assumed (code in
#: SRAM/TCM, or flash behind an accelerator that hits).
_P = (1, 2, 3)
_FIXED = {
    "vdiv": (14, 14, 14), "vsqrt": (14, 14, 14),
    "vmla": (3, 3, 3), "vmls": (3, 3, 3), "vnmla": (3, 3, 3), "vnmls": (3, 3, 3),
    "vfma": (3, 3, 3), "vfms": (3, 3, 3), "vfnma": (3, 3, 3), "vfnms": (3, 3, 3),
    "mla": (2, 2, 2), "mls": (2, 2, 2), "sdiv": (2, 7, 12), "udiv": (2, 7, 12),
    "ldrd": (3, 3, 3), "strd": (3, 3, 3), "it": (0, 1, 1), "tbb": (3, 4, 5), "tbh": (3, 4, 5),
}
_LOADSTORE = {"ldr", "ldrb", "ldrh", "ldrsb", "ldrsh", "str", "strb", "strh", "vldr", "vstr",
              "ldrex", "strex"}
_MULTI = {"ldm", "ldmia", "ldmfd", "ldmdb", "stm", "stmia", "stmea", "stmdb", "stmfd",
          "push", "pop", "vpush", "vpop", "vldmia", "vstmia", "vldmdb", "vstmdb", "vldm",
          "vstm"}
_CONDS = ("eq", "ne", "cs", "cc", "hs", "lo", "mi", "pl", "vs", "vc", "hi", "ls", "ge", "lt",
          "gt", "le", "al")


def _reg_count(ops: str) -> int:
    """Registers in a {list} (ranges r4-r7, s16-s23, d8-d9 = 2 words each)."""
    inner = ops[ops.find("{") + 1:ops.find("}")]
    n = 0
    for part in inner.split(","):
        part = part.strip()
        if "-" in part:
            a, b = part.split("-")
            k = int(b.strip()[1:]) - int(a.strip()[1:]) + 1
        else:
            k = 1
        n += 2 * k if part.startswith("d") else k
    return max(n, 1)


@dataclasses.dataclass(frozen=True)
class _Insn:
    size: int
    cls: str          # "branch", "ls" (single load/store), "multi", "fixed"
    cost: tuple       # (min, nominal, max) when not taken / not pipelined
    mnem: str


def _classify(mnem: str, ops: str, size: int) -> _Insn:
    m = mnem.lower().split(".")[0]
    base = m
    for c in _CONDS:  # conditional forms: beq, bxne, ldrne, ...
        if m.endswith(c) and m[:-len(c)] in ("b", "bx", "bl", "blx", "ldr", "str", "mov", "add",
                                             "sub", "cmp", "ldrb", "strb", "it"):
            base = m[:-len(c)]
            break
    if base in ("b", "bl", "bx", "blx", "cbz", "cbnz"):
        return _Insn(size, "branch", (1, 1, 1), base)
    if base in ("pop", "ldm", "ldmia", "ldmfd") and "pc" in ops:
        n = _reg_count(ops)
        return _Insn(size, "branch_multi", (1 + n, 1 + n, 1 + n), base)
    if base in _MULTI:
        n = _reg_count(ops)
        return _Insn(size, "multi", (1 + n, 1 + n, 1 + n), base)
    if base in _FIXED:
        return _Insn(size, "fixed", _FIXED[base], base)
    if base in _LOADSTORE:
        if base == "ldr" and ops.lstrip().startswith("pc"):
            return _Insn(size, "branch", (2, 2, 2), base)
        return _Insn(size, "ls", (2, 2, 2), base)
    if base == "vmov" and ops.count(",") == 2 and ops.split(",")[0].strip()[0] == "r" \
            and ops.split(",")[1].strip()[0] == "r":
        return _Insn(size, "fixed", (2, 2, 2), base)  # two core registers <-> a d register
    if base == "vmov" and ops.count(",") == 3:
        return _Insn(size, "fixed", (2, 2, 2), base)
    return _Insn(size, "fixed", (1, 1, 1), base)


def disassemble(elf: Path) -> tuple[dict[int, _Insn], dict[str, tuple[int, int]]]:
    """{address: instruction} of the ELF's code and {function: (start, end)}."""
    objdump = _tool("arm-none-eabi-objdump", "binutils-arm-none-eabi")
    txt = subprocess.run([objdump, "-d", str(elf)], capture_output=True, text=True,
                         check=True).stdout
    insns: dict[int, _Insn] = {}
    funcs: dict[str, tuple[int, int]] = {}
    cur, start = None, 0
    import re
    head = re.compile(r"^([0-9a-f]+) <([^>]+)>:$")
    line_re = re.compile(r"^\s*([0-9a-f]+):\t([0-9a-f ]+?)\s*\t(\S+)\s*(.*)$")
    last = 0
    for line in txt.splitlines():
        h = head.match(line)
        if h:
            if cur is not None:
                funcs[cur] = (start, last)
            cur, start = h.group(2), int(h.group(1), 16)
            continue
        m = line_re.match(line)
        if not m:
            continue
        addr = int(m.group(1), 16)
        raw = m.group(2).split()
        size = sum(len(x) // 2 for x in raw)
        if m.group(3).startswith(".") or size not in (2, 4):
            continue
        insns[addr] = _classify(m.group(3), m.group(4), size)
        last = addr + size
    if cur is not None:
        funcs[cur] = (start, last)
    return insns, funcs


@dataclasses.dataclass
class Window:
    cycles: tuple[int, int, int]   # min, nominal, max
    instructions: int


def trace_windows(elf: Path, vec: Path, work: Path, timeout: float = 900.0,
                  profile: list | None = None) -> list[Window]:
    """Run the vectors on QEMU with every executed instruction logged (one
    instruction a translation block, streamed through a FIFO) and cost each
    window between smd_mark_begin and smd_mark_end with the Cortex-M4
    timings above. The markers' own instructions are left out. With
    `profile` (a list), a dict per window of the nominal cycles by function
    is appended to it."""
    insns, funcs = disassemble(elf)
    owner = {}
    if profile is not None:
        for name, (a0, a1) in funcs.items():
            for a in range(a0, a1, 2):
                owner[a] = name
    b0, b1 = funcs["smd_mark_begin"]
    e0, e1 = funcs["smd_mark_end"]
    s0, s1 = funcs["mark_sink"]
    work.mkdir(parents=True, exist_ok=True)
    d = Path(tempfile.mkdtemp(prefix="smd_trace_", dir=work))
    fifo = d / "trace"
    os.mkfifo(fifo)
    out = d / "out.bin"
    # leave the start-up code (zeroing .bss) out of the trace
    r0, r1 = funcs["Reset_Handler"]
    cmd = qemu_command(elf, str(vec), str(out), trace=fifo) + [
        "-dfilter", f"0x0..0x{r0:x},0x{r1:x}..0x400000"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    timer = threading.Timer(timeout, proc.kill)
    timer.start()
    windows: list[Window] = []
    try:
        inside = False
        prev: _Insn | None = None
        prev_pc = 0
        prev_ls = False
        c = [0, 0, 0]
        n = 0
        with open(fifo, "r", buffering=1 << 20) as f:
            for line in f:
                lb = line.find("[")
                if lb < 0:
                    continue
                pc = int(line[lb + 10:lb + 18], 16)
                if b0 <= pc < b1:
                    if not inside and profile is not None:
                        profile.append({})
                    inside, prev, c, n, prev_ls = True, None, [0, 0, 0], 0, False
                    continue
                if e0 <= pc < e1:
                    if inside and prev is not None:
                        # the call of smd_mark_end (1 cycle counted; its
                        # refill was not) is not the window's
                        c = [c[0] - 1, c[1] - 1, c[2] - 1]
                        n -= 1
                        windows.append(Window((c[0], c[1], c[2]), n))
                    inside = False
                    continue
                if not inside or s0 <= pc < s1:
                    continue
                ins = insns.get(pc)
                if ins is None:
                    continue
                # the previous instruction's branch outcome is known now
                if prev is not None and prev.cls.startswith("branch") and \
                        pc != prev_pc + prev.size:
                    c = [c[0] + _P[0], c[1] + _P[1], c[2] + _P[2]]
                lo, nom, hi = ins.cost
                if ins.cls == "ls" and prev_ls:
                    lo, nom = 1, 1
                c = [c[0] + lo, c[1] + nom, c[2] + hi]
                if profile is not None:
                    fn = owner.get(pc, "?")
                    profile[-1][fn] = profile[-1].get(fn, 0) + nom
                n += 1
                prev_ls = ins.cls == "ls"
                prev, prev_pc = ins, pc
        proc.wait(timeout=60)
    finally:
        timer.cancel()
        if proc.poll() is None:
            proc.kill()
        shutil.rmtree(d, ignore_errors=True)
    if proc.returncode != 0:
        raise TargetError(f"QEMU trace run failed ({proc.returncode})")
    return windows


#: budgets of the control period at the papers' rates on a 168 MHz
#: Cortex-M4F (STM32F4 class)
F_CPU = 168e6
BUDGET = {"yang2018": 100e-6 * F_CPU, "yao2022": 50e-6 * F_CPU}
#: yao2022 Table VI, cycles on the 150 MHz TMS320F28335
TABLE6_PAPER = {"prediction": 489, "reaching_law": 268, "pll": 28}


@dataclasses.dataclass
class CycleRow:
    name: str
    paper: str            # whose period budget applies
    calls: int
    nominal: float        # mean cycles per call
    low: float            # mean of the lower bound (P = 1, IT folded, DIV 2)
    high: float           # mean of the upper bound (P = 3, DIV 12)
    worst: int            # largest nominal cycles of one call
    instructions: float   # mean instructions per call

    @property
    def budget_share(self) -> float:
        return self.nominal / BUDGET[self.paper]


def cycle_cases(samples: int = 150):
    """What the cycle table measures: each block on its PRNG inputs (the
    first 100 calls, before the edge values), yao2022 Table VI's three
    parts, and the drive step of each composition in its steady phase."""
    from .scenarios import drive, yao2022

    blocks = [("transforms", "yang2018"), ("svm", "yang2018"), ("pi", "yang2018"),
              ("dbpc", "yang2018"), ("smdo", "yang2018"), ("emf_pos", "yang2018"),
              ("pll", "yao2022"), ("bandpass", "yao2022")]
    cases: list = [BlockCase(f"block.{b}", b, 120, 11 + i) for i, (b, _) in enumerate(blocks)]
    paper = {f"block.{b}": p for b, p in blocks}
    modes = []
    for cur in ("pi", "dbpc", "robust_dbpc"):
        for pos in ("encoder", "smdo_emf"):
            modes.append((f"drive {cur} + {pos}", "yang2018",
                          drive._table1_steady("x").with_controller(current=cur, position=pos)))
    modes.append(("drive robust_dbpc + smdo_emf, I/f forced phase", "yang2018",
                  drive.if_start()))
    for pos, law in (("encoder", "proposed"), ("lcl_smo_pll", "proposed"),
                     ("lcl_smo_pll", "tde17"), ("lcl_linear", "proposed")):
        name = f"drive pi + LCL + {pos}" + (f" ({law})" if pos == "lcl_smo_pll" else "")
        modes.append((name, "yao2022",
                      yao2022.steady(100e3).with_controller(position=pos, law=law)))
    tables = None
    for name, p, s in modes:
        c = drive_case(name, s, samples)
        tables = tables or c.tables
        cases.append(c)
        paper[name] = p
    cases += [TablesCase("tables", tables),
              BlockCase("block.lcl_smo", "lcl_smo", 120, 3000),
              BlockCase("block.linobs", "linobs", 120, 3003),
              BlockCase("table6", "table6", 120, 7)]
    paper.update({"block.lcl_smo": "yao2022", "block.linobs": "yao2022",
                  "table6": "yao2022"})
    return cases, paper


def cycle_table(math: str = "fmath", work: Path | None = None,
                samples: int = 150) -> list[CycleRow]:
    """Cycles per call on the Cortex-M4F (QEMU instruction trace weighted by
    the Cortex-M4 timings) for every row of :func:`cycle_cases`."""
    cases, paper = cycle_cases(samples)
    work = Path(work) if work else _cache_dir()
    work.mkdir(parents=True, exist_ok=True)
    vec = work / f"cycles_{math}.bin"
    write_vectors(vec, cases)
    wins = trace_windows(build("m4", math), vec, work)
    rows: list[CycleRow] = []
    pos = 0

    def row(name, ws, p):
        nom = np.array([w.cycles[1] for w in ws], float)
        rows.append(CycleRow(name, p, len(ws), float(nom.mean()),
                             float(np.mean([w.cycles[0] for w in ws])),
                             float(np.mean([w.cycles[2] for w in ws])), int(nom.max()),
                             float(np.mean([w.instructions for w in ws]))))

    for c in cases:
        if isinstance(c, TablesCase):
            continue
        if isinstance(c, DriveCase):
            ws = wins[pos:pos + c.inputs.shape[0]]
            pos += c.inputs.shape[0]
            row(c.name, ws[samples // 3:], paper[c.name])  # after the first third
            continue
        per = {"smdo": 2}.get(c.block, 1) * (3 if c.block == "table6" else 1)
        ws = wins[pos:pos + per * c.n]
        pos += per * c.n
        if c.block == "table6":
            for j, part in enumerate(TABLE6_PAPER):
                row(f"table6.{part}", ws[j::3][:100], "yao2022")
            continue
        row(c.name, ws[:100], paper[c.name])
    if pos != len(wins):
        raise TargetError(f"cycle windows: {len(wins)} traced, {pos} expected")
    return rows


#: the structs whose RAM the size table reports (params: derived once at
#: init, constant; state: changes every sample)
SIZE_STRUCTS = ("smd_drive_config", "smd_drive_params", "smd_drive_state", "smd_dbpc_params",
                "smd_smdo_params", "smd_smdo_state", "smd_pi_params", "smd_pi_state",
                "smd_emf_pos_params", "smd_emf_pos_state", "smd_pll_params", "smd_pll_state",
                "smd_bandpass", "smd_lcl_smo_params", "smd_lcl_smo_state", "smd_lcl_model",
                "smd_linobs_params", "smd_linobs_state", "smd_linobs_model", "smd_svm_params")


def sizes(math: str = "libm") -> tuple[dict[str, int], dict[str, int]]:
    """Code size (.text + .rodata, bytes) of each core source compiled for
    the Cortex-M4F (-O2, as the firmware check) and the size of each struct
    of :data:`SIZE_STRUCTS` in the M4F build (from the symbol sizes of
    objects sized like them)."""
    cc = _tool("arm-none-eabi-gcc", "gcc-arm-none-eabi")
    size_tool = _tool("arm-none-eabi-size", "binutils-arm-none-eabi")
    nm = _tool("arm-none-eabi-nm", "binutils-arm-none-eabi")
    root = c_root()
    flags = M4_FLAGS + COMMON_FLAGS + (FMATH_DEFINES if math == "fmath" else []) + [
        f"-I{root / 'core/include'}"]
    code: dict[str, int] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for src in sorted((root / "core/src").glob("*.c")):
            obj = Path(tmp) / (src.stem + ".o")
            subprocess.run([cc, *flags, "-c", str(src), "-o", str(obj)], check=True,
                           capture_output=True)
            out = subprocess.run([size_tool, "-A", str(obj)], check=True, capture_output=True,
                                 text=True).stdout
            code[src.stem] = sum(int(ln.split()[1]) for ln in out.splitlines()
                                 if ln.startswith((".text", ".rodata")))
        probe = Path(tmp) / "sizes.c"
        probe.write_text('#include "smodrive/smd_drive.h"\n' + "".join(
            f"char sz_{s}[sizeof({s})];\n" for s in SIZE_STRUCTS))
        obj = Path(tmp) / "sizes.o"
        subprocess.run([cc, *flags, "-fno-common", "-c", str(probe), "-o", str(obj)],
                       check=True, capture_output=True)
        out = subprocess.run([nm, "-S", str(obj)], check=True, capture_output=True,
                             text=True).stdout
    ram = {}
    for ln in out.splitlines():
        parts = ln.split()
        if len(parts) == 4 and parts[3].startswith("sz_"):
            ram[parts[3][3:]] = int(parts[1], 16)
    return code, ram


def table6_cycles(math: str = "fmath", work: Path | None = None, calls: int = 120):
    """yao2022 Table VI's parts on the M4F: {part: CycleRow} and {part:
    {function: mean nominal cycles per call}}, over the last 100 of `calls`
    calls at 100 kr/min with the observer tables of the yao2022 design."""
    from .scenarios import yao2022
    from .simulate import lcl_observer_tables

    tables = lcl_observer_tables(yao2022.steady(100e3))
    cases = [TablesCase("tables", tables), BlockCase("table6", "table6", calls, 7)]
    work = Path(work) if work else _cache_dir()
    work.mkdir(parents=True, exist_ok=True)
    vec = work / f"table6_{math}.bin"
    write_vectors(vec, cases)
    prof: list[dict] = []
    wins = trace_windows(build("m4", math), vec, work, profile=prof)
    if len(wins) != 3 * calls or len(prof) != 3 * calls:
        raise TargetError(f"Table VI trace: {len(wins)} windows for {3 * calls} calls")
    rows, by_fn = {}, {}
    for j, part in enumerate(TABLE6_PAPER):
        ws = wins[j::3][calls - 100:]
        ps = prof[j::3][calls - 100:]
        nom = np.array([w.cycles[1] for w in ws], float)
        rows[part] = CycleRow(f"table6.{part}", "yao2022", len(ws), float(nom.mean()),
                              float(np.mean([w.cycles[0] for w in ws])),
                              float(np.mean([w.cycles[2] for w in ws])), int(nom.max()),
                              float(np.mean([w.instructions for w in ws])))
        fns: dict[str, float] = {}
        for d in ps:
            for k, v in d.items():
                fns[k] = fns.get(k, 0.0) + v / len(ps)
        by_fn[part] = dict(sorted(fns.items(), key=lambda kv: -kv[1]))
    return rows, by_fn
