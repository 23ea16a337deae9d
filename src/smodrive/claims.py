"""Claims: one checkable statement each, the paper's value (or an analytic
prediction) beside the reproduced one, with a tolerance and a verdict."""

from __future__ import annotations

import json
import math
import re
import string
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Literal

from ._util import tomllib

Check = Literal["abs", "rel", "max", "min"]

#: what a claim compares, counted apart (README, report.md): the paper's own
#: numbers (a value read from a table or a figure, or a statement such as
#: 'i_d kept at zero'); a prediction from the paper's own equations (exact or
#: linearised, computed before looking at the result); a check of a method of
#: ours (one measurement against another, or against the drive's own design);
#: and analytic checks, where no smodrive code is under test (outside the count)
KINDS: dict[str, str] = {
    "paper": "against the paper's numbers",
    "equation": "against the paper's own equations",
    "method": "method checks",
    "analytic": "analytic checks (no smodrive code under test; not counted)",
}
COUNTED_KINDS = ("paper", "equation", "method")


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
    # why the run could not measure it (a tool missing, ...): neither a pass
    # nor a fail; its reproduced value is NaN
    not_measured: str = ""
    kind: str = "method"  # one of KINDS

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"{self.id}: kind {self.kind!r} is not one of {', '.join(KINDS)}")
        self._check()

    def _check(self) -> None:
        # plain Python numbers (NumPy scalars do not serialise to JSON)
        for name in ("paper", "expected", "reproduced", "tolerance"):
            v = getattr(self, name)
            if v is not None:
                setattr(self, name, float(v))
        if self.not_measured:
            # the reason as one line of at most 240 characters (a failed
            # build's first compiler error, not the compiler's whole output)
            first = (str(self.not_measured).strip().splitlines() or ["not measured"])[0].strip()
            self.not_measured = first if len(first) <= 240 else first[:237] + "..."
            self.reproduced = float("nan")
            self.passed = False
            if "NOT MEASURED" not in self.statement:
                self.statement += f" NOT MEASURED: {self.not_measured}"
            return
        self.passed = bool(self.evaluate())
        if not self.passed and "FAILS" not in self.statement:
            self.statement += f" FAILS: {self.describe_check()}, reproduced {self.reproduced:.4g}."
            if self.why_fail:
                self.statement += f" Why: {self.why_fail}"

    @property
    def status(self) -> str:
        """"pass", "fail" or "not measured"."""
        return "not measured" if self.not_measured else "pass" if self.passed else "fail"

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
        }[self.check].rstrip()

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
        d["status"] = self.status
        if self.not_measured:
            d["reproduced"] = None  # strict JSON: no NaN
        return d


def count(claims: list[Claim]) -> dict[str, int]:
    """How many claims passed, failed and could not be measured (the
    analytic checks left out: they test no smodrive code)."""
    out = {"pass": 0, "fail": 0, "not measured": 0}
    for c in claims:
        if c.kind in COUNTED_KINDS:
            out[c.status] += 1
    return out


def count_by_kind(claims: list[Claim]) -> dict[str, dict[str, int]]:
    """:func:`count` for each kind of :data:`KINDS` (analytic included)."""
    return {k: {"pass": sum(c.kind == k and c.status == "pass" for c in claims),
                "fail": sum(c.kind == k and c.status == "fail" for c in claims),
                "not measured": sum(c.kind == k and c.status == "not measured"
                                    for c in claims)}
            for k in KINDS}


def describe_counts(claims: list[Claim]) -> str:
    """The counts by kind in one sentence (report.md, the CLI)."""
    parts = []
    for k, n in count_by_kind(claims).items():
        total = sum(n.values())
        if total:
            parts.append(f"{KINDS[k]}: {n['pass']} of {total} pass"
                         + (f", {n['not measured']} not measured" if n["not measured"] else ""))
    return "; ".join(parts)


def write_claims(claims: list[Claim], path: Path) -> None:
    path.write_text(json.dumps([c.to_json() for c in claims], indent=2) + "\n")


# ------------------------------------------------------ claims as data ---
#
# A paper's claims live in `<paper>.claims.toml` beside its scenario module:
# one table per claim id (or per family of ids, the id holding `{fields}`),
# with the statement, unit, check, the paper's value and the tolerance where
# they are fixed, the basis of the tolerance and the reason stated if the
# claim fails. Texts shared by several claims sit in the table `[text]` and
# are referenced as `{text.NAME}`. The run supplies what it measures.

