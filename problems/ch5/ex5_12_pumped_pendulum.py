"""5.12 Pendulum pumped by vertical vibration of its pivot: threshold, growth, stationary swing.

Analytic (reduced equations near Omega = 2 omega0): the pivot modulates the stiffness, omega0^2 (1 - mu cos Omega t)
with mu = a Omega^2/g; for theta = Re[A e^{i Omega t/2}] the coupling of A to A* is eps = mu omega0^2/(2 Omega) = a
Omega/(2 l), and with xi = Omega/2 - omega0 small swings grow at -delta + sqrt(eps^2 - xi^2); the threshold is a_th =
(2 l/Omega) sqrt(delta^2 + xi^2). The cubic term of sin theta lowers the swing's own frequency to omega0 (1 - A^2/16),
so the detuning seen by a swing of amplitude A is xi + omega0 A^2/16; the growth stops where (xi + omega0 A^2/16)^2 +
delta^2 = eps^2, and the branch a small swing grows into (above threshold) is theta_st^2 = 16 (sqrt(eps^2 - delta^2) -
xi)/omega0. Where the theory puts a below its threshold, theta_st = 0 has no relative error to give (expected error 0):
it is compared as a zero, so both methods must put a on the same side of the threshold.

Numeric: a_th and growth from the monodromy matrix of the linearized equation over one pivot period (q = exp(-delta t)
y leaves an even Hill equation: half a period of DOP853); a_th is the root in a of det(M + I), bracketed by a scan up
from a = 1e-4 l in factors of 2 to 4 l at most (at |xi| = 0.3 omega0 the exact threshold lies at 0.64 l, well above the
leading-order 0.43 l, and the zone reaches past 2.3 l: a factor-2 scan cannot step over it). Every output is written
once over arrays of variants (``small_swings``, the swing in ``_swing``): a one-point solve is its batch of one.
theta_st: the stationary swing has period 4 pi/Omega and theta(t + 2 pi/Omega) = -theta(t), so its start z is a fixed
point of the half-map H(z) = -phi_{2 pi/Omega}(z). From the bifurcation at a_th (H's multiplier +1, eigenvector e) the
branch of fixed points is followed by its amplitude s = |z| in (theta, theta'/omega0) with (z, a) as unknowns
(solvers.numerics.branch, every variant in lock-step with its own step; in the pivot's phase Omega t, so that every
variant's period is 2 pi; a carried as a constant third state, so that the variational equations give d/da with d/dz):
for Omega < 2 omega0 the bifurcation is subcritical and the branch first runs down in a to a fold near eps = delta,
then up through the given a. The branch is only a path to a guess (rtol 1e-8); z is then refined by Newton at fixed a
(its last steps at the full rtol), both multipliers of H are checked inside the unit circle, and the largest |theta| on
the orbit is found by events on theta' = 0. Its claim, 100 rtol, is times kappa, the fixed point's conditioning |(I + D
phi)^-1| (in ``_swing``): near the threshold the swing's multiplier nears +1 (critical slowing down) and a flow error
moves z by 1/(1 - multiplier) of itself (1.3e4 at growth 5.4e-5/s, mech sweep 5.12 --l 0.49:0.51:200). The declared
motion (``motion``) is the swing's full period, two pivot periods from z.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure, Tally
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


def _arrays(P):
    return (np.asarray(P[k], dtype=float) for k in ("l", "g", "delta", "a", "Omega"))


def _lo_of(l, g, delta, a, Omega, eps_factor=1.0, xi_shift=0.0):
    """``_lo`` at arrays of variants, with eps and the detuning moved as ``expected_error`` asks."""
    w0 = np.sqrt(g / l)
    return _lo(w0, delta, a * Omega / (2 * l) * eps_factor, Omega / 2 - w0 + xi_shift, l, Omega)


@exercise.analytic
def analytic(P):
    """The leading-order answers over arrays of variants (``_lo``)."""
    from mech.solvers.numerics.batch import Column

    return {k: Column(v) for k, v in _lo_of(*_arrays(P)).items()}


def _small_swing_allowances(l, g, delta, a, Omega):
    """{"a_th": rel, "growth": (rel, abs)} arrays for the small swings, whose equation is 5.11's (mu = a Omega^2/g,
    omega0^2 = g/l, the response at Omega/2): twice the first zone's next order (solvers.mechanics.mathieu)
    plus the floors measured for 5.11 (growth 0.002 k^2 of the rate, a_th 0.005 mu_th^2), k = mu/2."""
    w0 = np.sqrt(g / l)
    mu = a * Omega**2 / g
    lo = _lo(w0, delta, a * Omega / (2 * l), Omega / 2 - w0, l, Omega)
    nx = first_zone_next_order(w0, delta, mu, Omega / 2.0, edges=False)
    k2 = (mu / 2.0) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        g0 = lo["growth"]
        g_abs = 2.0 * np.abs(nx["growth"] - g0) + 0.002 * k2 * (nx["growth"] + delta)
        a_nx = nx["mu_th"] * g / Omega**2
        mt = lo["a_th"] * Omega**2 / g  # the threshold as a modulation depth
        return {"a_th": np.where(lo["a_th"] > 0, 2.0 * np.abs(a_nx / lo["a_th"] - 1.0) + 0.005 * mt**2, np.nan),
                "growth": (np.where(g0 != 0, g_abs / np.abs(g0), 0.0), np.where(g0 != 0, np.nan, g_abs))}


@exercise.expected_error
def expected_error(P):
    """Allowances over arrays of variants, one line each:
      a_th, growth  twice the next order of the first parametric zone (``_small_swing_allowances``, shared
                    with 5.11: measured there against Floquet at 66 points) plus its measured floor;
      theta_st      a bound: the largest change of the leading-order swing when eps moves by its
                    neglected O(xi/omega0, mu^2, theta^2) and the detuning by the zone's shift
                    mu^2 omega0/64 + delta^2/(2 omega0) + xi^2/omega0 + omega0 A^4/256 (the backbone's next term).
    A zero theta_st (below the theory's threshold) is compared as a zero (``theory_range``: not near it)."""
    l, g, delta, a, Omega = _arrays(P)
    w0 = np.sqrt(g / l)
    xi = Omega / 2 - w0
    mu = a * Omega**2 / g
    base = _lo_of(l, g, delta, a, Omega)["theta_st"]
    A2 = base**2
    r = np.abs(xi) / w0 + mu**2 / 16.0 + A2 / 8.0
    s = mu**2 * w0 / 64.0 + 0.5 * delta**2 / w0 + xi**2 / w0 + w0 * A2**2 / 256.0
    signs = np.array([[-1.0, -1.0, 1.0, 1.0], [-1.0, 1.0, -1.0, 1.0]])[..., None]  # (eps, detuning) moved
    alt = _lo_of(l, g, delta, a, Omega, 1 + signs[0] * r, signs[1] * s)["theta_st"]  # the four at once
    worst = np.abs(alt - base).max(axis=0)
    small = _small_swing_allowances(l, g, delta, a, Omega)
    with np.errstate(divide="ignore", invalid="ignore"):
        theta = np.where(base != 0, worst / base, 0.0)
    return {"a_th": small["a_th"], "growth": small["growth"], "theta_st": theta}


@exercise.theory_range
def theory_range(P):
    """The reduced equations expand in the pump's Mathieu parameter k = a Omega^2/(2 g), delta/omega0, the
    detuning |Omega/2 - omega0|/omega0 and, for the swing, its amplitude theta_st^2/8 and the threshold's own
    error over a's distance from it (within it the theory cannot tell whether a swing exists)."""
    l, g, delta, a, Omega = _arrays(P)
    w0 = np.sqrt(g / l)
    lo = _lo_of(l, g, delta, a, Omega)
    with np.errstate(divide="ignore", invalid="ignore"):
        near = _small_swing_allowances(l, g, delta, a, Omega)["a_th"] / np.abs(a / lo["a_th"] - 1.0)
    cands = np.stack(np.broadcast_arrays(a * Omega**2 / (2 * g), delta / w0, np.abs(Omega / 2 - w0) / w0,
                                         lo["theta_st"] ** 2 / 8.0, np.nan_to_num(near, nan=0.0, posinf=np.inf)))
    names = np.array(["a Omega^2/(2 g)", "delta/omega0", "|Omega/2 - omega0|/omega0", "theta_st^2/8",
                      "the threshold's error over |a/a_th - 1|"], dtype=object)
    small = (names[np.argmax(cands[:3], axis=0)], cands[:3].max(axis=0))
    return {"a_th": small, "growth": small,
            "theta_st": (names[np.argmax(cands, axis=0)], cands.max(axis=0))}


def _trace(l, g, delta, a, Omega, rtol, tally):
    """(tr M_y, |Wronskian drift|) of the linearization about theta = 0 over 2 pi/Omega (theta = exp(-delta t)
    y) at N variants at once: in the time s = Omega t every pivot period is 2 pi, so all integrate
    y'' + ((g/l - delta^2)/Omega^2 - (a/l) cos s) y = 0 over the same half period [0, pi]."""
    c0, c1 = (g / l - delta**2) / Omega**2, a / l
    (y1, y1p, y2, y2p), runs = even_hill_half(c0, -c1, math.cos, math.pi, rtol=rtol, vscale=np.sqrt(g / l) / Omega,
                                              integrator=tally.integrator)
    for r in runs:
        tally.record(r)
    return 2.0 * (y1 * y2p + y1p * y2), np.abs(y1 * y2p - y1p * y2 - 1.0)


def _growth(tr, delta, Omega, rtol):
    """(growth rate, its absolute error) from tr M_y: the largest |multiplier| exp(-delta T) (|tr| + (tr^2 -
    4)^(1/2))/2 (1 on the unit circle), its error the noise of tr amplified near |tr| = 2."""
    T, disc = 2.0 * math.pi / Omega, tr * tr - 4.0
    lam = np.where(disc > 0, 0.5 * (np.abs(tr) + np.sqrt(np.maximum(disc, 0.0))), 1.0)
    noise = 10.0 * rtol
    amplify = 1.0 + np.abs(tr) / np.sqrt(np.maximum(disc, noise))
    return np.log(np.exp(-delta * T) * lam) / T, noise * amplify / T


def _threshold(l, g, delta, Omega, rtol, tally):
    """a_th at N variants, the root of P(idx, a) = det(M + I) = 1 + exp(-delta T) tr M_y + exp(-2 delta T): the
    scan up from 1e-4 l in factors of 2 to a sign change, then the root (Illinois), its claim from the slope.
    (a_th, rel, no root, not converged, the largest Wronskian drift of each variant)."""
    from mech.solvers.numerics.batch import illinois, scan_up

    n = l.size
    drift = np.zeros(n)
    damp = np.exp(-delta * 2.0 * math.pi / Omega)

    def P(idx, a):
        tr, w = _trace(l[idx], g[idx], delta[idx], a, Omega[idx], rtol, tally)
        drift[idx] = np.maximum(drift[idx], w)
        return 1.0 + damp[idx] * tr + damp[idx] ** 2

    noise = 10.0 * rtol
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
    return a_th, rel, no_root, ~conv, drift


NO_ROOT = "no pivot amplitude below 4 l brings a multiplier to -1"
UNCONVERGED = "the root search for the threshold did not converge"
UNDECIDED = "a is within the threshold's own error of a_th: whether a stationary swing grows is not decided"


@exercise.motion
def motion(p, z=None):
    """One full period of the stationary swing from z: two pivot periods, the second from where the first
    ends (the half-map's symmetry makes it the first's mirror, theta -> -theta), with the turning points
    (theta' = 0) of each.  z (theta, theta') by default the swing's start the route finds at p (``_swing``):
    at rest below threshold."""
    from mech.problems.motion import Motion

    z = _start(p) if z is None else z
    g, l, W, d2, a = p.g, p.l, p.Omega, 2.0 * p.delta, p.a

    def f(t, y):
        return np.array([y[1], -d2 * y[1] - (g - a * W * W * math.cos(W * t)) / l * math.sin(y[0])])

    Tp = 2.0 * math.pi / W
    m = Motion(f, [float(x) for x in z], (0.0, Tp), y_size=[1.0, math.sqrt(g / l)])
    turns = {"events": [Event(lambda t, y: y[1], terminal=False, name="theta' = 0")]}
    return m.starting(options=turns,
                      then=lambda path: m.starting(y0=path.y_end, span=(Tp, 2.0 * Tp), options=turns))


def _start(p):
    """The stationary swing's start (theta, theta') at the one point p, by the route at its default rtol."""
    P = {k: np.array([float(p[k])]) for k in ("l", "g", "delta", "a", "Omega")}
    small = small_swings(P, (rtol := exercise.default_rtol), ("growth", "a_th"), tally=(tally := Tally()))
    if not small["growth"].value[0] > 0.0:
        return (0.0, 0.0)
    _, why, z, _ = _swing(*_arrays(P), small["a_th"].value, rtol, tally)
    if why[0] is not None:
        raise NumericFailure(why[0])
    return tuple(z[:, 0])


def _partials(c, c2, stiff, theta):
    """The partial derivatives of v' = -c2 v - (kg - k cos s) sin theta (``_flow``) in theta, v and k, with
    stiff = kg - k cos s and c = cos s (the declaration's Jacobian check reads them too: ``jacobian``)."""
    return -stiff * np.cos(theta), -c2, c * np.sin(theta)


def jacobian(p):
    """The Jacobian of the motion's rates (theta', theta'') in SI, from ``_partials`` in the phase s = Omega t:
    d theta''/d theta = Omega^2 d v'/d theta, d theta''/d theta' = Omega d v'/d v."""
    W = p.Omega

    def jac(t, y):
        c = math.cos(W * t)
        d_theta, d_v, _ = _partials(c, 2.0 * p.delta / W, p.g / (p.l * W * W) - p.a / p.l * c, y[0])
        return np.array([[0.0, 1.0], [W * W * float(d_theta), W * d_v]])

    return jac


def _flow(c2, kg, ksc, vsc, z, k, rtol, tally, variations=True, events=()):
    """The pendulum over one pivot period at N variants at once, in its phase s = Omega t (every period is
    2 pi): theta, v = dtheta/ds and k = a/l (a constant state, so that the variations give d/dk with d/dz),
        v' = -c2 v - (kg - k cos s) sin theta,   c2 = 2 delta/Omega,  kg = g/(l Omega^2),
    with the 3 x 3 variations (row-major) where asked.  ``ksc``, ``vsc``: the sizes of k and v (atol).
    (the integration, its end states (12 or 3, N), NaN where a variant failed)."""
    from mech.solvers.numerics.batch import integrate_batch

    m, nv = k.size, (12 if variations else 3)

    def rhs(s, y):
        c = math.cos(s)
        stiff, sn = kg - y[2] * c, np.sin(y[0])
        out = np.zeros_like(y)
        out[0], out[1] = y[1], -c2 * y[1] - stiff * sn
        if variations:
            P, D = y[3:].reshape(3, 3, -1), out[3:].reshape(3, 3, -1)
            d_theta, d_v, d_k = _partials(c, c2, stiff, y[0])
            D[0] = P[1]
            D[1] = d_theta * P[0] + d_v * P[1] + d_k * P[2]
        return out

    y0 = np.zeros((nv, m))
    y0[0], y0[1], y0[2] = z[0], z[1], k
    size = np.stack([np.ones(m), vsc, ksc])
    if variations:
        y0[3::4] = 1.0
        size = np.concatenate([size, (size[:, None] / size[None, :]).reshape(9, m)])
    with np.errstate(invalid="ignore", over="ignore"):
        res = integrate_batch(rhs, (0.0, 2.0 * math.pi), y0, rtol=rtol, atol=rtol * 1e-3 * size, events=events,
                              on_failure="mark")
    tally.record(res)
    y = res.y_end.copy()
    y[:, res.failed] = np.nan
    return res, y


def _swing(l, g, delta, a, Omega, a_th, rtol, tally):
    """(theta_st, why each failed (None: it did not), the swing's start (theta, theta') (2, N), kappa) at N variants
    above threshold (kappa: the fixed point's conditioning): z, the swing's start, is a fixed point of the
    half-map H(z) = -phi_{2 pi/Omega}(z), followed from the bifurcation at a_th (H's multiplier +1, eigenvector e)
    by its amplitude with (z, a) as unknowns (solvers.numerics.branch: a path to a guess at 1e-8), refined by
    Newton at the given a (its last steps at rtol), both multipliers of H checked inside the unit circle, then the
    largest |theta| by events on theta' = 0."""
    from mech.solvers.numerics.batch import BatchEvent

    N = l.size
    c2, kg, vsc = 2.0 * delta / Omega, g / (l * Omega**2), np.sqrt(g / l) / Omega
    kth, kt = a_th / l, a / l
    scale = np.stack([np.ones(N), vsc])  # (theta, theta'/omega0): the amplitude s = |z / scale|
    crude = max(rtol, 1e-8)  # the branch is only a path to a guess for Newton at the given a
    why = np.full(N, None, dtype=object)

    def flow(idx, z, k, tol):
        y = _flow(c2[idx], kg[idx], kth[idx], vsc[idx], z, k, tol, tally)[1]
        return z + y[:2], np.eye(2)[:, :, None] + y[3:].reshape(3, 3, -1)[:2, :2], y[3:].reshape(3, 3, -1)[:2, 2]

    _, J0, _ = flow(np.arange(N), np.zeros((2, N)), kth, crude)
    Ms = (J0 - np.eye(2)[:, :, None]) * scale[None, :, :] / scale[:, None, :]  # M in (theta, theta'/omega0)
    cand = np.stack([np.stack([Ms[0, 1], -1.0 - Ms[0, 0]]), np.stack([-1.0 - Ms[1, 1], Ms[1, 0]])])
    norms = np.sqrt((cand**2).sum(axis=1))
    e = np.where(norms[0] >= norms[1], cand[0] / norms[0], cand[1] / norms[1])  # M's eigenvector for -1
    corrector = lambda idx, z, k, s: on_branch(lambda i, zz, kk: flow(i, zz, kk, crude), idx, z, k, s,  # noqa
                                               scale, crude, kth, 10.0 * np.maximum(kth, kt))
    (zc, kc), (zn, kn), (tries, steps), lost = follow(corrector, e * scale, kth, kt)
    for k in np.flatnonzero(lost != None):  # noqa: E711
        why[k] = f"the branch of stationary swings: {lost[k]} (a swing over the top?)"
    tally.info["continuation_tries"], tally.info["continuation_steps"] = tries.astype(float), steps.astype(float)
    with np.errstate(invalid="ignore", divide="ignore"):  # from the bifurcation itself (zc = 0): a - a_th ~ s^2
        frac = np.where(kn != kc, (kt - kc) / (kn - kc), 1.0)
        z = zc + np.where((zc == 0.0).all(axis=0), np.sqrt(np.abs(frac)), frac) * (zn - zc)
    go = np.flatnonzero(why == None)  # noqa: E711
    theta, start, kappa = np.full(N, np.nan), np.full((2, N), np.nan), np.ones(N)
    if go.size == 0:
        return theta, why, start, kappa
    z, ok = newton(lambda i, zz, tol: flow(go[i], zz, kt[go[i]], tol)[:2], z[:, go], scale[:, go], crude, rtol)
    why[go[~ok]] = "Newton's method for the stationary swing did not converge"
    go, z = go[ok], z[:, ok]
    J = flow(go, z, kt[go], rtol)[1]
    Ms = (J - np.eye(2)[:, :, None]) * scale[None, :, go] / scale[:, None, go]
    mult, stable, double = _half_map_moduli(Ms, -2.0 * math.pi * c2[go], rtol)
    J = np.eye(2)[:, :, None] + Ms  # z = -phi(z) moves by J^-1 times the flow's error: kappa >= |J^-1| (adj/det)
    kappa[go] = np.sqrt((J**2).sum(axis=(0, 1))) / np.abs(J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0])
    tally.info["swing_multiplier_max"] = np.full(N, None, dtype=object)
    tally.info["swing_multiplier_max"][go] = mult.max(axis=0)
    why[go[double]] = ("the swing's half-map is at a double multiplier (tr^2 - 4 det within its rounding): "
                       "its stability cannot be decided")
    why[go[~double & ~stable]] = "the swing found is unstable: not the one a small swing grows into"
    turns = [BatchEvent(lambda s, y: y[1], direction=d, name="theta' = 0") for d in (-1.0, 1.0)]
    res, _ = _flow(c2[go], kg[go], kth[go], vsc[go], z, kt[go], rtol, tally, variations=False, events=turns)
    tops = np.abs(z[0])
    for ye in res.y_events:  # the turning points over the first pivot period (the second mirrors it)
        tops = np.fmax(tops, np.abs(ye[0]))
    theta[go] = np.where(res.failed, np.nan, tops)
    why[go[res.failed]] = "the integration of the swing failed"
    start[0, go], start[1, go] = z[0], z[1] * Omega[go]  # theta' = Omega dtheta/ds
    return theta, why, start, kappa


def _half_map_moduli(M, lndet, rtol):
    """(|multipliers| (2, N) of the half-maps -phi over one pivot period, M = D phi (2, 2, N); stable;
    undecided) at N variants.  det M = exp(lndet), lndet = -2 delta T (Liouville: the divergence is
    constant), so a complex pair (tr^2 < 4 det, an elliptic swing) lies inside the unit circle exactly when
    delta > 0, even where rounding leaves its moduli at 1 (delta = 1e-300 was refused as "too weak for
    double precision"); a real pair by its own values; a double one within M's rounding is undecided."""
    det, tr = np.exp(lndet), M[0, 0] + M[1, 1]
    disc = tr * tr - 4.0 * det
    slack = 100.0 * rtol * (np.abs(tr) + 1.0) * np.abs(M).max(axis=(0, 1))  # M to ~rtol
    cplx = disc < -slack
    root = np.sqrt(np.maximum(tr * tr - 4.0 * (M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]), 0.0))
    mult = np.where(cplx, np.sqrt(det), np.abs(np.stack([tr + root, tr - root]) / 2.0))
    stable = np.where(cplx, lndet < 0.0, mult.max(axis=0) < 1.0)
    return mult, stable, ~cplx & (disc <= slack)


