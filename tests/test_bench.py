"""mech bench: the contract's JSON (every point's fields, failures kept, the summary), the plot, the CLI.

Kept fast: two tolerances and a small time budget.
"""

import json
import math

import pytest
from click.testing import CliRunner

from mech.cli.main import cli
from mech.problems import registry
from mech.studies.bench import STUDENT, bench, error_against, summarize

POINT_KEYS = {"method", "rtol", "error", "time_s", "time_min_s", "time_max_s", "nfev", "ok"}


def run(*args):
    result = CliRunner().invoke(cli, list(args))
    return result.exit_code, result.stdout, result.stderr


def test_error_measure_is_max_relative_and_skips_zero_references():
    ref = {"a": 2.0, "b": 0.0, "c": -4.0}
    err, worst = error_against({"a": 2.002, "b": 1.0, "c": -4.0}, ref, ["a", "b", "c"])
    assert err == pytest.approx(1e-3) and worst == "a"


def test_summary_cheapest_and_ranking():
    pts = [
        {"method": "A", "rtol": 1e-6, "error": 1e-7, "time_s": 0.02, "nfev": 10, "ok": True},
        {"method": "A", "rtol": 1e-9, "error": 1e-10, "time_s": 0.05, "nfev": 30, "ok": True},
        {"method": "B", "rtol": 1e-6, "error": 1e-7, "time_s": 0.01, "nfev": 10, "ok": True},
        {"method": "B", "rtol": 1e-9, "error": None, "time_s": None, "nfev": None, "ok": False},
    ]
    s = {e["method"]: e for e in summarize(pts)}
    assert s["A"]["cheapest_for_1e-6"]["rtol"] == 1e-6 and s["A"]["cheapest_for_1e-9"]["time_s"] == 0.05
    assert s["B"]["cheapest_for_1e-9"] is None and s["B"]["failed_points"] == 1
    assert s["A"]["rank"] == 1 and s["B"]["rank"] == 2


def test_cli_bench_json_carries_every_point(tmp_path):
    png = tmp_path / "b.png"
    code, out, err = run("bench", "5.6", "--tols", "1e-4,1e-7", "--repeats", "1", "--budget", "1", "--json",
                         "--plot", str(png))
    assert code == 0, err
    d = json.loads(out)
    assert d["id"] == "5.6" and d["reference"] == "analytic" and "error_measure" in d
    methods = {p["method"] for p in d["points"]}
    assert {"RK45", "DOP853", "LSODA", "Radau", "Yoshida4", "Yoshida6", STUDENT} <= methods
    for p in d["points"]:
        assert POINT_KEYS <= set(p)
        if p["ok"]:
            assert p["error"] is not None and p["time_min_s"] <= p["time_s"] <= p["time_max_s"]
            assert p["nfev"] > 0
        else:
            assert p["error"] is None and p["note"]
    student = [p for p in d["points"] if p["method"] == STUDENT]
    assert len(student) == 1 and student[0]["rtol"] == 1e-3
    dop = [p for p in d["points"] if p["method"] == "DOP853" and p["ok"]]
    assert min(p["error"] for p in dop) < 1e-7  # tighter request, smaller error
    assert {s["method"] for s in d["summary"]} == methods
    for s in d["summary"]:
        assert "cheapest_for_1e-6" in s and "cheapest_for_1e-9" in s and s["rank"] >= 1
    assert sorted(d["ranking"]) == sorted(methods)
    assert png.stat().st_size > 1000


def test_a_failed_run_stays_in_the_table():
    ex = registry.get("5.6")
    # below the exercise's floor: not run, but kept as a failed point
    r = bench(ex, methods=["DOP853"], tols=[1e-8, 1e-14], repeats=1, budget_s=1.0)
    pts = {p["rtol"]: p for p in r["points"]}
    assert pts[1e-8]["ok"] and not pts[1e-14]["ok"] and pts[1e-14]["error"] is None and pts[1e-14]["note"]


def test_route_without_ode_is_benched_over_its_own_route():
    ex = registry.get("4.3")
    r = bench(ex, tols=[1e-6, 1e-10], repeats=1, budget_s=1.0)
    assert r["route"].startswith("no ODE")
    assert {p["method"] for p in r["points"]} == {r["default"]["method"]}
    assert all(p["ok"] for p in r["points"])


def test_bench_usage_errors():
    code, _, err = run("bench", "9.99")
    assert code == 2 and "unknown exercise" in err
    code, _, err = run("bench", "5.6", "--methods", "Euler")
    assert code == 2 and "unknown method" in err
    code, _, err = run("bench", "5.6", "--tols", "2")
    assert code == 2


def test_json_is_finite():
    ex = registry.get("5.6")
    r = bench(ex, methods=[STUDENT], tols=[1e-6], repeats=1, budget_s=1.0)
    for p in r["points"]:
        assert p["error"] is None or math.isfinite(p["error"])


# --- ode.integrate_to_event: the event confirmed on the dense output instead of a bounded rerun ----------

