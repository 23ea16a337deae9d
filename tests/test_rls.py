"""The online R_s / psi_r tracker (issue 23; core/include/smodrive/smd_rls.h):
recursive least squares with forgetting on the stator equation, excited by
a d-axis square wave of +-rls_i_inj.

Issue 23's criterion: a +40 % rise of R_s (winding heating) tracked within
2 % in under 2 s. The plant's R_s ramps from 1 to 1.4 times its value over
[1.0, 1.5] s (R_s_scale); the tracker's estimate must be within 2 % of the
true value before the ramp and from 2 s after the ramp began (t >= 3 s) to
the end (4 s), and psi_r within 2 % throughout, on 10 draws a motor of the
issue's conditions: current-sensor gains within +-0.5 %, offsets within
+-0.2 % of full scale, a dead time of 0.5-2 us with zero-current clamping,
the 12-bit ADC's noise. The drive's dead-time compensation is what
commissioning measured (step 1's drop, RsResult.t_dead): a drive that
compensates a dead time it does not have leaves a voltage along the
current that the d-axis fit cannot tell from a resistance (u_0 / |i| per
ohm: 13 % of R_s on the 600 V motor for a 1 us error). The operating point:
half rated speed and torque, position from the encoder (yang2018's robust
DBPC with its sensor), the square wave at 40 % of rated current.

The drive reads three current sensors (AdcCfg.sensors = 3). With two, the
sensors' unequal gains turn the measured current by phi = -(g_b - g_a) /
(2 sqrt 3) (smd_abc_to_ab2's note), and the stator equation's w L_s i term,
taken from the turned current, leaves phi w L_s i_d on the d axis: R_s off by
phi w L_s / R_s, which no fit at one speed can tell from a resistance. On
the 600 V motor at half speed w L_s / R_s = 9.4, and the draws' 0.8 % of
mismatch took R_s 2.2 % off (test_two_sensors_turn_the_current_into_R_s
checks the prediction); with three sensors the gains' mean is a real
factor, within 0.5 %.

"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from issue23_draws import sensor_errors

from smodrive.commission import identify_rs
from smodrive.engine import fault_names, simulate
from smodrive.model import LoadCfg, ParameterError, Profile
from smodrive.scenario_io import load_scenario

ROOT = Path(__file__).resolve().parents[1]
MOTORS = {"yang2018 Table I": ROOT / "scenarios/motors/yang2018_table1.toml",
          "servo 48 V 200 W": ROOT / "scenarios/motors/servo_48v_200w.toml",
          "industrial 600 V 10 kW": ROOT / "scenarios/motors/industrial_600v_10kw.toml",
          # invented (tests/motors): 10 pole pairs at 36 V
          "hub 36 V 350 W (invented)": ROOT / "tests/motors/hub_36v_350w.toml",
          # invented: identified at its own 50 us, tracked at 100 us
          "fan 48 V 300 W (invented)": ROOT / "tests/motors/fan_48v_300w.toml"}
RISE = 1.4
TOL = 0.02


def tracked(s0, seed: int, rng, i_inj_rel: float = 0.4, sensors: int = 3, gains_only=False,
            duration: float = 4.0, speed: float = 0.5, stale_ok: bool = False,
            T_sp: float = 100e-6, position: str = "encoder", **ctl):
    """One draw of the issue's conditions on motor scenario `s0` (or, with
    `gains_only`, of its sensor gains alone), the drive's dead-time
    compensation from commissioning's step 1; the run's times, R_s and psi_r
    estimates, and the scenario."""
    m = s0.motor
    plant = sensor_errors(s0, seed, rng, sensors)
    if gains_only:
        plant = plant.replace(adc=dataclasses.replace(plant.adc, offset=(0.0,) * 3),
                              inverter=dataclasses.replace(plant.inverter, t_dead=0.0))
    rs = identify_rs(plant)
    assert rs.ok, rs
    s = plant.replace(T_sp=T_sp, duration=duration, log_stride=10, warm_start=True,
                      w_M0=speed * m.w_M_N, w_M_ref=Profile((0.0,), (speed * m.w_M_N,)),
                      R_s_scale=Profile((0.0, 1.0, 1.5), (1.0, 1.0, RISE)),
                      load=LoadCfg(T_ext=Profile((0.0,), (0.5 * m.T_N,))))
    s = s.with_controller(current="robust_dbpc", position=position, start="handover",
                          t_dead_comp=min(rs.t_dead(), 0.25 * s.T_sp),
                          rls_i_inj=i_inj_rel * m.T_N / m.k_t, **ctl)
    r = simulate(s)
    assert r.status == 0 and (stale_ok or r.faults.t_first is None), fault_names(r.faults.first)
    return r["t"], r["R_s_rls"], r["psi_r_rls"], s


@pytest.mark.parametrize("name", list(MOTORS))
def test_a_40_percent_rise_of_R_s_within_2_percent_in_under_2_s(name):
    s0 = load_scenario(MOTORS[name])
    m = s0.motor
    rng = np.random.default_rng(2026)
    tol = TOL
    for seed in range(1, 11):
        t, R, psi, _ = tracked(s0, seed, rng)
        before = (t >= 0.8) & (t < 1.0)
        after = t >= 3.0
        assert np.all(np.abs(R[before] / m.R_s - 1.0) <= tol), (seed, R[before][-1])
        assert np.all(np.abs(R[after] / (RISE * m.R_s) - 1.0) <= tol), (seed, R[after].min(),
                                                                        R[after].max())
        assert np.all(np.abs(psi[t >= 0.8] / m.psi_r - 1.0) <= TOL), seed


def test_the_micro_motor_at_its_own_40_khz():
    """The micro motor (1 ohm, 50 uH, 2 mWb; tests/test_commission.py) at
    its own 25 us, where issue 23's 0.5-2 us of dead time is 2-8 % of the
    period. The dead time moves each pulse's centre by t_dc / 2 from where
    the current is sampled, and the d-axis line's slope is R_s (1 - R_s t_dc
    / (2 L_s)), as commissioning's step 1 measured it: 1.0-1.9 % low here
    before the rise, 1.4-2.6 % after, and the tracker read 3.0-4.0 % low
    after the rise (before 2026-11-27; 1e-4 on Table I's motor). The
    tracker now divides the slope by that factor with the dead time the
    drive compensates (smd_rls_set_dead_time): 10 draws within 2 % before
    and from 2 s after the rise began (measured 0.82 % and 1.82 %, within 2 %
    after at most 1.69 s). psi_r, fitted with the slope (the q axis's
    currents are sampled as the d axis's), reads 2.4-3.3 % high, outside
    the 2 % the other motors meet: bounded here at 4 % (docs/commissioning.md)."""
    from test_commission import CASES

    s0 = CASES["micro 1 ohm, 50 uH (invented)"]
    m = s0.motor
    rng = np.random.default_rng(2026)
    for seed in range(1, 11):
        t, R, psi, _ = tracked(s0, seed, rng, T_sp=s0.T_sp)
        before = (t >= 0.8) & (t < 1.0)
        after = t >= 3.0
        assert np.all(np.abs(R[before] / m.R_s - 1.0) <= TOL), (seed, R[before][-1])
        assert np.all(np.abs(R[after] / (RISE * m.R_s) - 1.0) <= TOL), (seed, R[after].min())
        assert np.all(np.abs(psi[t >= 0.8] / m.psi_r - 1.0) <= 0.04), seed


def test_the_micro_motor_without_a_position_sensor():
    """The micro motor at its own 25 us with the SMDO's angle. Its SMDO is
    designed at the edge of its error loop (l + lambda_min / rho = 1.2 R_s /
    L_s_hat, docs/design_from_motor.md): fed the tracker's R_s, 40 % above
    the design's, the loop was slower than the stator's pole and the angle
    turned 36 deg after the rise, at status 0 (2026-11-28). The drive feeds
    the SMDO an R_s only as far as that loop stays 1.2 times faster
    (smd_drive.c; here not at all), and the tracker's frame alone keeps R_s
    (measured within 0.92 % over the 10 draws, the square wave derived 20
    ms long) and the angle (0.2 deg off on average after the rise). psi_r,
    as with the encoder (test_the_micro_motor_at_its_own_40_khz), reads 1.7-
    2.6 % off: bounded at 4 %."""
    from test_commission import CASES

    s0 = CASES["micro 1 ohm, 50 uH (invented)"]
    m = s0.motor
    rng = np.random.default_rng(2026)
    for seed in range(1, 11):
        t, R, psi, s = tracked(s0, seed, rng, T_sp=s0.T_sp, position="smdo_emf")
        before = (t >= 0.8) & (t < 1.0)
        after = t >= 3.0
        assert np.all(np.abs(R[before] / m.R_s - 1.0) <= TOL), (seed, R[before].min())
        assert np.all(np.abs(R[after] / (RISE * m.R_s) - 1.0) <= TOL), (seed, R[after].min())
        assert np.all(np.abs(psi[t >= 0.8] / m.psi_r - 1.0) <= 0.04), seed
        if seed == 1:
            r = simulate(s)
            err = np.angle(np.exp(1j * (r["theta_hat"] - r["theta_r"])))
            assert abs(np.degrees(np.mean(err[r["t"] >= 2.0]))) < 3.0


def test_without_its_square_wave_R_s_is_not_tracked():
    """The excitation is what separates R_s from psi_r: a tracker whose
    square wave is lost in the noise keeps its initial R_s through the rise
    (off by the whole 40 %), where the working one is within 2 % (the test
    above). A fit that did not check its standard error returned -3 ohm
    here: R_s from the noise. The drive says so: the warning rls_stale from
    2 rls_tau (0.6 s) on, while the estimate is not taken (before
    2026-11-27 it ran on at status 0 with no warning, 40 % off: the worst
    kind of run). The working tracker of the tests above raises no fault or
    warning at all (tracked() checks it)."""
    s0 = load_scenario(MOTORS["yang2018 Table I"])
    t, R, _, s = tracked(s0, 1, np.random.default_rng(1), i_inj_rel=1e-4, stale_ok=True)
    assert R[-1] == pytest.approx(s0.controller.R_s_hat or s0.motor.R_s, rel=1e-6)
    assert abs(R[-1] / (RISE * s0.motor.R_s) - 1.0) > 0.25
    r = simulate(s)
    assert r.status == 0 and fault_names(r.faults.first) == ["rls_stale"]
    assert r.faults.t_first == pytest.approx(2.0 * s.controller.rls_tau, abs=2 * s.T_sp)
    assert "rls_stale" in fault_names(r.faults.final)


@pytest.mark.parametrize("sensors", [2, 3])
def test_two_sensors_turn_the_current_into_R_s(sensors):
    """The sensors' gains alone (no offset, no dead time), the 600 V motor
    at 0.9 of rated speed, where w L_s / R_s = 17: with two sensors the
    measured current is turned by phi = -(g_b - g_a) / (2 sqrt 3) and scaled by
    1 + g_a + (g_b - g_a) / 2, so R_s reads (1 + phi w L_s / R_s) / (1 + g_a +
    (g_b - g_a) / 2) of itself (the module's note); with three, 1 / (1 + mean
    g). Each of 10 draws' mean over the last 0.2 s within 0.5 % of its
    prediction: the bias is what is predicted; the noise left in a 0.2 s
    mean of the forgetting's 0.3 s fit is a few 0.1 % (measured: 0.13 % at
    worst with three sensors, 0.41 % with two, whose reconstructed phase c
    carries the noise of both readings; no gain error is left out of the
    predictions, the rest is the discretisation of the tracker's model).
    The draws' predictions with two sensors range over -4 % .. +1.7 %: a
    tracker that did not read the turn (predicted 0 turn) misses by up to
    3.9 %, and three sensors read as two by up to 4 %."""
    s0 = load_scenario(MOTORS["industrial 600 V 10 kW"])
    m = s0.motor
    rng = np.random.default_rng(2026)
    for seed in range(1, 11):
        t, R, _, s = tracked(s0, seed, rng, sensors=sensors, gains_only=True, duration=1.0,
                             speed=0.9)
        g = np.array(s.adc.gain) - 1.0
        if sensors == 2:
            phi = -(g[1] - g[0]) / (2.0 * np.sqrt(3.0))
            w = 0.9 * m.w_M_N * m.n_p
            pred = (1.0 + phi * w * m.L_s / m.R_s) / (1.0 + g[0] + (g[1] - g[0]) / 2.0)
        else:
            pred = 1.0 / (1.0 + g.mean())
        got = np.mean(R[t >= 0.8]) / m.R_s
        assert got == pytest.approx(pred, abs=0.005), seed


def test_the_plants_resistance_follows_its_profile():
    """R_s_scale changes the plant's R_s (winding heating): at standstill
    with a constant voltage the current settles at u / R_s, so doubling R_s
    halves it (the time constant L/R = 10 ms, 0.3 s is 30 of them)."""
    s0 = load_scenario(MOTORS["yang2018 Table I"])
    s0 = s0.replace(inverter=dataclasses.replace(s0.inverter, t_dead=0.0))
    s = s0.replace(duration=0.6, T_sp=100e-6, warm_start=False, log_stride=1,
                   R_s_scale=Profile((0.0, 0.3, 0.3), (1.0, 1.0, 2.0)),
                   i_d_ref=Profile((0.0,), (2.0,)))
    s = s.with_controller(current="robust_dbpc", position="encoder", start="handover",
                          speed_loop=False, t_dead_comp=0.0)
    r = simulate(s)
    t, i_d = r["t"], r["i_d"]
    # the current loop holds i_d = 2 A either way: the voltage doubles instead (the rotor
    # at theta = 0 stays there without i_q: d is alpha; the mean over 0.05 s, 500 samples,
    # of a deadbeat loop's voltage, which chases the ADC noise sample by sample)
    assert np.max(np.abs(r["theta_r"])) < 0.01
    u = r["u_alpha"]
    assert np.mean(i_d[(t > 0.25) & (t < 0.3)]) == pytest.approx(2.0, rel=0.01)
    ratio = np.mean(u[t > 0.55]) / np.mean(u[(t > 0.25) & (t < 0.3)])
    assert ratio == pytest.approx(2.0, rel=0.03)


@pytest.mark.parametrize("field,value,why", [
    ("rls_tau", 1e-5, "rls_tau"),
    ("rls_t_half", 1e-5, "rls_t_half"),
])
def test_a_bad_tracker_setting_is_named(field, value, why):
    s0 = load_scenario(MOTORS["yang2018 Table I"])
    s = s0.with_controller(rls_i_inj=1.0, **{field: value})
    with pytest.raises(ParameterError, match=why):
        simulate(s.replace(duration=0.01))


@pytest.mark.parametrize("name", list(MOTORS))
def test_without_a_position_sensor_a_40_percent_rise_within_2_percent_in_under_2_s(name):
    """The same criterion with the SMDO's angle (position = 'smdo_emf').
    Fitted in the SMDO's own frame, the tracker read the SMDO's model R_s: a
    resistance dR above it turns the SMDO's angle by about dR i_d / (w
    psi_r), the d axis's EMF then cancels dR i_d, and a +40 % rise ended 30 %
    low at status 0 (Table I's motor; before 2026-11-28 the tracker was
    refused without an encoder). The tracker now fits in the line through
    the angle's means over whole periods of its square wave (which the
    wave's periodic effect on the angle does not move), with the injection
    as the instrument, leaving out the intervals near a phase current's zero
    crossing (the dead-time compensation's residual: +5 % on the 600 V
    motor at 5 ms halves), and the SMDO and the robust DBPC take its R_s
    (without it the hub motor lost its rotor after the rise). The square
    wave is derived pi / (5 speed_bw) long (at 20 ms the 48 V servo's speed
    loop turned it into torque, and R_s ran 57 % off)."""
    s0 = load_scenario(MOTORS[name])
    m = s0.motor
    rng = np.random.default_rng(2026)
    for seed in range(1, 11):
        t, R, psi, _ = tracked(s0, seed, rng, position="smdo_emf")
        before = (t >= 0.8) & (t < 1.0)
        after = t >= 3.0
        assert np.all(np.abs(R[before] / m.R_s - 1.0) <= TOL), (seed, R[before].min(),
                                                               R[before].max())
        assert np.all(np.abs(R[after] / (RISE * m.R_s) - 1.0) <= TOL), (seed, R[after].min(),
                                                                        R[after].max())
        assert np.all(np.abs(psi[t >= 0.8] / m.psi_r - 1.0) <= TOL), seed


def test_the_usual_profile_with_the_tracker_raises_no_warning():
    """The 48 V servo without its sensor through the usual profile (start
    on I/f, steps, load, reversal) with the tracker on: its square wave,
    derived 2.1 ms a half, steps the current by 2 rls_i_inj 240 times a
    second, which the ripple measure read as an oscillation (the warning
    from 1.3 s on, before 2026-11-28); the drive now leaves the wave's
    first SMD_RLS_SKIP samples after each edge out of it. The run reaches
    its end with no fault or warning at all, the tracker's R_s within 2 %."""
    from smodrive.scenarios.trials import judge, profile_scenario

    s0 = load_scenario(MOTORS["servo 48 V 200 W"])
    m = s0.motor
    s = profile_scenario(s0).with_controller(rls_i_inj=0.4 * m.T_N / m.k_t)
    r = simulate(s)
    o = judge(r)
    assert o.verdict == "reached", str(o)
    assert r.faults.t_first is None, fault_names(r.faults.first)
    assert abs(r["R_s_rls"][-1] / m.R_s - 1.0) <= TOL


def test_the_tracker_behind_an_lcl_filter_is_refused():
    """The tracker's model (yang2018 eq. (1)) has no filter: behind yao2022's
    LCL filter it is refused by name, with any position source."""
    from smodrive.scenarios import yao2022

    for pos in ("encoder", "lcl_smo_pll"):
        s = yao2022.steady(60e3).with_controller(position=pos, rls_i_inj=1.0)
        with pytest.raises(ParameterError, match="rls_i_inj"):
            simulate(s.replace(duration=0.01))


def test_a_bad_heating_profile_is_named():
    s0 = load_scenario(MOTORS["yang2018 Table I"])
    with pytest.raises(ParameterError, match="R_s_scale"):
        s0.replace(R_s_scale=Profile((0.0,), (-1.0,)))
