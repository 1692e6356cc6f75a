"""Scene figures of chapter 4: the sliding ladder, the physical pendulum's Omega(l), the heavy top's
effective potential, the rotating frame's potential with the Lagrange points, the chime's normal modes.

The curves come from the physics written out here (a few lines each), the
marked answers from the exercise's own analytic and numeric solvers.
"""

from __future__ import annotations

import math

import numpy as np

from mech.cli.figures.common import ANALYTIC, NUMERIC, POINT, analytic_values, figure, numeric_values, series, spread, title


# -- 4.15 -----------------------------------------------------------------------------------------------

def ladder(ex, params, *, n_numeric=5, rtol=None):
    """The angle and the wall's force in time, up to the loss of contact, and the ladder drawn at a few instants.

    Both ends touching: T = M l^2 theta'^2 / 6, U = M g (l/2) sin theta, so
    theta'' = -(3g/2l) cos theta; the wall's force is M x_c'' with x_c = (l/2) cos theta.
    """
    from scipy.integrate import solve_ivp

    l, g, th0 = params.l, params.g, params.theta0
    start = min(th0, math.pi / 2 - 1e-3)  # the upright ladder needs a nudge: 1 mrad
    w0 = -math.sqrt(max(3 * g / l * (math.sin(th0) - math.sin(start)), 0.0))

    def rhs(t, y):
        return [y[1], -1.5 * g / l * math.cos(y[0])]

    def wall(t, y):  # N_wall / (M g)
        th, w = y
        acc = -1.5 * g / l * math.cos(th)
        return -(l / 2) * (math.cos(th) * w * w + math.sin(th) * acc) / g

    wall.terminal, wall.direction = True, -1
    sol = solve_ivp(rhs, (0, 100 * math.sqrt(l / g)), [start, w0], events=wall, rtol=1e-10, atol=1e-12,
                    dense_output=True, max_step=0.05 * math.sqrt(l / g))
    tc = sol.t_events[0][0] if len(sol.t_events[0]) else sol.t[-1]
    t = np.linspace(0, tc, 400)
    th, w = sol.sol(t)
    N = np.array([wall(0, [a, b]) for a, b in zip(th, w)])
    a = analytic_values(ex, params)
    nv, fail = numeric_values(ex, params, rtol) if n_numeric else ({}, None)

    fig, axes = figure(1, 3, w=3.6, h=3.2)
    ax = axes[0][0]
    ax.plot(t, np.degrees(th), color="C0", lw=1.8, label="θ(t), both ends touching")
    ax.axhline(math.degrees(a["theta_c"]), **POINT)
    ax.plot([tc], [math.degrees(a["theta_c"])], "*", color="k", ms=10, label=f"analytic θc = {math.degrees(a['theta_c']):.4g}°")
    if nv.get("theta_c") == nv.get("theta_c"):
        ax.plot([tc], [math.degrees(nv["theta_c"])], **{**NUMERIC, "label": f"numeric θc = {math.degrees(nv['theta_c']):.4g}°"})
    ax.set_xlabel("t [s]" + (" (from a 1 mrad nudge)" if start < th0 else ""))
    ax.set_ylabel("θ [deg] (from the floor)")
    ax.legend(fontsize=7, frameon=False)
    ax.grid(alpha=0.3)

    ax = axes[0][1]
    ax.plot(t, N, color="C2", lw=1.8, label="wall's force N / Mg")
    ax.axhline(0, color="k", lw=0.6)
    ax.axvline(tc, **POINT)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("N_wall / (M g)")
    ax.legend(fontsize=7, frameon=False)
    ax.grid(alpha=0.3)
    ax.annotate("top leaves the wall", (tc, 0), xytext=(0.35, 0.55), textcoords="axes fraction", fontsize=8,
                arrowprops=dict(arrowstyle="->", lw=0.8))

    ax = axes[0][2]
    thc = float(sol.sol(tc)[0])
    for k, thk in enumerate(np.linspace(start, thc, 6)):
        x, y = l * math.cos(thk), l * math.sin(thk)
        last = k == 5
        ax.plot([0, x], [y, 0], "-", color="C3" if last else "0.6", lw=2.2 if last else 1.2)
    ax.plot([0, 0], [0, 1.08 * l], "k", lw=2)
    ax.plot([0, 1.08 * l], [0, 0], "k", lw=2)
    ax.set_aspect("equal")
    ax.set_xlim(-0.05 * l, 1.1 * l)
    ax.set_ylim(-0.05 * l, 1.1 * l)
    ax.set_title("the ladder at equal steps of θ; red: at θc", fontsize=8)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    title(fig, ex, params, extra=f"ω at θc: analytic {a['omega_c']:.6g} rad/s"
          + (f", numeric {nv['omega_c']:.6g} rad/s" if nv.get("omega_c") == nv.get("omega_c") and nv else ""))
    return fig


