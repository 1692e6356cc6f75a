"""What every figure shares: matplotlib on demand (Agg), the output file's format, the house style."""

from __future__ import annotations

import math
import os

FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}
# the install command as it works today, from a checkout (on the package index the name "mech" is somebody
# else's project; this one is published as mech-likharev)
INSTALL = "pip install -e '.[plot]' in mech's checkout"
# the house style: sizes that stay readable when a figure is shown at half its width
FONT = dict(title=10, label=10, tick=9, legend=8.5, note=9, suptitle=11)

ANALYTIC = dict(color="C0", lw=1.8, label="analytic")
NUMERIC = dict(color="C3", marker="o", ms=5, ls="none", mfc="none", mew=1.4, label="numeric")
POINT = dict(color="k", lw=0.8, ls=":", alpha=0.7)


def _usage(msg: str):
    from mech.core.errors import BadUsage

    return BadUsage(msg)


def need_matplotlib():
    """matplotlib.pyplot with the non-interactive Agg backend; exit 2 with the install command without it."""
    try:
        import matplotlib
    except ImportError:
        raise _usage(f"plotting needs matplotlib, which is not installed: {INSTALL}") from None
    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def check_target(path: str) -> str:
    """The format of the output file, from its suffix; exit 2 for anything else or an unwritable place."""
    from mech.core.errors import BadInput
    from mech.core.safeio import check_output, shown

    ext = os.path.splitext(str(path))[1].lower()
    if ext not in FORMATS:
        raise _usage(f"cannot write '{shown(path)}': the file's suffix chooses the format, one of .png, .svg, .pdf")
    try:
        check_output(path, "--plot")
    except BadInput as exc:
        raise _usage(str(exc)) from None
    return FORMATS[ext]


def save(fig, path: str, dpi: float = 110) -> None:
    import matplotlib.pyplot as plt

    from mech.core.errors import BadInput
    from mech.core.safeio import atomic_write

    fmt = check_target(path)
    meta = {"Software": "mech"} if fmt == "png" else None
    try:
        # laid out at the resolution it is written at: the legends are placed on that layout, and when
        # placing them left every axis as it was, the layout is final and savefig need not run it again
        # (the layout passes were 2/3 of a figure's time)
        fig.set_dpi(dpi)
        if finish_legends(fig, final=True):
            # no engine at all where the rc file asks for none (None would bring its engine back): with an
            # engine, even "none", savefig draws the figure once more, without rendering, before the file
            rc_engine = plt.rcParams["figure.autolayout"] or plt.rcParams["figure.constrained_layout.use"]
            fig.set_layout_engine("none" if rc_engine else None)
        with atomic_write(path, "--plot", mode="wb") as fh:
            fig.savefig(fh, format=fmt, dpi=dpi, metadata=meta)
    except BadInput as exc:
        raise _usage(str(exc)) from None
    finally:
        plt.close(fig)


def figure(nrows=1, ncols=1, w=4.6, h=3.3, **kw):
    plt = need_matplotlib()
    fig, axes = plt.subplots(nrows, ncols, figsize=(w * ncols, h * nrows), squeeze=False, layout="constrained", **kw)
    return fig, axes


def title(fig, ex, params=None, skip=(), extra: str = "") -> None:
    """The exercise as the figure's title; the parameters held at their values underneath; every line
    wrapped to the figure's width (a character of the title font is about 0.6 of its size wide)."""
    import textwrap

    fit = max(40, min(110, int(fig.get_figwidth() * 72 / (FONT["suptitle"] * 0.6))))
    text = "\n".join(textwrap.wrap(f"{ex.id}  {ex.title}", fit))
    if params is not None:
        shown = [f"{p.symbol or p.name} = {p.show(params[p.name])}" for p in ex.params if p.name not in skip]
        line = ", ".join(shown)
        text += "\n" + textwrap.fill(line, fit)
    if extra:
        text += "\n" + "\n".join(textwrap.fill(line, fit) for line in extra.splitlines())
    fig.suptitle(text, fontsize=FONT["suptitle"])


def plain_log_ticks(axis):
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


def label(name: str, unit: str) -> str:
    return name if unit in ("1", "") else f"{name} [{unit}]"


def finite(v) -> float:
    """A solver's value as a float, NaN for an Undefined or a failure (matplotlib leaves a gap)."""
    try:
        f = float(v)
    except (TypeError, ValueError):
        return math.nan
    return f if math.isfinite(f) else math.nan


def analytic_values(ex, params):
    try:
        values = ex.solve_analytic(params)
    except Exception:
        return {o.name: math.nan for o in ex.outputs}
    return {k: finite(v) for k, v in values.items()}


# -- legends placed where they hide nothing ------------------------------------------------------------

LEGEND_LOCS = ("upper right", "upper left", "lower left", "lower right", "center right", "center left",
               "lower center", "upper center", "center")


