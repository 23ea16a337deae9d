"""Properties of the yao2022 offline observer design (src/smodrive/design).

Every tolerance is argued in the test that uses it; "round-off" tolerances are
a few hundred double epsilons times the size of the numbers involved, since
each check is a handful of dense 8x8 products and one inverse of a
well-conditioned matrix (cond(T_r) < 10, checked).
"""

from __future__ import annotations

import dataclasses
import math
import re
import shutil
import subprocess

import control
import numpy as np
import pytest
import scipy.integrate

from smodrive.design import yao2022 as y
from smodrive.design.cheader import REALTIME_FIELDS, write_c_header
from smodrive.model import LclFilterPars, ParameterError
from smodrive.scenarios.yao2022 import BASE

PLANT = y.DesignPlant(BASE.motor, BASE.lcl, BASE.T_sp)  # Table II
DESIGN = y.ObserverDesignPars()
T = PLANT.T_sp
SPEEDS_TEST_RPM = (0.0, 30e3, 60e3, 100e3, 110e3, -60e3)
EPS = np.finfo(float).eps


def w_of(n_rpm: float) -> float:
    return float(y.rpm_to_w(n_rpm, PLANT.motor.n_p))


@pytest.fixture(scope="module")
def tables() -> y.DesignTables:
    return y.design_tables(PLANT)


# --------------------------------------------------------------------------- parameters


def test_table_ii_resonance_frequency_is_5525_hz_within_0p1_percent() -> None:
    assert PLANT.L2 == pytest.approx(51.5e-6, rel=1e-12)
    assert abs(PLANT.f_res() / 5525.0 - 1.0) < 1e-3


def test_parameters_are_validated() -> None:
    with pytest.raises(ParameterError, match=r"^lcl\.C1 = -1\.0 "):
        y.DesignPlant(BASE.motor, LclFilterPars(C1=-1.0), T)
    with pytest.raises(ParameterError, match=r"^ObserverDesignPars\.p_L = "):
        y.ObserverDesignPars(p_L=(1.2, 0.3))
    with pytest.raises(ParameterError, match=r"^PllPars\.k_theta = 0\.0 "):
        y.PllPars(k_theta=0.0)


def _motor(**kw):
    return dataclasses.replace(PLANT, motor=dataclasses.replace(PLANT.motor, **kw))


@pytest.mark.parametrize("bad,field", [
    (lambda: dataclasses.replace(PLANT, lcl=dataclasses.replace(PLANT.lcl, C1=0.0)), "lcl.C1"),
    (lambda: _motor(n_p=1.5), "motor.n_p"),
    (lambda: _motor(R_s=-0.023), "motor.R_s"),
    (lambda: dataclasses.replace(PLANT, T_sp=0.0), "plant.T_sp"),
    (lambda: dataclasses.replace(PLANT, T_sp=math.nan), "plant.T_sp"),
    (lambda: y.DesignPlant(PLANT.lcl, PLANT.motor, T), "plant.motor"),
    (lambda: y.DesignPlant(PLANT.motor, None, T), "plant.lcl"),
    (lambda: y.design_tables(PLANT.motor), "plant"),
])
def test_a_bad_physical_value_raises_parameter_error_naming_the_field(bad, field) -> None:
    """The design takes the project's own MotorPars and LclFilterPars: a bad
    value (C1 <= 0, a fractional pole-pair count, R_s < 0, T_sp outside its
    range, a wrong class) raises ParameterError whose message starts with the
    field's name, before anything is designed."""
    with pytest.raises(ParameterError) as exc:
        bad()
    assert str(exc.value).startswith(f"{field} = "), str(exc.value)


def test_the_yao2022_preset_is_table_ii() -> None:
    """The design plant is the preset's MotorPars and LclFilterPars (one
    description of the physics); their values are Table II exactly."""
    assert (PLANT.motor.R_s, PLANT.motor.L_s, PLANT.motor.n_p) == (0.023, 24e-6, 1)
    assert (PLANT.lcl.L1, PLANT.lcl.L2o, PLANT.lcl.C1, T) == (54e-6, 27.5e-6, 31.48e-6, 50e-6)


# --------------------------------------------------------------------------- model (1)-(7)


