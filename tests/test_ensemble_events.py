"""The ensemble integrator's events and per-variant failures (solvers/numerics/batch.py), against closed
forms worked by hand: a harmonic oscillator's zero crossings, y' = y^2's blow-up at t = 1/y0."""

import math

import numpy as np
import pytest

from mech.core.errors import NumericFailure
from mech.solvers.numerics.batch import BatchEvent, integrate_batch

W = np.array([0.5, 1.0, 2.0, 3.7, 10.0])


def oscillator(t, y):  # y = (q, v), q'' = -w^2 q, one w per variant
    return np.array([y[1], -(W ** 2) * y[0]])


def start():  # q = cos(w t): crossings of q = 0 at (k + 1/2) pi / w, downward first
    return np.array([np.ones(W.size), np.zeros(W.size)])


def test_first_crossing_each_variant_its_own():
    down = BatchEvent(lambda t, y: y[0], direction=-1)
    up = BatchEvent(lambda t, y: y[0], direction=+1)
    res = integrate_batch(oscillator, (0.0, 2.0), start(), rtol=1e-11, atol=1e-13, events=[down, up])
    t_down, t_up = res.t_events
    want_down = 0.5 * math.pi / W
    want_up = 1.5 * math.pi / W
    seen_down = want_down <= 2.0
    seen_up = want_up <= 2.0
    assert np.allclose(t_down[seen_down], want_down[seen_down], rtol=1e-9, atol=0)
    assert np.isnan(t_down[~seen_down]).all()
    assert np.allclose(t_up[seen_up], want_up[seen_up], rtol=1e-9, atol=0)
    assert np.isnan(t_up[~seen_up]).all()
    # the state at the downward crossing: q = 0, v = -w
    v = res.y_events[0][1]
    assert np.allclose(v[seen_down], -W[seen_down], rtol=1e-8)
    assert np.allclose(res.y_events[0][0][seen_down], 0.0, atol=1e-10)
    # not terminal: every variant reaches the end, q = cos(2 w)
    assert np.allclose(res.y_end[0], np.cos(2.0 * W), atol=1e-8)
    assert np.array_equal(res.t_stop, np.full(W.size, 2.0))


def test_terminal_event_stops_its_variant_alone():
    stop = BatchEvent(lambda t, y: y[1], direction=+1, terminal=True)  # v = 0 upward: q = -1 at pi / w
    res = integrate_batch(oscillator, (0.0, 1.0), start(), rtol=1e-11, atol=1e-13, events=[stop])
    want = math.pi / W
    stopped = want <= 1.0
    assert stopped.any() and (~stopped).any()
    assert np.allclose(res.t_stop[stopped], want[stopped], rtol=1e-9)
    assert np.allclose(res.y_end[0][stopped], -1.0, atol=1e-9)  # frozen at the event
    assert np.allclose(res.y_end[0][~stopped], np.cos(W[~stopped]), atol=1e-8)
    assert (res.t_stop[~stopped] == 1.0).all()


def test_crossings_after_a_terminal_one_in_the_same_step_did_not_happen():
    # q = 0 downward (terminal) at pi/(2w), v = 0 upward at pi/w: the second never happens
    events = [BatchEvent(lambda t, y: y[0], direction=-1, terminal=True),
              BatchEvent(lambda t, y: y[1], direction=+1)]
    res = integrate_batch(oscillator, (0.0, 50.0), start(), rtol=1e-10, atol=1e-12, events=events)
    assert np.allclose(res.t_events[0], 0.5 * math.pi / W, rtol=1e-8)
    assert np.isnan(res.t_events[1]).all()


def test_a_blow_up_fails_its_variant_alone():
    y0 = np.array([[1.0, -1.0, 0.1, 0.25]])  # y = y0 / (1 - y0 t): y0 = 1 blows up at t = 1 < 2
    res = integrate_batch(lambda t, y: y * y, (0.0, 2.0), y0, rtol=1e-10, atol=1e-12, on_failure="mark")
    assert res.failed.tolist() == [True, False, False, False]
    assert res.why[0] and "underflowed" in res.why[0] and res.why[1] is None
    ok = ~res.failed
    want = y0[0] / (1.0 - y0[0] * 2.0)
    assert np.allclose(res.y_end[0][ok], want[ok], rtol=1e-8)
    assert np.isnan(res.t_stop[0]) and (res.t_stop[ok] == 2.0).all()


