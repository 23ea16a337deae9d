"""Typed, validated scenario parameters (frozen dataclasses), TOML in and out.

Every numeric field carries its valid range and unit; building a dataclass
with a bad value raises :class:`ParameterError` naming the field, the value
and the range, before anything is simulated.

One :class:`Scenario` describes every drive smodrive simulates: the plant
sections (``motor``, the optional ``lcl`` filter, ``inverter``, ``adc``,
``load``) and the composed controller (``controller.current``,
``controller.position``, ``controller.start``). Speeds are SI (rad/s) in
Python (``w_M...`` mechanical rad/s); a TOML key whose unit is not SI says so
in its name (``w_M0_rpm``, ``w_M_ref_rpm``, ``a_M_start_rpm_s``).

Example
-------
>>> from smodrive.params import MotorPars
>>> MotorPars(L_s=-1.0)
Traceback (most recent call last):
...
smodrive.params.ParameterError: motor.L_s = -1.0 is outside its valid range [1e-08, 10] H
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

RPM = 2.0 * math.pi / 60.0  # rad/s per r/min
#: The LCL observers' lookup tables cover this mechanical speed either way,
#: r/min (smodrive.simulate.TABLE_RPM): a run of those observers stays inside.
LCL_TABLE_RPM = 110e3


class ParameterError(ValueError):
    """A parameter is missing, unknown, or outside its valid range."""


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


def _fmt(x: float) -> str:
    return f"{x:g}"


def _is_real(v: Any) -> bool:
    """A real number (Python or NumPy), not a bool."""
    return isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))


def _plain(v: Any) -> Any:
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
#: mechanical values the paper does not give (J, B: docs/assumptions.md)
TABLE1_MOTOR: dict[str, float] = {
    "R_s": 2.25, "L_s": 23.45e-3, "psi_r": 0.4, "n_p": 4, "J": 0.012, "B": 0.002,
    "P_N": 2400.0, "w_M_N": 1500.0 * RPM}
#: the fields of a motor's data sheet that MotorPars never fills in for another machine
MOTOR_REQUIRED = ("R_s", "L_s", "psi_r", "n_p", "J", "P_N", "w_M_N")
#: B left out: viscous friction taking this fraction of the rated torque at rated speed
B_REL = 0.01


@dataclass(frozen=True)
class MotorPars(_Validated):
    """True machine (the plant). ``MotorPars()`` with no field given is
    yang2018 Table I, with the mechanical values the paper does not give (see
    docs/assumptions.md). Any other machine gives every field of its data
    sheet (``R_s``, ``L_s``, ``psi_r``, ``n_p``, ``J``, ``P_N``, ``w_M_N``):
    a field left out is refused, never filled in from Table I, except ``B``
    (viscous friction, rarely on a data sheet), which is then derived as
    ``B_REL T_N / w_M_N`` (1 % of the rated torque at rated speed) and
    recorded in ``derived`` (docs/design_from_motor.md)."""

    _section = "motor"
    R_s: float = num(None, 1e-6, 1e3, "ohm", "stator resistance", lo_open=True)
    L_s: float = num(None, 1e-8, 10.0, "H", "stator inductance")
    psi_r: float = num(None, 0.0, 100.0, "Wb", "PM flux linkage")
    n_p: int = num(None, 1, 100, "", "pole pairs", integer=True)
    J: float = num(None, 1e-9, 1e4, "kg m^2",
                   "inertia of motor and load (Table I: 0.012, assumed; any other motor: "
                   "required)")
    B: float = num(None, 0.0, 1e3, "N m s/rad",
                   "viscous friction (Table I: 0.002, assumed; left out: 0.01 T_N / w_M_N)")
    P_N: float = num(None, 0.0, 1e8, "W", "rated power")
    w_M_N: float = num(None, 0.1, 1e5, "rad/s", "rated speed (mechanical)")
    # record of the values derived by a rule (not a parameter): (name, value, rule)
    derived: tuple = field(default=(), compare=False, repr=False, metadata={"internal": True})

    def __post_init__(self) -> None:
        super().__post_init__()  # the ranges of the fields given (None: not given)
        rating = ("R_s", "L_s", "psi_r", "n_p", "P_N", "w_M_N")
        given = {n for n in TABLE1_MOTOR if getattr(self, n) is not None}
        table1 = not (given & set(rating)) or all(
            getattr(self, n) is not None and _plain(getattr(self, n)) == TABLE1_MOTOR[n]
            for n in rating)
        if table1:
            for n, v in TABLE1_MOTOR.items():
                if getattr(self, n) is None:
                    object.__setattr__(self, n, v)
        else:
            missing = [n for n in MOTOR_REQUIRED if getattr(self, n) is None]
            if missing:
                names = ", ".join(f"motor.{n}" for n in missing)
                what = {"J": "J (inertia of rotor and load, kg m^2: the data sheet's rotor "
                             "inertia plus the load's)"}
                detail = "; ".join(what.get(n, n) for n in missing if n in what)
                raise ParameterError(
                    f"{names} {'is' if len(missing) == 1 else 'are'} not given: a motor other "
                    "than yang2018 Table I gives every data-sheet field (R_s, L_s, psi_r, n_p, J, "
                    "P_N, w_M_N; B may be left out), smodrive never fills one in from Table I"
                    + (f"; give {detail}" if detail else ""))
        if self.B is None:
            b = min(B_REL * self.T_N / self.w_M_N, 1e3)
            object.__setattr__(self, "B", b)
            object.__setattr__(self, "derived", (("B", b, f"{B_REL:g} T_N / w_M_N: friction "
                                                 f"{B_REL:.0%} of the rated torque at rated "
                                                 "speed"),))
        elif self.derived and not _same_b(self.derived, self.B):
            object.__setattr__(self, "derived", ())  # B set since: the user's

    @property
    def T_N(self) -> float:
        """Rated torque P_N / (rated mechanical speed), N m."""
        return self.P_N / self.w_M_N

    @property
    def k_t(self) -> float:
        """Torque constant 1.5 n_p psi_r, N m/A."""
        return 1.5 * self.n_p * self.psi_r


def _same_b(derived: tuple, b: Any) -> bool:
    return any(n == "B" and v == b for n, v, _ in derived)


@dataclass(frozen=True)
class LclFilterPars(_Validated):
    """LCL filter between inverter and machine (yao2022 Fig. 1, Table II):
    L1 on the inverter side, C1 across, L2o in series with the machine's L_s."""

    _section = "lcl"
    L1: float = num(54e-6, 1e-8, 10.0, "H", "inverter-side inductance")
    L2o: float = num(27.5e-6, 0.0, 10.0, "H", "machine-side filter inductance")
    C1: float = num(31.48e-6, 1e-10, 1.0, "F", "filter capacitance")


