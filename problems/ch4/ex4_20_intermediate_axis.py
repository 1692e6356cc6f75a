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
lambda_2 (checked).  T_period: the Euler equations (in units of omega0) with
the orbit's phase psi = atan2(a omega3, b omega2) as the independent variable
(a^2 = I3 (I3 - I1), b^2 = I2 (I2 - I1): psi turns monotonically on an orbit
circling n1) and the time as a fourth variable, from omega(0) (psi = 0,
omega3 = 0 crossing down) over two legs to psi = -pi (omega3 = 0 crossing up,
T/2) and -2 pi (T): the crossings are the ends of fixed spans, no event to
locate; relative error control reaching down to the size of the small
components, at rtol/10 (PHASE_RTOL); energy, |L|^2 and the orbit's distance
from the separatrix, 2 E I2 - L^2 (evaluated as sum I_i (I2 - I_i) omega_i^2,
free of cancellation), are monitored at the crossings and the two half
periods must agree.  When that distance drifts by more than 10 rtol of itself
(tiny d: the orbit hugs the separatrix; a tilt below 1e-4 is not even tried),
the integration is not trusted and the period is instead four
times the quarter-cycle quadrature of d(omega3)/|d(omega3)/dt| from omega3 = 0
to its maximum, with omega1^2 and omega2^2 from the conserved E and L^2,
omega3 = omega3_max sin(phi), Gauss-Legendre on intervals halving toward the
logarithmically singular end phi = 0 (checked against a lower-order rule);
below phi ~ 1e-8 the variable is phi/sin(delta), so that even a subnormal
tilt keeps its digits.  The route is written once over arrays of variants
(the flips integrated together, the quadratures on padded arrays of
intervals; a one-point solve the batch of one); a variant that fails fails
alone.  The declared motion (what a trajectory shows) is the flip in time,
leg by leg to the crossings of omega3 = 0 as events.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise
from mech.solvers.mechanics.freebody import euler_omega_rhs, steady_rotation_pair
from mech.solvers.mechanics.inertia import gauss_legendre
from mech.solvers.numerics.ode import Event, first_event
from mech.solvers.numerics.special import agm

_agm = np.vectorize(agm, otypes=[float])  # the one-point AGM at each variant (a scalar iteration)

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
# the flips are integrated at this fraction of rtol (``numeric``)
PHASE_RTOL = 0.1


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
def analytic(P):
    """Over arrays of variants."""
    from mech.solvers.numerics.batch import Column

    I1, I2, I3, w, delta = (np.asarray(P[k], dtype=float) for k in ("I1", "I2", "I3", "omega0", "delta"))
    s, c = np.sin(delta), np.cos(delta)
    D = I1 * (I3 - I1) * s * s + I2 * (I3 - I2) * c * c
    ratio = np.sqrt(I1 * (I3 - I1) / D)
    kp = ratio * s  # not from its square: a tilt below 1e-154 would underflow
    # below k' = 1e-100, K = ln(4/k') + O(k'^2 ln k') exactly in double precision, with the logarithm split
    # so that a subnormal tilt keeps its digits; above, K(k) from the complementary modulus k'
    with np.errstate(divide="ignore"):
        K = np.where(kp < 1e-100, np.log(4.0) - np.log(ratio) - np.log(s),
                     math.pi / (2.0 * _agm(1.0, np.maximum(kp, 1e-100))))
    T = 4.0 * K / w * np.sqrt(I1 * I2 * I3 / ((I2 - I1) * D))
    return {
        "Omega_1": Column(w * np.sqrt((I2 - I1) * (I3 - I1) / (I2 * I3))),
        "lambda_2": Column(w * np.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))),
        "Omega_3": Column(w * np.sqrt((I3 - I1) * (I3 - I2) / (I1 * I2))),
        "T_period": Column(T),
    }


