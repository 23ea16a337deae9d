"""What every paper module of the catalogue shares: an experiment (a
figure or table of a paper) and its outcome (claims, results, figures)."""

from __future__ import annotations

import dataclasses
import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from ..claims import Claim, ClaimSpecs, load_specs
from ..engine import Engine, Result, simulate
from ..model import Scenario

ProgressFn = Callable[[str, float], None]


@dataclass
class Experiment:
    id: str
    title: str
    run: Callable[[ProgressFn], "Outcome"]


@dataclass
class Outcome:
    claims: list[Claim]
    results: dict[str, Result] = field(default_factory=dict)
    # (name, plot(fig_dir)): the closure writes the figure(s), returns a path or a list of paths
    figures: list[tuple[str, Callable]] = field(default_factory=list)


class Experiments(list):
    """A paper's experiments in the order they are declared; used as a
    decorator on each run function: ``@EXPERIMENTS("yang2018.fig8", "title")``."""

    def __call__(self, id: str, title: str) -> Callable:
        def register(run: Callable[[ProgressFn], Outcome]) -> Callable[[ProgressFn], Outcome]:
            self.append(Experiment(id, title, run))
            return run

        return register


def run_sim(s: Scenario, progress: ProgressFn, **kw) -> Result:
    """simulate() reporting progress under the scenario's name."""
    return simulate(s, progress=lambda f: progress(s.name, f), **kw)


def paper_specs(module_file: str) -> ClaimSpecs:
    """What each claim of a paper module says (statements, units, checks,
    the paper's values, fixed tolerances, their bases and failure reasons):
    the data file beside the module, `<paper>.claims.toml`."""
    return load_specs(Path(module_file).with_suffix(".claims.toml"))


# ------------------------------------------------------ over noise seeds ---
#
# A claim on a peak or a percentile of a noisy run is a random variable: the
# ADC noise seed (Scenario.adc.seed) picks one draw. over_seeds runs the same
# scenario for several seeds and reduces each run to numbers, so that a claim
# can be judged on a stated percentile across seeds, with the median and the
# worst seed reported beside it.

#: the seeds a claim is judged over unless it says otherwise
SEEDS = range(10)


@dataclass(frozen=True)
class SeedStats:
    """One metric over noise seeds: `values[i]` is the run with `seeds[i]`.
    `worst` is the largest value (`higher_is_worse`, e.g. an error) or the
    smallest. Percentiles are nearest-rank (numpy "inverted_cdf"): p90 of 10
    seeds is the 9th smallest value, so 9 of the 10 seeds lie at or below it
    (no interpolation between seeds)."""

    seeds: tuple[int, ...]
    values: tuple[float, ...]
    higher_is_worse: bool = True

    def percentile(self, q: float) -> float:
        v = np.asarray(self.values, dtype=float)
        if not self.higher_is_worse:
            q = 100.0 - q  # the q-th percentile of badness
        return float(np.percentile(v, q, method="inverted_cdf"))

    @property
    def median(self) -> float:
        return float(np.median(np.asarray(self.values, dtype=float)))

    @property
    def worst(self) -> float:
        return float(max(self.values) if self.higher_is_worse else min(self.values))

    @property
    def p90(self) -> float:
        return self.percentile(90.0)

    @property
    def worst_seed(self) -> int:
        return self.seeds[self.values.index(self.worst)]

    def count(self, ok: Callable[[float], bool]) -> int:
        """How many seeds satisfy `ok`."""
        return sum(bool(ok(v)) for v in self.values)

    def __len__(self) -> int:
        return len(self.values)


# the work of one over_seeds call, inherited by forked workers (a metric may
# then be any callable, a lambda or closure included: nothing is pickled but
# the seed and the returned floats)
_SEED_JOBS: dict[int, tuple[Scenario, dict[str, Callable[[Result], float]], dict]] = {}


