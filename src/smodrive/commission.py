"""Commissioning (issue 23): the drive measures its own motor before it runs.

Steps 1-3, here, by the core's tests (``core/include/smodrive/smd_ident.h``):
the stator resistance R_s and the inverter's voltage drop u_0 (a DC current
on the alpha axis, a staircase of levels, a least-squares line u = R_s i +
u_0), the inductance on the d and q axes (a square wave on a DC bias, the
exact discrete stator model fitted to the averaged wave), the PM flux (an
I/f spin at a quarter and half of rated speed, checked by a coast), against
the simulated plant, with its ADC (gain, offset, noise,
quantisation), PWM, dead time and mechanics. The test sees the measured
currents and the DC-link voltage, never the plant's motor.

What the user gives is what a nameplate gives: the test current
(``i_test``, default half the rated current) and the DC-link voltage of the
scenario's inverter.
"""

from __future__ import annotations

import ctypes as ct
import dataclasses
import math
import warnings
from dataclasses import dataclass

import numpy as np

from .commission_lcl import N_HALF_LCL, lcl_inductance
from .commission_outcomes import MECH_OUTCOMES, OUTCOMES
from .engine import LATCHED_FAULTS, _ffi, fault_names
from .engine.run import Engine
from .model import ParameterError, Profile
from .model.derive import I_MAX_ADC, IF_VOLTAGE, rated_current
from .model.scenario import Scenario

#: the test's defaults (assumed: windows of 20 ms, a level waits 2 s at most, 10 levels)
T_WIN = 0.02
T_LEVEL_MAX = 2.0
LEVELS = 10
#: the longest the whole test may run, s
T_MAX = 30.0


@dataclass(frozen=True)
class RsResult:
    """R_s and the inverter's drop as the test measured them."""
    R_s: float          # ohm
    u_0: float          # V, the line's intercept (dead time and switch drops)
    r2: float           # the fit's R^2
    resid: float        # V, the fit's residual RMS
    outcome: str        # OUTCOMES
    t: float            # s, the test's length
    i_levels: tuple     # A, each level's mean current
    u_levels: tuple     # V, each level's mean applied voltage command
    T_sp: float = math.nan  # s, the sampling period the drop was measured at
    u_dc: float = math.nan  # V, the DC link it was measured on
    R_fit: float = math.nan  # ohm, the staircase's slope before the sampling's
                             # correction (sampled_current_correction; nan: none made)

    @property
    def ok(self) -> bool:
        return self.outcome == "ok"

    def t_dead(self, T_sp: float | None = None, u_dc: float | None = None) -> float:
        """The dead time whose compensation cancels the measured drop, s:
        along alpha phase a carries i and phases b and c -i/2, each leg
        loses t_d / T_sp u_dc against its current, (2/3)(1 + 1/2 + 1/2) =
        4/3 of it along alpha, so t_d = 3/4 u_0 T_sp / u_dc (the switches'
        own drops counted as dead time), with the period and DC link the
        drop was measured at (the defaults: the test's own). A drive at
        another period keeps that dead time in seconds: the period of the
        measurement, not the drive's (a tracker at 100 us given the drop
        measured at 50 us once compensated twice the dead time, R_s -44 %)."""
        T = self.T_sp if T_sp is None else T_sp
        u = self.u_dc if u_dc is None else u_dc
        return max(0.0, 0.75 * self.u_0 * T / u)


def i_test_max(s: Scenario) -> tuple[float, str]:
    """The largest test current for scenario `s`, A, and why: the rated current
    (steps 1 and 2 hold it at standstill for seconds), and step 3's spin, at
    K_SPIN times it, within the share I_MAX_ADC of the current sensors' range
    the drive keeps its own limit in (a current beyond the range reads as the
    full scale: the test's checks would not see it)."""
    i_n = rated_current(s.motor)
    lim, why = i_n, f"the rated current I_N = {i_n:.4g} A"
    fs = s.adc.full_scale
    if fs is not None and math.isfinite(fs) and I_MAX_ADC * fs / K_SPIN < lim:
        lim = I_MAX_ADC * fs / K_SPIN
        why = (f"{I_MAX_ADC / K_SPIN:g} adc.full_scale = {lim:.4g} A (step 3 spins at {K_SPIN:g} "
               f"i_test, within {I_MAX_ADC:g} of the sensors' range {fs:g} A)")
    return lim, why


