"""Physics tests of the host plant without the filter (sim/src/smd_spmsm.c, the
shared mechanics of sim/src/smd_mech.c, ADC of smd_adc.c and PWM of smd_pwm.c) through
smodrive.engine.plant.Plant; the plant behind the LCL filter: test_lcl_plant.py.

Every reference below is computed independently of the plant's own
formulation (closed forms, a rotor-frame matrix exponential, Fourier sums of
pulses, Bessel series), and every tolerance is argued in a comment from the
physics or the floating-point numerics, not fitted to the output.

Conventions (yang2018 eq. (1), amplitude-invariant Clarke transform):
  L di/dt = u - R i - j w psi e^{j theta},  i_x = Re(i e^{-j 2 pi x / 3}),
  leg x contributes (2/3) u_dc a^x * (leg high), a = e^{j 2 pi / 3},
  T_e = 1.5 n_p psi Im(i e^{-j theta}),  J dw_M/dt = T_e - T_L - B w_M.
"""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.stats import chi2

from plant_helpers import SPMSM, A, duties_for, leg_dir, phase, pwm_segments, vary, wrap
from smodrive.analysis.pwm import leg_harmonics_bessel, leg_harmonics_from_edges
from smodrive.model import RPM
from smodrive.engine.plant import Plant


# ------------------------------------------------------------------ helpers --


def exact_period(i0: complex, th0: float, w: float, segs, c):
    """Exact solution of the electrical equation over consecutive segments
    [(tau, u_stationary), ...] at constant electrical speed w, in the ROTOR
    frame (independent of the plant, which works in the stationary frame):
      q = i e^{-j theta}:  L dq/dt = v - (R + j w L) q - j w psi,
      v = u e^{-j theta}:  dv/dt = -j w v,     Q = int q dt.
    The system in (q, v, Q, 1) is complex-linear, so one matrix exponential per
    segment is exact (c: the plant's config). Returns (i_end, theta_end,
    int_0^T q dt)."""
    R, L, psi = c.R_s, c.L_s, c.psi_r
    Amat = np.array(
        [
            [-(R / L + 1j * w), 1.0 / L, 0.0, -1j * w * psi / L],
            [0.0, -1j * w, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0],
        ],
        dtype=complex,
    )
    q = i0 * cmath.exp(-1j * th0)
    Q = 0.0
    th = th0
    for tau, u in segs:
        if tau <= 0.0:
            continue
        x = expm(Amat * tau) @ np.array([q, u * cmath.exp(-1j * th), Q, 1.0])
        q, Q = x[0], x[2]
        th += w * tau
    return q * cmath.exp(1j * th), th, Q


# ------------------------------------------------------ 1. locked rotor, avg --


def test_locked_rotor_step_response_averaged():
    # psi_r = 0: no EMF and no torque, so the rotor stays at w = 0 exactly and
    # the equation is L di/dt = u - R i with u constant.
    s = vary(SPMSM, psi_r=0.0, J=1e4, B=0.0)
    R, L, T = s.motor.R_s, s.motor.L_s, s.T_sp
    d = (0.55, 0.47, 0.49)
    u = complex(leg_dir(s.inverter.u_dc) @ np.array(d))
    p = Plant(s)
    worst = 0.0
    for k in range(1, 501):  # 0.05 s = 4.8 L/R
        p.step(d)
        ref = u / R * (1.0 - math.exp(-R * k * T / L))
        worst = max(worst, abs(p.i_s - ref))
        assert p.w_M == 0.0
    # The plant's recurrence i_{k+1} = e^{-aT} i_k + (1-e^{-aT}) u/R accumulates
    # ~1 ulp per step: 500 * 2.2e-16 ~ 1e-13 relative; 1e-9 leaves a wide margin
    # while any modelling error (e.g. a first-order step, error ~aT/2 = 5e-3)
    # would be caught by 6 orders of magnitude.
    assert worst <= 1e-9 * abs(u) / R
    # u_mean is exactly the averaged voltage of the duties
    assert abs(p.u_mean - u) <= 1e-12 * s.inverter.u_dc


# ------------------------------------------------ 2. carrier PWM, exact path --


