"""4.31 Body dropped from a height: eastward deflection by the Earth's rotation.

Analytic (exact solution of dv/dt = g - 2 w x v from rest): split the motion
along w = w_E (0, sin th, cos th) and across it.  Along w the body accelerates
uniformly with -g cos th; across it the complex velocity u = v_east + i v_perp
obeys u' = -2i w_E u + i g sin th, so u = (g sin th / 2w_E)(1 - exp(-2i w_E t)).
With phi = w_E t this gives
    height lost  g t^2 [cos^2 th + sin^2 th (sin phi / phi)^2] / 2 = h  (fall time),
    d_east = g sin th t^2 (2 phi - sin 2 phi) / (4 phi^2)  ~ (1/3) g w_E t^3 sin th,
    v_east = g sin th t sin^2 phi / phi                  ~ g w_E t^2 sin th.
The fall-time equation is solved by a bracketed root search; phi - sin phi is
evaluated by its series for small phi (no cancellation).

Numeric: the six Earth-frame equations of motion, in units of h and
T0 = (2h/g)^(1/2), integrated from rest with DOP853 to the event z = 0.  The
eastward and northward components get absolute tolerances on their own scale
(w_E T0 sin th times the height), so the centimetre deflection is integrated as
a variable in its own right, not as a difference of large coordinates.  The
Earth-frame energy v^2/2 + g z (the Coriolis force does no work) is monitored.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise
from mech.solvers.numerics.ode import Event
from mech.solvers.numerics.roots import bracketed_root

exercise = Exercise(
    "4.31",
    formulas=[
        "t_fall: (g t²/2) [cos²θ + sin²θ (sin φ/φ)²] = h, φ = ω_E t   (≈ (2h/g)^(1/2))",
        "d_east = g sinθ t² (2φ - sin 2φ)/(4φ²) = (1/3) ω_E g t³ sinθ Σ_k (-1)^k 6 (2φ)^(2k)/(2k+3)!"
        "   (= ... [1 - φ²/5 + 2φ⁴/105 - ...]: no cancellation at small φ)",
        "d_east ≈ (1/3) ω_E g t³ sinθ = (2√2/3) ω_E sinθ h^(3/2) g^(-1/2)",
        "v_east = g sinθ t sin²φ / φ ≈ ω_E g t² sinθ = 2 ω_E h sinθ",
        "(exact solution of dv/dt = g - 2 ω_E × v; the ≈ forms are leading order in ω_E t)",
    ],
    # the fall from rest at height h to the ground, ground-frame axes (east, north, up; origin at the
    # foot of the plumb line)
    states=[("x_east", "m"), ("y_north", "m"), ("z_up", "m"), ("v_east", "m/s"), ("v_north", "m/s"),
            ("v_up", "m/s")],
)

# the catalogue's note calls the analytic value leading-order; here it is the model's exact solution
exercise.restate_hard_case(1, (
    "a 90 s fall: the corrections of order (omega_E t)^2 to the textbook's leading-order formulas reach 1e-5 "
    "and exceed the tolerance, so both answers must solve the model's full equations (mech's analytic value is "
    "their exact solution, not the leading order)"))

# The model (uniform g with the centrifugal part folded in, h << R_E) needs the
# fall to take a small part of a turn of the Earth: w_E T0 = w_E (2h/g)^(1/2) << 1.
MAX_EPS = 0.5


exercise.declare_limits(
    f"omega_E (2h/g)^(1/2) <= {MAX_EPS:g}: the fall lasts a small part of a turn of the Earth",
)


@exercise.constraint
def constraint(p):
    eps = p.omega_E * math.sqrt(2.0 * p.h / p.g)
    if eps > MAX_EPS:
        return (
            f"omega_E (2h/g)^(1/2) = {eps:.3g} exceeds {MAX_EPS}: the fall would last a sizeable part of a "
            "turn of the Earth, which h << R_E (and a planet that holds together, omega_E^2 R_E < g) excludes"
        )


def _x_minus_sin_over_cube(x: float) -> float:
    """(x - sin x) / x^3 without cancellation for small x, and without forming x^3 (which underflows for
    |x| < 1e-103)."""
    if abs(x) > 0.5:
        return (x - math.sin(x)) / x**3
    # 1/3! - x^2/5! + x^4/7! - ...; terms fall by x^2/((2k)(2k+1)) < 0.0125
    term = 1.0 / 6.0
    total = 0.0
    k = 1
    while True:
        total += term
        if abs(term) <= 1e-18 * abs(total):
            break
        term *= -(x * x) / ((2 * k + 2) * (2 * k + 3))
        k += 1
    return total


def _one_minus_sinc(x: float) -> float:
    """1 - sin(x)/x, by its series x^2/3! - x^4/5! + ... for |x| <= 0.5 (no cancellation)."""
    if abs(x) > 0.5:
        return 1.0 - math.sin(x) / x
    return x * x * _x_minus_sin_over_cube(x)


def _sinc(x: float) -> float:
    return 1.0 if x == 0.0 else math.sin(x) / x


def _exact(theta, h, g, omega_E):
    """(t_fall, d_east, v_east) of one variant: the fall-time equation's root and the closed forms."""
    s, c = math.sin(theta), math.cos(theta)
    T0 = math.sqrt(2.0 * h / g)
    eps = omega_E * T0

    def lost(tau):  # height lost over h at scaled time tau, minus 1
        # (tau^2 - 1) - tau^2 s^2 (1 - sinc^2), not tau^2 (c^2 + s^2 sinc^2) - 1: c^2 + s^2 is 1 only to
        # rounding, and where s^2 eps^2/3 is below it (eps = 4.5e-8, theta = 0.032: lost(1) = -7e-19) lost(1)
        # came out +2.2e-16 and the root was not bracketed
        x = eps * tau
        m = _one_minus_sinc(x)
        return (tau - 1.0) * (tau + 1.0) - tau * tau * s * s * m * (2.0 - m)

    if eps < 1e-100:
        # tau - 1 ~ s^2 eps^2/6 is below 1e-200, far under an ulp of 1: tau is 1 in doubles (and pi/(2 eps)
        # would leave the range for a subnormal eps)
        tau = 1.0
    else:
        # lost(1) <= 0 (sinc <= 1); at eps tau = pi/2 it is >= 1/eps^2 - 1 > 0 for eps <= 0.5
        tau = bracketed_root(lost, 1.0, math.pi / (2.0 * eps))
    t = tau * T0
    phi = omega_E * t
    if phi == 0.0:
        d, v = 0.0, 0.0
    else:
        # g s t^2 (x - sin x) / (4 phi^2) with x = 2 phi
        d = 2.0 * g * s * t * t * phi * _x_minus_sin_over_cube(2.0 * phi)
        v = g * s * t * math.sin(phi) * _sinc(phi)
    return t, d, v


