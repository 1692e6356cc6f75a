"""Draws an exercise's Scene (mech.problems.scene): panels of curves, markers, bands, maps, guides.

Nothing here knows any physics: the exercise computed every number; this only
chooses how each kind of item looks.
"""

from __future__ import annotations

import math

import numpy as np

from mech.figures.common import FONT, figure, label, title
from mech.problems.scene import Band, Guide, Line, Map, Markers, Note

LINE_STYLE = {
    "analytic": dict(color="C0", lw=1.8),
    "reference": dict(color="C1", lw=1.2, ls="--"),
    "trajectory": dict(color="C3", lw=1.8),
    "drawing": dict(color="0.55", lw=1.3),
    "level": dict(color="0.6", lw=0.6),
}
MARKER_STYLE = {
    "numeric": dict(color="C3", marker="o", ms=9, ls="none", mfc="none", mew=1.6),
    "analytic": dict(color="k", marker="*", ms=11, ls="none"),
    "this": dict(color="k", marker="*", ms=11, ls="none"),
    "failure": dict(color="0.35", marker="x", ms=7, ls="none", mew=1.5),
}


def _line(ax, it: Line):
    style = dict(LINE_STYLE.get(it.kind, LINE_STYLE["analytic"]))
    if it.color:
        style["color"] = it.color
    if it.dashed:
        style["ls"] = "--"
    if it.width:
        style["lw"] = it.width
    if it.kind == "drawing":
        style["solid_capstyle"] = "round"
    ax.plot(np.asarray(it.x, float), np.asarray(it.y, float), label=it.label, **style)


def _markers(ax, it: Markers):
    x, y = np.atleast_1d(np.asarray(it.x, float)), np.atleast_1d(np.asarray(it.y, float))
    if it.kind == "failure" and len(x) and not np.all(np.isfinite(y)):
        lo, hi = ax.get_ylim()
        y = np.where(np.isfinite(y), y, lo + 0.04 * (hi - lo))
    style = dict(MARKER_STYLE.get(it.kind, MARKER_STYLE["numeric"]))
    if it.color:
        style["color"] = it.color
    if it.size:
        style["ms"] = it.size
    if len(x) == 0 or not np.any(np.isfinite(y)):
        return
    ax.plot(x, y, label=it.label, zorder=5, **style)


def _band(ax, it: Band):
    x, lo, hi = (np.asarray(v, float) for v in (it.x, it.lo, it.hi))
    ok = np.isfinite(x) & np.isfinite(lo) & np.isfinite(hi)
    fill = ax.fill_betweenx if it.vertical else ax.fill_between
    fill(x[ok], lo[ok], hi[ok], color=it.color or "C3", alpha=0.22, lw=0, label=it.label)


def _map(fig, ax, it: Map):
    z = np.asarray(it.z, float)
    lo, hi = it.clip if it.clip else (np.nanmin(z), np.nanmax(z))
    z = np.clip(z, lo, hi)
    levels = np.linspace(lo, hi, it.levels)
    cs = ax.contourf(it.x, it.y, z, levels=levels, cmap="viridis")
    ax.contour(it.x, it.y, z, levels=levels, colors="w", linewidths=0.3, alpha=0.6)
    bar = fig.colorbar(cs, ax=ax, shrink=0.9, format="%.3g")
    bar.set_label(label(it.label, it.unit), fontsize=FONT["label"])
    bar.ax.tick_params(labelsize=FONT["tick"])


def _guide(ax, it: Guide):
    style = dict(color=it.color or "k", lw=0.9, ls=":" if it.dashed else "-", alpha=0.8)
    (ax.axvline if it.axis == "x" else ax.axhline)(it.value, label=it.label, **style)


def _note(ax, it: Note):
    kw = dict(fontsize=FONT["note"], color=it.color or "k")
    if it.text_at is None:
        ax.annotate(it.text, it.xy, xytext=(4, 5), textcoords="offset points", **kw)
    else:
        ax.annotate(it.text, it.xy, xytext=it.text_at, textcoords="axes fraction",
                    arrowprops=dict(arrowstyle="->", lw=0.8, color=kw["color"]), **kw)


def _axis(ax, panel):
    for which, a in (("x", panel.x), ("y", panel.y)):
        getattr(ax, f"set_{which}label")(label(a.label, a.unit), fontsize=FONT["label"])
        if a.log:
            getattr(ax, f"set_{which}scale")("log")
            _plain_log_ticks(getattr(ax, f"{which}axis"))
        if a.lim:
            getattr(ax, f"set_{which}lim")(*a.lim)


def _plain_log_ticks(axis):
    """Tick labels of a log axis as plain numbers (2, 3, 0.05), not 2×10⁰, where the axis spans
    less than three decades; wider axes keep matplotlib's powers of ten."""
    from matplotlib.ticker import FuncFormatter, LogLocator

    def plain(v, _pos):
        if v <= 0 or not math.isfinite(v):
            return ""
        return f"{v:g}"

    lo, hi = axis.get_view_interval()
    if lo > 0 and hi / lo < 1e3:
        axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        axis.set_major_formatter(FuncFormatter(plain))
        axis.set_minor_formatter(FuncFormatter(lambda v, p: ""))


def draw_scene(ex, params, scene, run):
    n = len(scene.panels)
    fig, axes = figure(1, n, w=5.2 if n > 1 else 6.4, h=4.3)
    for k, panel in enumerate(scene.panels):
        ax = axes[0][k]
        for it in panel.items:
            if isinstance(it, Map):
                _map(fig, ax, it)
            elif isinstance(it, Band):
                _band(ax, it)
        for it in panel.items:
            if isinstance(it, Line):
                _line(ax, it)
            elif isinstance(it, Guide):
                _guide(ax, it)
        _axis(ax, panel)
        for it in panel.items:
            if isinstance(it, Markers):
                _markers(ax, it)
            elif isinstance(it, Note):
                _note(ax, it)
        _axis(ax, panel)  # the ticks again, now that the data have set the view
        if panel.equal_aspect:
            ax.set_aspect("equal")
        if not panel.ticks:
            ax.set_xticks([])
            ax.set_yticks([])
        elif not any(isinstance(i, Map) for i in panel.items):
            ax.grid(alpha=0.3, which="major")
        ax.tick_params(labelsize=FONT["tick"])
        ax.set_title(panel.title, fontsize=FONT["title"])
        handles, _ = ax.get_legend_handles_labels()
        if handles and panel.legend != "none":
            if panel.legend == "outside":
                ax.legend(fontsize=FONT["legend"], frameon=False, loc="upper center",
                          bbox_to_anchor=(0.5, -0.16), ncol=2)
            else:
                ax.legend(fontsize=FONT["legend"], framealpha=0.85, loc=panel.legend)
    extra = scene.caption
    if run is not None and run.failures:
        told = f"the numeric solver failed at {len(run.failures)} point(s) (no marker there): {run.failures[0][1]}"
        extra = (extra + "\n" if extra else "") + (told if len(told) < 200 else told[:197] + "...")
    title(fig, ex, params, skip=tuple(scene.on_axis), extra=extra)
    return fig
