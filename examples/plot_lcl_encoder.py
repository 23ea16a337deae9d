"""
The LCL-filtered high-speed drive on an encoder
===============================================

``drive.lcl_encoder`` (``scenarios/lcl_encoder.toml``): the yao2022 drive
(an SPMSM behind an LCL filter, 20 kHz) on the encoder, the reference its
sensorless observers are compared with.
"""

import matplotlib.pyplot as plt
import numpy as np

from smodrive import plots
from smodrive.scenarios import drive
from smodrive.engine import simulate

r = simulate(drive.lcl_encoder())
m = r.window(r.scenario.duration / 2, r.scenario.duration)
print(f"mean speed {np.mean(r.n_rpm[m]):.0f} r/min, motor current |i| "
      f"{np.mean(np.hypot(r['i_d'][m], r['i_q'][m])):.2f} A, capacitor voltage "
      f"{np.mean(np.hypot(r['uc_alpha'][m], r['uc_beta'][m])):.1f} V")

fig, axes = plt.subplots(3, 1, figsize=(7, 6), sharex=True, layout="constrained")
plots.time_panels(
    [r], ["yao2022 drive, encoder"], None,
    [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true")]),
     ("current (A)", [("i_abs", "motor |i_2|"), ("i1_abs", "inverter |i_1|")]),
     ("capacitor |u_c| (V)", [("uc_abs", "filter capacitor")])],
    ax=axes)
plots.show(fig, "plot_lcl_encoder")
