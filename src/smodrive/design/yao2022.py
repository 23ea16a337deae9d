"""Offline design maths of yao2022's sliding-mode back-EMF observer.

Yao, Huang, Peng, Dong, "A Sliding-Mode Position Estimation Method With
Chattering Suppression for LCL-Equipped High-Speed SPMSM Drives", IEEE TPEL
37(2), 2022. Equation numbers below refer to that paper.

Everything here depends only on parameters and on the electrical speed, so it
is computed offline and handed to the real-time core as lookup tables over
speed (Sec. IV-B, last paragraph; Sec. VII-F). The chain is

1. continuous LCL + SPMSM model, eq. (1)-(3);
2. zero-order-hold discretisation, eq. (4), and the model in the estimated
   rotor frame, eq. (5)-(7);
3. canonical form of the error dynamics, eq. (13)-(15);
4. augmented sliding surface with arbitrary pole placement, eq. (16)-(25) and
   design steps 1-5 (Fig. 2);
5. reaching-mode matrices, eq. (26)-(28);
6. reaching-law filters: band-pass eq. (45)-(46), EMF adaption gain eq. (51);
7. the third-order PLL, eq. (48)-(50);
8. the linear reduced-order comparison observer, eq. (64)-(65).

The errata found on the way are listed in ``docs/yao2022_design.md``; two
matter for an implementation: the EMF adaption (34) needs a minus sign,
``e_hat(k) = e_hat(k-1) - k (s(k) - Q s(k-1))`` (as printed its loop root is
``1 + k``), and eq. (51) lacks a factor ``2 pi``.

Example
-------
>>> from smodrive.design.yao2022 import DesignPlant, design_tables, interp_tables, rpm_to_w
>>> from smodrive.scenarios.yao2022 import BASE
>>> plant = DesignPlant(BASE.motor, BASE.lcl, BASE.T_sp)  # Table II
>>> round(plant.f_res())
5525
>>> tab = design_tables(plant, [0.0, 50e3, 100e3])
>>> tab.G.shape
(3, 6, 6)
>>> m = interp_tables(tab, rpm_to_w(75e3, plant.motor.n_p))
>>> m.Gamma_2.shape
(2, 2)
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass

import control
import numpy as np
import scipy.optimize
import scipy.signal

from ..model import ParameterError
from .lcl_model import (
    I2,
    J2,
    Z2,
    CanonicalForm,
    DesignPlant,
    ObserverDesignPars,
    PllPars,
    canonical_form,
    continuous_model,
    rot,
    rotor_frame_model,
    rpm_to_w,
    stationary_model,
    w_to_rpm,
    zoh,
)
from .observer_layout import OBSERVER_FIELDS

__all__ = [
    "I2",
    "J2",
    "DesignPlant",
    "ObserverDesignPars",
    "PllPars",
    "CanonicalForm",
    "SlidingSurface",
    "ReachingMode",
    "LinearObserver",
    "ObserverMatrices",
    "DesignTables",
    "rpm_to_w",
    "w_to_rpm",
    "rot",
    "continuous_model",
    "zoh",
    "stationary_model",
    "rotor_frame_model",
    "canonical_form",
    "place",
    "sliding_surface",
    "augmented_matrix",
    "reaching_mode",
    "bandpass_coefficients",
    "bandpass_response",
    "bandpass_edges",
    "emf_adaption_gain",
    "emf_adaption_gain_exact",
    "emf_lowpass_gain",
    "pll_open_loop",
    "pll_closed_loop",
    "pll_bandwidth_hz",
    "linear_observer",
    "design_point",
    "design_tables",
    "interp_tables",
]

# ---------------------------------------------------------------------------
# Sliding surface, eq. (16)-(25), design steps 1-5
# ---------------------------------------------------------------------------


def place(A: np.ndarray, B: np.ndarray, poles: Sequence[float]) -> np.ndarray:
    """State-feedback gain ``K`` with ``eig(A - B K) = poles``.

    ``scipy.signal.place_poles`` with the Tits-Yang method; it accepts a pole
    repeated up to ``rank(B)`` times (here rank 2, and every design pole of
    :class:`ObserverDesignPars` is at most double), and chooses the closed-loop
    eigenvectors as orthogonal as possible, so a double real pole gives a
    diagonalisable (robust) closed loop rather than a Jordan block. No pole
    offsets are needed.
    """
    p = np.asarray(poles, dtype=float)
    _, counts = np.unique(p, return_counts=True)
    if counts.max() > np.linalg.matrix_rank(B):
        raise ValueError(f"a pole is repeated more often than rank(B) = {np.linalg.matrix_rank(B)}")
    K = scipy.signal.place_poles(A, B, p, method="YT", maxiter=100, rtol=1e-10).gain_matrix
    # an ill-conditioned pair can come back with other poles than asked for:
    # 1e-3 is far above the round-off of a sound placement (about 1e-12) and
    # far below the design poles' distance to the unit circle (>= 0.05)
    got = np.sort_complex(np.linalg.eigvals(A - B @ K))
    err = float(np.max(np.abs(got - np.sort_complex(p.astype(complex)))))
    if not err <= 1e-3:
        raise ValueError(f"the pole placement did not converge: the poles differ by {err:.3g} "
                         "from the ones asked for")
    return K


@dataclass(frozen=True)
class SlidingSurface:
    """Augmented sliding surface, eq. (16), (18), (21) and design steps 2-4.

    Attributes
    ----------
    L : ndarray (2, 2)
        Reduced-order observer gain, ``eig(G11 + L G21) = p_L`` (step 2).
    K1, K2 : ndarray (2, 2)
        State feedback of step 3, ``eig(A_u - B_u [K1 K2]) = p_u``.
    M_y, M_c, H_c, D1, D2 : ndarray (2, 2)
        Eq. (21); ``H_c`` is the ``H`` of eq. (16) and (21).
    Gamma_c, Gamma_1, Gamma_2 : ndarray (2, 2)
        Switching-function matrices of eq. (18), step 4.
    G_sm : ndarray (6, 6)
        Sliding-mode dynamics matrix, eq. (20).
    """

    L: np.ndarray
    K1: np.ndarray
    K2: np.ndarray
    M_y: np.ndarray
    M_c: np.ndarray
    H_c: np.ndarray
    D1: np.ndarray
    D2: np.ndarray
    Gamma_c: np.ndarray
    Gamma_1: np.ndarray
    Gamma_2: np.ndarray
    G_sm: np.ndarray


def sliding_surface(cf: CanonicalForm, p_L: Sequence[float], p_u: Sequence[float]) -> SlidingSurface:
    """Design steps 2-4 (Fig. 2) and the sliding-mode matrix of eq. (20).

    Step 2: ``L`` makes ``G11 + L G21`` have the poles ``p_L``. This is the
    dual (transposed) pole-placement problem ``(G11^T, -G21^T)``: with
    ``K = place(G11^T, -G21^T, p_L)``, ``L = K^T``. (The paper writes the
    pair ``(G11, -G12)`` in step 2 and ``(G11, -G21)`` in the proof: erratum.)

    Step 3: ``[K1 K2] = place([[G11, G12], [G21, G22]], [G13; G23], p_u)``.

    Step 4: eq. (21), ``M_y = K2 - K1 L``, ``M_c = K1``,
    ``H = G11 + L G21``, ``D1 = G12 + L G22 - (G11 + L G21) L``,
    ``D2 = G13 + L G23``, and with ``Gamma_2^{-1} = B`` (below eq. (18)) and
    ``M_c = Gamma_2^{-1} Gamma_c`` (eq. (19)):
    ``Gamma_c = B^{-1} M_c``, ``Gamma_1 = B^{-1} M_y``, ``Gamma_2 = B^{-1}``.
    """
    G11, G12, G13 = cf.G11, cf.G12, cf.G13
    G21, G22, G23 = cf.G21, cf.G22, cf.G23
    L = place(G11.T, -G21.T, p_L).T
    A_u = np.block([[G11, G12], [G21, G22]])
    B_u = np.vstack([G13, G23])
    K = place(A_u, B_u, p_u)
    K1, K2 = K[:, 0:2], K[:, 2:4]
    M_y = K2 - K1 @ L
    M_c = K1
    H_c = G11 + L @ G21
    D1 = G12 + L @ G22 - H_c @ L
    D2 = G13 + L @ G23
    B_inv = np.linalg.inv(cf.B)
    G_sm = np.block([
        [H_c - D2 @ M_c, Z2, D1 - D2 @ M_y],
        [-G13 @ M_c, G11, G12 - G13 @ M_y],
        [-G23 @ M_c, G21, G22 - G23 @ M_y],
    ])
    return SlidingSurface(L=L, K1=K1, K2=K2, M_y=M_y, M_c=M_c, H_c=H_c, D1=D1, D2=D2,
                          Gamma_c=B_inv @ M_c, Gamma_1=B_inv @ M_y, Gamma_2=B_inv, G_sm=G_sm)


def augmented_matrix(cf: CanonicalForm, ss: SlidingSurface) -> tuple[np.ndarray, np.ndarray]:
    """``G_r`` (8x8) and ``F_r`` (8x2) of eq. (17), states ``[x_c, x_u, y_1, y_2]``."""
    G_r = np.zeros((8, 8))
    G_r[0:2, 0:2] = ss.H_c
    G_r[0:2, 4:6] = ss.D1
    G_r[0:2, 6:8] = ss.D2
    G_r[2:8, 2:8] = cf.G_r6
    F_r = np.vstack([Z2, Z2, Z2, cf.B])
    return G_r, F_r


@dataclass(frozen=True)
class ReachingMode:
    """Reaching-mode matrices of eq. (26)-(28).

    ``s(k+1) = G_s s + G_c x_c + G_u x_u + G_y y_1 + (w - e)``.

    Attributes
    ----------
    T_y : ndarray (8, 8)
        Eq. (27), maps ``[x_c, x_u, y_1, y_2]`` to ``[x_c, x_u, y_1, s]``.
    G_c, G_u, G_y, G_s : ndarray (2, 2)
        Last block row of ``T_y G_r T_y^{-1}``, eq. (26).
    """

    T_y: np.ndarray
    G_c: np.ndarray
    G_u: np.ndarray
    G_y: np.ndarray
    G_s: np.ndarray


def reaching_mode(cf: CanonicalForm, ss: SlidingSurface) -> ReachingMode:
    """Reaching-mode dynamics (26)-(28) from eq. (17) and (18)."""
    G_r, _ = augmented_matrix(cf, ss)
    T_y = np.eye(8)
    T_y[6:8, :] = np.hstack([ss.Gamma_c, Z2, ss.Gamma_1, ss.Gamma_2])
    G_t = T_y @ G_r @ np.linalg.inv(T_y)
    last = G_t[6:8]
    return ReachingMode(T_y=T_y, G_c=last[:, 0:2], G_u=last[:, 2:4], G_y=last[:, 4:6], G_s=last[:, 6:8])


# ---------------------------------------------------------------------------
# Reaching-law filters, eq. (45)-(46), (51), (63)
# ---------------------------------------------------------------------------


def bandpass_coefficients(w_n: float, Omega: float, T: float) -> tuple[float, float]:
    """Coefficients ``(a1, a2)`` of the band-pass (45), eq. (46).

    ``G_bp(z) = (1 - a2)/2 (1 - z^-2) / (1 - a1 z^-1 + a2 z^-2)``, centre
    ``w_n`` and -3 dB bandwidth ``Omega`` (both rad/s).

    At ``z = e^{j w_n T}`` the gain is exactly 1 with zero phase (the real
    part of the denominator, ``(1 + a2) cos(w T) - a1``, vanishes there). The
    -3 dB points are ``w_c T +- Omega T / 2`` with
    ``cos(w_c T) = cos(w_n T) cos(Omega T / 2)`` (see :func:`bandpass_edges`):
    the bandwidth is exactly ``Omega``, the band is centred slightly above
    ``w_n`` (bilinear warping).
    """
    t = math.tan(Omega * T / 2.0)
    return 2.0 * math.cos(w_n * T) / (1.0 + t), (1.0 - t) / (1.0 + t)


def bandpass_response(a1: float, a2: float, w: float | np.ndarray, T: float) -> np.ndarray:
    """Frequency response of eq. (45) at angular frequency ``w`` (rad/s)."""
    zi = np.exp(-1j * np.asarray(w, dtype=float) * T)
    return (1.0 - a2) / 2.0 * (1.0 - zi**2) / (1.0 - a1 * zi + a2 * zi**2)


def bandpass_edges(w_n: float, Omega: float, T: float) -> tuple[float, float]:
    """Exact -3 dB frequencies (rad/s) of the band-pass of eq. (45)-(46).

    ``|G_bp|^2 = 1/2`` where ``cos(wT) -+ tan(Omega T/2) sin(wT) = cos(w_n T)``,
    i.e. ``wT = arccos(cos(w_n T) cos(Omega T/2)) +- Omega T/2``.
    """
    half = Omega * T / 2.0
    c = math.acos(math.cos(w_n * T) * math.cos(half))
    return (c - half) / T, (c + half) / T


def emf_adaption_gain(f_e: float, phi: float, T: float) -> float:
    """EMF adaption gain ``k`` of eq. (51).

    The adaption (34) is the low-pass ``k / (z - 1 + k)`` (eq. (39), (63)),
    whose continuous equivalent has the corner ``k / T`` rad/s. Attenuation
    ``phi`` at ``2 f_e`` needs ``k = 2 (2 pi f_e) T sqrt(phi^2/(1 - phi^2))``.
    The printed eq. (51) lacks the ``2 pi`` (it reads right if its ``f_e``
    is the electrical angular frequency): erratum. The discrete filter's
    gain then differs from ``phi`` by the factor derived in
    :func:`emf_lowpass_gain`; :func:`emf_adaption_gain_exact` removes it.
    """
    return 2.0 * (2.0 * math.pi * f_e) * T * math.sqrt(phi**2 / (1.0 - phi**2))


def emf_adaption_gain_exact(f_e: float, phi: float, T: float) -> float:
    """``k`` for which ``|k / (z - 1 + k)| = phi`` exactly at ``2 f_e``.

    With ``s = sin(theta/2)``, ``theta = 2 pi 2 f_e T``, the gain condition
    ``k^2 = phi^2 (k^2 + 4 s^2 (1 - k))`` is a quadratic in ``k``; its positive
    root is returned.
    """
    s = math.sin(2.0 * math.pi * 2.0 * f_e * T / 2.0)
    return 2.0 * s * phi * (math.sqrt(s**2 * phi**2 + 1.0 - phi**2) - s * phi) / (1.0 - phi**2)


def emf_lowpass_gain(k: float, f: float | np.ndarray, T: float) -> np.ndarray:
    """Gain of the low-pass ``k / (z - 1 + k)`` of eq. (63) at ``f`` (Hz).

    ``|e^{j theta} - 1 + k|^2 = k^2 + 4 sin^2(theta/2) (1 - k)``, against the
    continuous-time approximation ``k^2 + theta^2`` behind eq. (51).
    """
    theta = 2.0 * math.pi * np.asarray(f, dtype=float) * T
    return k / np.sqrt(k**2 + 4.0 * np.sin(theta / 2.0) ** 2 * (1.0 - k))


# ---------------------------------------------------------------------------
# PLL, eq. (48)-(50)
# ---------------------------------------------------------------------------


def pll_open_loop(pll: PllPars) -> control.TransferFunction:
    """``G_PLL(z)`` of eq. (49), from the position error to the estimated angle.

    ``(k_theta z^2 + (k_omega T - 2 k_theta) z + k_theta - k_omega T + k_a T^2) / (z - 1)^3``,
    the z-transform of the recursion (48).
    """
    kt, kw, ka, T = pll.k_theta, pll.k_omega, pll.k_a, pll.T
    num = [kt, kw * T - 2.0 * kt, kt - kw * T + ka * T**2]
    den = [1.0, -3.0, 3.0, -1.0]
    return control.tf(num, den, T)


def pll_closed_loop(pll: PllPars) -> control.TransferFunction:
    """Closed position loop ``G_PLL / (1 + G_PLL)`` (unity feedback, Fig. 6)."""
    g = pll_open_loop(pll)
    return control.feedback(g, 1)


def pll_bandwidth_hz(pll: PllPars) -> float:
    """-3 dB bandwidth (Hz) of :func:`pll_closed_loop`.

    The first frequency above which ``|T(e^{j w T})|`` falls below
    ``1/sqrt(2)`` (any resonant peak below it is passed), by bracketing on
    a log grid and Brent's method.
    """
    tcl = pll_closed_loop(pll)
    num, den = np.ravel(tcl.num[0][0]), np.ravel(tcl.den[0][0])

    def mag(f: float) -> float:
        z = np.exp(1j * 2.0 * math.pi * f * pll.T)
        return float(abs(np.polyval(num, z) / np.polyval(den, z))) - 1.0 / math.sqrt(2.0)

    f_nyq = 0.5 / pll.T
    grid = np.geomspace(1e-3, f_nyq * 0.999, 4000)
    vals = np.array([mag(f) for f in grid])
    idx = np.nonzero((vals[:-1] >= 0) & (vals[1:] < 0))[0]
    if idx.size == 0:
        raise ValueError("closed loop does not cross -3 dB below the Nyquist frequency")
    i = idx[-1]
    return float(scipy.optimize.brentq(mag, grid[i], grid[i + 1], xtol=1e-12))


# ---------------------------------------------------------------------------
# Linear reduced-order observer, eq. (64)-(65)
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class LinearObserver:
    """Linear reduced-order observer in the stationary frame, eq. (64)-(65).

    ``x_1 = [i_1, i_2]`` (measured), ``x_2 = [u_c, e]``;
    ``x2_hat = z + L_s y``,
    ``z(k+1) = Theta x2_hat + Theta_y y + Theta_u u``.

    Attributes
    ----------
    L_s : ndarray (4, 4)
    Theta : ndarray (4, 4)
        ``G_s22 - L_s G_s12``, eigenvalues ``p_lin``.
    Theta_y : ndarray (4, 4)
        ``G_s21 - L_s G_s11``.
    Theta_u : ndarray (4, 2)
        ``H_s2 - L_s H_s1``.
    """

    L_s: np.ndarray
    Theta: np.ndarray
    Theta_y: np.ndarray
    Theta_u: np.ndarray


def linear_observer(plant: DesignPlant, w: float, poles: Sequence[float]) -> LinearObserver:
    """Reduced-order observer of eq. (65) for the model (64) at speed ``w``.

    Eq. (64) reorders ``x_s`` of eq. (4) as ``[x_1; x_2] = [i_1, i_2; u_c, e]``.
    ``L_s`` by the dual placement ``L_s = place(G_s22^T, G_s12^T, poles)^T``
    (the EMF model ``de/dt = w J e`` makes it speed dependent).
    """
    G_s, H_s = stationary_model(plant, w)
    perm = np.array([2, 3, 4, 5, 0, 1, 6, 7])
    Gp = G_s[np.ix_(perm, perm)]
    Hp = H_s[perm]
    G11, G12, G21, G22 = Gp[:4, :4], Gp[:4, 4:], Gp[4:, :4], Gp[4:, 4:]
    H1, H2 = Hp[:4], Hp[4:]
    L_s = place(G22.T, G12.T, poles).T
    return LinearObserver(L_s=L_s, Theta=G22 - L_s @ G12, Theta_y=G21 - L_s @ G11, Theta_u=H2 - L_s @ H1)


# ---------------------------------------------------------------------------
# Per-speed design and lookup tables
# ---------------------------------------------------------------------------


def _observer_fields(*head: tuple[str, str], per_speed: bool):
    """Class decorator: a frozen dataclass whose fields are `head`, then every
    field of OBSERVER_FIELDS (an array per speed, or at one speed an array, a
    float or an int by its shape and kind), then the class's own."""

    def wrap(cls):
        own = dict(cls.__dict__.get("__annotations__", {}))
        ann = dict(head)
        for name, shape, kind, _ in OBSERVER_FIELDS:
            ann[name] = ("np.ndarray" if per_speed or shape else
                         "int" if kind == "i" else "float")
        cls.__annotations__ = {**ann, **own}
        return dataclass(frozen=True)(cls)

    return wrap


