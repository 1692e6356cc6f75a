"""The cross-check: both solvers run on the same parameters and every output is compared.

Tolerance of an output, relative to the analytic value:
  * the numeric solver's claim for it (``run.claim``), by default
    ``exercise.tol_factor * rtol``: a global error of an adaptive integrator
    stays within a few tens of its requested rtol on the smooth, bounded runs
    these exercises need, and the verification below tests that claim;
  * for a leading-order analytic theory, at least the relative size of what it
    neglects (``exercise.expected_error``).
An absolute claim adds to it, for outputs that can be zero.

Verification (on by default): the numeric solver is run again at rtol/10;
when the two numeric answers differ by more than the claim, the claim is not
earned and the output is reported as unreliable (agree false).

On a machine with two or more cores (POSIX), the rerun runs at the same time
as the solve, in a forked child process that sends its answers back through a
pipe: a solve then takes the longer of the two instead of their sum (the
budget of ``mech solve`` is for 2 cores).  Set ``MECH_SERIAL_VERIFY=1`` (or
``crosscheck.PARALLEL_VERIFY = False``, as ``mech sweep``'s worker processes
do) to run it after the solve instead, sharing ``Run.shared`` with it.  The
numbers are the same either way: the solvers are deterministic.  Only a
single-threaded process forks (a lock held by another thread would stay held
in the child; ``mech check``'s progress bar is redrawn by hand for that), and
the child runs under the same work budget as a serial rerun (``budget.SOLVE_WORK``:
the same verdict either way) and a memory limit, and dies with its parent
whatever kills the parent (prctl PR_SET_PDEATHSIG).  A child that dies without
answering (a crash of the fork, not the solver's failure) is replaced by the
serial rerun; one that runs out of its work is a loud failure, like a serial
rerun that runs out of its work.  Linux only.

Budgets count work, never seconds (``mech.core.budget``): the solve and the
rerun each get ``budget.SOLVE_WORK`` units.  A wall clock (``budget_s``, or a
command's in force around the call) only stops the call: when the clock spent
is the caller's, its ``OutOfTime`` is raised to the caller (what it did not
reach is not judged), never turned into a verdict here.
"""

from __future__ import annotations

import math
import os
import pickle
import sys
import time
import warnings
from typing import Any

from mech.problems.scales import LOG10_LIMIT, out_of_range
from mech.problems.spec import BadInput, Exercise, NumericFailure, Params, Undefined
from mech.problems.validity import analytic_errors, expected_errors
from mech.verification.result import Failure, Quantity, Solution, _clean  # noqa: F401  (_clean: bench)

__all__ = ["Quantity", "Solution", "Failure", "cross_check", "PARALLEL_VERIFY"]

PARALLEL_VERIFY = True  # the rerun at rtol/10 in a forked child where there is a second core (see above)


def _parallel_ok() -> bool:
    if not PARALLEL_VERIFY or os.environ.get("MECH_SERIAL_VERIFY") or not hasattr(os, "fork"):
        return False
    import sys

    if not sys.platform.startswith("linux"):
        return False  # elsewhere fork after numpy's libraries are loaded is not known to be safe (macOS)
    import threading

    if threading.active_count() > 1:
        # a lock another thread holds at the fork (a progress bar's console, a stream's buffer) would stay
        # held forever in the child: fork only a single-threaded process
        return False
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    return cores >= 2


def _start_rerun(ex: Exercise, params: Params, rtol: float, budget_s: float | None):
    """Fork a child that solves at ``rtol`` and writes ``("ok", values)`` or ``("error", text)`` to a pipe.

    The child never outlives mech: the kernel kills it when its parent dies, whatever killed the parent
    (SIGKILL included), it stops itself if it finds its parent gone, it runs under the solve's work
    budget (and wall clock, where one is given or in force) and under a memory limit."""
    parent = os.getpid()
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: answer, then leave without running any of the parent's exit handlers
        code = 0
        try:
            _die_with_parent(parent)
            os.close(r)
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 1)  # nothing the solver might print reaches the parent's output twice
            os.dup2(devnull, 2)
            import sys
            import warnings

            # fresh stream objects (fresh locks) on the null device, and no warnings to write at all
            sys.stdout = sys.stderr = open(os.devnull, "w")
            warnings.simplefilter("ignore")
            _limit_memory(CHILD_MEMORY_BYTES)
            from mech.core import budget

            try:
                with budget.limit(budget_s, what=f"the rerun of {ex.id} at rtol={rtol:g}",
                                  work=budget.SOLVE_WORK):
                    values, _ = ex.solve_numeric(params, rtol)
                payload = ("ok", values)
            except MemoryError:
                payload = ("error", f"the rerun needed more than {CHILD_MEMORY_BYTES / 2**30:g} GiB of memory")
            except Exception as exc:
                payload = ("error", _failure_text(exc))
            data = pickle.dumps(payload)
            view = memoryview(data)
            while view:
                view = view[os.write(w, view):]
        except BaseException:
            code = 1
        finally:
            os._exit(code)
    os.close(w)
    return pid, r


