"""The runs of a sweep: every combination of axis values (or a
Latin-hypercube sample of the continuous axes) crossed with the seeds, in a
fixed order, each with its deterministic run id and its changes to the base
scenario; and the check, before anything runs, that every axis value makes
a valid scenario."""

from __future__ import annotations

import gc
import hashlib
import itertools
import json
import math
from dataclasses import dataclass
from statistics import NormalDist
from typing import Any, Callable, Iterable

import numpy as np

from ..model import ParameterError
from .axes import apply_changes, axis_changes, dotted, merge
from .spec import SweepSpec, check_run_count

#: the format of a results row: part of every run id, so that rows of an
#: older format (before 2: without the operating point) are run again
ROW_FORMAT = 2


@dataclass(frozen=True)
class Run:
    index: int
    id: str
    point: dict[str, Any]  # axis name -> value (and "seed")
    changes: dict[str, Any]  # as a scenario TOML: {"controller": {"L_s_hat": ...}, ...}


def _run_id(spec: SweepSpec, changes: dict) -> str:
    h = hashlib.sha256(json.dumps(
        {"base": spec.base_toml, "window": spec.window, "metrics": spec.metrics,
         "changes": changes, "rows": ROW_FORMAT}, sort_keys=True,
        default=repr).encode()).hexdigest()
    return h[:20]


def _run_ids(spec: SweepSpec) -> Callable[[dict], str]:
    """:func:`_run_id` of `spec`, for many runs: the same text hashed, but the
    hash of its part before the changes (the base scenario, some kB, whose
    encoding was most of the time of a run's id) computed once and copied.
    The keys in sorted order: base, changes, metrics, rows, window."""
    head = hashlib.sha256(('{"base": ' + json.dumps(spec.base_toml) + ', "changes": ')
                          .encode())
    tail = (', "metrics": ' + json.dumps(spec.metrics) + ', "rows": ' + json.dumps(ROW_FORMAT)
            + ', "window": ' + json.dumps(spec.window) + "}")
    encode = json.JSONEncoder(sort_keys=True, default=repr).encode  # json.dumps's, made once

    def run_id(changes: dict) -> str:
        h = head.copy()
        h.update((encode(changes) + tail).encode())
        return h.hexdigest()[:20]

    return run_id


def _lhs_points(spec: SweepSpec) -> list[dict[str, Any]]:
    """`samples` points of the continuous axes (Latin hypercube: each axis's
    range cut into `samples` equally likely strata, one point in each)."""
    cont = [a for a in spec.axes if a.marginal is not None]
    rng = np.random.default_rng([spec.seed, 7919])
    n = spec.samples
    cols = {}
    for a in cont:
        u = (rng.permutation(n) + rng.random(n)) / n
        kind, p, q = a.marginal
        if kind == "uniform":
            x = p + (q - p) * u
        elif kind == "loguniform":
            x = np.exp(math.log(p) + (math.log(q) - math.log(p)) * u)
        else:
            nd = NormalDist(p, q) if q > 0 else None
            x = np.array([p if nd is None else nd.inv_cdf(float(min(max(v, 1e-12),
                                                                     1 - 1e-12))) for v in u])
        cols[a.name] = [float(v) for v in x]
    return [{k: cols[k][i] for k in cols} for i in range(n)]


