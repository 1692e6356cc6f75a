"""mech plot: every registered exercise's default figure renders to a valid image of the expected size; the
scenes come from the exercises (numbers checked against hand derivations), and cli/ holds no physics."""

import math
import pathlib
import re
import struct
import subprocess
import sys

import numpy as np
import pytest
from click.testing import CliRunner

from mech.cli.main import cli
from mech.problems import registry
from mech.problems.scene import make_scene

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg", force=True)

DPI = 40


def run(*args):
    result = CliRunner().invoke(cli, list(args))
    return result.exit_code, result.stdout, result.stderr


def png_size(data: bytes) -> tuple[int, int]:
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    assert data[12:16] == b"IHDR"
    assert data[-8:-4] == b"IEND", "truncated PNG"
    return struct.unpack(">II", data[16:24])


@pytest.fixture
def quick(monkeypatch):
    """The same figures with fewer analytic points: the test is about rendering, not resolution."""
    from mech.figures import generic

    monkeypatch.setattr(generic, "N_LINE", 41)
    monkeypatch.setattr(generic, "LINE_BUDGET_S", 0.2)
    monkeypatch.setattr(generic, "CHOOSE_BUDGET_S", 0.1)


@pytest.mark.parametrize("ex_id", list(registry.all_exercises()))
def test_default_figure_of_every_exercise(ex_id, tmp_path, quick):
    from mech.figures import draw
    from mech.figures.common import save

    ex = registry.get(ex_id)
    fig = draw(ex, ex.resolve({}), n_numeric=2, finish=False)  # as mech plot: the legends placed by save
    w, h = (fig.get_size_inches() * DPI).round().astype(int)
    out = tmp_path / "f.png"
    save(fig, str(out), dpi=DPI)
    assert png_size(out.read_bytes()) == (w, h)
    assert out.stat().st_size > 2000  # something drawn, not a blank canvas


def test_cli_writes_svg_and_pdf_by_suffix(tmp_path):
    svg, pdf = tmp_path / "a.svg", tmp_path / "b.pdf"
    code, _, err = run("plot", "4.15", "--theta0", "60deg", "--points", "1", "-o", str(svg))
    assert code == 0, err
    assert b"<svg" in svg.read_bytes()[:1000]
    code, _, err = run("plot", "5.6", "--generic", "--vary", "l", "--points", "0", "-o", str(pdf))
    assert code == 0, err
    assert pdf.read_bytes()[:5] == b"%PDF-"


def test_generic_figure_of_a_scene_exercise(tmp_path):
    out = tmp_path / "g.png"
    code, _, err = run("plot", "4.10", "--generic", "--points", "2", "--dpi", "40", "-o", str(out))
    assert code == 0, err
    png_size(out.read_bytes())


@pytest.mark.parametrize("args, words", [
    (("plot", "4.15", "-o", "x.gif"), [".png, .svg, .pdf"]),
    (("plot", "4.15", "--theta0", "100deg"), ["theta0", "out of range"]),
    (("plot", "9.9"), ["unknown exercise"]),
    (("plot", "4.15", "--vary", "nope"), ["unknown parameter 'nope'"]),
])
def test_bad_input_exits_2_with_one_line(args, words):
    code, out, err = run(*args)
    assert code == 2 and err.count("\n") == 1
    for w in words:
        assert w in err


