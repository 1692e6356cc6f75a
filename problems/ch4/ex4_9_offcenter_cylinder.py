"""4.9 Rolling cylinder with an off-center center of mass: small and finite oscillations.

Analytic: the cylinder turns about the contact line, whose distance to the center
of mass is d, d^2 = R^2 + l^2 - 2 R l cos phi = (R - l)^2 + 4 R l sin^2(phi/2).  With
J(phi) = I + M d^2, T = J phi'^2/2 and U = -M g l cos phi, so the equation of motion is
J(phi) phi'' + M R l sin phi phi'^2 + M g l sin phi = 0, and about phi = 0
Omega^2 = M g l / (I + M (R - l)^2).
Period at amplitude phi0: energy gives dt = (J / (2 M g l (cos phi - cos phi0)))^(1/2) dphi;
with sin(phi/2) = k sin u, k = sin(phi0/2):
  period = 4 (M g l)^(-1/2) int_0^{pi/2} f(u) / (1 - k^2 sin^2 u)^(1/2) du,
  f(u) = (J0 + B sin^2 u)^(1/2), J0 = I + M (R - l)^2, B = 4 M R l k^2,
evaluated as f(pi/2) K(k) - B int cos^2 u / ((f(u) + f(pi/2)) (1 - k^2 sin^2 u)^(1/2)) du:
the logarithmic growth near the top sits in K (scipy's ellipkm1 of k'^2), the
remaining integral is bounded and smooth enough for adaptive quadrature.

Numeric (no Lagrangian): Newton's law for the center of mass and Euler's
equation about it, with the floor's friction F and normal force N unknown and the
center of mass's acceleration written through phi, phi', phi'' by the rolling
kinematics; at every evaluation Newton's law gives F and N as affine functions of
phi'' and Euler's equation is solved for it (the 3x3 system, eliminated in the
order that keeps digits when R - l is tiny).  Omega: the
derivative of phi''(phi, 0) at 0 by Richardson central differences, with the step
halved until successive estimates agree (the nonlinearity scale can be 1e-3 rad).
Period: a quarter swing from rest at phi0 to phi = 0, times 4, in time scaled
by the numeric Omega: a first leg from rest over s = Omega t in [0, 1] (the
quarter takes at least pi/2), the state holding phi - phi0 (so a start 1e-9
from the top is not rounded away) with absolute tolerances scaled by the
distance from the top; then the angle itself as the independent variable down
to phi = 0 (the rate is never zero on the way), so no event is needed; the
energy is checked at the legs' ends.  The route works in units of M, R and
sqrt(R/g), so that far-apart SI values do not underflow in its products, and
over arrays of variants (``numeric``; a one-point solve is the batch of one).
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "4.9",
    formulas=[
        "[I + M (R² + l² - 2Rl cos φ)] φ'' + M R l sin φ φ'² + M g l sin φ = 0",
        "Ω² = M g l / (I + M (R - l)²)",
        "period = 4 (M g l)^(-1/2) ∫₀^{π/2} [(I + M (R-l)² + 4MRl k² sin²u) / (1 - k² sin²u)]^(1/2) du, k = sin(φ₀/2)",
    ],
    # a quarter swing from rest at phi0 down to phi = 0
    states=[("phi", "rad"), ("phi_dot", "rad/s")],
)


exercise.declare_limits(
    "l < R: the center of mass lies inside the cylinder",
    "I <= M (R^2 - l^2): the most a body of mass M inside the cylinder can have",
)


@exercise.constraint
def constraint(p):
    if not p.l < p.R:
        return f"l = {p.l:g} m must be below R = {p.R:g} m (the center of mass lies inside the cylinder)"
    if p.I > p.M * (p.R - p.l) * (p.R + p.l) * (1 + 1e-12):
        return (f"I = {p.I:g} kg*m^2 exceeds M (R^2 - l^2) = {p.M * (p.R**2 - p.l**2):g} kg*m^2, "
                "the most a body of this mass inside the cylinder can have")


def _analytic_one(p):
    from mech.solvers.numerics.quadrature import quad
    from mech.solvers.numerics.special import ellipkm1

    M, R, l, I, g = p.M, p.R, p.l, p.I, p.g
    J0 = I + M * (R - l) ** 2
    # (M g l)^(1/2) and Omega as products of square roots: M g l / J0 in one piece leaves the floating-point
    # range where its square root does not (l = 1e-300 m, g = 2e-4 m/s^2: the ratio ~1e-302 SI, 1e-379
    # in the natural units of scales.py, gave Omega = 0 for 1.2e-151 rad/s)
    root_Mgl = np.sqrt(M) * np.sqrt(g) * np.sqrt(l)
    k = np.sin(p.phi0 / 2.0)
    # cos(phi0/2) straight from the library: its argument reduction uses pi to far more
    # digits than (pi - phi0) in double precision would, which matters within 1e-8 of the top
    kc = np.cos(p.phi0 / 2.0)
    B = 4.0 * M * R * l * k**2
    f1 = np.sqrt(J0 + B)

    def rest(u):
        su, cu = np.sin(u), np.cos(u)
        f = np.sqrt(J0 + B * su**2)
        return cu**2 / ((f + f1) * np.sqrt(cu**2 + kc**2 * su**2))

    # where f turns from its constant part to its sin u part (a sharp bend when J0 << B)
    bend = np.arcsin(min(1.0, np.sqrt(J0 / B))) if B > 0 else np.pi / 2
    pts = [bend] if 0.0 < bend < np.pi / 2 else None
    rem, _ = quad(rest, 0.0, np.pi / 2, points=pts, epsabs=0.0, epsrel=1e-13, limit=400, vectorized=True)
    quarter = (f1 * ellipkm1(kc**2) - B * rem) / root_Mgl
    return {"Omega": root_Mgl / np.sqrt(J0), "period": 4.0 * quarter}


@exercise.analytic
def analytic(P):
    """Over arrays of variants: the closed form (an elliptic integral and an adaptive quadrature) variant by
    variant (``_analytic_one``)."""
    from mech.problems.params import Params
    from mech.solvers.numerics.batch import Column

    arrays = {k: np.atleast_1d(np.asarray(P[k], dtype=float)) for k in ("M", "R", "l", "I", "phi0", "g")}
    n = arrays["M"].size
    got = [_analytic_one(Params({k: float(v[j]) for k, v in arrays.items()})) for j in range(n)]
    return {o: Column(np.array([float(x[o]) for x in got])) for o in ("Omega", "period")}


def _trig(phi0, dphi):
    """sin, cos and sin(phi/2) at phi = phi0 + dphi, by the addition theorems.

    The state carries the displacement dphi from the release angle, so that
    near the unstable top (phi0 within 1e-8 of pi) the angle's small distance from
    the top is not rounded away in phi0 + dphi.
    """
    s0, c0 = np.sin(phi0), np.cos(phi0)
    sd, cd = np.sin(dphi), np.cos(dphi)
    half = np.sin(phi0 / 2.0) * np.cos(dphi / 2.0) + np.cos(phi0 / 2.0) * np.sin(dphi / 2.0)
    return s0 * cd + c0 * sd, c0 * cd - s0 * sd, half


def _phi_ddot(trig, w, M, R, l, I, g):
    """phi'' from Newton-Euler with the contact forces (F, N) as unknowns.

    The center of mass is at (-R phi + l sin phi, R - l cos phi), so its acceleration
    is affine in a = phi''.  Newton's law then gives the friction F and the normal
    force N as affine functions of a; Euler's equation about the center of mass
    (torque of F and N applied at the contact, (-l sin phi, -(R - l cos phi)) from
    it) is solved for a.  The elimination is written out rather than left to a
    generic 3x3 solver, whose normwise backward error would swamp entries of
    order R - l when the center of mass sits next to the rim.
    """
    s, c, half = trig
    h = (R - l) + 2.0 * l * half**2  # R - l cos phi, the center of mass's height
    # x'' = -h a - l s w^2 and y'' = l s a + l c w^2 (rolling kinematics)
    F0, F1 = -M * l * s * w**2, -M * h  # F = M x'' = F0 + F1 a
    N0, N1 = M * g + M * l * c * w**2, M * l * s  # N = M (y'' + g) = N0 + N1 a
    # I a = h F - l s N  (torque about the center of mass)
    return (h * F0 - l * s * N0) / (I - h * F1 + l * s * N1)


def _energy(trig, w, M, R, l, I, g, unit=1.0):
    """The energy above the lowest position, divided by unit^2: the rate and sin(phi/2) are divided by
    ``unit`` (the amplitude) before they are squared, so that a release at 1e-184 rad is not squared to 0."""
    s, _, half = trig
    w_u, half_u = w / unit, half / unit
    rise_u = 2.0 * l * half_u**2  # height of the center of mass above its lowest, over unit^2
    vx_u, vy_u = -((R - l) + rise_u * unit * unit) * w_u, l * s * w_u  # velocity over unit
    return 0.5 * M * (vx_u**2 + vy_u**2) + 0.5 * I * w_u**2 + M * g * rise_u


def _natural(P):
    """The numeric route's units: mass M, length R, time sqrt(R/g), so that M = R = g = 1 and the parameters
    left are l/R and I/(M R^2) (far-apart SI values, M ~ 1e-288 kg with R ~ 1e117 m, would otherwise
    underflow in the products of the swing); and the unit of rate sqrt(g/R) in 1/s.  Numbers or arrays."""
    M, R, l, I, g = (np.asarray(P[k], dtype=float) for k in ("M", "R", "l", "I", "g"))
    return (1.0, 1.0, l / R, I / M / R / R, 1.0), np.sqrt(g) / np.sqrt(R)


def _omega(l, I):
    """Omega = (-d phi''/d phi at 0)^(1/2) by Richardson central differences (phi'' is odd in phi), the step
    halved until successive estimates agree, over arrays of variants (l, I in the route's units,
    ``_natural``): (Omega, the step, failure reason per variant or None)."""
    l, I = np.broadcast_arrays(np.atleast_1d(l), np.atleast_1d(I))
    n = l.size

    def slope(h, idx):
        acc = lambda phi: _phi_ddot(_trig(0.0, phi), 0.0, 1.0, 1.0, l[idx], I[idx], 1.0)  # noqa: E731
        return -(acc(h) - acc(-h)) / (2.0 * h)

    best, step = np.full(n, np.nan), np.full(n, np.nan)
    prev = np.full(n, np.nan)
    h = 1e-2
    live = np.arange(n)
    while h > 1e-15 and live.size:
        est = (4.0 * slope(h / 2.0, live) - slope(h, live)) / 3.0
        done = np.abs(est - prev[live]) <= 1e-13 * np.abs(est)
        best[live[done]], step[live[done]] = est[done], h
        prev[live] = est
        live = live[~done]
        h /= 2.0
    why = np.full(n, None, dtype=object)
    why[np.isnan(best)] = "the linearization did not converge as the step shrank"
    unstable = ~np.isnan(best) & ~(best > 0)
    why[unstable] = "phi = 0 came out unstable"
    with np.errstate(invalid="ignore"):
        return np.sqrt(np.where(best > 0, best, np.nan)), step, why


def _accel(phi0, l, I, Omega):
    """phi'' in the scaled time s = Omega t (route's units), as a function of (phi - phi0, dphi/ds)."""
    def acc(dphi, w):
        return _phi_ddot(_trig(phi0, dphi), w * Omega, 1.0, 1.0, l, I, 1.0) / Omega**2

    return acc


def _amplitude(phi0):
    """The size of the swing's variables: the smaller of the amplitude and the start's distance from the
    unstable top (2 cos(phi0/2) ~ pi - phi0): an error there sets the time spent."""
    return np.minimum(phi0, 2.0 * np.cos(phi0 / 2.0))


@exercise.motion
def motion(p):
    """A quarter swing from rest at phi0 down to phi = 0, in time s = Omega t scaled by the numeric Omega,
    the state holding (phi - phi0, dphi/ds) (a start next to the top keeps its digits)."""
    from mech.problems.motion import Motion

    (_, _, l, I, _), nu = _natural(p)
    l, I, nu = float(l), float(I), float(nu)
    phi0 = p.phi0
    Om, _, why = _omega(l, I)
    if why[0] is not None:
        raise NumericFailure(why[0])
    Omega = float(Om[0])
    acc = _accel(phi0, l, I, Omega)

    def rhs(s, y):
        return np.array([y[1], acc(y[0], y[1])])

    e0 = _energy(_trig(phi0, 0.0), 0.0, 1.0, 1.0, l, I, 1.0, phi0)

    def energy(y):
        """The energy's change from the start, relative to it."""
        return (_energy(_trig(phi0, y[0]), y[1] * Omega, 1.0, 1.0, l, I, 1.0, phi0) - e0) / e0

    t_release = np.sqrt(phi0 / abs(acc(0.0, 0.0)))  # an upper bound of the time, from the release acceleration
    return Motion(rhs, [0.0, 0.0], (0.0, 1e4 * max(1.0, t_release)),
                  event=Event(lambda s, y: phi0 + y[0], direction=-1, name="phi = 0"),
                  invariants={"energy": energy}, t_scale=1.0 / (Omega * nu), y_scale=[1.0, Omega * nu],
                  to_states=lambda y: [phi0 + y[0], y[1]], y_size=0.1 * _amplitude(phi0))


# the first leg of the quarter swing, in s = Omega t: the period grows with the amplitude (a softening torque,
# a growing inertia), so the quarter swing takes at least pi/2 and this leg ends above phi = 0 on the way down
LEG1 = 1.0


def _quarter(phi0, l, I, Omega, rtol, tally):
    """The quarter swings of N variants (route's units), in two legs integrated together: from rest in time
    s = Omega t over [0, LEG1] (state (phi - phi0, dphi/ds)); then with the angle itself as the independent
    variable from where the first leg ended down to phi = 0 (state (s, dphi/ds)), each variant's angle mapped
    onto sigma in [0, 1], the rate never zero on the way down.  Returns (the quarter period in s, the energy's
    largest relative change at the legs' ends)."""
    from mech.solvers.mechanics.floquet import integrate_ensemble

    N = phi0.size
    amp = 0.1 * _amplitude(phi0)

    def leg1(sel):
        acc = _accel(phi0[sel], l[sel], I[sel], Omega[sel])
        return lambda s, y: np.array([y[1], acc(y[0], y[1])])

    y1, runs = integrate_ensemble(leg1, (0.0, LEG1), np.zeros((2, N)), rtol=rtol,
                                  atol=1e-3 * rtol * np.stack([amp, amp]), integrator=tally.integrator)
    d1, w1 = y1
    span = -(phi0 + d1)  # the angle still to go, negative

    def leg2(sel):
        acc, d, L = _accel(phi0[sel], l[sel], I[sel], Omega[sel]), d1[sel], span[sel]

        def rhs(sigma, y):  # y = (s, w): ds/dsigma = L / w, dw/dsigma = (L / w) phi'' (L / w first: a
            w = y[1]        # swing of 1e-184 rad squares to 0)
            ratio = L / w
            return np.array([ratio, ratio * acc(d + sigma * L, w)])

        return rhs

    y2, more = integrate_ensemble(leg2, (0.0, 1.0), np.stack([np.full(N, LEG1), w1]), rtol=rtol,
                                  atol=1e-3 * rtol * np.stack([np.ones(N), amp]), integrator=tally.integrator)
    for r in runs + more:
        tally.record(r)
    e0 = _energy(_trig(phi0, 0.0), 0.0, 1.0, 1.0, l, I, 1.0, phi0)
    drift = np.zeros(N)
    for d, w in ((d1, w1), (-phi0, y2[1])):
        e = _energy(_trig(phi0, d), w * Omega, 1.0, 1.0, l, I, 1.0, phi0)
        drift = np.fmax(drift, np.abs((e - e0) / e0))
    return y2[0], drift


@exercise.batched(("Omega", "period"))
def numeric(P, rtol, outputs, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): Omega by Richardson
    differences over arrays, the quarter swings integrated together (``_quarter``)."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    (_, _, l, I, _), nu = _natural(P)
    phi0 = np.asarray(P["phi0"], dtype=float)
    N = phi0.size
    Omega_n, h, why = _omega(l, I)
    tally.info["linearization_step"] = h
    # far out in the bounds (l/R ~ 1e-150 with phi0 ~ 1e-230) the torque of the swing leaves the range of
    # doubles: said at once, not after a motion that cannot start
    lever = l * np.abs(np.sin(phi0))  # the restoring torque's arm, over R
    with np.errstate(all="ignore"):
        a0 = np.abs(_phi_ddot(_trig(phi0, 0.0), 0.0, 1.0, 1.0, l, I, 1.0))
    tiny = np.finfo(float).tiny
    far = ~(np.isfinite(a0) & (a0 >= tiny) & (lever >= tiny))
    why[(why == None) & far] = ("the swing's torque arm (l/R) sin(phi0) or its release acceleration is beyond "  # noqa: E711
                                "double precision here; the swing cannot be integrated")
    go = np.flatnonzero(why == None)  # noqa: E711
    quarter, drift = np.full(N, np.nan), np.zeros(N)
    if go.size:
        quarter[go], drift[go] = _quarter(phi0[go], l[go], I[go], Omega_n[go], rtol, tally)
    tally.invariant("energy", drift)
    Omega = Omega_n * nu
    tally.info["quarter_period_s"] = quarter / Omega
    failed = [(why == text, text) for text in sorted(set(why[why != None]))]  # noqa: E711
    # Omega: Richardson estimates agree to 1e-13; a small claim keeps the verification honest
    values = {"Omega": Omega, "period": 4.0 * quarter / Omega}
    claims = {"Omega": 1e-11, "period": exercise.tol_factor * rtol}
    return {o: Column(values[o], rel=claims[o], failed=failed) for o in outputs}
