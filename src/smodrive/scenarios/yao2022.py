"""yao2022: the experiments of the LCL-filtered high-speed SPMSM paper as
runnable scenarios that yield claims.

Plant: Table II; fan load fitted to Table IV; the values the paper does not
give (inertia, ADC error, noise, controller gains, start-up) are the
documented assumptions of :data:`BASE` and docs/assumptions.md. The
ADC scaling error and the PWM harmonics arise from the models (per-phase ADC
gains, regular-sampled carrier PWM), not from injected sinusoids.
"""

from __future__ import annotations

import ctypes as ct
import dataclasses
import math
from typing import Callable

import numpy as np

from .. import _ffi
from ..analysis import metrics
from ..analysis import pwm as pwm_an
from ..claims import Claim
from ..design import yao2022 as dz
from ..params import (
    RPM,
    AdcCfg,
    ControllerCfg,
    InverterCfg,
    LclFilterPars,
    LoadCfg,
    MotorPars,
    Profile,
    Scenario,
)
from ..simulate import Result
from .common import Experiment, Outcome, ProgressFn, run_sim

# Table II; J and B are not given (assumed), the fan load is fitted to
# Table IV (i_q = 30 A at 100 kr/min: 1.5 * 0.0012 * 30 / (10472 rad/s)^2 =
# 4.9e-10 N m s^2), and P_N is that fan load's power at the rated speed.
MOTOR = MotorPars(R_s=0.023, L_s=24e-6, psi_r=0.0012, n_p=1, J=1e-5, B=0.0, P_N=560.0,
                  n_N=100e3)
# ADC scaling error (assumed; the paper gives none): +-1 % on phases a, b of
# both current sensors; noise and range assumed (docs/assumptions.md).
ADC = AdcCfg(gain=(1.01, 0.99, 1.0), gain_i1=(1.01, 0.99, 1.0), noise=0.02, bits=12,
             full_scale=60.0)
# The drive of Fig. 1: PI current control with decoupling (gains assumed),
# the sliding-mode observer + PLL of eq. (48)-(50), speed PI on the model
# 1.5 n_p^2 psi / J; the observer's model is the plant's (Table II).
CONTROLLER = ControllerCfg(
    current="pi", position="lcl_smo_pll", start="running",
    L_s_hat=MOTOR.L_s, R_s_hat=MOTOR.R_s, psi_r_hat=MOTOR.psi_r,
    k_p_i=0.35, k_i_i=600.0, R_v=0.0, emf_ff=True,
    speed_bw=60.0, J_hat=MOTOR.J, psi_r_pi=MOTOR.psi_r, i_max=45.0,
    i_start=15.0, a_start_rpm_s=5e3, n_handover=5e3, t_dead_comp=0.0,
)
BASE = Scenario(
    name="yao2022.base", T_sp=50e-6, duration=0.5, motor=MOTOR, lcl=LclFilterPars(),
    inverter=InverterCfg(u_dc=65.0, pwm="carrier", t_dead=0.0), adc=ADC,
    load=LoadCfg(k_fan=4.9e-10), controller=CONTROLLER,
)
SPEEDS = (30e3, 60e3, 100e3)
TAG = {30e3: "30k", 60e3: "60k", 100e3: "100k"}
SETTLE, WINDOW = 0.1, 0.2  # steady-state runs: settle, then measure


_sim = run_sim


def steady(n: float, law: str = "proposed", name: str | None = None, **kw) -> Scenario:
    return BASE.replace(
        name=name or f"yao2022.steady.{law}.{TAG.get(n, int(n))}",
        duration=SETTLE + WINDOW,
        n_M0=n,
        w_M_ref=Profile.const(n * RPM),
        controller=dataclasses.replace(BASE.controller, law=law, **kw),
    )


# ----------------------------------------------------------- Table I -------