@dataclass(frozen=True)
class InverterCfg(_Validated):
    _section = "inverter"
    u_dc: float = num(540.0, 0.0, 1e5, "V", "DC-link voltage", lo_open=True)
    pwm: str = choice("carrier", ("carrier", "averaged"), "carrier comparison or cycle average")
    t_dead: float = num(2e-6, 0.0, 1e-3, "s", "dead time (assumed)")
    dead_time_model: str = choice(
        "sign", ("sign", "clamp"),
        "dead time near zero current: sign (the diode by the current's sign at the period "
        "start) or clamp (zero-current clamping: a current reaching zero in the dead time stays "
        "there and the open leg follows the back EMF; not with the LCL filter)")
    svm_limit: str = choice("hexagon", ("hexagon", "circle"), "voltage limit of the modulator")


@dataclass(frozen=True)
class AdcCfg(_Validated):
    """Current sensors and ADC: the motor-current channels (i_s; i_2 with the
    filter) and, with the LCL filter, the inverter-side ones (i_1)."""

    _section = "adc"
    gain: tuple[float, float, float] = num((1.0, 1.0, 1.0), 0.5, 2.0, "", "per-phase gain")
    offset: tuple[float, float, float] = num((0.0, 0.0, 0.0), -1e3, 1e3, "A", "per-phase offset")
    gain_i1: tuple[float, float, float] = num((1.0, 1.0, 1.0), 0.5, 2.0, "",
                                              "per-phase gain of the i_1 channels (LCL)")
    offset_i1: tuple[float, float, float] = num((0.0, 0.0, 0.0), -1e3, 1e3, "A",
                                                "per-phase offset of the i_1 channels (LCL)")
    noise: float | None = num(None, 0.0, 1e3, "A",
                              "white-noise standard deviation (assumed; None: 0.08 % of "
                              "full_scale, 0.02 A at Table I)")
    bits: int = num(12, 0, 24, "", "resolution (0: none)", integer=True)
    full_scale: float | None = num(None, 1e-6, 1e6, "A",
                                   "+- input range (assumed; None: sized for the motor, 25 A x "
                                   "I_N / I_N of Table I, 3.9 I_N)")
    seed: int = num(1, 0, 2**63 - 1, "", "noise seed", integer=True)
    n_oversample: int = num(1, 1, 64, "",
                            "conversions averaged a sample (oversampling burst at the carrier "
                            "peak, its duration neglected) (assumed)", integer=True)
    # record of the values derived from the motor (not a parameter): (name, value, rule)
    derived: tuple = field(default=(), compare=False, repr=False, metadata={"internal": True})


