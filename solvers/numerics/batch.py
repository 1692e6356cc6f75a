"""Many independent initial-value problems integrated at once, as one vectorised system.

A chart evaluates the same equation of motion at thousands of parameter
points.  Integrated one by one, the interpreter's cost per step (a few tens of
microseconds) dominates the arithmetic; integrated together, one step of all
points is a handful of numpy operations on arrays of N numbers.  The points
must share one time interval: an exercise puts every point on the same
interval by scaling time (its period onto a fixed span).

``integrate_batch(rhs, t_span, y0, rtol=, atol=)`` is the DOP853 pair of
``mech.solvers.numerics.dop853`` (the same tableau, error blend and step control) on a
state of shape (n, N): n components for each of N points.  The error of a step
is measured per point (the weighted RMS over that point's n components, as a
single run of that point would measure it) and the step is accepted only when
every point's error is below 1; the step size follows the worst point.  So
every point meets its own tolerance, on a mesh at least as fine as its own run
would choose.  Each point's largest accepted error estimate is returned, so a
caller can see how close to its tolerance each point came.

Events (``BatchEvent``): each point's first crossing of each event function is located on that point's
continuous extension of the step (DOP853's 7th-order dense output, computed only for the steps where a
point crosses); a terminal event stops its point there, its state frozen while the others go on.  With
``on_failure="mark"`` a point whose step size underflows or whose state turns non-finite fails alone
(``failed``, ``why``); by default the batch fails (``NumericFailure``), as a one-point run would.

Memory is (16 n N) numbers for the stages; a caller chunks large grids.
No physics here; numpy only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from mech.core.errors import NumericFailure
from mech.core import budget
from mech.solvers.numerics.dop853 import step_to

__all__ = ["BatchResult", "BatchEvent", "integrate_batch", "MAX_STEPS"]

SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
ERR_EXP = -1.0 / 8.0
MAX_STEPS = 100_000


@dataclass
class BatchResult:
    y_end: np.ndarray  # (n, N): every point's state at t_span[1] (at its terminal event, where it had one)
    steps: int  # accepted steps (shared by all points)
    rejected: int
    nfev: int  # right-hand-side evaluations of the whole batch (each evaluates all N points)
    err_max: np.ndarray  # (N,): each point's largest accepted error estimate (in units of its tolerance)
    method: str = "DOP853 (batched)"
    # one (N,) array per event: each point's first crossing (NaN: none); the states there, (n, N) each
    t_events: list = field(default_factory=list)
    y_events: list = field(default_factory=list)
    t_stop: np.ndarray | None = None  # (N,): where each point stopped (t_span[1], its terminal event, NaN: failed)
    failed: np.ndarray | None = None  # (N,) bool: the points that failed (``on_failure="mark"``)
    why: list | None = None  # N reasons (None: not failed)


@dataclass(frozen=True)
class BatchEvent:
    """An event of every point of an ensemble: ``g(t, y) -> (N,)`` for states y of shape (n, N) and t a
    number or one time per point (N,); a crossing of zero in ``direction`` (0: either way; +1: upward)
    is located on each point's continuous extension.  ``terminal``: the point stops there (its state is
    frozen at the event; the others go on)."""

    g: Callable
    direction: float = 0.0
    terminal: bool = False
    name: str = ""


def _tableau():
    from mech.solvers.numerics import dop853

    if not dop853.available():
        raise NumericFailure("the DOP853 tableau is unavailable: no batched integration")
    return dop853._TABLEAU


def _starting_step(f, t0, y, fy, direction, span, rtol, atol, first_step, active=None) -> float:
    """``first_step``, or Hairer's starting step with the worst point's norms (of the points ``active``)."""
    if first_step is not None:
        return min(abs(float(first_step)), span)
    act = np.ones(y.shape[1], dtype=bool) if active is None else active
    # Hairer's starting step, with the worst point's norms
    scale = atol + np.abs(y) * rtol
    d0 = np.sqrt(np.mean((y / scale) ** 2, axis=0))[act]
    d1 = np.sqrt(np.mean((fy / scale) ** 2, axis=0))[act]
    ratio = np.where((d0 < 1e-5) | (d1 < 1e-5), 1e-6, 0.01 * d0 / np.maximum(d1, 1e-300))
    h0 = min(float(ratio.min()), span)
    f1 = f(t0 + direction * h0, y + direction * h0 * fy)
    d2 = float(np.max(np.sqrt(np.mean(((f1 - fy) / scale) ** 2, axis=0))[act])) / h0
    dm = max(float(d1.max()), d2)
    h1 = max(1e-6, h0 * 1e-3) if not dm > 1e-15 else (0.01 / dm) ** (1.0 / 8.0)
    h = min(100.0 * h0, h1, span)
    return h if math.isfinite(h) else h0  # a trial state off the domain (NaN): the first guess, shrunk if need be


class _Ensemble:
    """The stepping state of ``integrate_batch``: the stages of a step of all points, its error per point,
    which points are still moving (``active``) and which failed, and the step's continuous extension."""

    def __init__(self, rhs, y0, rtol, atol, on_failure):
        tab = _tableau()
        self.C, self.A, self.B, self.D = tab["C"], tab["A"], tab["B"], tab["D"]
        self.EE = np.vstack([tab["E5"], tab["E3"]])
        self.rhs, self.rtol, self.atol, self.mark = rhs, rtol, atol, on_failure == "mark"
        self.y = np.array(y0, dtype=float)
        self.n, self.N = self.y.shape
        self.K = np.empty((16, self.n, self.N))
        self.nfev = 0
        self.active = np.ones(self.N, dtype=bool)
        self.failed = np.zeros(self.N, dtype=bool)
        self.why: list = [None] * self.N
        self.err_max = np.zeros(self.N)

    def step_cap(self) -> float:
        """The largest step the points still stepping allow (``max_step``)."""
        return float(self.max_step[self.active].min()) if self.active.any() else math.inf

    def f(self, t, yy):
        self.nfev += 1
        return np.asarray(self.rhs(t, yy), dtype=float)

    def attempt(self, t, h):
        """A step of size h from (t, self.y): (y_new, f_new, err per point; inf where not finite, 0 for the
        points that no longer move, whose state stays).  Where points fail alone, their overflows are
        theirs (they are marked), never a warning."""
        if self.mark:
            with np.errstate(all="ignore"):
                return self._attempt(t, h)
        return self._attempt(t, h)

    def _attempt(self, t, h):
        K, n, N = self.K, self.n, self.N
        K2 = K.reshape(16, n * N)
        K[0] = self.fy
        hA = h * self.A
        yflat = self.y.reshape(n * N)
        for s in range(1, 12):
            K[s] = self.f(t + self.C[s] * h, (yflat + hA[s, :s] @ K2[:s]).reshape(n, N))
        y_new = self.y + h * (self.B @ K2[:12]).reshape(n, N)
        frozen = ~self.active
        if frozen.any():
            y_new[:, frozen] = self.y[:, frozen]
        f_new = self.f(t + h, y_new)
        K[12] = f_new
        scale = self.atol + np.maximum(np.abs(self.y), np.abs(y_new)) * self.rtol
        with np.errstate(all="ignore"):
            ee = (self.EE @ K2[:13]).reshape(2, n, N) / scale
            n5 = np.einsum("ij,ij->j", ee[0], ee[0])
            n3 = np.einsum("ij,ij->j", ee[1], ee[1])
            den = np.sqrt(n * (n5 + 0.01 * n3))
            err = np.where(den > 0, abs(h) * n5 / np.where(den > 0, den, 1.0), 0.0)
        err[~np.isfinite(err) | ~np.isfinite(y_new).all(axis=0)] = np.inf
        err[frozen] = 0.0
        return y_new, f_new, err

    def fail(self, which, why: str) -> None:
        """Stop the points ``which`` (a mask) as failed, saying why; without ``on_failure="mark"`` the batch
        fails."""
        if not self.mark:
            raise NumericFailure(why)
        for k in np.flatnonzero(which):
            self.why[k] = why
        self.failed |= which
        self.active &= ~which

    def dense(self, t, h, y_new, f_new):
        """The continuous extension of the step just taken (its stages still in K): ``x -> y`` for x the
        fraction of the step, a number or one per point."""
        K, n, N = self.K, self.n, self.N
        K2 = K.reshape(16, n * N)
        hA = h * self.A
        yflat = self.y.reshape(n * N)
        for s in range(13, 16):
            K[s] = self.f(t + self.C[s] * h, (yflat + hA[s, :s] @ K2[:s]).reshape(n, N))
        dy = y_new - self.y
        F = np.empty((7, n, N))
        F[0] = dy
        F[1] = h * self.fy - dy
        F[2] = 2.0 * dy - h * (self.fy + f_new)
        F[3:] = h * (self.D @ K2).reshape(4, n, N)
        y_old = self.y.copy()

        def at(x):
            x = np.broadcast_to(np.asarray(x, dtype=float), (N,))
            x1 = 1.0 - x
            acc = F[6] * x
            for k in (5, 4, 3, 2, 1, 0):
                acc = (acc + F[k]) * (x1 if k % 2 else x)
            return y_old + acc

        return at


