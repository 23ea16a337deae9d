"""Parameter sweeps and Monte Carlo over a scenario, on Dask, into Parquet.

A sweep file (TOML) names a base scenario and the axes to vary; every
combination of axis values (or a Latin-hypercube sample of the continuous
axes), crossed with the noise seeds, is a run. Each run is reduced in the
worker to the metrics the sweep names (the registry
:data:`smodrive.analysis.metrics.METRICS`), and every finished batch of runs
becomes one Parquet file of ``OUT/runs/``, one row a run, keyed by a
deterministic run id: a sweep started again with the same file computes only
the runs that have no row yet.

Example (``docs/sweeps.md`` has the whole format)::

    [sweep]
    base = "drive.pi_encoder"            # a catalogue name or a scenario TOML
    metrics = ["id_error", "iq_error", "ripple"]
    window = [0.3, 0.6]                  # s: where the metrics are taken

    [[axes]]
    name = "L_ratio"
    key = "controller.L_s_hat"           # a scenario TOML key (dotted)
    relative_to = "motor.L_s"            # the value is a factor of this field
    range = [0.4, 2.5]
    n = 8

    [seeds]
    n = 4                                # adc.seed = 0, 1, 2, 3

>>> spec = load_sweep(builtin_path("yang2018_current"))   # doctest: +SKIP
>>> report = run_sweep(spec, "out/sweep1", workers=2)      # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import fcntl
import hashlib
import json
import math
import os
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: the same parser as a package
    import tomli as tomllib

import numpy as np

from .analysis.metrics import METRICS, metric_values
from .model import ParameterError, Scenario

BUILTIN_DIR = Path(__file__).resolve().parent / "sweeps"
#: columns every row has beside its axes and metrics
STANDARD_COLUMNS = ("run_id", "index", "seed", "status", "error", "first_fault", "fault_t",
                    "final_fault", "wall_s", "steps", "smodrive_version")
SWEEP_KEYS = {"title", "base", "metrics", "window", "sample", "samples", "seed",
              "batch_seconds"}
AXIS_KEYS = {"name", "label", "key", "relative_to", "values", "range", "n", "spacing", "draw",
             "low", "high", "mean", "std", "scale"}
SEED_KEYS = {"key", "n", "first", "values"}
PLOT_KINDS = ("heatmap", "lines", "envelope")
# what the LCL observers' offline design depends on (runs that share these
# share the tables a worker designs once, seconds each)
DESIGN_FIELDS = {"controller.C1_hat_ratio", "controller.L_s_hat", "controller.R_s_hat",
                 "controller.psi_r_hat", "controller.Q", "T_sp", "lcl.L1", "lcl.L2o", "lcl.C1",
                 "motor.n_p"}
DESIGN_SECONDS = 3.0  # estimated wall time of one LCL observer design
#: the most runs a sweep may have: the runs are expanded in memory (about
#: 1.2 kB each, some 1.2 GB at the bound) before the first one is sent;
#: a spec beyond it is refused before anything is allocated
MAX_RUNS = 1_000_000
STEPS_PER_S = {False: 2.0e6, True: 0.8e6}  # estimated engine rate without / with the LCL


def version() -> str:
    """smodrive's version (the installed distribution's; 0+src from a source tree)."""
    try:
        from importlib.metadata import version as v

        return v("smodrive")
    except Exception:  # not installed: running from the source tree
        return "0+src"


# ------------------------------------------------------------ the spec ---

@dataclass(frozen=True)
class Axis:
    """One swept quantity: `values` (in run order) set every key of `keys`
    (scenario TOML keys, dotted), each times the base's `relative_to` field
    if given. `kind`: grid, draw or values; `marginal` is what a
    Latin-hypercube sample draws from (None for a list of values)."""

    name: str
    label: str
    keys: tuple[str, ...]
    relative_to: str | None
    values: tuple[Any, ...]
    kind: str
    marginal: tuple | None = None  # ("uniform"|"loguniform", lo, hi) or ("normal", mu, sd)
    scale: float = 1.0  # the value set is value x scale (x the relative_to field)

    @property
    def numeric(self) -> bool:
        return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in self.values)

    @property
    def integer(self) -> bool:
        return self.kind == "values" and all(type(v) is int for v in self.values)


@dataclass(frozen=True)
class Run:
    index: int
    id: str
    point: dict[str, Any]  # axis name -> value (and "seed")
    changes: dict[str, Any]  # as a scenario TOML: {"controller": {"L_s_hat": ...}, ...}


@dataclass
class SweepSpec:
    name: str
    title: str
    base: Scenario  # with [set] applied
    base_toml: str
    metrics: tuple[str, ...]
    window: tuple[float, float]
    sample: str
    samples: int
    seed: int
    axes: list[Axis]
    seed_key: str | None
    seeds: tuple[int, ...]
    plots: list[dict]
    batch_seconds: float | None
    raw: dict = field(default_factory=dict)  # the normalised spec (sweep.json)

    @property
    def full_log(self) -> bool:
        return any(METRICS[m].needs_full_log for m in self.metrics)

    @property
    def axis_names(self) -> list[str]:
        return [a.name for a in self.axes]

    def axis(self, name: str) -> Axis:
        for a in self.axes:
            if a.name == name:
                return a
        raise ParameterError(f"{name!r} is not an axis of sweep {self.name} (axes: "
                             f"{', '.join(self.axis_names + (['seed'] if self.seeds else []))})")


def _where(ctx: str, key: str) -> str:
    return f"{ctx}.{key}" if ctx else key


def _is_num(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _need(ctx: str, d: dict, key: str) -> Any:
    if key not in d:
        raise ParameterError(f"{ctx}: missing {key!r}")
    return d[key]


def _unknown(ctx: str, d: dict, known: set[str]) -> None:
    bad = sorted(set(d) - known)
    if bad:
        raise ParameterError(f"{_where(ctx, bad[0])}: unknown field (known: "
                             f"{', '.join(sorted(known))})")


def _number(ctx: str, v: Any, lo: float = -math.inf, hi: float = math.inf,
            integer: bool = False) -> float:
    ok = (isinstance(v, int) and not isinstance(v, bool)) if integer else _is_num(v)
    what = "a whole number" if integer else "a number"
    if not ok or not math.isfinite(v) or not lo <= v <= hi:
        raise ParameterError(f"{ctx} = {v!r} is outside its valid range: {what} in "
                             f"[{lo:g}, {hi:g}]")
    return v


def _dotted(key: str, value: Any) -> dict:
    """'controller.L_s_hat', v -> {'controller': {'L_s_hat': v}}."""
    parts = key.split(".")
    out: dict = value
    for p in reversed(parts):
        out = {p: out}
    return out


def _merge(a: dict, b: dict) -> dict:
    out = dict(a)
    for k, v in b.items():
        out[k] = _merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else v
    return out


def _field_value(s: Scenario, path: str, ctx: str) -> float:
    obj: Any = s
    for part in path.split("."):
        if not hasattr(obj, part):
            raise ParameterError(f"{ctx} = {path!r}: no such field of the base scenario (e.g. "
                                 "'motor.L_s', 'motor.psi_r', 'lcl.C1')")
        obj = getattr(obj, part)
    if not _is_num(obj):
        raise ParameterError(f"{ctx} = {path!r} is not a number in the base scenario "
                             f"({obj!r})")
    return float(obj)


def apply_changes(base: Scenario, data: dict) -> Scenario:
    """`base` with the changes `data` (a parsed scenario TOML without
    `base`: sections as tables, keys with units as in scenario files)."""
    from . import scenario_io as sio

    top: dict[str, Any] = {}
    built: dict[str, Any] = {}
    for key, value in data.items():
        if key in sio.SECTIONS:
            if not isinstance(value, dict):
                raise ParameterError(f"[{key}] must be a table")
            if key == "controller":
                built[key] = sio._controller(value, base.controller)
            else:
                cur = getattr(base, key)
                cur = sio.SECTIONS[key]() if cur is None else cur
                built[key] = dataclasses.replace(cur, **sio._kwargs(sio.SECTIONS[key], key,
                                                                    value))
        elif key == "base":
            raise ParameterError("base: only in [sweep] (a sweep has one base scenario)")
        else:
            top[key] = value
    return dataclasses.replace(base, **sio._kwargs(Scenario, "scenario", top), **built)


def _load_base(ref: Any, ctx_dir: Path | None) -> Scenario:
    from .scenario_io import load_scenario
    from .scenarios import catalogue

    if isinstance(ref, dict) and set(ref) == {"toml"}:  # a stored sweep (sweep.json)
        from .scenario_io import scenario_from_dict

        return scenario_from_dict(tomllib.loads(ref["toml"]))
    if not isinstance(ref, str):
        raise ParameterError(f"sweep.base = {ref!r}: a catalogue name (smodrive scenarios) or "
                             "the path of a scenario TOML")
    cat = catalogue()
    if ref in cat:
        return cat[ref]()
    p = Path(ref)
    if not p.is_absolute() and ctx_dir is not None:
        p = ctx_dir / p
    if p.is_file():
        return load_scenario(p)
    raise ParameterError(f"sweep.base = {ref!r}: neither a catalogue name (smodrive "
                         f"scenarios) nor a scenario file (looked for {p})")


def _grid(ctx: str, a: dict) -> tuple[tuple, str, tuple | None]:
    spacing = a.get("spacing", "linear")
    if spacing not in ("linear", "log"):
        raise ParameterError(f"{ctx}.spacing = {spacing!r} is not one of linear, log")
    if "values" in a:
        for k in ("range", "draw", "n"):
            if k in a:
                raise ParameterError(f"{ctx}: give values or {k}, not both")
        vals = a["values"]
        if not isinstance(vals, list) or not vals:
            raise ParameterError(f"{ctx}.values = {vals!r} must be a non-empty list")
        kinds = {"num" if _is_num(v) else type(v).__name__ for v in vals}
        if len(kinds) > 1 or kinds - {"num", "str", "bool"}:
            raise ParameterError(f"{ctx}.values = {vals!r} must be all numbers, all strings or "
                                 "all booleans")
        if len(set(vals)) != len(vals):
            raise ParameterError(f"{ctx}.values = {vals!r} has repeated values")
        return tuple(vals), "values", None
    if "range" in a:
        r = a["range"]
        if not (isinstance(r, list) and len(r) == 2 and all(map(_is_num, r))
                and all(map(math.isfinite, r)) and r[0] < r[1]):
            raise ParameterError(f"{ctx}.range = {r!r} must be two numbers [low, high] with "
                                 "low < high")
        lo, hi = float(r[0]), float(r[1])
        if spacing == "log" and lo <= 0:
            raise ParameterError(f"{ctx}.range = {r!r}: a log spacing needs low > 0")
        n = int(_number(f"{ctx}.n", _need(ctx, a, "n"), 1, 100_000, integer=True))
        if n == 1:
            vals = np.array([lo])
        elif spacing == "log":
            vals = np.geomspace(lo, hi, n)
            vals[0], vals[-1] = lo, hi
        else:
            vals = np.linspace(lo, hi, n)
        # rounded to 12 significant digits: 1.0 is 1.0, not 0.9999999999999999
        vals = [float(f"{v:.12g}") for v in vals]
        return tuple(vals), "grid", ("loguniform" if spacing == "log" else "uniform", lo, hi)
    if "draw" in a:
        return (), "draw", None
    raise ParameterError(f"{ctx}: give values, range (with n) or draw (uniform or normal)")


def _axis(i: int, a: Any, base: Scenario, rng_seed: int, names: set[str]) -> Axis:
    ctx = f"axes[{i}]"
    if not isinstance(a, dict):
        raise ParameterError(f"{ctx} must be a table ([[axes]])")
    name = _need(ctx, a, "name")
    if not (isinstance(name, str) and name.isidentifier()):
        raise ParameterError(f"{ctx}.name = {name!r} must be a name (letters, digits, _)")
    ctx = f"axes[{i}] ({name})"
    _unknown(ctx, a, AXIS_KEYS)
    reserved = set(STANDARD_COLUMNS) | set(METRICS)
    if name in reserved or name in names:
        raise ParameterError(f"{ctx}.name = {name!r} is taken (by another axis, a metric or "
                             f"a standard column: {', '.join(STANDARD_COLUMNS)})")
    keys = _need(ctx, a, "key")
    keys = (keys,) if isinstance(keys, str) else keys
    if not (isinstance(keys, (list, tuple)) and keys and all(isinstance(k, str) and k
                                                            for k in keys)):
        raise ParameterError(f"{ctx}.key = {keys!r} must be a scenario key (e.g. "
                             "'controller.L_s_hat', 'w_M0_rpm') or a list of them")
    rel = a.get("relative_to")
    ref = 1.0 if rel is None else _field_value(base, rel, f"{ctx}.relative_to")
    vals, kind, marginal = _grid(ctx, a)
    if kind == "draw":
        d = a["draw"]
        n = int(_number(f"{ctx}.n", _need(ctx, a, "n"), 1, 100_000, integer=True))
        rng = np.random.default_rng([rng_seed, i])
        if d == "uniform":
            lo = _number(f"{ctx}.low", _need(ctx, a, "low"))
            hi = _number(f"{ctx}.high", _need(ctx, a, "high"))
            if not lo < hi:
                raise ParameterError(f"{ctx}: low = {lo!r} must be below high = {hi!r}")
            marginal = ("uniform", float(lo), float(hi))
            vals = rng.uniform(lo, hi, n)
        elif d == "normal":
            mu = _number(f"{ctx}.mean", _need(ctx, a, "mean"))
            sd = _number(f"{ctx}.std", _need(ctx, a, "std"), 0.0)
            marginal = ("normal", float(mu), float(sd))
            vals = rng.normal(mu, sd, n)
        else:
            raise ParameterError(f"{ctx}.draw = {d!r} is not one of uniform, normal")
        vals = tuple(float(v) for v in vals)
    if rel is not None and not all(_is_num(v) for v in vals):
        raise ParameterError(f"{ctx}: relative_to needs numeric values")
    label = a.get("label", name)
    if not isinstance(label, str):
        raise ParameterError(f"{ctx}.label = {label!r} must be a string")
    scale = 1.0
    if "scale" in a:
        scale = float(_number(f"{ctx}.scale", a["scale"], -1e12, 1e12))
        if scale == 0 or not all(_is_num(v) for v in vals):
            raise ParameterError(f"{ctx}.scale = {scale!r}: a non-zero factor of numeric "
                                 "values")
    return Axis(name, label, tuple(keys), rel, vals, kind, marginal, scale)


def _axis_changes(ax: Axis, value: Any, base: Scenario) -> dict:
    ref = 1.0 if ax.relative_to is None else _field_value(base, ax.relative_to, "")
    v = value * ref * ax.scale if (ax.relative_to is not None or ax.scale != 1.0) else value
    out: dict = {}
    for k in ax.keys:
        out = _merge(out, _dotted(k, v))
    return out


def _seeds(d: Any) -> tuple[str | None, tuple[int, ...]]:
    if d is None:
        return None, ()
    ctx = "seeds"
    if not isinstance(d, dict):
        raise ParameterError("[seeds] must be a table (n = 10, or values = [...])")
    _unknown(ctx, d, SEED_KEYS)
    key = d.get("key", "adc.seed")
    if not isinstance(key, str):
        raise ParameterError(f"seeds.key = {key!r} must be a scenario key such as 'adc.seed'")
    if "values" in d:
        vals = d["values"]
        if not (isinstance(vals, list) and vals and all(isinstance(v, int) and not
                                                        isinstance(v, bool) and v >= 0
                                                        for v in vals)):
            raise ParameterError(f"seeds.values = {vals!r} must be a non-empty list of whole "
                                 "numbers >= 0")
        if len(set(vals)) != len(vals):
            raise ParameterError(f"seeds.values = {vals!r} has repeated seeds")
        return key, tuple(vals)
    n = int(_number("seeds.n", _need(ctx, d, "n"), 1, 100_000, integer=True))
    first = int(_number("seeds.first", d.get("first", 0), 0, 2**62, integer=True))
    return key, tuple(range(first, first + n))


def run_count(spec: SweepSpec) -> tuple[int, str]:
    """How many runs `spec` has, from its axes' sizes alone (nothing is
    expanded), and those sizes as text (``L_ratio 8 x R_ratio 5 x 4
    seeds``)."""
    if spec.sample == "lhs":
        sizes = [(a.name, len(a.values)) for a in spec.axes if a.marginal is None]
        sizes.append((f"{spec.samples} lhs samples", None))
        n = math.prod(k for _, k in sizes if k is not None) * spec.samples
    else:
        sizes = [(a.name, len(a.values)) for a in spec.axes]
        n = math.prod(k for _, k in sizes)
    if spec.seeds:
        sizes.append((f"{len(spec.seeds)} seeds", None))
        n *= len(spec.seeds)
    text = " x ".join(name if k is None else f"{name} {k}" for name, k in sizes) or "one run"
    return n, text


def check_run_count(spec: SweepSpec) -> int:
    """The run count of `spec` (:func:`run_count`); a ParameterError naming
    it, the axes' sizes and :data:`MAX_RUNS` when it exceeds that bound."""
    n, sizes = run_count(spec)
    if n > MAX_RUNS:
        raise ParameterError(
            f"sweep {spec.name}: {n:,} runs ({sizes}) exceed the bound of {MAX_RUNS:,} runs a "
            "sweep may have; use fewer values (n) on an axis, fewer seeds, sample = 'lhs' with "
            "fewer samples, or several sweeps")
    return n


