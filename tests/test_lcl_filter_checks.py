"""A user's own LCL filter in a TOML scenario (docs/design_from_motor.md,
"The LCL drive"): a resonance the current loop cannot work with is said
before the run, an observer design that scipy cannot place robustly is one
warning naming the field, and an inductance beyond the decoupling's range is
refused naming the key the user wrote."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from click.testing import CliRunner

from smodrive.cli import main
from smodrive.engine import lcl_observer_tables, marshal
from smodrive.model import ParameterError
from smodrive.scenario_io import scenario_from_dict

LCL = 'base = "yao2022.base"\nduration = 0.01\n'


def _said(s) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        s.check_controller()
    return [str(w.message) for w in caught]


def _c1_for(f_res: float, s) -> float:
    """The capacitance that puts the plant's resonance at f_res (Hz):
    w^2 = (L1 + L2) / (L1 L2 C1), L2 = L2o + L_s (yao2022 Table II)."""
    L1, L2 = s.lcl.L1, s.lcl.L2o + s.motor.L_s
    return (L1 + L2) / (L1 * L2 * (2.0 * math.pi * f_res) ** 2)


def test_an_lcl_resonance_the_current_loop_cannot_work_with_is_said_before_the_run(tmp_path):
    """Each run with such a filter tripped overcurrent, named, with nothing
    said before. yao2022's drive (f_s = 20 kHz, rated f_e = 100,000 r/min x
    n_p 1 / 60 = 1667 Hz) acts 1.5 samples late: undamped (R_v = 0) its loop
    on the motor current is stable for f_s / 6 < f_res < f_s / 2 (yao2022 ref.
    [20]), each bound narrowed by f_e in the rotor frame: (5000, 8333) Hz;
    with active damping f_res + f_e < f_s / 6; and the resonance must lie
    above f_e. Table II's 5525 Hz fits."""
    base = scenario_from_dict({"base": "yao2022.base"})
    f_e = base.motor.n_p * base.motor.w_M_N / (2.0 * math.pi)
    f_s = 1.0 / base.T_sp
    assert (f_e, f_s) == (pytest.approx(1e5 / 60.0), pytest.approx(20e3))
    assert not [w for w in _said(base) if "resonates" in w]  # Table II: 5525 Hz

    def resonance(f_res: float, **controller) -> str:
        s = scenario_from_dict({"base": "yao2022.base", "lcl": {"C1": _c1_for(f_res, base)},
                                "controller": controller})
        said = [w for w in _said(s) if "resonates" in w]
        assert len(said) <= 1, said
        return said[0] if said else ""

    def bound(text: str, f: float) -> str:
        return f"{text} = {f:.4g} Hz"

    near_nyquist = resonance(9000.0)
    assert f"f_res = {9000.0:.4g} Hz" in near_nyquist
    assert bound("f_s / 2 - f_e", f_s / 2 - f_e) in near_nyquist
    assert "a larger lcl.C1 or lcl.L1" in near_nyquist
    undamped_low = resonance(4000.0)
    assert bound("f_s / 6 + f_e", f_s / 6 + f_e) in undamped_low
    assert "controller.R_v = 0" in undamped_low and "a smaller lcl.C1 or lcl.L1" in undamped_low
    assert resonance(6000.0) == ""  # within (5000, 8333)
    damped = resonance(2500.0, R_v=0.3)
    assert bound("f_s / 6 - f_e", f_s / 6 - f_e) in damped and "controller.R_v = 0.3" in damped
    below_rated = resonance(1500.0, R_v=0.3)
    assert "f_res = 1500 Hz" in below_rated
    assert bound("the rated electrical frequency f_e = n_p w_M_N / (2 pi)", f_e) in below_rated
    # `design` says it before anything else, as one warning line, and goes on
    p = tmp_path / "c1.toml"
    p.write_text(LCL + '[controller]\nposition = "encoder"\n[lcl]\n'
                 f'C1 = {_c1_for(9000.0, base)!r}\n')
    res = CliRunner().invoke(main, ["design", str(p)])
    assert res.exit_code == 0, res.output
    lines = [ln for ln in res.output.splitlines() if "resonates" in ln]
    assert len(lines) == 1 and lines[0].startswith("warning: "), res.output
    assert "Traceback" not in res.output


def _clear_table_caches() -> None:
    for f in (marshal.observer_tables, getattr(marshal, "_observer_tables", None)):
        if hasattr(f, "cache_clear"):
            f.cache_clear()


