"""Physics tests of the LCL-filtered SPMSM plant (sim/src/smd_lcl.c with the
mechanics of sim/src/smd_mech.c, ADC of smd_adc.c and PWM of smd_pwm.c shared with
the filterless plant)
through smodrive.engine.plant.Plant: a Scenario with its `lcl` section.

The plant diagonalises the filter matrix and solves each mode in closed form.
The references below do not: they use scipy's matrix exponential of the real
8x8 augmented system of yao2022 eq. (1)-(3) (with the circuit's signs), a
rotor-frame complex matrix exponential for the torque integral, numpy's
eigenvalue solver, the circuit's energy balance, and the algebra of a
per-phase ADC gain. Tolerances are argued in comments.

Conventions (amplitude-invariant Clarke, x = alpha + j beta):
  C1 du_c/dt = i_1 - i_2,  L1 di_1/dt = u - u_c,  L2 di_2/dt = u_c - R i_2 - e,
  e = j w psi_r e^{j theta},  L2 = L2o + L_s,  T_e = 1.5 n_p psi_r Im(i_2 e^{-j theta}),
  leg x contributes (2/3) u_dc a^x while high, a = e^{j 2 pi / 3}.
The plant's motor current i_s is i_2 (Plant.i_s); Plant.i_1 is i_1.
"""

from __future__ import annotations

import cmath
import ctypes as ct
import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.stats import chi2

from plant_helpers import (
    EPS,
    SPMSM,
    TABLE2,
    A,
    clarke,
    duties_for,
    phase,
    plant_from,
    segments,
    vary,
    w_mid,
    wrap,
)
from smodrive.engine import _ffi
from smodrive.model import RPM, AdcCfg, LclFilterPars, ParameterError
from smodrive.engine.plant import Plant
from smodrive.engine import plant_config


# ------------------------------------------------------------------ helpers --


def real_system(c, w: float) -> np.ndarray:
    """yao2022 eq. (1)-(3), states [u_c, i_1, i_2, e] (alpha, beta pairs) plus
    the two inverter-voltage inputs held as states (du/dt = 0): 10x10."""
    L2 = c.L2o + c.L_s
    I2, Z = np.eye(2), np.zeros((2, 2))
    Jm = np.array([[0.0, -1.0], [1.0, 0.0]])
    M = np.zeros((10, 10))
    M[:8, :8] = np.block(
        [
            [Z, I2 / c.C1, -I2 / c.C1, Z],
            [-I2 / c.L1, Z, Z, Z],
            [I2 / L2, Z, -c.R_s / L2 * I2, -I2 / L2],
            [Z, Z, Z, w * Jm],
        ]
    )
    M[2:4, 8:10] = I2 / c.L1
    return M


def reference_period(p: Plant, segs, w: float) -> np.ndarray:
    """[u_c, i_1, i_2] at the period end from expm of the 10x10 real system,
    piecewise over the segments, the EMF rotating at w from e(0)."""
    c = p.config
    e0 = 1j * w * c.psi_r * cmath.exp(1j * p.theta_r)
    x = np.array([p.u_c, p.i_1, p.i_s, e0])
    s = np.r_[np.column_stack([x.real, x.imag]).ravel(), 0.0, 0.0]
    M = real_system(c, w)
    for tau, u in segs:
        s[8:10] = u.real, u.imag
        s = expm(M * tau) @ s
    return s[0:6:2] + 1j * s[1:6:2]


def rotor_reference(p: Plant, segs, w: float):
    """Rotor-frame exact solution with the torque integral (independent of the
    plant's stationary-frame modal form): with y = x e^{-j theta},
    v = u e^{-j theta}, Q = int i_2r dt, the system in
    (u_cr, i_1r, i_2r, v, Q, 1) is complex-linear at constant w.
    Returns ([u_c, i_1, i_2] stationary at T, int_0^T i_2 e^{-j theta} dt)."""
    c = p.config
    L2 = c.L2o + c.L_s
    jw = 1j * w
    M = np.array(
        [
            [-jw, 1 / c.C1, -1 / c.C1, 0, 0, 0],
            [-1 / c.L1, -jw, 0, 1 / c.L1, 0, 0],
            [1 / L2, 0, -c.R_s / L2 - jw, 0, 0, -jw * c.psi_r / L2],
            [0, 0, 0, -jw, 0, 0],
            [0, 0, 1, 0, 0, 0],
            [0, 0, 0, 0, 0, 0],
        ],
        dtype=complex,
    )
    th = p.theta_r
    rot = cmath.exp(-1j * th)
    y = np.array([p.u_c * rot, p.i_1 * rot, p.i_s * rot, 0.0, 0.0, 1.0], dtype=complex)
    for tau, u in segs:
        y[3] = u * cmath.exp(-1j * th)
        y = expm(M * tau) @ y
        th += w * tau
    return y[:3] * cmath.exp(1j * th), y[4]


