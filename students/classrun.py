"""The class run: every readable entry of an answers file cross-checked and judged, variants of one
exercise solved together where the exercise has a batched route, in a pool of processes, within the
command's budget; ``grade_file`` reads, grades and reports one file."""

from __future__ import annotations

import time
import warnings

from mech.problems.spec import BadInput
from mech.core.safeio import shown
from mech.students.answers_files import Entry, read_answers
from mech.students.gradebook import GradeReport

__all__ = ["grade", "grade_file"]


def _not_graded(entry: Entry, why: str):
    """Judgements saying why ``entry``'s answers were not graded (``State.NOT_GRADED``: mech has no
    verdict; never wrong)."""
    from mech.students.answers import Judgement
    from mech.students.cells import State

    units = {o.name: o.unit for o in entry.exercise.outputs}
    return [Judgement(e.name, units.get(e.name, ""), e.text, e.value, False, None, verdict=why,
                      state=State.NOT_GRADED) for e in entry.expectations]


def _out_of_time(entry: Entry, total_s: float):
    """Judgements saying the command's budget did not reach ``entry``: not graded, never wrong."""
    from mech.students.answers import Judgement
    from mech.students.cells import State

    why = f"not graded: the total budget of {total_s:g} s ran out (--budget SECONDS gives it more)"
    units = {o.name: o.unit for o in entry.exercise.outputs}
    return [Judgement(e.name, units.get(e.name, ""), e.text, e.value, False, None, verdict=why,
                      state=State.NOT_GRADED) for e in entry.expectations]


