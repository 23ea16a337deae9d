"""The real-time core on a Cortex-M4F: the vector runner (core/target) built
for the host and for QEMU's ``mps2-an386`` board, test vectors, a bit-for-bit
comparison of the two builds, processor-in-the-loop runs against the host
plant, and cycle counts from the emulator's instruction trace.

The runner is the same C for both (``core/target/smd_vec.c``); the host
build is the simulator's float core (same sources, ``-ffp-contract=off``).
Three math variants: ``libm`` (each platform's C library: glibc on the host,
newlib on the target), ``fmath`` (the core's portable float math,
``smodrive/smd_fmath.h``, on both) and ``fast`` (the fast build's shorter
portable sin, cos and atan2, ``smodrive/smd_fastmath.h``), see
:data:`MATH_DEFINES`.

Needs ``arm-none-eabi-gcc`` (Debian: gcc-arm-none-eabi, libnewlib-arm-none-eabi)
and ``qemu-system-arm`` (Debian: qemu-system-arm); ``make toolchain``
installs them."""

from __future__ import annotations

import ctypes as ct
import hashlib
import os
import shutil
import subprocess
from pathlib import Path

from ..engine import _ffi

MAGIC = 0x56444D53
VERSION = 1
CASE_END, CASE_DRIVE, CASE_TABLES, CASE_BLOCK = 0, 1, 2, 3
BLOCKS = {"transforms": 1, "svm": 2, "pi": 3, "dbpc": 4, "smdo": 5, "emf_pos": 6, "pll": 7,
          "bandpass": 8, "lcl_smo": 9, "linobs": 10, "math": 11, "table6": 12,
          "table6_dec": 13, "ident": 14, "ident_ls": 15, "ident_psi": 16,
          "ident_mech": 17}
#: the math block's outputs per step, in order
MATH_FUNCS = ("sin", "cos", "atan2", "exp", "expm1", "floor", "sqrt", "fabs")
#: the core's math hooks mapped to its portable float math
FMATH_DEFINES = ['-DSMD_MATH_HEADER="smodrive/smd_fmath.h"', "-DSMD_SINF=smd_sinf",
                 "-DSMD_COSF=smd_cosf", "-DSMD_SINCOSF=smd_sincosf", "-DSMD_ATAN2F=smd_atan2f",
                 "-DSMD_EXPF=smd_expf", "-DSMD_EXPM1F=smd_expm1f"]
#: the fast build (``SMD_FAST``): its math (``smodrive/smd_fastmath.h``: shorter sin, cos and
#: atan2 with stated error bounds) and reciprocals for the hot divisions, as portable as the
#: exact build (the host and the target still agree bit for bit)
FAST_DEFINES = ["-DSMD_FAST", '-DSMD_MATH_HEADER="smodrive/smd_fastmath.h"',
                "-DSMD_SINF=smd_fast_sinf",
                "-DSMD_COSF=smd_fast_cosf", "-DSMD_SINCOSF=smd_fast_sincosf",
                "-DSMD_ATAN2F=smd_fast_atan2f", "-DSMD_EXPF=smd_expf", "-DSMD_EXPM1F=smd_expm1f"]
#: the math variants: each platform's C library, the portable exact math, the fast math
MATH_DEFINES = {"libm": [], "fmath": FMATH_DEFINES, "fast": FAST_DEFINES}
#: the papers' sensorless compositions fixed at compile time (smd_drive.h, "A
#: composition fixed at compile time"), each with the speed loop, no tracker and
#: the supervision spread over 4 samples: yang2018's robust DBPC on the SMDO's
#: angle without a filter, yao2022's PI behind the LCL filter on its
#: sliding-mode observer and PLL
_CURRENTS = ("SMD_CC_PI", "SMD_CC_DBPC", "SMD_CC_ROBUST_DBPC")
_POSITIONS = ("SMD_POS_ENCODER", "SMD_POS_SMDO_EMF", "SMD_POS_LCL_SMO_PLL", "SMD_POS_LCL_LINEAR")


def fixed_flags(cfg) -> tuple[str, ...]:
    """The compiler flags that fix the composition of drive configuration
    `cfg` (an smd_drive_config, :func:`smodrive.engine.drive_config`) in
    smd_drive.c (smd_drive.h, "A composition fixed at compile time")."""
    return (f"-DSMD_FIX_CURRENT={_CURRENTS[cfg.current]}",
            f"-DSMD_FIX_POSITION={_POSITIONS[cfg.position]}", f"-DSMD_FIX_LCL={int(cfg.lcl)}",
            f"-DSMD_FIX_RLS={int(cfg.rls_i_inj > 0.0)}",
            f"-DSMD_FIX_SPEED_LOOP={int(cfg.speed_loop)}",
            f"-DSMD_FIX_SUPERVISE_EVERY={max(int(cfg.supervise_every), 1)}")


