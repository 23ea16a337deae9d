"""yao2022's LCL + SPMSM plant as the observer design sees it: the design
parameters, the continuous model eq. (1)-(3), its zero-order-hold
discretisation eq. (4), the model in the estimated rotor frame eq. (5)-(7)
and the canonical form of the error dynamics eq. (13)-(15).

The first floor of :mod:`smodrive.design.yao2022` (which re-exports every
name here); equation numbers refer to Yao et al., IEEE TPEL 37(2), 2022.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ..model import LclFilterPars, MotorPars, ParameterError, Scenario
from ..model.fields import _Validated

I2 = np.eye(2)
J2 = np.array([[0.0, -1.0], [1.0, 0.0]])  # eq. (3)
Z2 = np.zeros((2, 2))


def rpm_to_w(n_rpm: float | np.ndarray, n_p: int) -> float | np.ndarray:
    """Mechanical speed in r/min to electrical angular speed in rad/s."""
    return n_p * np.asarray(n_rpm, dtype=float) * (2.0 * math.pi / 60.0)


def w_to_rpm(w: float | np.ndarray, n_p: int) -> float | np.ndarray:
    """Electrical angular speed in rad/s to mechanical speed in r/min."""
    return np.asarray(w, dtype=float) / n_p * (60.0 / (2.0 * math.pi))


def rot(theta: float, n_blocks: int = 1) -> np.ndarray:
    """Block-diagonal rotation ``blockdiag(e^{J theta}, ...)`` (2x2 blocks).

    ``rot(-w*T, 3)`` is the ``e^{-J w T}`` of eq. (7) acting on the six
    states of eq. (6).
    """
    c, s = math.cos(theta), math.sin(theta)
    r = np.array([[c, -s], [s, c]])
    return np.kron(np.eye(n_blocks), r)


# ---------------------------------------------------------------------------
# Parameters
# ---------------------------------------------------------------------------


def _check_positive(obj: object) -> None:
    for f in dataclasses.fields(obj):  # type: ignore[arg-type]
        v = getattr(obj, f.name)
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            if not (math.isfinite(v) and v > 0):
                raise ParameterError(
                    f"{type(obj).__name__}.{f.name} = {v!r} must be finite and > 0")


@dataclass(frozen=True)
class DesignPlant(_Validated):
    """The plant the observer is designed for: machine, LCL filter, sampling period.

    The physical parameters are the project's own classes, validated there
    (a bad value raises :class:`~smodrive.model.ParameterError` naming the
    field); this bundle only adds the sampling period. The design uses
    ``motor.R_s``, ``motor.L_s``, ``motor.n_p`` (speed axis) and ``lcl.L1``,
    ``lcl.L2o``, ``lcl.C1``; ``psi_r`` and the mechanics do not enter it
    (the EMF is a state, eq. (2)). Table II is the plant of
    :data:`smodrive.scenarios.yao2022.BASE`:
    ``DesignPlant(BASE.motor, BASE.lcl, BASE.T_sp)``. The drive designs its
    observer from the controller's estimates instead
    (:func:`smodrive.engine.lcl_observer_tables`).

    Parameters
    ----------
    motor : MotorPars
        Machine (``R_s`` winding resistance, ``L_s`` stator inductance).
    lcl : LclFilterPars
        Filter (``L1`` inverter side, ``L2o`` machine side, ``C1``).
    T_sp : float
        Sampling period (s), 1/f_s (Table II: f_s = 20 kHz); the range of
        :attr:`smodrive.model.Scenario.T_sp`.
    """

    _section = "plant"
    motor: MotorPars
    lcl: LclFilterPars
    T_sp: float = dataclasses.field(metadata=Scenario.__dataclass_fields__["T_sp"].metadata)

    def __post_init__(self) -> None:
        if not isinstance(self.motor, MotorPars):
            raise ParameterError(f"plant.motor = {self.motor!r} is not a MotorPars")
        if not isinstance(self.lcl, LclFilterPars):
            raise ParameterError(f"plant.lcl = {self.lcl!r} is not an LclFilterPars")
        super().__post_init__()

    @property
    def L2(self) -> float:
        """Total machine-side inductance ``L2 = L2o + L_s`` (H), below eq. (3)."""
        return self.lcl.L2o + self.motor.L_s

    def f_res(self) -> float:
        """LCL resonance frequency (Hz), Table II.

        ``f_res = sqrt((L1 + L2) / (L1 L2 C1)) / (2 pi)``: the nonzero
        eigenvalues of the lossless 6x6 block of eq. (2).
        """
        return self.lcl.f_res(self.motor.L_s)

    def summary(self) -> str:
        """The values the design depends on, exactly (``repr`` of each float)."""
        m, f = self.motor, self.lcl
        return (f"R_s = {m.R_s!r} ohm, L_s = {m.L_s!r} H, n_p = {m.n_p!r}, L1 = {f.L1!r} H, "
                f"L2o = {f.L2o!r} H, C1 = {f.C1!r} F, T_sp = {self.T_sp!r} s")


@dataclass(frozen=True)
class PllPars:
    """Third-order PLL of eq. (48), gains of eq. (50).

    Parameters
    ----------
    k_theta : float
        Position gain (rad per rad of error).
    k_omega : float
        Speed gain (rad/s per rad of error).
    k_a : float
        Acceleration gain (rad/s^2 per rad of error).
    T : float
        Sampling period (s).
    """

    k_theta: float = 0.1
    k_omega: float = 10.0
    k_a: float = 10.0
    T: float = 50e-6

    def __post_init__(self) -> None:
        _check_positive(self)


@dataclass(frozen=True)
class ObserverDesignPars:
    """Design choices of the sliding-mode observer (the missing Table III).

    The reasoning behind each default is in ``docs/yao2022_design.md``.

    Parameters
    ----------
    p_L : tuple of 2 floats
        Poles of ``G11 + L G21``, the reduced-order observer inside the
        augmented sliding surface (design step 2, eq. (23)).
    p_u : tuple of 4 floats
        Poles of the state feedback of step 3 (eq. (22), (24)).
    Q : tuple of 2 floats
        Diagonal of the convergence matrix ``Q`` of the reaching law (33).
    bw_rel_2, bw_rel_3 : float
        -3 dB bandwidths ``Omega`` of the 2 f_e and 3 f_e band-pass filters of
        eq. (45)-(46), as fractions of f_e (``Omega = 2 pi bw_rel f_e``).
    phi : float
        Attenuation of the EMF adaption low-pass at 2 f_e, eq. (51).
    k_min : float
        Lower bound of the EMF adaption gain ``k`` (not in the paper; eq. (51)
        gives ``k -> 0`` at standstill, which would freeze the EMF estimate).
    p_lin : tuple of 4 floats
        Poles of the linear reduced-order observer of eq. (65) (Sec. VII-E).
    n_delay_max : int
        Largest integer delay ``N`` of eq. (35) stored in the tables.
    """

    p_L: tuple[float, float] = (0.25, 0.25)
    p_u: tuple[float, float, float, float] = (0.4, 0.4, 0.5, 0.5)
    Q: tuple[float, float] = (0.5, 0.5)
    bw_rel_2: float = 0.2
    bw_rel_3: float = 0.2
    phi: float = 0.3
    k_min: float = 0.1
    p_lin: tuple[float, float, float, float] = (0.4, 0.4, 0.5, 0.5)
    n_delay_max: int = 64

    def __post_init__(self) -> None:
        for name, n in (("p_L", 2), ("p_u", 4), ("Q", 2), ("p_lin", 4)):
            v = getattr(self, name)
            if len(v) != n or not all(np.isfinite(v)) or max(abs(x) for x in v) >= 1.0:
                raise ParameterError(
                    f"ObserverDesignPars.{name} = {v!r} must be {n} values inside the unit circle")
        # p_L and p_u are placed through 2-column input matrices (rank 2): a
        # pole may repeat at most twice (place); p_lin's has rank 4
        for name in ("p_L", "p_u"):
            v = getattr(self, name)
            if max(list(v).count(x) for x in v) > 2:
                raise ParameterError(
                    f"ObserverDesignPars.{name} = {v!r}: a pole may repeat at most twice (the "
                    "rank of the input matrix it is placed through)")
        for name in ("bw_rel_2", "bw_rel_3", "k_min"):
            v = getattr(self, name)
            if not (math.isfinite(v) and 0.0 < v < 1.0):
                raise ParameterError(f"ObserverDesignPars.{name} = {v!r} must be in (0, 1)")
        if not 0.0 < self.phi < 1.0:
            raise ParameterError(f"ObserverDesignPars.phi = {self.phi!r} must be in (0, 1)")
        if isinstance(self.n_delay_max, np.integer):
            object.__setattr__(self, "n_delay_max", int(self.n_delay_max))
        if not (isinstance(self.n_delay_max, int) and self.n_delay_max >= 2):
            raise ParameterError(
                f"ObserverDesignPars.n_delay_max = {self.n_delay_max!r} must be an integer >= 2")


# ---------------------------------------------------------------------------
# Model, eq. (1)-(7)
# ---------------------------------------------------------------------------


def continuous_model(plant: DesignPlant, w: float) -> tuple[np.ndarray, np.ndarray]:
    """Continuous-time model in the stationary frame, eq. (1)-(3).

    States ``x_s = [u_c_ab, i_1_ab, i_2_ab, e_ab]`` (8), input ``u_s_ab``.

    The first block row is the capacitor KCL ``C1 du_c/dt = i_1 - i_2``; the
    printed ``-(1/C) i_1 + (1/C1) i_2`` has the signs swapped (erratum 1).

    Parameters
    ----------
    plant : DesignPlant
    w : float
        Electrical angular speed (rad/s), constant over the sample.

    Returns
    -------
    A_s : ndarray, shape (8, 8)
    B_s : ndarray, shape (8, 2)
    """
    C1, L1, L2, R_s = plant.lcl.C1, plant.lcl.L1, plant.L2, plant.motor.R_s
    A_s = np.block([
        [Z2, I2 / C1, -I2 / C1, Z2],
        [-I2 / L1, Z2, Z2, Z2],
        [I2 / L2, Z2, -R_s / L2 * I2, -I2 / L2],
        [Z2, Z2, Z2, w * J2],
    ])
    B_s = np.vstack([Z2, I2 / L1, Z2, Z2])
    return A_s, B_s


def zoh(A: np.ndarray, B: np.ndarray, T: float) -> tuple[np.ndarray, np.ndarray]:
    """Zero-order-hold discretisation, eq. (4).

    ``G = e^{A T}``, ``H = int_0^T e^{A t} dt B``, both read off one matrix
    exponential of the augmented matrix ``[[A, B], [0, 0]] T`` (Van Loan),
    which is exact also where ``A`` is singular (the EMF block at ``w = 0``).
    """
    n, m = B.shape
    M = np.zeros((n + m, n + m))
    M[:n, :n] = A * T
    M[:n, n:] = B * T
    E = scipy.linalg.expm(M)
    return E[:n, :n], E[:n, n:]


def stationary_model(plant: DesignPlant, w: float) -> tuple[np.ndarray, np.ndarray]:
    """Discrete stationary-frame model ``(G_s, H_s)`` of eq. (4), shapes (8, 8), (8, 2)."""
    A_s, B_s = continuous_model(plant, w)
    return zoh(A_s, B_s, plant.T_sp)


def rotor_frame_model(plant: DesignPlant, w: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Discrete model in the estimated rotor (gamma-delta) frame, eq. (5)-(7).

    ``x(k) = [u_c_gd, i_1_gd, i_2_gd]`` (6). The frame advances ``w T`` per
    sample, hence the factor ``e^{-J w T}`` of eq. (7); the stationary-frame
    blocks all commute with ``J`` (they are polynomials in ``J``), so the
    rotation by the frame angle at ``k`` cancels.

    Returns
    -------
    G : ndarray, shape (6, 6)
    H : ndarray, shape (6, 2)
    F : ndarray, shape (6, 2)
        EMF input matrix; ``e_gd(k)`` is the EMF at the start of the sample.
    """
    G_s, H_s = stationary_model(plant, w)
    Rm = rot(-w * plant.T_sp, 3)
    return Rm @ G_s[0:6, 0:6], Rm @ H_s[0:6, :], Rm @ G_s[0:6, 6:8]


