"""What an exercise is: a declaration its module writes and the floors above read.

The catalogue file (``problems/catalogue/ID.toml``, a verbatim copy of the shared
specification) is the single source of the statement, the parameters and the
outputs; an exercise module binds it with ``Exercise("4.15", formulas=[...])``
and registers, with the decorators below, what only the module knows: the
analytic and numeric solvers, joint parameter constraints, its motion, its
scene, its route over arrays of variants and, for a leading-order theory, its
range and the size of what it neglects.

The work done with a declaration lives beside it, in functions taking the
exercise: ``solving`` (parameters resolved, the solvers run at one point),
``validity`` (a theory's range, the allowances), ``batched`` (the route over
arrays and its batch of one), ``motion`` (``Run``, a motion followed), ``scene``
(a scene made); ``fields`` holds ``Param`` and ``Output``.
"""

from __future__ import annotations

from typing import Any, Callable, Mapping

from mech.core.errors import BadInput, NumericFailure
from mech.problems import batched as _batched, solving
from mech.problems.batched import BatchedRoute, Tally
from mech.problems.fields import Output, Param, read_catalogue
from mech.problems.motion import Run
from mech.problems.params import Params, Undefined

__all__ = ["BadInput", "BatchedRoute", "Exercise", "Output", "Param", "Params", "Run", "Tally", "Undefined",
           "NumericFailure"]


def _hook(name: str, doc: str) -> Callable:
    """The decorator method that registers ``fn`` as the exercise's hook ``name`` (``_name``) and returns it."""

    def register(self, fn: Callable) -> Callable:
        setattr(self, "_" + name, fn)
        return fn

    register.__name__, register.__qualname__ = name, f"Exercise.{name}"
    register.__doc__ = "Register " + " ".join(doc.split())
    return register