def _crossings(ev, a, b, active, found):
    """The points whose event function crosses zero in the event's direction over the step."""
    up, down = (a <= 0.0) & (b >= 0.0), (a >= 0.0) & (b <= 0.0)
    d = ev.direction
    hit = (up if d > 0 else down if d < 0 else up | down) & np.isfinite(a) & np.isfinite(b)
    return hit & active & ~found


def _events_in_step(ens, events, g_old, t, h, y_new, f_new, res, found):
    """Each point's first crossing of each event over the step just accepted, located on the step's
    continuous extension; a terminal event stops its point there (state frozen at the event).  Returns the
    events' values at the step's end."""
    g_new = [np.asarray(ev.g(t + h, y_new), dtype=float) for ev in events]
    hits = [_crossings(ev, g_old[k], g_new[k], ens.active, found[k]) for k, ev in enumerate(events)]
    if not any(m.any() for m in hits):
        return g_new
    at = ens.dense(t, h, y_new, f_new)
    roots = []
    for k, ev in enumerate(events):
        x = np.full(ens.N, np.nan)
        idx = np.flatnonzero(hits[k])
        if idx.size:
            def g_frac(xs, sub, _ev=ev, _idx=idx):
                full = np.ones(ens.N)
                full[_idx[sub]] = xs
                return np.asarray(_ev.g(t + full * h, at(full)), dtype=float)[_idx[sub]]

            xr, _ = illinois(g_frac, np.zeros(idx.size), np.ones(idx.size), g_old[k][idx], g_new[k][idx],
                             xtol=4 * np.finfo(float).eps, rtol=4 * np.finfo(float).eps)
            x[idx] = xr
        roots.append(x)
    # a point stops at its earliest terminal crossing; crossings after it in the same step did not happen
    stop = np.full(ens.N, np.inf)
    for k, ev in enumerate(events):
        if ev.terminal:
            stop = np.fmin(stop, np.where(hits[k], roots[k], np.inf))
    for k in range(len(events)):
        take = hits[k] & (roots[k] <= stop)
        if take.any():
            ys = at(np.where(take, roots[k], 1.0))
            res.t_events[k][take] = t + roots[k][take] * h
            res.y_events[k][:, take] = ys[:, take]
            found[k] |= take
    stopped = np.isfinite(stop)
    if stopped.any():
        ys = at(np.where(stopped, stop, 1.0))
        y_new[:, stopped] = ys[:, stopped]
        res.t_stop[stopped] = t + stop[stopped] * h
        ens.active &= ~stopped
    return g_new


