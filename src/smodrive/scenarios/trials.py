"""The usual profile on any motor, and whether a run is right or says why.

A new user's first runs of a motor (issue 18): sensorless robust DBPC
(yang2018's SMDO position) started by I/f from rest, speed steps to +50 %
and +100 % of rated speed, a rated load step (brake on, then off), a
reversal through zero to -50 % and -100 %. Every controller value is derived
from the motor (:mod:`smodrive.model.derive`); the profile's segments
scale with the motor's reference slew time (rated speed over the derived
``a_M_ref``), so a flywheel and a servo run the same sequence.

:func:`judge` classifies a run: ``reached`` (the speed within 2 % of the
final reference over the last tenth of the last segment and the angle error
within 10 deg RMS there), ``fault`` (it ends in a named fault), or
``silent`` (neither: a run that ends wrong with no fault, the worst outcome
smodrive can have; the tests require none).

Example
-------
>>> from smodrive.scenarios import trials
>>> from smodrive.model import Scenario
>>> s = trials.profile_scenario(Scenario())  # Table I
>>> [round(y / trials.RPM) for y in s.w_M_ref.y][:4]
[0, 750, 750, 1500]
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..engine import Result, fault_names
from ..model import RPM, LoadCfg, Profile, Scenario

#: the usual profile: (reference as a fraction of rated speed, segments it lasts)
STEPS = ((0.5, 2), (1.0, 2), ("load on", 2), ("load off", 1), (-0.5, 2), (-1.0, 2))
#: a run reaches its reference: speed within this fraction of it ...
SPEED_TOL = 0.02
#: ... and the angle error within this RMS, deg, over the end window
ANGLE_TOL_DEG = 10.0


def segment(s: Scenario) -> float:
    """One segment of the profile, s: twice the time the derived reference
    slew takes to rated speed (without a slew, a_M_ref = 0: the time the
    rotor takes at the current limit, J_hat w_M_N / (k_t i_max)), plus ten
    speed-loop time constants, at least 0.3 s."""
    c = s.controller
    if c.a_M_ref and c.a_M_ref > 0:
        t_ramp = s.motor.w_M_N / c.a_M_ref
    else:
        t_ramp = c.J_hat * s.motor.w_M_N / (1.5 * s.motor.n_p * c.psi_r_pi * c.i_max)
    return max(0.3, 2.0 * t_ramp + 10.0 / c.speed_bw)


def profile_scenario(base: Scenario, seed: int = 1, T_sp: float | None = None) -> Scenario:
    """`base`'s plant (motor, inverter, ADC) under sensorless robust DBPC
    with an I/f start, on the usual profile, ADC noise seed `seed`, sampled
    at `T_sp` (None: `base`'s own; before 2026-11-27 always 100 us, which ran
    a 40 kHz motor file at 10 kHz). Behind
    an LCL filter the drive is yao2022's instead (current PI, the
    sliding-mode observer and PLL), with the I/f start and its decoupling
    chosen for the filter (controller.decouple = "auto")."""
    T_sp = base.T_sp if T_sp is None else T_sp
    if base.load != LoadCfg():
        # (a fan motor's file ran the profile without its fan, "reached", and nothing said so)
        warnings.warn(f"{base.name}: the usual profile runs its own load (the rated brake on "
                      "and off) in place of the scenario's [load] (" + ", ".join(
                          f"{f.name} = {getattr(base.load, f.name)!r}"
                          for f in dataclasses.fields(LoadCfg)
                          if getattr(base.load, f.name) != getattr(LoadCfg(), f.name))
                      + "): not part of this run", UserWarning, stacklevel=2)
    s = base.replace(T_sp=T_sp, warm_start=False, w_M0=0.0, theta_r0=0.0,
                     adc=dataclasses.replace(base.adc, seed=seed),
                     load=LoadCfg(), name=f"{base.name}.profile")
    s = s.with_controller(**(dict(current="robust_dbpc", position="smdo_emf")
                             if base.lcl is None else
                             dict(current="pi", position="lcl_smo_pll", decouple="auto",
                                  w_M_if_enter=None, t_dwell=None, t_chatter=None)),
                          start="if")
    seg = segment(s)
    w_n, t_n = s.motor.w_M_N, s.motor.T_N
    t, y = [0.0, 0.0], [0.0, STEPS[0][0] * w_n]
    tb, yb = [0.0], [0.0]
    now = STEPS[0][1] * seg
    for what, n in STEPS[1:]:
        if isinstance(what, str):
            tb += [now, now]
            yb += [yb[-1], t_n if what == "load on" else 0.0]
        else:
            t += [now, now]
            y += [y[-1], what * w_n]
        now += n * seg
    return s.replace(duration=now, w_M_ref=Profile(tuple(t), tuple(y)),
                     load=LoadCfg(T_brake=Profile(tuple(tb), tuple(yb))),
                     log_stride=max(1, int(round(now / T_sp / 20000))))


@dataclass(frozen=True)
class Outcome:
    """What one run of the profile did."""

    verdict: str              # "reached", "fault" or "silent"
    speed_error: float        # |mean speed - reference| / |reference| at the end
    angle_rms_deg: float      # RMS angle error at the end
    faults: tuple[str, ...]   # the final fault word's names
    phase: int                # start-up phase at the end (0 forced, 2 source)

    def __str__(self) -> str:
        what = self.verdict if self.verdict != "fault" else "fault: " + ", ".join(self.faults)
        return (f"{what} (speed {100 * self.speed_error:.2f} % off, angle "
                f"{self.angle_rms_deg:.2f} deg RMS at the end)")


def judge(r: Result) -> Outcome:
    """Right (reached), wrong with a named fault, or wrong in silence."""
    s = r.scenario
    t = r.t
    end = t >= t[-1] - 0.1 * segment(s)
    ref = r["w_M_ref"][-1]
    err = abs(float(np.mean(r["w_M"][end])) - ref) / max(abs(ref), 1e-9)
    ang = math.degrees(float(np.sqrt(np.mean(r.theta_error[end] ** 2))))
    names = tuple(fault_names(r.faults.final))
    if names:
        verdict = "fault"
    elif err <= SPEED_TOL and ang <= ANGLE_TOL_DEG:
        verdict = "reached"
    else:
        verdict = "silent"
    return Outcome(verdict, err, ang, names, int(r["phase"][-1]))


def sensorless_angle_rms(r: Result) -> float:
    """RMS angle error, rad, over the logged samples on the sensorless source
    (start-up phase 2), without the first such sample after a change of
    phase: the log's phase is the drive's at the end of its step, its angle
    the one the step used, so the step that hands over logs phase 2 with the
    forced start's angle (80-90 deg off on a loaded I/f start; on a run
    logged every 12th sample it counted, or not, by where the stride fell:
    one such sample moved a profile's RMS by +87 %)."""
    ph = np.asarray(r["phase"])
    m = ph == 2
    m[1:] &= ph[:-1] == 2
    return float(np.sqrt(np.mean(r.theta_error[m] ** 2)))


