"""Checking your own answers: expected values (``--expect``), answers files (``mech grade FILE``) and
``mech check`` baselines, read and judged.

Reading the files and values; the judging is ``mech.students.answers``, the baseline comparison
``mech.verification.baseline``; printing them is ``mech.cli.grading``'s.
"""

from __future__ import annotations

import json
import math
import re
import time
from dataclasses import dataclass, field


from mech.core.units import CONSTANTS, ValueError_, tokens, to_si
from mech.problems.spec import BadInput, Exercise
from mech.core.safeio import shown

__all__ = ["parse_expectation", "parse_expect_options", "attach", "Entry", "BadFile", "load_answers",
           "load_answers_csv", "grade", "grade_file", "grade_json", "GradeReport", "gradebook_csv", "csv_safe", "open_baseline", "check_records", "baselines"]


# -- one expected value ---------------------------------------------------------------------------------

def _literal_precision(literal: str) -> tuple[float, int | None]:
    """Half a unit in the last digit of a number as written, and its significant digits.

    ``35.26`` -> (0.005, 4); ``1e-3`` -> (5e-4, 1); ``3500`` -> (0.5, 4): trailing zeros of a whole
    number count (write ``3.5e3`` for two digits); ``0.000`` -> (5e-4, None).
    """
    mantissa, _, exp = literal.lower().partition("e")
    exponent = int(exp) if exp else 0
    whole, _, frac = mantissa.partition(".")
    last_place = exponent - len(frac)
    digits = (whole + frac).lstrip("0")
    return 0.5 * 10.0**last_place, (len(digits) or None)


def _unit_factor(text: str, toks: list[tuple[str, str]], i: int, unit: str) -> tuple[float, str]:
    """SI size of the unit written around the literal at token ``i`` (sign included), and that unit as
    written when it follows the literal alone (``35.26 deg`` -> ``deg``)."""
    factor = to_si(" ".join("1" if j == i else v for j, (_, v) in enumerate(toks)), unit)
    leads = i == 0 or (i == 1 and toks[0][1] in ("-", "+"))
    unit_text = text.split(toks[i][1], 1)[1].strip() if leads else ""
    return factor, unit_text


def parse_expectation(ex: Exercise, raw_name: str, text, rtol: float | None = None) -> Expectation:
    """``theta_c``, ``35.26deg`` -> an Expectation in SI; BadInput naming the output otherwise."""
    from mech.students.answers import Expectation

    name = str(raw_name).strip().replace("-", "_")
    outputs = {o.name: o for o in ex.outputs}
    if name not in outputs:
        raise BadInput(f"{raw_name}: not an output of {ex.id}; its outputs are: {', '.join(outputs)}")
    unit = outputs[name].unit
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise BadInput(f"{name}: expected a number or a string such as '1.23 {unit}', got {type(text).__name__}")
    text = str(text)
    from dataclasses import replace

    try:
        value = to_si(text, unit)
        toks = tokens(text)
    except ValueError_ as exc:
        formula = _formula(ex, name, text)
        if formula is not None:
            return replace(formula, rtol=rtol)
        why = str(exc).replace("but the parameter is", f"but {name} is")
        raise BadInput(f"{name}: cannot use '{shown(text)}': {why}" + ("" if why != str(exc) else f" ({name} is in {unit})")) from None
    # a value that names a parameter is a formula (``E=m*g*l``), unless it reads as a number of the
    # output's dimension and the formula would not have it (``x=3 m`` in 4.7, whose m is a mass)
    formula = _formula(ex, name, text, parameters_only=True, unit=unit)
    if formula is not None:
        return replace(formula, rtol=rtol)
    # the literals that set the value (not exponents of units such as the 2 of m/s^2)
    literals = [i for i, (k, _) in enumerate(toks) if k == "num"
                and not (i > 0 and toks[i - 1][1] in ("^", "**"))
                and not (i > 1 and toks[i - 1][1] in ("-", "+") and toks[i - 2][1] in ("^", "**"))]
    if len(literals) != 1 or any(k == "name" and v in CONSTANTS for k, v in toks):
        return _expression_expectation(name, text, value, [toks[i][1] for i in literals], rtol)
    try:
        half_unit, digits = _literal_precision(toks[literals[0]][1])
    except OverflowError:
        raise BadInput(f"{name}: cannot use '{shown(text)}': an exponent too large") from None
    factor, unit_text = _unit_factor(text, toks, literals[0], unit)
    return Expectation(name, text, value, half_unit * abs(factor), digits, rtol, unit_text, abs(factor))


