"""The papers' claims as data: every spec of a `<paper>.claims.toml` is used
by a run and every claim a run produces comes from a spec (no orphan text,
no prose left in the code); the data files parse with known keys only; a
text with an unfilled `{field}` (or a field no text uses) is an error; a
claim built from a spec is the Claim the code used to build by hand; the
report embeds every figure a closure writes.

The claims are those of tests/test_yang2018_claims.py and
tests/test_yao2022_claims.py, computed once per session."""

from __future__ import annotations

import json
import re
import string
try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: the same parser as a package
    import tomli as tomllib
import types
from pathlib import Path

import pytest

from smodrive import report
from smodrive.claims import CHECKS, SPEC_KEYS, TEXT_TABLE, Claim, ClaimSpec, load_specs
from smodrive.scenarios import PAPERS
from smodrive.scenarios.common import Experiment, Outcome

from test_yang2018_claims import paper_claims as yang2018_claims
from test_yao2022_claims import paper_claims as yao2022_claims

RUNS = {"yang2018": yang2018_claims, "yao2022": yao2022_claims}


def data_path(paper: str) -> Path:
    return Path(PAPERS[paper].__file__).with_suffix(".claims.toml")


def template_regex(text: str) -> str:
    """A regex for what a text with `{fields}` becomes once filled."""
    return "".join(re.escape(lit) + ("" if name is None else ".*?")
                   for lit, name, _, _ in string.Formatter().parse(text))


@pytest.fixture(scope="module", params=sorted(PAPERS))
def paper(request):
    """(paper, its specs, the claims its runs produce in order)."""
    name = request.param
    return name, PAPERS[name].SPECS, RUNS[name]()


# ------------------------------------------------------------ the files ---

@pytest.mark.parametrize("name", sorted(PAPERS))
def test_data_file_parses_with_known_keys(name):
    """Raw TOML: only claim tables (ids of this paper) and the shared texts;
    each claim has a non-empty statement, known keys, a known check; the
    module's SPECS are exactly this file."""
    raw = tomllib.loads(data_path(name).read_text())
    texts = raw.pop(TEXT_TABLE, {})
    assert all(isinstance(v, str) and v.strip() for v in texts.values())
    for cid, spec in raw.items():
        assert cid.startswith(f"{name}."), cid
        assert set(spec) <= set(SPEC_KEYS), (cid, set(spec) - set(SPEC_KEYS))
        assert isinstance(spec["statement"], str) and spec["statement"].strip()
        assert spec.get("check", "abs") in CHECKS
        for key in ("statement", "basis", "why_fail"):
            # no line breaks or runs of spaces left by the TOML line continuations
            assert "\n" not in spec.get(key, "") and "  " not in spec.get(key, ""), (cid, key)
    assert set(PAPERS[name].SPECS) == set(raw)
    assert load_specs(data_path(name)).keys() == PAPERS[name].SPECS.keys()


def test_every_claim_comes_from_a_spec(paper):
    """Each produced claim id is a member of exactly one spec, and its unit,
    check and texts are the spec's (the statement may carry the FAILS
    suffix Claim appends)."""
    name, specs, claims = paper
    ids = [c.id for c in claims]
    assert len(ids) == len(set(ids))
    for c in claims:
        spec = specs.spec_of(c.id)
        assert spec is not None, f"{c.id} has no spec in {data_path(name).name}"
        assert (c.unit, c.check) == (spec.unit, spec.check)
        assert re.fullmatch(template_regex(spec.statement) + r"( FAILS: .*)?", c.statement,
                            re.S), c.id
        assert re.fullmatch(template_regex(spec.basis), c.basis, re.S), c.id
        assert re.fullmatch(template_regex(spec.why_fail), c.why_fail, re.S), c.id
        if not isinstance(spec.paper, dict) and spec.paper is not None:
            assert c.paper == spec.paper
        if isinstance(spec.paper, dict):
            assert c.paper == spec.paper[c.id]
        if isinstance(spec.tolerance, dict):
            assert c.tolerance == spec.tolerance[c.id]
        elif spec.tolerance is not None:
            assert c.tolerance == spec.tolerance


