"""4.20 Free rotation about the principal axes: stable about n1 and n3, unstable about n2.

Analytic: linearizing Euler's equations about omega0 n_j leaves the two other
components obeying x'' = -(I_j - I_k)(I_j - I_l) omega0^2/(I_k I_l) x, so
  Omega_1 = omega0 [(I2 - I1)(I3 - I1)/(I2 I3)]^(1/2),
  Omega_3 = omega0 [(I3 - I1)(I3 - I2)/(I1 I2)]^(1/2),
  lambda_2 = omega0 [(I2 - I1)(I3 - I2)/(I1 I3)]^(1/2).
The flip started at omega0 (sin d, cos d, 0) has L^2 < 2 E I2 (it circles n1);
Euler's equations are solved by Jacobi elliptic functions with
  T_period = (4 K(k)/omega0) [I1 I2 I3 / ((I2 - I1) D)]^(1/2),
  D = I1 (I3 - I1) sin^2 d + I2 (I3 - I2) cos^2 d,  1 - k^2 = I1 (I3 - I1) sin^2 d / D,
with K = pi / (2 AGM(1, k')) evaluated from the complementary parameter, so
that d -> 0 (T ~ (4/lambda_2) ln(4/k')) keeps its digits.

Numeric: the Jacobian of the torque-free Euler equations at each steady
rotation by central differences (exact for a quadratic right-hand side) and
its eigenvalues: an imaginary pair gives Omega_1 or Omega_3, a real pair
lambda_2 (checked).  T_period: the Euler equations (in units of omega0; the
declared motion, one leg per crossing, each confirmed with a bounded step)
integrated with a relative error control reaching down to the size of
the small components, from omega(0), timing the
upward crossings of omega3 = 0 at T/2 and 3T/2; energy, |L|^2 and the orbit's
distance from the separatrix, 2 E I2 - L^2 (evaluated as
sum I_i (I2 - I_i) omega_i^2, free of cancellation), are monitored.  When that
distance drifts by more than 10 rtol of itself (tiny d: the orbit hugs the
separatrix; a tilt below 1e-4 is not even tried), the integration is not
trusted and the period is instead four
times the quarter-cycle quadrature of d(omega3)/|d(omega3)/dt| from omega3 = 0
to its maximum, with omega1^2 and omega2^2 from the conserved E and L^2,
omega3 = omega3_max sin(phi), Gauss-Legendre on intervals halving toward the
logarithmically singular end phi = 0 (checked against a higher-order rule);
below phi ~ 1e-8 the variable is phi/sin(delta), so that even a subnormal
tilt keeps its digits.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.freebody import euler_omega_rhs, steady_rotation_pair
from mech.solvers.mechanics.inertia import gauss_legendre
from mech.solvers.numerics.ode import Event, first_event
from mech.solvers.numerics.special import agm

exercise = Exercise(
    "4.20",
    formulas=[
        "Ω₁ = ω₀ [(I₂ - I₁)(I₃ - I₁)/(I₂I₃)]^(1/2)",
        "λ₂ = ω₀ [(I₂ - I₁)(I₃ - I₂)/(I₁I₃)]^(1/2)",
        "Ω₃ = ω₀ [(I₃ - I₁)(I₃ - I₂)/(I₁I₂)]^(1/2)",
        "T = (4K(k)/ω₀) [I₁I₂I₃/((I₂ - I₁)D)]^(1/2), D = I₁(I₃ - I₁) sin²δ + I₂(I₃ - I₂) cos²δ",
        "1 - k² = I₁(I₃ - I₁) sin²δ / D   (δ → 0: T ≈ (4/λ₂) ln(4/k'))",
    ],
    # the body-axis angular velocity over 1.5 periods of the flip (the three legs the period is timed by)
    states=[("omega1", "rad/s"), ("omega2", "rad/s"), ("omega3", "rad/s")],
)

# the integration is trusted while the separatrix distance keeps this many rtol of itself
SEPARATRIX_DRIFT_LIMIT = 10.0


exercise.declare_limits(
    "I1 < I2 < I3 strictly",
    "I3 <= I1 + I2: moments a real body can have",
)


@exercise.constraint
def constraint(p):
    if not (p.I1 < p.I2 < p.I3):
        return f"the moments must satisfy I1 < I2 < I3 strictly (got {p.I1:g}, {p.I2:g}, {p.I3:g} kg m^2)"
    if p.I3 > p.I1 + p.I2:
        return f"I3 = {p.I3:g} exceeds I1 + I2 = {p.I1 + p.I2:g} kg m^2: no real body has such moments"


@exercise.analytic
def analytic(p):
    I1, I2, I3, w = p.I1, p.I2, p.I3, p.omega0
    s, c = np.sin(p.delta), np.cos(p.delta)
    D = I1 * (I3 - I1) * s * s + I2 * (I3 - I2) * c * c
    ratio = np.sqrt(I1 * (I3 - I1) / D)
    kp = ratio * s  # not from its square: a tilt below 1e-154 would underflow
    if kp < 1e-100:
        # K = ln(4/k') + O(k'^2 ln k'), exact in double precision here, and with the logarithm
        # split so that a subnormal tilt keeps its digits
        K = np.log(4.0) - np.log(ratio) - np.log(s)
    else:
        K = math.pi / (2.0 * agm(1.0, kp))  # K(k) from the complementary modulus k'
    T = 4.0 * K / w * np.sqrt(I1 * I2 * I3 / ((I2 - I1) * D))
    return {
        "Omega_1": w * np.sqrt((I2 - I1) * (I3 - I1) / (I2 * I3)),
        "lambda_2": w * np.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3)),
        "Omega_3": w * np.sqrt((I3 - I1) * (I3 - I2) / (I1 * I2)),
        "T_period": T,
    }


def _rates(I, omega0, run=None):
    """Omega_1, lambda_2, Omega_3 from the Jacobian eigenvalues at the three steady rotations (the eigenvalues
    and the claims reported to ``run`` when given)."""
    out = {}
    for k, name, kind in ((0, "Omega_1", "imag"), (1, "lambda_2", "real"), (2, "Omega_3", "imag")):
        la, lb, ev = steady_rotation_pair(I, k, omega0)
        mag = max(abs(la), abs(lb))
        if run is not None:
            run.info[f"eigenvalues_n{k + 1}"] = [str(complex(e)) for e in ev]
        if kind == "imag":
            if max(abs(la.real), abs(lb.real)) > 1e-12 * mag or abs(la.imag + lb.imag) > 1e-12 * mag:
                raise NumericFailure(f"the eigenvalues at n{k + 1} are not an imaginary pair: {la}, {lb}")
            out[name] = 0.5 * (abs(la.imag) + abs(lb.imag))
        else:
            if max(abs(la.imag), abs(lb.imag)) > 1e-12 * mag or abs(la.real + lb.real) > 1e-12 * mag:
                raise NumericFailure(f"the eigenvalues at n{k + 1} are not a real pair +-lambda: {la}, {lb}")
            out[name] = 0.5 * (abs(la.real) + abs(lb.real))
        if run is not None:
            run.claim(name, rel=1e-12)
    return out


def _separatrix_distance(I, w):
    """2 E I2 - |L|^2 as a sum of terms that each vanish with its own component (no cancellation)."""
    return I[0] * (I[1] - I[0]) * w[0] ** 2 + I[2] * (I[1] - I[2]) * w[2] ** 2


# the legs the period is timed by: the crossings of omega3 = 0 (direction, name)
CROSSINGS = ((+1, "omega3 up (T/2)"), (-1, "omega3 down (T)"), (+1, "omega3 up (3T/2)"))


@exercise.motion
def motion(p, rtol=None):
    """The flip from omega0 (sin delta, cos delta, 0) in units omega0 = 1, in three legs, each up to the next
    crossing of omega3 = 0 (CROSSINGS: T/2, T, 3T/2), recorded as a non-terminal event beside the drift of
    the separatrix distance beyond SEPARATRIX_DRIFT_LIMIT rtol, which ends the chain (the orbit's side of
    the separatrix is no longer certain); ``rtol``: the accuracy it is followed at, the exercise's default
    by default.  Relative error control down to the size of the small components near the saddle (they
    carry the answer)."""
    from mech.problems.motion import Motion

    I = np.array([p.I1, p.I2, p.I3])
    w0 = np.array([np.sin(p.delta), np.cos(p.delta), 0.0])
    rhs = euler_omega_rhs(I)
    # a generous bound on each leg: the slowest linear rate, times the logarithm of the initial tilt
    t_max = 1e3 * (40.0 + abs(np.log(abs(w0[0]) + 1e-300))) / min(_rates(I, 1.0).values())
    sep0 = _separatrix_distance(I, w0)
    limit = SEPARATRIX_DRIFT_LIMIT * (exercise.default_rtol if rtol is None else rtol)

    def w3(t, y):
        return y[2]

    def drift(t, y):
        return abs(_separatrix_distance(I, y) / sep0 - 1.0) - limit

    def leg(k, t0, y0):
        direction, name = CROSSINGS[k]

        def then(path):
            if k + 1 == len(CROSSINGS) or len(path.traj.t_events[1]):
                return None
            t_ev, y_ev = first_event(path.traj, 0)
            return leg(k + 1, t_ev, y_ev)

        return Motion(rhs, y0, (t0, t0 + t_max), t_scale=1.0 / p.omega0, y_scale=p.omega0,
                      options={"events": [Event(w3, direction=direction, name=name),
                                          Event(drift, direction=+1, name="drift")]},
                      y_size=abs(w0[0]) * np.linalg.norm(w0), then=then)

    return leg(0, 0.0, w0)


def _period_by_integration(I, m, rtol, run):
    """Times of the upward crossings of omega3 = 0 at T/2 and 3T/2 (units omega0 = 1) along the declared
    motion ``m``, each confirmed with a bounded step; and the invariants' drifts."""
    end = run.follow(m)
    times, states = [], [np.asarray(m.y0, dtype=float)]
    sep0 = _separatrix_distance(I, states[0])
    for path in end.legs:
        if len(path.traj.t_events[1]):
            return times, {"separatrix distance 2EI2 - L^2": np.inf}
        hit = first_event(path.traj, 0)
        # confirm with a bounded step: a crossing pair inside one step would be missed (scipy#9228)
        t0 = path.motion.span[0]
        bounded = path.motion.starting(options={**path.motion.options, "max_step": (hit[0] - t0) / 64}, then=None)
        check = run.follow(bounded, mark=False).traj
        name = path.motion.options["events"][0].name
        if len(check.t_events[1]) or abs(first_event(check, 0)[0] - hit[0]) > 1e3 * rtol * (hit[0] - t0):
            raise NumericFailure(f"crossing '{name}' not confirmed with a bounded step")
        t_ev, y_ev = hit
        times.append(t_ev)
        states.append(y_ev)
    sep_drift = max(abs(_separatrix_distance(I, y) / sep0 - 1) for y in states)
    E = [0.5 * np.dot(I, s * s) for s in states]
    L2 = [np.dot(I * s, I * s) for s in states]
    drifts = {
        "energy": max(abs(e / E[0] - 1) for e in E),
        "|L|^2": max(abs(x / L2[0] - 1) for x in L2),
        "separatrix distance 2EI2 - L^2": sep_drift,
    }
    run.info["crossing_times_scaled"] = times
    return times, drifts


