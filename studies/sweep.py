"""Solve one exercise at many parameter points: a grid, both methods, serial or over the machine's cores.

No command line here: ``mech.cli.sweep`` parses the ranges and prints; this
module builds the grid, runs the cross-check at every point and decides
whether a process pool pays for itself.

The decision is measured, not guessed: the first point runs in this process
and its wall time (without the one-time scipy import) times the points left
is the serial estimate.  A pool costs a start-up of its own (about
``POOL_OVERHEAD_S`` per worker on Linux, measured with fork) and only pays when
the estimate is several times that, so small or cheap sweeps stay serial.
Results come back in grid order whatever the schedule; every solver is
deterministic, so serial and parallel sweeps give the same numbers.

Charts (``run_batched``): where the exercise registers a batched route
(``Exercise.batched``) for every output asked, the grid goes through it in
chunks instead: both solves (rtol and rtol/10) and the analytic side over
arrays, and each point judged by the cross-check's rule over arrays
(``_judge``).  The result keeps arrays; ``point_list()`` builds the
per-point solve objects only when they are printed.
"""

from __future__ import annotations

import itertools
import math
import os
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from typing import Callable, Iterator, Sequence

from mech.core.errors import BadInput
from mech.problems.solving import constraint_message
from mech.problems.spec import Exercise, Params, Undefined
from mech.verification.result import Failure, Quantity, Solution, to_json

__all__ = ["MAX_POINTS", "describe_point", "validate_grid", "validate", "Refused", "grid_refusals", "Axis", "Sweep", "grid_points", "run_sweep", "plan_workers", "POOL_OVERHEAD_S", "MIN_PARALLEL_S",
           "pool_worker_init", "run_batched", "batched_outputs", "batched_points", "grid_arrays", "CHUNK"]

POOL_OVERHEAD_S = 0.15  # start-up of one worker process and its first imports (fork), measured
MIN_PARALLEL_S = 1.5  # below this much serial work left a pool is not worth its start-up


@dataclass(frozen=True)
class Axis:
    """One swept parameter: its name and the values it takes, in SI, in order."""

    name: str
    values: tuple[float, ...]
    log: bool = False
    unit: str | None = None  # the unit the values are shown in (the one typed, else the display unit)
    factor: float = 1.0  # SI value of one ``unit``


@dataclass
class Batched:
    """A batched sweep's arrays: the outputs its route ran, the grid (parameter -> array over the points,
    grid order), each output's judged columns (``_judge``'s dict) and the route's numeric info."""

    outputs: list[str]
    grid: dict
    judged: dict
    info: dict


