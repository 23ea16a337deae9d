"""What the firmware tests and the cycle table run: every composition of
the one drive on a scenario that exercises it, the standard vector set
(blocks, recorded drives with their edge-case variants, the papers'
recorded scenarios) and the cases of the Cortex-M4F cycle table. The
scenarios are the papers' (:mod:`smodrive.scenarios.drive`, :mod:`smodrive.scenarios.yao2022`); the machinery is
:mod:`smodrive.firmware`."""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np

from ..engine import drive_config
from ..firmware import cycles
from ..firmware.build import FIXED, IN_WORDS
from ..firmware.run import drive_case
from ..firmware.vectors import BlockCase, DriveCase, TablesCase, variants
from ..model import Profile
from . import drive, yao2022
from .catalogue import catalogue


def mode_scenarios() -> list[tuple[str, object]]:
    """Every composition of the one drive (smd_drive.h) on a scenario that
    exercises it: the yang2018 motor (current pi/dbpc/robust_dbpc x
    position encoder/smdo_emf x start running/handover/if) at 1500 r/min
    with the rated load (from standstill for I/f), and the yao2022 LCL drive
    (pi x encoder/lcl_smo_pll/lcl_linear x the three starts, and the two
    reference reaching laws) at 60 kr/min."""
    out = []
    for cur, pos, start in itertools.product(("pi", "dbpc", "robust_dbpc"),
                                             ("encoder", "smdo_emf"),
                                             ("running", "handover", "if")):
        base = drive.if_start() if start == "if" else drive._table1_steady("x")
        out.append((f"{cur}.{pos}.{start}",
                    base.with_controller(current=cur, position=pos, start=start)))
    for pos, start in itertools.product(("encoder", "lcl_smo_pll", "lcl_linear"),
                                        ("running", "handover", "if")):
        out.append((f"lcl.pi.{pos}.{start}",
                    yao2022.steady(60e3).with_controller(position=pos, start=start)))
    for law in ("tde17", "tde18"):
        out.append((f"lcl.pi.lcl_smo_pll.running.{law}",
                    yao2022.steady(60e3).with_controller(law=law)))
    out.append(("robust_dbpc.encoder.running.rls", tracker_scenario()))
    out.append(("robust_dbpc.smdo_emf.running.rls", tracker_scenario("smdo_emf")))
    return out


def tracker_scenario(position: str = "encoder"):
    """Table I's drive with the online R_s / psi_r tracker (smd_rls.h), its
    square wave (3 A) flipping every 5 ms (1.6 ms, 16 samples, with the
    SMDO's angle, whose frame is made of three whole periods first: the fit
    runs from the 96th sample) and forgetting over 20 ms,
    so that a few hundred samples see the fit take its values; at half rated
    speed (at rated speed and torque the deadbeat voltage, chasing the ADC's
    noise, reaches the hexagon on many samples, which the tracker leaves
    out)."""
    s = drive._table1_steady("x")
    w = 0.5 * s.motor.w_M_N
    return s.replace(w_M0=w, w_M_ref=Profile.const(w)).with_controller(
        current="robust_dbpc", position=position, rls_i_inj=3.0,
        rls_t_half=0.005 if position == "encoder" else 0.0016, rls_tau=0.02)



#: the paper scenarios whose recorded inputs the vectors replay at length
PAPER_CASES = ("yang2018.fig7a", "yao2022.steady.100k")


