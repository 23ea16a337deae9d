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
    fn: Callable[..., float]  # fn(r: Result, window: slice or boolean mask) -> float
    needs_full_log: bool = False
    #: the value means what it says for a run that ends in a fault (the
    #: fault and lock metrics); the others reduce signals the fault cut
    #: short or replaced by the safe state (a sweep records them as NaN)
    after_fault: bool = False


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
           f"{LOCK_DEG:g} deg and the run does not end in a fault, else 0", _holds_lock,
           after_fault=True),
    Metric("time_to_lock", "s", f"first time from which |position error| stays below "
           f"{LOCK_DEG:g} deg to the end of the run (NaN: never)", _time_to_lock,
           needs_full_log=True, after_fault=True),
    Metric("fault", "", "1 if the run ends in a (latched) fault, else 0",
           lambda r, m: float(r.faults.final != 0), after_fault=True),
    Metric("fault_time", "s", "time of the first fault the controller reported (NaN: none)",
           lambda r, m: math.nan if r.faults.t_first is None else float(r.faults.t_first),
           after_fault=True),
)}


def window_slice(r, t0: float, t1: float) -> slice:
    """The rows of `r` with t0 <= t < t1 as a slice (the log's times
    increase: the same rows as the mask ``r.window(t0, t1)``, without
    copying them)."""
    t = r.t
    return slice(int(np.searchsorted(t, t0, "left")), int(np.searchsorted(t, t1, "left")))


def metric_values(r, names, t0: float, t1: float) -> dict[str, float]:
    """The registry's metrics `names` of run `r` over [t0, t1) (NaN where a
    metric has no samples to reduce)."""
    m = window_slice(r, t0, t1)
    out = {}
    for n in names:
        try:
            out[n] = float(METRICS[n].fn(r, m))
        except ValueError:  # a reduction of an empty window
            out[n] = math.nan
    return out


# --------------------------------------------------- the operating point ---
#
# Whether a run held the operating point its metrics describe, over the
# metrics' window (docs/sweeps.md argues the numbers): a metric of a drive
# that lost its speed, runs into its current or voltage limit or lost its
# angle describes that failure, not the controller at its operating point.

#: the speed band: the window's mean |w_M - w_M_ref| within this fraction
#: of the mean |w_M_ref| ...
SPEED_BAND = 0.01
#: ... and at least within this fraction of the motor's rated speed (a
#: reference at or near zero)
SPEED_FLOOR = 0.001
#: a reference within this fraction of its limit is on the limit
LIMIT_TOL = 1e-3
#: the largest share of the window's samples a run may spend with a
#: reference on its limit and still hold
HOLD_SHARE = 0.2
#: |electrical position error| from which the current vector's torque has
#: lost its sign: a run that reaches it anywhere in the window has not held
ANGLE_HOLD_DEG = 90.0
#: why a run did not hold, in the order the maps report them
NOT_HELD = ("fault", "angle", "speed", "current_limit", "voltage_limit")


@dataclass(frozen=True)
class OperatingPoint:
    """What :func:`operating_point` found over a window."""

    held: bool
    reasons: tuple[str, ...]  # of NOT_HELD, in that order; () if held (no_samples: none)
    speed_offset_rpm: float  # mean w_M - w_M_ref over the window, r/min (NaN: no speed loop)
    speed_band_rpm: float  # the band it is judged against, r/min
    i_limit_share: float  # share of samples with a current reference on i_max
    u_limit_share: float  # share of samples with the voltage command on the modulator's limit
    angle_peak_deg: float  # peak |electrical position error|

    def as_row(self) -> dict:
        return {"held": self.held, "not_held": ",".join(self.reasons),
                "speed_offset_rpm": self.speed_offset_rpm, "i_limit_share": self.i_limit_share,
                "u_limit_share": self.u_limit_share}