@dataclass
class Sweep:
    """Solutions over a range or a grid, the one sweep type of ``mech sweep`` and the API (``mech.Sweep``):
    ``.points`` (or ``.solutions()``), ``.agree``, ``.to_arrays()``, ``.to_csv(path)``, ``.to_pandas()``."""

    exercise: Exercise
    axes: list[Axis]
    fixed: dict[str, float]
    points: list | None  # one ``result.Solution`` per grid point, grid order; None for a batched sweep until
    # ``solutions()`` builds them from its arrays
    workers: int = 1
    seconds: float = 0.0
    batched: Batched | None = None  # the batched route's arrays (None: solved point by point)
    only: tuple[str, ...] | None = None  # the outputs asked for (None: all)
    wall: list | None = None  # each point's wall time, s (point by point)
    refused: dict = field(default_factory=dict)  # grid index -> why a joint limit refused the point (unsolved)
    _json: list | None = field(default=None, repr=False)  # the points' solve objects, once built

    @property
    def output_names(self) -> list[str]:
        if self.batched is not None:
            return list(self.batched.outputs)
        return list(self.only) if self.only else [o.name for o in self.exercise.outputs]

    def solutions(self) -> list:
        """One typed ``Solution`` per grid point, grid order."""
        if self.points is None:
            self.points = batched_solutions(self)
        return self.points

    def point_list(self) -> list[dict]:
        """The points as the contract's solve objects (without id and title)."""
        if self._json is None:
            out = []
            for k, sol in enumerate(self.solutions()):
                out.append(self._point_json(k, sol))
            self._json = out
        return self._json

    def iter_points(self):
        """The points as the contract's solve objects, one at a time: never all held as JSON, and on the
        batched route never all held as typed solutions either (each is built from the arrays, written,
        dropped), so the memory does not grow with the number of points."""
        if self._json is not None:
            yield from self._json
            return
        sols = self.points if self.points is not None else iter_batched_solutions(self)
        for k, sol in enumerate(sols):
            yield self._point_json(k, sol)

    def _point_json(self, k: int, sol) -> dict:
        """Point ``k``'s solve object (without id and title): its wall time on the point by point route, and
        ``"refused"``, the one-line reason, where a joint limit refused it (nothing solved there)."""
        d = to_json(sol)
        d.pop("id", None)
        d.pop("title", None)
        if self.wall is not None:
            d["wall_s"] = self.wall[k]
        if k in self.refused:
            d["refused"] = self.refused[k]
        return d

    def failed_points(self):
        """(grid index, solve object) of every point that failed the cross-check, grid order, one at a time;
        on the batched route only those points are built."""
        if self.points is None:
            import numpy as np

            ks = [int(k) for k in np.flatnonzero(self._failed_mask())]
            for k, sol in zip(ks, iter_batched_solutions(self, ks)):
                d = to_json(sol)
                d.pop("id", None)
                d.pop("title", None)
                yield k, d
            return
        for k, d in enumerate(self.iter_points()):
            if d.get("agree") is False:
                yield k, d

    def write_json(self, out) -> None:
        """``as_json()`` written to the text stream ``out`` as ``json.dumps(..., indent=2)`` would, its
        points streamed one at a time: neither the points' JSON objects nor the text are held whole."""
        import json

        head = self.as_json(points=False)
        text = json.dumps({**head, "points": None}, indent=2, allow_nan=False)
        before, after = text.split('\n  "points": null', 1)
        out.write(before + '\n  "points": [')
        first = True
        for pt in self.iter_points():
            chunk = json.dumps(pt, indent=2, allow_nan=False).replace("\n", "\n    ")
            out.write(("\n    " if first else ",\n    ") + chunk)
            first = False
        out.write("\n  ]" if not first else "]")
        out.write(after + "\n")

    def __len__(self) -> int:
        if self.points is None:
            return int(next(iter(self.batched.grid.values())).size)
        return len(self.points)

    @property
    def n_failed(self) -> int:
        """How many points failed the cross-check."""
        if self.points is None:
            return int(self._failed_mask().sum())
        return sum(pt.agree is False for pt in self.points)

    def _failed_mask(self):
        """The batched route's failed points, as a boolean array over the grid."""
        import numpy as np

        bad = np.zeros(len(self), dtype=bool)
        for J in self.batched.judged.values():
            bad |= (J["agree"] == 0) | J["n_fail"] | J["ver_fail"]
        return bad

    @property
    def agree(self) -> bool | None:
        if self.points is None:
            import numpy as np

            from mech.verification.judge import conclude, conclude_arrays

            # the one rule (``judge.conclude``) over every output's values, per output at once
            flags = []
            for J in self.batched.judged.values():
                got = conclude_arrays(J["agree"], J["outside"] & ~np.isnan(J["verify_diff"]),
                                      J["n_fail"] | J["ver_fail"])
                flags += [False] if (got == 0).any() else [True] if (got == 1).any() else [None]
            return conclude(flags)
        from mech.verification.judge import conclude

        return conclude(pt.agree for pt in self.points)

    @property
    def outputs(self) -> list[str]:
        """The outputs swept (``output_names``)."""
        return self.output_names

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(a.values) for a in self.axes)

    def __iter__(self) -> Iterator[Solution]:
        return iter(self.solutions())

    def to_arrays(self) -> dict:
        """Flat arrays in grid order (the first swept parameter varies slowest; ``.reshape(sweep.shape)``
        gives the grid): each swept parameter, then per output ``_analytic``, ``_numeric`` and
        ``_numeric_err`` (float, NaN where there is no value) and ``_agree`` (bool) with ``_agree_mask``
        (bool, True where there is no verdict: nothing compared; ``_agree`` is False there), the
        convention of ``numpy.ma``: ``np.ma.array(a["x_agree"], mask=a["x_agree_mask"])``."""
        import numpy as np

        points = self.solutions()
        out: dict = {}
        for axis in self.axes:
            out[axis.name] = np.array([p.params[axis.name] for p in points], float)
        for name in self.outputs:
            qs = [p[name] for p in points]
            out[f"{name}_analytic"] = np.array([_value(q.analytic) for q in qs], float)
            out[f"{name}_numeric"] = np.array([_value(q.numeric) for q in qs], float)
            out[f"{name}_numeric_err"] = np.array([_value(q.numeric_err) for q in qs], float)
            out[f"{name}_agree"] = np.array([q.agree is True for q in qs], bool)
            out[f"{name}_agree_mask"] = np.array([q.agree is None for q in qs], bool)
        return out

    def _columns(self) -> list[tuple[str, str]]:
        cols = [(a.name, self.exercise.param_map[a.name].unit) for a in self.axes]
        units = {o.name: o.unit for o in self.exercise.outputs}
        for name in self.outputs:
            cols += [(f"{name}_analytic", units[name]), (f"{name}_numeric", units[name]),
                     (f"{name}_numeric_err", units[name]), (f"{name}_agree", "")]
        return cols

    def to_csv(self, path) -> None:
        """One row per point; the header gives each column's unit as ``name [unit]``; an empty cell where
        there is no value or no verdict."""
        import csv

        from mech.core.safeio import atomic_write

        arrays = self.to_arrays()
        cols = self._columns()
        with atomic_write(str(path), "--csv", newline="") as fh:
            out = csv.writer(fh)
            out.writerow([f"{n} [{u}]" if u and u != "1" else n for n, u in cols])
            swept = {a.name for a in self.axes}
            for k in range(len(self)):
                row = []
                for n, _ in cols:
                    v = arrays[n][k]
                    if n.endswith("_agree"):
                        row.append("" if arrays[f"{n}_mask"][k] else str(bool(v)).lower())
                    else:
                        # a swept value to 15 digits: 0.3 from linspace, not 0.30000000000000004
                        row.append("" if math.isnan(v) else f"{float(v):.15g}" if n in swept else repr(float(v)))
                out.writerow(row)

    def to_pandas(self):
        """A pandas DataFrame of ``to_arrays()`` (pandas is optional: ``pip install pandas``): the verdicts
        as pandas' nullable boolean (``pd.NA`` where there is none), without the mask columns."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Sweep.to_pandas needs pandas, which mech does not install: pip install pandas") \
                from None
        arrays = self.to_arrays()
        columns = {}
        for n, v in arrays.items():
            if n.endswith("_agree_mask"):
                continue
            if n.endswith("_agree"):
                columns[n] = pd.array([None if m else bool(x) for x, m in zip(v, arrays[f"{n}_mask"])],
                                      dtype="boolean")
            else:
                columns[n] = v
        return pd.DataFrame(columns)

    def __repr__(self) -> str:
        swept = ", ".join(f"{a.name}: {len(a.values)}" for a in self.axes)
        return f"<Sweep {self.exercise.id} over {swept}; {len(self)} points; agree={self.agree}>"

    def as_json(self, points: bool = True) -> dict:
        d = {
            "id": self.exercise.id,
            "title": self.exercise.title,
            "swept": [{"name": a.name, "values": list(a.values), "log": a.log} for a in self.axes],
            "fixed": self.fixed,
            "outputs": self.output_names,
            "points": self.point_list() if points else None,
            "agree": self.agree,
            "workers": self.workers,
            "seconds": self.seconds,
        }
        if self.batched is not None:
            d["route"] = "batched"
            d["numeric_info"] = self.batched.info
        return d


def _value(v) -> float:
    """A value as a float: NaN where there is none (None, or ``Undefined``)."""
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else math.nan


def grid_points(axes: Sequence[Axis], fixed: dict[str, float]) -> list[dict[str, float]]:
    """Every combination of the axes' values (the first axis varies slowest), with the fixed values added."""
    names = [a.name for a in axes]
    return [{**fixed, **dict(zip(names, combo))} for combo in itertools.product(*(a.values for a in axes))]


