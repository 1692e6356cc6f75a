"""``mech assign``: personal variants for a class, each verified before it is issued, with its key.

For each exercise the parameter sets are drawn as a formula's judging points are (``points.draw``,
inside every joint constraint) but inside each parameter's typical range (``Param.typical``: the
catalogue's, within a factor 3 of the textbook value by default, a constant of nature or of the Earth
fixed) unless ``--over`` gives another, from a seed made of the class's seed and the exercise's id, so a
roster's students take the draws in roster order.  Each value is rounded to ``digits`` significant
digits in the unit a handout prints (degrees for an angle), written as the handout shows it, and read
back exactly as ``mech grade`` will read it; the rounded variant must still lie inside the bounds, the
joint constraints and its ranges.  A cheap screen (``_promising``: the analytic values finite and in the
statement's regime, the theory's own neglect estimate small) throws out hopeless draws; the rest are
solved by both methods, and a variant is issued only where they agree, every output is finite, every
leading-order value lies within 1 % of the exact one and the regime holds (``_record``); otherwise the
student takes the next draw.

The files (``Assignment.files``): ``handout.md`` and ``handouts/<slug>.md``, ``answers.toml`` and
``answers.csv``, ``key.json``, ``key.csv`` and ``key.md``; every name from the roster escaped where it is
written (``safeio.md_text``, ``csv_cell``, ``slugs``).

Everything written is a function of the roster, the seed, the digits, the ranges and mech's version:
no time stamps, the JSON's keys sorted, floats as Python's shortest round-trip ``repr``.
"""

from __future__ import annotations

import json
import math
import re
import zlib
from dataclasses import dataclass, field

from mech.core.errors import BadInput
from mech.core.safeio import shown
from mech.problems.validity import expected_errors
from mech.verification.judge import within

__all__ = ["Assignment", "Variant", "read_roster", "parse_overs", "make", "assign", "MAX_STUDENTS"]

MAX_STUDENTS = 2000
MAX_ROSTER_BYTES = 256 * 1024
MAX_TRIES = 40  # verified draws a student may take for one exercise before mech gives up (a loud one line)
MAX_DRAWS_PER_VARIANT = 200  # draws screened (rounded, analytic, regime) per variant before mech gives up
# draws of an exercise none of which passes the screen: refused at once (a pass rate of 1/MAX_DRAWS_PER_VARIANT
# leaves all of them out with a chance of exp(-10)), rather than after MAX_DRAWS_PER_VARIANT per student
HOPELESS_DRAWS = 2048
MIN_DIGITS, MAX_DIGITS = 2, 12


@dataclass
class Variant:
    student: str
    exercise: object  # Exercise
    texts: dict  # parameter -> the value as written ("47.3deg")
    params: dict = field(default_factory=dict)  # SI, as read back from ``texts``
    outputs: dict = field(default_factory=dict)  # output -> the key's record


