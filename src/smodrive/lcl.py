"""LCL-filtered high-speed SPMSM drive (yao2022): scenario parameters and
simulation through the C engine (smd_lcl_plant + smd_lcl_drive).

The plant gets the true parameters; the observer is designed offline
(:mod:`smodrive.design.yao2022`) from the controller's estimates, packed into
the C lookup-table layout (``smd_lcl_model``) and interpolated in C.

Example
-------
>>> s = LclScenario(duration=0.01, n_M0=100e3, w_M_ref_rpm=Profile.const(100e3))
>>> r = simulate_lcl(s)
>>> r["w_M"].shape
(200,)
"""

from __future__ import annotations

import ctypes as ct
import dataclasses
import functools
import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from . import _ffi
from .design import yao2022 as dz
from .params import RPM, ParameterError, Profile, _Validated, choice, flag, num
from .simulate import SimulationError, _pwl

lib = _ffi.lib
real = _ffi.real


class LclDriveConfig(ct.Structure):
    _fields_ = [
        ("mode", ct.c_int),
        ("T", real),
        ("k_p_i", real),
        ("k_i_i", real),
        ("L_dec", real),
        ("R_v", real),
        ("emf_ff", ct.c_int),
        ("k_p_w", real),
        ("k_i_w", real),
        ("i_max", real),
        ("speed_loop", ct.c_int),
        ("k_theta", real),
        ("k_omega", real),
        ("k_a", real),
        ("i_start", real),
        ("a_start", real),
        ("w_handover", real),
        ("svm_limit", ct.c_int),
        ("pos_source", ct.c_int),
    ]


class LclObsConfig(ct.Structure):
    _fields_ = [
        ("law", ct.c_int),
        ("table", ct.c_void_p),
        ("n", ct.c_int),
        ("w_min", ct.c_float),
        ("dw", ct.c_float),
        ("Q1", ct.c_float),
        ("Q2", ct.c_float),
        ("bw_rel2", ct.c_float),
        ("bw_rel3", ct.c_float),
        ("w_bp_min", ct.c_float),
        ("lin_table", ct.c_void_p),
        ("lin_n", ct.c_int),
        ("lin_w_min", ct.c_float),
        ("lin_dw", ct.c_float),
    ]


class LclStart(ct.Structure):
    _fields_ = [("phase", ct.c_int), ("theta0", ct.c_double), ("w0", ct.c_double),
                ("i_delta0", ct.c_double)]


def _sig(name, restype, *args):
    f = getattr(lib, name)
    f.restype = restype
    f.argtypes = list(args)


_sig("smd_sizeof_lcl_engine", ct.c_ulong)
_sig("smd_sizeof_lcl_drive_config", ct.c_ulong)
_sig("smd_sizeof_lcl_obs_config", ct.c_ulong)
_sig("smd_sizeof_lcl_model", ct.c_ulong)
_sig("smd_sizeof_linobs_model", ct.c_ulong)
_sig("smd_lcl_log_channel_name", ct.c_char_p, ct.c_int)
_sig("smd_sizeof_lcl_config", ct.c_ulong)

from .lcl_plant import LclConfig  # noqa: E402  (mirror of smd_lcl_config)

_sig("smd_lcl_engine_init", ct.c_int, ct.c_void_p, ct.POINTER(LclConfig),
     ct.POINTER(LclDriveConfig), ct.POINTER(LclObsConfig), ct.POINTER(_ffi.Profiles),
     ct.POINTER(LclStart))
_sig("smd_lcl_engine_run", ct.c_long, ct.c_void_p, ct.c_long, ct.POINTER(ct.c_double), ct.c_long)

N_MODEL = 36 + 12 + 12 + 16 + 4 * 9 + 1  # floats in smd_lcl_model
N_LIN = 16 * 3 + 8  # floats in smd_linobs_model
N_LOG = 35
CHANNELS = tuple(lib.smd_lcl_log_channel_name(i).decode() for i in range(N_LOG))
for _name, _cls in (("lcl_drive_config", LclDriveConfig), ("lcl_obs_config", LclObsConfig)):
    if getattr(lib, f"smd_sizeof_{_name}")() != ct.sizeof(_cls):
        raise ImportError(f"smodrive binding out of date: {_name} size mismatch")
