"""What an exercise is: its catalogue metadata, its parameters, its outputs and its two solvers.

The catalogue file (``problems/catalogue/ID.toml``, a verbatim copy of the shared
specification) is the single source of the statement, the parameters and the
outputs; an exercise module binds it with ``Exercise("4.15", formulas=[...])``
and adds what only the module knows: the formulas as text, the analytic and
numeric solvers, joint parameter constraints and, for a leading-order theory,
the size of what it neglects.
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any, Callable, Mapping

from mech.core.errors import BadInput, NumericFailure
from mech.problems import batched as _batched, solving, validity
from mech.problems.batched import BatchedRoute, Tally
from mech.problems.fields import Output, Param
from mech.problems.motion import Run
from mech.problems.params import Params, Undefined

__all__ = [
    "BadInput",
    "BatchedRoute",
    "Exercise",
    "Output",
    "Param",
    "Params",
    "Run",
    "Tally",
    "Undefined",
    "NumericFailure",
]




def _load_catalogue(ex_id: str) -> dict:
    # beside this module (importlib.resources would cost 4 ms of imports at every start-up)
    text = (Path(__file__).parent / "catalogue" / f"{ex_id}.toml").read_text("utf-8")
    return tomllib.loads(text)


class Exercise:
    """One exercise: catalogue metadata plus the analytic and numeric solvers.

    Parameters beyond the id:
      formulas      the analytic results as text, for ``mech show``
      leading_order names of outputs whose analytic value is a leading-order theory
      axes          names of outputs that are the direction of an axis (no sense): answers judged modulo pi
      tol_factor    the numeric claim for every output is ``tol_factor * rtol`` unless
                    the solver claims otherwise; the cross-check uses that claim
      default_rtol  the numeric solver's default requested accuracy
    """

    def __init__(
        self,
        id: str,
        *,
        formulas: list[str],
        leading_order: tuple[str, ...] = (),
        axes: tuple[str, ...] = (),
        tol_factor: float = 100.0,
        default_rtol: float = 1e-10,
        min_rtol: float = 1e-13,
        route_note: str = "",
        states: tuple[tuple[str, str], ...] | list = (),
        constants: Mapping[str, str] | None = None,
    ):
        """``route_note``: where the implementation departs from the catalogue's numeric route (a
        named library routine replaced, say), shown by ``mech show`` under the route.  ``constants``: the
        dimensional constants the solvers use that are not parameters, name -> unit ({"G": "m^3/(kg s^2)"}),
        so that a change of units (``scales.natural_units``) leaves them unchanged."""
        spec = _load_catalogue(id)
        self.id = spec["id"]
        self.title = spec["title"]
        self.topic = spec["topic"]
        self.from_book = bool(spec.get("from_book", False))  # the book's own, or set for mech on its topics
        self.statement = spec["statement"].strip()
        # the statement as a class's handout gives it, where the statement quotes the defaults: ``{name}``
        # placeholders take each student's values (``mech assign``); empty: the statement serves
        self.handout = spec.get("handout", "").strip()
        # the regime the statement is about, where it is about one: {"positive": [outputs], "about": "..."}
        self.regime = dict(spec.get("regime", {}))
        self.model = spec["model"].strip()
        self.numeric_route = spec.get("numeric", {}).get("route", "").strip()
        self.params = [Param(**p) for p in spec["params"]]
        self.outputs = [
            Output(**o, theory="leading-order" if o["name"] in leading_order else "exact", axis=o["name"] in axes)
            for o in spec["outputs"]
        ]
        unknown = (set(leading_order) | set(axes)) - {o.name for o in self.outputs}
        if unknown:
            raise ValueError(f"{id}: leading_order names unknown outputs {sorted(unknown)}")
        self.hard_cases = [{"params": dict(h["params"]), "why": h.get("why", "")} for h in spec.get("hard_cases", [])]
        self.formulas = list(formulas)
        self.tol_factor = tol_factor
        self.default_rtol = default_rtol
        self.min_rtol = min_rtol
        self.route_note = route_note.strip()
        # (name, unit) of each component of the state vector its numeric route integrates, in order:
        # what a trajectory's rows are (``mech solve --trajectory``, ``Solution.trajectory``)
        self.states = tuple((str(n), str(u)) for n, u in states)
        self.constants = dict(constants or {})
        self._analytic: Callable | None = None
        self._numeric: Callable | None = None
        self._constraints: list[Callable] = []
        self.joint_limits: list[str] = []  # what the constraints enforce, as text (`mech show`, "constraints")
        self._expected_error: Callable | None = None
        self._analytic_error: Callable | None = None
        self._hamiltonian: Callable | None = None
        self._scene: Callable | None = None
        self._motion: Callable | None = None
        self._physics: Callable | None = None  # @exercise.physics: the symbolic declaration (problems/physics.py)
        self._physics_withheld: str | None = None
        self._batched: "BatchedRoute | None" = None
        # the hooks written on arrays (those of an exercise with a batched route): a one-point call is the
        # batch of one (problems/batched.py)
        self._on_arrays: set[str] = set()
        self._theory_range: Callable | None = None
        self._approximations: Callable | None = None
        self.param_map = {p.name: p for p in self.params}

    # -- decorators -------------------------------------------------------
    def analytic(self, fn: Callable[[Params], dict]) -> Callable:
        """Register ``fn(p) -> {output: value}``: the derived answer."""
        self._analytic = fn
        return fn

    def numeric(self, fn: Callable[[Params, Run], dict]) -> Callable:
        """Register ``fn(p, run) -> {output: value}``: the independent computation from the physics."""
        self._numeric = fn
        return fn

    def constraint(self, fn: Callable[[Params], str | None]) -> Callable:
        """Register a joint check of the parameters: return a one-line message when they are unphysical."""
        self._constraints.append(fn)
        return fn

    def restate_hard_case(self, k: int, why: str) -> None:
        """Replace the catalogue's note on hard case ``k`` (0-based) where it misdescribes mech's solution
        (the catalogue file stays the shared one)."""
        self.hard_cases[k]["why"] = why

    def declare_limits(self, *texts: str) -> None:
        """State, one line each, every joint limit the ``@exercise.constraint`` checks refuse beyond
        (``"|x0|/R <= 0.1"``): shown by ``mech show`` and in its JSON as ``"constraints"``, so that a
        user or a script can keep inside them. Declared beside the constraint, from the same constants."""
        self.joint_limits.extend(str(t) for t in texts)

    def expected_error(self, fn: Callable[[Params], dict]) -> Callable:
        """For leading-order outputs: ``fn(p) -> {output: relative size of what the theory neglects}``; an
        output whose leading-order value can be zero gives ``(relative, absolute)`` instead (absolute in SI)."""
        self._expected_error = fn
        return fn

    def theory_range(self, fn: Callable[[Params], dict]) -> Callable:
        """For leading-order outputs: ``fn(p) -> {output: (label, value)}``, the parameter the theory expands
        in at ``p`` (the largest where there are several): ``{"omega": ("mu/omega0", 3.3)}``.  At a value of 1
        or more the theory is outside its range (``theory_validity``)."""
        self._theory_range = fn
        return fn

    def approximations(self, fn: Callable[[Params], dict]) -> Callable:
        """Where the statement asks for an approximation next to an exact output: ``fn(p) -> {output:
        [(value, "what it is"), ...]}`` (values in SI), e.g. the small-swing period next to the exact one."""
        self._approximations = fn
        return fn

    def analytic_error(self, fn: Callable[[Params], dict]) -> Callable:
        """For outputs whose analytic value is ill-conditioned in its inputs (a phase of 1e6 rad, a
        cancellation): ``fn(p) -> {output: absolute round-off error of the analytic value, SI}``.
        Agreement is then judged against the numeric and analytic errors combined."""
        self._analytic_error = fn
        return fn

    def hamiltonian(self, fn: Callable[[Params], Any]) -> Callable:
        """Optional: ``fn(p) -> mech.solvers.numerics.symplectic.SeparableHamiltonian``, the scene as a separable
        Hamiltonian with the readout of the outputs, so that a symplectic integrator can solve it too
        (``mech bench`` adds that row).  It does not replace the numeric solver."""
        self._hamiltonian = fn
        return fn

    def motion(self, fn: Callable[[Params], Any]) -> Callable:
        """Register ``fn(p) -> mech.problems.motion.Motion``: the motion the numeric solve integrates, declared
        once (right-hand side, start, span, event, invariants, scales to SI; rows are ``states``).  The
        numeric solve follows it (``run.follow``), the scene takes it (``SceneRun.motion``)."""
        if not self.states:
            raise ValueError(f"{self.id}: a motion needs the exercise's states (names and units)")
        self._motion = fn
        return fn

    def motion_at(self, p: Params) -> Any:
        """The declared motion at ``p`` (``@exercise.motion``), None without one."""
        return None if self._motion is None else self._motion(p)

    def physics(self, fn: Callable[[Any], None]) -> Callable:
        """Register ``fn(d)``: the exercise's physics declared for sympy (``mech.problems.physics``), kept in
        ``physicsN_M.py`` beside the module and imported only by ``derive()``."""
        self._physics = fn
        return fn

    def physics_withheld(self, why: str) -> None:
        """Say why the motion has no declaration (a reduced or averaged model no Lagrangian gives)."""
        self._physics_withheld = " ".join(why.split())

    def derive(self):
        """The declared physics with its equations derived (sympy: the ``derive`` extra); LookupError says
        why there is none."""
        from mech.problems.physics import derive

        return derive(self)

    def scene(self, fn: Callable[[Params, Any], Any]) -> Callable:
        """Optional: ``fn(p, run) -> mech.problems.scene.Scene``, what ``mech plot`` draws for this
        exercise, computed from the exercise's own physics (``run``: a ``scene.SceneRun``)."""
        self._scene = fn
        return fn

    def batched(self, outputs: tuple[str, ...], *, boundaries: Mapping[str, tuple[str, str]] | None = None
                ) -> Callable:
        """Register the exercise's route over arrays of variants, ``fn(P, rtol, outputs[, memo, tally]) ->
        {output: Column}``, and declare its ``analytic``, ``expected_error`` and ``theory_range`` hooks written on
        arrays too: a one-point solve is the batch of one (problems/batched.py).  ``boundaries``: parameter ->
        (output, label), the analytic value of that output a boundary in that parameter, drawn on maps."""
        unknown = set(outputs) - {o.name for o in self.outputs}
        if unknown:
            raise ValueError(f"{self.id}: batched route names unknown outputs {sorted(unknown)}")
        return lambda fn: _batched.register(self, fn, outputs, boundaries)

    def batch_of_one(self, p: Params, run: Run, outputs: tuple[str, ...] | None = None) -> dict:
        """The batched route at the one point ``p`` (problems/batched.py ``one_point``): {output: value}, its
        claims, invariants and failure reported to ``run``."""
        return _batched.one_point(self, p, run, outputs)

    # -- what is registered: read by verification, bench, sweeps and tests ----
    @property
    def analytic_solver(self) -> Callable | None:
        """The analytic solver at one point, ``fn(p) -> {output: value}`` (None without one; a hook written on
        arrays called as the batch of one); assigning registers another (a one-point function)."""
        if self._analytic is not None and "analytic" in self._on_arrays:
            return _batched.analytic_solver(self._analytic)
        return self._analytic

    @analytic_solver.setter
    def analytic_solver(self, fn: Callable | None) -> None:
        hook = getattr(fn, "array_hook", None)
        self._analytic = fn if hook is None else hook
        (self._on_arrays.discard if hook is None else self._on_arrays.add)("analytic")

    @property
    def numeric_solver(self) -> Callable | None:
        """The numeric solver at one point, ``fn(p, run)`` (None without one): the registered one, else the
        batched route's batch of one where it gives every output; assigning registers another."""
        if self._numeric is None and self._batched is not None and \
                set(self._batched.outputs) == {o.name for o in self.outputs}:
            return self.batch_of_one
        return self._numeric

    @numeric_solver.setter
    def numeric_solver(self, fn: Callable | None) -> None:
        self._numeric = fn

    @property
    def has_analytic(self) -> bool:
        return self._analytic is not None

    @property
    def has_numeric(self) -> bool:
        return self.numeric_solver is not None

    @property
    def has_hamiltonian(self) -> bool:
        """Whether the exercise exposes its scene as a separable Hamiltonian (``mech bench``'s symplectic rows)."""
        return self._hamiltonian is not None

    def separable_hamiltonian(self, p: Params) -> Any:
        """The registered ``@exercise.hamiltonian`` at ``p``: a ``symplectic.SeparableHamiltonian``."""
        if self._hamiltonian is None:
            raise ValueError(f"{self.id} exposes no separable Hamiltonian")
        return self._hamiltonian(p)

    @property
    def has_constraints(self) -> bool:
        """Whether joint checks beyond the bounds are registered (``@exercise.constraint``)."""
        return bool(self._constraints)

    @property
    def has_motion(self) -> bool:
        """Whether the exercise declares its motion (``@exercise.motion``)."""
        return self._motion is not None

    @property
    def has_scene(self) -> bool:
        """Whether the exercise draws a scene of its own (``@exercise.scene``, ``mech plot``)."""
        return self._scene is not None

    @property
    def batched_route(self) -> "BatchedRoute | None":
        """The chart's batched route (``@exercise.batched``), None without one; assigning replaces it."""
        return self._batched

    @batched_route.setter
    def batched_route(self, route: "BatchedRoute | None") -> None:
        self._batched = route

    # -- use --------------------------------------------------------------
    @property
    def methods(self) -> list[str]:
        return [m for m, f in (("analytic", self._analytic), ("numeric", self.numeric_solver)) if f is not None]

    @property
    def chapter(self) -> int:
        return int(self.id.split(".")[0])

    def resolve(self, given: Mapping[str, float] | None = None) -> Params:
        """Defaults overlaid by the given values, each checked against its bounds, then the joint checks
        (``solving.resolve``)."""
        return solving.resolve(self, given)

    def solve_analytic(self, p: Params) -> dict:
        """The analytic answers, solved in the units that bring the parameters nearest their defaults where
        they are far from them (``solving.solve_analytic``)."""
        return solving.solve_analytic(self, p)

    def solve_numeric(self, p: Params, rtol: float | None = None, shared: dict | None = None,
                      keep_trajectories: bool = False, integrator: str | None = None) -> tuple[dict, Run]:
        """The numeric answers and their Run (``solving.solve_numeric``)."""
        return solving.solve_numeric(self, p, rtol, shared, keep_trajectories, integrator)

    def as_json(self) -> dict:
        return {
            "id": self.id,
            "title": self.title,
            "topic": self.topic,
            "statement": self.statement,
            "model": self.model,
            "params": [p.as_json() for p in self.params],
            "outputs": [o.as_json() for o in self.outputs],
            "formulas": self.formulas,
            "numeric_route": self.numeric_route,
            "hard_cases": self.hard_cases,
            "constraints": list(self.joint_limits),
            "methods": self.methods,
        }

    def __repr__(self) -> str:
        return f"<Exercise {self.id}: {self.title}>"