def test_lossless_lc_block_conserves_energy_kcl_sign() -> None:
    """The LCL part stores energy u'C u/2 + i'L i/2 and only R_s dissipates
    it: E A + A' E = -2 R_s diag(0, 0, I) with E = diag(C1, L1, L2) on the
    6x6 block (with R_s = 0 the LC part conserves energy, E A + A' E = 0).
    The printed sign of eq. (2)'s first row (du_c/dt = -i_1/C + i_2/C1)
    breaks this (erratum 1). Exact up to round-off of entries ~1/L ~ 2e4."""
    A, _ = y.continuous_model(PLANT, 0.0)
    E = np.kron(np.diag([PLANT.lcl.C1, PLANT.lcl.L1, PLANT.L2]), np.eye(2))
    D = np.kron(np.diag([0.0, 0.0, -2.0 * PLANT.motor.R_s]), np.eye(2))
    A6 = A[:6, :6]
    assert np.abs(E @ A6 + A6.T @ E - D).max() < 1e-12
    printed = A6.copy()
    printed[0:2, 2:4] *= -1.0
    printed[0:2, 4:6] *= -1.0
    assert np.abs(E @ printed + printed.T @ E).max() > 1.0


@pytest.mark.parametrize("n_rpm", [0.0, 100e3])
def test_zoh_matches_ode_integration(n_rpm: float) -> None:
    """Eq. (4): G_s, H_s from the augmented matrix exponential equal the ODE
    solution over one sample with a held input (DOP853, rtol 1e-12); the
    states are O(1) per unit input, so 1e-9 is the integrator's accuracy
    with three decades of margin."""
    w = w_of(n_rpm)
    A, B = y.continuous_model(PLANT, w)
    G_s, H_s = y.zoh(A, B, T)
    rng = np.random.default_rng(1)
    x0 = rng.normal(size=8)
    u = rng.normal(size=2)
    sol = scipy.integrate.solve_ivp(lambda t, x: A @ x + B @ u, (0.0, T), x0, method="DOP853",
                                    rtol=1e-12, atol=1e-14)
    assert np.abs(sol.y[:, -1] - (G_s @ x0 + H_s @ u)).max() < 1e-9 * np.abs(x0).max()


@pytest.mark.parametrize("n_rpm", SPEEDS_TEST_RPM)
def test_rotor_frame_model_equals_rotated_stationary_simulation(n_rpm: float) -> None:
    """Eq. (5)-(7) against a direct simulation: run the stationary-frame ZOH
    model (4) with u_s(k) = e^{J theta_k} u_gd(k) and the true EMF, and rotate
    its states into the frame theta_k = theta_0 + k w T. Both are exact
    discretisations; they agree to round-off accumulated over 40 steps of a
    model with |eig| < 1 (1e-10 relative)."""
    w = w_of(n_rpm)
    G, H, F = y.rotor_frame_model(PLANT, w)
    G_s, H_s = y.stationary_model(PLANT, w)
    rng = np.random.default_rng(2)
    theta0 = 0.7
    x_s = rng.normal(size=8)
    x = y.rot(-theta0, 4) @ x_s
    for k in range(40):
        theta_k = theta0 + k * w * T
        u_gd = rng.normal(size=2)
        e_gd = y.rot(-theta_k) @ x_s[6:8]
        x6 = G @ x[:6] + H @ u_gd + F @ e_gd
        x_s = G_s @ x_s + H_s @ (y.rot(theta_k) @ u_gd)
        x_ref = y.rot(-(theta_k + w * T), 4) @ x_s
        assert np.abs(x6 - x_ref[:6]).max() < 1e-10 * np.abs(x_s).max()
        x = x_ref


def test_emf_is_constant_in_the_synchronous_frame() -> None:
    """The EMF block of G_s is e^{J w T}: rotated by the frame advance w T
    it is the identity (round-off of a 2x2 expm, 1e-13)."""
    w = w_of(100e3)
    G_s, _ = y.stationary_model(PLANT, w)
    assert np.abs(y.rot(-w * T) @ G_s[6:8, 6:8] - np.eye(2)).max() < 1e-13


