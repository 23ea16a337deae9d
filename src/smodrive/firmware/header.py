"""The design a firmware gets from a scenario: the table of every derived
controller value with its source (:func:`design_rows`), the LCL drive's
offline design with its checks (:func:`lcl_design`) and a C99 header of the
drive's configuration with, for the LCL observers, their tables
(:func:`drive_header`). What ``smodrive design`` prints and writes."""

from __future__ import annotations

import dataclasses
import math
import re
import warnings
from typing import Any

from ..design import cheader
from ..design import yao2022 as dz
from ..engine import LAWS, TABLE_RPM, design_over_table, drive_config, lcl_observer_tables
from ..engine.marshal import placement_warning
from ..model import ControllerCfg, LclFilterPars, ParameterError
from ..model.derive import DERIVED_FIELDS
from ..model.margins import TABLE1_SPEED_PM, sensorless_margin
from .build import fixed_flags

# ------------------------------------------------------- the whole design --

@dataclasses.dataclass(frozen=True)
class DesignRow:
    """One value of the drive's design: the field, its value and unit, and
    where it comes from ("derived: <rule>", "set", or a rule of the drive)."""

    name: str
    value: Any
    unit: str
    origin: str


def _unit(name: str) -> str:
    f = ControllerCfg.__dataclass_fields__.get(name)
    return f.metadata.get("unit", "") if f is not None else ""


def design_rows(s: Any) -> list[DesignRow]:
    """Every motor-specific value of scenario `s`'s controller, with its
    origin, and the gains the drive computes from them (what `smodrive
    design` prints)."""
    c = s.controller
    derived = {n: src for n, _, src in c.derived}
    rows = []
    for name in DERIVED_FIELDS:
        v = getattr(c, name)
        if v is None:
            continue
        rows.append(DesignRow(f"controller.{name}", v, _unit(name),
                              f"derived: {derived[name]}" if name in derived else "set"))
    k_p, k_i = c.current_pi_gains()
    if c.k_p_i is None:
        rows.append(DesignRow("current PI k_p_i", k_p, "V/A", "current_bw L_s_hat"))
    if c.k_i_i is None:
        rows.append(DesignRow("current PI k_i_i", k_i, "V/(A s)", "current_bw R_s_hat"))
    rows.append(DesignRow("decoupling L_dec", s.L_dec, "H",
                          "set" if c.L_dec is not None else
                          "L_s_hat" + ("" if s.lcl is None else " + lcl.L1 + lcl.L2o")))
    k_pw, k_iw = c.pi_gains(s.motor.n_p)
    rows.append(DesignRow("speed PI k_p_w", k_pw, "A s/rad",
                          f"2 speed_bw / b, b = 1.5 n_p^2 psi_r_pi / J_hat, speed_bw = "
                          f"{c.speed_bw:g} rad/s"))
    rows.append(DesignRow("speed PI k_i_w", k_iw, "A/rad", "speed_bw^2 / b"))
    margin = sensorless_margin(s)
    if margin is not None:
        rows.append(DesignRow(
            "speed loop phase margin", margin[0], "deg",
            f"the PI on the rotor, w_lpf, the SMDO's w_c as a lag and the delay "
            f"(smodrive.model.margins); Table I's design: {TABLE1_SPEED_PM:.1f} deg"
            + ("; below it the speed rings on the ADC's noise (docs/design_from_motor.md)"
               if margin[1] else "")))
    rows.append(DesignRow("overcurrent trip i_trip", min(2.5 * c.i_max, 1e5)
                          if c.i_trip is None else c.i_trip, "A",
                          "2.5 i_max" if c.i_trip is None else "set"))
    return rows


def _lcl_c1_range(s: Any) -> tuple[float, float]:
    """The range of lcl.C1 in which the observers' filter model resonates
    below the Nyquist frequency (and the field's own range)."""
    lo, hi, _ = LclFilterPars.__dataclass_fields__["C1"].metadata["range"]
    L1, L2 = s.lcl.L1, s.lcl.L2o + s.controller.L_s_hat
    w_nyq = math.pi / s.T_sp
    c_min = (L1 + L2) / (L1 * L2 * w_nyq**2) / s.controller.C1_hat_ratio
    return max(lo, c_min), hi


