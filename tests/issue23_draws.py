"""Issue 23's measurement conditions, one draw at a time, shared by the
commissioning and tracker tests: current-sensor gains within +-0.5 %,
offsets within +-0.2 % of full scale, a dead time of 0.5-2 us with
zero-current clamping, the 12-bit ADC's noise (its seed)."""

from __future__ import annotations

import dataclasses


def sensor_errors(s0, seed: int, rng, sensors: int = 2):
    """`s0` with one draw from `rng` (gains, offsets, then the dead time)
    and ADC noise seed `seed`, read through `sensors` current sensors."""
    gain = tuple(float(g) for g in 1.0 + rng.uniform(-0.005, 0.005, 3))
    offset = tuple(float(o) for o in rng.uniform(-0.002, 0.002, 3) * s0.adc.full_scale)
    return s0.replace(adc=dataclasses.replace(s0.adc, seed=seed, gain=gain, offset=offset,
                                              sensors=sensors),
                      inverter=dataclasses.replace(s0.inverter,
                                                   t_dead=float(rng.uniform(0.5e-6, 2e-6)),
                                                   dead_time_model="clamp"))