if lib.smd_sizeof_lcl_model() != 4 * N_MODEL or lib.smd_sizeof_linobs_model() != 4 * N_LIN:
    raise ImportError("smodrive binding out of date: smd_lcl_model / smd_linobs_model size")
if CHANNELS[-1] != "status":
    raise ImportError("smodrive binding out of date: LCL log channels")


# ------------------------------------------------------------- parameters --

@dataclass(frozen=True)
class LclPlantPars(_Validated):
    """True plant (yao2022 Table II; mechanics and load assumed, see
    docs/assumptions.md)."""

    _section = "plant"
    R: float = num(0.023, 1e-6, 1e3, "ohm", "winding resistance", lo_open=True)
    L1: float = num(54e-6, 1e-8, 1.0, "H", "inverter-side inductance")
    L2o: float = num(27.5e-6, 0.0, 1.0, "H", "machine-side filter inductance")
    Ls: float = num(24e-6, 1e-8, 1.0, "H", "machine inductance")
    C1: float = num(31.48e-6, 1e-9, 1.0, "F", "filter capacitance")
    psi_m: float = num(0.0012, 0.0, 10.0, "Wb", "PM flux")
    n_p: int = num(1, 1, 100, "", "pole pairs", integer=True)
    J: float = num(1e-5, 1e-9, 1e3, "kg m^2", "inertia (assumed)")
    B: float = num(0.0, 0.0, 1e3, "N m s/rad", "viscous friction (assumed)")
    k_fan: float = num(4.9e-10, 0.0, 1.0, "N m s^2/rad^2", "fan load, Table IV fit")
    u_dc: float = num(65.0, 0.0, 1e4, "V", "DC-link voltage", lo_open=True)
    pwm: str = choice("carrier", ("carrier", "averaged"), "PWM model")
    t_dead: float = num(0.0, 0.0, 1e-5, "s", "dead time (assumed 0: not discussed)")

    def design_pars(self, T: float) -> dz.LclMotorPars:
        return dz.LclMotorPars(R=self.R, L1=self.L1, L2o=self.L2o, Ls=self.Ls, C1=self.C1,
                               psi_m=self.psi_m, n_p=self.n_p, T=T, u_dc=self.u_dc)


@dataclass(frozen=True)
class LclAdcCfg(_Validated):
    _section = "adc"
    gain_i1: tuple[float, float, float] = num((1.0, 1.0, 1.0), 0.5, 2.0, "", "i_1 phase gains")
    gain_i2: tuple[float, float, float] = num((1.0, 1.0, 1.0), 0.5, 2.0, "", "i_2 phase gains")
    offset_i1: tuple[float, float, float] = num((0.0, 0.0, 0.0), -1e3, 1e3, "A", "i_1 offsets")
    offset_i2: tuple[float, float, float] = num((0.0, 0.0, 0.0), -1e3, 1e3, "A", "i_2 offsets")
    noise: float = num(0.02, 0.0, 1e3, "A", "white noise RMS (assumed)")
    bits: int = num(12, 0, 24, "", "resolution", integer=True)
    full_scale: float = num(60.0, 1e-6, 1e6, "A", "+- range (assumed)")
    seed: int = num(1, 0, 2**63 - 1, "", "noise seed", integer=True)