def _grade_one(entry: Entry, deadline: float, total_s: float, solved: dict) -> None:
    """One entry, cross-checked and judged; whatever goes wrong in it (an overflow, a bug in mech) is
    this entry's verdict, never the rest of the class's.  Only the command's clock (``deadline``) stops
    it, and an entry it stopped, or that ended past it, is not graded: the solves and the checks inside
    count work, so an entry graded gets the same verdicts on any machine at any load."""
    from mech.core import budget
    from mech.students.answers import judge
    from mech.verification.crosscheck import cross_check

    t0 = time.perf_counter()
    try:
        left = deadline - time.monotonic()
        if left <= 0.05:  # not reached: not even its parameters are looked at (the budget holds)
            raise budget.OutOfTime("not reached")
        params = entry.exercise.resolve(entry.given)
        key = (entry.exercise.id, tuple(sorted(params.items())))
        # the solve and the formulas under the clock; a warning (numpy's, scipy's, an exercise's) is never
        # a message: the values it touches are judged like any other
        with budget.limit(left, what="grading (--budget gives it more)"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if key in solved:
                result = solved[key]
            else:
                result = solved[key] = cross_check(entry.exercise, params)
            entry.judgements = judge(result, entry.expectations)
        if time.monotonic() > deadline:  # ended past the clock: a check inside may have been cut short
            raise budget.OutOfTime("ended past the budget")
        entry.result = result.with_expected(entry.judgements)
    except budget.OutOfTime:  # the command's clock: not reached, not graded (its numbers say nothing)
        entry.result = None
        entry.judgements = _out_of_time(entry, total_s)
    except (BadInput, ArithmeticError, ValueError, budget.OutOfWork) as exc:  # this entry's own verdict
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
    todo, deadline, total_s = _POOL["args"]
    solved: dict = {}
    for key, sol in (presolved or {}).items():
        solved[key] = sol.replace(exercise=todo[indices[0]].exercise) if sol is not None else None
    solved = {k: v for k, v in solved.items() if v is not None}
    out = []
    for i in indices:
        e = todo[i]
        _grade_one(e, deadline, total_s, solved)
        result = e.result.replace(exercise=None, run=None) if e.result is not None else None
        out.append((i, result, e.judgements, e.seconds))
    return out


def _remote_batch(firsts: list[int]) -> dict:
    """A batched exercise's variants solved in a pool worker: {key: Solution without its exercise}."""
    todo, deadline, _total_s = _POOL["args"]
    got = _batched_solve([todo[i] for i in firsts], deadline)
    return {k: v.replace(exercise=None, run=None) for k, v in got.items()}


def grade(entries: list[Entry], total_s: float | None = None, jobs: int | None = None) -> None:
    """Cross-check and judge every readable entry, within a total wall-clock budget (``total_s``, default
    ``DEFAULT_TOTAL_S``): the solves and checks count work (the same verdicts at any load), the clock only
    stops the run, and an entry it did not reach, or cut short, is not graded (``State.NOT_GRADED``),
    saying so.  ``jobs``: processes (None: one per core once there are enough entries; each worker runs
    a cross-check's rerun after its solve)."""
    import threading

    from mech.studies.checking import plan_jobs
    from mech.studies.sweep import DEFAULT_TOTAL_S, check_total

    total_s = DEFAULT_TOTAL_S if total_s is None else check_total(total_s)
    deadline = time.monotonic() + total_s
    todo = [e for e in entries if e.invalid is None and e.expectations]
    groups = _solve_groups(todo)
    # a class file answers the same exercise at the same parameters: one solve each; an exercise with a
    # batched route solves all its variants at once
    plan = _batch_plan(todo, groups)
    workers = plan_jobs(len(groups), jobs)
    # fork only a single-threaded process (a lock another thread holds would stay held in the workers)
    if workers > 1 and threading.active_count() == 1:
        _grade_pooled(todo, groups, workers, deadline, total_s, plan)
        return
    solved: dict = {}
    for gidx in plan.values():
        solved.update(_batched_solve([todo[groups[g][0]] for g in gidx], deadline))
    for g in groups:
        for i in g:
            _grade_one(todo[i], deadline, total_s, solved)


MIN_BATCHED = 4  # variants of one exercise from which its batched route solves them (below: one by one)
BATCH_BLOCK = 64  # variants a batched solve takes at once (a class's 300 of one exercise: 5 blocks over the cores)


def _batch_plan(todo: list[Entry], groups: list[list[int]]) -> dict:
    """{(exercise id, block): the indices of its groups} for each exercise whose batched route (the charts')
    gives all its outputs, with a tighter rerun to verify by, and at least ``MIN_BATCHED`` variants."""
    from mech.studies.variants import batchable

    by_ex: dict = {}
    for k, g in enumerate(groups):
        ex = todo[g[0]].exercise
        if batchable(ex):
            by_ex.setdefault(ex.id, []).append(k)
    # blocks of at most BATCH_BLOCK variants in the file's order: the cores share an exercise's variants, and
    # a block, so each variant's solve, is the same for any number of workers
    return {(i, b): ks[b:b + BATCH_BLOCK] for i, ks in by_ex.items() if len(ks) >= MIN_BATCHED
            for b in range(0, len(ks), BATCH_BLOCK)}


def _batched_solve(firsts: list[Entry], deadline: float) -> dict:
    """The cross-checks of the variants of one exercise (an entry at each), solved at once: both solves
    (at rtol and rtol/10) over the variants' arrays and each variant judged by the cross-check's rule
    (``sweep.run_batched``).  {(exercise id, params): Solution}; empty when the batch fails as a whole
    (each variant is then cross-checked alone)."""
    from mech.studies.variants import cross_check_variants

    out: dict = {}
    ex = firsts[0].exercise
    try:
        params = [ex.resolve(e.given) for e in firsts]
        left = deadline - time.monotonic()
        if left <= 0.05:  # past the clock (not graded); never a different route for the time left
            return out
        solutions = cross_check_variants(ex, params, total_s=left)
        if time.monotonic() > deadline:
            return {}  # the clock may have cut a chunk: each variant meets the clock alone (not graded)
        for q, sol in zip(params, solutions):
            out[(ex.id, tuple(sorted(q.items())))] = sol
    except Exception:  # noqa: BLE001  the batch failed as a whole: each variant is cross-checked alone
        return {}
    return out


def _grade_pooled(todo, groups, workers, deadline, total_s, plan) -> None:
    """The groups over a pool of ``workers``: a batched exercise's variants are solved by one worker while
    the others grade the rest, then its groups are graded with the batch's solutions."""
    import multiprocessing
    import os
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

    from mech.studies.sweep import pool_worker_init

    _POOL["args"] = (todo, deadline, total_s)
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
        for ks in plan.values():
            pending[pool.submit(_remote_batch, [groups[k][0] for k in ks])] = ("batch", ks)
        for k in range(0, len(rest), size):
            indices = sum(rest[k:k + size], [])
            pending[pool.submit(_remote_group, indices)] = ("grade", indices)
        while pending:
            left = deadline - time.monotonic()
            if left < -0.05:  # the clock ran out: what the workers still hold is not reached (the budget holds)
                break
            done, _ = wait(list(pending), timeout=left + 0.05, return_when=FIRST_COMPLETED)
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
    if pending:  # left at the clock: not graded; the workers end their task past the clock at once
        for kind, ks in pending.values():
            for i in (ks if kind == "grade" else sum((groups[j] for j in ks), [])):
                if not todo[i].judgements:
                    todo[i].judgements = _out_of_time(todo[i], total_s)
        pool.shutdown(wait=False, cancel_futures=True)
        return
    pool.shutdown(wait=True)


def grade_file(path, total_s=None, *, strict: bool = False, jobs: int | None = None, params=None,
               started: float | None = None, assignment=None, min_digits: int | None = None) -> GradeReport:
    """A grading file (TOML, or CSV: by its name) read, graded and reported; ``params``: a CSV's parameters
    from an assignment's template; ``assignment``: the folder ``mech assign`` wrote, every entry held to
    it (its parameters, digits, range; ``students.against``); ``min_digits``: the digits rule's floor
    (default ``MIN_DIGITS``; with an assignment, its digits); ``started``: the ``time.perf_counter()`` the
    reported wall time counts from (default: now, reading the file included)."""
    t0 = time.perf_counter() if started is None else started
    entries = read_answers(path, strict=strict, params=params, assignment=assignment, min_digits=min_digits)
    grade(entries, total_s, jobs=jobs)
    return GradeReport(str(path), tuple(entries), time.perf_counter() - t0)

