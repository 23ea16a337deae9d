"""Scenarios as TOML: read (with catalogue bases and the older schemas) and
write.

A TOML file sets the top-level scenario fields and the sections
``[motor]``, ``[lcl]`` (the filter; absent: none), ``[inverter]``,
``[adc]``, ``[load]`` and ``[controller]``. Every field left out keeps its
default, or the value of the catalogue scenario named by ``base`` (for
example ``base = "yao2022.base"`` for the LCL-filtered high-speed drive).
Keys are SI unless their name says otherwise: every mechanical speed
``w_M...`` may be given in r/min as ``w_M..._rpm`` (``w_M0_rpm``, ``w_M_ref_rpm``,
``w_M_max_rpm``), an acceleration ``a_M...`` in r/min/s as ``a_M..._rpm_s``. The r/min
names of earlier versions (``n_M0``, ``n_max``, ...) are read with a warning.
``[controller] mode = "conventional" | "robust" |
"sensorless"`` is shorthand for yang2018's three compositions of parts.

A file of the older LCL schema (``kind = "lcl"``, a ``[plant]`` section)
still loads: it is read as ``base = "yao2022.base"`` with its keys moved to
where they live now, and a warning says what to write instead.

:func:`apply` applies such a table of changes (without ``base``) to a given
scenario, with the same keys, units and messages: :func:`scenario_from_dict`
applies a file's to its base, a sweep (:mod:`smodrive.sweep`) its ``[set]``
and each run's axis values to its base scenario.

Example
-------
>>> s = scenario_from_dict({"w_M0_rpm": 1000.0, "controller": {"mode": "sensorless"}})
>>> (s.controller.current, s.controller.position, s.controller.start)
('robust_dbpc', 'smdo_emf', 'handover')
"""

from __future__ import annotations

import dataclasses
import numbers
import re
import warnings
from pathlib import Path
from typing import Any

import tomli_w

from ._util import fmt_g, is_num, tomllib
from .model import (
    RPM,
    AdcCfg,
    ControllerCfg,
    InverterCfg,
    LclFilterPars,
    LoadCfg,
    MotorPars,
    ParameterError,
    Profile,
    Scenario,
    datasheet,
    derive,
    yang2018_mode,
)
from .scenarios import catalogue

SECTIONS: dict[str, type] = {
    "motor": MotorPars,
    "lcl": LclFilterPars,
    "controller": ControllerCfg,
    "inverter": InverterCfg,
    "adc": AdcCfg,
    "load": LoadCfg,
}


def _profile_from(name: str, v: Any, scale: float = 1.0) -> Profile:
    form = f"{name}: expected a number or a table {{t = [...], y = [...]}} of numbers"
    if is_num(v):
        try:
            return Profile.const(float(v) * scale)
        except ParameterError as exc:  # (a NaN or an infinity, named by its key)
            raise ParameterError(f"{name} = {v!r}: {exc}") from None
    if not (isinstance(v, dict) and set(v) == {"t", "y"}):
        raise ParameterError(form)
    t, y = v["t"], v["y"]
    if not (isinstance(t, list) and isinstance(y, list) and all(map(is_num, t + y))):
        raise ParameterError(form)
    try:
        return Profile(tuple(map(float, t)), tuple(float(x) * scale for x in y))
    except ParameterError as exc:
        raise ParameterError(f"{name}: {exc}") from None


def _profile_fields(cls: type) -> set[str]:
    obj = cls()
    return {f.name for f in dataclasses.fields(cls) if isinstance(getattr(obj, f.name), Profile)}


# the names fields had before speeds were SI in the Python API (r/min then)
_RENAMED = {"n_M0": "w_M0_rpm", "n_max": "w_M_max_rpm", "n_bp_min": "w_M_bp_min_rpm",
            "n_handover": "w_M_handover_rpm", "a_start_rpm_s": "a_M_start_rpm_s",
            "n_N": "w_M_N_rpm"}


def _unit_forms(cls: type) -> dict[str, tuple[str, float]]:
    """TOML keys in r/min (and r/min/s) for the mechanical speeds (and
    accelerations) of cls: key -> (field, factor to SI)."""
    out = {}
    for f in dataclasses.fields(cls):
        if f.name.startswith("w_M"):
            out[f.name + "_rpm"] = (f.name, RPM)
        elif f.name.startswith("a_M"):
            out[f.name + "_rpm_s"] = (f.name, RPM)
    return out