# --------------------------------------------------------------------------- canonical form (13)-(15)


@pytest.mark.parametrize("n_rpm", SPEEDS_TEST_RPM)
def test_canonical_form_structure(n_rpm: float) -> None:
    """T_r F = [0; 0; B], B invertible, F_t = flipud(Q') with Q a full QR
    factor of F2 (orthogonal, Q' F2 upper triangular with R11, R22 > 0),
    T_r invertible, and T_r maps the error dynamics (11) onto (13).
    |det B| = R11 R22 = sigma_1 sigma_2 of F2, and F2' F2 is a multiple of
    I (its blocks are a I + b J), so |det B| = ||F2||^2: > 0.1 ||F2||^2.
    Round-off: entries O(1), cond(T_r) < 10, so 1e-12."""
    G, _, F = y.rotor_frame_model(PLANT, w_of(n_rpm))
    cf = y.canonical_form(G, F)
    TF = cf.T_r @ F
    assert np.abs(TF[:4]).max() < 1e-12
    assert np.abs(TF[4:] - cf.B).max() == 0.0
    assert abs(np.linalg.det(cf.B)) > 0.1 * np.linalg.norm(F[2:], 2) ** 2
    Q = np.flipud(cf.F_t).T
    assert np.abs(Q.T @ Q - np.eye(4)).max() < 1e-14 * 10
    Rq = Q.T @ F[2:]
    assert np.abs(np.tril(Rq, -1)).max() < 1e-14 * 10
    assert Rq[0, 0] > 0 and Rq[1, 1] > 0
    assert np.linalg.cond(cf.T_r) < 10
    rng = np.random.default_rng(3)
    x, v = rng.normal(size=6), rng.normal(size=2)
    lhs = cf.T_r @ (G @ x + F @ v)
    rhs = cf.G_r6 @ (cf.T_r @ x) + np.concatenate([np.zeros(4), cf.B @ v])
    assert np.abs(lhs - rhs).max() < 1e-12 * 10


# --------------------------------------------------------------------------- sliding surface (16)-(25)


def _design(n_rpm: float) -> tuple[y.CanonicalForm, y.SlidingSurface]:
    G, _, F = y.rotor_frame_model(PLANT, w_of(n_rpm))
    cf = y.canonical_form(G, F)
    return cf, y.sliding_surface(cf, DESIGN.p_L, DESIGN.p_u)


@pytest.mark.parametrize("n_rpm", SPEEDS_TEST_RPM)
def test_step2_places_the_reduced_order_observer_and_the_printed_pair_does_not(n_rpm: float) -> None:
    """eig(G11 + L G21) = p_L (the Proposition's requirement). Double poles of
    a diagonalisable 2x2 are computed to ~eps*|G| (1e-9 leaves margin). The
    printed step-2 pair (G11, -G12) gives another L whose G11 + L G21 is off
    by > 1e-3 (erratum 2)."""
    cf, ss = _design(n_rpm)
    assert np.abs(np.sort(np.linalg.eigvals(ss.H_c).real) - np.sort(DESIGN.p_L)).max() < 1e-9
    assert np.abs(np.linalg.eigvals(ss.H_c).imag).max() < 1e-9
    L_printed = y.place(cf.G11, -cf.G12, DESIGN.p_L)
    ev = np.sort_complex(np.linalg.eigvals(cf.G11 + L_printed @ cf.G21))
    assert np.abs(ev - np.sort(DESIGN.p_L)).max() > 1e-3


@pytest.mark.parametrize("n_rpm", SPEEDS_TEST_RPM)
def test_sliding_mode_matrix_has_exactly_the_requested_poles(n_rpm: float) -> None:
    """Proposition (21): eig(G_sm) = [p_L, p_u] to 1e-9, and the
    characteristic polynomial (well conditioned also for repeated roots)
    matches to 1e-12 (coefficients O(10), round-off of a 6x6 Hessenberg)."""
    _, ss = _design(n_rpm)
    p = np.concatenate([DESIGN.p_L, DESIGN.p_u])
    ev = np.linalg.eigvals(ss.G_sm)
    assert np.abs(ev.imag).max() < 1e-9
    assert np.abs(np.sort(ev.real) - np.sort(p)).max() < 1e-9
    assert np.abs(np.poly(ss.G_sm) - np.poly(p)).max() < 1e-12


