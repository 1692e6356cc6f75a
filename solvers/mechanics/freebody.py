"""Free rigid rotation: following a torque-free body and measuring its rates from the motion.

* ``integrate_free``: Euler's equations with the quaternion attitude
  (``rigid.euler_rhs``) from a given body angular velocity and attitude, with
  per-component absolute tolerances so that small components keep relative
  accuracy.
* ``free_invariants``: the drift of the energy, of |L| and of the lab vector L
  along a sampled trajectory (relative, worst over the samples).
* ``phase_rate``: the slope of the unwrapped phase of a sampled planar vector,
  by least squares, refusing samples too sparse to unwrap.
* ``euler_jacobian`` / ``steady_rotation_pair``: the Jacobian of the torque-free
  Euler equations by central differences (exact for their quadratic right-hand
  side up to round-off) and its non-zero eigenvalue pair at a steady rotation.

No physics of one exercise here; scipy is imported inside the functions.
"""

from __future__ import annotations

import numpy as np

from mech.core.errors import NumericFailure
from mech.solvers.mechanics.frames import rotate_many
from mech.solvers.numerics.ode import integrate

__all__ = [
    "euler_omega_rhs",
    "free_rhs",
    "integrate_free",
    "lab_axes",
    "free_invariants",
    "phase_rate",
    "euler_jacobian",
    "steady_rotation_pair",
]


def euler_omega_rhs(I):
    """Torque-free Euler equations for the body angular velocity alone."""
    I1, I2, I3 = (float(v) for v in I)
    c1, c2, c3 = (I2 - I3) / I1, (I3 - I1) / I2, (I1 - I2) / I3

    def rhs(t, w):
        return np.array([c1 * w[1] * w[2], c2 * w[2] * w[0], c3 * w[0] * w[1]])

    return rhs


def free_rhs(I, restore=1.0):
    """The same right-hand side as ``rigid.euler_rhs(I, None, restore)`` for the state [omega(3), q(4)],
    written with scalars (a free body is integrated for many steps; this is several times faster)."""
    I1, I2, I3 = (float(v) for v in I)
    c1, c2, c3 = (I2 - I3) / I1, (I3 - I1) / I2, (I1 - I2) / I3

    def rhs(t, s):
        w1, w2, w3, q0, q1, q2, q3 = s
        k = restore * (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3 - 1.0)
        return np.array(
            [
                c1 * w2 * w3,
                c2 * w3 * w1,
                c3 * w1 * w2,
                0.5 * (-q1 * w1 - q2 * w2 - q3 * w3) - k * q0,
                0.5 * (q0 * w1 + q2 * w3 - q3 * w2) - k * q1,
                0.5 * (q0 * w2 - q1 * w3 + q3 * w1) - k * q2,
                0.5 * (q0 * w3 + q1 * w2 - q2 * w1) - k * q3,
            ]
        )

    return rhs


def integrate_free(I, omega_body0, q0, t_end, *, rtol, atol, t_eval=None, restore=1.0, integrator=None):
    """Integrate the free body from ``omega_body0`` and attitude ``q0`` (body -> lab) to ``t_end``.

    ``atol``: a 7-vector (3 for omega, 4 for q) or a scalar.
    """
    rhs = free_rhs(I, restore=restore)
    y0 = np.concatenate([np.asarray(omega_body0, dtype=float), np.asarray(q0, dtype=float)])
    return integrate(rhs, (0.0, t_end), y0, rtol=rtol, atol=atol, t_eval=t_eval, integrator=integrator)


def lab_axes(traj, body_vector) -> np.ndarray:
    """Lab components (3 x N) of a body-fixed vector along the trajectory."""
    return rotate_many(traj.y[3:7], body_vector)


def free_invariants(I, traj) -> dict:
    """Worst relative drift of the energy, |L| and the lab vector L over the samples."""
    I = np.asarray(I, dtype=float)
    w = traj.y[0:3]
    energy = 0.5 * np.einsum("i,in->n", I, w * w)
    L_body = I[:, None] * w
    L_lab = rotate_many(traj.y[3:7], L_body)
    Lmag = np.linalg.norm(L_body, axis=0)
    q_norm = np.linalg.norm(traj.y[3:7], axis=0)
    return {
        "energy": float(np.max(np.abs(energy / energy[0] - 1.0))),
        "|L|": float(np.max(np.abs(Lmag / Lmag[0] - 1.0))),
        "L (lab vector)": float(np.max(np.linalg.norm(L_lab - L_lab[:, :1], axis=0)) / Lmag[0]),
        "|q| - 1": float(np.max(np.abs(q_norm - 1.0))),
    }


def phase_rate(t, x, y, *, max_jump: float = 1.0) -> tuple[float, float]:
    """(slope, total phase) of the unwrapped phase of (x, y) sampled at t, by a least-squares line.

    A jump over ``max_jump`` rad between samples means the sampling is too sparse
    to unwrap unambiguously: a NumericFailure.
    """
    t = np.asarray(t, dtype=float)
    ph = np.arctan2(y, x)
    jumps = np.abs(np.angle(np.exp(1j * np.diff(ph))))
    if jumps.size and jumps.max() > max_jump:
        raise NumericFailure(f"the phase moves {jumps.max():.3g} rad between samples: too sparse to unwrap")
    ph = np.unwrap(ph)
    tc = t - t.mean()
    slope = float(np.dot(tc, ph - ph.mean()) / np.dot(tc, tc))
    return slope, float(ph[-1] - ph[0])


def euler_jacobian(I, omega, h=None) -> np.ndarray:
    """d(omega')/d(omega) of the torque-free Euler equations at ``omega``, by central differences.

    The right-hand side is quadratic, so the central difference has no truncation
    error; a step of the size of |omega| keeps the round-off at a few ulps.
    """
    rhs = euler_omega_rhs(I)
    omega = np.asarray(omega, dtype=float)
    h = float(np.linalg.norm(omega)) if h is None else h
    J = np.zeros((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        J[:, j] = (rhs(0.0, omega + e) - rhs(0.0, omega - e)) / (2.0 * h)
    return J


def steady_rotation_pair(I, axis_index: int, omega0: float) -> tuple[complex, complex, np.ndarray]:
    """The two eigenvalues of the Jacobian at steady rotation about a principal axis besides the zero one.

    Returns (lam_a, lam_b, all eigenvalues); the zero eigenvalue (a change of the rate
    along the axis) is the one of smallest modulus.
    """
    w = np.zeros(3)
    w[axis_index] = omega0
    J = euler_jacobian(I, w)
    ev = np.linalg.eigvals(J)
    order = np.argsort(np.abs(ev))
    return complex(ev[order[1]]), complex(ev[order[2]]), ev