def _rates(I):
    """Omega_1, lambda_2, Omega_3 (units omega0 = 1) from the Jacobian eigenvalues at the three steady
    rotations, over arrays of bodies (I: 3 x N): ({name: rate}, {axis: eigenvalues N x 3}, failures)."""
    out, eigen, failures = {}, {}, []
    for k, name, kind in ((0, "Omega_1", "imag"), (1, "lambda_2", "real"), (2, "Omega_3", "imag")):
        la, lb, eigen[k] = steady_rotation_pair(I, k, 1.0)
        mag = np.maximum(np.abs(la), np.abs(lb))
        part, other = (np.imag, np.real) if kind == "imag" else (np.real, np.imag)
        pair = (np.maximum(np.abs(other(la)), np.abs(other(lb))) <= 1e-12 * mag) & (
            np.abs(part(la) + part(lb)) <= 1e-12 * mag)
        what = "an imaginary pair" if kind == "imag" else "a real pair +-lambda"
        failures.append((~pair, f"the eigenvalues at n{k + 1} are not {what}"))
        out[name] = 0.5 * (np.abs(part(la)) + np.abs(part(lb)))
    return out, eigen, failures


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
    t_max = 1e3 * (40.0 + abs(np.log(abs(w0[0]) + 1e-300))) / min(float(r[0]) for r in _rates(I[:, None])[0].values())
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


def _phase_rhs(I):
    """``make_rhs(sel)`` of the Euler equations with the phase psi = atan2(a omega3, b omega2) as the independent
    variable (a^2 = I3 (I3 - I1), b^2 = I2 (I2 - I1): b^2 omega2^2 + a^2 omega3^2 = L^2 - 2 E I1 is conserved, so
    psi is the angle around the orbit's ellipse), for the state [omega(3), t]: d/dpsi = (d/dt) / psi', with
    psi' = a b omega1 (c3 omega2^2 - c2 omega3^2) / (b^2 omega2^2 + a^2 omega3^2), of one sign (two terms of
    one sign: no cancellation) on an orbit circling n1.  I: 3 x N."""
    def make_rhs(sel):
        I1, I2, I3 = (I[k, sel] for k in range(3))
        c1, c2, c3 = (I2 - I3) / I1, (I3 - I1) / I2, (I1 - I2) / I3
        a2, b2 = I3 * (I3 - I1), I2 * (I2 - I1)
        ab = np.sqrt(a2 * b2)

        def rhs(psi, y):
            w1, w2, w3 = y[0], y[1], y[2]
            inv = (b2 * w2 * w2 + a2 * w3 * w3) / (ab * w1 * (c3 * w2 * w2 - c2 * w3 * w3))
            return np.array([c1 * w2 * w3 * inv, c2 * w3 * w1 * inv, c3 * w1 * w2 * inv, inv])

        return rhs

    return make_rhs


def _half_periods(I, w0, t_size, rtol, tally):
    """The times (units omega0 = 1) at which the flips from w0 (3 x N) come back to omega3 = 0: at psi = -pi
    (omega3 crossing up, half a period) and -2 pi (crossing down, a period), each leg a fixed span of psi (no
    event to locate); and the states there.  A variant whose integration fails is NaN (its reason in ``why``)."""
    from mech.solvers.mechanics.floquet import integrate_ensemble
    from mech.solvers.numerics.ensemble import each_alone_on_failure

    n = w0.shape[1]
    Y = np.full((3, 4, n), np.nan)
    Y[0] = np.concatenate([w0, np.zeros((1, n))])
    why = np.full(n, "", dtype=object)
    atol = 1e-3 * rtol * np.concatenate([np.broadcast_to(w0[0] * np.sqrt(np.sum(w0 * w0, axis=0)), (3, n)),
                                         t_size[None, :]])
    make_rhs = _phase_rhs(I)

    def both_legs(idx):
        """Both legs of the variants idx together (a failure followed again variant by variant)."""
        y = Y[0][:, idx]
        for k in (1, 2):
            y, results = integrate_ensemble(lambda sel: make_rhs(idx[sel]), (-(k - 1) * np.pi, -k * np.pi),
                                            y, rtol=rtol, atol=atol[:, idx], integrator=tally.integrator)
            Y[k][:, idx] = y
            for r in results:
                tally.record(r)

    go = np.flatnonzero(np.isfinite(w0).all(axis=0))
    if go.size:
        each_alone_on_failure(both_legs, go, why)
    return Y, why


