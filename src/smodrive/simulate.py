"""Run a scenario: the C engine (plant + firmware drive) in chunks.

The Python side builds the C configuration structs once (the plant from the
scenario's plant sections, the drive from its controller section and, for
the LCL observers, the lookup tables designed offline by
:mod:`smodrive.design.yao2022`) and hands over a preallocated log buffer;
each chunk of samples is one call into C.

Example
-------
>>> from smodrive.params import Scenario, Profile, RPM
>>> s = Scenario(duration=0.01, w_M0=300 * RPM, w_M_ref=Profile.const(300 * RPM))
>>> r = simulate(s)
>>> r["w_M"].shape, r.unit("w_M")
((100,), 'rad/s')
"""

from __future__ import annotations

import ctypes as ct
import dataclasses
import functools
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from . import _ffi
from .params import LCL_TABLE_RPM, RPM, ParameterError, Profile, Scenario

CURRENT = {"pi": 0, "dbpc": 1, "robust_dbpc": 2}
POSITION = {"encoder": 0, "smdo_emf": 1, "lcl_smo_pll": 2, "lcl_linear": 3}
START = {"running": 0, "handover": 1, "if": 2}
LAWS = {"proposed": 0, "tde17": 1, "tde18": 2}
PHASES = {0: "forced (I/f)", 1: "encoder (handover)", 2: "position source"}

# Every logged channel: unit and meaning (the C engine's table, smd_engine.h).
CHANNELS: tuple[str, ...] = _ffi.LOG_CHANNELS
CHANNEL_INFO: dict[str, tuple[str, str]] = {
    "t": ("s", "time of sample k"),
    "w_M": ("rad/s", "true mechanical speed"),
    "theta_r": ("rad", "true electrical angle"),
    "i_alpha": ("A", "true motor current (i_2 with the filter), alpha"),
    "i_beta": ("A", "true motor current, beta"),
    "i_d": ("A", "true motor current in the true rotor frame, d"),
    "i_q": ("A", "true motor current in the true rotor frame, q"),
    "T_e": ("N m", "mean electromagnetic torque over [t_k, t_k+1)"),
    "T_L": ("N m", "mean load torque over [t_k, t_k+1) (friction B w excluded)"),
    "w_M_ref": ("rad/s", "mechanical speed reference"),
    "i_d_ref": ("A", "controller's current reference, d"),
    "i_q_ref": ("A", "controller's current reference, q"),
    "theta_hat": ("rad", "angle the controller uses at k"),
    "w_hat": ("rad/s", "electrical speed the controller uses at k"),
    "u_d_hat_alpha": ("V", "SMDO disturbance estimate u_d_hat^{k+1}, alpha"),
    "u_d_hat_beta": ("V", "SMDO disturbance estimate, beta"),
    "u_alpha": ("V", "mean inverter voltage over [t_k, t_k+1), alpha"),
    "u_beta": ("V", "mean inverter voltage, beta"),
    "u_cmd_alpha": ("V", "voltage commanded for the next period (after the limit), alpha"),
    "u_cmd_beta": ("V", "voltage commanded for the next period, beta"),
    "i_a_meas": ("A", "ADC motor phase current a"),
    "i_b_meas": ("A", "ADC motor phase current b"),
    "i_hat_alpha": ("A", "SMDO current prediction i_hat^{k+1}, alpha"),
    "i_hat_beta": ("A", "SMDO current prediction, beta"),
    "lambda": ("A/s", "SMDO adapted gain, eq. (37)"),
    "i_g": ("A", "PI current control: measured motor current in its frame, gamma (d); "
                 "0 with DBPC"),
    "i_dl": ("A", "PI current control: measured motor current in its frame, delta (q)"),
    "theta_err_est": ("rad", "LCL sources: estimated angle error, yao2022 eq. (47)"),
    "e_hat_g": ("V", "LCL sliding-mode observer: EMF estimate, gamma"),
    "e_hat_dl": ("V", "LCL sliding-mode observer: EMF estimate, delta"),
    "s_g": ("A", "LCL sliding-mode observer: switching function s(k), eq. (18), gamma"),
    "s_dl": ("A", "switching function s(k), delta"),
    "d_hat_g": ("A", "periodic-disturbance compensation, eq. (35), gamma"),
    "d_hat_dl": ("A", "periodic-disturbance compensation, delta"),
    "v_g": ("A", "disturbance part v(k-1) of the attraction function, gamma"),
    "v_dl": ("A", "disturbance part v(k-1), delta"),
    "i1_alpha": ("A", "true inverter-side current (motor current without filter), alpha"),
    "i1_beta": ("A", "true inverter-side current, beta"),
    "uc_alpha": ("V", "true filter-capacitor voltage (0 without filter), alpha"),
    "uc_beta": ("V", "true filter-capacitor voltage, beta"),
    "lin_e_alpha": ("V", "linear observer's EMF estimate, eq. (65), alpha"),
    "lin_e_beta": ("V", "linear observer's EMF estimate, beta"),
    "phase": ("", "start-up phase: 0 forced (I/f), 1 encoder handover, 2 position source"),
    "status": ("", "controller status code of the step (smd_status)"),
    "fault": ("", "controller fault word of the step (smd_drive_out.fault, FAULT_BITS)"),
}
if set(CHANNEL_INFO) != set(CHANNELS):
    raise ImportError("smodrive: channel descriptions out of date with the C engine")

