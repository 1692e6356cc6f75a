"""Periodic orbits of driven Duffing oscillators by shooting, many parameter sets at once.

The equation is that of ``harmonic_balance`` in its scaled form (tau = omega t, x = q/Q, the detuning
omega = omega0 + delta w, d = delta/omega0, gamma = alpha Q^2/(omega0 delta), s = 1 + d w):

    x'' = (2 d cos tau - 2 d s x' - x - d gamma x^3)/s^2,

so every problem's drive period is tau in [0, 2 pi] and all are integrated together by the batched DOP853
(``integrate_batch``; each column's span [tau0, tau0 + L] is mapped onto sigma in [0, 1]).  The
state y = (x, x') at tau = 0 is a periodic orbit where the one-period map closes, Phi(y, w) = y.  With it
are integrated the variational equations: the monodromy matrix M = dPhi/dy and y_w = dPhi/dw, and for the
folds the second-order ones, dM/dx0, dM/dv0, dM/dw.

``shoot_folds``: Newton's method on the augmented system {Phi(y, w) - y = 0, det(M - I) = 0} in (x0, v0, w).
``shoot_peak``: the orbit where the swing A (half the peak-to-peak of x: its extrema at the stops tau_c and
tau_c + pi, each corrected to the extremum by x - x'^2/(2 x'')) is stationary along the branch, dA/dw = 0;
dA/dw from the orbit's tangent (I - M) dy = y_w dw, Newton in w with d^2A/dw^2 from a second orbit at
w + h, each orbit closed by Newton's method on Phi(y, w) = y at the same time.  Both start from a
predictor (harmonic balance) and stop when Newton's step is below ``tol``; a problem that does not is
marked failed.  ``noise``: the relative error an integration error eps leaves in the orbit, eps over the
damping per period 4 pi d (the map's I - M is that small in some direction at resonance).  Liouville's
theorem is reported as a check: det M = exp(-4 pi d/s).

No physics of one exercise lives here; numpy only.
"""

from __future__ import annotations

import math

import numpy as np

from mech.solvers.numerics.batch import integrate_batch

__all__ = ["series_start", "shoot_folds", "shoot_peak", "Shots", "noise"]

TWO_PI = 2.0 * math.pi
MAX_ITER = 8


class Shots:
    """Counts the batched integrations and their steps; keeps the worst Liouville defect per problem."""

    def __init__(self, n):
        self.integrations = 0
        self.steps = 0
        self.liouville = np.zeros(n)

    def note(self, idx, M, d, s):
        det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
        np.maximum.at(self.liouville, idx, np.abs(det / np.exp(-2.0 * TWO_PI * d / s) - 1.0))


def noise(eps, d):
    """The relative error in a shot orbit from the integration's eps (a bound: 20 times the error measured at
    Q = 5000, eps 1e-12)."""
    return eps / (2.0 * TWO_PI * d)


def series_start(c, phi):
    """From odd-harmonic coefficients c (rows: a_1, b_1, a_3, b_3, ...): (x(0), x'(0), the crest's tau near phi)."""
    m = c.shape[1] // 2
    k = 2.0 * np.arange(m) + 1.0
    z = c[:, 0::2] - 1j * c[:, 1::2]
    tau = np.array(phi, dtype=float)
    for _ in range(4):
        e = z * np.exp(1j * np.outer(tau, k))
        tau = tau - (e.imag @ k) / (e.real @ (k * k))
    return c[:, 0::2].sum(axis=1), c[:, 1::2] @ k, tau


