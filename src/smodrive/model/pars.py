"""The plant's and the controller's parameter sections: the motor (yang2018
Table I by default), the LCL filter, the inverter, the ADC, the load and the
composed controller, each a frozen dataclass whose fields carry their unit
and valid range (:mod:`smodrive.model.fields`).

Speeds are SI (rad/s) in Python (``w_M...`` mechanical rad/s); a TOML key
whose unit is not SI says so in its name (``w_M0_rpm``, ``w_M_ref_rpm``,
``a_M_start_rpm_s``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from .._util import plain as _plain
from .fields import RPM, ParameterError, Profile, _Validated, choice, flag, num

#: yang2018 Table I (the motor of MotorPars() with no field given), with the
#: mechanical values the paper does not give (J, B: docs/assumptions.md)
TABLE1_MOTOR: dict[str, float] = {
    "R_s": 2.25, "L_s": 23.45e-3, "psi_r": 0.4, "n_p": 4, "J": 0.012, "B": 0.002,
    "P_N": 2400.0, "w_M_N": 1500.0 * RPM}
#: the fields of a motor's data sheet that MotorPars never fills in for another machine
MOTOR_REQUIRED = ("R_s", "L_s", "psi_r", "n_p", "J", "P_N", "w_M_N")
#: B left out: viscous friction taking this fraction of the rated torque at rated speed
B_REL = 0.01


@dataclass(frozen=True)
class MotorPars(_Validated):
    """True machine (the plant). ``MotorPars()`` with no field given is
    yang2018 Table I, with the mechanical values the paper does not give (see
    docs/assumptions.md). Any other machine gives every field of its data
    sheet (``R_s``, ``L_s``, ``psi_r``, ``n_p``, ``J``, ``P_N``, ``w_M_N``):
    a field left out is refused, never filled in from Table I, except ``B``
    (viscous friction, rarely on a data sheet), which is then derived as
    ``B_REL T_N / w_M_N`` (1 % of the rated torque at rated speed) and
    recorded in ``derived`` (docs/design_from_motor.md)."""

    _section = "motor"
    R_s: float = num(None, 1e-6, 1e3, "ohm", "stator resistance", lo_open=True)
    L_s: float = num(None, 1e-8, 10.0, "H", "stator inductance")
    psi_r: float = num(None, 0.0, 100.0, "Wb", "PM flux linkage")
    n_p: int = num(None, 1, 100, "", "pole pairs", integer=True)
    J: float = num(None, 1e-9, 1e4, "kg m^2",
                   "inertia of motor and load (Table I: 0.012, assumed; any other motor: "
                   "required)")
    B: float = num(None, 0.0, 1e3, "N m s/rad",
                   "viscous friction (Table I: 0.002, assumed; left out: 0.01 T_N / w_M_N)")
    P_N: float = num(None, 0.0, 1e8, "W", "rated power", lo_open=True)
    w_M_N: float = num(None, 0.1, 1e5, "rad/s", "rated speed (mechanical)")
    # record of the values derived by a rule (not a parameter): (name, value, rule)
    derived: tuple = field(default=(), compare=False, repr=False, metadata={"internal": True})

    def __post_init__(self) -> None:
        super().__post_init__()  # the ranges of the fields given (None: not given)
        rating = ("R_s", "L_s", "psi_r", "n_p", "P_N", "w_M_N")
        given = {n for n in TABLE1_MOTOR if getattr(self, n) is not None}
        table1 = not (given & set(rating)) or all(
            getattr(self, n) is not None and _plain(getattr(self, n)) == TABLE1_MOTOR[n]
            for n in rating)
        if table1:
            for n, v in TABLE1_MOTOR.items():
                if getattr(self, n) is None:
                    object.__setattr__(self, n, v)
        else:
            missing = [n for n in MOTOR_REQUIRED if getattr(self, n) is None]
            if missing:
                names = ", ".join(f"motor.{n}" for n in missing)
                what = {"J": "J (inertia of rotor and load, kg m^2: the data sheet's rotor "
                             "inertia plus the load's)"}
                detail = "; ".join(what.get(n, n) for n in missing if n in what)
                raise ParameterError(
                    f"{names} {'is' if len(missing) == 1 else 'are'} not given: a motor other "
                    "than yang2018 Table I gives every data-sheet field (R_s, L_s, psi_r, n_p, J, "
                    "P_N, w_M_N; B may be left out), smodrive never fills one in from Table I"
                    + (f"; give {detail}" if detail else ""))
        if self.B is None:
            b = min(B_REL * self.T_N / self.w_M_N, 1e3)
            object.__setattr__(self, "B", b)
            object.__setattr__(self, "derived", (("B", b, f"{B_REL:g} T_N / w_M_N: friction "
                                                 f"{B_REL:.0%} of the rated torque at rated "
                                                 "speed"),))
        elif self.derived and not _same_b(self.derived, self.B):
            object.__setattr__(self, "derived", ())  # B set since: the user's

    @property
    def T_N(self) -> float:
        """Rated torque P_N / (rated mechanical speed), N m."""
        return self.P_N / self.w_M_N

    @property
    def k_t(self) -> float:
        """Torque constant 1.5 n_p psi_r, N m/A."""
        return 1.5 * self.n_p * self.psi_r


def _same_b(derived: tuple, b: Any) -> bool:
    return any(n == "B" and v == b for n, v, _ in derived)


@dataclass(frozen=True)
class LclFilterPars(_Validated):
    """LCL filter between inverter and machine (yao2022 Fig. 1, Table II):
    L1 on the inverter side, C1 across, L2o in series with the machine's L_s."""

    _section = "lcl"
    L1: float = num(54e-6, 1e-8, 10.0, "H", "inverter-side inductance")
    L2o: float = num(27.5e-6, 0.0, 10.0, "H", "machine-side filter inductance")
    C1: float = num(31.48e-6, 1e-10, 1.0, "F", "filter capacitance")

    def f_res(self, L_s: float, C1_ratio: float = 1.0) -> float:
        """The filter's resonance frequency (Hz) with the machine inductance
        `L_s` behind L2o (yao2022 Table II: 5525 Hz), its capacitance taken
        `C1_ratio` times (the observers' model: controller.C1_hat_ratio):
        ``sqrt((L1 + L2) / (L1 L2 C1)) / (2 pi)``, ``L2 = L2o + L_s``, the
        nonzero eigenvalues of the lossless eq. (2); inf for ``L2 = 0`` (no
        machine-side inductance: the capacitor is shorted by the machine's EMF
        source)."""
        L1, L2, C1 = self.L1, self.L2o + L_s, self.C1 * C1_ratio
        try:
            return math.sqrt((L1 + L2) / (L1 * L2 * C1)) / (2.0 * math.pi)
        except (ZeroDivisionError, OverflowError):  # values at the ends of their ranges
            return math.inf


