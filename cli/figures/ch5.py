"""Scene figures of chapter 5: the pendulum's phase portrait, the Mathieu instability zone, the Kapitza chart.

Curves of the analytic theory come from the exercise's analytic solver run
over a parameter; the markers from its numeric solver at a handful of points.
"""

from __future__ import annotations

import math

import numpy as np

from mech.cli.figures.common import ANALYTIC, NUMERIC, POINT, analytic_values, figure, numeric_values, series, spread, title


# -- 5.6 ------------------------------------------------------------------------------------------------

def pendulum_phase(ex, params, *, n_numeric=5, rtol=None):
    """Phase portrait theta'' = -omega0^2 sin theta (energy contours, the separatrix, the swing at theta0)
    and the period T(theta0) / T0 rising to the separatrix."""
    th0 = params.theta0
    fig, axes = figure(1, 2, w=4.6, h=3.7)
    ax = axes[0][0]
    th = np.linspace(-1.25 * math.pi, 1.25 * math.pi, 500)
    v = np.linspace(-2.6, 2.6, 400)
    TH, V = np.meshgrid(th, v)
    E = 0.5 * V ** 2 - np.cos(TH)  # in units of m g l, velocity in omega0
    ax.contour(TH, V, E, levels=np.linspace(-0.95, 2.5, 16), colors="0.6", linewidths=0.6)
    ax.contour(TH, V, E, levels=[1.0], colors="C2", linewidths=1.2)
    e0 = -math.cos(th0)
    ts = np.linspace(-th0, th0, 400)
    vs = np.sqrt(np.maximum(2 * (e0 + np.cos(ts)), 0))
    ax.plot(np.concatenate([ts, ts[::-1]]), np.concatenate([vs, -vs[::-1]]), color="C3", lw=2,
            label=f"the swing at θ0 = {math.degrees(th0):.4g}°")
    ax.plot([], [], color="C2", label="separatrix")
    ax.set_xlabel("θ [rad]")
    ax.set_ylabel("θ' / ω0")
    ax.legend(fontsize=7, frameon=False, loc="upper right")
    ax.set_title("phase portrait, contours of the energy", fontsize=8)

    ax = axes[0][1]
    xs = np.linspace(0.02, math.pi - 1e-3, 300)
    an, _ = series(ex, params, "theta0", xs, numeric=False)
    ax.plot(np.degrees(xs), an["T_ratio"], **{**ANALYTIC, "label": "T/T0 analytic (elliptic K)"})
    ax.plot(np.degrees(xs), 1 + xs ** 2 / 16, color="C1", ls="--", lw=1, label="1 + θ0²/16")
    if n_numeric:
        pts = spread(0.2, math.pi - 0.05, max(n_numeric - 1, 1))
        _, num = series(ex, params, "theta0", pts, rtol=rtol)
        ax.plot(np.degrees(pts), num["T_ratio"], **NUMERIC)
        nv, _ = numeric_values(ex, params, rtol)
        ax.plot([math.degrees(th0)], [nv["T_ratio"]], **{**NUMERIC, "label": None})
    a = analytic_values(ex, params)
    ax.plot([math.degrees(th0)], [a["T_ratio"]], "k*", ms=10, label="this swing")
    ax.set_yscale("log")
    ax.set_xlabel("amplitude θ0 [deg]")
    ax.set_ylabel("T / T0")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, frameon=False)
    title(fig, ex, params, skip=("theta0",))
    return fig


# -- 5.11 -----------------------------------------------------------------------------------------------

