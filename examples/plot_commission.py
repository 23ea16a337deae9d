"""
Commission a motor: the drive measures R_s, L_s and psi_r
==========================================================

``smodrive.commission.commission`` (issue 23): the core's tests
(``smodrive/smd_ident.h``) against the servo of ``scenarios/motors/``,
seeing only the ADC's currents and the DC-link voltage; then the drive
designed from what they measured. The figure shows step 1's levels and its
least-squares line, whose intercept is the inverter's drop.
"""

import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from smodrive import plots


def repo_root() -> Path:
    """The checkout (the gallery runs from a copy of docs/)."""
    here = Path(__file__).resolve() if "__file__" in globals() else Path.cwd()
    for p in (Path.cwd(), *here.parents):
        if (p / "scenarios" / "motors").is_dir():
            return p
    raise FileNotFoundError("scenarios/motors")


start = Path.cwd()
os.chdir(repo_root())  # the README's example runs from the checkout

from smodrive.commission import commission
from smodrive.scenario_io import load_scenario

s = load_scenario("scenarios/motors/servo_48v_200w.toml")
c = commission(s)
print(c.rs.R_s, c.L_s, c.psi.psi)  # 0.2502 ohm, 0.00049 H, 0.01753 Wb
drive = s.with_controller(R_s_hat=c.rs.R_s, L_s_hat=c.L_s, psi_r_hat=c.psi.psi)
os.chdir(start)

i, u = np.array(c.rs.i_levels), np.array(c.rs.u_levels)
fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
ax.plot(i, u, "o", label="levels (settled, averaged)")
x = np.linspace(0.0, i.max(), 50)
ax.plot(x, c.rs.R_s * x + c.rs.u_0, "-",
        label=f"u = {c.rs.R_s:.4f} ohm i + {c.rs.u_0:.3f} V (R^2 {c.rs.r2:.6f})")
ax.set_xlabel("current along alpha (A)")
ax.set_ylabel("applied voltage command (V)")
ax.set_title(f"R_s test: true R_s {s.motor.R_s} ohm; L_s {c.L_s * 1e3:.4f} mH "
             f"(true {s.motor.L_s * 1e3:.4g}), psi_r {c.psi.psi:.5f} Wb (true {s.motor.psi_r})",
             fontsize=8)
ax.legend()
plots.show(fig, "plot_commission")
