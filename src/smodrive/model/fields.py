"""The parameter machinery: units, the error every bad value raises, the
field kinds with their valid ranges and units, the validating mixin and the
piecewise-linear :class:`Profile` (the bottom of :mod:`smodrive.model`).

Every numeric field carries its valid range and unit; building a dataclass
with a bad value raises :class:`ParameterError` naming the field, the value
and the range, before anything is simulated.

Example
-------
>>> from smodrive.model import MotorPars
>>> MotorPars(L_s=-1.0)
Traceback (most recent call last):
...
smodrive.model.ParameterError: motor.L_s = -1.0 is outside its valid range [1e-08, 10] H
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._util import fmt_g as _fmt
from .._util import is_real as _is_real
from .._util import plain as _plain

RPM = 2.0 * math.pi / 60.0  # rad/s per r/min
#: The LCL observers' lookup tables cover this mechanical speed either way,
#: r/min (smodrive.engine.TABLE_RPM): a run of those observers stays inside.
LCL_TABLE_RPM = 110e3


class ParameterError(ValueError):
    """A parameter is missing, unknown, or outside its valid range."""

    __module__ = "smodrive.model"  # the name users see in a traceback: where they import it


def num(default: Any, lo: float, hi: float, unit: str, doc: str, *, lo_open: bool = False,
        integer: bool = False, n: int = 0) -> Any:
    """A numeric dataclass field with range metadata (a tuple default makes
    it a vector of that length; a None default makes the field optional:
    None then means "derived", see the field's doc)."""
    n = len(default) if isinstance(default, tuple) else n
    return field(default=default, metadata={"range": (lo, hi, lo_open), "unit": unit, "doc": doc,
                                             "integer": integer, "n": n})


def flag(default: bool, doc: str) -> Any:
    """A boolean dataclass field."""
    return field(default=default, metadata={"bool": True, "doc": doc})


def choice(default: str, options: tuple[str, ...], doc: str) -> Any:
    return field(default=default, metadata={"choices": options, "doc": doc})


def _profile_text(p: "Profile") -> str:
    """A profile as a user wrote it: the number of a constant one, else the
    TOML table."""
    if len(p.t) == 1:
        return repr(p.y[0])
    return "{t = [" + ", ".join(map(repr, p.t)) + "], y = [" + ", ".join(map(repr, p.y)) + "]}"


class _Validated:
    """Mixin: range-check every field in __post_init__ (NumPy scalars are
    taken as the Python numbers they hold; a number given for a Profile
    field is a constant profile)."""

    _section = ""
    #: profile field -> (lo, hi, unit, why): the range of every value of it
    _profile_ranges: dict[str, tuple[float, float, str, str]] = {}

    def _normalise(self, f: dataclasses.Field, name: str, value: Any) -> Any:
        """value in the form the checks and the C structs take."""
        if f.type in ("Profile", "Profile | None"):
            if _is_real(value):
                return Profile.const(float(value))
            if not isinstance(value, Profile):
                raise ParameterError(f"{name} = {value!r} is not a Profile or a number")
            return value
        if "range" in f.metadata and f.metadata["n"]:
            if isinstance(value, (list, tuple)) or (isinstance(value, np.ndarray)
                                                    and value.ndim == 1):
                return tuple(_plain(v) for v in value)
            return value
        return _plain(value)

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):  # type: ignore[arg-type]
            name = f"{self._section}.{f.name}" if self._section else f.name
            value = self._normalise(f, name, getattr(self, f.name))
            if value is not getattr(self, f.name):
                object.__setattr__(self, f.name, value)
            if f.name in self._profile_ranges:
                lo, hi, unit, why = self._profile_ranges[f.name]
                if not all(lo <= y <= hi for y in value.y):
                    raise ParameterError(
                        f"{name} = {_profile_text(value)} is outside its valid range "
                        f"[{_fmt(lo)}, {_fmt(hi)}{']' if math.isfinite(hi) else ')'} {unit}: "
                        f"{why}")
            if f.metadata.get("bool") and not isinstance(value, bool):
                raise ParameterError(f"{name} = {value!r} is not true or false")
            if "range" in f.metadata and value is None and f.default is None:
                continue  # optional: derived
            if "range" in f.metadata:
                lo, hi, lo_open = f.metadata["range"]
                unit = f.metadata["unit"]
                n = f.metadata["n"]
                if n:
                    if not isinstance(value, tuple) or len(value) != n:
                        raise ParameterError(f"{name} = {value!r} must be {n} values (one a phase)")
                    values = value
                else:
                    if isinstance(value, (tuple, list)):
                        raise ParameterError(f"{name} = {value!r} must be a single number")
                    values = (value,)
                for v in values:
                    if isinstance(v, bool) or not isinstance(v, (int, float)):
                        raise ParameterError(f"{name} = {value!r} is not a number")
                    if f.metadata["integer"] and not isinstance(v, int):
                        raise ParameterError(f"{name} = {value!r} must be a whole number")
                    ok = math.isfinite(v) and (v > lo if lo_open else v >= lo) and v <= hi
                    if not ok:
                        br = "(" if lo_open else "["
                        raise ParameterError(
                            f"{name} = {value!r} is outside its valid range "
                            f"{br}{_fmt(lo)}, {_fmt(hi)}] {unit}".rstrip()
                        )
            if "choices" in f.metadata and value not in f.metadata["choices"]:
                raise ParameterError(
                    f"{name} = {value!r} is not one of {', '.join(f.metadata['choices'])}"
                )


#: yang2018 Table I (the motor of MotorPars() with no field given), with the


@dataclass(frozen=True)
class Profile:
    """Piecewise-linear y(t) through points (t_k, y_k); held outside."""

    t: tuple[float, ...] = (0.0,)
    y: tuple[float, ...] = (0.0,)

    def __post_init__(self) -> None:
        for axis in ("t", "y"):
            v = getattr(self, axis)
            if isinstance(v, (str, bytes)) or not isinstance(v, (tuple, list, np.ndarray)):
                raise ParameterError(f"profile: {axis} = {v!r} must be a sequence of numbers")
            if not all(map(_is_real, v)):
                raise ParameterError(f"profile: every point must be a number ({axis} = {v!r})")
            object.__setattr__(self, axis, tuple(float(x) for x in v))
        if len(self.t) != len(self.y) or not self.t:
            raise ParameterError("profile: t and y must be non-empty and of equal length")
        if len(self.t) > 64:
            raise ParameterError(f"profile: {len(self.t)} points, at most 64 are allowed")
        if any(not math.isfinite(v) for v in self.t + self.y):
            raise ParameterError("profile: every point must be finite")
        if any(b < a for a, b in zip(self.t, self.t[1:])):
            raise ParameterError("profile: times must be non-decreasing")

    @staticmethod
    def const(y: float) -> "Profile":
        return Profile((0.0,), (float(y),))

    @staticmethod
    def steps(y0: float, *changes: tuple[float, float], ramp: float = 0.0) -> "Profile":
        """Start at y0; at each (t, y) move to y, in a ramp of `ramp` seconds."""
        t, y = [0.0], [float(y0)]
        for tc, yc in changes:
            t += [tc, tc + ramp]
            y += [y[-1], float(yc)]
        return Profile(tuple(t), tuple(y))

    def scaled(self, k: float) -> "Profile":
        """The profile with every value multiplied by k (e.g. RPM)."""
        return Profile(self.t, tuple(y * k for y in self.y))

    def __call__(self, tq: float) -> float:
        return float(np.interp(tq, self.t, self.y))


