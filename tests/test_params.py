"""Parameter validation, TOML loading/serialisation and ctypes layout.

Every numeric field's range comes from its dataclass metadata, so that a field
added later is covered automatically; the tests check that the metadata is
enforced (value just outside rejected, boundaries accepted) and that the error
message lets a user find and fix the value.
"""

from __future__ import annotations

import ctypes as ct
import dataclasses
import math
import string

import pytest
from hypothesis import assume, HealthCheck, example, given, settings
from hypothesis import strategies as st

from smodrive import _ffi as F
from smodrive.params import (
    AdcCfg,
    ControllerCfg,
    InverterCfg,
    LoadCfg,
    MotorPars,
    ParameterError,
    Profile,
    Scenario,
    load_scenario,
    scenario_from_dict,
    scenario_to_toml,
)

CLASSES = {
    "motor": MotorPars,
    "controller": ControllerCfg,
    "inverter": InverterCfg,
    "adc": AdcCfg,
    "load": LoadCfg,
    "scenario": Scenario,
}
SECTIONS = [k for k in CLASSES if k != "scenario"]


def _numeric_fields():
    out = []
    for sec, cls in CLASSES.items():
        for f in dataclasses.fields(cls):
            if "range" in f.metadata:
                out.append((sec, cls, f))
    return out


NUMERIC = _numeric_fields()
NUMERIC_IDS = [f"{sec}.{f.name}" for sec, _, f in NUMERIC]


def _is_int(f: dataclasses.Field) -> bool:
    return f.type in ("int", int)


def _is_tuple(f: dataclasses.Field) -> bool:
    return isinstance(f.default, tuple)


def _just_outside(f: dataclasses.Field) -> list:
    lo, hi, lo_open = f.metadata["range"]
    if _is_int(f):
        return [lo if lo_open else lo - 1, hi + 1]
    return [lo if lo_open else math.nextafter(lo, -math.inf), math.nextafter(hi, math.inf)]


def _with(f: dataclasses.Field, v):
    """Value of field f carrying v (one element of a tuple field)."""
    if _is_tuple(f):
        return f.default[:-1] + (v,)
    return v


def _build(cls, f, v):
    extra = {}
    if cls is Scenario and f.name == "T_sp":
        # a dead time must fit a quarter of the period (cross-field rule,
        # tested separately): at the shortest periods use an ideal inverter
        extra["inverter"] = InverterCfg(t_dead=0.0)
    return cls(**{f.name: _with(f, v)}, **extra)


def test_every_section_has_numeric_fields_and_valid_defaults():
    # guards the parametrisation below against silently covering nothing
    assert len(NUMERIC) >= 40
    for sec, cls in CLASSES.items():
        assert any(s == sec for s, _, _ in NUMERIC)
        cls()  # the defaults are valid


@pytest.mark.parametrize("sec,cls,f", NUMERIC, ids=NUMERIC_IDS)
def test_value_just_outside_range_is_rejected_with_a_useful_message(sec, cls, f):
    lo, hi, lo_open = f.metadata["range"]
    for bad in _just_outside(f):
        with pytest.raises(ParameterError) as ei:
            _build(cls, f, bad)
        msg = str(ei.value)
        assert f"{sec}.{f.name}" in msg
        assert repr(bad) in msg
        assert f"{'(' if lo_open else '['}{lo:g}, {hi:g}]" in msg
        assert f.metadata["unit"] in msg


@pytest.mark.parametrize("sec,cls,f", NUMERIC, ids=NUMERIC_IDS)
def test_range_boundaries_are_accepted(sec, cls, f):
    lo, hi, lo_open = f.metadata["range"]
    inside = (lo + 1 if _is_int(f) else math.nextafter(lo, math.inf)) if lo_open else lo
    for v in (inside, hi):
        obj = _build(cls, f, v)
        assert getattr(obj, f.name) == _with(f, v)


