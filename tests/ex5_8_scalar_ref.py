"""5.8's scalar allowances and leading-order answers as they were before they were written over arrays
(problems/ch5/ex5_8_duffing_resonance.py at main 401767b: ``_folds``, ``_analytic_at``,
``_harmonic_balance``, ``_expected_at``, ``_range_at``), frozen here as the reference the array hooks
must reproduce (tests/test_ex5_8_array_hooks.py).  One point at a time, plain floats; not a test module."""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Undefined
from mech.solvers.numerics.roots import bracketed_root

G_CRIT = 8.0 / (3.0 * math.sqrt(3.0))
CUSP_BAND = 3.0


def _small(p):
    am = p.f0 / (2.0 * p.omega0 * p.delta)
    return p.delta / p.omega0, abs(p.alpha) * am**2 / p.omega0**2


def _g(p):
    am = p.f0 / (2.0 * p.omega0 * p.delta)
    return 3.0 * p.alpha / (8.0 * p.omega0) * am**2 / p.delta




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


def _analytic_at(p):
    """The leading-order answers at one point (``analytic`` runs it for each variant)."""
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
    sign = np.array([[1.0], [-1.0]])  # both halves of the curve at once, row by row
    ws = np.full((2, s.size), o0)
    for _ in range(20):
        arg = f0 * f0 / s - 4.0 * d * d * ws * ws
        ws = np.sqrt(np.maximum(o0 * o0 + 0.75 * al * s + sign * np.sqrt(np.maximum(arg, 0.0)), 1e-300))
    for x in np.where(arg > 0, ws - o0, np.nan):
        dx = np.diff(x)
        for i in np.flatnonzero(dx[:-1] * dx[1:] < 0) + 1:
            y0, y1, y2 = x[i - 1], x[i], x[i + 1]
            curv = y0 - 2.0 * y1 + y2
            ext.append(float(y1 - 0.125 * (y2 - y0) ** 2 / curv) if curv != 0 else float(y1))
    if len(ext) >= 2:  # the outermost: a pair of round-off wiggles near the tip can add two more
        out["xi_lo"], out["xi_hi"] = min(ext), max(ext)
    return out


def _expected_at(p):
    """Allowances at one point (``expected_error`` runs it for each variant), one line each, from the next order (``_harmonic_balance``: the relative change est of
    each output against the leading order; measured within 0.03-0.1 eps of the exact periodic orbits at the
    defaults and hard cases, eps = |alpha| A_max^2/omega0^2):
      A_max, xi_peak  2 |est| + 0.1 eps + 2 (delta/omega0)^2 (xi's est holds the linear -delta^2/omega0); at
               alpha = 0, where xi's leading value is 0, absolute: 2 |xi_est| + (0.1 eps + 2 (delta/omega0)^2) delta;
      xi_lo, xi_hi  2 |est| + 0.1 eps + 2 (delta/omega0)^2; where the next order finds no two folds (near the
               cusp), the bound 3 eps + 3 delta/omega0 (measured coefficients 1.0 and 0.7)."""
    e_d, e_n = _small(p)
    lead = _analytic_at(p)
    nx = _harmonic_balance(p)
    floor = 0.1 * e_n + 2.0 * e_d**2
    out = {}
    for name in ("A_max", "xi_peak", "xi_lo", "xi_hi"):
        a = lead[name]
        if isinstance(a, Undefined):
            continue
        if name == "xi_peak" and a == 0 and nx[name] is not None:
            # alpha = 0: no shift at leading order; the linear resonance's -delta^2/omega0 is the next order's
            out[name] = (None, 2.0 * abs(nx[name]) + floor * p.delta)
        elif nx[name] is None or a == 0:
            out[name] = 3.0 * e_n + 3.0 * e_d
        else:
            out[name] = 2.0 * abs(nx[name] / a - 1.0) + floor
    return out


def _range_at(p):
    """At one point (``theory_range`` runs it for each variant): the reduced equations expand in eps = |alpha| A_max^2/omega0^2 and delta/omega0 (the larger shown).
    The folds' theory also cannot tell whether the curve folds where g lies within CUSP_BAND (eps +
    delta/omega0) of g_c: there their parameter is that band over |g/g_c - 1|, 1 or more (outside)."""
    e_d, e_n = _small(p)
    big = ("|alpha| A_max^2/omega0^2", e_n) if e_n >= e_d else ("delta/omega0", e_d)
    out = {name: big for name in ("A_max", "xi_peak", "xi_lo", "xi_hi")}
    near = abs(abs(_g(p)) / G_CRIT - 1.0)
    band = CUSP_BAND * (e_n + e_d)
    if near <= band:
        cusp = (f"{CUSP_BAND:g} (eps + delta/omega0)/|g/g_c - 1|, the theory's error over the force's distance "
                f"from the critical f0 = {p.f0 * math.sqrt(G_CRIT / abs(_g(p))):.6g} m/s^2",
                band / near if near > 0 else math.inf)
        out["xi_lo"] = out["xi_hi"] = cusp
    return out


