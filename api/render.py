"""Rich renderings of exercises and results; the data they show is built elsewhere.

Three rules every rendering here keeps:

* catalogue text (statement, model, formulas, notes, errors) is shown as plain
  text, never read as rich markup: ``(M/36)[a² + b² ∓ q]`` keeps its bracket;
* a number is never cut: a table that does not fit the width is stacked (one
  block of lines per row) rather than truncated with an ellipsis;
* piped output has no trailing spaces, and follows ``COLUMNS`` where it is set
  (160 columns otherwise, wider than the 80 rich assumes).
"""

from __future__ import annotations

import math
import sys

from rich import box
from rich.console import Console, Group
from rich.table import Table
from rich.text import Text

from mech.problems.spec import Undefined
from mech.verification.result import STYLE, closing

PIPED_WIDTH = 160


def console() -> Console:
    """A console for this command's output: the terminal's width, else ``COLUMNS``, else 160 columns."""
    from mech.core.safeio import columns, normalize_columns

    normalize_columns()  # rich reads COLUMNS itself: 0 would print nothing, 5 would drop rows
    probe = Console()
    width = None if probe.is_terminal or columns() is not None else PIPED_WIDTH
    return Console(highlight=False, soft_wrap=False, width=width)


def emit(c: Console, *renderables) -> None:
    """Print; when piped, without the spaces rich pads every table line with."""
    if c.is_terminal:
        c.print(*renderables)
        return
    with c.capture() as cap:
        c.print(*renderables)
    text = "\n".join(line.rstrip() for line in cap.get().split("\n"))
    sys.stdout.write(text)
    sys.stdout.flush()


def plain(text) -> Text:
    """Catalogue text as it is written: brackets are text, not rich markup."""
    return text if isinstance(text, Text) else Text(str(text))


def prose(text: str) -> Text:
    """A catalogue paragraph reflowed to the width: its line breaks are the file's, not the reader's."""
    paragraphs = [" ".join(line.strip() for line in para.splitlines()) for para in str(text).split("\n\n")]
    return Text("\n\n".join(paragraphs))


def _ellipses(table: Table, width: int) -> int:
    probe = Console(width=width, color_system=None, highlight=False, soft_wrap=False)
    with probe.capture() as cap:
        probe.print(table)
    return cap.get().count("…")


def _natural_width(table: Table) -> int:
    """The width the table takes with every cell on one line (rich's measurement, nothing rendered)."""
    from rich.measure import Measurement

    probe = Console(width=10_000, color_system=None, highlight=False, soft_wrap=False)
    return Measurement.get(probe, probe.options, table).maximum


def uncut(table: Table, width: int) -> bool:
    """Whether a table whose cells may not wrap (``no_wrap`` columns) renders at ``width`` without cutting
    a cell: its natural width is within ``width`` (a render counted rich's ellipses: 12 ms a solve)."""
    return _natural_width(table) <= width


def fits(c: Console, table: Table) -> bool:
    """Whether the table renders at the console's width without cutting a word (rich marks a cut with an
    ellipsis: columns wrap at spaces, and a word too long for its column is cut).  Measured where that
    decides it, rendered only where it does not (two renders of a class's 1500-row table took 1.7 s): a
    table whose natural width (every cell on one line) is within the width cuts nothing, and one whose
    narrowest form (its longest words, its unwrapped cells) is wider must cut something."""
    from rich.measure import Measurement

    need = Measurement.get(c, c.options.update_width(10_000), table)
    if need.maximum <= c.width:
        return True
    if need.minimum > c.width or all(col.no_wrap for col in table.columns):
        return False  # (a cell that may not wrap is cut wherever the natural width does not fit: ``uncut``)
    return _ellipses(table, c.width) == _ellipses(table, 10_000)


# -- numbers ---------------------------------------------------------------------------------------------

MAX_SIG = 12  # digits shown for a value whose error is not known (a double's round-off aside)


def _num(v) -> str:
    if v is None:
        return "—"
    if isinstance(v, Undefined):
        return v.word
    return f"{float(v) + 0.0:.{MAX_SIG}g}"  # + 0.0: -0 prints as 0


