"""Maps of a sweep's results: heatmaps (two axes, with contours and
analytic overlays), lines with percentile bands over the seeds (one axis),
and the envelope of a pass/fail metric (the lowest value of an axis that
holds). What is drawn is the sweep file's ``[[plots]]`` (docs/sweeps.md,
checked by :mod:`smodrive.sweep.plotspec`).

A value is drawn only where its runs held their operating point
(:mod:`smodrive.sweep.cells`): a cell whose runs did not is hatched by the
reason, a faulted one is grey with its kind's marker, and the figure's
legend counts the runs of each state; every heatmap panel has its own
colour scale, its colour bar's arrows show values beyond it.
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import matplotlib
import matplotlib.colors as mcolors
import matplotlib.patches as mpatches
import matplotlib.ticker as mt
import numpy as np
from matplotlib.lines import Line2D

from ..analysis.metrics import METRICS, NOT_HELD
from ..engine.export import atomic_path
from ..model import ParameterError
from .cells import Cells, cells, held_column, reduce_values, select, state_counts
from .plotspec import OVERLAYS, rows_of, same
from .store import load_results

#: the hatch of a cell that did not hold, by its first reason
HATCH = {"angle": "xx", "speed": "--", "current_limit": "//", "voltage_limit": "\\\\"}
#: the marker of a faulted cell, by its fault's kind (others: a diamond)
FAULT_MARKER = {"overcurrent": "x", "lost_lock": "+", "speed_tracking": "v",
                "oscillation": "s", "chatter": "^", "start_failed": "<", "forced": ">",
                "hunting": "*"}
NOT_HELD_FILL, FAULT_FILL = "0.9", "0.55"
REASON_TEXT = {"angle": "position error beyond 90 deg", "speed": "mean speed out of its band",
               "current_limit": "current reference on i_max",
               "voltage_limit": "voltage on the modulator's limit"}
#: a cell of several runs is marked when they differ by more than this
#: share of its panel's colour range (or are in different states)
SEED_SPREAD = 0.1


# ------------------------------------------------------------- helpers ---

def _edges(v: np.ndarray, log: bool) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    if v.size == 1:
        return np.array([v[0] * 0.9, v[0] * 1.1]) if log else np.array([v[0] - 0.5, v[0] + 0.5])
    t = np.log(v) if log else v
    mid = (t[1:] + t[:-1]) / 2
    e = np.concatenate([[t[0] - (mid[0] - t[0])], mid, [t[-1] + (t[-1] - mid[-1])]])
    return np.exp(e) if log else e


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


def panel_norm(values: np.ndarray, log: bool = False, clip: float | None = None,
               floor: float = 0.0):
    """A panel's colour scale from the values it draws: (norm, colour map,
    the colour bar's extension). Logarithmic if `log` and every value is
    positive; symmetric about zero (RdBu_r) if any is negative; else from 0
    (or the least value) up. The scale spans every value, or with `clip`
    the `clip` percentile of them (of the magnitudes when symmetric); values
    beyond it get the end colours and the colour bar an arrow. A linear
    scale spans at least `floor` (a symmetric one +-floor): values below
    what the map resolves stay pale instead of filling the colours."""
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return mcolors.Normalize(0.0, 1.0), "viridis", "neither"
    if log and np.all(v > 0):
        lo, hi = (float(np.min(v)), float(np.max(v))) if clip is None else (
            float(np.percentile(v, 100 - clip)), float(np.percentile(v, clip)))
        if hi <= lo:
            lo, hi = lo / 1.1, hi * 1.1
        norm, cmap = mcolors.LogNorm(lo, hi), "viridis"
    elif np.min(v) < 0:
        a = float(np.max(np.abs(v)) if clip is None else np.percentile(np.abs(v), clip))
        a = max(a, floor) if max(a, floor) > 0 else 1.0
        norm, cmap = mcolors.Normalize(-a, a), "RdBu_r"
    else:
        lo = 0.0 if np.min(v) >= 0 else float(np.min(v))
        hi = max(float(np.max(v) if clip is None else np.percentile(v, clip)), lo + floor)
        norm, cmap = mcolors.Normalize(lo, hi if hi > lo else lo + 1.0), "viridis"
    below, above = bool(np.any(v < norm.vmin)), bool(np.any(v > norm.vmax))
    extend = {(False, False): "neither", (True, False): "min", (False, True): "max",
              (True, True): "both"}[(below, above)]
    return norm, cmap, extend


def _levels(norm) -> np.ndarray:
    """Contour levels inside a panel's scale: at most 6 round values (no
    zero: on a map of errors it traces the noise)."""
    lo, hi = norm.vmin, norm.vmax
    lv = np.array([])
    for nbins in (6, 8, 10, 12):
        if isinstance(norm, mcolors.LogNorm):
            lv = mt.LogLocator(subs=(1.0, 2.0, 5.0)).tick_values(lo, hi)
        else:
            lv = mt.MaxNLocator(nbins=nbins, steps=[1, 2, 2.5, 5, 10]).tick_values(lo, hi)
        lv = lv[(lv > lo) & (lv < hi) & (np.abs(lv) > 1e-9 * max(abs(lo), abs(hi)))]
        if lv.size >= 4 or isinstance(norm, mcolors.LogNorm):
            break
    while lv.size > 6:
        lv = lv[::2]
    return lv


def _spread_visible(C: Cells, norm) -> np.ndarray:
    """The cells whose runs (seeds) differ visibly: in their state, or by
    more than SEED_SPREAD of the panel's colour range."""
    with np.errstate(all="ignore"):
        if isinstance(norm, mcolors.LogNorm):
            d = np.log(C.hi / C.lo) / np.log(norm.vmax / norm.vmin)
        else:
            d = (C.hi - C.lo) / (norm.vmax - norm.vmin)
    return (C.n > 1) & (C.mixed | (np.nan_to_num(d) > SEED_SPREAD))


