"""The papers' experiments as data: scenario catalogues and their claims
(:mod:`.yang2018`, :mod:`.yao2022`), the drive compositions
(:mod:`.drive`), trial profiles for any motor (:mod:`.trials`) and the
firmware test's cases (:mod:`.target_cases`)."""

from .catalogue import PAPERS, catalogue

__all__ = ["PAPERS", "catalogue"]
