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
from typing import Callable

import control
import numpy as np

from .. import plots
from ..analysis import metrics, tf
from ..claims import Claim
from ..engine import Result
from ..model import (
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
from .common import Experiments, Outcome, ProgressFn, SeedStats, over_seeds, paper_specs, run_sim
from .yang2018_setup import (  # noqa: F401  (re-exported: the paper's scenarios and measures)
    BASE,
    FIG7_OVERSAMPLE,
    FIG8_OFF,
    FIG8_ON,
    FIG9_DOWN,
    FIG9_RATE,
    FIG9_UP,
    HANDOVER,
    MOTOR,
    NOISE_SMALL,
    NOISE_WINDOW,
    SENSORLESS_INVERTER,
    SS_WINDOW,
    STEP_T,
    T_N,
    W_N,
    _ctrl,
    _pos_err_deg,
    _rated_brake,
    _sim,
    _ss,
    dbpc_exact_closed_loop,
    dbpc_fixed_point,
    dbpc_noise_gain,
    fig1_scenario,
    fig2_scenario,
    fig6_noise_scenario,
    fig7_oversampled_scenario,
    fig7_scenario,
    fig8_scenario,
    fig9_scenario,
    fig56_scenario,
    peak_over_seeds,
    peak_pos_error,
    pos_error_lagged_deg,
    robust_dbpc_noise_gain,
    seed_fields,
)

SPECS = paper_specs(__file__)  # the claims' texts and fixed values: yang2018.claims.toml
claim = SPECS.claim
EXPERIMENTS = Experiments()  # filled by @EXPERIMENTS(id, title) on each run function


@EXPERIMENTS("yang2018.fig1", "Bode of H(z), eq. (14)")
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
        claim("yang2018.fig1.peak_gain_db_Lhat_2L", db(peak), expected=db(peak_closed),
              f_peak=f_peak),
        claim("yang2018.fig1.sim_peak_gain_db_Lhat_2L_vs_eq14", db(amp), expected=db(peak),
              f_ex=f_ex, peak_exact_db=db(peak_ex), peak_eq14_db=db(peak)),
        claim("yang2018.fig1.sim_peak_gain_db_Lhat_2L_vs_exact", db(amp),
              expected=db(peak_ex)),
    ]

    def plot(fig_dir):
        return plots.save(plots.fig1_bode(MOTOR, T, f_ex, amp), fig_dir, "yang2018_fig1")

    return Outcome(claims, {s.name: r_sim}, [("yang2018_fig1", plot)])


def fig2_measure(r: Result) -> tuple[complex, float, float]:
    """G(j w_r) of the SMDO measured in a run of fig2_scenario() as
    u_d_hat / u_d, with the mean electrical speed and the mean i_q."""
    m = _ss(r, 0.3, 0.6)
    w_r = MOTOR.n_p * r["w_M"][m]
    # u_d_hat^{k+1} (logged at t_k) is the disturbance the robust DBPC
    # assumes over [t_k+1, t_k+2): compare with the EMF at its middle.
    th = r["theta_r"][m] + 1.5 * w_r * r.scenario.T_sp
    u_d = -1j * w_r * MOTOR.psi_r * np.exp(1j * th)
    u_hat = r["u_d_hat_alpha"][m] + 1j * r["u_d_hat_beta"][m]
    return complex(np.mean(u_hat / u_d)), float(np.mean(w_r)), float(np.mean(r["i_q"][m]))


def fig2_expected(w_r: float, i_q: float, T: float = BASE.T_sp) -> tuple[float, float]:
    """What the discrete SMDO with the exact rotation measures in
    fig2_measure: (gain, phase in deg). Its filter has unity gain and zero
    phase at w_r for the disturbance its current model (35) identifies;
    that disturbance is (i) the interval average of the EMF over
    [t_k, t_k+1), whose magnitude is sinc(w_r T / 2) of the EMF's (the angle
    is the interval's middle, which fig2_measure compares with), and (ii)
    for the Euler model (35) on the exact plant, the average plus
    (R T / 2) L di/dt = (R T / 2) j w_r i: perpendicular to the EMF, it turns
    the estimate ahead by R T i_q / (2 psi_r) rad, independent of speed."""
    x = 0.5 * w_r * T
    return math.sin(x) / x, math.degrees(MOTOR.R_s * T * i_q / (2 * MOTOR.psi_r))


