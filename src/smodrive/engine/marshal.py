"""The C configuration structs of one scenario: the plant
(:func:`plant_config`), the drive (:func:`drive_config`, with the LCL
observers' lookup tables designed offline by :mod:`smodrive.design.yao2022`
and packed in the C layouts) and the reference profiles."""

from __future__ import annotations

import ctypes as ct
import dataclasses
import functools
import math
import warnings

import numpy as np

from ..design import yao2022 as dz
from ..design.observer_layout import OBSERVER_FIELDS
from ..model import LCL_TABLE_RPM, LclFilterPars, MotorPars, ParameterError, Profile, Scenario
from .channels import CURRENT, LAWS, POSITION, START
from . import _ffi
from ._structs import DESIGN_FIELDS

TABLE_RPM = np.arange(-LCL_TABLE_RPM, LCL_TABLE_RPM + 1.0, 1000.0)  # LCL observer tables, r/min


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
    c.adc_sensors = adc.sensors
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


def _block(a: np.ndarray, block) -> np.ndarray:
    """Design array `a` at one speed, or its block ((r0, r1), (c0, c1))."""
    if block is None:
        return np.asarray(a)
    (r0, r1), (c0, c1) = block
    return np.asarray(a)[r0:r1, c0:c1]


def _pack(t: dz.DesignTables, k: int, fields) -> np.ndarray:
    """Row k of a table model: its design fields (DESIGN_FIELDS, the header's
    @design annotations) in C order, row-major."""
    return np.concatenate([_block(getattr(t, name)[k], block).ravel()
                           for _, name, block in fields])


def packing_errors(design_fields=None) -> list[str]:
    """Every C array of a table model whose design field (its @design
    annotation) is not in OBSERVER_FIELDS, not real, or of another size."""
    design_fields = DESIGN_FIELDS if design_fields is None else design_fields
    layout = {name: (shape, kind) for name, shape, kind, _ in OBSERVER_FIELDS}
    errors = []
    for c_name, fields in design_fields.items():
        cls = _ffi.MIRRORS[c_name]
        for c_field, name, block in fields:
            n_c = getattr(cls, c_field).size // ct.sizeof(_ffi.real)
            if name not in layout or layout[name][1] != "f":
                errors.append(f"{c_name}.{c_field}: @design({name}) is no real field of "
                              "OBSERVER_FIELDS")
                continue
            shape = layout[name][0]
            if block is not None and (len(shape) != 2 or block[0][1] > shape[0]
                                      or block[1][1] > shape[1]):
                errors.append(f"{c_name}.{c_field}: block {block} outside {name} {shape}")
                continue
            n_d = _block(np.zeros(shape), block).size
            if n_d != n_c:
                errors.append(f"{c_name}.{c_field}: {n_c} reals in C, {n_d} in {name}"
                              f"{'' if block is None else str(list(block))} {shape}")
    return errors


if packing_errors():
    raise ImportError("smodrive: the observer tables' layout in the headers (@design) "
                      "disagrees with smodrive.design.observer_layout:\n  "
                      + "\n  ".join(packing_errors()))


#: how scipy's place_poles (Tits-Yang) says its eigenvector iteration stopped short
NOT_CONVERGED = "Convergence was not reached"
#: the inverter side's resonance a sample (w_1 T_sp) below which a design that stopped short
#: is put down to lcl.L1 or lcl.C1: three times scipy's edge (about 0.03, yao2022's drive)
W1T_MIN = 0.1


