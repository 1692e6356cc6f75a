"""The check runner behind ``mech check``: every exercise's cross-check at its defaults and, with --hard, on
its hard cases, in a process pool when there are enough cases to share.  An exercise with a batched route
(``batched``) has its cases solved together through it, each judged alone (``run_batch``)."""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass, field

from mech.problems.spec import BadInput, Exercise


@dataclass
class Case:
    exercise: Exercise
    label: str
    given: dict
    agree: bool | None = False  # the case's conclusion (``judge.conclude``): None no verdict, never a failure
    seconds: float = 0.0
    worst_ratio: float | None = None
    detail: str = ""
    result: object = None
    same_as: list = field(default_factory=list)  # hard cases (numbers) that resolve to this case's parameters

    @property
    def ok(self) -> bool:
        """The case did not fail: it agrees, or has no verdict (nothing could be compared)."""
        return self.agree is not False

    @property
    def description(self) -> str:
        """The label as shown: ``hard 2: theta0 = 1 deg``, ``defaults (= hard 1)``; ``label`` stays the key
        (``hard 2``) that baselines and scripts match on."""
        text = self.label
        if self.given and self.label != "defaults":
            text += f": {case_text(self.exercise, self.given)}"
        if self.same_as:
            text += f" (= hard {', '.join(map(str, self.same_as))})"
        return text

    def as_json(self) -> dict:
        d = {"id": self.exercise.id, "case": self.label, "description": self.description, "params": self.given,
             "ok": self.ok, "seconds": self.seconds, "worst_err_over_tol": self.worst_ratio, "detail": self.detail}
        if self.result is not None:
            d["quantities"] = [q.as_json() for q in self.result.quantities]
        return d


@dataclass
class Report:
    cases: list[Case] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def passed(self) -> int:
        return sum(c.agree is True for c in self.cases)

    @property
    def failed(self) -> int:
        return sum(c.agree is False for c in self.cases)

    @property
    def ok(self) -> bool:
        return self.failed == 0

    def as_json(self) -> dict:
        return {"ok": self.ok, "passed": self.passed, "failed": self.failed, "seconds": self.seconds,
                "cases": [c.as_json() for c in self.cases]}


def plan(exercises, hard: bool) -> list[Case]:
    """The cases to run: each exercise once (a repeated id is run once), its defaults first, then its hard
    cases; a hard case that resolves to the defaults is not run twice (the defaults' description names
    it)."""
    cases: list[Case] = []
    seen: set[str] = set()
    for ex in exercises:
        if ex.id in seen:
            continue
        seen.add(ex.id)
        defaults = Case(ex, "defaults", {})
        cases.append(defaults)
        if not hard:
            continue
        try:
            default_values = dict(ex.resolve({}))
        except BadInput:
            default_values = None
        same = []
        for k, h in enumerate(ex.hard_cases, 1):
            given = dict(h["params"])
            try:
                is_default = default_values is not None and dict(ex.resolve(given)) == default_values
            except BadInput:
                is_default = False
            if is_default:
                same.append(k)
                continue
            cases.append(Case(ex, f"hard {k}", given))
        defaults.same_as = same
    return cases


def case_text(ex: Exercise, values: dict) -> str:
    """``theta0 = 1 deg, l = 2 m``: a hard case's parameters as people read them."""
    return ", ".join(f"{k} = {ex.param_map[k].show(v)}" if k in ex.param_map else f"{k} = {v}"
                     for k, v in values.items())


def run_case(case: Case) -> Case:
    """One case cross-checked alone, as ``mech solve`` cross-checks it."""
    from mech.verification.crosscheck import cross_check

    t0 = time.perf_counter()
    ex = case.exercise
    try:
        params = ex.resolve(case.given)
    except BadInput as exc:
        case.detail = f"bad parameters: {exc}"
        case.agree = False
        case.seconds = time.perf_counter() - t0
        return case
    if len(ex.methods) < 2:
        case.agree = None  # nothing to compare: no verdict
        case.detail = f"only {', '.join(ex.methods) or 'no'} solver registered"
        case.seconds = time.perf_counter() - t0
        return case
    result = cross_check(ex, params)
    _conclude(case, result, time.perf_counter() - t0)
    return case


