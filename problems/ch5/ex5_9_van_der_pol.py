"""5.9 Van der Pol self-oscillator: the limit cycle's amplitude, frequency and Floquet exponent.

Analytic (reduced equation): with q = A cos(omega0 t + phi) and A, phi slow,
averaging the nonlinear damping over a period gives
dA/dt = (mu/2) A (1 - beta A^2/4), d phi/dt = 0.  Small A grows, every A > 0
goes to the stationary A0 = 2/sqrt(beta); the frequency stays omega0; the
deviation from A0 relaxes at the rate
d/dA[(mu/2) A (1 - beta A^2/4)] at A0 = -mu, the Floquet exponent.  Leading
order in mu/omega0.

Numeric (exact): in the scaled variables x = sqrt(beta) q, tau = omega0 t,
eps = mu/omega0 the equation is x'' - eps (1 - x^2) x' + x = 0.
eps <= 4: the return map from a maximum (X, 0) to the next (events on
x' = 0, DOP853) carries the integral of (1 - x^2) x'^2, the energy gained
over the return divided by eps; the cycle's X is its root (Brent, bracketed
by X = 1, where the damping is negative all along, and X = 3).  Unlike Newton
on the map itself, X -> X + O(eps), the root keeps its conditioning as
eps -> 0.  A = X/sqrt(beta), omega = 2 pi omega0/T; lambda_lc: Liouville's
formula, mu times the period average of (1 - x^2), checked against ln det M
of the converged cycle where that is resolvable.
eps > 4 (relaxation oscillation): x and u = x'/eps against the slow time
tau/eps with LSODA (stiff on the slow branches); from the maximum (2, 0) the
cycle attracts by exp(-1.44 eps^2) per half cycle, and the second full cycle
gives period, amplitude and exponent; its two halves must agree.
The declared motion (``motion``) is one period of the converged cycle (followed with its
variational equations: det M) or the relaxation's three legs; the search's returns are
tool runs of the same oscillator.

Allowances (leading-order outputs; outside mu/omega0 >= 1 nothing is compared):
  A          twice the next order eps^2/192 (Poincare-Lindstedt; fitted 0.005208);
  omega      twice the next order eps^2/16 (Nayfeh & Mook sec. 3.3; fitted 0.06250);
  lambda_lc  twice the next order eps^2/16 (fitted 0.06250).
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "5.9",
    formulas=[
        "dA/dt = (μ/2) A (1 - β A²/4)  (reduced equation)",
        "A = 2/β^(1/2),  ω = ω₀",
        "λ_lc = -μ",
    ],
    leading_order=("A", "omega", "lambda_lc"),
    route_note="""
The cycle is the root of the energy gained over one return from the section
(Brent in X alone), not Newton on (A, T): that Newton step is conditioned by
1/eps and moved A by 1e-7 at rtol/10 for eps ~ 1e-5.  For eps > 4, LSODA in
the slow time tau/eps replaces Radau, whose steps stalled at ~1e-6 of a
cycle on the slow branches (30 s at eps = 100).
""",
    # one period of the limit cycle from its maximum (mu/omega0 <= 4); for a relaxation oscillation
    # (mu/omega0 > 4) the cycle and a half from q = 2/beta^(1/2) at rest that settle onto it
    states=[("q", "m"), ("v", "m/s")],
)

# mu/omega0 above which the cycle is a relaxation oscillation: it attracts by exp(-1.44 eps^2) per half
# cycle (1e-10 at eps = 4), so that a start on the slow branch has settled after one half cycle, and the
# explicit method's stability limit (~eps^2 steps a cycle) makes the stiff solver the cheaper one
RELAX_EPS = 4.0
# mu/omega0 beyond which the jumps of the relaxation oscillation, ~1/eps^2 of its slow phases, fall below
# what double precision resolves of a period (1e-10 at 1e5; at 1e6 the jump's event is lost in round-off)
MAX_EPS = 1e5
# what the relaxation route asks of LSODA, relative to the solve's rtol: LSODA's global error of the period
# and of int (1 - x^2) ds is not rtol but up to ~95 rtol (mu/omega0 = 20-26, against scipy at rtol 1e-12),
# the whole default claim tol_factor * rtol; at rtol/10 it is <= 19 rtol over mu/omega0 = 4-120 (commit body)
RELAX_RTOL = 0.1


exercise.declare_limits(
    f"mu/omega0 <= {MAX_EPS:g}",
)


@exercise.constraint
def constraint(p):
    eps = p.mu / p.omega0
    if eps > MAX_EPS:
        # the ratio and its square as powers of ten: mu/omega0 itself overflows at mu = 1e290, omega0 = 1e-320
        k = math.log10(p.mu) - math.log10(p.omega0)
        return (f"mu/omega0 = {_power_of_ten(k)} exceeds {MAX_EPS:g}: a relaxation oscillation whose jumps last "
                f"~(omega0/mu)^2 = {_power_of_ten(-2.0 * k)} of its slow phases, below what double precision "
                "resolves of a period")


def _power_of_ten(k: float) -> str:
    """10^k written out (3 significant digits), also where it is beyond the doubles' range."""
    e = math.floor(k)
    m = 10.0 ** (k - e)
    if m >= 9.995:
        m, e = 1.0, e + 1
    return f"{m:.3g}e{e:+d}" if abs(e) >= 5 else f"{10.0**k:.3g}"


