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

Numeric (units 1/omega0 and A: x'' = -x - eps x^3 from (1, 0)); the quarter period is the
declared motion (``motion``), the c3 integrals are tool runs of the same oscillator:
* eps > -1/2: the quarter period by the event x = 0 (DOP853, energy monitored); for
  |eps| < 1/2 omega - omega0 instead from a quadrature of T - T0: energy
  conservation with x = cos th gives T/4 = int_0^{pi/2} dth/sqrt(1 + (eps/2)(1 + cos^2 th)),
  integrated as the cancellation-free difference from the harmonic pi/2.  c3 from
  the deviation r = x - cos(omega t), integrated as a state of its own
  (r'' = -omega^2 r + (omega^2 - 1) x - eps x^3, so a c3 of 1e-8 A keeps its relative
  digits) together with int r cos 3 omega t dt over a quarter period; the half-wave
  symmetry gives c3 = (8/T) times that integral (int cos wt cos 3wt vanishes there).
* eps <= -1/2 (softening, towards the barrier x_b = 1/sqrt(-eps)): the distance from
  the barrier top s = x_b - x, s'' = 2 s - 3 s^2/x_b - eps s^3, started at
  s0 = (1 + eps)/((-eps)(x_b + 1)) with 1 + eps exact, to the event s = x_b (x = 0);
  then c3 from int (x_b - s) cos 3 omega t over that quarter period.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.numerics.special import agm

exercise = Exercise(
    "5.7",
    formulas=[
        "q = A cn(Ωt | m),  Ω² = ω₀² + αA²,  m = αA²/(2Ω²)",
        "ω = πΩ/(2K(m)) = AGM((ω₀² + αA²)^½, (ω₀² + αA²/2)^½)",
        "c₃ = A (2π/(K√m)) q^{3/2}/(1 + q³),  q = exp(−πK(1−m)/K(m))  (m < 0: the cd series with m₁ = −m/(1−m))",
        "leading order: ω ≈ ω₀ + 3αA²/(8ω₀),  c₃ ≈ αA³/(32ω₀²)",
        "α < 0, A² → ω₀²/|α|: T ≈ (2√2/ω₀) ln(8ω₀²/(ω₀² + αA²)) → ∞ (logarithmic divergence)",
    ],
    # a quarter period from rest at q = A down to q = 0
    states=[("q", "m"), ("v", "m/s")],
)

EPS_MAX = 1e200  # alpha A^2/omega0^2 above this the scaled force and energy terms approach overflow


def _one_plus_eps(p) -> float:
    """1 + alpha A^2/omega0^2, computed exactly in rational arithmetic then rounded once."""
    w0, al, a = Fraction(p.omega0), Fraction(p.alpha), Fraction(p.A)
    return float((w0 * w0 + al * a * a) / (w0 * w0))


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
    """AGM(1 + da, 1 + db) - 1 from the deviations, without forming 1 + small and subtracting."""
    for _ in range(80):
        x = da + db + da * db  # a b - 1
        da, db = 0.5 * (da + db), x / (1.0 + math.sqrt(1.0 + x))
        if abs(da - db) <= 1e-17 * max(abs(da), 1e-300):
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


@exercise.analytic
def analytic(p):
    from mech.solvers.numerics.special import ellipk, ellipkm1

    w0, A = p.omega0, p.A
    eps = _eps(p)
    g = _one_plus_eps(p)  # (omega0^2 + alpha A^2)/omega0^2 = Omega^2/omega0^2
    h = 0.5 * (1.0 + g)  # (omega0^2 + alpha A^2/2)/omega0^2
    if abs(eps) < 0.5:
        # deviations of sqrt(1 + eps), sqrt(1 + eps/2) from 1
        da = eps / (math.sqrt(g) + 1.0)
        db = 0.5 * eps / (math.sqrt(h) + 1.0)
        dw = _agm_deviation(da, db)
        omega = w0 * (1.0 + dw)
        domega = w0 * dw
    else:
        omega = w0 * agm(math.sqrt(g), math.sqrt(h))
        domega = omega - w0
    # third harmonic
    m = 0.5 * eps / g  # alpha A^2/(2 Omega^2)
    if abs(m) < 1e-8:
        c3 = A * (m / 16.0) * (1.0 + 0.5 * m)
    elif m > 0.0:
        K, Kp = float(ellipk(m)), float(ellipkm1(m))
        qn = math.exp(-math.pi * Kp / K)
        c3 = A * (2.0 * math.pi / (K * math.sqrt(m))) * qn * math.sqrt(qn) / (1.0 + qn**3)
    else:
        # m1 = -m/(1 - m) = -eps/(1 + h); 1 - m1 = 2 g/(1 + g), exact near the barrier
        m1 = -eps / (2.0 * h)
        p1 = 2.0 * g / (1.0 + g)
        K1, K1p = float(ellipkm1(p1)), float(ellipk(p1))
        x = math.pi * K1p / K1
        q1 = math.exp(-x)
        c3 = -A * (2.0 * math.pi / (K1 * math.sqrt(m1))) * q1 * math.sqrt(q1) / (-math.expm1(-3.0 * x))
    return {"omega": omega, "domega": domega, "c3": c3}


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


