"""The Python API (CONTRACT.md, "Python API"), tried as a notebook user would.

Expected values by hand: for the ladder (4.15) sin θc = (2/3) sin θ0, so θ0 = 60° gives
θc = asin(1/√3) = 0.61547970867038..., and ω_c² = (g/l) sin θ0.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import mech
from mech.cli.main import cli
from mech.problems import registry

THETA_C_60 = math.asin(1 / math.sqrt(3))


def _without_timing(d: dict) -> dict:
    """A solve's JSON without what differs between two runs of the same solve: its times."""
    d = dict(d, numeric_info=dict(d["numeric_info"]))
    d.pop("timing")
    d["numeric_info"].pop("import_s", None)
    return d


def test_import_mech_loads_neither_numpy_nor_scipy():
    code = "import sys, mech; print('numpy' in sys.modules, 'scipy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]


def test_solve_with_units_and_si_numbers():
    sol = mech.solve("4.15", theta0="60deg", l=2.0)
    q = sol["theta_c"]
    assert q.numeric == pytest.approx(THETA_C_60, rel=1e-9)
    assert q.analytic == pytest.approx(THETA_C_60, rel=1e-14)
    assert q.unit == "rad" and q.agree is True and sol.agree is True
    assert 0 < q.numeric_err <= q.tol * abs(q.numeric) * 1.0000001
    assert abs(q.numeric - THETA_C_60) <= q.numeric_err
    omega = sol["omega_c"]
    assert omega.analytic == pytest.approx(math.sqrt(9.81 * math.sin(math.pi / 3) / 2.0), rel=1e-14)
    assert sol.params["l"] == 2.0 and sol.params["theta0"] == pytest.approx(math.pi / 3, rel=1e-15)
    assert mech.solve("4.15", l="15 cm").params["l"] == pytest.approx(0.15, rel=1e-15)


def test_the_ladder_trajectory_ends_where_it_leaves_the_wall():
    sol = mech.solve("4.15", theta0="60deg")
    tr = sol.trajectory
    assert tr.names == ["theta", "omega"] and tr.units == ["rad", "rad/s"]
    assert tr.y.shape == (len(tr.names), len(tr.t))
    assert np.all(np.diff(tr.t) > 0)
    # energy along the way: θ'² = (3g/l)(sin θ0 - sin θ), by hand from the rod's energy
    theta, omega = tr.y
    assert np.allclose(omega**2, 3 * 9.81 * (math.sin(math.pi / 3) - np.sin(theta)), rtol=1e-6, atol=1e-9)
    assert theta[-1] == pytest.approx(THETA_C_60, rel=1e-9)


def test_an_exercise_that_integrates_nothing_has_no_trajectory():
    assert mech.solve("4.1").trajectory is None  # moments of inertia: quadrature, no motion


def test_bad_input_raises_with_the_command_lines_message():
    with pytest.raises(mech.BadInput) as api_err:
        mech.solve("4.15", theta0="100deg")
    res = CliRunner().invoke(cli, ["solve", "4.15", "--theta0", "100deg"])
    assert res.exit_code == 2
    assert str(api_err.value) in res.output
    with pytest.raises(mech.BadInput):
        mech.solve("4.15", nonsense=1.0)
    with pytest.raises(mech.BadInput):
        mech.solve("9.99")


@pytest.mark.parametrize("ex_id", ["4.15", "4.29"])
def test_to_dict_is_what_the_command_line_prints(ex_id):
    """Also after the trajectory was asked for (4.29 integrates with dense output only then)."""
    sol = mech.solve(ex_id, theta0="60deg") if ex_id == "4.15" else mech.solve(ex_id)
    assert sol.trajectory is not None
    args = ["solve", ex_id, "--theta0", "60deg", "--json"] if ex_id == "4.15" else ["solve", ex_id, "--json"]
    res = CliRunner().invoke(cli, args)
    assert res.exit_code == 0
    cli_json = json.loads(res.output)
    api_json = sol.to_dict()
    assert _without_timing(api_json) == _without_timing(cli_json)


def test_a_numeric_failure_raises_with_the_solution_attached(monkeypatch):
    ex = mech.exercise("4.15")

    def fails(p, run):
        raise mech.NumericFailure("an event was not reached")

    monkeypatch.setattr(ex, "_numeric", fails)
    with pytest.raises(mech.NumericFailure, match="not reached") as err:
        mech.solve("4.15")
    assert err.value.solution.agree is False
    sol = mech.solve("4.15", raise_on_failure=False)
    assert sol.agree is False and sol["theta_c"].numeric is None