@dataclass(frozen=True)
class LclControllerCfg(_Validated):
    _section = "controller"
    mode: str = choice("sensorless", ("sensorless", "sensored"), "angle source")
    law: str = choice("proposed", ("proposed", "tde17", "tde18"), "reaching law")
    observer: str = choice("smo", ("smo", "linear"), "position source: sliding-mode or linear")
    C1_hat_ratio: float = num(1.0, 0.1, 10.0, "", "observer's capacitance / true (Fig. 23)")
    k_p_i: float = num(0.35, 0.0, 1e4, "V/A", "current PI gain (assumed)")
    k_i_i: float = num(600.0, 0.0, 1e9, "V/(A s)", "current PI integral gain (assumed)")
    R_v: float = num(0.0, 0.0, 1e4, "V/A", "virtual resistance on i_1 - i_2 (assumed)")
    emf_ff: bool = flag(True, "feed the estimated EMF forward")
    speed_bw: float = num(60.0, 0.0, 1e4, "rad/s", "speed-loop bandwidth (assumed)",
                          lo_open=True)
    i_max: float = num(45.0, 0.0, 1e4, "A", "current limit (assumed)", lo_open=True)
    speed_loop: bool = flag(True, "i_delta from the speed PI (else the i_q_ref profile)")
    k_theta: float = num(0.1, 0.0, 2.0, "", "PLL, eq. (50)")
    k_omega: float = num(10.0, 0.0, 1e9, "1/s", "PLL, eq. (50)")
    k_a: float = num(10.0, 0.0, 1e12, "1/s^2", "PLL, eq. (50)")
    i_start: float = num(15.0, 0.0, 1e4, "A", "start-up current (assumed)")
    a_start_rpm_s: float = num(5e3, 0.0, 1e9, "r/min/s", "start-up acceleration (assumed)")
    n_handover: float = num(5e3, 0.0, 1e6, "r/min", "handover speed (assumed)")
    Q: tuple[float, float] = num((0.5, 0.5), -0.999, 0.999, "", "reaching-law Q (Table III)")
    bw_rel: tuple[float, float] = num((0.2, 0.2), 1e-3, 1.9, "", "band-pass widths / f_e")
    n_bp_min: float = num(5e3, 0.0, 1e6, "r/min", "band-pass suppression above (assumed)")


@dataclass(frozen=True)
class LclScenario(_Validated):
    _section = "scenario"
    name: str = "lcl"
    T_sp: float = num(50e-6, 1e-7, 1.0, "s", "sampling period (Table II)")
    duration: float = num(0.5, 0.0, 1e4, "s", "simulated time", lo_open=True)
    n_M0: float = num(0.0, -1e6, 1e6, "r/min", "initial speed")
    theta_r0: float = num(0.0, -1e3, 1e3, "rad", "initial angle")
    w_M_ref_rpm: Profile = field(default_factory=lambda: Profile.const(0.0))
    i_d_ref: Profile = field(default_factory=lambda: Profile.const(0.0))
    i_q_ref: Profile = field(default_factory=lambda: Profile.const(0.0))
    T_ext: Profile = field(default_factory=lambda: Profile.const(0.0))
    start_open_loop: bool = flag(False, "begin with the forced-angle start-up")
    with_linear_observer: bool = flag(False, "run the linear observer (65) alongside")
    log_stride: int = num(1, 1, 10**6, "", "log every N samples", integer=True)
    plant: LclPlantPars = field(default_factory=LclPlantPars)
    adc: LclAdcCfg = field(default_factory=LclAdcCfg)
    controller: LclControllerCfg = field(default_factory=LclControllerCfg)

    @property
    def n_steps(self) -> int:
        return int(round(self.duration / self.T_sp))

    def replace(self, **kw) -> "LclScenario":
        return dataclasses.replace(self, **kw)


# ------------------------------------------------------------- the tables --

TABLE_RPM = np.arange(-110e3, 110e3 + 1.0, 1000.0)


@functools.lru_cache(maxsize=8)
def observer_tables(pars: dz.LclMotorPars, design: dz.ObserverDesignPars) -> tuple[np.ndarray,
                                                                                 np.ndarray, float,
                                                                                 float]:
    """Design tables packed in the C layouts: (models (n, N_MODEL) float32,
    linear observer (n, N_LIN) float32, w_min, dw)."""
    t = dz.design_tables(pars, TABLE_RPM, design)
    n = t.w.size
    m = np.zeros((n, N_MODEL), dtype=np.float32)
    lin = np.zeros((n, N_LIN), dtype=np.float32)
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
    dw = float(t.w[1] - t.w[0])
    return m, lin, float(t.w[0]), dw