def _invariant_drifts(I, Y):
    """The worst relative drift over the states Y (3 samples x 4 x N) of the energy, |L|^2 and the separatrix
    distance 2 E I2 - L^2 (evaluated as sum I_i (I2 - I_i) omega_i^2, free of cancellation)."""
    W = Y[:, 0:3].transpose(1, 0, 2)  # 3 components x samples x N
    Ik = I[:, None, :]
    sep = _separatrix_distance(I[:, None, :], W)
    E = 0.5 * np.sum(Ik * W * W, axis=0)
    L2 = np.sum((Ik * W) ** 2, axis=0)
    def drift(x):
        return np.max(np.abs(x / x[0] - 1.0), axis=0)

    return {"energy": drift(E), "|L|^2": drift(L2), "separatrix distance 2EI2 - L^2": drift(sep)}


def _halving(top, floor):
    """Edges top, top/2, ... down to the first at or below floor, per variant (N x M, each row padded with its
    last edge: zero-width intervals)."""
    e = np.array(top, dtype=float)
    cols = [e.copy()]
    while True:
        more = e > floor
        if not more.any():
            return np.stack(cols, axis=1)
        e[more] /= 2
        cols.append(e.copy())


def _quarter_quadrature(I, s, c, n):
    """T/4 from dt = d(omega3)/|omega3'| with omega3 = omega3_max sin(phi), geometric subdivision at phi = 0,
    over arrays (I: 3 x N, s = sin(delta), c = cos(delta) of the start at omega3 = 0): (T/4, intervals)."""
    I1, I2, I3 = I
    # 2 E I2 - L^2 = I1 (I2 - I1) omega1(0)^2 at omega3 = 0 = (sigma s)^2
    sig = np.sqrt(I1 * (I2 - I1))
    P = I2 * (I2 - I1) * c**2  # L^2 - 2 E I1 at omega3 = 0
    w3max = np.sqrt(P / (I3 * (I3 - I1)))
    w2coef = np.sqrt(I3 * (I3 - I1) / (I2 * (I2 - I1))) * w3max  # omega2 = w2coef cos(phi)
    b = np.sqrt(I3 * (I3 - I2))
    pre = (w3max * I3 / ((I2 - I1) * w2coef) * sig)[:, None, None]  # times 1/(sigma |omega1|)
    sig_, s_, bw = sig[:, None, None], s[:, None, None], (b * w3max)[:, None, None]

    def dt_dphi(phi):
        # |d omega3/dt| = (I2 - I1) |omega1 omega2| / I3, d omega3 = w3max cos(phi) d phi,
        # sigma |omega1| = hypot(sigma s, b omega3) from E and L^2
        return pre / np.hypot(sig_ * s_, bw * np.sin(phi))

    def dt_du(u):
        # the same below phi0 with phi = s u (d phi = s du), where sin(s u) = s u to round-off: the
        # factor s cancels, so a tilt down to the smallest double keeps its digits
        return pre / np.hypot(sig_, bw * u)

    x01, w01 = gauss_legendre(n, 0.0, 1.0)

    def rule(f, edges):
        hi, lo = edges[:, :-1, None], edges[:, 1:, None]
        return np.sum((hi - lo) * w01 * f(lo + (hi - lo) * x01), axis=(1, 2))

    # upper part in phi, halving from pi/2 down to phi0, where sin(phi) = phi to round-off and phi0/s stays finite
    up = _halving(np.full(s.shape, np.pi / 2), np.minimum(1e-8, s * 1e300))
    # the rest, [0, up's last edge], in u = phi/s, halving toward the width sigma/(b w3max) of the singular region
    low = _halving(up[:, -1] / s, 1e-3 * sig / (b * w3max))
    low = np.concatenate([low, np.zeros((s.size, 1))], axis=1)
    widths = np.count_nonzero(np.diff(up, axis=1), axis=1) + np.count_nonzero(np.diff(low, axis=1), axis=1)
    return rule(dt_dphi, up) + rule(dt_du, low), widths