def run_table1(progress: ProgressFn) -> Outcome:
    V_Q, M, N = 60.0, 0.9, 12  # Table I: V_Q = 60 V, M = 0.9, f_s / f_e = 12
    rep = pwm_an.leg_harmonics_from_edges(V_Q, M, N, 5, T=1 / 20e3)
    exp = pwm_an.leg_harmonics_bessel(V_Q, M, N, 5)
    table = ["26.723", "0.4097", "0.1288", "0.0073", "0.0013"]
    claims = []
    for h, (r, e, txt) in enumerate(zip(rep, exp, table), start=1):
        half_unit = 0.5 * 10.0 ** (-len(txt.split(".")[1]))
        claims.append(Claim(
            id=f"yao2022.table1.h{h}_V",
            statement=(f"Regular-sampled single-phase leg voltage, V_Q = 60 V, M = 0.9, "
                       f"f_s/f_e = 12: amplitude of harmonic {h}, from the plant's own PWM edges; "
                       f"the Bessel series of symmetric regular sampling gives {e:.6f} V."),
            paper=float(txt), expected=None, reproduced=float(r), unit="V",
            tolerance=half_unit,
            basis="the paper prints the value rounded to its last decimal, so the exact value "
                  "lies within half a unit of that decimal",
        ))
    progress("yao2022.table1", 1.0)
    return Outcome(claims)


# -------------------------------------------------------------- Fig. 4 ------

def lumped_disturbance(r: Result) -> np.ndarray:
    """D(k) = s(k+1) - Q s(k) - v(k), the lumped disturbance of the reaching
    mode (30) measured one sample later (complex gamma + j delta)."""
    Q = np.array(r.scenario.controller.Q)
    s = r["s_g"] + 1j * r["s_dl"]
    v = r["v_g"] + 1j * r["v_dl"]
    return (s[1:].real - Q[0] * s[:-1].real - v[:-1].real) + 1j * (
        s[1:].imag - Q[1] * s[:-1].imag - v[:-1].imag)


def run_fig4(progress: ProgressFn) -> Outcome:
    s = steady(100e3, name="yao2022.fig4")
    r = _sim(s, progress)
    m = r.window(SETTLE, s.duration)[:-1]
    d = lumped_disturbance(r)[m]
    d = d - d.mean()  # the EMF part is constant in steady state
    e17 = d[2:] - d[1:-1]  # eq. (31)
    e18 = d[2:] - 2 * d[1:-1] + d[:-2]  # eq. (32)
    ratio = float(np.sqrt(np.mean(np.abs(e18) ** 2) / np.mean(np.abs(e17) ** 2)))
    W2 = 2 * 2 * np.pi * 100e3 / 60 * s.T_sp
    claims = [Claim(
        id="yao2022.fig4.comp_error_ratio_18_over_17",
        statement=("100 kr/min: RMS compensation error of the time-delay estimator of ref. [18] "
                   "(eq. (32)) over that of ref. [17] (eq. (31)), applied to the lumped "
                   "disturbance d(k) of the simulation (ADC scaling error and PWM harmonics); "
                   "paper: 'even become worse in [18]'. Per harmonic the ratio is "
                   f"2 sin(W/2): {2 * math.sin(W2 / 2):.3f} at 2 f_e, "
                   f"{2 * math.sin(1.5 * W2 / 2):.3f} at 3 f_e."),
        paper=None, expected=None, reproduced=ratio, unit="", tolerance=1.0, check="min",
        basis="'worse' means a ratio above 1; at 100 kr/min every component at or above "
              "2 f_e (3333 Hz, W = pi/3) has 2 sin(W/2) >= 1",
    )]

    def plot(fig_dir):
        from .. import plots

        n = min(d.size, int(0.005 / s.T_sp))
        return plots.save(plots.disturbance_panels(
            r.t[:-1][m][:n], d[:n], e17[:n], e18[:n], s.T_sp,
            "Fig. 4: lumped disturbance and time-delay compensation errors, 100 kr/min"),
            fig_dir, "yao2022_fig4")

    return Outcome(claims, {s.name: r}, [("yao2022_fig4", plot)])


# -------------------------------------------------------------- Fig. 7 ------

def pll_bandwidth_measured(pll: dz.PllPars, n: int = 400_000) -> float:
    """-3 dB bandwidth of the firmware PLL closed around eq. (48), from its
    impulse response computed by the C code."""
    import scipy.optimize

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