# --------------------------------------------------------------- drawing ---

class _Legend:
    """The states a figure shows, for one legend below it: key -> (handle
    or tuple of handles drawn on each other, label)."""

    def __init__(self):
        self.handles: dict[str, tuple] = {}

    def add(self, key: str, handle, label: str | None = None) -> None:
        self.handles.setdefault(key, (handle, handle.get_label() if label is None else label))


def _state_handles(spec, cols, mask: np.ndarray, legend: _Legend) -> None:
    """Legend entries for the runs of `mask` that did not hold or ended in a
    fault, with their counts (faults: how many before the metrics' window)."""
    counts = state_counts(spec, cols, mask)
    for (st, why), (n, before, also) in sorted(counts.items()):
        if st == "not_held":
            more = [REASON_TEXT.get(a, a) for a in NOT_HELD if a in also and a != why]
            more_text = f"; also {', '.join(more)}" if more else ""
            legend.add(f"n:{why}", mpatches.Patch(
                facecolor=NOT_HELD_FILL, edgecolor="0.35", hatch=HATCH.get(why, ".."), lw=0,
                label=f"not held: {REASON_TEXT.get(why, why)} ({_runs(n)}{more_text})"))
        elif st == "fault":
            pre = f", {before} before the window" if before else ""
            legend.add(f"f:{why}", (
                Line2D([], [], ls="none", marker="s", ms=9, mfc=FAULT_FILL, mec=FAULT_FILL),
                Line2D([], [], ls="none", marker=FAULT_MARKER.get(why, "D"), color="w",
                       mec="w", ms=5, mew=1.0)), f"fault: {why} ({_runs(n)}{pre}; no values)")
        elif st == "error":
            legend.add("error", Line2D([], [], ls="none", marker="$?$", color="k",
                                       label=f"could not run ({_runs(n)})"))


def _runs(n: int) -> str:
    return f"{n} run" if n == 1 else f"{n} runs"


def _draw_states(ax, C: Cells, xe: np.ndarray, ye: np.ndarray) -> None:
    """The cells that are not ok: hatched (not held) or grey with a marker
    (fault), blank with '?' (error)."""
    for i, j in zip(*np.nonzero(C.state != "ok")):
        st = C.state[i, j]
        if not st:
            continue
        box = (xe[j], ye[i]), xe[j + 1] - xe[j], ye[i + 1] - ye[i]
        cx, cy = C.xs[j], C.ys[i]
        if st == "not_held":
            ax.add_patch(mpatches.Rectangle(*box, facecolor=NOT_HELD_FILL, edgecolor="0.35",
                                            hatch=HATCH.get(C.why[i, j], ".."), lw=0))
        elif st == "fault":
            ax.add_patch(mpatches.Rectangle(*box, facecolor=FAULT_FILL, lw=0))
            ax.plot([cx], [cy], ls="none", marker=FAULT_MARKER.get(C.why[i, j], "D"),
                    color="w", mec="w", ms=3.5, mew=0.8)
        else:
            ax.add_patch(mpatches.Rectangle(*box, facecolor="w", lw=0))
            ax.plot([cx], [cy], ls="none", marker="$?$", color="k", ms=4)