def test_an_observer_design_scipy_cannot_place_robustly_is_one_warning_naming_lcl_l1(
        tmp_path, monkeypatch, request):
    """A 1 H lcl.L1 flooded `design` with about 120 of scipy's raw warnings
    ("Convergence was not reached after maxiter iterations", one a pole
    placement at each speed of the tables). The design's step 3 reaches the
    filter's states through the capacitor only, within a sample as (w_1
    T_sp)^2, w_1 = 1 / sqrt(L1 C1) the inverter side's resonance: 50 us /
    sqrt(1 H x 31.48 uF) = 0.0089 rad (Table II: 1.2). Now one warning names
    lcl.L1. (Three speeds instead of the tables' 221: the same placements,
    a second instead of a minute.)"""
    monkeypatch.setattr(marshal, "TABLE_RPM", np.array([-50e3, 0.0, 50e3]))
    request.addfinalizer(_clear_table_caches)  # (tables of three speeds: no other test's)
    _clear_table_caches()
    s = scenario_from_dict({"base": "yao2022.base", "lcl": {"L1": 1.0}})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lcl_observer_tables(s)
    said = [str(w.message) for w in caught]
    assert len(said) == 1, said
    w1T = s.T_sp / math.sqrt(1.0 * s.lcl.C1)
    assert "lcl.L1 = 1.0 H leads there" in said[0] and f"w_1 T_sp = {w1T:.3g} rad" in said[0]
    assert "Convergence was not reached" not in said[0]
    # the CLI: one line of it, none of scipy's
    p = tmp_path / "l1.toml"
    p.write_text(LCL + "[lcl]\nL1 = 1.0\n")
    res = CliRunner().invoke(main, ["design", str(p)])
    assert res.exit_code == 0, res.output
    assert "Convergence was not reached" not in res.output and "You asked" not in res.output
    assert len([ln for ln in res.output.splitlines() if "lcl.L1 = 1.0 H leads" in ln]) == 1


def test_an_lcl_inductance_beyond_the_decoupling_range_is_named_by_its_own_key(tmp_path):
    """A 10 H lcl.L1 was refused as "controller.L_s_hat + lcl.L1 + lcl.L2o =
    10.0001 H is outside ...", a sum the user never wrote. The current PI
    decouples with the series inductance L1 + L2o + L_s_hat, at most 10 H
    (controller.L_dec's range): lcl.L1's valid range is [1e-8, 10 - L2o -
    L_s_hat] H."""
    s = scenario_from_dict({"base": "yao2022.base", "lcl": {"L1": 10.0}})
    top = 10.0 - s.lcl.L2o - s.controller.L_s_hat
    with pytest.raises(ParameterError) as ei:
        s.check_controller()
    assert str(ei.value).startswith(
        f"lcl.L1 = 10.0 H is outside its valid range [1e-08, {top:.6g}] H"), str(ei.value)
    p = tmp_path / "l1.toml"
    p.write_text(LCL + "[lcl]\nL1 = 10.0\n")
    for cmd in (["design", str(p)], ["run", str(p), "--out", str(tmp_path / "o")]):
        res = CliRunner().invoke(main, cmd)
        assert res.exit_code == 2, res.output
        assert "error: lcl.L1 = 10.0 H is outside its valid range" in res.output
        assert "Traceback" not in res.output and "controller.L_s_hat + lcl.L1" not in res.output


def test_the_rated_points_voltage_counts_the_filters_inductances():
    """yao2022's motor needs 15.2 V at rated point alone, 35.4 V through
    Table II's filter (lcl.L1 + lcl.L2o in series, 100 kr/min), of the
    37.5 V its 65 V DC link makes: not warned. With L1 1.3 times Table II's
    the filter's drop takes it beyond: warned, naming the filter (the check
    counted the motor alone: a 1 H L1 needing 311 kV went unsaid)."""
    import dataclasses
    import math
    import warnings

    from smodrive.model import derive
    from smodrive.scenarios import catalogue

    s = catalogue()["yao2022.base"]()
    m, f = s.motor, s.lcl
    assert abs(derive.rated_voltage(m) - 15.2) < 0.05
    assert abs(derive.rated_voltage(m, f.L1 + f.L2o) - 35.4) < 0.05
    assert abs(s.inverter.u_dc / math.sqrt(3.0) - 37.5) < 0.05

    def said(sc):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            sc.check_controller()
        return [str(x.message) for x in w if "rated point" in str(x.message)]

    assert said(s) == []
    big = s.replace(lcl=dataclasses.replace(f, L1=1.3 * f.L1))
    assert derive.rated_voltage(m, 1.3 * f.L1 + f.L2o) > 37.6
    msgs = said(big)
    assert len(msgs) == 1 and "through the LCL filter (lcl.L1 + lcl.L2o in series)" in msgs[0]