def test_analytic_only():
    sol = mech.solve("4.15", method="analytic", theta0="60deg")
    assert sol["theta_c"].analytic == pytest.approx(THETA_C_60, rel=1e-14)
    assert sol["theta_c"].numeric is None and sol.agree is None


def test_sweep_arrays_csv_and_grid(tmp_path):
    sw = mech.sweep("4.15", theta0=("10deg", "90deg", 9))
    arrays = sw.to_arrays()
    assert len(arrays["theta_c_numeric"]) == 9
    expected = np.arcsin(2 / 3 * np.sin(np.radians(np.linspace(10, 90, 9))))
    assert np.allclose(arrays["theta_c_numeric"], expected, rtol=1e-8)
    assert np.allclose(arrays["theta0"], np.radians(np.linspace(10, 90, 9)), rtol=1e-14)
    assert all(arrays["theta_c_agree"])
    path = tmp_path / "sweep.csv"
    sw.to_csv(path)
    lines = path.read_text().splitlines()
    assert lines[0].startswith("theta0 [rad],theta_c_analytic [rad],theta_c_numeric [rad]")
    assert len(lines) == 10
    grid = mech.sweep("4.15", theta0=["30deg", "60deg"], l=(1.0, 2.0, 3), only="theta_c")
    assert grid.shape == (2, 3) and len(grid.points) == 6
    assert set(grid.to_arrays()) == {"theta0", "l", "theta_c_analytic", "theta_c_numeric", "theta_c_numeric_err",
                                     "theta_c_agree", "theta_c_agree_mask"}


def test_sweep_refuses_nothing_to_sweep_and_unknown_outputs():
    with pytest.raises(mech.BadInput):
        mech.sweep("4.15", theta0="60deg")
    with pytest.raises(mech.BadInput):
        mech.sweep("4.15", theta0=("10deg", "90deg", 3), only="nope")


def test_to_pandas_when_pandas_is_there():
    pd = pytest.importorskip("pandas")
    df = mech.sweep("4.15", theta0=("10deg", "90deg", 3)).to_pandas()
    assert isinstance(df, pd.DataFrame) and len(df) == 3


def test_exercises_exercise_and_check():
    ids = [e.id for e in mech.exercises()]
    catalogue = Path(registry.__file__).parent / "catalogue"
    assert "4.15" in ids and sorted(ids) == sorted(p.stem for p in catalogue.glob("*.toml"))
    ex = mech.exercise("4.15")
    assert ex.title.startswith("Sliding ladder") and [o.name for o in ex.outputs] == ["theta_c", "omega_c"]
    report = mech.check(["4.15"])
    assert report.ok and report.passed >= 1


def test_a_solution_renders_in_a_terminal_and_in_jupyter():
    from rich.console import Console

    sol = mech.solve("4.15", theta0="60deg")
    console = Console(record=True, width=120)
    console.print(sol)
    text = console.export_text()
    assert "theta_c" in text and "0.6154797" in text
    html = sol._repr_html_()
    assert "<table>" in html and "theta_c" in html and "agree" in html


def test_the_command_line_writes_the_trajectory(tmp_path):
    path = tmp_path / "ladder.csv"
    res = CliRunner().invoke(cli, ["solve", "4.15", "--theta0", "60deg", "--trajectory", str(path)])
    assert res.exit_code == 0
    rows = path.read_text().splitlines()
    assert rows[0] == "t [s],theta [rad],omega [rad/s]"
    t, theta, omega = np.loadtxt(path, delimiter=",", skiprows=1).T
    assert np.all(np.diff(t) > 0) and theta[0] == pytest.approx(math.pi / 3, rel=1e-12)
    assert theta[-1] == pytest.approx(THETA_C_60, rel=1e-9)


def test_no_trajectory_where_nothing_is_integrated(tmp_path):
    res = CliRunner().invoke(cli, ["solve", "4.1", "--trajectory", str(tmp_path / "x.csv")])
    assert res.exit_code == 2 and "no trajectory" in res.output
    assert not (tmp_path / "x.csv").exists()


def test_a_chart_sweep_takes_the_batched_route_and_matches_single_solves():
    """5.11 has a batched route: its points must agree with mech.solve within the two error bars."""
    sw = mech.sweep("5.11", omega=(9.9, 10.1, 3), mu=[0.05], only="growth")
    a = sw.to_arrays()
    assert all(a["growth_agree"])
    one = mech.solve("5.11", omega=10.1, mu=0.05)["growth"]
    assert abs(a["growth_numeric"][2] - one.numeric) <= a["growth_numeric_err"][2] + one.numeric_err