@dataclass(frozen=True)
class InverterCfg(_Validated):
    _section = "inverter"
    u_dc: float = num(540.0, 0.0, 1e5, "V", "DC-link voltage", lo_open=True)
    pwm: str = choice("carrier", ("carrier", "averaged"), "carrier comparison or cycle average")
    t_dead: float = num(2e-6, 0.0, 1e-3, "s", "dead time (assumed)")
    dead_time_model: str = choice(
        "sign", ("sign", "clamp"),
        "dead time near zero current: sign (the diode by the current's sign at the period "
        "start) or clamp (zero-current clamping: a current reaching zero in the dead time stays "
        "there and the open leg follows the back EMF; not with the LCL filter)")
    svm_limit: str = choice("hexagon", ("hexagon", "circle"), "voltage limit of the modulator")


@dataclass(frozen=True)
class AdcCfg(_Validated):
    """Current sensors and ADC: the motor-current channels (i_s; i_2 with the
    filter) and, with the LCL filter, the inverter-side ones (i_1)."""

    _section = "adc"
    gain: tuple[float, float, float] = num((1.0, 1.0, 1.0), 0.5, 2.0, "", "per-phase gain")
    offset: tuple[float, float, float] = num((0.0, 0.0, 0.0), -1e3, 1e3, "A", "per-phase offset")
    gain_i1: tuple[float, float, float] = num((1.0, 1.0, 1.0), 0.5, 2.0, "",
                                              "per-phase gain of the i_1 channels (LCL)")
    offset_i1: tuple[float, float, float] = num((0.0, 0.0, 0.0), -1e3, 1e3, "A",
                                                "per-phase offset of the i_1 channels (LCL)")
    noise: float | None = num(None, 0.0, 1e3, "A",
                              "white-noise standard deviation (assumed; None: 0.08 % of "
                              "full_scale, 0.02 A at Table I)")
    bits: int = num(12, 0, 24, "", "resolution (0: none)", integer=True)
    full_scale: float | None = num(None, 1e-6, 1e6, "A",
                                   "+- input range (assumed; None: sized for the motor, 25 A x "
                                   "I_N / I_N of Table I, 3.9 I_N)")
    seed: int = num(1, 0, 2**63 - 1, "", "noise seed", integer=True)
    n_oversample: int = num(1, 1, 64, "",
                            "conversions averaged a sample (oversampling burst at the carrier "
                            "peak, its duration neglected) (assumed)", integer=True)
    sensors: int = num(2, 2, 3, "", "current sensors a channel set: 2 (phases a and b, "
                       "c = -a - b) or 3 (the drive takes the three with their zero sequence "
                       "removed: unequal gains then do not turn the measured current)",
                       integer=True)
    # record of the values derived from the motor (not a parameter): (name, value, rule)
    derived: tuple = field(default=(), compare=False, repr=False, metadata={"internal": True})


