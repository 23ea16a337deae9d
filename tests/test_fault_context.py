"""What the drive was doing before its first fault (summary.json's
``fault_context``, analysis.summary.fault_context): an overload is named as
one, not only by the fault it led to."""

from __future__ import annotations

import json

from click.testing import CliRunner

from smodrive.cli import main

from test_cli import SERVO_320, SERVO_560

#: the sensorless drive with an I/f start
SENSORLESS = '[controller]\ncurrent = "robust_dbpc"\nposition = "smdo_emf"\nstart = "if"\n'
#: the invented 320 V servo sensorless at 1,500 r/min, braked from 2 s on; its derived
#: i_max is 7.813 A, a torque of 1.5 n_p psi_r i_max = 1.5 x 4 x 0.12 x 7.813 = 5.625 Nm
BRAKED = ("warm_start = false\nduration = 4.0\nw_M_ref_rpm = 1500.0\n" + SERVO_320 +
          "[load]\nT_brake = { t = [0, 2.0, 2.0], y = [0, 0, BRAKE] }\n" + SENSORLESS)


def _run_toml(tmp_path, name: str, text: str):
    """`smodrive run` of scenario `text`: the CLI's result and summary.json."""
    src, out = tmp_path / f"{name}.toml", tmp_path / f"o_{name}"
    src.write_text(text)
    res = CliRunner().invoke(main, ["run", str(src), "--out", str(out)])
    return res, json.loads((out / "summary.json").read_text())


def _run(tmp_path, brake: float):
    return _run_toml(tmp_path, f"braked_{brake:g}", BRAKED.replace("BRAKE", repr(brake)))


def test_an_overload_is_named_as_one(tmp_path):
    """A brake of 6 Nm, 7 % beyond the 5.625 Nm the drive gives at i_max:
    the speed falls with the current reference on i_max, and the run ends
    in a fault (speed_tracking); its error and summary say that the current
    was on i_max before it, with the torque it gives: an overload."""
    res, summary = _run(tmp_path, 6.0)
    assert res.exit_code == 1 and summary["ends_in_fault"], res.output
    ctx = summary["fault_context"]
    assert ctx and "controller.i_max = 7.813 A" in ctx and "= 5.625 Nm (an overload)" in ctx
    assert "(an overload)" in res.output and "Traceback" not in res.output


def test_a_load_within_the_torque_has_no_fault_context(tmp_path):
    """A brake of 2 Nm (0.36 of the 5.625 Nm): no fault, no context."""
    res, summary = _run(tmp_path, 2.0)
    assert res.exit_code == 0 and not summary["first_fault"], res.output
    assert summary["fault_context"] is None


#: an invented 700 V, 5 kW direct drive (14 pole pairs, 1.2 ohm, 15 mH, 0.75 Wb, J 0.5
#: kg m^2) at 150 r/min, sensorless, a brake of 3 T_N (477.5 Nm) from 1.11 s; its derived i_max
#: 23.81 A gives 1.5 x 14 x 0.75 x 23.81 = 375 Nm
DIRECT_DRIVE = """warm_start = false
duration = 1.6
w_M_ref_rpm = 150.0
[motor]
R_s = 1.2
L_s = 15e-3
psi_r = 0.75
n_p = 14
J = 0.5
P_N = 5000.0
w_M_N_rpm = 300.0
[inverter]
u_dc = 700.0
t_dead = 2e-6
[load]
T_brake = { t = [0, 1.1105, 1.1105], y = [0, 0, 477.465] }
""" + SENSORLESS


def test_a_stall_too_short_to_hold_the_current_limit_is_named_an_overload(tmp_path):
    """The brake stops the rotor in 45 ms, its current on i_max for 16 % of
    the 0.2 s before the first fault (below the share that names it); the
    drive returns to I/f and fails its start against the brake
    (start_failed). The load torque the simulation applied, 477.5 Nm against
    the drive's 375 Nm, names the overload."""
    res, summary = _run_toml(tmp_path, "dd", DIRECT_DRIVE)
    assert res.exit_code == 1 and "start_failed" in summary["final_fault"], res.output
    ctx = summary["fault_context"]
    assert ctx and "the load's torque reached 477.5 Nm" in ctx and "= 375 Nm (an overload)" in ctx