@_observer_fields(("w", "float"), per_speed=False)
class ObserverMatrices:
    """Everything the real-time observer needs at one electrical speed.

    The fields after ``w`` are those of
    :data:`smodrive.design.observer_layout.OBSERVER_FIELDS`, in its order and
    shapes; their meanings (shapes without the speed axis):

    ``G`` (6,6), ``H`` (6,2), ``F`` (6,2): model (5)-(7), observer (9).
    ``T_r`` (6,6): eq. (14); the observer uses its lower-right ``F_t`` (4,4) block.
    ``B`` (2,2): eq. (13).
    ``H_c``, ``D1``, ``D2`` (2,2): augmented state (16).
    ``Gamma_c``, ``Gamma_1``, ``Gamma_2`` (2,2): switching function (18).
    ``G_s`` (2,2): reaching law (33); ``G_c``, ``G_u``, ``G_y`` (2,2): eq. (26).
    ``G_sm`` (6,6): sliding-mode dynamics (20) (analysis only).
    ``L`` (2,2): reduced-order observer gain of step 2 (eq. (23)).
    ``K_c``, ``K_y`` (2,2): the equivalent-control terms the reaching law
    subtracts, ``G_c x_c + G_y y_1 + G_u x_u_hat`` with ``x_u_hat = x_c - L y_1``
    (eq. (23)), i.e. ``K_c x_c + K_y y_1`` (see docs/yao2022_design.md).
    ``k``: EMF adaption gain (34), (51).
    ``a1_2``, ``a2_2``, ``a1_3``, ``a2_3``: band-pass (46) at 2 f_e and 3 f_e.
    ``N_2``, ``N_3``: integer delays ``round(f_s / (h f_e))`` of eq. (35),
    clipped to ``n_delay_max``.
    ``L_s`` (4,4), ``Theta`` (4,4), ``Theta_y`` (4,4), ``Theta_u`` (4,2):
    linear observer (65).
    ``w``: electrical speed (rad/s).
    """


