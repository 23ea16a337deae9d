"""Reproduce a paper: run its experiments, write figures, claims.json and
report.md."""

from __future__ import annotations

import platform
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from .claims import Claim, write_claims
from .scenarios import PAPERS


@dataclass
class Reproduction:
    claims: list[Claim] = field(default_factory=list)
    figures: list[Path] = field(default_factory=list)
    seconds: float = 0.0
    samples: int = 0


def reproduce(
    papers: list[str],
    out: Path,
    on_experiment: Callable[[str, str], None] | None = None,
    on_progress: Callable[[str, float], None] | None = None,
) -> Reproduction:
    out = Path(out)
    fig_dir = out / "figures"
    fig_dir.mkdir(parents=True, exist_ok=True)
    rep = Reproduction()
    t0 = time.perf_counter()
    progress = on_progress or (lambda name, frac: None)
    for paper in papers:
        for exp in PAPERS[paper].EXPERIMENTS:
            if on_experiment:
                on_experiment(exp.id, exp.title)
            outcome = exp.run(progress)
            rep.claims.extend(outcome.claims)
            rep.samples += sum(r.samples for r in outcome.results.values())
            for _, plot in outcome.figures:
                rep.figures.extend(_paths(plot(fig_dir)))
    rep.seconds = time.perf_counter() - t0
    write_claims(rep.claims, out / "claims.json")
    (out / "report.md").write_text(render_report(rep, papers, out))
    return rep


def _paths(written: Path | list[Path] | tuple[Path, ...]) -> list[Path]:
    """What a figure closure returns: the path of its file, or of each file
    when it writes several (all are embedded in the report)."""
    if isinstance(written, (list, tuple)):
        return [Path(p) for p in written]
    return [Path(written)]


def _fmt(x: float | None) -> str:
    if x is None:
        return "-"
    return f"{x:.4g}"


def render_report(rep: Reproduction, papers: list[str], out: Path) -> str:
    n_pass = sum(c.passed for c in rep.claims)
    n_fail = len(rep.claims) - n_pass
    lines = [
        f"# smodrive reproduction: {', '.join(papers)}",
        "",
        f"{n_pass} claims passed, {n_fail} failed. {rep.samples:,} control samples simulated "
        f"in {rep.seconds:.1f} s wall time on {platform.machine()} ({platform.python_version()}).",
        "",
        "| claim | paper | expected | reproduced | unit | criterion | result |",
        "|---|---|---|---|---|---|---|",
    ]
    for c in rep.claims:
        lines.append(
            f"| `{c.id}` | {_fmt(c.paper)} | {_fmt(c.expected)} | {_fmt(c.reproduced)} | "
            f"{c.unit} | {c.describe_check()} | {'pass' if c.passed else '**FAIL**'} |"
        )
    lines += ["", "## Statements and tolerances", ""]
    for c in rep.claims:
        lines.append(f"- **{c.id}** ({'pass' if c.passed else 'FAIL'}): {c.statement}"
                     + (f" *Tolerance:* {c.basis}." if c.basis else ""))
    lines += ["", "## Figures", ""]
    for f in rep.figures:
        rel = f.relative_to(out)
        lines.append(f"![{f.stem}]({rel.as_posix()})")
        lines.append("")
    return "\n".join(lines) + "\n"
