"""Transfer functions from the papers' own equations (python-control).

>>> import numpy as np
>>> g = G_smdo(w_c=1500.0, w_r=628.3)
>>> abs(g(1j * 628.3)) # eq. (33): unity gain at the rotor frequency
1.0
"""

from __future__ import annotations

import control
import numpy as np


def H_dbpc(L_s: float, L_s_hat: float, R_s: float, T_sp: float) -> control.TransferFunction:
    """yang2018 eq. (14): i_dq / i_dq_ref of conventional DBPC with an
    inductance error dL = L_s - L_s_hat (T_sc in the paper is T_sp)."""
    dL = L_s - L_s_hat
    den = [L_s, -R_s / L_s_hat * dL * T_sp, -dL + R_s / L_s_hat * dL * T_sp]
    return control.tf([L_s_hat], den, T_sp)


def peak_gain(sys: control.TransferFunction, n: int = 200_001) -> tuple[float, float]:
    """Peak |H(e^{j w T})| over (0, pi/T) on a dense grid refined around the
    maximum; returns (peak gain, frequency in Hz)."""
    T = sys.dt
    w = np.linspace(1e-3, np.pi / T, n)
    mag = np.abs(sys(np.exp(1j * w * T)))
    k = int(np.argmax(mag))
    lo, hi = w[max(k - 2, 0)], w[min(k + 2, n - 1)]
    w2 = np.linspace(lo, hi, 20_001)
    mag2 = np.abs(sys(np.exp(1j * w2 * T)))
    k2 = int(np.argmax(mag2))
    return float(mag2[k2]), float(w2[k2] / (2 * np.pi))


class _ComplexTF:
    """G(s) = w_c / (s - j w_r + w_c), a complex-coefficient filter (eq. (33));
    python-control has no complex coefficients, so it is evaluated directly."""

    def __init__(self, w_c: float, w_r: float):
        self.w_c, self.w_r = w_c, w_r

    def __call__(self, s: complex | np.ndarray) -> complex | np.ndarray:
        return self.w_c / (s - 1j * self.w_r + self.w_c)


def G_smdo(w_c: float, w_r: float) -> _ComplexTF:
    """yang2018 eq. (33)."""
    return _ComplexTF(w_c, w_r)


def G_smdo_discrete(w_c: float, w_r: float, T_sp: float, w: float) -> complex:
    """Discrete counterpart of eq. (33) implied by the Euler filter (36) on
    the sliding surface (u_smo = e_u):
    u_d_hat^{k+1} = (1 + j w_r T) u_d_hat^k + w_c T (u_d^k - u_d_hat^k),
    evaluated for u_d^k = e^{j w k T}."""
    z = np.exp(1j * w * T_sp)
    return complex(w_c * T_sp / (z - 1.0 - 1j * w_r * T_sp + w_c * T_sp))


def dbpc_steady_state(
    L_s: float, R_s: float, psi_r: float, L_s_hat: float, R_s_hat: float, psi_r_hat: float,
    w_r: float, T_sp: float, i_dref: float, i_qref: float,
) -> tuple[float, float]:
    """yang2018 eq. (12)-(13): steady-state i_d, i_q of conventional DBPC
    under parameter errors (i_q of (12) taken as i_qref, i_d of (13) from (12))."""
    dL, dR, dpsi = L_s - L_s_hat, R_s - R_s_hat, psi_r - psi_r_hat
    den = L_s_hat + 2 * dR * T_sp
    i_d = (L_s_hat * i_dref + 2 * dL * w_r * T_sp * i_qref) / den
    i_q = (L_s_hat * i_qref - 2 * w_r * T_sp * (dpsi + dL * i_d)) / den
    return i_d, i_q