def integrate_batch(
    rhs: Callable[[float, np.ndarray], np.ndarray],
    t_span: tuple[float, float],
    y0: np.ndarray,
    *,
    rtol: float,
    atol,
    first_step: float | None = None,
    max_steps: int = MAX_STEPS,
    events=(),
    on_failure: str = "raise",
    max_step=math.inf,
) -> BatchResult:
    """Integrate ``y' = rhs(t, y)`` for a state ``y`` of shape (n, N) from ``t_span[0]`` to ``t_span[1]``.

    ``atol``: a number, or one per component (shape (n,) or (n, 1)), or per component and point (n, N).
    ``max_step``: the largest step, a number or one per point (the shared step stays within the least of the
    points still stepping, as each one's own run would keep within its own).
    ``events``: ``BatchEvent``s, each point's first crossing of each recorded (``t_events``,
    ``y_events``); a terminal one stops its point.  ``rhs`` is always called with all N points (a point
    that stopped or failed keeps its state).  When the step size underflows, a point's state turns
    non-finite or ``max_steps`` is reached: ``NumericFailure`` for the batch, or with
    ``on_failure="mark"`` the points at fault fail alone (``failed``, ``why``) and the rest go on.
    """
    ens = _Ensemble(rhs, y0, rtol, atol, on_failure)
    if ens.y.ndim != 2:
        raise ValueError("y0 must have the shape (n, N)")
    n, N = ens.n, ens.N
    atol = np.asarray(atol, dtype=float)
    ens.atol = atol[:, None] if atol.ndim == 1 else atol
    t0, t_end = float(t_span[0]), float(t_span[1])
    direction = 1.0 if t_end >= t0 else -1.0
    res = BatchResult(ens.y, 0, 0, 0, ens.err_max, t_events=[np.full(N, np.nan) for _ in events],
                      y_events=[np.full((n, N), np.nan) for _ in events], t_stop=np.full(N, t_end),
                      failed=ens.failed, why=ens.why)
    if t_end == t0 or N == 0:
        return res
    ens.fy = ens.f(t0, ens.y)
    off = ~(np.isfinite(ens.y).all(axis=0) & np.isfinite(ens.fy).all(axis=0))
    if off.any():  # a start where the equations give no number: nothing to step from
        ens.fail(off, f"the state or its rate is not finite at the start (t = {t0:.6g})")
        if not ens.active.any():
            res.y_end, res.nfev = ens.y, ens.nfev
            res.t_stop[ens.failed] = np.nan
            return res
    ens.max_step = np.broadcast_to(np.asarray(max_step, dtype=float), (N,))
    h_abs = min(_starting_step(ens.f, t0, ens.y, ens.fy, direction, abs(t_end - t0), rtol, ens.atol, first_step,
                               ens.active), ens.step_cap())
    g_old = [np.asarray(ev.g(t0, ens.y), dtype=float) for ev in events]
    found = [np.zeros(N, dtype=bool) for _ in events]
    t = t0
    while (t_end - t) * direction > 0 and ens.active.any():
        if res.steps + res.rejected >= max_steps:
            ens.fail(ens.active.copy(), f"the batched integration took more than {max_steps} steps")
            break
        t, h_abs = _step(ens, t, h_abs, direction, t_end, res, events, g_old, found)
    res.y_end, res.nfev = ens.y, ens.nfev
    res.t_stop[ens.failed] = np.nan
    return res