def _in_range_as_written(cls: type, section: str, key: str, name: str, value: Any,
                         k: float) -> None:
    """A speed given in r/min (an acceleration in r/min/s) outside its field's
    range is refused as the file wrote it: its key, its value, the range in
    its unit (not the SI field's: w_M_N_rpm = -150 read "motor.w_M_N =
    -15.7... rad/s")."""
    f = next(f for f in dataclasses.fields(cls) if f.name == name)
    if "range" not in f.metadata:
        return
    lo, hi, lo_open = f.metadata["range"]
    v = float(value) * k
    if not (v == v and abs(v) != float("inf") and (v > lo if lo_open else v >= lo) and v <= hi):
        unit = "r/min/s" if key.endswith("_rpm_s") else "r/min"
        raise ParameterError(f"{section}.{key} = {value!r} is outside its valid range "
                             f"{'(' if lo_open else '['}{fmt_g(lo / k)}, {fmt_g(hi / k)}] {unit}")


def _kwargs(cls: type, section: str, data: dict[str, Any]) -> dict[str, Any]:
    names = {f.name for f in dataclasses.fields(cls)
             if not f.metadata.get("internal")} - set(SECTIONS)
    profiles = _profile_fields(cls)
    units = _unit_forms(cls)
    kwargs: dict[str, Any] = {}
    given: dict[str, str] = {}  # field -> the key that set it

    def once(name: str, key: str) -> None:
        """One quantity, one key: w_M_ref and w_M_ref_rpm together are refused."""
        if name in given:
            raise ParameterError(
                f"{section}.{given[name]} and {section}.{key} both set {section}.{name}: "
                "give one of them")
        given[name] = key

    for key, value in data.items():
        as_written = key
        if key in _RENAMED and _RENAMED[key] in units:
            warnings.warn(f"{section}.{key} is now {_RENAMED[key]} (SI field "
                          f"{units[_RENAMED[key]][0]}); read as such", UserWarning, stacklevel=5)
            key = _RENAMED[key]
        if key in units:
            name, k = units[key]
            once(name, as_written)
            if name in profiles:
                kwargs[name] = _profile_from(f"{section}.{key}", value, k)
            elif is_num(value):
                kwargs[name] = float(value) * k
                _in_range_as_written(cls, section, key, name, value, k)
            else:
                raise ParameterError(f"{section}.{key} = {value!r} is not a number")
        elif key not in names:
            known = sorted(names | set(units) | ({"base"} if cls is Scenario else set()))
            if cls is Scenario and isinstance(value, dict):
                # a table the file made up ([sim], [simulation]): say which
                # tables there are, and where its keys go when they are the
                # scenario's own
                own = sorted(k for k in value if k in known)
                where = (f"; {', '.join(own)} {'goes' if len(own) == 1 else 'go'} at the top "
                         "of the file, before any table" if own else "")
                raise ParameterError(
                    f"[{key}]: unknown table (tables: {', '.join(sorted(SECTIONS))}){where}")
            raise ParameterError(
                f"{section}.{key}: unknown parameter (known: {', '.join(known)})"
                + (datasheet.hint(key, section) if section in ("motor", "inverter") else ""))
        else:
            once(key, key)
            if key in profiles:
                kwargs[key] = _profile_from(f"{section}.{key}", value)
            elif isinstance(value, list):
                kwargs[key] = tuple(value)
            else:
                kwargs[key] = value
    return kwargs


def _controller(data: dict[str, Any], base: ControllerCfg) -> ControllerCfg:
    data = dict(data)
    if "mode" in data:
        parts = yang2018_mode(data.pop("mode"))
        clash = sorted(set(parts) & set(data))
        if clash:
            raise ParameterError(
                f"controller.mode sets {', '.join(parts)}; do not set {', '.join(clash)} too")
        data.update(parts)
    kw = _kwargs(ControllerCfg, "controller", data)
    # a value the file sets is the user's, even where it equals what the
    # base derived (an explicit 0: off)
    derived = tuple(t for t in base.derived if t[0] not in kw)
    return dataclasses.replace(base, **kw, derived=derived)


