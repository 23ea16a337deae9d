"""
Through zero speed, and a fault
===============================

``scenarios/sensorless_load_step.toml`` (the README's "Faults, and through
zero speed"): sensorless robust DBPC at 1000 r/min, a 10 N m brake at 0.4 s,
the reference ramped to -600 r/min. Below 210 r/min (derived from the
motor) the drive returns to I/f, crosses zero and hands back to the SMDO at
-420 r/min. Without the
return to I/f the estimate runs away and the drive stops in its safe state
with ``lost_lock`` (``Result.faults``). This is what
``tools/zero_crossing_figure.py`` draws for the README.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from smodrive import plots
from smodrive.scenario_io import load_scenario
from smodrive.engine import simulate


def repo_file(rel: str) -> Path:
    """A file of the checkout (the gallery runs from a copy of docs/)."""
    here = Path(__file__).resolve() if "__file__" in globals() else Path.cwd()
    for p in (Path.cwd(), *here.parents):
        if (p / rel).is_file():
            return p / rel
    raise FileNotFoundError(rel)


s = load_scenario(repo_file("scenarios/sensorless_load_step.toml"))
runs = [simulate(s), simulate(s.with_controller(w_M_if_enter=0.0))]
for label, r in zip(("with I/f", "without"), runs):
    f = r.faults
    ends = "" if not f.final else (
        f", ends in {', '.join(f.as_dict()['final_fault'])} (latched at "
        f"{r.t[np.nonzero(r['fault'].astype(int) & f.final)[0][0]]:.3f} s)")
    print(f"{label}: final speed {r.n_rpm[-1]:.1f} r/min, "
          + ("no fault" if f.t_first is None else
             f"first fault {', '.join(f.as_dict()['first_fault'])} at {f.t_first:.3f} s")
          + ends)

fig, axes = plt.subplots(3, 2, figsize=(9, 6), sharex="col", layout="constrained")
plots.time_panels(
    runs, ["return to I/f below 210 r/min (derived)", "without it"], None,
    [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true"),
                        ("n_hat_rpm", "estimated")]),
     ("position error (rad)", [("theta_error", "true")]),
     ("phase / fault", [("phase", "phase (0 I/f, 2 SMDO)"), ("fault", "fault word")])],
    t_window=(0.6, 1.6), ax=axes)
plots.show(fig, "plot_zero_crossing")