def _formula(ex: Exercise, name: str, text: str, parameters_only: bool = False, unit: str | None = None):
    """An Expectation holding a formula when ``text`` is one (it names a parameter or a function), else
    None; BadInput (one line) when it is a formula mech cannot read.  ``parameters_only``: for a text that
    also reads as a number: a formula only if it names a parameter and has the dimension of ``unit``."""
    from mech.students.answers import Expectation
    from mech.students.formula_ast import (MAX_LENGTH, FormulaError, dim_of_unit, looks_like_formula,
                                               parse_formula)

    if len(text) > MAX_LENGTH:
        raise BadInput(f"{name}: formula too long ({len(text)} characters; at most {MAX_LENGTH})")
    if not looks_like_formula(text, ex, parameters_only):
        return None
    try:
        f = parse_formula(text, ex)
    except FormulaError as exc:
        if parameters_only:
            return None
        raise BadInput(f"{name}: cannot use the formula '{shown(text, 60)}': {exc}") from None
    if parameters_only and (not f.names or f.dim != dim_of_unit(unit)[1]):
        return None
    return Expectation(name, text, math.nan, formula=f)


def _short(text: str, n: int = 60) -> str:
    return text if len(text) <= n else text[: n - 3] + "..."


def with_range(expectations: list, points=None, seed=None, over=None) -> list:
    """The formula expectations given the number of drawn points, the seed and the range (others as they are)."""
    from dataclasses import replace

    return [replace(e, points=points if points is not None else e.points, seed=seed if seed is not None else e.seed,
                    over=tuple(sorted(over.items())) if over else e.over) if e.formula is not None else e
            for e in expectations]


def parse_count(text, what: str, lo: int, hi: int) -> int | None:
    """A whole number in [lo, hi] (None when not given); BadInput naming the option otherwise."""
    if text is None:
        return None
    try:
        value = None if isinstance(text, bool) else text if isinstance(text, int) else int(str(text).strip()[:40])
    except ValueError:
        value = None
    if value is None or not lo <= value <= hi:
        raise BadInput(f"{what}: cannot use '{shown(text, 40)}': allowed a whole number in [{lo}, {hi}]")
    return value


def _expression_expectation(name: str, text: str, value: float, literals: list[str], rtol) -> Expectation:
    """An expression (``(9.81*0.866)^0.5``, ``2*pi/921.5``) is judged to the digits of its least precise
    number, relative: a whole number written without a point or an exponent (the 2 of ``2*pi``) and
    ``pi`` are exact, and an expression of exact numbers only is exact (no written tolerance)."""
    from mech.students.answers import Expectation

    worst = None  # (relative half unit, digits, literal) of the least precise number
    for lit in literals:
        if not any(c in lit.lower() for c in ".e"):
            continue
        try:
            half_unit, digits = _literal_precision(lit)
            size = abs(float(lit))
        except (OverflowError, ValueError):
            continue
        if not digits or not (size > 0 and math.isfinite(size)):
            continue
        rel = half_unit / size
        if worst is None or rel > worst[0]:
            worst = (rel, digits, lit)
    if worst is None:
        return Expectation(name, text, value, 0.0, None, rtol)
    rel, digits, lit = worst
    return Expectation(name, text, value, rel * abs(value), digits, rtol, least_precise=lit)


