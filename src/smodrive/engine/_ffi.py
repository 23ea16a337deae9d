"""ctypes binding to the compiled C library (firmware core + host engine).

Every struct mirror below names its C struct (``_c_name_``). At import,
:func:`check_layout` compares each mirror field by field (name, offset,
size, order) with the table the library exports (``sim/src/smd_layout.c``,
generated from the headers by ``tools/gen_layout.py`` and laid out by the
compiler), so a mirror that has drifted from its header fails at import
instead of corrupting memory.
"""

from __future__ import annotations

import ctypes as ct
import keyword
from pathlib import Path

real = ct.c_float  # smd_real of the default (float) build


def _load() -> ct.CDLL:
    here = Path(__file__).resolve().parent.parent  # the package root, where the wheel puts it
    for cand in (here / "libsmodrive.so", here / "libsmodrive.dylib"):
        if cand.exists():
            return ct.CDLL(str(cand))
    raise ImportError(
        f"smodrive's compiled library was not found in {here}; install the package with "
        "'pip install .' so that its C core is built"
    )


lib = _load()
MIRRORS: dict[str, type[ct.Structure]] = {}


def mirror(c_name: str):
    """Class decorator: register a ctypes mirror of C struct `c_name`."""

    def wrap(cls: type[ct.Structure]) -> type[ct.Structure]:
        cls._c_name_ = c_name  # type: ignore[attr-defined]
        MIRRORS[c_name] = cls
        return cls

    return wrap


def _arr(t, n: int):
    return t * n


# ------------------------------------------------------------ core blocks --

@mirror("smd_cplx")
class Cplx(ct.Structure):
    _fields_ = [("re", real), ("im", real)]

    @classmethod
    def of(cls, z: complex) -> "Cplx":
        return cls(float(z.real), float(z.imag))

    def __complex__(self) -> complex:
        return complex(self.re, self.im)


@mirror("smd_dbpc_params")
class DbpcParams(ct.Structure):
    _fields_ = [("T_sp", real), ("L_s_hat", real), ("R_s_hat", real), ("psi_r_hat", real)]


@mirror("smd_smdo_params")
class SmdoParams(ct.Structure):
    _fields_ = [("T_sp", real), ("L_s_hat", real), ("R_s_hat", real), ("lambda_min", real),
                ("l", real), ("w_c", real), ("rho", real), ("euler", ct.c_int)]


@mirror("smd_smdo_state")
class SmdoState(ct.Structure):
    _fields_ = [("i_s_hat", Cplx), ("u_d_hat", Cplx), ("e_i_prev", Cplx), ("u_smo_prev", Cplx),
                ("u_smo", Cplx), ("lambda_", real)]


@mirror("smd_pi_params")
class PiParams(ct.Structure):
    _fields_ = [("k_p", real), ("k_i", real), ("T_s", real), ("y_max", real)]


@mirror("smd_pi_state")
class PiState(ct.Structure):
    _fields_ = [("x_i", real), ("y", real)]


@mirror("smd_svm_params")
class SvmParams(ct.Structure):
    _fields_ = [("limit", ct.c_int), ("d_min", real)]


@mirror("smd_emf_pos_params")
class EmfPosParams(ct.Structure):
    _fields_ = [("T_sp", real), ("w_lpf", real), ("a_lpf", real), ("a_dir", real),
                ("w_hys", real), ("w_max", real)]


@mirror("smd_emf_pos_state")
class EmfPosState(ct.Structure):
    _fields_ = [("phi_prev", real), ("w_r_raw", real), ("w_r_hat", real), ("w_r_dir", real),
                ("theta_r_hat", real), ("dir", ct.c_int), ("primed", ct.c_int)]


@mirror("smd_bandpass")
class Bandpass(ct.Structure):
    _fields_ = [("b0", real), ("a1", real), ("a2", real), ("x1", Cplx), ("x2", Cplx),
                ("y1", Cplx), ("y2", Cplx)]


@mirror("smd_pll_params")
class PllParams(ct.Structure):
    _fields_ = [("T_sp", real), ("k_theta", real), ("k_omega", real), ("k_a", real)]


@mirror("smd_pll_state")
class PllState(ct.Structure):
    _fields_ = [("theta", real), ("w", real), ("a", real)]


MODEL_FIELDS = (("G", 36), ("H", 12), ("F", 12), ("Ft", 16), ("Hc", 4), ("D1", 4), ("D2", 4),
                ("Gam_c", 4), ("Gam_1", 4), ("Gam_2", 4), ("Gs", 4), ("Kc", 4), ("Ky", 4),
                ("k", 1))
