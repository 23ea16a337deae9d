"""The names of the engine's codes and logged channels: composition codes,
start-up phases, every logged channel with its unit and meaning, and the
bits of the controller's fault word (core/include/smodrive/smd_drive.h)."""

from __future__ import annotations

from . import _ffi

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

