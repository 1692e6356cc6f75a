"""``mech sweep --plot``: outputs against one swept parameter, or maps over two.

One swept parameter (or more than two): each output against the first, the
others as separate curves.  Two: a map per output, the numeric value coloured
over the grid with a colorbar in the output's unit; where the output changes
sign its exact zero (the numeric one) is a solid line; the leading-order
boundary the exercise declares is a dashed line; points with no value are
grey; failed points are crossed and their reason is in the legend; points
the exercise refused (a joint limit: not solved) are dotted lines on a curve,
plus signs on a map, their reason in the legend.  No physics
here: the values and the boundary come from the sweep.
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np

from mech.figures.common import ANALYTIC, NUMERIC, figure, finite, label, title

MAX_CURVES = 8
COARSE = 20  # a map with fewer points than this along an axis is drawn smooth between its points


def _shown(result, name):
    for a in result.axes:
        if a.name == name and a.unit:
            return a.unit, a.factor
    p = result.exercise.param_map[name]
    return (p.display, 1.0 / p.to_display(1.0)) if p.display else (p.unit, 1.0)


def sweep_figure(result):
    if len(result.axes) == 2:
        return map_figure(result)
    return curve_figure(result)


def curve_figure(result):
    from mech.studies.sweep import refusal_label

    ex = result.exercise
    first = result.axes[0]
    others = result.axes[1:]
    p = ex.param_map[first.name]
    unit, factor = _shown(result, first.name)
    names = result.output_names
    outs = [o for o in ex.outputs if o.name in names]
    # group the points by the values of the other axes (grid order: the first axis varies slowest)
    groups: dict[tuple, list[dict]] = {}
    for pt in result.point_list():
        key = tuple(pt["params"][a.name] for a in others)
        groups.setdefault(key, []).append(pt)
    keys = list(groups)
    if len(keys) > MAX_CURVES:
        keys = [keys[i] for i in np.linspace(0, len(keys) - 1, MAX_CURVES).round().astype(int)]
    k = len(outs)
    ncols = 1 if k == 1 else 2 if k in (2, 4) else 3
    nrows = math.ceil(k / ncols)
    fig, axes = figure(nrows, ncols, w=4.0, h=2.9)
    for j, o in enumerate(outs):
        ax = axes[j // ncols][j % ncols]
        for c, key in enumerate(keys):
            pts = groups[key]
            x = np.array([pt["params"][first.name] for pt in pts]) / factor
            qs = [next(q for q in pt["quantities"] if q["name"] == o.name) for pt in pts]
            qa = np.array([finite(q["analytic"]) for q in qs])
            qn = np.array([finite(q["numeric"]) for q in qs])
            bad = np.array([q["agree"] is False for q in qs])
            tag = ", ".join(f"{a.name} = {ex.param_map[a.name].show(v)}" for a, v in zip(others, key))
            color = f"C{c % 10}" if others else ANALYTIC["color"]
            ax.plot(x, qa, color=color, lw=1.5, label=("analytic" + (f" ({tag})" if tag else "")) if j == 0 else None)
            ax.plot(x, qn, **{**NUMERIC, "color": NUMERIC["color"] if not others else color,
                              "label": "numeric" if (j == 0 and c == 0) else None})
            if bad.any():
                ax.plot(x[bad], qn[bad], "x", color="k", ms=8, label="disagree" if j == 0 else None)
            refused = [pt["refused"] for pt in pts if pt.get("refused")]
            for n, xr in enumerate(x[[bool(pt.get("refused")) for pt in pts]]):
                ax.axvline(xr, color="0.55", ls=":", lw=1.0,
                           label=refusal_label(refused) if (j == 0 and c == 0 and n == 0) else None)
        if first.log:
            ax.set_xscale("log")
        ax.set_xlabel(label(p.symbol or p.name, unit))
        ax.set_ylabel(label(o.name, o.unit) + (" *" if o.theory != "exact" else ""), fontsize=9)
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=8)
        if j == 0:
            ax.legend(fontsize=7, frameon=False)
    for j in range(k, nrows * ncols):
        axes[j // ncols][j % ncols].set_visible(False)
    title(fig, ex, result.point_list()[0]["params"], skip=tuple(a.name for a in result.axes),
          extra=f"sweep of {len(result)} points")
    return fig


def _edges(v, log):
    """Cell edges around grid values (geometric midpoints on a log axis)."""
    v = np.asarray(v, dtype=float)
    if v.size == 1:
        return np.array([v[0] * 0.99, v[0] * 1.01]) if v[0] else np.array([-0.5, 0.5])
    if log:
        lv = np.log(v)
        mid = 0.5 * (lv[1:] + lv[:-1])
        return np.exp(np.concatenate([[2 * lv[0] - mid[0]], mid, [2 * lv[-1] - mid[-1]]]))
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def _colour_scale(Z):
    """(colour map, norm): diverging about 0 where the values change sign, else viridis; grey for no value."""
    import matplotlib
    import matplotlib.colors as mcolors

    finite_z = Z[np.isfinite(Z)]
    norm = None
    if finite_z.size and finite_z.min() < 0 < finite_z.max():
        cmap = matplotlib.colormaps["RdBu_r"]
        norm = mcolors.TwoSlopeNorm(vmin=finite_z.min(), vcenter=0.0, vmax=finite_z.max())
    else:
        cmap = matplotlib.colormaps["viridis"]
    return cmap.with_extremes(bad="0.82"), norm


def _overlays(ax, result, o, arr, Z, x, y, fx, fy, curves, y_name, diverging):
    """What is drawn over a map (zero and grey-region contours, the boundary curves, the failed points) and
    its legend's handles."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from mech.studies.sweep import failure_kind, refusal_label

    handles = []
    refused = arr["refused"]
    refused_map = refused.reshape(x.size, y.size).T  # as Z: rows y, columns x
    if x.size > 1 and y.size > 1:
        if diverging:
            ax.contour(x, y, Z, levels=[0.0], colors="k", linewidths=1.3)
            handles.append(Line2D([], [], color="k", lw=1.3, label=f"{o.name} = 0 (numeric, exact)"))
        undefined = ~np.isfinite(Z) & ~refused_map
        if undefined.any() and not undefined.all():
            ax.contour(x, y, undefined.astype(float), levels=[0.5], colors="k", linewidths=1.3)
            handles.append(Line2D([], [], color="k", lw=1.3, label="edge of the grey region (numeric, exact)"))
    if (np.isnan(Z) & ~refused_map).any():
        handles.append(Patch(facecolor="0.82", edgecolor="none", label=_grey_label(result, o.name)))
    for axis_name, xs, ys, text in curves:
        if axis_name == y_name:
            ax.plot(xs / fx, ys / fy, color="k", ls="--", lw=1.5)
        else:
            ax.plot(ys / fx, xs / fy, color="k", ls="--", lw=1.5)
        handles.append(Line2D([], [], color="k", ls="--", lw=1.5, label=text))
    if refused.any():
        X, Y = np.meshgrid(x, y, indexing="ij")
        ax.plot(X.ravel()[refused], Y.ravel()[refused], "+", color="0.3", ms=4, mew=1.0)
        handles.append(Line2D([], [], color="0.3", marker="+", ls="none",
                              label=refusal_label(arr["refused_reasons"][refused])))
    bad = arr["failed"]
    if bad.any():
        X, Y = np.meshgrid(x, y, indexing="ij")
        kinds = Counter(failure_kind(r) for r in arr["reasons"][bad])
        ax.plot(X.ravel()[bad], Y.ravel()[bad], "x", color="m", ms=4, mew=1.0)
        for kind, count in kinds.most_common(3):
            handles.append(Line2D([], [], color="m", marker="x", ls="none",
                                  label=f"FAILED ({count} points): {kind}"))
        if len(kinds) > 3:
            handles.append(Line2D([], [], color="m", marker="x", ls="none",
                                  label=f"FAILED: {len(kinds) - 3} other reasons (see --json)"))
    return handles


