"""5.6 Period of a pendulum at finite amplitude.

Analytic (exact): T = 4 K(m)/omega0, m = sin^2(theta0/2), omega0 = sqrt(g/l),
K the complete elliptic integral of the first kind, evaluated as
ellipkm1(cos^2(theta0/2)) with cos(theta0/2) = sin(phi0/2), phi0 = pi - theta0
taken against the true pi (math.pi plus its rounding residue), so the
separatrix approach keeps its digits.  T/T0 = (2/pi) K.  The frequency shift,
2 pi/T - omega0 = omega0 (AGM(1, cos(theta0/2)) - 1) (from K = pi/(2 AGM)), is
computed as the deviation of the AGM from 1, carried through the iteration, so
a tiny shift is not lost.  Small amplitude: domega ~ -omega0 theta0^2/16 (relative
error O(theta0^2)); near the top T ~ (4/omega0) ln(8/phi0) (logarithmic divergence).

Numeric: theta'' = -omega0^2 sin theta from rest at theta0, in tau = omega0 t, with the polar angle
psi = atan2(v, theta) of the phase point (theta, v = -theta') as the independent variable: it grows
monotonically, dpsi/dtau = (theta sin theta + v^2)/(theta^2 + v^2) > 0 away from the origin, from 0 at the
start to pi/2 at the bottom theta = 0, so the quarter period is the end of the fixed span [0, pi/2] for
every variant and an ensemble of pendulums integrates together (DOP853, ``integrate_ensemble``).  The clock
is carried as its excess over psi, E = tau - psi, with dE/dpsi = theta (theta - sin theta)/(theta sin theta +
v^2) (theta - sin theta by its series at small theta): T = 4 (pi/2 + E)/omega0 and
domega = -omega0 E/(pi/2 + E), with no difference of nearly equal numbers even at a tiny amplitude.
Above 90 degrees the angle is carried as the deviation phi = pi - theta from the upright position, which
keeps the small offset phi0 to full relative accuracy.  The energy is monitored, and theta = 0 at
psi = pi/2 (the polar angle the clock assumed) checked.  The declared motion (``motion``: the same quarter
swing in the time, to the event theta = 0) is what a trajectory and the scene show.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "5.6",
    formulas=[
        "T = 4 K(sin²(θ₀/2)) (l/g)^½",
        "T/T₀ = (2/π) K(sin²(θ₀/2)) ≈ 1 + θ₀²/16 + 11θ₀⁴/3072",
        "δω = 2π/T − ω₀ = ω₀ [AGM(1, cos(θ₀/2)) − 1] ≈ −ω₀ θ₀²/16",
        "θ₀ → π: T ≈ (4/ω₀) ln(8/(π − θ₀))",
    ],
    route_note=(
        "The quarter period is integrated with the phase point's polar angle as the independent variable (its "
        "end, the bottom, at the fixed angle pi/2 for every pendulum, so many integrate together), the clock's "
        "excess over that angle carried as a state: T - T0 and the frequency shift keep their relative digits "
        "at a tiny amplitude without a separate quadrature of the period integral."
    ),
    # a quarter swing from rest at theta0 down to the bottom
    states=[("theta", "rad"), ("theta_dot", "rad/s")],
)

PI_LO = 1.2246467991473532e-16  # pi - math.pi


def _phi0(theta0):
    return (math.pi - theta0) + PI_LO


@exercise.approximations
def approximations(p):
    """The statement asks for the leading-order correction at small amplitude: T = T0 (1 + theta0^2/16),
    the frequency shift -omega0 theta0^2/16."""
    T0 = 2.0 * math.pi * math.sqrt(p.l / p.g)
    c = p.theta0**2 / 16.0
    return {"T": [(T0 * (1.0 + c), "the small-amplitude period 2 pi sqrt(l/g) (1 + theta0^2/16)")],
            "T_ratio": [(1.0 + c, "the small-amplitude ratio 1 + theta0^2/16")],
            "domega": [(-math.sqrt(p.g / p.l) * c, "the leading-order shift -omega0 theta0^2/16")]}


def _arrays(P):
    return (np.asarray(P[k], dtype=float) for k in ("theta0", "l", "g"))


@exercise.analytic
def analytic(P):
    """T = 4 K/omega0 (K by ellipkm1 of cos^2(theta0/2)), T/T0 and the shift from the AGM's deviation, over
    arrays of variants."""
    from mech.solvers.numerics.batch import Column
    from mech.solvers.numerics.special import ellipkm1

    theta0, l, g = _arrays(P)
    w0 = np.sqrt(g) / np.sqrt(l)  # roots apart: g/l leaves the range where w0 does not
    c = np.sin(_phi0(theta0) / 2.0)  # cos(theta0/2)
    K = np.asarray(ellipkm1(c * c), dtype=float)
    # AGM(1, c) as 1 - alpha: the means a, b and their deviations alpha, beta from 1 carried side by side,
    # each new pair formed from whichever is accurate: while a b >= 1/2, 1 - sqrt(a b) from the deviations
    # (a tiny shift is not lost in 1 - AGM); below, sqrt(a b) from the means themselves (near the top
    # c = cos(theta0/2) ~ 1e-12, and 1 - a b formed from the deviations held c only to 1e-16/c: domega
    # came out 6.5e-8 off at theta0 = pi - 3e-12)
    a, b = np.ones_like(c), c
    alpha, beta = np.zeros_like(c), 2.0 * np.sin(theta0 / 4.0) ** 2  # 1 - cos(theta0/2)
    live = np.ones(c.shape, dtype=bool)
    for _ in range(60):
        near = a * b >= 0.5
        x = alpha + beta - alpha * beta  # 1 - a b
        beta_near = x / (1.0 + np.sqrt(np.abs(1.0 - x)))
        root = np.sqrt(a * b)
        b_next, beta_next = np.where(near, 1.0 - beta_near, root), np.where(near, beta_near, 1.0 - root)
        a, alpha = np.where(live, 0.5 * (a + b), a), np.where(live, 0.5 * (alpha + beta), alpha)
        b, beta = np.where(live, b_next, b), np.where(live, beta_next, beta)
        live &= ~(np.abs(alpha - beta) <= 1e-17 * np.abs(alpha))
        if not live.any():
            break
    return {"T": Column(4.0 * K / w0), "T_ratio": Column(2.0 * K / math.pi), "domega": Column(-w0 * alpha)}


# theta - sin(theta) = theta^3 (1/3! - theta^2/5! + ...): the series' coefficients, the last first (Horner); seven
# terms reach 2e-18 of the sum at theta = 0.3
_SERIES = [(-1.0) ** k / math.factorial(2 * k + 3) for k in range(6, -1, -1)]


def _theta_minus_sin(theta):
    """theta - sin(theta) over arrays, by its series below 0.3 (no cancellation at a small swing)."""
    t2 = theta * theta
    series = _SERIES[0]
    for c in _SERIES[1:]:
        series = series * t2 + c
    return np.where(np.abs(theta) < 0.3, theta * t2 * series, theta - np.sin(theta))


@exercise.motion
def motion(p):
    """A quarter swing from rest at theta0 down to the bottom, in tau = omega0 t; above 90 degrees in the
    deviation phi = pi - theta from upright (phi'' = sin phi, event phi = pi), which keeps a small
    offset phi0 to full relative accuracy."""
    from mech.problems.motion import Motion

    w0 = math.sqrt(p.g) / math.sqrt(p.l)  # roots apart: g/l leaves the range where w0 does not
    th0 = p.theta0
    # the energy range explored, U(theta0) - U(0) = 2 sin^2(theta0/2) in units m g l: the energy's scale
    drop = 2.0 * math.sin(th0 / 2.0) ** 2
    if th0 <= math.pi / 2.0:
        def rhs(t, y):
            return np.array([y[1], -math.sin(y[0])])

        event = Event(lambda t, y: y[0], direction=-1, name="theta = 0")
        start = [th0, 0.0]
        scale = th0
        energy = lambda y: (0.5 * y[1] ** 2 - math.cos(y[0])) / drop  # noqa: E731
        to_states = None
    else:
        def rhs(t, y):
            return np.array([y[1], math.sin(y[0])])

        event = Event(lambda t, y: y[0] - math.pi, direction=1, name="phi = pi")
        start = [_phi0(th0), 0.0]
        scale = 1.0
        energy = lambda y: (0.5 * y[1] ** 2 + math.cos(y[0])) / drop  # noqa: E731
        to_states = lambda y: [math.pi - y[0], -y[1]]  # noqa: E731
    span = 8.0 * (math.pi + math.log(1.0 + 8.0 / _phi0(th0)))
    # Integrator: DOP853 at rtol 1e-10 (tolerance 1e-8), kept after `mech bench 5.6`: the fewest evaluations
    # with an error well under the tolerance (the verification reruns at rtol/10).
    return Motion(rhs, start, (0.0, span), event=event, invariants={"energy": energy},
                  t_scale=1.0 / w0, y_scale=[1.0, w0], to_states=to_states,
                  y_size=[min(scale, start[0]), scale])


def _swing_rhs(high):
    """The right-hand side in the polar angle psi of the phase point, state (x, v, E) with x = theta (or
    phi = pi - theta where ``high``), v = -theta' and E = tau - psi, over arrays of variants (or one)."""
    def rhs(psi, y):
        x, v = y[0], y[1]
        theta = np.where(high, math.pi - x, x)
        s = np.sin(x)  # sin(theta) = sin(phi)
        excess = theta * _theta_minus_sin(theta) / (theta * s + v * v)  # dE/dpsi
        clock = 1.0 + excess  # dtau/dpsi = (theta^2 + v^2)/(theta sin theta + v^2)
        return np.array([np.where(high, 1.0, -1.0) * v * clock, s * clock, excess])

    return rhs