@pytest.mark.parametrize("t_dead", [0.0, 2e-6])
def test_locked_rotor_carrier_pwm_matches_piecewise_solution(t_dead):
    s = vary(SPMSM, pwm="carrier", t_dead=t_dead, psi_r=0.0, J=1e4, B=0.0)
    rng = np.random.default_rng(7)
    p = Plant(s)
    i_ref = 0j
    worst, scale = 0.0, 1.0
    for _ in range(300):
        d = tuple(rng.uniform(0.2, 0.8, 3))
        segs = pwm_segments(p.config, d, phase(i_ref))
        i_ref, _, _ = exact_period(i_ref, 0.0, 0.0, segs, p.config)
        p.step(d)
        worst = max(worst, abs(p.i_s - i_ref))
        scale = max(scale, abs(i_ref))
    # Both sides are exact solutions of the same linear ODE evaluated in double
    # precision (expm is accurate to ~1e-15 relative per call); 300 periods of
    # accumulation with a contraction e^{-aT} < 1 keep the difference ~1e-13
    # relative. 1e-9 is far below any PWM modelling error (one misplaced edge
    # by 1 ns changes i by u_dc*1e-9/L ~ 2e-5 A).
    assert worst <= 1e-9 * scale


def test_rotating_carrier_pwm_one_period_and_torque():
    # Spinning rotor (n = 1000 r/min) with EMF, dead time, carrier PWM. Each
    # period is compared with the exact constant-speed solution started from
    # the plant's state (i, theta, w_M at the period start). J = 1e4 bounds the
    # speed change within a period by |T_e| T / J <= 24*1e-4/1e4 = 2.4e-7 rad/s
    # (|i| <= 10 A); the plant holds the mid-period speed, so the two EMF
    # magnitudes differ by <= n_p psi * 1.2e-7 = 1.9e-7 V, a current difference
    # <= T/L * 1.9e-7 = 8e-10 A, i.e. ~1e-10 of the ~8 A current (the angle
    # difference, <= 5e-7 * T = 5e-11 rad, is smaller still). Tolerance 1e-9 of
    # the current scale; a one-edge error of 1 ns would be 2e-5 A.
    s = vary(SPMSM, pwm="carrier", t_dead=2e-6, J=1e4, B=0.0, w_M0=1000.0 * RPM, theta_r0=0.3)
    m, T = s.motor, s.T_sp
    Kt = 1.5 * m.n_p * m.psi_r
    p = Plant(s)
    worst_i = worst_T = 0.0
    for _ in range(200):
        i0, th0, w = p.i_s, p.theta_r, m.n_p * p.w_M
        # voltage = EMF + 8 A along q through R (approx. a current-controlled run)
        u = 1j * w * m.psi_r * cmath.exp(1j * th0) + (m.R_s + 1j * w * m.L_s) * 8j * cmath.exp(
            1j * th0
        )
        d = duties_for(u, s.inverter.u_dc)
        segs = pwm_segments(p.config, d, phase(i0))
        i1, _, Q = exact_period(i0, th0, w, segs, p.config)
        p.step(d)
        worst_i = max(worst_i, abs(p.i_s - i1) / max(1.0, abs(i1)))
        worst_T = max(worst_T, abs(p.T_e_mean - Kt * Q.imag / T) / (Kt * max(1.0, abs(i1))))
    assert worst_i <= 1e-9
    assert worst_T <= 1e-9


# -------------------------------------------- 3. sinusoidal steady state, avg --


