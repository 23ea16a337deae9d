"""The README's Python example does what the README says it does: it runs
and prints the line the README quotes after it."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_python_example_prints_what_the_readme_says():
    text = README.read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    quoted = re.search(r"It prints `([^`]+)`", text).group(1)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, str(README), "exec"), {"__name__": "readme_example"})
    assert out.getvalue().strip() == quoted


def test_the_tracker_example_prints_what_the_readme_says():
    """The tracker's example (with the encoder, then without it) prints the
    two lines quoted in its comments."""
    text = README.read_text()
    code = next(b for b in re.findall(r"```python\n(.*?)```", text, re.S) if "rls_i_inj" in b)
    quoted = [ln[2:] for ln in code.splitlines() if ln.startswith("# R_s")]
    assert len(quoted) == 2
    head = ("from smodrive.engine import simulate\n"
            "from smodrive.model import LoadCfg, Profile, Scenario\n")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(head + code, str(README), "exec"), {"__name__": "readme_example"})
    assert out.getvalue().strip().splitlines() == quoted


def test_the_commissioning_commands_do_what_the_readme_says(tmp_path, monkeypatch):
    """README "Commission your motor": its three commands, run as written
    from the repository's root (the files they write go to a scratch copy
    of the paths): identify writes the measured motor, design prints the
    drive designed from it, and run --profile usual runs that motor
    sensorless through the usual profile and says it reached its end."""
    import shlex
    import shutil

    from click.testing import CliRunner

    from smodrive.cli import main

    text = README.read_text()
    section = text[text.index("## Commission your motor"):]
    block = re.search(r"```sh\n(.*?)```", section, re.S).group(1)
    cmds = [shlex.split(line) for line in block.strip().splitlines()]
    assert [c[:2] for c in cmds] == [["smodrive", "identify"], ["smodrive", "design"],
                                     ["smodrive", "run"]]
    root = README.parent
    (tmp_path / "scenarios" / "motors").mkdir(parents=True)
    for f in (root / "scenarios" / "motors").glob("*.toml"):
        shutil.copy(f, tmp_path / "scenarios" / "motors" / f.name)
    monkeypatch.chdir(tmp_path)
    outs = []
    for c in cmds:
        res = CliRunner().invoke(main, c[1:])
        assert res.exit_code == 0, (c, res.output)
        outs.append(res.output)
    assert "R_s" in outs[0] and Path(cmds[0][cmds[0].index("--out") + 1]).exists()
    assert "speed PI" in outs[1]
    assert "usual profile: reached" in outs[2]
    # and, as the README says, the note on the servo's ringing speed loop
    assert "the sensorless speed loop has 9.0 deg of phase margin" in outs[2]