def test_without_marking_the_batch_fails_loudly():
    y0 = np.array([[1.0, 0.1]])
    with pytest.raises(NumericFailure, match="underflowed"):
        integrate_batch(lambda t, y: y * y, (0.0, 2.0), y0, rtol=1e-10, atol=1e-12)


def test_batch_of_one_locates_as_the_scalar_integrator_does():
    from mech.solvers.numerics import dop853
    w = 2.0

    def ev(t, y):
        return y[0]

    ev.direction, ev.terminal = -1.0, False
    one = dop853.solve(lambda t, y: np.array([y[1], -w * w * y[0]]), (0.0, 3.0), np.array([1.0, 0.0]),
                       rtol=1e-10, atol=1e-12, events=[ev])
    res = integrate_batch(lambda t, y: np.array([y[1], -w * w * y[0]]), (0.0, 3.0), np.array([[1.0], [0.0]]),
                          rtol=1e-10, atol=1e-12, events=[BatchEvent(lambda t, y: y[0], direction=-1)])
    assert res.t_events[0][0] == pytest.approx(float(one.t_events[0][0]), rel=1e-12)
    assert res.t_events[0][0] == pytest.approx(math.pi / 4, rel=1e-10)


# -- ensemble.follow and Tally.follow: the same question answered batched and one by one ----------------------

def _make_oscillator(sel):
    w = W[sel]
    return lambda t, y: np.array([y[1], -(w ** 2) * y[0]])


@pytest.mark.parametrize("integrator", [None, "scipy-DOP853"])
def test_follow_answers_alike_batched_and_one_by_one(integrator):
    from mech.solvers.numerics.ensemble import follow

    stop = BatchEvent(lambda t, y: y[1], direction=+1, terminal=True)  # q = -1 at pi / w
    got = follow(_make_oscillator, (0.0, 1.0), start(), rtol=1e-10, atol=1e-12, events=[stop],
                 integrator=integrator)
    want = math.pi / W
    stopped = want <= 1.0
    assert np.allclose(got.t_stop[stopped], want[stopped], rtol=1e-7)
    assert np.allclose(got.t_events[0][stopped], want[stopped], rtol=1e-7)
    assert np.isnan(got.t_events[0][~stopped]).all()
    assert np.allclose(got.y_end[0][~stopped], np.cos(W[~stopped]), atol=1e-7)
    assert len(got.records) == (1 if integrator is None else W.size)


@pytest.mark.parametrize("integrator", [None, "scipy-DOP853"])
def test_follow_fails_a_variant_alone_when_asked(integrator):
    from mech.solvers.numerics.ensemble import follow

    y0 = np.array([[1.0, -1.0, 0.1]])
    got = follow(lambda sel: (lambda t, y: y * y), (0.0, 2.0), y0, rtol=1e-10, atol=1e-12,
                 integrator=integrator, on_failure="mark")
    assert got.failed.tolist() == [True, False, False] and got.why[0]
    assert np.allclose(got.y_end[0][1:], y0[0][1:] / (1.0 - 2.0 * y0[0][1:]), rtol=1e-8)
    with pytest.raises(NumericFailure):
        follow(lambda sel: (lambda t, y: y * y), (0.0, 2.0), y0, rtol=1e-10, atol=1e-12, integrator=integrator)


def test_the_tally_records_what_it_followed():
    from mech.problems.batched import Tally

    tally = Tally("scipy-DOP853")
    got = tally.follow(_make_oscillator, (0.0, 0.5), start(), rtol=1e-9, atol=1e-12)
    assert len(tally.records) == W.size and all(r.forced for r in tally.records)
    assert np.allclose(got.y_end[0], np.cos(0.5 * W), atol=1e-7)