def parse_sweep(data: dict, name: str = "sweep", ctx_dir: Path | None = None) -> SweepSpec:
    """A SweepSpec from a parsed sweep file (see the module docstring and
    docs/sweeps.md); every field is checked, a wrong one is named with its
    valid range."""
    known_top = {"sweep", "set", "axes", "seeds", "plots"}
    _unknown("", data, known_top)
    sw = data.get("sweep")
    if not isinstance(sw, dict):
        raise ParameterError("[sweep] is missing: it names the base scenario and the metrics")
    _unknown("sweep", sw, SWEEP_KEYS)
    base = _load_base(_need("sweep", sw, "base"), ctx_dir)
    sets = data.get("set", {})
    if not isinstance(sets, dict):
        raise ParameterError("[set] must be a table of scenario keys")
    try:
        base = apply_changes(base, sets)
    except ParameterError as exc:
        raise ParameterError(f"[set] {exc}") from None
    from .scenario_io import scenario_to_toml

    base_toml = scenario_to_toml(base)
    metrics = _need("sweep", sw, "metrics")
    if not (isinstance(metrics, list) and metrics and all(isinstance(m, str) for m in metrics)):
        raise ParameterError(f"sweep.metrics = {metrics!r} must be a list of metric names "
                             f"(known: {', '.join(METRICS)})")
    for m in metrics:
        if m not in METRICS:
            raise ParameterError(f"sweep.metrics: {m!r} is not a metric (known: "
                                 f"{', '.join(METRICS)})")
    if len(set(metrics)) != len(metrics):
        raise ParameterError(f"sweep.metrics = {metrics!r} names a metric twice")
    dur = base.duration
    w = sw.get("window", [dur / 2, dur])
    if not (isinstance(w, list) and len(w) == 2 and all(map(_is_num, w))
            and 0.0 <= w[0] < w[1] <= dur * (1 + 1e-12)):
        raise ParameterError(f"sweep.window = {w!r} must be [t0, t1] seconds with 0 <= t0 < "
                             f"t1 <= duration = {dur:g} s (of the base scenario)")
    sample = sw.get("sample", "product")
    if sample not in ("product", "lhs"):
        raise ParameterError(f"sweep.sample = {sample!r} is not one of product, lhs")
    seed = int(_number("sweep.seed", sw.get("seed", 0), 0, 2**62, integer=True))
    samples = 0
    if sample == "lhs":
        samples = int(_number("sweep.samples", _need("sweep", sw, "samples"), 1, 1_000_000,
                              integer=True))
    elif "samples" in sw:
        raise ParameterError("sweep.samples is for sample = 'lhs' only")
    bs = sw.get("batch_seconds")
    if bs is not None:
        bs = float(_number("sweep.batch_seconds", bs, 0.01, 600.0))
    axes_raw = data.get("axes", [])
    if not isinstance(axes_raw, list):
        raise ParameterError("axes must be an array of tables ([[axes]])")
    axes: list[Axis] = []
    for i, a in enumerate(axes_raw):
        axes.append(_axis(i, a, base, seed, {x.name for x in axes}))
    seed_key, seeds = _seeds(data.get("seeds"))
    plots = data.get("plots", [])
    if not (isinstance(plots, list) and all(isinstance(p, dict) for p in plots)):
        raise ParameterError("plots must be an array of tables ([[plots]])")
    title = sw.get("title", name)
    if not isinstance(title, str):
        raise ParameterError(f"sweep.title = {title!r} must be a string")
    raw = {k: v for k, v in data.items() if k != "set"}
    raw["sweep"] = {**sw, "base": {"toml": base_toml}}
    spec = SweepSpec(name, title, base, base_toml, tuple(metrics),
                     (float(w[0]), float(min(w[1], dur))), sample, samples, seed, axes,
                     seed_key, seeds, plots, bs, raw)
    check_run_count(spec)  # before anything the size of the run list is made
    from .sweep_plot import check_plots

    check_plots(spec)
    return spec


