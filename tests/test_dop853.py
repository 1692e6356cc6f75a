"""mech's own DOP853 against exact solutions and against scipy's implementation of the same method."""

import math

import numpy as np
import pytest

from mech.problems.spec import NumericFailure
from mech.solvers.numerics import dop853, ode


def test_the_tableau_is_mechs_own_data():
    """Loaded from mech.solvers.numerics.dop853_tableau, never from a file of scipy's."""
    assert dop853.available()
    import inspect

    source = inspect.getsource(dop853)
    assert "dop853_coefficients" not in source and "find_spec" not in source


def test_the_tableau_equals_scipys_copy_of_the_published_numbers():
    coefficients = pytest.importorskip("scipy.integrate._ivp.dop853_coefficients")
    dop853.available()
    for name in ("C", "A", "B", "E3", "E5", "D"):
        theirs = np.asarray(getattr(coefficients, name), float)
        ours = dop853._TABLEAU[name]
        assert ours.shape == theirs.shape, name
        assert np.array_equal(ours, theirs), name


def kepler(t, y):
    r3 = (y[0] ** 2 + y[1] ** 2) ** 1.5
    return [y[2], y[3], -y[0] / r3, -y[1] / r3]


E = 0.6
Y0 = [1 - E, 0.0, 0.0, math.sqrt((1 + E) / (1 - E))]  # an orbit of period 2 pi


def test_tableau_check_rejects_a_wrong_coefficient():
    dop853.available()
    tab = {k: v.copy() for k, v in dop853._TABLEAU.items()}
    assert dop853._tableau_ok(tab)
    tab["B"][3] += 1e-9
    assert not dop853._tableau_ok(tab)


@pytest.mark.parametrize("rtol", [1e-6, 1e-9, 1e-12])
def test_orbit_closes_after_ten_periods(rtol):
    res = dop853.solve(kepler, (0.0, 20 * math.pi), Y0, rtol=rtol, atol=rtol * 1e-3)
    assert res.status == 0 and res.t[-1] == 20 * math.pi
    # the global error of a 10-orbit run of e = 0.6 grows to about 1e3 rtol (measured against scipy below)
    assert np.abs(res.y[:, -1] - Y0).max() < 1e4 * rtol


@pytest.mark.parametrize("rtol", [1e-6, 1e-9, 1e-12])
def test_same_steps_as_scipy(rtol):
    """The same method with the same step control: the same work and the same answer.

    The evaluations agree to within 10 % (with scipy 1.17 they are identical at
    1e-6 and 1e-9), which allows a future scipy to tune its controller.
    """
    from scipy.integrate import solve_ivp

    ref = solve_ivp(kepler, (0.0, 20 * math.pi), Y0, method="DOP853", rtol=rtol, atol=rtol * 1e-3)
    res = dop853.solve(kepler, (0.0, 20 * math.pi), Y0, rtol=rtol, atol=rtol * 1e-3)
    assert abs(res.nfev - ref.nfev) <= 0.1 * ref.nfev
    # the same order of accuracy: each run's own error against the exact closed orbit is about the same
    # (the step sequences may differ in the last bits of the error norm, and so the errors by some percent)
    err_ref = np.abs(ref.y[:, -1] - Y0).max()
    err_own = np.abs(res.y[:, -1] - Y0).max()
    assert 0.5 < err_own / err_ref < 2.0


def test_dense_output_is_seventh_order_accurate():
    res = dop853.solve(lambda t, y: [y[1], -y[0]], (0.0, 100.0), [1.0, 0.0], rtol=1e-11, atol=1e-14,
                       dense_output=True)
    tt = np.linspace(0.0, 100.0, 1001)
    assert np.abs(res.sol(tt)[0] - np.cos(tt)).max() < 2e-10
    assert res.sol(37.5).shape == (2,)


