"""Parameter sweeps and Monte Carlo over a scenario, on Dask, into Parquet.

A sweep file (TOML) names a base scenario and the axes to vary; every
combination of axis values (or a Latin-hypercube sample of the continuous
axes), crossed with the noise seeds, is a run. Each run is reduced in the
worker to the metrics the sweep names (the registry
:data:`smodrive.analysis.metrics.METRICS`), and every finished batch of runs
becomes one Parquet file of ``OUT/runs/``, one row a run, keyed by a
deterministic run id: a sweep started again with the same file computes only
the runs that have no row yet (another sweep into that folder is refused).

Example (``docs/sweeps.md`` has the whole format)::

    [sweep]
    base = "drive.pi_encoder"            # a catalogue name or a scenario TOML
    metrics = ["id_error", "iq_error", "ripple"]
    window = [0.3, 0.6]                  # s: where the metrics are taken

    [[axes]]
    name = "L_ratio"
    key = "controller.L_s_hat"           # a scenario TOML key (dotted)
    relative_to = "motor.L_s"            # the value is a factor of this field
    range = [0.4, 2.5]
    n = 8

    [seeds]
    n = 4                                # adc.seed = 0, 1, 2, 3

>>> spec = load_sweep(builtin_path("yang2018_current"))   # doctest: +SKIP
>>> report = run_sweep(spec, "out/sweep1", workers=2)      # doctest: +SKIP

The modules, each importing only those above it:

- :mod:`smodrive.sweep.axes`: an axis or ``[seeds]`` table parsed and checked; the
  changes an axis value makes (applied by :func:`smodrive.scenario_io.apply`);
- :mod:`smodrive.sweep.plotspec`: the ``[[plots]]`` entries checked, the analytic overlays;
- :mod:`smodrive.sweep.spec`: a sweep file into a :class:`SweepSpec`, the built-in
  sweeps (``builtin/*.toml``), the run count and its bound;
- :mod:`smodrive.sweep.plan`: the runs of a spec (:func:`expand`), their ids, their check;
- :mod:`smodrive.sweep.worker`: a run in a Dask worker, reduced to one row;
- :mod:`smodrive.sweep.store`: OUT, its Parquet parts and ``sweep.json``, read back;
- :mod:`smodrive.sweep.run`: batches on Dask (or in this process), :func:`run_sweep`;
- :mod:`smodrive.sweep.cells`: what each cell of a map shows (a value where the runs held
  their operating point; else why not, or the fault's kind);
- :mod:`smodrive.sweep.maps`: the maps of the results (:func:`plot_all`).
"""

from .axes import STANDARD_COLUMNS, Axis, apply_changes
from .cells import Cells, cells
from .maps import envelope_values, figure, lowest_holding, panel_norm, plot_all
from .plan import ROW_FORMAT, Run, check_runs, expand
from .plotspec import OVERLAYS, PLOT_KINDS, check_plots
from .run import SweepReport, estimate_seconds, make_batches, run_local, run_sweep, start_client
from .spec import (
    BUILTIN_DIR,
    MAX_RUNS,
    SweepSpec,
    builtin_path,
    builtins,
    check_run_count,
    load_sweep,
    parse_sweep,
    run_count,
)
from .store import (
    check_out,
    done_ids,
    done_rows,
    identity,
    load_out_spec,
    load_results,
    prepare_out,
    read_parts,
    write_part,
)
from .worker import Job, run_batch, run_one, version

__all__ = ["Axis", "Run", "SweepSpec", "SweepReport", "Job", "STANDARD_COLUMNS", "MAX_RUNS",
           "BUILTIN_DIR", "PLOT_KINDS", "OVERLAYS", "builtins", "builtin_path", "load_sweep",
           "parse_sweep", "run_count", "check_run_count", "apply_changes", "expand",
           "check_runs", "check_plots", "estimate_seconds", "make_batches", "start_client",
           "run_sweep", "run_local", "run_one", "run_batch", "version", "prepare_out",
           "load_out_spec", "check_out", "identity", "done_ids", "done_rows", "read_parts",
           "load_results", "write_part", "plot_all",
           "lowest_holding", "envelope_values", "Cells", "cells", "figure", "panel_norm",
           "ROW_FORMAT"]
