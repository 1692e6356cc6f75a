"""What ``mech.solve``, ``mech.sweep`` and ``mech.check`` return, and how they get it.

A ``Solution`` is the cross-check of one exercise at one set of parameters: the same
object ``mech solve --json`` prints (``to_dict``), with each output readable as a
``Quantity`` and, where the numeric route integrates equations of motion, the motion
as a ``Trajectory``.  A ``Sweep`` is many of them over a range or a grid.
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from mech.problems.spec import BadInput, NumericFailure
from mech.verification.result import Quantity, Solution, Trajectory  # the API's one motion type

__all__ = ["Quantity", "Solution", "Sweep", "Trajectory", "solve", "sweep", "check", "resolve_params"]


def __getattr__(name: str):
    """``Sweep``, the one sweep type, imported when first asked for: a solve needs none of the sweeps'
    pool machinery (45 ms of imports on every ``mech solve``)."""
    if name == "Sweep":
        from mech.studies.sweep import Sweep

        return Sweep
    raise AttributeError(f"module 'mech.api' has no attribute '{name}'")


# -- parameters ----------------------------------------------------------------

def _value_text(value: Any) -> str:
    """A parameter value as the command line would have received it."""
    if isinstance(value, str):
        return value
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise BadInput(f"cannot use {_shown(_kind(value))} {_shown(value)}: give a number (SI) or a string with "
                       "a unit, e.g. '60deg'")
    try:
        return repr(float(value))
    except OverflowError:
        raise BadInput(f"cannot use {_shown(value)}: beyond the floating-point range") from None


def _convert(ex, name: str, value: Any) -> float:
    from mech.problems.values import convert as convert_text, param_name

    canon = param_name(ex, name)
    return convert_text(ex, canon, _value_text(value))


def resolve_params(ex, given: dict[str, Any]):
    """Numbers (SI) or strings with units -> checked ``Params``, with the command line's messages."""
    values = {}
    for name, value in given.items():
        canon = name.replace("-", "_")
        if canon in values:
            raise BadInput(f"{canon}: given more than once")
        values[canon] = _convert(ex, name, value)
    return ex.resolve(values)


def _rtol(ex, rtol):
    if rtol is None:
        return None
    from mech.problems.values import parse_rtol

    return parse_rtol(_value_text(rtol), ex)


_METHODS = {"both": ("analytic", "numeric"), "analytic": ("analytic",), "numeric": ("numeric",)}


def _methods(method: str) -> tuple[str, ...]:
    try:
        return _METHODS[str(method).lower()]
    except KeyError:
        raise BadInput(f"method: '{_shown(method)}' is not one of both, analytic, numeric") from None


def _shown(value) -> str:
    from mech.core.safeio import shown

    return shown(value)


def _kind(value) -> str:
    return "None" if value is None else type(value).__name__


_ARG_KINDS = {
    "none": lambda v: v is None,
    "str": lambda v: isinstance(v, str),
    "number": lambda v: isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, (bool, np.bool_)),
    "bool": lambda v: isinstance(v, (bool, np.bool_)),
    "int": lambda v: isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_)),
    "dict": lambda v: isinstance(v, dict),
    "names": lambda v: isinstance(v, str) or (isinstance(v, (list, tuple)) and all(isinstance(x, str) for x in v)),
    "path": lambda v: isinstance(v, str) or hasattr(v, "__fspath__"),
    "numbers": lambda v: isinstance(v, (list, tuple, np.ndarray)),
}
_KIND_TEXT = {"none": "None", "str": "a string", "number": "a number", "bool": "True or False",
              "int": "a whole number", "dict": "a dict", "names": "a name or a list of names",
              "path": "a file name", "numbers": "a list of numbers"}


def _screen(name: str, value, *kinds: str):
    """An API argument of one of ``kinds``, checked before anything is done with it; BadInput naming it
    (the value shown escaped and cut) otherwise: a number beyond the floating-point range or not finite,
    a string with a NUL (a file name), a wrong type.  Returns the value."""
    if not any(_ARG_KINDS[k](value) for k in kinds):
        raise BadInput(f"{name}: give {' or '.join(_KIND_TEXT[k] for k in kinds)}, got {_kind(value)} "
                       f"{_shown(value)}")
    if _ARG_KINDS["number"](value):
        try:
            finite = math.isfinite(float(value))
        except OverflowError:
            finite = False
        if not finite:
            raise BadInput(f"{name}: {_shown(value)} is not a finite number in the floating-point range")
    if isinstance(value, str) and "path" in kinds and "\x00" in value:
        raise BadInput(f"{name}: {_shown(value)}: a file name with a NUL character")
    return value


