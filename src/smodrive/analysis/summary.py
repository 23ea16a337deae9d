"""summary.json of a run (``smodrive run``): the means of its last 20 %,
its faults, and whether it held its operating point there."""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from ..engine import FAULT_BITS, LATCHED_FAULTS
from ..model import RPM
from .metrics import HOLD_SHARE, LIMIT_TOL, _limit_share, _voltage_share, operating_point, window_slice


def _phase_end(s, r) -> str:
    """The start-up phase of the last logged row: "forced" (I/f), "encoder"
    (the encoder hand-over, or an encoder position source) or "observer"
    (a sensorless position source)."""
    k = int(r["phase"][-1])
    source = "encoder" if s.controller.position == "encoder" else "observer"
    return {0: "forced", 1: "encoder", 2: source}.get(k, str(k))


def _final_fault_t(r) -> float | None:
    """When the final fault (its latched bits, or the whole final word if
    none is latched) was set for the last time, from the logged ``fault``
    channel: the time of the first row of the last stretch of rows that
    hold those bits (to the log stride); None without a final fault, or
    when the log's last row does not hold it."""
    final = int(r.faults.final)
    if not final:
        return None
    latched = sum(FAULT_BITS[n] for n in LATCHED_FAULTS if n in FAULT_BITS)
    bits = (final & latched) or final
    on = (r["fault"].astype(np.int64) & bits) == bits
    if not on[-1]:
        return None
    off = np.flatnonzero(~on)
    return float(r.t[int(off[-1]) + 1 if off.size else 0])


#: a speed that ends farther than this share of its reference (or of rated speed, for a
#: reference near zero) from it is off its reference (the usual profile's judge: 2 %)
OFF_REFERENCE = 0.02


def _slew_end(s, n: int = 4000) -> float:
    """When the slew-limited speed reference (controller.a_M_ref, from the
    initial speed w_M0, as the core's starts) last arrives at the reference,
    to duration / n; 0 without the slew limit. (A constant reference of 1e7
    r/min, 1,385 s of ramp at a_M_ref, had counted as reached at once: its
    run, still on its ramp, was said to have a loop that had not settled.)"""
    a = s.controller.a_M_ref
    if not a:
        return 0.0
    dt = s.duration / n
    w, end, step = s.w_M0, 0.0, a * dt
    for k in range(n + 1):
        y = s.w_M_ref(k * dt)
        if abs(y - w) > step:
            w += math.copysign(step, y - w)
            end = (k + 1) * dt
        else:
            w = y
    return end


def off_reference(s, summary: dict[str, Any]) -> str | None:
    """Why a run that ends without a fault ends away from its speed
    reference, or None (no speed loop, a fault, a reference that still
    changes or ramps in the last 20 % of the run, or within OFF_REFERENCE):
    the drive's speed_tracking fault trips only beyond w_M_track (10 % of
    rated), so a drive held a few % below its reference by the DC link ends
    at status 0 (invented 250 V and 260 V drives 7 % below rated speed). The
    cause from what the summary measured: the forced start at the end (a
    reference below the handover speed), the voltage on its limit, the
    current on its limit, else a speed loop that has not settled."""
    c = s.controller
    if not c.speed_loop or summary["ends_in_fault"] or summary["speed_error_rpm_last_20pct"] is None:
        return None
    t0 = 0.8 * s.duration
    ref = s.w_M_ref
    # (the reference's last change, and its slew-limited ramp after it)
    t_change, step = max(((t1, abs(b - a)) for t1, a, b in zip(ref.t[1:], ref.y, ref.y[1:])
                          if a != b), default=(0.0, 0.0))
    if t_change + (step / c.a_M_ref if c.a_M_ref else 0.0) > t0 or _slew_end(s) > t0:
        return None
    err = summary["speed_error_rpm_last_20pct"] * RPM
    scale = max(abs(ref.y[-1]), 0.1 * s.motor.w_M_N)
    if abs(err) <= OFF_REFERENCE * scale:
        return None
    if summary["phase_end"] == "forced":
        why = (f"it ends on its forced start (I/f), below the handover speed "
               f"controller.w_M_handover = {c.w_M_handover / RPM:.4g} r/min, open loop")
    elif summary["voltage_limit_share_last_20pct"] > HOLD_SHARE:
        why = ("its voltage is on the modulator's limit: the reference or the load is beyond "
               "what inverter.u_dc reaches")
    elif summary["current_limit_share_last_20pct"] > HOLD_SHARE:
        why = "its current is at controller.i_max: the load is beyond the drive's torque"
    else:
        why = "its speed loop has not settled (controller.speed_bw, or the load's inertia)"
    return (f"the speed ends {100 * err / abs(scale):+.1f} % off its reference "
            f"({summary['speed_rpm_mean_last_20pct']:.5g} against "
            f"{summary['speed_ref_rpm_mean_last_20pct']:.5g} r/min over the last 20 % of the run) "
            f"without a fault (speed_tracking trips beyond controller.w_M_track = "
            f"{c.w_M_track / RPM:.4g} r/min): {why}")


