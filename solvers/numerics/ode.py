"""An ODE front end over scipy's ``solve_ivp`` that reports its cost and finds events reliably.

Work in scaled (order-one) variables: the default absolute tolerance is
``rtol * atol_scale`` with ``atol_scale = 1e-3``, which suits them.

scipy imports happen inside the functions so that importing this module (and so
listing exercises) stays cheap.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from mech.core import budget
from mech.core.errors import NumericFailure

__all__ = ["Event", "Trajectory", "integrate", "integrate_to_event", "first_event", "apply_integrator", "STUDENT"]

STUDENT = "student"


def apply_integrator(integrator: str | None, method: str, rtol: float, atol, max_step: float,
                     first_step: float | None):
    """The integration settings once a caller's integrator choice is applied (``mech bench``).

    ``None`` keeps the exercise's own ``method`` and step settings; a method name
    (``"LSODA"``, ``"RK45"``, ...) replaces the method and keeps the rest;
    ``"student"`` runs plain ``solve_ivp`` defaults (RK45, rtol 1e-3, atol 1e-6,
    no step bounds), the way a first attempt would.
    """
    if integrator == STUDENT:
        return "RK45", 1e-3, 1e-6, math.inf, None
    if integrator:
        return integrator, rtol, atol, max_step, first_step
    return method, rtol, atol, max_step, first_step


@dataclass
class Event:
    """A zero of ``fn(t, y)``; ``direction`` +1 / -1 keeps only upward / downward crossings.

    ``component``: the index i when ``fn(t, y)`` is just ``y[i]``; mech's DOP853 then locates the root
    on that one component of its continuous extension (the same arithmetic, without the whole state
    at every trial time)."""

    fn: Callable[[float, np.ndarray], float]
    terminal: bool = True
    direction: float = 0.0
    name: str = "event"
    component: int | None = None

    def as_scipy(self) -> Callable:
        def f(t, y):
            return self.fn(t, y)

        f.terminal = self.terminal
        f.direction = self.direction
        if self.component is not None:
            f.component = self.component
        return f


@dataclass
class Trajectory:
    """An integration's result with what it cost."""

    t: np.ndarray
    y: np.ndarray
    t_events: list[np.ndarray]
    y_events: list[np.ndarray]
    nfev: int
    njev: int
    nlu: int
    method: str
    rtol: float
    wall_s: float
    status: int
    message: str
    sol: object = None
    extra: dict = field(default_factory=dict)
    # True when a caller's integrator choice (``integrator=``) replaced the exercise's own settings
    forced: bool = False

    @property
    def y_end(self) -> np.ndarray:
        return self.y[:, -1]

    @property
    def t_end(self) -> float:
        return float(self.t[-1])


def integrate(
    rhs: Callable,
    t_span: tuple[float, float],
    y0: Sequence[float],
    *,
    rtol: float,
    atol: float | Sequence[float] | None = None,
    method: str = "DOP853",
    events: Sequence[Event] = (),
    max_step: float = math.inf,
    first_step: float | None = None,
    t_eval: Sequence[float] | None = None,
    dense_output: bool = False,
    jac: Callable | None = None,
    vectorized: bool = False,
    integrator: str | None = None,
) -> Trajectory:
    """Integrate ``y' = rhs(t, y)``; a failed integration raises ``NumericFailure``, never returns quietly.

    ``method="DOP853"`` runs mech's own implementation (``mech.solvers.numerics.dop853``:
    the same method and step control as scipy's, no scipy import, less
    overhead per step); ``"scipy-DOP853"`` forces scipy's; every other method
    is ``solve_ivp``'s.  ``integrator`` (``mech bench``, through the Run) replaces
    these settings: see ``apply_integrator``.
    """
    y0 = np.asarray(y0, dtype=float)
    if integrator:
        method, rtol, atol, max_step, first_step = apply_integrator(integrator, method, rtol, atol, max_step,
                                                                   first_step)
    if atol is None:
        atol = rtol * 1e-3
    kwargs = dict(
        method=method,
        rtol=rtol,
        atol=atol,
        events=[e.as_scipy() for e in events] or None,
        max_step=max_step,
        t_eval=t_eval,
        dense_output=dense_output,
        vectorized=vectorized,
    )
    if first_step is not None:
        kwargs["first_step"] = first_step
    if jac is not None and method in ("Radau", "BDF", "LSODA"):
        kwargs["jac"] = jac
    if method == "DOP853":
        from mech.solvers.numerics import dop853

        start = time.perf_counter()
        res = dop853.solve(rhs, t_span, y0, rtol=rtol, atol=atol, max_step=max_step,
                           first_step=first_step, events=kwargs["events"] or (), t_eval=t_eval,
                           dense_output=dense_output)
        wall = time.perf_counter() - start
        res.njev = res.nlu = 0
    else:
        from scipy.integrate import solve_ivp

        if method == "scipy-DOP853":
            kwargs["method"] = "DOP853"
        # scipy's integrators never look at the budget (5.9's LSODA ran until the backup timer): the
        # right-hand side counts each evaluation as a unit of work (~0.2 us against the call's ~10 us)
        inner, where = rhs, f"{kwargs['method']} step"

        def rhs(t, y):
            budget.check(where)
            return inner(t, y)

        start = time.perf_counter()
        res = solve_ivp(rhs, t_span, y0, **kwargs)
        wall = time.perf_counter() - start
    if res.status < 0:
        raise NumericFailure(f"{method} integration failed at t={res.t[-1]:.6g}: {res.message}")
    return Trajectory(
        t=res.t,
        y=res.y,
        t_events=list(res.t_events) if res.t_events is not None else [],
        y_events=list(res.y_events) if res.y_events is not None else [],
        nfev=int(res.nfev),
        njev=int(res.njev),
        nlu=int(res.nlu),
        method=method,
        rtol=rtol,
        wall_s=wall,
        status=int(res.status),
        message=res.message,
        sol=res.sol,
        forced=bool(integrator),
    )


