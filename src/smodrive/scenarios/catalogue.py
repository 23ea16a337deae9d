"""Every named scenario of both papers (and their bases) and the drive
compositions, by name."""

from __future__ import annotations

from typing import Callable

from ..model import Scenario
from . import drive, yang2018, yao2022

PAPERS = {"yang2018": yang2018, "yao2022": yao2022}


def catalogue() -> dict[str, Callable[[], Scenario]]:
    """Every named scenario of both papers (and their bases) and the drive
    compositions of :mod:`smodrive.scenarios.drive`, by name."""
    out: dict[str, Callable[[], Scenario]] = {
        "yang2018.base": lambda: yang2018.BASE,
        "yao2022.base": lambda: yao2022.BASE,
    }
    for mod in (*PAPERS.values(), drive):
        out.update(mod.SCENARIOS)
    return out
