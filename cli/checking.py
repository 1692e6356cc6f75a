"""``mech check``'s progress bar and JUnit report; the cases are run by ``mech.api.check``."""

from __future__ import annotations

from xml.etree import ElementTree as ET

from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pragma: no cover
    from mech.verification.checking import Report

__all__ = ["progress_bar", "write_junit", "check_apart"]


def check_apart(outputs, inputs=()) -> None:
    """Exit 2 (one line), before any work, when an output is the same file as an input or another output
    (``core.safeio.check_apart``): ``mech check`` and ``mech grade`` call it with their files."""
    import click

    from mech.core.errors import BadInput
    from mech.core.safeio import check_apart as apart

    try:
        apart(outputs, inputs)
    except BadInput as exc:
        raise click.UsageError(str(exc)) from None


class progress_bar:
    """A transient bar on a terminal's stderr, fed by ``mech.api.check``'s hooks: ``with progress_bar(on)
    as bar: api.check(..., started=bar.started, finished=bar.finished)``.  Off (or stderr not a terminal):
    the hooks do nothing.  No refresh thread (redrawn by hand around each case): the cross-check forks its
    rerun, and the pool its workers, only from a single-threaded process."""

    def __init__(self, on: bool):
        import sys

        self._on = on and sys.stderr.isatty()
        self._bar = self._task = None

    def __enter__(self):
        return self

    def started(self, case, n_cases: int) -> None:
        if not self._on:
            return
        if self._bar is None:
            from rich.console import Console
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

            self._bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                                 TimeElapsedColumn(), console=Console(stderr=True), transient=True,
                                 auto_refresh=False)
            self._bar.start()
            self._task = self._bar.add_task("checking", total=n_cases)
        self._bar.update(self._task, description=f"{case.exercise.id} {case.label}", refresh=True)

    def finished(self, case) -> None:
        if self._bar is not None:
            self._bar.advance(self._task)
            self._bar.refresh()

    def __exit__(self, *exc):
        if self._bar is not None:
            self._bar.stop()
        return False


def write_junit(report: Report, path: str) -> None:
    suite = ET.Element("testsuite", name="mech check", tests=str(len(report.cases)), failures=str(report.failed),
                       errors="0", time=f"{report.seconds:.3f}")
    for case in report.cases:
        # "mech.4.15" reads as package mech.4, class 15 in CI viewers: the id's dot becomes an underscore
        tc = ET.SubElement(suite, "testcase", classname=f"mech.ex{case.exercise.id.replace('.', '_')}",
                           name=f"{case.exercise.id} {case.description}", time=f"{case.seconds:.3f}")
        if not case.ok:
            fail = ET.SubElement(tc, "failure", message=case.detail or "cross-check failed")
            fail.text = case.detail
    root = ET.Element("testsuites", name="mech", tests=str(len(report.cases)), failures=str(report.failed))
    root.append(suite)
    ET.indent(root)
    from mech.core.safeio import atomic_write

    with atomic_write(path, "--junit", mode="wb") as fh:  # a failed write leaves the old report whole
        ET.ElementTree(root).write(fh, encoding="utf-8", xml_declaration=True)
