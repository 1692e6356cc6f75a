"""A motion an exercise integrates, declared once.

An integrating exercise registers ``@exercise.motion def motion(p) -> Motion``: the
right-hand side, the initial state, the span, the event that ends the motion and the
conserved quantities, in the variables it integrates, with the scales that bring them
to SI.  The state's names and units are the exercise's ``states``.  The numeric solve
follows it (``run.follow(motion)``: integrated under the Run's integrator, so bench
forces it too, its invariants' drifts reported, marked as the scene's motion); the API's
trajectory and the scene (``SceneRun.motion``) take the same integration.  Nothing
else writes the equations of motion, the start or the energy again.

A motion in legs (a strike, then rolling; a forced stretch, then free swinging) declares its
first leg with ``then``: a function of that leg's ``Path`` giving the next leg (or None), so
``run.follow`` integrates the whole chain and marks every leg.  A route that integrates the same
equations from other starts (a shooting, a settling run, a continuation) takes the declared
motion and changes its start (``Motion.starting``), following it with ``mark=False`` where the
integration is a tool and not the scene's motion.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

__all__ = ["Motion", "Path", "join", "Run", "motion_path"]


@dataclass(frozen=True)
class Motion:
    """``rhs(t, y)`` from ``y0`` over ``span`` in the integrated (often scaled) variables.

    ``event``: an ``ode.Event`` that ends the motion (found and confirmed on the dense output);
    ``invariants``: name -> ``f(y)``, a conserved quantity already divided by its scale, whose drift
    ``f(y_end) - f(y0)`` the solve reports; ``monitors``: name -> ``g(Y)``, the worst relative drift of
    a conserved quantity (or a constraint's violation) over the steps ``Y`` (n x N); ``t_scale``, ``y_scale``: SI time ``t_scale * t`` and
    state ``y_scale * to_states(y)`` (a number or one per state), ``to_states`` mapping the integrated
    variables (n x N) to the declared ones where they differ (an angle kept as its deviation from
    upright); ``options``: the integration's own settings (``max_step``, ``method``) at any rtol,
    overridden by a forced integrator; ``y_size``: the size of each integrated variable (a number or one
    per variable; 1 by default), the absolute tolerance being ``1e-3 * rtol * y_size``;
    ``t_offset``: the SI time at which this leg starts (``t_offset + t_scale * t``); ``then``:
    ``f(path) -> Motion | None``, the next leg from this one's end (a motion in legs); ``shown``: False for a
    leg that leads into the scene's motion without being part of it (a strike before the sliding the states
    describe): followed and recorded, never marked; ``clock``: where the integration's variable is not the
    time (a Sundman rescaling, the time carried as a state), ``clock(y)`` gives the time (in units of
    ``t_scale``) of the states y (n x N).

    For the comparison with the derived equations (``mech.problems.physics``, tests/test_physics_derived.py):
    ``from_states``: the exact inverse of ``to_states`` (declared states before ``y_scale`` -> y), needed only
    where ``to_states`` is not affine (an affine one is inverted from its offset and matrix; a non-affine one
    is differentiated numerically, to about 1e-13); ``event_scale``:
    the SI value of the event function is ``event_scale * event(t, y)``; ``idle_rows``: rows of y the
    right-hand side carries beside the states (a clock, a constant, a quadrature) that no declared state
    depends on, left out of the comparison."""

    rhs: Callable
    y0: Sequence[float]
    span: tuple[float, float]
    event: Any = None
    invariants: Mapping[str, Callable] = field(default_factory=dict)
    monitors: Mapping[str, Callable] = field(default_factory=dict)
    t_scale: float = 1.0
    y_scale: Any = None
    options: Mapping[str, Any] = field(default_factory=dict)
    y_size: Any = None
    to_states: Callable | None = None
    t_offset: float = 0.0
    then: Callable | None = None
    shown: bool = True
    clock: Callable | None = None
    from_states: Callable | None = None
    event_scale: Any = None
    idle_rows: tuple = ()

    def starting(self, y0=None, span=None, **changes) -> "Motion":
        """The same equations from another start (``y0``) or over another ``span`` (any other field by
        keyword): a shooting's trial, a settling run, the next leg."""
        from dataclasses import replace

        if y0 is not None:
            changes["y0"] = y0
        if span is not None:
            changes["span"] = (float(span[0]), float(span[1]))
        return replace(self, **changes)

    def with_variations(self, jac: Callable) -> "Motion":
        """The same motion with its variational equations carried along (a monodromy run): the state y
        (n rows) then d y/d y0 (n x n, row by row) from the identity, ``jac(t, y)`` the Jacobian of ``rhs``.
        The entry d y_i/d y0_j has the size s_i/s_j (s: ``y_size``); ``to_states`` reads the first n rows,
        so the declared states are the motion's own.  ``path.y_end[n:].reshape(n, n)`` is the matrix."""
        import numpy as np

        n = len(self.y0)
        f = self.rhs

        def rhs(t, z):
            return np.concatenate([f(t, z[:n]), (jac(t, z[:n]) @ z[n:n + n * n].reshape(n, n)).ravel()])

        s = np.ones(n) if self.y_size is None else np.broadcast_to(np.asarray(self.y_size, float), (n,))
        base = self.to_states
        return self.starting(y0=np.concatenate([np.asarray(self.y0, float), np.eye(n).ravel()]), rhs=rhs,
                             y_size=np.concatenate([s, np.outer(s, 1.0 / s).ravel()]), event=None,
                             invariants={}, monitors={}, then=None,
                             to_states=(lambda z: z[:n]) if base is None else (lambda z: base(z[:n])))

    def si(self, y):
        """A state (or n x N states) of the integrated variables, as the declared states in SI."""
        import numpy as np

        y = np.asarray(y, float)
        if self.to_states is not None:
            y = np.asarray(self.to_states(y), float)
        if self.y_scale is None:
            return y
        scale = np.broadcast_to(np.asarray(self.y_scale, float), (y.shape[0],))
        return y * (scale if y.ndim == 1 else scale[:, None])

    def states_map(self, y):
        """(b, A): ``to_states`` near y as offset and matrix, to_states(y + dy) = b + A (y + dy), each column
        from a unit step (exact for an affine map, the
        only kind the comparison takes)."""
        import numpy as np

        y = np.asarray(y, float)
        if self.to_states is None:
            return np.zeros(y.size), np.eye(y.size)
        f = lambda z: np.asarray(self.to_states(z), float)  # noqa: E731
        f0 = f(y)
        A = np.stack([f(y + e) - f0 for e in np.eye(y.size)], axis=1)
        return f0 - A @ y, A

    def integrated(self, x, y_fill=None):
        """The integrated variables y of the SI declared states x: ``from_states`` where given, else the affine
        ``to_states`` inverted (rows it ignores, ``idle_rows``, taken from ``y_fill``, the start by default)."""
        import numpy as np

        x = np.asarray(x, float)
        if self.y_scale is not None:
            x = x / np.broadcast_to(np.asarray(self.y_scale, float), x.shape)
        if self.from_states is not None:
            return np.asarray(self.from_states(x), float)
        fill = np.asarray(self.y0 if y_fill is None else y_fill, float).copy()
        b, A = self.states_map(fill)
        used = [j for j in range(fill.size) if j not in self.idle_rows]
        sol = np.linalg.lstsq(A[:, used], x - b - A[:, self.idle_rows] @ fill[list(self.idle_rows)], rcond=None)[0]
        fill[used] = sol
        return fill

    def states_rate(self, t, y):
        """The declared states' rates in SI at the SI time t and integrated state y, from ``rhs``."""
        import numpy as np

        y = np.asarray(y, float)
        dy = np.asarray(self.rhs((t - self.t_offset) / self.t_scale, y), float)
        if self.to_states is None:
            rate = dy[:y.size]
        elif self.from_states is None:  # affine
            rate = self.states_map(y)[1] @ dy
        else:  # the derivative of to_states along dy: 5 points and Richardson, error ~ 1e-13 of the rate
            f = lambda h: np.asarray(self.to_states(y + h * dy), float)  # noqa: E731
            step = 1e-3 * max(np.max(np.abs(y)), 1e-300) / max(np.max(np.abs(dy)), 1e-300)

            def central(h):
                return (8.0 * (f(h) - f(-h)) - (f(2 * h) - f(-2 * h))) / (12.0 * h)

            c1, c2 = central(step), central(step / 2)
            rate = c2 + (c2 - c1) / 15.0
        scale = 1.0 if self.y_scale is None else np.broadcast_to(np.asarray(self.y_scale, float), rate.shape)
        return rate * scale / self.t_scale

    @property
    def start(self):
        """The initial state in SI."""
        return self.si(self.y0)


