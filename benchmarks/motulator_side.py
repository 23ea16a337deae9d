"""motulator's side of benchmarks/vs_motulator.py (run by the python of the
benchmark's own venv, benchmarks/.motulator-venv; never imported by smodrive).

    python motulator_side.py version
    python motulator_side.py agree  JOB.json   # open loop, duties from JOB's npz
    python motulator_side.py closed JOB.json   # closed loop, timed

Every job writes its signals as .npz and its figures as JSON to the paths the
job names; stdout carries nothing the caller parses except `version`.

Written for motulator 0.18 (the functions `agree` and `closed`); motulator
0.5.x, the last release for Python 3.11, has an older API, bridged to the same
conventions by `agree_05` and `closed_05` (section "motulator 0.5" below). The
release installed picks the implementation.

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

import contextlib
import functools
import json
import sys
import time

import numpy as np


def _version() -> str:
    from importlib.metadata import version

    return version("motulator")


def _release() -> tuple[int, int]:
    """(major, minor) of the installed motulator."""
    major, minor = _version().split(".")[:2]
    return int(major), int(minor)


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


def _write_open_loop(job: dict, ctrl: OpenLoop, n: int, wall: float) -> None:
    """The signals recorded at t_0 .. t_{n-1} (.npz) and the timing (JSON)."""
    np.savez(job["output"], t=ctrl.t, i_s=ctrl.i_s, w_M=ctrl.w_M, theta_m=ctrl.theta_m,
             theta_M=ctrl.theta_M, n=min(ctrl.k, n))
    with open(job["output_json"], "w") as f:
        json.dump({"wall_s": wall, "samples": int(min(ctrl.k, n)), "motulator": _version()}, f)


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
    _write_open_loop(job, ctrl, n, wall)


def _pwl(points: list[list[float]]):
    f = _pwl_array(points)
    return lambda t: float(f(t))


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


# ------------------------------------------------------- motulator 0.5 ------
#
# What differs in 0.5.x from 0.18, and how each is bridged to the conventions
# above (the jobs, outputs and keys are the same):
#
# * No single update. Simulation calls the control system once per half carrier
#   period: ctrl(mdl) returns (T, d), T is passed on as the *half* carrier period
#   to CarrierComparison (which alternates its rising and falling halves call by
#   call) or to zoh. `_SingleUpdate` makes one carrier period = one sampling
#   period: it runs the wrapped control system every second call, with the
#   sampling period T, and returns (T/2, d) for both halves of the period. This
#   is what 0.18's Drive(single_update=True) does (two half-period PWM calls per
#   sample, the delay advanced on each), also in the averaged mode (zoh over the
#   two halves).
# * Drive(converter, machine, mechanics) takes no pwm/delay arguments: the model
#   has the attributes `pwm` (zoh by default) and `delay` (Delay(1)), set here
#   after construction. Delay's length counts calls of the control system, i.e.
#   half carrier periods with `_SingleUpdate`, as 0.18's `delay` does: Delay(0)
#   open loop, Delay(2) (one sampling period) closed loop.
# * The solver is not configurable: Simulation.simulate(t_stop, max_step) calls
#   scipy's solve_ivp with its defaults (RK45, rtol 1e-3, atol 1e-6, as 0.18's
#   defaults). `_solver_05` passes the job's method and tolerances to that call
#   for the agreement run, by wrapping the module's reference to solve_ivp for
#   the duration of the run (motulator's code itself is unchanged).
# * Load torque: StiffMechanicalSystem(J, B_L, tau_L) takes tau_L as a function
#   of time, there is no set_external_load_torque; the open loop gives a
#   function that returns the value set at the last sampling instant (constant
#   over the period). Post-processing calls tau_L with the array of time
#   instants, so the closed loop's piecewise-linear profile is vectorised.
# * State: SynchronousMachine.state.psi_s is in rotor coordinates and the angle
#   is kept as exp_j_theta_m (electrical), the mechanics' as exp_j_theta_M;
#   the stator current in stationary coordinates is machine.i_s * exp_j_theta_m
#   (the same vector motulator feeds its converter and its current
#   measurement). The states read at t_k are those motulator starts the next
#   integration from (Model.get_initial_values()).
# * Simulation.simulate returns nothing: the results are in mdl.<part>.data and
#   ctrl.data after post-processing; a FloatingPointError is printed, not
#   raised, so the run succeeded if it reached t_stop. The loop runs while
#   mdl.t0 <= t_stop, one call per half period: for the samples t_0 .. t_{n-1}
#   with period n-1 integrated, t_stop lies in [(n - 1/2) T, n T).
# * Controller: CurrentVectorControl(par, CurrentReferenceCfg, T_s, J,
#   sensorless) with its own observer and current-controller defaults; its
#   speed controller (fixed at 2 pi 4 rad/s) is replaced by one with the job's
#   bandwidth and torque limit; its PWM advances the voltage angle by 1.5 T w,
#   the one-sample computational delay plus half a sample of PWM, which is the
#   single-update timing set up here.


class _SingleUpdate:
    """One carrier period per sampling period for a 0.5 control system: the
    wrapped system runs at t_k (every second call) with the sampling period
    T and its duties are returned for both half carrier periods of [t_k,
    t_k+1)."""

    def __init__(self, ctrl):
        self.ctrl = ctrl
        self._half = 0
        self._out: tuple[float, list] | None = None

    def __call__(self, mdl):
        if self._half == 0:
            T_s, d = self.ctrl(mdl)
            self._out = (T_s / 2, list(d))
        self._half ^= 1
        return self._out

    def post_process(self):
        self.ctrl.post_process()


@contextlib.contextmanager
def _solver_05(s: dict):
    """solve_ivp of motulator 0.5's simulation loop with the job's method and
    tolerances (0.5 lets only max_step be chosen, in simulate())."""
    from motulator.common.model import _simulation as sim_module

    orig = sim_module.solve_ivp
    sim_module.solve_ivp = functools.partial(orig, method=s["method"], rtol=s["rtol"],
                                             atol=s["atol"])
    try:
        yield
    finally:
        sim_module.solve_ivp = orig


def _parts_05(job: dict, tau_L):
    """Drive model of the job's motor (SI, peak-valued vectors) in 0.5's API."""
    from motulator.common.model import CarrierComparison, zoh
    from motulator.drive import model
    from motulator.drive.utils import SynchronousMachinePars

    m = job["motor"]
    par = SynchronousMachinePars(n_p=int(m["n_p"]), R_s=m["R_s"], L_d=m["L_s"],
                                 L_q=m["L_s"], psi_f=m["psi_r"])
    mdl = model.Drive(model.VoltageSourceConverter(u_dc=job["u_dc"]),
                      model.SynchronousMachine(par),
                      model.StiffMechanicalSystem(J=m["J"], B_L=m["B"], tau_L=tau_L))
    mdl.pwm = CarrierComparison() if job["pwm"] == "carrier" else zoh
    return model, par, mdl


class OpenLoop05(OpenLoop):
    """OpenLoop for 0.5 (called once per sampling period through
    `_SingleUpdate`): records the plant at t_k, holds the k-th load torque for
    the mechanics' tau_L(t) and returns the k-th duties."""

    def __init__(self, T_s: float, d: np.ndarray, T_L: np.ndarray):
        super().__init__(T_s, d, T_L)
        self._tau_L = 0.0

    def tau_L(self, t):
        """Load torque of the ongoing period, whatever t (also an array)."""
        return self._tau_L

    def __call__(self, mdl):
        k = min(self.k, len(self.d) - 1)
        if self.k < len(self.d):
            mach, mech = mdl.machine, mdl.mechanics
            self.t[k] = mdl.t0
            self.i_s[k] = complex(mach.i_s * mach.state.exp_j_theta_m)
            self.w_M[k] = float(np.real(mech.state.w_M))
            self.theta_m[k] = float(np.angle(mach.state.exp_j_theta_m))
            self.theta_M[k] = float(np.angle(mech.state.exp_j_theta_M))
        self._tau_L = float(self.T_L[k])
        self.k += 1
        return self.T_s, list(self.d[k])


