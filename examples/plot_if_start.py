"""
Sensorless start from standstill (I/f)
======================================

``drive.if_start`` (``scenarios/if_start.toml``): yang2018's sensorless
robust DBPC started from standstill under the rated brake by I/f (a forced
angle and 10 A ramped at 3,000 r/min/s), handed over to the SMDO at 150
r/min, reaching 1500 r/min.
"""

import matplotlib.pyplot as plt
import numpy as np

from smodrive import plots
from smodrive.scenarios import drive
from smodrive.engine import simulate

r = simulate(drive.if_start())
m = r.window(r.scenario.duration - 0.1, r.scenario.duration)
print(f"final speed {np.mean(r.n_rpm[m]):.1f} r/min, angle error "
      f"{np.degrees(np.sqrt(np.mean(r.theta_error[m] ** 2))):.2f} deg RMS over the last 0.1 s")

fig, axes = plt.subplots(3, 1, figsize=(7, 6), sharex=True, layout="constrained")
plots.time_panels(
    [r], ["I/f start, handover to the SMDO"], None,
    [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true"),
                        ("n_hat_rpm", "estimated")]),
     ("angle error (deg)", [("theta_error_deg", "true - estimated")]),
     ("phase", [("phase", "0 I/f, 2 SMDO")])],
    ax=axes)
plots.show(fig, "plot_if_start")