CHILD_MEMORY_BYTES = 2 << 30  # address space the forked rerun may add to what it inherits


def _die_with_parent(parent: int) -> None:
    """Ask Linux to SIGKILL this process when its parent dies (prctl PR_SET_PDEATHSIG); then make sure
    the parent did not die before the request took effect."""
    import signal

    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        PR_SET_PDEATHSIG = 1
        libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent:
        os._exit(1)
    # the parent's handlers and timers are not the child's: a SIGTERM or SIGINT sent to the whole
    # process group ends the child at once
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _limit_memory(extra: int) -> None:
    try:
        import resource

        with open("/proc/self/statm") as fh:
            pages = int(fh.read().split()[0])
        used = pages * os.sysconf("SC_PAGE_SIZE")
        soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        want = used + extra
        if hard != resource.RLIM_INFINITY:
            want = min(want, hard)
        resource.setrlimit(resource.RLIMIT_AS, (want, hard))
    except (OSError, ValueError, ImportError):
        pass


def _finish_rerun(handle, wait_s: float) -> tuple[str, Any] | None:
    """The child's answer; None when it has not answered within ``wait_s`` (it is then stopped) or died
    without one."""
    import select

    pid, r = handle
    chunks = []
    deadline = time.monotonic() + wait_s  # inf: as long as the child takes (it counts its own work)
    while True:
        left = deadline - time.monotonic()
        if left <= 0 or not select.select([r], [], [], left if math.isfinite(left) else None)[0]:
            _abandon_rerun(handle)
            return None
        chunk = os.read(r, 1 << 16)
        if not chunk:
            break
        chunks.append(chunk)
    os.close(r)
    os.waitpid(pid, 0)
    if not chunks:
        return None  # the child died without answering (a crash, not the solver's error): rerun here
    return pickle.loads(b"".join(chunks))


def _abandon_rerun(handle) -> None:
    import signal

    pid, r = handle
    try:
        os.kill(pid, signal.SIGKILL)
    except OSError:
        pass
    try:
        os.close(r)
    except OSError:
        pass
    try:
        os.waitpid(pid, 0)
    except ChildProcessError:
        pass


class _Draft:
    """An output while it is being drafted: what the solves gave (``GIVEN``, ``Quantity``'s fields of the
    same names) and the notes found on the way; ``result.judged_quantity`` builds the Quantity from it and
    the judge's row."""

    GIVEN = ("name", "unit", "theory", "analytic", "numeric", "tol_abs", "analytic_err", "expected_err",
             "expected_err_abs", "theory_valid")
    __slots__ = GIVEN + ("notes",)

    def __init__(self, name: str, unit: str, **given) -> None:
        for key in self.GIVEN:
            setattr(self, key, None)
        self.name, self.unit, self.tol_abs = name, unit, 0.0
        self.notes = []
        for key, value in given.items():
            setattr(self, key, value)

    def _note(self, text: str) -> None:
        if text not in self.notes:
            self.notes.append(text)

    def given(self) -> dict:
        return {key: getattr(self, key) for key in self.GIVEN}


def _is_number(v) -> bool:
    return isinstance(v, float) and math.isfinite(v)


def _failure_text(exc: BaseException) -> str:
    if isinstance(exc, (NumericFailure, BadInput)):
        return str(exc)
    from mech.core.safeio import shown

    # the kind and the message, never a source path or line (CONTRACT: no source path in any message)
    return f"{type(exc).__name__}: {shown(exc, 200)}"


