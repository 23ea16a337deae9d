"""Cycle counts on the Cortex-M4F: the emulator's instruction trace priced
with the Cortex-M4 timings, per call of each vector case, the code size and
RAM of the core, and yao2022 Table VI's parts."""

from __future__ import annotations

import dataclasses
import os
import re
import shutil
import subprocess
import tempfile
import threading
from pathlib import Path
from typing import Collection

import numpy as np

from .build import (
    COMMON_FLAGS,
    M4_FLAGS,
    MATH_DEFINES,
    TargetError,
    _cache_dir,
    _tool,
    build,
    c_root,
)
from .run import qemu_command
from .vectors import BlockCase, DriveCase, TablesCase, write_vectors

# ---------------------------------------------------------------- cycles --

#: Cortex-M4 cycle timings (ARM Cortex-M4 TRM r0p1, sect. 3.3.1, and the FPU
#: TRM's VFP instruction table) as (min, nominal, max) per instruction class;
#: P, the pipeline refill of a taken branch, is 1..3 (nominal 2); a load or
#: store directly after another one pipelines to 1 cycle (nominal and min);
#: SDIV/UDIV take 2..12 (nominal 7). Zero-wait-state memory assumed (code in
#: SRAM/TCM, or flash behind an accelerator that hits).
_P = (1, 2, 3)
_FIXED = {
    "vdiv": (14, 14, 14), "vsqrt": (14, 14, 14),
    "vmla": (3, 3, 3), "vmls": (3, 3, 3), "vnmla": (3, 3, 3), "vnmls": (3, 3, 3),
    "vfma": (3, 3, 3), "vfms": (3, 3, 3), "vfnma": (3, 3, 3), "vfnms": (3, 3, 3),
    "mla": (2, 2, 2), "mls": (2, 2, 2), "sdiv": (2, 7, 12), "udiv": (2, 7, 12),
    "ldrd": (3, 3, 3), "strd": (3, 3, 3), "it": (0, 1, 1), "tbb": (3, 4, 5), "tbh": (3, 4, 5),
}
_LOADSTORE = {"ldr", "ldrb", "ldrh", "ldrsb", "ldrsh", "str", "strb", "strh", "vldr", "vstr",
              "ldrex", "strex"}
_MULTI = {"ldm", "ldmia", "ldmfd", "ldmdb", "stm", "stmia", "stmea", "stmdb", "stmfd",
          "push", "pop", "vpush", "vpop", "vldmia", "vstmia", "vldmdb", "vstmdb", "vldm",
          "vstm"}
_CONDS = ("eq", "ne", "cs", "cc", "hs", "lo", "mi", "pl", "vs", "vc", "hi", "ls", "ge", "lt",
          "gt", "le", "al")


def _reg_count(ops: str) -> int:
    """Registers in a {list} (ranges r4-r7, s16-s23, d8-d9 = 2 words each)."""
    inner = ops[ops.find("{") + 1:ops.find("}")]
    n = 0
    for part in inner.split(","):
        part = part.strip()
        if "-" in part:
            a, b = part.split("-")
            k = int(b.strip()[1:]) - int(a.strip()[1:]) + 1
        else:
            k = 1
        n += 2 * k if part.startswith("d") else k
    return max(n, 1)


@dataclasses.dataclass(frozen=True)
class _Insn:
    size: int
    cls: str          # "branch", "ls" (single load/store), "multi", "fixed"
    cost: tuple       # (min, nominal, max) when not taken / not pipelined
    mnem: str