@pytest.mark.parametrize("sec,cls,f", NUMERIC, ids=NUMERIC_IDS)
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf, True, "1.0", None])
def test_non_numbers_and_non_finite_are_rejected(sec, cls, f, bad):
    with pytest.raises(ParameterError, match=rf"{sec}\.{f.name}\b"):
        _build(cls, f, bad)


INT_FIELDS = [(s, c, f) for s, c, f in NUMERIC if _is_int(f)]
TUPLE_FIELDS = [(s, c, f) for s, c, f in NUMERIC if _is_tuple(f)]
SCALAR_FIELDS = [(s, c, f) for s, c, f in NUMERIC if not _is_tuple(f)]


def _accepted(cases) -> list[str]:
    """The (label, constructor) cases that do NOT raise ParameterError."""
    bad = []
    for label, make in cases:
        try:
            make()
        except ParameterError as exc:
            assert label.split("=")[0].strip() in str(exc), f"{label}: {exc}"
        else:
            bad.append(label)
    return bad


def test_integer_fields_reject_fractions():
    """n_p, bits, seed, speed_decimation, log_stride are counts: 2.5 pole pairs
    or a decimation of 1.5 cannot be passed on to the C structs (c_int)."""
    assert len(INT_FIELDS) >= 5
    cases = [(f"{s}.{f.name} = {f.metadata['range'][0] + 0.5}",
              lambda c=c, f=f: c(**{f.name: f.metadata["range"][0] + 0.5}))
             for s, c, f in INT_FIELDS]
    assert _accepted(cases) == []


@pytest.mark.parametrize("sec,cls,f", TUPLE_FIELDS,
                         ids=[f"{s}.{f.name}" for s, _, f in TUPLE_FIELDS])
def test_per_phase_fields_need_three_values(sec, cls, f):
    good = f.default[0]
    cases = [(f"{sec}.{f.name} = {bad!r}", lambda bad=bad: cls(**{f.name: bad}))
             for bad in (good, (good,), (good, good), (good,) * 4)]
    assert _accepted(cases) == []


def test_scalar_fields_reject_sequences():
    """A TOML array given for a scalar (T_sp = [1e-4]) must not pass."""
    cases = [(f"{s}.{f.name} = ({f.default!r},)",
              lambda c=c, f=f: c(**{f.name: (f.default,)})) for s, c, f in SCALAR_FIELDS]
    assert _accepted(cases) == []


CHOICES = [(sec, cls, f) for sec, cls in CLASSES.items() for f in dataclasses.fields(cls)
           if "choices" in f.metadata]


@pytest.mark.parametrize("sec,cls,f", CHOICES, ids=[f"{s}.{f.name}" for s, _, f in CHOICES])
def test_choice_fields(sec, cls, f):
    for ok in f.metadata["choices"]:
        assert getattr(cls(**{f.name: ok}), f.name) == ok
    with pytest.raises(ParameterError) as ei:
        cls(**{f.name: "bogus"})
    msg = str(ei.value)
    assert f"{sec}.{f.name}" in msg and "bogus" in msg
    assert all(c in msg for c in f.metadata["choices"])


BOOL_FIELDS = [(sec, cls, f) for sec, cls in CLASSES.items() for f in dataclasses.fields(cls)
               if f.type in ("bool", bool)]


def test_bool_fields_reject_non_bools():
    """'false' as a string is truthy: accepting it would silently switch the
    feature on."""
    assert len(BOOL_FIELDS) >= 2  # speed_loop, warm_start
    cases = [(f"{s}.{f.name} = {bad!r}", lambda c=c, f=f, bad=bad: c(**{f.name: bad}))
             for s, c, f in BOOL_FIELDS for bad in ("false", 0, 1.0)]
    assert _accepted(cases) == []


def test_parameters_are_frozen():
    m = MotorPars()
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.L_s = 1.0  # type: ignore[misc]


# ------------------------------------------------------------- Profile -----

