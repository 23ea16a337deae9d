"""yao2022: the experiments of the LCL-filtered high-speed SPMSM paper as
runnable scenarios that yield claims.

Plant: Table II; fan load fitted to Table IV; the values the paper does not
give (inertia, ADC error, noise, controller gains, start-up) are the
documented assumptions of :data:`BASE` and docs/assumptions.md. The
ADC scaling error and the PWM harmonics arise from the models (per-phase ADC
gains, regular-sampled carrier PWM), not from injected sinusoids.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import subprocess
from typing import Callable

import numpy as np

from .. import firmware, plots
from ..analysis import metrics
from ..analysis import pwm as pwm_an
from ..design import yao2022 as dz
from ..engine import Result, lcl_observer_tables, simulate
from ..model import (
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
from .common import (
    Experiments,
    Outcome,
    ProgressFn,
    SeedStats,
    over_seeds,
    over_seeds_multi,
    paper_specs,
    run_sim,
)
from .yao2022_metrics import (  # noqa: F401  (re-exported: the experiments' measures)
    GOOD_ANGLE,
    LOST,
    REVERSAL_BAND,
    SETTLE,
    STABLE_ANGLE,
    STABLE_SPEED,
    WINDOW,
    _observer_dc_error,
    _stable,
    capacitance_bias,
    compensation_errors,
    crossing,
    electrical_period_samples,
    end_speed_rpm,
    fig19_peak,
    fig21_peak,
    fig22_metrics,
    handover_time,
    harmonic_ripple,
    injection_reading,
    line_amplitudes,
    lumped_disturbance,
    peak_after_handover,
    periodic_part,
    pll_bandwidth_measured,
    pll_speed_gain,
    ripple_needs,
    ripple_parts,
    speed_ripple,
)
from .yao2022_setup import (  # noqa: F401  (re-exported: the paper's scenarios)
    ADC,
    BASE,
    CONTROLLER,
    FIG10_T_DEAD,
    FIG14_RATE,
    FIG14_RATES,
    FIG23_RATIOS,
    IDEAL_ADC,
    INJ_RESOLUTION,
    INJ_T,
    INJ_W,
    LAWS,
    MOTOR,
    PCT,
    SPEEDS,
    TABLE6_COSTS,
    TAG,
    fig10_scenario,
    fig14_scenario,
    fig19_scenario,
    fig22_protected_scenario,
    fig22_scenario,
    fig23_scenario,
    seed_fields,
    steady,
)

SPECS = paper_specs(__file__)  # the claims' texts and fixed values: yao2022.claims.toml
claim = SPECS.claim
EXPERIMENTS = Experiments()  # filled by @EXPERIMENTS(id, title) on each run function


_sim = run_sim


# ----------------------------------------------------------- Table I -------

@EXPERIMENTS("yao2022.table1", "Regular-sampled PWM harmonics")
def run_table1(progress: ProgressFn) -> Outcome:
    V_Q, M, N = 60.0, 0.9, 12  # Table I: V_Q = 60 V, M = 0.9, f_s / f_e = 12
    rep = pwm_an.leg_harmonics_from_edges(V_Q, M, N, 5, T=1 / 20e3)
    exp = pwm_an.leg_harmonics_bessel(V_Q, M, N, 5)
    claims = [claim("yao2022.table1.h{h}_V", float(r), h=h, bessel=e)
              for h, (r, e) in enumerate(zip(rep, exp), start=1)]
    progress("yao2022.table1", 1.0)
    return Outcome(claims)


# -------------------------------------------------------------- Fig. 4 ------


@EXPERIMENTS("yao2022.fig4", "Time-delay compensation errors")
def run_fig4(progress: ProgressFn) -> Outcome:
    s = steady(100e3, name="yao2022.fig4")
    r = _sim(s, progress)
    m = r.window(SETTLE, s.duration)[:-1]
    d = lumped_disturbance(r)[m]
    d = d - d.mean()  # the EMF part is constant in steady state
    e17 = d[2:] - d[1:-1]  # eq. (31)
    e18 = d[2:] - 2 * d[1:-1] + d[:-2]  # eq. (32)
    N = electrical_period_samples(100e3, s)
    p = periodic_part(d, N)
    ratio, e17_over_d = compensation_errors(p)
    raw = float(np.sqrt(np.mean(np.abs(e18) ** 2) / np.mean(np.abs(e17) ** 2)))
    lines = line_amplitudes(p)
    W2 = 2 * 2 * np.pi * 100e3 / 60 * s.T_sp
    claims = [claim("yao2022.fig4.comp_error_ratio_18_over_17", ratio,
                    gain_2fe=2 * math.sin(W2 / 2), gain_3fe=2 * math.sin(1.5 * W2 / 2),
                    periods=d.size // N, n_per=N, a1=lines[1], a2=lines[2], a3=lines[3],
                    a6=lines[6], e17_over_d=e17_over_d, raw=raw)]

    def plot(fig_dir):
        n = min(d.size, int(0.005 / s.T_sp))
        return plots.save(plots.disturbance_panels(
            r.t[:-1][m][:n], d[:n], e17[:n], e18[:n], s.T_sp,
            "Fig. 4: lumped disturbance and time-delay compensation errors, 100 kr/min"),
            fig_dir, "yao2022_fig4")

    return Outcome(claims, {s.name: r}, [("yao2022_fig4", plot)])


# -------------------------------------------------------------- Fig. 7 ------


@EXPERIMENTS("yao2022.fig7", "PLL bandwidth")
def run_fig7(progress: ProgressFn) -> Outcome:
    pll = dz.PllPars()
    exp = dz.pll_bandwidth_hz(pll)
    rep = pll_bandwidth_measured(pll)
    progress("yao2022.fig7", 1.0)

    def plot(fig_dir):
        f = np.logspace(0, np.log10(0.5 / pll.T), 800)
        responses = [
            (f"k = ({kt}, {kw}, {ka})",
             dz.pll_open_loop(dataclasses.replace(pll, k_theta=kt, k_omega=kw, k_a=ka))(
                 np.exp(2j * np.pi * f * pll.T)))
            for kt, kw, ka in ((0.1, 10, 10), (0.2, 10, 10), (0.1, 50, 10), (0.1, 10, 100))]
        return plots.save(plots.pll_bode(
            f, responses, f"Fig. 7: G_PLL of eq. (49); closed loop -3 dB at {rep:.1f} Hz"),
            fig_dir, "yao2022_fig7")

    return Outcome([claim("yao2022.fig7.pll_bandwidth_hz", rep, expected=exp)],
                   figures=[("yao2022_fig7", plot)])


# ------------------------------------------------------ Figs. 9 and 10 ------


@EXPERIMENTS("yao2022.fig9-10", "Position accuracy by current injection")
def run_fig9_10(progress: ProgressFn) -> Outcome:
    claims, res, reading, dead = [], {}, {}, {}
    for n in SPEEDS:
        s = fig10_scenario(n)
        r = _sim(s, progress)
        res[s.name] = r
        one = injection_reading(r, INJ_T, INJ_W)
        inj, true_during, true_before = one["inj"], one["during"], one["before"]
        # standard error of each window mean by batch means (10 batches): the
        # delta current carries the speed loop's noise-driven wander
        def sem(x: np.ndarray) -> float:
            b = np.array_split(x, 10)
            return float(np.std([np.mean(v) for v in b], ddof=1) / math.sqrt(len(b)))

        before, after = r.window(INJ_T - INJ_W, INJ_T), r.window(INJ_T + 0.05, s.duration)
        i_g2 = np.mean(r["i_g"][after])
        sigma = math.hypot(sem(r["i_dl"][before]), sem(r["i_dl"][after])) / abs(i_g2)
        # eq. (59) holds for the error theta_hat - theta (eq. (47) uses the
        # opposite sign, theta - theta_hat, as r.theta_error does); the method
        # reads the error while the 5 A flow, through the i_2 sensor, whose
        # per-phase gains rotate the measured vector by scaling_rotation().
        rot = metrics.scaling_rotation(s.adc.gain)
        claims.append(claim("yao2022.fig10.injection_vs_true_rad_{speed}", inj,
                            expected=true_during - rot, tolerance=round(0.002 + 3 * sigma, 4),
                            speed=TAG[n], krpm=n / 1e3, window=INJ_W, true_during=true_during,
                            true_before=true_before, rot_mrad=rot * 1e3, sigma=sigma))
        claims.append(claim("yao2022.fig9.true_pos_error_rad_{speed}", abs(true_before),
                            speed=TAG[n], krpm=n / 1e3))
        # the reading over the ADC noise seeds (the paper's is one draw)
        reading[n] = over_seeds_multi(
            s, {k: (lambda res_, k=k: injection_reading(res_, INJ_T, INJ_W)[k])
                for k in ("inj", "during")}, progress=progress, runs={s.adc.seed: r})
        # the same drive with FIG10_T_DEAD of uncompensated dead time
        r_dt = _sim(fig10_scenario(n, FIG10_T_DEAD), progress)
        dead[n] = injection_reading(r_dt, INJ_T, INJ_W)
    # against the paper's readings (magnitudes): its current readings'
    # resolution and the scatter of one reading over the seeds; the rotation
    # an unknown sensor-gain mismatch gives the paper's reading is stated
    # apart (not in the tolerance)
    rot_1pc = abs(metrics.scaling_rotation((1.01, 0.99, 1.0)))
    sigma = {n: float(np.std(reading[n]["inj"].values, ddof=1)) for n in SPEEDS}
    tol = {n: round(INJ_RESOLUTION + 3 * sigma[n], 4) for n in SPEEDS}
    dt_fit = "; ".join(
        f"{n / 1e3:g} kr/min {abs(abs(dead[n]['inj']) - paper_fig10(n)) * 1e3:.1f} mrad off, "
        + ("within" if abs(abs(dead[n]["inj"]) - paper_fig10(n)) <= tol[n] else "outside")
        + f" that claim's {tol[n] * 1e3:.1f} mrad" for n in SPEEDS)
    for n in SPEEDS:
        inj_st, during = reading[n]["inj"], reading[n]["during"]
        mean_inj = float(np.mean(inj_st.values))
        paper = paper_fig10(n)
        claims.append(claim(
            "yao2022.fig10.pos_error_vs_paper_rad_{speed}", abs(mean_inj),
            tolerance=tol[n], speed=TAG[n], krpm=n / 1e3, dt_fit=dt_fit,
            inj=mean_inj, true_during=float(np.mean(during.values)), n_seeds=len(inj_st),
            sigma=sigma[n], gap_mrad=(abs(mean_inj) - paper) * 1e3, rot_mrad=rot_1pc * 1e3,
            rot_pct=abs(abs(mean_inj) - paper) / rot_1pc,
            td_ns=FIG10_T_DEAD * 1e9,
            **{f"dt_{TAG[m]}": abs(dead[m]["inj"]) for m in SPEEDS},
            **{f"dt_before_{TAG[m]}": dead[m]["before"] for m in SPEEDS},
            **{f"dt_during_{TAG[m]}": dead[m]["during"] for m in SPEEDS}))

    def plot(fig_dir):
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


@EXPERIMENTS("yao2022.table5", "Speed-estimation ripple")
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
    # the 2 f_e and 3 f_e lines of the estimated speed, by law label and speed
    lines = {f"lines_{LAWS[law][0]}_{TAG[n]}": harm[(law, n)] for law, n in harm}
    for law, (label, equations) in LAWS.items():
        for n in SPEEDS:
            cid = f"yao2022.table5.ripple_rpm_{label}_{TAG[n]}"
            paper = SPECS["yao2022.table5.ripple_rpm_{law}_{speed}"].paper[cid]
            claims.append(claim(
                "yao2022.table5.ripple_rpm_{law}_{speed}", rip[(law, n)], law=label,
                speed=TAG[n], krpm=n / 1e3, equations=equations,
                lines_baseline_100k=lines["lines_baseline_100k"],
                lines_proposed_100k=lines["lines_proposed_100k"],
                **ripple_needs(n, paper, BASE.motor.n_p)))
    red = rip[("proposed", 100e3)] / rip[("tde17", 100e3)]
    lines_ratio = harm[("proposed", 100e3)] / harm[("tde17", 100e3)]
    # what the 100 kr/min ripple is made of: the true speed's own wander and
    # the estimation error n_hat - n; and the same runs with the ADC's gain
    # errors alone (no noise, no quantisation)
    parts = {law: ripple_parts(by_key[(law, 100e3)], spectra=True) for law in LAWS}
    quiet = {}
    for law in LAWS:
        s_q = steady(100e3, law, name=f"yao2022.steady.{law}.100k.gains_only").replace(
            adc=dataclasses.replace(ADC, noise=0.0, bits=0))
        quiet[law] = ripple_parts(_sim(s_q, progress))
    claims.append(claim(
        "yao2022.table5.ripple_reduction_100k", red, lines_ratio=lines_ratio,
        **{f"{k}_{LAWS[law][0]}": v for law in LAWS for k, v in parts[law].items()},
        **{f"quiet_{k}_{LAWS[law][0]}": v for law in LAWS for k, v in quiet[law].items()},
        ratio_quiet=quiet["proposed"]["ripple"] / quiet["tde17"]["ripple"],
        lines_baseline_100k=lines["lines_baseline_100k"],
        lines_proposed_100k=lines["lines_proposed_100k"]))
    claims.append(claim("yao2022.table5.harmonic_ripple_reduction_100k", lines_ratio, **lines))
    chat = {k: float(np.sqrt(np.mean(np.abs(r["s_g"] + 1j * r["s_dl"])[
        r.window(SETTLE, r.scenario.duration)] ** 2))) for k, r in by_key.items()}
    claims.append(claim(
        "yao2022.fig12_13.chattering_ratio_100k",
        chat[("proposed", 100e3)] / chat[("tde17", 100e3)],
        **{f"s_{LAWS[law][0]}_{TAG[n]}": chat[(law, n)] for law, n in chat
           if n in (30e3, 100e3)}))

    def plot17(fig_dir):
        rs = [by_key[("proposed", 60e3)], by_key[("proposed", 100e3)]]
        return [
            plots.save(plots.waveform_spectrum(rs, ["60 kr/min", "100 kr/min"], "i_alpha",
                                               "phase A motor current (A)",
                                               "Fig. 17: motor current (LCL-filtered)"),
                       fig_dir, "yao2022_fig17"),
            plots.save(plots.waveform_spectrum(rs[1:], ["100 kr/min"], "uc_alpha",
                                               "phase A capacitor voltage (V)",
                                               "Fig. 18: capacitor voltage and its spectrum"),
                       fig_dir, "yao2022_fig18"),
        ]

    def plot(fig_dir):
        return plots.save(plots.ripple_panels(by_key, SPEEDS,
                                              "Figs. 12-13, Table V: speed-estimation ripple "
                                              "and chattering, baseline vs proposed"),
                          fig_dir, "yao2022_fig12_13")

    return Outcome(claims, res, [("yao2022_fig12_13", plot), ("yao2022_fig17_18", plot17)])


# -------------------------------------------------------------- Fig. 14 -----


def fig14_rate_curve(progress: ProgressFn | None = None,
                     runs: dict[float, Result] | None = None) -> dict[float, tuple[float, float]]:
    """With ideal sensors, for each rate of FIG14_RATES: (peak position error
    from 0.1 s after the handover, rad; mean speed over the last 0.1 s,
    r/min). `runs`: results already simulated, by rate."""
    out = {}
    for rate in FIG14_RATES:
        r = (runs or {}).get(rate)
        if r is None:
            r = simulate(fig14_scenario(ideal=True, rate=rate))
        out[rate] = (peak_after_handover(r), end_speed_rpm(r))
        if progress is not None:
            progress("yao2022.fig14 rate curve", (FIG14_RATES.index(rate) + 1) / len(FIG14_RATES))
    return out


def crossing_rate(curve: dict[float, tuple[float, float]], bound: float) -> float:
    """The ramp rate at which the curve's peak first exceeds `bound`, linear
    between the grid points (inf if it never does)."""
    rates = sorted(curve)
    for lo, hi in itertools.pairwise(rates):
        p_lo, p_hi = curve[lo][0], curve[hi][0]
        if p_lo <= bound < p_hi:
            return lo + (hi - lo) * (bound - p_lo) / (p_hi - p_lo)
    return float("inf") if curve[rates[0]][0] <= bound else rates[0]


@EXPERIMENTS("yao2022.fig14", "Acceleration 0 -> 100 kr/min")
def run_fig14(progress: ProgressFn) -> Outcome:
    s_id = fig14_scenario(ideal=True)
    r_id = _sim(s_id, progress)
    curve = fig14_rate_curve(progress, runs={FIG14_RATE: r_id})
    bound = SPECS["yao2022.fig14.pos_error_peak_rad"].tolerance
    rate_fail = crossing_rate(curve, bound)
    end_min = SPECS["yao2022.fig14.end_speed_rpm"].tolerance
    short = [rate for rate in sorted(curve) if curve[rate][1] < end_min]
    s = fig14_scenario()
    r = _sim(s, progress)
    st = over_seeds_multi(s, {"peak": peak_after_handover, "end": end_speed_rpm,
                              "late": lambda res: peak_after_handover(res, 25e3)},
                          progress=progress, runs={s.adc.seed: r},
                          higher_is_worse={"peak": True, "end": False})
    peak, end = st["peak"], st["end"]
    claims = [
        claim("yao2022.fig14.pos_error_peak_rad", peak_after_handover(r_id),
              t_handover=handover_time(r_id), rate_krpm_s=FIG14_RATE / 1e3,
              curve=", ".join(f"{rate / 1e3:g}: {p:.4f}" for rate, (p, _) in sorted(curve.items())),
              rate_fail=rate_fail / 1e3,
              rate_short=short[0] / 1e3 if short else float("inf"),
              allows=": every rate of the grid at which it reaches 100 kr/min passes"
              if all(curve[k][0] <= bound for k in curve if curve[k][1] >= end_min) else ""),
        claim("yao2022.fig14.pos_error_peak_rad_adc", peak.percentile(PCT),
              rate_krpm_s=FIG14_RATE / 1e3, late=st["late"].median, **seed_fields(peak)),
        claim("yao2022.fig14.end_speed_rpm", end.percentile(PCT),
              rate_krpm_s=FIG14_RATE / 1e3, t_end=s.duration, end_ideal=end_speed_rpm(r_id),
              **seed_fields(end)),
    ]

    def plot(fig_dir):
        return plots.save(plots.time_panels(
            [r_id, r], ["ideal current sensors (as the paper's simulation)",
                        "+-1 % ADC gains, 0.02 A noise, 12 bit"],
            f"Figs. 14-16: forced-angle start, handover and sensorless acceleration at "
            f"{FIG14_RATE / 1e3:g} kr/min/s",
            [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true"),
                                ("n_hat_rpm", "estimated")]),
             ("position error (rad)", [("theta_error", "true")]),
             ("i_2 delta (A)", [("i_dl", "measured"), ("i_q_ref", "reference")]),
             ("phase", [("phase", "0 open loop, 1 sensorless")])]),
            fig_dir, "yao2022_fig14_16")

    def plot_rate(fig_dir):
        from matplotlib.figure import Figure

        with plots.style():
            fig = Figure(figsize=(5.5, 3.2))
            ax = fig.subplots()
            rates = np.array(sorted(curve)) / 1e3
            peaks = np.array([curve[k][0] for k in sorted(curve)])
            reach = np.array([curve[k][1] >= end_min for k in sorted(curve)])
            ax.plot(rates, peaks, "k-", lw=0.8)
            ax.plot(rates[reach], peaks[reach], "ko", ms=4, label="reaches 100 kr/min")
            ax.plot(rates[~reach], peaks[~reach], "o", mfc="none", mec="C3", ms=5,
                    label=f"stops below {end_min / 1e3:g} kr/min (voltage limit)")
            ax.axhline(bound, color="C0", ls=":", label=f"paper (Fig. 14): {bound:g} rad")
            ax.axvline(FIG14_RATE / 1e3, color="0.5", ls="--",
                       label=f"assumed ramp {FIG14_RATE / 1e3:g} kr/min/s")
            if math.isfinite(rate_fail):
                ax.plot([rate_fail / 1e3], [bound], "x", color="C3", ms=7,
                        label=f"exceeds the bound from {rate_fail / 1e3:.1f} kr/min/s")
            ax.set_xlabel("ramp rate after the handover (kr/min per s)")
            ax.set_ylabel("peak position error (rad)")
            ax.set_title("Fig. 14: peak error against the assumed ramp rate (ideal sensors)")
            ax.legend(fontsize=6, loc="upper left")
        return plots.save(fig, fig_dir, "yao2022_fig14_rate")

    return Outcome(claims, {s_id.name: r_id, s.name: r},
                   [("yao2022_fig14_16", plot), ("yao2022_fig14_rate", plot_rate)])


# ------------------------------------------------------ Figs. 19-21 ---------


@EXPERIMENTS("yao2022.fig19-21", "Torque-current step")
def run_fig19_21(progress: ProgressFn) -> Outcome:
    s = fig19_scenario()
    r = _sim(s, progress)
    st = over_seeds_multi(s, {"pos": fig19_peak, "speed": fig21_peak}, progress=progress,
                          runs={s.adc.seed: r})
    claims = [claim("yao2022.fig19.pos_error_peak_rad", st["pos"].percentile(PCT),
                    **seed_fields(st["pos"])),
              claim("yao2022.fig21.speed_error_peak_rpm", st["speed"].percentile(PCT),
                    **seed_fields(st["speed"]))]

    def plot(fig_dir):
        return plots.save(plots.time_panels(
            [r], ["i_delta step 10 -> 15 A at 0.05 s"],
            "Figs. 19-21: torque-current step with the fan load",
            [("i_2 delta (A)", [("i_dl", "measured"), ("i_q_ref", "reference")]),
             ("position error (rad)", [("theta_error", "true")]),
             ("speed (r/min)", [("n_rpm", "true"), ("n_hat_rpm", "estimated")])]),
            fig_dir, "yao2022_fig19_21")

    return Outcome(claims, {s.name: r}, [("yao2022_fig19_21", plot)])


# -------------------------------------------------------------- Fig. 22 -----


@EXPERIMENTS("yao2022.fig22", "Speed reversal")
def run_fig22(progress: ProgressFn) -> Outcome:
    s = fig22_scenario()
    r = _sim(s, progress)
    keys = ("outside", "band", "band_lost_ms", "band_ms", "done")
    st = over_seeds_multi(s, {k: (lambda res, k=k: fig22_metrics(res)[k]) for k in keys},
                          progress=progress, runs={s.adc.seed: r},
                          higher_is_worse={"done": False})
    n_done = st["done"].count(lambda v: v > 0.5)
    lost = st["band_lost_ms"]
    # the same reversal with smodrive's loss-of-lock protection on
    protected = over_seeds(fig22_protected_scenario(),
                           lambda res: float(res.faults.t_first is not None), progress=progress)
    n_stop_protected = protected.count(lambda v: v > 0.5)
    outside = st["outside"]
    # the same reversal with the ADC's gain errors alone (no noise, no
    # quantisation): the reason the claim states
    quiet = fig22_metrics(_sim(s.replace(name="yao2022.fig22.gains_only", adc=dataclasses.replace(
        s.adc, noise=0.0, bits=0)), progress))["outside"]
    claims = [
        claim("yao2022.fig22.reversal_pos_error_peak_rad",
              outside.count(lambda v: v <= GOOD_ANGLE) / len(outside),
              band_krpm=REVERSAL_BAND / 1e3, n_done=n_done, n_stop_protected=n_stop_protected,
              t_lock_ms=BASE.controller.t_lock * 1e3, bound=GOOD_ANGLE,
              n_within=outside.count(lambda v: v <= GOOD_ANGLE), n_seeds=len(outside),
              median=outside.median, p90=outside.percentile(PCT), worst=outside.worst,
              worst_seed=outside.worst_seed, quiet=quiet),
        claim("yao2022.fig22.crossing_pos_error_peak_rad", st["band"].percentile(PCT),
              band_krpm=REVERSAL_BAND / 1e3, n_seeds_stop=len(lost) - n_done, lost=LOST,
              lost_median=lost.median, lost_worst=lost.worst,
              band_median=st["band_ms"].median, **seed_fields(st["band"])),
    ]

    def plot(fig_dir):
        return plots.save(plots.time_panels(
            [r], ["+30 -> -30 kr/min"], "Fig. 22: speed reversal",
            [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true"),
                                ("n_hat_rpm", "estimated")]),
             ("position error (rad)", [("theta_error", "true")])]),
            fig_dir, "yao2022_fig22")

    return Outcome(claims, {s.name: r}, [("yao2022_fig22", plot)])


# -------------------------------------------------------------- Fig. 23 -----


def mean_angle_error(r: Result) -> float:
    """Mean theta - theta_hat over the second half of the run, rad."""
    m = r.window(r.scenario.duration / 2, r.scenario.duration)
    return float(np.mean(r.theta_error[m]))


@EXPERIMENTS("yao2022.fig23", "Robustness to a capacitance error")
def run_fig23(progress: ProgressFn) -> Outcome:
    res, verdict = {}, {}
    for obs in ("linear", "smo"):
        s = fig23_scenario(obs)
        r = _sim(s, progress)
        res[s.name] = r
        verdict[obs] = _stable(r)
    lin, smo = verdict["linear"], verdict["smo"]
    s_smo = fig23_scenario("smo")
    r_smo = res[s_smo.name]
    # the bias over the noise seeds; the same drive with the exact
    # capacitance (what the DC prediction leaves out); the prediction of
    # eq. (52)-(58) (the observer's DC fixed point) at 2 C and around it
    bias = over_seeds(s_smo, mean_angle_error, progress=progress,
                      runs={s_smo.adc.seed: r_smo})
    bias_exact = mean_angle_error(_sim(s_smo.with_controller(C1_hat_ratio=1.0).replace(
        name="yao2022.fig23.smo.exact_C"), progress))
    predicted = capacitance_bias(s_smo)
    sigma = float(np.std(bias.values, ddof=1))
    curve = []
    for ratio in FIG23_RATIOS:
        s_k = s_smo.with_controller(C1_hat_ratio=ratio)
        _, e_hat, e = _observer_dc_error(s_k, 0.0)  # in the rotor's own frame
        de = e_hat - e
        curve.append(f"{ratio:g} C: {capacitance_bias(s_k):.3f} rad, {math.hypot(*de):.2f} V "
                     f"at {math.degrees(math.atan2(de[1], de[0])):.0f} deg")
    _, e_hat, e = _observer_dc_error(s_smo, 0.0)

    def plot(fig_dir):
        return plots.save(plots.time_panels(
            list(res.values()),
            ["linear observer (65), C_hat = 2 C", "sliding-mode observer, C_hat = 2 C"],
            "Fig. 23: robustness to a capacitance error (sensorless, 60 kr/min)",
            [("position error (rad)", [("theta_error", "true")]),
             ("speed (r/min)", [("n_rpm", "true"), ("n_hat_rpm", "estimated")])]),
            fig_dir, "yao2022_fig23")

    return Outcome([
        claim("yao2022.fig23.linear_observer_stable", float(lin[0]), speed_dev=lin[1],
              angle_err=lin[2], angle_mean=mean_angle_error(res["yao2022.fig23.linear"])),
        claim("yao2022.fig23.smo_stable", float(smo[0]), speed_dev=smo[1], angle_err=smo[2]),
        claim("yao2022.fig23.smo_bias_rad", float(np.mean(bias.values)), expected=predicted,
              tolerance=round(abs(bias_exact) + 3 * sigma, 4), n_seeds=len(bias),
              sigma=sigma, bias_exact=bias_exact, e=math.hypot(*e),
              de=math.hypot(*(e_hat - e)),
              de_deg=math.degrees(math.atan2(*(e_hat - e)[::-1])), curve="; ".join(curve)),
    ], res, [("yao2022_fig23", plot)])


# ------------------------------------------------------------- Table VI -----


def table6_worst(rows: dict) -> dict[str, float]:
    """From the Table VI rows of smodrive.firmware.table6_cycles: each part's
    worst call at the pessimistic end of the timing range (its worst nominal
    call scaled by its mean's pessimistic / nominal ratio: the calls of a
    part take the same path and differ little) and their sum, an upper bound
    on the worst call of the whole step (the parts' worst calls may come
    from different samples)."""
    out = {part: r.worst * r.high / r.nominal for part, r in rows.items()}
    out["step"] = sum(out[part] for part in rows)
    return out


@EXPERIMENTS("yao2022.table6", "Execution cost")
def run_table6(progress: ProgressFn) -> Outcome:
    budget = firmware.BUDGET["yao2022"]
    paper = {part: float(c) for part, c in firmware.TABLE6_PAPER.items()}
    missing = ""
    try:
        # judged: the fast build (smd_fastmath); the exact one beside it
        tables = lcl_observer_tables(steady(100e3))
        rows, by_fn = firmware.table6_cycles(tables, "fast")
        rows_exact, _ = firmware.table6_cycles(tables, "fmath")
    except (firmware.TargetError, OSError, subprocess.SubprocessError) as exc:
        # toolchain or emulator missing: not measured (neither pass nor fail),
        # with the reason
        missing, rows, rows_exact, by_fn = str(exc), {}, {}, {}
    progress("yao2022.table6", 1.0)
    nan = float("nan")
    exact_step = flash_fast = flash_exact = nan
    if missing:
        parts, worst, costs, spread = "not measured", {"step": nan}, "not measured", nan
    else:
        worst = table6_worst(rows)
        exact_step = table6_worst(rows_exact)["step"]
        flash_fast = sum(r.worst_flash("stm32f4") for r in rows.values())
        flash_exact = sum(r.worst_flash("stm32f4") for r in rows_exact.values())
        parts = "; ".join(
            f"{part.replace('_', ' ')} {r.nominal:.0f} [{r.low:.0f}, {r.high:.0f}], worst "
            f"{worst[part]:.0f} (paper {paper[part]:.0f} on the C28x; ours "
            f"{r.nominal / paper[part]:.1f} times)" for part, r in rows.items())
        spread = max(r.worst / r.nominal - 1.0 for r in rows.values())
        cost: dict[str, float] = {}
        for fns in by_fn.values():
            for fn, c in fns.items():
                if not fn.startswith("blk_"):  # the test harness around the parts
                    label = TABLE6_COSTS.get(fn, fn)
                    cost[label] = cost.get(label, 0.0) + c
        costs = ", ".join(f"{k} {c:.0f}" for k, c in
                          sorted(cost.items(), key=lambda kv: -kv[1])[:5])
    total = sum(r.nominal for r in rows.values()) if rows else float("nan")
    claims = [claim("yao2022.table6.cycles_worst_call", worst["step"], tolerance=budget,
                    parts=parts, total=total, paper_total=sum(paper.values()),
                    ratio=total / sum(paper.values()), share=worst["step"] / budget,
                    left=budget - worst["step"], exact_step=exact_step,
                    flash_fast=flash_fast, flash_exact=flash_exact,
                    costs=costs, budget=budget, spread=spread, not_measured=missing)]
    return Outcome(claims)


SCENARIOS: dict[str, Callable[[], Scenario]] = {
    "yao2022.steady.100k": lambda: steady(100e3),
    "yao2022.fig14": fig14_scenario,
    "yao2022.fig14.ideal": lambda: fig14_scenario(ideal=True),
    "yao2022.fig19": fig19_scenario,
    "yao2022.fig22": fig22_scenario,
}


def paper_fig10(n: float) -> float:
    """The position error the paper reads by (60) at n r/min (the data file's)."""
    spec = SPECS["yao2022.fig10.pos_error_vs_paper_rad_{speed}"]
    return spec.paper[f"yao2022.fig10.pos_error_vs_paper_rad_{TAG[n]}"]
