"""What an exercise's figure shows, as data.

An exercise that has a scene registers ``@exercise.scene def scene(p, run) -> Scene``:
it computes every curve, trajectory, potential and marker from its own physics
(its equations of motion, energies, solvers) and hands them over with labels
and units.  ``mech plot`` (figures/) only draws what it is given; it holds
no equation of motion and no formula.

``run`` is a :class:`SceneRun`: the requested accuracy, how many numeric
solves the figure may spend (``--points``, 0 for none), and helpers that run
the exercise's own two solvers at a point or over a parameter, recording the
points where the numeric one fails so that the figure can show them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

from mech.core.errors import BadInput
from mech.problems.motion import motion_path

__all__ = ["Axis", "Band", "Guide", "Line", "Map", "Markers", "Note", "Panel", "Scene", "SceneRun", "make_scene",
           "spread"]


@dataclass
class Axis:
    """One axis: its quantity, unit (shown as ``label [unit]``), log scale, limits."""

    label: str
    unit: str = ""
    log: bool = False
    lim: tuple[float, float] | None = None


@dataclass
class Line:
    """A curve.  ``kind``: analytic (the derived result), reference (another theory or a guide
    curve), trajectory (an integrated motion), drawing (a sketch of the body), contour-free
    ``level`` lines; ``color`` and ``dashed`` override the kind's style."""

    x: Any
    y: Any
    label: str | None = None
    kind: str = "analytic"
    color: str | None = None
    dashed: bool = False
    width: float | None = None


@dataclass
class Markers:
    """Points.  ``kind``: numeric (the numeric solver's answers), analytic (an answer marked),
    this (the chosen parameter point), failure (where the numeric solver failed)."""

    x: Any
    y: Any
    label: str | None = None
    kind: str = "numeric"
    color: str | None = None
    size: float | None = None


@dataclass
class Band:
    """The region between two curves lo(x) and hi(x); ``vertical``: x runs along the y axis."""

    x: Any
    lo: Any
    hi: Any
    label: str | None = None
    color: str | None = None
    vertical: bool = False


@dataclass
class Map:
    """A scalar field z[y, x] on a grid, drawn as filled contours with a colorbar labelled ``label [unit]``;
    values outside ``clip`` are shown at the clip level."""

    x: Any
    y: Any
    z: Any
    label: str
    unit: str = ""
    clip: tuple[float, float] | None = None
    levels: int = 24


@dataclass
class Guide:
    """A straight line at a value of one axis (``axis``: "x" or "y")."""

    value: float
    axis: str = "x"
    label: str | None = None
    color: str | None = None
    dashed: bool = True


@dataclass
class Note:
    """Text at ``xy`` (data coordinates), with an arrow from ``text_at`` (axes fraction) when given."""

    text: str
    xy: tuple[float, float]
    text_at: tuple[float, float] | None = None
    color: str | None = None


@dataclass
class Panel:
    title: str
    x: Axis
    y: Axis
    items: list = field(default_factory=list)
    equal_aspect: bool = False
    legend: str = "best"  # a matplotlib location, "outside" (below the axes) or "none"
    ticks: bool = True

    def add(self, *items) -> "Panel":
        self.items.extend(i for i in items if i is not None)
        return self


@dataclass
class Scene:
    """Panels side by side; ``caption`` under the title; ``on_axis``: parameters an axis runs over
    (left out of the list of parameters held fixed)."""

    panels: list[Panel]
    caption: str = ""
    on_axis: Sequence[str] = ()


def spread(lo: float, hi: float, k: int, log: bool = False):
    """k points from lo to hi, not hitting an end exactly (the ends are often where a formula is singular)."""
    import numpy as np

    if k <= 0:
        return np.array([])
    f = (np.arange(k) + 0.5) / k
    return lo * (hi / lo) ** f if log else lo + (hi - lo) * f


def _finite(v) -> float:
    try:
        f = float(v)
    except (TypeError, ValueError):
        return math.nan
    return f if math.isfinite(f) else math.nan


