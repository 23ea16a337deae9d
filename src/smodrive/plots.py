"""Figures laid out like the papers' (speed, currents, position and
estimation error against time; Bode plots of the analyses)."""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .analysis import tf  # noqa: E402
from .params import RPM, MotorPars  # noqa: E402
from .simulate import Result  # noqa: E402

plt.rcParams.update({"figure.dpi": 110, "font.size": 8, "axes.grid": True, "grid.alpha": 0.3,
                     "figure.constrained_layout.use": True,
                     "lines.linewidth": 0.9})


def _save(fig, fig_dir: Path, name: str) -> Path:
    fig_dir.mkdir(parents=True, exist_ok=True)
    path = fig_dir / f"{name}.png"
    fig.savefig(path, bbox_inches="tight")
    plt.close(fig)
    return path


def fig1_bode(fig_dir: Path, m: MotorPars, T_sp: float, f_meas: float, gain_meas: float) -> Path:
    f = np.logspace(1, np.log10(0.5 / T_sp), 2000)
    z = np.exp(2j * np.pi * f * T_sp)
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(5, 4.5), sharex=True)
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
    return _save(fig, fig_dir, "yang2018_fig1")


def fig2_bode(fig_dir: Path, w_r: float, g_meas: float, ph_meas: float) -> Path:
    w = np.linspace(-6 * w_r, 6 * w_r, 4001)
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(5, 4.5), sharex=True)
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
    return _save(fig, fig_dir, "yang2018_fig2")


def dq_panels(fig_dir: Path, name: str, results: Sequence[Result], labels: Sequence[str],
              title: str) -> Path:
    """Paper Fig. 5/6 layout: per case, speed on top, i_d and i_q below."""
    n = len(results)
    fig, axes = plt.subplots(3, n, figsize=(3.2 * n, 5.5), sharex=True, squeeze=False)
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
    fig.suptitle(title)
    return _save(fig, fig_dir, name)


def sensorless_panels(fig_dir: Path, name: str, results: Sequence[Result], labels: Sequence[str],
                      title: str, t_window: Sequence[tuple[float, float]]) -> Path:
    """Paper Fig. 7-9 layout: speed (true, estimated), currents, position
    (true, estimated) and the estimation errors."""
    n = len(results)
    fig, axes = plt.subplots(4, n, figsize=(4.2 * n, 7), squeeze=False)
    for j, (r, lab, (t0, t1)) in enumerate(zip(results, labels, t_window)):
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
    fig.suptitle(title)
    return _save(fig, fig_dir, name)


# ------------------------------------------------------------- yao2022 ----

def _spectrum(x: np.ndarray, T: float) -> tuple[np.ndarray, np.ndarray]:
    x = x - np.mean(x)
    w = np.hanning(x.size)
    X = np.abs(np.fft.rfft(x * w)) * 2 / np.sum(w)
    return np.fft.rfftfreq(x.size, T), X


def lcl_time_panels(fig_dir: Path, name: str, results: Sequence, labels: Sequence[str],
                    title: str, rows: Sequence[tuple[str, Sequence[tuple[str, str]]]],
                    t_window: tuple[float, float] | None = None) -> Path:
    """Columns per run, rows of (ylabel, [(channel or derived name, legend)])."""
    n = len(results)
    fig, axes = plt.subplots(len(rows), n, figsize=(4.0 * n, 1.9 * len(rows) + 0.6),
                             squeeze=False, sharex="col")
    for j, (r, lab) in enumerate(zip(results, labels)):
        m = r.window(*t_window) if t_window else np.ones(r.t.size, bool)
        t = r.t[m]
        for i, (ylabel, chans) in enumerate(rows):
            ax = axes[i, j]
            for ch, leg in chans:
                y = _derived(r, ch)[m]
                ax.plot(t, y, label=leg)
            if j == 0:
                ax.set_ylabel(ylabel)
            if len(chans) > 1:
                ax.legend(fontsize=6, loc="best")
        axes[0, j].set_title(lab)
        axes[-1, j].set_xlabel("t (s)")
    fig.suptitle(title)
    return _save(fig, fig_dir, name)