def _exercise(ex_id):
    """The exercise of an API id: a string (a number, such as 4.15, gets the message asking to quote it)."""
    from mech.problems import registry

    if _ARG_KINDS["number"](ex_id) and abs(ex_id) < 1e6:
        return registry.get(ex_id)
    return registry.get(_screen("exercise id", ex_id, "str"))


def _screen_params(params: dict) -> dict:
    for k, v in params.items():
        _screen(_shown(k), v, "number", "str")
    return params


def _flag(name: str, value) -> bool:
    """A True/False argument: a bool (numpy's too), never a string such as 'no' that would read as True."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise BadInput(f"{name}: give True or False, got {_kind(value)} {_shown(value)}")


def _jobs(jobs):
    """None (decide) or a whole number of processes, at least 1."""
    if jobs is None:
        return None
    if isinstance(jobs, bool) or not isinstance(jobs, (int, np.integer)) or jobs < 1:
        raise BadInput(f"jobs: give a whole number of processes, at least 1 (or None), got {_shown(jobs)}")
    return int(jobs)


def _names(what: str, value) -> list[str]:
    """A name or a sequence of names (strings)."""
    if isinstance(value, str):
        return [value]
    if isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value):
        return list(value)
    raise BadInput(f"{what}: give a name or a list of names, got {_kind(value)} {_shown(value)}")


# -- results ---------------------------------------------------------------------

def _trajectory(ex, run) -> Trajectory | None:
    """The scene's motion as the numeric route marked it (``run.motion``), in SI, legs joined in time."""
    if run is None or not ex.states:
        return None
    try:
        joined = run.trajectory(len(ex.states))
    except RuntimeError as exc:
        raise RuntimeError(f"{ex.id}: {exc}") from None
    if joined is None:
        return None
    t, y = joined
    return Trajectory(t=t, y=y, names=[s[0] for s in ex.states], units=[s[1] for s in ex.states])


def _motion(sol: Solution, deadline: float | None = None) -> Trajectory | None:
    """A solution's trajectory (``Solution.trajectory``): the same numeric solve, run again with its motion
    kept (dense output between steps may cost evaluations the answer does not need, so the answer's solve
    keeps none: ``to_dict()`` stays what ``mech solve --json`` prints)."""
    ex = sol.exercise
    if ex is None or not ex.states or sol.run is None:
        return None
    if sol.solver_failed:
        return None  # the numeric solve itself did not finish: no motion to hand over
    from mech.problems.spec import Params
    from mech.core import budget

    info = sol.numeric_info or {}
    # a solve's work, and the solve's clock where it had one: what the cross-check left of it
    left = None if deadline is None else deadline - time.monotonic()
    if left is not None and left <= 0:
        raise budget.OutOfTime(f"the trajectory of {ex.id}: the solve's time budget is spent")
    with budget.limit(left, what=f"the trajectory of {ex.id}", work=budget.SOLVE_WORK):
        _, run = ex.solve_numeric(Params(dict(sol.params)), info.get("rtol"), keep_trajectories=True)
    return _trajectory(ex, run)


# -- solve -----------------------------------------------------------------------

def solve(ex_id: str, *, method: str = "both", rtol=None, verify: bool = True, raise_on_failure: bool = True,
          params: dict | None = None, expect: dict | None = None, expect_rtol=None, expect_points=None,
          expect_seed=None, expect_min_digits=None) -> Solution:
    from mech.problems import registry

    ex = _exercise(ex_id)
    _screen("method", method, "str")
    _screen("rtol", rtol, "none", "number", "str")
    _screen("expect", expect, "none", "dict")
    _screen("expect_rtol", expect_rtol, "none", "number", "str")
    verify = _flag("verify", verify)
    raise_on_failure = _flag("raise_on_failure", raise_on_failure)
    resolved = resolve_params(ex, _screen_params(dict(params or {})))
    expectations = _expectations(ex, expect, expect_rtol, expect_points, expect_seed, expect_min_digits)
    sol = solve_resolved(ex, resolved, methods=_methods(method), rtol=_rtol(ex, rtol), verify=verify,
                         expectations=expectations)
    if raise_on_failure and sol.solver_failed:
        exc = NumericFailure(f"{ex.id}: " + "; ".join(str(e) for e in sol.errors))
        exc.solution = sol
        raise exc
    return sol


