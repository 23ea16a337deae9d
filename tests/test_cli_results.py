"""What a run leaves behind (issue 18, "Results"): summary.json says the
start-up phase at the end, the speed-tracking error and the fault history;
the summary JSON is the only thing on stdout; the files are written
atomically and never over another run's without --force; a sweep too large
to list is refused before anything is allocated; the API refuses a wrong
argument by name."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tracemalloc
import types
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import smodrive.engine.export
from smodrive import report, sweep
from smodrive.claims import Claim
from smodrive.analysis.summary import run_summary
from smodrive.cli import main
from smodrive.design.yao2022 import ObserverDesignPars
from smodrive.model import RPM, ParameterError, Profile, Scenario
from smodrive.scenarios import catalogue
from smodrive.scenarios.common import Experiment, Outcome
from smodrive.engine import CHANNELS, FAULT_BITS, FaultReport, Result, log_plan, simulate

ROOT = Path(__file__).resolve().parents[1]
SHORT = "duration = 0.01\n"  # 100 samples of the default drive (encoder, 1000 r/min)
# the default drive (yang2018 Table I, encoder) at 1000 r/min under a brake
# that needs ~8 A, with the trip at 2 A: overcurrent on the first samples
TRIP = ('name = "trip"\nduration = 0.02\nw_M0_rpm = 1000.0\nw_M_ref_rpm = 1000.0\n'
        "[controller]\ni_trip = 2.0\n[load]\nT_brake = 15.0\n")


def _cli(*args) -> "click.testing.Result":  # noqa: F821
    return CliRunner().invoke(main, [str(a) for a in args])


def _toml(tmp_path: Path, text: str, name: str = "s.toml") -> Path:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def _env() -> dict[str, str]:
    """The environment of a subprocess that imports this tree's package
    (the dev build in src/ when there is one, as the tests run)."""
    env = {**os.environ}
    env.pop("SMODRIVE_DEBUG", None)
    if (ROOT / "src" / "smodrive" / "libsmodrive.so").is_file():
        env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), env.get("PYTHONPATH", "")])
    return env


def _smodrive(*args, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "smodrive.cli", *map(str, args)], cwd=cwd,
                          env=_env(), capture_output=True, text=True, timeout=300)


# ------------------------------------------------------------- summary -----

def _summary(s: Scenario) -> dict:
    r = simulate(s)
    return run_summary(s, r, log_plan(s))


def test_summary_says_the_phase_at_the_end():
    """0 forced (I/f), 1 encoder handover, 2 the position source: encoder
    or observer."""
    cat = catalogue()
    if_start = cat["drive.if_start"]()
    # the I/f start hands over at 150 r/min, reached after 50 ms at 3000 r/min/s
    assert _summary(if_start.replace(duration=0.02))["phase_end"] == "forced"
    assert _summary(if_start.replace(duration=0.3))["phase_end"] == "observer"
    enc = cat["drive.pi_encoder"]()
    assert enc.controller.position == "encoder"
    assert _summary(enc.replace(duration=0.02))["phase_end"] == "encoder"
    # the encoder handover (start = "handover") before the SMDO takes over
    fig8 = cat["yang2018.fig8"]()
    assert fig8.controller.start == "handover" and fig8.controller.t_handover > 0.02
    assert _summary(fig8.replace(duration=0.02))["phase_end"] == "encoder"


def test_summary_speed_tracking_error_over_the_last_fifth():
    s = Scenario(duration=0.1, w_M0=1000 * RPM, w_M_ref=Profile((0.0, 0.1), (1000 * RPM,
                                                                        1100 * RPM)))
    r = simulate(s)
    summ = run_summary(s, r, log_plan(s))
    last = slice(int(np.searchsorted(r.t, 0.8 * s.duration)), None)  # the last 20 %
    err = np.mean(r.n_rpm[last]) - np.mean(r["w_M_ref"][last] / RPM)
    assert summ["speed_error_rpm_last_20pct"] == pytest.approx(err, rel=1e-12)
    assert summ["speed_ref_rpm_mean_last_20pct"] == pytest.approx(1090.0, abs=1.0)
    ref_end = r["w_M_ref"][-1] / RPM
    assert summ["speed_error_rel_last_20pct"] == pytest.approx(err / ref_end, rel=1e-12)
    assert summ["speed_error_rel_last_20pct"] < 0  # the speed lags a rising ramp
    # a final reference of 0 has no relative error; without the speed loop
    # there is no tracking error at all
    s0 = Scenario(duration=0.02, w_M0=0.0, w_M_ref=Profile.const(0.0))
    assert _summary(s0)["speed_error_rel_last_20pct"] is None
    no_loop = s.with_controller(speed_loop=False).replace(duration=0.02)
    summ = _summary(no_loop)
    assert summ["speed_error_rpm_last_20pct"] is None
    assert summ["speed_error_rel_last_20pct"] is None


def _result(faults: list[int], report_: FaultReport) -> Result:
    s = Scenario(duration=len(faults) * 1e-4)
    data = np.zeros((len(faults), len(CHANNELS)))
    data[:, CHANNELS.index("t")] = np.arange(len(faults)) * 1e-4
    data[:, CHANNELS.index("fault")] = faults
    return Result(s, data, 0, report_)


def test_summary_fault_history_first_and_final_with_times():
    """The first fault and its time (the engine's), the final fault word and
    when its latched bits were set for the last time (from the log)."""
    inp, oc, uv = FAULT_BITS["input"], FAULT_BITS["overcurrent"], FAULT_BITS["undervoltage"]
    # an input warning at row 1, an overcurrent latched at row 3 (the input
    # warning again beside it at row 5), cleared, latched again at row 7
    words = [0, inp, 0, oc, oc, oc | inp, 0, oc, oc, oc | inp]
    r = _result(words, FaultReport(1e-4, inp, oc | inp))
    s = r.scenario
    summ = run_summary(s, r, log_plan(s))
    assert summ["first_fault"] == ["input"] and summ["first_fault_t"] == 1e-4
    assert summ["final_fault"] == ["input", "overcurrent"]
    assert summ["final_fault_t"] == pytest.approx(7e-4)  # the last stretch of overcurrent
    assert summ["ends_in_fault"] is True
    # a final word of warnings only: when all of them were set
    r = _result([0, uv, inp, inp], FaultReport(1e-4, uv, inp))
    assert run_summary(r.scenario, r, log_plan(r.scenario))["final_fault_t"] == \
        pytest.approx(2e-4)
    # no fault
    r = _result([0, 0, 0], FaultReport(None, 0, 0))
    summ = run_summary(r.scenario, r, log_plan(r.scenario))
    assert summ["final_fault_t"] is None and summ["ends_in_fault"] is False


# --------------------------------------------- stdout, stderr, exit code ---

def test_summary_json_alone_on_stdout_progress_on_stderr(tmp_path):
    """`smodrive run x.toml --out d | jq .status` works: stdout is the
    summary JSON and nothing else; progress and notes go to stderr."""
    src = _toml(tmp_path, 'name = "piped"\n' + SHORT + "log_stride = 1\n")
    res = _smodrive("run", src, "--out", tmp_path / "d", "--log-budget", "1kB", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    summary = json.loads(res.stdout)  # the whole of stdout is one JSON document
    assert summary == json.loads((tmp_path / "d" / "summary.json").read_text("utf-8"))
    assert summary["status"] == 0 and summary["name"] == "piped"
    assert "simulating piped" in res.stderr  # the progress
    assert "log:" in res.stderr and "stride" in res.stderr  # the budget's note


def test_a_run_ending_in_a_fault_exits_1_and_says_why_on_stderr(tmp_path):
    res = _smodrive("run", _toml(tmp_path, TRIP), "--out", tmp_path / "d", cwd=tmp_path)
    assert res.returncode == 1
    summary = json.loads(res.stdout)
    assert summary["final_fault"] == ["overcurrent"] and summary["ends_in_fault"] is True
    assert summary["phase_end"] == "encoder"
    assert summary["final_fault_t"] is not None
    assert summary["first_fault_t"] <= summary["final_fault_t"] <= 0.02
    errors = [ln for ln in res.stderr.splitlines() if ln.startswith("error:")]
    assert len(errors) == 1
    assert "ends in a fault: overcurrent" in errors[0] and "faults_expected" in errors[0]
    assert "Traceback" not in res.stderr
    # the scenario that expects the fault: exit 0, the fault noted on stderr
    res = _smodrive("run", _toml(tmp_path, "faults_expected = true\n" + TRIP, "e.toml"),
                    "--out", tmp_path / "e", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout)["faults_expected"] is True
    assert "faults: first overcurrent" in res.stderr


# ---------------------------------------------------- atomic outputs ------

KILL_WRITING_NPZ = """
import os, signal, sys
import numpy as np
orig, calls = np.lib.format.write_array, [0]
def write_array(*a, **k):
    calls[0] += 1
    if calls[0] == 20:  # half-way through signals.npz's channels
        os.kill(os.getpid(), signal.SIGKILL)
    return orig(*a, **k)
np.lib.format.write_array = write_array
from smodrive.cli import main
main(sys.argv[1:])
"""


def _killed_run(tmp_path: Path, *args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", KILL_WRITING_NPZ, *map(str, args)],
                          cwd=tmp_path, env=_env(), capture_output=True, text=True, timeout=300)


def test_a_run_killed_while_writing_leaves_no_truncated_file(tmp_path):
    src = _toml(tmp_path, 'name = "first"\n' + SHORT)
    out = tmp_path / "d"
    res = _killed_run(tmp_path, "run", src, "--out", out)
    assert res.returncode == -9  # SIGKILL, in the middle of signals.npz
    assert not (out / "signals.npz").exists()
    assert not (out / "summary.json").exists()
    # a complete run, then one that replaces it, killed while writing: the
    # first run's files stay whole under their names
    res = _cli("run", src, "--out", out)
    assert res.exit_code == 0, res.output
    # the killed run's temporary file was removed by the next run (and said)
    assert "left by a killed run" in res.output
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert set(before) == {"signals.npz", "summary.json", "scenario.toml", "first.png"}
    src2 = _toml(tmp_path, 'name = "second"\n' + SHORT, "s2.toml")
    res = _killed_run(tmp_path, "run", src2, "--out", out, "--force")
    assert res.returncode == -9
    after = {p.name: p.read_bytes() for p in out.iterdir()
             if p.is_file() and not p.name.startswith(".")}
    assert after == before
    sig = np.load(out / "signals.npz")
    assert sig["t"].shape == (100,)


def test_an_interrupted_write_removes_its_temporary_file(tmp_path, monkeypatch):
    """An exception while writing (disk full, Ctrl-C) leaves neither a
    partial file nor the temporary one; the earlier file stays whole."""
    src = _toml(tmp_path, SHORT)
    out = tmp_path / "d"
    assert _cli("run", src, "--out", out, "--format", "npz,csv").exit_code == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}

    def full(*a, **k):
        raise OSError(28, "No space left on device", "signals.csv")

    monkeypatch.setattr(np, "savetxt", full)
    res = _cli("run", src, "--out", out, "--format", "npz,csv", "--force")
    assert res.exit_code == 1 and "No space left on device" in res.output
    assert {p.name: p.read_bytes() for p in out.iterdir()}.keys() == before.keys()
    assert (out / "signals.csv").read_bytes() == before["signals.csv"]


def test_every_output_goes_through_a_temporary_name(tmp_path, monkeypatch):
    """Each file of a run (the log in every format with its sidecar,
    summary.json, scenario.toml, the figure) reaches its name by os.replace
    of a temporary file in the same folder."""
    pytest.importorskip("pyarrow")
    replaced: list[tuple[Path, Path]] = []
    real = os.replace

    def spy(a, b):
        replaced.append((Path(a), Path(b)))
        return real(a, b)

    monkeypatch.setattr(os, "replace", spy)
    out = tmp_path / "d"
    res = _cli("run", _toml(tmp_path, 'name = "all"\n' + SHORT), "--out", out, "--format",
               "npz,mat,csv,parquet")
    assert res.exit_code == 0, res.output
    finals = {b.name for _, b in replaced}
    assert finals == {p.name for p in out.iterdir()} == {
        "signals.npz", "signals.mat", "signals.csv", "signals.csv.json", "signals.parquet",
        "summary.json", "scenario.toml", "all.png"}
    for a, b in replaced:
        assert a.parent.parent == b.parent or a.parent == b.parent  # the figure: a subfolder
        assert a.name.startswith(".") or a.parent.name.startswith(".")


# ----------------------------------------- another run's files in OUT -----

def _files(out: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in out.iterdir()}


def test_a_run_refuses_a_folder_holding_another_runs_files(tmp_path):
    out = tmp_path / "d"
    assert _cli("run", _toml(tmp_path, 'name = "first"\n' + SHORT), "--out", out,
                "--format", "npz,mat").exit_code == 0
    before = _files(out)
    assert set(before) == {"signals.npz", "signals.mat", "summary.json", "scenario.toml",
                           "first.png"}
    # another scenario into that folder: refused, naming the run and its files
    src2 = _toml(tmp_path, 'name = "second"\n' + SHORT, "s2.toml")
    res = _cli("run", src2, "--out", out)
    assert res.exit_code == 2
    errors = [ln for ln in res.output.splitlines() if ln.startswith("error:")]
    assert len(errors) == 1 and res.output.strip() == errors[0]
    for word in ("--out", str(out), "'first'", "summary.json", "signals.npz", "--force"):
        assert word in errors[0], word
    assert _files(out) == before  # nothing written, nothing simulated
    # the same scenario again: the earlier run's files are still another run's
    res = _cli("run", _toml(tmp_path, 'name = "first"\n' + SHORT), "--out", out)
    assert res.exit_code == 2 and "--force" in res.output
    # one file the run would write is enough
    lone = tmp_path / "lone"
    lone.mkdir()
    (lone / "signals.npz").write_bytes(b"x")
    (lone / "notes.txt").write_text("mine")
    res = _cli("run", src2, "--out", lone)
    assert res.exit_code == 2 and "signals.npz" in res.output
    # files no run writes do not count
    (lone / "signals.npz").unlink()
    assert _cli("run", src2, "--out", lone).exit_code == 0
    assert (lone / "notes.txt").read_text() == "mine"


def test_force_replaces_the_earlier_run_entirely(tmp_path):
    """--force: the run's files replace the earlier run's, and the earlier
    run's files this run does not write (another format, its figure) are
    removed: the folder holds one run."""
    out = tmp_path / "d"
    assert _cli("run", _toml(tmp_path, 'name = "first"\n' + SHORT), "--out", out,
                "--format", "npz,mat").exit_code == 0
    (out / "notes.txt").write_text("mine")
    src2 = _toml(tmp_path, 'name = "second"\nduration = 0.02\n', "s2.toml")
    res = _cli("run", src2, "--out", out, "--force")
    assert res.exit_code == 0, res.output
    assert set(_files(out)) == {"signals.npz", "summary.json", "scenario.toml", "second.png",
                                "notes.txt"}
    assert json.loads((out / "summary.json").read_text())["name"] == "second"
    assert np.load(out / "signals.npz")["t"].shape == (200,)
    assert "earlier run (scenario 'first')" in res.output  # said on stderr


def test_reproduce_replaces_its_own_results(tmp_path, monkeypatch):
    """`make reproduce` runs `smodrive reproduce --out results` again and
    again into one folder: its own files are replaced, never refused."""

    def fig(fig_dir):
        (fig_dir / "f1.png").write_bytes(b"png")
        return fig_dir / "f1.png"

    def run(progress):
        return Outcome([Claim(id="fake.c", statement="s", paper=None, expected=1.0,
                              reproduced=1.0, unit="", tolerance=0.1)], figures=[("f1", fig)])

    monkeypatch.setitem(report.PAPERS, "fake",
                        types.SimpleNamespace(EXPERIMENTS=[Experiment("fake.x", "t", run)]))
    out = tmp_path / "results"
    for _ in range(2):
        res = _cli("reproduce", "fake", "--out", out)
        assert res.exit_code == 0, res.output
        assert json.loads((out / "claims.json").read_text())
        assert (out / "report.md").is_file() and (out / "figures" / "f1.png").is_file()


# ------------------------------------------------------- sweep bound ------

def _huge_sweep(n: int) -> dict:
    return {"sweep": {"base": "drive.pi_encoder", "metrics": ["id_error"]},
            "axes": [{"name": "L_ratio", "key": "controller.L_s_hat", "relative_to": "motor.L_s",
                      "range": [0.5, 2.0], "n": n},
                     {"name": "R_ratio", "key": "controller.R_s_hat", "relative_to": "motor.R_s",
                      "range": [0.5, 2.0], "n": n}]}


def test_a_sweep_beyond_the_run_bound_is_refused_before_allocating():
    """Two axes of n = 100000 are 1e10 runs (11 GB before this check): the
    count, the axes' sizes and the bound are named, from the sizes alone."""
    tracemalloc.start()
    try:
        with pytest.raises(ParameterError) as exc:
            sweep.parse_sweep(_huge_sweep(100_000), "huge")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    msg = str(exc.value)
    assert "\n" not in msg
    for word in ("10,000,000,000 runs", "L_ratio 100000 x R_ratio 100000",
                 f"{sweep.MAX_RUNS:,}"):
        assert word in msg, word
    assert peak < 100e6  # the axes' values, not the runs
    # seeds and Latin-hypercube samples count too
    spec = _huge_sweep(1000)
    spec["seeds"] = {"n": 2}
    with pytest.raises(ParameterError, match=r"2,000,000 runs \(L_ratio 1000 x R_ratio 1000 x "
                                             r"2 seeds\)"):
        sweep.parse_sweep(spec)
    spec = _huge_sweep(10)
    spec["sweep"].update(sample="lhs", samples=1_000_000)
    spec["axes"].append({"name": "current", "key": "controller.current",
                         "values": ["pi", "dbpc"]})
    with pytest.raises(ParameterError, match=r"2,000,000 runs \(current 2 x 1000000 lhs"):
        sweep.parse_sweep(spec)
    # at the bound: accepted (not expanded here)
    assert sweep.run_count(sweep.parse_sweep(_huge_sweep(1000)))[0] == sweep.MAX_RUNS


def test_the_sweep_command_refuses_a_huge_spec_in_one_line(tmp_path):
    src = tmp_path / "huge.toml"
    src.write_text('[sweep]\nbase = "drive.pi_encoder"\nmetrics = ["id_error"]\n'
                   '[[axes]]\nname = "a"\nkey = "controller.L_s_hat"\nrange = [1e-3, 2e-3]\n'
                   'n = 100000\n[[axes]]\nname = "b"\nkey = "controller.R_s_hat"\n'
                   "range = [0.5, 1.0]\nn = 100000\n")
    # in a process of at most 3 GiB of address space: a sweep that lists its
    # runs first ends in a MemoryError there, not in the machine's swap
    res = subprocess.run([sys.executable, "-m", "smodrive.cli", "sweep", str(src), "--out",
                          str(tmp_path / "o")], cwd=tmp_path, env=_env(), capture_output=True,
                         text=True, timeout=300, preexec_fn=_limit_memory)
    assert res.returncode == 2, res.stderr
    assert res.stderr.startswith("error:") and res.stderr.count("\n") == 1, res.stderr
    assert "10,000,000,000 runs" in res.stderr and "a 100000 x b 100000" in res.stderr
    assert res.stdout == ""
    assert not (tmp_path / "o").exists()


def _limit_memory() -> None:
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (3 * 2**30, 3 * 2**30))


