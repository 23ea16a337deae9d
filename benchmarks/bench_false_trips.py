"""False trips of the supervision over long random operation (issue 18).

Each machine of scenarios/motors/ (and tests/motors/ with --all) runs
minutes of random speed steps (uniform in +-w_M_N) and brake steps (uniform
in [0, T_N]), 20 of each a minute, from an I/f start, under sensorless
robust DBPC with every value derived (smodrive.scenarios.trials); the
script prints, per machine, the minutes run, the runs that ended in a fault
(a trip: the drive stopped) by name, the runs with an event the drive
reported and went on from (an automatic restart of a rotor lost and started
again on I/f, an angle jump, an oscillation warning) by their first event,
and the simulated time per wall second. Not a test: the counts are
figures to watch (tests/test_own_motor.py bounds 20 minutes).

    .venv/bin/python benchmarks/bench_false_trips.py --minutes 60
"""

from __future__ import annotations

import argparse
import collections
import time
import warnings
from pathlib import Path

import numpy as np

from smodrive.scenario_io import load_scenario
from smodrive.scenarios import trials
from smodrive.engine import fault_names, simulate

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--minutes", type=int, default=60, help="simulated minutes per machine")
    ap.add_argument("--all", action="store_true", help="also the data-sheet motors of tests/")
    ap.add_argument("--seed", type=int, default=11)
    a = ap.parse_args()
    files = sorted((ROOT / "scenarios" / "motors").glob("*.toml"))
    if a.all:
        files += sorted((ROOT / "tests" / "motors").glob("*.toml"))
    warnings.simplefilter("ignore")
    print(f"{'machine':28s} {'minutes':>7s} {'trips':>5s} {'events':>6s}  trips; first events  "
          "sim s / wall s")
    for f in files:
        base = load_scenario(f)
        rng = np.random.default_rng(a.seed)
        trips: collections.Counter = collections.Counter()
        restarts: collections.Counter = collections.Counter()
        t0 = time.perf_counter()
        for k in range(a.minutes):
            r = simulate(trials.random_profile(base, rng, seed=k + 1))
            if r.faults.final:
                trips[", ".join(fault_names(r.faults.final))] += 1
            elif r.faults.first:
                restarts[", ".join(fault_names(r.faults.first))] += 1
        wall = time.perf_counter() - t0
        print(f"{f.stem:28s} {a.minutes:7d} {sum(trips.values()):5d} {sum(restarts.values()):6d}  "
              f"{dict(trips) or '-'}; {dict(restarts) or '-'}  {60.0 * a.minutes / wall:.0f}")


if __name__ == "__main__":
    main()