# -- the small swings over many variants at once (a one-point solve is the batch of one) ------------------

@exercise.batched(("growth", "a_th", "theta_st"), boundaries={"a": ("a_th", "leading-order threshold a = a_th(Ω)")})
def small_swings(P, rtol, outputs, memo=None, tally=None):
    """growth, a_th and theta_st at N variants at once (``_trace``; a_th once per distinct (l, g, delta, Omega),
    kept in ``memo`` across a sweep's chunks and a solve's rerun; the stationary swing where the small swings
    grow, ``_swing``, else 0 exactly).  The Wronskian's drift goes to ``tally`` and fails the outputs it
    exceeds."""
    from mech.solvers.numerics.batch import Column, by_rows

    l, g, delta, a, Omega = _arrays(P)
    memo = {} if memo is None else memo
    tally = Tally() if tally is None else tally
    allowed = exercise.tol_factor * rtol
    drifted = f"the Wronskian drifted by more than {allowed:.3g}"
    out = {}
    if "theta_st" in outputs:
        outputs = set(outputs) | {"growth", "a_th"}
    if "growth" in outputs:
        tr, wronski = _trace(l, g, delta, a, Omega, rtol, tally)
        tally.invariant("Wronskian", wronski)
        growth, err = _growth(tr, delta, Omega, rtol)
        out["growth"] = Column(growth, rel=100 * rtol, abs=err, failed=[(wronski > allowed, drifted)])
    if "a_th" in outputs:
        v, rel, no_root, unconv, drift = by_rows(memo, ("a_th", rtol), (l, g, delta, Omega),
                                                 lambda *c: _threshold(*c, rtol, tally))
        tally.invariant("Wronskian", drift)
        out["a_th"] = Column(v, rel=rel, failed=[(no_root, NO_ROOT), (unconv, UNCONVERGED), (drift > allowed, drifted)])
    if "theta_st" in outputs:
        out["theta_st"] = _swing_column(l, g, delta, a, Omega, out, rtol, tally)
    return out


