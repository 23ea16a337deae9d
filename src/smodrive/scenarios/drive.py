"""Compositions of the one drive that neither paper runs: the baselines and
references a user compares the papers' methods against.

- ``drive.pi_encoder``, ``drive.pi_sensorless``: the yang2018 Table I motor
  under synchronous-frame PI current control (with decoupling and EMF
  feed-forward), on the encoder or on the SMDO's position (eq. (44)-(45));
- ``drive.if_start``: the yang2018 sensorless drive (robust DBPC + SMDO)
  started from standstill by I/f (current on a forced angle) with handover to
  the SMDO's position, up to 1500 r/min under rated load;
- ``drive.lcl_encoder``: the yao2022 LCL-filtered drive on the encoder, the
  reference for its observers.

:func:`current_control_table` runs the PI drives beside conventional and
robust DBPC at the Table I operating point (1500 r/min, rated load).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..engine import Result, simulate
from ..model import RPM, LoadCfg, Profile, Scenario
from . import yang2018 as y
from . import yao2022 as z

STEADY_WINDOW = (0.3, 0.6)  # s: after the warm start's settling


def _table1_steady(name: str, **ctrl) -> Scenario:
    """yang2018 Table I motor at 1500 r/min with the rated brake load, from a
    warm start, run long enough for a 0.3 s steady-state window."""
    return y.BASE.replace(
        name=name, duration=STEADY_WINDOW[1], w_M0=1500.0 * RPM, w_M_ref=Profile.const(y.W_N),
        load=LoadCfg(T_brake=Profile.const(y.T_N)),
    ).with_controller(**ctrl)


def pi_encoder() -> Scenario:
    return _table1_steady("drive.pi_encoder", current="pi", position="encoder")


def pi_sensorless() -> Scenario:
    return _table1_steady("drive.pi_sensorless", current="pi", position="smdo_emf",
                          start="handover", t_handover=y.HANDOVER)


IF_RAMP = 0.5  # s: speed reference 0 -> 1500 r/min


def if_start() -> Scenario:
    """Standstill, rated brake load, speed reference ramped to 1500 r/min in
    0.5 s; I/f with the ControllerCfg defaults (10 A, 3000 r/min/s, handover
    at 150 r/min)."""
    return y.BASE.replace(
        name="drive.if_start", duration=1.5, w_M0=0.0,
        w_M_ref=Profile((0.0, IF_RAMP), (0.0, y.W_N)),
        load=LoadCfg(T_brake=Profile.const(y.T_N)),
    ).with_controller(current="robust_dbpc", position="smdo_emf", start="if")


def lcl_encoder() -> Scenario:
    return z.steady(60e3, name="drive.lcl_encoder").with_controller(position="encoder")


SCENARIOS: dict[str, Callable[[], Scenario]] = {
    "drive.pi_encoder": pi_encoder,
    "drive.pi_sensorless": pi_sensorless,
    "drive.if_start": if_start,
    "drive.lcl_encoder": lcl_encoder,
}


def current_errors(r: Result, window: tuple[float, float] = STEADY_WINDOW) -> dict[str, float]:
    """Steady-state mean error (true current minus the controller's
    reference) and ripple (RMS about the mean) on each axis, A."""
    m = r.window(*window)
    e_d = r["i_d"][m] - r["i_d_ref"][m]
    e_q = r["i_q"][m] - r["i_q_ref"][m]
    return {"i_d_error_A": float(e_d.mean()), "i_q_error_A": float(e_q.mean()),
            "i_d_ripple_A": float(e_d.std()), "i_q_ripple_A": float(e_q.std()),
            "theta_error_rms_deg": float(np.degrees(np.sqrt(np.mean(r.theta_error[m] ** 2))))}


def current_control_table(progress: Callable[[str, float], None] | None = None
                          ) -> dict[str, dict[str, float]]:
    """Conventional DBPC, robust DBPC and PI (encoder, SMDO sensorless) at
    yang2018 Table I, 1500 r/min, rated load: current_errors of each."""
    runs = {
        "conventional DBPC": _table1_steady("drive.dbpc", mode="conventional"),
        "robust DBPC": _table1_steady("drive.robust_dbpc", mode="robust"),
        "PI, encoder": pi_encoder(),
        "PI, SMDO sensorless": pi_sensorless(),
    }
    out = {}
    for label, s in runs.items():
        cb = None if progress is None else (lambda f, n=s.name: progress(n, f))
        out[label] = current_errors(simulate(s, progress=cb))
    return out
