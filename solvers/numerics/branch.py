"""Following a branch of solutions of F(z, a) = 0 (z in R^n, a a parameter) by its amplitude.

A branch that leaves z = 0 at a = a0 along a direction e (a bifurcation), parametrized by the amplitude
s = |z / scale|: each point solves F(z, a) = 0 together with |z / scale|^2 = s^2 by Newton's method on
(z, a) (the bordered system, ``on_branch``), from a secant prediction through the last two points
(``follow``).  Parametrizing by s rather than by a passes folds of the branch in a (a subcritical
bifurcation turns back before it rises through the a asked for); the step in s halves wherever Newton
fails (a secant overshooting a sharp turn) and grows by 1.5 after a success.

Tested against a closed form (tests/test_branch.py): the pitchfork z^2 = a - 1 and a fold.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from mech.core.errors import NumericFailure

__all__ = ["on_branch", "follow", "newton"]


def on_branch(residual: Callable, z, a: float, s: float, scale, tol: float, a_scale: float, a_max: float,
              max_iter: int = 10):
    """(z, a) with residual(z, a) = (F, dF/dz, dF/da) zero and |z / scale| = s, by Newton from (z, a);
    None where Newton leaves the neighbourhood (a outside (0, a_max), |z / scale| beyond 2 s + 0.5) or does
    not converge to ``tol`` (in z / scale, and tol * a_scale in a) within ``max_iter`` steps."""
    scale = np.asarray(scale, dtype=float)
    n = scale.size
    for _ in range(max_iter):
        if not (0.0 < a < a_max) or np.linalg.norm(z / scale) > 2.0 * s + 0.5:
            return None  # heading off (a < 0 past a fold): give up before the integrations get stiff
        r, J, ra = residual(z, a)
        zs = z / scale
        F = np.append(r, 0.5 * (np.dot(zs, zs) - s * s))
        Jf = np.zeros((n + 1, n + 1))
        Jf[:n, :n], Jf[:n, n], Jf[n, :n] = J, ra, zs / scale
        du = np.linalg.solve(Jf, -F)
        z, a = z + du[:n], a + du[n]
        if np.linalg.norm(du[:n] / scale) < 10 * tol and abs(du[n]) < 10 * tol * a_scale:
            return (z, a) if a > 0.0 else None
    return None


def follow(corrector: Callable, e, a0: float, target: float, *, ds: float = 0.02, s_max: float = 3.0,
           max_tries: int = 200, ds_min: float = 1e-6):
    """Follow the branch leaving (0, a0) along e until a crosses ``target``: the two points around the
    crossing ((z, a) before, (z, a) after) and (tries, accepted steps).  ``corrector(z, a, s)`` puts a
    guess on the branch at amplitude s (``on_branch``) or returns None."""
    e = np.asarray(e, dtype=float)
    z_prev, a_prev, s_prev = np.zeros(e.size), a0, 0.0
    z_cur, a_cur, s_cur = np.zeros(e.size), a0, 0.0
    steps = tries = 0
    while True:
        s = s_cur + ds
        if steps == 0:
            z_guess, a_guess = s * e, a0
        else:  # secant predictor along the branch
            t = (s - s_cur) / (s_cur - s_prev)
            z_guess = z_cur + t * (z_cur - z_prev)
            a_guess = max(a_cur + t * (a_cur - a_prev), 0.5 * a_cur)
        tries += 1
        if tries > max_tries or s > s_max:
            raise NumericFailure(f"the branch does not reach a = {target:.6g} within the amplitude {s_max:g}")
        found = corrector(z_guess, a_guess, s)
        if found is None:
            ds *= 0.5
            if ds < ds_min:
                raise NumericFailure(f"the branch could not be followed at the amplitude s = {s:.3g}")
            continue
        z_new, a_new = found
        steps += 1
        if (a_new - target) * (a_cur - target) <= 0.0 and steps > 1 or (steps == 1 and a_new >= target > a0):
            return (z_cur, a_cur), (z_new, a_new), (tries, steps)
        z_prev, a_prev, s_prev = z_cur, a_cur, s_cur
        z_cur, a_cur, s_cur = z_new, a_new, s
        ds = min(1.5 * ds, 0.1)


def newton(residual: Callable, z, scale, crude: float, rtol: float, max_iter: int = 30):
    """A point of the branch at a fixed parameter: Newton on residual(z, tol) = (F, dF/dz), its first steps
    with F evaluated at the loose tolerance ``crude``, the last ones at ``rtol`` (from a step below 1e3
    crude), until a step at rtol is below rtol (in z / scale); None without convergence."""
    scale = np.asarray(scale, dtype=float)
    tol = crude
    for _ in range(max_iter):
        r, J = residual(z, tol)
        dz = np.linalg.solve(J, -r)
        z = z + dz
        step = np.linalg.norm(dz / scale)
        if tol == rtol and step < rtol:
            return z
        if step < 1e3 * crude:
            tol = rtol
    return None

