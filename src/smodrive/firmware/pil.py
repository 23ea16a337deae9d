"""Processor-in-the-loop: the controller on the emulated Cortex-M4F (or the
host runner) fed sample by sample from the host plant through a FIFO pair."""

from __future__ import annotations

import ctypes as ct
import dataclasses
import os
import shutil
import struct
import subprocess
import tempfile
import threading
from pathlib import Path

import numpy as np

from ..engine import CHANNELS, Engine, _ffi, fault_names
from ..engine.run import _wrap_pi
from .build import (
    CASE_DRIVE,
    IN_WORDS,
    MAGIC,
    OUT_BYTES,
    SAMPLE_BYTES,
    VERSION,
    VIEW_BYTES,
    TargetError,
    _cache_dir,
    build,
)
from .cycles import F_CPU, CycleRow, step_cycles
from .run import qemu_command, ulp_distance
from .vectors import DriveCase

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
    nch = len(CHANNELS)
    lib = _ffi.lib
    eng = Engine(s)
    din, dout, view = _ffi.DriveIn(), _ffi.DriveOut(), _ffi.DriveView()
    row = (ct.c_double * nch)()
    log = np.zeros((n, nch))
    duty = np.zeros((n, 3), np.float32)
    raw, ins = [], []
    link = None
    st0 = eng._st
    case = DriveCase(s.name, eng._dc, eng._tables, (_wrap_pi(st0.theta0), st0.w0, st0.i_q0),
                     np.zeros((0, IN_WORDS), np.float32))
    if controller != "sim":
        link = _Link(controller, math, case, work)
    try:
        if link is not None and link.init != 0:
            raise TargetError(f"PIL: the drive's init on the {controller} runner returned "
                              f"{link.init} ({_ffi.status_str(link.init)})")
        for k in range(n):
            lib.smd_engine_ext_inputs(eng._buf, ct.byref(din))
            ins.append(bytes(din))
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
    # the run's controller inputs, as a vector case (its cycles: pil(cycles=True))
    inputs = np.frombuffer(b"".join(ins), "<f4").reshape(n, IN_WORDS)
    case = dataclasses.replace(case, inputs=inputs)
    return {"raw": b"".join(raw), "duty": duty.astype(float), "log": log, "case": case}


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
    #: with cycles=True: the M4F's cycles per step over every sample of the run
    #: (smodrive.firmware.CycleRow: mean, 99th percentile, worst; in flash too)
    cycles: CycleRow | None = None


def pil(s, seconds: float, math: str = "fmath", progress=None,
        work: Path | None = None, cycles: bool = False) -> PilResult:
    """Processor in the loop: scenario `s` for `seconds` with the controller
    compiled for the Cortex-M4F on QEMU against the host plant, sample by
    sample, beside the host-only run of the same controller on its own copy
    of the plant: with math "fmath" the host build of the runner (both sides
    the portable float math: expected identical), with "libm" the
    simulator's own controller (glibc against newlib: bounded, not equal)."""
    n = int(round(seconds / s.T_sp))
    work = Path(work) if work else _cache_dir()
    work.mkdir(parents=True, exist_ok=True)
    ref_kind = "host" if math in ("fmath", "fast") else "sim"
    # (with the cycles, their trace is the last third: the bar had stood at 100 % for it)
    span = 2.0 / 3.0 if cycles else 1.0
    half = (lambda f: progress(0.5 * span * f)) if progress else None
    rest = (lambda f: progress(span * (0.5 + 0.5 * f))) if progress else None
    ref = _closed_loop(s, n, ref_kind, math, work, half)
    tgt = _closed_loop(s, n, "m4", math, work, rest)
    row = None
    if cycles:
        # the same inputs replayed through the traced runner: every step's cost
        # (the run's inputs include whatever faults the scenario injects)
        row = step_cycles(tgt["case"], _paper_of(s), math, work)
        if progress:
            progress(1.0)
    wa = np.frombuffer(tgt["raw"], "<u4")
    wb = np.frombuffer(ref["raw"], "<u4")
    fa, fb = wa.view("<f4"), wb.view("<f4")
    same = (wa == wb) | (np.isnan(fa) & np.isnan(fb))
    i_th, i_w = CHANNELS.index("theta_hat"), CHANNELS.index("w_hat")
    dth = np.abs(np.angle(np.exp(1j * (tgt["log"][:, i_th] - ref["log"][:, i_th]))))
    return PilResult(
        scenario=s.name, samples=n, math=math,
        reference=f"host runner ({math})" if ref_kind == "host" else "simulator (glibc libm)",
        max_duty_diff=float(np.max(np.abs(tgt["duty"] - ref["duty"]))),
        max_theta_diff_rad=float(dth.max()),
        max_w_diff=float(np.max(np.abs(tgt["log"][:, i_w] - ref["log"][:, i_w]))),
        max_view_ulp=int(ulp_distance(fa, fb).max()),
        identical=bool(same.all()), log_host=ref["log"], log_pil=tgt["log"], cycles=row)


