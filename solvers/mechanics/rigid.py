"""Rigid-body rotation: Euler's equations in the body frame and the orientation as a unit quaternion.

The state of a free or torqued body is ``[omega_1, omega_2, omega_3, q0, q1, q2, q3]``:
the angular velocity in principal-axis (body) components and the quaternion
taking body components to lab components.  The quaternion's derivative is
``q' = q * (0, omega) / 2`` plus a term ``-k (|q|^2 - 1) q`` that pulls it back to
the rotation group without changing the true solution (|q| = 1 is invariant).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from mech.solvers.mechanics.frames import quat_mul, quat_to_matrix

__all__ = [
    "euler_rhs",
    "body_state",
    "lab_vector",
    "angular_momentum_lab",
    "kinetic_energy",
]


def euler_rhs(
    I: np.ndarray,
    torque_body: Callable[[float, np.ndarray, np.ndarray], np.ndarray] | None = None,
    restore: float = 1.0,
) -> Callable[[float, np.ndarray], np.ndarray]:
    """Right-hand side for the state [omega(3), q(4)] of a body with principal moments ``I``.

    ``torque_body(t, omega, q)`` gives the torque in body components (None: a free body).
    """
    I1, I2, I3 = (float(v) for v in I)

    def rhs(t, s):
        w1, w2, w3 = s[0], s[1], s[2]
        q = s[3:7]
        tau = torque_body(t, s[0:3], q) if torque_body is not None else (0.0, 0.0, 0.0)
        dw = np.array(
            [
                ((I2 - I3) * w2 * w3 + tau[0]) / I1,
                ((I3 - I1) * w3 * w1 + tau[1]) / I2,
                ((I1 - I2) * w1 * w2 + tau[2]) / I3,
            ]
        )
        dq = 0.5 * quat_mul(q, np.array([0.0, w1, w2, w3])) - restore * (q @ q - 1.0) * q
        return np.concatenate([dw, dq])

    return rhs


def body_state(omega_body, q=(1.0, 0.0, 0.0, 0.0)) -> np.ndarray:
    return np.concatenate([np.asarray(omega_body, dtype=float), np.asarray(q, dtype=float)])


def lab_vector(q: np.ndarray, v_body: np.ndarray) -> np.ndarray:
    return quat_to_matrix(q) @ np.asarray(v_body, dtype=float)


def angular_momentum_lab(I: np.ndarray, state: np.ndarray) -> np.ndarray:
    return lab_vector(state[3:7], np.asarray(I, dtype=float) * state[0:3])


def kinetic_energy(I: np.ndarray, omega_body: np.ndarray) -> float:
    return 0.5 * float(np.dot(np.asarray(I, dtype=float), np.asarray(omega_body) ** 2))
