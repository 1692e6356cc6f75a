"""5.7 Free Duffing oscillator: frequency at finite amplitude and the third harmonic.

Analytic (exact).  With eps = alpha A^2/omega0^2, the motion from rest at q = A is
q = A cn(Omega t | m), Omega^2 = omega0^2 + alpha A^2, m = alpha A^2/(2 Omega^2)
(cn'' = (2m - 1) cn - 2m cn^3 matches q'' = -omega0^2 q - alpha q^3).  The period
4K(m)/Omega and K = pi/(2 AGM(1, sqrt(1 - m))) give, by the homogeneity of the AGM,
    omega = AGM( sqrt(omega0^2 + alpha A^2), sqrt(omega0^2 + alpha A^2/2) ),
valid for both signs of alpha; omega - omega0 is computed from the deviations of the
AGM's two sequences from omega0 (no cancellation for small eps), and
omega0^2 + alpha A^2 exactly (rational arithmetic) so the barrier approach keeps
its digits.  c3 from the nome series of cn, with q_n = exp(-pi K'/K):
    m >= 0:  c3 = A (2 pi/(K sqrt m)) q_n^(3/2)/(1 + q_n^3);
    m < 0:   cn(u|m) = cd(u sqrt(1-m) | m1), m1 = -m/(1-m), and the cd series gives
             c3 = -A (2 pi/(K1 sqrt m1)) q1^(3/2)/(1 - q1^3);
for |m| < 1e-8 the series c3 = A (m/16)(1 + m/2).  Leading order (Lindstedt):
omega = omega0 + 3 alpha A^2/(8 omega0), c3 = alpha A^3/(32 omega0^2).  For alpha < 0
the period diverges like ln(1/(1 + eps)) as A approaches the barrier omega0/sqrt(|alpha|).

Numeric (units 1/omega0 and A: x'' = -x - eps x^3 from (1, 0), in sigma = S omega0 t with S^2 = 1 + eps for a
stiff spring, eps >= 1/2, so that a period is of order one), over arrays of variants at once (a one-point
solve is the batch of one; ``numeric``):
* the quarter period with the polar angle psi of the phase point (x, -dx/dsigma) as the independent variable:
  it rises monotonically from 0 at rest to pi/2 at x = 0 for every bounded motion, so all variants end at the
  same psi; the clock is carried as its excess E = sigma - psi (T - T0 and omega - omega0 keep their digits
  at a tiny eps, no separate quadrature), and x as y = 1 - x with the force written from 1 + eps exact, so
  near the barrier top (1 + eps ~ 1e-8) the small force at the start keeps its digits (``_clock_rhs``);
* c3 (eps > -1/2) in the phase theta = ws sigma over [0, pi/2], ws the frequency measured, from the deviation
  z = x - cos theta integrated as a state with int z cos 3 theta (a c3 of 1e-8 A keeps its relative digits;
  ``_harmonic_rhs``); the half-wave symmetry gives c3 = (4/pi) int_0^{pi/2} x cos 3 theta, and int cos theta
  cos 3 theta vanishes there.  Near the barrier (eps <= -1/2) the long dwell at the start is crossed in the
  polar angle again, int x cos(3 ws sigma) dsigma carried as a fourth state.
The statement's energy is checked at the end of both, and x = 0 at psi = pi/2.  The declared motion
(``motion``: the quarter period in the time to the event x = 0, in the distance from the barrier top below
eps = -1/2) is what a trajectory and the scene show.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from mech.problems.spec import Exercise, NumericFailure

exercise = Exercise(
    "5.7",
    formulas=[
        "q = A cn(Ωt | m),  Ω² = ω₀² + αA²,  m = αA²/(2Ω²)",
        "ω = πΩ/(2K(m)) = AGM((ω₀² + αA²)^½, (ω₀² + αA²/2)^½)",
        "c₃ = A (2π/(K√m)) q^{3/2}/(1 + q³),  q = exp(−πK(1−m)/K(m))  (m < 0: the cd series with m₁ = −m/(1−m))",
        "leading order: ω ≈ ω₀ + 3αA²/(8ω₀),  c₃ ≈ αA³/(32ω₀²)",
        "α < 0, A² → ω₀²/|α|: T ≈ (2√2/ω₀) ln(8ω₀²/(ω₀² + αA²)) → ∞ (logarithmic divergence)",
    ],
    route_note=(
        "The quarter period is integrated with the phase point's polar angle as the independent variable "
        "(x = 0 at the fixed angle pi/2, so many oscillators integrate together), its clock's excess carried "
        "as a state: the small-amplitude shift keeps its digits without a quadrature of T - T0; near the "
        "barrier x is carried as its distance 1 - x from the start, the force formed from 1 + eps exact."
    ),
    # a quarter period from rest at q = A down to q = 0
    states=[("q", "m"), ("v", "m/s")],
)

EPS_MAX = 1e200  # alpha A^2/omega0^2 above this the scaled force and energy terms approach overflow


def _exact_one_plus_eps(w0, al, a) -> float:
    w0, al, a = Fraction(w0), Fraction(al), Fraction(a)
    return float((w0 * w0 + al * a * a) / (w0 * w0))


_ONE_PLUS_EPS = np.frompyfunc(_exact_one_plus_eps, 3, 1)


def _one_plus_eps(p) -> float:
    """1 + alpha A^2/omega0^2 at one point, computed exactly in rational arithmetic then rounded once."""
    return _exact_one_plus_eps(p.omega0, p.alpha, p.A)


def _eps(p) -> float:
    return (p.alpha / p.omega0) * (p.A / p.omega0) * p.A


exercise.declare_limits(
    "A < omega0/|alpha|^(1/2) when alpha < 0: bounded motion",
    f"alpha A^2/omega0^2 <= {EPS_MAX:g}",
    "the frequency shift |alpha| A^2/omega0 representable as a fraction of omega0 (alpha A^2/omega0^2 >= 1e-290 where the shift is)",
)


@exercise.constraint
def constraint(p):
    if p.alpha < 0.0 and _one_plus_eps(p) <= 0.0:
        qb = p.omega0 / math.sqrt(-p.alpha)
        return (f"A = {p.A:g} m is at or beyond the barrier top omega0/sqrt(|alpha|) = {qb:.10g} m: "
                "the motion is not bounded")
    if _eps(p) > EPS_MAX:
        return f"alpha A^2/omega0^2 = {_eps(p):.3g} exceeds {EPS_MAX:g}"
    # the shift omega - omega0 ~ (3/8) alpha A^2/omega0 is a fraction eps of omega0: when eps lies below the
    # floating-point range while the shift itself does not (omega0 1e200 times its default), neither solver
    # can form it (both would print a shift of 0, silently wrong)
    shift = abs(p.alpha / p.omega0) * p.A * p.A
    if p.alpha != 0.0 and abs(_eps(p)) < 1e-290 and shift >= 1e-290:
        return (f"alpha A^2/omega0^2 ~ 1e{math.log10(shift) - math.log10(p.omega0):.0f}: the "
                f"frequency shift ~ {shift:.3g} rad/s is a fraction of omega0 = {p.omega0:.3g} rad/s that "
                "floating point cannot represent")


def _agm_deviation(da, db):
    """AGM(1 + da, 1 + db) - 1 from the deviations (arrays), without forming 1 + small and subtracting."""
    live = np.ones(np.shape(da), dtype=bool)
    for _ in range(80):
        x = da + db + da * db  # a b - 1
        da, db = np.where(live, 0.5 * (da + db), da), np.where(live, x / (1.0 + np.sqrt(1.0 + x)), db)
        live &= ~(np.abs(da - db) <= 1e-17 * np.maximum(np.abs(da), 1e-300))
        if not live.any():
            break
    return 0.5 * (da + db)


@exercise.approximations
def approximations(p):
    """The statement asks for the frequency first to leading order in alpha A^2/omega0^2 (the shift
    3 alpha A^2/(8 omega0), Landau & Lifshitz, Mechanics, sec. 28), then exactly."""
    shift = 3.0 * p.alpha * p.A**2 / (8.0 * p.omega0)
    # the third harmonic to the same order (Lindstedt's first correction, the formula `mech show 5.7` prints)
    c3 = p.alpha * p.A**3 / (32.0 * p.omega0**2)
    return {"omega": [(p.omega0 + shift, "the leading-order frequency omega0 + 3 alpha A^2/(8 omega0)")],
            "domega": [(shift, "the leading-order shift 3 alpha A^2/(8 omega0)")],
            "c3": [(c3, "the leading-order third harmonic alpha A^3/(32 omega0^2)")]}


def _arrays(P):
    return (np.asarray(P[k], dtype=float) for k in ("omega0", "alpha", "A"))


def _third_harmonic(A, eps, g, h):
    """c3 from the nome series of cn (see the module's docstring), over arrays."""
    from mech.solvers.numerics.special import ellipk, ellipkm1

    m = 0.5 * eps / g  # alpha A^2/(2 Omega^2)
    tiny, pos = np.abs(m) < 1e-8, m > 0.0
    with np.errstate(all="ignore"):
        mp = np.where(pos & ~tiny, m, 0.5)
        K, Kp = np.asarray(ellipk(mp)), np.asarray(ellipkm1(mp))
        qn = np.exp(-math.pi * Kp / K)
        c_pos = A * (2.0 * math.pi / (K * np.sqrt(mp))) * qn * np.sqrt(qn) / (1.0 + qn**3)
        # m < 0: m1 = -m/(1 - m) = -eps/(1 + h); 1 - m1 = 2 g/(1 + g), exact near the barrier
        neg = ~pos & ~tiny
        m1 = np.where(neg, -eps / (2.0 * h), 0.5)
        p1 = np.where(neg, 2.0 * g / (1.0 + g), 0.5)
        K1, K1p = np.asarray(ellipkm1(p1)), np.asarray(ellipk(p1))
        x = math.pi * K1p / K1
        q1 = np.exp(-x)
        c_neg = -A * (2.0 * math.pi / (K1 * np.sqrt(m1))) * q1 * np.sqrt(q1) / (-np.expm1(-3.0 * x))
    return np.where(tiny, A * (m / 16.0) * (1.0 + 0.5 * m), np.where(pos, c_pos, c_neg))


@exercise.analytic
def analytic(P):
    """omega by the AGM (from the deviations below |eps| = 1/2) and c3 by the nome series, over arrays."""
    from mech.solvers.numerics.batch import Column
    from mech.solvers.numerics.special import agm

    w0, alpha, A = _arrays(P)
    eps = (alpha / w0) * (A / w0) * A
    g = np.asarray(_ONE_PLUS_EPS(w0, alpha, A), dtype=float)  # (omega0^2 + alpha A^2)/omega0^2 = Omega^2/omega0^2
    h = 0.5 * (1.0 + g)  # (omega0^2 + alpha A^2/2)/omega0^2
    small = np.abs(eps) < 0.5
    with np.errstate(all="ignore"):
        # deviations of sqrt(1 + eps), sqrt(1 + eps/2) from 1
        dw = _agm_deviation(np.where(small, eps / (np.sqrt(g) + 1.0), 0.0),
                            np.where(small, 0.5 * eps / (np.sqrt(h) + 1.0), 0.0))
        big = w0 * np.asarray(agm(np.sqrt(np.where(small, 1.0, g)), np.sqrt(np.where(small, 1.0, h))))
    omega = np.where(small, w0 * (1.0 + dw), big)
    domega = np.where(small, w0 * dw, big - w0)
    return {"omega": Column(omega), "domega": Column(domega), "c3": Column(_third_harmonic(A, eps, g, h))}


# ------------------------------------------------------------------ numeric
def cubic_force(x, b):
    """The anharmonic term of the scaled Duffing equation: -b x^3."""
    return -b * x**3


def equation_of_motion(x, a, b):
    """x'' of the scaled Duffing equation x'' = -a x - b x^3 (a = 1/S^2, b = eps/S^2)."""
    return -a * x + cubic_force(x, b)


def barrier_equation_of_motion(s, xb, eps):
    """s'' for the distance s = x_b - x from the barrier top, expanded about it without cancellation:
    s'' = -x'' = x + eps x^3 at x = x_b - s, with 1 + eps x_b^2 = 0."""
    return 2.0 * s - 3.0 * s * s / xb - eps * s**3


def physical_energy(p, x, u):
    """Energy per unit mass from the statement's potential, v^2/2 + omega0^2 q^2/2 + alpha q^4/4, at
    q = A x and v = A omega0 u, in units of (A omega0)^2: u^2/2 + x^2/2 + (alpha A^2/omega0^2) x^4/4.
    Written from the physics, not from the scaled equations above, so that it checks them; in these
    units it neither over- nor underflows when omega0 or A is 1e+-200 times its default (in SI,
    omega0^2 q^2 or q^4 left the range: energy drift NaN)."""
    k4 = (p.alpha / p.omega0) * (p.A / p.omega0) * p.A  # alpha A^2 / omega0^2, each factor in range
    return 0.5 * u * u + 0.5 * x * x + 0.25 * k4 * x**4


def _scaled(p):
    """(S, a, b): the time sigma = S tau with S^2 = 1 + eps for a stiff spring (S = 1 below eps = 1/2), so
    that one period is of order one however large eps, and x'' = -a x - b x^3 in it."""
    eps = _eps(p)
    S = math.sqrt(1.0 + eps) if eps >= 0.5 else 1.0
    return S, 1.0 / (S * S), eps / (S * S)


def _barrier(p):
    """(x_b, s0): the barrier top 1/sqrt(-eps) and the start's distance from it, with 1 + eps exact."""
    eps = _eps(p)
    xb = 1.0 / math.sqrt(-eps)
    return xb, _one_plus_eps(p) / ((-eps) * (xb + 1.0))


@exercise.motion
def motion(p):
    """A quarter period from rest at q = A down to q = 0, in units A and 1/omega0 (x = q/A); for
    eps > -1/2 in x against sigma = S omega0 t (``_scaled``), below in the distance s = x_b - x from the
    barrier top (``_barrier``), which keeps the start's small offset from it to full relative accuracy."""
    from mech.problems.motion import Motion
    from mech.solvers.numerics.ode import Event

    w0, A = p.omega0, p.A
    eps = _eps(p)
    if eps > -0.5:
        S, a, b = _scaled(p)

        def rhs(t, y):
            return np.array([y[1], equation_of_motion(y[0], a, b)])

        # the statement's energy in units of (A omega0)^2: q = A x, dq/dt = A omega0 (S dx/dsigma)
        e0 = physical_energy(p, 1.0, 0.0)
        return Motion(rhs, [1.0, 0.0], (0.0, 8.0 * math.pi),
                      event=Event(lambda t, y: y[0], direction=-1, name="x = 0"),
                      invariants={"energy": lambda y: physical_energy(p, y[0], S * y[1]) / e0},
                      t_scale=1.0 / (S * w0), y_scale=[A, A * S * w0], y_size=[1.0, math.sqrt(a + 0.5 * abs(b))])
    xb, s0 = _barrier(p)

    def rhs_s(t, y):
        return np.array([y[1], barrier_equation_of_motion(y[0], xb, eps)])

    # in units of (A omega0)^2 as above (q = A (x_b - s), dq/dt = -A omega0 ds/dtau), relative to the energy
    # itself, the kinetic energy at x = 0: the range explored (the potential's round-off near the barrier top,
    # 1/(-4 eps) in these units, is relative to that scale)
    e0 = physical_energy(p, xb - s0, 0.0)
    # the quarter period grows like ln(1/s0): bound the search generously
    return Motion(rhs_s, [s0, 0.0], (0.0, 8.0 * (math.pi + math.log(1.0 + 1.0 / s0))),
                  event=Event(lambda t, y: y[0] - xb, direction=1, name="x = 0"),
                  invariants={"energy": lambda y: physical_energy(p, xb - y[0], -y[1]) / e0},
                  t_scale=1.0 / w0, y_scale=[A, A * w0], to_states=lambda y: [xb - y[0], -y[1]], y_size=[s0, s0])


def restoring_factor(y, k, b):
    """-x''/x of the scaled equation, a + b x^2 = (1 + eps x^2)/S^2, at x = 1 - y, written from the distance y
    to the start: k - b y (2 - y), with k = (1 + eps)/S^2 (1 for S^2 = 1 + eps) and b = eps/S^2; 1 + eps
    exact, so near the barrier top (1 + eps ~ 1e-8) the small force at the start keeps its digits."""
    return k - b * y * (2.0 - y)


def _coefficients(P):
    """Per variant: (eps, 1 + eps exact, S, k, b, barrier) of the scaled equation (``_scaled``, over arrays):
    sigma = S omega0 t with S^2 = 1 + eps at eps >= 1/2 (1 below), ``barrier`` where eps <= -1/2."""
    w0, alpha, A = _arrays(P)
    eps = (alpha / w0) * (A / w0) * A
    g = np.asarray(_ONE_PLUS_EPS(w0, alpha, A), dtype=float)
    stiff = eps >= 0.5
    S = np.where(stiff, np.sqrt(np.where(stiff, g, 1.0)), 1.0)
    k = np.where(stiff, 1.0, g)
    b = eps / (S * S)
    return eps, g, S, k, b, eps <= -0.5


def _clock_rhs(eps, k, b, stiff, ws=None):
    """The quarter period in the polar angle psi of the phase point (x, u), u = -dx/dsigma, state (y, u, E)
    with y = 1 - x and E = sigma - psi: dpsi/dsigma = (x F + u^2)/(x^2 + u^2), F = x (a + b x^2) = -x'', rises
    from 0 at the start to pi/2 at x = 0 for every bounded variant; E' = x (x - F)/(x F + u^2), x - F formed
    without cancellation (-eps x^3 at S = 1, b x (1 - x^2) above).  With ``ws`` (the frequency measured) a
    fourth state, int x cos(3 ws sigma) dsigma (the barrier's c3, whose long dwell at the start the polar
    angle crosses in few steps)."""
    def rhs(psi, Y):
        y, u = Y[0], Y[1]
        x = 1.0 - y
        F = x * restoring_factor(y, k, b)
        gap = x * np.where(stiff, b * y * (2.0 - y), -eps * x * x)  # x - F
        den = x * F + u * u
        excess = x * gap / den
        clock = 1.0 + excess  # dsigma/dpsi
        rates = [u * clock, F * clock, excess]
        if ws is not None:
            rates.append(x * np.cos(3.0 * ws * (psi + Y[2])) * clock)
        return np.array(rates)

    return rhs


def _harmonic_rhs(b, ws, wgap):
    """The same quarter period (eps > -1/2) in the phase theta = ws sigma (0 to pi/2, ws the frequency the
    clock measured), state (z, z', I): z = x - cos theta, the deviation from the harmonic motion, so a c3 of
    1e-8 A keeps its digits, and I = int z cos 3 theta d theta; x'' = -x (a + b x^2)/ws^2 in theta, so
    z'' = -z + x (ws^2 - a - b x^2)/ws^2 (``wgap`` = ws^2 - a without cancellation)."""
    def rhs(th, Y):
        z = Y[0]
        x = np.cos(th) + z
        return np.array([Y[1], -z + x * (wgap - b * x * x) / ws**2, z * np.cos(3.0 * th)])

    return rhs


def _ensemble(make_rhs, span, y0, atol, rtol, tally, why, among):
    """The variants ``among`` (a mask) still without a failure followed together (``Tally.follow``), each
    failing alone (``why``, filled in); ``make_rhs(idx, sel)``: the right-hand side of the variants ``idx``
    (then ``sel`` of them).  NaN where not followed or failed."""
    y_end = np.full(y0.shape, np.nan)
    idx = np.flatnonzero(np.array([w is None for w in why], dtype=bool) & among)
    if idx.size:
        got = tally.follow(lambda sel: make_rhs(idx, sel), span, y0[:, idx], rtol=rtol, atol=atol[:, idx],
                           on_failure="mark")
        y_end[:, idx] = np.where(got.failed, np.nan, got.y_end)
        for j, w in zip(idx, got.why):
            why[int(j)] = w if w else why[int(j)]
    return y_end


def _energy(eps, S, x, dx):
    """The statement's energy v^2/2 + omega0^2 q^2/2 + alpha q^4/4 in units of (A omega0)^2 (q = A x,
    v = A omega0 S dx/dsigma), relative to its value at rest at q = A, minus 1: its drift."""
    e0 = 0.5 + 0.25 * eps
    return (0.5 * (S * dx) ** 2 + 0.5 * x * x + 0.25 * eps * x**4) / e0 - 1.0


@exercise.batched(("omega", "domega", "c3"))
def numeric(P, rtol, outputs, tally=None):
    """N oscillators at once (a one-point solve is the batch of one): the quarter period by the phase point's
    polar angle (``_clock_rhs``), then c3 in the measured phase (``_harmonic_rhs``), both over fixed spans;
    the energy at both ends and x = 0 at the quarter checked per variant, a variant beyond failing alone."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    w0, _, A = _arrays(P)
    eps, g, S, k, b, barrier = _coefficients(P)
    stiff = eps >= 0.5
    n = eps.size
    why = [None] * n
    half = 0.5 * math.pi
    small = np.minimum(g, 1.0)  # the start's distance from the barrier sets the scale of y and u early on
    every = np.ones(n, dtype=bool)
    with np.errstate(all="ignore"):
        u_max = np.sqrt((1.0 + 0.5 * eps) / np.where(stiff, g, 1.0))
        e_size = np.maximum(np.minimum(np.abs(eps), 1.0), 1e-300)
        sizes = np.stack([small, small * u_max, e_size])
        y, u, E = _ensemble(lambda i, sel: _clock_rhs(eps[i][sel], k[i][sel], b[i][sel], stiff[i][sel]),
                            (0.0, half), np.zeros((3, n)), 1e-3 * rtol * sizes, rtol, tally, why, every)
        quarter = half + E  # in sigma
        ws = half / quarter
        dws = -E / quarter  # ws - 1
        # c3: in the phase theta = ws sigma from the deviation z = x - cos theta (eps > -1/2); by the polar
        # angle again near the barrier, with int x cos 3 theta carried
        wgap = np.where(stiff, ws * ws - 1.0 / np.where(stiff, g, 1.0), dws * (2.0 + dws))  # ws^2 - a, a = 1/S^2
        sizes = np.stack([e_size, e_size, e_size])
        z, dz, integral = _ensemble(lambda i, sel: _harmonic_rhs(b[i][sel], ws[i][sel], wgap[i][sel]), (0.0, half),
                                    np.zeros((3, n)), 1e-3 * rtol * sizes, rtol, tally, why, ~barrier)
        sizes = np.stack([small, small * u_max, e_size, np.ones(n)])
        yb, ub, _, ib = _ensemble(lambda i, sel: _clock_rhs(eps[i][sel], k[i][sel], b[i][sel], stiff[i][sel],
                                                            ws[i][sel]),
                                  (0.0, half), np.zeros((4, n)), 1e-3 * rtol * sizes, rtol, tally, why, barrier)
        x_q = np.where(barrier, 1.0 - yb, z)  # cos(pi/2) is 6e-17: left out
        dx_q = np.where(barrier, -ub, ws * (-1.0 + dz))  # dx/dsigma
        drift = np.maximum(np.abs(_energy(eps, S, 1.0 - y, -u)), np.abs(_energy(eps, S, x_q, dx_q)))
        bottom = np.abs(1.0 - y) / np.abs(u)
        omega1 = S * ws
        dw = np.where(stiff, omega1 - 1.0, dws)
        c3 = (4.0 / math.pi) * np.where(barrier, ws * ib, integral)
    tally.invariant("energy", drift)
    tally.invariant("x = 0 at psi = pi/2", bottom)
    tally.info["x_at_quarter_period"] = x_q
    allowed = exercise.tol_factor * rtol
    ran = np.array([w is None for w in why], dtype=bool)
    failed = [(np.array([w == text for w in why], dtype=bool), text) for text in sorted({w for w in why if w})]
    failed += [(ran & ~(drift <= allowed), f"the energy drifted by more than {allowed:.3g}"),
               (ran & ~(bottom <= allowed), "the swing did not reach x = 0 at the polar angle pi/2")]
    values = {"omega": w0 * omega1, "domega": w0 * dw, "c3": A * c3}
    return {o: Column(values[o], rel=allowed, failed=failed) for o in outputs}
