"""yao2022: every claim of the reproduction, asserted with its tolerance.

As for yang2018, failing claims are pinned and their stated causes checked:
removing the cause named in the claim brings the result inside its bound,
or the number the reason quotes is verified.
"""

from __future__ import annotations

import functools
import itertools
import json
import math
import re
import tempfile
from pathlib import Path

import numpy as np
import pytest

from smodrive.analysis import metrics
from smodrive.claims import Claim, write_claims
from smodrive.design import yao2022 as dz
import dataclasses

from smodrive.model import Profile
from smodrive.engine import CHANNELS, simulate
from smodrive.scenarios import yao2022 as y

REQUIRED = (
    [f"yao2022.table1.h{h}_V" for h in range(1, 6)]
    + ["yao2022.fig4.comp_error_ratio_18_over_17", "yao2022.fig7.pll_bandwidth_hz"]
    + [f"yao2022.fig10.injection_vs_true_rad_{t}" for t in ("30k", "60k", "100k")]
    + [f"yao2022.fig10.pos_error_vs_paper_rad_{t}" for t in ("30k", "60k", "100k")]
    + [f"yao2022.fig9.true_pos_error_rad_{t}" for t in ("30k", "60k", "100k")]
    + [f"yao2022.table5.ripple_rpm_{law}_{t}" for law in ("baseline", "proposed")
       for t in ("30k", "60k", "100k")]
    + ["yao2022.table5.ripple_reduction_100k", "yao2022.fig14.pos_error_peak_rad",
       "yao2022.fig14.pos_error_peak_rad_adc", "yao2022.fig14.end_speed_rpm",
       "yao2022.fig19.pos_error_peak_rad", "yao2022.fig21.speed_error_peak_rpm",
       "yao2022.fig22.reversal_pos_error_peak_rad", "yao2022.fig22.crossing_pos_error_peak_rad",
       "yao2022.fig23.linear_observer_stable",
       "yao2022.fig23.smo_stable", "yao2022.fig23.smo_bias_rad",
       "yao2022.table6.cycles_worst_call"]
)

KNOWN_FAILING = {
    **{f"yao2022.table5.ripple_rpm_{law}_{t}": "the PLL attenuates the chattering"
       for law in ("baseline", "proposed") for t in ("30k", "60k", "100k")},
    "yao2022.table5.ripple_reduction_100k": "ripple set by the ADC noise and quantisation, "
                                            "the same with either law",
    **{f"yao2022.fig10.pos_error_vs_paper_rad_{t}": "no dead time in the simulated inverter: "
       "35 ns uncompensated give the paper's 30 and 60 kr/min readings" for t in ("30k", "60k")},
    "yao2022.fig14.pos_error_peak_rad_adc": "ADC noise at 5-10 kr/min after the handover",
    "yao2022.fig22.reversal_pos_error_peak_rad": "ADC noise just outside the crossing: 0 of 10 "
                                                 "seeds within 0.1 rad",
    "yao2022.fig22.crossing_pos_error_peak_rad": "no back EMF within +-3 kr/min",
    "yao2022.fig23.linear_observer_stable": "the linear observer keeps its designed poles",
}

IDEAL = y.IDEAL_ADC
GAINS_ONLY = dataclasses.replace(y.ADC, noise=0.0, bits=0)


# the figure closures of Table V's run (kept to check what they write)
TABLE5_FIGURES: list = []


@functools.cache
def paper_claims() -> tuple[Claim, ...]:
    """Every claim of yao2022 in the order of the reproduction, computed
    once per test session (tests/test_claims_data.py checks them against
    the data file)."""
    out = []
    for exp in y.EXPERIMENTS:
        outcome = exp.run(lambda name, frac: None)
        out += outcome.claims
        if exp.id == "yao2022.table5":
            TABLE5_FIGURES[:] = outcome.figures
    return tuple(out)


@pytest.fixture(scope="module")
def claims():
    return {c.id: c for c in paper_claims()}


def test_every_required_claim_is_produced(claims):
    assert not [c for c in REQUIRED if c not in claims]


def test_claims_json(claims, tmp_path):
    write_claims(list(claims.values()), tmp_path / "c.json")
    data = json.loads((tmp_path / "c.json").read_text())
    assert {d["id"] for d in data} == set(claims)


@pytest.mark.parametrize("cid", REQUIRED + ["yao2022.fig12_13.chattering_ratio_100k",
                                            "yao2022.table5.harmonic_ripple_reduction_100k"])
