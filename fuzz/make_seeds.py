"""Write the seed corpus of the fuzz targets (fuzz/corpus/<target>/seed-*).

The seeds are the papers' typical configurations in the byte format of
fuzz/fuzz.h (exact values: a raw float for the core, a raw double for the
plant), each followed by a sequence that runs the drive (or block) for some
hundred samples, and a few edge cases (non-finite inputs, a rejected
configuration). The drive configurations, plant configurations, profiles and
LCL observer tables come from the smodrive package (scenario catalogue,
smodrive.engine), the yang2018 Table I drive also from
core/test/drive_fixture.h (written out here). The LCL tables are cut to 3
rows around the scenario's speed (the table clamps outside), so that a seed
stays a few kB.

    .venv/bin/python fuzz/make_seeds.py          # rewrites seed-* only
    .venv/bin/python fuzz/make_seeds.py --check  # exit 1 naming every stale seed

The drive configuration's field order and ranges are fuzz/drive_fields.py,
generated with the decoder fuzz/fz_drive_config.h from the header
(tools/gen_layout.py).

Files not named seed-* (regression inputs of fixed findings, crash-*) are
left alone.
"""

from __future__ import annotations

import math
import struct
import sys
import tempfile
from pathlib import Path

from drive_fields import DRIVE_FIELDS, STRUCT_FIELDS  # generated from the headers (tools/gen_layout.py)

ROOT = Path(__file__).resolve().parent
CORPUS = ROOT / "corpus"
OUT = CORPUS  # where write() puts the seeds (a temporary directory for --check)

# ---------------------------------------------------------------- format --

NAN, INF, NINF, ZERO, NZERO, FLT_MAX, NFLT_MAX, BIG30, NBIG30 = range(0xE0, 0xE9)
FLT_MIN, DENORM, DBL_MAX, NDBL_MAX, LO, HI, E300 = range(0xE9, 0xF0)


class W:
    """Writer of fuzz.h's format."""

    def __init__(self) -> None:
        self.b = bytearray()

    def u8(self, v: int) -> "W":
        self.b.append(v & 0xFF)
        return self

    def u16(self, v: int) -> "W":
        self.b += struct.pack("<H", v & 0xFFFF)
        return self

    def u32(self, v: int) -> "W":
        self.b += struct.pack("<I", v & 0xFFFFFFFF)
        return self

    def int(self, v: int, lo: int, hi: int) -> "W":
        span = hi - lo + 1
        if lo <= v <= hi:
            if span < 0xFB:
                return self.u8(v - lo)
            if v - lo < 0x10000:
                return self.u8(0).u16(v - lo)
        self.u8(0xFD)
        self.b += struct.pack("<i", v)
        return self

    def f32(self, x: float) -> "W":
        """a real for the core: raw float bits"""
        self.u8(0xF0)
        self.b += struct.pack("<f", x)
        return self

    def f64(self, x: float) -> "W":
        """a real for the plant: raw double bits"""
        self.u8(0xF8)
        self.b += struct.pack("<d", x)
        return self

    def special(self, tag: int) -> "W":
        return self.u8(tag)

    def bytes(self) -> bytes:
        return bytes(self.b)


def write(target: str, name: str, data: bytes) -> None:
    d = OUT / target
    d.mkdir(parents=True, exist_ok=True)
    (d / f"seed-{name}").write_bytes(data)


# ------------------------------------------------------ drive (fuzz.h) --

def put_fields(w: W, fields, values: dict) -> None:
    """The int and real fields of a field list (DRIVE_FIELDS' kinds), a value
    values lacks 0 (off)."""
    for name, kind, args in fields:
        if kind == "int":
            w.int(int(values.get(name, 0)), *args)
        elif kind == "real":
            w.f32(float(values.get(name, 0.0)))
        else:
            raise ValueError(f"put_fields: {name} is {kind}")