N_MODEL = sum(k for _, k in MODEL_FIELDS)  # floats in smd_lcl_model
SMO_DELAY = 256  # SMD_LCL_SMO_DELAY


@mirror("smd_lcl_model")
class LclModel(ct.Structure):
    _fields_ = [(n, _arr(real, k)) if k > 1 else (n, real) for n, k in MODEL_FIELDS]


@mirror("smd_lcl_smo_config")
class SmoConfig(ct.Structure):
    _fields_ = [("T_sp", real), ("law", ct.c_int), ("table", ct.c_void_p), ("n", ct.c_int),
                ("w_min", real), ("dw", real), ("Q1", real), ("Q2", real), ("bw_rel2", real),
                ("bw_rel3", real), ("w_bp_min", real)]


@mirror("smd_lcl_smo_params")
class SmoParams(ct.Structure):
    _fields_ = SmoConfig._fields_


@mirror("smd_lcl_smo_state")
class SmoState(ct.Structure):
    _fields_ = [("x_hat", real * 6), ("x_c", real * 2), ("s", real * 2), ("y", real * 4),
                ("s_prev", real * 2), ("w_att", real * 2), ("v_prev", real * 2),
                ("D1", real * 2), ("D2", real * 2), ("e_hat", real * 2), ("d_hat", real * 2),
                ("theta_prev", real), ("v_hist", Cplx * SMO_DELAY), ("v_head", ct.c_int),
                ("bp2", Bandpass), ("bp3", Bandpass), ("primed", ct.c_int)]


@mirror("smd_linobs_model")
class LinModel(ct.Structure):
    _fields_ = [("L", real * 16), ("Theta", real * 16), ("Ky", real * 16), ("Ku", real * 8)]


N_LIN = 16 * 3 + 8  # floats in smd_linobs_model


@mirror("smd_linobs_config")
class LinConfig(ct.Structure):
    _fields_ = [("table", ct.c_void_p), ("n", ct.c_int), ("w_min", real), ("dw", real)]


@mirror("smd_linobs_params")
class LinParams(ct.Structure):
    _fields_ = LinConfig._fields_


@mirror("smd_linobs_state")
class LinState(ct.Structure):
    _fields_ = [("z", real * 4), ("x2", real * 4), ("primed", ct.c_int)]


# ------------------------------------------------------------------ drive --

@mirror("smd_drive_config")
class DriveConfig(ct.Structure):
    _fields_ = [
        ("current", ct.c_int), ("position", ct.c_int), ("start", ct.c_int), ("lcl", ct.c_int),
        ("T_sp", real),
        ("L_s_hat", real), ("R_s_hat", real), ("psi_r_hat", real),
        ("lambda_min", real), ("l", real), ("w_c", real), ("rho", real), ("smdo_euler", ct.c_int),
        ("w_lpf", real), ("w_hys", real), ("w_max", real),
        ("k_p_i", real), ("k_i_i", real), ("L_dec", real), ("R_v", real), ("emf_ff", ct.c_int),
        ("speed_loop", ct.c_int), ("k_p_w", real), ("k_i_w", real), ("i_max", real),
        ("speed_decimation", ct.c_int),
        ("k_theta", real), ("k_omega", real), ("k_a", real),
        ("smo", SmoConfig), ("lin", LinConfig),
        ("handover", ct.c_int), ("i_start", real), ("a_start", real), ("w_handover", real),
        ("svm_limit", ct.c_int), ("t_dead_comp", real), ("i_dtc", real),
        ("i_trip", real), ("u_dc_min", real), ("u_dc_max", real), ("safe_state", ct.c_int),
        ("lock_samples", ct.c_int), ("lock_ratio", real), ("w_lock_min", real),
        ("w_if_enter", real),
        ("a_ref", real), ("dwell", ct.c_int), ("chatter_max", ct.c_int),
        ("chatter_window", ct.c_int), ("track_samples", ct.c_int), ("w_track", real),
        ("forced_samples", ct.c_int), ("osc_i", real), ("osc_rel", real),
        ("osc_samples", ct.c_int), ("restart_max", ct.c_int), ("restart_window", ct.c_int),
    ]


@mirror("smd_drive_view")
class DriveView(ct.Structure):
    _fields_ = [("i_dq_ref", Cplx), ("i_dq", Cplx), ("u_ab", Cplx), ("u_ab_ref", Cplx),
                ("i_s_hat", Cplx), ("u_d_hat", Cplx), ("theta", real), ("w", real),
                ("lambda_", real), ("theta_err", real), ("e_hat", Cplx), ("s", Cplx),
                ("d_hat", Cplx), ("v", Cplx), ("e_lin", Cplx), ("phase", ct.c_int),
                ("fault", ct.c_uint32)]