def test_a_start_against_its_load_is_told_the_start_current_that_carries_it(tmp_path):
    """The servo started sensorless against an opposing 3.3 Nm, 0.88 of the
    3.75 Nm its derived i_start (5.208 A) gives: the I/f start pulls out
    (start_failed). Its error gives the share and the i_start that carries
    the load at START_CARRY (0.7) of its torque, 3.3 / (0.7 x 0.72) = 6.548 A;
    with it, the start succeeds. (0.7 is measured: a 6.0 A start, 0.76,
    pulls out.)"""
    from smodrive.analysis.summary import START_CARRY

    assert START_CARRY == 0.7
    base = ("warm_start = false\nduration = 1.5\nw_M_ref_rpm = 1500.0\n" + SERVO_320 +
            "[load]\nT_ext = 3.3\n" + SENSORLESS)
    runs = {name: _run_toml(tmp_path, name, base + extra)[0]
            for name, extra in (("derived", ""), ("told", "i_start = 6.548\n"),
                                ("less", "i_start = 6.0\n"))}
    out = runs["derived"].output
    assert runs["derived"].exit_code == 1 and "start_failed" in out
    assert "0.88 of the 3.75 Nm its current controller.i_start = 5.208 A gives" in out
    assert "controller.i_start of 6.548 A or more (at most i_max = 7.813 A) starts it" in out
    assert runs["told"].exit_code == 0, runs["told"].output
    assert runs["less"].exit_code == 1 and "start_failed" in runs["less"].output


#: test_cli's invented 560 V servo on 280 V at rated speed, the rated brake from 1 s
LOW_DC_560 = ("warm_start = false\nduration = 2.5\nw_M_ref_rpm = 3000.0\n"
              + SERVO_560.replace("u_dc = 560.0", "u_dc = 280.0")
              + "[load]\nT_brake = { t = [0, 1.0, 1.0], y = [0, 0, 9.549] }\n" + SENSORLESS)


def test_a_drive_on_its_voltage_limit_is_not_called_overloaded(tmp_path):
    """An invented 560 V, 3 kW servo (5 pole pairs, 0.12 Wb) on 280 V, asked
    for rated speed with the rated brake from 1 s: its back-EMF alone at
    3,000 r/min is 188.5 V against 161.7 V, the voltage rides the limit, its
    current does not follow the 25 A its speed PI asks, and it ends in
    speed_tracking. Its error had called it an overload (the reference on
    i_max) at rated load; it now names the voltage limit and the DC link."""
    res, summary = _run_toml(tmp_path, "lowdc", LOW_DC_560)
    assert res.exit_code == 1 and summary["final_fault"] == ["speed_tracking"], res.output
    ctx = summary["fault_context"]
    assert "its current did not follow its reference" in ctx and "inverter.u_dc = 280 V" in ctx
    assert "overload" not in ctx



def test_an_overcurrent_names_its_trip_and_where_it_comes_from(tmp_path):
    """The 560 V servo's P_N written in kW (3.0): its rated current is
    P_N / w_M_N / (1.5 n_p psi_r) = 3 / 314.16 / 0.9 = 10.61 mA, its derived
    i_max 25 mA and trip 2.5 i_max = 62.5 mA; the start trips at once. The
    error named no threshold; it now gives the trip, i_max and I_N."""
    res, summary = _run_toml(tmp_path, "kw", LOW_DC_560.replace("P_N = 3000.0", "P_N = 3.0")
                             .replace("u_dc = 280.0", "u_dc = 560.0")
                             .replace("duration = 2.5", "duration = 0.05")
                             .replace("w_M_ref_rpm = 3000.0", "w_M_ref_rpm = 1500.0"))
    ctx = summary["fault_context"]
    assert res.exit_code == 1 and "overcurrent" in res.output, res.output
    assert ctx == ("a phase current passed the overcurrent trip, 0.0625 A: 2.5 controller.i_max "
                   "(i_max = 0.025 A, derived from the rated current I_N = 0.01061 A: "
                   "motor.P_N / motor.w_M_N over 1.5 n_p psi_r)")


def test_an_overload_on_an_i_max_the_sensors_limit_names_them(tmp_path):
    """The servo on 6 A current sensors, an opposing torque of 6 Nm from 2 s
    (load.T_ext: it does not taper at standstill as the brake does): its
    i_max is limited to 0.9 x 6 = 5.4 A, 3.888 Nm. The overload names i_max
    and that the sensors' range limited it (it named the derived 5.4 A only,
    not the setting the user changed)."""
    res, summary = _run_toml(tmp_path, "fs6", BRAKED.replace("BRAKE", "6.0")
                             .replace("T_brake", "T_ext") + "[adc]\nfull_scale = 6.0\n")
    ctx = summary["fault_context"]
    assert res.exit_code == 1, res.output
    assert "controller.i_max = 5.4 A (scaled by I_N = T_N / k_t, limited to 0.9 " \
           "adc.full_scale), 1.5 n_p psi_r i_max = 3.888 Nm (an overload)" in ctx
