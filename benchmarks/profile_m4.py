"""Where a drive step's Cortex-M4F cycles go (not a test): one case of the
cycle table (benchmarks/bench_m4.py) traced on QEMU and costed as there,
its nominal cycles per call summed by the inlined function chain each
instruction belongs to (`arm-none-eabi-addr2line -i`: innermost < caller <
caller's caller), by instruction and by source line; with --worst, the
slowest calls against the median one. This is how docs/firmware.md's
breakdowns of issue 22 were measured. Usage:

    python benchmarks/profile_m4.py --list
    python benchmarks/profile_m4.py "drive robust_dbpc + smdo_emf, supervision / 4" \\
        [--math fast] [--fixed yang2018] [--top 40] [--lines 40] [--worst 3]
        [--probe control|law]

--fixed PAPER builds the composition fixed at compile time
(smodrive.firmware.FIXED[PAPER], the cycle table's fixed rows); --math is
the build's math (fmath: the exact build, fast, libm); --probe a measurement
build of smd_drive.c (control: the step's control law alone, without its input
checks, kept inputs, duties' check, state check and supervision; law: also
without the speed PI).
"""

from __future__ import annotations

import argparse
import collections
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from smodrive.firmware import FIXED, MATH_DEFINES, TargetError, build
from smodrive.firmware import cycles as C
from smodrive.firmware.vectors import write_vectors
from smodrive.scenarios import target_cases


#: smd_drive.c's measurement builds (issue 22's floor: docs/firmware.md)
PROBES = {"control": ("-DSMD_PROBE_CONTROL_ONLY",),
          "law": ("-DSMD_PROBE_CONTROL_ONLY", "-DSMD_PROBE_NO_SPEED_PI")}


def _chains(elf: Path, pcs: list[int], depth: int = 3) -> tuple[dict, dict]:
    """{pc: "innermost < caller < ..."} and {pc: "file:line"} of the code at
    each address, inlined frames included."""
    out = subprocess.run(["arm-none-eabi-addr2line", "-a", "-f", "-i", "-e", str(elf)]
                         + [f"0x{pc:x}" for pc in pcs],
                         capture_output=True, text=True, check=True).stdout.splitlines()
    chain, line = {}, {}
    cur, frames = None, []
    for ln in out + ["0x0"]:
        if ln.startswith("0x"):
            if cur is not None and frames:
                names = frames[0::2]
                chain[cur] = " < ".join(names[:depth])
                line[cur] = f"{frames[1].rsplit('/', 1)[-1]} ({' < '.join(names[:2])})"
            cur, frames = int(ln, 16), []
        else:
            frames.append(ln.strip())
    return chain, line


def _top(title: str, counts: collections.Counter, n: int, scale: float = 1.0) -> None:
    print(f"\n{title}")
    for k, v in counts.most_common(n):
        print(f"{v * scale:9.1f}  {k}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case", nargs="?", help="a name of the cycle table (--list)")
    ap.add_argument("--list", action="store_true", help="print the cases' names")
    ap.add_argument("--math", choices=sorted(MATH_DEFINES), default="fast")
    ap.add_argument("--fixed", choices=sorted(FIXED), help="the composition fixed for this paper")
    ap.add_argument("--top", type=int, default=40, help="rows of the chain and class tables")
    ap.add_argument("--lines", type=int, default=30, help="rows of the source-line table")
    ap.add_argument("--worst", type=int, default=0, help="the N slowest calls against the median")
    ap.add_argument("--probe", choices=sorted(PROBES),
                    help="a measurement build, never a firmware: control (the control law "
                         "without the checks and the supervision), law (also without the "
                         "speed PI)")
    args = ap.parse_args()
    cases, _ = target_cases.cycle_cases(150)
    names = [c.name for c in cases if c.name.startswith("drive")]
    if args.list or not args.case:
        print("\n".join(names))
        return
    if args.case not in names:
        sys.exit(f"error: no case {args.case!r}; --list prints the names")
    case = next(c for c in cases if c.name == args.case)
    extra = (tuple(FIXED[args.fixed]) if args.fixed else ()) + PROBES.get(args.probe, ())
    with tempfile.TemporaryDirectory(prefix="smd_prof_") as tmp:
        work = Path(tmp)
        vec = work / "vectors.bin"
        write_vectors(vec, [case])
        try:
            elf = build("m4", args.math, extra=extra)
            prof: list[dict] = []
            wins = C.trace_windows(elf, vec, work, profile=prof, by_pc=True)
            insns, _ = C.disassemble(elf)
            pcs = sorted({pc for d in prof for pc in d})
            chain, line = _chains(elf, pcs)
        except (TargetError, OSError, subprocess.CalledProcessError) as e:
            sys.exit(f"error: {str(e).splitlines()[0]} (make toolchain installs the M4F tools)")
    n = len(wins)
    ram = [w.cycles[1] for w in wins]
    print(f"{args.case}, {args.math} build{', fixed ' + args.fixed if args.fixed else ''}"
          f"{', probe ' + args.probe if args.probe else ''}: "
          f"{n} calls, mean {statistics.mean(ram):.1f}, worst {max(ram)} cycles (code in RAM)")
    by_chain, by_class, by_line = (collections.Counter() for _ in range(3))
    for d in prof:
        for pc, c in d.items():
            by_chain[chain.get(pc, "?")] += c
            by_class[insns[pc].mnem if pc in insns else "?"] += c
            by_line[line.get(pc, "?")] += c
    _top("cycles per call by function (innermost < caller < caller's caller)", by_chain,
         args.top, 1 / n)
    _top("cycles per call by instruction", by_class, args.top, 1 / n)
    _top("cycles per call by source line", by_line, args.lines, 1 / n)
    if args.worst:
        med = sorted(range(n), key=ram.__getitem__)[n // 2]
        for i in sorted(range(n), key=lambda k: -ram[k])[:args.worst]:
            d = collections.Counter()
            for pc, c in prof[i].items():
                d[chain.get(pc, "?")] += c
            for pc, c in prof[med].items():
                d[chain.get(pc, "?")] -= c
            rows = sorted(((k, v) for k, v in d.items() if v), key=lambda kv: -abs(kv[1]))
            print(f"\ncall {i}: {ram[i]} cycles against the median call {med}'s {ram[med]}")
            for k, v in rows[:12]:
                print(f"{v:+9d}  {k}")


if __name__ == "__main__":
    main()
