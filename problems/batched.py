"""A route written once: an exercise's batched route and the batch of one that is its one-point solve.

An exercise that registers a batched route (``Exercise.batched``) writes its hooks once, on arrays of
variants: ``analytic(P) -> {output: Column}``, ``expected_error(P) -> {output: rel | (rel, abs)}`` (arrays,
NaN: none), ``theory_range(P) -> {output: (label or labels, values)}`` and the numeric route
``fn(P, rtol, outputs, memo=None, tally=None) -> {output: Column}``.  ``P`` maps every parameter to an array
of N values (validated); the route computes only the ``outputs`` asked, for all N at once (see
``mech.solvers.numerics.batch``).  A sweep, a class and a chart call them over N variants; a one-point solve
calls them here over arrays of one and unpacks (the numeric route too where it gives every output; else the
registered ``numeric`` calls ``Exercise.batch_of_one`` for those it gives), so the one-point solve and the
batched route cannot drift apart.  A ``memo`` keyword, if the route takes one, is a dict shared by all the
chunks of one sweep (by a solve and its rerun); ``tally`` (a ``Tally``) takes the invariants' drifts and the
integrations.  ``boundaries`` maps a parameter to (output, label): the analytic value of that output is a
boundary in that parameter (5.11's mu = mu_th(omega)), drawn on maps over that parameter.

``Tally``: what a numeric route reports besides its Columns (each variant's invariant drifts, its
integrations); the batch of one hands them to the ``Run`` (``numeric_info``, bench's counts).
"""

from __future__ import annotations

import functools
import inspect
import math
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

from mech.core.errors import NumericFailure
from mech.problems.params import Params, Undefined

__all__ = ["BatchedRoute", "Tally", "register", "one_point", "analytic_solver", "analytic_at", "expected_at",
           "range_at"]


@dataclass(frozen=True)
class BatchedRoute:
    """What ``Exercise.batched`` registers: the numeric route over arrays and the exercise's own array hooks
    (``analytic``, ``expected_error``, ``theory_range``: the same functions its one-point solve calls)."""

    numeric: Callable
    outputs: tuple[str, ...]
    analytic: Callable
    expected_error: Callable | None = None
    boundaries: dict = field(default_factory=dict)
    # ``theory_range(P) -> {output: (label, array)}``: the expansion parameter of each leading-order output
    theory_range: Callable | None = None


class Tally:
    """What a batched numeric route reports besides its Columns.

    ``invariant(name, drift, allowed=None)``: the drift of a monitored invariant per variant (an array of N,
    the worst kept over calls), ``allowed`` what the method may drift (None: the exercise's claim);
    ``record(result)``: an integration (``nfev``, ``method``, ``forced``); ``method``: the route's own name
    for its method where the integrations' does not say it all (None: theirs); ``info``: anything else, one
    value per variant.  ``integrator``: the integrator a
    one-point solve was asked to force (``mech bench``), None for mech's DOP853 over the ensemble."""

    def __init__(self, integrator: str | None = None):
        self.integrator = integrator
        self.method: str | None = None
        self.invariants: dict = {}
        self.records: list = []
        self.info: dict = {}  # name -> one value per variant (None: nothing to say), ``run.info`` at one point

    def record(self, result: Any) -> Any:
        self.records.append(result)
        return result

    def follow(self, make_rhs: Callable, t_span, y0, *, rtol: float, atol, events=(), on_failure: str = "mark",
               max_step=math.inf):
        """The ensemble's ``Run.follow``: N variants (``y0``: n x N) followed over ``t_span`` by
        ``ensemble.follow`` (mech's DOP853 stepping them together; one by one under a forced ``integrator``),
        each with its own events and, by default, its own failure (``failed``, ``why``); the integrations
        are recorded.  Returns the ``ensemble.Ensemble``."""
        from mech.solvers.numerics.ensemble import follow

        got = follow(make_rhs, t_span, y0, rtol=rtol, atol=atol, events=events, integrator=self.integrator,
                     on_failure=on_failure, max_step=max_step)
        self.records.extend(got.records)
        return got

    def invariant(self, name: str, drift, allowed=None) -> None:
        import numpy as np

        drift = np.abs(np.asarray(drift, dtype=float))
        old = self.invariants.get(name)
        self.invariants[name] = (drift if old is None else np.fmax(old[0], drift), allowed)


def register(ex: Any, fn: Callable, outputs: tuple[str, ...], boundaries: Mapping | None) -> Callable:
    """``Exercise.batched``'s registration: ``fn`` is ``ex``'s route over arrays of variants giving ``outputs``,
    and its analytic, expected_error and theory_range hooks are declared written on arrays too."""
    ex._on_arrays = {"analytic", "expected_error", "theory_range"}
    ex.batched_route = BatchedRoute(
        fn, tuple(outputs), lambda P: ex._analytic(P),
        expected_error=lambda P: ex._expected_error(P) if ex._expected_error else {},
        boundaries=dict(boundaries or {}),
        theory_range=lambda P: ex._theory_range(P) if ex._theory_range else {})
    return fn


def analytic_solver(hook: Callable) -> Callable:
    """An analytic hook on arrays as a one-point solver, ``fn(p) -> {output: value}`` (the batch of one); its
    ``array_hook`` is the hook (assigned back, as a test's monkeypatch undone does, it registers the hook)."""

    def one(p):
        return analytic_at(hook, p)

    one.array_hook = hook
    return one