@dataclass
class Assignment:
    seed: int
    digits: int
    version: str
    variants: list  # Variant, by student (roster order) then exercise (as given)
    ranges: dict = field(default_factory=dict)  # exercise id -> parameter -> "LO:HI" or "VALUE" (SI) drawn in

    def key(self) -> dict:
        return {"mech": self.version, "seed": self.seed, "digits": self.digits, "over": self.ranges,
                "variants": [{"student": v.student, "exercise": v.exercise.id, "params": dict(v.texts),
                              "outputs": v.outputs} for v in self.variants]}

    def key_json(self) -> str:
        return json.dumps(self.key(), indent=1, sort_keys=True, allow_nan=False, ensure_ascii=False) + "\n"

    def students(self) -> list[str]:
        return list(dict.fromkeys(v.student for v in self.variants))

    def files(self) -> dict:
        """Every file of the assignment: relative path -> text."""
        from mech.core.safeio import slugs

        out = {"handout.md": self.handout_md(), "answers.toml": self.answers_toml(),
               "answers.csv": self.answers_csv(), "key.json": self.key_json(), "key.csv": self.key_csv(),
               "key.md": self.key_md()}
        names = self.students()
        for student, slug in zip(names, slugs(names)):
            out[f"handouts/{slug}.md"] = self.handout_md(student)
        return out

    def answers_toml(self) -> str:
        """The grading file with ``student``, ``exercise`` and ``params`` filled and every output's answer
        left empty ("" is "not answered" to ``mech grade``)."""
        out = [f"# mech assign, seed {self.seed}: fill in each expect (a number with its unit, a formula, or\n"
               "# none); an answer left \"\" is not graded.  Grade with: mech grade answers.toml --assignment .\n"]
        for v in self.variants:
            params = ", ".join(f"{k} = {_toml_str(t)}" for k, t in v.texts.items())
            expect = ", ".join(f"{o.name} = \"\"" for o in v.exercise.outputs)
            out.append(f"[[answer]]\nstudent = {_toml_str(v.student)}\nexercise = {_toml_str(v.exercise.id)}\n"
                       f"params = {{ {params} }}\nexpect = {{ {expect} }}\n")
        return "\n".join(out)

    def answers_csv(self) -> str:
        """The template for a spreadsheet: ``student``, each exercise's ``ID:param`` columns filled and its
        ``ID:output`` columns empty; every text cell neutralised (``safeio.csv_cell``)."""
        from mech.core.safeio import csv_cell

        exercises = list(dict.fromkeys(v.exercise for v in self.variants))
        header = ["student"]
        for ex in exercises:
            header += [f"{ex.id}:{p.name}" for p in ex.params] + [f"{ex.id}:{o.name}" for o in ex.outputs]
        rows = {s: {"student": s} for s in self.students()}
        for v in self.variants:
            rows[v.student].update({f"{v.exercise.id}:{k}": t for k, t in v.texts.items()})
        return _csv([header] + [[csv_cell(r.get(h, "")) for h in header] for r in rows.values()])

    def key_csv(self) -> str:
        """The key for a person: one row per student, exercise and output; ``answer`` is what the statement
        asks for (the leading-order value of a leading-order output), ``exact`` the verified exact value,
        ``allowance`` how far (absolute, SI) an answer to ``digits`` digits may lie from either."""
        from mech.core.safeio import csv_cell

        rows = [["student", "exercise", "output", "unit", "answer", "exact", "leading_order", "allowance"]]
        for v in self.variants:
            for name, rec in v.outputs.items():
                answer, exact = _answer(rec), rec["value"]
                rows.append([csv_cell(v.student), v.exercise.id, name, csv_cell(rec["unit"]), _num(answer),
                             _num(exact), _num(rec["analytic"]) if rec["leading_order"] else "",
                             _num(self.allowance(rec), 3)])
        return _csv(rows)

    def allowance(self, rec: dict) -> float:
        """Half a unit in the ``digits``-th significant digit of the answer, plus mech's error bar."""
        answer = _answer(rec)
        half = 0.5 * 10.0 ** (math.floor(math.log10(abs(answer))) - self.digits + 1) if answer else 0.0
        return half + abs(rec["numeric_err"])

    def key_md(self) -> str:
        from mech.core.safeio import md_text

        lines = [f"# Key (mech {self.version}, seed {self.seed}, {self.digits} digits)", "",
                 "An answer is right when it lies within the allowance of the answer, or, for a leading-order "
                 "output, of the exact value; `mech grade ANSWERS --assignment DIR` grades it so.", ""]
        student = None
        for v in self.variants:
            if v.student != student:
                student = v.student
                lines += [f"## {md_text(student)}", ""]
            ex = v.exercise
            values = ", ".join(f"{md_text(k)} = {t}" for k, t in v.texts.items())  # values: written by mech
            lines += [f"### Exercise {ex.id}", "", f"Values: {values}", "",
                      "| output | unit | answer | exact | allowance |", "|---|---|---|---|---|"]
            for name, rec in v.outputs.items():
                lead = " (leading order)" if rec["leading_order"] else ""
                lines.append(f"| {md_text(name)}{lead} | {md_text(rec['unit'])} | {_num(_answer(rec), 6)} | "
                             f"{_num(rec['value'], 6)} | {_num(self.allowance(rec), 2)} |")
            lines.append("")
        return "\n".join(lines)

    def handout_md(self, only: str | None = None) -> str:
        """The handout: every student's (``only``: one student's) statements with their own values, and
        how to answer."""
        from mech.core.safeio import md_text

        title = "Assignment" if only is None else f"Assignment: {md_text(only)}"
        lines = [f"# {title} (mech {self.version}, seed {self.seed})", "", *_how_to_answer(self.digits)]
        student = None
        for v in self.variants:
            if only is not None and v.student != only:
                continue
            if v.student != student and only is None:
                lines += [f"## {md_text(v.student)}", ""]
            student = v.student
            lines += _exercise_md(v)
        return "\n".join(lines)