TABLE_RPM = np.arange(-LCL_TABLE_RPM, LCL_TABLE_RPM + 1.0, 1000.0)  # LCL observer tables, r/min


class SimulationError(RuntimeError):
    """The engine refused the parameters or produced non-finite values."""


# ------------------------------------------------------------ C structs ---

def _pwl(p: Profile) -> _ffi.Pwl:
    w = _ffi.Pwl()
    w.n = len(p.t)
    for k, (t, y) in enumerate(zip(p.t, p.y)):
        w.t[k] = t
        w.y[k] = y
    return w


def _warm_i_q0(s: Scenario) -> float:
    """q-axis current of the steady state at t = 0 (the load and friction at
    the initial speed), or 0 without a warm start."""
    m = s.motor
    if not s.warm_start or s.controller.start == "if" or m.k_t <= 0:
        return 0.0
    w_M0 = s.w_M0
    brake = s.load.T_brake(0.0) * max(-1.0, min(1.0, w_M0 / s.load.w_brake_eps))
    T_L = s.load.T_ext(0.0) + brake + s.load.k_fan * w_M0 * abs(w_M0) + m.B * w_M0
    return T_L / m.k_t


def plant_config(s: Scenario) -> _ffi.PlantConfig:
    """The plant's C config: the true machine, filter, inverter, ADC, load
    and initial state (a warm start: the steady state carrying the load)."""
    m, inv, adc, f = s.motor, s.inverter, s.adc, s.lcl
    c = _ffi.PlantConfig()
    c.R_s, c.L_s, c.psi_r, c.n_p, c.J, c.B = m.R_s, m.L_s, m.psi_r, m.n_p, m.J, m.B
    if f is not None:
        c.lcl, c.L1, c.L2o, c.C1 = 1, f.L1, f.L2o, f.C1
    c.u_dc = inv.u_dc
    c.T_sw = s.T_sp
    c.pwm_mode = 1 if inv.pwm == "carrier" else 0
    c.t_dead = inv.t_dead
    c.dead_time_model = 1 if inv.dead_time_model == "clamp" else 0
    for k in range(3):
        c.adc_gain[k], c.adc_offset[k] = adc.gain[k], adc.offset[k]
        c.adc_gain_i1[k], c.adc_offset_i1[k] = adc.gain_i1[k], adc.offset_i1[k]
    c.adc_noise = adc.noise
    c.adc_bits = adc.bits
    c.adc_n_oversample = adc.n_oversample
    c.adc_full_scale = adc.full_scale
    c.seed = adc.seed
    c.w_brake_eps = s.load.w_brake_eps
    c.k_fan = s.load.k_fan
    c.w_M0 = s.w_M0
    c.theta_r0 = s.theta_r0
    c.i_q0 = i_q0 = _warm_i_q0(s)
    if f is not None and s.warm_start and s.controller.start != "if":
        # steady state of the LCL in the rotor frame with i_2 = j i_q0:
        # u_c = j w psi + (R + j w L2) i_2, i_1 = i_2 + j w C1 u_c
        w_e = s.w_M0 * m.n_p
        L2 = f.L2o + m.L_s
        uc = 1j * w_e * m.psi_r + (m.R_s + 1j * w_e * L2) * 1j * i_q0
        i1 = 1j * i_q0 + 1j * w_e * f.C1 * uc
        c.uc_d0, c.uc_q0 = uc.real, uc.imag
        c.i1_d0, c.i1_q0 = i1.real, i1.imag
    return c


