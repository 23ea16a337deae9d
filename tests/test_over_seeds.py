"""over_seeds: a metric over ADC noise seeds, in parallel, deterministic."""

from __future__ import annotations

import numpy as np
import pytest

from smodrive.model import RPM, Profile
from smodrive.scenarios import common
from smodrive.scenarios import yao2022 as y
from smodrive.engine import simulate


def short() -> "y.Scenario":
    return y.steady(30e3, name="over_seeds.short").replace(duration=0.01)


def peak(r) -> float:
    return float(np.max(np.abs(r.theta_error)))


def test_seed_stats_percentiles():
    st = common.SeedStats(tuple(range(10)), tuple(float(v) for v in range(10, 0, -1)))
    assert st.median == 5.5
    assert st.worst == 10.0 and st.worst_seed == 0
    assert st.p90 == 9.0  # nearest rank: 9 of the 10 values at or below
    assert st.percentile(50) == 5.0
    assert st.count(lambda v: v <= 9.0) == 9
    low = common.SeedStats((0, 1, 2), (1.0, 2.0, 3.0), higher_is_worse=False)
    assert low.worst == 1.0 and low.percentile(90) == 1.0


def test_over_seeds_deterministic_and_seeded(monkeypatch):
    s = short()
    par = common.over_seeds(s, peak, seeds=range(4))
    monkeypatch.setattr(common, "_workers", lambda n: 1)
    ser = common.over_seeds(s, peak, seeds=range(4))
    assert par.values == ser.values  # whatever the worker count
    assert par.seeds == (0, 1, 2, 3)
    assert len(set(par.values)) == 4  # the seed reaches the noise
    one = simulate(common.with_seed(s, 2))
    assert par.values[2] == peak(one)


def test_over_seeds_reuses_given_runs_and_lambdas(monkeypatch):
    s = short()
    r1 = simulate(common.with_seed(s, 1))
    calls = []
    real = common._seed_values
    monkeypatch.setattr(common, "_seed_values", lambda job, seed: calls.append(seed) or
                        real(job, seed))
    monkeypatch.setattr(common, "_workers", lambda n: 1)
    st = common.over_seeds_multi(s, {"peak": peak, "mean": lambda r: float(np.mean(r["i_g"]))},
                                 seeds=(1, 3), runs={1: r1})
    assert calls == [3]
    assert st["peak"].values[0] == peak(r1)
    with pytest.raises(ValueError):
        common.over_seeds(s, peak, seeds=(1,), runs={1: simulate(s.replace(duration=0.005))})
