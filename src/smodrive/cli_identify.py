"""`smodrive identify`: commissioning against the simulated plant (issue 23).

Step 1 so far: the core's R_s test (:mod:`smodrive.commission`). The command
prints what the test measured beside the scenario's true values and writes
the measured values as a TOML file (``[motor]`` with ``R_s``; the inverter's
drop and the test's record under ``[identified]``).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import click
import tomli_w

from .commission import OUTCOME_TEXT, identify_rs
from .engine import export
from .scenario_io import resolve_scenario


def _g(x: float) -> float:
    return float(f"{x:.6g}")


def identified_toml(name: str, r) -> str:
    """The TOML that `identify` writes for result `r` of scenario `name`."""
    head = (f"# Measured by `smodrive identify` on {name} (commissioning, issue 23).\n"
            "# Step 1 only: R_s and the inverter's drop; the other [motor] values are not\n"
            "# measured yet and must come from the data sheet.\n")
    data = {
        "motor": {"R_s": _g(r.R_s)},
        "identified": {
            "outcome": r.outcome, "u_0": _g(r.u_0), "r2": _g(r.r2),
            "resid_V": _g(r.resid), "test_s": _g(r.t),
            "i_levels_A": [_g(x) for x in r.i_levels],
            "u_levels_V": [_g(x) for x in r.u_levels],
        },
    }
    return head + tomli_w.dumps(data)


@click.command()
@click.argument("scenario")
@click.option("--out", type=click.Path(path_type=Path), default=None,
              help="write the measured values as TOML (default: print only)")
@click.option("--i-test", type=float, default=None,
              help="the test's top current, A (default: half the rated current)")
def identify(scenario: str, out: Path | None, i_test: float | None) -> None:
    """Measure the motor of SCENARIO as a drive would, before it runs: the
    stator resistance and the inverter's voltage drop (a DC staircase on the
    alpha axis, a least-squares line). The test sees only the measured
    currents and the DC-link voltage; the true values are printed beside."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        s = resolve_scenario(scenario)
    for w in caught:
        click.secho(f"warning: {w.message}", fg="yellow", err=True)
    r = identify_rs(s, i_test)
    err = 100.0 * (r.R_s / s.motor.R_s - 1.0)
    click.echo(f"{scenario}: R_s test, {len(r.i_levels)} levels from {min(r.i_levels):.3g} to "
               f"{max(r.i_levels):.3g} A, {r.t:.2f} s")
    click.echo(f"  R_s  {r.R_s:.5g} ohm measured, {s.motor.R_s:.5g} ohm true ({err:+.2f} %)")
    click.echo(f"  u_0  {r.u_0:.4g} V (the inverter's drop: dead time and switches)")
    click.echo(f"  fit  R^2 {r.r2:.6f}, residual {r.resid:.3g} V RMS: {r.outcome} "
               f"({OUTCOME_TEXT.get(r.outcome, '')})")
    if out is not None:
        export.write_text(out, identified_toml(scenario, r))
        click.echo(f"wrote {out}")
    if not r.ok:
        raise click.exceptions.Exit(1)
