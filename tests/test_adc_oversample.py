"""ADC oversampling (adc.n_oversample = N): each sample the mean of N
conversions, each with the channel's gain and offset, its own noise draw and
its own quantisation (the burst's duration neglected)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy import stats

from smodrive.model import Scenario
from smodrive.engine.plant import Plant


def _plant(n: int | None, noise: float, bits: int, i_d0: float = 0.0, i_q0: float = 0.0,
           seed: int = 7, **cfg) -> Plant:
    s = Scenario()
    adc = dataclasses.replace(s.adc, noise=noise, bits=bits, seed=seed,
                              **({} if n is None else {"n_oversample": n}))
    return Plant(s.replace(adc=adc, w_M0=0.0, theta_r0=0.0), i_d0=i_d0, i_q0=i_q0, **cfg)


def _samples(p: Plant, m: int) -> np.ndarray:
    return np.array([p.sample() for _ in range(m)])


def test_one_conversion_is_today():
    """N = 1 (the default) and the C config's 0 both take one conversion a
    channel: the same readings as a plant built without the field."""
    ref = _samples(_plant(None, 0.02, 12, 1.0, 2.0), 50)
    assert np.array_equal(_samples(_plant(1, 0.02, 12, 1.0, 2.0), 50), ref)
    assert np.array_equal(_samples(_plant(1, 0.02, 12, 1.0, 2.0, adc_n_oversample=0), 50), ref)


def test_each_conversion_draws_its_own_noise():
    """N = 4, no quantisation: channel a's reading minus the true value is
    the mean of the first four normal draws, which a one-conversion plant
    with the same seed gives as its a, b, c, a noise of two samples."""
    x = np.array([1.0, -0.5, -0.5])
    one = _samples(_plant(1, 0.05, 0, 1.0), 2) - x
    four = _plant(4, 0.05, 0, 1.0).sample()
    draws = one.ravel()[:4]
    assert four[0] - x[0] == pytest.approx(draws.mean(), abs=1e-15)


@pytest.mark.parametrize("n", [1, 4, 16, 64])
def test_noise_falls_as_one_over_sqrt_n(n):
    """Standard deviation of the averaged reading sigma / sqrt(N), judged by
    the chi-square distribution of the sample variance (k - 1) s^2 /
    sigma_N^2 ~ chi2(k - 1), k = 3 x 3000 readings, two-sided at 1e-6."""
    sigma, m = 0.05, 3000
    x = np.array([1.0, -0.5, -0.5])
    r = _samples(_plant(n, sigma, 0, 1.0), m) - x
    k = r.size
    s2 = r.var(ddof=1)
    sigma_n2 = sigma**2 / n
    lo, hi = stats.chi2.ppf([1e-6, 1 - 1e-6], k - 1) / (k - 1)
    assert lo < s2 / sigma_n2 < hi, (n, math.sqrt(s2 / sigma_n2))
    assert abs(r.mean()) < 6 * math.sqrt(sigma_n2 / k)


def test_quantisation_with_noise_dithers():
    """A current 0.3 LSB above a code: without noise every conversion reads
    the code (oversampling cannot help), with 0.5 LSB of noise the mean of
    16 conversions resolves LSB/16 and its average over readings finds the
    true value."""
    s = Scenario()
    lsb = 2 * s.adc.full_scale / 2**s.adc.bits
    x_a = 0.3 * lsb
    # phase a = i_alpha at theta = 0; b, c = -x_a/2 (rounded to 0 or -1 code)
    quiet = _samples(_plant(16, 0.0, s.adc.bits, x_a), 10)[:, 0]
    assert np.all(quiet == 0.0)
    noisy = _samples(_plant(16, 0.5 * lsb, s.adc.bits, x_a), 4000)[:, 0]
    steps = noisy / (lsb / 16)
    assert np.allclose(steps, np.round(steps), atol=1e-9)  # multiples of LSB/16
    assert len(np.unique(noisy)) > 4
    # mean over 4000 readings: standard error about 0.5 LSB / sqrt(64000)
    assert noisy.mean() == pytest.approx(x_a, abs=0.02 * lsb)
    # one conversion with the same noise is unbiased too, but much noisier
    single = _samples(_plant(1, 0.5 * lsb, s.adc.bits, x_a), 4000)[:, 0]
    assert single.std() > 3 * noisy.std()
