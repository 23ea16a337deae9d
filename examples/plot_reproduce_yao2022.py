"""
Reproducing yao2022
====================

Sliding-mode position estimation with chattering suppression for an
LCL-filtered 100 kr/min SPMSM: every experiment of the paper, its claims (the paper's
value, ours, the criterion and the verdict) and its figures, as
``smodrive reproduce yao2022`` writes them (``make reproduce`` for both
papers).

Run on its own this script reproduces the whole paper; in the documentation
build (``SMODRIVE_GALLERY_QUICK=1``) it runs the experiments of
:data:`QUICK` only.
"""

import os
import tempfile
import types
from pathlib import Path

import matplotlib.pyplot as plt

from smodrive import report
from smodrive.scenarios import PAPERS

PAPER = "yao2022"
QUICK = ("yao2022.table1", "yao2022.fig7", "yao2022.fig9-10")

experiments = PAPERS[PAPER].EXPERIMENTS
if os.environ.get("SMODRIVE_GALLERY_QUICK"):
    experiments = [e for e in experiments if e.id in QUICK]
PAPERS["_gallery"] = types.SimpleNamespace(EXPERIMENTS=experiments)
out = Path(tempfile.mkdtemp())
rep = report.reproduce(["_gallery"], out)
del PAPERS["_gallery"]

# %%
# The claims.
for c in rep.claims:
    print(f"{c.status:12s} {c.id}: reproduced {c.reproduced:.4g} {c.unit} "
          f"({c.describe_check()})")

# %%
# The figures.
for png in rep.figures:
    fig, ax = plt.subplots(figsize=(9, 6), layout="constrained")
    ax.imshow(plt.imread(png))
    ax.set_axis_off()
    ax.set_title(png.stem)
plt.show()