def test_profile_valid_forms():
    assert Profile((0.0,), (1.0,))(5.0) == 1.0
    p = Profile((0.0, 1.0, 1.0, 2.0), (0.0, 1.0, 3.0, 3.0))  # equal times: a step
    assert p(0.5) == pytest.approx(0.5)
    assert p(1.5) == 3.0
    assert p(-1.0) == 0.0 and p(10.0) == 3.0  # held outside
    n = 64
    assert len(Profile(tuple(map(float, range(n))), (0.0,) * n).t) == n


@given(t=st.lists(st.floats(-1e3, 1e3), min_size=2, max_size=64))
def test_profile_rejects_decreasing_times(t):
    ok = all(b >= a for a, b in zip(t, t[1:]))
    if ok:
        Profile(tuple(t), (0.0,) * len(t))
    else:
        with pytest.raises(ParameterError, match="non-decreasing"):
            Profile(tuple(t), (0.0,) * len(t))


@pytest.mark.parametrize("t,y", [((0.0, 1.0), (0.0,)), ((0.0,), (0.0, 1.0)), ((), ())])
def test_profile_rejects_unequal_or_empty(t, y):
    with pytest.raises(ParameterError, match="equal length"):
        Profile(t, y)


def test_profile_rejects_more_than_64_points():
    with pytest.raises(ParameterError, match="65 points"):
        Profile(tuple(float(k) for k in range(65)), (0.0,) * 65)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_profile_rejects_non_finite(bad):
    with pytest.raises(ParameterError, match="finite"):
        Profile((0.0, 1.0), (0.0, bad))
    with pytest.raises(ParameterError, match="finite"):
        Profile((0.0, bad), (0.0, 1.0))


def test_profile_steps_helper_fits_the_c_table():
    p = Profile.steps(0.0, (0.1, 1.0), (0.2, -1.0), ramp=0.01)
    assert p.t == pytest.approx((0.0, 0.1, 0.11, 0.2, 0.21))
    assert p.y == (0.0, 0.0, 1.0, 1.0, -1.0)
    assert len(p.t) <= F.PWL_MAX


# ---------------------------------------------------------------- TOML -----

def _toml_value(v) -> str:
    if isinstance(v, tuple):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return repr(v)


@pytest.mark.parametrize("sec,cls,f", NUMERIC, ids=NUMERIC_IDS)
def test_toml_out_of_range_value_is_rejected_naming_field(sec, cls, f, tmp_path):
    bad = _just_outside(f)[1]
    line = f"{f.name} = {_toml_value(_with(f, bad))}\n"
    text = line if sec == "scenario" else f"[{sec}]\n{line}"
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ParameterError) as ei:
        load_scenario(path)
    assert f"{sec}.{f.name}" in str(ei.value) and repr(bad) in str(ei.value)


