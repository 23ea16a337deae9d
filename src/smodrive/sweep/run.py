"""Running a sweep: the runs OUT has no row for, in batches of about
`batch_seconds` of work each, on Dask (a LocalCluster of worker processes
or a running scheduler), every finished batch written as a Parquet part;
or all of them in this process (:func:`run_local`, a reference for
tests)."""

from __future__ import annotations

import fcntl
import hashlib
import logging
import os
import signal
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable

from ..model import ParameterError
from .plan import Run, check_runs, expand
from .spec import SweepSpec, check_run_count
from .store import check_out, clear_partial, done_rows, prepare_out, write_part
from .worker import Job, run_batch, run_one, version, warm_up

# what the LCL observers' offline design depends on (runs that share these
# share the tables a worker designs once, seconds each)
DESIGN_FIELDS = {"controller.C1_hat_ratio", "controller.L_s_hat", "controller.R_s_hat",
                 "controller.psi_r_hat", "controller.Q", "T_sp", "lcl.L1", "lcl.L2o", "lcl.C1",
                 "motor.n_p"}
DESIGN_SECONDS = 3.0  # estimated wall time of one LCL observer design
STEPS_PER_S = {False: 2.0e6, True: 0.8e6}  # estimated engine rate without / with the LCL


# ----------------------------------------------------------- batching ---

def _uses_lcl_observer(spec: SweepSpec, run: Run) -> bool:
    pos = run.changes.get("controller", {}).get("position", spec.base.controller.position)
    return pos in ("lcl_smo_pll", "lcl_linear")


def _design_key(spec: SweepSpec, run: Run) -> tuple:
    key = []
    for a in spec.axes:
        if any(k in DESIGN_FIELDS for k in a.keys):
            key.append(run.point[a.name])
    return tuple(key)


def estimate_seconds(spec: SweepSpec, runs: list[Run]) -> list[float]:
    """Estimated wall time of each run in order (engine rate, and an LCL
    observer design where the design changes from the previous run)."""
    n = spec.base.n_steps
    out, prev = [], None
    for r in runs:
        lcl = _uses_lcl_observer(spec, r)
        sec = n / STEPS_PER_S[spec.base.lcl is not None] + 1e-3
        if lcl:
            key = _design_key(spec, r)
            if key != prev:
                sec += DESIGN_SECONDS
            prev = key
        out.append(sec)
    return out


def make_batches(spec: SweepSpec, runs: list[Run], n_workers: int) -> list[list[Run]]:
    """Contiguous batches of `runs`, each about `batch_seconds` of work
    (default: a quarter of an even share per worker, within [0.5, 2] s, so
    that a task's overhead, a few ms, stays below 2 %; a batch that would
    start a new LCL observer design starts a new batch)."""
    if not runs:
        return []
    est = estimate_seconds(spec, runs)
    target = spec.batch_seconds or min(2.0, max(0.5, sum(est) / (4 * max(1, n_workers))))
    batches: list[list[Run]] = [[]]
    cost, prev_key = 0.0, None
    for r, sec in zip(runs, est):
        key = _design_key(spec, r) if _uses_lcl_observer(spec, r) else None
        new_design = key is not None and key != prev_key and batches[-1]
        if batches[-1] and (cost >= target or (new_design and cost >= 0.5 * target)):
            batches.append([])
            cost = 0.0
        batches[-1].append(r)
        cost += sec
        prev_key = key
    return batches


# ---------------------------------------------------------- the driver ---

