"""``mech sweep``: one exercise solved over a range (a grid when several parameters sweep), both ways.

A swept parameter is ``--NAME START:STOP:N`` (N evenly spaced values, ends
included) or ``--NAME START:STOP:N:log`` (geometric spacing); START and STOP
take the same units and arithmetic as ``mech solve`` (``10deg:80deg:8``).
Any other ``--NAME VALUE`` is held fixed.  Every point is checked against the
parameter bounds and the exercise's joint constraints before anything runs: a value
out of its bounds refuses the sweep (exit 2); a point that only a joint limit
refuses (in-bounds values the exercise's theory cannot decide, such as a
locking edge) is marked "refused" with its one-line reason and the rest runs.
"""

from __future__ import annotations

import csv
import io
import math
import sys

import click

from mech.cli.main import SolveCommand, UsageFailure, _complete_ids, _get
from mech.core.exits import EXIT_DISAGREE, EXIT_INTERRUPTED, EXIT_OK
from mech.cli.options import collect_texts
from mech.core.safeio import columns
from mech.problems.values import convert, parse_rtol
from mech.core.units import ValueError_, to_si
from mech.problems.spec import BadInput, Exercise
from mech.studies.sweep import describe_point
from mech.core.safeio import shown

MAX_N = 10_000


def parse_range(ex: Exercise, name: str, text: str):
    """``START:STOP:N[:log]`` -> Axis; every value within the parameter's bounds."""
    from mech.studies.sweep import Axis

    param = ex.param_map[name]
    parts = [s.strip() for s in text.split(":")]
    log = False
    if len(parts) == 4 and parts[3].lower() in ("log", "geom"):
        log = True
        parts = parts[:3]
    if len(parts) != 3:
        raise BadInput(f"{name}: a range is START:STOP:N or START:STOP:N:log, got '{shown(text)}'")
    ends = []
    for part in parts[:2]:
        try:
            ends.append(to_si(part, param.unit))
        except ValueError_ as exc:
            raise BadInput(f"{name}: cannot use '{shown(part)}' in '{shown(text)}': {exc}; allowed range {param.range_text()}") from None
    try:
        n = int(parts[2])
        if str(n) != parts[2].lstrip("+"):
            raise ValueError
    except ValueError:
        raise BadInput(f"{name}: N in '{shown(text)}' must be a whole number of points, got '{shown(parts[2])}'") from None
    start, stop = ends
    if n < 1 or n > MAX_N:
        raise BadInput(f"{name}: N in '{shown(text)}' must be between 1 and {MAX_N}")
    if n == 1 and start != stop:
        raise BadInput(f"{name}: one point in '{shown(text)}' needs START = STOP (or N >= 2)")
    if log and (start <= 0 or stop <= 0):
        raise BadInput(f"{name}: a log range needs positive ends, got '{shown(text)}'")
    for v, typed in zip((start, stop), parts[:2]):
        param.check(v, typed)  # echoed as typed: "10 (= 572.958 deg)", not the SI value in degrees
    if n == 1:
        values = [start]
    elif log:
        lo, hi = math.log(start), math.log(stop)  # not log(stop / start): 1e300 / 1e-300 overflows
        values = [math.exp(lo + (hi - lo) * k / (n - 1)) for k in range(n)]
        values[0] = start
        values[-1] = stop
    else:
        values = [start + (stop - start) * k / (n - 1) for k in range(n)]
        values[-1] = stop
    for v in values:
        param.check(v)
    unit, factor = shown_unit(param, parts[0])
    return Axis(name, tuple(values), log, unit, factor)


def shown_unit(param, text: str = "") -> tuple[str, float]:
    """(unit, SI value of one unit) to show a parameter in: the unit typed in ``text`` if it has one
    (``10deg`` -> deg, ``2Hz`` -> Hz), else the parameter's display unit, else its SI unit."""
    import re

    from mech.core.units import UNITS

    m = re.fullmatch(r"\s*[-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?\s*([A-Za-z]+)\s*", text or "")
    if m and m.group(1) in UNITS:
        try:
            return m.group(1), to_si("1" + m.group(1), param.unit)
        except ValueError_:
            pass
    if param.display:
        return param.display, 1.0 / param.to_display(1.0)
    return param.unit, 1.0


