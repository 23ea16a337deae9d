"""yao2022: the LCL-filtered 100 kr/min drive and the operating points of
Sec. VII as scenarios (the motor and filter of Table II, :data:`BASE`, one
builder a figure), with the constants the experiments share.
:mod:`smodrive.scenarios.yao2022` runs the experiments and re-exports every
name here.

Plant: Table II; fan load fitted to Table IV; the values the paper does not
give (inertia, ADC error, noise, controller gains, start-up) are the
documented assumptions of :data:`BASE` and docs/assumptions.md. The ADC
scaling error and the PWM harmonics arise from the models (per-phase ADC
gains, regular-sampled carrier PWM), not from injected sinusoids.
"""

from __future__ import annotations

import dataclasses
import math

from ..model import (
    RPM,
    AdcCfg,
    ControllerCfg,
    InverterCfg,
    LclFilterPars,
    LoadCfg,
    MotorPars,
    Profile,
    Scenario,
)
from .common import SeedStats
from .yao2022_metrics import SETTLE, WINDOW

# Table II; J and B are not given (assumed), the fan load is fitted to
# Table IV (i_q = 30 A at 100 kr/min: 1.5 * 0.0012 * 30 / (10472 rad/s)^2 =
# 4.9e-10 N m s^2), and P_N is that fan load's power at the rated speed.
MOTOR = MotorPars(R_s=0.023, L_s=24e-6, psi_r=0.0012, n_p=1, J=1e-5, B=0.0, P_N=560.0,
                  w_M_N=100e3 * RPM)


# ADC scaling error (assumed; the paper gives none): +-1 % on phases a, b of
# both current sensors; noise and range assumed (docs/assumptions.md).
ADC = AdcCfg(gain=(1.01, 0.99, 1.0), gain_i1=(1.01, 0.99, 1.0), noise=0.02, bits=12,
             full_scale=60.0)


# exact, noiseless, unquantised current sensors (the paper's simulations)
IDEAL_ADC = dataclasses.replace(ADC, gain=(1.0, 1.0, 1.0), gain_i1=(1.0, 1.0, 1.0), noise=0.0,
                                bits=0)


# The drive of Fig. 1: PI current control with decoupling (gains assumed),
# the sliding-mode observer + PLL of eq. (48)-(50), speed PI on the model
# 1.5 n_p^2 psi / J; the observer's model is the plant's (Table II).
CONTROLLER = ControllerCfg(
    current="pi", position="lcl_smo_pll", start="running",
    L_s_hat=MOTOR.L_s, R_s_hat=MOTOR.R_s, psi_r_hat=MOTOR.psi_r,
    k_p_i=0.35, k_i_i=600.0, R_v=0.0, emf_ff=True,
    decouple="measured",  # as reproduced (docs/assumptions.md: at 100 kr/min and no load it oscillates)
    speed_bw=60.0, J_hat=MOTOR.J, psi_r_pi=MOTOR.psi_r, i_max=45.0,
    i_start=15.0, a_M_start=5e3 * RPM, w_M_handover=5e3 * RPM, t_dead_comp=0.0,
    w_M_if_enter=0.0, a_M_ref=0.0,  # the paper's drive: no return to I/f, references unshaped
)


BASE = Scenario(
    name="yao2022.base", T_sp=50e-6, duration=0.5, motor=MOTOR, lcl=LclFilterPars(),
    inverter=InverterCfg(u_dc=65.0, pwm="carrier", t_dead=0.0), adc=ADC,
    load=LoadCfg(k_fan=4.9e-10), controller=CONTROLLER,
)


SPEEDS = (30e3, 60e3, 100e3)


TAG = {30e3: "30k", 60e3: "60k", 100e3: "100k"}


# a claim on a peak of a noisy run is judged on this percentile over the ADC
# noise seeds of common.SEEDS (nearest rank: the 9th of 10)
PCT = 90.0


def seed_fields(st: SeedStats) -> dict:
    """The fields of `{text.seeds}`: what a claim over seeds reports."""
    return dict(n_seeds=len(st), median=st.median, worst=st.worst, worst_seed=st.worst_seed,
                pct=PCT)


def steady(n: float, law: str = "proposed", name: str | None = None, **kw) -> Scenario:
    return BASE.replace(
        name=name or f"yao2022.steady.{law}.{TAG.get(n, int(n))}",
        duration=SETTLE + WINDOW,
        w_M0=n * RPM,
        w_M_ref=Profile.const(n * RPM),
        controller=dataclasses.replace(BASE.controller, law=law, **kw),
    )


INJ_W = 1.0  # s, each averaging window (before and during the injection)


INJ_T = 0.2 + INJ_W  # +5 A on gamma from here (the start transient settled)


# the paper's readings are good to +-0.005 A on each of two currents over 5 A
INJ_RESOLUTION = 2 * 0.005 / 5.0


# Uncompensated dead time that makes the simulated reading of (60) at 30
# kr/min the paper's 0.018 rad (fitted once by hand: 30, 35 and 40 ns read
# 0.0160, 0.0182 and 0.0204 rad); the Fig. 10 claims report what it gives
# at 60 and 100 kr/min (docs/errata.md Y13).
FIG10_T_DEAD = 35e-9