MATRIX_FIELDS: tuple[str, ...] = tuple(name for name, *_ in OBSERVER_FIELDS)
"""Fields of :class:`ObserverMatrices` stored per speed in :class:`DesignTables`
(:data:`smodrive.design.observer_layout.OBSERVER_FIELDS`)."""


def design_point(plant: DesignPlant, w: float,
                 design: ObserverDesignPars | None = None) -> ObserverMatrices:
    """Full observer design at the electrical speed ``w`` (rad/s)."""
    design = design or ObserverDesignPars()
    G, H, F = rotor_frame_model(plant, w)
    try:
        cf = canonical_form(G, F)
        ss = sliding_surface(cf, design.p_L, design.p_u)
        rm = reaching_mode(cf, ss)
    except (ValueError, np.linalg.LinAlgError) as exc:
        raise ParameterError(
            f"the sliding-mode observer's design (ObserverDesignPars.p_L = {design.p_L!r}, "
            f"p_u = {design.p_u!r}) failed at w = {w:g} rad/s for the plant with T_sp = "
            f"{plant.T_sp!r} s: {exc}") from None
    f_e = abs(w) / (2.0 * math.pi)
    T = plant.T_sp
    k = max(emf_adaption_gain(f_e, design.phi, T), design.k_min)
    a1_2, a2_2 = bandpass_coefficients(2.0 * abs(w), 2.0 * math.pi * design.bw_rel_2 * f_e, T)
    a1_3, a2_3 = bandpass_coefficients(3.0 * abs(w), 2.0 * math.pi * design.bw_rel_3 * f_e, T)

    def n_delay(h: int) -> int:
        if f_e == 0.0:
            return design.n_delay_max
        return int(min(round(1.0 / (h * f_e * T)), design.n_delay_max))

    try:
        lo = linear_observer(plant, w, design.p_lin)
    except (ValueError, np.linalg.LinAlgError) as exc:
        raise ParameterError(
            f"the linear observer's design (ObserverDesignPars.p_lin = {design.p_lin!r}) failed "
            f"at w = {w:g} rad/s for the plant with T_sp = {plant.T_sp!r} s: {exc}") from None
    return ObserverMatrices(
        w=float(w), G=G, H=H, F=F, T_r=cf.T_r, B=cf.B, H_c=ss.H_c, D1=ss.D1, D2=ss.D2,
        Gamma_c=ss.Gamma_c, Gamma_1=ss.Gamma_1, Gamma_2=ss.Gamma_2,
        G_s=rm.G_s, G_c=rm.G_c, G_u=rm.G_u, G_y=rm.G_y, G_sm=ss.G_sm,
        L=ss.L, K_c=rm.G_c + rm.G_u, K_y=rm.G_y - rm.G_u @ ss.L,
        k=k, a1_2=a1_2, a2_2=a2_2, a1_3=a1_3, a2_3=a2_3, N_2=n_delay(2), N_3=n_delay(3),
        L_s=lo.L_s, Theta=lo.Theta, Theta_y=lo.Theta_y, Theta_u=lo.Theta_u,
    )