def _how_to_answer(digits: int) -> list[str]:
    return ["How to answer (in the answers file you are given, `answers.toml` or `answers.csv`):", "",
            f"- Give each number to at least {digits} significant digits, with a decimal point (not a comma).",
            "- Write the unit after the number (`1.68 m`, `35.3deg`, `2.9 rad/s`, `0.25 min`); a plain number "
            "is in SI units, angles in radians.",
            "- A formula in your parameters' names is accepted too, e.g. `sqrt(g/l)`, `asin(2/3*sin(theta0))`: "
            "with + - * / ^, parentheses, pi, and sqrt exp log sin cos tan asin acos atan sinh cosh tanh abs.",
            "- Write `none` for an output that has no value at your parameters.", ""]


_DEFAULT_NOTE = re.compile(r"\s*\((?:the )?defaults?\b[^)]*\)", re.I)


def _no_default(text: str) -> str:
    """A catalogue text without its notes about the default values ("(default: the Moon)")."""
    return " ".join(_DEFAULT_NOTE.sub("", str(text)).split())


def _fill(template: str, texts: dict) -> str:
    """``{name}`` placeholders of a handout statement filled with a student's values."""
    return re.sub(r"\{(\w+)\}", lambda m: texts.get(m.group(1), m.group(0)), template)


def _exercise_md(v: Variant) -> list[str]:
    from mech.core.safeio import md_text

    ex = v.exercise
    statement = _fill(ex.handout, v.texts) if ex.handout else ex.statement
    lines = [f"### Exercise {ex.id}: {md_text(ex.title)}", "", _no_default(statement), "", "Your values:", ""]
    for p in ex.params:
        sym = f" ({p.symbol})" if p.symbol and p.symbol != p.name else ""
        lines.append(f"- {md_text(p.name)}{sym} = {v.texts[p.name]}: {_no_default(p.doc)}")
    lines += ["", "Find:", ""]
    for o in ex.outputs:
        unit = "" if o.unit == "1" else f" [{o.unit}]"
        lines.append(f"- {md_text(o.name)}{unit}: {_no_default(o.doc)}")
    lines.append("")
    return lines


def _answer(rec: dict) -> float:
    """What the statement asks for: the leading-order value of a leading-order output, else mech's value."""
    return rec["analytic"] if rec["leading_order"] else rec["value"]


def _num(x: float, digits: int = 12) -> str:
    return f"{x:.{digits}g}"


def _csv(rows: list) -> str:
    import csv
    import io

    buf = io.StringIO(newline="")
    csv.writer(buf, lineterminator="\n").writerows(rows)
    return buf.getvalue()


def _toml_str(text: str) -> str:
    return json.dumps(str(text), ensure_ascii=False)  # a JSON string is a TOML basic string


# -- reading the class's inputs -------------------------------------------------------------------------

def read_roster(path: str) -> list[str]:
    """One identifier a line (blank lines and ``#`` comments skipped): printable, at most 80 characters,
    each once; BadInput naming the file and the line otherwise."""
    from mech.core.safeio import read_text, shown_path

    name = shown_path(path)
    text = read_text(path, "roster", limit=MAX_ROSTER_BYTES).lstrip("\ufeff")
    lines = [(i, raw.strip()) for i, raw in enumerate(text.splitlines(), 1)]
    return _check_roster([(i, s) for i, s in lines if s and not s.startswith("#")], name, "line")


def _check_roster(items: list[tuple[int, str]], name: str, what: str) -> list[str]:
    from mech.students.answers_files import MAX_STUDENT

    out, seen = [], {}
    for i, s in items:
        s = s.strip()
        if not s or len(s) > MAX_STUDENT or not s.isprintable():
            raise BadInput(f"{name}: {what} {i}: '{shown(s, 40)}' is not an identifier (a printable line of 1 "
                           f"to {MAX_STUDENT} characters)")
        if s in seen:
            raise BadInput(f"{name}: {what} {i}: '{shown(s, 40)}' is already {what} {seen[s]}")
        seen[s] = i
        out.append(s)
        if len(out) > MAX_STUDENTS:
            raise BadInput(f"{name}: more than {MAX_STUDENTS} students")
    if not out:
        raise BadInput(f"{name}: no students (one identifier a line)")
    return out