def _base(name: Any) -> Scenario:
    if not isinstance(name, str):
        raise ParameterError(f"base = {name!r} must be a catalogue name (smodrive scenarios)")
    cat = catalogue()
    if name not in cat:
        # (a file's name was answered with the catalogue's 24 names only)
        hint = (": base names a catalogue scenario, not a file; copy that file's tables into "
                "this one" if name.lower().endswith(".toml") else "")
        raise ParameterError(f"base = {name!r} is not in the catalogue{hint} (known: "
                             f"{', '.join(sorted(cat))})")
    return cat[name]()


# keys of the LCL schema before the one drive, and where they live now
_LEGACY_PLANT = {
    "R": ("motor", "R_s"), "Ls": ("motor", "L_s"), "psi_m": ("motor", "psi_r"),
    "n_p": ("motor", "n_p"), "J": ("motor", "J"), "B": ("motor", "B"),
    "L1": ("lcl", "L1"), "L2o": ("lcl", "L2o"), "C1": ("lcl", "C1"),
    "u_dc": ("inverter", "u_dc"), "pwm": ("inverter", "pwm"), "t_dead": ("inverter", "t_dead"),
    "k_fan": ("load", "k_fan"),
}
_LEGACY_ADC = {"gain_i2": "gain", "offset_i2": "offset"}
# the old LCL controller used the plant's own values for its model and speed PI
_LEGACY_ESTIMATES = {"R": ("R_s_hat",), "Ls": ("L_s_hat",), "psi_m": ("psi_r_hat", "psi_r_pi"),
                     "J": ("J_hat",)}


def _legacy_origins(data: dict[str, Any]) -> dict[str, str]:
    """For a `kind = "lcl"` file: each field its [plant] keys set -> the key
    as the user wrote it (a message names what the user wrote)."""
    if data.get("kind") != "lcl" or not isinstance(data.get("plant"), dict):
        return {}
    ctrl = data.get("controller")
    ctrl_given = set(ctrl) if isinstance(ctrl, dict) else set()
    out = {}
    for key in data["plant"]:
        if key in _LEGACY_PLANT:
            sec, new = _LEGACY_PLANT[key]
            out[f"{sec}.{new}"] = f"plant.{key}"
            for est in _LEGACY_ESTIMATES.get(key, ()):
                if est not in ctrl_given:
                    out[f"controller.{est}"] = f"plant.{key}"
    return out


def _as_written(exc: ParameterError, origins: dict[str, str]) -> ParameterError:
    """exc with the fields an older file's keys were moved to named by those keys."""
    if not origins:
        return exc
    pattern = "|".join(re.escape(k) for k in sorted(origins, key=len, reverse=True))
    return ParameterError(re.sub(rf"(?<![\w.])({pattern})(?![\w])",
                                 lambda m: origins[m.group(1)], str(exc)))


def _from_legacy_lcl(data: dict[str, Any]) -> dict[str, Any]:
    """Translate a `kind = "lcl"` file to the one schema."""
    data = {k: (dict(v) if isinstance(v, dict) else v) for k, v in data.items()}
    out: dict[str, Any] = {"base": "yao2022.base"}
    moved: list[str] = []
    for sec in ("motor", "lcl", "inverter", "load", "adc", "controller"):
        out[sec] = {}
    ctrl_given = set(data.get("controller", {}))
    for key, value in data.pop("plant", {}).items():
        if key not in _LEGACY_PLANT:
            raise ParameterError(f"plant.{key}: unknown parameter of the LCL plant")
        sec, new = _LEGACY_PLANT[key]
        out[sec][new] = value
        moved.append(f"[plant] {key} -> [{sec}] {new}")
        for est in _LEGACY_ESTIMATES.get(key, ()):
            if est not in ctrl_given:
                out["controller"][est] = value
                moved.append(f"[controller] {est} = {value!r} (the old drive used the plant's)")
    # the old ADC defaults were exact gains (yao2022.base has +-1 %)
    out["adc"].update({"gain": [1.0, 1.0, 1.0], "gain_i1": [1.0, 1.0, 1.0]})
    for key, value in data.pop("adc", {}).items():
        out["adc"][_LEGACY_ADC.get(key, key)] = value
        if key in _LEGACY_ADC:
            moved.append(f"[adc] {key} -> {_LEGACY_ADC[key]}")
    ctrl = data.pop("controller", {})
    mode = ctrl.pop("mode", "sensorless")
    observer = ctrl.pop("observer", "smo")
    if mode not in ("sensorless", "sensored") or observer not in ("smo", "linear"):
        raise ParameterError(f"controller.mode = {mode!r} / observer = {observer!r}: expected "
                             "sensorless or sensored, smo or linear")
    out["controller"]["position"] = ("encoder" if mode == "sensored" else
                                     "lcl_linear" if observer == "linear" else "lcl_smo_pll")
    moved.append(f"[controller] mode/observer -> position = {out['controller']['position']!r}")
    out["controller"].update(ctrl)
    if data.pop("start_open_loop", False):
        out["controller"]["start"] = "if"
        moved.append("start_open_loop -> [controller] start = 'if'")
    if "T_ext" in data:
        out["load"]["T_ext"] = data.pop("T_ext")
        moved.append("T_ext -> [load] T_ext")
    if data.pop("with_linear_observer", False):
        moved.append("with_linear_observer dropped (choose position = 'lcl_linear')")
    out.update(data)
    warnings.warn(
        "kind = 'lcl' is the schema before the one drive; read as base = 'yao2022.base' "
        "with: " + "; ".join(moved) + ". `smodrive show` prints a scenario in the current "
        "schema.", UserWarning, stacklevel=3)
    return {k: v for k, v in out.items() if v != {}}