CURRENT_CONTROL = ("pi", "dbpc", "robust_dbpc")
POSITION_SOURCES = ("encoder", "smdo_emf", "lcl_smo_pll", "lcl_linear")
STARTS = ("running", "handover", "if")

# yang2018's three drives (Fig. 3) as compositions of parts
YANG2018_MODES = {
    "conventional": dict(current="dbpc", position="encoder", start="running"),
    "robust": dict(current="robust_dbpc", position="encoder", start="running"),
    "sensorless": dict(current="robust_dbpc", position="smdo_emf", start="handover"),
}


@dataclass(frozen=True)
class ControllerCfg(_Validated):
    """The controller: its parts and its knowledge (parameter estimates and
    gains). Defaults: yang2018 Table I and Sec. IV-C; the values the papers
    do not give are assumed (docs/assumptions.md)."""

    _section = "controller"
    current: str = choice("robust_dbpc", CURRENT_CONTROL, "current control")
    position: str = choice("encoder", POSITION_SOURCES, "position source")
    start: str = choice("running", STARTS,
                        "running: the source from t = 0; handover: encoder for t_handover "
                        "first; if: I/f forced start up to w_M_handover")
    # model estimates
    L_s_hat: float | None = num(None, 0.0, 10.0, "H", "inductance estimate (None: motor.L_s)",
                                lo_open=True)
    R_s_hat: float | None = num(None, 0.0, 1e3, "ohm", "resistance estimate (None: motor.R_s)")
    psi_r_hat: float | None = num(None, 0.0, 100.0, "Wb",
                                  "PM flux estimate (DBPC, EMF feed-forward; None: motor.psi_r)")
    # SMDO, yang2018 eq. (34)-(39)
    lambda_min: float | None = num(None, 0.0, 1e7, "A/s",
                                   "SMDO lambda_min, eq. (37) (None: 800 A/s x (E_N / L_s) / "
                                   "(E_N / L_s of Table I), E_N = n_p w_M_N psi_r)")
    l: float = num(1200.0, 0.0, 1e7, "1/s", "SMDO proportional gain l, eq. (21)", lo_open=True)
    w_c: float | None = num(None, 0.0, 1e7, "rad/s", "SMDO filter gain omega_c, eq. (19) (None: "
                            "derived, Table I's 1500 or what keeps the filter stable to twice "
                            "rated speed)", lo_open=True)
    rho: float | None = num(None, 0.0, 1e3, "A", "SMDO smoothing rho, eq. (39) (None: 0.2 A x "
                            "the same ratio, so lambda_min / rho stays 4000 1/s)", lo_open=True)
    smdo_euler: bool = flag(False, "eq. (36) as printed (forward-Euler rotation)")
    # position from the disturbance, eq. (44)-(45)
    w_lpf: float | None = num(None, 0.0, 1e6, "rad/s",
                              "sensorless speed LPF bandwidth (assumed; None: 100 rad/s x the "
                              "speed_bw ratio, docs/design_from_motor.md)", lo_open=True)
    w_hys: float = num(5.0, 0.0, 1e5, "rad/s", "direction hysteresis (electrical)")
    w_M_max: float | None = num(None, 0.0, 1e5, "rad/s",
                                "sensorless speed-estimate limit (mechanical; None: 2 w_M_N, "
                                "within the SMDO filter's stable range)", lo_open=True)
    # current PI (current = "pi")
    current_bw: float = num(2500.0, 0.0, 1e6, "rad/s",
                            "current-loop bandwidth: k_p_i = bw L, k_i_i = bw R (assumed)",
                            lo_open=True)
    k_p_i: float | None = num(None, 0.0, 1e4, "V/A", "current PI gain (None: current_bw L_s_hat; "
                              "with the filter current_bw (L1 + L2o + L_s_hat))")
    k_i_i: float | None = num(None, 0.0, 1e9, "V/(A s)",
                              "current PI integral gain (None: current_bw R_s_hat)")
    L_dec: float | None = num(None, 0.0, 10.0, "H",
                              "decoupling inductance (None: L_s_hat, plus L1 + L2o with the filter)")
    R_v: float = num(0.0, 0.0, 1e4, "V/A", "virtual resistance on i_1 - i_2 (LCL, assumed)")
    decouple: str = choice("auto", ("auto", "measured", "reference"),
                           "the PI's decoupling j w L_dec i with the measured current or the "
                           "reference (auto: the reference behind the filter when w_M_N n_p "
                           "L_dec exceeds k_p_i, else the measured one)")
    emf_ff: bool = flag(True, "feed the position source's EMF estimate forward (PI)")
    # speed loop
    speed_loop: bool = flag(True, "i_q reference from the speed PI (else from i_q_ref)")
    speed_bw: float | None = num(None, 0.0, 1e4, "rad/s",
                                 "speed-loop bandwidth (assumed; None: 60 rad/s x T_N / (J w_M_N) "
                                 "over Table I's, the same load-step dip)", lo_open=True)
    J_hat: float | None = num(None, 1e-9, 1e4, "kg m^2",
                              "inertia used to tune the speed PI (None: motor.J)")
    psi_r_pi: float | None = num(None, 0.0, 100.0, "Wb",
                                 "flux used to tune the speed PI (None: motor.psi_r)", lo_open=True)
    i_max: float | None = num(None, 0.0, 1e5, "A",
                              "current-reference limit (None: 15 A x I_N / (I_N of Table I), "
                              "I_N = T_N / k_t; at most 0.9 adc.full_scale)", lo_open=True)
    speed_decimation: int = num(1, 1, 1000, "", "speed loop runs every N samples", integer=True)
    # PLL, yao2022 eq. (48), (50)
    k_theta: float = num(0.1, 0.0, 2.0, "", "PLL, eq. (50)")
    k_omega: float = num(10.0, 0.0, 1e9, "1/s", "PLL, eq. (50)")
    k_a: float = num(10.0, 0.0, 1e12, "1/s^2", "PLL, eq. (50)")
    # yao2022 observers
    law: str = choice("proposed", ("proposed", "tde17", "tde18"), "reaching law")
    C1_hat_ratio: float = num(1.0, 0.1, 10.0, "", "observer's capacitance / true (Fig. 23)")
    Q: tuple[float, float] = num((0.5, 0.5), -0.999, 0.999, "", "reaching-law Q (Table III)")
    bw_rel: tuple[float, float] = num((0.2, 0.2), 1e-3, 1.9, "", "band-pass widths / f_e")
    w_M_bp_min: float = num(5e3 * RPM, 0.0, 1e5, "rad/s",
                            "band-pass suppression above this speed (mechanical, assumed)")
    smo_decimation: int = num(1, 1, 64, "", "the sliding-mode observer recomputes its model, "
                              "band-pass coefficients and delay taps every this many samples "
                              "(1: every sample, as published; more: the fast build's option, "
                              "docs/firmware.md)", integer=True)
    supervise_every: int = num(1, 1, 64, "", "the supervision's three pieces (loss of lock, "
                               "the start-up and speed criteria, the state's finiteness) "
                               "each run every this many samples, one a sample (1: every "
                               "piece every sample; more: the fast build's option, "
                               "docs/firmware.md)", integer=True)
    # start
    t_handover: float = num(0.0, 0.0, 1e3, "s", "handover: time run on the encoder first")
    i_start: float | None = num(None, 0.0, 1e5, "A",
                                "I/f start current (None: 10 A x I_N / (I_N of Table I), at "
                                "most i_max)")
    a_M_start: float | None = num(None, 0.0, 1e8, "rad/s^2",
                                  "I/f acceleration (mechanical; None: 3000 r/min/s x the "
                                  "smaller of the ratios of T_N / J and of w_M_N to Table I's)")
    w_M_handover: float | None = num(None, 0.0, 1e6, "rad/s",
                                     "I/f: speed of the handover (mechanical; None: 0.1 w_M_N)")
    # modulator
    t_dead_comp: float | None = num(None, 0.0, 1e-3, "s", "dead time compensated by the "
                                    "modulator (None: inverter.t_dead)")
    i_dtc: float | None = num(None, 0.0, 1e5, "A", "linear zone of the compensation (None: "
                              "0.3 A x I_N / (I_N of Table I))", lo_open=True)
    # protection, loss of lock, zero-speed crossing (smd_drive.h; assumed values)
    i_trip: float | None = num(None, 0.0, 1e5, "A",
                               "overcurrent trip, peak phase current (None: 2.5 i_max; 0: off)")
    u_dc_min_ratio: float = num(0.5, 0.0, 1.0, "",
                                "undervoltage trip, fraction of the inverter's u_dc (0: off)")
    u_dc_max_ratio: float = num(1.5, 0.0, 100.0, "",
                                "overvoltage trip, multiple of the inverter's u_dc (0: off)")
    safe_state: str = choice("zero_vector", ("zero_vector", "pwm_off"),
                             "what a fault applies: the zero vector (the terminals shorted) or every "
                             "switch off (the legs on their diodes)")
    t_lock: float = num(0.02, 0.0, 100.0, "s",
                        "loss of lock after this long implausible (sensorless; 0: off)")
    lock_ratio: float = num(3.0, 1.0, 1e3, "", "EMF plausibility band [1/r, r] of |w| psi",
                            lo_open=True)
    w_M_lock_min: float = num(300.0 * RPM, 0.0, 1e6, "rad/s",
                              "no EMF plausibility check below this speed (mechanical)")
    w_M_if_enter: float | None = num(None, 0.0, 1e6, "rad/s",
                                     "sensorless below this speed returns to I/f, through zero "
                                     "(mechanical; 0: never; below w_M_handover; None: derived "
                                     "from the back EMF the source needs, docs/"
                                     "design_from_motor.md)")
    # reference shaping and supervision (smd_drive.h; None: derived, 0: off)
    a_M_ref: float | None = num(None, 0.0, 1e8, "rad/s^2",
                                "speed-reference slew-rate limit (mechanical; None: derived "
                                "from the torque and the speed estimate's lag; 0: off)")
    t_dwell: float | None = num(None, 0.0, 100.0, "s",
                                "least time between two start-up switches (handover, return "
                                "to I/f; None: 4 / w_lpf sensorless, 0 with the encoder)")
    chatter_max: int = num(4, 0, 1000, "", "chatter fault: more start-up switches than this "
                           "within t_chatter (0: off)", integer=True)
    t_chatter: float | None = num(None, 0.0, 1e3, "s",
                                  "window of the chatter count (None: 20 t_dwell, at least "
                                  "0.5 s)")
    hunt_max: int = num(4, 0, 1000, "", "hunting fault: more swings of the speed PI from one "
                        "current limit to the other than this within t_hunt (0: off)",
                        integer=True)
    t_hunt: float | None = num(None, 0.0, 1e3, "s",
                               "window of the hunting count (None: 10 / speed_bw, ten time "
                               "constants of the speed loop)")
    w_M_track: float | None = num(None, 0.0, 1e6, "rad/s",
                                  "speed-tracking fault: farther than this from the reference "
                                  "(mechanical; None: 0.1 w_M_N) ...")
    t_track: float | None = num(None, 0.0, 1e3, "s",
                                "... at the current limit for this long (None: derived from "
                                "the inertia; 0: off)")
    t_forced: float | None = num(None, 0.0, 1e3, "s",
                                 "forced-phase fault: I/f for this long while the reference "
                                 "asks for the source (None: derived from the I/f ramp; 0: off)")
    osc_i: float | None = num(None, 0.0, 1e5, "A",
                              "oscillation warning: current ripple beyond osc_i + osc_rel "
                              "|i_ref| (None: derived from the ADC noise and I_N) ...")
    osc_rel: float = num(0.1, 0.0, 100.0, "", "... (the part relative to the reference) ...")
    t_osc: float = num(0.02, 0.0, 100.0, "s", "... for this long (0: off)")
    restart_max: int = num(2, 0, 100, "", "SMDO position with an I/f start: automatic restarts "
                           "from rest on I/f after a lost lock or a failed start, at most this "
                           "many within t_restart (0: latch at once)", integer=True)
    t_restart: float = num(2.0, 0.0, 1e3, "s", "the window of the restart count")
    rls_i_inj: float = num(0.0, 0.0, 1e5, "A", "online R_s / psi_r tracker (smd_rls.h; with "
                           "position = 'encoder' or 'smdo_emf'): its d-axis square wave of "
                           "+-rls_i_inj (0: no tracker) ...")
    rls_tau: float = num(0.3, 0.0, 1e3, "s", "... the time constant of its forgetting ...",
                         lo_open=True)
    rls_t_half: float | None = num(None, 0.0, 1e3, "s", "... the half period of its square "
                                   "wave (None: 20 ms; with the SMDO's angle pi / (5 "
                                   "speed_bw) within [16 T_sp, 20 ms]) ...", lo_open=True)
    rls_w_M_min: float = num(0.0, 0.0, 1e6, "rad/s", "... psi_r fitted only at |w_M| >= this "
                             "(mechanical)")
    # record of the design from the motor (not a parameter)
    derived: tuple = field(default=(), compare=False, repr=False, metadata={"internal": True})

    def _need(self, *names: str) -> None:
        """A derived field used before a Scenario resolved it is named."""
        for n in names:
            if getattr(self, n) is None:
                raise ParameterError(
                    f"controller.{n} is unset: it is derived from the motor when the "
                    "ControllerCfg is part of a Scenario (Scenario(...).controller), or set it")

    def pi_gains(self, n_p: int) -> tuple[float, float]:
        """Speed PI gains in A per electrical rad/s: the loop
        b / s with b = 1.5 n_p^2 psi / J closed by k_p + k_i / s has the
        characteristic polynomial s^2 + b k_p s + b k_i; both roots at -speed_bw."""
        self._need("psi_r_pi", "J_hat")
        b = 1.5 * n_p**2 * self.psi_r_pi / self.J_hat
        if not (math.isfinite(b) and b > 0.0):
            raise ParameterError(
                f"controller.psi_r_pi = {self.psi_r_pi!r} with J_hat = {self.J_hat!r}: the "
                "speed-loop gain 1.5 n_p^2 psi / J is not a positive finite number")
        return 2.0 * self.speed_bw / b, self.speed_bw**2 / b

    def current_pi_gains(self) -> tuple[float, float]:
        """(k_p_i, k_i_i): the set values, or the internal-model design
        k_p = bw L_s_hat, k_i = bw R_s_hat (the PI zero cancels the R/L pole)."""
        if self.k_p_i is None:
            self._need("L_s_hat")
        if self.k_i_i is None:
            self._need("R_s_hat")
        k_p = self.current_bw * self.L_s_hat if self.k_p_i is None else self.k_p_i
        k_i = self.current_bw * self.R_s_hat if self.k_i_i is None else self.k_i_i
        return k_p, k_i


def yang2018_mode(mode: str) -> dict[str, str]:
    """The parts of yang2018's conventional, robust or sensorless drive."""
    try:
        return dict(YANG2018_MODES[mode])
    except KeyError:
        raise ParameterError(
            f"controller.mode = {mode!r} is not one of {', '.join(YANG2018_MODES)}") from None



@dataclass(frozen=True)
class LoadCfg(_Validated):
    _section = "load"
    _profile_ranges = {"T_brake": (0.0, math.inf, "N m", "a brake torque is a magnitude (the "
                                   "brake opposes the rotation, whichever its sense)")}
    T_brake: Profile = field(default_factory=lambda: Profile.const(0.0))
    T_ext: Profile = field(default_factory=lambda: Profile.const(0.0))
    w_brake_eps: float = num(1.0, 1e-9, 1e3, "rad/s", "brake taper speed (assumed)")
    k_fan: float = num(0.0, 0.0, 1e3, "N m s^2/rad^2", "fan load coefficient")

