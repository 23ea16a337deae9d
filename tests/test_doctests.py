"""The docstring examples of every module of the package run as written
(issue 13, point 5): the API reference shows them, so they must be true.
Each module's examples run with doctest; a module with an example that fails
fails here with doctest's report."""

from __future__ import annotations

import doctest
import importlib
import importlib.util
import pkgutil

import pytest

import smodrive

# the Python modules (not the C library, which the loader also finds)
MODULES = ["smodrive"] + sorted(m.name for m in pkgutil.walk_packages(smodrive.__path__, "smodrive.")
                 if str(importlib.util.find_spec(m.name).origin).endswith(".py"))
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE

# modules whose examples the documentation points users to: they must have some
WITH_EXAMPLES = {"smodrive", "smodrive.engine.run", "smodrive.scenario_io",
                 "smodrive.engine.export", "smodrive.report", "smodrive.model.fields",
                 "smodrive.model.derive", "smodrive.plots"}


def _run(name: str) -> doctest.TestResults:
    mod = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    out: list[str] = []
    for test in finder.find(mod, name):
        runner.run(test, out=out.append)
    res = runner.summarize(verbose=False)
    assert res.failed == 0, "".join(out)
    return res


def test_the_package_has_its_modules():
    assert {"smodrive.model.scenario", "smodrive.engine.run", "smodrive.cli",
            "smodrive.engine.export", "smodrive.design.yao2022", "smodrive.firmware.cycles",
            "smodrive.scenarios.yao2022"} <= set(MODULES)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name):
    res = _run(name)
    if name in WITH_EXAMPLES:
        assert res.attempted >= 1, f"{name}: no docstring example"


def test_a_wrong_example_fails():
    """The runner above reports a wrong expected output (so a passing module
    is one whose examples are right)."""
    bad = doctest.DocTestParser().get_doctest(">>> 1 + 1\n3\n", {}, "bad", None, 0)
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    runner.run(bad, out=lambda s: None)
    assert runner.summarize(verbose=False).failed == 1
