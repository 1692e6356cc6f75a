"""Bracketed scalar root finding and bounded minimization on numpy alone.

scipy.optimize costs 0.4-0.6 s to import (it pulls in scipy.linalg, sparse
and special), which is more than most exercises need for the whole solve.
These two routines are what the exercises and the ODE front end used from
it, written for mech:

* ``brentq(f, a, b)``: Brent's method (inverse quadratic interpolation,
  secant, bisection as the safe fallback), for a bracket with a sign change.
* ``bracketed_root(f, lo, hi)``: bisection on the floats' bit patterns, to the
  last bit whatever the root's magnitude; ``walk_to_sign_change`` finds its bracket.
* ``minimize_bounded(f, a, b)``: Brent's minimizer (golden section with
  parabolic steps) on a closed interval.

Both raise ``NumericFailure`` rather than return a guess: a bracket without
a sign change or an iteration budget spent is a failed solve.
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Callable

from mech.core import budget
from mech.core.errors import NumericFailure

__all__ = ["brentq", "bracketed_root", "walk_to_sign_change", "minimize_bounded", "minimize_scalar", "RootResult"]

_EPS = 2.220446049250313e-16


@dataclass
class RootResult:
    root: float
    iterations: int
    function_calls: int
    converged: bool = True


def _tick(where: str) -> None:
    """A unit of work, counted at every pass of a search (each pass may call an integration, or a whole
    nested search: 4.21's root of a maximum ran until the backup timer)."""
    budget.check(where)


def brentq(
    f: Callable[[float], float],
    a: float,
    b: float,
    *,
    xtol: float = 2e-12,
    rtol: float = 4 * _EPS,
    maxiter: int = 200,
    full_output: bool = False,
    fa: float | None = None,
    fb: float | None = None,
):
    """A root of ``f`` in ``[a, b]``, where ``f(a)`` and ``f(b)`` differ in sign.

    ``fa``, ``fb``: the values at the ends when the caller has them already (each
    call of ``f`` may be an integration).

    Converged when the bracket is narrower than ``xtol + rtol |x|``
    (scipy's convention for the same arguments, so callers keep their
    tolerances).  An exact zero ends the search at once.
    """
    a, b = float(a), float(b)
    calls = (fa is None) + (fb is None)
    fa = float(f(a)) if fa is None else float(fa)
    fb = float(f(b)) if fb is None else float(fb)
    if not (math.isfinite(fa) and math.isfinite(fb)):
        raise NumericFailure(f"root search: f is not finite at the bracket ends ({fa:.3g}, {fb:.3g})")
    if fa == 0.0:
        return (a, RootResult(a, 0, calls)) if full_output else a
    if fb == 0.0:
        return (b, RootResult(b, 0, calls)) if full_output else b
    if (fa > 0) == (fb > 0):
        raise NumericFailure(f"root search: no sign change on [{a:.6g}, {b:.6g}] (f = {fa:.3g}, {fb:.3g})")
    # b: best estimate; a: previous b; c: the end that keeps the sign change with b
    c, fc = a, fa
    d = e = b - a
    for it in range(1, maxiter + 1):
        _tick("root search")
        if (fb > 0) == (fc > 0):
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, fa = b, fb
            b, fb = c, fc
            c, fc = a, fa
        tol = 0.5 * (xtol + rtol * abs(b))
        half = 0.5 * (c - b)
        if abs(half) <= tol or fb == 0.0:
            return (b, RootResult(b, it, calls)) if full_output else b
        if abs(e) >= tol and abs(fa) > abs(fb):
            # interpolate: secant when only two distinct points, else inverse quadratic
            s = fb / fa
            if a == c:
                p, q = 2.0 * half * s, 1.0 - s
            else:
                qa, r = fa / fc, fb / fc
                p = s * (2.0 * half * qa * (qa - r) - (b - a) * (r - 1.0))
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0:
                q = -q
            else:
                p = -p
            # accept the interpolation only when it stays well inside and shrinks fast enough
            if 2.0 * p < min(3.0 * half * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = half
        else:
            d = e = half
        a, fa = b, fb
        b += d if abs(d) > tol else math.copysign(tol, half)
        fb = float(f(b))
        calls += 1
        if not math.isfinite(fb):
            raise NumericFailure(f"root search: f is not finite at x = {b:.17g}")
    raise NumericFailure(f"root search: no convergence in {maxiter} iterations on [{min(b, c):.17g}, {max(b, c):.17g}]")


def walk_to_sign_change(
    f: Callable[[float], float], start: float, step: Callable[[float], float], sign: float, max_steps: int = 4000
) -> float:
    """From ``start``, apply ``step`` until ``f`` has the given sign; the walk is the caller's geometry
    (halving toward a body, doubling toward infinity).  Failing to get there is a failure, not a guess."""
    x = start
    for _ in range(max_steps):
        _tick("walk to a sign change")
        v = f(x)
        if v != 0.0 and math.copysign(1.0, v) == sign:
            return x
        nxt = step(x)
        if nxt == x:
            break
        x = nxt
    raise NumericFailure(f"no sign change found walking from {start:g} (stopped at {x:.17g})")


def _float_key(x: float) -> int:
    """An integer that orders like the float (for x >= 0: its bit pattern)."""
    return struct.unpack("<q", struct.pack("<d", x))[0]


def _key_float(k: int) -> float:
    return struct.unpack("<d", struct.pack("<q", k))[0]


def bracketed_root(f: Callable[[float], float], lo: float, hi: float) -> float:
    """The root of ``f`` in [lo, hi] (opposite signs required), to the last bit.

    Bisection on the floats' bit patterns: at most ~64 halvings whatever the
    magnitude of the root (1e-30 or 1e3), and no scipy import."""
    flo, fhi = f(lo), f(hi)
    if flo == 0.0:
        return lo
    if fhi == 0.0:
        return hi
    if (flo > 0) == (fhi > 0):
        raise NumericFailure(f"root not bracketed in [{lo:.17g}, {hi:.17g}]: f = {flo:.3g}, {fhi:.3g}")
    if lo < 0.0 < hi:  # split at zero so that both ends share a sign
        f0 = f(0.0)
        if f0 == 0.0:
            return 0.0
        if (f0 > 0) == (flo > 0):
            lo, flo = 0.0, f0
        else:
            hi = 0.0
    neg = hi <= 0.0
    a, b = (0.0 - hi, 0.0 - lo) if neg else (lo + 0.0, hi + 0.0)  # 0 <= a < b (no -0.0); g(t) = f(+-t)
    fa_pos = (flo > 0) if not neg else (fhi > 0)
    ka, kb = _float_key(a), _float_key(b)
    while kb - ka > 1:
        _tick("bisection")
        km = (ka + kb) // 2
        m = _key_float(km)
        fm = f(-m if neg else m)
        if fm == 0.0:
            return -m if neg else m
        if (fm > 0) == fa_pos:
            ka = km
        else:
            kb = km
    a, b = _key_float(ka), _key_float(kb)
    fa, fb = f(-a if neg else a), f(-b if neg else b)
    best = a if abs(fa) <= abs(fb) else b
    return -best if neg else best


_GOLD = 0.5 * (3.0 - math.sqrt(5.0))  # 0.381966..., the golden section's smaller part


def minimize_bounded(
    f: Callable[[float], float], a: float, b: float, *, xatol: float = 1e-5, maxiter: int = 500
) -> tuple[float, float, int]:
    """Brent's minimizer on ``[a, b]``: returns ``(x, f(x), calls)``.

    Golden-section steps guarantee progress; a parabola through the three best
    points is used when it falls inside and shrinks the step.  Stops when the
    point is known to within ``xatol`` (plus a relative round-off floor).
    """
    a, b = float(min(a, b)), float(max(a, b))
    x = w = v = a + _GOLD * (b - a)
    fx = fw = fv = float(f(x))
    calls = 1
    d = e = 0.0
    for _ in range(maxiter):
        _tick("minimum search")
        mid = 0.5 * (a + b)
        tol1 = math.sqrt(_EPS) * abs(x) + xatol / 3.0
        tol2 = 2.0 * tol1
        if abs(x - mid) <= tol2 - 0.5 * (b - a):
            return x, fx, calls
        parabolic = False
        if abs(e) > tol1:
            r = (x - w) * (fx - fv)
            q = (x - v) * (fx - fw)
            p = (x - v) * q - (x - w) * r
            q = 2.0 * (q - r)
            if q > 0:
                p = -p
            q = abs(q)
            if abs(p) < abs(0.5 * q * e) and q * (a - x) < p < q * (b - x):
                e, d = d, p / q
                u = x + d
                if u - a < tol2 or b - u < tol2:
                    d = math.copysign(tol1, mid - x)
                parabolic = True
        if not parabolic:
            e = (b - x) if x < mid else (a - x)
            d = _GOLD * e
        u = x + (d if abs(d) >= tol1 else math.copysign(tol1, d))
        fu = float(f(u))
        calls += 1
        if fu <= fx:
            if u < x:
                b = x
            else:
                a = x
            v, fv, w, fw, x, fx = w, fw, x, fx, u, fu
        else:
            if u < x:
                a = u
            else:
                b = u
            if fu <= fw or w == x:
                v, fv, w, fw = w, fw, u, fu
            elif fu <= fv or v == x or v == w:
                v, fv = u, fu
    raise NumericFailure(f"bounded minimization: no convergence in {maxiter} iterations")


def golden_min(f: Callable[[float], float], a: float, b: float, *, xtol: float,
               stop: Callable[[float], bool] | None = None) -> tuple[float, float, bool]:
    """Golden-section search for a minimum of ``f`` on [a, b], to a bracket of width ``xtol``.

    ``stop(fx)``, when given, ends the search at the first value it accepts (a search for where ``f``
    goes negative need not find the minimum itself).  Returns ``(x, f(x), stopped)`` with the best point
    seen."""
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    best = (c, fc) if fc < fd else (d, fd)
    if stop is not None and stop(best[1]):
        return best[0], best[1], True
    while b - a > xtol:
        _tick("golden-section search")
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = f(c)
            if stop is not None and stop(fc):
                return c, fc, True
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = f(d)
            if stop is not None and stop(fd):
                return d, fd, True
    return (c, fc, False) if fc < fd else (d, fd, False)


def minimize_scalar(fun: Callable[[float], float], bounds: tuple[float, float], method: str = "bounded",
                    options: dict | None = None):
    """The call shape of ``scipy.optimize.minimize_scalar(..., method="bounded")``, on ``minimize_bounded``.

    Returns an object with ``x``, ``fun`` and ``nfev``; only the bounded method exists.
    """
    if method != "bounded":
        raise ValueError("only the bounded method is provided")
    opts = {"xatol": 1e-5, "maxiter": 500, **(options or {})}
    x, fx, calls = minimize_bounded(fun, bounds[0], bounds[1], xatol=opts["xatol"], maxiter=opts["maxiter"])
    return SimpleNamespace(x=x, fun=fx, nfev=calls, success=True)