# -- 4.10 -----------------------------------------------------------------------------------------------

def physical_pendulum(ex, params, *, n_numeric=5, rtol=None):
    """Omega(l) = (M g l / (I + M l^2))^1/2: its maximum at l_opt = (I/M)^1/2 and the conjugate pair l, I/(M l)."""
    M, I, g, l = params.M, params.I, params.g, params.l
    lopt = math.sqrt(I / M)
    lo, hi = min(l, I / (M * l), lopt) / 8, max(l, I / (M * l), lopt) * 8
    ls = np.geomspace(lo, hi, 300)
    Om = np.sqrt(M * g * ls / (I + M * ls * ls))
    a = analytic_values(ex, params)
    fig, axes = figure(1, 1, w=6.4, h=4.0)
    ax = axes[0][0]
    ax.plot(ls, Om, **{**ANALYTIC, "label": "Ω(l) analytic"})
    if n_numeric:
        xs = spread(lo, hi, max(n_numeric - 1, 1), log=True)
        _, num = series(ex, params, "l", xs, rtol=rtol)
        ax.plot(xs, num["Omega"], **NUMERIC)
    ax.axvline(a["l_opt"], color="C2", ls="--", lw=1, label=f"l_opt = {a['l_opt']:.4g} m")
    ax.axhline(a["Omega_max"], color="C2", ls=":", lw=1)
    ax.plot([l, a["l_conj"]], [a["Omega"]] * 2, "k*-", ms=10, lw=0.8, label=f"conjugate pair l = {l:.4g} m, "
            f"l' = {a['l_conj']:.4g} m")
    nv, _ = numeric_values(ex, params, rtol) if n_numeric else ({}, None)
    if nv:
        ax.plot([nv["l_opt"]], [nv["Omega_max"]], **{**NUMERIC, "label": None})
    ax.set_xscale("log")
    ax.set_xlabel("pivot distance from the center of mass l [m]")
    ax.set_ylabel("Ω [rad/s]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, frameon=False, loc="lower center")
    title(fig, ex, params, skip=("l",), extra=f"l + l' = l_ef = {a['l_ef']:.4g} m: the reversible (Kater) pendulum")
    return fig


# -- 4.21 -----------------------------------------------------------------------------------------------

def heavy_top(ex, params, *, n_numeric=5, rtol=None):
    """U_ef(theta) = (L_z - L_3 cos theta)^2 / (2 I_A sin^2 theta) + M g l cos theta for the steady precession's L_z.

    Steady precession at theta0 at the rate Omega has L_z = I_A Omega sin^2 theta0 + L_3 cos theta0:
    its effective potential has its minimum at theta0 (like Fig. 4.11).
    """
    M, l, I1, I3, w3, th0, g = (params[k] for k in ("M", "l", "I1", "I3", "omega3", "theta0", "g"))
    IA = I1 + M * l * l
    L3 = I3 * w3
    a = analytic_values(ex, params)
    nv, _ = numeric_values(ex, params, rtol) if n_numeric else ({}, None)
    fig, axes = figure(1, 2, w=4.6, h=3.6)
    ax = axes[0][0]
    th = np.linspace(0.02, math.pi - 0.02, 600)
    Om = a["omega_pre"]
    if math.isfinite(Om):
        Lz = IA * Om * math.sin(th0) ** 2 + L3 * math.cos(th0)
        U = (Lz - L3 * np.cos(th)) ** 2 / (2 * IA * np.sin(th) ** 2) + M * g * l * np.cos(th)
        U0 = (Lz - L3 * math.cos(th0)) ** 2 / (2 * IA * math.sin(th0) ** 2) + M * g * l * math.cos(th0)
        ax.plot(np.degrees(th), (U - U0) / (M * g * l), **{**ANALYTIC, "label": "U_ef, slow precession's L_z"})
        ax.axvline(math.degrees(th0), **POINT)
        ax.plot([math.degrees(th0)], [0], "k*", ms=10, label="θ0: steady precession")
        span = 3.0
        ax.set_ylim(-0.5, span)
    else:
        ax.text(0.5, 0.5, "no steady precession at θ0:\nω3 < ω_min", ha="center", transform=ax.transAxes)
    ax.set_xlabel("θ [deg] (axis from the upward vertical)")
    ax.set_ylabel("(U_ef − U_ef(θ0)) / (M g l)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, frameon=False)

    ax = axes[0][1]
    lo = max(a["omega_min"], a["omega_th"] * 0.2, 1e-9) * 1.02 if a["omega_min"] > 0 else a["omega_th"] * 0.2
    hi = max(w3, a["omega_th"]) * 5
    ws = np.geomspace(lo, hi, 200)
    an, _ = series(ex, params, "omega3", ws, numeric=False)
    ax.plot(ws, an["omega_pre"], **{**ANALYTIC, "label": "slow precession, exact"})
    ax.plot(ws, M * g * l / (I3 * ws), color="C1", ls="--", lw=1.2, label="fast-top estimate M g l / I3 ω3")
    if n_numeric:
        xs = spread(lo, hi, max(n_numeric - 1, 1), log=True)
        _, num = series(ex, params, "omega3", xs, rtol=rtol)
        ax.plot(xs, num["omega_pre"], **NUMERIC)
    if nv:
        ax.plot([w3], [nv["omega_pre"]], **{**NUMERIC, "label": None})
    ax.plot([w3], [Om], "k*", ms=10, label="this top")
    ax.axvline(a["omega_th"], color="C2", ls=":", lw=1, label=f"sleeping-top threshold {a['omega_th']:.4g} rad/s")
    if a["omega_min"] > 0:
        ax.axvline(a["omega_min"], color="C4", ls=":", lw=1, label=f"ω_min = {a['omega_min']:.4g} rad/s")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("ω3 [rad/s]")
    ax.set_ylabel("precession rate [rad/s]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6.5, frameon=False)
    title(fig, ex, params)
    return fig


# -- 4.27, 4.28 -----------------------------------------------------------------------------------------

def lagrange(ex, params, *, n_numeric=5, rtol=None):
    """The rotating frame's effective potential -G M1/r1 - G M2/r2 - Omega^2 r^2 / 2 with L1..L5 marked."""
    M1, M2, d = params.M1, params.M2, params.d
    mu = M2 / (M1 + M2)
    # units: d, and G (M1 + M2) / d (Omega^2 d^2)
    x1, x2 = -mu, 1 - mu
    a = analytic_values(ex, params)
    nv, _ = numeric_values(ex, params, rtol) if n_numeric else ({}, None)

    def phi(x, y):
        r1 = np.hypot(x - x1, y)
        r2 = np.hypot(x - x2, y)
        return -(1 - mu) / r1 - mu / r2 - 0.5 * (x * x + y * y)

    fig, axes = figure(1, 2, w=4.6, h=4.0)
    ax = axes[0][0]
    g = np.linspace(-1.6, 1.6, 400)
    X, Y = np.meshgrid(g, g)
    P = phi(X, Y)
    # the interesting levels are those of the Lagrange points (about -1.5 to -1.7 in these units)
    xl = [x2 - r for r in np.linspace(0.01, 0.5, 200)]
    lmin = min(-1.75, float(np.max(phi(np.array(xl), 0 * np.array(xl)))) - 0.15)
    Pc = np.clip(P, lmin, -1.49)
    ax.contourf(X, Y, Pc, levels=np.linspace(lmin, -1.49, 24), cmap="viridis")
    ax.contour(X, Y, Pc, levels=np.linspace(lmin, -1.49, 24), colors="w", linewidths=0.3)
    ax.plot([x1], [0], "o", color="C0", ms=8)
    ax.plot([x2], [0], "o", color="0.5", ms=5)
    pts = {}
    if ex.id == "4.27":
        for src, vals in (("analytic", a), ("numeric", nv)):
            if not vals:
                continue
            pts[src] = {"L1": (x2 - vals["r_L1"] / d, 0), "L2": (x2 + vals["r_L2"] / d, 0),
                        "L3": (x1 - vals["r_L3"] / d, 0)}
    else:
        for src, vals in (("analytic", a), ("numeric", nv)):
            if not vals:
                continue
            pts[src] = {"L4": (vals["x_L4"] / d, vals["y_L4"] / d), "L5": (vals["x_L4"] / d, -vals["y_L4"] / d)}
    for name, (x, y) in pts.get("analytic", {}).items():
        ax.plot([x], [y], "*", color="w", mec="k", ms=12)
        ax.annotate(name, (x, y), xytext=(4, 6), textcoords="offset points", fontsize=9, color="w")
    for name, (x, y) in pts.get("numeric", {}).items():
        ax.plot([x], [y], **{**NUMERIC, "label": None, "ms": 9})
    ax.set_aspect("equal")
    ax.set_xlabel("x / d (rotating frame, from the center of mass)")
    ax.set_ylabel("y / d")
    ax.set_title("effective potential: contours; ★ analytic, ○ numeric", fontsize=8)

    ax = axes[0][1]
    x = np.linspace(-1.6, 1.6, 2000)
    ax.plot(x, phi(x, 0 * x), color="C0", lw=1.5, label="φ_ef(x, 0)")
    ax.set_ylim(-4.0, -1.0)
    for name, (px, py) in pts.get("analytic", {}).items():
        if abs(py) < 1e-12:
            ax.axvline(px, **POINT)
            ax.annotate(name, (px, -1.2), ha="center", fontsize=9)
    if ex.id == "4.28":
        xl = pts["analytic"]["L4"][0]
        yl = pts["analytic"]["L4"][1]
        ax.plot(x, phi(x, yl + 0 * x), color="C1", lw=1.2, label="φ_ef(x, y_L4)")
        ax.axvline(xl, **POINT)
        ax.annotate("L4", (xl, -1.2), ha="center", fontsize=9)
        stab = "stable" if a["growth_rate"] == 0 else f"unstable, growth {a['growth_rate']:.3g} 1/s"
        ax.set_title(f"L4 is a maximum of φ_ef, yet {stab}\n(Coriolis force; μ = {mu:.4g})", fontsize=8)
    else:
        ax.set_title(f"L1, L2, L3: saddles on the axis (μ = {mu:.4g})", fontsize=8)
    ax.set_xlabel("x / d")
    ax.set_ylabel("φ_ef / (G(M1+M2)/d)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, frameon=False, loc="lower center")
    title(fig, ex, params)
    return fig


# -- 4.12 -----------------------------------------------------------------------------------------------

def chime(ex, params, *, n_numeric=5, rtol=None):
    """The chime's two normal modes drawn: thread angle phi and bar angle psi = r phi, at the extremes of a swing."""
    l, lp = params.l, params.l_prime
    a = analytic_values(ex, params)
    nv, _ = numeric_values(ex, params, rtol) if n_numeric else ({}, None)
    fig, axes = figure(1, 3, w=3.3, h=3.6)
    amp = 0.35
    for k, (r, w, label) in enumerate(((a["r1"], a["omega1"], "lower mode"), (a["r2"], a["omega2"], "higher mode"))):
        ax = axes[0][k]
        s = amp / max(1.0, abs(r))
        for sign, shade in ((1, "C3"), (-1, "C0"), (0, "0.6")):
            phi, psi = sign * s, sign * s * r
            x1, y1 = lp * math.sin(phi), -lp * math.cos(phi)
            x2, y2 = x1 + l * math.sin(psi), y1 - l * math.cos(psi)
            ax.plot([0, x1], [0, y1], color=shade, lw=1, ls="--" if sign == 0 else "-")
            ax.plot([x1, x2], [y1, y2], color=shade, lw=4 if sign else 2, solid_capstyle="round")
        ax.plot([-0.2 * lp, 0.2 * lp], [0, 0], "k", lw=2)
        ax.set_aspect("equal")
        ax.set_xlim(-0.7 * (l + lp), 0.7 * (l + lp))
        ax.set_ylim(-1.1 * (l + lp), 0.1 * (l + lp))
        ax.set_xticks([])
        ax.set_yticks([])
        num = f"\nnumeric ω = {nv['omega%d' % (k + 1)]:.6g}, ψ/φ = {nv['r%d' % (k + 1)]:.5g}" if nv else ""
        ax.set_title(f"{label}: ω = {w:.6g} rad/s, ψ/φ = {r:.5g}{num}", fontsize=7.5)
    ax = axes[0][2]
    ls = np.geomspace(lp / 20, lp * 20, 200)
    an, _ = series(ex, params, "l_prime", ls, numeric=False)
    ax.plot(ls, an["omega1"], color="C0", lw=1.6, label="ω1 analytic")
    ax.plot(ls, an["omega2"], color="C1", lw=1.6, label="ω2 analytic")
    if n_numeric:
        xs = spread(ls[0], ls[-1], max(n_numeric - 1, 1), log=True)
        _, num = series(ex, params, "l_prime", xs, rtol=rtol)
        ax.plot(xs, num["omega1"], **NUMERIC)
        ax.plot(xs, num["omega2"], **{**NUMERIC, "label": None})
    ax.axvline(lp, **POINT)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("thread length l' [m]")
    ax.set_ylabel("ω [rad/s]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, frameon=False)
    title(fig, ex, params)
    return fig