class SceneRun:
    """What a scene is given: the accuracy, the budget of numeric solves, and the exercise's solvers.

    ``points``: how many numeric solves the figure may spend over a parameter (0: none; then
    ``numeric`` gives None and ``series`` no numeric values).  Values come back as floats, NaN
    where an output is Undefined; a numeric failure is recorded in ``failures`` (parameter
    point, message) and gives NaN.
    """

    def __init__(self, exercise, rtol: float | None = None, points: int = 5):
        self.exercise = exercise
        self.rtol = float(rtol or exercise.default_rtol)
        self.points = int(points)
        self.failures: list[tuple[dict, str]] = []
        self.failed_x: dict[str, list[float]] = {}  # parameter -> values where ``series`` saw a numeric failure
        self.out_of_budget = False

    def analytic(self, p) -> dict:
        try:
            values = self.exercise.solve_analytic(p)
        except Exception:  # a figure shows what it can
            return {o.name: math.nan for o in self.exercise.outputs}
        return {k: _finite(v) for k, v in values.items()}

    def numeric(self, p) -> dict | None:
        """The numeric solver's outputs at ``p``; None when the figure spends no numeric solves.

        Each solve runs under the work budget of a solve (``mech.core.budget``, as in the
        cross-check); once one has run out of it the figure's remaining numeric solves are skipped
        (recorded as failures), so that a figure never waits on several slow solves in a row."""
        from mech.core import budget

        if self.points <= 0:
            return None
        nan = {o.name: math.nan for o in self.exercise.outputs}
        if self.out_of_budget:
            self.failures.append((dict(p), "skipped: an earlier numeric solve ran out of its budget"))
            return nan
        try:
            with budget.limit(what=f"the numeric solve of {self.exercise.id} for the figure", work=budget.SOLVE_WORK):
                values, _ = self.exercise.solve_numeric(p, self.rtol)
        except budget.OutOfBudget as exc:
            self.out_of_budget = True
            self.failures.append((dict(p), str(exc)))
            return nan
        except Exception as exc:  # told in the figure, never drawn as a number
            self.failures.append((dict(p), f"{type(exc).__name__}: {exc}"))
            return nan
        return {k: _finite(v) for k, v in values.items()}

    def series(self, p, name: str, xs, numeric: bool = False) -> dict:
        """Outputs with parameter ``name`` at each of ``xs`` (arrays; NaN where a point is not allowed
        or has no value): the analytic solver's, or (``numeric=True``) the numeric solver's."""
        import numpy as np

        out = {o.name: np.full(len(xs), math.nan) for o in self.exercise.outputs}
        for i, x in enumerate(xs):
            try:
                q = self.exercise.resolve({**p, name: float(x)})
            except BadInput:
                continue
            before = len(self.failures)
            values = self.numeric(q) if numeric else self.analytic(q)
            if len(self.failures) > before:
                self.failed_x.setdefault(name, []).append(float(x))
            for k, v in (values or {}).items():
                out[k][i] = v
        return out

    def numeric_points(self, lo: float, hi: float, log: bool = False):
        """Where the numeric markers go over a parameter range: ``points - 1`` of them (the point
        itself is usually the last one), none when the figure spends no numeric solves."""
        return spread(lo, hi, max(self.points - 1, 1), log=log) if self.points > 0 else spread(lo, hi, 0)

    def motion(self, p):
        """The exercise's declared motion at ``p`` (``@exercise.motion``) integrated at the figure's
        accuracy: ``(motion, path)``, the ``motion.Motion`` and the ``motion.Path`` it gave (its
        ``traj.sol`` a continuous extension in the integrated variables; ``motion.si`` brings them to SI)."""
        m, path = motion_path(self.exercise, p, self.rtol)
        if m is None:
            raise RuntimeError(f"{self.exercise.id} declares no motion")
        return m, path


def make_scene(ex, p, rtol: float | None = None, points: int = 5) -> tuple:
    """``ex``'s scene at ``p`` (``@exercise.scene``) and the run that made it, or (None, None) without one."""
    if ex._scene is None:
        return None, None
    run = SceneRun(ex, rtol, points)
    return ex._scene(p, run), run
