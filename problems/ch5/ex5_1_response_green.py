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

The route is written once, over arrays of variants (``numeric``; a one-point solve is its
batch of one): the non-stiff variants' segments are stepped together, each in the time
s/D (fourier.oscillator_spectra), the stiff ones by their flow one by one, and each
variant's G by its own adaptive quadrature, once per distinct (delta/omega0, tau omega0).

A weakly damped oscillator asked late (tau of 1e5..1e11 periods) has a phase
Theta = w1 tau known in floats to u Theta only (u = 2^-53; the product tau w0 is
rounded, in both methods): the claims and ``analytic_error`` carry that
round-off times the envelope exp(-delta tau), and a phase beyond 1e15 rad, where
it carries no digit, is refused while the envelope still matters.
"""

from __future__ import annotations

import math

import numpy as np

from mech.core.budget import OutOfBudget
from mech.core.errors import NumericFailure
from mech.problems.spec import Exercise, Tally
from mech.solvers.numerics.fourier import FLOW, impulse_spectrum, inverse_fourier, oscillator_spectra

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


def _arrays(P):
    return (np.asarray(P[k], dtype=float) for k in ("m", "omega0", "delta", "tau", "omega"))


def _green(m, w0, d, t):
    """G(tau) by the closed forms, over arrays, and its round-off: sin of the phase Theta = w1 tau computed
    in floats is off by ~ u Theta (w1 from a rounded product and root, w1 tau rounded), moving G by its
    slope, at most the envelope exp(-delta tau)/(m w1), times 4 u (1 + Theta); the exponentials' arguments
    delta tau (or g1 tau) are rounded too: a relative 4 u (1 + delta tau) of G."""
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        under, over = d < w0, d > w0
        w1 = np.sqrt(np.where(under, (w0 - d) * (w0 + d), 1.0))
        wp = np.sqrt(np.where(over, (d - w0) * (d + w0), 1.0))
        g1 = w0 * w0 / (d + wp)  # = d - wp without cancellation
        G = np.where(under, np.exp(-d * t) * np.sin(w1 * t) / (m * w1),
                     np.where(over, np.exp(-g1 * t) * (-np.expm1(-2.0 * wp * t)) / (2.0 * m * wp),
                              t * np.exp(-d * t) / m))
        phase, decay = np.where(under, w1 * t, 0.0), d * t
        err = 4.0 * _U * (1.0 + decay) * np.abs(G)
        err = err + np.where(phase > 0.0, 4.0 * _U * (1.0 + phase) * np.exp(-decay) / (m * w1), 0.0)
    return G, err


@exercise.analytic
def analytic(P):
    """The closed forms over arrays of variants, G's round-off its Column's ``abs`` (``_green``)."""
    from mech.solvers.numerics.batch import Column

    m, w0, d, t, w = _arrays(P)
    G, err = _green(m, w0, d, t)
    chi = 1.0 / (m * ((w0 - w) * (w0 + w) - 2j * d * w))
    return {"G": Column(G, abs=err), "G_minus": Column(np.zeros_like(G)), "chi_re": Column(chi.real),
            "chi_im": Column(chi.imag)}


@exercise.analytic_error
def analytic_error(p):
    """G's round-off at one point (``_green``)."""
    return {"G": float(_green(*(np.float64(p[k]) for k in ("m", "omega0", "delta", "tau")))[1])}


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


def _chi_local(d):
    """chi in scaled units at x = base + off (arrays) for the damping d (``inverse_fourier``'s local form)."""

    def chi_local(base, off):
        # frequency domain: q = a exp(-i x t) turns q'' + 2 d q' + q = F into (-x^2 - 2 i d x + 1) a = F,
        # at x = base + off (arrays), 1 - x^2 as (1 - x)(1 + x) with 1 - x = (1 - base) - off (1 - base exact
        # near x = 1): a resonance of width d = 1e-10 is resolved without the 1e-16 rounding of x itself
        # beyond |x| ~ 1e154 (an early time's window reaches 40/t) the product overflows and chi = 0,
        # its true size ~ 1/x^2 being under the smallest double anyway
        with np.errstate(over="ignore"):
            return 1.0 / (((1.0 - base) - off) * ((1.0 + base) + off) - 2j * d * (base + off))

    return chi_local