@mirror("smd_drive_in")
class DriveIn(ct.Structure):
    _fields_ = [("i_a", real), ("i_b", real), ("i1_a", real), ("i1_b", real),
                ("theta_enc", real), ("w_enc", real), ("u_dc", real), ("w_ref", real),
                ("i_dq_ref", Cplx)]


@mirror("smd_drive_out")
class DriveOut(ct.Structure):
    _fields_ = [("d_abc", real * 3), ("fault", ct.c_uint32), ("pwm_off", ct.c_int)]


# ------------------------------------------------------------------ plant --

_D3 = ct.c_double * 3


@mirror("smd_plant_config")
class PlantConfig(ct.Structure):
    _fields_ = [
        ("R_s", ct.c_double), ("L_s", ct.c_double), ("psi_r", ct.c_double),
        ("n_p", ct.c_double), ("J", ct.c_double), ("B", ct.c_double),
        ("lcl", ct.c_int), ("L1", ct.c_double), ("L2o", ct.c_double), ("C1", ct.c_double),
        ("u_dc", ct.c_double), ("T_sw", ct.c_double), ("pwm_mode", ct.c_int),
        ("dead_time_model", ct.c_int), ("t_dead", ct.c_double),
        ("adc_gain", _D3), ("adc_offset", _D3), ("adc_gain_i1", _D3), ("adc_offset_i1", _D3),
        ("adc_noise", ct.c_double), ("adc_bits", ct.c_int), ("adc_n_oversample", ct.c_int),
        ("adc_full_scale", ct.c_double),
        ("seed", ct.c_uint64),
        ("w_brake_eps", ct.c_double), ("k_fan", ct.c_double),
        ("w_M0", ct.c_double), ("theta_r0", ct.c_double), ("i_d0", ct.c_double),
        ("i_q0", ct.c_double), ("uc_d0", ct.c_double), ("uc_q0", ct.c_double),
        ("i1_d0", ct.c_double), ("i1_q0", ct.c_double),
    ]


@mirror("smd_plant")
class PlantHead(ct.Structure):
    """The leading (public) fields of struct smd_plant, checked as a prefix
    of the C struct's fields."""

    _fields_ = [
        ("c", PlantConfig),
        ("i_re", ct.c_double), ("i_im", ct.c_double),
        ("i1_re", ct.c_double), ("i1_im", ct.c_double),
        ("uc_re", ct.c_double), ("uc_im", ct.c_double),
        ("theta_r", ct.c_double), ("w_M", ct.c_double),
        ("T_e_mean", ct.c_double), ("T_L_mean", ct.c_double),
        ("u_re", ct.c_double), ("u_im", ct.c_double),
    ]
    _prefix_ = True


PWL_MAX = 64


@mirror("smd_pwl")
class Pwl(ct.Structure):
    _fields_ = [("n", ct.c_int), ("t", ct.c_double * PWL_MAX), ("y", ct.c_double * PWL_MAX)]


@mirror("smd_profiles")
class Profiles(ct.Structure):
    _fields_ = [("w_M_ref", Pwl), ("T_ext", Pwl), ("T_brake", Pwl), ("i_d_ref", Pwl),
                ("i_q_ref", Pwl), ("i_d_sin_amp", ct.c_double), ("i_d_sin_freq", ct.c_double)]


@mirror("smd_engine_start")
class EngineStart(ct.Structure):
    _fields_ = [("theta0", ct.c_double), ("w0", ct.c_double), ("i_q0", ct.c_double)]


# -------------------------------------------------------------- functions --

def _sig(name: str, restype, *argtypes):
    f = getattr(lib, name)
    f.restype = restype
    f.argtypes = list(argtypes)
    return f


P = ct.POINTER
_sig("smd_status_str", ct.c_char_p, ct.c_int)
_sig("smd_plant_field", ct.c_char_p, ct.c_int)
_sig("smd_log_channel_name", ct.c_char_p, ct.c_int)
_sig("smd_layout_rows", ct.c_int)
_sig("smd_layout_type_at", ct.c_char_p, ct.c_int)
_sig("smd_layout_row_at", ct.c_int, ct.c_int, P(ct.c_char_p), P(ct.c_char_p), P(ct.c_ulong),
     P(ct.c_ulong))
_sig("smd_sizeof_engine", ct.c_ulong)
_sig("smd_sizeof_plant", ct.c_ulong)
_sig("smd_engine_init", ct.c_int, ct.c_void_p, P(PlantConfig), P(DriveConfig), P(Profiles),
     P(EngineStart))
