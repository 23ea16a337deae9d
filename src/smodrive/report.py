"""Reproduce a paper: run its experiments, write figures, claims.json and
report.md."""

from __future__ import annotations

import os
import platform
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Collection

from .claims import KINDS, Claim, count, describe_counts, write_claims
from .engine import _ffi
from .scenarios import PAPERS


@dataclass
class Reproduction:
    claims: list[Claim] = field(default_factory=list)
    figures: list[Path] = field(default_factory=list)
    seconds: float = 0.0
    samples: int = 0
    # (experiment id, title, the figures its outcome wrote), in run order
    sections: list[tuple[str, str, list[Path]]] = field(default_factory=list)


def _pngs(fig_dir: Path) -> dict[Path, int]:
    return {p: p.stat().st_mtime_ns for p in fig_dir.glob("*.png")}


def reproduce(
    papers: list[str],
    out: Path,
    on_experiment: Callable[[str, str], None] | None = None,
    on_progress: Callable[[str, float], None] | None = None,
    only: Collection[str] | None = None,
) -> Reproduction:
    """Run the experiments of `papers` (only those whose id is in `only`,
    when given) and write their figures, claims.json and report.md to
    `out`."""
    out = Path(out)
    fig_dir = out / "figures"
    fig_dir.mkdir(parents=True, exist_ok=True)
    rep = Reproduction()
    t0 = time.perf_counter()
    progress = on_progress or (lambda name, frac: None)
    for paper in papers:
        for exp in PAPERS[paper].EXPERIMENTS:
            if only is not None and exp.id not in only:
                continue
            if on_experiment:
                on_experiment(exp.id, exp.title)
            outcome = exp.run(progress)
            rep.claims.extend(outcome.claims)
            rep.samples += sum(r.samples for r in outcome.results.values())
            made: list[Path] = []
            for _, plot in outcome.figures:
                before = _pngs(fig_dir)
                made += _paths(plot(fig_dir))
                # a figure a closure writes without returning it is shown too
                made += sorted(p for p, t in _pngs(fig_dir).items() if before.get(p) != t)
            made = list(dict.fromkeys(p.resolve() for p in made))
            rep.figures.extend(made)
            rep.sections.append((exp.id, exp.title, made))
    rep.seconds = time.perf_counter() - t0
    write_claims(rep.claims, out / "claims.json")
    (out / "report.md").write_text(render_report(rep, papers, out), encoding="utf-8")
    return rep


def gallery(paper: str, quick: Collection[str]) -> Reproduction:
    """A gallery page's reproduction of `paper` (examples/plot_reproduce_*):
    every experiment, or those of `quick` in the documentation build
    (SMODRIVE_GALLERY_QUICK set), into a temporary folder; prints each
    claim with its verdict and shows each figure."""
    import matplotlib.pyplot as plt

    short = bool(os.environ.get("SMODRIVE_GALLERY_QUICK"))
    rep = reproduce([paper], Path(tempfile.mkdtemp()), only=quick if short else None)
    for c in rep.claims:
        print(f"{c.status:12s} {c.id}: reproduced {_fmt(c.reproduced)} {c.unit} "
              f"({c.describe_check()})")
    for png in rep.figures:
        fig, ax = plt.subplots(figsize=(9, 6), layout="constrained")
        ax.imshow(plt.imread(png))
        ax.set_axis_off()
        ax.set_title(png.stem)
    return rep


def _paths(written: Path | list[Path] | tuple[Path, ...]) -> list[Path]:
    """What a figure closure returns: the path of its file, or of each file
    when it writes several (all are embedded in the report)."""
    if isinstance(written, (list, tuple)):
        return [Path(p) for p in written]
    return [Path(written)]


def _fmt(x: float | None) -> str:
    if x is None or x != x:
        return "-"
    return f"{x:.4g}"


def cell(text: str) -> str:
    r"""Text as one cell of a GitHub/CommonMark-extension table: ``|``
    escaped (also inside code spans, where the table parser splits first),
    line breaks as spaces.

    >>> print(cell("|rep - exp| <= 0.1 A"))
    \|rep - exp\| <= 0.1 A
    """
    return str(text).replace("\\|", "|").replace("|", "\\|").replace("\r", " ").replace(
        "\n", " ")


RESULT = {"pass": "pass", "fail": "**FAIL**", "not measured": "not measured"}


def _rel(f: Path, out: Path) -> str:
    try:
        return Path(f).resolve().relative_to(Path(out).resolve()).as_posix()
    except ValueError:
        return Path(f).as_posix()


def render_report(rep: Reproduction, papers: list[str], out: Path) -> str:
    """report.md: the claims table (one row of eight cells per claim in any
    Markdown renderer), each claim's statement and tolerance, and every
    figure of the run under its experiment."""
    n = count(rep.claims)
    lines = [
        f"# smodrive reproduction: {', '.join(papers)}",
        "",
        f"{n['pass']} claims passed, {n['fail']} failed"
        + (f", {n['not measured']} not measured" if n["not measured"] else "")
        + f". {rep.samples:,} control samples simulated in {rep.seconds:.1f} s wall time on "
        f"{platform.machine()} ({platform.python_version()}), the {_ffi.MATH} build of the "
        "core (docs/firmware.md).",
        "",
        f"By kind: {describe_counts(rep.claims)}. A claim against the paper's numbers compares "
        "with a value or a statement of the paper; one against the paper's own equations with "
        "a prediction computed from them before the run; a method check measures a method of "
        "ours against another measurement or the drive's design; an analytic check exercises "
        "no smodrive code and is not counted.",
        "",
        "| claim | kind | paper | expected | reproduced | unit | criterion | result |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for c in rep.claims:
        cells = [f"`{c.id}`", c.kind, _fmt(c.paper), _fmt(c.expected), _fmt(c.reproduced),
                 c.unit, c.describe_check(), RESULT[c.status]]
        lines.append("| " + " | ".join(cell(x) for x in cells) + " |")
    lines += ["", "## Statements and tolerances", ""]
    for c in rep.claims:
        verdict = {"pass": "pass", "fail": "FAIL", "not measured": "not measured"}[c.status]
        lines.append(f"- **{c.id}** ({verdict}; {KINDS[c.kind]}): {c.statement}"
                     + (f" *Tolerance:* {c.basis}." if c.basis else ""))
    lines += ["", "## Figures", ""]
    shown = set()
    sections = rep.sections or [("", "", list(rep.figures))]
    for exp_id, title, figs in sections:
        if not figs:
            continue
        if exp_id:
            lines += [f"### {exp_id}: {title}", ""]
        for f in figs:
            shown.add(Path(f))
            lines += [f"![{Path(f).stem}]({_rel(f, out)})", ""]
    rest = [f for f in rep.figures if Path(f) not in shown]
    for f in rest:
        lines += [f"![{Path(f).stem}]({_rel(f, out)})", ""]
    return "\n".join(lines) + "\n"
