"""yang2018: every claim of the reproduction, asserted with its tolerance.

Claims that fail for a stated reason are pinned as failing (so a change that
makes them pass, or breaks a passing one, shows up), and the stated reason is
itself checked with a number: removing the cause named in the claim must
bring the result inside the claim's bound.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math

import numpy as np
import pytest

from smodrive.analysis import metrics
from smodrive.claims import Claim, write_claims
from smodrive.scenarios import yang2018 as y
from smodrive.scenarios.common import over_seeds
from smodrive.engine import simulate

REQUIRED = [
    "yang2018.fig1.peak_gain_db_Lhat_2L",
    "yang2018.fig2.gain_at_wr",
    "yang2018.fig2.phase_at_wr_deg",
    "yang2018.fig5a.id_offset_A",
    "yang2018.fig5a.eq12_vs_exact",
    "yang2018.fig5b.noise_ripple_ratio",
    "yang2018.fig5c.iq_error_A",
    "yang2018.fig5d.iq_error_A",
    "yang2018.fig6a.id_offset_A",
    "yang2018.fig6a.iq_error_A",
    "yang2018.fig6a.noise_ripple_ratio",
    "yang2018.fig6b.id_offset_A",
    "yang2018.fig6b.iq_error_A",
    "yang2018.fig6b.noise_ripple_ratio",
    "yang2018.fig7a.pos_error_deg",
    "yang2018.fig7a.pos_error_peak_deg",
    "yang2018.fig7b.pos_error_deg",
    "yang2018.fig7b.pos_error_peak_deg",
    "yang2018.fig7b.pos_error_peak_deg_oversampled",
    "yang2018.fig8.speed_dip_rpm",
    "yang2018.fig8.pos_error_peak_deg",
    "yang2018.fig9.pos_error_peak_deg",
    "yang2018.fig9.speed_error_rms_rpm",
]

# Failing claims and why (each reason is checked below).
KNOWN_FAILING = {
    "yang2018.fig1.sim_peak_gain_db_Lhat_2L_vs_eq14": "eq. (14) assumes the Euler plant",
    "yang2018.fig5a.eq12_vs_exact": "eq. (12) assumes the Euler plant",
    "yang2018.fig7b.pos_error_peak_deg": "ADC noise and dead time at 75 r/min",
    "yang2018.fig7b.pos_error_peak_deg_oversampled": "the dead time alone exceeds the bound",
    "yang2018.fig9.pos_error_peak_deg": "ADC noise and dead time at 150 r/min",
}


@functools.cache
def paper_claims() -> tuple[Claim, ...]:
    """Every claim of yang2018 in the order of the reproduction, computed
    once per test session (tests/test_claims_data.py checks them against
    the data file)."""
    return tuple(c for exp in y.EXPERIMENTS for c in exp.run(lambda name, frac: None).claims)


@pytest.fixture(scope="module")
def claims():
    return {c.id: c for c in paper_claims()}


def test_every_required_claim_is_produced(claims):
    missing = [c for c in REQUIRED if c not in claims]
    assert not missing


def test_claims_json_schema(claims, tmp_path):
    write_claims(list(claims.values()), tmp_path / "claims.json")
    data = json.loads((tmp_path / "claims.json").read_text())
    assert isinstance(data, list) and len(data) == len(claims)
    for item in data:
        for key in ("id", "statement", "paper", "expected", "reproduced", "unit", "tolerance",
                    "passed"):
            assert key in item
        assert isinstance(item["passed"], bool)
        assert math.isfinite(item["reproduced"])


@pytest.mark.parametrize("cid", REQUIRED + ["yang2018.fig1.sim_peak_gain_db_Lhat_2L_vs_exact",
                                            "yang2018.fig6a.ripple_vs_fig5b"])
def test_claim_verdict(claims, cid):
    c = claims[cid]
    # the verdict is the claim's own check, recomputed here
    if c.check == "max":
        ok = c.reproduced <= c.tolerance
    elif c.check == "min":
        ok = c.reproduced >= c.tolerance
    elif c.check == "abs":
        ok = abs(c.reproduced - c.target) <= c.tolerance
    else:
        ok = abs(c.reproduced / c.target - 1) <= c.tolerance
    assert ok == c.passed
    if cid in KNOWN_FAILING:
        assert not c.passed and "Why:" in c.statement, f"{cid} now passes: update KNOWN_FAILING"
    else:
        assert c.passed, c.statement


def test_known_failing_claims_are_pinned(claims):
    for cid in KNOWN_FAILING:
        assert not claims[cid].passed


# ---------------------------------------------------------- the reasons ----

def test_fig1_eq14_overestimates_because_of_euler_plant():
    """With the Euler plant (3) the exact closed loop reduces to eq. (14)'s
    peak (within 0.01 dB); with the zero-order-hold plant it is > 5 dB lower."""
    L, R, T = y.MOTOR.L_s, y.MOTOR.R_s, y.BASE.T_sp
    from smodrive.analysis import tf

    peak14, f14 = tf.peak_gain(tf.H_dbpc(L, 2 * L, R, T))
    w = 2 * np.pi * np.linspace(0.9 * f14, 1.1 * f14, 200_001)
    z = np.exp(1j * w * T)
    c = 1 - R * T / (2 * L)
    a_eu, b_eu = 1 - R * T / L, T / L  # Euler plant, eq. (3)
    h_eu = (2 * L / T) / ((z - a_eu) * (z + c) / b_eu + (2 * L / T) * c**2)
    h_ex = y.dbpc_exact_closed_loop(L, R, 2 * L, R, T, z)
    # eq. (14) drops only T^2 terms of the Euler loop: agreement to 0.05 dB
    assert abs(20 * np.log10(np.max(np.abs(h_eu)) / peak14)) < 0.05
    assert 20 * np.log10(peak14 / np.max(np.abs(h_ex))) > 5.0


def _ideal_adc(s):
    return s.replace(adc=dataclasses.replace(s.adc, noise=0.0, bits=0))


def _ideal_inverter(s):
    return s.replace(inverter=dataclasses.replace(s.inverter, t_dead=0.0),
                     controller=dataclasses.replace(s.controller, t_dead_comp=0.0))


def test_fig6a_ripple_is_adc_noise():
    """The ripple growth of Fig. 6(a) (robust DBPC, L_hat = 2 L against
    L_hat = L) is the noise gain's (errata E12): without ADC noise and
    quantisation the growth is under a fifth of the growth with them
    (measured 0.0077 A against 0.065 A, 12 %). A growth of the loop's own
    (a limit cycle that the SMDO did not remove) would be there without
    the noise too, and the share would be near 1. (Until 2026-11-27 this
    bounded the noiseless ratio at 1.5, measured 1.17; the plant's duty of
    0 without a dead-time pulse sends the exact-parameter run, through the
    load step's saturated samples, into the quieter of its two limit
    cycles, 0.0100 A instead of 0.0153 A, and the ratio to 1.77: a ratio
    of two noiseless ripples depends on which cycle each run ends in, the
    growth's share does not.)"""
    L = y.MOTOR.L_s
    r = {}
    for adc in ("ideal", "noisy"):
        for key, kw in (("ex", {}), ("2L", {"L_s_hat": 2 * L})):
            s = y.fig56_scenario(key, "robust", **kw)
            res = simulate(_ideal_adc(s) if adc == "ideal" else s)
            m = res.window(*y.SS_WINDOW)
            r[adc, key] = metrics.ripple_dq(res["i_d"][m], res["i_q"][m])
    growth_ideal = r["ideal", "2L"] - r["ideal", "ex"]
    growth_noisy = r["noisy", "2L"] - r["noisy", "ex"]
    assert growth_noisy > 0.0
    assert growth_ideal <= 0.2 * growth_noisy, r


def test_fig7b_holds_lock_with_the_clipped_duties_voltage():
    """Fig. 7(b), 75 r/min at rated load: the robust DBPC chases the ADC
    noise onto the hexagon, about 7 % of its duties at exactly 0 or 1, where
    the dead-time compensation is clipped and the inverter does not apply
    what the modulator computed (a duty of 0 switches nothing; a duty of 1
    keeps its rising edge's dead time). The drive gives the SMDO that
    voltage (smd_svm_deadtime_comp_lost): over 10 noise seeds no run loses
    the rotor, and the RMS position error after 0.5 s stays below 4 deg
    (measured 3.2-3.6; the claim's quoted value is 1.1). Given the
    modulator's voltage instead, 2 of the 10 lost the rotor (lost_lock,
    angle_jump) once the plant's duty of 0 had no dead-time pulse."""
    s0 = y.fig7_scenario(75.0)
    for seed in range(1, 11):
        r = simulate(s0.replace(adc=dataclasses.replace(s0.adc, seed=seed)))
        assert r.faults.final == 0, seed
        m = r.t >= 0.5
        rms = math.degrees(float(np.sqrt(np.mean(r.theta_error[m] ** 2))))
        assert rms < 4.0, (seed, rms)


def _no_noise(s):
    """The ADC noise off, its 12-bit quantisation kept."""
    return s.replace(adc=dataclasses.replace(s.adc, noise=0.0))


def _p90_peak(s, t0):
    return over_seeds(s, y.peak_pos_error(t0, s.duration)).p90


@pytest.mark.parametrize("scenario, t0, cid", [
    (lambda: y.fig7_scenario(75.0), 0.5, "yang2018.fig7b.pos_error_peak_deg"),
    (y.fig9_scenario, y.HANDOVER, "yang2018.fig9.pos_error_peak_deg"),
])
def test_low_speed_peaks_are_adc_noise_and_dead_time(claims, scenario, t0, cid):
    """With an ideal ADC and no dead time the low-speed peak position error
    is inside the claims' 10 deg bound (and its quoted 1.1 deg); with the
    noise off and the quantisation kept, below the quoted 1.5 deg (1.47 at
    75 r/min since issue 18's warm start applies its steady-state voltage
    from t = 0; 1.42 before: the quantisation-limited peak depends on where
    the 12-bit steps fall, which the first samples move; the bound stays
    seven times below the claims' 10 deg)."""
    bound = claims[cid].tolerance
    assert bound == 10.0 and claims[cid].check == "max"
    peak = y.peak_pos_error(t0, scenario().duration)
    assert peak(simulate(_ideal_inverter(_ideal_adc(scenario())))) <= min(bound, 1.1)
    assert peak(simulate(_ideal_inverter(_no_noise(scenario())))) <= 1.5


def test_fig7b_each_cause_alone_fails():
    """At 75 r/min either cause alone exceeds the 10 deg bound (90th
    percentile over the seeds): the dead time with the noise off (quoted
    10.5 deg), the noise with the dead time off (quoted 13.0 deg)."""
    s = y.fig7_scenario(75.0)
    assert 10.0 < _p90_peak(_no_noise(s), 0.5) <= 11.0
    assert 10.0 < _p90_peak(_ideal_inverter(s), 0.5) <= 14.0


def test_fig7b_oversampling_leaves_the_dead_time(claims):
    """Oversampling the current lowers the noise's share of the 75 r/min
    peak (below the single-conversion claim's value) but not the dead
    time's: without noise the oversampled drive's peak is the same 10.5 deg
    (averaging quantised noiseless conversions changes nothing), so the
    second claim fails for the reason it states."""
    single = claims["yang2018.fig7b.pos_error_peak_deg"].reproduced
    ov = claims["yang2018.fig7b.pos_error_peak_deg_oversampled"]
    assert ov.reproduced < single - 2.0
    s = y.fig7_oversampled_scenario()
    assert s.adc.n_oversample == y.FIG7_OVERSAMPLE > 1
    assert 10.0 < _p90_peak(_no_noise(s), 0.5) <= 11.0


def test_fig9_peak_is_dead_time():
    """In Fig. 9 the dead time dominates: with the noise off the peak stays
    above the bound (quoted 14.4 deg), with the dead time off it is inside
    (quoted 8.4 deg, 90th percentile)."""
    s = y.fig9_scenario()
    assert s.inverter.dead_time_model == "clamp" and s.load.T_brake.y == (0.0,)
    assert 13.5 < _p90_peak(_no_noise(s), y.HANDOVER) <= 15.0
    assert _p90_peak(_ideal_inverter(s), y.HANDOVER) <= 10.0


def test_fig9_clamp_lowers_the_peak():
    """Zero-current clamping (the physical model near zero current) gives a
    lower Fig. 9 peak than the hard-sign model (quoted 23.0 deg), over the
    same seeds."""
    s = y.fig9_scenario()
    sign = s.replace(inverter=dataclasses.replace(s.inverter, dead_time_model="sign"))
    assert _p90_peak(s, y.HANDOVER) < _p90_peak(sign, y.HANDOVER) - 3.0


# ------------------------------------------------- the wrong variants ----
#
# Each claim's criterion must reject the plausible wrong implementation:
# the variant is measured the way the claim measures and judged by the
# claim's own check.

def test_fig2_euler_rotation_fails_both_claims():
    """The forward-Euler rotation printed in (36) (gain 1.0133, phase
    0.215 deg) fails both Fig. 2 claims, the exact rotation passes them."""
    s = y.fig2_scenario()
    G, w, i_q = y.fig2_measure(simulate(s))
    s_e = s.replace(controller=dataclasses.replace(s.controller, smdo_euler=True))
    G_e, w_e, i_q_e = y.fig2_measure(simulate(s_e))
    assert all(c.passed for c in y.fig2_claims(G, w, i_q, G_e))
    assert not any(c.passed for c in y.fig2_claims(G_e, w_e, i_q_e, G_e))


def test_fig2_phase_follows_the_load():
    """The expected phase R T i_q / (2 psi) is a prediction, not a fit: it
    moves with the load, and without load the measured phase follows it to
    0.005 deg (the claim's tolerance is 0.03 deg)."""
    s = y.fig2_scenario().replace(load=y.LoadCfg())
    G, w, i_q = y.fig2_measure(simulate(s))
    gain, phase = y.fig2_expected(w, i_q)
    assert abs(i_q) < 0.5 and abs(phase) < 0.01
    assert abs(np.degrees(np.angle(G)) - phase) < 0.01
    assert abs(abs(G) - gain) < 1e-4


def test_fig7a_timing_errors_fail():
    """The controller's angle one sample late (3.6 deg RMS), or eq. (44)
    without the half-sample advance of errata E4 (1.8 deg), fails the
    1500 r/min RMS claim."""
    r = simulate(y.fig7_scenario(1500.0))
    m = r.window(0.5, 1.0)
    lag = metrics.rms(y.pos_error_lagged_deg(r, m, 1))
    assert 3.3 < lag < 3.9
    half = (r["theta_r"] - (r["theta_hat"] - 0.5 * r["w_hat"] * r.scenario.T_sp) + np.pi) \
        % (2 * np.pi) - np.pi
    for wrong in (lag, metrics.rms(np.degrees(half[m]))):
        assert not y.SPECS.claim("yang2018.fig7a.pos_error_deg", wrong, lag_deg=lag).passed
    right = metrics.rms(y.pos_error_lagged_deg(r, m, 0))
    assert y.SPECS.claim("yang2018.fig7a.pos_error_deg", right, lag_deg=lag).passed


def test_fig9_wrong_speed_paths_fail():
    """The RMS claim rejects what the old mean criterion (|mean| <= 0.5 r/min)
    cannot: eq. (45) on the angle without the low-pass (mean error still
    small); and, like the mean, a single cycle slip (a 2 pi step of the angle
    through the low-pass, about 90 r/min RMS over these windows)."""
    s = y.fig9_scenario()
    r = simulate(s)
    T, ctrl = s.T_sp, s.controller
    ok = y.fig9_speed_claim(r, y.fig9_speed_error_rpm(r, r["w_hat"]))
    assert ok.passed
    raw = np.concatenate([[0.0], np.diff(np.unwrap(r["theta_hat"])) / T])
    dw = y.fig9_speed_error_rpm(r, raw)
    assert abs(np.mean(dw)) < 0.5
    assert not y.fig9_speed_claim(r, dw).passed
    # one slip of -2 pi in the steady interval at 1500 r/min, through the LPF
    p = np.exp(-ctrl.w_lpf * T)
    k0 = int(np.searchsorted(r.t, 1.0))
    slip = np.zeros_like(r.t)
    slip[k0:] = -2 * np.pi / T * (1 - p) * p ** np.arange(len(r.t) - k0)
    dw = y.fig9_speed_error_rpm(r, r["w_hat"] + slip)
    assert 60.0 < metrics.rms(dw) < 120.0
    assert not y.fig9_speed_claim(r, dw).passed


def test_fig6_noise_ratio_rejects_loop_without_smdo():
    """The noise-ripple claim rejects the conventional DBPC in its place
    (the same L_hat, no SMDO: ratio 4 or more with L_hat = 2 L) and the
    open-loop 2x."""
    st = y.noise_ripple_ratios(2.0, mode="conventional")
    g = y.robust_dbpc_noise_gain
    expected = g(2 * y.MOTOR.L_s) / g(y.MOTOR.L_s)
    kw = dict(expected=expected, letter="a", ratio=2.0, n_seeds=len(st), worst=st.worst,
              noise_mA=0.5, scenario_ratio=3.0)
    assert not y.SPECS.claim("yang2018.fig6{letter}.noise_ripple_ratio", st.median, **kw).passed
    assert not y.SPECS.claim("yang2018.fig6{letter}.noise_ripple_ratio", 2.0, **kw).passed


def _fig5a_operating_point(r):
    m = r.window(*y.SS_WINDOW)
    L, psi = y.MOTOR.L_s, y.MOTOR.psi_r
    return (L, y.MOTOR.R_s, psi, 0.5 * L, y.MOTOR.R_s, psi,
            float(np.mean(r["w_M"][m])) * y.MOTOR.n_p, r.scenario.T_sp, 0.0,
            float(np.mean(r["i_q"][m]))), float(np.mean(r["i_d"][m]))


def test_fig5a_exact_fixed_point_is_the_ideal_drive():
    """With an ideal inverter (no dead time, none compensated) and an ideal
    ADC the simulated offset of Fig. 5(a) is the exact steady state of
    (7)-(9) on the zero-order-hold machine to 1e-4 A (measured 0.9403 both),
    the agreement the claim's statement reports; eq. (12) (0.817 A) and the
    Euler plant's fixed point (0.801 A) are 0.12-0.14 A away."""
    r = simulate(_ideal_adc(_ideal_inverter(
        y.fig56_scenario("fig5a.ideal", "conventional", L_s_hat=0.5 * y.MOTOR.L_s))))
    op, i_d = _fig5a_operating_point(r)
    assert i_d == pytest.approx(y.dbpc_fixed_point(*op)[0], abs=1e-4)
    assert abs(i_d - y.dbpc_fixed_point(*op, plant="euler")[0]) > 0.1
    assert abs(i_d - y.tf.dbpc_steady_state(*op)[0]) > 0.1


def test_fig5a_criterion_rejects_the_wrong_predictions(claims):
    """The claim's bound (0.01 A about the exact steady state with the dead
    time) rejects the plausible wrong expectations, each at the measured
    operating point: eq. (12), the Euler plant's steady state and the exact
    one without the dead time (a drive or a model that leaves it out)."""
    c = claims["yang2018.fig5a.id_offset_A"]
    s = y.fig56_scenario("fig5a", "conventional", L_s_hat=0.5 * y.MOTOR.L_s)
    op, i_d = _fig5a_operating_point(simulate(s))
    assert i_d == pytest.approx(c.reproduced, abs=1e-12)  # the claim's run
    dt = dict(t_dead=s.inverter.t_dead, t_dead_comp=s.controller.t_dead_comp,
              u_dc=s.inverter.u_dc)
    assert c.expected == pytest.approx(y.dbpc_fixed_point(*op, **dt)[0], abs=1e-12)
    for wrong in (y.tf.dbpc_steady_state(*op)[0], y.dbpc_fixed_point(*op, plant="euler")[0],
                  y.dbpc_fixed_point(*op)[0]):
        assert abs(i_d - wrong) > 2 * c.tolerance


def test_fig5b_noise_ratio_rejects_the_plausible_wrong_loops(claims):
    """Fig. 5(b)'s noise-ripple claim passes against the linear loop's H2
    norm (11.98) and rejects what the old bound (>= 2) let through: the
    open-loop doubling of the deadbeat gain (2.0) and the Euler model (3) of
    the machine (20.6: an Euler-plant simulator), and a robust DBPC in the
    conventional one's place (the SMDO damps the ring: about 2.3)."""
    c = claims["yang2018.fig5b.noise_ripple_ratio"]
    assert c.passed and c.expected == pytest.approx(11.98, abs=0.01)
    g = y.dbpc_noise_gain
    euler = g(2 * y.MOTOR.L_s, plant="euler") / g(y.MOTOR.L_s, plant="euler")
    assert euler > 20.0
    robust = claims["yang2018.fig6a.noise_ripple_ratio"].reproduced
    kw = dict(expected=c.expected, n_seeds=10, worst=0.0, noise_mA=0.5, scenario_ratio=4.5,
              euler=euler)
    for wrong in (2.0, euler, robust):
        assert not y.SPECS.claim("yang2018.fig5b.noise_ripple_ratio", wrong, **kw).passed


@pytest.mark.parametrize("change", [dict(J_hat_k=1.25), dict(speed_bw_k=0.8),
                                    dict(speed_bw_k=1.25), dict(w_lpf_k=2.0)])
def test_fig8_speed_dip_rejects_a_speed_loop_off_its_design(change):
    """The dip claim checks the speed path against its linear design: a
    drive whose speed PI or speed filter is not the designed one (gains 25 %
    off, the filter twice as fast), judged against the design's dip, fails."""
    s0 = y.fig8_scenario()
    c = s0.controller
    k = {"J_hat": c.J_hat * change.get("J_hat_k", 1.0),
         "speed_bw": c.speed_bw * change.get("speed_bw_k", 1.0),
         "w_lpf": c.w_lpf * change.get("w_lpf_k", 1.0)}
    r = simulate(s0.with_controller(**k))
    dip = float(y.W_N - np.min(r["w_M"][r.window(y.FIG8_ON, y.FIG8_OFF)])) / y.RPM
    exp_dip = y.speed_loop_load_dip(c, s0.motor.J, s0.motor.n_p, y.T_N) / y.RPM
    assert not y.SPECS.claim("yang2018.fig8.speed_dip_rpm", dip, expected=exp_dip,
                             tolerance=round(0.06 * exp_dip, 2)).passed


def test_fig7a_and_fig8_peaks_reject_a_one_sample_lag(claims):
    """The peak bounds (3 and 3.5 deg, three times their error budgets)
    reject the controller's angle one sample late, which the 10 deg bound of
    the paper's 'almost coincide' let through."""
    for cid, s, t0 in (("yang2018.fig7a.pos_error_peak_deg", y.fig7_scenario(1500.0), 0.5),
                       ("yang2018.fig8.pos_error_peak_deg", y.fig8_scenario(), y.HANDOVER)):
        c = claims[cid]
        assert c.passed
        r = simulate(s)
        lag = float(np.max(np.abs(y.pos_error_lagged_deg(r, r.window(t0, s.duration), 1))))
        assert lag > c.tolerance