SPEC_KEYS = ("statement", "kind", "unit", "check", "paper", "tolerance", "basis", "why_fail")
CHECKS = ("abs", "rel", "max", "min")
TEXT_TABLE = "text"
# arguments of ClaimSpec.make, so not available as field names
_RESERVED = {"reproduced", "expected", "paper", "tolerance"}

_formatter = string.Formatter()


def _field_names(text: str, where: str) -> set[str]:
    """The `{name}` fields of a text (format specs allowed, `{{` escapes);
    positional, indexed or attribute fields are an error."""
    names = set()
    try:
        parsed = list(_formatter.parse(text))
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from None
    for _, name, _, conv in parsed:
        if name is None:
            continue
        if not name.isidentifier() or name in _RESERVED or conv:
            raise ValueError(f"{where}: field {{{name}}} is not a plain name "
                             f"(or is one of {sorted(_RESERVED)})")
        names.add(name)
    return names


@dataclass(frozen=True)
class ClaimSpec:
    """What a claim says, as data: the statement (with `{name}` fields
    filled by the run), unit, check, the paper's value and the tolerance
    where they are fixed, the basis of the tolerance and the reason stated if
    it fails. The id may hold fields too (one spec for a family, e.g. per
    speed); `paper` and `tolerance` are then a number for every member or a
    table by concrete claim id. The run supplies the reproduced value (and
    what it computes: expected, a computed tolerance, the fields)."""

    id: str
    statement: str
    kind: str = ""
    unit: str = ""
    check: Check = "abs"
    paper: float | dict[str, float] | None = None
    tolerance: float | dict[str, float] | None = None
    basis: str = ""
    why_fail: str = ""

    def __post_init__(self) -> None:
        if self.check not in CHECKS:
            raise ValueError(f"{self.id}: check {self.check!r} is not one of {CHECKS}")
        if self.kind not in KINDS:
            raise ValueError(f"{self.id}: kind {self.kind!r} is not one of {', '.join(KINDS)} "
                             "(every claim says what it compares)")
        for name in ("id", "statement", "unit", "basis", "why_fail"):
            if not isinstance(getattr(self, name), str):
                raise ValueError(f"{self.id}: {name} must be a string")
        self.fields()  # the texts parse, with plain names only
        for name in ("paper", "tolerance"):
            v = getattr(self, name)
            values = v.values() if isinstance(v, dict) else [] if v is None else [v]
            if not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in values):
                raise ValueError(f"{self.id}: {name} must be a number or a table of numbers "
                                 "by claim id")
            if isinstance(v, dict):
                bad = [k for k in v if not self.matches(k)]
                if bad:
                    raise ValueError(f"{self.id}: {name} for ids not of this spec: {bad}")

    def fields(self) -> set[str]:
        """The names the run must supply (in the id and the texts)."""
        return set().union(*(_field_names(getattr(self, k), f"{self.id}: {k}")
                             for k in ("id", "statement", "basis", "why_fail")))

    def matches(self, cid: str) -> bool:
        """Whether the concrete claim id `cid` is a member of this spec."""
        pattern = "".join(re.escape(lit) + ("" if name is None else ".+?")
                          for lit, name, _, _ in _formatter.parse(self.id))
        return re.fullmatch(pattern, cid) is not None

    def ids(self) -> set[str] | None:
        """The concrete ids the data names (the id itself without fields, the
        keys of a `paper` or `tolerance` table), or None if only the run
        can tell."""
        if not _field_names(self.id, self.id):
            return {self.id}
        keys = set()
        for v in (self.paper, self.tolerance):
            if isinstance(v, dict):
                keys |= set(v)
        return keys or None

    def _fixed(self, name: str, cid: str, from_run: float | None) -> float | None:
        data = getattr(self, name)
        if data is not None and from_run is not None:
            raise ValueError(f"{cid}: {name} is fixed in the data and given by the run")
        if isinstance(data, dict):
            if cid not in data:
                raise ValueError(f"{cid}: no {name} for this id in the table of {self.id}")
            return data[cid]
        return data if from_run is None else from_run

    def make(self, reproduced: float, /, expected: float | None = None, *,
             paper: float | None = None, tolerance: float | None = None,
             not_measured: str = "", **fields) -> Claim:
        """The claim of one run; `fields` fill `{name}` in the id and texts.
        A field the texts need and the run does not give, or one it gives
        that no text uses, is an error (so neither text nor number is lost).
        `not_measured`: why the run could not measure the claim (it is then
        neither passed nor failed)."""
        need = self.fields()
        missing, unused = need - set(fields), set(fields) - need
        if missing or unused:
            raise ValueError(f"{self.id}: unfilled fields {sorted(missing)}, "
                             f"unused fields {sorted(unused)}")
        cid = self.id.format(**fields)
        tol = self._fixed("tolerance", cid, tolerance)
        if tol is None:
            raise ValueError(f"{cid}: no tolerance in the data or from the run")
        return Claim(
            id=cid, statement=self.statement.format(**fields),
            paper=self._fixed("paper", cid, paper), expected=expected,
            reproduced=reproduced, unit=self.unit, tolerance=tol, check=self.check,
            basis=self.basis.format(**fields), why_fail=self.why_fail.format(**fields),
            not_measured=not_measured, kind=self.kind)


