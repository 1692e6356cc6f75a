"""``mech bench ID``: speed against error of an exercise's numeric solver (machinery in mech.studies.bench)."""

from __future__ import annotations

import json

import click
from mech.core.safeio import shown

__all__ = ["bench_cmd", "plot_bench"]


def _float_list(text: str | None, what: str) -> list[float] | None:
    if not text:
        return None
    out = []
    for part in text.replace(" ", ",").split(","):
        if not part:
            continue
        try:
            v = float(part)
        except ValueError:
            raise click.BadParameter(f"'{shown(part)}' is not a number", param_hint=what) from None
        if not (0.0 < v < 1.0):
            raise click.BadParameter(f"{part} is out of range; allowed (0, 1)", param_hint=what)
        out.append(v)
    return out


@click.command("bench")
@click.argument("ex_id", metavar="ID")
@click.option("-p", "pairs", multiple=True, metavar="NAME=VALUE", help="Set a parameter (repeatable).")
@click.option("--methods", "methods_text", metavar="M1,M2",
              help="Rows to run: RK45, DOP853 (mech's own), LSODA, Radau, BDF, RK23, scipy-DOP853, Yoshida4, Yoshida6, scipy-default, "
                   "default [the integrators, the symplectic rows where the exercise has a Hamiltonian, "
                   "the student row and the default].")
@click.option("--tols", "tols_text", metavar="T1,T2", help="Requested tolerances [1e-3 to 1e-12, every decade].")
@click.option("--repeats", default=5, show_default=True, help="Timed runs per point at most (after a warm-up).")
@click.option("--budget", "budget_s", default=45.0, show_default=True,
              help="Seconds the timed repeats may take in all; slow points are timed once.")
@click.option("--max-seconds", default=55.0, show_default=True,
              help="Start no new point after this many seconds (the rest are kept as 'not run').")
@click.option("--json", "as_json", is_flag=True,
              help="Print the result as one JSON object on stdout (fields: docs/json.md).")
@click.option("--plot", "plot_file", type=click.Path(dir_okay=False, writable=True),
              help="Draw error against time and against evaluations (log-log) to this PNG (needs matplotlib).")
def bench_cmd(ex_id, pairs, methods_text, tols_text, repeats, budget_s, max_seconds, as_json, plot_file):
    """Speed against error of exercise ID's numeric solver.

    Every point: requested rtol, achieved error against the exact analytic answer
    (max over outputs of |numeric - analytic|/|analytic|), median wall time after a
    warm-up with its spread, and right-hand-side evaluations.  Failed runs stay as
    failures.  Summary: per method the setting reaching 1e-6 and 1e-9 with the fewest
    evaluations, ranked by them (wall time is shown, and ranked, separately).  On a
    fixed-step row (Yoshida4/6) rtol controls no error: it only picks the step.
    """
    from mech import api
    from mech.cli.main import UsageFailure, _get
    from mech.cli.options import collect_params
    from mech.core.errors import BadInput

    ex = _get(ex_id)
    if not (ex.has_numeric and ex.has_analytic):
        raise UsageFailure(f"{ex.id} has no numeric and analytic solver pair to bench")
    try:
        params = ex.resolve(collect_params(ex, [], list(pairs)))
        methods = api.bench_methods(ex, params, methods_text) if methods_text else None
    except BadInput as exc:
        raise UsageFailure(str(exc)) from None
    tols = _float_list(tols_text, "--tols")
    if plot_file:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            raise UsageFailure("--plot needs matplotlib: pip install -e '.[plot]' in mech's checkout") from None
        from mech.figures.common import check_target

        check_target(plot_file)  # before the bench's seconds of work

    progress = None
    if not as_json:
        from mech.render import console

        c = console()

        def progress(pt):
            if c.is_terminal:
                c.print(f"  {pt['method']:>13}  rtol {pt['rtol']:.0e}", style="dim", end="\r")

    try:
        result = api.bench_resolved(ex, params, methods=methods, tols=tols, repeats=repeats, budget_s=budget_s,
                                    max_seconds=max_seconds, progress=progress).to_dict()
    except BadInput as exc:
        raise UsageFailure(str(exc)) from None
    if plot_file:
        plot_bench(result, plot_file)
    if as_json:
        click.echo(json.dumps(api.json_safe(result), indent=2, allow_nan=False))
    else:
        _print(result, plot_file)


def _g(v, fmt=".2g"):
    return "—" if v is None else format(v, fmt)