def _quarter_quadrature(I, w0, n):
    """T/4 from dt = d(omega3)/|omega3'| with omega3 = omega3_max sin(phi), geometric subdivision at phi = 0."""
    I1, I2, I3 = I
    if w0[2] != 0.0:
        raise ValueError("the quadrature starts at omega3 = 0")
    # 2 E I2 - L^2 = I1 (I2 - I1) omega1(0)^2 at omega3 = 0 = (sigma s)^2 with s = omega1(0)
    sig = np.sqrt(I1 * (I2 - I1))
    s = abs(w0[0])
    P = I2 * (I2 - I1) * w0[1] ** 2  # L^2 - 2 E I1 at omega3 = 0
    w3max = np.sqrt(P / (I3 * (I3 - I1)))
    w2coef = np.sqrt(I3 * (I3 - I1) / (I2 * (I2 - I1))) * w3max  # omega2 = w2coef cos(phi)
    b = np.sqrt(I3 * (I3 - I2))
    pre = w3max * I3 / ((I2 - I1) * w2coef) * sig  # times 1/(sigma |omega1|)

    def dt_dphi(phi):
        # |d omega3/dt| = (I2 - I1) |omega1 omega2| / I3, d omega3 = w3max cos(phi) d phi,
        # sigma |omega1| = hypot(sigma s, b omega3) from E and L^2
        return pre / np.hypot(sig * s, b * w3max * np.sin(phi))

    def dt_du(u):
        # the same below phi0 with phi = s u (d phi = s du), where sin(s u) = s u to round-off: the
        # factor s cancels, so a tilt down to the smallest double keeps its digits
        return pre / np.hypot(sig, b * w3max * u)

    x01, w01 = gauss_legendre(n, 0.0, 1.0)

    def rule(f, edges):
        hi, lo = edges[:-1], edges[1:]
        x = lo[:, None] + (hi - lo)[:, None] * x01[None, :]
        return float(np.sum((hi - lo)[:, None] * w01[None, :] * f(x)))

    def halving(top, floor):
        edges = [top]
        while edges[-1] > floor:
            edges.append(edges[-1] / 2)
        return edges

    # upper part in phi, halving from pi/2 down to phi0, where sin(phi) = phi to round-off
    # and phi0/s stays finite
    phi0 = min(1e-8, s * 1e300)
    up = np.array(halving(np.pi / 2, phi0))
    # the rest, [0, up[-1]], in u = phi/s, halving toward the width sigma/(b w3max) of the singular region
    low = np.array(halving(up[-1] / s, 1e-3 * sig / (b * w3max)) + [0.0])
    total = rule(dt_dphi, up) + rule(dt_du, low)
    return total, len(up) + len(low) - 2


