"""4.2 Principal moments of a rod triangle, a triangular plate and a regular tetrahedron.

Analytic (about the center of mass, total mass M, edge a):
  rod triangle: each rod (mass M/3) has its midpoint at the inradius a/(2 sqrt 3)
  from the center, so I3 = 3 (M/3)(a^2/12 + a^2/12) = M a^2/6, and the planar
  (perpendicular-axis) rule with the threefold symmetry gives I1 = I2 = M a^2/12;
  plate: I3 = M (a^2 + a^2 + a^2)/36 = M a^2/12, I1 = I2 = M a^2/24;
  tetrahedron: the second-moment tensor about the centroid is (M/20) sum_i v_i v_i^T
  over the vertices, isotropic with sum |v_i|^2 = 4 (3/8) a^2, so the covariance is
  M a^2/40 times the unit tensor and I = 2 M a^2/40 = M a^2/20.
The mass spreads outward from rods to plate to solid less and less: the rods put
all the mass on the rim, the plate fills in toward the center.

Numeric: the bodies are built from their vertices, placed in a generic rotated
and shifted frame, and filled with Gauss rules exact for the quadratic
integrands (Gauss-Legendre on each rod, the collapsed Duffy product rule on the
triangle and on the tetrahedron; solvers.mechanics.shapes).  The inertia tensor is taken
about the numerically found center of mass, diagonalized by a symmetric
eigensolver, and the eigenvalues are grouped by a relative (scale-free)
degeneracy test; each group reports its mean.
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.frames import rotation
from mech.solvers.mechanics.inertia import degenerate_groups, inertia_tensor
from mech.solvers.mechanics.shapes import rod_polyline, tetrahedron, triangle

exercise = Exercise(
    "4.2",
    formulas=[
        "rod triangle: I1 = I2 = M a²/12, I3 = M a²/6",
        "triangular plate: I1 = I2 = M a²/24, I3 = M a²/12",
        "regular tetrahedron: I1 = I2 = I3 = M a²/20",
    ],
)


@exercise.analytic
def analytic(p):
    Ma2 = p.M * p.a**2
    return {
        "I_rods_inplane": Ma2 / 12.0,
        "I_rods_normal": Ma2 / 6.0,
        "I_plate_inplane": Ma2 / 24.0,
        "I_plate_normal": Ma2 / 12.0,
        "I_tetra": Ma2 / 20.0,
    }


# A generic orientation and offset, so that no axis of the computation is a symmetry axis.
_FRAME = rotation([0.31, -0.72, 0.55], 1.234)
_OFFSET = np.array([0.37, -0.21, 0.13])

# Relative gap below which neighbouring eigenvalues count as one degenerate value.
_DEGENERATE_REL = 1e-9


def _place(vertices, a):
    v = np.asarray(vertices, dtype=float) * a
    return v @ _FRAME.T + _OFFSET * a


def _grouped(points, masses, expected_sizes):
    """Eigenvalues of the inertia tensor about the center of mass, grouped; their means per group."""
    lam = np.linalg.eigvalsh(inertia_tensor(points, masses))
    groups = degenerate_groups(lam, rel=_DEGENERATE_REL)
    sizes = [len(g) for g in groups]
    if sizes != expected_sizes:
        raise NumericFailure(f"eigenvalues {lam} group as {sizes}, not as the symmetry requires {expected_sizes}")
    return [float(np.mean(lam[g])) for g in groups], lam


@exercise.numeric
def numeric(p, run):
    a, M = p.a, p.M
    tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, np.sqrt(3.0) / 2.0, 0.0]]
    apex = [0.5, np.sqrt(3.0) / 6.0, np.sqrt(2.0 / 3.0)]
    verts = _place(tri, a)
    tet = _place(tri + [apex], a)
    edges = [np.linalg.norm(tet[i] - tet[j]) for i in range(4) for j in range(i + 1, 4)]
    if max(edges) - min(edges) > 1e-12 * a:
        raise NumericFailure("the tetrahedron built is not regular")

    r_pts, r_w = rod_polyline(verts, n=4)
    (rods_pair, rods_normal), lam_r = _grouped(r_pts, M * r_w, [2, 1])
    p_pts, p_w = triangle(*verts, n=4)
    (plate_pair, plate_normal), lam_p = _grouped(p_pts, M * p_w, [2, 1])
    t_pts, t_w = tetrahedron(*tet, n=4)
    (tetra,), lam_t = _grouped(t_pts, M * t_w, [3])

    run.method = "Gauss quadrature (collapsed product rules) + symmetric eigensolver"
    scale = M * a**2
    run.info["splitting_of_degenerate_values_rel"] = max(
        (lam_r[1] - lam_r[0]) / scale, (lam_p[1] - lam_p[0]) / scale, (lam_t[2] - lam_t[0]) / scale
    )
    run.info["nodes"] = int(len(r_w) + len(p_w) + len(t_w))
    for name in ("I_rods_inplane", "I_rods_normal", "I_plate_inplane", "I_plate_normal", "I_tetra"):
        run.claim(name, rel=1e-12)  # exact quadrature: round-off only
    return {
        "I_rods_inplane": rods_pair,
        "I_rods_normal": rods_normal,
        "I_plate_inplane": plate_pair,
        "I_plate_normal": plate_normal,
        "I_tetra": tetra,
    }
