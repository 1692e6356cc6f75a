"""``mech grade FILE`` and the printing of grades and baselines: tables, JUnit, exit status.

The reading and judging is ``mech.api.grade_entries`` (``mech.verification.grading``).
"""

from __future__ import annotations

import json

import click

from typing import TYPE_CHECKING

from mech.core.errors import BadInput

if TYPE_CHECKING:  # pragma: no cover
    from mech.verification.grading import Entry

__all__ = ["grade_cmd", "write_grade_junit", "print_grade", "junit_baseline", "print_baseline"]


def write_grade_junit(path: str, entries: list[Entry], seconds: float, out_file: str) -> None:
    """One test case per expected value; the classname ``mech.ex4_15`` has no dot inside the id, so CI
    viewers do not split "4.15" into a package 4 and a class 15."""
    from xml.etree import ElementTree as ET

    from mech.core.safeio import atomic_write, shown, shown_path

    judgements = [(e, j) for e in entries for j in e.judgements]
    failed = sum(not j.match for _, j in judgements)
    suite = ET.Element("testsuite", name=f"mech grade {shown_path(path)}", tests=str(len(judgements)),
                       failures=str(failed), errors="0", time=f"{seconds:.3f}")
    for e, j in judgements:
        who = f"{e.student}: " if e.student else ""
        # an entry's cross-check time, shared by its expected values (the cases add up to the run)
        tc = ET.SubElement(suite, "testcase", classname=f"mech.ex{e.exercise.id.replace('.', '_')}",
                           name=f"{who}{j.name} = {shown(j.text)} ({e.label()})",
                           time=f"{e.seconds / max(len(e.judgements), 1):.3f}")
        if e.student:
            props = ET.SubElement(tc, "properties")
            ET.SubElement(props, "property", name="student", value=e.student)
        if not j.match:
            fail = ET.SubElement(tc, "failure", message=j.verdict)
            fail.text = (f"{e.exercise.id} {j.name}: yours {shown(j.text)}, mech {j.shown_reference or '—'}"
                         f" ({j.reference or 'no reference'}): {j.verdict}")
    root = ET.Element("testsuites", name="mech", tests=str(len(judgements)), failures=str(failed))
    root.append(suite)
    ET.indent(root)
    with atomic_write(out_file, "--junit", mode="wb") as fh:
        ET.ElementTree(root).write(fh, encoding="utf-8", xml_declaration=True)


def print_grade(entries: list[Entry], seconds: float) -> None:
    """One row per expected value; where the table does not fit the width, one block per value (the
    stacking rule of the other commands); piped, no trailing spaces."""
    from rich import box
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    from mech import render
    from mech.core.safeio import shown

    students = any(e.student for e in entries)
    cols = [("#", "right")] + ([("student", "left")] if students else []) + [
        ("exercise", "left"), ("quantity", "left"), ("yours", "right"), ("mech", "right"), ("verdict", "left")]
    t = Table(box=box.SIMPLE_HEAD, show_edge=False)
    for col, just in cols:
        t.add_column(col, justify=just, no_wrap=True)
    blocks = []
    for e in entries:
        given = ", ".join(f"{k}={v}" for k, v in e.written.items())
        where = f"{e.exercise.id}" + (f" ({given})" if given else "")
        for i, j in enumerate(e.judgements):
            verdict = Text(j.verdict, style="green" if j.match else "bold red")
            first = i == 0
            t.add_row(*([str(e.number) if first else ""] + ([e.student or "" if first else ""] if students else [])
                        + [where if first else "", j.name, shown(j.text), j.shown_reference or "—", verdict]))
            head = f"{e.number}  " + (f"{e.student}: " if e.student else "") + f"{where}: {j.name}"
            blocks.append((head, [("yours", shown(j.text)), ("mech", j.shown_reference or "—"), ("verdict", verdict)]))
    c = render.console()
    table = t if render.fits(c, t) else render._stacked("", blocks)
    judgements = [j for e in entries for j in e.judgements]
    right = sum(j.match for j in judgements)
    lines = []
    if students:
        from mech import api

        for s in api.grade_students(entries):
            n = s["passed"] + s["failed"]
            lines.append(Text(f"{s['student'] or '(no student named)'}: {s['passed']} of {n} right",
                              style="green" if s["failed"] == 0 else "bold red"))
    lines.append(Text(f"{right} of {len(judgements)} answers right, {len(judgements) - right} wrong"
                      f" ({len(entries)} entr{'y' if len(entries) == 1 else 'ies'}) in {seconds:.1f} s",
                      style="green" if right == len(judgements) else "bold red"))
    render.emit(c, Group(table, *lines))


def _complete_files(ctx, param, incomplete):
    """The shell's own file completion for FILE."""
    from click.shell_completion import CompletionItem

    return [CompletionItem(incomplete, type="file")]


