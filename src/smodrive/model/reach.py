"""What a run's speeds can reach (part of :meth:`Scenario.check_run`): the
sampled drive's electrical Nyquist speed, the SMDO's sensorless speed limit
and the speed the DC link reaches without field weakening. An invented 3,000
r/min servo asked for 1e7 r/min ran without a word before, and ended 100 %
off its reference with status 0, its warning blaming an unsettled loop."""

from __future__ import annotations

import math

from .fields import RPM, ParameterError


def _peak(s) -> tuple[str, str, float]:
    """The key, the verb and the speed (rad/s, mechanical) of the run's
    fastest: the initial speed or the reference's largest value."""
    w_ref = max(s.w_M_ref.y, key=abs)
    if abs(s.w_M0) > abs(w_ref):
        return "w_M0", "=", float(s.w_M0)
    return "w_M_ref", "reaches", float(w_ref)


def check_reach(s) -> list[str]:
    """Scenario `s`'s speeds against what the drive can follow: raises
    ParameterError for an electrical speed at or beyond pi / T_sp (the
    rotor's angle turns half a turn or more a sample: no sampled drive
    follows it, whatever its position source); returns the warnings of a
    reference beyond the sensorless limit controller.w_M_max (smdo_emf: the
    speed estimate stops there, yang2018 eq. (45) as the core limits it) and
    of one whose back-EMF alone, n_p w psi_r, exceeds the voltage the
    inverter makes at every angle, u_dc / sqrt 3 (the drive keeps i_d_ref = 0,
    yang2018 Section II: no field weakening)."""
    key, verb, w = _peak(s)
    m, c, T = s.motor, s.controller, s.T_sp
    nyq = math.pi / (T * m.n_p)  # mechanical
    if abs(w) >= nyq:
        raise ParameterError(
            f"{key} {verb} {w / RPM:.4g} r/min: at T_sp = {T:g} s and n_p = {m.n_p:g} the "
            f"rotor's electrical angle would turn {m.n_p * abs(w) * T:.3g} rad a sample, at or "
            f"beyond pi, which no sampled drive follows; keep {key} (or {key}_rpm) within "
            f"+-{nyq / RPM:.4g} r/min (pi / (n_p T_sp)), or sample faster")
    out = []
    if key != "w_M_ref":
        return out
    if c.position == "smdo_emf" and c.w_M_max and abs(w) > c.w_M_max:
        out.append(
            f"w_M_ref reaches {w / RPM:.4g} r/min, beyond controller.w_M_max = "
            f"{c.w_M_max / RPM:.4g} r/min, the sensorless speed limit: the SMDO's speed estimate "
            "stops there, so the drive cannot follow the reference; the run ends off it, in "
            "speed_tracking or a lost lock")
    u_max = s.inverter.u_dc / math.sqrt(3.0)
    emf = m.n_p * abs(w) * m.psi_r
    if emf > u_max:
        # (an invented 24 V drone asked for 1.6 x rated, 16 V of EMF against 13.9 V, reached it
        # with the voltage on its limit 91 % of the time and i_d at -11 A: a run there may end
        # on the reference, below it, or in speed_tracking)
        out.append(
            f"w_M_ref reaches {w / RPM:.4g} r/min, where the back-EMF alone, n_p w psi_r = "
            f"{emf:.4g} V, exceeds the {u_max:.4g} V the inverter makes (inverter.u_dc / sqrt 3), "
            "and the drive has no field weakening (i_d_ref = 0): beyond about "
            f"{u_max / (m.n_p * m.psi_r) / RPM:.4g} r/min (without load) it runs on its voltage "
            "limit, where the current is what the limit leaves (a negative i_d, field "
            "weakening nobody asked for), not what the controller asks; it may reach the "
            "reference or end below it, in speed_tracking when more than controller.w_M_track "
            "below")
    return out