@functools.lru_cache(maxsize=8)
def observer_tables(plant, design) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The LCL observers' tables for `plant`
    (:class:`smodrive.design.yao2022.DesignPlant`: motor, filter, T_sp),
    designed offline at every 1000 r/min of TABLE_RPM and packed in the C
    layouts: (models (n, N_MODEL) float32, linear observer (n, N_LIN)
    float32, w_min, dw)."""
    from .design import yao2022 as dz

    t = dz.design_tables(plant, TABLE_RPM, design)
    n = t.w.size
    m = np.zeros((n, _ffi.N_MODEL), dtype=np.float32)
    lin = np.zeros((n, _ffi.N_LIN), dtype=np.float32)
    for k in range(n):
        parts = [t.G[k].ravel(), t.H[k].ravel(), t.F[k].ravel(), t.T_r[k][2:, 2:].ravel(),
                 t.H_c[k].ravel(), t.D1[k].ravel(), t.D2[k].ravel(), t.Gamma_c[k].ravel(),
                 t.Gamma_1[k].ravel(), t.Gamma_2[k].ravel(), t.G_s[k].ravel(),
                 t.K_c[k].ravel(), t.K_y[k].ravel(), [t.k[k]]]
        m[k] = np.concatenate(parts)
        lin[k] = np.concatenate([t.L_s[k].ravel(), t.Theta[k].ravel(), t.Theta_y[k].ravel(),
                                 t.Theta_u[k].ravel()])
    if not (np.all(np.isfinite(m)) and np.all(np.isfinite(lin))):
        raise ParameterError("observer design produced non-finite matrices")
    m.flags.writeable = lin.flags.writeable = False
    return m, lin, float(t.w[0]), float(t.w[1] - t.w[0])


def lcl_observer_tables(s: Scenario, design=None):
    """observer_tables for scenario `s`: designed from the controller's
    estimates (L_s_hat, R_s_hat, psi_r_hat) and the filter with the
    observer's capacitance C1_hat_ratio C1, at the scenario's T_sp."""
    from .design import yao2022 as dz
    from .params import LclFilterPars, MotorPars

    c = s.controller
    if s.lcl is None:
        raise ParameterError("the LCL observers need the [lcl] filter section")
    # the design's machine and filter are the controller's estimates: a value
    # the design cannot take is named by the field the user set
    for label, value, cls, name in (
            ("controller.R_s_hat", c.R_s_hat, MotorPars, "R_s"),
            ("controller.L_s_hat", c.L_s_hat, MotorPars, "L_s"),
            ("controller.psi_r_hat", c.psi_r_hat, MotorPars, "psi_r"),
            (f"lcl.C1 x controller.C1_hat_ratio = {s.lcl.C1!r} x {c.C1_hat_ratio!r}",
             s.lcl.C1 * c.C1_hat_ratio, LclFilterPars, "C1")):
        lo, hi, lo_open = cls.__dataclass_fields__[name].metadata["range"]
        if not ((value > lo if lo_open else value >= lo) and value <= hi):
            raise ParameterError(
                f"{label} = {value!r} is outside its valid range {'(' if lo_open else '['}"
                f"{lo:g}, {hi:g}] {cls.__dataclass_fields__[name].metadata['unit']} of the "
                "LCL observers' design (their model is the controller's estimates)")
    est_motor = dataclasses.replace(s.motor, R_s=c.R_s_hat, L_s=c.L_s_hat, psi_r=c.psi_r_hat)
    est_lcl = dataclasses.replace(s.lcl, C1=s.lcl.C1 * c.C1_hat_ratio)
    design = design or dz.ObserverDesignPars(Q=tuple(c.Q))
    try:
        return observer_tables(dz.DesignPlant(est_motor, est_lcl, s.T_sp), design)
    except (ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
        raise ParameterError(
            f"{s.name}: the LCL observers' design failed: {exc}. It is designed from T_sp = "
            f"{s.T_sp!r} s, lcl.L1, lcl.L2o, lcl.C1 x controller.C1_hat_ratio, "
            "controller.L_s_hat, controller.R_s_hat and controller.Q (motor.n_p scales its "
            "speed axis)") from None


def drive_config(s: Scenario, tables=None) -> _ffi.DriveConfig:
    """The drive's C config (SI units, electrical angles and speeds). For
    the LCL observers `tables` (from :func:`lcl_observer_tables`) must be
    kept alive as long as the config is in use."""
    k, T = s.controller, s.T_sp
    n_p = s.motor.n_p
    c = _ffi.DriveConfig()
    c.current, c.position, c.start = CURRENT[k.current], POSITION[k.position], START[k.start]
    c.lcl = 0 if s.lcl is None else 1
    c.T_sp = T
    c.L_s_hat, c.R_s_hat, c.psi_r_hat = k.L_s_hat, k.R_s_hat, k.psi_r_hat
    c.lambda_min, c.l, c.w_c, c.rho = k.lambda_min, k.l, k.w_c, k.rho
    c.smdo_euler = 1 if k.smdo_euler else 0
    c.w_lpf, c.w_hys = k.w_lpf, k.w_hys
    c.w_max = k.w_M_max * n_p
    c.k_p_i, c.k_i_i = k.current_pi_gains()
    c.L_dec = s.L_dec
    c.R_v = k.R_v
    c.emf_ff = 1 if k.emf_ff else 0
    c.speed_loop = 1 if k.speed_loop else 0
    c.k_p_w, c.k_i_w = k.pi_gains(n_p)
    c.i_max = k.i_max
    c.speed_decimation = k.speed_decimation
    c.k_theta, c.k_omega, c.k_a = k.k_theta, k.k_omega, k.k_a
    if tables is not None:
        m, lin, w_min, dw = tables
        c.smo = _ffi.SmoConfig(T_sp=T, law=LAWS[k.law], table=m.ctypes.data, n=m.shape[0],
                               w_min=w_min, dw=dw, Q1=k.Q[0], Q2=k.Q[1], bw_rel2=k.bw_rel[0],
                               bw_rel3=k.bw_rel[1], w_bp_min=k.w_M_bp_min * n_p)
        c.lin = _ffi.LinConfig(table=lin.ctypes.data, n=lin.shape[0], w_min=w_min, dw=dw)
    c.handover = int(round(k.t_handover / T)) if k.start == "handover" else 0
    c.i_start = k.i_start
    c.a_start = k.a_M_start * n_p
    c.w_handover = k.w_M_handover * n_p
    c.svm_limit = 1 if s.inverter.svm_limit == "hexagon" else 0
    c.t_dead_comp = k.t_dead_comp
    c.i_dtc = k.i_dtc
    c.i_trip = min(2.5 * k.i_max, 1e5) if k.i_trip is None else k.i_trip
    c.u_dc_min = k.u_dc_min_ratio * s.inverter.u_dc
    c.u_dc_max = k.u_dc_max_ratio * s.inverter.u_dc
    c.safe_state = 1 if k.safe_state == "pwm_off" else 0
    sensorless = k.position != "encoder"
    c.lock_samples = int(round(k.t_lock / T)) if sensorless else 0
    c.lock_ratio = k.lock_ratio
    c.w_lock_min = k.w_M_lock_min * n_p
    c.w_if_enter = k.w_M_if_enter * n_p
    c.a_ref = k.a_M_ref * n_p
    c.dwell = int(round(k.t_dwell / T))
    c.chatter_max = k.chatter_max
    c.chatter_window = max(1, int(round(k.t_chatter / T)))
    c.track_samples = int(round(k.t_track / T)) if k.speed_loop else 0
    c.w_track = k.w_M_track * n_p
    c.forced_samples = int(round(k.t_forced / T)) if (k.start == "if" or k.w_M_if_enter > 0) \
        else 0
    c.osc_i, c.osc_rel = k.osc_i, k.osc_rel
    c.osc_samples = int(round(k.t_osc / T)) if k.osc_i > 0 else 0
    c.restart_max = k.restart_max if (k.start == "if" and k.position == "smdo_emf") else 0
    c.restart_window = max(1, int(round(k.t_restart / T)))
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


# --------------------------------------------------------------- results --

#: bits of the controller's fault word (core/include/smodrive/smd_drive.h)
FAULT_BITS = {"input": 1, "internal": 2, "overcurrent": 4, "undervoltage": 8,
              "overvoltage": 16, "lost_lock": 32, "speed_tracking": 64, "forced": 128,
              "chatter": 256, "oscillation": 512, "start_failed": 1024, "restart": 2048,
              "angle_jump": 4096}
#: the latched ones: the drive stays in its safe state until cleared
LATCHED_FAULTS = ("overcurrent", "undervoltage", "overvoltage", "lost_lock", "speed_tracking",
                  "forced", "chatter", "start_failed")
#: warnings: reported while their condition holds, the drive runs on
WARNING_FAULTS = ("oscillation", "restart", "angle_jump")


def fault_names(word: int) -> list[str]:
    """The names of the bits set in a fault word."""
    return [k for k, b in FAULT_BITS.items() if int(word) & b]


@dataclass(frozen=True)
class FaultReport:
    """When the controller first reported a fault, with which bits, and the
    fault word of the last sample (non-zero: the run ends in a fault)."""

    t_first: float | None  # s; None: no fault
    first: int
    final: int

    @property
    def ends_in_fault(self) -> bool:
        return self.final != 0

    def as_dict(self) -> dict:
        return {"first_fault_t": self.t_first, "first_fault": fault_names(self.first),
                "final_fault": fault_names(self.final)}


NO_FAULT = FaultReport(None, 0, 0)


@dataclass
class Result:
    """Logged signals of one run, by channel name (:data:`CHANNELS`; units
    and meanings: :data:`CHANNEL_INFO`, :meth:`unit`)."""

    scenario: Scenario
    data: np.ndarray  # rows x channels
    status: int
    faults: FaultReport = NO_FAULT
    log_stride: int | None = None  # control samples per row (None: the scenario's)
    samples: int | None = None  # control samples simulated (None: the scenario's n_steps)

    def __post_init__(self) -> None:
        if self.log_stride is None:
            self.log_stride = self.scenario.log_stride
        if self.samples is None:
            self.samples = self.scenario.n_steps

    def __getitem__(self, name: str) -> np.ndarray:
        """The logged channel `name` (:data:`CHANNELS`); an unknown name is
        a KeyError naming it and the channels."""
        try:
            return self.data[:, CHANNELS.index(name)]
        except ValueError:
            raise Result._no_channel(name) from None

    @staticmethod
    def unit(name: str) -> str:
        """The SI unit of channel `name` ("" for a dimensionless code).

        >>> Result.unit("T_e")
        'N m'
        """
        try:
            return CHANNEL_INFO[name][0]
        except (KeyError, TypeError):
            raise Result._no_channel(name) from None

    @staticmethod
    def description(name: str) -> str:
        """What channel `name` is.

        >>> Result.description("w_M")
        'true mechanical speed'
        """
        try:
            return CHANNEL_INFO[name][1]
        except (KeyError, TypeError):
            raise Result._no_channel(name) from None

    @staticmethod
    def _no_channel(name) -> KeyError:
        """The KeyError for a name that is not a channel: the closest
        channels, a derived quantity's property, and every channel."""
        import difflib

        hint = ""
        if isinstance(name, str) and isinstance(getattr(Result, name, None), property):
            hint = f" ({name} is derived: Result.{name})"
        elif isinstance(name, str):
            close = difflib.get_close_matches(name, CHANNELS, n=3, cutoff=0.6)
            if close:
                hint = f" (closest: {', '.join(close)})"
        return KeyError(f"{name!r} is not a logged channel{hint}; the channels are "
                        f"{', '.join(CHANNELS)} (smodrive.simulate.CHANNELS, CHANNEL_INFO)")

    def to_dataframe(self):
        """The log as a pandas DataFrame (needs pandas: the extra
        ``smodrive[pandas]``): a column per channel, units and descriptions
        in ``df.attrs["units"]`` and ``df.attrs["descriptions"]``
        (:func:`smodrive.export.to_dataframe`)."""
        from .export import to_dataframe

        return to_dataframe(self)

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

    @property
    def n_rpm(self) -> np.ndarray:
        """True speed, r/min."""
        return self["w_M"] / RPM

    @property
    def n_hat_rpm(self) -> np.ndarray:
        """Speed the controller uses, r/min (mechanical)."""
        return self["w_hat"] / self.scenario.motor.n_p / RPM


