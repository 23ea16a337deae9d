"""The supervision spread over samples (issue 22, `controller.supervise_every`):
its three pieces (loss of lock, the start-up and speed criteria, the state's
finiteness) run one a sample, each every N samples, their counts kept in
samples (smd_drive.h). Nothing of the control law reads the supervision, so
a healthy run is the same run bit for bit; a fault is the same fault, up to
N samples either side of its sample (a count goes up N at a time, once every
N samples). The criteria sample by sample: core/test/test_supervision.c,
which runs each with supervise_every = 1 and 4."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from smodrive import RPM, Profile
from smodrive.engine import FAULT_BITS, fault_names, simulate
from smodrive.model import ControllerCfg, LoadCfg, MotorPars, ParameterError, Scenario
from smodrive.scenario_io import load_scenario
from smodrive.scenarios import yao2022 as y

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "scenarios" / "sensorless_load_step.toml"
N = 4


def _first(r, name: str) -> float:
    hit = np.flatnonzero(r["fault"].astype(np.int64) & FAULT_BITS[name])
    return float(r.t[hit[0]]) if hit.size else float("inf")


@pytest.mark.parametrize("every", [2, N, 64])
def test_a_healthy_run_is_the_same_run(every):
    """The README's sensorless example (start on I/f, steps, load, reversal
    through zero on I/f) with the pieces spread: every logged channel equal
    to the every-sample run's, and no fault or warning in either. A piece
    that changed a state the control law reads (the ripple's last current,
    the piece counter in the wrong struct) would move the currents."""
    s = load_scenario(EXAMPLE)
    a = simulate(s)
    b = simulate(s.with_controller(supervise_every=every))
    assert a.faults.first == 0 and b.faults.first == 0
    for ch in ("i_d", "i_q", "w_M", "theta_hat", "d_a", "d_b", "d_c", "phase"):
        assert np.array_equal(a[ch], b[ch]), ch


def test_the_loss_of_lock_is_the_same_fault():
    """The example without the return to I/f loses the angle at the reversal:
    the sample of the SMDO's angle jump latches lost_lock (test_faults.py).
    A jump is checked every sample, spread or not: the same sample, the same
    words."""
    s = load_scenario(EXAMPLE).with_controller(w_M_if_enter=0.0)
    a = simulate(s)
    b = simulate(s.with_controller(supervise_every=N))
    assert fault_names(b.faults.first) == fault_names(a.faults.first) == ["lost_lock",
                                                                          "angle_jump"]
    assert b.faults.t_first == a.faults.t_first
    assert fault_names(b.faults.final) == ["lost_lock"]


def test_a_slipping_lcl_observer_is_still_flagged_early():
    """yao2022's drive with the observer's C_1 at half the filter's (the
    observer sweep's silent slip, test_lcl_lock.py): the leaky count trips
    lost_lock within 0.15 s, after the angle passed 90 deg. Spread over 4
    samples (200 us at 20 kHz) the count reads a quarter of the samples of
    an estimate plausible only part of the time, so its trip moves by more
    than 4 samples (measured: 23, of 610): the bound it is held to is the
    one the every-sample count is held to."""
    s = dataclasses.replace(y.BASE, duration=0.3, w_M0=20e3 * RPM,
                            w_M_ref=Profile.const(20e3 * RPM))
    s = s.with_controller(C1_hat_ratio=0.5, position="lcl_smo_pll", supervise_every=N)
    r = simulate(s)
    t = _first(r, "lost_lock")
    assert "lost_lock" in fault_names(r.faults.final) and t < 0.15
    assert np.max(np.abs(np.degrees(r.theta_error[r.window(0.0, t)]))) > 90.0


def test_a_hunting_lcl_observer_trips_within_n_samples():
    """The wobbling observer of test_lcl_lock.py (C_1 / sqrt 2, L_s 2 x at
    20 kr/min) ends in `hunting`: the swings of the speed PI between its
    limits last many samples each, so the spread count sees each swing, and
    trips within N samples of the every-sample count."""
    s = dataclasses.replace(y.BASE, duration=0.3, w_M0=20e3 * RPM,
                            w_M_ref=Profile.const(20e3 * RPM))
    s = s.with_controller(C1_hat_ratio=0.5 ** 0.5, L_s_hat=2.0 * y.MOTOR.L_s,
                          position="lcl_smo_pll")
    a = simulate(s)
    b = simulate(s.with_controller(supervise_every=N))
    assert fault_names(a.faults.first) == fault_names(b.faults.first) == ["hunting"]
    assert abs(_first(b, "hunting") - _first(a, "hunting")) <= N * s.T_sp * (1 + 1e-9)


def test_a_locked_rotor_restarts_and_latches_the_same():
    """A rotor held by a brake under an I/f start (test_own_motor.py): two
    restarts, each reported once (the restart's sample), then start_failed
    latched; spread, the same events within N samples each."""
    s = Scenario(duration=0.4, warm_start=False, w_M_ref=Profile.const(1500 * RPM),
                 load=LoadCfg(T_brake=Profile.const(1000.0)),
                 controller=ControllerCfg(current="robust_dbpc", position="smdo_emf",
                                          start="if"))
    runs = [simulate(s), simulate(s.with_controller(supervise_every=N))]
    events = [np.flatnonzero(r["fault"].astype(np.int64) & FAULT_BITS["restart"]) for r in runs]
    assert len(events[0]) == len(events[1]) == 2
    assert np.all(np.abs(events[1] - events[0]) <= N)
    for r in runs:
        assert fault_names(r.faults.final) == ["start_failed"]
    assert abs(_first(runs[1], "start_failed") - _first(runs[0], "start_failed")) <= \
        N * s.T_sp * (1 + 1e-9)


def test_an_oscillation_is_warned_while_it_lasts():
    """Robust DBPC with L_hat = 2 L: a limit cycle that never decays
    (test_own_motor.py, row 6). The ripple's filter takes N samples' step
    (1 - (1 - 1/n)^N) on N samples' difference: the warning is on over the
    last 0.2 s in both, and off with L_hat = L."""
    base = Scenario(duration=0.5, w_M0=1000 * RPM,
                    i_q_ref=Profile((0.0, 0.1, 0.1), (0.0, 0.0, 1.0)),
                    motor=dataclasses.replace(MotorPars(), J=1e4),
                    controller=ControllerCfg(current="robust_dbpc", position="encoder",
                                             speed_loop=False, supervise_every=N))
    bad = simulate(base.with_controller(L_s_hat=2 * 23.45e-3))
    m = bad.window(0.3, 0.5)
    osc = bad["fault"].astype(np.int64)[m] & FAULT_BITS["oscillation"]
    assert np.all(osc != 0)
    assert simulate(base).faults.first == 0


@pytest.mark.parametrize("every", [0, 65, 2.5])
def test_out_of_range_is_named(every):
    with pytest.raises(ParameterError, match="supervise_every"):
        ControllerCfg(supervise_every=every)
