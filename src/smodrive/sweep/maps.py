"""Maps of a sweep's results: heatmaps (two axes, with contours and
analytic overlays), lines with percentile bands over the seeds (one axis),
and the envelope of a pass/fail metric (the lowest value of an axis that
holds). What is drawn is the sweep file's ``[[plots]]`` (docs/sweeps.md,
checked by :mod:`smodrive.sweep.plotspec`).
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import matplotlib
import matplotlib.colors as mcolors
import matplotlib.ticker as mt
import numpy as np

from ..analysis.metrics import METRICS
from ..engine.export import atomic_path
from ..model import ParameterError
from .plotspec import OVERLAYS, rows_of, same
from .store import load_results

# ------------------------------------------------------------- helpers ---

def _select(cols: dict, fixed: dict) -> np.ndarray:
    m = np.ones(len(cols["run_id"]), dtype=bool)
    for k, v in fixed.items():
        m &= np.array([same(x, v) for x in cols[k]], dtype=bool)
    return m


def _reduce(x: np.ndarray, how: str) -> float:
    x = np.asarray(x, dtype=float)
    if x.size == 0 or np.all(np.isnan(x)):
        return math.nan
    return float({"median": np.nanmedian, "mean": np.nanmean, "max": np.nanmax,
                  "min": np.nanmin}[how](x))


def _edges(v: np.ndarray, log: bool) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    if v.size == 1:
        return np.array([v[0] * 0.9, v[0] * 1.1]) if log else np.array([v[0] - 0.5, v[0] + 0.5])
    t = np.log(v) if log else v
    mid = (t[1:] + t[:-1]) / 2
    e = np.concatenate([[t[0] - (mid[0] - t[0])], mid, [t[-1] + (t[-1] - mid[-1])]])
    return np.exp(e) if log else e


def _axis_label(spec, name: str) -> str:
    return spec.axis(name).label


def _metric_label(m: str) -> str:
    u = METRICS[m].unit
    return f"{m} ({u})" if u else m


def _is_log_axis(spec, name: str) -> bool:
    a = spec.axis(name)
    if not a.numeric or a.kind != "grid":
        return False
    v = np.asarray(a.values, dtype=float)
    return v.size > 2 and np.all(v > 0) and np.allclose(np.diff(np.log(v)),
                                                        np.log(v[1] / v[0]), rtol=1e-6)


def _log_ticks(ax, which: str, values: np.ndarray, log: bool) -> None:
    """A log axis labelled at the grid's values, as plain numbers."""
    if not log:
        return
    getattr(ax, f"set_{which}scale")("log")
    axis = ax.xaxis if which == "x" else ax.yaxis
    ticks = values if values.size <= 8 else values[::int(math.ceil(values.size / 8))]
    axis.set_major_locator(mt.FixedLocator(ticks))
    axis.set_major_formatter(mt.FuncFormatter(lambda v, _: f"{v:.3g}"))
    axis.set_minor_locator(mt.NullLocator())


# --------------------------------------------------------------- drawing ---