def put_lcl_grid(w: W, tables) -> None:
    """fz_lcl_grid (fuzz.h): one grid and the rows of both observer tables
    (models (n, 113), lin (n, 56), w_min, dw)."""
    m, lin, w_min, dw = tables
    w.int(m.shape[0], 0, 6)
    w.f32(w_min).f32(dw)
    for k in range(m.shape[0]):
        for x in m[k]:
            w.f32(float(x))
        for x in lin[k]:
            w.f32(float(x))


def put_lcl_tables(w: W, cfg: dict, tables) -> None:
    """smd_drive_config.lin as fz_lcl_tables (fuzz.h) reads it: for an LCL
    source the grid and tables, then 0 (0xFF: NULL tables)."""
    if cfg["position"] in (2, 3):
        put_lcl_grid(w, tables)
        w.u8(0)


def put_drive(w: W, cfg: dict, tables=None, protection: bool = False) -> None:
    """The drive configuration in the order of fz_drive_config (DRIVE_FIELDS,
    generated from the header with it). cfg: the fields of smd_drive_config
    by name, a nested config (smo) as a dict of its fields (a field cfg lacks
    is 0: off); tables: (models (n, 113), lin (n, 56), w_min, dw). protection:
    the flagged fields (protection and supervision) follow; else they are 0."""
    for name, kind, args in DRIVE_FIELDS:
        if kind == "flag":
            w.u8(1 if protection else 0)
            if not protection:
                return
        if kind in ("int", "real"):
            put_fields(w, [(name, kind, args)], cfg)
        elif kind == "struct":
            put_fields(w, STRUCT_FIELDS[args[0]], cfg.get(name, {}))
        elif kind == "call":
            {"fz_lcl_tables": put_lcl_tables}[args[0]](w, cfg, tables)


# the yang2018 Table I drive of core/test/drive_fixture.h
LS, RS, PSI, TSP = 23.45e-3, 2.25, 0.4, 1e-4


def fixture_config(current: int, position: int, start: int) -> dict:
    return dict(current=current, position=position, start=start, lcl=0, T_sp=TSP,
                L_s_hat=LS, R_s_hat=RS, psi_r_hat=PSI, lambda_min=800.0, l=1200.0, w_c=1500.0,
                rho=0.2, smdo_euler=0, w_lpf=200.0, w_hys=20.0, w_max=2000.0,
                k_p_i=LS * 2000.0, k_i_i=LS * 2000.0 * 2000.0 / 4.0, L_dec=LS, R_v=0.0,
                emf_ff=1, speed_loop=0, k_p_w=0.05, k_i_w=2.0, i_max=15.0, speed_decimation=1,
                k_theta=0.1, k_omega=10.0, k_a=10.0, handover=0, i_start=8.0, a_start=2e4,
                w_handover=201.0, svm_limit=1, t_dead_comp=0.0, i_dtc=1.0,
                i_trip=37.5, u_dc_min=270.0, u_dc_max=700.0, safe_state=0, lock_samples=200,
                lock_ratio=3.0, w_lock_min=50.0, w_if_enter=0.0)


# synthetic source of fuzz_drive.c: set (op 1) parameter `which`, run (op 2)
SYN = dict(theta=0, w=1, i_d=2, i_q=3, k1=4, u_dc=5, w_ref=6, id_ref=7, iq_ref=8)


def syn_set(out: W, **kv) -> None:
    for name, v in kv.items():
        out.u8(1).u8(SYN[name]).f32(float(v))


def syn_run(w: W, n: int) -> None:
    while n > 0:
        k = min(n, 256)
        w.u8(2).u8(k - 1)
        n -= k


def raw_step(w: W, i_a, i_b, i1_a, i1_b, th, we, udc, wref, idr, iqr) -> None:
    w.u8(0)
    for v in (i_a, i_b, i1_a, i1_b, th, we, udc, wref, idr, iqr):
        if isinstance(v, float) or isinstance(v, int):
            w.f32(float(v))
        else:  # a special tag, e.g. ("s", NAN)
            w.special(v[1])


