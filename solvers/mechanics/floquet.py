"""Floquet theory and shooting: monodromy matrices over one period, multipliers, periodic orbits.

* ``linear_monodromy(damp, stiff, T, ...)``: the monodromy matrix of the scalar
  linear equation q'' + damp(t) q' + stiff(t) q = 0 over [t0, t0 + T], from the
  two fundamental solutions integrated together (one 4-state run).  Its
  determinant is exp(-int damp dt) exactly (Liouville), which the caller can
  use as a check.
* ``flow_with_variations(f, jac, y0, t_span, ...)``: the end state of a
  nonlinear flow and its Jacobian with respect to the start (the variational
  equations carried along), the building block of shooting by Newton.
* ``multipliers``, ``largest_exponent``, ``minus_one_function`` (p(-1) =
  1 + tr M + det M, which changes sign when a multiplier crosses -1: a smooth
  function to root-find on, unlike the growth rate).

No physics of one exercise lives here.  scipy is imported inside functions.
"""

from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np

from mech.solvers.numerics.ode import Trajectory, integrate

__all__ = [
    "integrate_ensemble",
    "even_hill_half",
    "even_hill_discriminant",
    "half_period_minus_one",
    "half_period_growth",
    "linear_monodromy",
    "flow_with_variations",
    "multipliers",
    "largest_exponent",
    "minus_one_function",
]


def linear_monodromy(
    damp: Callable[[float], float],
    stiff: Callable[[float], float],
    T: float,
    *,
    rtol: float,
    t0: float = 0.0,
    vscale: float = 1.0,
    method: str = "DOP853",
    integrator: str | None = None,
) -> tuple[np.ndarray, Trajectory]:
    """Monodromy matrix of q'' + damp(t) q' + stiff(t) q = 0 for the state (q, q').

    ``vscale`` is the typical size of q' for q ~ 1 (an angular frequency); the
    absolute tolerances are set from it so that both components are resolved.
    """

    def rhs(t, y):
        c, k = damp(t), stiff(t)
        return np.array([y[1], -c * y[1] - k * y[0], y[3], -c * y[3] - k * y[2]])

    atol_q = rtol * 1e-3
    atol = [atol_q, atol_q * vscale, atol_q, atol_q * vscale]
    # second column started with q' = vscale so that both columns have the same size
    traj = integrate(rhs, (t0, t0 + T), [1.0, 0.0, 0.0, vscale], rtol=rtol, atol=atol, method=method,
                     integrator=integrator)
    y = traj.y_end
    M = np.array([[y[0], y[2] / vscale], [y[1], y[3] / vscale]])
    return M, traj


def flow_with_variations(
    f: Callable[[float, np.ndarray], np.ndarray],
    jac: Callable[[float, np.ndarray], np.ndarray],
    y0: Sequence[float],
    t_span: tuple[float, float],
    *,
    rtol: float,
    scale: Sequence[float] | None = None,
    method: str = "DOP853",
    integrator: str | None = None,
    extra: Callable[[float, np.ndarray], Sequence[float]] | None = None,
    n_extra: int = 0,
    events=(),
) -> tuple[np.ndarray, np.ndarray, np.ndarray, Trajectory]:
    """(phi(y0), d phi / d y0, extra integrals, trajectory) over ``t_span``.

    ``scale``: the typical size of each component of y (absolute tolerances
    follow from it).  ``extra(t, y)`` optionally adds quadratures carried along
    (e.g. the divergence of f for Liouville's formula), started at zero.
    """
    y0 = np.asarray(y0, dtype=float)
    n = y0.size

    def rhs(t, z):
        y = z[:n]
        Phi = z[n : n + n * n].reshape(n, n)
        out = [f(t, y), (jac(t, y) @ Phi).ravel()]
        if extra is not None:
            out.append(np.asarray(extra(t, y), dtype=float))
        return np.concatenate(out)

    z0 = np.concatenate([y0, np.eye(n).ravel(), np.zeros(n_extra)])
    s = np.ones(n) if scale is None else np.asarray(scale, dtype=float)
    # the variational entries d y_i / d y0_j have the size s_i / s_j
    atol = rtol * 1e-3 * np.concatenate([s, np.outer(s, 1.0 / s).ravel(), np.ones(n_extra)])
    traj = integrate(rhs, t_span, z0, rtol=rtol, atol=atol, method=method, events=events,
                     integrator=integrator)
    z = traj.y_end
    return z[:n], z[n : n + n * n].reshape(n, n), z[n + n * n :], traj