def _expectations(ex, expect: dict | None, expect_rtol, expect_points=None, expect_seed=None, min_digits=None):
    """``expect={"theta_c": "35.26deg"}`` -> the command line's --expect judgements (None: nothing expected);
    ``expect_points``/``expect_seed`` as ``--expect-points``/``--expect-seed``, named as the API names them."""
    if not expect:
        if expect_rtol is not None:
            raise BadInput("expect_rtol: given without any expected value")
        if expect_points is not None or expect_seed is not None:
            raise BadInput("expect_points/expect_seed: given without any formula in expect")
        if min_digits is not None:
            raise BadInput("expect_min_digits: given without any expected value")
        return None
    outputs = [o.name for o in ex.outputs]
    for name, value in expect.items():
        if not isinstance(name, str) or name.strip().replace("-", "_") not in outputs:
            key = f'expect["{_shown(name)}"]' if isinstance(name, str) else f"expect[{_shown(name)}]"
            raise BadInput(f"{key}: not an output of {ex.id}; its outputs are: {', '.join(outputs)}")
        _screen(f"expect[{name!r}]", value, "number", "str")
    pairs = [f"{name}={_value_text(value)}" for name, value in expect.items()]
    try:
        return parse_expectations(ex, pairs, None if expect_rtol is None else _value_text(expect_rtol),
                                  expect_points, expect_seed, names=("expect_points", "expect_seed", "expect_min_digits"),
                                  min_digits=min_digits)
    except BadInput as exc:  # named as the API names them: the keyword, not the command-line flag
        raise BadInput(_api_words(str(exc))) from None


def _api_words(message: str) -> str:
    """``--expect theta_c: ...`` -> ``expect["theta_c"]: ...``; ``--expect-rtol`` -> ``expect_rtol``."""
    import re

    message = message.replace("--expect-rtol", "expect_rtol")
    message = re.sub(r"^--expect ([A-Za-z_][A-Za-z0-9_]*):", r'expect["\1"]:', message)
    return message.replace("--expect NAME=VALUE", "expect={NAME: VALUE}").replace("--expect", "expect=")


def solve_resolved(ex, params, *, methods=("analytic", "numeric"), rtol: float | None = None,
                   verify: bool = True, expectations=None, budget_s: float | None = None) -> Solution:
    """The cross-check at checked parameters: what ``mech.solve`` and ``mech solve`` both run;
    ``expectations`` (``parse_expectations``) judges the user's own answers against it.  ``budget_s``: the
    solve's budget (default ``MECH_BUDGET_S``), which the trajectory, when asked for, shares."""
    from mech.core import budget
    from mech.verification.crosscheck import cross_check

    import functools

    budget_s = budget.default_seconds() if budget_s is None else float(budget_s)
    deadline = time.monotonic() + budget_s
    result = cross_check(ex, params, methods=tuple(methods), rtol=rtol, verify=verify and "numeric" in methods,
                         budget_s=budget_s)
    # the trajectory, when asked for, shares the solve's budget
    result = result.replace(trajectory_of=functools.partial(_motion, deadline=deadline))
    if expectations is None:
        return result
    from mech.students import expectations as expecting

    # the formulas' points, references and judging share the solve's budget: what the cross-check left
    with budget.limit(max(deadline - time.monotonic(), 1e-3), what="the solve (MECH_BUDGET_S gives it more)"):
        return expecting.attach(result, expectations)


def parse_expectations(ex, pairs: list[str], expect_rtol: str | None = None, expect_points=None,
                       expect_seed=None, names: tuple = ("--expect-points", "--expect-seed", "--min-digits"),
                       min_digits=None):
    """``--expect NAME=VALUE`` texts (and ``--expect-rtol``) -> the judgements ``solve_resolved`` takes;
    ``expect_points``/``expect_seed``: how many parameter sets a formula is checked at, and their seed
    (``names``: how an error names them)."""
    from mech.students import expectations as expecting
    from mech.students.points import MAX_POINTS  # parameter sets a formula is checked at, at most

    digits = expecting.parse_count(min_digits, names[2] if len(names) > 2 else "--min-digits", 1, 17)
    out = expecting.parse_expect_options(ex, list(pairs), expect_rtol,
                                         expecting.MIN_DIGITS if digits is None else digits)
    points = expecting.parse_count(expect_points, names[0], 1, MAX_POINTS)
    seed = expecting.parse_count(expect_seed, names[1], 0, 2**63 - 1)
    if points is not None or seed is not None:
        out = expecting.with_range(out, points, seed)
    return out


# -- sweep -----------------------------------------------------------------------

MAX_N = 10_000  # values of one swept parameter, as on the command line
MAX_POINTS = 100_000  # points of one sweep, as on the command line