def parse_overs(exercises: list, pairs: list[str]) -> tuple[dict, dict]:
    """``--over NAME=LO:HI`` (a range inside the bounds) or ``--over NAME=VALUE`` (one value: fixed), for
    every exercise with that parameter, or ``--over ID:NAME=...`` for one -> ({exercise id: {name: (lo, hi)}}
    in SI, {exercise id: {name: the text given}}); BadInput naming the option otherwise."""
    out: dict = {ex.id: {} for ex in exercises}
    texts: dict = {ex.id: {} for ex in exercises}
    for pair in pairs:
        if "=" not in pair:
            raise BadInput(f"--over takes NAME=LO:HI or NAME=VALUE, got '{shown(pair)}'")
        name, rng = pair.split("=", 1)
        target = None
        if ":" in name:
            target, name = name.split(":", 1)
            target = target.strip()
        name = name.strip().replace("-", "_")
        hit = False
        for ex in exercises:
            if (target is not None and ex.id != target) or name not in ex.param_map:
                continue
            out[ex.id][name] = _over_range(ex, name, rng.strip())
            texts[ex.id][name] = rng.strip()
            hit = True
        if not hit:
            where = f"exercise {shown(target, 20)}" if target else "any of the exercises"
            raise BadInput(f"--over {shown(name, 40)}: not a parameter of {where} assigned")
    return out, texts


def _over_range(ex, name: str, text: str) -> tuple[float, float]:
    """One ``--over`` value: LO:HI (LO below HI, or LO = HI: fixed) or VALUE, inside the bounds, in SI."""
    from mech.core.units import ValueError_, to_si
    from mech.students.points import parse_over

    p = ex.param_map[name]
    ends = text.split(":")
    if len(ends) == 2:
        try:
            lo, hi = to_si(ends[0], p.unit), to_si(ends[1], p.unit)
        except (ValueError_, OverflowError) as exc:
            raise BadInput(f"--over {ex.id}:{name}: {shown(exc, 120)}") from None
        if lo != hi:
            try:
                return parse_over(ex, {name: text})[name]
            except BadInput as exc:
                raise BadInput(f"--over {ex.id}:{name}: {exc.reason}") from None
        text = ends[0]
    elif len(ends) != 1:
        raise BadInput(f"--over {ex.id}:{name}: give LO:HI or one VALUE, got '{shown(text, 40)}'")
    try:
        v = to_si(text, p.unit)
        p.check(v, text)
    except (ValueError_, BadInput, OverflowError) as exc:
        why = exc.reason if isinstance(exc, BadInput) else str(exc)
        raise BadInput(f"--over {ex.id}:{name}: {shown(why, 120)}") from None
    return v, v


def ranges_for(ex, over: dict) -> dict:
    """The range each parameter of ``ex`` is drawn from (SI): its typical range (``Param.typical``: a
    constant fixed, others within a factor 3 of the textbook value unless the catalogue says otherwise),
    replaced by ``--over`` where given."""
    return {p.name: tuple(over.get(p.name) or p.typical) for p in ex.params}


def _range_text(lo: float, hi: float) -> str:
    return repr(lo) if lo == hi else f"{lo!r}:{hi!r}"


# -- drawing and verifying ------------------------------------------------------------------------------

LEADING_ORDER_AGREE = 0.01  # a leading-order value kept within 1 % of the exact one: the book's method is right
# the screen before the cross-check: a variant whose declared neglect estimate (``expected_error``, an order
# of magnitude that runs 2 to 4 times the real gap at 5.8's and 5.12's defaults) exceeds 2 % is not solved
SCREEN_NEGLECT = 0.02


def _seed_for(seed: int, ex_id: str) -> int:
    return (seed * 1_000_003 + zlib.crc32(ex_id.encode())) % (2**63)


def _round_text(p, value: float, digits: int) -> str:
    """The value rounded to ``digits`` significant digits in the unit a handout prints, as text."""
    from mech.core.units import parse_unit

    unit = p.display or p.unit
    factor = parse_unit(unit)[0] if unit != "1" else 1.0
    shown_v = float(f"{value / factor:.{digits}g}")
    text = f"{shown_v:.{digits}g}"
    if unit == "1":
        return text
    if unit.startswith("1/"):
        return f"{text}{unit[1:]}"  # "0.07/s": "0.07 1/s" would read as two numbers
    return f"{text}{unit}" if unit == "deg" else f"{text} {unit}"


