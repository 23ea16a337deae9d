"""motulator's side of benchmarks/vs_motulator.py (run by the python of the
benchmark's own venv, benchmarks/.motulator-venv; never imported by smodrive).

    python motulator_side.py version
    python motulator_side.py agree  JOB.json   # open loop, duties from JOB's npz
    python motulator_side.py closed JOB.json   # closed loop, timed

Every job writes its signals as .npz and its figures as JSON to the paths the
job names; stdout carries nothing the caller parses except `version`.

Conventions (see benchmarks/README.md):
* one carrier period = one sampling period: Drive(..., single_update=True);
* open loop: delay=0, so the duties returned at t_k act during [t_k, t_k+1),
  as smodrive's Plant.step(d) does; closed loop: delay=2 (one sampling period,
  the delay motulator's controllers compensate, and smodrive's convention);
* the state is read at t_k, before the duties of period k are returned: the
  same instant at which smodrive's plant is read before its step k;
* dead time 0, no threshold voltage, ideal sensors, constant u_dc.
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np


def _version() -> str:
    from importlib.metadata import version

    return version("motulator")


def _parts(job: dict):
    """Machine, mechanics, converter of the job's motor (SI, peak-valued vectors)."""
    from motulator.drive import model

    m = job["motor"]
    par = model.SynchronousMachinePars(n_p=int(m["n_p"]), R_s=m["R_s"], L_d=m["L_s"],
                                       L_q=m["L_s"], psi_f=m["psi_r"])
    machine = model.SynchronousMachine(par)
    mechanics = model.MechanicalSystem(J=m["J"], B_L=m["B"])
    converter = model.VoltageSourceConverter(u_dc=job["u_dc"], t_d=0.0)
    return model, par, machine, mechanics, converter


class OpenLoop:
    """A control system that records the plant at t_k and returns the k-th
    duty ratios of a given sequence (and sets the k-th load torque)."""

    def __init__(self, T_s: float, d: np.ndarray, T_L: np.ndarray):
        self.T_s, self.d, self.T_L = T_s, d, T_L
        n = len(d)
        self.k = 0
        self.i_s = np.zeros(n, complex)
        self.w_M = np.zeros(n)
        self.theta_m = np.zeros(n)
        self.theta_M = np.zeros(n)
        self.t = np.zeros(n)
        self.t_ctrl = 0.0

    def get_enable(self) -> bool:
        return True

    def __call__(self, mdl):
        k = min(self.k, len(self.d) - 1)
        if self.k < len(self.d):
            self.t[k] = mdl.t0
            self.i_s[k] = complex(mdl.machine.out.i_s_ab)
            self.w_M[k] = float(np.real(mdl.mechanics.state.w_M))
            self.theta_m[k] = float(np.real(mdl.machine.state.theta_m))
            self.theta_M[k] = float(np.real(mdl.mechanics.state.theta_M))
        # load torque of period k, constant over the period (as smodrive's T_ext)
        mdl.mechanics.set_external_load_torque(float(self.T_L[k]))
        self.k += 1
        return self.T_s, list(self.d[k])

    def post_process(self):
        return None


def agree(job: dict) -> None:
    from motulator.common.model._simulation import SolverCfg

    model, par, machine, mechanics, converter = _parts(job)
    data = np.load(job["input"])
    d, T_L, T = data["d"], data["T_L"], float(job["T_s"])
    n = len(d)
    mdl = model.Drive(machine, mechanics, converter, pwm=job["pwm"] == "carrier", delay=0,
                      single_update=True)
    ctrl = OpenLoop(T, d, T_L)
    s = job["solver"]
    cfg = SolverCfg(method=s["method"], rtol=s["rtol"], atol=s["atol"],
                    max_step=s["max_step"] if s["max_step"] > 0 else np.inf)
    sim = model.Simulation(mdl, ctrl, show_progress=False, cfg=cfg)
    t0 = time.perf_counter()
    # the run stops at the first sampling instant after t_stop: the n samples
    # t_0 .. t_{n-1} are recorded (and period n-1 integrated) for t_stop = (n - 0.5) T
    sim.simulate(t_stop=(n - 0.5) * T)
    wall = time.perf_counter() - t0
    np.savez(job["output"], t=ctrl.t, i_s=ctrl.i_s, w_M=ctrl.w_M, theta_m=ctrl.theta_m,
             theta_M=ctrl.theta_M, n=min(ctrl.k, n))
    with open(job["output_json"], "w") as f:
        json.dump({"wall_s": wall, "samples": int(min(ctrl.k, n)), "motulator": _version()}, f)


def _pwl(points: list[list[float]]):
    tt = [p[0] for p in points]
    yy = [p[1] for p in points]
    return lambda t: float(np.interp(t, tt, yy))


def closed(job: dict) -> None:
    """The closed-loop scenario with motulator's own sensorless current-vector
    control; times sim.simulate() (the integration, the controller and the
    post-processing of the results), not the imports or the set-up."""
    from motulator.drive.control import sm as control

    model, par, machine, mechanics, converter = _parts(job)
    T = float(job["T_s"])
    m = job["motor"]
    mdl = model.Drive(machine, mechanics, converter, pwm=job["pwm"] == "carrier", delay=2,
                      single_update=True)
    cfg = control.CurrentVectorControllerCfg(i_s_max=job["i_s_max"], sensorless=True, T_s=T,
                                             J=m["J"])
    vector_ctrl = control.CurrentVectorController(par, cfg)
    tau_max = 1.5 * m["n_p"] * m["psi_r"] * job["i_s_max"]
    speed_ctrl = control.SpeedController(J=m["J"], alpha_s=job["alpha_s"], tau_M_max=tau_max)
    ctrl = control.VectorControlSystem(vector_ctrl, speed_ctrl,
                                       pwm=control.PWM(single_update=True))
    ctrl.set_speed_ref(_pwl(job["w_M_ref"]))
    mdl.mechanics.set_external_load_torque(_pwl(job["T_L"]))
    sim = model.Simulation(mdl, ctrl, show_progress=False)  # default solver settings
    t0 = time.perf_counter()
    res = sim.simulate(t_stop=job["duration"] - 0.5 * T)
    wall = time.perf_counter() - t0
    steps = int(len(res.ctrl.t))
    w_M = np.real(res.ctrl.fbk.w_M) if hasattr(res.ctrl.fbk, "w_M") else np.zeros(steps)
    np.savez(job["output"], t=res.ctrl.t, w_M_est=w_M, t_mdl=res.mdl.t[::50],
             w_M=res.mdl.mechanics.w_M[::50])
    with open(job["output_json"], "w") as f:
        json.dump({"wall_s": wall, "steps": steps, "steps_per_s": steps / wall,
                   "success": bool(res.success), "motulator": _version(),
                   "python": sys.version.split()[0]}, f)


def main() -> None:
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    cmd = sys.argv[1]
    if cmd == "version":
        print(_version())
        return
    with open(sys.argv[2]) as f:
        job = json.load(f)
    {"agree": agree, "closed": closed}[cmd](job)


if __name__ == "__main__":
    main()
