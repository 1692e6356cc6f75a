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

Numeric (tau = omega0 t, zeta = delta/omega0, x'' + 2 zeta x' + x = 0), written once over arrays of
variants (``numeric``; a one-point solve is its batch of one), each stage's integrations stepped together:
* Q from the ringdown in amplitude-phase variables x = r cos th, x' = -r sin th, where the equation of
  motion reads th' = 1 - zeta sin 2th, (ln E)' = -4 zeta sin^2 th: with th as the independent variable
  over half a cycle (the integrands have period pi) the cycle T' between maxima and the decrement of E
  (as l = ln(E)/zeta: no log of a ratio close to 1); delta = -ln(E ratio)/(2 T'),
  omega0 = sqrt((2 pi/T')^2 + delta^2), Q = omega0/(2 delta).
* Loss per cycle: the declared motion's equations (``motion``), (x, x') with the dissipated work W
  carried, from rest at x = 1 over the cycle T' (its end is the next maximum: the section is the end of a
  fixed span in tau/T'); W/E(0) there, E + W monitored.  Past zeta = 0.9 (the motion dies by e^-13
  within the cycle) -expm1 of the decrement.
* E_ratio: t1 = m half-cycles (each shifts ln E by zeta l) plus a remainder integrated in time.
* Width: |a|^2 at drive omega from the periodic orbit of the map over one drive period in the
  variation-of-constants variables (q = u cos wt + v sin wt), M - I integrated as a deviation so that a
  narrow peak keeps its relative accuracy; the peak by Brent's bounded search in the detuning
  u = omega - omega0 (bracket from the ringdown's delta), the half-power points by Illinois on each side,
  bracketed by doubling steps.  omega -> 0: the static deflection (the same periodic-orbit solve over a
  free period); the lower point is absent when the curve stays above half its maximum down to it.  Lower
  points below 0.02 omega0 (within ~1e-4 of the threshold) fail: a drive period spans 50 free periods.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, Tally

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

_NO_LOWER_EXACT = "the lower half-power point does not exist (delta >= sin(pi/8) omega0)"
_NO_LOWER = "|a|^2 stays above half its maximum down to omega = 0: no lower half-power point"


def _arrays(P):
    return (np.asarray(P[k], dtype=float) for k in ("omega0", "delta", "t1"))


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
    """The statement relates Q to the loss per period (2 pi/Q, weak damping) and the width (omega0/Q)."""
    Q = p.omega0 / (2.0 * p.delta)
    return {"loss_per_cycle": [(2.0 * math.pi / Q, "the weak-damping loss per period 2 pi/Q")],
            "bandwidth": [(p.omega0 / Q, "the weak-damping width omega0/Q")]}


@exercise.analytic
def analytic(P):
    """Over arrays of variants, in z = delta/omega0 (no omega0^2 formed)."""
    from mech.solvers.numerics.batch import Column

    w0, d, t1 = _arrays(P)
    z = d / w0
    wd = np.sqrt((1.0 - z) * (1.0 + z))  # omega_d/omega0
    loss = -np.expm1(-4.0 * math.pi * z / wd)
    ph = np.fmod(wd * (w0 * t1), 2.0 * math.pi)
    c, s = np.cos(ph), np.sin(ph)
    log_decay = -2.0 * d * t1
    with np.errstate(under="ignore"):
        shape = (c + z / wd * s) ** 2 + (s / wd) ** 2
        e_ratio = np.where(log_decay > -800, np.exp(np.maximum(log_decay, -800.0)) * shape, 0.0)
    # in units of omega0: x_-+ = 1 - 2 z^2 -+ 2 z wd (no cancellation for small z)
    big = 1.0 - 2.0 * z * z
    x_minus = big - 2.0 * z * wd
    lower = x_minus > 0.0
    x_plus = big + 2.0 * z * wd
    width = np.where(lower, w0 * (4.0 * z * wd / (np.sqrt(np.abs(x_plus)) + np.sqrt(np.abs(x_minus)))), np.nan)
    return {"Q": Column(0.5 / z), "loss_per_cycle": Column(loss), "E_ratio": Column(e_ratio),
            "bandwidth": Column(width, undefined=[(~lower, _NO_LOWER_EXACT)])}


def _ensemble(system, coefs, span, y0, atol, rtol, tally, work=None):
    """``ensemble_search.integrate_variants`` with this route's integrator and records (``tally``)."""
    from mech.solvers.numerics.ensemble_search import integrate_variants

    return integrate_variants(system, coefs, span, y0, rtol=rtol, atol=atol, work=work, integrator=tally.integrator,
                              record=tally.record)[:2]


def _reasons(why):
    """[(mask, reason)] of an array of failures ("" where none), one entry a distinct reason."""
    return [(why == w, w) for w in sorted(set(why[why != ""]))]


# ---------------------------------------------------------------- ringdown
def _half_cycle(z, om):
    """Half a cycle in amplitude-phase variables with th as the independent variable, th: 0 -> pi, to
    (T', l) with l = ln(E_end/E_start)/zeta.  om = 1 - zeta, passed exactly so that
    1 - zeta sin 2th = om + 2 zeta sin^2(th - pi/4) keeps its digits when zeta is close to 1."""
    def rhs(th, y):
        g = om + 2.0 * z * math.sin(th - 0.25 * math.pi) ** 2  # 1 - zeta sin 2th
        s = math.sin(th)
        return np.array([1.0 / g, -4.0 * s * s / g])

    return rhs


def _ringdown_half(z, om, rtol, tally):
    """(T', l) over half a cycle (``_half_cycle``) at N variants, and each variant's failure.  The integrand
    1/g peaks at 1/(1 - zeta) over a width ~(1 - zeta)^(1/2): the steps grow as its inverse."""
    (half_t, half_l), why = _ensemble(_half_cycle, (z, om), (0.0, math.pi), np.zeros((2, z.size)), 1e-3 * rtol,
                                      rtol, tally, work=1.0 / np.sqrt(om))
    return half_t, half_l, why


def _ringdown(z, t_cyc):
    """(x, x', w) from rest at x = 1 against s = tau/T' over one cycle T', s: 0 -> 1: x'' = -2 zeta x' - x with
    the dissipated work W = 2 zeta w, w' = x'^2 (the declared motion's equations, its span one cycle)."""
    def rhs(s, y):
        return t_cyc * np.array([y[1], -2.0 * z * y[1] - y[0], y[1] * y[1]])

    return rhs


def _polar_in_time(z, tau):
    """(th, l) against s = t/tau, s: 0 -> 1, from th = 0 (a maximum), l = ln(E ratio)/zeta."""
    def rhs(s, y):
        sn = np.sin(y[0])
        return tau * np.array([1.0 - z * np.sin(2.0 * y[0]), -4.0 * sn * sn])

    return rhs


@exercise.motion
def motion(p, cycle=None):
    """The free ringdown from rest at x = q/q0 = 1 over 1.25 cycles (tau = omega0 t; ``_ringdown``'s equations),
    the maxima x' = 0 (downward) marked; ``cycle``: T' in tau (by default measured by ``_ringdown_half`` at the
    default rtol).  None past zeta = 0.9, where the motion dies within a cycle."""
    from mech.problems.motion import Motion
    from mech.solvers.numerics.ode import Event

    w0 = p.omega0
    z = p.delta / w0
    if z > 0.9:
        return None
    if cycle is None:
        cycle = 2.0 * float(_ringdown_half(np.array([z]), np.array([(w0 - p.delta) / w0]), exercise.default_rtol,
                                           Tally())[0][0])
    rhs = _ringdown(z, 1.0)

    def balance(y):  # E + W relative to E(0) = 1/2
        return (0.5 * (y[0] ** 2 + y[1] ** 2) + 2.0 * z * y[2] - 0.5) / 0.5

    peak = Event(lambda t, y: y[1], terminal=False, direction=-1, name="x' = 0 (maximum)")
    return Motion(rhs, [1.0, 0.0, 0.0], (0.0, 1.25 * cycle), invariants={"E + dissipated work": balance},
                  t_scale=1.0 / w0, y_scale=[1.0, w0], to_states=lambda Y: Y[[0, 1]],  # not the work
                  options={"events": [peak]})


def _loss(z, t_cyc, log_dec, rtol, tally):
    """The loss per cycle: the work dissipated over the cycle T' from rest at x = 1 (``_ringdown``, the
    declared motion's equations over a span ending at the next maximum), relative to E(0) = 1/2; past
    zeta = 0.9 (the motion dies by e^-13 within the cycle) -expm1 of the cycle's decrement.  Returns the
    loss, E + W's drift, each variant's failure and where the work was integrated."""
    loss, ring = -np.expm1(log_dec), (z <= 0.9) & np.isfinite(t_cyc)
    idx = np.flatnonzero(ring)
    drift, why = np.zeros(z.size), np.full(z.size, "", dtype=object)
    y0 = np.array([[1.0], [0.0], [0.0]]) * np.ones(idx.size)
    y, why[idx] = _ensemble(_ringdown, (z[idx], t_cyc[idx]), (0.0, 1.0), y0, 1e-3 * rtol, rtol, tally)
    loss[idx] = 2.0 * z[idx] * y[2] / 0.5
    drift[idx] = (0.5 * (y[0] ** 2 + y[1] ** 2) + 2.0 * z[idx] * y[2] - 0.5) / 0.5
    # the cycle's end is a maximum: x' = 0 there to the accuracy of T'; x'/x is the time to the maximum
    tally.info["maximum_after_cycle_end"] = np.where(ring, drift * np.nan, None)
    tally.info["maximum_after_cycle_end"][idx] = y[1] / y[0]
    tally.info["loss_route"] = np.where(ring, "dissipated work over the cycle",
                                        "-expm1 of the cycle's energy decrement").astype(object)
    return loss, drift, why, ring


def _energy_at(z, tau1, half_t, half_l, rtol, tally):
    """ln(E(t1)/E(0)): whole half-cycles by periodicity (each shifts ln E by zeta l), the remainder
    integrated in time (``_polar_in_time``); and each variant's failure."""
    m = np.floor(tau1 / half_t)
    back = tau1 - m * half_t < 0.0
    m -= back
    rem = np.clip(tau1 - m * half_t, 0.0, half_t)
    (_, l_rem), why = _ensemble(_polar_in_time, (z, rem), (0.0, 1.0), np.zeros((2, z.size)), 1e-3 * rtol, rtol,
                                tally)
    tally.info["E_ratio_half_cycles"] = m
    return z * (m * half_l + l_rem), why


# ---------------------------------------------------------------- forced response
def _drive_map(z, u):
    """The map over one drive period at drive omega = 1 + u (units omega0 = 1) in the variation-of-constants
    variables of x'' + 2 zeta x' + x = cos(omega t), x = p cos(omega t) + q sin(omega t), against
    s = omega t, s: 0 -> 2 pi: M - I (its columns as deviations, so that a narrow peak keeps its relative
    accuracy) and the orbit from rest, (d1, d2, f) with (p, q)' = [-sin s, cos s]^T k."""
    w = 1.0 + u
    a1 = 2.0 * z / w
    a2 = -u * (2.0 + u) / (w * w)  # (1 - w)(1 + w)/w^2 without cancellation
    force = 1.0 / (w * w)
    cos, sin = math.cos, math.sin

    def rhs(s, y):
        c, sn = cos(s), sin(s)
        gu = a1 * sn - a2 * c
        gv = -a1 * c - a2 * sn
        # rank one: each column (d1, d2, f) needs one dot product, k = [gu, gv] (I + D | f) + [0, 0, force c]
        k = gu * y[0::2] + gv * y[1::2]
        k[0] += gu
        k[1] += gv
        k[2] += force * c
        out = np.empty((6,) + np.shape(k[0]))
        out[0::2], out[1::2] = -sn * k, c * k
        return out

    return rhs


def _constant_force(z):
    """x'' + 2 zeta x' + x = 1 over one free period from rest, with the two columns of the free map."""
    def rhs(t, y):
        return np.array([y[1], -2.0 * z * y[1] - y[0] + 1.0, y[3], -2.0 * z * y[3] - y[2], y[5],
                         -2.0 * z * y[5] - y[4]])

    return rhs


class _Resonance:
    """|a|^2 per unit force per mass at drive omega = 1 + u (units omega0 = 1) for N variants (``z``: zeta): the
    periodic orbits of ``_drive_map``, integrated together; each variant's worst Liouville drift, solves, failure."""

    def __init__(self, z, rtol, tally):
        self.z, self.rtol, self.tally = z, rtol, tally
        self.liouville = np.zeros(z.size)
        self.calls = np.zeros(z.size)
        self.why = np.full(z.size, "", dtype=object)

    def amp2(self, u, idx):
        z = self.z[idx]
        w = 1.0 + u
        period = 2.0 * math.pi / w
        dev = np.minimum(1.0, (np.abs(u * (2.0 + u)) + 2.0 * z * w) * period / w)
        atol = np.vstack([dev] * 4 + [period / w] * 2) * self.rtol * 1e-3
        # one drive period spans 1/omega free periods: the steps grow as 1/omega
        y, why = _ensemble(_drive_map, (z, u), (0.0, 2.0 * math.pi), np.zeros((6, idx.size)), atol, self.rtol,
                           self.tally, work=np.maximum(1.0, 1.0 / w))
        self.why[idx] = np.where(self.why[idx] == "", why, self.why[idx])
        d00, d10, d01, d11 = y[0], y[1], y[2], y[3]  # M - I
        det = d00 * d11 - d01 * d10
        # Liouville: det M = exp(-2 zeta period); det(I + D) - 1 = tr D + det D
        np.fmax.at(self.liouville, idx, np.abs((d00 + d11 + det) - np.expm1(-2.0 * z * period)))
        np.add.at(self.calls, idx, 1.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            x0 = -(d11 * y[4] - d01 * y[5]) / det  # the periodic orbit: (M - I) x = -f
            x1 = -(d00 * y[5] - d10 * y[4]) / det
        return x0 * x0 + x1 * x1

    def static(self, idx):
        """omega -> 0: the periodic orbit of x'' + 2 zeta x' + x = 1 (a constant force) over one free period."""
        y0 = np.array([[0.0], [0.0], [1.0], [0.0], [0.0], [1.0]]) * np.ones(idx.size)
        y, why = _ensemble(_constant_force, (self.z[idx],), (0.0, 2.0 * math.pi), y0, 1e-3 * self.rtol, self.rtol,
                           self.tally)
        self.why[idx] = np.where(self.why[idx] == "", why, self.why[idx])
        a, b, c, d = 1.0 - y[2], -y[4], -y[3], 1.0 - y[5]  # I - M
        det = a * d - b * c
        x0, x1 = (d * y[0] - b * y[1]) / det, (a * y[1] - c * y[0]) / det
        return x0 * x0 + x1 * x1


def _fail(why, where, reason):
    """Each variant's first failure: ``reason`` where ``where`` (a mask or indices) and none yet."""
    mask = np.zeros(why.size, dtype=bool)
    mask[where] = True
    why[mask & (why == "")] = reason


def _half_power_points(res, u_pk, half, d_meas, go, rtol, why):
    """The distances x below and above the peak of each variant ``go`` to its half-power points:
    f = 1 - half/|a|^2 > 0 inside, bracketed by doubling steps from d_meas (``scan_up``; below, down to
    omega = LOW_FLOOR), then the root by Illinois in x^2 (f is nearly a parabola in x, so nearly linear in
    x^2).  Returns (x_below, x_above) over all variants and where the lower point is absent; failures to
    ``why``."""
    from mech.solvers.numerics.batch import illinois, scan_up

    N, M = u_pk.size, go.size
    var, sign = np.concatenate([go, go]), np.concatenate([-np.ones(M), np.ones(M)])
    below, undefined = sign < 0, np.zeros(N, dtype=bool)

    def f(k, x):  # k: sides
        return 1.0 - half[var[k]] / res.amp2(u_pk[var[k]] + sign[k] * x, var[k])

    limit = np.where(below, 1.0 + u_pk[var] - LOW_FLOOR, 1e3)
    lo, hi, flo, fhi, none = scan_up(f, np.zeros(2 * M), np.minimum(d_meas[var], limit), factor=2.0, limit=limit,
                                     flo=np.full(2 * M, 0.5))
    floor = np.flatnonzero(none & below)
    if floor.size:  # the lower scan reached omega = LOW_FLOOR: the static deflection, else shot there
        rises = res.static(var[floor]) >= half[var[floor]]
        undefined[var[floor[rises]]] = True
        shot = floor[~rises]
        f_floor = f(shot, limit[shot]) if shot.size else np.zeros(0)
        inside = shot[f_floor <= 0.0]
        hi[inside], fhi[inside], none[inside] = limit[inside], f_floor[f_floor <= 0.0], False
        _fail(why, var[shot[f_floor > 0.0]], f"the lower half-power point lies below {LOW_FLOOR} omega0 (delta "
              "within ~1e-4 of sin(pi/8) omega0): one drive period would span too many free periods")
    _fail(why, var[none & ~below], "no upper half-power point found")
    k = np.flatnonzero(~none)
    x = np.full(2 * M, np.nan)
    if k.size:
        xtol = max(1e-3 * rtol, 1e-13) * d_meas[var[k]]
        y, conv = illinois(lambda y, i: f(k[i], np.sqrt(y)), lo[k] ** 2, hi[k] ** 2, flo[k], fhi[k],
                           xtol=2.0 * hi[k] * xtol, rtol=0.0)
        x[k] = np.where(conv, np.sqrt(y), np.nan)
        _fail(why, var[k[~conv]], "the root search for a half-power point did not converge")
    x_below, x_above = np.full(N, np.nan), np.full(N, np.nan)
    x_below[go], x_above[go] = x[:M], x[M:]
    return x_below, x_above, undefined


def _bandwidth(z, d_meas, rtol, tally):
    """The full width at half maximum of |a|^2 in units of omega0 at N variants: the peak by Brent's bounded
    search in the detuning u (``brent_minimum`` of 1/|a|^2, smooth and nearly parabolic there), bracketed by
    the ringdown's delta, then the half-power points (``_half_power_points``).  Returns the width, where the
    lower point is absent, each variant's failure, its Liouville drift, peak, half-power points and solves."""
    from mech.solvers.numerics.ensemble_search import brent_minimum

    N = z.size
    res = _Resonance(z, rtol, tally)
    ok = np.isfinite(d_meas)
    left_edge = -(1.0 - 0.1)
    lo, hi = np.maximum(-4.0 * d_meas, left_edge), d_meas
    u_pk, g_pk, conv = np.full(N, np.nan), np.full(N, np.nan), np.ones(N, dtype=bool)
    # a search bracket reaching 0.1 omega0: where 1/|a|^2 rises from there (within the 1e-5 delta the search
    # resolves), the peak is at the edge (the one minimum Brent's search assumes): no golden steps to it
    k = np.flatnonzero(ok & (lo <= left_edge))
    g2 = 1.0 / res.amp2(np.concatenate([lo[k], lo[k] + 1e-5 * d_meas[k]]), np.concatenate([k, k]))
    rising = k[g2[k.size:] >= g2[:k.size]]
    u_pk[rising], g_pk[rising] = lo[rising], g2[:k.size][g2[k.size:] >= g2[:k.size]]
    idx = np.flatnonzero(ok & np.isnan(u_pk))
    if idx.size:
        u_pk[idx], g_pk[idx], conv[idx] = brent_minimum(lambda u, i: 1.0 / res.amp2(u, idx[i]), lo[idx], hi[idx],
                                                        xatol=1e-6 * d_meas[idx], x0=np.zeros(idx.size))
    top = 1.0 / g_pk
    out_hi = ok & (hi - u_pk < 1e-5 * d_meas)
    at_lo = ok & ~out_hi & (u_pk - lo < 1e-5 * d_meas)
    undefined = np.zeros(N, dtype=bool)
    # the curve rising towards omega -> 0: its maximum at or below 0.1 omega0
    edge = np.flatnonzero(at_lo & (lo <= left_edge))
    if edge.size:
        s0 = res.static(edge)
        undefined[edge] = s0 >= 0.5 * np.fmax(top[edge], s0)
    why = res.why  # an integration's failure first: where the searches then went astray, it is the reason
    _fail(why, ~conv, "the search for the resonance peak did not converge")
    _fail(why, out_hi | (at_lo & (lo > left_edge)), "the resonance peak was not inside its search bracket")
    _fail(why, at_lo & ~undefined & (lo <= left_edge), "the resonance peak lies below 0.1 omega0")
    go = np.flatnonzero(ok & conv & ~out_hi & ~at_lo)
    x_below, x_above, no_lower = _half_power_points(res, u_pk, 0.5 * top, d_meas, go, rtol, why)
    return (x_below + x_above, undefined | no_lower, why, res.liouville, 1.0 + u_pk, 1.0 + u_pk - x_below,
            1.0 + u_pk + x_above, res.calls)


@exercise.batched(("Q", "loss_per_cycle", "E_ratio", "bandwidth"))
def numeric(P, rtol, outputs, memo=None, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): the ringdown's half cycle in
    amplitude-phase variables (``_ringdown_half``: Q and the decrement), the dissipated work over the cycle
    (``_loss``), E(t1) (``_energy_at``) and the resonance width (``_bandwidth``), each stage's integrations
    stepped together.  A variant that fails fails alone; E + W's and Liouville's drifts go to ``tally``."""
    from mech.solvers.numerics.batch import Column, by_rows

    tally = Tally() if tally is None else tally
    w0, d, t1 = np.broadcast_arrays(*_arrays(P))
    z, om = d / w0, (w0 - d) / w0
    N = z.size
    claim = exercise.tol_factor * rtol
    half_t, half_l, why = _ringdown_half(z, om, rtol, tally)
    t_cyc = 2.0 * half_t
    log_dec = 2.0 * half_l * z  # ln(E(T')/E(0))
    d_meas = -log_dec / (2.0 * t_cyc)  # in units of omega0
    tally.info["T_cycle_over_T0"] = t_cyc / (2.0 * math.pi)
    ring_failed = _reasons(why)
    out = {}
    if "Q" in outputs:
        q_meas = np.hypot(2.0 * math.pi / t_cyc, d_meas) / (2.0 * d_meas)
        out["Q"] = Column(q_meas, rel=claim, failed=ring_failed)
    if "loss_per_cycle" in outputs:
        loss, drift, lwhy, ring = _loss(z, t_cyc, log_dec, rtol, tally)
        if ring.any():
            tally.invariant("E + dissipated work", drift)
        out["loss_per_cycle"] = Column(loss, rel=claim, failed=ring_failed + _reasons(lwhy) + [
            (~(np.abs(drift) <= claim), "the invariant 'E + dissipated work' drifts by more than the claim: the "
             "integration is not to be trusted")])
    if "E_ratio" in outputs:
        log_e, ewhy = _energy_at(z, w0 * t1, half_t, half_l, rtol, tally)
        with np.errstate(under="ignore"):
            e_ratio = np.where(log_e > -800, np.exp(np.maximum(log_e, -800.0)), 0.0)
        out["E_ratio"] = Column(e_ratio, rel=claim * np.maximum(1.0, np.abs(log_e)), abs=1e-300,
                                failed=ring_failed + _reasons(ewhy))
    if "bandwidth" in outputs:  # once for each distinct zeta (a sweep in t1 shares it; the rerun does not)
        memo = {} if memo is None else memo
        got = by_rows(memo, ("5.5 width", rtol), (z, d_meas), lambda zs, ds: _bandwidth(zs, ds, rtol, tally))
        width, undefined, bwhy, liouville = got[:4]
        tally.info.update({f"{k}_omega_over_omega0": v for k, v in zip(("peak", "half_power_low", "half_power_high"),
                                                                         got[4:7])}, width_amplitude_solves=got[7])
        tally.invariant("Liouville det of the drive-period map", liouville)
        failed = ring_failed + _reasons(np.asarray(bwhy, dtype=object)) + [
            (~(liouville <= claim), "the drive-period map's determinant drifts from Liouville's by more than the "
             "claim: the integration is not to be trusted")]
        out["bandwidth"] = Column(width * w0, rel=claim, undefined=[(undefined > 0, _NO_LOWER)], failed=failed)
    return out
