"""Rich renderings of exercises and results; the data they show is built elsewhere."""

from __future__ import annotations

from rich import box
from rich.console import Console, Group
from rich.panel import Panel
from rich.table import Table
from rich.text import Text

from mech.problems.spec import Undefined

_out: Console | None = None


def console() -> Console:
    global _out
    if _out is None:
        probe = Console()
        # piped output keeps whole numbers and whole rows: wider than the 80 columns rich assumes
        _out = Console(highlight=False, soft_wrap=False, width=None if probe.is_terminal else 160)
    return _out


def _num(v) -> str:
    if v is None:
        return "—"
    if isinstance(v, Undefined):
        return "undefined"
    return f"{v:.12g}"


def _small(v) -> str:
    return "—" if v is None else f"{v:.2g}"


def print_show(ex) -> None:
    c = console()
    c.print(Text(f"{ex.id}  {ex.title}", style="bold"))
    c.print(Text(ex.topic, style="italic"))
    c.print()
    c.print(ex.statement)
    c.print()
    c.print(Text("Model", style="bold"))
    c.print(ex.model)
    c.print()
    pt = Table(title="Parameters", title_justify="left", box=box.SIMPLE_HEAD)
    for col in ("name", "symbol", "unit", "default", "allowed", "meaning"):
        pt.add_column(col)
    for p in ex.params:
        pt.add_row(p.name, p.symbol, p.unit, p.show(p.default), p.range_text(), p.doc)
    c.print(pt)
    ot = Table(title="Outputs", title_justify="left", box=box.SIMPLE_HEAD)
    for col in ("name", "unit", "meaning"):
        ot.add_column(col)
    for o in ex.outputs:
        doc = o.doc + (" [leading-order theory]" if o.theory != "exact" else "")
        ot.add_row(o.name, o.unit, doc)
    c.print(ot)
    c.print(Text("Analytic results", style="bold"))
    for f in ex.formulas:
        c.print(f"  {f}")
    c.print()
    c.print(Text("Numeric route", style="bold"))
    c.print(ex.numeric_route)
    if ex.route_note:
        c.print()
        c.print(Text("As implemented here", style="bold"))
        c.print(ex.route_note)
    if ex.hard_cases:
        c.print()
        c.print(Text("Hard cases", style="bold"))
        for h in ex.hard_cases:
            values = ", ".join(
                f"{k} = {ex.param_map[k].show(v)}" if k in ex.param_map else f"{k} = {v}" for k, v in h["params"].items()
            )
            c.print(f"  {values}: {h['why']}")
    c.print()
    c.print(f"methods: {', '.join(ex.methods)}", style="dim")


def _agree_text(flag) -> Text:
    if flag is None:
        return Text("—", style="dim")
    return Text("yes", style="green") if flag else Text("NO", style="bold red")


def solve_table(result) -> Table:
    ex = result.exercise
    params = ", ".join(f"{p.symbol or p.name} = {p.show(result.params[p.name])}" for p in ex.params)
    t = Table(title=f"{ex.id}  {ex.title}\n{params}", title_justify="left", box=box.SIMPLE_HEAD)
    expected = getattr(result, "expected", None) or {}  # your own answers (mech solve --expect)
    for col, just in (("quantity", "left"), ("unit", "left"), ("analytic", "right"), ("numeric", "right"),
                      ("rel. diff", "right"), ("tol", "right"), ("agree", "center")):
        t.add_column(col, justify=just, no_wrap=True)
    if expected:
        t.add_column("yours", justify="right", no_wrap=True)
        t.add_column("verdict", justify="left")
    for q in result.quantities:
        name = q.name + (" *" if q.theory != "exact" else "")
        row = [q.name if q.theory == "exact" else name, q.unit, _num(q.analytic), _num(q.numeric),
               _small(q.rel_err), _small(q.tol), _agree_text(q.agree)]
        if expected:
            j = expected.get(q.name)
            row += [j.text, Text(j.verdict, style="green" if j.match else "bold red")] if j else ["", ""]
        t.add_row(*row)
    return t


def print_solve(result) -> None:
    c = console()
    parts = [solve_table(result)]
    notes = [f"{q.name}: {'; '.join(q.notes)}" for q in result.quantities if q.notes]
    if any(q.theory != "exact" for q in result.quantities):
        notes.insert(0, "* leading-order theory: tol is the size of what it neglects")
    timing = result.timing
    cost = []
    if timing.get("analytic_s") is not None:
        cost.append(f"analytic {timing['analytic_s'] * 1e3:.3g} ms")
    if timing.get("numeric_s") is not None:
        info = result.numeric_info or {}
        detail = ", ".join(
            x for x in (info.get("method"), f"rtol {info['rtol']:g}" if info.get("rtol") else None,
                        f"{info.get('nfev')} evaluations" if info.get("nfev") else None) if x
        )
        cost.append(f"numeric {timing['numeric_s'] * 1e3:.3g} ms ({detail})" if detail else
                    f"numeric {timing['numeric_s'] * 1e3:.3g} ms")
        inv = (result.numeric_info or {}).get("invariants") or {}
        if inv:
            cost.append("invariant drift: " + ", ".join(f"{k} {v:.2g}" for k, v in inv.items()))
    parts.append(Text("cost: " + "; ".join(cost), style="dim"))
    for n in notes:
        parts.append(Text(n, style="yellow"))
    for e in result.errors:
        parts.append(Text(e, style="bold red"))
    if getattr(result, "expect_summary", None):
        ok = all(j.match for j in result.expected.values())
        parts.append(Text(result.expect_summary, style="green" if ok else "bold red"))
    verdict = result.agree
    if verdict is True:
        parts.append(Text("analytic and numeric agree", style="green"))
    elif verdict is False:
        parts.append(Text("CROSS-CHECK FAILED", style="bold red"))
    c.print(Group(*parts))


def print_check(report) -> None:
    c = console()
    t = Table(box=box.SIMPLE_HEAD, show_edge=False)
    for col, just in (("id", "left"), ("case", "left"), ("result", "center"), ("worst err/tol", "right"),
                      ("time", "right"), ("detail", "left")):
        t.add_column(col, justify=just)
    for case in report.cases:
        res = Text("pass", style="green") if case.ok else Text("FAIL", style="bold red")
        ratio = "—" if case.worst_ratio is None else f"{case.worst_ratio:.2g}"
        t.add_row(case.exercise.id, case.label, res, ratio, f"{case.seconds:.2f} s", case.detail)
    c.print(t)
    style = "green" if report.ok else "bold red"
    c.print(Text(f"{report.passed} passed, {report.failed} failed in {report.seconds:.1f} s", style=style))
