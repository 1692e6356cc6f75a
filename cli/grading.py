"""``mech grade FILE`` and the printing of grades: table, JSON, JUnit, the gradebook CSV, exit status.

The reading and judging is ``mech.api.grade_report`` (``mech.students.classrun``).  Exit status: 0
every graded answer right and no cell invalid or not graded (an unanswered cell does not change it); 1
otherwise; 2 a file that cannot be read at all (and, with ``--strict``, any invalid entry or cell,
before anything is graded).
"""

from __future__ import annotations

import json
import os
import time

import click

from typing import TYPE_CHECKING

from mech.core.errors import BadInput

if TYPE_CHECKING:  # pragma: no cover
    from mech.students.answers_files import Entry
    from mech.students.gradebook import GradeReport

__all__ = ["grade_cmd", "write_grade_junit", "print_grade", "write_gradebook"]

EXIT_OK, EXIT_WRONG, EXIT_USAGE = 0, 1, 2  # the contract's exit statuses (as ``mech.cli.main``'s)


def _classname(e: Entry) -> str:
    return f"mech.ex{e.ex_id.replace('.', '_')}"


def write_grade_junit(path: str, entries: list[Entry], seconds: float, out_file: str) -> None:
    """One test case per cell (``Entry.cells``): right passes, wrong is a ``<failure>``, invalid an
    ``<error>``, not graded and unanswered ``<skipped>``; an invalid entry without any output named is one
    ``<error>``.  The classname ``mech.ex4_15`` has no dot inside the id, so CI viewers do not split "4.15"
    into a package 4 and a class 15."""
    from xml.etree import ElementTree as ET

    from mech.core.safeio import atomic_write, shown, shown_path
    from mech.students.cells import State

    cases = [(e, j) for e in entries for j in e.cells]
    bare = [e for e in entries if e.invalid is not None and not e.columns]
    failed = sum(j.cell is State.WRONG for _, j in cases)
    errors = sum(j.cell is State.INVALID for _, j in cases) + len(bare)
    skipped = sum(j.cell in (State.NOT_GRADED, State.UNANSWERED) for _, j in cases)
    tests = len(cases) + len(bare)
    suite = ET.Element("testsuite", name=f"mech grade {shown_path(path)}", tests=str(tests),
                       failures=str(failed), errors=str(errors), skipped=str(skipped), time=f"{seconds:.3f}")

    def case(e: Entry, name: str, seconds_each: float):
        who = f"{e.student}: " if e.student else ""
        tc = ET.SubElement(suite, "testcase", classname=_classname(e), name=f"{who}{name} ({e.label()})",
                           time=f"{seconds_each:.3f}")
        if e.student:
            props = ET.SubElement(tc, "properties")
            ET.SubElement(props, "property", name="student", value=e.student)
        return tc

    for e in entries:
        if e.invalid is not None and not e.columns:
            tc = case(e, f"{e.ex_id}: invalid entry", 0.0)
            ET.SubElement(tc, "error", message=e.invalid, type="invalid").text = f"answer {e.number}: {e.invalid}"
            continue
        graded = max(sum(j.cell in (State.RIGHT, State.WRONG) for j in e.cells), 1)
        for j in e.cells:
            if j.cell is State.UNANSWERED:
                ET.SubElement(case(e, f"{j.name} (not answered)", 0.0), "skipped", message="not answered")
                continue
            # an entry's cross-check time, shared by its judged values (the cases add up to the run)
            each = e.seconds / graded if j.cell in (State.RIGHT, State.WRONG) else 0.0
            tc = case(e, f"{j.name} = {shown(j.text)}" if j.text else f"{e.ex_id} {j.name}", each)
            if j.cell is State.WRONG:
                fail = ET.SubElement(tc, "failure", message=j.verdict)
                fail.text = (f"{e.ex_id} {j.name}: yours {shown(j.text)}, mech {j.shown_reference or '—'}"
                             f" ({j.reference or 'no reference'}): {j.verdict}")
            elif j.cell is State.INVALID:
                ET.SubElement(tc, "error", message=j.verdict, type="invalid").text = \
                    f"answer {e.number}: {j.name}: {j.verdict}"
            elif j.cell is State.NOT_GRADED:
                ET.SubElement(tc, "skipped", message=j.verdict)
    root = ET.Element("testsuites", name="mech", tests=str(tests), failures=str(failed), errors=str(errors))
    root.append(suite)
    ET.indent(root)
    with atomic_write(out_file, "--junit", mode="wb") as fh:
        ET.ElementTree(root).write(fh, encoding="utf-8", xml_declaration=True)