# ------------------------------------------------ the API's arguments -----

@pytest.mark.parametrize("bad,words", [
    (None, ("s = None", "not a Scenario", "Scenario(")),
    ("yang2018.fig7a", ("s = 'yang2018.fig7a'", "catalogue()['yang2018.fig7a']",
                        "load_scenario")),
    ({"duration": 0.1}, ("s = {'duration': 0.1}", "scenario_from_dict")),
])
def test_simulate_refuses_what_is_not_a_scenario(bad, words):
    with pytest.raises(ParameterError) as exc:
        simulate(bad)
    for w in words:
        assert w in str(exc.value), w


@pytest.mark.parametrize("value", [math.nan, 0, 0.0, -1, math.inf, "0.1", True])
def test_simulate_refuses_a_chunk_outside_its_range(value):
    with pytest.raises(ParameterError, match=r"chunk_seconds = .* \(0, inf\) s"):
        simulate(Scenario(duration=0.01), chunk_seconds=value)


def test_simulate_refuses_an_unknown_design():
    with pytest.raises(ParameterError, match=r"design = 'fast' \(str\) must be None .*"
                                             r"ObserverDesignPars"):
        simulate(Scenario(duration=0.01), design="fast")
    r = simulate(Scenario(duration=0.01), design=ObserverDesignPars(), chunk_seconds=0.004)
    assert r["t"].shape == (100,)


