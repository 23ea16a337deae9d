"""What every paper module of the catalogue shares: an experiment (a
figure or table of a paper) and its outcome (claims, results, figures)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

from ..claims import Claim
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


def run_sim(s: Scenario, progress: ProgressFn, **kw) -> Result:
    """simulate() reporting progress under the scenario's name."""
    return simulate(s, progress=lambda f: progress(s.name, f), **kw)