@exercise.numeric
def numeric(p, run):
    # moments as given: rescaling them would round I2 and spoil I3 - I2 for a near-symmetric body
    I = np.array([p.I1, p.I2, p.I3])
    out = _rates(I, 1.0, run)

    w0 = np.array([np.sin(p.delta), np.cos(p.delta), 0.0])
    # below a tilt of 1e-4 the separatrix distance is under 1e-8 of its natural size and no
    # double-precision integration keeps it: go to the quadrature at once
    try:
        if w0[0] < 1e-4:
            raise NumericFailure(f"tilt {w0[0]:.3g} too close to the separatrix for an integration")
        times, drifts = _period_by_integration(I, motion(p, run.rtol), run.rtol, run)
        trusted = drifts["separatrix distance 2EI2 - L^2"] <= SEPARATRIX_DRIFT_LIMIT * run.rtol
        if trusted:
            for name, drift in drifts.items():
                run.invariant(name, drift)
        else:
            run.info["abandoned_integration_drifts"] = drifts
    except NumericFailure as exc:
        run.info["integration_refused"] = str(exc)
        trusted = False
    if trusted:
        half_1 = times[1] - times[0]
        half_2 = times[2] - times[1]
        T = times[2] - times[0]
        run.info["half_periods_scaled"] = [half_1, half_2]
        if abs(half_1 - half_2) > 1e3 * run.rtol * T:
            raise NumericFailure(f"the two half periods differ: {half_1:.12g} and {half_2:.12g}")
        run.info["T_route"] = "integration: successive upward crossings of omega3 = 0"
    else:
        q20, nint = _quarter_quadrature(I, w0, 20)
        q30, _ = _quarter_quadrature(I, w0, 30)
        if abs(q30 - q20) > 1e-13 * q30:
            raise NumericFailure(f"the quarter-period quadrature does not settle: {q20!r} vs {q30!r}")
        T = 4.0 * q30
        run.claim("T_period", rel=1e-12)
        run.info["T_route"] = f"quarter-cycle quadrature on {nint} geometric intervals (the integration was not trusted here)"
        run.method = run.method or "Gauss-Legendre quadrature"
    result = {k: v * p.omega0 for k, v in out.items()}
    result["T_period"] = T / p.omega0
    return result
