"""Property tests of the C core blocks through the ctypes binding (float build).

Parameter validation: every parameter outside the range documented in
core/src/smd_status.c is rejected with the status code that names it, valid
sets are accepted and stored. Steps: finite inputs in a physically broad range
give finite outputs within the documented bounds.
"""

from __future__ import annotations

import ctypes as ct
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from smodrive.engine import _ffi as F
from smodrive.model import RPM, ControllerCfg, Profile, Scenario, yang2018_mode

lib = F.lib

SETTINGS = settings(max_examples=200, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])

# Status codes (core/include/smodrive/smd_types.h)
OK, ERR_NULL, ERR_TS, ERR_L, ERR_R, ERR_PSI = 0, 1, 2, 3, 4, 5
ERR_LAMBDA, ERR_L_GAIN, ERR_WC, ERR_RHO, ERR_KP, ERR_KI = 6, 7, 8, 9, 10, 11
ERR_LIMIT, ERR_MODE, ERR_STABILITY, ERR_WLPF, ERR_NONFINITE = 12, 13, 14, 15, 16
ERR_WHYS, ERR_WMAX, ERR_DMIN = 18, 19, 22

PI_F = float(np.float32(np.pi))  # SMD_PI in the float build (slightly above pi)
INF, NAN = math.inf, math.nan


def f32(x: float) -> float:
    with np.errstate(over="ignore"):
        return float(np.float32(x))


def next_up(x: float) -> float:
    return float(np.nextafter(np.float32(x), np.float32(np.inf)))


def next_down(x: float) -> float:
    return float(np.nextafter(np.float32(x), np.float32(-np.inf)))


def finite(*zs) -> bool:
    return all(math.isfinite(complex(z).real) and math.isfinite(complex(z).imag) for z in zs)


def C(z: complex) -> F.Cplx:
    return F.Cplx.of(z)


# --------------------------------------------------------------------------
# Documented ranges (smd_status_str): (name, lo, hi, lo_open, code)
# Every upper bound is closed except w_lpf's, which depends on T_sp and is
# handled separately.
DBPC = [
    ("T_sp", 0.0, 1.0, True, ERR_TS),
    ("L_s_hat", 0.0, 10.0, True, ERR_L),
    ("R_s_hat", 0.0, 1000.0, False, ERR_R),
    ("psi_r_hat", 0.0, 100.0, False, ERR_PSI),
]
SMDO = [
    ("T_sp", 0.0, 1.0, True, ERR_TS),
    ("L_s_hat", 0.0, 10.0, True, ERR_L),
    ("R_s_hat", 0.0, 1000.0, False, ERR_R),
    ("lambda_min", 0.0, 1e7, False, ERR_LAMBDA),
    ("l", 0.0, 1e7, True, ERR_L_GAIN),
    ("w_c", 0.0, 1e7, True, ERR_WC),
    ("rho", 0.0, 1000.0, True, ERR_RHO),
]
PI = [
    ("k_p", 0.0, 1e6, False, ERR_KP),
    ("k_i", 0.0, 1e9, False, ERR_KI),
    ("T_s", 0.0, 1.0, True, ERR_TS),
    ("y_max", 0.0, 1e9, True, ERR_LIMIT),
]
EMF = [  # w_lpf in (0, pi/T_sp), w_max in (w_hys, pi/T_sp]: upper bounds in own tests
    ("T_sp", 0.0, 1.0, True, ERR_TS),
    ("w_lpf", 0.0, INF, True, ERR_WLPF),
    ("w_hys", 0.0, 1e5, False, ERR_WHYS),
    ("w_max", 0.0, INF, True, ERR_WMAX),
]


def fl(lo: float, hi: float) -> st.SearchStrategy[float]:
    """float32 values in [lo, hi] (bounds rounded to float32)."""
    return st.floats(f32(lo), f32(hi), width=32)


def valid(lo: float, hi: float, lo_open: bool) -> st.SearchStrategy[float]:
    return st.floats(f32(lo), f32(hi), width=32, exclude_min=lo_open)


def invalid(lo: float, hi: float, lo_open: bool) -> st.SearchStrategy[float]:
    below = st.floats(max_value=f32(lo) if lo_open else next_down(lo), width=32,
                      allow_nan=False)
    parts = [below, st.just(NAN)]
    if math.isfinite(hi):
        parts.append(st.floats(min_value=next_up(hi), width=32, allow_nan=False))
    else:
        parts.append(st.just(INF))
    return st.one_of(*parts)