def _derived(r, ch: str) -> np.ndarray:
    if ch == "n_rpm":
        return r.n_rpm
    if ch == "n_hat_rpm":
        return r.n_hat_rpm
    if ch == "theta_error":
        return r.theta_error
    if ch == "n_ref_rpm":
        return r["w_M_ref"] / RPM
    if ch == "s_abs":
        return np.abs(r["s_g"] + 1j * r["s_dl"])
    return r[ch]


def ripple_panels(fig_dir: Path, name: str, results: dict, speeds: Sequence[float],
                  title: str) -> Path:
    """Figs. 12-13 layout: estimated speed and its spectrum, chattering s(k),
    for the baseline (61)-(63) and the proposed reaching law at each speed."""
    fig, axes = plt.subplots(3, len(speeds), figsize=(4.2 * len(speeds), 7), squeeze=False)
    for j, n in enumerate(speeds):
        for law, col in (("tde17", "C3"), ("proposed", "C0")):
            r = results[(law, n)]
            m = r.window(0.1, r.scenario.duration)
            t = r.t[m]
            lab = "baseline (61)" if law == "tde17" else "proposed (33)"
            axes[0, j].plot(t, r.n_hat_rpm[m], color=col, label=lab, lw=0.6)
            f, X = _spectrum(r.n_hat_rpm[m], r.scenario.T_sp * r.scenario.log_stride)
            axes[1, j].semilogy(f, X + 1e-6, color=col, lw=0.6)
            axes[2, j].plot(t, np.abs(r["s_g"][m] + 1j * r["s_dl"][m]), color=col, lw=0.5)
        axes[0, j].set_title(f"{n / 1e3:g} kr/min")
        axes[1, j].set_xlim(0, 10e3)
        axes[1, j].set_xlabel("f (Hz)")
        axes[2, j].set_xlabel("t (s)")
    axes[0, 0].set_ylabel("estimated speed (r/min)")
    axes[1, 0].set_ylabel("speed ripple spectrum (r/min)")
    axes[2, 0].set_ylabel("|s(k)| (A)")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(title)
    return _save(fig, fig_dir, name)


def waveform_spectrum(fig_dir: Path, name: str, results: Sequence, labels: Sequence[str],
                      channel: str, ylabel: str, title: str, span: float = 0.004,
                      f_max: float = 10e3) -> Path:
    """Figs. 17-18 layout: a phase waveform over a few periods and its spectrum."""
    n = len(results)
    fig, axes = plt.subplots(2, n, figsize=(4.2 * n, 5), squeeze=False)
    for j, (r, lab) in enumerate(zip(results, labels)):
        t1 = r.scenario.duration
        m = r.window(t1 - span, t1)
        axes[0, j].plot(r.t[m] * 1e3, r[channel][m])
        axes[0, j].set_title(lab)
        axes[0, j].set_xlabel("t (ms)")
        mm = r.window(0.1, t1)
        f, X = _spectrum(r[channel][mm], r.scenario.T_sp * r.scenario.log_stride)
        axes[1, j].semilogy(f, X + 1e-9)
        axes[1, j].set_xlim(0, f_max)
        axes[1, j].set_xlabel("f (Hz)")
    axes[0, 0].set_ylabel(ylabel)
    axes[1, 0].set_ylabel("amplitude")
    fig.suptitle(title)
    return _save(fig, fig_dir, name)


def disturbance_panels(fig_dir: Path, name: str, t: np.ndarray, d: np.ndarray,
                       e17: np.ndarray, e18: np.ndarray, T: float, title: str) -> Path:
    """Fig. 4 layout: d(k) and the compensation errors of [17], [18], with spectra."""
    fig, axes = plt.subplots(2, 3, figsize=(11, 5))
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
    fig.suptitle(title)
    return _save(fig, fig_dir, name)