# ---------------------------------------------------------------------------
# Canonical form, eq. (13)-(15)
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class CanonicalForm:
    """Canonical form of the error dynamics (11), eq. (13)-(15).

    Attributes
    ----------
    T_r : ndarray, shape (6, 6)
        ``[x_u; y_1; y_2] = T_r x`` (eq. (14)).
    F_t : ndarray, shape (4, 4)
        Lower-right block of ``T_r``: ``[y_1; y_2] = F_t [i_1; i_2]`` (eq. (15)).
    B : ndarray, shape (2, 2)
        Input matrix of ``y_2``: ``T_r F = [0; 0; B]`` (eq. (13)).
    G_r6 : ndarray, shape (6, 6)
        ``T_r G T_r^{-1}``; blocks ``G11 .. G33`` as properties.
    """

    T_r: np.ndarray
    F_t: np.ndarray
    B: np.ndarray
    G_r6: np.ndarray

    def blk(self, i: int, j: int) -> np.ndarray:
        """Block ``G_ij`` (1-based, 2x2) of ``T_r G T_r^{-1}``."""
        return self.G_r6[2 * (i - 1):2 * i, 2 * (j - 1):2 * j]

    G11 = property(lambda self: self.blk(1, 1))
    G12 = property(lambda self: self.blk(1, 2))
    G13 = property(lambda self: self.blk(1, 3))
    G21 = property(lambda self: self.blk(2, 1))
    G22 = property(lambda self: self.blk(2, 2))
    G23 = property(lambda self: self.blk(2, 3))
    G31 = property(lambda self: self.blk(3, 1))
    G32 = property(lambda self: self.blk(3, 2))
    G33 = property(lambda self: self.blk(3, 3))


