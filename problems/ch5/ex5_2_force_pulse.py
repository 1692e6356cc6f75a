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
exactly tau = omega0 T with non-terminal events x' = 0 (its turning points);
absolute tolerances are scaled to the size of the state during the pulse,
(omega0 T)^2 for x and omega0 T for x'.  The free leg starts from the state at
T: its amplitude is sqrt(x^2 + x'^2) there, checked against the largest |x|
over one free period from events x' = 0.  x at t1 > T comes from the free
flow map: the 2x2 fundamental matrix integrated numerically over h =
(tau1 - tauT)/N and raised to the power N (linear autonomous flow), so that a
reading hundreds of periods in costs one short integration.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.ode import Event, integrate

exercise = Exercise(
    "5.2",
    formulas=[
        "q(t) = 2 q_st sin²(ω₀t/2),  0 ≤ t ≤ T   (q_st = F₀/(m ω₀²))",
        "q(t) = 2 q_st sin(ω₀T/2) sin ω₀(t − T/2),  t ≥ T",
        "A_after = 2 |q_st| |sin(ω₀T/2)|",
        "q_max = 2 |q_st| if ω₀T ≥ π, else A_after",
    ],
)


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


def _forced(t, y):
    return np.array([y[1], 1.0 - y[0]])


def _free(t, y):
    return np.array([y[1], -y[0]])


def _free_stack(t, y):
    # two copies of the free equation side by side: the columns of the fundamental matrix
    return np.array([y[1], -y[0], y[3], -y[2]])


@exercise.numeric
def numeric(p, run):
    qst = p.F0 / (p.m * p.omega0**2)
    tau_T = p.omega0 * p.T
    tau_1 = p.omega0 * p.t1
    rtol = run.rtol
    # size of the state during the pulse: x ~ min(2, tau^2/2), x' ~ min(1, tau)
    sx = min(2.0, tau_T**2 / 2.0)
    sv = min(1.0, tau_T)
    atol = [rtol * 1e-3 * sx, rtol * 1e-3 * sv]

    # forced leg, never stepping across the switch-off at tau_T; split at tau_1 when it falls inside
    turning = Event(lambda t, y: y[1], terminal=False, name="x' = 0")
    max_step = tau_T / 8.0 if tau_T < 1 else 1.0
    stops = [0.0] + ([tau_1] if 0.0 < tau_1 < tau_T else []) + [tau_T]
    state = np.array([0.0, 0.0])
    turn_x, x1 = [], (0.0 if tau_1 == 0.0 else None)
    for a, b in zip(stops[:-1], stops[1:]):
        leg1 = integrate(_forced, (a, b), state, rtol=rtol, atol=atol, events=[turning], max_step=max_step)
        run.record(leg1)
        if leg1.t_end != b:
            raise NumericFailure("the forced leg did not reach its end")
        state = leg1.y_end
        turn_x += [abs(y[0]) for y in leg1.y_events[0]] if leg1.y_events else []
        if b == tau_1:
            x1 = state[0]
    xT, vT = state
    # invariant of the forced leg: x'^2/2 + (x - 1)^2/2
    run.invariant("energy (pulse)", ((vT**2 + (xT - 1.0) ** 2) / 2.0 - 0.5) / 0.5)
    x_max_pulse = max([abs(xT)] + turn_x)

    # free leg: amplitude from the state at T, checked over one free period
    amp = math.hypot(xT, vT)
    period = 2.0 * math.pi
    leg2 = integrate(_free, (tau_T, tau_T + period), [xT, vT], rtol=rtol,
                     atol=rtol * 1e-3 * max(amp, 1e-300), events=[turning])
    run.record(leg2)
    free_turns = [abs(y[0]) for y in leg2.y_events[0]] if leg2.y_events else []
    tol_amp = 1e3 * rtol * sx + 1e3 * rtol * amp
    if amp > tol_amp:
        if not free_turns:
            raise NumericFailure("no turning point found in one free period")
        if abs(max(free_turns) - amp) > tol_amp:
            raise NumericFailure(
                f"free amplitude {amp:.12g} from the state at T but {max(free_turns):.12g} from turning points")
    run.info["free_turning_points_in_one_period"] = len(free_turns)

    if tau_1 > tau_T:
        # fundamental matrix of the free flow over h, then its N-th power
        span = tau_1 - tau_T
        n = max(1, 2 ** int(math.ceil(math.log2(max(span / 1.0, 1.0)))))
        h = span / n
        fm = integrate(_free_stack, (0.0, h), [1.0, 0.0, 0.0, 1.0], rtol=min(rtol, 1e-13),
                       atol=1e-16)
        run.record(fm)
        phi = np.array([[fm.y_end[0], fm.y_end[2]], [fm.y_end[1], fm.y_end[3]]])
        run.invariant("det of the free flow map (Liouville)", np.linalg.det(phi) - 1.0)
        state = np.linalg.matrix_power(phi, n) @ np.array([xT, vT])
        run.info["free_flow_steps"] = n
        run.invariant("energy (free)", (math.hypot(*state) - amp) / max(amp, 1e-300) if amp > 0 else 0.0)
        x1 = state[0]

    s_scale = min(2.0, tau_T)  # size of the state at T relative to q_st
    run.claim("A_after", rel=exercise.tol_factor * rtol, abs=exercise.tol_factor * rtol * abs(qst) * s_scale)
    run.claim("q_t", rel=exercise.tol_factor * rtol,
              abs=exercise.tol_factor * rtol * abs(qst) * (sx if tau_1 <= tau_T else s_scale))
    return {"A_after": abs(qst) * amp, "q_max": abs(qst) * max(x_max_pulse, amp), "q_t": qst * x1}