def load_sweep(path: str | Path) -> SweepSpec:
    """Read a sweep file (or a built-in sweep by name, see :func:`builtins`)."""
    p = Path(path)
    if not p.is_file():
        if str(path) in builtins():
            p = builtin_path(str(path))
        else:
            raise ParameterError(f"{path}: neither a sweep file nor a built-in sweep (known: "
                                 f"{', '.join(builtins())})")
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8-sig"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ParameterError(f"{p}: not valid TOML: {exc}") from None
    except OSError as exc:
        raise ParameterError(f"{p}: cannot read the file ({exc.strerror or exc})") from None
    return parse_sweep(data, p.stem, p.parent)


def builtins() -> dict[str, str]:
    """The built-in sweeps: name -> title."""
    out = {}
    for p in sorted(BUILTIN_DIR.glob("*.toml")):
        title = tomllib.loads(p.read_text(encoding="utf-8")).get("sweep", {}).get("title", "")
        out[p.stem] = title
    return out


def builtin_path(name: str) -> Path:
    return BUILTIN_DIR / f"{name}.toml"


# ------------------------------------------------------------- the runs ---

def _run_id(spec: SweepSpec, changes: dict) -> str:
    h = hashlib.sha256(json.dumps(
        {"base": spec.base_toml, "window": spec.window, "metrics": spec.metrics,
         "changes": changes}, sort_keys=True, default=repr).encode()).hexdigest()
    return h[:20]


