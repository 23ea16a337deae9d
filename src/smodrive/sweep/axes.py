"""The axes and seeds of a sweep file: each parsed and checked (a wrong
field named with its valid range), and the changes an axis value makes to
the base scenario (dotted TOML keys to nested tables), applied with
:func:`smodrive.scenario_io.apply`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import scenario_io as sio
from .._util import is_num
from ..analysis.metrics import METRICS
from ..model import ParameterError, Scenario

#: columns every row has beside its axes and metrics
STANDARD_COLUMNS = ("run_id", "index", "seed", "status", "error", "first_fault", "fault_t",
                    "final_fault", "wall_s", "steps", "smodrive_version", "held", "not_held",
                    "speed_offset_rpm", "i_limit_share", "u_limit_share")
AXIS_KEYS = {"name", "label", "key", "relative_to", "values", "range", "n", "spacing", "draw",
             "low", "high", "mean", "std", "scale"}
SEED_KEYS = {"key", "n", "first", "values", "where"}


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


# ------------------------------------------------------------ checking ---

def where(ctx: str, key: str) -> str:
    return f"{ctx}.{key}" if ctx else key


def need(ctx: str, d: dict, key: str) -> Any:
    if key not in d:
        raise ParameterError(f"{ctx}: missing {key!r}")
    return d[key]


def unknown(ctx: str, d: dict, known: set[str]) -> None:
    bad = sorted(set(d) - known)
    if bad:
        raise ParameterError(f"{where(ctx, bad[0])}: unknown field (known: "
                             f"{', '.join(sorted(known))})")


def number(ctx: str, v: Any, lo: float = -math.inf, hi: float = math.inf,
           integer: bool = False) -> float:
    ok = (isinstance(v, int) and not isinstance(v, bool)) if integer else is_num(v)
    what = "a whole number" if integer else "a number"
    if not ok or not math.isfinite(v) or not lo <= v <= hi:
        raise ParameterError(f"{ctx} = {v!r} is outside its valid range: {what} in "
                             f"[{lo:g}, {hi:g}]")
    return v


# ------------------------------------------------------------- changes ---

def dotted(key: str, value: Any) -> dict:
    """'controller.L_s_hat', v -> {'controller': {'L_s_hat': v}}."""
    parts = key.split(".")
    out: dict = value
    for p in reversed(parts):
        out = {p: out}
    return out


def merge(a: dict, b: dict) -> dict:
    out = dict(a)
    for k, v in b.items():
        out[k] = merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else v
    return out


def apply_changes(base: Scenario, data: dict) -> Scenario:
    """`base` with the changes `data` (a parsed scenario TOML without
    `base`: sections as tables, keys with units as in scenario files), by
    :func:`smodrive.scenario_io.apply`. Unlike a scenario file, another
    motor does not reset the base's controller: only the values the base
    derived from its motor follow it, the ones it sets stay."""
    if "base" in data:
        raise ParameterError("base: only in [sweep] (a sweep has one base scenario)")
    return sio.apply(base, data, rederive=False)


def field_value(s: Scenario, path: str, ctx: str) -> float:
    obj: Any = s
    for part in path.split("."):
        if not hasattr(obj, part):
            raise ParameterError(f"{ctx} = {path!r}: no such field of the base scenario (e.g. "
                                 "'motor.L_s', 'motor.psi_r', 'lcl.C1')")
        obj = getattr(obj, part)
    if not is_num(obj):
        raise ParameterError(f"{ctx} = {path!r} is not a number in the base scenario "
                             f"({obj!r})")
    return float(obj)


def axis_changes(ax: Axis, value: Any, base: Scenario) -> dict:
    """The changes (nested tables) that `value` of axis `ax` makes."""
    ref = 1.0 if ax.relative_to is None else field_value(base, ax.relative_to, "")
    v = value * ref * ax.scale if (ax.relative_to is not None or ax.scale != 1.0) else value
    out: dict = {}
    for k in ax.keys:
        out = merge(out, dotted(k, v))
    return out


# ------------------------------------------------------------- parsing ---

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
        kinds = {"num" if is_num(v) else type(v).__name__ for v in vals}
        if len(kinds) > 1 or kinds - {"num", "str", "bool"}:
            raise ParameterError(f"{ctx}.values = {vals!r} must be all numbers, all strings or "
                                 "all booleans")
        if len(set(vals)) != len(vals):
            raise ParameterError(f"{ctx}.values = {vals!r} has repeated values")
        return tuple(vals), "values", None
    if "range" in a:
        r = a["range"]
        if not (isinstance(r, list) and len(r) == 2 and all(map(is_num, r))
                and all(map(math.isfinite, r)) and r[0] < r[1]):
            raise ParameterError(f"{ctx}.range = {r!r} must be two numbers [low, high] with "
                                 "low < high")
        lo, hi = float(r[0]), float(r[1])
        if spacing == "log" and lo <= 0:
            raise ParameterError(f"{ctx}.range = {r!r}: a log spacing needs low > 0")
        n = int(number(f"{ctx}.n", need(ctx, a, "n"), 1, 100_000, integer=True))
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


def parse_axis(i: int, a: Any, base: Scenario, rng_seed: int, names: set[str]) -> Axis:
    """Axis `i` of the file ([[axes]] table `a`); `names`: the axes before it."""
    ctx = f"axes[{i}]"
    if not isinstance(a, dict):
        raise ParameterError(f"{ctx} must be a table ([[axes]])")
    name = need(ctx, a, "name")
    if not (isinstance(name, str) and name.isidentifier()):
        raise ParameterError(f"{ctx}.name = {name!r} must be a name (letters, digits, _)")
    ctx = f"axes[{i}] ({name})"
    unknown(ctx, a, AXIS_KEYS)
    reserved = set(STANDARD_COLUMNS) | set(METRICS)
    if name in reserved or name in names:
        raise ParameterError(f"{ctx}.name = {name!r} is taken (by another axis, a metric or "
                             f"a standard column: {', '.join(STANDARD_COLUMNS)})")
    keys = need(ctx, a, "key")
    keys = (keys,) if isinstance(keys, str) else keys
    if not (isinstance(keys, (list, tuple)) and keys and all(isinstance(k, str) and k
                                                            for k in keys)):
        raise ParameterError(f"{ctx}.key = {keys!r} must be a scenario key (e.g. "
                             "'controller.L_s_hat', 'w_M0_rpm') or a list of them")
    rel = a.get("relative_to")
    if rel is not None:
        field_value(base, rel, f"{ctx}.relative_to")
    vals, kind, marginal = _grid(ctx, a)
    if kind == "draw":
        d = a["draw"]
        n = int(number(f"{ctx}.n", need(ctx, a, "n"), 1, 100_000, integer=True))
        rng = np.random.default_rng([rng_seed, i])
        if d == "uniform":
            lo = number(f"{ctx}.low", need(ctx, a, "low"))
            hi = number(f"{ctx}.high", need(ctx, a, "high"))
            if not lo < hi:
                raise ParameterError(f"{ctx}: low = {lo!r} must be below high = {hi!r}")
            marginal = ("uniform", float(lo), float(hi))
            vals = rng.uniform(lo, hi, n)
        elif d == "normal":
            mu = number(f"{ctx}.mean", need(ctx, a, "mean"))
            sd = number(f"{ctx}.std", need(ctx, a, "std"), 0.0)
            marginal = ("normal", float(mu), float(sd))
            vals = rng.normal(mu, sd, n)
        else:
            raise ParameterError(f"{ctx}.draw = {d!r} is not one of uniform, normal")
        vals = tuple(float(v) for v in vals)
    if rel is not None and not all(is_num(v) for v in vals):
        raise ParameterError(f"{ctx}: relative_to needs numeric values")
    label = a.get("label", name)
    if not isinstance(label, str):
        raise ParameterError(f"{ctx}.label = {label!r} must be a string")
    scale = 1.0
    if "scale" in a:
        scale = float(number(f"{ctx}.scale", a["scale"], -1e12, 1e12))
        if scale == 0 or not all(is_num(v) for v in vals):
            raise ParameterError(f"{ctx}.scale = {scale!r}: a non-zero factor of numeric "
                                 "values")
    return Axis(name, label, tuple(keys), rel, vals, kind, marginal, scale)


def parse_seeds(d: Any) -> tuple[str | None, tuple[int, ...]]:
    """The [seeds] table: (the key each seed sets, the seeds); (None, ())
    without one."""
    if d is None:
        return None, ()
    ctx = "seeds"
    if not isinstance(d, dict):
        raise ParameterError("[seeds] must be a table (n = 10, or values = [...])")
    unknown(ctx, d, SEED_KEYS)
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
    n = int(number("seeds.n", need(ctx, d, "n"), 1, 100_000, integer=True))
    first = int(number("seeds.first", d.get("first", 0), 0, 2**62, integer=True))
    return key, tuple(range(first, first + n))
