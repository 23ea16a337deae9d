"""What a Dask worker runs: a batch of runs, each in this process on the C
engine directly (the samples before the metrics' window unlogged), reduced
to one row of the results (point, metrics, whether the run held its
operating point over the window and why not, status, fault, wall time)."""

from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass
from importlib.metadata import version as _dist_version
from typing import Any

import numpy as np

from ..analysis.metrics import METRICS, metric_values, operating_point
from ..engine import CHANNELS, Engine, Result, fault_names
from ..model import Scenario
from .axes import apply_changes
from .plan import Run


def version() -> str:
    """smodrive's version (the installed distribution's; 0+src from a source tree)."""
    try:
        return _dist_version("smodrive")
    except Exception:  # not installed: running from the source tree
        return "0+src"


@dataclass(frozen=True)
class Job:
    """What every batch of a sweep shares (sent with each task)."""

    base: Scenario
    metrics: tuple[str, ...]
    window: tuple[float, float]
    full_log: bool
    version: str


_LOCAL = threading.local()


def _log_buffer(rows: int, cols: int) -> np.ndarray:
    """A log buffer of at least `rows` rows, kept for the thread's next runs
    (a worker with several threads has one each): a fresh one each run
    costs page faults, about a tenth of a yang2018 run in a Dask worker."""
    buf = getattr(_LOCAL, "buf", None)
    if buf is None or buf.shape[0] < rows or buf.shape[1] != cols:
        buf = _LOCAL.buf = np.empty((rows, cols))
    return buf[:rows]


def run_one(job: Job, run: Run) -> dict[str, Any]:
    """One run in this process: the C engine directly, the samples before the
    metrics' window unlogged; the row of the results (point, metrics,
    status, fault, wall time)."""
    t_start = time.perf_counter()
    row: dict[str, Any] = {"run_id": run.id, "index": run.index, **run.point}
    row.update(dict.fromkeys(job.metrics, math.nan))
    row.update(status="error", error="", first_fault="", fault_t=math.nan, final_fault="",
               steps=0, smodrive_version=job.version, held=False, not_held="error",
               speed_offset_rpm=math.nan, i_limit_share=math.nan, u_limit_share=math.nan)
    try:
        s = apply_changes(job.base, run.changes)
        eng = Engine(s)  # checks the controller
        n = s.n_steps
        T = s.T_sp
        n0 = 0 if job.full_log else min(n, max(0, int(math.floor(job.window[0] / T + 1e-9))))
        n1 = min(n, int(math.ceil(job.window[1] / T - 1e-9)))
        if n0:
            eng.run_nolog(n0)
        rows = max(n1 - n0, 0)
        out = _log_buffer(max(rows, 1), len(CHANNELS))
        got = eng.run(rows, out, 0, 1) if rows else 0
        if n > n1:
            eng.run_nolog(n - n1)
        f = eng.faults()
        data = out[:got]
        status = int(np.max(data[:, CHANNELS.index("status")])) if got else 0
        r = Result(s, data, status, f, log_stride=1, samples=n)
        with np.errstate(all="ignore"):
            vals = metric_values(r, job.metrics, *job.window)
            row.update(operating_point(r, *job.window).as_row())
        if f.final:  # the window's signals are cut short by the fault: no values
            vals = {k: v if METRICS[k].after_fault else math.nan for k, v in vals.items()}
        row.update(vals)
        row.update(status="fault" if f.final else "ok", steps=n,
                   first_fault=",".join(fault_names(f.first)),
                   fault_t=math.nan if f.t_first is None else f.t_first,
                   final_fault=",".join(fault_names(f.final)))
    except Exception as exc:  # a refused combination: recorded, the sweep goes on
        row["error"] = f"{type(exc).__name__}: {exc}"
    row["wall_s"] = time.perf_counter() - t_start
    return row


def warm_up(base: Scenario) -> None:
    """On each worker before the runs: the modules and the C library loaded,
    one engine initialised (start-up is not counted in the run phase)."""
    Engine(base)


def run_batch(job: Job, runs: list[Run]) -> list[dict[str, Any]]:
    """A Dask task: the rows of a batch of runs."""
    return [run_one(job, r) for r in runs]
