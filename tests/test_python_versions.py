"""What `requires-python` promises (3.10 and later) holds for the source:
every use of tomllib (3.11+) falls back to tomli, the same parser as a
package, which pyproject.toml requires on 3.10 (issue 13.2). A fresh
`make test` on 3.10 found the one import that did not."""

from __future__ import annotations

import re
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]


def _python_files():
    for top in ("src", "tests", "tools", "benchmarks", "examples", "fuzz", "docs"):
        yield from (ROOT / top).rglob("*.py")


def test_every_tomllib_import_falls_back_to_tomli():
    bare = []
    for path in _python_files():
        lines = path.read_text(encoding="utf-8").splitlines()
        for i, ln in enumerate(lines):
            if re.match(r"\s*(import tomllib|from tomllib import)", ln):
                prev = lines[i - 1].strip() if i else ""
                after = " ".join(l.strip() for l in lines[i + 1:i + 3])
                if prev != "try:" or "except ModuleNotFoundError" not in after \
                        or "tomli" not in after:
                    bare.append(f"{path.relative_to(ROOT)}:{i + 1}")
    assert not bare, bare


def test_pyproject_requires_tomli_where_tomllib_is_missing():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert meta["requires-python"] == ">=3.10"
    assert any(re.match(r"tomli\b.*python_version\s*<\s*['\"]3\.11['\"]", d)
               for d in meta["dependencies"]), meta["dependencies"]