def _conclude(case: Case, result, seconds: float) -> None:
    """The case's verdict, worst ratio and detail from its cross-check ``result``."""
    case.result = result
    case.seconds = seconds
    # |numeric - analytic| over the allowance the judge held it to (its verdict is the case's)
    ratios = [q.abs_err / q.allowed for q in result.quantities
              if q.abs_err is not None and q.allowed and q.agree is not None]
    case.worst_ratio = max(ratios) if ratios else None
    case.agree = result.agree
    bad = [q.name for q in result.quantities if q.agree is False]
    details = []
    if bad:
        details.append("disagree: " + ", ".join(bad))
    details.extend(str(e) for e in result.errors)
    for q in result.quantities:
        if q.agree is False and q.notes:
            details.append(f"{q.name}: {'; '.join(q.notes)}")
    case.detail = "; ".join(details)


def run_batch(cases: list[Case]) -> list[Case]:
    """The cases of one exercise with a batched route, solved together through it (``variants.
    cross_check_variants``: both solves over the variants' arrays, each variant judged by the cross-check's
    rule, its claim, rerun at rtol/10 and invariants its own).  A case the batch does not pass cleanly (it
    fails, has no verdict or a failure noted), or the whole batch when it raises, is then cross-checked alone
    (``run_case``): a failure reads as ``mech solve`` gives it, and fails that case only.  A case whose
    parameters are refused is reported by ``run_case``.  The batch is the exercise's, never the pool's: the
    same for any number of workers."""
    from mech.studies.variants import cross_check_variants

    t0 = time.perf_counter()
    ex = cases[0].exercise
    todo, params = [], []
    if batched(ex) and len(ex.methods) >= 2:
        for case in cases:
            try:
                params.append(ex.resolve(case.given))
                todo.append(case)
            except BadInput:
                continue
    solved: set[int] = set()
    if len(todo) >= 2:
        try:
            solutions = cross_check_variants(ex, params)
        except Exception:  # noqa: BLE001  the batch failed as a whole: each case is cross-checked alone
            solutions = []
        share = (time.perf_counter() - t0) / len(todo)  # each case's part of the batch
        for case, solution in zip(todo, solutions):
            if _clean(solution):
                _conclude(case, solution, share)
                solved.add(id(case))
    for case in cases:
        if id(case) not in solved:
            run_case(case)
    return cases


def _clean(solution) -> bool:
    """Did the batch pass the case as the one-point cross-check would?  It agrees, notes no failure, and each
    value is a finite number inside mech's floating-point range or declared undefined (the one-point check
    fails a value beyond that range, ``crosscheck._undefine_bad_values``; the batch does not look)."""
    from mech.studies.variants import in_range

    if solution.agree is not True or solution.errors:
        return False
    return in_range(solution)


def batched(ex: Exercise) -> bool:
    """Are ``ex``'s cases solved together?  Where its batched route gives every output with a tighter rerun
    (``variants.batchable``) and its one-point solve is that route's batch of one, on the same analytic hook
    (a one-point solver of its own, such as 5.8's, or one a test swapped in, is what ``mech solve`` runs:
    its cases are checked one by one)."""
    from mech.studies.variants import batchable

    return (batchable(ex) and ex.numeric_solver == ex.batch_of_one
            and getattr(ex.analytic_solver, "array_hook", None) is not None)


def units(cases: list[Case]) -> list[list[int]]:
    """The work in plan order, as indices of ``cases``: the cases of an exercise with a batched route
    together (``run_batch``), every other case alone."""
    out: list[list[int]] = []
    batch_of: dict = {}
    for i, case in enumerate(cases):
        ex = case.exercise
        if not batched(ex):
            out.append([i])
        elif ex.id in batch_of:
            batch_of[ex.id].append(i)
        else:
            batch_of[ex.id] = [i]
            out.append(batch_of[ex.id])
    return out


def run_unit(cases: list[Case]) -> list[Case]:
    """One unit of ``units``: a batch, or a case alone."""
    return run_batch(cases) if len(cases) > 1 else [run_case(cases[0])]