def map_figure(result):
    from mech.studies.sweep import boundary_curves, output_arrays

    ex = result.exercise
    ax_x, ax_y = result.axes
    px, py = ex.param_map[ax_x.name], ex.param_map[ax_y.name]
    ux, fx = _shown(result, ax_x.name)
    uy, fy = _shown(result, ax_y.name)
    x = np.asarray(ax_x.values) / fx
    y = np.asarray(ax_y.values) / fy
    shape = (x.size, y.size)
    names = result.output_names
    outs = [o for o in ex.outputs if o.name in names]
    k = len(outs)
    ncols = 1 if k == 1 else 2
    nrows = math.ceil(k / ncols)
    fig, axes = figure(nrows, ncols, w=6.4 if k == 1 else 5.0, h=5.6 if k == 1 else 4.6)
    curves = boundary_curves(result)
    coarse = min(x.size, y.size) < COARSE and x.size > 1 and y.size > 1
    any_smooth = False
    for j, o in enumerate(outs):
        ax = axes[j // ncols][j % ncols]
        arr = output_arrays(result, o.name)
        Z = arr["numeric"].reshape(shape).T  # rows: y, columns: x
        cmap, norm = _colour_scale(Z)
        smooth = coarse and bool(np.all(np.isfinite(Z)))
        if smooth:
            # a coarse grid as flat cells is a mosaic of blocks: colour linearly between the computed points
            # (dotted) instead; the map then spans the grid's own range
            mesh = ax.pcolormesh(x, y, Z, cmap=cmap, norm=norm, shading="gouraud", rasterized=True)
            X, Y = np.meshgrid(x, y)
            ax.plot(X.ravel(), Y.ravel(), ls="none", marker="o", ms=2.5, mfc="w", mec="k", mew=0.5, clip_on=False)
        else:
            mesh = ax.pcolormesh(_edges(x, ax_x.log), _edges(y, ax_y.log), np.ma.masked_invalid(Z), cmap=cmap,
                                 norm=norm, shading="flat", rasterized=True)
        any_smooth |= smooth
        cb = fig.colorbar(mesh, ax=ax, shrink=0.92, pad=0.02)
        if norm is not None:  # both ends labelled: the scale is not the same on both sides of zero
            from matplotlib.ticker import MaxNLocator

            up = [t for t in MaxNLocator(6).tick_values(0.0, norm.vmax) if 0.0 <= t <= norm.vmax]
            down = [t for t in MaxNLocator(3).tick_values(norm.vmin, 0.0) if norm.vmin <= t < 0.0]
            cb.set_ticks(sorted(set(down + up + [norm.vmin])))
        cb.set_label(label(f"{o.name} (numeric)", o.unit), fontsize=9)
        cb.ax.tick_params(labelsize=8)
        handles = _overlays(ax, result, o, arr, Z, x, y, fx, fy, curves, ax_y.name, norm is not None)
        if smooth:
            ax.set_xlim(x[0], x[-1])
            ax.set_ylim(y[0], y[-1])
        else:
            ax.set_xlim(_edges(x, ax_x.log)[[0, -1]])
            ax.set_ylim(_edges(y, ax_y.log)[[0, -1]])
        if ax_x.log:
            ax.set_xscale("log")
        if ax_y.log:
            ax.set_yscale("log")
        ax.set_xlabel(label(px.symbol or px.name, ux))
        ax.set_ylabel(label(py.symbol or py.name, uy))
        ax.tick_params(labelsize=8)
        if handles:  # under the map, where it hides nothing
            ax.legend(handles=handles, fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.13),
                      ncol=1 if k == 1 else 1, frameon=False)
    for j in range(k, nrows * ncols):
        axes[j // ncols][j % ncols].set_visible(False)
    n = len(result)
    n_bad = int(output_arrays(result, outs[0].name)["failed"].sum()) if outs else 0
    verdict = "every point verified and agreeing" if n_bad == 0 else f"{n_bad} points FAILED (crossed)"
    if result.refused:
        verdict = verdict.replace("every point", "every point solved") + f"; {len(result.refused)} refused (+)"
    if any_smooth:
        verdict += "; coarse grid: colours interpolated linearly between the computed points (dots)"
    elif coarse:
        verdict += "; coarse grid: each cell shows the value at its centre point"
    title(fig, ex, {**{p.name: p.default for p in ex.params}, **result.fixed},
          skip=tuple(a.name for a in result.axes),
          extra=f"map of {ax_x.values.__len__()} x {len(ax_y.values)} points; {verdict}")
    return fig


def _grey_label(result, name):
    """What a grey cell means: the numeric method's reason for having no value there."""
    if result.points is None:
        J = result.batched.judged[name]
        reasons = [why for _, why in J["num"].undefined]
        if reasons:
            return f"no value: {reasons[0]}"
        return "no value (failed)"
    for pt in result.points:
        for q in pt["quantities"]:
            if q["name"] == name and q["numeric"] is None and q.get("note"):
                return "no value: " + q["note"].split(";")[0].replace("numeric: ", "")
    return "no value"