def _step(ens, t, h_abs, direction, t_end, res, events, g_old, found):
    """One accepted step of the points still moving (points at fault failed on the way): (t, next h)."""
    h_start = h_abs
    step_rejected = False
    last_err = np.full(ens.N, np.inf)
    while True:
        # a step of the ensemble counts as one step (its width is numpy's arithmetic, not the work's count): the
        # work a route does variant by variant (a search, a stiff variant alone) is what a chunk's share pays for
        budget.check("batched DOP853 step", 12)
        min_step = 10.0 * abs(math.nextafter(t, direction * math.inf) - t)
        if not h_abs >= min_step:  # (NaN too)
            ens.fail(ens.active & ~(last_err < 1.0),
                     f"the batched integration's step size underflowed at t = {t:.6g}")
            if not ens.active.any():
                return t_end, h_abs
            h_abs, step_rejected = h_start, False
            continue
        t_new, h, h_abs = step_to(t, h_abs, direction, t_end)
        y_new, f_new, err = ens.attempt(t, h)
        last_err = err
        worst = float(err[ens.active].max()) if ens.active.any() else 0.0
        if worst < 1.0:
            factor = MAX_FACTOR if worst == 0.0 else min(MAX_FACTOR, SAFETY * worst ** ERR_EXP)
            if step_rejected:
                factor = min(1.0, factor)
            break
        h_abs *= MIN_FACTOR if not math.isfinite(worst) else max(MIN_FACTOR, SAFETY * worst ** ERR_EXP)
        step_rejected = True
        res.rejected += 1
    np.maximum(ens.err_max, np.where(ens.active, err, 0.0), out=ens.err_max)
    if events:
        g_old[:] = _events_in_step(ens, events, g_old, t, h, y_new, f_new, res, found)
    ens.y, ens.fy = y_new, f_new
    res.steps += 1
    return t_new, min(h_abs * factor, ens.step_cap())


