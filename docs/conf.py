"""Sphinx configuration of the smodrive documentation site (`make docs`).

`make docs` copies docs/ to build/docs-src and builds build/docs from the
copy, so that what Sphinx generates (the API stubs of autosummary, the
gallery sphinx-gallery runs from examples/) stays out of the source tree.
Before the build the parameter tables of parameters.md are regenerated from
the dataclass metadata (tools/gen_parameters.py): the parameter reference is
the code's, never a stale copy. The package documented is the one installed
in the environment (`make docs` installs it with the extra `docs`).
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path


def _root() -> Path:
    """The repository: $SMODRIVE_ROOT if set (a copy of docs/ built outside
    the checkout, as tests/test_gallery.py does), else the first parent of
    this file with pyproject.toml and examples/."""
    here = Path(__file__).resolve().parent
    env = os.environ.get("SMODRIVE_ROOT")
    for p in ([Path(env)] if env else [here, *here.parents]):
        if (p / "pyproject.toml").is_file() and (p / "examples").is_dir():
            return p
    raise RuntimeError(f"no smodrive checkout above {here}")


ROOT = _root()
sys.path.insert(0, str(ROOT / "tools"))

import gen_parameters  # noqa: E402  (tools/, found through the path above)

# the parameter reference from the metadata, written into the copy being built
gen_parameters.main(["--doc", str(Path(__file__).resolve().parent / "parameters.md")])

# the README as the site's first page: its links into docs/ made relative to
# this folder (images and the Markdown notes live here)
_here = Path(__file__).resolve().parent
_readme = (ROOT / "README.md").read_text(encoding="utf-8")
(_here / "readme.md").write_text(_readme.replace("](docs/", "]("), encoding="utf-8")

# gallery scripts run their short versions (each says what its full run does)
os.environ.setdefault("SMODRIVE_GALLERY_QUICK", "1")

project = "smodrive"
author = "smodrive contributors"
copyright = "smodrive contributors"
try:
    from importlib.metadata import version as _version

    release = _version("smodrive")
except Exception:  # pragma: no cover - the package is not installed
    release = "0"

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "auto_examples/*.ipynb", "auto_examples/*.py",
                    "auto_examples/*.zip", "auto_examples/*.json"]
myst_heading_anchors = 3
suppress_warnings = ["myst.header", "myst.xref_missing", "misc.highlighting_failure"]

autosummary_generate = True
# each object documented once, where it is defined: a package's __all__
# re-exports its modules' names (from smodrive.engine import simulate), which
# autodoc would document a second time under the package
autodoc_default_options = {"members": True, "show-inheritance": True, "ignore-module-all": True}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
napoleon_numpy_docstring = True

sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("matplotlib",),
}

html_theme = "alabaster"
html_title = "smodrive"
html_static_path: list[str] = []


_GLOB_STAR = re.compile(r"(?<=/)\*")


def _escape_bars(app, what, name, obj, options, lines) -> None:
    """The docstrings are plain text: ``|x|`` is a magnitude there, not a
    reStructuredText substitution, and the ``*`` of a file pattern
    (``scenarios/*.toml``) is not the start of an emphasis; escape them
    outside doctest blocks and literal code."""
    in_doctest = False
    for k, line in enumerate(lines):
        s = line.strip()
        if s.startswith(">>>"):
            in_doctest = True
        elif not s:
            in_doctest = False
        if not in_doctest and "``" not in line:
            lines[k] = _GLOB_STAR.sub(r"\\*", line.replace("|", "\\|"))


def setup(app) -> None:
    app.connect("autodoc-process-docstring", _escape_bars)
