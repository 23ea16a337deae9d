"""The ctypes binding (smodrive.engine._ffi) against the compiled library.

Every mirror is checked field by field (name, offset, size, order) against
the layout table that sim/src/smd_layout.c exports (generated from the
headers by tools/gen_layout.py, laid out by the compiler). The tests here
show that the check passes on the real mirrors, that it catches each kind of
drift (two fields swapped, a field missing, a field of the wrong type) and
turns it into an ImportError, that the committed table is current, and that
the log channels are described.
"""

from __future__ import annotations

import ctypes as ct
import dataclasses
import importlib.util
import os
import subprocess
import sys
import types
from pathlib import Path

import pytest

from smodrive.design import cheader, yao2022
from smodrive.design.observer_layout import OBSERVER_FIELDS
from smodrive.engine import _codes
from smodrive.engine import _ffi as F
from smodrive.engine._structs import DESIGN_FIELDS
from smodrive.engine import CHANNEL_INFO, CHANNELS, marshal
from smodrive.scenarios import catalogue

ROOT = Path(__file__).resolve().parents[1]
# the folder of the smodrive this process imported (installed, or src/ with PYTHONPATH):
# the generators' subprocesses import the same one
PKG_PATH = str(Path(F.__file__).resolve().parents[2])
real = F.real


def _copy(cls: type[ct.Structure], fields: list) -> type[ct.Structure]:
    return type(f"Drifted{cls.__name__}", (ct.Structure,), {"_fields_": fields})


def _swapped(cls: type[ct.Structure], a: str, b: str) -> type[ct.Structure]:
    """A copy of mirror cls with fields a and b exchanged."""
    fields = list(cls._fields_)
    names = [n for n, *_ in fields]
    i, j = names.index(a), names.index(b)
    fields[i], fields[j] = fields[j], fields[i]
    return _copy(cls, fields)


# ------------------------------------------------------- the real mirrors --

def test_every_mirror_matches_the_library():
    assert F.layout_errors() == []
    F.check_layout()  # raises ImportError on any mismatch


def test_every_mirrored_struct_is_in_the_table_and_vice_versa():
    """The table has a row for each mirror (so none is checked against
    nothing), and gen_layout mirrors no struct the binding lacks."""
    table = F.layout_table()
    assert set(table) == set(F.MIRRORS)
    assert len(F.MIRRORS) >= 27
    for name, rows in table.items():
        assert rows[0][0] == "" and rows[0][2] > 0, name  # the struct's own size first
        assert len(rows) >= 2, name


def test_sizes_the_library_exports_agree():
    assert F.lib.smd_sizeof_plant_config() == ct.sizeof(F.PlantConfig)
    sizes = {name: rows[0][2] for name, rows in F.layout_table().items()}
    for name in ("smd_drive_config", "smd_profiles", "smd_plant_config", "smd_drive_view"):
        assert sizes[name] == ct.sizeof(F.MIRRORS[name]), name
    # the plant is mirrored by its head only: the C struct is longer
    assert sizes["smd_plant"] == F.lib.smd_sizeof_plant() > ct.sizeof(F.PlantHead)
    assert F.ENGINE_SIZE == F.lib.smd_sizeof_engine() > 0


# --------------------------------------------------------- drifted mirrors --

@pytest.mark.parametrize("c_name,cls,a,b", [
    ("smd_smdo_params", F.SmdoParams, "L_s_hat", "R_s_hat"),
    ("smd_drive_config", F.DriveConfig, "k_p_i", "k_i_i"),
    ("smd_pll_params", F.PllParams, "k_omega", "k_a"),
    ("smd_plant_config", F.PlantConfig, "L1", "L2o"),
])
def test_two_swapped_float_fields_are_caught_naming_them(c_name, cls, a, b):
    """Two adjacent fields of the same type swapped: every offset and size
    still agrees, only the order tells (a run would silently exchange the
    two gains)."""
    Swapped = _swapped(cls, a, b)
    assert ct.sizeof(Swapped) == ct.sizeof(cls)
    errors = F.layout_errors(mirrors={c_name: Swapped})
    assert len(errors) == 1
    msg = errors[0]
    assert msg.startswith(f"{c_name}: fields ")
    py, c = msg.split(" in Python, ")
    assert py.index(repr(b)) < py.index(repr(a))  # the mirror's order ...
    assert c.index(repr(a)) < c.index(repr(b))    # ... and the header's
    assert F.layout_errors(mirrors={c_name: cls}) == []