def _paper_of(s) -> str:
    """Whose control period budgets scenario `s` (smodrive.firmware.BUDGET):
    the LCL drive's (50 us) or the yang2018 drive's (100 us)."""
    return "yao2022" if s.lcl is not None else "yang2018"




#: the drive's start-up phases as the log's "phase" channel holds them
_PHASES = {0: "forced", 1: "encoder", 2: "source"}


def report(s, r: PilResult) -> tuple[dict, list[str]]:
    """pil.json of PIL run `r` of scenario `s`, and the warnings to print:
    the comparison; the drive's own account of the run (its fault word at
    the end, the start-up phases it ran in); with the cycles, their budget
    is the scenario's period, T_sp at F_CPU (an invented fan at 10 us had
    been judged against yang2018's 100 us: 17 % of the period for a step
    that takes 172 %), and a cycle count of a run that ends in a fault (the
    safe state's steps) or never leaves its forced start (the start's) is
    said to be one."""
    log = r.log_pil
    final = int(log[-1, CHANNELS.index("fault")]) if len(log) else 0
    seen = sorted({int(p) for p in log[:, CHANNELS.index("phase")]}) if len(log) else []
    out = {"name": s.name, "samples": r.samples, "math": r.math, "reference": r.reference,
           "identical": r.identical, "max_duty_diff": r.max_duty_diff,
           "max_theta_hat_diff_rad": r.max_theta_diff_rad,
           "max_w_hat_diff_rad_s": r.max_w_diff, "max_word_diff_ulp": r.max_view_ulp,
           "final_fault": fault_names(final), "phases": [_PHASES.get(p, str(p)) for p in seen]}
    said: list[str] = []
    if r.cycles is None:
        return out, said
    c = r.cycles
    budget = s.T_sp * F_CPU
    worst_f4 = c.worst_flash("stm32f4")
    out["cycles"] = {
        "steps": c.calls, "mean": c.nominal, "p99": c.p99, "worst": c.worst,
        "range_mean": [c.low, c.high], "flash": c.flash,
        "budget": budget, "budget_is": f"T_sp = {s.T_sp:g} s at {F_CPU / 1e6:g} MHz, cycles",
        "worst_share_flash_stm32f4": worst_f4 / budget}
    if worst_f4 > budget:
        said.append(f"the step's worst call in STM32F4 flash, {worst_f4:,.0f} cycles, is "
                    f"{worst_f4 / budget:.0%} of its period (T_sp = {s.T_sp:g} s at "
                    f"{F_CPU / 1e6:g} MHz: {budget:,.0f} cycles): it cannot run at this T_sp "
                    "on such a part; a longer T_sp, the fixed composition (smodrive.firmware."
                    "FIXED), or code in RAM (docs/firmware.md)")
    if final:
        said.append(f"the PIL run ends in a fault ({', '.join(fault_names(final))}): its cycles "
                    "include the safe state's steps, not the control law's")
    elif seen and max(seen) == 0 and s.controller.position != "encoder":
        said.append("the PIL run never left its forced start (I/f) within --seconds: its cycles "
                    "are the start's, not the sensorless drive's; a longer --seconds covers it")
    return out, said
