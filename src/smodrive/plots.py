"""Figures laid out like the papers' (speed, currents, position and
estimation error against time; Bode plots of the analyses).

Every drawing function takes the Axes to draw on (``ax``: one Axes, or for a
multi-panel layout any sequence or array of Axes, row-major, of the size the
function documents) and returns them, as a NumPy array shaped like the
layout. With ``ax=None`` it makes its own :class:`matplotlib.figure.Figure`
(object-oriented API: no pyplot state, the user's backend untouched) with
the paper's layout. :func:`save` writes the figure of the returned Axes as
``NAME.png``:

>>> axes = time_panels([r], ["run"], [("speed (r/min)", [("n_rpm", "true")])])  # doctest: +SKIP
>>> save(axes, Path("figures"), "my_run")  # doctest: +SKIP

Nothing here changes ``matplotlib.rcParams``: the house style :data:`STYLE`
is applied inside each function with :func:`style` (a
:func:`matplotlib.rc_context`), so it shapes what the function creates
(figure size, dpi, layout, grid, fonts, line widths) and is gone on return.
On Axes the caller made, only the artists drawn here follow the style (the
grid and layout are the caller's).
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import shutil
import sys
from pathlib import Path
from typing import Callable, Iterator, Sequence

import matplotlib
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from .analysis import tf
from .claims import load_specs
from .engine import CHANNELS, Result
from .model import RPM, MotorPars

#: At most this many points a curve (a longer log is drawn from every k-th row).
MAX_POINTS = 200_000

#: The house style, applied in a context by every drawing function.
STYLE: dict[str, object] = {"figure.dpi": 110, "font.size": 8, "axes.grid": True,
                            "grid.alpha": 0.3, "figure.constrained_layout.use": True,
                            "lines.linewidth": 0.9}


@contextlib.contextmanager
def style(**overrides) -> Iterator[None]:
    """:data:`STYLE` (updated by `overrides`, rcParams names with dots
    written as in ``style(**{"font.size": 10})``) in a
    :func:`matplotlib.rc_context`; the previous rcParams return on exit."""
    with matplotlib.rc_context({**STYLE, **overrides}):
        yield


def _styled(fn: Callable) -> Callable:
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        with style():
            return fn(*args, **kwargs)

    return wrapper


def _layout(ax, nrows: int, ncols: int, figsize: tuple[float, float], **subplots_kw
            ) -> np.ndarray:
    """The (nrows, ncols) array of Axes to draw on: `ax` reshaped (row-major),
    or, for ``ax=None``, the Axes of a new Figure (call inside :func:`style`,
    which the new figure's dpi and layout engine are read from)."""
    if ax is None:
        fig = Figure(figsize=figsize)
        return fig.subplots(nrows, ncols, squeeze=False, **subplots_kw)
    items = [ax] if isinstance(ax, Axes) else list(np.ravel(np.asarray(ax, dtype=object)))
    a = np.empty(len(items), dtype=object)
    a[:] = items
    if a.size != nrows * ncols or not all(isinstance(x, Axes) for x in a):
        raise ValueError(f"ax: expected {nrows * ncols} Axes ({nrows} x {ncols}), got "
                         f"{a.size} object(s)")
    return a.reshape(nrows, ncols)


def _suptitle(axes: np.ndarray, title: str | None) -> None:
    if title is not None:
        np.ravel(axes)[0].figure.suptitle(title)


def save(ax, fig_dir: Path, name: str) -> Path:
    """Write the figure of `ax` (a Figure, an Axes or an array of Axes of one
    figure) to ``fig_dir/name.png`` in :data:`STYLE`; returns the path. A
    paper figure (`name` a key of :data:`PAPER_MARKS`, `ax` its layout's
    array of Axes) gets the paper's values drawn on it first
    (:func:`draw_paper_marks`)."""
    fig = ax if isinstance(ax, Figure) else np.ravel(np.asarray(ax, dtype=object))[0].figure
    if name in PAPER_MARKS and not isinstance(ax, Figure):
        with style():
            draw_paper_marks(ax, name)
    fig_dir = Path(fig_dir)
    fig_dir.mkdir(parents=True, exist_ok=True)
    path = fig_dir / f"{name}.png"
    with style():
        fig.savefig(path, bbox_inches="tight")
    return path


# ------------------------------------------------------------- yang2018 ----

@_styled
def fig1_bode(m: MotorPars, T_sp: float, f_meas: float, gain_meas: float,
              ax=None) -> np.ndarray:
    """Fig. 1: |H(z)| and arg H(z) of eq. (14) for five inductance errors and
    the measured point. `ax`: 2 Axes (magnitude, phase); returns them."""
    a1, a2 = _layout(ax, 2, 1, (5, 4.5), sharex=True)[:, 0]
    f = np.logspace(1, np.log10(0.5 / T_sp), 2000)
    z = np.exp(2j * np.pi * f * T_sp)
    for k in (0.5, 0.75, 1.0, 1.5, 2.0):
        H = tf.H_dbpc(m.L_s, k * m.L_s, m.R_s, T_sp)
        h = H(z)
        a1.semilogx(f, 20 * np.log10(np.abs(h)), label=rf"$\hat L_s={k:g}L_s$")
        a2.semilogx(f, np.degrees(np.unwrap(np.angle(h))))
    a1.plot([f_meas], [20 * np.log10(gain_meas)], "kx", ms=7, label="C controller + plant")
    a1.set_ylabel("magnitude (dB)")
    a2.set_ylabel("phase (deg)")
    a2.set_xlabel("frequency (Hz)")
    a1.legend(fontsize=7)
    a1.set_title("Fig. 1: H(z) of eq. (14), 10 kHz")
    return np.array([a1, a2], dtype=object)


@_styled
def fig2_bode(w_r: float, g_meas: float, ph_meas: float, ax=None) -> np.ndarray:
    """Fig. 2: G(j w) of eq. (33) over both sequences for four cut-offs and
    the simulated point. `ax`: 2 Axes (magnitude, phase); returns them."""
    a1, a2 = _layout(ax, 2, 1, (5, 4.5), sharex=True)[:, 0]
    w = np.linspace(-6 * w_r, 6 * w_r, 4001)
    for k in (0.1, 0.2, 0.3, 0.4):
        G = tf.G_smdo(k * w_r, w_r)(1j * w)
        a1.plot(w / (2 * np.pi), 20 * np.log10(np.abs(G)), label=rf"$\omega_c={k:g}\omega_r$")
        a2.plot(w / (2 * np.pi), np.degrees(np.angle(G)))
    a1.plot([w_r / (2 * np.pi)], [20 * np.log10(g_meas)], "kx", ms=7,
            label=r"simulated, $\omega_c$=1500 rad/s")
    a2.plot([w_r / (2 * np.pi)], [np.degrees(ph_meas)], "kx", ms=7)
    a1.set_ylabel("magnitude (dB)")
    a2.set_ylabel("phase (deg)")
    a2.set_xlabel("frequency (Hz), negative = negative sequence")
    a1.legend(fontsize=7)
    a1.set_title(r"Fig. 2: G(s) of eq. (33), $\omega_r$ at 1500 r/min")
    return np.array([a1, a2], dtype=object)


@_styled
def dq_panels(results: Sequence[Result], labels: Sequence[str], title: str | None = None,
              ax=None) -> np.ndarray:
    """Paper Fig. 5/6 layout: per case (column), speed on top, i_d and i_q
    below, each with its reference. `ax`: 3 x len(results) Axes; returns
    them as a (3, len(results)) array."""
    n = len(results)
    axes = _layout(ax, 3, n, (3.2 * n, 5.5), sharex=True)
    for j, (r, lab) in enumerate(zip(results, labels)):
        t = r.t
        axes[0, j].plot(t, r["w_M_ref"] / RPM, "k--", label="reference")
        axes[0, j].plot(t, r["w_M"] / RPM, label="speed")
        axes[0, j].set_title(lab)
        axes[1, j].plot(t, r["i_d_ref"], "k--")
        axes[1, j].plot(t, r["i_d"], color="C1")
        axes[2, j].plot(t, r["i_q_ref"], "k--")
        axes[2, j].plot(t, r["i_q"], color="C2")
        axes[2, j].set_xlabel("t (s)")
    axes[0, 0].set_ylabel("speed (r/min)")
    axes[1, 0].set_ylabel("$i_d$ (A)")
    axes[2, 0].set_ylabel("$i_q$ (A)")
    axes[0, 0].legend(fontsize=7)
    _suptitle(axes, title)
    return axes


@_styled
def sensorless_panels(results: Sequence[Result], labels: Sequence[str],
                      title: str | None = None,
                      t_window: Sequence[tuple[float, float]] | None = None,
                      ax=None) -> np.ndarray:
    """Paper Fig. 7-9 layout, per run (column): speed (reference, true,
    estimated), currents, position (true, estimated) and the estimation
    errors, over `t_window[j]` (default the whole run). `ax`: 4 x
    len(results) Axes; returns them as a (4, len(results)) array."""
    n = len(results)
    axes = _layout(ax, 4, n, (4.2 * n, 7))
    windows = t_window if t_window is not None else [(0.0, np.inf)] * n
    for j, (r, lab, (t0, t1)) in enumerate(zip(results, labels, windows)):
        m = r.window(t0, t1)
        t = r.t[m]
        n_p = r.scenario.motor.n_p
        a = axes[:, j]
        a[0].plot(t, r["w_M_ref"][m] / RPM, "k--", label="reference")
        a[0].plot(t, r["w_M"][m] / RPM, label="actual")
        a[0].plot(t, r["w_hat"][m] / n_p / RPM, alpha=0.8, label="estimated")
        a[0].set_ylabel("speed (r/min)")
        a[0].set_title(lab)
        a[0].legend(fontsize=7)
        a[1].plot(t, r["i_q"][m], color="C2", label="$i_q$")
        a[1].plot(t, r["i_d"][m], color="C1", label="$i_d$")
        a[1].set_ylabel("current (A)")
        a[1].legend(fontsize=7)
        a[2].plot(t, np.mod(r["theta_r"][m], 2 * np.pi), label=r"$\theta_r$")
        a[2].plot(t, np.mod(r["theta_hat"][m], 2 * np.pi), "--", label=r"$\hat\theta_r$")
        a[2].set_ylabel("position (rad)")
        a[2].legend(fontsize=7)
        a[3].plot(t, np.degrees(r.theta_error[m]), color="C3", label=r"$\Delta\theta_r$ (deg)")
        a[3].plot(t, (r["w_M"][m] - r["w_hat"][m] / n_p) / RPM, color="C4", alpha=0.7,
                  label=r"$\Delta\omega_r$ (r/min)")
        a[3].set_ylabel("estimation error")
        a[3].set_xlabel("t (s)")
        a[3].legend(fontsize=7)
    _suptitle(axes, title)
    return axes


# ------------------------------------------------- time panels, any plant ----

#: Channels computed from the logged ones, usable wherever :func:`channel`
#: reads one (both plants log the same channels): name -> (unit, meaning, f).
DERIVED: dict[str, tuple[str, str, Callable[[Result], np.ndarray]]] = {
    "n_ref_rpm": ("r/min", "mechanical speed reference", lambda r: r["w_M_ref"] / RPM),
    "n_rpm": ("r/min", "true mechanical speed", lambda r: r.n_rpm),
    "n_hat_rpm": ("r/min", "mechanical speed the controller uses", lambda r: r.n_hat_rpm),
    "n_error_rpm": ("r/min", "speed-estimation error n - n_hat",
                    lambda r: r.n_rpm - r.n_hat_rpm),
    "theta_error": ("rad", "angle error theta_r - theta_hat wrapped to [-pi, pi)",
                    lambda r: r.theta_error),
    "theta_error_deg": ("deg", "angle error in degrees", lambda r: np.degrees(r.theta_error)),
    "theta_r_mod": ("rad", "true electrical angle in [0, 2 pi)",
                    lambda r: np.mod(r["theta_r"], 2 * np.pi)),
    "theta_hat_mod": ("rad", "controller's angle in [0, 2 pi)",
                      lambda r: np.mod(r["theta_hat"], 2 * np.pi)),
    "i_abs": ("A", "motor current magnitude |i_d + j i_q|",
              lambda r: np.hypot(r["i_d"], r["i_q"])),
    "i1_abs": ("A", "inverter-side current magnitude |i1_alpha + j i1_beta|",
               lambda r: np.hypot(r["i1_alpha"], r["i1_beta"])),
    "uc_abs": ("V", "filter-capacitor voltage magnitude (0 without filter)",
               lambda r: np.hypot(r["uc_alpha"], r["uc_beta"])),
    "s_abs": ("A", "LCL sliding-mode observer: |s(k)| (0 for the other sources)",
              lambda r: np.hypot(r["s_g"], r["s_dl"])),
    "u_d_hat_abs": ("V", "SMDO disturbance estimate magnitude (0 for the other sources)",
                    lambda r: np.hypot(r["u_d_hat_alpha"], r["u_d_hat_beta"])),
}


def channel(r: Result, name: str) -> np.ndarray:
    """A logged channel of `r` (:data:`smodrive.engine.CHANNELS`) or a
    derived one (:data:`DERIVED`), by name."""
    if name in DERIVED:
        return DERIVED[name][2](r)
    try:
        return r[name]
    except ValueError:
        raise KeyError(f"unknown channel {name!r}: neither logged (smodrive.engine.CHANNELS) "
                       f"nor derived ({', '.join(DERIVED)})") from None


def thinned(r: Result, t_window: tuple[float, float] | None = None,
            max_points: int = MAX_POINTS) -> Result:
    """The rows of `r` with t0 <= t < t1 (default all), every k-th of them
    for at most `max_points`: a view of the log (no copy), for drawing."""
    i0, i1 = (0, r.data.shape[0]) if t_window is None else \
        np.searchsorted(r.t, t_window, side="left")
    k = max(1, -(-(int(i1) - int(i0)) // max(1, int(max_points))))
    return dataclasses.replace(r, data=r.data[i0:i1:k])


@_styled
def time_panels(results: Sequence[Result], labels: Sequence[str], title: str | None,
                rows: Sequence[tuple[str, Sequence[tuple[str, str]]]],
                t_window: tuple[float, float] | None = None, ax=None,
                max_points: int = MAX_POINTS, robust: bool = True) -> np.ndarray:
    """Columns per run, rows of ``(ylabel, [(channel, legend), ...])``, one
    curve per channel (logged or :data:`DERIVED`), over `t_window` (default
    the whole run), each of at most `max_points` points (every k-th row,
    :func:`thinned`); either plant. With `robust` each panel's y axis is
    scaled to the bulk of its samples when a few (a start transient) would
    flatten the rest (:func:`robust_ylim`). `ax`: len(rows) x len(results)
    Axes; returns them as a (len(rows), len(results)) array."""
    n = len(results)
    axes = _layout(ax, len(rows), n, (4.0 * n, 1.9 * len(rows) + 0.6), sharex="col")
    for j, (r, lab) in enumerate(zip(results, labels)):
        r = thinned(r, t_window, max_points)
        t = r.t
        for i, (ylabel, chans) in enumerate(rows):
            a = axes[i, j]
            ys = []
            for ch, leg in chans:
                ys.append(channel(r, ch))
                a.plot(t, ys[-1], label=leg)
            if robust:
                robust_ylim(a, t, ys)
            if j == 0:
                a.set_ylabel(ylabel)
            if len(chans) > 1:
                a.legend(fontsize=6, loc="best")
        axes[0, j].set_title(lab)
        axes[-1, j].set_xlabel("t (s)")
    _suptitle(axes, title)
    return axes


#: robust_ylim: the share of samples that may lie off scale at each end
ROBUST_TAIL = 0.005
#: ... and only when the full range is at least this many times the rest's
ROBUST_RATIO = 5.0


def robust_ylim(ax: Axes, t: np.ndarray, ys: Sequence[np.ndarray],
                tail: float = ROBUST_TAIL, ratio: float = ROBUST_RATIO) -> bool:
    """Scale the y axis of `ax` to the bulk of the curves `ys` (sampled at
    `t`): when the full range of the samples is more than `ratio` times the
    range between their `tail` and 1 - `tail` quantiles (a start transient
    of a few samples beside a steady error of milliradians), the axis shows
    that range with a margin of a quarter of it, and a note names the peak
    left off scale and when it occurs. Returns whether it rescaled."""
    data = [np.asarray(y, dtype=float) for y in ys if np.size(y)]
    if not data:
        return False
    v = np.concatenate([y.ravel() for y in data])
    v = v[np.isfinite(v)]
    if v.size < 20:
        return False
    lo, hi = np.quantile(v, [tail, 1.0 - tail])
    span = hi - lo
    full = float(v.max() - v.min())
    if not (span > 0 and full > ratio * span):
        return False
    y0, y1 = lo - 0.25 * span, hi + 0.25 * span
    ax.set_ylim(y0, y1)
    # the largest excursion off scale, with its time
    best, when, peak = 0.0, 0.0, 0.0
    for y in data:
        off = np.where(y > y1, y - y1, np.where(y < y0, y0 - y, 0.0))
        off = np.where(np.isfinite(off), off, 0.0)
        k = int(np.argmax(off)) if off.size else 0
        if off.size and off[k] > best:
            best, when, peak = float(off[k]), float(t[min(k, len(t) - 1)]), float(y[k])
    if best > 0:
        ax.annotate(f"off scale: {peak:.3g} at t = {when:.3g} s", xy=(0.01, 0.97),
                    xycoords="axes fraction", va="top", ha="left", fontsize=6, color="0.3")
    return True


# ----------------------------------------------------- the paper's values ----

@dataclasses.dataclass(frozen=True)
class PaperMark:
    """A value the paper prints, drawn on the panel (`row`, `col`) of a
    figure's layout (`col` None: every column): the `claim`'s paper value
    from the paper's claims data, as horizontal lines at ``center +- v``
    (`kind` "pm") or at ``center + v`` ("level"), `v` mapped by `scale`
    (e.g. a gain to dB)."""

    row: int
    col: int | None
    claim: str
    label: str  # "{v}" is the drawn value
    kind: str = "pm"
    center: float = 0.0
    color: str = "k"
    scale: Callable[[float], float] | None = None


def _tags(fmt: str, speeds=(30e3, 60e3, 100e3)) -> list[tuple[int, float, str]]:
    return [(j, n, fmt.format(tag=f"{n / 1e3:g}k")) for j, n in enumerate(speeds)]


#: The paper's values drawn on each reproduced figure, by figure name (the
#: name passed to :func:`save`): the numbers come from the claims data
#: (``scenarios/<paper>.claims.toml``), the layout is the figure's.
PAPER_MARKS: dict[str, list[PaperMark]] = {
    "yao2022_fig10": [PaperMark(1, j, cid, "paper, by (60): +-{v:g} rad")
                      for j, _, cid in _tags("yao2022.fig10.pos_error_vs_paper_rad_{tag}")],
    "yao2022_fig12_13": [
        PaperMark(0, j, cid, f"Table V, {lab}: +-{{v:g}} r/min", center=n, color=col)
        for law, lab, col in (("baseline", "baseline", "C3"), ("proposed", "proposed", "C0"))
        for j, n, cid in _tags(f"yao2022.table5.ripple_rpm_{law}_{{tag}}")],
    "yao2022_fig14_16": [PaperMark(1, None, "yao2022.fig14.pos_error_peak_rad",
                                   "paper (Fig. 16): peak +-{v:g} rad")],
    "yao2022_fig19_21": [PaperMark(1, None, "yao2022.fig19.pos_error_peak_rad",
                                   "paper (Fig. 20): peak +-{v:g} rad")],
    "yang2018_fig2": [
        PaperMark(1, 0, "yang2018.fig2.phase_at_wr_deg", "paper, eq. (33): {v:g} deg at w_r",
                  kind="level")],
}


@functools.lru_cache(maxsize=4)
def _paper_specs(paper: str):
    return load_specs(Path(__file__).resolve().parent / "scenarios" / f"{paper}.claims.toml")


def paper_value(claim_id: str) -> float | None:
    """The paper's value of a claim (None if the data gives none).

    >>> paper_value("yao2022.fig10.pos_error_vs_paper_rad_30k")  # Sec. VII-A, rad
    0.018
    """
    spec = _paper_specs(claim_id.split(".")[0]).spec_of(claim_id)
    if spec is None:
        return None
    v = spec.paper
    return v.get(claim_id) if isinstance(v, dict) else v


def draw_paper_marks(ax, name: str) -> int:
    """Draw the paper's values of figure `name` (:data:`PAPER_MARKS`) on its
    Axes `ax` (the layout's array). A value within three times the panel's
    range widens the axis to show it; one further off is stated in the
    panel instead (the axis stays scaled to the reproduced curves). Returns
    the number of values drawn or stated."""
    axes = np.asarray(ax, dtype=object)
    axes = axes.reshape(-1, 1) if axes.ndim == 1 else axes.reshape(axes.shape[0], -1)
    done = 0
    for m in PAPER_MARKS.get(name, []):
        v = paper_value(m.claim)
        if v is None:
            continue
        shown = m.scale(v) if m.scale else v
        cols = range(axes.shape[1]) if m.col is None else [m.col]
        for j in cols:
            a = axes[m.row, j]
            y0, y1 = a.get_ylim()
            ys = [m.center + shown] if m.kind == "level" else [m.center - shown,
                                                               m.center + shown]
            half = max(y1 - y0, 1e-300)
            label = m.label.format(v=shown)
            if all(y0 - 3 * half <= y <= y1 + 3 * half for y in ys):
                for k, y in enumerate(ys):
                    a.axhline(y, color=m.color, ls=":", lw=1.1,
                              label=label if k == 0 else None)
                a.set_ylim(min(y0, *ys) - 0.05 * half if min(ys) < y0 else y0,
                           max(y1, *ys) + 0.05 * half if max(ys) > y1 else y1)
                a.legend(fontsize=6, loc="best")
            else:
                n_notes = sum(1 for tx in a.texts if tx.get_gid() == "paper-note")
                a.text(0.99, 0.03 + 0.08 * n_notes, label + " (off this scale)",
                       transform=a.transAxes, ha="right", va="bottom", fontsize=6,
                       color=m.color, gid="paper-note")
            done += 1
    return done


# ------------------------------------------------------------- yao2022 ----

def _spectrum(x: np.ndarray, T: float) -> tuple[np.ndarray, np.ndarray]:
    x = x - np.mean(x)
    w = np.hanning(x.size)
    X = np.abs(np.fft.rfft(x * w)) * 2 / np.sum(w)
    return np.fft.rfftfreq(x.size, T), X


@_styled
def pll_bode(f: np.ndarray, responses: Sequence[tuple[str, np.ndarray]], title: str,
             ax=None) -> np.ndarray:
    """Fig. 7 of yao2022: magnitude and phase of open-loop responses `h`
    sampled at frequencies `f` (Hz), one curve per ``(label, h)``. `ax`: 2
    Axes (magnitude, phase); returns them."""
    a1, a2 = _layout(ax, 2, 1, (5, 4.5), sharex=True)[:, 0]
    for label, h in responses:
        a1.semilogx(f, 20 * np.log10(np.abs(h)), label=label)
        a2.semilogx(f, np.degrees(np.angle(h)))
    a1.set_ylabel("|G_PLL| (dB)")
    a2.set_ylabel("phase (deg)")
    a2.set_xlabel("f (Hz)")
    a1.legend(fontsize=7)
    a1.set_title(title)
    return np.array([a1, a2], dtype=object)


@_styled
def ripple_panels(results: dict, speeds: Sequence[float], title: str | None = None,
                  ax=None) -> np.ndarray:
    """Figs. 12-13 layout: estimated speed and its spectrum, chattering s(k),
    for the baseline (61)-(63) and the proposed reaching law at each speed
    (`results[(law, speed)]`, law "tde17" or "proposed"). `ax`: 3 x
    len(speeds) Axes; returns them as a (3, len(speeds)) array."""
    axes = _layout(ax, 3, len(speeds), (4.2 * len(speeds), 7))
    for j, n in enumerate(speeds):
        for law, col in (("tde17", "C3"), ("proposed", "C0")):
            r = results[(law, n)]
            m = r.window(0.1, r.scenario.duration)
            t = r.t[m]
            lab = "baseline (61)" if law == "tde17" else "proposed (33)"
            axes[0, j].plot(t, r.n_hat_rpm[m], color=col, label=lab, lw=0.6)
            f, X = _spectrum(r.n_hat_rpm[m], r.scenario.T_sp * r.log_stride)
            axes[1, j].semilogy(f, X + 1e-6, color=col, lw=0.6)
            axes[2, j].plot(t, channel(r, "s_abs")[m], color=col, lw=0.5)
        axes[0, j].set_title(f"{n / 1e3:g} kr/min")
        axes[1, j].set_xlim(0, 10e3)
        axes[1, j].set_xlabel("f (Hz)")
        axes[2, j].set_xlabel("t (s)")
    axes[0, 0].set_ylabel("estimated speed (r/min)")
    axes[1, 0].set_ylabel("speed ripple spectrum (r/min)")
    axes[2, 0].set_ylabel("|s(k)| (A)")
    axes[0, 0].legend(fontsize=7)
    _suptitle(axes, title)
    return axes


@_styled
def waveform_spectrum(results: Sequence[Result], labels: Sequence[str], channel_name: str,
                      ylabel: str, title: str | None = None, span: float = 0.004,
                      f_max: float = 10e3, ax=None) -> np.ndarray:
    """Figs. 17-18 layout: per run (column), the last `span` seconds of
    `channel_name` and its spectrum from 0.1 s on. `ax`: 2 x len(results)
    Axes; returns them as a (2, len(results)) array."""
    n = len(results)
    axes = _layout(ax, 2, n, (4.2 * n, 5))
    for j, (r, lab) in enumerate(zip(results, labels)):
        t1 = r.scenario.duration
        x = channel(r, channel_name)
        m = r.window(t1 - span, t1)
        axes[0, j].plot(r.t[m] * 1e3, x[m])
        axes[0, j].set_title(lab)
        axes[0, j].set_xlabel("t (ms)")
        mm = r.window(0.1, t1)
        f, X = _spectrum(x[mm], r.scenario.T_sp * r.log_stride)
        axes[1, j].semilogy(f, X + 1e-9)
        axes[1, j].set_xlim(0, f_max)
        axes[1, j].set_xlabel("f (Hz)")
    axes[0, 0].set_ylabel(ylabel)
    axes[1, 0].set_ylabel("amplitude")
    _suptitle(axes, title)
    return axes


@_styled
def disturbance_panels(t: np.ndarray, d: np.ndarray, e17: np.ndarray, e18: np.ndarray,
                       T: float, title: str | None = None, ax=None) -> np.ndarray:
    """Fig. 4 layout: d(k) and the compensation errors of [17], [18] (gamma
    and delta against t), with the spectra of their magnitudes below.
    `ax`: 2 x 3 Axes; returns them as a (2, 3) array."""
    axes = _layout(ax, 2, 3, (11, 5))
    for j, (x, lab) in enumerate(((d, "d(k)"), (e17, "error [17], eq. (31)"),
                                  (e18, "error [18], eq. (32)"))):
        axes[0, j].plot(t[: x.size] * 1e3, x.real, lw=0.6, label="gamma")
        axes[0, j].plot(t[: x.size] * 1e3, x.imag, lw=0.6, label="delta")
        axes[0, j].set_title(lab)
        axes[0, j].set_xlabel("t (ms)")
        f, X = _spectrum(np.abs(x), T)
        axes[1, j].plot(f, X)
        axes[1, j].set_xlim(0, 10e3)
        axes[1, j].set_xlabel("f (Hz)")
    axes[0, 0].legend(fontsize=7)
    _suptitle(axes, title)
    return axes


# ------------------------------------------------- processor in the loop ----

@_styled
def pil_panels(r, ax=None) -> np.ndarray:
    """A processor-in-the-loop run (:class:`smodrive.firmware.PilResult`):
    angle estimate, q current and duty-relevant voltage of the host-only run
    and of the Cortex-M4F controller, and their difference. `ax`: 3 x 2
    Axes; returns them."""
    axes = _layout(ax, 3, 2, (8.0, 6.0), sharex=True)
    t = r.log_host[:, CHANNELS.index("t")]
    rows = [("theta_hat", "angle estimate (rad)"), ("i_q", "i_q (A)"),
            ("u_cmd_alpha", "u_alpha command (V)")]
    for i, (ch, label) in enumerate(rows):
        j = CHANNELS.index(ch)
        axes[i, 0].plot(t, r.log_host[:, j], label="host")
        axes[i, 0].plot(t, r.log_pil[:, j], "--", label="Cortex-M4F (QEMU)")
        axes[i, 0].set_ylabel(label)
        d = r.log_pil[:, j] - r.log_host[:, j]
        if ch == "theta_hat":
            d = np.angle(np.exp(1j * d))
        axes[i, 1].plot(t, d)
        axes[i, 1].set_ylabel("M4F - host")
    axes[0, 0].legend(fontsize=6)
    axes[-1, 0].set_xlabel("t (s)")
    axes[-1, 1].set_xlabel("t (s)")
    _suptitle(axes, f"{r.scenario}: processor in the loop ({r.math}; "
                    f"{'identical' if r.identical else 'max duty diff %.3g' % r.max_duty_diff})")
    return axes


#: matplotlib backends that draw no window: plt.show() would show nothing
_HEADLESS = ("agg", "cairo", "pdf", "pgf", "ps", "svg", "template")


def show(fig: Figure | None = None, name: str = "figure",
         files: Sequence[Path] = ()) -> None:
    """An example script's last line: ``plt.show()``, except without a
    display (a non-interactive backend: MPLBACKEND=Agg, or no display to open
    a window on), where it would show nothing: then `fig` is kept as
    ``name.png`` in the current folder (and `files`, figures already written,
    are copied into the folder ``name``), the path printed on stderr. The
    documentation's gallery (sphinx-gallery) collects the figures itself."""
    import matplotlib.pyplot as plt

    if "sphinx_gallery" in sys.modules or plt.get_backend().lower() not in _HEADLESS:
        plt.show()
        return
    kept = []
    if fig is not None:
        png = Path(f"{name}.png").resolve()
        fig.savefig(png)
        kept.append(str(png))
    if files:
        keep = Path(name).resolve()
        keep.mkdir(exist_ok=True)
        for f in files:
            shutil.copy2(f, keep / Path(f).name)
        kept.append(f"{len(files)} figures in {keep}")
    plt.close("all")
    print(f"no display: {', '.join(kept) or 'no figure'}", file=sys.stderr)