def parse_only(ex: Exercise, text: str | None) -> tuple[str, ...] | None:
    """``--only a,b``: output names, each one of the exercise's."""
    if not text:
        return None
    names = [t.strip() for t in text.split(",") if t.strip()]
    known = [o.name for o in ex.outputs]
    for n in names:
        if n not in known:
            raise BadInput(f"--only: '{shown(n)}' is not an output of {ex.id}; its outputs are: {', '.join(known)}")
    return tuple(dict.fromkeys(names))


def collect(ex: Exercise, args: list[str], pairs: list[str]):
    """The ``--NAME VALUE`` arguments and ``-p`` pairs split into axes (ranges) and fixed values."""
    texts = collect_texts(ex, args, pairs, forms="--NAME START:STOP:N, --NAME VALUE or -p NAME=...")
    axes, fixed = [], {}
    for name, text in texts.items():
        if ":" in text:
            axes.append(parse_range(ex, name, text))
        else:
            fixed[name] = convert(ex, name, text)
    if not axes:
        names = ", ".join(ex.param_map)
        raise BadInput(f"nothing to sweep: give at least one --NAME START:STOP:N (parameters of {ex.id}: {names})")
    return axes, fixed


# -- output ----------------------------------------------------------------

TABLE_MAX = 400  # above this many points the table is left out (the summary, --csv, --json and --plot stay)
SHOW_ERRORS = 20


def _fmt(v) -> str:
    return "—" if v is None else f"{v + 0.0:.10g}"  # + 0.0: -0 prints as 0


def _cell(q: dict, key: str) -> str:
    """A value, or why there is none: "infinite" / "undefined" where the solver said so (its note)."""
    if q[key] is None and f"{key}: " in (q.get("note") or ""):
        return "infinite" if q.get("infinite") else "undefined"
    return _fmt(q[key])


def _undefined_reasons(points: list[dict]) -> list[str]:
    """Each output's reasons for having no value, once, with how many points gave it (a refused point is
    listed on its own, ``_refused_lines``)."""
    seen: dict[str, int] = {}
    for pt in points:
        if pt.get("refused"):
            continue
        for q in pt["quantities"]:
            if (q["analytic"] is None or q["numeric"] is None) and q.get("note"):
                note = q["note"]
                a, _, n = note.partition("; numeric: ")
                if a == f"analytic: {n}":  # both methods give the same reason: say it once
                    note = f"{'infinite' if q.get('infinite') else 'undefined'}: {n}"
                key = f"{q['name']}: {note}"
                seen[key] = seen.get(key, 0) + 1
    return [f"{text} ({n} point{'s' if n > 1 else ''})" for text, n in seen.items()]


def _unit_of(result, name):
    """(unit, SI value of one unit) a parameter is shown in: its axis's unit if it sweeps, else its display unit."""
    for a in result.axes:
        if a.name == name and a.unit:
            return a.unit, a.factor
    return shown_unit(result.exercise.param_map[name])


def _summary(result) -> tuple[str, bool]:
    n = len(result)
    n_bad = result.n_failed
    n_refused = len(result.refused)
    route = " (batched)" if result.batched is not None else ""
    every = "every point" if not n_refused else "every point solved"
    text = (f"{n} points, {result.seconds:.2f} s{route} on {result.workers} "
            f"process{'es' if result.workers > 1 else ''}; "
            + (f"analytic and numeric agree at {every}" if n_bad == 0 else f"{n_bad} points FAILED the cross-check")
            + (f"; {n_refused} point{'s' if n_refused > 1 else ''} refused, not solved (below)" if n_refused else ""))
    return text, n_bad == 0


def _outside_lines(points: list[dict]) -> list[str]:
    """Per output, how many points its leading-order theory is outside its range at: nothing compared there
    (the point's "yes" is its numeric value verified by the rerun, as ``mech solve`` says)."""
    count: dict[str, int] = {}
    for pt in points:
        for q in pt["quantities"]:
            if q.get("theory_valid") is False:
                count[q["name"]] = count.get(q["name"], 0) + 1
    by_n: dict[int, list[str]] = {}
    for name, n in count.items():
        by_n.setdefault(n, []).append(name)
    return [f"{', '.join(names)}: the leading-order theory is outside its range at {n} point{'s' if n > 1 else ''}; "
            "nothing compared there, the numeric value (verified at rtol/10) is the answer"
            for n, names in by_n.items()]


