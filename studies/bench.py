"""Speed against error: sweep the numeric solver of one exercise over integrators and tolerances.

For every (method, requested rtol) point the exercise's own numeric solver runs
with every ODE integration inside it forced onto that method (the Run's
``integrator``: ``ex.solve_numeric(p, rtol, integrator=method)``); the error is measured against the exact
analytic answer and the time is the median of repeated runs after a warm-up.

Error measure: max over outputs of |numeric - analytic| / |analytic|, over the
outputs whose analytic value is exact (leading-order outputs are left out: their
difference is the theory's, not the integrator's), and finite and nonzero (a
zero or undefined analytic value has no relative error; it is skipped and
named in ``skipped_outputs``).  An exercise whose every output is leading-order
is measured against its own numeric solver at its tightest rtol instead
(``reference`` says which).

Rows:
  * RK45, DOP853 (explicit), LSODA (switches to BDF on stiffness), Radau
    (implicit, for possible stiffness): the exercise's solver with that method forced;
    DOP853 is mech's own implementation (``mech.solvers.numerics.dop853``), every other
    method scipy's ``solve_ivp``; ``scipy-DOP853`` (on request) is scipy's
    DOP853, for comparing the two at equal error;
  * ``scipy-default``: what a student would write, ``solve_ivp`` with its defaults
    (RK45, rtol 1e-3, atol 1e-6, no step bounds; the Run's integrator ``"student"``),
    one point, run with ``run.rtol = 1e-3`` so that the exercise's own checks
    (event confirmation) match what was integrated;
  * ``Yoshida4`` / ``Yoshida6``: fixed-step symplectic compositions of
    Stormer-Verlet, for exercises that expose a separable Hamiltonian
    (``exercise.hamiltonian``); no error control: the requested rtol only picks the fixed
    step, h = 0.5 tau rtol^(1/order) (``fixed_step`` true on the point);
  * ``default``: the exercise's own settings (its method, step bounds) at its default rtol.
An exercise whose numeric route integrates no ODE (quadrature, eigenproblems,
root finding) gets one row, its own route over the rtol sweep; ``route`` says so.

Timing: one warm-up run (it also gives the error and nfev), then repeated runs
while they fit in the point's share of the time budget (at most ``repeats``);
a point slower than its share is timed by its single run (``timed_runs`` 1).
A run longer than ``run_limit_s`` is stopped and is a failed point; after a
point slower than ``slow_s`` the tighter tolerances of that method are not
run (failed points with a note); the sweep goes tolerance by tolerance over
all methods and starts no new point after ``max_seconds`` (55 s), so
``mech bench`` stays near a minute and a slow exercise loses its tightest
points, each kept as a failed point saying why.
Failed runs stay in the table with ``ok`` false, ``error`` null and a note.
"""

from __future__ import annotations

import math
import os
import signal
import statistics
import threading
import time
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, fields

from mech.problems.spec import Exercise, Params, Undefined

__all__ = ["BenchResult", "DEFAULT_TOLS", "ODE_METHODS", "STUDENT", "bench", "summarize", "error_against"]

DEFAULT_TOLS = tuple(10.0 ** -k for k in range(3, 13))
ODE_METHODS = ("RK45", "DOP853", "LSODA", "Radau")
OTHER_ODE = ("RK23", "BDF", "scipy-DOP853")
SYMPLECTIC = {"Yoshida4": 4, "Yoshida6": 6}
STUDENT = "scipy-default"
DEFAULT_ROW = "default"
TARGETS = (1e-6, 1e-9)


class _Timeout(Exception):
    pass


@contextmanager
def _time_limit(seconds: float):
    """Stop a run after ``seconds`` (SIGALRM; only in the main thread, elsewhere unlimited)."""
    if not seconds or threading.current_thread() is not threading.main_thread() or not hasattr(signal, "setitimer"):
        yield
        return

    def handler(signum, frame):
        raise _Timeout(f"stopped after {seconds:g} s")

    old = signal.signal(signal.SIGALRM, handler)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _num(v):
    return isinstance(v, float) and math.isfinite(v)