# ---------------------------------------------------------------- engine --

def _wrap_pi(x: float) -> float:
    """x wrapped to [-pi, pi), as the plant wraps its angle."""
    return x - 2 * math.pi * math.floor((x + math.pi) / (2 * math.pi))


# The C plant's field codes (smd_plant_field) and the controller's init
# statuses (smd_status) as the scenario fields behind them: the C names
# (T_sw, i_d0/i_q0, omega_c, k_p, w_max, ...) are the structs', not the user's.
_WARM = ("warm_start", "w_M0", "load.T_ext", "load.T_brake", "load.k_fan", "motor.B",
         "motor.psi_r", "motor.n_p")
_PLANT_FIELDS: dict[int, tuple[str, ...]] = {
    1: ("motor.R_s",), 2: ("motor.L_s",), 3: ("motor.psi_r",), 4: ("motor.n_p",),
    5: ("motor.J",), 6: ("motor.B",), 7: ("lcl",), 8: ("lcl.L1",), 9: ("lcl.L2o",),
    10: ("lcl.C1",), 11: ("inverter.u_dc",), 12: ("T_sp",), 13: ("inverter.pwm",),
    14: ("inverter.t_dead",), 15: ("adc.gain",), 16: ("adc.offset",), 17: ("adc.gain_i1",),
    18: ("adc.offset_i1",), 19: ("adc.noise",), 20: ("adc.bits",), 21: ("adc.full_scale",),
    22: ("load.w_brake_eps",), 23: ("load.k_fan",), 24: ("w_M0",), 25: ("theta_r0",),
    26: _WARM,  # the warm start's q current, T_L(0) / k_t
    27: _WARM + ("motor.R_s", "motor.L_s", "lcl.L2o"),  # ... its capacitor voltage
    28: _WARM + ("motor.R_s", "motor.L_s", "lcl.L2o", "lcl.C1"),  # ... its i_1
    29: ("motor.R_s", "motor.L_s", "lcl.L1", "lcl.L2o", "lcl.C1"),
    30: ("inverter.dead_time_model", "lcl"),  # clamp: the machine without the filter only
    31: ("adc.n_oversample",),
}
_SPEED_PI = ("controller.speed_bw", "controller.J_hat", "controller.psi_r_pi", "motor.n_p")
_PLL = ("controller.k_theta", "controller.k_omega", "controller.k_a")
_DRIVE_FIELDS: dict[int, tuple[str, ...]] = {
    2: ("T_sp",), 3: ("controller.L_s_hat",), 4: ("controller.R_s_hat",),
    5: ("controller.psi_r_hat",), 6: ("controller.lambda_min",), 7: ("controller.l",),
    8: ("controller.w_c",), 9: ("controller.rho",), 10: _SPEED_PI + _PLL,
    11: _SPEED_PI + _PLL, 12: ("controller.i_max", "controller.bw_rel", "controller.w_M_bp_min"),
    13: ("controller.current", "controller.position", "controller.start", "controller.law",
         "inverter.svm_limit"),
    14: ("controller.l", "controller.lambda_min", "controller.rho", "controller.w_c",
         "controller.w_M_max", "controller.Q", "T_sp") + _PLL,
    15: ("controller.w_lpf", "T_sp"), 17: ("controller.speed_decimation",),
    18: ("controller.w_hys",), 19: ("controller.w_M_max", "controller.w_hys", "motor.n_p", "T_sp"),
    20: ("controller.t_dead_comp", "controller.i_dtc", "T_sp"), 21: ("controller.t_handover",),
    23: ("controller.position", "lcl", "T_sp"),
    24: ("controller.current", "controller.position", "controller.R_v", "lcl"),
    25: ("controller.current_bw", "controller.k_p_i", "controller.k_i_i", "controller.L_dec",
         "controller.R_v"),
    26: ("controller.i_start", "controller.a_M_start", "controller.w_M_handover", "T_sp"),
    27: ("controller.i_trip", "controller.u_dc_min_ratio", "controller.u_dc_max_ratio",
         "controller.safe_state", "controller.t_lock", "controller.lock_ratio",
         "controller.w_M_lock_min", "controller.w_M_if_enter", "inverter.u_dc"),
}
_PROFILES = ("w_M_ref", "load.T_ext", "load.T_brake", "i_d_ref", "i_q_ref", "i_d_sin_amp",
             "i_d_sin_freq", "theta_r0", "w_M0")