def pool_worker_init(parent: int | None = None) -> None:
    """In a pool worker: the cores are the pool's, so each cross-check's rerun runs after its solve; and
    the worker dies with the sweep (a sweep killed by a signal leaves no workers behind)."""
    from mech.verification import crosscheck

    crosscheck.PARALLEL_VERIFY = False
    if parent is not None and hasattr(crosscheck, "_die_with_parent"):
        crosscheck._die_with_parent(parent)


def solve_point(ex_id: str, values: dict, rtol: float | None, verify: bool, only=None,
                deadline: float | None = None, total_s: float | None = None):
    """One grid point's cross-check: (its ``Solution`` without the exercise and the run, so that it
    pickles; its wall time in s, without a one-time import).

    ``only``: the output names to keep (the solvers still compute all of them on this route).
    ``deadline``: the sweep's end (``time.monotonic()``, one clock for every process); the point's solve
    counts its work (``budget.SOLVE_WORK``) and the sweep's clock only stops it, and a point reached after
    it is not solved: it fails, saying so (its analytic value is still given)."""
    from mech.problems import registry
    from mech.verification.crosscheck import cross_check

    ex = registry.get(ex_id)
    params = Params(values) if isinstance(values, dict) else values
    t0 = time.perf_counter()
    left = math.inf if deadline is None else deadline - time.monotonic()
    if left <= 0.05:
        from mech.verification.result import Failure

        result = cross_check(ex, params, methods=("analytic",), rtol=rtol, verify=False)
        why = (f"numeric solver failed: not run: the sweep's total budget of {total_s or 0:g} s ran out "
               "(--budget SECONDS gives it more)")
        result = result.replace(errors=tuple(result.errors) + (Failure("numeric", why),))
    else:
        # the solve counts work (budget.SOLVE_WORK); the sweep's clock, where it has one, only stops it
        result = cross_check(ex, params, rtol=rtol, verify=verify, budget_s=left if math.isfinite(left) else None)
    import_s = (result.numeric_info or {}).get("import_s") or 0.0
    wall = time.perf_counter() - t0 - import_s
    if only:
        result = result.replace(quantities=tuple(q for q in result.quantities if q.name in only))
    return result.replace(exercise=None, run=None), wall


DEFAULT_TOTAL_S = 600.0  # a sweep's or a grading's wall-clock budget: 10 minutes, a class's file at 6 s a answer
MAX_TOTAL_S = 7 * 86_400.0


def check_total(seconds, name: str = "--budget") -> float:
    """A total budget in seconds: finite, positive, at most a week; BadInput naming it (``name``) otherwise."""
    from mech.core.errors import BadInput

    try:
        value = float(seconds)
    except (TypeError, ValueError, OverflowError):
        value = math.nan
    if isinstance(seconds, bool) or not (0 < value <= MAX_TOTAL_S):
        from mech.core.safeio import shown

        raise BadInput(f"{name}: '{shown(seconds, 40)}' is not a number of seconds; allowed (0, {MAX_TOTAL_S:g}]")
    return value


def usable_cores() -> int:
    """The cores this process may run on: a cap for -j (256 workers on 2 cores only thrash)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def plan_workers(n_left: int, seconds_per_point: float, cores: int | None = None) -> int:
    """How many processes the points left should use: 1 unless the serial work clearly pays a pool's start-up."""
    cores = cores if cores is not None else usable_cores()
    if cores < 2 or n_left < 2:
        return 1
    serial = n_left * seconds_per_point
    if serial < max(MIN_PARALLEL_S, 4 * POOL_OVERHEAD_S * cores):
        return 1
    return min(cores, n_left)