def fig10_scenario(n: float, t_dead: float = 0.0) -> Scenario:
    """Steady state at n r/min, +5 A on gamma at INJ_T; `t_dead`: that much
    dead time in the inverter, not compensated."""
    s = steady(n, name=f"yao2022.fig10.{TAG[n]}").replace(
        duration=INJ_T + 0.05 + INJ_W, i_d_ref=Profile.steps(0.0, (INJ_T, 5.0)))
    if t_dead:
        s = s.replace(name=f"{s.name}.dead_time",
                      inverter=dataclasses.replace(s.inverter, t_dead=t_dead)
                      ).with_controller(t_dead_comp=0.0)
    return s


# the reaching laws compared in Table V: id label and equations
LAWS = {"tde17": ("baseline", "(61)-(63) of ref. [17]"), "proposed": ("proposed", "(33)-(35)")}


# r/min per s after the handover (assumed; the paper gives none): 80 % of the
# fastest ramp the 65 V bus allows at 100 kr/min (docs/assumptions.md)
FIG14_RATE = 8e3


# the ramp rates of the peak-against-rate curve (ideal sensors), r/min per s
FIG14_RATES = (4e3, 6e3, 8e3, 10e3, 12e3, 14e3, 16e3, 20e3)


def fig14_scenario(ideal: bool = False, rate: float | None = None) -> Scenario:
    """0 -> 100 kr/min at `rate` r/min per s after the handover (None:
    FIG14_RATE); `ideal`: exact, noiseless, unquantised current sensors (the
    paper's Fig. 14 is a MATLAB simulation)."""
    rate = FIG14_RATE if rate is None else rate
    t_up = 1.1 + 95e3 / rate
    name = "yao2022.fig14.ideal" if ideal else "yao2022.fig14"
    return BASE.replace(
        name=name if rate == FIG14_RATE else f"{name}.{rate / 1e3:g}k_per_s", duration=t_up + 0.3,
        w_M0=0.0, controller=dataclasses.replace(BASE.controller, start="if"),
        w_M_ref=Profile((0.0, 1.1, t_up), (5e3, 5e3, 100e3)).scaled(RPM), log_stride=2,
        adc=IDEAL_ADC if ideal else ADC,
    )


def fig19_scenario() -> Scenario:
    # torque-current step 10 -> 15 A at 0.05 s (speed loop off, fan load)
    n0 = math.sqrt(10.0 * 1.5 * 0.0012 / 4.9e-10) / RPM  # fan equilibrium at 10 A
    return BASE.replace(
        name="yao2022.fig19", duration=0.35, w_M0=n0 * RPM, w_M_ref=Profile.const(n0 * RPM),
        controller=dataclasses.replace(BASE.controller, speed_loop=False),
        i_q_ref=Profile.steps(10.0, (0.05, 15.0)),
    )


def fig22_scenario() -> Scenario:
    # The paper's drive has no loss-of-lock or hunting protection: with
    # smodrive's (t_lock = 20 ms, hunt_max = 4) most seeds stop in the safe
    # state at zero speed (fig22_protected_scenario), which is the protection
    # working, not the observer the figure shows.
    return BASE.replace(name="yao2022.fig22", duration=2.6, w_M0=30e3 * RPM,
                        w_M_ref=Profile((0.0, 0.2, 2.2), (30e3, 30e3, -30e3)).scaled(RPM),
                        log_stride=2,
                        controller=dataclasses.replace(BASE.controller, t_lock=0.0,
                                                       hunt_max=0))


def fig22_protected_scenario() -> Scenario:
    """Fig. 22 with the loss-of-lock protection on (the default t_lock)."""
    return fig22_scenario().replace(name="yao2022.fig22.protected",
                                    controller=BASE.controller)


def fig23_scenario(observer: str) -> Scenario:
    position = {"linear": "lcl_linear", "smo": "lcl_smo_pll"}[observer]
    return steady(60e3, name=f"yao2022.fig23.{observer}", position=position,
                  C1_hat_ratio=2.0).replace(duration=0.4)


# the observer's capacitance over the real one at which the statement gives
# the predicted bias (the curve through Fig. 23's 2 C)
FIG23_RATIOS = (1.25, 1.5, 1.75, 2.0, 2.5)


# what the largest costs on the Cortex-M4F are, for the claims' reasons
TABLE6_COSTS = {
    "smd_lcl_smo_model": "interpolating all 113 floats of the observer model between "
                         "speed-table entries",
    "smd_lcl_smo_predict": "the observer prediction (9), (16)",
    "smd_lcl_smo_reach": "the switching function and reaching law",
    "reduce": "sin and cos", "smd_sinf": "sin and cos", "smd_cosf": "sin and cos",
    "smd_bandpass_set": "recomputing both band-pass filters' coefficients for the speed",
    "harmonic.isra.0": "rotating the disturbance to 2 f_e and 3 f_e",
    "smd_pll_step": "the PLL (48)", "smd_atan2f": "the atan2 of the position error (47)",
    "atan_pos": "the atan2 of the position error (47)",
}