def plant_fields(code: int) -> tuple[str, ...]:
    """The scenario fields behind the C plant's field code `code`."""
    return _PLANT_FIELDS.get(code, ())


def controller_fields(status: int) -> tuple[str, ...]:
    """The scenario fields behind the controller's init status `status`
    (none for the statuses of a step)."""
    return _DRIVE_FIELDS.get(status, ())


def _value(s: Scenario, name: str):
    obj = s
    for part in name.split("."):
        obj = getattr(obj, part, None)
    return obj


def _with_values(s: Scenario, names: tuple[str, ...]) -> str:
    out = []
    for n in names:
        v = _value(s, n)
        out.append(n if v is None or dataclasses.is_dataclass(v) else f"{n} = {v!r}")
    return ", ".join(out)


def _describe(rc: int, s: Scenario) -> str:
    """The engine's refusal `rc` in the scenario's fields."""
    if rc in (1026, 1027, 1028):
        i_q0 = _warm_i_q0(s)
        k_t = s.motor.k_t
        what = {1026: f"a q current of {i_q0:.4g} A (beyond +-1e5 A)",
                1027: "a filter-capacitor voltage beyond +-1e5 V",
                1028: "an inverter-side current beyond +-1e5 A"}[rc]
        return (f"the warm start (warm_start = true) would need {what} to carry the load at "
                f"t = 0: load torque {i_q0 * k_t:.4g} N m (load.T_ext + load.T_brake at t = 0, "
                f"load.k_fan w_M0 |w_M0|, motor.B w_M0; w_M0 = {s.w_M0:.4g} rad/s) over the "
                f"torque constant 1.5 motor.n_p motor.psi_r = {k_t:.4g} N m/A. Lower the load "
                "or the speed at t = 0, check motor.psi_r and the [lcl] filter, or set "
                "warm_start = false")
    if 1000 <= rc < 2000:
        return (f"the plant model refused {_with_values(s, plant_fields(rc - 1000))} "
                f"(plant field code {rc - 1000})")
    if 2000 <= rc < 3000:
        names = controller_fields(rc - 2000) or ("controller",)
        return (f"the controller refused {_with_values(s, names)} (smd_status {rc - 2000}; "
                "docs/parameters.md lists the codes)")
    return (f"a profile or the initial state is malformed: {', '.join(_PROFILES)} must be "
            "finite, with non-decreasing times")


