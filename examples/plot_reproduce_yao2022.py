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
:data:`QUICK` only (:func:`smodrive.report.gallery`).
"""

import matplotlib.pyplot as plt

from smodrive import report

PAPER = "yao2022"
QUICK = ("yao2022.table1", "yao2022.fig7", "yao2022.fig9-10")

# %%
# The claims (each with its verdict) and the figures.
rep = report.gallery(PAPER, QUICK)
# sphinx_gallery_start_ignore
# Without a display (a non-interactive backend: MPLBACKEND=Agg, or no
# display to open a window on) plt.show() shows nothing: the figures are
# kept as PNG files in the folder PAPER_figures of the current folder
# instead, its path printed on stderr.
import shutil  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

if "sphinx_gallery" not in sys.modules and plt.get_backend().lower() in (
        "agg", "cairo", "pdf", "pgf", "ps", "svg", "template"):
    keep = Path(f"{PAPER}_figures").resolve()
    keep.mkdir(exist_ok=True)
    for png in rep.figures:
        shutil.copy2(png, keep / png.name)
    plt.close("all")
    print(f"no display: the {len(rep.figures)} figures are in {keep}", file=sys.stderr)
# sphinx_gallery_end_ignore
plt.show()