def run_sweep(
    ex: Exercise,
    axes: Sequence[Axis],
    fixed: dict[str, float],
    params: Sequence[Params],
    *,
    rtol: float | None = None,
    verify: bool = True,
    jobs: int | None = None,
    progress: Callable[[int], None] | None = None,
    only: Sequence[str] | None = None,
    total_s: float | None = None,
) -> Sweep:
    """Cross-check at every (already validated) point; ``jobs`` forces the number of processes (None: decide;
    never more than the cores).

    ``progress(k)`` is called after each finished point with the number done so far.  ``total_s``: the
    sweep's wall-clock budget (None: ``DEFAULT_TOTAL_S``); points it leaves unsolved fail, saying so.
    """
    t0 = time.perf_counter()
    total_s = DEFAULT_TOTAL_S if total_s is None else check_total(total_s)
    deadline = time.monotonic() + total_s
    points: list[dict | None] = [None] * len(params)
    done = 0

    def tick():
        nonlocal done
        done += 1
        if progress:
            progress(done)

    if not params:
        return Sweep(ex, list(axes), dict(fixed), [], 1, 0.0, only=only, wall=[])
    only = tuple(only) if only else None
    refused = {i: pt for i, pt in enumerate(params) if isinstance(pt, Refused)}
    for i, pt in refused.items():  # marked, not solved
        points[i] = (refused_solution(ex, pt, [o.name for o in ex.outputs if not only or o.name in only]), 0.0)
        tick()
    todo = [i for i in range(len(params)) if i not in refused]
    if not todo:
        return Sweep(ex, list(axes), dict(fixed), [sol for sol, _ in points], 1, time.perf_counter() - t0,
                     only=only, wall=[w for _, w in points], refused={i: r.reason for i, r in refused.items()})
    # the first point here: it measures the cost per point
    points[todo[0]] = solve_point(ex.id, dict(params[todo[0]]), rtol, verify, only, deadline, total_s)
    tick()
    rest = todo[1:]
    workers = min(jobs, usable_cores()) if jobs is not None else plan_workers(len(rest), points[todo[0]][1])
    workers = max(1, min(workers, len(rest))) if rest else 1
    if workers == 1:
        for i in rest:
            points[i] = solve_point(ex.id, dict(params[i]), rtol, verify, only, deadline, total_s)
            tick()
    else:
        with ProcessPoolExecutor(max_workers=workers, initializer=pool_worker_init,
                                 initargs=(os.getpid(),)) as pool:
            futures = {pool.submit(solve_point, ex.id, dict(params[i]), rtol, verify, only, deadline, total_s): i
                       for i in rest}
            from concurrent.futures import as_completed

            for fut in as_completed(futures):
                points[futures[fut]] = fut.result()
                tick()
    solutions = [sol.replace(exercise=ex) for sol, _ in points]
    return Sweep(ex, list(axes), dict(fixed), solutions, workers, time.perf_counter() - t0, only=only,
                 wall=[w for _, w in points], refused={i: r.reason for i, r in refused.items()})


def refused_solution(ex: Exercise, point: Refused, names=None) -> Solution:
    """The solve object of a refused point: every parameter, no value on either side and no verdict (nothing
    was solved), each output (``names``, in that order; None: all) noting why."""
    note = f"refused: {point.reason}"
    outs = {o.name: o for o in ex.outputs}
    quantities = tuple(Quantity(n, outs[n].unit, theory=outs[n].theory, notes=(note,))
                       for n in (names or list(outs)))
    return Solution(ex, Params(dict(point.values)), quantities, timing={}, numeric_info=None)


# -- charts: the batched route -----------------------------------------------------------------------

CHUNK = 8192  # points integrated together: the stages take 16 * 4 * CHUNK numbers (4 MB)


def batched_outputs(ex: Exercise, only: Sequence[str] | None) -> tuple[str, ...] | None:
    """The outputs a batched sweep computes, or None when the exercise has no batched route for them all."""
    route = getattr(ex, "batched_route", None)
    if route is None:
        return None
    wanted = tuple(only) if only else tuple(o.name for o in ex.outputs)
    return wanted if set(wanted) <= set(route.outputs) else None


def grid_arrays(ex: Exercise, axes: Sequence[Axis], fixed: dict[str, float]) -> dict:
    """Every parameter as an array over the grid (the first axis varies slowest), defaults filled in."""
    import numpy as np

    mesh = np.meshgrid(*[np.asarray(a.values, dtype=float) for a in axes], indexing="ij")
    n = mesh[0].size
    P = {}
    for p in ex.params:
        P[p.name] = np.full(n, float(fixed.get(p.name, p.default)))
    for a, m in zip(axes, mesh):
        P[a.name] = m.ravel()
    return P


def _judge(ex, name, a_col, e_rel, num, ver, rtol, tighter, outside=None):
    """One output at every point of a batched sweep, judged by the one judge (``judge.judge``), with the
    columns and reasons a chart and a point's solve object need.  ``outside``: (mask, reasons) where a
    leading-order theory is outside its range."""
    import numpy as np

    from mech.verification import judge as judging

    out = next(o for o in ex.outputs if o.name == name)
    a = a_col.value
    N = a.size
    rel = np.broadcast_to(np.asarray(num.rel, dtype=float), (N,))
    rel = np.where(np.isnan(rel), ex.tol_factor * rtol, rel)  # no claim: the exercise's default one
    tol_abs = np.broadcast_to(np.asarray(num.abs, dtype=float), (N,))
    expected = expected_abs = None
    if out.theory != "exact" and e_rel is not None:
        expected, expected_abs = (np.asarray(x, dtype=float) for x in e_rel)
        # an absolute part alone: the relative one is 0
        expected = np.where(np.isnan(expected) & ~np.isnan(expected_abs), 0.0, expected)
    ver_fail = np.zeros(N, dtype=bool) if ver is None else ver.mask("failed") & ~num.mask("failed")
    J = judging.judge(
        analytic=a, numeric=num.value, a_undefined=a_col.mask("undefined"), n_undefined=num.mask("undefined"),
        n_failed=num.mask("failed"), rel_claim=rel, abs_claim=tol_abs,
        analytic_err=np.broadcast_to(np.asarray(a_col.abs, dtype=float), (N,)), leading=out.theory != "exact",
        expected_rel=np.nan if expected is None else expected,
        expected_abs=np.nan if expected_abs is None else expected_abs,
        verify=None if ver is None else np.where(ver.mask("undefined") | ver.mask("failed"), np.nan, ver.value),
        outside=None if outside is None else outside[0], outside_why=None if outside is None else outside[1])
    n_fail = num.mask("failed")
    return {
        "J": J, "outside": J.outside, "outside_why": J.outside_why,
        "analytic": np.where(~a_col.mask("undefined") & np.isfinite(a), a, np.nan),
        "numeric": np.where(~num.mask("undefined") & ~n_fail & np.isfinite(num.value), num.value, np.nan),
        "a_und": a_col.mask("undefined"), "n_und": num.mask("undefined"), "n_fail": n_fail, "ver_fail": ver_fail,
        "abs_err": J.abs_err, "rel_err": J.rel_err, "tol": J.tol, "tol_abs": tol_abs, "agree": J.agree,
        "expected_err": expected, "expected_err_abs": expected_abs, "small": J.small,
        "verify_diff": J.verify_diff, "unreliable": J.verdict == judging.UNRELIABLE,
        "numeric_err": J.numeric_err, "a_col": a_col, "num": num, "ver": ver,
        "no_claim": J.verdict == judging.NO_CLAIM, "tighter": tighter,
    }