def test_sinusoidal_steady_state_averaged_exact_discrete():
    """Rotating voltage u_k = U e^{j w (k + 1/2) T} held over period k (the
    averaged mode's zero-order hold, sampled mid-period), rotor angle
    theta(t) = theta0 + w t. With i_k = I e^{j w k T} the exact period map
      i_{k+1} = e^{-aT} i_k + (1/L)[u_k T phi1(aT) - j w psi e^{j theta_k} G1],
      G1 = int_0^T e^{-a(T-s)} e^{j w s} ds = (e^{jwT} - e^{-aT}) / (a + jw)
    gives
      I = U e^{jwT/2} (1 - e^{-aT}) / (R (e^{jwT} - e^{-aT}))
          - j w psi e^{j theta0} / (R + j w L),
    (the EMF term is the continuous phasor exactly, the voltage term tends to
    U / (R + jwL) as T -> 0), and from i_0 = 0 the transient is exactly
    i_k = I e^{jwkT} - I e^{-akT} (the error obeys x_{k+1} = e^{-aT} x_k)."""
    th0 = 0.3
    s = vary(SPMSM, J=1e4, B=0.0, w_M0=1000.0 * RPM, theta_r0=th0)
    m, T = s.motor, s.T_sp
    R, L, psi, a = m.R_s, m.L_s, m.psi_r, m.R_s / m.L_s
    w = m.n_p * 1000.0 * RPM
    # amplitude chosen for ~6 A at ~40 deg ahead of the q axis (any U works)
    U = (1j * w * psi + (R + 1j * w * L) * 6.0 * cmath.exp(1j * 2.3)) * cmath.exp(1j * th0)
    assert abs(U) < 0.5 * s.inverter.u_dc  # duties stay inside [0, 1]
    I = U * cmath.exp(1j * w * T / 2) * (1 - math.exp(-a * T)) / (
        R * (cmath.exp(1j * w * T) - math.exp(-a * T))
    ) - 1j * w * psi * cmath.exp(1j * th0) / (R + 1j * w * L)
    # sanity of the reference maths: the ZOH result differs from the continuous
    # phasor U/(R+jwL) only at O((wT)^2, (aT)^2) (mid-period sampling).
    I_cont = (U - 1j * w * psi * cmath.exp(1j * th0)) / (R + 1j * w * L)
    assert abs(I - I_cont) <= ((w * T) ** 2 + (a * T) ** 2) * abs(U) / R
    assert abs(I - I_cont) > 1e-7 * abs(I)  # ...but it is resolved by this test

    p = Plant(s)
    worst = 0.0
    for k in range(1500):
        uk = U * cmath.exp(1j * w * (k + 0.5) * T)
        # Feed the last period's mean torque back as load: by telescoping, the
        # speed then never departs from w_M0 by more than T max|T_e| / J =
        # 1e-4 * 15 / 1e4 = 1.5e-7 rad/s, a rotor-angle drift below
        # n_p * 1.5e-7 * 0.15 s = 9e-8 rad. That turns the EMF current
        # (|w psi / (R + jwL)| = 16.6 A) by 9e-8 rad: 1.5e-6 A = 2.5e-7 of |I|
        # (6 A). The rounding of 1500 steps is ~1e-13. Tolerance 1e-6 of |I|.
        p.step(duties_for(uk, s.inverter.u_dc), T_ext=p.T_e_mean)
        kk = k + 1
        ref = I * cmath.exp(1j * w * kk * T) - I * math.exp(-a * kk * T)
        worst = max(worst, abs(p.i_s - ref))
    assert worst <= 1e-6 * abs(I)
    assert abs(p.w_M - 1000.0 * RPM) <= 1e-6

    # steady-state mean torque: exact rotor-frame integral over one period
    # (the last step was period k = 1499, from t = 1499 T)
    thk = th0 + w * 1499 * T
    _, _, Q = exact_period(I * cmath.exp(1j * w * 1499 * T), thk, w,
                           [(T, U * cmath.exp(1j * w * 1499.5 * T))], p.config)
    Te_ref = 1.5 * m.n_p * psi * Q.imag / T
    # remaining transient e^{-a * 0.15} ~ 5e-7 of I plus the 1e-7 drift above
    assert abs(p.T_e_mean - Te_ref) <= 2e-6 * 1.5 * m.n_p * psi * abs(I)


# ------------------------------------------------------------ 4. energy -----


