"""Sweeps (smodrive.sweep): the file format and its errors, the runs a sweep
expands to, the worker's rows against simulate(), determinism across worker
counts, resumption after a killed sweep and after a killed worker, maps."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from smodrive import scenario_io
from smodrive import sweep as sw
from smodrive.analysis.metrics import metric_values, operating_point
from smodrive.analysis.tf import dbpc_steady_state
from smodrive.cli import main
from smodrive.model import ParameterError
from smodrive.engine import simulate
from smodrive.scenario_io import scenario_from_dict
from smodrive.scenarios import catalogue
from smodrive.sweep import lowest_holding

ROOT = Path(__file__).resolve().parents[1]

SMALL = """
[sweep]
title = "test"
base = "drive.pi_encoder"
metrics = ["id_error", "iq_error", "ripple", "fault", "pos_error_rms_deg"]
window = [0.1, 0.2]
batch_seconds = {batch}

[set]
duration = {duration}

[[axes]]
name = "L_ratio"
label = "L_hat / L"
key = "controller.L_s_hat"
relative_to = "motor.L_s"
values = {L_values}

[[axes]]
name = "current"
key = "controller.current"
values = ["dbpc", "robust_dbpc"]

[seeds]
n = {seeds}
"""


def small(tmp_path: Path, batch=0.01, duration=0.2, L_values="[0.5, 1.0, 2.0]", seeds=2,
          plots=True, name="small") -> Path:
    text = SMALL.format(batch=batch, duration=duration, L_values=L_values, seeds=seeds)
    if plots:
        text += ('[[plots]]\nkind = "lines"\nfile = "lines"\nx = "L_ratio"\nhue = "current"\n'
                 'metric = "ripple"\n')
    p = tmp_path / f"{name}.toml"
    p.write_text(text)
    return p


def _parts_ids(out: Path) -> list[str]:
    t = sw.read_parts(out)
    return [] if t is None else t.column("run_id").to_pylist()


# ------------------------------------------------------------ the format ---

def _bad(tmp_path, text: str) -> str:
    p = tmp_path / "bad.toml"
    p.write_text(text)
    with pytest.raises(ParameterError) as e:
        sw.load_sweep(p)
    return str(e.value)


def test_bad_fields_are_named_with_their_valid_range(tmp_path):
    good = small(tmp_path).read_text()
    msg = _bad(tmp_path, good.replace("values = [0.5, 1.0, 2.0]", "range = [0.5, 2.0]\nn = 0"))
    assert "axes[0] (L_ratio).n = 0" in msg and "[1, 100000]" in msg
    msg = _bad(tmp_path, good.replace("values = [0.5, 1.0, 2.0]",
                                      'range = [0.5, 2.0]\nn = 3\nspacing = "cubic"'))
    assert "axes[0] (L_ratio).spacing = 'cubic'" in msg and "linear, log" in msg
    msg = _bad(tmp_path, good.replace('name = "current"', 'name = "current"\nstep = 2'))
    assert "axes[1] (current).step: unknown field" in msg
    msg = _bad(tmp_path, good.replace('"ripple"', '"rippel"'))
    assert "'rippel' is not a metric" in msg and "ripple" in msg
    msg = _bad(tmp_path, good.replace("window = [0.1, 0.2]", "window = [0.1, 0.5]"))
    assert "sweep.window" in msg and "duration = 0.2 s" in msg
    msg = _bad(tmp_path, good.replace('base = "drive.pi_encoder"', 'base = "nope.toml"'))
    assert "sweep.base = 'nope.toml'" in msg
    # a value the scenario refuses is named with its axis and the field's range
    p = tmp_path / "bad.toml"
    p.write_text(good.replace("[0.5, 1.0, 2.0]", "[0.5, 1.0, -2.0]"))
    spec = sw.load_sweep(p)
    with pytest.raises(ParameterError) as e:
        sw.check_runs(spec, sw.expand(spec))
    assert "axis L_ratio = -2.0" in str(e.value) and "controller.L_s_hat" in str(e.value)
    assert "valid range" in str(e.value)
    msg = _bad(tmp_path, good.replace("[seeds]\nn = 2", "[seeds]\nn = 2\nfirst = -1"))
    assert "seeds.first = -1" in msg


def test_runs_ids_and_latin_hypercube(tmp_path):
    spec = sw.load_sweep(small(tmp_path))
    runs = sw.expand(spec)
    assert len(runs) == 3 * 2 * 2  # L values x controllers x seeds
    assert len({r.id for r in runs}) == len(runs)
    # the first axis varies slowest, the seed fastest
    assert [r.point["seed"] for r in runs[:4]] == [0, 1, 0, 1]
    assert [r.point["L_ratio"] for r in runs[::4]] == [0.5, 1.0, 2.0]
    assert runs[0].changes == {"controller": {"L_s_hat": 0.5 * spec.base.motor.L_s,
                                              "current": "dbpc"}, "adc": {"seed": 0}}
    # ids: the same file gives the same ids; an extended grid keeps the old ones
    again = sw.expand(sw.load_sweep(small(tmp_path)))
    assert [r.id for r in again] == [r.id for r in runs]
    wider = sw.expand(sw.load_sweep(small(tmp_path, L_values="[0.5, 1.0, 2.0, 1.5]",
                                          name="w")))
    assert {r.id for r in runs} < {r.id for r in wider}
    # another base (a [set] change) makes every run another one
    other = sw.expand(sw.load_sweep(small(tmp_path, duration=0.25, name="o")))
    assert not {r.id for r in runs} & {r.id for r in other}
    # Latin hypercube: each axis's range cut into n equal strata (log strata on
    # a log axis), exactly one sample in each
    lhs = tmp_path / "lhs.toml"
    lhs.write_text("""
