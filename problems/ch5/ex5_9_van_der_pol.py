"""5.9 Van der Pol self-oscillator: the limit cycle's amplitude, frequency and Floquet exponent.

Analytic (reduced equation): with q = A cos(omega0 t + phi) and A, phi slow,
averaging the nonlinear damping over a period gives
dA/dt = (mu/2) A (1 - beta A^2/4), d phi/dt = 0.  Small A grows, every A > 0
goes to the stationary A0 = 2/sqrt(beta); the frequency stays omega0; the
deviation from A0 relaxes at the rate
d/dA[(mu/2) A (1 - beta A^2/4)] at A0 = -mu, the Floquet exponent.  Leading
order in mu/omega0.

Numeric (exact), written once over arrays of variants (``numeric``; a one-point solve is its batch of
one), once for each distinct eps = mu/omega0: in x = sqrt(beta) q, tau = omega0 t the equation is
x'' - eps (1 - x^2) x' + x = 0.
eps <= 4: the return from a maximum (X, 0) to the next (two legs, each ended by its own event x' = 0,
the variants stepped together by DOP853) carries the integral of (1 - x^2) x'^2, the energy gained over
the return divided by eps; the cycle's X is its root in X^2 (bracketed by X = 1, where the damping is
negative all along, and X = 2.5), which keeps its conditioning as eps -> 0 (the map, X -> X + O(eps), does
not).  A = X/sqrt(beta), omega = 2 pi omega0/T; lambda_lc: Liouville's formula, mu times the period average
of (1 - x^2), checked against ln det M of the converged cycle (its variational equations over the period,
a fixed span) where det's cancellation leaves that resolvable.
eps > 4 (relaxation oscillation): x and u = x'/eps against the slow time tau/eps, from the maximum (2, 0);
the cycle attracts by exp(-1.44 eps^2) per half cycle, so the first minimum is on it, and the half cycle
from there to the maximum gives half the period and of the divergence's integral (the cycle is symmetric
under x -> -x), the maximum the amplitude; |x_min| = x_max is the check that it settled.  Up to eps = 16
the variants are stepped together by DOP853; above, each alone with LSODA (stiff).  The declared motion
(``motion``) is one period of the converged cycle or the relaxation's three legs.

Allowances (leading-order outputs; outside mu/omega0 >= 1 nothing is compared):
  A          twice the next order eps^2/192 (Poincare-Lindstedt; fitted 0.005208);
  omega      twice the next order eps^2/16 (Nayfeh & Mook sec. 3.3; fitted 0.06250);
  lambda_lc  twice the next order eps^2/16 (fitted 0.06250).
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure, Tally
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
The cycle is the root of the energy gained over one return from the section (in X^2
alone), not Newton on (A, T), conditioned by 1/eps: it moved A by 1e-7 at rtol/10 for
eps ~ 1e-5.  For eps > 4, LSODA in the slow time tau/eps replaces Radau, whose steps
stalled at ~1e-6 of a cycle on the slow branches (30 s at eps = 100).
""",
    # one period of the limit cycle from its maximum (mu/omega0 <= 4); else a cycle and a half from q = 2/beta^(1/2)
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
# mu/omega0 up to which the relaxation oscillations of many variants are stepped together by DOP853 (its ~2.4 eps^2
# steps a cycle shared by all of them); above, each alone with LSODA, the stiff solver
ENSEMBLE_EPS = 16.0
# the cycle's search (``_cycles``): its bracket's top (X = 2.5, in X^2); a first stage with returns at PRE_RTOL (half
# the steps of 1e-10) to PRE_STOP of it, then at the solve's rtol from a bracket of +-PRE_SPAN about that root
TOP, PRE_RTOL, PRE_STOP, PRE_SPAN = 6.25, 1e-7, 10.0, 3e-6


exercise.declare_limits(f"mu/omega0 <= {MAX_EPS:g}")


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
def analytic(P):
    """Over arrays of variants."""
    from mech.solvers.numerics.batch import Column

    omega0, mu, beta = _arrays(P)
    return {"A": Column(2.0 / np.sqrt(beta)), "omega": Column(omega0 + 0.0 * mu),
            "lambda_lc": Column(-mu + 0.0 * omega0)}


def _arrays(P):
    return np.broadcast_arrays(*(np.asarray(P[k], dtype=float) for k in ("omega0", "mu", "beta")))