def _lhs_points(spec: SweepSpec) -> list[dict[str, Any]]:
    """`samples` points of the continuous axes (Latin hypercube: each axis's
    range cut into `samples` equally likely strata, one point in each)."""
    from statistics import NormalDist

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
    slowest, the seed fastest); a sweep of more than :data:`MAX_RUNS` runs
    is refused before any is made."""
    import itertools

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
    seeds = spec.seeds or (None,)
    for point in combos:
        ch: dict = {}
        for a in spec.axes:
            ch = _merge(ch, _axis_changes(a, point[a.name], spec.base))
        for sd in seeds:
            changes = ch if sd is None else _merge(ch, _dotted(spec.seed_key, sd))
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
    seen: set[str] = set()
    for a in spec.axes:
        for v in (a.values if a.kind != "draw" or spec.sample == "product"
                  else sorted({r.point[a.name] for r in runs})[::max(1, len(runs) // 50)]):
            pt = {**first, a.name: v}
            ch: dict = {}
            for b in spec.axes:
                ch = _merge(ch, _axis_changes(b, pt.get(b.name, first.get(b.name)), spec.base))
            key = json.dumps(ch, sort_keys=True, default=repr)
            if key in seen:
                continue
            seen.add(key)
            try:
                apply_changes(spec.base, ch).check_controller()
            except ParameterError as exc:
                raise ParameterError(f"axis {a.name} = {v!r}: {exc}") from None
    if spec.seeds:
        try:
            apply_changes(spec.base, _dotted(spec.seed_key, max(spec.seeds)))
        except ParameterError as exc:
            raise ParameterError(f"[seeds] {exc}") from None


# ------------------------------------------------------- in the worker ---

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
    from .engine import CHANNELS, Engine, Result

    t_start = time.perf_counter()
    row: dict[str, Any] = {"run_id": run.id, "index": run.index, **run.point}
    row.update(dict.fromkeys(job.metrics, math.nan))
    row.update(status="error", error="", first_fault="", fault_t=math.nan, final_fault="",
               steps=0, smodrive_version=job.version)
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
            row.update(metric_values(r, job.metrics, *job.window))
        from .engine import fault_names

        row.update(status="fault" if f.final else "ok", steps=n,
                   first_fault=",".join(fault_names(f.first)),
                   fault_t=math.nan if f.t_first is None else f.t_first,
                   final_fault=",".join(fault_names(f.final)))
    except Exception as exc:  # a refused combination: recorded, the sweep goes on
        row["error"] = f"{type(exc).__name__}: {exc}"
    row["wall_s"] = time.perf_counter() - t_start
    return row


def _warm_up(base: Scenario) -> None:
    """On each worker before the runs: the modules and the C library loaded,
    one engine initialised (start-up is not counted in the run phase)."""
    from .engine import Engine

    Engine(base)


def run_batch(job: Job, runs: list[Run]) -> list[dict[str, Any]]:
    """A Dask task: the rows of a batch of runs."""
    return [run_one(job, r) for r in runs]


# ---------------------------------------------------------- the results ---

def _schema(spec: SweepSpec):
    import pyarrow as pa

    cols = [("run_id", pa.string()), ("index", pa.int64())]
    for a in spec.axes:
        typ = (pa.int64() if a.integer else pa.float64() if a.numeric
               else pa.bool_() if all(isinstance(v, bool) for v in a.values) else pa.string())
        cols.append((a.name, typ))
    if spec.seeds:
        cols.append(("seed", pa.int64()))
    cols += [(m, pa.float64()) for m in spec.metrics]
    cols += [("status", pa.string()), ("error", pa.string()), ("first_fault", pa.string()),
             ("fault_t", pa.float64()), ("final_fault", pa.string()), ("wall_s", pa.float64()),
             ("steps", pa.int64()), ("smodrive_version", pa.string())]
    return pa.schema(cols)


def runs_dir(out: Path) -> Path:
    return Path(out) / "runs"


def _part_files(out: Path) -> list[Path]:
    d = runs_dir(out)
    return sorted(d.glob("part-*.parquet")) if d.is_dir() else []


def done_ids(out: Path) -> set[str]:
    """The run ids OUT has a row for."""
    import pyarrow.parquet as pq

    ids: set[str] = set()
    for p in _part_files(out):
        ids.update(pq.read_table(p, columns=["run_id"]).column(0).to_pylist())
    return ids


def read_parts(out: Path):
    """Every row of OUT/runs (all parts, as written: a run twice would show
    twice), as one pyarrow Table."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    tables = [pq.read_table(p) for p in _part_files(out)]
    if not tables:
        return None
    return pa.concat_tables(tables, promote_options="permissive")