def plant_with_state(rng, **kw) -> Plant:
    """The Table II plant (fields changed by `kw`, see plant_helpers.vary)
    from a random rotor-frame state: u_c, i_1 and the motor current i_2."""
    st = dict(
        uc_d0=rng.uniform(-20, 20), uc_q0=rng.uniform(-20, 20),
        i1_d0=rng.uniform(-30, 30), i1_q0=rng.uniform(-30, 30),
        i_d0=rng.uniform(-30, 30), i_q0=rng.uniform(-30, 30),
    )
    kw.setdefault("theta_r0", rng.uniform(-math.pi, math.pi))
    return plant_from(vary(TABLE2, **kw), **st)


def state_scale(x: np.ndarray, c) -> float:
    """Magnitude scale of the states: the largest state, or the currents the
    DC link can drive through the filter in one period."""
    return max(np.max(np.abs(x)), c.u_dc * c.T_sw / c.L1)


# ---------------------------------------------------- (a) carrier PWM period --

# Cases: Table II at 100 kr/min; reversed speed with dead time; a speed whose
# electrical frequency sits exactly on the filter resonance (exercises the
# near-resonance series branch for short sub-intervals); a heavily damped
# filter (R = 0.2 ohm with a tiny L2: three real modes, the all-real
# branch; the L1-C loop is damped only through L2, so this needs
# R < sqrt(L1/C1)/2 and L2 << L1); small inertia
# (the mid-period speed correction matters).
CASES = [
    dict(w_M0=100e3 * RPM, J=1e4),
    dict(w_M0=-60e3 * RPM, J=1e4, t_dead=1e-6),
    dict(w_M0=None, J=1e4),  # filled with the resonance below
    dict(w_M0=40e3 * RPM, J=1e4, R_s=0.2, L2o=0.0, L_s=1e-7),
    dict(w_M0=80e3 * RPM, J=1e-7, B=1e-6, k_fan=4.9e-10),
]


def _case(kw, rng):
    kw = dict(kw)
    if kw["w_M0"] is None:
        kw["w_M0"] = plant_with_state(rng).eigenvalues[1].imag  # n_p = 1
    return kw


@pytest.mark.parametrize("case", range(len(CASES)))
@pytest.mark.parametrize("pwm", ["carrier", "averaged"])
def test_period_matches_expm_of_augmented_system(case, pwm):
    # (a) carrier PWM and (b) switching-cycle average, random duties and
    # states, EMF rotating (e' = w J e) inside the 8x8 augmented system.
    rng = np.random.default_rng(100 + case)
    kw = _case(CASES[case], rng)
    p = plant_with_state(rng, pwm=pwm, **kw)
    c = p.config
    if kw.get("R_s") == 0.2:
        assert np.all(p.eigenvalues.imag == 0.0)  # the all-real branch is exercised
    worst = 0.0
    for _ in range(12):
        d = rng.uniform(0.02, 0.98, 3)
        i1_abc = phase(p.i_1)
        w = w_mid(p)
        segs = segments(c, d, i1_abc)
        ref = reference_period(p, segs, w)
        p.step(d)
        got = np.array([p.u_c, p.i_1, p.i_s])
        worst = max(worst, np.max(np.abs(got - ref)) / state_scale(ref, c))
    # Both sides are exact up to rounding. The plant's error is a few ulps of
    # the modal coordinates times the eigenvector basis' condition number
    # (the modes' eigenvector entries differ by ~1e2 in magnitude), the
    # reference's is scipy's Pade expm error (~1e-15 ||M tau||) per segment,
    # up to 7 segments: observed ~1e-14. 1e-10 is a 1e4 margin, while the
    # mildest modelling error (e.g. the EMF held constant over a period at
    # 100 kr/min, w T = 0.52 rad) would be ~1e-1 relative.
    assert worst < 1e-10, worst


def test_period_averaged_equals_carrier_at_zero_ripple():
    # Consistency between the modes: duties 0 or 1 give the same constant
    # voltage in both, so the two plants agree to rounding.
    rng = np.random.default_rng(5)
    pa = plant_with_state(np.random.default_rng(6), pwm="averaged", w_M0=50e3 * RPM, J=1e4)
    pc = plant_with_state(np.random.default_rng(6), pwm="carrier", w_M0=50e3 * RPM, J=1e4)
    for _ in range(20):
        d = rng.integers(0, 2, 3).astype(float)
        pa.step(d)
        pc.step(d)
        scale = state_scale(np.array([pa.u_c, pa.i_1, pa.i_s]), pa.config)
        assert abs(pa.i_1 - pc.i_1) < 1e-12 * scale
        assert abs(pa.i_s - pc.i_s) < 1e-12 * scale
        assert abs(pa.T_e_mean - pc.T_e_mean) <= 1e-12 * max(1.0, abs(pa.T_e_mean))


