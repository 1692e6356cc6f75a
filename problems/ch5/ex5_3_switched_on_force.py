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
q' = omega (w cos wt - u sin wt) (``_rotating_rhs``, in sigma = omega t over
[0, 2 pi] so every variant's period is one span; no motion is declared, q(t1)
being the exact flow), with M - I
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
route is written once over arrays of variants (``numeric``: a one-point solve is
the batch of one; each variant's generator its own matrix in a stack).  The
phases omega t1, omega0 t1 are known in floats to u times themselves only, in
both methods: ``analytic_error`` and the claims carry it, and a phase beyond
1e15 rad is refused.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise

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


_U = 2.0**-53
MAX_PHASE = 1e15  # rad: beyond it the phase's round-off (u * phase) reaches a tenth of a radian


exercise.declare_limits(
    f"max(omega, omega0) t1 <= {MAX_PHASE:g} rad: the phase carries a digit in double precision",
)


@exercise.constraint
def constraint(p):
    phase = max(p.omega, p.omega0) * p.t1
    if phase > MAX_PHASE:
        return (f"the phase max(omega, omega0) t1 = {phase:.3g} rad carries no significant digit in double "
                f"precision (its round-off u * phase exceeds 0.1 rad; at most {MAX_PHASE:g} rad)")


def _closed(f, w0, d, w, t1):
    """The closed forms at one variant and their round-off: ({q_t, v_t, A_ss (None: infinite)}, {errors}).
    Round-off from the phases: exp(i omega t1) and exp(p t1) are evaluated at products rounded to
    u (omega t1), u (|p| t1), so each term moves by its size times that.  The stationary term's size is A_ss;
    the transient's is at most the state at t1 less the stationary motion, |q| + A_ss in position and
    (|q'| + omega A_ss)/omega0 from the velocity (its rates are at least omega0 in modulus for the fast part;
    a slow overdamped part shows in |q|).  Dividing |q'| by omega instead (as once here) made the bar ~1e185
    at omega = 6e-200 rad/s, where the drive is static."""
    q, v = _response(w0, d, w, t1)
    den = abs(complex((w0 - w) * (w0 + w), 2.0 * d * w))
    a_ss = None if den == 0 else abs(f) / den
    qa, va, sa = abs(f * q), abs(f * v), 0.0 if a_ss is None else a_ss
    size = qa + (va + w * sa) / w0 + 2.0 * sa
    free = w0 if d < w0 else w0 * w0 / (d + math.sqrt((d - w0) * (d + w0)))
    err = 8.0 * _U * (1.0 + (w + free) * t1) * size
    return {"q_t": f * q, "v_t": f * v, "A_ss": a_ss}, {"q_t": err, "v_t": err * max(w, w0), "A_ss": 4.0 * _U * sa}


def _arrays(P):
    return (np.asarray(P[k], dtype=float) for k in ("m", "omega0", "delta", "F0", "omega", "t1"))


@exercise.analytic
def analytic(P):
    """The divided-difference closed form (``_closed``, a scalar recursion run for each variant) over arrays,
    each value with its round-off."""
    from mech.solvers.numerics.batch import Column

    m, w0, d, F0, w, t1 = _arrays(P)
    cols = [np.ravel(x) for x in np.broadcast_arrays(F0 / m, w0, d, w, t1)]
    got = [_closed(*map(float, row)) for row in zip(*cols)]
    out = {}
    for name in ("q_t", "v_t", "A_ss"):
        vals = np.array([math.inf if g[0][name] is None else g[0][name] for g in got])
        out[name] = Column(vals, abs=np.array([g[1][name] for g in got]))
    out["A_ss"].undefined.append((np.isinf(out["A_ss"].value), UNDAMPED))
    return out


UNDAMPED = "undamped exact resonance: the amplitude grows without bound"


@exercise.analytic_error
def analytic_error(p):
    """The round-off of the closed forms at one point (``_closed``: the bars the analytic Columns carry)."""
    return _closed(p.F0 / p.m, p.omega0, p.delta, p.omega, p.t1)[1]


def _generator(w0, d, w, unit):
    """The equation of motion with the drive as a state of its own, in the time unit 1/unit and
    x = q unit^2 per unit force per mass: (x, x', C, S) with x'' = -a x - 2 b x' + C, C' = -c S, S' = c C
    (C = cos omega t, S = sin omega t): an autonomous linear system, one 4 x 4 matrix per variant."""
    a, b, c = (w0 / unit) ** 2, d / unit, w / unit
    G = np.zeros((np.size(w0), 4, 4))
    G[:, 0, 1], G[:, 1, 0], G[:, 1, 1], G[:, 1, 2], G[:, 2, 3], G[:, 3, 2] = 1.0, -a, -2.0 * b, 1.0, -c, c
    return G


def _rotating_rhs(d, w, det2):
    """The one-period map near resonance in exact variation-of-constants variables (u, w'), q = u cos wt +
    w' sin wt, in sigma = omega t over [0, 2 pi]: y = (d1, d2, xp), the deviations of the two unit columns
    from their start (M - I keeps its relative digits however nearly resonant) and the forced state from
    rest, per unit force per mass.  u' = -s G/omega, w' = c G/omega, G = cos wt - 2 delta q' - (w0^2 - w^2) q."""
    def rhs(sig, y):
        c, s = np.cos(sig), np.sin(sig)
        gu = 2.0 * d * w * s - det2 * c
        gw = -2.0 * d * w * c - det2 * s
        k = 1.0 / (w * w)  # 1/omega for the equation, 1/omega more for d/dsigma

        def apply(p, r):  # a @ (p, r), a = [[-s gu, -s gw], [c gu, c gw]]/omega
            lin = gu * p + gw * r
            return -s * lin * k, c * lin * k

        a1, b1 = apply(y[0] + 1.0, y[1])
        a2, b2 = apply(y[2], y[3] + 1.0)
        a3, b3 = apply(y[4], y[5])
        return np.array([a1, b1, a2, b2, a3 - s * c * k, b3 + c * c * k])

    return rhs


def _solve_orbits(i_minus_m, b, sig_mat, sig_b):
    """(I - M) x* = b for a stack of 2 x 2 maps, with x*'s error bound |(I - M)^-1| (sig_b + sig_M |x*|) and
    where I - M is singular to rounding (no unique orbit)."""
    singular = np.linalg.svd(i_minus_m, compute_uv=False)[:, -1] == 0.0
    safe = np.where(singular[:, None, None], np.eye(2), i_minus_m)
    inv = np.linalg.inv(safe)
    xs = np.einsum("kij,kj->ki", inv, b)
    dxs = np.einsum("kij,kj->ki", np.abs(inv), sig_b + np.einsum("kij,kj->ki", sig_mat, np.abs(xs)))
    return xs, dxs, singular


def _rotating_orbits(w0, d, w, rtol, tally):
    """Near resonance: the one-period map in variation-of-constants variables (``_rotating_rhs``) by DOP853 for
    every variant together, in 8 legs (its largest size read at their ends); the periodic state
    (q*, q'*) per unit force per mass, its relative error, undamped exact resonance and failures."""
    det2 = (w0 - w) * (w0 + w)
    period = 2.0 * math.pi / w
    dev = (np.abs(det2) + 2.0 * d * w) * period / w
    s_force = 1.0 / np.maximum(np.maximum(w * w, np.abs(det2) + w * w), 2.0 * d * w)
    scale = np.stack([np.maximum(dev, 1e-300)] * 4 + [s_force] * 2)
    atol = np.maximum(scale * rtol * 1e-3, 1e-300)
    y = np.zeros((6, w.size))
    biggest = np.zeros((6, w.size))
    why = [None] * w.size
    for k in range(8):
        got = tally.follow(lambda sel: _rotating_rhs(d[sel], w[sel], det2[sel]), (k * math.pi / 4, (k + 1) * math.pi / 4),
                           y, rtol=rtol, atol=atol, on_failure="mark")
        y = got.y_end
        biggest = np.maximum(biggest, np.abs(y))
        why = [a or b for a, b in zip(why, got.why)]
    i_minus_m = -np.stack([np.stack([y[0], y[2]], -1), np.stack([y[1], y[3]], -1)], 1)
    b = y[4:6].T
    drift = np.where(d == 0.0, np.linalg.det(np.eye(2) - i_minus_m) - 1.0, 0.0)
    # DOP853's global error grows by about 0.06 rtol per radian of the fastest motion (measured against the
    # exact map: 0.01-0.063 over 6-565 rad) on top of ~rtol; the claim takes 1 + 0.2 per radian
    g_one = rtol * (1.0 + 0.2 * 2.0 * math.pi)
    sig_m = g_one * biggest[0:4] + atol[0:4]  # entries (0,0), (1,0), (0,1), (1,1)
    sig_b = (g_one * biggest[4:6] + atol[4:6]).T
    sig_mat = np.stack([np.stack([sig_m[0], sig_m[2]], -1), np.stack([sig_m[1], sig_m[3]], -1)], 1)
    xs, dxs, singular = _solve_orbits(i_minus_m, b, sig_mat, sig_b)
    rel = np.hypot(dxs[:, 0], dxs[:, 1]) / np.maximum(np.hypot(xs[:, 0], xs[:, 1]), 1e-300)
    resonant = singular & (d == 0.0) & (det2 == 0.0)
    # the orbit at t = 0 (cos = 1, sin = 0): q = u, q' = omega w'
    return (xs[:, 0], w * xs[:, 1]), rel, resonant, singular & ~resonant, why, drift


def _flow_orbits(gen, unit, w):
    """Away from resonance: the one-period map of each variant's ``gen`` as its matrix exponential, carried as
    M - I (a slow mode that barely moves in one period keeps its digits); (q*, q'*) per unit force per mass,
    its relative error (rounding propagated entry by entry) and where I - M is singular to rounding."""
    from mech.solvers.numerics.linear_flow import expm_minus_identity, rounding_bound

    period = 2.0 * math.pi * unit / w  # in the time unit 1/unit
    dm = expm_minus_identity(gen * period[:, None, None])
    rb = rounding_bound(gen, period)[:, None, None]
    sig = rb * (np.abs(dm) @ (np.abs(dm) + 2.0 * np.eye(4)))
    i_minus_m, b = -dm[:, :2, :2], dm[:, :2, 2]
    # the period itself is known to rb P only (the drive's phase): b moves by that time the state's rate
    end = np.stack([b[:, 0], b[:, 1], np.ones(w.size), np.zeros(w.size)], -1)
    sig_b = sig[:, :2, 2] + rb[:, :, 0] * period[:, None] * np.abs(np.einsum("kij,kj->ki", gen, end))[:, :2]
    xs, dxs, singular = _solve_orbits(i_minus_m, b, sig[:, :2, :2], sig_b)
    c = w / unit
    rel = np.hypot(dxs[:, 0], dxs[:, 1] / c) / np.maximum(np.hypot(xs[:, 0], xs[:, 1] / c), 1e-300)
    return (xs[:, 0] / unit**2, xs[:, 1] / unit), rel, singular


def _manifold_orbits(gen, unit, w):
    """Where one-period shooting is ill-conditioned (a slow mode that barely decays over a period: the
    drive's phase round-off is amplified by 1/(1 - its multiplier)): the stationary motion is the flow's
    invariant plane that moves with the drive, (x, x') = X (C, S) for all t, so A X + B = X R with A, B, R
    the generator's blocks (oscillator, force, drive): a 4x4 linear system for X per variant.  Returns
    (q*, q'*) at t = 0 per unit force per mass, the relative error (Skeel's bound) and the amplitude of
    q = X00 C + X01 S itself (q'* = X10 is tiny beside its own round-off when the drive is slow: omega =
    6e-200 rad/s made A_ss ~ 1e183 from hypot(q*, q'*/omega))."""
    eye = np.eye(2)
    # row-major vec: vec(A X) = (A kron I) vec X, vec(X R) = (I kron R^T) vec X
    k = np.stack([np.kron(g[:2, :2], eye) - np.kron(eye, g[2:, 2:].T) for g in gen])
    rhs = -gen[:, :2, 2:].reshape(-1, 4)
    x = np.linalg.solve(k, rhs[:, :, None])[:, :, 0]
    skeel = np.einsum("kij,kj->ki", np.abs(np.linalg.inv(k)),
                      np.einsum("kij,kj->ki", np.abs(k), np.abs(x)) + np.abs(rhs))
    amp = np.hypot(x[:, 0], x[:, 1])
    rel = 16.0 * _U * np.max(skeel[:, :2], axis=1) / np.maximum(amp, 1e-300)
    return (x[:, 0] / unit**2, x[:, 2] / unit), rel, amp / unit**2


def _stationary(w0, d, w, unit, gen, rtol, tol, tally):
    """Each variant's periodic orbit per unit force per mass: (q*, q'*), the amplitude, its relative error,
    how it was found, resonance (A_ss infinite) and failures."""
    from mech.solvers.numerics.linear_flow import rounding_bound

    n = w.size
    det2 = (w0 - w) * (w0 + w)
    with np.errstate(over="ignore"):  # a static drive (omega = 6e-200 rad/s): its period overflows, not rotating
        rotating = (np.abs(det2) + 2.0 * d * w) * (2.0 * math.pi / w) / w <= 2.0
    qs, vs, rel = np.zeros(n), np.zeros(n), np.full(n, np.inf)
    how = np.array(["one-period map in variation-of-constants variables (DOP853)"] * n, dtype=object)
    resonant, singular, why, drift = np.zeros(n, bool), np.zeros(n, bool), [None] * n, np.zeros(n)
    r = np.flatnonzero(rotating)
    if r.size:
        (qs[r], vs[r]), rel[r], resonant[r], singular[r], why_r, drift[r] = _rotating_orbits(w0[r], d[r], w[r], rtol,
                                                                                          tally)
        for j, text in zip(r, why_r):
            why[j] = text
    # the one-period exponential's own rounding alone exceeds the claim over a period of more than ~1e7 time
    # units (a drive far slower than the oscillator): shooting could not earn it, and over 1e200 units its
    # squarings overflow; straight to the invariant plane then
    shoot = ~rotating & (rounding_bound(gen, 2.0 * math.pi * unit / w) <= tol)
    f_ = np.flatnonzero(shoot)
    if f_.size:
        (qs[f_], vs[f_]), rel[f_], singular[f_] = _flow_orbits(gen[f_], unit[f_], w[f_])
        how[f_] = "one-period map as the matrix exponential of the equation's generator"
    with np.errstate(over="ignore", invalid="ignore"):  # replaced by the invariant plane's where it overflows
        amp = np.hypot(qs, vs / w)
    plane = ~rotating & ~(rel <= tol)
    p_ = np.flatnonzero(plane)
    if p_.size:
        (qs[p_], vs[p_]), rel[p_], amp[p_] = _manifold_orbits(gen[p_], unit[p_], w[p_])
        singular[p_] = False
        how[p_] = "shooting ill-conditioned: the invariant plane of the generator that moves with the drive"
    return qs, vs, amp, rel, how, resonant, singular, why, drift


@exercise.batched(("q_t", "v_t", "A_ss"))
def numeric(P, rtol, outputs, tally=None):
    """N drives at once (a one-point solve is the batch of one): q(t1), q'(t1) by each variant's exact flow
    from rest, A_ss by its periodic orbit (``_stationary``); each variant's claims, failures its own."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column
    from mech.solvers.numerics.linear_flow import expm, rounding_bound

    tally = Tally() if tally is None else tally
    m, w0, d, F0, w, t1 = _arrays(P)
    f = F0 / m
    unit = np.maximum(np.maximum(w0, w), d)  # time unit 1/unit: every rate of the scaled system is at most 2
    gen = _generator(w0, d, w, unit)
    tol = exercise.tol_factor * rtol
    qs, vs, amp, rel, how, resonant, singular, why, drift = _stationary(w0, d, w, unit, gen, rtol, tol, tally)
    tally.invariant("det of the period map (Liouville, delta = 0)", drift)
    tally.info["orbit"] = list(how)
    a_ss = np.where(resonant, np.inf, np.abs(f) * amp)
    stationary = np.where(resonant, 0.0, (np.abs(qs) + np.abs(vs) / unit) * unit**2)  # in the flow's units
    # q(t1), q'(t1): the exact flow of the equation of motion with the drive as a state, from rest
    s1 = unit * t1
    flow = expm(gen * s1[:, None, None])
    y = flow[:, :, 2]  # from (x, x', C, S) = (0, 0, 1, 0)
    # its round-off: every component j injects about rb times its size, carried to x and x' by the flow
    rb = rounding_bound(gen, s1)
    s_x = np.abs(y[:, 0]) + np.abs(y[:, 1]) + 2.0 * stationary
    sizes = np.stack([s_x, s_x, np.ones(w.size), np.ones(w.size)], -1)
    err = rb[:, None] * np.einsum("kij,kj->ki", np.abs(flow[:, :2, :]), sizes)
    tally.info["flow"] = ["matrix exponential of the generator over t1 (scaling and squaring)"] * w.size
    failed = [(np.array([x == text for x in why], dtype=bool), text) for text in sorted({x for x in why if x})]
    failed += [(singular, "the one-period map is the identity to rounding: no unique periodic orbit"),
               (~resonant & ~singular & (rel > 1e-3),
                "the one-period map is the identity within its accuracy (drive period a multiple of the free "
                "period at no damping?): the periodic orbit is not determined by shooting")]
    failed_all = failed[:1] if failed and failed[0][1] in set(x for x in why if x) else []
    return {"q_t": Column(f * y[:, 0] / unit**2, rel=tol, abs=np.abs(f) * err[:, 0] / unit**2, failed=failed_all),
            "v_t": Column(f * y[:, 1] / unit, rel=tol, abs=np.abs(f) * err[:, 1] / unit, failed=failed_all),
            "A_ss": Column(a_ss, rel=np.maximum(tol, np.where(np.isfinite(rel), rel, tol)), failed=failed,
                           undefined=[(resonant, "undamped exact resonance: the period map is the identity, no "
                                                 "periodic orbit; the amplitude grows without bound")])}