def write_gradebook(report: GradeReport, out_file: str) -> None:
    """``--csv FILE``: one row per student, ``student, points, max`` and a column per ``ID:output``."""
    from mech.core.safeio import atomic_write

    text = report.gradebook()
    with atomic_write(out_file, "--csv", newline="") as fh:
        fh.write(text)


_STYLE = {"right": "green", "wrong": "bold red", "invalid": "bold magenta", "not-graded": "yellow",
          "unanswered": "dim"}


def cell_verdict(j) -> str:
    """A cell's verdict as the table prints it, led by its state: right and wrong verdicts say so
    themselves; an invalid cell "invalid: <reason>", an unanswered one "not answered", a cell not graded
    the reason mech reached no verdict ("not graded: ...", "cannot judge: ...")."""
    from mech.students.cells import State

    if j.cell is State.INVALID:
        return f"invalid: {j.verdict}"
    if j.cell is State.UNANSWERED:
        return "not answered"
    return j.verdict


def summary_line(figures: dict, who: str = "", what: str = "points") -> str:
    """Figures as one line: points of max (a student's gradebook row; ``what`` "answers right": the cells
    of the whole file), the cells wrong, invalid, not graded and not answered, and how many a person must
    review."""
    parts = [f"{figures['points']} of {figures['max']} {what}", f"{figures['wrong']} wrong"]
    parts += [f"{figures[k]} {w}" for k, w in (("invalid", "invalid"), ("not_graded", "not graded"),
                                                 ("unanswered", "not answered")) if figures[k]]
    review = f"; {figures['review']} to review" if figures["review"] else ""
    return f"{who}{', '.join(parts)}{review}"


def print_grade(entries: list[Entry], started: float) -> None:
    """One row per cell (``Entry.cells``: its state leads the verdict); where the table does not fit the
    width, one block per value (the stacking rule of the other commands); piped, no trailing spaces.  The
    closing lines give each student's gradebook row (``gradebook.gradebook_rows``) and the file's cells
    counted by state (``gradebook.cell_counts``: the same sums where no student answers an output twice); the time is
    the command's wall time up to it (``started``: its ``time.perf_counter()``), the printing included."""
    from rich import box
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    from mech import render
    from mech.core.safeio import shown
    from mech.students.gradebook import cell_counts, gradebook_rows

    students = any(e.student for e in entries)
    cols = [("#", "right")] + ([("student", "left")] if students else []) + [
        ("exercise", "left"), ("quantity", "left"), ("yours", "right"), ("mech", "right"), ("verdict", "left")]
    t = Table(box=box.SIMPLE_HEAD, show_edge=False)
    for col, just in cols:
        t.add_column(col, justify=just, no_wrap=True)
    blocks = []
    for e in entries:
        given = ", ".join(f"{k}={v}" for k, v in e.written.items())
        where = f"{e.ex_id}" + (f" ({given})" if given else "")
        rows = [(j.name, shown(j.text), j.shown_reference or "—", Text(cell_verdict(j), style=_STYLE[j.cell.value]))
                for j in e.cells]
        if not rows and e.invalid is not None:
            rows = [("—", "—", "—", Text(f"invalid: {e.invalid}", style=_STYLE["invalid"]))]
        for i, (name, yours, ref, verdict) in enumerate(rows):
            first = i == 0
            t.add_row(*([str(e.number) if first else ""] + ([e.student or "" if first else ""] if students else [])
                        + [where if first else "", name, yours, ref, verdict]))
            head = f"{e.number}  " + (f"{e.student}: " if e.student else "") + f"{where}: {name}"
            blocks.append((head, [("yours", yours), ("mech", ref), ("verdict", verdict)]))
    c = render.console()
    if len(blocks) > LONG_TABLE:
        _emit_lines(c, _long_table(c, t, blocks))
    else:
        render.emit(c, t if render.fits(c, t) else render._stacked("", blocks))
    lines = []
    if students:
        for row in gradebook_rows(entries)[1]:
            lines.append(Text(summary_line(row, f"{row['student'] or '(no student named)'}: "),
                              style="green" if row["wrong"] + row["review"] == 0 else "bold red"))
    counts = cell_counts(entries)
    book = {"points": counts["passed"], "max": sum(counts.values()), "wrong": counts["failed"],
            "review": counts["invalid"] + counts["not_graded"], **counts}
    bad = sum(e.invalid is not None for e in entries)
    extra = f", {bad} of them invalid" if bad else ""
    lines.append(Text(f"{summary_line(book, what='answers right')} ({len(entries)} entr{'y' if len(entries) == 1 else 'ies'}{extra})"
                      f" in {time.perf_counter() - started:.1f} s",
                      style="green" if book["wrong"] + book["review"] == 0 else "bold red"))
    if len(lines) > LONG_TABLE:
        _emit_lines(c, lines)
    else:
        render.emit(c, Group(*lines))