@pytest.mark.parametrize("text,names", [
    ("durration = 1.0\n", ["durration"]),
    ("[motor]\nL_ss = 0.01\n", ["motor.L_ss"]),
    ("[controller]\nlambda = 5.0\n", ["controller.lambda"]),
    ("[load]\nT_load = 1.0\n", ["load.T_load"]),
    ("[plant]\nR_s = 1.0\n", ["plant"]),
    ("[scenario]\nT_sp = 1e-4\n", ["scenario"]),
])
def test_toml_unknown_keys_are_rejected_naming_them(text, names, tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(text)
    with pytest.raises(ParameterError) as ei:
        load_scenario(path)
    assert all(n in str(ei.value) for n in names), str(ei.value)


@pytest.mark.parametrize("sec", SECTIONS)
@pytest.mark.parametrize("value", ["5", '"abc"', "[1, 2]", "[[x]]"])
def test_toml_section_of_wrong_type_is_rejected_naming_it(sec, value, tmp_path):
    text = f"[[{sec}]]\nx = 1\n" if value == "[[x]]" else f"{sec} = {value}\n"
    path = tmp_path / "s.toml"
    path.write_text(text)
    with pytest.raises(ParameterError, match=sec):
        load_scenario(path)


PROFILE_KEYS = [("w_M_ref", ""), ("w_M_ref_rpm", ""), ("i_d_ref", ""), ("i_q_ref", ""),
                ("T_brake", "load"), ("T_ext", "load")]


def _load_text(tmp_path, text):
    path = tmp_path / "s.toml"
    path.write_text(text)
    return load_scenario(path)


def _profile_line(key, sec, value):
    line = f"{key} = {value}\n"
    return f"[{sec}]\n{line}" if sec else line


@pytest.mark.parametrize("value", ['"fast"', "true", "[1.0, 2.0]", "{ t = [0.0], z = [1.0] }",
                                   "{ t = 0.0, y = 1.0 }", '{ t = ["a"], y = [1.0] }',
                                   '{ t = [0.0], y = ["a"] }'])
def test_toml_malformed_profile_is_a_parameter_error_naming_it(value, tmp_path):
    for key, sec in PROFILE_KEYS:
        with pytest.raises(ParameterError) as ei:
            _load_text(tmp_path, _profile_line(key, sec, value))
        assert key in str(ei.value), str(ei.value)


@pytest.mark.parametrize("value", ["{ t = [1.0, 0.0], y = [1.0, 2.0] }",
                                   "{ t = [0.0, 1.0], y = [1.0] }",
                                   "{ t = [], y = [] }"])
def test_toml_invalid_profile_message_names_it(value, tmp_path):
    """Five profiles share the checks: the message must say which one."""
    unnamed = []
    for key, sec in PROFILE_KEYS:
        with pytest.raises(ParameterError) as ei:
            _load_text(tmp_path, _profile_line(key, sec, value))
        if key not in str(ei.value):
            unnamed.append(f"{key}: {ei.value}")
    assert unnamed == []


def test_toml_syntax_error_names_the_file(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("duration = = 1\n")
    with pytest.raises(ParameterError, match="broken.toml"):
        load_scenario(path)


def test_toml_rpm_reference_is_converted(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("w_M_ref_rpm = { t = [0.0, 0.5], y = [0.0, 1500.0] }\n"
                    "[load]\nT_brake = 2.0\n[controller]\nmode = \"sensorless\"\n")
    s = load_scenario(path)
    assert s.w_M_ref.y == (0.0, pytest.approx(1500.0 * 2 * math.pi / 60))
    assert s.w_M_ref.t == (0.0, 0.5)
    assert s.load.T_brake == Profile.const(2.0)
    assert s.controller.mode == "sensorless"
    assert s.motor == MotorPars()  # sections not given keep their defaults


# ------------------------------------------------------- round trip --------

def _field_value(draw, f: dataclasses.Field):
    lo, hi, lo_open = f.metadata["range"]
    if _is_int(f):
        v = st.integers(int(lo) + (1 if lo_open else 0), int(hi))
    else:
        v = st.floats(lo, hi, exclude_min=lo_open, allow_nan=False)
    if _is_tuple(f):
        return tuple(draw(v) for _ in f.default)
    return draw(v)


@st.composite
def profiles(draw):
    n = draw(st.integers(1, 64))
    t = sorted(draw(st.lists(st.floats(-1e3, 1e3), min_size=n, max_size=n)))
    y = draw(st.lists(st.floats(-1e6, 1e6), min_size=n, max_size=n))
    return Profile(tuple(t), tuple(y))


@st.composite
def instances(draw, cls):
    kw = {}
    for f in dataclasses.fields(cls):
        if f.name in CLASSES:
            kw[f.name] = draw(instances(CLASSES[f.name]))
        elif "range" in f.metadata:
            kw[f.name] = _field_value(draw, f)
        elif "choices" in f.metadata:
            kw[f.name] = draw(st.sampled_from(f.metadata["choices"]))
        elif f.type in ("bool", bool):
            kw[f.name] = draw(st.booleans())
        elif f.type in ("Profile", Profile):
            kw[f.name] = draw(profiles())
        elif f.name == "name":
            kw[f.name] = draw(st.text(string.ascii_letters + string.digits + "_- .",
                                      max_size=30))
        else:
            raise AssertionError(f"{cls.__name__}.{f.name}: no strategy (new field type?)")
    if cls is Scenario and kw["inverter"].t_dead > 0.25 * kw["T_sp"]:
        # cross-field rule (tested on its own): keep the dead time within T_sp/4
        kw["inverter"] = dataclasses.replace(kw["inverter"], t_dead=0.25 * kw["T_sp"])
    return cls(**kw)


RT = settings(max_examples=150, deadline=None,
              suppress_health_check=[HealthCheck.function_scoped_fixture])


@RT
@given(s=instances(Scenario))
def test_scenario_toml_round_trip(s, tmp_path):
    try:
        s.check_controller()  # load_scenario also applies the cross-field rules
    except ParameterError:
        assume(False)
    path = tmp_path / "rt.toml"
    path.write_text(scenario_to_toml(s))
    back = load_scenario(path)
    assert back == s
    assert scenario_to_toml(back) == scenario_to_toml(s)


@RT
@example(name='say "hi"')
@example(name="C:\\temp\\x")
@example(name="two\nlines")
@given(name=st.text(max_size=40))
def test_scenario_name_round_trip(name, tmp_path):
    """Any name (quotes, backslashes, newlines, unicode) survives the trip."""
    s = Scenario(name=name)
    path = tmp_path / "rt.toml"
    path.write_text(scenario_to_toml(s), encoding="utf-8")
    assert load_scenario(path).name == name


def test_scenario_from_dict_matches_constructor():
    d = {"duration": 0.5, "motor": {"L_s": 0.01, "n_p": 2},
         "adc": {"gain": [1.0, 1.1, 0.9]}, "controller": {"mode": "conventional"}}
    s = scenario_from_dict(d)
    assert s == Scenario(duration=0.5, motor=MotorPars(L_s=0.01, n_p=2),
                         adc=AdcCfg(gain=(1.0, 1.1, 0.9)),
                         controller=ControllerCfg(mode="conventional"))


# ------------------------------------------------------------- layout ------

def test_ctypes_layout_matches_c():
    F.check_layout()  # raises ImportError on mismatch
    for name, cls in (("plant_config", F.PlantConfig), ("drive_config", F.DriveConfig),
                      ("profiles", F.Profiles)):
        assert getattr(F.lib, f"smd_sizeof_{name}")() == ct.sizeof(cls), name
    assert F.ENGINE_SIZE == F.lib.smd_sizeof_engine() > 0
    assert len(F.LOG_CHANNELS) == F.N_LOG and len(set(F.LOG_CHANNELS)) == F.N_LOG
    assert F.LOG_CHANNELS[0] == "t" and F.LOG_CHANNELS[-1] == "status"


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
    """The block structs have no C sizeof export: C must write every mirrored
    field (mirror not too long) and nothing beyond it (not too short)."""
    obj, buf, n = _guarded(cls)
    rc = call(ct.byref(obj))
    assert rc in (None, 0)
    assert bytes(buf[n:]) == bytes([GUARD]) * 64, "C wrote past the Python struct"
    raw = bytes(buf[:n])
    for name, typ in cls._fields_:
        off = getattr(cls, name).offset
        size = ct.sizeof(typ)
        assert raw[off:off + size] != bytes([GUARD]) * size, f"{cls.__name__}.{name} unwritten"


def test_cross_field_limits_name_the_fields():
    """Limits that involve two fields are checked before any simulation."""
    with pytest.raises(ParameterError, match=r"inverter\.t_dead"):
        Scenario(T_sp=1e-6, inverter=InverterCfg(t_dead=1e-6))
    s = Scenario(controller=ControllerCfg(mode="sensorless", w_lpf=4e4))
    with pytest.raises(ParameterError, match=r"controller\.w_lpf"):
        s.check_controller()
    s = Scenario(controller=ControllerCfg(mode="sensorless", n_max=1e5))
    with pytest.raises(ParameterError, match=r"controller\.n_max"):
        s.check_controller()
