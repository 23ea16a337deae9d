"""Harmonics of the regular-sampled PWM leg voltage (yao2022 Table I).

Two independent routes: the exact Fourier integral of the pulses the plant's
own edge function produces, and the Jacobi-Anger (Bessel) series of
symmetric regular sampling (Holmes and McGrath's baseband term plus the
carrier sidebands that alias onto the baseband).
"""

from __future__ import annotations

import cmath
import math

import numpy as np
from scipy.special import jv

from ..engine.plant import leg_edges


def leg_harmonics_from_edges(V_Q: float, M: float, N: int, nmax: int,
                             T: float = 50e-6, t_dead: float = 0.0) -> np.ndarray:
    """Amplitudes of harmonics 1..nmax of the leg voltage (0..V_Q) over one
    fundamental period N T: exact integrals of the pulses [kT + t_on, kT + t_off)
    from the plant's edge function, duties d_k = (1 + M cos(w_e k T)) / 2
    sampled at the carrier peaks t_k = k T."""
    Te = N * T
    we = 2 * math.pi / Te
    amps = []
    for n in range(1, nmax + 1):
        c = 0j
        for k in range(N):
            d = 0.5 * (1 + M * math.cos(we * k * T))
            t_on, t_off = leg_edges(T, t_dead, d, 0.0)
            ta, tb = k * T + t_on, k * T + t_off
            c += V_Q * (cmath.exp(-1j * n * we * tb) - cmath.exp(-1j * n * we * ta)) / (
                -1j * n * we)
        amps.append(abs(2.0 / Te * c))
    return np.array(amps)


def leg_harmonics_bessel(V_Q: float, M: float, N: int, nmax: int, l_max: int = 3) -> np.ndarray:
    """Same amplitudes from the Bessel series: pulse k centred at (k + 1/2) T
    of width d_k T gives c_n = (2 V_Q N / (n pi)) e^{-j n pi / N}
    sum_l (e^{j b} j^m - e^{-j b} (-j)^m) / (2j) J_m(b M), m = n + l N,
    b = n pi / (2 N)."""
    out = []
    for n in range(1, nmax + 1):
        beta = n * math.pi / (2 * N)
        tot = 0j
        for l in range(-l_max, l_max + 1):
            mm = n + l * N
            tot += (cmath.exp(1j * beta) * 1j**mm - cmath.exp(-1j * beta) * (-1j) ** mm) / (
                2j) * jv(mm, beta * M)
        out.append(abs(2 * V_Q * N / (n * math.pi) * cmath.exp(-1j * n * math.pi / N) * tot))
    return np.array(out)
