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

Numeric: the full equation of motion; over one drive period P = 2 pi/omega
the map is x -> M x + b, M from the two unit initial states and b from rest.
Near resonance (where M is close to I) the variables are the exact
variation-of-constants pair (u, w), q = u cos wt + w sin wt,
q' = omega (w cos wt - u sin wt) (no averaging: u' and w' carry the whole
force), and M - I is integrated directly as the deviation of the unit states,
so it keeps its relative accuracy however nearly resonant the drive; elsewhere
plain (q, q').  A_ss: the periodic orbit
(I - M) x* = b, amplitude |x*|.  q(t1), q'(t1): the augmented map raised to the
N = floor(t1/P) power, then a direct integration over the remaining part of a
period.  DOP853; Radau with the exact Jacobian when overdamped and 2 delta P > 1e3
(stiff).  The claim on A_ss scales with the conditioning of I - M; where M is
the identity within its accuracy (no damping, drive period a multiple of the
free period) shooting cannot pick the orbit and the solver fails loudly.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure, Undefined
from mech.solvers.ode import integrate

exercise = Exercise(
    "5.3",
    formulas=[
        "q(t) = (F₀/m) Re e^{zt}[iω, p₁, p₂]  (divided difference; p₁,₂ = −δ ± (δ² − ω₀²)^½)",
        "      = a e^{iωt} + transient,  a = (F₀/m)/(ω₀² − ω² + 2iδω)",
        "δ = 0, ω = ω₀:  q = (F₀/m) t sin(ω₀t)/(2ω₀)  (secular growth)",
        "A_ss = (F₀/m)/[(ω₀² − ω²)² + 4δ²ω²]^½",
    ],
)


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
        from scipy.linalg import expm

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
    a_ss = Undefined("undamped exact resonance: the amplitude grows without bound") if den == 0 else abs(f) / den
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

    def rhs_full(self, t, y):
        a, force = self.coeffs(t)
        return a @ y + force

    def rhs_period(self, t, y):
        # y = [d1, d2, xp]: deviations of the two unit columns from their start, and the forced state from rest
        a, force = self.coeffs(t)
        return np.concatenate([a @ (y[0:2] + (1.0, 0.0)), a @ (y[2:4] + (0.0, 1.0)), a @ y[4:6] + force])

    jac_full = jac_period = None

    def to_qv(self, x, s):
        c, sn = math.cos(self.w * s), math.sin(self.w * s)
        return x[0] * c + x[1] * sn, self.w * (x[1] * c - x[0] * sn)


class _Direct:
    """Unit force per mass in (q, q'); used away from resonance, Radau when overdamped and stiff."""

    def __init__(self, w0, d, w):
        self.w = w
        self.a = np.array([[0.0, 1.0], [-w0 * w0, -2.0 * d]])

    def rhs_full(self, t, y):
        return self.a @ y + (0.0, math.cos(self.w * t))

    def rhs_period(self, t, y):
        # here the unit columns are integrated as they are (the map is far from the identity)
        a = self.a
        return np.concatenate([a @ (y[0:2] + (1.0, 0.0)), a @ (y[2:4] + (0.0, 1.0)),
                               a @ y[4:6] + (0.0, math.cos(self.w * t))])

    def jac_full(self, t, y):
        return self.a

    def jac_period(self, t, y):
        j = np.zeros((6, 6))
        for k in range(3):
            j[2 * k:2 * k + 2, 2 * k:2 * k + 2] = self.a
        return j

    def to_qv(self, x, s):
        return x[0], x[1]


@exercise.numeric
def numeric(p, run):
    f = p.F0 / p.m
    w0, d, w = p.omega0, p.delta, p.omega
    period = 2.0 * math.pi / w
    det2 = (w0 - w) * (w0 + w)
    dev = (abs(det2) + 2.0 * d * w) * period / w  # how far the one-period map is from the identity
    rotating = dev <= 2.0
    model = (_Rotating if rotating else _Direct)(w0, d, w)
    stiff = (not rotating) and d > w0 and 2.0 * d * period > 1e3
    method = "Radau" if stiff else "DOP853"
    run.info["variables"] = "variation of constants (u, w)" if rotating else "(q, q')"
    rtol = run.rtol
    s_force = 1.0 / max(w0 * w0, w * w, 2.0 * d * w)  # displacement per unit force per mass, roughly
    if rotating:
        scale = np.array([dev] * 4 + [s_force] * 2)
    else:
        scale = np.array([1.0, w0, 1.0 / w0, 1.0, s_force, s_force * max(w, w0)])
    atol = np.maximum(scale * rtol * 1e-3, 1e-300)
    one = integrate(model.rhs_period, (0.0, period), np.zeros(6), rtol=rtol, atol=atol, method=method,
                    jac=model.jac_period if stiff else None)
    run.record(one)
    y = one.y_end
    i_minus_m = -np.array([[y[0], y[2]], [y[1], y[3]]])
    b = y[4:6]
    m_map = np.eye(2) - i_minus_m
    if d == 0.0:
        run.invariant("det of the period map (Liouville, delta = 0)", np.linalg.det(m_map) - 1.0)
    # accuracy of the one-period map, entry by entry: DOP853's global error grows along the run by about
    # 0.06 rtol per radian of the fastest motion (measured against the exact map: 0.01-0.063 over 6-565 rad)
    # on top of ~rtol; the claim takes 1 + 0.2 per radian times the largest value each entry meets
    fast = max(w, w0 if d < w0 else 0.0)
    g_one = rtol * (1.0 + 0.2 * fast * period)
    sig_m = g_one * np.abs(one.y[0:4]).max(axis=1) + atol[0:4]  # entries (0,0), (1,0), (0,1), (1,1)
    sig_b = g_one * np.abs(one.y[4:6]).max(axis=1) + atol[4:6]

    sv = np.linalg.svd(i_minus_m, compute_uv=False)
    if sv[-1] == 0.0:
        if rotating and d == 0.0 and det2 == 0.0:
            a_ss = Undefined("undamped exact resonance: the period map is the identity, no periodic orbit")
        else:
            raise NumericFailure("the one-period map is the identity to rounding: no unique periodic orbit")
    else:
        xs = np.linalg.solve(i_minus_m, b)
        # first-order error of x* = (I - M)^-1 b, component by component (units kept apart: q and q' differ
        # by a frequency, so no common norm)
        sig_mat = np.array([[sig_m[0], sig_m[2]], [sig_m[1], sig_m[3]]])
        dxs = np.abs(np.linalg.inv(i_minus_m)) @ (sig_b + sig_mat @ np.abs(xs))
        qs, vs = model.to_qv(xs, 0.0)
        if rotating:
            rel = float(np.hypot(*dxs) / max(np.hypot(*xs), 1e-300))
        else:
            rel = math.hypot(dxs[0], dxs[1] / w) / max(math.hypot(qs, vs / w), 1e-300)
        if rel > 1e-3:
            raise NumericFailure(
                "the one-period map is the identity within its accuracy (drive period a multiple of the free "
                "period at no damping?): the periodic orbit is not determined by shooting")
        a_ss = abs(f) * math.hypot(qs, vs / w)
        run.claim("A_ss", rel=max(exercise.tol_factor * rtol, rel))

    # the state at t1: N whole periods by the augmented map, then the rest of a period directly
    n = int(p.t1 // period)
    rest = p.t1 - n * period
    if rest < 0.0:
        n, rest = n - 1, p.t1 - (n - 1) * period
    aug = np.eye(3)
    aug[:2, :2] = m_map
    aug[:2, 2] = b
    x = (np.linalg.matrix_power(aug, n) @ np.array([0.0, 0.0, 1.0]))[:2] if n > 0 else np.zeros(2)
    run.info["whole_periods"] = n
    # the map's errors (sig_m, sig_b above) propagated through the N-fold power exactly, entry by entry:
    # d(A^N) is the upper-right block of [[A, dA], [0, A]]^N (the error grows with N as the route does)
    err = np.zeros(2)
    if n > 0:
        entries = [((0, 0), sig_m[0]), ((1, 0), sig_m[1]), ((0, 1), sig_m[2]), ((1, 1), sig_m[3]),
                   ((0, 2), sig_b[0]), ((1, 2), sig_b[1])]
        for (i, j), sig in entries:
            blk = np.zeros((6, 6))
            blk[:3, :3] = blk[3:, 3:] = aug
            blk[i, 3 + j] = 1.0
            err += np.abs(np.linalg.matrix_power(blk, n)[:2, 5]) * sig
    if rest > 0.0:
        # the tail carries its own unit columns along: its flow maps the error of the whole periods
        size = np.maximum(np.abs(x), scale[4:6])
        tail = integrate(model.rhs_period, (0.0, rest), np.concatenate([np.zeros(4), x]), rtol=rtol,
                         atol=np.concatenate([atol[0:4], rtol * 1e-3 * size]), method=method,
                         jac=model.jac_period if stiff else None)
        run.record(tail)
        yt = tail.y_end
        flow = np.eye(2) + np.array([[yt[0], yt[2]], [yt[1], yt[3]]])
        g_tail = rtol * (1.0 + 0.2 * fast * rest)
        err = np.abs(flow) @ err + g_tail * np.abs(tail.y[4:6]).max(axis=1) + rtol * 1e-3 * size
        x = yt[4:6]
    q, qd = model.to_qv(x, rest)
    if rotating:
        c, sn = abs(math.cos(w * rest)), abs(math.sin(w * rest))
        eq, ev = err[0] * c + err[1] * sn, w * (err[1] * c + err[0] * sn)
    else:
        eq, ev = err
    run.claim("q_t", rel=exercise.tol_factor * rtol, abs=abs(f) * abs(eq))
    run.claim("v_t", rel=exercise.tol_factor * rtol, abs=abs(f) * abs(ev))
    return {"q_t": f * q, "v_t": f * qd, "A_ss": a_ss}