@dataclass(frozen=True)
class Path:
    """What following a motion gives: its end (the event's time and state, or the span's end) in the
    integrated variables, and the integration (``t``, ``y``, ``sol`` when dense).  Following a motion in
    legs gives the last leg's path; ``legs`` holds every leg's path in order (this one last) and
    ``motion`` the leg it followed."""

    t_end: float
    y_end: Any
    traj: Any
    motion: Any = None
    legs: tuple = ()


def join(parts, n: int, samples: int = 201):
    """The motion legs a solve marked (``Run.motion_parts``) in SI, joined in time order: ``(t, y)`` with y
    n x N.  A leg with a continuous extension and fewer than ``samples`` steps is sampled at least that
    densely (the integrator's own interpolant between its steps: a smooth curve to plot)."""
    import numpy as np

    ts, ys = [], []
    for traj, t_scale, t_offset, y_scale, rows in parts:
        t = np.asarray(traj.t, float)
        sol = getattr(traj, "sol", None)
        if sol is not None and t.size < samples:
            t = np.union1d(np.linspace(t.min(), t.max(), samples), t)
            y = np.asarray(sol(t), float)
        else:
            y = np.asarray(traj.y, float)
        y = y.reshape(-1, t.size)
        if rows is not None:
            y = y[rows]
        if y.shape[0] != n:
            raise RuntimeError(f"the motion has {y.shape[0]} states, the exercise declares {n}")
        scale = np.ones(n) if y_scale is None else np.broadcast_to(np.asarray(y_scale, float), (n,))
        ts.append(t_offset + t_scale * t)
        ys.append(y * scale[:, None])
    t = np.concatenate(ts)
    y = np.concatenate(ys, axis=1)
    order = np.argsort(t, kind="stable")
    t, y = t[order], y[:, order]
    keep = np.concatenate(([True], np.diff(t) > 0))  # a time shared by two legs once
    return t[keep], y[:, keep]