def with_error(v, err) -> str:
    """``v`` to the digits its absolute error ``err`` earns, that error on the last digit in parentheses.

    ``0.729727656(8)`` means 0.729727656 ± 8e-9 (the error rounded up to one digit); ``9.99993(7)e-06``
    likewise.  Without an error (None, zero, not finite) the value gets ``MAX_SIG`` digits; an error
    larger than the value gives ``v ± err``.
    """
    if v is None or isinstance(v, Undefined):
        return _num(v)
    v = float(v) + 0.0  # -0 prints as 0
    if err is None or not math.isfinite(err) or err <= 0 or not math.isfinite(v):
        return _num(v)
    e_err = math.floor(math.log10(err))
    digit = math.ceil(err / 10.0**e_err * (1 - 1e-12))  # 1..10: the error rounded up to one digit
    if digit >= 10:
        digit, e_err = 1, e_err + 1
    if v == 0 or abs(v) < digit * 10.0**e_err:
        return f"{v:.2g} ± {digit * 10.0**e_err:.1g}"
    e_v = math.floor(math.log10(abs(v)))
    rounded = round(v / 10.0**e_err) * 10.0**e_err
    if rounded != 0:
        e_v = math.floor(math.log10(abs(rounded)))
    nsig = e_v - e_err + 1
    if nsig > MAX_SIG:
        return _num(v)
    if -4 <= e_v < MAX_SIG and e_err <= 0:
        return f"{rounded:.{-e_err}f}({digit})"
    mant = rounded / 10.0**e_v
    return f"{mant:.{nsig - 1}f}({digit})e{e_v:+03d}"


def _tol_text(q) -> str:
    """The relative tolerance, with the absolute allowance where an output can be zero."""
    abs_part = max(getattr(q, "tol_abs", 0.0) or 0.0, getattr(q, "expected_err_abs", None) or 0.0)
    if abs_part and (q.analytic == 0 or isinstance(q.analytic, Undefined) or q.tol == 0):
        return f"±{abs_part:.2g}"
    return _small(q.tol)


def _small(v) -> str:
    return "—" if v is None else f"{v:.2g}"


def _agree_text(cell: str) -> Text:
    """A verdict's cell (``Quantity.cell``), coloured."""
    return Text(cell, style=STYLE.get(cell, ""))


# -- mech show -------------------------------------------------------------------------------------------

def print_show(ex, from_book: bool | None = None) -> None:
    c = console()
    parts: list = [Text(f"{ex.id}  {ex.title}", style="bold"), Text(ex.topic, style="italic")]
    if from_book is not None:
        parts.append(Text("source: the book's own exercise" if from_book else
                          "source: set for mech on the chapter's topics, not one of the book's exercises",
                          style="dim"))
    parts += [Text(), prose(ex.statement), Text(), Text("Model", style="bold"), prose(ex.model), Text()]

    pt = Table(title="Parameters", title_justify="left", box=box.SIMPLE_HEAD)
    for col in ("name", "symbol", "unit", "default", "allowed", "meaning"):
        pt.add_column(col)
    for p in ex.params:
        pt.add_row(*(plain(x) for x in (p.name, p.symbol, p.unit, p.show(p.default), p.range_text(), p.doc)))
    if not fits(c, pt):
        pt = _stacked("Parameters", [(p.name, [("symbol", p.symbol), ("unit", p.unit), ("default", p.show(p.default)),
                                                ("allowed", p.range_text()), ("meaning", p.doc)]) for p in ex.params])
    ot = Table(title="Outputs", title_justify="left", box=box.SIMPLE_HEAD)
    for col in ("name", "unit", "meaning"):
        ot.add_column(col)
    for o in ex.outputs:
        doc = o.doc + (" [leading-order theory]" if o.theory != "exact" else "")
        ot.add_row(plain(o.name), plain(o.unit), plain(doc))
    if not fits(c, ot):
        ot = _stacked("Outputs", [(o.name, [("unit", o.unit), ("meaning", o.doc + (
            " [leading-order theory]" if o.theory != "exact" else ""))]) for o in ex.outputs])
    parts.append(pt)
    if ex.joint_limits:
        parts += [Text("Joint limits (a solve refuses parameters beyond them)", style="bold")]
        parts += [plain("  " + t) for t in ex.joint_limits]
        parts.append(Text())
    parts += [ot, Text("Analytic results", style="bold")]
    parts += [plain("  " + f) for f in ex.formulas]
    parts += [Text(), Text("Numeric route", style="bold"), prose(ex.numeric_route)]
    if ex.route_note:
        parts += [Text(), Text("As implemented here", style="bold"), prose(ex.route_note)]
    if ex.hard_cases:
        parts += [Text(), Text("Hard cases", style="bold")]
        for h in ex.hard_cases:
            parts.append(plain(f"  {case_params_text(ex, h['params'])}: {h['why']}"))
    leading = [o.name for o in ex.outputs if o.theory != "exact"]
    theory = f"leading-order for {', '.join(leading)}" if leading else "exact"
    methods = [f"analytic ({theory})" if m == "analytic" else m for m in ex.methods]
    parts += [Text(), Text(f"methods: {', '.join(methods)}", style="dim")]
    emit(c, Group(*parts))


