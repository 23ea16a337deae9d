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

from smodrive import plots, report

PAPER = "yao2022"
QUICK = ("yao2022.table1", "yao2022.fig7", "yao2022.fig9-10")

# %%
# The claims (each with its verdict) and the figures.
rep = report.gallery(PAPER, QUICK)
plots.show(name=f"{PAPER}_figures", files=rep.figures)