@exercise.analytic
def analytic(p):
    return {"A": 2.0 / math.sqrt(p.beta), "omega": p.omega0, "lambda_lc": -p.mu}


@exercise.expected_error
def expected_error(p):
    """The reduced equation is the first order of an expansion in eps = mu/omega0.  The second order
    (Poincare-Lindstedt; Nayfeh & Mook, Nonlinear Oscillations, sec. 3.3; Bogoliubov & Mitropolsky) gives
    omega = omega0 (1 - eps^2/16 + 17 eps^4/3072), the maximum of q 2/sqrt(beta) (1 + eps^2/192) and, by
    Floquet's exponent of the cycle, lambda_lc = -mu (1 + eps^2/16); fitted against the numeric route at
    eps = 0.02-0.1 the coefficients are 0.005208, -0.06250, +0.06250 (1/192, -1/16, 1/16), and the ratio
    measured/next-order falls from 1 to 0.91-0.95 at eps = 1.  Allowances, one line each:
      A          twice eps^2/192;
      omega      twice eps^2/16;
      lambda_lc  twice eps^2/16.
    At eps >= 1 the expansion is outside its range (``theory_range``): nothing is compared there."""
    e2 = (p.mu / p.omega0) ** 2
    return {"A": e2 / 96.0, "omega": e2 / 8.0, "lambda_lc": e2 / 8.0}


@exercise.theory_range
def theory_range(p):
    """The reduced equation expands in mu/omega0."""
    eps = ("mu/omega0", p.mu / p.omega0)
    return {"A": eps, "omega": eps, "lambda_lc": eps}


def _f(t, y, eps):
    """The oscillator in x = sqrt(beta) q against tau = omega0 t: x'' = eps (1 - x^2) x' - x."""
    return np.array([y[1], eps * (1.0 - y[0] ** 2) * y[1] - y[0]])


def _jac(t, y, eps):
    return np.array([[0.0, 1.0], [-2.0 * eps * y[0] * y[1] - 1.0, eps * (1.0 - y[0] ** 2)]])


def _slow(eps):
    """The same oscillator in x and u = x'/eps against the slow time s = tau/eps (a relaxation oscillation):
    x_s = eps^2 u, u_s = eps^2 (1 - x^2) u - x, with int (1 - x^2) ds carried along; and its Jacobian."""
    e2 = eps * eps

    def rhs(s, z):
        x, u = z[0], z[1]
        d = 1.0 - x * x
        return [e2 * u, e2 * d * u - x, d]

    def jac(s, z):
        x, u = z[0], z[1]
        return [[0.0, e2, 0.0], [-2.0 * e2 * x * u - 1.0, e2 * (1.0 - x * x), 0.0], [-2.0 * x, 0.0, 0.0]]

    return rhs, jac


def _extrema(rhs, z, t, length, turns, missing, options=None, **fields):
    """The motion from ``z`` at ``t`` on to the next extrema of x, one leg each: ``turns`` the (direction,
    name) of each in order, a leg ending at its terminal event x' = 0 (found within ``length``, else
    ``missing(name)`` fails), the next one starting there with x' = 0 exactly (on its section)."""
    from mech.problems.motion import Motion

    (direction, what), rest = turns[0], turns[1:]
    ev = Event(lambda t, z: z[1], terminal=True, direction=direction, name=f"x' = 0, {what}")

    def then(path):
        t1, z1 = _turn(path, what, missing)
        return _extrema(rhs, z1, t1, length, rest, missing, options, **fields) if rest else None

    return Motion(rhs, z, (t, t + length), options={**(options or {}), "events": [ev]}, then=then, **fields)