@exercise.expected_error
def expected_error(P):
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
    e2 = (np.asarray(P["mu"], dtype=float) / np.asarray(P["omega0"], dtype=float)) ** 2
    return {"A": e2 / 96.0, "omega": e2 / 8.0, "lambda_lc": e2 / 8.0}


@exercise.theory_range
def theory_range(P):
    """The reduced equation expands in mu/omega0."""
    eps = ("mu/omega0", np.asarray(P["mu"], dtype=float) / np.asarray(P["omega0"], dtype=float))
    return {"A": eps, "omega": eps, "lambda_lc": eps}


def _f(t, y, eps):
    """The oscillator in x = sqrt(beta) q against tau = omega0 t: x'' = eps (1 - x^2) x' - x."""
    return np.array([y[1], eps * (1.0 - y[0] ** 2) * y[1] - y[0]])


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
    """The motion from ``z`` at ``t`` on to the next extrema of x, one leg each: ``turns`` the (direction, name) of
    each in order, a leg ending at its terminal event x' = 0 (found within ``length``, else ``missing(name)``
    fails), the next one starting there with x' = 0 exactly."""
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
def motion(p, X=None, T=None):
    """mu/omega0 <= 4: one period of the cycle from its maximum (X, 0) in x = sqrt(beta) q, tau = omega0 t
    (by default the cycle the route finds, ``_cycles``, at the default rtol).  Above: the relaxation
    oscillation in the slow time tau/eps from the maximum (2, 0), three legs, max -> min -> max -> min, with
    int (1 - x^2) ds carried along (``_slow``)."""
    from mech.problems.motion import Motion

    eps = p.mu / p.omega0
    qs = 1.0 / math.sqrt(p.beta)
    if eps <= RELAX_EPS:
        if X is None:
            got = _cycles(np.array([eps]), exercise.default_rtol, Tally())
            if got[5][0]:
                raise NumericFailure(got[5][0])
            X, T = float(got[0][0]), float(got[1][0])
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


def _jac(t, y, eps):
    return np.array([[0.0, 1.0], [-2.0 * eps * y[0] * y[1] - 1.0, eps * (1.0 - y[0] ** 2)]])


def _carried(eps):
    """The oscillator (``_f``) with int (1 - x^2) x'^2 dtau and int (1 - x^2) dtau carried along, for floats or
    arrays of variants.  The energy (x^2 + x'^2)/2 changes over a return by eps times the first: a periodic
    orbit is where it vanishes, a root that keeps its conditioning however small eps is (the return map
    itself, X -> X + eps (...), cannot resolve X better than rtol/eps)."""
    def rhs(t, z):
        x, v = z[0], z[1]
        d = 1.0 - x * x
        return np.array([v, eps * d * v - x, d * v * v, d])

    return rhs


def _returns(eps, X, rtol, tally):
    """From the maxima (X, 0) to the next ones at N variants, in two legs (to the minimum, x' = 0 upward; then
    to the maximum, each from its section), the variants stepped together, each stopped at its own event:
    (X_next, period, int (1 - x^2) x'^2, int (1 - x^2), failure)."""
    from mech.solvers.numerics.ensemble_search import integrate_variants

    vs = np.maximum(1.0, eps)  # x' reaches ~eps in the fast parts for eps ~ 1
    atol = 1e-3 * rtol * np.vstack([np.ones_like(vs), vs, vs * vs, np.ones_like(vs)])
    t_max = 20.0 + 4.0 * float(np.max(eps, initial=0.0))  # a half period is pi at eps = 0 and ~4.5 at eps = 4
    z = np.vstack([X, np.zeros((3, X.size))])
    t, why = np.zeros(X.size), np.full(X.size, "", dtype=object)
    for direction, what in ((1.0, "minimum"), (-1.0, "maximum")):
        z, w, leg = integrate_variants(_carried, (eps,), (0.0, t_max), z, rtol=rtol, atol=atol, work=1.0 + eps,
                                       integrator=tally.integrator, record=tally.record,
                                       event=(lambda t, y: y[1], direction))
        why = np.where(why != "", why, w)
        lost = (why == "") & np.isnan(leg)
        why[lost] = [f"no {what} of x within tau = {t_max:g} from X = {x:.6g}" for x in X[lost]]
        z[1], t = 0.0, t + leg  # on its section
    return z[0], t, z[2], z[3], why


