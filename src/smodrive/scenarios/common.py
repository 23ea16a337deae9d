"""What every paper module of the catalogue shares: an experiment (a
figure or table of a paper) and its outcome (claims, results, figures)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..claims import Claim, ClaimSpecs, load_specs
from ..simulate import Result, simulate
from ..params import Scenario

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
