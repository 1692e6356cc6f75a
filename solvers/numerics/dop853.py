"""mech's own DOP853: the explicit Runge-Kutta 8(5,3) pair of Dormand and Prince, on numpy alone.

Why it exists: importing ``scipy.integrate`` takes 0.6-0.9 s (it drags in
scipy.optimize, linalg, sparse and special), which is most of the 1 s budget
of a ``mech solve``; and for the 2-12 equations of these exercises
``solve_ivp``'s per-step machinery costs more than the arithmetic
(scipy#8257).  This module integrates with the same method (Hairer, Norsett
and Wanner, *Solving ODEs I*, sec. II.10) in one tight loop:

* 12 stages per step plus the first-same-as-last evaluation; the error is the
  method's blend of its 5th- and 3rd-order estimates,
  ``|h| e5^2 / sqrt(n (e5^2 + 0.01 e3^2))`` in the weighted RMS norm with
  weights ``atol + rtol max(|y_old|, |y_new|)``;
* step control ``h *= clip(0.9 err^(-1/8), 0.2, 10)``, no growth right after
  a rejected step, a non-finite stage counted as a rejection;
* the 7th-order continuous extension (three more stages, computed only for
  the steps that need it: dense output, output times, a sign change of an
  event function);
* events found as in ``solve_ivp``: a sign change between the ends of a step
  in the event's direction, the root located on the continuous extension
  by Brent's method to 4 ulp; a terminal event ends the run there.

The tableau (the method's published coefficients) is data in this package,
``mech.solvers.numerics.dop853_tableau``; it is checked on loading (row sums, the
quadrature order conditions up to 8, error weights summing to zero), and
tests/test_dop853.py compares it entry by entry with scipy's copy.
"""

from __future__ import annotations

import math
import time
from typing import Callable, Sequence

import numpy as np

from mech.core import budget
from mech.core.errors import NumericFailure

__all__ = ["available", "tableau_load_seconds", "solve", "stepper", "DenseSolution", "Result"]

_TABLEAU = None
_TABLEAU_TRIED = False
LOAD_S = 0.0  # the one-time cost of loading the tableau (start-up, kept out of a solve's time)
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
ERR_EXP = -1.0 / 8.0
_EPS = np.finfo(float).eps


def _load_tableau():
    from mech.solvers.numerics import dop853_tableau as data

    tab = {}
    for name, shape in data.SHAPES.items():
        arr = np.zeros(shape)
        for index, value in getattr(data, name).items():
            arr[index] = value
        tab[name] = arr
    if not _tableau_ok(tab):
        raise RuntimeError("mech.solvers.numerics.dop853_tableau fails its order conditions: the data file is damaged")
    return tab


def _tableau_ok(tab) -> bool:
    C, A, B, E3, E5, D = (tab[k] for k in ("C", "A", "B", "E3", "E5", "D"))
    if A.shape != (16, 16) or C.shape != (16,) or B.shape != (12,) or E3.shape != (13,) or E5.shape != (13,):
        return False
    if D.shape != (4, 16):
        return False
    if not np.allclose(A.sum(axis=1), C, atol=1e-13, rtol=0):
        return False
    # quadrature conditions sum b_i c_i^(k-1) = 1/k for k = 1..8 (an 8th-order method)
    for k in range(1, 9):
        if abs(float(B @ C[:12] ** (k - 1)) - 1.0 / k) > 1e-13:
            return False
    # the error estimates must vanish for a constant derivative (they are differences of weights)
    return abs(float(E3.sum())) < 1e-13 and abs(float(E5.sum())) < 1e-13


def available() -> bool:
    """Whether the tableau is loaded (it always is: it is data in this package, checked on loading)."""
    global _TABLEAU, _TABLEAU_TRIED, LOAD_S
    if not _TABLEAU_TRIED:
        _TABLEAU_TRIED = True
        t0 = time.perf_counter()
        _TABLEAU = _load_tableau()
        LOAD_S = time.perf_counter() - t0
    return _TABLEAU is not None