def _cycles(eps, rtol, tally, starts=None):
    """The limit cycles of N variants (eps <= 4): each maximum X the root of the energy gained over one return
    (``_returns``) over X^2, bracketed in [1, 2.5] (for X <= 1 the damping is negative all along the orbit;
    from X = 2.5 the energy falls), by interpolation in X^2 (``interpolated_root``; the gain is ~pi (1 - X^2/4)
    for small eps): first at PRE_RTOL (kept in ``starts`` by eps: a rerun's is the same), then at rtol from
    +-PRE_SPAN about that root, to rtol of X (the noise floor: the gain is resolved to ~rtol, its slope O(1)).
    Returns (X, T, int (1 - x^2) over the cycle, closure X_next - X, evaluations, failure)."""
    from mech.solvers.numerics.ensemble_search import interpolated_root

    N, r0, starts = eps.size, max(rtol, PRE_RTOL), {} if starts is None else starts
    last = [np.full(N, np.nan) for _ in range(5)]  # X and the return from it, the last evaluated
    why, calls, y0, g_lo, g_hi = np.full(N, "", dtype=object), np.zeros(N), *(np.full(N, np.nan) for _ in range(3))

    def gain(y, idx, r):
        X = np.sqrt(y)
        X_next, T, energy, div, w = _returns(eps[idx], X, r, tally)
        for k, v in enumerate((X, X_next, T, energy, div)):
            last[k][idx] = v
        for k in np.flatnonzero((w != "") & (why[idx] == "")):
            why[idx[k]] = w[k]
        np.add.at(calls, idx, 1.0)
        return energy / y

    def search(r, go, *bracket, stop=2.0):
        # a gain within half its resolution of zero (0.5 r of X^2 times the mean slope over the local one) is a root
        thr = 0.5 * r * (g_lo[go] - g_hi[go]) / (TOP - 1.0)

        def f(y, i):
            g = gain(y, go[i], r)
            return np.where(np.abs(g) <= thr[i] * y, 0.0, g)

        y, conv = interpolated_root(f, *bracket, rtol=stop * r)
        why[go[~conv]] = "the root search for the limit cycle did not converge"
        return y

    keys = [(float(e), r0) for e in eps]
    new = np.flatnonzero([k not in starts for k in keys])
    if new.size:
        one, top, mid = np.ones(new.size), np.full(new.size, TOP), np.full(new.size, 0.5 * (1.0 + TOP))
        g_lo[new], g_hi[new], g_mid = np.split(gain(np.concatenate([one, top, mid]), np.tile(new, 3), r0), 3)
        gap = (why[new] == "") & ~((g_lo[new] > 0.0) & (g_hi[new] < 0.0))
        why[new[gap]] = [f"the energy gained over a cycle does not change sign between X = 1 and 2.5 ({a:.3g}, "
                         f"{b:.3g}): no bracket for the limit cycle" for a, b in zip(g_lo[new[gap]], g_hi[new[gap]])]
        k = why[new] == ""
        go = new[k]
        y0[go] = search(r0, go, one[k], top[k], g_lo[go], g_hi[go], mid[k], g_mid[k], stop=PRE_STOP)
        starts.update({keys[j]: (y0[j], g_lo[j], g_hi[j], why[j]) for j in new})
    for j in range(N):
        y0[j], g_lo[j], g_hi[j], why[j] = starts[keys[j]]
    go, X = np.flatnonzero(why == ""), np.full(N, np.nan)
    if go.size:
        ya, yb = y0[go] * (1.0 - PRE_SPAN), y0[go] * (1.0 + PRE_SPAN)
        ga, gb = np.split(gain(np.concatenate([ya, yb]), np.concatenate([go, go]), rtol), 2)
        ok = why[go] == ""  # each end of the bracket at rtol where the pair brackets the root, else the far end
        a, fa = np.where(gb > 0, yb, np.where(ga > 0, ya, 1.0)), np.where(gb > 0, gb, np.where(ga > 0, ga, g_lo[go]))
        b, fb = np.where(ga < 0, ya, np.where(gb < 0, yb, TOP)), np.where(ga < 0, ga, np.where(gb < 0, gb, g_hi[go]))
        go = go[ok]
        X[go] = np.sqrt(search(rtol, go, a[ok], b[ok], fa[ok], fb[ok]))
        again = go[(why[go] == "") & (last[0][go] != X[go])]  # the root's own return, where not the last evaluated
        if again.size:
            gain(X[again] ** 2, again, rtol)
    X[why != ""] = np.nan
    return X, last[2], last[4], last[1] - X, calls, why