def rs_config(s: Scenario, i_test: float | None = None) -> _ffi.IdentRsConfig:
    """The test's settings for scenario `s`: i_test (default half the rated
    current; at most i_test_max), the voltage limit u_dc / sqrt 3, the ramp,
    the windows."""
    lim, why = i_test_max(s)
    if i_test is None:
        i_test = 0.5 * rated_current(s.motor)
        if i_test > lim:
            warnings.warn(f"the test current i_test = {lim:.4g} A, not half the rated current "
                          f"({i_test:.4g} A): at most {why}", stacklevel=2)
            i_test = lim
    i_test = float(i_test)
    if not (math.isfinite(i_test) and 0.0 < i_test <= lim):
        raise ParameterError(f"i_test = {i_test!r} A is outside its valid range (0, {lim:.4g}] A: "
                             f"at most {why}")
    u_max = s.inverter.u_dc / math.sqrt(3.0)
    return _ffi.IdentRsConfig(T_sp=s.T_sp, i_test=i_test, u_max=u_max, t_win=T_WIN,
                              t_level_max=T_LEVEL_MAX, levels=LEVELS)


def bench(s: Scenario) -> Scenario:
    """The motor of `s` on the bench for commissioning: from standstill, with
    no load torque or brake (the scenario's profiles belong to its run; a fan
    load and the inertia stay, as they are part of the machine)."""
    return s.replace(w_M0=0.0, load=dataclasses.replace(s.load, T_brake=Profile.const(0.0),
                                                        T_ext=Profile.const(0.0)))


def _engine(s: Scenario) -> Engine:
    """The plant of `s` on the bench (its drive configured, never stepped)."""
    return Engine(bench(s))


def identify_rs(s: Scenario, i_test: float | None = None, engine: Engine | None = None
                ) -> RsResult:
    """Run the R_s test of the core against the plant of scenario `s` (from
    standstill, the scenario's initial angle, or where `engine` is) and
    return what it measured."""
    cfg = rs_config(s, i_test)
    p, st = _ffi.IdentRsParams(), _ffi.IdentRsState()
    rc = _ffi.lib.smd_ident_rs_init(ct.byref(p), ct.byref(cfg))
    if rc != 0:
        raise ParameterError(f"the R_s test refused its settings (smd_status {rc}): "
                             f"i_test = {cfg.i_test:g} A, T_sp = {cfg.T_sp:g} s")
    _ffi.lib.smd_ident_rs_reset(ct.byref(st))
    eng = engine or _engine(s)
    n_max = int(round(T_MAX / s.T_sp))
    n = int(_ffi.lib.smd_engine_run_ident_rs(eng._buf, ct.byref(p), ct.byref(st), n_max, None, 1))
    k = int(p.levels)
    return RsResult(R_s=float(st.R_s), u_0=float(st.u_0), r2=float(st.r2),
                    resid=float(st.resid), outcome=OUTCOMES.get(int(st.outcome), "?"),
                    t=n * s.T_sp, i_levels=tuple(float(x) for x in np.array(st.i_lv)[:k]),
                    u_levels=tuple(float(x) for x in np.array(st.u_lv)[:k]),
                    T_sp=s.T_sp, u_dc=s.inverter.u_dc)


#: step 2's defaults (assumed): a square wave of 8 samples each way, 400 periods averaged at
#: one bias (identify_ls; commission runs three levels, LS_LEVELS)
N_HALF = 8
PERIODS = 400


@dataclass(frozen=True)
class LsResult:
    """The inductance along one axis, as step 2 measured it."""
    axis: str           # "d" or "q"
    L: float            # H
    du: float           # V, the square wave's amplitude
    swing: float        # A, the triangle's swing
    outcome: str
    t: float            # s
    moved: float        # rad, how far the rotor turned during the test (electrical, true)
    L_series: float = math.nan  # H, the core's first-order fit (behind a filter: the filter's
    #                             inductances and the motor's in series, the capacitor aside)
    i_bias: float = math.nan    # A, the DC bias it was measured on
    levels: tuple = ()          # LsResult of each bias level (identify_ls_levels), or ()

    @property
    def ok(self) -> bool:
        return self.outcome == "ok"


#: step 2's bias levels (assumed), fractions of step 1's largest level (about half the rated
#: current), LS_PERIODS periods each: the inductance at three currents, as a saturating motor's
#: data sheet gives it. Downwards, each within the test's trip (3 x its bias) of the current
#: before it; no lower than half (at a quarter, phases b and c carry an eighth, near zero
#: against the ripple: Table I's L_d read +9 %). 3 x 80 periods: within 0.1 s of one level's 400
LS_LEVELS = (1.0, 0.75, 0.5)
LS_PERIODS = 80
#: twice the weighted mean's standard error (from the levels' scatter) within this share of
#: it, L_s's stated accuracy (docs/commissioning.md: +-5 %), or the result is not trusted
#: ("levels_disagree")
LS_AGREE = 0.05