def drive_run(w: W, w_e: float, i_q: float, u_dc: float, k1: float = 0.0,
              samples: int = 1024, step_to: float | None = None) -> None:
    """the synthetic machine at speed w_e carrying i_q, then a reference step"""
    syn_set(w, w=w_e, i_q=i_q, u_dc=u_dc, w_ref=w_e, iq_ref=i_q, k1=k1)
    syn_run(w, samples)
    if step_to is not None:
        syn_set(w, iq_ref=step_to, i_q=step_to)
        syn_run(w, 512)


def drive_seeds(cat, sim) -> None:
    # yang2018 Table I (drive_fixture.h): the five compositions of the tests
    for name, (cc, pos, st) in {
            "fixture-dbpc-encoder": (1, 0, 0), "fixture-robust-encoder": (2, 0, 0),
            "fixture-sensorless-handover": (2, 1, 1), "fixture-pi-encoder": (0, 0, 0),
            "fixture-pi-smdo": (0, 1, 0), "fixture-robust-if": (2, 1, 2)}.items():
        cfg = fixture_config(cc, pos, st)
        if st == 1:
            cfg["handover"] = 500
        w = W()
        put_drive(w, cfg)
        w.f32(0.3).f32(400.0).f32(2.0)  # reset: theta0, w0 = 400 rad/s, i_q0 = 2 A
        drive_run(w, 400.0, 2.0, 540.0, samples=1024, step_to=6.0)
        write("fuzz_drive", name, w.bytes())
    # the same with the protection on and the speed loop, then faults
    cfg = fixture_config(2, 1, 1)
    cfg.update(speed_loop=1, handover=100)
    w = W()
    put_drive(w, cfg, protection=True)
    w.f32(0.0).f32(400.0).f32(1.0)
    drive_run(w, 400.0, 1.0, 540.0, samples=600)
    syn_set(w, i_q=60.0)       # overcurrent
    syn_run(w, 10)
    w.u8(4)                    # clear the faults
    syn_set(w, i_q=1.0, u_dc=200.0)  # undervoltage
    syn_run(w, 10)
    w.u8(4)
    syn_set(w, u_dc=540.0)
    w.u8(3).f32(0.0).f32(400.0).f32(1.0)  # restart
    syn_run(w, 300)
    write("fuzz_drive", "fixture-protection-faults", w.bytes())
    # non-finite and huge inputs on the robust DBPC, then recovery
    w = W()
    put_drive(w, fixture_config(2, 0, 0))
    w.f32(0.0).f32(400.0).f32(0.0)
    drive_run(w, 400.0, 2.0, 540.0, samples=300)
    raw_step(w, ("s", NAN), 1.0, 0.0, 0.0, 0.5, 400.0, 540.0, 400.0, 0.0, 2.0)
    raw_step(w, 1.0, 1.0, 0.0, 0.0, ("s", INF), 400.0, 540.0, 400.0, 0.0, 2.0)
    raw_step(w, 1.0, 1.0, 0.0, 0.0, 0.5, ("s", FLT_MAX), ("s", NINF), 400.0, 0.0, 2.0)
    raw_step(w, ("s", FLT_MAX), ("s", NFLT_MAX), 0.0, 0.0, 0.5, 400.0, 540.0, 400.0,
             ("s", BIG30), 2.0)
    syn_run(w, 300)
    write("fuzz_drive", "fixture-nonfinite-inputs", w.bytes())
    # a composition the drive refuses (DBPC through an LCL filter)
    w = W()
    cfg = fixture_config(1, 0, 0)
    cfg["lcl"] = 1
    put_drive(w, cfg)
    write("fuzz_drive", "rejected-dbpc-lcl", w.bytes())

    # the catalogue's scenarios (both papers, every composition)
    for name in ("yang2018.base", "yang2018.fig1", "yang2018.fig7a", "yang2018.fig9",
                 "drive.pi_encoder", "drive.pi_sensorless", "drive.if_start",
                 "drive.lcl_encoder", "yao2022.steady.100k", "yao2022.fig14",
                 "yao2022.fig19", "yao2022.fig22"):
        s = cat[name]()
        cfg, tables = scenario_drive(s, sim)
        n_p = s.motor.n_p
        w_e = s.w_M0 * n_p
        i_q0 = sim._warm_i_q0(s)
        w = W()
        put_drive(w, cfg, tables)
        w.f32(s.theta_r0).f32(w_e).f32(i_q0)
        k1 = 0.05 if s.lcl is not None else 0.0
        drive_run(w, w_e, i_q0, s.inverter.u_dc, k1=k1, samples=1024,
                  step_to=i_q0 + 0.2 * cfg["i_max"])
        write("fuzz_drive", name.replace(".", "-"), w.bytes())
        if name == "yao2022.fig22":  # the same drive on the linear LCL observer
            cfg = dict(cfg, position=3)
            w = W()
            put_drive(w, cfg, tables)
            w.f32(s.theta_r0).f32(w_e).f32(i_q0)
            drive_run(w, w_e, i_q0, s.inverter.u_dc, k1=k1, samples=1024)
            write("fuzz_drive", "yao2022-fig22-linear", w.bytes())


