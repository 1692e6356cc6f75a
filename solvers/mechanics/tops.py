"""A symmetric top about a fixed point, in nonsingular vector form, and rate measurement.

State ``[n3(3), L(3)]``: the unit symmetry axis and the angular momentum about the
fixed point, both lab components.  For a symmetric body (I_A about every axis
normal to n3 through the point, I3 about n3) the angular velocity is
``omega = L / I_A + L3 (1/I3 - 1/I_A) n3`` with ``L3 = L . n3``, so
``dn3/dt = omega x n3 = L x n3 / I_A`` and ``dL/dt = torque(t, n3)``: no Euler
angles, no singularity at the vertical.  ``L3`` is conserved whenever the
torque is normal to n3 (forces applied on the axis).

The rate of a steady rotation about z is measured from a sampled run by a least
squares fit of the unwrapped azimuth.  ``follow_scaled``: many runs at once, each
over its own duration folded into a scaled time, sampled, with a bound on the step.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

__all__ = ["axis_rhs", "top_energy", "azimuth", "polar_angle", "fit_rate", "follow_scaled", "PrecessionResidual",
           "residual_max", "slow_roots", "least_spin", "ROOT_FAILS", "LEAST_SPIN_FAILS", "NO_PRECESSION"]


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
    """Unwrapped azimuth of the horizontal projection of the vectors n (3 x K samples, or 3 x K x N runs),
    along the samples."""
    return np.unwrap(np.arctan2(n[1], n[0]), axis=0)


def polar_angle(n: np.ndarray) -> np.ndarray:
    """Angle from +z, well conditioned near both poles."""
    return np.arctan2(np.hypot(n[0], n[1]), n[2])


def fit_rate(t: np.ndarray, angle: np.ndarray):
    """Least-squares slope of angle(t) and the rms residual of the straight line: numbers for K samples,
    arrays (N) for K x N (the samples of N runs at the same t)."""
    t = np.asarray(t, dtype=float).reshape((-1,) + (1,) * (np.ndim(angle) - 1))
    tc = t - t.mean()
    ac = angle - np.mean(angle, axis=0)
    slope = np.sum(tc * ac, axis=0) / np.sum(tc * tc)
    return slope, np.sqrt(np.mean((ac - slope * tc) ** 2, axis=0))


def follow_scaled(make_rhs, y0, samples: int, *, max_step, rtol: float, atol, integrator: str | None = None):
    """N runs over a scaled time tau in [0, 1] (each variant's duration folded into its right-hand side),
    sampled at K + 1 evenly spaced times, K = max(samples, 1/max_step): (tau (K + 1), states K + 1 x n x N,
    the integrations).  No step is longer than ``max_step`` (in tau, one per variant or one for all).

    ``make_rhs(sel)``: the right-hand side of the variants ``sel`` (``slice(None)``: all, states n x N; an
    index j: variant j alone, n floats).  Many variants: mech's DOP853 steps them together
    (``batch.integrate_batch``) leg by leg between the samples, each leg started with a step of its length
    (so no step exceeds it), each variant's error held to rtol as its own run would hold it.  One alone, or
    each with an ``integrator`` forced (``mech bench``): ``ode.integrate`` with ``max_step`` and the samples
    as ``t_eval``.  ``atol``: n x N."""
    from mech.solvers.numerics.ensemble import follow_sampled

    y0 = np.asarray(y0, dtype=float)
    max_step = np.broadcast_to(np.asarray(max_step, dtype=float), (y0.shape[1],))
    K = int(max(samples, np.ceil(1.0 / float(np.min(max_step)))))
    tau = np.linspace(0.0, 1.0, K + 1)
    Y, records = follow_sampled(make_rhs, tau, y0, rtol=rtol, atol=atol, integrator=integrator, max_step=max_step,
                                legs_start_whole=True)
    return tau, Y, records


# -- steady precession of the heavy symmetric top: the torque balance's residual and its searches, over arrays

class PrecessionResidual:
    """The torque balance's residual along z x n3, in units of M g l sin theta0, over arrays of tops.

    The angular velocity Omega z + psidot n3 is split on the body's principal
    directions before the inertia tensor acts: z = cos theta0 n3 + sin theta0 u
    with u = (-cos theta0, 0, sin theta0) normal to n3, so
    omega = Omega sin theta0 u + omega3 n3 and L = I_A Omega sin theta0 u + I3 omega3 n3.
    (Rotating the tensor into lab axes first loses the digits of L when
    I_A >> I3: the two I_A terms of L_x cancel to a part in I_A/I3.)
    """

    def __init__(self, IA, I3, Mgl, theta0):
        self.IA, self.I3, self.Mgl = IA, I3, Mgl
        s, c = np.sin(theta0), np.cos(theta0)
        zero = np.zeros_like(s)
        self.s = s
        self.n3 = np.stack([s, zero, c])
        self.u = np.stack([-c, zero, s])
        self.torque = Mgl * np.stack([zero, s, zero])  # l n3 x (-M g z) = M g l z x n3

    def angular_momentum(self, idx, Om, omega3):
        """L (3 x n) of the tops idx turning at Om with the spin omega3."""
        return self.IA[idx] * Om * self.s[idx] * self.u[:, idx] + self.I3[idx] * omega3 * self.n3[:, idx]

    def __call__(self, idx, Om, omega3):
        """The residual (Omega z x L - torque) . e / (M g l sin theta0), e = z x n3 / sin theta0 = y."""
        L = self.angular_momentum(idx, Om, omega3)
        z_cross_L = np.stack([-L[1], L[0], np.zeros_like(L[0])])
        return (Om * z_cross_L - self.torque[:, idx])[1] / (self.Mgl[idx] * self.s[idx])


# a bracket of the residual's maximum narrowed to this part of Omega, then a parabolic step (golden_max),
# leaves the maximum's value to round-off
MAX_XTOL = 1e-4
DOUBLINGS = 400


def _doubling_scan(R, omega3, stop_positive):
    """Per top, Omega doubled from the rate scale M g l/(I3 omega3) until the residual is positive (when
    ``stop_positive``) or falls (past its maximum): (f(0), the last three abscissae (prev2, prev, Om) and
    f(prev), f(Om), how each scan ended: 1 positive, 2 falling, 0 neither within DOUBLINGS)."""
    n = omega3.size
    every = np.arange(n)
    f0 = R(every, 0.0, omega3)
    prev2, prev, fprev = np.zeros(n), np.zeros(n), f0.copy()
    Om = R.Mgl / (R.I3 * omega3)
    fv, how = np.full(n, np.nan), np.zeros(n)
    todo = every
    for _ in range(DOUBLINGS):
        if not todo.size:
            break
        fv[todo] = R(todo, Om[todo], omega3[todo])
        pos = (fv[todo] > 0) if stop_positive else np.zeros(todo.size, dtype=bool)
        fall = ~pos & (fv[todo] < fprev[todo])
        how[todo[pos]], how[todo[fall]] = 1.0, 2.0
        on = todo[~pos & ~fall]
        prev2[on], prev[on], fprev[on] = prev[on], Om[on], fv[on]
        Om[on] *= 2.0
        todo = on
    return f0, prev2, prev, Om, fprev, fv, how


def residual_max(R, omega3, stop_positive=False):
    """The residual's maximum over Omega > 0 of each top at its spin omega3 (+inf where it grows without
    bound; with ``stop_positive``, a positive value of it where one is met first)."""
    from mech.solvers.numerics.searches import golden_max

    _, prev2, _, Om, _, fv, how = _doubling_scan(R, omega3, stop_positive)
    out = np.where(how == 1.0, fv, np.inf)
    fall = np.flatnonzero(how == 2.0)
    if fall.size:
        out[fall] = golden_max(lambda i, x: R(fall[i], x, omega3[fall[i]]), prev2[fall], Om[fall],
                               MAX_XTOL * Om[fall])[1]
    return out


def slow_roots(IA, I3, Mgl, theta0, omega3):
    """The smallest positive zero of the residual of each top (units rad/s), and its maximum where it was
    located (NaN elsewhere), and a code: 0 a root, 1 none (the residual stays negative), 2 the residual at zero
    precession is not negative, 3 no sign change found, 4 the root search did not converge."""
    from mech.solvers.numerics.batch import illinois
    from mech.solvers.numerics.searches import golden_max

    R = PrecessionResidual(IA, I3, Mgl, theta0)
    f0, prev2, prev, Om, fprev, fv, how = _doubling_scan(R, omega3, True)
    code = np.where(f0 < 0, np.where(how == 0.0, 3.0, 0.0), 2.0)
    lo, hi, flo, fhi = prev, Om.copy(), fprev, fv.copy()
    fmax = np.full(omega3.size, np.nan)
    fall = np.flatnonzero((code == 0) & (how == 2.0))
    if fall.size:  # past the maximum without a positive value: the root lies below the maximum, if it is >= 0
        x, fmax[fall] = golden_max(lambda i, x: R(fall[i], x, omega3[fall[i]]), prev2[fall], Om[fall],
                                   MAX_XTOL * Om[fall])
        lo[fall], flo[fall], hi[fall], fhi[fall] = 0.0, f0[fall], x, fmax[fall]
        code[fall[fmax[fall] < 0]] = 1.0
    root = np.full(omega3.size, np.nan)
    go = np.flatnonzero(code == 0)
    if go.size:
        x, conv = illinois(lambda x, i: R(go[i], x, omega3[go[i]]), lo[go], hi[go], flo[go], fhi[go],
                           xtol=1e-300, rtol=1e-15, max_iter=500)
        root[go] = x
        code[go[~conv]] = 4.0
    return root, fmax, code


ROOT_FAILS = {2.0: "the residual at zero precession is not negative",
               3.0: "no sign change of the precession residual found",
               4.0: "the root search for the precession rate did not converge"}
NO_PRECESSION = "the precession residual stays negative: no steady precession at theta0"


def least_spin(IA, I3, Mgl, theta0, omega_th):
    """omega_min, the least spin with a steady precession at theta0, over arrays of tops: where the residual's
    maximum over Omega touches zero (Illinois on it as a function of the spin, from 1e-12 omega_th up); 0 where
    a steady precession exists at every spin (within 1e-12 omega_th); and a code: 0 found, 1 no spin found with
    a steady precession, 2 not converged."""
    from mech.solvers.numerics.batch import illinois

    R = PrecessionResidual(IA, I3, Mgl, theta0)
    n = IA.size
    w_lo = 1e-12 * omega_th
    f_lo = residual_max(R, w_lo, stop_positive=True)
    out, code = np.where(f_lo >= 0, 0.0, np.nan), np.zeros(n)
    go = np.flatnonzero(~(f_lo >= 0))
    w_hi, f_hi, todo = omega_th.copy(), np.full(n, np.nan), go
    for _ in range(200):
        if not todo.size:
            break
        f_hi[todo] = residual_max(PrecessionResidual(IA[todo], I3[todo], Mgl[todo], theta0[todo]), w_hi[todo])
        todo = todo[~(f_hi[todo] >= 0)]
        w_hi[todo] *= 2
    code[todo] = 1.0
    go = np.setdiff1d(go, todo)
    if go.size:
        def fm(x, i):
            j = go[i]
            return residual_max(PrecessionResidual(IA[j], I3[j], Mgl[j], theta0[j]), x)

        # the bracket narrowed to a factor 2 by halving (Illinois is slow across the decades between 1e-12
        # omega_th and omega_th), its lower end 1e-12 omega_th where the halving reaches it
        lo, flo, hi, fhi = w_hi[go] / 2, np.full(go.size, np.nan), w_hi[go].copy(), f_hi[go].copy()
        todo = np.arange(go.size)
        while todo.size:
            floor = todo[lo[todo] <= w_lo[go[todo]]]
            lo[floor], flo[floor] = w_lo[go[floor]], f_lo[go[floor]]
            todo = todo[lo[todo] > w_lo[go[todo]]]
            f = fm(lo[todo], todo)
            flo[todo[f < 0]] = f[f < 0]
            up = todo[~(f < 0)]
            hi[up], fhi[up] = lo[up], f[~(f < 0)]
            lo[up] /= 2
            todo = up
        x, conv = illinois(fm, lo, hi, flo, fhi, xtol=1e-300, rtol=1e-15, max_iter=500)
        out[go] = x
        code[go[~conv]] = 2.0
    return out, code


LEAST_SPIN_FAILS = {1.0: "no spin found at which a steady precession exists",
                    2.0: "the root search for omega_min did not converge"}