#: the stretch before a run's first fault that fault_context reads, s
FAULT_WINDOW = 0.2
#: the share of its current's torque (1.5 n_p psi_r i_start) an I/f start carries against an
#: opposing load: the start places its current where it gives half, then the rotor swings.
#: Measured on two invented motors (a 320 V servo: 0.67 started, 0.72 and 0.70 started with a
#: larger i_start, 0.76 and 0.88 pulled out; a 700 V direct drive: 0.76 pulled out, 0.70 with
#: a larger i_start started): tests/test_fault_context.py
START_CARRY = 0.7
#: the share of its reference below which the current did not follow it (fault_context)
FOLLOW_SHARE = 0.8


def fault_context(s, r) -> str | None:
    """What the drive was doing in the FAULT_WINDOW before its first fault,
    when that names the cause better than the fault itself: its current
    reference on controller.i_max, or its voltage on the modulator's limit,
    in more than HOLD_SHARE of the samples; None otherwise (no fault, too
    few samples). An invented servo braked beyond its torque ended in
    speed_tracking, and an overloaded sensorless drive in start_failed (a
    lost lock, then an I/f restart that cannot carry the load), each named
    by the fault the overload led to, not by the overload."""
    t1 = r.faults.t_first
    if t1 is None:
        return None
    c, mot = s.controller, s.motor
    if int(r.faults.first) & FAULT_BITS["overcurrent"]:
        # the trip and where it comes from (a 3 kW motor's P_N written in kW, I_N 10.6 mA,
        # tripped at 0.3 ms naming no threshold)
        trip = c.i_trip if c.i_trip is not None else 2.5 * c.i_max
        how = ("controller.i_trip" if c.i_trip is not None else
               f"2.5 controller.i_max (i_max = {c.i_max:.4g} A"
               + (f", derived from the rated current I_N = {mot.T_N / mot.k_t:.4g} A: motor.P_N "
                  "/ motor.w_M_N over 1.5 n_p psi_r)" if "i_max" in {d[0] for d in c.derived}
                  else ")"))
        return f"a phase current passed the overcurrent trip, {trip:.4g} A: {how}"
    t0 = max(float(r.t[0]), t1 - FAULT_WINDOW)
    m = window_slice(r, t0, t1)
    if m.stop - m.start < 2:
        return None
    w = r["w_M"][m] / RPM
    fell = f"; the speed went from {w[0]:.5g} to {w[-1]:.5g} r/min"
    t_max = 1.5 * mot.n_p * mot.psi_r * c.i_max  # (the drive's torque at i_max)
    # (i_max derived and limited by the sensors: the setting the user changed is named)
    why = next((d[2] for d in c.derived if d[0] == "i_max" and "full_scale" in d[2]), None)
    lim = f"the drive's torque at controller.i_max = {c.i_max:.4g} A" \
          + (f" ({why})" if why else "") + \
          f", 1.5 n_p psi_r i_max = {t_max:.4g} Nm (an overload)"
    # the plant's load torque, which the simulation knows (a 3 T_N brake stalled a direct
    # drive in 45 ms, 18 % of the window on i_max, then failed its I/f restart against it)
    T_L = r["T_L"][m]
    k = int(np.argmax(np.abs(T_L)))
    if abs(T_L[k]) > t_max:
        return (f"in the {t1 - t0:.3g} s before the first fault the load's torque reached "
                f"{abs(T_L[k]):.4g} Nm (the plant's T_L at t = {r.t[m][k]:.4g} s), beyond "
                + lim + fell)
    t_start = 1.5 * mot.n_p * mot.psi_r * (c.i_start or 0.0)  # (the forced start's at most)
    forced = np.mean(r["phase"][m] == 0) > 0.5
    if forced and c.start == "if" and abs(T_L[k]) > 0.5 * t_start:
        # (an invented direct drive started against an opposing 1.2 T_N, 0.76 of its start
        # current's torque: start_failed, unnamed)
        need = abs(T_L[k]) / (START_CARRY * 1.5 * mot.n_p * mot.psi_r)
        return (f"in the {t1 - t0:.3g} s before the first fault the drive was on its forced "
                f"start (I/f) and the load's torque reached {abs(T_L[k]):.4g} Nm, "
                f"{abs(T_L[k]) / t_start:.2f} of the {t_start:.4g} Nm its current "
                f"controller.i_start = {c.i_start:.4g} A gives (1.5 n_p psi_r i_start); an I/f "
                f"start carries about {START_CARRY:g} of that: "
                + (f"no I/f start carries this load (it would need {need:.4g} A, beyond "
                   f"controller.i_max = {c.i_max:.4g} A): start with the encoder, or unloaded"
                   if need > c.i_max else
                   f"controller.i_start of {need:.4g} A or more (at most i_max = "
                   f"{c.i_max:.4g} A) starts it") + fell)
    i_share = _limit_share(r["i_d_ref"][m], r["i_q_ref"][m], (1.0 - LIMIT_TOL) * c.i_max)
    u_share = _voltage_share(r["u_cmd_alpha"][m], r["u_cmd_beta"][m], s.inverter.u_dc,
                             s.inverter.svm_limit == "hexagon")
    # the current that flowed against the one asked for: on the voltage limit it does not
    # follow (an invented 560 V servo on 280 V, i_q near 0 against 25 A asked, had been called
    # an overload at its rated load)
    ref = float(np.mean(np.abs(r["i_q_ref"][m])))
    follows = ref == 0.0 or float(np.mean(np.abs(r["i_q"][m]))) >= FOLLOW_SHARE * ref
    if u_share > HOLD_SHARE and (not follows or i_share <= HOLD_SHARE):
        return (f"in the {t1 - t0:.3g} s before the first fault its voltage was on the "
                f"modulator's limit in {100 * u_share:.0f} % of the samples"
                + ("" if follows else " and its current did not follow its reference")
                + f": the speed or the load asked for more than inverter.u_dc = "
                f"{s.inverter.u_dc:g} V reaches{fell}")
    if i_share > HOLD_SHARE:
        return (f"in the {t1 - t0:.3g} s before the first fault its current reference was on "
                f"controller.i_max = {c.i_max:.4g} A in {100 * i_share:.0f} % of the samples"
                ": the load asked for more than " + lim + fell)
    return None


