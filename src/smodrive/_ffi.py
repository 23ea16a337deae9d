"""ctypes binding to the compiled C library (firmware core + host engine).

The struct mirrors below must match the C headers; :func:`check_layout`
compares their sizes with the ones the library reports and is run at import.
"""

from __future__ import annotations

import ctypes as ct
from pathlib import Path

real = ct.c_float  # smd_real of the default (float) build


def _load() -> ct.CDLL:
    here = Path(__file__).resolve().parent
    for cand in (here / "libsmodrive.so", here / "libsmodrive.dylib"):
        if cand.exists():
            return ct.CDLL(str(cand))
    raise ImportError(
        f"smodrive's compiled library was not found in {here}; install the package with "
        "'pip install .' so that its C core is built"
    )


lib = _load()


class Cplx(ct.Structure):
    _fields_ = [("re", real), ("im", real)]

    @classmethod
    def of(cls, z: complex) -> "Cplx":
        return cls(float(z.real), float(z.imag))

    def __complex__(self) -> complex:
        return complex(self.re, self.im)


class DriveConfig(ct.Structure):
    _fields_ = [
        ("mode", ct.c_int),
        ("T_sp", real),
        ("L_s_hat", real),
        ("R_s_hat", real),
        ("psi_r_hat", real),
        ("lambda_min", real),
        ("l", real),
        ("w_c", real),
        ("rho", real),
        ("k_p", real),
        ("k_i", real),
        ("i_max", real),
        ("speed_decimation", ct.c_int),
        ("speed_loop", ct.c_int),
        ("w_lpf", real),
        ("w_hys", real),
        ("svm_limit", ct.c_int),
        ("w_max", real),
        ("handover", ct.c_int),
        ("t_dead_comp", real),
        ("i_dtc", real),
        ("smdo_euler", ct.c_int),
    ]


class PlantConfig(ct.Structure):
    _fields_ = [
        ("R_s", ct.c_double),
        ("L_s", ct.c_double),
        ("psi_r", ct.c_double),
        ("n_p", ct.c_double),
        ("J", ct.c_double),
        ("B", ct.c_double),
        ("u_dc", ct.c_double),
        ("T_sw", ct.c_double),
        ("pwm_mode", ct.c_int),
        ("t_dead", ct.c_double),
        ("adc_gain", ct.c_double * 3),
        ("adc_offset", ct.c_double * 3),
        ("adc_noise", ct.c_double),
        ("adc_bits", ct.c_int),
        ("adc_full_scale", ct.c_double),
        ("seed", ct.c_uint64),
        ("w_brake_eps", ct.c_double),
        ("k_fan", ct.c_double),
        ("w_M0", ct.c_double),
        ("theta_r0", ct.c_double),
        ("i_d0", ct.c_double),
        ("i_q0", ct.c_double),
    ]


PWL_MAX = 64


class Pwl(ct.Structure):
    _fields_ = [("n", ct.c_int), ("t", ct.c_double * PWL_MAX), ("y", ct.c_double * PWL_MAX)]


class Profiles(ct.Structure):
    _fields_ = [
        ("w_M_ref", Pwl),
        ("T_ext", Pwl),
        ("T_brake", Pwl),
        ("i_d_ref", Pwl),
        ("i_q_ref", Pwl),
        ("i_d_sin_amp", ct.c_double),
        ("i_d_sin_freq", ct.c_double),
    ]


# Block-level structs (used by the tests and by users who script blocks).
class DbpcParams(ct.Structure):
    _fields_ = [("T_sp", real), ("L_s_hat", real), ("R_s_hat", real), ("psi_r_hat", real)]


class SmdoParams(ct.Structure):
    _fields_ = [
        ("T_sp", real),
        ("L_s_hat", real),
        ("R_s_hat", real),
        ("lambda_min", real),
        ("l", real),
        ("w_c", real),
        ("rho", real),
        ("euler", ct.c_int),
    ]


class SmdoState(ct.Structure):
    _fields_ = [
        ("i_s_hat", Cplx),
        ("u_d_hat", Cplx),
        ("e_i_prev", Cplx),
        ("u_smo_prev", Cplx),
        ("u_smo", Cplx),
        ("lambda_", real),
    ]