@_observer_fields(("speeds_rpm", "np.ndarray"), ("w", "np.ndarray"), per_speed=True)
class DesignTables:
    """Speed-indexed lookup tables of :class:`ObserverMatrices`.

    Every matrix field has shape ``(N,) + shape_at_one_speed`` (C order,
    speed first), scalars shape ``(N,)``. ``speeds_rpm`` is strictly
    increasing mechanical speed, ``w`` the electrical speed (rad/s);
    ``plant`` and ``design`` are the inputs the tables were designed from.
    """

    plant: DesignPlant
    design: ObserverDesignPars = dataclasses.field(default_factory=ObserverDesignPars)

    def arrays(self) -> dict[str, np.ndarray]:
        """The speed axis and every per-speed field, in declaration order."""
        return {"speeds_rpm": self.speeds_rpm, "w": self.w, **{n: getattr(self, n) for n in MATRIX_FIELDS}}


DEFAULT_SPEEDS_RPM = np.arange(0.0, 110e3 + 1.0, 1000.0)
"""0 to 110 kr/min in 1 kr/min steps (grid argued in docs/yao2022_design.md)."""


def design_tables(plant: DesignPlant, speeds_rpm: Sequence[float] | np.ndarray | None = None,
                  design: ObserverDesignPars | None = None) -> DesignTables:
    """Lookup tables of the observer design over mechanical speed.

    Parameters
    ----------
    plant : DesignPlant
    speeds_rpm : sequence of float, optional
        Strictly increasing mechanical speeds (r/min); default
        :data:`DEFAULT_SPEEDS_RPM`. Negative speeds are allowed.
    design : ObserverDesignPars, optional

    Returns
    -------
    DesignTables
    """
    if not isinstance(plant, DesignPlant):
        raise ParameterError(f"plant = {plant!r} is not a DesignPlant")
    design = design or ObserverDesignPars()
    n = np.asarray(DEFAULT_SPEEDS_RPM if speeds_rpm is None else speeds_rpm, dtype=float)
    if n.ndim != 1 or n.size < 2 or not np.all(np.diff(n) > 0) or not np.all(np.isfinite(n)):
        raise ValueError("speeds_rpm must be a strictly increasing 1-D sequence of at least 2 finite speeds")
    w = np.asarray(rpm_to_w(n, plant.motor.n_p))
    points = [design_point(plant, float(wi), design) for wi in w]
    cols = {name: np.array([getattr(p, name) for p in points]) for name in MATRIX_FIELDS}
    for name, shape, kind, _ in OBSERVER_FIELDS:  # the layout the tables promise
        if cols[name].shape[1:] != shape or cols[name].dtype.kind != kind:
            raise AssertionError(f"design field {name}: shape {cols[name].shape[1:]} "
                                 f"{cols[name].dtype}, the layout says {shape} {kind}")
    return DesignTables(speeds_rpm=n, w=w, plant=plant, design=design, **cols)


def interp_tables(tables: DesignTables, w: float) -> ObserverMatrices:
    """Linear interpolation of the tables at electrical speed ``w`` (rad/s).

    Integer fields (``N_2``, ``N_3``) take the nearest table value. Raises
    ``ValueError`` outside the table (no extrapolation).
    """
    x = tables.w
    if not x[0] <= w <= x[-1]:
        raise ValueError(f"w = {w} rad/s is outside the table [{x[0]}, {x[-1]}] rad/s")
    i = int(np.clip(np.searchsorted(x, w, side="right") - 1, 0, x.size - 2))
    lam = (w - x[i]) / (x[i + 1] - x[i])
    out: dict[str, object] = {"w": float(w)}
    for name in MATRIX_FIELDS:
        a = getattr(tables, name)
        if a.dtype.kind in "iu":
            out[name] = int(a[i] if lam < 0.5 else a[i + 1])
        elif a.ndim == 1:
            out[name] = float((1.0 - lam) * a[i] + lam * a[i + 1])
        else:
            out[name] = (1.0 - lam) * a[i] + lam * a[i + 1]
    return ObserverMatrices(**out)  # type: ignore[arg-type]
