"""Commissioning's step 2 behind an LCL filter (yao2022's motor): the
motor's inductance from the square wave's averaged response through the
filter's model (its data sheet's L1, C1, L2o), since the wave's response
is the filter's and the motor's (docs/commissioning.md, step 2)."""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import expm
from scipy.optimize import minimize_scalar

from .model.scenario import Scenario

#: step 2's half period behind an LCL filter, samples: the wave's resonance (its edges ring the
#: filter) sampled well enough for the filter's model (yao2022's motor: L_s -0.6 % at 16,
#: -5.0 % at 8, -3.3 % at 32)
N_HALF_LCL = 16


def _lcl_wave(s: Scenario, L_s: float, R_s: float, n_half: int, du: float) -> np.ndarray:
    """The periodic current of the motor behind the filter (L1, C1, L2o of
    s.lcl; R_s in the motor's branch, as the plant has) under step 2's
    square wave, +-du from the command of the sample before (ZOH over each
    sample, the exact discrete model), its mean removed."""
    f = s.lcl
    L2 = f.L2o + L_s
    A = np.array([[0.0, -1.0 / f.L1, 0.0], [1.0 / f.C1, 0.0, -1.0 / f.C1],
                  [0.0, 1.0 / L2, -R_s / L2]])
    M = expm(np.block([[A, np.array([[1.0 / f.L1], [0.0], [0.0]])],
                       [np.zeros((1, 4))]]) * s.T_sp)
    Ad, Bd = M[:3, :3], M[:3, 3]
    n2 = 2 * n_half
    v = [du if (k - 1) % n2 < n_half else -du for k in range(n2)]
    acc = np.zeros(3)
    for k in range(n2):
        acc = Ad @ acc + Bd * v[k]
    x = np.linalg.solve(np.eye(3) - np.linalg.matrix_power(Ad, n2), acc)
    out = np.empty(n2)
    for k in range(n2):
        out[k] = x[2]
        x = Ad @ x + Bd * v[k]
    return out - out.mean()


def lcl_inductance(s: Scenario, R_s: float, w: np.ndarray, n_half: int, du: float) -> float:
    """The motor's inductance behind s.lcl from step 2's averaged wave w
    (mean removed): the L_s whose model wave (:func:`_lcl_wave`) is nearest
    in least squares (a bounded search over 1 uH to 10 x the filter's
    inductance; 10 nH to 10 x the filter's)."""
    lo, hi = 1e-8, 10.0 * (s.lcl.L1 + s.lcl.L2o)

    def sse(lg: float) -> float:
        return float(np.sum((_lcl_wave(s, math.exp(lg), R_s, n_half, du) - w) ** 2))

    r = minimize_scalar(sse, bounds=(math.log(lo), math.log(hi)), method="bounded",
                        options={"xatol": 1e-6})
    return float(math.exp(r.x))
