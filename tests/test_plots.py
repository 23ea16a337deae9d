"""smodrive.plots: drawing functions take and return matplotlib Axes, make
their own Figure (no pyplot) when given none, and leave the caller's
rcParams and backend as they were (the house style lives in a context).

Everything asserted here is exact: identities of Axes objects, counts of
axes and curves, and equality of plotted data with the Result's channels.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import matplotlib as mpl
import numpy as np
import pytest
from matplotlib.figure import Figure

from smodrive import plots
from smodrive.model import RPM
from smodrive.scenarios import yang2018, yao2022
from smodrive.engine import CHANNELS, simulate


# rows of the CLI's `run` figure: 3 + 2 + 1 curves
ROWS = [("speed (r/min)", [("n_ref_rpm", "reference"), ("n_rpm", "true"),
                           ("n_hat_rpm", "estimated")]),
        ("motor current (A)", [("i_d", "d"), ("i_q", "q")]),
        ("position error (rad)", [("theta_error", "true")])]


@pytest.fixture(scope="module")
def r_spmsm():
    r = simulate(yang2018.fig7_scenario(1500.0).replace(duration=0.02))
    assert r.status == 0 and r.t.size == 200  # 0.02 s at T_sp = 100 us
    return r


@pytest.fixture(scope="module")
def r_lcl():
    # 0.12 s: the ripple and spectrum layouts analyse from 0.1 s on (the papers' settling)
    r = simulate(yao2022.steady(60e3).replace(duration=0.12))
    assert r.status == 0 and r.t.size == 2400  # 0.12 s at T_sp = 50 us
    return r


def _rc_snapshot() -> dict:
    # dict.items reads the stored values without RcParams.__getitem__ (which
    # would resolve an automatic backend and so change what it compares)
    return dict(dict.items(mpl.rcParams))


def _rc_diff(before: dict) -> list[str]:
    after = _rc_snapshot()
    return sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))


@pytest.fixture
def rc_unchanged():
    mpl.get_backend()  # resolve the automatic backend before the snapshot
    before = _rc_snapshot()
    yield
    assert _rc_diff(before) == []


def _n_lines(axes) -> list[int]:
    return [len(a.lines) for a in np.ravel(axes)]


# ------------------------------------------------------ (a) rcParams --------

def test_import_and_drawing_leave_rcparams_and_backend_alone(tmp_path):
    # A fresh interpreter with a user's backend and a user's setting: neither
    # importing smodrive.plots nor drawing and saving may change any rcParam
    # (the old module called matplotlib.use("Agg") and rcParams.update at
    # import), and pyplot must not be needed to draw.
    code = textwrap.dedent(f"""
        import sys
        import matplotlib as mpl
        mpl.use("svg")
        mpl.rcParams["lines.linewidth"] = 2.5
        mpl.rcParams["font.size"] = 13.0
        before = dict(dict.items(mpl.rcParams))

        def diff():
            after = dict(dict.items(mpl.rcParams))
            return sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))

        import numpy as np
        from smodrive import plots
        from smodrive.engine import CHANNELS, Result
        from smodrive.scenarios import yang2018
        assert diff() == [], ("import", diff())
        data = np.zeros((50, len(CHANNELS)))
        data[:, CHANNELS.index("t")] = np.arange(50) * 1e-4
        r = Result(yang2018.fig7_scenario(1500.0).replace(duration=0.005), data, 0)
        axes = plots.sensorless_panels([r], ["x"], "title")
        assert diff() == [], ("draw", diff())
        path = plots.save(axes, {str(tmp_path)!r}, "synthetic")
        assert diff() == [], ("save", diff())
        assert mpl.get_backend() == "svg", mpl.get_backend()
        # the style applied in the context, the user's value outside it
        assert axes[0, 0].lines[0].get_linewidth() == plots.STYLE["lines.linewidth"]
        assert mpl.rcParams["lines.linewidth"] == 2.5
        print(path)
    """)
    # the same smodrive as this process imported (installed, or src/ with PYTHONPATH)
    env = dict(os.environ, PYTHONPATH=str(Path(plots.__file__).resolve().parents[1]))
    env.pop("MPLBACKEND", None)
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=env, timeout=120)
    assert res.returncode == 0, res.stderr
    png = Path(res.stdout.strip())
    assert png == tmp_path / "synthetic.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_every_drawing_function_leaves_rcparams_alone(r_spmsm, r_lcl, tmp_path,
                                                      rc_unchanged):
    m = yang2018.MOTOR
    z = np.exp(1j * np.linspace(0, 1, 64))
    made = [
        plots.fig1_bode(m, 1e-4, 500.0, 1.2),
        plots.fig2_bode(1500 * RPM * m.n_p, 1.0, 0.0),
        plots.dq_panels([r_spmsm], ["a"], "dq"),
        plots.sensorless_panels([r_spmsm], ["a"], "sensorless", [(0.0, 0.02)]),
        plots.time_panels([r_spmsm, r_lcl], ["spmsm", "lcl"], "time", ROWS),
        plots.pll_bode(np.logspace(0, 3, 64), [("k", 1.0 / (1j * np.logspace(0, 3, 64)))],
                       "pll"),
        plots.ripple_panels({(law, 60e3): r_lcl for law in ("tde17", "proposed")}, [60e3],
                            "ripple"),
        plots.waveform_spectrum([r_lcl], ["60 kr/min"], "i_alpha", "i (A)", "waveform"),
        plots.disturbance_panels(np.arange(64) * 5e-5, z, z, z, 5e-5, "disturbance"),
    ]
    for k, axes in enumerate(made):
        assert plots.save(axes, tmp_path, f"f{k}").is_file()


# ------------------------------------------- (b) drawing on given Axes -------

def test_time_panels_draw_on_the_given_axes_one_curve_per_channel(r_spmsm, r_lcl):
    # both plants side by side, on the caller's own 3 x 2 grid
    fig = Figure()
    mine = fig.subplots(3, 2)
    axes = plots.time_panels([r_spmsm, r_lcl], ["spmsm", "lcl"], None, ROWS, ax=mine)
    assert axes.shape == (3, 2)
    assert all(a is b for a, b in zip(np.ravel(axes), np.ravel(mine)))
    assert len(fig.axes) == 6  # nothing added
    assert _n_lines(axes) == [3, 3, 2, 2, 1, 1]
    for j, r in enumerate((r_spmsm, r_lcl)):
        np.testing.assert_array_equal(axes[0, j].lines[1].get_ydata(), r["w_M"] / RPM)
        np.testing.assert_array_equal(axes[0, j].lines[2].get_ydata(), r.n_hat_rpm)
        np.testing.assert_array_equal(axes[2, j].lines[0].get_ydata(), r.theta_error)
        np.testing.assert_array_equal(axes[1, j].lines[0].get_xdata(), r.t)
    assert fig.get_suptitle() == ""  # title None: the caller's figure keeps its own


def test_time_panels_window_and_single_axes(r_lcl):
    a = Figure().add_subplot()
    out = plots.time_panels([r_lcl], ["x"], None, [("i (A)", [("i_g", "g"), ("i_dl", "dl")])],
                            t_window=(0.001, 0.002), ax=a)
    assert out.shape == (1, 1) and out[0, 0] is a
    assert _n_lines(out) == [2]
    m = r_lcl.window(0.001, 0.002)
    assert m.sum() == 20  # 1 ms at 50 us
    np.testing.assert_array_equal(a.lines[1].get_ydata(), r_lcl["i_dl"][m])


@pytest.mark.parametrize("plant", ["r_spmsm", "r_lcl"])
def test_every_derived_channel_works_for_both_plants(plant, request):
    r = request.getfixturevalue(plant)
    for name in plots.DERIVED:
        x = plots.channel(r, name)
        assert x.shape == r.t.shape and np.all(np.isfinite(x)), name
    np.testing.assert_array_equal(plots.channel(r, "n_ref_rpm"), r["w_M_ref"] / RPM)
    np.testing.assert_array_equal(plots.channel(r, "s_abs"), np.hypot(r["s_g"], r["s_dl"]))
    np.testing.assert_array_equal(plots.channel(r, "i_q"), r["i_q"])
    assert set(plots.DERIVED).isdisjoint(CHANNELS)  # a derived name never hides a logged one
    with pytest.raises(KeyError, match="n_rmp"):
        plots.channel(r, "n_rmp")


def test_paper_layouts_draw_on_the_given_axes(r_spmsm):
    fig = Figure()
    mine = fig.subplots(4, 2)
    axes = plots.sensorless_panels([r_spmsm, r_spmsm], ["a", "b"], "t",
                                   [(0.0, 0.01), (0.01, 0.02)], ax=mine)
    assert all(a is b for a, b in zip(np.ravel(axes), np.ravel(mine)))
    # speed: reference, true, estimated; currents i_q, i_d; position true,
    # estimated; errors angle, speed
    assert _n_lines(axes) == [3, 3, 2, 2, 2, 2, 2, 2]
    assert fig.get_suptitle() == "t"

    mine = Figure().subplots(3, 1)
    axes = plots.dq_panels([r_spmsm], ["a"], ax=list(mine.ravel()))  # a plain list
    assert axes.shape == (3, 1) and axes[2, 0] is mine[2]
    assert _n_lines(axes) == [2, 2, 2]  # each signal with its reference

    mine = Figure().subplots(2, 1)
    axes = plots.fig1_bode(yang2018.MOTOR, 1e-4, 500.0, 1.2, ax=mine)
    assert axes[0] is mine[0] and axes[1] is mine[1]
    assert _n_lines(axes) == [6, 5]  # five inductance errors + the measured point


def test_wrong_number_of_axes_is_refused(r_spmsm):
    with pytest.raises(ValueError, match="expected 6 Axes"):
        plots.time_panels([r_spmsm, r_spmsm], ["a", "b"], None, ROWS,
                          ax=Figure().subplots(3, 1))


# --------------------------------------------- (c) ax=None: own figure -------

def test_without_axes_each_function_makes_its_own_figure_in_the_style(r_spmsm, r_lcl):
    import matplotlib.pyplot as plt

    figs_before = plt.get_fignums()
    cases = [
        (plots.time_panels([r_spmsm, r_lcl], ["a", "b"], "T", ROWS), (3, 2)),
        (plots.sensorless_panels([r_spmsm], ["a"], "T"), (4, 1)),
        (plots.dq_panels([r_spmsm] * 4, list("abcd"), "T"), (3, 4)),
        (plots.waveform_spectrum([r_lcl, r_lcl], ["a", "b"], "uc_alpha", "u (V)", "T"),
         (2, 2)),
        (plots.ripple_panels({(law, n): r_lcl for law in ("tde17", "proposed")
                              for n in (30e3, 60e3, 100e3)}, [30e3, 60e3, 100e3], "T"),
         (3, 3)),
        (plots.disturbance_panels(np.arange(8) * 5e-5, np.ones(8, complex),
                                  np.ones(6, complex), np.ones(6, complex), 5e-5, "T"),
         (2, 3)),
        (plots.fig2_bode(1000.0, 1.0, 0.0), (2,)),
    ]
    for axes, shape in cases:
        assert axes.shape == shape
        fig = np.ravel(axes)[0].figure
        assert isinstance(fig, Figure)
        assert len(fig.axes) == int(np.prod(shape))
        assert all(a.figure is fig for a in np.ravel(axes))
        # the style was in force when the figure was made
        assert fig.dpi == plots.STYLE["figure.dpi"]
        assert type(fig.get_layout_engine()).__name__ == "ConstrainedLayoutEngine"
        lw = 0.6 if shape in ((3, 3), (2, 3)) else plots.STYLE["lines.linewidth"]
        assert np.ravel(axes)[0].lines[0].get_linewidth() == lw  # ripple, fig. 4 set 0.6
    # pyplot keeps no reference to these figures (they are garbage once dropped)
    assert plt.get_fignums() == figs_before
    # multi-run layouts carry the suptitle
    assert cases[0][0][0, 0].figure.get_suptitle() == "T"


def test_save_writes_the_named_png(r_spmsm, tmp_path, rc_unchanged):
    axes = plots.time_panels([r_spmsm], ["a"], "T", ROWS)
    path = plots.save(axes, tmp_path / "sub", "name_x")
    assert path == tmp_path / "sub" / "name_x.png"
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # a Figure or a single Axes is accepted as well
    fig = axes[0, 0].figure
    assert plots.save(fig, tmp_path, "fig").is_file()
    assert plots.save(axes[1, 0], tmp_path, "ax").is_file()
