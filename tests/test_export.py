"""Exports (issue 13, point 3): `smodrive run --format npz,mat,csv,parquet`,
Result.to_dataframe(), and a unit and a description for every channel.

Each format is read back with its own reader (numpy, scipy.io.loadmat, the
csv module / pandas, pyarrow) and compared with the Result it was written
from: the values must be identical (float64 written exactly: .npz, .mat and
Parquet store the bits, CSV 17 significant digits, which round-trip every
float64), and the units and descriptions those of CHANNEL_INFO."""

from __future__ import annotations

import csv
import json
import sys

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
import scipy.io
from click.testing import CliRunner

from smodrive.engine import export
from smodrive.cli import main
from smodrive.model import RPM, ControllerCfg, ParameterError, Profile, Scenario
from smodrive.engine import CHANNEL_INFO, CHANNELS, Result, simulate

# the units a channel may have: SI as the channels use them, "" for a code
UNITS = {"s", "rad", "rad/s", "A", "V", "N m", "A/s", "ohm", "Wb", "1", ""}  # 1: a ratio (duty)
CODES = {"phase", "status", "fault"}  # the dimensionless channels


@pytest.fixture(scope="module")
def run() -> Result:
    """20 ms of the sensorless robust DBPC drive at 600 r/min under a load:
    every group of channels moves (currents, voltages, the SMDO's estimates)."""
    s = Scenario(name="export test", duration=0.02, w_M0=600 * RPM,
                 w_M_ref=Profile.const(600 * RPM),
                 controller=ControllerCfg(current="robust_dbpc", position="smdo_emf"))
    return simulate(s)


def test_every_channel_has_a_unit_and_a_description():
    assert set(CHANNEL_INFO) == set(CHANNELS)
    for c in CHANNELS:
        unit, desc = CHANNEL_INFO[c]
        assert unit in UNITS, (c, unit)
        assert (unit == "") == (c in CODES), c
        assert len(desc) >= 10, c  # a sentence, not a placeholder
        assert Result.unit(c) == unit and Result.description(c) == desc
    assert [row["name"] for row in export.channel_table()] == list(CHANNELS)


def test_the_run_moves_the_channels_it_is_exported_for(run):
    """Otherwise a writer that drops values would pass: the currents, the
    voltages and the SMDO's disturbance estimate are not all zero."""
    for c in ("w_M", "i_d", "i_q", "u_alpha", "u_d_hat_alpha", "theta_hat"):
        assert np.ptp(run[c]) > 0, c


def _same(a: np.ndarray, b: np.ndarray) -> None:
    np.testing.assert_array_equal(np.asarray(a, dtype=np.float64).ravel(), b)


def test_npz_reads_back_with_units(run, tmp_path):
    (p,) = export.write(run, tmp_path, ("npz",))
    with np.load(p) as z:
        for c in CHANNELS:
            _same(z[c], run[c])
        assert list(z["_units"]) == [CHANNEL_INFO[c][0] for c in CHANNELS]
        assert list(z["_descriptions"]) == [CHANNEL_INFO[c][1] for c in CHANNELS]


def test_mat_reads_back_with_units_struct(run, tmp_path):
    (p,) = export.write(run, tmp_path, ("mat",))
    m = scipy.io.loadmat(p, squeeze_me=True, struct_as_record=False)
    for c in CHANNELS:
        _same(m[c], run[c])
        assert str(m["units"].__dict__[c]) == CHANNEL_INFO[c][0] or (
            CHANNEL_INFO[c][0] == "" and np.size(m["units"].__dict__[c]) == 0)
        assert str(m["descriptions"].__dict__[c]) == CHANNEL_INFO[c][1]
    assert m["info"].scenario == "export test"
    assert m["info"].log_stride == run.log_stride and m["info"].samples == run.samples
    assert m["info"].T_sp == run.scenario.T_sp
    raw = scipy.io.loadmat(p)  # unsqueezed: column vectors, as MATLAB sees them
    assert raw["w_M"].shape == (run.data.shape[0], 1)