class ClaimSpecs(Mapping[str, ClaimSpec]):
    """The specs of one data file by (template) id, and `claim(id, ...)` to
    build a claim from one of them."""

    def __init__(self, specs: dict[str, ClaimSpec], path: Path | None = None):
        self._specs = dict(specs)
        self.path = path

    def __getitem__(self, key: str) -> ClaimSpec:
        try:
            return self._specs[key]
        except KeyError:
            raise KeyError(f"no claim spec {key!r} in {self.path}") from None

    def __iter__(self):
        return iter(self._specs)

    def __len__(self) -> int:
        return len(self._specs)

    def claim(self, key: str, reproduced: float, /, expected: float | None = None,
              **kw) -> Claim:
        """`self[key].make(reproduced, expected, **kw)`."""
        return self[key].make(reproduced, expected, **kw)

    def spec_of(self, cid: str) -> ClaimSpec | None:
        """The spec a concrete claim id belongs to (None if none; an error if
        the templates are ambiguous)."""
        hits = [s for s in self._specs.values() if s.matches(cid)]
        if len(hits) > 1:
            raise ValueError(f"{cid} matches several specs: {[s.id for s in hits]}")
        return hits[0] if hits else None


def _shared_texts(data: dict, path: Path) -> dict[str, str]:
    texts = data.pop(TEXT_TABLE, {})
    if not isinstance(texts, dict) or not all(isinstance(v, str) for v in texts.values()):
        raise ValueError(f"{path}: [{TEXT_TABLE}] must hold strings")
    return texts


def load_specs(path: Path) -> ClaimSpecs:
    """Every claim spec of a `<paper>.claims.toml` by id: tables keyed by
    (template) id with the keys of ClaimSpec, and the optional `[text]` table
    of shared texts referenced as `{text.NAME}`. Unknown keys, missing
    statements, unknown or unused shared texts are errors."""
    path = Path(path)
    data = tomllib.loads(path.read_text())
    texts = _shared_texts(data, path)
    used: set[str] = set()
    ref = re.compile(r"\{" + TEXT_TABLE + r"\.(\w+)\}")

    def expand(text: str, where: str) -> str:
        def sub(m: re.Match) -> str:
            if m.group(1) not in texts:
                raise ValueError(f"{path}: {where}: no shared text {m.group(0)}")
            used.add(m.group(1))
            return texts[m.group(1)]
        return ref.sub(sub, text)

    out = {}
    for cid, spec in data.items():
        if not isinstance(spec, dict):
            raise ValueError(f"{path}: {cid} is not a table")
        unknown = set(spec) - set(SPEC_KEYS)
        if unknown:
            raise ValueError(f"{path}: claim {cid}: unknown keys {sorted(unknown)}")
        if "statement" not in spec:
            raise ValueError(f"{path}: claim {cid}: no statement")
        spec = {k: expand(v, f"{cid}.{k}") if isinstance(v, str) else v
                for k, v in spec.items()}
        out[cid] = ClaimSpec(id=cid, **spec)
    orphans = set(texts) - used
    if orphans:
        raise ValueError(f"{path}: shared texts used by no claim: {sorted(orphans)}")
    return ClaimSpecs(out, path)