def identify_ls_levels(s: Scenario, rs: RsResult, axis: str, i_max: float, engine: Engine
                       ) -> LsResult:
    """Step 2 on `axis` at each bias of LS_LEVELS x `i_max`. L weighs each
    level's by its swing squared (L's noise goes as the ADC's over the swing,
    a tenth of the bias); `levels` keeps each (a saturating stator's L falls
    with the current; the plant's does not). The first level not ok is the
    outcome."""
    runs = []
    for f in LS_LEVELS:
        r = identify_ls(s, rs, axis, f * i_max, engine, periods=LS_PERIODS)
        runs.append(r)
        if not r.ok:
            break
    t = sum(r.t for r in runs)
    moved = max(r.moved for r in runs)
    if not runs[-1].ok:  # (the levels stop at the first not ok)
        return dataclasses.replace(runs[-1], t=t, moved=moved, levels=tuple(runs))
    w = [r.swing ** 2 for r in runs]
    L = sum(wk * r.L for wk, r in zip(w, runs)) / sum(w)
    Ls = sum(wk * r.L_series for wk, r in zip(w, runs)) / sum(w)
    # (the weighted mean's standard error from the levels' scatter, sqrt(sum w^2 (L_k -
    # L)^2) / sum w: twice it beyond L's stated accuracy is not trusted; an invented 12 V
    # motor under 0.1 A of ADC noise read 0.144 / 0.113 / 0.109 mH for 0.16 and reported
    # L_q -12 % "ok". A stator whose L moves with its current scatters its levels too)
    se = math.sqrt(sum((wk * (r.L - L)) ** 2 for wk, r in zip(w, runs))) / sum(w)
    outcome = runs[0].outcome if L > 0.0 and 2.0 * se <= LS_AGREE * L else "levels_disagree"
    return dataclasses.replace(runs[0], L=L, L_series=Ls, t=t, moved=moved, levels=tuple(runs),
                               outcome=outcome)


def identify_ls(s: Scenario, rs: RsResult, axis: str, i_bias: float, engine: Engine,
                periods: int = PERIODS) -> LsResult:
    """Step 2 on `axis` ("d" or "q") with the bias i_bias along alpha, on the
    R_s and drop that step 1 measured, where `engine` is, averaging
    `periods` periods."""
    n_half = N_HALF if s.lcl is None else N_HALF_LCL
    cfg = _ffi.IdentLsConfig(T_sp=s.T_sp, R_s=max(rs.R_s, 0.0), u_0=max(rs.u_0, 0.0),
                             i_bias=i_bias, u_max=s.inverter.u_dc / math.sqrt(3.0), t_win=T_WIN,
                             axis={"d": 0, "q": 1}[axis], n_half=n_half, periods=periods)
    p, st = _ffi.IdentLsParams(), _ffi.IdentLsState()
    rc = _ffi.lib.smd_ident_ls_init(ct.byref(p), ct.byref(cfg))
    if rc != 0:
        raise ParameterError(f"the inductance test refused its settings (smd_status {rc})")
    _ffi.lib.smd_ident_ls_reset(ct.byref(st))
    th0 = _ffi.lib.smd_engine_rotor_angle(eng_buf := engine._buf)
    n = int(_ffi.lib.smd_engine_run_ident_ls(eng_buf, ct.byref(p), ct.byref(st),
                                             int(round(T_MAX / s.T_sp))))
    th1 = _ffi.lib.smd_engine_rotor_angle(eng_buf)
    moved = abs((th1 - th0 + math.pi) % (2 * math.pi) - math.pi)
    L = float(st.L)
    if s.lcl is not None and int(st.outcome) == 0:
        # behind an LCL filter the wave's response is the filter's and the motor's: the
        # motor's inductance by the filter's model (its data sheet's L1, C1, L2o)
        n2 = 2 * n_half
        w = np.array(st.acc_w[:n2]) / st.period
        L = lcl_inductance(s, rs.R_s, w - w.mean(), n_half, float(st.du))
    return LsResult(axis=axis, L=L, du=float(st.du), swing=float(st.swing),
                    outcome=OUTCOMES.get(int(st.outcome), "?"), t=n * s.T_sp, moved=moved,
                    L_series=float(st.L), i_bias=i_bias)


