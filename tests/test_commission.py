"""Commissioning, step 1 (issue 23): the core's R_s test against the plant,
which the test does not see (it gets the ADC's currents and the DC-link
voltage).

The criterion: R_s within 2 % (issue 23) over 10 ADC noise seeds on every
motor below, and the inverter's drop u_0 within 3 % of what the plant's dead
time gives, 4/3 t_d / T_sp u_dc (with the sign model the drop is t_d / T_sp
u_dc per leg against the current's direction; along alpha phase a carries i
and phases b and c -i/2: (2/3)(1 + 1/2 + 1/2) = 4/3). A test that fitted
u = R i through the origin (no intercept) would put the drop into R_s: 14.4 V
against 2.25 ohm x 4 A for Table I, several times R_s, which the 2 % rejects
(checked below on the levels the test measured)."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from issue23_draws import sensor_errors

from smodrive._util import tomllib
from smodrive.cli import main
from smodrive.commission import commission, identify_mech, identify_rs, mech_room, mech_scenario
from smodrive.model import ParameterError
from smodrive.scenario_io import load_scenario, scenario_from_dict
from smodrive.scenarios import yao2022
from smodrive.scenarios.catalogue import catalogue

ROOT = Path(__file__).resolve().parents[1]
MOTORS = ROOT / "scenarios" / "motors"


def _motor(s, **kw):
    return s.replace(motor=dataclasses.replace(s.motor, **kw))


def _inverter(s, **kw):
    return s.replace(inverter=dataclasses.replace(s.inverter, **kw))


def _cases():
    yang = load_scenario(MOTORS / "yang2018_table1.toml")
    ind = load_scenario(MOTORS / "industrial_600v_10kw.toml")
    return {
        "yang2018 Table I": yang,
        "servo 48 V 200 W": load_scenario(MOTORS / "servo_48v_200w.toml"),
        "industrial 600 V 10 kW": ind,
        # invented: the ends of issue 23's range, 20 ohm and 20 mohm (the low one with
        # zero-current clamping, as issue 23 asks: the sign model's current chatters about
        # zero at 2 us on 600 V across 0.2 mH, 8 A a sample)
        "20 ohm, 50 mH (invented)": _motor(yang, R_s=20.0, L_s=50e-3),
        "20 mohm, 0.2 mH (invented)": _inverter(_motor(ind, R_s=0.02, L_s=0.2e-3),
                                                dead_time_model="clamp"),
        # issue 23's micro motor, 1 ohm / 50 uH / 2 mWb (L/R = 50 us), on the inverter such a
        # motor has: 12 V, 40 kHz, 0.1 us of dead time (at 10 kHz, with L/R half a sample,
        # the current sampled at the carrier's peak is not the period's mean: R_s +4 %)
        # (rated 12 W at 3000 r/min: its rated point needs 5.7 V of the 6.9 V a 12 V inverter
        # has; 20 W, as first written here, needed 7.8 V and its usual profile ended in
        # speed_tracking at rated load, which the rated-point warning now names)
        "micro 1 ohm, 50 uH (invented)": _inverter(
            _motor(servo := load_scenario(MOTORS / "servo_48v_200w.toml"), R_s=1.0, L_s=50e-6,
                   psi_r=2e-3, P_N=12.0), u_dc=12.0, t_dead=0.1e-6).replace(T_sp=2.5e-5),
    }


CASES = _cases()


@pytest.mark.parametrize("name", list(CASES))
def test_rs_within_2_percent_over_ten_seeds(name):
    s0 = CASES[name]
    u0 = 4.0 / 3.0 * s0.inverter.t_dead / s0.T_sp * s0.inverter.u_dc
    errs, drops = [], []
    for seed in range(1, 11):
        s = s0.replace(adc=dataclasses.replace(s0.adc, seed=seed))
        r = identify_rs(s)
        assert r.ok, (seed, r.outcome)
        errs.append(r.R_s / s.motor.R_s - 1.0)
        drops.append(r.u_0 / u0 - 1.0)
        assert len(r.i_levels) >= 8 and r.t <= 10.0
        # the wrong fit, through the origin, on the same levels
        i, u = np.array(r.i_levels), np.array(r.u_levels)
        r_origin = float(i @ u / (i @ i))
        assert abs(r_origin / s.motor.R_s - 1.0) > 0.02
    assert max(abs(e) for e in errs) < 0.02, errs
    assert max(abs(d) for d in drops) < 0.03, drops


def test_yao2022_motor_the_current_sensors_gain_error_is_the_error():
    """yao2022's motor (23 mohm, behind its LCL filter, no dead time) with the
    scenario's ADC gains 1.01 / 0.99 / 1.00: the test measures along phase a,
    whose 1 % gain error is R_s's error (-1 %: the current reads 1 % high),
    within 2 %; with exact gains the error is below 0.3 %."""
    s = yao2022.steady(30e3)
    r = identify_rs(s)
    assert r.ok and abs(r.R_s / s.motor.R_s - 1.0) < 0.02
    assert r.R_s / s.motor.R_s - 1.0 == pytest.approx(1.0 / 1.01 - 1.0, abs=0.003)
    exact = s.replace(adc=dataclasses.replace(s.adc, gain=(1.0, 1.0, 1.0)))
    r = identify_rs(exact)
    assert r.ok and abs(r.R_s / s.motor.R_s - 1.0) < 0.003


def test_an_open_phase_is_named():
    """No current at any voltage (a winding of 1 kohm on 48 V, i_test 3 A):
    the test ends in no_current at the voltage limit, with no R_s."""
    s = _motor(CASES["servo 48 V 200 W"], R_s=1000.0)
    r = identify_rs(s, i_test=3.0)
    assert r.outcome == "no_current" and not r.ok


def test_a_test_current_beyond_the_motor_or_its_sensors_is_refused_by_name():
    """The 200 W servo (I_N 6.063 A): i_test above the rated current is refused
    naming the range; with current sensors of 8 A, the spin of step 3 (twice
    i_test) must stay within 0.9 of their range: i_test at most 3.6 A, and
    the default (half of I_N, 3.03 A) stays. With 5 A sensors the default
    is above 0.45 x 5 = 2.25 A: the test runs at 2.25 A and says so. (A
    400 V servo with 8 A sensors and the default 9.9 A had driven 1,245 A:
    the clipped reading never reached i_test, the voltage rose to its limit,
    the trip at 1.5 i_test could not see the current, and the outcome blamed
    the motor: no_current.)"""
    s = _motor(CASES["servo 48 V 200 W"])
    with pytest.raises(ParameterError, match=r"i_test = 12.0 A is outside its valid range "
                                             r"\(0, 6.063\] A: at most the rated current"):
        identify_rs(s, i_test=12.0)
    s8 = s.replace(adc=dataclasses.replace(s.adc, full_scale=8.0))
    with pytest.raises(ParameterError, match=r"\(0, 3.6\] A: at most 0.45 adc.full_scale"):
        identify_rs(s8, i_test=4.0)
    s5 = s.replace(adc=dataclasses.replace(s.adc, full_scale=5.0))
    with pytest.warns(UserWarning, match=r"i_test = 2.25 A, not half the rated current"):
        r = identify_rs(s5)
    # (the staircase's top: where the search passed i_test, within the 1.2 i_test it backs off at)
    assert r.ok and 2.25 <= max(r.i_levels) <= 1.2 * 2.25


def test_a_clipped_current_sensor_stops_the_test_named(monkeypatch):
    """The same servo with 2 A sensors and i_test 3 A, the Python bound lifted
    (a firmware that calls the core's test itself): the reading stops at
    2 A while the voltage rises, and the core stops with sensor_range (it
    had searched up to the voltage limit, 27.7 V across 0.25 ohm, and said
    no_current: core/test/test_ident.c measures the true current)."""
    import smodrive.commission as cm
    s = _motor(CASES["servo 48 V 200 W"])
    s2 = s.replace(adc=dataclasses.replace(s.adc, full_scale=2.0))
    monkeypatch.setattr(cm, "i_test_max", lambda s: (math.inf, ""))
    r = identify_rs(s2, i_test=3.0)
    assert r.outcome == "sensor_range" and not r.ok


def test_cli_on_the_lcl_example_writes_its_fan(tmp_path):
    """`identify` on the README's LCL example (yao2022's motor, B = 0, a fan
    load): the true B of 0 is printed as a difference (a relative error of
    it divided by zero: a traceback before), and the fitted fan's K goes to
    [load] k_fan within 20 %."""
    out = tmp_path / "y.toml"
    res = CliRunner().invoke(main, ["identify", str(ROOT / "scenarios" / "lcl_speed_step.toml"),
                                    "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert "the fan's K" in res.output and "0 true (+" in res.output
    data = tomllib.loads(out.read_text())
    assert data["load"]["k_fan"] == pytest.approx(4.9e-10, rel=0.20)
    assert data["motor"]["J"] == pytest.approx(1e-5, rel=0.10)


def test_cli_writes_the_measured_motor(tmp_path):
    out = tmp_path / "m.toml"
    res = CliRunner().invoke(main, ["identify", str(MOTORS / "servo_48v_200w.toml"),
                                    "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert "R_s" in res.output and "true" in res.output
    data = tomllib.loads(out.read_text())
    assert data["motor"]["R_s"] == pytest.approx(0.25, rel=0.02)
    assert data["motor"]["L_s"] == pytest.approx(0.5e-3, rel=0.05)
    assert data["motor"]["psi_r"] == pytest.approx(0.0175, rel=0.02)
    assert data["motor"]["J"] == pytest.approx(4e-5, rel=0.10)
    assert data["motor"]["B"] == pytest.approx(2e-5, rel=0.20)
    assert '#   outcome = "ok"' in out.read_text()
    # the uncertainty: each test's measured accuracy, and R_s's standard error from its line
    # (well below the 2 % budget on a clean staircase: a tenth of it at most)
    assert "R_s +-2 %, L_s +-5 %, psi_r +-2 %, J +-10 %, B +-40 %" in out.read_text()
    # (and the premises of those: the sensors' gain, a free shaft; what running the file does)
    assert "current sensors whose gain is right within 0.5 %" in out.read_text()
    assert "a run of it simulates the measured" in out.read_text()
    # the inertia step 3's spin saw, which step 4's drive is designed for, is printed
    assert "the spin's inertia" in res.output
    se = float(out.read_text().split("R_s_std_error = ")[1].split()[0])
    assert 0.0 < se < 0.002 * 0.25
    # the measured drop sets the dead-time compensation: 3/4 u_0 T_sp / u_dc is the
    # plant's 0.5 us within the drop's 3 % (test 1's criterion)
    assert data["controller"]["t_dead_comp"] == pytest.approx(0.5e-6, rel=0.03)
    # the file is a scenario: `smodrive design` and `smodrive run` take it from there
    m = load_scenario(out).motor
    assert m.R_s == data["motor"]["R_s"] and m.n_p == 4
    res = CliRunner().invoke(main, ["design", str(out)])
    assert res.exit_code == 0 and "0.250" in res.output
    res = CliRunner().invoke(main, ["run", str(out), "--out", str(tmp_path / "run")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "run" / "summary.json").is_file()
    bad = tmp_path / "open.toml"
    bad.write_text((MOTORS / "servo_48v_200w.toml").read_text().replace("R_s = 0.25",
                                                                        "R_s = 1000.0"))
    res = CliRunner().invoke(main, ["identify", str(bad), "--i-test", "3"])
    assert res.exit_code == 1 and "no_current" in res.output
    res = CliRunner().invoke(main, ["identify", str(bad), "--i-test", "-1"])
    assert res.exit_code == 2 and "i_test" in res.output


@pytest.mark.parametrize("name", list(CASES))
def test_inductance_within_5_percent_over_ten_seeds(name):
    """Step 2 after step 1, on the same plant: L_d and L_q each within 5 %
    (issue 23) over 10 ADC seeds, the rotor moved by less than 1 deg
    (electrical) by the q-axis wave, the three tests within 10 s. (The SPMSMs
    here have L_d = L_q = L_s.)"""
    s0 = CASES[name]
    for seed in range(1, 11):
        s = s0.replace(adc=dataclasses.replace(s0.adc, seed=seed))
        c = commission(s)
        assert c.ok, (seed, c.rs.outcome, c.ld and c.ld.outcome, c.lq and c.lq.outcome)
        for x in (c.ld, c.lq):
            assert abs(x.L / s.motor.L_s - 1.0) < 0.05, (seed, x)
            assert x.moved < np.radians(1.0)
        assert abs(c.L_s / s.motor.L_s - 1.0) < 0.05
        assert c.t <= 10.0


def test_inductance_at_three_current_levels():
    """Issue 23 asks for L_s at several current levels: step 2 runs at step
    1's largest level, three quarters and half of it, from the highest down.
    On every motor each level is within 5 % of L_s (the plant does not
    saturate), the result is their swing-squared weighted mean, and the
    three take under 0.9 s an axis (measured 0.25-0.85 s; one level of 400
    periods took 0.21-0.80 s). Upwards, the first level would start
    from step 1's last current, 4 x a quarter level's bias, beyond the
    test's trip of 3 x (the plausible wrong order: it trips at once)."""
    import smodrive.commission as C

    for name, s in CASES.items():
        c = commission(s, mechanics=False)
        assert c.ok, name
        i_max = max(c.rs.i_levels)
        for x in (c.ld, c.lq):
            assert [v.i_bias for v in x.levels] == pytest.approx([i_max, 0.75 * i_max,
                                                                  0.5 * i_max], rel=1e-12)
            for v in x.levels:
                assert v.ok and abs(v.L / s.motor.L_s - 1.0) < 0.05, (name, v)
            w = np.array([v.swing for v in x.levels]) ** 2
            assert x.L == pytest.approx(float(w @ [v.L for v in x.levels]) / w.sum(), rel=1e-12)
            assert x.t == pytest.approx(sum(v.t for v in x.levels), rel=1e-12)
            assert x.t < 0.9, (name, x.t)  # of the sequence's 10 s
    s = CASES["servo 48 V 200 W"]
    eng = C._engine(s)
    rs = C.identify_rs(s, None, eng)
    assert C.identify_ls(s, rs, "d", 0.25 * max(rs.i_levels), eng).outcome == "overcurrent"


