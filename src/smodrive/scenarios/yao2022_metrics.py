"""yao2022: what the experiments measure from a run or a design: the lumped
disturbance and its periodic part (Fig. 4), the PLL's bandwidth from the C
code (Fig. 7), the speed ripple and its harmonics (Table V), the handover
and peak position errors (Figs. 14, 19-21), the zero crossing (Fig. 22) and
stability (Fig. 23). Pure functions of a :class:`~smodrive.engine.Result`
or of design parameters; :mod:`smodrive.scenarios.yao2022` runs the experiments."""

from __future__ import annotations

import ctypes as ct
import math

import numpy as np
import scipy.optimize

from ..analysis import metrics
from ..design import yao2022 as dz
from ..engine import Result, _ffi
from ..model import RPM, Scenario

STABLE_SPEED, STABLE_ANGLE = 0.01, 0.1  # the bounds of _stable (fig23_basis)
# rad: the largest position error the paper presents as good estimation (Fig. 19,
# 'still within 0.1 rd'); the bound of the Fig. 22 claim (its basis)
GOOD_ANGLE = 0.1
SETTLE, WINDOW = 0.1, 0.2  # steady-state runs: settle, then measure


def lumped_disturbance(r: Result) -> np.ndarray:
    """D(k) = s(k+1) - Q s(k) - v(k), the lumped disturbance of the reaching
    mode (30) measured one sample later (complex gamma + j delta)."""
    Q = np.array(r.scenario.controller.Q)
    s = r["s_g"] + 1j * r["s_dl"]
    v = r["v_g"] + 1j * r["v_dl"]
    return (s[1:].real - Q[0] * s[:-1].real - v[:-1].real) + 1j * (
        s[1:].imag - Q[1] * s[:-1].imag - v[:-1].imag)


def electrical_period_samples(n_rpm: float, s: Scenario) -> int:
    """Samples per electrical period at n_rpm, which must be a whole number
    (12 at 100 kr/min and 20 kHz: f_s / f_e = 12)."""
    per = 60.0 / (n_rpm * s.motor.n_p * s.T_sp)
    if abs(per - round(per)) > 1e-9:
        raise ValueError(f"{per} samples per electrical period is not a whole number")
    return int(round(per))


def periodic_part(d: np.ndarray, period: int) -> np.ndarray:
    """One period of the synchronous average of d over its whole periods:
    the lines at multiples of f_e, without the broadband noise (whose power
    falls by the number of periods averaged)."""
    n = d.size // period * period
    return d[:n].reshape(-1, period).mean(axis=0)


def compensation_errors(p: np.ndarray) -> tuple[float, float]:
    """For one period p of a periodic disturbance (taken as repeating):
    (RMS of the error (32) of ref. [18] / RMS of the error (31) of ref. [17],
    RMS of (31) / RMS of p)."""
    e17 = p - np.roll(p, 1)  # eq. (31)
    e18 = p - 2 * np.roll(p, 1) + np.roll(p, 2)  # eq. (32)
    rms = lambda x: float(np.sqrt(np.mean(np.abs(x) ** 2)))  # noqa: E731
    return rms(e18) / rms(e17), rms(e17) / rms(p)


def line_amplitudes(p: np.ndarray, harmonics=(1, 2, 3, 6)) -> dict[int, float]:
    """RSS amplitude of the +h and -h f_e lines of one period p of a complex
    (rotor-frame) sequence, by h."""
    X = np.fft.fft(p) / p.size
    n = p.size
    return {h: float(math.hypot(abs(X[h % n]), abs(X[-h % n])) if 2 * h != n else abs(X[h]))
            for h in harmonics}


def pll_bandwidth_measured(pll: dz.PllPars, n: int = 400_000) -> float:
    """-3 dB bandwidth of the firmware PLL closed around eq. (48), from its
    impulse response computed by the C code."""
    f = _ffi.lib.smd_pll_impulse
    f.restype = ct.c_int
    f.argtypes = [ct.c_double] * 5 + [ct.c_long, ct.POINTER(ct.c_double)]
    h = np.zeros(n)
    rc = f(pll.T, pll.k_theta, pll.k_omega, pll.k_a, 1e-3, n,
           h.ctypes.data_as(ct.POINTER(ct.c_double)))
    if rc != 0:
        raise RuntimeError(f"PLL rejected: {_ffi.status_str(rc)}")
    k = np.arange(1, n + 1)

    def gain(fr: float) -> float:
        return float(abs(np.sum(h * np.exp(-2j * np.pi * fr * pll.T * k))))

    return float(scipy.optimize.brentq(lambda fr: gain(fr) - 1 / math.sqrt(2), 10.0,
                                       0.45 / pll.T, xtol=1e-6))


def injection_reading(r: Result, t_inj: float, w: float) -> dict[str, float]:
    """The current-injection reading of eq. (60) from a run whose gamma
    current steps to +5 A at t_inj: the mean delta current over the window w
    before the step and over w after it (from t_inj + 0.05 s, the step
    settled); with the true mean errors theta_hat - theta (the sign of (59),
    docs/errata.md Y9) before and during the injection."""
    before, after = r.window(t_inj - w, t_inj), r.window(t_inj + 0.05, r.scenario.duration)
    i_dl1, i_dl2 = np.mean(r["i_dl"][before]), np.mean(r["i_dl"][after])
    i_g2 = np.mean(r["i_g"][after])
    return {"inj": float(math.atan((i_dl1 - i_dl2) / i_g2)),
            "during": -float(np.mean(r.theta_error[after])),
            "before": -float(np.mean(r.theta_error[before]))}