def test_energy_balance_accelerating_under_load():
    """Averaged mode, T = 2 us, 40 ms from standstill to ~45 rad/s against a
    constant load, a fan load and viscous friction. Each period the plant's
    voltage is constant (u_mean), so E_in = 1.5 int Re(u conj i) dt needs the
    trapezoid in i only; all other integrals are trapezoids of smooth sample
    sequences. Trapezoid error per period: T^3/12 |f''|. The largest curvature
    is that of i from the rotating EMF, |i''| <~ a|i'| + w_e^2 psi / L
    <= 96*1e3 + 200^2*0.4/0.02345 ~ 8e5 A/s^2 (w_e <= n_p*50 rad/s), which with
    |u| <= 110 V gives <= 1.5 * (2e-6)^3/12 * 110 * 8e5 = 1.8e-10 J per period,
    <= 3.5e-6 J over 20000 periods, i.e. <= 2e-7 of E_in (~20 J). The plant's
    own O(T^2) approximation (speed held at the predicted mid-period value)
    costs 0.125 T^2 max(T_e)^2 / J ~ 4e-8 J. So 1e-6 of E_in is a 5x margin
    over the worst-case bound, while any wrong factor (1.5, n_p, psi, a held
    load evaluated at the wrong instant) shows up at >= 1e-4."""
    k_fan = 2e-5
    T_ext = 1.0
    s = vary(SPMSM, T_sp=2e-6, B=0.002, J=0.012, k_fan=k_fan)
    m, T = s.motor, s.T_sp
    R, L, J, B = m.R_s, m.L_s, m.J, m.B
    p = Plant(s)
    n = 20000  # 40 ms
    i = np.empty(n + 1, complex)
    w = np.empty(n + 1)
    u = np.empty(n, complex)
    TL = np.empty(n)
    i[0], w[0] = p.i_s, p.w_M
    for k in range(n):
        # q-axis voltage, self-commutated from the rotor angle: accelerates
        V = 25.0 + m.n_p * m.psi_r * p.w_M  # 25 V over the EMF: i_q ~ 11 A
        uk = 1j * V * cmath.exp(1j * p.theta_r) - 5.0 * cmath.exp(1j * p.theta_r)
        TL[k] = T_ext + k_fan * p.w_M * abs(p.w_M)  # load as held by the plant
        p.step(duties_for(uk, s.inverter.u_dc), T_ext=T_ext)
        u[k] = p.u_mean
        i[k + 1], w[k + 1] = p.i_s, p.w_M
    assert np.max(np.abs(u)) < 0.5 * s.inverter.u_dc  # duties stayed in [0, 1]
    assert w[-1] > 30.0  # it really accelerated (to > 280 r/min)
    im = 0.5 * (i[1:] + i[:-1])
    E_in = 1.5 * T * np.sum((u * np.conj(im)).real)
    E_cu = 1.5 * R * T * np.sum(0.5 * (np.abs(i[1:]) ** 2 + np.abs(i[:-1]) ** 2))
    E_mag = 0.75 * L * (abs(i[-1]) ** 2 - abs(i[0]) ** 2)
    E_kin = 0.5 * J * (w[-1] ** 2 - w[0] ** 2)
    E_load = T * np.sum(TL * 0.5 * (w[1:] + w[:-1]))
    E_fric = B * T * np.sum(0.5 * (w[1:] ** 2 + w[:-1] ** 2))
    out = E_cu + E_mag + E_kin + E_load + E_fric
    assert E_kin > 0.5 and E_load > 0.1  # every term is significant
    assert abs(E_in - out) <= 1e-6 * E_in, (E_in, E_cu, E_mag, E_kin, E_load, E_fric)


# ---------------------------------------------------------- 5. mechanics -----


def test_viscous_decay_exact():
    # psi_r = 0 and zero duties' vector: i stays 0, T_e = 0, so
    # J dw/dt = -B w -> w = w0 e^{-B t / J}, theta = n_p w0 J/B (1 - e^{-Bt/J}).
    # The plant integrates this linear ODE exactly per period; only rounding
    # remains (~2000 * 1 ulp ~ 5e-13 relative) -> 1e-11.
    s = vary(SPMSM, T_sp=1e-3, psi_r=0.0, J=0.012, B=0.002, w_M0=1500.0 * RPM)
    m = s.motor
    w0 = 1500.0 * RPM
    p = Plant(s)
    for k in range(1, 2001):  # 2 s = 0.33 J/B
        p.step((0.5, 0.5, 0.5))
        t = k * s.T_sp
        assert p.i_s == 0
        assert abs(p.w_M - w0 * math.exp(-m.B * t / m.J)) <= 1e-11 * w0
    th = m.n_p * w0 * m.J / m.B * (1 - math.exp(-m.B * t / m.J))
    # the angle is ~5000 rad before wrapping: rounding ~ 5000 * 2000 ulp ~ 2e-9
    assert abs(wrap(p.theta_r - th)) <= 1e-8


@pytest.mark.parametrize(
    "J, T_brake, eps",
    [
        # r = T T_brake / (J eps): speed step of the held brake torque per
        # period, relative to the taper width
        (0.012, 5.0, 1.0),  # r = 0.042: default motor, default taper
        (1e-3, 15.0, 1.0),  # r = 1.5: overshoots into the taper, still decays
        (0.012, 15.0, 0.01),  # r = 12.5: default motor, rated-torque brake, eps = 0.01
    ],
)
def test_brake_constant_deceleration_and_taper(J, T_brake, eps):
    """Constant brake torque T_b opposing rotation, B = 0, no current. Above
    w_brake_eps the deceleration is exactly T_b / J; inside +-eps the torque
    tapers linearly to 0 at standstill, so the speed must come to rest without
    reversing by more than eps (no sign chattering beyond w_brake_eps)."""
    T = 1e-4
    w0 = 22.3
    s = vary(SPMSM, T_sp=T, psi_r=0.0, J=J, B=0.0, w_M0=w0, w_brake_eps=eps)
    p = Plant(s)
    ws = [p.w_M]
    for _ in range(3000):
        w_prev = p.w_M
        p.step((0.5, 0.5, 0.5), 0.0, T_brake)
        ws.append(p.w_M)
        if w_prev >= eps and p.w_M >= eps:
            # outside the taper band for the whole period: torque -T_b, exact
            # linear decrease (a period entering the band is split there)
            # (rounding of one subtraction, 1e-12 relative to w0)
            assert abs((w_prev - p.w_M) - T_brake * T / J) <= 1e-12 * w0
    ws = np.array(ws)
    assert ws.min() >= -eps, f"speed reversed to {ws.min():.3g} rad/s (eps = {eps})"
    assert np.max(np.abs(ws[-100:])) <= 1e-3 * eps, f"no rest: last |w| {np.abs(ws[-4:])}"