# ------------------------------------------------------- (c) resonance --------


def test_resonance_frequency_table2():
    p = Plant(TABLE2)
    c = p.config
    L2 = c.L2o + c.L_s
    # independent eigenvalues: numpy's solver on the real 6x6 filter matrix
    lam_np = np.linalg.eigvals(real_system(c, 0.0)[:6, :6])
    for lam in p.eigenvalues:
        # each eigenvalue of the complex 3x3 appears twice in the real 6x6;
        # relative agreement to ~1e-13 is rounding in both solvers (the pair
        # is well separated from the real root, condition ~1).
        assert np.min(np.abs(lam_np - lam)) < 1e-11 * abs(lam)
    f_res = abs(p.eigenvalues[1].imag) / (2 * math.pi)
    f_formula = 1.0 / (2 * math.pi * math.sqrt(c.L1 * L2 * c.C1 / (c.L1 + L2)))
    # R shifts the damped resonance by O(zeta^2) with zeta = sigma/omega
    # = 114/34713 = 3.3e-3, i.e. ~1e-5 relative: far inside 0.1 %.
    assert abs(f_res / f_formula - 1) < 1e-3
    assert abs(f_res / 5525.0 - 1) < 1e-3  # Table II, f_res = 5525 Hz
    # the real mode is the total-inductance L/R decay: lambda_0 ~ -R/(L1+L2)
    # up to O(R^2 C / L) ~ 1e-6 relative
    assert abs(p.eigenvalues[0].real / (-c.R_s / (c.L1 + L2)) - 1) < 1e-3
    # lightly damped: the pair's damping ratio is below 1 %
    assert -p.eigenvalues[1].real / abs(p.eigenvalues[1]) < 0.01


# -------------------------------------------------- (d) energy balance -------


def energy_residual(T_sw: float, t_end: float) -> tuple[float, float]:
    """Run the self-synchronous drive (voltage locked to the rotor angle) from
    76 kr/min with small inertia (the speed, and so the mechanical power,
    varies) in averaged mode and return
    (|residual| of the cumulative balance, total input energy), J."""
    p = Plant(vary(TABLE2, T_sp=T_sw, pwm="averaged", J=2e-7, B=1e-7, k_fan=4.9e-10,
                   theta_r0=0.3, w_M0=8000.0))
    c = p.config
    L2 = c.L2o + c.L_s

    def stored():
        return 0.75 * (c.L1 * abs(p.i_1) ** 2 + L2 * abs(p.i_s) ** 2 + c.C1 * abs(p.u_c) ** 2)

    E0 = stored()
    E_in = E_cu = E_mech = 0.0
    n = int(round(t_end / T_sw))
    for k in range(n):
        th = p.theta_r + 1.65  # voltage leads the rotor: motoring
        d = [0.5 + 0.35 * math.cos(th - 2 * math.pi * x / 3) for x in range(3)]
        i1a, i2a, wm = p.i_1, p.i_s, w_mid(p) / c.n_p
        p.step(d)
        u = p.u_mean  # constant over the period in averaged mode
        E_in += 1.5 * (u * np.conj(0.5 * (i1a + p.i_1))).real * T_sw
        E_cu += 1.5 * c.R_s * 0.5 * (abs(i2a) ** 2 + abs(p.i_s) ** 2) * T_sw
        # EMF power = T_e w_M; the plant's electrical solution holds the EMF
        # at the mid-period speed, so the energy it transfers in the period
        # is exactly T_e_mean * w_mid * T.
        E_mech += p.T_e_mean * wm * T_sw
    # the speed changed (inertia, fan and friction are active) and the
    # mechanical power is a major term of the balance
    assert abs(p.w_M - 8000.0) > 100.0
    assert E_mech > 0.3 * E_in
    return abs(E_in - E_cu - E_mech - (stored() - E0)), E_in


def test_energy_balance():
    # (d) input 1.5 Re(u conj i_1) = copper 1.5 R |i_2|^2 + d/dt stored
    # 0.75 (L1|i_1|^2 + L2|i_2|^2 + C1|u_c|^2) + T_e w_M. The plant's
    # per-period solution conserves this exactly; the test's bookkeeping
    # integrates i_1 and |i_2|^2 by the trapezoid rule from period-end values,
    # a relative error ~ (w T)^2 / 12 at the highest frequency present (the
    # 5.5 kHz resonance: (34713 * 1e-6)^2 / 12 = 1e-4). So the residual must
    # be below ~1e-4 of the input energy and shrink as T^2.
    r1, E1 = energy_residual(1e-6, 4e-3)
    r2, E2 = energy_residual(2e-6, 4e-3)
    assert r1 < 2e-4 * E1, (r1, E1)
    assert r2 < 8e-4 * E2, (r2, E2)
    # second order: halving T divides the residual by ~4 (3 ... 5.5 allows
    # for the O(T^3) remainder); a plant that leaked energy at O(T) would
    # give ~2, an exact-but-inconsistent one ~1.
    ratio = r2 / r1
    assert 3.0 < ratio < 5.5, ratio