def multipliers(M: np.ndarray) -> np.ndarray:
    """Floquet multipliers, largest modulus first."""
    ev = np.linalg.eigvals(M)
    return ev[np.argsort(-np.abs(ev))]


def largest_exponent(M: np.ndarray, T: float) -> float:
    """ln |largest multiplier| / T: the growth rate of the fastest-growing solution."""
    return math.log(float(np.max(np.abs(np.linalg.eigvals(M))))) / T


def minus_one_function(M: np.ndarray) -> float:
    """det(M + I) = 1 + tr M + det M for 2x2 M: zero when a multiplier is -1."""
    return 1.0 + float(np.trace(M)) + float(np.linalg.det(M))


def integrate_ensemble(make_rhs: Callable, t_span: tuple[float, float], y0: np.ndarray, *, rtol: float, atol,
                       integrator: str | None = None) -> tuple[np.ndarray, list]:
    """N variants of one equation integrated over the same ``t_span`` from ``y0`` (n x N): (states at the end,
    n x N; the integrations, each with ``nfev`` and ``method``): ``ensemble.follow`` (which says how; a
    failure of any variant fails the call)."""
    from mech.solvers.numerics.ensemble import follow

    got = follow(make_rhs, t_span, y0, rtol=rtol, atol=atol, integrator=integrator)
    return got.y_end, got.records


def even_hill_half(
    c0,
    c1,
    wave: Callable[[float], float],
    t_half: float,
    *,
    rtol: float,
    vscale=1.0,
    integrator: str | None = None,
) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray], list]:
    """(y1, y1', y2, y2') at t_half for N Hill equations y'' + (c0 + c1 wave(t)) y = 0 at once, y1 even and y2
    odd.

    ``c0``, ``c1``: the N variants' coefficients (arrays of N, or numbers shared by all); ``wave(t)`` the
    shape all share, even in t with period 2 t_half (scale each variant's time so that its half period is
    ``t_half``).  They give the whole monodromy matrix: tr M = 2 (y1 y2' + y1' y2), and with the Wronskian
    y1 y2' - y1' y2 = 1, tr M - 2 = 4 y1' y2 and tr M + 2 = 4 y1 y2', forms that keep their relative accuracy
    when a multiplier is near +1 or -1.

    Integrated by ``integrate_ensemble`` (``integrator``: forced by ``mech bench``).  ``vscale`` (a number or
    one per variant) is the size of y' for y ~ 1: y2 starts with y2' = vscale and is divided by it at the end.
    Returns ((y1, y1', y2, y2') as arrays of N, the integrations).
    """
    c0, c1, vs = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (c0, c1, vscale)))
    c0, c1, vs = (np.atleast_1d(x) for x in (c0, c1, vs))
    n_points = c0.size

    def make_rhs(sel):
        if isinstance(sel, int):  # one variant: plain floats
            a, b = float(c0[sel]), float(c1[sel])

            def one(t, y):
                k = a + b * wave(t)
                return np.array([y[1], -k * y[0], y[3], -k * y[2]])

            return one

        def rhs(t, y):
            k = c0 + c1 * wave(t)
            out = np.empty_like(y)
            out[0] = y[1]
            out[1] = -k * y[0]
            out[2] = y[3]
            out[3] = -k * y[2]
            return out

        return rhs

    y0 = np.zeros((4, n_points))
    y0[0] = 1.0
    y0[3] = vs
    atol_q = rtol * 1e-3
    atol = np.stack([np.full(n_points, atol_q), atol_q * vs, np.full(n_points, atol_q), atol_q * vs])
    (y1, y1p, y2, y2p), results = integrate_ensemble(make_rhs, (0.0, t_half), y0, rtol=rtol, atol=atol,
                                                     integrator=integrator)
    return (y1, y1p, y2 / vs, y2p / vs), results


def even_hill_discriminant(
    c0: float,
    c1: float,
    wave: Callable[[float], float],
    T: float,
    *,
    rtol: float,
    vscale: float = 1.0,
    integrator: str | None = None,
) -> tuple[float, float, list]:
    """tr M of the Hill equation y'' + (c0 + c1 wave(t)) y = 0 with wave even in t and of period T.

    Only half a period is integrated (see ``even_hill_half``).  Returns
    (tr M, Wronskian drift y1 y2' - y1' y2 - 1 at T/2, the integrations); det M = 1.
    A damped equation q'' + 2 delta q' + k(t) q = 0 reduces to this one by
    q = exp(-delta t) y with c0 + c1 wave = k - delta^2; its multipliers are
    exp(-delta T) times those of y.
    """
    (y1, y1p, y2, y2p), runs = even_hill_half(c0, c1, wave, 0.5 * T, rtol=rtol, vscale=vscale,
                                              integrator=integrator)
    return float(2.0 * (y1 * y2p + y1p * y2)[0]), float((y1 * y2p - y1p * y2 - 1.0)[0]), runs


