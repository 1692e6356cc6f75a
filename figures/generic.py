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

from mech.figures.common import (ANALYTIC, FONT, NUMERIC, POINT, analytic_values, figure, label,
                                     defer_legend, plain_log_ticks, title)
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


ROUND_OFF = 1e3 * 2.220446049250313e-16  # relative to an output's scale: below it a value is round-off of 0
COINCIDE = 1e-9  # two outputs whose values agree to this (relative) draw one on the other
HOURS_FROM_S = 2 * 3600.0  # a time whose typical value exceeds this is drawn in hours


def _zero_round_off(ys: np.ndarray, scale: float) -> np.ndarray:
    """Values below the round-off of the output's scale are zero (cos 90 deg = 6e-17, not data)."""
    ys = np.array(ys, float)
    tiny = np.isfinite(ys) & (np.abs(ys) <= ROUND_OFF * scale)
    ys[tiny] = 0.0
    return ys


def _power_law_slope(xs: np.ndarray, ys: np.ndarray) -> float | None:
    """The exponent where ys is one power of xs (constant log-log slope), else None."""
    ok = np.isfinite(ys) & (xs > 0)
    if ok.sum() < 3:
        return None
    x, y = xs[ok], ys[ok]
    y = -y if np.all(y < 0) else y
    if not np.all(y > 0):
        return None
    sl = np.diff(np.log(y)) / np.diff(np.log(x))
    return float(np.mean(sl)) if np.ptp(sl) < 0.02 else None


def _skewed(values: np.ndarray) -> bool:
    """Positive values whose bulk sits at the bottom of a range wider than x5 (a divergence drawn as a spike):
    a log axis reads them; a linear one shows a flat line and a spike."""
    lo, hi, mid = values.min(), values.max(), float(np.median(values))
    return hi / lo > 5 and (mid - lo) / (hi - lo) < 0.1


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


def _panel_values(group, rows, num_rows, at_point, has_numeric):
    """Each output's values on the line, at the numeric points and at the point itself, round-off of zero
    set to zero; the panel's unit and its factor from SI (hours where a time runs to days)."""
    lines = {}
    for o in group:
        ys = np.array([r[o.name] for r in rows], float)
        ny = np.array([r[o.name] for r in num_rows], float) if has_numeric else np.array([])
        y0 = at_point.get(o.name, math.nan)
        fin = ys[np.isfinite(ys)]
        ref = float(np.max(np.abs(fin))) if fin.size else 0.0
        ys, ny = _zero_round_off(ys, ref), _zero_round_off(ny, ref)
        y0 = float(_zero_round_off(np.array([y0]), ref)[0])
        lines[o.name] = (ys, ny, y0)
    unit = group[0].unit
    shown = np.concatenate([np.abs(v[0][np.isfinite(v[0])]) for v in lines.values()] + [np.zeros(0)])
    factor = 1.0
    if unit == "s" and shown.size and float(np.median(shown)) > HOURS_FROM_S:
        unit, factor = "h", 1.0 / 3600.0
    return lines, unit, factor


def _panel_scales(ax, xs, lines, every, log, n_outputs):
    """Log or linear axes for a panel: a power law on log-log axes, a proportional one on linear axes, a
    constant's round-off kept from filling the axis."""
    slopes = [_power_law_slope(xs, v[0]) for v in lines.values()]
    power_laws = log and all(s is not None for s in slopes)
    proportional = power_laws and all(abs(s - 1.0) < 0.02 for s in slopes)
    log_x = log and not proportional  # proportional to the parameter: a straight line on linear axes
    if log_x:
        ax.set_xscale("log")
    if n_outputs == 1 and len(every) and np.ptp(every) <= 1e-9 * max(np.max(np.abs(every)), 1e-300):
        # a constant: round-off in the numeric markers must not fill the axis
        c0 = float(every[0])
        half = abs(c0) * 0.05 if c0 != 0 else 1.0
        ax.set_ylim(c0 - half, c0 + half)
    elif not proportional and len(every) and np.all(every > 0) and (
            every.max() / every.min() > 300 or _skewed(every)
            or (power_laws and log_x and every.max() / every.min() > 3)):
        ax.set_yscale("log")  # a power law on log-log axes is a straight line
    for axis, scale_name in ((ax.xaxis, ax.get_xscale()), (ax.yaxis, ax.get_yscale())):
        if scale_name == "log":
            plain_log_ticks(axis)


