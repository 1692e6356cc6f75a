"""4.15 Sliding ladder: the angle at which it leaves the wall.

Analytic: with both ends in contact the ladder has one coordinate, theta.
Energy gives dtheta/dt^2 = (3g/l)(sin theta0 - sin theta); the wall's force is
M times the horizontal acceleration of the center, which is proportional to
cos theta (3/2 sin theta - sin theta0); it vanishes first at
sin theta_c = (2/3) sin theta0, where omega_c^2 = (g/l) sin theta0.

Numeric: Newton-Euler for the rigid rod, not the Lagrangian: at each instant the
three unknowns (the angular acceleration and the two normal forces) solve the
linear system of the center's two equations of motion and the torque about the
center, with the center's acceleration tied to theta by the contacts, in units
M = l = g = 1 (the run does not depend on l or g).  The integration stops at the event N_wall = 0 (confirmed with a bounded step).
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "4.15",
    formulas=[
        "sin θc = (2/3) sin θ₀",
        "ω_c = (g sin θ₀ / l)^(1/2)",
        "(from θ'² = (3g/l)(sin θ₀ - sin θ) and N_wall ∝ cos θ (3/2 sin θ - sin θ₀))",
    ],
    states=[("theta", "rad"), ("omega", "rad/s")],
)

# Start this close below the upright position on the energy-conserving path:
# the upright ladder is an equilibrium that an integrator would never leave.
UPRIGHT_NUDGE = 1e-6


def _log10_rates(p):
    """log10 of (g/l)^(1/2) and of omega_c = (g sin theta0 / l)^(1/2), summed in logs: no overflow."""
    unit = 0.5 * (math.log10(p.g) - math.log10(p.l))
    return unit, unit + 0.5 * math.log10(math.sin(p.theta0))


exercise.declare_limits(
    "theta0 >= 1e-300 rad",
    "(g/l)^(1/2) and omega_c between 1e-300 and 1e300: the rates within the floating-point range",
)


@exercise.constraint
def constraint(p):
    if p.theta0 < 1e-300:
        return f"theta0 = {p.theta0:.3g} rad is below 1e-300: the angles leave the floating-point range"
    unit, omega_c = _log10_rates(p)
    if abs(unit) > 300 or abs(omega_c) > 300:
        return (f"(g/l)^(1/2) = 10^{unit:.0f} 1/s, omega_c = 10^{omega_c:.0f} rad/s: "
                "the rates leave the floating-point range")


@exercise.analytic
def analytic(p):
    s0 = math.sin(p.theta0)
    return {"theta_c": math.asin(2.0 * s0 / 3.0),
            "omega_c": math.sqrt(s0) * math.sqrt(p.g) / math.sqrt(p.l)}


def _accelerations(theta, omega, M, l, g):
    """(theta'', N_wall, N_floor) from Newton's laws for the rod with both ends on the walls."""
    s, c = math.sin(theta), math.cos(theta)
    I_cm = M * l**2 / 12.0
    # center (x, y) = (l/2 cos theta, l/2 sin theta): x'' = -(l/2)(s th'' + c w^2), y'' = (l/2)(c th'' - s w^2)
    # unknowns u = (theta'', N_wall, N_floor):
    #   M x'' = N_wall ;  M y'' = N_floor - M g
    #   the rod's orientation angle is pi - theta, so -I_cm theta'' = torque about the center:
    #   torque = -(l/2) s N_wall + (l/2) c N_floor
    # The system's first two rows give the forces in terms of theta'' (a unit column each), so the
    # elimination is done by hand, in floats: np.linalg.solve on a 3x3 cost half of the numeric solve
    # (measured with scripts/perf_budget.py --overhead: 53 % in numpy, the right-hand side called ~1200 times).
    #   N_wall = b1 - (M l/2) s theta'',  N_floor = b2 + (M l/2) c theta''   (rows 1, 2)
    #   row 3: -I_cm theta'' + (l/2) s N_wall - (l/2) c N_floor = 0
    b1 = -M * l / 2 * c * omega**2
    b2 = M * g - M * l / 2 * s * omega**2
    th_dd = (l / 2) * (s * b1 - c * b2) / (I_cm + M * l**2 / 4 * (s * s + c * c))
    return th_dd, b1 - M * l / 2 * s * th_dd, b2 + M * l / 2 * c * th_dd


