"""Draw docs/img/zero_crossing.png: the README example
(scenarios/sensorless_load_step.toml) through zero speed on I/f, and the
same run without the return to I/f (the loss of lock it now reports).

    PYTHONPATH=src python tools/zero_crossing_figure.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from smodrive import plots
from smodrive.scenario_io import load_scenario
from smodrive.engine import FAULT_BITS, simulate

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    s = load_scenario(ROOT / "scenarios" / "sensorless_load_step.toml")
    runs = [simulate(s), simulate(s.with_controller(w_M_if_enter=0.0))]
    r = runs[1]
    t_lost = r.t[np.nonzero(r["fault"].astype(int) & FAULT_BITS["lost_lock"])[0][0]]
    with plots.style():
        axes = plots.time_panels(
            runs, ["return to I/f below 210 r/min (derived)",
                   "without it: angle jump at %.3f s, loss of lock at %.3f s"
                   % (r.faults.t_first, t_lost)],
            "scenarios/sensorless_load_step.toml through zero speed",
            [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true"),
                                ("n_hat_rpm", "estimated")]),
             ("position error (rad)", [("theta_error", "true")]),
             ("phase / fault", [("phase", "phase (0 I/f, 2 SMDO)"), ("fault", "fault word")])],
            t_window=(0.6, 1.6))
        print(plots.save(axes, ROOT / "docs" / "img", "zero_crossing"))


if __name__ == "__main__":
    main()
