"""A circle map's increment as a Fourier series, and its rotation number.

A map theta -> theta + d(theta) (mod 2 pi) sampled at some angles: ``fourier_fit`` fits d with K harmonics by
least squares (with the largest residual, an honest error of the fit); ``rotation_number`` is the mean
increment per iterate, by the weighted Birkhoff average of d along an orbit (weights exp(-1/(s (1 - s))),
which converges faster than any power of the orbit's length for a smooth quasi-periodic orbit).  5.10 uses
them for the beat of an oscillator just outside its locking range.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["fourier_fit", "rotation_number"]


def _basis(theta, K):
    k = np.arange(1, K + 1)
    ang = np.outer(np.atleast_1d(theta), k)
    return np.hstack([np.ones((ang.shape[0], 1)), np.cos(ang), np.sin(ang)])


def fourier_fit(theta, d, K):
    """(coefficients [c0, a_1..a_K, b_1..b_K], the largest residual) of d ~ c0 + sum a_k cos k theta +
    b_k sin k theta, least squares."""
    B = _basis(theta, K)
    coef, *_ = np.linalg.lstsq(B, d, rcond=None)
    resid = float(np.max(np.abs(B @ coef - d)))
    return coef, resid


def rotation_number(coef, K):
    """Weighted Birkhoff average of d along an orbit of theta -> theta + d(theta) (mod 2 pi), d the series
    of ``coef`` (``fourier_fit``'s order)."""
    c0 = float(coef[0])
    # sum_k a_k cos k theta + b_k sin k theta = Re sum_k (a_k - i b_k) e^(i k theta): Horner in e^(i theta),
    # a few complex products per iterate instead of numpy calls on K-vectors (the loop below runs
    # thousands of times)
    c = [complex(float(coef[k]), -float(coef[K + k])) for k in range(1, K + 1)]

    def d(theta):
        z = complex(math.cos(theta), math.sin(theta))
        acc = 0j
        for ck in reversed(c):
            acc = (acc + ck) * z
        return c0 + acc.real

    # the orbit's quasi-period in iterations is about 2 pi/|c0| (c0 ~ the mean of d); many of them are needed
    slip = 2.0 * math.pi / max(abs(c0), 1e-12)
    n = int(min(max(400.0, 25.0 * slip), 200000))
    theta, num, den = 0.0, 0.0, 0.0
    for i in range(n):
        s = (i + 0.5) / n
        wgt = math.exp(-1.0 / (s * (1.0 - s)))
        dd = d(theta)
        num += wgt * dd
        den += wgt
        theta = math.fmod(theta + dd, 2.0 * math.pi)
    return num / den