@dataclass(frozen=True)
class Commissioning:
    """Steps 1 and 2 on one plant: R_s and the drop, L_d and L_q."""
    rs: RsResult
    ld: LsResult | None
    lq: LsResult | None
    psi: "PsiResult | None" = None
    mech: "MechResult | None" = None

    @property
    def L_s(self) -> float:
        """The SPMSM's one inductance: the mean of L_d and L_q."""
        return 0.5 * (self.ld.L + self.lq.L)

    @property
    def ok(self) -> bool:
        return self.rs.ok and self.ld is not None and self.ld.ok and self.lq is not None \
            and self.lq.ok

    @property
    def t(self) -> float:
        return self.rs.t + sum(x.t for x in (self.ld, self.lq, self.psi, self.mech)
                               if x is not None)


def commission(s: Scenario, i_test: float | None = None, mechanics: bool = True,
               slow: float = 1.0) -> Commissioning:
    """R_s and the drop (step 1), L_d and L_q (step 2) at three levels of the test
    current, psi_r (step 3) on one plant from standstill; then, with
    `mechanics`, J and B (step 4) by the drive designed from them. `slow` (>= 1)
    runs step 3's spin and step 4's start and ramp that many times slower, for
    a load that much heavier than the defaults allow (step 3 ends "slipped")."""
    if not (math.isfinite(slow) and 1.0 <= slow <= 100.0):
        raise ParameterError(f"slow = {slow!r} is outside its valid range [1, 100]")
    eng = _engine(s)
    rs = identify_rs(s, i_test, eng)
    if not rs.ok:
        return Commissioning(rs, None, None)
    i_max = max(rs.i_levels)
    ld = identify_ls_levels(s, rs, "d", i_max, eng)
    lq = identify_ls_levels(s, rs, "q", i_max, eng) if ld.ok else None
    psi = mech = None
    if lq is not None and lq.ok:
        rs, ld, lq = sampled_current_correction(s, rs, ld, lq)
        L_s = 0.5 * (ld.L + lq.L)
        psi = identify_psi(s, rs, L_s, spin_current(s, rs), eng, slow)
        if psi.ok and mechanics:
            mech = identify_mech(s, rs.R_s, L_s, psi.psi,
                                 t_dead_comp=rs.t_dead(),
                                 u_0=max(rs.u_0, 0.0), slow=slow, J_spin=psi.J_spin)
    return Commissioning(rs, ld, lq, psi, mech)


#: the sampling's correction of R_s is made up to this share (beyond it the first-order model
#: is not to be trusted, and the slope is kept as fitted)
K_SAMPLE_MAX = 0.1


def sampled_current_correction(s: Scenario, rs: RsResult, ld: LsResult, lq: LsResult
                               ) -> tuple[RsResult, LsResult, LsResult]:
    """R_s, L_d and L_q corrected for where the current is sampled: the dead
    time moves each pulse's centre by t_d / 2 from the carrier's. The sample
    is off the period's mean by u t_d / (2 L_s), u = R_s i across the stator,
    so the staircase's slope is R_s (1 - R_s t_d / (2 L_s)) (step 1: the
    micro motor's slope -0.95 % a us, -1.0 % predicted); the square wave's
    voltage comes t_d / 2 late to each sample, so its exact discrete model
    reads b e^{R_s t_d / (2 L)}, and L e^{-R_s t_d / (2 L)} (step 2: the
    micro motor's L -0.5 to -1.8 % at 0.9-1.9 us, -0.9 to -1.9 % predicted).
    t_d from the measured drop, each level corrected as the result. Not
    behind an LCL filter (docs/commissioning.md)."""
    L_s = 0.5 * (ld.L + lq.L)
    k = rs.R_s * rs.t_dead() / (2.0 * L_s) if L_s > 0.0 else 0.0
    if s.lcl is not None or not (0.0 < k <= K_SAMPLE_MAX):
        return rs, ld, lq
    rs = dataclasses.replace(rs, R_s=rs.R_s / (1.0 - k), R_fit=rs.R_s)
    h = rs.R_s * rs.t_dead() / 2.0

    def fix(x: LsResult) -> LsResult:
        return dataclasses.replace(x, L=x.L * math.exp(h / x.L),
                                   levels=tuple(fix(v) for v in x.levels))
    return rs, fix(ld), fix(lq)


#: step 3's defaults (assumed): 25 % and 50 % of rated speed, reached in 2 s, held 0.5 s
#: each; a coast of 0.1 s; the current loop at a twentieth of the sampling rate (pi / (20 T_sp))
T_SPIN = 2.0
T_HOLD = 0.5
T_COAST = 0.1
#: step 3's spin current over step 1's largest level (assumed): twice, about the rated current
#: (at the level itself, half the rated current, yao2022's first ramp asked 95 % of its torque,
#: and its rotor slipped in 2 of 10 draws with issue 23's dead time; with 10 x their inertia the
#: 600 V, 20 mohm and micro motors' rotors slipped: they now measure psi_r within 0.8 %)
K_SPIN = 2.0