def sentinel(cls):
    """A struct with every field -1, to see whether init wrote to it."""
    return cls(*[-1 if typ is ct.c_int else -1.0 for _, typ in cls._fields_])


def dbpc_init(*args):
    p = sentinel(F.DbpcParams)
    return lib.smd_dbpc_init(ct.byref(p), *args), p


def smdo_init(*args):
    p = sentinel(F.SmdoParams)
    return lib.smd_smdo_init(ct.byref(p), *args), p


def pi_init(*args):
    p = sentinel(F.PiParams)
    return lib.smd_pi_init(ct.byref(p), *args), p


def emf_init(*args):
    p = sentinel(F.EmfPosParams)
    return lib.smd_emf_pos_init(ct.byref(p), *args), p


def emf_args(T_sp: float, w_lpf_frac: float, w_hys: float, w_max_frac: float = 0.5):
    """A valid emf_pos parameter set (T_sp, w_lpf, w_hys, w_max); w_lpf and
    w_max as fractions of pi/T_sp, w_hys reduced below w_max if needed."""
    w_max = w_max_frac * math.pi / T_sp
    return T_sp, w_lpf_frac * math.pi / T_sp, min(w_hys, 0.5 * w_max), w_max


INITS = {
    "dbpc": (dbpc_init, DBPC),
    "smdo": (smdo_init, SMDO),
    "pi": (pi_init, PI),
    "emf_pos": (emf_init, EMF),
}


def _valid_base(table, draw):
    return [draw(valid(lo, min(hi, 1e30), op)) for _, lo, hi, op, _ in table]


# ------------------------------------------------------------ init: ranges --

@pytest.mark.parametrize("block", list(INITS))
@SETTINGS
@given(data=st.data())
def test_init_rejects_each_out_of_range_parameter_with_its_code(block, data):
    init, table = INITS[block]
    args = _valid_base(table, data.draw)
    if block == "emf_pos":  # keep w_lpf below pi/T_sp (finite) for the base set
        args[0] = max(args[0], 1e-30)
        args = list(emf_args(args[0], data.draw(st.floats(1e-6, 0.999)), args[2],
                             data.draw(st.floats(1e-6, 1.0))))
    k = data.draw(st.integers(0, len(table) - 1))
    name, lo, hi, lo_open, code = table[k]
    bad = data.draw(invalid(lo, hi, lo_open))
    args[k] = bad
    rc, p = init(*args)
    assert rc == code, f"{block}: {name} = {bad!r} gave status {rc}, expected {code}"
    # a rejected set writes nothing
    assert all(getattr(p, f) == -1.0 for f, _ in p._fields_)


@pytest.mark.parametrize("block,k", [(b, k) for b, (_, t) in INITS.items()
                                     for k in range(len(t))])
@pytest.mark.parametrize("bad", [NAN, INF, -INF])
def test_init_rejects_nan_and_inf(block, k, bad):
    init, table = INITS[block]
    nominal = {"dbpc": [1e-4, 0.02, 2.0, 0.4],
               "smdo": [1e-4, 0.02, 2.0, 800.0, 1200.0, 1500.0, 0.2],
               "pi": [0.1, 10.0, 1e-4, 15.0],
               "emf_pos": [1e-4, 200.0, 5.0, 1000.0]}[block]
    assert init(*nominal)[0] == OK
    nominal[k] = bad
    assert init(*nominal)[0] == table[k][4]


def test_init_rejects_null_pointers():
    assert lib.smd_dbpc_init(None, 1e-4, 0.02, 2.0, 0.4) == ERR_NULL
    assert lib.smd_smdo_init(None, 1e-4, 0.02, 2.0, 800.0, 1200.0, 1500.0, 0.2) == ERR_NULL
    assert lib.smd_pi_init(None, 0.1, 10.0, 1e-4, 15.0) == ERR_NULL
    assert lib.smd_svm_init(None, 1, 0.0) == ERR_NULL
    assert lib.smd_emf_pos_init(None, 1e-4, 200.0, 5.0, 1000.0) == ERR_NULL


