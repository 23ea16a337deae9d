"""Run a scenario: the C engine (plant + firmware drive) in chunks.

The Python side builds the C configuration structs once (the plant from the
scenario's plant sections, the drive from its controller section and, for
the LCL observers, the lookup tables designed offline by
:mod:`smodrive.design.yao2022`) and hands over a preallocated log buffer;
each chunk of samples is one call into C.

Example
-------
>>> from smodrive.model import Scenario, Profile, RPM
>>> s = Scenario(duration=0.01, w_M0=300 * RPM, w_M_ref=Profile.const(300 * RPM))
>>> r = simulate(s)
>>> r["w_M"].shape, r.unit("w_M")
((100,), 'rad/s')
"""

from __future__ import annotations

import ctypes as ct
import dataclasses
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..design.yao2022 import ObserverDesignPars
from ..model import ParameterError, Scenario
from .channels import CHANNELS
from . import _codes, _ffi
from .marshal import _warm_i_q0, drive_config, lcl_observer_tables, plant_config, profiles
from .result import FaultReport, Result


class SimulationError(RuntimeError):
    """The engine refused the parameters or produced non-finite values."""


def _wrap_pi(x: float) -> float:
    """x wrapped to [-pi, pi), as the plant wraps its angle."""
    return x - 2 * math.pi * math.floor((x + math.pi) / (2 * math.pi))


# The C plant's field codes (smd_plant_field) and the controller's init
# statuses (smd_status) as the scenario fields behind them: the C names
# (T_sw, i_d0/i_q0, omega_c, k_p, w_max, ...) are the structs', not the user's.
# Both maps are generated from the headers' @scenario annotations (_codes).
_PLANT_FIELDS: dict[int, tuple[str, ...]] = _codes.PLANT_FIELDS
_DRIVE_FIELDS: dict[int, tuple[str, ...]] = _codes.DRIVE_FIELDS
# the warm start's codes: the state that carries the load at t = 0
_WARM_CODES = {1000 + _codes.SMD_PF_I_DQ0: "a q current of {i_q0:.4g} A (beyond +-1e5 A)",
               1000 + _codes.SMD_PF_UC_DQ0: "a filter-capacitor voltage beyond +-1e5 V",
               1000 + _codes.SMD_PF_I1_DQ0: "an inverter-side current beyond +-1e5 A"}
_PROFILES = ("w_M_ref", "load.T_ext", "load.T_brake", "i_d_ref", "i_q_ref", "i_d_sin_amp",
             "i_d_sin_freq", "theta_r0", "w_M0")


def plant_fields(code: int) -> tuple[str, ...]:
    """The scenario fields behind the C plant's field code `code`."""
    return _PLANT_FIELDS.get(code, ())


def controller_fields(status: int) -> tuple[str, ...]:
    """The scenario fields behind the controller's init status `status`
    (none for the statuses of a step)."""
    return _DRIVE_FIELDS.get(status, ())


def _value(s: Scenario, name: str):
    obj = s
    for part in name.split("."):
        obj = getattr(obj, part, None)
    return obj


def _with_values(s: Scenario, names: tuple[str, ...]) -> str:
    out = []
    for n in names:
        v = _value(s, n)
        out.append(n if v is None or dataclasses.is_dataclass(v) else f"{n} = {v!r}")
    return ", ".join(out)


def _describe(rc: int, s: Scenario) -> str:
    """The engine's refusal `rc` in the scenario's fields."""
    if rc in _WARM_CODES:
        i_q0 = _warm_i_q0(s)
        k_t = s.motor.k_t
        what = _WARM_CODES[rc].format(i_q0=i_q0)
        return (f"the warm start (warm_start = true) would need {what} to carry the load at "
                f"t = 0: load torque {i_q0 * k_t:.4g} N m (load.T_ext + load.T_brake at t = 0, "
                f"load.k_fan w_M0 |w_M0|, motor.B w_M0; w_M0 = {s.w_M0:.4g} rad/s) over the "
                f"torque constant 1.5 motor.n_p motor.psi_r = {k_t:.4g} N m/A. Lower the load "
                "or the speed at t = 0, check motor.psi_r and the [lcl] filter, or set "
                "warm_start = false")
    if 1000 <= rc < 2000:
        return (f"the plant model refused {_with_values(s, plant_fields(rc - 1000))} "
                f"(plant field code {rc - 1000})")
    if 2000 <= rc < 3000:
        names = controller_fields(rc - 2000) or ("controller",)
        return (f"the controller refused {_with_values(s, names)} (smd_status {rc - 2000}; "
                "docs/parameters.md lists the codes)")
    return (f"a profile or the initial state is malformed: {', '.join(_PROFILES)} must be "
            "finite, with non-decreasing times")


