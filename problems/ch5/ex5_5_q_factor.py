"""5.5 Energy decay of a weakly damped oscillator, its Q factor and resonance width.

Analytic (exact): Q = omega0/(2 delta).  The free motion is e^{-delta t} times a
function of period T' = 2 pi/omega_d (omega_d = sqrt(omega0^2 - delta^2)), so over
T' both q and q' shrink by e^{-delta T'} and the loss per cycle is
1 - e^{-2 delta T'} = -expm1(-4 pi delta/omega_d).  From rest at q0,
q = q0 e^{-delta t}(cos w_d t + (delta/w_d) sin w_d t), q' = -q0 (omega0^2/w_d) e^{-delta t} sin w_d t,
so E(t)/E0 = e^{-2 delta t}[(cos w_d t + (delta/w_d) sin w_d t)^2 + (omega0/w_d)^2 sin^2 w_d t].
|a|^2 is proportional to 1/((omega0^2 - omega^2)^2 + 4 delta^2 omega^2); in x = omega^2 its
half-power points are x = omega0^2 - 2 delta^2 -+ 2 delta omega_d, so the full width is
4 delta omega_d/(omega_+ + omega_-) (about 2 delta = omega0/Q), defined while the lower
point exists: delta < sin(pi/8) omega0.

Numeric (tau = omega0 t, zeta = delta/omega0, the full equation x'' + 2 zeta x' + x = 0):
* Q from the ringdown, in amplitude-phase variables x = r cos th, x' = -r sin th, in
  which the equation of motion reads th' = 1 - zeta sin 2th, (ln E)' = -4 zeta sin^2 th.
  Integrating with th as the independent variable over one cycle (th: 0 -> 2 pi, from
  one maximum of x to the next; the integrands have period pi, so over [0, pi] and
  doubled) gives the period T' between maxima and the log decrement of the energy
  directly (as l = ln(E)/zeta: no log of a ratio close to 1 is ever taken); then
  delta = -ln(E ratio)/(2 T'), omega0 = sqrt((2 pi/T')^2 + delta^2), Q = omega0/(2 delta).
* Loss per cycle: the declared motion (``motion``), (q, q') with the dissipated work W
  carried as a state, from rest at x = 1 over 1.25 cycles; W/E(0) at the next maximum
  (event x' = 0, downward); E + W monitored.  Past
  zeta = 0.9 (the motion dies by e^-13 within the cycle) -expm1 of the decrement above.
* E_ratio: the same amplitude-phase flow; t1 = m half-cycles plus a remainder, the
  half-cycle shift of ln E taken from the cycle integration and the remainder
  integrated in time (no integration over thousands of periods, no energy drift).
* Width: the steady amplitude per unit force at drive omega, from one linear
  periodic-orbit solve: the map over one drive period in the exact
  variation-of-constants variables (q = u cos wt + v sin wt), with M - I integrated
  as a deviation so that a narrow peak keeps its relative accuracy; the peak by a
  bounded Brent search in the detuning u = omega - omega0 (bracket from the ringdown's
  delta), the half-power points by brentq in u on each side, bracketed by doubling
  steps.  omega -> 0 is the static deflection under a constant force (the same
  periodic-orbit solve); the lower point is absent when the curve stays above half
  its maximum down to it.  Lower points below 0.02 omega0 (within ~1e-4 of the
  threshold) are refused as NumericFailure: one drive period spans 50 free periods.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure, Undefined

exercise = Exercise(
    "5.5",
    formulas=[
        "Q = ω₀/(2δ)",
        "loss per cycle = 1 − exp(−4πδ/ω_d),  ω_d = (ω₀² − δ²)^½  (≈ 2π/Q)",
        "E(t)/E₀ = e^{−2δt}[(cos ω_d t + (δ/ω_d) sin ω_d t)² + (ω₀/ω_d)² sin² ω_d t]",
        "FWHM of |a|²: ω∓ = (ω₀² − 2δ² ∓ 2δω_d)^½,  Δω = 4δω_d/(ω₊ + ω₋) ≈ 2δ = ω₀/Q",
        "the lower half-power point exists only for δ < sin(π/8) ω₀ (Q > 1.307)",
    ],
    # the free ringdown (delta <= 0.9 omega0) from rest at q(0) over about 1.25 cycles, relative to q(0)
    states=[("q_over_q0", "1"), ("v_over_q0", "1/s")],
)

ZETA_MIN = 1e-150  # delta/omega0 below this the peak |a|^2 ~ 1/(4 zeta^2) per unit force leaves double precision
MAX_PHASE = 1e15  # omega0 t1 above this: the phase at t1 is not resolved in double precision
LOW_FLOOR = 0.02  # lowest drive frequency (in omega0) shot for the lower half-power point


exercise.declare_limits(
    "delta < omega0: damped oscillations",
    f"omega0 t1 <= {MAX_PHASE:g}: the phase at t1 resolved in double precision",
)


@exercise.constraint
def constraint(p):
    if p.delta >= p.omega0:
        return f"delta = {p.delta:g} 1/s must be below omega0 = {p.omega0:g} rad/s (damped oscillations)"
    if p.omega0 * p.t1 > MAX_PHASE:
        return (f"omega0 t1 = {p.omega0 * p.t1:.3g} exceeds {MAX_PHASE:g}: the phase at t1, on which E(t1) depends, "
                "is not resolved in double precision")


# Q above 5e149: the resonance peak |a|^2 ~ 1/(4 zeta^2) per unit force overflows
ranges.declare(exercise, ranges.Scale("delta/omega0", {"delta": 1, "omega0": -1}, "the resonance peak's width",
                                      low=math.log10(ZETA_MIN), high=math.inf))


@exercise.approximations
def approximations(p):
    """The statement relates Q to the loss per period (2 pi/Q for weak damping) and the resonance width
    (omega0/Q)."""
    Q = p.omega0 / (2.0 * p.delta)
    return {"loss_per_cycle": [(2.0 * math.pi / Q, "the weak-damping loss per period 2 pi/Q")],
            "bandwidth": [(p.omega0 / Q, "the weak-damping width omega0/Q")]}


@exercise.analytic
def analytic(p):
    w0, d = p.omega0, p.delta
    z = d / w0
    wd = math.sqrt((1.0 - z) * (1.0 + z))  # omega_d/omega0 (scaled: no overflow of omega0^2)
    loss = -math.expm1(-4.0 * math.pi * z / wd)
    ph = math.fmod(wd * (w0 * p.t1), 2.0 * math.pi)
    c, s = math.cos(ph), math.sin(ph)
    log_decay = -2.0 * d * p.t1
    e_ratio = math.exp(log_decay) * ((c + z / wd * s) ** 2 + (s / wd) ** 2) if log_decay > -800 else 0.0
    # in units of omega0: x_-+ = 1 - 2 z^2 -+ 2 z wd (no cancellation for small z)
    big = 1.0 - 2.0 * z * z
    x_minus = big - 2.0 * z * wd
    if x_minus <= 0.0:
        width = Undefined("the lower half-power point does not exist (delta >= sin(pi/8) omega0)")
    else:
        x_plus = big + 2.0 * z * wd
        width = w0 * (4.0 * z * wd / (math.sqrt(x_plus) + math.sqrt(x_minus)))
    return {"Q": 0.5 / z, "loss_per_cycle": loss, "E_ratio": e_ratio, "bandwidth": width}


# ---------------------------------------------------------------- ringdown
def _half_cycle(z, om):
    """Half a cycle in amplitude-phase variables with th as the independent variable, th: 0 -> pi:
    (T', l) with l = ln(E_end/E_start)/zeta.

    om = 1 - zeta, passed exactly so that 1 - zeta sin 2th = om + 2 zeta sin^2(th - pi/4)
    keeps its digits when zeta is close to 1.
    """
    from mech.problems.motion import Motion

    def rhs(th, y):
        g = om + 2.0 * z * math.sin(th - 0.25 * math.pi) ** 2  # 1 - zeta sin 2th
        s = math.sin(th)
        return np.array([1.0 / g, -4.0 * s * s / g])

    return Motion(rhs, [0.0, 0.0], (0.0, math.pi), y_size=[1.0, 1.0])


def _polar_in_time(z, tau):
    """(th, l) over time tau from th = 0 (a maximum), l = ln(E ratio)/zeta."""
    from mech.problems.motion import Motion

    def rhs(t, y):
        s = math.sin(y[0])
        return np.array([1.0 - z * math.sin(2.0 * y[0]), -4.0 * s * s])

    return Motion(rhs, [0.0, 0.0], (0.0, tau), y_size=[1.0, 1.0])


@exercise.motion
def motion(p, cycle=None):
    """The free ringdown from rest at x = q/q0 = 1 over 1.25 cycles (tau = omega0 t), with the dissipated work
    carried as W = 2 zeta w, w' = x'^2 (E + W conserved), and the maxima x' = 0 (downward) marked.  ``cycle``:
    the cycle T' (in tau) the numeric solve measured in amplitude-phase variables (``_half_cycle``); measured
    here at the default rtol when not given.  None past zeta = 0.9, where the motion dies within a cycle and
    the loss comes from the decrement."""
    from mech.problems.motion import Motion
    from mech.solvers.numerics.ode import Event

    w0 = p.omega0
    z = p.delta / w0
    if z > 0.9:
        return None
    if cycle is None:
        from mech.problems.spec import Run

        half = Run(rtol=exercise.default_rtol).follow(_half_cycle(z, (w0 - p.delta) / w0), mark=False)
        cycle = 2.0 * half.y_end[0]

    def rhs(t, y):
        return np.array([y[1], -2.0 * z * y[1] - y[0], y[1] * y[1]])

    def balance(y):  # E + W relative to E(0) = 1/2
        return (0.5 * (y[0] ** 2 + y[1] ** 2) + 2.0 * z * y[2] - 0.5) / 0.5

    peak = Event(lambda t, y: y[1], terminal=False, direction=-1, name="x' = 0 (maximum)")
    return Motion(rhs, [1.0, 0.0, 0.0], (0.0, 1.25 * cycle), invariants={"E + dissipated work": balance},
                  t_scale=1.0 / w0, y_scale=[1.0, w0], to_states=lambda Y: Y[[0, 1]],  # not the work
                  options={"events": [peak]})


# ---------------------------------------------------------------- forced response
class _Resonance:
    """|a|^2 per unit force per mass at drive omega = omega0 + u, in units omega0 = 1."""

    def __init__(self, z, rtol, run):
        self.z, self.rtol, self.run = z, rtol, run
        self.calls = 0
        self.cache = {}

    def amp2(self, u):
        from mech.problems.motion import Motion

        if u in self.cache:
            return self.cache[u]

        z = self.z
        w = 1.0 + u
        det2 = -u * (2.0 + u)  # (1 - w)(1 + w) without cancellation
        period = 2.0 * math.pi / w

        cos, sin = math.cos, math.sin
        zw2 = 2.0 * z * w

        def rhs(t, y):
            c, s = cos(w * t), sin(w * t)
            gu = (zw2 * s - det2 * c) / w
            gv = (-zw2 * c - det2 * s) / w
            # a = [-s, c]^T [gu, gv]: rank one, so each column needs one dot product
            k1 = gu * (y[0] + 1.0) + gv * y[1]
            k2 = gu * y[2] + gv * (y[3] + 1.0)
            k3 = gu * y[4] + gv * y[5] + c / w
            return np.array([-s * k1, c * k1, -s * k2, c * k2, -s * k3, c * k3])

        dev = min(1.0, (abs(det2) + 2.0 * z * w) * period / w)
        force = period / w
        atol = np.array([dev] * 4 + [force] * 2) * self.rtol * 1e-3
        y = self.run.follow(Motion(rhs, np.zeros(6), (0.0, period), options={"atol": atol}), self.rtol,
                            mark=False).y_end
        d_m = np.array([[y[0], y[2]], [y[1], y[3]]])  # M - I
        # Liouville: det M = exp(-2 zeta period); det(I + D) - 1 = tr D + det D
        liou = (np.trace(d_m) + np.linalg.det(d_m)) - math.expm1(-2.0 * z * period)
        self.run.invariant("Liouville det of the drive-period map", liou)
        xs = np.linalg.solve(-d_m, y[4:6])
        self.calls += 1
        val = float(xs @ xs)
        self.cache[u] = val
        return val

    def static(self):
        """omega -> 0: the periodic orbit of x'' + 2 zeta x' + x = 1 (a constant force) over one free period."""
        from mech.problems.motion import Motion

        z = self.z

        def rhs(t, y):
            return np.array([y[1], -2.0 * z * y[1] - y[0] + 1.0, y[3], -2.0 * z * y[3] - y[2], y[5], -2.0 * z * y[5] - y[4]])

        y = self.run.follow(Motion(rhs, [0, 0, 1, 0, 0, 1], (0.0, 2.0 * math.pi)), self.rtol, mark=False).y_end
        m = np.array([[y[2], y[4]], [y[3], y[5]]])
        xs = np.linalg.solve(np.eye(2) - m, y[0:2])
        return float(xs[0] ** 2 + xs[1] ** 2)


def _bandwidth(z, d_meas, rtol, run):
    """The full width at half maximum of |a|^2 in units of omega0, or Undefined."""
    from mech.solvers.numerics.roots import brentq, minimize_scalar

    res = _Resonance(z, rtol, run)
    left_edge = -(1.0 - 0.1)
    lo = max(-4.0 * d_meas, left_edge)
    hi = 1.0 * d_meas
    # minimize 1/|a|^2: smooth and nearly parabolic around the peak, so Brent's
    # parabolic steps converge in a few solves
    opt = minimize_scalar(lambda u: 1.0 / res.amp2(u), bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-6 * d_meas, "maxiter": 200})
    u_pk, top = float(opt.x), 1.0 / float(opt.fun)
    run.info["peak_omega_over_omega0"] = 1.0 + u_pk
    if hi - u_pk < 1e-5 * d_meas:
        raise NumericFailure("the resonance peak was not inside its search bracket")
    half = 0.5 * top
    s0 = res.static()
    if u_pk - lo < 1e-5 * d_meas:
        if lo > left_edge:
            raise NumericFailure("the resonance peak was not inside its search bracket")
        # the curve rises towards omega -> 0: its maximum is at or below 0.1 omega0
        if s0 >= 0.5 * max(top, s0):
            return Undefined("|a|^2 stays above half its maximum down to omega = 0: no lower half-power point"), res
        raise NumericFailure("the resonance peak lies below 0.1 omega0")

    def f(u):  # in 1/|a|^2, nearly parabolic in u: brentq's interpolation converges fast
        return 1.0 - half / res.amp2(u)

    xtol = 1e-13 * d_meas
    # lower half-power point
    step, u_in = d_meas, u_pk
    while True:
        u_try = u_pk - step
        if 1.0 + u_try <= LOW_FLOOR:
            if s0 >= half:
                return Undefined("|a|^2 stays above half its maximum down to omega = 0: no lower half-power point"), res
            if f(LOW_FLOOR - 1.0) < 0.0:
                u_try = LOW_FLOOR - 1.0
                break
            raise NumericFailure(
                f"the lower half-power point lies below {LOW_FLOOR} omega0 (delta within ~1e-4 of sin(pi/8) omega0): "
                "one drive period would span too many free periods"
            )
        if f(u_try) < 0.0:
            break
        u_in, step = u_try, 2.0 * step
    u_minus = brentq(f, u_try, u_in, xtol=xtol, rtol=1e-15)
    step, u_in = d_meas, u_pk
    while f(u_pk + step) >= 0.0:
        u_in, step = u_pk + step, 2.0 * step
        if step > 1e3:
            raise NumericFailure("no upper half-power point found")
    u_plus = brentq(f, u_in, u_pk + step, xtol=xtol, rtol=1e-15)
    run.info["half_power_omega_over_omega0"] = [1.0 + u_minus, 1.0 + u_plus]
    return u_plus - u_minus, res


