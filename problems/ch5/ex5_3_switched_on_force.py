"""5.3 Sinusoidal force switched on at t = 0: transient plus stationary response.

Analytic: with f = F0/m and the roots p1,2 = -delta +- sqrt(delta^2 - omega0^2)
of p^2 + 2 delta p + omega0^2, the response from rest is the Duhamel
convolution of the impulse response (e^{p1 t} - e^{p2 t})/(p1 - p2) with
f e^{i omega t}, i.e. f times the second divided difference of z -> e^{zt} on
the nodes {i omega, p1, p2}:
    q(t) = f Re e^{zt}[i omega, p1, p2],  q'(t) = f Re (z e^{zt})[i omega, p1, p2].
This single expression covers under-, critically and over-damped transients and
exact resonance (confluent nodes: at delta = 0, omega = omega0 it is
f t sin(omega0 t)/(2 omega0)); it is evaluated without cancellation as the
recursion e[a,m,b] = (e[a,m] - e[m,b])/(a - b) with e[x,y] = e^{yt} t phi1((x-y)t),
phi1(x) = (e^x - 1)/x, the node differences formed analytically (so that
nearly equal nodes lose nothing) and the farthest pair as the outer one; at
short times (all |node| t <= 1) as the (0, 2) entry of the exponential of the
bidiagonal matrix t [[i omega, 1, 0], [0, p1, 1], [0, 0, p2]] (Opitz).  The stationary amplitude is
A_ss = |f| / |(omega0 - omega)(omega0 + omega) + 2 i delta omega|, infinite at
delta = 0, omega = omega0.

Numeric: the full equation of motion with the drive as a state of its own,
(q, q', C, S) with C = cos wt, S = sin wt (C' = -w S, S' = w C): an autonomous
linear system, in the time unit 1/max(omega0, omega, delta).  q(t1), q'(t1):
its exact flow from rest, the matrix exponential of the generator over t1
(solvers/numerics/linear_flow: scaling and squaring, numpy only), never stepped through
1e6..1e11 rad; the claim carries the flow's round-off, u times its phase,
entry by entry.  A_ss: the periodic orbit (I - M) x* = b of the one-period map
x -> M x + b.  Near resonance (where M is close to I) the map is integrated by
DOP853 in the exact variation-of-constants pair (u, w), q = u cos wt + w sin wt,
q' = omega (w cos wt - u sin wt) (``_Rotating.one_period``, a tool followed
unmarked: no motion is declared, q(t1) being the exact flow), with M - I
integrated directly as the deviation of the unit states, so it keeps its relative accuracy however nearly
resonant the drive; elsewhere M - I and b are the matrix exponential of the
generator over one period, carried as exp - I.  Where that shooting is
ill-conditioned (a slow mode that barely decays over a drive period amplifies
the drive's phase round-off by 1/(1 - its multiplier)), the stationary motion
is taken instead as the invariant plane of the flow that moves with the drive:
(q, q') = X (C, S) at all times, a 4x4 linear system for X.  The claim on A_ss
propagates the map's errors through (I - M)^-1 entry by entry; where M is the
identity within its accuracy (no damping, drive period a multiple of the free
period) shooting cannot pick the orbit and the solver fails loudly.  The
phases omega t1, omega0 t1 are known in floats to u times themselves only, in
both methods: ``analytic_error`` and the claims carry it, and a phase beyond
1e15 rad is refused.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure, Undefined

exercise = Exercise(
    "5.3",
    formulas=[
        "q(t) = (F₀/m) Re e^{zt}[iω, p₁, p₂]  (divided difference; p₁,₂ = −δ ± (δ² − ω₀²)^½)",
        "      = a e^{iωt} + transient,  a = (F₀/m)/(ω₀² − ω² + 2iδω)",
        "δ = 0, ω = ω₀:  q = (F₀/m) t sin(ω₀t)/(2ω₀)  (secular growth)",
        "A_ss = (|F₀|/m)/[(ω₀² − ω²)² + 4δ²ω²]^½   (an amplitude: positive for either sign of F₀)",
    ],
    route_note=(
        "q(t1) is the exact flow of the equation of motion (the drive made a state of its own, the matrix "
        "exponential of the generator by scaling and squaring) rather than a DOP853 run to t1, which through "
        "1e6..1e11 rad of phase timed out; A_ss by shooting as the route says, with DOP853 near resonance and "
        "the one-period matrix exponential elsewhere, and the flow's invariant plane where shooting is "
        "ill-conditioned (a slow mode under a fast drive)."
    ),
)

# the route's time unit is the fastest rate, whose square scales the displacements back
ranges.declare(exercise, ranges.Scale("max(omega0, omega, delta)", {}, "the fastest rate and its square", low=-150,
                                      high=150, factor=lambda p: max(p.omega0, p.omega, p.delta)))


def _nodes(w0, d, w):
    """The nodes i omega, p1, p2 and their pairwise differences, each formed without cancellation."""
    z0 = complex(0.0, w)
    if d < w0:
        wd = math.sqrt((w0 - d) * (w0 + d))
        p1, p2 = complex(-d, wd), complex(-d, -wd)
        w_minus_wd = ((w - w0) * (w + w0) + d * d) / (w + wd)
        diff = {(0, 1): complex(d, w_minus_wd), (0, 2): complex(d, w + wd), (1, 2): complex(0.0, 2.0 * wd)}
    else:
        k = math.sqrt((d - w0) * (d + w0))
        p1, p2 = complex(-w0 * w0 / (d + k)), complex(-(d + k))
        diff = {(0, 1): complex(w0 * w0 / (d + k), w), (0, 2): complex(d + k, w), (1, 2): complex(2.0 * k)}
    for (i, j), v in list(diff.items()):
        diff[(j, i)] = -v
    return (z0, p1, p2), diff


def _phi1(x):
    """(e^x - 1)/x for complex |x| < 0.2, by its series."""
    term, total = 1.0 + 0j, 0j
    for k in range(1, 16):
        total += term
        term *= x / (k + 1)
    return total


def _response(w0, d, w, t):
    """(Re e^{zt}[z0, p1, p2], Re (z e^{zt})[z0, p1, p2]) for the nodes z0 = i omega, p1, p2."""
    nodes, diff = _nodes(w0, d, w)
    if t == 0.0:
        return 0.0, 0.0
    if t * max(abs(z) for z in nodes) <= 1.0:
        # all nodes within 1/t of the origin: the exponential of the small bidiagonal matrix (no squaring)
        from mech.solvers.numerics.linear_flow import expm

        B = np.array([[nodes[0], 1, 0], [0, nodes[1], 1], [0, 0, nodes[2]]], dtype=complex)
        E = expm(t * B)
        return E[0, 2].real, (B @ E)[0, 2].real
    # endpoints a, b: the farthest pair (|a - b| t >~ 1, so the outer difference does not cancel)
    a, b = max(((0, 1), (0, 2), (1, 2)), key=lambda ij: abs(diff[ij]))
    m = 3 - a - b

    def first(x, y):  # e^{zt}[x, y] = (e^{xt} - e^{yt})/(x - y) = e^{y t} t phi1((x - y) t)
        h = diff[(x, y)] * t
        if abs(h) < 0.2:
            return np.exp(nodes[y] * t) * t * _phi1(h)
        return (np.exp(nodes[x] * t) - np.exp(nodes[y] * t)) / diff[(x, y)]

    e_mb = first(m, b)
    e_amb = (first(a, m) - e_mb) / diff[(a, b)]
    return e_amb.real, (nodes[a] * e_amb + e_mb).real


@exercise.analytic
def analytic(p):
    f = p.F0 / p.m
    q, v = _response(p.omega0, p.delta, p.omega, p.t1)
    den = abs(complex((p.omega0 - p.omega) * (p.omega0 + p.omega), 2.0 * p.delta * p.omega))
    a_ss = Undefined("undamped exact resonance: the amplitude grows without bound", infinite=True) if den == 0 else abs(f) / den
    return {"q_t": f * q, "v_t": f * v, "A_ss": a_ss}


class _Rotating:
    """Unit force per mass in exact variation-of-constants variables (u, w); used near resonance."""

    def __init__(self, w0, d, w):
        self.w, self.d = w, d
        self.det2 = (w0 - w) * (w0 + w)  # omega0^2 - omega^2 without cancellation

    def coeffs(self, t):
        c, s = math.cos(self.w * t), math.sin(self.w * t)
        # u' = -s G/omega, w' = c G/omega, G = cos wt - 2 delta q' - (w0^2 - w^2) q
        gu = 2.0 * self.d * self.w * s - self.det2 * c
        gw = -2.0 * self.d * self.w * c - self.det2 * s
        a = np.array([[-s * gu, -s * gw], [c * gu, c * gw]]) / self.w
        return a, np.array([-s * c, c * c]) / self.w

    def rhs_period(self, t, y):
        # y = [d1, d2, xp]: deviations of the two unit columns from their start, and the forced state from rest
        a, force = self.coeffs(t)
        return np.concatenate([a @ (y[0:2] + (1.0, 0.0)), a @ (y[2:4] + (0.0, 1.0)), a @ y[4:6] + force])

    def one_period(self, atol):
        """The one-period map as a motion from (d1, d2, xp) = 0: a tool of the shooting, not the scene's motion."""
        from mech.problems.motion import Motion

        return Motion(self.rhs_period, np.zeros(6), (0.0, 2.0 * math.pi / self.w), options={"atol": atol})

    def to_qv(self, x, s):
        c, sn = math.cos(self.w * s), math.sin(self.w * s)
        return x[0] * c + x[1] * sn, self.w * (x[1] * c - x[0] * sn)