def parse_rtol_value(text, what: str = "--expect-rtol") -> float:
    try:
        value = to_si(str(text), "1") if not isinstance(text, bool) else math.nan
    except ValueError_ as exc:
        raise BadInput(f"{what}: cannot use '{shown(text)}': {exc}; allowed (0, 1)") from None
    if not (0 < value < 1):
        raise BadInput(f"{what}: {text} is out of range; allowed (0, 1)")
    return value


def parse_expect_options(ex: Exercise, pairs: list[str], rtol_text: str | None) -> list[Expectation]:
    """The ``--expect NAME=VALUE`` options of ``mech solve``; BadInput on the first bad one."""
    if rtol_text is not None and not pairs:
        raise BadInput("--expect-rtol: given without any --expect NAME=VALUE")
    rtol = parse_rtol_value(rtol_text) if rtol_text is not None else None
    out: dict[str, Expectation] = {}
    for pair in pairs:
        if "=" not in pair:
            raise BadInput(f"--expect takes NAME=VALUE, got '{shown(pair)}'")
        try:
            e = parse_expectation(ex, *pair.split("=", 1), rtol=rtol)
        except BadInput as exc:
            raise BadInput(f"--expect {exc}") from None
        if e.name in out:
            raise BadInput(f"--expect {e.name}: given more than once")
        out[e.name] = e
    return list(out.values())


def attach(result, expectations: list[Expectation]):
    """The solution with every expectation judged on its quantity (``Quantity.expected``) and the summary
    line (``expect_summary``); ``.expect_ok`` says whether every expected value matches."""
    from mech.students.answers import judge

    return result.with_expected(judge(result, expectations))



# -- mech grade FILE ------------------------------------------------------------------------------------

_ENTRY_KEYS = ("exercise", "params", "expect", "rtol", "points", "seed", "over", "student")
MAX_STUDENT = 80  # characters of a student's name


@dataclass
class Entry:
    """One ``[[answer]]`` (or one exercise of a CSV row).  ``invalid``: "line N: the reason" when the entry
    cannot be read (it is then not graded, and counts as wrong); ``unanswered``: the outputs whose answer
    was left empty (``expect = { theta_c = "" }``, an assignment's template): not graded, an empty cell in
    the gradebook."""

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

    @property
    def conclusion(self) -> bool | None:
        """What the entry concludes, by the one overall rule (``judge.conclude``): False when it cannot be
        read or an answer is wrong, None when nothing was judged (no verdict: every answer left empty),
        else True."""
        from mech.verification.judge import conclude, holds

        return conclude((holds(None, j.match) for j in self.judgements), failed=self.invalid is not None)

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


def _read_entry(k: int, item: dict, line: int | None, where: str, keys=_ENTRY_KEYS,
                memo: dict | None = None) -> tuple[Entry, list[str]]:
    """One answer, read and checked: the Entry (``invalid`` set when anything is wrong) and its problems,
    each one line naming ``where`` (the file and the entry), the field and the reason.  ``memo``: values
    already read in this file (a class writes the same formula many times), by exercise, name and text."""
    found = _Problems(where)
    for key in item:
        if key not in keys:
            found.bad(key, f"unknown field; an answer has {', '.join(keys)}")
    ex_id = item.get("exercise")
    ex = _read_exercise(ex_id, found)
    given, written = _read_params(ex, item.get("params", {}), found)
    rtol = None
    if "rtol" in item:
        try:
            rtol = parse_rtol_value(item["rtol"], "rtol")
        except BadInput as exc:
            found.refused(exc)
    expectations, unanswered, columns = _read_expect(ex, item.get("expect"), rtol, memo, found)
    if ex is not None and not found.lines and expectations:
        try:
            expectations = _formula_range(ex, item, expectations)
        except BadInput as exc:
            found.refused(exc)
    student = _read_student(item.get("student"), found)
    entry = Entry(k, line, ex, given, written, expectations, student=student, unanswered=unanswered,
                  exercise_text=shown("?" if ex_id is None else str(ex_id), 20), columns=columns)
    if found.lines:
        from mech.core.safeio import escape

        text = escape("; ".join(" ".join(r.split()) for r in found.reasons))
        text = f"line {line}: {text}" if line else f"answer {k}: {text}"
        entry.invalid = text if len(text) <= MAX_INVALID_CHARS else text[: MAX_INVALID_CHARS - 3] + "..."
        entry.expectations = []
    return entry, found.lines


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