def test_claim_verdict(claims, cid):
    c = claims[cid]
    if cid in KNOWN_FAILING:
        assert not c.passed and "Why:" in c.statement, f"{cid} now passes: update KNOWN_FAILING"
    else:
        assert c.passed, c.statement


# ---------------------------------------------------------- the reasons ----

@pytest.mark.parametrize("n", [30e3, 100e3])
def test_injection_reading_is_shifted_by_the_adc_scaling_rotation(n):
    """The expectation of the injection_vs_true claims: without ADC noise, the reading of eq. (60)
    minus the true error during the injection is 0 with ideal gains and
    -arg k1 = -5.77 mrad with the +-1 % gains, each within 1.5 mrad (the
    second-order terms the claim's tolerance allows 2 mrad for)."""

    def offset(adc):
        s = y.steady(n, name="x").replace(
            duration=y.INJ_T + 0.05 + y.INJ_W, i_d_ref=Profile.steps(0.0, (y.INJ_T, 5.0)),
            adc=adc)
        r = simulate(s)
        b, a = r.window(y.INJ_T - y.INJ_W, y.INJ_T), r.window(y.INJ_T + 0.05, s.duration)
        inj = math.atan((r["i_dl"][b].mean() - r["i_dl"][a].mean()) / r["i_g"][a].mean())
        return inj + r.theta_error[a].mean()  # reading - (theta_hat - theta)

    rot = metrics.scaling_rotation(GAINS_ONLY.gain)
    assert rot == pytest.approx(0.01 / math.sqrt(3), rel=1e-3)
    assert abs(offset(IDEAL)) <= 0.0015
    assert abs(offset(GAINS_ONLY) + rot) <= 0.0015


def test_scaling_rotation_against_a_sampled_clarke_transform():
    """arg k1 from the closed form against the mean of i_meas / i over a
    turn of a sampled current vector, measured as smodrive's controllers do
    (a, b through their gains, c = -a - b)."""
    rng = np.random.default_rng(3)
    for _ in range(5):
        g = tuple(1.0 + rng.uniform(-0.05, 0.05, 3))
        th = np.linspace(0, 2 * np.pi, 720, endpoint=False)
        i = 7.0 * np.exp(1j * (th + 0.3))
        ia, ib = i.real, (i * np.exp(-2j * np.pi / 3)).real
        xa, xb = g[0] * ia, g[1] * ib
        i_meas = xa + 1j * (xa + 2 * xb) / math.sqrt(3)
        k1 = np.mean(i_meas / i)  # the k2 conj(i)/i part averages out over a turn
        assert metrics.scaling_rotation(g) == pytest.approx(np.angle(k1), abs=1e-12)


def test_pll_attenuates_the_chattering_harmonics():
    """The ripple claims' reason: the closed loop of eq. (48)-(50) passes
    2 f_e and 3 f_e at 100 kr/min with gain below 0.11 (so a ripple of
    hundreds of r/min would need kHz angle-error swings of radians)."""
    g = dz.pll_closed_loop(dz.PllPars())
    for f in (2 * 100e3 / 60, 3 * 100e3 / 60):
        assert abs(g(np.exp(2j * np.pi * f * 50e-6))) < 0.11


def test_fig14_peak_is_adc_noise(claims):
    """With the realistic ADC the peak after the handover is ADC noise:
    without the noise (gains kept) it drops below a third of the claim's
    value; with ideal sensors it is the first fig14 claim (within 0.02)."""
    s = y.fig14_scenario()
    noisy = claims["yao2022.fig14.pos_error_peak_rad_adc"].reproduced
    assert y.peak_after_handover(simulate(s.replace(adc=GAINS_ONLY))) < noisy / 3
    assert claims["yao2022.fig14.pos_error_peak_rad"].reproduced < 0.02


def test_fig14_ideal_peak_scales_with_the_ramp_rate():
    """The numbers docs/assumptions.md and the basis quote: with ideal
    sensors the peak is about 0.016 rad at 10 kr/min/s and 0.032 rad at 20
    (so the paper's 0.02 bounds the rate the reproduction may assume), and
    the 20 kr/min/s run stops at 94.5 kr/min on the voltage limit: the
    end-speed claim rejects it."""
    got = {}
    for rate in (10e3, 20e3):
        r = simulate(y.fig14_scenario(ideal=True, rate=rate))
        got[rate] = (y.peak_after_handover(r), y.end_speed_rpm(r))
    assert got[10e3][0] == pytest.approx(0.016, abs=0.002)
    assert got[20e3][0] == pytest.approx(0.032, abs=0.003)
    r = simulate(y.fig14_scenario(rate=20e3))
    assert y.end_speed_rpm(r) == pytest.approx(94.5e3, abs=500)
    c = y.claim("yao2022.fig14.end_speed_rpm", y.end_speed_rpm(r), rate_krpm_s=20.0, t_end=0.0,
                end_ideal=got[20e3][1], n_seeds=1, median=0.0, worst=0.0, worst_seed=1,
                pct=90.0)
    assert not c.passed


