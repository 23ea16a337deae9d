"""Command line: `smodrive run SCENARIO.toml --out DIR`,
`smodrive reproduce [PAPER ...] --out DIR`, `smodrive scenarios`."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click
import numpy as np
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from .params import ParameterError
from .scenario_io import load_scenario, scenario_to_toml
from .scenarios import PAPERS, catalogue

console = Console(stderr=True)


def _progress() -> Progress:
    return Progress(
        TextColumn("[bold]{task.description}"),
        BarColumn(),
        TextColumn("{task.percentage:>3.0f}%"),
        TimeElapsedColumn(),
        console=console,
        transient=False,
    )


@click.group()
@click.version_option(package_name="smodrive")
def main() -> None:
    """smodrive: sliding-mode observer based PMSM drive control."""


@main.command()
@click.argument("papers", nargs=-1)
@click.option("--out", type=click.Path(path_type=Path), default=Path("results"),
              show_default=True, help="results folder")
def reproduce(papers: tuple[str, ...], out: Path) -> None:
    """Run every experiment of PAPERS (default: all) and write figures,
    claims.json and report.md into OUT."""
    from .report import reproduce as run

    chosen = list(papers) or list(PAPERS)
    unknown = [p for p in chosen if p not in PAPERS]
    if unknown:
        raise click.BadParameter(f"unknown paper {unknown}; known: {', '.join(PAPERS)}")
    with _progress() as prog:
        tasks: dict[str, int] = {}

        def on_progress(name: str, frac: float) -> None:
            if name not in tasks:
                tasks[name] = prog.add_task(name, total=1.0)
            prog.update(tasks[name], completed=frac)

        rep = run(chosen, out, on_progress=on_progress)
    table = Table(title=f"claims ({out / 'claims.json'})")
    for col in ("claim", "paper", "expected", "reproduced", "unit", "result"):
        table.add_column(col)
    for c in rep.claims:
        table.add_row(c.id, _f(c.paper), _f(c.expected), _f(c.reproduced), c.unit,
                      "[green]pass" if c.passed else "[red]FAIL")
    Console().print(table)
    n_pass = sum(c.passed for c in rep.claims)
    console.print(f"{n_pass} claims passed, {len(rep.claims) - n_pass} failed; report: "
                  f"{out / 'report.md'}; {rep.samples:,} samples in {rep.seconds:.1f} s")


def _f(x: float | None) -> str:
    return "-" if x is None else f"{x:.4g}"


def _load(scenario: str):
    """A TOML file, or a name of the catalogue (`smodrive scenarios`)."""
    path = Path(scenario)
    if path.is_file():
        return load_scenario(path)
    cat = catalogue()
    if scenario in cat:
        return cat[scenario]()
    raise ParameterError(f"{scenario}: neither a scenario file nor a catalogue name "
                         "(see `smodrive scenarios`)")


@main.command()
@click.argument("scenario")
@click.option("--out", type=click.Path(path_type=Path), default=Path("results"),
              show_default=True)
@click.option("--pil", is_flag=True,
              help="processor in the loop: the controller compiled for a Cortex-M4F runs on "
                   "QEMU (mps2-an386) against the host plant, beside the host-only run")
@click.option("--seconds", type=float, default=0.2, show_default=True,
              help="with --pil: simulated time")
@click.option("--math", type=click.Choice(["fmath", "libm"]), default="fmath",
              show_default=True,
              help="with --pil: the core's portable float math on both sides (bit-identical), "
                   "or each platform's C library (glibc against newlib)")
def run(scenario: str, out: Path, pil: bool, seconds: float, math: str) -> None:
    """Simulate one SCENARIO (a TOML file or a catalogue name); write
    signals.npz, summary.json and a figure (with --pil: pil.json and the
    comparison figure)."""
    from . import plots
    from .simulate import CHANNELS, SimulationError, simulate

    try:
        s = _load(scenario)
    except ParameterError as exc:
        console.print(f"[red]error:[/red] {exc}")
        sys.exit(2)
    if pil:
        _run_pil(s, out, seconds, math)
        return
    out.mkdir(parents=True, exist_ok=True)
    with _progress() as prog:
        task = prog.add_task(s.name, total=1.0)
        try:
            r = simulate(s, progress=lambda f: prog.update(task, completed=f))
        except (SimulationError, ParameterError) as exc:
            console.print(f"[red]error:[/red] {exc}")
            sys.exit(1)
    np.savez_compressed(out / "signals.npz", **{c: r[c] for c in CHANNELS})
    (out / "scenario.toml").write_text(scenario_to_toml(s))
    last = r.window(0.8 * s.duration, s.duration)
    summary = {
        "name": s.name,
        "samples": int(r.data.shape[0] * s.log_stride),
        "status": r.status,
        "speed_rpm_mean_last_20pct": float(np.mean(r.n_rpm[last])),
        "speed_estimate_rpm_mean_last_20pct": float(np.mean(r.n_hat_rpm[last])),
        "i_d_mean_last_20pct": float(np.mean(r["i_d"][last])),
        "i_q_mean_last_20pct": float(np.mean(r["i_q"][last])),
        "theta_error_rms_deg_last_20pct": float(np.degrees(np.sqrt(np.mean(
            r.theta_error[last] ** 2)))),
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    plots.save(plots.time_panels(
        [r], [s.name], s.name,
        [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true"),
                            ("n_hat_rpm", "estimated")]),
         ("motor current (A)", [("i_d", "d"), ("i_q", "q")]),
         ("position error (rad)", [("theta_error", "true")])]),
        out, s.name.replace(".", "_"))
    console.print(json.dumps(summary, indent=2))


def _run_pil(s, out: Path, seconds: float, math: str) -> None:
    from . import plots
    from .target import TargetError, pil

    if not 0.0 < seconds <= 10.0:
        console.print(f"[red]error:[/red] --seconds {seconds}: must be in (0, 10] s")
        sys.exit(2)
    out.mkdir(parents=True, exist_ok=True)
    with _progress() as prog:
        task = prog.add_task(f"{s.name} (PIL, {math})", total=1.0)
        try:
            r = pil(s, seconds, math=math, progress=lambda f: prog.update(task, completed=f))
        except (TargetError, ParameterError) as exc:
            console.print(f"[red]error:[/red] {exc}")
            sys.exit(1)
    summary = {
        "name": s.name, "samples": r.samples, "math": math, "reference": r.reference,
        "identical": r.identical, "max_duty_diff": r.max_duty_diff,
        "max_theta_hat_diff_rad": r.max_theta_diff_rad,
        "max_w_hat_diff_rad_s": r.max_w_diff, "max_word_diff_ulp": r.max_view_ulp,
    }
    (out / "pil.json").write_text(json.dumps(summary, indent=2) + "\n")
    plots.save(plots.pil_panels(r), out, s.name.replace(".", "_") + "_pil")
    console.print(json.dumps(summary, indent=2))


@main.command()
def scenarios() -> None:
    """List the catalogue of paper scenarios."""
    for name in catalogue():
        click.echo(name)


@main.command()
@click.argument("name")
def show(name: str) -> None:
    """Print a catalogue scenario as TOML (a starting point for your own)."""
    cat = catalogue()
    if name in cat:
        click.echo(scenario_to_toml(cat[name]()))
        return
    raise click.BadParameter(f"unknown scenario {name}; see `smodrive scenarios`")


if __name__ == "__main__":
    main()