def test_every_spec_is_used(paper):
    """No orphan text: every spec yields at least one claim, and every id a
    spec's `paper` or `tolerance` table names is produced."""
    name, specs, claims = paper
    ids = {c.id for c in claims}
    for key, spec in specs.items():
        members = {cid for cid in ids if spec.matches(cid)}
        assert members, f"{key} in {data_path(name).name} is used by no run"
        named = spec.ids()
        if named is not None:
            assert named == members, (key, named ^ members)


def test_claim_counts(paper):
    """The reproduction's 26 + 37 claims (yang2018: 24 when the texts became
    data, + the two noise-ripple ratios of Fig. 6, issue 11, + eq. (12)'s
    error and - the two Fig. 6 ripple ratios, issue 20; yao2022: 31, + Fig. 10
    against the paper at three speeds, Fig. 14 with the ADC and its end speed,
    the Fig. 22 crossing, issue 11; + Fig. 23's bias, Table VI's three parts
    judged as one worst call, issue 20)."""
    name, _, claims = paper
    assert len(claims) == {"yang2018": 26, "yao2022": 36}[name]


@pytest.mark.parametrize("name", sorted(PAPERS))
def test_no_claim_is_built_by_hand(name):
    """The runs build claims only through their specs."""
    source = Path(PAPERS[name].__file__).read_text()
    assert "Claim(" not in source and "statement=" not in source


# ------------------------------------------------------------ the specs ---

def test_unfilled_field_raises():
    spec = PAPERS["yang2018"].SPECS["yang2018.fig1.peak_gain_db_Lhat_2L"]
    assert spec.fields() == {"f_peak"}
    with pytest.raises(ValueError, match=r"unfilled fields \['f_peak'\]"):
        spec.make(52.4, expected=52.39)
    with pytest.raises(ValueError, match=r"unused fields \['f_pek'\]"):
        spec.make(52.4, expected=52.39, f_pek=2500.0)
    # a family: the id's own field must be filled too
    fam = PAPERS["yao2022"].SPECS["yao2022.fig9.true_pos_error_rad_{speed}"]
    with pytest.raises(ValueError, match="speed"):
        fam.make(0.003, krpm=30.0)


def test_make_builds_the_same_claim_as_by_hand():
    """A spec's claim is the Claim with the data's attributes and the run's
    values: same JSON (key order included), same verdict and FAILS text."""
    spec = ClaimSpec(id="p.x_{tag}", kind="method", statement="At {n:g} r/min: error {e:.2f}.", unit="rad",
                     check="max", paper={"p.x_a": 0.1, "p.x_b": 0.2}, tolerance=0.15,
                     basis="bound {n:g}", why_fail="because")
    for tag, r in (("a", 0.1), ("b", 0.3)):
        got = spec.make(r, tag=tag, n=1500.0, e=0.123)
        want = Claim(id=f"p.x_{tag}", statement="At 1500 r/min: error 0.12.",
                     paper={"a": 0.1, "b": 0.2}[tag], expected=None, reproduced=r, unit="rad",
                     tolerance=0.15, check="max", basis="bound 1500", why_fail="because")
        assert json.dumps(got.to_json()) == json.dumps(want.to_json())
        assert got.passed == (r <= 0.15)
    assert "FAILS: reproduced <= 0.15 rad, reproduced 0.3. Why: because" in got.statement


def test_fixed_and_computed_values_do_not_mix():
    spec = ClaimSpec(id="p.x", kind="method", statement="s", paper=1.0, tolerance=0.1)
    with pytest.raises(ValueError, match="tolerance is fixed in the data"):
        spec.make(1.0, tolerance=0.2)
    with pytest.raises(ValueError, match="paper is fixed in the data"):
        spec.make(1.0, paper=2.0)
    with pytest.raises(ValueError, match="no tolerance"):
        ClaimSpec(id="p.y", kind="method", statement="s").make(1.0)
    with pytest.raises(ValueError, match="no paper for this id"):
        ClaimSpec(id="p.{k}", kind="method", statement="s", paper={"p.a": 1.0}, tolerance=1.0).make(1.0, k="b")


