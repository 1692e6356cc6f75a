"""What a graded file reports: per student (points, maximum), the gradebook CSV, the JSON report and
``GradeReport``, all read from the judged entries."""

from __future__ import annotations

import re
from dataclasses import dataclass

from mech.students.answers_files import Entry
from mech.students.cells import State

__all__ = ["per_student", "gradebook_rows", "gradebook_csv", "csv_safe", "grade_json", "GradeReport", "totals",
           "book_cell", "COUNTS"]


# a column answered twice by one student: the worse state stands (1 only when every answer is right)
_RANK = {State.UNANSWERED: 0, State.RIGHT: 1, State.WRONG: 2, State.NOT_GRADED: 3, State.INVALID: 4}
# what a gradebook cell holds for each state (``State.RIGHT``: 1, ``State.WRONG``: 0)
_BOOK = {State.RIGHT: 1, State.WRONG: 0, State.UNANSWERED: None, State.INVALID: "invalid",
         State.NOT_GRADED: "not graded"}
COUNTS = ("points", "max", "review", "wrong", "invalid", "not_graded", "unanswered")


def book_cell(state: State):
    """The gradebook's cell for a state: 1, 0, None (empty: unanswered), "invalid" or "not graded"."""
    return _BOOK[state]


def per_student(entries: list[Entry]) -> list[dict]:
    """For each student named in the file (in order of first appearance; entries without a name under
    null): the gradebook's figures (``points``, ``max``, ``review`` and the cells wrong, invalid, not
    graded and unanswered), the answers right and wrong (``passed``, ``failed``), the entries and the
    invalid entries."""
    out: dict = {}
    book = {row["student"]: row for row in gradebook_rows(entries)[1]}
    for e in entries:
        s = out.setdefault(e.student, {"student": e.student, "passed": 0, "failed": 0, "entries": 0,
                                       "invalid_entries": 0})
        s["entries"] += 1
        s["invalid_entries"] += e.invalid is not None
        for j in e.cells:
            s["passed"] += j.cell is State.RIGHT
            s["failed"] += j.cell is State.WRONG
    for s in out.values():
        row = book[s["student"] or ""]
        s.update({k: row[k] for k in COUNTS})
    return list(out.values())


def gradebook_rows(entries: list[Entry]) -> tuple[list[str], list[dict]]:
    """The gradebook: its ``ID:output`` columns (in order of first appearance) and one row per student:
    ``student``, ``points`` (cells right), ``max`` (cells asked), ``review`` (cells invalid or not
    graded: a person must look), the counts ``wrong``, ``invalid``, ``not_graded``, ``unanswered``, and
    each column's state (``cells.State``).  Every output an entry names is a column of its student, an
    invalid entry's too; against an assignment, every output assigned."""
    cols: list[str] = []
    rows: dict = {}
    for e in entries:
        cells = rows.setdefault(e.student or "", {})
        for j in e.cells:
            col = f"{e.ex_id}:{j.name}"
            if col not in cols:
                cols.append(col)
            was = cells.get(col)
            cells[col] = j.cell if was is None or _RANK[j.cell] > _RANK[was] else was
    out = []
    for student, cells in rows.items():
        states = list(cells.values())
        out.append({"student": student, "points": states.count(State.RIGHT), "max": len(states),
                    "review": sum(st.needs_review for st in states), "wrong": states.count(State.WRONG),
                    "invalid": states.count(State.INVALID), "not_graded": states.count(State.NOT_GRADED),
                    "unanswered": states.count(State.UNANSWERED),
                    **{c: cells[c] for c in cols if c in cells}})
    return cols, out


def totals(entries: list[Entry]) -> dict:
    """The gradebook's figures over every student (``COUNTS``): what the summary line prints."""
    rows = gradebook_rows(entries)[1]
    return {k: sum(r[k] for r in rows) for k in COUNTS}


_CSV_UNSAFE = ("=", "+", "-", "@", "\t", "\r")
# a part of a cell a spreadsheet may split off (after , ; | a tab or a line break) that starts, after
# blanks, with a character that makes it a formula
_CSV_PART = re.compile(r"([,;|\t\r\n])([ \u00a0]*)(?=[=+\-@])")


def csv_safe(text: str) -> str:
    """A cell a spreadsheet will not run: one starting with = + - @ (or a tab, a carriage return) gets a
    leading apostrophe, which spreadsheets read as "text"; so does every part after a separator a
    spreadsheet may split the cell on (``a;=HYPERLINK(...)`` -> ``a;'=HYPERLINK(...)``)."""
    text = _CSV_PART.sub(lambda m: m.group(1) + m.group(2) + "'", str(text))
    return "'" + text if text.lstrip(" \u00a0").startswith(_CSV_UNSAFE) else text


def gradebook_csv(entries: list[Entry]) -> str:
    """The gradebook as CSV text: ``student, points, max, review`` then one column per ``ID:output``
    holding ``1``, ``0``, nothing (unanswered), ``invalid`` or ``not graded``."""
    import csv
    import io

    cols, rows = gradebook_rows(entries)
    buf = io.StringIO(newline="")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["student", "points", "max", "review"] + [csv_safe(c) for c in cols])
    for r in rows:
        w.writerow([csv_safe(r["student"]), r["points"], r["max"], r["review"]]
                   + ["" if c not in r or book_cell(r[c]) is None else book_cell(r[c]) for c in cols])
    return buf.getvalue()


