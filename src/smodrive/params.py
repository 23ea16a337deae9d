"""Typed, validated scenario parameters (frozen dataclasses), TOML in and out.

Every numeric field carries its valid range and unit; building a dataclass
with a bad value raises :class:`ParameterError` naming the field, the value
and the range, before anything is simulated.

Example
-------
>>> from smodrive.params import MotorPars
>>> MotorPars(L_s=-1.0)
Traceback (most recent call last):
...
smodrive.params.ParameterError: motor.L_s = -1.0 is outside its valid range [1e-07, 10] H
"""

from __future__ import annotations

import dataclasses
import json
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

RPM = 2.0 * math.pi / 60.0  # rad/s per r/min


class ParameterError(ValueError):
    """A parameter is missing, unknown, or outside its valid range."""


def num(default: Any, lo: float, hi: float, unit: str, doc: str, *, lo_open: bool = False,
        integer: bool = False) -> Any:
    """A numeric dataclass field with range metadata (a tuple default makes
    it a per-phase vector of that length)."""
    n = len(default) if isinstance(default, tuple) else 0
    return field(default=default, metadata={"range": (lo, hi, lo_open), "unit": unit, "doc": doc,
                                             "integer": integer, "n": n})


def flag(default: bool, doc: str) -> Any:
    """A boolean dataclass field."""
    return field(default=default, metadata={"bool": True, "doc": doc})


def choice(default: str, options: tuple[str, ...], doc: str) -> Any:
    return field(default=default, metadata={"choices": options, "doc": doc})


def _fmt(x: float) -> str:
    return f"{x:g}"


class _Validated:
    """Mixin: range-check every field in __post_init__."""

    _section = ""

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):  # type: ignore[arg-type]
            value = getattr(self, f.name)
            name = f"{self._section}.{f.name}" if self._section else f.name
            if f.metadata.get("bool") and not isinstance(value, bool):
                raise ParameterError(f"{name} = {value!r} is not true or false")
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


@dataclass(frozen=True)
class MotorPars(_Validated):
    """True machine (the plant). Defaults: yang2018 Table I, with the
    mechanical values the paper does not give (see docs/assumptions.md)."""

    _section = "motor"
    R_s: float = num(2.25, 1e-6, 1e3, "ohm", "stator resistance", lo_open=True)
    L_s: float = num(23.45e-3, 1e-7, 10.0, "H", "stator inductance")
    psi_r: float = num(0.4, 0.0, 100.0, "Wb", "PM flux linkage")
    n_p: int = num(4, 1, 100, "", "pole pairs", integer=True)
    J: float = num(0.012, 1e-9, 1e4, "kg m^2", "inertia of motor and load (assumed)")
    B: float = num(0.002, 0.0, 1e3, "N m s/rad", "viscous friction (assumed)")
    P_N: float = num(2400.0, 0.0, 1e8, "W", "rated power")
    n_N: float = num(1500.0, 1.0, 1e6, "r/min", "rated speed")

    @property
    def T_N(self) -> float:
        """Rated torque P_N / (rated mechanical speed), N m."""
        return self.P_N / (self.n_N * RPM)

    @property
    def k_t(self) -> float:
        """Torque constant 1.5 n_p psi_r, N m/A."""
        return 1.5 * self.n_p * self.psi_r


@dataclass(frozen=True)
class InverterCfg(_Validated):
    _section = "inverter"
    u_dc: float = num(540.0, 0.0, 1e5, "V", "DC-link voltage", lo_open=True)
    pwm: str = choice("carrier", ("carrier", "averaged"), "carrier comparison or cycle average")
    t_dead: float = num(2e-6, 0.0, 1e-3, "s", "dead time (assumed)")
    svm_limit: str = choice("hexagon", ("hexagon", "circle"), "voltage limit of the modulator")


@dataclass(frozen=True)
class AdcCfg(_Validated):
    _section = "adc"
    gain: tuple[float, float, float] = num((1.0, 1.0, 1.0), 0.5, 2.0, "", "per-phase gain")
    offset: tuple[float, float, float] = num((0.0, 0.0, 0.0), -1e3, 1e3, "A", "per-phase offset")
    noise: float = num(0.02, 0.0, 1e3, "A", "white-noise standard deviation (assumed)")
    bits: int = num(12, 0, 24, "", "resolution (0: none)", integer=True)
    full_scale: float = num(25.0, 1e-6, 1e6, "A", "+- input range (assumed)")
    seed: int = num(1, 0, 2**63 - 1, "", "noise seed", integer=True)