def error_against(values: dict, reference: dict, names: list[str]) -> tuple[float, str | None]:
    """Max relative error over ``names`` (reference finite and nonzero); an undefined numeric value is infinite."""
    worst, which = 0.0, None
    for n in names:
        r, v = reference.get(n), values.get(n)
        if not _num(r) or r == 0.0:
            continue
        if v is None:
            continue  # an output a row does not compute (a symplectic readout may give a subset)
        if not _num(v):
            return math.inf, n
        e = float(abs(v - r) / abs(r))
        if e >= worst:
            worst, which = e, n
    return worst, which


class _Runner:
    """Runs one configuration: returns (values, nfev, integrator name, Run or None)."""

    def __init__(self, ex: Exercise, params: Params):
        self.ex, self.params = ex, params

    def __call__(self, method: str, rtol: float):
        from mech.solvers.numerics import ode

        ex, p = self.ex, self.params
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if method in SYMPLECTIC:
                from mech.solvers.numerics.symplectic import solve_scene

                values, res = solve_scene(ex.separable_hamiltonian(p), rtol, SYMPLECTIC[method])
                return values, res.nfev, method, None
            if method == STUDENT:
                values, run = ex.solve_numeric(p, 1e-3, integrator=ode.STUDENT)
            elif method in ODE_METHODS + OTHER_ODE:
                values, run = ex.solve_numeric(p, rtol, integrator=method)
            else:  # the exercise's own route / settings
                values, run = ex.solve_numeric(p, rtol)
            return values, run.nfev, run.method, run


def probe_route(ex: Exercise, params: Params) -> tuple[bool, str]:
    """Whether the numeric solver integrates ODEs that take the Run's integrator choice, and its method.

    A run with LSODA forced on the Run says how many of its recorded integrations took it
    (``run.forced_runs``): none, and the route has no integration bench can force."""
    rtol = ex.default_rtol
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, own = ex.solve_numeric(params, rtol)
        try:
            _, forced = ex.solve_numeric(params, rtol, integrator="LSODA")
            integrates = forced.forced_runs > 0
        except Exception:  # noqa: BLE001 - a forced run that fails: a failure inside a forced integration
            integrates = True
    return integrates, own.method or "own route"


@dataclass(frozen=True)
class BenchResult:
    """The bench of one exercise (see the module docstring): ``to_dict()`` is the contract's JSON object that
    ``mech bench --json`` prints; ``result[key]`` reads one of its keys."""

    id: str
    title: str
    params: dict
    reference: str
    error_measure: str
    measured_outputs: tuple[str, ...]
    skipped_outputs: tuple[str, ...]
    left_out_outputs: tuple[str, ...]
    route: str
    default: dict
    points: tuple[dict, ...]
    summary: tuple[dict, ...]
    timing: dict
    ranking: tuple[str, ...]
    student_vs_default: dict | None

    def to_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in fields(self)}
        for key in ("measured_outputs", "skipped_outputs", "left_out_outputs", "points", "summary", "ranking"):
            d[key] = list(d[key])
        return d

    def __getitem__(self, key: str):
        return self.to_dict()[key]


@dataclass(frozen=True)
class _Reference:
    """What a bench's errors are measured against: the values, the outputs measured and how it says so."""

    values: dict
    kind: str
    names: list[str]
    skipped: list[str]
    left_out: list[str]
    measure: str


def _reference(ex: Exercise, params: Params, own_method: str) -> _Reference:
    """The exact analytic outputs, or (every output leading-order) the own route at its tightest rtol."""
    exact = [o.name for o in ex.outputs if o.theory == "exact"]
    if exact:
        values, kind, names = ex.solve_analytic(params), "analytic", exact
    else:
        r = max(ex.min_rtol, 1e-13)
        values, _ = ex.solve_numeric(params, r)
        kind = f"numeric ({own_method}, rtol {r:g}): every output's analytic value is leading-order"
        names = [o.name for o in ex.outputs]
    skipped = [n for n in names if not _num(values.get(n)) or values.get(n) == 0.0]
    measure = ("max over outputs of |numeric - analytic| / |analytic|" if kind == "analytic"
               else "max over outputs of |numeric - reference| / |reference|")
    return _Reference(values, kind, names, skipped, [o.name for o in ex.outputs if o.name not in names], measure)


