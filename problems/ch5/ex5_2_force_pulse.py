"""5.2 Rectangular force pulse on an undamped oscillator.

Analytic: with q_st = F0/(m omega0^2), during the pulse q = q_st (1 - cos omega0 t)
= 2 q_st sin^2(omega0 t/2); after it the two step responses superpose to
q = q_st [cos omega0 (t - T) - cos omega0 t] = 2 q_st sin(omega0 T/2) sin omega0 (t - T/2).
So A_after = 2 |q_st| |sin(omega0 T/2)|, and q_max = 2 |q_st| if omega0 T >= pi
(the forced leg reaches its full swing 2 q_st) and A_after otherwise (then
2 sin^2 <= 2 |sin|).  Half-angle forms avoid the cancellation in 1 - cos.

Numeric: the equation of motion in the scaled variables x = q/q_st,
tau = omega0 t (x'' + x = 1 during the pulse, x'' + x = 0 after it), which is
linear, so q = q_st x.  Written once over arrays of variants (``numeric``: N pulses
at once, a one-point solve the batch of one), each variant's stepped part put on
s = tau/L in [0, 1].  The forced leg is integrated with DOP853 from rest to
tau = omega0 T, or over its first free period 2 pi when the pulse is longer
(the state is back at rest there, checked, and the motion repeats), with
events x' = 0 (its turning point) and tau = omega0 t1 (the reading); absolute tolerances are
scaled to the size of the state during the pulse, (omega0 T)^2 for x and
omega0 T for x'.  A longer pulse is carried to its end by the exact flow of its
linear equation, the matrix exponential of its generator in (x, x', 1)
(solvers/numerics/linear_flow), never stepped through millions of periods.  The free
leg starts from the state at T: its amplitude is sqrt(x^2 + x'^2) there,
checked against |x| at its turning point over one free period (event x' = 0); x at
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
def analytic(P):
    """The closed forms over arrays of variants, each with its phases' round-off (``_rounding``)."""
    from mech.solvers.numerics.batch import Column

    m, w0, F0, T, t1 = _arrays(P)
    qst = F0 / (m * w0**2)
    phi = w0 * T
    s = np.sin(phi / 2.0)
    a_after = 2.0 * np.abs(qst) * np.abs(s)
    q_max = np.where(phi >= math.pi, 2.0 * np.abs(qst), a_after)
    q_t = np.where(t1 <= T, 2.0 * qst * np.sin(w0 * t1 / 2.0) ** 2, 2.0 * qst * s * np.sin(w0 * (t1 - T / 2.0)))
    err = _rounding(qst, w0, T, t1)
    return {"A_after": Column(a_after, abs=err["A_after"]), "q_max": Column(q_max, abs=err["q_max"]),
            "q_t": Column(q_t, abs=err["q_t"])}


def _arrays(P):
    return (np.asarray(P[k], dtype=float) for k in ("m", "omega0", "F0", "T", "t1"))


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


def _rounding(qst, w0, T, t1):
    """Round-off of the closed forms from their phases: sin of a phase phi computed in floats is off by
    ~ u phi (the products omega0 t and the differences t1 - T/2 are rounded), so each value moves by its
    slope, at most 2 |q_st|, times 2 u (1 + phi) per phase it contains."""
    e_T = 2.0 * np.abs(qst) * 2.0 * _U * (1.0 + w0 * T)
    e_1 = 2.0 * np.abs(qst) * 2.0 * _U * (1.0 + w0 * t1)
    return {"A_after": e_T, "q_max": e_T, "q_t": e_1 + e_T}


@exercise.analytic_error
def analytic_error(p):
    """``_rounding`` at one point (the same bars the analytic Columns carry over arrays)."""
    return {k: float(v) for k, v in _rounding(p.F0 / (p.m * p.omega0**2), p.omega0, p.T, p.t1).items()}


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


def _pulse_rhs(L):
    """x'' + x = 1 in s = tau/L (each variant's stepped part of the pulse, L = min(omega0 T, 2 pi), onto [0, 1])."""
    def rhs(s, y):
        return np.array([L * y[1], L * (1.0 - y[0])])

    return rhs


def _free_rhs(s, y):
    return np.array([y[1], -y[0]])


def _pulse_energy(x, v):
    """x'^2/2 + (x - 1)^2/2 of the forced equation, relative to its value 1/2 at rest."""
    return ((v**2 + (x - 1.0) ** 2) / 2.0 - 0.5) / 0.5


def _flow_at(generator, taus, state):
    """exp(G tau) applied to one state per variant (n x N): the exact flow of a linear equation."""
    from mech.solvers.numerics.linear_flow import expm_many

    return np.einsum("kij,jk->ik", expm_many(generator, taus), state)