def _green_numeric(d, t, rtol):
    """G(+-t) in scaled units (time 1/w0, G in 1/(m w0)) by the inverse Fourier integral of chi, each
    variant's own adaptive quadrature: (G+, G-, claimed absolute errors of each, quadrature info, why
    failed ("" where not)).  The claims: relative to G's scale, plus the quadrature's own estimate, plus the
    rounding of the scaled time (see the comments)."""
    N = d.size
    Gp, Gm, ep, em = (np.full(N, np.nan) for _ in range(4))
    info = {k: np.full(N, np.nan) for k in ("quad_error_estimate", "quad_panels", "quad_tail_cycles",
                                            "quad_evaluations", "G_phase_roundoff")}
    why = np.full(N, "", dtype=object)
    eps_q = max(0.1 * rtol, 1e-14)
    for k in range(N):
        poles = 1j * _characteristic_roots(float(d[k]))  # frequency domain: q = exp(-i x t) at x = i lam
        chi_local = _chi_local(float(d[k]))
        try:
            plus = inverse_fourier(chi_local, float(t[k]), poles, epsrel=eps_q, vectorized=True, local=True)
            minus = inverse_fourier(chi_local, -float(t[k]), poles, epsrel=eps_q, vectorized=True, local=True)
        except NumericFailure as exc:
            if isinstance(exc, OutOfBudget):
                raise
            why[k] = str(exc)
            continue
        # the quadrature: relative to the size of G's scale (1/(m w0) in these units), plus its own error
        # estimate (a strongly overdamped chi is a peak of width 1/(2d) and G is ~ 1/(2d): the quadrature's
        # target is eps_q times the pieces' summed sizes, that small too, and 100 eps_q claimed 2e-9 of G
        # at d = 1e8)
        g_scale = min(1.0, max(plus.target, minus.target) / eps_q) if d[k] > 1.0 else 1.0
        g_abs = 100.0 * eps_q * g_scale + 10.0 * (plus.abserr + minus.abserr)
        # and the scaled time t = tau w0 is rounded: the integral is G at t (1 + u), off by u t |G'(t)|
        g_phase = 2.0 * _U * float(t[k]) * _impulse_slope(poles, float(t[k]))
        Gp[k], Gm[k], ep[k], em[k] = plus.value, minus.value, g_abs + g_phase, g_abs
        for name, v in (("quad_error_estimate", plus.abserr + minus.abserr),
                        ("quad_panels", plus.panels + minus.panels),
                        ("quad_tail_cycles", plus.tail_cycles + minus.tail_cycles),
                        ("quad_evaluations", plus.evaluations + minus.evaluations), ("G_phase_roundoff", g_phase)):
            info[name][k] = v
    return Gp, Gm, ep, em, info, why


def _chi_numeric(d, w, rtol, tally):
    """chi in scaled units (1/(m w0^2)) as the transform of the integrated impulse response: each variant's
    segment, the non-stiff ones stepped together (``oscillator_spectra``), a stiff one by its exact flow
    (``impulse_spectrum``'s FLOW); (values, relative claims, Liouville drifts, segments, stiff, why failed)."""
    N = d.size
    value = np.full(N, np.nan, dtype=complex)
    rel, drift, segment = np.full(N, np.nan), np.zeros(N), np.full(N, np.nan)
    stiff = np.zeros(N, dtype=bool)
    amp = np.ones(N)
    why = np.full(N, "", dtype=object)
    for k in range(N):
        segment[k], stiff[k], slow, amplification = _segment_length(_characteristic_roots(float(d[k])), float(w[k]))
        amp[k] = amplification(segment[k])
        if not stiff[k]:
            continue
        # absolute tolerances at each component's own size: Phi's entries (row-major) go as 1, s, s, s^2
        # (s the slow rate, 1/s the fast one), the accumulators as those of q times min(D, 1/w).  A common
        # atol of 1e-3 rtol sat above the q' row (1/(2d)): det(Phi) drifted 8e-7 at d = 1e10
        L = min(segment[k], 1.0 / w[k]) if w[k] > 0 else segment[k]
        atol = 1e-3 * rtol * np.array([1.0, slow, slow, slow * slow, L, slow * L, L, slow * L])
        A = np.array([[0.0, 1.0], [-1.0, -2.0 * d[k]]])
        try:
            spec = impulse_spectrum(A, np.array([0.0, 1.0]), np.array([1.0, 0.0]), float(w[k]), rtol=rtol,
                                    segment=float(segment[k]), method=FLOW, integrator=tally.integrator, atol=atol)
        except NumericFailure as exc:
            if isinstance(exc, OutOfBudget):
                raise
            why[k] = str(exc)
            continue
        tally.record(spec.traj)
        value[k], drift[k] = spec.value, spec.liouville_drift
    easy = np.flatnonzero(~stiff)
    if easy.size:
        got, dr, ens = oscillator_spectra(d[easy], w[easy], rtol=rtol, segment=segment[easy],
                                          follow=lambda *a, **kw: tally.follow(*a, **kw, on_failure="mark"))
        value[easy], drift[easy] = got, np.where(ens.failed, 0.0, dr)
        why[easy] = np.where(ens.failed, ens.why, why[easy])
    # honest accuracy: the segment map's error is amplified by 1/|1 - exp(i w D) mu| (``_segment_length``),
    # and for a fast drive the half-period segments' integrals (~1/w) cancel down to chi (~1/w^2): relative ~ w
    rel = max(rtol * 100.0, 1e-13) * np.maximum(1.0, amp) * np.maximum(1.0, w)
    return value, rel, drift, segment, stiff, why