def fig2_claims(G: complex, w_r: float, i_q: float, G_euler: complex) -> list[Claim]:
    """The claims of Fig. 2 for a measured G(j w_r) at the operating point
    (w_r, i_q); `G_euler` is the printed forward-Euler (36) measured the same
    way (stated in the claims, and judged by the same check in the tests)."""
    gain, phase = fig2_expected(w_r, i_q)
    g_disc = tf.G_smdo_discrete(BASE.controller.w_c, w_r, BASE.T_sp, w_r)
    return [
        claim("yang2018.fig2.gain_at_wr", float(abs(G)), expected=gain,
              gain_euler=abs(G_euler), gain_euler_filter=abs(g_disc)),
        claim("yang2018.fig2.phase_at_wr_deg", float(np.degrees(np.angle(G))), expected=phase,
              phase_euler_deg=np.degrees(np.angle(G_euler)), i_q=i_q),
    ]


@EXPERIMENTS("yang2018.fig2", "Bode of G(s), eq. (33)")
def run_fig2(progress: ProgressFn) -> Outcome:
    s = fig2_scenario()
    r = _sim(s, progress)
    G, w_mean, i_q = fig2_measure(r)
    s_e = s.replace(name="yang2018.fig2.euler",
                    controller=dataclasses.replace(s.controller, smdo_euler=True))
    G_e, _, _ = fig2_measure(_sim(s_e, progress))
    claims = fig2_claims(G, w_mean, i_q, G_e)

    def plot(fig_dir):
        return plots.save(plots.fig2_bode(w_mean, abs(G), float(np.angle(G))), fig_dir,
                          "yang2018_fig2")

    return Outcome(claims, {s.name: r}, [("yang2018_fig2", plot)])


def noise_ripple(r: Result) -> float:
    """dq current ripple (A RMS) of a fig6_noise_scenario run in its window."""
    m = r.window(*NOISE_WINDOW)
    return metrics.ripple_dq(r["i_d"][m], r["i_q"][m])


def noise_ripple_ratios(L_ratio: float, mode: str = "robust", noise: float = NOISE_SMALL,
                        progress: ProgressFn | None = None,
                        ref: SeedStats | None = None) -> SeedStats:
    """Per noise seed, the ripple of fig6_noise_scenario(L_ratio, mode) over
    that of the robust DBPC with L_hat = L with the same seed (`ref`: those
    reference ripples if already run)."""
    if ref is None:
        ref = over_seeds(fig6_noise_scenario(1.0, "robust", noise), noise_ripple,
                         progress=progress)
    mm = over_seeds(fig6_noise_scenario(L_ratio, mode, noise), noise_ripple, seeds=ref.seeds,
                    progress=progress)
    return SeedStats(ref.seeds, tuple(b / a for a, b in zip(ref.values, mm.values)))


def fig6_noise_ratios(progress: ProgressFn) -> dict[float, dict]:
    """The noise-driven ripple ratios of L_hat = 2 L and 0.5 L over seeds,
    and the linear loop's prediction (robust_dbpc_noise_gain)."""
    g1 = robust_dbpc_noise_gain(MOTOR.L_s)
    ref = over_seeds(fig6_noise_scenario(1.0), noise_ripple, progress=progress)
    return {k: {"stats": noise_ripple_ratios(k, progress=progress, ref=ref),
                "expected": robust_dbpc_noise_gain(k * MOTOR.L_s) / g1}
            for k in (2.0, 0.5)}


def fig5b_noise_ratio(progress: ProgressFn) -> dict:
    """Fig. 5(b)'s ripple growth with the ADC noise as the only source:
    conventional DBPC with L_hat = 2 L over L_hat = L, per noise seed, and the
    linear loop's prediction (dbpc_noise_gain)."""
    ref = over_seeds(fig6_noise_scenario(1.0, "conventional"), noise_ripple, progress=progress)
    return {"stats": noise_ripple_ratios(2.0, "conventional", progress=progress, ref=ref),
            "expected": dbpc_noise_gain(2 * MOTOR.L_s) / dbpc_noise_gain(MOTOR.L_s),
            "euler": (dbpc_noise_gain(2 * MOTOR.L_s, plant="euler")
                      / dbpc_noise_gain(MOTOR.L_s, plant="euler"))}


