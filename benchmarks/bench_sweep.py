"""Throughput of a sweep on Dask (not a test): the built-in sweep
yang2018_current (1452 runs of 0.6 s, 6000 control samples each) on a
LocalCluster of 1 and of 2 worker processes, and on a 2-worker cluster
started as separate processes (`dask scheduler`, `dask worker`) and used
through --scheduler. Prints runs/s and aggregate control samples/s of the
run phase (cluster start-up excluded), the 2-worker speed-up, and the share
of the workers' time spent in runs (1 - scheduling and writing overhead).

    PYTHONPATH=src .venv/bin/python benchmarks/bench_sweep.py [--sweep NAME] [--repeat N]
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from smodrive import sweep as sw


def one(spec, scheduler=None, workers=None) -> sw.SweepReport:
    with tempfile.TemporaryDirectory() as d:
        return sw.run_sweep(spec, Path(d) / "out", scheduler=scheduler, workers=workers)


def show(label: str, reps: list[sw.SweepReport]) -> float:
    best = min(reps, key=lambda r: r.seconds)
    eff = best.busy_seconds / (best.seconds * best.workers)
    print(f"{label:<34} {best.workers:>2} workers {best.batches:>4} batches "
          f"{best.computed / best.seconds:8.1f} runs/s {best.steps / best.seconds / 1e6:6.2f} M "
          f"steps/s  busy {100 * eff:5.1f} %  ({best.seconds:.2f} s; best of {len(reps)})",
          flush=True)
    return best.steps / best.seconds


def dask_cli() -> list[str]:
    exe = Path(sys.executable).with_name("dask")
    return [str(exe)] if exe.exists() else [shutil.which("dask") or "dask"]


def external_cluster(n: int, tmp: Path):
    """`dask scheduler` and `dask worker --nworkers n` as processes; returns
    (address, processes)."""
    sched_file = tmp / "scheduler.json"
    # the workers import the smodrive this script imports (installed or src/)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(Path(sw.__file__).resolve().parents[2]), os.environ.get("PYTHONPATH", "")])}
    procs = [subprocess.Popen(dask_cli() + ["scheduler", "--scheduler-file", str(sched_file),
                                            "--port", "0", "--no-dashboard"], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    t_end = time.time() + 60
    while not sched_file.exists():
        if time.time() > t_end:
            raise RuntimeError("dask scheduler did not start")
        time.sleep(0.1)
    procs.append(subprocess.Popen(dask_cli() + ["worker", "--scheduler-file", str(sched_file),
                                                "--nworkers", str(n), "--nthreads", "1",
                                                "--no-dashboard"], env=env,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    from distributed import Client

    with Client(scheduler_file=str(sched_file), timeout="30s") as c:
        c.wait_for_workers(n, timeout=60)
        return c.scheduler.address, procs


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sweep", default="yang2018_current")
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    spec = sw.load_sweep(args.sweep)
    runs = sw.expand(spec)
    print(f"{args.sweep}: {len(runs)} runs, {spec.base.n_steps} control samples each, "
          f"{os.cpu_count()} cores", flush=True)
    r1 = show("LocalCluster", [one(spec, workers=1) for _ in range(args.repeat)])
    r2 = show("LocalCluster", [one(spec, workers=2) for _ in range(args.repeat)])
    print(f"speed-up 2 workers / 1 worker: {r2 / r1:.2f} x", flush=True)
    with tempfile.TemporaryDirectory() as d:
        addr, procs = external_cluster(2, Path(d))
        try:
            show(f"--scheduler {addr}", [one(spec, scheduler=addr) for _ in range(args.repeat)])
        finally:
            for p in reversed(procs):
                p.terminate()
            for p in procs:
                p.wait(timeout=30)


if __name__ == "__main__":
    main()
