"""The loops of a drive as smodrive designs them, in closed form (`smodrive
design` prints the sensorless speed loop's phase margin)."""

from __future__ import annotations

import math


def speed_loop_margin(speed_bw: float, w_lpf: float, w_c: float, T_sp: float,
                      decimation: int = 1) -> float:
    """Phase margin, deg, of the sensorless speed loop as designed: the speed
    PI tuned for `speed_bw` on the rotor (open loop (2 bw s + bw^2) / s^2:
    k_p = 2 bw / b, k_i = bw^2 / b, b = 1.5 n_p^2 psi_r / J), the speed
    estimate's low-pass of yang2018 eq. (45) at `w_lpf`, the SMDO's
    disturbance filter (36) taken as a first-order lag at `w_c` (the angle
    follows the EMF through it), and 1.5 + (decimation - 1) / 2 samples of
    delay (the computation's sample, the hold's half, the speed loop's own
    hold). Table I's design (60 and 100 rad/s, w_c 1500 rad/s, 100 us):
    24.9 deg."""
    delay = T_sp * (1.5 + 0.5 * (decimation - 1))

    def phase(w: float) -> float:  # deg above -180
        return math.degrees(math.atan(2.0 * w / speed_bw) - math.atan(w / w_lpf)
                            - math.atan(w / w_c) - w * delay)

    def gain(w: float) -> float:
        return (math.hypot(2.0 * w * speed_bw, speed_bw ** 2) / (w * w)
                / math.hypot(1.0, w / w_lpf) / math.hypot(1.0, w / w_c))

    lo, hi = 1e-6 * speed_bw, 1e3 * speed_bw  # |L| falls monotonically through 1
    for _ in range(100):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if gain(mid) > 1.0 else (lo, mid)
    return phase(lo)


#: Table I's design's margin, deg (speed_loop_margin(60, 100, 1500, 100e-6)): the
#: reference `smodrive design` prints a sensorless design's margin beside
TABLE1_SPEED_PM = speed_loop_margin(60.0, 100.0, 1500.0, 100e-6)


def sensorless_margin(s) -> tuple[float, bool] | None:
    """Scenario `s`'s sensorless speed loop (the SMDO's angle, the speed
    loop on): its phase margin, deg, and whether it is below Table I's
    design's (the loop rings on the ADC's noise); None for another drive."""
    c = s.controller
    if c.position != "smdo_emf" or not c.speed_loop:
        return None
    pm = speed_loop_margin(c.speed_bw, c.w_lpf, c.w_c, s.T_sp, c.speed_decimation)
    return pm, pm < TABLE1_SPEED_PM - 0.05