def _heatmap_panel(fig, ax, spec, cols, r: dict, metric: str, fv, legend: _Legend) -> None:
    fixed = dict(r.get("fixed", {}))
    if fv is not None:
        fixed[r["facet"]] = fv
    C = cells(spec, cols, r["x"], r["y"], metric, fixed, r.get("reduce", "median"))
    xs, ys = C.xs, C.ys
    xlog, ylog = _is_log_axis(spec, r["x"]), _is_log_axis(spec, r["y"])
    _log_ticks(ax, "x", xs, xlog)
    _log_ticks(ax, "y", ys, ylog)
    xe, ye = _edges(xs, xlog), _edges(ys, ylog)
    norm, cmap, extend = panel_norm(C.value, bool(r.get("log")), r.get("clip"),
                                    float(r.get("scale_floor", 0.0)))
    mesh = ax.pcolormesh(xe, ye, np.ma.masked_invalid(C.value), norm=norm, cmap=cmap,
                         shading="flat")
    _draw_states(ax, C, xe, ye)
    X, Y = np.meshgrid(xs, ys)
    spread = _spread_visible(C, norm)
    if spread.any():
        ax.plot(X[spread], Y[spread], ls="none", marker="o", mfc="none", mec="k", ms=4,
                mew=0.7)
        legend.add("seeds", Line2D([], [], ls="none", marker="o", mfc="none", mec="k",
                                   label=f"the cell's runs (seeds) differ: the "
                                         f"{r.get('reduce', 'median')} shown"))
    levels = _levels(norm)
    if np.isfinite(C.value).sum() >= 4 and xs.size > 1 and ys.size > 1 and levels.size:
        cs = ax.contour(X, Y, np.ma.masked_invalid(C.value), levels=levels, colors="k",
                        linewidths=0.6)
        for t in ax.clabel(cs, fontsize=6, fmt="%.3g", inline=False):
            t.set_bbox({"facecolor": "w", "alpha": 0.6, "pad": 0.3, "lw": 0})
            t.set_gid("smodrive-contour-label")
    ov_name = r.get("overlay")
    if ov_name and metric == r["metric"] and levels.size and (
            r.get("overlay_facet") is None or same(fv, r.get("overlay_facet"))):
        fine = [np.geomspace(v.min(), v.max(), 120) if lg else np.linspace(v.min(), v.max(), 120)
                for v, lg in ((xs, xlog), (ys, ylog))]
        FX, FY = np.meshgrid(*fine)
        FP = OVERLAYS[ov_name](spec, {**r, "metric": metric}, FX, FY)
        if FP is not None:
            ax.contour(FX, FY, FP, levels=levels, colors="m", linewidths=1.0, linestyles="--")
            legend.add("overlay", Line2D([], [], ls="--", color="m",
                                         label="eq. (12)-(13) at the same levels"))
    title = metric if fv is None else f"{r['facet']} = {fv}"
    ax.set_title(title, fontsize=8)
    ax.set_xlabel(spec.axis(r["x"]).label, fontsize=8)
    ax.set_ylabel(spec.axis(r["y"]).label, fontsize=8)
    ax.tick_params(labelsize=7)
    cb = fig.colorbar(mesh, ax=ax, shrink=0.9, pad=0.02, extend=extend)
    cb.set_label(r.get("label", _metric_label(metric)) if metric == r["metric"]
                 else _metric_label(metric), fontsize=7)
    if isinstance(norm, mcolors.LogNorm):
        cb.ax.yaxis.set_major_locator(mt.LogLocator(subs=(1.0, 2.0, 5.0)))
        cb.ax.yaxis.set_major_formatter(mt.FuncFormatter(lambda v, _: f"{v:.2g}"))
        cb.ax.yaxis.set_minor_formatter(mt.NullFormatter())
    cb.ax.tick_params(which="both", labelsize=6)