def test_csv_reads_back_exactly_with_sidecar_units(run, tmp_path):
    paths = export.write(run, tmp_path, ("csv",))
    assert [q.name for q in paths] == ["signals.csv", "signals.csv.json"]
    with open(paths[0], newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == list(CHANNELS)
    back = np.array(rows[1:], dtype=np.float64)
    np.testing.assert_array_equal(back, run.data)  # 17 digits: every bit back
    side = json.loads(paths[1].read_text())
    assert side["file"] == "signals.csv"
    assert [(c["name"], c["unit"], c["description"]) for c in side["columns"]] == \
        [(c, *CHANNEL_INFO[c]) for c in CHANNELS]
    assert side["log_stride"] == run.log_stride and side["scenario"] == "export test"
    # pandas: exact with its round-trip parser, pandas 3's default (pandas 2's
    # default parser may differ in the last bit: 2.3 on Python 3.10 did, by
    # 1e-16; pandas 3 deprecates the argument)
    pd2 = int(pd.__version__.split(".")[0]) < 3
    df = pd.read_csv(paths[0], **({"float_precision": "round_trip"} if pd2 else {}))
    np.testing.assert_array_equal(df.to_numpy(), run.data)


def test_parquet_reads_back_with_units_in_the_column_metadata(run, tmp_path):
    (p,) = export.write(run, tmp_path, ("parquet",))
    t = pq.read_table(p)
    assert t.column_names == list(CHANNELS)
    for c in CHANNELS:
        _same(t.column(c).to_numpy(), run[c])
        md = t.schema.field(c).metadata
        assert md[b"unit"].decode() == CHANNEL_INFO[c][0]
        assert md[b"description"].decode() == CHANNEL_INFO[c][1]
    info = json.loads(t.schema.metadata[b"smodrive"])
    assert info == export.run_info(run)


def test_to_dataframe(run):
    df = run.to_dataframe()
    assert list(df.columns) == list(CHANNELS)
    np.testing.assert_array_equal(df.to_numpy(), run.data)
    assert df.attrs["units"]["w_M"] == "rad/s" and df.attrs["units"]["T_e"] == "N m"
    assert df.attrs["descriptions"] == {c: CHANNEL_INFO[c][1] for c in CHANNELS}
    df.loc[0, "w_M"] = -1.0  # a copy: the Result is not changed through it
    assert run["w_M"][0] != -1.0


@pytest.mark.parametrize("text,expected", [("npz", ("npz",)), ("mat, CSV", ("mat", "csv")),
                                           ("parquet,npz,parquet", ("parquet", "npz"))])
def test_parse_formats(text, expected):
    assert export.parse_formats(text) == expected


@pytest.mark.parametrize("text,named", [("xls", "'xls'"), ("npz,,mat", "''"),
                                        ("npz,hdf5,json", "'hdf5', 'json'")])
def test_bad_format_names_itself_and_the_choices(text, named):
    with pytest.raises(ParameterError) as e:
        export.parse_formats(text)
    msg = str(e.value)
    assert named in msg and "npz, mat, csv, parquet" in msg


def test_cli_run_writes_every_format(tmp_path):
    out = tmp_path / "o"
    toml = tmp_path / "s.toml"
    toml.write_text('name = "cli export"\nduration = 0.005\nw_M0_rpm = 300.0\n'
                    'w_M_ref_rpm = 300.0\n')
    res = CliRunner().invoke(main, ["run", str(toml), "--out", str(out),
                                    "--format", "npz,mat,csv,parquet"])
    assert res.exit_code == 0, res.output
    names = {p.name for p in out.iterdir()}
    assert {"signals.npz", "signals.mat", "signals.csv", "signals.csv.json",
            "signals.parquet", "summary.json", "scenario.toml"} <= names
    with np.load(out / "signals.npz") as z:
        n = z["t"].size
    assert n == 50  # 5 ms at 10 kHz, every sample logged
    assert scipy.io.loadmat(out / "signals.mat")["t"].shape == (n, 1)
    assert pq.read_table(out / "signals.parquet").num_rows == n


def test_cli_default_format_is_npz_only(tmp_path):
    toml = tmp_path / "s.toml"
    toml.write_text("duration = 0.002\n")
    res = CliRunner().invoke(main, ["run", str(toml), "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    assert not list((tmp_path / "o").glob("signals.*[!z]"))  # only signals.npz
    assert (tmp_path / "o" / "signals.npz").is_file()


def test_cli_bad_format_is_one_error_line_before_anything_runs(tmp_path):
    out = tmp_path / "o"
    res = CliRunner().invoke(main, ["run", "yang2018.fig8", "--out", str(out),
                                    "--format", "npz,xlsx"])
    assert res.exit_code == 2
    assert "Traceback" not in res.output
    assert "error: --format: unknown format 'xlsx'; the formats are npz, mat, csv, " \
           "parquet" in res.output
    assert not out.exists()  # refused before the (1.6 s) run and before OUT is made


def test_cli_parquet_without_pyarrow_says_so(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # import pyarrow raises ImportError
    res = CliRunner().invoke(main, ["run", "yang2018.fig8", "--out", str(tmp_path / "o"),
                                    "--format", "parquet"])
    assert res.exit_code == 2 and "Traceback" not in res.output
    assert "--format parquet needs pyarrow: pip install pyarrow" in res.output