@SETTINGS
@given(data=st.data())
def test_dbpc_pi_init_accept_valid_and_store_them(data):
    args = _valid_base(DBPC, data.draw)
    rc, p = dbpc_init(*args)
    assert rc == OK
    assert [p.T_sp, p.L_s_hat, p.R_s_hat, p.psi_r_hat] == args
    args = _valid_base(PI, data.draw)
    rc, p = pi_init(*args)
    assert rc == OK
    assert [p.k_p, p.k_i, p.T_s, p.y_max] == args


@SETTINGS
@given(data=st.data())
def test_smdo_init_accepts_valid_iff_discrete_loop_stable(data):
    args = _valid_base(SMDO, data.draw)
    T, L, R, lam, l, wc, rho = (np.float32(a) for a in args)
    # documented stability condition, evaluated in float like the C code
    with np.errstate(over="ignore"):
        unstable = (l + lam / rho) * T >= np.float32(2.0) or wc * T >= np.float32(1.0)
    rc, p = smdo_init(*args)
    assert rc == (ERR_STABILITY if unstable else OK)
    if rc == OK:
        assert [p.T_sp, p.L_s_hat, p.R_s_hat, p.lambda_min, p.l, p.w_c, p.rho] == args
        assert p.euler == 0  # exact rotation by default


@pytest.mark.parametrize("euler", [-1, 0, 1, 2, 100])
def test_smdo_set_euler(euler):
    p = F.SmdoParams()
    assert lib.smd_smdo_init(ct.byref(p), 1e-4, 0.02, 2.0, 800.0, 1200.0, 1500.0, 0.2) == OK
    assert lib.smd_smdo_set_euler(None, 1) == ERR_NULL
    rc = lib.smd_smdo_set_euler(ct.byref(p), euler)
    assert rc == (OK if euler in (0, 1) else ERR_MODE)
    assert p.euler == (euler if rc == OK else 0)


@SETTINGS
@given(T=fl(1e-30, 1.0), frac=st.floats(1e-6, 0.9999), w_hys=valid(0.0, 1e5, False),
       frac_max=st.floats(1e-6, 0.9999))
def test_emf_pos_init_accepts_valid_and_derives_a_lpf(T, frac, w_hys, frac_max):
    args = emf_args(T, frac, w_hys, frac_max)
    rc, p = emf_init(*args)
    assert rc == OK
    assert p.T_sp == T and p.w_lpf == f32(args[1])
    assert p.w_hys == f32(args[2]) and p.w_max == f32(args[3])
    assert p.a_lpf == pytest.approx(-math.expm1(-p.w_lpf * p.T_sp), abs=2e-7, rel=1e-5)
    assert 0.0 < p.a_lpf < 1.0


@SETTINGS
@given(T=valid(0.0, 1.0, True), excess=st.floats(1.0 + 1e-5, 1e6))
def test_emf_pos_init_rejects_w_lpf_above_nyquist(T, excess):
    w = math.pi / T * excess
    assume(math.isfinite(f32(w)))
    assert emf_init(T, w, 0.0, 1.0 / T)[0] == ERR_WLPF
    assert emf_init(T, 1.0 / T, 0.0, w)[0] == ERR_WMAX  # w_max beyond pi/T_sp


@pytest.mark.parametrize("T", [1e-4, 1e-3, 0.5, 1.0])
def test_emf_pos_init_rejects_w_lpf_at_nyquist(T):
    """Documented range is the open interval (0, pi/T_sp)."""
    nyq = f32(np.float32(np.pi) / np.float32(T))  # SMD_PI / T_sp in float
    assert emf_init(T, next_down(nyq), 0.0, 1.0 / T)[0] == OK
    assert emf_init(T, nyq, 0.0, 1.0 / T)[0] == ERR_WLPF


@SETTINGS
@given(T=fl(1e-6, 1.0), w_hys=fl(0.0, 1e5), below=st.floats(0.0, 1.0))
def test_emf_pos_init_rejects_w_max_not_above_w_hys(T, w_hys, below):
    """|w_hat| is limited to w_max; a limit inside the hysteresis band could
    never flip the direction, so w_max <= w_hys is rejected."""
    w_max = f32(below * w_hys)
    assert emf_init(T, 1.0 / T, w_hys, w_max)[0] == ERR_WMAX
    if w_hys < math.pi / T * 0.99:
        assert emf_init(T, 1.0 / T, w_hys, next_up(w_hys))[0] == OK


@SETTINGS
@given(limit=st.integers(-5, 5), d_min=st.one_of(
    st.floats(width=32), st.just(NAN), valid(0.0, 0.49, False)))