class _Transformed:
    """An integration seen through a map of its states (``Run.motion``'s ``transform``)."""

    def __init__(self, traj: Any, transform: Callable):
        self.t = traj.t
        self._transform = transform
        self.y = self._map(traj.y, len(traj.t))
        sol = getattr(traj, "sol", None)
        self.sol = None if sol is None else (lambda t: self._map(sol(t), len(t)))

    def _map(self, y, n: int):
        import numpy as np

        return np.asarray(self._transform(np.asarray(y, float).reshape(-1, n)), float)


class _Clocked:
    """An integration in another variable than the time, seen in time (``Run.motion``'s ``clock``): sampled on
    its continuous extension at 201 even values of its variable and at its steps."""

    sol = None

    def __init__(self, traj: Any, clock: Callable):
        import numpy as np

        s = np.union1d(np.linspace(traj.t[0], traj.t[-1], 201), traj.t)
        y = np.asarray(traj.sol(s), float).reshape(-1, s.size)
        self.t = np.asarray(clock(y), float)
        self.y = y


@dataclass
class Run:
    """What a numeric solver is given and what it reports back besides its answers.

    Given: ``rtol``, the requested relative accuracy; ``integrator``, the integrator every ODE
    integration must use (``mech bench``: a method name, or "student" for solve_ivp's defaults; None
    keeps each integration's own method and step settings; ``follow`` applies it, a shared solver
    takes it as ``integrator=run.integrator``); ``keep_trajectories``, whether the motion is kept;
    ``shared``, a dict shared by the runs of one cross-check (the solve and its rerun at rtol/10),
    where a solver may keep what it computed at a tolerance that does not depend on rtol, keyed by
    everything it depends on (never in the JSON, new for every cross-check).

    Reported: the method, the cost of what it integrated (``record``, ``cost``), the drift of the
    invariants it monitors (``invariant``), per-output accuracy claims (``claim``), the scene's motion
    (``motion``, ``follow``) and anything else worth showing (``info``).
    """

    rtol: float
    integrator: str | None = None
    keep_trajectories: bool = False
    shared: dict = field(default_factory=dict, repr=False)
    method: str | None = None
    info: dict = field(default_factory=dict)
    claims: dict = field(default_factory=dict)
    invariants: dict = field(default_factory=dict)
    # name -> the drift the method allows for that invariant (None: the exercise's default claim,
    # tol_factor * rtol); a drift beyond it fails the cross-check
    invariant_allowed: dict = field(default_factory=dict)
    # (evaluations, forced) of each recorded integration (forced: ``integrator`` was applied) or of a cost
    # that is no integration (forced None)
    costs: list = field(default_factory=list, repr=False)
    motion_parts: list = field(default_factory=list, repr=False)

    @property
    def nfev(self) -> int:
        """Right-hand-side (or model) evaluations of everything recorded."""
        return sum(n for n, _ in self.costs)

    @property
    def forced_runs(self) -> int:
        """Recorded integrations that ran with ``integrator`` applied."""
        return sum(1 for _, forced in self.costs if forced)

    @property
    def own_runs(self) -> int:
        """Recorded integrations that ran with the exercise's own settings."""
        return sum(1 for _, forced in self.costs if forced is False)

    def record(self, result: Any, method: str | None = None) -> Any:
        """Add the cost of an integration (anything with ``nfev``, ``method`` and ``forced``: a trajectory,
        an orbit map that integrated many)."""
        m = method or getattr(result, "method", None)
        if m and not self.method:
            self.method = m
        self.costs.append((int(getattr(result, "nfev", 0) or 0), bool(getattr(result, "forced", False))))
        return result

    def cost(self, nfev: int) -> None:
        """Add evaluations of a route that integrates no ODE through ``ode`` (a splitting, a quadrature)."""
        self.costs.append((int(nfev), None))

    def _integrate(self, rhs: Callable, t_span, y0, **kwargs) -> Any:
        """``ode.integrate`` under the Run's integrator choice, recorded; the keywords are the exercise's own
        choice (method, step bounds), used when no integrator is forced."""
        from mech.solvers.numerics.ode import integrate

        return self.record(integrate(rhs, t_span, y0, integrator=self.integrator, **kwargs))

    def _integrate_to_event(self, rhs: Callable, t_span, y0, event, **kwargs) -> tuple:
        """``ode.integrate_to_event`` under the Run's integrator choice; the trajectory is recorded."""
        from mech.solvers.numerics.ode import integrate_to_event

        t_ev, y_ev, traj = integrate_to_event(rhs, t_span, y0, event, integrator=self.integrator, **kwargs)
        self.record(traj)
        return t_ev, y_ev, traj

    def follow(self, motion: Any, rtol: float | None = None, dense: bool = False, mark: bool = True) -> Any:
        """Integrate a declared ``motion.Motion`` at ``rtol`` (the Run's by default): recorded, its invariants'
        drifts reported, marked as the scene's motion (``mark=False``: an integration that is a tool, a
        shooting's trial, not the motion to show).  A motion in legs (``Motion.then``) is followed leg by
        leg.  Returns the last leg's ``motion.Path`` (``legs``: every leg's)."""

        legs = []
        while motion is not None:
            path = self._follow_leg(motion, rtol, dense, mark)
            legs.append(path)
            motion = None if motion.then is None else motion.then(path)
        last = legs[-1]
        return Path(last.t_end, last.y_end, last.traj, last.motion, tuple(legs[:-1]) + (last,))

    def _follow_leg(self, motion: Any, rtol: float | None, dense: bool, mark: bool) -> Any:

        rtol = self.rtol if rtol is None else rtol
        mark = mark and motion.shown
        opts = dict(motion.options)
        if motion.y_size is not None:
            size = motion.y_size
            opts["atol"] = [rtol * 1e-3 * v for v in size] if hasattr(size, "__len__") else rtol * 1e-3 * size
        if motion.event is not None:
            t_end, y_end, traj = self._integrate_to_event(motion.rhs, motion.span, motion.y0, motion.event,
                                                         rtol=rtol, **opts)
        else:
            if dense or (mark and self.keep_trajectories):
                opts["dense_output"] = True  # a smooth trajectory; the steps are the same
            traj = self._integrate(motion.rhs, motion.span, motion.y0, rtol=rtol, **opts)
            t_end, y_end = float(traj.t[-1]), traj.y[:, -1]
        for name, f in motion.invariants.items():
            self.invariant(name, f(y_end) - f(motion.y0))
        for name, g in motion.monitors.items():
            self.invariant(name, g(traj.y))
        if mark:
            self.motion(traj, t_scale=motion.t_scale, t_offset=motion.t_offset, y_scale=motion.y_scale,
                        transform=motion.to_states, clock=motion.clock)
        return Path(float(t_end), y_end, traj, motion)

    def motion(self, traj: Any, *, t_scale: float = 1.0, t_offset: float = 0.0, y_scale=None,
               rows=None, transform: Callable | None = None, clock: Callable | None = None) -> None:
        """Mark an integration (anything with ``t``, ``y`` and optionally a continuous extension ``sol``) as
        (a leg of) the scene's motion: its ``rows`` (all by default) are the exercise's declared ``states``.
        Scaled variables are brought to SI: time ``t_offset + t_scale * t``, state ``y_scale * y`` (a number
        or one per state).  Where the integrated variables are not the declared ones (an angle kept as its
        change, a branch's own variables), ``transform`` maps the state array (n x N, scaled) to them before
        ``rows`` and ``y_scale``; it runs only when a trajectory was asked for.  ``clock``: where the
        integration's variable is not the time, the time (before ``t_scale``) from the states, read on the
        continuous extension at 201 even values of the variable and at its steps.  Legs marked one after
        another are joined in time order."""
        if self.keep_trajectories:
            if clock is not None:
                traj = _Clocked(traj, clock)
            if transform is not None:
                traj = _Transformed(traj, transform)
            self.motion_parts.append((traj, float(t_scale), float(t_offset), y_scale, rows))

    def trajectory(self, n: int, samples: int = 201):
        """The motion marked (``motion``), in SI, legs joined in time: ``(t, y)``, or None when none was kept."""
        if not self.motion_parts:
            return None

        return join(self.motion_parts, n, samples)

    def claim(self, name: str, rel: float | None = None, abs: float | None = None) -> None:
        """Declare the accuracy of one output: relative and/or absolute."""
        self.claims[name] = (rel, abs)

    def invariant(self, name: str, drift: float, allowed: float | None = None) -> None:
        """Record the relative drift of a conserved quantity (the worst over the run).

        ``allowed`` is the drift the method can have and still be right (by default the exercise's
        claim ``tol_factor * rtol``); a larger drift fails the cross-check: the integration is wrong."""
        drift = float(abs(drift))
        self.invariants[name] = max(drift, self.invariants.get(name, 0.0))
        if allowed is not None:
            self.invariant_allowed[name] = float(allowed)

    def as_json(self) -> dict:
        d = {"method": self.method, "rtol": self.rtol, "nfev": self.nfev}
        if self.invariants:
            d["invariants"] = {k: v for k, v in self.invariants.items()}
        d.update(self.info)
        return d


def motion_path(ex, p, rtol: float | None = None) -> tuple:
    """``ex``'s declared motion at ``p`` integrated at ``rtol`` with its continuous extension: ``(motion, path)``
    (``Motion``, ``Path``), (None, None) without one."""
    m = ex.motion_at(p)
    if m is None:
        return None, None
    return m, Run(rtol=rtol).follow(m, dense=True)