class Engine:
    """A live engine: plant and controller state persist between run() calls."""

    def __init__(self, s: Scenario, design=None):
        s.check_controller()
        self.scenario = s
        self._tables = (lcl_observer_tables(s, design)
                        if s.controller.position in ("lcl_smo_pll", "lcl_linear") else None)
        self._buf = (ct.c_double * math.ceil(_ffi.ENGINE_SIZE / 8 + 1))()
        self._pc, self._pr = plant_config(s), profiles(s)
        self._dc = drive_config(s, self._tables)
        self._st = _ffi.EngineStart(theta0=_wrap_pi(s.theta_r0),
                                    w0=s.w_M0 * s.motor.n_p, i_q0=self._pc.i_q0)
        rc = _ffi.lib.smd_engine_init(self._buf, ct.byref(self._pc), ct.byref(self._dc),
                                      ct.byref(self._pr), ct.byref(self._st))
        if rc != 0:
            raise ParameterError(f"{s.name}: {_describe(rc, s)}")

    def run(self, n: int, out: np.ndarray, row0: int, stride: int) -> int:
        ptr = out[row0:].ctypes.data_as(ct.POINTER(ct.c_double))
        return int(_ffi.lib.smd_engine_run(self._buf, n, ptr, stride))

    def faults(self) -> "FaultReport":
        """The first fault of the run so far (time, cause) and the last
        sample's fault word."""
        first, now = ct.c_uint(0), ct.c_uint(0)
        k = int(_ffi.lib.smd_engine_fault(self._buf, ct.byref(first), ct.byref(now)))
        return FaultReport(None if k < 0 else k * self.scenario.T_sp, int(first.value),
                           int(now.value))

    def run_nolog(self, n: int) -> None:
        """Run n samples without logging (benchmarks)."""
        _ffi.lib.smd_engine_run(self._buf, n, None, 1)


#: Memory the log of one run may take by default (2 GiB), bytes.
DEFAULT_LOG_BUDGET = 2 * 1024**3


@dataclass(frozen=True)
class LogPlan:
    """How a run is logged: every `stride`-th control sample, `rows` rows of
    `bytes` bytes in all, within `budget_bytes`; `decimated` when the budget
    made the stride larger than the scenario's log_stride."""

    stride: int
    rows: int
    bytes: int
    budget_bytes: int
    decimated: bool

    def as_dict(self) -> dict:
        return dataclasses.asdict(self)