def run_check(exercises, hard: bool = False, jobs: int | None = None, started=None, finished=None) -> Report:
    """Every planned case, in plan order.  ``jobs``: processes to use (None: one per core when there are
    enough cases to share, see ``plan_jobs``; never more than the units of work, ``units``).
    ``started(case, n_cases)`` and ``finished(case)``, where given, are called around every case (a batch's
    cases all started before it, all finished after), in this process and never from a thread (a progress
    bar: the cross-check forks its rerun, and the pool its workers, only from a single-threaded process)."""
    cases = plan(exercises, hard)
    report = Report(cases=cases)
    t0 = time.perf_counter()
    work = units(cases)
    workers = min(plan_jobs(len(cases), jobs), len(work))  # a batch is one worker's

    def begin(case):
        if started is not None:
            started(case, len(cases))

    def end(case):
        if finished is not None:
            finished(case)

    if workers > 1:
        _run_pooled(cases, work, workers, begin, end)
    else:
        for unit in work:
            for i in unit:
                begin(cases[i])
            run_unit([cases[i] for i in unit])
            for i in unit:
                end(cases[i])
    report.seconds = time.perf_counter() - t0
    return report


MIN_POOLED_CASES = 8  # fewer cases stay in this process, each with its rerun forked beside it


def plan_jobs(n_cases: int, jobs: int | None = None) -> int:
    """Processes for ``n_cases``: ``jobs`` when given, else one per core once there are enough cases.

    Measured on a 2-core machine (``mech check --hard``, 162 cases): the cases one after the other, each
    with its rerun forked onto the second core, spend 3.4 s of CPU on the 162 forks alone; two workers,
    each running its cases' reruns after their solves, keep both cores busy with the work itself."""
    from mech.studies.sweep import usable_cores

    cores = usable_cores()
    if jobs is not None:  # never more than the cores: -j 256 on 2 cores only thrashes
        return max(1, min(jobs, n_cases, cores))
    if cores < 2 or n_cases < MIN_POOLED_CASES or not hasattr(os, "fork") or not sys.platform.startswith("linux"):
        return 1
    return min(cores, n_cases)


def _schedule(cases: list[Case], work: list[list[int]]) -> list[list[int]]:
    """The order units are handed to the workers: batches first, then the cases that integrate equations of
    motion (they are the long ones), hard cases before defaults, so that the last unit to finish is a short
    one."""
    def key(k):
        unit = work[k]
        c = cases[unit[0]]
        return (len(unit) == 1, not c.exercise.states, c.label == "defaults", k)

    return [work[k] for k in sorted(range(len(work)), key=key)]


def _run_pooled(cases: list[Case], work: list[list[int]], workers: int, started, finished) -> None:
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    from mech.studies.sweep import pool_worker_init

    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"),
                               initializer=pool_worker_init, initargs=(os.getpid(),))
    try:
        futures = {}
        for unit in _schedule(cases, work):
            ex_id = cases[unit[0]].exercise.id
            futures[pool.submit(_remote_unit, ex_id, [(cases[i].label, cases[i].given) for i in unit])] = unit
        for fut in as_completed(futures):
            unit = futures[fut]
            got = fut.result()
            for i, (agree, seconds, ratio, detail, result) in zip(unit, got):
                case = cases[i]
                started(case)
                if result is not None:
                    result = result.replace(exercise=case.exercise)
                case.agree, case.seconds, case.worst_ratio, case.detail, case.result = (agree, seconds, ratio,
                                                                                        detail, result)
                finished(case)
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


def _remote_unit(ex_id: str, labelled: list):
    """One unit of work (a batch, or a case alone) in a pool worker (a case alone runs its rerun after its
    solve: the cores are the pool's): each case's outcome, in order."""
    from mech.problems import registry

    ex = registry.get(ex_id)
    out = []
    for case in run_unit([Case(ex, label, given) for label, given in labelled]):
        result = case.result
        if result is not None:  # what a report uses travels back; the exercise is the parent's own
            result = result.replace(exercise=None, run=None)
        out.append((case.agree, case.seconds, case.worst_ratio, case.detail, result))
    return out