def apply(base: Scenario | None, data: dict[str, Any], *, rederive: bool = True) -> Scenario:
    """`base` with the changes `data`, a parsed scenario TOML without
    ``base`` and ``kind``: the sections (``[motor]``, ``[controller]``, ...)
    as tables, the top-level fields as keys, with the units of a scenario
    file (``w_M0_rpm``, ``a_M_start_rpm_s``, a profile as ``{t, y}``, the
    ``mode`` shorthand); a wrong key or value is named with its section and
    valid range. A value `data` sets is the user's, even where it equals the
    one the base derived from its motor.

    `base` None: the defaults of :class:`Scenario`, and a ``[motor]`` is a
    whole machine (every data-sheet field from `data`, never Table I's).
    `rederive`: when ``[motor]`` makes another machine than the base's, all
    of the base's motor-specific controller values (a preset's estimates,
    gains and limits) are derived anew from it unless ``[controller]`` sets
    them, as in a scenario file; with False only those the base derived
    from its motor (``controller.derived``) follow the new one and the
    values the base sets stay (a sweep's changes; the older LCL schema,
    which kept the preset's).

    >>> s = apply(scenario_from_dict({"w_M0_rpm": 1000.0}), {"controller": {"L_s_hat": 0.02}})
    >>> (round(s.w_M0 / RPM), s.controller.L_s_hat)
    (1000, 0.02)
    """
    if "base" in data:
        raise ParameterError("base: the base scenario is given apart from the changes (the "
                             "top-level base of a scenario file, sweep.base of a sweep)")
    top: dict[str, Any] = {}
    sections: dict[str, Any] = {}
    for key, value in data.items():
        if key in SECTIONS:
            if not isinstance(value, dict):
                raise ParameterError(f"[{key}] must be a table")
            sections[key] = value
        else:
            top[key] = value
    scenario = Scenario() if base is None else base
    built: dict[str, Any] = {}
    for key, value in sections.items():
        if key == "controller":
            continue
        if key == "motor" and base is None:
            # a machine of the user's: every field from the file (MotorPars
            # refuses one left out, derives B), never the Table I defaults
            built[key] = MotorPars(**_kwargs(MotorPars, key, value))
            continue
        current = getattr(scenario, key)
        if current is None:  # the filter section of a base without one
            current = SECTIONS[key]()
        kw = _kwargs(SECTIONS[key], key, value)
        if getattr(current, "derived", ()):
            # a value the file sets is the user's, even where it equals
            # what the base derived
            kw["derived"] = tuple(t for t in current.derived if t[0] not in kw)
        built[key] = dataclasses.replace(current, **kw)
    if base is None and "motor" in built and built["motor"] != MotorPars() and \
            "u_dc" not in sections.get("inverter", {}):
        # (a 12 V gimbal motor's file without it ran on Table I's 540 V: identify ended in
        # an overcurrent naming neither, design said nothing)
        warnings.warn(f"inverter.u_dc is not given: yang2018 Table I's {InverterCfg().u_dc:g} V "
                      "is assumed for this motor; give its inverter's DC link (V)", UserWarning,
                      stacklevel=3)
    base_ctrl = scenario.controller
    if rederive and "motor" in built and built["motor"] != scenario.motor:
        # another machine than the base's: the base's motor-specific
        # controller values are derived anew from it, unless [controller]
        # sets them
        base_ctrl = derive.unset(base_ctrl)
    if "controller" in sections or base_ctrl is not scenario.controller:
        built["controller"] = _controller(sections.get("controller", {}), base_ctrl)
    return dataclasses.replace(scenario, **_kwargs(Scenario, "scenario", top), **built)


