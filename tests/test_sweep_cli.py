"""`smodrive sweep` into a folder that already holds results: the end line
counts every run of the sweep (computed now and reused), another sweep is
refused before anything runs, a built-in sweep leaves its sweep.toml like a
sweep file does, and building a large grid shows its progress (a LocalCluster
of one worker where a test runs; the sweeps are a few runs of 0.2 s)."""

from __future__ import annotations

import hashlib
import json

import numpy as np
from click.testing import CliRunner

from smodrive import sweep as sw
from smodrive.cli import main
from smodrive.sweep import plan as sweep_plan
from smodrive.sweep import spec as sweep_spec
from test_sweep import small


def _flat(text: str) -> str:
    """The CLI's output as one line (rich wraps long lines at its width)."""
    return " ".join(text.split())


def _sweep(*args: str):
    return CliRunner().invoke(main, ["sweep", *args, "--workers", "1"])


def test_resumed_sweep_end_line_counts_all_its_runs(tmp_path):
    """A sweep resumed into its folder says how many runs it has in all, how
    many it computed now and how many it reused, and its counts of faults
    and of runs that did not hold are of all of them (they were of the
    computed ones only: 0 when every run was reused)."""
    # 2 L_hat x 2 controllers x 2 seeds = 8 runs, in that order; conventional DBPC at
    # L_hat = 2.5 L (run 4, reused below) rides the voltage limit: it does not hold
    spec_file = small(tmp_path, plots=False, L_values="[1.0, 2.5]")
    spec = sw.load_sweep(spec_file)
    runs = sw.expand(spec)
    assert len(runs) == 8
    out = tmp_path / "o"
    # the folder as an interrupted sweep leaves it: its first 5 runs
    sw.prepare_out(spec, out, spec_file.read_text())
    sw.write_part(out, spec, sw.run_local(spec, runs[:5]))
    res = _sweep(str(spec_file), "--out", str(out))
    assert res.exit_code == 0, res.output
    text = _flat(res.output)
    assert "8 runs in all: 3 computed now in " in text, text
    assert f", 5 reused from {out};" in text, text
    rows = sw.load_results(spec, out)
    assert len(rows["run_id"]) == 8
    faults = int(np.sum(rows["status"] == "fault"))
    not_held = int(np.sum((rows["status"] == "ok") & ~rows["held"].astype(bool)))
    held_reused = rows["held"][:5].astype(bool)
    assert not held_reused.all()  # a reused run did not hold: the counts below see it
    counts = (f"of the 8: {faults} end in a fault, {not_held} did not hold their operating "
              "point, 0 could not run")
    assert counts in text, text
    # again: every run reused, none computed; the counts the same
    res = _sweep(str(spec_file), "--out", str(out))
    assert res.exit_code == 0, res.output
    text = _flat(res.output)
    assert f"8 runs in all: 0 computed now, 8 reused from {out};" in text, text
    assert counts in text, text


def test_another_sweep_into_a_sweep_folder_is_refused(tmp_path):
    """A sweep with other axis values run into a folder holding another
    sweep's results is refused before it runs, named (exit 2, no
    traceback); the folder is left as it was. The same sweep with another
    title and plots (which do not change its runs) resumes there."""
    a = small(tmp_path, plots=False, name="a")  # L_hat 0.5, 1, 2 L
    b = small(tmp_path, plots=False, L_values="[0.5, 1.0]", name="b")
    spec_a = sw.load_sweep(a)
    runs_a = sw.expand(spec_a)
    out = tmp_path / "o"
    sw.prepare_out(spec_a, out, a.read_text())
    sw.write_part(out, spec_a, sw.run_local(spec_a, runs_a[:2]))
    stored = {p.name: p.read_bytes() for p in [out / "sweep.json", out / "sweep.toml",
                                              *(out / "runs").iterdir()]}
    res = _sweep(str(b), "--out", str(out))
    assert res.exit_code == 2, res.output
    assert "Traceback" not in res.output
    text = _flat(res.output)
    assert text.startswith(f"error: sweep b: {out} holds the results of another sweep (a: "
                           "L_ratio 3 x current 2 x 2 seeds)"), text
    assert "it differs in axis L_ratio" in text, text
    assert f"choose another --out folder, or delete {out}" in text, text
    assert "starting Dask" not in text  # refused before anything ran
    assert {p.name: p.read_bytes() for p in [out / "sweep.json", out / "sweep.toml",
                                            *(out / "runs").iterdir()]} == stored
    # the same runs under another title and with plots: resumed, 2 reused
    same = tmp_path / "a2.toml"
    same.write_text(small(tmp_path, name="a3").read_text().replace('title = "test"',
                                                                   'title = "renamed"'))
    res = _sweep(str(same), "--out", str(out), "--no-plot")
    assert res.exit_code == 0, res.output
    assert "12 runs in all: 10 computed now in " in _flat(res.output), res.output
    assert sorted(sw.load_results(spec_a, out)["run_id"]) == sorted(r.id for r in runs_a)