def _read_params(ex: Exercise | None, params, found: _Problems) -> tuple[dict, dict]:
    """The answer's parameters: (SI values, the values as written), each checked against its range."""
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
            why = str(exc).removeprefix(f"{pname}: ")
            found.bad(f"params.{raw_name}", f"cannot use '{shown(value)}': {why}")
            given.pop(pname, None)
            continue
        written[pname] = shown(value, 40)
    if ex is not None and not found.lines:
        try:
            ex.resolve(given)
        except BadInput as exc:
            found.bad("params", str(exc))
    return given, written


def _read_expect(ex: Exercise | None, expect, rtol, memo: dict | None, found: _Problems):
    """The answer's expected values: (expectations, outputs left unanswered, outputs asked)."""
    expectations, unanswered, columns = [], [], []
    if not isinstance(expect, dict) or not expect:
        found.bad("expect", "missing or empty; give a table such as { theta_c = \"35.26deg\" }")
        return expectations, unanswered, columns
    if ex is None:
        return expectations, unanswered, columns
    outputs = {o.name for o in ex.outputs}
    for raw_name, value in expect.items():
        name = str(raw_name).strip().replace("-", "_")
        if name in columns:
            found.bad(f"expect.{raw_name}", "given more than once")
            continue
        if name in outputs:
            columns.append(name)
        if name in outputs and _blank(value):
            unanswered.append(name)  # left for the student: not graded
            continue
        mkey = (ex.id, str(raw_name), type(value).__name__, str(value), rtol)
        got = memo.get(mkey) if memo is not None else None
        if got is None:
            try:
                got = parse_expectation(ex, raw_name, value, rtol)
            except BadInput as exc:
                got = BadInput(str(exc))
            if isinstance(memo, _Memo) and getattr(got, "formula", None) is not None:
                memo.formula_chars += len(got.text)
                if memo.formula_chars > MAX_FORMULA_CHARS:  # the file's, not this entry's: refused whole
                    raise BadFile(f"{found.where}: the file's formulas pass {MAX_FORMULA_CHARS} characters; at "
                                  f"most {MAX_FORMULA_CHARS} are read (split the file)")
            if memo is not None and len(memo) < 10000:
                memo[mkey] = got
        if isinstance(got, BadInput):
            found.bad(f"expect.{raw_name}", str(got).split(": ", 1)[-1])
            continue
        expectations.append(got)
    return expectations, unanswered, columns


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


def load_answers(path: str, strict: bool = True) -> list[Entry]:
    """Read and check a whole grading file before anything is solved.

    A file that cannot be read, is not TOML, or has no ``[[answer]]`` tables: BadFile.  An entry that cannot
    be read: with ``strict``, BadFile listing every problem (a line each, naming the file, the entry and the
    field); without, the entry comes back ``invalid`` ("line N: the reason") and the rest is graded."""
    from mech.core.safeio import load_toml_text, shown_path

    if str(path).lower().endswith(".csv"):
        return load_answers_csv(path, strict=strict)
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
        entry, found = _read_entry(k, item, line, where, memo=memo)
        problems += found
        entries.append(entry)
    if problems and strict:
        _refuse(name, problems)
    return entries


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