_sig("smd_engine_run", ct.c_long, ct.c_void_p, ct.c_long, P(ct.c_double), ct.c_long)
_sig("smd_engine_ext_inputs", None, ct.c_void_p, P(DriveIn))
_sig("smd_engine_ext_apply", None, ct.c_void_p, P(DriveOut), ct.c_int, P(DriveView),
     P(ct.c_double))
_sig("smd_engine_host_step", ct.c_int, ct.c_void_p, P(DriveIn), P(DriveOut), P(DriveView))
_sig("smd_engine_fault", ct.c_long, ct.c_void_p, P(ct.c_uint), P(ct.c_uint))
_sig("smd_plant_init", ct.c_int, ct.c_void_p, P(PlantConfig))
_sig("smd_plant_step", None, ct.c_void_p, P(ct.c_double), ct.c_double, ct.c_double)
_sig("smd_plant_sample", None, ct.c_void_p, P(ct.c_double), P(ct.c_double))
_sig("smd_plant_phase_currents", None, ct.c_void_p, P(ct.c_double), P(ct.c_double))
_sig("smd_plant_eigenvalues", None, ct.c_void_p, P(ct.c_double), P(ct.c_double))
_sig("smd_plant_run_open", None, ct.c_void_p, ct.c_long, ct.c_double, ct.c_double, ct.c_double)
_sig("smd_pwm_edges", None, ct.c_double, ct.c_double, ct.c_double, ct.c_double, P(ct.c_double),
     P(ct.c_double))
_sig("smd_pwm_avg_duty", ct.c_double, ct.c_double, ct.c_double, ct.c_double, ct.c_double)
_sig("smd_pwm_avg_duty_clamp", ct.c_double, ct.c_double, ct.c_double, ct.c_double, ct.c_double,
     ct.c_double, ct.c_double)
_sig("smd_pwl_eval", ct.c_double, P(Pwl), ct.c_double)
_sig("smd_pll_impulse", ct.c_int, ct.c_double, ct.c_double, ct.c_double, ct.c_double,
     ct.c_double, ct.c_long, P(ct.c_double))
_sig("smd_dbpc_init", ct.c_int, P(DbpcParams), real, real, real, real)
_sig("smd_dbpc_predict", Cplx, P(DbpcParams), Cplx, Cplx, real, real)
_sig("smd_dbpc_ref_k2", Cplx, P(DbpcParams), Cplx, real, real)
_sig("smd_dbpc_conventional", Cplx, P(DbpcParams), Cplx, Cplx, Cplx, real, real)
_sig("smd_dbpc_robust", Cplx, P(DbpcParams), Cplx, Cplx, Cplx)
_sig("smd_smdo_init", ct.c_int, P(SmdoParams), real, real, real, real, real, real, real)
_sig("smd_smdo_reset", None, P(SmdoState), Cplx, Cplx)
_sig("smd_smdo_set_euler", ct.c_int, P(SmdoParams), ct.c_int)
_sig("smd_smdo_step", ct.c_int, P(SmdoParams), P(SmdoState), Cplx, Cplx, real)
_sig("smd_pi_init", ct.c_int, P(PiParams), real, real, real, real)
_sig("smd_pi_reset", None, P(PiState), real)
_sig("smd_pi_step", real, P(PiParams), P(PiState), real)
_sig("smd_svm_init", ct.c_int, P(SvmParams), ct.c_int, real)
_sig("smd_svm_step", None, P(SvmParams), Cplx, real, P(real), P(Cplx))
_sig("smd_emf_pos_init", ct.c_int, P(EmfPosParams), real, real, real, real)
_sig("smd_emf_pos_reset", None, P(EmfPosState), real)
_sig("smd_emf_pos_step", None, P(EmfPosParams), P(EmfPosState), Cplx)
_sig("smd_abc_to_ab", Cplx, P(real))
_sig("smd_ab2_to_ab", Cplx, real, real)
_sig("smd_lcl_smo_init", ct.c_int, P(SmoParams), P(SmoConfig))
_sig("smd_lcl_smo_reset", None, P(SmoState), real)
_sig("smd_lcl_smo_model", None, P(SmoParams), real, P(LclModel))
_sig("smd_lcl_smo_step", ct.c_int, P(SmoParams), P(SmoState), Cplx, Cplx, Cplx, real, real)
_sig("smd_lcl_smo_reach", None, P(SmoParams), P(SmoState), P(LclModel), Cplx, Cplx, real)
_sig("smd_lcl_smo_predict", None, P(LclModel), P(SmoState), Cplx)
_sig("smd_lcl_smo_theta_err", real, P(SmoState), real)
_sig("smd_lcl_smo_reframe", None, P(SmoState), real)
_sig("smd_linobs_init", ct.c_int, P(LinParams), P(LinConfig))
_sig("smd_linobs_reset", None, P(LinState))
_sig("smd_linobs_step", ct.c_int, P(LinParams), P(LinState), Cplx, Cplx, Cplx, real)