CURRENT_CONTROL = ("pi", "dbpc", "robust_dbpc")
POSITION_SOURCES = ("encoder", "smdo_emf", "lcl_smo_pll", "lcl_linear")
STARTS = ("running", "handover", "if")

# yang2018's three drives (Fig. 3) as compositions of parts
YANG2018_MODES = {
    "conventional": dict(current="dbpc", position="encoder", start="running"),
    "robust": dict(current="robust_dbpc", position="encoder", start="running"),
    "sensorless": dict(current="robust_dbpc", position="smdo_emf", start="handover"),
}


@dataclass(frozen=True)
class ControllerCfg(_Validated):
    """The controller: its parts and its knowledge (parameter estimates and
    gains). Defaults: yang2018 Table I and Sec. IV-C; the values the papers
    do not give are assumed (docs/assumptions.md)."""

    _section = "controller"
    current: str = choice("robust_dbpc", CURRENT_CONTROL, "current control")
    position: str = choice("encoder", POSITION_SOURCES, "position source")
    start: str = choice("running", STARTS,
                        "running: the source from t = 0; handover: encoder for t_handover "
                        "first; if: I/f forced start up to w_M_handover")
    # model estimates
    L_s_hat: float | None = num(None, 0.0, 10.0, "H", "inductance estimate (None: motor.L_s)",
                                lo_open=True)
    R_s_hat: float | None = num(None, 0.0, 1e3, "ohm", "resistance estimate (None: motor.R_s)")
    psi_r_hat: float | None = num(None, 0.0, 100.0, "Wb",
                                  "PM flux estimate (DBPC, EMF feed-forward; None: motor.psi_r)")
    # SMDO, yang2018 eq. (34)-(39)
    lambda_min: float | None = num(None, 0.0, 1e7, "A/s",
                                   "SMDO lambda_min, eq. (37) (None: 800 A/s x (E_N / L_s) / "
                                   "(E_N / L_s of Table I), E_N = n_p w_M_N psi_r)")
    l: float = num(1200.0, 0.0, 1e7, "1/s", "SMDO proportional gain l, eq. (21)", lo_open=True)
    w_c: float = num(1500.0, 0.0, 1e7, "rad/s", "SMDO filter gain omega_c, eq. (19)", lo_open=True)
    rho: float | None = num(None, 0.0, 1e3, "A", "SMDO smoothing rho, eq. (39) (None: 0.2 A x "
                            "the same ratio, so lambda_min / rho stays 4000 1/s)", lo_open=True)
    smdo_euler: bool = flag(False, "eq. (36) as printed (forward-Euler rotation)")
    # position from the disturbance, eq. (44)-(45)
    w_lpf: float | None = num(None, 0.0, 1e6, "rad/s",
                              "sensorless speed LPF bandwidth (assumed; None: 100 rad/s x the "
                              "speed_bw ratio, docs/design_from_motor.md)", lo_open=True)
    w_hys: float = num(5.0, 0.0, 1e5, "rad/s", "direction hysteresis (electrical)")
    w_M_max: float | None = num(None, 0.0, 1e5, "rad/s",
                                "sensorless speed-estimate limit (mechanical; None: 2 w_M_N, "
                                "within the SMDO filter's stable range)", lo_open=True)
    # current PI (current = "pi")
    current_bw: float = num(2500.0, 0.0, 1e6, "rad/s",
                            "current-loop bandwidth: k_p_i = bw L, k_i_i = bw R (assumed)",
                            lo_open=True)
    k_p_i: float | None = num(None, 0.0, 1e4, "V/A", "current PI gain (None: current_bw L_s_hat; "
                              "with the filter current_bw (L1 + L2o + L_s_hat))")
    k_i_i: float | None = num(None, 0.0, 1e9, "V/(A s)",
                              "current PI integral gain (None: current_bw R_s_hat)")
    L_dec: float | None = num(None, 0.0, 10.0, "H",
                              "decoupling inductance (None: L_s_hat, plus L1 + L2o with the filter)")
    R_v: float = num(0.0, 0.0, 1e4, "V/A", "virtual resistance on i_1 - i_2 (LCL, assumed)")
    emf_ff: bool = flag(True, "feed the position source's EMF estimate forward (PI)")
    # speed loop
    speed_loop: bool = flag(True, "i_q reference from the speed PI (else from i_q_ref)")
    speed_bw: float | None = num(None, 0.0, 1e4, "rad/s",
                                 "speed-loop bandwidth (assumed; None: 60 rad/s x T_N / (J w_M_N) "
                                 "over Table I's, the same load-step dip)", lo_open=True)
    J_hat: float | None = num(None, 1e-9, 1e4, "kg m^2",
                              "inertia used to tune the speed PI (None: motor.J)")
    psi_r_pi: float | None = num(None, 0.0, 100.0, "Wb",
                                 "flux used to tune the speed PI (None: motor.psi_r)", lo_open=True)
    i_max: float | None = num(None, 0.0, 1e5, "A",
                              "current-reference limit (None: 15 A x I_N / (I_N of Table I), "
                              "I_N = T_N / k_t; at most 0.9 adc.full_scale)", lo_open=True)
    speed_decimation: int = num(1, 1, 1000, "", "speed loop runs every N samples", integer=True)
    # PLL, yao2022 eq. (48), (50)
    k_theta: float = num(0.1, 0.0, 2.0, "", "PLL, eq. (50)")
    k_omega: float = num(10.0, 0.0, 1e9, "1/s", "PLL, eq. (50)")
    k_a: float = num(10.0, 0.0, 1e12, "1/s^2", "PLL, eq. (50)")
    # yao2022 observers
    law: str = choice("proposed", ("proposed", "tde17", "tde18"), "reaching law")
    C1_hat_ratio: float = num(1.0, 0.1, 10.0, "", "observer's capacitance / true (Fig. 23)")
    Q: tuple[float, float] = num((0.5, 0.5), -0.999, 0.999, "", "reaching-law Q (Table III)")
    bw_rel: tuple[float, float] = num((0.2, 0.2), 1e-3, 1.9, "", "band-pass widths / f_e")
    w_M_bp_min: float = num(5e3 * RPM, 0.0, 1e5, "rad/s",
                            "band-pass suppression above this speed (mechanical, assumed)")
    # start
    t_handover: float = num(0.0, 0.0, 1e3, "s", "handover: time run on the encoder first")
    i_start: float | None = num(None, 0.0, 1e5, "A",
                                "I/f start current (None: 10 A x I_N / (I_N of Table I), at "
                                "most i_max)")
    a_M_start: float | None = num(None, 0.0, 1e8, "rad/s^2",
                                  "I/f acceleration (mechanical; None: 3000 r/min/s x the "
                                  "smaller of the ratios of T_N / J and of w_M_N to Table I's)")
    w_M_handover: float | None = num(None, 0.0, 1e6, "rad/s",
                                     "I/f: speed of the handover (mechanical; None: 0.1 w_M_N)")
    # modulator
    t_dead_comp: float | None = num(None, 0.0, 1e-3, "s", "dead time compensated by the "
                                    "modulator (None: inverter.t_dead)")
    i_dtc: float | None = num(None, 0.0, 1e5, "A", "linear zone of the compensation (None: "
                              "0.3 A x I_N / (I_N of Table I))", lo_open=True)
    # protection, loss of lock, zero-speed crossing (smd_drive.h; assumed values)
    i_trip: float | None = num(None, 0.0, 1e5, "A",
                               "overcurrent trip, peak phase current (None: 2.5 i_max; 0: off)")
    u_dc_min_ratio: float = num(0.5, 0.0, 1.0, "",
                                "undervoltage trip, fraction of the inverter's u_dc (0: off)")
    u_dc_max_ratio: float = num(1.5, 0.0, 100.0, "",
                                "overvoltage trip, multiple of the inverter's u_dc (0: off)")
    safe_state: str = choice("zero_vector", ("zero_vector", "pwm_off"),
                             "what a fault applies (the plant models both as the zero vector)")
    t_lock: float = num(0.02, 0.0, 100.0, "s",
                        "loss of lock after this long implausible (sensorless; 0: off)")
    lock_ratio: float = num(3.0, 1.0, 1e3, "", "EMF plausibility band [1/r, r] of |w| psi",
                            lo_open=True)
    w_M_lock_min: float = num(300.0 * RPM, 0.0, 1e6, "rad/s",
                              "no EMF plausibility check below this speed (mechanical)")
    w_M_if_enter: float | None = num(None, 0.0, 1e6, "rad/s",
                                     "sensorless below this speed returns to I/f, through zero "
                                     "(mechanical; 0: never; below w_M_handover; None: derived "
                                     "from the back EMF the source needs, docs/"
                                     "design_from_motor.md)")
    # reference shaping and supervision (smd_drive.h; None: derived, 0: off)
    a_M_ref: float | None = num(None, 0.0, 1e8, "rad/s^2",
                                "speed-reference slew-rate limit (mechanical; None: derived "
                                "from the torque and the speed estimate's lag; 0: off)")
    t_dwell: float | None = num(None, 0.0, 100.0, "s",
                                "least time between two start-up switches (handover, return "
                                "to I/f; None: 4 / w_lpf sensorless, 0 with the encoder)")
    chatter_max: int = num(4, 0, 1000, "", "chatter fault: more start-up switches than this "
                           "within t_chatter (0: off)", integer=True)
    t_chatter: float | None = num(None, 0.0, 1e3, "s",
                                  "window of the chatter count (None: 20 t_dwell, at least "
                                  "0.5 s)")
    w_M_track: float | None = num(None, 0.0, 1e6, "rad/s",
                                  "speed-tracking fault: farther than this from the reference "
                                  "(mechanical; None: 0.1 w_M_N) ...")
    t_track: float | None = num(None, 0.0, 1e3, "s",
                                "... at the current limit for this long (None: derived from "
                                "the inertia; 0: off)")
    t_forced: float | None = num(None, 0.0, 1e3, "s",
                                 "forced-phase fault: I/f for this long while the reference "
                                 "asks for the source (None: derived from the I/f ramp; 0: off)")
    osc_i: float | None = num(None, 0.0, 1e5, "A",
                              "oscillation warning: current ripple beyond osc_i + osc_rel "
                              "|i_ref| (None: derived from the ADC noise and I_N) ...")
    osc_rel: float = num(0.1, 0.0, 100.0, "", "... (the part relative to the reference) ...")
    t_osc: float = num(0.02, 0.0, 100.0, "s", "... for this long (0: off)")
    restart_max: int = num(2, 0, 100, "", "SMDO position with an I/f start: automatic restarts "
                           "from rest on I/f after a lost lock or a failed start, at most this "
                           "many within t_restart (0: latch at once)", integer=True)
    t_restart: float = num(2.0, 0.0, 1e3, "s", "the window of the restart count")
    # record of the design from the motor (not a parameter)
    derived: tuple = field(default=(), compare=False, repr=False, metadata={"internal": True})

    def _need(self, *names: str) -> None:
        """A derived field used before a Scenario resolved it is named."""
        for n in names:
            if getattr(self, n) is None:
                raise ParameterError(
                    f"controller.{n} is unset: it is derived from the motor when the "
                    "ControllerCfg is part of a Scenario (Scenario(...).controller), or set it")

    def pi_gains(self, n_p: int) -> tuple[float, float]:
        """Speed PI gains in A per electrical rad/s: the loop
        b / s with b = 1.5 n_p^2 psi / J closed by k_p + k_i / s has the
        characteristic polynomial s^2 + b k_p s + b k_i; both roots at -speed_bw."""
        self._need("psi_r_pi", "J_hat")
        b = 1.5 * n_p**2 * self.psi_r_pi / self.J_hat
        if not (math.isfinite(b) and b > 0.0):
            raise ParameterError(
                f"controller.psi_r_pi = {self.psi_r_pi!r} with J_hat = {self.J_hat!r}: the "
                "speed-loop gain 1.5 n_p^2 psi / J is not a positive finite number")
        return 2.0 * self.speed_bw / b, self.speed_bw**2 / b

    def current_pi_gains(self) -> tuple[float, float]:
        """(k_p_i, k_i_i): the set values, or the internal-model design
        k_p = bw L_s_hat, k_i = bw R_s_hat (the PI zero cancels the R/L pole)."""
        if self.k_p_i is None:
            self._need("L_s_hat")
        if self.k_i_i is None:
            self._need("R_s_hat")
        k_p = self.current_bw * self.L_s_hat if self.k_p_i is None else self.k_p_i
        k_i = self.current_bw * self.R_s_hat if self.k_i_i is None else self.k_i_i
        return k_p, k_i