@exercise.batched(("G", "G_minus", "chi_re", "chi_im"))
def numeric(P, rtol, outputs, memo=None, tally=None):
    """Both domains crossed over arrays of variants, in scaled units (time 1/w0): G(+-tau) by the inverse
    Fourier integral of chi once per distinct (d, t) and chi by the integrated impulse response once per
    distinct (d, w), kept in ``memo`` across a sweep's chunks; Liouville's det(Phi) = exp(-2 d D) monitored
    and failing chi where it drifts beyond the claim."""
    from mech.solvers.numerics.batch import Column, by_rows

    m, w0, delta, tau, omega = _arrays(P)
    memo = {} if memo is None else memo
    tally = Tally() if tally is None else tally
    d, t, w = delta / w0, tau * w0, omega / w0  # scaled damping, time and drive
    out = {}
    parts = ["DOP853"] * bool({"chi_re", "chi_im"} & set(outputs)) + ["Filon/Wynn Fourier quadrature"] * bool(
        {"G", "G_minus"} & set(outputs))
    tally.method = " + ".join(parts)
    if {"G", "G_minus"} & set(outputs):
        def green(dd, tt):
            Gp, Gm, ep, em, info, why = _green_numeric(dd, tt, rtol)
            return (Gp, Gm, ep, em, why, *info.values())

        got = by_rows(memo, ("G", rtol), (d, t), green)
        failed = [(got[4] == r, r) for r in dict.fromkeys(got[4][got[4] != ""])]
        scale = m * w0
        out["G"] = Column(got[0] / scale, rel=100.0 * max(0.1 * rtol, 1e-14), abs=got[2] / scale, failed=failed)
        out["G_minus"] = Column(got[1] / scale, rel=100.0 * max(0.1 * rtol, 1e-14), abs=got[3] / scale,
                                failed=failed)
        names = ("quad_error_estimate", "quad_panels", "quad_tail_cycles", "quad_evaluations", "G_phase_roundoff")
        for name, v in zip(names, got[5:]):
            v = v / scale if name in ("quad_error_estimate", "G_phase_roundoff") else v
            tally.info[name] = [None if x != x else x for x in v.tolist()]
    if {"chi_re", "chi_im"} & set(outputs):
        chi, rel, drift, segment, stiff, why = by_rows(memo, ("chi", rtol), (d, w),
                                                       lambda dd, ww: _chi_numeric(dd, ww, rtol, tally))
        tally.invariant("Liouville det(Phi)", drift)
        allowed = exercise.tol_factor * rtol
        drifted = f"Liouville's det(Phi) drifted by more than {allowed:.3g}"
        failed = [(why == r, r) for r in dict.fromkeys(why[why != ""])] + [(~(np.abs(drift) <= allowed), drifted)]
        chi = chi / (m * w0 * w0)
        size = np.abs(chi)
        out["chi_re"] = Column(chi.real, rel=rel, abs=rel * size, failed=failed)
        out["chi_im"] = Column(chi.imag, rel=rel, abs=rel * size, failed=failed)
        tally.info["segment"] = (segment / w0).tolist()
        tally.info["stiff"] = stiff.tolist()
    return out