def agree_05(job: dict) -> None:
    from motulator.common.model import Delay

    data = np.load(job["input"])
    d, T_L, T = data["d"], data["T_L"], float(job["T_s"])
    n = len(d)
    ctrl = OpenLoop05(T, d, T_L)
    model, par, mdl = _parts_05(job, ctrl.tau_L)
    mdl.delay = Delay(0)  # the duties returned at t_k act on [t_k, t_k+1)
    sim = model.Simulation(mdl, _SingleUpdate(ctrl))
    s = job["solver"]
    t0 = time.perf_counter()
    with _solver_05(s):
        # calls at t_0, t_0 + T/2, ..., t_{n-1} + T/2; none at t_n
        sim.simulate(t_stop=(n - 0.25) * T,
                     max_step=s["max_step"] if s["max_step"] > 0 else np.inf)
    wall = time.perf_counter() - t0
    _write_open_loop(job, ctrl, n, wall)


def _pwl_array(points: list[list[float]]):
    tt = [p[0] for p in points]
    yy = [p[1] for p in points]
    return lambda t: np.interp(t, tt, yy)


def closed_05(job: dict) -> None:
    """`closed` with 0.5's CurrentVectorControl (sensorless); times
    sim.simulate() (integration, controller, post-processing)."""
    from motulator.common.model import Delay
    from motulator.drive.control import sm as control

    T = float(job["T_s"])
    m = job["motor"]
    model, par, mdl = _parts_05(job, _pwl_array(job["T_L"]))
    mdl.delay = Delay(2)  # two half carrier periods = one sampling period
    w_M_ref = _pwl_array(job["w_M_ref"])
    # the field-weakening gain needs a nominal speed: the top of the speed
    # reference (the machine's rated speed in this scenario)
    w_m_nom = par.n_p * max(abs(p[1]) for p in job["w_M_ref"])
    cfg = control.CurrentReferenceCfg(par, max_i_s=job["i_s_max"], nom_w_m=w_m_nom)
    vector_ctrl = control.CurrentVectorControl(par, cfg, T_s=T, J=m["J"], sensorless=True)
    tau_max = 1.5 * m["n_p"] * m["psi_r"] * job["i_s_max"]
    vector_ctrl.speed_ctrl = control.SpeedController(J=m["J"], alpha_s=job["alpha_s"],
                                                     max_tau_M=tau_max)
    vector_ctrl.ref.w_m = lambda t: par.n_p * float(w_M_ref(t))  # electrical rad/s
    sim = model.Simulation(mdl, _SingleUpdate(vector_ctrl))  # default solver settings
    t_stop = job["duration"] - 0.25 * T  # last call at duration - T/2
    t0 = time.perf_counter()
    sim.simulate(t_stop=t_stop)
    wall = time.perf_counter() - t0
    data = vector_ctrl.data
    steps = int(len(data.ref.t))
    w_M = np.real(data.fbk.w_m) / par.n_p
    np.savez(job["output"], t=data.ref.t, w_M_est=w_M, t_mdl=mdl.mechanics.data.t[::50],
             w_M=mdl.mechanics.data.w_M[::50])
    with open(job["output_json"], "w") as f:
        json.dump({"wall_s": wall, "steps": steps, "steps_per_s": steps / wall,
                   "success": bool(mdl.t0 > t_stop), "motulator": _version(),
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
    if _release() < (0, 6):  # 0.5.x: the older API (checked with 0.5.0)
        {"agree": agree_05, "closed": closed_05}[cmd](job)
    else:
        {"agree": agree, "closed": closed}[cmd](job)


if __name__ == "__main__":
    main()