def test_svm_init_limit_and_d_min(limit, d_min):
    p = F.SvmParams(-7, -1.0)
    rc = lib.smd_svm_init(ct.byref(p), limit, d_min)
    if limit not in (0, 1):
        assert rc == ERR_MODE
    elif not (0.0 <= d_min <= f32(0.49)):
        assert rc == ERR_DMIN
    else:
        assert rc == OK and p.limit == limit and p.d_min == d_min
    if rc != OK:
        assert p.limit == -7 and p.d_min == -1.0


# ------------------------------------------------------------ steps ---------

cur = fl(-1e3, 1e3)
volt = fl(-1e4, 1e4)
speed = fl(-1e4, 1e4)
angle = fl(-1e6, 1e6)
cplx_i = st.builds(complex, cur, cur)
cplx_u = st.builds(complex, volt, volt)
# physically broad controller parameters
T_phys = fl(1e-7, 1e-2)
L_phys = fl(1e-6, 10.0)
R_phys = fl(0.0, 1000.0)
psi_phys = fl(0.0, 100.0)


def _dbpc(T, L, R, psi):
    p = F.DbpcParams()
    assert lib.smd_dbpc_init(ct.byref(p), T, L, R, psi) == OK
    return p


@SETTINGS
@given(T=T_phys, L=L_phys, R=R_phys, psi=psi_phys, i=cplx_i, u=cplx_u, i_ref=cplx_i,
       theta=angle, w=speed)
def test_dbpc_conventional_finite_and_deadbeat(T, L, R, psi, i, u, i_ref, theta, w):
    p = _dbpc(T, L, R, psi)
    u_next = complex(lib.smd_dbpc_conventional(ct.byref(p), C(i), C(u), C(i_ref), theta, w))
    assert finite(u_next)
    # Deadbeat: through the controller's own model (8) at k+1 (angle advanced
    # by w T_sp), u_next drives the predicted current to the reference (7).
    i_k1 = complex(lib.smd_dbpc_predict(ct.byref(p), C(i), C(u), theta, w))
    theta_k1 = float(np.float32(theta) + np.float32(w) * np.float32(p.T_sp))  # as in C
    i_k2 = complex(lib.smd_dbpc_predict(ct.byref(p), C(i_k1), C(u_next), theta_k1, w))
    ref_k2 = complex(lib.smd_dbpc_ref_k2(ct.byref(p), C(i_ref), theta, w))
    assert abs(ref_k2) == pytest.approx(abs(i_ref), rel=1e-5, abs=1e-4)
    scale = abs(i_k1) + abs(i_ref) + (abs(u_next) + R * abs(i_k1) + abs(w) * psi) * T / L
    assert abs(i_k2 - ref_k2) <= 1e-4 * scale + 1e-3


@SETTINGS
@given(T=T_phys, L=L_phys, R=R_phys, i=cplx_i, u_d=cplx_u, i_ref=cplx_i)
def test_dbpc_robust_finite_and_deadbeat(T, L, R, i, u_d, i_ref):
    p = _dbpc(T, L, R, 0.0)
    u = complex(lib.smd_dbpc_robust(ct.byref(p), C(i), C(u_d), C(i_ref)))
    assert finite(u)
    # model (15) with the disturbance: i^{k+2} = i^{k+1} + T/L (u + u_d - R i^{k+1})
    i_k2 = i + (u + u_d - R * i) * p.T_sp / p.L_s_hat
    scale = abs(i) + abs(i_ref) + (abs(u) + abs(u_d) + R * abs(i)) * T / L
    assert abs(i_k2 - i_ref) <= 1e-5 * scale + 1e-4


def _smdo_params(draw, euler: int = 0) -> F.SmdoParams:
    T = draw(fl(1e-6, 1e-3))
    L = draw(fl(1e-4, 1.0))
    R = draw(fl(0.0, 100.0))
    rho = draw(fl(1e-3, 100.0))
    # gains drawn as fractions of the stability bounds
    l = draw(st.floats(0.01, 0.95)) / T
    lam = min(draw(st.floats(0.0, 0.95)) * rho / T, 1e7)
    w_c = draw(st.floats(0.01, 0.95)) / T
    p = F.SmdoParams()
    assert lib.smd_smdo_init(ct.byref(p), T, L, R, lam, l, w_c, rho) == OK
    assert lib.smd_smdo_set_euler(ct.byref(p), euler) == OK
    return p


