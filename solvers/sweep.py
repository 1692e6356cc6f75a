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
"""

from __future__ import annotations

import itertools
import os
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from typing import Callable, Sequence

from mech.problems.spec import Exercise, Params

__all__ = ["Axis", "SweepResult", "grid_points", "run_sweep", "plan_workers", "POOL_OVERHEAD_S", "MIN_PARALLEL_S"]

POOL_OVERHEAD_S = 0.15  # start-up of one worker process and its first imports (fork), measured
MIN_PARALLEL_S = 1.5  # below this much serial work left a pool is not worth its start-up


@dataclass(frozen=True)
class Axis:
    """One swept parameter: its name and the values it takes, in SI, in order."""

    name: str
    values: tuple[float, ...]
    log: bool = False


@dataclass
class SweepResult:
    exercise: Exercise
    axes: list[Axis]
    fixed: dict[str, float]
    points: list[dict]  # one cross-check JSON object per grid point (without id and title), grid order
    workers: int = 1
    seconds: float = 0.0
    extra: dict = field(default_factory=dict)

    @property
    def agree(self) -> bool | None:
        flags = [pt.get("agree") for pt in self.points]
        if any(f is False for f in flags):
            return False
        if all(f is None for f in flags):
            return None
        return True

    def as_json(self) -> dict:
        return {
            "id": self.exercise.id,
            "title": self.exercise.title,
            "swept": [{"name": a.name, "values": list(a.values), "log": a.log} for a in self.axes],
            "fixed": self.fixed,
            "points": self.points,
            "agree": self.agree,
            "workers": self.workers,
            "seconds": self.seconds,
        }


def grid_points(axes: Sequence[Axis], fixed: dict[str, float]) -> list[dict[str, float]]:
    """Every combination of the axes' values (the first axis varies slowest), with the fixed values added."""
    names = [a.name for a in axes]
    return [{**fixed, **dict(zip(names, combo))} for combo in itertools.product(*(a.values for a in axes))]


def _serial_verify() -> None:
    """In a pool worker: the cores are the pool's, so each cross-check's rerun runs after its solve."""
    from mech.solvers import crosscheck

    crosscheck.PARALLEL_VERIFY = False


def solve_point(ex_id: str, values: dict, rtol: float | None, verify: bool) -> dict:
    """One grid point's cross-check as the contract's solve object (without id and title); picklable."""
    from mech.problems import registry
    from mech.solvers.crosscheck import cross_check

    ex = registry.get(ex_id)
    params = Params(values) if isinstance(values, dict) else values
    t0 = time.perf_counter()
    result = cross_check(ex, params, rtol=rtol, verify=verify)
    d = result.as_json()
    d.pop("id", None)
    d.pop("title", None)
    import_s = (d.get("numeric_info") or {}).get("import_s") or 0.0
    d["wall_s"] = time.perf_counter() - t0 - import_s
    return d


def plan_workers(n_left: int, seconds_per_point: float, cores: int | None = None) -> int:
    """How many processes the points left should use: 1 unless the serial work clearly pays a pool's start-up."""
    cores = cores if cores is not None else (os.cpu_count() or 1)
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
) -> SweepResult:
    """Cross-check at every (already validated) point; ``jobs`` forces the number of processes (None: decide).

    ``progress(k)`` is called after each finished point with the number done so far.
    """
    t0 = time.perf_counter()
    points: list[dict | None] = [None] * len(params)
    done = 0

    def tick():
        nonlocal done
        done += 1
        if progress:
            progress(done)

    if not params:
        return SweepResult(ex, list(axes), dict(fixed), [], 1, 0.0)
    # the first point here: it measures the cost per point
    points[0] = solve_point(ex.id, dict(params[0]), rtol, verify)
    tick()
    rest = list(range(1, len(params)))
    workers = jobs if jobs is not None else plan_workers(len(rest), points[0]["wall_s"])
    workers = max(1, min(workers, len(rest))) if rest else 1
    if workers == 1:
        for i in rest:
            points[i] = solve_point(ex.id, dict(params[i]), rtol, verify)
            tick()
    else:
        with ProcessPoolExecutor(max_workers=workers, initializer=_serial_verify) as pool:
            futures = {pool.submit(solve_point, ex.id, dict(params[i]), rtol, verify): i for i in rest}
            from concurrent.futures import as_completed

            for fut in as_completed(futures):
                points[futures[fut]] = fut.result()
                tick()
    return SweepResult(ex, list(axes), dict(fixed), points, workers, time.perf_counter() - t0)