class Engine:
    """A live engine: plant and controller state persist between run() calls."""

    def __init__(self, s: Scenario, design=None):
        s.check_controller()
        self.scenario = s
        self._tables = (lcl_observer_tables(s, design)
                        if s.controller.position in ("lcl_smo_pll", "lcl_linear") else None)
        self._buf = (ct.c_double * math.ceil(_ffi.ENGINE_SIZE / 8 + 1))()
        self._pc, self._pr = plant_config(s), profiles(s)
        self._dc = drive_config(s, self._tables)
        self._st = _ffi.EngineStart(theta0=_wrap_pi(s.theta_r0),
                                    w0=s.w_M0 * s.motor.n_p, i_q0=self._pc.i_q0)
        rc = _ffi.lib.smd_engine_init(self._buf, ct.byref(self._pc), ct.byref(self._dc),
                                      ct.byref(self._pr), ct.byref(self._st))
        if rc != 0:
            raise ParameterError(f"{s.name}: {_describe(rc, s)}")

    def run(self, n: int, out: np.ndarray, row0: int, stride: int) -> int:
        ptr = out[row0:].ctypes.data_as(ct.POINTER(ct.c_double))
        return int(_ffi.lib.smd_engine_run(self._buf, n, ptr, stride))

    def faults(self) -> "FaultReport":
        """The first fault of the run so far (time, cause) and the last
        sample's fault word."""
        first, now = ct.c_uint(0), ct.c_uint(0)
        k = int(_ffi.lib.smd_engine_fault(self._buf, ct.byref(first), ct.byref(now)))
        return FaultReport(None if k < 0 else k * self.scenario.T_sp, int(first.value),
                           int(now.value))

    def run_nolog(self, n: int) -> None:
        """Run n samples without logging (benchmarks)."""
        _ffi.lib.smd_engine_run(self._buf, n, None, 1)


