"""Searches over N functions at once: each round evaluates every point still searching in one call.

A batched route (many variants of one exercise) evaluates its function for all variants together, one
ensemble integration a round; a search written for one point would integrate them one at a time.
``integrate_variants`` integrates them (``ensemble.follow`` over chunks of like cost: mech's DOP853 stepping variants together, a variant
whose integration fails failing alone); ``interpolated_root`` finds roots by inverse quadratic interpolation kept inside a bracket (few rounds
where each costs an integration); ``brent_minimum`` is Brent's bounded minimizer
(``roots.minimize_bounded``'s steps: golden sections that guarantee progress, a parabola through the three
best points where it falls inside and shrinks the step), each point with its own bracket, its own steps and
its own stopping test, written on arrays.

No physics here; numpy only.
"""

from __future__ import annotations

import math

import numpy as np

from mech.core import budget

__all__ = ["brent_minimum", "integrate_variants", "interpolated_root"]

_GOLD = 0.5 * (3.0 - math.sqrt(5.0))
_SQRT_EPS = math.sqrt(np.finfo(float).eps)


def brent_minimum(f, a, b, *, xatol, x0=None, max_iter: int = 500):
    """Minima of N functions, each on its own bracket [a, b] (arrays of N), by Brent's method.

    ``f(x, idx)`` evaluates the functions of the points ``idx`` (indices into the N) at ``x`` (one value
    each).  ``x0``: each point's first trial inside its bracket (default: the golden section of [a, b]).  A
    point stops when its minimum is known within ``xatol`` (a number or N of them) plus a relative round-off
    floor sqrt(eps)|x|, as ``roots.minimize_bounded``.  Returns (x, f(x), converged): a point not converged
    in ``max_iter`` rounds is left so for the caller to fail loudly.
    """
    a, b = np.minimum(a, b).astype(float), np.maximum(a, b).astype(float)
    n = a.size
    xatol = np.broadcast_to(np.asarray(xatol, dtype=float), (n,))
    x = a + _GOLD * (b - a) if x0 is None else np.clip(np.asarray(x0, dtype=float), a, b)
    fx = np.asarray(f(x.copy(), np.arange(n)), dtype=float)
    w, v, fw, fv = x.copy(), x.copy(), fx.copy(), fx.copy()
    d, e = np.zeros(n), np.zeros(n)
    active = np.ones(n, dtype=bool)
    for _ in range(max_iter):
        mid = 0.5 * (a + b)
        tol1 = _SQRT_EPS * np.abs(x) + xatol / 3.0
        tol2 = 2.0 * tol1
        active &= ~(np.abs(x - mid) <= tol2 - 0.5 * (b - a))
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        budget.check("batched minimum search")
        X, W, V, FX, FW, FV = x[idx], w[idx], v[idx], fx[idx], fw[idx], fv[idx]
        A, B, M, T1, T2, D, E = a[idx], b[idx], mid[idx], tol1[idx], tol2[idx], d[idx], e[idx]
        # the parabola through (x, w, v): its step p/q, accepted inside the bracket and below half the step
        # before last
        r = (X - W) * (FX - FV)
        q = (X - V) * (FX - FW)
        p = (X - V) * q - (X - W) * r
        q = 2.0 * (q - r)
        p = np.where(q > 0, -p, p)
        q = np.abs(q)
        para = (np.abs(E) > T1) & (np.abs(p) < np.abs(0.5 * q * E)) & (q * (A - X) < p) & (p < q * (B - X))
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(para, p / np.where(q != 0, q, 1.0), 0.0)
        near_end = para & (((X + step) - A < T2) | (B - (X + step) < T2))
        step = np.where(near_end, np.copysign(T1, M - X), step)
        golden_e = np.where(X < M, B - X, A - X)
        E_new = np.where(para, D, golden_e)
        D_new = np.where(para, step, _GOLD * golden_e)
        U = X + np.where(np.abs(D_new) >= T1, D_new, np.copysign(T1, D_new))
        FU = np.asarray(f(U.copy(), idx), dtype=float)
        better = FU <= FX
        left = U < X
        # the bracket shrinks towards the better point
        A_new = np.where(better, np.where(left, A, X), np.where(left, U, A))
        B_new = np.where(better, np.where(left, X, B), np.where(left, B, U))
        # the three best points: u replaces x (x -> w -> v), or takes w's or v's place
        to_w = ~better & ((FU <= FW) | (W == X))
        to_v = ~better & ~to_w & ((FU <= FV) | (V == X) | (V == W))
        V_new = np.where(better | to_w, W, np.where(to_v, U, V))
        FV_new = np.where(better | to_w, FW, np.where(to_v, FU, FV))
        W_new = np.where(better, X, np.where(to_w, U, W))
        FW_new = np.where(better, FX, np.where(to_w, FU, FW))
        x[idx], fx[idx] = np.where(better, U, X), np.where(better, FU, FX)
        w[idx], fw[idx], v[idx], fv[idx] = W_new, FW_new, V_new, FV_new
        a[idx], b[idx], d[idx], e[idx] = A_new, B_new, D_new, E_new
    return x, fx, ~active