def _flow(d, g, w, Y0, tau0, span, eps, shots, second):
    """Integrate the state (positions rows, then their velocities) over [tau0, tau0 + span] of each column, to
    the absolute tolerance eps (one a column: the state, M and its derivatives are of order 1)."""
    s = 1.0 + d * w
    c1, c3, b = 1.0 / (s * s), 3.0 * d * g / (s * s), -2.0 * d / s
    fc, fx3, fw1, ax = 2.0 * d * c1, d * g * c1, 2.0 * d * d * c1, 2.0 * c3
    half = Y0.shape[0] // 2

    def rhs(sigma, Y):
        out = np.empty_like(Y)  # fresh: the integrator keeps earlier derivatives
        P, V = Y[:half], Y[half:]
        x, v = P[0], V[0]
        xx = x * x
        a = -(c1 + c3 * xx)
        dV = out[half:]
        np.multiply(a, P, out=dV)
        dV += b * V
        f2 = fc * np.cos(tau0 + span * sigma) + b * v - (c1 + fx3 * xx) * x
        dV[0] = f2
        dV[3] += b * f2 - fw1 * v  # y_w: + dF/dw
        if second:  # (dJ/dp) M, J's second row moved by p = x0, v0, w: (a_p, b_p) times M's columns
            axx = -ax * x
            M1 = P[1:3]
            dV[4:6] += (axx * P[1]) * M1
            dV[6:8] += (axx * P[2]) * M1
            dV[8:10] += (axx * P[3] + b * a) * M1 + fw1 * V[1:3]  # a_w = -2 d a/s = b a, b_w = 2 d^2/s^2
        out[:half] = V
        out *= span
        return out
    res = integrate_batch(rhs, (0.0, 1.0), Y0, rtol=0.0, atol=np.broadcast_to(eps, Y0.shape))
    shots.integrations += 1
    shots.steps += res.steps
    return res.y_end


def _start(y0, second):
    """The state at tau = 0: (x, M11, M12, y_w[, dM/dx0 row 1, dM/dv0 row 1, dM/dw row 1]) then velocities."""
    n = y0.shape[1]
    rows = 10 if second else 4
    Y = np.zeros((2 * rows, n))
    Y[0], Y[rows] = y0[0], y0[1]
    Y[1] = 1.0  # M11
    Y[rows + 2] = 1.0  # M22
    return Y


def _monodromy(Y):
    half = Y.shape[0] // 2
    M = np.array([[Y[1], Y[2]], [Y[half + 1], Y[half + 2]]])  # (2, 2, n)
    return M, np.array([Y[3], Y[half + 3]]), np.array([Y[0], Y[half]])


def _det_minus_one(M):
    return (M[0, 0] - 1.0) * (M[1, 1] - 1.0) - M[0, 1] * M[1, 0]


def _solve2(A, r):
    """Solve the 2x2 systems A (2, 2, n) x = r (2, n)."""
    det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    return np.array([A[1, 1] * r[0] - A[0, 1] * r[1], A[0, 0] * r[1] - A[1, 0] * r[0]]) / det


def shoot_folds(d, gamma, w, y0, *, eps, tol, shots, idx):
    """Newton on {Phi(y, w) = y, det(M - I) = 0} from (y0 (2, n), w), integrated to eps, until its step is below
    tol (arrays of n); returns (w, y0, ok)."""
    w, y = np.array(w, dtype=float), np.array(y0, dtype=float)
    ok = np.zeros(w.size, dtype=bool)
    live = np.arange(w.size)
    for _ in range(MAX_ITER):
        if live.size == 0:
            break
        dl, gl, wl = d[live], gamma[live], w[live]
        Y = _flow(dl, gl, wl, _start(y[:, live], True), 0.0, TWO_PI, eps[live], shots, True)
        M, yw, end = _monodromy(Y)
        shots.note(idx[live], M, dl, 1.0 + dl * wl)
        # dM/dp (p = x0, v0, w): rows 4..9 hold row 1 of each, rows 14..19 row 2
        dM = [np.array([[Y[4 + 2 * j], Y[5 + 2 * j]], [Y[14 + 2 * j], Y[15 + 2 * j]]]) for j in range(3)]
        dD = [dm[0, 0] * (M[1, 1] - 1.0) + (M[0, 0] - 1.0) * dm[1, 1] - dm[0, 1] * M[1, 0] - M[0, 1] * dm[1, 0]
              for dm in dM]
        J = np.zeros((live.size, 3, 3))
        J[:, :2, :2] = np.moveaxis(M - np.eye(2)[:, :, None], 2, 0)
        J[:, :2, 2] = yw.T
        J[:, 2, :] = np.array(dD).T
        F = np.concatenate([end - y[:, live], _det_minus_one(M)[None]]).T
        with np.errstate(all="ignore"):
            step = -np.linalg.solve(J, F[:, :, None])[:, :, 0]
        y[:, live] += step[:, :2].T
        w[live] += step[:, 2]
        size = np.maximum(np.abs(step[:, :2]).max(axis=1) / np.maximum(1.0, np.abs(y[:, live]).max(axis=0)),
                          np.abs(step[:, 2]) / np.maximum(1.0, np.abs(w[live])))
        done = size <= tol[live]
        ok[live[done]] = True
        live = live[~done & np.isfinite(size)]
    return w, y, ok