@dataclass(frozen=True)
class ControllerCfg(_Validated):
    """The controller's knowledge: parameter estimates and gains. Defaults:
    yang2018 Table I and Sec. IV-C; speed-loop values assumed."""

    _section = "controller"
    mode: str = choice("robust", ("conventional", "robust", "sensorless"), "control structure")
    L_s_hat: float = num(23.45e-3, 0.0, 10.0, "H", "inductance estimate", lo_open=True)
    R_s_hat: float = num(2.25, 0.0, 1e3, "ohm", "resistance estimate")
    psi_r_hat: float = num(0.4, 0.0, 100.0, "Wb", "PM flux estimate (conventional DBPC)")
    lambda_min: float = num(800.0, 0.0, 1e7, "A/s", "SMDO lambda_min, eq. (37)")
    l: float = num(1200.0, 0.0, 1e7, "1/s", "SMDO proportional gain l, eq. (21)", lo_open=True)
    w_c: float = num(1500.0, 0.0, 1e7, "rad/s", "SMDO filter gain omega_c, eq. (19)", lo_open=True)
    rho: float = num(0.2, 0.0, 1e3, "A", "SMDO smoothing rho, eq. (39)", lo_open=True)
    speed_bw: float = num(60.0, 0.0, 1e4, "rad/s", "speed-loop bandwidth (assumed)", lo_open=True)
    J_hat: float = num(0.012, 1e-9, 1e4, "kg m^2", "inertia used to tune the speed PI")
    psi_r_pi: float = num(0.4, 0.0, 100.0, "Wb", "flux used to tune the speed PI", lo_open=True)
    i_max: float = num(15.0, 0.0, 1e5, "A", "q-axis current limit (assumed)", lo_open=True)
    speed_decimation: int = num(1, 1, 1000, "", "speed loop runs every N samples", integer=True)
    w_lpf: float = num(100.0, 0.0, 1e6, "rad/s", "sensorless speed LPF bandwidth (assumed)",
                       lo_open=True)
    w_hys: float = num(5.0, 0.0, 1e5, "rad/s", "direction hysteresis (electrical)")
    t_handover: float = num(0.0, 0.0, 1e3, "s", "sensorless: time run on the encoder first")
    t_dead_comp: float = num(2e-6, 0.0, 1e-3, "s", "dead time compensated by the modulator")
    i_dtc: float = num(0.3, 0.0, 1e5, "A", "linear zone of the compensation", lo_open=True)
    n_max: float = num(3000.0, 0.0, 1e6, "r/min", "sensorless speed-estimate limit", lo_open=True)
    speed_loop: bool = flag(True, "i_q reference from the speed PI (else from i_q_ref)")
    smdo_euler: bool = flag(False, "eq. (36) as printed (forward-Euler rotation)")

    def pi_gains(self, n_p: int) -> tuple[float, float]:
        """Speed PI gains in A per electrical rad/s: the loop
        b / s with b = 1.5 n_p^2 psi / J closed by k_p + k_i / s has the
        characteristic polynomial s^2 + b k_p s + b k_i; both roots at -speed_bw."""
        b = 1.5 * n_p**2 * self.psi_r_pi / self.J_hat
        if not (math.isfinite(b) and b > 0.0):
            raise ParameterError(
                f"controller.psi_r_pi = {self.psi_r_pi!r} with J_hat = {self.J_hat!r}: the "
                "speed-loop gain 1.5 n_p^2 psi / J is not a positive finite number")
        return 2.0 * self.speed_bw / b, self.speed_bw**2 / b


@dataclass(frozen=True)
class Profile:
    """Piecewise-linear y(t) through points (t_k, y_k); held outside."""

    t: tuple[float, ...] = (0.0,)
    y: tuple[float, ...] = (0.0,)

    def __post_init__(self) -> None:
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

    def __call__(self, tq: float) -> float:
        import numpy as np

        return float(np.interp(tq, self.t, self.y))


@dataclass(frozen=True)
class LoadCfg(_Validated):
    _section = "load"
    T_brake: Profile = field(default_factory=lambda: Profile.const(0.0))
    T_ext: Profile = field(default_factory=lambda: Profile.const(0.0))
    w_brake_eps: float = num(1.0, 1e-9, 1e3, "rad/s", "brake taper speed (assumed)")
    k_fan: float = num(0.0, 0.0, 1e3, "N m s^2/rad^2", "fan load coefficient")