def first_event(traj: Trajectory, index: int = 0) -> tuple[float, np.ndarray]:
    """The first occurrence of event ``index``; its absence is a failure, not a default."""
    if index >= len(traj.t_events) or len(traj.t_events[index]) == 0:
        raise NumericFailure(f"the event was not reached by t={traj.t_end:.6g} ({traj.method})")
    return float(traj.t_events[index][0]), np.asarray(traj.y_events[index][0])


def integrate_to_event(
    rhs: Callable,
    t_span: tuple[float, float],
    y0: Sequence[float],
    event: Event,
    *,
    rtol: float,
    confirm: bool | str = True,
    steps_per_event: int = 64,
    **kwargs,
) -> tuple[float, np.ndarray, Trajectory]:
    """Integrate to the first zero of ``event`` and return ``(t_event, y_event, trajectory)``.

    solve_ivp looks for a sign change only between the ends of each step, so an
    event function that crosses zero twice inside one step is missed (scipy
    issue 9228).  The event is therefore confirmed:

    * ``confirm=True`` (default): the event function is evaluated on the run's
      own dense output (DOP853's 7th-order interpolant) at ``steps_per_event``
      even times up to the event and 8 points inside every step; a crossing
      in the event's direction before the event found is a failure.  It costs
      no right-hand-side evaluation (a bounded-step rerun was 80-90 % of the
      evaluations of the event exercises, measured by ``mech bench``).
    * ``confirm="rerun"``: the run is repeated with the step bounded to a
      ``steps_per_event``-th of the way; a different first event is a failure.
    * ``confirm=False``: no confirmation.
    """
    event = Event(event.fn, terminal=True, direction=event.direction, name=event.name)
    if confirm is True:
        kwargs["dense_output"] = True
    traj = integrate(rhs, t_span, y0, rtol=rtol, events=[event], **kwargs)
    t_ev, y_ev = first_event(traj)
    if confirm is True and t_ev != t_span[0]:
        _confirm_on_dense_output(traj, event, t_span[0], t_ev, steps_per_event)
    elif confirm == "rerun":
        bounded = dict(kwargs)
        span = abs(t_ev - t_span[0])
        bounded["max_step"] = min(kwargs.get("max_step", math.inf), span / steps_per_event) if span > 0 else math.inf
        second = integrate(rhs, t_span, y0, rtol=rtol, events=[event], **bounded)
        t_ev2, _ = first_event(second)
        scale = max(abs(t_ev - t_span[0]), abs(t_ev2 - t_span[0]))
        if abs(t_ev2 - t_ev) > max(1e3 * rtol * scale, 1e-300):
            raise NumericFailure(
                f"event '{event.name}' at t={t_ev:.10g} but at t={t_ev2:.10g} with a bounded step: "
                "a sign change was stepped over"
            )
        traj.nfev += second.nfev
        traj.extra["confirm_nfev"] = second.nfev
    return t_ev, y_ev, traj


def _sorted_distinct(a: np.ndarray) -> np.ndarray:
    """``np.unique`` of a 1-d float array without its import of numpy.ma (8 ms at every start-up)."""
    a = np.sort(a)
    return a[np.concatenate(([True], a[1:] != a[:-1]))] if a.size else a


def _confirm_on_dense_output(traj: Trajectory, event: Event, t0: float, t_ev: float, n_grid: int) -> None:
    """Fail when the event function already crossed zero (in its direction) before ``t_ev``."""
    steps = traj.t[traj.t <= t_ev] if traj.t[-1] >= traj.t[0] else traj.t[traj.t >= t_ev]
    inner = (steps[:-1, None] + np.diff(steps)[:, None] * (np.arange(1, 9) / 9.0)[None, :]).ravel()
    grid = np.linspace(t0, t_ev, n_grid + 1)[:-1]
    ts = _sorted_distinct(np.concatenate([grid, inner, steps[:-1]]))
    ts = ts[(ts - t0) * (t_ev - ts) >= 0.0]
    ts = ts[ts != t_ev]
    if t_ev < t0:
        ts = ts[::-1]
    ys = traj.sol(ts)
    g = [float(event.fn(t, ys[:, k])) for k, t in enumerate(ts)]
    for k in range(len(g) - 1):
        a, b = g[k], g[k + 1]
        down = a > 0.0 >= b
        up = a < 0.0 <= b
        if (down and event.direction <= 0) or (up and event.direction >= 0):
            raise NumericFailure(
                f"event '{event.name}' found at t={t_ev:.10g}, but the solution already crosses it near "
                f"t={ts[k + 1]:.10g}: a sign change was stepped over"
            )
    traj.extra["confirm"] = f"event function sampled at {len(ts)} points of the dense output"
