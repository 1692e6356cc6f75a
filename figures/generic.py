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

from mech.figures.common import ANALYTIC, FONT, NUMERIC, POINT, analytic_values, figure, label, title
from mech.problems.scene import SceneRun
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
        moved, bent, slopes = 0, 0, []
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
                    slopes.append(float(np.mean(np.abs(sl))))
                    if np.ptp(sl) > 0.05:
                        bent += 1
                else:
                    bent += 1
        score = moved + 0.5 * min(bent, 1) + 0.25 * bent / max(len(ex.outputs), 1)
        # among power laws, the steeper one tells more (I ~ M R^2: R before M)
        score += 0.1 * min(float(np.mean(slopes)) if slopes else 0.0, 3.0) / 3.0
        score += 0.3 * (p.min is not None and p.max is not None) - 0.01 * order
        score -= 0.5 * (params[p.name] == 0)
        if score > best_score:
            best, best_score = p.name, score
    return best


def _panels(ex, at_point) -> list[list]:
    """Outputs sharing a panel: those of one unit whose values at the point are all positive (a log
    axis shows them together) or within a factor 30 of each other; every other output alone."""
    by_unit: dict[str, list] = {}
    for o in ex.outputs:
        by_unit.setdefault(o.unit, []).append(o)
    panels = []
    for group in by_unit.values():
        vals = np.array([at_point.get(o.name, math.nan) for o in group])
        mags = np.abs(vals[np.isfinite(vals)])
        together = len(group) > 1 and len(mags) == len(group) and (
            np.all(vals > 0) or (mags.min() > 0 and mags.max() / mags.min() < 30))
        panels.extend([group] if together else [[o] for o in group])
    return panels


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
    num_x = [x0] + [float(xs[i]) for i in picks]
    num_p = [params] + [resolved[i] for i in picks]
    has_numeric = "numeric" in ex.methods and n_numeric > 0
    solves = SceneRun(ex, rtol, n_numeric)  # each numeric solve under its time budget, failures kept
    num_rows = [solves.numeric(r) for r in num_p] if has_numeric else []
    failures = solves.failures
    at_point = analytic_values(ex, params)

    groups = _panels(ex, at_point)
    k = len(groups)
    ncols = 1 if k == 1 else 2 if k in (2, 4) else 3
    nrows = math.ceil(k / ncols)
    fig, axes = figure(nrows, ncols, w=5.0 if k > 1 else 6.4, h=3.7 if k > 1 else 4.3)
    scale = p.to_display(1.0)
    for j, group in enumerate(groups):
        ax = axes[j // ncols][j % ncols]
        every = []
        for c, o in enumerate(group):
            color = f"C{c % 10}"
            tag = o.name + (" *" if o.theory != "exact" else "")
            ys = np.array([r[o.name] for r in rows])
            every.extend(ys[np.isfinite(ys)])
            if "analytic" in ex.methods:
                ax.plot(xs * scale, ys, **{**ANALYTIC, "color": color, "label": tag if len(group) > 1 else "analytic"})
            if has_numeric:
                ny = np.array([r[o.name] for r in num_rows])
                every.extend(ny[np.isfinite(ny)])
                ax.plot(np.array(num_x) * scale, ny, **{**NUMERIC, "color": color if len(group) > 1 else NUMERIC["color"],
                                                        "label": "numeric" if len(group) == 1 else None})
            y0 = at_point.get(o.name, math.nan)
            if math.isfinite(y0):
                ax.plot([x0 * scale], [y0], marker="*", color="k", ms=10, ls="none", zorder=5)
        ax.plot([], [], marker="*", color="k", ms=10, ls="none", label=f"this point, {p.symbol or p.name} = {p.show(x0)}")
        ax.axvline(x0 * scale, **POINT)
        if log:
            ax.set_xscale("log")
        every = np.array(every)
        if len(group) == 1 and len(every) and np.ptp(every) <= 1e-9 * max(np.max(np.abs(every)), 1e-300):
            # a constant: round-off in the numeric markers must not fill the axis
            c0 = float(every[0])
            half = abs(c0) * 0.05 if c0 != 0 else 1.0
            ax.set_ylim(c0 - half, c0 + half)
        elif len(every) and np.all(every > 0) and every.max() / every.min() > 300:
            ax.set_yscale("log")
        unit = group[0].unit
        ylabel = label(group[0].name + (" *" if group[0].theory != "exact" else ""), unit) if len(group) == 1 \
            else ("[" + unit + "]" if unit not in ("1", "") else "dimensionless")
        ax.set_xlabel(label(f"{p.symbol or p.name}", p.display or p.unit), fontsize=FONT["label"])
        ax.set_ylabel(ylabel, fontsize=FONT["label"])
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=FONT["tick"])
        if len(group) > 1 or j == next(i for i, g in enumerate(groups) if len(g) == 1):
            ax.legend(fontsize=FONT["legend"], framealpha=0.85, ncol=2 if len(group) > 4 else 1)
    for j in range(k, nrows * ncols):
        axes[j // ncols][j % ncols].set_visible(False)
    extra = ""
    if any(o.theory != "exact" for o in ex.outputs):
        extra = "* leading-order analytic theory"
    if any(len(g) > 1 for g in groups):
        extra += ("; " if extra else "") + "lines analytic, circles numeric"
    if failures:
        extra += ("; " if extra else "") + f"numeric failed at {len(failures)} of {len(num_p)} points"
    title(fig, ex, params, skip=(name,), extra=extra)
    return fig
