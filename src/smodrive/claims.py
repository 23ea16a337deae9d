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


# ------------------------------------------------------ claims as data ---

@dataclass(frozen=True)
class ClaimSpec:
    """What a claim says, as data (a paper's `<paper>.claims.toml`): the
    statement (with `{name}` fields filled by the run), unit, check, the
    paper's value and the tolerance where they are fixed, the basis of the
    tolerance and the reason stated if it fails. The run supplies the
    reproduced value (and what it computes: expected, tolerance, fields)."""

    id: str
    statement: str
    unit: str = ""
    check: Check = "abs"
    paper: float | None = None
    tolerance: float | None = None
    basis: str = ""
    why_fail: str = ""

    def make(self, reproduced: float, expected: float | None = None, *,
             paper: float | None = None, tolerance: float | None = None, **fields) -> Claim:
        """The claim of one run; `fields` fill `{name}` in the texts."""
        tol = self.tolerance if tolerance is None else tolerance
        if tol is None:
            raise ValueError(f"{self.id}: no tolerance in the data or from the run")
        return Claim(
            id=self.id, statement=self.statement.format(**fields),
            paper=self.paper if paper is None else paper, expected=expected,
            reproduced=reproduced, unit=self.unit, tolerance=tol, check=self.check,
            basis=self.basis.format(**fields), why_fail=self.why_fail.format(**fields))


def load_specs(path: Path) -> dict[str, ClaimSpec]:
    """Every claim of a `<paper>.claims.toml` by id (tables keyed by id;
    keys of ClaimSpec; unknown keys are an error)."""
    import tomllib

    data = tomllib.loads(Path(path).read_text())
    names = set(ClaimSpec.__dataclass_fields__) - {"id"}
    out = {}
    for cid, spec in data.items():
        unknown = set(spec) - names
        if unknown:
            raise ValueError(f"{path}: claim {cid}: unknown keys {sorted(unknown)}")
        out[cid] = ClaimSpec(id=cid, **spec)
    return out