def test_switching_function_matrices_are_consistent() -> None:
    """Gamma_2^{-1} = B (below (18)); M_c = Gamma_2^{-1} Gamma_c and
    M_y = Gamma_2^{-1} Gamma_1 (19); (21) for M_y, M_c."""
    cf, ss = _design(100e3)
    assert np.abs(ss.Gamma_2 @ cf.B - np.eye(2)).max() < 1e-14 * 10
    assert np.abs(cf.B @ ss.Gamma_c - ss.M_c).max() < 1e-13
    assert np.abs(cf.B @ ss.Gamma_1 - ss.M_y).max() < 1e-13
    assert np.abs(ss.M_y - (ss.K2 - ss.K1 @ ss.L)).max() == 0.0


@pytest.mark.parametrize("n_rpm", [30e3, 100e3])
def test_sliding_motion_of_the_augmented_system_follows_g_sm(n_rpm: float) -> None:
    """Run (17) with the equivalent input that keeps s = 0 (eq. (28) with
    s(k+1) = 0) from a state on the surface (19); the reduced state
    [x_c, x_u, y_1] follows x_sm(k+1) = G_sm x_sm (20). Both decay with
    |p| <= 0.5; round-off relative to the initial state, 1e-11."""
    cf, ss = _design(n_rpm)
    rm = y.reaching_mode(cf, ss)
    G_r, F_r = y.augmented_matrix(cf, ss)
    rng = np.random.default_rng(4)
    x_sm = rng.normal(size=6)
    x_r = np.concatenate([x_sm, -ss.M_c @ x_sm[0:2] - ss.M_y @ x_sm[4:6]])
    scale = np.abs(x_r).max()
    for _ in range(15):
        v = -(rm.G_c @ x_r[0:2] + rm.G_u @ x_r[2:4] + rm.G_y @ x_r[4:6])
        x_r = G_r @ x_r + F_r @ v
        x_sm = ss.G_sm @ x_sm
        s = ss.Gamma_c @ x_r[0:2] + ss.Gamma_1 @ x_r[4:6] + ss.Gamma_2 @ x_r[6:8]
        assert np.abs(s).max() < 1e-11 * scale
        assert np.abs(x_r[:6] - x_sm).max() < 1e-11 * scale


# --------------------------------------------------------------------------- reaching mode (26)-(28)


@pytest.mark.parametrize("n_rpm", SPEEDS_TEST_RPM)
def test_reaching_mode_identity_for_random_states(n_rpm: float) -> None:
    """s(k+1) = G_s s + G_c x_c + G_y y1 + G_u x_u + (w - e) (28) holds for
    any state and input of (17); T_y F_r = [0; 0; 0; I]. Round-off, 1e-12."""
    cf, ss = _design(n_rpm)
    rm = y.reaching_mode(cf, ss)
    G_r, F_r = y.augmented_matrix(cf, ss)
    TF = rm.T_y @ F_r
    assert np.abs(TF - np.vstack([np.zeros((6, 2)), np.eye(2)])).max() < 1e-14 * 10
    rng = np.random.default_rng(5)
    for _ in range(20):
        x_r, v = rng.normal(size=8), rng.normal(size=2)
        x_c, x_u, y1, y2 = x_r[0:2], x_r[2:4], x_r[4:6], x_r[6:8]
        s = ss.Gamma_c @ x_c + ss.Gamma_1 @ y1 + ss.Gamma_2 @ y2
        x_n = G_r @ x_r + F_r @ v
        s_n = ss.Gamma_c @ x_n[0:2] + ss.Gamma_1 @ x_n[4:6] + ss.Gamma_2 @ x_n[6:8]
        pred = rm.G_s @ s + rm.G_c @ x_c + rm.G_y @ y1 + rm.G_u @ x_u + v
        assert np.abs(s_n - pred).max() < 1e-12 * 10


# --------------------------------------------------------------------------- band-pass (45)-(46)