def spin_current(s: Scenario, rs: RsResult) -> float:
    """Step 3's current, A: K_SPIN times step 1's largest level, at most
    I_MAX_ADC of the current sensors' range and IF_VOLTAGE u_dc / sqrt 3
    across the measured R_s, the share the drive's own I/f start takes (the
    rest is for the EMF and w L_s i at the spin's speeds). (An invented 12 V gimbal motor, 6 ohm: twice its largest level
    needed 7.7 V of the 6.9 V the modulator has; the current fell short, the
    governor held the ramp at 1 % of its rate; "running" after 30 s.)"""
    i = K_SPIN * max(rs.i_levels)
    if rs.R_s > 0.0:
        i = min(i, IF_VOLTAGE * s.inverter.u_dc / math.sqrt(3.0) / rs.R_s)
    fs = s.adc.full_scale
    if fs is not None and math.isfinite(fs):
        # (within the sensors' share that i_test_max promises: step 1's levels reach 1.2
        # i_test, and a 48 V hub motor's spin ran at 5.35 A on 5 A sensors)
        i = min(i, I_MAX_ADC * fs)
    return i


#: step 3's governor (assumed): the ramp waits while the rotor takes more than this share of
#: the spin current's torque (smd_ident_psi_config.share_max)
SHARE_MAX = 0.7
#: step 3's stabiliser (assumed): its gain, rad/s (smd_ident_psi_config.w_damp)
W_DAMP = 2.0 * math.pi * 20.0


@dataclass(frozen=True)
class PsiResult:
    """The PM flux as step 3 measured it."""
    psi: float          # Wb, the result: at the higher speed (psi2), or coasting when shorted
    psi1: float         # Wb, at the lower speed
    psi2: float         # Wb, at the higher (= psi)
    psi_slope: float    # Wb, the slope between the two
    psi_coast: float    # Wb, coasting
    outcome: str
    t: float            # s
    w_coast: float = math.nan  # rad/s: the rotor's electrical speed coasting (the frame's: w2)
    J_spin: float = math.nan   # kg m^2: the inertia the second ramp saw (friction and load in)
    #: the coast shorted the stator (the inverter's drop over a fifth of the EMF): psi is the
    #: coast's, the holds its check (smd_ident.h)
    shorted: bool = False
    w_lim: float = 0.0  # rad/s, electrical: the frame's, where the voltage was first limited

    @property
    def ok(self) -> bool:
        return self.outcome == "ok"


def identify_psi(s: Scenario, rs: RsResult, L_s: float, i_spin: float, engine: Engine,
                 slow: float = 1.0) -> PsiResult:
    """Step 3 on the R_s, drop and L_s measured before, where `engine` is;
    its ramps `slow` times slower than T_SPIN."""
    w_n = s.motor.n_p * s.motor.w_M_N  # the nameplate's rated speed, electrical
    cfg = _ffi.IdentPsiConfig(T_sp=s.T_sp, R_s=max(rs.R_s, 0.0), L_s=L_s, u_0=max(rs.u_0, 0.0),
                              i_spin=i_spin, w1=0.25 * w_n, w2=0.5 * w_n,
                              a_spin=0.5 * w_n / (T_SPIN * slow), t_hold=T_HOLD,
                              t_coast=T_COAST,
                              w_cc=math.pi / (20.0 * s.T_sp), share_max=SHARE_MAX, w_damp=W_DAMP,
                              **({} if s.lcl is None else
                                 {"L1": s.lcl.L1, "C1": s.lcl.C1, "L2o": s.lcl.L2o}))
    p, st = _ffi.IdentPsiParams(), _ffi.IdentPsiState()
    rc = _ffi.lib.smd_ident_psi_init(ct.byref(p), ct.byref(cfg))
    if rc != 0:
        raise ParameterError(f"the flux test refused its settings (smd_status {rc})")
    _ffi.lib.smd_ident_psi_reset(ct.byref(st))
    n = int(_ffi.lib.smd_engine_run_ident_psi(engine._buf, ct.byref(p), ct.byref(st),
                                              int(round(T_MAX * slow / s.T_sp))))
    return PsiResult(psi=float(st.psi), psi1=float(st.psi1), psi2=float(st.psi2),
                     psi_slope=float(st.psi_slope), psi_coast=float(st.psi_coast),
                     outcome=OUTCOMES.get(int(st.outcome), "?"), t=n * s.T_sp,
                     w_coast=float(st.w_coast), J_spin=spin_inertia(s, st, i_spin),
                     shorted=bool(st.shorted), w_lim=float(st.w_lim))