def expand(spec: SweepSpec, progress: Callable[[int, int], None] | None = None) -> list[Run]:
    """Every run of the sweep, in a fixed order (the first axis varies
    slowest, the seed fastest); a sweep of more than
    :data:`~smodrive.sweep.spec.MAX_RUNS` runs is refused before any is made.
    `progress(done, total)` about every 1 % of the runs (a million take some
    17 s to make)."""
    total = check_run_count(spec)
    if spec.sample == "lhs":
        discrete = [a for a in spec.axes if a.marginal is None]
        pts = _lhs_points(spec)
        combos: Iterable[dict] = (
            {**dict(zip([a.name for a in discrete], c)), **p}
            for c in itertools.product(*[a.values for a in discrete]) for p in pts)
    else:
        combos = (dict(zip(spec.axis_names, c))
                  for c in itertools.product(*[a.values for a in spec.axes]))
    # each axis value's changes made once, not once a run (the LHS values are all different)
    made: list[dict] = [{} for _ in spec.axes]

    def changes_of(i: int, v: Any) -> dict:
        key = (type(v), v)
        if key not in made[i]:
            made[i][key] = axis_changes(spec.axes[i], v, spec.base)
        return made[i][key]

    seeds = [(sd, dotted(spec.seed_key, sd)) for sd in spec.seeds] or [(None, {})]
    run_id = _run_ids(spec)
    runs: list[Run] = []
    step = max(1, total // 100)
    next_report = step
    base_seed = spec.base_seed if spec.seeds_where else None
    # (the cyclic garbage collector paused: these objects hold no cycles, and its passes over
    # the growing list were a quarter of the time of a million runs)
    collecting = gc.isenabled()
    gc.disable()
    try:
        for point in combos:
            ch: dict = {}
            for i, a in enumerate(spec.axes):
                ch = merge(ch, changes_of(i, point[a.name]))
            if spec.seeds and not spec.seeded(point):  # outside [seeds].where: the base's seed
                runs.append(Run(len(runs), run_id(ch), {**point, "seed": base_seed}, ch))
            else:
                for sd, sd_changes in seeds:
                    changes = ch if sd is None else merge(ch, sd_changes)
                    pt = dict(point) if sd is None else {**point, "seed": sd}
                    runs.append(Run(len(runs), run_id(changes), pt, changes))
            if progress and len(runs) >= next_report:
                progress(len(runs), total)
                next_report = len(runs) + step
    finally:
        if collecting:
            gc.enable()
    if progress:
        progress(len(runs), total)
    ids = {r.id for r in runs}
    if len(ids) != len(runs):
        raise ParameterError(f"sweep {spec.name}: two runs are the same scenario (repeated axis "
                             "values, or two axes that set the same key)")
    return runs


def check_runs(spec: SweepSpec, runs: list[Run],
               progress: Callable[[int, int], None] | None = None) -> None:
    """Build the scenario of each axis value (the others at their first
    value) before anything runs: a value a field refuses is named with its
    axis and the field's valid range. `progress(done, total)` after each
    scenario (some 3 ms each: 13 s for two axes of 1000 values)."""
    if not runs:
        return
    first = runs[0].point
    # an LHS draws every run's own value: 50 of them, spread over their range
    values = {a.name: (a.values if a.kind != "draw" or spec.sample == "product"
                       else sorted({r.point[a.name] for r in runs})[::max(1, len(runs) // 50)])
              for a in spec.axes}
    total, done = 2 * sum(map(len, values.values())), 0

    def check(name, v, ch, others=""):
        nonlocal done
        try:
            s = apply_changes(spec.base, ch)
            s.check_controller()
        except ParameterError as exc:
            raise ParameterError(f"axis {name} = {v!r}{others}: {exc}") from None
        if s.duration < spec.window[1]:
            raise ParameterError(f"axis {name} = {v!r}{others}: the run ends at duration = "
                                 f"{s.duration:g} s, before the end of sweep.window = "
                                 f"{list(spec.window)} s, where the metrics are taken")
        done += 1
        if progress:
            progress(done, total)

    # (each axis's values on the base alone first: a value bad by itself is named with its own
    # axis, not with the axis whose loop met it at the others' first values)
    for a in spec.axes:
        for v in values[a.name]:
            check(a.name, v, axis_changes(a, v, spec.base))
    seen: set[str] = set()
    for a in spec.axes:
        for v in values[a.name]:
            pt = {**first, a.name: v}
            ch: dict = {}
            for b in spec.axes:
                ch = merge(ch, axis_changes(b, pt.get(b.name, first.get(b.name)), spec.base))
            key = json.dumps(ch, sort_keys=True, default=repr)
            if key in seen:
                done += 1  # (the same scenario as one checked: counted, not built again)
                continue
            seen.add(key)
            check(a.name, v, ch, " (the other axes at their first values: " + ", ".join(
                f"{b.name} = {first.get(b.name)!r}" for b in spec.axes if b is not a) + ")")
    if progress:
        progress(total, total)
    if spec.seeds:
        try:
            apply_changes(spec.base, dotted(spec.seed_key, max(spec.seeds)))
        except ParameterError as exc:
            raise ParameterError(f"[seeds] {exc}") from None