def table_slice(tables, w_e: float, rows: int = 3):
    m, lin, w_min, dw = tables
    n = m.shape[0]
    k = int(round((w_e - w_min) / dw)) - 1
    k = max(0, min(n - rows, k))
    return m[k:k + rows], lin[k:k + rows], float(w_min + k * dw), float(dw)


def scenario_drive(s, sim):
    """(config dict, sliced tables or None) of scenario s"""
    tables = sim.lcl_observer_tables(s) if s.lcl is not None else None
    c = sim.drive_config(s, tables)
    cfg = {name: getattr(c, name) for name, kind, _ in DRIVE_FIELDS if kind in ("int", "real")}
    cfg["smo"] = {name: getattr(c.smo, name) for name, _, _ in STRUCT_FIELDS["smd_lcl_smo_config"]}
    if tables is not None:
        tables = table_slice(tables, s.w_M0 * s.motor.n_p)
    return cfg, tables


# ------------------------------------------------------ plant, engine --

PLANT_FIELDS = ["R_s", "L_s", "psi_r", "n_p", "J", "B", ("lcl", (0, 1)), "L1", "L2o", "C1",
                "u_dc", "T_sw", ("pwm_mode", (0, 1)), ("dead_time_model", (0, 1)),
                "t_dead"]
PLANT_TAIL = ["w_brake_eps", "k_fan", "w_M0", "theta_r0", "i_d0", "i_q0", "uc_d0", "uc_q0",
              "i1_d0", "i1_q0"]


def put_plant(w: W, c) -> None:
    for f in PLANT_FIELDS:
        if isinstance(f, tuple):
            w.int(int(getattr(c, f[0])), *f[1])
        else:
            w.f64(float(getattr(c, f)))
    for k in range(3):
        w.f64(c.adc_gain[k]).f64(c.adc_offset[k]).f64(c.adc_gain_i1[k]).f64(c.adc_offset_i1[k])
    w.f64(c.adc_noise)
    w.int(int(c.adc_bits), 0, 24)
    w.int(int(c.adc_n_oversample), 0, 64)
    w.int(int(c.adc_sensors), 0, 3)
    w.f64(c.adc_full_scale)
    w.u32(int(c.seed))
    for f in PLANT_TAIL:
        w.f64(float(getattr(c, f)))