def case_params_text(ex, values: dict) -> str:
    """``theta0 = 1 deg, l = 2 m``: parameter values as people read them."""
    from mech.studies.checking import case_text

    return case_text(ex, values)


def _stacked(title: str, blocks: list[tuple[str, list[tuple[str, object]]]]) -> Group:
    """The narrow form of a table: for each row a heading line, then one ``label  value`` line per field."""
    parts: list = [Text(title, style="bold")] if title else []
    for k, (head, fields) in enumerate(blocks):
        if k:
            parts.append(Text())
        parts.append(Text(head, style="bold"))
        t = Table(box=None, show_header=False, padding=(0, 1), pad_edge=False)
        t.add_column("label", no_wrap=True)
        t.add_column("value")
        for label, value in fields:
            t.add_row(Text("  " + label), plain(value))
        parts.append(t)
    return Group(*parts)


# -- mech solve ------------------------------------------------------------------------------------------

def _columns(result) -> list[str]:
    """The columns a result has something for: no numeric, diff, tol or agree column for an analytic-only
    solve, no analytic one for a numeric-only solve."""
    qs = result.quantities
    has_a = any(q.analytic is not None for q in qs)
    has_n = any(q.numeric is not None for q in qs)
    cols = ["quantity", "unit"] + (["analytic"] if has_a else []) + (["numeric"] if has_n else [])
    if has_a and has_n:
        cols += ["rel. diff", "tol", "agree"]
    elif has_n and any(q.agree is False for q in qs):
        cols += ["agree"]
    if result.expected:  # your own answers (mech solve --expect)
        cols += ["yours", "verdict"]
    return cols


def _cells(q, expected: dict | None = None) -> dict:
    name = q.name if q.theory == "exact" else q.name + " *"
    j = (expected or {}).get(q.name)
    return {
        "yours": Text(j.text if j else ""),
        "verdict": Text(j.verdict, style="green" if j.match else "bold red") if j else Text(""),
        "quantity": Text(name),
        "unit": Text(q.unit),
        "analytic": Text(with_error(q.analytic, getattr(q, "analytic_err", None))),
        "numeric": Text(with_error(q.numeric, getattr(q, "numeric_err", None))),
        "rel. diff": Text(_small(q.rel_err)),
        "tol": Text(_tol_text(q)),
        "agree": _agree_text(q.cell),
    }


def _params_line(result) -> str:
    ex = result.exercise
    return ", ".join(f"{p.symbol or p.name} = {p.show(result.params[p.name])}" for p in ex.params)


def solve_title(result) -> Text:
    ex = result.exercise
    return Text(f"{ex.id}  {ex.title}\n{_params_line(result)}")


def solve_table(result, width: int | None = None) -> Table | Group:
    """The results, one row per output; where that is wider than ``width``, the unit joins the name, and
    where it still is, one block of lines per output: never a cut number."""
    cols = _columns(result)
    expected = result.expected
    for merged in (False, True):
        t = Table(box=box.SIMPLE_HEAD, show_edge=False, pad_edge=False)
        shown = [c for c in cols if not (merged and c == "unit")]
        for col in shown:
            t.add_column(col, justify="left" if col in ("quantity", "unit", "verdict") else
                         "center" if col == "agree" else "right", no_wrap=True)
        for q in result.quantities:
            cells = _cells(q, expected)
            if merged and q.unit != "1":
                cells["quantity"] = Text(f"{cells['quantity'].plain} [{q.unit}]")
            t.add_row(*(cells[col] for col in shown))
        if width is None or uncut(t, width):  # every column no_wrap
            return t
    blocks = []
    for q in result.quantities:
        cells = _cells(q, expected)
        unit = "" if q.unit == "1" else f" [{q.unit}]"
        fields = [(col, cells[col]) for col in ("analytic", "numeric") if col in cols]
        if "agree" in cols:
            check = Text.assemble(cells["agree"])
            if "tol" in cols:
                check.append(f" (rel. diff {cells['rel. diff'].plain}, tol {cells['tol'].plain})")
            fields.append(("agree", check))
        if expected.get(q.name):
            fields += [("yours", cells["yours"]), ("verdict", cells["verdict"])]
        blocks.append((cells["quantity"].plain + unit, fields))
    return _stacked("", blocks)


