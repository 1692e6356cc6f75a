"""4.4 Rotation about a fixed axis away from the center of mass: L_z = I omega, T = I omega^2/2.

Analytic: a rod point at arc length s from the center (s in [-l/2, l/2]) sits at
the distance rho = d + s sin(beta) from the axis and at the height s cos(beta)
above the axis point nearest the center.  With v = omega z x r,
  L_z = omega sum m rho^2 = I omega  about any point of the axis (the height drops out),
  T = (omega^2/2) sum m rho^2 = I omega^2/2,
  I = M (d^2 + l^2 sin^2(beta)/12)  (the center's term plus the rod's own, the
      parallel-axis theorem falling out of the sum);
the normal part of L is -omega sum m rho z, of magnitude
  L_perp = M l^2 |omega| sin(beta) cos(beta)/12,
nonzero unless the rod is parallel or perpendicular to the axis: L is not along omega.

Numeric: Gauss-Legendre nodes along the rod, placed in a generic azimuthal plane;
each node gets v = omega z x r, and sum m r x v (about the axis point nearest
the center and, as a check, about another axis point), sum m v^2/2 and
sum m rho^2 are summed directly.  Neither L = I omega nor the parallel-axis
theorem is used.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise
from mech.solvers.mechanics.shapes import rod

exercise = Exercise(
    "4.4",
    formulas=[
        "I = M (d² + l² sin²β / 12)",
        "L_z = I ω,  T = I ω² / 2   (about any point of the axis)",
        "L_perp = M l² |ω| sin β cos β / 12",
    ],
)


@exercise.analytic
def analytic(p):
    sb = math.sin(p.beta)
    cb = math.sin(math.pi / 2 - p.beta)  # cos(beta), exactly 0 at beta = pi/2 (the float)
    I = p.M * (p.d**2 + p.l**2 * sb**2 / 12.0)
    return {
        "I_axis": I,
        "Lz": I * p.omega,
        "T": 0.5 * I * p.omega**2,
        "L_perp": p.M * p.l**2 * abs(p.omega) * sb * cb / 12.0,
    }


# the rod's azimuth about the axis and the height of its center: any values do
_PHI0 = 0.7
_ZC = 0.37


@exercise.numeric
def numeric(p, run):
    radial = np.array([math.cos(_PHI0), math.sin(_PHI0), 0.0])
    zhat = np.array([0.0, 0.0, 1.0])
    center = p.d * radial + _ZC * p.l * zhat
    direction = math.sin(p.beta) * radial + math.cos(p.beta) * zhat
    pts, w = rod(center - 0.5 * p.l * direction, center + 0.5 * p.l * direction, n=4)
    m = p.M * w
    v = p.omega * np.cross(zhat, pts)

    def ang_mom(about):
        return (m[:, None] * np.cross(pts - about, v)).sum(axis=0)

    L = ang_mom(np.array([0.0, 0.0, center[2]]))  # axis point nearest the rod's center
    L_other = ang_mom(np.array([0.0, 0.0, center[2] - 2.9 * p.l]))
    I = float(m @ (pts[:, 0] ** 2 + pts[:, 1] ** 2))
    T = float(0.5 * m @ np.einsum("ni,ni->n", v, v))

    run.method = "Gauss-Legendre nodes along the rod, direct sums"
    run.info["Lz_about_another_axis_point"] = float(L_other[2])
    scale = p.M * (p.d**2 + p.l**2 + (_ZC * p.l) ** 2)  # size of the sums' terms
    run.claim("I_axis", rel=1e-12, abs=1e-14 * scale)
    run.claim("Lz", rel=1e-12, abs=1e-14 * scale * abs(p.omega))
    run.claim("T", rel=1e-12, abs=1e-14 * scale * p.omega**2)
    run.claim("L_perp", rel=1e-12, abs=1e-14 * scale * abs(p.omega))
    return {"I_axis": I, "Lz": float(L[2]), "T": T, "L_perp": float(math.hypot(L[0], L[1]))}