def interpolated_root(f, a, b, fa, fb, x0=None, f0=None, *, rtol, max_iter: int = 100):
    """Roots of N functions, each bracketed by [a, b] (fa, fb of opposite signs) and, if given, known at x0
    inside it (f0): each round evaluates every point still searching once (``f(x, idx)`` as in
    ``brent_minimum``).

    The trial is the inverse quadratic through the last three points evaluated (the secant through the last
    two where two values coincide), kept where it falls inside the bracket and is under half the step before
    last (Brent's safeguard: the bracket then shrinks geometrically), else the bracket's midpoint.  A point
    stops at the last point it evaluated when f is exactly zero there, when its bracket is within ``rtol |x|``,
    or when the next interpolated step from it is within ``rtol |x|`` and under a tenth of the step that led
    there: the iteration is then superlinear and that step is the point's error.  So the root is always a
    point evaluated last (its other values hold there).  Returns (x, converged); a point not converged in
    ``max_iter`` rounds is left so for the caller to fail loudly."""
    lo, hi = np.array(a, dtype=float), np.array(b, dtype=float)
    flo, fhi = np.array(fa, dtype=float), np.array(fb, dtype=float)
    if np.any(np.sign(flo) * np.sign(fhi) > 0):
        raise ValueError("interpolated_root: a root is not bracketed")
    if x0 is None:  # the end nearer its root (by f) as the last point, the other before it
        near = np.abs(flo) <= np.abs(fhi)
        x0, f0, lo, flo, hi, fhi = (np.where(near, lo, hi), np.where(near, flo, fhi), np.where(near, hi, lo),
                                    np.where(near, fhi, flo), np.where(near, lo, hi), np.where(near, flo, fhi))
    x1, f1 = np.array(x0, dtype=float), np.array(f0, dtype=float)  # the last three points, newest first
    x2, f2, x3, f3 = lo.copy(), flo.copy(), hi.copy(), fhi.copy()
    side = np.sign(f1) == np.sign(flo)
    lo, flo = np.where(side, x1, lo), np.where(side, f1, flo)
    hi, fhi = np.where(side, hi, x1), np.where(side, fhi, f1)
    step, before = np.abs(x1 - x2), np.abs(hi - lo)  # the step that led to x1 and the one before it
    done = f1 == 0.0
    for _ in range(max_iter):
        with np.errstate(divide="ignore", invalid="ignore"):
            quad = (x1 * f2 * f3 / ((f1 - f2) * (f1 - f3)) + x2 * f1 * f3 / ((f2 - f1) * (f2 - f3))
                    + x3 * f1 * f2 / ((f3 - f1) * (f3 - f2)))
            trial = np.where(np.isfinite(quad), quad, x1 - f1 * (x1 - x2) / (f1 - f2))
        s = np.abs(trial - x1)
        left, right = np.minimum(lo, hi), np.maximum(lo, hi)
        inside = np.isfinite(trial) & (trial > left) & (trial < right)
        tol = rtol * np.abs(x1)
        done |= (right - left <= tol) | ((s <= tol) & (s <= 0.1 * step))  # a tiny step may round outside
        idx = np.flatnonzero(~done)
        if idx.size == 0:
            break
        budget.check("batched root search")
        keep = inside[idx] & (s[idx] < 0.5 * before[idx])
        x = np.where(keep, trial[idx], 0.5 * (lo[idx] + hi[idx]))
        fx = np.asarray(f(x.copy(), idx), dtype=float)
        before[idx] = np.where(keep, step[idx], 0.5 * (right - left)[idx])
        step[idx] = np.abs(x - x1[idx])
        x3[idx], f3[idx], x2[idx], f2[idx], x1[idx], f1[idx] = x2[idx], f2[idx], x1[idx], f1[idx], x, fx
        same = np.sign(fx) == np.sign(flo[idx])
        lo[idx], flo[idx] = np.where(same, x, lo[idx]), np.where(same, fx, flo[idx])
        hi[idx], fhi[idx] = np.where(same, hi[idx], x), np.where(same, fhi[idx], fx)
        done[idx] = fx == 0.0
    return x1, done


# a batched step's fixed cost and a step of one variant alone (plain floats), in variants' worth of arithmetic
# (``batch.chunks_by_work``): measured for 5.5's 6 components, ~0.27 ms a step +0.33 us a variant, 0.13 ms alone
STEP_OVERHEAD, STEP_ALONE = 800.0, 400.0