def load_results(spec: SweepSpec, out: Path) -> dict[str, np.ndarray]:
    """The rows of OUT that belong to the runs of `spec` (one per run, in
    run order), as columns: name -> numpy array."""
    t = read_parts(out)
    runs = expand(spec)
    order = {r.id: r.index for r in runs}
    if t is None:
        return {c: np.array([]) for c in _schema(spec).names}
    ids = t.column("run_id").to_pylist()
    keep, seen = [], set()
    for i, rid in enumerate(ids):
        if rid in order and rid not in seen:
            seen.add(rid)
            keep.append(i)
    keep.sort(key=lambda i: order[ids[i]])
    t = t.take(keep)
    import pyarrow as pa

    cols = {}
    for name in t.column_names:
        col = t.column(name)
        cols[name] = np.array(col.to_pylist(), dtype=object if col.type == pa.string() else None)
    return cols


def _write_part(out: Path, spec: SweepSpec, rows: list[dict]) -> Path:
    import pyarrow as pa
    import pyarrow.parquet as pq

    tag = hashlib.sha256("".join(r["run_id"] for r in rows).encode()).hexdigest()[:12]
    path = runs_dir(out) / f"part-{min(r['index'] for r in rows):08d}-{tag}.parquet"
    tmp = path.with_name("." + path.name + f".{os.getpid()}.tmp")
    schema = _schema(spec)
    table = pa.Table.from_pylist([{k: r.get(k) for k in schema.names} for r in rows],
                                 schema=schema)
    pq.write_table(table, tmp)
    with open(tmp, "rb") as f:
        os.fsync(f.fileno())
    os.replace(tmp, path)  # a part is there whole or not at all
    return path


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
    total: int  # runs of the sweep
    done_before: int  # of them, already in OUT
    computed: int  # computed now
    failed_batches: list[str]  # batches Dask gave up on (their runs are still missing)
    errors: int  # rows with status "error"
    faults: int  # rows with status "fault"
    seconds: float  # wall time of the run phase
    steps: int  # control samples simulated now
    workers: int
    batches: int
    busy_seconds: float = 0.0  # sum of the runs' wall times in the workers


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
    import logging

    from distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout="20s"), None
        except (OSError, TimeoutError) as exc:
            raise ParameterError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
    n = workers or _cores()
    if not 1 <= n <= 1024:
        raise ParameterError(f"--workers {n} is outside its valid range [1, 1024]")
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                           dashboard_address=":0", silence_logs=logging.CRITICAL)
    return Client(cluster), cluster