_U = 2.0**-53
MAX_PHASE = 1e15  # rad: beyond it the phase's round-off (u * phase) reaches a tenth of a radian


def _rate(p):
    """The fastest phase rate of the motion: the drive and the free oscillation (or the slow decay)."""
    w0, d = p.omega0, p.delta
    free = w0 if d < w0 else w0 * w0 / (d + math.sqrt((d - w0) * (d + w0)))
    return p.omega + free


exercise.declare_limits(
    f"max(omega, omega0) t1 <= {MAX_PHASE:g} rad: the phase carries a digit in double precision",
)


@exercise.constraint
def constraint(p):
    phase = max(p.omega, p.omega0) * p.t1
    if phase > MAX_PHASE:
        return (f"the phase max(omega, omega0) t1 = {phase:.3g} rad carries no significant digit in double "
                f"precision (its round-off u * phase exceeds 0.1 rad; at most {MAX_PHASE:g} rad)")


@exercise.analytic_error
def analytic_error(p):
    """Round-off of the closed form from its phases: exp(i omega t1) and exp(p t1) are evaluated at
    products rounded to u (omega t1), u (|p| t1), so each term moves by its size times that.  The
    stationary term's size is A_ss; the transient's is at most the state at t1 less the stationary
    motion, |q| + A_ss in position and (|q'| + omega A_ss)/omega0 from the velocity (its rates are at
    least omega0 in modulus for the fast part; a slow overdamped part shows in |q|).  Dividing |q'| by
    omega instead (as once here) made the bar ~1e185 at omega = 6e-200 rad/s, where the drive is static."""
    a = analytic(p)
    a_ss = 0.0 if isinstance(a["A_ss"], Undefined) else a["A_ss"]
    q, v = abs(a["q_t"]), abs(a["v_t"])
    size = q + (v + p.omega * a_ss) / p.omega0 + 2.0 * a_ss
    err = 8.0 * _U * (1.0 + _rate(p) * p.t1) * size
    return {"q_t": err, "v_t": err * max(p.omega, p.omega0), "A_ss": 4.0 * _U * a_ss}