# ------------------------------------------------------ 6. PWM spectrum ------


def test_regular_sampled_pwm_spectrum_yao2022_table1():
    """smodrive.analysis.pwm: the exact Fourier integrals of the pulses the
    plant's own edge function (leg_edges) produces, duties sampled at the
    carrier peaks, against yao2022 Table I and against the Jacobi-Anger
    (Bessel) series of symmetric regular sampling: pulse k centred at
    (k + 1/2) T_s of width d_k T_s has the n-th harmonic
    (2 V_Q / (T_e n w_e)) sum_k e^{-jnw_e c_k} 2 sin(beta (1 + M cos phi_k)),
    beta = n pi / (2N); Jacobi-Anger and sum_k e^{j2pi(m-n)k/N} = N [m = n
    mod N] leave the terms m = n + lN: l = 0 is Holmes & McGrath's baseband
    term, l != 0 the carrier sidebands that alias onto n w_e."""
    V_Q, M, N = 60.0, 0.9, 12
    amps = leg_harmonics_from_edges(V_Q, M, N, 5, T=1.0 / 20e3, t_dead=0.0)
    table = ["26.723", "0.4097", "0.1288", "0.0073", "0.0013"]  # yao2022 Table I, V
    for a, txt in zip(amps, table):
        # the paper prints the value rounded to its last shown decimal: the true
        # value lies within half a unit of that decimal (+ 1e-12 V of rounding
        # in the 12-pulse sum).
        half_unit = 0.5 * 10.0 ** (-len(txt.split(".")[1]))
        assert abs(a - float(txt)) <= half_unit + 1e-12, (a, txt)
    # Analytic Bessel series: the sidebands beyond |l| = 3 are below
    # J_37(0.6) ~ 1e-70; both sides are then exact up to rounding of a few
    # dozen terms -> 1e-12 relative.
    bes = leg_harmonics_bessel(V_Q, M, N, 5, l_max=3)
    np.testing.assert_allclose(amps, bes, rtol=1e-12, atol=1e-12 * V_Q)
    # fundamental: ideal M V_Q / 2 reduced by the sampling, 27 -> 26.72
    assert abs(amps[0] - M * V_Q / 2) > 0.2


# ---------------------------------------------------------- 7. dead time -----


@pytest.mark.parametrize("pwm", ["averaged", "carrier"])
@pytest.mark.parametrize("angle", [0.4, 2.0, -2.5])
def test_dead_time_mean_voltage_loss(pwm, angle):
    """Each leg loses t_dead/T of its duty when its current is positive and
    gains it when negative (the diode of the current direction conducts during
    the dead time), so
      u_mean = u_ideal - (2/3) u_dc (t_dead / T) sum_x sign(i_x) a^x.
    Duties stay in [0.3, 0.7] so that no edge is clipped at the period end.
    Both forms are a handful of double operations: 1e-12 u_dc."""
    t_dead = 2e-6
    s = vary(SPMSM, pwm=pwm, t_dead=t_dead, psi_r=0.0, J=1e4)
    u_dc, T = s.inverter.u_dc, s.T_sp
    ld = leg_dir(u_dc)
    p = Plant(s)
    d = duties_for(20.0 * cmath.exp(1j * angle), u_dc)
    assert all(0.3 <= x <= 0.7 for x in d)
    # first period: i = 0, so no dead-time shift at all
    p.step(d)
    assert abs(p.u_mean - complex(ld @ np.array(d))) <= 1e-12 * u_dc
    for _ in range(20):
        i_x = phase(p.i_s)  # current at the start of the period
        assert np.all(np.abs(i_x) > 1e-3)  # signs are well defined
        p.step(d)
        ref = complex(ld @ np.array(d)) - 2.0 / 3.0 * u_dc * t_dead / T * complex(
            np.sum(np.sign(i_x) * np.array([A**x for x in range(3)]))
        )
        assert abs(p.u_mean - ref) <= 1e-12 * u_dc
    # the loss has the size (2/3) u_dc t_dead/T * |sum sign a^x| = 4/3 * 10.8 V
    assert abs(complex(ld @ np.array(d)) - p.u_mean) == pytest.approx(
        4.0 / 3.0 * u_dc * t_dead / T, rel=1e-12
    )