def _print(r: dict, plot_file: str | None) -> None:
    from rich import box
    from rich.table import Table
    from rich.text import Text

    from rich.console import Group

    from mech.render import console, emit

    c = console()
    parts: list = []
    parts.append(Text(f"{r['id']}  {r['title']}", style="bold"))
    parts.append(Text(f"error: {r['error_measure']} (reference: {r['reference']}; outputs {', '.join(r['measured_outputs'])}"
            + (f"; skipped {', '.join(r['skipped_outputs'])}: zero or undefined" if r["skipped_outputs"] else "")
            + (f"; leading-order, left out: {', '.join(r['left_out_outputs'])}" if r["left_out_outputs"] else "")
            + ")", style="dim"))
    if r["route"] != "ode":
        parts.append(Text(r["route"], style="dim"))
    t = Table(box=box.SIMPLE_HEAD, show_edge=False)
    for col, just in (("method", "left"), ("rtol", "right"), ("error", "right"), ("time ms", "right"),
                      ("spread ms", "right"), ("nfev", "right"), ("note", "left")):
        t.add_column(col, justify=just)
    last = None
    for p in r["points"]:
        if last is not None and p["method"] != last:
            t.add_section()
        last = p["method"]
        if p["ok"]:
            spread = f"{p['time_min_s'] * 1e3:.3g}–{p['time_max_s'] * 1e3:.3g}"
            t.add_row(p["method"], f"{p['rtol']:.0e}", _g(p["error"]), f"{p['time_s'] * 1e3:.3g}", spread,
                      str(p["nfev"]), p.get("note", "") or p.get("integrator", ""))
        else:
            t.add_row(p["method"], f"{p['rtol']:.0e}", (Text("n/a", style="dim") if p.get("applies") is False else Text("failed", style="red")), "—", "—", "—",
                      p.get("note", ""))
    parts.append(t)
    if any(p.get("fixed_step") for p in r["points"]):
        fixed = ", ".join(dict.fromkeys(p["method"] for p in r["points"] if p.get("fixed_step")))
        parts.append(Text(f"rtol on a fixed-step row ({fixed}) controls no error: it only picks the step, "
                          "h = 0.5 tau rtol^(1/order), tau the motion's time scale", style="dim"))
    s = Table(title="Summary: ranked by the evaluations needed to reach 1e-9, then 1e-6 (what the work-precision "
                    "plot compares)", title_justify="left", box=box.SIMPLE_HEAD, show_edge=False)
    for col in ("rank", "method", "to 1e-6: rtol", "nfev", "ms", "to 1e-9: rtol", "nfev", "ms", "best error",
                "by time"):
        s.add_column(col, justify="left" if col == "method" else "right")
    for e in sorted(r["summary"], key=lambda e: e["rank"]):
        row = [str(e["rank"]), e["method"]]
        for key in ("fewest_evals_for_1e-6", "fewest_evals_for_1e-9"):
            ch = e[key]
            row += [f"{ch['rtol']:.0e}", str(ch["nfev"]), f"{ch['time_s'] * 1e3:.3g}"] if ch else ["—", "—", "—"]
        row += [_g(e["best_error"]), str(e["rank_by_time"])]
        s.add_row(*row)
    parts.append(s)
    parts.append(Text("by time: the rank by median wall time to the same targets, a measure of this machine and of "
                      "Python's overhead per step (a fixed-step loop pays less of it per evaluation) as much as "
                      "of the method", style="dim"))
    sv = r.get("student_vs_default")
    if sv:
        parts.append(Text(f"student row (solve_ivp defaults): error {sv['student_error']:.2g} in {sv['student_time_s'] * 1e3:.3g} ms; "
                f"{sv['method']} at rtol {sv['default_rtol']:.0e}: {sv['default_error']:.2g} in "
                f"{sv['default_time_s'] * 1e3:.3g} ms (error ratio {sv['error_ratio']:.2g})"))
    tm = r["timing"]
    parts.append(Text(f"{tm['seconds']:.1f} s; medians of up to {tm['repeats_max']} runs after a warm-up; "
            f"load {_g(tm['load_1min'])} on {tm['cpus']} cpus" + (f"; plot: {plot_file}" if plot_file else ""),
            style="dim"))
    emit(c, Group(*parts))


def plot_bench(r: dict, path: str) -> None:
    """Error against median time and against nfev, log-log, one line per method (figures/benchfig.py)."""
    from mech import api

    api.plot_bench(r, path)