def test_fig14_peak_against_the_ramp_rate(claims):
    """The curve the claim states (and figure yao2022_fig14_rate draws): with
    ideal sensors the peak grows with the assumed ramp rate, from 0.0067 rad
    at 4 kr/min/s to 0.031 at 20; it crosses the paper's 0.02 rad between 12
    and 14 kr/min/s (12.9, linear), above the rates at which the drive
    reaches 100 kr/min (10 and below: the voltage limit). The claim rejects
    the plausible wrong set-up, a faster assumed ramp (14 and 20 kr/min/s,
    the old 20 among them), and passes the argued 8."""
    curve = y.fig14_rate_curve()
    rates = sorted(curve)
    peaks = [curve[r][0] for r in rates]
    assert rates == sorted(y.FIG14_RATES) and y.FIG14_RATE in rates
    assert all(b > a for a, b in itertools.pairwise(peaks))
    assert curve[4e3][0] == pytest.approx(0.0067, abs=0.001)
    assert curve[20e3][0] == pytest.approx(0.031, abs=0.002)
    rate_fail = y.crossing_rate(curve, 0.02)
    assert 12e3 < rate_fail < 14e3
    assert all(curve[r][1] >= 99e3 for r in rates if r <= 10e3)
    assert all(curve[r][1] < 99e3 for r in rates if r >= 12e3)
    c = claims["yao2022.fig14.pos_error_peak_rad"]
    assert c.passed and c.reproduced == pytest.approx(curve[y.FIG14_RATE][0], rel=1e-12)
    assert f"exceeds the bound from {rate_fail / 1e3:.1f} kr/min/s" in c.basis
    for rate in (14e3, 20e3):
        assert not dataclasses.replace(c, reproduced=curve[rate][0], statement="").passed
    # the crossing helper: linear between the grid points, inf if never crossed
    assert y.crossing_rate({1.0: (0.01, 0), 3.0: (0.03, 0)}, 0.02) == pytest.approx(2.0)
    assert y.crossing_rate({1.0: (0.01, 0), 3.0: (0.015, 0)}, 0.02) == math.inf


def test_fig14_voltage_limit_at_100krpm():
    """The reason the ramp is 8 kr/min/s (docs/assumptions.md): in steady
    state at 100 kr/min the LCL drive needs |u| = 31.9 V for the fan's
    29.9 A (Table IV) of the u_dc / sqrt 3 = 37.5 V the 65 V bus gives
    (linear modulation); the current at which it needs all 37.5 V leaves
    5.9 A for acceleration, 10.2 kr/min/s with J = 1e-5; 8 kr/min/s (4.7 A)
    needs 36.3 V, 20 kr/min/s (11.6 A) 43.1 V."""
    import scipy.optimize

    m, f = y.MOTOR, y.BASE.lcl
    w = 100e3 * y.RPM * m.n_p

    def u(i_q):
        i2 = 1j * i_q
        uc = 1j * w * m.psi_r + (m.R_s + 1j * w * (f.L2o + m.L_s)) * i2
        return abs(uc + 1j * w * f.L1 * (i2 + 1j * w * f.C1 * uc))

    k_t = 1.5 * m.n_p * m.psi_r
    i_fan = y.BASE.load.k_fan * (100e3 * y.RPM) ** 2 / k_t
    i_acc = lambda rate: m.J * rate * y.RPM / k_t  # noqa: E731
    u_max = y.BASE.inverter.u_dc / math.sqrt(3)
    assert i_fan == pytest.approx(29.9, abs=0.05)
    assert u(i_fan) == pytest.approx(31.9, abs=0.05)
    i_top = scipy.optimize.brentq(lambda i: u(i) - u_max, i_fan, 45.0)
    assert (i_top - i_fan) * k_t / m.J / y.RPM == pytest.approx(10.2e3, abs=100)
    assert y.FIG14_RATE == 8e3
    assert u(i_fan + i_acc(8e3)) == pytest.approx(36.3, abs=0.05)
    assert u(i_fan + i_acc(20e3)) == pytest.approx(43.1, abs=0.05)


