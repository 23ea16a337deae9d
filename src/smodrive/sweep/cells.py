"""What each cell of a map shows: the runs at a point of the plotted axes
reduced to one value, and the cell's state: the runs held their operating
point (``ok``: the value is drawn), did not (``not_held``, with the first
reason of :data:`smodrive.analysis.metrics.NOT_HELD`), ended in a fault
(``fault``, with its kind) or could not run (``error``). A cell of several
runs (seeds) takes the worst state among them; :mod:`smodrive.sweep.maps`
draws the cells."""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analysis.metrics import NOT_HELD
from .plotspec import same

#: the states of a cell, best first (a cell of several runs takes the worst)
STATES = ("ok", "not_held", "fault", "error")


def held_column(cols: dict) -> np.ndarray:
    """The runs that held their operating point (results without the column,
    from before it existed, count as held)."""
    n = len(cols["run_id"])
    if "held" not in cols:
        return np.ones(n, dtype=bool)
    return np.array([bool(v) if v is not None else False for v in cols["held"]], dtype=bool)


def run_states(cols: dict) -> np.ndarray:
    """Each run's state: ok, not_held, fault or error."""
    status = np.asarray(cols["status"], dtype=object)
    held = held_column(cols)
    out = np.where(status == "error", "error", np.where(status == "fault", "fault",
                                                        np.where(held, "ok", "not_held")))
    return out.astype(object)


def fault_kind(final_fault: Any) -> str:
    """The kind of a run's fault: the first name of the fault word the run
    ended with."""
    return (str(final_fault or "").split(",")[0]) or "fault"


def first_reason(not_held: Any) -> str:
    """The first reason (in NOT_HELD order) a run did not hold."""
    rs = str(not_held or "").split(",")
    for n in NOT_HELD:
        if n in rs:
            return n
    return rs[0] or "not held"


def index_of(col: np.ndarray, values) -> np.ndarray:
    """For each row, the index of its value among `values` (axis values, as
    :func:`same` compares them); -1 where none matches."""
    col = np.asarray(col)
    out = np.full(len(col), -1, dtype=int)
    x = None
    for k, v in enumerate(values):
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            if x is None:
                x = (col.astype(float) if col.dtype.kind in "fiu" else
                     np.array([c if isinstance(c, (int, float)) and not isinstance(c, bool)
                               else np.nan for c in col], dtype=float))
            m = np.isclose(x, float(v), rtol=1e-9, atol=1e-12)
        else:
            m = np.array([same(c, v) for c in col], dtype=bool)
        out[m & (out < 0)] = k
    return out


def select(cols: dict, fixed: dict) -> np.ndarray:
    """The rows at the axis values `fixed` (axis -> value)."""
    m = np.ones(len(cols["run_id"]), dtype=bool)
    for k, v in fixed.items():
        m &= index_of(cols[k], [v]) == 0
    return m


def reduce_values(x: np.ndarray, how: str) -> float:
    """The reduction `how` of the finite values of `x` (NaN if none): median,
    mean, max, min, or worst (the value of the largest magnitude)."""
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    if x.size == 0:
        return math.nan
    if how == "worst":
        return float(x[np.argmax(np.abs(x))])
    return float({"median": np.median, "mean": np.mean, "max": np.max, "min": np.min}[how](x))


@dataclass
class Cells:
    """One panel's cells on the grid ys x xs (rows: y)."""

    xs: np.ndarray
    ys: np.ndarray
    value: np.ndarray  # the reduction over the cell's runs; NaN unless state is ok
    raw: np.ndarray  # the reduction over every run of the cell, whatever its state
    lo: np.ndarray  # the smallest and largest value over the cell's runs (seeds)
    hi: np.ndarray
    n: np.ndarray  # runs in the cell
    state: np.ndarray  # STATES ("" without runs)
    why: np.ndarray  # not_held: the first reason; fault: its kind; else ""
    mixed: np.ndarray  # the cell's runs are in more than one state


def cells(spec, cols: dict, x: str, y: str, metric: str, fixed: dict,
          how: str = "median") -> Cells:
    """The cells of the (x, y) grid at the axis values `fixed`: `metric`
    reduced by `how` over each cell's runs, and the cell's state (the worst
    of its runs'): what a heatmap panel draws."""
    xs = np.asarray(spec.axis(x).values, float)
    ys = np.asarray(spec.axis(y).values, float)
    sel = select(cols, fixed)
    ix, iy = index_of(cols[x], xs), index_of(cols[y], ys)
    vals = np.asarray(cols[metric], dtype=float)
    states = run_states(cols)
    shape = (ys.size, xs.size)
    out = Cells(xs, ys, np.full(shape, np.nan), np.full(shape, np.nan), np.full(shape, np.nan),
                np.full(shape, np.nan), np.zeros(shape, int), np.full(shape, "", dtype=object),
                np.full(shape, "", dtype=object), np.zeros(shape, bool))
    rows = np.flatnonzero(sel & (ix >= 0) & (iy >= 0))
    groups: dict[tuple[int, int], list[int]] = {}
    for k in rows:
        groups.setdefault((iy[k], ix[k]), []).append(k)
    for (i, j), ks in groups.items():
        st = [states[k] for k in ks]
        worst = max(st, key=STATES.index)
        v = vals[ks]
        out.n[i, j] = len(ks)
        out.state[i, j] = worst
        out.mixed[i, j] = len(set(st)) > 1
        out.raw[i, j] = reduce_values(v, how)
        if worst == "ok":
            out.value[i, j] = out.raw[i, j]
            fin = v[np.isfinite(v)]
            if fin.size:
                out.lo[i, j], out.hi[i, j] = float(np.min(fin)), float(np.max(fin))
        elif worst == "not_held":
            reasons = {first_reason(cols["not_held"][k]) for k in ks if states[k] == worst}
            out.why[i, j] = min(reasons, key=lambda r: NOT_HELD.index(r) if r in NOT_HELD
                                else len(NOT_HELD))
        elif worst == "fault":
            kinds = Counter(fault_kind(cols["final_fault"][k]) for k in ks if states[k] == worst)
            out.why[i, j] = kinds.most_common(1)[0][0]
    return out


def state_counts(spec, cols: dict, mask: np.ndarray) -> dict[tuple[str, str], list]:
    """Over the runs of `mask`: (state, first reason or fault kind) -> [runs,
    of them with a fault before the metrics' window, the set of every reason
    those runs did not hold for]."""
    states = run_states(cols)
    out: dict[tuple[str, str], list[int]] = {}
    t0 = spec.window[0]
    for k in np.flatnonzero(mask):
        st = states[k]
        if st == "not_held":
            key = (st, first_reason(cols["not_held"][k]))
        elif st == "fault":
            key = (st, fault_kind(cols["final_fault"][k]))
        else:
            key = (st, "")
        c = out.setdefault(key, [0, 0, set()])
        c[0] += 1
        if st == "not_held":
            c[2].update(str(cols["not_held"][k]).split(","))
        ft = cols["fault_t"][k] if "fault_t" in cols else math.nan
        if st == "fault" and ft is not None and np.isfinite(ft) and ft < t0:
            c[1] += 1
    return out
