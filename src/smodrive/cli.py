"""Command line: `smodrive run SCENARIO.toml --out DIR`,
`smodrive reproduce [PAPER ...] --out DIR`, `smodrive scenarios`.

Whatever the input, the user sees one ``error: ...`` line (exit 2 for bad
input, 1 for a failed run), never a Python traceback (set SMODRIVE_DEBUG=1
to get one). User text (names, values) is printed as it is: rich markup in
it is not interpreted.

What a command prints for a program to read (the summary JSON of
``smodrive run``, the lists of ``scenarios`` and ``show``) goes to stdout;
progress, notes, warnings and errors go to stderr, so that
``smodrive run x.toml --out d | jq .status`` works. Every file is written
under a temporary name and renamed onto its own (:func:`smodrive.engine.export.atomic_path`):
a killed run never leaves a truncated file under its final name.
"""

from __future__ import annotations

import glob
import json
import math
import os
import re
import shutil
import sys
import tempfile
import warnings
from pathlib import Path
from typing import Any, Callable, Iterable, NoReturn

import click
from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table
from rich.text import Text

from . import firmware, plots
from . import sweep as sw
from .analysis.metrics import HOLD_SHARE
from .analysis.summary import run_summary
from .claims import count, describe_counts
from .engine import SimulationError, _ffi, export, log_plan, simulate
from .engine.export import write_npz
from .firmware import header as fw_header
from .model import ParameterError, derive
from .model.margins import TABLE1_SPEED_PM, sensorless_margin
from .report import reproduce as reproduce_papers
from .cli_identify import identify
from .scenario_io import resolve_scenario, scenario_to_toml
from .scenarios import PAPERS, catalogue, trials
from .sweep import plot_all

console = Console(stderr=True)


def _say(text: str, style: str | None = None) -> None:
    """Print `text` as it is (no markup, no wrapping inside words or values)."""
    console.print(Text(text, style=style or ""), soft_wrap=True)


def _fail(message: str, code: int) -> NoReturn:
    """`error: message` and exit `code` (2: bad input, 1: the run failed)."""
    console.print(Text.assemble(("error:", "bold red"), " ", str(message)), soft_wrap=True)
    sys.exit(code)


_said: set[str] = set()


def _warn(text: str) -> None:
    """`warning: text`, once a command: the same check said of a scenario
    and then of its run (`scenario: ...`, `scenario.profile: ...`) is one
    line."""
    key = text.split(": ", 1)[-1]
    if key not in _said:
        _said.add(key)
        _say(f"warning: {text}", "yellow")


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """warnings.showwarning for a command: a warning raised while it runs (the
    engine's checks before a simulation) is a `warning:` line, not Python's
    two lines with the source file and line."""
    _warn(str(message))


class _Cli(click.Group):
    """The command group: what escapes a command ends as one error line."""

    def invoke(self, ctx: click.Context) -> Any:
        shown = warnings.showwarning
        warnings.showwarning = _show_warning
        _said.clear()
        try:
            return super().invoke(ctx)
        except (click.exceptions.ClickException, click.exceptions.Exit,
                click.exceptions.Abort):
            raise
        except ParameterError as exc:
            _fail(str(exc), 2)
        except Exception as exc:  # a bug, or the system (disk full, ...)
            if os.environ.get("SMODRIVE_DEBUG"):
                raise
            what = (f"{exc.strerror}: {exc.filename}" if isinstance(exc, OSError)
                    and exc.strerror and exc.filename else f"{type(exc).__name__}: {exc}")
            _fail(f"{what} (SMODRIVE_DEBUG=1 shows where)", 1)
        finally:
            warnings.showwarning = shown


def _progress() -> Progress:
    return Progress(
        TextColumn("[bold]{task.description}"),
        BarColumn(),
        TextColumn("{task.percentage:>3.0f}%"),
        TimeElapsedColumn(),
        console=console,
        transient=False,
    )


def _task(prog: Progress, description: str, total: float = 1.0) -> int:
    """A progress task whose description is printed as it is."""
    return prog.add_task(escape(description), total=total)