def test_fig22_reasons():
    """Seed 0: the paper's drive (no loss-of-lock protection) gets through the
    crossing; with smodrive's protection the loss of lock is declared in the
    crossing and the drive ends in its safe state near zero speed. Without
    the noise the error outside the crossing falls inside the bound."""
    s = y.fig22_scenario()
    assert s.controller.t_lock == 0.0 and y.fig22_protected_scenario().controller.t_lock > 0
    seed0 = dataclasses.replace(s.adc, seed=0)
    r_paper = simulate(s.replace(adc=seed0))
    assert y.crossing(r_paper)[1] and r_paper.faults.t_first is None
    r0 = simulate(y.fig22_protected_scenario().replace(adc=seed0))
    band, done = y.crossing(r0)
    assert not done and "lost_lock" in r0.faults.as_dict()["first_fault"]
    assert 1.0 < r0.faults.t_first < 1.4 and abs(y.end_speed_rpm(r0)) < 100
    r = simulate(s.replace(adc=GAINS_ONLY))
    m = y.fig22_metrics(r)
    assert m["done"] == 1.0 and m["outside"] <= y.GOOD_ANGLE
    assert m["band"] > math.pi / 2  # the crossing: lost without noise too


def test_fig22_pass_fraction_rejects_what_the_median_passed(claims):
    """The claim is the fraction of seeds within 0.1 rad outside the
    crossing (at least 9 of 10). The seeds' peaks (0.17-0.24 rad) have a
    median under the old self-set 0.2 rad, which passed; none is within the
    argued 0.1 rad, so the claim fails with its measured reason. The drive
    without ADC noise (gains kept; every seed alike) has all seeds within
    the bound and passes; 8 of 10 within would fail."""
    c = claims["yao2022.fig22.reversal_pos_error_peak_rad"]
    peaks = y.over_seeds(y.fig22_scenario(), lambda r: y.fig22_metrics(r)["outside"])
    assert c.check == "min" and c.tolerance == 0.9
    assert c.reproduced == peaks.count(lambda v: v <= y.GOOD_ANGLE) / len(peaks) == 0.0
    assert peaks.median <= 0.2  # the old criterion (median within 0.2 rad) passed
    assert not c.passed and f"{peaks.median:.3f}" in c.statement
    m = re.search(r"peaks at ([0-9.]+) rad outside the crossing", c.statement)
    assert m and float(m.group(1)) <= y.GOOD_ANGLE
    assert dataclasses.replace(c, reproduced=1.0, statement="").passed
    assert not dataclasses.replace(c, reproduced=0.8, statement="").passed


def test_fig22_crossing_hides_nothing():
    """The crossing is cut where the drive really crosses: a run that never
    leaves the band counts as pi outside it (it used to be measured only
    before the band, hiding the stop), and the time in the band is reported."""
    s = y.fig22_scenario().replace(duration=1.3)  # ends inside the band
    m = y.fig22_metrics(simulate(s))
    assert m["done"] == 0.0 and m["outside"] == math.pi and m["band_ms"] > 50


def test_fig17_18_closure_returns_both_figures(claims, tmp_path):
    """Table V's run plots Figs. 17 and 18 in one closure; it returns both
    paths (report.md embeds every path a closure returns)."""
    plots = dict(TABLE5_FIGURES)
    paths = plots["yao2022_fig17_18"](tmp_path)
    assert [p.name for p in paths] == ["yao2022_fig17.png", "yao2022_fig18.png"]
    assert all(p.is_file() and p.stat().st_size > 10_000 for p in paths)


def test_linear_observer_keeps_its_poles_with_a_capacitance_error():
    """Theta = G22 - L G12 designed with 2 C has the designed poles; the true
    plant only biases the estimate (the reason the Fig. 23 claim fails)."""
    p = dz.DesignPlant(y.BASE.motor, y.BASE.lcl, y.BASE.T_sp)
    lo = dz.linear_observer(dataclasses.replace(p, lcl=dataclasses.replace(p.lcl, C1=2 * p.lcl.C1)),
                            2 * math.pi * 1000, (0.4, 0.4, 0.5, 0.5))
    eig = np.sort(np.abs(np.linalg.eigvals(lo.Theta)))
    np.testing.assert_allclose(eig, [0.4, 0.4, 0.5, 0.5], atol=1e-6)