def load_answers_csv(path: str, strict: bool = True, params_path: str | None = None) -> list[Entry]:
    """Answers from a CSV file: a header row, then one row per student; a ``student`` column, ``ID:output``
    columns holding answers (an empty cell: not answered) and optional ``ID:param`` columns holding the
    parameters, else ``params_path`` (an assignment's template) gives each student's.  Each exercise of a
    row is an entry, read as an ``[[answer]]`` is; the header's faults refuse the file (BadFile)."""
    from mech.core.safeio import shown_path
    from mech.problems import registry

    name = shown_path(path)
    rows = _csv_rows(path, "answers file")
    if not rows:
        raise BadFile(f"{name}: no header row")
    (_, header), body = rows[0], rows[1:]
    header = [h.strip() for h in header]
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
        student = row[s_col].strip()
        for ex_id in order:
            item: dict = {"exercise": ex_id, "expect": {}}
            if student:
                item["student"] = student
            params = {}
            for i, (cid, col, kind) in columns.items():
                if cid != ex_id:
                    continue
                if kind == "output":
                    item["expect"][col] = row[i]
                elif row[i].strip():
                    params[col] = row[i].strip()
            extra = []
            if template is not None and not params:
                params = template.get((student, ex_id))
                if params is None:
                    params = {}
                    extra.append(f"params: no answer for {shown(student or '(no student)', 40)} and {ex_id} "
                                 "in the --params file")
            if params:
                item["params"] = params
            if len(row) > len(header):
                extra.append(f"{len(row) - len(header)} cells beyond the header's columns")
            k = len(entries) + 1
            where = f"{name}: line {line}, {ex_id}"
            entry, found = _read_entry(k, item, line, where, memo=memo)
            if extra:
                found = [f"{where}: {x}" for x in extra] + found
                text = "; ".join(extra)
                entry.invalid = f"line {line}: {text}" + (f"; {entry.invalid.split(': ', 1)[1]}" if entry.invalid else "")
                entry.expectations = []
            entries.append(entry)
            all_problems += found
    if not entries:
        raise BadFile(f"{name}: no rows of answers under the header")
    if all_problems and strict:
        _refuse(name, all_problems)
    return entries


# -- the grading -----------------------------------------------------------------------------------------

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


def _not_graded(entry: Entry, why: str):
    """Judgements saying why ``entry``'s answers were not graded (each wrong: mech has no verdict)."""
    from mech.students.answers import Judgement

    units = {o.name: o.unit for o in entry.exercise.outputs}
    return [Judgement(e.name, units.get(e.name, ""), e.text, e.value, False, None, verdict=why)
            for e in entry.expectations]


def _grade_one(entry: Entry, deadline: float, total_s: float, per_solve: float, solved: dict) -> None:
    """One entry, cross-checked and judged; whatever goes wrong in it (an overflow, a bug in mech) is
    this entry's verdict, never the rest of the class's."""
    from mech.core import budget
    from mech.students.answers import judge
    from mech.verification.crosscheck import cross_check
    from mech.verification.result import Failure

    t0 = time.perf_counter()
    try:
        params = entry.exercise.resolve(entry.given)
        key = (entry.exercise.id, tuple(sorted(params.items())))
        left = deadline - time.monotonic()
        if key in solved:
            result = solved[key]
            left = max(deadline - time.monotonic(), 1e-3)
            with budget.limit(left, what="grading (--budget gives it more)"):  # formulas too
                entry.judgements = judge(result, entry.expectations)
        elif left <= 0.05:
            why = f"not graded: the total budget of {total_s:g} s ran out (--budget SECONDS gives it more)"
            result = cross_check(entry.exercise, params, methods=("analytic",), verify=False)
            result = result.replace(errors=tuple(result.errors) + (Failure("numeric", f"numeric solver failed: {why}"),))
            entry.judgements = _not_graded(entry, why)
        else:
            result = solved[key] = cross_check(entry.exercise, params, budget_s=min(per_solve, left))
            left = max(deadline - time.monotonic(), 1e-3)
            with budget.limit(left, what="grading (--budget gives it more)"):  # formulas too
                entry.judgements = judge(result, entry.expectations)
        entry.result = result.with_expected(entry.judgements)
    except (BadInput, ArithmeticError, ValueError) as exc:  # this entry's numbers: its own verdict
        entry.result = None
        entry.judgements = _not_graded(entry, f"not graded: {shown(exc, 160)}")
    except MemoryError:  # not a bug: this entry asked for more memory than the process had left
        entry.result = None
        entry.judgements = _not_graded(entry, "not graded: out of memory")
    except Exception as exc:  # noqa: BLE001  a bug in mech, met on this entry only
        entry.result = None
        entry.judgements = _not_graded(entry, f"not graded: an internal error in mech ({type(exc).__name__}: "
                                              f"{shown(exc, 120)}); please report it")
    entry.seconds = time.perf_counter() - t0  # this entry's own work: its solve where it was the first


