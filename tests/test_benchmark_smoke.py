"""The benchmark script runs (a tiny case) and prints its table; it asserts
nothing about speed (benchmarks are not tests)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_benchmark_script_runs(tmp_path):
    out = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "bench_engine.py"), "--seconds", "0.01",
         "--repeat", "1", "--json", str(tmp_path / "b.json")],
        capture_output=True, text=True, check=True,
    )
    assert "steps/s" in out.stdout and "carrier" in out.stdout
    assert (tmp_path / "b.json").stat().st_size > 0