def put_pwl(w: W, p) -> None:
    n = min(int(p.n), 4)  # fz_pwl: n in [0, 4] (its last point holds)
    w.int(n, 0, 4)
    t_prev = 0.0
    for k in range(n):
        w.f64(float(p.t[k]) - t_prev)
        t_prev = float(p.t[k])
        w.f64(float(p.y[k]))


def plant_seeds(cat, sim) -> None:
    for name in ("yang2018.base", "yang2018.fig1", "yao2022.steady.100k", "drive.lcl_encoder"):
        s = cat[name]()
        c = sim.plant_config(s)
        w = W()
        put_plant(w, c)
        # open-loop periods at modulation 0.6, then raw duties and a brake
        for _ in range(4):
            w.u8(1).u8(255).f64(0.6).f64(0.3).f64(0.0)
        w.u8(0).f64(0.9).f64(0.1).f64(0.5).f64(0.5).f64(2.0)
        w.u8(2).u8(2 + 8).u8(2 + 16)
        w.u8(3).f64(s.T_sp).f64(s.inverter.t_dead).f64(0.7).f64(-3.0)
        w.u8(4).f64(5.0).f64(1.0).f64(0.01).f64(0.02).int(12, 0, 24).f64(30.0)
        w.u8(5).int(29, -1, 33)
        write("fuzz_plant", name.replace(".", "-"), w.bytes())
    # zero-current clamping and ADC oversampling near standstill, small current
    s = cat["yang2018.base"]()
    c = sim.plant_config(s)
    c.dead_time_model, c.adc_n_oversample = 1, 4
    c.w_M0, c.i_q0 = 2.0, 0.05
    w = W()
    put_plant(w, c)
    for _ in range(4):
        w.u8(1).u8(255).f64(0.02).f64(1.5).f64(0.0)
    w.u8(0).f64(0.501).f64(0.5).f64(0.499).f64(0.0).f64(0.0)
    w.u8(2).u8(2 + 8).u8(2 + 16)
    write("fuzz_plant", "yang2018-base-clamp", w.bytes())
    # a refused configuration (the helpers run on)
    w = W()
    for _ in range(14):
        w.special(NAN)
    w.u8(1).f64(1e-4).f64(2e-6).special(NAN).f64(1.0)
    write("fuzz_plant", "rejected-nan", w.bytes())


def engine_seeds(cat, sim, n_log: int) -> None:
    for name in ("yang2018.base", "yang2018.fig7a", "drive.pi_encoder", "drive.if_start",
                 "yao2022.steady.100k", "yao2022.fig14", "drive.lcl_encoder"):
        s = cat[name]()
        w = W()
        put_plant(w, sim.plant_config(s))
        cfg, tables = scenario_drive(s, sim)
        put_drive(w, cfg, tables, protection=name == "drive.if_start")
        p = sim.profiles(s)
        for pw in (p.w_M_ref, p.T_ext, p.T_brake, p.i_d_ref, p.i_q_ref):
            put_pwl(w, pw)
        w.f64(p.i_d_sin_amp).f64(p.i_d_sin_freq)
        w.f64(s.theta_r0).f64(s.w_M0 * s.motor.n_p).f64(sim._warm_i_q0(s))
        for _ in range(3):
            w.u8(0).u8(255)            # 256 samples, every one logged
        w.u8(1 + 4).u8(1)              # split samples, one with a log row
        w.u8(4).u8(255)                # 256 samples, a row every second one
        w.u8(2).u8(0).f64(0.01)        # a profile value
        w.u8(3).u8(16).f64(s.T_sp).f64(0.1).f64(10.0).f64(10.0).f64(0.1).int(3, -1, n_log)
        w.int(5, -1, 400)              # a row of the layout table
        write("fuzz_engine", name.replace(".", "-"), w.bytes())


# ------------------------------------------------------- LCL observers --