def _limit_share(x: np.ndarray, y: np.ndarray, lim: float) -> float:
    """The share of samples with |x| or |y| at or beyond `lim` (the window's
    extremes first: most windows are nowhere near the limit)."""
    n = x.size
    if not n:
        return math.nan
    if max(x.max(), -x.min(), y.max(), -y.min()) < lim:
        return 0.0
    return float(np.count_nonzero((np.abs(x) >= lim) | (np.abs(y) >= lim))) / n


def _voltage_share(ua: np.ndarray, ub: np.ndarray, u_dc: float, hexagon: bool) -> float:
    """The share of samples with the voltage command on the modulator's
    limit (within LIMIT_TOL): the hexagon, whose largest line-to-line
    voltage is u_dc, or its inscribed circle |u| = u_dc / sqrt 3. Only the
    samples outside the inscribed circle can be on the hexagon."""
    n = ua.size
    if not n:
        return math.nan
    r2 = ua * ua + ub * ub
    circle = ((1.0 - LIMIT_TOL) * u_dc) ** 2 / 3.0
    near = r2 >= circle
    if not hexagon:
        return float(np.count_nonzero(near)) / n
    k = np.flatnonzero(near)
    if not k.size:
        return 0.0
    a, b = ua[k], ub[k]
    h = 0.5 * math.sqrt(3.0) * b
    # the largest of |u_ab|, |u_bc|, |u_ca| (ab_to_abc: a, -a/2 + h, -a/2 - h)
    span = np.maximum(np.maximum(np.abs(1.5 * a - h), np.abs(2.0 * h)), np.abs(1.5 * a + h))
    return float(np.count_nonzero(span >= (1.0 - LIMIT_TOL) * u_dc)) / n


def operating_point(r, t0: float, t1: float) -> OperatingPoint:
    """Whether run `r` held its operating point over [t0, t1): it does not
    end in a fault; with a speed loop, its mean true speed is within the
    band of the mean reference (SPEED_BAND of it, at least SPEED_FLOOR of
    the rated speed); its current references (|i_d_ref|, |i_q_ref| against
    controller.i_max) and its voltage command (u_cmd against the
    modulator's limit, the hexagon or the circle of inverter.u_dc) are each
    on their limit in at most HOLD_SHARE of the samples; and its position
    error stays below ANGLE_HOLD_DEG."""
    s = r.scenario
    k = s.controller
    m = window_slice(r, t0, t1)
    if m.stop <= m.start:  # nothing to judge
        return OperatingPoint(False, ("no_samples",), math.nan, math.nan, math.nan, math.nan,
                              math.nan)
    rpm = 2.0 * math.pi / 60.0
    if k.speed_loop:
        w_ref = float(np.mean(r["w_M_ref"][m]))
        offset = (float(np.mean(r["w_M"][m])) - w_ref) / rpm
        band = max(SPEED_BAND * abs(w_ref), SPEED_FLOOR * s.motor.w_M_N) / rpm
    else:
        offset, band = math.nan, math.nan
    i_share = _limit_share(r["i_d_ref"][m], r["i_q_ref"][m], (1.0 - LIMIT_TOL) * k.i_max)
    u_share = _voltage_share(r["u_cmd_alpha"][m], r["u_cmd_beta"][m], s.inverter.u_dc,
                             s.inverter.svm_limit == "hexagon")
    d = r["theta_r"][m] - r["theta_hat"][m]
    d -= (2 * np.pi) * np.rint(d / (2 * np.pi))  # wrapped to [-pi, pi] (a peak: either end)
    peak = float(np.degrees(max(d.max(), -d.min())))
    bad = {"fault": r.faults.final != 0,
           "angle": not peak < ANGLE_HOLD_DEG,
           "speed": abs(offset) > band,
           "current_limit": i_share > HOLD_SHARE,
           "voltage_limit": u_share > HOLD_SHARE}
    reasons = tuple(n for n in NOT_HELD if bad[n])
    return OperatingPoint(not reasons, reasons, offset, band, i_share, u_share, peak)