def _heatmap_row(fig, axs, spec, cols, r: dict) -> None:
    metric = r["metric"]
    facet_vals = spec.axis(r["facet"]).values if "facet" in r else (None,)
    xa, ya = spec.axis(r["x"]), spec.axis(r["y"])
    xs, ys = np.asarray(xa.values, float), np.asarray(ya.values, float)
    xlog, ylog = _is_log_axis(spec, r["x"]), _is_log_axis(spec, r["y"])
    grids, bads = [], []
    for fv in facet_vals:
        fixed = dict(r.get("fixed", {}))
        if fv is not None:
            fixed[r["facet"]] = fv
        sel = _select(cols, fixed)
        Z = np.full((ys.size, xs.size), np.nan)
        B = np.zeros_like(Z, dtype=bool)
        for i, yv in enumerate(ys):
            for j, xv in enumerate(xs):
                m = sel & _select(cols, {r["x"]: xv, r["y"]: yv})
                Z[i, j] = _reduce(cols[metric][m].astype(float), r.get("reduce", "median"))
                B[i, j] = bool(np.any(cols["status"][m] != "ok")) if m.any() else False
        grids.append(Z)
        bads.append(B)
    good = np.concatenate([z[~b].ravel() for z, b in zip(grids, bads)] or [np.array([])])
    good = good[np.isfinite(good)]
    signed = good.size and np.min(good) < 0
    if r.get("log") and good.size and np.all(good > 0):
        norm = mcolors.LogNorm(vmin=max(np.percentile(good, 1), 1e-12),
                               vmax=np.percentile(good, 99))
        cmap = "viridis"
    elif signed:
        v = float(np.percentile(np.abs(good), 98)) or 1.0
        norm, cmap = mcolors.Normalize(-v, v), "RdBu_r"
    else:
        hi = float(np.percentile(good, 98)) if good.size else 1.0
        norm, cmap = mcolors.Normalize(0.0 if good.size and good.min() >= 0 else None,
                                       hi or 1.0), "viridis"
    X, Y = np.meshgrid(xs, ys)
    ov_name = r.get("overlay")
    mesh = None
    for ax, fv, Z, B in zip(axs, facet_vals, grids, bads):
        mesh = ax.pcolormesh(_edges(xs, xlog), _edges(ys, ylog), np.ma.masked_invalid(Z),
                             norm=norm, cmap=cmap, shading="flat")
        if B.any():
            ax.plot(X[B], Y[B], "x", color="k", ms=4, mew=0.8, label="fault or error")
        Zc = np.where(B, np.nan, Z)
        levels = None
        if np.isfinite(Zc).sum() >= 4 and xs.size > 1 and ys.size > 1:
            lo, hi = norm.vmin, norm.vmax
            if isinstance(norm, mcolors.LogNorm):
                levels = np.geomspace(lo, hi, 6)[1:-1]
            else:
                levels = np.linspace(lo, hi, 9)[1:-1]
                if signed:  # no zero contour: on a map of errors it traces the noise
                    levels = levels[np.abs(levels) > 1e-6 * hi]
            cs = ax.contour(X, Y, np.ma.masked_invalid(Zc), levels=levels, colors="k",
                            linewidths=0.6)
            ax.clabel(cs, fontsize=6, fmt="%.3g")
        if ov_name and (r.get("overlay_facet") is None or same(fv, r.get("overlay_facet"))):
            P = OVERLAYS[ov_name](spec, r, X, Y)
            if P is not None and levels is not None:
                fine = [np.geomspace(v.min(), v.max(), 120) if lg else
                        np.linspace(v.min(), v.max(), 120) for v, lg in ((xs, xlog), (ys, ylog))]
                FX, FY = np.meshgrid(*fine)
                FP = OVERLAYS[ov_name](spec, r, FX, FY)
                ax.contour(FX, FY, FP, levels=levels, colors="m", linewidths=1.0,
                           linestyles="--")
                ax.plot([], [], "--", color="m", label="eq. (12)-(13)")
                ax.legend(loc="upper right", fontsize=6)
        _log_ticks(ax, "x", xs, xlog)
        _log_ticks(ax, "y", ys, ylog)
        title = metric if fv is None else f"{r['facet']} = {fv}"
        ax.set_title(r.get("label", title) if fv is None else f"{title}", fontsize=8)
        ax.set_xlabel(_axis_label(spec, r["x"]), fontsize=8)
        ax.set_ylabel(_axis_label(spec, r["y"]), fontsize=8)
        ax.tick_params(labelsize=7)
    cb = fig.colorbar(mesh, ax=list(axs), shrink=0.9)
    cb.set_label(r.get("label", _metric_label(metric)), fontsize=8)
    if isinstance(norm, mcolors.LogNorm):
        plain = mt.FuncFormatter(lambda v, _: f"{v:.2g}")
        cb.ax.yaxis.set_major_locator(mt.LogLocator(subs=(1.0, 2.0, 5.0)))
        cb.ax.yaxis.set_major_formatter(plain)
        cb.ax.yaxis.set_minor_formatter(mt.NullFormatter())
    cb.ax.tick_params(which="both", labelsize=7)


def _band_lines(ax, spec, cols, r: dict, values_of: callable) -> None:
    """One line per hue value: the reduction over seeds of values_of(mask)
    at each x, and the band of percentiles r['band'] over the seeds."""
    xa = spec.axis(r["x"])
    xs = np.asarray(xa.values, float)
    hues = spec.axis(r["hue"]).values if "hue" in r else (None,)
    lo, hi = r.get("band", [10, 90])
    for hv in hues:
        fixed = dict(r.get("fixed", {}))
        if hv is not None:
            fixed[r["hue"]] = hv
        med, blo, bhi = [], [], []
        for xv in xs:
            v = np.asarray(values_of({**fixed, r["x"]: xv}), float)
            v = v[np.isfinite(v)]
            med.append(_reduce(v, r.get("reduce", "median")))
            blo.append(np.percentile(v, lo) if v.size else np.nan)
            bhi.append(np.percentile(v, hi) if v.size else np.nan)
        label = None if hv is None else f"{spec.axis(r['hue']).label} = {hv:g}" if isinstance(
            hv, (int, float)) else f"{r['hue']} = {hv}"
        line, = ax.plot(xs, med, "o-", ms=3, label=label)
        ax.fill_between(xs, blo, bhi, color=line.get_color(), alpha=0.2, lw=0)
    _log_ticks(ax, "x", xs, _is_log_axis(spec, r["x"]))
    if r.get("log"):
        ax.set_yscale("log")
    ax.set_xlabel(_axis_label(spec, r["x"]), fontsize=8)
    ax.tick_params(labelsize=7)
    ax.grid(alpha=0.3)
    if hues != (None,):
        ax.legend(fontsize=6)