#: Memory the log of one run may take by default (2 GiB), bytes.
DEFAULT_LOG_BUDGET = 2 * 1024**3


@dataclass(frozen=True)
class LogPlan:
    """How a run is logged: every `stride`-th control sample, `rows` rows of
    `bytes` bytes in all, within `budget_bytes`; `decimated` when the budget
    made the stride larger than the scenario's log_stride."""

    stride: int
    rows: int
    bytes: int
    budget_bytes: int
    decimated: bool

    def as_dict(self) -> dict:
        return dataclasses.asdict(self)


def log_plan(s: Scenario, budget: int = DEFAULT_LOG_BUDGET) -> LogPlan:
    """The log of scenario `s` within `budget` bytes: the scenario's
    log_stride, or the smallest multiple of it whose rows (len(CHANNELS)
    float64 each) fit the budget."""
    if isinstance(budget, bool) or not isinstance(budget, (int, float, np.integer,
                                                           np.floating)):
        raise ParameterError(f"log budget = {budget!r} is not a number of bytes")
    row = len(CHANNELS) * 8
    if not (math.isfinite(budget) and budget >= 2 * row):
        raise ParameterError(f"log budget = {budget!r} B is outside its valid range "
                             f"[{2 * row}, inf) B: two rows of the log ({row} B each)")
    budget = int(budget)
    n, stride = s.n_steps, s.log_stride
    # ceil(n / (stride k)) <= max_rows  <=>  k >= n / (stride max_rows)
    k = max(1, -(-n // (stride * (budget // row))))
    rows = -(-n // (stride * k))
    return LogPlan(stride * k, rows, rows * row, budget, k > 1)


def simulate(
    s: Scenario,
    progress: Callable[[float], None] | None = None,
    chunk_seconds: float = 0.05,
    design=None,
    log_budget: int = DEFAULT_LOG_BUDGET,
) -> Result:
    """Run scenario `s` to its duration; `progress(fraction)` after each
    chunk. `design` overrides the LCL observer's design choices
    (:class:`smodrive.design.yao2022.ObserverDesignPars`). The log takes at
    most `log_budget` bytes: a longer one logs every k-th sample instead
    (:func:`log_plan`; the stride is ``Result.log_stride``).

    A wrong argument is a ParameterError naming it and what it must be:

    >>> simulate("yang2018.fig7a")
    Traceback (most recent call last):
    ...
    smodrive.params.ParameterError: s = 'yang2018.fig7a' (str) is not a Scenario: a catalogue name is smodrive.scenarios.catalogue()['yang2018.fig7a'](), a TOML file smodrive.scenario_io.load_scenario('yang2018.fig7a')
    """
    if not isinstance(s, Scenario):
        if isinstance(s, str):
            how = (f"a catalogue name is smodrive.scenarios.catalogue()[{s!r}](), a TOML file "
                   f"smodrive.scenario_io.load_scenario({s!r})")
        elif isinstance(s, dict):
            how = ("a dict of TOML keys is smodrive.scenario_io.scenario_from_dict(d), a "
                   "catalogue entry smodrive.scenarios.catalogue()[name]()")
        else:
            how = ("build one with smodrive.params.Scenario(...), take one of the catalogue "
                   "(smodrive.scenarios.catalogue()[name]()) or read a TOML file "
                   "(smodrive.scenario_io.load_scenario(path))")
        shown = repr(s) if len(repr(s)) <= 60 else repr(s)[:57] + "..."
        raise ParameterError(f"s = {shown} ({type(s).__name__}) is not a Scenario: {how}")
    if progress is not None and not callable(progress):
        raise ParameterError(f"progress = {progress!r} must be None or a function of the "
                             "fraction done")
    if (isinstance(chunk_seconds, bool)
            or not isinstance(chunk_seconds, (int, float, np.integer, np.floating))
            or not (math.isfinite(chunk_seconds) and chunk_seconds > 0)):
        raise ParameterError(f"chunk_seconds = {chunk_seconds!r} is outside its valid range "
                             "(0, inf) s (simulated time per call into C)")
    if design is not None:
        from .design.yao2022 import ObserverDesignPars

        if not isinstance(design, ObserverDesignPars):
            raise ParameterError(f"design = {design!r} ({type(design).__name__}) must be None "
                                 "(the design from the scenario's controller.Q) or a "
                                 "smodrive.design.yao2022.ObserverDesignPars")
    eng = Engine(s, design)
    plan = log_plan(s, log_budget)
    n, stride = s.n_steps, plan.stride
    out = np.zeros((plan.rows, len(CHANNELS)), dtype=np.float64)
    chunk = max(stride, int(chunk_seconds / s.T_sp) // stride * stride)
    done, row = 0, 0
    while done < n:
        m = min(chunk, n - done)
        got = eng.run(m, out, row, stride)
        _check_finite(s, out[row:row + got])  # one chunk at a time: no log-sized temporary
        row += got
        done += m
        if progress is not None:
            progress(done / n)
    out = out[:row]
    status = int(np.max(out[:, CHANNELS.index("status")])) if row else 0
    return Result(s, out, status, eng.faults(), log_stride=stride, samples=n)


def _check_finite(s: Scenario, rows: np.ndarray) -> None:
    bad = ~np.isfinite(rows)
    if bad.any():
        first = int(np.argmax(bad.any(axis=1)))
        raise SimulationError(
            f"{s.name}: non-finite values at t = {rows[first, 0]:.6f} s "
            f"in {[c for c, b in zip(CHANNELS, bad[first]) if b]}"
        )
