"""docs/parameters.md is the code's: its generated tables are current, every
section class of smodrive.model has one, its examples (doctests, TOML
files, shell commands) run as written and print what it says, and its
hand-written C tables name every field and status of the headers."""

from __future__ import annotations

import ctypes as ct
import dataclasses
import doctest
import importlib.util
import inspect
import io
import json
import math
import re
import shlex
import warnings
try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: the same parser as a package
    import tomli as tomllib
from contextlib import redirect_stdout
from pathlib import Path

import pytest
from click.testing import CliRunner

from smodrive import model as params
from smodrive.model.fields import _Validated
from smodrive.engine import _codes, _ffi
from smodrive.cli import main as cli_main
from smodrive.model import YANG2018_MODES, ParameterError, Scenario
from smodrive.scenario_io import SECTIONS, scenario_from_dict
from smodrive.scenarios import catalogue, yang2018, yao2022
from smodrive.engine import drive_config, plant_config, profiles

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "parameters.md"
TEXT = DOC.read_text()


def _load_generator():
    spec = importlib.util.spec_from_file_location("gen_parameters",
                                                  ROOT / "tools" / "gen_parameters.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


gen = _load_generator()


def _blocks(lang: str) -> list[str]:
    return re.findall(rf"^```{lang}\n(.*?)^```$", TEXT, flags=re.S | re.M)


def _section(heading: str) -> str:
    """The text of the doc from the heading starting with `heading` to the next."""
    i = TEXT.index("\n## " + heading)
    j = TEXT.find("\n## ", i + 1)
    return TEXT[i:j if j > 0 else len(TEXT)]


# ------------------------------------------------------ generated tables --

def test_generated_tables_are_current():
    stale = gen.check(DOC)
    assert stale == [], (f"stale tables {stale} in {DOC}: run "
                         "`PYTHONPATH=src .venv/bin/python tools/gen_parameters.py`")


def test_check_finds_a_stale_table_and_rewrite_keeps_the_prose(tmp_path):
    row = "| `R_s` | ohm | 2.25 (Table I; else required) |"
    assert TEXT.count(row) == 1
    edited = TEXT.replace(row, "| `R_s` | ohm | 2.5 |")
    assert gen.stale(edited) == ["motor"]
    assert gen.render(edited) == TEXT
    prose = "yao2022 Fig. 1, Table II"
    assert TEXT.count(prose) == 1
    reworded = edited.replace(prose, "yao2022 Fig. 1 and Table II")
    assert gen.render(reworded) == TEXT.replace(prose, "yao2022 Fig. 1 and Table II")
    # the command line: --check fails on the stale copy, passes on the doc
    doc = tmp_path / "parameters.md"
    doc.write_text(edited)
    assert gen.main(["--check", "--doc", str(doc)]) == 1
    assert gen.main(["--doc", str(doc)]) == 0
    assert doc.read_text() == TEXT
    assert gen.main(["--check", "--doc", str(doc)]) == 0
    # a block without its markers is stale, not silently skipped
    assert "lcl" in gen.stale(TEXT.replace("<!-- /gen:lcl -->", ""))


def _section_classes() -> list[type]:
    """Found here independently of the generator: the classes of
    smodrive.model with a TOML section name."""
    return [c for _, c in inspect.getmembers(params, inspect.isclass)
            if c.__module__.startswith(params.__name__ + ".") and issubclass(c, _Validated)
            and c._section]


def test_every_section_class_has_a_generated_block():
    classes = _section_classes()
    sections = {c._section for c in classes}
    # the TOML sections and the top level at least (no vacuous pass)
    assert set(SECTIONS) | {"scenario"} <= sections
    for cls in classes:
        sec = cls._section
        assert TEXT.count(f"<!-- gen:{sec} -->") == 1, f"no generated block for {cls.__name__}"
        assert TEXT.count(f"<!-- /gen:{sec} -->") == 1
        assert f"## `{cls.__name__}`" in TEXT, f"no heading for {cls.__name__}"
        block = TEXT[TEXT.index(f"<!-- gen:{sec} -->"):TEXT.index(f"<!-- /gen:{sec} -->")]
        for f in dataclasses.fields(cls):
            if f.metadata.get("internal"):
                continue  # a record the code keeps (ControllerCfg.derived), no parameter
            assert f"\n| `{f.name}` |" in block, f"{sec}.{f.name} missing from its table"


def test_yang2018_base_is_the_defaults():
    # the doc's default column is yang2018's drive, which does not return to
    # I/f nor slew-limit its reference (the paper's drive)
    assert yang2018.BASE.replace(name=Scenario().name) == Scenario().with_controller(
        w_M_if_enter=0.0, a_M_ref=0.0)


# --------------------------------------------------------------- examples --

def test_doctests_run_as_written():
    res = doctest.testfile(str(DOC), module_relative=False, optionflags=doctest.ELLIPSIS,
                           verbose=False, report=True)
    assert res.attempted >= 7
    assert res.failed == 0


def test_toml_examples_load():
    blocks = _blocks("toml")
    texts = _blocks("text")
    assert len(blocks) == 3
    for b in blocks:
        data = tomllib.loads(b)
        if data.get("kind") == "lcl":
            with pytest.warns(UserWarning) as rec:
                s = scenario_from_dict(data)
            # the schema warning, quoted in the text block after it, and one a
            # renamed r/min key (n_M0 -> w_M0_rpm) of the old file
            after = TEXT[TEXT.index(b) + len(b):]
            quoted = next(t for t in texts if t in after).strip()
            messages = [str(w.message) for w in rec]
            assert quoted in messages
            assert len(messages) == 1 + sum(k in data for k in ("n_M0",))
            assert s.controller.position == "encoder" and s.lcl.C1 == 40e-6
            assert s.adc.gain == (1.01, 0.99, 1.0)
        else:
            s = scenario_from_dict(data)
        s.check_controller()
        assert s.name == data["name"]
        assert math.isclose(s.w_M_ref(0.0) * 60 / (2 * math.pi), data["w_M_ref_rpm"],
                            rel_tol=1e-12)


def test_shell_commands_run_as_written(tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    lines = [ln for b in _blocks("sh") for ln in b.splitlines() if ln.strip()]
    assert lines[0] == "make install"  # not run here (the tests run in the installed tree)
    ran = 0
    for ln in lines[1:]:
        args = shlex.split(ln)
        if args[:2] == [".venv/bin/python", "-c"]:
            out = io.StringIO()
            # the doc's own example file in the current schema: a legacy
            # field's warning (docs/example.toml had n_M0) is an error here
            with redirect_stdout(out), warnings.catch_warnings():
                warnings.simplefilter("error")
                exec(compile(args[2], "<doc>", "exec"), {})
            printed = out.getvalue().strip()
            assert printed and f"prints `{printed}`" in TEXT, printed
        elif args[0] == ".venv/bin/smodrive":
            argv = args[1:]
            if argv[0] == "run":
                argv[argv.index("--out") + 1] = str(tmp_path / "run")
            res = CliRunner().invoke(cli_main, argv)
            assert res.exit_code == 0, res.output
            if argv[0] == "show":
                shown = scenario_from_dict(tomllib.loads(res.output))
                assert shown == catalogue()[argv[1]]()
            if argv[0] == "run":
                summary = json.loads((tmp_path / "run" / "summary.json").read_text())
                assert summary["status"] == 0
        else:
            pytest.fail(f"a command of the doc the test does not know how to run: {ln}")
        ran += 1
    assert ran == 3


# ------------------------------------------------------ hand-written rules --

COMBINATIONS = [
    yang2018.BASE.with_controller(position="lcl_smo_pll"),
    yao2022.BASE.with_controller(current="robust_dbpc"),
    yao2022.BASE.with_controller(position="smdo_emf"),
    yang2018.BASE.with_controller(R_v=0.1),
]


@pytest.mark.parametrize("s", COMBINATIONS, ids=["lcl_source", "lcl_dbpc", "lcl_smdo", "R_v"])
def test_combination_rules_as_quoted(s):
    with pytest.raises(ParameterError) as exc:
        s.check_controller()
    assert f"| `{exc.value}` |" in TEXT
    # the C core refuses it with SMD_ERR_COMBINATION: engine code 2024
    buf = (ct.c_double * math.ceil(_ffi.ENGINE_SIZE / 8 + 1))()
    start = _ffi.EngineStart(theta0=0.0, w0=0.0, i_q0=0.0)
    rc = _ffi.lib.smd_engine_init(buf, ct.byref(plant_config(s)), ct.byref(drive_config(s)),
                                  ct.byref(profiles(s)), ct.byref(start))
    assert rc == 2024
    assert "`SMD_ERR_COMBINATION` (24; engine code 2024)" in TEXT


def test_mode_table():
    assert len(YANG2018_MODES) == 3
    for mode, parts in YANG2018_MODES.items():
        row = f'| `"{mode}"` | `{parts["current"]}` | `{parts["position"]}` | `{parts["start"]}`'
        assert row in TEXT, row


def test_status_table_matches_the_header():
    header = (ROOT / "core" / "include" / "smodrive" / "smd_types.h").read_text()
    enum = re.search(r"typedef enum smd_status \{(.*?)\} smd_status;", header, re.S).group(1)
    codes = [(n, int(v)) for n, v in re.findall(r"(SMD_\w+) = (\d+)", enum)]
    assert len(codes) == 31 and codes[-1] == ("SMD_ERR_RLS", 30)
    table = _section("Status codes")
    for name, code in codes:
        assert f"\n| {code} | `{name}` |" in table, name
    assert len(re.findall(r"\n\| \d+ \| `SMD_", table)) == len(codes)


def test_plant_field_codes_match_the_library():
    table = _section("C configuration: `smd_plant_config`")
    codes = 0
    for code in range(1, 100):
        name = _ffi.lib.smd_plant_field(code).decode()
        if name == "unknown":
            break
        assert f"\n| {code} | `{name}`" in table, (code, name)
        codes += 1
    assert codes == _codes.SMD_PF_N - 1
    assert _ffi.lib.smd_plant_field(codes).decode() in TEXT


def test_c_config_tables_name_every_field():
    words = set(re.findall(r"\w+", _section("C configuration: `smd_drive_config`")))
    for cls in (_ffi.DriveConfig, _ffi.SmoConfig, _ffi.LinConfig):
        missing = [f[0] for f in cls._fields_ if f[0] not in words]
        assert not missing, (cls.__name__, missing)
    words = set(re.findall(r"\w+", _section("C configuration: `smd_plant_config`")))
    missing = [f[0] for f in _ffi.PlantConfig._fields_ if f[0] not in words]
    assert not missing