def tableau_load_seconds() -> float | None:
    """What loading the tableau cost, once per process (start-up, kept out of a solve's time); None until
    it has been loaded."""
    return LOAD_S if _TABLEAU_TRIED else None


class _Segment:
    """The continuous extension over one step: ``y(t_old + x h)`` for x in [0, 1]."""

    __slots__ = ("t_old", "h", "y_old", "F")

    def __init__(self, t_old, h, y_old, F):
        self.t_old, self.h, self.y_old, self.F = t_old, h, y_old, F

    def __call__(self, t):
        x = (np.asarray(t, float) - self.t_old) / self.h
        F = self.F
        if x.ndim == 0:
            x1 = 1.0 - x
            acc = F[6] * x
            for k in (5, 4, 3, 2, 1, 0):
                acc = (acc + F[k]) * (x1 if k % 2 else x)
            return self.y_old + acc
        xs = x[None, :]
        x1 = 1.0 - xs
        acc = F[6][:, None] * xs
        for k in (5, 4, 3, 2, 1, 0):
            acc = (acc + F[k][:, None]) * (x1 if k % 2 else xs)
        return self.y_old[:, None] + acc

    def component(self, i: int) -> Callable[[float], float]:
        """``t -> y_i(t)`` on Python floats: the operations of ``__call__`` for one component, in its order
        (so the same values to the bit), at a fraction of the cost of a numpy call per trial time."""
        t_old, h, y0 = self.t_old, self.h, float(self.y_old[i])
        c0, c1, c2, c3, c4, c5, c6 = (float(v) for v in self.F[:, i])

        def y_i(t):
            x = (t - t_old) / h
            x1 = 1.0 - x
            return y0 + (((((((c6 * x + c5) * x1 + c4) * x + c3) * x1 + c2) * x + c1) * x1 + c0) * x)

        return y_i


class DenseSolution:
    """The piecewise continuous extension over the whole run; ``sol(t)`` as scipy's OdeSolution."""

    def __init__(self, segments: list[_Segment], t_ends: Sequence[float], direction: float):
        self.segments = segments
        self.ts = np.asarray(t_ends, float)  # step boundaries, in the run's order
        self.direction = direction
        self.t_min, self.t_max = (self.ts[0], self.ts[-1]) if direction > 0 else (self.ts[-1], self.ts[0])

    def _index(self, t):
        key = self.ts if self.direction > 0 else -self.ts
        tt = t if self.direction > 0 else -t
        idx = np.searchsorted(key, tt, side="right") - 1
        return np.clip(idx, 0, len(self.segments) - 1)

    def __call__(self, t):
        t = np.asarray(t, float)
        if t.ndim == 0:
            return self.segments[int(self._index(t))](t)
        out = np.empty((self.segments[0].y_old.size, t.size))
        idx = self._index(t)
        for k in np.flatnonzero(np.bincount(idx)):  # the segments hit (np.unique would load numpy.ma)
            sel = idx == k
            out[:, sel] = self.segments[int(k)](t[sel])
        return out


class Result:
    __slots__ = ("t", "y", "t_events", "y_events", "nfev", "status", "message", "sol", "njev", "nlu")


def step_to(t: float, h_abs: float, direction: float, t_end: float) -> tuple[float, float, float]:
    """The next step from ``t``: (t_new, h, |h|), cut so as not to pass ``t_end``."""
    t_new = t + h_abs * direction
    if (t_new - t_end) * direction > 0:
        t_new = t_end
    h = t_new - t
    return t_new, h, abs(h)


def _rms(v):
    return math.sqrt(float(v @ v) / v.size)