def _pendulum():
    import numpy as np

    from mech.solvers.numerics.ode import Event

    return (lambda t, y: np.array([y[1], -math.sin(y[0])])), Event(lambda t, y: y[0], direction=-1, name="q = 0")


def test_lean_event_is_ode_event_at_a_fraction_of_the_cost():
    from mech.solvers.numerics import ode

    rhs, ev = _pendulum()
    t1, y1, tr1 = ode.integrate_to_event(rhs, (0.0, 50.0), [1.0, 0.0], ev, rtol=1e-10, confirm="rerun")
    t2, y2, tr2 = ode.integrate_to_event(rhs, (0.0, 50.0), [1.0, 0.0], ev, rtol=1e-10)
    assert t2 == t1 and (y2 == y1).all()
    assert tr2.nfev < 0.3 * tr1.nfev  # no 64-step rerun


def test_lean_event_catches_a_stepped_over_crossing():
    import numpy as np

    from mech.problems.spec import NumericFailure
    from mech.solvers.numerics.ode import Event, integrate_to_event

    # y = t; the event crosses upward at 1.9 and 6, the integrator's steps (exact, growing x10) jump to 6
    g = Event(lambda t, y: ((y[0] - 2.0) ** 2 - 0.01) * (y[0] - 6.0), direction=1)
    with pytest.raises(NumericFailure, match="stepped over"):
        integrate_to_event(lambda t, y: np.array([1.0]), (0.0, 20.0), [0.0], g, rtol=1e-6)
    with pytest.raises(NumericFailure, match="stepped over"):
        integrate_to_event(lambda t, y: np.array([1.0]), (0.0, 20.0), [0.0], g, rtol=1e-6, confirm="rerun")


def test_lean_event_obeys_the_runs_integrator():
    from mech.problems.spec import Run

    from mech.problems.motion import Motion

    rhs, ev = _pendulum()
    run = Run(rtol=1e-8, integrator="LSODA")
    tr = run.follow(Motion(rhs, [1.0, 0.0], (0.0, 50.0), event=ev, options={"method": "DOP853"})).traj
    assert tr.method == "LSODA" and tr.forced
    assert (run.forced_runs, run.own_runs, run.nfev) == (1, 0, tr.nfev)


def test_the_student_integrator_drops_the_exercises_settings():
    """"student": solve_ivp's defaults (RK45, rtol 1e-3, atol 1e-6, no step bound), whatever the call asked."""
    from mech.problems.spec import Run

    from mech.problems.motion import Motion

    run = Run(rtol=1e-10, integrator="student")
    tr = run.follow(Motion(lambda t, y: -y, [1.0], (0.0, 1.0), options={"atol": 1e-14, "max_step": 1e-3})).traj
    assert (tr.method, tr.rtol, tr.forced) == ("RK45", 1e-3, True)
    # RK45 at rtol 1e-3 over one decay time takes a handful of steps, not the 1000 the step bound forces
    assert len(tr.t) < 20


def test_no_integrator_keeps_the_exercises_own_choice():
    from mech.problems.spec import Run

    from mech.problems.motion import Motion

    run = Run(rtol=1e-9)
    tr = run.follow(Motion(lambda t, y: -y, [1.0], (0.0, 1.0), options={"method": "DOP853"})).traj
    assert (tr.method, tr.forced, run.forced_runs, run.own_runs, run.method) == ("DOP853", False, 0, 1, "DOP853")


@pytest.mark.parametrize("ex_id, applies", [("4.21", True), ("5.12", True), ("5.10", True), ("4.1", False),
                                             ("5.8", False)])
def test_probe_sees_whether_the_forced_integrator_ran(ex_id, applies):
    """The probe forces LSODA on the Run: an exercise that integrates (directly, through floquet, through the
    orbit continuation) reports it ran; a closed-form route (4.1: integrals over the mass) or a harmonic balance
    (5.8) does not."""
    from mech.problems import registry
    from mech.studies.bench import probe_route

    ex = registry.get(ex_id)
    integrates, _ = probe_route(ex, ex.resolve({}))
    assert integrates is applies


# --- issue 34: bench returns a typed result whose to_dict() is the contract's JSON ---------------------

def test_bench_result_is_typed_frozen_and_its_dict_is_the_json():
    import dataclasses

    from mech.studies.bench import BenchResult

    ex = registry.get("4.15")
    r = bench(ex, methods=["DOP853"], tols=[1e-6], repeats=1, budget_s=1.0)
    assert isinstance(r, BenchResult)
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.id = "4.16"
    d = r.to_dict()
    # the contract's keys, in the order mech bench --json has always printed them
    assert list(d) == ["id", "title", "params", "reference", "error_measure", "measured_outputs",
                       "skipped_outputs", "left_out_outputs", "route", "default", "points", "summary", "timing",
                       "ranking", "student_vs_default"]
    assert all(isinstance(d[k], list) for k in ("points", "summary", "ranking", "measured_outputs"))
    assert d["id"] == r.id == r["id"] == "4.15" and d["points"][0]["method"] == "DOP853"
    json.dumps(d)  # plain JSON types all the way down
