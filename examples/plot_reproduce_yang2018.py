"""
Reproducing yang2018
====================

Deadbeat predictive current control with a multipurpose sliding-mode
disturbance observer: every experiment of the paper, its claims (the paper's
value, ours, the criterion and the verdict) and its figures, as
``smodrive reproduce yang2018`` writes them (``make reproduce`` for both
papers).

Run on its own this script reproduces the whole paper; in the documentation
build (``SMODRIVE_GALLERY_QUICK=1``) it runs the experiments of
:data:`QUICK` only (:func:`smodrive.report.gallery`).
"""

from smodrive import plots, report

PAPER = "yang2018"
QUICK = ("yang2018.fig1", "yang2018.fig2", "yang2018.fig5-6")

# %%
# The claims (each with its verdict) and the figures.
rep = report.gallery(PAPER, QUICK)
plots.show(name=f"{PAPER}_figures", files=rep.figures)