def test_a_builtin_sweep_writes_its_sweep_toml(tmp_path, monkeypatch):
    """A sweep run by its built-in name leaves OUT/sweep.toml as a sweep
    file's run does (docs/sweeps.md: every sweep folder holds one): its
    text is the built-in file's, and it loads to the same runs."""
    spec = sw.load_sweep("yang2018_current")
    sw.prepare_out(spec, tmp_path / "real")
    assert ((tmp_path / "real" / "sweep.toml").read_text(encoding="utf-8")
            == sw.builtin_path("yang2018_current").read_text(encoding="utf-8"))
    # the CLI, on a built-in sweep of 2 runs (the real ones take minutes)
    builtin = tmp_path / "builtin"
    builtin.mkdir()
    text = small(tmp_path, plots=False, L_values="[1.0]", seeds=1).read_text()
    (builtin / "tiny.toml").write_text(text)
    monkeypatch.setattr(sweep_spec, "BUILTIN_DIR", builtin)
    assert "tiny" in sw.builtins()
    out = tmp_path / "o"
    res = _sweep("tiny", "--out", str(out))
    assert res.exit_code == 0, res.output
    assert (out / "sweep.toml").read_text(encoding="utf-8") == text
    assert ([r.id for r in sw.expand(sw.load_sweep(out / "sweep.toml"))]
            == [r.id for r in sw.expand(sw.load_sweep("tiny"))])


def test_building_a_large_grid_shows_its_progress(tmp_path):
    """Building the runs of a large grid (1,000,000 runs took 55 s) reports
    its progress as it goes, and the CLI shows that phase; the run ids are
    those of the formula every sweep folder was written with (a folder
    resumes after the faster build)."""
    grid = tmp_path / "grid.toml"
    grid.write_text(small(tmp_path, plots=False, seeds=40).read_text().replace(
        "values = [0.5, 1.0, 2.0]", "range = [0.5, 2.0]\nn = 250"))
    spec = sw.load_sweep(grid)
    calls: list[tuple[int, int]] = []
    runs = sw.expand(spec, progress=lambda done, total: calls.append((done, total)))
    total = 250 * 2 * 40
    assert len(runs) == total and calls[-1] == (total, total)
    done = [d for d, t in calls if t == total]
    assert len(done) >= 10 and done == sorted(done) and 0 < done[1] < total  # as it goes
    for r in runs:
        key = json.dumps({"base": spec.base_toml, "window": spec.window, "metrics": spec.metrics,
                          "changes": r.changes, "rows": sweep_plan.ROW_FORMAT},
                         sort_keys=True, default=repr)
        assert r.id == hashlib.sha256(key.encode()).hexdigest()[:20]
    # the CLI names the phase and its size: 2 L_hat x 2 controllers x 1 seed
    tiny = small(tmp_path, plots=False, L_values="[1.0, 2.0]", seeds=1, name="tiny")
    res = _sweep(str(tiny), "--out", str(tmp_path / "o"))
    assert res.exit_code == 0, res.output
    text = _flat(res.output)
    assert "tiny: building 4 runs" in text, text
    assert text.index("tiny: building 4 runs") < text.index("tiny: starting Dask")


def test_the_axes_sizes_count_one_seed_as_one():
    """run_count's text said "1 seeds"; 1 seed and 2 seeds now."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as d:
        for n, want in ((1, "x 1 seed"), (2, "x 2 seeds")):
            _, text = sweep_spec.run_count(sw.load_sweep(small(Path(d), seeds=n, plots=False)))
            assert text.endswith(want), text