def _refused_lines(result, swept) -> list[str]:
    """One line per refused point (at most SHOW_ERRORS, then a count): where, and the exercise's reason."""
    ex = result.exercise
    lines = []
    for n, (k, why) in enumerate(sorted(result.refused.items())):
        if n == SHOW_ERRORS:
            lines.append(f"... and {len(result.refused) - n} more refused points (--json lists every point)")
            break
        P = result.batched.grid if result.batched is not None else None
        params = ({a: float(P[a][k]) for a in swept} if P is not None else result.solutions()[k].params)
        lines.append(f"point {k + 1} ({describe_point(ex, params, swept)}) refused: {why}")
    return lines


def print_table(result) -> None:
    from rich import box
    from rich.markup import escape
    from rich.table import Table
    from rich.text import Text

    from mech import render

    ex = result.exercise
    swept = [a.name for a in result.axes]
    fixed = ", ".join(f"{p.symbol or p.name} = {p.show(result.fixed[p.name])}" for p in ex.params
                      if p.name not in swept and p.name in result.fixed)
    c = render.console()
    names = result.output_names
    outs = [o for o in ex.outputs if o.name in names]
    if len(result) <= TABLE_MAX:
        title = escape(f"{ex.id}  {ex.title}" + (f"\n{fixed}" if fixed else ""))
        t = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD)
        for name in swept:
            unit, _ = _unit_of(result, name)
            t.add_column(escape(f"{name} [{unit}]"), justify="right", no_wrap=True)
        for o in outs:
            unit = "" if o.unit == "1" else f" [{o.unit}]"
            t.add_column(escape(f"{o.name}{unit}\nanalytic"), justify="right", no_wrap=True)
            t.add_column(f"{o.name}\nnumeric", justify="right", no_wrap=True)
        t.add_column("worst\nrel. diff", justify="right", no_wrap=True)
        t.add_column("agree", justify="center", no_wrap=True)
        blocks = []
        for pt in result.point_list():
            row = []
            for name in swept:
                _, factor = _unit_of(result, name)
                row.append(f"{pt['params'][name] / factor:.6g}")
            rels = []
            for q in pt["quantities"]:
                row += [_cell(q, "analytic"), _cell(q, "numeric")]
                if q.get("rel_err") is not None:
                    rels.append(q["rel_err"])
            row.append(f"{max(rels):.2g}" if rels else "—")
            flag = pt.get("agree")
            row.append(Text("refused", style="yellow") if pt.get("refused") else
                       Text("—", style="dim") if flag is None else
                       Text("yes", style="green") if flag else Text("NO", style="bold red"))
            t.add_row(*row)
            head = ", ".join(f"{name} = {val} {_unit_of(result, name)[0]}" for name, val in zip(swept, row))
            labels = [f"{o.name} {kind}" + ("" if o.unit == "1" else f" [{o.unit}]")
                      for o in outs for kind in ("analytic", "numeric")] + ["worst rel. diff", "agree"]
            blocks.append((head, list(zip(labels, row[len(swept):]))))
        if not c.is_terminal and columns() is None:
            # piped with no width asked for: one row per point, as wide as the grid's table needs
            from rich.console import Console

            probe = Console(width=100_000)
            c = Console(highlight=False, soft_wrap=False, width=max(probe.measure(t).maximum, 80))
            render.emit(c, t)
        elif render.fits(c, t):
            render.emit(c, t)
        else:  # too narrow for the grid's table: one block per point, every number whole
            render.emit(c, render._stacked(f"{ex.id}  {ex.title}" + (f"\n{fixed}" if fixed else ""), blocks))
    else:
        c.print(escape(f"{ex.id}  {ex.title}" + (f"; {fixed}" if fixed else "")))
        c.print(f"(no table above {TABLE_MAX} points: --csv, --json or --plot FILE show them all)", style="dim")
    text, ok = _summary(result)
    import textwrap  # wrapped here: rich leaves a space at the end of a line it wraps

    for part in textwrap.wrap(text, max(c.width, 20)):
        c.print(Text(part, style="dim" if ok else "bold red"))
    if len(result) <= TABLE_MAX:
        reasons = _undefined_reasons(result.point_list())
        for r in reasons[:SHOW_ERRORS]:
            c.print(Text(r, style="yellow"))
        for line in _outside_lines(result.point_list()):
            c.print(Text(line, style="yellow"))
    for line in _refused_lines(result, swept):
        c.print(Text(line, style="yellow"))
    # the first failures, the failed points built one at a time and only until SHOW_ERRORS lines are printed
    # (a failed 100 000-point sweep built every point's JSON here: 750 MB, 18 s); then a count of the rest
    shown, cut, at = 0, False, set()
    for k, pt in result.failed_points() if not ok else ():
        msgs = list(pt.get("errors", []))
        if pt.get("agree") is False and not msgs:
            msgs = [f"{q['name']}: {q.get('note') or 'disagree'}" for q in pt["quantities"] if q["agree"] is False]
        for e in msgs:
            if shown == SHOW_ERRORS:
                cut = True
                break
            c.print(Text(f"point {k + 1} ({describe_point(ex, pt['params'], swept)}): {e}", style="red"))
            shown += 1
            at.add(k)
        if cut:
            break
    if cut:
        rest = result.n_failed - len(at)
        more = f"{rest} more failed point{'' if rest == 1 else 's'}" if rest > 0 else "more"
        c.print(Text(f"... and {more} (--json lists every point)", style="red"))


