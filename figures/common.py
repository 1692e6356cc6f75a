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
    """The exercise as the figure's title; the parameters held at their values underneath."""
    text = f"{ex.id}  {ex.title}"
    if len(text) > 90:
        cut = text.rfind(" ", 0, 88)
        text = text[:cut] + "\n" + text[cut + 1:]
    if params is not None:
        shown = [f"{p.symbol or p.name} = {p.show(params[p.name])}" for p in ex.params if p.name not in skip]
        line = ", ".join(shown)
        if len(line) > 110:
            half = len(shown) // 2
            line = ", ".join(shown[:half]) + "\n" + ", ".join(shown[half:])
        text += "\n" + line
    if extra:
        import textwrap

        text += "\n" + "\n".join(textwrap.fill(line, 100) for line in extra.splitlines())
    fig.suptitle(text, fontsize=FONT["suptitle"])


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