@dataclass(frozen=True)
class Scenario(_Validated):
    """One runnable experiment."""

    _section = "scenario"
    name: str = "scenario"
    T_sp: float = num(100e-6, 1e-7, 1.0, "s", "sampling (= carrier) period")
    duration: float = num(1.0, 0.0, 1e4, "s", "simulated time", lo_open=True)
    n_M0: float = num(0.0, -9.5e5, 9.5e5, "r/min", "initial speed")
    theta_r0: float = num(0.0, -1e3, 1e3, "rad", "initial electrical angle")
    w_M_ref: Profile = field(default_factory=lambda: Profile.const(0.0))  # rad/s
    i_d_ref: Profile = field(default_factory=lambda: Profile.const(0.0))
    i_q_ref: Profile = field(default_factory=lambda: Profile.const(0.0))
    i_d_sin_amp: float = num(0.0, 0.0, 1e4, "A", "sinusoid added to the i_d reference")
    i_d_sin_freq: float = num(0.0, 0.0, 1e7, "Hz", "its frequency")
    log_stride: int = num(1, 1, 10**6, "", "log every N samples", integer=True)
    warm_start: bool = flag(True, "start in steady state: current and speed PI carry the load")
    motor: MotorPars = field(default_factory=MotorPars)
    controller: ControllerCfg = field(default_factory=ControllerCfg)
    inverter: InverterCfg = field(default_factory=InverterCfg)
    adc: AdcCfg = field(default_factory=AdcCfg)
    load: LoadCfg = field(default_factory=LoadCfg)

    def __post_init__(self) -> None:
        super().__post_init__()
        # plant limits that depend on more than one field
        if self.inverter.t_dead > 0.25 * self.T_sp:
            raise ParameterError(
                f"inverter.t_dead = {self.inverter.t_dead!r} is outside its valid range "
                f"[0, T_sp/4 = {0.25 * self.T_sp:g}] s")

    def check_controller(self) -> None:
        """Controller limits that depend on more than one field (the ones the
        C core's init checks too); run by load_scenario and before every
        simulation, not for plant-only use."""
        T, c = self.T_sp, self.controller
        nyq = math.pi / T
        if c.t_handover / T > 2**31 - 1:
            raise ParameterError(
                f"controller.t_handover = {c.t_handover!r} is too long: at most "
                f"{(2**31 - 1) * T:g} s at T_sp = {T:g} s")
        k_p, k_i = c.pi_gains(self.motor.n_p)
        if not (k_p <= 1e6 and k_i <= 1e9):
            raise ParameterError(
                f"controller.speed_bw = {c.speed_bw!r} with J_hat = {c.J_hat!r} gives speed-PI "
                f"gains k_p = {k_p:g}, k_i = {k_i:g}, beyond the core's limits 1e6 and 1e9")
        if c.t_dead_comp > 0.25 * T:
            raise ParameterError(
                f"controller.t_dead_comp = {c.t_dead_comp!r} is outside its valid range "
                f"[0, T_sp/4 = {0.25 * T:g}] s")
        if c.mode == "sensorless":
            if c.w_lpf >= nyq:
                raise ParameterError(
                    f"controller.w_lpf = {c.w_lpf!r} is outside its valid range "
                    f"(0, pi/T_sp = {nyq:g}) rad/s")
            w_max = c.n_max * RPM * self.motor.n_p
            if not (c.w_hys < w_max <= nyq):
                raise ParameterError(
                    f"controller.n_max = {c.n_max!r} is outside its valid range: the "
                    f"electrical speed limit n_max n_p must lie in (w_hys = {c.w_hys:g}, "
                    f"pi/T_sp = {nyq:g}] rad/s")
            a, b = 1.0 - c.w_c * T, w_max * T
            if a * a + b * b >= 1.0:
                raise ParameterError(
                    f"controller.w_c = {c.w_c!r} with n_max = {c.n_max!r}: the filter (36) "
                    "would be unstable, |1 - w_c T_sp + j w_max T_sp| must be below 1")
        if c.mode != "conventional" and (c.l + c.lambda_min / c.rho) * T >= 2.0:
            raise ParameterError(
                f"controller.l = {c.l!r}, lambda_min = {c.lambda_min!r}, rho = {c.rho!r}: "
                "(l + lambda_min/rho) T_sp must be below 2 for a stable SMDO")
        if c.mode != "conventional" and c.w_c * T >= 1.0:
            raise ParameterError(
                f"controller.w_c = {c.w_c!r} is outside its valid range (0, 1/T_sp = {1 / T:g})"
                " rad/s")

    @property
    def n_steps(self) -> int:
        return int(round(self.duration / self.T_sp))

    def replace(self, **changes: Any) -> "Scenario":
        return dataclasses.replace(self, **changes)


# ---------------------------------------------------------------- TOML -----

