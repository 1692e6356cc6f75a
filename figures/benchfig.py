"""``mech bench --plot``: the work-precision diagram, error against time and against evaluations."""

from __future__ import annotations

from mech.figures.common import FONT, figure, save

# the student's first attempt and the exercise's tuned default stand out as single points
SINGLE = {"scipy-default": dict(marker="*", ms=14, ls="none", color="k"),
          "default": dict(marker="D", ms=9, ls="none", color="C3")}


def bench_figure(r: dict):
    fig, axes = figure(1, 2, w=5.4, h=4.4)
    methods = list(dict.fromkeys(p["method"] for p in r["points"]))
    for k, m in enumerate(methods):
        pts = [p for p in r["points"] if p["method"] == m and p["ok"] and p["error"]]
        if not pts:
            continue
        style = SINGLE.get(m, dict(marker="o", ms=5, ls="-", lw=1.6, color=f"C{k % 10}"))
        label = {"scipy-default": "solve_ivp's defaults (a first attempt)",
                 "default": "mech's tuned default"}.get(m, m)
        for ax, key in zip(axes[0], ("time_s", "nfev")):
            ax.plot([p[key] for p in pts], [max(p["error"], 1e-17) for p in pts], label=label, **style)
    axes[0][0].set_xlabel("median wall time [s]", fontsize=FONT["label"])
    axes[0][1].set_xlabel("right-hand-side evaluations", fontsize=FONT["label"])
    axes[0][0].set_ylabel("error (largest, relative to the analytic answer)", fontsize=FONT["label"])
    for ax in axes[0]:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="major", alpha=0.3)
        ax.tick_params(labelsize=FONT["tick"])
    axes[0][1].sharey(axes[0][0])
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside right center", fontsize=FONT["legend"], frameon=False)
    fig.suptitle(f"{r['id']}  {r['title']}\nlower left is better: less error for less work",
                 fontsize=FONT["suptitle"])
    return fig


def plot_bench(r: dict, path: str, dpi: float = 110) -> None:
    save(bench_figure(r), path, dpi=dpi)
