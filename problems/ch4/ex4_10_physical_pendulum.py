"""4.10 Physical pendulum: small-oscillation frequency versus pivot distance.

Analytic: with I' = I + M l^2 about the pivot (parallel axes), Omega^2 = M g l / I'.
So l_ef = g / Omega^2 = l + I/(M l); Omega is largest where l^2 = I/M, i.e.
l_opt = (I/M)^(1/2), with Omega_max^2 = g / (2 l_opt); and since
Omega^2 = g / (l + r^2/l) with r^2 = I/M, the other pivot distance of the same
frequency is l_conj = r^2 / l = I/(M l).

Numeric: the body is four point masses M/4 on a circle of radius (I/M)^(1/2)
about its center, at an arbitrary orientation, hung a distance l from the
pivot (in units M = g = 1 and lengths in rho, so that only l/rho matters); they
form two exactly opposite pairs and every sum over them is taken
without rounding, so the body's own first moment cancels exactly.  The inertia
about the pivot is sum m |r|^2 from the particle positions (the parallel-axis
theorem is never used) and the stiffness U''(0) is the first
Fourier cosine coefficient of U(phi) = sum m g y (a first-degree trigonometric
polynomial, so a 4-point projection is exact and free of step-size
cancellation).  Omega is cross-checked by integrating the nonlinear equation at
amplitude 1e-4 rad over its predicted period and timing the last return to the
release from the end state's phase angle.  l_opt is the root of dOmega/dl
(complex-step derivative, bracketed on a geometric grid); l_conj is the root of
Omega(x) - Omega(l) on the other side of l_opt, bracketed by geometric
expansion; both roots polished by Illinois; within 1e-4 of l_opt that
difference is lost to round-off, and a cubic Taylor model of Omega about l_opt
solves it instead.  The route runs over arrays of variants (``numeric``; a
one-point solve is the batch of one).
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "4.10",
    formulas=[
        "Ω = (M g l / (I + M l²))^(1/2)",
        "l_ef = g / Ω² = l + I / (M l)",
        "l_opt = (I / M)^(1/2),  Ω_max = (g / (2 l_opt))^(1/2)",
        "l_conj = I / (M l)   (l · l_conj = l_opt²)",
    ],
    # the cross-check's small swing at pivot distance l (amplitude PERIOD_AMPLITUDE, released at rest)
    states=[("phi", "rad"), ("phi_dot", "rad/s")],
)

PERIOD_AMPLITUDE = 1e-4
_ALPHA = 0.4137  # orientation of the four-mass cross relative to the pivot line


# the inertia about the farther pivot, M (l^2 + I/M), is formed: l and (I/M)^(1/2) within 150 decades of each other
ranges.declare(exercise, ranges.Scale("l / (I/M)^(1/2)", {"l": 1, "I": -0.5, "M": 0.5}, "the two pivot distances",
                                      low=-150.0, high=150.0))


@exercise.analytic
def analytic(P):
    """Over arrays of variants, in terms of the radius of gyration r = (I/M)^(1/2) and x = l/r, so no l^2 or
    I/M can overflow: Omega^2 = (g/r) x/(1 + x^2), l_ef = r (x + 1/x), l_conj = r/x, l_opt = r,
    Omega_max^2 = g/(2r)."""
    from mech.solvers.numerics.batch import Column

    M, I, l, g = (np.asarray(P[k], dtype=float) for k in ("M", "I", "l", "g"))
    r = np.sqrt(I) / np.sqrt(M)
    x = l / r
    return {
        "Omega": Column(np.sqrt(g) / np.sqrt(r) * np.sqrt(x / (1.0 + x * x))),
        "l_ef": Column(r * (x + 1.0 / x)),
        "l_conj": Column(r / x),
        "l_opt": Column(r),
        "Omega_max": Column(np.sqrt(g) / np.sqrt(2.0 * r)),
    }


def _sum4(a, b, c, d):
    """The sum over the four masses, the opposite ones first ((a + c) + (b + d)): a pair's terms that are
    exact opposites (offsets d and -d) cancel exactly, on numbers or arrays, real or complex."""
    return (a + c) + (b + d)


class _Body:
    """Four equal point masses standing in for the body: same M, same I about the center.

    The masses sit in two exactly opposite pairs (offsets d and -d, built by negation,
    not by a rotation of pi), and every sum over them adds the opposite ones first
    (``_sum4``): a particle's height is the center's height plus its own offset, so the
    potential is sum m g y_c + sum m g d_y, whose second sum is exactly zero.  A plain
    float sum would leave the body's own first moment at eps * rho, which swamps the
    pendulum term M g l once l is 1e-6 of rho (the conjugate pivot of a long pendulum).
    The pivot distance ``l`` and the angle may be numbers or arrays of variants (complex for the step).
    """

    def __init__(self, M, I, g):
        self.M, self.g = M, g
        self.rho = np.sqrt(I / M)
        self.m = M / 4

    def offsets(self, phi):
        """Particle offsets from the center, ((dx...), (dy...)), as exact opposite pairs."""
        c, s = self.rho * np.cos(phi + _ALPHA), self.rho * np.sin(phi + _ALPHA)
        return (c, -s, -c, s), (s, c, -s, -c)

    def center(self, l, phi):
        """The center, at angle phi from straight down below the pivot (origin), y up."""
        return l * np.sin(phi), -l * np.cos(phi)

    def inertia_about_pivot(self, l):
        cx, cy = self.center(l, 0.0)
        dx, dy = self.offsets(0.0)
        return _sum4(*(self.m * ((cx + ex) * (cx + ex) + (cy + ey) * (cy + ey)) for ex, ey in zip(dx, dy)))

    def potential(self, l, phi):
        _, cy = self.center(l, phi)
        _, dy = self.offsets(phi)
        mc = self.m * cy
        return self.g * (_sum4(mc, mc, mc, mc) + _sum4(*(self.m * ey for ey in dy)))

    def stiffness(self, l):
        """U''(0) = -(cosine coefficient of U), exact by a 4-point discrete Fourier projection."""
        phis = np.pi / 2 * np.arange(4)
        return -0.5 * _sum4(*(self.potential(l, ph) * np.cos(ph) for ph in phis))

    def torque(self, l, phi):
        """Gravity's torque about the pivot, sum of x_i * (-m_i g)."""
        cx, _ = self.center(l, phi)
        dx, _ = self.offsets(phi)
        mc = self.m * cx
        return -self.g * (_sum4(mc, mc, mc, mc) + _sum4(*(self.m * ex for ex in dx)))

    def omega(self, l):
        return np.sqrt(self.stiffness(l) / self.inertia_about_pivot(l))


