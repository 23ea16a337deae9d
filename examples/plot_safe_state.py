"""
A fault's safe state: the zero vector or every switch open
===========================================================

A drive that trips applies its safe state (``controller.safe_state``):
``"zero_vector"`` shorts the motor's terminals, so its current decays only
through R_s (L_s / R_s = 10 ms on yang2018's motor), the back EMF driving more
around the short; ``"pwm_off"`` opens every switch, and the current returns
to the DC link through the diodes within half a millisecond and then stays
zero while the EMF's line peak is below ``u_dc``. The plant walks the open
inverter's legs event by event (``docs/architecture.md``, Plant). Here
yang2018's drive at 75 r/min under load trips at once (its overcurrent trip
set at 5 A, below the load's current), and the load's brake then stops the
rotor.
"""

import matplotlib.pyplot as plt
import numpy as np

from smodrive import plots
from smodrive.engine import simulate
from smodrive.scenarios import yang2018_setup

fig, (ax_i, ax_t) = plt.subplots(2, 1, figsize=(6, 5), sharex=True, layout="constrained")
for safe in ("zero_vector", "pwm_off"):
    s = yang2018_setup.fig56_scenario("trip", "robust").with_controller(i_trip=5.0,
                                                                        safe_state=safe)
    r = simulate(s.replace(duration=0.02))
    i = np.abs(r["i_alpha"] + 1j * r["i_beta"])
    print(f"{safe}: tripped at {r.faults.t_first * 1e3:.1f} ms, |i| {i[r.t >= 2e-3][0]:.3f} A "
          f"and torque {r['T_e'][r.t >= 2e-3][0]:+.3f} N m 2 ms later")
    ax_i.plot(r.t * 1e3, i, label=safe)
    ax_t.plot(r.t * 1e3, r["T_e"], label=safe)
ax_i.set_ylabel("|i_s| (A)")
ax_i.set_title("after an overcurrent trip at t = 0", fontsize=9)
ax_i.legend()
ax_t.set_ylabel("torque T_e (N m)")
ax_t.set_xlabel("time (ms)")
plots.show(fig, "plot_safe_state")
