"""Run a scenario: the C engine (plant + firmware controller) in chunks.

The Python side only builds the C parameter structs and hands over a
preallocated log buffer; each chunk of samples is one call into C.

Example
-------
>>> from smodrive.params import Scenario, Profile, RPM
>>> s = Scenario(duration=0.01, n_M0=300.0, w_M_ref=Profile.const(300 * RPM))
>>> r = simulate(s)
>>> r["w_M"].shape
(100,)
"""

from __future__ import annotations

import ctypes as ct
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from . import _ffi
from .params import RPM, ParameterError, Profile, Scenario

MODES = {"conventional": 0, "robust": 1, "sensorless": 2}


class SimulationError(RuntimeError):
    """The engine refused the parameters or produced non-finite values."""


def _pwl(p: Profile, scale: float = 1.0) -> _ffi.Pwl:
    w = _ffi.Pwl()
    w.n = len(p.t)
    for k, (t, y) in enumerate(zip(p.t, p.y)):
        w.t[k] = t
        w.y[k] = y * scale
    return w


def plant_config(s: Scenario) -> _ffi.PlantConfig:
    m, inv, adc = s.motor, s.inverter, s.adc
    c = _ffi.PlantConfig()
    c.R_s, c.L_s, c.psi_r, c.n_p, c.J, c.B = m.R_s, m.L_s, m.psi_r, m.n_p, m.J, m.B
    c.u_dc = inv.u_dc
    c.T_sw = s.T_sp
    c.pwm_mode = 1 if inv.pwm == "carrier" else 0
    c.t_dead = inv.t_dead
    for k in range(3):
        c.adc_gain[k] = adc.gain[k]
        c.adc_offset[k] = adc.offset[k]
    c.adc_noise = adc.noise
    c.adc_bits = adc.bits
    c.adc_full_scale = adc.full_scale
    c.seed = adc.seed
    c.w_brake_eps = s.load.w_brake_eps
    c.k_fan = s.load.k_fan
    c.w_M0 = s.n_M0 * RPM
    c.theta_r0 = s.theta_r0
    if s.warm_start:
        # steady state at t = 0: the current carries the initial load and friction
        w_M0 = s.n_M0 * RPM
        brake = s.load.T_brake(0.0) * max(-1.0, min(1.0, w_M0 / s.load.w_brake_eps))
        T_L = s.load.T_ext(0.0) + brake + s.load.k_fan * w_M0 * abs(w_M0) + m.B * w_M0
        c.i_q0 = T_L / m.k_t if m.k_t > 0 else 0.0
    return c


def drive_config(s: Scenario) -> _ffi.DriveConfig:
    k = s.controller
    c = _ffi.DriveConfig()
    c.mode = MODES[k.mode]
    c.T_sp = s.T_sp
    c.L_s_hat, c.R_s_hat, c.psi_r_hat = k.L_s_hat, k.R_s_hat, k.psi_r_hat
    c.lambda_min, c.l, c.w_c, c.rho = k.lambda_min, k.l, k.w_c, k.rho
    c.k_p, c.k_i = k.pi_gains(s.motor.n_p)
    c.i_max = k.i_max
    c.speed_decimation = k.speed_decimation
    c.speed_loop = 1 if k.speed_loop else 0
    c.w_lpf, c.w_hys = k.w_lpf, k.w_hys
    c.svm_limit = 1 if s.inverter.svm_limit == "hexagon" else 0
    c.w_max = k.n_max * RPM * s.motor.n_p
    c.handover = int(round(k.t_handover / s.T_sp))
    c.t_dead_comp = k.t_dead_comp
    c.i_dtc = k.i_dtc
    c.smdo_euler = 1 if k.smdo_euler else 0
    return c


def profiles(s: Scenario) -> _ffi.Profiles:
    p = _ffi.Profiles()
    p.w_M_ref = _pwl(s.w_M_ref)
    p.T_ext = _pwl(s.load.T_ext)
    p.T_brake = _pwl(s.load.T_brake)
    p.i_d_ref = _pwl(s.i_d_ref)
    p.i_q_ref = _pwl(s.i_q_ref)
    p.i_d_sin_amp = s.i_d_sin_amp
    p.i_d_sin_freq = s.i_d_sin_freq
    return p


@dataclass
class Result:
    """Logged signals of one run, by channel name (see :data:`CHANNELS`)."""

    scenario: Scenario
    data: np.ndarray  # rows x channels
    status: int

    def __getitem__(self, name: str) -> np.ndarray:
        return self.data[:, _ffi.LOG_CHANNELS.index(name)]

    @property
    def t(self) -> np.ndarray:
        return self["t"]

    def window(self, t0: float, t1: float) -> np.ndarray:
        """Boolean mask of samples with t0 <= t < t1."""
        return (self.t >= t0) & (self.t < t1)

    @property
    def theta_error(self) -> np.ndarray:
        """theta_r - theta_hat wrapped to [-pi, pi), rad."""
        d = self["theta_r"] - self["theta_hat"]
        return (d + np.pi) % (2 * np.pi) - np.pi


CHANNELS = _ffi.LOG_CHANNELS


class Engine:
    """A live engine: plant and controller state persist between run() calls."""

    def __init__(self, s: Scenario):
        s.check_controller()
        self.scenario = s
        self._buf = (ct.c_double * math.ceil(_ffi.ENGINE_SIZE / 8 + 1))()
        self._pc, self._dc, self._pr = plant_config(s), drive_config(s), profiles(s)
        rc = _ffi.lib.smd_engine_init(
            self._buf, ct.byref(self._pc), ct.byref(self._dc), ct.byref(self._pr)
        )
        if rc != 0:
            if 1000 <= rc < 2000:
                field = _ffi.lib.smd_plant_field(rc - 1000).decode()
                raise ParameterError(f"plant parameter {field} rejected by the engine")
            if 2000 <= rc < 3000:
                raise ParameterError(f"controller rejected: {_ffi.status_str(rc - 2000)}")
            raise ParameterError("a profile is malformed (times must be non-decreasing)")

    def run(self, n: int, out: np.ndarray, row0: int, stride: int) -> int:
        ptr = out[row0:].ctypes.data_as(ct.POINTER(ct.c_double))
        return int(_ffi.lib.smd_engine_run(self._buf, n, ptr, stride))


def simulate(
    s: Scenario,
    progress: Callable[[float], None] | None = None,
    chunk_seconds: float = 0.05,
) -> Result:
    """Run scenario `s` to its duration; `progress(fraction)` after each chunk."""
    eng = Engine(s)
    n = s.n_steps
    stride = s.log_stride
    rows = math.ceil(n / stride)
    out = np.zeros((rows, _ffi.N_LOG), dtype=np.float64)
    chunk = max(stride, int(chunk_seconds / s.T_sp) // stride * stride)
    done, row = 0, 0
    while done < n:
        m = min(chunk, n - done)
        row += eng.run(m, out, row, stride)
        done += m
        if progress is not None:
            progress(done / n)
    out = out[:row]
    status = int(np.max(out[:, -1])) if row else 0
    bad = ~np.isfinite(out)
    if bad.any():
        first = int(np.argmax(bad.any(axis=1)))
        raise SimulationError(
            f"{s.name}: non-finite values at t = {out[first, 0]:.6f} s "
            f"in {[c for c, b in zip(CHANNELS, bad[first]) if b]}"
        )
    return Result(s, out, status)
