"""5.2 Rectangular force pulse on an undamped oscillator.

Analytic: with q_st = F0/(m omega0^2), during the pulse q = q_st (1 - cos omega0 t)
= 2 q_st sin^2(omega0 t/2); after it the two step responses superpose to
q = q_st [cos omega0 (t - T) - cos omega0 t] = 2 q_st sin(omega0 T/2) sin omega0 (t - T/2).
So A_after = 2 |q_st| |sin(omega0 T/2)|, and q_max = 2 |q_st| if omega0 T >= pi
(the forced leg reaches its full swing 2 q_st) and A_after otherwise (then
2 sin^2 <= 2 |sin|).  Half-angle forms avoid the cancellation in 1 - cos.

Numeric: the equation of motion in the scaled variables x = q/q_st,
tau = omega0 t (x'' + x = 1 during the pulse, x'' + x = 0 after it), which is
linear, so q = q_st x.  The forced leg is integrated with DOP853 from rest to
tau = omega0 T, or over its first free period 2 pi when the pulse is longer
(the state is back at rest there, checked, and the motion repeats), with
non-terminal events x' = 0 (its turning points); absolute tolerances are
scaled to the size of the state during the pulse, (omega0 T)^2 for x and
omega0 T for x'.  A longer pulse is carried to its end by the exact flow of its
linear equation, the matrix exponential of its generator in (x, x', 1)
(solvers/numerics/linear_flow), never stepped through millions of periods.  The free
leg starts from the state at T: its amplitude is sqrt(x^2 + x'^2) there,
checked against the largest |x| over one free period from events x' = 0; x at
t1 > T is the free flow's matrix exponential over omega0 (t1 - T) applied to
the state at T.  The stepped pulse and the free leg are the declared motion
(``motion``, in legs); after a longer pulse the free leg is followed as a check
only.  A phase Theta of 1e6..1e15 rad is known in floats to u Theta only, in
both methods: the claims and ``analytic_error`` carry that round-off,
and a phase beyond 1e15 rad is refused.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "5.2",
    formulas=[
        "q(t) = 2 q_st sin²(ω₀t/2),  0 ≤ t ≤ T   (q_st = F₀/(m ω₀²))",
        "q(t) = 2 q_st sin(ω₀T/2) sin ω₀(t − T/2),  t ≥ T",
        "A_after = 2 |q_st| |sin(ω₀T/2)|",
        "q_max = 2 |q_st| if ω₀T ≥ π, else A_after",
    ],
    # from rest through the pulse (its first free period when the pulse is longer: the motion then
    # repeats) and one free period after it
    states=[("q", "m"), ("v", "m/s")],
)

# the static displacement is the route's unit of length (and the error estimate's)
ranges.declare(exercise, ranges.Scale("F0/(m omega0^2)", {"F0": 1, "m": -1, "omega0": -2}, "the static displacement"))


@exercise.analytic
def analytic(p):
    qst = p.F0 / (p.m * p.omega0**2)
    phi = p.omega0 * p.T
    s = math.sin(phi / 2.0)
    a_after = 2.0 * abs(qst) * abs(s)
    q_max = 2.0 * abs(qst) if phi >= math.pi else a_after
    if p.t1 <= p.T:
        q_t = 2.0 * qst * math.sin(p.omega0 * p.t1 / 2.0) ** 2
    else:
        q_t = 2.0 * qst * s * math.sin(p.omega0 * (p.t1 - p.T / 2.0))
    return {"A_after": a_after, "q_max": q_max, "q_t": q_t}


# the pulse's equation x'' + x = 1 as an autonomous linear system in (x, x', 1), and the free one in (x, x')
_PULSE_GENERATOR = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 1.0], [0.0, 0.0, 0.0]])
_FREE_GENERATOR = np.array([[0.0, 1.0], [-1.0, 0.0]])
_U = 2.0**-53
MAX_PHASE = 1e15  # rad: beyond it the phase's round-off (u * phase) reaches a tenth of a radian


def _forced(t, y):
    return np.array([y[1], 1.0 - y[0]])


def _free(t, y):
    return np.array([y[1], -y[0]])


exercise.declare_limits(
    f"omega0 t1 <= {MAX_PHASE:g} rad and omega0 T <= {MAX_PHASE:g} rad: the phases carry a digit in double precision",
)


@exercise.constraint
def constraint(p):
    for name, phase in (("omega0 t1", p.omega0 * p.t1), ("omega0 T", p.omega0 * p.T)):
        if phase > MAX_PHASE:
            return (f"the phase {name} = {phase:.3g} rad carries no significant digit in double precision "
                    f"(its round-off u * phase exceeds 0.1 rad; at most {MAX_PHASE:g} rad)")


@exercise.analytic_error
def analytic_error(p):
    """Round-off of the closed forms from their phases: sin of a phase phi computed in floats is off by
    ~ u phi (the products omega0 t and the differences t1 - T/2 are rounded), so each value moves by its
    slope, at most 2 |q_st|, times 2 u (1 + phi) per phase it contains."""
    qst = abs(p.F0 / (p.m * p.omega0**2))
    e_T = 2.0 * qst * 2.0 * _U * (1.0 + p.omega0 * p.T)
    e_1 = 2.0 * qst * 2.0 * _U * (1.0 + p.omega0 * p.t1)
    return {"A_after": e_T, "q_max": e_T, "q_t": e_1 + e_T}


_TURNING = Event(lambda t, y: y[1], terminal=False, name="x' = 0")  # the turning points of either leg


def _free_leg(p, state):
    """One free period after the pulse from the state (x, x') at tau = omega0 T, with its turning points."""
    from mech.problems.motion import Motion

    qst = p.F0 / (p.m * p.omega0**2)
    tau_T = p.omega0 * p.T
    amp = math.hypot(*state)
    return Motion(_free, [state[0], state[1]], (tau_T, tau_T + 2.0 * math.pi), options={"events": [_TURNING]},
                  y_size=max(amp, 1e-300), t_scale=1.0 / p.omega0, y_scale=[qst, qst * p.omega0])


@exercise.motion
def motion(p):
    """From rest through the pulse, then one free period, in x = q/q_st and tau = omega0 t.  The forced leg
    never steps across the switch-off at tau_T and is split at tau_1 when it falls inside (x is read there).
    Only its first free period is stepped: the state then returns to rest and the motion repeats, so a
    longer pulse is carried to its end by the exact flow (``numeric``) and its free leg is a check, not the
    scene's motion (None follows the stepped pulse then)."""
    from mech.problems.motion import Motion

    qst = p.F0 / (p.m * p.omega0**2)
    tau_T = p.omega0 * p.T
    tau_1 = p.omega0 * p.t1
    # size of the state during the pulse: x ~ min(2, tau^2/2), x' ~ min(1, tau)
    # (for tau_T below 1e-145 the scale of x, tau_T^2/2, falls under 1e-290 of q_st: floored there, where x
    # (with x' ~ tau_T beside it) no longer moves any answer; an absolute tolerance of 0 would shrink the
    # steps without end)
    sx = max(min(2.0, tau_T**2 / 2.0), 1e-290)
    sv = min(1.0, tau_T)
    period = 2.0 * math.pi
    stepped = min(tau_T, period)
    max_step = stepped / 8.0 if stepped < 1 else 1.0
    stops = [0.0] + ([tau_1] if 0.0 < tau_1 < stepped else []) + [stepped]

    def after_pulse(path):  # one free period from the state at T, unless the pulse outlasts the stepped part
        return _free_leg(p, path.y_end) if tau_T <= period else None

    def pulse(k, state):
        then = after_pulse if k + 2 == len(stops) else (lambda path: pulse(k + 1, path.y_end))
        return Motion(_forced, state, (stops[k], stops[k + 1]),
                      options={"events": [_TURNING], "max_step": max_step}, y_size=[sx, sv],
                      t_scale=1.0 / p.omega0, y_scale=[qst, qst * p.omega0], then=then)

    return pulse(0, np.array([0.0, 0.0]))


def _pulse_energy(x, v):
    """x'^2/2 + (x - 1)^2/2 of the forced equation, relative to its value 1/2 at rest."""
    return ((v**2 + (x - 1.0) ** 2) / 2.0 - 0.5) / 0.5


@exercise.numeric
def numeric(p, run):
    from mech.solvers.numerics.linear_flow import expm, rounding_bound

    qst = p.F0 / (p.m * p.omega0**2)
    tau_T = p.omega0 * p.T
    tau_1 = p.omega0 * p.t1
    rtol = run.rtol
    period = 2.0 * math.pi

    # the declared motion: the stepped pulse (its first free period at most) and, after a pulse that short,
    # the free leg
    path = run.follow(motion(p))
    forced = [leg for leg in path.legs if leg.motion.rhs is _forced]
    sx = forced[0].motion.y_size[0]  # the size of x during the pulse
    turn_x, x1 = [], (0.0 if tau_1 == 0.0 else None)
    for leg in forced:
        if leg.t_end != leg.motion.span[1]:
            raise NumericFailure("the forced leg did not reach its end")
        turn_x += [abs(y[0]) for y in leg.traj.y_events[0]] if leg.traj.y_events else []
        if leg.motion.span[1] == tau_1:
            x1 = leg.y_end[0]
    state = forced[-1].y_end
    x_max_pulse = max([abs(state[0])] + turn_x)
    err_T = err_1 = 0.0  # round-off of the states at T and t1 from the long-span flow, relative to q_st
    if tau_T > period:
        run.invariant("return to rest after one free period of the pulse", math.hypot(*state) / 2.0)
        run.info["pulse_flow"] = "exact flow of the linear equation (matrix exponential)"
        xT, vT = (expm(_PULSE_GENERATOR * tau_T) @ np.array([0.0, 0.0, 1.0]))[:2]
        err_T = 3.0 * rounding_bound(_PULSE_GENERATOR, tau_T)
        if x1 is None and tau_1 <= tau_T:
            x1 = (expm(_PULSE_GENERATOR * tau_1) @ np.array([0.0, 0.0, 1.0]))[0]
            err_1 = 3.0 * rounding_bound(_PULSE_GENERATOR, tau_1)
        # the free leg from the flow's state at T: the amplitude's check, not joined to the stepped pulse
        free = run.follow(_free_leg(p, [xT, vT]), mark=False)
    else:
        xT, vT = state
        free = path
    # invariant of the forced leg, exact for the flow up to its round-off
    run.invariant("energy (pulse)", _pulse_energy(xT, vT), allowed=exercise.tol_factor * rtol + err_T)

    # free leg: amplitude from the state at T, checked over one free period
    amp = math.hypot(xT, vT)
    free_turns = [abs(y[0]) for y in free.traj.y_events[0]] if free.traj.y_events else []
    tol_amp = 1e3 * rtol * sx + 1e3 * rtol * amp
    if amp > tol_amp:
        if not free_turns:
            raise NumericFailure("no turning point found in one free period")
        if abs(max(free_turns) - amp) > tol_amp:
            raise NumericFailure(
                f"free amplitude {amp:.12g} from the state at T but {max(free_turns):.12g} from turning points")
    run.info["free_turning_points_in_one_period"] = len(free_turns)

    s_scale = min(2.0, tau_T)  # size of the state at T relative to q_st
    if tau_1 > tau_T:
        # the free flow over t1 - T, exact for the linear equation up to its round-off
        span = p.omega0 * (p.t1 - p.T)
        state1 = expm(_FREE_GENERATOR * span) @ np.array([xT, vT])
        err_1 = err_T + rounding_bound(_FREE_GENERATOR, span) * amp
        run.invariant("energy (free)", (math.hypot(*state1) - amp) / max(amp, 1e-300) if amp > 0 else 0.0,
                      allowed=exercise.tol_factor * rtol + err_1 / max(amp, 1e-300))
        x1 = state1[0]
    q_scale = s_scale if tau_1 > tau_T else sx

    tol = exercise.tol_factor * rtol
    run.claim("A_after", rel=tol, abs=abs(qst) * (tol * s_scale + err_T))
    run.claim("q_max", rel=tol, abs=abs(qst) * err_T)
    run.claim("q_t", rel=tol, abs=abs(qst) * (tol * q_scale + err_1))
    return {"A_after": abs(qst) * amp, "q_max": abs(qst) * max(x_max_pulse, amp), "q_t": qst * x1}