def _starting_step(f, t0: float, t_end: float, y, fy, direction: float, rtol: float, atol, max_step: float,
                   first_step) -> float:
    """The first step's size: ``first_step`` or Hairer's heuristic (a step on which the solution changes by
    about 1% of its scale).  A ``NumericFailure`` where the error scale atol + rtol |y| is so small against
    the derivative that their ratio leaves the floating-point range (no step could be measured)."""
    if first_step is not None:
        h_abs = min(abs(float(first_step)), abs(t_end - t0))
    else:
        scale = atol + np.abs(y) * rtol
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            d0, d1 = _rms(y / scale), _rms(fy / scale)
        h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
        h0 = min(h0, abs(t_end - t0))
        if not (h0 > 0.0 and math.isfinite(d0) and math.isfinite(d1)):
            raise NumericFailure(
                f"DOP853 cannot start: the error scale atol + rtol |y| (down to {float(np.min(scale)):.3g}) is too "
                f"small for the derivative (up to {float(np.max(np.abs(fy))):.3g}): their ratio leaves the "
                "floating-point range")
        y1 = y + direction * h0 * fy
        f1 = f(t0 + direction * h0, y1)
        with np.errstate(over="ignore", invalid="ignore"):
            d2 = _rms((f1 - fy) / scale) / h0
        if d1 <= 1e-15 and d2 <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
        h_abs = min(100.0 * h0, h1, abs(t_end - t0))
    return min(h_abs, max_step)


class _Stepper:
    """The stages of one step of the pair and their step control (``attempt``), with the evaluations
    counted in ``nfev``; ``segment`` gives the step's continuous extension (three more stages)."""

    __slots__ = ("call", "fun", "n", "K", "A", "Cl", "B", "EE", "D", "rtol", "atol", "max_step", "nfev")

    def __init__(self, fun, call, n, tab, rtol, atol, max_step):
        self.fun, self.call, self.n = fun, call, n
        self.K = np.empty((16, n))
        self.A, self.Cl, self.B, self.D = tab["A"], tab["C"].tolist(), tab["B"], tab["D"]
        self.EE = np.vstack([tab["E5"], tab["E3"]])
        self.rtol, self.atol, self.max_step = rtol, atol, max_step
        self.nfev = 0

    def f(self, t, yy):
        self.nfev += 1
        out = np.asarray(self.fun(t, yy), dtype=float)
        return out if out.ndim == 1 else out.ravel()

    def attempt(self, t, y, fy, h_abs, direction, t_end, quantum=None):
        """Steps from (t, y) until one is accepted: (t_new, h, y_new, f_new, h_next), or None where the
        step would fall below the spacing of the numbers near t (status -1).  ``quantum``: every try spans
        a whole number (at least 1) of it, and None comes back where one quantum is rejected."""
        K, call, A, Cl, B, n = self.K, self.call, self.A, self.Cl, self.B, self.n
        min_step = 10.0 * abs(math.nextafter(t, direction * math.inf) - t)
        step_rejected = one_tried = False
        while True:
            budget.check("DOP853 step", 12)  # 12 evaluations a try, rejected ones too (4.9 far out)
            if quantum is not None:
                j = max(1, math.floor(h_abs / quantum))
                if j == 1:
                    if one_tried:
                        return None
                    one_tried = True
                h_abs = j * quantum
            if h_abs < min_step:
                return None
            t_new, h, h_abs = step_to(t, h_abs, direction, t_end)
            K[0] = fy
            hA = h * A  # the step's tableau: one product instead of one per stage
            for s in range(1, 12):
                # fun's value goes straight into K (numpy converts a list); the count is kept below
                K[s] = call(t + Cl[s] * h, y + hA[s, :s] @ K[:s])
            self.nfev += 11
            y_new = y + h * (B @ K[:12])
            f_new = self.f(t_new, y_new)
            K[12] = f_new
            scale = self.atol + np.maximum(np.abs(y), np.abs(y_new)) * self.rtol
            ee = self.EE @ K[:13]  # the 5th- and 3rd-order error estimates, in one product
            ee /= scale
            n5, n3 = (ee * ee).sum(axis=1).tolist()
            if n5 == 0.0:
                err = 0.0  # err is proportional to n5 (and 0.01 n3 can underflow to 0: a division by zero)
            else:
                err = abs(h) * n5 / math.sqrt(n * (n5 + 0.01 * n3))
            if not math.isfinite(err) or not math.isfinite(float(np.add.reduce(y_new))):
                h_abs *= MIN_FACTOR
                step_rejected = True
                continue
            if err < 1.0:
                factor = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err ** ERR_EXP)
                if step_rejected:
                    factor = min(1.0, factor)
                return t_new, h, y_new, f_new, min(h_abs * factor, self.max_step)
            h_abs *= max(MIN_FACTOR, SAFETY * err ** ERR_EXP)
            step_rejected = True

    def segment(self, t, h, y, fy, y_new, f_new):
        """The continuous extension of the step just accepted (its stages are still in K)."""
        K, call, Cl = self.K, self.call, self.Cl
        hA = h * self.A
        for s in range(13, 16):
            K[s] = call(t + Cl[s] * h, y + hA[s, :s] @ K[:s])
        self.nfev += 3
        dy = y_new - y
        F = np.empty((7, self.n))
        F[0] = dy
        F[1] = h * fy - dy
        F[2] = 2.0 * dy - h * (fy + f_new)
        F[3:] = h * (self.D @ K)
        return _Segment(t, h, y.copy(), F)