# -------------------------------------------------------------- simulate ---

@dataclass
class LclResult:
    scenario: LclScenario
    data: np.ndarray
    status: int

    def __getitem__(self, name: str) -> np.ndarray:
        return self.data[:, CHANNELS.index(name)]

    @property
    def t(self) -> np.ndarray:
        return self["t"]

    def window(self, t0: float, t1: float) -> np.ndarray:
        return (self.t >= t0) & (self.t < t1)

    @property
    def theta_error(self) -> np.ndarray:
        d = self["theta_r"] - self["theta_hat"]
        return (d + np.pi) % (2 * np.pi) - np.pi

    @property
    def n_hat_rpm(self) -> np.ndarray:
        return self["w_hat"] / self.scenario.plant.n_p / RPM

    @property
    def n_rpm(self) -> np.ndarray:
        return self["w_M"] / RPM


LAWS = {"proposed": 0, "tde17": 1, "tde18": 2}


class LclEngine:
    def __init__(self, s: LclScenario, design: dz.ObserverDesignPars | None = None):
        self.scenario = s
        p, c = s.plant, s.controller
        design = design or dz.ObserverDesignPars(Q=tuple(c.Q))
        est = dataclasses.replace(p.design_pars(s.T_sp), C1=p.C1 * c.C1_hat_ratio)
        self._m, self._lin, w_min, dw = observer_tables(est, design)
        from .lcl_plant import lcl_config

        w_M0 = s.n_M0 * RPM
        pc = lcl_config(
            R=p.R, L1=p.L1, L2o=p.L2o, Ls=p.Ls, C1=p.C1, psi_m=p.psi_m, n_p=p.n_p, J=p.J, B=p.B,
            k_fan=p.k_fan, u_dc=p.u_dc, T_sw=s.T_sp, pwm=p.pwm,
            t_dead=p.t_dead, adc_gain_i1=s.adc.gain_i1, adc_offset_i1=s.adc.offset_i1,
            adc_gain_i2=s.adc.gain_i2, adc_offset_i2=s.adc.offset_i2, adc_noise=s.adc.noise,
            adc_bits=s.adc.bits, adc_full_scale=s.adc.full_scale, seed=s.adc.seed, w_M0=w_M0,
            theta_r0=s.theta_r0,
        )
        # warm start: the steady-state current that carries the load
        T_L0 = p.k_fan * w_M0 * abs(w_M0) + p.B * w_M0 + s.T_ext(0.0)
        k_t = 1.5 * p.n_p * p.psi_m
        i_q0 = 0.0 if s.start_open_loop or k_t == 0 else T_L0 / k_t
        if not s.start_open_loop:
            # steady state of the LCL in the rotor frame with i_2 = j i_q0:
            # u_c = j w psi + (R + j w L2) i_2, i_1 = i_2 + j w C1 u_c
            w_e = w_M0 * p.n_p
            L2 = p.L2o + p.Ls
            uc = 1j * w_e * p.psi_m + (p.R + 1j * w_e * L2) * 1j * i_q0
            i1 = 1j * i_q0 + 1j * w_e * p.C1 * uc
            pc.i2_q0 = i_q0
            pc.uc_d0, pc.uc_q0 = uc.real, uc.imag
            pc.i1_d0, pc.i1_q0 = i1.real, i1.imag
        self._pc = pc
        L_tot = p.L1 + p.L2o + p.Ls
        b = 1.5 * p.n_p**2 * p.psi_m / p.J
        dc = LclDriveConfig(
            mode=0 if c.mode == "sensorless" else 1, T=s.T_sp, k_p_i=c.k_p_i, k_i_i=c.k_i_i,
            L_dec=L_tot, R_v=c.R_v, emf_ff=int(c.emf_ff), k_p_w=2 * c.speed_bw / b,
            k_i_w=c.speed_bw**2 / b, i_max=c.i_max, speed_loop=int(c.speed_loop),
            k_theta=c.k_theta, k_omega=c.k_omega, k_a=c.k_a,
            i_start=c.i_start if s.start_open_loop else 0.0,
            a_start=c.a_start_rpm_s * RPM * p.n_p, w_handover=c.n_handover * RPM * p.n_p,
            svm_limit=1, pos_source=1 if c.observer == "linear" else 0,
        )
        self._dc = dc
        oc = LclObsConfig(
            law=LAWS[c.law], table=self._m.ctypes.data, n=self._m.shape[0], w_min=w_min, dw=dw,
            Q1=c.Q[0], Q2=c.Q[1], bw_rel2=c.bw_rel[0], bw_rel3=c.bw_rel[1],
            w_bp_min=c.n_bp_min * RPM * p.n_p,
            lin_table=(self._lin.ctypes.data
                       if s.with_linear_observer or c.observer == "linear" else None),
            lin_n=self._lin.shape[0], lin_w_min=w_min, lin_dw=dw,
        )
        self._oc = oc
        pr = _ffi.Profiles()
        pr.w_M_ref = _pwl(s.w_M_ref_rpm, RPM)
        pr.T_ext = _pwl(s.T_ext)
        pr.T_brake = _pwl(Profile.const(0.0))
        pr.i_d_ref = _pwl(s.i_d_ref)
        pr.i_q_ref = _pwl(s.i_q_ref)
        self._pr = pr
        st = LclStart(phase=0 if s.start_open_loop else 1, theta0=s.theta_r0,
                      w0=w_M0 * p.n_p, i_delta0=i_q0)
        self._st = st
        self._buf = (ct.c_double * math.ceil(lib.smd_sizeof_lcl_engine() / 8 + 1))()
        rc = lib.smd_lcl_engine_init(self._buf, ct.byref(pc), ct.byref(dc), ct.byref(oc),
                                     ct.byref(pr), ct.byref(st))
        if rc != 0:
            raise ParameterError(f"LCL engine rejected the configuration (code {rc}: "
                                 f"{_describe(rc)})")

    def run(self, n: int, out: np.ndarray, row0: int, stride: int) -> int:
        ptr = out[row0:].ctypes.data_as(ct.POINTER(ct.c_double))
        return int(lib.smd_lcl_engine_run(self._buf, n, ptr, stride))

    def run_nolog(self, n: int) -> None:
        """Run n samples without logging (benchmarks)."""
        lib.smd_lcl_engine_run(self._buf, n, None, 1)