def _plan(ex: Exercise, methods: list[str] | None, tols: list[float], integrates: bool,
          own_method: str) -> list[tuple[str, float]]:
    """The (method, rtol) points in the order they run: tolerance-major, so that when the wall-time cap
    stops the sweep every method has its looser points; then the student and default rows."""
    if methods:
        known = ODE_METHODS + OTHER_ODE + tuple(SYMPLECTIC) + (STUDENT, DEFAULT_ROW, own_method)
        unknown = [m for m in methods if m not in known]
        if unknown:
            from mech.core.errors import BadInput
            from mech.core.safeio import shown

            raise BadInput(f"methods: unknown method '{shown(unknown[0])}'; known: {', '.join(dict.fromkeys(known))}")
        rows = [m for m in methods if m != STUDENT]
        extra = [(STUDENT, 1e-3)] if STUDENT in methods else []
    elif integrates:
        rows = list(ODE_METHODS) + (list(SYMPLECTIC) if ex.has_hamiltonian else [])
        extra = [(STUDENT, 1e-3), (DEFAULT_ROW, ex.default_rtol)]
    else:
        rows, extra = [own_method], []
    return [(m, t) for t in tols for m in rows] + extra


def _skip_note(ex: Exercise, method: str, rtol: float, too_slow: dict, started: float,
               max_seconds: float) -> str | None:
    """Why a point is not run (kept as a failed point with that note), or None."""
    if method in too_slow:
        return too_slow[method]
    if time.perf_counter() - started > max_seconds and method not in (STUDENT, DEFAULT_ROW):
        return f"not run: the bench's {max_seconds:g} s were spent (--max-seconds)"
    if rtol < ex.min_rtol and method not in SYMPLECTIC:
        return f"not run: below the exercise's floor rtol {ex.min_rtol:g}"
    if method in SYMPLECTIC and not ex.has_hamiltonian:
        return "not run: the exercise exposes no separable Hamiltonian"
    return None


def _timed(runner: _Runner, method: str, rtol: float, ref: _Reference, repeats: int, share: float,
           run_limit_s: float):
    """One warm-up run (its values give the error), then repeats while they fit in ``share`` seconds:
    (error, worst output, values, nfev, integrator used, Run, the times)."""
    times = []
    with _time_limit(run_limit_s):
        t0 = time.perf_counter()
        values, nfev, used, run = runner(method, rtol)
        times.append(time.perf_counter() - t0)
    err, worst = error_against(values, ref.values, ref.names)
    while len(times) < repeats + 1 and sum(times) + times[0] <= share:
        t0 = time.perf_counter()
        runner(method, rtol)
        times.append(time.perf_counter() - t0)
    return err, worst, values, nfev, used, run, times


def _annotate(pt: dict, method: str, err: float, worst, values: dict, ref: _Reference, used, run) -> None:
    """The notes of a measured point: a fixed step, a partial route, an undefined output, a forced
    integrator that never ran or ran on part of the route."""
    if worst:
        pt["worst_output"] = worst
    if method in SYMPLECTIC:
        # no error control on a fixed-step row: the rtol asked for only picks the step
        pt["fixed_step"] = True
        pt["note"] = (f"fixed step: rtol sets h = 0.5 tau rtol^(1/{SYMPLECTIC[method]}) "
                      "(tau the motion's time scale); no error control")
    partial = [n for n in ref.names if n not in values and n not in ref.skipped]
    if partial:
        pt["note"] = f"this route gives {', '.join(n for n in ref.names if n in values)} only"
    if not math.isfinite(err):
        pt["note"] = f"failed: numeric {worst} undefined where the analytic value is finite"
    if run is not None and method in ODE_METHODS + OTHER_ODE + (STUDENT,):
        if run.forced_runs == 0:
            # no integration of the route took the forced integrator (it integrates with a scheme of
            # its own, or not at all): this point measures nothing about it (never a silent row)
            pt.update(ok=False, error=None, applies=False,
                      note=f"not applicable: this route integrates with its own scheme ({used}); "
                           f"{method} never ran")
        elif run.own_runs and "note" not in pt:
            pt["note"] = (f"{method} ran {run.forced_runs} of the route's {run.forced_runs + run.own_runs} "
                          "recorded integrations; the others are the route's own")