def _exact_text(p, value: float, digits: int) -> str:
    """A fixed value as text with the fewest digits (at least ``digits``) that read back to it exactly."""
    from mech.core.units import to_si

    for k in range(digits, 18):
        text = _round_text(p, value, k)
        if to_si(text, p.unit) == value:
            return text
    return repr(value) if p.unit in ("1", "rad") else f"{value!r} {p.unit}"


def _rounded(ex, p_si: dict, digits: int, rng: dict):
    """The variant rounded and read back as ``mech grade`` reads it: (texts, SI params), or None when the
    rounded values leave the bounds, a joint constraint or the drawing ranges ``rng``.  A fixed value
    (LO = HI) is written with the digits that give it exactly."""
    from mech.core.units import ValueError_, to_si

    texts, values = {}, {}
    for p in ex.params:
        lo, hi = rng[p.name]
        text = _exact_text(p, lo, digits) if lo == hi else _round_text(p, float(p_si[p.name]), digits)
        texts[p.name] = text
        try:
            values[p.name] = to_si(text, p.unit)
            p.check(values[p.name])
        except (ValueError_, BadInput, OverflowError):
            return None
        if not lo <= values[p.name] <= hi:
            return None
    try:
        params = ex.resolve(values)
    except BadInput:
        return None
    return texts, params


def _outside_regime(ex, values: dict) -> str | None:
    """Why outputs ``values`` (SI) lie outside the regime the statement is about (the catalogue's ``[regime]``:
    ``positive``, outputs that must be above zero, and ``about``, the regime in words), or None: only variants
    inside it are issued."""
    for name in ex.regime.get("positive", ()):
        v = values.get(name)
        if not (isinstance(v, float) and v > 0):
            return f"{name} is not positive: not {ex.regime.get('about', 'the regime of the statement')}"
    return None


def _promising(ex, params) -> bool:
    """A cheap screen before the cross-check: every analytic value finite, and inside the statement's
    regime (by the analytic values; the verified ones decide).  Only ever throws a candidate out."""
    try:
        got = ex.solve_analytic(params)
    except (BadInput, ArithmeticError, ValueError):
        return False
    values = {k: v for k, v in got.items() if isinstance(v, float)}
    if len(values) != len(got) or not all(math.isfinite(v) for v in values.values()):
        return False
    try:
        neglected = expected_errors(ex, params)
    except (ArithmeticError, ValueError):
        return False
    for name, err in neglected.items():  # what the theory neglects, estimated (rel, or (rel, abs))
        rel = err[0] if isinstance(err, (tuple, list)) else err
        if rel is None or not rel <= SCREEN_NEGLECT:
            return False
    return _outside_regime(ex, values) is None


def _screen(ex, params: list) -> list[bool]:
    """``_promising`` for each candidate; where the exercise's hooks are written on arrays (a batched route),
    one call of its analytic and expected-error hooks over all of them (a call costs ~1 ms, a candidate
    within it microseconds), the same tests applied to each: every analytic value a finite number, what
    the theory neglects within SCREEN_NEGLECT, the analytic values inside the statement's regime."""
    route = getattr(ex, "batched_route", None)
    if route is None or len(params) < 2:
        return [_promising(ex, p) for p in params]
    import warnings

    import numpy as np

    from mech.problems.params import Params

    P = Params({name: np.array([float(p[name]) for p in params]) for name in ex.param_map})
    try:
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cols = route.analytic(P)
            neglected = route.expected_error(P) if route.expected_error else {}
    except (ArithmeticError, ValueError):  # a candidate the arrays cannot take: each one alone
        return [_promising(ex, p) for p in params]
    ok = np.ones(len(params), dtype=bool)
    values = {}
    for o in ex.outputs:
        col = cols[o.name]
        v = np.broadcast_to(np.asarray(col.value, dtype=float), ok.shape)
        ok &= ~col.mask("undefined") & np.isfinite(v)
        values[o.name] = v
    for name, err in neglected.items():  # relative, or (relative, absolute): an absolute part alone fails
        rel, ab = err if isinstance(err, tuple) else (err, np.nan)
        rel = np.broadcast_to(np.asarray(rel, dtype=float), ok.shape)
        given = ~(np.isnan(rel) & np.isnan(np.broadcast_to(np.asarray(ab, dtype=float), ok.shape)))
        ok &= ~given | (rel <= SCREEN_NEGLECT)
    return [bool(ok[k]) and _outside_regime(ex, {n: float(v[k]) for n, v in values.items()}) is None
            for k in range(len(params))]