def stepper(fun: Callable, n: int, *, rtol: float, atol: float, max_step: float = math.inf) -> _Stepper:
    """The pair one step at a time, for a caller that runs its own loop (``attempt`` and its ``quantum``:
    4.24's stroboscopic averaging, whose steps span whole periods); ``fun(t, y)`` gives n numbers."""
    if not available():
        raise RuntimeError("DOP853 tableau unavailable")
    return _Stepper(fun, fun, n, _TABLEAU, rtol, np.asarray(atol, float), abs(max_step))


def _events_in_step(events, g_old, t, t_new, y_new, segment, res):
    """The events whose functions change sign in their direction over the step, located on its continuous
    extension and recorded in ``res``, in the order of time: (their values at t_new, the terminal event's
    (time, state) or None)."""
    g_new = [float(ev(t_new, y_new)) for ev in events]
    found = []
    for k, ev in enumerate(events):
        a, b = g_old[k], g_new[k]
        up, down = a <= 0.0 <= b, a >= 0.0 >= b
        dirn = getattr(ev, "direction", 0.0)
        if (up and dirn > 0) or (down and dirn < 0) or ((up or down) and dirn == 0):
            sg = segment()
            comp = getattr(ev, "component", None)
            if comp is not None:
                if b != y_new[comp]:
                    raise ValueError(f"an event declared as component {comp} of the state is not it")
                root = _event_root(sg.component(comp), t, t_new)
            else:
                root = _event_root(lambda tt: float(ev(tt, sg(tt))), t, t_new)
            found.append((root, k))
    direction = 1.0 if t_new >= t else -1.0
    found.sort(key=lambda rk: rk[0] * direction)
    for root, k in found:
        y_root = segment()(root)
        res.t_events[k] = np.append(res.t_events[k], root)
        res.y_events[k] = np.vstack([res.y_events[k], y_root])
        if getattr(events[k], "terminal", False):
            return g_new, (root, y_root)
    return g_new, None


def _new_result(n_events: int, n: int) -> Result:
    res = Result()
    res.t_events = [np.empty(0) for _ in range(n_events)]
    res.y_events = [np.empty((0, n)) for _ in range(n_events)]
    res.sol = None
    return res


def _passed(t_eval, i: int, t_stop: float, direction: float) -> int:
    """The index of the first output time beyond ``t_stop``, from ``i`` on."""
    while i < t_eval.size and (t_eval[i] - t_stop) * direction <= 0:
        i += 1
    return i