def _classify(mnem: str, ops: str, size: int) -> _Insn:
    m = mnem.lower().split(".")[0]
    base = m
    for c in _CONDS:  # conditional forms: beq, bxne, ldrne, ...
        if m.endswith(c) and m[:-len(c)] in ("b", "bx", "bl", "blx", "ldr", "str", "mov", "add",
                                             "sub", "cmp", "ldrb", "strb", "it"):
            base = m[:-len(c)]
            break
    if base == m and m not in _FIXED:
        # a conditional multi-cycle instruction in an IT block (vdivls, vdivhi: atan2's
        # ite pair, one of which passes): 1 cycle when its condition fails, the whole
        # when it passes; which one the trace does not say, so nominal the mean, the
        # range both ends (it was costed 1, as an unknown instruction)
        for c in _CONDS:
            if m.endswith(c) and m[:-len(c)] in _FIXED and _FIXED[m[:-len(c)]][2] > 1:
                lo, _, hi = _FIXED[m[:-len(c)]]
                return _Insn(size, "fixed", (1, (1 + hi + 1) // 2, hi), m[:-len(c)])
    if base in ("b", "bl", "bx", "blx", "cbz", "cbnz"):
        return _Insn(size, "branch", (1, 1, 1), base)
    if base in ("pop", "ldm", "ldmia", "ldmfd") and "pc" in ops:
        n = _reg_count(ops)
        return _Insn(size, "branch_multi", (1 + n, 1 + n, 1 + n), base)
    if base in _MULTI:
        n = _reg_count(ops)
        return _Insn(size, "multi", (1 + n, 1 + n, 1 + n), base)
    if base in _FIXED:
        return _Insn(size, "fixed", _FIXED[base], base)
    if base in _LOADSTORE:
        if base == "ldr" and ops.lstrip().startswith("pc"):
            return _Insn(size, "branch", (2, 2, 2), base)
        return _Insn(size, "ls", (2, 2, 2), base)
    if base == "vmov" and ops.count(",") == 2 and ops.split(",")[0].strip()[0] == "r" \
            and ops.split(",")[1].strip()[0] == "r":
        return _Insn(size, "fixed", (2, 2, 2), base)  # two core registers <-> a d register
    if base == "vmov" and ops.count(",") == 3:
        return _Insn(size, "fixed", (2, 2, 2), base)
    return _Insn(size, "fixed", (1, 1, 1), base)


def disassemble(elf: Path) -> tuple[dict[int, _Insn], dict[str, tuple[int, int]]]:
    """{address: instruction} of the ELF's code and {function: (start, end)}."""
    objdump = _tool("arm-none-eabi-objdump", "binutils-arm-none-eabi")
    txt = subprocess.run([objdump, "-d", str(elf)], capture_output=True, text=True,
                         check=True).stdout
    insns: dict[int, _Insn] = {}
    funcs: dict[str, tuple[int, int]] = {}
    cur, start = None, 0
    head = re.compile(r"^([0-9a-f]+) <([^>]+)>:$")
    line_re = re.compile(r"^\s*([0-9a-f]+):\t([0-9a-f ]+?)\s*\t(\S+)\s*(.*)$")
    last = 0
    for line in txt.splitlines():
        h = head.match(line)
        if h:
            if cur is not None:
                funcs[cur] = (start, last)
            cur, start = h.group(2), int(h.group(1), 16)
            continue
        m = line_re.match(line)
        if not m:
            continue
        addr = int(m.group(1), 16)
        raw = m.group(2).split()
        size = sum(len(x) // 2 for x in raw)
        if m.group(3).startswith(".") or size not in (2, 4):
            continue
        insns[addr] = _classify(m.group(3), m.group(4), size)
        last = addr + size
    if cur is not None:
        funcs[cur] = (start, last)
    return insns, funcs


@dataclasses.dataclass(frozen=True)
class Flash:
    """Code in flash behind an STM32 ART accelerator: an instruction cache of
    `lines` lines of `line_bytes`, fully associative with LRU replacement
    (assumed), a miss costs `wait_states` cycles, and the prefetch of the next
    line hides as many of them as the code spent in the line before when the
    fetch is sequential. Literal-pool loads are assumed to hit the data cache.
    The values are the reference manuals' (RM0090 sect. 3.4-3.5, RM0440 sect.
    3.3) at the top clock and full supply voltage."""

    label: str
    f_cpu: float
    wait_states: int
    line_bytes: int
    lines: int


#: the memories the cycle table prices beside zero-wait RAM
#: VDIV and VSQRT hold the FPU for their 14 cycles but the integer pipeline
#: for one: the integer instructions after one execute while it runs, and
#: the next FPU instruction (any V... instruction, loads and stores of S
#: registers too) waits for it (GCC's Cortex-M4 pipeline description,
#: gcc/config/arm/cortex-m4-fpu.md: "Integer instructions following VDIV or
#: VSQRT complete out-of-order", the divide reserving the FPU 13 cycles
#: after its one in the integer pipeline; ARM erratum 776924: a VDIV
#: completes while an interrupt's stacking runs). The min and nominal
#: columns count the overlap; the max column does not (each divide its whole
#: 14 cycles, the serial bound).
_FPU_BACKGROUND = ("vdiv", "vsqrt")


class _Clock:
    """The (min, nominal, max) cycles of one window's instruction stream,
    instruction by instruction (trace_windows): the taken branch's refill,
    pipelined loads and stores, and the FPU's divider in the background."""

    def __init__(self) -> None:
        self.c = [0, 0, 0]
        self.fpu_free = [0, 0]      # when the FPU is free again (min, nominal)
        self.div_pc = 0             # the divide that holds it
        self.prev: _Insn | None = None
        self.prev_pc = 0
        self.prev_ls = False
        self.refill = 0             # the nominal refill the last step added

    def step(self, pc: int, ins: _Insn) -> list[tuple[int, int]]:
        """Count the instruction at `pc`; returns what it added to the
        nominal column as (address charged, cycles) pairs: the previous
        branch's refill (the branch's), a wait for the divider (the
        divide's), the instruction's own."""
        charged = []
        prev = self.prev
        self.refill = 0
        if prev is not None and prev.cls.startswith("branch") and pc != self.prev_pc + prev.size:
            self.c = [self.c[i] + _P[i] for i in range(3)]
            self.refill = _P[1]
            charged.append((self.prev_pc, _P[1]))
        lo, nom, hi = ins.cost
        if ins.cls == "ls" and self.prev_ls:
            lo, nom = 1, 1
        if ins.mnem.startswith("v"):
            wait = [max(0, self.fpu_free[i] - self.c[i]) for i in range(2)]
            self.c[0] += wait[0]
            self.c[1] += wait[1]
            if wait[1]:
                charged.append((self.div_pc, wait[1]))
        if ins.mnem in _FPU_BACKGROUND:
            self.fpu_free = [self.c[0] + lo, self.c[1] + nom]
            self.div_pc = pc
            lo, nom = min(lo, 1), min(nom, 1)
        self.c = [self.c[0] + lo, self.c[1] + nom, self.c[2] + hi]
        charged.append((pc, nom))
        self.prev_ls = ins.cls == "ls"
        self.prev, self.prev_pc = ins, pc
        return charged

    def finish(self) -> list[tuple[int, int]]:
        """The end of the window: a divide still running is waited for."""
        wait = [max(0, self.fpu_free[i] - self.c[i]) for i in range(2)]
        self.c[0] += wait[0]
        self.c[1] += wait[1]
        return [(self.div_pc, wait[1])] if wait[1] else []


FLASH = {
    "stm32f4": Flash("STM32F4, 168 MHz: 5 wait states, ART 64 lines x 16 B", 168e6, 5, 16, 64),
    "stm32g4": Flash("STM32G4, 170 MHz: 4 wait states, ART 32 lines x 32 B", 170e6, 4, 32, 32),
}


class _ICache:
    """The fetch penalties of :class:`Flash` for one instruction stream."""

    def __init__(self, f: Flash) -> None:
        self.f = f
        self.lru: dict[int, None] = {}
        self.cur = -2
        self.spent = 0

    def flush(self) -> None:
        self.lru.clear()
        self.cur = -2
        self.spent = 0

    def fetch(self, pc: int, cost: int) -> int:
        """The stall of fetching the instruction at `pc` that then takes
        `cost` cycles."""
        line = pc // self.f.line_bytes
        stall = 0
        if line != self.cur:
            if line in self.lru:
                del self.lru[line]
            else:
                stall = self.f.wait_states
                if line == self.cur + 1:  # prefetched while the last line ran
                    stall = max(0, stall - self.spent)
                if len(self.lru) >= self.f.lines:
                    del self.lru[next(iter(self.lru))]
            self.lru[line] = None
            self.cur, self.spent = line, 0
        self.spent += cost + stall
        return stall


@dataclasses.dataclass
class Window:
    cycles: tuple[int, int, int]   # min, nominal, max
    instructions: int
    #: the nominal cycles with the code in each :data:`FLASH` memory: warm (the
    #: cache as the previous call left it) and cold (emptied at the call)
    flash: dict = dataclasses.field(default_factory=dict)


def trace_windows(elf: Path, vec: Path, work: Path, timeout: float = 900.0,
                  profile: list | None = None, by_pc: bool = False) -> list[Window]:
    """Run the vectors on QEMU with every executed instruction logged (one
    instruction a translation block, streamed through a FIFO) and cost each
    window between smd_mark_begin and smd_mark_end with the Cortex-M4
    timings above. The markers' own instructions are left out. With
    `profile` (a list), a dict per window of the nominal cycles by function
    is appended to it (`by_pc`: by instruction address instead, for the
    inlined functions and source lines: benchmarks/profile_m4.py)."""
    insns, funcs = disassemble(elf)
    owner = {}
    if profile is not None:
        for name, (a0, a1) in funcs.items():
            for a in range(a0, a1, 2):
                owner[a] = name
    b0, b1 = funcs["smd_mark_begin"]
    e0, e1 = funcs["smd_mark_end"]
    s0, s1 = funcs["mark_sink"]
    work.mkdir(parents=True, exist_ok=True)
    d = Path(tempfile.mkdtemp(prefix="smd_trace_", dir=work))
    fifo = d / "trace"
    os.mkfifo(fifo)
    out = d / "out.bin"
    # leave the start-up code (zeroing .bss) out of the trace
    r0, r1 = funcs["Reset_Handler"]
    cmd = qemu_command(elf, str(vec), str(out), trace=fifo) + [
        "-dfilter", f"0x0..0x{r0:x},0x{r1:x}..0x400000"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    timer = threading.Timer(timeout, proc.kill)
    timer.start()
    windows: list[Window] = []
    try:
        inside = False
        clock = _Clock()
        n = 0
        caches = {(name, mode): _ICache(fl) for name, fl in FLASH.items()
                  for mode in ("warm", "cold")}
        stalls = dict.fromkeys(caches, 0)
        with open(fifo, "r", buffering=1 << 20) as f:
            for line in f:
                lb = line.find("[")
                if lb < 0:
                    continue
                pc = int(line[lb + 10:lb + 18], 16)
                if b0 <= pc < b1:
                    if not inside and profile is not None:
                        profile.append({})
                    inside, clock, n = True, _Clock(), 0
                    for key, ic in caches.items():
                        if key[1] == "cold":
                            ic.flush()
                        stalls[key] = 0
                    continue
                if e0 <= pc < e1:
                    if inside and clock.prev is not None:
                        # the call of smd_mark_end (1 cycle counted; its
                        # refill was not) is not the window's
                        clock.c = [clock.c[0] - 1, clock.c[1] - 1, clock.c[2] - 1]
                        n -= 1
                        tail = clock.finish()
                        c = clock.c
                        if profile is not None:
                            fb = clock.prev_pc if by_pc else owner.get(clock.prev_pc, "?")
                            profile[-1][fb] -= 1
                            for a, k in tail:
                                fa = a if by_pc else owner.get(a, "?")
                                profile[-1][fa] = profile[-1].get(fa, 0) + k
                        fl: dict = {}
                        for (name, mode), st in stalls.items():
                            fl.setdefault(name, {})[mode] = c[1] + st
                        windows.append(Window((c[0], c[1], c[2]), n, fl))
                    inside = False
                    continue
                if not inside or s0 <= pc < s1:
                    continue
                ins = insns.get(pc)
                if ins is None:
                    continue
                # (the previous instruction's branch outcome is known now)
                t0 = clock.c[1]
                charged = clock.step(pc, ins)
                for key, ic in caches.items():
                    stalls[key] += ic.fetch(pc, clock.c[1] - t0 - clock.refill)
                if profile is not None:
                    for a, k in charged:
                        fn = a if by_pc else owner.get(a, "?")
                        profile[-1][fn] = profile[-1].get(fn, 0) + k
                n += 1
        proc.wait(timeout=60)
    finally:
        timer.cancel()
        if proc.poll() is None:
            proc.kill()
        shutil.rmtree(d, ignore_errors=True)
    if proc.returncode != 0:
        raise TargetError(f"QEMU trace run failed ({proc.returncode})")
    return windows


#: budgets of the control period at the papers' rates on a 168 MHz
#: Cortex-M4F (STM32F4 class)
F_CPU = 168e6
BUDGET = {"yang2018": 100e-6 * F_CPU, "yao2022": 50e-6 * F_CPU}
#: yao2022 Table VI, cycles on the 150 MHz TMS320F28335
TABLE6_PAPER = {"prediction": 489, "reaching_law": 268, "pll": 28}


@dataclasses.dataclass
class CycleRow:
    name: str
    paper: str            # whose period budget applies
    calls: int
    nominal: float        # mean cycles per call
    low: float            # mean of the lower bound (P = 1, IT folded, DIV 2)
    high: float           # mean of the upper bound (P = 3, DIV 12)
    worst: int            # largest nominal cycles of one call
    instructions: float   # mean instructions per call
    p99: float = 0.0      # 99th percentile of the nominal cycles of one call
    #: with the code in flash (:data:`FLASH`): {memory: {"mean_warm", "worst_warm",
    #: "mean_cold", "worst_cold"}} (nominal timings plus the fetch stalls)
    flash: dict = dataclasses.field(default_factory=dict)

    @property
    def budget_share(self) -> float:
        """The mean call's share of the period's budget."""
        return self.nominal / BUDGET[self.paper]

    @property
    def worst_share(self) -> float:
        """The worst call's share of the budget, the code in zero-wait RAM."""
        return self.worst / BUDGET[self.paper]

    def worst_flash(self, memory: str = "stm32f4") -> float:
        """The worst call with the code in `memory`'s flash, the cache emptied
        before the call (an interrupt's other code evicted it): the
        pessimistic count a budget check uses for flash-resident code."""
        return self.flash[memory]["worst_cold"]


def _row(name: str, paper: str, ws: list[Window]) -> CycleRow:
    nom = np.array([w.cycles[1] for w in ws], float)
    fl: dict = {}
    for mem in FLASH:
        for mode in ("warm", "cold"):
            x = np.array([w.flash[mem][mode] for w in ws], float)
            fl.setdefault(mem, {})[f"mean_{mode}"] = float(x.mean())
            fl[mem][f"worst_{mode}"] = float(x.max())
    return CycleRow(name, paper, len(ws), float(nom.mean()),
                    float(np.mean([w.cycles[0] for w in ws])),
                    float(np.mean([w.cycles[2] for w in ws])), int(nom.max()),
                    float(np.mean([w.instructions for w in ws])),
                    float(np.percentile(nom, 99)), fl)



def cycle_table(cases: list, paper: dict[str, str], math: str = "fmath",
                work: Path | None = None, samples: int = 150,
                whole: Collection[str] = (), extra: tuple[str, ...] = ()) -> list[CycleRow]:
    """Cycles per call on the Cortex-M4F (QEMU instruction trace weighted by
    the Cortex-M4 timings) for every case of `cases` (drive cases of
    `samples` samples, measured after their first third; blocks over their
    first 100 calls), each row labelled with its paper from `paper`
    (:func:`smodrive.scenarios.target_cases.cycle_cases` makes both); the
    drive cases named in `whole` are measured over every sample (those with
    injected faults); `extra` flags go to the build (:func:`build`)."""
    work = Path(work) if work else _cache_dir()
    work.mkdir(parents=True, exist_ok=True)
    vec = work / f"cycles_{math}.bin"
    write_vectors(vec, cases)
    wins = trace_windows(build("m4", math, extra=extra), vec, work)
    rows: list[CycleRow] = []
    pos = 0

    def row(name, ws, p):
        rows.append(_row(name, p, ws))

    for c in cases:
        if isinstance(c, TablesCase):
            continue
        if isinstance(c, DriveCase):
            ws = wins[pos:pos + c.inputs.shape[0]]
            pos += c.inputs.shape[0]
            # after the first third (the steady phase), or every sample
            row(c.name, ws if c.name in whole else ws[samples // 3:], paper[c.name])
            continue
        per = {"smdo": 2}.get(c.block, 1) * (3 if c.block == "table6" else 1)
        ws = wins[pos:pos + per * c.n]
        pos += per * c.n
        if c.block == "table6":
            for j, part in enumerate(TABLE6_PAPER):
                row(f"table6.{part}", ws[j::3][:100], "yao2022")
            continue
        if c.block == "table6_dec":
            # after the first two refresh cycles (the first call refreshes
            # whole), every call: each piece of the spread refresh is in
            row(c.name, ws[16:], paper[c.name])
            continue
        row(c.name, ws[:100], paper[c.name])
    if pos != len(wins):
        raise TargetError(f"cycle windows: {len(wins)} traced, {pos} expected")
    return rows


def step_cycles(case: DriveCase, paper: str, math: str = "fmath",
                work: Path | None = None) -> CycleRow:
    """Every step of one drive case (e.g. a whole PIL run's inputs,
    :func:`smodrive.firmware.pil` with cycles=True) traced on the Cortex-M4F:
    one row over all its samples (mean, 99th percentile, worst; in flash)."""
    work = Path(work) if work else _cache_dir()
    work.mkdir(parents=True, exist_ok=True)
    vec = work / f"steps_{math}_{os.getpid()}.bin"
    write_vectors(vec, [case])
    try:
        wins = trace_windows(build("m4", math), vec, work)
    finally:
        vec.unlink(missing_ok=True)
    if len(wins) != case.inputs.shape[0]:
        raise TargetError(f"step cycles: {len(wins)} windows for {case.inputs.shape[0]} samples")
    return _row(case.name, paper, wins)


#: the structs whose RAM the size table reports (params: derived once at
#: init, constant; state: changes every sample)
SIZE_STRUCTS = ("smd_drive_config", "smd_drive_params", "smd_drive_state", "smd_dbpc_params",
                "smd_smdo_params", "smd_smdo_state", "smd_pi_params", "smd_pi_state",
                "smd_emf_pos_params", "smd_emf_pos_state", "smd_pll_params", "smd_pll_state",
                "smd_bandpass", "smd_lcl_smo_params", "smd_lcl_smo_state", "smd_lcl_model",
                "smd_linobs_params", "smd_linobs_state", "smd_linobs_model", "smd_svm_params")


def sizes(math: str = "libm") -> tuple[dict[str, int], dict[str, int]]:
    """Code size (.text + .rodata, bytes) of each core source compiled for
    the Cortex-M4F (-O3, the cycle table's flags) and the size of each struct
    of :data:`SIZE_STRUCTS` in the M4F build (from the symbol sizes of
    objects sized like them)."""
    cc = _tool("arm-none-eabi-gcc", "gcc-arm-none-eabi")
    size_tool = _tool("arm-none-eabi-size", "binutils-arm-none-eabi")
    nm = _tool("arm-none-eabi-nm", "binutils-arm-none-eabi")
    root = c_root()
    flags = M4_FLAGS + COMMON_FLAGS + MATH_DEFINES[math] + [
        f"-I{root / 'core/include'}"]
    code: dict[str, int] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for src in sorted((root / "core/src").glob("*.c")):
            obj = Path(tmp) / (src.stem + ".o")
            subprocess.run([cc, *flags, "-c", str(src), "-o", str(obj)], check=True,
                           capture_output=True)
            out = subprocess.run([size_tool, "-A", str(obj)], check=True, capture_output=True,
                                 text=True).stdout
            code[src.stem] = sum(int(ln.split()[1]) for ln in out.splitlines()
                                 if ln.startswith((".text", ".rodata")))
        probe = Path(tmp) / "sizes.c"
        probe.write_text('#include "smodrive/smd_drive.h"\n' + "".join(
            f"char sz_{s}[sizeof({s})];\n" for s in SIZE_STRUCTS))
        obj = Path(tmp) / "sizes.o"
        subprocess.run([cc, *flags, "-fno-common", "-c", str(probe), "-o", str(obj)],
                       check=True, capture_output=True)
        out = subprocess.run([nm, "-S", str(obj)], check=True, capture_output=True,
                             text=True).stdout
    ram = {}
    for ln in out.splitlines():
        parts = ln.split()
        if len(parts) == 4 and parts[3].startswith("sz_"):
            ram[parts[3][3:]] = int(parts[1], 16)
    return code, ram


def table6_cycles(tables, math: str = "fmath", work: Path | None = None, calls: int = 120):
    """yao2022 Table VI's parts on the M4F: {part: CycleRow} and {part:
    {function: mean nominal cycles per call}}, over the last 100 of `calls`
    calls with the observer tables `tables`
    (:func:`smodrive.engine.lcl_observer_tables` of the drive at 100 kr/min)."""
    cases = [TablesCase("tables", tables), BlockCase("table6", "table6", calls, 7)]
    work = Path(work) if work else _cache_dir()
    work.mkdir(parents=True, exist_ok=True)
    vec = work / f"table6_{math}.bin"
    write_vectors(vec, cases)
    prof: list[dict] = []
    wins = trace_windows(build("m4", math), vec, work, profile=prof)
    if len(wins) != 3 * calls or len(prof) != 3 * calls:
        raise TargetError(f"Table VI trace: {len(wins)} windows for {3 * calls} calls")
    rows, by_fn = {}, {}
    for j, part in enumerate(TABLE6_PAPER):
        ws = wins[j::3][calls - 100:]
        ps = prof[j::3][calls - 100:]
        rows[part] = _row(f"table6.{part}", "yao2022", ws)
        fns: dict[str, float] = {}
        for d in ps:
            for k, v in d.items():
                fns[k] = fns.get(k, 0.0) + v / len(ps)
        by_fn[part] = dict(sorted(fns.items(), key=lambda kv: -kv[1]))
    return rows, by_fn