def _concat_columns(cols):
    """One Column from the chunks' Columns (values, claims and masks laid end to end)."""
    import numpy as np

    from mech.solvers.numerics.batch import Column

    sizes = [c.value.size for c in cols]

    def full(x, k):
        return np.broadcast_to(np.asarray(x, dtype=float), (sizes[k],))

    value = np.concatenate([c.value for c in cols])
    rel = np.concatenate([full(c.rel, k) for k, c in enumerate(cols)])
    ab = np.concatenate([full(c.abs, k) for k, c in enumerate(cols)])
    out = Column(value, rel=rel, abs=ab)
    for which in ("undefined", "failed"):
        reasons = {}
        for c in cols:
            for _, why in getattr(c, which):
                reasons.setdefault(why, None)
        for why in reasons:
            parts = []
            for k, c in enumerate(cols):
                m = np.zeros(sizes[k], dtype=bool)
                for mm, w in getattr(c, which):
                    if w == why:
                        m |= np.asarray(mm, dtype=bool)
                parts.append(m)
            getattr(out, which).append((np.concatenate(parts), why))
    return out


def _failed_column(n, why):
    import numpy as np

    from mech.solvers.numerics.batch import Column

    return Column(np.full(n, np.nan), rel=np.nan, abs=0.0, failed=[(np.ones(n, dtype=bool), why)])


def run_batched(ex: Exercise, axes: Sequence[Axis], fixed: dict[str, float], outputs: Sequence[str],
                **options) -> Sweep:
    """The chart route (``_run_batched``, whose keywords ``options`` are and which says what they do).  numpy's
    warnings (an invalid value in an intermediate that the route masks later) are not written to stderr, as
    in the cross-check: the values they touch are judged like any other, and the warnings are kept, without
    their source path, in the sweep's ``numeric_info["fp_warnings"]``."""
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RuntimeWarning)
        result = _run_batched(ex, axes, fixed, outputs, **options)
    if caught:
        result.batched.info["fp_warnings"] = _warning_lines(caught)
    return result


def _warning_lines(caught) -> list[str]:
    """Caught warnings as ``file.py:line: message`` (the file's name, never its path), at most 5."""
    return list(dict.fromkeys(f"{os.path.basename(str(w.filename))}:{w.lineno}: {w.message}" for w in caught))[:5]


def _run_batched(
    ex: Exercise,
    axes: Sequence[Axis],
    fixed: dict[str, float],
    outputs: Sequence[str],
    *,
    rtol: float | None = None,
    verify: bool = True,
    chunk: int = CHUNK,
    progress: Callable[[int], None] | None = None,
    total_s: float | None = None,
    points: dict | None = None,
) -> Sweep:
    """The chart route: every (validated) grid point through the exercise's batched route, chunk by chunk.

    Both solves (at rtol and at rtol/10) and the analytic side run over the
    chunk's arrays; each point gets its own verdict by the cross-check's rule.
    A chunk whose integration fails (step underflow, the time budget) fails
    its points loudly with the reason; the others stand.  ``total_s``: the
    sweep's wall-clock budget (None: ``DEFAULT_TOTAL_S``), as on the point by
    point route: a solve still running at its end stops and fails its chunk,
    a solve reached after it is not run and fails its chunk, saying so (the
    analytic values are still given).  ``points``: every parameter as an array (scattered points, such as
    a class's personal variants) instead of the grid of ``axes`` and ``fixed``.
    """
    import numpy as np

    from mech.core import budget
    from mech.problems.spec import NumericFailure

    route = ex.batched_route
    rtol = float(rtol or ex.default_rtol)
    tighter = max(rtol / 10.0, ex.min_rtol)
    verify = verify and tighter < rtol
    t0 = time.perf_counter()
    total_s = DEFAULT_TOTAL_S if total_s is None else check_total(total_s)
    deadline = time.monotonic() + total_s
    spent = (f"the sweep's total budget of {total_s:g} s ran out (--budget SECONDS gives it more)")
    P = grid_arrays(ex, axes, fixed) if points is None else points
    N = next(iter(P.values())).size
    refused, P_route = ({}, P) if points is not None else _stand_ins(ex, axes, fixed, P)
    nums = {o: [] for o in outputs}
    vers = {o: [] for o in outputs}
    analytic = {o: [] for o in outputs}
    expected = {o: [] for o in outputs}
    stats = {"steps": 0, "chunks": 0}
    # what a route computes once per distinct value of the parameters an output depends on, shared by the
    # sweep's chunks (a route that takes a ``memo`` keyword)
    import inspect

    memo: dict = {}
    takes_memo = "memo" in inspect.signature(route.numeric).parameters
    for start in range(0, N, chunk):
        sl = slice(start, min(start + chunk, N))
        Pc = {k: v[sl] for k, v in P_route.items()}
        m = sl.stop - sl.start
        for tol, store in ((rtol, nums), (tighter, vers)) if verify else ((rtol, nums),):
            failed = f"numeric solver failed{'' if tol == rtol else f' at rtol={tol:g}'}: "
            left = deadline - time.monotonic()
            try:
                if left <= 0.05:
                    raise budget.OutOfBudget(f"not run: {spent}")
                # each variant the work of a one-point solve (budget.SOLVE_WORK), pooled over the chunk
                with budget.limit(left, what=f"the batched sweep of {ex.id}", work=budget.SOLVE_WORK * m):
                    got = (route.numeric(Pc, tol, tuple(outputs), memo=memo) if takes_memo
                           else route.numeric(Pc, tol, tuple(outputs)))
            except budget.OutOfWork as exc:  # the chunk's work, the same on any machine: its failure
                got = {o: _failed_column(m, failed + str(exc)) for o in outputs}
            except budget.OutOfBudget as exc:
                why = str(exc) if str(exc).startswith("not run") else spent
                got = {o: _failed_column(m, failed + why) for o in outputs}
            except NumericFailure as exc:
                got = {o: _failed_column(m, failed + str(exc)) for o in outputs}
            for o in outputs:
                store[o].append(got[o])
        a = route.analytic(Pc)
        e = route.expected_error(Pc) if route.expected_error else {}
        for o in outputs:
            analytic[o].append(a[o])
            # relative, or (relative, absolute) where the leading-order value can be zero; NaN: none given
            rel_abs = e.get(o, np.nan)
            if not isinstance(rel_abs, tuple):
                rel_abs = (rel_abs, np.nan)
            expected[o].append(np.stack([np.broadcast_to(np.asarray(x, dtype=float), (m,)) for x in rel_abs]))
        stats["chunks"] += 1
        if progress:
            progress(sl.stop)
    from mech.verification.judge import theory_validity_batch

    judged = {}
    expected = {o: np.concatenate(expected[o], axis=1) for o in outputs}
    validity = theory_validity_batch(ex, P_route, {o: tuple(expected[o]) for o in outputs})
    for o in outputs:
        judged[o] = _mark_refused(_judge(ex, o, _concat_columns(analytic[o]), expected[o],
                                         _concat_columns(nums[o]), _concat_columns(vers[o]) if verify else None,
                                         rtol, tighter, outside=validity.get(o)), refused)
    info = {"method": "DOP853 (batched)", "rtol": rtol, "verify_rtol": tighter if verify else None,
            "chunk": chunk, "chunks": stats["chunks"]}
    return Sweep(ex, list(axes), dict(fixed), None, 1, time.perf_counter() - t0,
                 batched=Batched(list(outputs), P, judged, info), refused=refused)


