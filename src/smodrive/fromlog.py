"""R_s, L_s and psi_r from a log of a running drive (issue 23,
``smodrive identify --from-log``), for users with hardware.

The log (CSV with a header line, or Parquet), one row per sampling instant
t_k, uniformly spaced:

=========================  ====  =============================================
column                     unit  meaning
=========================  ====  =============================================
``t``                      s     the sampling instant t_k
``i_a``, ``i_b``           A     phase currents sampled at t_k
``i_c``                    A     optional (else -i_a - i_b)
``d_a``, ``d_b``, ``d_c``  -     duties in [0, 1] applied during [t_k, t_k+1)
``u_dc``                   V     DC-link voltage (a column, or ``--u-dc``)
``u_a``, ``u_b``, ``u_c``  V     instead of the duties: phase voltages, the
                                 mean over [t_k, t_k+1), any common reference
``theta``                  rad   optional: the rotor's electrical angle at t_k
                                 (an encoder); else it is estimated
=========================  ====  =============================================

The method (yang2018 eq. (1), SPMSM, in the stationary frame over each
sampling interval, the currents averaged over it and the EMF taken at its
middle, as the online tracker does: :mod:`smodrive`'s ``smd_rls.h``)::

    u = R_s i_m + L_s (i(k+1) - i(k)) / T + j w psi_r e^{j theta_m} + u_0 phi

with ``phi = (2/3) sum_x sgn(i_x) a^x`` the direction of the inverter's
drop (dead time and switches, ``u_0`` per leg, fitted too: a drive's duties
are not its voltages). Turned into the rotor frame it is linear in
(R_s, L_s, psi_r, u_0) and solved by least squares. Without ``theta`` the
rotor frame is the EMF's: starting from the voltage's own angle at speed, the
fit and the angle of its EMF ``u - R_s i_m - L_s di/dt - u_0 phi`` (smoothed
in its own frame) are iterated to a fixed point; only samples whose EMF is
at least a fifth of the log's largest take part (the angle of a small EMF
is noise). The intervals are 95 % percentiles of a block bootstrap (the
fit repeated on 200 resamplings of 40 blocks of the log), so correlated
residuals widen them as they should.

What a log must contain to tell the four apart: load changes (R_s i
against u_0's constant magnitude) and speed changes (w psi_r against R_s
i_q); a log at one operating point gives wide intervals, and the result
says so.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.signal import butter, filtfilt

from .model import ParameterError

#: the columns a log may have (the docstring's table)
COLUMNS = ("t", "i_a", "i_b", "i_c", "d_a", "d_b", "d_c", "u_dc", "u_a", "u_b", "u_c", "theta")
#: samples take part where the EMF is at least this fraction of the log's largest
EMF_MIN = 0.2
#: the block bootstrap: blocks, resamplings
BLOCKS, RESAMPLES = 40, 200
#: the angle's smoothing: a zero-phase low-pass of the EMF in its own frame, Hz
SMOOTH_HZ = 50.0
#: the fit's common low-pass of currents, voltages and the drop's direction, Hz (at most a
#: tenth of the sampling rate)
FIT_HZ = 1000.0
ITERATIONS = 30
#: the drop's fade near zero current: bands tried, fractions of the log's largest current
BANDS = (0.0, 0.005, 0.01, 0.02, 0.04)
#: bands whose residual is within this factor of the best one's widen the intervals
BAND_SLACK = 1.05


@dataclass(frozen=True)
class DriveLog:
    """A log in the stationary frame: i(k) and the voltage of [t_k, t_k+1)."""
    T: float                 # s, the sampling period
    i_ab: np.ndarray         # complex, A
    u_ab: np.ndarray         # complex, V
    phi: np.ndarray          # complex: the drop's direction (2/3) sum sgn(i_x) a^x
    theta: np.ndarray | None  # rad, the rotor's angle, or None


@dataclass(frozen=True)
class Estimate:
    """One parameter: the fit's value and its 95 % interval."""
    value: float
    lo: float
    hi: float

    def __str__(self) -> str:
        return f"{self.value:.5g} [{self.lo:.5g}, {self.hi:.5g}]"


@dataclass(frozen=True)
class LogFit:
    R_s: Estimate   # ohm
    L_s: Estimate   # H
    psi_r: Estimate  # Wb
    u_0: Estimate   # V, the inverter's drop per leg
    samples: int    # samples the fit used
    angle: str      # "log" (a theta column) or "estimated"
    resid: float    # V, the residual RMS

    @property
    def ok(self) -> bool:
        """The intervals are narrow enough to use: R_s within +-10 %, L_s
        and psi_r within +-5 % (half widths)."""
        def rel(e: Estimate) -> float:
            return 0.5 * (e.hi - e.lo) / abs(e.value) if e.value else math.inf
        return rel(self.R_s) <= 0.10 and rel(self.L_s) <= 0.05 and rel(self.psi_r) <= 0.05