def _undefined_notes(q) -> list[str]:
    """Why an output has no value: one note when both methods say the same, else one per method."""
    why = {key: v for key in ("analytic", "numeric") if isinstance(v := getattr(q, key, None), Undefined)}
    if len(why) == 2 and why["analytic"].why == why["numeric"].why:
        v = why["analytic"]
        return [f"{v.word}: {v.why}"]
    return [f"{key}: {v.why}" for key, v in why.items()]


def _notes(result) -> list[str]:
    """Each note once, with the outputs it is about: ``xi_lo, xi_hi: ...``; an undefined or infinite
    output always says why."""
    by_text: dict[str, list[str]] = {}
    for q in result.quantities:
        own = _undefined_notes(q)
        # the JSON's rendering notes each method's reason on the quantity; the table says it once
        rest = [n for n in q.notes if not any(n == f"{k}: {getattr(q, k).why}" for k in ("analytic", "numeric")
                                              if isinstance(getattr(q, k, None), Undefined))]
        for n in dict.fromkeys(own + rest):
            by_text.setdefault(n, []).append(q.name)
    return [f"{', '.join(names)}: {text}" for text, names in by_text.items()]


def _verdict(result) -> Text | None:
    said = closing(result)
    return None if said is None else Text(said[0], style=STYLE[said[1]])


def print_solve(result) -> None:
    c = console()
    parts = [solve_title(result), Text(), solve_table(result, width=c.width), Text()]
    notes = _notes(result)
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
    fp = (result.numeric_info or {}).get("fp_warnings") or []
    if fp:  # numpy's warnings are kept off stderr but shown: what they touched was judged like any value
        parts.append(Text("floating-point warnings in the solve: " + "; ".join(fp), style="dim"))
    for n in notes:
        parts.append(Text(n, style="yellow"))
    for e in result.errors:
        parts.append(Text(str(e), style="bold red"))
    verdict = _verdict(result)
    if verdict is not None:
        parts.append(verdict)
    if result.expect_summary:
        parts.append(Text(result.expect_summary, style="green" if result.expect_ok else "bold red"))
    emit(c, Group(*parts))


# -- mech check ------------------------------------------------------------------------------------------

def print_check(report) -> None:
    c = console()
    t = Table(box=box.SIMPLE_HEAD, show_edge=False)
    for col, just in (("id", "left"), ("case", "left"), ("result", "center"), ("worst err/tol", "right"),
                      ("time", "right"), ("detail", "left")):
        t.add_column(col, justify=just, no_wrap=col != "detail")
    rows = []
    for case in report.cases:
        res = (Text("pass", style="green") if case.agree else Text("FAIL", style="bold red") if not case.ok
               else Text("no verdict", style="yellow"))
        ratio = "—" if case.worst_ratio is None else f"{case.worst_ratio:.2g}"
        rows.append((case.exercise.id, case.description, res, ratio, f"{case.seconds:.2f} s", case.detail))
        t.add_row(Text(case.exercise.id), Text(case.description), res, Text(ratio), Text(f"{case.seconds:.2f} s"),
                  Text(case.detail))
    if not fits(c, t):
        t = _stacked("", [(f"{i}  {label}", [("result", res), ("worst err/tol", ratio), ("time", secs)]
                           + ([("detail", detail)] if detail else []))
                          for i, label, res, ratio, secs, detail in rows])
    style = "green" if report.ok else "bold red"
    none = len(report.cases) - report.passed - report.failed
    said = f"{report.passed} passed, " + (f"{none} no verdict, " if none else "") + f"{report.failed} failed"
    emit(c, Group(t, Text(f"{said} in {report.seconds:.1f} s", style=style)))
