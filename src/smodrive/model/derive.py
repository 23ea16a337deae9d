"""The controller designed from the motor: every motor-specific
:class:`~smodrive.model.ControllerCfg` value the user leaves unset.

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

:func:`resolve` is called by :class:`~smodrive.model.Scenario` on
construction; the resolved :class:`ControllerCfg` records in its
``derived`` field which values were derived (name, value, source). A value
the user set is kept; :func:`override_warnings` names the ones far from the
motor's value.

Example
-------
>>> from smodrive.model import MotorPars, Scenario
>>> s = Scenario(motor=MotorPars(L_s=2e-3, R_s=0.3, psi_r=0.05, n_p=4, J=2e-4, P_N=500.0,
...                                w_M_N=314.0))
>>> s.controller.L_s_hat, s.controller.R_s_hat
(0.002, 0.3)
>>> dict((n, src) for n, _, src in s.controller.derived)["L_s_hat"]
'motor.L_s'
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from .fields import RPM, ParameterError
from .pars import ControllerCfg, MotorPars

#: the reference motor: yang2018 Table I (the MotorPars defaults)
REF_MOTOR = MotorPars()
#: the yang2018 drive's values on it (Sec. IV-C and docs/assumptions.md)
REFERENCE: dict[str, float] = {
    "w_c": 1500.0, "lambda_min": 800.0, "rho": 0.2, "w_M_max": 3000.0 * RPM, "i_max": 15.0,
    "i_start": 10.0, "a_M_start": 3000.0 * RPM, "w_M_handover": 150.0 * RPM, "i_dtc": 0.3,
}
#: fields derived from the motor (and the filter and inverter), in the order they are resolved
DERIVED_FIELDS: tuple[str, ...] = (
    "w_c", "L_s_hat", "R_s_hat", "psi_r_hat", "J_hat", "psi_r_pi", "speed_bw", "w_lpf",
    "rls_t_half", "lambda_min", "rho", "w_M_max",
    "i_max", "i_start", "a_M_start", "w_M_if_enter", "w_M_handover", "t_dead_comp", "i_dtc",
    "k_p_i", "k_i_i", "a_M_ref", "t_dwell", "t_chatter", "t_hunt", "w_M_track", "t_track",
    "t_forced", "osc_i")
#: the speed loop's bandwidth (and the SMDO speed filter's) scales with the inverse
#: mechanical time constant T_N / (J w_M_N) over Table I's, at most this factor ...
SPEED_BW_MAX_RATIO = 5.0
#: ... and never below this one (a slower loop only lengthens the transients)
SPEED_BW_MIN_RATIO = 0.25
#: the tracker's square wave with the SMDO's angle: its angular frequency pi / rls_t_half
#: this many times the speed loop's bandwidth (slower, the speed loop turns what the
#: wave does to the angle into torque and the rotor moves with it: a 48 V servo's R_s
#: ran 57 % off at 20 ms), within [RLS_MIN_HALF T_sp, 20 ms]
RLS_BW_RATIO = 5.0
RLS_MIN_HALF = 16
#: the derived ADC: full scale 25 A x I_N / I_N(Table I), noise this fraction of it
ADC_NOISE_FS = 0.02 / 25.0
#: the speed reference's slew limit takes this fraction of the torque at the current limit
A_REF_TORQUE = 0.5
#: ... and lets the SMDO's speed estimate (low-pass w_lpf) lag by this fraction of w_M_N
A_REF_LAG = 0.05
#: ... and by this fraction of w_M_if_enter, where the return to I/f is on
A_REF_LAG_IF = 0.25
#: hunting fault: the window of its count, in time constants 1 / speed_bw of the speed
#: loop (a well-damped loop swings from one current limit to the other at most once per
#: reference change and settles within a few time constants)
HUNT_TAU = 10.0
#: speed-tracking fault: this fraction of rated speed away from the reference
TRACK_REL = 0.1
#: oscillation warning: this fraction of the rated current, plus OSC_NOISE x the ADC noise
OSC_REL_N = 0.02
OSC_NOISE = 4.0
#: the sensorless sources' back EMF must exceed the voltage error of their
#: input (dead time, ADC noise) by this factor for the return to I/f ...
EMF_MARGIN_ENTER = 2.0
#: the share of the dead time's voltage error counted where the full error would put the
#: handover above HANDOVER_MAX w_M_N and the drive compensates it: inside the compensation's
#: linear zone the error and its compensation lie along the current, which at light load
#: lies along q, the EMF's direction (they change the EMF's length, not its angle).
#: Measured (issue 23's micro motor at 2 us on 12 V, 40 kHz: a 1.22 V drop): the usual
#: profile holds its lock with the return at 0.2 of the drop (3 of 3 seeds) and loses it
#: at 0.1 (1 of 3); a quarter, with the margin EMF_MARGIN_ENTER on top, is 2.5 x the first
DTC_RESIDUAL = 0.25
#: ... and by this one for the handover to the source (the hysteresis)
HANDOVER_RATIO = 2.0
#: the handover is at least this many times the rotor's speed swing on I/f (if_swing)
SWING_MARGIN = 3.0
#: the handover speed at most this share of rated speed: i_start is limited to keep the
#: swing rule below it (assumed: half the speed range sensorless at least)
HANDOVER_MAX = 0.5
#: the SMDO's error loop at least this many times the stator's pole R_s / L_s
RHO_POLE = 1.2
#: the share of the modulator's voltage (u_dc / sqrt 3) the I/f current may take across R_s
IF_VOLTAGE = 0.5
#: least return-to-I/f speed, fraction of rated speed (docs/design_from_motor.md)
IF_ENTER_MIN = 0.05
#: the plant quantities the design reads when the Scenario gives none (Table I's drive)
DEFAULT_PLANT = {"t_dead": 2e-6, "u_dc": 540.0, "noise": 0.02}


def resolve_adc(a: Any, m: MotorPars) -> Any:
    """`a` (an AdcCfg) with full_scale and noise derived from the motor where
    unset (or still at a derived value): current sensors sized for the machine,
    25 A x I_N / I_N(Table I) (3.9 I_N, Table I's assumed +-25 A), and a noise
    of ADC_NOISE_FS of that range (0.02 A at Table I)."""
    before = {n: v for n, v, _ in a.derived}
    out: dict[str, Any] = {}
    record = []
    fs = a.full_scale
    if fs is None or ("full_scale" in before and before["full_scale"] == fs):
        k = _ratio(rated_current(m), rated_current(REF_MOTOR))
        fs = 25.0 * k if k is not None else 25.0
        fs = min(max(fs, 1e-6), 1e6)  # within the field's range (a machine at its ends)
        out["full_scale"] = fs
        record.append(("full_scale", fs, "25 A x I_N / I_N of Table I (sensors sized for the "
                       "machine)" if k is not None else "25 A (no rated current)"))
    if a.noise is None or ("noise" in before and before["noise"] == a.noise):
        out["noise"] = ADC_NOISE_FS * fs
        record.append(("noise", out["noise"], f"{ADC_NOISE_FS:g} x full_scale"))
    if not out:
        return a if not a.derived else dataclasses.replace(a, derived=())
    return dataclasses.replace(a, **out, derived=tuple(record))


def plant_of(s: Any) -> dict[str, float]:
    """The plant quantities (inverter and ADC) the design from the motor reads."""
    return {"t_dead": s.inverter.t_dead, "u_dc": s.inverter.u_dc, "noise": s.adc.noise}


def if_swing(m: MotorPars, i_start: float) -> float:
    """The amplitude of the rotor's speed swing about the forced angle on
    I/f, mechanical rad/s: the forced current's torque K = k_t i_start holds
    the rotor like a pendulum of stiffness K (per electrical rad) and natural
    frequency sqrt(n_p K / J); the start places the current 30 deg from the
    rotor's equilibrium at worst (smd_drive.h), so the rotor swings by
    pi/6 rad electrical, pi/6 sqrt(n_p K / J) / n_p in speed (undamped: the
    current control removes the resistance's damping)."""
    k = m.k_t * i_start
    if not (k > 0.0 and math.isfinite(k)):
        return 0.0
    return math.pi / 6.0 * math.sqrt(m.n_p * k / m.J) / m.n_p


def source_voltage_error(m: MotorPars, c: ControllerCfg, *, T_sp: float,
                         plant: dict[str, float], compensated: bool = False
                         ) -> tuple[float, float, float]:
    """(total, dead time, noise): the voltage error, V, of the back EMF a
    sensorless source estimates near zero current. Dead time: the
    fundamental of the uncompensated per-leg error t_dead / T_sp u_dc, a
    square wave, (4 / pi) t_dead / T_sp u_dc (the compensation removes it
    only outside its linear zone, which a lightly loaded machine at low
    speed sits in; `compensated`: DTC_RESIDUAL of it). ADC noise: the SMDO's
    disturbance estimate reads the current noise sigma through L_s / T_sp
    and filters it to its bandwidth
    w_c: sigma L_s / T_sp sqrt(w_c T_sp / 2) (one standard deviation),
    counted three times."""
    u_dt = 4.0 / math.pi * plant["t_dead"] / T_sp * plant["u_dc"]
    if compensated:
        u_dt *= DTC_RESIDUAL
    u_n = 3.0 * plant["noise"] * m.L_s / T_sp * math.sqrt(min(c.w_c * T_sp, 2.0) / 2.0)
    return u_dt + u_n, u_dt, u_n
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


def _uses(c: ControllerCfg, get: Any = None) -> dict[str, str | None]:
    """For each derived field: None if the composition uses it, else why not
    (`get(name)`: a field's value as resolved so far)."""
    get = get or (lambda n: getattr(c, n))
    smdo = c.current == "robust_dbpc" or c.position == "smdo_emf"
    sensorless = c.position != "encoder"
    if_enter = get("w_M_if_enter")
    if_ = c.start == "if" or (sensorless and (if_enter is None or if_enter > 0.0))
    t_dc = get("t_dead_comp")
    no_smdo = None if smdo else "no SMDO (current and position do not use it)"
    return {
        "L_s_hat": None, "R_s_hat": None, "psi_r_hat": None, "i_max": None,
        "speed_bw": None if c.speed_loop else "speed_loop = false",
        "w_lpf": None if c.position == "smdo_emf" else "position is not smdo_emf",
        "rls_t_half": None if c.rls_i_inj > 0.0 else "no R_s tracker (rls_i_inj = 0)",
        "J_hat": None if c.speed_loop else "speed_loop = false",
        "psi_r_pi": None if c.speed_loop else "speed_loop = false",
        "w_c": no_smdo, "lambda_min": no_smdo, "rho": no_smdo,
        "w_M_max": None if c.position == "smdo_emf" else "position is not smdo_emf",
        "i_start": None if if_ else "no I/f (start and w_M_if_enter)",
        "a_M_start": None if if_ else "no I/f (start and w_M_if_enter)",
        "w_M_handover": None if if_ else "no I/f (start and w_M_if_enter)",
        "w_M_if_enter": None if sensorless else "position is the encoder",
        "t_dead_comp": None,
        "i_dtc": None if (t_dc is None or t_dc > 0.0) else "t_dead_comp = 0",
        "a_M_ref": None if c.speed_loop else "speed_loop = false",
        "t_dwell": None if (sensorless and if_) else "no return to I/f and handover",
        "t_chatter": None if (sensorless and if_) else "no return to I/f and handover",
        "t_hunt": None if c.speed_loop else "speed_loop = false",
        "w_M_track": None if c.speed_loop else "speed_loop = false",
        "t_track": None if c.speed_loop else "speed_loop = false",
        "t_forced": None if if_ else "no I/f (start and w_M_if_enter)",
        "osc_i": None,
    }


def derive(name: str, m: MotorPars, c: ControllerCfg, *, T_sp: float, lcl: Any = None,
           adc_full_scale: float = math.inf, resolved: dict[str, Any] | None = None,
           plant: dict[str, float] | None = None) -> tuple[Any, str]:
    """(value, source) of field `name` derived from motor `m` for controller
    `c` (whose other derived fields are in `resolved`, by name)."""
    r = resolved or {}
    get = lambda n: r.get(n, getattr(c, n))  # noqa: E731
    ref = REF_MOTOR
    if name == "w_c":
        # Table I's 1500 rad/s, raised where the SMDO's filter (36) would not be stable
        # to twice rated speed (the drive's w_M_max): |1 - w_c T + j w T| < 1 with
        # w = 2 n_p w_M_N / W_MAX_MARGIN needs w_c T >= 1 - sqrt(1 - (w T)^2) (a 7-pole-
        # pair 15,000 r/min motor at 40 kHz: 7,400 rad/s; with 1500 its angle swung by
        # 22 deg RMS at 3/4 of rated speed, at status 0)
        v = REFERENCE["w_c"]
        q = 2.0 * m.n_p * m.w_M_N * T_sp / W_MAX_MARGIN
        if q >= 1.0:
            return 0.5 / T_sp, ("0.5 / T_sp (no w_c keeps the SMDO's filter stable to twice "
                                "rated speed at this T_sp: w_M_max is limited instead)")
        need = (1.0 - math.sqrt(1.0 - q * q)) / T_sp
        if need > v:
            return need, ("the SMDO's filter (36) stable to twice rated speed "
                          f"(|1 - w_c T + j 2 w_N T / {W_MAX_MARGIN:g}| = 1), above Table I's "
                          f"{v:g}")
        return v, "Table I's 1500 rad/s (its filter (36) stable to twice rated speed)"
    if c.w_c is None:
        c = dataclasses.replace(c, w_c=get("w_c"))
    if name in ("L_s_hat", "R_s_hat", "psi_r_hat", "J_hat", "psi_r_pi"):
        src = {"L_s_hat": "L_s", "R_s_hat": "R_s", "psi_r_hat": "psi_r", "J_hat": "J",
               "psi_r_pi": "psi_r"}[name]
        v = getattr(m, src)
        if name == "psi_r_pi" and v <= 0.0:
            return REFERENCE_MODEL["psi_r_pi"], ("reference: motor.psi_r = 0 gives no speed-loop "
                                                 "gain to tune for")
        return v, f"motor.{src}"
    if name in ("speed_bw", "w_lpf"):
        ref_v = {"speed_bw": 60.0, "w_lpf": 100.0}[name]
        k = _ratio(m.T_N / (m.J * m.w_M_N), ref.T_N / (ref.J * ref.w_M_N))
        if k is None:
            return ref_v, "reference: no rated torque"
        k_c = min(max(k, SPEED_BW_MIN_RATIO), SPEED_BW_MAX_RATIO)
        # the speed filter stays below a third of the SMDO's filter w_c
        k_c = min(k_c, c.w_c / (3.0 * 100.0)) if c.w_c > 0 else k_c
        k_c = 1.0 if k_c == 1.0 else k_c
        return ref_v * k_c, (f"{ref_v:g} rad/s x T_N / (J w_M_N) over Table I's (the same "
                             f"load-step dip), within [{SPEED_BW_MIN_RATIO:g}, "
                             f"{SPEED_BW_MAX_RATIO:g}] and w_lpf <= w_c / 3")
    if name == "rls_t_half":
        if c.position != "smdo_emf" or not c.speed_loop:
            return 0.02, "20 ms"
        v = math.pi / (RLS_BW_RATIO * get("speed_bw"))
        v = min(max(v, RLS_MIN_HALF * T_sp), 0.02)
        return v, (f"pi / ({RLS_BW_RATIO:g} speed_bw) within [{RLS_MIN_HALF} T_sp, 20 ms] "
                   "(the speed loop does not follow the square wave; smd_rls.h)")
    if name in ("lambda_min", "rho"):
        k = _ratio(rated_emf(m) / m.L_s, rated_emf(ref) / ref.L_s)
        if k is None:
            return REFERENCE[name], "reference: motor.psi_r = 0 (no rated back EMF)"
        v, why = REFERENCE[name] * k, "scaled by E_N / L_s (rated back EMF over inductance)"
        if name == "rho":
            # the SMDO's error loop, l + lambda_min / rho (1/s, eq. (21), (39)), faster
            # than the stator's own pole R_s / L_s by RHO_POLE: slower, its disturbance
            # estimate ran away (issue 23's 1 ohm / 50 uH micro motor, R_s / L_s = 20,000
            # 1/s against 5,400: |u_d_hat| 11.7 V for an EMF of 0.1 V; at 20,000 it held)
            # (within the discrete loop's stability, (l + lambda_min / rho) T_sp < 2,
            # at half of it: a stator faster than that is named by the check)
            need = min(RHO_POLE * m.R_s / m.L_s, 1.0 / T_sp)
            lam = get("lambda_min")
            # (v > 0: a flux of 5e-324 Wb scales rho to 0.0, which divided here: issue 23's
            # Hypothesis run, a ZeroDivisionError out of Scenario())
            if lam > 0.0 and v > 0.0 and c.l + lam / v < need:
                v, why = lam / (need - c.l), (f"{why}, limited so that l + lambda_min / rho is "
                                             f"{RHO_POLE:g} R_s / L_s (the SMDO's error loop "
                                             "faster than the stator)")
        return v, why
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
        if name == "i_start":
            why = "scaled by I_N = T_N / k_t (rated current)"
            if v > get("i_max"):
                v, why = get("i_max"), "scaled by I_N, limited to i_max"
            # the rotor's swing on I/f grows as sqrt(i_start) (if_swing), and the handover
            # must clear it (SWING_MARGIN): a current whose swing puts the handover beyond
            # HANDOVER_MAX w_M_N would keep the drive on I/f at every speed the profile asks
            # (a 10 pole-pair hub motor: 33 A, a handover at 313 r/min, rated 300; issue 23)
            s1 = if_swing(m, 1.0)
            ratio = HANDOVER_MAX * m.w_M_N / (SWING_MARGIN * s1) if s1 > 0.0 else math.inf
            # (squared: beyond 1e150 it is no bound; a float's square would overflow)
            cap = ratio * ratio if ratio < 1e150 else math.inf
            if v > cap:
                v, why = cap, (f"{why}, limited so that {SWING_MARGIN:g} x the rotor's speed "
                               f"swing on I/f is {HANDOVER_MAX:g} w_M_N (the handover's bound)")
            # the voltage the I/f current needs at standstill, R_s i_start, within
            # IF_VOLTAGE of what the modulator has (u_dc / sqrt 3): beyond it the current
            # loop saturates and the forced current's direction is lost (a 1 ohm micro
            # motor on 12 V: 8.3 A asked, 6.9 V available; issue 23)
            u_cap = IF_VOLTAGE * (plant or DEFAULT_PLANT)["u_dc"] / math.sqrt(3.0)
            if m.R_s * v > u_cap:
                v, why = u_cap / m.R_s, (f"{why}; limited so that R_s i_start is "
                                         f"{IF_VOLTAGE:g} u_dc / sqrt 3 (the voltage the "
                                         "modulator has)")
            return v, why
        return v, "scaled by I_N = T_N / k_t (rated current)"
    if name == "a_M_start":
        k = _ratio(m.T_N / m.J, ref.T_N / ref.J)
        if k is None:
            return REFERENCE[name], "reference: motor.P_N = 0 (no rated torque)"
        k_w = _ratio(m.w_M_N, ref.w_M_N)
        if k_w is not None and k_w < k:
            return REFERENCE[name] * k_w, ("scaled by w_M_N (the handover speed in 50 ms), "
                                           "below the T_N / J scaling")
        return REFERENCE[name] * k, "scaled by T_N / J (rated torque over inertia)"
    plant = plant or DEFAULT_PLANT
    if name == "t_dead_comp":
        return plant["t_dead"], "inverter.t_dead (the inverter's dead time)"
    if name in ("w_M_if_enter", "w_M_handover"):
        if m.psi_r <= 0.0:
            return REFERENCE_UNUSED[name], "reference: motor.psi_r = 0 (no back EMF)"
        u_err, u_dt, u_n = source_voltage_error(m, c, T_sp=T_sp, plant=plant)
        w_emf = EMF_MARGIN_ENTER * u_err / (m.n_p * m.psi_r)
        why = (f"{EMF_MARGIN_ENTER:g} x the voltage error of the source's EMF "
               f"({u_dt:.3g} V dead time + {u_n:.3g} V ADC noise) over n_p psi_r")
        t_dc = get("t_dead_comp")
        w_cap = HANDOVER_MAX * m.w_M_N / HANDOVER_RATIO
        if w_emf > w_cap and (t_dc is None or t_dc > 0.0):
            # a drop as large as the EMF over most of the speed range (issue 23's micro
            # motor at 2 us, 8 % of its 40 kHz period: the rule above hands over at 1.96
            # w_M_N, and the drive never leaves its forced start): with the dead time
            # compensated, the source needs a quarter of it (DTC_RESIDUAL); the return
            # then where the handover is half rated speed, or the residual's speed above it
            u_res = source_voltage_error(m, c, T_sp=T_sp, plant=plant, compensated=True)[0]
            w_emf = max(w_cap, EMF_MARGIN_ENTER * u_res / (m.n_p * m.psi_r))
            why = (f"{why}, limited to where the handover is {HANDOVER_MAX:g} w_M_N, above "
                   f"{EMF_MARGIN_ENTER:g} x the compensated dead time's residual "
                   f"({DTC_RESIDUAL:g} of it) + the noise over n_p psi_r")
        w_floor = IF_ENTER_MIN * m.w_M_N
        enter = max(w_emf, w_floor)
        if w_emf < w_floor:
            why = (f"{IF_ENTER_MIN:g} w_M_N (above the {EMF_MARGIN_ENTER:g} x {u_err:.3g} V "
                   "of the source's voltage error)")
        if name == "w_M_if_enter":
            return enter, why
        hand = max(HANDOVER_RATIO * (get("w_M_if_enter") or enter),
                   REFERENCE[name] * _ratio(m.w_M_N, ref.w_M_N))  # type: ignore[operator]
        swing = if_swing(m, get("i_start"))
        if SWING_MARGIN * swing > hand:
            return SWING_MARGIN * swing, (
                f"{SWING_MARGIN:g} x the rotor's speed swing about the forced angle on I/f "
                f"({swing / RPM:.0f} r/min: 30 deg at sqrt(n_p k_t i_start / J)), above 0.1 "
                f"w_M_N and {HANDOVER_RATIO:g} x w_M_if_enter")
        return hand, (f"the larger of 0.1 w_M_N and {HANDOVER_RATIO:g} x w_M_if_enter "
                      "(the return to I/f's hysteresis)")
    if name == "a_M_ref":
        a_t = A_REF_TORQUE * m.k_t * get("i_max") / m.J
        if c.position == "smdo_emf":
            lag = A_REF_LAG * m.w_M_N
            what = f"{A_REF_LAG:.0%} of rated speed"
            if_enter = get("w_M_if_enter")
            if if_enter and A_REF_LAG_IF * if_enter < lag:
                lag = A_REF_LAG_IF * if_enter
                what = (f"{A_REF_LAG_IF:g} w_M_if_enter (the return to I/f sees the speed "
                        "before the rotor reaches zero)")
            a_l = lag * get("w_lpf")
            if a_l < a_t:
                return a_l, (f"the SMDO's speed estimate (low-pass w_lpf) lags by {what} "
                             f"(below {A_REF_TORQUE:g} k_t i_max / J)")
        return a_t, f"{A_REF_TORQUE:g} k_t i_max / J (half the acceleration of the current limit)"
    if name == "t_dwell":
        if c.position == "smdo_emf":
            return 4.0 / get("w_lpf"), "4 / w_lpf (the settling of the SMDO's speed estimate)"
        return 0.02, "20 ms (7 time constants of the PLL of eq. (50) at 351 Hz)"
    if name == "t_chatter":
        return max(0.5, 20.0 * get("t_dwell")), "20 t_dwell, at least 0.5 s"
    if name == "t_hunt":
        return HUNT_TAU / get("speed_bw"), (f"{HUNT_TAU:g} / speed_bw ({HUNT_TAU:g} time constants "
                                            "of the speed loop)")
    if name == "w_M_track":
        return TRACK_REL * m.w_M_N, f"{TRACK_REL:g} w_M_N"
    if name == "t_track":
        torque = m.k_t * get("i_max")
        if not (torque > 0.0 and math.isfinite(torque)):
            return 0.0, "off: no torque at the current limit (motor.psi_r or i_max)"
        if get("a_M_ref") and get("a_M_ref") > 0.0:
            t_c = m.J * get("w_M_track") / (m.k_t * get("i_max"))
            return 0.1 + 4.0 * t_c, ("0.1 s + 4 J w_M_track / (k_t i_max) (the reference is "
                                     "slew-limited: the PI saturates only to recover a lag)")
        t_rev = 2.0 * m.J * m.w_M_N / (m.k_t * get("i_max"))
        return 0.1 + 2.0 * t_rev, ("0.1 s + twice the time a reversal from +w_M_N to -w_M_N "
                                   "takes at the current limit (2 J w_M_N / (k_t i_max))")
    if name == "t_forced":
        a = get("a_M_start")
        t_ramp = 2.0 * get("w_M_handover") / a if a and a > 0 else 0.0
        return 2.0 * t_ramp + 2.0 * get("t_dwell") + 0.1, (
            "twice the I/f ramp from -w_M_handover to +w_M_handover at a_M_start, plus 2 "
            "t_dwell + 0.1 s")
    if name == "osc_i":
        i_n = rated_current(m)
        i_n = i_n if math.isfinite(i_n) else 1.0
        return OSC_REL_N * i_n + OSC_NOISE * plant["noise"], (
            f"{OSC_REL_N:g} I_N + {OSC_NOISE:g} adc.noise")
    if name == "k_p_i":
        return c.current_bw * (lcl.L1 + lcl.L2o + get("L_s_hat")), \
            "current_bw (lcl.L1 + lcl.L2o + L_s_hat)"
    if name == "k_i_i":
        return c.current_bw * get("R_s_hat"), "current_bw R_s_hat"
    raise KeyError(name)


# the model values standing in where the motor gives none (Table I)
REFERENCE_MODEL = {"psi_r_pi": REF_MOTOR.psi_r}
#: the value a field the composition does not use keeps (the yang2018 drive's)
REFERENCE_UNUSED = {**REFERENCE, "J_hat": REF_MOTOR.J, "psi_r_pi": REF_MOTOR.psi_r,
                    "speed_bw": 60.0, "w_lpf": 100.0, "rls_t_half": 0.02,
                    "w_M_if_enter": 0.0, "t_dead_comp": DEFAULT_PLANT["t_dead"],
                    "a_M_ref": 0.0, "t_dwell": 0.0, "t_chatter": 1.0, "t_hunt": 1.0,
                    "w_M_track": 0.1 * REF_MOTOR.w_M_N, "t_track": 0.0, "t_forced": 0.0}


def resolve(c: ControllerCfg, m: MotorPars, *, T_sp: float, lcl: Any = None,
            adc_full_scale: float = math.inf,
            plant: dict[str, float] | None = None) -> ControllerCfg:
    """`c` with every motor-derived field that is unset (None), or still at
    the value an earlier resolution derived, derived from motor `m` (and the
    filter `lcl`); the others kept. The result's ``derived`` lists the
    derived ones as (name, value, source)."""
    if not (isinstance(c.derived, tuple) and all(
            isinstance(t, tuple) and len(t) == 3 and t[0] in DERIVED_FIELDS for t in c.derived)):
        raise ParameterError(f"controller.derived = {c.derived!r}: the record of the values "
                             "derived from the motor is kept by the code; leave it out")
    before = {n: (v, src) for n, v, src in c.derived}
    out: dict[str, Any] = {}
    record = []
    for name in DERIVED_FIELDS:
        uses = _uses(c, lambda n: out.get(n, getattr(c, n)))
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
                              resolved=out, plant=plant)
            new, src = _within_range(name, new, src)
        out[name] = new
        record.append((name, new, src))
    hand = out.get("w_M_handover", c.w_M_handover)
    if_enter = out.get("w_M_if_enter")
    if "w_M_handover" not in out and if_enter and hand is not None and if_enter >= hand:
        # the user's handover speed: the derived return to I/f stays below it
        out["w_M_if_enter"] = hand / HANDOVER_RATIO
        record = [(n, hand / HANDOVER_RATIO, f"w_M_handover / {HANDOVER_RATIO:g} (the "
                   "hysteresis below the handover set in [controller])") if n == "w_M_if_enter"
                  else (n, v, src) for n, v, src in record]
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


#: current_bw T_sp above which the current PI's loop, delayed 1.5 samples, loses its phase
#: margin (1.5 w_c T_sp of phase: 43 deg at 0.5; Table I's 2,500 rad/s at 100 us: 0.25)
CURRENT_BW_T_MAX = 0.5


def override_warnings(c: ControllerCfg, m: MotorPars, *, T_sp: float, lcl: Any = None,
                      adc_full_scale: float = math.inf,
                      plant: dict[str, float] | None = None) -> list[str]:
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
        ref, src = derive(name, m, c, T_sp=T_sp, lcl=lcl, adc_full_scale=adc_full_scale,
                          plant=plant)
        if src.startswith("reference") or not (ref > 0.0 and math.isfinite(ref)):
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
    hand = c.w_M_handover
    if uses.get("w_M_handover") is None and hand is not None and hand >= m.w_M_N > 0.0:
        # (issue 23's micro motor at 2 us, before the residual rule: the drive ran its
        # whole profile on I/f, 78 deg off, at status 0)
        out.append(f"controller.w_M_handover = {hand:.4g} rad/s is at or above rated speed "
                   f"(w_M_N = {m.w_M_N:.4g} rad/s): below it the drive runs on its forced start "
                   "(I/f), the rotor's angle unknown, and hands over to the sensorless source "
                   "only above it; check inverter.t_dead, inverter.u_dc and motor.psi_r")
    if _ratio(rated_current(m), 1.0) is None:
        # (no torque constant: a flux of 0, or one so small that T_N / k_t overflows)
        out.append(f"motor.psi_r = {m.psi_r:g} Wb gives no rated current (T_N / (1.5 n_p "
                   "psi_r)): the controller's current limits and start current are yang2018 "
                   "Table I's, not this motor's; give the motor's flux linkage")
    # (invented motors at the default 10 kHz: a 16-pole 12 kr/min outrunner, a 2-pole 100 kr/min
    # spindle ended in overcurrent, a coreless motor in start_failed, nothing pointing at T_sp)
    w_lim = c.w_M_max
    if c.position == "smdo_emf" and w_lim is not None and 0.0 < w_lim < m.w_M_N:
        out.append(f"controller.w_M_max = {w_lim:.4g} rad/s, the sensorless speed limit, is "
                   f"below rated speed (w_M_N = {m.w_M_N:.4g} rad/s): at T_sp = {T_sp:g} s the "
                   "SMDO's filter (36) turns too far a sample above it, and the drive cannot "
                   "follow the rotor's angle at rated speed; sample faster (a shorter T_sp)")
    if (c.position == "smdo_emf" or c.current in ("dbpc", "robust_dbpc")) and \
            m.R_s * T_sp > m.L_s:
        out.append(f"the stator's time constant L_s / R_s = {m.L_s / m.R_s:.3g} s is shorter "
                   f"than the sample, T_sp = {T_sp:g} s: the deadbeat control's and the SMDO's "
                   "one-sample models (yang2018 eq. (8), (35), forward Euler) overshoot such a "
                   f"stator; sample faster (T_sp below {m.L_s / m.R_s:.3g} s)")
    if c.current == "pi" and c.current_bw * T_sp > CURRENT_BW_T_MAX:  # (a servo at 1 ms)
        out.append(f"controller.current_bw = {c.current_bw:g} rad/s is {c.current_bw * T_sp:.3g} "
                   f"/ T_sp (T_sp = {T_sp:g} s): the current PI's loop, delayed 1.5 samples, "
                   f"keeps its phase margin up to {CURRENT_BW_T_MAX:g} / T_sp "
                   f"({CURRENT_BW_T_MAX / T_sp:.4g} rad/s); a lower current_bw or a shorter T_sp")
    rated = rated_voltage(m, lcl.L1 + lcl.L2o if lcl is not None else 0.0)  # (1 H L1: 311 kV)
    u_max = (plant or DEFAULT_PLANT)["u_dc"] / math.sqrt(3.0)
    if rated > u_max:
        at, lk = (" through the LCL filter (lcl.L1 + lcl.L2o in series)", " and lcl.L1, lcl.L2o") \
            if lcl is not None else ("", "")
        out.append(f"the motor's rated point (I_N = {rated_current(m):.3g} A at w_M_N = "
                   f"{m.w_M_N:.4g} rad/s) needs {rated:.3g} V at the inverter{at} and it has "
                   f"{u_max:.3g} V (inverter.u_dc / sqrt 3): rated torque at rated speed is out of"
                   " reach: a run asking for it ends below its reference, in a fault when more "
                   "than controller.w_M_track below (speed_tracking), and a start without the "
                   f"voltage it needs fails; check motor.R_s, L_s, psi_r, P_N, w_M_N, "
                   f"inverter.u_dc{lk}")
    return out


def rated_voltage(m: MotorPars, L_series: float = 0.0) -> float:
    """The rated point's voltage amplitude, V: i_q = I_N at w = n_p w_M_N, steady (SPMSM), |(R_s
    + j w (L_s + L_series)) j I_N + j w psi_r|, L_series a filter's (0 without a rated current)."""
    i_n = rated_current(m)
    if not (i_n and i_n > 0.0 and math.isfinite(i_n)):
        return 0.0
    w = m.n_p * m.w_M_N
    return math.hypot(w * (m.L_s + L_series) * i_n, m.R_s * i_n + w * m.psi_r)


def unset(c: ControllerCfg, keep: set[str] | frozenset[str] = frozenset()) -> ControllerCfg:
    """`c` with every motor-derived field (except those in `keep`) unset, so
    that a scenario with another motor derives them anew."""
    return dataclasses.replace(c, derived=(), **{n: None for n in DERIVED_FIELDS
                                                 if n not in keep})


