"""The runs of a sweep: every combination of axis values (or a
Latin-hypercube sample of the continuous axes) crossed with the seeds, in a
fixed order, each with its deterministic run id and its changes to the base
scenario; and the check, before anything runs, that every axis value makes
a valid scenario."""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from dataclasses import dataclass
from statistics import NormalDist
from typing import Any

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


def expand(spec: SweepSpec) -> list[Run]:
    """Every run of the sweep, in a fixed order (the first axis varies
    slowest, the seed fastest); a sweep of more than
    :data:`~smodrive.sweep.spec.MAX_RUNS` runs is refused before any is made."""
    check_run_count(spec)
    if spec.sample == "lhs":
        discrete = [a for a in spec.axes if a.marginal is None]
        pts = _lhs_points(spec)
        combos = [({**dict(zip([a.name for a in discrete], c)), **p})
                  for c in itertools.product(*[a.values for a in discrete]) for p in pts]
    else:
        combos = [dict(zip(spec.axis_names, c))
                  for c in itertools.product(*[a.values for a in spec.axes])]
    runs = []
    base_seed = spec.base_seed if spec.seeds_where else None
    for point in combos:
        ch: dict = {}
        for a in spec.axes:
            ch = merge(ch, axis_changes(a, point[a.name], spec.base))
        if spec.seeds and not spec.seeded(point):  # outside [seeds].where: the base's seed
            runs.append(Run(len(runs), _run_id(spec, ch), {**point, "seed": base_seed}, ch))
            continue
        for sd in spec.seeds or (None,):
            changes = ch if sd is None else merge(ch, dotted(spec.seed_key, sd))
            pt = dict(point) if sd is None else {**point, "seed": sd}
            runs.append(Run(len(runs), _run_id(spec, changes), pt, changes))
    ids = [r.id for r in runs]
    if len(set(ids)) != len(ids):
        raise ParameterError(f"sweep {spec.name}: two runs are the same scenario (repeated axis "
                             "values, or two axes that set the same key)")
    return runs


def check_runs(spec: SweepSpec, runs: list[Run]) -> None:
    """Build the scenario of each axis value (the others at their first
    value) before anything runs: a value a field refuses is named with its
    axis and the field's valid range."""
    if not runs:
        return
    first = runs[0].point

    def values(a):
        return (a.values if a.kind != "draw" or spec.sample == "product"
                else sorted({r.point[a.name] for r in runs})[::max(1, len(runs) // 50)])

    def check(name, v, ch, others=""):
        try:
            s = apply_changes(spec.base, ch)
            s.check_controller()
        except ParameterError as exc:
            raise ParameterError(f"axis {name} = {v!r}{others}: {exc}") from None
        if s.duration < spec.window[1]:
            raise ParameterError(f"axis {name} = {v!r}{others}: the run ends at duration = "
                                 f"{s.duration:g} s, before the end of sweep.window = "
                                 f"{list(spec.window)} s, where the metrics are taken")

    # (each axis's values on the base alone first: a value bad by itself is named with its own
    # axis, not with the axis whose loop met it at the others' first values)
    for a in spec.axes:
        for v in values(a):
            check(a.name, v, axis_changes(a, v, spec.base))
    seen: set[str] = set()
    for a in spec.axes:
        for v in values(a):
            pt = {**first, a.name: v}
            ch: dict = {}
            for b in spec.axes:
                ch = merge(ch, axis_changes(b, pt.get(b.name, first.get(b.name)), spec.base))
            key = json.dumps(ch, sort_keys=True, default=repr)
            if key in seen:
                continue
            seen.add(key)
            check(a.name, v, ch, " (the other axes at their first values: " + ", ".join(
                f"{b.name} = {first.get(b.name)!r}" for b in spec.axes if b is not a) + ")")
    if spec.seeds:
        try:
            apply_changes(spec.base, dotted(spec.seed_key, max(spec.seeds)))
        except ParameterError as exc:
            raise ParameterError(f"[seeds] {exc}") from None
