"""Shared helpers of the plant tests (test_plant.py: the SPMSM alone,
test_lcl_plant.py: behind the LCL filter; both are smodrive.engine.plant.Plant).

Conventions (amplitude-invariant Clarke, x = alpha + j beta):
  i_x = Re(i e^{-j 2 pi x / 3}),  leg x contributes (2/3) u_dc a^x while
  high, a = e^{j 2 pi / 3}.
"""

from __future__ import annotations

import cmath
import dataclasses
import math

import numpy as np

from smodrive.model import (
    AdcCfg,
    InverterCfg,
    LclFilterPars,
    LoadCfg,
    MotorPars,
    Scenario,
)
from smodrive.engine.plant import Plant, leg_edges
from smodrive.scenarios import yao2022

A = cmath.exp(2j * math.pi / 3)
EPS = np.finfo(float).eps

# ------------------------------------------------------------- scenarios --

# The plant sections of a Scenario, by the names of their fields.
_SECTIONS = {"motor": MotorPars, "lcl": LclFilterPars, "inverter": InverterCfg,
             "adc": AdcCfg, "load": LoadCfg}
_FIELDS = {name: {f.name for f in dataclasses.fields(cls)} for name, cls in _SECTIONS.items()}
_TOP = {f.name for f in dataclasses.fields(Scenario)} - set(_SECTIONS)


def vary(s: Scenario, **kw) -> Scenario:
    """`s` with plant fields changed by their own names, whatever section
    holds them (R_s, L1, pwm, gain_i1, k_fan, T_sp, w_M0, theta_r0, ...). Filter fields on a
    scenario without the filter add one (LclFilterPars defaults for the
    rest)."""
    top: dict = {}
    parts: dict[str, dict] = {name: {} for name in _SECTIONS}
    for k, v in kw.items():
        owner = [name for name, names in _FIELDS.items() if k in names]
        if owner:
            parts[owner[0]][k] = v
        elif k in _TOP:
            top[k] = v
        else:
            raise TypeError(f"no scenario or plant field named {k!r}")
    for name, changes in parts.items():
        if changes:
            cur = getattr(s, name)
            top[name] = (_SECTIONS[name](**changes) if cur is None
                         else dataclasses.replace(cur, **changes))
    return s.replace(**top)


# The SPMSM alone: yang2018 Table I machine, switching-cycle average, no dead
# time, exact ADC, initial state at rest in current (no warm start).
SPMSM = Scenario(inverter=InverterCfg(pwm="averaged", t_dead=0.0),
                 adc=AdcCfg(noise=0.0, bits=0), warm_start=False)

# yao2022 Table II behind its LCL filter (smodrive.scenarios.yao2022.BASE:
# motor, filter, 65 V, 20 kHz carrier PWM, fan load 4.9e-10 N m s^2, J 1e-5),
# with an exact ADC and zero initial electrical state.
TABLE2 = vary(yao2022.BASE, gain=(1.0, 1.0, 1.0), gain_i1=(1.0, 1.0, 1.0), noise=0.0, bits=0,
              full_scale=100.0, warm_start=False)


def plant_from(s: Scenario, **fields) -> Plant:
    """The Plant of `s` with fields of its C config (smd_plant_config)
    changed before init, e.g. an arbitrary initial rotor-frame state (i_d0,
    i_q0, uc_d0, uc_q0, i1_d0, i1_q0), which a Scenario sets only as its warm
    start. Raises ParameterError naming the field the C init rejects."""
    return Plant(s, **fields)


# ---------------------------------------------------------- space vectors --


def leg_dir(u_dc: float) -> np.ndarray:
    return np.array([2.0 / 3.0 * u_dc * A**x for x in range(3)])


def phase(z: complex) -> np.ndarray:
    return np.array([(z * A ** (-x)).real for x in range(3)])


def clarke(x_abc) -> complex:
    return 2.0 / 3.0 * sum(x_abc[k] * A**k for k in range(3))


def duties_for(u: complex, u_dc: float) -> tuple[float, float, float]:
    """Duties whose switching-cycle average is the stator vector u:
    (2/3) sum_x Re(u a^-x) a^x = u, and sum_x a^x = 0 absorbs the 0.5."""
    return tuple(0.5 + (u * A ** (-x)).real / u_dc for x in range(3))


def wrap(x: float) -> float:
    return (x + math.pi) % (2 * math.pi) - math.pi


# -------------------------------------------------------------- inverter --


def pwm_segments(c, d_abc, i_abc) -> list[tuple[float, complex]]:
    """Piecewise-constant inverter voltage of one carrier period, [(tau, u)],
    from the leg edges the plant uses (c: the plant's smd_plant_config;
    dead-time direction from the phase currents i_abc of the inverter-side
    current)."""
    T = c.T_sw
    ld = leg_dir(c.u_dc)
    edges = [leg_edges(T, c.t_dead, d, ix) for d, ix in zip(d_abc, i_abc)]
    cuts = sorted({0.0, T, *[e for pair in edges for e in pair]})
    segs = []
    for ta, tb in zip(cuts, cuts[1:]):
        tm = 0.5 * (ta + tb)
        u = sum(ld[x] for x in range(3) if edges[x][0] <= tm < edges[x][1])
        segs.append((tb - ta, complex(u)))
    return segs


def avg_segments(c, d_abc, i_abc) -> list[tuple[float, complex]]:
    """Switching-cycle average: d clamped, minus/plus t_dead/T by the sign of
    the leg current, as one constant voltage over the period."""
    T = c.T_sw
    de = []
    for d, ix in zip(d_abc, i_abc):
        d = min(max(d, 0.0), 1.0)
        if c.t_dead > 0.0:
            d += -c.t_dead / T if ix > 0 else (c.t_dead / T if ix < 0 else 0.0)
            d = min(max(d, 0.0), 1.0)
        de.append(d)
    return [(T, complex(leg_dir(c.u_dc) @ np.array(de)))]


def segments(c, d_abc, i_abc) -> list[tuple[float, complex]]:
    """The period's voltage segments in the plant's PWM mode."""
    return (pwm_segments if c.pwm_mode == 1 else avg_segments)(c, d_abc, i_abc)


# ------------------------------------------------------------- mechanics --


def w_mid(p: Plant, T_ext: float = 0.0) -> float:
    """The plant's documented mid-period electrical speed (held for the
    electrical solution): n_p (w_M + T/2 (T_e0 - T_L - B w_M) / J), no brake."""
    c = p.config
    T_e0 = 1.5 * c.n_p * c.psi_r * (p.i_s * cmath.exp(-1j * p.theta_r)).imag
    T_L = T_ext + c.k_fan * p.w_M * abs(p.w_M)
    return c.n_p * (p.w_M + 0.5 * c.T_sw * (T_e0 - T_L - c.B * p.w_M) / c.J)