def _point(runner: _Runner, method: str, rtol: float, ref: _Reference, too_slow: dict, *, own_method: str,
           repeats: int, share: float, run_limit_s: float, slow_s: float, skip: str | None) -> dict:
    """One (method, rtol) point of the table; a failed or skipped run is a point with a note."""
    pt = {"method": method, "rtol": rtol, "error": None, "time_s": None, "time_min_s": None,
          "time_max_s": None, "nfev": None, "ok": False}
    if method == DEFAULT_ROW:
        pt["integrator"] = own_method
    if skip:
        pt["note"] = skip
        return pt
    try:
        err, worst, values, nfev, used, run, times = _timed(runner, method, rtol, ref, repeats, share, run_limit_s)
    except _Timeout as exc:
        pt["note"] = f"failed: {exc}"
        too_slow[method] = f"not run: a looser tolerance already took over {run_limit_s:g} s"
        return pt
    except Exception as exc:  # noqa: BLE001 - a failed run is a point, not a crash
        pt["note"] = f"failed: {type(exc).__name__}: {' '.join(str(exc).split())[:200]}"
        return pt
    timed = times[1:] if len(times) > 1 else times
    pt.update(error=err if math.isfinite(err) else None, time_s=statistics.median(timed), time_min_s=min(timed),
              time_max_s=max(timed), nfev=int(nfev), ok=math.isfinite(err), timed_runs=len(timed))
    _annotate(pt, method, err, worst, values, ref, used, run)
    if timed[0] > slow_s and method not in (STUDENT, DEFAULT_ROW):
        too_slow[method] = f"not run: a looser tolerance already took {timed[0]:.2g} s"
    return pt


def bench(
    ex: Exercise,
    params: Params | None = None,
    *,
    methods: list[str] | None = None,
    tols: list[float] | None = None,
    repeats: int = 5,
    budget_s: float = 45.0,
    run_limit_s: float = 10.0,
    slow_s: float = 3.0,
    max_seconds: float = 55.0,
    progress=None,
) -> BenchResult:
    """The bench of one exercise (see the module docstring): reference, plan, points, summary."""
    import scipy.integrate  # noqa: F401  (imported before any timing)

    started = time.perf_counter()
    params = params if params is not None else ex.resolve({})
    tols = sorted({float(t) for t in (tols or DEFAULT_TOLS)}, reverse=True)
    integrates, own_method = probe_route(ex, params)
    ref = _reference(ex, params, own_method)
    plan = _plan(ex, methods, tols, integrates, own_method)
    share = budget_s / max(len(plan), 1)
    runner = _Runner(ex, params)

    points = []
    too_slow: dict[str, str] = {}
    for method, rtol in plan:
        skip = _skip_note(ex, method, rtol, too_slow, started, max_seconds)
        pt = _point(runner, method, rtol, ref, too_slow, own_method=own_method, repeats=repeats, share=share,
                    run_limit_s=run_limit_s, slow_s=slow_s, skip=skip)
        points.append(pt)
        if progress and "timed_runs" in pt:  # a point that ran to the end
            progress(pt)

    order = {m: k for k, m in enumerate(dict.fromkeys([m for m, _ in plan]))}
    points.sort(key=lambda p: (order[p["method"]], -p["rtol"]))
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    summary = summarize(points)
    return BenchResult(
        id=ex.id, title=ex.title, params=dict(params), reference=ref.kind, error_measure=ref.measure,
        measured_outputs=tuple(n for n in ref.names if n not in ref.skipped), skipped_outputs=tuple(ref.skipped),
        left_out_outputs=tuple(ref.left_out),
        route="ode" if integrates else f"no ODE integration: the sweep is over rtol of the exercise's own route ({own_method})",
        default={"method": own_method, "rtol": ex.default_rtol, "tol_factor": ex.tol_factor},
        points=tuple(points), summary=tuple(summary),
        timing={"repeats_max": repeats, "budget_s": budget_s, "max_seconds": max_seconds,
                "seconds": time.perf_counter() - started, "load_1min": load, "cpus": os.cpu_count()},
        ranking=tuple(s["method"] for s in sorted(summary, key=lambda s: s["rank"])),
        student_vs_default=student_vs_default(points, own_method, ex.default_rtol),
    )


