"""Issue 18: a motor of one's own is either run right or said to be wrong.

Each case of the issue's table becomes a test (the run now reaches its
reference, or it ends in a named fault with a non-zero exit: never status 0
away from it); three motors written from a data sheet (tests/motors/*.toml,
only [motor] and [inverter]) run the usual profile over 10 ADC noise seeds;
the detection figures of the supervision are measured.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from smodrive.cli import main
from smodrive.firmware import header as fw_header
from smodrive.model import (RPM, ControllerCfg, InverterCfg, LoadCfg, MotorPars, ParameterError,
                             Profile, Scenario)
from smodrive.scenario_io import load_scenario, scenario_from_dict
from smodrive.scenarios import drive, trials
from smodrive.engine import fault_names, simulate

ROOT = Path(__file__).resolve().parents[1]
DATASHEET = sorted((ROOT / "tests" / "motors").glob("*.toml"))
REPO_MOTORS = sorted((ROOT / "scenarios" / "motors").glob("*.toml"))
#: the issue's 24 V, 100 W motor as a new user typed it (no J, no B)
SERVO_NO_J = {"R_s": 0.3, "L_s": 0.5e-3, "psi_r": 0.006, "n_p": 4, "P_N": 100.0,
              "w_M_N_rpm": 3000.0}
SERVO = load_scenario(ROOT / "tests" / "motors" / "servo_24v_100w.toml")


def _end(r, seconds: float):
    return r.t >= r.t[-1] - seconds


def _right_or_named(r, seconds: float) -> str:
    """'reached' (speed within 2 % of the final reference, angle within 10
    deg RMS over the last `seconds`), 'fault' (a named fault at the end) or
    'silent' (neither)."""
    m = _end(r, seconds)
    ref = r["w_M_ref"][-1]
    err = abs(np.mean(r["w_M"][m]) - ref) / max(abs(ref), 1e-9)
    ang = math.degrees(np.sqrt(np.mean(r.theta_error[m] ** 2)))
    if r.faults.final:
        return "fault"
    return "reached" if err <= 0.02 and ang <= 10.0 else "silent"


# ------------------------------------------------- the table --

def test_row1_a_motor_without_inertia_is_refused_by_name(tmp_path):
    """J and B silently took the 2.4 kW motor's 0.012 kg m^2 and 0.002: now
    J left out is refused, naming the field and what to give (exit 2, no
    traceback), and B left out is derived by the stated rule."""
    f = tmp_path / "servo.toml"
    f.write_text("[motor]\n" + "".join(f"{k} = {v!r}\n" for k, v in SERVO_NO_J.items())
                 + "\n[inverter]\nu_dc = 24.0\n")
    res = CliRunner().invoke(main, ["run", str(f), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and "Traceback" not in res.output
    assert "motor.J is not given" in res.output and "rotor inertia" in res.output
    m = SERVO.motor
    assert m.J == 1.5e-5 and m.B == pytest.approx(0.01 * m.T_N / m.w_M_N, rel=1e-12)
    assert [n for n, _, _ in m.derived] == ["B"]


def test_row2_the_same_motor_reverses_to_minus_rated():
    """The reversal to -1500 r/min ended at -48.8 r/min in the forced phase,
    status 0: now it reaches -1500 r/min on the SMDO (or names a fault),
    without a hand-set I/f threshold."""
    s = SERVO.replace(duration=1.2, w_M_ref=Profile((0.0, 0.0, 0.6, 0.6),
                                                    (0.0, 1500 * RPM, 1500 * RPM, -1500 * RPM)),
                      warm_start=False).with_controller(current="robust_dbpc",
                                                        position="smdo_emf", start="if")
    r = simulate(s)
    assert _right_or_named(r, 0.1) == "reached"
    assert r["phase"][-1] == 2  # on the observer, not forced


def test_row3_a_hand_set_return_threshold_does_not_chatter():
    """With w_M_if_enter = 200 r/min the start-up switched 12 times in 0.5 s
    with the speed swinging -2890 ... +1518 r/min, no fault: now the start
    either reaches 1500 r/min with at most 3 switches (start, and no more
    than one return) or ends in a named fault (chatter among them)."""
    s = SERVO.replace(duration=0.8, w_M_ref=Profile.const(1500 * RPM), warm_start=False
                      ).with_controller(current="robust_dbpc", position="smdo_emf",
                                        start="if", w_M_if_enter=200 * RPM)
    r = simulate(s)
    switches = int(np.count_nonzero(np.diff(r["phase"])))
    verdict = _right_or_named(r, 0.1)
    assert verdict != "silent"
    if verdict == "reached":
        assert switches <= 3


def test_row4_table1_reversal_without_hand_set_thresholds():
    """Table I sensorless: the return to I/f was off by default and every
    reversal lost lock: now derived (210 and 420 r/min) and on, the
    reversal 1000 -> -1000 r/min under a 5 N m brake reaches its reference."""
    s = Scenario(duration=2.0, w_M0=1000 * RPM,
                 w_M_ref=Profile((0.0, 0.5, 0.5), (1000 * RPM, 1000 * RPM, -1000 * RPM)),
                 load=LoadCfg(T_brake=Profile.const(5.0)),
                 controller=ControllerCfg(current="robust_dbpc", position="smdo_emf",
                                          start="handover", t_handover=0.1))
    assert s.controller.w_M_if_enter == pytest.approx(210.13 * RPM, rel=1e-4)
    r = simulate(s)
    assert _right_or_named(r, 0.2) == "reached"


def test_row5_table1_with_L_hat_1_5_L_holds_its_speed_with_the_predicted_angle_bias():
    """Sensorless with L_hat = 1.5 L: the speed is held (within 0.5 %), and
    the angle error is the SMDO's model bias the issue saw (10.2 deg): the
    disturbance estimate takes (L_hat - L) w_e i_q = 0.5 x 23.45 mH x 628
    rad/s x 6.37 A = 47 V at right angles to the 251 V back EMF, atan(47 /
    251) = 10.6 deg (within 1 deg), a bias, not an oscillation: the current
    stays below the oscillation warning (0.30 A sd against its 0.84 A bound)
    and the drive ends without a fault, holding speed and load. A run that
    reaches its reference with a biased angle is what the model error gives
    (docs/supervision.md); the angle is checked against that prediction."""
    L = 23.45e-3
    s = Scenario(duration=1.0, w_M0=1500 * RPM, w_M_ref=Profile.const(1500 * RPM),
                 load=LoadCfg(T_brake=Profile.const(MotorPars().T_N)),
                 controller=ControllerCfg(current="robust_dbpc", position="smdo_emf",
                                          start="handover", t_handover=0.2, L_s_hat=1.5 * L))
    r = simulate(s)
    m = r.window(0.5, 1.0)
    assert abs(np.mean(r.n_rpm[m]) / 1500 - 1) < 0.005
    w_e = 4 * 1500 * RPM
    i_q = MotorPars().T_N / MotorPars().k_t
    bias = math.degrees(math.atan(0.5 * L * w_e * i_q / (w_e * 0.4)))
    ang = math.degrees(np.sqrt(np.mean(r.theta_error[m] ** 2)))
    assert abs(ang - bias) < 1.0
    assert r.faults.final == 0


def test_row6_a_deadbeat_limit_cycle_is_flagged():
    """Robust DBPC with L_hat = 2 L, 1 A step: a limit cycle of 0.32 A sd
    that never decays, status 0. Now the oscillation warning names it while
    it lasts (the drive runs on): the run ends with `oscillation` in its
    fault word, and the CLI would exit non-zero; with L_hat = L it is
    silent."""
    base = Scenario(duration=0.5, w_M0=1000 * RPM,
                    i_q_ref=Profile((0.0, 0.1, 0.1), (0.0, 0.0, 1.0)),
                    motor=dataclasses.replace(MotorPars(), J=1e4),
                    controller=ControllerCfg(current="robust_dbpc", position="encoder",
                                             speed_loop=False))
    bad = simulate(base.with_controller(L_s_hat=2 * 23.45e-3))
    m = bad.window(0.3, 0.5)
    assert np.std(bad["i_d"][m]) > 0.2  # the limit cycle is there
    assert fault_names(bad.faults.final) == ["oscillation"]
    good = simulate(base)
    assert good.faults.first == 0


def test_row7_dead_time_compensation_follows_the_inverter(tmp_path):
    """[inverter] t_dead = 0.5e-6 left controller.t_dead_comp at 2e-6 and
    the C header carried 2e-6: now it is derived from the inverter (unless
    set), and the header carries it."""
    s = scenario_from_dict({"inverter": {"t_dead": 0.5e-6}})
    assert s.controller.t_dead_comp == 0.5e-6
    assert dict((n, src) for n, _, src in s.controller.derived)["t_dead_comp"].startswith(
        "inverter.t_dead")
    header = fw_header.drive_header(s)
    assert "#define SMD_T_DEAD_COMP 4.99999999e-07f" in header  # the float of 0.5e-6
    assert scenario_from_dict({"inverter": {"t_dead": 0.5e-6},
                               "controller": {"t_dead_comp": 1e-6}}).controller.t_dead_comp \
        == 1e-6


@pytest.mark.parametrize("which", ["table1", "lcl"])
def test_row8_warm_start_applies_its_steady_state_from_the_first_sample(which):
    """A warm start applied the zero vector during the first period: i_q
    fell 6.497 -> 5.304 A (Table I, 1000 r/min) and 10.75 -> 2.80 A (the
    LCL drive at 60 kr/min). Now the period before the first sample applies
    the steady-state voltage of the initial condition: on an ideal plant
    (no dead time, exact ADC) the first sample's current is within 1 % of
    the initial one (Table I: the first ten samples; the LCL drive: the
    first, after which its PI and its observer, which start without an EMF
    estimate, move it by up to 11 % within 6 samples, instead of the zero
    vector's -74 % in one)."""
    if which == "table1":
        s = Scenario(duration=0.01, w_M0=1000 * RPM, w_M_ref=Profile.const(1000 * RPM),
                     load=LoadCfg(T_brake=Profile.const(MotorPars().T_N)),
                     inverter=InverterCfg(t_dead=0.0, pwm="averaged"))
        s = s.replace(adc=dataclasses.replace(s.adc, noise=0.0, bits=0))
        n, tol = 10, 0.01
    else:
        s = drive.lcl_encoder()
        s = s.replace(duration=0.01, adc=dataclasses.replace(
            s.adc, noise=0.0, bits=0, gain=(1.0, 1.0, 1.0), gain_i1=(1.0, 1.0, 1.0)),
            inverter=dataclasses.replace(s.inverter, t_dead=0.0))
        n, tol = 2, 0.01
    r = simulate(s)
    i_q = r["i_q"]
    assert i_q[0] > 1.0
    assert np.max(np.abs(i_q[:n] / i_q[0] - 1)) < tol


# --------------------------------------- three motors from a data sheet --

@pytest.mark.parametrize("path", DATASHEET, ids=[p.stem for p in DATASHEET])
def test_data_sheet_motor_runs_the_usual_profile(path):
    """I/f start, steps to +50 % and +100 % rated speed, a rated brake step
    on and off, a reversal through zero to -50 % and -100 %, sensorless
    robust DBPC, every controller value derived, over 10 noise seeds: no run
    ends wrong in silence, and at least 9 of 10 reach their reference
    (measured: 10 of 10 each, 2026-11-26; the 5 uH multirotor motor, added
    2026-11-27, 10 of 10 once the SMDO's filter gain w_c was derived for its
    electrical speed: with Table I's 1500 rad/s it lost its lock on every
    seed, and its angle swung by 22 deg RMS at status 0 at 3/4 of rated
    speed)."""
    base = load_scenario(path)
    assert base.controller.derived  # nothing set by hand
    outcomes = [trials.judge(simulate(trials.profile_scenario(base, seed)))
                for seed in range(1, 11)]
    verdicts = [o.verdict for o in outcomes]
    print(path.stem, verdicts.count("reached"), "of 10 reached;",
          "; ".join(str(o) for o in outcomes if o.verdict != "reached"))
    assert "silent" not in verdicts
    assert verdicts.count("reached") >= 9


# ------------------------------------------------- detection figures --

def test_locked_rotor_at_start_is_flagged_within_200_ms():
    """A rotor that cannot turn (held by a 1000 N m brake, 65 x the rated
    torque) under an I/f start of the sensorless Table I drive:
    SMD_FAULT_START within 200 ms (the forced speed passes w_M_if_enter,
    210 r/min, after 70 ms at 3000 r/min/s, then t_lock = 20 ms of an EMF
    estimate below a third of |w_f| psi); the drive restarts on I/f twice
    (restart_max = 2: the sample of each restart reports start_failed with
    restart) and then latches start_failed."""
    s = Scenario(duration=0.4, warm_start=False, w_M_ref=Profile.const(1500 * RPM),
                 load=LoadCfg(T_brake=Profile.const(1000.0)),
                 controller=ControllerCfg(current="robust_dbpc", position="smdo_emf",
                                          start="if"))
    r = simulate(s)
    assert fault_names(r.faults.first) == ["start_failed", "restart"]
    assert r.faults.t_first <= 0.2
    assert fault_names(r.faults.final) == ["start_failed"]
    events = r["fault"].astype(int)
    assert np.count_nonzero(events & 2048) == 2  # two restarts, then latched


@pytest.mark.parametrize("path", REPO_MOTORS, ids=[p.stem for p in REPO_MOTORS])
def test_no_false_trip_in_random_operation(path):
    """Random speed steps (uniform in +-w_M_N) and brake steps (uniform in
    [0, T_N]), 20 of each a minute, I/f start, sensorless robust DBPC, every
    value derived, one simulated hour (60 runs of a minute): no run ends in
    a fault, none ends away from its reference (over the last 0.3 s of each
    minute, when the last reference step had its slew-limited ramp and one
    second more, and the reference is at least the handover speed: within
    2 %). Table I and the 10 kW machine run without an event (seed 7; the
    benchmark's seed 11 gives the 10 kW machine 3 restarts in an hour, each
    an I/f rotor pulled out under a near-rated brake and started again:
    at most 6 allowed); the 200 W servo's light rotor
    (J = 4e-5 kg m^2: a rated brake step at low speed stops it in 4 ms,
    faster than its 300 rad/s speed loop and the SMDO's 2 ms speed filter
    can answer) loses the rotor on some brake steps, and the drive restarts
    it on I/f (restart_max = 2 within 2 s): the events are reported (the
    SMDO's angle jumping as it loses a rotor near zero speed, the restart
    with its cause) and the run goes on to its reference (measured: 24 runs
    with an event of 60, at most 36 allowed). `benchmarks/bench_false_trips.py`
    prints the counts over longer runs."""
    base = load_scenario(path)
    rng = np.random.default_rng(7)
    ended_in_fault, restarted, off = [], 0, []
    for k in range(60):
        s = trials.random_profile(base, rng, seed=k + 1)
        r = simulate(s)
        if r.faults.final:
            ended_in_fault.append(fault_names(r.faults.final))
        restarted += bool(r.faults.first)  # an event the run went on from
        last_change, step = max((t, abs(b - a)) for t, a, b in zip(
            s.w_M_ref.t[1:], s.w_M_ref.y, s.w_M_ref.y[1:]) if a != b)
        settle = step / s.controller.a_M_ref + 1.0  # the slew-limited ramp, then 1 s
        # (below the handover speed the drive is on I/f, whose rotor swings
        # about the forced speed, undamped: not judged by its mean)
        if s.duration - last_change > settle and \
                abs(s.w_M_ref.y[-1]) >= s.controller.w_M_handover:
            m = r.t >= s.duration - 0.3
            ref = s.w_M_ref.y[-1]
            if abs(np.mean(r["w_M"][m]) - ref) > 0.02 * max(abs(ref), 0.1 * s.motor.w_M_N):
                off.append(k)
    print(path.stem, f"{restarted} of 60 runs with an event")
    assert ended_in_fault == [] and off == []
    assert restarted <= (36 if "servo" in path.stem else 6)


def test_cli_exits_non_zero_and_says_why_on_a_named_fault(tmp_path):
    """The locked-rotor start as a file: `smodrive run` exits 1 with one
    `error:` line naming the fault; the summary on stdout names it too."""
    f = tmp_path / "locked.toml"
    f.write_text("duration = 0.5\nwarm_start = false\nw_M_ref_rpm = 1500.0\n"
                 "[controller]\ncurrent = \"robust_dbpc\"\nposition = \"smdo_emf\"\n"
                 "start = \"if\"\n[load]\nT_brake = 1000.0\n")
    res = CliRunner().invoke(main, ["run", str(f), "--out", str(tmp_path / "o")])
    assert res.exit_code == 1
    assert "start_failed" in res.stderr
    summary = json.loads(res.stdout)
    assert summary["final_fault"] == ["start_failed"]


def test_the_return_to_if_starts_at_the_rotors_speed():
    """The invented 30,000 r/min spindle (tests/motors/spindle_48v_30krpm.toml)
    reversing: the drive returns to I/f below w_M_if_enter while its slewed
    reference still decelerates at a_M_ref. The SMDO's speed estimate,
    low-passed at w_lpf, lags the rotor by a_M_ref / w_lpf there (the derived
    a_M_ref allows a quarter of w_M_if_enter); the forced frame started at
    the estimate, 33 % faster than the light rotor, which slipped
    (start_failed on every seed). It now starts within 5 % of the rotor's
    speed (the estimate less that lag; what is left is the rotor's own lag
    behind the slewed reference)."""
    base = load_scenario(ROOT / "tests" / "motors" / "spindle_48v_30krpm.toml")
    s = trials.profile_scenario(base, 1)
    r = simulate(s)
    ph = r["phase"]
    k = next(k for k in range(1, len(ph)) if ph[k] == 0 and ph[k - 1] == 2)
    n_p = base.motor.n_p
    w_f, w_M = r["w_hat"][k] / n_p, r["w_M"][k]
    lag = s.controller.a_M_ref / s.controller.w_lpf
    assert 0.2 * w_M < lag  # (the estimate's lag is a fifth of the speed and more here)
    assert abs(w_f / w_M - 1.0) < 0.05, (w_f, w_M, lag)
    assert trials.judge(r).verdict == "reached"


def test_the_sensorless_angle_error_leaves_out_the_handovers_forced_angle():
    """The log's phase is the drive's at the end of a step, its angle the one
    the step used: the step that hands over logs phase 2 with the forced
    start's angle. Table I's I/f start, every sample logged: that sample is
    16 deg off, the next within 1 deg; trials.sensorless_angle_rms leaves it
    out (a profile logged every 12th sample read +87 % when the stride fell
    on it) and is the RMS of the others, which the plain phase-2 mask is not."""
    from smodrive.scenarios import drive

    r = simulate(drive.if_start().replace(log_stride=1))
    ph = r["phase"]
    i = int(np.nonzero(np.diff(ph))[0][0]) + 1
    assert ph[i - 1] == 0 and ph[i] == 2 and ph[i + 1] == 2
    e = np.degrees(np.abs(r.theta_error))
    assert e[i] > 10.0 and e[i + 1] < 1.0
    after = np.arange(len(ph)) > i
    want = float(np.sqrt(np.mean(r.theta_error[(ph == 2) & after] ** 2)))
    assert trials.sensorless_angle_rms(r) == pytest.approx(want, rel=1e-12)
    assert float(np.sqrt(np.mean(r.theta_error[ph == 2] ** 2))) > 1.05 * want


# ------------------------------------- held off its reference: says why --

#: an invented 700 V, 5 kW direct drive (14 pole pairs, 300 r/min, 1.2 ohm, 15 mH,
#: 0.75 Wb, a 0.5 kg m^2 table), started sensorless on I/f toward rated speed
DIRECT_DRIVE = {"warm_start": False, "duration": 2.0, "w_M_ref_rpm": 300.0,
                "motor": {"R_s": 1.2, "L_s": 15e-3, "psi_r": 0.75, "n_p": 14, "J": 0.5,
                          "P_N": 5000.0, "w_M_N_rpm": 300.0},
                "inverter": {"u_dc": 700.0, "t_dead": 2e-6},
                "controller": {"current": "robust_dbpc", "position": "smdo_emf",
                               "start": "if"}}


def test_a_load_the_current_limit_cannot_carry_ends_in_speed_tracking_through_adc_noise():
    """The direct drive under a fan load of 5 T_N at rated speed (k_fan =
    5 T_N / w_N^2): the current limit's torque (2.4 T_N) balances the fan at
    sqrt(2.4 / 5) = 0.69 w_N, 31 % below the reference and beyond w_M_track
    (10 % of rated), the speed PI at its limit. The ADC's noise (the derived
    0.1 % of full scale) takes the PI's output off its limit for a sample now
    and then (here on more than 100 samples before the trip): a count reset
    by each never reached t_track (118 ms; the longest unbroken stretch at
    the limit was 10 ms, and the run ended 31 % low with status 0). The
    count now holds while the speed is away: speed_tracking, latched, within
    t_track of the speed falling w_M_track behind plus the spread of the
    dips (0.6 s of the run at most), and a non-zero status."""
    s = scenario_from_dict(DIRECT_DRIVE | {"load": {"k_fan": 0.0}})
    T_N, w_N = s.motor.T_N, s.motor.w_M_N
    s = s.replace(load=dataclasses.replace(s.load, k_fan=5.0 * T_N / w_N ** 2))
    r = simulate(s)
    assert fault_names(r.faults.final) == ["speed_tracking"]
    assert r.status != 0
    t_trip = r.faults.t_first
    i_lim = 0.999 * s.controller.i_max
    away = (np.abs(r["w_M_ref"] - r["w_M"]) > s.controller.w_M_track) & (r["phase"] == 2) \
        & (r.t < t_trip)
    off_limit = away & (np.abs(r["i_q_ref"]) < i_lim)
    assert np.count_nonzero(off_limit) > 100  # (the dips the reset count stopped at)
    assert t_trip - r.t[np.argmax(away)] < s.controller.t_track + 0.6


def test_a_start_that_keeps_failing_latches_instead_of_restarting_for_ever():
    """An invented 500 W fan motor (325 V, 5 pole pairs, 3 ohm, 20 mH, 0.19 Wb,
    J 0.02) reversed from rated speed to minus rated with the reference's slew
    limit off (a_M_ref = 0): the reversal's I/f start fails, and restarts
    fail again about once a second, each from the forced phase. The restart
    count leaked restart_max / t_restart (1 a second) on every sample, so
    the drive restarted for ever (29 restarts in 28 s, ending at +0.08 w_N
    against -w_N with status 0). It now leaks only while the drive runs on
    its source: restart_max (2) restarts that never hand over, then
    start_failed latches, within 4 s of the first."""
    s = scenario_from_dict({
        "warm_start": False, "duration": 16.0,
        "w_M_ref_rpm": {"t": [0.0, 0.0, 5.74779, 5.74779, 9.57966, 9.57966],
                        "y": [0.0, 450.0, 450.0, 1500.0, 1500.0, -1500.0]},
        "motor": {"R_s": 3.0, "L_s": 20e-3, "psi_r": 0.19, "n_p": 5, "J": 0.02,
                  "P_N": 500.0, "w_M_N_rpm": 1500.0},
        "inverter": {"u_dc": 325.0, "t_dead": 2e-6},
        "controller": {"current": "robust_dbpc", "position": "smdo_emf", "start": "if",
                       "a_M_ref": 0.0}})
    r = simulate(s)
    events = r["fault"].astype(int)
    restarts = r.t[(events & 2048) != 0]
    assert fault_names(r.faults.final) == ["start_failed"]
    assert r.status != 0
    assert len(restarts) == s.controller.restart_max
    t_latched = r.t[np.argmax(r["status"] != 0)]
    assert t_latched - restarts[0] < 4.0


#: an invented 12 V, 150 W wet-rotor pump (4 pole pairs, 30 mohm, 40 uH, 3.5 mWb)
PUMP = {"warm_start": False, "duration": 1.5, "w_M_ref_rpm": 450.0,
        "motor": {"R_s": 0.03, "L_s": 40e-6, "psi_r": 0.0035, "n_p": 4, "J": 3e-5,
                  "P_N": 150.0, "w_M_N_rpm": 3000.0},
        "inverter": {"u_dc": 12.0, "t_dead": 0.5e-6},
        "controller": {"current": "robust_dbpc", "position": "smdo_emf", "start": "if"}}


def test_a_reference_held_below_the_handover_speed_is_named_before_the_run():
    """The pump's derived handover is 1,186 r/min (the back EMF the SMDO needs
    against its dead time and noise); asked to hold 450 r/min from an I/f
    start, the drive ran its whole run on I/f, open loop at i_start (1.6
    I_N, whatever the load; 51 deg RMS off the rotor's angle) with status 0
    and nothing said. A warning now names the reference, the handover speed
    and the start current before the run; at 1,500 r/min, and on the encoder,
    there is none."""
    s = scenario_from_dict(PUMP)
    with pytest.warns(UserWarning, match=r"holds 450 r/min, below the handover speed "
                                         r"controller.w_M_handover = 1186 r/min"):
        s.check_controller()
    assert s.held_below_handover() == pytest.approx(450.0 * RPM)
    for other in (PUMP | {"w_M_ref_rpm": 1500.0},
                  PUMP | {"controller": PUMP["controller"] | {"position": "encoder"}}):
        assert scenario_from_dict(other).held_below_handover() is None


def test_the_usual_profile_says_it_replaces_the_scenarios_load():
    """`--profile usual` runs its own load (the rated brake on and off): a fan
    motor's file ran without its fan and was judged "reached" without a word.
    It now says which of the file's load it leaves out; a file without a
    load, nothing."""
    s = scenario_from_dict(PUMP | {"load": {"k_fan": 1e-5}})
    with pytest.warns(UserWarning, match=r"in place of the scenario's \[load\] \(k_fan = 1e-05\)"):
        trials.profile_scenario(s)
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        trials.profile_scenario(scenario_from_dict(PUMP | {"w_M_ref_rpm": 1500.0}))
