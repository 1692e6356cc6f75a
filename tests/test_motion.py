"""The declared motion (problems/motion.py) and what a Run reports of it, on the harmonic oscillator,
whose motion is known in closed form: x = cos t, v = -sin t from (1, 0), a quarter period pi/2 to x = 0."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mech.problems.motion import Motion, join
from mech.problems.registry import all_exercises, get
from mech.problems.spec import Run
from mech.solvers.numerics.ode import Event


def oscillator(**kw):
    return Motion(lambda t, y: np.array([y[1], -y[0]]), [1.0, 0.0], (0.0, 10.0),
                  event=Event(lambda t, y: y[0], direction=-1, name="x = 0"),
                  invariants={"energy": lambda y: 0.5 * (y[0] ** 2 + y[1] ** 2) / 0.5}, **kw)


def test_follow_ends_at_the_event_and_reports_the_energy_drift():
    run = Run(rtol=1e-10)
    end = run.follow(oscillator())
    assert end.t_end == pytest.approx(math.pi / 2, rel=1e-9)
    assert end.y_end == pytest.approx([0.0, -1.0], abs=1e-9)
    assert 0.0 <= run.invariants["energy"] < 1e-8
    assert run.nfev > 0 and run.method == "DOP853" and run.forced_runs == 0 and run.own_runs == 1


def test_the_trajectory_is_the_followed_motion_in_si():
    """Time scaled by T = 2 s and the state by (3 m, 1.5 m/s): x = 3 cos(t/2), v = -1.5 sin(t/2)."""
    run = Run(rtol=1e-10, keep_trajectories=True)
    run.follow(oscillator(t_scale=2.0, y_scale=[3.0, 1.5]))
    t, y = run.trajectory(2)
    assert t[0] == 0.0 and t[-1] == pytest.approx(math.pi, rel=1e-9) and t.size >= 201
    assert np.allclose(y[0], 3.0 * np.cos(t / 2.0), atol=1e-8) and np.allclose(y[1], -1.5 * np.sin(t / 2.0), atol=1e-8)


def test_to_states_maps_the_integrated_variables_before_the_scale():
    """Integrated as the deviation u = x - 1 from the start: declared x = 1 + u."""
    m = Motion(lambda t, u: np.array([u[1], -(1.0 + u[0])]), [0.0, 0.0], (0.0, 1.0), y_scale=[2.0, 2.0],
               to_states=lambda u: [1.0 + u[0], u[1]])
    assert m.start == pytest.approx([2.0, 0.0])
    run = Run(rtol=1e-10, keep_trajectories=True)
    end = run.follow(m)
    assert m.si(end.y_end) == pytest.approx([2.0 * math.cos(1.0), -2.0 * math.sin(1.0)], rel=1e-8)
    t, y = run.trajectory(2)
    assert np.allclose(y[0], 2.0 * np.cos(t), atol=1e-8)


def test_a_forced_integrator_runs_the_declared_motion():
    run = Run(rtol=1e-8, integrator="RK45")
    run.follow(oscillator())
    assert run.forced_runs == 1 and run.own_runs == 0 and run.method == "RK45"


def test_monitors_report_the_worst_drift_over_the_steps():
    run = Run(rtol=1e-10)
    m = Motion(lambda t, y: np.array([y[1], -y[0]]), [1.0, 0.0], (0.0, 20.0),
               monitors={"energy": lambda Y: float(np.max(np.abs(Y[0] ** 2 + Y[1] ** 2 - 1.0)))})
    end = run.follow(m)
    assert end.t_end == 20.0 and end.y_end == pytest.approx([math.cos(20.0), -math.sin(20.0)], abs=1e-8)
    assert 0.0 < run.invariants["energy"] < 1e-8


def test_costs_are_recorded_not_set():
    run = Run(rtol=1e-6)
    run.cost(40)
    assert run.nfev == 40 and run.own_runs == 0 and run.forced_runs == 0
    with pytest.raises(AttributeError):
        run.nfev = 3


def test_join_orders_legs_in_time_and_drops_a_shared_time():
    class Leg:
        def __init__(self, t, y):
            self.t, self.y, self.sol = np.array(t), np.array(y), None

    t, y = join([(Leg([1.0, 2.0], [[1.0, 2.0]]), 1.0, 0.0, None, None),
                 (Leg([0.0, 1.0], [[0.0, 1.0]]), 1.0, 0.0, None, None)], 1)
    assert list(t) == [0.0, 1.0, 2.0] and list(y[0]) == [0.0, 1.0, 2.0]


def test_a_declared_motion_matches_the_exercises_states():
    """Every exercise that declares a motion has declared states, one per row its motion maps to."""
    declared = [ex for ex in map(get, all_exercises()) if ex.has_motion]
    assert {"4.15", "4.29", "4.30", "4.31", "4.34", "5.6"} <= {ex.id for ex in declared}
    for ex in declared:
        p = ex.resolve({})
        m = ex.motion_at(p)
        assert len(m.start) == len(ex.states), ex.id


def test_a_motion_in_legs_is_followed_leg_by_leg_and_joined_in_time():
    """Leg 1: the oscillator from (1, 0) to x = 0 at t = pi/2, v = -1.  Leg 2: free flight (no force) from
    there for 1 s, declared with its own clock (t_offset pi/2 s): x = -(t - pi/2), v = -1."""
    def flight(path):
        x, v = path.y_end
        return Motion(lambda t, y: np.array([y[1], 0.0]), [x, v], (0.0, 1.0), t_offset=path.t_end)

    run = Run(rtol=1e-10, keep_trajectories=True)
    end = run.follow(oscillator(then=flight))
    assert len(end.legs) == 2 and end.legs[-1] is not end.legs[0]
    assert end.legs[0].t_end == pytest.approx(math.pi / 2, rel=1e-9)
    assert end.t_end == 1.0 and end.y_end == pytest.approx([-1.0, -1.0], abs=1e-8)
    assert run.own_runs == 2
    t, y = run.trajectory(2)
    assert t[0] == 0.0 and t[-1] == pytest.approx(math.pi / 2 + 1.0, rel=1e-9)
    first, second = t <= math.pi / 2, t > math.pi / 2
    assert np.allclose(y[0][first], np.cos(t[first]), atol=1e-8)
    assert np.allclose(y[0][second], -(t[second] - math.pi / 2), atol=1e-8)


def test_a_tool_integration_is_not_the_scenes_motion():
    """``starting`` changes the start of the same equations; ``mark=False`` keeps it out of the trajectory
    (a shooting's trial), while its cost is still recorded."""
    m = oscillator()
    trial = m.starting(y0=[2.0, 0.0], span=(0.0, 5.0))
    assert trial.rhs is m.rhs and trial.event is m.event and list(trial.y0) == [2.0, 0.0]
    run = Run(rtol=1e-10, keep_trajectories=True)
    end = run.follow(trial, mark=False)
    assert end.y_end == pytest.approx([0.0, -2.0], abs=1e-8)
    assert run.trajectory(2) is None and run.own_runs == 1


def test_a_leg_not_shown_is_followed_but_not_the_trajectory():
    """A lead-in leg (shown=False: a strike before the phase the states describe): the oscillator from (1, 0)
    to x = 0 is integrated and recorded, and only the free flight after it (x = -(t - pi/2), v = -1 from
    t = pi/2) is the trajectory."""
    def flight(path):
        x, v = path.y_end
        return Motion(lambda t, y: np.array([y[1], 0.0]), [x, v], (0.0, 1.0), t_offset=path.t_end)

    run = Run(rtol=1e-10, keep_trajectories=True)
    end = run.follow(oscillator(then=flight, shown=False))
    assert len(end.legs) == 2 and run.own_runs == 2
    t, y = run.trajectory(2)
    assert t[0] == pytest.approx(math.pi / 2, rel=1e-9) and t[-1] == pytest.approx(math.pi / 2 + 1.0, rel=1e-9)
    assert np.allclose(y[0], -(t - math.pi / 2), atol=1e-8) and np.allclose(y[1], -1.0, atol=1e-8)


def test_with_variations_carries_the_monodromy_matrix_and_keeps_the_states():
    """x'' = -x over t = 1: d(x, v)/d(x0, v0) = [[cos 1, sin 1], [-sin 1, cos 1]]; the trajectory is the
    motion's own two states (x = 2 cos t from (2, 0)), not the 4 variational rows."""
    m = Motion(lambda t, y: np.array([y[1], -y[0]]), [2.0, 0.0], (0.0, 1.0), y_size=[2.0, 2.0])
    run = Run(rtol=1e-10, keep_trajectories=True)
    end = run.follow(m.with_variations(lambda t, y: np.array([[0.0, 1.0], [-1.0, 0.0]])))
    c, s = math.cos(1.0), math.sin(1.0)
    assert end.y_end[:2] == pytest.approx([2.0 * c, -2.0 * s], abs=1e-9)
    assert end.y_end[2:].reshape(2, 2) == pytest.approx(np.array([[c, s], [-s, c]]), abs=1e-9)
    t, y = run.trajectory(2)
    assert y.shape[0] == 2 and np.allclose(y[0], 2.0 * np.cos(t), atol=1e-8)


def test_a_motion_integrated_in_another_variable_is_seen_in_time():
    """The oscillator in a variable s with dt/ds = 1 + x^2 (a Sundman rescaling, t carried as a third
    state): seen through ``clock`` its trajectory is still x = cos t, v = -sin t, in times that increase to
    the t reached at the span's end."""
    def rhs(s, y):
        f = 1.0 + y[0] ** 2
        return np.array([f * y[1], -f * y[0], f])

    m = Motion(rhs, [1.0, 0.0, 0.0], (0.0, 2.0), to_states=lambda y: y[:2], clock=lambda y: y[2],
               t_scale=2.0, y_scale=[3.0, 1.5])
    run = Run(rtol=1e-10, keep_trajectories=True)
    end = run.follow(m)
    t, y = run.trajectory(2)
    assert t[0] == 0.0 and t[-1] == pytest.approx(2.0 * end.y_end[2], rel=1e-12) and t.size >= 201
    assert np.all(np.diff(t) > 0)
    assert np.allclose(y[0], 3.0 * np.cos(t / 2.0), atol=1e-8) and np.allclose(y[1], -1.5 * np.sin(t / 2.0), atol=1e-8)