def yang2018_mode(mode: str) -> dict[str, str]:
    """The parts of yang2018's conventional, robust or sensorless drive."""
    try:
        return dict(YANG2018_MODES[mode])
    except KeyError:
        raise ParameterError(
            f"controller.mode = {mode!r} is not one of {', '.join(YANG2018_MODES)}") from None


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


@dataclass(frozen=True)
class LoadCfg(_Validated):
    _section = "load"
    _profile_ranges = {"T_brake": (0.0, math.inf, "N m", "a brake torque is a magnitude (the "
                                   "brake opposes the rotation, whichever its sense)")}
    T_brake: Profile = field(default_factory=lambda: Profile.const(0.0))
    T_ext: Profile = field(default_factory=lambda: Profile.const(0.0))
    w_brake_eps: float = num(1.0, 1e-9, 1e3, "rad/s", "brake taper speed (assumed)")
    k_fan: float = num(0.0, 0.0, 1e3, "N m s^2/rad^2", "fan load coefficient")


@dataclass(frozen=True)
class Scenario(_Validated):
    """One runnable experiment: a plant (motor, optional LCL filter,
    inverter, ADC, load), a composed controller and the references."""

    _section = "scenario"
    name: str = "scenario"
    T_sp: float = num(100e-6, 1e-7, 1.0, "s", "sampling (= carrier) period")
    duration: float = num(1.0, 0.0, 1e4, "s", "simulated time", lo_open=True)
    w_M0: float = num(0.0, -9.9e4, 9.9e4, "rad/s", "initial speed (mechanical)")
    theta_r0: float = num(0.0, -1e3, 1e3, "rad", "initial electrical angle")
    w_M_ref: Profile = field(default_factory=lambda: Profile.const(0.0))  # rad/s
    i_d_ref: Profile = field(default_factory=lambda: Profile.const(0.0))
    i_q_ref: Profile = field(default_factory=lambda: Profile.const(0.0))
    i_d_sin_amp: float = num(0.0, 0.0, 1e4, "A", "sinusoid added to the i_d reference")
    i_d_sin_freq: float = num(0.0, 0.0, 1e7, "Hz", "its frequency")
    log_stride: int = num(1, 1, 10**6, "", "log every N samples", integer=True)
    faults_expected: bool = flag(False, "a run that ends in a fault is what the scenario "
                                        "tests (the CLI exits 0)")
    warm_start: bool = flag(True, "start in steady state: current and speed PI carry the load")
    motor: MotorPars = field(default_factory=MotorPars)
    lcl: LclFilterPars | None = None
    controller: ControllerCfg = field(default_factory=ControllerCfg)
    inverter: InverterCfg = field(default_factory=InverterCfg)
    adc: AdcCfg = field(default_factory=AdcCfg)
    load: LoadCfg = field(default_factory=LoadCfg)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise ParameterError(f"scenario.name = {self.name!r} is not a string (the label of "
                                 "the run, also used in its file names)")
        for sec in ("motor", "controller", "inverter", "adc", "load"):
            cls = type(self).__dataclass_fields__[sec].default_factory  # type: ignore[misc]
            if not isinstance(getattr(self, sec), cls):
                raise ParameterError(
                    f"scenario.{sec} = {getattr(self, sec)!r} is not a {cls.__name__}")
        super().__post_init__()
        if self.lcl is not None and not isinstance(self.lcl, LclFilterPars):
            raise ParameterError(f"scenario.lcl = {self.lcl!r} is not an LclFilterPars or None")
        # the controller's motor-specific values the user left unset, derived
        # from the motor (smodrive.design.from_motor; the record: controller.derived)
        from .design import from_motor

        object.__setattr__(self, "adc", from_motor.resolve_adc(self.adc, self.motor))
        object.__setattr__(self, "controller", from_motor.resolve(
            self.controller, self.motor, T_sp=self.T_sp, lcl=self.lcl,
            adc_full_scale=self.adc.full_scale, plant=from_motor.plant_of(self)))
        # plant limits that depend on more than one field
        if self.inverter.t_dead > 0.25 * self.T_sp:
            raise ParameterError(
                f"inverter.t_dead = {self.inverter.t_dead!r} is outside its valid range "
                f"[0, T_sp/4 = {0.25 * self.T_sp:g}] s")

    @property
    def L_dec(self) -> float:
        """Decoupling inductance of the current PI, H."""
        c = self.controller
        if c.L_dec is not None:
            return c.L_dec
        if self.lcl is None:
            return c.L_s_hat
        return self.lcl.L1 + self.lcl.L2o + c.L_s_hat

    def check_controller(self) -> None:
        """Controller limits that depend on more than one field (the ones the
        C core's init checks too); run by load_scenario and before every
        simulation, not for plant-only use."""
        T, c = self.T_sp, self.controller
        nyq = math.pi / T
        from .design import from_motor

        for msg in from_motor.override_warnings(c, self.motor, T_sp=T, lcl=self.lcl,
                                                adc_full_scale=self.adc.full_scale,
                                                plant=from_motor.plant_of(self)):
            warnings.warn(f"{self.name}: {msg}", UserWarning, stacklevel=2)
        lcl_src = c.position in ("lcl_smo_pll", "lcl_linear")
        if lcl_src and self.lcl is None:
            raise ParameterError(
                f"controller.position = {c.position!r} needs the LCL filter: add an [lcl] "
                "section (L1, L2o, C1) or choose encoder / smdo_emf")
        if self.lcl is not None and c.current != "pi":
            raise ParameterError(
                f"controller.current = {c.current!r} with the LCL filter: only 'pi' (with "
                "active damping) is designed for the filtered drive")
        if self.lcl is not None and c.position == "smdo_emf":
            raise ParameterError(
                "controller.position = 'smdo_emf' with the LCL filter: the SMDO's model "
                "(yang2018 eq. (15)) has no filter; choose lcl_smo_pll, lcl_linear or encoder")
        if self.lcl is None and c.R_v > 0.0:
            raise ParameterError(
                f"controller.R_v = {c.R_v!r}: active damping needs the LCL filter's current "
                "i_1; set it to 0 without the filter")
        if c.t_handover / T > 2**31 - 1:
            raise ParameterError(
                f"controller.t_handover = {c.t_handover!r} is too long: at most "
                f"{(2**31 - 1) * T:g} s at T_sp = {T:g} s")
        k_p, k_i = c.pi_gains(self.motor.n_p)
        if not (k_p <= 1e6 and k_i <= 1e9):
            raise ParameterError(
                f"controller.speed_bw = {c.speed_bw!r} with J_hat = {c.J_hat!r} gives speed-PI "
                f"gains k_p = {k_p:g}, k_i = {k_i:g}, beyond the core's limits 1e6 and 1e9")
        if c.current == "pi":
            k_p, k_i = c.current_pi_gains()
            if not (k_p <= 1e4 and k_i <= 1e9):
                raise ParameterError(
                    f"controller.current_bw = {c.current_bw!r} gives current-PI gains "
                    f"k_p_i = {k_p:g} V/A, k_i_i = {k_i:g} V/(A s), beyond the core's limits "
                    "1e4 and 1e9")
            if self.L_dec > 10.0:
                # L_dec unset is derived: name what it is derived from
                src = ("controller.L_dec" if c.L_dec is not None else "controller.L_s_hat"
                       if self.lcl is None else "controller.L_s_hat + lcl.L1 + lcl.L2o")
                raise ParameterError(
                    f"{src} = {self.L_dec:g} H is outside the valid range [0, 10] H of the "
                    "decoupling inductance (controller.L_dec)")
        if c.t_dead_comp > 0.25 * T:
            raise ParameterError(
                f"controller.t_dead_comp = {c.t_dead_comp!r} is outside its valid range "
                f"[0, T_sp/4 = {0.25 * T:g}] s")
        if c.start == "if" and c.w_M_handover * self.motor.n_p > nyq:
            raise ParameterError(
                f"controller.w_M_handover = {c.w_M_handover!r} is outside its valid range: "
                f"w_M_handover n_p must be at most pi/T_sp = {nyq:g} rad/s")
        if c.w_M_if_enter > 0.0:
            if c.position == "encoder":
                raise ParameterError(
                    f"controller.w_M_if_enter = {c.w_M_if_enter!r}: the return to I/f through "
                    "zero speed is for a sensorless position source; set it to 0 with the "
                    "encoder")
            if not c.w_M_if_enter < c.w_M_handover:
                raise ParameterError(
                    f"controller.w_M_if_enter = {c.w_M_if_enter!r} must be below "
                    f"w_M_handover = {c.w_M_handover!r} (the hysteresis of the return to I/f)")
        if 0.0 < c.u_dc_max_ratio <= c.u_dc_min_ratio:
            raise ParameterError(
                f"controller.u_dc_max_ratio = {c.u_dc_max_ratio!r} must exceed "
                f"u_dc_min_ratio = {c.u_dc_min_ratio!r} (or be 0: off)")
        if c.t_lock / T > 1e6:
            raise ParameterError(
                f"controller.t_lock = {c.t_lock!r} is too long: at most {1e6 * T:g} s "
                f"at T_sp = {T:g} s")
        if c.position == "smdo_emf":
            if c.w_lpf >= nyq:
                raise ParameterError(
                    f"controller.w_lpf = {c.w_lpf!r} is outside its valid range "
                    f"(0, pi/T_sp = {nyq:g}) rad/s")
            w_max = c.w_M_max * self.motor.n_p
            if not (c.w_hys < w_max <= nyq):
                raise ParameterError(
                    f"controller.w_M_max = {c.w_M_max!r} is outside its valid range: the "
                    f"electrical speed limit w_M_max n_p must lie in (w_hys = {c.w_hys:g}, "
                    f"pi/T_sp = {nyq:g}] rad/s")
            a, b = 1.0 - c.w_c * T, w_max * T
            if a * a + b * b >= 1.0:
                raise ParameterError(
                    f"controller.w_c = {c.w_c!r} with w_M_max = {c.w_M_max!r}: the filter (36) "
                    "would be unstable, |1 - w_c T_sp + j w_max T_sp| must be below 1")
        uses_smdo = c.current == "robust_dbpc" or c.position == "smdo_emf"
        if uses_smdo and (c.l + c.lambda_min / c.rho) * T >= 2.0:
            raise ParameterError(
                f"controller.l = {c.l!r}, lambda_min = {c.lambda_min!r}, rho = {c.rho!r}: "
                "(l + lambda_min/rho) T_sp must be below 2 for a stable SMDO")
        if uses_smdo and c.w_c * T >= 1.0:
            raise ParameterError(
                f"controller.w_c = {c.w_c!r} is outside its valid range (0, 1/T_sp = {1 / T:g})"
                " rad/s")
        self.check_run()

    def check_run(self) -> None:
        """Limits of a run as a whole (part of :meth:`check_controller`):
        samples to simulate and log, a back-EMF for the sensorless position
        sources, and for the LCL observers a sampling period and speeds
        their offline design covers."""
        T, c = self.T_sp, self.controller
        if self.duration < 2.0 * T:
            raise ParameterError(
                f"duration = {self.duration!r} is outside its valid range [2 T_sp = {2 * T:g}, "
                f"1e4] s: the run would have {self.n_steps} control samples")
        n = self.n_steps
        if self.log_stride >= n:
            raise ParameterError(
                f"log_stride = {self.log_stride!r} is outside its valid range [1, {n - 1}] for "
                f"the {n} control samples of the run (duration / T_sp): the log would hold the "
                "initial state only")
        if c.position != "encoder" and self.motor.psi_r == 0.0:
            raise ParameterError(
                f"motor.psi_r = 0.0 with controller.position = {c.position!r}: a machine "
                "without magnet flux has no back-EMF to estimate the angle from; motor.psi_r "
                "must be above 0 (or choose position = 'encoder')")
        if c.position not in ("lcl_smo_pll", "lcl_linear") or self.lcl is None:
            return
        # the observers' model: lcl.L1, lcl.L2o + L_s_hat, C1_hat_ratio lcl.C1 (eq. (1)-(3))
        L1, L2, C1 = self.lcl.L1, self.lcl.L2o + c.L_s_hat, self.lcl.C1 * c.C1_hat_ratio
        try:
            f_res = math.sqrt((L1 + L2) / (L1 * L2 * C1)) / (2.0 * math.pi)
        except (ZeroDivisionError, OverflowError):  # values at the ends of their ranges
            f_res = math.inf
        if T > 0.5 / f_res:
            raise ParameterError(
                f"T_sp = {T!r} is outside its valid range (0, 1/(2 f_res) = {0.5 / f_res:g}] s "
                f"for the LCL observers: their filter model (lcl.L1, lcl.L2o + "
                f"controller.L_s_hat, lcl.C1 x controller.C1_hat_ratio) resonates at f_res = "
                f"{f_res:g} Hz, which the sampling must resolve (Nyquist)")
        lim = LCL_TABLE_RPM * RPM
        for name, verb, values in (("w_M0", "=", (self.w_M0,)),
                                   ("w_M_ref", "reaches", self.w_M_ref.y)):
            w = max(values, key=abs)
            if abs(w) > lim:
                raise ParameterError(
                    f"{name} {verb} {w / RPM:g} r/min ({w:g} rad/s), beyond the LCL observers' "
                    f"tables, which cover [{-LCL_TABLE_RPM:g}, {LCL_TABLE_RPM:g}] r/min: keep "
                    f"{name} (or {name}_rpm) within them")

    @property
    def n_steps(self) -> int:
        return int(round(self.duration / self.T_sp))

    def replace(self, **changes: Any) -> "Scenario":
        return dataclasses.replace(self, **changes)

    def with_controller(self, **changes: Any) -> "Scenario":
        """A copy with controller fields changed (``mode`` expands to yang2018's
        parts)."""
        if "mode" in changes:
            changes = {**yang2018_mode(changes.pop("mode")), **changes}
        return self.replace(controller=dataclasses.replace(self.controller, **changes))