def standard_cases(samples: int = 600, paper_samples: int = 3000) -> list:
    """The vector set of the target test: every block of the core on its
    PRNG inputs (with non-finite values in the last tenth), every drive
    composition recorded from its scenario with the edge-case variants,
    the paper scenarios' recorded inputs, and a rejected composition."""
    cases: list = [BlockCase(f"block.{b}", b, 3000, 1000 + i)
                   for i, b in enumerate(("transforms", "svm", "pi", "dbpc", "smdo", "emf_pos",
                                          "pll", "bandpass", "math"))]
    tables = None
    for name, s in mode_scenarios():
        rec = drive_case("drive." + name, s, samples)
        cases += [rec, *variants(rec)]
        tables = tables or rec.tables
    cases += [TablesCase("tables", tables),
              BlockCase("block.lcl_smo.a", "lcl_smo", 3000, 3000),  # seed % 3: the law
              BlockCase("block.lcl_smo.b", "lcl_smo", 3000, 3001),
              BlockCase("block.lcl_smo.c", "lcl_smo", 3000, 3002),
              BlockCase("block.linobs", "linobs", 3000, 3003),
              BlockCase("block.table6", "table6", 1000, 3004),
              BlockCase("block.table6_dec", "table6_dec", 1000, 3005),
              BlockCase("block.ident", "ident", 6000, 3006),
              BlockCase("block.ident_ls.a", "ident_ls", 4000, 3008),  # seed % 2: the axis
              BlockCase("block.ident_ls.b", "ident_ls", 4000, 3007),
              BlockCase("block.ident_psi", "ident_psi", 3000, 3009),  # seed even: a filter
              BlockCase("block.ident_psi.lcl", "ident_psi", 3000, 3012),
              BlockCase("block.ident_psi.shorted", "ident_psi", 3000, 3013),
              BlockCase("block.ident_mech", "ident_mech", 800, 3010)]
    cat = catalogue()
    for name in PAPER_CASES:
        cases.append(drive_case("paper." + name, cat[name](), paper_samples))
    # a composition the drive rejects (DBPC through the LCL filter): both
    # builds must answer SMD_ERR_COMBINATION
    bad = cat["yao2022.steady.100k"]()
    cfg = drive_config(bad, tables)
    cfg.current = 1
    cases.append(DriveCase("drive.rejected.dbpc_lcl", cfg, tables, (0.0, 0.0, 0.0),
                           np.zeros((5, IN_WORDS), np.float32)))
    return cases


#: the suffix of a cycle case with injected faults (measured over every sample)
FAULTS = ", fault injection"
#: its samples: the last injected fault is at sample 40 + 11 x 39 = 469
FAULT_SAMPLES = 480


#: the name's tail of the cycle cases with the supervision spread over 4 samples
SPREAD = ", supervision / 4"