class PiParams(ct.Structure):
    _fields_ = [("k_p", real), ("k_i", real), ("T_s", real), ("y_max", real)]


class PiState(ct.Structure):
    _fields_ = [("x_i", real), ("y", real)]


class SvmParams(ct.Structure):
    _fields_ = [("limit", ct.c_int), ("d_min", real)]


class EmfPosParams(ct.Structure):
    _fields_ = [
        ("T_sp", real),
        ("w_lpf", real),
        ("a_lpf", real),
        ("a_dir", real),
        ("w_hys", real),
        ("w_max", real),
    ]


class EmfPosState(ct.Structure):
    _fields_ = [
        ("phi_prev", real),
        ("w_r_raw", real),
        ("w_r_hat", real),
        ("w_r_dir", real),
        ("theta_r_hat", real),
        ("dir", ct.c_int),
        ("primed", ct.c_int),
    ]


def _sig(name: str, restype, *argtypes) -> None:
    f = getattr(lib, name)
    f.restype = restype
    f.argtypes = list(argtypes)


P = ct.POINTER
_sig("smd_status_str", ct.c_char_p, ct.c_int)
_sig("smd_plant_field", ct.c_char_p, ct.c_int)
_sig("smd_log_channel_name", ct.c_char_p, ct.c_int)
for _n in ("engine", "plant_config", "drive_config", "profiles"):
    _sig(f"smd_sizeof_{_n}", ct.c_ulong)
_sig("smd_sizeof_block", ct.c_ulong, ct.c_int)
_sig("smd_engine_init", ct.c_int, ct.c_void_p, P(PlantConfig), P(DriveConfig), P(Profiles))
_sig("smd_engine_run", ct.c_long, ct.c_void_p, ct.c_long, P(ct.c_double), ct.c_long)
_sig("smd_sizeof_plant", ct.c_ulong)
_sig("smd_plant_init", ct.c_int, ct.c_void_p, P(PlantConfig))
_sig("smd_plant_step", None, ct.c_void_p, P(ct.c_double), ct.c_double, ct.c_double)
_sig("smd_plant_sample", None, ct.c_void_p, P(ct.c_double))
_sig("smd_plant_phase_currents", None, ct.c_void_p, P(ct.c_double))
_sig("smd_pwm_leg_edges", None, P(PlantConfig), ct.c_double, ct.c_double, P(ct.c_double),
     P(ct.c_double))
_sig("smd_pwl_eval", ct.c_double, P(Pwl), ct.c_double)
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

N_LOG: int = 26
LOG_CHANNELS: tuple[str, ...] = tuple(
    lib.smd_log_channel_name(i).decode() for i in range(N_LOG)
)


def status_str(code: int) -> str:
    return lib.smd_status_str(code).decode()


def check_layout() -> None:
    """Raise if a ctypes mirror disagrees with the compiled struct size."""
    pairs = {
        "plant_config": PlantConfig,
        "drive_config": DriveConfig,
        "profiles": Profiles,
    }
    blocks = (DbpcParams, SmdoParams, SmdoState, PiParams, PiState, SvmParams, EmfPosParams,
              EmfPosState)
    for k, cls in enumerate(blocks):
        if lib.smd_sizeof_block(k) != ct.sizeof(cls):
            raise ImportError(
                f"smodrive binding out of date: sizeof({cls.__name__}) is "
                f"{lib.smd_sizeof_block(k)} in C and {ct.sizeof(cls)} in Python")
    for name, cls in pairs.items():
        c_size = getattr(lib, f"smd_sizeof_{name}")()
        if c_size != ct.sizeof(cls):
            raise ImportError(
                f"smodrive binding out of date: sizeof({name}) is {c_size} in C and "
                f"{ct.sizeof(cls)} in Python"
            )
    if LOG_CHANNELS[-1] != "status" or "" in LOG_CHANNELS:
        raise ImportError("smodrive binding out of date: log channel table mismatch")


check_layout()
ENGINE_SIZE: int = lib.smd_sizeof_engine()
