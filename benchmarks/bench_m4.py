"""Cortex-M4F cost benchmark (not a test): cycles per call of each block of
the core and of the whole drive step in each composition, code size per
source and RAM per struct, for the M4F build.

Method: the vector runner (core/target) runs on QEMU's mps2-an386 board
(Cortex-M4F) with every executed instruction logged (-singlestep -d exec);
each call between the runner's markers is costed with the Cortex-M4 TRM's
cycle table (src/smodrive/firmware/cycles.py): a taken branch 1 + P with P = 1..3
(nominal 2), loads and stores 2 (1 when pipelined behind another), VDIV and
VSQRT 14, fused multiply-adds 3, SDIV 2..12, zero-wait-state memory. The
range [low, high] takes every P, IT folding and divide at its extreme;
flash wait states beyond an accelerator's hits, bus contention and
interrupts are not in it. Beside it, the same calls with the code in flash
behind an STM32F4 or STM32G4 ART accelerator (wait states, instruction
cache and prefetch: smodrive.firmware.FLASH), warm and cold. Usage:

    python benchmarks/bench_m4.py [--math fmath|libm|fast|both|all] [--json out.json]
"""

from __future__ import annotations

import argparse
import dataclasses
import json

from smodrive import firmware as T
from smodrive.firmware.cycles import F_CPU
from smodrive.scenarios import target_cases


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--math", choices=("fmath", "libm", "fast", "both", "all"), default="both",
                    help="both: fmath and libm; all: fmath, fast and libm")
    ap.add_argument("--json", help="write the tables to this file")
    args = ap.parse_args()
    maths = {"both": ("fmath", "libm"), "all": ("fmath", "fast", "libm")}.get(args.math,
                                                                         (args.math,))
    tables = {m: target_cases.cycle_table(m) for m in maths}
    budget = {p: int(b) for p, b in T.BUDGET.items()}
    print(f"Cortex-M4F cycles per call (QEMU mps2-an386 instruction trace x Cortex-M4 timings); "
          f"budget at {F_CPU / 1e6:.0f} MHz: yang2018 100 us = {budget['yang2018']} cycles, "
          f"yao2022 50 us = {budget['yao2022']}")
    mems = list(T.FLASH)
    for m in maths:
        print(f"\n{m} math: cycles per call, the code in zero-wait RAM (mean [low, high], 99th "
              "percentile, worst call) and in flash (" + "; ".join(
                  f"{k}: {T.FLASH[k].label}" for k in mems) + "; mean with the cache as the "
              "previous call left it, worst with it emptied before the call); budget: the larger "
              "share of its period the worst call in flash takes (at each part's clock)")
        print(f"{'':50s}{'mean':>7s} {'[low, high]':>14s} {'p99':>6s} {'worst':>6s}" + "".join(
            f" {k + ' mean':>13s} {k + ' worst':>13s}" for k in mems) + f" {'budget':>7s}")
        for r in tables[m]:
            fl = "".join(f" {r.flash[k]['mean_warm']:13.0f} {r.flash[k]['worst_cold']:13.0f}"
                         for k in mems)
            period = budget[r.paper] / F_CPU  # s
            share = max(r.worst_flash(k) / (period * T.FLASH[k].f_cpu) for k in mems)
            print(f"{r.name:50s}{r.nominal:7.0f} {f'[{r.low:.0f}, {r.high:.0f}]':>14s} "
                  f"{r.p99:6.0f} {r.worst:6d}{fl} {100 * share:6.1f}%")
    fixed = {m: [r for p in T.FIXED for r in target_cases.fixed_cycle_table(p, m)]
             for m in maths if m != "libm"}
    for m, rows in fixed.items():
        print(f"\n{m} math, the composition fixed at compile time (smd_drive.h; "
              "smodrive.firmware.FIXED):")
        for r in rows:
            fl = "".join(f" {k} {r.flash[k]['mean_warm']:.0f} / {r.flash[k]['worst_cold']:.0f}"
                         for k in mems)
            print(f"{r.name + ', fixed':90s}{r.nominal:7.0f} p99 {r.p99:6.0f} worst {r.worst:6d};"
                  f" in flash (mean / worst):{fl}")
    t6 = {m: {r.name.split(".")[1]: r.nominal for r in tables[m] if r.name.startswith("table6.")}
          for m in maths}
    for m in maths:
        total = sum(t6[m].values())
        print(f"yao2022 Table VI on the M4F ({m}): prediction {t6[m]['prediction']:.0f}, "
              f"reaching law {t6[m]['reaching_law']:.0f}, PLL {t6[m]['pll']:.0f}: "
              f"{total:.0f} cycles against the paper's 785 on the TMS320F28335")
    code, ram = T.sizes()
    print("\ncode size for the Cortex-M4F (-O3, .text + .rodata, bytes): " + ", ".join(
        f"{k} {v}" for k, v in code.items()) + f"; total {sum(code.values())}")
    print("RAM (bytes): " + ", ".join(f"{k} {v}" for k, v in ram.items()))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"cycles": {m: [dataclasses.asdict(r) for r in tables[m]] for m in maths},
                       "fixed": {m: [dataclasses.asdict(r) for r in rows]
                                 for m, rows in fixed.items()},
                       "code": code, "ram": ram}, f, indent=2)


if __name__ == "__main__":
    main()