def student_vs_default(points: list[dict], own_method: str, default_rtol: float) -> dict | None:
    """The student row's error over the exercise's own method's error at the nearest wall time (log scale).

    The own method's row is its forced sweep (same integrator, the exercise's step bounds), so its
    points are what the tuned default gives at other rtols; the default point itself is one of them.
    """
    st = [p for p in points if p["method"] == STUDENT and p["ok"] and p["error"]]
    own = [p for p in points if p["method"] in (own_method, DEFAULT_ROW) and p["ok"] and p["error"] is not None]
    if not st or not own:
        return None
    s = st[0]
    near = min(own, key=lambda p: abs(math.log(p["time_s"] / s["time_s"])))
    return {"method": own_method, "student_error": s["error"], "student_time_s": s["time_s"],
            "default_error": near["error"], "default_rtol": near["rtol"], "default_time_s": near["time_s"],
            "error_ratio": s["error"] / max(near["error"], 1e-300), "time_ratio": near["time_s"] / s["time_s"]}


def _cheapest(pts, target, cost: str = "time_s"):
    """The point reaching ``target`` at the least ``cost`` (median wall time, or evaluations ``nfev``)."""
    good = [p for p in pts if p["ok"] and p["error"] is not None and p["error"] <= target]
    if not good:
        return None
    p = min(good, key=lambda p: (p[cost], p["time_s"]))
    return {"rtol": p["rtol"], "error": p["error"], "time_s": p["time_s"], "nfev": p["nfev"]}


def _target_key(target: float) -> str:
    return f"{target:.0e}".replace("e-0", "e-")


def summarize(points: list[dict]) -> list[dict]:
    """Per method: the point reaching 1e-6 and 1e-9 with the fewest evaluations (``fewest_evals_for_*``)
    and the one in the least median time (``cheapest_for_*``), and two ranks.

    ``rank``: by the evaluations to reach 1e-9, then to reach 1e-6, then the best error: the comparison
    the work-precision plot makes, independent of the machine and of Python's per-step overhead (which
    makes a fixed-step loop look fast in wall time at equal work). ``rank_by_time``: the same by median
    wall time.
    """
    methods = list(dict.fromkeys(p["method"] for p in points))
    out = []
    for m in methods:
        pts = [p for p in points if p["method"] == m]
        s = {"method": m}
        for target in TARGETS:
            s[f"cheapest_for_{_target_key(target)}"] = _cheapest(pts, target)
            s[f"fewest_evals_for_{_target_key(target)}"] = _cheapest(pts, target, "nfev")
        errs = [p["error"] for p in pts if p["ok"] and p["error"] is not None]
        s["best_error"] = min(errs) if errs else None
        s["failed_points"] = sum(not p["ok"] for p in pts)
        out.append(s)

    def key(prefix, cost):
        def k(s):
            c9, c6 = s[f"{prefix}_1e-9"], s[f"{prefix}_1e-6"]
            return (c9[cost] if c9 else math.inf, c6[cost] if c6 else math.inf,
                    s["best_error"] if s["best_error"] is not None else math.inf)
        return k

    for rank, s in enumerate(sorted(out, key=key("fewest_evals_for", "nfev")), 1):
        s["rank"] = rank
    for rank, s in enumerate(sorted(out, key=key("cheapest_for", "time_s")), 1):
        s["rank_by_time"] = rank
    return out