# ------------------------------------------------------------- Fig. 4 -----

def _fig4_ratio(d: np.ndarray) -> float:
    return y.compensation_errors(y.periodic_part(d, 12))[0]


def test_fig4_ratio_rejects_a_pure_2fe_tone(claims):
    """The criterion rejects what the old one (>= 1) passed: a pure 2 f_e
    tone gives exactly 1, and so does a 2 f_e tone under white noise of
    the simulated disturbance's power (the synchronous average removes the
    noise, which alone would give sqrt 3 on the raw signal); a 3 f_e line of
    the size the simulation has (equal to the 2 f_e one or more) passes."""
    c = claims["yao2022.fig4.comp_error_ratio_18_over_17"]
    assert c.check == "min" and c.tolerance == 1.1 and c.passed
    k = np.arange(4000)
    tone2 = np.exp(2j * np.pi * 2 * k / 12)
    assert _fig4_ratio(tone2) == pytest.approx(1.0, abs=1e-12)
    rng = np.random.default_rng(0)
    noise = (rng.standard_normal(k.size) + 1j * rng.standard_normal(k.size)) / math.sqrt(2)
    noisy = tone2 + noise
    raw = np.sqrt(np.mean(np.abs(np.diff(noisy, 2)) ** 2) / np.mean(np.abs(np.diff(noisy)) ** 2))
    assert raw > 1.1  # the raw ratio would pass a 2 f_e tone in noise
    assert _fig4_ratio(noisy) < 1.02
    for made in (tone2, noisy):
        assert not y.claim("yao2022.fig4.comp_error_ratio_18_over_17", _fig4_ratio(made),
                           gain_2fe=1.0, gain_3fe=1.414, periods=333, n_per=12, a1=0.0,
                           a2=1.0, a3=0.0, a6=0.0, e17_over_d=1.0, raw=raw).passed
    tone3 = np.exp(-2j * np.pi * 3 * k / 12)
    assert _fig4_ratio(tone3) == pytest.approx(math.sqrt(2), abs=1e-12)
    assert _fig4_ratio(tone2 + 0.4 * tone3) > 1.1 > _fig4_ratio(tone2 + 0.3 * tone3)


def test_fig4_lines():
    """line_amplitudes reads the +h and -h f_e lines of one period."""
    k = np.arange(12)
    p = 0.3 * np.exp(2j * np.pi * 2 * k / 12) + 0.4 * np.exp(-2j * np.pi * 3 * k / 12) + 0.1 * (
        -1.0) ** k
    a = y.line_amplitudes(p)
    assert a[2] == pytest.approx(0.3) and a[3] == pytest.approx(0.4)
    assert a[6] == pytest.approx(0.1) and a[1] == pytest.approx(0.0, abs=1e-15)


# ------------------------------------------------------------ Fig. 10 -----

def test_fig10_paper_tolerance_rejects_a_zero_error_observer(claims):
    """Against the paper: |mean reading over the seeds| within 2 mrad (the
    paper's 0.01 A readings) + 3 sigma of one reading over the seeds; the
    rotation a sensor-gain mismatch gives a reading (5.77 mrad per 1 %) is
    stated apart, not in the tolerance. A zero-error observer (reading 0)
    fails at every speed; with the old tolerance (2 mrad + 3 sigma of the
    batch means + 5.77 mrad: 0.011 rad at 60 kr/min) it passed the paper's
    0.008. The method claim keeps its 2 mrad + 3 sigma around the true
    error minus our rotation, so a reading off by the paper's 0.016 rad at
    30 kr/min fails it. Kinds: the method check apart from the two
    comparisons with the paper's numbers."""
    rot = abs(metrics.scaling_rotation((1.01, 0.99, 1.0)))
    for t in ("30k", "60k", "100k"):
        method = claims[f"yao2022.fig10.injection_vs_true_rad_{t}"]
        paper = claims[f"yao2022.fig10.pos_error_vs_paper_rad_{t}"]
        assert (method.kind, paper.kind) == ("method", "paper")
        assert claims[f"yao2022.fig9.true_pos_error_rad_{t}"].kind == "paper"
        sigma = float(re.search(r"3 sigma = 3 x ([0-9.]+) rad", paper.basis).group(1))
        assert paper.tolerance == pytest.approx(0.002 + 3 * sigma, abs=2e-4)
        assert paper.paper == {"30k": 0.018, "60k": 0.008, "100k": 0.024}[t]
        assert paper.tolerance < paper.paper
        assert not dataclasses.replace(paper, reproduced=0.0, statement="").passed
        assert f"{rot * 1e3:.2f} mrad per 1 %" in paper.statement
        old_tol = method.tolerance + rot  # 2 mrad + 3 sigma (batch means) + rotation
        if t == "60k":
            assert abs(0.0 - paper.paper) <= old_tol  # the zero-error observer passed
    c30 = claims["yao2022.fig10.injection_vs_true_rad_30k"]
    assert abs(c30.expected - 0.018) > c30.tolerance and abs(-0.018 - c30.expected) > c30.tolerance