class ByteSize(click.ParamType):
    """A memory size: bytes, or a number with B, kB, MB, GB, TB (powers of
    1000) or KiB, MiB, GiB, TiB (powers of 1024)."""

    name = "size"
    UNITS = {"": 1, "b": 1, "kb": 10**3, "mb": 10**6, "gb": 10**9, "tb": 10**12,
             "kib": 2**10, "mib": 2**20, "gib": 2**30, "tib": 2**40}

    def convert(self, value: Any, param, ctx) -> int:
        if isinstance(value, int):
            return value
        m = re.fullmatch(r"\s*(\d+(?:\.\d*)?(?:[eE][+-]?\d+)?)\s*([A-Za-z]*)\s*", str(value))
        unit = m and m.group(2).lower()
        if not m or unit not in self.UNITS or not float(m.group(1)) > 0:
            self.fail(f"{value!r} is not a size above 0 (bytes, or e.g. 500MB, 2GiB)", param,
                      ctx)
        return int(float(m.group(1)) * self.UNITS[unit])


def _size(n: float) -> str:
    for unit, k in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n >= k:
            return f"{n / k:.3g} {unit}"
    return f"{n:.0f} B"


def _prepare_out(out: Path) -> None:
    """Create OUT and check that files can be written in it, before anything
    runs (exit 2 if not)."""
    for p in (out, *out.parents):
        try:
            is_file = p.exists() and not p.is_dir()
        except OSError:
            continue  # not searchable: mkdir below says why
        if is_file:
            _fail(f"--out {out}: " + ("a file of that name exists; it is not a directory"
                                      if p == out else f"{p} is a file, not a directory"), 2)
    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=out):
            pass
    except OSError as exc:
        _fail(f"--out {out}: cannot write there ({exc.strerror or exc})", 2)


#: the files every `smodrive run` may write into OUT (beside its figures,
#: named after the scenario): the log in each --format, summary.json,
#: scenario.toml, and with --pil pil.json
RUN_FILES = (*export.FORMATS.values(), "signals.csv.json", "summary.json", "scenario.toml",
             "pil.json")


def _earlier_run(out: Path, figures: Iterable[str]) -> tuple[str | None, list[str]]:
    """The scenario name of an earlier run in OUT (from its summary.json or
    pil.json; None if neither says) and the files of it OUT holds: those of
    :data:`RUN_FILES`, the `figures` this run would write, and the earlier
    run's own figures."""
    old = None
    for f in ("summary.json", "pil.json"):
        try:
            name = json.loads((out / f).read_text(encoding="utf-8")).get("name")
        except (OSError, ValueError, AttributeError):
            continue
        if isinstance(name, str):
            old = name
            break
    names = [*RUN_FILES, *figures]
    if old is not None:
        names += [f"{_file_stem(old)}.png", f"{_file_stem(old)}_pil.png"]
    return old, [n for n in dict.fromkeys(names) if (out / n).is_file()]


def _claim_out(out: Path, figures: Iterable[str], force: bool) -> list[str]:
    """Refuse (exit 2) an OUT that holds an earlier run's files, unless
    `force`; returns those files (with `force`: replaced by this run's, or
    removed once it has written its own)."""
    old, found = _earlier_run(out, figures)
    who = "" if old is None else f" (scenario {old!r})"
    if found and not force:
        _fail(f"--out {out} holds the files of an earlier run{who}: {', '.join(found)}; "
              "choose another --out, or pass --force to replace them", 2)
    _remove_leftovers(out)
    if found:
        _say(f"note: --force: this run replaces the files of the earlier run{who} in {out}: "
             f"{', '.join(found)}", "yellow")
    return found


def _remove_leftovers(out: Path) -> None:
    """Remove the temporary files a killed run left in OUT (hidden:
    ``.signals.npz.RANDOM.tmp``, ``.figure-RANDOM/``), and say so."""
    left = [p for n in RUN_FILES for p in out.glob(f".{glob.escape(n)}.*.tmp")]
    left += [p for p in out.glob(".figure-*") if p.is_dir()]
    for p in left:
        if p.is_dir():
            shutil.rmtree(p, ignore_errors=True)
        else:
            p.unlink(missing_ok=True)
    if left:
        _say(f"note: removed {', '.join(p.name for p in left)} in {out}, left by a killed run",
             "yellow")