def lowest_holding(over_values, ok: np.ndarray, over: np.ndarray) -> float:
    """The lowest value v of the `over` axis such that every run at v and
    above holds (`ok`), among the runs given (one a value of `over`); NaN
    if the highest value does not hold."""
    best = math.nan
    for v in sorted(over_values, reverse=True):
        m = np.array([same(x, v) for x in over])
        if not m.any():
            continue
        if np.all(ok[m]):
            best = float(v)
        else:
            break
    return best


def envelope_values(spec, cols, r: dict, fixed: dict) -> np.ndarray:
    """Per seed (or the single run without seeds): the lowest value of axis
    r['over'] that holds (metric r['ok'] >= 0.5 and no fault) at the point
    `fixed` of the other axes."""
    sel = _select(cols, fixed)
    seeds = sorted(set(cols["seed"][sel])) if "seed" in cols and spec.seeds else [None]
    out = []
    for sd in seeds:
        m = sel & (np.asarray(cols["seed"]) == sd) if sd is not None else sel
        ok = (cols[r["ok"]][m].astype(float) >= 0.5) & (cols["status"][m] == "ok")
        out.append(lowest_holding(spec.axis(r["over"]).values, ok, cols[r["over"]][m]))
    return np.array(out, float)


def plot_all(spec, out: Path, cols: dict | None = None) -> list[Path]:
    """Draw every [[plots]] entry of the sweep from OUT's results into
    OUT/maps/<file>.png; returns the paths."""
    matplotlib.use("Agg")
    # pyplot after the backend is chosen: files only, never a window
    import matplotlib.pyplot as plt

    out = Path(out)
    if cols is None:
        cols = load_results(spec, out)
    if len(cols["run_id"]) == 0:
        raise ParameterError(f"{out}: no results of this sweep to plot (run it first)")
    (out / "maps").mkdir(parents=True, exist_ok=True)
    paths = []
    for i, p in enumerate(spec.plots):
        rows = rows_of(p)
        kind = p["kind"]
        ncol = len(spec.axis(p["facet"]).values) if "facet" in p else 1
        width = max(6.5, 3.3 * ncol + 1.2)
        fig, axs = plt.subplots(len(rows), ncol, figsize=(width, 2.8 * len(rows) + 0.4),
                                squeeze=False, constrained_layout=True)
        for k, r in enumerate(rows):
            if kind == "heatmap":
                _heatmap_row(fig, axs[k], spec, cols, r)
                continue
            facets = spec.axis(r["facet"]).values if "facet" in r else (None,)
            for ax, fv in zip(axs[k], facets):
                rr = dict(r)
                if fv is not None:
                    rr["fixed"] = {**r.get("fixed", {}), r["facet"]: fv}
                if kind == "lines":
                    def vals(fx, rr=rr):
                        return cols[rr["metric"]][_select(cols, fx)].astype(float)
                    _band_lines(ax, spec, cols, rr, vals)
                    ax.set_ylabel(r.get("label", _metric_label(r["metric"])), fontsize=8)
                else:
                    def vals(fx, rr=rr):
                        return envelope_values(spec, cols, rr, fx)
                    _band_lines(ax, spec, cols, rr, vals)
                    ax.set_ylabel(r.get("label", f"lowest {spec.axis(r['over']).label} "
                                                 "that holds"), fontsize=8)
                if fv is not None:
                    ax.set_title(f"{r['facet']} = {fv}", fontsize=8)
        fig.suptitle(textwrap.fill(p.get("title", spec.title), int(width * 14)), fontsize=9)
        path = out / "maps" / f"{p.get('file', f'map{i}')}.png"
        with atomic_path(path) as tmp:  # never a truncated map under its name
            fig.savefig(tmp, format="png", dpi=int(p.get("dpi", 90)))
        plt.close(fig)
        paths.append(path)
    return paths