def _describe(rc: int) -> str:
    if 1000 <= rc < 2000:
        return "plant parameter " + lib.smd_lcl_field(rc - 1000).decode()
    if 2000 <= rc < 3000:
        return "observer: " + _ffi.status_str(rc - 2000)
    if 3000 <= rc < 4000:
        return "drive: " + _ffi.status_str(rc - 3000)
    if 4000 <= rc < 5000:
        return "linear observer: " + _ffi.status_str(rc - 4000)
    return "profile"


_sig("smd_lcl_field", ct.c_char_p, ct.c_int)


def simulate_lcl(s: LclScenario, progress: Callable[[float], None] | None = None,
                 design: dz.ObserverDesignPars | None = None,
                 chunk_seconds: float = 0.02) -> LclResult:
    eng = LclEngine(s, design)
    n = s.n_steps
    stride = s.log_stride
    rows = math.ceil(n / stride)
    out = np.zeros((rows, N_LOG))
    chunk = max(stride, int(chunk_seconds / s.T_sp) // stride * stride)
    done = row = 0
    while done < n:
        m = min(chunk, n - done)
        row += eng.run(m, out, row, stride)
        done += m
        if progress is not None:
            progress(done / n)
    out = out[:row]
    bad = ~np.isfinite(out)
    if bad.any():
        first = int(np.argmax(bad.any(axis=1)))
        raise SimulationError(f"{s.name}: non-finite values at t = {out[first, 0]:.6f} s")
    status = int(np.max(out[:, -1])) if row else 0
    return LclResult(s, out, status)