def test_events_direction_and_terminal():
    def ydown(t, y):
        return y[1]

    ydown.terminal, ydown.direction = False, -1.0

    def x_cross(t, y):
        return y[0] + 0.5

    x_cross.terminal, x_cross.direction = True, 0.0
    res = dop853.solve(kepler, (0.0, 20 * math.pi), Y0, rtol=1e-11, atol=1e-14, events=[ydown, x_cross])
    assert res.status == 1
    # y goes down through 0 at apocentre only (t = pi); the run stops at x = -0.5 before that
    assert len(res.t_events[0]) == 0
    t_hit = res.t_events[1][0]
    assert res.t[-1] == t_hit and abs(res.y[0, -1] + 0.5) < 1e-12
    # Kepler's equation: x = cos(Ecc) - e, t = Ecc - e sin(Ecc)
    ecc = math.acos(-0.5 + E)
    assert t_hit == pytest.approx(ecc - E * math.sin(ecc), abs=1e-10)
    res = dop853.solve(kepler, (0.0, 20 * math.pi), Y0, rtol=1e-11, atol=1e-14, events=[ydown])
    assert np.allclose(res.t_events[0], math.pi * (2 * np.arange(10) + 1), atol=1e-9)


def test_component_event_is_the_same_root_to_the_bit():
    """An event declared as one component of the state (ode.Event(component=i)) is located on that
    component alone; the continuous extension's arithmetic is the same, so the roots are the same floats
    as the general path's (which evaluates the whole state at each trial time): the apocentre passes of
    the Kepler orbit, t = pi (2 j + 1) (y goes down through 0 there)."""
    general = ode.Event(lambda t, y: y[1], terminal=False, direction=-1.0)
    single = ode.Event(lambda t, y: y[1], terminal=False, direction=-1.0, component=1)
    runs = [dop853.solve(kepler, (0.0, 20 * math.pi), Y0, rtol=1e-11, atol=1e-14, events=[ev.as_scipy()])
            for ev in (general, single)]
    assert len(runs[0].t_events[0]) == 10
    assert runs[1].t_events[0].tolist() == runs[0].t_events[0].tolist()
    assert np.array_equal(runs[1].y_events[0], runs[0].y_events[0])
    assert np.allclose(runs[1].t_events[0], math.pi * (2 * np.arange(10) + 1), atol=1e-9)
    # a component that is not what the event function computes is refused, never used quietly
    wrong = ode.Event(lambda t, y: y[1], terminal=False, direction=-1.0, component=0)
    with pytest.raises(ValueError):
        dop853.solve(kepler, (0.0, 20 * math.pi), Y0, rtol=1e-11, atol=1e-14, events=[wrong.as_scipy()])


def test_backwards_with_t_eval():
    t_eval = np.linspace(0.0, -3.0, 7)
    res = dop853.solve(lambda t, y: [y[1], -y[0]], (0.0, -3.0), [1.0, 0.0], rtol=1e-12, atol=1e-15,
                       t_eval=t_eval)
    assert np.array_equal(res.t, t_eval)
    assert np.abs(res.y[0] - np.cos(t_eval)).max() < 1e-11


def test_blow_up_fails_loudly():
    with pytest.raises(NumericFailure):
        ode.integrate(lambda t, y: [y[0] ** 2], (0.0, 2.0), [1.0], rtol=1e-8)


def test_a_damaged_tableau_is_refused_loudly(monkeypatch):
    """No silent fallback: a tableau that fails its order conditions stops the integrator."""
    from mech.solvers.numerics import dop853_tableau

    monkeypatch.setattr(dop853_tableau, "B", {**dop853_tableau.B, 3: dop853_tableau.B.get(3, 0.0) + 1e-9})
    monkeypatch.setattr(dop853, "_TABLEAU_TRIED", False)
    monkeypatch.setattr(dop853, "_TABLEAU", None)
    with pytest.raises(RuntimeError, match="order conditions"):
        dop853.available()
    monkeypatch.setattr(dop853, "_TABLEAU_TRIED", False)