def _swing_column(l, g, delta, a, Omega, out, rtol, tally):
    """theta_st where the small swings grow (``_swing``, claimed to 100 rtol kappa), 0 exactly where they decay;
    failed where growth, a_th or the swing failed, refused where a is within a_th's claim of it (undecided)."""
    from mech.solvers.numerics.batch import Column

    grow = (growth := out["growth"]).value > 0.0
    pairs = list(growth.failed) + [(m & grow, r) for m, r in out["a_th"].failed]
    with np.errstate(invalid="ignore", divide="ignore"):  # a within a_th's own claim of it
        pairs.append((np.abs(a / out["a_th"].value - 1.0) <= out["a_th"].rel, UNDECIDED))
    up = np.flatnonzero(grow & ~growth.mask("failed") & ~out["a_th"].mask("failed") & ~pairs[-1][0])
    value, rel = np.zeros(l.size), np.zeros(l.size)
    why = np.full(l.size, None, dtype=object)
    if up.size:
        value[up], why[up], _, kappa = _swing(*(x[up] for x in (l, g, delta, a, Omega, out["a_th"].value)), rtol, tally)
        rel[up] = exercise.tol_factor * rtol * np.maximum(1.0, kappa)
    pairs += [(why == r, r) for r in set(why[why != None])]  # noqa: E711
    return Column(value, rel=rel, abs=0.0, failed=pairs)
