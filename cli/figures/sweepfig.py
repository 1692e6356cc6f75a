"""``mech sweep --plot``: each output against the first swept parameter; other swept parameters as separate curves."""

from __future__ import annotations

import math

import numpy as np

from mech.cli.figures.common import ANALYTIC, NUMERIC, figure, finite, label, title

MAX_CURVES = 8


def sweep_figure(result):
    ex = result.exercise
    first = result.axes[0]
    others = result.axes[1:]
    p = ex.param_map[first.name]
    scale = p.to_display(1.0)
    # group the points by the values of the other axes (grid order: the first axis varies slowest)
    groups: dict[tuple, list[dict]] = {}
    for pt in result.points:
        key = tuple(pt["params"][a.name] for a in others)
        groups.setdefault(key, []).append(pt)
    keys = list(groups)
    if len(keys) > MAX_CURVES:
        keys = [keys[i] for i in np.linspace(0, len(keys) - 1, MAX_CURVES).round().astype(int)]
    k = len(ex.outputs)
    ncols = 1 if k == 1 else 2 if k in (2, 4) else 3
    nrows = math.ceil(k / ncols)
    fig, axes = figure(nrows, ncols, w=4.0, h=2.9)
    for j, o in enumerate(ex.outputs):
        ax = axes[j // ncols][j % ncols]
        for c, key in enumerate(keys):
            pts = groups[key]
            x = np.array([pt["params"][first.name] for pt in pts]) * scale
            qa = np.array([finite(pt["quantities"][j]["analytic"]) for pt in pts])
            qn = np.array([finite(pt["quantities"][j]["numeric"]) for pt in pts])
            bad = np.array([pt["quantities"][j]["agree"] is False for pt in pts])
            tag = ", ".join(f"{a.name} = {ex.param_map[a.name].show(v)}" for a, v in zip(others, key))
            color = f"C{c % 10}" if others else ANALYTIC["color"]
            ax.plot(x, qa, color=color, lw=1.5, label=("analytic" + (f" ({tag})" if tag else "")) if j == 0 else None)
            ax.plot(x, qn, **{**NUMERIC, "color": NUMERIC["color"] if not others else color,
                              "label": "numeric" if (j == 0 and c == 0) else None})
            if bad.any():
                ax.plot(x[bad], qn[bad], "x", color="k", ms=8, label="disagree" if j == 0 else None)
        if first.log:
            ax.set_xscale("log")
        ax.set_xlabel(label(p.symbol or p.name, p.display or p.unit))
        ax.set_ylabel(label(o.name, o.unit) + (" *" if o.theory != "exact" else ""), fontsize=9)
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=8)
        if j == 0:
            ax.legend(fontsize=7, frameon=False)
    for j in range(k, nrows * ncols):
        axes[j // ncols][j % ncols].set_visible(False)
    title(fig, ex, result.points[0]["params"], skip=tuple(a.name for a in result.axes),
          extra=f"sweep of {len(result.points)} points")
    return fig