def test_an_unknown_channel_is_a_key_error_naming_it_and_the_channels():
    r = simulate(Scenario(duration=0.01))
    for get in (lambda n: r[n], Result.unit, Result.description, r.unit):
        with pytest.raises(KeyError) as exc:
            get("nope")
        msg = exc.value.args[0]
        assert "'nope' is not a logged channel" in msg and "w_M_ref, i_d_ref" in msg
        assert "CHANNELS" in msg
    with pytest.raises(KeyError, match=r"closest: w_M\b"):
        r["w_m"]
    with pytest.raises(KeyError, match=r"n_rpm is derived: Result\.n_rpm"):
        r["n_rpm"]
    with pytest.raises(KeyError, match="not a logged channel"):
        Result.unit(["w_M"])  # unhashable
    assert r["w_M"].shape == (100,) and Result.unit("w_M") == "rad/s"


def test_atomic_path_replaces_only_a_whole_file(tmp_path):
    p = tmp_path / "f.txt"
    p.write_text("old")
    with pytest.raises(RuntimeError):
        with smodrive.engine.export.atomic_path(p) as tmp:
            tmp.write_text("half")
            raise RuntimeError("killed")
    assert p.read_text() == "old" and [q.name for q in tmp_path.iterdir()] == ["f.txt"]
    smodrive.engine.export.write_text(p, "new")
    assert p.read_text() == "new" and [q.name for q in tmp_path.iterdir()] == ["f.txt"]