@click.command("grade")
@click.argument("file", metavar="FILE", shell_complete=_complete_files)
@click.option("--json", "as_json", is_flag=True, help="A JSON report on stdout.")
@click.option("--junit", "junit_file", metavar="FILE",
              help="Write a JUnit XML report: one test case per expected value.")
@click.option("--budget", "total_s", metavar="SECONDS", type=float,
              help="Wall-clock budget of the whole grading [600]; answers not reached by then fail, saying so.")
def grade_cmd(file, as_json, junit_file, total_s):
    """Hold a TOML file of answers against mech (each [[answer]]: exercise, params, expect, rtol).

    \b
    [[answer]]
    student = "alice"
    exercise = "4.15"
    params = { theta0 = "60deg" }
    expect = { theta_c = "35.26deg", omega_c = "2.91 rad/s" }

    Values are judged to the digits written (or to rtol). Exit status: 0 all right,
    1 any wrong, 2 a bad file (one line naming the file, the answer and the field).
    """
    from mech.cli.main import EXIT_DISAGREE, EXIT_OK, EXIT_USAGE, UsageFailure
    from mech.core.safeio import check_output, escape

    from mech import api

    ctx = click.get_current_context()
    try:
        if junit_file is not None:
            check_output(junit_file, "--junit")  # before the grading, not after
        from mech.core.safeio import check_apart

        check_apart([(junit_file, "--junit")], [(file, "the answers file")])
        entries, seconds = api.grade_entries(file, total_s=total_s)
    except BadInput as exc:
        problems = getattr(exc, "problems", None)  # a bad answers file: every problem, a line each
        if not problems:
            raise UsageFailure(str(exc)) from None
        for line in problems:
            click.echo(f"mech: error: {escape(' '.join(line.split()))}", err=True)
        ctx.exit(EXIT_USAGE)
    if junit_file:
        write_grade_junit(file, entries, seconds, junit_file)
    if as_json:
        click.echo(json.dumps(api.grade_json(file, entries, seconds), indent=2, allow_nan=False))
    else:
        print_grade(entries, seconds)
    ok = all(e.ok for e in entries)
    click.get_current_context().exit(EXIT_OK if ok else EXIT_DISAGREE)


def junit_baseline(junit_file: str, cmp) -> None:
    """Add to ``mech check``'s JUnit report a suite with one test case per point compared with the
    baseline, failed when any of its values moved: CI shows what moved, not only the exit status."""
    from xml.etree import ElementTree as ET

    tree = ET.parse(junit_file)
    root = tree.getroot()
    moved: dict[tuple[str, str], list[str]] = {}
    for m in cmp.moved:
        moved.setdefault((m.id, m.case), []).append(m.text())
    suite = ET.SubElement(root, "testsuite", name=f"mech baseline {cmp.path}", tests=str(len(cmp.points)),
                          failures=str(len(moved)), errors="0")
    for ex_id, case in cmp.points:
        tc = ET.SubElement(suite, "testcase", classname=f"mech.baseline.ex{ex_id.replace('.', '_')}", name=case)
        if (ex_id, case) in moved:
            fail = ET.SubElement(tc, "failure", message="moved beyond its error bars since the baseline")
            fail.text = "\n".join(moved[(ex_id, case)])
    root.set("tests", str(int(root.get("tests", "0")) + len(cmp.points)))
    root.set("failures", str(int(root.get("failures", "0")) + len(moved)))
    ET.indent(root)
    from mech.core.safeio import atomic_write

    with atomic_write(junit_file, "--junit", mode="wb") as fh:
        tree.write(fh, encoding="utf-8", xml_declaration=True)


def print_baseline(cmp, saved: str | None) -> None:
    from rich.text import Text

    from mech import render

    c = render.console()
    if cmp is not None:
        then = cmp.versions_then
        changed = [f"{k} {then.get(k)} -> {v}" for k, v in cmp.versions_now.items() if then.get(k) != v]
        since = f" (since: {', '.join(changed)})" if changed else ""
        if cmp.ok:
            c.print(Text(f"baseline {cmp.path}: {cmp.compared} values, none moved beyond its error bars{since}",
                         style="green"))
        else:
            c.print(Text(f"baseline {cmp.path}: {len(cmp.moved)} of {cmp.compared} values moved beyond their "
                         f"error bars{since}:", style="bold red"))
            for m in cmp.moved:
                c.print(Text(f"  {m.text()}", style="red"))
        if cmp.not_in_baseline:
            c.print(Text(f"not in the baseline: {', '.join(cmp.not_in_baseline)}", style="yellow"))
    if saved:
        c.print(Text(f"baseline saved to {saved}", style="dim"))
