"""5.12 Pendulum pumped by vertical vibration of its pivot: threshold, growth, stationary swing.

Analytic (reduced equations near Omega = 2 omega0): the pivot modulates the
stiffness, omega0^2 (1 - mu cos Omega t) with mu = a Omega^2/g; for
theta = Re[A e^{i Omega t/2}] the coupling of A to A* is
eps = mu omega0^2/(2 Omega) = a Omega/(2 l), and with xi = Omega/2 - omega0
small swings grow at -delta + sqrt(eps^2 - xi^2); the threshold is
a_th = (2 l/Omega) sqrt(delta^2 + xi^2).  The cubic term of sin theta lowers the
swing's own frequency to omega0 (1 - A^2/16), so the detuning seen by a
swing of amplitude A is xi + omega0 A^2/16; the growth stops where
(xi + omega0 A^2/16)^2 + delta^2 = eps^2, and the branch a small swing grows
into (above threshold) is theta_st^2 = 16 (sqrt(eps^2 - delta^2) - xi)/omega0.
Where the theory puts a below its threshold, theta_st = 0 has no relative
error to give (expected error 0): it is compared as a zero, so both methods
must put a on the same side of the threshold.

Numeric: a_th and growth from the monodromy matrix of the linearized equation over one pivot period
(q = exp(-delta t) y leaves an even Hill equation: half a period of DOP853); a_th is the root in a of
det(M + I), bracketed by a scan up from a = 1e-4 l in factors of 2 to 4 l at most (at |xi| = 0.3 omega0
the exact threshold lies at 0.64 l, well above the leading-order 0.43 l, and the zone reaches past 2.3 l:
a factor-2 scan cannot step over it).  The one-point route is the batched one (``numeric_batch``) at one
point, with the Run's integrator.  theta_st: the stationary swing has period 4 pi/Omega and
theta(t + 2 pi/Omega) = -theta(t), so its start z is a fixed point of the half-map
H(z) = -phi_{2 pi/Omega}(z).  From the bifurcation at a_th (H's multiplier +1, eigenvector e) the branch
of fixed points is followed by its amplitude s = |z| in (theta, theta'/omega0) with (z, a) as unknowns
(solvers.numerics.branch; a carried as a constant third state, so that the variational equations give
d/da with d/dz): for Omega < 2 omega0 the bifurcation is subcritical and the branch first runs down in a
to a fold near eps = delta, then up through the given a.  The branch is only a path to a guess (rtol
1e-8); z is then refined by Newton at fixed a (its last steps at the full rtol), both multipliers of H are
checked inside the unit circle, and the largest |theta| on the orbit is found by events on theta' = 0.
The declared motion (``motion``) is the swing's full period, two pivot periods from z.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.numerics.branch import follow, newton, on_branch
from mech.solvers.mechanics.floquet import even_hill_half
from mech.solvers.mechanics.mathieu import first_zone_next_order
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "5.12",
    formulas=[
        "ε = a Ω/(2 l),  ξ = Ω/2 - ω₀,  ω₀ = (g/l)^(1/2)",
        "a_th = (2 l/Ω) (δ² + ξ²)^(1/2)",
        "growth = -δ + (ε² - ξ²)^(1/2)  (−δ for |ξ| ≥ ε)",
        "θ_st² = 16 ((ε² - δ²)^(1/2) - ξ)/ω₀ above threshold, else 0",
    ],
    leading_order=("a_th", "growth", "theta_st"),
    default_rtol=1e-11,
    min_rtol=1e-12,
    # above threshold: one full period (two pivot periods) of the stationary swing the small swing grows into
    states=[("theta", "rad"), ("theta_dot", "rad/s")],
)

MAX_DETUNING = 0.3
MAX_DAMPING = 0.2
MAX_AMPLITUDE = 0.1


exercise.declare_limits(
    f"|Omega/2 - omega0| <= {MAX_DETUNING:g} omega0, omega0 = (g/l)^(1/2)",
    f"delta <= {MAX_DAMPING:g} omega0: weak damping",
    f"a <= {MAX_AMPLITUDE:g} l",
)


@exercise.constraint
def constraint(p):
    w0 = math.sqrt(p.g / p.l)
    if abs(p.Omega / 2 - w0) > MAX_DETUNING * w0:
        return (f"Omega = {p.Omega:g} rad/s is not near 2 omega0 = {2 * w0:.6g} rad/s: the exercise needs "
                f"|Omega/2 - omega0| <= {MAX_DETUNING:g} omega0")
    if p.delta > MAX_DAMPING * w0:
        return f"delta = {p.delta:g} 1/s is not weak damping: the exercise needs delta <= {MAX_DAMPING:g} omega0"
    if p.a > MAX_AMPLITUDE * p.l:
        return f"a = {p.a:g} m is not small against l = {p.l:g} m: the exercise needs a <= {MAX_AMPLITUDE:g} l"


def _lo(w0, delta, eps, xi, l, Omega):
    """The leading-order answers, over arrays of points (or at one, as 0-d arrays)."""
    s2 = eps * eps - xi * xi
    growth = np.where(s2 > 0, -delta + np.sqrt(np.maximum(s2, 0.0)), -delta)
    theta2 = np.where(growth > 0, 16.0 * (np.sqrt(np.maximum(eps * eps - delta * delta, 0.0)) - xi) / w0, 0.0)
    return {"a_th": 2.0 * l * np.hypot(delta, xi) / Omega, "growth": growth,
            "theta_st": np.sqrt(np.maximum(theta2, 0.0))}


def _lo_at(p, eps_factor=1.0, xi_shift=0.0):
    """``_lo`` at the point p (floats), with eps and the detuning moved as ``expected_error`` asks."""
    w0 = math.sqrt(p.g / p.l)
    lo = _lo(w0, p.delta, p.a * p.Omega / (2 * p.l) * eps_factor, p.Omega / 2 - w0 + xi_shift, p.l, p.Omega)
    return {k: float(v) for k, v in lo.items()}


@exercise.analytic
def analytic(p):
    return _lo_at(p)


def _small_swing_allowances(l, g, delta, a, Omega):
    """{"a_th": rel, "growth": (rel, abs)} arrays for the small swings, whose equation is 5.11's (mu = a Omega^2/g,
    omega0^2 = g/l, the response at Omega/2): twice the first zone's next order (solvers.mechanics.mathieu)
    plus the floors measured for 5.11 (growth 0.002 k^2 of the rate, a_th 0.005 mu_th^2), k = mu/2."""
    w0 = np.sqrt(g / l)
    mu = a * Omega**2 / g
    lo = _lo(w0, delta, a * Omega / (2 * l), Omega / 2 - w0, l, Omega)
    nx = first_zone_next_order(w0, delta, mu, Omega / 2.0)
    k2 = (mu / 2.0) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        g0 = lo["growth"]
        g_abs = 2.0 * np.abs(nx["growth"] - g0) + 0.002 * k2 * (nx["growth"] + delta)
        a_nx = nx["mu_th"] * g / Omega**2
        mt = lo["a_th"] * Omega**2 / g  # the threshold as a modulation depth
        return {"a_th": np.where(lo["a_th"] > 0, 2.0 * np.abs(a_nx / lo["a_th"] - 1.0) + 0.005 * mt**2, np.nan),
                "growth": (np.where(g0 != 0, g_abs / np.abs(g0), 0.0), np.where(g0 != 0, np.nan, g_abs))}


@exercise.expected_error
def expected_error(p):
    """Allowances, one line each:
      a_th, growth  twice the next order of the first parametric zone (``_small_swing_allowances``, shared
                    with 5.11: measured there against Floquet at 66 points) plus its measured floor;
      theta_st      a bound: the largest change of the leading-order swing when eps moves by its
                    neglected O(xi/omega0, mu^2, theta^2) and the detuning by the zone's shift
                    mu^2 omega0/64 + delta^2/(2 omega0) + xi^2/omega0 + omega0 A^4/256 (the backbone's next term).
    A zero theta_st (below the theory's threshold) has no relative error to give: it is compared as a zero,
    so both methods must put a on the same side of the threshold."""
    w0, mu = math.sqrt(p.g / p.l), p.a * p.Omega**2 / p.g
    xi, base, worst = p.Omega / 2 - w0, _lo_at(p), 0.0
    A2 = base["theta_st"] ** 2
    r = abs(xi) / w0 + mu**2 / 16.0 + A2 / 8.0
    s = mu**2 * w0 / 64.0 + 0.5 * p.delta**2 / w0 + xi**2 / w0 + w0 * A2**2 / 256.0
    for se, sx in ((-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)):
        worst = max(worst, abs(_lo_at(p, 1 + se * r, sx * s)["theta_st"] - base["theta_st"]))
    small = _small_swing_allowances(*(np.float64(x) for x in (p.l, p.g, p.delta, p.a, p.Omega)))
    rel, ab = (float(x) for x in small["growth"])
    return {"a_th": float(small["a_th"]), "growth": rel if ab != ab else (rel, ab),
            "theta_st": worst / base["theta_st"] if base["theta_st"] != 0 else 0.0}


@exercise.theory_range
def theory_range(p):
    """The reduced equations expand in the pump's Mathieu parameter k = a Omega^2/(2 g), delta/omega0, the
    detuning |Omega/2 - omega0|/omega0 and, for the swing, its amplitude theta_st^2/8 (the largest is shown)."""
    w0 = math.sqrt(p.g / p.l)
    cands = [("a Omega^2/(2 g)", p.a * p.Omega**2 / (2 * p.g)), ("delta/omega0", p.delta / w0),
             ("|Omega/2 - omega0|/omega0", abs(p.Omega / 2 - w0) / w0)]
    big, th = max(cands, key=lambda c: c[1]), _lo_at(p)["theta_st"]
    return {"a_th": big, "growth": big, "theta_st": max(cands + [("theta_st^2/8", th * th / 8.0)], key=lambda c: c[1])}


def _trace(p, a, rtol, run):
    """tr M_y of the linearization about theta = 0 over 2 pi/Omega (theta = exp(-delta t) y), at this a."""
    T = 2.0 * math.pi / p.Omega
    g_l, aW2_l, W, d2 = p.g / p.l, a * p.Omega**2 / p.l, p.Omega, p.delta**2
    (y1, y1p, y2, y2p), traj = even_hill_half(
        lambda t: g_l - aW2_l * math.cos(W * t) - d2, T, rtol=rtol, vscale=math.sqrt(g_l),
        integrator=run.integrator,
    )
    run.record(traj)
    run.invariant("Wronskian", y1 * y2p - y1p * y2 - 1.0)
    return 2.0 * (y1 * y2p + y1p * y2)


def _growth(tr, delta, Omega, rtol):
    """(growth rate, its absolute error) from tr M_y: the largest |multiplier| exp(-delta T) (|tr| + (tr^2 -
    4)^(1/2))/2 (1 on the unit circle), its error the noise of tr amplified near |tr| = 2."""
    T, disc = 2.0 * math.pi / Omega, tr * tr - 4.0
    lam = np.where(disc > 0, 0.5 * (np.abs(tr) + np.sqrt(np.maximum(disc, 0.0))), 1.0)
    noise = 10.0 * rtol
    amplify = 1.0 + np.abs(tr) / np.sqrt(np.maximum(disc, noise))
    return np.log(np.exp(-delta * T) * lam) / T, noise * amplify / T


def _threshold(P, l, rtol):
    """a_th at N points, P(idx, a) = det(M + I) there: the scan up from 1e-4 l in factors of 2 to a sign
    change, then the root (Illinois), its claim from the slope.  (a_th, rel, no root, not converged)."""
    from mech.solvers.numerics.batch import illinois, scan_up

    n, noise = l.size, 10.0 * rtol
    lo, hi, flo, fhi, no_root = scan_up(P, np.zeros(n), 1e-4 * l, factor=2.0, limit=4.0 * l)
    first = np.isnan(flo)  # the bracket starts at a = 0
    idx0 = np.flatnonzero(first & ~no_root)
    if idx0.size:
        flo[idx0] = P(idx0, np.zeros(idx0.size))
    go = np.flatnonzero(~no_root)
    a_th, conv = np.full(n, np.nan), np.ones(n, dtype=bool)
    rel = np.full(n, 100.0 * rtol)
    if go.size:
        x, ok = illinois(lambda x, i: P(go[i], x), lo[go], hi[go], flo[go], fhi[go], xtol=1e-16 * l[go], rtol=1e-14)
        a_th[go], conv[go] = x, ok
        da = 1e-5 * x
        slope = np.abs(P(go, x + da)) / da
        with np.errstate(divide="ignore", invalid="ignore"):
            rel[go] = np.maximum(100.0 * rtol, noise / (slope * x))
    a_th[~conv] = np.nan
    return a_th, rel, no_root, ~conv


NO_ROOT = "no pivot amplitude below 4 l brings a multiplier to -1"
UNCONVERGED = "the root search for the threshold did not converge"


@exercise.numeric
def numeric(p, run):
    """The batched route (``numeric_batch``) at this one point, with the Run's integrator and records."""
    rtol = run.rtol
    g, err = _growth(_trace(p, p.a, rtol, run), p.delta, p.Omega, rtol)
    growth = float(g)
    run.claim("growth", rel=100 * rtol, abs=float(err))
    damp = math.exp(-p.delta * 2.0 * math.pi / p.Omega)

    def P(idx, a):  # det(M + I) = 1 + exp(-delta T) tr M_y + exp(-2 delta T)
        return np.array([1.0 + damp * _trace(p, float(a[0]), rtol, run) + damp * damp])

    a_th, rel, no_root, unconv = _threshold(P, np.array([p.l]), rtol)
    if no_root[0] or unconv[0]:
        raise NumericFailure(NO_ROOT if no_root[0] else UNCONVERGED)
    run.claim("a_th", rel=float(rel[0]))
    out = {"a_th": float(a_th[0]), "growth": growth}
    if growth <= 0.0:
        out["theta_st"] = 0.0
        run.claim("theta_st", rel=0.0, abs=0.0)
        return out
    out["theta_st"] = _stationary_swing(p, out["a_th"], run)
    return out


def _stiffness(p):
    """k(a, t) = (g - a Omega^2 cos Omega t)/l: gravity and the pivot's acceleration, per unit length."""
    g, l, W = p.g, p.l, p.Omega
    return lambda a, t: (g - a * W * W * math.cos(W * t)) / l


def _pendulum(p, a):
    """(f, jac): the damped pendulum with its pivot vibrated at the amplitude a, in theta and theta' (SI),
    theta'' = -2 delta theta' - (g - a Omega^2 cos Omega t)/l sin theta, and its Jacobian."""
    d2, k = 2.0 * p.delta, _stiffness(p)

    def f(t, y):
        return np.array([y[1], -d2 * y[1] - k(a, t) * math.sin(y[0])])

    def jac(t, y):
        return np.array([[0.0, 1.0], [-k(a, t) * math.cos(y[0]), -d2]])

    return f, jac


def _pendulum_in_a(p):
    """``_pendulum`` with a carried as a constant third state, so that one run of the variational equations
    gives d/dz and d/da of the half-map together (the branch's unknowns)."""
    d2, W, l, k = 2.0 * p.delta, p.Omega, p.l, _stiffness(p)

    def f3(t, y):
        return np.array([y[1], -d2 * y[1] - k(y[2], t) * math.sin(y[0]), 0.0])

    def jac3(t, y):
        c = math.cos(W * t)
        return np.array([[0.0, 1.0, 0.0],
                         [-k(y[2], t) * math.cos(y[0]), -d2, W * W * c / l * math.sin(y[0])],
                         [0.0, 0.0, 0.0]])

    return f3, jac3


def _pivot_period(p, a, z):
    """The pendulum at the pivot amplitude a from z over one pivot period 2 pi/Omega."""
    from mech.problems.motion import Motion

    f, _ = _pendulum(p, a)
    return Motion(f, z, (0.0, 2.0 * math.pi / p.Omega), y_size=[1.0, math.sqrt(p.g / p.l)])


@exercise.motion
def motion(p, z=(0.0, 0.0)):
    """One full period of the stationary swing from z (the solve finds it): two pivot periods, the second
    from where the first ends (the half-map's symmetry makes it the first's mirror, theta -> -theta), with
    the turning points (theta' = 0) of each.  By default at rest, the stationary state below threshold."""
    m = _pivot_period(p, p.a, list(z))
    Tp = m.span[1]
    turns = {"events": [Event(lambda t, y: y[1], terminal=False, name="theta' = 0")]}
    return m.starting(options=turns,
                      then=lambda path: m.starting(y0=path.y_end, span=(Tp, 2.0 * Tp), options=turns))


def _stationary_swing(p, a_th, run):
    rtol = run.rtol
    scale = [1.0, math.sqrt(p.g / p.l)]

    # the branch is only followed to bring Newton close to the swing at the given a: a looser
    # tolerance is enough for that (the final Newton at fixed a below uses the full rtol)
    crude = max(rtol, 1e-8)

    def residual(z, a, tol=crude):
        _, jac = _pendulum(p, a)
        end = run.follow(_pivot_period(p, a, z).with_variations(jac), rtol=tol, mark=False)
        y, M = end.y_end[:2], end.y_end[2:].reshape(2, 2)
        return z + y, np.eye(2) + M, M  # z - H(z), its Jacobian, and M

    # along the branch a is an unknown too: carried as a constant third state (``_pendulum_in_a``)
    f3, jac3 = _pendulum_in_a(p)
    half_map_in_a = _pivot_period(p, a_th, [0.0, 0.0]).starting(rhs=f3, y_size=[*scale, a_th])

    def residual_a(z, a):
        """z - H(z) at a, its Jacobian in z and its derivative in a."""
        end = run.follow(half_map_in_a.starting(y0=[z[0], z[1], a]).with_variations(jac3), rtol=crude,
                         mark=False)
        y, M = end.y_end[:3], end.y_end[3:].reshape(3, 3)
        return z + y[:2], np.eye(2) + M[:2, :2], M[:2, 2]

    # the critical direction at the bifurcation: M's eigenvector for the multiplier -1
    _, J0, M0 = residual(np.zeros(2), a_th)
    ev, vec = np.linalg.eig(M0)
    k = int(np.argmin(np.abs(ev + 1.0)))
    e = np.real(vec[:, k]) / np.array(scale)
    e /= np.linalg.norm(e)
    e_phys = e * np.array(scale)  # the branch leaves z = 0 along e; s = |z / scale| along it

    a_big = 10.0 * max(a_th, p.a)

    # For Omega < 2 omega0 the bifurcation is subcritical: the branch first runs down in a to a fold
    # near eps = delta (a sharp turn when delta is small) and then up through the given a (followed by its
    # amplitude, solvers.numerics.branch)
    target = p.a
    try:
        (z_cur, a_cur), (z_new, a_new), (tries, steps) = follow(
            lambda z, a, s: on_branch(residual_a, z, a, s, scale, crude, a_th, a_big), e_phys, a_th, target)
    except NumericFailure as exc:
        raise NumericFailure(f"the branch of stationary swings: {exc} (a swing over the top?)") from None
    run.info["continuation_tries"] = tries
    run.info["continuation_steps"] = steps
    # interpolate to the target and refine z at fixed a
    w = (target - a_cur) / (a_new - a_cur) if a_new != a_cur else 1.0
    z = z_cur + w * (z_new - z_cur)
    z = newton(lambda z, tol: residual(z, target, tol)[:2], z, scale, crude, rtol)
    if z is None:
        raise NumericFailure("Newton's method for the stationary swing did not converge")
    r, J, M = residual(z, target, rtol)
    mult, stable = _half_map_moduli(M, np.trace(_pendulum(p, target)[1](0.0, z)), 2 * math.pi / p.Omega, rtol)
    run.info["swing_multipliers_of_half_map"] = [float(m) for m in mult]
    if not stable:
        raise NumericFailure(f"the swing found is unstable (half-map multipliers {mult}): not the one a small swing grows into")
    # the swing's full period is the motion; its largest |theta|: the extrema on theta' = 0 over the first
    # pivot period (the second mirrors it)
    swing = run.follow(motion(p, z))
    ext = [abs(y[0]) for y in swing.legs[0].traj.y_events[0]] + [abs(z[0])]
    return float(max(ext))


def _half_map_moduli(M, div, Tp, rtol):
    """(|multipliers| of the half-map -phi over the pivot period Tp, M = D phi; stable).  The divergence
    ``div`` (-2 delta) is constant: det M = exp(div Tp) (Liouville), so a complex pair (tr^2 < 4 det, an
    elliptic swing) lies inside the unit circle exactly when div < 0, even where rounding leaves its moduli
    at 1 (delta = 1e-300 was refused as "too weak for double precision"); a real pair by its own values."""
    det, tr = math.exp(div * Tp), float(np.trace(M))
    disc, slack = tr * tr - 4.0 * det, 100.0 * rtol * (abs(tr) + 1.0) * float(np.max(np.abs(M)))  # M to ~rtol
    if disc < -slack:
        return np.full(2, math.sqrt(det)), div < 0.0
    if disc <= slack:
        raise NumericFailure(f"the swing's half-map is at a double multiplier (tr^2 - 4 det = {disc:.2g}, within "
                             "its rounding): its stability cannot be decided")
    mult = np.abs(np.linalg.eigvals(-M))
    return mult, bool(np.max(mult) < 1.0)


# -- charts: the small-swing growth rate over many points at once ----------------------------------------

def _arrays(P):
    return (np.asarray(P[k], dtype=float) for k in ("l", "g", "delta", "a", "Omega"))


def analytic_batch(P):
    """The analytic solver over arrays of points (tests hold it equal to ``analytic``)."""
    from mech.solvers.numerics.batch import Column

    l, g, delta, a, Omega = _arrays(P)
    w0 = np.sqrt(g / l)
    lo = _lo(w0, delta, a * Omega / (2 * l), Omega / 2 - w0, l, Omega)
    return {k: Column(v) for k, v in lo.items()}


def expected_error_batch(P):
    """``expected_error`` of the small-swing outputs over arrays of points."""
    return _small_swing_allowances(*_arrays(P))


def theory_range_batch(P):
    """``theory_range`` of the small-swing outputs over arrays of points."""
    l, g, delta, a, Omega = _arrays(P)
    w0 = np.sqrt(g / l)
    big = np.maximum(np.maximum(a * Omega**2 / (2 * g), delta / w0), np.abs(Omega / 2 - w0) / w0)
    label = "max(a Omega^2/(2 g), delta/omega0, |Omega/2 - omega0|/omega0)"
    return {"a_th": (label, big), "growth": (label, big)}


def _trace_batch(l, g, delta, a, Omega, rtol):
    """(tr M_y, |Wronskian drift|) of ``_trace``'s Hill equation at N points at once: in the time s = Omega t
    every pivot period is 2 pi, so all points integrate y'' + ((g/l - delta^2)/Omega^2 - (a/l) cos s) y = 0
    over the same half period [0, pi]."""
    from mech.solvers.mechanics.floquet import even_hill_half_batch

    c0, c1 = (g / l - delta**2) / Omega**2, a / l
    (y1, y1p, y2, y2p), _ = even_hill_half_batch(lambda s: c0 - c1 * math.cos(s), math.pi, Omega.size, rtol=rtol,
                                                  vscale=np.sqrt(g / l) / Omega)
    return 2.0 * (y1 * y2p + y1p * y2), np.abs(y1 * y2p - y1p * y2 - 1.0)


def _threshold_batch(l, g, delta, Omega, rtol):
    """``_threshold`` at N points with the batched trace; the largest Wronskian drift of each point kept."""
    n = Omega.size
    drift = np.zeros(n)
    damp = np.exp(-delta * 2.0 * math.pi / Omega)

    def P(idx, a):
        tr, w = _trace_batch(l[idx], g[idx], delta[idx], a, Omega[idx], rtol)
        drift[idx] = np.maximum(drift[idx], w)
        return 1.0 + damp[idx] * tr + damp[idx] ** 2

    return (*_threshold(P, l, rtol), drift)


@exercise.batched(("growth", "a_th"), analytic=analytic_batch, expected_error=expected_error_batch,
                  theory_range=theory_range_batch,
                  boundaries={"a": ("a_th", "leading-order threshold a = a_th(Ω)")})
def numeric_batch(P, rtol, outputs, memo=None):
    """growth and a_th at N points at once (``_trace_batch``; a_th once per distinct (l, g, delta, Omega), kept
    in ``memo`` across a sweep's chunks); the stationary swing (a continuation per point) has no batched route."""
    from mech.solvers.numerics.batch import Column, by_rows

    l, g, delta, a, Omega = _arrays(P)
    memo = {} if memo is None else memo
    allowed = exercise.tol_factor * rtol
    drifted = f"the Wronskian drifted by more than {allowed:.3g}"
    out = {}
    if "growth" in outputs:
        tr, wronski = _trace_batch(l, g, delta, a, Omega, rtol)
        growth, err = _growth(tr, delta, Omega, rtol)
        out["growth"] = Column(growth, rel=100 * rtol, abs=err, failed=[(wronski > allowed, drifted)])
    if "a_th" in outputs:
        v, rel, no_root, unconv, drift = by_rows(memo, ("a_th", rtol), (l, g, delta, Omega),
                                                 lambda *c: _threshold_batch(*c, rtol))
        out["a_th"] = Column(v, rel=rel, failed=[(no_root, NO_ROOT), (unconv, UNCONVERGED), (drift > allowed, drifted)])
    return out