def _axis_values(ex, name: str, spec) -> tuple[list[float], bool]:
    """A range tuple (start, stop, n[, "log"]) or a list of values -> SI values, within the command line's
    limits (checked before anything is allocated)."""
    if isinstance(spec, tuple) and len(spec) in (3, 4) and isinstance(spec[2], (int, np.integer)) \
            and not isinstance(spec[2], bool):
        log = len(spec) == 4 and str(spec[3]).lower() in ("log", "geom")
        if len(spec) == 4 and not log:
            raise BadInput(f"{name}: a range is (start, stop, n) or (start, stop, n, 'log'), got {_shown(spec)}")
        n = int(spec[2])
        if n < 1 or n > MAX_N:
            raise BadInput(f"{name}: n in {_shown(spec)} must be between 1 and {MAX_N}")
        start, stop = _convert(ex, name, spec[0]), _convert(ex, name, spec[1])
        if n == 1 and start != stop:
            raise BadInput(f"{name}: one point in {_shown(spec)} needs start = stop (or n >= 2)")
        if log:
            if start <= 0 or stop <= 0:
                raise BadInput(f"{name}: a log range needs positive ends, got {_shown(spec)}")
            lo, hi = math.log(start), math.log(stop)  # not log(stop/start): 1e300/1e-300 overflows
            values = [math.exp(lo + (hi - lo) * k / (n - 1)) for k in range(n)] if n > 1 else [start]
        else:
            values = list(np.linspace(start, stop, n))
        values[0], values[-1] = start, stop
        return [float(v) for v in values], log
    if isinstance(spec, np.ndarray):
        spec = spec.ravel().tolist() if spec.size <= MAX_N else spec
    if len(spec) == 0 or len(spec) > MAX_N:
        raise BadInput(f"{name}: give between 1 and {MAX_N} values, or a range (start, stop, n), "
                       f"got {len(spec)} values")
    return [_convert(ex, name, v) for v in spec], False


def _is_swept(spec) -> bool:
    return isinstance(spec, (tuple, list, np.ndarray))


def sweep(ex_id: str, *, method: str = "both", rtol=None, verify: bool = True, only=None, jobs=None,
          ranges: dict | None = None, budget=None) -> Sweep:
    from mech.problems import registry
    from mech.studies.sweep import Axis, check_total

    ex = _exercise(ex_id)
    _screen("method", method, "str")
    _screen("rtol", rtol, "none", "number", "str")
    _screen("only", only, "none", "names")
    _screen("budget", budget, "none", "number", "str")
    for k, v in dict(ranges or {}).items():
        _screen(_shown(k), v, "number", "str", "numbers")
        if isinstance(v, (list, tuple, np.ndarray)):
            for x in v:
                _screen(_shown(k), x, "number", "str")
    verify = _flag("verify", verify)
    jobs = _jobs(jobs)
    total_s = None if budget is None else check_total(budget, "budget")
    axes, fixed = [], {}
    for name, spec in dict(ranges or {}).items():
        canon = name.replace("-", "_")
        if _is_swept(spec):
            values, log = _axis_values(ex, name, spec)
            axes.append(Axis(canon, tuple(values), log))
        else:
            fixed[canon] = _convert(ex, name, spec)
    if not axes:
        raise BadInput(f"nothing to sweep: give a parameter of {ex.id} a range (start, stop, n) or a list")
    total = math.prod(len(a.values) for a in axes)
    if total > MAX_POINTS:
        raise BadInput(f"the grid has {total} points; at most {MAX_POINTS} in one sweep")
    if only is not None:
        wanted = _names("only", only)
        known = {o.name for o in ex.outputs}
        for name in wanted:
            if name not in known:
                raise BadInput(f"only: '{_shown(name)}' is not an output of {ex.id}; its outputs are: "
                               f"{', '.join(known)}")
    else:
        wanted = None
    methods = _methods(method)
    if methods != ("analytic", "numeric"):
        raise BadInput("sweep runs both methods, cross-checked: method='both'")
    rtol_value = _rtol(ex, rtol)
    result = run_sweep_plan(plan_sweep(ex, axes, fixed, wanted), rtol=rtol_value, verify=verify, jobs=jobs,
                            total_s=total_s)
    result.solutions()  # ``.points``: one typed Solution per point, on either route
    # ``.plot(path=None)``: the figure ``mech sweep --plot`` draws (figures sit above verification's floor)
    result.plot = functools.partial(plot_sweep, result)
    return result


def plot_sweep(result, path=None):
    """A sweep's figure, as ``mech sweep --plot`` draws it (needs matplotlib): the outputs against the first
    swept parameter, or a map over two; returns the matplotlib Figure, saved to ``path`` if given."""
    from mech.figures.common import save
    from mech.figures.sweepfig import sweep_figure

    fig = sweep_figure(result)
    if path is not None:
        save(fig, str(path))
    return fig