_SECTIONS = {
    "motor": MotorPars,
    "controller": ControllerCfg,
    "inverter": InverterCfg,
    "adc": AdcCfg,
    "load": LoadCfg,
}


def _scenario_classes() -> dict[str, type]:
    """Scenario kinds by the TOML key `kind` (default "pmsm")."""
    from .lcl import LclScenario  # late: lcl imports this module

    return {"pmsm": Scenario, "lcl": LclScenario}


def _sections_of(cls: type) -> dict[str, type]:
    """Fields of cls that are parameter sections (nested dataclasses)."""
    obj = cls()
    out = {}
    for f in dataclasses.fields(cls):
        v = getattr(obj, f.name)
        if dataclasses.is_dataclass(v) and not isinstance(v, Profile):
            out[f.name] = type(v)
    return out


def _is_profile(cls: type, name: str) -> bool:
    return isinstance(getattr(cls(), name, None), Profile)


def _profile_from(name: str, v: Any, scale: float = 1.0) -> Profile:
    form = f"{name}: expected a number or a table {{t = [...], y = [...]}} of numbers"
    is_num = lambda x: isinstance(x, (int, float)) and not isinstance(x, bool)  # noqa: E731
    if is_num(v):
        return Profile.const(float(v) * scale)
    if not (isinstance(v, dict) and set(v) == {"t", "y"}):
        raise ParameterError(form)
    t, y = v["t"], v["y"]
    if not (isinstance(t, list) and isinstance(y, list) and all(map(is_num, t + y))):
        raise ParameterError(form)
    try:
        return Profile(tuple(map(float, t)), tuple(float(x) * scale for x in y))
    except ParameterError as exc:
        raise ParameterError(f"{name}: {exc}") from None


def _build(cls: type, section: str, data: dict[str, Any]) -> Any:
    names = {f.name: f for f in dataclasses.fields(cls)}
    kwargs: dict[str, Any] = {}
    for key, value in data.items():
        if key == "w_M_ref_rpm" and "w_M_ref" in names:
            kwargs["w_M_ref"] = _profile_from(f"{section}.{key}", value, RPM)
            continue
        if key not in names:
            raise ParameterError(
                f"{section}.{key}: unknown parameter (known: {', '.join(sorted(names))})"
            )
        if _is_profile(cls, key):
            kwargs[key] = _profile_from(f"{section}.{key}", value)
        elif isinstance(value, list):
            kwargs[key] = tuple(value)
        else:
            kwargs[key] = value
    return cls(**kwargs)


def scenario_from_dict(data: dict[str, Any]) -> Any:
    """A Scenario (or, with kind = "lcl", an LclScenario) from parsed TOML."""
    data = dict(data)
    kinds = _scenario_classes()
    kind = data.pop("kind", "pmsm")
    if kind not in kinds:
        raise ParameterError(f"kind = {kind!r} is not one of {', '.join(kinds)}")
    cls = kinds[kind]
    sections = _sections_of(cls)
    top: dict[str, Any] = {}
    for key, value in data.items():
        if key in sections:
            if not isinstance(value, dict):
                raise ParameterError(f"[{key}] must be a table")
            top[key] = _build(sections[key], key, value)
        else:
            top[key] = value
    return _build(cls, "scenario", top)


def load_scenario(path: str | Path) -> Scenario:
    """Read a scenario from a TOML file (see scenarios/*.toml)."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(f"{path}: not valid TOML: {exc}") from exc
    s = scenario_from_dict(data)
    if isinstance(s, Scenario):
        s.check_controller()
    return s


def scenario_to_toml(s: Scenario) -> str:
    """Serialise a scenario to TOML (round-trips through load_scenario)."""

    def val(v: Any) -> str:
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            # a JSON string is a TOML basic string, but for DEL, which TOML escapes
            return json.dumps(v, ensure_ascii=False).replace("\x7f", "\\u007f")
        if isinstance(v, tuple):
            return "[" + ", ".join(val(x) for x in v) + "]"
        if isinstance(v, Profile):
            return "{ t = " + val(v.t) + ", y = " + val(v.y) + " }"
        return repr(v)

    sections = _sections_of(type(s))
    lines = [] if isinstance(s, Scenario) else ['kind = "lcl"']
    for f in dataclasses.fields(s):
        v = getattr(s, f.name)
        if f.name not in sections:
            lines.append(f"{f.name} = {val(v)}")
    for sec in sections:
        lines.append(f"\n[{sec}]")
        obj = getattr(s, sec)
        for f in dataclasses.fields(obj):
            lines.append(f"{f.name} = {val(getattr(obj, f.name))}")
    return "\n".join(lines) + "\n"