def _smdo_state_finite(s: F.SmdoState) -> bool:
    return finite(s.i_s_hat, s.u_d_hat, s.e_i_prev, s.u_smo_prev, s.u_smo) and \
        math.isfinite(s.lambda_)


@settings(max_examples=60, deadline=None)
@given(data=st.data(), n=st.integers(100, 400), euler=st.sampled_from([0, 1]))
def test_smdo_random_inputs_keep_state_finite(data, n, euler):
    p = _smdo_params(data.draw, euler)
    s = F.SmdoState()
    lib.smd_smdo_reset(ct.byref(s), C(data.draw(cplx_i)), C(data.draw(cplx_u)))
    seed = data.draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    i = rng.uniform(-1e3, 1e3, (n, 2))
    u = rng.uniform(-1e4, 1e4, (n, 2))
    w = rng.uniform(-1e4, 1e4, n)
    for k in range(n):
        rc = lib.smd_smdo_step(ct.byref(p), ct.byref(s), F.Cplx(*i[k]), F.Cplx(*u[k]), w[k])
        assert rc in (OK, ERR_NONFINITE)
        assert _smdo_state_finite(s), f"step {k}: state not finite (rc {rc})"
        if rc == OK:
            assert s.lambda_ >= p.lambda_min


@pytest.mark.parametrize("where", ["i_re", "i_im", "u_re", "u_im", "w"])
@pytest.mark.parametrize("bad", [NAN, INF])
@pytest.mark.parametrize("euler", [0, 1])
def test_smdo_nonfinite_input_reports_and_state_stays_finite(where, bad, euler):
    p = F.SmdoParams()
    assert lib.smd_smdo_init(ct.byref(p), 1e-4, 0.02345, 2.25, 800.0, 1200.0, 1500.0, 0.2) == OK
    assert lib.smd_smdo_set_euler(ct.byref(p), euler) == OK
    s = F.SmdoState()
    lib.smd_smdo_reset(ct.byref(s), C(1 + 2j), C(30 - 40j))
    for _ in range(5):
        assert lib.smd_smdo_step(ct.byref(p), ct.byref(s), C(1 + 2j), C(10 + 5j), 300.0) == OK
    vals = {"i_re": 1.0, "i_im": 2.0, "u_re": 10.0, "u_im": 5.0, "w": 300.0}
    vals[where] = bad
    rc = lib.smd_smdo_step(ct.byref(p), ct.byref(s), F.Cplx(vals["i_re"], vals["i_im"]),
                           F.Cplx(vals["u_re"], vals["u_im"]), vals["w"])
    assert rc == ERR_NONFINITE
    assert _smdo_state_finite(s), (complex(s.i_s_hat), complex(s.u_d_hat))
    # and the observer carries on normally with finite inputs
    for _ in range(3):
        assert lib.smd_smdo_step(ct.byref(p), ct.byref(s), C(1 + 2j), C(10 + 5j), 300.0) == OK
    assert _smdo_state_finite(s)


@SETTINGS
@given(k_p=valid(0.0, 1e6, False), k_i=valid(0.0, 1e9, False), T=valid(0.0, 1.0, True),
       y_max=valid(0.0, 1e9, True), x0=fl(-1e9, 1e9),
       errs=st.lists(fl(-1e4, 1e4), min_size=1, max_size=50))
def test_pi_output_within_limit(k_p, k_i, T, y_max, x0, errs):
    p = F.PiParams()
    assert lib.smd_pi_init(ct.byref(p), k_p, k_i, T, y_max) == OK
    s = F.PiState()
    lib.smd_pi_reset(ct.byref(s), max(-y_max, min(y_max, x0)))
    for e in errs:
        y = lib.smd_pi_step(ct.byref(p), ct.byref(s), e)
        assert math.isfinite(y) and -y_max <= y <= y_max
        assert y == s.y
        assert math.isfinite(s.x_i) and -y_max <= s.x_i <= y_max  # anti-windup
    # with zero error the output holds at the integrator value
    x_i = s.x_i
    assert lib.smd_pi_step(ct.byref(p), ct.byref(s), 0.0) == x_i


@SETTINGS
@given(k_p=fl(0.0, 10.0), k_i=fl(0.0, 1e3),
       e=fl(-1e3, 1e3))