def _dlog_omega(body, x):
    """d Omega / d l by the complex step: exact to round-off, no subtraction."""
    h = 1e-20 * x
    return np.imag(body.omega(x + 1j * h)) / h


def _swing_rhs(body, lam, inertia):
    """The small swing about the pivot at lam (units M = rho = g = 1), for one variant or N."""
    def rhs(t, y):
        return np.array([y[1], body.torque(lam, y[0]) / inertia])

    return rhs


@exercise.motion
def motion(p):
    """The cross-check's small swing: released at rest at PERIOD_AMPLITUDE, over 1.5 small-oscillation
    periods, its crossings of phi = 0 recorded.  Units M = rho = g = 1 (rho = (I/M)^(1/2)), brought to SI
    by the time unit (rho/g)^(1/2); the torque about the pivot from the point masses."""
    from mech.problems.motion import Motion

    rho = math.sqrt(p.I) / math.sqrt(p.M)
    lam = p.l / rho
    body = _Body(1.0, 1.0, 1.0)
    guess = 2 * np.pi / body.omega(lam)  # only bounds the integration time
    t_unit = math.sqrt(rho) / math.sqrt(p.g)
    return Motion(_swing_rhs(body, lam, body.inertia_about_pivot(lam)), [PERIOD_AMPLITUDE, 0.0],
                  (0.0, 1.5 * guess), t_scale=t_unit, y_scale=[1.0, 1.0 / t_unit],
                  options={"events": [Event(lambda t, y: y[0], terminal=False, name="phi = 0")],
                           "max_step": guess / 16},
                  y_size=[PERIOD_AMPLITUDE, PERIOD_AMPLITUDE / guess])


def _period_omega(body, lam, omega, rtol, integrator, tally):
    """Omega from the period of the nonlinear swing at PERIOD_AMPLITUDE, N variants at once: each released at
    rest and integrated over its predicted period 2 pi / omega (time scaled onto [0, 1]); the period is that
    time less the swing's phase angle in the (phi, phi'/omega) plane at its end over the phase's rate there
    (the last return to the release, found from the end state: the phase is off by ~A^2/16)."""
    from mech.solvers.mechanics.floquet import integrate_ensemble

    T = 2 * np.pi / omega
    inertia = body.inertia_about_pivot(lam)
    N = lam.size
    A = PERIOD_AMPLITUDE

    def make_rhs(sel):
        swing, Ts = _swing_rhs(body, lam[sel], inertia[sel]), T[sel]

        def rhs(s, y):  # s = t / T: y = (phi, dphi/ds)
            f = swing(s, np.array([y[0], y[1] / Ts]))
            return np.array([f[0] * Ts, f[1] * Ts * Ts])

        return rhs

    y0 = np.stack([np.full(N, A), np.zeros(N)])
    size = np.stack([np.full(N, A), np.full(N, 2 * np.pi * A)])
    y1, results = integrate_ensemble(make_rhs, (0.0, 1.0), y0, rtol=rtol, atol=1e-3 * rtol * size,
                                     integrator=integrator)
    for r in results:
        tally.record(r)
    phi, v = y1[0], y1[1] / T  # v: phi' in the time unit
    acc = body.torque(lam, phi) / inertia
    # the phase angle theta = atan2(-phi'/omega, phi) and its rate (phi'^2 - phi phi'') / (omega (phi^2 + ..))
    q = -v / omega
    theta = np.arctan2(q, phi)
    rate = (v * v - phi * acc) / (omega * (phi * phi + q * q))
    return 2 * np.pi / (T - theta / rate)


