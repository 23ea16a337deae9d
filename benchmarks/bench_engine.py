"""Engine speed benchmark (not a test): control steps per wall-second.

Runs the yang2018 Fig. 9 scenario (sensorless robust DBPC + SMDO, 150 -> 1500
-> 150 r/min) with carrier-comparison PWM, and the same in the switching-
cycle-averaged mode, with the hard-sign dead-time model (the rows every
earlier measurement used) and once with zero-current clamping (the model the
reproduction's Fig. 9 uses: its event-walked solver costs about half the
speed), and the yao2022 100 kr/min scenario (LCL filter, sliding-mode
observer + PLL, 20 kHz), each several times; prints steps/s and
simulated seconds per wall-second (min / median / max over repetitions). Usage:

    python benchmarks/bench_engine.py [--seconds 20] [--repeat 5] [--json out.json]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import platform
import statistics
import time

import numpy as np

from smodrive.model import Scenario
from smodrive.scenarios import yang2018 as y
from smodrive.scenarios import yao2022
from smodrive.engine import CHANNELS, Engine

MOTULATOR_STEPS_PER_S = {"carrier": 330.0, "averaged": 1000.0}  # DEVELOPERS.md figures


def _rates(s: Scenario, repeat: int, log: bool) -> list[float]:
    """Control steps per wall-second of `repeat` fresh runs of `s` (the engine
    and the log buffer are made before the clock starts)."""
    n = s.n_steps
    rates = []
    for _ in range(repeat):
        eng = Engine(s)
        buf = np.empty((n if log else 1, len(CHANNELS)))
        t0 = time.perf_counter()
        if log:
            eng.run(n, buf, 0, 1)
        else:
            eng.run_nolog(n)
        dt = time.perf_counter() - t0
        rates.append(n / dt)
    return rates


def bench(pwm: str, seconds: float, repeat: int, log: bool, dead_time: str = "sign") -> dict:
    """yang2018 Fig. 9 (sensorless robust DBPC + SMDO), T_sp = 100 us."""
    base = y.fig9_scenario()
    s = base.replace(duration=seconds, inverter=dataclasses.replace(
        base.inverter, pwm=pwm, dead_time_model=dead_time))
    label = pwm if dead_time == "sign" else f"{pwm} ({dead_time})"
    return _summary(label, pwm, log, s.n_steps, _rates(s, repeat, log), s.T_sp)


def _summary(label: str, pwm: str, log: bool, n: int, rates: list[float], T_sp: float) -> dict:
    med = statistics.median(rates)
    return {
        "pwm": label,
        "logging": log,
        "steps": n,
        "steps_per_s_min": min(rates),
        "steps_per_s_median": med,
        "steps_per_s_max": max(rates),
        "sim_s_per_wall_s": med * T_sp,
        "vs_motulator": med / MOTULATOR_STEPS_PER_S[pwm],
    }


def bench_lcl(pwm: str, seconds: float, repeat: int, log: bool) -> dict:
    """yao2022 at 100 kr/min (LCL filter, sliding-mode observer + PLL), T_sp = 50 us."""
    base = yao2022.steady(100e3)
    s = base.replace(duration=seconds, inverter=dataclasses.replace(base.inverter, pwm=pwm))
    return _summary(f"{pwm} (LCL)", pwm, log, s.n_steps, _rates(s, repeat, log), s.T_sp)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=20.0, help="simulated seconds per run")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", type=str, default="")
    a = ap.parse_args()
    rows = [bench(pwm, a.seconds, a.repeat, log) for pwm in ("carrier", "averaged")
            for log in (True, False)]
    rows += [bench("carrier", a.seconds, a.repeat, True, dead_time="clamp")]
    rows += [bench_lcl("carrier", a.seconds / 2, a.repeat, log) for log in (True, False)]
    print(f"smodrive engine benchmark: yang2018 Fig. 9 scenario, T_sp = 100 us, "
          f"{a.seconds:g} s simulated x {a.repeat}, {platform.processor() or platform.machine()}, "
          f"one core")
    print(f"{'PWM':15s} {'log':4s} {'steps/s min':>12s} {'median':>12s} {'max':>12s} "
          f"{'sim s/wall s':>12s} {'x motulator':>12s}")
    for r in rows:
        print(f"{r['pwm']:15s} {'yes' if r['logging'] else 'no':4s} {r['steps_per_s_min']:12,.0f} "
              f"{r['steps_per_s_median']:12,.0f} {r['steps_per_s_max']:12,.0f} "
              f"{r['sim_s_per_wall_s']:12.1f} {r['vs_motulator']:12,.0f}")
    print("x motulator: against the ~330 (carrier) / ~1000 (averaged) steps/s quoted for "
          "motulator; benchmarks/vs_motulator.py measures it side by side. Targets: "
          ">= 1,000,000 steps/s for the yang2018 drive with carrier PWM, "
          ">= 400,000 for the LCL drive at 20 kHz")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=2)


if __name__ == "__main__":
    main()
