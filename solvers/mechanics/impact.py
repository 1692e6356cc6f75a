"""Impacts as short finite force pulses: a stiff, critically damped contact integrated through.

An impulsive collision is modelled as a contact spring-damper between the two
bodies' contact points, with the force F = -K d - C d' on one body (and -F on the
other) for the relative displacement d.  Near the contact the relative
acceleration is d'' = W F, where W = G Minv G^T (plus 1/m for a point mass) is the
contact's inverse effective mass matrix (the Delassus operator) built from the
bodies' mass matrices and the contact Jacobian G.  Choosing
    K = W^-1 / tp^2,   C = 2 W^-1 / tp
makes the linearized relative motion critically damped with the single time
tp in every direction: d = d'(0) t exp(-t/tp) for a contact that starts closed.
After ``decay`` pulse times (45 by default: exp(-45) ~ 3e-20) the relative motion
is gone to round-off and the bodies move as one (a perfectly inelastic, sticking
impact).  For a bouncing impact, use a spring alone and stop when the force
changes sign instead.

A finite pulse lets the bodies move during the impact; the result differs from
the impulsive limit by a power of tp (tp^2 when the leading effect is the
turning of the bodies during an impact symmetric in time).  ``richardson``
evaluates a pulse-dependent result at two pulse lengths, extrapolates to tp -> 0,
and returns the size of the correction as the estimate of what is left.

No physics of one exercise here.
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

__all__ = ["delassus", "critical_contact", "pulse_end", "richardson"]

DECAY = 45.0


def delassus(Minv: np.ndarray, G: np.ndarray, point_mass: float | None = None) -> np.ndarray:
    """The contact's inverse effective mass W = G Minv G^T (+ 1/m I for a point mass on the other side)."""
    G = np.atleast_2d(np.asarray(G, dtype=float))
    W = G @ np.asarray(Minv, dtype=float) @ G.T
    if point_mass is not None:
        W = W + np.eye(W.shape[0]) / point_mass
    return 0.5 * (W + W.T)


def critical_contact(W: np.ndarray, tp: float) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and damping matrices (K, C) that make the contact critically damped with time tp."""
    Winv = np.linalg.inv(np.atleast_2d(W))
    Winv = 0.5 * (Winv + Winv.T)
    return Winv / tp**2, 2.0 * Winv / tp


def pulse_end(tp: float, decay: float = DECAY) -> float:
    """The time by which a critically damped contact pulse of time tp has died out to round-off."""
    return decay * tp


def richardson(
    fn: Callable[[float], Mapping[str, float]],
    tp: float,
    *,
    ratio: float = 2.0,
    order: float = 2.0,
) -> tuple[dict, dict, dict]:
    """Evaluate ``fn`` at tp and tp/ratio; extrapolate each value to tp -> 0 assuming an error ~ tp^order.

    Returns ``(extrapolated, correction, fine)``: the extrapolated values, the absolute size of the
    correction made (an estimate of the finite-pulse error of the fine value and an upper estimate
    of what remains in the extrapolated one) and the values at the shorter pulse.
    """
    coarse = dict(fn(tp))
    fine = dict(fn(tp / ratio))
    factor = ratio**order - 1.0
    extrapolated, correction = {}, {}
    for key, f in fine.items():
        delta = (f - coarse[key]) / factor
        extrapolated[key] = f + delta
        correction[key] = abs(delta)
    return extrapolated, correction, fine
