"""An exercise is a declaration (issue 41 item 4): ``Exercise`` holds what its module writes, the fields and
the hooks its decorators register, and the work done with it lives in the modules whose job it is
(problems/solving.py, validity.py, batched.py, motion.py, scene.py), as functions taking the exercise."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from mech.problems import motion, scene, solving, validity
from mech.problems.spec import Exercise

ROOT = Path(__file__).resolve().parents[1]
CLASS_MAX = 200  # lines of the Exercise class (415 before the split)


def test_the_exercise_class_stays_a_declaration():
    tree = ast.parse((ROOT / "problems" / "spec.py").read_text("utf-8"))
    cls = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Exercise")
    assert cls.end_lineno - cls.lineno + 1 <= CLASS_MAX


def _fresh() -> Exercise:
    return Exercise("4.15", formulas=[], states=[("theta", "rad"), ("omega", "rad/s")])


def test_each_decorator_registers_its_hook_and_returns_it_unchanged():
    """The decorator API the exercise modules use, and where each hook is read."""
    ex = _fresh()
    p = ex.resolve({})
    assert not (ex.has_analytic or ex.has_numeric or ex.has_motion or ex.has_scene or ex.has_hamiltonian
                or ex.has_constraints)
    assert validity.expected_errors(ex, p) == {} and validity.theory_ranges(ex, p) == {}
    assert validity.analytic_errors(ex, p) == {} and validity.approximations_at(ex, p) == {}
    assert ex.motion_at(p) is None and motion.motion_path(ex, p) == (None, None)
    assert scene.make_scene(ex, p) == (None, None)

    def analytic(p):
        return {"theta_c": 0.5, "omega_c": 2.0}

    def numeric(p, run):
        return {"theta_c": 0.25, "omega_c": 1.0}

    hooks = {
        "expected_error": lambda p: {"theta_c": 1e-3},
        "theory_range": lambda p: {"theta_c": ("eps", 0.1)},
        "approximations": lambda p: {"omega_c": [(2.1, "small angles")]},
        "analytic_error": lambda p: {"omega_c": 1e-15},
        "hamiltonian": lambda p: ("H", p.theta0),
        "motion": lambda p: ("motion", p.theta0),
        "scene": lambda p, run: ("scene", run.rtol),
        "physics": lambda d: None,
    }
    assert ex.analytic(analytic) is analytic and ex.numeric(numeric) is numeric
    for name, fn in hooks.items():
        assert getattr(ex, name)(fn) is fn, name
    check = ex.constraint(lambda q: "too steep" if q.theta0 > 1.0 else None)
    assert callable(check) and ex.has_constraints

    assert ex.analytic_solver is analytic and ex.numeric_solver is numeric and ex.methods == ["analytic", "numeric"]
    assert ex.solve_analytic(p) == {"theta_c": 0.5, "omega_c": 2.0}
    values, run = ex.solve_numeric(p, rtol=1e-6)
    assert values == {"theta_c": 0.25, "omega_c": 1.0} and run.rtol == 1e-6
    assert validity.expected_errors(ex, p) == {"theta_c": 1e-3}
    assert validity.theory_ranges(ex, p) == {"theta_c": ("eps", 0.1)}
    assert validity.approximations_at(ex, p) == {"omega_c": [(2.1, "small angles")]}
    assert validity.analytic_errors(ex, p) == {"omega_c": 1e-15}
    assert ex.has_hamiltonian and ex.separable_hamiltonian(p) == ("H", p.theta0)
    assert ex.has_motion and ex.motion_at(p) == ("motion", p.theta0)
    made, run = scene.make_scene(ex, p, rtol=1e-7)
    assert ex.has_scene and made == ("scene", 1e-7) and run.rtol == 1e-7
    assert solving.constraint_message(ex, p.replace(theta0=1.2)) == "too steep"
    assert solving.constraint_message(ex, p.replace(theta0=0.5)) is None


def test_a_batched_route_is_the_numeric_solver_and_declares_the_array_hooks():
    import numpy as np

    from mech.solvers.numerics.batch import Column

    ex = _fresh()

    @ex.analytic
    def analytic(P):
        return {"theta_c": Column(np.asarray(P["theta0"]) / 2), "omega_c": Column(np.asarray(P["l"]) * 0 + 3.0)}

    def route(P, rtol, outputs):
        return {o: Column(np.asarray(P["theta0"]) / 2, rel=1e-9) for o in outputs}

    assert ex.batched(("theta_c", "omega_c"))(route) is route
    assert ex.batched_route.numeric is route and ex.numeric_solver == ex.batch_of_one
    p = ex.resolve({"theta0": 1.0})
    assert ex.solve_analytic(p) == {"theta_c": 0.5, "omega_c": 3.0}  # the array hook as a batch of one
    assert ex.solve_numeric(p)[0] == {"theta_c": 0.5, "omega_c": 0.5}
    with pytest.raises(ValueError, match="unknown outputs"):
        ex.batched(("theta_c", "nonsense"))