def _heatmap_row(fig, axs, spec, cols, r: dict, legend: _Legend) -> np.ndarray:
    """One row of panels: per metric (the row's, then `beside`) one panel a
    facet value; returns the runs the row shows."""
    facet_vals = spec.axis(r["facet"]).values if "facet" in r else (None,)
    metrics = [r["metric"], *r.get("beside", [])]
    k = 0
    for metric in metrics:
        for fv in facet_vals:
            _heatmap_panel(fig, axs[k], spec, cols, r, metric, fv, legend)
            k += 1
    return select(cols, dict(r.get("fixed", {})))


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
            med.append(reduce_values(v, r.get("reduce", "median")))
            blo.append(np.percentile(v, lo) if v.size else np.nan)
            bhi.append(np.percentile(v, hi) if v.size else np.nan)
        label = None if hv is None else f"{spec.axis(r['hue']).label} = {hv:g}" if isinstance(
            hv, (int, float)) else f"{r['hue']} = {hv}"
        line, = ax.plot(xs, med, "o-", ms=3, label=label)
        ax.fill_between(xs, blo, bhi, color=line.get_color(), alpha=0.2, lw=0)
    _log_ticks(ax, "x", xs, _is_log_axis(spec, r["x"]))
    if r.get("log"):
        ax.set_yscale("log")
    ax.set_xlabel(xa.label, fontsize=8)
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
    r['over'] that holds (metric r['ok'] >= 0.5, no fault, and the run held
    its operating point) at the point `fixed` of the other axes."""
    sel = select(cols, fixed)
    held = held_column(cols)
    seeds = sorted(set(cols["seed"][sel])) if "seed" in cols and spec.seeds else [None]
    out = []
    for sd in seeds:
        m = sel & (np.asarray(cols["seed"]) == sd) if sd is not None else sel
        ok = (cols[r["ok"]][m].astype(float) >= 0.5) & (cols["status"][m] == "ok") & held[m]
        out.append(lowest_holding(spec.axis(r["over"]).values, ok, cols[r["over"]][m]))
    return np.array(out, float)


def _held_values(cols, metric: str, mask: np.ndarray) -> np.ndarray:
    """`metric` of the runs of `mask` that held their operating point (the
    others' values are left out of a line and its band)."""
    ok = mask & held_column(cols) & (cols["status"] == "ok")
    return cols[metric][ok].astype(float)


def _remove_overlapping_labels(fig) -> int:
    """Contour labels that overlap a label kept before them (or leave their
    axes) are removed; returns how many."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    kept, removed = [], 0
    for ax in fig.axes:
        box = ax.get_window_extent(renderer)
        for t in [t for t in ax.texts if t.get_gid() == "smodrive-contour-label"]:
            bb = t.get_window_extent(renderer).expanded(1.05, 1.1)
            inside = (bb.x0 >= box.x0 and bb.x1 <= box.x1 and bb.y0 >= box.y0
                      and bb.y1 <= box.y1)
            if not inside or any(bb.overlaps(k) for k in kept):
                t.remove()
                removed += 1
            else:
                kept.append(bb)
    return removed


def figure(spec, cols: dict, p: dict):
    """The matplotlib figure of one [[plots]] entry (not saved)."""
    import matplotlib.pyplot as plt  # after plot_all chose the backend

    rows = rows_of(p)
    kind = p["kind"]
    nfacet = len(spec.axis(p["facet"]).values) if "facet" in p else 1
    ncol = nfacet * (1 + max(len(r.get("beside", [])) for r in rows)) if kind == "heatmap" \
        else nfacet
    per = 3.5 if kind == "heatmap" else 3.3
    width = max(6.5, per * ncol + 0.6)
    fig, axs = plt.subplots(len(rows), ncol, figsize=(width, 2.9 * len(rows) + 1.0),
                            squeeze=False, layout="constrained")
    legend = _Legend()
    shown = np.zeros(len(cols["run_id"]), dtype=bool)
    for k, r in enumerate(rows):
        if kind == "heatmap":
            shown |= _heatmap_row(fig, axs[k], spec, cols, r, legend)
            continue
        facets = spec.axis(r["facet"]).values if "facet" in r else (None,)
        for ax, fv in zip(axs[k], facets):
            rr = dict(r)
            if fv is not None:
                rr["fixed"] = {**r.get("fixed", {}), r["facet"]: fv}
            shown |= select(cols, rr.get("fixed", {}))
            if kind == "lines":
                def vals(fx, rr=rr):
                    return _held_values(cols, rr["metric"], select(cols, fx))
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
    _state_handles(spec, cols, shown, legend)
    if legend.handles:
        hs, labels = zip(*legend.handles.values())
        ncol = max(1, min(3, len(labels), int(width // 3.3)))
        wrap = int(width * 14 / ncol) - 8  # characters of 7 pt a column holds
        fig.legend(list(hs), [textwrap.fill(t, wrap) for t in labels],
                   loc="outside lower center", ncol=ncol, fontsize=7, frameon=False)
    fig.suptitle(textwrap.fill(p.get("title", spec.title), int(width * 14)), fontsize=9)
    if kind == "heatmap":
        _remove_overlapping_labels(fig)
    return fig


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
        fig = figure(spec, cols, p)
        path = out / "maps" / f"{p.get('file', f'map{i}')}.png"
        with atomic_path(path) as tmp:  # never a truncated map under its name
            fig.savefig(tmp, format="png", dpi=int(p.get("dpi", 90)))
        plt.close(fig)
        paths.append(path)
    return paths