def csv_text(result) -> str:
    """Every parameter as ``name [unit]`` (swept ones in the unit typed), then per output its columns."""
    buf = io.StringIO()
    write_csv(result, buf)
    return buf.getvalue()


def write_csv(result, out) -> None:
    """``csv_text`` written to the text stream ``out`` a row at a time, the points built one at a time (a
    100 000-point sweep built whole took 918 MB)."""
    ex = result.exercise
    w = csv.writer(out, lineterminator="\n")
    units = {p.name: _unit_of(result, p.name) for p in ex.params}
    header = [f"{p.name} [{units[p.name][0]}]" for p in ex.params]
    outs = [o for o in ex.outputs if o.name in result.output_names]
    for o in outs:
        header += [f"{o.name}_analytic [{o.unit}]", f"{o.name}_numeric [{o.unit}]",
                   f"{o.name}_numeric_err [{o.unit}]", f"{o.name}_rel_err [1]", f"{o.name}_agree"]
    header += ["agree", "refused"]
    w.writerow(header)

    def cell(v):
        if v is None:
            return ""
        if isinstance(v, bool):
            return "true" if v else "false"
        return repr(float(v))

    def typed(v):  # a parameter in the unit typed, to 15 digits: 30 deg, not 29.999999999999996
        return f"{v:.15g}"

    for pt in result.iter_points():
        row = [typed(pt["params"][p.name] / units[p.name][1]) for p in ex.params]
        for q in pt["quantities"]:
            row += [cell(q["analytic"]), cell(q["numeric"]), cell(q.get("numeric_err")), cell(q["rel_err"]),
                    cell(q["agree"])]
        row += [cell(pt.get("agree")), pt.get("refused", "")]
        w.writerow(row)


@click.command("sweep", cls=SolveCommand)
@click.argument("ex_id", metavar="ID", shell_complete=_complete_ids)
@click.option("-p", "pairs", multiple=True, metavar="NAME=RANGE", help="A range or a value (repeatable).")
@click.option("--only", "only_text", metavar="OUT,...", help="Compute only these outputs at each point [all].")
@click.option("--rtol", "rtol_text", metavar="R", help="Requested accuracy of the numeric solver [exercise default].")
@click.option("--no-verify", is_flag=True, help="Skip the rerun at rtol/10 at every point (twice as fast).")
@click.option("--json", "as_json", is_flag=True, help="One JSON object: the axes and a solve object per point.")
@click.option("--csv", "as_csv", is_flag=True, help="CSV on stdout: every parameter as 'name [unit]', then per "
              "output analytic, numeric, numeric_err, rel_err, agree.")
