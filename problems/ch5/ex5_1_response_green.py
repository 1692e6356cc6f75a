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
Wynn's epsilon algorithm); solvers/response.inverse_fourier.
(2) chi(w) as the Fourier transform of the integrated impulse response
(q = 0, q' = 1/m): the equation of motion's fundamental matrix with two
accumulators of q exp(i w t) is integrated over one segment (mech's DOP853, or
scipy's LSODA, which switches to its implicit BDF branch, only when the decay
rates differ by more than 50: strongly overdamped, stiff), and
the infinite decaying run is summed exactly by the semigroup property as a
geometric series; solvers/response.impulse_spectrum (a drive much faster than
the oscillator gets segments of half its period).  Liouville's
det Phi = exp(-2 delta t) is monitored.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise
from mech.solvers.numerics.fourier import impulse_spectrum, inverse_fourier

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
        "until the motion has decayed by exp(-40); LSODA (BDF) only where the decay rates differ by more "
        "than 50."
    ),
)


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
        return 1.0 / (((1.0 - base) - off) * ((1.0 + base) + off) - 2j * d * (base + off))

    # characteristic roots in the frequency variable: where the coefficient above vanishes
    poles = np.roots([-1.0, -2j * d, 1.0])
    eps_q = max(0.1 * run.rtol, 1e-14)
    Gp = inverse_fourier(chi_local, t, poles, epsrel=eps_q, vectorized=True, local=True)
    Gm = inverse_fourier(chi_local, -t, poles, epsrel=eps_q, vectorized=True, local=True)

    # impulse response, transformed: one segment plus the exact geometric sum
    lam = np.linalg.eigvals(A)
    slow, fast = np.min(-lam.real), np.max(-lam.real)
    osc = np.max(np.abs(lam.imag))
    stiff = fast / slow > 50.0
    # one segment: up to one slow decay time, at most four oscillation periods; when stiff, the
    # implicit integration stops after the fast transient (50 fast decay times) and the exact
    # geometric sum carries the slow tail
    segment = min(1.0 / slow, 8.0 * math.pi / osc if osc > 0 else math.inf, 50.0 / fast if stiff else math.inf)
    if w > 4.0 * max(1.0, float(np.max(np.abs(lam)))) and w * segment > math.pi:
        # a fast drive: half a period of exp(i w t) per segment (exp(i w D) = -1 keeps the sum well
        # conditioned) instead of resolving hundreds of its periods in one segment
        segment = math.pi / w

    def amplification(D):
        # the segment map's error is amplified by 1/|1 - exp(i w D) mu| (mu = exp(lam D): its eigenvalues)
        return 1.0 / np.min(np.abs(1.0 - np.exp(1j * w * D) * np.exp(lam * D)))

    # avoid a segment whose length makes exp(i (w -+ w1) D) = 1 by accident (not a physical resonance)
    segment = min((segment * f for f in (1.0, 0.9, 0.8, 0.7, 0.6, 0.5)), key=lambda D: (amplification(D), -D))
    method = "LSODA" if stiff else "DOP853"
    spec = impulse_spectrum(A, b, c, w, rtol=run.rtol, segment=segment, method=method,
                            integrator=run.integrator)
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
    chi_abs = float(abs(spec.value))
    # and for a fast drive the half-period segments' integrals (~1/w) cancel down to chi (~1/w^2): relative ~ w
    rel_chi = max(run.rtol * 100.0, 1e-13) * max(1.0, amp) * max(1.0, w)
    rel_chi = float(rel_chi)
    run.claim("chi_re", rel=rel_chi, abs=rel_chi * chi_abs)
    run.claim("chi_im", rel=rel_chi, abs=rel_chi * chi_abs)
    # the quadrature: relative to the size of G's scale (1/(m w0) in these units), plus its own error estimate
    g_abs = float(100.0 * eps_q + 10.0 * (Gp.abserr + Gm.abserr))
    run.claim("G", rel=100.0 * eps_q, abs=g_abs / (m * w0))
    run.claim("G_minus", rel=100.0 * eps_q, abs=g_abs / (m * w0))
    run.method = method + " + Filon/Wynn Fourier quadrature"

    chi = spec.value / (m * w0 * w0)
    return {
        "G": Gp.value / (m * w0),
        "G_minus": Gm.value / (m * w0),
        "chi_re": chi.real,
        "chi_im": chi.imag,
    }
