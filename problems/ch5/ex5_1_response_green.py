"""5.1 Damped oscillator: response function, Green's function and causality.

Analytic (exact in all three regimes): with q = Re[a exp(-i w t)],
m(-w^2 - 2 i delta w + w0^2) a = F_w, so
chi(w) = 1 / (m (w0^2 - w^2 - 2 i delta w)),
Re chi = (w0^2 - w^2)/(m D), Im chi = 2 delta w/(m D), D = (w0^2 - w^2)^2 + 4 delta^2 w^2.
Its poles w = -i delta +- (w0^2 - delta^2)^(1/2) lie in the lower half plane,
so for tau < 0 the contour closes above and G(-tau) = 0 (causality); for
tau > 0 the residues give
  underdamped  G = exp(-delta tau) sin(w1 tau)/(m w1),   w1 = (w0^2 - delta^2)^(1/2)
  critical     G = tau exp(-delta tau)/m
  overdamped   G = [exp(-g1 tau) - exp(-g2 tau)]/(2 m w'), w' = (delta^2 - w0^2)^(1/2),
               g1 = w0^2/(delta + w'), g2 = delta + w' (no cancellation in g1; expm1 for small w' tau).

Numeric, crossing the two domains in scaled variables (time 1/w0):
(1) G(+-tau) as the inverse Fourier integral of chi, chi(w) obtained at each w
by solving the frequency-domain equation of motion (one complex unknown);
folded onto w >= 0 and integrated with Fourier-weighted rules on numpy alone
(Filon-type panels, f interpolated and its product with the exponential
integrated exactly, on a window cut at the characteristic roots and their
widths; the tail cycle by cycle, the alternating partial sums extrapolated by
Wynn's epsilon algorithm); solvers/numerics/fourier.inverse_fourier.
(2) chi(w) as the Fourier transform of the integrated impulse response
(q = 0, q' = 1/m): the equation of motion's fundamental matrix with two
accumulators of q exp(i w t) is integrated over one segment by mech's DOP853 or,
when the decay rates differ by more than 50 (strongly overdamped, stiff), not
stepped: Phi(D) = exp(A D) by scaling and squaring and the accumulated transform
by adaptive Gauss-Legendre quadrature at rtol/10 (numpy only; scipy's LSODA
when mech bench forces an integrator), and
the infinite decaying run is summed exactly by the semigroup property as a
geometric series; solvers/numerics/fourier.impulse_spectrum (a drive much faster than
the oscillator gets segments of half its period).  Liouville's
det Phi = exp(-2 delta t) is monitored.

A weakly damped oscillator asked late (tau of 1e5..1e11 periods) has a phase
Theta = w1 tau known in floats to u Theta only (u = 2^-53; the product tau w0 is
rounded, in both methods): the claims and ``analytic_error`` carry that
round-off times the envelope exp(-delta tau), and a phase beyond 1e15 rad, where
it carries no digit, is refused while the envelope still matters.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise
from mech.solvers.numerics.fourier import FLOW, impulse_spectrum, inverse_fourier

exercise = Exercise(
    "5.1",
    formulas=[
        "χ(ω) = 1 / [m (ω₀² - ω² - 2iδω)]",
        "G(τ) = e^{-δτ} sin(ω₁τ)/(m ω₁), ω₁ = (ω₀² - δ²)^{1/2}   (δ < ω₀)",
        "G(τ) = τ e^{-δτ}/m   (δ = ω₀)",
        "G(τ) = e^{-δτ} sinh(ω'τ)/(m ω'), ω' = (δ² - ω₀²)^{1/2}   (δ > ω₀)",
        "G(τ) = 0 for τ < 0: the poles -iδ ± ω₁ lie in the lower half plane",
    ],
    route_note=(
        "(1) The Fourier-weighted quadrature is mech's own, on numpy, in place of QUADPACK's QAWO/QAWF "
        "(scipy.integrate alone cost more than the 1 s budget of a solve): Filon-type panels (f interpolated, "
        "its product with cos/sin integrated exactly) on the window, and the tail cycle by cycle with Wynn's "
        "epsilon extrapolation, as QAWF does.  (2) The impulse response is integrated over one segment and "
        "the decaying rest summed exactly as a geometric series of that segment's map, instead of integrating "
        "until the motion has decayed by exp(-40); where the decay rates differ by more than 50 (stiff) the "
        "segment is the exact flow exp(A D) and the transform adaptive quadrature, instead of Radau/BDF."
    ),
)


_U = 2.0**-53
MAX_PHASE = 1e15  # rad: beyond it the phase's round-off (u * phase) reaches a tenth of a radian
FADED = 40.0  # delta tau beyond which G is below exp(-40) of its scale 1/(m w1): its phase no longer shows


def _phase(p):
    """w1 tau (underdamped) or 0, and the decay delta tau."""
    m, w0, d, t = p.m, p.omega0, p.delta, p.tau
    w1 = math.sqrt((w0 - d) * (w0 + d)) if d < w0 else 0.0
    return w1 * t, d * t


exercise.declare_limits(
    f"omega1 tau <= {MAX_PHASE:g} rad unless delta tau >= {FADED:g}: the phase carries a digit in double precision",
)


@exercise.constraint
def constraint(p):
    phase, decay = _phase(p)
    if phase > MAX_PHASE and decay < FADED:
        return (f"the phase omega1 tau = {phase:.3g} rad carries no significant digit in double precision "
                f"(its round-off u * phase exceeds 0.1 rad; at most {MAX_PHASE:g} rad while "
                f"delta tau = {decay:.3g} < {FADED:g}: lower tau)")


@exercise.analytic
def analytic(p):
    m, w0, d, t, w = p.m, p.omega0, p.delta, p.tau, p.omega
    if d < w0:
        w1 = math.sqrt((w0 - d) * (w0 + d))
        G = math.exp(-d * t) * math.sin(w1 * t) / (m * w1)
    elif d == w0:
        G = t * math.exp(-d * t) / m
    else:
        wp = math.sqrt((d - w0) * (d + w0))
        g1 = w0 * w0 / (d + wp)  # = d - wp without cancellation
        G = math.exp(-g1 * t) * (-math.expm1(-2.0 * wp * t)) / (2.0 * m * wp)
    chi = 1.0 / (m * complex((w0 - w) * (w0 + w), -2.0 * d * w))
    return {"G": G, "G_minus": 0.0, "chi_re": chi.real, "chi_im": chi.imag}


@exercise.analytic_error
def analytic_error(p):
    """Round-off of G's closed forms: sin of the phase Theta = w1 tau computed in floats is off by ~ u Theta
    (w1 from a rounded product and root, w1 tau rounded), moving G by its slope, at most the envelope
    exp(-delta tau)/(m w1), times 4 u (1 + Theta); the exponentials' arguments delta tau (or g1 tau) are
    rounded too: a relative 4 u (1 + delta tau) of G."""
    phase, decay = _phase(p)
    G = analytic(p)["G"]
    err = 4.0 * _U * (1.0 + decay) * abs(G)
    if phase > 0.0:
        w1 = phase / p.tau
        err += 4.0 * _U * (1.0 + phase) * math.exp(-decay) / (p.m * w1)
    return {"G": err}


def _characteristic_roots(d):
    """The roots of lambda^2 + 2 d lambda + 1 = 0 (q'' + 2 d q' + q = 0 with q = exp(lambda t)), free of
    round-off: the large-magnitude root of an overdamped pair directly, the small one as the reciprocal
    (their product is 1).  numpy's eigenvalues lose it: at d = 1e8 the slow rate 1/(2d) = 5e-9 is
    below their absolute round-off ~ u 2d = 2e-8 and can come out growing."""
    if d > 1.0:
        fast = -(d + math.sqrt(d - 1.0) * math.sqrt(d + 1.0))
        return np.array([fast, 1.0 / fast], dtype=complex)
    if d == 1.0:
        return np.array([-1.0, -1.0], dtype=complex)
    w1 = math.sqrt((1.0 - d) * (1.0 + d))
    return np.array([complex(-d, w1), complex(-d, -w1)])


def _segment_length(lam, w):
    """The segment of the impulse response's transform (one segment plus the exact geometric sum), whether
    the system is stiff, its slow rate, and the amplification of a segment map's error at a length D."""
    # impulse response, transformed: one segment plus the exact geometric sum
    slow, fast = np.min(-lam.real), np.max(-lam.real)
    osc = np.max(np.abs(lam.imag))
    stiff = fast / slow > 50.0
    # one segment: up to one slow decay time, at most four oscillation periods; when stiff, at most four
    # periods of the drive too (the implicit method crosses the fast transient in a few steps).  A
    # segment cut at the fast transient (50 fast decay times) left the slow mode at exp(-25/(2 d^2))
    # = 1 - 1e-15 (d = 1e8): the geometric sum's 1 - exp(i w D) mu amplified its error by up to 1e7
    segment = min(1.0 / slow, 8.0 * math.pi / osc if osc > 0 else math.inf,
                  8.0 * math.pi / w if stiff and w > 0 else math.inf)
    if w > 4.0 * max(1.0, float(np.max(np.abs(lam)))) and w * segment > math.pi:
        # a fast drive: half a period of exp(i w t) per segment (exp(i w D) = -1 keeps the sum well
        # conditioned) instead of resolving hundreds of its periods in one segment
        segment = math.pi / w

    def amplification(D):
        # the segment map's error is amplified by 1/|1 - exp(i w D) mu| (mu = exp(lam D): its eigenvalues)
        return 1.0 / np.min(np.abs(1.0 - np.exp(1j * w * D) * np.exp(lam * D)))

    # avoid a segment whose length makes exp(i (w -+ w1) D) = 1 by accident (not a physical resonance)
    segment = min((segment * f for f in (1.0, 0.9, 0.8, 0.7, 0.6, 0.5)), key=lambda D: (amplification(D), -D))
    return segment, stiff, slow, amplification


def _impulse_slope(poles, t):
    """A bound on |q'| at the scaled time t after a unit impulse (see ``numeric``'s phase round-off)."""
    # and the scaled time t = tau w0 is rounded: the integral is G at t (1 + u), off by u t |G'(t)|.  The
    # slope is bounded by the velocity after a unit impulse: |q'| <= 1 (the energy 1/2 never grows) and,
    # from the residues at the poles (slowest decay rate s, fastest f), |q'| <= e^{-s t} (1 + s t + s/(f - s))
    # (the last term only when the rates differ: overdamped).  A long phase of a weakly damped oscillator
    # (t of 1e11, phase known to 1e-5 rad) makes this the largest part
    rates = sorted(-z.imag for z in poles)
    # the slow rate of a strongly overdamped oscillator is rounded relative to the fast one (the roots'
    # product is 1 in these units, so 1/f gives it to full precision); the smaller keeps the bound safe
    f_fast = rates[-1]
    s_slow = min(rates[0], 1.0 / f_fast)
    spread = s_slow / (f_fast - s_slow) if f_fast - s_slow > 1e-8 * f_fast else 0.0
    slope = min(1.0, math.exp(-s_slow * t) * (1.0 + s_slow * t + spread))
    if f_fast - s_slow > 1e-8 * f_fast:
        # distinct real rates (overdamped): q = (e^{-s t} - e^{-f t})/(f - s) exactly, so
        # |q'| <= (s e^{-s t} + f e^{-f t})/(f - s): ~ s/f = 1/(4 d^2) once the fast transient is over
        # (the bound above, ~1, claimed 1.7e-7 of G at d = 5.4e7)
        slope = min(slope, (s_slow * math.exp(-s_slow * t) + f_fast * math.exp(-f_fast * t)) / (f_fast - s_slow))
    return slope


@exercise.numeric
def numeric(p, run):
    m, w0 = p.m, p.omega0
    d = p.delta / w0  # scaled damping
    t = p.tau * w0
    w = p.omega / w0

    # the equation of motion q'' + 2 d q' + q = f in scaled units, as y' = A y + b f
    A = np.array([[0.0, 1.0], [-1.0, -2.0 * d]])
    b = np.array([0.0, 1.0])
    c = np.array([1.0, 0.0])

    def chi_local(base, off):
        # frequency domain: q = a exp(-i x t) turns q'' + 2 d q' + q = F into (-x^2 - 2 i d x + 1) a = F,
        # at x = base + off (arrays), 1 - x^2 as (1 - x)(1 + x) with 1 - x = (1 - base) - off (1 - base exact
        # near x = 1): a resonance of width d = 1e-10 is resolved without the 1e-16 rounding of x itself
        # beyond |x| ~ 1e154 (an early time's window reaches 40/t) the product overflows and chi = 0,
        # its true size ~ 1/x^2 being under the smallest double anyway
        with np.errstate(over="ignore"):
            return 1.0 / (((1.0 - base) - off) * ((1.0 + base) + off) - 2j * d * (base + off))

    # characteristic roots in the frequency variable: where the coefficient above vanishes
    lam = _characteristic_roots(d)  # time domain: q = exp(lam t)
    poles = 1j * lam  # frequency domain: q = exp(-i x t) at x = i lam
    eps_q = max(0.1 * run.rtol, 1e-14)
    Gp = inverse_fourier(chi_local, t, poles, epsrel=eps_q, vectorized=True, local=True)
    Gm = inverse_fourier(chi_local, -t, poles, epsrel=eps_q, vectorized=True, local=True)

    segment, stiff, slow, amplification = _segment_length(lam, w)
    method = FLOW if stiff else "DOP853"
    atol = None
    if stiff:
        # absolute tolerances at each component's own size: Phi's entries (row-major) go as 1, s, s, s^2
        # (s the slow rate, 1/s the fast one), the accumulators as those of q times min(D, 1/w).  A common
        # atol of 1e-3 rtol sat above the q' row (1/(2d)): det(Phi) drifted 8e-7 at d = 1e10
        L = min(segment, 1.0 / w) if w > 0 else segment
        atol = 1e-3 * run.rtol * np.array([1.0, slow, slow, slow * slow, L, slow * L, L, slow * L])
    spec = impulse_spectrum(A, b, c, w, rtol=run.rtol, segment=segment, method=method,
                            integrator=run.integrator, atol=atol)
    run.record(spec.traj)
    run.invariant("Liouville det(Phi)", spec.liouville_drift)
    run.info["segment"] = segment / w0
    run.info["stiff"] = bool(stiff)
    run.info["quad_error_estimate"] = Gp.abserr + Gm.abserr
    run.info["quad_panels"] = Gp.panels + Gm.panels
    run.info["quad_tail_cycles"] = Gp.tail_cycles + Gm.tail_cycles
    run.info["quad_evaluations"] = Gp.evaluations + Gm.evaluations

    # honest accuracy: the segment map's error is amplified as above
    amp = amplification(segment)
    chi_abs = float(abs(spec.value)) / (m * w0 * w0)  # |chi| in the output's units (spec.value is scaled)
    # and for a fast drive the half-period segments' integrals (~1/w) cancel down to chi (~1/w^2): relative ~ w
    rel_chi = max(run.rtol * 100.0, 1e-13) * max(1.0, amp) * max(1.0, w)
    rel_chi = float(rel_chi)
    run.claim("chi_re", rel=rel_chi, abs=rel_chi * chi_abs)
    run.claim("chi_im", rel=rel_chi, abs=rel_chi * chi_abs)
    # the quadrature: relative to the size of G's scale (1/(m w0) in these units), plus its own error estimate
    # (a strongly overdamped chi is a peak of width 1/(2d) and G is ~ 1/(2d): the quadrature's target is
    # eps_q times the pieces' summed sizes, that small too, and 100 eps_q claimed 2e-9 of G at d = 1e8)
    g_scale = min(1.0, max(Gp.target, Gm.target) / eps_q) if d > 1.0 else 1.0
    g_abs = float(100.0 * eps_q * g_scale + 10.0 * (Gp.abserr + Gm.abserr))
    # and the scaled time t = tau w0 is rounded: the integral is G at t (1 + u), off by u t |G'(t)|
    slope = _impulse_slope(poles, t)
    g_phase = 2.0 * 2.0**-53 * t * slope
    run.info["G_phase_roundoff"] = g_phase / (m * w0)
    run.claim("G", rel=100.0 * eps_q, abs=(g_abs + g_phase) / (m * w0))
    run.claim("G_minus", rel=100.0 * eps_q, abs=g_abs / (m * w0))
    run.method = spec.traj.method + " + Filon/Wynn Fourier quadrature"

    chi = spec.value / (m * w0 * w0)
    return {
        "G": Gp.value / (m * w0),
        "G_minus": Gm.value / (m * w0),
        "chi_re": chi.real,
        "chi_im": chi.imag,
    }