def test_fig10_dead_time_gives_the_papers_low_speed_readings():
    """The reason the 30 and 60 kr/min claims state: with FIG10_T_DEAD = 35
    ns of uncompensated dead time the reading of (60) is the paper's 0.018
    rad at 30 kr/min (fitted, within 1 mrad) and its 0.008 at 60 kr/min
    within that claim's tolerance; before the injection the true error
    stays within 1 mrad at both speeds, during it it is turned by more than
    2 mrad (12.9 at 30 kr/min): the injection makes the reading. Without
    the dead time the same drive reads 0.002-0.003 rad."""
    assert y.FIG10_T_DEAD == 35e-9
    for n, paper, tol in ((30e3, 0.018, 0.001), (60e3, 0.008, None)):
        got = y.injection_reading(simulate(y.fig10_scenario(n, y.FIG10_T_DEAD)), y.INJ_T,
                                  y.INJ_W)
        if tol is None:
            tol = next(c for c in paper_claims()
                       if c.id == "yao2022.fig10.pos_error_vs_paper_rad_60k").tolerance
        assert abs(abs(got["inj"]) - paper) <= tol, (n, got)
        assert abs(got["before"]) < 0.001 and abs(got["during"] - got["before"]) > 0.002
        plain = y.injection_reading(simulate(y.fig10_scenario(n)), y.INJ_T, y.INJ_W)
        assert 0.0015 < abs(plain["inj"]) < 0.0035


# ------------------------------------------------------------ Fig. 23 -----

def test_fig23_stable_apart_from_the_bias(claims):
    """Stable is no fault, the speed within 1 % and the angle within pi/2:
    the nominal drive (exact capacitance) passes, the sliding-mode observer
    designed with half the capacitance loses the rotor and fails. An
    estimate turned by 0.3 rad is still stable (the old criterion, 0.1 rad,
    called any bias instability); the bias claim rejects it instead, and
    rejects the plausible wrong observer that ignores the capacitance error
    (the exact-capacitance run, -0.003 rad, against the 0.104 predicted)."""
    c = claims["yao2022.fig23.smo_bias_rad"]
    assert claims["yao2022.fig23.smo_stable"].passed and c.passed
    s = y.fig23_scenario("smo")
    nominal = simulate(s.with_controller(C1_hat_ratio=1.0))
    ok, _, err = y._stable(nominal)
    assert ok == 1 and err < 0.02
    half = simulate(s.with_controller(C1_hat_ratio=0.5))
    assert y._stable(half)[0] == 0
    turned = dataclasses.replace(nominal, data=nominal.data.copy())
    turned.data[:, CHANNELS.index("theta_hat")] += 0.3
    ok, _, err = y._stable(turned)
    assert ok == 1 and 0.25 < err < 0.5
    for wrong in (y.mean_angle_error(turned), y.mean_angle_error(nominal)):
        assert not dataclasses.replace(c, reproduced=wrong, statement="").passed
    assert abs(y.mean_angle_error(nominal)) < 0.005


def test_fig23_bias_follows_the_fixed_point_of_eq_52_58(claims):
    """The bias is the observer's own steady state under the model error:
    the DC fixed point is exactly zero with the exact capacitance, 0.104 rad
    with 2 C, and larger, 0.136 rad, with 1.5 C, where the simulated drive
    follows it within the claim's tolerance too (the reason the 1.5 C bias
    exceeds the 2 C one)."""
    c = claims["yao2022.fig23.smo_bias_rad"]
    s = y.fig23_scenario("smo")
    assert abs(y.capacitance_bias(s.with_controller(C1_hat_ratio=1.0))) < 1e-9
    assert c.expected == pytest.approx(0.104, abs=0.001)
    s15 = s.with_controller(C1_hat_ratio=1.5)
    pred15 = y.capacitance_bias(s15)
    assert pred15 == pytest.approx(0.136, abs=0.001) and pred15 > c.expected
    assert abs(y.mean_angle_error(simulate(s15)) - pred15) <= c.tolerance


