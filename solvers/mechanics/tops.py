"""A symmetric top about a fixed point, in nonsingular vector form, and rate measurement.

State ``[n3(3), L(3)]``: the unit symmetry axis and the angular momentum about the
fixed point, both lab components.  For a symmetric body (I_A about every axis
normal to n3 through the point, I3 about n3) the angular velocity is
``omega = L / I_A + L3 (1/I3 - 1/I_A) n3`` with ``L3 = L . n3``, so
``dn3/dt = omega x n3 = L x n3 / I_A`` and ``dL/dt = torque(t, n3)``: no Euler
angles, no singularity at the vertical.  ``L3`` is conserved whenever the
torque is normal to n3 (forces applied on the axis).

The rate of a steady rotation about z is measured from a sampled run by a least
squares fit of the unwrapped azimuth.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

__all__ = ["axis_rhs", "top_energy", "azimuth", "polar_angle", "fit_rate"]


def axis_rhs(I_A: float, torque: Callable[[float, np.ndarray], np.ndarray], L_scale: float = 1.0):
    """rhs for ``[n3, L / L_scale]``: dn3/dt = L x n3 / I_A, d(L/L_scale)/dt = torque(t, n3) / L_scale."""
    k = L_scale / I_A

    def rhs(t, y):
        n = y[0:3]
        L = y[3:6]
        dn = k * np.array([L[1] * n[2] - L[2] * n[1], L[2] * n[0] - L[0] * n[2], L[0] * n[1] - L[1] * n[0]])
        return np.concatenate([dn, np.asarray(torque(t, n), dtype=float) / L_scale])

    return rhs


def top_energy(I_A: float, I3: float, n: np.ndarray, L: np.ndarray) -> np.ndarray:
    """Kinetic energy L_perp^2/(2 I_A) + L3^2/(2 I3) for arrays of states (columns)."""
    L3 = np.sum(n * L, axis=0)
    L2 = np.sum(L * L, axis=0)
    return 0.5 * (L2 - L3**2) / I_A + 0.5 * L3**2 / I3


def azimuth(n: np.ndarray) -> np.ndarray:
    """Unwrapped azimuth of the horizontal projection of the vectors (columns) n."""
    return np.unwrap(np.arctan2(n[1], n[0]))


def polar_angle(n: np.ndarray) -> np.ndarray:
    """Angle from +z, well conditioned near both poles."""
    return np.arctan2(np.hypot(n[0], n[1]), n[2])


def fit_rate(t: np.ndarray, angle: np.ndarray) -> tuple[float, float]:
    """Least-squares slope of angle(t) and the rms residual of the straight line."""
    A = np.stack([t, np.ones_like(t)], axis=1)
    coef, *_ = np.linalg.lstsq(A, angle, rcond=None)
    resid = angle - A @ coef
    return float(coef[0]), float(np.sqrt(np.mean(resid**2)))