@click.option("--plot", "plot_file", type=click.Path(dir_okay=False), metavar="FILE",
              help="Also draw the outputs: against the first swept parameter, or as a map over two "
                   "(PNG, SVG or PDF by suffix).")
@click.option("-j", "--jobs", type=click.IntRange(1, 256),
              help="Processes to use, at most one per core [decided from the measured cost].")
@click.option("--budget", "total_s", metavar="SECONDS", type=float,
              help="Wall-clock budget of the whole sweep [600]; points not reached by then fail, saying so.")
@click.pass_context
def sweep_cmd(ctx, ex_id, pairs, only_text, rtol_text, no_verify, as_json, as_csv, plot_file, jobs, total_s):
    """Solve exercise ID over a range: --NAME START:STOP:N[:log] for each swept parameter.

    \b
    Several ranges make a grid (the first varies slowest); --NAME VALUE holds a
    parameter fixed.  Both methods run at every point and are cross-checked as
    in `mech solve`.  Where the exercise has a batched route for the outputs
    asked (--only), all points are integrated together as one vectorised
    system (5.11, 5.12, 5.13); otherwise point by point, over the machine's cores.
    A point inside every parameter's bounds that the exercise's joint limits
    refuse (a locking edge, a critical force) is marked "refused" with its
    reason and left unsolved; the rest is swept.
    \b
    Examples:
      mech sweep 4.15 --theta0 10deg:90deg:9
      mech sweep 5.6 --theta0 0.1:3:12 --csv > period.csv
      mech sweep 4.10 --l 1cm:1m:20:log --plot omega.png
      mech sweep 5.11 --omega 7:13:200 --mu 0.005:0.5:200 --only growth --plot chart.png
    Exit status: 0 every point solved agrees, 1 a point failed, 2 bad input (a value out of its bounds, or
    every point refused), 3 internal error, 130 interrupted.
    """
    from mech import api

    if as_json and as_csv:
        raise UsageFailure("--json and --csv: choose one")
    ex = _get(ex_id)
    try:
        axes, fixed = collect(ex, ctx.meta.get("mech_param_args", []), list(pairs))
        only = parse_only(ex, only_text)
        plan = api.plan_sweep(ex, axes, fixed, only)
        rtol = parse_rtol(rtol_text, ex)
        if total_s is not None:
            from mech.studies.sweep import check_total

            total_s = check_total(total_s)
    except BadInput as exc:
        raise UsageFailure(str(exc)) from None
    if plot_file:
        api.check_figure_target(plot_file)

    done = [0]

    def run(progress=None):
        def tick(k):
            done[0] = k
            if progress:
                progress(k)

        return api.run_sweep_plan(plan, rtol=rtol, verify=not no_verify, jobs=jobs, progress=tick, total_s=total_s)

    n_points = plan.n_points
    try:
        if sys.stderr.isatty():
            from rich.console import Console
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, \
                TimeRemainingColumn

            with Progress(TextColumn(f"sweep {ex.id}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                          TimeRemainingColumn(), console=Console(stderr=True), transient=True) as bar:
                task = bar.add_task("sweep", total=n_points)
                result = run(lambda k: bar.update(task, completed=k))
        else:
            result = run()
    except KeyboardInterrupt:
        click.echo(f"mech: interrupted after {done[0]} of {n_points} points; nothing written", err=True)
        ctx.exit(EXIT_INTERRUPTED)
    # the fixed part of the table's title: every parameter that does not sweep, defaults included
    swept = {a.name for a in axes}
    result.fixed = {p.name: float(fixed.get(p.name, p.default)) for p in ex.params if p.name not in swept}

    if plot_file:
        import warnings

        with warnings.catch_warnings():  # matplotlib's layout notes (a crowded legend) are no message of
            warnings.simplefilter("ignore")  # the sweep's, and would print a source path
            api.save_sweep_figure(result, plot_file)
    if as_json:
        result.write_json(sys.stdout)  # streamed: 100 000 points took 1.9 GB built whole
    elif as_csv:
        write_csv(result, sys.stdout)  # streamed, like --json
    else:
        print_table(result)
    if plot_file:
        click.echo(f"wrote {plot_file}", err=True)
    ctx.exit(EXIT_DISAGREE if result.agree is False else EXIT_OK)