def lcl_seeds(cat, sim) -> None:
    for name, law in (("yao2022.steady.100k", None), ("yao2022.fig19", 1), ("yao2022.fig22", 2),
                      ("yao2022.fig14", None)):
        s = cat[name]()
        cfg, tables = scenario_drive(s, sim)
        w_e = max(s.w_M0 * s.motor.n_p, 500.0)
        if name == "yao2022.fig14":
            tables = table_slice(sim.lcl_observer_tables(s), 0.0)
        m, lin, w_min, dw = tables
        w = W()
        w.f32(s.T_sp)
        put_fields(w, STRUCT_FIELDS["smd_lcl_smo_config"],
                   cfg["smo"] if law is None else {**cfg["smo"], "law": law})
        put_lcl_grid(w, (m, lin, w_min, dw))
        w.f32(0.0)  # reset angle
        # rotation at w_e: EMF-sized voltage, i_1 a little above i_2
        psi = s.controller.psi_r_hat
        w.u8(5).f64(w_e).f64(5.2).f64(5.0).f64(w_e * psi)
        for _ in range(4):
            w.u8(1).u8(255)
        w.u8(2).f32(0.01)                                  # reframe
        w.u8(4).f32(w_e).f32(5.0).f32(0.0).f32(5.0).f32(0.0).f32(w_e * psi).f32(0.0)
        # a raw step: i_1 (NaN), i_2, u, theta, w
        w.u8(0).special(NAN).f32(0.0).f32(1.0).f32(0.0).f32(0.0).f32(0.0).f32(0.0).f32(w_e)
        w.u8(1).u8(100)
        w.u8(3).f32(0.0)                                   # reset
        w.u8(1).u8(100)
        write("fuzz_lcl_obs", name.replace(".", "-") + (f"-law{law}" if law else ""), w.bytes())


# ----------------------------------------------------- blocks and math --