@dataclass(frozen=True)
class SweepPlan:
    """A validated sweep of ``mech sweep``: its axes and fixed values, the outputs asked, and whether it runs
    through the exercise's batched route (``batched``: those outputs) or point by point (``points``)."""

    exercise: Any
    axes: list
    fixed: dict
    only: Any
    batched: Any
    points: Any
    n_points: int


def plan_sweep(ex, axes: list, fixed: dict, only=None) -> SweepPlan:
    """Every point validated (bounds and joint checks, ``BadInput`` naming the first bad one) before any
    solve; the batched route where the exercise has one for the outputs asked."""
    from mech.studies.sweep import batched_outputs, validate, validate_grid

    batched = batched_outputs(ex, only)
    if batched:
        validate_grid(ex, axes, fixed)
        return SweepPlan(ex, axes, fixed, only, batched, None, math.prod(len(a.values) for a in axes))
    points = validate(ex, axes, fixed)
    return SweepPlan(ex, axes, fixed, only, None, points, len(points))


def run_sweep_plan(plan: SweepPlan, *, rtol: float | None = None, verify: bool = True, jobs: int | None = None,
                   progress=None, total_s: float | None = None):
    """Run a planned sweep: ``progress(k)`` after every k-th point; returns ``studies.sweep``'s result.
    ``total_s``: the sweep's wall-clock budget (default 600 s), on either route."""
    from mech.studies.sweep import run_batched, run_sweep

    if plan.batched:
        return run_batched(plan.exercise, plan.axes, plan.fixed, plan.batched, rtol=rtol, verify=verify,
                           progress=progress, total_s=total_s)
    return run_sweep(plan.exercise, plan.axes, plan.fixed, plan.points, rtol=rtol, verify=verify, jobs=jobs,
                     progress=progress, only=plan.only, total_s=total_s)


def check_figure_target(path) -> None:
    """Fail (``BadUsage``, one line) before any work when ``path`` cannot take a figure or matplotlib is
    missing."""
    from mech.figures.common import check_target, need_matplotlib

    need_matplotlib()
    check_target(str(path))


def save_sweep_figure(result, path) -> None:
    """A sweep's outputs against its first swept parameter, or as a map over two, saved to ``path``."""
    from mech.figures.common import save
    from mech.figures.sweepfig import sweep_figure

    save(sweep_figure(result), str(path))


# -- grade, bench, plot ----------------------------------------------------------------

def grade(path, budget=None, *, strict: bool = False, jobs: int | None = None, params=None, assignment=None,
          min_digits=None):
    """``mech grade FILE``: every answer of a grading file (TOML, or CSV) held against mech, as a
    ``GradeReport`` (``.to_dict()`` is ``--json``; ``report["ok"]`` reads it).  ``budget``: the grading's
    wall-clock budget in seconds (``--budget``; default 600); ``strict``: BadInput for any entry that
    cannot be read, before anything is graded (else it is graded invalid); ``jobs``: processes;
    ``params``: a CSV's parameters from an assignment's template (``--params``); ``assignment``: the folder
    ``mech assign`` wrote, every entry held to it (``--assignment``); ``min_digits``: the digits rule's
    floor (``--min-digits``; default 2, with an assignment its digits)."""
    from mech.studies.sweep import check_total
    from mech.students.expectations import parse_count

    _screen("path", path, "path")
    _screen("budget", budget, "none", "number", "str")
    _screen("params", params, "none", "path")
    _screen("assignment", assignment, "none", "path")
    strict = _flag("strict", strict)
    jobs = _jobs(jobs)
    min_digits = parse_count(min_digits, "min_digits", 1, 17)
    return grade_report(path, None if budget is None else check_total(budget, "budget"), strict=strict,
                        jobs=jobs, params=params, assignment=assignment, min_digits=min_digits)


def grade_report(path, total_s=None, *, strict: bool = False, jobs: int | None = None, params=None,
                 started: float | None = None, assignment=None, min_digits: int | None = None):
    """The ``GradeReport`` of a grading file; ``started``: the ``time.perf_counter()`` the reported wall
    time counts from (default: now, reading the file included); ``assignment``, ``min_digits``: as
    ``grade``'s."""
    from mech.students import classrun

    return classrun.grade_file(path, total_s, strict=strict, jobs=jobs, params=params, started=started,
                               assignment=assignment, min_digits=min_digits)


