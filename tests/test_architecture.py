"""The package is a house with one direction (issue 19): its modules stand
on floors, every import points to the same floor or down, there is no
import circle, no smodrive import hides inside a function, and no module is
a dumping ground. Read from the source with ast (nothing is imported), so a
new back-import or circle fails here, named, before anyone runs into it.

The floors, bottom up (docs/architecture.md draws them)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "smodrive"

#: each module's floor, by the first name after "smodrive." that matches
#: (longest prefix first); the package __init__ (the public API) is the roof
FLOORS: dict[str, int] = {
    "smodrive._util": 0,
    "smodrive.model": 1,
    "smodrive.claims": 1,
    "smodrive.design": 2,
    "smodrive.engine": 3,
    "smodrive.analysis": 4,
    "smodrive.plots": 5,
    "smodrive.firmware": 5,
    "smodrive.scenarios": 6,
    "smodrive.scenario_io": 7,
    "smodrive.sweep": 8,
    "smodrive.report": 9,
    "smodrive.cli": 10,
    "smodrive.cli_identify": 10,
    "smodrive.commission": 4,
    "smodrive.commission_lcl": 4,
    "smodrive.commission_outcomes": 4,
    "smodrive.fromlog": 2,
    "smodrive": 11,
}
#: the line count above which a module is a dumping ground to split
MAX_LINES = 650


def _modules() -> dict[str, Path]:
    out = {}
    for p in sorted(SRC.rglob("*.py")):
        rel = p.relative_to(SRC.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


MODULES = _modules()


def _floor(name: str) -> int:
    for prefix in sorted(FLOORS, key=len, reverse=True):
        if name == prefix or name.startswith(prefix + "."):
            return FLOORS[prefix]
    raise AssertionError(f"{name}: on no floor; add it to FLOORS")


def _package(name: str) -> str:
    """The package a relative import in module `name` starts from."""
    p = MODULES[name]
    return name if p.name == "__init__.py" else name.rsplit(".", 1)[0]


def _imports(name: str) -> list[tuple[str, int, bool]]:
    """(imported smodrive module, line, inside a function) of module `name`."""
    tree = ast.parse(MODULES[name].read_text())
    out: list[tuple[str, int, bool]] = []

    def visit(node: ast.AST, in_fn: bool) -> None:
        for child in ast.iter_child_nodes(node):
            fn = in_fn or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
            if isinstance(child, ast.Import):
                for a in child.names:
                    if a.name == "smodrive" or a.name.startswith("smodrive."):
                        out.append((a.name, child.lineno, in_fn))
            elif isinstance(child, ast.ImportFrom):
                if child.level:
                    base = _package(name).split(".")
                    base = base[:len(base) - (child.level - 1)]
                    mod = ".".join(base + ([child.module] if child.module else []))
                else:
                    mod = child.module or ""
                if not (mod == "smodrive" or mod.startswith("smodrive.")):
                    continue
                for a in child.names:  # `from pkg import module` imports the module
                    sub = f"{mod}.{a.name}"
                    out.append((sub if sub in MODULES else mod, child.lineno, in_fn))
            visit(child, fn)

    visit(tree, False)
    return out


GRAPH = {m: sorted({t for t, _, _ in _imports(m) if t != m}) for m in MODULES}


def test_every_module_is_on_a_floor():
    assert len(MODULES) > 40  # the whole package was read
    for m in MODULES:
        _floor(m)


def test_imports_point_down_or_along_a_floor():
    up = [f"{m} (floor {_floor(m)}) imports {t} (floor {_floor(t)}), line {ln}"
          for m in MODULES for t, ln, _ in _imports(m) if _floor(t) > _floor(m)]
    assert up == []


def _cycle(graph: dict[str, list[str]] = GRAPH) -> list[str] | None:
    state: dict[str, int] = {}
    stack: list[str] = []

    def dfs(m: str) -> list[str] | None:
        state[m] = 1
        stack.append(m)
        for t in graph.get(m, []):
            if state.get(t) == 1:
                return stack[stack.index(t):] + [t]
            if t not in state and (c := dfs(t)):
                return c
        stack.pop()
        state[m] = 2
        return None

    for m in graph:
        if m not in state and (c := dfs(m)):
            return c
    return None


def test_the_import_graph_has_no_circle():
    assert _cycle() is None, " -> ".join(_cycle() or [])


def test_the_circle_check_finds_a_planted_circle():
    """The check above can fail: a back-import from the model to the engine
    closes a circle (the engine imports the model), and it is found."""
    g = {k: list(v) for k, v in GRAPH.items()}
    g["smodrive.model.fields"] = g["smodrive.model.fields"] + ["smodrive.engine.run"]
    c = _cycle(g)
    assert c is not None and "smodrive.model.fields" in c


def test_no_smodrive_import_inside_a_function():
    hidden = [f"{m}:{ln} imports {t}" for m in MODULES for t, ln, in_fn in _imports(m) if in_fn]
    assert hidden == []


@pytest.mark.parametrize("name", sorted(MODULES))
def test_no_module_is_a_dumping_ground(name):
    n = len(MODULES[name].read_text().splitlines())
    assert n <= MAX_LINES, f"{name}: {n} lines (split it by what it does)"


def test_the_public_api_is_named():
    tree = ast.parse((SRC / "__init__.py").read_text())
    names = [n for node in tree.body if isinstance(node, ast.Assign)
             for t in node.targets if isinstance(t, ast.Name) and t.id == "__all__"
             for n in ast.literal_eval(node.value)]
    assert {"Scenario", "load_scenario", "simulate", "Result", "ParameterError"} <= set(names)