def _stand_ins(ex: Exercise, axes, fixed, P: dict) -> tuple[dict, dict]:
    """({grid index: reason} of the points a joint limit refuses, the grid the route runs).  A refused point
    is not solved: the route runs an accepted point in its place (the arrays keep their shape) and it is
    marked afterwards (``_mark_refused``)."""
    import numpy as np

    found = grid_refusals(ex, axes, fixed)
    refused = {k: r.reason for k, r in found.items()}
    if not refused:
        return refused, P
    if len(refused) == next(iter(P.values())).size:
        raise _all_refused(ex, found, [a.name for a in axes])
    ok = next(k for k in range(next(iter(P.values())).size) if k not in refused)
    idx = np.array(sorted(refused))
    P_route = {name: v.copy() for name, v in P.items()}
    for v in P_route.values():
        v[idx] = v[ok]
    return refused, P_route


def _mark_refused(J: dict, refused: dict) -> dict:
    """One output's judged columns with the refused points blanked: no value, no verdict, no failure (the
    route solved a stand-in there)."""
    if not refused:
        return J
    import numpy as np

    idx = np.array(sorted(refused))
    out = dict(J)
    for key, blank in (("analytic", np.nan), ("numeric", np.nan), ("verify_diff", np.nan), ("agree", -1),
                       ("n_fail", False), ("ver_fail", False), ("outside", False), ("a_und", False),
                       ("n_und", False), ("unreliable", False)):
        col = np.array(out[key], copy=True)
        col[idx] = blank
        out[key] = col
    return out


def _num(x):
    import math as _m

    x = float(x)
    return x if _m.isfinite(x) else None


def batched_solutions(result: Sweep) -> list[Solution]:
    """The chart's per-point solutions (as ``mech solve`` gives them, the asked outputs only), built from the
    judged arrays."""
    return list(iter_batched_solutions(result))


def iter_batched_solutions(result: Sweep, indices=None):
    """``batched_solutions`` one point at a time, grid order: none is kept (``sweep --json`` writes each
    as it is built).  ``indices``: only these points (grid order)."""
    import numpy as np

    from mech.verification.result import judged_quantity

    ex = result.exercise
    P = result.batched.grid
    judged = result.batched.judged
    info = result.batched.info
    units = {o.name: o for o in ex.outputs}
    names = [p.name for p in ex.params]
    N = next(iter(P.values())).size
    only = list(judged)
    a_errs = {name: np.broadcast_to(np.asarray(J["a_col"].abs, dtype=float), (N,)) for name, J in judged.items()}
    for k in range(N) if indices is None else indices:
        if k in result.refused:
            yield refused_solution(ex, Refused({n: float(P[n][k]) for n in names}, result.refused[k]), only)
            continue
        quantities, errors = [], []
        for name, J in judged.items():
            o = units[name]
            analytic, numeric = _num(J["analytic"][k]), _num(J["numeric"][k])
            if J["a_und"][k]:  # +-inf where undefined: infinite by the physics
                analytic = Undefined(J["a_col"].reason("undefined", k), infinite=bool(np.isinf(J["a_col"].value[k])))
            if J["n_und"][k]:
                numeric = Undefined(J["num"].reason("undefined", k), infinite=bool(np.isinf(J["num"].value[k])))
            if J["n_fail"][k]:
                why = J["num"].reason("failed", k)
                errors.append(Failure("numeric", why if why.startswith("numeric")
                                      else f"numeric solver failed: {name}: {why}", name))
            if J["ver_fail"][k]:
                why = J["ver"].reason("failed", k)
                errors.append(Failure("rerun", why if why.startswith("numeric") else
                                      f"numeric solver failed at rtol={J['tighter']:g}: {name}: {why}", name))
            leading = o.theory != "exact"
            e_abs = None if J["expected_err_abs"] is None else _num(J["expected_err_abs"][k])
            a_err = _num(a_errs[name][k])
            quantities.append(judged_quantity(
                J["J"], k, name=name, unit=o.unit, theory=o.theory, analytic=analytic, numeric=numeric,
                tol_abs=float(J["tol_abs"][k]),
                analytic_err=abs(a_err) if a_err and isinstance(analytic, float) else None,
                theory_valid=(not J["outside"][k]) if leading else None,
                expected_err=_num(J["expected_err"][k]) if leading and J["expected_err"] is not None else None,
                expected_err_abs=e_abs if leading else None))
        # a failure of the whole chunk (a solve that ran out of time) reads the same for every output: once,
        # for the whole solve
        once: dict = {}
        for e in errors:
            key = (e.kind, e.message)
            once[key] = Failure(e.kind, e.message) if key in once else e
        yield Solution(ex, {n: float(P[n][k]) for n in names}, tuple(quantities), timing={},
                       numeric_info=dict(info), errors=tuple(once.values()))


