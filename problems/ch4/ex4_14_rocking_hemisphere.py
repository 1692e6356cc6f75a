"""4.14 Solid hemisphere rocking on a plane, frictionless and rolling.

Analytic: the center of mass lies d = 3R/8 below the center O of the flat face.
The moment about an axis through O in the flat face is 2MR^2/5, so about the
parallel axis through the center of mass I_c = (2/5 - 9/64) M R^2 = 83 M R^2/320.
The potential is U = M g (R - d cos theta), stiffness M g d.  (i) Frictionless:
the center of mass moves only vertically (second order), T = I_c theta'^2/2,
omega^2 = g d M / I_c = 120 g / (83 R).  (ii) Rolling: rotation about the
contact point at distance R - d = 5R/8 from the center of mass,
I_P = I_c + 25 M R^2/64 = 13 M R^2/20, omega^2 = M g d / I_P = 15 g / (26 R).

Numeric: the volume is a tensor Gauss rule (radius, cosine of the polar angle
measured from the downward axis, azimuth), exact for the polynomial moments
needed; d is its first moment.  T(q, q') with q = (x_O, theta) is the quadrature
sum of w |v|^2/2 over the rigid field v = (x_O', 0) + theta' z x (r - r_O), U the
sum of w g y (heights taken from their equilibrium values, so the differences
stay free of cancellation).  The mass matrix follows by polarization, the
stiffness by Richardson central differences, all in units M = R = g = 1
(scaled back at the end, so the run is the same for every R and g).  Case
(i): the 2x2 problem, the zero (free-sliding) root discarded.  Case (ii): the
rolling constraint x_O' = -R theta' projects both matrices onto one coordinate.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.inertia import gauss_legendre, periodic
from mech.solvers.mechanics.frames import cross_z, rotate2
from mech.solvers.mechanics.rolling import balanced_modes
from mech.solvers.numerics.modes import hessian, mass_matrix

exercise = Exercise(
    "4.14",
    formulas=[
        "d = 3R/8 (center of mass below the flat face's center)",
        "(i) frictionless: ω² = M g d / I_c = 120 g / (83 R), I_c = 83 M R²/320",
        "(ii) rolling: ω² = M g d / (I_c + M (R - d)²) = 15 g / (26 R)",
    ],
)


ranges.declare(exercise, ranges.Scale("(g/R)^(1/2)", {"g": 0.5, "R": -0.5}, "the frequencies"))


@exercise.analytic
def analytic(p):
    rate = math.sqrt(p.g) / math.sqrt(p.R)
    return {
        "omega_frictionless": math.sqrt(120.0 / 83.0) * rate,
        "omega_rolling": math.sqrt(15.0 / 26.0) * rate,
        "d_cm": 3.0 * p.R / 8.0,
    }


def _hemisphere_points(R, n_r=6, n_u=6, n_phi=8):
    """Unit-mass quadrature of the solid hemisphere y <= 0 about O, plane (x, y) coordinates."""
    r, wr = gauss_legendre(n_r, 0.0, R)
    u, wu = gauss_legendre(n_u, 0.0, 1.0)  # u = cos of the angle from the -y axis
    phi, wp = periodic(n_phi, 0.3)
    rr, uu, pp = np.meshgrid(r, u, phi, indexing="ij")
    w = np.einsum("i,j,k->ijk", wr * r**2, wu, wp).ravel()
    s = np.sqrt(1.0 - uu**2)
    pts = np.stack([(rr * s * np.cos(pp)).ravel(), (-rr * uu).ravel()], axis=1)
    return pts, w / np.sum(w)


@exercise.numeric
def numeric(p, run):
    # units M = R = g = 1: the mass cancels, R and g only set the length and time units, and a unit
    # rate of x_O moves the body as fast as a unit rate of theta (in SI the polarization's cross
    # terms drowned in round-off once R was far from 1 m: 4e-4 off at R = 1e-13 m)
    R, g, M = 1.0, 1.0, 1.0
    pts, w = _hemisphere_points(R)
    w = M * w
    cm = w @ pts
    d = -cm[1]

    def T(q, qdot):
        r_rel = rotate2(pts, q[1])  # positions relative to O in the tilted body
        v = np.array([qdot[0], 0.0])[None, :] + cross_z(qdot[1], r_rel)
        return 0.5 * float(np.sum(w * np.sum(v * v, axis=1)))

    def U(q):
        # height of every point above its equilibrium height: O stays at height R
        dy = pts[:, 0] * np.sin(q[1]) - 2.0 * pts[:, 1] * np.sin(q[1] / 2.0) ** 2
        return g * float(np.sum(w * dy))

    q0 = np.zeros(2)
    Mm = mass_matrix(T, q0)
    K = hessian(U, q0, scale=[R, 1.0])
    free = balanced_modes(Mm, K)
    w2 = free.omega2
    if not (w2[-1] > 0 and abs(w2[0]) < 1e-8 * w2[-1]):
        raise NumericFailure(f"expected one zero and one positive root, got {w2}")
    # rolling: x_O = -R theta
    c = np.array([-R, 1.0])
    w2_roll = (c @ K @ c) / (c @ Mm @ c)
    run.info["free_mode_xO_per_theta"] = float(free.shapes[0, 1] / free.shapes[1, 1]) * p.R
    # Hessian: truncation h^4/1440 ~ 1e-15 and round-off ~ 1e-12 at h = 1e-3; quadrature is exact
    run.claim("omega_frictionless", rel=1e-10)
    run.claim("omega_rolling", rel=1e-10)
    run.claim("d_cm", rel=1e-13)
    rate = math.sqrt(p.g) / math.sqrt(p.R)
    return {"omega_frictionless": math.sqrt(w2[-1]) * rate, "omega_rolling": math.sqrt(w2_roll) * rate,
            "d_cm": d * p.R}
