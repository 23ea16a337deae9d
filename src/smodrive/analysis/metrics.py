"""Metrics of logged signals."""

from __future__ import annotations

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