def run_fig7(progress: ProgressFn) -> Outcome:
    pll = dz.PllPars()
    exp = dz.pll_bandwidth_hz(pll)
    rep = pll_bandwidth_measured(pll)
    progress("yao2022.fig7", 1.0)

    def plot(fig_dir):
        from .. import plots

        f = np.logspace(0, np.log10(0.5 / pll.T), 800)
        responses = [
            (f"k = ({kt}, {kw}, {ka})",
             dz.pll_open_loop(dataclasses.replace(pll, k_theta=kt, k_omega=kw, k_a=ka))(
                 np.exp(2j * np.pi * f * pll.T)))
            for kt, kw, ka in ((0.1, 10, 10), (0.2, 10, 10), (0.1, 50, 10), (0.1, 10, 100))]
        return plots.save(plots.pll_bode(
            f, responses, f"Fig. 7: G_PLL of eq. (49); closed loop -3 dB at {rep:.1f} Hz"),
            fig_dir, "yao2022_fig7")

    return Outcome([Claim(
        id="yao2022.fig7.pll_bandwidth_hz",
        statement=("Closed-loop -3 dB bandwidth of the PLL (48) with the gains of eq. (50), "
                   "measured on the firmware PLL's impulse response; expected from the "
                   "transfer function (49) with unity feedback."),
        paper=None, expected=exp, reproduced=rep, unit="Hz", tolerance=0.01, check="rel",
        basis="the float32 PLL and the truncated impulse response (20 time constants of the "
              "slowest pole) change the gain by far less than 1 %",
    )], figures=[("yao2022_fig7", plot)])


# ------------------------------------------------------ Figs. 9 and 10 ------

PAPER_FIG10 = {30e3: 0.018, 60e3: 0.008, 100e3: 0.024}  # rad, Sec. VII-A
INJ_W = 1.0  # s, each averaging window (before and during the injection)
INJ_T = 0.2 + INJ_W  # +5 A on gamma from here (the start transient settled)


def run_fig9_10(progress: ProgressFn) -> Outcome:
    claims, res = [], {}
    for n in SPEEDS:
        s = steady(n, name=f"yao2022.fig10.{TAG[n]}").replace(
            duration=INJ_T + 0.05 + INJ_W, i_d_ref=Profile.steps(0.0, (INJ_T, 5.0)))
        r = _sim(s, progress)
        res[s.name] = r
        before, after = r.window(INJ_T - INJ_W, INJ_T), r.window(INJ_T + 0.05, s.duration)
        i_dl1, i_dl2 = np.mean(r["i_dl"][before]), np.mean(r["i_dl"][after])
        i_g2 = np.mean(r["i_g"][after])
        inj = float(math.atan((i_dl1 - i_dl2) / i_g2))  # eq. (60)
        # standard error of each window mean by batch means (10 batches): the
        # delta current carries the speed loop's noise-driven wander
        def sem(x: np.ndarray) -> float:
            b = np.array_split(x, 10)
            return float(np.std([np.mean(v) for v in b], ddof=1) / math.sqrt(len(b)))

        sigma = math.hypot(sem(r["i_dl"][before]), sem(r["i_dl"][after])) / abs(i_g2)
        # eq. (59) holds for the error theta_hat - theta (eq. (47) uses the
        # opposite sign, theta - theta_hat, as r.theta_error does); the method
        # reads the error while the 5 A flow, through the i_2 sensor, whose
        # per-phase gains rotate the measured vector by scaling_rotation().
        true_before = -float(np.mean(r.theta_error[before]))
        true_during = -float(np.mean(r.theta_error[after]))
        rot = metrics.scaling_rotation(s.adc.gain)
        tag = TAG[n]
        claims.append(Claim(
            id=f"yao2022.fig10.pos_error_rad_{tag}",
            statement=(f"{n / 1e3:g} kr/min: position error by the current-injection method, "
                       "eq. (59)-(60), +5 A on the gamma axis, speed loop active, fan load, "
                       f"{INJ_W:g} s windows. Expected: the simulation's true mean error while "
                       f"the 5 A flow ({true_during:+.4f} rad; {true_before:+.4f} before) minus "
                       f"the rotation the i_2 sensor's +-1 % ADC gains give the measured current "
                       f"({rot * 1e3:.2f} mrad, the mean part of the scaling error, "
                       "docs/errata.md Y9)."),
            paper=PAPER_FIG10[n], expected=true_during - rot, reproduced=inj, unit="rad",
            tolerance=round(0.002 + 3 * sigma, 4),
            basis=(f"the method divides a difference of two mean delta currents by 5 A; their "
                   f"standard error (batch means) gives sigma = {sigma:.4f} rad; 2 mrad more "
                   "for what the first-order prediction leaves out (the 2 f_e part of the "
                   "scaling error through the observer's nonlinear angle extraction, products "
                   "of two ~6 mrad terms, and the float32 controller): 2 mrad + 3 sigma"),
            why_fail="the reading of eq. (60) departs from the true error plus the ADC "
                     "scaling rotation by more than noise and second-order terms explain",
        ))
        claims.append(Claim(
            id=f"yao2022.fig9.true_pos_error_rad_{tag}",
            statement=(f"{n / 1e3:g} kr/min: mean position error from the true angle, steady "
                       "state (the paper's hardware value by the injection method beside)."),
            paper=PAPER_FIG10[n], expected=None, reproduced=abs(true_before), unit="rad",
            tolerance=0.03, check="max",
            basis="the paper calls its 0.008-0.024 rad 'high accuracy'; 0.03 rad (1.7 deg) "
                  "keeps the claim on that scale",
        ))

    def plot(fig_dir):
        from .. import plots

        rs = list(res.values())
        return plots.save(plots.time_panels(
            rs, [f"{n / 1e3:g} kr/min" for n in SPEEDS],
            f"Figs. 9-10: position accuracy by +5 A gamma injection at {INJ_T:g} s",
            [("i_2 gamma, delta (A)", [("i_g", "gamma"), ("i_dl", "delta")]),
             ("position error (rad)", [("theta_error", "true"),
                                       ("theta_err_est", "estimated, eq. (47)")]),
             ("speed (r/min)", [("n_rpm", "true"), ("n_hat_rpm", "estimated")])]),
            fig_dir, "yao2022_fig10")

    return Outcome(claims, res, [("yao2022_fig10", plot)])


