"""ctypes binding to the compiled C library (firmware core + host engine).

The struct mirrors are generated from the C headers by
``tools/gen_layout.py`` (:mod:`._structs`, each naming its C struct in
``_c_name_``). At import, :func:`check_layout` compares each mirror field by
field (name, offset, size, declared type, order) with the table the library
exports (``sim/src/smd_layout.c``, generated from the same headers and laid
out by the compiler), and the log channel names with the library's, so a
library built from other headers than the mirrors fails at import instead of
corrupting memory.
"""

from __future__ import annotations

import ctypes as ct
import keyword
import os
from pathlib import Path

from ._codes import LOG_CHANNELS as _LOG_CHANNELS
from ._codes import N_LOG
from ._structs import (  # noqa: F401 (the mirrors, re-exported)
    MIRRORS, SMD_LCL_SMO_DELAY, SMD_PWL_MAX, Bandpass, Cplx, DbpcParams, DriveConfig, DriveIn,
    DriveOut, DriveView, EmfPosParams, EmfPosState, EngineStart, IdentLsConfig, IdentLsParams,
    IdentLsState, IdentMechConfig, IdentMechParams, IdentMechState, IdentPsiConfig, IdentPsiParams, IdentPsiState, IdentRsConfig, IdentRsParams, IdentRsState, LclModel, LinConfig, LinModel,
    LinParams, LinState, PiParams, PiState, PlantConfig, PlantHead, PllParams, PllState, Profiles,
    Pwl, SmdoParams, SmdoState, SmoConfig, SmoParams, SmoState, SvmParams, real,
)


#: the builds of the core the simulator can run: the exact one (each elementary function
#: from the C library) and the fast one (smodrive/smd_fastmath.h, docs/firmware.md)
MATHS = {"exact": "libsmodrive", "fast": "libsmodrive_fast"}


def _math() -> str:
    """The build SMODRIVE_MATH asks for ("exact" when unset)."""
    m = os.environ.get("SMODRIVE_MATH", "exact") or "exact"
    if m not in MATHS:
        raise ImportError(f"SMODRIVE_MATH = {m!r}: must be one of {', '.join(MATHS)}")
    return m


def _load(math: str) -> ct.CDLL:
    here = Path(__file__).resolve().parent.parent  # the package root, where the wheel puts it
    for suffix in (".so", ".dylib"):
        cand = here / (MATHS[math] + suffix)
        if cand.exists():
            return ct.CDLL(str(cand))
    raise ImportError(
        f"smodrive's compiled library ({MATHS[math]}, the {math} build) was not found in "
        f"{here}; install the package with 'pip install .' so that its C core is built"
    )


#: the build this process runs (fixed at import: SMODRIVE_MATH)
MATH = _math()
lib = _load(MATH)

# The mirrors, one a C struct, are generated from the headers
# (src/smodrive/engine/_structs.py by tools/gen_layout.py).
SMO_DELAY = SMD_LCL_SMO_DELAY
PWL_MAX = SMD_PWL_MAX
#: the fields of smd_lcl_model: (name, floats)
MODEL_FIELDS: tuple[tuple[str, int], ...] = tuple(
    (n, ct.sizeof(t) // ct.sizeof(real)) for n, t in LclModel._fields_)
N_MODEL = ct.sizeof(LclModel) // ct.sizeof(real)  # floats in smd_lcl_model
N_LIN = ct.sizeof(LinModel) // ct.sizeof(real)  # floats in smd_linobs_model


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
_sig("smd_engine_run_ident_rs", ct.c_long, ct.c_void_p, P(IdentRsParams), P(IdentRsState),
     ct.c_long, P(ct.c_double), ct.c_long)
_sig("smd_ident_rs_init", ct.c_int, P(IdentRsParams), P(IdentRsConfig))
_sig("smd_ident_rs_reset", None, P(IdentRsState))
_sig("smd_engine_run_ident_ls", ct.c_long, ct.c_void_p, P(IdentLsParams), P(IdentLsState),
     ct.c_long)
_sig("smd_engine_rotor_angle", ct.c_double, ct.c_void_p)
_sig("smd_ident_ls_init", ct.c_int, P(IdentLsParams), P(IdentLsConfig))
_sig("smd_ident_ls_reset", None, P(IdentLsState))
_sig("smd_engine_run_ident_psi", ct.c_long, ct.c_void_p, P(IdentPsiParams), P(IdentPsiState),
     ct.c_long)
_sig("smd_engine_rotor_speed", ct.c_double, ct.c_void_p)
_sig("smd_ident_psi_init", ct.c_int, P(IdentPsiParams), P(IdentPsiConfig))
_sig("smd_ident_psi_reset", None, P(IdentPsiState))
_sig("smd_engine_run_ident_mech", ct.c_long, ct.c_void_p, P(IdentMechParams),
     P(IdentMechState), ct.c_long, P(ct.c_double), ct.c_long)
_sig("smd_ident_mech_init", ct.c_int, P(IdentMechParams), P(IdentMechConfig))
_sig("smd_ident_mech_reset", None, P(IdentMechState))
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
_sig("smd_lcl_smo_init", ct.c_int, P(SmoParams), real, P(SmoConfig))
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


#: the channel names the library gives (smd_log_channel_name), in row order
LOG_CHANNELS: tuple[str, ...] = tuple(lib.smd_log_channel_name(i).decode() for i in range(N_LOG))


def check_layout() -> None:
    """Raise ImportError if a mirror or the log channels disagree with the
    compiled library."""
    errors = layout_errors()
    names = tuple(c[0] for c in _LOG_CHANNELS)
    if LOG_CHANNELS != names or lib.smd_log_channel_name(N_LOG):
        errors.append(f"log channel table: the library's names {LOG_CHANNELS} (and "
                      f"{lib.smd_log_channel_name(N_LOG)!r} after them), the headers' {names}")
    if errors:
        raise ImportError("smodrive binding out of date with its C library:\n  "
                          + "\n  ".join(errors))


check_layout()
ENGINE_SIZE: int = lib.smd_sizeof_engine()
