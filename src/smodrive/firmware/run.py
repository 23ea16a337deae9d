"""Running the vectors: on the host and on the emulated Cortex-M4F, the
bit-for-bit comparison of the two, and drive cases recorded from a scenario
through the split engine step."""

from __future__ import annotations

import ctypes as ct
import dataclasses
import hashlib
import subprocess
from pathlib import Path

import numpy as np

from ..engine import CHANNELS, Engine, _ffi
from ..engine.run import _wrap_pi
from .build import IN_WORDS, TargetError, _tool, build
from .vectors import DriveCase, read_outputs, write_vectors

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
    return len(CHANNELS)


def _start_of(eng) -> tuple[float, float, float]:
    st = eng._st
    return (_wrap_pi(st.theta0), st.w0, st.i_q0)


def drive_case(name: str, s, n: int) -> DriveCase:
    """Scenario `s`'s drive on its first n recorded samples."""
    ins, _, _, eng = record(s, n)
    return DriveCase(name, eng._dc, eng._tables, _start_of(eng), ins)