def scenario_from_dict(data: dict[str, Any]) -> Scenario:
    """A Scenario from parsed TOML (see the module docstring): its ``base``
    (or the defaults) with the rest of `data` applied (:func:`apply`)."""
    try:
        changes = dict(data)
        kind = changes.pop("kind", None)
        if kind == "lcl":
            changes = _from_legacy_lcl(changes)
        elif kind not in (None, "pmsm"):
            raise ParameterError(f"kind = {kind!r} is not one of pmsm, lcl (and no longer "
                                 "needed)")
        base = _base(changes.pop("base")) if "base" in changes else None
        # a file of the older LCL schema keeps the preset's controller, as that drive did
        return apply(base, changes, rederive=kind != "lcl")
    except ParameterError as exc:
        raise _as_written(exc, _legacy_origins(data)) from None


def load_scenario(path: str | Path) -> Scenario:
    """Read a scenario from a TOML file (see scenarios/*.toml) and check its
    controller."""
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ParameterError(f"{path}: cannot read the file ({exc.strerror or exc})") from None
    try:
        text = raw.decode("utf-8-sig")  # TOML is UTF-8 (a byte-order mark is skipped)
    except UnicodeDecodeError as exc:
        raise ParameterError(
            f"{path}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}); a "
            "TOML file is UTF-8: save it in that encoding") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(f"{path}: not valid TOML: {exc}") from None
    s = scenario_from_dict(data)
    try:
        s.check_controller()
    except ParameterError as exc:
        raise _as_written(exc, _legacy_origins(data)) from None
    return s


def resolve_scenario(scenario: str) -> Scenario:
    """A TOML file, or a name of the catalogue (`smodrive scenarios`)."""
    path = Path(scenario)
    if path.is_file():
        return load_scenario(path)
    if scenario in catalogue():
        return catalogue()[scenario]()
    raise ParameterError(f"{scenario}: neither a scenario file nor a catalogue name "
                         "(see `smodrive scenarios`)")


def _toml_value(v: Any) -> Any:
    """A field value as tomli-w writes it: a profile as a table {t, y}, tuples
    as arrays, NumPy scalars as Python numbers (floats keep their repr, so a
    value round-trips exactly)."""
    if isinstance(v, Profile):
        return {"t": _toml_value(v.t), "y": _toml_value(v.y)}
    if isinstance(v, (tuple, list)):
        return [_toml_value(x) for x in v]
    if isinstance(v, (bool, str)):
        return v
    if isinstance(v, numbers.Integral):
        return int(v)
    if isinstance(v, numbers.Real):
        return float(v)
    return v


def scenario_dict(s: Scenario) -> dict[str, Any]:
    """A scenario as the nested dict its TOML holds (the inverse of
    :func:`scenario_from_dict`; optional fields left at None, "derived", are
    omitted, as is an absent [lcl] section)."""
    out: dict[str, Any] = {}
    for f in dataclasses.fields(s):
        v = getattr(s, f.name)
        if f.name in SECTIONS:
            if v is not None:
                # controller values derived from the motor are left out: the
                # file derives them again from its [motor] (smodrive design)
                derived = {n for n, _, _ in getattr(v, "derived", ())}
                out[f.name] = {g.name: _toml_value(getattr(v, g.name))
                               for g in dataclasses.fields(v)
                               if getattr(v, g.name) is not None and g.name not in derived
                               and not g.metadata.get("internal")}
        elif v is not None and not f.metadata.get("internal"):
            out[f.name] = _toml_value(v)
    return out


def scenario_to_toml(s: Scenario) -> str:
    """Serialise a scenario to TOML with tomli-w (round-trips through
    load_scenario; optional fields left at None, "derived", are omitted).

    >>> from smodrive.model import Scenario
    >>> text = scenario_to_toml(Scenario(duration=0.5))
    >>> scenario_from_dict(tomllib.loads(text)) == Scenario(duration=0.5)
    True
    """
    return tomli_w.dumps(scenario_dict(s))
