"""4.33 Motion near a satellite on a circular orbit: the relative ellipse.

Analytic.  Leading order (Hill / Clohessy-Wiltshire, the book's answer):
x'' - 2 Omega y' - 3 Omega^2 x = 0, y'' + 2 Omega x' = 0, z'' = -Omega^2 z;
the drift-free solution from (x0, 0) is x = x0 cos Omega t, y = -2 x0 sin Omega t:
an ellipse centred on the satellite, long axis along the track, axis ratio 1/2,
eccentricity 3^(1/2)/2, v0 = -2 Omega x0, period 2 pi/Omega.
Exact (two-body): the path closes when the body's period equals the
satellite's, i.e. its semi-major axis is R; starting at R + x0 with a purely
tangential velocity it is at an apse of an ellipse of eccentricity e = |x0|/R,
vis-viva gives v0 = Omega R [(1 - xi)/(1 + xi)]^(1/2) - Omega (R + x0),
xi = x0/R, evaluated as -Omega R xi [1 + 2/((1 + xi)(1 + s))], s the root.
In the rotating frame the body is at angle nu - M (true minus mean anomaly)
from the satellite: x = r cos(nu - M) - R, y = r sin(nu - M).  The radial
extremes are the apses (for e < 1/4): a_radial = |x0| exactly.  The along-track
half-extent is the maximum over the eccentric anomaly E of
y/R = beta sin E cos M + sin(e sin E)(1 - e cos E) + e sin E cos(e sin E),
beta = -e^2/(1 + (1 - e^2)^(1/2)), M = E - e sin E (no term of order R is
subtracted), maximized by golden section; 2|x0| (1 + O(e^2)).  T_rel = 2 pi/Omega.

Numeric: the exact relative equations in the satellite's rotating frame
(solvers/gravity.relative_gravity: the difference of the two gravity terms
without cancellation, plus centrifugal and Coriolis forces), in units |x0| and
1/Omega, DOP853.  Shooting on v0 (Illinois regula falsi, bracket [-2.4, -1.7] in
these units, checked for a sign change): the path closes when it crosses the x
axis at right angles again, so the residual is y at the next zero of dx/dt
(time-reversal symmetry), and T_rel is twice that time.  Then one full period with
the events of its far radial extreme (dx/dt = 0) and of its two along-track extremes
(dy/dt = 0 upward and downward, one in each half); the return to the start state is
checked at its end.  The Jacobi integral is monitored.  Written once over arrays of
variants (the shooting's trials and the periods of all variants stepped together,
each variant's events its own; a one-point solve is the batch of one).
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.gravity import relative_gravity, relative_potential
from mech.solvers.numerics.roots import minimize_bounded

exercise = Exercise(
    "4.33",
    formulas=[
        "Hill: x'' - 2Ωy' - 3Ω²x = 0, y'' + 2Ωx' = 0, z'' = -Ω²z",
        "closed: v₀ ≈ -2Ωx₀; x = x₀ cos Ωt, y = -2x₀ sin Ωt: axes x₀ (radial), 2x₀ (along track)",
        "axis ratio 1/2, eccentricity √3/2, T = 2π/Ω",
        "exact: v₀ = ΩR[(1-ξ)/(1+ξ)]^{1/2} - Ω(R + x₀), ξ = x₀/R; a_radial = |x₀|; "
        "a_along = max_E r sin(ν - M) (e = |ξ|)",
    ],
    # one period of the closed relative path, in the frame turning with the satellite and centred on
    # it: x radially outward, y along the orbital motion
    states=[("x", "m"), ("y", "m"), ("vx", "m/s"), ("vy", "m/s")],
)

MAX_OFFSET = 0.1  # |x0|/R


exercise.declare_limits(
    "x0 != 0",
    f"1e-90 <= |x0|/R <= {MAX_OFFSET:g}: the body stays close to the satellite",
)


@exercise.constraint
def constraint(p):
    if p.x0 == 0.0:
        return "x0 must be nonzero: at x0 = 0 the body sits on the satellite and there is no ellipse"
    xi = abs(p.x0) / p.R
    if xi > MAX_OFFSET:
        return f"|x0|/R = {xi:.3g} must be at most {MAX_OFFSET} (the body stays close to the satellite)"
    if xi < 1e-90:
        return f"|x0|/R = {xi:.3g} is below 1e-90: offsets that small are below any physical meaning"


def _orbit_rate(GM, R):
    """Omega = (GM/R^3)^(1/2) as GM^(1/2)/R/R^(1/2) (numbers or arrays): GM/R^3 in one piece leaves the normal
    range of the doubles where Omega does not (GM = 1e-300 m^3/s^2 at R = 6.8e6 m: GM/R^3 = 3.2e-321, a
    subnormal with 10 significant bits, and Omega 3.1e-6 off)."""
    return np.sqrt(GM) / R / np.sqrt(R)


def _along(e):
    """The along-track half-extent over R at eccentricity e: the maximum over the eccentric anomaly E of
    y/R = beta sin E cos M + sin(e sin E)(1 - e cos E) + e sin E cos(e sin E) (golden section, one variant)."""
    beta = -e * e / (1.0 + math.sqrt(1.0 - e * e))

    def y_over_R(E):
        se = e * math.sin(E)
        M = E - se
        return beta * math.sin(E) * math.cos(M) + math.sin(se) * (1.0 - e * math.cos(E)) + se * math.cos(se)

    return -minimize_bounded(lambda E: -y_over_R(E), 0.0, math.pi, xatol=1e-15)[1]


@exercise.analytic
def analytic(P):
    """Over arrays of variants (the along-track maximum a scalar search, run for each)."""
    from mech.solvers.numerics.batch import Column

    R, x0, GM = (np.asarray(P[k], dtype=float) for k in ("R", "x0", "GM"))
    W = _orbit_rate(GM, R)
    xi = x0 / R
    s = np.sqrt((1.0 - xi) / (1.0 + xi))
    v0 = -W * R * xi * (1.0 + 2.0 / ((1.0 + xi) * (1.0 + s)))
    e = np.abs(xi)
    a_along = R * np.reshape([_along(float(x)) for x in np.ravel(e)], np.shape(e))
    a_radial = np.abs(x0)
    ratio = a_radial / a_along
    return {"v0": Column(v0), "a_along": Column(a_along), "a_radial": Column(a_radial),
            "ecc": Column(np.sqrt((1.0 - ratio) * (1.0 + ratio))), "T_rel": Column(2.0 * math.pi / W)}


def _units(P):
    """(Omega, L = |x0|, sgn x0, R/L) over arrays: lengths in |x0|, time in 1/Omega (GM = (R/L)^3 there)."""
    R, x0, GM = (np.asarray(P[k], dtype=float) for k in ("R", "x0", "GM"))
    W = _orbit_rate(GM, R)
    L = np.abs(x0)
    return W, L, np.where(x0 > 0, 1.0, -1.0), R / L


def _rhs(Rh, T=1.0):
    """The exact relative equations in the satellite's rotating frame, units |x0| and 1/Omega (GM = Rh^3),
    time in units T (numbers, or arrays of variants): gravity relative to the satellite (without
    cancellation), centrifugal (x, y) and Coriolis -2 e_z x v."""

    def rhs(t, y):
        a = relative_gravity(np.array([y[0], y[1], np.zeros_like(y[0])]), Rh, Rh**3)
        return T * np.array([y[2], y[3], a[0] + y[0] + 2.0 * y[3], a[1] + y[1] - 2.0 * y[2]])

    return rhs


def _jacobi(y, Rh):
    """The Jacobi integral, in its scale (Omega x0)^2 = 1 (states 4 x ...)."""
    r = np.array([y[0], y[1], np.zeros_like(y[0])])
    return 0.5 * (y[2] ** 2 + y[3] ** 2) + relative_potential(r, Rh, Rh**3) - 0.5 * (y[0] ** 2 + y[1] ** 2)


def _shoot(sgn, Rh, rtol, tally):
    """The tangential speed that closes the path, at N variants at once: the path closes when it crosses the
    x axis at right angles again (time-reversal symmetry), so the residual is y at the next zero of dx/dt
    (a terminal event of each variant's run), bracketed in [-2.4, -1.7] sgn (-1.5: the circular orbit
    through the start, no radial turning), its root by Illinois; the half period is that time.  Returns
    (v0, half period, reasons: "" where none)."""
    from mech.solvers.numerics.batch import BatchEvent, illinois

    N = sgn.size
    why = np.full(N, "", dtype=object)

    def far(idx, v):
        """(y, t) at the next radial extreme of the variants idx started at the speeds v."""
        y0 = np.stack([sgn[idx], np.zeros(idx.size), np.zeros(idx.size), v])
        ev = BatchEvent(lambda t, y, _s=sgn[idx]: _s * y[2], direction=1.0, terminal=True, name="far extreme")
        got = tally.follow(lambda sel: _rhs(Rh[idx][sel]), (0.0, 20.0), y0, rtol=rtol, atol=1e-3 * rtol,
                     events=[ev])
        miss = (got.why == "") & ~np.isfinite(got.t_events[0])
        why[idx[miss]] = "no radial turning point within 20/Omega"
        why[idx[got.why != ""]] = got.why[got.why != ""]
        return got.y_events[0][1], got.t_events[0]

    every = np.arange(N)
    lo, hi = -2.4 * sgn, -1.7 * sgn
    flo, fhi = far(every, lo)[0], far(every, hi)[0]
    bad = ~(np.sign(flo) * np.sign(fhi) < 0) & (why == "")
    why[bad] = "v0 not bracketed in [-2.4, -1.7] Omega x0"
    go = np.flatnonzero(why == "")
    v0 = np.full(N, np.nan)
    if go.size:
        x, done = illinois(lambda v, i: np.nan_to_num(far(go[i], v)[0]), lo[go], hi[go], flo[go], fhi[go],
                           xtol=1e-3 * rtol, rtol=0.0, max_iter=100)
        v0[go] = x
        why[go[~done & (why[go] == "")]] = "the shooting for v0 did not converge"
    half = np.full(N, np.nan)
    go = np.flatnonzero(why == "")
    if go.size:
        half[go] = far(go, v0[go])[1]
    return v0, half, why


@exercise.motion
def motion(p):
    """One period of the closed relative path: the exact relative equations in the satellite's rotating
    frame, in units |x0| and 1/Omega, from (x0, 0) at the tangential speed v0 that closes the path (shot at
    this one point, ``_shoot``, at the exercise's default accuracy)."""
    from mech.problems.motion import Motion

    W, L, sgn, Rh = (float(x) for x in _units({k: np.float64(p[k]) for k in ("R", "x0", "GM")}))
    from mech.problems.batched import Tally

    v0, half, why = _shoot(np.array([sgn]), np.array([Rh]), exercise.default_rtol, Tally())
    if why[0]:
        raise NumericFailure(why[0])
    return Motion(_rhs(Rh), [sgn, 0.0, 0.0, float(v0[0])], (0.0, 2.0 * float(half[0])),
                  invariants={"Jacobi integral": lambda y: _jacobi(y, Rh)}, t_scale=1.0 / W,
                  y_scale=[L, L, L * W, L * W], y_size=1.0, options={"method": "DOP853", "max_step": 0.25})


@exercise.batched(("v0", "a_along", "a_radial", "ecc", "T_rel"))
def numeric(P, rtol, outputs, tally=None):
    """The closed relative paths of N variants at once (a one-point solve is the batch of one): v0 and the half
    period shot (``_shoot``), then one full period of each (its time onto [0, 1]) with the events of its far
    radial extreme (dx/dt = 0) and its two along-track extremes (dy/dt = 0 upward and downward, one in each
    half); the return to the start checked at the end, the Jacobi integral's drift reported to ``tally``."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import BatchEvent, Column

    tally = Tally() if tally is None else tally
    W, L, sgn, Rh = _units(P)
    N = W.size
    v0, half, why = _shoot(sgn, Rh, rtol, tally)
    go = np.flatnonzero(why == "")
    T = 2.0 * half
    y0 = np.stack([sgn, np.zeros(N), np.zeros(N), v0])
    yend = np.full((4, N), np.nan)
    xs_far, y_up, y_down = (np.full(N, np.nan) for _ in range(3))
    if go.size:
        evs = [BatchEvent(lambda t, y, _s=sgn[go]: _s * y[2], direction=1.0, name="far radial extreme"),
               BatchEvent(lambda t, y: y[3], direction=1.0, name="along-track extreme (dy/dt up)"),
               BatchEvent(lambda t, y: y[3], direction=-1.0, name="along-track extreme (dy/dt down)")]
        got = tally.follow(lambda sel: _rhs(Rh[go][sel], T[go][sel]), (0.0, 1.0), y0[:, go], rtol=rtol,
                           atol=1e-3 * rtol, events=evs)
        yend[:, go] = got.y_end
        xs_far[go], y_up[go], y_down[go] = got.y_events[0][0], got.y_events[1][1], got.y_events[2][1]
        why[go] = got.why
    with np.errstate(invalid="ignore"):
        found = np.isfinite(xs_far) & np.isfinite(y_up) & np.isfinite(y_down)
        a_radial = 0.5 * np.abs(sgn - xs_far)
        a_along = 0.5 * np.abs(y_up - y_down)
        closure = np.max(np.abs(yend - y0), axis=0)
        ratio = a_radial / a_along
        ecc = np.sqrt((1.0 - ratio) * (1.0 + ratio))
    drift = np.abs(_jacobi(yend, Rh) - _jacobi(y0, Rh))
    tally.invariant("Jacobi integral", np.nan_to_num(drift))
    tally.info["closure_error"] = closure
    ran = why == ""
    failed = [(why == text, text) for text in sorted(set(why[~ran]))]
    failed += [(ran & ~found, "the extremes of the relative path were not all found"),
               (ran & ~(closure <= 1e4 * rtol), "the relative path does not close after 2 x the half period"),
               (ran & ~(drift <= exercise.tol_factor * rtol), "the invariant 'Jacobi integral' drifts by more than "
                "the method allows: the integration is not to be trusted")]
    values = {"v0": v0 * L * W, "a_along": a_along * L, "a_radial": a_radial * L, "ecc": ecc, "T_rel": T / W}
    return {o: Column(values[o], rel=exercise.tol_factor * rtol, failed=failed) for o in outputs}