@exercise.analytic
def analytic(P):
    """Over arrays: the fall-time equation is a scalar root search, run for each variant (``_exact``)."""
    from mech.solvers.numerics.batch import Column

    args = np.broadcast_arrays(*(np.asarray(P[k], dtype=float) for k in ("theta", "h", "g", "omega_E")))
    got = np.array([_exact(*(float(x) for x in row)) for row in zip(*(a.ravel() for a in args))]).reshape(-1, 3)
    shape = args[0].shape
    return {name: Column(got[:, j].reshape(shape)) for j, name in enumerate(("t_fall", "d_east", "v_east"))}


# Tuned default (from `mech bench 4.31`, rtol 1e-10, cross-check tolerance 1e-8): DOP853.  The equations
# are linear with constant coefficients and z = 0 is crossed once; with the event confirmed on the dense
# output (mech.solvers.numerics.ode) DOP853 needs 77 evaluations for an error of 2e-14 (1e-15 on the 90 s fall),
# LSODA 59 for 1.6e-13 and RK45 50 for 2.4e-11, all within a few ms.  With ode's bounded rerun DOP853
# cost 862 evaluations (the rerun's 64 steps of 12 stages) and LSODA, at 167, was the cheaper choice.
METHOD = "DOP853"


def _rates(y, wn, wu):
    """dv/dt = g - 2 w x v with w = (0, wn, wu) scaled (g T0^2/h = 2): the rates of (x, y, z, vx, vy, vz) (numbers,
    or arrays of variants)."""
    vx, vy, vz = y[3], y[4], y[5]
    return np.array([vx, vy, vz, -2.0 * (wn * vz - wu * vy), -2.0 * wu * vx, -2.0 + 2.0 * wn * vx])