def random_profile(base: Scenario, rng: np.random.Generator, duration: float = 60.0,
                   n_changes: int = 20, seed: int = 1, T_sp: float | None = None
                   ) -> Scenario:
    """`base`'s plant under sensorless robust DBPC with an I/f start, for
    `duration` seconds of random operation within the rated envelope:
    `n_changes` speed steps (uniform in [-w_M_N, w_M_N]) and as many brake
    steps (uniform in [0, T_N]) at random times (a false-trip test: every
    run is one the drive can do)."""
    s = profile_scenario(base, seed, T_sp)
    T_sp = s.T_sp
    w_n, t_n = s.motor.w_M_N, s.motor.T_N
    ts = np.sort(rng.uniform(0.5, duration, n_changes))
    ws = rng.uniform(-1.0, 1.0, n_changes) * w_n
    t, y = [0.0, 0.0], [0.0, float(ws[0])]
    for tk, wk in zip(ts[1:], ws[1:]):
        t += [float(tk), float(tk)]
        y += [y[-1], float(wk)]
    tl = np.sort(rng.uniform(0.5, duration, n_changes))
    ls = rng.uniform(0.0, 1.0, n_changes) * t_n
    tb, yb = [0.0], [0.0]
    for tk, lk in zip(tl, ls):
        tb += [float(tk), float(tk)]
        yb += [yb[-1], float(lk)]
    return s.replace(duration=duration, w_M_ref=Profile(tuple(t), tuple(y)),
                     load=LoadCfg(T_brake=Profile(tuple(tb), tuple(yb))),
                     log_stride=max(1, int(round(duration / T_sp / 2000))))