@dataclass
class Column:
    """One output over N points, as a batched route returns it.

    ``value``: the numbers (NaN where undefined or failed).  ``rel``/``abs``:
    the claimed accuracy (numbers or arrays of N), as ``Run.claim`` would give
    it for one point.  ``undefined``/``failed``: lists of (mask, reason): where
    the output has no finite value (both methods should agree on that), and
    where the route could not give a trustworthy number (a loud failure of
    that point, never a number).
    """

    value: np.ndarray
    rel: object = 0.0
    abs: object = 0.0
    undefined: list = None
    failed: list = None

    def __post_init__(self):
        self.value = np.asarray(self.value, dtype=float)
        self.undefined = list(self.undefined or [])
        self.failed = list(self.failed or [])

    def mask(self, which: str) -> np.ndarray:
        out = np.zeros(self.value.shape, dtype=bool)
        for m, _ in getattr(self, which):
            out |= np.asarray(m, dtype=bool)
        return out

    def reason(self, which: str, k: int) -> str | None:
        for m, why in getattr(self, which):
            if np.asarray(m, dtype=bool)[k]:
                return why
        return None


__all__ += ["Column"]


def illinois(f, a, b, fa, fb, *, xtol, rtol, max_iter: int = 200):
    """Roots of N functions at once, each bracketed by its own [a, b] with fa, fb of opposite signs.

    ``f(x, idx)`` evaluates the functions of the points ``idx`` (indices into the N) at ``x`` (one
    value each).  The Illinois variant of false position: superlinear, and the bracket shrinks from
    both sides.  A point is done when its bracket is within ``xtol + rtol |x|`` (arrays or numbers) or
    f is exactly zero.  Returns (x, converged); a point not converged in ``max_iter`` passes is left
    unconverged for the caller to fail loudly.
    """
    a, b = np.array(a, dtype=float), np.array(b, dtype=float)
    fa, fb = np.array(fa, dtype=float), np.array(fb, dtype=float)
    n = a.size
    xtol = np.broadcast_to(np.asarray(xtol, dtype=float), (n,))
    rtol = np.broadcast_to(np.asarray(rtol, dtype=float), (n,))
    if np.any(np.sign(fa) * np.sign(fb) > 0):
        raise ValueError("illinois: a root is not bracketed")
    x = np.where(fa == 0, a, b)
    done = (fa == 0) | (fb == 0) | (np.abs(b - a) <= xtol + rtol * np.abs(b))
    for _ in range(max_iter):
        idx = np.flatnonzero(~done)
        if idx.size == 0:
            break
        budget.check("batched root search")
        A, B, FA, FB = a[idx], b[idx], fa[idx], fb[idx]
        with np.errstate(divide="ignore", invalid="ignore"):
            c = B - FB * (B - A) / (FB - FA)
        lo, hi = np.minimum(A, B), np.maximum(A, B)
        off = ~np.isfinite(c) | (c <= lo) | (c >= hi)
        c[off] = 0.5 * (A + B)[off]
        fc = np.asarray(f(c, idx), dtype=float)
        cross = np.sign(fc) * np.sign(FB) < 0  # the root lies between b and c: b becomes the other end
        A = np.where(cross, B, A)
        FA = np.where(cross, FB, 0.5 * FA)  # Illinois: the end kept twice has its value halved
        a[idx], fa[idx], b[idx], fb[idx], x[idx] = A, FA, c, fc, c
        done[idx] = (fc == 0) | (np.abs(c - A) <= xtol[idx] + rtol[idx] * np.abs(c))
    return x, done


__all__ += ["illinois"]


def scan_up(f, lo, hi, *, factor: float, limit, flo=None, fhi=None):
    """Brackets of the first sign change of N functions from positive to non-positive, scanning up: per
    point, [lo, hi] moves to [hi, factor hi] while f(hi) > 0, until hi passes ``limit`` (no root there).
    ``f(idx, x)`` evaluates the points ``idx`` at x; ``flo``, ``fhi``: values already known at lo and hi
    (else NaN, and f(hi) is evaluated first).  Returns (lo, hi, f(lo) (NaN where lo was never evaluated),
    f(hi), no_root)."""
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    limit = np.broadcast_to(np.asarray(limit, dtype=float), lo.shape)
    n = lo.size
    flo = np.full(n, np.nan) if flo is None else np.array(flo, dtype=float)
    known = fhi is not None
    fhi = np.full(n, np.nan) if fhi is None else np.array(fhi, dtype=float)
    scan = np.ones(n, dtype=bool)
    no_root = np.zeros(n, dtype=bool)
    while scan.any():
        idx = np.flatnonzero(scan)
        if not known:
            fhi[idx] = f(idx, hi[idx])
        known = False
        up = fhi[idx] > 0.0
        grow = idx[up]
        lo[grow], flo[grow], hi[grow] = hi[grow], fhi[grow], factor * hi[grow]
        over = grow[hi[grow] > limit[grow]]
        no_root[over] = True
        scan[idx[~up]] = False
        scan[over] = False
    return lo, hi, flo, fhi, no_root