def batched_points(result: Sweep) -> list[dict]:
    """The chart's per-point solve objects (as ``mech solve --json`` gives them, the asked outputs only)."""
    return result.point_list()


def output_arrays(result: Sweep, name: str) -> dict:
    """One output over the grid as arrays in grid order: numeric, analytic (NaN where none), agree
    (1, 0, -1 for no verdict), failed (the point's verdict is a failure) and the reason of each failure."""
    import numpy as np

    if result.points is None:
        J = result.batched.judged[name]
        pts_failed = np.zeros(J["agree"].size, dtype=bool)
        for other in result.batched.judged.values():
            pts_failed |= (other["agree"] == 0) | other["n_fail"] | other["ver_fail"]
        reasons = np.full(J["agree"].size, "", dtype=object)
        for k in np.flatnonzero(pts_failed):
            reasons[k] = _reason_batched(result, int(k))
        return {"numeric": J["numeric"], "analytic": J["analytic"], "agree": J["agree"], "failed": pts_failed,
                "reasons": reasons, **_refused_arrays(result, J["agree"].size)}
    pts = result.point_list()
    num = np.array([_nan(q["numeric"]) for pt in pts for q in pt["quantities"] if q["name"] == name])
    ana = np.array([_nan(q["analytic"]) for pt in pts for q in pt["quantities"] if q["name"] == name])
    agree = np.array([-1 if q["agree"] is None else int(q["agree"])
                      for pt in pts for q in pt["quantities"] if q["name"] == name], dtype=np.int8)
    failed = np.array([pt.get("agree") is False for pt in pts])
    reasons = np.array([_reason_point(sol) if sol.agree is False else "" for sol in result.solutions()],
                       dtype=object)
    return {"numeric": num, "analytic": ana, "agree": agree, "failed": failed, "reasons": reasons,
            **_refused_arrays(result, len(pts))}


def _refused_arrays(result: Sweep, n: int) -> dict:
    """The refused points as arrays over the grid: ``refused`` (bool) and ``refused_reasons``."""
    import numpy as np

    mask = np.zeros(n, dtype=bool)
    why = np.full(n, "", dtype=object)
    for k, reason in result.refused.items():
        mask[k], why[k] = True, reason
    return {"refused": mask, "refused_reasons": why}


def refusal_label(reasons, width: int = 48) -> str:
    """A legend's words for the refused points: how many, and the first one's reason in at most two lines of
    ``width`` characters (every reason is in --json and the table)."""
    import textwrap

    reasons = list(reasons)
    lines = textwrap.wrap(f"refused ({len(reasons)} point{'s' if len(reasons) > 1 else ''}): {reasons[0]}",
                          width, max_lines=2, placeholder=" ...")
    return "\n".join(lines)


def _nan(v):
    return float("nan") if v is None else float(v)


def failure_kind(text: str) -> str:
    """A failure's reason shortened to its kind, for a legend: the words before any number."""
    import re

    head = re.split(r"[-+]?\d", text, maxsplit=1)[0].rstrip(" =:(,")
    return head or text


def _reason_point(sol: Solution) -> str:
    """Why a point failed, from its first failure or its typed verdicts (``judge.Verdict``)."""
    from mech.verification.judge import Verdict

    if sol.errors:
        return str(sol.errors[0])
    for q in sol.quantities:
        if q.agree is False:
            if q.verdict == Verdict.UNRELIABLE:
                return f"{q.name}: unreliable (the rerun at rtol/10 moved it beyond its claim)"
            if q.verdict == Verdict.ONE_UNDEFINED:
                return f"{q.name}: one method finds no finite value where the other does"
            return f"{q.name}: analytic and numeric differ beyond the error bars"
    return "failed"


def _reason_batched(result: Sweep, k: int) -> str:
    for name, J in result.batched.judged.items():
        if J["n_fail"][k]:
            return f"{name}: {J['num'].reason('failed', k)}"
        if J["ver_fail"][k]:
            return f"{name}: at rtol/10: {J['ver'].reason('failed', k)}"
    for name, J in result.batched.judged.items():
        if J["agree"][k] == 0:
            if J["unreliable"][k]:
                return f"{name}: unreliable (the rerun at rtol/10 moved it beyond its claim)"
            if J["a_und"][k] != J["n_und"][k]:
                return f"{name}: one method finds no finite value where the other does"
            return f"{name}: analytic and numeric differ beyond the error bars"
    return "failed"


