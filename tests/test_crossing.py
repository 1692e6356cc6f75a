"""``crossing.to_crossing``: one variant stepped by a scipy method to its first crossing of one terminal event.

It must give what ``solve_ivp`` with that terminal event gives, bit for bit (the same solver steps, the
same crossing test and the same brentq on the dense output), and the crossing itself where it is known by
hand: the harmonic oscillator x'' = -x from (1, 0) has x' = -sin t, which crosses zero upward at t = pi
and downward at t = 2 pi (but a start on x' = 0 leaving it downward is that crossing already, as in
solve_ivp); x = cos t crosses zero downward at pi/2."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from mech.core import budget
from mech.core.errors import NumericFailure
from mech.solvers.numerics.crossing import to_crossing


def _vdp_slow(eps):
    # the van der Pol oscillator in x, u = x'/eps against the slow time, with int (1 - x^2) ds: stiff for large eps
    e2 = eps * eps

    def rhs(s, z):
        d = 1.0 - z[0] * z[0]
        return [e2 * z[1], e2 * d * z[1] - z[0], d]

    def jac(s, z):
        return [[0.0, e2, 0.0], [-2.0 * e2 * z[0] * z[1] - 1.0, e2 * (1.0 - z[0] ** 2), 0.0], [-2.0 * z[0], 0.0, 0.0]]

    return rhs, jac


def _scipy(rhs, span, y0, g, direction, **kw):
    ev = lambda t, y: g(t, y)  # noqa: E731
    ev.terminal, ev.direction = True, direction
    return solve_ivp(rhs, span, y0, events=[ev], **kw)


@pytest.mark.parametrize("method, eps, direction", [("LSODA", 50.0, 1.0), ("LSODA", 300.0, 1.0), ("BDF", 20.0, 1.0),
                                                    ("Radau", 20.0, 1.0), ("LSODA", 50.0, 0.0)])
def test_the_same_numbers_as_solve_ivp_with_a_terminal_event(method, eps, direction):
    rhs, jac = _vdp_slow(eps)
    rtol, atol = 1e-10, 1e-13 * np.array([1.0, 1.0 / eps**2, 1.0])
    y0 = np.array([2.0, 0.0, 0.0])
    g = lambda t, y: y[1]  # noqa: E731
    ours = to_crossing(rhs, (0.0, 4.0), y0, rtol=rtol, atol=atol, g=g, direction=direction, method=method, jac=jac)
    ref = _scipy(rhs, (0.0, 4.0), y0, g, direction, method=method, rtol=rtol, atol=atol, jac=jac)
    assert ref.status == 1 and ours.status == 1
    assert ours.t_events[0][0] == ref.t_events[0][0]
    assert np.array_equal(ours.y_events[0][0], ref.y_events[0][0])
    assert np.array_equal(ours.y_end, ref.y[:, -1]) and ours.t_end == ref.t[-1]
    assert ours.nfev == ref.nfev and ours.method == method


@pytest.mark.parametrize("component, direction, when", [(1, 1.0, math.pi), (0, -1.0, 0.5 * math.pi),
                                                        (0, 0.0, 0.5 * math.pi)])
def test_the_crossing_where_it_is_known_by_hand(component, direction, when):
    got = to_crossing(lambda t, y: [y[1], -y[0]], (0.0, 10.0), [1.0, 0.0], rtol=1e-11, atol=1e-14,
                      g=lambda t, y: y[component], direction=direction)
    assert got.t_events[0][0] == pytest.approx(when, rel=1e-9)
    assert got.y_end == pytest.approx([math.cos(when), -math.sin(when)], abs=1e-9)
    assert got.y_end[component] == pytest.approx(0.0, abs=1e-12)


def test_a_start_on_the_surface_leaving_it_in_the_event_direction_is_the_crossing():
    kw = dict(rtol=1e-11, atol=1e-14)
    got = to_crossing(lambda t, y: [y[1], -y[0]], (0.0, 10.0), [1.0, 0.0], g=lambda t, y: y[1], direction=-1.0,
                      method="LSODA", **kw)
    ref = _scipy(lambda t, y: [y[1], -y[0]], (0.0, 10.0), [1.0, 0.0], lambda t, y: y[1], -1.0, method="LSODA", **kw)
    assert got.t_events[0][0] == ref.t_events[0][0] == 0.0
    # from just past it, the next downward crossing is at 2 pi
    got = to_crossing(lambda t, y: [y[1], -y[0]], (0.0, 10.0), [math.cos(0.1), -math.sin(0.1)], g=lambda t, y: y[1],
                      direction=-1.0, **kw)
    assert got.t_events[0][0] == pytest.approx(2.0 * math.pi - 0.1, rel=1e-9)


def test_no_crossing_runs_to_the_end_of_the_span():
    # x = cos t stays above -2: no crossing; the state at t = 3 is scipy's without events, bit for bit
    kw = dict(rtol=1e-10, atol=1e-13)
    got = to_crossing(lambda t, y: [y[1], -y[0]], (0.0, 3.0), [1.0, 0.0], g=lambda t, y: y[0] + 2.0, direction=-1.0,
                      method="LSODA", **kw)
    ref = solve_ivp(lambda t, y: [y[1], -y[0]], (0.0, 3.0), [1.0, 0.0], method="LSODA", **kw)
    assert len(got.t_events[0]) == 0 and got.status == 0
    assert got.t_end == 3.0 and np.array_equal(got.y_end, ref.y[:, -1])
    assert got.y_end == pytest.approx([math.cos(3.0), -math.sin(3.0)], abs=1e-8)


def test_every_evaluation_counts_as_work():
    # the work budget stops the integration (OutOfWork, a NumericFailure), as ode.integrate's does
    rhs, jac = _vdp_slow(300.0)
    with pytest.raises(budget.OutOfWork):
        with budget.limit(work=200):
            to_crossing(rhs, (0.0, 4.0), [2.0, 0.0, 0.0], rtol=1e-10, atol=1e-13, g=lambda t, y: y[1], direction=1.0,
                        jac=jac)
    assert issubclass(budget.OutOfWork, NumericFailure)
