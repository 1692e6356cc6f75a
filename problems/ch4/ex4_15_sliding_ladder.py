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
M = l = g = 1 (the run does not depend on l or g).  The route is written once over arrays of variants
(mech's DOP853 stepping them together, a one-point solve the batch of one); each variant stops at its own
event N_wall = 0, located on the step's continuous extension.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
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


ranges.declare(
    exercise,
    ranges.Scale("theta0", {"theta0": 1}, "the angles", high=math.inf),
    ranges.Scale("(g/l)^(1/2)", {"g": 0.5, "l": -0.5}, "the rates"),
    ranges.Scale("omega_c = (g sin(theta0)/l)^(1/2)", {"g": 0.5, "l": -0.5}, "the rates",
                 log_factor=lambda p: 0.5 * math.log10(math.sin(p.theta0))),
)


@exercise.analytic
def analytic(P):
    """Over arrays of variants."""
    from mech.solvers.numerics.batch import Column

    theta0, l, g = (np.asarray(P[k], dtype=float) for k in ("theta0", "l", "g"))
    s0 = np.sin(theta0)
    return {"theta_c": Column(np.arcsin(2.0 * s0 / 3.0)), "omega_c": Column(np.sqrt(s0) * np.sqrt(g) / np.sqrt(l))}


def _accelerations(theta, omega, M, l, g):
    """(theta'', N_wall, N_floor) from Newton's laws for the rod with both ends on the walls (numbers, or arrays
    of variants)."""
    s, c = np.sin(theta), np.cos(theta)
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
    """(theta, omega) at the start, units M = l = g = 1 (numbers, or arrays of variants): at rest at theta0, or,
    within UPRIGHT_NUDGE of the upright equilibrium (which an integrator would never leave), UPRIGHT_NUDGE below
    it on the energy-conserving path."""
    near = np.pi / 2 - theta0 < UPRIGHT_NUDGE
    theta = np.where(near, theta0 - UPRIGHT_NUDGE, theta0)
    e0, u = _energy(theta0, 0.0, 1.0, 1.0, 1.0), _energy(theta, 0.0, 1.0, 1.0, 1.0)
    with np.errstate(invalid="ignore"):
        omega = np.where(near, -np.sqrt((e0 - u) / (_energy(theta, 1.0, 1.0, 1.0, 1.0) - u)), 0.0)
    return (theta, omega) if np.ndim(theta) else (float(theta), float(omega))


def _units(theta0):
    """(a_s, w_s): a small start angle falls for a time of order theta0^(1/2) at speeds of that order, so the
    state is integrated as (theta/theta0, omega/theta0^(1/2)) in time t/theta0^(1/2), each of order one."""
    return theta0, np.sqrt(theta0)


def _rhs(a_s, w_s):
    """The scaled equations (units M = l = g = 1), for numbers or arrays of variants."""

    def rhs(t, y):
        # d(theta/a_s)/d(t/w_s) = omega/w_s, d(omega/w_s)/d(t/w_s) = theta'' (a_s = w_s^2)
        return np.array([y[1], _accelerations(a_s * y[0], w_s * y[1], 1.0, 1.0, 1.0)[0]])

    return rhs


def _wall(a_s, w_s):
    """The wall's force over theta0 (units M = g = 1): the event of the ladder leaving the wall."""
    return lambda t, y: _accelerations(a_s * y[0], w_s * y[1], 1.0, 1.0, 1.0)[1] / a_s


def _scaled_energy(a_s, w_s):
    """(T + U) / (theta0 M g l / 2): of order one for any theta0."""
    return lambda y: _energy(a_s * y[0], w_s * y[1], 1.0, 1.0, 1.0) / a_s / 0.5


# the scaled run's end: the wall lets go by then from any start (within UPRIGHT_NUDGE of upright: ~30)
T_MAX = 200.0


@exercise.motion
def motion(p):
    """The ladder from its start until the wall lets go.  Units M = l = g = 1: the mass cancels from every
    output and l, g only set the time unit (l/g)^(1/2), so the run is the same for every l and g (``_units``:
    scaled by theta0)."""
    from mech.problems.motion import Motion

    a_s, w_s = (float(x) for x in _units(p.theta0))
    theta_start, omega_start = _start(p.theta0)
    w_unit = math.sqrt(p.g) / math.sqrt(p.l)
    # Integrator: DOP853 at rtol 1e-10 (tolerance 1e-8), kept after `mech bench 4.15`: fewest evaluations
    # for an error well under the tolerance.
    return Motion(_rhs(a_s, w_s), [theta_start / a_s, omega_start / w_s], (0.0, T_MAX),
                  event=Event(_wall(a_s, w_s), direction=-1, name="N_wall = 0"),
                  invariants={"energy": _scaled_energy(a_s, w_s)},
                  t_scale=w_s * math.sqrt(p.l) / math.sqrt(p.g), y_scale=[a_s, w_s * w_unit],
                  event_scale=a_s * p.g)  # the wall's force in SI for a mass of 1 kg


@exercise.batched(("theta_c", "omega_c"))
def numeric(P, rtol, outputs, tally=None):
    """The ladders of N variants at once (a one-point solve is the batch of one), each in its own units
    (``_units``), stopped where its wall's force falls through zero (an event per variant on the ensemble's
    continuous extension); the energy's drift and the time of the loss of contact reported to ``tally``."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import BatchEvent, Column

    tally = Tally() if tally is None else tally
    theta0, l, g = (np.asarray(P[k], dtype=float) for k in ("theta0", "l", "g"))
    a_s, w_s = _units(theta0)
    theta, omega = _start(theta0)
    y0 = np.stack([theta / a_s, omega / w_s])
    got = tally.follow(lambda sel: _rhs(a_s[sel], w_s[sel]), (0.0, T_MAX), y0, rtol=rtol, atol=1e-3 * rtol,
                 events=[BatchEvent(_wall(a_s, w_s), direction=-1.0, terminal=True, name="N_wall = 0")])
    t_c = got.t_events[0]
    why = np.where((got.why == "") & ~np.isfinite(t_c), "the wall did not let go within the run", got.why)
    y = got.y_end
    energy = _scaled_energy(a_s, w_s)
    drift = np.abs(energy(y) - energy(y0))
    tally.invariant("energy", np.nan_to_num(drift))
    t_unit = np.sqrt(l) / np.sqrt(g)
    tally.info["t_c"] = t_c * w_s * t_unit
    failed = [(why == text, text) for text in sorted(set(why[why != ""]))]
    failed.append(((why == "") & ~(drift <= exercise.tol_factor * rtol), "the invariant 'energy' drifts by more "
                   "than the method allows: the integration is not to be trusted"))
    values = {"theta_c": y[0] * a_s, "omega_c": np.abs(y[1] * w_s) / t_unit}
    return {o: Column(values[o], rel=exercise.tol_factor * rtol, failed=failed) for o in outputs}


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