def _record(ex, result) -> dict | None:
    """The key's outputs from a cross-check, or None when the variant is not issued: both methods must
    have run and agree, every output be finite, every leading-order value lie within 1 % of the exact
    one, and the variant be inside the regime the statement is about."""
    if result.errors or result.agree is not True:
        return None
    out = {}
    for q in result.quantities:
        a, n = q.analytic, q.numeric
        if not (isinstance(a, float) and math.isfinite(a) and isinstance(n, float) and math.isfinite(n)):
            return None
        if q.agree is not True or q.numeric_err is None or not math.isfinite(q.numeric_err):
            return None
        lead = q.theory != "exact"
        if lead and not within(abs(a - n), scale=n, rel=LEADING_ORDER_AGREE):
            return None
        out[q.name] = {"value": float(n) if lead else float(a), "unit": q.unit, "analytic": float(a),
                       "numeric": float(n), "numeric_err": float(q.numeric_err), "leading_order": lead}
    if _outside_regime(ex, {k: r["value"] for k, r in out.items()}) is not None:
        return None
    return out


def _solve_all(ex, todo: list[tuple[str, dict]], jobs: int | None) -> list:
    """Cross-check each (exercise id, SI params) of ``ex``; the Solutions in order: together through the
    exercise's batched route where it has one (the same on any number of cores), else one by one, pooled
    over the cores."""
    from mech.studies.checking import plan_jobs
    from mech.studies.sweep import solve_point
    from mech.studies.variants import batchable, cross_check_variants

    if len(todo) > 1 and batchable(ex):
        from mech.problems.params import Params

        return cross_check_variants(ex, [Params(dict(p)) for _, p in todo])
    workers = plan_jobs(len(todo), jobs)
    if workers <= 1:
        return [solve_point(ex_id, dict(p), None, True)[0] for ex_id, p in todo]
    import multiprocessing
    import os
    from concurrent.futures import ProcessPoolExecutor

    from mech.studies.sweep import pool_worker_init

    with ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"),
                             initializer=pool_worker_init, initargs=(os.getpid(),)) as pool:
        futures = [pool.submit(solve_point, ex_id, dict(p), None, True) for ex_id, p in todo]
        return [f.result()[0] for f in futures]


def _candidates(ex, seed: int, digits: int, rng: dict, pool: list, drawn_n: int, wanted: int) -> int:
    """Extend ``pool`` with rounded, promising candidates until it holds ``wanted``; the draws used so far."""
    from mech.students.points import draw

    size = max(wanted, drawn_n + 8)
    while len(pool) < wanted:
        size = max(2 * size, drawn_n + 2 * (wanted - len(pool)) + 8)
        if not pool and drawn_n < HOPELESS_DRAWS:
            size = min(size, HOPELESS_DRAWS)
        pts = draw(ex, size, _seed_for(seed, ex.id), rng)
        new = pts[drawn_n:]
        if not new:
            raise BadInput(f"{ex.id}: cannot draw the variants inside its typical ranges, constraints and "
                           "--over; widen --over")
        drawn_n = len(pts)
        rounded = [got for got in (_rounded(ex, p, digits, rng) for p in new) if got is not None]
        pool.extend(got for got, ok in zip(rounded, _screen(ex, [got[1] for got in rounded])) if ok)
        if not pool and drawn_n >= HOPELESS_DRAWS:
            raise BadInput(_hopeless(ex, seed, digits, rng, [got[1] for got in rounded], drawn_n))
        if len(pool) < wanted and drawn_n >= MAX_DRAWS_PER_VARIANT * wanted + 256:
            raise BadInput(f"{ex.id}: too few drawn variants rounded to {digits} digits stay inside the ranges, "
                           "the joint constraints, the statement's regime and 1 % of the exact value for every "
                           "leading-order answer; give more --digits or change --over")
    return drawn_n