def _solve_groups(todo: list[Entry]) -> list[list[int]]:
    """The entries to grade, grouped by what they are solved at (one cross-check per group), the long
    groups first (those that integrate equations of motion), so that the last to finish is a short one."""
    groups: dict = {}
    for i, e in enumerate(todo):
        key = (e.exercise.id, tuple(sorted(e.given.items())))
        groups.setdefault(key, []).append(i)
    order = sorted(groups.values(), key=lambda g: (not todo[g[0]].exercise.states, g[0]))
    return order


_POOL: dict = {}  # what a forked worker inherits: the entries and the budget


def _remote_group(indices: list[int], presolved: dict | None = None):
    """Entries graded in a pool worker (``presolved``: {key: Solution without its exercise}, from a batch);
    what travels back pickles (no exercise, no run)."""
    todo, deadline, total_s, per_solve = _POOL["args"]
    solved: dict = {}
    for key, sol in (presolved or {}).items():
        solved[key] = sol.replace(exercise=todo[indices[0]].exercise) if sol is not None else None
    solved = {k: v for k, v in solved.items() if v is not None}
    out = []
    for i in indices:
        e = todo[i]
        _grade_one(e, deadline, total_s, per_solve, solved)
        result = e.result.replace(exercise=None, run=None) if e.result is not None else None
        out.append((i, result, e.judgements, e.seconds))
    return out


def _remote_batch(firsts: list[int]) -> dict:
    """A batched exercise's variants solved in a pool worker: {key: Solution without its exercise}."""
    todo, deadline, _total_s, _per_solve = _POOL["args"]
    got = _batched_solve([todo[i] for i in firsts], deadline)
    return {k: v.replace(exercise=None, run=None) for k, v in got.items()}


def grade(entries: list[Entry], total_s: float | None = None, jobs: int | None = None) -> None:
    """Cross-check and judge every readable entry, within a total wall-clock budget (``total_s``, default
    ``DEFAULT_TOTAL_S``): each solve gets what is left when that is less than its own budget, and an
    entry reached after the end is not graded: its answers fail, saying so.  ``jobs``: processes (None:
    one per core once there are enough entries; each worker runs a cross-check's rerun after its solve)."""
    import threading

    from mech.core import budget
    from mech.studies.checking import plan_jobs
    from mech.studies.sweep import DEFAULT_TOTAL_S, check_total

    total_s = DEFAULT_TOTAL_S if total_s is None else check_total(total_s)
    deadline = time.monotonic() + total_s
    per_solve = budget.default_seconds()
    todo = [e for e in entries if e.invalid is None and e.expectations]
    groups = _solve_groups(todo)
    # a class file answers the same exercise at the same parameters: one solve each; an exercise with a
    # batched route solves all its variants at once
    plan = _batch_plan(todo, groups)
    workers = plan_jobs(len(groups), jobs)
    # fork only a single-threaded process (a lock another thread holds would stay held in the workers)
    if workers > 1 and threading.active_count() == 1:
        _grade_pooled(todo, groups, workers, deadline, total_s, per_solve, plan)
        return
    solved: dict = {}
    for gidx in plan.values():
        solved.update(_batched_solve([todo[groups[g][0]] for g in gidx], deadline))
    for g in groups:
        for i in g:
            _grade_one(todo[i], deadline, total_s, per_solve, solved)