def integrate_variants(system, coefs, span, y0, *, rtol, atol, work=None, integrator=None, record=None, event=None,
                       options=None, overhead: float = STEP_OVERHEAD, alone: float = STEP_ALONE):
    """The end states (n x N) of N variants of one equation over ``span`` from ``y0`` (n x N), each variant's
    failure (an object array of N reasons, "" where it ran) and where each stopped.

    ``system(*c)`` is the right-hand side ``rhs(t, y)`` for the coefficients ``c``: arrays (the variants
    stepped together, y of n x N) or floats (one variant, y of n); ``coefs``: numbers or arrays of N.
    ``atol``: a number, n numbers or n x N.  ``event``: (g, direction), a terminal event: each variant stops
    at its first crossing (``g(t, y)`` of either form of the state); its time is returned (NaN where there
    was none within the span, the state then at the span's end).  Variants are stepped together by
    ``batch.integrate_batch`` (each held to its own tolerance, located at its own event, failing alone), in
    chunks of like ``work`` (each variant's expected steps, ``batch.chunks_by_work`` with ``overhead`` and
    ``alone``; None: one chunk); a chunk of one, or each variant with an ``integrator`` forced (``mech
    bench``), by ``ode.integrate``; ``options(*c)``: ``ode.integrate``'s keywords for a variant (a stiff
    method and its Jacobian), each variant then alone (with an ``event``, stepped to it by
    ``crossing.to_crossing``: solve_ivp's steps and event, without its overhead).  A variant that fails keeps its reason and a NaN
    state; the work budget running out stops the call (``ensemble.follow``: never one variant's failure).  ``record(result)`` takes each integration (its ``nfev``, ``method``).  Returns (y_end, why,
    t_stop)."""
    from mech.solvers.numerics.batch import BatchEvent, chunks_by_work
    from mech.solvers.numerics.ensemble import follow

    y0 = np.asarray(y0, dtype=float)
    n, N = y0.shape
    atol = np.asarray(atol, dtype=float)
    atol = np.broadcast_to(atol[:, None] if atol.ndim == 1 else atol, (n, N))
    coefs = [np.broadcast_to(np.asarray(c, dtype=float), (N,)) for c in coefs]
    if options is not None and integrator is None and event is not None:
        return _alone_to_event(system, coefs, span, y0, rtol, atol, event, options, record)
    y_end, why = np.full((n, N), np.nan), np.full(N, "", dtype=object)
    t_stop = np.full(N, float(span[1]) if event is None else np.nan)
    record = record or (lambda result: None)
    events = [] if event is None else [BatchEvent(event[0], event[1], terminal=True)]
    chunks = [np.arange(N)] if work is None or N <= 1 else chunks_by_work(work, overhead, alone)
    for chunk in chunks:
        def make_rhs(sel, _c=chunk):  # the chunk's variants together (a slice), or its variant sel alone
            return system(*(c[_c] if isinstance(sel, slice) else float(c[_c[sel]]) for c in coefs))

        opts = None if options is None else (lambda j, _c=chunk: options(*(float(c[_c[j]]) for c in coefs)))
        got = follow(make_rhs, span, y0[:, chunk], rtol=rtol, atol=np.array(atol[:, chunk]), events=events,
                     integrator=integrator, on_failure="mark", options=opts)
        for result in got.records:
            record(result)
        y_end[:, chunk] = np.where(got.failed, np.nan, got.y_end)
        why[chunk[got.failed]] = [got.why[k] for k in np.flatnonzero(got.failed)]
        if event is not None:
            t_stop[chunk] = np.where(got.failed, np.nan, got.t_events[0])
    return y_end, why, t_stop


def _alone_to_event(system, coefs, span, y0, rtol, atol, event, options, record):
    """``integrate_variants`` of variants each alone with a scipy method (``options``) up to a terminal event:
    ``crossing.to_crossing`` for each (what ``ode.integrate`` with that event gives, bit for bit), a variant
    that fails failing alone, the work budget running out stopping the call."""
    from mech.core.budget import OutOfBudget
    from mech.core.errors import NumericFailure
    from mech.solvers.numerics.crossing import to_crossing

    n, N = y0.shape
    y_end, why, t_stop = np.full((n, N), np.nan), np.full(N, "", dtype=object), np.full(N, np.nan)
    record = record or (lambda result: None)
    for j in range(N):
        c = [float(x[j]) for x in coefs]
        try:
            traj = to_crossing(system(*c), span, y0[:, j], rtol=rtol, atol=np.array(atol[:, j]), g=event[0],
                               direction=event[1], **options(*c))
        except OutOfBudget:
            raise
        except NumericFailure as exc:
            why[j] = str(exc)
            continue
        record(traj)
        y_end[:, j] = traj.y_end
        if len(traj.t_events[0]):
            t_stop[j] = traj.t_events[0][0]
    return y_end, why, t_stop
