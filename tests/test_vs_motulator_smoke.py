"""The motulator comparison script runs on a tiny case without motulator (no
venv, no network): the smodrive side of every section and the table writing.
It asserts nothing about speed or about motulator (benchmarks are not tests)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_vs_motulator_script_runs_without_motulator(tmp_path):
    out = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "vs_motulator.py"), "--no-motulator",
         "--smoke", "--out", str(tmp_path)],
        capture_output=True, text=True, check=True, timeout=600,
    )
    assert "Speed, same closed-loop work" in out.stdout
    res = json.loads((tmp_path / "results.json").read_text())
    assert set(res["agreement"]["modes"]) == {"averaged", "carrier"}
    for mode in ("averaged", "carrier"):
        row = res["speed"]["modes"][mode]
        assert row["smodrive_steps_per_s"]["median"] > 0
        assert "motulator_steps_per_s" not in row
    assert res["scaling"]["batch"]["runs"] == 2
    md = (tmp_path / "results.md").read_text()
    assert "| averaged |" in md and "| carrier |" in md