@pytest.mark.parametrize("body, error", [
    ('["p.x"]\nstatement = "s"\nkind = \"method\"\nunits = "A"\n', "unknown keys"),
    ('["p.x"]\nunit = "A"\n', "no statement"),
    ('["p.x"]\nstatement = "s"\nkind = \"method\"\ncheck = "ratio"\n', "check"),
    ('["p.x"]\nstatement = "s"\n', "kind"),
    ('["p.x"]\nstatement = "s"\nkind = \"guess\"\n', "kind"),
    ('["p.x"]\nstatement = "s {}"\nkind = \"method\"\n', "not a plain name"),
    ('["p.x"]\nstatement = "s {a.b}"\nkind = \"method\"\n', "not a plain name"),
    ('["p.x"]\nstatement = "s {expected}"\nkind = \"method\"\n', "not a plain name"),
    ('["p.x"]\nstatement = "s {text.nope}"\nkind = \"method\"\n', "no shared text"),
    ('[text]\nold = "t"\n["p.x"]\nstatement = "s"\nkind = \"method\"\n', "used by no claim"),
    ('["p.{k}"]\nstatement = "s"\nkind = \"method\"\npaper = { "q.a" = 1.0 }\n', "not of this spec"),
    ('["p.x"]\nstatement = "s"\nkind = \"method\"\npaper = "0.1"\n', "number"),
    ('["p.x"]\nstatement = "s"\nkind = \"method\"\nunit = 1\n', "string"),
])
def test_bad_data_raises(tmp_path, body, error):
    path = tmp_path / "bad.claims.toml"
    path.write_text(body)
    with pytest.raises(ValueError, match=error):
        load_specs(path)


def test_shared_texts_are_inserted(tmp_path):
    path = tmp_path / "p.claims.toml"
    path.write_text('[text]\nwhy = "noise at {n:g} r/min"\n'
                    '["p.x"]\nstatement = "s"\nkind = \"method\"\ntolerance = 1.0\nwhy_fail = "{text.why}."\n')
    c = load_specs(path).claim("p.x", 2.0, expected=0.0, n=75.0)
    assert c.why_fail == "noise at 75 r/min."
    assert c.statement.endswith("Why: noise at 75 r/min.")


# ----------------------------------------------------------- the report ---

def test_report_embeds_every_path_a_closure_returns(tmp_path, monkeypatch):
    """A figure closure may return one path or a list; report.md embeds
    each, in order."""

    def one(fig_dir):
        (fig_dir / "f1.png").write_bytes(b"png")
        return fig_dir / "f1.png"

    def two(fig_dir):
        for n in ("f2", "f3"):
            (fig_dir / f"{n}.png").write_bytes(b"png")
        return [fig_dir / "f2.png", fig_dir / "f3.png"]

    def run(progress):
        return Outcome([Claim(id="fake.c", statement="s", paper=None, expected=1.0,
                              reproduced=1.0, unit="", tolerance=0.1)],
                       figures=[("f2_3", two), ("f1", one)])

    monkeypatch.setitem(report.PAPERS, "fake",
                        types.SimpleNamespace(EXPERIMENTS=[Experiment("fake.x", "t", run)]))
    rep = report.reproduce(["fake"], tmp_path)
    assert [p.name for p in rep.figures] == ["f2.png", "f3.png", "f1.png"]
    md = (tmp_path / "report.md").read_text()
    embeds = re.findall(r"!\[(\w+)\]\((figures/\w+\.png)\)", md)
    assert embeds == [("f2", "figures/f2.png"), ("f3", "figures/f3.png"),
                      ("f1", "figures/f1.png")]
