"""The figure every exercise has: each output against one parameter, analytic as a line, numeric as markers.

It needs nothing but the registry.  The parameter (``--vary`` or chosen here:
the one that moves the most outputs, preferring a curve over a power law and
a bounded range) runs over a range around its value within its bounds: the
whole interval where both bounds are finite, a decade either side on a log
scale where the parameter is positive, twice its size either side otherwise.
Points the exercise's joint constraints refuse are left out.  The numeric
solver runs at a handful of points (it costs 0.05-1 s each), one of them the
chosen parameter point, which is marked.
"""

from __future__ import annotations

import math
import time

import numpy as np

from mech.cli.figures.common import ANALYTIC, NUMERIC, POINT, analytic_values, figure, finite, label, numeric_values, title
from mech.problems.spec import BadInput

N_LINE = 121
LINE_BUDGET_S = 1.0  # the analytic line's share of the time: fewer points for a slow formula
CHOOSE_BUDGET_S = 0.5


def param_range(p, value: float) -> tuple[float, float, bool]:
    """(lo, hi, log) around ``value`` within the parameter's bounds."""
    lo_b, hi_b = p.min, p.max
    if lo_b is not None and hi_b is not None:
        span = hi_b - lo_b
        lo = lo_b + (0.01 * span if p.min_open else 0.0)
        hi = hi_b - (0.01 * span if p.max_open else 0.0)
        lo, hi = min(lo, value), max(hi, value)
        log = lo > 0 and hi / lo > 100
        return lo, hi, log
    if value > 0 and (lo_b is None or lo_b >= 0):
        lo, hi = value / 10, value * 10
        if lo_b is not None and lo <= lo_b:
            lo = lo_b + 0.05 * (value - lo_b) if (p.min_open or lo_b == 0) else lo_b
        if hi_b is not None and hi >= hi_b:
            hi = hi_b - 0.05 * (hi_b - value) if p.max_open else hi_b
        return lo, hi, lo > 0 and hi / lo > 20
    scale = abs(value) if value != 0 else 1.0
    lo, hi = value - 2 * scale, value + 2 * scale
    if lo_b is not None and lo <= lo_b:
        lo = lo_b + 0.01 * (value - lo_b) if p.min_open else lo_b
    if hi_b is not None and hi >= hi_b:
        hi = hi_b - 0.01 * (hi_b - value) if p.max_open else hi_b
    return lo, hi, False


def grid(p, value: float, n: int = N_LINE) -> tuple[np.ndarray, bool]:
    lo, hi, log = param_range(p, value)
    xs = np.geomspace(lo, hi, n) if log else np.linspace(lo, hi, n)
    return xs, log


def _valid(ex, params, name, xs):
    """The grid values the exercise accepts (bounds and joint constraints), with their resolved parameters."""
    keep, resolved = [], []
    for x in xs:
        try:
            resolved.append(ex.resolve({**params, name: float(x)}))
            keep.append(float(x))
        except BadInput:
            pass
    return np.array(keep), resolved


def _analytic_cost(ex, params) -> float:
    t0 = time.perf_counter()
    analytic_values(ex, params)
    return time.perf_counter() - t0


def choose_param(ex, params, cost: float | None = None) -> str:
    """The parameter whose variation tells the most: moves most outputs, bends them, has a bounded range."""
    best, best_score = ex.params[0].name, -1.0
    cost = _analytic_cost(ex, params) if cost is None else cost
    n = int(min(7, max(3, CHOOSE_BUDGET_S / max(cost * len(ex.params), 1e-9))))
    base = analytic_values(ex, params)
    for order, p in enumerate(ex.params):
        xs, log = grid(p, params[p.name], n)
        xs, resolved = _valid(ex, params, p.name, xs)
        if len(xs) < 3:
            continue
        rows = [analytic_values(ex, r) for r in resolved]
        moved, bent = 0, 0
        for o in ex.outputs:
            ys = np.array([r[o.name] for r in rows])
            if not np.all(np.isfinite(ys)):
                ys = ys[np.isfinite(ys)]
                if len(ys) < 3:
                    continue
            ref = max(abs(base.get(o.name, 0.0)) if math.isfinite(base.get(o.name, math.nan)) else 0.0,
                      float(np.max(np.abs(ys))), 1e-300)
            if np.ptp(ys) > 1e-6 * ref:
                moved += 1
                # a power law is a straight line on log-log axes: curvature is what is worth a picture
                ys = -ys if np.all(ys < 0) else ys
                if np.all(ys > 0) and np.all(xs > 0):
                    sl = np.diff(np.log(ys)) / np.diff(np.log(xs[: len(ys)]))
                    if np.ptp(sl) > 0.05:
                        bent += 1
                else:
                    bent += 1
        score = moved + 0.5 * min(bent, 1) + 0.25 * bent / max(len(ex.outputs), 1)
        score += 0.3 * (p.min is not None and p.max is not None) - 0.01 * order
        score -= 0.5 * (params[p.name] == 0)
        if score > best_score:
            best, best_score = p.name, score
    return best