def _turn(path, what, missing):
    """(t, z) of a leg's extremum, x' set to exactly 0."""
    traj = path.traj
    if len(traj.t_events[0]) == 0:
        raise NumericFailure(missing(what))
    t, z = float(traj.t_events[0][0]), np.array(traj.y_events[0][0])
    z[1] = 0.0
    return t, z


@exercise.motion
def motion(p, X=2.0, T=2.0 * math.pi):
    """mu/omega0 <= 4: one period of the cycle from its maximum (X, 0) in x = sqrt(beta) q, tau = omega0 t
    (the solve finds X and the period T; by default x = 2 over 2 pi, their limits as mu -> 0).  Above: the
    relaxation oscillation in the slow time tau/eps from the maximum (2, 0), three legs, max -> min -> max
    -> min, with int (1 - x^2) ds carried along (``_slow``)."""
    from mech.problems.motion import Motion

    eps = p.mu / p.omega0
    qs = 1.0 / math.sqrt(p.beta)
    if eps <= RELAX_EPS:
        return Motion(lambda t, y: _f(t, y, eps), [X, 0.0], (0.0, T), t_scale=1.0 / p.omega0,
                      y_scale=[qs, qs * p.omega0], y_size=[1.0, max(1.0, eps)])
    rhs, jac = _slow(eps)
    e2 = eps * eps

    def missing(what):
        return f"no {what} of x within 4 slow times (the relaxation cycle's half takes ~0.8)"

    # u is ~1/eps^2 on the slow branches, ~1 in the jumps; LSODA switches to BDF on the stiff slow branches
    return _extrema(rhs, np.array([2.0, 0.0, 0.0]), 0.0, 4.0, ((1.0, "minimum"), (-1.0, "maximum"), (1.0, "minimum")),
                    missing, {"method": "LSODA", "jac": jac}, y_size=[1.0, 1.0 / e2, 1.0],
                    t_scale=eps / p.omega0, y_scale=[qs, qs * p.omega0 * eps], to_states=lambda z: z[:2])


def _return(m, X, eps, rtol, run):
    """From the maximum (X, 0) to the next one, the declared oscillator ``m`` with int (1 - x^2) x'^2 dtau and
    int (1 - x^2) dtau carried along: a tool run (a trial of the search), not the motion.

    Returns (X_next, period, int (1 - x^2) x'^2 dtau, int (1 - x^2) dtau).  The energy
    (x^2 + x'^2)/2 changes over the return by eps times the third: a periodic orbit is where
    that integral vanishes, a root that keeps its conditioning however small eps is (the
    return map itself, X -> X + eps (...), cannot resolve X better than rtol/eps)."""
    vs = max(1.0, eps)  # x' reaches ~eps in the fast parts for eps ~ 1
    f = m.rhs

    def rhs(t, z):
        x, v = z[0], z[1]
        d = 1.0 - x * x
        return np.concatenate([f(t, z[:2]), [d * v * v, d]])

    t_max = 20.0 + 4.0 * eps  # a half period is pi at eps = 0 and ~4.5 at eps = 4

    def missing(what):
        return f"no {what} of x within tau = {t_max:g} from X = {X:.6g}"

    # two legs: to the minimum (x' = 0 upward), then to the maximum; each starts on its other section
    trial = _extrema(rhs, [X, 0.0, 0.0, 0.0], 0.0, t_max, ((1.0, "minimum"), (-1.0, "maximum")), missing,
                     y_size=[1.0, vs, vs * vs, 1.0])
    t, z = _turn(run.follow(trial, rtol=rtol, mark=False), "maximum", missing)
    return float(z[0]), t, float(z[2]), float(z[3])