def grade_entries(path, total_s=None) -> tuple[list, float]:
    """Every answer of a grading file, judged (``students.answers_files.Entry``), and the seconds it took;
    ``BadInput`` for a bad file, every fault at once (``BadFile.problems``, a line each).  ``total_s``: the
    grading's wall-clock budget (default 600 s); answers not reached by then fail, saying so."""
    report = grade_report(path, total_s, strict=True)
    return list(report.entries), report.seconds


_ASSIGN_MAX_TEXT = 4096  # characters of one string argument of assign (an id, a name, a path, an --over)
_ASSIGN_MAX_ITEMS = 1000  # exercises or --over entries in one call


def _any_shown(value) -> str:
    """``_shown`` of any object, even one whose ``str`` fails or is huge."""
    try:
        return _shown(value)
    except Exception:  # an argument whose __str__ raises: name its type only  # noqa: BLE001
        return f"<{_kind(value)}>"


def _assign_list(name: str, value, limit: int, what: str = "strings") -> list:
    """A string or a list/tuple of strings for ``assign``: its size checked before anything is read from it."""
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, (list, tuple)):
        raise BadInput(f"{name}: give a list of {what}, got {_kind(value)} {_any_shown(value)}")
    if len(value) > limit:
        raise BadInput(f"{name}: {len(value)} items; at most {limit}")
    for v in value:
        if not isinstance(v, str) or len(v) > _ASSIGN_MAX_TEXT:
            raise BadInput(f"{name}: give {what}, got {_kind(v)} {_any_shown(v)}")
    return list(value)


def _assign_path(name: str, value) -> str:
    """A file or folder name: a string or a path object (os.PathLike of a string), no NUL, not too long."""
    import os

    if not _ARG_KINDS["path"](value):
        raise BadInput(f"{name}: give a file name, got {_kind(value)} {_any_shown(value)}")
    try:
        text = os.fspath(value)
    except Exception:  # a path object whose __fspath__ fails: not a path  # noqa: BLE001
        text = None
    if not isinstance(text, str) or len(text) > _ASSIGN_MAX_TEXT:
        raise BadInput(f"{name}: give a file name, got {_kind(value)} {_any_shown(value)}")
    return _screen(name, text, "path")


def _assign_count(name: str, value, none_ok: bool):
    if value is None and none_ok:
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer, str)) or \
            (isinstance(value, str) and len(value) > 40):
        raise BadInput(f"{name}: give a whole number, got {_kind(value)} {_any_shown(value)}")
    return int(value) if isinstance(value, np.integer) else value


def assign(ids, *, seed, out, students=None, n=None, over=None, digits=3, jobs=None, force=False) -> dict:
    """``mech assign``: each student's verified variant of each exercise, written to ``out`` (handout.md,
    handouts/, answers.toml, answers.csv, key.json, key.csv, key.md; atomically; a folder already holding
    an assignment is refused unless ``force``); returns the key.  ``students``: a roster file's path or a
    list of identifiers; ``n``: s1 ... sN instead; ``over``: {name or "ID:name": "LO:HI" or "VALUE"} or
    ["NAME=LO:HI", ...]; ``digits``: significant digits printed.  Every argument is checked (types, sizes,
    paths) before any work: BadInput, never another exception."""
    from mech.core.version import version
    from mech.students import assign as A

    ids = _assign_list("ids", ids, _ASSIGN_MAX_ITEMS, "exercise ids (strings such as \"4.15\")")
    seed = _assign_count("seed", seed, True)
    n = _assign_count("n", n, True)
    digits = _assign_count("digits", digits, False)
    if jobs is not None and (isinstance(jobs, (bool, np.bool_)) or not isinstance(jobs, (int, np.integer))
                             or not 1 <= jobs <= 256):
        raise BadInput(f"jobs: give a whole number of processes in [1, 256] (or None), got {_kind(jobs)} "
                       f"{_any_shown(jobs)}")
    if not isinstance(force, (bool, np.bool_)):
        raise BadInput(f"force: give True or False, got {_kind(force)} {_any_shown(force)}")
    jobs, force = None if jobs is None else int(jobs), bool(force)
    out = _assign_path("out", out)
    if students is not None and not isinstance(students, (list, tuple)):
        students = _assign_path("students", students)
    elif students is not None:
        students = _assign_list("students", students, A.MAX_STUDENTS, "student names (strings)")
    if isinstance(over, dict):
        if len(over) > _ASSIGN_MAX_ITEMS:
            raise BadInput(f"over: {len(over)} items; at most {_ASSIGN_MAX_ITEMS}")
        over = [f"{k}={v}" for k, v in zip(_assign_list("over", list(over), _ASSIGN_MAX_ITEMS, "names"),
                                           _assign_list("over", list(over.values()), _ASSIGN_MAX_ITEMS,
                                                        "ranges (strings such as \"10deg:60deg\")"))]
    elif over is not None:
        over = _assign_list("over", over, _ASSIGN_MAX_ITEMS, "NAME=LO:HI strings")
    return A.assign(ids, seed=seed, out=out, students=students, n=n, over=over, digits=digits, jobs=jobs,
                    version=version(), force=force)


