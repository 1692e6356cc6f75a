"""Time a stability chart against a plain scipy loop over the same points, in the same run.

    python scripts/chart_bench.py [--n 200] [--loop-points 400] [--mech PATH]

The chart: 5.11's growth rate over omega in [7, 13] rad/s and mu in
[0.005, 0.5] on an n x n grid, through mech's batched route (both solves,
rtol 1e-12 and the rerun at 1e-13, the analytic side and every point's
verdict), timed in this process; then the whole command
``mech sweep 5.11 --omega 7:13:n --mu 0.005:0.5:n --only growth --plot FILE``
timed end to end (start-up, the figure).

The loop: what a student writes (for each point one ``solve_ivp`` of the
fundamental matrix over a modulation period pi/omega, DOP853 at rtol 1e-10,
the Floquet multipliers by ``numpy.linalg.eigvals``, growth = ln|largest|/T),
on ``--loop-points`` points drawn from the same grid (its cost per point does
not depend on how many).  The ratio compares the cost per point.  Both run
in the same process minutes apart, so the machine's load affects both alike.
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np


def chart(n: int):
    from mech.problems import registry
    from mech.studies.sweep import Axis, run_batched

    ex = registry.get("5.11")
    axes = [Axis("omega", tuple(np.linspace(7.0, 13.0, n))), Axis("mu", tuple(np.linspace(0.005, 0.5, n)))]
    t0 = time.perf_counter()
    res = run_batched(ex, axes, {}, ("growth",))
    dt = time.perf_counter() - t0
    return res, dt


def scipy_loop(points, omega0=10.0, delta=0.05):
    from scipy.integrate import solve_ivp

    out = []
    t0 = time.perf_counter()
    for omega, mu in points:
        def f(t, y):
            k = omega0**2 * (1.0 + mu * math.cos(2.0 * omega * t))
            return [y[1], -2 * delta * y[1] - k * y[0], y[3], -2 * delta * y[3] - k * y[2]]

        T = math.pi / omega
        sol = solve_ivp(f, (0.0, T), [1.0, 0.0, 0.0, 1.0], method="DOP853", rtol=1e-10, atol=1e-12)
        y = sol.y[:, -1]
        M = np.array([[y[0], y[2]], [y[1], y[3]]])
        out.append(math.log(max(abs(np.linalg.eigvals(M)))) / T)
    return np.array(out), time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=200, help="grid side (n x n points) [200]")
    ap.add_argument("--loop-points", type=int, default=400, help="points of the scipy loop [400]")
    ap.add_argument("--mech", default=shutil.which("mech") or os.path.join(os.path.dirname(sys.executable), "mech"),
                    help="the mech command to time end to end")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    import scipy.integrate  # noqa: F401  (imported before timing: both sides start warm)

    from mech.solvers.numerics import dop853

    dop853.available()
    n = args.n
    res, t_chart = chart(n)
    N = n * n
    # the loop over points drawn from the same grid
    rng = np.random.default_rng(args.seed)
    idx = rng.choice(N, size=min(args.loop_points, N), replace=False)
    om = res.batched.grid["omega"][idx]
    mu = res.batched.grid["mu"][idx]
    loop_vals, t_loop = scipy_loop(list(zip(om, mu)))
    J = res.batched.judged["growth"]
    diff = np.abs(loop_vals - J["numeric"][idx])
    per_chart, per_loop = t_chart / N, t_loop / len(idx)
    print(f"chart  (batched, rtol 1e-12 + rerun 1e-13, verdicts): {N} points in {t_chart:.2f} s = "
          f"{per_chart * 1e6:.1f} us/point; {res.n_failed} failed")
    print(f"loop   (solve_ivp DOP853 rtol 1e-10, one point at a time): {len(idx)} points in {t_loop:.2f} s = "
          f"{per_loop * 1e6:.1f} us/point")
    print(f"ratio  loop / chart per point: {per_loop / per_chart:.1f}")
    print(f"agreement on the loop's points: max |growth_loop - growth_chart| = {diff.max():.2g} 1/s")
    if args.mech and os.path.exists(args.mech):
        with tempfile.TemporaryDirectory() as tmp:
            png = os.path.join(tmp, "chart.png")
            cmd = [args.mech, "sweep", "5.11", "--omega", f"7:13:{n}", "--mu", f"0.005:0.5:{n}", "--only", "growth",
                   "--plot", png]
            t0 = time.perf_counter()
            proc = subprocess.run(cmd, capture_output=True, text=True)
            wall = time.perf_counter() - t0
        print(f"command: {' '.join(cmd[1:-1])} chart.png: {wall:.2f} s wall, exit {proc.returncode}")


if __name__ == "__main__":
    main()