def test_pi_unsaturated_is_linear(k_p, k_i, e):
    p = F.PiParams()
    assert lib.smd_pi_init(ct.byref(p), k_p, k_i, 1e-3, 1e9) == OK
    s = F.PiState()
    lib.smd_pi_reset(ct.byref(s), 0.0)
    y1 = lib.smd_pi_step(ct.byref(p), ct.byref(s), e)
    y2 = lib.smd_pi_step(ct.byref(p), ct.byref(s), e)
    assert y1 == pytest.approx(k_p * e + k_i * 1e-3 * e, rel=1e-5, abs=1e-6)
    assert y2 == pytest.approx(k_p * e + 2 * k_i * 1e-3 * e, rel=1e-5, abs=1e-6)


def _abc_span(z: complex) -> float:
    a = z.real
    b = -0.5 * z.real + 0.5 * math.sqrt(3) * z.imag
    c = -0.5 * z.real - 0.5 * math.sqrt(3) * z.imag
    return max(a, b, c) - min(a, b, c)


@SETTINGS
@given(limit=st.sampled_from([0, 1]), d_min=valid(0.0, 0.49, False),
       u_ref=st.one_of(cplx_u, st.builds(complex, fl(-1e7, 1e7),
                                         fl(-1e7, 1e7))),
       u_dc=fl(1e-3, 1e4))
def test_svm_duties_and_applied_vector(limit, d_min, u_ref, u_dc):
    p = F.SvmParams()
    assert lib.smd_svm_init(ct.byref(p), limit, d_min) == OK
    d = (F.real * 3)()
    app = F.Cplx()
    lib.smd_svm_step(ct.byref(p), C(u_ref), u_dc, d, ct.byref(app))
    d = np.array(d[:], dtype=float)
    app = complex(app)
    assert np.all(np.isfinite(d)) and finite(app)
    assert np.all(d >= 0.0) and np.all(d <= 1.0)
    assert np.all(d >= d_min - 1e-6) and np.all(d <= 1.0 - d_min + 1e-6)
    u_avail = (1.0 - 2.0 * d_min) * u_dc
    tol = 1e-5 * u_dc
    if limit == 0:   # circle
        assert abs(app) <= u_avail / math.sqrt(3) + tol
    else:            # hexagon: line-to-line span of the phase voltages
        assert _abc_span(app) <= u_avail + tol
        assert abs(app) <= u_avail * 2.0 / 3.0 + tol
    # the applied vector is what the duties realise ...
    realised = complex(lib.smd_abc_to_ab((F.real * 3)(*(d * u_dc))))
    assert abs(realised - app) <= 1e-5 * u_dc + 1e-6
    # ... and the reference shrunk along its own direction (never grown)
    assert abs(app) <= abs(u_ref) * (1 + 1e-6) + 1e-6
    assert abs((app * u_ref.conjugate()).imag) <= 1e-5 * abs(app) * abs(u_ref) + 1e-6
    assert (app * u_ref.conjugate()).real >= -1e-6
    if abs(u_ref) <= u_avail / math.sqrt(3) * (1 - 1e-5):  # inside the linear range
        assert abs(app - u_ref) <= 1e-5 * abs(u_ref) + 1e-6


@pytest.mark.parametrize("u_dc", [0.0, -540.0, NAN])
def test_svm_without_dc_link_applies_zero_vector(u_dc):
    p = F.SvmParams()
    assert lib.smd_svm_init(ct.byref(p), 1, 0.0) == OK
    d = (F.real * 3)()
    app = F.Cplx(1.0, 1.0)
    lib.smd_svm_step(ct.byref(p), C(100 + 50j), u_dc, d, ct.byref(app))
    assert list(d) == [0.5, 0.5, 0.5] and complex(app) == 0


@SETTINGS
@given(T=fl(1e-6, 1e-2), frac=st.floats(1e-4, 0.999),
       w_hys=fl(0.0, 1e5), frac_max=st.floats(1e-4, 1.0), w0=speed,
       ud=st.lists(st.one_of(cplx_u, st.just(0j)), min_size=1, max_size=60))
