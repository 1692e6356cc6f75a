"""mech plot: every registered exercise's default figure renders to a valid image of the expected size."""

import struct
import subprocess
import sys

import pytest
from click.testing import CliRunner

from mech.cli.main import cli
from mech.problems import registry

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
    from mech.cli.figures import generic

    monkeypatch.setattr(generic, "N_LINE", 41)
    monkeypatch.setattr(generic, "LINE_BUDGET_S", 0.2)
    monkeypatch.setattr(generic, "CHOOSE_BUDGET_S", 0.1)


@pytest.mark.parametrize("ex_id", list(registry.all_exercises()))
def test_default_figure_of_every_exercise(ex_id, tmp_path, quick):
    from mech.cli.figures import draw
    from mech.cli.figures.common import save

    ex = registry.get(ex_id)
    fig = draw(ex, ex.resolve({}), n_numeric=2)
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
    assert code == 2 and "pip install 'mech[plot]'" in err and err.count("\n") == 1


def test_list_and_help_do_not_import_matplotlib():
    code = ("import sys; from mech.cli.main import cli; cli.main(['list'], standalone_mode=False); "
            "cli.main(['plot', '--help'], standalone_mode=False); cli.main(['sweep', '--help'], standalone_mode=False); "
            "bad = [m for m in ('matplotlib', 'scipy') if m in sys.modules]; print(bad); assert not bad")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