def half_period_minus_one(y1, y1p, y2, y2p, e, dT, omega0):
    """(F, its absolute error) with F = det(M + I) / exp(-delta T), M the monodromy matrix of q over the period
    T of a damped even Hill equation q'' + 2 delta q' + k(t) q = 0, from the half-period solutions (y1 even,
    y2 odd) of its undamped form for y = exp(delta t) q, each with the absolute error e (y1, y2' unit-sized,
    y1' ~ omega0, y2 ~ 1/omega0); dT = delta T.  Over arrays.

    With the multipliers of q equal to exp(-delta T) times those of y, det(M + I) = 1 + exp(-dT) tr M_y +
    exp(-2 dT), so F = 2 cosh dT + tr M_y.  Near a multiplier -1 (tr M_y near -2) that sum cancels almost
    completely (a narrow zone: F ~ -(eps^2 - delta^2) T^2 ~ 1e-14 while tr M_y ~ 2 carries an error ~rtol),
    so it is formed from the half-period products that do not cancel: tr M_y + 2 = 4 y1 y2' gives
    F = 4 y1 y2' + 4 sinh^2(dT/2); tr M_y - 2 = 4 y1' y2 gives F = 4 y1' y2 + 4 cosh^2(dT/2) (used when
    tr M_y > 0, where F is far from 0).  The error is that of the product from the errors e of its two
    unit-sized factors, plus the round-off of the sum."""
    neg = y1 * y2p + y1p * y2 < 0  # tr M_y < 0
    prod = 4.0 * np.where(neg, y1 * y2p, y1p * y2)
    extra = np.where(neg, 4.0 * np.sinh(0.5 * dT) ** 2, 4.0 * np.cosh(0.5 * dT) ** 2)
    err = 4.0 * e * (np.where(neg, np.abs(y1) + np.abs(y2p), np.abs(y1p) / omega0 + np.abs(y2) * omega0) + e)
    return prod + extra, err + 4.0 * 2.0**-53 * (np.abs(prod) + extra)


def half_period_growth(y1, y1p, y2, y2p, e, omega0, delta, T):
    """(growth, its absolute error) of the damped even Hill equation (as ``half_period_minus_one``) from its
    half-period solutions, over arrays.

    growth = ln(lambda_y)/T - delta with lambda_y the largest |multiplier| of the Hill equation for
    y = exp(delta t) q.  Near the zone's edge and near threshold lambda_y is close to 1, and the
    growth a difference of two nearly equal rates, so ln(lambda_y) = arccosh(1 + h) is formed from
    h = (|tr M| - 2)/2 without cancellation: with the half-period solutions (y1 even, y2 odd) and the
    Wronskian y1 y2' - y1' y2 = 1, tr M + 2 = 4 y1 y2' and tr M - 2 = 4 y1' y2, and
    arccosh(1 + h) = log1p(h + (h (h + 2))^(1/2)).  Its error is that of the four half-period
    values (e each), propagated through h and the square root (which amplifies it near the zone's edge)."""
    tr = 2.0 * (y1 * y2p + y1p * y2)
    neg = tr < 0  # |tr| - 2 from the product that does not cancel: -(tr + 2) for tr < 0, tr - 2 for tr > 0
    h = np.where(neg, -2.0 * y1 * y2p, 2.0 * y1p * y2)
    dh = 2.0 * e * np.where(neg, np.abs(y1) + np.abs(y2p), np.abs(y1p) / omega0 + np.abs(y2) * omega0)
    hp = np.maximum(h, 0.0)
    root = np.sqrt(hp * (hp + 2.0))
    ln_lam = np.where(h > 0, np.log1p(hp + root), 0.0)  # |tr| <= 2: both multipliers of y on the unit circle
    with np.errstate(divide="ignore", invalid="ignore"):
        d_pos = np.where(h > dh, dh / np.where(root > 0, root, 1.0), np.sqrt(2.0 * np.maximum(h + dh, 0.0)))
    d_neg = np.where(-h < dh, np.sqrt(2.0 * dh), 0.0)
    d_ln = np.where(h > 0, d_pos, d_neg)
    return ln_lam / T - delta, d_ln / T + 4.0 * 2.0**-53 * (ln_lam / T + delta)
