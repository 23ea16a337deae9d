"""yang2018: every figure of the paper's analysis and experiments as a
runnable scenario that yields claims.

Operating points follow Sec. VI; values the paper does not give are the
documented assumptions of :data:`BASE` (docs/assumptions.md). Rated load is
the rated torque P_N / (1500 r/min) = 15.28 N m, applied by a brake that
opposes rotation (the paper's magnetic powder brake).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..analysis import metrics, tf
from ..claims import Claim
from ..params import (
    RPM,
    AdcCfg,
    ControllerCfg,
    InverterCfg,
    LoadCfg,
    MotorPars,
    Profile,
    Scenario,
    yang2018_mode,
)
from ..simulate import Result
from .common import Experiment, Outcome, ProgressFn, run_sim

MOTOR = MotorPars()
T_N = MOTOR.T_N  # rated torque, N m
W_N = 1500 * RPM  # rated mechanical speed, rad/s

BASE = Scenario(
    name="yang2018.base",
    T_sp=100e-6,
    motor=MOTOR,
    controller=ControllerCfg(),
    inverter=InverterCfg(),
    adc=AdcCfg(),
)


def _rated_brake() -> Profile:
    """Rated brake torque from t = 0 (with the warm start, the run begins in
    steady state under that load, as the paper's experiments do)."""
    return Profile.const(T_N)


def _ctrl(mode: str | None = None, **kw) -> ControllerCfg:
    """BASE's controller with fields changed; `mode` names one of yang2018's
    three drives (conventional, robust, sensorless), a composition of parts."""
    if mode is not None:
        kw = {**yang2018_mode(mode), **kw}
    return dataclasses.replace(BASE.controller, **kw)


# ---------------------------------------------------------- scenarios ------

def fig1_scenario(L_ratio: float = 2.0, f_inj: float = 2500.0) -> Scenario:
    """Locked rotor, conventional DBPC with L_hat = L_ratio L, sinusoidal i_d
    reference at f_inj: measures the closed-loop gain of eq. (14)."""
    return BASE.replace(
        name=f"yang2018.fig1.L{L_ratio:g}",
        duration=1.0,
        motor=dataclasses.replace(MOTOR, J=1e4),
        controller=_ctrl(mode="conventional", L_s_hat=L_ratio * MOTOR.L_s, speed_loop=False,
                         t_dead_comp=0.0),
        inverter=dataclasses.replace(BASE.inverter, pwm="averaged", t_dead=0.0),
        adc=dataclasses.replace(BASE.adc, noise=0.0, bits=0),
        i_d_sin_amp=2e-4,
        i_d_sin_freq=f_inj,
    )


def fig2_scenario() -> Scenario:
    """Robust DBPC with exact parameters, 1500 r/min, rated load, ideal
    inverter and ADC: the disturbance is the back EMF alone, eq. (43)."""
    return BASE.replace(
        name="yang2018.fig2",
        duration=0.6,
        n_M0=1500.0,
        w_M_ref=Profile.const(W_N),
        controller=_ctrl(mode="robust", t_dead_comp=0.0),
        inverter=dataclasses.replace(BASE.inverter, t_dead=0.0),
        adc=dataclasses.replace(BASE.adc, noise=0.0, bits=0),
        load=LoadCfg(T_brake=_rated_brake()),
    )


# Sensorless runs start on the encoder while the SMDO converges (the paper's
# experiments start from a running drive); claims are measured after it.
HANDOVER = 0.2
STEP_T = 0.1  # speed command 75 -> 1500 r/min, Sec. VI-A
SS_WINDOW = (0.6, 1.0)


def fig56_scenario(name: str, mode: str, **ctrl) -> Scenario:
    """Sec. VI-A: running at 75 r/min, speed command steps to 1500 r/min,
    rated load."""
    return BASE.replace(
        name=name,
        duration=SS_WINDOW[1],
        n_M0=75.0,
        w_M_ref=Profile.steps(75 * RPM, (STEP_T, W_N)),
        controller=_ctrl(mode=mode, **ctrl),
        load=LoadCfg(T_brake=_rated_brake()),
    )


def fig7_scenario(n: float) -> Scenario:
    tag = "a" if n >= 1000 else "b"
    return BASE.replace(
        name=f"yang2018.fig7{tag}",
        duration=1.0,
        n_M0=n,
        w_M_ref=Profile.const(n * RPM),
        controller=_ctrl(mode="sensorless", t_handover=HANDOVER),
        load=LoadCfg(T_brake=_rated_brake()),
    )


FIG8_ON, FIG8_OFF = 0.4, 1.0


def fig8_scenario() -> Scenario:
    return BASE.replace(
        name="yang2018.fig8",
        duration=1.6,
        n_M0=1500.0,
        w_M_ref=Profile.const(W_N),
        controller=_ctrl(mode="sensorless", t_handover=HANDOVER),
        load=LoadCfg(T_brake=Profile.steps(0.0, (FIG8_ON, T_N), (FIG8_OFF, 0.0))),
    )


FIG9_RATE = 4500 * RPM  # rad/s^2 (4500 r/min per second)
FIG9_UP, FIG9_DOWN = 0.4, 1.4


def fig9_scenario() -> Scenario:
    ramp = (1500 - 150) * RPM / FIG9_RATE
    return BASE.replace(
        name="yang2018.fig9",
        duration=2.4,
        n_M0=150.0,
        w_M_ref=Profile.steps(150 * RPM, (FIG9_UP, W_N), (FIG9_DOWN, 150 * RPM), ramp=ramp),
        controller=_ctrl(mode="sensorless", t_handover=HANDOVER),
    )


# ------------------------------------------------------------ helpers ------

def _ss(r: Result, t0: float | None = None, t1: float | None = None) -> np.ndarray:
    a, b = SS_WINDOW
    return r.window(a if t0 is None else t0, b if t1 is None else t1)


def _pos_err_deg(r: Result, mask: np.ndarray) -> tuple[float, float]:
    e = np.degrees(r.theta_error[mask])
    return metrics.rms(e), float(np.max(np.abs(e)))


_sim = run_sim


# ---------------------------------------------------------- experiments ----

def dbpc_exact_closed_loop(L: float, R: float, L_hat: float, R_hat: float, T: float,
                           z: np.ndarray) -> np.ndarray:
    """i_dq / i_dq_ref of conventional DBPC (8)-(9) at standstill with the
    exact (zero-order-hold) plant i^{k+1} = a i^k + b u^k, a = e^{-R T / L},
    b = (1 - a) / R, keeping every term that eq. (14) drops:
    H = (L_hat / T) / [(z - a)(z + c) / b + (L_hat / T) c^2], c = 1 - R_hat T / L_hat."""
    a = math.exp(-R * T / L)
    b = (1.0 - a) / R
    c = 1.0 - R_hat * T / L_hat
    return (L_hat / T) / ((z - a) * (z + c) / b + (L_hat / T) * c**2)


def run_fig1(progress: ProgressFn) -> Outcome:
    L, R, T = MOTOR.L_s, MOTOR.R_s, BASE.T_sp
    H2 = tf.H_dbpc(L, 2 * L, R, T)
    peak, f_peak = tf.peak_gain(H2)
    # Closed form from the pole pair of eq. (14): poles r e^{+-j W0} with
    # r^2 = (-dL + R dL T / L_hat) / L; at W0 ~ pi/2 the peak is
    # L_hat / (L |e^{jW0} - p1| |e^{jW0} - p2|) ~ L_hat / (2 L (1 - r)).
    dL = L - 2 * L
    r = math.sqrt((-dL + R / (2 * L) * dL * T) / L)
    peak_closed = 2 * L / (2 * L * (1 - r))
    # Measured: inject at the exact closed loop's peak frequency into the C
    # controller and the exact plant (locked rotor); gain = |i_d| / |i_d_ref|.
    w = np.linspace(2 * np.pi * 0.8 * f_peak, 2 * np.pi * 1.2 * f_peak, 400_001)
    h_ex = np.abs(dbpc_exact_closed_loop(L, R, 2 * L, R, T, np.exp(1j * w * T)))
    k = int(np.argmax(h_ex))
    peak_ex, f_ex = float(h_ex[k]), float(w[k] / (2 * np.pi))
    s = fig1_scenario(2.0, f_ex)
    r_sim = _sim(s, progress)
    m = r_sim.window(0.6, 1.0)
    amp = abs(metrics.sine_amplitude(r_sim.t[m], r_sim["i_d"][m], f_ex)) / s.i_d_sin_amp
    db = lambda x: 20 * math.log10(x)  # noqa: E731
    claims = [
        Claim(
            id="yang2018.fig1.peak_gain_db_Lhat_2L",
            statement=(
                f"Conventional DBPC with L_hat = 2 L at 10 kHz: peak gain of H(z), eq. (14), "
                f"from the transfer function (python-control, dense grid), at {f_peak:.1f} Hz; "
                "expected from the closed form of its pole pair, L_hat / (2 L (1 - r))."
            ),
            paper=None, expected=db(peak_closed), reproduced=db(peak), unit="dB",
            tolerance=0.1,
            basis="the closed form neglects the pole angle's offset from pi/2 (0.14 deg) and "
                  "the second pole's distance, both O(1 - r) = 0.24 % in gain",
        ),
        Claim(
            id="yang2018.fig1.sim_peak_gain_db_Lhat_2L_vs_eq14",
            statement=(
                f"The same closed loop measured with the C controller and the exact plant "
                f"(locked rotor, averaged PWM, ideal ADC, i_d reference injected at {f_ex:.1f} "
                "Hz) against the peak eq. (14) predicts."
            ),
            paper=None, expected=db(peak), reproduced=db(amp), unit="dB", tolerance=1.0,
            basis="1 dB: eq. (14) drops T_sp^2 terms",
            why_fail=(
                "eq. (14) takes the Euler model (3) for the plant; its resonance damping is "
                "itself O(R T_sp / L), so the dropped second-order terms matter: with the "
                "exact plant the pole radius is 0.99282 instead of 0.99760 and the peak "
                f"{db(peak_ex):.2f} dB (next claim), not {db(peak):.2f} dB "
                "(docs/errata.md)."
            ),
        ),
        Claim(
            id="yang2018.fig1.sim_peak_gain_db_Lhat_2L_vs_exact",
            statement=(
                "The measured closed-loop peak against the exact discrete closed loop of "
                "(8)-(9) with the zero-order-hold plant (no terms dropped)."
            ),
            paper=None, expected=db(peak_ex), reproduced=db(amp), unit="dB", tolerance=0.2,
            basis="float32 controller arithmetic and the finite window; the resonance "
                  "decays with a 14 ms time constant, so 0.6 s of settling is ample; 0.2 dB",
        ),
    ]

    def plot(fig_dir):
        from .. import plots

        return plots.save(plots.fig1_bode(MOTOR, T, f_ex, amp), fig_dir, "yang2018_fig1")

    return Outcome(claims, {s.name: r_sim}, [("yang2018_fig1", plot)])


def run_fig2(progress: ProgressFn) -> Outcome:
    def measure(s: Scenario) -> tuple[complex, float, Result]:
        r = _sim(s, progress)
        m = _ss(r, 0.3, 0.6)
        w_r = MOTOR.n_p * r["w_M"][m]
        # u_d_hat^{k+1} (logged at t_k) is the disturbance the robust DBPC
        # assumes over [t_k+1, t_k+2): compare with the EMF at its middle.
        th = r["theta_r"][m] + 1.5 * w_r * s.T_sp
        u_d = -1j * w_r * MOTOR.psi_r * np.exp(1j * th)
        u_hat = r["u_d_hat_alpha"][m] + 1j * r["u_d_hat_beta"][m]
        return complex(np.mean(u_hat / u_d)), float(np.mean(w_r)), r

    s = fig2_scenario()
    G, w_mean, r = measure(s)
    s_e = s.replace(name="yang2018.fig2.euler",
                    controller=dataclasses.replace(s.controller, smdo_euler=True))
    G_e, _, _ = measure(s_e)
    g_disc = tf.G_smdo_discrete(BASE.controller.w_c, w_mean, s.T_sp, w_mean)
    claims = [
        Claim(
            id="yang2018.fig2.gain_at_wr",
            statement=(
                "SMDO: |G(j w_r)| of eq. (33) at 1500 r/min (w_c = 1500 rad/s), measured as "
                "u_d_hat / u_d in the simulation (robust DBPC, exact parameters, no dead time, "
                "exact rotation in (36)). With the forward-Euler rotation printed in (36) the "
                f"simulation gives {abs(G_e):.4f} and the Euler filter predicts "
                f"{abs(g_disc):.4f} (docs/errata.md)."
            ),
            paper=1.0,
            expected=1.0,
            reproduced=float(abs(G)),
            unit="",
            tolerance=0.02,
            basis=(
                "eq. (33) is continuous; with the exact rotation the discrete filter on the "
                "sliding surface has unity gain at w_r too, and what remains is the float32 "
                "arithmetic and the small PWM and sampling effects; the Euler form would be "
                "1.3 % high, so 2 % separates a correct filter from a wrong one"
            ),
        ),
        Claim(
            id="yang2018.fig2.phase_at_wr_deg",
            statement="SMDO: arg G(j w_r) of eq. (33) at 1500 r/min, measured as above "
                      f"(Euler rotation: {np.degrees(np.angle(G_e)):.3f} deg).",
            paper=0.0,
            expected=0.0,
            reproduced=float(np.degrees(np.angle(G))),
            unit="deg",
            tolerance=1.0,
            basis=(
                "the Euler filter's phase error is (wT)^3 / (6 (w_c T - (wT)^2/2)) = 0.02 deg; "
                "1 deg = 0.017 rad of angle error, small beside the sensorless claims"
            ),
        ),
    ]

    def plot(fig_dir):
        from .. import plots

        return plots.save(plots.fig2_bode(w_mean, abs(G), float(np.angle(G))), fig_dir,
                          "yang2018_fig2")

    return Outcome(claims, {s.name: r}, [("yang2018_fig2", plot)])


def run_fig5_fig6(progress: ProgressFn) -> Outcome:
    L, psi = MOTOR.L_s, MOTOR.psi_r
    cases = {
        "yang2018.fig5.exact": fig56_scenario("yang2018.fig5.exact", "conventional"),
        "yang2018.fig5a": fig56_scenario("yang2018.fig5a", "conventional", L_s_hat=0.5 * L),
        "yang2018.fig5b": fig56_scenario("yang2018.fig5b", "conventional", L_s_hat=2 * L),
        "yang2018.fig5c": fig56_scenario("yang2018.fig5c", "conventional", psi_r_hat=0.5 * psi),
        "yang2018.fig5d": fig56_scenario("yang2018.fig5d", "conventional", psi_r_hat=2 * psi),
        "yang2018.fig6.exact": fig56_scenario("yang2018.fig6.exact", "robust"),
        "yang2018.fig6a": fig56_scenario("yang2018.fig6a", "robust", L_s_hat=2 * L),
        "yang2018.fig6b": fig56_scenario("yang2018.fig6b", "robust", L_s_hat=0.5 * L),
    }
    res = {k: _sim(s, progress) for k, s in cases.items()}

    def stats(r: Result) -> dict[str, float]:
        m = _ss(r)
        return {
            "i_d": float(np.mean(r["i_d"][m])),
            "i_q": float(np.mean(r["i_q"][m])),
            "i_d_ref": float(np.mean(r["i_d_ref"][m])),
            "i_q_ref": float(np.mean(r["i_q_ref"][m])),
            "w_r": float(np.mean(r["w_M"][m])) * MOTOR.n_p,
            "ripple": metrics.ripple_dq(r["i_d"][m], r["i_q"][m]),
        }

    st = {k: stats(r) for k, r in res.items()}
    claims: list[Claim] = []
    T = BASE.T_sp

    # Fig. 5(a): d-axis offset from the inductance error, eq. (12)
    a = st["yang2018.fig5a"]
    ida, _ = tf.dbpc_steady_state(L, MOTOR.R_s, psi, 0.5 * L, MOTOR.R_s, psi, a["w_r"], T,
                                  a["i_d_ref"], a["i_q"])
    claims.append(Claim(
        id="yang2018.fig5a.id_offset_A",
        statement=(
            "Conventional DBPC, L_hat = 0.5 L, 1500 r/min, rated load: steady-state mean i_d "
            "(reference 0); expected from eq. (12) with the measured i_q and speed."
        ),
        paper=None, expected=ida, reproduced=a["i_d"] - a["i_d_ref"], unit="A",
        tolerance=round(0.1 * abs(ida) + 0.05, 3),
        basis=(
            "eq. (12) drops T_sp^2 terms (relative O(w T) = 6 %) and ignores dead time and "
            "PWM; 10 % of the prediction plus 0.05 A (dead-time voltage 2 % of u_dc through "
            "the deadbeat gain 2 T / L_hat)"
        ),
    ))
    # Fig. 5(b): ripple with overestimated inductance
    rb = st["yang2018.fig5b"]["ripple"] / st["yang2018.fig5.exact"]["ripple"]
    claims.append(Claim(
        id="yang2018.fig5b.ripple_ratio",
        statement=(
            "Conventional DBPC, L_hat = 2 L: RMS ripple of i_d and i_q about their means over "
            "the ripple with exact parameters, 1500 r/min, rated load. Paper: 'significant "
            "ripple components'; eq. (14) puts a lightly damped pole pair at 2.5 kHz."
        ),
        paper=None, expected=None, reproduced=rb, unit="", tolerance=2.0, check="min",
        basis=(
            "Fig. 5(b) shows the ripple visibly larger than in Fig. 5(a)-(d); a factor of at "
            "least 2 is what 'significant' needs to mean on the paper's scale"
        ),
    ))
    # Fig. 5(c), (d): q-axis error from the flux error, eq. (13)
    for tag, ratio in (("c", 0.5), ("d", 2.0)):
        k = f"yang2018.fig5{tag}"
        c = st[k]
        _, iq = tf.dbpc_steady_state(L, MOTOR.R_s, psi, L, MOTOR.R_s, ratio * psi, c["w_r"], T,
                                     c["i_d"], c["i_q_ref"])
        exp = iq - c["i_q_ref"]
        claims.append(Claim(
            id=f"{k}.iq_error_A",
            statement=(
                f"Conventional DBPC, psi_hat = {ratio:g} psi, 1500 r/min, rated load: mean i_q "
                "minus mean i_q reference; expected from eq. (13)."
            ),
            paper=None, expected=exp, reproduced=c["i_q"] - c["i_q_ref"], unit="A",
            tolerance=round(0.1 * abs(exp) + 0.05, 3),
            basis="as for fig5a: T_sp^2 terms, dead time and PWM are outside eq. (13)",
        ))
    # Fig. 6: robust DBPC, inductance errors
    for tag, ratio in (("a", 2.0), ("b", 0.5)):
        k = f"yang2018.fig6{tag}"
        c = st[k]
        claims.append(Claim(
            id=f"{k}.id_offset_A",
            statement=f"Robust DBPC (SMDO), L_hat = {ratio:g} L, 1500 r/min, rated load: mean "
                      "i_d minus its reference (paper: i_d kept at zero).",
            paper=0.0, expected=0.0, reproduced=c["i_d"] - c["i_d_ref"], unit="A",
            tolerance=0.05,
            basis="0.05 A is 0.8 % of rated current and 1/10 of the conventional offset of "
                  "Fig. 5(a); the SMDO estimate has no steady-state error at w_r (eq. (33))",
        ))
        claims.append(Claim(
            id=f"{k}.iq_error_A",
            statement=f"Robust DBPC (SMDO), L_hat = {ratio:g} L: mean i_q minus mean i_q "
                      "reference (paper: accurate tracking).",
            paper=0.0, expected=0.0, reproduced=c["i_q"] - c["i_q_ref"], unit="A",
            tolerance=0.05,
            basis="same argument as the d axis",
        ))
        ratio_r = c["ripple"] / st["yang2018.fig6.exact"]["ripple"]
        claims.append(Claim(
            id=f"{k}.ripple_ratio",
            statement=f"Robust DBPC (SMDO), L_hat = {ratio:g} L: dq current ripple over the "
                      "ripple of the robust DBPC with exact parameters (paper: no large "
                      "ripples like Fig. 5(b)).",
            paper=None, expected=1.0, reproduced=ratio_r, unit="", tolerance=1.5, check="max",
            basis="at most 1.5 times the exact-parameter ripple, i.e. well below the "
                  "conventional Fig. 5(b) case",
            why_fail=(
                "the ripple comes from ADC noise amplified by the deadbeat gain L_hat / T_sp "
                "(it vanishes with an ideal ADC); the SMDO (w_c = 1500 rad/s) cannot cancel a "
                "2.5 kHz mode, so an overestimated L_hat still doubles or triples the ripple. "
                "It is smaller than the conventional Fig. 5(b) case (next claim)."
            ),
        ))
        if tag == "a":
            rel = c["ripple"] / st["yang2018.fig5b"]["ripple"]
            claims.append(Claim(
                id="yang2018.fig6a.ripple_vs_fig5b",
                statement="Robust DBPC with L_hat = 2 L: dq current ripple over that of the "
                          "conventional DBPC with L_hat = 2 L (Fig. 5(b)), same operating point "
                          "and ADC noise (paper: 'no large ripples like that in Fig. 5(b)').",
                paper=None, expected=None, reproduced=rel, unit="", tolerance=0.7, check="max",
                basis="'no ripples like Fig. 5(b)' needs at least a clear reduction; 0.7 is "
                      "30 % less, beyond the run-to-run scatter of a noise-driven RMS over "
                      "4000 samples (about 2 %)",
            ))

    def plot5(fig_dir):
        from .. import plots

        return plots.save(plots.dq_panels(
            [res[f"yang2018.fig5{t}"] for t in "abcd"],
            [r"(a) $\hat L_s=0.5L_s$", r"(b) $\hat L_s=2L_s$", r"(c) $\hat\psi_r=0.5\psi_r$",
             r"(d) $\hat\psi_r=2\psi_r$"],
            "Fig. 5: conventional DBPC with mismatched parameters",
        ), fig_dir, "yang2018_fig5")

    def plot6(fig_dir):
        from .. import plots

        return plots.save(plots.dq_panels(
            [res["yang2018.fig6a"], res["yang2018.fig6b"]],
            [r"(a) $\hat L_s=2L_s$", r"(b) $\hat L_s=0.5L_s$"],
            "Fig. 6: robust DBPC (SMDO) with mismatched inductance",
        ), fig_dir, "yang2018_fig6")

    return Outcome(claims, res, [("yang2018_fig5", plot5), ("yang2018_fig6", plot6)])


POS_RMS_MAX_DEG = 5.0
POS_PEAK_MAX_DEG = 10.0
_POS_BASIS = (
    "the paper shows no number, only that the estimated position 'almost coincides' with "
    "the measured one on a 0-2pi scale; 5 deg RMS (1.4 % of the scale) and a 10 deg peak "
    "are the largest errors that would still look coincident there"
)


LOW_SPEED_WHY = (
    "at 75-150 r/min the back EMF is only 12.6-25 V. The SMDO passes the assumed ADC noise "
    "(0.02 A RMS, 12 bits) into u_d_hat (about 1 V RMS), and the dead-time compensation "
    "leaves volt-second errors of a few volts around each current zero crossing; the "
    "arctangent of eq. (44) (no PLL, as in the paper) turns both into angle errors with "
    "peaks above 10 deg. With an ideal ADC and no dead time the peak is below 1.1 deg "
    "(tests/test_yang2018_claims.py). The RMS error stays within its bound; the paper's "
    "noise and dead-time figures are not given."
)


def run_fig7(progress: ProgressFn) -> Outcome:
    claims: list[Claim] = []
    res = {}
    for n, tag in ((1500.0, "a"), (75.0, "b")):
        s = fig7_scenario(n)
        r = _sim(s, progress)
        res[s.name] = r
        rms_e, peak_e = _pos_err_deg(r, _ss(r, 0.5, 1.0))
        claims.append(Claim(
            id=f"yang2018.fig7{tag}.pos_error_deg",
            statement=f"Sensorless, rated load, {n:g} r/min: RMS electrical position error in "
                      "steady state.",
            paper=None, expected=None, reproduced=rms_e, unit="deg",
            tolerance=POS_RMS_MAX_DEG, check="max", basis=_POS_BASIS,
        ))
        claims.append(Claim(
            id=f"yang2018.fig7{tag}.pos_error_peak_deg",
            statement=f"Sensorless, rated load, {n:g} r/min: peak electrical position error in "
                      "steady state.",
            paper=None, expected=None, reproduced=peak_e, unit="deg",
            tolerance=POS_PEAK_MAX_DEG, check="max", basis=_POS_BASIS, why_fail=LOW_SPEED_WHY,
        ))

    def plot(fig_dir):
        from .. import plots

        return plots.save(plots.sensorless_panels(
            list(res.values()),
            ["(a) 1500 r/min, rated load", "(b) 75 r/min, rated load"],
            "Fig. 7: sensorless steady state", t_window=[(0.9, 1.0), (0.6, 1.0)],
        ), fig_dir, "yang2018_fig7")

    return Outcome(claims, res, [("yang2018_fig7", plot)])


def speed_loop_load_dip(ctrl: ControllerCfg, J: float, n_p: int, dT: float) -> float:
    """Peak speed dip (rad/s, mechanical) after a load step dT for the speed
    loop b (k_p + k_i / s) / s with b = 1.5 n_p^2 psi / J and the speed
    feedback through the first-order LPF w_lpf of the sensorless estimate
    (python-control step response; the current loop is taken as ideal)."""
    import control

    k_p, k_i = ctrl.pi_gains(n_p)
    b = 1.5 * n_p**2 * ctrl.psi_r_pi / J
    s = control.tf("s")
    plant = b / s  # electrical speed per A
    pi = k_p + k_i / s
    lpf = ctrl.w_lpf / (s + ctrl.w_lpf)
    # load torque dT enters as -dT n_p / J (electrical speed)
    d2w = control.feedback(1 / s, pi * lpf * b)  # disturbance (rad/s^2) -> speed
    t = np.linspace(0, 0.5, 50_001)
    _, y = control.step_response(d2w * (dT * n_p / J), t)
    return float(np.max(y)) / n_p


def run_fig8(progress: ProgressFn) -> Outcome:
    s = fig8_scenario()
    r = _sim(s, progress)
    m_on = r.window(FIG8_ON, FIG8_OFF)
    dip = float(W_N - np.min(r["w_M"][m_on])) / RPM
    exp_dip = speed_loop_load_dip(s.controller, s.motor.J, s.motor.n_p, T_N) / RPM
    _, peak = _pos_err_deg(r, r.window(HANDOVER, s.duration))
    claims = [
        Claim(
            id="yang2018.fig8.speed_dip_rpm",
            statement="Sensorless at 1500 r/min: speed dip after the rated load is applied; "
                      "expected from the linear speed loop (PI + speed-estimate low-pass, "
                      "ideal current control) with the assumed inertia and gains.",
            paper=None, expected=exp_dip, reproduced=dip, unit="r/min",
            tolerance=round(0.2 * exp_dip, 2), check="abs",
            basis="the linear model ignores the 2-sample current-loop delay and the SMDO "
                  "dynamics (w_c = 1500 rad/s, 25 times the speed bandwidth); 20 %",
        ),
        Claim(
            id="yang2018.fig8.pos_error_peak_deg",
            statement="Sensorless at 1500 r/min: peak electrical position error through the "
                      "rated load step and release (paper: 'small').",
            paper=None, expected=None, reproduced=peak, unit="deg",
            tolerance=POS_PEAK_MAX_DEG, check="max", basis=_POS_BASIS,
        ),
    ]

    def plot(fig_dir):
        from .. import plots

        return plots.save(plots.sensorless_panels(
            [r], ["rated load applied and released at 1500 r/min"],
            "Fig. 8: step load at 1500 r/min", t_window=[(0.2, s.duration)],
        ), fig_dir, "yang2018_fig8")

    return Outcome(claims, {s.name: r}, [("yang2018_fig8", plot)])


def run_fig9(progress: ProgressFn) -> Outcome:
    s = fig9_scenario()
    r = _sim(s, progress)
    _, peak = _pos_err_deg(r, r.window(HANDOVER, s.duration))
    steady = r.window(HANDOVER, FIG9_UP) | r.window(0.8, FIG9_DOWN) | r.window(1.9, s.duration)
    dw = (r["w_M"][steady] - r["w_hat"][steady] / MOTOR.n_p) / RPM
    claims = [
        Claim(
            id="yang2018.fig9.pos_error_peak_deg",
            statement="Sensorless, 150 -> 1500 -> 150 r/min at 4500 r/min/s: peak electrical "
                      "position error (paper: 'no excessive position error').",
            paper=None, expected=None, reproduced=peak, unit="deg",
            tolerance=POS_PEAK_MAX_DEG, check="max", basis=_POS_BASIS, why_fail=LOW_SPEED_WHY,
        ),
        Claim(
            id="yang2018.fig9.speed_error_mean_rpm",
            statement="Sensorless, same run: mean speed-estimation error w_r - w_r_hat in the "
                      "steady-state intervals (paper: 'the average estimation error of rotor "
                      "speed is zero').",
            paper=0.0, expected=0.0, reproduced=float(np.mean(dw)), unit="r/min",
            tolerance=0.5,
            basis="the speed estimate is the difference of a bounded angle estimate, so its "
                  "mean over a window of length T_w is off by at most 2 peak error / T_w: "
                  "with 10 deg electrical over 0.2 s that is 0.1 r/min; 0.5 r/min leaves room "
                  "for the low-pass transient",
        ),
    ]

    def plot(fig_dir):
        from .. import plots

        return plots.save(plots.sensorless_panels(
            [r], ["150 -> 1500 -> 150 r/min"],
            "Fig. 9: speed steps at 4500 r/min/s", t_window=[(0.0, s.duration)],
        ), fig_dir, "yang2018_fig9")

    return Outcome(claims, {s.name: r}, [("yang2018_fig9", plot)])


EXPERIMENTS: list[Experiment] = [
    Experiment("yang2018.fig1", "Bode of H(z), eq. (14)", run_fig1),
    Experiment("yang2018.fig2", "Bode of G(s), eq. (33)", run_fig2),
    Experiment("yang2018.fig5-6", "DBPC under parameter mismatch", run_fig5_fig6),
    Experiment("yang2018.fig7", "Sensorless steady state", run_fig7),
    Experiment("yang2018.fig8", "Sensorless load step", run_fig8),
    Experiment("yang2018.fig9", "Sensorless speed steps", run_fig9),
]

SCENARIOS: dict[str, Callable[[], Scenario]] = {
    "yang2018.fig1": fig1_scenario,
    "yang2018.fig2": fig2_scenario,
    "yang2018.fig5a": lambda: fig56_scenario("yang2018.fig5a", "conventional",
                                             L_s_hat=0.5 * MOTOR.L_s),
    "yang2018.fig5b": lambda: fig56_scenario("yang2018.fig5b", "conventional",
                                             L_s_hat=2 * MOTOR.L_s),
    "yang2018.fig5c": lambda: fig56_scenario("yang2018.fig5c", "conventional",
                                             psi_r_hat=0.5 * MOTOR.psi_r),
    "yang2018.fig5d": lambda: fig56_scenario("yang2018.fig5d", "conventional",
                                             psi_r_hat=2 * MOTOR.psi_r),
    "yang2018.fig6a": lambda: fig56_scenario("yang2018.fig6a", "robust", L_s_hat=2 * MOTOR.L_s),
    "yang2018.fig6b": lambda: fig56_scenario("yang2018.fig6b", "robust",
                                             L_s_hat=0.5 * MOTOR.L_s),
    "yang2018.fig7a": lambda: fig7_scenario(1500.0),
    "yang2018.fig7b": lambda: fig7_scenario(75.0),
    "yang2018.fig8": fig8_scenario,
    "yang2018.fig9": fig9_scenario,
}
