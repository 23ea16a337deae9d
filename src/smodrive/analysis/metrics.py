"""Metrics of logged signals."""

from __future__ import annotations

import math

import numpy as np


def wrap(x: np.ndarray) -> np.ndarray:
    """Wrap angles to [-pi, pi)."""
    return (x + np.pi) % (2 * np.pi) - np.pi


def rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.square(x))))


def ripple_dq(i_d: np.ndarray, i_q: np.ndarray) -> float:
    """RMS of i_d and i_q about their means, sqrt(var(i_d) + var(i_q)), A."""
    return float(np.sqrt(np.var(i_d) + np.var(i_q)))


def sine_amplitude(t: np.ndarray, x: np.ndarray, f: float) -> complex:
    """Complex amplitude of the component of x at frequency f (least squares
    with a constant), so that x ~ Re{A e^{j 2 pi f t}} + c."""
    w = 2 * np.pi * f
    M = np.column_stack([np.cos(w * t), -np.sin(w * t), np.ones_like(t)])
    coef, *_ = np.linalg.lstsq(M, x, rcond=None)
    return complex(coef[0], coef[1])


def scaling_rotation(gain_abc: tuple[float, float, float]) -> float:
    """Angle (rad) by which per-phase ADC gains rotate the measured current
    vector, on average, when phases a and b are measured and c = -a - b (as
    the controllers of smodrive do; the gain of phase c is not used).

    With x_a = g_a i_a, x_b = g_b i_b and the amplitude-invariant Clarke
    transform, i_meas = k1 i + k2 conj(i) with
    k1 = 1 + (e_a + e_b)/2 + j (e_a - e_b)/(2 sqrt 3), e_x = g_x - 1.
    The k2 part turns at -2 w in the rotor frame (the 2 f_e disturbance of
    yao2022 Sec. IV-A); k1 is constant there: a gain and a rotation arg(k1).
    """
    e_a, e_b = gain_abc[0] - 1.0, gain_abc[1] - 1.0
    return math.atan2((e_a - e_b) / (2.0 * math.sqrt(3.0)), 1.0 + 0.5 * (e_a + e_b))