def run_summary(s, r, plan) -> dict[str, Any]:
    """summary.json of a run: means over the last 20 % of the run (at least
    the last logged row), the control samples simulated and how the log was
    kept; the start-up phase at the end (``phase_end``: forced, encoder or
    observer); the speed-tracking error over the last 20 % (mean true speed
    minus mean reference, r/min, and that over the final reference's
    magnitude; null without the speed loop, the relative one also for a
    final reference of 0); the faults: the first (``first_fault``, its
    time ``first_fault_t``), the final (``final_fault``, ``ends_in_fault``)
    and when the final one was set (``final_fault_t``, from the log); the
    shares of the last 20 % with the voltage command on the modulator's limit
    and a current reference on controller.i_max
    (:func:`smodrive.analysis.metrics.operating_point`); ``off_reference``:
    why a run without a fault ends away from its speed reference (null when
    it does not: :func:`off_reference`); ``fault_context``: what the drive was
    doing before its first fault when that names its cause (an overload, the
    voltage limit; null otherwise: :func:`fault_context`)."""
    i0 = min(int(np.searchsorted(r.t, 0.8 * s.duration)), r.data.shape[0] - 1)
    op = operating_point(r, float(r.t[i0]), math.inf)
    last = dataclasses.replace(r, data=r.data[i0:])  # a view of those rows
    n_ref = last["w_M_ref"] / RPM
    err = rel = None
    if s.controller.speed_loop:
        err = float(np.mean(last.n_rpm) - np.mean(n_ref))
        ref_end = float(r["w_M_ref"][-1] / RPM)
        rel = err / abs(ref_end) if ref_end != 0.0 else None
    out = {
        "name": s.name,
        "samples": int(r.samples),
        "status": int(r.status),
        "speed_rpm_mean_last_20pct": float(np.mean(last.n_rpm)),
        "speed_estimate_rpm_mean_last_20pct": float(np.mean(last.n_hat_rpm)),
        "i_d_mean_last_20pct": float(np.mean(last["i_d"])),
        "i_q_mean_last_20pct": float(np.mean(last["i_q"])),
        "theta_error_rms_deg_last_20pct": float(np.degrees(np.sqrt(np.mean(
            last.theta_error ** 2)))),
        "speed_ref_rpm_mean_last_20pct": float(np.mean(n_ref)),
        "speed_error_rpm_last_20pct": err,
        "speed_error_rel_last_20pct": rel,
        "phase_end": _phase_end(s, r),
        "voltage_limit_share_last_20pct": float(op.u_limit_share),
        "current_limit_share_last_20pct": float(op.i_limit_share),
        **r.faults.as_dict(),
        "final_fault_t": _final_fault_t(r),
        "ends_in_fault": bool(r.faults.ends_in_fault),
        "faults_expected": bool(s.faults_expected),
        "log": plan.as_dict(),
    }
    out["off_reference"] = off_reference(s, out)
    out["fault_context"] = fault_context(s, r)
    return out
