"""Transfer functions of the papers' analyses and metrics of logged signals."""
