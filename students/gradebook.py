"""What a graded file reports: per student (points, maximum), the gradebook CSV, the JSON report and
``GradeReport``, all read from the judged entries."""

from __future__ import annotations

import json
from dataclasses import dataclass

from mech.students.answers_files import Entry

__all__ = ["per_student", "gradebook_rows", "gradebook_csv", "csv_safe", "grade_json", "GradeReport"]


def per_student(entries: list[Entry]) -> list[dict]:
    """For each student named in the file (in order of first appearance; entries without a name under
    null): answers right and wrong, entries, invalid entries, and the gradebook's points and maximum."""
    out: dict = {}
    book = {row["student"]: row for row in gradebook_rows(entries)[1]}
    for e in entries:
        s = out.setdefault(e.student, {"student": e.student, "passed": 0, "failed": 0, "entries": 0,
                                       "invalid": 0})
        s["entries"] += 1
        s["invalid"] += e.invalid is not None
        for j in e.judgements:
            s["passed" if j.match else "failed"] += 1
    for s in out.values():
        row = book.get(s["student"] or "")
        s["points"], s["max"] = (row["points"], row["max"]) if row else (0, 0)
    return list(out.values())


def gradebook_rows(entries: list[Entry]) -> tuple[list[str], list[dict]]:
    """The gradebook: its ``ID:output`` columns (in order of first appearance) and one row per student
    (``student``, ``points``, ``max``, and each column: 1 right, 0 wrong or invalid, None not answered).
    A column answered twice by one student is 1 only when every answer to it is right."""
    cols: list[str] = []
    rows: dict = {}
    for e in entries:
        row = rows.setdefault(e.student or "", {"student": e.student or "", "cells": {}})
        cells = row["cells"]
        for name in e.columns:
            col = f"{e.ex_id}:{name}"
            if col not in cols:
                cols.append(col)
            cells.setdefault(col, None)
        if e.invalid is not None:
            for name in e.columns:
                cells[f"{e.ex_id}:{name}"] = 0
            continue
        for j in e.judgements:
            col = f"{e.ex_id}:{j.name}"
            was = cells.get(col)
            cells[col] = int(j.match) if was is None else min(was, int(j.match))
    out = []
    for row in rows.values():
        cells = row["cells"]
        out.append({"student": row["student"], "points": sum(v or 0 for v in cells.values()),
                    "max": len(cells), **{c: cells.get(c) for c in cols if c in cells}})
    return cols, out


_CSV_UNSAFE = ("=", "+", "-", "@", "\t", "\r")


def csv_safe(text: str) -> str:
    """A cell a spreadsheet will not run: one starting with = + - @ (or a tab, a carriage return) gets a
    leading apostrophe, which spreadsheets read as "text"."""
    text = str(text)
    return "'" + text if text.startswith(_CSV_UNSAFE) else text


def gradebook_csv(entries: list[Entry]) -> str:
    """The gradebook as CSV text: ``student, points, max`` then one column per ``ID:output``."""
    import csv
    import io

    cols, rows = gradebook_rows(entries)
    buf = io.StringIO(newline="")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["student", "points", "max"] + [csv_safe(c) for c in cols])
    for r in rows:
        w.writerow([csv_safe(r["student"]), r["points"], r["max"]]
                   + ["" if r.get(c) is None else r[c] for c in cols])
    return buf.getvalue()


def _entry_json(e: Entry) -> dict:
    if e.result is None:
        params = {}
        if e.exercise is not None and e.invalid is None:
            params = dict(e.exercise.resolve(e.given))
        quantities = [{"name": j.name, "unit": j.unit, "expected": j.as_json()} for j in e.judgements]
        d = {"exercise": e.ex_id, "answer": e.number, "student": e.student, "params": params,
             "quantities": quantities, "agree": None, "ok": e.ok, "seconds": e.seconds}
    else:
        d = {"exercise": e.ex_id, "answer": e.number, "student": e.student, "params": dict(e.result.params),
             "quantities": e.result.to_dict()["quantities"], "agree": e.result.agree, "ok": e.ok,
             "seconds": e.seconds}
    d["invalid"] = e.invalid
    if e.unanswered:
        d["unanswered"] = list(e.unanswered)
    return d


def grade_json(path: str, entries: list[Entry], seconds: float) -> dict:
    judgements = [j for e in entries for j in e.judgements]
    passed = sum(j.match for j in judgements)
    invalid = sum(e.invalid is not None for e in entries)
    return {
        "file": path,
        "entries": [_entry_json(e) for e in entries],
        "ok": passed == len(judgements) and not invalid,
        "passed": passed,
        "failed": len(judgements) - passed,
        "invalid": invalid,
        "unanswered": sum(len(e.unanswered) for e in entries),
        "students": [{k: v for k, v in s.items()} for s in per_student(entries) if s["student"] is not None],
        "seconds": seconds,
    }


@dataclass(frozen=True)
class GradeReport:
    """What ``mech grade`` found: every entry judged (``students.grading.Entry``), the wall time it
    took, and the totals.  ``to_dict()`` is ``mech grade --json``; ``report["ok"]`` reads it too."""

    file: str
    entries: tuple
    seconds: float

    @property
    def judgements(self) -> list:
        return [j for e in self.entries for j in e.judgements]

    @property
    def passed(self) -> int:
        return sum(j.match for j in self.judgements)

    @property
    def failed(self) -> int:
        return len(self.judgements) - self.passed

    @property
    def invalid(self) -> int:
        return sum(e.invalid is not None for e in self.entries)

    @property
    def ok(self) -> bool:
        return self.failed == 0 and self.invalid == 0

    def students(self) -> list[dict]:
        return per_student(list(self.entries))

    def gradebook(self) -> str:
        """The gradebook CSV (``--csv FILE``)."""
        return gradebook_csv(list(self.entries))

    def to_dict(self) -> dict:
        return grade_json(self.file, list(self.entries), self.seconds)

    def __getitem__(self, key):
        return self.to_dict()[key]