# -------------------------------------------------------------- (e) ADC -----


def test_adc_measures_both_currents_with_own_gains_offsets():
    g1, o1 = (1.03, 0.97, 1.01), (0.2, -0.1, 0.05)
    g2, o2 = (0.98, 1.02, 1.005), (-0.3, 0.15, 0.0)
    rng = np.random.default_rng(11)
    # i_1 channels: gain_i1, offset_i1; motor (i_2) channels: gain, offset
    p = plant_with_state(rng, w_M0=30e3 * RPM, J=1e4, gain_i1=g1, offset_i1=o1, gain=g2,
                         offset=o2)
    for _ in range(30):
        p.step(rng.uniform(0.1, 0.9, 3))
        m2, m1 = p.sample_all()
        t2, t1 = p.phase_currents()
        # the true phases are Re(i e^{-j 2 pi x / 3}) of the state
        assert np.allclose(t1, phase(p.i_1), rtol=0, atol=4 * EPS * max(1.0, abs(p.i_1)))
        assert np.allclose(t2, phase(p.i_s), rtol=0, atol=4 * EPS * max(1.0, abs(p.i_s)))
        # one multiply-add per channel: equal to a couple of ulps
        tol1 = 4 * EPS * (np.abs(t1) + 1.0)
        tol2 = 4 * EPS * (np.abs(t2) + 1.0)
        assert np.all(np.abs(m1 - (np.array(g1) * t1 + np.array(o1))) <= tol1)
        assert np.all(np.abs(m2 - (np.array(g2) * t2 + np.array(o2))) <= tol2)


def test_adc_noise_on_all_six_channels():
    # Zero state, duties 0.5 (u = 0) and no flux: the samples are pure noise.
    # Each channel's sample variance over n draws is sigma^2 chi2(n)/n; the
    # 1e-6 two-sided quantiles make a false failure negligible. The six
    # channels must be mutually uncorrelated (|r| < 5/sqrt(n)).
    sigma, n = 0.05, 4000
    p = Plant(vary(TABLE2, psi_r=0.0, noise=sigma, seed=9))
    s = np.empty((n, 6))
    for k in range(n):
        p.step((0.5, 0.5, 0.5))
        m2, m1 = p.sample_all()
        s[k] = np.r_[m1, m2]
    # sum_x a^x = 0 up to rounding: u ~ 1e-16 u_dc, currents ~1e-16 A
    assert abs(p.i_1) < 1e-12 and abs(p.i_s) < 1e-12
    lo, hi = chi2.ppf([1e-6, 1 - 1e-6], n) / n
    var = (s**2).mean(axis=0) / sigma**2
    assert np.all((var > lo) & (var < hi)), var
    r = np.corrcoef(s.T)
    assert np.max(np.abs(r - np.eye(6))) < 5 / math.sqrt(n)