def generic_figure(ex, params, *, vary: str | None = None, n_numeric: int = 5, rtol: float | None = None):
    cost = _analytic_cost(ex, params)
    name = vary or choose_param(ex, params, cost)
    p = ex.param_map[name]
    x0 = params[name]
    xs, log = grid(p, x0, int(min(N_LINE, max(25, LINE_BUDGET_S / max(cost, 1e-9)))))
    xs, resolved = _valid(ex, params, name, xs)
    if len(xs) == 0:  # nothing around the point is allowed: the point alone
        xs, resolved = np.array([x0]), [params]
    rows = [analytic_values(ex, r) for r in resolved]

    # numeric: a handful spread over the range, and the point itself
    picks = sorted(set(np.linspace(0, len(xs) - 1, max(n_numeric - 1, 1)).round().astype(int).tolist()))
    num_x = [float(xs[i]) for i in picks] + [x0]
    num_p = [resolved[i] for i in picks] + [params]
    has_numeric = "numeric" in ex.methods and n_numeric > 0
    num_rows, failures = [], []
    if has_numeric:
        for r in num_p:
            vals, fail = numeric_values(ex, r, rtol)
            num_rows.append(vals)
            if fail:
                failures.append(fail)
    at_point = analytic_values(ex, params)

    k = len(ex.outputs)
    ncols = 1 if k == 1 else 2 if k in (2, 4) else 3
    nrows = math.ceil(k / ncols)
    fig, axes = figure(nrows, ncols, w=4.0, h=2.9)
    scale = p.to_display(1.0)
    for j, o in enumerate(ex.outputs):
        ax = axes[j // ncols][j % ncols]
        ys = np.array([r[o.name] for r in rows])
        if "analytic" in ex.methods:
            ax.plot(xs * scale, ys, **ANALYTIC)
        if has_numeric:
            ny = np.array([r[o.name] for r in num_rows])
            ax.plot(np.array(num_x) * scale, ny, **NUMERIC)
        ax.axvline(x0 * scale, **POINT)
        y0 = at_point.get(o.name, math.nan)
        if math.isfinite(y0):
            ax.plot([x0 * scale], [y0], marker="*", color="k", ms=9, ls="none", label="this point")
        if log:
            ax.set_xscale("log")
        fin = ys[np.isfinite(ys)]
        if len(fin) and np.ptp(fin) <= 1e-9 * max(np.max(np.abs(fin)), 1e-300):
            # a constant: round-off in the numeric markers must not fill the axis
            c = float(fin[0])
            half = abs(c) * 0.05 if c != 0 else 1.0
            ax.set_ylim(c - half, c + half)
        every = np.concatenate([ys[np.isfinite(ys)], [v for r in num_rows if math.isfinite(v := r[o.name])]])
        if len(every) and np.all(every > 0) and every.max() / every.min() > 300:
            ax.set_yscale("log")
        ax.set_xlabel(label(f"{p.symbol or p.name}", p.display or p.unit))
        ax.set_ylabel(label(o.name, o.unit) + (" *" if o.theory != "exact" else ""), fontsize=9)
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=8)
        if j == 0:
            ax.legend(fontsize=7.5, frameon=False)
    for j in range(k, nrows * ncols):
        axes[j // ncols][j % ncols].set_visible(False)
    extra = ""
    if any(o.theory != "exact" for o in ex.outputs):
        extra = "* leading-order analytic theory"
    if failures:
        extra += ("; " if extra else "") + f"numeric failed at {len(failures)} of {len(num_p)} points"
    title(fig, ex, params, skip=(name,), extra=extra)
    return fig