def log_plan(s: Scenario, budget: int = DEFAULT_LOG_BUDGET) -> LogPlan:
    """The log of scenario `s` within `budget` bytes: the scenario's
    log_stride, or the smallest multiple of it whose rows (len(CHANNELS)
    float64 each) fit the budget."""
    if isinstance(budget, bool) or not isinstance(budget, (int, float, np.integer,
                                                           np.floating)):
        raise ParameterError(f"log budget = {budget!r} is not a number of bytes")
    row = len(CHANNELS) * 8
    if not (math.isfinite(budget) and budget >= 2 * row):
        raise ParameterError(f"log budget = {budget!r} B is outside its valid range "
                             f"[{2 * row}, inf) B: two rows of the log ({row} B each)")
    budget = int(budget)
    n, stride = s.n_steps, s.log_stride
    # ceil(n / (stride k)) <= max_rows  <=>  k >= n / (stride max_rows)
    k = max(1, -(-n // (stride * (budget // row))))
    rows = -(-n // (stride * k))
    return LogPlan(stride * k, rows, rows * row, budget, k > 1)


def simulate(
    s: Scenario,
    progress: Callable[[float], None] | None = None,
    chunk_seconds: float = 0.05,
    design=None,
    log_budget: int = DEFAULT_LOG_BUDGET,
) -> Result:
    """Run scenario `s` to its duration; `progress(fraction)` after each
    chunk. `design` overrides the LCL observer's design choices
    (:class:`smodrive.design.yao2022.ObserverDesignPars`). The log takes at
    most `log_budget` bytes: a longer one logs every k-th sample instead
    (:func:`log_plan`; the stride is ``Result.log_stride``).

    A wrong argument is a ParameterError naming it and what it must be:

    >>> simulate("yang2018.fig7a")
    Traceback (most recent call last):
    ...
    smodrive.model.ParameterError: s = 'yang2018.fig7a' (str) is not a Scenario: a catalogue name is smodrive.scenarios.catalogue()['yang2018.fig7a'](), a TOML file smodrive.scenario_io.load_scenario('yang2018.fig7a')
    """
    if not isinstance(s, Scenario):
        if isinstance(s, str):
            how = (f"a catalogue name is smodrive.scenarios.catalogue()[{s!r}](), a TOML file "
                   f"smodrive.scenario_io.load_scenario({s!r})")
        elif isinstance(s, dict):
            how = ("a dict of TOML keys is smodrive.scenario_io.scenario_from_dict(d), a "
                   "catalogue entry smodrive.scenarios.catalogue()[name]()")
        else:
            how = ("build one with smodrive.model.Scenario(...), take one of the catalogue "
                   "(smodrive.scenarios.catalogue()[name]()) or read a TOML file "
                   "(smodrive.scenario_io.load_scenario(path))")
        shown = repr(s) if len(repr(s)) <= 60 else repr(s)[:57] + "..."
        raise ParameterError(f"s = {shown} ({type(s).__name__}) is not a Scenario: {how}")
    if progress is not None and not callable(progress):
        raise ParameterError(f"progress = {progress!r} must be None or a function of the "
                             "fraction done")
    if (isinstance(chunk_seconds, bool)
            or not isinstance(chunk_seconds, (int, float, np.integer, np.floating))
            or not (math.isfinite(chunk_seconds) and chunk_seconds > 0)):
        raise ParameterError(f"chunk_seconds = {chunk_seconds!r} is outside its valid range "
                             "(0, inf) s (simulated time per call into C)")
    if design is not None:
        if not isinstance(design, ObserverDesignPars):
            raise ParameterError(f"design = {design!r} ({type(design).__name__}) must be None "
                                 "(the design from the scenario's controller.Q) or a "
                                 "smodrive.design.yao2022.ObserverDesignPars")
    eng = Engine(s, design)
    plan = log_plan(s, log_budget)
    n, stride = s.n_steps, plan.stride
    out = np.zeros((plan.rows, len(CHANNELS)), dtype=np.float64)
    chunk = max(stride, int(chunk_seconds / s.T_sp) // stride * stride)
    done, row = 0, 0
    while done < n:
        m = min(chunk, n - done)
        got = eng.run(m, out, row, stride)
        _check_finite(s, out[row:row + got])  # one chunk at a time: no log-sized temporary
        row += got
        done += m
        if progress is not None:
            progress(done / n)
    out = out[:row]
    status = int(np.max(out[:, CHANNELS.index("status")])) if row else 0
    return Result(s, out, status, eng.faults(), log_stride=stride, samples=n)


def _check_finite(s: Scenario, rows: np.ndarray) -> None:
    bad = ~np.isfinite(rows)
    if bad.any():
        first = int(np.argmax(bad.any(axis=1)))
        raise SimulationError(
            f"{s.name}: non-finite values at t = {rows[first, 0]:.6f} s "
            f"in {[c for c, b in zip(CHANNELS, bad[first]) if b]}"
        )