def design_over_table(plant, design) -> tuple[dz.DesignTables, int]:
    """The observers' design (:func:`smodrive.design.yao2022.design_tables`)
    at every speed of TABLE_RPM, and how many of its pole placements stopped
    short of a robust one: scipy warns once a placement (a 1 H lcl.L1: about
    120 raw warnings), counted here and said once, naming the field, by
    :func:`lcl_observer_tables`. Other warnings pass."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t = dz.design_tables(plant, TABLE_RPM, design)
    n = 0
    for w in caught:
        if issubclass(w.category, UserWarning) and str(w.message).startswith(NOT_CONVERGED):
            n += 1
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return t, n


def placement_warning(s: Scenario, n: int) -> str:
    """The one warning for `n` pole placements of scenario `s`'s observer
    design that stopped short (:func:`design_over_table`), naming the field
    that leads there."""
    f, c = s.lcl, s.controller
    # step 3 reaches the filter's states through the capacitor only: its pair's
    # controllability measured 0.7 (w_1 T_sp)^2, w_1 the inverter side's own resonance
    # (1.0 at Table II, where w_1 T_sp = 1.2; scipy stops short below about 0.03)
    C1 = f.C1 * c.C1_hat_ratio
    w1T = s.T_sp / math.sqrt(f.L1 * C1)
    ref = LclFilterPars()
    if w1T >= W1T_MIN:
        why = ("it is designed from T_sp, lcl.L1, lcl.L2o, lcl.C1 x controller.C1_hat_ratio, "
               "controller.L_s_hat, controller.R_s_hat and controller.Q")
    else:
        key, value, unit, top = (  # the one further from Table II's
            ("lcl.L1", f.L1, "H", s.T_sp ** 2 / (W1T_MIN ** 2 * C1))
            if f.L1 / ref.L1 >= f.C1 / ref.C1
            else ("lcl.C1", f.C1, "F", s.T_sp ** 2 / (W1T_MIN ** 2 * f.L1 * c.C1_hat_ratio)))
        why = (f"{key} = {value!r} {unit} leads there: the observer reaches the filter's states "
               "through the capacitor only, whose coupling within a sample falls as (w_1 "
               "T_sp)^2, w_1 = 1 / sqrt(lcl.L1 lcl.C1 C1_hat_ratio) the inverter side's own "
               f"resonance, here w_1 T_sp = {w1T:.3g} rad (yao2022 Table II: "
               f"{50e-6 / math.sqrt(ref.L1 * ref.C1):.2g}); {key} at most {top:.3g} {unit} "
               f"keeps w_1 T_sp at {W1T_MIN:g} or more")
    return (f"{s.name}: the LCL observers' design did not converge to a robust pole placement "
            f"(yao2022 step 3, eq. (21); scipy's place_poles) at {n} placements over the tables' "
            f"{TABLE_RPM.size} speeds: the poles are placed (checked), but the closed loop's "
            f"eigenvectors are ill-conditioned and its gains large; {why}")


def observer_tables(plant, design) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The LCL observers' tables for `plant`
    (:class:`smodrive.design.yao2022.DesignPlant`: motor, filter, T_sp),
    designed offline at every 1000 r/min of TABLE_RPM and packed in the C
    layouts: (models (n, N_MODEL) float32, linear observer (n, N_LIN)
    float32, w_min, dw)."""
    return _observer_tables(plant, design)[0]


@functools.lru_cache(maxsize=8)
def _observer_tables(plant, design):
    """observer_tables, and the placements that stopped short (design_over_table)."""
    t, n_short = design_over_table(plant, design)
    n = t.w.size
    m = np.zeros((n, _ffi.N_MODEL), dtype=np.float32)
    lin = np.zeros((n, _ffi.N_LIN), dtype=np.float32)
    for k in range(n):
        m[k] = _pack(t, k, DESIGN_FIELDS["smd_lcl_model"])
        lin[k] = _pack(t, k, DESIGN_FIELDS["smd_linobs_model"])
    if not (np.all(np.isfinite(m)) and np.all(np.isfinite(lin))):
        raise ParameterError("observer design produced non-finite matrices")
    m.flags.writeable = lin.flags.writeable = False
    return (m, lin, float(t.w[0]), float(t.w[1] - t.w[0])), n_short