MIN_BATCHED = 4  # variants of one exercise from which its batched route solves them (below: one by one)


def _batch_plan(todo: list[Entry], groups: list[list[int]]) -> dict:
    """{exercise id: the indices of its groups} for each exercise whose batched route (the charts') gives
    all its outputs, with a tighter rerun to verify by, and at least ``MIN_BATCHED`` variants."""
    by_ex: dict = {}
    for k, g in enumerate(groups):
        ex = todo[g[0]].exercise
        route = getattr(ex, "batched_route", None)
        if route is None or set(route.outputs) != {o.name for o in ex.outputs}:
            continue
        if max(ex.default_rtol / 10.0, ex.min_rtol) >= ex.default_rtol:
            continue  # no tighter rerun to verify with: the cross-check says so point by point
        by_ex.setdefault(ex.id, []).append(k)
    return {i: ks for i, ks in by_ex.items() if len(ks) >= MIN_BATCHED}


def _batched_solve(firsts: list[Entry], deadline: float) -> dict:
    """The cross-checks of the variants of one exercise (an entry at each), solved at once: both solves
    (at rtol and rtol/10) over the variants' arrays and each variant judged by the cross-check's rule
    (``sweep.run_batched``).  {(exercise id, params): Solution}; empty when the batch fails as a whole
    (each variant is then cross-checked alone)."""
    import numpy as np

    from mech.studies.sweep import iter_batched_solutions, run_batched

    out: dict = {}
    ex = firsts[0].exercise
    try:
        params = [ex.resolve(e.given) for e in firsts]
        P = {p.name: np.array([float(q[p.name]) for q in params]) for p in ex.params}
        left = deadline - time.monotonic()
        if left <= 1.0:
            return out
        result = run_batched(ex, [], {}, tuple(o.name for o in ex.outputs), total_s=left, points=P)
        for q, sol in zip(params, iter_batched_solutions(result)):
            out[(ex.id, tuple(sorted(q.items())))] = sol
    except Exception:  # noqa: BLE001  the batch failed as a whole: each variant is cross-checked alone
        return {}
    return out