# --------------------------------------------------- Table V, Figs. 12-13 ----

PAPER_RIPPLE = {"tde17": {30e3: 200.0, 60e3: 600.0, 100e3: 1100.0},
                "proposed": {30e3: 200.0, 60e3: 350.0, 100e3: 600.0}}


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


def run_table5(progress: ProgressFn) -> Outcome:
    claims, res, rip = [], {}, {}
    by_key = {}
    for law in ("tde17", "proposed"):
        for n in SPEEDS:
            s = steady(n, law)
            r = _sim(s, progress)
            res[s.name] = r
            by_key[(law, n)] = r
            rip[(law, n)] = speed_ripple(r)
    harm = {(law, n): harmonic_ripple(by_key[(law, n)], n) for law in ("tde17", "proposed")
            for n in SPEEDS}
    why = ("the speed estimate is the PLL's (eq. (48), (50)), whose closed loop passes only "
           "351 Hz (gain 0.10 at 3.3 kHz, 0.07 at 5 kHz): the 2 f_e and 3 f_e chattering is "
           "attenuated by the PLL itself, so with the assumed +-1 % ADC gain error the "
           "ripple is a few to tens of r/min, dominated by ADC noise, not hundreds; the "
           "chattering itself is reduced 5x by the proposed law (chattering claim), and the "
           "2 f_e / 3 f_e lines of the speed estimate with it (at 100 kr/min "
           f"{harm[('tde17', 100e3)]:.2f} -> {harm[('proposed', 100e3)]:.2f} r/min, "
           "harmonic-ripple claim); the paper's ADC error and noise are not given")
    for law, name in (("tde17", "baseline"), ("proposed", "proposed")):
        for n in SPEEDS:
            claims.append(Claim(
                id=f"yao2022.table5.ripple_rpm_{name}_{TAG[n]}",
                statement=(f"{n / 1e3:g} kr/min, reaching law "
                           f"{'(61)-(63) of ref. [17]' if law == 'tde17' else '(33)-(35)'}: half "
                           "peak-to-peak speed-estimation ripple in steady state."),
                paper=PAPER_RIPPLE[law][n], expected=None, reproduced=rip[(law, n)],
                unit="r/min", tolerance=0.5, check="rel",
                basis="hardware ripple depends on the ADC error and noise the paper does not "
                      "give; within a factor of about 2 (rel 0.5) would reproduce its scale",
                why_fail=why,
            ))
    red = rip[("proposed", 100e3)] / rip[("tde17", 100e3)]
    claims.append(Claim(
        id="yao2022.table5.ripple_reduction_100k",
        statement=("100 kr/min: speed-estimation ripple of the proposed reaching law over the "
                   "baseline (61)-(63) (paper: 600 / 1100)."),
        paper=600.0 / 1100.0, expected=None, reproduced=red, unit="", tolerance=0.2,
        check="abs",
        basis="the paper's ratio from two rounded hardware readings; 0.2 absolute",
        why_fail="both ripples are small here (see the ripple claims), so the ratio is set by "
                 "residual noise rather than by the 2 f_e / 3 f_e chattering the method targets; "
                 "those lines alone fall to "
                 f"{harm[('proposed', 100e3)] / harm[('tde17', 100e3)]:.2f} of the baseline's "
                 "(harmonic-ripple claim)",
    ))
    claims.append(Claim(
        id="yao2022.table5.harmonic_ripple_reduction_100k",
        statement=("100 kr/min: the 2 f_e and 3 f_e lines of the estimated speed (RSS of the two "
                   "amplitudes) with the proposed reaching law over those with the baseline "
                   "(61)-(63); the paper's FFTs place its ripple there and its Table V ratio is "
                   "600 / 1100. Lines, baseline / proposed: " + "; ".join(
                       f"{n / 1e3:g} kr/min {harm[('tde17', n)]:.3f} / "
                       f"{harm[('proposed', n)]:.3f} r/min" for n in SPEEDS) + "."),
        paper=600.0 / 1100.0, expected=None,
        reproduced=harm[("proposed", 100e3)] / harm[("tde17", 100e3)], unit="",
        tolerance=600.0 / 1100.0, check="max",
        basis="the proposed law must cut the chattering lines of the speed estimate at least "
              "as much as the paper's total ripple fell (its total includes non-periodic "
              "ripple, so the lines alone should fall at least as far)",
    ))
    chat = {k: float(np.sqrt(np.mean(np.abs(r["s_g"] + 1j * r["s_dl"])[
        r.window(SETTLE, r.scenario.duration)] ** 2))) for k, r in by_key.items()}
    claims.append(Claim(
        id="yao2022.fig12_13.chattering_ratio_100k",
        statement=("100 kr/min: RMS of the switching function |s(k)| (the chattering) with the "
                   "proposed reaching law over that with the baseline (61)-(63) "
                   f"({chat[('proposed', 100e3)]:.3f} A over {chat[('tde17', 100e3)]:.3f} A; "
                   f"30 kr/min: {chat[('proposed', 30e3)]:.3f} over {chat[('tde17', 30e3)]:.3f})"
                   " - the mechanism behind Table V."),
        paper=None, expected=None, reproduced=chat[("proposed", 100e3)] / chat[("tde17", 100e3)],
        unit="", tolerance=0.5, check="max",
        basis="the paper's point is a clear reduction of the chattering; at least halving it",
    ))

    def plot17(fig_dir):
        from .. import plots

        rs = [by_key[("proposed", 60e3)], by_key[("proposed", 100e3)]]
        plots.save(plots.waveform_spectrum(rs, ["60 kr/min", "100 kr/min"], "i_alpha",
                                           "phase A motor current (A)",
                                           "Fig. 17: motor current (LCL-filtered)"),
                   fig_dir, "yao2022_fig17")
        return plots.save(plots.waveform_spectrum(rs[1:], ["100 kr/min"], "uc_alpha",
                                                  "phase A capacitor voltage (V)",
                                                  "Fig. 18: capacitor voltage and its spectrum"),
                          fig_dir, "yao2022_fig18")

    def plot(fig_dir):
        from .. import plots

        return plots.save(plots.ripple_panels(by_key, SPEEDS,
                                              "Figs. 12-13, Table V: speed-estimation ripple "
                                              "and chattering, baseline vs proposed"),
                          fig_dir, "yao2022_fig12_13")

    return Outcome(claims, res, [("yao2022_fig12_13", plot), ("yao2022_fig17_18", plot17)])