def cycle_cases(samples: int = 150):
    """What the cycle table measures: each block on its PRNG inputs (the
    first 100 calls, before the edge values), yao2022 Table VI's three
    parts, and the drive step of each composition in its steady phase."""
    blocks = [("transforms", "yang2018"), ("svm", "yang2018"), ("pi", "yang2018"),
              ("dbpc", "yang2018"), ("smdo", "yang2018"), ("emf_pos", "yang2018"),
              ("pll", "yao2022"), ("bandpass", "yao2022"), ("ident", "yang2018"),
              ("ident_ls", "yang2018"), ("ident_psi", "yang2018"), ("ident_mech", "yang2018")]
    # (step 4's block: 170 calls, its fit's end at 160 among them)
    cases: list = [BlockCase(f"block.{b}", b, 170 if b == "ident_mech" else 120, 11 + i)
                   for i, (b, _) in enumerate(blocks)]
    paper = {f"block.{b}": p for b, p in blocks}
    modes = []
    for cur in ("pi", "dbpc", "robust_dbpc"):
        for pos in ("encoder", "smdo_emf"):
            modes.append((f"drive {cur} + {pos}", "yang2018",
                          drive._table1_steady("x").with_controller(current=cur, position=pos)))
    modes.append(("drive robust_dbpc + smdo_emf, I/f forced phase", "yang2018",
                  drive.if_start()))
    modes.append(("drive robust_dbpc + encoder, R_s/psi_r tracker", "yang2018",
                  tracker_scenario()))
    modes.append(("drive robust_dbpc + smdo_emf, R_s/psi_r tracker", "yang2018",
                  tracker_scenario("smdo_emf")))
    for pos, law in (("encoder", "proposed"), ("lcl_smo_pll", "proposed"),
                     ("lcl_smo_pll", "tde17"), ("lcl_linear", "proposed")):
        name = f"drive pi + LCL + {pos}" + (f" ({law})" if pos == "lcl_smo_pll" else "")
        modes.append((name, "yao2022",
                      yao2022.steady(100e3).with_controller(position=pos, law=law)))
    # the fast build's option: the observer's model, band-pass coefficients
    # and delay taps refreshed every 8 samples (400 us at 20 kHz)
    modes.append(("drive pi + LCL + lcl_smo_pll (proposed, refresh / 8)", "yao2022",
                  yao2022.steady(100e3).with_controller(position="lcl_smo_pll",
                                                        smo_decimation=8)))
    # and the supervision's pieces one a sample over 4 (400 us at 10 kHz,
    # 200 us at 20 kHz: smd_drive.h, supervise_every)
    modes.append((f"drive robust_dbpc + smdo_emf{SPREAD}", "yang2018",
                  drive._table1_steady("x").with_controller(current="robust_dbpc",
                                                            position="smdo_emf",
                                                            supervise_every=4)))
    modes.append((f"drive pi + LCL + lcl_smo_pll (proposed, refresh / 8){SPREAD}", "yao2022",
                  yao2022.steady(100e3).with_controller(position="lcl_smo_pll",
                                                        smo_decimation=8,
                                                        supervise_every=4)))
    tables = None
    for name, p, s in modes:
        c = drive_case(name, s, samples)
        tables = tables or c.tables
        cases.append(c)
        paper[name] = p
    # the two sensorless steps with faults injected (NaN, +-inf, 1e30 at single
    # samples of each input, u_dc = 0 for ten samples: the vector tests'
    # .faults variant), every sample measured: the worst call includes the
    # fault path (held inputs, the safe state, the blocks' recovery)
    for name, p, s in modes:
        if name in ("drive robust_dbpc + smdo_emf", "drive pi + LCL + lcl_smo_pll (proposed)",
                    f"drive robust_dbpc + smdo_emf{SPREAD}",
                    f"drive pi + LCL + lcl_smo_pll (proposed, refresh / 8){SPREAD}"):
            c = variants(drive_case(name, s, FAULT_SAMPLES))[3]
            c = dataclasses.replace(c, name=name + FAULTS)
            cases.append(c)
            paper[c.name] = p
    cases += [TablesCase("tables", tables),
              BlockCase("block.lcl_smo", "lcl_smo", 120, 3000),
              BlockCase("block.linobs", "linobs", 120, 3003),
              BlockCase("table6", "table6", 120, 7),
              BlockCase("table6 (refresh / 8)", "table6_dec", 160, 7)]
    paper.update({"block.lcl_smo": "yao2022", "block.linobs": "yao2022",
                  "table6": "yao2022", "table6 (refresh / 8)": "yao2022"})
    return cases, paper



def cycle_table(math: str = "fmath", work=None, samples: int = 150):
    """The Cortex-M4F cycle table of :func:`cycle_cases`
    (:func:`smodrive.firmware.cycle_table`)."""
    cases, paper = cycle_cases(samples)
    return cycles.cycle_table(cases, paper, math, work, samples,
                              whole={n for n in paper if n.endswith(FAULTS)})


#: the cases each fixed composition runs (build.FIXED), steady and with faults
#: injected
_YANG, _YAO = "drive robust_dbpc + smdo_emf", "drive pi + LCL + lcl_smo_pll (proposed, refresh / 8)"
FIXED_CASES = {"yang2018": (f"{_YANG}{SPREAD}", f"{_YANG}{SPREAD}{FAULTS}"),
               "yao2022": (f"{_YAO}{SPREAD}", f"{_YAO}{SPREAD}{FAULTS}")}


def fixed_cycle_table(paper_name: str, math: str = "fast", work=None, samples: int = 150):
    """The sensorless step of `paper_name` ("yang2018" or "yao2022") of
    :func:`cycle_table` (steady, and with faults injected) with its
    composition fixed at compile time (smd_drive.h;
    :data:`smodrive.firmware.build.FIXED`)."""
    names = FIXED_CASES[paper_name]
    cases, paper = cycle_cases(samples)
    cases = [c for c in cases if c.name in names]
    return cycles.cycle_table(cases, paper, math, work, samples,
                              whole={n for n in names if n.endswith(FAULTS)},
                              extra=FIXED[paper_name])