def test_a_missing_field_is_caught():
    fields = [f for f in F.SmdoParams._fields_ if f[0] != "rho"]
    errors = F.layout_errors(mirrors={"smd_smdo_params": _copy(F.SmdoParams, fields)})
    assert len(errors) == 1 and errors[0].startswith("smd_smdo_params: fields ")
    assert "'rho'" in errors[0].split(" in Python, ")[1]


@pytest.mark.parametrize("c_name,cls,field,typ", [
    ("smd_drive_config", F.DriveConfig, "T_sp", ct.c_double),  # float build: smd_real is float
    ("smd_lcl_smo_config", F.SmoConfig, "n", ct.c_int64),
    ("smd_plant_config", F.PlantConfig, "seed", ct.c_uint32),
    ("smd_smdo_state", F.SmdoState, "u_smo", real * 3),
])
def test_a_field_of_the_wrong_type_is_caught(c_name, cls, field, typ):
    """A field of another size than in C: its own size disagrees (and the
    offsets of the fields after it, and the struct's size)."""
    old = dict((n, t) for n, t, *_ in cls._fields_)[field]
    assert ct.sizeof(typ) != ct.sizeof(old)
    fields = [(n, typ) if n == field else (n, t) for n, t, *_ in cls._fields_]
    errors = F.layout_errors(mirrors={c_name: _copy(cls, fields)})
    assert errors[0].startswith(f"{c_name}.{field}: offset/size "), errors
    assert f"/{ct.sizeof(typ)} in Python, " in errors[0]
    assert errors[0].endswith(f"/{ct.sizeof(old)} in C")


@pytest.mark.parametrize("c_name,cls,field,typ", [
    ("smd_drive_config", F.DriveConfig, "current", real),      # int -> float, both 4 bytes
    ("smd_drive_config", F.DriveConfig, "T_sp", ct.c_int),     # float -> int
    ("smd_plant_config", F.PlantConfig, "seed", ct.c_double),  # uint64_t -> double
    ("smd_lcl_smo_config", F.SmoConfig, "table", ct.c_uint64),  # pointer -> integer
])
def test_a_field_of_the_same_size_but_another_type_is_caught(c_name, cls, field, typ):
    """The table carries each field's declared type, so an int mirrored as
    a float (same size, same offsets) is caught by name."""
    old = dict((n, t) for n, t, *_ in cls._fields_)[field]
    assert ct.sizeof(typ) == ct.sizeof(old)
    fields = [(n, typ) if n == field else (n, t) for n, t, *_ in cls._fields_]
    errors = F.layout_errors(mirrors={c_name: _copy(cls, fields)})
    assert len(errors) == 1 and errors[0].startswith(f"{c_name}.{field}: "), errors
    assert errors[0].endswith(" in C") and "offset/size" not in errors[0]


def test_a_struct_the_library_does_not_know_is_caught():
    class Stray(ct.Structure):
        _fields_ = [("x", real)]

    assert F.layout_errors(mirrors={"smd_no_such_struct": Stray}) == [
        "smd_no_such_struct: not in the library's layout table"]


def test_a_drifted_head_is_caught():
    """PlantHead is checked as a prefix of struct smd_plant: a swap inside
    the prefix is caught although the C struct goes on."""
    Swapped = _swapped(F.PlantHead, "i_re", "i_im")
    Swapped._prefix_ = True
    errors = F.layout_errors(mirrors={"smd_plant": Swapped})
    assert len(errors) == 1 and errors[0].startswith("smd_plant: fields ")