def solve(
    fun: Callable,
    t_span: tuple[float, float],
    y0,
    *,
    rtol: float,
    atol,
    max_step: float = math.inf,
    first_step: float | None = None,
    events: Sequence[Callable] = (),
    t_eval=None,
    dense_output: bool = False,
) -> Result:
    """Integrate ``y' = fun(t, y)`` over ``t_span``; the arguments mean what they mean for ``solve_ivp``.

    ``events`` are callables ``g(t, y)`` with the attributes ``terminal`` and
    ``direction``.  Returns a ``Result`` with ``t, y, t_events, y_events, nfev,
    status`` (0 reached the end, 1 a terminal event, -1 step size underflow),
    ``message`` and ``sol`` (a ``DenseSolution`` when ``dense_output``).
    """
    if not available():
        raise RuntimeError("DOP853 tableau unavailable")
    t0, t_end = float(t_span[0]), float(t_span[1])
    y = np.array(y0, dtype=float).ravel()
    n = y.size
    direction = 1.0 if t_end >= t0 else -1.0
    atol = np.asarray(atol, float)

    res = _new_result(len(events), n)
    ts, ys = [t0], [y.copy()]
    t_eval_arr = None
    if t_eval is not None:
        t_eval_arr = np.asarray(t_eval, float)
        ts, ys = [], []
        t_eval_arr = t_eval_arr[(t_eval_arr - t0) * direction >= 0]
        i_eval = 0
    segments, seg_ends = ([], [t0]) if dense_output else (None, None)

    raw = np.asarray(fun(t0, y), dtype=float)
    fy = raw.ravel()
    # the stages write fun's value straight into K when it comes as n numbers in a row; anything else
    # (a column, say) is flattened on the way
    call = fun if raw.ndim <= 1 else (lambda tt, yy: np.asarray(fun(tt, yy), dtype=float).ravel())
    st = _Stepper(fun, call, n, _TABLEAU, rtol, atol, abs(max_step))
    st.nfev = 1
    if t_end == t0:
        res.t, res.y, res.nfev, res.status = np.array([t0]), y[:, None], st.nfev, 0
        res.message = "The solver successfully reached the end of the integration interval."
        return res
    h_abs = _starting_step(st.f, t0, t_end, y, fy, direction, rtol, atol, abs(max_step), first_step)

    g_old = [float(ev(t0, y)) for ev in events]
    t = t0
    status, message = 0, "The solver successfully reached the end of the integration interval."
    while (t_end - t) * direction > 0:
        step = st.attempt(t, y, fy, h_abs, direction, t_end)
        if step is None:
            status, message = -1, "Required step size is less than spacing between numbers."
            break
        t_new, h, y_new, f_new, h_next = step
        seg = None

        def segment():
            nonlocal seg
            if seg is None:
                seg = st.segment(t, h, y, fy, y_new, f_new)
            return seg

        stop_at = None
        if events:
            g_old, stop_at = _events_in_step(events, g_old, t, t_new, y_new, segment, res)
        t_stop, y_stop = (stop_at if stop_at is not None else (t_new, y_new))

        if t_eval_arr is not None:
            lo, i_eval = i_eval, _passed(t_eval_arr, i_eval, t_stop, direction)
            if i_eval > lo:
                pts = t_eval_arr[lo:i_eval]
                ts.extend(pts.tolist())
                ys.extend(segment()(pts).T)
        else:
            ts.append(t_stop)
            ys.append(y_stop)  # a fresh array every step (never written to afterwards)
        if dense_output:
            segments.append(segment())
            seg_ends.append(t_stop)
        if stop_at is not None:
            status, message = 1, "A termination event occurred."
            break
        t, y, fy, h_abs = t_new, y_new, f_new, h_next

    res.t = np.asarray(ts, float)
    res.y = np.asarray(ys, float).T if ys else np.empty((n, 0))
    res.nfev = st.nfev
    res.status, res.message = status, message
    if dense_output and segments:
        res.sol = DenseSolution(segments, seg_ends, direction)
    return res


def _event_root(g: Callable[[float], float], a: float, b: float) -> float:
    from mech.solvers.numerics.roots import brentq

    ga, gb = g(a), g(b)
    if ga == 0.0:
        return a
    if gb == 0.0:
        return b
    if (ga > 0) == (gb > 0):  # the interpolant disagrees with the step ends in the last bits
        return b if abs(gb) < abs(ga) else a
    return brentq(g, a, b, xtol=4 * _EPS, rtol=4 * _EPS)
