"""Direct access to the C plant of an LCL-filtered high-speed SPMSM
(sim/src/smd_lcl.c; yao2022 Sec. II eq. (1)-(3), Table II), open loop.

Defaults are yao2022 Table II; J, B and the fan coefficient are not given in
the paper: k_fan is fitted to Table IV (i_q = 30 A at 100 kr/min:
1.5 * 0.0012 * 30 / (10472 rad/s)^2 = 4.9e-10 N m s^2), J and B are assumed.

Example
-------
>>> p = LclPlant()
>>> p.step((0.6, 0.5, 0.4))
>>> abs(p.i_1) > 0
True
"""

from __future__ import annotations

import ctypes as ct
import math
from typing import Any, Sequence

import numpy as np

from ._ffi import lib

PWM_MODES = {"averaged": 0, "carrier": 1}


class LclConfig(ct.Structure):
    _fields_ = [
        ("R", ct.c_double),
        ("L1", ct.c_double),
        ("L2o", ct.c_double),
        ("Ls", ct.c_double),
        ("C1", ct.c_double),
        ("psi_m", ct.c_double),
        ("n_p", ct.c_double),
        ("J", ct.c_double),
        ("B", ct.c_double),
        ("k_fan", ct.c_double),
        ("u_dc", ct.c_double),
        ("T_sw", ct.c_double),
        ("pwm_mode", ct.c_int),
        ("t_dead", ct.c_double),
        ("adc_gain_i1", ct.c_double * 3),
        ("adc_offset_i1", ct.c_double * 3),
        ("adc_gain_i2", ct.c_double * 3),
        ("adc_offset_i2", ct.c_double * 3),
        ("adc_noise", ct.c_double),
        ("adc_bits", ct.c_int),
        ("adc_full_scale", ct.c_double),
        ("seed", ct.c_uint64),
        ("w_M0", ct.c_double),
        ("theta_r0", ct.c_double),
        ("uc_d0", ct.c_double),
        ("uc_q0", ct.c_double),
        ("i1_d0", ct.c_double),
        ("i1_q0", ct.c_double),
        ("i2_d0", ct.c_double),
        ("i2_q0", ct.c_double),
    ]


class _LclHead(ct.Structure):
    """The public leading fields of struct smd_lcl_plant."""

    _fields_ = [
        ("c", LclConfig),
        ("uc_re", ct.c_double),
        ("uc_im", ct.c_double),
        ("i1_re", ct.c_double),
        ("i1_im", ct.c_double),
        ("i2_re", ct.c_double),
        ("i2_im", ct.c_double),
        ("theta_r", ct.c_double),
        ("w_M", ct.c_double),
        ("T_e_mean", ct.c_double),
        ("T_L_mean", ct.c_double),
        ("u_re", ct.c_double),
        ("u_im", ct.c_double),
        ("lam_re", ct.c_double * 3),
        ("lam_im", ct.c_double * 3),
        ("L2", ct.c_double),
    ]


def _sig(name: str, restype, *argtypes) -> None:
    f = getattr(lib, name)
    f.restype = restype
    f.argtypes = list(argtypes)


_P = ct.POINTER
_D3 = ct.c_double * 3
_sig("smd_sizeof_lcl_plant", ct.c_ulong)
_sig("smd_sizeof_lcl_config", ct.c_ulong)
_sig("smd_lcl_field", ct.c_char_p, ct.c_int)
_sig("smd_lcl_init", ct.c_int, ct.c_void_p, _P(LclConfig))
_sig("smd_lcl_step", None, ct.c_void_p, _P(ct.c_double), ct.c_double)
_sig("smd_lcl_sample", None, ct.c_void_p, _P(ct.c_double), _P(ct.c_double))
_sig("smd_lcl_phase_currents", None, ct.c_void_p, _P(ct.c_double), _P(ct.c_double))
_sig("smd_lcl_run_open", None, ct.c_void_p, ct.c_long, ct.c_double, ct.c_double, ct.c_double)
_sig("smd_pwm_edges", None, ct.c_double, ct.c_double, ct.c_double, ct.c_double,
     _P(ct.c_double), _P(ct.c_double))

if lib.smd_sizeof_lcl_config() != ct.sizeof(LclConfig):
    raise ImportError(
        f"smodrive binding out of date: sizeof(smd_lcl_config) is {lib.smd_sizeof_lcl_config()} "
        f"in C and {ct.sizeof(LclConfig)} in Python"
    )