def with_seed(s: Scenario, seed: int) -> Scenario:
    """`s` with the ADC noise seed `seed`."""
    return s.replace(adc=dataclasses.replace(s.adc, seed=int(seed)))


def _seed_values(job: int, seed: int) -> dict[str, float]:
    s, metrics, kw = _SEED_JOBS[job]
    r = simulate(with_seed(s, seed), **kw)
    return {k: float(f(r)) for k, f in metrics.items()}


def _workers(n_jobs: int) -> int:
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        cores = os.cpu_count() or 1
    return max(1, min(cores, n_jobs))


def over_seeds_multi(
    scenario: Scenario,
    metrics: dict[str, Callable[[Result], float]],
    seeds=SEEDS,
    progress: ProgressFn | None = None,
    runs: dict[int, Result] | None = None,
    higher_is_worse: bool | dict[str, bool] = True,
    **sim_kw,
) -> dict[str, SeedStats]:
    """Several metrics of the same runs (one simulation per seed): metric
    name -> SeedStats. `runs` holds results already simulated, by seed (e.g.
    the run behind a figure), which are reused rather than run again; the
    others run in parallel processes when more than one core is available.
    The values depend only on the seeds, not on the worker count (each run
    is a deterministic function of its scenario). `sim_kw` go to simulate()."""
    seeds = tuple(int(x) for x in seeds)
    if not seeds or len(set(seeds)) != len(seeds):
        raise ValueError(f"over_seeds: seeds must be distinct and not empty, got {seeds}")
    runs = dict(runs or {})
    for seed, r in runs.items():
        if r.scenario != with_seed(scenario, seed):
            raise ValueError(f"over_seeds: the given run of seed {seed} is not of this scenario")
    got: dict[int, dict[str, float]] = {
        seed: {k: float(f(runs[seed])) for k, f in metrics.items()}
        for seed in seeds if seed in runs}
    todo = [seed for seed in seeds if seed not in got]
    label = f"{scenario.name} x{len(seeds)} seeds"

    def tick() -> None:
        if progress is not None:
            progress(label, len(got) / len(seeds))

    job = id(metrics)
    _SEED_JOBS[job] = (scenario, metrics, sim_kw)
    try:
        n_workers = _workers(len(todo))
        fork = "fork" in multiprocessing.get_all_start_methods()
        if n_workers > 1 and fork:
            # whatever the runs share and cache (the LCL observers' tables,
            # seconds to design) is built once here and inherited
            Engine(scenario, sim_kw.get("design"))
            ctx = multiprocessing.get_context("fork")
            with ProcessPoolExecutor(n_workers, mp_context=ctx) as pool:
                futures = {pool.submit(_seed_values, job, seed): seed for seed in todo}
                for fut in as_completed(futures):
                    got[futures[fut]] = fut.result()
                    tick()
        else:
            for seed in todo:
                got[seed] = _seed_values(job, seed)
                tick()
    finally:
        del _SEED_JOBS[job]
    tick()
    worse = (higher_is_worse if isinstance(higher_is_worse, dict)
             else dict.fromkeys(metrics, higher_is_worse))
    return {k: SeedStats(seeds, tuple(got[seed][k] for seed in seeds), worse.get(k, True))
            for k in metrics}


def over_seeds(
    scenario: Scenario,
    metric: Callable[[Result], float],
    seeds=SEEDS,
    progress: ProgressFn | None = None,
    runs: dict[int, Result] | None = None,
    higher_is_worse: bool = True,
    **sim_kw,
) -> SeedStats:
    """`metric` of `scenario` run with each ADC noise seed (adc.seed):
    values per seed, median, worst and percentiles (:class:`SeedStats`).
    Runs in parallel processes when more than one core is available; the
    values do not depend on the worker count. See :func:`over_seeds_multi`."""
    return over_seeds_multi(scenario, {"metric": metric}, seeds, progress, runs,
                            higher_is_worse, **sim_kw)["metric"]