# -------------------------------------------------------------- Fig. 14 -----

FIG14_RATE = 20e3  # r/min per s after the handover (assumed; the paper gives none)


def fig14_scenario() -> Scenario:
    t_up = 1.1 + 95e3 / FIG14_RATE
    return BASE.replace(
        name="yao2022.fig14", duration=t_up + 0.3, n_M0=0.0,
        controller=dataclasses.replace(BASE.controller, start="if"),
        w_M_ref=Profile((0.0, 1.1, t_up), (5e3, 5e3, 100e3)).scaled(RPM), log_stride=2,
    )


def run_fig14(progress: ProgressFn) -> Outcome:
    s = fig14_scenario()
    r = _sim(s, progress)
    closed = r["phase"] > 0.5
    t_ho = float(r.t[np.argmax(closed)]) if closed.any() else s.duration
    m = closed & (r.t >= t_ho + 0.1)
    peak = float(np.max(np.abs(r.theta_error[m]))) if m.any() else float("nan")
    claims = [Claim(
        id="yao2022.fig14.pos_error_peak_rad",
        statement=(f"0 -> 100 kr/min: forced-angle start at 15 A, handover at 5 kr/min "
                   f"(t = {t_ho:.2f} s), then sensorless acceleration at "
                   f"{FIG14_RATE / 1e3:g} kr/min/s; peak position error from 0.1 s after the "
                   "handover to the end (paper, simulation: below 0.02 rad)."),
        paper=0.02, expected=None, reproduced=peak, unit="rad", tolerance=0.02, check="max",
        basis="the paper's own bound",
        why_fail=("the peak comes right after the handover, at 5-10 kr/min, where the back "
                  "EMF is only 0.6-1.3 V against the assumed 0.02 A ADC noise; without noise "
                  "and ADC gain error the peak is about 0.03 rad, the PLL of eq. (50) settling "
                  "its acceleration state slowly (slowest pole 0.99995). From 25 kr/min on "
                  "the error stays below about 0.025 rad"),
    )]

    def plot(fig_dir):
        from .. import plots

        return plots.save(plots.time_panels(
            [r], ["0 -> 100 kr/min"],
            "Figs. 14-16: forced-angle start, handover and sensorless acceleration",
            [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true"),
                                ("n_hat_rpm", "estimated")]),
             ("position error (rad)", [("theta_error", "true")]),
             ("i_2 delta (A)", [("i_dl", "measured"), ("i_q_ref", "reference")]),
             ("phase", [("phase", "0 open loop, 1 sensorless")])]),
            fig_dir, "yao2022_fig14_16")

    return Outcome(claims, {s.name: r}, [("yao2022_fig14_16", plot)])