# ----------------------------------------------------------------- 8. ADC ----


def test_adc_gain_offset_per_phase_exact():
    gain, offset = (1.03, 0.97, 1.11), (0.05, -0.2, 0.7)
    s = vary(SPMSM, psi_r=0.0, J=1e4, gain=gain, offset=offset)
    p = Plant(s)
    for _ in range(30):
        p.step((0.6, 0.45, 0.47))
    i_x = phase(p.i_s)
    assert np.min(np.abs(i_x)) > 0.5
    # one multiply-add per phase: a few ulp of ~10 A
    np.testing.assert_allclose(p.sample(), np.array(gain) * i_x + np.array(offset),
                               rtol=0, atol=1e-13)


def test_adc_quantisation_mid_tread_and_clamp():
    """bits = 4, full scale 10 A: lsb = 2 * 10 / 2^4 = 1.25 A, codes
    -8 .. 7 (two's complement range -FS .. FS - lsb), mid-tread (0 A is a
    code). The plant's current is 0 before the first step, so the offsets
    are the ADC inputs."""
    FS, bits = 10.0, 4
    lsb = 2 * FS / 2**bits
    assert lsb == 1.25
    cases = {  # input -> expected output
        0.0: 0.0, 0.3: 0.0, -0.6: 0.0, 0.7: 1.25, -0.7: -1.25, 1.8: 1.25, 1.9: 2.5,
        8.6: 8.75, 9.5: 8.75, 25.0: 8.75, -9.9: -10.0, -10.6: -10.0, -300.0: -10.0,
    }
    vals = list(cases)
    for j in range(0, len(vals), 3):
        chunk = (vals[j:j + 3] + [0.0, 0.0])[:3]
        s = vary(SPMSM, offset=tuple(chunk), bits=bits, full_scale=FS)
        got = Plant(s).sample()
        assert list(got) == [cases[v] for v in chunk], (chunk, got)
    # property over many inputs: output on the code grid, |error| <= lsb/2 inside range
    rng = np.random.default_rng(3)
    v = rng.uniform(-FS, FS - lsb, 300)
    for j in range(0, 300, 3):
        s = vary(SPMSM, offset=tuple(v[j:j + 3]), bits=bits, full_scale=FS)
        got = Plant(s).sample()
        assert np.all(np.abs(got - v[j:j + 3]) <= lsb / 2 + 1e-12)
        assert np.all(got / lsb == np.round(got / lsb))


def test_adc_noise_statistics_and_seed():
    sigma = 0.1
    s = vary(SPMSM, noise=sigma, seed=42)
    p = Plant(s)  # current 0: samples are pure noise
    x = np.array([p.sample() for _ in range(20000)]).ravel()
    n = x.size
    # (n-1) S^2 / sigma^2 ~ chi2(n-1): two-sided 1e-6 acceptance region (the
    # sequence is deterministic, so this is a once-and-for-all check that the
    # generator has the requested variance; a false alarm has probability 1e-6).
    stat = (n - 1) * np.var(x, ddof=1) / sigma**2
    assert chi2.ppf(0.5e-6, n - 1) <= stat <= chi2.ppf(1 - 0.5e-6, n - 1)
    # mean: N(0, sigma^2/n), 5 sigma (p ~ 6e-7)
    assert abs(x.mean()) <= 5 * sigma / math.sqrt(n)
    # lag-1 correlation of white noise ~ N(0, 1/n), 5 sigma
    assert abs(np.corrcoef(x[1:], x[:-1])[0, 1]) <= 5 / math.sqrt(n)
    # same seed, same sequence; another seed, another sequence
    p1, p2, p3 = Plant(s), Plant(s), Plant(vary(s, seed=43))
    a = np.array([p1.sample() for _ in range(50)])
    b = np.array([p2.sample() for _ in range(50)])
    c = np.array([p3.sample() for _ in range(50)])
    assert np.array_equal(a, b)
    assert np.all(a != c)