def cross_check(
    ex: Exercise,
    params: Params,
    *,
    methods: tuple[str, ...] = ("analytic", "numeric"),
    rtol: float | None = None,
    verify: bool = True,
    budget_s: float | None = None,
    keep_trajectories: bool = False,
    fork_rerun: bool = True,
) -> Solution:
    """Run the asked-for solvers and compare; solver failures become loud entries, never numbers.

    The numeric solve and its rerun at rtol/10 each do at most ``budget.SOLVE_WORK`` units of work:
    past it the solve fails loudly, the same on any machine.  ``budget_s``: a wall clock for the call
    (a command's: ``mech solve``'s), past which it fails loudly too; a caller's limits in force around
    the call that are spent raise their ``OutOfBudget`` instead.  ``fork_rerun``: False runs the rerun
    after the solve in this process (many short solves: a fork costs more than it saves); the numbers
    are the same either way.
    """
    rtol = float(rtol or ex.default_rtol)
    budget_s = None if budget_s is None else float(budget_s)

    # the solvers' warnings (numpy's overflow in an intermediate, a 0/0 later masked, scipy's) are not
    # written to stderr: the answers they touch are judged below like any other (non-finite, out of
    # range, moved at rtol/10), and the warnings' words are kept in numeric_info["fp_warnings"]
    caught = warnings.catch_warnings(record=True)
    fp_warnings = caught.__enter__()
    warnings.simplefilter("always")
    try:
        return _cross_check(ex, params, methods, rtol, verify, budget_s, keep_trajectories, fp_warnings,
                            fork_rerun)
    finally:
        caught.__exit__(None, None, None)


def _cross_check(ex, params, methods, rtol, verify, budget_s, keep_trajectories, fp_warnings,
                 fork_rerun=True) -> Solution:
    """The steps of ``cross_check``: run the solvers, check the invariants, draft every output and judge
    them all at once."""
    timing: dict[str, float | None] = {"analytic_s": None, "numeric_s": None}
    errors: list[Failure] = []  # in the order found: analytic, numeric, rerun, invariants, estimates, values
    analytic = _run_analytic(ex, params, methods, timing, errors)
    numeric, run, verify_values, import_s = {}, None, {}, None
    if "numeric" in methods and ex.has_numeric:
        numeric, run, verify_values, import_s = _run_numeric(ex, params, rtol, verify, budget_s,
                                                             keep_trajectories, fork_rerun, timing, errors)
    if run is not None:
        _check_invariants(ex, run, rtol, errors)
    drafts, rows = _draft_outputs(ex, params, rtol, analytic, numeric, run, verify_values, errors)
    quantities = _judge_outputs(drafts, rows, bool(verify_values)) if rows else ()
    if run is not None and fp_warnings:
        # the warnings' words, never their source file and line
        run.info["fp_warnings"] = list(dict.fromkeys(str(w.message) for w in fp_warnings))[:5]
    return Solution(
        exercise=ex,
        params=params,
        quantities=quantities,
        timing=timing,
        numeric_info={**run.as_json(), "import_s": import_s} if run is not None else None,
        errors=tuple(errors),
        run=run,
    )


def _run_analytic(ex, params, methods, timing: dict, errors: list) -> dict:
    """The analytic solver's answers ({} when it is not asked for, or fails: the failure is in ``errors``)."""
    analytic: dict = {}
    if "analytic" in methods and ex.has_analytic:
        t0 = time.perf_counter()
        try:
            analytic = ex.solve_analytic(params)
        except Exception as exc:  # a broken solver is a failed check, reported, not a crash
            errors.append(Failure("analytic", f"analytic solver failed: {_failure_text(exc)}"))
        timing["analytic_s"] = time.perf_counter() - t0
    return analytic


