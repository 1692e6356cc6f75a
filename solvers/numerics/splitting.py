"""Fixed-step splitting: symmetric compositions of kick-drift-kick (Strang) steps, and events inside a step.

A flow dy/dt = A(y, t) + B(y) whose two parts can each be followed exactly (a "kick" by A over a time c,
a "drift" by B) is advanced by the Strang step: half a kick, a drift, half a kick, second order and
symmetric.  A symmetric composition of s Strang steps of sizes w_1 h, ..., w_s h (sum w_i = 1, w
palindromic) cancels the odd error terms up to a higher order: Yoshida's 7-step solution A (order 6;
``symplectic.YOSHIDA6``, the same weights) and Kahan and Li's 17-step s17odr8b (order 8).  Adjacent half
kicks merge, so a composed step is s + 1 kicks and s drifts (``stages``).

Why a splitting rather than an adaptive Runge-Kutta: where the drift is a fast rotation done exactly
(thousands of its periods per run), each part is solved in closed form and the step only resolves the
coupling, and whatever the parts conserve (a length, a projection) is kept to round-off at every step.

Events of a fixed-step run: the step in which a function changes sign is found by the caller; the event
itself is located on a partial step from the step's start (``crossing``), so it carries the method's
full order, and a minimum inside two steps by partial steps too (``lowest``).

Tested against closed forms (tests/test_splitting.py): the harmonic oscillator's exact flow, the order
of each composition from its error at halved steps, the weights' own conditions.
"""

from __future__ import annotations

from typing import Callable, Sequence

from mech.solvers.numerics.symplectic import YOSHIDA6

__all__ = ["YOSHIDA6", "KAHAN_LI8", "STRANG", "stages", "composed", "crossing", "lowest"]

STRANG = (1.0,)
# Kahan and Li, Math. Comp. 66 (1997) 1089, s17odr8b: the first nine weights, the other eight mirror them
_K = (0.12713692773487857916, 0.56170253798880269972, -0.38253471994883018888, 0.16007605629464743119,
      -0.40181637432680696673, 0.18736671654227849724, 0.26070870920779240570, 0.29039738812516162389,
      -0.60607448323584816258)
KAHAN_LI8 = _K + _K[-2::-1]


def stages(weights: Sequence[float]) -> tuple[list[float], list[float], list[float]]:
    """The composed step of ``weights`` as merged stages, per unit step: (kick lengths, their times after
    the step's start, drift lengths).  There is one kick more than drifts: kick 0, drift 0, kick 1, ...,
    drift s-1, kick s; the kicks sum to 1, as do the drifts."""
    cs = list(weights)
    kicks = [0.5 * cs[0]] + [0.5 * (cs[i] + cs[i + 1]) for i in range(len(cs) - 1)] + [0.5 * cs[-1]]
    offsets = [sum(cs[:i]) for i in range(len(cs) + 1)]
    return kicks, offsets, cs


def composed(kick: Callable, drift: Callable, weights: Sequence[float] = YOSHIDA6) -> Callable:
    """step(y, t, h) -> (y, t + h): the composition of ``weights`` of Strang steps.  ``kick(y, t, c)``
    follows the kicking part over a time c from time t; ``drift(y, c)`` the drifting part (autonomous)."""
    kw, offsets, dw = stages(weights)

    def step(y, t, h):
        for c, o, d in zip(kw, offsets, dw):
            y = drift(kick(y, t + o * h, c * h), d * h)
        return kick(y, t + offsets[-1] * h, kw[-1] * h), t + h

    return step


def crossing(value_after: Callable[[float], float], h: float, v0: float | None = None,
             vh: float | None = None) -> float:
    """The partial step tau in (0, h] at which ``value_after(tau)`` (the quantity after a step of tau from
    the step's start, positive at 0 and not above 0 at h) reaches zero: Brent's method (``roots.brentq``) to
    a few ulps of h, about ten partial steps (bisection to the last bit took some 66).  ``v0``, ``vh``: the
    values at 0 and h where the caller has them (the step's ends)."""
    from mech.solvers.numerics.roots import brentq

    v0 = value_after(0.0) if v0 is None else v0
    vh = value_after(h) if vh is None else vh
    if vh == 0.0:
        return h
    return brentq(value_after, 0.0, h, xtol=4.0 * 2.220446049250313e-16 * h, fa=v0, fb=vh)


def lowest(value_after: Callable, starts: Sequence, h: float, scan: int = 16) -> tuple[float, object, float]:
    """The least value over partial steps from each of ``starts`` (the states at the start of consecutive
    steps of h): scanned at h/scan, then refined by a bounded minimization around the best point.
    ``value_after(state, tau)``.  Returns (value, the start it was reached from, tau)."""
    from mech.solvers.numerics.roots import minimize_scalar

    best = (float("inf"), None, 0.0)
    for s0 in starts:
        for j in range(1, scan + 1):
            v = value_after(s0, h * j / scan)
            if v < best[0]:
                best = (v, s0, h * j / scan)
    v0, s0, tau0 = best
    res = minimize_scalar(lambda x: value_after(s0, x), bounds=(max(0.0, tau0 - h / scan), min(h, tau0 + h / scan)),
                          method="bounded", options={"xatol": 1e-10 * h})
    return (float(res.fun), s0, float(res.x)) if res.fun < v0 else best