def _emit_lines(c, lines) -> None:
    """Many one-line Texts: through rich on a terminal (its colours), else written as they are (rich wraps
    and measures every line it prints: a second for 10 000)."""
    import sys

    from rich.console import Group

    if c.is_terminal:
        c.print(Group(*lines))
        return
    sys.stdout.write("".join(line.plain.rstrip() + "\n" for line in lines))
    sys.stdout.flush()


LONG_TABLE = 200  # rows from which the table is laid out here, not measured and rendered by rich


def _long_table(c, t, blocks):
    """A class's table of many rows as aligned lines (rich measures and renders every cell of a Table,
    some 1.6 ms a row: 8 s for 5000), in the columns ``t`` has, cut to the width like ``_stacked`` where the
    rows do not fit it."""
    from rich.cells import cell_len
    from rich.text import Text

    heads = [col.header for col in t.columns]
    cells = [[cell.plain if isinstance(cell, Text) else str(cell) for cell in col._cells] for col in t.columns]
    widths = [max([cell_len(h)] + [cell_len(x) for x in col]) for h, col in zip(heads, cells)]
    if sum(widths) + 2 * (len(widths) - 1) > c.width:
        lines = []
        for head, fields in blocks:
            lines.append(Text(head, style="bold"))
            lines += [Text(f"  {label:<8}") + (v if isinstance(v, Text) else Text(str(v))) for label, v in fields]
        return lines
    right = [col.justify == "right" for col in t.columns]

    def line(values, style_last=None):
        parts = [v.rjust(w) if r else v.ljust(w) for v, w, r in zip(values[:-1], widths, right)]
        out = Text("  ".join(parts) + "  ")
        out.append(values[-1], style=style_last or "")
        return out

    verdicts = t.columns[-1]._cells
    rows = [line(heads, "bold"), Text("─" * sum(widths) + "─" * 2 * (len(widths) - 1))]
    for k in range(len(verdicts)):
        v = verdicts[k]
        rows.append(line([col[k] for col in cells], v.style if isinstance(v, Text) else None))
    return rows


def _json_parts(obj) -> list[str]:
    """``json.dumps(obj, indent=2)`` in blocks of a few thousand pieces: the indenting encoder yields a
    small string per value and bracket, and kept until the end they cost some six times the text (10 000
    answers: 20 MB of JSON, 117 MB more at the peak); in blocks, about the text (19 MB more)."""
    parts, pieces = [], []
    for piece in json.JSONEncoder(indent=2, allow_nan=False).iterencode(obj):
        pieces.append(piece)
        if len(pieces) >= 4096:
            parts.append("".join(pieces))
            pieces.clear()
    parts.append("".join(pieces))
    return parts


def _complete_files(ctx, param, incomplete):
    """The shell's own file completion for FILE."""
    from click.shell_completion import CompletionItem

    return [CompletionItem(incomplete, type="file")]