def _cell_json(j) -> dict:
    d = {"output": j.name, "state": j.cell.value}
    if j.cell not in (State.RIGHT, State.WRONG):
        d["reason"] = j.verdict
    return d


def _entry_json(e: Entry) -> dict:
    cells = e.cells
    if e.result is None:
        params = {}
        if e.exercise is not None and e.invalid is None:
            params = dict(e.exercise.resolve(e.given))
        quantities = [{"name": j.name, "unit": j.unit, "expected": j.as_json()} for j in e.judgements + e.void]
        d = {"exercise": e.ex_id, "answer": e.number, "student": e.student, "params": params,
             "quantities": quantities, "agree": None, "ok": e.ok, "seconds": e.seconds}
    else:
        quantities = e.result.to_dict()["quantities"]
        void = {j.name: j for j in e.void}
        for q in quantities:  # a cell that could not be read, on its quantity
            if q.get("name") in void:
                q["expected"] = void.pop(q["name"]).as_json()
        quantities += [{"name": j.name, "unit": j.unit, "expected": j.as_json()} for j in void.values()]
        d = {"exercise": e.ex_id, "answer": e.number, "student": e.student, "params": dict(e.result.params),
             "quantities": quantities, "agree": e.result.agree, "ok": e.ok, "seconds": e.seconds}
    d["invalid"] = e.invalid
    if e.unanswered:
        d["unanswered"] = list(e.unanswered)
    d["cells"] = [_cell_json(j) for j in cells]
    return d


def cell_counts(entries: list[Entry]) -> dict:
    """Every cell of every entry counted by state (a column answered twice counted twice; the gradebook's
    ``totals`` count it once): passed, failed, invalid, not_graded, unanswered."""
    states = [j.cell for e in entries for j in e.cells]
    return {"passed": states.count(State.RIGHT), "failed": states.count(State.WRONG),
            "invalid": states.count(State.INVALID), "not_graded": states.count(State.NOT_GRADED),
            "unanswered": states.count(State.UNANSWERED)}


def grade_json(path: str, entries: list[Entry], seconds: float) -> dict:
    counts = cell_counts(entries)
    invalid_entries = sum(e.invalid is not None for e in entries)
    book = totals(entries)
    return {
        "file": path,
        "entries": [_entry_json(e) for e in entries],
        "ok": passes(counts, invalid_entries),
        **counts,
        "invalid_entries": invalid_entries,
        "points": book["points"], "max": book["max"], "review": book["review"],
        "students": [dict(s) for s in per_student(entries) if s["student"] is not None],
        "seconds": seconds,
    }


def passes(counts: dict, invalid_entries: int) -> bool:
    """The exit status' rule: every graded cell right, none invalid nor left without a verdict, no
    invalid entry; unanswered cells do not fail a file (they score 0 in the gradebook)."""
    return counts["failed"] == 0 and counts["invalid"] == 0 and counts["not_graded"] == 0 and invalid_entries == 0


@dataclass(frozen=True)
class GradeReport:
    """What ``mech grade`` found: every entry judged (``answers_files.Entry``), the wall time it took, and
    the totals by cell state.  ``to_dict()`` is ``mech grade --json``; ``report["ok"]`` reads it too."""

    file: str
    entries: tuple
    seconds: float

    @property
    def judgements(self) -> list:
        return [j for e in self.entries for j in e.judgements]

    @property
    def cells(self) -> list:
        """Every cell (``Judgement``, its ``cell`` the state) of every entry."""
        return [j for e in self.entries for j in e.cells]

    def count(self, key: str) -> int:
        return cell_counts(list(self.entries))[key]

    @property
    def passed(self) -> int:
        return self.count("passed")

    @property
    def failed(self) -> int:
        return self.count("failed")

    @property
    def invalid(self) -> int:
        """Invalid cells (an invalid entry's are all invalid)."""
        return self.count("invalid")

    @property
    def not_graded(self) -> int:
        return self.count("not_graded")

    @property
    def unanswered(self) -> int:
        return self.count("unanswered")

    @property
    def invalid_entries(self) -> int:
        return sum(e.invalid is not None for e in self.entries)

    @property
    def ok(self) -> bool:
        return passes(cell_counts(list(self.entries)), self.invalid_entries)

    def students(self) -> list[dict]:
        return per_student(list(self.entries))

    def totals(self) -> dict:
        """The gradebook's figures over every student: points, max, review, wrong, invalid, ..."""
        return totals(list(self.entries))

    def gradebook(self) -> str:
        """The gradebook CSV (``--csv FILE``)."""
        return gradebook_csv(list(self.entries))

    def to_dict(self) -> dict:
        return grade_json(self.file, list(self.entries), self.seconds)

    def __getitem__(self, key):
        return self.to_dict()[key]