def spin_inertia(s: Scenario, st, i_spin: float) -> float:
    """The inertia step 3's second ramp saw, kg m^2: the torque the rotor
    took, 1.5 n_p psi i_spin times its mean share, over the frame's mean
    acceleration, mechanical (smd_ident.h); a friction's and a load's torque
    count as inertia (an upper estimate), nan without a governed ramp."""
    n_p = s.motor.n_p
    if not (st.a_ramp > 0.0 and st.share_ramp > 0.0 and st.psi > 0.0):
        return math.nan
    return float(1.5 * n_p * n_p * st.psi * i_spin * st.share_ramp / st.a_ramp)


#: step 4's defaults (assumed): the drive's speed loop tuned for a guessed inertia, a rotor
#: that would reach rated speed in 0.1 s at rated torque, at a bandwidth of 20 rad/s (stable
#: for inertias 10 x either side of the guess); started by I/f to 40 % of rated speed, held
#: until T_STEP, the reference then ramped to 80 % in T_RAMP and held T_HOLD_MECH
J_GUESS_T = 0.1
SPEED_BW_MECH = 20.0
#: step 4's speed estimate's low-pass at least W_LPF_RAMP / T_RAMP (its lag a hundredth of the
#: ramp's span), at most w_c / 3 (at 31 rad/s, derived from a 60,000 r/min blower's inertia, the
#: lag turned the SMDO's filter (36) off the rotor: J +16 %, B +86 % read as ok)
W_LPF_RAMP = 100.0
T_STEP = 1.5
T_RAMP = 0.4
T_HOLD_MECH = 0.6
T_BIN = 0.02
#: ... and a coast at zero current after the hold (B from the deceleration, no torque to
#: measure; not with a fan load)
T_COAST_MECH = 0.4


#: step 4's handover (assumed): no lower than where the EMF is K_DROP times the inverter drop's
#: fundamental, and then reached by the forced start within T_START
K_DROP = 1.0
T_START = 1.2
#: ... and its acceleration asks at most this share of the start current's torque (the spin
#: governor's SHARE_MAX) of the inertia the drive is designed for (step 3's, else the guess)
K_START_TORQUE = 0.7


@dataclass(frozen=True)
class MechResult:
    """J and B as step 4 measured them."""
    J: float            # kg m^2
    B: float            # N m s/rad
    outcome: str        # "ok", "poor_fit", "not_settled", "no_sensorless_range", "voltage_limit" or
                        # "fault: <names>"
    t: float            # s
    K: float = 0.0      # N m s^2/rad^2: a fan load's K w_M |w_M| (fitted with one)
    B_ramp: float = math.nan  # N m s/rad: B from the ramp alone (the coast's is B)
    B_se: float = math.nan    # N m s/rad: B's standard error from the coast (nan: no coast)

    @property
    def ok(self) -> bool:
        return self.outcome == "ok"


#: step 4's ramp spans at least this share of rated speed (assumed), else the test is not
#: run ("no_sensorless_range": the drive's handover is too close to rated speed)
MIN_RAMP_MECH = 0.2
#: the share of the inverter's voltage, u_dc / sqrt 3, step 4's back EMF may take at its top
#: speed (mech_voltage_speed)
V_MECH = 0.8


def mech_room(sd: Scenario) -> bool:
    """Whether step 4's speeds (mech_speeds) leave its ramp MIN_RAMP_MECH of
    rated speed at least."""
    w1, w2 = mech_speeds(sd)
    return w2 - w1 >= MIN_RAMP_MECH * sd.motor.w_M_N


def mech_voltage_speed(sd: Scenario) -> float:
    """The fastest speed of step 4, mechanical rad/s, whose back EMF (with
    the measured flux, psi_r_hat) takes at most V_MECH of the voltage the
    inverter makes, u_dc / sqrt 3 (the rest for R_s i and w L_s i); inf
    without a flux."""
    psi = sd.controller.psi_r_hat
    if not psi or psi <= 0.0:
        return math.inf
    return V_MECH * sd.inverter.u_dc / math.sqrt(3.0) / (sd.motor.n_p * psi)


def mech_speeds(sd: Scenario) -> tuple[float, float]:
    """Step 4's two speeds, mechanical rad/s: 40 % and 80 % of rated speed,
    the first at least 1.25 times the drive's handover speed (below it the
    drive stays on its forced start, whose torque is not k_t i_q: the hub
    motor's handover is at half its rated speed), the second 40 % of rated
    above it, at most rated and mech_voltage_speed (a 12 V gimbal motor on
    5 V: 80 % of rated needed 3.5 V of EMF of the 2.9 V its inverter makes,
    and its drive faulted, blamed on the inertia), the first then lower, to
    40 % of rated below the second when the handover allows."""
    w_n, w_h = sd.motor.w_M_N, 1.25 * sd.controller.w_M_handover
    w2 = min(w_n, max(0.4 * w_n, w_h) + 0.4 * w_n, mech_voltage_speed(sd))
    return max(w_h, min(0.4 * w_n, w2 - 0.4 * w_n)), w2


