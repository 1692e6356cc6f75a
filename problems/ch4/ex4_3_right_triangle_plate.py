"""4.3 Principal moments of inertia of a right-triangular plate with legs a (along x) and b (along y).

Analytic: about the centroid (a/3, b/3) the second moments per unit mass are
<x^2> = a^2/18, <y^2> = b^2/18, <xy> = -ab/36 (from (1/12) sum over the vertices
of v v^T, measured from the centroid).  The moment about an in-plane axis at
angle theta is (M/36)[(a^2+b^2) + (b^2-a^2) cos 2theta + ab sin 2theta], whose
extremes are
  I2 = (M/36)[a^2 + b^2 + q],  I1 = (M/36)(a^2 + b^2 - q) = (M/12) a^2 b^2/(a^2 + b^2 + q),
  q = sqrt(a^4 - a^2 b^2 + b^4),  I3 = I1 + I2 = M (a^2 + b^2)/18,
with the I1 axis at theta1 = (1/2) atan2(-ab, a^2 - b^2) (in (-pi/2, 0)); for a = b:
I1 = M a^2/36 along the hypotenuse (theta1 = -45 deg), I2 = M a^2/12, I3 = M a^2/9.
The second form of I1 avoids the cancellation of the first for a sliver.

Numeric: the plate is filled with the collapsed (Duffy) Gauss product rule
(exact for the quadratic integrands), the second moments are assembled about the
numerically found center of mass in the legs' own frame, and its in-plane 2x2
block (built from the second moments, not by subtracting them from |r|^2) is
diagonalized by hand: the larger eigenvalue from the trace and the
discriminant, the smaller as determinant / larger (no difference of O(I2)
terms), the I1 axis from the eigenvector (taken from the better-conditioned row),
turned into the right half-plane before its angle is taken.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise
from mech.solvers.mechanics.shapes import triangle

exercise = Exercise(
    "4.3",
    formulas=[
        "I1,2 = (M/36)[a² + b² ∓ q],  q = (a⁴ - a²b² + b⁴)^(1/2);  I1 = (M/12) a²b² / (a² + b² + q)",
        "I3 = I1 + I2 = M (a² + b²)/18",
        "θ1 = (1/2) atan2(-ab, a² - b²)   (a = b: I1 = Ma²/36 along the hypotenuse, θ1 = -45°)",
    ],
    axes=("theta1",),  # the direction of an axis, which has no sense: an answer is judged modulo pi
)


def _reduce_axis_angle(theta):
    """An axis angle into (-pi/2, pi/2] as floating point sees it (the same axis either way)."""
    while theta > math.pi / 2:
        theta -= math.pi
    while theta <= -math.pi / 2:
        theta += math.pi
    return theta


@exercise.analytic
def analytic(p):
    s = max(p.a, p.b)
    al, be = p.a / s, p.b / s  # the largest is 1: no overflow or underflow in the fourth powers
    q = math.hypot(al**2 - be**2, al * be)  # sqrt(a^4 - a^2 b^2 + b^4), without cancellation
    unit = p.M * s**2
    I2 = unit * (al**2 + be**2 + q) / 36.0
    I1 = unit * al**2 * be**2 / (12.0 * (al**2 + be**2 + q))
    theta1 = _reduce_axis_angle(0.5 * math.atan2(-al * be, (al - be) * (al + be)))
    return {"I1": I1, "I2": I2, "I3": unit * (al**2 + be**2) / 18.0, "theta1": theta1}


@exercise.numeric
def numeric(p, run):
    # lengths in units of the longer leg and mass fractions (no overflow in the products below)
    L = max(p.a, p.b)
    pts2, w = triangle([0.0, 0.0], [p.a / L, 0.0], [0.0, p.b / L], n=4)
    m = w
    d = pts2 - (m @ pts2) / m.sum()  # from the numerically found center of mass
    # Second moments first, moments from them: I_xx = sum m y^2 directly, not as
    # sum m |r|^2 - sum m x^2 (solvers.mechanics.inertia.inertia_tensor), which for a sliver
    # cancels away the small moment (4e-5 relative error at b/a = 1e-6).
    Sxx, Syy, Sxy = m @ (d[:, 0] ** 2), m @ (d[:, 1] ** 2), m @ (d[:, 0] * d[:, 1])
    A, B, C = Syy, Sxx, -Sxy  # in-plane block of the inertia tensor
    I_normal = Sxx + Syy
    big = 0.5 * (A + B + math.hypot(A - B, 2.0 * C))
    small = (A * B - C * C) / big
    # eigenvector of `small`: orthogonal to the better-conditioned row of (I - small)
    r1 = np.array([A - small, C])
    r2 = np.array([C, B - small])
    row = r1 if np.linalg.norm(r1) >= np.linalg.norm(r2) else r2
    v = np.array([row[1], -row[0]])
    if v[0] < 0 or (v[0] == 0 and v[1] < 0):
        v = -v
    theta1 = _reduce_axis_angle(math.atan2(v[1], v[0]))
    resid = np.linalg.norm(np.array([[A, C], [C, B]]) @ v - small * v) / (big * np.linalg.norm(v))
    run.method = "collapsed Gauss rule on the triangle + 2x2 eigenproblem"
    run.info["eigenvector_residual_rel"] = float(resid)
    run.info["centroid"] = [float(x) for x in (w @ pts2)]
    for name in ("I1", "I2", "I3", "theta1"):
        run.claim(name, rel=1e-12)  # exact quadrature: round-off only
    unit = p.M * L**2
    return {"I1": unit * small, "I2": unit * big, "I3": unit * I_normal, "theta1": theta1}