def _generator(w0, d, w, unit):
    """The equation of motion with the drive as a state of its own, in the time unit 1/unit and
    x = q unit^2 per unit force per mass: (x, x', C, S) with x'' = -a x - 2 b x' + C, C' = -c S, S' = c C
    (C = cos omega t, S = sin omega t): an autonomous linear system."""
    a, b, c = (w0 / unit) ** 2, d / unit, w / unit
    return np.array([[0.0, 1.0, 0.0, 0.0], [-a, -2.0 * b, 1.0, 0.0], [0.0, 0.0, 0.0, -c], [0.0, 0.0, c, 0.0]])


def _orbit_by_rotating_shooting(model, w, d, rtol, run):
    """Near resonance: the one-period map in variation-of-constants variables by DOP853 (M - I integrated
    directly, so it keeps its relative digits however close to the identity); returns the periodic
    state (q*, q'*) per unit force per mass at t = 0 and its relative error, or Undefined."""
    period = 2.0 * math.pi / w
    dev = (abs(model.det2) + 2.0 * d * w) * period / w
    s_force = 1.0 / max(w * w, abs(model.det2) + w * w, 2.0 * d * w)
    scale = np.array([max(dev, 1e-300)] * 4 + [s_force] * 2)
    atol = np.maximum(scale * rtol * 1e-3, 1e-300)
    one = run.follow(model.one_period(atol), rtol, mark=False).traj
    y = one.y_end
    i_minus_m = -np.array([[y[0], y[2]], [y[1], y[3]]])
    b = y[4:6]
    if d == 0.0:
        run.invariant("det of the period map (Liouville, delta = 0)", np.linalg.det(np.eye(2) - i_minus_m) - 1.0)
    # DOP853's global error grows by about 0.06 rtol per radian of the fastest motion (measured against the
    # exact map: 0.01-0.063 over 6-565 rad) on top of ~rtol; the claim takes 1 + 0.2 per radian
    g_one = rtol * (1.0 + 0.2 * w * period)
    sig_m = g_one * np.abs(one.y[0:4]).max(axis=1) + atol[0:4]  # entries (0,0), (1,0), (0,1), (1,1)
    sig_b = g_one * np.abs(one.y[4:6]).max(axis=1) + atol[4:6]
    if np.linalg.svd(i_minus_m, compute_uv=False)[-1] == 0.0:
        if d == 0.0 and model.det2 == 0.0:
            return Undefined("undamped exact resonance: the period map is the identity, no periodic orbit; "
                             "the amplitude grows without bound", infinite=True), 0.0
        raise NumericFailure("the one-period map is the identity to rounding: no unique periodic orbit")
    xs = np.linalg.solve(i_minus_m, b)
    sig_mat = np.array([[sig_m[0], sig_m[2]], [sig_m[1], sig_m[3]]])
    dxs = np.abs(np.linalg.inv(i_minus_m)) @ (sig_b + sig_mat @ np.abs(xs))
    return model.to_qv(xs, 0.0), float(np.hypot(*dxs) / max(np.hypot(*xs), 1e-300))