def mech_scenario(s: Scenario, R_s: float, L_s: float, psi_r: float,
                  t_dead_comp: float | None = None, u_0: float = 0.0,
                  slow: float = 1.0, J_spin: float = math.nan) -> Scenario:
    """Step 4's run: the sensorless drive (robust DBPC, SMDO, I/f start) on
    the bench, designed from the measured R_s, L_s, psi_r and inertia (a
    guessed one without step 3's), on the reference of the test (:func:`mech_speeds`);
    `t_dead_comp`: the dead time step 1's drop gives (None: the scenario's
    own setting); `u_0`: that drop, V: the forced start hands over no lower
    than where the EMF is twice the drop's fundamental, (3/pi) u_0 (below,
    what the compensation misses of the drop misleads the observer: yao2022's
    motor behind its filter at 1.3 us of dead time lost its rotor right
    after a handover at 5 kr/min, where the EMF is 0.63 V against 2.1 V of
    drop), at most half the rated speed. `slow`: the start, the settling
    (T_STEP), the ramp (T_RAMP) and the guessed inertia that many times
    longer and heavier (a heavy load; the holds and the coast stay).
    `J_spin`: the inertia step 3's spin saw; the drive is designed for it
    (the start's acceleration, the speed loop and the supervision's times
    follow the inertia; nan: the guess)."""
    m = s.motor
    w_n = m.w_M_N
    t_step, t_ramp = T_STEP * slow, T_RAMP * slow
    t2 = t_step + t_ramp + T_HOLD_MECH + T_COAST_MECH

    def design(w1: float, w2: float) -> Scenario:
        sd = bench(s).replace(duration=t2, warm_start=False, theta_r0=0.0,
                              w_M_ref=Profile((0.0, 0.0, t_step, t_step + t_ramp),
                                              (0.0, w1, w1, w2)))
        # behind an LCL filter: yao2022's drive (current PI with active damping, the
        # sliding-mode observer and PLL), the filter's data sheet values as they are
        parts = (dict(current="robust_dbpc", position="smdo_emf") if s.lcl is None else
                 dict(current="pi", position="lcl_smo_pll", decouple="auto"))
        if t_dead_comp is not None:
            parts["t_dead_comp"] = min(t_dead_comp, 0.25 * s.T_sp)
        # the inertia: the one step 3's spin saw, else the guess
        J_hat = J_GUESS_T * slow * m.T_N / w_n
        if math.isfinite(J_spin) and J_spin > 0.0:
            J_hat = J_spin
        sd = sd.with_controller(**parts, start="if",
                                R_s_hat=R_s, L_s_hat=L_s, psi_r_hat=psi_r, J_hat=J_hat,
                                a_M_ref=(w2 - w1) / t_ramp,
                                speed_bw=SPEED_BW_MECH)
        # every value derived from the motor (the start's acceleration and current, the
        # handover, the supervision's times) from what the drive knows: the measured R_s,
        # L_s, psi_r and dead time and the guessed inertia, not the plant's (the true J
        # had set the start's acceleration and the tracking time: a leak of the truth)
        meas = dataclasses.replace(m, R_s=R_s, L_s=L_s, psi_r=psi_r, J=J_hat)
        inv = (sd.inverter if t_dead_comp is None else
               dataclasses.replace(sd.inverter, t_dead=min(t_dead_comp, 0.25 * s.T_sp)))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            known = sd.replace(motor=meas, inverter=inv)
        sd = sd.replace(controller=dataclasses.replace(known.controller, derived=()))
        c = sd.controller
        w_drop = K_DROP * 3.0 / math.pi * u_0 / (psi_r * m.n_p) if psi_r > 0.0 else 0.0
        if w_drop > c.w_M_handover:
            w_h = min(w_drop, 0.5 * w_n)
            sd = sd.with_controller(w_M_handover=w_h,
                                    a_M_start=max(c.a_M_start, w_h / (T_START * slow)))
            c = sd.controller
        # the forced start's acceleration within what its current can give the inertia
        # the drive is designed for (K_START_TORQUE of it; a preset's own value too:
        # yao2022's 5 kr/min/s asked 2 x its 15 A of yao2022's rotor with 10 x its inertia)
        a_cap = K_START_TORQUE * 1.5 * m.n_p * psi_r * c.i_start / J_hat
        if psi_r > 0.0 and c.a_M_start > a_cap:
            sd = sd.with_controller(a_M_start=a_cap)
        w_lpf = min(W_LPF_RAMP / t_ramp, c.w_c / 3.0)
        if s.lcl is None and c.w_lpf < w_lpf:
            sd = sd.with_controller(w_lpf=w_lpf)
        return sd

    sd = design(0.4 * w_n, 0.8 * w_n)
    if not mech_room(sd):
        return sd  # (no room for the test: identify_mech names it)
    w1, w2 = mech_speeds(sd)
    return sd if (w1, w2) == (0.4 * w_n, 0.8 * w_n) else design(w1, w2)