# ------------------------------------------------------ Figs. 19-21 ---------

def fig19_scenario() -> Scenario:
    # torque-current step 10 -> 15 A at 0.05 s (speed loop off, fan load)
    n0 = math.sqrt(10.0 * 1.5 * 0.0012 / 4.9e-10) / RPM  # fan equilibrium at 10 A
    return BASE.replace(
        name="yao2022.fig19", duration=0.35, n_M0=n0, w_M_ref=Profile.const(n0 * RPM),
        controller=dataclasses.replace(BASE.controller, speed_loop=False),
        i_q_ref=Profile.steps(10.0, (0.05, 15.0)),
    )


def run_fig19_21(progress: ProgressFn) -> Outcome:
    s = fig19_scenario()
    r = _sim(s, progress)
    m = r.window(0.02, s.duration)
    peak = float(np.max(np.abs(r.theta_error[m])))
    dn = float(np.max(np.abs(r.n_hat_rpm[m] - r.n_rpm[m])))
    claims = [
        Claim(id="yao2022.fig19.pos_error_peak_rad",
              statement="Torque-current step 10 -> 15 A at 0.05 s with the fan load: peak "
                        "position error (paper: within 0.1 rad).",
              paper=0.1, expected=None, reproduced=peak, unit="rad", tolerance=0.1,
              check="max", basis="the paper's own bound"),
        Claim(id="yao2022.fig21.speed_error_peak_rpm",
              statement="Same step: peak speed-estimation error while the fan load "
                        "accelerates the motor (paper: about 150 r/min).",
              paper=150.0, expected=None, reproduced=dn, unit="r/min", tolerance=150.0,
              check="max",
              basis="'about 150 r/min' is the paper's maximum; a simulation without its "
                    "measurement noise should not exceed it"),
    ]

    def plot(fig_dir):
        from .. import plots

        return plots.save(plots.time_panels(
            [r], ["i_delta step 10 -> 15 A at 0.05 s"],
            "Figs. 19-21: torque-current step with the fan load",
            [("i_2 delta (A)", [("i_dl", "measured"), ("i_q_ref", "reference")]),
             ("position error (rad)", [("theta_error", "true")]),
             ("speed (r/min)", [("n_rpm", "true"), ("n_hat_rpm", "estimated")])]),
            fig_dir, "yao2022_fig19_21")

    return Outcome(claims, {s.name: r}, [("yao2022_fig19_21", plot)])