def _scaled(theta, h, g, omega_E):
    """(T0, the scaled Earth rate's components wn, wu, the sideways components' scale) over arrays."""
    T0 = np.sqrt(2.0 * h / g)
    eps = omega_E * T0
    return T0, eps * np.sin(theta), eps * np.cos(theta), np.maximum(eps * np.abs(np.sin(theta)), 1e-300)


def _energy(y):
    """(v^2/2 + g z) / (g h), scaled: the Coriolis force does no work (states 6 x ...)."""
    return (0.5 * (y[3] ** 2 + y[4] ** 2 + y[5] ** 2) + 2.0 * y[2]) / 2.0


@exercise.motion
def motion(p):
    """The fall in the Earth's rotating frame, dv/dt = g - 2 w x v (east, north, up), from rest at height h
    to the ground, in lengths h and time T0 = (2h/g)^(1/2) (so g T0^2/h = 2)."""
    from mech.problems.motion import Motion

    T0, wn, wu, small = (float(x) for x in _scaled(p.theta, p.h, p.g, p.omega_E))
    return Motion(lambda t, y: _rates(y, wn, wu), [0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
                  (0.0, 3.0),  # lands by tau = arcsin(eps)/eps <= 1.05 for eps <= 0.5
                  event=Event(lambda t, y: y[2], direction=-1, name="z = 0"), invariants={"energy": _energy},
                  t_scale=T0, y_scale=[p.h] * 3 + [p.h / T0] * 3,
                  y_size=[small, small, 1.0, small, small, 1.0], options={"method": METHOD})


def _legs(wn, wu, small, rtol, tally):
    """The falls of N variants at once, in two legs on shared spans (``variants.follow``): in time to tau = 1
    (no variant lands before: the height lost by then is at most h, the free fall's), then with the height
    as the independent variable, sigma in [0, 1] from z(1) down to z = 0 (dz/dsigma = -z(1); the body falls
    at about 2 h/T0 there), the time carried as a seventh state.  So the landing is the end of a fixed span,
    no event to locate.  Returns (states 7 x N at the ground: x, y, z, vx, vy, vz, tau; failures)."""

    N = wn.size
    atol = 1e-3 * rtol * np.stack([small, small, np.ones(N), small, small, np.ones(N), np.ones(N)])
    y0 = np.zeros((6, N))
    y0[2] = 1.0
    got = tally.follow(lambda sel: (lambda t, y: _rates(y, wn[sel], wu[sel])), (0.0, 1.0), y0, rtol=rtol, atol=atol[:6])
    y1, why = got.y_end, got.why
    ok = np.flatnonzero(why == "")
    z1, a, b = y1[2, ok], wn[ok], wu[ok]

    def down(sel):
        zs, wa, wb = z1[sel], a[sel], b[sel]

        def rhs(sigma, y):
            return (-zs / y[5]) * np.concatenate([_rates(y, wa, wb), [np.ones_like(y[5])]])  # dt/dsigma = -z1/vz

        return rhs

    y2 = np.full((7, N), np.nan)
    if ok.size:
        start = np.vstack([y1[:, ok], np.ones((1, ok.size))])
        got = tally.follow(down, (0.0, 1.0), start, rtol=rtol, atol=atol[:, ok])
        y2[:, ok], why[ok] = got.y_end, got.why
    return y2, why


@exercise.batched(("t_fall", "d_east", "v_east"))
def numeric(P, rtol, outputs, tally=None):
    """The falls at N variants at once (``_legs``; a one-point solve is the batch of one), in lengths h and
    time T0; the energy's drift and the northward deviation reported to ``tally``."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    theta, h, g, omega_E = (np.asarray(P[k], dtype=float) for k in ("theta", "h", "g", "omega_E"))
    T0, wn, wu, small = _scaled(theta, h, g, omega_E)
    y, why = _legs(wn, wu, small, rtol, tally)
    drift = np.abs(_energy(y) - 1.0)
    tally.invariant("energy", np.nan_to_num(drift))
    tally.info["north_deviation_m"] = y[1] * h
    failed = [(why == text, text) for text in sorted(set(why[why != ""]))]
    failed.append(((why == "") & ~(drift <= exercise.tol_factor * rtol), "the invariant 'energy' drifts by more "
                   "than the method allows: the integration is not to be trusted"))
    values = {"t_fall": y[6] * T0, "d_east": y[0] * h, "v_east": y[3] * h / T0}
    return {o: Column(values[o], rel=exercise.tol_factor * rtol, failed=failed) for o in outputs}