def _orbit_by_flow_shooting(gen, unit, w, run):
    """Away from resonance: the one-period map of the autonomous system ``gen`` as its matrix exponential,
    carried as M - I (a slow mode that barely moves in one period keeps its digits); the periodic state
    (q*, q'*) per unit force per mass and its relative error (rounding propagated entry by entry)."""
    from mech.solvers.numerics.linear_flow import expm_minus_identity, rounding_bound

    period = 2.0 * math.pi * unit / w  # in the time unit 1/unit
    dm = expm_minus_identity(gen * period)
    rb = rounding_bound(gen, period)
    sig = rb * (np.abs(dm) @ (np.abs(dm) + 2.0 * np.eye(4)))
    i_minus_m, b = -dm[:2, :2], dm[:2, 2]
    sig_mat, sig_b = sig[:2, :2], sig[:2, 2]
    # the period itself is known to rb P only (the drive's phase): b moves by that time the state's rate
    end = np.array([b[0], b[1], 1.0, 0.0])
    sig_b = sig_b + rb * period * np.abs(gen @ end)[:2]
    if np.linalg.svd(i_minus_m, compute_uv=False)[-1] == 0.0:
        raise NumericFailure("the one-period map is the identity to rounding: no unique periodic orbit")
    xs = np.linalg.solve(i_minus_m, b)
    dxs = np.abs(np.linalg.inv(i_minus_m)) @ (sig_b + sig_mat @ np.abs(xs))
    c = w / unit
    rel = math.hypot(dxs[0], dxs[1] / c) / max(math.hypot(xs[0], xs[1] / c), 1e-300)
    return (xs[0] / unit**2, xs[1] / unit), float(rel)


def _orbit_by_invariant_manifold(gen, unit, w):
    """Where one-period shooting is ill-conditioned (a slow mode that barely decays over a period: the
    drive's phase round-off is amplified by 1/(1 - its multiplier)): the stationary motion is the flow's
    invariant plane that moves with the drive, (x, x') = X (C, S) for all t, so A X + B = X R with A, B, R
    the generator's blocks (oscillator, force, drive): a 4x4 linear system for X, solved as it stands.
    Returns (q*, q'*) at t = 0 per unit force per mass and the relative error (Skeel's bound)."""
    a_osc, b_force, r_drive = gen[:2, :2], gen[:2, 2:], gen[2:, 2:]
    eye = np.eye(2)
    # row-major vec: vec(A X) = (A kron I) vec X, vec(X R) = (I kron R^T) vec X
    k = np.kron(a_osc, eye) - np.kron(eye, r_drive.T)
    rhs = -b_force.ravel()
    x = np.linalg.solve(k, rhs)
    skeel = np.abs(np.linalg.inv(k)) @ (np.abs(k) @ np.abs(x) + np.abs(rhs))
    c = w / unit
    x_mat = x.reshape(2, 2)
    qs, vs = x_mat[0, 0], x_mat[1, 0]  # at t = 0: (C, S) = (1, 0)
    amp = math.hypot(x_mat[0, 0], x_mat[0, 1])
    rel = 16.0 * _U * float(np.max(skeel[:2])) / max(amp, 1e-300)
    # the amplitude is that of q = X00 C + X01 S itself, not hypot(q*, q'*/omega): q'* = X10 is tiny
    # beside its own round-off when the drive is slow (omega = 6e-200 rad/s made A_ss ~ 1e183)
    return (qs / unit**2, vs / unit), rel, amp / unit**2


