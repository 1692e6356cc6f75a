"""The exact flow of a linear autonomous system y' = A y over a long span, on numpy alone.

A linear problem over millions of periods is not stepped through them: its flow
exp(A t) is one matrix, computed by scaling and squaring (a Taylor series of
exp(A t / 2^s) - I for ||A t / 2^s|| <= 1/2, then s squarings).  The squarings
carry D = exp(.) - I rather than exp(.) itself, (I + D)^2 - I = D (D + 2 I), so a
flow that moves the state only a little (a slow mode over a short span) keeps
its relative digits in exp(A t) - I (Higham's expm1 device).  A forced system
with a force that is itself the solution of a linear equation (a constant, a
sinusoid) is made autonomous by appending the force's own state.

The rounding error of the squarings grows like the flow's phase: a rotation
through Theta rad comes out rotated by Theta (1 + O(u)), u the unit round-off,
so ``rounding_bound(A, t)`` is the relative error to claim, ``ROUNDING_FACTOR``
times u (1 + ||A t||) (measured against 40-digit values in tests/test_linear_flow.py).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["expm", "expm_many", "expm_minus_identity", "rounding_bound", "ROUNDING_FACTOR"]

_U = 2.0**-53
ROUNDING_FACTOR = 16.0


def _norm1(a: np.ndarray) -> float:
    return float(np.max(np.sum(np.abs(a), axis=0))) if a.size else 0.0


def _series_and_squarings(x: np.ndarray, squarings: np.ndarray) -> np.ndarray:
    """exp(X) - I for a stack of matrices X (N x n x n) already scaled to ||X||_1 <= 1/2, then squared
    ``squarings[k]`` times each: the one scaling-and-squaring loop of this module."""
    # Taylor series of exp(x) - I: with ||x|| <= 1/2 the terms fall below 2^-60 by the 18th
    term = x.copy()
    d = x.copy()
    for k in range(2, 30):
        term = term @ x / k
        d = d + term
        sizes = np.max(np.sum(np.abs(term), axis=1), axis=1)
        if np.all(sizes <= 1e-18 * np.maximum(np.max(np.sum(np.abs(d), axis=1), axis=1), 1e-300)):
            break
    eye = np.eye(x.shape[1])
    for k in range(1, int(squarings.max(initial=0)) + 1):
        sel = squarings >= k
        ds = d[sel]
        d[sel] = ds @ (ds + 2.0 * eye)  # exp(2y) - I = (exp(y) - I)(exp(y) - I + 2 I)
    return d


def _squarings(norms: np.ndarray) -> np.ndarray:
    """Halvings that bring each 1-norm to 1/2 or below."""
    out = np.zeros(norms.size, dtype=int)
    big = norms > 0.5
    out[big] = np.ceil(np.log2(norms[big] / 0.5)).astype(int)
    return out


def _norms1(a: np.ndarray) -> np.ndarray:
    """The 1-norm of each matrix of a stack (N x n x n)."""
    return np.max(np.sum(np.abs(a), axis=-2), axis=-1) if a.size else np.zeros(a.shape[0])


def expm_minus_identity(a) -> np.ndarray:
    """exp(A) - I for a real or complex square matrix, or for each of a stack of them (N x n x n, each with
    its own squarings), each entry to its own relative accuracy where the squarings allow it (no 1 + small
    - 1)."""
    a = np.asarray(a)
    a = a.astype(complex if np.iscomplexobj(a) else float)
    n = a.shape[-1]
    if a.ndim not in (2, 3) or a.shape[-2:] != (n, n):
        raise ValueError("expm: a square matrix (or a stack of them) is needed")
    stack = a if a.ndim == 3 else a[None, :, :]
    norms = _norms1(stack)
    if not np.all(np.isfinite(norms)):
        raise ValueError("expm: the matrix has non-finite entries")
    s = _squarings(norms)
    d = _series_and_squarings(stack / (2.0 ** s)[:, None, None], s)
    return d if a.ndim == 3 else d[0]


def expm(a) -> np.ndarray:
    """exp(A) by scaling and squaring (see ``expm_minus_identity``; a stack of matrices gives a stack)."""
    a = np.asarray(a)
    return np.eye(a.shape[-1]) + expm_minus_identity(a)


def expm_many(a, ts) -> np.ndarray:
    """exp(A t) for every t of ``ts`` at once (shape (len(ts), n, n)): the same scaling and squaring as
    ``expm``, each t with its own number of squarings, the matrix products stacked (a flow sampled at
    the nodes of a quadrature rule or along a grid costs a few numpy calls, not one Python loop each)."""
    a = np.asarray(a, dtype=float)
    ts = np.asarray(ts, dtype=float).ravel()
    n = a.shape[0]
    if a.shape != (n, n):
        raise ValueError("expm_many: a square matrix is needed")
    if not np.all(np.isfinite(ts)):
        raise ValueError("expm_many: non-finite times")
    squarings = _squarings(_norm1(a) * np.abs(ts))
    x = a[None, :, :] * (ts / 2.0**squarings)[:, None, None]
    return _series_and_squarings(x, squarings) + np.eye(n)


def rounding_bound(a, t=1.0):
    """The relative rounding error of exp(A t) by these squarings: ROUNDING_FACTOR u (1 + ||A t||_1) (a
    number; an array for a stack of matrices or an array of t)."""
    a = np.asarray(a)
    norm = _norm1(a) if a.ndim == 2 else _norms1(a)
    out = ROUNDING_FACTOR * _U * (1.0 + norm * np.abs(t))
    return float(out) if np.ndim(out) == 0 else out