@dataclass
class SweepReport:
    """What a sweep did. The counts of errors, faults and runs that did not
    hold are of all its rows, those it reused from OUT (`done_before`) and
    those it computed now: the sweep's results, not only this call's."""

    total: int  # runs of the sweep
    done_before: int  # of them, already in OUT (reused)
    computed: int  # computed now
    failed_batches: list[str]  # batches Dask gave up on (their runs are still missing)
    errors: int  # rows with status "error"
    faults: int  # rows with status "fault"
    seconds: float  # wall time of the run phase
    steps: int  # control samples simulated now
    workers: int
    batches: int
    busy_seconds: float = 0.0  # sum of the runs' wall times in the workers
    not_held: int = 0  # rows with status "ok" that did not hold their operating point
    #: rows with status "fault" by the fault they ended in (its first name)
    fault_kinds: dict[str, int] = field(default_factory=dict)

    def count(self, status: str, held: bool, final_fault: str) -> None:
        """Count one row of the sweep (reused or computed now)."""
        self.errors += status == "error"
        self.faults += status == "fault"
        self.not_held += status == "ok" and not held
        if status == "fault":
            kind = final_fault.split(",")[0] or "fault"
            self.fault_kinds[kind] = self.fault_kinds.get(kind, 0) + 1

    def summary(self, out: Path) -> str:
        """The end line of `smodrive sweep`: the runs in all, computed now and
        reused from OUT, and what became of those with a row."""
        rows = self.done_before + self.computed
        rate = (f" in {self.seconds:.1f} s ({self.computed / self.seconds:.1f} runs/s, "
                f"{self.steps / self.seconds / 1e6:.2f} M steps/s on {self.workers} workers)"
                if self.computed and self.seconds > 0 else "")
        kinds = ", ".join(f"{n} {k}" for k, n in sorted(self.fault_kinds.items()))
        return (f"{self.total:,} runs in all: {self.computed:,} computed now{rate}, "
                f"{self.done_before:,} reused from {out}"
                + (f", {self.total - rows:,} missing" if rows < self.total else "")
                + f"; of the {rows:,}: {self.faults:,} end in a fault"
                + (f" ({kinds})" if kinds else "")
                + f", {self.not_held:,} did not hold their operating point, {self.errors:,} "
                "could not run")


class _Lock:
    """OUT/.lock held while a sweep writes OUT (released when the process
    ends, however it ends)."""

    def __init__(self, out: Path):
        self.f = open(Path(out) / ".lock", "a+")
        try:
            fcntl.flock(self.f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self.f.close()
            raise ParameterError(f"{out}: another sweep is writing there (OUT/.lock is held); "
                                 "wait for it or choose another --out") from None

    def close(self) -> None:
        fcntl.flock(self.f, fcntl.LOCK_UN)
        self.f.close()


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def start_client(scheduler: str | None = None, workers: int | None = None):
    """A dask.distributed Client: to the scheduler at `scheduler`, or to a
    new LocalCluster of `workers` single-threaded worker processes (default:
    one a core). Returns (client, cluster or None)."""
    # distributed takes about 0.4 s to import: only when a sweep runs, not
    # with every smodrive command (the CLI imports this package)
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout="20s"), None
        except (OSError, TimeoutError) as exc:
            raise ParameterError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
        except ValueError as exc:  # (an address distributed cannot parse: "garbage")
            raise ParameterError(f"--scheduler {scheduler}: not a scheduler address "
                                 f"(tcp://host:port): {exc}") from None
    n = workers or _cores()
    if not 1 <= n <= 1024:
        raise ParameterError(f"--workers {n} is outside its valid range [1, 1024]")
    # (the workers start with SIGINT ignored, which a process keeps across exec, as a mask it
    # does not: a Ctrl-C in the terminal reaches the whole process group, and each worker
    # printed its KeyboardInterrupt's traceback; the sweep itself stops, closing the cluster,
    # and a rerun resumes it. One pressed in the 2-3 s the cluster takes to start is lost)
    main = threading.current_thread() is threading.main_thread()
    before = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=":0", silence_logs=logging.CRITICAL)
    finally:
        if main:
            signal.signal(signal.SIGINT, before)
    return Client(cluster), cluster