def lcl_observer_tables(s: Scenario, design=None):
    """observer_tables for scenario `s`: designed from the controller's
    estimates (L_s_hat, R_s_hat, psi_r_hat) and the filter with the
    observer's capacitance C1_hat_ratio C1, at the scenario's T_sp."""
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
        plant = dz.DesignPlant(est_motor, est_lcl, s.T_sp)
        out, n = _observer_tables(plant, design)
        if n:
            warnings.warn(placement_warning(s, n), UserWarning, stacklevel=2)
        return out
    except (ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
        raise ParameterError(
            f"{s.name}: the LCL observers' design failed: {exc}. It is designed from T_sp = "
            f"{s.T_sp!r} s, lcl.L1, lcl.L2o, lcl.C1 x controller.C1_hat_ratio, "
            "controller.L_s_hat, controller.R_s_hat and controller.Q (motor.n_p scales its "
            "speed axis)") from None


def _every_field(cls, values: dict, who: str):
    """Mirror `cls` with every field set from `values` (field -> value). A
    field of the C struct that `values` lacks, or a name it does not have,
    raises: a field added to the header fails loudly here instead of being
    left 0 (the mirrors are generated from the header)."""
    names = [n for n, *_ in cls._fields_]
    missing = [n for n in names if n not in values]
    unknown = [n for n in values if n not in names]
    if missing or unknown:
        raise RuntimeError(
            f"{who} does not fill {cls._c_name_} field by field: "
            + "; ".join(([f"unset: {', '.join(missing)}"] if missing else [])
                        + ([f"no such field: {', '.join(unknown)}"] if unknown else []))
            + f" (the fields are those of the C header, mirrored in {cls.__module__})")
    c = cls()
    for n in names:
        setattr(c, n, values[n])
    return c


def drive_config(s: Scenario, tables=None) -> _ffi.DriveConfig:
    """The drive's C config (SI units, electrical angles and speeds), every
    field of smd_drive_config set (a field left unset raises RuntimeError).
    For the LCL observers `tables` (from :func:`lcl_observer_tables`) must be
    kept alive as long as the config is in use."""
    k, T = s.controller, s.T_sp
    n_p = s.motor.n_p
    sensorless = k.position != "encoder"
    k_p_i, k_i_i = k.current_pi_gains()
    k_p_w, k_i_w = k.pi_gains(n_p)
    if tables is not None:
        m, lin, w_min, dw = tables
        smo = _every_field(_ffi.SmoConfig, dict(
            law=LAWS[k.law], table=m.ctypes.data, n=m.shape[0], w_min=w_min, dw=dw,
            Q1=k.Q[0], Q2=k.Q[1], bw_rel2=k.bw_rel[0], bw_rel3=k.bw_rel[1],
            w_bp_min=k.w_M_bp_min * n_p, decimation=k.smo_decimation), "drive_config")
        lin_c = _every_field(_ffi.LinConfig, dict(
            table=lin.ctypes.data, n=lin.shape[0], w_min=w_min, dw=dw), "drive_config")
    else:  # no LCL observer: their configs all 0
        smo, lin_c = _ffi.SmoConfig(), _ffi.LinConfig()
    return _every_field(_ffi.DriveConfig, dict(
        current=CURRENT[k.current], position=POSITION[k.position], start=START[k.start],
        lcl=0 if s.lcl is None else 1,
        T_sp=T,
        L_s_hat=k.L_s_hat, R_s_hat=k.R_s_hat, psi_r_hat=k.psi_r_hat,
        lambda_min=k.lambda_min, l=k.l, w_c=k.w_c, rho=k.rho,
        smdo_euler=1 if k.smdo_euler else 0,
        w_lpf=k.w_lpf, w_hys=k.w_hys, w_max=k.w_M_max * n_p,
        k_p_i=k_p_i, k_i_i=k_i_i, L_dec=s.L_dec, R_v=k.R_v, dec_ref=1 if s.decouple_ref else 0,
        emf_ff=1 if k.emf_ff else 0,
        speed_loop=1 if k.speed_loop else 0,
        k_p_w=k_p_w, k_i_w=k_i_w, i_max=k.i_max,
        speed_decimation=k.speed_decimation,
        k_theta=k.k_theta, k_omega=k.k_omega, k_a=k.k_a,
        smo=smo, lin=lin_c,
        handover=int(round(k.t_handover / T)) if k.start == "handover" else 0,
        i_start=k.i_start, a_start=k.a_M_start * n_p, w_handover=k.w_M_handover * n_p,
        svm_limit=1 if s.inverter.svm_limit == "hexagon" else 0,
        t_dead_comp=k.t_dead_comp, i_dtc=k.i_dtc,
        i_trip=min(2.5 * k.i_max, 1e5) if k.i_trip is None else k.i_trip,
        u_dc_min=k.u_dc_min_ratio * s.inverter.u_dc,
        u_dc_max=k.u_dc_max_ratio * s.inverter.u_dc,
        safe_state=1 if k.safe_state == "pwm_off" else 0,
        lock_samples=int(round(k.t_lock / T)) if sensorless else 0,
        lock_ratio=k.lock_ratio,
        w_lock_min=k.w_M_lock_min * n_p,
        w_if_enter=k.w_M_if_enter * n_p,
        a_ref=k.a_M_ref * n_p,
        dwell=int(round(k.t_dwell / T)),
        chatter_max=k.chatter_max,
        chatter_window=max(1, int(round(k.t_chatter / T))),
        hunt_max=k.hunt_max if k.speed_loop else 0,
        hunt_window=max(1, int(round(k.t_hunt / T))),
        track_samples=int(round(k.t_track / T)) if k.speed_loop else 0,
        w_track=k.w_M_track * n_p,
        forced_samples=(int(round(k.t_forced / T)) if (k.start == "if" or k.w_M_if_enter > 0)
                        else 0),
        osc_i=k.osc_i, osc_rel=k.osc_rel,
        osc_samples=int(round(k.t_osc / T)) if k.osc_i > 0 else 0,
        restart_max=k.restart_max if (k.start == "if" and k.position == "smdo_emf") else 0,
        restart_window=max(1, int(round(k.t_restart / T))),
        supervise_every=k.supervise_every,
        rls_i_inj=k.rls_i_inj, rls_tau=k.rls_tau,
        rls_half=max(1, int(round(k.rls_t_half / T))),
        rls_w_min=k.rls_w_M_min * n_p,
    ), "drive_config")


def profiles(s: Scenario) -> _ffi.Profiles:
    p = _ffi.Profiles()
    p.w_M_ref = _pwl(s.w_M_ref)
    p.T_ext = _pwl(s.load.T_ext)
    p.T_brake = _pwl(s.load.T_brake)
    p.i_d_ref = _pwl(s.i_d_ref)
    p.i_q_ref = _pwl(s.i_q_ref)
    p.i_d_sin_amp = s.i_d_sin_amp
    p.i_d_sin_freq = s.i_d_sin_freq
    # the motor's R_s over time (winding heating): none when it stays 1
    p.R_s_scale = _pwl(s.R_s_scale) if any(y != 1.0 for y in s.R_s_scale.y) else _ffi.Pwl()
    return p