def block_seeds() -> None:
    T = 1e-4
    # 0 svm: hexagon, then circle; a turning reference beyond the hexagon
    for limit in (0, 1):
        w = W().u8(0).int(limit, 0, 1).f32(0.0)
        w.u8(1).f32(540.0).u8(255).f64(400.0).f64(0.0).f64(0.05)   # run, no dead-time comp.
        w.u8(0).f32(540.0).f32(300.0).f32(-100.0)                   # one step
        w.u8(2).f32(540.0).f32(100.0).f32(50.0)                     # one step + dead time
        w.f32(0.02).f32(1.0).f32(10.0).f32(-0.5).f32(3.0)
        w.u8(0).f32(540.0).special(FLT_MAX).special(NFLT_MAX)       # the huge reference
        write("fuzz_blocks", f"svm-limit{limit}", w.bytes())
    # 1 pi: the yang2018 speed PI
    w = W().u8(1).f32(0.05).f32(2.0).f32(T).f32(15.0).f32(0.0)
    w.u8(1).f32(20.0).u8(255).u8(3).f32(-2000.0).u8(200).f32(0.0).u8(0).special(NAN)
    write("fuzz_blocks", "pi-yang2018", w.bytes())
    # 2 dbpc: Table I
    w = W().u8(2).f32(T).f32(LS).f32(RS).f32(PSI)
    for k in range(8):
        th = -3.0 + 0.8 * k
        w.f32(3.0).f32(-1.0).f32(200.0).f32(50.0).f32(0.0).f32(5.0).f32(th).f32(400.0)
    write("fuzz_blocks", "dbpc-yang2018", w.bytes())
    # 3 smdo: Table I, both discretisations
    for euler in (0, 1):
        w = W().u8(3).f32(T).f32(LS).f32(RS).f32(800.0).f32(1200.0).f32(1500.0).f32(0.2)
        w.int(euler, 0, 1).f32(0.0).f32(0.0).f32(0.0).f32(0.0)
        w.u8(1).f32(400.0).u8(255).f64(5.0).f64(0.0).f64(0.04).f64(160.0).f64(1.57).f64(0.04)
        w.u8(1).f32(400.0).u8(255).f64(5.0).f64(0.0).f64(0.04).f64(160.0).f64(1.57).f64(0.04)
        w.u8(0).f32(400.0).special(NAN).f32(0.0).f32(0.0).f32(0.0)
        write("fuzz_blocks", f"smdo-euler{euler}", w.bytes())
    # 4 emf_pos: yang2018 (w_lpf 200, w_hys 20, w_max 2000)
    w = W().u8(4).f32(T).f32(200.0).f32(20.0).f32(2000.0).f32(400.0)
    w.u8(1).u8(255).f64(160.0).f64(0.0).f64(0.04)
    w.u8(1).u8(255).f64(160.0).f64(0.0).f64(-0.04)
    w.u8(0).special(NAN).f32(1.0)
    write("fuzz_blocks", "emf-pos-yang2018", w.bytes())
    # 5 pll: yao2022 eq. (50) at 20 kHz
    w = W().u8(5).f32(5e-5).f32(0.1).f32(10.0).f32(10.0).f32(0.0).f32(1000.0)
    w.u8(1).f32(0.01).u8(255).u8(0).special(INF).u8(3).f32(0.0).u8(50).f32(-1.0).f32(0.0)
    write("fuzz_blocks", "pll-yao2022", w.bytes())
    # 6 bandpass: 2 f_e at 1 krad/s, 20 % bandwidth
    w = W().u8(6)
    w.u8(1 + 2).u8(255).f32(5e-5).f32(2000.0).f32(400.0).f64(1.0).f64(0.0).f64(0.1)
    w.u8(1 + 4).u8(255).f64(1.0).f64(0.0).f64(0.1)
    w.u8(2).f32(5e-5).f32(70000.0).f32(400.0).f32(1.0).f32(0.0)
    write("fuzz_blocks", "bandpass-yao2022", w.bytes())
    # ident (a first byte of 0xF0 or more): issue 23's R_s test as core/target runs it (Table I
    # stator, 10 kHz, i_test 4 A, 2 ms windows, 8 levels), a search's currents, then a NaN
    w = W().u8(0xF0).f32(1e-4).f32(4.0).f32(311.0).f32(2e-3).f32(0.2).int(8, 0, 40)
    for i_a in (0.0, 0.0, 0.1, 0.5, 1.0, 2.0, 4.5):
        w.u8(1).f32(i_a).f32(-0.5 * i_a).f32(540.0).u8(40)
    w.u8(0).special(NAN).f32(0.0).f32(540.0)
    write("fuzz_blocks", "ident-yang2018", w.bytes())
    # the inductance test (0xF8 or more) on the d axis of the same stator, its bias, a wave
    w = W().u8(0xF8).f32(1e-4).f32(2.25).f32(14.4).f32(2.0).f32(311.0).f32(2e-3)
    w.int(0, -1, 2).int(8, 0, 80).int(20, 0, 200)
    for i_a in (0.0, 1.0, 2.0, 2.0, 2.1, 1.9, 2.0):
        w.u8(1).f32(i_a).f32(-0.5 * i_a).f32(540.0).u8(60)
    write("fuzz_blocks", "ident-ls-yang2018", w.bytes())
    # the flux test (0xFB or more) on the same stator: a spin's first samples
    w = W().u8(0xFB).f32(1e-4).f32(2.25).f32(23.45e-3).f32(14.4).f32(4.0).f32(157.0)
    w.f32(314.0).f32(157.0).f32(0.05).f32(0.02).f32(1570.0).f32(0.0).f32(0.0).f32(0.0)  # no filter
    w.f32(125.7).f32(0.7)  # the stabiliser and the governor
    for i_a in (0.0, 1.0, 2.0, -2.0, 3.0, 0.5):
        w.u8(1).f32(i_a).f32(-0.5 * i_a).f32(540.0).u8(200)
    write("fuzz_blocks", "ident-psi-yang2018", w.bytes())
    # step 4 (0xEC-0xEF): J and B at 10 kHz, Table I's k_t and pole pairs, a short sequence
    # (20 ms each part, 2 ms bins), a rotor accelerating under its torque current, a fault
    w = W().u8(0xEC).f32(1e-4).f32(2.4).int(4, 0, 120).f32(250.0).f32(500.0).f32(0.02)
    w.f32(0.02).f32(0.02).f32(0.008).f32(0.002).f32(100.0).int(1, -1, 2)  # with a fan
    w.f32(0.06)  # a coast
    for i_q, w_e in ((0.5, 250.0), (0.5, 250.0), (3.0, 300.0), (3.0, 400.0), (0.5, 500.0)):
        w.u8(1).f32(i_q).f32(w_e).f32(540.0).u8(120)
    w.u8(0).f32(0.5).f32(500.0).f32(-1.0)
    write("fuzz_blocks", "ident-mech-yang2018", w.bytes())