def drawn_points(ax, step_px: float = 2.0):
    """Display coordinates of what a legend in ``ax`` could hide: every data line's vertices and points
    every ``step_px`` pixels along its segments (a line crossing a box counts, not only its vertices),
    markers, and the boxes of annotations.  Reference lines spanning the axes (axvline, axhline) are
    left out: a legend may sit over a stretch of them."""
    import numpy as np

    pts = []
    for ln in ax.get_lines():
        if not ln.get_visible() or ln.get_transform() is not ax.transData:
            continue
        xy = np.asarray(ln.get_xydata(), float)
        if xy.size == 0:
            continue
        disp = ln.get_transform().transform(xy)
        ok = np.all(np.isfinite(disp), axis=1)
        pts.append(disp[ok])
        if ln.get_linestyle() not in ("None", "none", "", " ") and len(disp) > 1:
            a, b = disp[:-1], disp[1:]
            both = ok[:-1] & ok[1:]
            a, b = a[both], b[both]
            n = np.minimum(np.linalg.norm(b - a, axis=1) // step_px, 2000).astype(int)
            long = n > 1  # segments longer than a step get points along them
            if long.any():
                reps = n[long]
                t = np.concatenate([np.arange(k) / k for k in reps])[:, None]
                pts.append(np.repeat(a[long], reps, axis=0) + t * np.repeat((b - a)[long], reps, axis=0))
    renderer = ax.figure.canvas.get_renderer()
    for text in ax.texts:
        bb = text.get_window_extent(renderer)
        gx, gy = np.meshgrid(np.linspace(bb.x0, bb.x1, 12), np.linspace(bb.y0, bb.y1, 4))
        pts.append(np.column_stack([gx.ravel(), gy.ravel()]))
    return np.vstack(pts) if pts else np.zeros((0, 2))


def hidden_by(legend, points, pad_px: float = 1.0) -> int:
    """How many of ``points`` (display coordinates) the legend's box covers."""
    bb = legend.get_window_extent(legend.figure.canvas.get_renderer()).padded(pad_px)
    if len(points) == 0:
        return 0
    x, y = points[:, 0], points[:, 1]
    return int(((x >= bb.x0) & (x <= bb.x1) & (y >= bb.y0) & (y <= bb.y1)).sum())


def defer_legend(ax, preferred: str | None = None, **kw) -> None:
    """Ask for a legend in ``ax`` placed by ``finish_legends`` once the figure is complete."""
    fig = ax.figure
    if not hasattr(fig, "_mech_legends"):
        fig._mech_legends = []
    fig._mech_legends.append((ax, preferred, kw))


def finish_legends(fig, final: bool = False):
    """Lay the figure out once and place every deferred legend where it hides no data (``save`` calls
    this; so does ``figures.draw`` unless told not to). Returns the figure; with ``final``, whether the
    layout it ran still holds (no legend had to make room by moving an axis's limits)."""
    pending = getattr(fig, "_mech_legends", None)
    held = False
    if pending:
        fig._mech_legends = []
        engine = fig.get_layout_engine()
        if engine is not None:
            engine.execute(fig)  # the axes where they will be saved (a full draw costs twice as much)
            held = True
        for ax, preferred, kw in pending:
            limits = (ax.get_xlim(), ax.get_ylim())
            place_legend(ax, preferred, **kw)
            held = held and (ax.get_xlim(), ax.get_ylim()) == limits
    return held if final else fig


def place_legend(ax, preferred: str | None = None, **kw):
    """A legend inside ``ax`` where it covers no drawn point: ``preferred`` first, then the corners and
    edges; where every place covers something, room is made above the data and the legend goes there.
    The figure should be laid out already (``finish_legends``)."""
    fig = ax.figure
    points = drawn_points(ax)
    order = ([preferred] if preferred and preferred != "best" else []) + [c for c in LEGEND_LOCS if c != preferred]
    best, best_n = None, None
    for loc in order:
        leg = ax.legend(loc=loc, **kw)
        n = hidden_by(leg, points)
        if n == 0:
            return leg
        if best_n is None or n < best_n:
            best, best_n = loc, n
    # nowhere free: raise the top of the axis by the legend's height (plus a margin) and put it there
    leg = ax.legend(loc="upper right", **kw)
    frac = leg.get_window_extent(fig.canvas.get_renderer()).height / ax.get_window_extent().height + 0.04
    lo, hi = ax.get_ylim()
    if ax.get_yscale() == "log":
        import math

        span = math.log10(hi) - math.log10(lo)
        ax.set_ylim(lo, 10 ** (math.log10(lo) + span / max(1.0 - frac, 0.3)))
    else:
        ax.set_ylim(lo, lo + (hi - lo) / max(1.0 - frac, 0.3))
    points = drawn_points(ax)
    for loc in ("upper right", "upper left", "upper center"):
        leg = ax.legend(loc=loc, **kw)
        if hidden_by(leg, points) == 0:
            return leg
    return ax.legend(loc=best, **kw)