def mathieu(ex, params, *, n_numeric=5, rtol=None):
    """The first instability zone of q'' + 2 delta q' + omega0^2 (1 + mu cos 2 omega t) q = 0 in the (omega, mu) plane."""
    w0, mu = params.omega0, params.mu
    xi = params.omega - w0
    a = analytic_values(ex, params)
    fig, axes = figure(1, 2, w=4.6, h=3.7)
    ax = axes[0][0]
    top = min(1.0, max(3 * mu, 3 * a["mu_th"] if math.isfinite(a["mu_th"]) else 0, 0.05))
    mus = np.linspace(top / 300, top * 0.999, 300)
    an, _ = series(ex, params, "mu", mus, numeric=False)
    lo, hi = an["xi_lo"], an["xi_hi"]
    ok = np.isfinite(lo) & np.isfinite(hi)
    ax.fill_betweenx(mus[ok], lo[ok], hi[ok], color="C3", alpha=0.25, label="unstable (analytic zone)")
    ax.plot(lo, mus, color="C3", lw=1.5)
    ax.plot(hi, mus, color="C3", lw=1.5)
    if n_numeric:
        pts = spread(mus[ok][0] if ok.any() else top / 10, top, max(n_numeric - 1, 1))
        _, num = series(ex, params, "mu", pts, rtol=rtol)
        ax.plot(num["xi_lo"], pts, **{**NUMERIC, "label": "numeric edges (Floquet)"})
        ax.plot(num["xi_hi"], pts, **{**NUMERIC, "label": None})
    ax.plot([xi], [mu], "k*", ms=10, label="this oscillator")
    ax.set_xlabel("ξ = ω − ω0 [rad/s]")
    ax.set_ylabel("modulation depth μ")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, frameon=False)
    ax.set_title(f"first zone; threshold μ_th = {a['mu_th']:.4g} at this ω", fontsize=8)

    ax = axes[0][1]
    width = max(abs(xi), 2 * mu * w0 / 4, 4 * params.delta, 1e-3 * w0)
    ws = w0 + np.linspace(-width, width, 300)
    an, _ = series(ex, params, "omega", ws, numeric=False)
    ax.plot(ws - w0, an["growth"], **{**ANALYTIC, "label": "growth rate, analytic"})
    if n_numeric:
        pts = w0 + spread(-width, width, max(n_numeric - 1, 1))
        _, num = series(ex, params, "omega", pts, rtol=rtol)
        ax.plot(pts - w0, num["growth"], **NUMERIC)
    ax.axhline(0, color="k", lw=0.6)
    ax.axvline(xi, **POINT)
    ax.plot([xi], [a["growth"]], "k*", ms=10)
    ax.set_xlabel("ξ = ω − ω0 [rad/s]")
    ax.set_ylabel("growth rate [1/s]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, frameon=False)
    title(fig, ex, params)
    return fig


# -- 5.13 -----------------------------------------------------------------------------------------------

def kapitza(ex, params, *, n_numeric=5, rtol=None):
    """The Kapitza condition a^2 Omega^2 > 2 g l in the (Omega, a) plane, and the slow frequencies against a."""
    l, g, amp, Om = params.l, params.g, params.a, params.Omega
    w0 = math.sqrt(g / l)
    a = analytic_values(ex, params)
    fig, axes = figure(1, 2, w=4.6, h=3.7)
    ax = axes[0][0]
    Oms = np.geomspace(max(Om / 10, 8 * w0), Om * 10, 200)
    an, _ = series(ex, params, "Omega", Oms, numeric=False)
    ax.plot(Oms, an["a_min"], **{**ANALYTIC, "label": "a_min analytic: a Ω = (2 g l)^½"})
    ax.fill_between(Oms, an["a_min"], np.nanmax(an["a_min"]) * 10, color="C2", alpha=0.2,
                    label="inverted pendulum stable")
    if n_numeric:
        pts = spread(Oms[0], Oms[-1], max(n_numeric - 1, 1), log=True)
        _, num = series(ex, params, "Omega", pts, rtol=rtol)
        ax.plot(pts, num["a_min"], **NUMERIC)
    ax.plot([Om], [amp], "k*", ms=10, label="this pendulum")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylim(np.nanmin(an["a_min"]) / 3, np.nanmax(an["a_min"]) * 3)
    ax.set_xlabel("pivot frequency Ω [rad/s]")
    ax.set_ylabel("pivot amplitude a [m]")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, frameon=False)

    ax = axes[0][1]
    amin = a["a_min"]
    As = np.linspace(0.3 * amin, max(3 * amin, 1.5 * amp), 300)
    As = As[As < 0.5 * l]
    an, _ = series(ex, params, "a", As, numeric=False)
    ax.plot(As, an["omega_down"], color="C0", lw=1.6, label="about the lower position")
    ax.plot(As, an["omega_inv"], color="C1", lw=1.6, label="about the inverted position")
    if n_numeric:
        pts = spread(As[0], As[-1], max(n_numeric - 1, 1))
        _, num = series(ex, params, "a", pts, rtol=rtol)
        ax.plot(pts, num["omega_down"], **NUMERIC)
        ax.plot(pts, num["omega_inv"], **{**NUMERIC, "label": None})
    ax.axvline(amin, color="C2", ls="--", lw=1, label=f"a_min = {amin:.4g} m")
    ax.axvline(amp, **POINT)
    ax.set_xlabel("pivot amplitude a [m]")
    ax.set_ylabel("slow frequency [rad/s]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, frameon=False)
    title(fig, ex, params, extra="leading-order analytic theory (averaging over the fast period)")
    return fig