def _grade_pooled(todo, groups, workers, deadline, total_s, per_solve, plan) -> None:
    """The groups over a pool of ``workers``: a batched exercise's variants are solved by one worker while
    the others grade the rest, then its groups are graded with the batch's solutions."""
    import multiprocessing
    import os
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

    from mech.studies.sweep import pool_worker_init

    _POOL["args"] = (todo, deadline, total_s, per_solve)
    batched = {k for ks in plan.values() for k in ks}
    rest = [g for k, g in enumerate(groups) if k not in batched]
    # a few groups a task: fewer round trips, and still the work shared out to the end
    size = max(1, min(8, len(groups) // (8 * workers)))
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"),
                               initializer=pool_worker_init, initargs=(os.getpid(),))

    def take(got):
        for i, result, judgements, seconds in got:
            e = todo[i]
            e.judgements, e.seconds = judgements, seconds
            e.result = result.replace(exercise=e.exercise) if result is not None else None

    from concurrent.futures.process import BrokenProcessPool

    pending: dict = {}  # future -> ("batch", group indices) or ("grade", entry indices)
    try:
        for ex_id, ks in plan.items():
            pending[pool.submit(_remote_batch, [groups[k][0] for k in ks])] = ("batch", ks)
        for k in range(0, len(rest), size):
            indices = sum(rest[k:k + size], [])
            pending[pool.submit(_remote_group, indices)] = ("grade", indices)
        while pending:
            done, _ = wait(list(pending), return_when=FIRST_COMPLETED)
            for fut in done:
                kind, ks = pending[fut]
                got = fut.result()  # a dead worker raises here, its entries still pending
                del pending[fut]
                if kind == "grade":
                    take(got)
                    continue
                solved = got  # the batch: now its groups, a few a task, each with its solution
                for k in range(0, len(ks), size):
                    chunk = ks[k:k + size]
                    indices = sum((groups[j] for j in chunk), [])
                    keys = {(todo[groups[j][0]].exercise.id, tuple(sorted(todo[groups[j][0]].exercise.resolve(
                        todo[groups[j][0]].given).items()))) for j in chunk}
                    pre = {key: solved[key] for key in keys if key in solved}
                    pending[pool.submit(_remote_group, indices, pre)] = ("grade", indices)
    except BrokenProcessPool as exc:  # a worker died (killed, out of memory): its entries say so, not the class
        why = f"not graded: the process grading it stopped ({shown(exc, 100) or 'killed'}); grade again with -j 1"
        for kind, ks in pending.values():
            indices = ks if kind == "grade" else sum((groups[j] for j in ks), [])
            for i in indices:
                if not todo[i].judgements:
                    todo[i].judgements = _not_graded(todo[i], why)
        pool.shutdown(wait=False, cancel_futures=True)
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    finally:
        _POOL.clear()
    pool.shutdown(wait=True)


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


def grade_file(path, total_s=None, *, strict: bool = False, jobs: int | None = None, params=None,
               started: float | None = None) -> GradeReport:
    """A grading file (TOML, or CSV: by its name) read, graded and reported; ``params``: a CSV's parameters
    from an assignment's template; ``started``: the ``time.perf_counter()`` the reported wall time counts
    from (default: now, reading the file included)."""
    t0 = time.perf_counter() if started is None else started
    csv_file = str(path).lower().endswith(".csv")
    if params is not None and not csv_file:
        raise BadInput("--params: only for answers read from a CSV file")
    if csv_file:
        entries = load_answers_csv(str(path), strict=strict, params_path=None if params is None else str(params))
    else:
        entries = load_answers(str(path), strict=strict)
    grade(entries, total_s, jobs=jobs)
    return GradeReport(str(path), tuple(entries), time.perf_counter() - t0)


# -- mech check --save-baseline / --baseline ------------------------------------------------------------

def open_baseline(path: str) -> dict:
    """A baseline file, read and checked before the run (BadInput: one line naming the file and field)."""
    from mech.core.safeio import load_json, shown, shown_path
    from mech.verification import baseline

    data = load_json(path, "baseline")  # a regular file under 10 MB, nesting bounded, finite numbers
    problem = baseline.validate(data)
    if problem:
        raise BadInput(f"{shown_path(path)}: {shown(problem, 300)}")
    return data


def check_records(report) -> list[dict]:
    from mech.verification import baseline

    return [baseline.record_case(c.exercise.id, c.label, getattr(c.result, "params", None) or c.given, c.ok,
                                 getattr(c.result, "quantities", None)) for c in report.cases]


def baselines(report, hard: bool, old: dict | None, old_path: str | None, save_path: str | None):
    """Compare this check with a loaded baseline and/or save it as one; the Comparison or None."""
    from mech.verification import baseline

    records = check_records(report)
    cmp = baseline.compare(old, records, old_path or "") if old is not None else None
    if save_path:
        from mech.core.safeio import atomic_write

        text = json.dumps(baseline.make(records, hard), indent=1, allow_nan=False) + "\n"
        with atomic_write(save_path, "--save-baseline") as fh:  # a failed write leaves the old file whole
            fh.write(text)
    return cmp