def test_adc_gain_error_gives_2fe_in_dq():
    # (e) 'ADC scaling error' (yao2022 Sec. III-A-1): with per-phase gains g_x
    # the Clarke/Park of the measured phases of a current I e^{j theta} is
    #   (mean g) I + (1/3) conj(I) e^{-2 j theta} sum_x g_x a^{2x},
    # a 2 f_e ripple in dq. Steady state at constant speed (J = 1e4; the
    # torque of ~0.05 N m changes w by 2.5e-10 rad/s per period) with the
    # voltage locked to the rotor: at 100 kr/min, w T = pi/6 exactly, 12
    # samples per electrical period.
    g1 = (1.02, 1.0, 0.99)
    g2 = (0.97, 1.01, 1.0)
    p = Plant(vary(TABLE2, pwm="averaged", J=1e4, w_M0=100e3 * RPM, gain_i1=g1, gain=g2))
    # transients: slowest modes e^{-114 t} (resonance) and e^{-218 t}: after
    # 0.3 s they are e^{-34} ~ 1e-15 of the initial mismatch
    p.run_open(6000, 0.6, 1.6)
    n = 12 * 24
    th = np.empty(n)
    y1, y2, q1, q2 = (np.empty(n, complex) for _ in range(4))
    for k in range(n):
        th[k] = p.theta_r
        m2, m1 = p.sample_all()
        rot = cmath.exp(-1j * th[k])
        y1[k], y2[k] = clarke(m1) * rot, clarke(m2) * rot
        q1[k], q2[k] = p.i_1 * rot, p.i_s * rot
        p.run_open(1, 0.6, 1.6)
    # steady state: the true rotor-frame currents are constant at the samples
    # (the averaged voltage satisfies u(t + T) = e^{j w T} u(t))
    for q in (q1, q2):
        assert np.max(np.abs(q - q.mean())) < 1e-10 * abs(q.mean())
    assert abs(q2.mean()) > 5.0  # a meaningful current
    for y, q, g in ((y1, q1, g1), (y2, q2, g2)):
        I = q.mean()
        c2_pred = np.conj(I) * sum(g[x] * A ** (2 * x) for x in range(3)) / 3
        dc_pred = I * np.mean(g)
        # least-squares fit over 24 electrical periods at the sampled angles:
        # y = dc + c2 e^{-2 j theta} + c1 e^{-j theta} + c2p e^{2 j theta}
        X = np.column_stack([np.ones(n), np.exp(-2j * th), np.exp(-1j * th), np.exp(2j * th)])
        (dc, c2, c1, c2p), *_ = np.linalg.lstsq(X, y, rcond=None)
        # amplitude of the 2 f_e component, e.g. |I| |0.02 - 0.01 a^4| / 3;
        # the identity is exact per sample, so only rounding (~1e-15 |I|) and
        # the non-constancy of the true dq current (<1e-10 |I|, asserted
        # above) remain.
        assert abs(c2 - c2_pred) < 1e-10 * abs(I)
        assert abs(dc - dc_pred) < 1e-10 * abs(I)
        assert abs(c1) < 1e-10 * abs(I)  # no f_e term without offsets
        assert abs(c2p) < 1e-10 * abs(I)  # only the negative sequence
        assert abs(c2) > 2e-3 * abs(I)  # the ripple is really there (~0.5-1 % of |I|)
    # with exact gains there is no 2 f_e component
    p0 = Plant(vary(TABLE2, pwm="averaged", J=1e4, w_M0=100e3 * RPM))
    p0.run_open(6000, 0.6, 1.6)
    c2 = 0.0
    for k in range(n):
        m2 = p0.sample()
        c2 += clarke(m2) * cmath.exp(-1j * p0.theta_r) * cmath.exp(2j * p0.theta_r) / n
        p0.run_open(1, 0.6, 1.6)
    assert abs(c2) < 1e-9 * abs(p0.i_s)


# ------------------------------------------------- (f) torque at locked speed --


@pytest.mark.parametrize("pwm", ["carrier", "averaged"])
def test_mean_torque_equals_kt_mean_iq(pwm):
    # (f) Locked speed (J = 1e4 kg m^2), psi_r > 0: per period,
    # T_e_mean = 1.5 n_p psi_r (1/T) int i_q dt with i_q = Im(i_2 e^{-j theta})
    # integrated exactly by the rotor-frame reference (expm over the PWM
    # sub-intervals with the integral as a state).
    rng = np.random.default_rng(21)
    p = plant_with_state(rng, pwm=pwm, w_M0=100e3 * RPM, J=1e4)
    c = p.config
    Kt = 1.5 * c.n_p * c.psi_r
    Te, iq = [], []
    worst_x = 0.0
    for k in range(40):
        th = p.theta_r + 1.6
        d = np.array([0.5 + 0.45 * math.cos(th - 2 * math.pi * x / 3) for x in range(3)])
        w = w_mid(p)
        segs = segments(c, d, phase(p.i_1))
        x_ref, Q = rotor_reference(p, segs, w)
        p.step(d)
        worst_x = max(worst_x, np.max(np.abs(np.array([p.u_c, p.i_1, p.i_s]) - x_ref))
                      / state_scale(x_ref, c))
        Te.append(p.T_e_mean)
        iq.append(Q.imag / c.T_sw)
    Te, iq = np.array(Te), np.array(iq)
    # Both exact up to rounding, as in (a): the integral of i_q is a sum of
    # terms of the size of i_q T, so ~1e-13 relative to max|i_q|.
    assert np.max(np.abs(Te - Kt * iq)) < 1e-10 * Kt * np.max(np.abs(iq))
    assert worst_x < 1e-10
    assert abs(Te.mean() - Kt * iq.mean()) < 1e-10 * Kt * np.max(np.abs(iq))
    assert np.max(np.abs(iq)) > 1.0
    # locked: the speed moved by less than 1e-9 relative
    assert abs(p.w_M / (100e3 * RPM) - 1) < 1e-9


# --------------------------------------------- (g) brake, shared mechanics --


