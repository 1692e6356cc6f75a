"""Free rigid rotation: following a torque-free body and measuring its rates from the motion.

* ``follow_free``: Euler's equations with the quaternion attitude
  (``rigid.euler_rhs``) for many bodies at once, sampled, with per-component
  absolute tolerances so that small components keep relative accuracy.
* ``free_invariants``: the drift of the energy, of |L| and of the lab vector L
  along sampled runs (relative, worst over the samples), on arrays of runs.
* ``phase_rate``: the slope of the unwrapped phase of sampled planar vectors,
  by least squares, marking samples too sparse to unwrap.
* ``euler_jacobian`` / ``steady_rotation_pair``: the Jacobian of the torque-free
  Euler equations by central differences (exact for their quadratic right-hand
  side up to round-off) and its non-zero eigenvalue pair at a steady rotation.

No physics of one exercise here; scipy is imported inside the functions.
"""

from __future__ import annotations

import numpy as np

from mech.solvers.mechanics.frames import quat_to_matrix

__all__ = [
    "euler_omega_rhs",
    "free_rhs",
    "follow_free",
    "lab_axes",
    "free_invariants",
    "phase_rate",
    "euler_jacobian",
    "steady_rotation_pair",
]


def euler_omega_rhs(I):
    """Torque-free Euler equations for the body angular velocity alone: of one body (I: 3 numbers, omega: 3)
    or of N bodies at once (I and omega: 3 x N)."""
    I1, I2, I3 = I
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


def follow_free(I, y0, t_pts, *, rtol, atol, integrator=None, restore=1.0):
    """The free bodies started from ``y0`` ([omega_body(3), q(4)] x N, body -> lab) sampled at ``t_pts`` (from
    t_pts[0]): (states K x 7 x N, the integrations).  ``atol``: 7 x N.

    Many bodies: mech's DOP853 steps them together (``batch.integrate_batch``), leg by leg between the
    samples, each body's error held to rtol as its own run would hold it.  One alone, or each with an
    ``integrator`` forced (``mech bench``): one ``ode.integrate`` run a body, sampled at ``t_pts``."""
    from mech.solvers.numerics.ensemble import follow_sampled

    rhs = free_rhs(I, restore=restore)
    return follow_sampled(lambda sel: rhs, t_pts, y0, rtol=rtol, atol=atol, integrator=integrator)


def lab_axes(q, body_vector) -> np.ndarray:
    """Lab components (3 x ...) of a body-fixed vector (3, or 3 x ...) at the attitudes ``q`` (4 x ...)."""
    q = np.asarray(q, dtype=float)
    v = np.asarray(body_vector, dtype=float)
    if v.ndim == 1:
        v = v.reshape((3,) + (1,) * (q.ndim - 1))
    v = np.broadcast_to(v, (3,) + q.shape[1:])
    return np.einsum("ij...,j...->i...", quat_to_matrix(q), v)


def free_invariants(I, Y) -> dict:
    """Worst relative drift of the energy, |L| and the lab vector L over the samples Y (7 x K x ...: the
    states of K samples of each run), and of |q| - 1: {name: array (...)}."""
    I = np.asarray(I, dtype=float).reshape((3,) + (1,) * (Y.ndim - 1))
    w, q = Y[0:3], Y[3:7]
    energy = 0.5 * np.sum(I * w * w, axis=0)
    L_body = I * w
    L_lab = lab_axes(q, L_body)
    Lmag = np.sqrt(np.sum(L_body * L_body, axis=0))
    q_norm = np.sqrt(np.sum(q * q, axis=0))
    dL = L_lab - L_lab[:, :1]
    return {
        "energy": np.max(np.abs(energy / energy[:1] - 1.0), axis=0),
        "|L|": np.max(np.abs(Lmag / Lmag[:1] - 1.0), axis=0),
        "L (lab vector)": np.max(np.sqrt(np.sum(dL * dL, axis=0)), axis=0) / Lmag[0],
        "|q| - 1": np.max(np.abs(q_norm - 1.0), axis=0),
    }


def phase_rate(t, x, y, *, max_jump: float = 1.0):
    """(slope, total phase, too sparse) of the unwrapped phase of (x, y) sampled at t (K samples x ...), by a
    least-squares line: arrays (...).  ``too sparse``: a jump over ``max_jump`` rad between samples, where
    the phase cannot be unwrapped unambiguously (the slope is then not to be trusted)."""
    t = np.asarray(t, dtype=float).reshape((-1,) + (1,) * (np.ndim(x) - 1))
    ph = np.arctan2(y, x)
    jumps = np.abs(np.angle(np.exp(1j * np.diff(ph, axis=0))))
    sparse = np.max(jumps, axis=0, initial=0.0) > max_jump
    ph = np.unwrap(ph, axis=0)
    tc = t - t.mean()
    slope = np.sum(tc * (ph - ph.mean(axis=0)), axis=0) / np.sum(tc * tc)
    return slope, ph[-1] - ph[0], sparse


def euler_jacobian(I, omega, h=None) -> np.ndarray:
    """d(omega')/d(omega) of the torque-free Euler equations at ``omega``, by central differences: 3 x 3, or
    N x 3 x 3 for N bodies (I, omega: 3 x N).

    The right-hand side is quadratic, so the central difference has no truncation
    error; a step of the size of |omega| keeps the round-off at a few ulps.
    """
    rhs = euler_omega_rhs(I)
    omega = np.asarray(omega, dtype=float)
    h = np.sqrt(np.sum(omega * omega, axis=0)) if h is None else h
    J = np.zeros(omega.shape[1:] + (3, 3))
    for j in range(3):
        e = np.zeros_like(omega)
        e[j] = h
        J[..., :, j] = np.moveaxis((rhs(0.0, omega + e) - rhs(0.0, omega - e)) / (2.0 * h), 0, -1)
    return J


def steady_rotation_pair(I, axis_index: int, omega0: float):
    """The two eigenvalues of the Jacobian at steady rotation about a principal axis besides the zero one:
    (lam_a, lam_b, all eigenvalues), each an array over the bodies (I: 3 x N; all eigenvalues N x 3, by
    modulus).  The zero eigenvalue (a change of the rate along the axis) is the one of smallest modulus."""
    I = np.asarray(I, dtype=float)
    w = np.zeros_like(I)
    w[axis_index] = omega0
    ev = np.linalg.eigvals(euler_jacobian(I, w))
    ev = np.take_along_axis(ev, np.argsort(np.abs(ev), axis=-1), axis=-1)
    return ev[..., 1], ev[..., 2], ev