def _period_by_quadrature(I, s, c):
    """T (units omega0 = 1) four times the quarter-cycle quadrature at 30 points an interval, checked against
    20; failures [(mask, reason)]; the intervals."""
    q20, _ = _quarter_quadrature(I, s, c, 20)
    q30, nint = _quarter_quadrature(I, s, c, 30)
    unsettled = ~(np.abs(q30 - q20) <= 1e-13 * q30)
    return 4.0 * q30, [(unsettled, "the quarter-period quadrature does not settle")], nint


@exercise.batched(("Omega_1", "lambda_2", "Omega_3", "T_period"))
def numeric(P, rtol, outputs, memo=None, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): the rates from the Jacobians'
    eigenvalues; T_period from the flips integrated together in the orbit's phase (``_half_periods``), or, where
    the tilt is below 1e-4 or the separatrix distance drifts by more than SEPARATRIX_DRIFT_LIMIT rtol of itself,
    from the quarter-cycle quadrature.  Each failure and invariant beyond the claim fails its variant alone."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    I1, I2, I3, omega0, delta = (np.asarray(P[k], dtype=float) for k in ("I1", "I2", "I3", "omega0", "delta"))
    # moments as given: rescaling them would round I2 and spoil I3 - I2 for a near-symmetric body
    I = np.stack([I1, I2, I3])
    N = delta.size
    rates, eigen, failures = _rates(I)
    for k, ev in eigen.items():
        tally.info[f"eigenvalues_n{k + 1}"] = np.array([str([str(complex(e)) for e in row]) for row in ev],
                                                       dtype=object)
    s, c = np.sin(delta), np.cos(delta)
    w0 = np.stack([s, c, np.zeros(N)])
    # below a tilt of 1e-4 the separatrix distance is under 1e-8 of its natural size and no
    # double-precision integration keeps it: go to the quadrature at once
    tried = s >= 1e-4
    # the legs at PHASE_RTOL rtol: in the phase the separatrix distance, on which the trust rests, drifts
    # ~10 times more than in time (3.6e-9 against 1.3e-10 at the defaults, rtol 1e-10)
    Y, why = _half_periods(I, np.where(tried, w0, np.nan), 1.0 / rates["Omega_1"], PHASE_RTOL * rtol, tally)
    drifts = _invariant_drifts(I, Y)
    trusted = tried & (why == "") & (drifts["separatrix distance 2EI2 - L^2"] <= SEPARATRIX_DRIFT_LIMIT * rtol)
    tol = exercise.tol_factor * rtol
    for name, drift in drifts.items():
        tally.invariant(name, np.where(trusted, drift, 0.0))
        failures.append((trusted & ~(drift <= tol), f"the invariant '{name}' drifts by more than the method "
                         "allows: the integration is not to be trusted"))
    half_1, T = Y[1, 3], Y[2, 3]
    failures.append((trusted & ~(np.abs(2.0 * half_1 - T) <= 1e3 * rtol * T), "the two half periods differ"))
    T_rel = np.full(N, tol)
    quad = np.flatnonzero(~trusted)
    routes = np.full(N, "integration: two successive crossings of omega3 = 0, the orbit's phase as the time",
                     dtype=object)
    if quad.size:
        T_q, fails, nint = _period_by_quadrature(I[:, quad], s[quad], c[quad])
        T[quad], T_rel[quad] = T_q, 1e-12
        for mask, reason in fails:
            full = np.zeros(N, dtype=bool)
            full[quad] = mask
            failures.append((full, reason))
        routes[quad] = [f"quarter-cycle quadrature on {k} geometric intervals (the integration was not trusted "
                        "here)" for k in nint]
    tally.info["T_route"] = routes
    tally.info["integration_refused"] = np.where(why == "", None, why)
    cols = {name: Column(rates[name] * omega0, rel=1e-12, failed=failures) for name in rates}
    cols["T_period"] = Column(T / omega0, rel=T_rel, failed=failures)
    return {o: cols[o] for o in outputs}
