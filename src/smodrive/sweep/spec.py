"""The sweep spec: a sweep file (TOML) parsed and checked into a
:class:`SweepSpec` (its base scenario with ``[set]`` applied, the metrics
and window, the axes, the seeds, the plots), the built-in sweeps, and the
run count of a spec with its bound :data:`MAX_RUNS`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .._util import is_num, tomllib
from ..analysis.metrics import METRICS
from ..model import ParameterError, Scenario
from ..scenario_io import load_scenario, scenario_from_dict, scenario_to_toml
from ..scenarios import catalogue
from .axes import Axis, apply_changes, need, number, parse_axis, parse_seeds, unknown
from .plotspec import check_plots, same

#: the built-in sweeps (``smodrive sweep --list``), one TOML file each
BUILTIN_DIR = Path(__file__).resolve().parent / "builtin"
SWEEP_KEYS = {"title", "base", "metrics", "window", "sample", "samples", "seed",
              "batch_seconds"}
#: the most runs a sweep may have: the runs are expanded in memory (about
#: 1.2 kB each, some 1.2 GB at the bound) before the first one is sent;
#: a spec beyond it is refused before anything is allocated
MAX_RUNS = 1_000_000


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
    #: [seeds].where: the seeds are run only at the points whose axes take
    #: these values (axis name -> values); elsewhere the base's own seed
    #: (empty: the seeds everywhere)
    seeds_where: dict[str, tuple] = field(default_factory=dict)
    #: the text of the sweep file it was read from (a built-in sweep's too),
    #: written to OUT/sweep.toml; None for a spec not read from a file
    text: str | None = None

    @property
    def full_log(self) -> bool:
        return any(METRICS[m].needs_full_log for m in self.metrics)

    def seeded(self, point: dict) -> bool:
        """The seeds are run at `point` (every point without [seeds].where)."""
        return bool(self.seeds) and all(any(same(point[k], v) for v in vals)
                                        for k, vals in self.seeds_where.items())

    @property
    def base_seed(self) -> Any:
        """The seed the base scenario has at [seeds].key (the seed of the
        points outside [seeds].where)."""
        obj: Any = self.base
        for part in (self.seed_key or "adc.seed").split("."):
            obj = getattr(obj, part)
        return obj

    @property
    def axis_names(self) -> list[str]:
        return [a.name for a in self.axes]

    def axis(self, name: str) -> Axis:
        for a in self.axes:
            if a.name == name:
                return a
        raise ParameterError(f"{name!r} is not an axis of sweep {self.name} (axes: "
                             f"{', '.join(self.axis_names + (['seed'] if self.seeds else []))})")


def _load_base(ref: Any, ctx_dir: Path | None) -> Scenario:
    if isinstance(ref, dict) and set(ref) == {"toml"}:  # a stored sweep (sweep.json)
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
    if spec.seeds and spec.seeds_where:
        inside = math.prod(len(spec.seeds_where.get(a.name, a.values)) for a in spec.axes)
        sizes.append((f"{len(spec.seeds)} seeds at {inside} points", None))
        n += inside * (len(spec.seeds) - 1)
    elif spec.seeds:
        sizes.append((f"{len(spec.seeds)} seed{'' if len(spec.seeds) == 1 else 's'}", None))
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
    """A SweepSpec from a parsed sweep file (see the package docstring and
    docs/sweeps.md); every field is checked, a wrong one is named with its
    valid range."""
    known_top = {"sweep", "set", "axes", "seeds", "plots"}
    unknown("", data, known_top)
    sw = data.get("sweep")
    if not isinstance(sw, dict):
        raise ParameterError("[sweep] is missing: it names the base scenario and the metrics")
    unknown("sweep", sw, SWEEP_KEYS)
    base = _load_base(need("sweep", sw, "base"), ctx_dir)
    sets = data.get("set", {})
    if not isinstance(sets, dict):
        raise ParameterError("[set] must be a table of scenario keys")
    try:
        base = apply_changes(base, sets)
    except ParameterError as exc:
        raise ParameterError(f"[set] {exc}") from None
    base_toml = scenario_to_toml(base)
    metrics = need("sweep", sw, "metrics")
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
    if not (isinstance(w, list) and len(w) == 2 and all(map(is_num, w))
            and 0.0 <= w[0] < w[1] <= dur * (1 + 1e-12)):
        raise ParameterError(f"sweep.window = {w!r} must be [t0, t1] seconds with 0 <= t0 < "
                             f"t1 <= duration = {dur:g} s (of the base scenario)")
    sample = sw.get("sample", "product")
    if sample not in ("product", "lhs"):
        raise ParameterError(f"sweep.sample = {sample!r} is not one of product, lhs")
    seed = int(number("sweep.seed", sw.get("seed", 0), 0, 2**62, integer=True))
    samples = 0
    if sample == "lhs":
        samples = int(number("sweep.samples", need("sweep", sw, "samples"), 1, 1_000_000,
                             integer=True))
    elif "samples" in sw:
        raise ParameterError("sweep.samples is for sample = 'lhs' only")
    bs = sw.get("batch_seconds")
    if bs is not None:
        bs = float(number("sweep.batch_seconds", bs, 0.01, 600.0))
    axes_raw = data.get("axes", [])
    if not isinstance(axes_raw, list):
        raise ParameterError("axes must be an array of tables ([[axes]])")
    axes: list[Axis] = []
    for i, a in enumerate(axes_raw):
        axes.append(parse_axis(i, a, base, seed, {x.name for x in axes}))
    seed_key, seeds = parse_seeds(data.get("seeds"))
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
    spec.seeds_where = _seeds_where(data.get("seeds"), spec)
    check_run_count(spec)  # before anything the size of the run list is made
    check_plots(spec)
    return spec


def _seeds_where(d: Any, spec: SweepSpec) -> dict[str, tuple]:
    """[seeds].where checked: axis name -> the values (of that axis) where
    the seeds are run."""
    w = d.get("where") if isinstance(d, dict) else None
    if w is None:
        return {}
    if not isinstance(w, dict) or not w:
        raise ParameterError("seeds.where must be a table axis = value or [values] (the "
                             "points where the seeds are run)")
    if spec.sample != "product":
        raise ParameterError("seeds.where needs a grid (sample = 'product')")
    out = {}
    for k, v in w.items():
        if k not in spec.axis_names:
            raise ParameterError(f"seeds.where.{k}: not an axis (axes: "
                                 f"{', '.join(spec.axis_names)})")
        vals = v if isinstance(v, list) else [v]
        ax = spec.axis(k)
        for x in vals:
            if not any(same(x, a) for a in ax.values):
                raise ParameterError(f"seeds.where.{k} = {x!r} is not one of the axis's values "
                                     f"{list(ax.values)}")
        out[k] = tuple(vals)
    return out


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
        text = p.read_text(encoding="utf-8-sig")
        data = tomllib.loads(text)
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ParameterError(f"{p}: not valid TOML: {exc}") from None
    except OSError as exc:
        raise ParameterError(f"{p}: cannot read the file ({exc.strerror or exc})") from None
    spec = parse_sweep(data, p.stem, p.parent)
    spec.text = text
    return spec


def builtins() -> dict[str, str]:
    """The built-in sweeps: name -> title."""
    out = {}
    for p in sorted(BUILTIN_DIR.glob("*.toml")):
        title = tomllib.loads(p.read_text(encoding="utf-8")).get("sweep", {}).get("title", "")
        out[p.stem] = title
    return out


def builtin_path(name: str) -> Path:
    """The file of built-in sweep `name`."""
    return BUILTIN_DIR / f"{name}.toml"