[sweep]
base = "drive.pi_encoder"
metrics = ["ripple"]
sample = "lhs"
samples = 40
seed = 3
[[axes]]
name = "a"
key = "controller.L_s_hat"
relative_to = "motor.L_s"
range = [0.5, 2.0]
n = 2
spacing = "log"
[[axes]]
name = "b"
key = "adc.noise"
draw = "uniform"
low = 0.0
high = 0.04
n = 5
[[axes]]
name = "c"
key = "controller.current"
values = ["dbpc", "pi"]
""")
    runs = sw.expand(sw.load_sweep(lhs))
    assert len(runs) == 2 * 40
    for c in ("dbpc", "pi"):
        pts = [r.point for r in runs if r.point["c"] == c]
        a = np.log(np.array([p["a"] for p in pts]) / 0.5) / np.log(4.0)
        b = np.array([p["b"] for p in pts]) / 0.04
        for u in (a, b):
            assert sorted(np.floor(u * 40).astype(int)) == list(range(40))


def test_changes_are_applied_as_a_scenario_file_reads_them():
    """[set] and a run's changes go through scenario_io.apply, the function a
    scenario file goes through: the same keys, units and messages; another
    motor keeps the controller values the base sets (a file derives them
    anew)."""
    base = catalogue()["drive.pi_encoder"]()
    ch = {"w_M0_rpm": 900.0, "controller": {"L_s_hat": 0.03}, "adc": {"seed": 3}}
    assert sw.apply_changes(base, ch) == scenario_from_dict({"base": "drive.pi_encoder", **ch})
    with pytest.raises(ParameterError, match=r"controller\.L_s_hat = -1\.0 is outside its valid "
                                             r"range \(0, 10\] H"):
        sw.apply_changes(base, {"controller": {"L_s_hat": -1.0}})
    with pytest.raises(ParameterError, match=r"^base: only in \[sweep\]"):
        sw.apply_changes(base, {"base": "drive.pi_encoder"})
    own = base.with_controller(L_s_hat=0.03)  # set, not derived from the motor
    motor = {"motor": {"L_s": 0.02}}
    assert sw.apply_changes(own, motor).controller.L_s_hat == 0.03
    assert scenario_io.apply(own, motor).controller.L_s_hat == 0.02


# ------------------------------------------------------------ the rows ---

def test_worker_row_is_simulate_with_the_registry(tmp_path):
    """The worker runs the samples before the window unlogged, in one call:
    its metrics and its operating point are bit-identical to the registry's
    on a full simulate() log. And the map of conventional DBPC meets eq. (12)
    at L_hat = 0.5 L within the tolerance of the claim yang2018.fig5a (0.1
    |prediction| + 0.05 A)."""
    spec = sw.load_sweep(small(tmp_path, duration=0.6, seeds=1))
    spec.window = (0.3, 0.6)
    runs = sw.expand(spec)
    run = runs[0]  # L_ratio 0.5, dbpc, seed 0
    row = sw.run_one(sw.Job(spec.base, spec.metrics, spec.window, False, "t"), run)
    assert row["status"] == "ok"
    r = simulate(sw.apply_changes(spec.base, run.changes))
    ref = metric_values(r, spec.metrics, 0.3, 0.6)
    for m in spec.metrics:
        assert row[m] == ref[m] or (math.isnan(row[m]) and math.isnan(ref[m])), m
    op = operating_point(r, 0.3, 0.6)
    assert op.held and row["held"] is True and row["not_held"] == ""
    for k in ("speed_offset_rpm", "i_limit_share", "u_limit_share"):
        assert row[k] == getattr(op, k), k
    s = spec.base
    w = s.w_M0
    i_q = (s.load.T_brake(0.0) + s.motor.B * w) / s.motor.k_t
    i_d, _ = dbpc_steady_state(s.motor.L_s, s.motor.R_s, s.motor.psi_r, 0.5 * s.motor.L_s,
                               s.motor.R_s, s.motor.psi_r, w * s.motor.n_p, s.T_sp, 0.0, i_q)
    assert abs(row["id_error"] - i_d) <= 0.1 * abs(i_d) + 0.05


# --------------------------------------------------- Dask and Parquet ---

def test_same_metrics_on_one_and_two_workers(tmp_path):
    spec = sw.load_sweep(small(tmp_path))
    rep1 = sw.run_sweep(spec, tmp_path / "w1", workers=1)
    rep2 = sw.run_sweep(spec, tmp_path / "w2", workers=2)
    assert (rep1.computed, rep2.computed, rep2.workers) == (12, 12, 2)
    assert rep2.batches > 2  # the work was split
    a, b = sw.load_results(spec, tmp_path / "w1"), sw.load_results(spec, tmp_path / "w2")
    local = sw.run_local(spec)
    assert list(a["run_id"]) == list(b["run_id"]) == [r["run_id"] for r in local]
    for m in spec.metrics:
        ref = np.array([r[m] for r in local])
        assert np.array_equal(a[m], b[m], equal_nan=True), m
        assert np.array_equal(a[m], ref, equal_nan=True), m
    assert set(a["status"]) == {"ok"}
    # what a row carries besides the metrics
    assert set(sw.STANDARD_COLUMNS) - {"seed"} < set(a) and "seed" in a
    assert np.all(a["wall_s"] > 0) and np.all(a["steps"] == 2000)
    # maps from the results: a lines plot with its band, via the CLI
    res = CliRunner().invoke(main, ["sweep", "--plot", str(tmp_path / "w1")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "w1" / "maps" / "lines.png").stat().st_size > 10_000


def test_ctrl_c_stops_a_sweep_without_a_traceback(tmp_path):
    """Ctrl-C in a terminal signals the whole process group: the sweep's
    Dask workers printed two tracebacks (CancelledError, KeyboardInterrupt)
    before "Aborted!". The workers now start with SIGINT ignored; the CLI
    stops with "Aborted!", exit 1, no traceback (the interrupted sweep is
    resumed by running it again: the test above)."""
    src = small(tmp_path, duration=2.0, L_values="[0.5, 0.75, 1.0, 1.25, 1.5]", seeds=20,
                plots=False)
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(Path(sw.__file__).resolve().parents[2])
           + os.pathsep + os.environ.get("PYTHONPATH", "")}
    # (SIGINT at its default, as in a terminal's foreground job; a background job of a
    # non-interactive shell, and so a test's child, may start with it ignored)
    proc = subprocess.Popen([sys.executable, "-m", "smodrive.cli", "sweep", str(src), "--out",
                             str(out), "--workers", "2"], env=env, start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        t_end = time.time() + 60
        while time.time() < t_end and not list((out / "runs").glob("part-*.parquet")):
            assert proc.poll() is None, "the sweep ended before it was interrupted"
            time.sleep(0.005)
        os.killpg(proc.pid, signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert proc.returncode == 1
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert "Aborted" in err


def test_killed_sweep_resumes_with_the_missing_runs_only(tmp_path):
    """A sweep killed (SIGKILL to the CLI and its cluster) after some batches:
    the same command again computes exactly the runs that have no row."""
    # 200 runs of 2 s (about 2 s of work on one worker): the sweep is killed
    # after its first part, long before its end
    src = small(tmp_path, duration=2.0, L_values="[0.5, 0.75, 1.0, 1.25, 1.5]", seeds=20,
                plots=False)
    spec = sw.load_sweep(src)
    total = len(sw.expand(spec))
    out = tmp_path / "out"
    # the subprocess imports the smodrive these tests import (installed or src/)
    env = {**os.environ, "PYTHONPATH": str(Path(sw.__file__).resolve().parents[2])
           + os.pathsep + os.environ.get("PYTHONPATH", "")}
    proc = subprocess.Popen([sys.executable, "-m", "smodrive.cli", "sweep", str(src), "--out",
                             str(out), "--workers", "1"], env=env, start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        t_end = time.time() + 60
        while time.time() < t_end and not list((out / "runs").glob("part-*.parquet")):
            assert proc.poll() is None, "the sweep ended before it was killed"
            time.sleep(0.005)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    before = _parts_ids(out)
    assert 0 < len(before) < total, (len(before), total)
    rep = sw.run_sweep(spec, out, workers=1)
    assert rep.done_before == len(before)
    assert rep.computed == total - len(before)
    ids = _parts_ids(out)
    assert sorted(ids) == sorted(r.id for r in sw.expand(spec))  # each run exactly once
    # a part being written when the sweep was killed is cleared, never read
    assert not list((out / "runs").glob(".*tmp"))
    assert sw.run_sweep(spec, out, workers=1).computed == 0


def test_worker_killed_mid_sweep_loses_no_result(tmp_path):
    src = small(tmp_path, duration=1.0, L_values="[0.5, 0.75, 1.0, 1.25, 1.5]", seeds=8,
                plots=False)
    spec = sw.load_sweep(src)
    total = len(sw.expand(spec))
    client, cluster = sw.start_client(workers=2)
    killed: list[int] = []
    after_kill: list[int] = []
    try:
        pids = client.run(os.getpid)

        def on_batch(rows, cl):
            if killed:
                after_kill.append(len(rows))
                return
            busy = [w for w, tasks in cl.processing().items() if tasks]
            if busy:  # kill a worker that is running a batch
                killed.append(pids[busy[0]])
                os.kill(pids[busy[0]], signal.SIGKILL)

        rep = sw.run_sweep(spec, tmp_path / "out", client=client, on_batch=on_batch)
        assert killed and sum(after_kill) > 0  # killed mid-sweep, the sweep went on
        assert rep.failed_batches == []
        assert rep.computed == total
        ids = _parts_ids(tmp_path / "out")
        assert sorted(ids) == sorted(r.id for r in sw.expand(spec))  # each run exactly once
        assert sw.run_sweep(spec, tmp_path / "out", client=client).computed == 0
    finally:
        client.close()
        cluster.close()


# ------------------------------------------------------ maps and the CLI ---

def test_lowest_speed_that_holds():
    speeds = [25.0, 50.0, 100.0, 200.0]
    over = np.array(speeds)
    # holds from 100 up: 100
    assert lowest_holding(speeds, np.array([False, False, True, True]), over) == 100.0
    # 50 holds but 100 does not: the envelope is what holds from there up, 200
    assert lowest_holding(speeds, np.array([False, True, False, True]), over) == 200.0
    assert math.isnan(lowest_holding(speeds, np.array([True, True, True, False]), over))
    assert lowest_holding(speeds, np.ones(4, bool), over) == 25.0


def test_builtin_sweeps_load_and_fit_a_few_minutes():
    names = sw.builtins()
    assert set(names) == {"yang2018_current", "yang2018_envelope", "yao2022_observers"}
    for name in names:
        spec = sw.load_sweep(name)
        runs = sw.expand(spec)
        sw.check_runs(spec, runs)
        # estimated from the engine's rate and the LCL designs: under 3
        # minutes on 2 workers
        assert sum(sw.estimate_seconds(spec, runs)) / 2 < 180.0, name
        assert spec.plots


def test_cli_sweep_errors_and_list(tmp_path):
    runner = CliRunner()
    res = runner.invoke(main, ["sweep", "--list"])
    assert res.exit_code == 0 and "yang2018_current" in res.output
    bad = tmp_path / "bad.toml"
    bad.write_text(small(tmp_path).read_text().replace("n = 2", "n = 2.5"))
    res = runner.invoke(main, ["sweep", str(bad), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert "seeds.n = 2.5" in res.output and "Traceback" not in res.output
    res = runner.invoke(main, ["sweep", "--plot", str(tmp_path / "nothing")])
    assert res.exit_code == 2 and "no sweep.json" in res.output
    res = runner.invoke(main, ["sweep", "nosuch"])
    assert res.exit_code == 2 and "built-in sweep" in res.output


def test_the_docs_example_and_quoted_errors(tmp_path):
    """docs/sweeps.md: its sweep file loads as written, and the errors it
    quotes are the ones raised."""
    doc = (ROOT / "docs" / "sweeps.md").read_text()
    block = doc.split("```toml\n")[1].split("```")[0]
    p = tmp_path / "doc.toml"
    p.write_text(block)
    spec = sw.load_sweep(p)
    assert len(sw.expand(spec)) == 22 * 3 * 10
    good = small(tmp_path).read_text()
    quoted = [
        _bad(tmp_path, good.replace("values = [0.5, 1.0, 2.0]", "range = [0.5, 2.0]\nn = 0")),
        _bad(tmp_path, good.replace("window = [0.1, 0.2]", "window = [0.1, 0.5]")),
    ]
    p.write_text(good.replace("[0.5, 1.0, 2.0]", "[0.5, 1.0, -2.0]"))
    spec = sw.load_sweep(p)
    with pytest.raises(ParameterError) as e:
        sw.check_runs(spec, sw.expand(spec))
    quoted.append(str(e.value))
    flat = " ".join(doc.split())
    snippets = ["axes[0] (L_ratio).n = 0 is outside its valid range: a whole number in "
                "[1, 100000]",
                "sweep.window = [0.1, 0.5] must be [t0, t1] seconds with 0 <= t0 < t1 <= "
                "duration = 0.2 s",
                "axis L_ratio = -2.0: controller.L_s_hat = -0.0469 is outside its valid range "
                "(0, 10] H"]
    for snippet, msg in zip(snippets, quoted):
        assert f"`{snippet}" in flat and snippet in msg, (snippet, msg)


def test_lock_metrics_on_a_constructed_log():
    """holds_lock, time_to_lock, fault and fault_time on a log whose angle
    error is known: 20 deg until t = 0.3 s, then 5 deg, then one 12 deg
    sample at t = 0.5 s; after it 1 deg."""
    from smodrive.analysis.metrics import METRICS, LOCK_DEG
    from smodrive.model import Scenario
    from smodrive.engine import CHANNELS, FaultReport, Result

    assert LOCK_DEG == 10.0
    t = np.arange(1000) * 1e-3
    err = np.where(t < 0.3, 20.0, 5.0)
    err[500] = 12.0
    err[501:] = 1.0
    data = np.zeros((t.size, len(CHANNELS)))
    data[:, CHANNELS.index("t")] = t
    data[:, CHANNELS.index("theta_r")] = np.radians(err)
    r = Result(Scenario(duration=1.0, T_sp=1e-3), data, 0, FaultReport(None, 0, 0))
    vals = metric_values(r, ["holds_lock", "time_to_lock", "pos_error_peak_deg", "fault",
                             "fault_time"], 0.6, 1.0)
    assert vals["holds_lock"] == 1.0 and vals["pos_error_peak_deg"] == pytest.approx(1.0)
    assert vals["time_to_lock"] == pytest.approx(0.501)  # the sample after the last 12 deg
    assert vals["fault"] == 0.0 and math.isnan(vals["fault_time"])
    assert metric_values(r, ["holds_lock"], 0.4, 1.0)["holds_lock"] == 0.0  # 12 deg inside
    faulted = Result(r.scenario, data, 0, FaultReport(0.25, 32, 32))
    vals = metric_values(faulted, ["holds_lock", "fault", "fault_time"], 0.6, 1.0)
    assert vals == {"holds_lock": 0.0, "fault": 1.0, "fault_time": 0.25}
    assert METRICS["time_to_lock"].needs_full_log


def test_cli_summary_counts_faults_by_kind_and_runs_not_held(tmp_path):
    """`smodrive sweep` says how many runs did not hold their operating point
    and which faults ended the others (issue 21): the numbers it prints are
    those of the rows it wrote."""
    spec_file = small(tmp_path, plots=False)
    res = CliRunner().invoke(main, ["sweep", str(spec_file), "--out", str(tmp_path / "o"),
                                    "--workers", "1"])
    assert res.exit_code == 0, res.output
    rows = sw.load_results(sw.load_sweep(spec_file), tmp_path / "o")
    ok = rows["status"] == "ok"
    n_not_held = int(np.sum(ok & ~rows["held"].astype(bool)))
    assert f"{n_not_held} did not hold their operating point" in " ".join(res.output.split())
    assert f"{int(np.sum(rows['status'] == 'fault'))} end in a fault" in \
        " ".join(res.output.split())