def _quarter_excess(eps):
    """(T/4 - pi/2) in units 1/omega0 by quadrature of the energy integral, and its error estimate."""
    from mech.solvers.numerics.quadrature import quad

    def f(th):
        c = math.cos(th)
        s = 0.5 * eps * (1.0 + c * c)
        g = math.sqrt(1.0 + s)
        return -s / (g * (g + 1.0))  # 1/g - 1

    val, err = quad(f, 0.0, 0.5 * math.pi, epsabs=0.0, epsrel=1e-13, limit=200)
    return val, err


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


def _deviation(p, ws, ws2ma):
    """The same oscillator (eps > -1/2) as its deviation r = x - cos(ws sigma) from the harmonic motion at
    its own frequency ws, with int r cos(3 ws sigma) d sigma carried along, over a quarter period from
    r = r' = 0: r'' = x'' + ws^2 cos(ws sigma) = -ws^2 r + (ws^2 - a) x - b x^3 (the -a x of x'' split as
    -ws^2 x + (ws^2 - a) x so that r stays small; ``ws2ma`` = ws^2 - a without cancellation)."""
    from mech.problems.motion import Motion

    _, _, b = _scaled(p)

    def rhs_r(t, y):
        c = math.cos(ws * t)
        x = c + y[0]
        return np.array([y[1], -ws * ws * y[0] + ws2ma * x + cubic_force(x, b), y[0] * math.cos(3.0 * ws * t)])

    rs = min(max(abs(_eps(p)), 1e-300), 1.0)  # the size of r (|eps|/32 small, order one large)
    tq = 0.5 * math.pi / ws
    return Motion(rhs_r, [0.0, 0.0, 0.0], (0.0, tq), y_size=[rs, rs * ws, rs * tq])


def _with_harmonic(m, xb, omega1, t_q):
    """The barrier branch's quarter period ``m`` again, with int x cos(3 omega1 tau) d tau carried along."""
    def rhs_c(t, y):
        s, ds = m.rhs(t, y[:2])
        return np.array([s, ds, (xb - y[0]) * math.cos(3.0 * omega1 * t)])

    s0 = m.y0[0]
    return m.starting(y0=[s0, 0.0, 0.0], span=(0.0, t_q), rhs=rhs_c, event=None, invariants={},
                      to_states=None, y_size=[s0, s0, t_q])


@exercise.numeric
def numeric(p, run):
    w0, A = p.omega0, p.A
    eps = _eps(p)
    m = motion(p)
    end = run.follow(m)
    t_q = end.t_end

    if eps > -0.5:
        S, a, b = _scaled(p)
        if abs(eps) < 0.5:
            excess, err = _quarter_excess(eps)
            dw = -excess / (0.5 * math.pi + excess)  # pi/(2 (pi/2 + excess)) - 1
            run.claim("domega", rel=max(1e-12, 10.0 * err / max(abs(excess), 1e-300)) if excess != 0.0 else None,
                      abs=0.0 if excess != 0.0 else 1e-300)
            run.info["domega_route"] = "quadrature of T - T0"
            run.invariant("quarter period: event vs quadrature", (t_q - (0.5 * math.pi + excess)) / t_q)
            ws = 1.0 + dw  # angular frequency in units of S omega0 = omega0
            ws2ma = dw * (2.0 + dw)  # ws^2 - a without cancellation
        else:
            ws = 0.5 * math.pi / t_q
            ws2ma = ws * ws - a
            run.info["domega_route"] = "event x = 0"
        omega1 = S * ws
        dw = omega1 - 1.0 if abs(eps) >= 0.5 else dw

        # c3 from the deviation r = x - cos(ws sigma)
        h = run.follow(_deviation(p, ws, ws2ma), mark=False)
        r_end, v_end, integral = h.y_end
        tq = h.t_end
        x_end = r_end + math.cos(ws * tq)
        e0 = physical_energy(p, 1.0, 0.0)
        run.invariant("energy", (physical_energy(p, x_end, S * (v_end - ws * math.sin(ws * tq))) - e0) / e0)
        run.info["x_at_quarter_period"] = x_end
        c3_over_a = 4.0 * ws / math.pi * integral
    else:
        omega1 = 0.5 * math.pi / t_q
        dw = omega1 - 1.0
        run.info["domega_route"] = "event x = 0 in the distance from the barrier top"
        xb, _ = _barrier(p)
        h = run.follow(_with_harmonic(m, xb, omega1, t_q), mark=False)
        run.info["x_at_quarter_period"] = xb - h.y_end[0]
        c3_over_a = 4.0 * omega1 / math.pi * h.y_end[2]
    if not math.isfinite(omega1) or not math.isfinite(c3_over_a):
        raise NumericFailure("non-finite frequency or harmonic")
    return {"omega": w0 * omega1, "domega": w0 * dw, "c3": A * c3_over_a}