def identify_mech(s: Scenario, R_s: float, L_s: float, psi_r: float,
                  t_dead_comp: float | None = None, u_0: float = 0.0,
                  slow: float = 1.0, J_spin: float = math.nan) -> MechResult:
    """Step 4: the drive itself (the firmware code) runs the core's test
    (``smd_ident_mech``, smodrive/smd_ident.h), which gives it the speed
    reference (:func:`mech_speeds`: a speed, a ramp to the second, a hold)
    and fits the drive's torque, k_t i_q with k_t from the measured flux,
    passed through the low-pass its speed estimate has passed (w_lpf),
    against what it estimates of the speed (the SMDO's): from 0.5 s before
    the ramp, once the drive runs on its estimate (it waits for the end of
    the forced start: a heavy rotor's is long), T_BIN bins, T = J dw/dt + B w
    by least squares (viscous friction: a Coulomb term of its own would take
    most of B's share with two speed levels; the holds need not be steady: a
    heavy rotor is still settling there). Then, without a fan load, a coast
    of T_COAST_MECH at zero current (the drive in torque mode): B / J from
    the deceleration, with no torque to measure, and J from the ramp with
    it (the ramp's own B is kept as B_ramp). With a fan (the scenario's
    load.k_fan) its K w|w| is fitted on the ramp too, and no coast. The
    drive's own supervision stays on: a run that ends in a fault is named; a
    drive that never leaves its forced start is "not_settled"."""
    sd = mech_scenario(s, R_s, L_s, psi_r, t_dead_comp, u_0, slow, J_spin)
    if not mech_room(sd):
        short = mech_voltage_speed(sd) < s.motor.w_M_N
        return MechResult(math.nan, math.nan,
                          "voltage_limit" if short else "no_sensorless_range", 0.0)
    w1, w2 = mech_speeds(sd)
    # (with a fan the coast's deceleration is mostly the fan's, where B and K lean on each
    # other: yao2022's K came out -41 % from a 0.4 s coast, -3 % from the ramp alone)
    fan = s.load.k_fan > 0.0
    m = s.motor
    n_p = m.n_p
    cfg = _ffi.IdentMechConfig(T_sp=s.T_sp, k_t=1.5 * n_p * psi_r, n_p=n_p,
                               w1=w1 * n_p, w2=w2 * n_p, t_step=T_STEP * slow,
                               t_ramp=T_RAMP * slow, t_hold=T_HOLD_MECH, t_fit=0.5, t_bin=T_BIN,
                               w_lpf=sd.controller.w_lpf if s.lcl is None else 0.0,
                               fan=1 if fan else 0, t_coast=0.0 if fan else T_COAST_MECH)
    p, st = _ffi.IdentMechParams(), _ffi.IdentMechState()
    rc = _ffi.lib.smd_ident_mech_init(ct.byref(p), ct.byref(cfg))
    if rc != 0:
        raise ParameterError(f"the J and B test refused its settings (smd_status {rc})")
    _ffi.lib.smd_ident_mech_reset(ct.byref(st))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the estimates differ from the plant's values
        eng = Engine(sd)
    n = int(_ffi.lib.smd_engine_run_ident_mech(eng._buf, ct.byref(p), ct.byref(st),
                                               2 * int(round(sd.duration / s.T_sp)) + 2, None, 1))
    t = n * s.T_sp
    outcome = MECH_OUTCOMES.get(int(st.outcome), "?")
    if outcome == "fault":
        names = [n for n in fault_names(eng.faults().final) if n in LATCHED_FAULTS]
        return MechResult(math.nan, math.nan, "fault: " + ", ".join(names), t, math.nan)
    if outcome not in ("ok", "poor_fit"):
        return MechResult(math.nan, math.nan, outcome, t, math.nan)
    return MechResult(float(st.J), float(st.B), outcome, t, float(st.K), float(st.B_ramp),
                      float(st.B_se) if st.B_se >= 0.0 else math.nan)