@exercise.numeric
def numeric(p, run):
    w0, d = p.omega0, p.delta
    z = d / w0
    om = (w0 - d) / w0
    rtol = run.rtol

    # ringdown in amplitude-phase variables: T' and ln(E) over one cycle (a tool: th is its clock)
    half_t, half_l = run.follow(_half_cycle(z, om), mark=False).y_end
    t_cyc = 2.0 * half_t
    log_dec = 2.0 * half_l * z  # ln(E(T')/E(0))
    d_meas = -log_dec / (2.0 * t_cyc)  # in units of omega0
    w0_meas = math.hypot(2.0 * math.pi / t_cyc, d_meas)
    q_meas = w0_meas / (2.0 * d_meas)
    run.info["T_cycle_over_T0"] = t_cyc / (2.0 * math.pi)

    # loss per cycle from the dissipated work: the declared ringdown, from rest to the next maximum
    if z <= 0.9:
        ring = run.follow(motion(p, cycle=t_cyc))
        t_span = ring.motion.span[1]
        later = [(t, y) for t, y in zip(ring.traj.t_events[0], ring.traj.y_events[0]) if t > 0.5 * t_span / 1.25]
        if not later:
            raise NumericFailure("the ringdown reached no maximum after the start within 1.25 periods")
        t_max, y = later[0]
        work = 2.0 * z * y[2]
        loss = work / 0.5
        run.info["loss_route"] = "dissipated work over the cycle"
        run.info["T_between_maxima_by_event_minus_by_phase"] = float(t_max) - t_cyc
    else:
        loss = -math.expm1(log_dec)
        run.info["loss_route"] = "-expm1 of the cycle's energy decrement"

    # E(t1)/E(0): whole half-cycles by periodicity, the remainder integrated
    tau1 = w0 * p.t1
    m = math.floor(tau1 / half_t)
    rem = tau1 - m * half_t
    if rem < 0.0:
        m, rem = m - 1, rem + half_t
    rem = min(rem, half_t)
    if rem > 0.0:
        l_rem = run.follow(_polar_in_time(z, rem), mark=False).y_end[1]
    else:
        l_rem = 0.0
    log_e = z * (m * half_l + l_rem)
    e_ratio = math.exp(log_e) if log_e > -800 else 0.0
    run.info["E_ratio_half_cycles"] = m
    run.claim("E_ratio", rel=exercise.tol_factor * rtol * max(1.0, abs(log_e)), abs=1e-300)

    # resonance width
    width, res = _bandwidth(z, d_meas, rtol, run)
    run.info["width_amplitude_solves"] = res.calls
    if not isinstance(width, Undefined):
        width = width * w0
    return {"Q": q_meas, "loss_per_cycle": loss, "E_ratio": e_ratio, "bandwidth": width}
