"""smodrive side by side with motulator: plant agreement, speed on the same
work, and what smodrive's cost is made of (issue 4). A benchmark, not a test.

    python benchmarks/vs_motulator.py [--out benchmarks/results] [--repeat 3]
                                      [--seconds 1.0] [--agree-seconds 1.2]
    python benchmarks/vs_motulator.py --no-motulator --smoke   # tiny, no install

motulator is installed into its own venv (benchmarks/.motulator-venv, with the
first Python >= 3.12 found, else Python 3.11 and the last motulator release
for it) and runs in a subprocess (benchmarks/motulator_side.py); it is never a
dependency of smodrive. Writes results.json and results.md to --out.
benchmarks/README.md explains every convention bridged and how to read the
figures.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import glob
import json
import multiprocessing as mp
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from smodrive.model import RPM, AdcCfg, InverterCfg, LoadCfg, Profile
from smodrive.engine.plant import Plant
from smodrive.scenarios import yang2018 as y
from smodrive.engine import simulate

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
VENV = HERE / ".motulator-venv"
SIDE = HERE / "motulator_side.py"
MOTULATOR_SPEC = "motulator==0.18.0"  # the release this helper was written and checked with
MOTULATOR_SPEC_311 = "motulator==0.5.0"  # the last release installable on Python 3.11
T_SP = 100e-6
U_DC = 540.0
MOTOR = y.MOTOR  # yang2018 Table I
CARRIER_N = 4096  # motulator's carrier counter (CarrierComparison(N=2**12)): duty grid
TARGET_RMS = {"averaged": 0.5, "carrier": 1.0}  # %, issue 4
TARGET_RATIO = {"averaged": 1000.0, "carrier": 3000.0}
MODES = ("averaged", "carrier")


def log(msg: str) -> None:
    print(msg, flush=True)


# ------------------------------------------------------- motulator venv -----

def _py_version(exe: str) -> tuple[int, int] | None:
    """(major, minor) of a working interpreter with venv, else None (a pyenv
    shim of a version that is not selected fails here, as it should)."""
    try:
        r = subprocess.run([exe, "-c", "import sys, venv; print(*sys.version_info[:2])"],
                           capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return None
    if r.returncode != 0:
        return None
    try:
        a, b = r.stdout.split()
        return int(a), int(b)
    except ValueError:
        return None


def _pyenv_versions() -> list[str]:
    root = None
    if shutil.which("pyenv"):
        r = subprocess.run(["pyenv", "root"], capture_output=True, text=True)
        root = r.stdout.strip() if r.returncode == 0 else None
    root = root or os.environ.get("PYENV_ROOT") or str(Path.home() / ".pyenv")
    found = glob.glob(os.path.join(root, "versions", "3.1[0-9]*", "bin", "python3.1[0-9]"))

    def key(p: str) -> tuple[int, ...]:
        m = re.search(r"versions/(\d+)\.(\d+)(?:\.(\d+))?", p)
        return tuple(int(x or 0) for x in m.groups()) if m else (0,)

    return sorted(found, key=key, reverse=True)


def find_python(forced: str | None) -> tuple[str, tuple[int, int], str]:
    """(interpreter, version, motulator spec): the first Python >= 3.12 found
    (this one, python3.13, python3.12 on PATH, then pyenv's versions), else a
    Python 3.11 with the last motulator release for 3.11."""
    if forced:
        v = _py_version(forced)
        if v is None:
            raise SystemExit(f"--python {forced}: not a working interpreter with venv")
        return forced, v, MOTULATOR_SPEC if v >= (3, 12) else MOTULATOR_SPEC_311
    cands: list[str] = []
    if sys.version_info >= (3, 12):
        cands.append(sys.executable)
    cands += [w for w in (shutil.which("python3.13"), shutil.which("python3.12")) if w]
    pyenv = _pyenv_versions()
    cands += pyenv
    for c in cands:
        v = _py_version(c)
        if v is not None and v >= (3, 12):
            return c, v, MOTULATOR_SPEC
    old = ([sys.executable] if sys.version_info[:2] == (3, 11) else []) + \
        [w for w in (shutil.which("python3.11"),) if w] + pyenv
    for c in old:
        v = _py_version(c)
        if v == (3, 11):
            return c, v, MOTULATOR_SPEC_311
    raise SystemExit("no Python >= 3.11 with venv found for motulator")


def setup_motulator(venv: Path, forced_python: str | None, spec: str | None) -> dict:
    """Create (or reuse) the venv and install motulator; returns what was used."""
    exe, ver, default_spec = find_python(forced_python)
    spec = spec or default_spec
    py = venv / "bin" / "python"
    stamp = venv / "smodrive-bench.json"
    if stamp.exists() and py.exists():
        info = json.loads(stamp.read_text())
        if info.get("spec") == spec and info.get("base_python") == exe and \
                _py_version(str(py)) is not None:
            log(f"motulator venv: reusing {venv} (motulator {info['motulator']}, "
                f"Python {info['python']})")
            return info
    if venv.exists():
        shutil.rmtree(venv)
    log(f"motulator venv: creating {venv} with {exe} (Python {ver[0]}.{ver[1]}), "
        f"installing {spec}")
    subprocess.run([exe, "-m", "venv", str(venv)], check=True)
    subprocess.run([str(py), "-m", "pip", "install", "-q", "--disable-pip-version-check",
                    spec], check=True)
    mver = subprocess.run([str(py), str(SIDE), "version"], check=True, capture_output=True,
                          text=True).stdout.strip()
    pver = subprocess.run([str(py), "-c", "import platform; print(platform.python_version())"],
                          check=True, capture_output=True, text=True).stdout.strip()
    info = {"spec": spec, "motulator": mver, "python": pver, "base_python": exe,
            "venv": str(venv)}
    stamp.write_text(json.dumps(info, indent=2))
    if ver < (3, 12):
        log("note: Python 3.11 only: motulator_side.py bridges motulator 0.5's older API to "
            "the same conventions (see benchmarks/README.md); other releases before 0.18 "
            "are not supported")
    return info


def run_side(py: Path, cmd: str, job: dict, tmp: Path, name: str) -> dict:
    jpath = tmp / f"{name}.job.json"
    job = dict(job, output=str(tmp / f"{name}.npz"), output_json=str(tmp / f"{name}.json"))
    jpath.write_text(json.dumps(job))
    subprocess.run([str(py), str(SIDE), cmd, str(jpath)], check=True)
    res = json.loads(Path(job["output_json"]).read_text())
    res["npz"] = job["output"]
    return res


def motor_dict() -> dict:
    m = MOTOR
    return {"R_s": m.R_s, "L_s": m.L_s, "psi_r": m.psi_r, "n_p": m.n_p, "J": m.J, "B": m.B}


# ------------------------------------------------------- 1. agreement -------

def duty_sequence(seconds: float) -> tuple[np.ndarray, np.ndarray, dict]:
    """Open-loop duties (n, 3) and load torque (n,) a period: start from rest,
    a rotating voltage vector whose frequency (0 -> 15 Hz electrical) and
    amplitude ramp up under a 2 N m load, then a load step to 5 N m. The
    vector is u = (R I0 + j w (psi + L I0)) e^{j theta_f} (a forced current
    I0 = 10 A in the forced frame), modulated with min-max zero-sequence
    injection and rounded to motulator's 12-bit carrier counter. 15 Hz: open-
    loop V/f of this machine is undamped above about 20 Hz (no feedback is
    allowed in an open-loop comparison), so the sequence stays below it."""
    m = MOTOR
    n = int(round(seconds / T_SP))
    t = np.arange(n) * T_SP
    D = seconds
    t_ramp0, t_ramp1, t_load, t_step = D / 60, D / 2, D / 12, 0.75 * D
    f1, I0, TL1, TL2 = 15.0, 10.0, 2.0, 5.0
    f = np.clip((t - t_ramp0) / (t_ramp1 - t_ramp0), 0.0, 1.0) * f1
    th = 2 * np.pi * np.cumsum(f) * T_SP
    w = 2 * np.pi * f
    u = (m.R_s * I0 + 1j * w * (m.psi_r + m.L_s * I0)) * np.exp(1j * th)
    a = np.exp(2j * np.pi / 3)
    u_abc = np.stack([np.real(u), np.real(u * a.conjugate()), np.real(u * a)], axis=1)
    u0 = -(u_abc.max(axis=1) + u_abc.min(axis=1)) / 2
    d = np.clip(0.5 + (u_abc + u0[:, None]) / U_DC, 0.0, 1.0)
    d = np.round(d * CARRIER_N) / CARRIER_N
    T_L = np.where(t < t_load, 0.0, np.where(t < t_step, TL1, TL2))
    info = {"f_el_max_Hz": f1, "I0_A": I0, "ramp_s": [t_ramp0, t_ramp1], "load_Nm": TL1,
            "load_on_s": t_load, "load_step_s": t_step, "load_step_Nm": TL2}
    return d, T_L, info


def smodrive_open_loop(pwm: str, d: np.ndarray, T_L: np.ndarray) -> tuple[dict, float]:
    s = y.BASE.replace(inverter=InverterCfg(pwm=pwm, t_dead=0.0), adc=AdcCfg(noise=0.0, bits=0))
    p = Plant(s)
    n = len(d)
    i_s = np.zeros(n, complex)
    w_M = np.zeros(n)
    th = np.zeros(n)
    t0 = time.perf_counter()
    for k in range(n):  # the state at t_k, then the period [t_k, t_k+1) with d_k
        i_s[k] = p.i_s
        w_M[k] = p.w_M
        th[k] = p.theta_r
        p.step(d[k], T_ext=float(T_L[k]))
    wall = time.perf_counter() - t0
    return {"i_alpha": i_s.real, "i_beta": i_s.imag, "w_M": w_M, "theta_r": th}, wall


def compare(a: dict, b: dict) -> dict:
    """Max and RMS of b - a relative to the range of a (angle: the wrapped
    difference relative to 2 pi, the range of a wrapped angle)."""
    out = {}
    for k in ("i_alpha", "i_beta", "w_M", "theta_r"):
        diff = b[k] - a[k]
        if k == "theta_r":
            diff = (diff + np.pi) % (2 * np.pi) - np.pi
            rng = 2 * np.pi
        else:
            rng = float(np.ptp(a[k]))
        out[k] = {"range": rng, "max_abs": float(np.max(np.abs(diff))),
                  "rms_abs": float(np.sqrt(np.mean(diff**2))),
                  "max_pct": 100 * float(np.max(np.abs(diff))) / rng,
                  "rms_pct": 100 * float(np.sqrt(np.mean(diff**2))) / rng}
    return out


def agreement(a, py: Path | None, tmp: Path, out_dir: Path) -> dict:
    d, T_L, info = duty_sequence(a.agree_seconds)
    np.savez(tmp / "duties.npz", d=d, T_L=T_L)
    solver = {"method": "DOP853", "rtol": 1e-9, "atol": 1e-9, "max_step": 0.0}
    res = {"sequence": info, "seconds": a.agree_seconds, "samples": len(d), "solver": solver,
           "modes": {}}
    for pwm in MODES:
        sm, wall_sm = smodrive_open_loop(pwm, d, T_L)
        row = {"smodrive_wall_s": wall_sm}
        if py is not None:
            log(f"agreement, {pwm}: motulator open loop, {a.agree_seconds:g} s ...")
            job = {"motor": motor_dict(), "u_dc": U_DC, "T_s": T_SP, "pwm": pwm,
                   "input": str(tmp / "duties.npz"), "solver": solver}
            r = run_side(py, "agree", job, tmp, f"agree_{pwm}")
            z = np.load(r["npz"])
            mo = {"i_alpha": z["i_s"].real, "i_beta": z["i_s"].imag, "w_M": z["w_M"],
                  "theta_r": z["theta_m"]}
            if r["samples"] != len(d) or np.max(np.abs(z["t"] - np.arange(len(d)) * T_SP)) > 1e-9:
                raise RuntimeError(f"motulator sampled {r['samples']} instants, not {len(d)}")
            row["motulator_wall_s"] = r["wall_s"]
            row["signals"] = compare(sm, mo)
            worst = max(v["rms_pct"] for v in row["signals"].values())
            row["worst_rms_pct"] = worst
            row["target_rms_pct"] = TARGET_RMS[pwm]
            row["met"] = worst <= TARGET_RMS[pwm]
            np.savez_compressed(out_dir / f"agreement_{pwm}.npz", d=d, T_L=T_L,
                                **{f"smodrive_{k}": v for k, v in sm.items()},
                                **{f"motulator_{k}": v for k, v in mo.items()})
        res["modes"][pwm] = row
    return res


# ------------------------------------------------------- 2. speed -----------

def closed_loop_spec(seconds: float) -> dict:
    """The closed-loop work both simulators do: from rest, speed reference
    0 -> 1500 r/min (ramp 0.05 .. 0.35 s), rated load torque from 0.6 of the
    run; ideal sensors, no dead time, constant 540 V."""
    D = seconds
    w_ref = [[0.0, 0.0], [0.05, 0.0], [0.35, 1500 * RPM], [max(D, 0.35), 1500 * RPM]]
    t_l = 0.6 * D
    T_L = [[0.0, 0.0], [t_l, 0.0], [t_l + 1e-9, y.T_N], [D + 1e-9, y.T_N]]
    return {"duration": D, "w_M_ref": w_ref, "T_L": T_L}


def smodrive_scenario(pwm: str, seconds: float):
    sp = closed_loop_spec(seconds)
    prof = lambda pts: Profile(tuple(p[0] for p in pts), tuple(p[1] for p in pts))  # noqa: E731
    return y.BASE.replace(
        name=f"vs_motulator.{pwm}", duration=seconds, w_M0=0.0, w_M_ref=prof(sp["w_M_ref"]),
        inverter=InverterCfg(pwm=pwm, t_dead=0.0), adc=AdcCfg(noise=0.0, bits=0),
        load=LoadCfg(T_ext=prof(sp["T_L"])),
    ).with_controller(mode="sensorless", t_handover=0.25, t_dead_comp=0.0)


def time_smodrive(pwm: str, seconds: float) -> tuple[float, int, float]:
    s = smodrive_scenario(pwm, seconds)
    t0 = time.perf_counter()
    r = simulate(s)
    wall = time.perf_counter() - t0
    return wall, s.n_steps, float(r["w_M"][-1] / RPM)


def _stats(rates: list[float]) -> dict:
    return {"min": min(rates), "median": statistics.median(rates), "max": max(rates),
            "all": rates}


def speed(a, py: Path | None, tmp: Path) -> dict:
    res = {"seconds": a.seconds, "repeat": a.repeat, "modes": {}}
    sm_rates = {m: [] for m in MODES}
    mo_rates = {m: [] for m in MODES}
    final = {m: {} for m in MODES}
    for rep in range(a.repeat):
        for pwm in MODES:  # alternating: smodrive, motulator, smodrive, motulator ...
            wall, n, w_end = time_smodrive(pwm, a.seconds)
            sm_rates[pwm].append(n / wall)
            final[pwm]["smodrive_rpm_end"] = w_end
            msg = f"speed, rep {rep + 1}/{a.repeat}, {pwm}: smodrive {n / wall:,.0f} steps/s"
            if py is not None:
                sp = closed_loop_spec(a.seconds)
                job = {"motor": motor_dict(), "u_dc": U_DC, "T_s": T_SP, "pwm": pwm,
                       "i_s_max": 15.0, "alpha_s": 60.0, **sp}
                r = run_side(py, "closed", job, tmp, f"closed_{pwm}_{rep}")
                mo_rates[pwm].append(r["steps_per_s"])
                z = np.load(r["npz"])
                final[pwm]["motulator_rpm_end"] = float(z["w_M"][-1] / RPM)
                final[pwm]["motulator_steps"] = r["steps"]
                msg += f", motulator {r['steps_per_s']:,.1f} steps/s"
            log(msg)
    for pwm in MODES:
        row = {"smodrive_steps_per_s": _stats(sm_rates[pwm]), **final[pwm],
               "steps": int(round(a.seconds / T_SP))}
        if mo_rates[pwm]:
            row["motulator_steps_per_s"] = _stats(mo_rates[pwm])
            ratios = [s / m for s, m in zip(sm_rates[pwm], mo_rates[pwm])]
            row["ratio"] = _stats(ratios)
            row["ratio_of_medians"] = (statistics.median(sm_rates[pwm])
                                       / statistics.median(mo_rates[pwm]))
            row["target_ratio"] = TARGET_RATIO[pwm]
            row["met"] = row["ratio_of_medians"] >= TARGET_RATIO[pwm]
        res["modes"][pwm] = row
    return res


# ------------------------------------------------------- 3. cost ------------

def instructions(tmp: Path) -> dict:
    """Instructions per smd_drive_step in each mode (callgrind, host -O2,
    float). Cortex-M4F cycles, yao2022's observer parts included:
    benchmarks/bench_m4.py."""
    for tool in ("cc", "valgrind", "callgrind_annotate"):
        if shutil.which(tool) is None:
            return {"error": f"{tool} is not installed"}
    exe = tmp / "drive_cost"
    srcs = sorted(str(p) for p in (ROOT / "core" / "src").glob("*.c"))
    subprocess.run(["cc", "-std=c99", "-O2", "-g", "-I", str(ROOT / "core" / "include"),
                    str(HERE / "cost" / "drive_cost.c"), *srcs, "-lm", "-o", str(exe)],
                   check=True, capture_output=True)
    out = tmp / "callgrind.drive.out"
    subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", str(exe)],
                   check=True, capture_output=True)
    ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", str(out)], check=True,
                         capture_output=True, text=True).stdout
    res: dict = {"unit": "x86-64 instructions per call (host build, -O2, float)"}
    for mode in ("conventional", "robust", "sensorless"):
        m = re.search(r"^\s*([\d,]+)\s+\([^)]*\)\s+\S*:cost_" + mode + r"\b", ann, re.M)
        res[f"drive_{mode}"] = int(m.group(1).replace(",", "")) / 1000 if m else None
    sizes = subprocess.run([str(exe), "sizes"], check=True, capture_output=True,
                           text=True).stdout.split("\n")
    res["host_sizeof"] = {ln.split()[0]: int(ln.split()[1]) for ln in sizes if ln.strip()}
    return res


def m4_sizes(tmp: Path) -> dict:
    """arm-none-eabi-size of each core/src/*.c compiled for a Cortex-M4F, and
    sizeof of the controller structs on that target (array symbols of that
    size, read back with arm-none-eabi-nm)."""
    gcc, size, nm = (shutil.which(t) for t in ("arm-none-eabi-gcc", "arm-none-eabi-size",
                                                "arm-none-eabi-nm"))
    if not (gcc and size and nm):
        return {"error": "arm-none-eabi toolchain not installed (make toolchain)"}
    flags = ["-std=c99", "-mcpu=cortex-m4", "-mthumb", "-mfpu=fpv4-sp-d16",
             "-mfloat-abi=hard", "-O2", "-I", str(ROOT / "core" / "include")]
    objs = []
    odir = tmp / "m4"
    odir.mkdir(exist_ok=True)
    for src in sorted((ROOT / "core" / "src").glob("*.c")):
        obj = odir / (src.stem + ".o")
        subprocess.run([gcc, *flags, "-c", str(src), "-o", str(obj)], check=True,
                       capture_output=True)
        objs.append(obj)
    txt = subprocess.run([size, *map(str, objs)], check=True, capture_output=True,
                         text=True).stdout.splitlines()
    files = {}
    for ln in txt[1:]:
        f = ln.split()
        files[Path(f[5]).stem] = {"text": int(f[0]), "data": int(f[1]), "bss": int(f[2])}
    tot = {k: sum(v[k] for v in files.values()) for k in ("text", "data", "bss")}
    yang = [k for k in files if not re.match(r"smd_(lcl|pll|bandpass)", k)]
    tot_yang = {k: sum(files[f][k] for f in yang) for k in ("text", "data", "bss")}
    # the one drive (every composition), and the LCL observers' parts: the
    # states of the sliding-mode and the linear observer (members of the
    # drive state's position union) and one entry of the sliding-mode
    # observer's model table (the table is the caller's, n entries)
    structs = ["smd_drive_params", "smd_drive_state", "smd_lcl_smo_state",
               "smd_linobs_state", "smd_lcl_model"]
    probe = odir / "sizeof.c"
    probe.write_text('#include "smodrive/smd_drive.h"\n'
                     + "".join(f"char sz_{s}[sizeof({s})];\n" for s in structs))
    subprocess.run([gcc, *flags, "-fno-common", "-c", str(probe), "-o", str(odir / "sz.o")],
                   check=True, capture_output=True)
    syms = subprocess.run([nm, "-S", str(odir / "sz.o")], check=True, capture_output=True,
                          text=True).stdout
    sz = {m.group(2): int(m.group(1), 16)
          for m in re.finditer(r"^\S+\s+([0-9a-f]+)\s+\w\s+sz_(\w+)$", syms, re.M)}
    return {"flags": " ".join(flags[:-2]), "files": files, "total": tot,
            "total_yang2018": tot_yang, "sizeof": sz}


def _sim_wall(args: tuple[str, float]) -> float:
    pwm, seconds = args
    return time_smodrive(pwm, seconds)[0]


def scaling(a) -> dict:
    """Wall time against simulated duration, and a batch over the cores."""
    pts = []
    for D in a.durations:
        walls = [_sim_wall(("carrier", D)) for _ in range(max(1, min(a.repeat, 3)))]
        pts.append({"seconds": D, "wall_s": min(walls)})
        log(f"scaling: {D:g} s simulated in {min(walls) * 1e3:.1f} ms (min of {len(walls)})")
    x = np.array([p["seconds"] for p in pts])
    yv = np.array([p["wall_s"] for p in pts])
    slope, icpt = (np.polyfit(x, yv, 1) if len(x) > 1 else (yv[0] / x[0], 0.0))
    per_s = yv / x
    lin = {"points": pts, "fit_wall_per_sim_s": float(slope), "fit_intercept_s": float(icpt),
           "wall_per_sim_s_spread_pct": float(100 * (per_s.max() - per_s.min()) / np.median(per_s))}
    cores = os.cpu_count() or 1
    n_runs = a.batch or 4 * cores
    jobs = [("carrier", a.batch_seconds)] * n_runs
    t0 = time.perf_counter()
    for j in jobs:
        _sim_wall(j)
    serial = time.perf_counter() - t0
    with mp.get_context("fork").Pool(cores) as pool:
        pool.map(_sim_wall, [("carrier", 0.001)] * cores)  # start the workers first
        t0 = time.perf_counter()
        pool.map(_sim_wall, jobs, chunksize=1)
        par = time.perf_counter() - t0
    batch = {"cores": cores, "runs": n_runs, "seconds_each": a.batch_seconds,
             "serial_wall_s": serial, "parallel_wall_s": par, "speedup": serial / par,
             "efficiency": serial / par / cores,
             "sim_s_per_wall_s_parallel": n_runs * a.batch_seconds / par}
    log(f"batch: {n_runs} runs of {a.batch_seconds:g} s on {cores} cores: serial "
        f"{serial:.2f} s, pool {par:.2f} s, speed-up {serial / par:.2f}")
    return {"linearity": lin, "batch": batch}


# ------------------------------------------------------- output -------------

def _k(x: float) -> str:
    if x >= 1e6:
        return f"{x / 1e6:.2f} M"
    if x >= 1e3:
        return f"{x / 1e3:.1f} k"
    return f"{x:.0f}"


def _motulator_controller(version: str | None) -> str:
    """The class motulator_side.py runs for the closed loop of this release."""
    if version and version.startswith("0.5."):
        return "CurrentVectorControl with a SpeedController at 60 rad/s"
    return "VectorControlSystem"


def markdown(R: dict) -> str:
    mpy = R["meta"].get("motulator_python")
    L = [f"# smodrive vs motulator ({R['meta']['date']})", "",
         f"Machine: {R['meta']['machine']}; smodrive Python {R['meta']['python']}; "
         f"motulator {R['meta'].get('motulator', 'not run')}"
         f"{f' (Python {mpy})' if mpy else ''}.",
         f"Command: `{R['meta']['command']}`", ""]
    ag = R.get("agreement")
    if ag:
        L += ["## 1. Plant agreement (open loop, same duties)", "",
              f"{ag['samples']} samples of {T_SP * 1e6:.0f} us ({ag['seconds']:g} s); motulator "
              f"solver {ag['solver']['method']} rtol {ag['solver']['rtol']:g} atol "
              f"{ag['solver']['atol']:g}. Differences relative to the signal's range "
              "(angle: wrapped, relative to 2 pi).", "",
              "| PWM | signal | range | max diff | RMS diff | max % | RMS % |",
              "|---|---|---|---|---|---|---|"]
        for pwm, row in ag["modes"].items():
            for sig, v in row.get("signals", {}).items():
                unit = {"w_M": "rad/s", "theta_r": "rad"}.get(sig, "A")
                L.append(f"| {pwm} | {sig} | {v['range']:.3g} {unit} | {v['max_abs']:.3g} | "
                         f"{v['rms_abs']:.3g} | {v['max_pct']:.2e} | {v['rms_pct']:.2e} |")
        if not any("signals" in r for r in ag["modes"].values()):
            L.append("| - | motulator not run | | | | | |")
        for pwm, row in ag["modes"].items():
            if "met" in row:
                L.append(f"\n{pwm}: worst RMS {row['worst_rms_pct']:.2e} % (target <= "
                         f"{row['target_rms_pct']} %): {'met' if row['met'] else 'NOT met'}; "
                         f"wall time of the open-loop run: motulator {row['motulator_wall_s']:.1f}"
                         f" s, smodrive (a Python loop of Plant.step) "
                         f"{row['smodrive_wall_s']:.3f} s.")
        L.append("")
    sp = R.get("speed")
    if sp:
        L += ["## 2. Speed, same closed-loop work", "",
              f"{sp['seconds']:g} s simulated ({int(round(sp['seconds'] / T_SP)):,} control "
              f"steps), {sp['repeat']} repetitions, alternating. smodrive: sensorless robust "
              "DBPC + SMDO (simulate()); motulator: sensorless current-vector control "
              f"({_motulator_controller(R['meta'].get('motulator'))}), default solver.", "",
              "| PWM | smodrive steps/s min / median / max | motulator steps/s min / median / "
              "max | ratio (medians) | target | | end speed r/min (smodrive / motulator) |",
              "|---|---|---|---|---|---|---|"]
        for pwm, row in sp["modes"].items():
            s = row["smodrive_steps_per_s"]
            m = row.get("motulator_steps_per_s")
            mtxt = (f"{m['min']:,.0f} / {m['median']:,.0f} / {m['max']:,.0f}" if m else "not run")
            rtxt = f"{row['ratio_of_medians']:,.0f} x" if m else "-"
            met = ("met" if row.get("met") else "NOT met") if m else "-"
            end = f"{row['smodrive_rpm_end']:.1f} / " + (
                f"{row['motulator_rpm_end']:.1f}" if m else "-")
            L.append(f"| {pwm} | {_k(s['min'])} / {_k(s['median'])} / {_k(s['max'])} | {mtxt} | "
                     f"{rtxt} | >= {TARGET_RATIO[pwm]:,.0f} x | {met} | {end} |")
        L.append("")
    c = R.get("cost")
    if c:
        L += ["## 3. What the cost is made of", ""]
        ins = c.get("instructions", {})
        if "error" in ins:
            L.append(f"Instruction counts: not measured ({ins['error']}).")
        else:
            L += ["Instructions per control step (valgrind callgrind, x86-64 host build, -O2, "
                  "float; benchmarks/cost/drive_cost.c):", "",
                  "| controller | instructions/step |", "|---|---|"]
            for mode in ("conventional", "robust", "sensorless"):
                v = ins.get(f"drive_{mode}")
                L.append(f"| yang2018 {mode} DBPC (smd_drive_step) | "
                         f"{'-' if v is None else f'{v:,.0f}'} |")
            L.append("\nCortex-M4F cycles of every block and composition, yao2022 Table VI's "
                     "parts included: `benchmarks/bench_m4.py`.")
        m4 = c.get("m4", {})
        if "error" in m4:
            L.append(f"\nCortex-M4F sizes: not measured ({m4['error']}).")
        else:
            t, ty = m4["total"], m4["total_yang2018"]
            L += ["", f"Cortex-M4F (`arm-none-eabi-gcc {m4['flags']}`, arm-none-eabi-size): "
                  f"whole core text {t['text']:,} B, data {t['data']} B, bss {t['bss']} B; "
                  f"of it, the files other than smd_lcl_*, smd_pll, smd_bandpass (the blocks "
                  f"yang2018's compositions run) text {ty['text']:,} B; smd_drive.c calls the "
                  "LCL observers, so an image of the one drive links the whole core. "
                  "State and parameters (sizeof on the target): "
                  + ", ".join(f"{k} {v} B" for k, v in m4["sizeof"].items()) + ".", ""]
            L += ["| file | text | data | bss |", "|---|---|---|---|"]
            for f, v in m4["files"].items():
                L.append(f"| {f}.c | {v['text']} | {v['data']} | {v['bss']} |")
        L.append("")
    sc = R.get("scaling")
    if sc:
        lin, b = sc["linearity"], sc["batch"]
        L += ["Wall time against simulated duration (carrier PWM, logging every sample):", "",
              "| simulated s | wall ms | wall ms per simulated s |", "|---|---|---|"]
        for p in lin["points"]:
            L.append(f"| {p['seconds']:g} | {p['wall_s'] * 1e3:.1f} | "
                     f"{p['wall_s'] / p['seconds'] * 1e3:.2f} |")
        L += ["", f"Fit: {lin['fit_wall_per_sim_s'] * 1e3:.2f} ms per simulated second "
              f"{lin['fit_intercept_s'] * 1e3:+.2f} ms; spread of ms/s "
              f"{lin['wall_per_sim_s_spread_pct']:.1f} %.",
              f"Batch: {b['runs']} independent runs of {b['seconds_each']:g} s on {b['cores']} "
              f"cores (multiprocessing): serial {b['serial_wall_s']:.2f} s, pool "
              f"{b['parallel_wall_s']:.2f} s, speed-up {b['speedup']:.2f} (efficiency "
              f"{b['efficiency'] * 100:.0f} %), {b['sim_s_per_wall_s_parallel']:.0f} simulated "
              "s per wall s.", ""]
    return "\n".join(L)


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        for ln in Path("/proc/cpuinfo").read_text().splitlines():
            if ln.startswith("model name"):
                cpu = ln.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{platform.machine()}, {cpu}, {os.cpu_count()} cores, {platform.system()}"


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(HERE / "results"), help="directory for results.*")
    ap.add_argument("--seconds", type=float, default=1.0, help="closed-loop simulated s")
    ap.add_argument("--agree-seconds", type=float, default=1.2, help="open-loop simulated s")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--durations", default="1,2,4,8", help="scaling: simulated seconds")
    ap.add_argument("--batch", type=int, default=0, help="runs in the batch (0: 4 x cores)")
    ap.add_argument("--batch-seconds", type=float, default=20.0)
    ap.add_argument("--no-motulator", action="store_true", help="smodrive side only")
    ap.add_argument("--smoke", action="store_true",
                    help="tiny case: 0.02 s runs, one repetition (implies nothing on timing)")
    ap.add_argument("--skip-cost", action="store_true", help="no callgrind / cross build")
    ap.add_argument("--venv", default=str(VENV))
    ap.add_argument("--python", default=None, help="interpreter for the motulator venv")
    ap.add_argument("--motulator-spec", default=None,
                    help=f"pip requirement (default {MOTULATOR_SPEC}; on Python 3.11 "
                    f"{MOTULATOR_SPEC_311})")
    a = ap.parse_args(argv)
    if a.smoke:
        a.seconds, a.agree_seconds, a.repeat = 0.02, 0.02, 1
        a.durations, a.batch, a.batch_seconds = "0.01,0.02", 2, 0.01
    a.durations = [float(x) for x in a.durations.split(",") if x.strip()]
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    R: dict = {"meta": {
        "date": _dt.date.today().isoformat(), "machine": machine(),
        "python": platform.python_version(),
        "command": " ".join(["python benchmarks/vs_motulator.py",
                             *(argv if argv is not None else sys.argv[1:])])}}
    py = None
    if not a.no_motulator:
        info = setup_motulator(Path(a.venv), a.python, a.motulator_spec)
        R["meta"].update(motulator=info["motulator"], motulator_python=info["python"],
                         motulator_spec=info["spec"])
        py = Path(a.venv) / "bin" / "python"
    with tempfile.TemporaryDirectory(prefix="vs_motulator_") as tmpd:
        tmp = Path(tmpd)
        R["agreement"] = agreement(a, py, tmp, out)
        R["speed"] = speed(a, py, tmp)
        if not a.skip_cost:
            R["cost"] = {"instructions": instructions(tmp), "m4": m4_sizes(tmp)}
        R["scaling"] = scaling(a)
    (out / "results.json").write_text(json.dumps(R, indent=2, default=float))
    md = markdown(R)
    (out / "results.md").write_text(md + "\n")
    print()
    print(md)
    print(f"\nwritten: {out / 'results.json'}, {out / 'results.md'}")
    return R


if __name__ == "__main__":
    main()