def _liouville(eps, X, T, int_div, rtol, tally):
    """One period of each converged cycle from its maximum with its variational equations (the time scaled by
    T: a fixed span): the second multiplier det M = exp(eps int (1 - x^2) dtau) (Liouville), where resolvable.
    Returns the relative drift of ln det M (0 where not resolvable), what it may drift, failures and det M."""
    from mech.solvers.numerics.ensemble_search import integrate_variants

    def system(e, period):
        def rhs(s, z):
            x, v, m00, m01, m10, m11 = z
            d = 1.0 - x * x
            j10, j11 = -2.0 * e * x * v - 1.0, e * d
            return period * np.array([v, e * d * v - x, m10, m11, j10 * m00 + j11 * m10, j10 * m01 + j11 * m11])

        return rhs

    vs = np.maximum(1.0, eps)
    one = np.ones_like(vs)
    z0 = np.vstack([X, 0.0 * X, one, 0.0 * X, 0.0 * X, one])  # M row by row from the identity
    z, why, _ = integrate_variants(system, (eps, T), (0.0, 1.0), z0, rtol=rtol, integrator=tally.integrator,
                                   atol=1e-3 * rtol * np.vstack([one, vs, one, 1.0 / vs, vs, one]),  # M: s_i/s_j
                                   record=tally.record)
    det = z[2] * z[5] - z[3] * z[4]
    # ln det M carries each entry's error (rtol of it plus its atol) through det's cancellation: compared where
    # that leaves it resolved to 1e-3 of its scale, allowed the claim plus tol_factor times that error
    size = np.vstack([one, 1.0 / vs, vs, one])
    err = rtol * (np.abs(z[2:]) + 1e-3 * size)
    d_det = err[0] * np.abs(z[5]) + err[3] * np.abs(z[2]) + err[1] * np.abs(z[4]) + err[2] * np.abs(z[3])
    scale = np.maximum(np.abs(eps * int_div), 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        d_log = d_det / det / scale
        seen = (det > 0.0) & (d_log < 1e-3)
        drift = np.where(seen, (np.log(np.where(seen, det, 1.0)) - eps * int_div) / scale, 0.0)
    allowed = exercise.tol_factor * rtol + exercise.tol_factor * np.where(seen, d_log, 0.0)
    return drift, allowed, why, det


def _slow_legs(eps, rtol, tally, options=None):
    """The relaxation oscillation of N variants in the slow time (``_slow``) from the maximum (2, 0), the declared
    motion's first two legs, max -> min -> max, each ending at its event u = 0, the next starting there on its
    section: (slow times of the two extrema, their states, failure)."""
    from mech.solvers.numerics.ensemble_search import integrate_variants

    n = eps.size
    e2 = eps * eps
    z = np.vstack([np.full(n, 2.0), np.zeros((2, n))])
    s, marks, why = np.zeros(n), [], np.full(n, "", dtype=object)
    for direction, what in ((1.0, "minimum"), (-1.0, "maximum")):
        z, w, leg = integrate_variants(lambda e: _slow(e)[0], (eps,), (0.0, 4.0), z, rtol=rtol, options=options,
                                       work=e2,
                                       atol=1e-3 * rtol * np.vstack([np.ones(n), 1.0 / e2, np.ones(n)]),
                                       integrator=tally.integrator, record=tally.record,
                                       event=(lambda t, y: y[1], direction))
        why = np.where(why != "", why, w)
        why[(why == "") & np.isnan(leg)] = (f"no {what} of x within 4 slow times (the relaxation cycle's half "
                                            "takes ~0.8)")
        z[1], s = 0.0, s + leg
        marks.append((s.copy(), z.copy()))
    return marks, why


def _relaxation(eps, rtol, tally):
    """The stiff case (eps > 4) at N variants, the declared motion's legs (``_slow_legs``): from the maximum (2, 0)
    the cycle attracts by exp(-1.44 eps^2) per half cycle, so that the first minimum is on it; the cycle is
    symmetric under x -> -x, and the half from that minimum to the next maximum gives half the period, the
    amplitude and half the divergence's integral; |x_min| = x_max checks that the start has settled.  Up to
    ENSEMBLE_EPS the variants are stepped together by DOP853 (~2.4 eps^2 steps a cycle); above, one by one with
    LSODA (asked RELAX_RTOL rtol).  Returns (X, T in tau, int (1 - x^2) dtau over the cycle, failure)."""
    n = eps.size
    (X, T, div), why = (np.full(n, np.nan) for _ in range(3)), np.full(n, "", dtype=object)
    for sel, r, options in ((eps <= ENSEMBLE_EPS, rtol, None),
                            # scipy raises an rtol below 100 EPS = 2.2e-14 to it, with a warning: 3e-14 it takes
                            (eps > ENSEMBLE_EPS, max(RELAX_RTOL * rtol, 3e-14),
                             lambda e: {"method": "LSODA", "jac": _slow(e)[1]})):
        k = np.flatnonzero(sel)
        if not k.size:
            continue
        ((s1, z1), (s2, z2)), why[k] = _slow_legs(eps[k], r, tally, options)
        unsettled = np.abs(z1[0] + z2[0]) > 100 * rtol * z2[0]
        why[k[unsettled & (why[k] == "")]] = [f"the relaxation cycle has not settled: extrema {a:.12g}, {b:.12g}"
                                              for a, b in zip(z1[0][unsettled], z2[0][unsettled])]
        X[k], T[k], div[k] = z2[0], 2.0 * eps[k] * (s2 - s1), 2.0 * eps[k] * (z2[2] - z1[2])
    return X, T, div, why


def _scaled(eps, rtol, tally, starts=None):
    """Each distinct eps's cycle in x = sqrt(beta) q and tau = omega0 t: (X, T, lambda/mu, the Liouville drift
    and its allowance, failure, closure, evaluations, det M); the relaxation oscillations (``_relaxation``)."""
    N, (X, T, div, det) = eps.size, (np.full(eps.size, np.nan) for _ in range(4))
    drift, allowed = np.zeros(N), np.full(N, exercise.tol_factor * rtol)
    why, closure, calls = np.full(N, "", dtype=object), np.full(N, np.nan), np.zeros(N)
    small = np.flatnonzero(eps <= RELAX_EPS)
    if small.size:
        e = eps[small]
        X[small], T[small], div[small], closure[small], calls[small], why[small] = _cycles(e, rtol, tally, starts)
        ok = small[why[small] == ""]
        drift[ok], allowed[ok], why[ok], det[ok] = _liouville(eps[ok], X[ok], T[ok], div[ok], rtol, tally)
    big = np.flatnonzero(eps > RELAX_EPS)
    if big.size:
        X[big], T[big], div[big], why[big] = _relaxation(eps[big], rtol, tally)
    return X, T, div / T, drift, allowed, why, closure, calls, det


@exercise.batched(("A", "omega", "lambda_lc"))
def numeric(P, rtol, outputs, memo=None, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): the cycle depends on eps alone,
    found once for each distinct eps (``_scaled``, kept in ``memo`` across a sweep's chunks): the energy balance's
    root (``_cycles``), its Liouville check (``_liouville``), the relaxation oscillations.  A variant fails alone."""
    from mech.solvers.numerics.batch import Column, by_rows

    tally = Tally() if tally is None else tally
    memo = {} if memo is None else memo
    omega0, mu, beta = _arrays(P)
    eps = mu / omega0
    starts = memo.setdefault("5.9 starts", {})  # the cycle search's first stage, the same for a solve and its rerun
    X, T, lam, drift, allowed, why, closure, calls, det = by_rows(memo, ("5.9 cycle", rtol), (eps,),
                                                    lambda e: _scaled(e, rtol, tally, starts))
    why = np.asarray(why, dtype=object)
    small = eps <= RELAX_EPS
    if small.any():
        tally.invariant("Liouville (ln det M - int div)", np.where(small, drift, 0.0), allowed)
    tally.info["closure"] = np.where(small, closure, None)
    tally.info["cycle_evaluations"], tally.info["det_M"] = np.where(small, calls, None), np.where(small, det, None)
    tally.info["method_note"] = np.where(small, None, "LSODA in the slow time tau/eps: stiff relaxation oscillation")
    claim = exercise.tol_factor * rtol
    failed = [(why == w, w) for w in sorted(set(why[why != ""]))]
    failed.append((~(np.abs(drift) <= allowed), "the invariant 'Liouville (ln det M - int div)' drifts by more than "
                   "the claim: the integration is not to be trusted"))
    values = {"A": X / np.sqrt(beta), "omega": 2.0 * math.pi * omega0 / T, "lambda_lc": mu * lam}
    return {o: Column(values[o], rel=claim, failed=failed) for o in outputs}