# yao2022 Table II (and the assumptions in the module docstring).
DEFAULTS: dict[str, Any] = dict(
    R=0.023, L1=54e-6, L2o=27.5e-6, Ls=24e-6, C1=31.48e-6, psi_m=0.0012, n_p=1.0,
    J=1e-5, B=0.0, k_fan=4.9e-10, u_dc=65.0, T_sw=50e-6, pwm="carrier", t_dead=0.0,
    adc_gain_i1=(1.0, 1.0, 1.0), adc_offset_i1=(0.0, 0.0, 0.0),
    adc_gain_i2=(1.0, 1.0, 1.0), adc_offset_i2=(0.0, 0.0, 0.0),
    adc_noise=0.0, adc_bits=0, adc_full_scale=100.0, seed=1,
    w_M0=0.0, theta_r0=0.0, uc_d0=0.0, uc_q0=0.0, i1_d0=0.0, i1_q0=0.0, i2_d0=0.0, i2_q0=0.0,
)


def lcl_config(**kw: Any) -> LclConfig:
    """A filled smd_lcl_config: DEFAULTS overridden by keyword arguments
    (pwm as "carrier" / "averaged")."""
    unknown = set(kw) - set(DEFAULTS)
    if unknown:
        raise TypeError(f"unknown LCL plant parameter(s): {', '.join(sorted(unknown))}")
    v = {**DEFAULTS, **kw}
    c = LclConfig()
    for name, _ in LclConfig._fields_:
        if name == "pwm_mode":
            c.pwm_mode = PWM_MODES[v["pwm"]]
        elif name.startswith("adc_gain") or name.startswith("adc_offset"):
            setattr(c, name, _D3(*[float(x) for x in v[name]]))
        elif name in ("adc_bits", "seed"):
            setattr(c, name, int(v[name]))
        else:
            setattr(c, name, float(v[name]))
    return c


class LclPlant:
    """Inverter + LCL filter + SPMSM, stepped one carrier period at a time."""

    def __init__(self, **kw: Any):
        self.config = lcl_config(**kw)
        self._buf = (ct.c_double * math.ceil(lib.smd_sizeof_lcl_plant() / 8 + 1))()
        rc = lib.smd_lcl_init(self._buf, ct.byref(self.config))
        if rc != 0:
            raise ValueError(f"LCL plant parameter {lib.smd_lcl_field(rc).decode()} rejected")
        self._head = _LclHead.from_buffer(self._buf)

    def step(self, d_abc: Sequence[float], T_ext: float = 0.0) -> None:
        lib.smd_lcl_step(self._buf, _D3(*d_abc), T_ext)

    def run_open(self, n: int, m: float, delta: float = 0.0, T_ext: float = 0.0) -> None:
        """n periods (in C) with d_x = 0.5 + 0.5 m cos(theta_r + delta - 2 pi x / 3)."""
        lib.smd_lcl_run_open(self._buf, n, m, delta, T_ext)

    def sample(self) -> tuple[np.ndarray, np.ndarray]:
        """ADC samples of the phase currents (i_1 abc, i_2 abc), A."""
        a, b = _D3(), _D3()
        lib.smd_lcl_sample(self._buf, a, b)
        return np.array(a[:]), np.array(b[:])

    def phase_currents(self) -> tuple[np.ndarray, np.ndarray]:
        """True phase currents (i_1 abc, i_2 abc), A."""
        a, b = _D3(), _D3()
        lib.smd_lcl_phase_currents(self._buf, a, b)
        return np.array(a[:]), np.array(b[:])

    @property
    def u_c(self) -> complex:
        return complex(self._head.uc_re, self._head.uc_im)

    @property
    def i_1(self) -> complex:
        return complex(self._head.i1_re, self._head.i1_im)

    @property
    def i_2(self) -> complex:
        return complex(self._head.i2_re, self._head.i2_im)

    @property
    def theta_r(self) -> float:
        return self._head.theta_r

    @property
    def w_M(self) -> float:
        return self._head.w_M

    @property
    def T_e_mean(self) -> float:
        return self._head.T_e_mean

    @property
    def T_L_mean(self) -> float:
        return self._head.T_L_mean

    @property
    def u_mean(self) -> complex:
        return complex(self._head.u_re, self._head.u_im)

    @property
    def eigenvalues(self) -> np.ndarray:
        """Eigenvalues of the filter matrix A, 1/s ([0] real, [1:] the resonant pair)."""
        h = self._head
        return np.array([complex(h.lam_re[k], h.lam_im[k]) for k in range(3)])

    @property
    def L2(self) -> float:
        return self._head.L2


def leg_edges(T: float, t_dead: float, d: float, i_x: float = 0.0) -> tuple[float, float]:
    """[t_on, t_off) of a leg within a carrier period, as the plants use it."""
    t_on, t_off = ct.c_double(), ct.c_double()
    lib.smd_pwm_edges(T, t_dead, d, i_x, ct.byref(t_on), ct.byref(t_off))
    return t_on.value, t_off.value