@click.command("grade")
@click.argument("file", metavar="FILE", shell_complete=_complete_files)
@click.option("--json", "as_json", is_flag=True, help="A JSON report on stdout.")
@click.option("--junit", "junit_file", metavar="FILE",
              help="Write a JUnit XML report: a test case per answer; wrong a <failure>, invalid an <error>, "
                   "not graded and unanswered <skipped>.")
@click.option("--csv", "csv_file", metavar="FILE",
              help="Write the gradebook: a row per student (student, points, max, review, a column per ID:output "
                   "holding 1, 0, empty (unanswered), invalid or not graded).")
@click.option("--assignment", "assignment", metavar="DIR",
              help="Grade against the assignment mech assign wrote in DIR: its parameters, digits, range and "
                   "outputs; a file that sets them otherwise is invalid there.")
@click.option("--min-digits", "min_digits", metavar="D", type=click.IntRange(1, 17),
              help="An answer with fewer significant digits is judged as if written to D [2; with "
                   "--assignment, its digits].")
@click.option("--strict", is_flag=True,
              help="Refuse the whole file (exit 2, before grading) when any entry cannot be read.")
@click.option("--params", "params_file", metavar="FILE",
              help="For a CSV of answers: each student's parameters from this assignment template (answers.toml).")
@click.option("-j", "--jobs", type=click.IntRange(1, 256), metavar="N",
              help="Processes to grade with [one per core].")
@click.option("--budget", "total_s", metavar="SECONDS", type=float,
              help="Wall-clock budget of the whole grading [600]; answers not reached by then are not graded.")
def grade_cmd(file, as_json, junit_file, csv_file, assignment, min_digits, strict, params_file, jobs, total_s):
    """Hold a TOML file of answers against mech (each [[answer]]: exercise, params, expect, rtol).

    \b
    [[answer]]
    student = "alice"
    exercise = "4.15"
    params = { theta0 = "60deg" }
    expect = { theta_c = "35.26deg", omega_c = "2.91 rad/s" }

    FILE may also be a CSV (a student column, ID:output columns). Values are judged to the digits
    written (or to rtol). Each answer is a cell: right, wrong, invalid (it cannot be read: that cell
    only), unanswered (left empty) or not graded (mech reached no verdict). With --assignment DIR each
    entry is held to the assignment mech assign wrote. Exit status: 0 every graded answer right and
    nothing invalid or not graded (unanswered ones do not count), 1 otherwise, 2 a file that cannot be
    read (with --strict: any invalid entry or cell, one line each naming the file, entry and field).
    """
    from mech.core.safeio import check_output, escape

    from mech import api

    started = time.perf_counter()
    ctx = click.get_current_context()
    from mech.cli.checking import check_apart

    outputs = [(p, w) for p, w in ((junit_file, "--junit"), (csv_file, "--csv")) if p is not None]
    # an output never overwrites the answers, the template, or another output (exit 2, before any work)
    check_apart(outputs, [(file, "FILE"), (params_file, "--params")]
                + ([(os.path.join(assignment, "key.json"), "--assignment")] if assignment else []))
    for path, what in outputs:
        check_output(path, what)  # before the grading, not after
    try:
        report = api.grade_report(file, total_s, strict=strict, jobs=jobs, params=params_file, started=started,
                                  assignment=assignment, min_digits=min_digits)
    except BadInput as exc:
        problems = getattr(exc, "problems", None)  # a bad answers file: every problem, a line each
        if not problems:
            raise
        for line in problems:
            click.echo(f"mech: error: {escape(' '.join(line.split()))}", err=True)
        ctx.exit(EXIT_USAGE)
    entries = list(report.entries)
    if junit_file:
        write_grade_junit(file, entries, report.seconds, junit_file)
    if csv_file:
        write_gradebook(report, csv_file)
    if as_json:
        for part in _json_parts(report.to_dict()):  # all encoded before anything is written
            click.echo(part, nl=False)
        click.echo()
    else:
        print_grade(entries, started)
    ctx.exit(EXIT_OK if report.ok else EXIT_WRONG)