_FIX_COMMON = ("-DSMD_FIX_RLS=0", "-DSMD_FIX_SPEED_LOOP=1", "-DSMD_FIX_SUPERVISE_EVERY=4")
FIXED = {"yang2018": ("-DSMD_FIX_CURRENT=SMD_CC_ROBUST_DBPC", "-DSMD_FIX_POSITION=SMD_POS_SMDO_EMF",
                      "-DSMD_FIX_LCL=0") + _FIX_COMMON,
         "yao2022": ("-DSMD_FIX_CURRENT=SMD_CC_PI", "-DSMD_FIX_POSITION=SMD_POS_LCL_SMO_PLL",
                     "-DSMD_FIX_LCL=1") + _FIX_COMMON}
M4_FLAGS = ["-mcpu=cortex-m4", "-mthumb", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard"]
#: -O3 as CMake's Release build of the core gives a firmware project (2,890 -> 2,690 cycles for
#: the yang2018 sensorless step, 7,289 -> 6,342 for yao2022's, 11 % more code than -O2);
#: -fno-math-errno lets sqrtf be the VSQRT instruction (IEEE: the same bits as newlib's call);
#: -ffp-contract=off keeps a*b + c two roundings (the host's bits). -flto would move the
#: runner's cycle markers. -fno-trapping-math (no code reads the FPU's exception flags: a
#: compare may be if-converted, the values are IEEE's) and -funroll-loops (the three phases'
#: loops) change no result bit (the PIL and vector tests): the fixed yang2018 step 1,294 ->
#: 1,287 cycles, yao2022's 2,499 -> 2,450, 3.5 % more code in a fixed build, 7 % in the whole
#: core (57.9 kB).
COMMON_FLAGS = ["-std=c99", "-O3", "-fno-math-errno", "-ffp-contract=off", "-fno-trapping-math",
                "-funroll-loops", "-Wall", "-Wextra", "-Werror"]
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
    here = Path(__file__).resolve().parents[1]  # the package root (firmware/..)
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
    """The runner for `kind` ("host" or "m4") with `math` ("libm", "fmath"
    or "fast", :data:`MATH_DEFINES`), built once per content of its sources
    and flags; `extra` flags go last (tests build deliberately wrong variants
    with them)."""
    if kind not in ("host", "m4") or math not in MATH_DEFINES:
        raise ValueError(f"build({kind!r}, {math!r})")
    root = c_root()
    srcs = _sources(root, kind)
    headers = sorted((root / "core").glob("*/**/*.h")) + [root / "core/target/m4/mps2_an386.ld"]
    flags = list(COMMON_FLAGS) + MATH_DEFINES[math]
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
    h = hashlib.sha256(" ".join([cc, kind, math, "core-as-one-unit"] + flags + cmd_tail).encode())
    for f in srcs + headers:
        h.update(f.read_bytes())
    out_dir = Path(out_dir) if out_dir else _cache_dir()
    exe = out_dir / f"smd_vec_{kind}_{math}_{h.hexdigest()[:12]}{'.elf' if kind == 'm4' else ''}"
    if exe.exists():
        return exe
    out_dir.mkdir(parents=True, exist_ok=True)
    tmp = exe.with_suffix(exe.suffix + f".tmp{os.getpid()}")
    # the core as one translation unit (the runner's own files apart): the
    # compiler inlines across the core's files as a firmware project's
    # link-time optimisation would, without moving the runner's cycle
    # markers (-flto would); the same bits (no contraction: -ffp-contract=off)
    core = [f for f in srcs if f.parent.name == "src"]
    unity = tmp.with_name(tmp.name + "_core.c")
    unity.write_text("".join(f'#include "{f}"\n' for f in core))
    cmd = [cc, *flags, f"-I{root / 'core/include'}", f"-I{root / 'core/target'}",
           str(unity), *(str(f) for f in srcs if f not in core), "-o", str(tmp), *cmd_tail]
    try:
        res = subprocess.run(cmd, capture_output=True, text=True)
    finally:
        unity.unlink(missing_ok=True)
    if res.returncode != 0:
        # the first error on the first line (a claim's statement shows that
        # line), the compiler's last words below it
        errors = [ln.strip() for ln in res.stderr.splitlines() if "error" in ln.lower()]
        first = errors[0] if errors else f"exit status {res.returncode}"
        raise TargetError(f"building the {kind} runner failed: {first}\n{res.stderr[-3000:]}")
    os.replace(tmp, exe)
    return exe