def _least_neglect(ex, params: list) -> float | None:
    """The smallest, over ``params``, of the largest relative error the theory's own estimate gives."""
    best = None
    for p in params[:256]:
        try:
            errs = expected_errors(ex, p)
        except (ArithmeticError, ValueError, BadInput):
            continue
        rels = [e[0] if isinstance(e, (tuple, list)) else e for e in errs.values()]
        if rels and all(r is not None and math.isfinite(r) for r in rels):
            best = max(rels) if best is None else min(best, max(rels))
    return best


def _hopeless(ex, seed: int, digits: int, rng: dict, params: list, drawn_n: int) -> str:
    """The one line refusing an exercise none of whose first ``drawn_n`` draws passes the screen, naming
    what would work: the exercise's typical ranges, where --over moved them and they pass."""
    from mech.students.points import draw

    least = _least_neglect(ex, params) if any(o.theory != "exact" for o in ex.outputs) else None
    why = (f"what its theory neglects is at least {100 * least:.2g} % at each of them (its own estimate; "
           f"a leading-order answer must be within {100 * LEADING_ORDER_AGREE:g} %)" if least is not None
           and least > SCREEN_NEGLECT else "they fail its joint limits, its regime or its analytic answer")
    typical = {p.name: tuple(p.typical) for p in ex.params}
    moved = [name for name in rng if tuple(rng[name]) != typical[name]]
    hint = "change --over"
    if moved:
        pts = draw(ex, 64, _seed_for(seed, ex.id), typical)
        rounded = [got for got in (_rounded(ex, p, digits, typical) for p in pts) if got is not None]
        if any(_screen(ex, [got[1] for got in rounded])):
            hint = ("its typical ranges do: " + ", ".join(f"{name}={_range_text(*typical[name])}" for name in moved)
                    + " (drop those --over)")
    return f"{ex.id}: none of {drawn_n} draws inside the ranges is worth assigning: {why}; {hint}"


def make(exercises: list, students: list[str], seed: int, overs: dict | None = None, digits: int = 3,
         jobs: int | None = None, version: str = "") -> Assignment:
    """Every student's verified variant of every exercise (see the module's docstring)."""
    overs = overs or {}
    n = len(students)
    variants: dict = {}  # (student index, exercise index) -> Variant
    ranges = {}
    for k, ex in enumerate(exercises):
        rng = ranges_for(ex, overs.get(ex.id) or {})
        ranges[ex.id] = {name: _range_text(*lo_hi) for name, lo_hi in rng.items()}
        pool: list = []  # the exercise's rounded candidates, in draw order
        drawn_n = cursor = 0
        waiting = list(range(n))  # students still without a verified variant, in roster order
        tries = {i: 0 for i in waiting}
        while waiting:
            drawn_n = _candidates(ex, seed, digits, rng, pool, drawn_n, cursor + len(waiting))
            batch = []
            for i in waiting:
                texts, params = pool[cursor]
                cursor += 1
                tries[i] += 1
                batch.append((i, Variant(students[i], ex, texts, dict(params))))
            results = _solve_all(ex, [(ex.id, v.params) for _, v in batch], jobs)
            still = []
            for (i, v), result in zip(batch, results):
                rec = _record(ex, result)
                if rec is None:
                    if tries[i] >= MAX_TRIES:
                        raise BadInput(f"{ex.id}: no variant for {shown(students[i], 40)} verified in {MAX_TRIES}"
                                       " draws; narrow the range with --over")
                    still.append(i)
                    continue
                v.outputs = rec
                variants[(i, k)] = v
            waiting = still
    ordered = [variants[(i, k)] for i in range(n) for k in range(len(exercises))]
    return Assignment(seed, digits, version, ordered, ranges)


# -- the command ----------------------------------------------------------------------------------------

# what marks a folder as holding an assignment: refused as --out unless --force
ASSIGNMENT_FILES = ("key.json", "answers.toml", "answers.csv", "handout.md", "key.csv", "key.md")


def _exercises(ids) -> list:
    from mech.problems import registry

    if isinstance(ids, str):
        ids = [ids]
    exercises = []
    for i in ids:
        ex = registry.get(i)  # a number for an id is refused there, naming the quoted form
        if ex.id in [e.id for e in exercises]:
            raise BadInput(f"{ex.id}: named twice")
        exercises.append(ex)
    if not exercises:
        raise BadInput("assign: name at least one exercise")
    return exercises