def _qr_full(F2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Full QR ``F2 = Q R`` (Q 4x4) with a unique, speed-smooth basis.

    ``numpy.linalg.qr`` (LAPACK Householder, like MATLAB's ``qr``) fixes the
    subspaces but not the basis: column signs flip when a Householder pivot
    changes sign, and the basis of the complement of range(F2) is arbitrary up
    to a 2x2 orthogonal factor. Jumps in that basis with speed would make the
    lookup tables impossible to interpolate, so

    * ``Q1`` (range of F2) gets the signs that make ``diag(R) > 0`` (the
      Gram-Schmidt basis, unique for full-rank F2);
    * ``Q2`` (complement) is rotated inside the complement to the orthonormal
      basis closest (Frobenius, orthogonal Procrustes) to ``S Q1 P`` with
      ``S = [[0, -P], [P, 0]]``, ``P = diag(1, -1)``. Because the blocks of
      F2 commute with J (complex numbers a + jb), ``S Q1 P`` already lies in
      the complement and is orthonormal, so it is taken exactly.

    Both are valid full QR factorisations of F2; only the coordinates of
    ``y_1`` and ``y_2`` differ from LAPACK's by a fixed orthogonal map.
    """
    Q, R = np.linalg.qr(F2, mode="complete")
    sgn = np.sign(np.diag(R))
    sgn[sgn == 0] = 1.0
    Q1 = Q[:, :2] * sgn
    R = R.copy()
    R[:2] = sgn[:, None] * R[:2]
    Q2 = Q[:, 2:]
    P = np.diag([1.0, -1.0])
    S = np.block([[Z2, -P], [P, Z2]])
    u, _, vt = np.linalg.svd(Q2.T @ (S @ Q1 @ P))
    Q2 = Q2 @ (u @ vt)
    return np.hstack([Q1, Q2]), R


def canonical_form(G: np.ndarray, F: np.ndarray) -> CanonicalForm:
    """Transformation of the error dynamics (11) to the canonical form (13).

    ``F = [F1; F2]`` with ``F1`` 2x2 (capacitor rows) and ``F2`` 4x2 (current
    rows), eq. (14). With the full QR ``F2 = [Q1 Q2] [R1; 0]`` (eq. (15),
    MATLAB ``[F_t, F_p] = qr(F2)``), ``F_t = flipud(Q^T)`` has rows
    ``[q4; q3; q2; q1]``: its first two rows span the left null space of
    ``F2`` (so ``y_1`` is not driven by the EMF error), its last two give
    ``B = flipud(R1)``, invertible iff F2 has full column rank. ``T_r`` is
    invertible because it is block upper-triangular with an identity and an
    orthogonal diagonal block, and its first block row
    ``[I, -F1 (F2^T F2)^{-1} F2^T]`` annihilates F.

    Parameters
    ----------
    G : ndarray, shape (6, 6)
    F : ndarray, shape (6, 2)

    Returns
    -------
    CanonicalForm
    """
    F1, F2 = F[0:2], F[2:6]
    Q, R = _qr_full(F2)
    F_t = np.flipud(Q.T)
    top = np.hstack([I2, -F1 @ np.linalg.solve(F2.T @ F2, F2.T)])
    bottom = np.hstack([np.zeros((4, 2)), F_t])
    T_r = np.vstack([top, bottom])
    B = (T_r @ F)[4:6]
    G_r6 = T_r @ G @ np.linalg.inv(T_r)
    return CanonicalForm(T_r=T_r, F_t=F_t, B=B, G_r6=G_r6)


