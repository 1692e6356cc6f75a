"""Does 5.8's periodic response lose its q -> -q symmetry near f0 = 0.0163 m/s^2?  (issue 41, item 5)

An independent check by long time integration of the driven Duffing oscillator
q'' + 2 delta q' + omega0^2 q + alpha q^3 = f0 cos(omega t) (scipy's DOP853, rtol 1e-11), no harmonic balance
and no shooting: from several initial states, for 14 damping times (transients decay by e^-14), then a
Poincare section at t = k T over 30 more periods.  For each attractor reached it prints the spread of the
section (a periodic response of the drive's period: a fixed point, spread ~ 0), the symmetry defect
max |q(t + T/2) + q(t)| over the last period (zero for a symmetric response), its swing (half peak-to-peak)
and mech's swing of the symmetric branch at the same frequency, when the phase-parametrized harmonic balance
(``mech.solvers.mechanics.harmonic_balance``) has a branch point there.

    python scripts/duffing_symmetry.py [--f0 0.016327731092437] [--w -1.72366 2.6 2.9 3.1]
"""

from __future__ import annotations

import argparse
import math

import numpy as np
from scipy.integrate import solve_ivp

OMEGA0, DELTA, ALPHA = 10.0, 0.02, 1000.0


def attractor(f0, omega, y0, damping_times=14.0, periods=30):
    T = 2 * math.pi / omega

    def rhs(t, y):
        return [y[1], -2 * DELTA * y[1] - OMEGA0**2 * y[0] - ALPHA * y[0] ** 3 + f0 * math.cos(omega * t)]

    n0 = math.ceil(damping_times / (DELTA * T))
    t_end = (n0 + periods) * T
    ts = np.concatenate([np.arange(n0, n0 + periods + 1) * T, n0 * T + (np.arange(401) / 400.0) * T])
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=1e-11, atol=1e-14, dense_output=True)
    sec = sol.sol(np.arange(n0, n0 + periods + 1) * T)
    t1 = n0 * T + np.linspace(0.0, T, 401)
    q, q_half = sol.sol(t1)[0], sol.sol(t1 + 0.5 * T)[0]
    spread = float(np.max(np.ptp(sec, axis=1)))
    return sec[:, -1], spread, float(np.max(np.abs(q + q_half))), 0.5 * float(np.ptp(q))


def branch_swings(f0, omega):
    """mech's symmetric branch at this frequency: the swings of every branch point (by phase on a fine grid)."""
    from mech.solvers.mechanics.harmonic_balance import DuffingBalance

    Q = f0 / (2 * OMEGA0 * DELTA)
    d, gamma = DELTA / OMEGA0, ALPHA * Q * Q / (OMEGA0 * DELTA)
    phis = np.linspace(1e-3, math.pi - 1e-3, 4001)
    hb = DuffingBalance(np.full(phis.size, d), np.full(phis.size, gamma))
    v = hb.evaluate(phis, np.arange(phis.size))
    w = (omega - OMEGA0) / DELTA
    s = np.sign(v.w - w)
    out = []
    for i in np.flatnonzero(s[:-1] != s[1:]):
        t = (w - v.w[i]) / (v.w[i + 1] - v.w[i])
        out.append(Q * (v.A[i] + t * (v.A[i + 1] - v.A[i])))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--f0", type=float, default=0.016327731092437)
    ap.add_argument("--w", type=float, nargs="+", default=[-1.72366, 0.0, 2.6, 2.9, 3.1, 5.0])
    args = ap.parse_args()
    Q = args.f0 / (2 * OMEGA0 * DELTA)
    starts = [(0.0, 0.0), (Q, 0.0), (-Q, 0.0), (0.3 * Q, 3 * Q * OMEGA0), (2 * Q, 0.0), (0.0, -2 * Q * OMEGA0)]
    for w in args.w:
        omega = OMEGA0 + DELTA * w
        print(f"w = {w:g} (omega = {omega:.8g} rad/s): branch swings {[f'{a:.6g}' for a in branch_swings(args.f0, omega)]}")
        for y0 in starts:
            end, spread, defect, swing = attractor(args.f0, omega, list(y0))
            print(f"  from ({y0[0]:+.3g} m, {y0[1]:+.3g} m/s): section spread {spread:.1e}, symmetry defect "
                  f"{defect:.1e} m, swing {swing:.6g} m")


if __name__ == "__main__":
    main()
