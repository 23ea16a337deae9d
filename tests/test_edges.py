"""The edges of the CLI and the API (issue 10, points 5 and 6): whatever a
user types, the CLI answers with one ``error: ...`` line naming the user's
field and its valid range (exit 2 for bad input, 1 for a failed run), never
a Python traceback; the API refuses bad input with a ParameterError at
construction or before running, never an AttributeError from deep inside;
and a long run keeps its log within a memory budget.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import tracemalloc
try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: the same parser as a package
    import tomli as tomllib
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import smodrive.report
import smodrive.engine
from smodrive import plots
from smodrive.engine import _ffi
from smodrive.cli import main
from smodrive.design import yao2022 as dz
from smodrive.model import (RPM, AdcCfg, ControllerCfg, LoadCfg, MotorPars, ParameterError,
                             Profile, Scenario)
from smodrive.scenario_io import SECTIONS, scenario_from_dict
from smodrive.scenarios import yao2022
from smodrive.engine import CHANNELS, Result, simulate

SHORT = "duration = 0.01\n"  # 100 samples of the default drive (T_sp = 0.1 ms)
LCL = 'base = "yao2022.base"\nduration = 0.005\n'  # 100 samples of the LCL drive


def _cli(*args: str):
    return CliRunner().invoke(main, [str(a) for a in args])


def _no_traceback(res) -> None:
    """The CLI ended by its own exit (never by an escaping exception) and
    printed no Python traceback."""
    assert res.exception is None or isinstance(res.exception, SystemExit), res.output
    assert "Traceback" not in res.output


def _refused(res, code: int, *words: str) -> str:
    """res is a clean refusal: exit `code`, an ``error:`` line, every one of
    `words` in the message."""
    _no_traceback(res)
    assert res.exit_code == code, res.output
    assert "error:" in res.output, res.output
    for w in words:
        assert w in res.output, f"{w!r} not in {res.output!r}"
    return res.output


def _toml(tmp_path: Path, text: str | bytes, name: str = "s.toml") -> Path:
    p = tmp_path / name
    if isinstance(text, bytes):
        p.write_bytes(text)
    else:
        p.write_text(text, encoding="utf-8")
    return p


# ------------------------------------------------------------ --out ------

@pytest.fixture
def no_simulation(monkeypatch):
    """Fail the test if anything is simulated (the checks come first)."""

    def boom(*a, **k):
        raise AssertionError("simulated before the output folder was checked")

    monkeypatch.setattr(smodrive.engine, "simulate", boom)
    monkeypatch.setattr("smodrive.cli.simulate", boom, raising=False)
    monkeypatch.setattr(smodrive.report, "reproduce", boom)


def _unwritable_dir(tmp_path: Path) -> Path:
    """A directory nobody may create files in: a read-only one for a normal
    user; root ignores permission bits, so then sysfs's top directory, where
    the kernel refuses new files to everyone."""
    d = tmp_path / "read_only"
    d.mkdir()
    d.chmod(0o500)
    if os.access(d, os.W_OK):
        d = Path("/sys")
    with pytest.raises(OSError):  # the premise: it really is unwritable
        (d / "probe").write_text("x")
    return d


def _outs(tmp_path: Path) -> dict[str, tuple[Path, str]]:
    a_file = tmp_path / "a_file"
    a_file.write_text("not a folder")
    return {"existing file": (a_file, "not a directory"),
            "under a file": (a_file / "sub", "not a directory"),
            "unwritable": (_unwritable_dir(tmp_path), "cannot write")}


@pytest.mark.parametrize("case", ["existing file", "under a file", "unwritable"])
def test_run_checks_out_before_simulating(case, tmp_path, no_simulation):
    out, why = _outs(tmp_path)[case]
    _refused(_cli("run", _toml(tmp_path, SHORT), "--out", out), 2, "--out", str(out), why)


@pytest.mark.parametrize("case", ["existing file", "under a file", "unwritable"])
def test_reproduce_checks_out_before_running(case, tmp_path, no_simulation):
    out, why = _outs(tmp_path)[case]
    _refused(_cli("reproduce", "yang2018", "--out", out), 2, "--out", str(out), why)


def test_unexpected_failure_is_one_error_line_not_a_traceback(tmp_path, monkeypatch):
    """A bug (here: simulate raising an arbitrary exception) still ends in
    `error: ...` and exit 1, not in a traceback."""

    def broken(*a, **k):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(smodrive.engine, "simulate", broken)
    monkeypatch.setattr("smodrive.cli.simulate", broken, raising=False)
    _refused(_cli("run", _toml(tmp_path, SHORT), "--out", tmp_path / "o"), 1,
             "float division by zero")


# ---------------------------------------------------- the TOML file -------

def test_non_utf8_file_is_refused_naming_the_encoding(tmp_path):
    src = _toml(tmp_path, b'name = "caf\xe9"\nduration = 0.01\n')  # Latin-1
    _refused(_cli("run", src, "--out", tmp_path / "o"), 2, "s.toml", "UTF-8")
    assert not (tmp_path / "o").exists()


def test_utf8_with_a_byte_order_mark_is_read(tmp_path):
    src = _toml(tmp_path, '\ufeffname = "café"\nduration = 0.01\n'.encode())
    res = _cli("run", src, "--out", tmp_path / "o")
    _no_traceback(res)
    assert res.exit_code == 0, res.output
    assert json.loads((tmp_path / "o" / "summary.json").read_text("utf-8"))["name"] == "café"


def test_markup_in_a_name_is_printed_literally(tmp_path):
    """rich would read "[/x]" as a closing tag (MarkupError): user text is
    printed as it is."""
    res = _cli("run", _toml(tmp_path, 'name = "[/x] [bold]b"\n' + SHORT), "--out",
               tmp_path / "o")
    _no_traceback(res)
    assert res.exit_code == 0, res.output
    assert "[/x] [bold]b" in res.output


def test_markup_in_a_bad_value_is_printed_literally(tmp_path):
    src = _toml(tmp_path, SHORT + '[controller]\nmode = "[/red]"\n')
    _refused(_cli("run", src, "--out", tmp_path / "o"), 2, "controller.mode", "[/red]")


def test_a_name_of_the_wrong_type_is_refused_by_name(tmp_path):
    _refused(_cli("run", _toml(tmp_path, "name = 123\n" + SHORT), "--out", tmp_path / "o"), 2,
             "scenario.name", "123")
    with pytest.raises(ParameterError, match=r"scenario\.name"):
        Scenario(name=123)  # type: ignore[arg-type]


@pytest.mark.parametrize("name,stem", [("a/b", "a_b"), ("../../up", "______up"),
                                       ("C:\\x", "C__x"), ("", "scenario")])
def test_a_name_with_path_characters_stays_in_out(name, stem, tmp_path):
    """The name becomes the figure's file name: every character other than
    a letter, digit, - or _ is written as _, so the file lands in OUT."""
    out = tmp_path / "deep" / "o"
    res = _cli("run", _toml(tmp_path, f"name = {json.dumps(name)}\n" + SHORT), "--out", out)
    _no_traceback(res)
    assert res.exit_code == 0, res.output
    assert (out / f"{stem}.png").stat().st_size > 1000
    assert json.loads((out / "summary.json").read_text("utf-8"))["name"] == name
    outside = {p for p in tmp_path.rglob("*") if out not in p.parents and p != out}
    assert outside == {tmp_path / "s.toml", tmp_path / "deep"}


# ------------------------------------------------------------ values ------

@pytest.mark.parametrize("text,names", [
    ("w_M_ref = 10.0\nw_M_ref_rpm = 100.0\n", ("w_M_ref", "w_M_ref_rpm")),
    ("w_M0_rpm = 100.0\nw_M0 = 10.0\n", ("w_M0", "w_M0_rpm")),
    ("n_M0 = 100.0\nw_M0_rpm = 100.0\n", ("n_M0", "w_M0_rpm")),  # an older name too
    ("[controller]\na_M_start = 1.0\na_M_start_rpm_s = 1.0\n",
     ("controller.a_M_start", "a_M_start_rpm_s")),
])
def test_one_quantity_given_twice_is_refused_naming_both(text, names, tmp_path):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the older name's note
        res = _cli("run", _toml(tmp_path, SHORT + text), "--out", tmp_path / "o")
    _refused(res, 2, *names)


@pytest.mark.parametrize("value", ["-5.0", "{ t = [0.0, 1.0], y = [1.0, -1.0] }"])
def test_negative_brake_torque_is_refused_naming_field_and_range(value, tmp_path):
    """T_brake is a magnitude (the brake always opposes the rotation, its
    sign comes from the speed): a negative one would drive the machine."""
    src = _toml(tmp_path, SHORT + f"[load]\nT_brake = {value}\n")
    _refused(_cli("run", src, "--out", tmp_path / "o"), 2, "load.T_brake", "-1" if "{" in value
             else "-5", "[0, inf)", "N m")
    with pytest.raises(ParameterError, match=r"load\.T_brake .*\[0, inf\) N m"):
        LoadCfg(T_brake=Profile.const(-0.1))
    assert LoadCfg(T_brake=Profile.const(0.0)).T_brake.y == (0.0,)


@pytest.mark.parametrize("text,named,hidden", [
    # the warm start's current: the load at t = 0 over a tiny torque constant
    (SHORT + "base = \"yang2018.base\"\n[motor]\npsi_r = 1e-6\n[load]\nT_ext = 100.0\n",
     ("load.T_ext", "motor.psi_r", "warm_start"), ("i_q0", "i_d0")),
    # the LCL observers are designed from the controller's estimates
    (LCL + "[controller]\nR_s_hat = 0.0\n", ("controller.R_s_hat",), ("motor.R_s",)),
    (LCL + "[controller]\nL_s_hat = 1e-9\n", ("controller.L_s_hat",), ("motor.L_s",)),
    (LCL + "[lcl]\nC1 = 0.5\n[controller]\nC1_hat_ratio = 10.0\n",
     ("lcl.C1", "controller.C1_hat_ratio"), ()),
    # L_dec left unset is derived from the estimate and the filter: the term the user wrote
    # that takes most of the sum, its range the 10 H less the others (10 - 6 - 24e-6)
    (LCL + "[lcl]\nL1 = 6.0\nL2o = 6.0\n", ("lcl.L1 = 6.0 H", "[1e-08, 3.99998] H"),
     ("controller.L_s_hat + lcl.L1 + lcl.L2o =",)),
    # the old LCL schema: psi_m sets the flux of the speed-PI design too
    ('kind = "lcl"\nduration = 0.005\n[plant]\npsi_m = 0.0\n', ("plant.psi_m",),
     ("psi_r_pi",)),
])
def test_messages_name_the_users_field_not_a_derived_one(text, named, hidden, tmp_path):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the old schema's note
        res = _cli("run", _toml(tmp_path, text), "--out", tmp_path / "o")
    out = _refused(res, 2, *named)
    # the error names the user's field (a warning beside it may name both the
    # override and the motor's value it is far from: design_from_motor.md)
    error = out[out.index("error:"):]
    for h in hidden:
        assert h not in error


def _schema_names() -> set[str]:
    """Every field a user can set: `sec.field` and the top-level ones."""
    names = {f.name for f in dataclasses.fields(Scenario) if f.name not in SECTIONS}
    for sec, cls in SECTIONS.items():
        names |= {f"{sec}.{f.name}" for f in dataclasses.fields(cls)}
    return names | set(SECTIONS)


def test_every_engine_refusal_names_fields_of_the_schema():
    """The C plant and controller name their own config fields (T_sw,
    i_d0/i_q0, omega_c, k_p, ...), which a user never sets: every code they
    can return is translated to fields of the scenario."""
    schema = _schema_names()
    codes = [k for k in range(1, 200) if _ffi.lib.smd_plant_field(k) != b"unknown"]
    assert len(codes) >= 28
    for k in codes:
        fields = smodrive.engine.plant_fields(k)
        assert fields and set(fields) <= schema, (k, fields)
    statuses = [k for k in range(2, 200) if _ffi.status_str(k) != "unknown status"]
    assert len(statuses) >= 25
    for k in statuses:
        fields = smodrive.engine.controller_fields(k)
        assert set(fields) <= schema, (k, fields)


# ---------------------------------------------- LCL observer design -------

def test_lcl_observers_refuse_a_machine_without_magnet_flux(tmp_path):
    """psi_r = 0: no back-EMF, nothing for a sensorless position source to
    estimate the angle from."""
    _refused(_cli("run", _toml(tmp_path, LCL + "[motor]\npsi_r = 0.0\n"), "--out",
                  tmp_path / "o"), 2, "motor.psi_r", "controller.position")


def test_lcl_observers_refuse_a_sampling_period_beyond_the_resonance(tmp_path):
    """The observers sample the filter: its resonance (5.5 kHz, Table II)
    must lie below the Nyquist frequency, T_sp <= 1 / (2 f_res) = 90.5 us."""
    f_res = dz.DesignPlant(yao2022.MOTOR, yao2022.BASE.lcl, 50e-6).f_res()
    limit = f"{1.0 / (2.0 * f_res):g}"
    for T in ("1.0", "0.001", "1e-4"):
        res = _cli("run", _toml(tmp_path, LCL.replace("0.005", "2.0") + f"T_sp = {T}\n"
                                "[inverter]\nt_dead = 0.0\n"), "--out", tmp_path / "o")
        _refused(res, 2, "T_sp", limit)


def test_a_failed_pole_placement_is_a_parameter_error_naming_the_field():
    plant = dz.DesignPlant(yao2022.MOTOR, yao2022.BASE.lcl, 1.0)
    with pytest.raises(ParameterError, match="T_sp"):
        dz.design_tables(plant, [0.0, 1000.0])
    # a pole repeated more often than the input matrix's rank (2)
    with pytest.raises(ParameterError, match="p_u"):
        dz.ObserverDesignPars(p_u=(0.5, 0.5, 0.5, 0.5))


@pytest.mark.parametrize("key", ["w_M_ref_rpm", "w_M0_rpm"])
def test_a_speed_beyond_the_observer_tables_is_refused_before_running(key, tmp_path,
                                                                    no_simulation):
    lim = f"{smodrive.engine.TABLE_RPM[-1]:g}"
    assert lim == "110000"
    res = _cli("run", _toml(tmp_path, LCL + f"{key} = 150000.0\n"), "--out", tmp_path / "o")
    _refused(res, 2, key.removesuffix("_rpm"), lim, "r/min")
    s = yao2022.BASE.replace(w_M_ref=Profile((0.0, 0.1), (0.0, 120e3 * RPM)))
    with pytest.raises(ParameterError, match="w_M_ref"):
        s.check_controller()


# --------------------------------------------------- runs and summary -----

@pytest.mark.parametrize("text,field", [("duration = 1e-9\n", "duration"),
                                        ("duration = 0.01\nlog_stride = 100\n", "log_stride"),
                                        ("duration = 0.01\nlog_stride = 1000\n", "log_stride")])
def test_a_run_without_samples_to_summarise_is_refused(text, field, tmp_path):
    """1e-9 s is no sample at T_sp = 0.1 ms; a log stride of all 100 samples
    or more would log the initial state only."""
    _refused(_cli("run", _toml(tmp_path, text), "--out", tmp_path / "o"), 2, field)
    with pytest.raises(ParameterError, match=field):
        simulate(scenario_from_dict(tomllib.loads(text)))


def _strict_json(text: str) -> dict:
    def no_constant(c):
        raise AssertionError(f"{c} is not JSON")

    return json.loads(text, parse_constant=no_constant)


def test_summary_is_strict_json_and_counts_control_samples(tmp_path):
    """105 samples logged every 10th: 11 rows, but 105 control samples
    (rows x stride would say 110)."""
    src = _toml(tmp_path, "duration = 0.0105\nlog_stride = 10\n")
    res = _cli("run", src, "--out", tmp_path / "o")
    assert res.exit_code == 0, res.output
    s = _strict_json((tmp_path / "o" / "summary.json").read_text("utf-8"))
    assert s["samples"] == 105
    assert all(math.isfinite(v) for v in s.values() if isinstance(v, float))
    # a log stride leaving no row in the last fifth: the last row stands for it
    src = _toml(tmp_path, "duration = 0.01\nlog_stride = 60\n")
    res = _cli("run", src, "--out", tmp_path / "o2")
    assert res.exit_code == 0, res.output
    s = _strict_json((tmp_path / "o2" / "summary.json").read_text("utf-8"))
    assert all(math.isfinite(v) for v in s.values() if isinstance(v, float))


# --------------------------------------------------------- the API --------

def test_numpy_scalars_are_accepted_as_numbers():
    m = MotorPars(n_p=np.int64(4), L_s=np.float32(1e-3), R_s=np.float64(2.0),
                  psi_r=np.float64(0.4), J=np.float32(0.01), P_N=np.int32(2000),
                  w_M_N=np.float64(157.0))
    assert (m.n_p, type(m.n_p)) == (4, int)
    assert type(m.L_s) is float and m.L_s == pytest.approx(1e-3, rel=1e-7)  # float32's
    a = AdcCfg(gain=np.array([1.0, 1.01, 0.99]), bits=np.int32(10))
    assert a.gain == (1.0, 1.01, 0.99) and all(type(g) is float for g in a.gain)
    c = ControllerCfg(speed_loop=np.bool_(True), speed_decimation=np.uint8(2))
    assert c.speed_loop is True and c.speed_decimation == 2
    s = Scenario(duration=np.float32(0.01), log_stride=np.int64(2), w_M0=np.float16(10.0),
                 w_M_ref=Profile(np.array([0.0, 0.005]), np.array([10.0, 20.0])))
    r = simulate(s)
    assert r.data.shape[0] == 50 and r.samples == 100
    assert s.w_M_ref.t == (0.0, 0.005)
    json.dumps(dataclasses.asdict(s))  # every value is a Python one
    with pytest.raises(ParameterError, match="n_p"):
        dataclasses.replace(m, n_p=np.float64(4.5))


def test_a_number_for_a_profile_is_a_constant_profile():
    assert Scenario(w_M_ref=100.0).w_M_ref == Profile.const(100.0)
    assert Scenario(i_q_ref=np.float32(2.0)).i_q_ref == Profile.const(2.0)
    assert LoadCfg(T_brake=5).T_brake == Profile.const(5.0)
    r = simulate(Scenario(duration=0.01, w_M0=100.0, w_M_ref=100.0))
    assert abs(r["w_M"][-1] - 100.0) < 1.0  # the speed loop holds it (1 %)
    for bad in ("fast", [1.0, 2.0], None, True):
        with pytest.raises(ParameterError, match=r"scenario\.w_M_ref"):
            Scenario(w_M_ref=bad)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"load\.T_ext"):
        LoadCfg(T_ext="1 N m")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"scenario\.motor"):
        Scenario(motor=5)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="profile"):
        Profile((0.0, "1"), (0.0, 1.0))  # type: ignore[arg-type]


# ------------------------------------------------- point 6: memory --------

ROW = len(CHANNELS) * 8  # bytes of one logged row


def _long(duration: float = 3.0) -> Scenario:
    return Scenario(name="long", duration=duration, w_M0=300 * RPM,
                    w_M_ref=Profile.const(300 * RPM))


def test_log_plan_fits_the_budget_with_the_smallest_stride():
    s = _long()  # 30,000 samples: 10.6 MB of log
    plan = smodrive.engine.log_plan(s, 2**31)
    assert (plan.stride, plan.rows, plan.decimated) == (1, 30_000, False)
    plan = smodrive.engine.log_plan(s, 4_000_000)
    # every 3rd sample: 10,000 rows (3.5 MB); every 2nd would be 5.3 MB
    assert (plan.stride, plan.rows, plan.decimated) == (3, 10_000, True)
    assert plan.bytes == 10_000 * ROW <= 4_000_000 < 15_000 * ROW
    plan = smodrive.engine.log_plan(s.replace(log_stride=2), 4_000_000)
    assert plan.stride == 4  # a multiple of the scenario's own stride
    with pytest.raises(ParameterError, match="budget"):
        smodrive.engine.log_plan(s, ROW)  # not two rows


def test_a_long_run_keeps_its_log_within_the_budget():
    """3 s at 10 kHz with a 4 MB budget: the log is every 3rd sample, the
    same rows as a run logging every 3rd sample, and the run's traced peak
    stays within the budget plus a fixed 0.5 MB for what does not grow with
    the run (engine state, configs, one chunk's finiteness check)."""
    s, budget = _long(), 4_000_000
    simulate(_long(0.01), log_budget=budget)  # imports and caches first
    tracemalloc.start()
    try:
        r = simulate(s, log_budget=budget)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert r.data.nbytes <= budget
    assert peak <= budget + 512 * 1024, peak
    assert (r.log_stride, r.samples, r.data.shape[0]) == (3, 30_000, 10_000)
    np.testing.assert_allclose(np.diff(r.t), 3 * s.T_sp, rtol=1e-9)
    ref = simulate(s.replace(log_stride=3))
    assert np.array_equal(r.data, ref.data)


def test_cli_log_budget_decimates_and_says_so(tmp_path):
    src = _toml(tmp_path, 'name = "long"\nduration = 3.0\nw_M0_rpm = 300.0\n'
                          "w_M_ref_rpm = 300.0\n")
    out = tmp_path / "o"
    res = _cli("run", src, "--out", out, "--log-budget", "4MB")
    _no_traceback(res)
    assert res.exit_code == 0, res.output
    summary = _strict_json((out / "summary.json").read_text("utf-8"))
    assert summary["samples"] == 30_000
    assert summary["log"] == {"stride": 3, "rows": 10_000, "bytes": 10_000 * ROW,
                              "budget_bytes": 4_000_000, "decimated": True}
    assert "stride 3" in res.output and "4 MB" in res.output
    for phase in ("simulating", "writing signals.npz", "plotting"):
        assert phase in res.output
    sig = np.load(out / "signals.npz")
    assert set(sig.files) == set(CHANNELS) | {"_units", "_descriptions"}
    assert sig["t"].shape == (10_000,)
    np.testing.assert_allclose(np.diff(sig["t"]), 3e-4, rtol=1e-9)
    ref = simulate(_long().replace(log_stride=3))
    assert np.array_equal(sig["w_M"], ref["w_M"])
    # the speed held (1 %): the summary reads the decimated log
    assert abs(summary["speed_rpm_mean_last_20pct"] - 300.0) < 3.0
    assert (out / "long.png").stat().st_size > 10_000
    # without pressure nothing is decimated
    res = _cli("run", src, "--out", tmp_path / "o2")
    assert res.exit_code == 0, res.output
    log = _strict_json((tmp_path / "o2" / "summary.json").read_text("utf-8"))["log"]
    assert (log["stride"], log["decimated"]) == (1, False)


@pytest.mark.parametrize("bad", ["lots", "-1MB", "0", "12 parsecs"])
def test_cli_log_budget_must_be_a_size(bad, tmp_path):
    res = _cli("run", _toml(tmp_path, SHORT), "--out", tmp_path / "o", "--log-budget", bad)
    _no_traceback(res)
    assert res.exit_code == 2 and "Invalid value for '--log-budget'" in res.output
    assert "not a size" in res.output


def test_figures_draw_at_most_max_points_per_curve():
    """A curve of 5,000 rows drawn with max_points = 1,000 keeps every 5th
    point; the default caps a curve at 200,000 points."""
    assert plots.MAX_POINTS == 200_000
    s = _long(0.5)
    data = np.zeros((5000, len(CHANNELS)))
    data[:, CHANNELS.index("t")] = np.arange(5000) * s.T_sp
    r = Result(s, data, 0)
    ax = plots.time_panels([r], ["x"], None, [("speed", [("n_rpm", "n"), ("w_M", "w")])],
                           max_points=1000)
    for line in ax[0, 0].get_lines():
        assert 500 < line.get_xdata().size <= 1000


def test_a_dead_time_zone_whose_reciprocal_overflows_is_refused_by_name():
    """controller.i_dtc = 1e-39 A is within its range (0, 1e5] but a
    subnormal float: the core's 1 / i_dtc overflows, and a zero phase current
    times it is NaN (fuzz_blocks found the compensation's lost voltage NaN
    there, 2026-11-27; its input is in fuzz/corpus). The core's init refuses
    it (SMD_ERR_DEADTIME), named with the field; 1e-37 A still runs."""
    from smodrive.engine import simulate
    from smodrive.model import ParameterError, Scenario

    s = Scenario().replace(duration=0.005)
    with pytest.raises(ParameterError, match="controller.i_dtc = 1e-39"):
        simulate(s.with_controller(i_dtc=1e-39))
    assert simulate(s.with_controller(i_dtc=1e-37)).status == 0
