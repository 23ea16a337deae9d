"""yao2022: what the experiments measure from a run or a design: the lumped
disturbance and its periodic part (Fig. 4), the PLL's bandwidth from the C
code (Fig. 7), the speed ripple and its harmonics (Table V), the handover
and peak position errors (Figs. 14, 19-21), the zero crossing (Fig. 22) and
stability (Fig. 23). Pure functions of a :class:`~smodrive.engine.Result`
or of design parameters; :mod:`smodrive.scenarios.yao2022` runs the experiments."""

from __future__ import annotations

import ctypes as ct
import dataclasses
import math

import numpy as np
import scipy.optimize

from ..analysis import metrics
from ..design import yao2022 as dz
from ..engine import Result, _ffi
from ..model import RPM, Scenario

STABLE_SPEED, STABLE_ANGLE = 0.01, math.pi / 2  # the bounds of _stable (fig23_basis)
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


def ripple_parts(r: Result, spectra: bool = False) -> dict[str, float]:
    """The steady-state speed ripple of a run and what it is made of (r/min):
    the estimated speed's half peak-to-peak (`ripple`, :func:`speed_ripple`),
    the true speed's (`wander`) and the RMS of the estimation error n_hat - n
    (`err_rms`); with `spectra`, the share of the error's power within the
    PLL's bandwidth (`err_in_pll`) and of the true speed's below 50 Hz
    (`wander_below_50`)."""
    m = r.window(SETTLE, r.scenario.duration)
    n_hat, n = r.n_hat_rpm[m], r.n_rpm[m]
    out = {"ripple": float((n_hat.max() - n_hat.min()) / 2),
           "wander": float((n.max() - n.min()) / 2), "err_rms": float(np.std(n_hat - n))}
    if spectra:
        f = np.fft.rfftfreq(n.size, r.scenario.T_sp * r.log_stride)

        def share(x: np.ndarray, f_max: float) -> float:
            p = np.abs(np.fft.rfft(x - np.mean(x))) ** 2
            return float(np.sum(p[f < f_max]) / np.sum(p))

        out["err_in_pll"] = share(n_hat - n, dz.pll_bandwidth_hz(dz.PllPars()))
        out["wander_below_50"] = share(n, 50.0)
    return out


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


def _observer_dc_error(s: Scenario, th: float) -> tuple[float, np.ndarray, np.ndarray]:
    """The DC fixed point of the sliding-mode observer (9), (16), (18) with
    the reaching law (56) (equivalent control of Y4, s = 0, d_hat = 0) and
    the EMF adaption (34) (which leaves no DC in s(k) - Q s(k-1)), designed
    on the controller's model (capacitance C1_hat_ratio C1), driven by the
    true plant's DC steady state at the scenario's constant speed and fan
    load, seen in an estimated frame turned by th = theta - theta_hat (the
    drive's i_gamma = 0, i_delta carrying the load). Returns (the angle (47)
    reads, the EMF estimate and the true EMF, both in the estimated frame)."""
    m, c = s.motor, s.controller
    w = s.w_M_ref(0.0) * m.n_p
    true = dz.DesignPlant(m, s.lcl, s.T_sp)
    G, H, F = dz.rotor_frame_model(true, w)
    i_delta = s.load.k_fan * s.w_M_ref(0.0) ** 2 / (m.k_t * math.cos(th))
    rot = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    i2 = rot.T @ np.array([0.0, i_delta])  # in the true rotor frame
    e = np.array([0.0, w * m.psi_r])
    # true DC steady state x = G x + H u + F e, x = [u_c, i_1, i_2], for u_c, i_1, u
    IG = np.eye(6) - G
    z = np.linalg.solve(np.hstack([IG[:, 0:4], -H]), F @ e - IG[:, 4:6] @ i2)
    i1, u = z[2:4], z[4:6]
    est_motor = dataclasses.replace(m, R_s=c.R_s_hat, L_s=c.L_s_hat, psi_r=c.psi_r_hat)
    est = dz.DesignPlant(est_motor, dataclasses.replace(s.lcl, C1=s.lcl.C1 * c.C1_hat_ratio),
                         s.T_sp)
    M = dz.design_point(est, w, dz.ObserverDesignPars(Q=tuple(c.Q)))
    meas = np.concatenate([rot @ i1, rot @ i2])
    # unknowns z = [x_hat (6), x_c (2), e_hat (2)]; y = F_t (x_hat[2:6] - meas)
    sel = lambda a, b: np.eye(10)[a:b]
    Ft = M.T_r[2:, 2:]
    Y, y0 = Ft @ sel(2, 6), -Ft @ meas
    Xc, Eh, X = sel(6, 8), sel(8, 10), sel(0, 6)
    S = M.Gamma_c @ Xc + M.Gamma_1 @ Y[0:2] + M.Gamma_2 @ Y[2:4]  # eq. (18)
    W = -M.K_c @ Xc - M.K_y @ Y[0:2] + Eh  # eq. (56) with s = 0, d_hat = 0 (Y4)
    A = np.vstack([S, X - M.G @ X - M.F @ W, Xc - M.H_c @ Xc - M.D1 @ Y[0:2] - M.D2 @ Y[2:4]])
    b = np.concatenate([-(M.Gamma_1 @ y0[0:2] + M.Gamma_2 @ y0[2:4]),
                        M.H @ (rot @ u) + M.F @ (-M.K_y @ y0[0:2]),
                        M.D1 @ y0[0:2] + M.D2 @ y0[2:4]])
    e_hat = np.linalg.solve(A, b)[8:10]
    return math.atan2(-e_hat[0], e_hat[1]), e_hat, rot @ e


def capacitance_bias(s: Scenario) -> float:
    """The angle error theta - theta_hat in the steady state of eq. (52)-(58)
    for the sliding-mode observer of scenario `s` (constant speed, fan load,
    the observer's capacitance C1_hat_ratio C1): the frame angle at which the
    observer's DC fixed point (:func:`_observer_dc_error`) makes (47) read
    zero, which the PLL (48) settles to."""
    return float(scipy.optimize.brentq(lambda th: _observer_dc_error(s, th)[0], -1.0, 1.0,
                                       xtol=1e-10))


def _stable(r: Result) -> tuple[int, float, float]:
    """Stable (Fig. 23's word): the drive holds its speed within 1 % and the
    angle error stays within pi/2 over the last half of the run, without a
    fault. How large the error is, is not stability (the Fig. 23 bias claim)."""
    m = r.window(r.scenario.duration / 2, r.scenario.duration)
    n_ref = r.scenario.w_M_ref(0.0) / RPM
    dn = float(np.max(np.abs(r.n_rpm[m] - n_ref)) / n_ref)
    err = float(np.max(np.abs(r.theta_error[m])))
    return int(dn <= STABLE_SPEED and err <= STABLE_ANGLE and r.status == 0), dn, err
