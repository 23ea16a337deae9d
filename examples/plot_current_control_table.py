"""
Current control compared on one motor
=====================================

The README's table: conventional DBPC, robust DBPC (SMDO) and the
synchronous-frame PI (encoder and SMDO sensorless) on the yang2018 Table I
motor at 1500 r/min under the rated load. Each entry is the mean error and
the ripple of the true current against its reference over 0.3-0.6 s, in mA
(``smodrive.scenarios.drive.current_control_table``).
"""

import matplotlib.pyplot as plt

from smodrive import plots
from smodrive.scenarios import drive

table = drive.current_control_table()
keys = ["i_d_error_A", "i_q_error_A", "i_d_ripple_A", "i_q_ripple_A"]
print("current control, mA".ljust(22) + "".join(k[:-2].rjust(12) for k in keys))
for label, row in table.items():
    print(label.ljust(22) + "".join(f"{1e3 * row[k]:12.1f}" for k in keys))

# %%
# The same numbers as bars.
fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
width = 0.2
for j, label in enumerate(table):
    ax.bar([i + j * width for i in range(len(keys))], [1e3 * table[label][k] for k in keys],
           width, label=label)
ax.set_xticks([i + 1.5 * width for i in range(len(keys))], [k[:-2] for k in keys])
ax.set_ylabel("mA")
ax.axhline(0, color="k", lw=0.5)
ax.legend(fontsize=7)
plots.show(fig, "plot_current_control_table")