def test_brake_decay_matches_analytic_and_the_filterless_plant():
    """The mechanics (smd_mech_advance) are shared, so the LCL plant brakes
    as the filterless one does. psi_r = 0: no EMF, no drive torque (T_e = 0
    exactly, Kt = 0), duties 0.5 (no voltage). Outside the taper band
    (w >= w_brake_eps) J dw/dt = -T_b - B w, so
      w(t) = (w0 + T_b/B) e^{-Bt/J} - T_b/B,
      theta(t) = n_p [(w0 + T_b/B) (J/B) (1 - e^{-Bt/J}) - (T_b/B) t];
    inside it the brake is the viscous T_b w / eps: exact exponential decay
    to rest, no reversal. J = 1e-5 (Table II), B = 1e-5, T_b = 5 mN m: the
    brake (500 rad/s^2) and the friction (1000 rad/s^2 at w0) both matter;
    B T / J = 5e-5 keeps the plant's (1 - e^{-x})/x on its series branch
    (exact to an ulp; the direct form would lose eps/x ~ 2e-12 per step)."""
    J, B, T_b, eps, w0 = 1e-5, 1e-5, 5e-3, 1.0, 1000.0
    kw = dict(psi_r=0.0, J=J, B=B, k_fan=0.0, w_brake_eps=eps, w_M0=w0, theta_r0=0.0)
    s = vary(TABLE2, **kw)
    p = Plant(s)
    q = Plant(s.replace(lcl=None))  # the same scenario without the filter
    assert p.config.lcl == 1 and q.config.lcl == 0
    c, T, n_p = p.config, s.T_sp, s.motor.n_p
    w0 = c.w_M0  # w0 / RPM * RPM: the plant's own start
    # time to reach the band: (J/B) ln((w0 + T_b/B) / (eps + T_b/B)) = 1.10 s
    t_band = J / B * math.log((w0 + T_b / B) / (eps + T_b / B))
    n_out = int(t_band / T)  # periods that end outside the band
    n = n_out + 2000  # then 0.1 s in the band: rate (B + T_b/eps)/J = 501/s, e^{-50}
    worst_w = worst_th = 0.0
    ws = np.empty(n)
    for k in range(1, n + 1):
        p.step((0.5, 0.5, 0.5), 0.0, T_b)
        q.step((0.5, 0.5, 0.5), 0.0, T_b)
        ws[k - 1] = p.w_M
        # the same mechanics with the same (zero) torques: bit for bit
        assert p.w_M == q.w_M and p.theta_r == q.theta_r
        if k <= n_out:
            t = k * T
            e = math.exp(-B * t / J)
            w_ref = (w0 + T_b / B) * e - T_b / B
            th_ref = n_p * ((w0 + T_b / B) * J / B * (1 - e) - T_b / B * t)
            worst_w = max(worst_w, abs(p.w_M - w_ref))
            worst_th = max(worst_th, abs(wrap(p.theta_r - th_ref)))
    # nothing drives: Kt = 1.5 n_p psi_r = 0 exactly, and the duties' vector
    # (2/3) u_dc 0.5 sum_x a^x is 0 up to rounding (~1e-16 u_dc)
    assert p.T_e_mean == 0.0 and abs(p.i_s) < 1e-12 and abs(p.i_1) < 1e-12
    assert ws[n_out - 1] >= eps > ws[n_out]  # the band is entered where predicted
    # Rounding: each period's exact update w + (F/J - b w) T phi1(bT) is a
    # contraction (factor 1 - bT phi1 < 1) whose rounding is under an ulp of
    # w0 (the addition, half an ulp, plus a few ulps of the 0.08 rad/s
    # increment), so n_out periods stay within n_out eps w0 = 5e-9 rad/s; the
    # reference's exp and products add a few ulps of w0 + T_b/B. A missing
    # brake or friction term would be off by 50 rad/s within 0.1 s.
    assert worst_w <= n_out * EPS * w0 + 8 * EPS * (w0 + T_b / B), worst_w
    # The angle is wrapped to [-pi, pi) every period: rounding under 2 ulps of
    # 2 pi a period, plus TWO_PI's own 2.4e-16 per wrap (about 70 wraps) and
    # a few ulps of the ~450 rad reference: n_out 4 pi eps = 6e-11 rad.
    assert worst_th <= n_out * 4 * math.pi * EPS + 16 * EPS * abs(th_ref), worst_th
    # inside the band: viscous, exact exponential decay: no reversal, at rest
    assert ws.min() >= 0.0
    assert ws[-1] <= eps * math.exp(-(B + T_b / eps) / J * 1999 * T) * 1.01


# ------------------------------------------- (h) the filter vanishing -------


