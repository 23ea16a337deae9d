"""What a run's speeds can reach (smodrive.model.reach), and a run still on
its slew-limited ramp (analysis.summary.off_reference).

An invented 320 V, 750 W servo (4 pole pairs, 0.12 Wb, 3,000 r/min) asked
for 1e7 r/min ran without a word, and ended 100 % off its reference at
status 0, its warning blaming a speed loop that had not settled."""

from __future__ import annotations

import math
import warnings

import pytest
from click.testing import CliRunner

from smodrive.analysis import summary as summ
from smodrive._util import tomllib
from smodrive.cli import main
from smodrive.model import RPM, ParameterError
from smodrive.scenario_io import scenario_from_dict

from test_cli import SERVO_320  # (the invented 320 V servo)

#: the servo's limits, from its data: the electrical Nyquist speed pi / (n_p T_sp) at the
#: default 100 us, 75,000 r/min; the no-load speed of its 320 V DC link, (320 / sqrt 3) /
#: (n_p psi_r) = 384.9 rad/s, 3,676 r/min
NYQ_RPM = math.pi / (4 * 1e-4) / RPM
DC_RPM = 320.0 / math.sqrt(3.0) / (4 * 0.12) / RPM


def _servo(rpm: float, sensorless: bool = False, duration: float = 1.0):
    d = tomllib.loads(SERVO_320)
    d["w_M_ref_rpm"], d["duration"] = rpm, duration
    if sensorless:
        d["controller"] = {"position": "smdo_emf", "current": "robust_dbpc", "start": "if"}
    return scenario_from_dict(d)


def _said(s) -> list[str]:
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        s.check_controller()
    return [str(x.message) for x in w]


def test_the_numbers_of_the_servo():
    assert abs(NYQ_RPM - 75000.0) < 1e-6 and abs(DC_RPM - 3676.0) < 0.5


def test_a_reference_beyond_the_sampled_drives_nyquist_speed_is_refused(tmp_path):
    """1e7 r/min turns the electrical angle 419 rad a sample (n_p w T_sp):
    refused, naming the key and the range +-75,000 r/min; the CLI says so in
    one line, exit 2, nothing simulated. Just below the bound it is not this
    error (only the warnings of the limits below it)."""
    with pytest.raises(ParameterError, match=r"w_M_ref reaches 1e\+07 r/min.*419 rad a sample"
                                             r".*within \+-7\.5e\+04 r/min"):
        _servo(1e7).check_controller()
    _said(_servo(0.99 * NYQ_RPM))  # (no error)
    src = tmp_path / "absurd.toml"
    src.write_text("w_M_ref_rpm = 1e7\n" + SERVO_320)
    res = CliRunner().invoke(main, ["run", str(src), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2, res.output
    assert "within +-7.5e+04 r/min" in res.output and "Traceback" not in res.output
    assert not (tmp_path / "o" / "summary.json").exists()


def test_a_reference_beyond_the_dc_link_is_warned():
    """6,000 r/min needs a back-EMF of 301.6 V alone, against the 184.8 V the
    320 V DC link makes: warned, with the no-load bound 3,676 r/min beyond
    which the drive runs on its voltage limit (a drone asked for 1.6 x rated
    past its bound reached it that way: the warning says "may"); rated
    speed (150.8 V) and 3,600 r/min (181.0 V) are not."""
    said = _said(_servo(6000.0))
    assert any("back-EMF alone, n_p w psi_r = 301.6 V" in m and "beyond about 3676 r/min" in m
               and "runs on its voltage limit" in m for m in said), said
    for rpm in (3000.0, 3600.0):
        assert not any("back-EMF alone" in m for m in _said(_servo(rpm)))


def test_a_sensorless_reference_beyond_w_M_max_is_warned():
    """The SMDO's speed estimate stops at controller.w_M_max (derived: twice
    rated, 6,000 r/min): a sensorless reference beyond it is warned, one at
    it is not. (Both are beyond the DC link's 3,676 r/min, also warned.)"""
    assert abs(_servo(3000.0, True).controller.w_M_max / RPM - 6000.0) < 1e-3
    assert any("beyond controller.w_M_max = 6000 r/min" in m
               for m in _said(_servo(6500.0, True)))
    assert not any("w_M_max" in m for m in _said(_servo(6000.0, True)))
    assert not any("w_M_max" in m for m in _said(_servo(6500.0)))  # (the encoder's: no limit)


def _summary_far_off(rpm: float) -> dict:
    """A summary that ends 40 % below `rpm`, no fault, neither limit held."""
    return {"ends_in_fault": False, "speed_error_rpm_last_20pct": -0.4 * rpm,
            "speed_rpm_mean_last_20pct": 0.6 * rpm, "speed_ref_rpm_mean_last_20pct": rpm,
            "phase_end": "observer", "voltage_limit_share_last_20pct": 0.0,
            "current_limit_share_last_20pct": 0.0}


def test_a_run_still_on_its_slewed_ramp_is_not_off_its_reference():
    """The sensorless servo's reference of 3,000 r/min from rest, slewed at
    its a_M_ref of 120.4 rad/s^2, is reached after 2.61 s: a run of 3 s ends
    on its ramp (from 2.4 s on), not off its reference; one of 4 s 40 % low
    is off it. (A constant reference's ramp from w_M0 had counted as
    reached at t = 0.)"""
    s = _servo(3000.0, True, duration=3.0)
    ramp = 3000.0 * RPM / s.controller.a_M_ref
    assert abs(ramp - 2.608) < 0.01 and abs(summ._slew_end(s) - ramp) < 2 * 3.0 / 4000
    assert summ.off_reference(s, _summary_far_off(3000.0)) is None
    s4 = _servo(3000.0, True, duration=4.0)
    assert summ.off_reference(s4, _summary_far_off(3000.0)).startswith(
        "the speed ends -40.0 % off its reference")
