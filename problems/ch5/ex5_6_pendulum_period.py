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

Numeric: theta'' = -omega0^2 sin theta from rest at theta0 to the event theta = 0
(a quarter period), DOP853 in tau = omega0 t; above 90 degrees in the deviation
phi = pi - theta from the upright position (phi'' = sin phi, event phi = pi),
which keeps the small offset phi0 to full relative accuracy.  The energy is
monitored.  For theta0 < 1 rad, domega comes from a quadrature (scipy quad) of the
period integral minus its harmonic counterpart, with theta = theta0 sin u and the
integrand F - 1 = (F^2 - 1)/(F + 1), F^2 = 1/(sinc a sinc b),
a, b = (theta0 -+ theta)/2, and 1 - sinc by its series: no difference of nearly
equal numbers is formed.
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


@exercise.analytic
def analytic(p):
    from mech.solvers.numerics.special import ellipkm1

    w0 = math.sqrt(p.g) / math.sqrt(p.l)  # roots apart: g/l leaves the range where w0 does not
    c = math.sin(_phi0(p.theta0) / 2.0)  # cos(theta0/2)
    K = float(ellipkm1(c * c))
    # AGM(1, c) as 1 - alpha: the means a, b and their deviations alpha, beta from 1 carried side by side,
    # each new pair formed from whichever is accurate: while a b >= 1/2, 1 - sqrt(a b) from the deviations
    # (a tiny shift is not lost in 1 - AGM); below, sqrt(a b) from the means themselves (near the top
    # c = cos(theta0/2) ~ 1e-12, and 1 - a b formed from the deviations held c only to 1e-16/c: domega
    # came out 6.5e-8 off at theta0 = pi - 3e-12)
    a, b = 1.0, c
    alpha, beta = 0.0, 2.0 * math.sin(p.theta0 / 4.0) ** 2  # 1 - cos(theta0/2)
    for _ in range(60):
        if a * b >= 0.5:
            x = alpha + beta - alpha * beta  # 1 - a b
            beta_next = x / (1.0 + math.sqrt(1.0 - x))
            b_next = 1.0 - beta_next
        else:
            b_next = math.sqrt(a * b)
            beta_next = 1.0 - b_next
        a, alpha = 0.5 * (a + b), 0.5 * (alpha + beta)
        b, beta = b_next, beta_next
        if abs(alpha - beta) <= 1e-17 * abs(alpha):
            break
    return {"T": 4.0 * K / w0, "T_ratio": 2.0 * K / math.pi, "domega": -w0 * alpha}


def _one_minus_sinc(x):
    if abs(x) < 0.3:
        x2, term, total = x * x, x * x / 6.0, 0.0
        for k in range(1, 12):
            total += term
            term *= -x2 / ((2 * k + 2) * (2 * k + 3))
        return total
    return 1.0 - math.sin(x) / x


def _period_excess(theta0):
    """(T - T0) omega0 by quadrature of the period integral minus the harmonic one; also its error estimate."""
    from mech.solvers.numerics.quadrature import quad

    def integrand(u):
        th = theta0 * math.sin(u)
        a = theta0 * math.sin(math.pi / 4.0 - u / 2.0) ** 2  # (theta0 - theta)/2
        b = (theta0 + th) / 2.0
        sa, sb = 1.0 - _one_minus_sinc(a), 1.0 - _one_minus_sinc(b)
        f2m1 = (_one_minus_sinc(a) + sa * _one_minus_sinc(b)) / (sa * sb)
        f = math.sqrt(1.0 + f2m1)
        return f2m1 / (f + 1.0)

    val, err = quad(integrand, 0.0, math.pi / 2.0, epsabs=0.0, epsrel=1e-13, limit=200)
    return 4.0 * val, 4.0 * err


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


@exercise.numeric
def numeric(p, run):
    w0 = math.sqrt(p.g) / math.sqrt(p.l)  # roots apart: g/l leaves the range where w0 does not
    rtol = run.rtol
    th0 = p.theta0
    t_q = run.follow(motion(p)).t_end
    T = 4.0 * t_q / w0
    T0 = 2.0 * math.pi / w0
    out = {"T": T, "T_ratio": T / T0}
    if th0 < 1.0:
        excess, err = _period_excess(th0)
        out["domega"] = -w0 * excess / (2.0 * math.pi + excess)
        run.claim("domega", rel=max(1e-12, 10.0 * err / excess))
        run.info["domega_route"] = "quadrature of T - T0"
    else:
        out["domega"] = 2.0 * math.pi / T - w0
        run.claim("domega", rel=exercise.tol_factor * rtol * (2.0 * math.pi / T) / abs(out["domega"]))
    if not math.isfinite(T):
        raise NumericFailure("no finite quarter period")
    return out


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
