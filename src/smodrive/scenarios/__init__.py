"""The papers' experiments as data: scenario catalogues and their claims
(:mod:`smodrive.scenarios.yang2018`, :mod:`smodrive.scenarios.yao2022`), the drive compositions
(:mod:`smodrive.scenarios.drive`), trial profiles for any motor (:mod:`smodrive.scenarios.trials`) and the
firmware test's cases (:mod:`smodrive.scenarios.target_cases`)."""

from .catalogue import PAPERS, catalogue

__all__ = ["PAPERS", "catalogue"]