class Exercise:
    """One exercise: its catalogue metadata and the hooks its module registers.

    Parameters beyond the id:
      formulas      the analytic results as text, for ``mech show``
      leading_order names of outputs whose analytic value is a leading-order theory
      axes          names of outputs that are the direction of an axis (no sense): answers judged modulo pi
      tol_factor    the numeric claim for every output is ``tol_factor * rtol`` unless
                    the solver claims otherwise; the cross-check uses that claim
      default_rtol  the numeric solver's default requested accuracy (``min_rtol``: the smallest it takes)
      route_note    where the implementation departs from the catalogue's numeric route, shown by ``mech show``
      states        (name, unit) of each component of the state its numeric route integrates, in order: the
                    rows of a trajectory (``mech solve --trajectory``, ``Solution.trajectory``)
      constants     the dimensional constants the solvers use that are not parameters, name -> unit
                    ({"G": "m^3/(kg s^2)"}), so that a change of units (``scales.natural_units``) keeps them
    """

    # the registered hooks (None: not declared), each set by its decorator below
    _analytic = _numeric = _expected_error = _analytic_error = _theory_range = _approximations = None
    _hamiltonian = _scene = _motion = _physics = _physics_withheld = None
    batched_route: BatchedRoute | None = None  # ``@exercise.batched``: the route over arrays of variants

    def __init__(self, id: str, *, formulas: list[str], leading_order: tuple[str, ...] = (),
                 axes: tuple[str, ...] = (), tol_factor: float = 100.0, default_rtol: float = 1e-10,
                 min_rtol: float = 1e-13, route_note: str = "", states: tuple[tuple[str, str], ...] | list = (),
                 constants: Mapping[str, str] | None = None):
        spec = read_catalogue(id)
        self.id, self.title, self.topic = spec["id"], spec["title"], spec["topic"]
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
        self.param_map = {p.name: p for p in self.params}
        self.outputs = [Output(**o, theory="leading-order" if o["name"] in leading_order else "exact",
                               axis=o["name"] in axes) for o in spec["outputs"]]
        unknown = (set(leading_order) | set(axes)) - {o.name for o in self.outputs}
        if unknown:
            raise ValueError(f"{id}: leading_order names unknown outputs {sorted(unknown)}")
        self.hard_cases = [{"params": dict(h["params"]), "why": h.get("why", "")} for h in spec.get("hard_cases", [])]
        self.formulas = list(formulas)
        self.tol_factor, self.default_rtol, self.min_rtol = tol_factor, default_rtol, min_rtol
        self.route_note = route_note.strip()
        self.states = tuple((str(n), str(u)) for n, u in states)
        self.constants = dict(constants or {})
        self._constraints: list[Callable] = []
        self.joint_limits: list[str] = []  # what the constraints enforce, as text (`mech show`, "constraints")
        self._on_arrays: set[str] = set()  # the hooks written on arrays (``batched``): called as a batch of one

    # -- what an exercise module declares ----------------------------------------------------------------
    # the hooks its decorators register (``@exercise.analytic`` and so on), each ``fn`` returned as it is
    analytic = _hook("analytic", "``fn(p) -> {output: value}``: the derived answer.")
    numeric = _hook("numeric", "``fn(p, run) -> {output: value}``: the independent computation from the physics.")
    expected_error = _hook("expected_error", """``fn(p) -> {output: relative size of what its leading-order
        theory neglects}``, or ``(relative, absolute)`` where the value can be zero (absolute in SI).""")
    theory_range = _hook("theory_range", """``fn(p) -> {output: (label, value)}``: the parameter a leading-order
        theory expands in (``("mu/omega0", 3.3)``); at 1 or more it is outside its range.""")
    approximations = _hook("approximations", """``fn(p) -> {output: [(value, "what it is"), ...]}`` (SI): what the
        statement asks for beside an exact output (the small-swing period beside the exact one, say).""")
    analytic_error = _hook("analytic_error", """``fn(p) -> {output: absolute round-off error, SI}`` where an
        analytic value is ill-conditioned (a phase of 1e6 rad, a cancellation): added to what agreement allows.""")
    hamiltonian = _hook("hamiltonian", """``fn(p) -> symplectic.SeparableHamiltonian`` (optional): the scene with
        the readout of the outputs, for ``mech bench``'s symplectic rows (never the numeric solver).""")
    physics = _hook("physics", "``fn(d)``: the physics declared for sympy (problems/physics.py), in physicsN_M.py.")
    scene = _hook("scene", "``fn(p, run) -> scene.Scene`` (optional): what ``mech plot`` draws, from its physics.")

    def constraint(self, fn: Callable[[Params], str | None]) -> Callable:
        """Register a joint check of the parameters: return a one-line message when they are unphysical."""
        self._constraints.append(fn)
        return fn

    def declare_limits(self, *texts: str) -> None:
        """State, one line each, every joint limit the ``@exercise.constraint`` checks refuse beyond (``"|x0|/R
        <= 0.1"``): ``mech show`` and its JSON's ``"constraints"``; declared beside the check, from its constants."""
        self.joint_limits.extend(str(t) for t in texts)

    def restate_hard_case(self, k: int, why: str) -> None:
        """Replace the catalogue's note on hard case ``k`` (0-based) where it misdescribes mech's solution."""
        self.hard_cases[k]["why"] = why

    def motion(self, fn: Callable[[Params], Any]) -> Callable:
        """Register ``fn(p) -> motion.Motion``: the motion the numeric solve integrates, declared once (rows are
        ``states``); the numeric solve follows it (``run.follow``), the scene takes it (``SceneRun.motion``)."""
        if not self.states:
            raise ValueError(f"{self.id}: a motion needs the exercise's states (names and units)")
        self._motion = fn
        return fn

    def physics_withheld(self, why: str) -> None:
        """Say why the motion has no declaration (a reduced or averaged model no Lagrangian gives)."""
        self._physics_withheld = " ".join(why.split())

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
        """The batched route at the one point ``p`` (``batched.one_point``): {output: value}; its claims,
        invariants and failure go to ``run``."""
        return _batched.one_point(self, p, run, outputs)

    # -- what the floors above read ----------------------------------------------------------------------
    @property
    def analytic_solver(self) -> Callable | None:
        """``fn(p) -> {output: value}`` at one point (None without one; a hook on arrays called as the batch of
        one); assigning registers another."""
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
        """``fn(p, run)`` at one point (None without one): the registered one, else the batched route's batch
        of one where it gives every output; assigning registers another."""
        if self._numeric is None and self.batched_route is not None and \
                set(self.batched_route.outputs) == {o.name for o in self.outputs}:
            return self.batch_of_one
        return self._numeric

    @numeric_solver.setter
    def numeric_solver(self, fn: Callable | None) -> None:
        self._numeric = fn

    has_analytic = property(lambda self: self._analytic is not None)
    has_numeric = property(lambda self: self.numeric_solver is not None)
    has_constraints = property(lambda self: bool(self._constraints))  # checks beyond the bounds
    has_motion = property(lambda self: self._motion is not None)
    has_scene = property(lambda self: self._scene is not None)  # ``mech plot`` draws the exercise's own
    has_hamiltonian = property(lambda self: self._hamiltonian is not None)  # ``mech bench``'s symplectic rows
    chapter = property(lambda self: int(self.id.split(".")[0]))

    @property
    def methods(self) -> list[str]:
        return [m for m, f in (("analytic", self._analytic), ("numeric", self.numeric_solver)) if f is not None]

    def motion_at(self, p: Params) -> Any:
        """The declared motion at ``p`` (``@exercise.motion``), None without one."""
        return None if self._motion is None else self._motion(p)

    def separable_hamiltonian(self, p: Params) -> Any:
        """The registered ``@exercise.hamiltonian`` at ``p``."""
        if self._hamiltonian is None:
            raise ValueError(f"{self.id} exposes no separable Hamiltonian")
        return self._hamiltonian(p)

    def derive(self):
        """The declared physics with its equations derived (sympy); LookupError says why there is none."""
        from mech.problems.physics import derive

        return derive(self)

    # the solving done at one point, in problems/solving.py: one line each here, for their many callers
    def resolve(self, given: Mapping[str, float] | None = None) -> Params:
        """Defaults overlaid by the given values, checked against the bounds and the joint checks."""
        return solving.resolve(self, given)

    def solve_analytic(self, p: Params) -> dict:
        """The analytic answers, in the units that suit the parameters (``solving.solve_analytic``)."""
        return solving.solve_analytic(self, p)

    def solve_numeric(self, p: Params, rtol: float | None = None, shared: dict | None = None,
                      keep_trajectories: bool = False, integrator: str | None = None) -> tuple[dict, Run]:
        """The numeric answers and their Run (``solving.solve_numeric``)."""
        return solving.solve_numeric(self, p, rtol, shared, keep_trajectories, integrator)

    def as_json(self) -> dict:
        """The declaration as ``mech show --json`` gives it (docs/json.md)."""
        return {**{k: getattr(self, k) for k in ("id", "title", "topic", "statement", "model")},
                "params": [p.as_json() for p in self.params], "outputs": [o.as_json() for o in self.outputs],
                "formulas": self.formulas, "numeric_route": self.numeric_route, "hard_cases": self.hard_cases,
                "constraints": list(self.joint_limits), "methods": self.methods}

    def __repr__(self) -> str:
        return f"<Exercise {self.id}: {self.title}>"