def run_sweep(spec: SweepSpec, out: str | Path, scheduler: str | None = None,
              workers: int | None = None, client=None,
              progress: Callable[[str, int, int], None] | None = None,
              on_batch: Callable[[list[dict], Any], None] | None = None,
              sweep_text: str | None = None) -> SweepReport:
    """Run the runs of `spec` that OUT has no row for, on Dask; write each
    finished batch as a Parquet part of OUT/runs. An OUT holding another
    sweep's results is refused first (:func:`~smodrive.sweep.store.check_out`).
    `progress(phase, done, total)`: building the runs, checking the axes'
    values, starting Dask, running; `on_batch(rows, client)` after each
    part is written (tests use it to kill a worker mid-sweep). A batch Dask
    gives up on (its workers died three times) is reported, not written:
    run again."""
    import pyarrow.parquet  # noqa: F401  (optional, see store; imported now, not while the workers run)
    from distributed import as_completed  # slow to import: see start_client

    out = Path(out)
    check_out(spec, out)  # another sweep's folder: refused now, not after its runs are built
    n = check_run_count(spec)
    # (building a million runs takes some 17 s, checking two axes of 1000 values 13 s: shown)
    runs = expand(spec, progress and (lambda d, t: progress(f"building {n:,} runs", d, t)))
    check_runs(spec, runs, progress and (lambda d, t: progress("checking the axes' values",
                                                               d, t)))
    out.mkdir(parents=True, exist_ok=True)
    lock = _Lock(out)
    own_client = client is None
    cluster = None
    try:
        check_out(spec, out)  # again, under the lock: a sweep may have finished there meanwhile
        prepare_out(spec, out, sweep_text)
        clear_partial(out)  # a write a killed sweep left half done
        have = done_rows(out)
        todo = [r for r in runs if r.id not in have]
        n_before = len(runs) - len(todo)
        rep = SweepReport(len(runs), n_before, 0, [], 0, 0, 0.0, 0, 0, 0)
        for r in runs:
            if r.id in have:
                rep.count(*have[r.id])
        if progress:
            progress("starting Dask", 0, 1)
        if todo and own_client:
            client, cluster = start_client(scheduler, workers)
        n_workers = len(client.scheduler_info()["workers"]) if todo else 0
        if todo:
            client.run(warm_up, spec.base)  # imports and the C library, once
        if progress:
            progress("starting Dask", 1, 1)
        batches = make_batches(spec, todo, n_workers)
        job = Job(spec.base, spec.metrics, spec.window, spec.full_log, version())
        rep.workers, rep.batches = n_workers, len(batches)
        if progress:
            progress("running", n_before, len(runs))
        t0 = time.perf_counter()
        if batches:
            futs = {}
            for b in batches:
                key = "smodrive-sweep-" + hashlib.sha256(
                    "".join(r.id for r in b).encode()).hexdigest()[:16]
                futs[client.submit(run_batch, job, b, key=key, retries=1)] = b
            done = n_before
            for fut in as_completed(list(futs)):
                try:
                    rows = fut.result()
                except Exception as exc:  # KilledWorker after repeated worker deaths
                    rep.failed_batches.append(f"runs {futs[fut][0].index}..{futs[fut][-1].index}:"
                                              f" {type(exc).__name__}: {exc}")
                    fut.release()
                    continue
                fut.release()
                write_part(out, spec, rows)
                rep.computed += len(rows)
                rep.steps += sum(r["steps"] for r in rows)
                rep.busy_seconds += sum(r["wall_s"] for r in rows)
                for r in rows:
                    rep.count(r["status"], r["held"], r["final_fault"])
                done += len(rows)
                if progress:
                    progress("running", done, len(runs))
                if on_batch:
                    on_batch(rows, client)
        rep.seconds = time.perf_counter() - t0
        return rep
    finally:
        if own_client and client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
        lock.close()


def run_local(spec: SweepSpec, runs: Iterable[Run] | None = None) -> list[dict]:
    """The rows of `runs` (default: all) computed in this process, no Dask
    (a reference for tests)."""
    job = Job(spec.base, spec.metrics, spec.window, spec.full_log, version())
    return [run_one(job, r) for r in (expand(spec) if runs is None else runs)]
