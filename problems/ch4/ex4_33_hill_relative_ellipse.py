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
(time-reversal symmetry), and T_rel is twice that time.  The declared motion is one full
period with events dx/dt = 0 (radial extremes) and dy/dt = 0 (along-track extremes);
the return to the start state is checked at its end.  The Jacobi integral is monitored.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.gravity import relative_gravity, relative_potential
from mech.solvers.numerics.ode import Event
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
    """Omega = (GM/R^3)^(1/2) as GM^(1/2)/R/R^(1/2): GM/R^3 in one piece leaves the normal range of the
    doubles where Omega does not (GM = 1e-300 m^3/s^2 at R = 6.8e6 m: GM/R^3 = 3.2e-321, a subnormal
    with 10 significant bits, and Omega 3.1e-6 off)."""
    return math.sqrt(GM) / R / math.sqrt(R)


@exercise.analytic
def analytic(p):
    W = _orbit_rate(p.GM, p.R)
    xi = p.x0 / p.R
    s = math.sqrt((1.0 - xi) / (1.0 + xi))
    v0 = -W * p.R * xi * (1.0 + 2.0 / ((1.0 + xi) * (1.0 + s)))
    e = abs(xi)
    beta = -e * e / (1.0 + math.sqrt(1.0 - e * e))

    def y_over_R(E):
        se = e * math.sin(E)
        M = E - se
        return beta * math.sin(E) * math.cos(M) + math.sin(se) * (1.0 - e * math.cos(E)) + se * math.cos(se)

    a_along = -p.R * minimize_bounded(lambda E: -y_over_R(E), 0.0, math.pi, xatol=1e-15)[1]
    a_radial = abs(p.x0)
    ratio = a_radial / a_along
    return {
        "v0": v0,
        "a_along": a_along,
        "a_radial": a_radial,
        "ecc": math.sqrt((1.0 - ratio) * (1.0 + ratio)),
        "T_rel": 2.0 * math.pi / W,
    }


def _xdot(t, y):
    return y[2]


def _ydot(t, y):
    return y[3]


@exercise.motion
def motion(p, run=None):
    """One period of the closed relative path: the exact relative equations in the satellite's rotating
    frame, in units |x0| and 1/Omega, from (x0, 0) at the tangential speed v0 that closes the path, with
    the events of its radial (dx/dt = 0) and along-track (dy/dt = 0) extremes.  v0 and the period are shot
    through ``run`` (tool integrations of the same equations; a Run at the exercise's default accuracy when
    none is given): the path closes when it crosses the x axis at right angles again (time-reversal
    symmetry), so the residual is y at the next zero of dx/dt, bracketed in [-2.4, -1.7], and the period
    is twice that time."""
    from mech.problems.motion import Motion
    from mech.problems.spec import Run
    from mech.solvers.numerics.roots import brentq

    run = Run(rtol=exercise.default_rtol) if run is None else run
    W = _orbit_rate(p.GM, p.R)
    L = abs(p.x0)
    sgn = 1.0 if p.x0 > 0 else -1.0
    Rh = p.R / L  # orbit radius in units of |x0|
    GMh = Rh**3  # GM in units L^3 Omega^2

    def rhs(t, y):
        r = np.array([y[0], y[1], 0.0])
        a = relative_gravity(r, Rh, GMh)
        # centrifugal (x, y) and Coriolis -2 e_z x v, Omega = 1
        return np.array([y[2], y[3], a[0] + y[0] + 2.0 * y[3], a[1] + y[1] - 2.0 * y[2]])

    def jacobi(y):
        """The Jacobi integral, in its scale (Omega x0)^2 = 1."""
        r = np.array([y[0], y[1], 0.0])
        return 0.5 * (y[2] ** 2 + y[3] ** 2) + relative_potential(r, Rh, GMh) - 0.5 * (y[0] ** 2 + y[1] ** 2)

    def path(v, t_end):
        """From (x0, 0) at the tangential speed v until t_end."""
        return Motion(rhs, [sgn, 0.0, 0.0, v], (0.0, t_end), invariants={"Jacobi integral": jacobi},
                      t_scale=1.0 / W, y_scale=[L, L, L * W, L * W], y_size=1.0,
                      options={"method": "DOP853", "max_step": 0.25,
                               "events": [Event(_xdot, terminal=False, name="radial extremes"),
                                          Event(_ydot, terminal=False, name="along-track extremes")]})

    half = {"method": "DOP853", "max_step": 0.25, "events": [Event(_xdot, direction=sgn, terminal=True)]}

    def far_extreme(v):
        """(y, t) where the path from (x0, 0) at speed v next crosses dx/dt = 0 (the far radial extreme)."""
        tr = run.follow(path(v, 20.0).starting(invariants={}, options=half), mark=False).traj
        if len(tr.t_events[0]) == 0:
            raise NumericFailure(f"no radial turning point with v0 = {v:.6g} (scaled)")
        return tr.y_events[0][0][1], tr.t_events[0][0]

    lo, hi = sgn * -2.4, sgn * -1.7  # (-1.5: the circular orbit through the start, no radial turning)
    flo, fhi = far_extreme(lo)[0], far_extreme(hi)[0]
    if not (flo > 0) != (fhi > 0):
        raise NumericFailure(f"v0 not bracketed: y residuals {flo:.3g}, {fhi:.3g}")
    v0 = brentq(lambda v: far_extreme(v)[0], lo, hi, fa=flo, fb=fhi, xtol=1e-3 * run.rtol, maxiter=100)
    return path(v0, 2.0 * far_extreme(v0)[1])


@exercise.numeric
def numeric(p, run):
    W = _orbit_rate(p.GM, p.R)
    L = abs(p.x0)
    sgn = 1.0 if p.x0 > 0 else -1.0
    # one full period (twice the half period, by the same time-reversal symmetry): radial and
    # along-track extremes, and the closure of the path checked at its end
    m = motion(p, run)
    y0, v0, T = m.y0, m.y0[3], m.span[1]
    tr = run.follow(m).traj
    xs = [sgn] + [yy[0] for tt, yy in zip(tr.t_events[0], tr.y_events[0]) if tt > 1e-6]
    ys = [yy[1] for yy in tr.y_events[1]]
    if len(xs) < 2 or len(ys) < 2:
        raise NumericFailure("the extremes of the relative path were not all found")
    a_radial = 0.5 * (max(xs) - min(xs))
    a_along = 0.5 * (max(ys) - min(ys))
    yend = tr.y_end
    closure = float(np.max(np.abs(yend - np.array(y0))))
    run.info["closure_error"] = closure
    if closure > 1e4 * run.rtol:
        raise NumericFailure(f"the relative path does not close after 2 x the half period: miss {closure:.3g} x0")
    ratio = a_radial / a_along
    return {
        "v0": v0 * L * W,
        "a_along": a_along * L,
        "a_radial": a_radial * L,
        "ecc": math.sqrt((1.0 - ratio) * (1.0 + ratio)),
        "T_rel": T / W,
    }