def grade_students(entries: list) -> list[dict]:
    """Per student named in a grading file (entries without a name under None): passed, failed, entries."""
    from mech.students import gradebook

    return gradebook.per_student(entries)


def grade_json(path, entries: list, seconds: float) -> dict:
    """The JSON report of judged grading entries (``mech grade --json``)."""
    from mech.students import gradebook

    return gradebook.grade_json(str(path), entries, seconds)


def bench(ex_id: str, *, methods=None, tols=None, params: dict | None = None, **options) -> dict:
    """``mech bench ID --json``: speed against error of the numeric solver(s)."""
    from mech.problems import registry

    ex = _exercise(ex_id)
    _screen("methods", methods, "none", "names")
    _screen("tols", tols, "none", "number", "numbers")
    for k in ("repeats",):
        if k in options:
            _screen(k, options[k], "int")
            if not 1 <= options[k] <= 1000:
                raise BadInput(f"{k}: {_shown(options[k])}: allowed a whole number in [1, 1000]")
    if "max_seconds" in options:
        _screen("max_seconds", options["max_seconds"], "number")
        if not 0 < options["max_seconds"] <= 3600:
            raise BadInput(f"max_seconds: {_shown(options['max_seconds'])}: allowed (0, 3600]")
    resolved = resolve_params(ex, _screen_params(dict(params or {})))
    if methods is not None:
        methods = _names("methods", [m.strip() for m in methods.split(",")] if isinstance(methods, str) else methods)
    if tols is not None:
        try:
            tols = [float(t) for t in ([tols] if isinstance(tols, (int, float)) else tols)]
        except (TypeError, ValueError, OverflowError):
            raise BadInput(f"tols: give a list of tolerances such as [1e-6, 1e-9], got {_shown(tols)}") from None
        if not tols or not all(0 < t < 1 for t in tols):
            raise BadInput(f"tols: every tolerance must be in (0, 1), got {_shown(tols)}")
    return bench_resolved(ex, resolved, methods=methods, tols=tols, **options)


def bench_resolved(ex, params, *, methods=None, tols=None, **options) -> dict:
    """The bench at checked parameters (``mech bench``); ``BadInput`` for an exercise without a solver pair
    or an unknown method."""
    from mech.studies import bench as benching

    if not (ex.has_numeric and ex.has_analytic):
        raise BadInput(f"{ex.id} has no numeric and analytic solver pair to bench")
    try:
        return benching.bench(ex, params, methods=methods, tols=list(tols) if tols else None, **options)
    except ValueError as exc:
        raise BadInput(str(exc)) from None


def bench_methods(ex, params, text: str) -> list[str]:
    """``--methods`` text -> the rows' canonical names, matched without case (``rk45`` is RK45); an unknown
    name is ``BadInput`` with the nearest name and every known one."""
    import difflib

    from mech.studies import bench as machinery

    names = list(dict.fromkeys(machinery.ODE_METHODS + machinery.OTHER_ODE + tuple(machinery.SYMPLECTIC)
                               + (machinery.STUDENT, machinery.DEFAULT_ROW)))
    by_lower = {n.lower(): n for n in names}
    out = []
    for raw in (m.strip() for m in text.split(",")):
        if not raw:
            continue
        name = by_lower.get(raw.lower())
        if name is None:
            _, own = machinery.probe_route(ex, params)  # a route of the exercise's own (not an integrator)
            if own and own.lower() == raw.lower():
                name = own
            else:
                known = names + ([own] if own and own not in names else [])
                close = difflib.get_close_matches(raw.lower(), [k.lower() for k in known], n=1, cutoff=0.6)
                hint = f"; did you mean {by_lower.get(close[0], close[0])}?" if close else ""
                raise BadInput(f"--methods: unknown method '{_shown(raw)}'{hint} (known: {', '.join(known)})")
        out.append(name)
    return out


def json_safe(obj):
    """An info structure (a bench, a sweep) made JSON-safe: non-finite numbers become null."""
    from mech.verification.crosscheck import _clean

    return _clean(obj)