def _drive_both(eps: float, n: int = 300):
    """The yang2018 machine (L_s = 23.45 mH, R_s = 2.25 ohm) spinning at
    1000 r/min (J = 1e4: the speed is held), 10 kHz carrier PWM without dead
    time, duties of a rotating voltage locked to the filterless plant's angle
    (~6 A), fed to the filterless plant and to the same machine behind
    L1 = eps L_s, L2o = 0, C1 = 0.1 nF (resonance >= 1 MHz, above the 10 kHz
    carrier by >= 100). Returns the rows (i, i_2, i_1, LP) at the period ends,
    LP_k = a int_0^t_k e^{-a (t_k - s)} i(s) ds from the filterless current's
    samples (exact for its chord), and the capacitor-current bound
    2 a C1 max|u_c| (sampled maximum) and a t_n."""
    base = vary(SPMSM, pwm="carrier", t_dead=0.0, J=1e4, B=0.0, w_M0=1000.0 * RPM, theta_r0=0.3)
    m, T = base.motor, base.T_sp
    p0 = Plant(base)
    p1 = Plant(vary(base, L1=eps * m.L_s, L2o=0.0, C1=1e-10))
    assert abs(p1.eigenvalues[1].imag) / (2 * math.pi) > 100 / T
    a = m.R_s / m.L_s
    E = math.exp(-a * T)
    g = -math.expm1(-a * T)
    w_end = g - g / (a * T) + E  # weight of the period-end sample (the start: g - w_end)
    w = m.n_p * 1000 * RPM
    U = 1j * w * m.psi_r + (m.R_s + 1j * w * m.L_s) * 6.0 * cmath.exp(2.3j)
    out = np.empty((n, 4), complex)
    LP, uc_max = 0j, 0.0
    for k in range(n):
        d = duties_for(U * cmath.exp(1j * p0.theta_r), base.inverter.u_dc)
        i_prev = p0.i_s
        p0.step(d)
        p1.step(d)
        LP = E * LP + (g - w_end) * i_prev + w_end * p0.i_s
        out[k] = p0.i_s, p1.i_s, p1.i_1, LP
        uc_max = max(uc_max, abs(p1.u_c))
    return out, 2 * a * p1.config.C1 * uc_max, a * n * T


def test_lcl_tends_to_filterless_as_the_filter_vanishes():
    """With L2o = 0 the machine sees u_c = u - L1 di_1/dt instead of u, so the
    motor-current difference d = i_2 - i obeys L_s dd/dt + R d = -L1 di_1/dt:
    from rest,
      d(t) = -(L1/L_s) [i_1(t) - a int_0^t e^{-a(t-s)} i_1(s) ds],  a = R/L_s,
    the drop across the filter's remaining impedance L1; it vanishes with
    L1/L_s. The test checks this at every period end with the integral taken
    over the filterless current i; what that neglects, relative to
    (L1/L_s) max|i|:
    - the capacitor current C1 du_c/dt in i_1: a C1 (u_c - low-pass of u_c),
      <= 2 a C1 max|u_c| ~ 4e-5 (u_c rings at the undamped resonance up to
      ~20 kV, the sampled maximum is used);
    - the chord rule for i within a period: the leg pulses are centred in the
      period (regular sampling, no dead time), so their first moment vanishes
      and what remains is (w T)^2 / 12 = 1.5e-4 of the rotating current plus
      the weight's tilt a T = 0.01 over the ripple (<= (2/3) u_dc (T/2) / L_s
      = 0.77 A, max|i| ~ 8.6 A): 9e-4; with the above, 2e-3 is a 2x margin;
    - i_2 - i = d itself inside the integral: <= (1 - e^{-a t}) max|d|
      (second order in L1/L_s);
    - the EMF difference from the speeds' divergence: the torques differ by
      O(L1), J = 1e4 keeps the angles within 1e-8 rad (L1 = 0.01 L_s), i.e.
      1.7e-6 V of EMF and < 1e-6 A: under 1e-5 of the scale."""
    for eps in (1e-2, 1e-3, 1e-4):
        x, cap, at = _drive_both(eps)
        i, i2, i1, LP = x.T
        d = i2 - i
        scale = eps * np.max(np.abs(i))
        assert cap < 1e-4 * np.max(np.abs(i)), cap  # the first item
        resid = np.max(np.abs(d + eps * (i1 - LP)))
        tol = 2e-3 * scale + eps * (1 - math.exp(-at)) * np.max(np.abs(d))
        assert resid <= tol, (eps, resid / scale)
        # the effect is resolved: the drop is of the order of (L1/L_s) |i|
        assert np.max(np.abs(d)) > 0.5 * scale


def test_lcl_error_shrinks_with_the_filter():
    """By the identity of the previous test, max|i_2 - i| <= (L1/L_s)
    (max|i_1| + max|i|) up to its residual (< 0.3 % of that here): the
    relative error is L1/L_s times (max|i_1| + max|i|) / max|i|. In i_1 the
    load current does not depend on L1, the resonance ringing the edges
    excite (a (2/3) u_dc step over the characteristic impedance sqrt(L1/C1)
    per edge, C1 fixed) grows as L1^{-1/2}; so the error falls as L1 to
    L1^{1/2}: two decades of L1 cut it by 100 to 10, at least 10."""
    err = {}
    for eps in (1e-2, 1e-4):
        x, _, _ = _drive_both(eps)
        i, i2, i1, _ = x.T
        i_max = np.max(np.abs(i))
        err[eps] = np.max(np.abs(i2 - i)) / i_max
        assert err[eps] <= 1.01 * eps * (np.max(np.abs(i1)) + i_max) / i_max, err
    assert err[1e-4] <= err[1e-2] / 10, err