def _roster(students, n, inputs: list) -> list[str]:
    from mech.students.expectations import parse_count

    if (students is None) == (n is None):
        raise BadInput("give the class as --students FILE or --n N (one of the two)")
    if n is not None:
        return [f"s{k}" for k in range(1, parse_count(n, "--n", 1, MAX_STUDENTS) + 1)]
    if isinstance(students, (list, tuple)):
        return _check_roster([(k, str(s)) for k, s in enumerate(students, 1)], "students", "item")
    inputs.append(str(students))
    return read_roster(str(students))


def _folder(out, force: bool, names: list[str], inputs: list) -> dict:
    """The folder's output paths, checked before any work: not a file, no assignment there already unless
    ``force``, writable, none of them an input.  Creates the folder (and ``handouts/``)."""
    import os

    from mech.core.safeio import check_apart, check_output, shown_path

    folder = str(out)
    if folder.strip() == "":
        raise BadInput("--out: an empty folder name")
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise BadInput(f"--out {shown_path(folder)}: not a folder")
    held = [f for f in ASSIGNMENT_FILES + ("handouts",) if os.path.lexists(os.path.join(folder, f))]
    if held and not force:
        raise BadInput(f"--out {shown_path(folder)}: already holds an assignment ({held[0]}); give another "
                       "folder, or --force to replace it")
    try:
        os.makedirs(os.path.join(folder, "handouts"), exist_ok=True)
    except OSError as exc:
        raise BadInput(f"--out {shown_path(folder)}: cannot create the folder: {exc.strerror or exc}") from None
    paths = {}
    for name in names:
        path = os.path.join(folder, *name.split("/"))
        check_apart([(path, "--out")], [(given, "the input") for given in inputs])  # never over an input
        paths[name] = check_output(path, "--out")
    return paths


def _stale_handouts(folder: str, keep: set) -> list[str]:
    """Handouts an earlier assignment left in ``folder``/handouts that this one does not write."""
    import os

    where = os.path.join(folder, "handouts")
    return [os.path.join(where, f) for f in sorted(os.listdir(where))
            if f.endswith(".md") and f"handouts/{f}" not in keep and os.path.isfile(os.path.join(where, f))
            and not os.path.islink(os.path.join(where, f))]


def assign(ids, *, seed, out, students=None, n=None, over=None, digits=3, jobs=None, version: str = "",
           force: bool = False) -> dict:
    """Check every input before any work (BadInput, one line), draw and verify the variants, write every
    file of the assignment into ``out`` atomically (a folder already holding one is refused unless
    ``force``; an output that is an input is refused), and return the key."""
    import os

    from mech.core.safeio import atomic_write, slugs
    from mech.students.answers_files import MAX_ANSWERS
    from mech.students.expectations import parse_count

    exercises = _exercises(ids)
    seed_v = parse_count(seed, "--seed", 0, 2**63 - 1)
    if seed_v is None:
        raise BadInput("--seed: required (a whole number: the same seed gives the same variants)")
    digits_v = parse_count(digits, "--digits", MIN_DIGITS, MAX_DIGITS)
    inputs: list = []
    roster = _roster(students, n, inputs)
    # the template filled in must be a file mech grade reads: at most MAX_ANSWERS expected values
    answers = len(roster) * sum(len(ex.outputs) for ex in exercises)
    if answers > MAX_ANSWERS:
        raise BadInput(f"{len(roster)} students x {answers // len(roster)} outputs are {answers} answers; mech grade "
                       f"reads at most {MAX_ANSWERS} a file (fewer students or exercises per assignment)")
    if over is None:
        pairs = []
    elif isinstance(over, dict):
        pairs = [f"{k}={v}" for k, v in over.items()]
    else:
        pairs = [str(p) for p in over]
    overs, _ = parse_overs(exercises, pairs)
    names = list(ASSIGNMENT_FILES) + [f"handouts/{s}.md" for s in slugs(roster)]
    paths = _folder(out, force, names, inputs)
    a = make(exercises, roster, seed_v, overs, digits_v, jobs=jobs, version=version)
    texts = a.files()
    for name, path in paths.items():
        with atomic_write(path, "--out", newline="") as fh:
            fh.write(texts[name])
    for path in _stale_handouts(str(out), set(paths)) if force else ():
        os.unlink(path)
    return a.key()