def _energy(theta, omega, M, l, g):
    """T + U summed from the center's motion (speed l omega / 2) and the rotation about it."""
    v2 = (l / 2 * omega) ** 2
    return 0.5 * M * v2 + 0.5 * (M * l**2 / 12.0) * omega**2 + M * g * l / 2 * np.sin(theta)


def _start(theta0):
    """(theta, omega) at the start, units M = l = g = 1: at rest at theta0, or, within UPRIGHT_NUDGE of
    the upright equilibrium (which an integrator would never leave), UPRIGHT_NUDGE below it on the
    energy-conserving path."""
    if np.pi / 2 - theta0 >= UPRIGHT_NUDGE:
        return theta0, 0.0
    theta = theta0 - UPRIGHT_NUDGE
    e0, u = _energy(theta0, 0.0, 1.0, 1.0, 1.0), _energy(theta, 0.0, 1.0, 1.0, 1.0)
    return theta, -np.sqrt((e0 - u) / (_energy(theta, 1.0, 1.0, 1.0, 1.0) - u))


@exercise.motion
def motion(p):
    """The ladder from its start until the wall lets go.  Units M = l = g = 1: the mass cancels from every
    output and l, g only set the time unit (l/g)^(1/2), so the run is the same for every l and g.  A small
    start angle falls for a time of order theta0^(1/2) at speeds of that order, so the state is integrated
    as (theta/theta0, omega/theta0^(1/2)) in time t/theta0^(1/2), each of order one for any theta0."""
    from mech.problems.motion import Motion

    M, l, g = 1.0, 1.0, 1.0
    a_s, w_s = p.theta0, math.sqrt(p.theta0)
    theta_start, omega_start = _start(p.theta0)

    def rhs(t, y):
        # d(theta/a_s)/d(t/w_s) = omega/w_s, d(omega/w_s)/d(t/w_s) = theta'' (a_s = w_s^2)
        return np.array([y[1], _accelerations(a_s * y[0], w_s * y[1], M, l, g)[0]])

    def wall_force(t, y):
        return _accelerations(a_s * y[0], w_s * y[1], M, l, g)[1] / a_s

    def energy(y):
        """(T + U) / (theta0 M g l / 2): of order one for any theta0."""
        return _energy(a_s * y[0], w_s * y[1], M, l, g) / a_s / (M * g * l / 2)

    w_unit = math.sqrt(p.g) / math.sqrt(p.l)
    # Integrator: DOP853 at rtol 1e-10 (tolerance 1e-8), kept after `mech bench 4.15`: fewest evaluations
    # for an error well under the tolerance.
    return Motion(rhs, [theta_start / a_s, omega_start / w_s], (0.0, 200.0),
                  event=Event(wall_force, direction=-1, name="N_wall = 0"), invariants={"energy": energy},
                  t_scale=w_s * math.sqrt(p.l) / math.sqrt(p.g), y_scale=[a_s, w_s * w_unit],
                  event_scale=a_s * p.g)  # the wall's force in SI for a mass of 1 kg


@exercise.numeric
def numeric(p, run):
    m = motion(p)
    end = run.follow(m)
    theta_c, omega_c = m.si(end.y_end)
    run.info["t_c"] = end.t_end * m.t_scale
    return {"theta_c": theta_c, "omega_c": abs(omega_c)}