# ----------------------------------------------------------- API hygiene -----


def test_bad_parameters_are_named():
    # the Python sections name the field (and its section) first
    with pytest.raises(ParameterError, match=r"lcl\.C1"):
        LclFilterPars(C1=-1.0)
    with pytest.raises(ParameterError, match=r"adc\.gain "):
        AdcCfg(gain=(1.0, 3.0, 1.0))  # the motor (i_2) channels
    with pytest.raises(ParameterError, match=r"adc\.gain_i1"):
        AdcCfg(gain_i1=(1.0, 3.0, 1.0))
    with pytest.raises(ParameterError, match=r"inverter\.t_dead"):
        vary(TABLE2, t_dead=20e-6)  # T_sp / 4 = 12.5 us
    with pytest.raises(TypeError):
        LclFilterPars(L_s=1.0)  # the machine's, not the filter's


def _init(c) -> tuple[int, str]:
    buf = (ct.c_double * (_ffi.lib.smd_sizeof_plant() // 8 + 1))()
    rc = _ffi.lib.smd_plant_init(buf, ct.byref(c))
    return rc, _ffi.lib.smd_plant_field(rc).decode()


@pytest.mark.parametrize("field, value, name", [
    ("C1", 0.0, "C1"), ("C1", math.nan, "C1"), ("L1", 0.0, "L1"), ("L2o", -1e-6, "L2o"),
    ("adc_gain_i1", (1.0, 3.0, 1.0), "adc_gain_i1"), ("uc_d0", math.inf, "uc_d0/uc_q0"),
    ("i1_q0", math.nan, "i1_d0/i1_q0"),
])
def test_init_checks_the_filter_fields_only_with_the_filter(field, value, name):
    """smd_plant_init names a bad filter value through smd_plant_field
    (below the Python sections' own checks, e.g. for configs built in C),
    and ignores every filter field when lcl = 0."""
    c = plant_config(TABLE2)
    setattr(c, field, value)
    assert _init(c)[1] == name
    with pytest.raises(ParameterError, match=f"plant parameter {name} rejected"):
        plant_from(TABLE2, **{field: value})
    # without the filter the same garbage is not read: init succeeds and the
    # plant runs bit for bit as with clean filter fields
    ref = Plant(vary(SPMSM, pwm="carrier", w_M0=500.0 * RPM, theta_r0=0.4))
    c = plant_config(ref.scenario)
    assert c.lcl == 0
    setattr(c, field, value)
    rc, _ = _init(c)
    assert rc == 0
    p = plant_from(ref.scenario, **{field: value})
    for _ in range(50):
        d = duties_for(100.0 * cmath.exp(1j * (ref.theta_r + 2.0)), 540.0)
        ref.step(d)
        p.step(d)
        assert (p.i_s, p.i_1, p.u_c, p.w_M, p.theta_r) == (ref.i_s, ref.i_1, ref.u_c, ref.w_M,
                                                          ref.theta_r)
        (a, a1), (b, b1) = p.sample_all(), ref.sample_all()
        assert np.array_equal(a, b) and np.array_equal(a1, b1) and not a1.any()
    assert p.u_c == 0 and p.i_1 == p.i_s and p.eigenvalues.tolist() == [0, 0, 0]
    assert abs(p.i_s) > 1.0  # it really ran


@pytest.mark.parametrize("lcl", [True, False])
def test_initial_state_in_rotor_frame(lcl):
    """The config's rotor-frame state, turned by theta_r0 (x_ab = x_dq
    e^{j theta}): a rotation, ~1 ulp per component. Without the filter
    u_c = 0 and i_1 = i_s whatever the filter fields say."""
    s = vary(TABLE2 if lcl else SPMSM, theta_r0=0.7)
    p = plant_from(s, uc_d0=1.0, uc_q0=2.0, i1_d0=3.0, i1_q0=4.0, i_d0=5.0, i_q0=6.0)
    r = cmath.exp(0.7j)
    assert abs(p.i_s - (5 + 6j) * r) < 1e-14 * 8
    if lcl:
        assert abs(p.u_c - (1 + 2j) * r) < 1e-14 * 3
        assert abs(p.i_1 - (3 + 4j) * r) < 1e-14 * 5
    else:
        assert p.u_c == 0 and p.i_1 == p.i_s
