"""Metrics of logged signals."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np


def wrap(x: np.ndarray) -> np.ndarray:
    """Wrap angles to [-pi, pi)."""
    return (x + np.pi) % (2 * np.pi) - np.pi


def rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.square(x))))


def ripple_dq(i_d: np.ndarray, i_q: np.ndarray) -> float:
    """RMS of i_d and i_q about their means, sqrt(var(i_d) + var(i_q)), A."""
    return float(np.sqrt(np.var(i_d) + np.var(i_q)))


def sine_amplitude(t: np.ndarray, x: np.ndarray, f: float) -> complex:
    """Complex amplitude of the component of x at frequency f (least squares
    with a constant), so that x ~ Re{A e^{j 2 pi f t}} + c."""
    w = 2 * np.pi * f
    M = np.column_stack([np.cos(w * t), -np.sin(w * t), np.ones_like(t)])
    coef, *_ = np.linalg.lstsq(M, x, rcond=None)
    return complex(coef[0], coef[1])


def scaling_rotation(gain_abc: tuple[float, float, float]) -> float:
    """Angle (rad) by which per-phase ADC gains rotate the measured current
    vector, on average, when phases a and b are measured and c = -a - b (as
    the controllers of smodrive do; the gain of phase c is not used).

    With x_a = g_a i_a, x_b = g_b i_b and the amplitude-invariant Clarke
    transform, i_meas = k1 i + k2 conj(i) with
    k1 = 1 + (e_a + e_b)/2 + j (e_a - e_b)/(2 sqrt 3), e_x = g_x - 1.
    The k2 part turns at -2 w in the rotor frame (the 2 f_e disturbance of
    yao2022 Sec. IV-A); k1 is constant there: a gain and a rotation arg(k1).
    """
    e_a, e_b = gain_abc[0] - 1.0, gain_abc[1] - 1.0
    return math.atan2((e_a - e_b) / (2.0 * math.sqrt(3.0)), 1.0 + 0.5 * (e_a + e_b))


# ------------------------------------------------------------- registry ---
#
# One registry of named run metrics, shared by the sweeps (smodrive.sweep)
# and available to the claims: each metric reduces one run (a
# smodrive.engine.Result) over a time window [t0, t1) to one float. A
# metric that needs the whole run (`needs_full_log`) is given the log from
# t = 0; the others only the window's rows (a sweep runs the samples before
# the window without logging them).

#: position error (electrical deg) a sensorless drive must stay within to
#: hold lock (yang2018's envelope: peak error below 10 deg over the window)
LOCK_DEG = 10.0


@dataclass(frozen=True)
class Metric:
    name: str
    unit: str
    doc: str
    fn: Callable[..., float]  # fn(r: Result, mask: np.ndarray) -> float
    needs_full_log: bool = False


def _pos_err_deg(r, m) -> np.ndarray:
    return np.degrees(r.theta_error[m])


def _mean_or_nan(x: np.ndarray) -> float:
    return float(np.mean(x)) if x.size else math.nan


def _time_to_lock(r, m) -> float:
    """The first time from which |position error| stays within LOCK_DEG to
    the end of the run (NaN if the last sample is out of it)."""
    bad = np.abs(np.degrees(r.theta_error)) >= LOCK_DEG
    if bad.size == 0 or bad[-1]:
        return math.nan
    last_bad = np.flatnonzero(bad)
    return float(r.t[0] if last_bad.size == 0 else r.t[last_bad[-1] + 1])


def _holds_lock(r, m) -> float:
    e = _pos_err_deg(r, m)
    return float(e.size > 0 and bool(np.max(np.abs(e)) < LOCK_DEG)
                 and r.faults.final == 0)


METRICS: dict[str, Metric] = {m.name: m for m in (
    Metric("id_error", "A", "mean of i_d - i_d_ref (true current against the controller's "
           "reference) over the window",
           lambda r, m: _mean_or_nan(r["i_d"][m] - r["i_d_ref"][m])),
    Metric("iq_error", "A", "mean of i_q - i_q_ref over the window",
           lambda r, m: _mean_or_nan(r["i_q"][m] - r["i_q_ref"][m])),
    Metric("id_ripple", "A", "standard deviation of i_d - i_d_ref over the window",
           lambda r, m: float(np.std(r["i_d"][m] - r["i_d_ref"][m]))),
    Metric("iq_ripple", "A", "standard deviation of i_q - i_q_ref over the window",
           lambda r, m: float(np.std(r["i_q"][m] - r["i_q_ref"][m]))),
    Metric("ripple", "A", "sqrt(var(i_d) + var(i_q)) over the window (ripple_dq, the "
           "yang2018 Fig. 5-6 claims' ripple)",
           lambda r, m: ripple_dq(r["i_d"][m], r["i_q"][m])),
    Metric("pos_error_mean_deg", "deg", "mean electrical position error theta_r - theta_hat",
           lambda r, m: _mean_or_nan(_pos_err_deg(r, m))),
    Metric("pos_error_rms_deg", "deg", "RMS electrical position error over the window",
           lambda r, m: rms(_pos_err_deg(r, m))),
    Metric("pos_error_peak_deg", "deg", "peak |electrical position error| over the window",
           lambda r, m: float(np.max(np.abs(_pos_err_deg(r, m))))),
    Metric("pos_error_rms_rad", "rad", "RMS electrical position error over the window",
           lambda r, m: rms(r.theta_error[m])),
    Metric("pos_error_peak_rad", "rad", "peak |electrical position error| over the window",
           lambda r, m: float(np.max(np.abs(r.theta_error[m])))),
    Metric("speed_rpm", "r/min", "mean true speed over the window",
           lambda r, m: _mean_or_nan(r.n_rpm[m])),
    Metric("speed_error_mean", "r/min", "mean of true speed - reference over the window",
           lambda r, m: _mean_or_nan(r.n_rpm[m] - r["w_M_ref"][m] / (2 * math.pi / 60))),
    Metric("speed_error_rms", "r/min", "RMS of true speed - reference over the window",
           lambda r, m: rms(r.n_rpm[m] - r["w_M_ref"][m] / (2 * math.pi / 60))),
    Metric("speed_est_error_rms", "r/min", "RMS of estimated - true speed over the window",
           lambda r, m: rms(r.n_hat_rpm[m] - r.n_rpm[m])),
    Metric("holds_lock", "", f"1 if the peak position error over the window is below "
           f"{LOCK_DEG:g} deg and the run does not end in a fault, else 0", _holds_lock),
    Metric("time_to_lock", "s", f"first time from which |position error| stays below "
           f"{LOCK_DEG:g} deg to the end of the run (NaN: never)", _time_to_lock,
           needs_full_log=True),
    Metric("fault", "", "1 if the run ends in a (latched) fault, else 0",
           lambda r, m: float(r.faults.final != 0)),
    Metric("fault_time", "s", "time of the first fault the controller reported (NaN: none)",
           lambda r, m: math.nan if r.faults.t_first is None else float(r.faults.t_first)),
)}


def metric_values(r, names, t0: float, t1: float) -> dict[str, float]:
    """The registry's metrics `names` of run `r` over [t0, t1) (NaN where a
    metric has no samples to reduce)."""
    m = r.window(t0, t1)
    out = {}
    for n in names:
        try:
            out[n] = float(METRICS[n].fn(r, m))
        except ValueError:  # a reduction of an empty window
            out[n] = math.nan
    return out
