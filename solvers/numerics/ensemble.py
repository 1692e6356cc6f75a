"""An ensemble of N variants of one equation of motion followed over one span: the route every batched
exercise integrates by (``Tally.follow`` records it for the exercise's run).

``follow(make_rhs, t_span, y0, rtol=, atol=)``: ``make_rhs(sel)`` gives the right-hand side of the variants
``sel``: ``slice(None)`` for all (states n x N), an index j for variant j alone (states of n floats).  Many
variants: mech's DOP853 steps them together (``batch.integrate_batch``: each variant's error held to rtol
as its own run would; each its own events; a variant that fails, alone).  One variant, or each with an
``integrator`` forced (``mech bench``): ``ode.integrate`` one by one, the same events and failures, so a
forced integrator answers the same question.  The result reads the same either way (``Ensemble``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, NamedTuple

import numpy as np

from mech.core.errors import NumericFailure

__all__ = ["Ensemble", "follow", "follow_sampled", "each_alone_on_failure"]


@dataclass
class Ensemble:
    """What following N variants gave: each one's state where it stopped (``y_end``, n x N), where that was
    (``t_stop``: the span's end or its terminal event; NaN where it failed), each event's first crossing
    per variant (``t_events``: one (N,) array per event, NaN: none; ``y_events``: (n, N) each), the failed
    variants (``failed``, ``why``) and the integrations run (``records``, each with ``nfev`` and
    ``method``)."""

    y_end: np.ndarray
    t_stop: np.ndarray
    t_events: list
    y_events: list
    failed: np.ndarray
    why: np.ndarray  # N texts, "" where the variant did not fail (a route masks with ``why == ""``)
    records: list = field(default_factory=list)

    def __post_init__(self):
        """A failed variant has no state (NaN), and its reason is a text."""
        self.failed = np.asarray(self.failed, dtype=bool)
        self.why = np.array(["" if w is None else str(w) for w in self.why], dtype=object)
        self.y_end = np.array(self.y_end, dtype=float)
        self.y_end[:, self.failed] = np.nan
        self.t_stop = np.asarray(self.t_stop, dtype=float)


def _one_event(ev, j: int, n_all: int):
    """``ev`` (a ``batch.BatchEvent``) for variant j alone, as ``ode.Event``: its function sees variant j's
    state in every column of an ensemble of ``n_all`` (so per-variant constants line up) and gives j's value."""
    from mech.solvers.numerics.ode import Event

    def fn(t, y):
        return float(np.asarray(ev.g(t, np.repeat(np.asarray(y, dtype=float)[:, None], n_all, axis=1)))[j])

    return Event(fn, terminal=ev.terminal, direction=ev.direction, name=ev.name or "event")


def follow(make_rhs: Callable, t_span: tuple[float, float], y0, *, rtol: float, atol, events=(),
           integrator: str | None = None, on_failure: str = "raise", options: Callable | None = None,
           max_step=math.inf) -> Ensemble:
    """The N variants of ``y0`` (n x N) followed over ``t_span`` (see the module).  ``atol``: a number, per
    component or n x N.  ``events``: ``batch.BatchEvent``s.  ``on_failure="mark"``: a variant that fails is
    marked with its reason and the others go on; by default the first failure raises ``NumericFailure``.
    ``options(j)``: ``ode.integrate``'s keywords for variant j (a stiff method and its Jacobian): each
    variant then alone.  ``max_step``: the largest step, a number or one per variant.  The work budget
    running out, or the clock, stops the whole call (``OutOfBudget``): it is never one variant's failure."""
    from mech.core.budget import OutOfBudget
    from mech.solvers.numerics.batch import integrate_batch

    y0 = np.asarray(y0, dtype=float)
    n, N = y0.shape
    atol = np.broadcast_to(np.asarray(atol, dtype=float).reshape(-1, 1) if np.ndim(atol) == 1 else atol, (n, N))
    if integrator is None and options is None and N > 1:
        res = integrate_batch(make_rhs(slice(None)), t_span, y0, rtol=rtol, atol=atol, events=events,
                              on_failure=on_failure, max_step=max_step)
        return Ensemble(res.y_end, res.t_stop, res.t_events, res.y_events, res.failed, res.why, [res])
    from mech.solvers.numerics.ode import integrate

    caps = np.broadcast_to(np.asarray(max_step, dtype=float), (N,))
    out = _Filling(y0.copy(), np.full(N, float(t_span[1])), [np.full(N, np.nan) for _ in events],
                   [np.full((n, N), np.nan) for _ in events], np.zeros(N, dtype=bool), [None] * N, [])
    for j in range(N):
        try:
            traj = integrate(make_rhs(j), t_span, y0[:, j], rtol=rtol, atol=atol[:, j],
                             events=[_one_event(ev, j, N) for ev in events], integrator=integrator,
                             **{"max_step": float(caps[j]), **(options(j) if options else {})})
        except NumericFailure as exc:
            if on_failure != "mark" or isinstance(exc, OutOfBudget):
                raise
            out.failed[j], out.why[j], out.t_stop[j] = True, str(exc), np.nan
            continue
        out.records.append(traj)
        out.y_end[:, j], out.t_stop[j] = traj.y_end, traj.t_end
        for k in range(len(events)):
            if len(traj.t_events[k]):
                out.t_events[k][j] = traj.t_events[k][0]
                out.y_events[k][:, j] = traj.y_events[k][0]
    return Ensemble(*out)


class _Filling(NamedTuple):
    """An ``Ensemble``'s fields while the variants are followed one by one."""

    y_end: np.ndarray
    t_stop: np.ndarray
    t_events: list
    y_events: list
    failed: np.ndarray
    why: list
    records: list


def each_alone_on_failure(step: Callable, idx, why) -> None:
    """``step(idx)`` for the variants ``idx`` together; where it fails (``NumericFailure``), again for each
    variant alone, so that a failure is its own variant's: a variant that fails alone gets the reason in
    ``why[k]``.  The work budget or the clock running out stops it all (``OutOfBudget``), never a variant's
    verdict.  For routes whose integration over the ensemble cannot mark a variant's failure itself."""
    from mech.core.budget import OutOfBudget

    idx = np.asarray(idx)
    try:
        step(idx)
    except OutOfBudget:
        raise
    except NumericFailure as exc:
        if idx.size == 1:
            why[idx[0]] = str(exc)
            return
        for k in idx:
            each_alone_on_failure(step, np.array([k]), why)


def follow_sampled(make_rhs: Callable, t_pts, y0, *, rtol: float, atol, integrator: str | None = None,
                   max_step=math.inf, legs_start_whole: bool = False) -> tuple[np.ndarray, list]:
    """N variants (``y0``: n x N) sampled at the times ``t_pts`` (from t_pts[0]): (states K x n x N, the
    integrations).  Many variants: mech's DOP853 steps them together leg by leg between the samples (each
    variant's error held to rtol as its own run would hold it; ``legs_start_whole``: each leg tried first as
    one step, so that no step exceeds a leg).  One alone, or each with an ``integrator`` forced (``mech
    bench``): one ``ode.integrate`` run a variant, sampled at ``t_pts`` (``max_step``: a number or one per
    variant).  A failure fails the call (``each_alone_on_failure`` gives it to its variant)."""
    from mech.solvers.numerics.batch import integrate_batch
    from mech.solvers.numerics.ode import integrate

    y0 = np.asarray(y0, dtype=float)
    t_pts = np.asarray(t_pts, dtype=float)
    n, N = y0.shape
    atol = np.broadcast_to(np.asarray(atol, dtype=float), y0.shape)
    Y = np.empty((t_pts.size, n, N))
    Y[0] = y0
    records = []
    if integrator is None and N > 1:
        rhs = make_rhs(slice(None))
        for k in range(1, t_pts.size):
            res = integrate_batch(rhs, (t_pts[k - 1], t_pts[k]), Y[k - 1], rtol=rtol, atol=atol,
                                  first_step=t_pts[k] - t_pts[k - 1] if legs_start_whole else None)
            Y[k] = res.y_end
            records.append(res)
        return Y, records
    caps = np.broadcast_to(np.asarray(max_step, dtype=float), (N,))
    for j in range(N):
        traj = integrate(make_rhs(j), (t_pts[0], t_pts[-1]), y0[:, j], rtol=rtol, atol=atol[:, j],
                         max_step=float(caps[j]), t_eval=t_pts, integrator=integrator)
        Y[:, :, j] = traj.y.T
        records.append(traj)
    return Y, records