def test_without_matplotlib_exit_2_with_the_install_command(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    code, _, err = run("plot", "4.15", "-o", str(tmp_path / "x.png"))
    assert code == 2 and "pip install -e '.[plot]'" in err and err.count("\n") == 1


def test_list_and_help_do_not_import_matplotlib():
    code = ("import sys; from mech.cli.main import cli; cli.main(['list'], standalone_mode=False); "
            "cli.main(['plot', '--help'], standalone_mode=False); cli.main(['sweep', '--help'], standalone_mode=False); "
            "bad = [m for m in ('matplotlib', 'scipy') if m in sys.modules]; print(bad); assert not bad")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


SCENES = [ex_id for ex_id in registry.all_exercises() if registry.get(ex_id).has_scene]
CLI = pathlib.Path(__file__).resolve().parent.parent / "cli"


def test_the_scenes_are_those_their_modules_register():
    """Read from the sources, not from the Exercise: a module registers a scene with ``@exercise.scene``."""
    import importlib

    sources = {e.id: pathlib.Path(importlib.import_module(e.module).__file__).read_text("utf-8")
               for e in registry.index()}
    assert set(SCENES) == {i for i, text in sources.items() if "\n@exercise.scene\n" in text}
    assert len(SCENES) >= 9


@pytest.mark.parametrize("ex_id", SCENES)
def test_every_scene_is_data_with_units_and_finite_curves(ex_id):
    from mech.problems.scene import Band, Line, Map, Markers, Panel, Scene

    ex = registry.get(ex_id)
    scene, run = make_scene(ex, ex.resolve({}), points=1)
    assert isinstance(scene, Scene) and scene.panels
    for panel in scene.panels:
        assert isinstance(panel, Panel)
        drawn = [i for i in panel.items if isinstance(i, (Line, Band, Map))]
        assert drawn, f"{ex_id}: panel '{panel.title}' draws nothing"
        for item in drawn:
            values = np.asarray(item.z if isinstance(item, Map) else item.y if isinstance(item, Line) else item.lo, float)
            assert np.isfinite(values).any(), f"{ex_id}: an all-NaN curve in '{panel.title}'"
        numeric = [i for i in panel.items if isinstance(i, Markers) and i.kind == "numeric"]
        for m in numeric:
            assert np.isfinite(np.asarray(m.y, float)).all(), f"{ex_id}: a numeric marker without a value"
    assert not run.failures, run.failures


def test_points_0_on_the_command_line(tmp_path):
    """Issue 18 item 4: --points 0 is inside the advertised range 0..50 (4.15 raised KeyError: 'theta_c')."""
    out = tmp_path / "f.png"
    code, _, err = run("plot", "4.15", "--points", "0", "--dpi", "40", "-o", str(out))
    assert code == 0, err
    png_size(out.read_bytes())


@pytest.mark.parametrize("ex_id", SCENES)
def test_points_0_draws_analytic_lines_only(ex_id):
    """Every scene with --points 0: no numeric marker, no failure, and the figure is drawn from it (the
    layout and the image file are the same code for every scene: the test above writes one)."""
    import matplotlib.pyplot as plt

    from mech.figures.scene import draw_scene
    from mech.problems.scene import Markers

    ex = registry.get(ex_id)
    params = ex.resolve({})
    scene, scene_run = make_scene(ex, params, points=0)
    kinds = {i.kind for p in scene.panels for i in p.items if isinstance(i, Markers) and len(np.atleast_1d(i.x))}
    assert "numeric" not in kinds
    assert scene_run.failures == []
    plt.close(draw_scene(ex, params, scene, scene_run))


def _lines(scene, kind):
    from mech.problems.scene import Line

    return [i for p in scene.panels for i in p.items if isinstance(i, Line) and i.kind == kind]


@pytest.mark.parametrize("theta0_deg", [90.0, 60.0, 25.0])
def test_ladder_force_curve_is_newtons_law(theta0_deg):
    """4.15.  Energy: theta'^2 = (3g/l)(sin theta0 - sin theta); the torque: theta'' = -(3g/2l) cos theta.
    The wall's force is M x_c'' with x_c = (l/2) cos theta:
        N / (M g) = -(1/2g)(l)(sin th th'' + cos th th'^2) = (3/4) cos th (3 sin th - 2 sin theta0),
    zero first at sin theta_c = (2/3) sin theta0.  The scene's integrated curve must follow it."""
    ex = registry.get("4.15")
    th0 = math.radians(theta0_deg)
    scene, _ = make_scene(ex, ex.resolve({"theta0": th0, "l": 2.5}), points=0)
    (curve,) = _lines(scene, "trajectory")
    th = np.radians(np.asarray(curve.x))
    expected = 0.75 * np.cos(th) * (3 * np.sin(th) - 2 * math.sin(th0))
    assert np.max(np.abs(np.asarray(curve.y) - expected)) < 1e-6
    assert abs(th[-1] - math.asin(2 * math.sin(th0) / 3)) < 1e-7


def test_heavy_top_effective_potential_has_its_minimum_at_theta0():
    """4.21.  dU_ef/dtheta = 0 at theta0 is the torque balance of the steady precession
    (I_A cos th0 Om^2 - I3 w3 Om + M g l = 0); the scene's U_ef curve must bottom out there (to its grid step)."""
    ex = registry.get("4.21")
    for th0 in (0.3, 1.0, 2.0):
        scene, _ = make_scene(ex, ex.resolve({"theta0": th0}), points=0)
        curve = _lines(scene, "analytic")[0]
        x, y = np.asarray(curve.x), np.asarray(curve.y)
        assert abs(x[np.argmin(y)] - math.degrees(th0)) < 0.35  # the grid step is 0.30 deg
        assert abs(np.min(y)) < 1e-3


def test_pendulum_swing_reaches_theta0_and_the_energy_speed():
    """5.6.  From rest at theta0, energy gives the largest speed theta'/omega0 = (2 (1 - cos theta0))^1/2
    = 2 sin(theta0/2) at the bottom; the swing turns at +-theta0."""
    ex = registry.get("5.6")
    th0 = math.radians(120.0)
    scene, _ = make_scene(ex, ex.resolve({"theta0": th0}), points=0)
    (swing,) = _lines(scene, "trajectory")
    assert abs(np.max(np.abs(swing.x)) - 120.0) < 1e-3
    assert abs(np.max(np.abs(swing.y)) - 2 * math.sin(th0 / 2)) < 1e-4


def test_lagrange_maps_mark_l4_on_the_equilateral_apex():
    """4.28: L4 at (1/2 - mu, sqrt(3)/2) in units of d (equilateral triangle with the two bodies)."""
    from mech.problems.scene import Markers

    ex = registry.get("4.28")
    p = ex.resolve({})
    mu = p.M2 / (p.M1 + p.M2)
    scene, _ = make_scene(ex, p, points=1)
    marks = [i for i in scene.panels[0].items if isinstance(i, Markers) and i.kind in ("analytic", "numeric")]
    for m in marks:
        assert np.allclose(np.asarray(m.x), 0.5 - mu, atol=1e-9)
        assert np.allclose(np.abs(np.asarray(m.y)), math.sqrt(3) / 2, atol=1e-9)


def _python_sources(folder):
    return [(f, f.read_text("utf-8")) for f in sorted(folder.rglob("*.py"))]


def test_cli_holds_no_physics():
    """Issue 16: no equation of motion or formula in cli/: it imports only the verification modules of
    mech.solvers, calls no integrator, and uses no trigonometry or roots (the scenes compute those)."""
    # the integrators, root finders and shared mechanics (mech.solvers.numerics and .mechanics) are physics
    # tools; the verification room (crosscheck, bench, sweep, answers, budget) is what cli/ may call
    for f, text in _python_sources(CLI):
        rooms = re.findall(r"mech\.solvers\.(\w+)", text)
        for names in re.findall(r"from mech\.solvers import ([\w, ]+)", text):
            rooms += [n.strip() for n in names.split(",")]
        for room in rooms:
            assert room == "verification", f"{f.name} imports mech.solvers.{room}"
        assert not re.search(r"\b(solve_ivp|odeint|integrate|integrate_to_event|quad)\s*\(", text), f.name
        assert not re.search(r"\b(np|numpy|math)\.(sin|cos|tan|sqrt|hypot|arcsin|arccos|arctan|asin|acos|atan)\b", text), f.name
        assert not re.search(r"^\s*(import|from) scipy", text, re.M), f"{f.name} imports scipy"


def test_distribution_name_is_not_the_index_s_mech():
    """Issue 18 item 21: 'mech' on the package index is another project; ours installs as mech-likharev,
    and --version reads that distribution's metadata."""
    import importlib.metadata
    import tomllib

    root = CLI.parent
    project = tomllib.loads((root / "pyproject.toml").read_text("utf-8"))["project"]
    assert project["name"] == "mech-likharev"
    code, out, err = run("--version")
    assert code == 0, err
    assert out.strip() == f"mech {importlib.metadata.version('mech-likharev')}"
    for f, text in _python_sources(CLI) + [(root / "README.md", (root / "README.md").read_text("utf-8"))]:
        assert not re.search(r"pip install '?mech(?![-\w])", text), f.name  # mech-likharev is ours


def test_bench_figure_is_large_enough_to_read(tmp_path):
    from mech.figures.benchfig import plot_bench

    points = [{"method": m, "ok": True, "error": e, "time_s": t, "nfev": n}
              for m, e, t, n in (("DOP853", 1e-6, 1e-3, 100), ("DOP853", 1e-9, 2e-3, 200),
                                 ("scipy-default", 1e-3, 1e-3, 80), ("default", 1e-11, 3e-3, 500))]
    out = tmp_path / "b.png"
    plot_bench({"id": "4.15", "title": "ladder", "points": points}, str(out))
    w, h = png_size(out.read_bytes())
    assert w >= 1100 and h >= 450


def _endless(*args):
    from mech.core import budget

    while True:
        budget.check("a test's endless loop")


def test_a_slow_numeric_solve_is_cut_by_its_budget_and_the_rest_skipped(monkeypatch):
    from mech.problems.scene import SceneRun

    ex = registry.get("4.15")
    monkeypatch.setattr(ex, "_numeric", _endless)
    monkeypatch.setattr("mech.core.budget.SOLVE_WORK", 10_000)  # a solve's work, counted, not its seconds
    run_ = SceneRun(ex, None, points=3)
    p = ex.resolve({})
    assert all(math.isnan(v) for v in run_.numeric(p).values())
    assert run_.out_of_budget and "work budget of 10,000 units" in run_.failures[0][1]
    assert all(math.isnan(v) for v in run_.numeric(p).values())
    assert "skipped" in run_.failures[1][1]


def test_plot_with_a_slow_solver_still_draws_and_says_so(monkeypatch, tmp_path):
    import time

    monkeypatch.setattr(registry.get("4.15"), "_numeric", _endless)
    monkeypatch.setenv("MECH_BUDGET_S", "0.3")
    t0 = time.perf_counter()
    code, _, err = run("plot", "4.15", "--points", "4", "--dpi", "40", "-o", str(tmp_path / "s.png"))
    assert code == 0, err
    assert time.perf_counter() - t0 < 0.3 + 10  # one budget, then the rest skipped; the drawing itself


def test_a_scene_that_never_ends_fails_in_one_line(monkeypatch, tmp_path):
    monkeypatch.setattr(registry.get("4.15"), "_scene", _endless)
    monkeypatch.setenv("MECH_BUDGET_S", "0.2")
    code, _, err = run("plot", "4.15", "-o", str(tmp_path / "s.png"))
    assert code == 1 and err.count("\n") == 1
    assert "cannot draw 4.15" in err and "time budget" in err
