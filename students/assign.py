"""``mech assign``: personal variants for a class, each verified before it is issued, with its key.

For each exercise the parameter sets are drawn as a formula's judging points are
(``formulas.draw``: across the declared ranges, log-uniform on a positive range, inside every joint
constraint, narrowed by ``--over``), from a seed made of the class's seed and the exercise's id, so a
roster's students take the draws in roster order.  Each value is rounded to ``digits`` significant
digits in the unit a handout prints (degrees for an angle), written as the handout shows it, and read
back exactly as ``mech grade`` will read it; the rounded variant must still lie inside the bounds, the
joint constraints and ``--over``, and is then solved by both methods: a variant whose methods do not
agree, or where an output has no value, is not issued and the student takes the next draw.

Everything written is a function of the roster, the seed, the digits, the ranges and mech's version:
no time stamps, the JSON's keys sorted, floats as Python's shortest round-trip ``repr``.
"""

from __future__ import annotations

import json
import math
import zlib
from dataclasses import dataclass, field

from mech.core.errors import BadInput
from mech.core.safeio import shown

__all__ = ["Assignment", "Variant", "read_roster", "parse_overs", "make", "assign", "MAX_STUDENTS"]

MAX_STUDENTS = 2000
MAX_ROSTER_BYTES = 256 * 1024
MAX_TRIES = 40  # draws a student may take for one exercise before mech gives up (a loud one line)
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

    def key(self) -> dict:
        return {"mech": self.version, "seed": self.seed,
                "variants": [{"student": v.student, "exercise": v.exercise.id, "params": dict(v.texts),
                              "outputs": v.outputs} for v in self.variants]}

    def key_json(self) -> str:
        return json.dumps(self.key(), indent=1, sort_keys=True, allow_nan=False, ensure_ascii=False) + "\n"

    def answers_toml(self) -> str:
        """The grading file with ``student``, ``exercise`` and ``params`` filled and every output's answer
        left empty ("" is "not answered" to ``mech grade``)."""
        out = [f"# mech assign, seed {self.seed}: fill in each expect (a number with its unit, or a formula);\n"
               "# an answer left \"\" is not graded.  Grade with: mech grade answers.toml\n"]
        for v in self.variants:
            params = ", ".join(f"{k} = {_toml_str(t)}" for k, t in v.texts.items())
            expect = ", ".join(f"{o.name} = \"\"" for o in v.exercise.outputs)
            out.append(f"[[answer]]\nstudent = {_toml_str(v.student)}\nexercise = {_toml_str(v.exercise.id)}\n"
                       f"params = {{ {params} }}\nexpect = {{ {expect} }}\n")
        return "\n".join(out)

    def handout_md(self) -> str:
        lines = [f"# Assignment (mech {self.version}, seed {self.seed})", ""]
        student = None
        for v in self.variants:
            if v.student != student:
                student = v.student
                lines += [f"## {_md(student)}", ""]
            ex = v.exercise
            lines += [f"### Exercise {ex.id}: {_md(ex.title)}", "", ' '.join(ex.statement.split()), "",
                      "Your values:", ""]
            for p in ex.params:
                sym = f" ({p.symbol})" if p.symbol and p.symbol != p.name else ""
                lines.append(f"- {p.name}{sym} = {v.texts[p.name]}: {' '.join(p.doc.split())}")
            lines += ["", "Find:", ""]
            for o in ex.outputs:
                unit = "" if o.unit == "1" else f" [{o.unit}]"
                lines.append(f"- {o.name}{unit}: {' '.join(o.doc.split())}")
            lines.append("")
        return "\n".join(lines)


def _toml_str(text: str) -> str:
    return json.dumps(str(text), ensure_ascii=False)  # a JSON string is a TOML basic string


def _md(text: str) -> str:
    return str(text).replace("\n", " ")


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


def parse_overs(exercises: list, pairs: list[str]) -> dict:
    """``--over NAME=LO:HI`` (every exercise with that parameter) or ``--over ID:NAME=LO:HI`` (one) ->
    {exercise id: {name: (lo, hi)}} in SI; BadInput naming the option otherwise."""
    from mech.students.points import parse_over

    out: dict = {ex.id: {} for ex in exercises}
    for pair in pairs:
        if "=" not in pair:
            raise BadInput(f"--over takes NAME=LO:HI, got '{shown(pair)}'")
        name, rng = pair.split("=", 1)
        target = None
        if ":" in name:
            target, name = name.split(":", 1)
            target = target.strip()
        hit = False
        for ex in exercises:
            if target is not None and ex.id != target:
                continue
            if name.strip().replace("-", "_") not in ex.param_map:
                continue
            try:
                got = parse_over(ex, {name: rng})
            except BadInput as exc:
                raise BadInput(f"--over {ex.id}:{str(exc).removeprefix('over.')}") from None
            out[ex.id].update(got)
            hit = True
        if not hit:
            where = f"exercise {target}" if target else "any of the exercises"
            raise BadInput(f"--over {shown(name)}: not a parameter of {where} assigned")
    return out


# -- drawing and verifying ------------------------------------------------------------------------------

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


