"""Answers files: ``mech grade FILE`` reads a TOML file of ``[[answer]]`` entries or a CSV gradebook-shaped
file into ``Entry`` values, every field bounded before it is read; an entry that cannot be read is kept,
``invalid``, with its reason (the rest of the file is graded)."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from mech.core.units import ValueError_, to_si
from mech.problems.spec import BadInput, Exercise
from mech.core.safeio import shown
from mech.students.cells import State
from mech.students.expectations import MIN_DIGITS, parse_count, parse_expectation, parse_rtol_value, with_range

__all__ = ["Entry", "BadFile", "load_answers", "load_answers_csv", "MAX_ANSWERS", "MAX_STUDENT", "MIN_DIGITS",
           "void_cell", "unanswered_variants", "read_answers"]


_ENTRY_KEYS = ("exercise", "params", "expect", "rtol", "points", "seed", "over", "student")
MAX_STUDENT = 80  # characters of a student's name


@dataclass
class Entry:
    """One ``[[answer]]`` (or one exercise of a CSV row).  ``invalid``: "line N: the reason" when the entry
    cannot be read as a whole (its exercise, parameters, student, a field the assignment fixes): none of
    it is graded, and every output it names is an invalid cell; ``void``: the cells that could not be read
    on their own (an unparsable value, an unknown output: invalid, each with its reason; the entry's other
    answers are graded); ``unanswered``: the outputs whose answer was left empty (``expect = { theta_c =
    "" }``, an assignment's template) or, against an assignment, not given: an empty cell in the
    gradebook.  ``cells``: every output asked, in order, with its state (``cells.State``)."""

    number: int  # 1-based, in file order
    line: int | None
    exercise: Exercise | None  # None only for an invalid entry whose exercise is unknown
    given: dict  # SI
    written: dict  # the parameters as written, for labels
    expectations: list
    result: object = None
    judgements: list = field(default_factory=list)
    student: str | None = None  # `student = "alice"`: names the entry in every report
    seconds: float = 0.0  # the cross-check's wall time
    invalid: str | None = None
    unanswered: list = field(default_factory=list)
    exercise_text: str = ""  # the exercise as written (an invalid entry's, shown escaped)
    columns: list = field(default_factory=list)  # the outputs asked (answered or not), for the gradebook
    void: list = field(default_factory=list)  # Judgements of the cells that could not be read (invalid)
    assigned: bool = False  # an assignment's variant no entry answered: every output unanswered
    invalid_reason: str = ""  # ``invalid`` without the line it names
    texts: dict = field(default_factory=dict)  # output -> the answer as written (an invalid entry's cells show it)

    @property
    def cells(self) -> list:
        """Every output asked, in order, as a ``Judgement`` whose ``cell`` is its state: the judged ones
        (right, wrong, not graded), the unreadable ones (invalid), those left empty (unanswered); every
        output of an invalid entry is invalid, with the entry's reason."""
        units = {o.name: o.unit for o in self.exercise.outputs} if self.exercise is not None else {}
        if self.invalid is not None:
            return [void_cell(n, units.get(n, ""), self.texts.get(n, ""), State.INVALID, self.invalid)
                    for n in self.columns]
        got = {j.name: j for j in self.void}
        got.update((j.name, j) for j in self.judgements)
        out = []
        for n in self.columns:
            if n in got:
                out.append(got[n])
            elif n in self.unanswered:
                out.append(void_cell(n, units.get(n, ""), "", State.UNANSWERED, "not answered"))
            else:  # asked, readable, but no verdict reached it
                out.append(void_cell(n, units.get(n, ""), "", State.NOT_GRADED, "not graded"))
        return out

    @property
    def conclusion(self) -> bool | None:
        """What the entry concludes, by the one overall rule (``judge.conclude``): False when anything in
        it cannot be read, an answer is wrong or was not graded, None when nothing was judged (no verdict:
        every answer left empty), else True."""
        from mech.verification.judge import conclude, holds

        cells = self.cells
        return conclude((holds(None, j.match) for j in cells if j.cell is not State.UNANSWERED),
                        failed=self.invalid is not None)

    @property
    def ok(self) -> bool:
        """No failure: "no verdict" is none (as in ``mech solve``, ``sweep`` and ``check``)."""
        return self.conclusion is not False

    @property
    def ex_id(self) -> str:
        return self.exercise.id if self.exercise is not None else self.exercise_text

    def label(self) -> str:
        given = ", ".join(f"{k}={v}" for k, v in self.written.items())
        return f"answer {self.number}" + (f": {given}" if given else "")


def void_cell(name: str, unit: str, text: str, state: State, reason: str):
    """A cell no judge reached (``Judgement`` with its state and, as its verdict, the reason)."""
    from mech.students.answers import Judgement

    return Judgement(name, unit, text, math.nan, False, None, verdict=reason, state=state)


class BadFile(BadInput):
    """A grading file mech cannot use.  ``problems``: every problem found, each one line naming the file,
    the entry (and its line) and the field; the message is all of them, a line each."""

    def __init__(self, problems):
        self.problems = [problems] if isinstance(problems, str) else list(problems)
        super().__init__("\n".join(self.problems))


MAX_PROBLEMS = 50  # problems of a bad file listed before "... and N more"
MAX_INVALID_CHARS = 400  # an invalid entry's reason, as reported
# answers (expected values) of one file: each costs some 10 kB until the report (docs/grading.md); as
# each entry has one at least, as many [[answer]] tables, counted before the file is parsed
MAX_ANSWERS = 20_000
MAX_FORMULA_CHARS = 1_000_000  # formulas parsed in one file (a repeat read once is counted once), characters


class _Memo(dict):
    """The values already read in one file, by exercise, name and text; ``formula_chars``: the characters
    of the formulas parsed so far (a parsed formula holds some 60 bytes a character until the report)."""

    formula_chars = 0

    def __init__(self):
        super().__init__()
        self.resolved: dict = {}  # (exercise, parameters as written in SI) -> the joint checks' refusal or None


def _entry_lines(text: str) -> list[int]:
    return [i for i, line in enumerate(text.splitlines(), 1) if re.match(r"\s*\[\[\s*answer\s*\]\]", line)]


def _blank(value) -> bool:
    """An answer left for the student to fill: an empty (or blank) string."""
    return isinstance(value, str) and not value.strip()


class _Problems:
    """What is wrong with one answer: ``lines`` each naming ``where`` (the file and the entry), the field and
    the reason; ``reasons`` the same without ``where`` (the invalid entry's text)."""

    def __init__(self, where: str):
        self.where = where
        self.lines: list[str] = []
        self.reasons: list[str] = []

    def bad(self, fld: str, why: str) -> None:
        self.lines.append(f"{self.where}: {shown(fld)}: {why}")
        self.reasons.append(f"{shown(fld)}: {why}")

    def refused(self, exc: BadInput) -> None:
        """A problem whose message names its field already."""
        self.lines.append(f"{self.where}: {exc}")
        self.reasons.append(str(exc))

    def cell(self, fld: str, why: str, sep: str = ": ") -> str:
        """A problem of one cell (listed by ``--strict``; the entry's other cells are graded): its reason.
        ``sep``: "." where ``why`` is a message that starts with the output's name."""
        text = f"{shown(fld)}{sep}{' '.join(str(why).split())}"
        self.lines.append(f"{self.where}: {text}")
        return text


def _cell_reason(line: int | None, k: int, text: str) -> str:
    from mech.core.safeio import escape

    text = escape(text)
    text = f"line {line}: {text}" if line else f"answer {k}: {text}"
    return text if len(text) <= MAX_INVALID_CHARS else text[: MAX_INVALID_CHARS - 3] + "..."


def _read_entry(k: int, item: dict, line: int | None, where: str, keys=_ENTRY_KEYS,
                memo: dict | None = None, min_digits: int | None = None, against=None,
                every_param: bool = True) -> tuple[Entry, list[str]]:
    """One answer, read and checked: the Entry and its problems, each one line naming ``where`` (the file
    and the entry), the field and the reason.  A fault of the whole entry sets ``invalid``; an unreadable
    value voids its own cell only (``Entry.void``).  ``memo``: values already read in this file (a class
    writes the same formula many times), by exercise, name and text; ``min_digits``: the digits rule's
    floor; ``against``: the ``against.Assignment`` the entry is held to (its parameters, digits, range and
    outputs; ``every_param``: the answer must write every assigned parameter)."""
    found = _Problems(where)
    for key in item:
        if key not in keys:
            found.bad(key, f"unknown field; an answer has {', '.join(keys)}")
    ex_id = item.get("exercise")
    ex = _read_exercise(ex_id, found)
    student = _read_student(item.get("student"), found)
    if against is not None:
        for fld, why in against.refusals(item, ex, student):
            found.bad(fld, why)
    given, written = _read_params(ex, item.get("params", {}), found, memo)
    variant = against.variant(student, ex.id) if against is not None and ex is not None else None
    if variant is not None and not found.lines:
        for fld, why in against.params_problems(ex, variant, written, every_param):
            found.bad(fld, why)
        given, written = against.given(ex, variant)
    rtol = None
    if "rtol" in item and against is None:
        try:
            rtol = parse_rtol_value(item["rtol"], "rtol")
        except BadInput as exc:
            found.refused(exc)
    expectations, unanswered, columns, void = _read_expect(ex, item.get("expect"), rtol, memo, found, min_digits,
                                                           None if variant is None else variant.outputs)
    if ex is not None and not found.reasons and expectations:
        try:
            expectations = (_formula_range(ex, item, expectations) if against is None
                            else with_range(expectations, over=against.formula_range(ex)))
        except BadInput as exc:
            found.refused(exc)
    entry = Entry(k, line, ex, given, written, expectations, student=student, unanswered=unanswered,
                  exercise_text=shown("?" if ex_id is None else str(ex_id), 20), columns=columns)
    entry.void = [void_cell(n, _unit(ex, n), text, State.INVALID, _cell_reason(line, k, why)) for n, text, why in void]
    if found.reasons:
        expect = item.get("expect")
        entry.texts = ({shown(str(k).strip().replace("-", "_"), 40): shown(v) for k, v in expect.items()}
                       if isinstance(expect, dict) else {})
        entry.invalid_reason = "; ".join(" ".join(r.split()) for r in found.reasons)
        entry.invalid = _cell_reason(line, k, entry.invalid_reason)
        entry.expectations, entry.void, entry.unanswered = [], [], []  # every cell it names: invalid
    return entry, found.lines


def _unit(ex: Exercise | None, name: str) -> str:
    return next((o.unit for o in ex.outputs if o.name == name), "") if ex is not None else ""


def _read_exercise(ex_id, found: _Problems) -> Exercise | None:
    """The answer's exercise (None when it names none that mech knows)."""
    from mech.problems import registry

    if not isinstance(ex_id, str):
        found.bad("exercise", "missing, or not a string such as \"4.15\"")
        return None
    try:
        return registry.get(ex_id)
    except BadInput as exc:
        found.bad("exercise", str(exc))
        return None


def _read_params(ex: Exercise | None, params, found: _Problems, memo=None) -> tuple[dict, dict]:
    """The answer's parameters: (SI values, the values as written), each checked against its range (the
    joint checks once per exercise and values in a file: ``memo``)."""
    if not isinstance(params, dict):
        found.bad("params", "not a table such as { theta0 = \"60deg\" }")
        params = {}
    given, written = {}, {}
    for raw_name, value in params.items():
        if ex is None:
            break
        pname = str(raw_name).strip().replace("-", "_")
        if pname not in ex.param_map:
            found.bad(f"params.{raw_name}",
                      f"not a parameter of {ex.id}; its parameters are: {', '.join(ex.param_map)}")
            continue
        param = ex.param_map[pname]
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            found.bad(f"params.{raw_name}", "not a number or a string such as \"60deg\"")
            continue
        try:
            given[pname] = to_si(str(value), param.unit)
            param.check(given[pname])
        except (ValueError_, BadInput, OverflowError) as exc:
            why = exc.reason if isinstance(exc, BadInput) else str(exc)
            found.bad(f"params.{raw_name}", f"cannot use '{shown(value)}': {why}")
            given.pop(pname, None)
            continue
        written[pname] = shown(value, 40)
    if ex is not None and not found.lines:
        why = _joint_refusal(ex, given, getattr(memo, "resolved", None))
        if why is not None:
            found.bad("params", why)
    return given, written


def _joint_refusal(ex: Exercise, given: dict, seen: dict | None) -> str | None:
    """Why ``ex`` refuses the parameters ``given`` together (None: it takes them), once per file for the
    same values (``seen``; a class writes the same parameters thousands of times)."""
    key = (ex.id, tuple((k, float(v).hex()) for k, v in given.items()))
    if seen is not None and key in seen:
        return seen[key]
    try:
        ex.resolve(given)
        why = None
    except BadInput as exc:
        why = str(exc)
    if seen is not None and len(seen) < 10000:
        seen[key] = why
    return why


def _read_expect(ex: Exercise | None, expect, rtol, memo: dict | None, found: _Problems,
                 min_digits: int | None = None, asked: tuple | None = None):
    """The answer's expected values: (expectations, outputs left unanswered, outputs asked, the cells that
    cannot be read: (output, text, reason)).  ``asked``: the outputs an assignment asks (those not given
    are unanswered; one it does not ask is an invalid cell)."""
    expectations, unanswered, columns, void = [], [], [], []
    if asked is not None and (expect is None or expect == {}):
        expect = {}  # against an assignment: nothing answered, every output asked unanswered
    elif not isinstance(expect, dict) or not expect:
        found.bad("expect", "missing or empty; give a table such as { theta_c = \"35.26deg\" }")
        return expectations, unanswered, columns, void
    if ex is None:  # every output named is a cell of the entry (invalid with it)
        columns = list(dict.fromkeys(shown(str(k).strip().replace("-", "_"), 40) for k in expect))
        return expectations, unanswered, columns, void
    outputs = [o.name for o in ex.outputs]
    for raw_name, value in expect.items():
        name = str(raw_name).strip().replace("-", "_")
        if name in columns or shown(name, 40) in columns:
            found.bad(f"expect.{raw_name}", "given more than once")
            continue
        if name not in outputs:
            columns.append(shown(name, 40))
            void.append((shown(name, 40), shown(value), found.cell(
                f"expect.{raw_name}", f"not an output of {ex.id}; its outputs are: {', '.join(outputs)}")))
            continue
        columns.append(name)
        if asked is not None and name not in asked:
            void.append((name, shown(value), found.cell(f"expect.{raw_name}", "not asked by the assignment")))
            continue
        if _blank(value):
            unanswered.append(name)  # left for the student: not graded
            continue
        mkey = (ex.id, str(raw_name), type(value).__name__, str(value), rtol, min_digits)
        got = memo.get(mkey) if memo is not None else None
        if got is None:
            try:
                got = parse_expectation(ex, raw_name, value, rtol, min_digits=min_digits)
            except BadInput as exc:
                got = exc
            if isinstance(memo, _Memo) and getattr(got, "formula", None) is not None:
                memo.formula_chars += len(got.text)
                if memo.formula_chars > MAX_FORMULA_CHARS:  # the file's, not this entry's: refused whole
                    raise BadFile(f"{found.where}: the file's formulas pass {MAX_FORMULA_CHARS} characters; at "
                                  f"most {MAX_FORMULA_CHARS} are read (split the file)")
            if memo is not None and len(memo) < 10000:
                memo[mkey] = got
        if isinstance(got, BadInput):  # its message names the output: "expect." names the field
            fld, why = (f"expect.{got.field}", got.reason) if got.field else ("expect", str(got))
            void.append((name, shown(value), found.cell(fld, why, sep="." if not got.field else ": ")))
            continue
        expectations.append(got)
    for name in asked or ():
        if name not in columns:  # asked, not given: unanswered
            columns.append(name)
            unanswered.append(name)
    return expectations, unanswered, columns, void


def _read_student(student, found: _Problems) -> str | None:
    """The student's name, stripped (None when none is given, or it is not a one-line name)."""
    if student is None:
        return None
    if not isinstance(student, str) or not student.strip() or len(student.strip()) > MAX_STUDENT \
            or not student.strip().isprintable():
        found.bad("student", f"not a name such as \"alice\" (a one-line string of 1 to {MAX_STUDENT} "
                             "characters)")
        return None
    return student.strip()


def _refuse(name: str, problems: list[str]) -> None:
    if len(problems) > MAX_PROBLEMS:
        problems = problems[:MAX_PROBLEMS] + [f"{name}: ... and {len(problems) - MAX_PROBLEMS} more problems"]
    raise BadFile(problems)


def load_answers(path: str, strict: bool = True, *, min_digits: int | None = None, against=None) -> list[Entry]:
    """Read and check a whole grading file before anything is solved.

    A file that cannot be read, is not TOML, or has no ``[[answer]]`` tables: BadFile.  An entry that cannot
    be read: with ``strict``, BadFile listing every problem (a line each, naming the file, the entry and the
    field); without, the entry comes back ``invalid`` ("line N: the reason"), or the cell that cannot be
    read invalid, and the rest is graded.  ``min_digits``: the digits rule's floor; ``against``: the
    assignment (``against.Assignment``) every entry is held to, whose variants no entry answers come
    back unanswered (``Entry.assigned``)."""
    from mech.core.safeio import load_toml_text, shown_path

    if str(path).lower().endswith(".csv"):
        return load_answers_csv(path, strict=strict, min_digits=min_digits, against=against)
    name = shown_path(path)
    # BadInput naming the file: unreadable, too big, too deep, malformed, too many [[answer]] tables
    data, text = load_toml_text(path, "answers file", max_tables=(MAX_ANSWERS, "[[answer]] entries"))
    problems: list[str] = []
    for key in data:
        if key != "answer":
            problems.append(f"{name}: '{shown(key)}': unknown top-level key; answers go in [[answer]] tables")
    answers = data.get("answer")
    if not isinstance(answers, list) or not answers or not all(isinstance(a, dict) for a in answers):
        raise BadFile(problems + [f"{name}: no [[answer]] tables"])
    # the values, and the entries written inline (answer = [{...}, ...]) the pre-scan could not count
    values = sum(len(a["expect"]) if isinstance(a.get("expect"), dict) else 1 for a in answers)
    if values > MAX_ANSWERS:
        raise BadFile(f"{name}: {values} answers (expected values) in {len(answers)} entries; at most "
                      f"{MAX_ANSWERS} are read (split the file)")
    if problems:  # the file's own shape, not one entry's: nothing to grade
        _refuse(name, problems)
    lines = _entry_lines(text)
    entries = []
    memo = _Memo()
    for k, item in enumerate(answers, 1):
        line = lines[k - 1] if len(lines) == len(answers) else None
        where = f"{name}: answer {k}" + (f" (line {line})" if line else "")
        entry, found = _read_entry(k, item, line, where, memo=memo, min_digits=min_digits, against=against)
        problems += found
        entries.append(entry)
    if problems and strict:
        _refuse(name, problems)
    return entries + unanswered_variants(entries, against)


def unanswered_variants(entries: list[Entry], against) -> list[Entry]:
    """An entry for each of the assignment's variants that no entry answers: every output unanswered."""
    from mech.problems import registry

    if against is None:
        return []
    seen = {(e.student, e.ex_id) for e in entries}
    out = []
    for (student, ex_id), v in against.variants.items():
        if (student, ex_id) in seen:
            continue
        ex = registry.get(ex_id)
        given, written = against.given(ex, v)
        out.append(Entry(len(entries) + len(out) + 1, None, ex, given, written, [], student=student,
                         unanswered=list(v.outputs), columns=list(v.outputs), assigned=True))
    return out


def _formula_range(ex: Exercise, item: dict, expectations: list) -> list:
    """An answer's optional ``points``, ``seed`` and ``over`` (the range its formulas are meant to hold
    in), given to its formula expectations; BadInput naming the field."""
    from mech.students.points import parse_over

    if not any(k in item for k in ("points", "seed", "over")):
        return expectations
    if not any(e.formula is not None for e in expectations):
        raise BadInput(f"{next(k for k in ('points', 'seed', 'over') if k in item)}: only for formulas, and "
                       "this answer has none")
    from mech.students.points import MAX_POINTS

    points = parse_count(item["points"], "points", 1, MAX_POINTS) if "points" in item else None
    seed = parse_count(item["seed"], "seed", 0, 2**63 - 1) if "seed" in item else None
    over = item.get("over")
    if over is not None:
        if not isinstance(over, dict) or not over:
            raise BadInput("over: not a table such as { theta0 = \"10deg:60deg\" }")
        over = parse_over(ex, over)
    return with_range(expectations, points, seed, over)


# -- answers from a spreadsheet -------------------------------------------------------------------------

MAX_CSV_BYTES = 4 * 1024 * 1024
MAX_CSV_ROWS = 5000  # students
MAX_CSV_COLUMNS = 400
MAX_CSV_FIELD = 1000  # characters of one cell (a formula is at most ``formula_ast.MAX_LENGTH``)


def _csv_rows(path: str, what: str) -> list[tuple[int, list[str]]]:
    """The rows of a CSV file (with the line each starts on), its size, row count and cell length bounded
    before anything in it is used; BadFile naming the file otherwise."""
    import csv
    import io

    from mech.core.safeio import read_text, shown_path

    name = shown_path(path)
    text = read_text(path, what, limit=MAX_CSV_BYTES).lstrip("\ufeff")  # a spreadsheet's byte-order mark
    if text.count("\n") > MAX_CSV_ROWS + 1 and sum(1 for ln in text.splitlines() if ln.strip()) > MAX_CSV_ROWS + 1:
        raise BadFile(f"{name}: more than {MAX_CSV_ROWS} rows; at most {MAX_CSV_ROWS} students are read")
    reader = csv.reader(io.StringIO(text, newline=""), strict=True)
    rows = []
    try:
        while True:
            line = reader.line_num + 1
            try:
                row = next(reader)
            except StopIteration:
                break
            if len(row) > MAX_CSV_COLUMNS:
                raise BadFile(f"{name}: line {line}: {len(row)} columns; at most {MAX_CSV_COLUMNS}")
            for cell in row:
                if len(cell) > MAX_CSV_FIELD:
                    raise BadFile(f"{name}: line {line}: a cell of {len(cell)} characters; at most {MAX_CSV_FIELD}")
            if any(c.strip() for c in row):
                rows.append((line, row))
            if len(rows) > MAX_CSV_ROWS + 1:
                raise BadFile(f"{name}: more than {MAX_CSV_ROWS} rows; at most {MAX_CSV_ROWS} students are read")
    except csv.Error as exc:
        raise BadFile(f"{name}: malformed CSV: line {reader.line_num}: {shown(exc, 120)}") from None
    return rows


def _as_typed(cell: str) -> str:
    """A CSV cell as it was typed: the apostrophes that neutralised it for a spreadsheet taken out (a
    template's "'=ann"), so that what mech wrote (``core.safeio.csv_cell``) reads back as what it holds."""
    from mech.core.safeio import csv_uncell

    return csv_uncell(cell) if "'" in cell else cell


def _template_params(params_path: str) -> dict:
    """An assignment's template (``answers.toml``): (student, exercise) -> its params table."""
    from mech.core.safeio import load_toml, shown_path

    data = load_toml(params_path, "--params file")
    answers = data.get("answer")
    name = shown_path(params_path)
    if not isinstance(answers, list) or not all(isinstance(a, dict) for a in answers):
        raise BadFile(f"--params {name}: no [[answer]] tables")
    out = {}
    for a in answers:
        student, ex_id, params = a.get("student"), a.get("exercise"), a.get("params", {})
        if isinstance(student, str) and isinstance(ex_id, str) and isinstance(params, dict):
            out[(student.strip(), ex_id.strip())] = params
    return out


def _csv_columns(name: str, header: list[str]) -> tuple[dict, list[str], list[str]]:
    """A CSV header read: {index: (exercise id, name, "output" | "param")}, the exercises in order, and
    the problems found (each one line naming the file and the column)."""
    from mech.problems import registry

    problems = []
    if "student" not in header:
        problems.append(f"{name}: line 1: no 'student' column")
    columns = {}  # index -> (exercise id, name, "output" | "param")
    order: list[str] = []
    for i, h in enumerate(header):
        if h == "student" or h == "":
            continue
        if ":" not in h:
            problems.append(f"{name}: column '{shown(h, 40)}': not 'student' nor ID:NAME such as 4.15:theta_c")
            continue
        ex_id, _, col = h.partition(":")
        try:
            ex = registry.get(ex_id.strip())
        except BadInput as exc:
            problems.append(f"{name}: column '{shown(h, 40)}': {exc}")
            continue
        col = col.strip().replace("-", "_")
        kind = ("output" if col in {o.name for o in ex.outputs} else
                "param" if col in ex.param_map else None)
        if kind is None:
            problems.append(f"{name}: column '{shown(h, 40)}': not an output nor a parameter of {ex.id}; "
                            f"its outputs are {', '.join(o.name for o in ex.outputs)}")
            continue
        columns[i] = (ex.id, col, kind)
        if ex.id not in order:
            order.append(ex.id)
    named = [h for h in header if h]
    if len(set(named)) != len(named):
        problems.append(f"{name}: line 1: a column is named twice")
    if not any(kind == "output" for _, _, kind in columns.values()):
        problems.append(f"{name}: line 1: no ID:output column holding answers")
    return columns, order, problems


def load_answers_csv(path: str, strict: bool = True, params_path: str | None = None, *,
                     min_digits: int | None = None, against=None) -> list[Entry]:
    """Answers from a CSV file: a header row, then one row per student; a ``student`` column, ``ID:output``
    columns holding answers (an empty cell: not answered) and optional ``ID:param`` columns holding the
    parameters, else ``params_path`` (an assignment's template) gives each student's.  Each exercise of a
    row is an entry, read as an ``[[answer]]`` is; the header's faults refuse the file (BadFile)."""
    from mech.core.safeio import shown_path

    name = shown_path(path)
    rows = _csv_rows(path, "answers file")
    if not rows:
        raise BadFile(f"{name}: no header row")
    (_, header), body = rows[0], rows[1:]
    header = [h.strip() for h in header]
    columns, order, problems = _csv_columns(name, header)
    if problems:
        _refuse(name, problems)
    outs = sum(kind == "output" for _, _, kind in columns.values())
    if len(body) * outs > MAX_ANSWERS:  # a value per row and output column
        raise BadFile(f"{name}: {len(body)} rows of {outs} answer columns are {len(body) * outs} "
                      f"answers; at most {MAX_ANSWERS} are read (split the file)")
    template = _template_params(params_path) if params_path else None
    s_col = header.index("student")
    entries: list[Entry] = []
    all_problems: list[str] = []
    memo = _Memo()
    for line, row in body:
        row = row + [""] * (len(header) - len(row))
        student = _as_typed(row[s_col]).strip()
        for ex_id in order:
            item: dict = {"exercise": ex_id, "expect": {}}
            if student:
                item["student"] = student
            params = {}
            for i, (cid, col, kind) in columns.items():
                if cid != ex_id:
                    continue
                if kind == "output":
                    item["expect"][col] = _as_typed(row[i])
                elif row[i].strip():
                    params[col] = _as_typed(row[i]).strip()
            extra = []
            if template is not None and not params and against is None:
                params = template.get((student, ex_id))
                if params is None:
                    params = {}
                    extra.append(f"params: no answer for {shown(student or '(no student)', 40)} and {ex_id} "
                                 "in the --params file")
            if params:
                item["params"] = params
            if (against is not None and against.variant(student, ex_id) is None and not params
                    and all(_blank(v) for v in item["expect"].values())):
                continue  # a column of an exercise this student was not assigned, left empty
            if len(row) > len(header):
                extra.append(f"{len(row) - len(header)} cells beyond the header's columns")
            k = len(entries) + 1
            where = f"{name}: line {line}, {ex_id}"
            entry, found = _read_entry(k, item, line, where, memo=memo, min_digits=min_digits, against=against,
                                       every_param=False)
            if extra:  # the row's own faults: the whole entry, before anything it read
                found = [f"{where}: {x}" for x in extra] + found
                entry.invalid = _cell_reason(line, k, "; ".join(extra + ([entry.invalid_reason] if entry.invalid else [])))
                entry.expectations, entry.void, entry.unanswered = [], [], []
            entries.append(entry)
            all_problems += found
    if not entries:
        raise BadFile(f"{name}: no rows of answers under the header")
    if all_problems and strict:
        _refuse(name, all_problems)
    return entries + unanswered_variants(entries, against)



def read_answers(path, *, strict: bool = False, params=None, assignment=None,
                 min_digits: int | None = None) -> list[Entry]:
    """A grading file (TOML, or CSV: by its name) read into entries.  ``params``: a CSV's parameters from
    an assignment's template; ``assignment``: the folder ``mech assign`` wrote, every entry held to it (its
    parameters, digits, range and outputs; ``students.against``); ``min_digits``: the digits rule's floor
    (default ``MIN_DIGITS``; with an assignment, its digits, and no other may be given)."""
    from mech.students.against import load_assignment

    csv_file = str(path).lower().endswith(".csv")
    if params is not None and not csv_file:
        raise BadInput("only for answers read from a CSV file", field="--params", kind="usage")
    against = None
    if assignment is not None:
        if params is not None:
            raise BadInput("not with --assignment, which gives each student's parameters", field="--params",
                           kind="usage")
        if min_digits is not None:
            raise BadInput("not with --assignment, which fixes the digits", field="--min-digits", kind="usage")
        against = load_assignment(assignment)
        min_digits = against.digits
    min_digits = MIN_DIGITS if min_digits is None else min_digits
    if csv_file:
        return load_answers_csv(str(path), strict=strict, params_path=None if params is None else str(params),
                                min_digits=min_digits, against=against)
    return load_answers(str(path), strict=strict, min_digits=min_digits, against=against)
