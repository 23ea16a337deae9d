"""results/report.md (issue 13, point 4): the claims table renders as a
table in a real Markdown renderer (markdown-it-py, CommonMark with the
GitHub table extension), one row of eight cells per claim (the kind of comparison in the second) with the
criterion's `|` intact; every figure a run writes is shown; a claim the run
could not measure says so and why, and is neither a pass nor a fail."""

from __future__ import annotations

import json
import types
from pathlib import Path

import pytest
from markdown_it import MarkdownIt

from smodrive import report
from smodrive.claims import Claim, count
from smodrive.scenarios import PAPERS
from smodrive.scenarios.common import Experiment, Outcome

HEADER = ["claim", "kind", "paper", "expected", "reproduced", "unit", "criterion", "result"]


def table_rows(md: str) -> list[list[str]]:
    """The rows of the first table of `md` as rendered: each row the text of
    its cells (header row first)."""
    tokens = MarkdownIt("commonmark").enable("table").parse(md)
    rows, row, in_cell = [], None, False
    for t in tokens:
        if t.type == "table_close":
            break
        if t.type == "tr_open":
            row = []
        elif t.type == "tr_close":
            rows.append(row)
        elif t.type in ("th_open", "td_open"):
            in_cell = True
            row.append("")
        elif t.type in ("th_close", "td_close"):
            in_cell = False
        elif t.type == "inline" and in_cell:
            row[-1] = "".join(c.content for c in t.children)
    return rows


def claims() -> list[Claim]:
    """One claim of each check, passing and failing, one the run could not
    measure, and text with `|` where a cell holds it (unit, id)."""
    return [
        Claim("p.abs_pass", "s.", 1.0, None, 1.05, "A", 0.1, "abs"),
        Claim("p.abs_fail", "s.", None, 2.0, 2.5, "V", 0.1, "abs", why_fail="because"),
        Claim("p.rel_pass", "s.", 100.0, None, 104.0, "r/min", 0.05, "rel"),
        Claim("p.max_fail", "s.", 0.02, None, 0.2, "rad", 0.02, "max"),
        Claim("p.min_pass", "s.", None, None, 3.0, "", 2.0, "min"),
        Claim("p.cycles|odd", "s.", 489.0, None, float("nan"), "cycles|x", 1956.0, "max",
              not_measured="arm-none-eabi-gcc not found: install Debian's gcc-arm-none-eabi"),
    ]


def test_claims_table_has_every_cell_in_a_real_renderer(tmp_path):
    cs = claims()
    md = report.render_report(report.Reproduction(claims=cs), ["p"], tmp_path)
    rows = table_rows(md)
    assert rows[0] == HEADER
    assert len(rows) == 1 + len(cs)
    for c, row in zip(cs, rows[1:]):
        assert len(row) == 8, row
        assert row[0] == c.id  # the code span, `|` and all
        assert row[1] == c.kind
        assert row[5] == c.unit
        assert row[6] == c.describe_check()  # "|reproduced - expected| <= ..." intact
        assert row[7] == {"pass": "pass", "fail": "FAIL", "not measured": "not measured"}[
            c.status]
    # the absolute criteria hold two `|`: the case the issue found broken
    assert rows[1][6].startswith("|reproduced - paper| <= 0.1 A")
    assert [r[7] for r in rows[1:]] == ["pass", "FAIL", "pass", "FAIL", "pass", "not measured"]


def test_unescaped_table_would_break_in_the_same_renderer():
    """The check above can fail: the row as report.md wrote it before has
    its criterion split at the `|` and loses the verdict."""
    c = claims()[0]
    old = (f"| `{c.id}` | method | 1 | - | 1.05 | A | {c.describe_check()} | pass |")
    rows = table_rows("| " + " | ".join(HEADER) + " |\n|" + "---|" * 8 + "\n" + old + "\n")
    assert rows[1][6] != c.describe_check() and "pass" not in rows[1]


def test_not_measured_is_neither_pass_nor_fail():
    c = claims()[-1]
    assert c.status == "not measured" and not c.passed
    assert "NOT MEASURED: arm-none-eabi-gcc not found" in c.statement
    assert "FAILS" not in c.statement
    assert count(claims()) == {"pass": 3, "fail": 2, "not measured": 1}
    d = c.to_json()
    assert d["status"] == "not measured" and d["reproduced"] is None
    json.dumps(d, allow_nan=False)  # strict JSON


