"""Direct access to the C plant (open loop): for tests, agreement checks and
users who drive the machine with their own duty sequence.

Example
-------
>>> from smodrive.params import Scenario
>>> p = Plant(Scenario())
>>> p.step((0.6, 0.5, 0.4))
>>> abs(p.i_s) > 0
True
"""

from __future__ import annotations

import ctypes as ct
import math
from typing import Sequence

import numpy as np

from . import _ffi
from .params import ParameterError, Scenario
from .simulate import plant_config

# Offsets of the first fields of struct smd_plant after its config member.
_CFG = ct.sizeof(_ffi.PlantConfig)


class _PlantHead(ct.Structure):
    _fields_ = [
        ("c", _ffi.PlantConfig),
        ("a", ct.c_double),
        ("i_re", ct.c_double),
        ("i_im", ct.c_double),
        ("theta_r", ct.c_double),
        ("w_M", ct.c_double),
        ("T_e_mean", ct.c_double),
        ("T_L_mean", ct.c_double),
        ("u_re", ct.c_double),
        ("u_im", ct.c_double),
    ]


class Plant:
    """SPMSM + inverter + ADC of a scenario, stepped one carrier period at a time."""

    def __init__(self, s: Scenario):
        self.scenario = s
        self.config = plant_config(s)
        self._buf = (ct.c_double * math.ceil(_ffi.lib.smd_sizeof_plant() / 8 + 1))()
        rc = _ffi.lib.smd_plant_init(self._buf, ct.byref(self.config))
        if rc != 0:
            raise ParameterError(f"plant parameter {_ffi.lib.smd_plant_field(rc).decode()} rejected")
        self._head = _PlantHead.from_buffer(self._buf)

    def step(self, d_abc: Sequence[float], T_ext: float = 0.0, T_brake: float = 0.0) -> None:
        d = (ct.c_double * 3)(*d_abc)
        _ffi.lib.smd_plant_step(self._buf, d, T_ext, T_brake)

    def sample(self) -> np.ndarray:
        """ADC sample of the three phase currents, A."""
        out = (ct.c_double * 3)()
        _ffi.lib.smd_plant_sample(self._buf, out)
        return np.array(out[:])

    @property
    def i_s(self) -> complex:
        return complex(self._head.i_re, self._head.i_im)

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
    def u_mean(self) -> complex:
        return complex(self._head.u_re, self._head.u_im)


def leg_edges(s: Scenario, d: float, i_x: float = 0.0) -> tuple[float, float]:
    """[t_on, t_off) of a leg within a carrier period, as the plant uses it."""
    c = plant_config(s)
    t_on, t_off = ct.c_double(), ct.c_double()
    _ffi.lib.smd_pwm_leg_edges(ct.byref(c), d, i_x, ct.byref(t_on), ct.byref(t_off))
    return t_on.value, t_off.value