def speed_ripple(r: Result) -> float:
    m = r.window(SETTLE, r.scenario.duration)
    n_hat = r.n_hat_rpm[m]
    return float((n_hat.max() - n_hat.min()) / 2)


def harmonic_ripple(r: Result, n: float) -> float:
    """RSS of the 2 f_e and 3 f_e lines of the estimated speed in steady state
    (r/min), the components the paper's FFTs of Figs. 12-13 single out."""
    m = r.window(SETTLE, r.scenario.duration)
    f_e = n / 60.0 * r.scenario.motor.n_p
    amps = [abs(metrics.sine_amplitude(r.t[m], r.n_hat_rpm[m], h * f_e)) for h in (2, 3)]
    return float(math.hypot(*amps))


def pll_speed_gain(pll: dz.PllPars, f: float) -> float:
    """|omega_hat / theta~| at f Hz: the speed ripple (electrical rad/s) that
    an angle-error ripple of 1 rad from (47) gives through the PLL (48)
    closed around (49) (theta~ = theta - theta_hat + ripple)."""
    z = np.exp(2j * np.pi * f * pll.T)
    g = dz.pll_open_loop(pll)(z)
    return float(abs((pll.k_omega / (z - 1) + pll.k_a * pll.T / (z - 1) ** 2) / (1 + g)))


def ripple_needs(n: float, ripple_rpm: float, n_p: int) -> dict[str, float]:
    """The fields of the Table V reasons at n r/min: the PLL's speed gain at
    2 f_e and 3 f_e and the angle-error ripple (rad) a speed ripple of
    ripple_rpm would need at either."""
    pll = dz.PllPars()
    f_e = n / 60.0 * n_p
    g2, g3 = (pll_speed_gain(pll, h * f_e) for h in (2, 3))
    w = ripple_rpm * RPM * n_p
    return dict(g2=g2, g3=g3, need2=w / g2, need3=w / g3)


def handover_time(r: Result) -> float:
    """When the sensorless drive took over from the forced start (the run's
    end if it never did)."""
    closed = r["phase"] > 0.5
    return float(r.t[np.argmax(closed)]) if closed.any() else r.scenario.duration


def peak_after_handover(r: Result, n_min: float = 0.0) -> float:
    """Peak |theta - theta_hat| from 0.1 s after the handover to the end (at
    true speeds of at least n_min r/min)."""
    m = (r["phase"] > 0.5) & (r.t >= handover_time(r) + 0.1) & (r.n_rpm >= n_min)
    return float(np.max(np.abs(r.theta_error[m]))) if m.any() else float("nan")


def end_speed_rpm(r: Result) -> float:
    """Mean true speed over the last 0.1 s, r/min."""
    return float(np.mean(r.n_rpm[r.t >= r.scenario.duration - 0.1]))


def fig19_peak(r: Result) -> float:
    """Peak |theta - theta_hat| from 0.02 s (the warm start settled)."""
    return float(np.max(np.abs(r.theta_error[r.window(0.02, r.scenario.duration)])))


def fig21_peak(r: Result) -> float:
    """Peak |n_hat - n| from 0.02 s, r/min."""
    m = r.window(0.02, r.scenario.duration)
    return float(np.max(np.abs(r.n_hat_rpm[m] - r.n_rpm[m])))


REVERSAL_BAND = 3e3  # r/min around zero where the EMF (< 0.4 V) carries no angle


LOST = 0.5  # rad: the angle counts as lost beyond this (12 % of torque, cos 0.5 = 0.88)


def crossing(r: Result) -> tuple[np.ndarray, bool]:
    """The samples of the zero-speed crossing: from the first time the true
    speed is within +-REVERSAL_BAND (after 0.05 s) to the first time after
    that it is below -REVERSAL_BAND; and whether it got there (False: the
    crossing runs to the end of the run)."""
    t0 = r.t >= 0.05
    inside = t0 & (np.abs(r.n_rpm) <= REVERSAL_BAND)
    m = np.zeros(r.t.size, dtype=bool)
    if not inside.any():
        return m, False
    i_in = int(np.argmax(inside))
    below = r.n_rpm[i_in:] < -REVERSAL_BAND
    done = bool(below.any())
    i_out = i_in + int(np.argmax(below)) if done else r.t.size
    m[i_in:i_out] = True
    return m, done


def fig22_metrics(r: Result) -> dict[str, float]:
    band, done = crossing(r)
    err = np.abs(r.theta_error)
    outside = (r.t >= 0.05) & ~band
    dt = r.scenario.T_sp * r.log_stride
    return {
        # a run that never gets through the band has lost the rotor: pi
        "outside": float(np.max(err[outside])) if done else math.pi,
        "band": float(np.max(err[band])) if band.any() else 0.0,
        "band_lost_ms": float(np.sum(err[band] > LOST) * dt * 1e3),
        "band_ms": float(np.sum(band) * dt * 1e3),
        "done": float(done),
    }


def _stable(r: Result) -> tuple[int, float, float]:
    """Stable, and working well (Fig. 23's words): the drive holds its speed
    within 1 % and the angle error stays within 0.1 rad over the last half
    of the run, without a fault."""
    m = r.window(r.scenario.duration / 2, r.scenario.duration)
    n_ref = r.scenario.w_M_ref(0.0) / RPM
    dn = float(np.max(np.abs(r.n_rpm[m] - n_ref)) / n_ref)
    err = float(np.max(np.abs(r.theta_error[m])))
    return int(dn <= STABLE_SPEED and err <= STABLE_ANGLE and r.status == 0), dn, err