def _rounded(ex, p_si: dict, digits: int, over: dict):
    """The variant rounded and read back as ``mech grade`` reads it: (texts, SI params), or None when the
    rounded values leave the bounds, a joint constraint or ``--over``."""
    from mech.core.units import ValueError_, to_si

    texts, values = {}, {}
    for p in ex.params:
        texts[p.name] = _round_text(p, float(p_si[p.name]), digits)
        try:
            values[p.name] = to_si(texts[p.name], p.unit)
            p.check(values[p.name])
        except (ValueError_, BadInput, OverflowError):
            return None
        lo_hi = over.get(p.name)
        if lo_hi and not lo_hi[0] <= values[p.name] <= lo_hi[1]:
            return None
    try:
        params = ex.resolve(values)
    except BadInput:
        return None
    return texts, params


def _record(result) -> dict | None:
    """The key's outputs from a cross-check, or None when it does not verify: both methods must have run,
    agree, and give a finite value for every output."""
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
        out[q.name] = {"value": float(n) if lead else float(a), "unit": q.unit, "analytic": float(a),
                       "numeric": float(n), "numeric_err": float(q.numeric_err), "leading_order": lead}
    return out


def _solve_all(todo: list[tuple[str, dict]], jobs: int | None) -> list:
    """Cross-check each (exercise id, SI params); the Solutions in order (pooled over the cores)."""
    from mech.studies.checking import plan_jobs
    from mech.studies.sweep import solve_point

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


def make(exercises: list, students: list[str], seed: int, overs: dict | None = None, digits: int = 3,
         jobs: int | None = None, version: str = "") -> Assignment:
    """Every student's verified variant of every exercise (see the module's docstring)."""
    from mech.students.points import draw

    overs = overs or {}
    n = len(students)
    variants: dict = {}  # (student index, exercise index) -> Variant
    for k, ex in enumerate(exercises):
        over = overs.get(ex.id) or {}
        pool: list = []  # the exercise's rounded candidates, in draw order
        drawn_n = 0
        want = n
        cursor = 0
        waiting = list(range(n))  # students still without a verified variant, in roster order
        tries = {i: 0 for i in waiting}
        while waiting:
            # enough candidates for everyone still waiting (a draw's first points do not depend on n)
            while len(pool) - cursor < len(waiting):
                size = max(2 * want, drawn_n + 2 * len(waiting) + 8)
                pts = draw(ex, size, _seed_for(seed, ex.id), over or None)
                new = pts[drawn_n:]
                if not new:
                    raise BadInput(f"{ex.id}: cannot draw {n} variants inside its ranges and constraints"
                                   + (" and --over" if over else "") + "; widen --over")
                drawn_n = len(pts)
                want = size
                kept = 0
                for p in new:
                    got = _rounded(ex, p, digits, over)
                    if got is not None:
                        pool.append(got)
                        kept += 1
                if kept == 0 and len(new) >= 16:  # rounding throws every draw out: say so, at once
                    raise BadInput(f"{ex.id}: every drawn variant rounded to {digits} digits leaves the "
                                   "parameters' bounds or joint constraints; give more --digits or narrow --over")
            batch = []
            for i in waiting:
                texts, params = pool[cursor]
                cursor += 1
                tries[i] += 1
                batch.append((i, Variant(students[i], ex, texts, dict(params))))
            results = _solve_all([(ex.id, v.params) for _, v in batch], jobs)
            still = []
            for (i, v), result in zip(batch, results):
                rec = _record(result)
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
    return Assignment(seed, digits, version, ordered)


# -- the command ----------------------------------------------------------------------------------------

def assign(ids, *, seed, out, students=None, n=None, over=None, digits=3, jobs=None, version: str = "") -> dict:
    """Check every input before any work (BadInput, one line), draw and verify the variants, write
    ``out``/handout.md, answers.toml and key.json atomically (an output that is an input is refused), and
    return the key."""
    import os

    from mech.core.safeio import atomic_write, check_apart, check_output, shown_path
    from mech.problems import registry
    from mech.students.answers_files import MAX_ANSWERS
    from mech.students.expectations import parse_count

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
    seed_v = parse_count(seed, "--seed", 0, 2**63 - 1)
    if seed_v is None:
        raise BadInput("--seed: required (a whole number: the same seed gives the same variants)")
    digits_v = parse_count(digits, "--digits", MIN_DIGITS, MAX_DIGITS)
    inputs = []
    if (students is None) == (n is None):
        raise BadInput("give the class as --students FILE or --n N (one of the two)")
    if n is not None:
        roster = [f"s{k}" for k in range(1, parse_count(n, "--n", 1, MAX_STUDENTS) + 1)]
    elif isinstance(students, (list, tuple)):
        roster = _check_roster([(k, str(s)) for k, s in enumerate(students, 1)], "students", "item")
    else:
        roster = read_roster(str(students))
        inputs.append(str(students))
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
    overs = parse_overs(exercises, pairs)
    folder = str(out)
    if folder.strip() == "":
        raise BadInput("--out: an empty folder name")
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise BadInput(f"--out {shown_path(folder)}: not a folder")
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as exc:
        raise BadInput(f"--out {shown_path(folder)}: cannot create the folder: {exc.strerror or exc}") from None
    paths = {}
    for name in ("handout.md", "answers.toml", "key.json"):
        path = os.path.join(folder, name)
        check_apart([(path, "--out")], [(given, "the input") for given in inputs])  # never over an input
        paths[name] = check_output(path, "--out")
    a = make(exercises, roster, seed_v, overs, digits_v, jobs=jobs, version=version)
    texts = {"handout.md": a.handout_md(), "answers.toml": a.answers_toml(), "key.json": a.key_json()}
    for name, path in paths.items():
        with atomic_write(path, "--out", newline="") as fh:
            fh.write(texts[name])
    return a.key()
