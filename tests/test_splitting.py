"""solvers.numerics.splitting against closed forms: the harmonic oscillator's exact flow, the order of each
composition measured from halved steps, the weights' own order conditions, events on partial steps."""

import math

import pytest

from mech.solvers.numerics.splitting import KAHAN_LI8, STRANG, YOSHIDA6, composed, crossing, lowest, stages


# q'' = -q split as kick p -= q c (exact flow of H = q^2/2) and drift q += p c (exact flow of p^2/2)
def _kick(y, t, c):
    q, p = y
    return (q, p - q * c)


def _drift(y, c):
    q, p = y
    return (q + p * c, p)


def _error(weights, h, t_end=2.0):
    """Largest state error at t_end against the exact flow q = cos t, p = -sin t."""
    step = composed(_kick, _drift, weights)
    y, t = (1.0, 0.0), 0.0
    for _ in range(round(t_end / h)):
        y, t = step(y, t, h)
    return max(abs(y[0] - math.cos(t_end)), abs(y[1] + math.sin(t_end)))


@pytest.mark.parametrize("weights, order, h", [(STRANG, 2, 0.05), (YOSHIDA6, 6, 0.25), (KAHAN_LI8, 8, 0.5)])
def test_each_composition_has_its_order(weights, order, h):
    # the error at h over the error at h/2 is 2^order for a method of that order (by hand: the leading
    # term C h^order of the global error); within 15 % at these steps, above round-off
    ratio = _error(weights, h) / _error(weights, h / 2)
    assert ratio == pytest.approx(2.0**order, rel=0.15)


def test_weights_meet_their_order_conditions():
    # symmetric compositions of a symmetric 2nd-order step: sum w = 1, and the order-3 (and, for order 6 and
    # 8, order-5 and order-7) terms sum w^3, w^5, w^7 vanish only as far as the order needs; palindromic
    for w, odd in ((YOSHIDA6, (3, 5)), (KAHAN_LI8, (3, 5, 7))):
        assert sum(w) == pytest.approx(1.0, abs=1e-14)
        assert tuple(w) == tuple(reversed(w))
        for k in odd:
            assert abs(sum(x**k for x in w)) < 1e-13


def test_stages_merge_adjacent_half_kicks():
    kicks, offsets, drifts = stages((0.25, 0.5, 0.25))
    assert kicks == [0.125, 0.375, 0.375, 0.125] and offsets == [0.0, 0.25, 0.75, 1.0] and drifts == [0.25, 0.5, 0.25]
    for w in (YOSHIDA6, KAHAN_LI8):
        k, o, d = stages(w)
        assert len(k) == len(d) + 1 and sum(k) == pytest.approx(1.0) and o[-1] == pytest.approx(1.0)


def test_a_long_run_keeps_the_energy_bounded():
    # symplectic: the energy error of 10^4 periods stays at the size of one step's (no linear growth)
    step = composed(_kick, _drift, YOSHIDA6)
    y, t, h = (1.0, 0.0), 0.0, 0.3
    worst = 0.0
    for _ in range(20000):
        y, t = step(y, t, h)
        worst = max(worst, abs(0.5 * (y[0] ** 2 + y[1] ** 2) - 0.5))
    assert worst < 1e-5


def test_crossing_and_lowest_on_partial_steps():
    # q = cos t from t = 1.5 with h = 0.2: q crosses zero at pi/2, 0.0708 into the step (to the method's
    # accuracy); the lowest q = -1 at t = pi, within one partial step's local error (h^7 = 1.3e-5 times the
    # method's small constant: the composition is not the exact flow)
    step = composed(_kick, _drift, YOSHIDA6)
    y0 = (math.cos(1.5), -math.sin(1.5))
    tau = crossing(lambda s: step(y0, 1.5, s)[0][0], 0.2)
    assert 1.5 + tau == pytest.approx(math.pi / 2, abs=1e-9)
    y1 = (math.cos(3.0), -math.sin(3.0))
    y2, _ = step(y1, 3.0, 0.2)
    v, start, tau = lowest(lambda s, x: step(s, 0.0, x)[0][0], [y1, y2], 0.2)
    assert v == pytest.approx(-1.0, abs=1e-6) and start is y1 and 3.0 + tau == pytest.approx(math.pi, abs=1e-5)