@exercise.batched(("A_after", "q_max", "q_t"))
def numeric(P, rtol, outputs, tally=None):
    """N pulses at once (a one-point solve is the batch of one): the stepped pulse (its first free period at
    most) with its turning point and the reading at t1 as events, a longer pulse carried by the exact flow,
    then one free period from the state at T with its turning point; each variant's claims, invariants and
    failures its own (``Tally.follow``)."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import BatchEvent, Column
    from mech.solvers.numerics.linear_flow import rounding_bound

    tally = Tally() if tally is None else tally
    m, w0, F0, T, t1 = _arrays(P)
    n = m.size
    qst = F0 / (m * w0**2)
    tau_T, tau_1 = w0 * T, w0 * t1
    period = 2.0 * math.pi
    L = np.minimum(tau_T, period)
    # size of the state during the pulse: x ~ min(2, tau^2/2), x' ~ min(1, tau) (floored: see ``motion``)
    sx = np.maximum(np.minimum(2.0, tau_T**2 / 2.0), 1e-290)
    sv = np.minimum(1.0, tau_T)
    s1 = np.where(tau_1 < L, tau_1 / L, 2.0)  # the reading inside the stepped part (2: never)
    pulse = tally.follow(lambda sel: _pulse_rhs(L[sel]), (0.0, 1.0), np.zeros((2, n)), rtol=rtol, atol=1e-3 * rtol * np.stack([sx, sv]),
                         events=[BatchEvent(lambda s, y: y[1], direction=-1, name="x' = 0"),
                                 BatchEvent(lambda s, y: s - s1, direction=1, name="t = t1")], on_failure="mark")
    why = list(pulse.why)
    x_turn = np.abs(pulse.y_events[0][0])  # NaN: no turning point in the stepped part
    long = tau_T > period
    xT, vT = pulse.y_end
    err_T, err_1 = np.zeros(n), np.zeros(n)
    tally.invariant("return to rest after one free period of the pulse", np.where(long, np.hypot(xT, vT) / 2.0, 0.0))
    if long.any():  # the exact flow of the pulse's linear equation carries it to its end (and to t1 inside it)
        at_rest = np.tile(np.array([[0.0], [0.0], [1.0]]), (1, n))
        flowT = _flow_at(_PULSE_GENERATOR, np.where(long, tau_T, 0.0), at_rest)
        xT, vT = np.where(long, flowT[0], xT), np.where(long, flowT[1], vT)
        err_T = np.where(long, 3.0 * rounding_bound(_PULSE_GENERATOR, tau_T), 0.0)
    inside = (tau_1 >= L) & (tau_1 <= tau_T)  # read in the flowed part of the pulse
    x1 = np.where(tau_1 == 0.0, 0.0, pulse.y_events[1][0])
    if inside.any():
        at_rest = np.tile(np.array([[0.0], [0.0], [1.0]]), (1, n))
        x1 = np.where(inside, _flow_at(_PULSE_GENERATOR, np.where(inside, tau_1, 0.0), at_rest)[0], x1)
        err_1 = np.where(inside, 3.0 * rounding_bound(_PULSE_GENERATOR, tau_1), 0.0)
    allowed = exercise.tol_factor * rtol
    tally.invariant("energy (pulse)", _pulse_energy(xT, vT), allowed=allowed + err_T)
    # the free leg: its amplitude from the state at T, checked against its turning point over one period
    amp = np.hypot(xT, vT)
    free = tally.follow(lambda sel: _free_rhs, (0.0, period), np.stack([xT, vT]), rtol=rtol,
                        atol=1e-3 * rtol * np.stack([np.maximum(amp, 1e-300)] * 2),
                        events=[BatchEvent(lambda s, y: y[1], name="x' = 0")], on_failure="mark")
    why = [a or b for a, b in zip(why, free.why)]
    free_turn = np.abs(free.y_events[0][0])
    tol_amp = 1e3 * rtol * (sx + amp)
    checked = amp > tol_amp
    missed = checked & np.isnan(free_turn)
    off = checked & (np.abs(free_turn - amp) > tol_amp)
    s_scale = np.minimum(2.0, tau_T)  # size of the state at T relative to q_st
    after = tau_1 > tau_T
    if after.any():  # the free flow over t1 - T, exact for the linear equation up to its round-off
        span = np.where(after, w0 * (t1 - T), 0.0)
        state1 = _flow_at(_FREE_GENERATOR, span, np.stack([xT, vT]))
        x1 = np.where(after, state1[0], x1)
        err_1 = np.where(after, err_T + rounding_bound(_FREE_GENERATOR, span) * amp, err_1)
        with np.errstate(invalid="ignore", divide="ignore"):
            drift = np.where(after & (amp > 0), (np.hypot(*state1) - amp) / np.maximum(amp, 1e-300), 0.0)
        tally.invariant("energy (free)", drift, allowed=allowed + err_1 / np.maximum(amp, 1e-300))
    q_scale = np.where(after, s_scale, sx)
    x_max = np.fmax(np.fmax(np.abs(xT), x_turn), amp)
    aq = np.abs(qst)
    failed = [(np.array([w == text for w in why], dtype=bool), text) for text in sorted({w for w in why if w})]
    failed += [(missed, "no turning point found in one free period"),
               (off, "the free amplitude from the state at T and from its turning point disagree"),
               (np.isnan(x1) & ~np.array([bool(w) for w in why]), "the reading at t1 was not reached")]
    values = {"A_after": aq * amp, "q_max": aq * x_max, "q_t": qst * x1}
    claims = {"A_after": aq * (allowed * s_scale + err_T), "q_max": aq * err_T, "q_t": aq * (allowed * q_scale + err_1)}
    return {o: Column(values[o], rel=allowed, abs=claims[o], failed=failed) for o in outputs}
