"""Linear response of a linear, time-invariant system, computed two independent ways.

* ``inverse_fourier(chi, t, poles)``: the Green's function as the inverse
  transform G(t) = (1/2 pi) int chi(w) exp(-i w t) dw of a response function
  with chi(-w) = conj(chi(w)), folded onto w >= 0:
  G(t) = (1/pi) int_0^inf [Re chi cos(w t) + Im chi sin(w t)] dw.
  The window [0, W] is cut at the poles' real parts and at their widths
  (|Im| multiples) and integrated piece by piece with QUADPACK's
  Fourier-weighted rule (QAWO: no sampling of the oscillation), the tail
  [W, inf) with QAWF.
* ``impulse_spectrum(A, b, c, w)``: int_0^inf c.y(t) exp(i w t) dt for
  y' = A y, y(0) = b (the transform of the impulse response).  One segment
  [0, D] of the fundamental matrix Phi is integrated together with the
  accumulators w_j = int_0^D c.Phi(s) e_j exp(i w s) ds; the rest of the
  infinite run follows exactly from the semigroup property
  Phi(t + D) = Phi(D) Phi(t): the integral is the geometric series
  sum_k exp(i w k D) w.Phi(D)^k b = w.(1 - exp(i w D) Phi(D))^(-1) b.
  No truncation of the decaying tail, no thousands of ringing periods.
  Liouville's formula det Phi(D) = exp(D tr A) is returned as the monitor.
Both work best in scaled variables (rates of order one).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mech.problems.spec import NumericFailure
from mech.solvers.ode import integrate

__all__ = ["inverse_fourier", "impulse_spectrum", "Spectrum", "FourierIntegral"]


@dataclass
class FourierIntegral:
    value: float
    abserr: float  # QUADPACK's summed error estimates
    pieces: int
    warnings: int = 0  # QUADPACK's round-off / subdivision warnings (its estimates then bound the error)


def _breakpoints(poles, window):
    pts = {0.0, window}
    for z in poles:
        c, w = abs(z.real), abs(z.imag)
        pts.add(c)
        # offsets growing geometrically from the peak's width to the window: a narrow resonance's
        # Lorentzian tails are resolved piece by piece
        k = 0.5 * w
        while k < window and k > 0:
            for x in (c - k, c + k):
                pts.add(x)
            k *= 4.0
    return sorted(x for x in pts if 0.0 <= x <= window)


def inverse_fourier(chi, t: float, poles, *, epsrel: float = 1e-12, window_factor: float = 40.0) -> FourierIntegral:
    """G(t) = (1/pi) int_0^inf [Re chi cos(w t) + Im chi sin(w t)] dw; ``poles``: chi's poles (complex)."""
    from scipy.integrate import quad

    if t == 0:
        raise ValueError("inverse_fourier: t = 0 is where G jumps; ask for t != 0")
    poles = [complex(z) for z in poles]
    window = window_factor * max(1.0, max(abs(z) for z in poles))
    pts = _breakpoints(poles, window)
    at = abs(t)
    sign = 1.0 if t > 0 else -1.0
    re = lambda w: chi(w).real  # noqa: E731
    im = lambda w: chi(w).imag  # noqa: E731
    import warnings

    total, err, pieces, nwarn = 0.0, 0.0, 0, 0
    peak = max(abs(chi(x)) for x in pts)
    epsabs = 1e-3 * epsrel * peak / max(at, 1.0 / window)
    for a, b in zip(pts[:-1], pts[1:]):
        if b <= a:
            continue
        for f, wt, s in ((re, "cos", 1.0), (im, "sin", sign)):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                v, e = quad(f, a, b, weight=wt, wvar=at, epsabs=epsabs, epsrel=epsrel, limit=400)
            nwarn += len(caught)
            total += s * v
            err += e
            pieces += 1
    for f, wt, s in ((re, "cos", 1.0), (im, "sin", sign)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            v, e = quad(f, window, np.inf, weight=wt, wvar=at, epsabs=epsabs, limlst=200)
        nwarn += len(caught)
        total += s * v
        err += e
        pieces += 1
    return FourierIntegral(total / math.pi, err / math.pi, pieces, nwarn)


@dataclass
class Spectrum:
    value: complex
    segment: float
    liouville_drift: float
    traj: object


def impulse_spectrum(A, b, c, omega: float, *, rtol: float, segment: float, method: str = "DOP853") -> Spectrum:
    """int_0^inf c.y(t) exp(i omega t) dt for y' = A y, y(0) = b; all eigenvalues of A must decay."""
    A = np.asarray(A, dtype=float)
    b = np.asarray(b, dtype=float)
    c = np.asarray(c, dtype=float)
    n = A.shape[0]
    if np.max(np.linalg.eigvals(A).real) >= 0:
        raise NumericFailure("impulse_spectrum: the system does not decay; its transform does not exist")

    def rhs(s, y):
        Phi = y[: n * n].reshape(n, n)
        out = c @ Phi  # the coordinate's response to each basis initial state
        ph = complex(math.cos(omega * s), math.sin(omega * s))
        acc = out * ph
        return np.concatenate([(A @ Phi).ravel(), acc.real, acc.imag])

    def jac(s, y):
        J = np.zeros((n * n + 2 * n, n * n + 2 * n))
        J[: n * n, : n * n] = np.kron(A, np.eye(n))
        cs, sn = math.cos(omega * s), math.sin(omega * s)
        for j in range(n):
            for i in range(n):
                J[n * n + j, i * n + j] = c[i] * cs
                J[n * n + n + j, i * n + j] = c[i] * sn
        return J

    y0 = np.concatenate([np.eye(n).ravel(), np.zeros(2 * n)])
    atol = rtol * 1e-3
    traj = integrate(rhs, (0.0, segment), y0, rtol=rtol, atol=atol, method=method, jac=jac)
    yend = traj.y_end
    Phi = yend[: n * n].reshape(n, n)
    w = yend[n * n : n * n + n] + 1j * yend[n * n + n :]
    lam = complex(math.cos(omega * segment), math.sin(omega * segment))
    M = np.eye(n) - lam * Phi
    value = complex(w @ np.linalg.solve(M, b))
    expected_det = math.exp(segment * np.trace(A))
    # relative to the size of the products in the determinant (it can be far smaller than they are)
    drift = (np.linalg.det(Phi) - expected_det) / max(float(np.prod(np.max(np.abs(Phi), axis=1))), 1e-300)
    return Spectrum(value, segment, float(drift), traj)