def test_emf_pos_angle_range(T, frac, w_hys, frac_max, w0, ud):
    p = F.EmfPosParams()
    assert lib.smd_emf_pos_init(ct.byref(p), *emf_args(T, frac, w_hys, frac_max)) == OK
    s = F.EmfPosState()
    lib.smd_emf_pos_reset(ct.byref(s), w0)
    for k, z in enumerate(ud):
        lib.smd_emf_pos_step(ct.byref(p), ct.byref(s), C(z))
        assert -PI_F <= s.theta_r_hat < PI_F, s.theta_r_hat
        if k > 0:  # from the second sample on the speed estimate is limited
            assert abs(s.w_r_hat) <= p.w_max
        assert math.isfinite(s.w_r_hat) and math.isfinite(s.w_r_raw)
        assert abs(s.w_r_raw) <= max(abs(w0), PI_F / T * (1 + 1e-5))
        assert s.dir in (-1, 1)
    # a NaN input keeps the previous estimates
    before = [getattr(s, f) for f, _ in s._fields_]
    lib.smd_emf_pos_step(ct.byref(p), ct.byref(s), C(complex(NAN, 1.0)))
    assert [getattr(s, f) for f, _ in s._fields_] == before


@settings(max_examples=40, deadline=None)
@given(psi=st.floats(0.1, 1.0), w=st.floats(50.0, 2000.0), sign=st.sampled_from([-1, 1]),
       theta0=st.floats(-math.pi, math.pi))
def test_emf_pos_tracks_rotating_back_emf(psi, w, sign, theta0):
    """u_d = -j w psi e^{j theta} (eq. 43) with theta = theta0 + w t: the
    estimate locks to theta (after the half-sample correction) and to w."""
    T = 1e-4
    w = sign * w
    p = F.EmfPosParams()
    assert lib.smd_emf_pos_init(ct.byref(p), T, 500.0, 5.0, 5000.0) == OK
    s = F.EmfPosState()
    lib.smd_emf_pos_reset(ct.byref(s), w)
    for k in range(200):
        # disturbance identified over [t_k, t_k+1): evaluated at t_k + T/2
        th = theta0 + w * (k + 0.5) * T
        lib.smd_emf_pos_step(ct.byref(p), ct.byref(s), C(-1j * w * psi * np.exp(1j * th)))
    th_k = theta0 + w * 199 * T
    err = (s.theta_r_hat - th_k + math.pi) % (2 * math.pi) - math.pi
    assert abs(err) < 1e-3
    assert s.w_r_hat == pytest.approx(w, rel=1e-3)


# ------------------------------------------------------------ engine --------

@st.composite
def controllers(draw):
    T = 100e-6
    rho = draw(st.floats(0.05, 2.0))
    l = draw(st.floats(100.0, 5000.0))
    lam = draw(st.floats(0.0, 1.0)) * rho * (1.5 / T - l)  # keeps (l + lam/rho) T < 1.5
    return ControllerCfg(
        **yang2018_mode(draw(st.sampled_from(["conventional", "robust", "sensorless"]))),
        L_s_hat=draw(st.floats(0.5, 2.0)) * 23.45e-3,
        R_s_hat=draw(st.floats(0.0, 2.0)) * 2.25,
        psi_r_hat=draw(st.floats(0.5, 1.5)) * 0.4,
        lambda_min=lam, l=l, w_c=draw(st.floats(100.0, 5000.0)), rho=rho,
        speed_bw=draw(st.floats(5.0, 200.0)),
        i_max=draw(st.floats(1.0, 30.0)),
        speed_decimation=draw(st.integers(1, 20)),
        w_lpf=draw(st.floats(10.0, 2000.0)),
        w_hys=draw(st.floats(0.0, 50.0)),
        speed_loop=draw(st.booleans()),
    )


@settings(max_examples=40, deadline=None)
@given(ctrl=controllers(), n0=st.floats(-1500.0, 1500.0), n_ref=st.floats(-1500.0, 1500.0),
       i_q=st.floats(-10.0, 10.0), svm=st.sampled_from(["hexagon", "circle"]),
       pwm=st.sampled_from(["carrier", "averaged"]))
def test_engine_never_logs_nan(ctrl, n0, n_ref, i_q, svm, pwm):
    from smodrive.model import InverterCfg
    from smodrive.engine import simulate

    s = Scenario(duration=0.01, w_M0=n0 * RPM, w_M_ref=Profile.const(n_ref * RPM),
                 i_q_ref=Profile.const(i_q), controller=ctrl,
                 inverter=InverterCfg(svm_limit=svm, pwm=pwm))
    r = simulate(s)
    assert r.data.shape == (100, F.N_LOG)
    assert np.all(np.isfinite(r.data))
    assert r.status != ERR_NONFINITE