def prepare_out(spec: SweepSpec, out: Path, sweep_text: str | None = None) -> None:
    out = Path(out)
    from .engine.export import write_text  # atomic: a killed sweep never leaves half a sweep.json

    runs_dir(out).mkdir(parents=True, exist_ok=True)
    write_text(out / "sweep.json", json.dumps(
        {"name": spec.name, "spec": spec.raw}, indent=1, default=repr) + "\n")
    if sweep_text is not None:
        write_text(out / "sweep.toml", sweep_text)


def load_out_spec(out: Path) -> SweepSpec:
    """The sweep whose results OUT holds (OUT/sweep.json)."""
    p = Path(out) / "sweep.json"
    if not p.is_file():
        raise ParameterError(f"{out}: no sweep.json there (not the --out of a sweep)")
    d = json.loads(p.read_text(encoding="utf-8"))
    return parse_sweep(d["spec"], d.get("name", "sweep"))


def run_sweep(spec: SweepSpec, out: str | Path, scheduler: str | None = None,
              workers: int | None = None, client=None,
              progress: Callable[[str, int, int], None] | None = None,
              on_batch: Callable[[list[dict], Any], None] | None = None,
              sweep_text: str | None = None) -> SweepReport:
    """Run the runs of `spec` that OUT has no row for, on Dask; write each
    finished batch as a Parquet part of OUT/runs. `progress(phase, done,
    total)`; `on_batch(rows, client)` after each part is written (tests
    use it to kill a worker mid-sweep). A batch Dask gives up on (its
    workers died three times) is reported, not written: run again."""
    import pyarrow.parquet  # noqa: F401  (imported now, not while the workers run)
    from distributed import as_completed

    out = Path(out)
    runs = expand(spec)
    check_runs(spec, runs)
    out.mkdir(parents=True, exist_ok=True)
    lock = _Lock(out)
    own_client = client is None
    cluster = None
    try:
        prepare_out(spec, out, sweep_text)
        for tmp in runs_dir(out).glob(".part-*.tmp"):  # a write a killed sweep left half done
            tmp.unlink()
        have = done_ids(out)
        todo = [r for r in runs if r.id not in have]
        n_before = len(runs) - len(todo)
        if progress:
            progress("starting Dask", 0, 1)
        if todo and own_client:
            client, cluster = start_client(scheduler, workers)
        n_workers = len(client.scheduler_info()["workers"]) if todo else 0
        if todo:
            client.run(_warm_up, spec.base)  # imports and the C library, once
        if progress:
            progress("starting Dask", 1, 1)
        batches = make_batches(spec, todo, n_workers)
        job = Job(spec.base, spec.metrics, spec.window, spec.full_log, version())
        rep = SweepReport(len(runs), n_before, 0, [], 0, 0, 0.0, 0, n_workers, len(batches))
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
                _write_part(out, spec, rows)
                rep.computed += len(rows)
                rep.steps += sum(r["steps"] for r in rows)
                rep.busy_seconds += sum(r["wall_s"] for r in rows)
                rep.errors += sum(r["status"] == "error" for r in rows)
                rep.faults += sum(r["status"] == "fault" for r in rows)
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