def _l_opt(body, lam):
    """l_opt, N variants at once (units rho = 1): the root of dOmega/dl, positive below and negative above,
    bracketed on a geometric grid of 61 points per variant (ends off round numbers: no grid point lands
    exactly on the maximum, lam = 1 is a hard case), then Illinois to 1e-15.  (l_opt, failed mask)."""
    from mech.solvers.numerics.batch import illinois

    N = lam.size
    lo, hi = np.minimum(lam, body.rho) * 0.9173e-3, np.maximum(lam, body.rho) * 1.0781e3
    grid = np.exp(np.linspace(np.log(lo), np.log(hi), 61))  # (61, N)
    slopes = _dlog_omega(body, grid)
    down = np.diff(np.sign(slopes), axis=0) < 0
    bad = down.sum(axis=0) != 1
    k = np.argmax(down, axis=0)
    cols = np.arange(N)
    a, b = grid[k, cols], grid[k + 1, cols]
    fa, fb = slopes[k, cols], slopes[k + 1, cols]
    ok = np.flatnonzero(~bad)
    x = np.full(N, np.nan)
    x[ok], conv = illinois(lambda x, i: _dlog_omega(body, x), a[ok], b[ok], fa[ok], fb[ok],
                           xtol=1e-15 * a[ok], rtol=1e-15)
    bad[ok[~conv]] = True
    return x, bad


def _l_conj(body, lam, l_opt, omega):
    """l_conj, N variants at once (units rho = 1): the same Omega on the other side of l_opt.  Within 1e-4 of
    l_opt the difference is lost to round-off and a cubic Taylor model of Omega about l_opt solves it; else
    the root of Omega(x) - Omega(lam), bracketed by doubling (or halving) from l_opt, then Illinois.
    (l_conj, cubic mask, failed mask)."""
    from mech.solvers.numerics.batch import illinois

    N = lam.size
    v = lam - l_opt
    cubic = np.abs(v) < 1e-4 * l_opt
    out = np.full(N, np.nan)
    if cubic.any():
        lo, vv = l_opt[cubic], v[cubic]
        h = 1e-3 * lo
        d_minus, d0, d_plus = (_dlog_omega(body, lo + s) for s in (-h, 0.0, h))
        w2 = (d_plus - d_minus) / (2 * h)
        w3 = (d_plus - 2 * d0 + d_minus) / h**2
        u = -vv
        for _ in range(5):  # u = -v - (w3 / 3 w2)(u^2 + u v + v^2)
            u = -vv - w3 / (3 * w2) * (u * u + u * vv + vv * vv)
        out[cubic] = lo + u
    go = np.flatnonzero(~cubic)
    factor = np.where(lam[go] < l_opt[go], 2.0, 0.5)
    target = omega[go]
    f = lambda x, i: body.omega(x) - target[i]  # noqa: E731
    a = l_opt[go].copy()
    fa = f(a, np.arange(go.size))
    b, fb = a.copy(), fa.copy()
    bad = np.zeros(N, dtype=bool)
    live = np.arange(go.size)
    for _ in range(1100):  # march until the sign changes
        if live.size == 0:
            break
        a[live], fa[live] = b[live], fb[live]
        b[live] = a[live] * factor[live]
        fb[live] = f(b[live], live)
        live = live[np.sign(fb[live]) == np.sign(fa[live])]
    bad[go[live]] = True
    ok = np.setdiff1d(np.arange(go.size), live)
    lo_, hi_ = np.minimum(a[ok], b[ok]), np.maximum(a[ok], b[ok])
    flo, fhi = np.where(a[ok] < b[ok], fa[ok], fb[ok]), np.where(a[ok] < b[ok], fb[ok], fa[ok])
    x, conv = illinois(lambda x, i: f(x, ok[i]), lo_, hi_, flo, fhi, xtol=1e-15 * lo_, rtol=1e-15)
    out[go[ok]] = x
    bad[go[ok[~conv]]] = True
    return out, cubic, bad


