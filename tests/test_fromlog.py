"""R_s, L_s and psi_r from a running drive's log (issue 23,
``smodrive identify --from-log``; smodrive.fromlog).

The logs are the simulator's own runs of the usual profile (start on I/f,
speed steps, rated load, reversal; smodrive.scenarios.trials) written as a
drive logs itself: the ADC's phase currents, the duties it applied (with
its dead-time compensation) and the DC-link voltage; the plant's 0.5-2 us
of dead time is in them. The fit sees neither the plant nor the drive.

Budgets (smodrive's choice for a log: the issue sets the accuracy of the
commissioning tests, not of a log's): psi_r within 2 % and L_s within 5 %,
commissioning's own; R_s within 5 %, wider than commissioning's 2 %
because in a drive's log R_s i and the inverter's drop are nearly
collinear and the drop's fade near zero current is not known (the fit's
interval spans the shapes it tries: +-9 % of R_s on Table I's motor). The
intervals are statistical: the model's bias is not in them (the value can
sit just outside a narrow interval; docs/commissioning.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from smodrive import fromlog as F
from smodrive.cli import main
from smodrive.engine import simulate
from smodrive.model import ParameterError
from smodrive.scenario_io import load_scenario
from smodrive.scenarios import trials

ROOT = Path(__file__).resolve().parents[1]
MOTORS = ["yang2018_table1", "servo_48v_200w", "industrial_600v_10kw"]


def _run(name: str):
    s = trials.profile_scenario(load_scenario(ROOT / "scenarios/motors" / f"{name}.toml"))
    return simulate(s.replace(log_stride=1))


def _check(fit, m, L_known: bool):
    assert abs(fit.R_s.value / m.R_s - 1.0) < 0.05, fit.R_s
    assert abs(fit.psi_r.value / m.psi_r - 1.0) < 0.02, fit.psi_r
    if not L_known:
        assert abs(fit.L_s.value / m.L_s - 1.0) < 0.05, fit.L_s
    for e in (fit.R_s, fit.L_s, fit.psi_r):
        assert e.lo <= e.value <= e.hi
    assert fit.ok


@pytest.mark.parametrize("name", MOTORS)
def test_from_a_log_with_the_rotor_angle(name):
    r = _run(name)
    cols = F.drive_log_columns(r)
    cols["theta"] = r["theta_r"]
    fit = F.fit_log(F.log_from_columns(cols))
    assert fit.angle == "log"
    _check(fit, r.scenario.motor, L_known=False)


@pytest.mark.parametrize("name", MOTORS)
def test_from_a_sensorless_log_with_the_inductance_given(name):
    """No angle column: the rotor's frame is the EMF's, from the fit's own
    EMF (its fixed point); the inductance is given, as `identify` measures
    it (without it the inductance and the angle trade off: refused)."""
    r = _run(name)
    log = F.log_from_columns(F.drive_log_columns(r))
    with pytest.raises(ParameterError, match="L_s"):
        F.fit_log(log)
    fit = F.fit_log(log, L_s=r.scenario.motor.L_s)
    assert fit.angle == "estimated"
    _check(fit, r.scenario.motor, L_known=True)


def test_the_drop_is_in_the_fit():
    """The duties are not the voltages: the inverter loses t_d / T_sp u_dc
    per leg against the current (2 us at 540 V, 10 kHz: 10.8 V on Table I's
    plant). A fit without the drop puts it into R_s (a drop along the
    current is a resistance of u_0 / |i|); the fit's u_0 is within 10 % of
    it (its fade near zero current is fitted by shape, not known)."""
    r = _run("yang2018_table1")
    s = r.scenario
    cols = F.drive_log_columns(r)
    cols["theta"] = r["theta_r"]
    fit = F.fit_log(F.log_from_columns(cols))
    u0 = s.inverter.t_dead / s.T_sp * s.inverter.u_dc
    assert fit.u_0.value == pytest.approx(u0, rel=0.10)


def test_cli_from_a_csv_log(tmp_path):
    r = _run("servo_48v_200w")
    m = r.scenario.motor
    log = F.write_csv(F.drive_log_columns(r), tmp_path / "drive.csv")
    out = tmp_path / "motor.toml"
    res = CliRunner().invoke(main, ["identify", "--from-log", str(log), "--L-s",
                                    str(m.L_s), "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert "R_s" in res.output and "psi_r" in res.output and "from the EMF" in res.output
    from smodrive._util import tomllib
    data = tomllib.loads(out.read_text())["motor"]
    assert data["R_s"] == pytest.approx(m.R_s, rel=0.05)
    assert data["psi_r"] == pytest.approx(m.psi_r, rel=0.02)
    # a bad log names what is wrong, with no traceback
    bad = tmp_path / "bad.csv"
    bad.write_text("t,i_a\n0,1\n")
    res = CliRunner().invoke(main, ["identify", "--from-log", str(bad)])
    assert res.exit_code == 2 and "i_b" in res.output and "Traceback" not in res.output
    res = CliRunner().invoke(main, ["identify", "--from-log", str(log)])
    assert res.exit_code == 2 and "L_s" in res.output
    res = CliRunner().invoke(main, ["identify"])
    assert res.exit_code == 2 and "--from-log" in res.output


def test_a_log_that_is_not_uniform_or_not_finite_is_named():
    t = np.arange(2000) * 1e-4
    cols = {"t": t, "i_a": np.zeros_like(t), "i_b": np.zeros_like(t),
            "d_a": np.full_like(t, 0.5), "d_b": np.full_like(t, 0.5),
            "d_c": np.full_like(t, 0.5), "u_dc": np.full_like(t, 48.0)}
    bad = dict(cols, t=t * np.r_[1.0, np.ones(1998), 1.5])
    with pytest.raises(ParameterError, match="not uniform"):
        F.log_from_columns(bad)
    bad = dict(cols, i_a=np.r_[np.zeros(1999), np.nan])
    with pytest.raises(ParameterError, match="'i_a' is not finite at row 1999"):
        F.log_from_columns(bad)
    bad = dict(cols, d_a=np.full_like(t, 1.5))
    with pytest.raises(ParameterError, match="outside"):
        F.log_from_columns(bad)