def _energy_balance(p, run, eps):
    """The cycle's maximum X is the root of the energy gained over one return, in [1, 3]: for X <= 1
    the damping is negative all along the orbit (the energy grows); from X = 3 it falls."""
    from mech.solvers.numerics.roots import brentq

    rtol = run.rtol
    r_search = max(rtol, 1e-7)  # the search runs cheaper; secant steps at rtol finish it
    seen = {}
    m = motion(p)

    def gain(X, r):
        seen[X, r] = _return(m, X, eps, r, run)
        return seen[X, r][2] / (X * X)

    g_lo, g_hi = gain(1.0, r_search), gain(3.0, r_search)
    if not (g_lo > 0.0 > g_hi):
        raise NumericFailure(f"the energy gained over a cycle does not change sign between X = 1 and 3 "
                             f"({g_lo:.3g}, {g_hi:.3g}): no bracket for the limit cycle")
    Xs = brentq(lambda X: gain(X, r_search), 1.0, 3.0, xtol=1e-5, rtol=1e-15, maxiter=100, fa=g_lo, fb=g_hi)
    # the gain's slope is O(1) (-4 pi at eps -> 0): secant steps at rtol from either side of the search's root
    x0, x1 = Xs - 1e-5, Xs + 1e-5
    f0, f1 = gain(x0, rtol), gain(x1, rtol)
    for _ in range(12):
        if f1 == f0:
            break
        x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
        if not 1.0 <= x2 <= 3.0:
            raise NumericFailure(f"the secant steps for the limit cycle left the bracket [1, 3] (X = {x2:.6g})")
        x0, f0, x1 = x1, f1, x2
        f1 = gain(x1, rtol)
        if abs(x1 - x0) <= rtol * x1:  # the noise floor: g is resolved to ~rtol, its slope is O(1)
            break
    else:
        raise NumericFailure("the secant steps for the limit cycle did not converge in 12 steps")
    X = x1
    X_next, T, _, int_div = seen[X, rtol]
    run.info["closure"] = X_next - X
    run.info["brent_evaluations"] = len(seen)

    # Liouville: the second multiplier det M of the converged cycle is exp(eps int (1 - x^2) dtau); this
    # period of the cycle, from its maximum, is the motion
    cycle = run.follow(motion(p, X, T).with_variations(lambda t, y: _jac(t, y, eps)))
    M = cycle.y_end[2:].reshape(2, 2)
    det = float(np.linalg.det(M))
    run.info["det_M"] = det
    if det > 1e3 * rtol:
        run.invariant("Liouville (ln det M - int div)", (math.log(det) - eps * int_div) / max(abs(eps * int_div), 1.0))
    return {"A": X / math.sqrt(p.beta), "omega": 2.0 * math.pi * p.omega0 / T, "lambda_lc": p.mu * int_div / T}


@exercise.numeric
def numeric(p, run):
    eps = p.mu / p.omega0
    if eps > RELAX_EPS:
        return _relaxation(p, run, eps)
    return _energy_balance(p, run, eps)


def _relaxation(p, run, eps):
    """The stiff case, the declared motion (``motion``): from the maximum (2, 0) the cycle attracts by
    exp(-1.44 eps^2) per half cycle; of the three legs, max -> min -> max -> min, the last full cycle
    (min to min) gives the period, its maximum the amplitude and the integral of the divergence the
    exponent.  Its two halves must agree (the cycle is symmetric under x -> -x): the check that the start
    has settled."""
    rtol = run.rtol
    e2 = eps * eps
    # scipy raises an rtol below 100 EPS = 2.2e-14 to it, with a warning: 3e-14 is what LSODA can be asked
    path = run.follow(motion(p), rtol=max(RELAX_RTOL * rtol, 3e-14))
    marks = [_turn(leg, what, None) for leg, what in zip(path.legs, ("minimum", "maximum", "minimum"))]
    (s1, z1), (s2, z2), (s3, z3) = marks
    T, h1, h2 = s3 - s1, s2 - s1, s3 - s2
    if abs(h1 - h2) > 100 * rtol * T or abs(z2[0] + z3[0]) > 100 * rtol * z2[0]:
        raise NumericFailure(f"the relaxation cycle has not settled: half periods {h1:.12g}, {h2:.12g}")
    int_div = z3[2] - z1[2]  # int (1 - x^2) ds over the cycle
    run.info["second_multiplier_log10"] = e2 * int_div / math.log(10.0)
    run.info["method_note"] = "LSODA in the slow time tau/eps: stiff relaxation oscillation"
    return {"A": z2[0] / math.sqrt(p.beta), "omega": 2.0 * math.pi * p.omega0 / (eps * T),
            "lambda_lc": p.mu * int_div / T}
