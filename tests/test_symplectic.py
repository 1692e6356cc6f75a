"""The symplectic integrator: order, events, and bounded energy error over thousands of periods (scipy#12690).

The pendulum (5.6's scene) in tau = omega0 t: H = p^2/2 - cos q.  An adaptive
Runge-Kutta method's energy error grows with the number of periods; a
symplectic one's oscillates within a band fixed by the step.  Measured: the
worst energy error over the last tenth of the run against the first tenth.
"""

import math

import numpy as np
import pytest

from mech.problems import registry
from mech.solvers.numerics.ode import integrate
from mech.solvers.numerics.symplectic import YOSHIDA4, YOSHIDA6, integrate_fixed, pendulum, solve_scene


def test_composition_weights_are_consistent():
    assert sum(YOSHIDA4) == pytest.approx(1.0, abs=1e-15)
    assert sum(YOSHIDA6) == pytest.approx(1.0, abs=1e-14)
    # order 4 needs sum w^3 = 0 (the third-order error term of the composition cancels)
    assert sum(w**3 for w in YOSHIDA4) == pytest.approx(0.0, abs=1e-14)


@pytest.mark.parametrize("order", [4, 6])
def test_convergence_order(order):
    """Halving the step divides the error at a fixed time by 2^order (within 30 %)."""
    sc = pendulum(1.0, 2.0)
    ref = integrate_fixed(sc, 0.01, order=6)
    errs = [abs(integrate_fixed(sc, h, order=order).q - ref.q) for h in (0.2, 0.1)]
    assert errs[0] / errs[1] == pytest.approx(2.0**order, rel=0.3)


def test_pendulum_energy_bounded_while_dop853_drifts():
    periods = 1000  # theta0 = 1 rad: period 6.70 in tau
    sc = pendulum(1.0, periods)
    sym = integrate_fixed(sc, 0.25, order=6, sample_every=50)
    e = np.abs([s[1] for s in sym.samples])
    n = len(e)
    sym_first, sym_last = e[: n // 10].max(), e[-n // 10:].max()

    def rhs(t, y):
        return np.array([y[1], -math.sin(y[0])])

    tr = integrate(rhs, (0.0, sc.t_max), [1.0, 0.0], rtol=1e-4, atol=1e-7)
    h0 = 0.5 * 0.0 - math.cos(1.0)
    d = np.abs(0.5 * tr.y[1] ** 2 - np.cos(tr.y[0]) - h0) / abs(h0)
    m = len(d)
    rk_first, rk_last = d[: m // 10].max(), d[-m // 10:].max()
    # symplectic: bounded (the band does not grow), and small at a step of ~27 per period
    assert sym_last < 1.5 * sym_first and sym_last < 1e-5
    # DOP853: the error grows roughly linearly with time (x10 between the first and the last tenth)
    assert rk_last > 5.0 * rk_first
    assert rk_last > 10.0 * sym_last


@pytest.mark.parametrize("ex_id", ["5.6", "4.15", "4.34"])
def test_exercise_scenes_match_the_analytic_answer(ex_id):
    ex = registry.get(ex_id)
    p = ex.resolve({})
    values, res = solve_scene(ex.separable_hamiltonian(p), 1e-8, 6)
    exact = ex.solve_analytic(p)
    for name, v in values.items():
        assert v == pytest.approx(exact[name], rel=1e-7), name
    assert res.event_found and res.energy_drift < 1e-9
