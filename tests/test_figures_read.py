"""Issue 27 item 9: the figures read as a student would read them.

Axis scales follow from the physics worked out by hand: 4.19's Omega_body = omega cos(alpha) (zero at
alpha = 90 deg, so never a log axis); 4.30's T_F = 2 pi/(omega_E |cos theta|) (a day to infinity: hours, log);
4.14's d_cm = 3R/8 (proportional to R: linear axes) and omega ~ R^(-1/2) (a power law: log-log);
4.1's I_hoop_diam = I_disk_axis = M R^2/2 (the same line, which must stay visible).  The legend and line
checks below are this file's own geometry, not the figure code's."""

import math

import numpy as np
import pytest
from click.testing import CliRunner

from mech.problems import registry

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg", force=True)


@pytest.fixture
def quick(monkeypatch):
    from mech.figures import generic

    monkeypatch.setattr(generic, "N_LINE", 61)
    monkeypatch.setattr(generic, "LINE_BUDGET_S", 0.3)


def _figure(ex_id, **kw):
    from mech.figures import draw

    ex = registry.get(ex_id)
    return draw(ex, ex.resolve({}), n_numeric=3, **kw)


def _panel(fig, ylabel_part):
    return next(ax for ax in fig.axes if ylabel_part in ax.get_ylabel())


def _close(fig):
    import matplotlib.pyplot as plt

    plt.close(fig)


def _line_points(ax, line, step=1.5):
    """Display points along a drawn line (its segments sampled every ``step`` pixels) and its markers."""
    xy = ax.transData.transform(np.asarray(line.get_xydata(), float))
    ok = np.all(np.isfinite(xy), axis=1)
    out = [xy[ok]]
    if line.get_linestyle() not in ("None", "none", "", " "):
        for a, b, good in zip(xy[:-1], xy[1:], ok[:-1] & ok[1:]):
            if good:
                n = max(2, int(np.hypot(*(b - a)) / step))
                out.append(a + np.linspace(0, 1, n)[:, None] * (b - a))
    return np.vstack(out)


def _legend_hides_nothing(fig):
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    for ax in fig.axes:
        leg = ax.get_legend()
        if leg is None or not ax.get_visible():
            continue
        box = leg.get_window_extent(r)
        frame = ax.get_window_extent(r)
        if not (frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1):
            continue  # a legend outside the axes hides no data
        for line in ax.get_lines():
            if line.get_transform() is not ax.transData or not line.get_label() or not len(line.get_xydata()):
                continue
            pts = _line_points(ax, line)
            inside = (pts[:, 0] > box.x0) & (pts[:, 0] < box.x1) & (pts[:, 1] > box.y0) & (pts[:, 1] < box.y1)
            assert not inside.any(), f"{ax.get_ylabel()}: the legend covers {line.get_label()}"


def test_419_round_off_of_zero_is_not_drawn_on_a_log_axis(quick):
    fig = _figure("4.19", generic=True)
    ax = _panel(fig, "rad/s")
    assert ax.get_yscale() == "linear"
    lo, hi = ax.get_ylim()
    assert lo > -5 and hi < 30  # Omega_body from 10 rad/s down to 0, omega_lab from 20 to 10
    _legend_hides_nothing(fig)
    _close(fig)


def test_430_foucault_period_in_hours_on_a_log_axis(quick):
    fig = _figure("4.30")
    ax = _panel(fig, "T_F")
    assert "[h]" in ax.get_ylabel() and ax.get_yscale() == "log"
    # at the pole T_F = 2 pi/omega_E = 86164 s = 23.93 h (a sidereal day): the lowest value drawn
    ys = np.concatenate([ln.get_ydata() for ln in ax.get_lines() if ln.get_transform() is ax.transData])
    assert np.nanmin(ys) == pytest.approx(2 * math.pi / 7.2921159e-5 / 3600, rel=1e-6)
    _close(fig)


def test_414_proportional_output_on_linear_axes_and_power_law_on_log_log(quick):
    fig = _figure("4.14")
    d = _panel(fig, "d_cm")
    assert d.get_xscale() == "linear" and d.get_yscale() == "linear"
    w = _panel(fig, "rad/s")
    assert w.get_xscale() == "log" and w.get_yscale() == "log"
    _close(fig)


def test_415_legend_leaves_the_curve_visible():
    fig = _figure("4.15")
    _legend_hides_nothing(fig)
    _close(fig)


def test_41_coincident_lines_stay_visible_and_are_named(quick):
    fig = _figure("4.1")
    ax = fig.axes[0]
    lines = [ln for ln in ax.get_lines() if ln.get_transform() is ax.transData and len(ln.get_xydata()) > 1]
    pairs = 0
    for i, a in enumerate(lines):
        for b in lines[i + 1:]:
            ya, yb = np.asarray(a.get_ydata(), float), np.asarray(b.get_ydata(), float)
            if ya.shape == yb.shape and np.allclose(ya, yb, rtol=1e-9, equal_nan=True) \
                    and np.allclose(a.get_xdata(), b.get_xdata()):
                pairs += 1
                same_look = (a.get_linestyle(), a.get_marker()) == (b.get_linestyle(), b.get_marker())
                assert not same_look, (a.get_label(), b.get_label())
    assert pairs >= 2  # the analytic lines and the numeric markers of I_hoop_diam and I_disk_axis
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any("I_disk_axis" in t and "= I_hoop_diam" in t for t in labels)
    _legend_hides_nothing(fig)
    _close(fig)


def test_coarse_sweep_map_is_interpolated_and_says_so(monkeypatch, tmp_path):

    from mech.figures import common
    from mech.cli.main import cli

    made = []
    monkeypatch.setattr(common, "save", lambda fig, path, **kw: made.append(fig))
    result = CliRunner().invoke(cli, ["sweep", "5.6", "--theta0", "10deg:170deg:9", "--l", "0.5:2:4",
                                      "--no-verify", "--plot", str(tmp_path / "m.png")])
    assert result.exit_code == 0, result.output
    fig = made[0]
    ax = fig.axes[0]
    mesh = next(c for c in ax.collections if c.__class__.__name__ == "QuadMesh")
    # the colours are given at the 9 x 4 computed points, not on 10 x 5 cell edges (blocks)
    assert mesh.get_coordinates().shape[:2] == (4, 9)
    assert "interpolated" in fig._suptitle.get_text()
    _close(fig)