@pytest.mark.parametrize("n_rpm,h", [(30e3, 2), (30e3, 3), (100e3, 2), (100e3, 3), (110e3, 3)])
def test_bandpass_centre_and_bandwidth(n_rpm: float, h: int) -> None:
    """Unity gain, zero phase at w_n (1e-12: the real part of the
    denominator is exactly zero there). |G| = 1/sqrt 2 at the exact edges
    arccos(cos w_nT cos(OmegaT/2)) +- OmegaT/2 (1e-12), which are exactly
    Omega apart. At the naive edges w_n +- Omega/2 the gain is off by at most
    |delta| max|d|G|/dw| <= |delta| / Omega (a second-order band-pass has
    max |d|G|/dw| = 0.77/Omega; 1/Omega covers the bilinear warping), delta
    being the warping shift of the band centre (sign of cot(w_n T); zero
    where w_n T = pi/2, e.g. 3 f_e at 100 kr/min)."""
    w = w_of(n_rpm)
    w_n = h * w
    Omega = 2.0 * math.pi * DESIGN.bw_rel_2 * w / (2.0 * math.pi)
    a1, a2 = y.bandpass_coefficients(w_n, Omega, T)
    g0 = complex(y.bandpass_response(a1, a2, w_n, T))
    assert abs(g0 - 1.0) < 1e-12
    lo, hi = y.bandpass_edges(w_n, Omega, T)
    assert hi - lo == pytest.approx(Omega, rel=1e-12)
    for we in (lo, hi):
        assert abs(abs(complex(y.bandpass_response(a1, a2, we, T))) - 1.0 / math.sqrt(2.0)) < 1e-12
    delta = 0.5 * (lo + hi) - w_n
    assert delta * math.cos(w_n * T) >= 0.0
    for we in (w_n - Omega / 2.0, w_n + Omega / 2.0):
        g = abs(complex(y.bandpass_response(a1, a2, we, T)))
        assert abs(g - 1.0 / math.sqrt(2.0)) <= abs(delta) / Omega + 1e-12
    # the filter removes DC (the EMF) completely
    assert abs(complex(y.bandpass_response(a1, a2, 0.0, T))) < 1e-15


# --------------------------------------------------------------------------- EMF adaption gain (51), (63)


@pytest.mark.parametrize("n_rpm", [30e3, 60e3, 100e3])
@pytest.mark.parametrize("phi", [0.1, 0.3])
def test_emf_lowpass_attenuation_at_2fe(n_rpm: float, phi: float) -> None:
    """With k from (51), the discrete low-pass k/(z - 1 + k) has gain g at
    2 f_e with 1 <= g/phi <= 1/sqrt(1 - (1 - phi^2) eps), eps = k + theta^2/12,
    theta = 2 pi 2 f_e T: exact |e^{j theta} - 1 + k|^2 = k^2 + rho theta^2
    with 1 - eps <= rho = (1 - k) sinc^2(theta/2) <= 1. The closed-form gain
    equals the python-control TF (1e-12); the exact-inversion gain hits phi
    (1e-12); the printed (51) without 2 pi misses phi by more than a factor 2
    (erratum 3)."""
    f_e = n_rpm * PLANT.motor.n_p / 60.0
    k = y.emf_adaption_gain(f_e, phi, T)
    theta = 2.0 * math.pi * 2.0 * f_e * T
    g = float(y.emf_lowpass_gain(k, 2.0 * f_e, T))
    tf = control.tf([k], [1.0, k - 1.0], T)
    assert abs(g - abs(tf(np.exp(1j * theta)))) < 1e-12
    eps = k + theta**2 / 12.0
    assert 1.0 <= g / phi <= 1.0 / math.sqrt(1.0 - (1.0 - phi**2) * eps)
    k_x = y.emf_adaption_gain_exact(f_e, phi, T)
    assert abs(float(y.emf_lowpass_gain(k_x, 2.0 * f_e, T)) - phi) < 1e-12
    k_printed = 2.0 * f_e * math.sqrt(phi**2 / (1.0 - phi**2)) * T
    assert float(y.emf_lowpass_gain(k_printed, 2.0 * f_e, T)) < phi / 2.0


# --------------------------------------------------------------------------- PLL (48)-(50)