def test_a_sweeps_spec_and_maps_are_written_atomically(tmp_path, monkeypatch):
    """sweep.json, sweep.toml and the maps reach their names by os.replace
    of a temporary file (the Parquet parts already were)."""
    from smodrive.sweep import plot_all

    src = tmp_path / "small.toml"
    src.write_text('[sweep]\nbase = "drive.pi_encoder"\nmetrics = ["ripple"]\n'
                   'window = [0.01, 0.02]\n[set]\nduration = 0.02\n'
                   '[[axes]]\nname = "L_ratio"\nkey = "controller.L_s_hat"\n'
                   'relative_to = "motor.L_s"\nvalues = [0.5, 1.0]\n'
                   '[[plots]]\nkind = "lines"\nfile = "lines"\nx = "L_ratio"\n'
                   'metric = "ripple"\n')
    spec = sweep.load_sweep(src)
    out = tmp_path / "o"
    replaced: list[str] = []
    real = os.replace

    def spy(a, b):
        replaced.append(Path(b).name)
        return real(a, b)

    monkeypatch.setattr(os, "replace", spy)
    sweep.prepare_out(spec, out, src.read_text())
    sweep.write_part(out, spec, sweep.run_local(spec))
    paths = plot_all(spec, out)
    assert [p.name for p in paths] == ["lines.png"] and paths[0].stat().st_size > 1000
    assert {"sweep.json", "sweep.toml", "lines.png"} <= set(replaced)
    assert sorted(p.name for p in (out / "maps").iterdir()) == ["lines.png"]