# -------------------------------------------------------------- Fig. 22 -----

def fig22_scenario() -> Scenario:
    return BASE.replace(name="yao2022.fig22", duration=2.6, n_M0=30e3,
                        w_M_ref=Profile((0.0, 0.2, 2.2), (30e3, 30e3, -30e3)).scaled(RPM),
                        log_stride=2)


REVERSAL_BAND = 3e3  # r/min around zero where the EMF (< 0.4 V) carries no angle


def run_fig22(progress: ProgressFn) -> Outcome:
    s = fig22_scenario()
    r = _sim(s, progress)
    m = r.window(0.05, s.duration) & (np.abs(r.n_rpm) > REVERSAL_BAND)
    peak = float(np.max(np.abs(r.theta_error[m])))

    def plot(fig_dir):
        from .. import plots

        return plots.save(plots.time_panels(
            [r], ["+30 -> -30 kr/min"], "Fig. 22: speed reversal",
            [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true"),
                                ("n_hat_rpm", "estimated")]),
             ("position error (rad)", [("theta_error", "true")])]),
            fig_dir, "yao2022_fig22")

    return Outcome([Claim(
        id="yao2022.fig22.reversal_pos_error_peak_rad",
        statement=("Speed reversal +30 -> -30 kr/min in 2 s, sensorless throughout: peak "
                   f"position error outside +-{REVERSAL_BAND / 1e3:g} kr/min (the paper shows "
                   "the reversal as a figure only)."),
        paper=None, expected=None, reproduced=peak, unit="rad", tolerance=0.2, check="max",
        basis="0.2 rad (11 deg) costs 2 % of torque; the paper's figure shows the estimate "
              "following the reversal without loss of lock",
        why_fail=("near zero speed the back EMF vanishes and the estimate loses the angle "
                  "for a moment (excluded band), then the PLL re-locks; just outside the "
                  "band, at 3-4 kr/min (EMF 0.4-0.5 V), the assumed 0.02 A ADC noise puts the "
                  "error at the bound (about 0.06 rad with an ideal ADC)"),
    )], {s.name: r}, [("yao2022_fig22", plot)])


# -------------------------------------------------------------- Fig. 23 -----

def fig23_scenario(observer: str) -> Scenario:
    position = {"linear": "lcl_linear", "smo": "lcl_smo_pll"}[observer]
    return steady(60e3, name=f"yao2022.fig23.{observer}", position=position,
                  C1_hat_ratio=2.0).replace(duration=0.4)


def _stable(r: Result) -> tuple[int, float, float]:
    """Stable = the drive holds its speed within 5 % and the angle error stays
    below 0.5 rad over the last half of the run."""
    m = r.window(r.scenario.duration / 2, r.scenario.duration)
    n_ref = r.scenario.w_M_ref(0.0) / RPM
    dn = float(np.max(np.abs(r.n_rpm[m] - n_ref)) / n_ref)
    err = float(np.max(np.abs(r.theta_error[m])))
    return int(dn < 0.05 and err < 0.5 and r.status == 0), dn, err


