"""The ``[[plots]]`` entries of a sweep file (docs/sweeps.md): their fields,
the check of each against the sweep's axes and metrics (when the file is
read, before anything runs), and the analytic overlays an entry may name.
:mod:`smodrive.sweep.maps` draws them."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..analysis.tf import dbpc_steady_state
from ..model import ParameterError

PLOT_KEYS = {"kind", "file", "title", "metric", "x", "y", "facet", "hue", "fixed", "rows",
             "reduce", "band", "log", "overlay", "overlay_facet", "over", "ok", "label",
             "beside", "clip", "scale_floor"}
PLOT_KINDS = ("heatmap", "lines", "envelope")
REDUCE = ("median", "mean", "max", "min", "worst")


def rows_of(p: dict) -> list[dict]:
    """A plot's rows of panels: `rows` (tables overriding the plot's keys),
    or one row a metric of `metric` when it is a list."""
    base = {k: v for k, v in p.items() if k != "rows"}
    if "rows" in p:
        return [{**base, **r} for r in p["rows"]]
    m = p.get("metric")
    if isinstance(m, list):
        return [{**base, "metric": x} for x in m]
    return [base]


def same(a: Any, b: Any) -> bool:
    """Two axis values are the same (numbers to 1e-9 relative)."""
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)
    return a == b


# -------------------------------------------------------------- overlays ---

def _yang2018_eq12_13(spec, r: dict, X: np.ndarray, Y: np.ndarray) -> np.ndarray | None:
    """yang2018 eq. (12)-(13) (conventional DBPC, steady state): the
    predicted id_error or iq_error over the (x, y) grid of L_hat and psi_hat
    axes; i_d_ref = 0 and i_q_ref carrying the base scenario's load at its
    initial speed."""
    s = spec.base
    m = s.motor
    vals = {}
    for axis_name, grid in ((r["x"], X), (r["y"], Y)):
        a = spec.axis(axis_name)
        ref = 1.0
        if a.relative_to:
            obj: Any = s
            for part in a.relative_to.split("."):
                obj = getattr(obj, part)
            ref = float(obj)
        for k in a.keys:
            vals[k] = grid * ref
    L_hat = vals.get("controller.L_s_hat", np.full_like(X, s.controller.L_s_hat))
    psi_hat = vals.get("controller.psi_r_hat", np.full_like(X, s.controller.psi_r_hat))
    w = s.w_M0
    T_L = s.load.T_brake(0.0) + s.load.T_ext(0.0) + s.load.k_fan * w * abs(w) + m.B * w
    i_q = T_L / m.k_t
    i_d, i_qs = dbpc_steady_state(m.L_s, m.R_s, m.psi_r, L_hat, s.controller.R_s_hat, psi_hat,
                                  w * m.n_p, s.T_sp, 0.0, i_q)
    if r["metric"] == "id_error":
        return i_d - 0.0
    if r["metric"] == "iq_error":
        return i_qs - i_q
    return None


#: analytic predictions a heatmap may overlay (``overlay = NAME``)
OVERLAYS = {"yang2018_eq12_13": _yang2018_eq12_13}


# ------------------------------------------------------------ checking ---

def check_plots(spec) -> None:
    """Every [[plots]] entry names existing axes, metrics and options; each
    axis is plotted, fixed, or reduced (the seeds)."""
    names = set(spec.axis_names)
    for i, p in enumerate(spec.plots):
        ctx = f"plots[{i}]"
        bad = sorted(set(p) - PLOT_KEYS)
        if bad:
            raise ParameterError(f"{ctx}.{bad[0]}: unknown field (known: "
                                 f"{', '.join(sorted(PLOT_KEYS))})")
        kind = p.get("kind")
        if kind not in PLOT_KINDS:
            raise ParameterError(f"{ctx}.kind = {kind!r} is not one of heatmap, lines, envelope")
        if not isinstance(p.get("file", ""), str) or not p.get("file", "x").isidentifier():
            raise ParameterError(f"{ctx}.file = {p.get('file')!r} must be a file stem "
                                 "(letters, digits, _)")
        if "rows" in p and not (isinstance(p["rows"], list) and p["rows"]
                                and all(isinstance(r, dict) for r in p["rows"])):
            raise ParameterError(f"{ctx}.rows must be a non-empty array of tables")
        for j, r in enumerate(rows_of(p)):
            c = f"{ctx}" if "rows" not in p else f"{ctx}.rows[{j}]"
            bad = sorted(set(r) - PLOT_KEYS)
            if bad:
                raise ParameterError(f"{c}.{bad[0]}: unknown field")
            metric = r.get("ok") if kind == "envelope" else r.get("metric")
            what = "ok" if kind == "envelope" else "metric"
            if metric not in spec.metrics:
                raise ParameterError(f"{c}.{what} = {metric!r} is not a metric of the sweep "
                                     f"(sweep.metrics: {', '.join(spec.metrics)})")
            need = {"heatmap": ("x", "y"), "lines": ("x",), "envelope": ("x", "over")}[kind]
            used = set()
            for k in need + ("facet", "hue"):
                if k in r:
                    if r[k] not in names:
                        raise ParameterError(f"{c}.{k} = {r[k]!r} is not an axis (axes: "
                                             f"{', '.join(spec.axis_names)})")
                    used.add(r[k])
                elif k in need:
                    raise ParameterError(f"{c}: missing {k!r} (an axis name)")
            if kind == "heatmap":
                for k in ("x", "y"):
                    ax = spec.axis(r[k])
                    if not ax.numeric or ax.kind == "draw":
                        raise ParameterError(f"{c}.{k} = {r[k]!r}: a heatmap needs a numeric "
                                             "grid or list of values, not a "
                                             + ("random draw" if ax.kind == "draw" else
                                                "list of names") + " (use facet or hue)")
            fixed = r.get("fixed", {})
            if not isinstance(fixed, dict):
                raise ParameterError(f"{c}.fixed must be a table axis = value")
            for k, v in fixed.items():
                if k not in names:
                    raise ParameterError(f"{c}.fixed.{k}: not an axis")
                ax = spec.axis(k)
                if not any(same(v, a) for a in ax.values):
                    raise ParameterError(f"{c}.fixed.{k} = {v!r} is not one of the axis's "
                                         f"values {list(ax.values)}")
            for a in spec.axes:
                if a.name not in used and a.name not in fixed and len(a.values) > 1:
                    raise ParameterError(f"{c}: axis {a.name} is neither plotted (x, y, facet, "
                                         "hue, over) nor fixed (fixed = {" f"{a.name} = ...}})")
            red = r.get("reduce", "median")
            if red not in REDUCE:
                raise ParameterError(f"{c}.reduce = {red!r} is not one of {', '.join(REDUCE)}")
            band = r.get("band", [10, 90])
            if not (isinstance(band, list) and len(band) == 2
                    and all(isinstance(b, (int, float)) for b in band)
                    and 0 <= band[0] < band[1] <= 100):
                raise ParameterError(f"{c}.band = {band!r} must be two percentiles [lo, hi] "
                                     "with 0 <= lo < hi <= 100")
            beside = r.get("beside", [])
            if not (isinstance(beside, list) and all(b in spec.metrics for b in beside)):
                raise ParameterError(f"{c}.beside = {beside!r} must be a list of metrics of the "
                                     f"sweep (sweep.metrics: {', '.join(spec.metrics)})")
            if beside and kind != "heatmap":
                raise ParameterError(f"{c}.beside: for a heatmap only")
            clip = r.get("clip")
            if clip is not None and not (isinstance(clip, (int, float)) and not
                                         isinstance(clip, bool) and 50 <= clip < 100):
                raise ParameterError(f"{c}.clip = {clip!r} must be a percentile in [50, 100) "
                                     "(the colour scale's end; what lies beyond is shown by "
                                     "the colour bar's arrows)")
            fl = r.get("scale_floor", 0.0)
            if not (isinstance(fl, (int, float)) and not isinstance(fl, bool) and fl >= 0
                    and math.isfinite(fl)):
                raise ParameterError(f"{c}.scale_floor = {fl!r} must be a number >= 0 (the "
                                     "least span of a linear colour scale, in the metric's "
                                     "unit)")
            ov = r.get("overlay")
            if ov is not None and ov not in OVERLAYS:
                raise ParameterError(f"{c}.overlay = {ov!r} is not one of "
                                     f"{', '.join(OVERLAYS)}")
    if spec.sample == "lhs" and any(p.get("kind") == "heatmap" for p in spec.plots):
        raise ParameterError("plots: a heatmap needs a grid (sample = 'product'); a Latin-"
                             "hypercube sample has no grid")
