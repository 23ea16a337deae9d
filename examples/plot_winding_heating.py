"""
Track a heating winding: the drive's online R_s / psi_r estimate
================================================================

``controller.rls_i_inj`` (issue 23; ``smodrive/smd_rls.h``): recursive
least squares on the stator equation, excited by a d-axis square wave. The
plant's winding heats (``R_s_scale``: +40 % over half a second) while
Table I's drive runs at half rated speed and torque with its encoder, then
without it (the SMDO's angle: the tracker fits in the frame of the angle's
means over whole periods of its square wave, and the SMDO takes its R_s);
the figure shows the true R_s and the drive's two estimates.
"""

import matplotlib.pyplot as plt
import numpy as np

from smodrive import plots
from smodrive.engine import simulate
from smodrive.model import LoadCfg, Profile, Scenario

s = Scenario()  # yang2018 Table I
m = s.motor
s = s.replace(duration=4.0, w_M0=0.5 * m.w_M_N, w_M_ref=Profile.const(0.5 * m.w_M_N),
              load=LoadCfg(T_ext=Profile.const(0.5 * m.T_N)),
              R_s_scale=Profile((0.0, 1.0, 1.5), (1.0, 1.0, 1.4)))
s = s.with_controller(current="robust_dbpc", position="encoder", start="handover",
                      rls_i_inj=0.4 * m.T_N / m.k_t)  # a +-2.5 A square wave on i_d
r = simulate(s)
print(f"R_s {r['R_s_rls'][-1]:.3f} ohm (true {1.4 * m.R_s:.3f}), "
      f"psi_r {r['psi_r_rls'][-1]:.4f} Wb (true {m.psi_r})")
r = simulate(s.with_controller(position="smdo_emf"))  # without the encoder
print(f"R_s {r['R_s_rls'][-1]:.3f} ohm, psi_r {r['psi_r_rls'][-1]:.4f} Wb, status {r.status}")
# R_s 3.148 ohm (true 3.150), psi_r 0.4000 Wb (true 0.4)
# R_s 3.150 ohm, psi_r 0.3998 Wb, status 0
r_enc = simulate(s)

fig, ax = plt.subplots(figsize=(6, 3.5), layout="constrained")
t = r["t"]
ax.plot(t, m.R_s * np.interp(t, s.R_s_scale.t, s.R_s_scale.y), "k--",
        label="true R_s (the winding heats)")
ax.plot(t, r_enc["R_s_rls"], label="the drive's estimate, with its encoder")
ax.plot(r["t"], r["R_s_rls"], label="the drive's estimate, without it")
ax.set_xlabel("time (s)")
ax.set_ylabel("R_s (ohm)")
ax.legend()
plots.show(fig, "plot_winding_heating")