def boundary_curves(result: Sweep) -> list[tuple[str, "object", "object", str]]:
    """The leading-order boundaries the exercise declares for a map over its two swept parameters.

    Returns (axis name the curve gives, values along the other axis, boundary values, label): the
    exercise's own analytic value of the declared output along the other axis (the others fixed)."""
    import numpy as np

    route = getattr(result.exercise, "batched_route", None)
    if route is None or len(result.axes) != 2:
        return []
    curves = []
    for k, axis in enumerate(result.axes):
        if axis.name not in route.boundaries:
            continue
        output, text = route.boundaries[axis.name]
        other = result.axes[1 - k]
        xs = np.linspace(min(other.values), max(other.values), 400)
        if other.log:
            xs = np.geomspace(min(other.values), max(other.values), 400)
        P = {p.name: np.full(xs.size, float(result.fixed.get(p.name, p.default))) for p in result.exercise.params}
        P[other.name] = xs
        P[axis.name] = np.full(xs.size, float(axis.values[0]))
        col = route.analytic(P)[output]
        ys = np.where(col.mask("undefined"), np.nan, col.value)
        curves.append((axis.name, xs, ys, text))
    return curves


# -- the grid's points checked before anything is solved ---------------------------------------------

MAX_POINTS = 100_000


def describe_point(ex: Exercise, values: dict, names) -> str:
    """The swept parameters of one grid point, as a person reads them (``l = 15 cm, theta0 = 30 deg``)."""
    return ", ".join(f"{n} = {ex.param_map[n].show(values[n])}" for n in names)


@dataclass(frozen=True)
class Refused:
    """A grid point inside every parameter's bounds that the exercise refuses to solve (a joint limit: a
    locking edge the theory cannot place, a force near its critical value): marked with ``reason`` and
    left unsolved, while the rest of the sweep runs.  ``values``: every parameter, in SI."""

    values: dict
    reason: str


def _in_bounds(ex: Exercise, values: dict) -> bool:
    """Every value names a parameter and lies within its own bounds (what a refusal may not hide)."""
    try:
        for name, v in values.items():
            ex.param_map[name].check(float(v))
    except (BadInput, KeyError):
        return False
    return True


def _all_refused(ex: Exercise, refused: dict, names) -> BadInput:
    """Every point refused: nothing to sweep (the one-line error names the first)."""
    first = refused[min(refused)]
    return BadInput(f"every point of the sweep is refused; sweep point "
                    f"{describe_point(ex, first.values, names)}: {first.reason}")


def grid_refusals(ex: Exercise, axes, fixed) -> dict:
    """{grid index: ``Refused``} for every point of the grid that a joint limit refuses (grid order).

    The axes' values were checked against their bounds when parsed and the
    fixed values when converted, so each point only needs the joint checks."""

    base = {p.name: float(fixed.get(p.name, p.default)) for p in ex.params}
    if not ex.has_constraints:
        return {}
    names = [a.name for a in axes]
    view = _PointView(base)
    refused = {}
    import warnings

    for k, combo in enumerate(itertools.product(*(a.values for a in axes))):
        view.__dict__.update(zip(names, combo))
        try:
            with warnings.catch_warnings():  # a check's overflow at a far point refuses it, never prints
                warnings.simplefilter("ignore")
                msg = constraint_message(ex, view)
        except Exception:  # a check that needs more than attribute access: the real Params
            try:
                ex.resolve(dict(view.__dict__))
                msg = None
            except BadInput as exc:
                msg = str(exc)
        if msg:
            refused[k] = Refused(dict(view.__dict__), msg)
    return refused


def validate_grid(ex: Exercise, axes, fixed) -> None:
    """The batched route's check of the grid: its size, and not every point refused by the joint checks
    (a refused point is marked and left unsolved, ``grid_refusals``; ``run_batched`` finds them again)."""
    total = math.prod(len(a.values) for a in axes)
    if total > MAX_POINTS:
        raise BadInput(f"the grid has {total} points; at most {MAX_POINTS} in one sweep")
    refused = grid_refusals(ex, axes, fixed)
    if refused and len(refused) == total:
        raise _all_refused(ex, refused, [a.name for a in axes])


class _PointView:
    """A grid point's values read as ``p.name`` or ``p["name"]``, refilled in place for every point (the
    joint checks of 40 000 points then cost milliseconds, not the half second of building Params)."""

    def __init__(self, values):
        self.__dict__.update(values)

    def __getitem__(self, key):
        return self.__dict__[key]


def validate(ex: Exercise, axes, fixed):
    """Every grid point resolved with the bounds and joint constraints, as solve does: a value out of its
    bounds is refused (``BadInput`` naming the first); a point in bounds that a joint limit refuses is a
    ``Refused`` in the list, marked and left unsolved by the sweep (unless every point is)."""
    total = math.prod(len(a.values) for a in axes)
    if total > MAX_POINTS:
        raise BadInput(f"the grid has {total} points; at most {MAX_POINTS} in one sweep")
    names = [a.name for a in axes]
    resolved, refused = [], {}
    import warnings

    for values in grid_points(axes, fixed):
        try:
            with warnings.catch_warnings():  # a check's overflow at a far point refuses it, never prints
                warnings.simplefilter("ignore")
                resolved.append(ex.resolve(values))
        except BadInput as exc:
            if not _in_bounds(ex, values):
                raise BadInput(f"sweep point {describe_point(ex, values, names)}: {exc}") from None
            full = {p.name: float(values.get(p.name, p.default)) for p in ex.params}
            refused[len(resolved)] = Refused(full, str(exc))
            resolved.append(refused[len(resolved)])
    if refused and len(refused) == len(resolved):
        raise _all_refused(ex, refused, names)
    return resolved
