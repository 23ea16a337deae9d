"""Claims: one checkable statement each, the paper's value (or an analytic
prediction) beside the reproduced one, with a tolerance and a verdict."""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Literal

Check = Literal["abs", "rel", "max", "min"]


@dataclass
class Claim:
    id: str
    statement: str
    paper: float | None
    expected: float | None
    reproduced: float
    unit: str
    tolerance: float
    check: Check = "abs"
    passed: bool = False
    basis: str = ""  # why the tolerance is what it is
    why_fail: str = ""  # the reason, stated in the claim if it fails

    def __post_init__(self) -> None:
        # plain Python numbers (NumPy scalars do not serialise to JSON)
        for name in ("paper", "expected", "reproduced", "tolerance"):
            v = getattr(self, name)
            if v is not None:
                setattr(self, name, float(v))
        self.passed = bool(self.evaluate())
        if not self.passed and "FAILS" not in self.statement:
            self.statement += f" FAILS: {self.describe_check()}, reproduced {self.reproduced:.4g}."
            if self.why_fail:
                self.statement += f" Why: {self.why_fail}"

    @property
    def target(self) -> float | None:
        return self.expected if self.expected is not None else self.paper

    def describe_check(self) -> str:
        ref = "expected" if self.expected is not None else "paper"
        return {
            "abs": f"|reproduced - {ref}| <= {self.tolerance:g} {self.unit}",
            "rel": f"|reproduced / {ref} - 1| <= {self.tolerance:g}",
            "max": f"reproduced <= {self.tolerance:g} {self.unit}",
            "min": f"reproduced >= {self.tolerance:g} {self.unit}",
        }[self.check]

    def evaluate(self) -> bool:
        r = self.reproduced
        if r is None or not math.isfinite(r):
            return False
        if self.check == "max":
            return r <= self.tolerance
        if self.check == "min":
            return r >= self.tolerance
        tgt = self.target
        if tgt is None:
            return False
        if self.check == "abs":
            return abs(r - tgt) <= self.tolerance
        return abs(r / tgt - 1.0) <= self.tolerance

    def to_json(self) -> dict:
        d = asdict(self)
        d["criterion"] = self.describe_check()
        return d


def write_claims(claims: list[Claim], path: Path) -> None:
    path.write_text(json.dumps([c.to_json() for c in claims], indent=2) + "\n")