PSI_CASES = [n for n in CASES if not n.startswith("20 ohm")]


@pytest.mark.parametrize("name", PSI_CASES)
def test_flux_within_2_percent_over_ten_seeds(name):
    """Step 3 after steps 1 and 2, on the same plant: psi_r from the I/f spin
    at half of rated speed within 2 % (issue 23) over 10 ADC seeds, the
    coasting back EMF and the lower speed within the 5 % the test checks, the
    three steps within 10 s."""
    s0 = CASES[name]
    for seed in range(1, 11):
        s = s0.replace(adc=dataclasses.replace(s0.adc, seed=seed))
        c = commission(s)
        assert c.psi is not None and c.psi.ok, (seed, c.psi)
        assert abs(c.psi.psi / s.motor.psi_r - 1.0) < 0.02, (seed, c.psi)
        assert c.t <= 10.0


def test_flux_a_result_it_gives_is_right_or_named():
    """The invented 20 ohm, 50 mH stator on yang2018's heavy rotor (J = 0.012
    kg m^2): before the spin's stabiliser, 3 seeds of 10 swung at the lower
    speed (psi from it 3.7 % high, the coast 5-6 % off) and the test named
    them (poor_fit); with it, all 10 measured (psi within 0.3 %, the coast
    within 1.2 %). Every result it accepts is within 2 %, none is accepted
    with the coast off by more than 5 %, and at least 9 are accepted."""
    s0 = CASES["20 ohm, 50 mH (invented)"]
    accepted = 0
    for seed in range(1, 11):
        s = s0.replace(adc=dataclasses.replace(s0.adc, seed=seed))
        p = commission(s).psi
        assert p is not None and p.outcome in ("ok", "poor_fit")
        if p.ok:
            accepted += 1
            assert abs(p.psi / s.motor.psi_r - 1.0) < 0.02, (seed, p)
            assert abs(p.psi_coast / p.psi - 1.0) <= 0.05
        else:
            assert abs(p.psi_coast / p.psi - 1.0) > 0.05 or abs(p.psi1 / p.psi - 1.0) > 0.05
    assert accepted >= 9