@EXPERIMENTS("yang2018.fig5-6", "DBPC under parameter mismatch")
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

    # Fig. 5(a): d-axis offset from the inductance error: the exact steady
    # state of (7)-(9) on the sampled machine (with the inverter's dead time
    # and its compensation), and eq. (12)'s prediction against it
    a = st["yang2018.fig5a"]
    s5a = cases["yang2018.fig5a"]
    op = (L, MOTOR.R_s, psi, 0.5 * L, MOTOR.R_s, psi, a["w_r"], T, a["i_d_ref"], a["i_q"])
    id_exact, _, dU = dbpc_fixed_point(*op, t_dead=s5a.inverter.t_dead,
                                       t_dead_comp=s5a.controller.t_dead_comp,
                                       u_dc=s5a.inverter.u_dc)
    id_ideal, _, _ = dbpc_fixed_point(*op)
    id_euler, _, _ = dbpc_fixed_point(*op, plant="euler")
    id_eq12, _ = tf.dbpc_steady_state(*op)
    claims.append(claim("yang2018.fig5a.id_offset_A", a["i_d"] - a["i_d_ref"],
                        expected=id_exact, id_exact=id_exact, id_ideal=id_ideal, dU=abs(dU),
                        shift=id_exact - id_ideal, id_eq12=id_eq12))
    claims.append(claim("yang2018.fig5a.eq12_vs_exact", id_eq12 - a["i_d_ref"],
                        expected=id_ideal - a["i_d_ref"], id_ideal=id_ideal, id_euler=id_euler,
                        eq12_err=id_eq12 / id_ideal - 1))
    # Fig. 5(b): ripple with overestimated inductance, driven by the ADC
    # noise alone, against the loop's H2 norm
    rb = st["yang2018.fig5b"]["ripple"] / st["yang2018.fig5.exact"]["ripple"]
    nb = fig5b_noise_ratio(progress)
    claims.append(claim("yang2018.fig5b.noise_ripple_ratio", nb["stats"].median,
                        expected=nb["expected"], n_seeds=len(nb["stats"]),
                        worst=nb["stats"].worst, noise_mA=1e3 * NOISE_SMALL,
                        scenario_ratio=rb, euler=nb["euler"]))
    # Fig. 5(c), (d): q-axis error from the flux error, eq. (13)
    for tag, ratio in (("c", 0.5), ("d", 2.0)):
        c = st[f"yang2018.fig5{tag}"]
        _, iq = tf.dbpc_steady_state(L, MOTOR.R_s, psi, L, MOTOR.R_s, ratio * psi, c["w_r"], T,
                                     c["i_d"], c["i_q_ref"])
        exp = iq - c["i_q_ref"]
        claims.append(claim("yang2018.fig5{letter}.iq_error_A", c["i_q"] - c["i_q_ref"],
                            expected=exp, tolerance=round(0.1 * abs(exp) + 0.05, 3),
                            letter=tag, ratio=ratio))
    # Fig. 6: robust DBPC, inductance errors
    noise = fig6_noise_ratios(progress)
    for tag, ratio in (("a", 2.0), ("b", 0.5)):
        c = st[f"yang2018.fig6{tag}"]
        claims.append(claim("yang2018.fig6{letter}.id_offset_A", c["i_d"] - c["i_d_ref"],
                            expected=0.0, letter=tag, ratio=ratio))
        claims.append(claim("yang2018.fig6{letter}.iq_error_A", c["i_q"] - c["i_q_ref"],
                            expected=0.0, letter=tag, ratio=ratio))
        ratio_r = c["ripple"] / st["yang2018.fig6.exact"]["ripple"]
        if tag == "a":
            rel = c["ripple"] / st["yang2018.fig5b"]["ripple"]
            claims.append(claim("yang2018.fig6a.ripple_vs_fig5b", rel))
        n = noise[ratio]
        claims.append(claim("yang2018.fig6{letter}.noise_ripple_ratio", n["stats"].median,
                            expected=n["expected"], letter=tag, ratio=ratio,
                            n_seeds=len(n["stats"]), worst=n["stats"].worst,
                            noise_mA=1e3 * NOISE_SMALL, scenario_ratio=ratio_r))

    def plot5(fig_dir):
        return plots.save(plots.dq_panels(
            [res[f"yang2018.fig5{t}"] for t in "abcd"],
            [r"(a) $\hat L_s=0.5L_s$", r"(b) $\hat L_s=2L_s$", r"(c) $\hat\psi_r=0.5\psi_r$",
             r"(d) $\hat\psi_r=2\psi_r$"],
            "Fig. 5: conventional DBPC with mismatched parameters",
        ), fig_dir, "yang2018_fig5")

    def plot6(fig_dir):
        return plots.save(plots.dq_panels(
            [res["yang2018.fig6a"], res["yang2018.fig6b"]],
            [r"(a) $\hat L_s=2L_s$", r"(b) $\hat L_s=0.5L_s$"],
            "Fig. 6: robust DBPC (SMDO) with mismatched inductance",
        ), fig_dir, "yang2018_fig6")

    return Outcome(claims, res, [("yang2018_fig5", plot5), ("yang2018_fig6", plot6)])