def test_check_layout_raises_import_error_on_a_drifted_mirror(monkeypatch):
    Swapped = _swapped(F.SmdoParams, "L_s_hat", "R_s_hat")
    monkeypatch.setattr(F, "MIRRORS", {**F.MIRRORS, "smd_smdo_params": Swapped})
    with pytest.raises(ImportError) as ei:
        F.check_layout()
    msg = str(ei.value)
    assert msg.startswith("smodrive binding out of date with its C library")
    assert "smd_smdo_params: fields" in msg
    monkeypatch.undo()
    F.check_layout()  # the real mirrors pass again


# ------------------------------------------------ mirrors written by C ----

GUARD = 0xA5


def _guarded(cls):
    """A struct inside a buffer with GUARD bytes after it."""
    n = ct.sizeof(cls)
    buf = (ct.c_ubyte * (n + 64))(*([GUARD] * (n + 64)))
    return cls.from_buffer(buf), buf, n


@pytest.mark.parametrize("cls,call", [
    (F.DbpcParams, lambda p: F.lib.smd_dbpc_init(p, 1e-4, 0.02, 2.0, 0.4)),
    (F.SmdoParams, lambda p: F.lib.smd_smdo_init(p, 1e-4, 0.02, 2.0, 800.0, 1200.0, 1500.0, 0.2)),
    (F.PiParams, lambda p: F.lib.smd_pi_init(p, 0.1, 10.0, 1e-4, 15.0)),
    (F.SvmParams, lambda p: F.lib.smd_svm_init(p, 1, 0.01)),
    (F.EmfPosParams, lambda p: F.lib.smd_emf_pos_init(p, 1e-4, 200.0, 5.0, 1000.0)),
    (F.SmdoState, lambda s: F.lib.smd_smdo_reset(s, F.Cplx(1.0, 2.0), F.Cplx(3.0, 4.0))),
    (F.PiState, lambda s: F.lib.smd_pi_reset(s, 1.0)),
    (F.EmfPosState, lambda s: F.lib.smd_emf_pos_reset(s, 10.0)),
])
def test_block_struct_mirrors_match_c(cls, call):
    """Independently of the table: C must write every mirrored field (mirror
    not too long) and nothing beyond it (not too short)."""
    obj, buf, n = _guarded(cls)
    rc = call(ct.byref(obj))
    assert rc in (None, 0)
    assert bytes(buf[n:]) == bytes([GUARD]) * 64, "C wrote past the Python struct"
    raw = bytes(buf[:n])
    for name, typ in cls._fields_:
        off = getattr(cls, name).offset
        size = ct.sizeof(typ)
        assert raw[off:off + size] != bytes([GUARD]) * size, f"{cls.__name__}.{name} unwritten"


# ------------------------------------------------ the generated files ----