def _quarter_swings(theta0, rtol, tally):
    """(x, v, E) at psi = pi/2 for every variant (``_swing_rhs``, all at once: ``Tally.follow``), and each
    variant's failure (None: none), its own alone."""
    high = theta0 > math.pi / 2.0
    x0 = np.where(high, _phi0(theta0), theta0)
    n = theta0.size
    y0 = np.stack([x0, np.zeros(n), np.zeros(n)])
    # sizes: x from x0 (a small offset from upright keeps its digits), v ~ theta0 (1 above 90 degrees),
    # E ~ (pi/2) theta0^2/16 at a small swing
    atol = 1e-3 * rtol * np.stack([x0, np.where(high, 1.0, theta0), math.pi * theta0**2 / 32.0])
    got = tally.follow(lambda sel: _swing_rhs(high[sel]), (0.0, 0.5 * math.pi), y0, rtol=rtol, atol=atol,
                       on_failure="mark")
    y_end = np.where(got.failed, np.nan, got.y_end)
    return y_end, high, list(got.why)


@exercise.batched(("T", "T_ratio", "domega"))
def numeric(P, rtol, outputs, tally=None):
    """The quarter swings of N pendulums at once (a one-point solve is the batch of one), each from its own
    equation of motion in the phase point's polar angle (``_quarter_swings``); the energy and the bottom
    theta = 0 at psi = pi/2 checked per variant, a variant beyond its claim failing alone."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    theta0, l, g = _arrays(P)
    w0 = np.sqrt(g) / np.sqrt(l)  # roots apart: g/l leaves the range where w0 does not
    (x, v, E), high, why = _quarter_swings(theta0, rtol, tally)
    allowed = exercise.tol_factor * rtol
    with np.errstate(invalid="ignore", divide="ignore"):
        theta_end = np.where(high, math.pi - x, x)
        # the energy v^2/2 + 2 sin^2(theta/2) (from the bottom) against its value at rest, the drop
        # 2 sin^2(theta0/2) = 2 cos^2(phi0/2) (in phi above 90 degrees: no rounding of theta0 near pi)
        drop = 2.0 * np.where(high, np.cos(_phi0(theta0) / 2.0), np.sin(theta0 / 2.0)) ** 2
        energy = (0.5 * v * v + 2.0 * np.sin(theta_end / 2.0) ** 2) / drop - 1.0
        bottom = np.abs(theta_end) / np.abs(v)  # the polar angle's departure from pi/2 at its end
        quarter = 0.5 * math.pi + E
    tally.invariant("energy", energy)
    tally.invariant("theta = 0 at psi = pi/2", bottom)
    tally.info["period_route"] = ["clock in the phase point's polar angle: T/4 = pi/2 + E"] * theta0.size
    ran = np.array([w is None for w in why])
    failed = [(np.array([w == text for w in why]), text) for text in sorted({w for w in why if w})]
    failed += [(ran & ~(np.abs(energy) <= allowed), f"the energy drifted by more than {allowed:.3g}"),
               (ran & ~(bottom <= allowed), "the swing did not reach theta = 0 at the polar angle pi/2 "
                                            "(the clock's variable is off)")]
    values = {"T": 4.0 * quarter / w0, "T_ratio": quarter / (0.5 * math.pi), "domega": -w0 * E / quarter}
    return {o: Column(values[o], rel=allowed, failed=failed) for o in outputs}

@exercise.hamiltonian
def hamiltonian(p):
    """For the symplectic rows of ``mech bench``: H = p²/2 - cos θ in τ = ω₀ t (separable), from rest at θ₀
    to the first downward passage through θ = 0, a quarter period; T, T/T₀ and δω read from it."""
    from mech.solvers.numerics.symplectic import SeparableHamiltonian

    w0 = math.sqrt(p.g) / math.sqrt(p.l)  # roots apart: g/l leaves the range where w0 does not

    def readout(t, q, mom):
        T = 4.0 * t / w0
        return {"T": T, "T_ratio": T * w0 / (2.0 * math.pi), "domega": 2.0 * math.pi / T - w0}

    return SeparableHamiltonian(
        velocity=lambda mom: mom,
        force=lambda q: -math.sin(q),
        energy=lambda q, mom: 0.5 * mom * mom - math.cos(q),
        q0=float(p.theta0),
        p0=0.0,
        t_max=8.0 * (math.pi + math.log(1.0 + 8.0 / _phi0(p.theta0))),
        readout=readout,
        event=lambda q, mom: q,
        direction=-1,
        time_scale=1.0,
        name="pendulum quarter swing",
    )


@exercise.scene
def scene(p, run):
    """The phase portrait (contours of the energy, the separatrix, the swing at theta0: the declared quarter
    swing and its mirror images, by time reversal and parity) and the period's rise with the amplitude,
    angles in degrees throughout."""
    from mech.problems.scene import Axis, Line, Markers, Panel, Scene

    H = hamiltonian(p)  # H = p^2/2 - cos(theta) in tau = omega0 t: its energy draws the levels
    deg = 180.0 / math.pi
    w0 = math.sqrt(p.g) / math.sqrt(p.l)  # roots apart: g/l leaves the range where w0 does not
    m, path = run.motion(p)
    q1, v1 = m.si(path.traj.sol(np.linspace(0.0, path.t_end, 750)))  # theta0 down to 0, theta' <= 0
    v1 = v1 / w0
    q = np.concatenate([q1, -q1[::-1], -q1, q1[::-1]])
    mom = np.concatenate([v1, v1[::-1], -v1, -v1[::-1]])
    phase = Panel("phase portrait: levels of the energy", Axis("θ", "deg"), Axis("θ' / ω0"), legend="upper right")
    th = np.linspace(-1.25 * math.pi, 1.25 * math.pi, 400)
    u = np.array([H.energy(x, 0.0) for x in th])  # the potential energy
    for level in np.linspace(-0.9, 2.4, 12):  # energy levels in units of m g l
        for sign in (1, -1):
            v2 = 2.0 * (level - u)
            v = np.where(v2 >= 0, sign * np.sqrt(np.abs(v2)), np.nan)
            phase.add(Line(th * deg, v, kind="level"))
    sep = 2.0 * (H.energy(math.pi, 0.0) - u)
    for sign in (1, -1):
        phase.add(Line(th * deg, sign * np.sqrt(np.maximum(sep, 0.0)), "separatrix" if sign > 0 else None,
                       color="C2", width=1.3))
    phase.add(Line(q * deg, mom, f"the swing at θ0 = {p.theta0 * deg:.4g}°, integrated", kind="trajectory"))
    phase.y.lim = (-2.7, 3.4)
    xs = np.linspace(0.02, math.pi - 1e-3, 300)
    curve = run.series(p, "theta0", xs)
    period = Panel("the period grows with the amplitude", Axis("amplitude θ0", "deg"), Axis("T / T0"),
                   legend="upper left")
    period.add(Line(xs * deg, curve["T_ratio"], "analytic (elliptic K)"),
               Line(xs * deg, 1 + xs**2 / 16, "small-swing estimate 1 + θ0²/16", kind="reference"))
    pts = run.numeric_points(0.2, math.pi - 0.05)
    if len(pts):
        period.add(Markers(pts * deg, run.series(p, "theta0", pts, numeric=True)["T_ratio"], "numeric"))
    nv = run.numeric(p)
    if nv:
        period.add(Markers([p.theta0 * deg], [nv["T_ratio"]]))
    period.add(Markers([p.theta0 * deg], [run.analytic(p)["T_ratio"]], "this swing", kind="this"))
    return Scene([phase, period], on_axis=("theta0",))