def test_a_start_without_numbers_fails_at_once_never_loops():
    """Right-hand sides that are NaN at the start (every variant, or one): the variants fail at once, saying
    why; the rest go on (e^-1 at t = 1).  The loop stepped a NaN step size for ever before."""
    from mech.core import budget

    nan_all = lambda t, y: np.full_like(y, np.nan)  # noqa: E731
    one_nan = lambda t, y: np.where(np.arange(y.shape[1]) == 1, np.nan, -y)  # noqa: E731
    with budget.limit(5.0, what="the test"):
        res = integrate_batch(nan_all, (0.0, 1.0), np.ones((1, 3)), rtol=1e-8, atol=1e-10, on_failure="mark")
        assert res.failed.all() and all("not finite at the start" in w for w in res.why)
        with pytest.raises(NumericFailure, match="not finite at the start"):
            integrate_batch(one_nan, (0.0, 1.0), np.ones((1, 3)), rtol=1e-8, atol=1e-10)
        res = integrate_batch(one_nan, (0.0, 1.0), np.ones((1, 3)), rtol=1e-8, atol=1e-10, on_failure="mark")
    assert res.failed.tolist() == [False, True, False]
    assert res.y_end[0][[0, 2]] == pytest.approx(math.exp(-1.0), rel=1e-7)


@pytest.mark.parametrize("integrator", [None, "scipy-DOP853"])
def test_max_step_holds_each_variant_to_its_own_cap(integrator):
    """y' = 1 from 0 to 1 is one step without a cap; with caps (0.1, 0.25) the shared step keeps within the
    least cap of the variants still stepping, and one by one each within its own."""
    from mech.solvers.numerics.ensemble import follow

    got = follow(lambda sel: (lambda t, y: np.ones_like(y)), (0.0, 1.0), np.zeros((1, 2)), rtol=1e-8, atol=1e-10,
                 max_step=np.array([0.1, 0.25]), integrator=integrator)
    assert got.y_end[0] == pytest.approx([1.0, 1.0], rel=1e-12)
    if integrator is None:
        assert got.records[0].steps >= 10
    else:
        assert [r.t.size - 1 for r in got.records][0] >= 10 and [r.t.size - 1 for r in got.records][1] >= 4
    free = integrate_batch(lambda t, y: np.ones_like(y), (0.0, 1.0), np.zeros((1, 2)), rtol=1e-8, atol=1e-10)
    assert free.steps < 10


def test_each_alone_on_failure_gives_a_failure_to_its_own_variant():
    """A step over four variants that fails whenever variant 2 is in it: the four again one by one, only
    variant 2 failing with the step's reason; the budget running out is never a variant's verdict."""
    from mech.core import budget
    from mech.solvers.numerics.ensemble import each_alone_on_failure

    done, why = [], np.full(4, "", dtype=object)

    def step(idx):
        if 2 in idx:
            raise NumericFailure("variant 2 cannot")
        done.extend(int(k) for k in idx)

    each_alone_on_failure(step, np.arange(4), why)
    assert sorted(done) == [0, 1, 3] and list(why) == ["", "", "variant 2 cannot", ""]

    def spent(idx):
        raise budget.OutOfWork("spent")

    with pytest.raises(budget.OutOfWork):
        each_alone_on_failure(spent, np.arange(4), np.full(4, "", dtype=object))


@pytest.mark.parametrize("integrator", [None, "scipy-DOP853"])
def test_follow_sampled_gives_each_variant_at_each_sample(integrator):
    """The oscillators sampled at 0, 0.25, ..., 1: q = cos(w t) at every sample, batched and one by one."""
    from mech.solvers.numerics.ensemble import follow_sampled

    t = np.linspace(0.0, 1.0, 5)
    Y, records = follow_sampled(_make_oscillator, t, start(), rtol=1e-10, atol=1e-12, integrator=integrator,
                                legs_start_whole=True)
    assert Y.shape == (5, 2, W.size)
    assert np.allclose(Y[:, 0, :], np.cos(np.outer(t, W)), atol=1e-7)
    assert len(records) == (4 if integrator is None else W.size)