def plot(ex_id: str, path=None, *, generic: bool = False, vary: str | None = None, params: dict | None = None):
    """``mech plot ID -o PATH``: the exercise's figure (needs matplotlib); returns the matplotlib Figure,
    saved to ``path`` when one is given."""
    from mech.figures import draw
    from mech.figures.common import need_matplotlib, save
    from mech.problems import registry

    ex = _exercise(ex_id)
    _screen("path", path, "none", "path")
    _screen("vary", vary, "none", "str")
    generic = _flag("generic", generic)
    resolved = resolve_params(ex, _screen_params(dict(params or {})))
    if path is not None:
        from mech.core.errors import BadUsage
        from mech.figures.common import check_target

        try:
            check_target(str(path))
        except BadUsage as exc:
            raise BadInput(str(exc)) from None
    if vary is not None:
        if not isinstance(vary, str) or vary.replace("-", "_") not in ex.param_map:
            raise BadInput(f"vary: '{_shown(vary)}' is not a parameter of {ex.id}; its parameters are: "
                           f"{', '.join(ex.param_map)}")
    need_matplotlib()
    fig = draw(ex, resolved, generic=generic, vary=vary.replace("-", "_") if vary else None)
    if path is not None:
        save(fig, str(path))
    return fig


def plot_resolved(ex, params, path, *, generic: bool = False, vary: str | None = None, n_numeric: int | None = None,
                  rtol: float | None = None, dpi: float = 110, budgets: float = 2) -> None:
    """``mech plot``: the exercise's figure at checked parameters, saved to ``path`` (its suffix chooses
    the format; a bad target or no matplotlib fails before any solve).  Every numeric solve has its own
    budget (a failed one is shown in the figure); the whole figure, the scene's own integrations included,
    ends within ``budgets`` solve budgets or raises ``NumericFailure``."""
    import warnings

    from mech.core import budget
    from mech.figures import draw
    from mech.figures.common import check_target, need_matplotlib, save

    check_target(str(path))
    need_matplotlib()
    options = {} if n_numeric is None else {"n_numeric": n_numeric}
    with budget.limit(budgets * budget.default_seconds(), what=f"the figure of {ex.id}"), \
            warnings.catch_warnings():
        # numpy's overflow and division warnings are no message of the figure: a value that is not
        # finite leaves a gap, and a numeric solver's failure is told in the caption
        warnings.simplefilter("ignore", RuntimeWarning)
        # the legends are placed by save (a layout pass, no physics), outside the solves' budget
        fig = draw(ex, params, generic=generic, vary=vary, rtol=rtol, finish=False, **options)
    save(fig, str(path), dpi=dpi)


# -- check -------------------------------------------------------------------------

def check(ids=None, hard: bool = False, *, jobs: int | None = None, started=None, finished=None):
    """The report of ``mech check``.  ``started(case, n_cases)`` and ``finished(case)``, where given, are
    called around every case (a progress bar); ``jobs``: processes (None: decided by the number of cases)."""
    from mech.studies.checking import run_check
    from mech.problems import registry

    if ids is not None and not _ARG_KINDS["names"](ids):
        for i in ids if isinstance(ids, (list, tuple)) else [ids]:
            if _ARG_KINDS["number"](i) and abs(i) < 1e6:
                registry.get(i)  # a number: BadInput saying to quote it
        raise BadInput(f"ids: give an id or a list of ids, got {_kind(ids)} {_shown(ids)}")
    if isinstance(ids, str):
        ids = [ids]
    hard = _flag("hard", hard)
    exercises = [registry.get(i) for i in ids] if ids else list(registry.all_exercises().values())
    return run_check(exercises, hard=hard, jobs=jobs, started=started, finished=finished)


def check_against_baselines(ids=None, hard: bool = False, *, baseline: str | None = None,
                            save_baseline: str | None = None, jobs: int | None = None, started=None,
                            finished=None):
    """``mech check`` with baselines: (the report, the comparison with ``baseline`` or None).  A bad
    baseline file fails (``BadInput``) before any case runs; ``save_baseline`` records every checked value."""
    if not (baseline or save_baseline):
        return check(ids, hard, jobs=jobs, started=started, finished=finished), None
    from mech.verification import baseline as baselines_

    old = baselines_.open_baseline(baseline) if baseline else None
    report = check(ids, hard, jobs=jobs, started=started, finished=finished)
    return report, baselines_.baselines(report, hard, old, baseline, save_baseline)


def plot_bench(result: dict, path) -> None:
    """A bench's error against time and against evaluations, log-log, to ``path`` (needs matplotlib)."""
    from mech.figures.benchfig import plot_bench as draw

    draw(result, str(path))
