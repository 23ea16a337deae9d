"""How `make test` spreads the tests over processes (pytest-xdist,
`pytest -n <cores>`); a plain `pytest` (no -n) runs as before.

Under xdist each worker is its own process, so what a module computes once
(a module-scoped fixture; the functools.cache of the papers' claims) would be
computed again by every worker that runs one of its tests. So the tests are
handed to the workers in units, each run by one worker:

- the papers' claims: test_yang2018_claims.py, test_yao2022_claims.py,
  test_claims_data.py and test_fast_build.py share paper_claims() (every
  experiment of a paper);
- each test of the modules in SPLIT (long tests that share nothing) alone;
- every other module as a whole (as `--dist loadscope`).

The units that take long go first (the longest first is the usual rule for
two machines), so that the run does not end with one worker busy for many
seconds and the other idle. (xdist's own `--dist loadgroup` would do the
grouping from `xdist_group` marks, but it does not group on pytest 9.2:
pytest-dev/pytest-xdist#1386.)
"""

from __future__ import annotations

import pytest

#: test files whose tests share paper_claims() (functools.cache, per process)
PAPER_CLAIMS = ("test_claims_data.py", "test_yang2018_claims.py", "test_yao2022_claims.py",
                "test_fast_build.py")

#: modules without a module-scoped fixture whose tests are long: one unit a test
SPLIT = ("test_own_motor.py", "test_gallery.py", "test_sweep.py", "test_sweep_cli.py",
         "test_cli_results.py",
         "test_benchmark_smoke.py", "test_vs_motulator_smoke.py")

#: long units (CPU seconds measured 2026-11-26, one process), the longest
#: first: a test (all its parametrisations) or a module. A unit not listed
#: keeps its place in the collection, after these.
LONG_FIRST = (
    "tests/test_own_motor.py::test_no_false_trip_in_random_operation",  # 3 x 18 s
    "tests/test_claims_data.py",  # the papers' claims, 21 s
    "tests/test_params.py",  # 14 s (the TOML round trip 12.6 s)
    "tests/test_gallery.py::test_the_documentation_builds_without_warnings",  # 11 s
    "tests/test_gallery.py::test_reproduction_script_short_version",  # 7.6 s and 4.1 s
    "tests/test_plots.py",  # 7.5 s
    "tests/test_sweep.py::test_killed_sweep_resumes_with_the_missing_runs_only",  # 7 s
    "tests/test_yao2022_design.py",  # 2 s, and on the way to the 5 s units below
    "tests/test_benchmark_smoke.py::test_benchmark_script_runs",  # 5 s
    "tests/test_gallery.py::test_lcl_encoder_and_exports_examples",  # 3.9 s
    "tests/test_cli_results.py::test_a_run_ending_in_a_fault_exits_1_and_says_why_on_stderr",
    "tests/test_vs_motulator_smoke.py::test_vs_motulator_script_runs_without_motulator",
    "tests/test_target.py",  # 3.5 s
    "tests/test_own_motor.py::test_data_sheet_motor_runs_the_usual_profile",
)


def _unit(nodeid: str) -> str:
    """The unit of work a test belongs to."""
    module = nodeid.split("::", 1)[0]
    name = module.rsplit("/", 1)[-1]
    if name in PAPER_CLAIMS:
        return "paper_claims"
    if name in SPLIT:
        return nodeid
    return module


def _rank(nodeid: str) -> int:
    base = nodeid.split("[", 1)[0]
    module = nodeid.split("::", 1)[0]
    if _unit(nodeid) == "paper_claims":
        module = "tests/test_claims_data.py"
    for k, key in enumerate(LONG_FIRST):
        if key in (base, module):
            return k
    return len(LONG_FIRST)


@pytest.hookimpl(trylast=True)  # after pytest's own ordering (by fixture scope)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """On an xdist worker: the long units first (every worker collects the
    same order; the scheduler hands out units in it). Within a rank, and
    within a unit, the collection order."""
    if hasattr(config, "workerinput"):
        items.sort(key=lambda it: _rank(it.nodeid))


@pytest.hookimpl(optionalhook=True)  # a hook of xdist: pytest without xdist runs too
def pytest_xdist_make_scheduler(config: pytest.Config, log):
    """`-n N` (xdist's default --dist load): the units above, in collection
    order. Another --dist given explicitly is left to xdist."""
    if config.getvalue("dist") != "load":
        return None
    from xdist.scheduler import LoadScopeScheduling

    class UnitScheduling(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return _unit(nodeid)

    config.option.loadscopereorder = False  # keep the long-first order
    return UnitScheduling(config, log)