@exercise.numeric
def numeric(p, run):
    from mech.solvers.numerics.linear_flow import expm, rounding_bound

    f = p.F0 / p.m
    w0, d, w = p.omega0, p.delta, p.omega
    period = 2.0 * math.pi / w
    det2 = (w0 - w) * (w0 + w)
    dev = (abs(det2) + 2.0 * d * w) * period / w  # how far the one-period map is from the identity
    rotating = dev <= 2.0
    unit = max(w0, w, d)  # time unit 1/unit: every rate of the scaled system is at most 2
    gen = _generator(w0, d, w, unit)
    rtol = run.rtol
    tol = exercise.tol_factor * rtol

    # A_ss: the periodic orbit of the one-period map x -> M x + b, (I - M) x* = b
    amp = None
    if rotating:
        run.info["orbit"] = "one-period map in variation-of-constants variables (DOP853)"
        orbit, rel = _orbit_by_rotating_shooting(_Rotating(w0, d, w), w, d, rtol, run)
    else:
        from mech.solvers.numerics.linear_flow import rounding_bound as _rb

        # the one-period exponential's own rounding alone exceeds the claim over a period of more than
        # ~1e7 time units (a drive far slower than the oscillator): shooting could not earn it, and over
        # 1e200 units its squarings overflow; straight to the invariant plane then
        if _rb(gen, 2.0 * math.pi * unit / w) > tol:
            orbit, rel = None, math.inf
        else:
            run.info["orbit"] = "one-period map as the matrix exponential of the equation's generator"
            orbit, rel = _orbit_by_flow_shooting(gen, unit, w, run)
        if not rel <= tol:
            why = "drive period too long to shoot over" if orbit is None else f"relative error {rel:.2g}"
            run.info["orbit"] = (f"shooting ill-conditioned ({why}): the invariant plane of the "
                                 "generator that moves with the drive")
            orbit, rel, amp = _orbit_by_invariant_manifold(gen, unit, w)
    if isinstance(orbit, Undefined):
        a_ss, stationary = orbit, 0.0
    else:
        if rel > 1e-3:
            raise NumericFailure(
                "the one-period map is the identity within its accuracy (drive period a multiple of the free "
                "period at no damping?): the periodic orbit is not determined by shooting")
        qs, vs = orbit
        a_ss = abs(f) * (amp if amp is not None else math.hypot(qs, vs / w))
        run.claim("A_ss", rel=max(tol, rel))
        stationary = (abs(qs) + abs(vs) / unit) * unit**2  # in the scaled units of the flow below

    # q(t1), q'(t1): the exact flow of the equation of motion with the drive as a state, from rest
    s1 = unit * p.t1
    flow = expm(gen * s1)
    y = flow[:, 2]  # from (x, x', C, S) = (0, 0, 1, 0)
    run.info["flow"] = "matrix exponential of the generator over t1 (scaling and squaring)"
    # its round-off: every component j injects about rb times its size, carried to x and x' by the flow
    rb = rounding_bound(gen, s1)
    s_x = abs(y[0]) + abs(y[1]) + 2.0 * stationary
    sizes = np.array([s_x, s_x, 1.0, 1.0])
    err = rb * (np.abs(flow[:2]) @ sizes)
    run.claim("q_t", rel=tol, abs=abs(f) * err[0] / unit**2)
    run.claim("v_t", rel=tol, abs=abs(f) * err[1] / unit)
    return {"q_t": f * y[0] / unit**2, "v_t": f * y[1] / unit, "A_ss": a_ss}
