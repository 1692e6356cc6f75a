"""5.8 Forced Duffing oscillator: the resonance curve, its peak and the bistability window.

Analytic (reduced equations, leading order): with q = A cos(omega t - phi),
A and phi slow, averaging over a period gives the stationary condition
A^2 [(xi - kappa A^2)^2 + delta^2] = (f0/(2 omega0))^2, kappa = 3 alpha/(8 omega0).
The peak is where xi = kappa A^2: A_max = f0/(2 omega0 delta), xi_peak = kappa A_max^2.
With s = (A/A_max)^2 and g = kappa A_max^2/delta, the curve folds where
d xi/d s = 0, i.e. s^3 (1 - s) = 1/(4 g^2), at xi = delta (g s + 1/(2 g s^2)).
Two roots (one each side of s = 3/4) exist only for |g| > 8/(3 sqrt 3): the
critical force.  They are found from s = 3/4 + t, t^2 ((1 + t)^2 + 1/8) =
27/256 - 1/(4 g^2), without the cancellation of the quartic near the cusp.

Numeric (exact periodic orbits, solvers/mechanics/continuation.py): the one-period map of the
full equation (time tau = omega t, variational equations carried along,
DOP853) and Newton on its fixed point give the periodic response at one
frequency.  An upward sweep starts below the resonance, a downward one above
it; each follows its branch (pseudo-arclength continuation, loosely converged
points) until det(M - I) changes sign: the fold where a slow sweep jumps.  The
fold is refined on the branch by Brent's method on det(M - I) at the full
tolerance; the peak by Brent's method on dA/ds, where A is half the
peak-to-peak swing (extrema by events on q' = 0; its gradient from the
variational equations at the extrema).  Liouville's formula det M =
exp(-4 pi delta/omega) is monitored.  Units: A by f0/(2 omega0 delta), the
detuning by delta.

Allowances (``_harmonic_balance``, the next order: one harmonic without the rotating-wave linearization):
  A_max, xi_peak, xi_lo, xi_hi  twice the change it makes + 0.1 eps + 2 (delta/omega0)^2; the folds fall
  back to 3 eps + 3 delta/omega0 where it finds no two (near the cusp).
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure, Undefined
from mech.solvers.numerics.roots import bracketed_root

exercise = Exercise(
    "5.8",
    formulas=[
        "A² [(ξ - κA²)² + δ²] = (f₀/2ω₀)²,  κ = 3α/(8ω₀)  (reduced equations)",
        "A_max = f₀/(2ω₀δ),  ξ_peak = κ A_max²",
        "g = κ A_max²/δ;  folds at s = (A/A_max)² with s³(1 - s) = 1/(4g²)",
        "ξ_fold = δ (g s + 1/(2 g s²));  bistable only for |g| > 8/(3√3)",
    ],
    leading_order=("A_max", "xi_peak", "xi_lo", "xi_hi"),
)

G_CRIT = 8.0 / (3.0 * math.sqrt(3.0))
MAX_DAMPING = 0.05  # delta/omega0: the weak damping the reduced equations need
MAX_NONLINEARITY = 0.05  # |alpha| A_max^2/omega0^2: the weak nonlinearity they need
# Near the critical force the leading-order theory cannot tell whether the curve folds: its g is off by
# relative O(eps + delta/omega0).  Refused within CUSP_BAND times that of g_crit (checked at the defaults'
# omega0, delta, alpha: at 4 % above and 3 % below g_crit both solvers agree on whether the curve folds)
CUSP_BAND = 3.0
G_MAX = 100.0  # largest |g| the sweeps resolve in their time budget (see the constraint)


def _small(p):
    am = p.f0 / (2.0 * p.omega0 * p.delta)
    return p.delta / p.omega0, abs(p.alpha) * am**2 / p.omega0**2


def _g(p):
    am = p.f0 / (2.0 * p.omega0 * p.delta)
    return 3.0 * p.alpha / (8.0 * p.omega0) * am**2 / p.delta


@exercise.constraint
def constraint(p):
    e_d, e_n = _small(p)
    if e_d > MAX_DAMPING:
        return (f"delta = {p.delta:g} 1/s is not weak damping for omega0 = {p.omega0:g} rad/s: "
                f"the reduced equations need delta <= {MAX_DAMPING:g} omega0")
    if e_n > MAX_NONLINEARITY:
        return (f"|alpha| A^2/omega0^2 = {e_n:.3g} at the resonant amplitude A = f0/(2 omega0 delta): "
                f"the weak-nonlinearity theory needs it <= {MAX_NONLINEARITY:g} (lower f0 or |alpha|)")
    g = abs(_g(p))
    if g > G_MAX:
        return (f"|g| = {g:.4g} (the peak's shift over the half-width, 3 alpha A^2/(8 omega0 delta)) exceeds {G_MAX:g}: "
                f"the curve's tip, where peak and upper fold lie delta/(4g) apart, is then too thin for the sweep's "
                "shooting within its time budget (lower f0 or |alpha|, or raise delta)")
    band = CUSP_BAND * (e_n + e_d)
    if abs(g / G_CRIT - 1.0) < band:
        return (f"the force is within {band:.2g} (relative) of the critical force of bistability, "
                f"f0 = {p.f0 * math.sqrt(G_CRIT / g):.6g} m/s^2 at leading order: closer than the theory's own "
                "error, it cannot tell whether the curve folds")


def _folds(g):
    """The two roots s of s^3 (1 - s) = 1/(4 g^2), or None below the critical |g|."""
    D = 27.0 / 256.0 - 1.0 / (4.0 * g * g)
    if D <= 0.0:
        return None
    roots = []
    for lo, hi in ((-0.75, 0.0), (0.0, 0.25)):
        # t^2 ((1 + t)^2 + 1/8) = D is monotonic on each bracket: bisection to the last bit
        roots.append(0.75 + bracketed_root(lambda t: t * t * ((1.0 + t) ** 2 + 0.125) - D, lo, hi))
    return roots


@exercise.analytic
def analytic(p):
    am = p.f0 / (2.0 * p.omega0 * p.delta)
    kappa = 3.0 * p.alpha / (8.0 * p.omega0)
    out = {"A_max": am, "xi_peak": kappa * am**2}
    g = kappa * am**2 / p.delta
    roots = _folds(g) if g != 0.0 else None
    if roots is None:
        why = f"no bistability: |g| = {abs(g):.4g} is below the critical 8/(3 sqrt 3) = {G_CRIT:.4g}"
        out["xi_lo"] = out["xi_hi"] = Undefined(why)
    else:
        xis = sorted(p.delta * (g * s + 1.0 / (2.0 * g * s * s)) for s in roots)
        out["xi_lo"], out["xi_hi"] = xis
    return out


def _harmonic_balance(p):
    """The next order: one harmonic, q = A cos(omega t - phi), balanced without the rotating-wave
    linearization (omega^2 - omega0^2 kept whole, the drag 2 delta omega):
        A^2 [(omega0^2 - omega^2 + 3 alpha A^2/4)^2 + 4 delta^2 omega^2] = f0^2
    (Nayfeh & Mook, Nonlinear Oscillations, sec. 4.1; Landau & Lifshitz, Mechanics, sec. 29).  The peak
    (dA/domega = 0): omega0^2 - omega^2 + 3 alpha A^2/4 = 2 delta^2, A = f0/(2 delta sqrt(omega^2 + delta^2));
    the folds: the extrema of omega along the curve, parametrized by s = A^2.  Returns {output: value}, the
    folds None where this curve has no two."""
    o0, d, al, f0 = p.omega0, p.delta, p.alpha, p.f0
    w = o0
    for _ in range(60):
        A = f0 / (2.0 * d * math.sqrt(w * w + d * d))
        w = math.sqrt(max(o0 * o0 + 0.75 * al * A * A - 2.0 * d * d, 1e-300))
    out = {"A_max": A, "xi_peak": w - o0, "xi_lo": None, "xi_hi": None}
    # s = A^2 (1 - u), u geometric: the upper fold lies within (delta/omega0)^2 of the tip at high Q
    # the tip, where the two branches meet: f0^2 = 4 delta^2 s (omega0^2 + 3 alpha s/4)
    s_top = 2.0 * f0 * f0 / (4.0 * d * d * o0 * o0 + math.sqrt(16.0 * d**4 * o0**4 + 12.0 * al * d * d * f0 * f0))
    s = (1.0 - np.geomspace(0.999, 1e-8, 6001)) * s_top
    ext = []
    for sign in (1.0, -1.0):
        ws = np.full_like(s, o0)
        for _ in range(20):
            arg = f0 * f0 / s - 4.0 * d * d * ws * ws
            ws = np.sqrt(np.maximum(o0 * o0 + 0.75 * al * s + sign * np.sqrt(np.maximum(arg, 0.0)), 1e-300))
        x = np.where(arg > 0, ws - o0, np.nan)
        dx = np.diff(x)
        for i in np.flatnonzero(dx[:-1] * dx[1:] < 0) + 1:
            y0, y1, y2 = x[i - 1], x[i], x[i + 1]
            curv = y0 - 2.0 * y1 + y2
            ext.append(float(y1 - 0.125 * (y2 - y0) ** 2 / curv) if curv != 0 else float(y1))
    if len(ext) >= 2:  # the outermost: a pair of round-off wiggles near the tip can add two more
        out["xi_lo"], out["xi_hi"] = min(ext), max(ext)
    return out


@exercise.expected_error
def expected_error(p):
    """Allowances, one line each, from the next order (``_harmonic_balance``: the relative change est of
    each output against the leading order; measured within 0.03-0.1 eps of the exact periodic orbits at the
    defaults and hard cases, eps = |alpha| A_max^2/omega0^2):
      A_max    2 |est| + 0.1 eps + 2 (delta/omega0)^2;
      xi_peak  2 |est| + 0.1 eps + 2 (delta/omega0)^2 (est includes the linear resonance's -delta^2/omega0:
               where that dominates the leading value the theory is outside its range);
      xi_lo, xi_hi  2 |est| + 0.1 eps + 2 (delta/omega0)^2; where the next order finds no two folds (near the
               cusp), the bound 3 eps + 3 delta/omega0 (measured coefficients 1.0 and 0.7)."""
    e_d, e_n = _small(p)
    lead = analytic(p)
    nx = _harmonic_balance(p)
    floor = 0.1 * e_n + 2.0 * e_d**2
    out = {}
    for name in ("A_max", "xi_peak", "xi_lo", "xi_hi"):
        a = lead[name]
        if isinstance(a, Undefined):
            continue
        if nx[name] is None or a == 0:
            out[name] = 3.0 * e_n + 3.0 * e_d
        else:
            out[name] = 2.0 * abs(nx[name] / a - 1.0) + floor
    return out


@exercise.theory_range
def theory_range(p):
    """The reduced equations expand in eps = |alpha| A_max^2/omega0^2 and delta/omega0 (the larger shown)."""
    e_d, e_n = _small(p)
    big = ("|alpha| A_max^2/omega0^2", e_n) if e_n >= e_d else ("delta/omega0", e_d)
    return {name: big for name in ("A_max", "xi_peak", "xi_lo", "xi_hi")}


# ---------------------------------------------------------------------------------------------------------
def _force(omega0, delta, alpha):
    w2, d2 = omega0 * omega0, 2.0 * delta

    def force(q, v):
        return -d2 * v - w2 * q - alpha * q * q * q, -w2 - 3.0 * alpha * q * q, -d2

    return force


def _remainder(delta, alpha):
    """The force per unit mass besides the linear -omega0^2 q and the drive: drag and the cubic."""
    d2 = 2.0 * delta

    def remainder(q, v):
        return -d2 * v - alpha * q * q * q, -3.0 * alpha * q * q, -d2

    return remainder


# damping per period 4 pi delta/omega0 below which the one-period map is taken in the rotating frame: the
# plain map resolves its fixed point only to rtol/damp, and its refinements, at rtol 10 damp, reach the
# integrator's floor 3e-14 at rtol/10 = 1e-11 for damp 3e-4; the rotating one costs 1.7 times the
# evaluations (its integrand carries the cubic's harmonics), so the defaults (damp 0.025) keep the plain one
ROTATING_BELOW = 1e-3
MAX_CHORD = 1.0  # longest bracket (scaled units) refined directly: a longer one is first re-swept in short steps


def _turn(bp):
    return bp.tangent[2]  # det(M - I): zero at a fold


def _swing_slope(bp):
    return bp.dA_ds  # zero at the peak


@exercise.numeric
def numeric(p, run):
    from mech.solvers.mechanics.continuation import OrbitMap, RotatingOrbitMap, refine_root, shorten_bracket, solve_on_plane, sweep

    rtol = run.rtol
    Q = p.f0 / (2.0 * p.omega0 * p.delta)  # unit of length: the linear resonant swing
    W = p.delta  # unit of detuning: the half-width
    memo_key = ("5.8", *(float(p[k]) for k in p))
    damp = 4.0 * math.pi * p.delta / p.omega0  # 1 - det M: the damping per period
    if damp < ROTATING_BELOW:
        # the map in the rotating frame, integrated as its increment over the damping scale: its fixed
        # point is conditioned by O(1) however weak the damping.  The sweeps only bracket (points to
        # ~1e-5), the refinements run at rtol
        rs, rr = max(rtol, 1e-7), rtol
        om = RotatingOrbitMap(_remainder(p.delta, p.alpha), p.f0, Q, p.omega0, W, 2.0 * p.delta / p.omega0,
                              memo=run.shared, memo_key=memo_key, integrator=run.integrator)
    else:
        # the plain map: its fixed point's condition number is about 1/damp, and the sweep needs its points
        # to ~1e-5; the refinements integrate at rtol scaled by the same condition number, so that the
        # orbit (and so the outputs) come out to about rtol
        rs = max(rtol, min(1e-7, 1e-6 * damp))
        rr = max(3e-14, rtol * min(1.0, 10.0 * damp))  # scipy floors rtol at 2.2e-14
        # the drag and the cubic are odd in (q, q'): the half-period map of the symmetric orbit (see OrbitMap).
        # DOP853 starts at 4 rtol^(1/8) of drive phase: its steps on these near-harmonic orbits settle at
        # 5-6 rtol^(1/8) (measured at rtol 2.5e-8 - 2.5e-12), where its own start spends three steps growing
        om = OrbitMap(_force(p.omega0, p.delta, p.alpha), p.f0, Q, p.omega0, W, memo=run.shared, memo_key=memo_key,
                      integrator=run.integrator, odd=True, step_scale=4.0)
    run.info["rtol_integration"] = rr
    run.info["orbit_map"] = type(om).__name__
    # the sweeps run over +-(4 half-widths + 0.6 times the nonlinear shift scale |alpha| Q^2/omega0)
    w_end = 4.0 + 0.6 * abs(p.alpha) * Q * Q / (p.omega0 * p.delta)

    def start(w):
        bp = solve_on_plane(om, [0.0, 0.0, w], [0.0, 0.0, 1.0], w, rtol=rs, tol=1e-6, max_iter=20, fresh=False)
        if bp is None:
            raise NumericFailure(f"no periodic orbit found at the sweep's end w = {w:g}")
        return bp

    h_max = max(1.0, 0.2 * w_end)

    def refine(a, b, g, polish):
        a, b = shorten_bracket(om, a, b, g, rtol=rs, max_chord=MAX_CHORD)
        return refine_root(om, a, b, g, rtol=rr, rtol_search=rs, xtol=1e-7, polish=polish)

    up = sweep(om, start(-w_end), +1.0, w_end, rtol=rs, h_max=h_max)
    sweeps = [up]
    folds = []
    if up.fold_bracket is not None:
        folds.append(refine(*up.fold_bracket, _turn, False))
        down = sweep(om, start(w_end), -1.0, -w_end, rtol=rs, h_max=h_max)
        if down.fold_bracket is None:
            raise NumericFailure("the upward sweep jumped but the downward one did not: no consistent window")
        folds.append(refine(*down.fold_bracket, _turn, False))
        sweeps.append(down)
    run.info["sweep_steps"] = [s.steps for s in sweeps]
    run.info["sweep_rejected"] = [s.rejected for s in sweeps]

    # the peak: the largest swing seen, refined where dA/ds changes sign next to it
    best = max(((k, i) for k, s in enumerate(sweeps) for i in range(len(s.points))),
               key=lambda ki: sweeps[ki[0]].points[ki[1]].A)
    pts = sweeps[best[0]].points
    i = best[1]
    for end in (pts[0], pts[-1] if sweeps[best[0]].fold_bracket is None else None):
        if end is not None and end.A > 0.35 * pts[i].A:
            raise NumericFailure("a sweep's end is not far from the resonance: the sweep range is too short")
    # the sweep's points are loosely converged and carry their last iterate's Jacobian: near the flat
    # maximum dA/ds is small, so the largest point and its neighbours are first put on the branch
    near = []
    for bp in pts[max(0, i - 1): i + 2]:
        t = bp.tangent / np.linalg.norm(bp.tangent)
        fixed = solve_on_plane(om, bp.z, t, t @ bp.z, rtol=rs, tol=1e-9, max_iter=12, fresh=False)
        if fixed is None:
            raise NumericFailure(f"could not put the sweep's point at w = {bp.z[2]:.6g} back on the branch")
        near.append(fixed)
    pairs = [(u, v) for u, v in zip(near, near[1:]) if np.sign(u.dA_ds) != np.sign(v.dA_ds)]
    if not pairs:
        raise NumericFailure("the swing's maximum is not bracketed by the sweep's points")
    a, b = pairs[0]
    peak = refine(a, b, _swing_slope, True)

    # Liouville: the divergence of the flow is -2 delta, so det M = exp(-4 pi delta/omega) exactly
    monodromy = getattr(om, "monodromy", lambda bp: bp.M)
    for bp in [peak, *folds]:
        det_exact = math.exp(-4.0 * math.pi * p.delta / om.omega(bp.z[2]))
        run.invariant("Liouville det M", (float(np.linalg.det(monodromy(bp))) - det_exact) / det_exact)
    run.record(om, method="DOP853")  # every integration of the orbit map
    run.info["orbit_maps"] = om.calls
    run.info["orbit_maps_reused"] = om.memo_hits  # taken from the solve by its rerun (Run.shared)

    # the peak's position is a root of dA/ds, whose noise is set by the tolerance relative to the curve's
    # own scale, the half-width: an absolute claim for a peak shift that may be tiny (weak alpha)
    run.claim("xi_peak", rel=exercise.tol_factor * rtol, abs=1e3 * rtol * p.delta)
    out = {"A_max": peak.A * Q, "xi_peak": peak.z[2] * W}
    if folds:
        xi = sorted(f.z[2] * W for f in folds)
        out["xi_lo"], out["xi_hi"] = xi
        run.info["fold_multipliers"] = [sorted(np.abs(np.linalg.eigvals(monodromy(f))).tolist()) for f in folds]
    else:
        why = "no bistability: both sweeps follow one branch without a fold"
        out["xi_lo"] = out["xi_hi"] = Undefined(why)
    return out