def test_fig23_linear_observer_with_half_the_capacitance():
    """The linear observer's reason: with half the real capacitance it too
    stays stable, biased by about 2 mrad."""
    s = y.fig23_scenario("linear").with_controller(C1_hat_ratio=0.5)
    r = simulate(s)
    ok, dn, err = y._stable(r)
    m = r.window(0.2, 0.4)
    assert ok == 1 and abs(np.mean(r.theta_error[m])) < 0.003


# ------------------------------------------------------------ Table V -----

def test_table5_needs_more_angle_ripple_than_eq47_can_give():
    """docs/errata.md: from the position error of (47) to the PLL's speed
    (48), gains (50), the gain is 10.49 rad/s per rad at 2 f_e and 7.43 at
    3 f_e at 100 kr/min (transfer function, and the firmware PLL's impulse
    response); +-1100 r/min then needs an angle-error ripple of 11.0 or
    15.5 rad, where (47) gives at most pi/2."""
    import ctypes as ct

    from smodrive.engine import _ffi

    pll = dz.PllPars()
    n = 400_000
    f = _ffi.lib.smd_pll_impulse
    f.restype = ct.c_int
    f.argtypes = [ct.c_double] * 5 + [ct.c_long, ct.POINTER(ct.c_double)]
    h = np.zeros(n)
    assert f(pll.T, pll.k_theta, pll.k_omega, pll.k_a, 1e-3, n,
             h.ctypes.data_as(ct.POINTER(ct.c_double))) == 0
    k = np.arange(1, n + 1)
    for harm, gain, need in ((2, 10.49, 11.0), (3, 7.43, 15.5)):
        fr = harm * 100e3 / 60
        z = np.exp(2j * np.pi * fr * pll.T)
        g_tf = y.pll_speed_gain(pll, fr)
        T_c = np.sum(h * np.exp(-2j * np.pi * fr * pll.T * k))  # closed loop, C PLL
        g_c = abs(pll.k_omega / (z - 1) + pll.k_a * pll.T / (z - 1) ** 2) * abs(1 - T_c)
        assert g_tf == pytest.approx(gain, abs=0.005)
        assert g_c == pytest.approx(g_tf, rel=1e-6)
        assert 1100 * y.RPM / g_tf == pytest.approx(need, abs=0.05)
        assert 1100 * y.RPM / g_tf > 2 * math.pi  # beyond any angle, let alone pi/2


def test_table5_ripple_ratio_is_set_by_the_adc_noise(claims):
    """The reason the ripple-ratio claim states, measured: at 100 kr/min the
    PLL's estimation error n_hat - n is the same with either law (RMS within
    15 %). Removing the ADC noise and quantisation (gains kept) brings
    the ratio within the claim's tolerance of the paper's 0.545 (0.66);
    removing the noise alone, quantisation kept, does not (0.79): both are
    the cause."""
    c = claims["yao2022.table5.ripple_reduction_100k"]
    assert not c.passed
    parts = {law: y.ripple_parts(simulate(y.steady(100e3, law))) for law in y.LAWS}
    e_b, e_p = parts["tde17"]["err_rms"], parts["proposed"]["err_rms"]
    assert abs(e_p / e_b - 1) < 0.15
    assert c.reproduced == pytest.approx(parts["proposed"]["ripple"] / parts["tde17"]["ripple"])

    def ratio(adc):
        rip = {law: y.speed_ripple(simulate(y.steady(100e3, law).replace(adc=adc)))
               for law in y.LAWS}
        return rip["proposed"] / rip["tde17"]

    quiet = ratio(GAINS_ONLY)
    assert abs(quiet - c.paper) <= c.tolerance
    assert f"the ratio to {quiet:.2f}" in c.statement
    quantised = ratio(dataclasses.replace(y.ADC, noise=0.0))
    assert abs(quantised - c.paper) > c.tolerance


def test_table6_without_the_target_toolchain_is_not_measured(monkeypatch):
    """Without the cross compiler or the emulator the Table VI claims are
    'not measured' with the reason, never a failing NaN (issue 13.2)."""
    from smodrive import firmware as target

    def no_toolchain(*_a, **_k):
        raise target.TargetError("arm-none-eabi-gcc not found")

    monkeypatch.setattr(target, "table6_cycles", no_toolchain)
    exp = next(e for e in y.EXPERIMENTS if e.id == "yao2022.table6")
    claims = exp.run(lambda name, frac: None).claims
    assert len(claims) == 1
    for c in claims:
        assert c.status == "not measured", c.id
        assert "arm-none-eabi-gcc not found" in c.statement