def test_own_answers_from_python():
    """θ0 = 60° gives θc = asin(1/√3) = 35.264°; 70.53° is twice that (by hand)."""
    right = mech.solve("4.15", theta0="60deg", expect={"theta_c": "35.26deg"})
    assert right.expect_ok is True and right["theta_c"].expected.match is True
    wrong = mech.solve("4.15", theta0="60deg", expect={"theta_c": "70.53deg"})
    assert wrong.expect_ok is False and "2" in wrong["theta_c"].expected.hint
    res = CliRunner().invoke(cli, ["solve", "4.15", "--theta0", "60deg", "--expect", "theta_c=70.53deg", "--json"])
    cli_json = json.loads(res.output)
    api_json = wrong.to_dict()
    assert _without_timing(api_json) == _without_timing(cli_json)
    with pytest.raises(mech.BadInput):
        mech.solve("4.15", expect={"nope": 1.0})


def test_grade_bench_and_plot_from_python(tmp_path):
    answers = tmp_path / "hw.toml"
    answers.write_text('[[answer]]\nexercise = "4.15"\nparams = { theta0 = "60deg" }\n'
                       'expect = { theta_c = "35.26deg" }\n')
    graded = mech.grade(answers)
    assert graded["ok"] is True and graded["passed"] == 1
    b = mech.bench("4.15", methods="DOP853", tols=[1e-6], repeats=1, max_seconds=5)
    assert b["id"] == "4.15" and any(p["method"] == "DOP853" and p["ok"] for p in b["points"])
    pytest.importorskip("matplotlib")
    fig = mech.plot("4.15", tmp_path / "ladder.png", theta0="80deg")
    assert (tmp_path / "ladder.png").stat().st_size > 1000 and fig is not None


# -- issue 27 item 1: an id is a string; a number is refused, never read as another exercise ----------

@pytest.mark.parametrize("call", [
    lambda i: mech.solve(i),
    lambda i: mech.sweep(i, theta0=("10deg", "80deg", 2)),
    lambda i: mech.check([i]),
    lambda i: mech.check(i),
    lambda i: mech.exercise(i),
    lambda i: mech.bench(i),
    lambda i: mech.plot(i),
])
@pytest.mark.parametrize("number", [4.10, 4.15, 5.10, 4, np.float64(4.30)])
def test_a_number_for_an_id_is_refused_with_the_quoted_form(call, number):
    # 4.10 as a float is 4.1: solving it would answer another exercise without a word
    with pytest.raises(mech.BadInput) as err:
        call(number)
    msg = str(err.value)
    assert "is a number" in msg and 'mech.solve("4.10")' in msg and "\n" not in msg


def test_a_quoted_id_still_solves():
    assert mech.exercise("4.10").id == "4.10" and mech.exercise(" 4.1").id == "4.1"


def test_import_mech_from_the_folder_holding_a_checkout_named_mech(tmp_path):
    # issue 27 item 2: a notebook started beside a clone named `mech` found the clone as an empty
    # namespace package (AttributeError: module 'mech' has no attribute 'solve')
    import os

    checkout = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    (tmp_path / "mech").symlink_to(checkout, target_is_directory=True)
    code = ("import sys, mech; s = mech.solve('4.15', theta0='60deg'); "
            "from mech.cli.main import cli; from mech.problems import registry; "
            "print(repr(s['theta_c'].numeric))")
    run = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True,
                         env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"})
    assert run.returncode == 0, run.stderr[-600:]
    assert float(run.stdout) == pytest.approx(THETA_C_60, rel=1e-8)


def test_sweep_and_grade_take_a_total_budget_like_the_command_line(tmp_path):
    """``budget=`` is the API's ``--budget``: points not reached by then fail, saying so; a budget that is
    no finite positive number is BadInput naming it, before any solve."""
    sw = mech.sweep("4.15", theta0=("10deg", "80deg", 40), budget=0.001, jobs=1)
    last = sw.points[-1]
    assert last.solver_failed and "total budget of 0.001 s ran out" in str(last.errors[0])
    for bad in (float("nan"), 0, -1, "abc", True):
        with pytest.raises(mech.BadInput, match="^budget: "):
            mech.sweep("4.15", theta0=("10deg", "80deg", 3), budget=bad)
    answers = tmp_path / "a.toml"
    answers.write_text('[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "41.81deg" }\n')  # asin(2/3)
    with pytest.raises(mech.BadInput, match="^budget: "):
        mech.grade(answers, budget=float("inf"))
    assert mech.grade(answers, budget=60)["ok"] is True