def _swing(d, g, w, y, tc, eps, shots):
    """The orbits from y at w through the stops tc and tc + pi to 2 pi: (A, dA/dw along the branch, the stops
    moved to the extrema, the closing step (I - M)^-1 (Phi - y), M).  The three ends are three columns of one
    batched integration from tau = 0 (spans tc, tc + pi and 2 pi)."""
    t1 = np.mod(tc, math.pi)
    k = t1.size
    three = np.concatenate([np.arange(k)] * 3)
    spans = np.concatenate([t1, t1 + math.pi, np.full(k, TWO_PI)])
    Y = _flow(d[three], g[three], w[three], _start(y[:, three], False), 0.0, spans, eps[three], shots, False)
    stops = [Y[:, :k], Y[:, k:2 * k]]
    M, yw, end = _monodromy(Y[:, 2 * k:])
    I_M = np.eye(2)[:, :, None] - M
    tangent = _solve2(I_M, yw)
    close = _solve2(I_M, end - y)
    s = 1.0 + d * w
    ext, dext, moved = [], [], []
    for Ys, tau in zip(stops[:2], (t1, t1 + math.pi)):
        Ms, yws, (x, v) = _monodromy(Ys)
        acc = (2.0 * d * np.cos(tau) - 2.0 * d * s * v - x - d * g * x ** 3) / (s * s)
        ext.append(x - v * v / (2.0 * acc))
        dext.append(Ms[0, 0] * tangent[0] + Ms[0, 1] * tangent[1] + yws[0])  # x' = 0 there: tau's shift is second order
        moved.append(tau - v / acc)
    sign = np.sign(ext[0] - ext[1])
    return 0.5 * sign * (ext[0] - ext[1]), 0.5 * sign * (dext[0] - dext[1]), moved[0], close, tangent, M


def shoot_peak(d, gamma, w, y0, tc, *, eps, tol, shots, idx, h=1e-4, fold=None):
    """Newton in w on dA/dw = 0 along the branch, each orbit closed by Newton on Phi(y, w) = y; two orbits a
    problem (at w and w + h, h relative to the peak's scale 1 + |w|) for d^2A/dw^2.  ``fold``: the w of the
    fold nearest each peak (NaN where none): the second orbit is taken away from it, at most a quarter of the
    way there, so that it stays on the peak's side of the fold, where the branch exists.  Returns
    (w, A, y0, ok)."""
    n = w.size
    w, y, tc = np.array(w, dtype=float), np.array(y0, dtype=float), np.array(tc, dtype=float)
    fold = np.full(n, np.nan) if fold is None else np.asarray(fold, dtype=float)
    A = np.full(n, np.nan)
    ok = np.zeros(n, dtype=bool)
    live = np.arange(n)
    for _ in range(MAX_ITER):
        if live.size == 0:
            break
        gap = w[live] - fold[live]
        with np.errstate(invalid="ignore"):
            room = np.where(np.isfinite(gap), 0.25 * np.abs(gap), np.inf)
        hl = np.where(gap < 0.0, -1.0, 1.0) * np.minimum(h * (1.0 + np.abs(w[live])), room)
        both = np.concatenate([live, live])
        ww = np.concatenate([w[live], w[live] + hl])
        yy = np.concatenate([y[:, live], y[:, live]], axis=1)
        amp, slope, moved, close, tangent, M = _swing(d[both], gamma[both], ww, yy, np.concatenate([tc[live]] * 2),
                                                      np.concatenate([eps[live]] * 2), shots)
        shots.note(idx[both], M, d[both], 1.0 + d[both] * ww)
        k = live.size
        curv = (slope[k:] - slope[:k]) / hl
        dw = -slope[:k] / curv
        A[live] = amp[:k]
        y[:, live] += close[:, :k] + tangent[:, :k] * dw
        w[live] += dw
        tc[live] = moved[:k]
        size = np.maximum(np.abs(close[:, :k]).max(axis=0) / np.maximum(1.0, np.abs(y[:, live]).max(axis=0)),
                          np.abs(dw) / (1.0 + np.abs(w[live])))
        done = size <= tol[live]
        ok[live[done]] = True
        live = live[~done & np.isfinite(size)]
    return w, A, y, ok