def math_seeds() -> None:
    w = W()
    for x, y in ((0.7853982, 1.0), (8192.5, -3.0), (1e30, 0.0), (-2.5, -1e-3), (88.0, 1e38),
                 (-104.0, -0.0), (3.4e38, 1e38)):
        w.u8(0).f64(x).f64(y)
    w.u8(0).special(FLT_MAX).special(NFLT_MAX)
    w.u8(0).special(NZERO).special(NINF)
    w.u8(0).special(NAN).f64(1.0)
    write("fuzz_math", "fmath", w.bytes())
    w = W()
    w.u8(1).f32(10.0).f32(-4.0).f32(-6.0).f32(0.5)
    w.u8(1).special(FLT_MAX).special(NFLT_MAX).special(NAN).special(BIG30)
    w.u8(2).f32(1.0).f32(0.0).f32(2.0).f32(1e-4).f32(0.02).f32(2.0).int(14, -1, 40)
    write("fuzz_math", "transforms-helpers", w.bytes())
    w = W().u8(3).int(4, 2, 9).int(3, 1, 6)
    for k in range(12):
        w.f32(0.1 * k - 0.5)
    w.f32(-100.0).f32(50.0).f32(33.0)
    write("fuzz_math", "table-interp", w.bytes())


def seeds(corpus: Path) -> dict[str, bytes]:
    """Every seed-* file under corpus: relative path -> bytes."""
    return {str(f.relative_to(corpus)): f.read_bytes() for f in sorted(corpus.glob("*/seed-*"))}


def main(argv: list[str] | None = None) -> int:
    global OUT
    argv = sys.argv[1:] if argv is None else argv
    check = "--check" in argv
    try:
        from smodrive.engine import marshal as sim
        from smodrive.engine.channels import CHANNELS
        from smodrive.scenarios import catalogue
    except ImportError as exc:  # the package is needed for the scenario seeds
        print(f"smodrive not importable ({exc}): run with the project's .venv", file=sys.stderr)
        return 1
    with tempfile.TemporaryDirectory() as tmp:
        OUT = Path(tmp) if check else CORPUS
        block_seeds()
        math_seeds()
        cat = catalogue()
        drive_seeds(cat, sim)
        plant_seeds(cat, sim)
        engine_seeds(cat, sim, len(CHANNELS))  # SMD_LOG_N
        lcl_seeds(cat, sim)
        if check:  # the committed seeds are what this writes
            new, old = seeds(OUT), seeds(CORPUS)
            bad = sorted(k for k in set(new) | set(old) if new.get(k) != old.get(k))
            for k in bad:
                print(f"fuzz/corpus/{k} is out of date: run fuzz/make_seeds.py", file=sys.stderr)
            return 1 if bad else 0
    for d in sorted(CORPUS.iterdir()):
        files = list(d.glob("seed-*"))
        print(f"{d.name}: {len(files)} seeds, {sum(f.stat().st_size for f in files)} bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