def _caption(ex, groups, coincident_notes, failures, n_points):
    """The figure's note: leading-order theory, lines and circles, coincident outputs, numeric failures."""
    extra = ""
    if any(o.theory != "exact" for o in ex.outputs):
        extra = "* leading-order analytic theory"
    if any(len(g) > 1 for g in groups):
        extra += ("; " if extra else "") + "lines analytic, circles numeric"
    if coincident_notes:
        extra += ("; " if extra else "") + "coincide (dashed over): " + ", ".join(coincident_notes)
    if failures:
        extra += ("; " if extra else "") + f"numeric failed at {len(failures)} of {n_points} points"
    return extra


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
    legends = []
    coincident_notes = []
    for j, group in enumerate(groups):
        ax = axes[j // ncols][j % ncols]
        every = []
        lines, unit, factor = _panel_values(group, rows, num_rows, at_point, has_numeric)
        drawn: list[tuple[str, np.ndarray]] = []
        for c, o in enumerate(group):
            color = f"C{c % 10}"
            tag = o.name + (" *" if o.theory != "exact" else "")
            ys, ny, y0 = (v * factor for v in lines[o.name])
            # an output that lies exactly on one drawn before it is dashed over it, its markers squares,
            # and the legend says so: otherwise it would be invisible
            twin = next((name for name, other in drawn if other.shape == ys.shape and np.all(
                np.isfinite(ys) == np.isfinite(other)) and np.allclose(ys, other, rtol=COINCIDE, atol=0.0,
                                                                       equal_nan=True)), None)
            drawn.append((o.name, ys))
            style, marker = {}, {}
            if twin is not None:
                tag += f" (= {twin}, dashed)"
                style = dict(ls=(0, (4, 3)), lw=2.4)
                marker = dict(marker="s", ms=7)
                coincident_notes.append(f"{o.name} = {twin}")
            every.extend(ys[np.isfinite(ys)])
            if "analytic" in ex.methods:
                ax.plot(xs * scale, ys, **{**ANALYTIC, "color": color, **style,
                                           "label": tag if len(group) > 1 else "analytic"})
            if has_numeric:
                every.extend(ny[np.isfinite(ny)])
                ax.plot(np.array(num_x) * scale, ny, **{**NUMERIC, "color": color if len(group) > 1 else NUMERIC["color"],
                                                        **marker, "label": "numeric" if len(group) == 1 else None})
            if math.isfinite(y0):
                ax.plot([x0 * scale], [y0], marker="*", color="k", ms=10, ls="none", zorder=5)
        ax.plot([], [], marker="*", color="k", ms=10, ls="none", label=f"this point, {p.symbol or p.name} = {p.show(x0)}")
        ax.axvline(x0 * scale, **POINT)
        _panel_scales(ax, xs, lines, np.array(every), log, len(group))
        ylabel = label(group[0].name + (" *" if group[0].theory != "exact" else ""), unit) if len(group) == 1 \
            else ("[" + unit + "]" if unit not in ("1", "") else "dimensionless")
        ax.set_xlabel(label(f"{p.symbol or p.name}", p.display or p.unit), fontsize=FONT["label"])
        ax.set_ylabel(ylabel, fontsize=FONT["label"])
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=FONT["tick"])
        if len(group) > 1 or j == next(i for i, g in enumerate(groups) if len(g) == 1):
            legends.append((ax, dict(fontsize=FONT["legend"], framealpha=0.85, ncol=2 if len(group) > 4 else 1)))
    for j in range(k, nrows * ncols):
        axes[j // ncols][j % ncols].set_visible(False)
    extra = _caption(ex, groups, coincident_notes, failures, len(num_p))
    title(fig, ex, params, skip=(name,), extra=extra)
    for ax, kw in legends:
        defer_legend(ax, None, **kw)
    return fig