def run_fig23(progress: ProgressFn) -> Outcome:
    res, verdict = {}, {}
    for obs in ("linear", "smo"):
        s = fig23_scenario(obs)
        r = _sim(s, progress)
        res[s.name] = r
        verdict[obs] = _stable(r)
    basis = ("stable = in the sensorless loop, speed held within 5 % and angle error below "
             "0.5 rad over the second half of a 0.4 s run at 60 kr/min")
    lin, smo = verdict["linear"], verdict["smo"]

    def plot(fig_dir):
        from .. import plots

        return plots.save(plots.time_panels(
            list(res.values()),
            ["linear observer (65), C_hat = 2 C", "sliding-mode observer, C_hat = 2 C"],
            "Fig. 23: robustness to a capacitance error (sensorless, 60 kr/min)",
            [("position error (rad)", [("theta_error", "true")]),
             ("speed (r/min)", [("n_rpm", "true"), ("n_hat_rpm", "estimated")])]),
            fig_dir, "yao2022_fig23")

    return Outcome([
        Claim(id="yao2022.fig23.linear_observer_stable",
              statement=("Sensorless at 60 kr/min with the linear reduced-order observer "
                         "(64)-(65), poles [0.4 0.4 0.5 0.5], designed with twice the real "
                         f"capacitance: stable (1) or not (0) (paper: unstable). Speed deviation "
                         f"{lin[1]:.3f}, peak angle error {lin[2]:.3f} rad."),
              paper=0.0, expected=None, reproduced=float(lin[0]), unit="", tolerance=0.0,
              basis=basis,
              why_fail=("the observer's error dynamics Theta = G22 - L G12 keep the designed "
                        "poles whatever the capacitance error, which only biases the estimate "
                        "(here by under 1 mrad); the instability the paper observed on hardware "
                        "needs a mechanism the paper does not describe (with half the real "
                        "capacitance the same observer does fail in this simulation)")),
        Claim(id="yao2022.fig23.smo_stable",
              statement=("Same test with the sliding-mode observer designed with twice the real "
                         f"capacitance (paper: stable). Speed deviation {smo[1]:.3f}, peak angle "
                         f"error {smo[2]:.3f} rad."),
              paper=1.0, expected=None, reproduced=float(smo[0]), unit="", tolerance=0.0,
              basis=basis),
    ], res, [("yao2022_fig23", plot)])


# ------------------------------------------------------------- Table VI -----

PAPER_TABLE6 = {"observer": ("prediction", 489.0), "reaching_law": ("reaching_law", 268.0),
                "pll": ("pll", 28.0)}


def run_table6(progress: ProgressFn) -> Outcome:
    from ..analysis import cost

    try:
        counts = cost.instructions_per_call()
        why = ""
    except (RuntimeError, OSError) as exc:  # tool or sources missing: the claim fails
        counts = {k: float("nan") for k in cost.PARTS}
        why = str(exc)
    progress("yao2022.table6", 1.0)
    claims = []
    for cid, (part, paper) in PAPER_TABLE6.items():
        claims.append(Claim(
            id=f"yao2022.table6.instructions_{cid}",
            statement=(f"Instructions per call of the {part.replace('_', ' ')} part (host "
                       "x86-64 build of the C core, -O2, float, counted by valgrind's "
                       "callgrind; benchmarks/cost/obs_cost.c) beside the paper's cycles on a "
                       "150 MHz TMS320F28335."),
            paper=paper, expected=None, reproduced=counts[part], unit="instructions",
            tolerance=10 * paper, check="max",
            basis="x86-64 instructions and C28x cycles are different units (the C28x has "
                  "single-cycle float multiply-accumulate; sin/cos/atan2 are library calls on "
                  "both); the same computational class means within a factor of 10",
            why_fail=why,
        ))
    return Outcome(claims)


EXPERIMENTS: list[Experiment] = [
    Experiment("yao2022.table1", "Regular-sampled PWM harmonics", run_table1),
    Experiment("yao2022.fig4", "Time-delay compensation errors", run_fig4),
    Experiment("yao2022.fig7", "PLL bandwidth", run_fig7),
    Experiment("yao2022.fig9-10", "Position accuracy by current injection", run_fig9_10),
    Experiment("yao2022.table5", "Speed-estimation ripple", run_table5),
    Experiment("yao2022.fig14", "Acceleration 0 -> 100 kr/min", run_fig14),
    Experiment("yao2022.fig19-21", "Torque-current step", run_fig19_21),
    Experiment("yao2022.fig22", "Speed reversal", run_fig22),
    Experiment("yao2022.fig23", "Robustness to a capacitance error", run_fig23),
    Experiment("yao2022.table6", "Execution cost", run_table6),
]

SCENARIOS: dict[str, Callable[[], Scenario]] = {
    "yao2022.steady.100k": lambda: steady(100e3),
    "yao2022.fig14": fig14_scenario,
    "yao2022.fig19": fig19_scenario,
    "yao2022.fig22": fig22_scenario,
}