def _simulate_pll(pll: y.PllPars, theta_err: np.ndarray) -> np.ndarray:
    """Recursion (48), output theta_hat(k)."""
    th, om, a = 0.0, 0.0, 0.0
    out = np.empty_like(theta_err)
    for k, e in enumerate(theta_err):
        out[k] = th
        th, om, a = th + om * pll.T + pll.k_theta * e, om + a * pll.T + pll.k_omega * e, a + pll.k_a * e
    return out


def test_pll_transfer_function_is_the_z_transform_of_the_recursion() -> None:
    """G_PLL of (49) reproduces the impulse and step responses of (48).
    Both are simulations of a triple integrator: a round-off of eps |y| at
    step j grows like (n - j)^2/2 through it, so the two may differ by up to
    ~eps max|y| n^3/6; we allow eps max(1, |y|) n^3 (3e-9 for n = 100, while
    a wrong coefficient shows up at O(k_omega T) = 5e-4)."""
    pll = y.PllPars()
    g = y.pll_open_loop(pll)
    n = 100
    for u in (np.r_[1.0, np.zeros(n - 1)], np.ones(n)):
        ref = _simulate_pll(pll, u)
        resp = control.forced_response(g, T=np.arange(n) * T, U=u).outputs
        assert np.abs(ref - resp).max() < EPS * max(1.0, np.abs(ref).max()) * n**3


def test_pll_closed_loop_matches_the_loop_and_bandwidth() -> None:
    """Closed loop theta_err = theta - theta_hat around (48) equals
    G/(1 + G) (round-off through three poles near 1, bounded as in the open
    loop test by eps n^3). pll_bandwidth_hz is where |G/(1+G)| = 1/sqrt 2
    (1e-9). Near crossover G ~ k_theta/(z - 1) (the zeros of (49) sit at
    ~1 and ~99 rad/s, far below k_theta/T = 2000 rad/s), whose closed loop
    has its -3 dB point at f_1 = asin(k_theta / (2 sqrt(1 - k_theta))) / (pi T);
    the neglected terms are of relative size k_omega T / (k_theta w_c T) = 5 %,
    so |f_3dB / f_1 - 1| < 0.1."""
    pll = y.PllPars()
    n = 300
    theta = np.ones(n)
    th, om, a = 0.0, 0.0, 0.0
    ref = np.empty(n)
    for k in range(n):
        ref[k] = th
        e = theta[k] - th
        th, om, a = th + om * T + pll.k_theta * e, om + a * T + pll.k_omega * e, a + pll.k_a * e
    resp = control.forced_response(y.pll_closed_loop(pll), T=np.arange(n) * T, U=theta).outputs
    assert np.abs(ref - resp).max() < EPS * n**3
    f3 = y.pll_bandwidth_hz(pll)
    tcl = y.pll_closed_loop(pll)
    assert abs(abs(tcl(np.exp(2j * math.pi * f3 * T))) - 1.0 / math.sqrt(2.0)) < 1e-9
    f1 = math.asin(pll.k_theta / (2.0 * math.sqrt(1.0 - pll.k_theta))) / (math.pi * T)
    assert abs(f3 / f1 - 1.0) < 0.1


# --------------------------------------------------------------------------- tables


def test_table_shapes(tables: y.DesignTables) -> None:
    n = tables.speeds_rpm.size
    expect = {"G": (6, 6), "H": (6, 2), "F": (6, 2), "T_r": (6, 6), "B": (2, 2), "H_c": (2, 2),
              "D1": (2, 2), "D2": (2, 2), "Gamma_c": (2, 2), "Gamma_1": (2, 2), "Gamma_2": (2, 2),
              "G_s": (2, 2), "G_sm": (6, 6), "k": (), "a1_2": (), "N_2": (), "L_s": (4, 4),
              "Theta": (4, 4), "Theta_y": (4, 4), "Theta_u": (4, 2)}
    for name, shape in expect.items():
        assert getattr(tables, name).shape == (n,) + shape, name
    assert tables.speeds_rpm[0] == 0.0 and tables.speeds_rpm[-1] == 110e3