@exercise.batched(("Omega", "l_ef", "l_conj", "l_opt", "Omega_max"))
def numeric(P, rtol, outputs, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): the model's stiffness and
    inertia, the period check integrated together, the roots searched together (Illinois)."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    M, I, l, g = (np.asarray(P[k], dtype=float) for k in ("M", "I", "l", "g"))
    # units: M, the radius of gyration rho = (I/M)^(1/2) and g are 1 (Omega in (g/rho)^(1/2)); the body
    # is the same for every M, I, g, and only l/rho shapes the problem (1e-200 or 1e200 included)
    rho = np.sqrt(I) / np.sqrt(M)
    lam = l / rho
    body = _Body(1.0, 1.0, 1.0)
    omega = body.omega(lam)
    # the torque's sums are exact (see _Body), so the period check can run at the solve's own tolerance
    period_rtol = min(max(rtol, 1e-12), 1e-6)
    omega_swing = _period_omega(body, lam, omega, period_rtol, tally.integrator, tally)
    mismatch = np.abs(omega_swing - omega) / omega
    rate = np.sqrt(g) / np.sqrt(rho)
    tally.info["Omega_from_period"] = omega_swing * rate
    tally.info["period_check_rtol"] = np.full(lam.size, period_rtol)
    failed = [(~(mismatch <= 100 * period_rtol + PERIOD_AMPLITUDE**2 / 16),
               "Omega from the stiffness and from the timed period differ")]
    l_opt, bad_opt = _l_opt(body, lam)
    failed.append((bad_opt, "dOmega/dl does not change sign exactly once on the grid, or its root did not "
                   "converge"))
    omega_max = body.omega(l_opt)
    l_conj, cubic, bad_conj = _l_conj(body, lam, l_opt, omega)
    failed.append((bad_conj, "no sign change of Omega(x) - Omega(l) found while bracketing l_conj, or its root "
                   "did not converge"))
    tally.info["l_conj_route"] = np.where(cubic, "cubic Taylor model about l_opt", "bracketed root")
    # U, T and the torque are exact sums (no eps * rho / l round-off): Omega and l_ef carry a few ulps,
    # l_conj the root's tolerance (1e-15) over the slope d ln Omega / d ln l >= 1e-4 away from l_opt
    claims = {"Omega": 1e-11, "l_ef": 1e-11, "l_conj": 1e-11, "l_opt": 1e-10, "Omega_max": 1e-12}
    values = {"Omega": omega * rate, "l_ef": rho / omega**2, "l_conj": l_conj * rho, "l_opt": l_opt * rho,
              "Omega_max": omega_max * rate}
    return {o: Column(values[o], rel=claims[o], failed=failed) for o in outputs}


@exercise.scene
def scene(p, run):
    """Omega against the pivot distance, with its maximum at l_opt and the pair l, l_conj of equal Omega."""
    from mech.problems.scene import Axis, Guide, Line, Markers, Panel, Scene

    a = run.analytic(p)
    lo = min(p.l, a["l_conj"], a["l_opt"]) / 8
    hi = max(p.l, a["l_conj"], a["l_opt"]) * 8
    ls = np.geomspace(lo, hi, 300)
    curve = run.series(p, "l", ls)["Omega"]
    panel = Panel("Ω(l): one maximum, and two pivots for every lower Ω",
                  Axis("pivot's distance from the center of mass l", "m", log=True), Axis("Ω", "rad/s"),
                  legend="lower center")
    panel.add(Line(ls, curve, "Ω(l), analytic"))
    xs = run.numeric_points(lo, hi, log=True)
    if len(xs):
        panel.add(Markers(xs, run.series(p, "l", xs, numeric=True)["Omega"], "numeric"))
    panel.add(
        Guide(a["l_opt"], label=f"l_opt = {a['l_opt']:.4g} m", color="C2"),
        Guide(a["Omega_max"], axis="y", color="C2"),
        Line([p.l, a["l_conj"]], [a["Omega"], a["Omega"]], kind="drawing", color="k", width=0.9),
        Markers([p.l, a["l_conj"]], [a["Omega"], a["Omega"]],
                f"same Ω: l = {p.l:.4g} m and l_conj = {a['l_conj']:.4g} m", kind="this"),
    )
    nv = run.numeric(p)
    if nv:
        panel.add(Markers([nv["l_opt"], nv["l_conj"]], [nv["Omega_max"], nv["Omega"]], kind="numeric"))
    return Scene([panel], on_axis=("l",),
                 caption=f"l + l_conj = l_ef = {a['l_ef']:.4g} m: the reversible (Kater) pendulum")
