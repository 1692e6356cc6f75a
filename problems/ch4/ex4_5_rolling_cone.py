"""4.5 Kinetic energy of a solid cone rolling on a table about its resting apex.

Analytic: with Omega = 2 pi f and the half-angle alpha (tan alpha = R/H), the line
of contact is the instantaneous axis; the symmetry axis, at alpha above the table,
turns about the vertical at Omega, so omega = Omega z + s n3 must lie along the
contact line: s = -Omega/sin alpha and |omega| = Omega cot alpha = Omega H/R.
The moment about the contact line (through the apex, at alpha to the axis) is
I3 cos^2 alpha + I1' sin^2 alpha with I3 = (3/10) M R^2 and the moment about a
transverse axis through the apex I1' = (3/5) M (H^2 + R^2/4); so
  T = (1/2) I omega^2 = (3/40) M Omega^2 H^2 (6 H^2 + R^2)/(H^2 + R^2)
    = (3/40) M Omega^2 H^2 (1 + 5 cos^2 alpha),    M = pi rho R^2 H/3.

Numeric: the cone is filled with a product Gauss rule (Gauss-Legendre along the
axis and the radius, the trapezoid rule in azimuth; exact for the quadratic
integrand), whose raw weights also give the volume.  It is laid on the table
(apex at the origin, one generator along +x, the body above z = 0, checked).
The angular velocity is Omega z + s n3 with s from zero velocity of the rim
point touching the table (least squares); T = sum rho dV |omega x r|^2/2.
No closed-form moment of inertia enters.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.shapes import cone

exercise = Exercise(
    "4.5",
    formulas=[
        "M = π ρ R² H / 3,   Ω = 2π f",
        "ω = Ω H / R   (along the line of contact)",
        "T = (3/40) M Ω² H² (6H² + R²)/(H² + R²) = (3/40) M Ω² H² (1 + 5 cos²α)",
    ],
)


@exercise.analytic
def analytic(p):
    Om = 2.0 * math.pi * p.f
    M = math.pi * p.rho * p.R**2 * p.H / 3.0
    h, r = p.H / max(p.H, p.R), p.R / max(p.H, p.R)  # ratios: no overflow in the fourth powers
    T = 0.075 * M * Om**2 * p.H**2 * (6.0 * h**2 + r**2) / (h**2 + r**2)
    return {"T": T, "omega": Om * p.H / p.R, "M": M}


@exercise.numeric
def numeric(p, run):
    H, R = p.H, p.R
    pts_b, w, volume = cone(H, R, n_axis=5, n_r=4, n_phi=8, volume=True)
    M = p.rho * volume
    L = math.hypot(H, R)
    # lab axes in body components: x along the generator at body azimuth pi, z the
    # table's upward normal (minus the cone's outward normal along that generator)
    ex = np.array([-R, 0.0, H]) / L
    ez = np.array([H, 0.0, R]) / L
    ey = np.cross(ez, ex)
    to_lab = np.vstack([ex, ey, ez])
    pts = pts_b @ to_lab.T
    phi = np.linspace(0.0, 2 * np.pi, 721)
    rim = np.column_stack([R * np.cos(phi), R * np.sin(phi), np.full_like(phi, H)]) @ to_lab.T
    if rim[:, 2].min() < -1e-12 * L or pts[:, 2].min() < 0:
        raise NumericFailure("the cone placed on the table dips below it")
    touch = np.array([-R, 0.0, H]) @ to_lab.T  # rim point on the table

    Om = 2.0 * math.pi * p.f
    zhat = np.array([0.0, 0.0, 1.0])
    n3 = to_lab[:, 2]  # the symmetry axis in the lab
    # zero velocity of the touching rim point: (Om z + s n3) x touch = 0
    A = np.cross(n3, touch)[:, None]
    b = -Om * np.cross(zhat, touch)
    (s,), *_ = np.linalg.lstsq(A, b, rcond=None)
    omega = Om * zhat + s * n3
    if np.linalg.norm(np.cross(omega, touch)) > 1e-12 * abs(s) * L:
        raise NumericFailure("no spin rate brings the touching rim point to rest")
    v = np.cross(omega, pts)
    T = 0.5 * M * float(w @ np.einsum("ni,ni->n", v, v))

    run.method = "product Gauss rule on the cone + least-squares rolling constraint"
    run.cost(len(w))
    mid = 0.5 * touch  # a point of the contact line halfway: must be at rest too
    run.info["contact_line_speed_rel"] = float(np.linalg.norm(np.cross(omega, mid)) / (abs(Om) * L))
    run.info["spin_rate"] = float(s)
    # round-off only (the quadrature is exact); the flat cone loses digits in the
    # near-cancelling sum Omega z + s n3: an ulp of Omega in the vertical component
    # against |omega| = Omega H/R, i.e. ~ 2 eps R/H relative
    lost = 2e-15 * R / H
    run.claim("T", rel=1e-12 + lost)
    run.claim("omega", rel=1e-12 + lost)
    run.claim("M", rel=1e-12)
    return {"T": T, "omega": float(np.linalg.norm(omega)), "M": M}