def test_every_table_point_has_the_requested_poles(tables: y.DesignTables) -> None:
    """Sliding mode (20) and linear observer (65) at every grid speed: the
    characteristic polynomials match the requested poles to 1e-12."""
    p_sm = np.poly(np.concatenate([DESIGN.p_L, DESIGN.p_u]))
    p_lin = np.poly(DESIGN.p_lin)
    for i in range(tables.speeds_rpm.size):
        assert np.abs(np.poly(tables.G_sm[i]) - p_sm).max() < 1e-12
        assert np.abs(np.poly(tables.Theta[i]) - p_lin).max() < 1e-12


def test_linear_interpolation_error_is_bounded_by_the_second_derivative(tables: y.DesignTables) -> None:
    """At the midpoint of [x_i, x_i+1] linear interpolation errs by exactly
    h^2/8 |f''(xi)|. The table's own second differences D = f''(eta) at
    nearby eta (within 2h) bound |f''| up to its variation over 2h; the
    fastest speed dependence is the frame rotation e^{-J w T} whose second
    derivative changes by ~2h T dw/dn ~ 1 % over that span, so a factor 2
    covers it; 1e-12 of the field's size absorbs round-off. Integer delays
    are excluded; the gain k is piecewise linear (checked separately)."""
    h = tables.speeds_rpm[1] - tables.speeds_rpm[0]
    n = tables.speeds_rpm.size
    for i in (0, 1, 7, 29, 54, 80, 99, n - 2):
        mid = 0.5 * (tables.speeds_rpm[i] + tables.speeds_rpm[i + 1])
        fresh = y.design_point(PLANT, w_of(mid), DESIGN)
        interp = y.interp_tables(tables, w_of(mid))
        lo, hi = max(i - 1, 0), min(i + 3, n)
        for name in y.MATRIX_FIELDS:
            a = getattr(tables, name)
            if a.dtype.kind in "iu" or name == "k":
                continue
            d2 = np.abs(np.diff(a[lo:hi], 2, axis=0)).max() / h**2
            bound = 2.0 * h**2 / 8.0 * d2 + 1e-12 * max(1.0, np.abs(a).max())
            err = np.abs(np.asarray(getattr(interp, name)) - np.asarray(getattr(fresh, name))).max()
            assert err <= bound, (name, mid, err, bound)
        # k = max(c |w|, k_min): exact where linear, else within slope * h / 4
        slope = np.abs(np.diff(tables.k)).max() / h
        assert abs(interp.k - fresh.k) <= slope * h / 4.0 + 1e-15


def test_grid_spacing_keeps_the_relative_interpolation_error_below_1e_4(tables: y.DesignTables) -> None:
    """Grid argument of docs/yao2022_design.md: with 1 kr/min steps the
    h^2/8 |f''| bound, relative to each field's size, stays below 1e-4
    everywhere (below ADC quantisation, 2^-12, and parameter tolerances)."""
    h = tables.speeds_rpm[1] - tables.speeds_rpm[0]
    for name in y.MATRIX_FIELDS:
        a = getattr(tables, name)
        if a.dtype.kind in "iu" or name == "k":
            continue
        d2 = np.abs(np.diff(a, 2, axis=0)).max() / h**2
        assert 2.0 * h**2 / 8.0 * d2 <= 1e-4 * max(np.abs(a).max(), 1e-300), name


def test_interp_rejects_speeds_outside_the_table(tables: y.DesignTables) -> None:
    with pytest.raises(ValueError):
        y.interp_tables(tables, -1.0)
    at_node = y.interp_tables(tables, float(tables.w[5]))
    assert np.array_equal(at_node.G, tables.G[5])


# --------------------------------------------------------------------------- C header


def _parse_array(text: str, ident: str) -> np.ndarray:
    m = re.search(rf"{ident}(\[[^=]*)=\s*(\{{.*?\}});", text, re.S)
    assert m is not None, ident
    nums = re.findall(r"[-+]?(?:\d+\.?\d*(?:[eE][-+]?\d+)?)", m.group(2).replace("f", ""))
    return np.array([float(v) for v in nums])


@pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc not installed")
def test_c_header_compiles_and_round_trips(tmp_path, tables: y.DesignTables) -> None:
    """The header compiles under gcc -std=c99 -Wall -Wextra -Werror (plus
    -pedantic -Wdouble-promotion of the firmware build), and every float is
    float(value) exactly, hence within 2^-24 relative of the double design
    (better than 7 significant digits, 5e-7)."""
    sub = y.design_tables(PLANT, tables.speeds_rpm[::10], DESIGN)
    hdr = write_c_header(sub, tmp_path / "yao_tables.h", "YAO")
    src = tmp_path / "use.c"
    src.write_text('#include "yao_tables.h"\n'
                   "float yao_g00(int i);\n"
                   "float yao_g00(int i) { return YAO_G[i][0][0] * YAO_speeds[i] + (float)YAO_N_2[i]; }\n")
    res = subprocess.run(["gcc", "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-Wdouble-promotion",
                          "-c", str(src), "-o", str(tmp_path / "use.o")], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    text = hdr.read_text()
    assert f"#define YAO_N {sub.speeds_rpm.size}" in text
    assert sub.plant is PLANT and f" * Plant: {PLANT.summary()}\n" in text
    arrays = {"speeds": sub.speeds_rpm, **{f: getattr(sub, f) for f in REALTIME_FIELDS}}
    for name, a in arrays.items():
        got = _parse_array(text, f"YAO_{name}")
        want = np.asarray(a, dtype=float).ravel()
        assert got.size == want.size, name
        if a.dtype.kind in "iu":
            assert np.array_equal(got, want), name
            continue
        assert np.array_equal(got.astype(np.float32), want.astype(np.float32)), name
        assert np.all(np.abs(got - want) <= 2.0**-24 * np.abs(want) + 1e-37), name


# --------------------------------------------------------------------------- errata evidence and model sanity


def test_discrete_model_modes_are_the_lcl_resonance_shifted_by_the_frame() -> None:
    """eig(G) = e^{-j w T} eig(G_s[0:6, 0:6]): in the rotor frame at
    100 kr/min the LCL resonance f_res appears at f_res -+ f_e, and the
    series mode has |z| = e^{-R_s T / (L1 + L2)}. R_s damping shifts the resonance
    by O((R_s / (w_r L2))^2) ~ 2e-4 relative, hence 1e-3."""
    w = w_of(100e3)
    G, _, _ = y.rotor_frame_model(PLANT, w)
    z = np.linalg.eigvals(G)
    f = np.sort(np.abs(np.angle(z))) / (2.0 * math.pi * T)
    f_e = w / (2.0 * math.pi)
    assert f[0:2] == pytest.approx([f_e, f_e], rel=1e-3)
    assert f[2:4] == pytest.approx([PLANT.f_res() - f_e] * 2, rel=1e-3)
    assert f[4:6] == pytest.approx([PLANT.f_res() + f_e] * 2, rel=1e-3)
    series = z[np.argsort(np.abs(np.angle(z)))[:2]]
    R_s, L1 = PLANT.motor.R_s, PLANT.lcl.L1
    assert np.abs(series) == pytest.approx([math.exp(-R_s * T / (L1 + PLANT.L2))] * 2, rel=1e-3)


@pytest.mark.parametrize("sign,converges", [(+1.0, False), (-1.0, True)])
def test_emf_adaption_sign_erratum(sign: float, converges: bool) -> None:
    """Reaching law (33) on the reaching dynamics (36) with d = 0: the
    adaption (34) as printed, e_hat(k) = e_hat(k-1) + k (s(k) - Q s(k-1)),
    has the loop root 1 + k (diverges); with the minus sign it is the
    low-pass of (39) with root 1 - k, and e_hat -> e. After 400 samples with
    k = 0.1 the error is 0.9^400 ~ 5e-19 of the step (1e-9 allowed)."""
    k, Q, e = 0.1, np.diag(DESIGN.Q), np.array([3.0, -1.0])
    s, e_hat = np.zeros(2), np.zeros(2)
    s_prev = s.copy()
    for _ in range(400):
        e_hat = e_hat + sign * k * (s - Q @ s_prev)
        s_prev = s
        s = Q @ s + e_hat - e  # eq. (36), d = d_hat = 0
    err = np.abs(e_hat - e).max()
    assert (err < 1e-9) if converges else (err > 1e6)
