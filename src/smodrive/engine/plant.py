"""Direct access to the C plant (open loop): for tests, agreement checks and
users who drive the machine with their own duty sequence. The plant of any
scenario: the SPMSM alone or behind the LCL filter.

Example
-------
>>> from smodrive.model import Scenario
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

from ..model import ParameterError, Scenario
from . import _ffi
from .marshal import plant_config
from .run import plant_fields

_D3 = ct.c_double * 3


class Plant:
    """Inverter (+ LCL filter) + SPMSM + ADC of a scenario, stepped one
    carrier period at a time. Keyword arguments set fields of the C config
    (``smd_plant_config``) before init, e.g. an arbitrary initial rotor-frame
    state (``i_d0``, ``i_q0``, ``uc_d0``, ``uc_q0``, ``i1_d0``, ``i1_q0``) that a
    Scenario sets only as its warm start."""

    def __init__(self, s: Scenario, **config_fields: float):
        self.scenario = s
        self.config = plant_config(s)
        for k, v in config_fields.items():
            if not hasattr(self.config, k):
                raise TypeError(f"smd_plant_config has no field {k!r}")
            setattr(self.config, k, v)
        self._buf = (ct.c_double * math.ceil(_ffi.lib.smd_sizeof_plant() / 8 + 1))()
        rc = _ffi.lib.smd_plant_init(self._buf, ct.byref(self.config))
        if rc != 0:
            # the C name when a config field of it was passed here, else the
            # scenario's fields behind it
            c_name = _ffi.lib.smd_plant_field(rc).decode()
            given = set(config_fields) & set(c_name.split("/"))
            names = c_name if given else ", ".join(plant_fields(rc))
            raise ParameterError(f"plant parameter {names} rejected")
        self._head = _ffi.PlantHead.from_buffer(self._buf)

    def step(self, d_abc: Sequence[float], T_ext: float = 0.0, T_brake: float = 0.0) -> None:
        _ffi.lib.smd_plant_step(self._buf, _D3(*d_abc), T_ext, T_brake)

    def run_open(self, n: int, m: float, delta: float = 0.0, T_ext: float = 0.0) -> None:
        """n periods (in C) with d_x = 0.5 + 0.5 m cos(theta_r + delta - 2 pi x / 3)."""
        _ffi.lib.smd_plant_run_open(self._buf, n, m, delta, T_ext)

    def sample_all(self) -> tuple[np.ndarray, np.ndarray]:
        """ADC samples (motor phase currents, inverter-side phase currents), A;
        without the filter the second is zero."""
        a, b = _D3(), _D3()
        _ffi.lib.smd_plant_sample(self._buf, a, b)
        return np.array(a[:]), np.array(b[:])

    def sample(self) -> np.ndarray:
        """ADC sample of the three motor phase currents, A."""
        return self.sample_all()[0]

    def phase_currents(self) -> tuple[np.ndarray, np.ndarray]:
        """True phase currents (motor, inverter side), A."""
        a, b = _D3(), _D3()
        _ffi.lib.smd_plant_phase_currents(self._buf, a, b)
        return np.array(a[:]), np.array(b[:])

    @property
    def i_s(self) -> complex:
        """Motor current (i_2 with the filter), A."""
        return complex(self._head.i_re, self._head.i_im)

    @property
    def i_1(self) -> complex:
        """Inverter-side current (the motor current without the filter), A."""
        return complex(self._head.i1_re, self._head.i1_im)

    @property
    def u_c(self) -> complex:
        """Filter-capacitor voltage (0 without the filter), V."""
        return complex(self._head.uc_re, self._head.uc_im)

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
    def pwm_off(self) -> bool:
        """Every switch open over the next periods (a drive's pwm_off): the
        legs on their diodes, or floating at zero current; the duties given
        to :meth:`step` are then unused."""
        return bool(self._head.off)

    @pwm_off.setter
    def pwm_off(self, on: bool) -> None:
        self._head.off = 1 if on else 0

    @property
    def lower_on(self) -> bool:
        """Every lower switch on, forced, over the next periods (the
        commissioning's shorted coast, ``pwm_off = 2``): nothing switches,
        so no dead time; the duties given to :meth:`step` are then unused."""
        return self._head.off == 2

    @lower_on.setter
    def lower_on(self, on: bool) -> None:
        self._head.off = 2 if on else 0

    @property
    def eigenvalues(self) -> np.ndarray:
        """Eigenvalues of the filter-machine matrix A, 1/s ([0] real, [1:] the
        resonant pair); zeros without the filter."""
        re, im = _D3(), _D3()
        _ffi.lib.smd_plant_eigenvalues(self._buf, re, im)
        return np.array(re[:]) + 1j * np.array(im[:])


def leg_edges(T: float, t_dead: float, d: float, i_x: float = 0.0) -> tuple[float, float]:
    """[t_on, t_off) of a leg within a carrier period, as the plant uses it."""
    t_on, t_off = ct.c_double(), ct.c_double()
    _ffi.lib.smd_pwm_edges(T, t_dead, d, i_x, ct.byref(t_on), ct.byref(t_off))
    return t_on.value, t_off.value