def _clarke(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Amplitude-invariant: x_ab = (2/3)(x_a + a x_b + a^2 x_c)."""
    return (2.0 / 3.0) * (a - 0.5 * (b + c)) + 1j * (b - c) / math.sqrt(3.0)


def read_log(path: str | Path, u_dc: float | None = None) -> DriveLog:
    """The log at `path` (CSV with a header line, or .parquet), checked:
    a missing or non-finite column, a non-uniform time base or a duty
    outside [0, 1] is a ParameterError naming it."""
    path = Path(path)
    if not path.is_file():
        raise ParameterError(f"--from-log {path}: no such file")
    if path.suffix.lower() in (".parquet", ".pq"):
        try:
            import pyarrow.parquet as pq
        except ImportError:
            raise ParameterError("a Parquet log needs pyarrow: pip install pyarrow") from None
        table = pq.read_table(path)
        cols = {n: np.asarray(table.column(n).to_numpy(), dtype=float)
                for n in table.column_names if n in COLUMNS}
    else:
        try:
            data = np.genfromtxt(path, delimiter=",", names=True, dtype=float)
        except ValueError as e:
            raise ParameterError(f"{path}: not a CSV log with a header line ({e})") from None
        if data.dtype.names is None:
            raise ParameterError(f"{path}: not a CSV log with a header line")
        cols = {n: np.atleast_1d(data[n]).astype(float) for n in data.dtype.names
                if n in COLUMNS}
    return log_from_columns(cols, u_dc, str(path))


def log_from_columns(cols: dict, u_dc: float | None = None, where: str = "log") -> DriveLog:
    """A DriveLog from named columns (:data:`COLUMNS`)."""
    need = ["t", "i_a", "i_b"]
    for n in need:
        if n not in cols:
            raise ParameterError(f"{where}: no column {n!r}; a log has {', '.join(need)}, "
                                 "d_a, d_b, d_c and u_dc (or u_a, u_b, u_c); see "
                                 "docs/commissioning.md")
    t = cols["t"]
    if len(t) < 1000:
        raise ParameterError(f"{where}: {len(t)} rows; the fit needs at least 1000")
    for n, x in cols.items():
        if not np.all(np.isfinite(x)):
            k = int(np.argmax(~np.isfinite(x)))
            raise ParameterError(f"{where}: column {n!r} is not finite at row {k}")
    dt = np.diff(t)
    T = float(np.median(dt))
    if not (T > 0.0 and np.all(np.abs(dt - T) <= 1e-3 * T)):
        raise ParameterError(f"{where}: the times in 't' are not uniform (median step "
                             f"{T:.4g} s, steps from {dt.min():.4g} to {dt.max():.4g} s)")
    i_a, i_b = cols["i_a"], cols["i_b"]
    i_c = cols.get("i_c", -i_a - i_b)
    if all(n in cols for n in ("u_a", "u_b", "u_c")):
        u_ab = _clarke(cols["u_a"], cols["u_b"], cols["u_c"])
    elif all(n in cols for n in ("d_a", "d_b", "d_c")):
        d = np.stack([cols["d_a"], cols["d_b"], cols["d_c"]])
        if d.min() < -1e-6 or d.max() > 1.0 + 1e-6:
            raise ParameterError(f"{where}: a duty is outside [0, 1] (from {d.min():.4g} to "
                                 f"{d.max():.4g})")
        if "u_dc" in cols:
            udc = cols["u_dc"]
        elif u_dc is not None and u_dc > 0 and math.isfinite(u_dc):
            udc = np.full_like(t, float(u_dc))
        else:
            raise ParameterError(f"{where}: duties need the DC-link voltage: a 'u_dc' "
                                 "column or --u-dc V (> 0)")
        u_ab = _clarke(*(d * udc))
    else:
        raise ParameterError(f"{where}: no voltages: columns d_a, d_b, d_c (with u_dc) or "
                             "u_a, u_b, u_c")
    i_ab = _clarke(i_a, i_b, i_c)
    s = np.sign(np.stack([i_a, i_b, i_c]))
    phi = _clarke(*s)
    return DriveLog(T, i_ab, u_ab, phi, cols.get("theta"))


def _intervals(log: DriveLog):
    """Per interval [k, k+1): mean current, di/dt, voltage, and the mean
    current unfiltered (for the drop's direction). The model is linear in
    the stationary frame, so the same zero-phase low-pass (FIT_HZ, far above
    the electrical frequencies) on currents, voltages and the drop's
    direction keeps it: it takes the ADC's noise out of di/dt, which would
    otherwise be a regressor with noise of its own and pull L_s toward
    zero."""
    T = log.T
    i = _lowpass_c(log.i_ab, T, FIT_HZ)
    i_m = 0.5 * (i[:-1] + i[1:])
    di = (i[1:] - i[:-1]) / T
    raw = 0.5 * (log.i_ab[:-1] + log.i_ab[1:])
    return i_m, di, _lowpass_c(log.u_ab, T, FIT_HZ)[:-1], raw


def _drop(raw: np.ndarray, band: float, T: float) -> np.ndarray:
    """The drop's direction (2/3) sum_x s(i_x) a^x with s the sign (band 0)
    or i_x / band clipped to +-1: a leg's drop fades as its current's ripple
    crosses zero, over a band the log does not tell, so the fit tries
    several (BANDS)."""
    ph = [np.real(raw * np.exp(-2j * math.pi * x / 3)) for x in range(3)]
    s = [np.sign(p) if band <= 0.0 else np.clip(p / band, -1.0, 1.0) for p in ph]
    return _lowpass_c(_clarke(*s), T, FIT_HZ)


def _lowpass(x: np.ndarray, T: float, hz: float) -> np.ndarray:
    b, a = butter(2, min(0.9, 2.0 * hz * T))
    return filtfilt(b, a, x)


def _frame(emf: np.ndarray, T: float) -> tuple[np.ndarray, np.ndarray]:
    """The rotor's angle and electrical speed from an EMF estimate, smoothed
    in the EMF's own frame: e = j w psi_r e^{j theta} leads the rotor by 90
    deg turning forward and lags it by 90 deg turning backward."""
    th = np.unwrap(np.angle(emf))
    # the EMF turned back by its own (noisy) angle's smoothed version: the
    # remaining angle is small, low-passed and added back
    th_s = _lowpass(th, T, SMOOTH_HZ)
    res = np.angle(emf * np.exp(-1j * th_s))
    th_f = th_s + _lowpass(res, T, SMOOTH_HZ)
    w = np.gradient(th_f, T)
    return th_f - np.sign(w) * 0.5 * math.pi, w


def _design(i_m, di, ph, th_m, w):
    """The rotor-frame regression: rows d then q, columns R_s, L_s, psi_r,
    u_0."""
    r = np.exp(-1j * th_m)
    a, b, p = i_m * r, di * r, ph * r
    z = np.zeros_like(w)
    A = np.concatenate([np.stack([a.real, b.real, z, p.real], 1),
                        np.stack([a.imag, b.imag, w, p.imag], 1)])
    return A, r


def _solve(A, y):
    keep = np.any(A != 0.0, axis=0)  # a known parameter's column is zero
    x = np.zeros(A.shape[1])
    x[keep], *_ = np.linalg.lstsq(A[:, keep], y, rcond=None)
    return x


def fit_log(log: DriveLog, L_s: float | None = None, seed: int = 0,
            progress: Callable[[float], None] | None = None) -> LogFit:
    """R_s, L_s, psi_r and the drop from `log`, with 95 % intervals; with
    `L_s` given (H), the inductance is taken as known; `progress(fraction)`
    after each band's fit and bootstrap (a log without the
    rotor's angle needs it: the inductance and the angle trade off, the
    fit's fixed point then had L_s 37 % low on Table I's motor).

    The drop's shape near zero current is tried at each band of BANDS (a
    fraction of the log's largest current): the value is the best band's
    fit, the interval the union of the bootstrap intervals of every band
    whose residual is within BAND_SLACK of the best. (R_s i and the drop
    are nearly collinear in a drive's own log, so R_s's interval is mostly
    that shape's uncertainty: +-9 % on Table I's motor, where psi_r's is
    0.3 %.)"""
    if log.theta is None and L_s is None:
        raise ParameterError("a log without the rotor's angle (a 'theta' column) needs L_s "
                             "(--L-s H, e.g. from `smodrive identify`): without it the "
                             "inductance and the estimated angle trade off")
    i_m, di, u, raw = _intervals(log)
    T = log.T
    if L_s is not None:
        u = u - L_s * di  # the inductance's share is known: the fit sees u - L_s di/dt
        di = np.zeros_like(di)
    i_big = float(np.percentile(np.abs(raw), 99.5))
    if log.theta is not None:
        # the log's angle: the same frame for every band
        th = np.unwrap(log.theta)
        th_log = 0.5 * (th[:-1] + th[1:])
        w_log = np.gradient(_lowpass(th, T, SMOOTH_HZ), T)[:-1]
        sel_log = np.ones_like(w_log, dtype=bool)
        edge = math.ceil(5.0 / (2.0 * math.pi * SMOOTH_HZ * T))
        sel_log[:edge] = sel_log[-edge:] = False
    fits = []
    for band in BANDS:
        ph = _drop(raw, band * i_big, T)
        if log.theta is not None:
            th_m, w, sel = th_log, w_log, sel_log
        else:
            # from the voltage's own angle (the EMF dominates at speed) to the
            # fixed point of the fit and the angle of its EMF
            x = np.zeros(4)
            for _ in range(ITERATIONS):
                emf = u - x[0] * i_m - x[3] * ph
                th_m, w = _frame(emf, T)
                sel = _select(emf, T)
                A, r = _design(i_m[sel], di[sel], ph[sel], th_m[sel], w[sel])
                y = np.concatenate([(u[sel] * r).real, (u[sel] * r).imag])
                x_new = _solve(A, y)
                done = np.allclose(x_new, x, rtol=1e-6, atol=0)
                x = x_new
                if done:
                    break
        n = int(sel.sum())
        if n < 1000:
            raise ParameterError(f"the log has {n} samples at speed (EMF at least "
                                 f"{EMF_MIN:g} of its largest); the fit needs 1000")
        A, r = _design(i_m[sel], di[sel], ph[sel], th_m[sel], w[sel])
        y = np.concatenate([(u[sel] * r).real, (u[sel] * r).imag])
        x = _solve(A, y)
        fits.append((float(np.sqrt(np.mean((y - A @ x) ** 2))), x, A, y, n))
        if progress is not None:
            progress(0.5 * len(fits) / len(BANDS))
    best = min(f[0] for f in fits)
    rng = np.random.default_rng(seed)
    lo, hi = np.full(4, np.inf), np.full(4, -np.inf)
    for j, (resid, x, A, y, n) in enumerate(fits):
        if progress is not None:
            progress(0.5 + 0.5 * (j + 1) / len(fits))
        if resid > BAND_SLACK * best:
            continue
        # block bootstrap: the rows of each block are its d and its q rows
        edges = np.linspace(0, n, BLOCKS + 1).astype(int)
        blocks = [np.r_[edges[k]:edges[k + 1]] for k in range(BLOCKS)]
        boot = []
        for _ in range(RESAMPLES):
            idx = np.concatenate([blocks[k] for k in rng.integers(0, BLOCKS, BLOCKS)])
            rows = np.concatenate([idx, idx + n])
            boot.append(_solve(A[rows], y[rows]))
        b_lo, b_hi = np.percentile(np.array(boot), [2.5, 97.5], axis=0)
        lo, hi = np.minimum(lo, b_lo), np.maximum(hi, b_hi)
    resid, x, _, _, n = min(fits, key=lambda f: f[0])
    if L_s is not None:
        x[1] = lo[1] = hi[1] = L_s
    est = [Estimate(float(v), float(a), float(b)) for v, a, b in zip(x, lo, hi)]
    return LogFit(est[0], est[1], est[2], est[3], n,
                  "log" if log.theta is not None else "estimated", resid)


def _lowpass_c(x: np.ndarray, T: float, hz: float) -> np.ndarray:
    """A complex signal through a zero-phase low-pass at min(hz, 0.1 / T)."""
    hz = min(hz, 0.1 / T)
    return _lowpass(x.real, T, hz) + 1j * _lowpass(x.imag, T, hz)


def _select(emf: np.ndarray, T: float) -> np.ndarray:
    """Samples at speed (EMF at least EMF_MIN of the log's largest), away
    from the log's ends (the zero-phase filters' edges: five time constants
    of the angle's smoothing)."""
    mag = np.abs(emf)
    sel = mag >= EMF_MIN * np.percentile(mag, 99.5)
    edge = math.ceil(5.0 / (2.0 * math.pi * SMOOTH_HZ * T))
    sel[:edge] = False
    sel[-edge:] = False
    return sel


def drive_log_columns(r) -> dict[str, np.ndarray]:
    """The columns of a log (:data:`COLUMNS`) from a smodrive run `r`
    logged every sample, as a drive logs itself: the ADC's currents, the
    duties it applied (with its dead-time compensation) and the DC-link
    voltage. For tests and examples."""
    if r.log_stride != 1:
        raise ParameterError(f"the run logged every {r.log_stride} samples; a drive log "
                             "needs every sample (log_stride = 1)")
    i_a, i_b = r["i_a_meas"], r["i_b_meas"]
    return {"t": r["t"], "i_a": i_a, "i_b": i_b, "i_c": -i_a - i_b, "d_a": r["d_a"],
            "d_b": r["d_b"], "d_c": r["d_c"],
            "u_dc": np.full_like(i_a, r.scenario.inverter.u_dc)}


def write_csv(cols: dict[str, np.ndarray], path: str | Path) -> Path:
    path = Path(path)
    names = list(cols)
    np.savetxt(path, np.stack([cols[n] for n in names], 1), delimiter=",",
               header=",".join(names), comments="", fmt="%.9g")
    return path