def _remove_stale(out: Path, earlier: Iterable[str], written: Iterable[str]) -> None:
    """Remove the files of the earlier run that this run did not write
    (after it wrote its own: a failed run leaves the earlier one whole)."""
    keep = set(written)
    for name in earlier:
        if name not in keep:
            try:
                (out / name).unlink()
            except FileNotFoundError:
                pass


def _save_figure(axes, out: Path, stem: str) -> Path:
    """plots.save into a temporary folder of OUT, then renamed onto
    OUT/stem.png (atomic: never a truncated figure under its name)."""
    tmp = Path(tempfile.mkdtemp(dir=out, prefix=".figure-"))
    try:
        made = plots.save(axes, tmp, stem)
        path = out / made.name
        os.replace(made, path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return path


def _file_stem(name: str) -> str:
    """A file name for a scenario name: every character but a letter, a
    digit, - and _ becomes _ (the file stays in OUT whatever the name)."""
    return re.sub(r"[^A-Za-z0-9_-]", "_", name)[:120] or "scenario"


def _json(obj: Any) -> str:
    """Strict JSON (no NaN or Infinity, which many readers refuse): a
    non-finite number is written as null."""

    def finite(x: Any) -> Any:
        if isinstance(x, float) and not math.isfinite(x):
            return None
        if isinstance(x, dict):
            return {k: finite(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [finite(v) for v in x]
        return x

    return json.dumps(finite(obj), indent=2, allow_nan=False, ensure_ascii=False) + "\n"


@click.group(cls=_Cli)
@click.version_option(package_name="smodrive")
def main() -> None:
    """smodrive: sliding-mode observer based PMSM drive control."""


main.add_command(identify)


@main.command()
@click.argument("papers", nargs=-1)
@click.option("--out", type=click.Path(path_type=Path), default=Path("results"),
              show_default=True, help="results folder")
@click.option("--math", "math_build", type=click.Choice(["exact", "fast"]), default=None,
              help="the build of the core the simulator runs: exact (default; the C "
                   "library's sin, cos, atan2) or fast (the fast build's math, "
                   "docs/firmware.md); also SMODRIVE_MATH")
def reproduce(papers: tuple[str, ...], out: Path, math_build: str | None) -> None:
    """Run every experiment of PAPERS (default: all) and write figures,
    claims.json and report.md into OUT."""
    if math_build is not None and math_build != _ffi.MATH:
        # the core's library is loaded at import: run again with the other one
        env = dict(os.environ, SMODRIVE_MATH=math_build)
        os.execve(sys.executable, [sys.executable, "-m", "smodrive.cli", *sys.argv[1:]], env)
    chosen = list(papers) or list(PAPERS)
    unknown = [p for p in chosen if p not in PAPERS]
    if unknown:
        _fail(f"unknown paper {', '.join(map(repr, unknown))}; known: {', '.join(PAPERS)}", 2)
    _prepare_out(out)
    with _progress() as prog:
        tasks: dict[str, int] = {}

        def on_progress(name: str, frac: float) -> None:
            if name not in tasks:
                tasks[name] = _task(prog, name)
            prog.update(tasks[name], completed=frac)

        rep = reproduce_papers(chosen, out, on_progress=on_progress)
    table = Table(title=escape(f"claims ({out / 'claims.json'})"))
    for col in ("claim", "paper", "expected", "reproduced", "unit", "result"):
        table.add_column(col)
    for c in rep.claims:
        table.add_row(escape(c.id), _f(c.paper), _f(c.expected), _f(c.reproduced),
                      escape(c.unit), {"pass": "[green]pass", "fail": "[red]FAIL",
                                       "not measured": "[yellow]not measured"}[c.status])
    Console().print(table)
    n = count(rep.claims)
    _say(f"{n['pass']} claims passed, {n['fail']} failed"
         + (f", {n['not measured']} not measured (report.md says why)"
            if n["not measured"] else "")
         + f"; report: {out / 'report.md'}; {rep.samples:,} samples in {rep.seconds:.1f} s")
    _say(f"by kind: {describe_counts(rep.claims)}")


def _f(x: float | None) -> str:
    return "-" if x is None or x != x else f"{x:.4g}"


def _load(scenario: str):
    """A TOML file, or a name of the catalogue (`smodrive scenarios`); its
    warnings (older key names) are printed as one line each."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        s = resolve_scenario(scenario)
    for w in caught:
        _warn(str(w.message))
    return s


@main.command()
@click.argument("scenario")
@click.option("--out", type=click.Path(path_type=Path), default=Path("results"),
              show_default=True, help="results folder: this run's files alone (see --force)")
@click.option("--log-budget", type=ByteSize(), default="2GiB", show_default=True,
              help="memory the signal log may take; a longer log keeps every k-th sample "
                   "(the stride is stated in summary.json)")
@click.option("--pil", is_flag=True,
              help="processor in the loop: the controller compiled for a Cortex-M4F runs on "
                   "QEMU (mps2-an386) against the host plant, beside the host-only run")
@click.option("--seconds", type=float, default=0.2, show_default=True,
              help="with --pil: simulated time")
@click.option("--math", type=click.Choice(["fmath", "fast", "libm"]), default="fmath",
              show_default=True,
              help="with --pil: the core's portable float math on both sides (bit-identical), "
                   "the fast build's (bit-identical too), or each platform's C library (glibc "
                   "against newlib)")
@click.option("--cycles", is_flag=True,
              help="with --pil: the Cortex-M4F's cycles of every step of the run (mean, 99th "
                   "percentile, worst call; with the code in STM32F4 and STM32G4 flash too), "
                   "in pil.json")
@click.option("--format", "formats", default="npz", show_default=True, metavar="FORMATS",
              help="the log's formats, comma-separated: npz, mat (MATLAB, with the structs "
                   "units and descriptions), csv (units in signals.csv.json), parquet (units "
                   "in the column metadata)")
@click.option("--force", is_flag=True,
              help="replace the files of an earlier run in OUT (without it a run refuses an "
                   "OUT that holds any: summary.json, scenario.toml, signals.*, pil.json or "
                   "a run's figure)")
@click.option("--profile", type=click.Choice(["usual"]), default=None,
              help="usual: the SCENARIO's motor, inverter and ADC, sensorless from rest on "
                   "the usual profile (I/f start, +50 % and +100 % of rated speed, rated load "
                   "on and off, reversal to -50 % and -100 %; smodrive.scenarios.trials), "
                   "judged at its end: reached, or exit code 1 saying why not")
def run(scenario: str, out: Path, log_budget: int, pil: bool, seconds: float,
        math: str, cycles: bool, formats: str, force: bool, profile: str | None) -> None:
    """Simulate one SCENARIO (a TOML file or a catalogue name); write
    signals.npz (or the --format files), summary.json and a figure (with
    --pil: pil.json and the comparison figure) into OUT, which must not hold
    an earlier run's files (unless --force). The summary JSON is printed on
    stdout, progress and notes on stderr; the exit code is 1 when the run
    ends in a fault (unless the scenario sets faults_expected)."""
    fmts = export.parse_formats(formats)
    if "parquet" in fmts:
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            _fail("--format parquet needs pyarrow: pip install pyarrow", 2)
    given = [f"--{n}" for n in ("seconds", "math", "cycles") if click.get_current_context()
             .get_parameter_source(n) is not click.core.ParameterSource.DEFAULT]
    if given and not pil:  # (they were dropped without a word)
        _fail(f"{', '.join(given)}: options of --pil (the controller on the emulated Cortex-M4F); "
              "add --pil, or leave them out (a plain run lasts the scenario's duration)", 2)
    s = _load(scenario)
    if profile is not None:
        s = trials.profile_scenario(s)
    if pil:
        if not 0.0 < seconds <= 10.0:
            _fail(f"--seconds {seconds}: must be in (0, 10] s", 2)
        _prepare_out(out)
        earlier = _claim_out(out, [f"{_file_stem(s.name)}_pil.png"], force)
        written = _run_pil(s, out, seconds, math, cycles)
        _remove_stale(out, earlier, written)
        return
    try:
        plan = log_plan(s, log_budget)
    except ParameterError as exc:
        _fail(f"--log-budget: {exc}", 2)
    _prepare_out(out)
    stem = _file_stem(s.name)
    earlier = _claim_out(out, [f"{stem}.png"], force)
    if plan.decimated:
        full = s.n_steps / s.log_stride * plan.bytes / plan.rows
        _say(f"log: {s.n_steps:,} samples would take {_size(full)}, above the budget of "
             f"{_size(plan.budget_bytes)} (--log-budget): logging every {plan.stride}th "
             f"sample (stride {plan.stride}, {plan.rows:,} rows, {_size(plan.bytes)}); "
             "summary and figure use those rows")
    with _progress() as prog:
        t_sim = _task(prog, f"simulating {s.name}")
        t_npz = _task(prog, "writing " + ", ".join(export.FORMATS[f] for f in fmts))
        t_fig = _task(prog, "plotting", 2)
        try:
            r = simulate(s, progress=lambda f: prog.update(t_sim, completed=f),
                         log_budget=log_budget)
        except SimulationError as exc:
            _fail(str(exc), 1)
        written = [p.name for p in export.write(r, out, fmts,
                                                lambda f: prog.update(t_npz, completed=f))]
        summary = run_summary(s, r, plan)
        if profile is not None:
            o = trials.judge(r)
            summary["profile"] = {"name": profile, "verdict": o.verdict,
                                  "speed_error_rel_end": o.speed_error,
                                  "theta_error_rms_deg_end": o.angle_rms_deg}
        export.write_text(out / "scenario.toml", scenario_to_toml(s))
        export.write_text(out / "summary.json", _json(summary))
        written += ["scenario.toml", "summary.json"]
        axes = plots.time_panels(
            [r], [s.name], s.name,
            [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true"),
                                ("n_hat_rpm", "estimated")]),
             ("motor current (A)", [("i_d", "d"), ("i_q", "q")]),
             ("position error (rad)", [("theta_error", "true")])])
        prog.update(t_fig, completed=1)
        written.append(_save_figure(axes, out, stem).name)
        prog.update(t_fig, completed=2)
    _remove_stale(out, earlier, written)
    click.echo(_json(summary), nl=False)  # stdout: the one thing a program reads
    f = r.faults
    if f.t_first is not None:
        what, ctx = ", ".join(summary["first_fault"]), summary["fault_context"]
        if f.ends_in_fault and not s.faults_expected:
            _fail(f"the run ends in a fault: {', '.join(summary['final_fault'])} (first fault: "
                  f"{what} at t = {f.t_first:.6g} s{'; ' + ctx if ctx else ''}); the outputs are "
                  f"in {out}. If the scenario tests this fault, set faults_expected = true in it", 1)
        _say(f"faults: first {what} at t = {f.t_first:.6g} s"
             + ("" if not f.ends_in_fault else " (expected by the scenario)"))
    if profile is not None:
        o = summary["profile"]
        if o["verdict"] == "silent":
            _fail(f"the {profile} profile ended wrong without a fault: the speed "
                  f"{100 * o['speed_error_rel_end']:.1f} % off its reference (within "
                  f"{100 * trials.SPEED_TOL:g} % expected), the angle error "
                  f"{o['theta_error_rms_deg_end']:.1f} deg RMS (within {trials.ANGLE_TOL_DEG:g}) "
                  f"at its end; the outputs are in {out}", 1)
        _say(f"{profile} profile: {o['verdict']} (speed {100 * o['speed_error_rel_end']:.2f} % "
             f"off, angle {o['theta_error_rms_deg_end']:.2f} deg RMS at its end)")
    if profile is None and summary["off_reference"] is not None:
        _warn(summary["off_reference"])
    margin = sensorless_margin(s)
    if margin is not None and margin[1]:
        _say(f"note: the sensorless speed loop has {margin[0]:.1f} deg of phase margin (Table "
             f"I's design: {TABLE1_SPEED_PM:.1f} deg; w_c, w_lpf and the delay against "
             "speed_bw): its speed rings on the ADC's noise (docs/design_from_motor.md)")
    share = summary["voltage_limit_share_last_20pct"]
    if share > HOLD_SHARE:
        _say(f"note: the voltage was on the modulator's limit in {100 * share:.1f} % of the "
             "last 20 % of the run: the drive holds it without voltage headroom, and its "
             "current loop does not set the voltage there (a deadbeat loop's limit cycle, or "
             "a speed or load beyond what inverter.u_dc reaches; check the reference, the "
             "load, inverter.u_dc and controller.L_s_hat)")


def write_signals(path: Path, r, progress: Callable[[float], None] | None = None) -> None:
    """signals.npz (:func:`smodrive.engine.export.write_npz`)."""
    write_npz(r, path, progress)


def _run_pil(s, out: Path, seconds: float, math: str, cycles: bool = False) -> list[str]:
    """The PIL run: pil.json and the comparison figure; returns their names."""
    if seconds < 2.0 * s.T_sp:  # (1e-5 s at 100 us had ended in a raw numpy ValueError)
        _fail(f"--seconds {seconds:g} is below two samples of the scenario, 2 T_sp = "
              f"{2.0 * s.T_sp:g} s", 2)
    with _progress() as prog:
        task = _task(prog, f"{s.name} (PIL, {math}" + (", then its cycles)" if cycles else ")"))
        try:
            r = firmware.pil(s, seconds, math=math, cycles=cycles,
                             progress=lambda f: prog.update(task, completed=f))
        except firmware.TargetError as exc:
            _fail(str(exc), 1)
    summary, said = firmware.pil_report(s, r)
    if r.cycles is not None:
        c, budget = r.cycles, summary["cycles"]["budget"]
        _say(f"cycles per step on the Cortex-M4F over {c.calls:,} steps: mean {c.nominal:,.0f}, "
             f"99th percentile {c.p99:,.0f}, worst {c.worst:,}; in STM32F4 flash worst "
             f"{c.worst_flash('stm32f4'):,.0f} ({c.worst_flash('stm32f4') / budget:.0%} of the "
             f"{budget:,.0f} of its period, {summary['cycles']['budget_is']})")
    for text in said:
        _warn(text)
    export.write_text(out / "pil.json", _json(summary))
    fig = _save_figure(plots.pil_panels(r), out, _file_stem(s.name) + "_pil")
    click.echo(_json(summary), nl=False)
    return ["pil.json", fig.name]


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
    if name not in cat:
        _fail(f"unknown scenario {name!r}; see `smodrive scenarios`", 2)
    click.echo(scenario_to_toml(cat[name]()))


@main.command()
@click.argument("scenario")
@click.option("--header", "header", type=click.Path(path_type=Path), default=None,
              help="write the drive's configuration (and LCL observer tables) as a C header")
@click.option("--name", default="SMD", show_default=True, help="prefix of the header's names")
def design(scenario: str, header: Path | None, name: str) -> None:
    """Print the controller designed from the motor: each motor-specific value,
    derived (with its rule) or set; with --header, write it for firmware."""
    if header is not None and (header.is_dir() or not header.parent.is_dir()):  # (before it)
        _fail(f"--header {header}: " + ("a folder, not a file" if header.is_dir() else
                                        f"the folder {header.parent} does not exist"), 2)
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):  # (it was, after the design)
        _fail(f"--name {name!r} is not a C identifier", 2)
    s = _load(scenario)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        s.check_controller()
    for w in caught:
        _warn(str(w.message))
    m = s.motor
    click.echo(f"{s.name}: {s.controller.current} current control, {s.controller.position} "
               f"position, {s.controller.start} start")
    click.echo(f"motor: E_N = {derive.rated_emf(m):.4g} V peak (n_p w_M_N psi_r), I_N = "
               f"{derive.rated_current(m):.4g} A peak (T_N / k_t), T_N = {m.T_N:.4g} N m")
    t = Table("value", "", "unit", "origin", box=None)
    for r in fw_header.design_rows(s):
        t.add_row(r.name, f"{r.value:.6g}", r.unit, r.origin)
    Console(soft_wrap=True, width=160).print(t)
    if s.lcl is not None and s.controller.position in ("lcl_smo_pll", "lcl_linear"):
        with _progress() as prog:  # (10-20 s for a new filter: cached per design after)
            task = _task(prog, f"{s.name}: the LCL observers' design at each speed of its tables")
            d = fw_header.lcl_design(s)
            prog.update(task, completed=1)
        lo, hi, n = d["table_rpm"]
        click.echo(f"LCL observers: filter resonance {d['f_res_hz']:.5g} Hz (observer's model), "
                   f"PLL bandwidth {d['pll_bandwidth_hz']:.4g} Hz, tables designed at {n} speeds "
                   f"from {lo:g} to {hi:g} r/min")
    if header is not None:
        text = fw_header.drive_header(s, name)
        export.write_text(header, text)
        _say(f"wrote {header}")



@main.command()
@click.argument("sweep_file", required=False)
@click.option("--out", type=click.Path(path_type=Path), default=None,
              help="results folder (default: sweeps/<name>); runs already there are not run "
                   "again")
@click.option("--scheduler", default=None, metavar="ADDRESS",
              help="a running Dask scheduler (tcp://host:port); default: a LocalCluster over "
                   "this machine's cores")
@click.option("--workers", type=int, default=None,
              help="LocalCluster worker processes (default: one a core)")
@click.option("--plot", "plot_dir", type=click.Path(path_type=Path), default=None,
              metavar="DIR", help="only draw the maps of the sweep whose results DIR holds")
@click.option("--list", "list_", is_flag=True, help="list the built-in sweeps")
@click.option("--no-plot", is_flag=True, help="do not draw the maps after the runs")
def sweep(sweep_file: str | None, out: Path | None, scheduler: str | None,
          workers: int | None, plot_dir: Path | None, list_: bool, no_plot: bool) -> None:
    """Run a parameter sweep (a sweep TOML, or a built-in name from --list) on
    Dask: one Parquet row a run in OUT/runs, maps in OUT/maps."""
    if list_:
        for name, title in sw.builtins().items():
            click.echo(f"{name}  {title}")
        return
    if plot_dir is not None:
        if sweep_file is not None:
            _fail("give a SWEEP_FILE to run or --plot DIR to draw, not both", 2)
        spec = sw.load_out_spec(plot_dir)
        for p in plot_all(spec, plot_dir):
            _say(f"wrote {p}")
        return
    if sweep_file is None:
        _fail("missing SWEEP_FILE (a sweep TOML or a built-in name: smodrive sweep --list)", 2)
    if workers is not None and not 1 <= workers <= 1024:
        _fail(f"--workers {workers} is outside its valid range [1, 1024]", 2)
    spec = sw.load_sweep(sweep_file)
    out = out or Path("sweeps") / spec.name
    _prepare_out(out)
    sw.check_out(spec, out)  # (another sweep's folder: refused before the progress bars start)
    with _progress() as prog:
        tasks: dict[str, int] = {}

        def on_progress(phase: str, done: int, total: int) -> None:
            if phase not in tasks:
                tasks[phase] = _task(prog, f"{spec.name}: {phase}", max(total, 1))
            prog.update(tasks[phase], completed=done, total=max(total, 1))

        rep = sw.run_sweep(spec, out, scheduler=scheduler, workers=workers,
                           progress=on_progress)  # (OUT/sweep.toml: the file's text, spec.text)
    _say(rep.summary(out))
    if rep.failed_batches:
        _fail(f"{len(rep.failed_batches)} batches were lost with their workers "
              f"({rep.failed_batches[0]}); run the same command again for the missing runs", 1)
    if not no_plot and spec.plots:
        for p in plot_all(spec, out):
            _say(f"wrote {p}")


if __name__ == "__main__":
    main()