@EXPERIMENTS("yang2018.fig7", "Sensorless steady state")
def run_fig7(progress: ProgressFn) -> Outcome:
    claims: list[Claim] = []
    res = {}
    for n, tag in ((1500.0, "a"), (75.0, "b")):
        s = fig7_scenario(n)
        r = _sim(s, progress)
        res[s.name] = r
        m = _ss(r, 0.5, 1.0)
        rms_e, _ = _pos_err_deg(r, m)
        if tag == "a":
            lag = metrics.rms(pos_error_lagged_deg(r, m, 1))
            claims.append(claim("yang2018.fig7a.pos_error_deg", rms_e, lag_deg=lag))
        else:
            claims.append(claim("yang2018.fig7b.pos_error_deg", rms_e))
        peaks = peak_over_seeds(s, r, 0.5, 1.0, progress)
        # at 1500 r/min the bound is the error budget: the peak with the
        # angle one sample late is stated beside it
        extra = {"lag_peak": float(np.max(np.abs(pos_error_lagged_deg(r, m, 1))))} \
            if tag == "a" else {}
        claims.append(claim(f"yang2018.fig7{tag}.pos_error_peak_deg", peaks.p90,
                            **seed_fields(peaks), **extra))
        if tag == "b":
            s_ov = fig7_oversampled_scenario()
            ov = over_seeds(s_ov, peak_pos_error(0.5, 1.0), progress=progress)
            claims.append(claim("yang2018.fig7b.pos_error_peak_deg_oversampled", ov.p90,
                                n_oversample=s_ov.adc.n_oversample, single=peaks.p90,
                                **seed_fields(ov)))

    def plot(fig_dir):
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


@EXPERIMENTS("yang2018.fig8", "Sensorless load step")
def run_fig8(progress: ProgressFn) -> Outcome:
    s = fig8_scenario()
    r = _sim(s, progress)
    m_on = r.window(FIG8_ON, FIG8_OFF)
    dip = float(W_N - np.min(r["w_M"][m_on])) / RPM
    exp_dip = speed_loop_load_dip(s.controller, s.motor.J, s.motor.n_p, T_N) / RPM
    peaks = peak_over_seeds(s, r, HANDOVER, s.duration, progress)
    lag_peak = float(np.max(np.abs(pos_error_lagged_deg(r, r.window(HANDOVER, s.duration), 1))))
    claims = [
        claim("yang2018.fig8.speed_dip_rpm", dip, expected=exp_dip,
              tolerance=round(0.06 * exp_dip, 2)),
        claim("yang2018.fig8.pos_error_peak_deg", peaks.p90, lag_peak=lag_peak,
              **seed_fields(peaks)),
    ]

    def plot(fig_dir):
        return plots.save(plots.sensorless_panels(
            [r], ["rated load applied and released at 1500 r/min"],
            "Fig. 8: step load at 1500 r/min", t_window=[(0.2, s.duration)],
        ), fig_dir, "yang2018_fig8")

    return Outcome(claims, {s.name: r}, [("yang2018_fig8", plot)])


