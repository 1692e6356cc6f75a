"""Checking your own answers: expected values (``--expect``), answers files (``mech grade FILE``) and
``mech check`` baselines, read and judged.

Reading the files and values; the judging is ``mech.verification.answers``, the baseline comparison
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
           "grade", "grade_json", "open_baseline", "check_records", "baselines"]


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
    from mech.verification.answers import Expectation

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
    from mech.verification.answers import Expectation
    from mech.verification.formula_ast import (MAX_LENGTH, FormulaError, dim_of_unit, looks_like_formula,
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
    from mech.verification.answers import Expectation

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
    from mech.verification.answers import judge

    return result.with_expected(judge(result, expectations))



# -- mech grade FILE ------------------------------------------------------------------------------------

_ENTRY_KEYS = ("exercise", "params", "expect", "rtol", "points", "seed", "over", "student")
MAX_STUDENT = 80  # characters of a student's name


@dataclass
class Entry:
    number: int  # 1-based, in file order
    line: int | None
    exercise: Exercise
    given: dict  # SI
    written: dict  # the parameters as written, for labels
    expectations: list
    result: object = None
    judgements: list = field(default_factory=list)
    student: str | None = None  # `student = "alice"`: names the entry in every report
    seconds: float = 0.0  # the cross-check's wall time

    @property
    def ok(self) -> bool:
        return bool(self.judgements) and all(j.match for j in self.judgements)

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


def _entry_lines(text: str) -> list[int]:
    return [i for i, line in enumerate(text.splitlines(), 1) if re.match(r"\s*\[\[\s*answer\s*\]\]", line)]


def load_answers(path: str) -> list[Entry]:
    """Read and check a whole grading file before anything is solved; BadFile listing every problem."""
    from mech.problems import registry
    from mech.core.safeio import load_toml_text, shown, shown_path

    name = shown_path(path)
    data, text = load_toml_text(path, "answers file")  # BadInput naming the file: unreadable, too big, too deep, malformed
    problems: list[str] = []
    for key in data:
        if key != "answer":
            problems.append(f"{name}: '{shown(key)}': unknown top-level key; answers go in [[answer]] tables")
    answers = data.get("answer")
    if not isinstance(answers, list) or not answers or not all(isinstance(a, dict) for a in answers):
        raise BadFile(problems + [f"{name}: no [[answer]] tables"])
    lines = _entry_lines(text)
    entries = []
    for k, item in enumerate(answers, 1):
        line = lines[k - 1] if len(lines) == len(answers) else None
        where = f"{name}: answer {k}" + (f" (line {line})" if line else "")
        found = len(problems)

        def bad(fld: str, why: str) -> None:
            problems.append(f"{where}: {shown(fld)}: {why}")

        for key in item:
            if key not in _ENTRY_KEYS:
                bad(key, f"unknown field; an answer has {', '.join(_ENTRY_KEYS)}")
        ex_id = item.get("exercise")
        ex = None
        if not isinstance(ex_id, str):
            bad("exercise", "missing, or not a string such as \"4.15\"")
        else:
            try:
                ex = registry.get(ex_id)
            except BadInput as exc:
                bad("exercise", str(exc))
        params = item.get("params", {})
        if not isinstance(params, dict):
            bad("params", "not a table such as { theta0 = \"60deg\" }")
            params = {}
        given, written = {}, {}
        for raw_name, value in params.items():
            if ex is None:
                break
            pname = raw_name.strip().replace("-", "_")
            if pname not in ex.param_map:
                bad(f"params.{raw_name}", f"not a parameter of {ex.id}; its parameters are: {', '.join(ex.param_map)}")
                continue
            param = ex.param_map[pname]
            if isinstance(value, bool) or not isinstance(value, (str, int, float)):
                bad(f"params.{raw_name}", "not a number or a string such as \"60deg\"")
                continue
            try:
                given[pname] = to_si(str(value), param.unit)
                param.check(given[pname])
            except (ValueError_, BadInput, OverflowError) as exc:
                why = str(exc).removeprefix(f"{pname}: ")
                bad(f"params.{raw_name}", f"cannot use '{shown(value)}': {why}")
                given.pop(pname, None)
                continue
            written[pname] = shown(value, 40)
        if ex is not None and len(problems) == found:
            try:
                ex.resolve(given)
            except BadInput as exc:
                bad("params", str(exc))
        rtol = None
        if "rtol" in item:
            try:
                rtol = parse_rtol_value(item["rtol"], "rtol")
            except BadInput as exc:
                problems.append(f"{where}: {exc}")
        expect = item.get("expect")
        expectations = []
        if not isinstance(expect, dict) or not expect:
            bad("expect", "missing or empty; give a table such as { theta_c = \"35.26deg\" }")
        elif ex is not None:
            for raw_name, value in expect.items():
                try:
                    expectations.append(parse_expectation(ex, raw_name, value, rtol))
                except BadInput as exc:
                    bad(f"expect.{raw_name}", str(exc).split(": ", 1)[-1])
                    continue
                if [e.name for e in expectations].count(expectations[-1].name) > 1:
                    bad(f"expect.{raw_name}", "given more than once")
        if ex is not None and len(problems) == found:
            try:
                expectations = _formula_range(ex, item, expectations)
            except BadInput as exc:
                problems.append(f"{where}: {exc}")
        student = item.get("student")
        if student is not None:
            if not isinstance(student, str) or not student.strip() or len(student.strip()) > MAX_STUDENT \
                    or not student.strip().isprintable():
                bad("student", f"not a name such as \"alice\" (a one-line string of 1 to {MAX_STUDENT} "
                               "characters)")
                student = None
            else:
                student = student.strip()
        if len(problems) == found and ex is not None:
            entries.append(Entry(k, line, ex, given, written, expectations, student=student))
    if problems:
        if len(problems) > MAX_PROBLEMS:
            problems = problems[:MAX_PROBLEMS] + [f"{name}: ... and {len(problems) - MAX_PROBLEMS} more problems"]
        raise BadFile(problems)
    return entries


def _formula_range(ex: Exercise, item: dict, expectations: list) -> list:
    """An answer's optional ``points``, ``seed`` and ``over`` (the range its formulas are meant to hold
    in), given to its formula expectations; BadInput naming the field."""
    from mech.verification.formulas import parse_over

    if not any(k in item for k in ("points", "seed", "over")):
        return expectations
    if not any(e.formula is not None for e in expectations):
        raise BadInput(f"{next(k for k in ('points', 'seed', 'over') if k in item)}: only for formulas, and "
                       "this answer has none")
    from mech.verification.points import MAX_POINTS

    points = parse_count(item["points"], "points", 1, MAX_POINTS) if "points" in item else None
    seed = parse_count(item["seed"], "seed", 0, 2**63 - 1) if "seed" in item else None
    over = item.get("over")
    if over is not None:
        if not isinstance(over, dict) or not over:
            raise BadInput("over: not a table such as { theta0 = \"10deg:60deg\" }")
        over = parse_over(ex, over)
    return with_range(expectations, points, seed, over)


def per_student(entries: list[Entry]) -> list[dict]:
    """For each student named in the file (in order of first appearance; entries without a name under
    null): answers right and wrong, and entries."""
    out: dict = {}
    for e in entries:
        s = out.setdefault(e.student, {"student": e.student, "passed": 0, "failed": 0, "entries": 0})
        s["entries"] += 1
        for j in e.judgements:
            s["passed" if j.match else "failed"] += 1
    return list(out.values())


def grade(entries: list[Entry], total_s: float | None = None) -> None:
    """Cross-check and judge every entry, within a total wall-clock budget (``total_s``, default
    ``DEFAULT_TOTAL_S``): each solve gets what is left when that is less than its own budget, and an
    entry reached after the end is not graded: its answers fail, saying so."""
    from mech.core import budget
    from mech.verification.answers import Judgement, judge
    from mech.verification.crosscheck import cross_check
    from mech.verification.result import Failure
    from mech.verification.sweep import DEFAULT_TOTAL_S, check_total

    total_s = DEFAULT_TOTAL_S if total_s is None else check_total(total_s)
    deadline = time.monotonic() + total_s
    per_solve = budget.default_seconds()
    solved: dict = {}  # a class file answers the same exercise at the same parameters: one solve each
    for entry in entries:
        t0 = time.perf_counter()
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
            units = {o.name: o.unit for o in entry.exercise.outputs}
            entry.judgements = [Judgement(e.name, units.get(e.name, ""), e.text, e.value, False, None, verdict=why)
                                for e in entry.expectations]
        else:
            result = solved[key] = cross_check(entry.exercise, params, budget_s=min(per_solve, left))
            left = max(deadline - time.monotonic(), 1e-3)
            with budget.limit(left, what="grading (--budget gives it more)"):  # formulas too
                entry.judgements = judge(result, entry.expectations)
        entry.result = result.with_expected(entry.judgements)
        entry.seconds = time.perf_counter() - t0  # this entry's own work: its solve where it was the first


def grade_json(path: str, entries: list[Entry], seconds: float) -> dict:
    judgements = [j for e in entries for j in e.judgements]
    passed = sum(j.match for j in judgements)
    return {
        "file": path,
        "entries": [{"exercise": e.exercise.id, "answer": e.number, "student": e.student,
                     "params": dict(e.result.params), "quantities": e.result.to_dict()["quantities"],
                     "agree": e.result.agree, "ok": e.ok, "seconds": e.seconds}
                    for e in entries],
        "ok": passed == len(judgements),
        "passed": passed,
        "failed": len(judgements) - passed,
        "students": [{k: v for k, v in s.items()} for s in per_student(entries) if s["student"] is not None],
        "seconds": seconds,
    }


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