def test_table6_names_a_failed_build_by_its_first_error_in_one_line(monkeypatch):
    """A firmware build that fails (a core that does not compile for the
    M4F) leaves the Table VI claim 'not measured' with the first compiler
    error as its reason, in one line: not the compiler's whole output (up to
    3,000 characters) in the claim's statement and the report's table."""
    import importlib

    from smodrive import firmware as target

    fb = importlib.import_module("smodrive.firmware.build")  # (the module, not its function)
    stderr = ("In file included from core/src/smd_drive.c:1:\n"
              "core/src/smd_drive.c:1210:19: error: 'x.ej_half.im' may be used uninitialized\n"
              + "  | context line of the compiler's report\n" * 80)

    Failed = type("Failed", (), {"returncode": 1, "stderr": stderr})

    monkeypatch.setattr(fb.subprocess, "run", lambda *a, **k: Failed())
    monkeypatch.setattr(fb, "_cache_dir", lambda: Path(tempfile.mkdtemp()))
    with pytest.raises(target.TargetError) as err:
        fb.build("m4", "fast")
    first = str(err.value).splitlines()[0]
    assert "error: 'x.ej_half.im' may be used uninitialized" in first

    def build_fails(*_a, **_k):
        raise err.value

    monkeypatch.setattr(target, "table6_cycles", build_fails)
    exp = next(e for e in y.EXPERIMENTS if e.id == "yao2022.table6")
    (c,) = exp.run(lambda name, frac: None).claims
    assert c.status == "not measured"
    assert "\n" not in c.statement and "context line" not in c.statement
    assert "may be used uninitialized" in c.statement
    reason = c.statement.split("NOT MEASURED: ", 1)[1]
    assert reason.startswith("building the m4 runner failed: ") and len(reason) <= 240


def test_table6_judges_the_worst_call_against_the_period(claims, monkeypatch):
    """Table VI is judged as 'fits the 50 us period, worst call': the
    parts' worst calls at the pessimistic end of the timing range, summed,
    within 8,400 cycles (168 MHz); the paper's C28x counts are shown, not
    judged. The measure is the worst, not the mean: it exceeds the mean
    nominal count. The old criterion (4 x the paper's count per part)
    failed the reaching law and the PLL of this step, which fits; a step
    three times as costly (a stand-in for, e.g., a core without the FPU,
    which costs ten times) fails the new one."""
    from smodrive import firmware as target

    c = claims["yao2022.table6.cycles_worst_call"]
    assert c.passed and c.tolerance == target.BUDGET["yao2022"] == 8400
    assert c.paper == 785.0 and c.kind == "paper"
    rows, _ = target.table6_cycles(y.lcl_observer_tables(y.steady(100e3)), "fast")
    worst = y.table6_worst(rows)
    assert c.reproduced == pytest.approx(worst["step"], rel=1e-9)
    # the exact build beside it: slower (the exact sines), and the flash's
    # stalls on top of the nominal worst calls
    exact, _ = target.table6_cycles(y.lcl_observer_tables(y.steady(100e3)), "fmath")
    assert "exact build" in c.statement
    assert y.table6_worst(exact)["step"] > c.reproduced
    assert sum(r.worst_flash() for r in rows.values()) > sum(r.worst for r in rows.values())
    high, nominal = (sum(getattr(r, k) for r in rows.values()) for k in ("high", "nominal"))
    assert worst["step"] > high > nominal
    old = {part: r.nominal <= 4 * target.TABLE6_PAPER[part] for part, r in rows.items()}
    assert old == {"prediction": True, "reaching_law": False, "pll": False}

    def tripled(*a, **k):
        return ({part: dataclasses.replace(r, nominal=3 * r.nominal, low=3 * r.low,
                                           high=3 * r.high, worst=3 * r.worst)
                 for part, r in rows.items()}, {})

    monkeypatch.setattr(target, "table6_cycles", tripled)
    exp = next(e for e in y.EXPERIMENTS if e.id == "yao2022.table6")
    (bad,) = exp.run(lambda name, frac: None).claims
    assert not bad.passed and bad.reproduced == pytest.approx(3 * c.reproduced)