def fig9_steady(r: Result) -> np.ndarray:
    """The steady-state intervals of the Fig. 9 run (after the handover,
    before the ramp up, between the ramps, after the ramp down settles)."""
    return r.window(HANDOVER, FIG9_UP) | r.window(0.8, FIG9_DOWN) | r.window(1.9, r.t[-1] + 1.0)


def fig9_speed_error_rpm(r: Result, w_hat: np.ndarray) -> np.ndarray:
    """w_M - w_hat / n_p (r/min) in the steady intervals, for an electrical
    speed estimate `w_hat` (the logged one, or a variant's)."""
    m = fig9_steady(r)
    return (r["w_M"][m] - w_hat[m] / MOTOR.n_p) / RPM


def fig9_speed_claim(r: Result, dw: np.ndarray) -> Claim:
    """The RMS speed-estimation error `dw` (r/min, in the steady intervals of
    run `r`) against the bound its own speed path allows: the estimate is the
    angle's difference through the speed loop's feedback low-pass w_lpf, so
    its error is the low-pass's lag on the true speed, w - LPF(w), plus the
    angle error's difference through the low-pass, whose gain from angle to
    speed, |j W w_lpf / (j W + w_lpf)|, never exceeds w_lpf: by the triangle
    inequality RMS(dw) <= RMS(w - LPF(w)) + w_lpf RMS(theta error), both
    measured on the same run and intervals."""
    ctrl, T, n_p = r.scenario.controller, r.scenario.T_sp, r.scenario.motor.n_p
    m = fig9_steady(r)
    pos_rms = math.degrees(metrics.rms(r.theta_error[m]))
    w = r["w_M"] * n_p
    a = 1.0 - math.exp(-ctrl.w_lpf * T)  # the drive's first-order speed filter
    lp = np.empty_like(w)
    lp[0] = w[0]
    for k in range(1, w.size):
        lp[k] = lp[k - 1] + a * (w[k] - lp[k - 1])
    lag_rms = metrics.rms((w - lp)[m]) / n_p / RPM
    angle_part = ctrl.w_lpf * math.radians(pos_rms) / n_p / RPM
    bound = lag_rms + angle_part
    k_p, _ = ctrl.pi_gains(n_p)
    return claim("yang2018.fig9.speed_error_rms_rpm", metrics.rms(dw),
                 tolerance=round(bound, 2), mean=float(np.mean(dw)), w_lpf=ctrl.w_lpf,
                 pos_rms=pos_rms, lag_rms=lag_rms, angle_part=angle_part,
                 i_q_rms=k_p * n_p * RPM * bound)


@EXPERIMENTS("yang2018.fig9", "Sensorless speed steps")
def run_fig9(progress: ProgressFn) -> Outcome:
    s = fig9_scenario()
    r = _sim(s, progress)
    peaks = peak_over_seeds(s, r, HANDOVER, s.duration, progress)
    dw = fig9_speed_error_rpm(r, r["w_hat"])
    claims = [
        claim("yang2018.fig9.pos_error_peak_deg", peaks.p90, **seed_fields(peaks)),
        fig9_speed_claim(r, dw),
    ]

    def plot(fig_dir):
        return plots.save(plots.sensorless_panels(
            [r], ["150 -> 1500 -> 150 r/min"],
            "Fig. 9: speed steps at 4500 r/min/s", t_window=[(0.0, s.duration)],
        ), fig_dir, "yang2018_fig9")

    return Outcome(claims, {s.name: r}, [("yang2018_fig9", plot)])


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
    "yang2018.fig7b.oversampled": fig7_oversampled_scenario,
    "yang2018.fig8": fig8_scenario,
    "yang2018.fig9": fig9_scenario,
}