def _one(p: Mapping) -> Params:
    """The parameters of one point as arrays of one variant (a numeric route indexes its variants)."""
    import numpy as np

    return Params({k: np.array([float(v)]) for k, v in p.items()})


def _point(p: Mapping) -> Params:
    """The parameters of one point as 0-d arrays, for the closed forms (analytic, expected_error,
    theory_range): numpy's scalars cost a third of arrays of one (5.11's allowances: 1 ms against 3)."""
    import numpy as np

    return Params({k: np.float64(v) for k, v in p.items()})


def _reason(pairs, k: int = 0):
    """The first reason of a Column's (mask, reason) list that holds at variant k (masks of any shape)."""
    import numpy as np

    for m, why in pairs:
        if np.ravel(np.asarray(m, dtype=bool))[k]:
            return why
    return None


def _first(x) -> float:
    import numpy as np

    return float(np.ravel(np.asarray(x, dtype=float))[0])


def analytic_at(fn: Callable, p: Mapping) -> dict:
    """``fn(P) -> {output: Column}`` at one point: {output: float | Undefined(its reason)}."""
    import numpy as np

    with np.errstate(all="ignore"):
        cols = fn(_point(p))
    out = {}
    for name, col in cols.items():
        why = _reason(col.undefined)
        # an undefined value that is +-inf is infinite by the physics (a period of a plane that stops turning)
        out[name] = Undefined(why, infinite=bool(np.isinf(_first(col.value)))) if why is not None else _first(col.value)
    return out


def expected_at(fn: Callable, p: Mapping) -> dict:
    """``expected_error`` on arrays at one point, in the one-point form: rel, (rel, abs) or (None, abs);
    an output with neither (NaN) is left out."""
    import numpy as np

    with np.errstate(all="ignore"):
        got = fn(_point(p))
    out = {}
    for name, e in got.items():
        rel, ab = e if isinstance(e, tuple) else (e, math.nan)
        rel, ab = _first(rel), _first(ab)
        if rel == rel and ab == ab:
            out[name] = (rel, ab)
        elif rel == rel:
            out[name] = rel
        elif ab == ab:
            out[name] = (None, ab)
    return out


def label_at(label, k: int):
    """A theory range's label at variant k: one text for all, or one per variant."""
    if label is None or isinstance(label, str):
        return label
    import numpy as np

    return str(np.ravel(np.asarray(label, dtype=object))[k])


def range_at(fn: Callable, p: Mapping) -> dict:
    """``theory_range`` on arrays at one point: {output: (label, value)}."""
    return {name: (label_at(label, 0), _first(vals)) for name, (label, vals) in fn(_point(p)).items()}


@functools.lru_cache(maxsize=64)
def _keywords(fn: Callable) -> frozenset:
    """The parameters a route takes (``memo``, ``tally``): read once (``inspect`` costs 2 ms a call)."""
    return frozenset(inspect.signature(fn).parameters)


def one_point(ex: Any, p: Mapping, run: Any, outputs=None) -> dict:
    """The batched route at the one point ``p`` (arrays of one): its values ({output: float | Undefined}), its
    claims (``run.claim``), invariants, integrations and failure (``NumericFailure``, the first output's that
    failed) reported to ``run``.  ``outputs``: those asked (all the route's by default).  Where a trajectory is
    asked for, the declared motion is followed and marked (it is what the solve shows, not what it answers)."""
    import numpy as np

    route = ex.batched_route
    outputs = tuple(route.outputs if outputs is None else outputs)
    tally = Tally(run.integrator)
    takes = _keywords(route.numeric)
    kw = {}
    if "memo" in takes:  # shared by a solve and its rerun, as a sweep's chunks share it
        kw["memo"] = run.shared.setdefault(("batched route", ex.id), {})
    if "tally" in takes:
        kw["tally"] = tally
    cols = route.numeric(_one(p), run.rtol, outputs, **kw)
    if tally.method:
        run.method = tally.method
    for result in tally.records:
        run.record(result)
    for name, (drift, allowed) in tally.invariants.items():
        run.invariant(name, _first(drift), allowed=None if allowed is None else _first(allowed))
    for name, per_variant in tally.info.items():
        v = list(per_variant)[0]
        if v is not None:
            run.info[name] = v if isinstance(v, str) else float(v)
    values = {}
    for name in outputs:
        col = cols[name]
        why = col.reason("failed", 0)
        if why is not None:
            raise NumericFailure(why)
        undefined = col.reason("undefined", 0)
        if undefined is not None:
            values[name] = Undefined(undefined, infinite=bool(np.isinf(_first(col.value))))
            continue
        values[name] = _first(col.value)
        rel, ab = _first(col.rel), _first(col.abs)
        run.claim(name, rel=rel if rel == rel else None, abs=ab if ab == ab and ab else None)
    if run.keep_trajectories and ex.has_motion and set(outputs) == {o.name for o in ex.outputs}:
        motion = ex.motion_at(p)
        if motion is not None:  # None: nothing moves at p (4.34 at theta_amp = 0, 4.29's bead at rest on the axis)
            run.follow(motion)
    return values