def _gen_layout():
    spec = importlib.util.spec_from_file_location("gen_layout", ROOT / "tools" / "gen_layout.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["gen_layout"] = mod  # its dataclasses look their module up
    spec.loader.exec_module(mod)
    return mod


GEN = _gen_layout()
GENERATED = [rel for rel, _ in GEN.outputs()]


def test_every_generator_check_passes_on_the_committed_files():
    """Each generator in check mode: the committed generated files are what
    the generators write from the schema (the annotated headers; the model
    dataclasses for the parameter tables of the docs)."""
    for tool in ("gen_layout.py", "gen_parameters.py"):
        res = subprocess.run([sys.executable, str(ROOT / "tools" / tool), "--check"],
                             capture_output=True, text=True, cwd=ROOT,
                             env={**os.environ, "PYTHONPATH": PKG_PATH})
        assert res.returncode == 0, (tool, res.stdout, res.stderr)
    assert GEN.stale() == []


def test_generated_files_say_so():
    for rel, text in GEN.outputs():
        head = text[:200]
        assert "Generated by tools/gen_layout.py" in head and "do not edit" in head, rel


@pytest.mark.parametrize("rel", GENERATED)
def test_check_fails_on_a_planted_stale_edit(rel, tmp_path):
    """A copy of the committed generated files passes the check; one line of
    one file removed (a field or channel missing, as a file not regenerated
    after a header change has it) fails it, naming that file, and the check
    writes nothing."""
    for other in GENERATED:
        (tmp_path / other).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / other).write_text((ROOT / other).read_text())
    assert GEN.stale(ROOT, tmp_path) == []
    path = tmp_path / rel
    lines = path.read_text().split("\n")
    del lines[len(lines) // 2]
    planted = "\n".join(lines)
    path.write_text(planted)
    assert GEN.stale(ROOT, tmp_path) == [rel]
    assert path.read_text() == planted


def test_check_fails_on_a_header_change_not_regenerated(tmp_path):
    """The other way round: a header changed (a log channel renamed) without
    running the generator leaves the committed files stale."""
    for rel in GEN.HEADERS:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text((ROOT / rel).read_text())
    h = tmp_path / "sim/include/smdsim/smd_engine.h"
    h.write_text(h.read_text().replace("@log(w_hat, rad/s)", "@log(w_hat_e, rad/s)"))
    assert GEN.stale(tmp_path, ROOT) == ["src/smodrive/engine/_codes.py",
                                         "sim/src/smd_log_names.h"]


@pytest.mark.parametrize("header,old,new,what", [
    ("core/include/smodrive/smd_drive.h", "    int restart_window;",
     "    smd_real w_new;\n    int restart_window;", "smd_drive_config.w_new has no @fuzz"),
    ("sim/include/smdsim/smd_engine.h", "    SMD_LOG_N\n",
     "    SMD_LOG_NEW,\n    SMD_LOG_N\n", "SMD_LOG_NEW has no @log"),
    ("sim/include/smdsim/smd_plant.h", "    SMD_PF_N ",
     "    SMD_PF_NEW = 33, /* @scenario(motor.R_s) */\n    SMD_PF_N ", 'SMD_PF_NEW has no "name"'),
    ("core/include/smodrive/smd_lcl_smo.h", "@design(K_y)", "", "smd_lcl_model.Ky has no @design"),
])
def test_a_declaration_without_its_annotation_stops_the_generator(header, old, new, what,
                                                                   tmp_path):
    """A field or entry added to a boundary without the annotation its other
    copies need is refused, named, instead of generating a partial copy."""
    for rel in GEN.HEADERS:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text((ROOT / rel).read_text())
    h = tmp_path / header
    assert old in h.read_text()
    h.write_text(h.read_text().replace(old, new, 1))
    with pytest.raises(SystemExit, match=what):
        GEN.outputs(tmp_path)


def test_gen_layout_mirrors_what_the_binding_mirrors():
    gen = GEN
    assert set(gen.MIRRORED) == set(F.MIRRORS)
    fields = gen.structs()
    # the parsed headers give the mirrors' field names in order (a C field
    # named like a Python keyword, lambda, is mirrored as lambda_)
    for c_name, cls in F.MIRRORS.items():
        py = [n[:-1] if n.endswith("_") else n for n, *_ in cls._fields_]
        c = [f for f, _ in fields[c_name]]
        c = c[:len(py)] if getattr(cls, "_prefix_", False) else c
        assert py == c, c_name


# ------------------------------------------------------- log channels -----

def test_log_channel_table():
    assert F.N_LOG == 50
    assert len(CHANNELS) == len(set(CHANNELS)) == 50
    assert CHANNELS[0] == "t" and CHANNELS[-1] == "fault"
    # outside the table the name is "" (what check_layout relies on)
    assert F.lib.smd_log_channel_name(50) == F.lib.smd_log_channel_name(-1) == b""
    assert all(F.lib.smd_log_channel_name(k) for k in range(50))


DIMENSIONLESS = {"phase", "status", "fault"}


def test_every_channel_has_a_unit_and_a_description():
    assert set(CHANNEL_INFO) == set(CHANNELS)
    for name in CHANNELS:
        unit, doc = CHANNEL_INFO[name]
        assert isinstance(unit, str) and isinstance(doc, str)
        assert (unit == "") == (name in DIMENSIONLESS), name
        assert len(doc) >= 10, name
    # the motor current is i_* for both plants; the filter's are i1_*, uc_*
    for name in ("i_alpha", "i_beta", "i_d", "i_q", "i_g", "i_dl", "i_d_ref", "i_q_ref",
                 "i1_alpha", "i1_beta", "uc_alpha", "uc_beta"):
        assert name in CHANNELS, name
    for old in ("i2_g", "i2_dl", "i_ref_g", "i_ref_dl", "i2_alpha", "i2_d", "i2_q"):
        assert old not in CHANNELS, old
    assert CHANNEL_INFO["w_M"][0] == "rad/s" and CHANNEL_INFO["theta_r"][0] == "rad"
    assert CHANNEL_INFO["T_e"][0] == "N m" and CHANNEL_INFO["u_alpha"][0] == "V"


# ------------------------------------------ drive_config fills every field --

def _scenarios():
    cat = catalogue()
    return [cat[n]() for n in ("yang2018.base", "drive.if_start", "yao2022.fig22")]


def test_drive_config_sets_every_field_of_the_header():
    """drive_config builds smd_drive_config from a complete field -> value
    map (else it raises): every field of the header, the LCL observers' too."""
    for s in _scenarios():
        tables = marshal.lcl_observer_tables(s) if s.lcl is not None else None
        c = marshal.drive_config(s, tables)
        assert isinstance(c, F.DriveConfig)
        if tables is not None:
            assert c.smo.n == c.lin.n == tables[0].shape[0] and c.smo.table and c.lin.table


def test_drive_config_fails_loudly_on_a_field_the_header_gains(monkeypatch):
    """A field added to smd_drive_config (the mirror is regenerated from the
    header) that drive_config does not set raises, naming it, instead of
    going to C as 0."""

    class Grown(ct.Structure):
        _c_name_ = "smd_drive_config"
        _fields_ = list(F.DriveConfig._fields_) + [("w_new_limit", real)]

    monkeypatch.setattr(marshal._ffi, "DriveConfig", Grown)
    with pytest.raises(RuntimeError, match=r"unset: w_new_limit \("):
        marshal.drive_config(_scenarios()[0])


def test_drive_config_fails_loudly_when_an_assignment_is_dropped():
    """marshal.py with one field's assignment deleted (a planted slip, run
    as a copy of the module): the call raises naming the field."""
    src = (ROOT / "src/smodrive/engine/marshal.py").read_text()
    line = "        osc_i=k.osc_i, osc_rel=k.osc_rel,\n"
    assert src.count(line) == 1
    mod = types.ModuleType("smodrive.engine._planted_marshal")
    mod.__package__ = "smodrive.engine"
    exec(compile(src.replace(line, "        osc_i=k.osc_i,\n"), "planted_marshal", "exec"),
         mod.__dict__)
    with pytest.raises(RuntimeError, match=r"drive_config .* smd_drive_config .*unset: osc_rel"):
        mod.drive_config(_scenarios()[0])


# ------------------------------------------------ observer-table layout --

def test_observer_layout_is_the_one_list():
    """ObserverMatrices, DesignTables, MATRIX_FIELDS, cheader.REALTIME_FIELDS
    and the packing (the headers' @design annotations) all come from
    OBSERVER_FIELDS."""
    names = tuple(n for n, *_ in OBSERVER_FIELDS)
    assert yao2022.MATRIX_FIELDS == names
    assert [f.name for f in dataclasses.fields(yao2022.ObserverMatrices)] == ["w", *names]
    assert [f.name for f in dataclasses.fields(yao2022.DesignTables)] == [
        "speeds_rpm", "w", *names, "plant", "design"]
    assert cheader.REALTIME_FIELDS == ("w",) + tuple(n for n, _, _, rt in OBSERVER_FIELDS if rt)
    assert marshal.packing_errors() == []
    packed = [name for rows in DESIGN_FIELDS.values() for _, name, _ in rows]
    assert set(packed) <= set(names) and len(packed) == len(set(packed))
    # the C models hold exactly what is packed, in C order
    for c_name, rows in DESIGN_FIELDS.items():
        assert [r[0] for r in rows] == [n for n, *_ in F.MIRRORS[c_name]._fields_]


@pytest.mark.parametrize("planted,what", [
    ((("Ft", "T_r", ((2, 6), (2, 5))),), "12 in T_r"),       # a block of the wrong size
    ((("Ft", "T_rr", ((2, 6), (2, 6))),), "no real field"),  # a design field that is not
    ((("Ft", "N_2", None),), "no real field"),               # an integer field
    ((("Ft", "G", None),), "36 in G"),                       # a whole field of another size
    ((("Ft", "H", ((2, 6), (2, 6))),), "outside H"),          # a block outside the field
])
def test_packing_check_catches_a_drifted_annotation(planted, what):
    """An @design annotation that does not fit the design list (what the
    import-time check of smodrive.engine.marshal reports)."""
    rows = tuple(r if r[0] != "Ft" else planted[0] for r in DESIGN_FIELDS["smd_lcl_model"])
    errors = marshal.packing_errors({"smd_lcl_model": rows})
    assert len(errors) == 1 and errors[0].startswith("smd_lcl_model.Ft: ") and what in errors[0]


def test_fuzz_seeds_are_current():
    """fuzz/make_seeds.py --check: the committed seeds are what the seed
    writer gives from the generated field list and the package (a change of
    smd_drive_config's fuzz format needs the seeds written again)."""
    res = subprocess.run([sys.executable, str(ROOT / "fuzz" / "make_seeds.py"), "--check"],
                         capture_output=True, text=True, cwd=ROOT,
                         env={**os.environ, "PYTHONPATH": PKG_PATH})
    assert res.returncode == 0, res.stderr


# ------------------------------------------------------ plant field codes --

def test_each_plant_field_code_is_the_one_smd_plant_init_returns():
    """The enum smd_plant_field_code (the schema of the codes, their names
    and scenario fields) against smd_plant_init's checks: each field made
    bad in turn gives the code the enum names for it."""
    cat = catalogue()
    plain = marshal.plant_config(cat["yang2018.base"]())
    lcl = marshal.plant_config(cat["drive.lcl_encoder"]())
    nan = float("nan")
    cases = {}  # code -> (config, field, bad value, index)
    for name in ("R_s", "L_s", "psi_r", "n_p", "J", "B", "u_dc", "T_sw", "t_dead", "adc_noise",
                 "adc_full_scale", "w_brake_eps", "k_fan", "w_M0", "theta_r0"):
        cases[name] = (plain, name, nan, None)
    for name in ("L1", "L2o", "C1"):
        cases[name] = (lcl, name, nan, None)
    for name in ("adc_gain", "adc_offset"):
        cases[name] = (plain, name, nan, 0)
    for name in ("adc_gain_i1", "adc_offset_i1"):
        cases[name] = (lcl, name, nan, 2)
    cases.update({"lcl": (plain, "lcl", 2, None), "pwm_mode": (plain, "pwm_mode", 7, None),
                  "adc_bits": (plain, "adc_bits", 25, None),
                  "i_d0/i_q0": (plain, "i_q0", 2e5, None),
                  "uc_d0/uc_q0": (lcl, "uc_d0", nan, None),
                  "i1_d0/i1_q0": (lcl, "i1_q0", -2e5, None),
                  "dead_time_model": (lcl, "dead_time_model", 2, None),
                  "adc_n_oversample": (plain, "adc_n_oversample", 65, None),
                  "adc_sensors": (plain, "adc_sensors", 1, None)})
    buf = (ct.c_double * (F.lib.smd_sizeof_plant() // 8 + 1))()
    assert F.lib.smd_plant_init(buf, ct.byref(plain)) == _codes.SMD_PF_OK
    assert F.lib.smd_plant_init(buf, ct.byref(lcl)) == _codes.SMD_PF_OK
    codes = {name: code for code, name in _codes.PLANT_FIELD_NAMES.items()}
    checked = set()
    for name, (base, field, value, index) in cases.items():
        c = type(base).from_buffer_copy(base)
        if index is None:
            setattr(c, field, value)
        else:
            getattr(c, field)[index] = value
        assert F.lib.smd_plant_init(buf, ct.byref(c)) == codes[name], name
        assert F.lib.smd_plant_field(codes[name]).decode() == name
        checked.add(codes[name])
    # every code but ok and the filter's modes (a property of several fields)
    assert checked == set(range(1, _codes.SMD_PF_N)) - {_codes.SMD_PF_MODES}
    assert F.lib.smd_plant_field(_codes.SMD_PF_N) == b"unknown"
