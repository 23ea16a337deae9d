"""One runnable experiment: :class:`Scenario`, the plant sections, the
composed controller and the references; on construction the controller
values the user left unset are derived from the motor
(:mod:`smodrive.model.derive`).

One :class:`Scenario` describes every drive smodrive simulates: the plant
sections (``motor``, the optional ``lcl`` filter, ``inverter``, ``adc``,
``load``) and the composed controller (``controller.current``,
``controller.position``, ``controller.start``).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field
from typing import Any

from . import derive, lcl_bounds, reach
from .fields import LCL_TABLE_RPM, RPM, ParameterError, Profile, _Validated, flag, num

#: a rated speed within this share of the LCL observers' tables leaves room for a step's
#: overshoot (yao2022's motor, rated 100 kr/min: 0.91 of them)
LCL_TABLE_MARGIN = 0.95
from .pars import (
    AdcCfg,
    ControllerCfg,
    InverterCfg,
    LclFilterPars,
    LoadCfg,
    MotorPars,
    yang2018_mode,
)


@dataclass(frozen=True)
class Scenario(_Validated):
    """One runnable experiment: a plant (motor, optional LCL filter,
    inverter, ADC, load), a composed controller and the references."""

    _section = "scenario"
    _profile_ranges = {"R_s_scale": (0.01, 100.0, "", "the motor's R_s over time as a multiple "
                                     "of motor.R_s (winding heating)")}
    name: str = "scenario"
    T_sp: float = num(100e-6, 1e-7, 1.0, "s", "sampling (= carrier) period")
    duration: float = num(1.0, 0.0, 1e4, "s", "simulated time", lo_open=True)
    w_M0: float = num(0.0, -9.9e4, 9.9e4, "rad/s", "initial speed (mechanical)")
    theta_r0: float = num(0.0, -1e3, 1e3, "rad", "initial electrical angle")
    w_M_ref: Profile = field(default_factory=lambda: Profile.const(0.0))  # rad/s
    i_d_ref: Profile = field(default_factory=lambda: Profile.const(0.0))
    i_q_ref: Profile = field(default_factory=lambda: Profile.const(0.0))
    i_d_sin_amp: float = num(0.0, 0.0, 1e4, "A", "sinusoid added to the i_d reference")
    i_d_sin_freq: float = num(0.0, 0.0, 1e7, "Hz", "its frequency")
    R_s_scale: Profile = field(default_factory=lambda: Profile.const(1.0))  # winding heating
    log_stride: int = num(1, 1, 10**6, "", "log every N samples", integer=True)
    faults_expected: bool = flag(False, "a run that ends in a fault is what the scenario "
                                        "tests (the CLI exits 0)")
    warm_start: bool = flag(True, "start in steady state: current and speed PI carry the load")
    motor: MotorPars = field(default_factory=MotorPars)
    lcl: LclFilterPars | None = None
    controller: ControllerCfg = field(default_factory=ControllerCfg)
    inverter: InverterCfg = field(default_factory=InverterCfg)
    adc: AdcCfg = field(default_factory=AdcCfg)
    load: LoadCfg = field(default_factory=LoadCfg)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise ParameterError(f"scenario.name = {self.name!r} is not a string (the label of "
                                 "the run, also used in its file names)")
        for sec in ("motor", "controller", "inverter", "adc", "load"):
            cls = type(self).__dataclass_fields__[sec].default_factory  # type: ignore[misc]
            if not isinstance(getattr(self, sec), cls):
                raise ParameterError(
                    f"scenario.{sec} = {getattr(self, sec)!r} is not a {cls.__name__}")
        super().__post_init__()
        if self.lcl is not None and not isinstance(self.lcl, LclFilterPars):
            raise ParameterError(f"scenario.lcl = {self.lcl!r} is not an LclFilterPars or None")
        # the controller's motor-specific values the user left unset, derived
        # from the motor (smodrive.model.derive; the record: controller.derived)
        object.__setattr__(self, "adc", derive.resolve_adc(self.adc, self.motor))
        object.__setattr__(self, "controller", derive.resolve(
            self.controller, self.motor, T_sp=self.T_sp, lcl=self.lcl,
            adc_full_scale=self.adc.full_scale, plant=derive.plant_of(self)))
        # plant limits that depend on more than one field
        if self.inverter.t_dead > 0.25 * self.T_sp:
            raise ParameterError(
                f"inverter.t_dead = {self.inverter.t_dead!r} is outside its valid range "
                f"[0, T_sp/4 = {0.25 * self.T_sp:g}] s")

    @property
    def L_dec(self) -> float:
        """Decoupling inductance of the current PI, H."""
        c = self.controller
        if c.L_dec is not None:
            return c.L_dec
        if self.lcl is None:
            return c.L_s_hat
        return self.lcl.L1 + self.lcl.L2o + c.L_s_hat

    @property
    def decouple_ref(self) -> bool:
        """Whether the current PI decouples with the current reference
        (controller.decouple; auto: behind the filter, where the measured
        current's delayed cross-coupling w L_dec at rated speed outgrows the
        PI's proportional gain: yao2022's motor, 1.1 ohm against 0.35, no load
        at 100 kr/min, oscillated at 2.3 kHz)."""
        c = self.controller
        if c.current != "pi" or c.decouple == "measured":
            return False
        if c.decouple == "reference":
            return True
        k_p, _ = c.current_pi_gains()
        return self.lcl is not None and self.motor.w_M_N * self.motor.n_p * self.L_dec > k_p

    def held_below_handover(self) -> float | None:
        """A speed reference (rad/s) the sensorless drive with an I/f start is
        asked to hold, for 0.5 s or to the end, between 0 and its handover
        speed, where it stays on the forced start (an invented 12 V pump at
        450 r/min against its 1,186 r/min handover ran its whole run on I/f,
        1.6 I_N and 51 deg off, status 0); None: none."""
        c, p = self.controller, self.w_M_ref
        if c.start != "if" or c.position == "encoder" or not c.w_M_handover:
            return None
        t, y = list(p.t) + [max(self.duration, p.t[-1] + 0.5)], list(p.y) + [p.y[-1]]
        for k in range(len(y) - 1):
            if y[k] == y[k + 1] and t[k + 1] - t[k] >= 0.5 and \
                    0.0 < abs(y[k]) < c.w_M_handover:
                return float(y[k])
        return None

    def check_controller(self) -> None:
        """Controller limits that depend on more than one field (the ones the
        C core's init checks too); run by load_scenario and before every
        simulation, not for plant-only use."""
        T, c = self.T_sp, self.controller
        nyq = math.pi / T
        for msg in derive.override_warnings(c, self.motor, T_sp=T, lcl=self.lcl,
                                                adc_full_scale=self.adc.full_scale,
                                                plant=derive.plant_of(self)):
            warnings.warn(f"{self.name}: {msg}", UserWarning, stacklevel=2)
        low = self.held_below_handover()
        if low is not None:
            warnings.warn(
                f"{self.name}: the speed reference holds {low / RPM:.4g} r/min, below the "
                f"handover speed controller.w_M_handover = {c.w_M_handover / RPM:.4g} r/min: a "
                "start toward it stays on the forced start (I/f: open loop, the rotor's angle "
                f"unknown, i_start = {c.i_start:.3g} A whatever the load) and never hands over "
                "to the sensorless source; a reference at or above the handover speed, or the "
                "encoder", UserWarning, stacklevel=2)
        lcl_src = c.position in ("lcl_smo_pll", "lcl_linear")
        if lcl_src and self.lcl is None:
            raise ParameterError(
                f"controller.position = {c.position!r} needs the LCL filter: add an [lcl] "
                "section (L1, L2o, C1) or choose encoder / smdo_emf")
        if self.lcl is not None and c.current != "pi":
            raise ParameterError(
                f"controller.current = {c.current!r} with the LCL filter: only 'pi' (with "
                "active damping) is designed for the filtered drive")
        if self.lcl is not None and c.position == "smdo_emf":
            raise ParameterError(
                "controller.position = 'smdo_emf' with the LCL filter: the SMDO's model "
                "(yang2018 eq. (15)) has no filter; choose lcl_smo_pll, lcl_linear or encoder")
        res = lcl_bounds.resonance_warning(self)
        if res is not None:
            warnings.warn(f"{self.name}: {res}", UserWarning, stacklevel=2)
        if c.rls_i_inj > 0.0 and c.position not in ("encoder", "smdo_emf"):
            raise ParameterError(
                f"controller.rls_i_inj = {c.rls_i_inj!r} with position = {c.position!r}: the "
                "R_s / psi_r tracker's model has no LCL filter (position = 'encoder' or "
                "'smdo_emf' without a filter; docs/commissioning.md)")
        if self.lcl is None and c.R_v > 0.0:
            raise ParameterError(
                f"controller.R_v = {c.R_v!r}: active damping needs the LCL filter's current "
                "i_1; set it to 0 without the filter")
        if c.t_handover / T > 2**31 - 1:
            raise ParameterError(
                f"controller.t_handover = {c.t_handover!r} is too long: at most "
                f"{(2**31 - 1) * T:g} s at T_sp = {T:g} s")
        k_p, k_i = c.pi_gains(self.motor.n_p)
        if not (k_p <= 1e6 and k_i <= 1e9):
            raise ParameterError(
                f"controller.speed_bw = {c.speed_bw!r} with J_hat = {c.J_hat!r} gives speed-PI "
                f"gains k_p = {k_p:g}, k_i = {k_i:g}, beyond the core's limits 1e6 and 1e9")
        if c.current == "pi":
            k_p, k_i = c.current_pi_gains()
            if not (k_p <= 1e4 and k_i <= 1e9):
                raise ParameterError(
                    f"controller.current_bw = {c.current_bw!r} gives current-PI gains "
                    f"k_p_i = {k_p:g} V/A, k_i_i = {k_i:g} V/(A s), beyond the core's limits "
                    "1e4 and 1e9")
            if self.L_dec > 10.0:
                # L_dec unset is derived: name the key the user wrote (with the filter: the
                # term of the sum that takes most of it, lcl_bounds)
                raise ParameterError(lcl_bounds.decoupling_error(self) or (
                    f"{'controller.L_dec' if c.L_dec is not None else 'controller.L_s_hat'} = "
                    f"{self.L_dec:g} H is outside the valid range [0, 10] H of the decoupling "
                    "inductance (controller.L_dec)"))
        if c.t_dead_comp > 0.25 * T:
            raise ParameterError(
                f"controller.t_dead_comp = {c.t_dead_comp!r} is outside its valid range "
                f"[0, T_sp/4 = {0.25 * T:g}] s")
        if c.start == "if" and c.w_M_handover * self.motor.n_p > nyq:
            raise ParameterError(
                f"controller.w_M_handover = {c.w_M_handover!r} is outside its valid range: "
                f"w_M_handover n_p must be at most pi/T_sp = {nyq:g} rad/s")
        if c.w_M_if_enter > 0.0:
            if c.position == "encoder":
                raise ParameterError(
                    f"controller.w_M_if_enter = {c.w_M_if_enter!r}: the return to I/f through "
                    "zero speed is for a sensorless position source; set it to 0 with the "
                    "encoder")
            if not c.w_M_if_enter < c.w_M_handover:
                raise ParameterError(
                    f"controller.w_M_if_enter = {c.w_M_if_enter!r} must be below "
                    f"w_M_handover = {c.w_M_handover!r} (the hysteresis of the return to I/f)")
        if 0.0 < c.u_dc_max_ratio <= c.u_dc_min_ratio:
            raise ParameterError(
                f"controller.u_dc_max_ratio = {c.u_dc_max_ratio!r} must exceed "
                f"u_dc_min_ratio = {c.u_dc_min_ratio!r} (or be 0: off)")
        if c.t_lock / T > 1e6:
            raise ParameterError(
                f"controller.t_lock = {c.t_lock!r} is too long: at most {1e6 * T:g} s "
                f"at T_sp = {T:g} s")
        if c.position == "smdo_emf":
            if c.w_lpf >= nyq:
                raise ParameterError(
                    f"controller.w_lpf = {c.w_lpf!r} is outside its valid range "
                    f"(0, pi/T_sp = {nyq:g}) rad/s")
            w_max = c.w_M_max * self.motor.n_p
            if not (c.w_hys < w_max <= nyq):
                raise ParameterError(
                    f"controller.w_M_max = {c.w_M_max!r} is outside its valid range: the "
                    f"electrical speed limit w_M_max n_p must lie in (w_hys = {c.w_hys:g}, "
                    f"pi/T_sp = {nyq:g}] rad/s")
            a, b = 1.0 - c.w_c * T, w_max * T
            if a * a + b * b >= 1.0:
                raise ParameterError(
                    f"controller.w_c = {c.w_c!r} with w_M_max = {c.w_M_max!r}: the filter (36) "
                    "would be unstable, |1 - w_c T_sp + j w_max T_sp| must be below 1")
        uses_smdo = c.current == "robust_dbpc" or c.position == "smdo_emf"
        if uses_smdo and (c.l + c.lambda_min / c.rho) * T >= 2.0:
            gain = c.l + c.lambda_min / c.rho
            derived = {d[0] for d in c.derived}
            how = ", ".join(f"{n} = {getattr(c, n):.4g}" + (" derived" if n in derived else "")
                            for n in ("l", "lambda_min", "rho"))
            raise ParameterError(
                f"T_sp = {T:g} s is too long for the SMDO's gains (controller.{how}): "
                f"(l + lambda_min / rho) T_sp = {gain * T:.3g} must be below 2 for a stable "
                f"SMDO, T_sp below {2.0 / gain:.3g} s")
        if uses_smdo and c.w_c * T >= 1.0:
            raise ParameterError(
                f"controller.w_c = {c.w_c!r} is outside its valid range (0, 1/T_sp = {1 / T:g})"
                " rad/s")
        self.check_run()

    def check_run(self) -> None:
        """Limits of a run as a whole (part of :meth:`check_controller`):
        samples to simulate and log, a back-EMF for the sensorless position
        sources, and for the LCL observers a sampling period and speeds
        their offline design covers."""
        T, c = self.T_sp, self.controller
        if self.duration < 2.0 * T:
            raise ParameterError(
                f"duration = {self.duration!r} is outside its valid range [2 T_sp = {2 * T:g}, "
                f"1e4] s: the run would have {self.n_steps} control samples")
        n = self.n_steps
        if self.log_stride >= n:
            raise ParameterError(
                f"log_stride = {self.log_stride!r} is outside its valid range [1, {n - 1}] for "
                f"the {n} control samples of the run (duration / T_sp): the log would hold the "
                "initial state only")
        if c.position != "encoder" and self.motor.psi_r == 0.0:
            raise ParameterError(
                f"motor.psi_r = 0.0 with controller.position = {c.position!r}: a machine "
                "without magnet flux has no back-EMF to estimate the angle from; motor.psi_r "
                "must be above 0 (or choose position = 'encoder')")
        for msg in reach.check_reach(self):
            warnings.warn(f"{self.name}: {msg}", UserWarning, stacklevel=3)
        if c.position not in ("lcl_smo_pll", "lcl_linear") or self.lcl is None:
            return
        # the observers' model: lcl.L1, lcl.L2o + L_s_hat, C1_hat_ratio lcl.C1 (eq. (1)-(3))
        f_res = self.lcl.f_res(c.L_s_hat, c.C1_hat_ratio)
        if T > 0.5 / f_res:
            raise ParameterError(
                f"T_sp = {T!r} is outside its valid range (0, 1/(2 f_res) = {0.5 / f_res:g}] s "
                f"for the LCL observers: their filter model (lcl.L1, lcl.L2o + "
                f"controller.L_s_hat, lcl.C1 x controller.C1_hat_ratio) resonates at f_res = "
                f"{f_res:g} Hz, which the sampling must resolve (Nyquist)")
        lim = LCL_TABLE_RPM * RPM
        if self.motor.w_M_N > LCL_TABLE_MARGIN * lim:
            # (an invented 150 kr/min turbine motor designed without a word, then every run at
            # rated speed refused; one rated 110 kr/min overshot its step to 115.7 kr/min, past
            # where the estimate stops, and lost the rotor)
            warnings.warn(
                f"{self.name}: motor.w_M_N = {self.motor.w_M_N / RPM:g} r/min is beyond "
                f"{LCL_TABLE_MARGIN:g} of the LCL observers' tables, which cover "
                f"[{-LCL_TABLE_RPM:g}, {LCL_TABLE_RPM:g}] r/min (smodrive.model.LCL_TABLE_RPM): a "
                "reference beyond them is refused, and a step's overshoot near their edge leaves "
                "them (the speed estimate stops there); this motor cannot be run up to its rated "
                "speed on lcl_smo_pll or lcl_linear", UserWarning, stacklevel=2)
        for name, verb, values in (("w_M0", "=", (self.w_M0,)),
                                   ("w_M_ref", "reaches", self.w_M_ref.y)):
            w = max(values, key=abs)
            if abs(w) > lim:
                raise ParameterError(
                    f"{name} {verb} {w / RPM:g} r/min ({w:g} rad/s), beyond the LCL observers' "
                    f"tables, which cover [{-LCL_TABLE_RPM:g}, {LCL_TABLE_RPM:g}] r/min: keep "
                    f"{name} (or {name}_rpm) within them")

    @property
    def n_steps(self) -> int:
        return int(round(self.duration / self.T_sp))

    def replace(self, **changes: Any) -> "Scenario":
        return dataclasses.replace(self, **changes)

    def with_controller(self, **changes: Any) -> "Scenario":
        """A copy with controller fields changed (``mode`` expands to yang2018's
        parts)."""
        if "mode" in changes:
            changes = {**yang2018_mode(changes.pop("mode")), **changes}
        return self.replace(controller=dataclasses.replace(self.controller, **changes))


