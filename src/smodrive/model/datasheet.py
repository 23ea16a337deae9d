"""What a motor data sheet's quantities are in smodrive's [motor] (the
papers' model: a surface-PM motor, yang2018 eq. (1) and yao2022 eq. (1),
space vectors of the phases' peak values): the hint an unknown [motor] key
gets. A new user typing a data sheet writes poles, K_t, K_e, L_d and L_q,
a line-to-line resistance, the rated current or torque: each was answered
with the list of known keys only."""

from __future__ import annotations

#: 1,000 r/min in rad/s (a back-EMF constant's speed)
_KRPM = 1000.0 * 2.0 * 3.141592653589793 / 60.0

_POLES = ("n_p = poles / 2: smodrive counts pole pairs (an 8-pole motor: n_p = 4)")
_KT = ("psi_r = K_t / (1.5 n_p) for a torque constant per ampere of phase peak, "
       "K_t / (1.5 sqrt(2) n_p) per ampere RMS (the usual data sheet's): T = 1.5 n_p psi_r i_q, "
       "i_q a peak value")
_KE = (f"psi_r = K_e / (sqrt(3/2) n_p {_KRPM:.2f}) for a back-EMF constant in volts line to line "
       f"RMS per 1,000 r/min, K_e / (sqrt(3) n_p {_KRPM:.2f}) line to line peak (the phase's "
       "peak EMF is n_p w_M psi_r)")
_LDQ = ("smodrive's motor is a surface-PM one, L_d = L_q = L_s (yang2018 eq. (1)); a salient "
        "motor is outside both papers' model: L_s = L_q is the nearest (i_d_ref = 0, the q "
        "current's dynamics; the SMDO takes the rest as a disturbance), untested")
_RLL = "R_s = R_LL / 2 for a resistance measured line to line (a star connection)"
_LLL = "L_s = L_LL / 2 for an inductance measured line to line (a star connection)"
_RATED = ("P_N = T_N w_M_N with w_M_N_rpm (smodrive derives the rated current from them and "
          "psi_r: I_N = T_N / (1.5 n_p psi_r), a peak value)")

#: key (lower case, without "_", "-" and spaces) -> the hint
HINTS = {
    "poles": _POLES, "polecount": _POLES, "npoles": _POLES, "p": _POLES.replace(
        "n_p = poles / 2", "n_p (or poles / 2, if p counts poles)"),
    "polepairs": "n_p: the pole pairs", "pp": "n_p: the pole pairs", "np": "n_p: the pole pairs",
    "kt": _KT, "torqueconstant": _KT,
    "ke": _KE, "kv": _KE + "; a K_v in r/min per volt is 1,000 / K_e of the same convention",
    "backemf": _KE, "emfconstant": _KE,
    "ld": _LDQ, "lq": _LDQ, "lsd": _LDQ, "lsq": _LDQ,
    "l": "L_s: the stator (phase) inductance, H", "ls": "L_s", "lph": "L_s", "lphase": "L_s",
    "lll": _LLL, "lline": _LLL, "llinetoline": _LLL,
    "r": "R_s: the stator (phase) resistance, ohm", "rs": "R_s", "rph": "R_s", "rphase": "R_s",
    "rll": _RLL, "rline": _RLL, "rlinetoline": _RLL,
    "psi": "psi_r: the magnet's flux linkage, Wb (phase peak)", "psim": "psi_r", "psipm": "psi_r",
    "lambda": "psi_r", "lambdam": "psi_r", "flux": "psi_r",
    "tn": _RATED, "trated": _RATED, "ratedtorque": _RATED, "torque": _RATED,
    "in": _RATED, "irated": _RATED, "ratedcurrent": _RATED, "current": _RATED,
    "pn": "P_N: the rated (shaft) power, W", "power": "P_N", "prated": "P_N",
    "n": "w_M_N_rpm: the rated speed in r/min", "rpm": "w_M_N_rpm", "nn": "w_M_N_rpm",
    "nrated": "w_M_N_rpm", "speed": "w_M_N_rpm", "ratedspeed": "w_M_N_rpm",
    "jload": "J: the inertia of the rotor and its load together, kg m^2",
    "jrotor": "J: the inertia of the rotor and its load together, kg m^2",
    "inertia": "J: kg m^2, rotor and load", "friction": "B: viscous friction, N m s/rad",
}


_FSW = ("the switching frequency is the top-level T_sp = 1 / f_sw (before any table): one "
        "sample a carrier period, regular sampling")
#: [inverter] keys a data sheet or another tool uses -> the hint
INVERTER_HINTS = {"fsw": _FSW, "fpwm": _FSW, "fs": _FSW, "pwmfrequency": _FSW,
                  "switchingfrequency": _FSW, "tsw": _FSW, "tpwm": _FSW,
                  "vdc": "did you mean u_dc (the DC link, V)?", "udc": "did you mean u_dc?",
                  "deadtime": "did you mean t_dead (s)?", "td": "did you mean t_dead (s)?"}

#: [motor]'s keys (a hint that is one of them, or begins with one and a colon, renames)
_KEYS = ("R_s", "L_s", "psi_r", "n_p", "J", "B", "P_N", "w_M_N_rpm")


def hint(key: str, section: str = "motor") -> str:
    """The data-sheet hint for key `key` of [motor] or [inverter] ("" if
    none): "did you mean" for another name of one of its keys, the
    conversion for a data sheet's quantity."""
    norm = "".join(c for c in key.lower() if c not in "_- ")
    if section == "inverter":
        h = INVERTER_HINTS.get(norm, "")
        return f"; {h}" if h.startswith("did") else (f"; {key}: {h}" if h else "")
    h = HINTS.get(norm, "")
    name, _, what = h.partition(": ")
    if name in _KEYS:
        return f"; did you mean {name}" + (f" ({what})" if what else "") + "?"
    return f"; {key} looks like a data sheet's: {h}" if h else ""