def status_str(code: int) -> str:
    return lib.smd_status_str(code).decode()


def layout_table() -> dict[str, list[tuple]]:
    """The library's layout table: struct -> [(field, offset, size, type)],
    with the struct's own size as the field "" first."""
    out: dict[str, list[tuple]] = {}
    s, f = ct.c_char_p(), ct.c_char_p()
    off, size = ct.c_ulong(), ct.c_ulong()
    for k in range(lib.smd_layout_rows()):
        lib.smd_layout_row_at(k, ct.byref(s), ct.byref(f), ct.byref(off), ct.byref(size))
        out.setdefault(s.value.decode(), []).append(
            (f.value.decode(), off.value, size.value, lib.smd_layout_type_at(k).decode()))
    return out


# C type names a ctypes scalar mirrors (smd_real is float in the default build)
_C_TYPES = {ct.c_float: {"smd_real", "float"}, ct.c_double: {"double"}, ct.c_int: {"int"},
            ct.c_uint64: {"uint64_t"}, ct.c_uint32: {"uint32_t"}, ct.c_void_p: {"*"}}


def _c_type_ok(t, c_type: str) -> bool:
    """Whether ctypes type t (or its array element type) mirrors C type c_type."""
    while hasattr(t, "_length_"):
        t = t._type_
    if isinstance(t, type) and issubclass(t, ct.Structure):
        return getattr(t, "_c_name_", None) == c_type
    return c_type in _C_TYPES.get(t, set())


def layout_errors(table: dict[str, list[tuple[str, int, int]]] | None = None,
                  mirrors: dict[str, type[ct.Structure]] | None = None) -> list[str]:
    """Every disagreement between a ctypes mirror and the C layout."""
    table = layout_table() if table is None else table
    mirrors = MIRRORS if mirrors is None else mirrors
    errors = []
    for c_name, cls in mirrors.items():
        rows = table.get(c_name)
        if rows is None:
            errors.append(f"{c_name}: not in the library's layout table")
            continue
        (_, _, c_size, _), c_fields = rows[0], rows[1:]
        # a C field named like a Python keyword is mirrored with a trailing _
        py = [(name[:-1] if keyword.iskeyword(name[:-1]) else name, getattr(cls, name).offset,
               getattr(cls, name).size, typ) for name, typ, *_ in cls._fields_]
        if getattr(cls, "_prefix_", False):  # a head: the leading fields only
            c_fields, c_size = c_fields[:len(py)], ct.sizeof(cls)
        if [f[0] for f in py] != [f[0] for f in c_fields]:
            errors.append(f"{c_name}: fields {[f[0] for f in py]} in Python, "
                          f"{[f[0] for f in c_fields]} in C")
            continue
        for (name, o_py, s_py, t_py), (_, o_c, s_c, t_c) in zip(py, c_fields):
            if (o_py, s_py) != (o_c, s_c):
                errors.append(f"{c_name}.{name}: offset/size {o_py}/{s_py} in Python, "
                              f"{o_c}/{s_c} in C")
            elif not _c_type_ok(t_py, t_c):
                errors.append(f"{c_name}.{name}: {getattr(t_py, '__name__', t_py)} in Python, "
                              f"{t_c} in C")
        if ct.sizeof(cls) != c_size:
            errors.append(f"{c_name}: sizeof {ct.sizeof(cls)} in Python, {c_size} in C")
    return errors


N_LOG = 45
LOG_CHANNELS: tuple[str, ...] = tuple(lib.smd_log_channel_name(i).decode() for i in range(N_LOG))


def check_layout() -> None:
    """Raise ImportError if a mirror disagrees with the compiled library."""
    errors = layout_errors()
    if LOG_CHANNELS[-1] != "fault" or "" in LOG_CHANNELS or lib.smd_log_channel_name(N_LOG):
        errors.append(f"log channel table: expected {N_LOG} channels ending in 'fault'")
    if errors:
        raise ImportError("smodrive binding out of date with its C library:\n  "
                          + "\n  ".join(errors))


check_layout()
ENGINE_SIZE: int = lib.smd_sizeof_engine()
