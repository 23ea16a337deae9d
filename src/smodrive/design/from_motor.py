"""The controller designed from the motor: every motor-specific
:class:`~smodrive.params.ControllerCfg` value the user leaves unset.

The rules (reasoning in docs/design_from_motor.md) are scaling laws
anchored on the yang2018 drive, whose values on its Table I motor are the
reference: a value is ``reference x (q / q_ref)``, where ``q`` is the motor
quantity the value scales with (rated back EMF over inductance for the SMDO,
rated current for current limits, rated speed for speeds, rated torque over
inertia for the I/f acceleration) and ``q_ref`` the same quantity of Table
I. For Table I ``q / q_ref`` is exactly 1.0, so the derived values are
bit-identical to the values the drive used before they were derived. The
model estimates are the motor's own values.

A value the drive's composition does not use (the SMDO's gains under PI
current control on the encoder, the speed PI's model with the speed loop
off, the I/f values without an I/f start, ...) keeps the reference value:
the drive ignores it, and a preset keeps the configuration it had.

:func:`resolve` is called by :class:`~smodrive.params.Scenario` on
construction; the resolved :class:`ControllerCfg` records in its
``derived`` field which values were derived (name, value, source). A value
the user set is kept; :func:`override_warnings` names the ones far from the
motor's value.

Example
-------
>>> from smodrive.params import MotorPars, Scenario
>>> s = Scenario(motor=MotorPars(L_s=2e-3, R_s=0.3, psi_r=0.05, P_N=500.0))
>>> s.controller.L_s_hat, s.controller.R_s_hat
(0.002, 0.3)
>>> dict((n, src) for n, _, src in s.controller.derived)["L_s_hat"]
'motor.L_s'
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from ..params import RPM, ControllerCfg, MotorPars, ParameterError

#: the reference motor: yang2018 Table I (the MotorPars defaults)
REF_MOTOR = MotorPars()
#: the yang2018 drive's values on it (Sec. IV-C and docs/assumptions.md)
REFERENCE: dict[str, float] = {
    "lambda_min": 800.0, "rho": 0.2, "w_M_max": 3000.0 * RPM, "i_max": 15.0,
    "i_start": 10.0, "a_M_start": 3000.0 * RPM, "w_M_handover": 150.0 * RPM, "i_dtc": 0.3,
}
#: fields derived from the motor (and the filter), in the order they are resolved
DERIVED_FIELDS: tuple[str, ...] = (
    "L_s_hat", "R_s_hat", "psi_r_hat", "J_hat", "psi_r_pi", "lambda_min", "rho", "w_M_max",
    "i_max", "i_start", "a_M_start", "w_M_handover", "i_dtc", "k_p_i", "k_i_i")
#: an override whose ratio to the motor's value lies outside this band warns
WARN_BAND = (0.2, 5.0)
#: the fields that have a motor's value to compare an override with: the
#: model estimates and the current limit (the gains and start-up values are
#: design choices, which a user may well set far from the rule)
WARNED = ("L_s_hat", "R_s_hat", "psi_r_hat", "J_hat", "psi_r_pi", "i_max")
#: the derived sensorless speed limit stays this far inside the SMDO filter's stability bound
W_MAX_MARGIN = 0.95
#: the derived current limit stays within this fraction of the ADC's range
I_MAX_ADC = 0.9


def rated_emf(m: MotorPars) -> float:
    """Peak phase back EMF at rated speed, n_p w_M_N psi_r (V)."""
    return m.n_p * m.w_M_N * m.psi_r


def rated_current(m: MotorPars) -> float:
    """Peak phase current of rated torque, T_N / k_t (A; inf without flux)."""
    return m.T_N / m.k_t if m.k_t > 0.0 else math.inf


def _ratio(q: float, q_ref: float) -> float | None:
    """q / q_ref, exactly 1.0 when equal; None when q is not a usable
    (positive, finite) quantity."""
    if not (math.isfinite(q) and q > 0.0):
        return None
    return 1.0 if q == q_ref else q / q_ref


def _uses(c: ControllerCfg) -> dict[str, str | None]:
    """For each derived field: None if the composition uses it, else why not."""
    smdo = c.current == "robust_dbpc" or c.position == "smdo_emf"
    if_ = c.start == "if" or c.w_M_if_enter > 0.0
    no_smdo = None if smdo else "no SMDO (current and position do not use it)"
    return {
        "L_s_hat": None, "R_s_hat": None, "psi_r_hat": None, "i_max": None,
        "J_hat": None if c.speed_loop else "speed_loop = false",
        "psi_r_pi": None if c.speed_loop else "speed_loop = false",
        "lambda_min": no_smdo, "rho": no_smdo,
        "w_M_max": None if c.position == "smdo_emf" else "position is not smdo_emf",
        "i_start": None if if_ else "no I/f (start and w_M_if_enter)",
        "a_M_start": None if if_ else "no I/f (start and w_M_if_enter)",
        "w_M_handover": None if if_ else "no I/f (start and w_M_if_enter)",
        "i_dtc": None if c.t_dead_comp > 0.0 else "t_dead_comp = 0",
    }


def derive(name: str, m: MotorPars, c: ControllerCfg, *, T_sp: float, lcl: Any = None,
           adc_full_scale: float = math.inf, resolved: dict[str, Any] | None = None
           ) -> tuple[Any, str]:
    """(value, source) of field `name` derived from motor `m` for controller
    `c` (whose other derived fields are in `resolved`, by name)."""
    r = resolved or {}
    get = lambda n: r.get(n, getattr(c, n))  # noqa: E731
    ref = REF_MOTOR
    if name in ("L_s_hat", "R_s_hat", "psi_r_hat", "J_hat", "psi_r_pi"):
        src = {"L_s_hat": "L_s", "R_s_hat": "R_s", "psi_r_hat": "psi_r", "J_hat": "J",
               "psi_r_pi": "psi_r"}[name]
        v = getattr(m, src)
        if name == "psi_r_pi" and v <= 0.0:
            return REFERENCE_MODEL["psi_r_pi"], ("reference: motor.psi_r = 0 gives no speed-loop "
                                                 "gain to tune for")
        return v, f"motor.{src}"
    if name in ("lambda_min", "rho"):
        k = _ratio(rated_emf(m) / m.L_s, rated_emf(ref) / ref.L_s)
        if k is None:
            return REFERENCE[name], "reference: motor.psi_r = 0 (no rated back EMF)"
        return REFERENCE[name] * k, "scaled by E_N / L_s (rated back EMF over inductance)"
    if name == "w_M_max":
        k = _ratio(m.w_M_N, ref.w_M_N)
        v = REFERENCE[name] * k  # type: ignore[operator]
        # |1 - w_c T + j w_max T| < 1 (filter (36)) and w_max <= pi / T
        a = 1.0 - c.w_c * T_sp
        bound = min(math.sqrt(max(1.0 - a * a, 0.0)) / T_sp, math.pi / T_sp) / m.n_p
        if 0.0 < W_MAX_MARGIN * bound < v:  # (w_c T >= 1: check_controller names w_c)
            return W_MAX_MARGIN * bound, (f"2 w_M_N, limited to {W_MAX_MARGIN:g} of the speed "
                                          "the SMDO filter (36) is stable at (w_c, T_sp)")
        return v, "2 w_M_N (twice rated speed)"
    if name in ("i_max", "i_start", "i_dtc"):
        k = _ratio(rated_current(m), rated_current(ref))
        if k is None:
            return REFERENCE[name], "reference: no rated current (motor.psi_r or P_N = 0)"
        v = REFERENCE[name] * k
        if name == "i_max" and v > I_MAX_ADC * adc_full_scale:
            return I_MAX_ADC * adc_full_scale, (f"scaled by I_N = T_N / k_t, limited to "
                                                f"{I_MAX_ADC:g} adc.full_scale")
        if name == "i_start" and v > get("i_max"):
            return get("i_max"), "scaled by I_N, limited to i_max"
        return v, "scaled by I_N = T_N / k_t (rated current)"
    if name == "a_M_start":
        k = _ratio(m.T_N / m.J, ref.T_N / ref.J)
        if k is None:
            return REFERENCE[name], "reference: motor.P_N = 0 (no rated torque)"
        return REFERENCE[name] * k, "scaled by T_N / J (rated torque over inertia)"
    if name == "w_M_handover":
        k = _ratio(m.w_M_N, ref.w_M_N)
        return REFERENCE[name] * k, "0.1 w_M_N (a tenth of rated speed)"  # type: ignore[operator]
    if name == "k_p_i":
        return c.current_bw * (lcl.L1 + lcl.L2o + get("L_s_hat")), \
            "current_bw (lcl.L1 + lcl.L2o + L_s_hat)"
    if name == "k_i_i":
        return c.current_bw * get("R_s_hat"), "current_bw R_s_hat"
    raise KeyError(name)


# the model values standing in where the motor gives none (Table I)
REFERENCE_MODEL = {"psi_r_pi": REF_MOTOR.psi_r}
#: the value a field the composition does not use keeps (the yang2018 drive's)
REFERENCE_UNUSED = {**REFERENCE, "J_hat": REF_MOTOR.J, "psi_r_pi": REF_MOTOR.psi_r}


def resolve(c: ControllerCfg, m: MotorPars, *, T_sp: float, lcl: Any = None,
            adc_full_scale: float = math.inf) -> ControllerCfg:
    """`c` with every motor-derived field that is unset (None), or still at
    the value an earlier resolution derived, derived from motor `m` (and the
    filter `lcl`); the others kept. The result's ``derived`` lists the
    derived ones as (name, value, source)."""
    before = {n: (v, src) for n, v, src in c.derived}
    uses = _uses(c)
    out: dict[str, Any] = {}
    record = []
    for name in DERIVED_FIELDS:
        v = getattr(c, name)
        was_derived = name in before and _same(before[name][0], v)
        if not (v is None or was_derived):
            continue  # the user's value
        if name in ("k_p_i", "k_i_i") and lcl is None:
            # without the filter the PI gains stay unset: current_pi_gains()
            # derives them from current_bw, L_s_hat and R_s_hat
            if was_derived:
                out[name] = None
            continue
        why_not = uses.get(name)
        if why_not is not None:
            new, src = REFERENCE_UNUSED[name], f"reference, unused: {why_not}"
        else:
            new, src = derive(name, m, c, T_sp=T_sp, lcl=lcl, adc_full_scale=adc_full_scale,
                              resolved=out)
            new, src = _within_range(name, new, src)
        out[name] = new
        record.append((name, new, src))
    try:
        return dataclasses.replace(c, **out, derived=tuple(record))
    except ParameterError as exc:
        bad = next((n for n, _, _ in record if f"controller.{n} " in str(exc)), None)
        if bad is None:
            raise
        raise ParameterError(
            f"{exc} (derived from the motor: {dict((n, s) for n, _, s in record)[bad]}; set "
            f"controller.{bad} in [controller])") from None


def _within_range(name: str, v: float, src: str) -> tuple[float, str]:
    """A derived value clamped into the field's valid range (a machine at
    the ends of the ranges; the drive's own checks then name what does not
    fit)."""
    lo, hi, lo_open = ControllerCfg.__dataclass_fields__[name].metadata["range"]
    if v > hi:
        return hi, f"{src}; clamped to the upper end of its range"
    if v < lo or (lo_open and v <= lo) or not math.isfinite(v):
        ref = REFERENCE_UNUSED.get(name)
        if ref is not None:
            return ref, f"reference: {src} gives {v:g}, outside the field's range"
    return v, src


def _same(a: Any, b: Any) -> bool:
    return a is b or (a is not None and b is not None and a == b)


#: the motor quantity each model estimate stands for (for the warnings)
_MOTOR_VALUE = {"L_s_hat": "L_s", "R_s_hat": "R_s", "psi_r_hat": "psi_r", "J_hat": "J",
                "psi_r_pi": "psi_r"}


def override_warnings(c: ControllerCfg, m: MotorPars, *, T_sp: float, lcl: Any = None,
                      adc_full_scale: float = math.inf) -> list[str]:
    """Messages for the user-set fields the composition uses whose value is
    outside WARN_BAND times the value derived from the motor, each naming
    both values."""
    derived = {n for n, _, _ in c.derived}
    uses = _uses(c)
    out = []
    lo, hi = WARN_BAND
    for name in DERIVED_FIELDS:
        v = getattr(c, name)
        if name in derived or v is None or uses.get(name) is not None:
            continue
        if name not in WARNED:
            continue
        ref, src = derive(name, m, c, T_sp=T_sp, lcl=lcl, adc_full_scale=adc_full_scale)
        if not (ref > 0.0 and math.isfinite(ref)):
            continue
        ratio = v / ref
        if lo <= ratio <= hi:
            continue
        unit = ControllerCfg.__dataclass_fields__[name].metadata["unit"]
        basis = (f"motor.{_MOTOR_VALUE[name]}" if name in _MOTOR_VALUE else src)
        out.append(f"controller.{name} = {v:g} {unit} is {ratio:.3g} x the value derived from "
                   f"the motor, {ref:g} {unit} ({basis}), outside [{lo:g}, {hi:g}]: the "
                   f"controller is tuned for another machine; remove controller.{name} to "
                   "derive it".replace("  ", " "))
    return out


def unset(c: ControllerCfg, keep: set[str] | frozenset[str] = frozenset()) -> ControllerCfg:
    """`c` with every motor-derived field (except those in `keep`) unset, so
    that a scenario with another motor derives them anew."""
    return dataclasses.replace(c, derived=(), **{n: None for n in DERIVED_FIELDS
                                                 if n not in keep})
