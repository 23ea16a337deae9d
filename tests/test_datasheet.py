"""A data sheet's quantities in [motor] (smodrive.model.datasheet): an
unknown [motor] key that a data sheet uses is told what it is in
smodrive's model, not only the list of known keys."""

from __future__ import annotations

import math

import pytest
from click.testing import CliRunner

from smodrive.cli import main
from smodrive.model import RPM, MotorPars
from smodrive.model.datasheet import HINTS, hint


@pytest.mark.parametrize("key, want", [
    ("poles", "n_p = poles / 2"), ("Pole_Pairs", "did you mean n_p"),
    ("K_t", "K_t / (1.5 sqrt(2) n_p) per ampere RMS"), ("Ke", "sqrt(3/2) n_p 104.72"),
    ("L_d", "L_s = L_q is the nearest"), ("Lq", "surface-PM"), ("R_LL", "R_s = R_LL / 2"),
    ("Ls", "did you mean L_s?"), ("I_N", "P_N = T_N w_M_N"), ("J_load", "did you mean J")])
def test_a_data_sheets_key_is_told_what_it_is(tmp_path, key, want):
    f = tmp_path / "m.toml"
    f.write_text(f"[motor]\n{key} = 1.0\n")
    res = CliRunner().invoke(main, ["run", str(f), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and f"motor.{key}: unknown parameter" in res.output
    assert want in res.output and "Traceback" not in res.output, res.output


def test_other_unknown_keys_and_sections_get_no_hint():
    assert hint("foo") == "" and hint("T_sp_x") == ""


def test_the_constants_conversions_agree_with_the_textbook_identity():
    """The hints' conversions, as their texts state them, on a motor of
    psi_r = 0.0565 Wb and 4 pole pairs: K_t per ampere RMS (1.5 sqrt 2 n_p
    psi_r) and K_e in volts line to line RMS per 1,000 r/min (sqrt(3/2) n_p
    w psi_r) obey K_t = sqrt 3 K_e / w_1000 (N m / A_rms against V s / rad,
    a sinusoidal PM motor's identity); the torque constant per ampere of
    peak is the model's k_t (T = 1.5 n_p psi_r i_q)."""
    n_p, psi = 4, 0.0565
    w1000 = 1000.0 * RPM
    assert "104.72" in HINTS["ke"] and abs(w1000 - 104.72) < 0.005
    k_t_rms = 1.5 * math.sqrt(2.0) * n_p * psi
    k_e = math.sqrt(1.5) * n_p * w1000 * psi
    assert math.isclose(k_t_rms, math.sqrt(3.0) * k_e / w1000, rel_tol=1e-12)
    m = MotorPars(R_s=1.0, L_s=1e-3, psi_r=psi, n_p=n_p, J=1e-3, P_N=100.0, w_M_N=300.0)
    assert math.isclose(m.k_t, k_t_rms / math.sqrt(2.0), rel_tol=1e-12)


def test_a_motor_without_its_dc_link_is_told_which_it_runs_on():
    """A 12 V gimbal motor's file without [inverter] ran on yang2018 Table
    I's 540 V without a word; its own motor without u_dc is now warned,
    naming the 540 V; with u_dc, or Table I's own motor, it is not."""
    import warnings

    from smodrive.scenario_io import scenario_from_dict

    gimbal = {"R_s": 5.0, "L_s": 2e-3, "psi_r": 0.010, "n_p": 7, "J": 1e-4, "P_N": 2.0,
              "w_M_N_rpm": 600.0}
    for data, want in (({"motor": gimbal}, True),
                       ({"motor": gimbal, "inverter": {"t_dead": 1e-6}}, True),
                       ({"motor": gimbal, "inverter": {"u_dc": 12.0}}, False),
                       ({"inverter": {"t_dead": 1e-6}}, False)):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            scenario_from_dict(data)
        said = [str(x.message) for x in w if "inverter.u_dc is not given" in str(x.message)]
        assert bool(said) == want, data
        assert not said or "Table I's 540 V is assumed" in said[0]


@pytest.mark.parametrize("key, want", [("f_sw", "the top-level T_sp = 1 / f_sw"),
                                       ("Vdc", "did you mean u_dc"),
                                       ("deadtime", "did you mean t_dead")])
def test_an_inverter_key_of_another_tool_is_told_where_it_goes(tmp_path, key, want):
    """[inverter] f_sw (the switching frequency is the scenario's T_sp) and
    other tools' names got the list of known keys only."""
    f = tmp_path / "m.toml"
    f.write_text(f"[inverter]\n{key} = 1.0\n")
    res = CliRunner().invoke(main, ["run", str(f), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and f"inverter.{key}: unknown parameter" in res.output
    assert want in " ".join(res.output.split())