def _run_numeric(ex, params, rtol, verify, budget_s, keep_trajectories, fork_rerun, timing: dict,
                 errors: list):
    """The numeric solve and its rerun at rtol/10 (forked beside the solve, or after it), each under its own
    work budget (``budget.SOLVE_WORK``) and both under the wall clock ``budget_s`` where one is given:
    (answers, run, the rerun's answers, the integrator's one-time load in seconds or None).  A wall clock
    or a work limit of the caller's that is spent raises its ``OutOfBudget`` here, not a failure."""
    from mech.core import budget

    numeric: dict = {}
    run = None
    verify_values: dict = {}
    import_s = None
    # the one-time load of the integrator and its tableau is start-up cost, not the solve: timed
    # apart (when this solve is the one that loads it) and taken out of the numeric time
    dop = sys.modules.get("mech.solvers.numerics.dop853")
    loaded_before = dop is not None and dop.tableau_load_seconds() is not None
    tighter = max(rtol / 10.0, ex.min_rtol)
    rerun = None
    outer = budget.state()  # the caller's limits: spent, they stop this call (raised, not a failure)
    if verify and tighter < rtol and fork_rerun and _parallel_ok() and not budget.capped():
        rerun = _start_rerun(ex, params, tighter, budget_s)  # on the second core, while the solve runs here
    t0 = time.perf_counter()
    shared: dict = {}  # what a serial rerun may reuse of the solve (see Run.shared)
    with budget.limit(budget_s, what=f"the numeric solve of {ex.id}"):
        try:
            with budget.limit(what=f"the numeric solve of {ex.id}", work=budget.SOLVE_WORK):
                numeric, run = ex.solve_numeric(params, rtol, shared=shared, keep_trajectories=keep_trajectories)
        except BaseException as exc:
            if rerun is not None:
                _abandon_rerun(rerun)
                rerun = None
            if not isinstance(exc, Exception):
                raise
            budget.stop_if_spent(outer, exc)
            errors.append(Failure("numeric", f"numeric solver failed: {_failure_text(exc)}"))
        timing["numeric_s"] = time.perf_counter() - t0
        dop = sys.modules.get("mech.solvers.numerics.dop853")
        load_s = dop.tableau_load_seconds() if dop is not None else None
        if not loaded_before and load_s is not None:
            import_s = load_s
            timing["numeric_s"] = max(0.0, timing["numeric_s"] - import_s)
        answer = None
        if rerun is not None:
            # the child counts its own work and stops at the same limit as a serial rerun; a child that has
            # not answered when the wall clock in force is spent is stopped (a child never hangs the command)
            try:
                answer = _finish_rerun(rerun, wait_s=budget.remaining() + 1.0)
            except budget.OutOfBudget as exc:
                _abandon_rerun(rerun)
                budget.stop_if_spent(outer, exc)
                answer = ("error", str(exc))
            if answer is None:
                budget.stop_if_spent(outer)
                run.info["verify_parallel_fallback"] = "the forked rerun did not answer: rerun after the solve"
        if answer is not None:
            status, payload = answer
            if status == "ok":
                verify_values = payload
                run.info["verify_rtol"] = tighter
            else:
                budget.stop_if_spent(outer)
                errors.append(Failure("rerun", f"numeric solver failed at rtol={tighter:g}: {payload}"))
        elif verify and run is not None and tighter < rtol:
            try:
                with budget.limit(what=f"the rerun of {ex.id} at rtol={tighter:g}", work=budget.SOLVE_WORK):
                    verify_values, vrun = ex.solve_numeric(params, tighter, shared=shared)
                run.info["verify_rtol"] = tighter
            except Exception as exc:
                budget.stop_if_spent(outer, exc)
                errors.append(Failure("rerun", f"numeric solver failed at rtol={tighter:g}: {_failure_text(exc)}"))
    budget.stop_if_spent(outer)
    return numeric, run, verify_values, import_s


def _check_invariants(ex, run, rtol, errors: list) -> None:
    """A monitored invariant drifting by more than the method allows is a failure."""
    from mech.verification import judge as judging

    default_allowed = float(ex.tol_factor * rtol)
    for name, drift in run.invariants.items():
        allowed = run.invariant_allowed.get(name, default_allowed)
        if not judging.within(drift, bars=(allowed,)):
            errors.append(Failure(
                "invariant", f"the invariant '{name}' drifts by {drift:.2g}, more than the {allowed:.2g} the "
                "method allows: the integration is not to be trusted"))


