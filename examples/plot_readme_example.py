"""
A drive in fifteen lines
========================

The README's first example, as it is written there: the yang2018 motor
under PI current control on the SMDO's position (a composition neither paper
runs), 1500 r/min, rated brake load; then its speed, currents and angle
error drawn on a figure of your own (every drawing function of
:mod:`smodrive.plots` takes the Axes to draw on).
"""

# %%
# The README example (``tests/test_gallery.py`` checks that it is the README's
# code, verbatim).
import numpy as np
from smodrive import RPM, ControllerCfg, LoadCfg, MotorPars, Profile, Scenario, simulate

motor = MotorPars()  # yang2018 Table I
s = Scenario(
    duration=1.0,
    w_M0=1500 * RPM,
    w_M_ref=Profile.const(1500 * RPM),
    controller=ControllerCfg(current="pi", position="smdo_emf", start="handover", t_handover=0.2),
    load=LoadCfg(T_brake=Profile.const(motor.T_N)),
)
r = simulate(s)  # one call into C per chunk: the plant and the firmware controller
m = r.window(0.5, 1.0)
print(f"RMS position error {np.degrees(np.sqrt(np.mean(r.theta_error[m] ** 2))):.2f} deg")

# %%
# The run on a figure: rows of ``(label, [(channel, legend), ...])``, any
# logged channel (``smodrive.engine.CHANNELS``) or derived one
# (``smodrive.plots.DERIVED``).
import matplotlib.pyplot as plt

from smodrive import plots

fig, axes = plt.subplots(3, 1, figsize=(7, 6), sharex=True, layout="constrained")
plots.time_panels(
    [r], ["PI current control, SMDO position"], None,
    [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true"),
                        ("n_hat_rpm", "estimated")]),
     ("motor current (A)", [("i_d", "d"), ("i_q", "q")]),
     ("angle error (deg)", [("theta_error_deg", "true - estimated")])],
    ax=axes)
plots.show(fig, "plot_readme_example")