__all__ += ["scan_up"]


def scan_down(f, hi, fhi, *, factor: float, floor: float):
    """Brackets within a factor 1/``factor`` of a sign change below hi, for N functions negative at hi:
    per point hi moves to factor hi while f(factor hi) < 0 (down to ``floor``).  Returns (lo, hi, f(lo),
    f(hi)); lo is 0 with f(lo) NaN where the floor was reached."""
    hi, fhi = np.array(hi, dtype=float), np.array(fhi, dtype=float)
    n = hi.size
    lo, flo = np.zeros(n), np.full(n, np.nan)
    down = np.ones(n, dtype=bool)
    while down.any():
        idx = np.flatnonzero(down)
        f4 = f(idx, factor * hi[idx])
        neg = f4 < 0.0
        stepped = idx[neg]
        hi[stepped], fhi[stepped] = factor * hi[stepped], f4[neg]
        down[idx[~neg]] = False
        down[stepped[hi[stepped] <= floor]] = False
        ok = idx[~neg]
        lo[ok], flo[ok] = factor * hi[ok], f4[~neg]
    return lo, hi, flo, fhi


__all__ += ["scan_down"]


def by_rows(memo: dict, key, arrays, compute):
    """``compute`` once for each distinct row of ``arrays`` (the parameters an output depends on), the
    results kept in ``memo[key]`` for later calls (a sweep's later chunks); returns them for every point.

    ``compute(*columns)`` takes the distinct rows' columns and returns a tuple of arrays, one entry per
    row; the result is that tuple spread back over all N points."""
    rows = np.stack([np.asarray(a, dtype=float) for a in arrays], axis=1)
    uniq, inverse = np.unique(rows, axis=0, return_inverse=True)
    store = memo.setdefault(key, {})
    keys = [tuple(r) for r in uniq.tolist()]
    todo = [j for j, k in enumerate(keys) if k not in store]
    if todo:
        got = compute(*(uniq[todo, c] for c in range(uniq.shape[1])))
        for n, j in enumerate(todo):
            store[keys[j]] = tuple(g[n] for g in got)
    per_row = [store[k] for k in keys]
    inv = inverse.ravel()
    return tuple(np.array([r[m] for r in per_row])[inv] for m in range(len(per_row[0])))


__all__ += ["by_rows"]


def chunks_by_work(work, overhead: float, single: float | None = None):
    """Indices of N batched problems split into chunks, each integrated on its own.

    A chunk takes as many steps as its hardest problem (``work``: each problem's expected steps, in any unit)
    and a step of n problems costs ``overhead + n`` (``overhead``: the fixed cost of a vectorised step, in
    problems' worth of arithmetic); ``single``: what a step of a problem integrated alone costs (in plain
    floats), None: as a chunk of one.  The problems are sorted by work and binned by its powers of 2; each bin
    is integrated with its neighbours (the cheapest partition into runs of bins) or one by one.  A list of
    index arrays (size 1: alone), easiest first."""
    work = np.maximum(np.asarray(work, dtype=float), 1e-300)
    order = np.argsort(work, kind="stable")
    bins = np.floor(np.log2(work[order]))
    groups = np.split(order, np.flatnonzero(np.diff(bins)) + 1) if order.size else []
    single = overhead + 1.0 if single is None else min(single, overhead + 1.0)
    B = len(groups)
    best = [0.0] + [math.inf] * B  # best[j]: the cheapest plan of the first j bins
    plan: list = [None] * (B + 1)
    for j in range(1, B + 1):
        alone = best[j - 1] + single * float(work[groups[j - 1]].sum())
        best[j], plan[j] = alone, ("alone", j - 1)
        n = 0
        for i in range(j - 1, -1, -1):
            n += groups[i].size
            cost = best[i] + float(work[groups[j - 1]].max()) * (overhead + n)
            if cost < best[j]:
                best[j], plan[j] = cost, ("batch", i)
    out: list = []
    j = B
    while j > 0:
        kind, i = plan[j]
        if kind == "alone":
            out[:0] = [np.array([k]) for k in groups[i]]
        else:
            out[:0] = [np.concatenate(groups[i:j])]
        j = i
    return out


__all__ += ["chunks_by_work"]
