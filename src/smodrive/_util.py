"""Small helpers every layer uses: number tests and forms, atomic file writes.

The bottom of the package: it imports nothing of smodrive.
"""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np

# the TOML parser: the standard library's from Python 3.11, the same as a package before
try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover (Python 3.10)
    import tomli as tomllib  # type: ignore[no-redef]

__all__ = ["tomllib", "fmt_g", "fmt4", "is_num", "is_real", "plain"]


def fmt_g(x: float) -> str:
    """A number as %g (ranges in messages)."""
    return f"{x:g}"


def fmt4(x: float | None) -> str:
    """A number to 4 significant digits for tables; None or NaN as '-'."""
    if x is None or x != x:
        return "-"
    return f"{x:.4g}"


def is_num(x: Any) -> bool:
    """A Python int or float, not a bool (a TOML number)."""
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def is_real(v: Any) -> bool:
    """A real number (Python or NumPy), not a bool."""
    return isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))


def plain(v: Any) -> Any:
    """A NumPy scalar as the Python int, float or bool it holds (so that
    np.int64(4) or np.float32(1e-3) work wherever a Python number does);
    anything else unchanged."""
    if v is None or type(v) in (bool, int, float, str):
        return v
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, numbers.Integral):
        return int(v)
    if isinstance(v, numbers.Real):
        return float(v)
    return v