def test_not_measured_from_a_spec(tmp_path):
    from smodrive.claims import load_specs

    p = tmp_path / "x.claims.toml"
    p.write_text('["x.cycles"]\nstatement = "Cycles."\nkind = "method"\nunit = "cycles"\ncheck = "max"\n'
                 "paper = 10.0\ntolerance = 40.0\n")
    c = load_specs(p).claim("x.cycles", float("nan"), not_measured="no emulator")
    assert c.status == "not measured" and c.statement.endswith("NOT MEASURED: no emulator")


def _fake_paper(made: list[str]):
    """A paper of two experiments: the first writes two figures and returns
    only the first (as a closure drawing Figs. 17 and 18 could), the second
    writes one and returns it."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    def write(fig_dir: Path, name: str) -> Path:
        fig = Figure(figsize=(1, 1))
        fig.add_subplot().plot([0, 1])
        path = fig_dir / f"{name}.png"
        fig.savefig(path)
        made.append(name)
        return path

    def exp1(progress):
        def plot(fig_dir):
            p = write(fig_dir, "fake_fig17")
            write(fig_dir, "fake_fig18")
            return p
        return Outcome(claims()[:2], {}, [("fake_fig17_18", plot)])

    def exp2(progress):
        return Outcome(claims()[2:], {}, [("fake_fig20", lambda d: write(d, "fake_fig20"))])

    return types.SimpleNamespace(EXPERIMENTS=[Experiment("fake.fig17", "Two figures", exp1),
                                              Experiment("fake.fig20", "One figure", exp2)])


def test_every_figure_written_is_in_the_report(tmp_path, monkeypatch):
    made: list[str] = []
    monkeypatch.setitem(PAPERS, "fake", _fake_paper(made))
    out = tmp_path / "results"
    (out / "figures").mkdir(parents=True)
    stale = out / "figures" / "from_an_earlier_run.png"
    stale.write_bytes(b"")  # not written by this run: not shown
    rep = report.reproduce(["fake"], out)
    md = (out / "report.md").read_text()
    assert made == ["fake_fig17", "fake_fig18", "fake_fig20"]
    for name in made:
        assert f"![{name}](figures/{name}.png)" in md
    assert "from_an_earlier_run" not in md
    assert [s[0] for s in rep.sections] == ["fake.fig17", "fake.fig20"]
    assert md.index("### fake.fig17") < md.index("fake_fig18.png") < md.index("### fake.fig20")
    assert len(table_rows(md)) == 1 + len(claims())
    data = json.loads((out / "claims.json").read_text())
    assert [d["status"] for d in data] == ["pass", "fail", "pass", "fail", "pass",
                                           "not measured"]


@pytest.mark.parametrize("exp_id", ["yao2022.fig7", "yang2018.fig1"])
def test_real_experiment_figures_are_shown(exp_id, tmp_path, monkeypatch):
    """A real experiment (the fast analyses) through reproduce(): its
    figures are files in OUT/figures and each is in report.md."""
    paper = PAPERS[exp_id.split(".")[0]]
    exp = next(e for e in paper.EXPERIMENTS if e.id == exp_id)
    monkeypatch.setitem(PAPERS, "one", types.SimpleNamespace(EXPERIMENTS=[exp]))
    rep = report.reproduce(["one"], tmp_path)
    md = (tmp_path / "report.md").read_text()
    pngs = sorted(p.name for p in (tmp_path / "figures").glob("*.png"))
    assert pngs and [p.name for p in rep.figures] == pngs
    for name in pngs:
        assert f"(figures/{name})" in md
    assert len(table_rows(md)) == 1 + len(rep.claims)


def test_only_runs_the_named_experiments(tmp_path, monkeypatch):
    """reproduce(..., only=ids) runs just those experiments of the paper
    (the gallery's short versions); the others' claims and figures are
    absent."""
    made: list[str] = []
    monkeypatch.setitem(PAPERS, "fake", _fake_paper(made))
    rep = report.reproduce(["fake"], tmp_path, only={"fake.fig20"})
    assert made == ["fake_fig20"]
    assert [s[0] for s in rep.sections] == ["fake.fig20"]
    assert [c.id for c in rep.claims] == [c.id for c in claims()[2:]]
