"""Where an LCL filter's resonance lets the drive's current loop work, and
the series inductance the current PI can decouple (yao2022 Fig. 1; checked
by :meth:`smodrive.model.Scenario.check_controller`, so before every run and
in `smodrive design`).

The PI controls the machine-side current ``i_2`` through the filter; its
voltage acts 1.5 samples after the current was sampled (one sample of
computation, half a sample of the regular-sampled PWM). yao2022's ref. [20]
(Parker, McGrath, Holmes, "Regions of active damping control for LCL
filters", IEEE TIA 2014) draws the regions this leaves for the resonance
``f_res`` (the undamped resonance is an infinite gain whose phase jumps by
-180 deg; the delay adds ``-1.5 T_sp 2 pi f``, 90 deg at ``f_s / 6`` and 270
deg at ``f_s / 2``):

- without active damping (``controller.R_v = 0``) the loop on ``i_2`` is
  stable for ``f_s / 6 < f_res < f_s / 2``;
- with the capacitor-current feedback ``R_v (i_1 - i_2)`` it is stable for
  ``f_res < f_s / 6`` (above, the delayed feedback is a negative resistance).

The PI works in the rotor frame, where the resonance's two sequences lie
``f_e`` below and above ``f_res``, so at rated speed each bound narrows by
the rated electrical frequency ``f_e = n_p w_M_N / (2 pi)``. Measured on
yao2022's drive (encoder, decoupling with the reference, 0.1 s at constant
speed, the resonance moved by ``lcl.C1``; 2026-11-28): without damping 100
kr/min (the rule: 5000-8333 Hz) ran at 5.0-7.0 kHz and tripped or oscillated
at 4.5, 8.4 and 9.0 kHz, 60 kr/min (4333-9000 Hz) ran at 4.5-9.0 kHz and
tripped at 4.0 and 9.5; with ``R_v`` = 0.3 V/A 60 kr/min (below 2333 Hz) ran
at 2.0 kHz and oscillated at 2.5; Table II's 5525 Hz at T_sp = 40 us tripped
at 100 kr/min (5834 Hz) and ran at 60 (5167 Hz). The preset's measured
decoupling narrows the band further (not covered). And the resonance must
lie above the rated electrical frequency, or the fundamental drives it on
the way to rated speed.
"""

from __future__ import annotations

import math
from typing import Any

#: the loop's delay, samples: one of computation and half of the regular-sampled PWM
DELAY_SAMPLES = 1.5


def resonance_warning(s: Any) -> str | None:
    """What is wrong with scenario `s`'s LCL resonance for its current loop at
    rated speed, naming the resonance, the bound it violates and what to
    change; None without a filter or where it fits."""
    if s.lcl is None:
        return None
    f, m, T = s.lcl, s.motor, s.T_sp
    # the plant's own resonance: the filter and the machine behind it (Table II)
    f_res = f.f_res(m.L_s)
    f_e = m.n_p * m.w_M_N / (2.0 * math.pi)
    f_90 = 1.0 / (4.0 * DELAY_SAMPLES * T)  # f_s / 6: the delay's 90 deg
    f_nyq = 0.5 / T
    lo, hi = f_90 + f_e, f_nyq - f_e  # undamped, in the rotor frame at rated speed
    what = (f"the LCL filter resonates at f_res = {f_res:.4g} Hz (sqrt((L1 + L2) / (L1 L2 C1)) "
            f"/ (2 pi) with lcl.L1 = {f.L1:g} H, L2 = lcl.L2o + motor.L_s = {f.L2o + m.L_s:g} H, "
            f"lcl.C1 = {f.C1:g} F)")
    rated = (f"the rated electrical frequency f_e = n_p w_M_N / (2 pi) = {f_e:.4g} Hz")
    where = (f"f_s = 1 / T_sp = {1.0 / T:.5g} Hz; docs/design_from_motor.md: in the rotor "
             "frame the resonance lies f_e lower and higher, and the current loop acts 1.5 "
             "samples late")
    if f_res <= f_e:
        return (f"{what}, at or below {rated}: on its way to rated speed the fundamental "
                "crosses the resonance and drives it (an overcurrent); the resonance must lie "
                f"above {f_e:.4g} Hz: a smaller lcl.C1 or lcl.L1 raises it")
    if s.controller.R_v > 0.0:
        top = f_90 - f_e
        if f_res < top:
            return None
        return (f"{what}, at or above f_s / 6 - f_e = {top:.4g} Hz ({where}): with active "
                f"damping (controller.R_v = {s.controller.R_v:g} V/A) the feedback on the "
                "capacitor current damps only below f_s / 6, above it the delay turns it into "
                "a negative resistance (yao2022 ref. [20]); a larger lcl.C1 or lcl.L1, a "
                f"shorter T_sp, or controller.R_v = 0 with the resonance within ({lo:.4g}, "
                f"{hi:.4g}) Hz")
    if f_res <= lo:
        alt = (f", or active damping (controller.R_v > 0) with the resonance below f_s / 6 - "
               f"f_e = {f_90 - f_e:.4g} Hz" if f_90 - f_e > f_e else "")
        return (f"{what}, at or below f_s / 6 + f_e = {lo:.4g} Hz ({where}): without active "
                "damping (controller.R_v = 0) the PI on the motor current is stable only with "
                "the resonance above f_s / 6, where the delay has turned its phase by 90 deg "
                f"(yao2022 ref. [20]), and {rated} shifts it; a smaller lcl.C1 or lcl.L1 "
                f"raises it into ({lo:.4g}, {hi:.4g}) Hz{alt}")
    if f_res >= hi:
        return (f"{what}, at or above f_s / 2 - f_e = {hi:.4g} Hz ({where}): near the Nyquist "
                f"frequency f_s / 2 = {f_nyq:.5g} Hz the sampled loop cannot follow the "
                "resonance (the delay turns its phase by 270 deg there, yao2022 ref. [20]); a "
                f"larger lcl.C1 or lcl.L1 lowers it into ({lo:.4g}, {hi:.4g}) Hz, or a shorter "
                "T_sp raises the bound")
    return None


def decoupling_error(s: Any) -> str | None:
    """The current PI decouples with ``L_dec = lcl.L1 + lcl.L2o + L_s_hat``
    (controller.L_dec unset, with the filter), at most 10 H (controller.L_dec's
    range, the C core's): where the sum is beyond, the term the user wrote
    that takes most of it, its value and its valid range with the others; None
    where it fits."""
    c = s.controller
    if s.lcl is None or c.L_dec is not None or s.L_dec <= 10.0:
        return None
    est = "motor.L_s" if any(d[0] == "L_s_hat" for d in c.derived) else "controller.L_s_hat"
    terms = {"lcl.L1": (s.lcl.L1, 1e-8), "lcl.L2o": (s.lcl.L2o, 0.0), est: (c.L_s_hat, 0.0)}
    key = max(terms, key=lambda k: terms[k][0])
    value, lo = terms[key]
    rest = sum(v for k, (v, _) in terms.items() if k != key)
    return (f"{key} = {value!r} H is outside its valid range [{lo:g}, {10.0 - rest:.6g}] H with "
            "this filter and machine: the current PI decouples with the whole series "
            f"inductance L_dec = lcl.L1 + lcl.L2o + controller.L_s_hat = {s.L_dec:g} H, at most "
            "10 H (the range of controller.L_dec)")