@pytest.mark.parametrize("motor", ["servo_48v_200w", "industrial_600v_10kw", "yang2018_table1",
                                   "micro 1 ohm, 50 uH (invented)", "yao2022"])
def test_the_drive_designed_from_the_identified_motor(motor):
    """Issue 23: the sensorless drive (robust DBPC + SMDO, I/f start; behind
    yao2022's LCL filter its PI, sliding-mode observer and PLL, I/f start
    and return to it through zero speed) with R_s_hat, L_s_hat and psi_r_hat
    from commissioning, instead of the true values, on the usual profile
    (start, steps, rated load, reversal: smodrive.scenarios.trials): it
    reaches the end, and its RMS angle error over the sensorless phase is
    within 10 % of the drive designed from the true values (measured: within
    2.5 %; yao2022's 1.35 against 1.42 deg)."""
    import warnings

    from smodrive.engine import simulate
    from smodrive.scenarios import trials

    if motor == "yao2022":
        base = catalogue()["yao2022.steady.100k"]()
    else:
        base = CASES[motor] if motor in CASES else load_scenario(MOTORS / f"{motor}.toml")
    c = commission(base)
    assert c.ok and c.psi.ok
    # (the micro motor on its 40 kHz inverter, yao2022's at its 20 kHz; the others at the
    # profile's 10 kHz)
    s = trials.profile_scenario(base, T_sp=base.T_sp if motor in CASES or motor == "yao2022"
                                else 100e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "tuned for another machine": by a few %, here
        runs = [simulate(x) for x in (s, s.with_controller(R_s_hat=c.rs.R_s, L_s_hat=c.L_s,
                                                            psi_r_hat=c.psi.psi))]
    rms = []
    for r in runs:
        assert trials.judge(r).verdict == "reached"
        rms.append(trials.sensorless_angle_rms(r))
    assert abs(rms[1] / rms[0] - 1.0) < 0.10, rms


def test_the_readme_example_designed_from_the_identified_motor():
    """The README's sensorless example (scenarios/sensorless_load_step.toml:
    a brake step and a reversal through I/f): commissioning on the bench (its
    brake profile is the run's, not the bench's), then the run with the
    identified values ends at -600 r/min with no fault, its RMS angle error
    over the whole run within 10 % of the true design's (measured 30.30 vs
    30.19 deg: the I/f phase dominates)."""
    import warnings

    from smodrive.engine import fault_names, simulate

    s = load_scenario(ROOT / "scenarios" / "sensorless_load_step.toml")
    c = commission(s)
    assert c.ok and c.psi.ok
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r0 = simulate(s)
        r1 = simulate(s.with_controller(R_s_hat=c.rs.R_s, L_s_hat=c.L_s, psi_r_hat=c.psi.psi))
    assert not fault_names(r1.faults.final)
    assert r1.n_rpm[-1] == pytest.approx(-600.0, abs=6.0)
    e = [float(np.sqrt(np.mean(r.theta_error[r.t > 0.2] ** 2))) for r in (r0, r1)]
    assert abs(e[1] / e[0] - 1.0) < 0.10, e


def test_a_load_on_the_bench_is_named_not_measured():
    """The same motor with the example's 10 N m brake left on during the
    spin (not on the bench): the rotor stalls, and the test says so
    (slipped: coasting, the rotor does not turn at the frame's speed; before
    the coast's check, poor_fit from the flux at half speed and at a quarter
    disagreeing) instead of giving psi_r 37 x too small."""
    from smodrive import commission as C
    from smodrive.engine.run import Engine

    s = load_scenario(ROOT / "scenarios" / "sensorless_load_step.toml").replace(w_M0=0.0)
    eng = Engine(s)
    rs = C.identify_rs(s, None, eng)
    i_b = 0.5 * max(rs.i_levels)
    ld, lq = C.identify_ls(s, rs, "d", i_b, eng), C.identify_ls(s, rs, "q", i_b, eng)
    p = C.identify_psi(s, rs, 0.5 * (ld.L + lq.L), max(rs.i_levels), eng)
    assert p.outcome == "slipped" and p.psi < 0.1 * s.motor.psi_r


#: every motor (the micro motor's drive starts since its I/f current fits the voltage and
#: its SMDO's error loop is faster than its stator: smodrive.model.derive, issue 23)
MECH_CASES = list(CASES)


@pytest.mark.parametrize("name", MECH_CASES)
def test_inertia_within_10_and_friction_within_20_percent(name):
    """Step 4: the sensorless drive designed from steps 1-3 (and a guessed
    inertia) runs a speed ramp on the bench; J from the torque it makes
    (k_t i_q, k_t from the measured flux) against its estimated speed's
    acceleration, B from the friction at two speeds (least squares over the
    log): J within 10 % and B within 20 % (issue 23), and the whole sequence
    within 10 s of motor time."""
    s = CASES[name]
    c = commission(s)
    assert c.mech is not None and c.mech.ok, c.mech
    assert abs(c.mech.J / s.motor.J - 1.0) < 0.10, c.mech
    assert abs(c.mech.B / s.motor.B - 1.0) < 0.20, c.mech
    assert c.t <= 10.0


def test_b_carries_its_standard_error():
    """Step 4's B with the coast's standard error (the fit quality issue 23
    asks of each result): small where the coast decelerates the rotor well
    (Table I: J / B = 6 s against the 0.4 s coast, measured 1.7 %), large
    where it hardly does (the flywheel with 10 x its inertia, J / B = 250 s:
    measured 58 %, with B +35 %). The two are held to at most 5 % and at
    least 25 %: an error of B that is the coast's noise is seen in it (a
    bias is not: the invented 400 V motor's +31 % has 0.7 %, the plant's dead-time
    model's braking in the coast, test_b_is_right_where_the_plant_clamps_at_zero_current)."""
    s = CASES["yang2018 Table I"]
    c = commission(s)
    assert c.mech.ok and 0.0 < c.mech.B_se < 0.05 * c.mech.B
    f0 = load_scenario(ROOT / "tests" / "motors" / "flywheel_48v_1kw.toml")
    f = f0.replace(motor=dataclasses.replace(f0.motor, J=10.0 * f0.motor.J))
    cf = commission(f, slow=10.0)
    assert cf.mech.ok and cf.mech.B_se > 0.25 * cf.mech.B


def test_b_is_right_where_the_plant_clamps_at_zero_current():
    """Where step 4's B missed by 8-31 % (the invented 400 V motor +31 %, the
    Table I, 600 V and flywheel motors +8-10 %), it was the plant's dead-time
    model, not the drive. The coast holds the sampled current at zero. The
    "sign" model (the default: the diode by the current's sign at the period's
    start) then delays every pulse's centre by t_dead / 2, so the period's mean
    current is the sample minus u_q t_dead / (2 L_s): it brakes with k_t E
    t_dead / (2 L_s) (measured within 1 % on these motors). Relative to the
    friction at the second speed that is 1.5 (n_p psi_r)^2 t_dead / (2 L_s B),
    whatever the speed. Zero-current clamping (the model issue 23 names) keeps a
    current at zero in the dead time: no such braking.

    On the 400 V motor: with clamping, J within 5 % and B within 5 %. With
    the sign model, B's error is the predicted braking's share within a
    quarter of it (predicted +32 %, measured +31 %)."""
    s0 = load_scenario(ROOT / "tests" / "motors" / "industrial_400v_5kw.toml")
    m = s0.motor
    clamp = s0.replace(inverter=dataclasses.replace(s0.inverter, dead_time_model="clamp"))
    c = commission(clamp)
    assert c.mech.ok and abs(c.mech.J / m.J - 1.0) < 0.05 and abs(c.mech.B / m.B - 1.0) < 0.05
    assert s0.inverter.dead_time_model == "sign"
    cs = commission(s0)
    pred = 1.5 * (m.n_p * m.psi_r) ** 2 * s0.inverter.t_dead / (2.0 * m.L_s * m.B)
    assert cs.mech.ok and abs((cs.mech.B / m.B - 1.0) / pred - 1.0) < 0.25, (cs.mech.B, pred)


def test_inertia_with_a_load_of_ten_times_the_rotor():
    """Issue 23: valid with a load inertia up to 10 x the rotor's. Table I's
    motor with 10 x its inertia (12 x the guessed inertia; step 4's drive is
    designed for the inertia step 3's spin saw, 0.92 of the true one): J
    within 10 %, B within 20 %. (With 5 x, B's fit comes out negative and
    the step names it poor_fit: a named failure, measured.)"""
    s0 = CASES["yang2018 Table I"]
    s = s0.replace(motor=dataclasses.replace(s0.motor, J=10.0 * s0.motor.J))
    c = commission(s)
    assert c.mech.ok and abs(c.mech.J / s.motor.J - 1.0) < 0.10
    assert abs(c.mech.B / s.motor.B - 1.0) < 0.20
    s5 = s0.replace(motor=dataclasses.replace(s0.motor, J=5.0 * s0.motor.J))
    c5 = commission(s5)
    assert c5.mech.ok or c5.mech.outcome == "poor_fit"
    if c5.mech.ok:
        assert abs(c5.mech.J / s5.motor.J - 1.0) < 0.10


def test_step_4_designs_its_drive_from_what_it_measured():
    """Step 4's drive is designed from the measured R_s, L_s, psi_r and dead
    time and the inertia step 3's spin saw (a guessed one without it), not
    the plant's: the same
    measured values on two plants whose rotors differ 10 x in inertia give
    the same drive. Before, the values the design derives from the motor
    came from the plant's own (the forced start's acceleration, scaled by
    T_N / J, and the speed-tracking time): 10 x the inertia gave a start 10 x
    slower, a leak of the truth that had carried the heavy rotors' tests."""
    s0 = CASES["yang2018 Table I"]
    m = s0.motor
    heavy = s0.replace(motor=dataclasses.replace(m, J=10.0 * m.J))
    args = (1.01 * m.R_s, 0.98 * m.L_s, 1.005 * m.psi_r)
    a, b = (mech_scenario(x, *args, t_dead_comp=1e-6, u_0=0.5).controller for x in (s0, heavy))
    assert a == b
    # ... and the inertia step 3's spin saw is the drive's: its speed loop and what is
    # derived from the inertia (here the forced start's acceleration, T_N / J: 10 x slower)
    c = mech_scenario(heavy, *args, t_dead_comp=1e-6, u_0=0.5, J_spin=10.0 * m.J).controller
    d = mech_scenario(heavy, *args, t_dead_comp=1e-6, u_0=0.5, J_spin=m.J).controller
    assert c.J_hat == 10.0 * m.J and d.J_hat == m.J
    assert c.a_M_start == pytest.approx(0.1 * d.a_M_start, rel=1e-9)


def _heavy_yao(k: float):
    s0 = catalogue()["yao2022.steady.100k"]()
    return s0.replace(motor=dataclasses.replace(s0.motor, J=k * s0.motor.J))


def test_a_rotor_that_slips_in_the_spin_is_named():
    """yao2022's motor with 10 x its inertia: the spin's first ramp asks 4.8
    times the rated current's torque, and the rotor stays behind. Step 3
    names it "slipped" (the coast's turn, 10,000 rad/s of noise, is not the
    frame's 5,236), not poor_fit, and no inertia is measured."""
    c = commission(_heavy_yao(10.0))
    assert c.psi.outcome == "slipped"
    assert abs(c.psi.w_coast / (0.5 * 2.0 * math.pi * 100e3 / 60.0) - 1.0) > 0.5
    assert c.mech is None


@pytest.mark.parametrize("u_dc,slow,outcome", [(12.0, 1.0, "ok"), (3.5, 1.0, "voltage_limit"),
                                               (1.0, 1.0, "voltage_limit"),
                                               (1.0, 10.0, "voltage_limit")])
def test_a_spin_beyond_the_dc_links_reach_is_named(u_dc, slow, outcome):
    """An invented 12 V pump (tests/commission_motors/pump_12v_60w.toml)
    commissioned on a lower supply, as on a bench: step 3's spin at half
    rated speed meets 2.2 V of back EMF (plus R_s i), and u_dc / sqrt 3 is
    2.02 V on 3.5 V, 0.58 V on 1 V. The rotor falls out of the spin there;
    before 2026-11-27 the test named it "slipped" and `identify` advised
    --slow 10, which cannot help (the EMF is the speed's, not the ramp's:
    at --slow 10 the same). The spin now counts the samples whose voltage
    the modulator limited, and a spin without a result that was limited for
    more than a twentieth of a hold ends "voltage_limit", with the advice to
    check u_dc and w_M_N. On 12 V (6.93 V) the spin has room: psi_r within
    2 %. (Load slips stay "slipped": the tests above.)"""
    s0 = load_scenario(ROOT / "tests" / "commission_motors" / "pump_12v_60w.toml")
    s = _inverter(s0, u_dc=u_dc)
    c = commission(s, mechanics=False, slow=slow)
    assert c.ok, c.rs
    assert c.psi.outcome == outcome
    if outcome == "ok":
        assert abs(c.psi.psi / s.motor.psi_r - 1.0) < 0.02


def test_the_voltage_limits_advice_works():
    """voltage_limit says where the limit came (w_lim, the frame's speed at
    the first limited sample above the governor's start) and `identify`
    advises w_M_N_rpm up to 1.6 times it (the spin's upper speed half of
    w_M_N, at 0.8 of the limit). On 3.5 V the limit must come where the EMF,
    w psi_r, is between 0.7 (R_s i and the drop take 0.55 V of the 2.02 V)
    and 1.16 (the hexagon's corners, 2/3 u_dc) of u_dc / sqrt 3; measured
    0.79. The advice taken (w_M_N_rpm = 1.6 x the limit's r/min), psi_r is
    measured within 2 %."""
    s0 = load_scenario(ROOT / "tests" / "commission_motors" / "pump_12v_60w.toml")
    s = _inverter(s0, u_dc=3.5)
    c = commission(s, mechanics=False)
    assert c.psi.outcome == "voltage_limit"
    k = c.psi.w_lim * s.motor.psi_r / (3.5 / math.sqrt(3.0))
    assert 0.7 <= k <= 1.16, k
    rpm = c.psi.w_lim / s.motor.n_p * 30.0 / math.pi
    s2 = s.replace(motor=dataclasses.replace(s.motor, w_M_N=1.6 * rpm * math.pi / 30.0))
    c2 = commission(s2, mechanics=False)
    assert c2.psi.ok and abs(c2.psi.psi / s.motor.psi_r - 1.0) < 0.02, c2.psi


def test_a_step_1_without_a_result_writes_no_resistance(tmp_path):
    """The pump on 1 V with its nameplate's 60 W at 722 r/min: rated current
    50 A, and step 1's top current needs more than the 0.58 V the modulator
    has (no_current). `identify` wrote the motor with the R_s it had not
    measured, 0 ohm, and stopped with "motor.R_s = 0.0 is outside its valid
    range" (before 2026-11-27); it now says "not measured", writes the
    scenario's values with the record of why, and exits 1."""
    src = ROOT / "tests" / "commission_motors" / "pump_12v_60w.toml"
    text = src.read_text().replace("u_dc = 12.0", "u_dc = 1.0").replace(
        "w_M_N_rpm = 4000.0", "w_M_N_rpm = 722.0")
    scen, out = tmp_path / "pump_1v.toml", tmp_path / "measured.toml"
    scen.write_text(text)
    res = CliRunner().invoke(main, ["identify", str(scen), "--out", str(out)])
    assert res.exit_code == 1, res.output
    assert "R_s  not measured" in res.output and "no_current" in res.output
    assert "outside its valid range" not in res.output
    # (the spin's: on 3.5 V it stops before its holds, and says so instead of -100 %)
    scen.write_text(src.read_text().replace("u_dc = 12.0", "u_dc = 3.5"))
    res = CliRunner().invoke(main, ["identify", str(scen)])
    assert res.exit_code == 1 and "psi_r not measured" in res.output, res.output
    assert "voltage_limit" in res.output and "fits w_M_N_rpm up to" in res.output
    written = out.read_text()
    assert "nothing measured" in written and 'outcome = "no_current"' in written
    assert load_scenario(out).motor.R_s == 0.05


def test_a_heavy_load_commissioned_slowly():
    """The same motor with `slow` = 10 (the spin and step 4's start and ramp
    10 x slower): every step ok, psi_r within 2 %, J within 10 %, the fan's
    K within 20 % (issue 23's bounds; measured -0.7 %, -2.2 %, -7.1 %), in
    44 s of motor time (the 10 s bound is for the motors as they are; a
    10 x heavier rotor takes 10 x as long to spin up at the same current)."""
    s = _heavy_yao(10.0)
    c = commission(s, slow=10.0)
    m = s.motor
    assert c.psi.ok and abs(c.psi.psi / m.psi_r - 1.0) < 0.02
    assert c.mech.ok and abs(c.mech.J / m.J - 1.0) < 0.10
    assert abs(c.mech.K / s.load.k_fan - 1.0) < 0.20
    assert c.t < 60.0


def test_slow_out_of_range_is_named():
    with pytest.raises(ParameterError, match="slow"):
        commission(CASES["yang2018 Table I"], slow=0.5)


def _profile_within_10_percent(s, c, seed: int) -> None:
    """Issue 23: the usual profile on plant `s`, sensorless, designed from
    the true values and from commissioning `c`'s: both reach its end, their
    RMS angle errors over the sensorless phase within 10 % of each other."""
    from smodrive.engine import simulate
    from smodrive.scenarios import trials

    p = trials.profile_scenario(s, seed)
    rms = []
    for x in (p, p.with_controller(R_s_hat=c.rs.R_s, L_s_hat=c.L_s, psi_r_hat=c.psi.psi)):
        r = simulate(x)
        assert trials.judge(r).verdict == "reached", (seed, trials.judge(r))
        rms.append(trials.sensorless_angle_rms(r))
    assert abs(rms[1] / rms[0] - 1.0) < 0.10, (seed, rms)


def _issue23_draws(s0, per_period: bool = False, mechanics: bool = True,
                   profile: bool = False) -> list:
    """Commission 10 draws of issue 23's conditions on `s0` (with
    `per_period`, the dead time as the same share of `s0`'s period as of
    100 us) and hold each to the issue's bounds: R_s 2 %, L_d and L_q 5 %,
    psi_r 2 %, and with `mechanics` J 10 % and B 20 %, every step ok; with
    `profile`, the usual profile on the same plant, sensorless, designed from
    the measured and from the true values, both reaching its end with RMS
    angle errors within 10 % of each other; the commissionings."""

    rng = np.random.default_rng(2026)
    out = []
    for seed in range(1, 11):
        s = sensor_errors(s0, seed, rng)
        if per_period:
            s = _inverter(s, t_dead=s.inverter.t_dead * s0.T_sp / 100e-6)
        c = commission(s, mechanics=mechanics)
        m = s.motor
        assert c.ok and c.psi.ok and (c.mech.ok if mechanics else True), (seed, c)
        assert abs(c.rs.R_s / m.R_s - 1.0) < 0.02
        assert abs(c.ld.L / m.L_s - 1.0) < 0.05 and abs(c.lq.L / m.L_s - 1.0) < 0.05
        assert abs(c.psi.psi / m.psi_r - 1.0) < 0.02
        if mechanics:
            assert abs(c.mech.J / m.J - 1.0) < 0.10 and abs(c.mech.B / m.B - 1.0) < 0.20
        if profile:
            _profile_within_10_percent(s, c, seed)
        out.append(c)
    return out


@pytest.mark.parametrize("motor", ["yang2018_table1", "servo_48v_200w", "industrial_600v_10kw"])
def test_accuracy_with_sensor_errors_and_dead_time(motor):
    """Issue 23's conditions, 10 draws a motor: current-sensor gains within
    +-0.5 %, offsets within +-0.2 % of full scale, a dead time of 0.5-2 us
    with zero-current clamping, the 12-bit ADC's noise (its seed): R_s within
    2 %, L_d and L_q within 5 %, psi_r within 2 %, J within 10 %, B within
    20 %, every step ok. (A gain error on phase a is R_s's error one for one:
    +-0.5 % here; an offset moves the intercept, not the slope.) Then the
    usual profile on each draw's plant, sensorless, designed from the
    measured and from the true values: both reach its end, RMS angle errors
    within 10 % (measured: Table I within 4.3 %, the servo 6.7 %, the 600 V
    motor 1.4 %; counting the handover's logged sample, which carries the
    forced start's angle, one draw read +87 %: trials.sensorless_angle_rms)."""
    _issue23_draws(load_scenario(MOTORS / f"{motor}.toml"), profile=True)


def test_micro_motor_with_sensor_errors_and_dead_time():
    """Issue 23's conditions on its 1 ohm / 50 uH / 2 mWb micro motor, 10
    draws: the gains, offsets and ADC noise as above; the dead time the same
    0.5-2 % of the period as 0.5-2 us is of the other motors' 100 us, here
    0.125-0.5 us of its 25 us (40 kHz). R_s within 2 %, L_d and L_q within
    5 %, psi_r within 2 %, J within 10 %, B within 20 %, every step ok, in
    10 s (measured: 0.43, 1.9, 0.65, 2.4, 4.7 %, 7.8 s). The issue's
    0.5-2 us itself: the next test."""
    for c in _issue23_draws(CASES["micro 1 ohm, 50 uH (invented)"], per_period=True):
        assert c.t <= 10.0


def test_micro_motor_under_the_issues_dead_time():
    """The micro motor under issue 23's 0.5-2 us as written, 2-8 % of its
    40 kHz period: on the 12 V bus a drop (3/pi) u_0 of up to 1.1 V against
    the 1.26 V of EMF at step 3's second speed. The holds read the drop's
    model error (-1 to -7 %), and a coast at zero current read the drop
    itself (+10 to +41 %, named poor_fit on all 10 draws); the coast now
    shorts the stator (no switching, no dead time) and psi_r is the short's
    current through the measured impedance. 10 draws of issue 23's
    conditions: R_s within 2 %, L_d and L_q within 5 %, psi_r within 2 %, J
    within 10 %, B within 20 % (measured 0.71, 2.3, 0.67, 5.7 and 4.9 %;
    before R_s's correction for where the current is sampled and step 4's
    speed estimate fast enough for its ramp, 1.3, 2.4, 1.4, 3.6 and 16.7 %),
    the whole sequence in 10 s (8.9 s at most); the holds' value, the plausible
    wrong result, is more than 2 % off on some draw. Then the usual profile
    (start, steps, rated load, reversal) sensorless, designed from the
    measured and from the true values: both reach its end, the RMS angle
    errors within 10 % of each other (measured within 2.4 %; 9.9 % before
    step 2's correction for where the current is sampled: the micro motor's
    angle error moves 6 % for 1 % of L_s_hat, docs/commissioning.md). L_s, the
    mean of L_d and L_q that the drive is designed from, within 1 %
    (measured 0.85 %; -0.5 to -1.8 % before that correction: the square
    wave's voltage comes t_d / 2 late to each sample, e^{-R_s t_d / (2 L_s)},
    -0.9 to -1.9 % at these draws' 0.9-1.9 us). Before the
    handover counted the compensated drop (derive.DTC_RESIDUAL) the drive
    handed over at 1.8-2 x rated speed: step 4 said no_sensorless_range and
    the profile ran on I/f to its end."""

    s0 = CASES["micro 1 ohm, 50 uH (invented)"]
    rng = np.random.default_rng(2026)
    holds = []
    for seed in range(1, 11):
        s = sensor_errors(s0, seed, rng)
        c = commission(s)
        m = s.motor
        assert c.ok and c.psi.ok and c.psi.shorted, (seed, c)
        assert abs(c.rs.R_s / m.R_s - 1.0) < 0.02
        assert abs(c.ld.L / m.L_s - 1.0) < 0.05 and abs(c.lq.L / m.L_s - 1.0) < 0.05
        assert abs(c.L_s / m.L_s - 1.0) < 0.01, (seed, c.L_s / m.L_s)
        assert abs(c.psi.psi / m.psi_r - 1.0) < 0.02
        assert c.mech is not None and c.mech.ok, c.mech
        assert abs(c.mech.J / m.J - 1.0) < 0.10 and abs(c.mech.B / m.B - 1.0) < 0.20
        assert c.rs.t + c.ld.t + c.lq.t + c.psi.t + c.mech.t <= 10.0
        holds.append(abs(c.psi.psi2 / m.psi_r - 1.0))
        _profile_within_10_percent(s, c, seed)
    assert max(holds) > 0.02


def test_the_search_backs_off_once_an_overshoot():
    """Step 1's search backs off to half its last step when the current
    passes 1.2 i_test, and did so on every sample of the current's decay
    after the cut: 11 times on the 20 mohm stator (issue 23's draw 5: 1 us
    of dead time, an 8 V drop on 600 V), leaving a step of 1 mV to climb
    through the drop, 20 ms a step: step 1 took 8.8 s and the sequence 16 s.
    It now backs off while the current still rises. Over issue 23's 10
    draws on the two 600 V stators step 1 takes at most 2.5 s (measured
    1.9 s) and R_s stays within 2 %."""
    for name in ("20 mohm, 0.2 mH (invented)", "industrial 600 V 10 kW"):
        s0 = CASES[name]
        rng = np.random.default_rng(2026)
        for seed in range(1, 11):
            s = sensor_errors(s0, seed, rng)
            r = identify_rs(s)
            assert r.ok and r.t <= 2.5, (name, seed, r.t)
            assert abs(r.R_s / s.motor.R_s - 1.0) < 0.02


def test_r_s_corrected_for_where_the_current_is_sampled():
    """The dead time moves each pulse's centre by t_d / 2 from the carrier's,
    where the current is sampled: the staircase's slope is R_s (1 - R_s t_d /
    (2 L_s)). The micro motor (R_s / L_s = 20,000 1/s) at 1 and 2 us with
    clamping, 3 ADC seeds each: the slope is that far low (-1 and -2 %,
    within 0.4 % of R_s: measured -0.66 and -1.72 %), and the corrected R_s
    (t_d from the measured drop, L_s from step 2) is within 0.5 % (the
    plausible wrong result, the slope, is not at 2 us); psi_r, which step 3
    takes through R_s, within 1 %. On Table I the factor is below 2e-4;
    behind yao2022's LCL filter nothing is corrected."""
    s0 = CASES["micro 1 ohm, 50 uH (invented)"]
    for t_d in (1e-6, 2e-6):
        for seed in (1, 2, 3):
            s = _inverter(s0, t_dead=t_d, dead_time_model="clamp")
            s = s.replace(adc=dataclasses.replace(s.adc, seed=seed))
            c = commission(s, mechanics=False)
            m = s.motor
            assert c.ok and c.psi.ok, c
            k = m.R_s * t_d / (2.0 * m.L_s)
            assert abs(c.rs.R_fit / m.R_s - (1.0 - k)) < 0.004, (t_d, c.rs)
            assert abs(c.rs.R_s / m.R_s - 1.0) < 0.005, (t_d, c.rs)
            if t_d == 2e-6:
                assert abs(c.rs.R_fit / m.R_s - 1.0) > 0.01
            assert abs(c.psi.psi / m.psi_r - 1.0) < 0.01, (t_d, c.psi)
    c = commission(CASES["yang2018 Table I"], mechanics=False)
    assert 0.0 < c.rs.R_s / c.rs.R_fit - 1.0 < 2e-4
    y = catalogue()["yao2022.steady.100k"]()
    c = commission(y, mechanics=False)
    assert math.isnan(c.rs.R_fit)


def test_no_room_for_step_4_below_rated_speed_is_named():
    """The micro motor with 2 us of dead time on a 24 V bus: the drop's
    fundamental, (4/pi) 0.08 x 24 V = 2.44 V, is the EMF at 1.9 x rated
    speed; even a quarter of it (the compensated residual the handover
    counts, derive.DTC_RESIDUAL) puts the handover at rated speed, and step
    4's ramp has no room below it: it is not run and says so, before any
    simulation, instead of the negative ramp it was once given (a
    ParameterError on a_M_ref). On 12 V the same dead time leaves it room
    (test_micro_motor_under_the_issues_dead_time)."""
    s0 = CASES["micro 1 ohm, 50 uH (invented)"]
    for u_dc, room in ((24.0, False), (12.0, True)):
        s = _inverter(s0, u_dc=u_dc, t_dead=2e-6, dead_time_model="clamp")
        m = s.motor
        sd = mech_scenario(s, m.R_s, m.L_s, m.psi_r, 2e-6, 0.08 * u_dc)
        assert mech_room(sd) is room, (u_dc, sd.controller.w_M_handover / m.w_M_N)
    r = identify_mech(_inverter(s0, u_dc=24.0, t_dead=2e-6, dead_time_model="clamp"),
                      1.0, 50e-6, 2e-3, 2e-6, 0.08 * 24.0)
    assert r.outcome == "no_sensorless_range" and r.t == 0.0 and not r.ok


def test_five_microhenry_drone_motor_steps_1_to_3_with_sensor_errors():
    """Issue 23's 5 uH end of the inductance range: an invented 24 V, 500 W
    multirotor outrunner (tests/motors/drone_24v_5uh.toml: 25 mohm, 5 uH,
    0.875 mWb, 7 pole pairs, 15,000 r/min, on a 40 kHz inverter), 10 draws of
    issue 23's conditions, the dead time as the micro motor's (0.5-2 % of the
    period). R_s within 2 %, L_d and L_q within 5 %, psi_r within 2 %
    (measured: 0.46, 1.8, 0.36 %, steps 1-3 in 4.7 s at most).

    Step 4 is the next test."""
    _issue23_draws(load_scenario(ROOT / "tests" / "motors" / "drone_24v_5uh.toml"),
                   per_period=True, mechanics=False)


def test_step_4s_speed_estimate_is_fast_enough_for_its_ramp():
    """An invented 60,000 r/min blower (tests/commission_motors): its drive,
    designed for the inertia step 3 measured (0.98 of the true), derives
    its speed estimate's low-pass from the inertia, 31 rad/s; in step 4's
    ramp the estimate lagged by 200 rad/s, the SMDO's filter (36) turned by
    it, and the fit read J +16 %, B +86 % as ok. Step 4's drive now has a
    low-pass of at least 100 / T_RAMP = 250 rad/s (its lag a hundredth of
    the ramp's span): J and B within 10 and 20 % over 3 ADC seeds (measured
    +0.8 %, +3.2 %), and the drive's own derived value is left as it was."""
    from smodrive.commission import T_RAMP, W_LPF_RAMP

    s0 = load_scenario(ROOT / "tests" / "commission_motors" / "blower_24v_60krpm.toml")
    m = s0.motor
    for seed in (1, 2, 3):
        s = s0.replace(adc=dataclasses.replace(s0.adc, seed=seed))
        c = commission(s)
        assert c.ok and c.psi.ok and c.mech.ok, (seed, c.mech)
        assert abs(c.mech.J / m.J - 1.0) < 0.10 and abs(c.mech.B / m.B - 1.0) < 0.20, c.mech
    sd = mech_scenario(s0, m.R_s, m.L_s, m.psi_r, 0.3e-6, 0.384, J_spin=m.J)
    assert sd.controller.w_lpf == pytest.approx(W_LPF_RAMP / T_RAMP, rel=1e-12)
    assert s0.with_controller(current="robust_dbpc", position="smdo_emf",
                              J_hat=m.J).controller.w_lpf < 40.0


def test_a_torque_the_drive_misreports_is_named():
    """Step 4 on the 5 uH multirotor motor (0.2 rad a sample at 40 kHz): the
    coast's B (no torque in it) and the ramp's (the drive's k_t i_q) must
    give friction torques at w2 within a twentieth of the ramp's torque.
    Once the angle lagged 3-5 deg in the ramp (J -28 %, B +450 %, 27 % of
    the ramp's torque apart); with step 4's speed estimate fast enough
    (commission.W_LPF_RAMP) J reads -4.5 %, but the coast's zero current is
    not the rotor's zero torque there: B +161 % by the coast, +47 % by the
    ramp, 9.7 % of the ramp's torque apart, which the former bound of a
    tenth passed as ok. It is named (poor_fit, the values given). On 30
    other runs, 10 x their inertia too, the two are at most 2.0 % apart
    (commission.py's W_LPF_RAMP, smd_ident.h)."""
    s = load_scenario(ROOT / "tests" / "motors" / "drone_24v_5uh.toml")
    c = commission(s)
    assert c.psi.ok and c.mech is not None
    assert c.mech.outcome == "poor_fit", c.mech
    assert abs(c.mech.B / s.motor.B - 1.0) > 0.20  # (what "ok" had said)
    w2 = 0.8 * s.motor.w_M_N
    apart = abs(c.mech.B - c.mech.B_ramp) * w2 / (c.mech.J * 0.4 * s.motor.w_M_N / 0.4)
    assert 0.05 < apart < 0.1


def test_yao2022_motor_behind_its_lcl_filter():
    """The yao2022 motor (24 uH) behind its LCL filter (L1 54 uH, C1 31.5 uF,
    L2o 27.5 uH): step 2's wave rings the filter, and a first-order fit sees
    the filter's inductances and the motor's in series, the capacitor aside
    (the wave's shape, not one inductance); subtracting the filter's 81.5 uH
    from it leaves the motor's 24 uH off by more than 5 % (the plausible wrong
    implementation: checked). The filter's model (its data sheet's values)
    fitted to the averaged wave gives L_d and L_q within 5 % over 10 ADC
    seeds (issue 23), R_s within 2 % (phase a's current sensor reads 1 %
    high in this scenario: R_s -1 %)."""
    s0 = catalogue()["yao2022.steady.100k"]()
    m, f = s0.motor, s0.lcl
    for seed in range(1, 11):
        s = s0.replace(adc=dataclasses.replace(s0.adc, seed=seed))
        c = commission(s, mechanics=False)
        assert c.ok, (seed, c)
        assert abs(c.rs.R_s / m.R_s - 1.0) < 0.02
        for x in (c.ld, c.lq):
            assert abs(x.L / m.L_s - 1.0) < 0.05, (seed, x)
            assert abs((x.L_series - f.L1 - f.L2o) / m.L_s - 1.0) > 0.05, (seed, x)
        assert c.t <= 10.0


@pytest.mark.parametrize("seeds", [range(1, 6), range(6, 11)])
def test_yao2022_flux_inertia_and_fan_behind_its_lcl_filter(seeds):
    """The yao2022 motor behind its LCL filter, steps 3 and 4 (issue 23), 10
    ADC seeds. Step 3: the I/f rotor has no friction, and its fan and the
    ramp ask more than the spin current's torque: without the governor and
    the stabiliser it slipped (psi_r 23 % of the true value, logged); the
    filter's voltage drop is taken out of the EMF through the capacitor's
    voltage. psi_r within 2 %, its coasting value agreeing. Step 4 by
    yao2022's own drive (current PI, sliding-mode observer and PLL, I/f
    start) on the bench with the fan: J within 10 %, the fan's K within 20 %,
    B (0 on this motor) not negative and the load torque the fit gives at
    the second speed, B w2 + K w2^2, within 10 % of the fan's (J's bound: the
    torque the fit splits is what J is measured against); the whole
    sequence within 10 s. (B's own share is not held to more than K's
    error: over the ramp's 40-80 % of rated speed w and w^2 are nearly
    collinear, w^2 = 0.64 w_n w within 0.1 w_n^2 (least squares), so the fit's
    B takes K's error, 0.64 w_n dK per unit; this test held B to 2 % of the
    fan's torque while step 4's speed loop had a guessed inertia 24 x too
    small, and measured 5 % with K -8 % once it had the spin's.)"""
    s0 = catalogue()["yao2022.steady.100k"]()
    m, k_fan = s0.motor, s0.load.k_fan
    for seed in seeds:
        s = s0.replace(adc=dataclasses.replace(s0.adc, seed=seed))
        c = commission(s)
        assert c.ok and c.psi.ok and c.mech.ok, (seed, c)
        assert abs(c.psi.psi / m.psi_r - 1.0) < 0.02, (seed, c.psi)
        assert abs(c.mech.J / m.J - 1.0) < 0.10, (seed, c.mech)
        assert abs(c.mech.K / k_fan - 1.0) < 0.20, (seed, c.mech)
        w2 = 0.8 * m.w_M_N
        assert c.mech.B >= 0.0, (seed, c.mech)
        load = c.mech.B * w2 + c.mech.K * w2 * w2
        assert abs(load / (k_fan * w2 * w2) - 1.0) < 0.10, (seed, c.mech)
        assert c.t <= 10.0, (seed, c.t)


def test_yao2022_motor_with_sensor_errors_and_dead_time():
    """yao2022's motor behind its LCL filter under issue 23's conditions
    (10 draws: current-sensor gains within +-0.5 %, offsets within +-0.2 %
    of full scale, 0.5-2 us of dead time with zero-current clamping on its
    65 V bus, where 2 us is 3.5 V of drop against 6 V of EMF at step 3's
    second speed): every step ok, R_s within 2 %, L_d and L_q within 5 %,
    psi_r within 2 %, J within 10 %, the fan's K within 20 %, the sequence
    within 10 s. What made it work: the plant's clamping behind the filter;
    step 3 takes the drop along the inverter's current and the capacitor's
    voltage from it, coasts with every switch open (the legs' dead time at
    the capacitor's current had put the coast 15 % high), and spins at the
    rated current (at half of it, the first ramp asked 95 % of the current's
    torque of this rotor, and in 2 of the 10 draws, where the dead time
    biased the governor's reading at low speed, the rotor slipped); step 4's
    drive compensates the measured dead time and hands over where the EMF
    reaches the drop."""
    s0 = catalogue()["yao2022.steady.100k"]()
    m, k_fan = s0.motor, s0.load.k_fan
    rng = np.random.default_rng(2026)
    for seed in range(1, 11):
        s = sensor_errors(s0, seed, rng)
        c = commission(s)
        assert c.ok and c.psi.ok and c.mech.ok, (seed, c)
        assert abs(c.rs.R_s / m.R_s - 1.0) < 0.02
        assert abs(c.ld.L / m.L_s - 1.0) < 0.05 and abs(c.lq.L / m.L_s - 1.0) < 0.05
        assert abs(c.psi.psi / m.psi_r - 1.0) < 0.02, (seed, c.psi)
        assert abs(c.mech.J / m.J - 1.0) < 0.10 and abs(c.mech.K / k_fan - 1.0) < 0.20
        assert c.t <= 10.0, (seed, c.t)


def test_the_spin_current_within_the_voltage_it_needs():
    """An invented 12 V, 6 ohm gimbal motor (tests/commission_motors/gimbal_12v_6ohm.toml):
    step 3's spin current, twice step 1's largest level (1.3 A), needs 7.7 V
    across R_s of the 6.9 V the modulator has; the current falls short, the
    governor holds the ramp at 1 % of its rate and the spin ends "running"
    after 30 s (the plausible wrong current: checked). Capped at half the
    modulator's voltage across the measured R_s (0.58 A), every step is ok,
    psi_r within 2 %, J within 10 %, B within 20 %, in 10 s (measured +0.1 %,
    +0.1 %, -2.1 %, 7.9 s)."""
    import warnings

    from smodrive.commission import K_SPIN, _engine, identify_ls, identify_psi, identify_rs
    from smodrive.commission import spin_current

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (its rated point is out of reach: said)
        s = load_scenario(ROOT / "tests" / "commission_motors" / "gimbal_12v_6ohm.toml")
        c = commission(s)
    m = s.motor
    assert c.ok and c.psi.ok and c.mech is not None and c.mech.ok, c
    assert abs(c.psi.psi / m.psi_r - 1.0) < 0.02
    assert abs(c.mech.J / m.J - 1.0) < 0.10 and abs(c.mech.B / m.B - 1.0) < 0.20
    assert c.t <= 10.0
    i_cap = spin_current(s, c.rs)
    assert i_cap < K_SPIN * max(c.rs.i_levels) and i_cap * c.rs.R_s < s.inverter.u_dc / 3 ** 0.5
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        eng = _engine(s)
        rs = identify_rs(s, None, eng)
        ld = identify_ls(s, rs, "d", 0.5 * max(rs.i_levels), eng)
        wrong = identify_psi(s, rs, ld.L, K_SPIN * max(rs.i_levels), eng)
    assert not wrong.ok, wrong


def test_the_dead_time_is_the_one_measured_whatever_the_drives_period():
    """Step 1's drop u_0 is a dead time's share of the period it was measured
    at: RsResult.t_dead() takes that period and DC link (kept in the
    result). The 48 V servo identified at 50 us with 1 us of dead time
    (zero-current clamping): within 10 % of 1 us (the switches' clamping
    near zero current makes the drop a little smaller). The drive's own
    period given instead, 100 us, is twice the dead time: what the tracker's
    test harness once passed, and an invented 48 V fan motor's R_s read 44 %
    low through the doubled compensation."""
    s0 = load_scenario(MOTORS / "servo_48v_200w.toml")
    s = _inverter(s0.replace(T_sp=5e-5), t_dead=1e-6, dead_time_model="clamp")
    r = identify_rs(s)
    assert r.ok and r.T_sp == 5e-5 and r.u_dc == s.inverter.u_dc
    assert abs(r.t_dead() / 1e-6 - 1.0) < 0.10, r.t_dead()
    assert r.t_dead(1e-4, s.inverter.u_dc) == pytest.approx(2.0 * r.t_dead(), rel=1e-12)


@pytest.mark.parametrize("seed", [7, 8, 10])
def test_an_inductance_the_noise_moved_beyond_5_percent_is_not_ok(seed):
    """An invented 12 V hobby motor (0.8 ohm, 160 uH, 2 pole pairs) under 0.1 A
    of ADC noise (five times the derived): its 0.27 A swing carries the
    noise, and on these seeds L_q read 12-21 % low, reported "ok" (the three
    bias levels 0.144 / 0.113 / 0.109 mH on seed 7). L is the levels' mean
    weighted by their swings squared; twice its standard error estimated from
    the levels' scatter beyond L's stated accuracy (5 %) is now
    "levels_disagree": every L reported ok is within 5 % of the motor's, and
    each seed names one axis (q on seeds 7 and 8, -12 and -21 %; d on seed
    10, whose mean was right but not to be told from the scatter). The ten
    seeds of each motor of test_inductance_within_5_percent_over_ten_seeds
    are all still ok."""
    s = scenario_from_dict({"motor": {"R_s": 0.8, "L_s": 160e-6, "psi_r": 0.004, "n_p": 2,
                                      "J": 3e-6, "B": 4e-8, "P_N": 18.0, "w_M_N_rpm": 5000.0},
                            "inverter": {"u_dc": 12.0, "t_dead": 0.5e-6},
                            "adc": {"noise": 0.1, "seed": seed}})
    c = commission(s, mechanics=False)
    assert c.rs.ok
    results = [x for x in (c.ld, c.lq) if x is not None]
    for x in results:
        if x.ok:
            assert abs(x.L / s.motor.L_s - 1.0) <= 0.05, (x.axis, x.L)
    assert any(x.outcome == "levels_disagree" for x in results)


def test_the_spin_current_stays_within_the_sensors_share():
    """Step 3 spins at K_SPIN (2) times step 1's largest level, which the
    search takes to up to 1.2 i_test: with i_test at its sensor-bound limit,
    0.45 of 5 A sensors, that was 5.35 A on 5 A sensors (an invented 48 V
    hub motor), beyond the 0.9 of their range i_test_max promises. It is now
    at most 0.9 x 5 = 4.5 A; with 50 A sensors the same levels spin at 2 x
    their largest, 5.35 A."""
    from smodrive.commission import RsResult, i_test_max, spin_current

    s = scenario_from_dict({"motor": {"R_s": 0.2, "L_s": 0.4e-3, "psi_r": 0.03, "n_p": 23,
                                      "J": 0.08, "P_N": 350.0, "w_M_N_rpm": 350.0},
                            "inverter": {"u_dc": 48.0}, "adc": {"full_scale": 5.0}})
    lim, why = i_test_max(s)
    assert lim == pytest.approx(2.25) and "0.45 adc.full_scale" in why
    rs = RsResult(R_s=0.2, u_0=0.5, r2=1.0, resid=0.0, outcome="ok", t=1.0,
                  i_levels=(0.5, 1.5, 2.675), u_levels=(0.6, 0.8, 1.0))
    assert spin_current(s, rs) == pytest.approx(4.5)
    wide = s.replace(adc=dataclasses.replace(s.adc, full_scale=50.0))
    assert spin_current(wide, rs) == pytest.approx(5.35)


def test_step_4_keeps_its_speeds_within_the_dc_link():
    """An invented 12 V gimbal motor (7 pole pairs, 10 mWb, 600 r/min) on a
    5 V DC link: step 4's 80 % of rated speed needs 3.5 V of back EMF, the
    inverter makes 2.89 V; its drive faulted (speed_tracking), blamed on
    the inertia, and --slow 10 did not help. Its top speed is now where the
    EMF takes 0.8 of u_dc / sqrt 3 (2.31 V: 315 r/min), the ramp from 40 %
    of rated below it, and J and B are measured (J within its 10 %)."""
    from smodrive.commission import V_MECH

    s = scenario_from_dict({"motor": {"R_s": 5.0, "L_s": 2e-3, "psi_r": 0.010, "n_p": 7,
                                      "J": 1e-4, "P_N": 2.0, "w_M_N_rpm": 600.0},
                            "inverter": {"u_dc": 5.0, "t_dead": 1e-6}})
    w_top = V_MECH * 5.0 / math.sqrt(3.0) / (7 * 0.010)
    assert abs(w_top * 30.0 / math.pi - 315.0) < 0.5
    c = commission(s)
    assert c.mech is not None and c.mech.outcome == "ok", c.mech
    assert c.mech.J == pytest.approx(1e-4, rel=0.10)
