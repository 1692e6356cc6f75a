"""Frequency sweeps of a driven one-coordinate oscillator: periodic orbits continued in the drive frequency.

The equation is q'' = a(q, q') + f0 cos(omega t).  A periodic response of the
drive's period is a fixed point of the one-period map; it is found by Newton's
method (shooting), with the map's Jacobian from the variational equations
carried along the orbit, and followed in omega step by step: a slow frequency
sweep without waiting for any transient.

Units and unknowns.  Time is the drive phase tau = omega t (the period is 2 pi
for every omega); the state is X = q/Q, Y = q'/(omega_ref Q) for a length unit
Q and a reference frequency omega_ref; the frequency is omega = omega_ref +
W w with a frequency unit W.  The unknowns z = (X0, Y0, w) are all of order
one over the interesting part of a resonance curve.

* ``OrbitMap(...).evaluate(z, rtol)``: the residual phi(X0, Y0) - (X0, Y0), its
  2 x 3 Jacobian (monodromy matrix M minus I, and the derivative in w), the
  half peak-to-peak swing of q (extrema by events on q' = 0) and its gradient
  in z (at an extremum dq/dtau = 0, so only the explicit dependence counts).
* ``solve_on_plane``: Newton on {residual = 0, n . (z - z_base) = sigma}: a
  fixed frequency for n = e_w, a pseudo-arclength corrector otherwise.
* ``sweep``: continuation by pseudo-arclength from a start in one direction of
  w until the first fold (where the tangent's w-component, det(M - I), changes
  sign: the branch turns back and a slow sweep jumps), or until w passes a
  stop.  Steps are controlled by the corrector's size, the turning of the
  tangent and a secant prediction of where det(M - I) vanishes, so that a
  small S-shaped piece of the curve is not stepped over.
* ``refine_root``: a zero of a smooth function along the branch between two
  of its points (Brent's method on the distance along their chord): the fold
  itself (det(M - I) = 0), or where the swing is largest (dA/ds = 0).

No physics of one exercise lives here.  scipy is imported inside functions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from mech.core.errors import NumericFailure
from mech.core import budget
from mech.solvers.numerics.ode import Event, integrate

__all__ = ["OrbitMap", "RotatingOrbitMap", "BranchPoint", "Sweep", "solve_on_plane", "sweep", "refine_root", "shorten_bracket", "bisect_parameter"]


@dataclass
class BranchPoint:
    """A periodic orbit: z = (X0, Y0, w), and what the one-period map tells about it."""

    z: np.ndarray
    J: np.ndarray  # 2 x 3: [M - I | d phi / d w]
    A: float  # half peak-to-peak swing of q, in units of Q
    gradA: np.ndarray  # dA/dz
    res: np.ndarray  # phi(X0, Y0) - (X0, Y0) at the last evaluation (over eps)
    eps: float = 1.0  # res and J are the map's increments divided by eps (RotatingOrbitMap)

    @property
    def residual(self) -> float:
        return float(np.max(np.abs(self.res)))

    @property
    def M(self) -> np.ndarray:
        return self.eps * self.J[:, :2] + np.eye(2)

    @property
    def tangent(self) -> np.ndarray:
        """Null vector of J (not normalized, orientation fixed by J): its w-component is det(M - I)."""
        return np.cross(self.J[0], self.J[1])

    @property
    def det_m_minus_i(self) -> float:
        return float(self.J[0, 0] * self.J[1, 1] - self.J[0, 1] * self.J[1, 0])

    @property
    def dA_ds(self) -> float:
        """Derivative of the swing along the branch (the tangent's orientation, unnormalized)."""
        t = self.tangent
        return float(self.gradA @ t / np.linalg.norm(t))

    @property
    def w_turn(self) -> float:
        """det(M - I) / |tangent|: the w-component of the unit tangent, zero at a fold."""
        t = self.tangent
        return float(t[2] / np.linalg.norm(t))


class OrbitMap:
    """The one-period map of q'' = a(q, q') + f0 cos(omega t) in the scaled variables of the module doc.

    ``force(q, p)`` returns (a, da/dq, da/dp) as floats.

    ``step_scale``: DOP853's first step is ``step_scale * rtol**(1/8)`` (drive phase) instead of its
    starting heuristic, which begins a smooth one-period orbit with a step a few hundred times too short
    and spends three steps growing it: for a near-harmonic response, whose steps in the drive phase are
    about c rtol^(1/8) with c set by the waveform alone (a function of rtol, never of the history, so that
    a map's value depends on (z, rtol) only).

    ``odd``: the force is odd, a(-q, -p) = -a(q, p).  The equation is then unchanged by q -> -q with
    t -> t + T/2 (the drive changes sign over half a period), and the periodic response that grows out
    of the linear one keeps that symmetry, q(t + T/2) = -q(t).  Such an orbit is a fixed point of the
    half-period map followed by (q, q') -> (-q, -q'), G = -phi_{T/2}, and the one-period map is G o G:
    so it is G that is integrated (half the work), its fixed point found, and M = (dG)^2 (``monodromy``).
    The residual, J = dG - I and the swing are G's: det(M - I) = det(dG - I) det(dG + I) changes sign
    where det(dG - I) does unless dG + I is singular, an eigenvalue -1 of dG where the symmetric orbit
    would lose its symmetry; ``evaluate`` fails loudly well before that (det(I + dG) < 1, where it is
    about 4 for the near-harmonic response of a weak nonlinearity).
    """

    def __init__(
        self,
        force: Callable[[float, float], tuple[float, float, float]],
        f0: float,
        Q: float,
        omega_ref: float,
        W: float,
        method: str = "DOP853",
        memo: dict | None = None,
        memo_key: tuple | None = None,
        integrator: str | None = None,
        odd: bool = False,
        step_scale: float | None = None,
    ):
        """``memo``/``memo_key``: a dict shared by the runs of one cross-check (``run.shared``) and a key
        naming everything the force depends on.  The map is a deterministic function of (z, rtol), so an
        evaluation repeated at the same point and tolerance (the rerun at rtol/10 repeats the sweeps,
        which run at a tolerance that does not depend on rtol) is taken from there: the same numbers
        without the integration.  Without both, nothing is kept."""
        self.force, self.f0, self.Q, self.omega_ref, self.W, self.method = force, f0, Q, omega_ref, W, method
        # the Run's integrator choice (``mech bench``), applied to every integration of the map
        self.integrator = integrator
        self.forced = bool(integrator)
        self.nfev = 0
        self.calls = 0
        self.memo_hits = 0
        self._memo = memo if memo is not None and memo_key is not None else None
        self.odd = bool(odd)
        self.step_scale = step_scale
        self._memo_key = (type(self).__name__, memo_key, f0, Q, omega_ref, W, method, integrator, self.odd,
                          step_scale)

    def monodromy(self, bp: BranchPoint) -> np.ndarray:
        """The one-period monodromy matrix M at a periodic orbit: bp.M, or (dG)^2 for an odd force."""
        M = bp.M
        return M @ M if self.odd else M

    def omega(self, w: float) -> float:
        return self.omega_ref + self.W * w

    def _rhs(self, omega: float):
        Q, ws, W, f0, force = self.Q, self.omega_ref, self.W, self.f0, self.force
        c_xy = ws / omega  # dX/dtau = (omega_ref/omega) Y
        c_y = 1.0 / (omega * ws * Q)

        cos = math.cos

        def rhs(tau, s):
            X, Y, p00, p01, p02, p10, p11, p12 = s.tolist()  # floats: cheaper than indexing the array 8 times
            a, a_q, a_p = force(Q * X, ws * Q * Y)
            fx = c_xy * Y
            fy = (a + f0 * cos(tau)) * c_y
            jyx = a_q / (omega * ws)
            jyy = a_p / omega
            gx, gy = -W / omega * fx, -W / omega * fy  # d/dw of (fx, fy)
            return [
                fx,
                fy,
                c_xy * p10,
                c_xy * p11,
                c_xy * p12 + gx,
                jyx * p00 + jyy * p10,
                jyx * p01 + jyy * p11,
                jyx * p02 + jyy * p12 + gy,
            ]

        return rhs

    def evaluate(self, z, rtol: float) -> BranchPoint:
        """Integrate one drive period from (X0, Y0) at w; the point need not be periodic."""
        z = np.asarray(z, dtype=float)
        key = None
        if self._memo is not None:
            key = (self._memo_key, tuple(z.tolist()), float(rtol))
            hit = self._memo.get(key)
            if hit is not None:
                self.memo_hits += 1
                # a copy: callers move a point's z and A in place
                return _copy(hit)
        budget.check("a periodic orbit's one-period map")
        bp = self._evaluate(z, rtol)
        if key is not None:
            self._memo[key] = _copy(bp)
        return bp

    def _evaluate(self, z: np.ndarray, rtol: float) -> BranchPoint:
        omega = self.omega(z[2])
        if not omega > 0:
            raise NumericFailure(f"the sweep reached a non-positive drive frequency ({omega:g} rad/s)")
        y0 = [z[0], z[1], 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        top = Event(lambda t, s: s[1], terminal=False, direction=-1.0, name="q' = 0, maximum", component=1)
        bottom = Event(lambda t, s: s[1], terminal=False, direction=1.0, name="q' = 0, minimum", component=1)
        scale = max(abs(z[0]), abs(z[1]), 1e-3)
        atol = [rtol * 1e-3 * scale] * 2 + [rtol * 1e-3] * 6
        span = math.pi if self.odd else 2.0 * math.pi
        first = None if self.step_scale is None else min(span, self.step_scale * rtol ** 0.125)
        traj = integrate(self._rhs(omega), (0.0, span), y0, rtol=rtol, atol=atol, method=self.method,
                         events=[top, bottom], integrator=self.integrator, first_step=first)
        self.nfev += traj.nfev
        self.calls += 1
        s = traj.y_end
        if self.odd:
            # G = -phi_{T/2}: dG = -Phi (the half period's variational matrix); det(I + dG) = det(I - Phi)
            sym = (1.0 - s[2]) * (1.0 - s[6]) - s[3] * s[5]
            if not sym > 1.0:
                raise NumericFailure(f"the half-period map has det(I + dG) = {sym:.3g} at w = {z[2]:.6g}: the "
                                     "periodic response is near losing its q -> -q symmetry, which this map assumes")
            J = np.array([[-s[2] - 1.0, -s[3], -s[4]], [-s[5], -s[6] - 1.0, -s[7]]])
            res = np.array([-s[0] - z[0], -s[1] - z[1]])
            # over half a period q reaches one of its extremes; the other is its mirror: the swing is the
            # largest |q| among the turning points and the ends (on the periodic orbit, q' = 0 at an end
            # only where an extreme sits there)
            cands = [y for k in (0, 1) for y in traj.y_events[k]] + [np.array(y0), s]
            y = max(cands, key=lambda c: abs(c[0]))
            sign = 1.0 if y[0] >= 0 else -1.0
            return BranchPoint(z=z.copy(), J=J, A=abs(float(y[0])), gradA=sign * np.array([y[2], y[3], y[4]]),
                               res=res)
        J = np.array([[s[2] - 1.0, s[3], s[4]], [s[5], s[6] - 1.0, s[7]]])
        res = np.array([s[0] - z[0], s[1] - z[1]])

        def extreme(k, sign):
            # the largest (sign=+1) or smallest q among the events, the ends as a fallback (q' = 0 at tau = 0)
            cands = [(sign * y[0], y) for y in traj.y_events[k]]
            cands.append((sign * z[0], np.array(y0)))
            cands.append((sign * s[0], s))
            _, y = max(cands, key=lambda c: c[0])
            return y[0], np.array([y[2], y[3], y[4]])

        qmax, gmax = extreme(0, 1.0)
        qmin, gmin = extreme(1, -1.0)
        return BranchPoint(z=z.copy(), J=J, A=0.5 * (qmax - qmin), gradA=0.5 * (gmax - gmin), res=res)


def _copy(bp: BranchPoint) -> BranchPoint:
    # a copy: callers move a point's z and A in place
    return BranchPoint(z=bp.z.copy(), J=bp.J.copy(), A=bp.A, gradA=bp.gradA.copy(), res=bp.res.copy(), eps=bp.eps)


class RotatingOrbitMap(OrbitMap):
    """The one-period map of q'' + omega0^2 q = r(q, q') + f0 cos(omega t) for a small remainder r, in
    the rotating frame: q/Q = a cos tau + b sin tau, q'/(omega Q) = -a sin tau + b cos tau (tau = omega t,
    an exact change of variables: a, b vary slowly when r, f0 and omega - omega0 are small).

    With x = q/Q, x'' + x = F = (r + f0 cos tau)/(omega^2 Q) + (1 - omega0^2/omega^2) x and
    a' = -F sin tau, b' = F cos tau.  What is integrated is the increment over ``eps`` (the size of
    F, e.g. the damping 2 delta/omega0): A1 = (a - a0)/eps, B1 = (b - b0)/eps, and their derivatives
    in (a0, b0, w) likewise.  So the map's residual and Jacobian come out to rtol of their own size
    however weak the damping: the plain map, x -> x + O(eps), resolves its fixed point only to
    rtol/eps (Q = omega0/(2 delta) = 1e8 left it at 1e-6 at best).  z = (a0, b0, w); the residual
    and J are those increments (BranchPoint.eps scales J back to M).

    ``remainder(q, p)`` returns (r, dr/dq, dr/dp) as floats; ``omega_ref`` is omega0.
    """

    def __init__(self, remainder, f0, Q, omega0, W, eps, *, memo=None, memo_key=None, integrator=None):
        super().__init__(remainder, f0, Q, omega0, W, memo=memo, memo_key=memo_key, integrator=integrator)
        self.eps = float(eps)
        self._memo_key = (*self._memo_key, self.eps)

    def _evaluate(self, z: np.ndarray, rtol: float) -> BranchPoint:
        omega = self.omega(z[2])
        if not omega > 0:
            raise NumericFailure(f"the sweep reached a non-positive drive frequency ({omega:g} rad/s)")
        Q, w0, W, f0, rem, eps = self.Q, self.omega_ref, self.W, self.f0, self.force, self.eps
        a0, b0 = float(z[0]), float(z[1])
        om2 = omega * omega
        k = W * z[2] * (2.0 * w0 + W * z[2]) / om2  # 1 - omega0^2/omega^2, without cancellation
        inv_om2Q = 1.0 / (om2 * Q)
        dk = 2.0 * w0 * w0 / (om2 * omega)  # d k / d omega

        def state(tau, s):
            c, sn = math.cos(tau), math.sin(tau)
            a, b = a0 + eps * s[0], b0 + eps * s[1]
            return c, sn, a * c + b * sn, -a * sn + b * c

        def rhs(tau, s):
            c, sn, x, v = state(tau, s)
            r, r_q, r_p = rem(Q * x, omega * Q * v)
            drive = (r + f0 * c) * inv_om2Q
            G = (drive + k * x) / eps
            Fx = (r_q / om2 + k) / eps
            Fv = r_p / omega / eps
            Fw = W * (r_p * v / om2 - 2.0 * drive / omega + dk * x) / eps
            out = [-G * sn, G * c, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
            for j in range(3):
                P0 = (1.0 if j == 0 else 0.0) + eps * s[2 + j]
                P1 = (1.0 if j == 1 else 0.0) + eps * s[5 + j]
                dF = Fx * (c * P0 + sn * P1) + Fv * (-sn * P0 + c * P1) + (Fw if j == 2 else 0.0)
                out[2 + j] = -sn * dF
                out[5 + j] = c * dF
            return out

        def velocity(tau, s):
            return state(tau, s)[3]

        top = Event(velocity, terminal=False, direction=-1.0, name="q' = 0, maximum")
        bottom = Event(velocity, terminal=False, direction=1.0, name="q' = 0, minimum")
        scale = max(abs(a0), abs(b0), 1.0)
        traj = integrate(rhs, (0.0, 2.0 * math.pi), [0.0] * 8, rtol=rtol, atol=1e-3 * rtol * scale,
                         method=self.method, events=[top, bottom], integrator=self.integrator)
        self.nfev += traj.nfev
        self.calls += 1
        s = traj.y_end

        def extreme(k_ev, sign):
            cands = [(tau, y) for tau, y in zip(traj.t_events[k_ev], traj.y_events[k_ev])]
            cands += [(0.0, np.zeros(8)), (2.0 * math.pi, s)]  # the ends as a fallback
            best = None
            for tau, y in cands:
                c, sn, x, _ = state(tau, y)
                if best is None or sign * x > sign * best[0]:
                    P0 = np.array([1.0, 0.0, 0.0]) + eps * np.asarray(y[2:5])
                    P1 = np.array([0.0, 1.0, 0.0]) + eps * np.asarray(y[5:8])
                    best = (x, c * P0 + sn * P1)
            return best

        xmax, gmax = extreme(0, 1.0)
        xmin, gmin = extreme(1, -1.0)
        J = np.array([s[2:5], s[5:8]], dtype=float)
        return BranchPoint(z=z.copy(), J=J, A=0.5 * (xmax - xmin), gradA=0.5 * (gmax - gmin),
                           res=np.array([s[0], s[1]], dtype=float), eps=eps)


# a fresh point accepted at the noise floor must close to this many times rtol (times its size): 5.10's points
# stopped there close to < 1 rtol; a far start that passed the floor with a step of the size of z, to 1e4
FLOOR_RESIDUAL = 100.0


def solve_on_plane(
    omap: OrbitMap,
    z_guess,
    n,
    c: float,
    *,
    rtol: float,
    tol: float,
    max_iter: int = 8,
    fresh: bool | str = True,
    monotone: bool = True,
) -> BranchPoint | None:
    """Newton on {phi(X0, Y0; w) = (X0, Y0), n . z = c}; None when it does not converge.

    ``tol``: the step size (max norm, scaled units) at which it stops, or the
    noise floor (what the map's error, about rtol, makes of a step through
    K^-1) if that is larger.  With ``fresh`` the returned point is evaluated at
    the converged z (its Jacobian and swing are current); otherwise they belong
    to the last iterate before it.  With ``fresh`` a stop at the floor also
    needs that point to close to ``FLOOR_RESIDUAL`` times rtol (else Newton
    goes on from it).  ``fresh="floor"``: only such a stop at the floor is evaluated again (and
    confirmed); a stop below ``tol`` keeps the last iterate's Jacobian, one map fewer.
    ``monotone``: give up as soon as a step is not smaller than the one before
    (continuation); without it, far starts get all ``max_iter`` steps.
    """
    z = np.asarray(z_guess, dtype=float).copy()
    n = np.asarray(n, dtype=float)
    last = None
    checked = None  # the fresh evaluation at z that did not confirm a floor-limited step: Newton goes on from it
    for _ in range(max_iter):
        bp = checked if checked is not None else omap.evaluate(z, rtol)
        checked = None
        K = np.vstack([bp.J, n])
        rhs = np.concatenate([-bp.res, [c - n @ z]])
        try:
            dz = np.linalg.solve(K, rhs)
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(dz)):
            return None
        step = float(np.max(np.abs(dz)))
        # the map is computed to about rtol; Newton cannot resolve z better than that times |K^-1|
        # (large for a weakly damped orbit, whose multipliers are close to the unit circle)
        scale = max(1e-3, float(np.max(np.abs(z[:2]))))
        floor = rtol * float(np.max(np.abs(np.linalg.inv(K)).sum(axis=1))) * scale
        tol_eff = max(tol, floor)
        if monotone and last is not None and step > 0.9 * last and step > tol_eff:
            return None  # not contracting
        z = z + dz
        last = step
        if step < tol_eff:
            if fresh is True or (fresh == "floor" and step >= tol):
                new = omap.evaluate(z, rtol)
                # the floor bounds the step that the map's error could cause; it says the point is converged
                # only where the residual is down to that error.  Far from the orbit, where K is nearly
                # singular (a self-oscillator's neutral phase), the floor can exceed a real step of the size
                # of z itself: the fresh residual tells, and Newton goes on from the new point
                if step < tol or new.residual <= FLOOR_RESIDUAL * rtol * scale:
                    return new
                checked = new
                continue
            bp.A = bp.A + float(bp.gradA @ (z - bp.z))
            bp.z = z
            return bp
    return None


@dataclass
class Sweep:
    """The points of one continuation run, in order, and the fold that ended it (if any)."""

    points: list = field(default_factory=list)
    fold: BranchPoint | None = None
    fold_bracket: tuple | None = None  # (last point before, first point after) the fold
    reached_stop: bool = False
    watched: bool = False
    steps: int = 0
    rejected: int = 0


def sweep(
    omap: OrbitMap,
    start: BranchPoint,
    direction: float,
    w_stop: float,
    *,
    rtol: float,
    h0: float = 0.3,
    h_max: float = math.inf,
    h_min: float = 1e-9,
    max_steps: int = 400,
    corrector_max: float = 0.2,
    angle_max: float = 0.5,
    newton_tol: float = 1e-3,
    max_state_move: float = 0.1,
    toward: np.ndarray | None = None,
    watch: Callable[[BranchPoint], float] | None = None,
) -> Sweep:
    """Follow the branch from ``start`` with w initially moving in ``direction`` (+1 up, -1 down).

    Stops at the first fold (det(M - I) changes sign between two points; the
    bracket is returned, refine it with ``refine_root``) or when w passes
    ``w_stop``.  A step is accepted when Newton's corrections fall below
    ``newton_tol`` (scaled units: the sweep's points are only brackets, the
    precise values come from the refinements), the corrector moved the point
    by less than ``corrector_max`` times the step and the tangent turned by
    less than ``angle_max`` radians.

    ``toward``: start in the direction of this point instead (``direction``
    is then ignored); ``watch``: also stop where this function of the points
    changes sign (the bracket is in ``fold_bracket``, ``watched`` is set).
    """
    out = Sweep(points=[start])
    t = _unit(start.tangent)
    if (t @ (np.asarray(toward) - start.z) if toward is not None else t[2] * direction) < 0:
        t = -t
    if toward is not None:
        direction = math.copysign(1.0, t[2])  # the way w goes at the start
    bp, h = start, h0
    prev_turn = None  # (s, w_turn) of the previous point, for the secant prediction of a zero
    s_total = 0.0
    while out.steps < max_steps:
        budget.check("continuation of a periodic orbit")
        h_try = _capped_step(bp, min(h, h_max), prev_turn, s_total)
        new, t_new, angle = _corrected(omap, bp, t, h_try, rtol, newton_tol, corrector_max, angle_max,
                                       max_state_move)
        if new is None:
            out.rejected += 1
            h = 0.4 * h_try
            if h < h_min:
                raise NumericFailure(f"continuation stalled at w = {bp.z[2]:.10g} (step below {h_min:g})")
            continue
        out.steps += 1
        stop, new = _stopped(out, omap, bp, new, direction, watch, rtol)
        if stop:
            return out
        prev_turn = (s_total, abs(bp.w_turn))
        s_total += h_try
        out.points.append(new)
        bp, t = new, t_new
        if (bp.z[2] - w_stop) * direction >= 0:
            out.reached_stop = True
            return out
        h = h_try * (1.6 if angle < 0.4 * angle_max else 1.0)
    raise NumericFailure(f"no fold and w = {bp.z[2]:.6g} short of {w_stop:.6g} after {max_steps} steps")


def _capped_step(bp, h_try, prev_turn, s_total):
    """The step, capped by a secant prediction of where det(M - I) (the tangent's w-component) vanishes, so
    that a narrow fold pair (an S of the curve) is not stepped over."""
    wt = abs(bp.w_turn)
    if prev_turn is not None:
        s_prev, wt_prev = prev_turn
        slope = (wt - wt_prev) / max(s_total - s_prev, 1e-300)
        if slope < 0:
            d0 = wt / -slope
            h_try = min(h_try, max(1.3 * d0, 0.05 * h_try))
    return h_try


def _corrected(omap, bp, t, h_try, rtol, newton_tol, corrector_max, angle_max, max_state_move):
    """The predictor's point corrected onto the branch, with its tangent and the angle turned: (point,
    tangent, angle), or (None, None, None) where the step is rejected (Newton failed, or the corrector moved
    too far, or the tangent turned too much)."""
    pred = bp.z + h_try * t
    new = solve_on_plane(omap, pred, t, t @ bp.z + h_try, rtol=rtol, tol=min(newton_tol, 0.05 * corrector_max * h_try),
                         max_iter=5, fresh=False)
    if new is None:
        return None, None, None
    move = float(np.max(np.abs(new.z - pred)))
    t_new = _unit(new.tangent)
    if t_new @ t < 0:
        t_new = -t_new
    angle = math.acos(max(-1.0, min(1.0, float(t_new @ t))))
    # the state's correction is also capped absolutely: a step may not jump to another branch of the
    # curve however long it is along w
    move_xy = float(np.max(np.abs((new.z - pred)[:2])))
    if angle <= angle_max and move <= corrector_max * h_try and move_xy <= max_state_move:
        return new, t_new, angle
    return None, None, None


def _stopped(out, omap, bp, new, direction, watch, rtol):
    """(whether the sweep ends at the accepted point ``new``, that point): a fold (det(M - I) changes sign,
    or w moved backward) or a sign change of ``watch``; the bracket is set on ``out``.  Where a fold seen by
    the loose tangents is not confirmed, the point goes on re-evaluated at the branch."""
    # the cross-product tangent is continuous along the branch: a sign change of its w-component is a fold
    if np.sign(new.tangent[2]) != np.sign(bp.tangent[2]) and new.tangent[2] != 0.0:
        # the loosely converged points carry the Jacobian of their last iterate: confirm at the points
        new, bp_fresh = omap.evaluate(new.z, rtol), omap.evaluate(bp.z, rtol)
        out.points[-1] = bp_fresh
        if np.sign(new.tangent[2]) != np.sign(bp_fresh.tangent[2]):
            out.points.append(new)
            out.fold_bracket = (bp_fresh, new)
            return True, new
    # the same fold seen geometrically: w moved backward (the det test can miss it when the loosely
    # converged points carry Jacobians from off the branch); it lies between the point before the last
    # one and the new one
    if (new.z[2] - bp.z[2]) * direction < 0 and len(out.points) >= 2:
        fresh = [omap.evaluate(q.z, rtol) for q in (out.points[-2], new)]
        out.points.append(new)
        out.fold_bracket = (fresh[0], fresh[1])
        return True, new
    if watch is not None and np.sign(watch(new)) != np.sign(watch(bp)):
        out.points.append(new)
        out.fold_bracket = (bp, new)
        out.watched = True
        return True, new
    return False, new


def refine_root(
    omap: OrbitMap,
    a: BranchPoint,
    b: BranchPoint,
    g: Callable[[BranchPoint], float],
    *,
    rtol: float,
    rtol_search: float,
    xtol: float,
    polish: bool,
) -> BranchPoint:
    """The point between two branch points a and b where g changes sign.

    Each trial point solves the orbit on the plane through a + sigma n normal
    to the chord n = (b - a)/|b - a| (a short chord keeps the plane transverse
    to the branch); Newton starts from the nearest trial already solved, moved
    onto the new plane.  Brent's method on sigma runs at the cheaper
    ``rtol_search`` down to a bracket of ``xtol`` times the chord; the point
    there is then solved at ``rtol``.  That is enough where the reported value
    is stationary at the root (a fold's frequency: an error d sigma costs
    d sigma^2).  With ``polish`` (a root whose position is reported) secant
    steps on values computed at ``rtol`` follow, started a little either side
    of the search's root.  The ends a
    and b are solved afresh, so they may be a sweep's loosely converged points.
    """
    from mech.solvers.numerics.roots import brentq

    d = b.z - a.z
    L = float(np.linalg.norm(d))
    n = d / L
    base = float(n @ a.z)
    solved: dict = {}

    def solve(sigma, r):
        if solved:
            s0 = min(solved, key=lambda s: abs(s - sigma))
            guess = solved[s0].z + (sigma - s0) * n
        else:
            guess = a.z + sigma * n
        # not fresh: the last Newton step is below tol, so the Jacobian and the swing of the iterate
        # before it differ from the converged point's by about that much (the swing is moved along its gradient)
        bp = solve_on_plane(omap, guess, n, base + sigma, rtol=r, tol=max(10.0 * r, 1e-13), max_iter=12,
                            fresh=False)
        if bp is None:
            raise NumericFailure(f"Newton failed on the branch at chord distance {sigma:g} of {L:g}")
        if r == rtol_search:
            solved[sigma] = bp
        return bp

    values: dict = {}

    def f(sigma):
        values[sigma] = g(solve(sigma, rtol_search))
        return values[sigma]

    fa, fb = f(0.0), f(L)
    if np.sign(fa) == np.sign(fb):
        raise NumericFailure("refine_root: the function does not change sign between the two branch points")
    root = brentq(f, 0.0, L, xtol=xtol * L, rtol=1e-15, maxiter=100)
    if not polish:
        return solve(root, rtol)
    # secant steps on precise values, from two points a little either side of the search's root
    s0, s1 = root - 1e3 * xtol * L, root + 1e3 * xtol * L
    g0, g1 = g(solve(s0, rtol)), g(solve(s1, rtol))
    for _ in range(8):
        if g1 == g0:
            break
        s2 = s1 - g1 * (s1 - s0) / (g1 - g0)
        if not (-0.5 * L <= s2 <= 1.5 * L):
            raise NumericFailure("refine_root: the precise secant steps left the branch piece")
        s0, g0 = s1, g1
        s1 = s2
        bp = solve(s1, rtol)
        g1 = g(bp)
        # converged when the step is below what rtol (or double precision: the orbit's condition number
        # amplifies round-off) resolves of the point's size
        if abs(s1 - s0) <= max(10.0 * rtol, 1e-11) * max(L, float(np.max(np.abs(a.z)))):
            return bp
    raise NumericFailure("refine_root: the precise secant steps did not converge")


def shorten_bracket(
    omap: OrbitMap, a: BranchPoint, b: BranchPoint, g: Callable[[BranchPoint], float], *, rtol: float,
    max_chord: float, max_rounds: int = 6,
) -> tuple[BranchPoint, BranchPoint]:
    """A bracket of a sign change of g along the branch no longer than ``max_chord``: the sweep's steps grow
    long where the branch is straight, and a long chord is no good plane family for ``refine_root``."""
    for _ in range(max_rounds):
        L = float(np.linalg.norm(b.z - a.z))
        if L <= max_chord:
            return a, b
        sw = sweep(omap, a, 1.0, math.inf, rtol=rtol, h0=L / 10.0, h_max=L / 10.0, toward=b.z, watch=g,
                   max_steps=200)
        if sw.fold_bracket is None:
            raise NumericFailure("shorten_bracket: the sign change was not found again on the branch")
        a, b = sw.fold_bracket
    raise NumericFailure("shorten_bracket: the bracket did not shrink")


def bisect_parameter(pred: Callable[[float], bool], lo: float, hi: float, *, xtol: float, max_iter: int = 200):
    """Bisection for the switch of a yes/no property: pred(lo) != pred(hi); returns the final (lo, hi)."""
    p_lo = pred(lo)
    if pred(hi) == p_lo:
        raise NumericFailure("bisect_parameter: the property does not switch in the bracket")
    for _ in range(max_iter):
        budget.check("bisection of a parameter")
        if abs(hi - lo) <= xtol:
            break
        mid = 0.5 * (lo + hi)
        if pred(mid) == p_lo:
            lo = mid
        else:
            hi = mid
    return lo, hi


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


# ---------------------------------------------------------------------------------------------------------
# Many oscillators at once: the one-period maps of N variants integrated together (floquet.integrate_ensemble:
# mech's DOP853 stepping the ensemble), Newton on each variant's own plane with its own iterate, convergence
# and failure.


class OrbitEnsemble:
    """The one-period maps of N oscillators q'' + omega_ref^2 q = r(q, q') + f0 cos(omega t), omega = omega_ref
    + W w, in the units of ``OrbitMap`` (plain) or of ``RotatingOrbitMap`` (in the frame rotating with the
    drive, the increments over ``eps``), variant by variant (``rotating``: a mask).

    ``remainder(sel)`` gives the function (q, p) -> (r, dr/dq, dr/dp) of the variants ``sel`` (an index array,
    or an int for one variant alone: floats); ``f0``, ``Q``, ``omega_ref``, ``W``, ``eps`` are arrays of N (``eps``: 1 on the
    plain map).  ``evaluate`` integrates the variants asked (8 numbers each: the state and its derivatives in
    (z0, z1, w)) over one drive period; ``calls[j]`` counts variant j's maps, ``records`` the integrations."""

    def __init__(self, remainder, f0, Q, omega_ref, W, eps, rotating, *, integrator=None):
        self.remainder, self.integrator = remainder, integrator
        self.f0, self.Q, self.w0, self.W, self.eps = (np.asarray(x, dtype=float) for x in (f0, Q, omega_ref, W, eps))
        self.rotating = np.asarray(rotating, dtype=bool)
        self.calls = np.zeros(self.f0.size, dtype=int)
        self.records: list = []

    def evaluate(self, z, idx, rtol):
        """(residual (2, m), Jacobian (2, 3, m)) of the maps of the variants ``idx`` at z (3, m), each held to its
        ``rtol`` (a number or one per variant; relative, 1e-3 rtol absolute in units of its state's size).  The
        variants are integrated in groups, one per kind of map, each variant's error held to its own rtol (the
        shared step the least they allow: the ensemble's cost is its numpy calls, and a class of 300 over 5.10
        integrated 921 groups per decade of rtol against 474 so); with an ``integrator`` (variant by variant)
        per kind of map and decade of rtol, each group at the tightest rtol in it."""
        z, idx = np.asarray(z, dtype=float), np.asarray(idx)
        budget.check("periodic orbits' one-period maps")
        rtol = np.broadcast_to(np.asarray(rtol, dtype=float), (idx.size,))
        res, J = np.empty((2, idx.size)), np.empty((2, 3, idx.size))
        group = self.rotating[idx].astype(float)
        if self.integrator is not None:  # variant by variant, each at one rtol: per decade as the shared step
            group += 2 * np.floor(np.log10(rtol) + 1e-9)
        for g in np.unique(group):
            part = np.flatnonzero(group == g)
            r = rtol[part] if part.size > 1 and self.integrator is None else float(rtol[part].min())
            res[:, part], J[:, :, part] = self._integrate(z[:, part], idx[part], r,
                                                          bool(self.rotating[idx[part[0]]]))
        return res, J

    def _integrate(self, zp, sel, rtol, rot):
        """The maps of the variants ``sel`` (all plain or all rotating) at zp, integrated together at rtol."""
        from mech.solvers.mechanics.floquet import integrate_ensemble

        m = sel.size
        omega = self.w0[sel] + self.W[sel] * zp[2]
        if not np.all(omega > 0):
            raise NumericFailure("a periodic orbit's drive frequency came out non-positive")
        scale = np.maximum(np.maximum(np.abs(zp[0]), np.abs(zp[1])), 1.0 if rot else 1e-3)
        y0 = np.zeros((8, m))
        if rot:
            atol = np.broadcast_to(1e-3 * rtol * scale, (8, m)).copy()
        else:
            y0[0], y0[1], y0[2], y0[6] = zp[0], zp[1], 1.0, 1.0
            atol = np.vstack([np.broadcast_to(1e-3 * rtol * scale, (2, m)), np.full((6, m), 1e-3 * rtol)])
        make = self._rotating_rhs if rot else self._plain_rhs
        s, runs = integrate_ensemble(lambda k: make(sel, zp, k), (0.0, 2.0 * math.pi), y0, rtol=rtol, atol=atol,
                                     integrator=self.integrator)
        self.records += runs
        np.add.at(self.calls, sel, 1)
        J = np.stack([s[2:5], s[5:8]])
        if rot:
            return s[:2], J
        J[0, 0] -= 1.0
        J[1, 1] -= 1.0
        return s[:2] - zp[:2], J

    def _params(self, sel, zp, k):
        """(f0, Q, omega_ref, W, eps, z) of the variants ``sel[k]`` (k: slice(None) for all, an int for one)."""
        pick = sel[k]
        return (self.f0[pick], self.Q[pick], self.w0[pick], self.W[pick], self.eps[pick], zp[:, k], pick)

    def _plain_rhs(self, sel, zp, k):
        f0, Q, ws, W, _, z, pick = self._params(sel, zp, k)
        omega = ws + W * z[2]
        c_xy, c_y = ws / omega, 1.0 / (omega * ws * Q)
        k_x, f_y, c_q, c_p, w_o = ws * ws * Q * c_y, f0 * c_y, 1.0 / (omega * ws), 1.0 / omega, W / omega
        rem = self.remainder(pick)

        def rhs(tau, s):  # (the products folded into constants: the ensemble's cost is its numpy calls)
            r, r_q, r_p = rem(Q * s[0], ws * Q * s[1])
            out = np.empty_like(s)
            out[0] = fx = c_xy * s[1]
            out[1] = fy = r * c_y - k_x * s[0] + f_y * math.cos(tau)
            out[2:5] = c_xy * s[5:8]
            out[5:8] = (r_q * c_q - c_xy) * s[2:5] + (r_p * c_p) * s[5:8]
            out[4] -= w_o * fx
            out[7] -= w_o * fy
            return out

        return rhs

    def _rotating_rhs(self, sel, zp, k):
        f0, Q, w0, W, eps, z, pick = self._params(sel, zp, k)
        omega = w0 + W * z[2]
        om2 = omega * omega
        kk = W * z[2] * (2.0 * w0 + W * z[2]) / om2  # 1 - omega0^2/omega^2, without cancellation
        inv_om2Q, dk = 1.0 / (om2 * Q), 2.0 * w0 * w0 / (om2 * omega)
        a0, b0, rem = z[0], z[1], self.remainder(pick)
        # F = (r + f0 cos tau)/(omega^2 Q) + k x over eps, and its derivatives, with the products folded in
        g_r, g_x = inv_om2Q / eps, kk / eps
        c_fx, c_fv = 1.0 / (om2 * eps), 1.0 / (omega * eps)
        w_p, w_r, w_x = W / (om2 * eps), 2.0 * W * inv_om2Q / (omega * eps), W * dk / eps
        Qw = omega * Q
        e0, e1 = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
        if np.ndim(a0):  # many variants: the unit columns broadcast over them
            e0, e1 = e0[:, None], e1[:, None]

        def rhs(tau, s):
            c, sn = math.cos(tau), math.sin(tau)
            a, b = a0 + eps * s[0], b0 + eps * s[1]
            x, v = a * c + b * sn, b * c - a * sn
            r, r_q, r_p = rem(Q * x, Qw * v)
            rd = r + f0 * c
            G = rd * g_r + g_x * x
            Fx, Fv = r_q * c_fx + g_x, r_p * c_fv
            P0, P1 = eps * s[2:5] + e0, eps * s[5:8] + e1
            dF = (Fx * c - Fv * sn) * P0 + (Fx * sn + Fv * c) * P1
            dF[2] += (r_p * v) * w_p - rd * w_r + w_x * x
            out = np.empty_like(s)
            out[0], out[1] = -sn * G, c * G
            out[2:5], out[5:8] = -sn * dF, c * dF
            return out

        return rhs


def _solve3(J, n, res, gap):
    """Newton's steps and |K^-1|'s largest row sum for m systems K = [J; n] (J: (2, 3, m), n: (3, m)); NaN where K
    is singular."""
    K = np.concatenate([np.transpose(J, (2, 0, 1)), n.T[:, None, :]], axis=1)  # (m, 3, 3)
    det = np.linalg.det(K)
    bad = ~(np.isfinite(det) & (det != 0.0))
    K[bad] = np.eye(3)
    inv = np.linalg.inv(K)
    rhs = np.concatenate([-res, gap[None, :]]).T  # (m, 3)
    dz = np.einsum("mij,mj->mi", inv, rhs).T
    norm = np.abs(inv).sum(axis=2).max(axis=1)
    dz[:, bad], norm[bad] = np.nan, np.nan
    return dz, norm


def newton_on_planes(ens: OrbitEnsemble, idx, z_guess, n, c, *, rtol, tol: float, max_iter: int, fresh):
    """Newton on {phi(z0, z1; w) = (z0, z1), n . z = c} for each variant ``idx`` at once (``solve_on_plane``'s
    rule, each variant its own iterate, stop and failure): z_guess, n (3, m), c (m,); each variant's maps
    integrated at its ``rtol`` (a number or one per variant), its noise floor taken there.
    ``fresh`` (m,): 0, the last iterate's Jacobian kept; 1, a stop at the noise floor evaluated again and
    confirmed (``FLOOR_RESIDUAL``); 2, every stop evaluated again.  Returns (z, J (Jacobian of the last
    evaluation), converged)."""
    z = np.array(z_guess, dtype=float)
    m = z.shape[1]
    n, c, rtol = np.asarray(n, dtype=float), np.asarray(c, dtype=float), np.broadcast_to(rtol, (m,))
    fresh = np.broadcast_to(np.asarray(fresh), (m,))
    J, res = np.full((2, 3, m), np.nan), np.full((2, m), np.nan)
    done, ok, checking = np.zeros(m, bool), np.zeros(m, bool), np.zeros(m, bool)
    last, left = np.full(m, np.inf), np.full(m, max_iter)
    while not done.all():
        act = np.flatnonzero(~done)
        res[:, act], J[:, :, act] = ens.evaluate(z[:, act], idx[act], rtol[act])
        scale = np.maximum(1e-3, np.max(np.abs(z[:2, act]), axis=0))
        chk = checking[act]
        accept = chk & ((last[act] < tol) | (np.max(np.abs(res[:, act]), axis=0)
                                             <= FLOOR_RESIDUAL * rtol[act] * scale))
        done[act[accept]] = ok[act[accept]] = True
        checking[act] = False
        go = act[~accept]
        out = go[left[go] <= 0]
        done[out] = True
        go = go[left[go] > 0]
        if go.size == 0:
            continue
        dz, norm = _solve3(J[:, :, go], n[:, go], res[:, go], c[go] - np.einsum("ij,ij->j", n[:, go], z[:, go]))
        step = np.max(np.abs(dz), axis=0)
        sc = np.maximum(1e-3, np.max(np.abs(z[:2, go]), axis=0))
        tol_eff = np.maximum(tol, rtol[go] * norm * sc)
        finite = np.isfinite(step)
        done[go[~finite]] = True
        go, dz, step, tol_eff = go[finite], dz[:, finite], step[finite], tol_eff[finite]
        z[:, go] += dz
        left[go] -= 1
        last[go] = step
        stop = step < tol_eff
        again = stop & ((fresh[go] == 2) | ((fresh[go] == 1) & (step >= tol)))
        checking[go[again]] = True
        kept = go[stop & ~again]  # the last iterate's Jacobian, a step below the floor away
        done[kept] = ok[kept] = True
    return z, J, ok


__all__ += ["OrbitEnsemble", "newton_on_planes", "on_phase_loop", "loop_fold_brackets", "loop_fold"]


# The locked orbits form a closed loop around the w axis, parametrized by their phase against the drive: on
# the plane n = (-sin th, cos th, 0), Newton solves for the swing and w, well posed however weak the drive (at
# a fixed w instead, its first step along the nearly neutral phase overshoots from a far start).
def on_phase_loop(ens, idx, th, known, r, fresh):
    """The locked orbits of phases th (m,) of the variants idx, Newton started from the solved points
    ``known`` = (th', z', tangent') moved along the branch's tangent (first order in th - th'; None at a
    start: a swing of 2 Q, w = 0), each at its rtol ``r``.  ``fresh`` (newton_on_planes): 1 from a far
    start or on the rotating map, whose weak drive leaves the phase nearly neutral and the noise floor a poor
    bound on the distance to the orbit (5.10's locking ranges of 5e-17 omega0 came out in the
    wrong order without the check); 0 from a solved point nearby on the plain map, the last iterate's
    Jacobian kept (det(M - I) moves by a step below the floor times its curvature).  (z, tangent, ok): the
    tangent, the null vector of [M - I | d phi/dw], has det(M - I) as its w-component."""
    m = idx.size
    R, w = np.full(m, 2.0), np.zeros(m)
    if known is not None:
        t_k, zk, tg = known
        R, w = np.hypot(zk[0], zk[1]), zk[2].copy()
        dth = (zk[0] * tg[1] - zk[1] * tg[0]) / (R * R)  # d(phase)/ds along the tangent
        use = np.abs(dth) * R > 1e-3 * np.linalg.norm(tg, axis=0)
        with np.errstate(divide="ignore", invalid="ignore"):
            R = np.where(use, R + (zk[0] * tg[0] + zk[1] * tg[1]) / R / dth * (th - t_k), R)
            w = np.where(use, w + tg[2] / dth * (th - t_k), w)
    c, sn = np.cos(th), np.sin(th)
    z, J, ok = newton_on_planes(ens, idx, np.stack([R * c, R * sn, w]), np.stack([-sn, c, np.zeros(m)]),
                                np.zeros(m), rtol=r, tol=1e-9, max_iter=12, fresh=fresh)
    ok &= np.hypot(z[0], z[1]) > 1.0  # not the small unstable orbit near rest
    return z, np.cross(J[0], J[1], axis=0), ok, J


def loop_fold_brackets(ens, idx, rs, step=math.pi / 3.0):
    """Phases bracketing the two folds of each variant: from the phase where the drive pushes the swing
    outward (the centre of the range, w ~ 0), in steps of ``step`` (a third of a turn) each way round (both
    ways at once) until w turns back: the edges are the folds, where det(M - I), the w-component of the
    branch's tangent, changes sign.  Adler's loop is w ~ -(Delta/W) cos(phase) with the folds a quarter turn
    either side, moved by ~Delta/mu rad by the drive's push on the swing (at most 0.25 rad, half a step).
    Not all the way round: where the drive pushes the swing inward and 4 Delta/mu exceeds 4/(3 sqrt 3), no
    locked orbit of a large swing has that phase.  An array (m, 29): per direction (th, z, tangent) of the
    point before the turn and after it, then a failure code (0 none, 1 Newton, 2 no turn)."""
    m, th0 = idx.size, 0.5 * math.pi
    z0, tg0, ok, _ = on_phase_loop(ens, idx, np.full(m, th0), None, rs, 1)
    code = np.where(ok, 0.0, 1.0)
    # both directions as 2 m searches: variant j going up is j, going down m + j
    two, r2, d = np.concatenate([idx, idx]), np.concatenate([rs, rs]), np.repeat([1.0, -1.0], m)
    fresh = np.where(ens.rotating[two], 1, 0)
    pt, pz, ptg = np.full(2 * m, th0), np.hstack([z0, z0]), np.hstack([tg0, tg0])
    bt, bz, btg = pt.copy(), pz.copy(), ptg.copy()
    found, bad = np.zeros(2 * m, dtype=bool), np.tile(code != 0, 2)
    for k in (1, 2, 3):
        go = np.flatnonzero(~found & ~bad)
        if go.size == 0:
            break
        th = th0 + d[go] * k * step
        z, tg, okk, _ = on_phase_loop(ens, two[go], th, (pt[go], pz[:, go], ptg[:, go]), r2[go], fresh[go])
        bad[go[~okk]] = True
        turn = okk & (np.sign(tg[2]) != np.sign(ptg[2, go]))
        on = okk & ~turn
        g, h = go[turn], go[on]
        bt[g], bz[:, g], btg[:, g], found[g] = th[turn], z[:, turn], tg[:, turn], True
        pt[h], pz[:, h], ptg[:, h] = th[on], z[:, on], tg[:, on]
    code[(code == 0) & (bad[:m] | bad[m:])] = 1.0
    code[(code == 0) & ~(found[:m] & found[m:])] = 2.0
    cols = [np.hstack([pt[s][:, None], pz[:, s].T, ptg[:, s].T, bt[s][:, None], bz[:, s].T, btg[:, s].T])
            for s in (slice(0, m), slice(m, 2 * m))]
    return np.hstack(cols + [code[:, None]])


def loop_fold(ens, idx, br, r_search, rr, xtol, fresh):
    """Each variant's fold in its bracket ``br`` (th, z, tangent before and after): Illinois on det(M - I)
    over the phase at r_search, each trial started from the nearest point solved, then the fold solved at rr
    from the nearest (its Jacobian that of the last iterate: the edge is z's w).  (z, J-tangent, ok)."""
    from mech.solvers.numerics.batch import illinois

    m = idx.size
    hist = [(br[:, 0], br[:, 1:4].T, br[:, 4:7].T), (br[:, 7], br[:, 8:11].T, br[:, 11:14].T)]
    ok = np.ones(m, dtype=bool)

    def nearest(sel, x):
        ths = np.stack([h[0][sel] for h in hist])
        k = np.argmin(np.where(np.isnan(ths), np.inf, np.abs(ths - x)), axis=0)
        cols = np.arange(sel.size)
        return (ths[k, cols], np.stack([h[1][:, sel] for h in hist])[k, :, cols].T,
                np.stack([h[2][:, sel] for h in hist])[k, :, cols].T)

    def det(x, i):
        z, tg, okk, _ = on_phase_loop(ens, idx[i], x, nearest(i, x), r_search[i], fresh[i])
        ok[i[~okk]] = False
        th, zz, tt = np.full(m, np.nan), np.full((3, m), np.nan), np.full((3, m), np.nan)
        th[i], zz[:, i], tt[:, i] = x, z, tg
        hist.append((th, zz, tt))
        return np.where(okk, tg[2], 0.0)

    x, conv = illinois(det, br[:, 0], br[:, 7], br[:, 6], br[:, 13], xtol=xtol, rtol=0.0)
    z, _, okk, J = on_phase_loop(ens, idx, x, nearest(np.arange(m), x), rr, np.zeros(m, dtype=int))
    # Liouville: the divergence mu (1 - beta q^2) is not constant, so det M is not known in closed form; at a
    # fold one multiplier is exactly 1, recorded (the largest in modulus) as a check of the refinement
    M = ens.eps[idx, None, None] * np.transpose(J[:, :2], (2, 0, 1)) + np.eye(2)
    return z, np.max(np.abs(np.linalg.eigvals(M)), axis=1), ok & okk & conv