def lcl_design(s: Any, build: bool = True) -> dict[str, Any]:
    """The LCL drive's offline design from the scenario's plant sections
    (yao2022 steps 1-5 and the observer tables over speed, from the
    controller's estimates, which follow [motor]; the filter; the PLL).
    Any failure is a ParameterError naming the field. Returns the tables
    and what `smodrive design` prints."""
    c = s.controller
    if s.lcl is None:
        raise ParameterError("lcl: the scenario has no LCL filter section; the LCL observers' "
                             "design needs one")
    lo, hi = _lcl_c1_range(s)
    L2 = s.lcl.L2o + c.L_s_hat
    f_res = s.lcl.f_res(c.L_s_hat, c.C1_hat_ratio)
    if not lo <= s.lcl.C1 <= hi:
        raise ParameterError(
            f"lcl.C1 = {s.lcl.C1!r} is outside its valid range [{lo:.4g}, {hi:g}] F for the LCL "
            f"observers at T_sp = {s.T_sp!r} s: with lcl.L1 = {s.lcl.L1:g} H, lcl.L2o + "
            f"controller.L_s_hat = {L2:g} H (and C1_hat_ratio = {c.C1_hat_ratio:g}) the filter "
            f"resonates at {f_res:.4g} Hz, above the Nyquist frequency {0.5 / s.T_sp:g} Hz "
            "the observer's discrete model must resolve")
    pll = dz.PllPars(k_theta=c.k_theta, k_omega=c.k_omega, k_a=c.k_a, T=s.T_sp) \
        if min(c.k_theta, c.k_omega, c.k_a) > 0 else None
    if pll is None:
        raise ParameterError(
            f"controller.k_theta, k_omega, k_a = {c.k_theta:g}, {c.k_omega:g}, {c.k_a:g}: the "
            "PLL of eq. (48) needs all three above 0")
    poles = dz.pll_closed_loop(pll).poles()
    if not all(abs(p) < 1.0 for p in poles):
        raise ParameterError(
            f"controller.k_theta = {c.k_theta!r} (with k_omega = {c.k_omega!r}, k_a = "
            f"{c.k_a!r}, T_sp = {s.T_sp!r} s): the PLL of eq. (48)-(50) is unstable (closed-"
            f"loop pole at |z| = {max(abs(p) for p in poles):.4g}); its valid range is where "
            "all poles lie inside the unit circle")
    # ParameterError naming the fields on failure
    tables = lcl_observer_tables(s) if build else None
    return {"f_res_hz": f_res, "pll_bandwidth_hz": dz.pll_bandwidth_hz(pll),
            "table_rpm": (float(TABLE_RPM[0]), float(TABLE_RPM[-1]), len(TABLE_RPM)),
            "tables": tables}


def _c_num(x: float) -> str:
    s = f"{float(x):.9g}"
    return s + ("" if any(ch in s for ch in ".eEn") else ".0") + "f"


def drive_header(s: Any, name: str = "SMD") -> str:
    """A C99 header for firmware: the drive's configuration
    (smd_drive_config, SI units, electrical speeds) as one #define a field,
    and for the LCL observers their tables (design.cheader)."""
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        raise ParameterError(f"--name {name!r} is not a C identifier")
    s.check_controller()
    cfg = drive_config(s)
    derived = {n for n, _, _ in s.controller.derived}
    out = [f"/* Generated by smodrive design from scenario {s.name!r}: do not edit.",
           f" * Motor: R_s = {s.motor.R_s!r} ohm, L_s = {s.motor.L_s!r} H, psi_r = "
           f"{s.motor.psi_r!r} Wb, n_p = {s.motor.n_p}, J = {s.motor.J!r} kg m^2.",
           " * The smd_drive_config fields (core/include/smodrive/smd_drive.h), SI units,",
           " * electrical speeds; derived from the motor: " + (", ".join(sorted(derived)) or "-"),
           " * A firmware that runs only this composition may compile the core's smd_drive.c",
           " * with it fixed (smd_drive.h, \"A composition fixed at compile time\"):",
           " *   " + " ".join(fixed_flags(cfg)),
           " */", f"#ifndef {name}_DRIVE_CONFIG_H", f"#define {name}_DRIVE_CONFIG_H",
           ""]
    pm = sensorless_margin(s)
    if pm is not None and pm[1]:
        # (a servo's 9 deg were in design's table only, not beside the gains it judges)
        out[-4:-4] = [f" * Note: the sensorless speed loop's phase margin is {pm[0]:.1f} deg, below "
                      f"yang2018 Table I's design's {TABLE1_SPEED_PM:.1f} deg: its speed rings on",
                      " * the ADC's noise (SMD_K_P_W, SMD_K_I_W; docs/design_from_motor.md)."]
    for field, _ in cfg._fields_:
        v = getattr(cfg, field)
        if field in ("smo", "lin"):
            continue
        text = str(int(v)) if isinstance(v, int) else _c_num(v)
        out.append(f"#define {name}_{field.upper()} {text}")
    if s.lcl is not None and s.controller.position in ("lcl_smo_pll", "lcl_linear"):
        c = s.controller
        est = dataclasses.replace(s.motor, R_s=c.R_s_hat, L_s=c.L_s_hat, psi_r=c.psi_r_hat)
        plant = dz.DesignPlant(est, dataclasses.replace(s.lcl, C1=s.lcl.C1 * c.C1_hat_ratio),
                               s.T_sp)
        lcl_design(s, build=False)  # the checks, with the fields named
        tables, n_short = design_over_table(plant, dz.ObserverDesignPars(Q=tuple(c.Q)))
        if n_short:  # one warning naming the field, not scipy's one a placement
            warnings.warn(placement_warning(s, n_short), UserWarning, stacklevel=2)
        # every field of smd_lcl_smo_config but its table pointer (the law and the
        # decimation had been left out: a tde17 drive refreshed every 8 samples and the
        # paper's got the same header), and the tables' speed grid (electrical rad/s)
        w = tables.w
        for k, v in (("LAW", LAWS[c.law]), ("N", int(w.size)), ("W_MIN", float(w[0])),
                     ("DW", float(w[1] - w[0])), ("Q1", c.Q[0]), ("Q2", c.Q[1]),
                     ("BW_REL2", c.bw_rel[0]), ("BW_REL3", c.bw_rel[1]),
                     ("W_BP_MIN", c.w_M_bp_min * s.motor.n_p),
                     ("DECIMATION", int(c.smo_decimation))):
            out.append(f"#define {name}_SMO_{k} {v if isinstance(v, int) else _c_num(v)}")
        out += ["", f"#endif /* {name}_DRIVE_CONFIG_H */", ""]
        return "\n".join(out) + cheader.format_c_header(tables, f"{name}_LCL")
    out += ["", f"#endif /* {name}_DRIVE_CONFIG_H */", ""]
    return "\n".join(out)
