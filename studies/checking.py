"""The check runner behind ``mech check``: every exercise's cross-check at its defaults and, with --hard, on
its hard cases, in a process pool when there are enough cases to share."""

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
    case.result = result
    case.seconds = time.perf_counter() - t0
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
    return case


def run_check(exercises, hard: bool = False, jobs: int | None = None, started=None, finished=None) -> Report:
    """Every planned case, in plan order.  ``jobs``: processes to use (None: one per core when there are
    enough cases to share, see ``plan_jobs``).  ``started(case, n_cases)`` and ``finished(case)``, where
    given, are called around every case, in this process and never from a thread (a progress bar: the
    cross-check forks its rerun, and the pool its workers, only from a single-threaded process)."""
    cases = plan(exercises, hard)
    report = Report(cases=cases)
    t0 = time.perf_counter()
    workers = plan_jobs(len(cases), jobs)

    def begin(case):
        if started is not None:
            started(case, len(cases))

    def end(case):
        if finished is not None:
            finished(case)

    if workers > 1:
        _run_pooled(cases, workers, begin, end)
    else:
        for case in cases:
            begin(case)
            run_case(case)
            end(case)
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


def _schedule(cases: list[Case]) -> list[int]:
    """The order cases are handed to the workers: those that integrate equations of motion first (they
    are the long ones), hard cases before defaults, so that the last case to finish is a short one."""
    def key(i):
        c = cases[i]
        return (not c.exercise.states, c.label == "defaults", i)

    return sorted(range(len(cases)), key=key)


def _run_pooled(cases: list[Case], workers: int, started, finished) -> None:
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    from mech.studies.sweep import pool_worker_init

    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"),
                               initializer=pool_worker_init, initargs=(os.getpid(),))
    try:
        futures = {}
        for i in _schedule(cases):
            c = cases[i]
            futures[pool.submit(_remote_case, c.exercise.id, c.label, c.given)] = i
        for fut in as_completed(futures):
            case = cases[futures[fut]]
            started(case)
            agree, seconds, ratio, detail, result = fut.result()
            if result is not None:
                result = result.replace(exercise=case.exercise)
            case.agree, case.seconds, case.worst_ratio, case.detail, case.result = agree, seconds, ratio, detail, result
            finished(case)
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


def _remote_case(ex_id: str, label: str, given: dict):
    """One case in a pool worker (its rerun after its solve: the cores are the pool's)."""
    from mech.problems import registry

    case = run_case(Case(registry.get(ex_id), label, given))
    result = case.result
    if result is not None:  # what a report uses travels back; the exercise is the parent's own
        result = result.replace(exercise=None, run=None)
    return case.agree, case.seconds, case.worst_ratio, case.detail, result