@exercise.hamiltonian
def hamiltonian(p):
    """For the symplectic rows of ``mech bench``.  With both ends in contact the center moves on a circle of
    radius l/2, so T = (1/2)(M l²/4 + M l²/12) θ'² = (M l²/6) θ'² does not depend on θ: H = 3 p²/(2 M l²)
    + (M g l/2) sin θ is separable.  Units M = l = 1, τ = (g/l)^½ t: θ' = 3p, p' = -(1/2) cos θ.  The wall's
    force is M x'' with x = (l/2) cos θ: N ∝ -(sin θ θ'' + cos θ θ'²) = cos θ ((3/2) sin θ - θ'²), so the
    event is (3/2) sin θ - θ'² falling through zero.  Started where the declared motion starts."""
    from mech.solvers.numerics.symplectic import SeparableHamiltonian

    theta, omega = _start(p.theta0)
    w_unit = math.sqrt(p.g) / math.sqrt(p.l)
    return SeparableHamiltonian(
        velocity=lambda mom: 3.0 * mom,
        force=lambda q: -0.5 * np.cos(q),
        energy=lambda q, mom: _energy(q, 3.0 * mom, 1.0, 1.0, 1.0),
        q0=float(theta),
        p0=float(omega / 3.0),
        t_max=200.0,
        readout=lambda t, q, mom: {"theta_c": q, "omega_c": abs(3.0 * mom) * w_unit},
        event=lambda q, mom: 1.5 * np.sin(q) - 9.0 * mom * mom,
        direction=-1,
        time_scale=1.0,
        name="ladder until the wall lets go",
    )


@exercise.scene
def scene(p, run):
    """The wall's force against the angle along the declared motion, up to the loss of contact; and the
    ladder drawn at equal steps of angle."""
    from mech.problems.scene import Axis, Guide, Line, Markers, Note, Panel, Scene

    l = p.l
    m, path = run.motion(p)
    # the angle runs from theta0 down to theta_c; sample it evenly in angle, not in time (most of the
    # time is spent near the upright start)
    ys = path.traj.sol(np.linspace(0.0, path.t_end, 4000))
    (th, w), y_c = m.si(ys), m.si(path.y_end)
    theta = th[0]
    M, g = 1.0, p.g
    N = np.array([_accelerations(a, b, M, l, g)[1] for a, b in zip(th, w)]) / (M * g)
    deg = 180.0 / np.pi
    a = run.analytic(p)
    nv = run.numeric(p)
    force = Panel("the wall's push, while both ends touch", Axis("θ, the ladder's angle from the floor", "deg"),
                  Axis("wall's force N / (M g)"), legend="upper left")
    force.add(
        Line(th * deg, N, "Newton-Euler, integrated", kind="trajectory"),
        Guide(0.0, axis="y", dashed=False, color="0.3"),
        Markers([a["theta_c"] * deg], [0.0], f"analytic θc = {a['theta_c'] * deg:.5g}°", kind="analytic"),
        Markers([nv["theta_c"] * deg] if nv else [], [0.0],
                f"numeric θc = {nv['theta_c'] * deg:.5g}°" if nv else None, kind="numeric"),
        Note("the top leaves the wall", (a["theta_c"] * deg, 0.0), text_at=(0.42, 0.25)),
    )
    force.x.lim = (max(th[0], p.theta0) * deg + 2.0, y_c[0] * deg - 5.0)  # time runs left to right
    sketch = Panel("the ladder at equal steps of θ; red: at θc", Axis("x", "m"), Axis("y", "m"),
                   equal_aspect=True, legend="none")
    steps = np.linspace(max(theta, y_c[0]), y_c[0], 6)
    for k, tk in enumerate(steps):
        last = k == len(steps) - 1
        sketch.add(Line([0.0, l * np.cos(tk)], [l * np.sin(tk), 0.0], kind="drawing",
                        color="C3" if last else None, width=2.4 if last else None))
    sketch.add(Line([0.0, 0.0, 1.08 * l], [1.08 * l, 0.0, 0.0], kind="drawing", color="k", width=2.0))
    sketch.x.lim = sketch.y.lim = (-0.05 * l, 1.1 * l)
    caption = f"ω at θc: analytic {a['omega_c']:.6g} rad/s" + (f", numeric {nv['omega_c']:.6g} rad/s" if nv else "")
    if theta < p.theta0:
        caption += f"; started {UPRIGHT_NUDGE:g} rad below upright (an equilibrium)"
    return Scene([force, sketch], caption=caption)