def _draft_outputs(ex, params, rtol, analytic, numeric, run, verify_values, errors: list):
    """Every output's draft quantity and the judge's arguments for it (one row each)."""
    from mech.verification import judge as judging

    expected = expected_errors(ex, params) if analytic and numeric else {}
    try:
        validity = judging.theory_validity(ex, params, expected if analytic and numeric else None)
    except Exception as exc:
        validity = {}
        errors.append(Failure("estimate", f"the leading-order theory's range failed: {_failure_text(exc)}"))
    try:
        analytic_errs = analytic_errors(ex, params) if analytic else {}
    except Exception as exc:
        analytic_errs = {}
        errors.append(Failure("estimate", f"analytic error estimate failed: {_failure_text(exc)}"))
    quantities = []
    rows = []  # the judge's arguments, one element per output
    for out in ex.outputs:
        q = _Draft(out.name, out.unit, theory=out.theory)
        q.analytic = analytic.get(out.name) if analytic else None
        q.numeric = numeric.get(out.name) if numeric else None
        rel_claim, abs_claim = (None, None)
        if run is not None:
            rel_claim, abs_claim = run.claims.get(out.name, (None, None))
        rel_claim = float(ex.tol_factor * rtol) if rel_claim is None else float(rel_claim)
        q.tol_abs = float(abs_claim or 0.0)
        if out.theory != "exact":
            _draft_leading(q, expected.get(out.name), bool(analytic and numeric), validity.get(out.name))
        _undefine_bad_values(q, out, errors)
        a, n = q.analytic, q.numeric
        if _is_number(a) and out.name in analytic_errs:
            q.analytic_err = abs(float(analytic_errs[out.name]))
        v = verify_values.get(out.name) if verify_values else None
        rows.append(dict(
            analytic=a if _is_number(a) else math.nan, numeric=n if _is_number(n) else math.nan,
            a_undefined=isinstance(a, Undefined), n_undefined=isinstance(n, Undefined),
            has_analytic=a is not None, has_numeric=n is not None, rel_claim=rel_claim, abs_claim=q.tol_abs,
            analytic_err=q.analytic_err or 0.0, leading=out.theory != "exact",
            expected_rel=math.nan if q.expected_err is None else q.expected_err,
            expected_abs=math.nan if q.expected_err_abs is None else q.expected_err_abs,
            verify=v if _is_number(v) else math.nan,
            outside=out.theory != "exact" and validity.get(out.name) is not None,
            outside_why=validity.get(out.name) or ""))
        quantities.append(q)
    return quantities, rows


def _draft_leading(q, expected_err, both: bool, invalid_why) -> None:
    """A leading-order output: the size of what its theory neglects (relative, and absolute where its value
    can be zero), and whether the theory applies here (``invalid_why`` None)."""
    q.expected_err = expected_err
    if isinstance(q.expected_err, (tuple, list)):
        # (relative, absolute): what the theory neglects where its value can be zero
        rel_part, abs_part = q.expected_err
        q.expected_err = None if rel_part is None else float(rel_part)
        q.expected_err_abs = None if abs_part is None else abs(float(abs_part))
        if q.expected_err is None and q.expected_err_abs is not None:
            q.expected_err = 0.0
    if q.expected_err is None and both:
        q._note("the exercise gives no size for what its leading-order theory neglects")
    elif q.expected_err is not None:
        q.expected_err = float(q.expected_err)
    q.theory_valid = invalid_why is None


def _undefine_bad_values(q, out, errors: list) -> None:
    """A non-finite value, or one outside the floating-point range, becomes Undefined and a failure."""
    for key in ("analytic", "numeric"):
        v = getattr(q, key)
        if isinstance(v, float) and not math.isfinite(v):
            q._note(f"{key} value is not finite ({v}): a solver defect")
            setattr(q, key, Undefined(f"non-finite {key} value"))
            errors.append(Failure("non-finite", f"{out.name}: {key} value is not finite", out.name))
        elif isinstance(v, float) and out_of_range(v):
            # beyond 1e+-290 a value has lost the room its own error needs (subnormal, or one
            # operation from overflow): no number is better than one that cannot be trusted
            q._note(f"{key} value {v:.3g} lies outside the floating-point range mech works in")
            setattr(q, key, Undefined(f"{key} value outside the floating-point range"))
            errors.append(Failure("out-of-range", f"{out.name}: the {key} value {v:.3g} {out.unit} lies outside "
                                  f"the floating-point range (1e-{LOG10_LIMIT:.0f}..1e{LOG10_LIMIT:.0f})", out.name))


def _judge_outputs(drafts, rows, verified: bool) -> tuple:
    """The judge, once over every output's row; the Quantities built from the drafts and its verdicts."""
    import numpy as np

    from mech.verification import judge as judging
    from mech.verification.result import judged_quantity

    columns = {key: np.array([r[key] for r in rows]) for key in rows[0] if key != "outside_why"}
    J = judging.judge(**{k: v for k, v in columns.items() if k != "verify"},
                      verify=columns["verify"] if verified else None,
                      outside_why=[r["outside_why"] for r in rows])
    return tuple(judged_quantity(J, k, notes=q.notes, **q.given()) for k, q in enumerate(drafts))
