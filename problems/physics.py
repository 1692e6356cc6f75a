"""Physics declared, equations derived: the symbolic route (sympy.physics.mechanics).

An integrating exercise may declare its physics beside its module, in ``problems/chN/physicsN_M.py``
(a name the registry, which takes ``exN_M_*.py``, never mistakes for an exercise): a function
registered with ``@exercise.physics`` that receives a ``Declaration`` and states, in physicists' terms,

* the generalized coordinates (``d.coordinates``) and, for Kane's method, the speeds (``d.speeds``);
* the Lagrangian (``d.lagrangian``) or the bodies and loads (``d.kane``);
* generalized forces, a Rayleigh dissipation function, holonomic and nonholonomic constraints;
* symbols named after the exercise's parameters (``d.params``) and the constants that are not
  parameters (``d.constant``, with the value the module's run takes: its unit of mass, say);
* the exercise's declared ``states`` as functions of (t, q, u) in SI (``d.states``), with the inverse
  map where they are not simply (q, q-dot) (``inverse``);
* optionally what the motion's event function measures (``d.event``) and the module's hand-written
  Jacobian (``d.jacobian``).

It is written from the statement's physics, never transcribed from the module's equations: the
equations of motion are derived here (Lagrange's equations with multipliers, or Kane's equations)
and ``tests/test_physics_derived.py`` compares them with the module's right-hand side at random
parameters and states (``Derivation.compare``).  ``mech show ID --derive`` prints the declaration
and the derived equations (``--latex``, ``--json``).

An exercise whose motion is a reduced or averaged model (no Lagrangian gives it) says so with
``exercise.physics_withheld("why")`` in the same place.  sympy (the ``derive`` extra) is imported
only here, inside functions and by the declaration files, which only ``derive`` imports: ``mech
list``, ``solve`` and ``import mech`` never load it.
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass, field
from typing import Any, Callable

from mech.core.errors import BadUsage

__all__ = ["Declaration", "Derivation", "derive", "why_not", "INSTALL_HINT"]

INSTALL_HINT = "needs sympy (the 'derive' extra): pip install 'mech-likharev[derive]' (or pip install sympy)"
DIGITS = 40  # mpmath's working precision for the derived side: its formulas may cancel where the module's do not

_CACHE: dict[str, "Derivation"] = {}


def _sympy():
    try:
        import sympy
    except ImportError:
        raise BadUsage(f"--derive {INSTALL_HINT}") from None
    return sympy


def find_declaration(ex):
    """(fn, reason): the registered declaration of ``ex`` (importing ``physicsN_M`` beside its module), or
    None and why there is none."""
    if ex._physics is None and ex._physics_withheld is None:
        chapter, number = ex.id.split(".")
        name = f"mech.problems.ch{chapter}.physics{chapter}_{number}"
        try:
            importlib.import_module(name)
        except ImportError as exc:
            if getattr(exc, "name", None) != name:  # the declaration is there but cannot load
                _sympy()  # BadUsage with how to install it, where sympy is what is missing
                raise
    if ex._physics is not None:
        return ex._physics, None
    if ex._physics_withheld is not None:
        return None, ex._physics_withheld
    if not ex.has_motion:
        return None, ("it integrates no equations of motion (its numeric route reaches the answer without "
                      "following a motion), so there are none to derive")
    return None, "its physics is not declared yet (see docs/derive.md to add a declaration)"


def why_not(ex) -> str | None:
    """Why ``ex`` has no derivation, or None when it has one (sympy is not imported for this)."""
    return find_declaration(ex)[1]


def derive(ex) -> "Derivation":
    """The derivation of ``ex``'s declared physics (cached: one per exercise and process).  Raises
    ``BadUsage`` when sympy is missing, ``LookupError`` (with the reason) when nothing is declared."""
    if ex.id in _CACHE:
        return _CACHE[ex.id]
    fn, reason = find_declaration(ex)  # why there is none is said with or without sympy
    if fn is None:
        raise LookupError(reason)
    _sympy()
    d = Declaration(ex)
    fn(d)
    der = Derivation(ex, d)
    _CACHE[ex.id] = der
    return der


# ---------------------------------------------------------------------------------------------- declaring


@dataclass(frozen=True)
class Rate:
    """A state that is a quadrature (dissipated energy): not a function of the coordinates and speeds, its
    rate is ``expr`` (``Declaration.rate``)."""

    expr: Any


class Declaration:
    """What a physics declaration states (see the module docstring); built by calling its methods."""

    def __init__(self, ex):
        import sympy as sp
        from sympy.physics.mechanics import dynamicsymbols

        self.ex = ex
        self.t = dynamicsymbols._t
        self._sp = sp
        self.q: list = []
        self.u: list = []
        self.param_symbols: dict = {}
        self.constant_values: dict = {}  # symbol -> (value, unit, why)
        self.method: str | None = None
        self.L = None
        self.generalized_forces: dict = {}
        self.rayleigh = None
        self.loads: list = []
        self.bodies: list = []
        self.frame = None
        self.holonomic: list = []
        self.dependent: list = []
        self.kinematics: list = []
        self.u_dependent: list = []
        self.nonholonomic: list = []
        self.state_exprs: list | None = None
        self.inverse_fn: Callable | None = None
        self.within: Callable | None = None
        self.event_expr = None
        self.jacobian_fn: Callable | None = None
        self.sizes: dict = {}
        self.notes: list[str] = []
        self.shown: dict = {}  # heading -> expression shown beside the equations (an energy, a potential)
        self.solve_shown = True  # False: the equations solved for the accelerations are not printed

    # -- symbols
    def coordinates(self, names: str):
        """Generalized coordinates (functions of time), e.g. ``theta, x = d.coordinates("theta x")``."""
        from sympy.physics.mechanics import dynamicsymbols

        out = dynamicsymbols(names)
        out = list(out) if isinstance(out, (list, tuple)) else [out]
        self.q += out
        return out[0] if len(out) == 1 else out

    def speeds(self, names: str):
        """Generalized speeds for Kane's method."""
        from sympy.physics.mechanics import dynamicsymbols

        out = dynamicsymbols(names)
        out = list(out) if isinstance(out, (list, tuple)) else [out]
        self.u += out
        return out[0] if len(out) == 1 else out

    def params(self, names: str):
        """Symbols for the exercise's own parameters, by their catalogue names (an unknown name is an error)."""
        sp = self._sp
        out = []
        for name in names.split():
            if name not in self.ex.param_map:
                raise ValueError(f"{self.ex.id}: {name!r} is not a parameter (they are {', '.join(self.ex.param_map)})")
            par = self.ex.param_map[name]
            positive = par.min is not None and par.min >= 0
            sym = sp.Symbol(name, positive=True) if positive else sp.Symbol(name, real=True)
            self.param_symbols[sym] = name
            out.append(sym)
        return out[0] if len(out) == 1 else out

    def constant(self, name: str, value: float, unit: str, why: str):
        """A constant that is not a parameter, with the value the module's run takes (its unit of mass, the
        book's number; or ``f(p)``, a model constant the parameters set), its unit and why that value."""
        sym = self._sp.Symbol(name, real=True)
        self.constant_values[sym] = (value if callable(value) else float(value), unit, why)
        return sym

    # -- the physics
    def lagrangian(self, L, *, forces=None, rayleigh=None, loads=(), frame=None, constraints=(), dependent=()):
        """Lagrange's equations of ``L`` (with ``loads``: (point or frame, vector) pairs in ``frame``;
        ``forces``: coordinate -> generalized force; ``rayleigh``: the dissipation function), under the
        holonomic ``constraints`` (expressions equal to zero, each with its multiplier) that fix the
        ``dependent`` coordinates."""
        self.method = "Lagrange"
        self.L = L
        self.generalized_forces = dict(forces or {})
        self.rayleigh = rayleigh
        self.loads = list(loads)
        self.frame = frame
        self.holonomic = list(constraints)
        self.dependent = list(dependent)

    def kane(self, frame, *, kinematics, bodies, loads, u_dependent=(), velocity_constraints=()):
        """Kane's equations for ``bodies`` under ``loads`` in the inertial ``frame``: ``kinematics`` the
        kinematic differential equations (expressions equal to zero, one per coordinate), the speeds
        ``u_dependent`` fixed by the nonholonomic ``velocity_constraints``."""
        self.method = "Kane"
        self.frame = frame
        self.kinematics = list(kinematics)
        self.bodies = list(bodies)
        self.loads = list(loads)
        self.u_dependent = list(u_dependent)
        self.nonholonomic = list(velocity_constraints)

    # -- what the module integrates
    def states(self, exprs, inverse: Callable | None = None, sizes: dict | None = None,
               within: Callable | None = None):
        """The exercise's declared ``states``, in order and in SI, as expressions in t, the coordinates and the
        speeds (q-dot for Lagrange's method); ``inverse(x, values) -> {symbol: value}`` the coordinates and
        independent speeds of an SI state vector x (not needed when the states are the coordinates then
        their rates).  ``sizes``: name -> the typical size of a coordinate or speed for the draws around the
        start (a number, or ``f(p, value)``: a lean kept off the flat disk).  ``within(x, x0) -> bool``: whether
        the SI state x lies where the module's equations describe this motion (started at x0); draws outside
        are drawn again."""
        self.within = within
        self.state_exprs = list(exprs)
        self.inverse_fn = inverse
        self.sizes = dict(sizes or {})

    def rate(self, expr) -> Rate:
        """A state given by its rate alone (a quadrature: the energy dissipated), for ``states``."""
        return Rate(expr)

    def event(self, expr):
        """What the motion's (first) event function measures, in SI: an expression in t, q, u and the
        accelerations (q-double-dot, u-dot), compared with ``Motion.event_scale * event(t, y)``."""
        self.event_expr = expr

    def jacobian(self, fn: Callable):
        """``fn(p) -> jac(t, y)``: the module's hand-written Jacobian of its right-hand side, to compare."""
        self.jacobian_fn = fn

    def unsolved(self, why: str):
        """Print the equations of motion without solving them for the accelerations (a closed form too long to
        read, or to simplify in a few seconds), and say why."""
        self.solve_shown = False
        self.note(why)

    def note(self, text: str):
        self.notes.append(" ".join(text.split()))

    def show(self, heading: str, expr):
        """An expression shown beside the equations (the energy, the effective potential)."""
        self.shown[heading] = expr


# ---------------------------------------------------------------------------------------------- deriving


class Derivation:
    """The declared physics of one exercise with its equations derived, and their numeric evaluation."""

    def __init__(self, ex, d: Declaration):
        import sympy as sp

        self.ex, self.d = ex, d
        self.method = d.method
        if d.method is None:
            raise ValueError(f"{ex.id}: the declaration states no Lagrangian and no bodies")
        q = list(d.q)
        n = len(q)
        # plain symbols for the numeric side: q_i, their rates (or the speeds) and their derivatives
        Q = [sp.Symbol(f"q{i}_", real=True) for i in range(n)]
        if d.method == "Lagrange":
            A, b, U, to_plain, indep, u_ind = self._lagrange(q, Q)
        else:  # Kane
            A, b, U, to_plain, indep, u_ind = self._kane(q, Q)
        self.q, self.n = q, n
        self.Q, self.U, self.to_plain = Q, U, to_plain
        self.indep = indep
        self.u_ind = u_ind
        P = list(d.param_symbols) + list(d.constant_values)
        self.P = P
        args = [sp.Symbol("t_", real=True)] + Q + U + P
        self.args = args
        to_plain[d.t] = args[0]
        self._check_states()
        # compiled at the first number asked for (``show --derive`` asks none: 0.8 CPU-s over 24 exercises)
        self._unbuilt: tuple | None = (A, b)

    def _built(self) -> None:
        """The numeric side (``_numeric_side``, ``_states``) compiled, once."""
        if self._unbuilt is not None:
            A, b = self._unbuilt
            self._numeric_side(A, b)
            self._states()
            self._unbuilt = None

    def _lagrange(self, q, Q):
        """Lagrange's equations (with the declared generalized forces, dissipation and holonomic constraints),
        solved for the accelerations and multipliers: (A, b, speeds, plain symbols, independent coordinates,
        their rates)."""
        import sympy as sp
        from sympy.physics import mechanics as me

        d, t, n = self.d, self.d.t, len(q)
        speeds = [qi.diff(t) for qi in q]
        self.lm = me.LagrangesMethod(d.L, q, forcelist=d.loads or None, frame=d.frame,
                                     hol_coneqs=d.holonomic or None)
        eom = self.lm.form_lagranges_equations()
        for i, qi in enumerate(q):
            if qi in d.generalized_forces:
                eom[i] -= d.generalized_forces[qi]
            if d.rayleigh is not None:
                eom[i] += sp.diff(d.rayleigh, speeds[i])
        self.eom = eom
        lam = list(self.lm.lam_vec) if d.holonomic else []
        acc = [qi.diff(t, 2) for qi in q]
        unknowns = acc + lam
        rows = list(eom) + [sp.diff(c, t, 2) for c in d.holonomic]
        A = sp.Matrix(rows).jacobian(unknowns)
        b = -sp.Matrix(rows).xreplace({x: 0 for x in unknowns})
        self.unknowns = unknowns
        indep = [qi for qi in q if qi not in d.dependent]
        u_ind = [qi.diff(t) for qi in indep]
        # the dependent coordinates from the constraints
        dep_sol = {}
        if d.dependent:
            sols = sp.solve(d.holonomic, d.dependent, dict=True)
            if len(sols) != 1:
                raise ValueError(f"{self.ex.id}: the constraints do not fix the dependent coordinates once")
            dep_sol = sols[0]
        self.dep_sol = dep_sol
        U = [sp.Symbol(f"u{i}_", real=True) for i in range(n)]
        to_plain = {}
        for i, qi in enumerate(q):
            to_plain[qi.diff(t, 2)] = sp.Symbol(f"a{i}_", real=True)
            to_plain[qi.diff(t)] = U[i]
            to_plain[qi] = Q[i]
        self.all_speeds = U
        self.rate_syms = [to_plain[a] for a in acc] + [sp.Symbol(f"lam{j}_", real=True) for j in range(len(lam))]
        to_plain.update({lv: self.rate_syms[n + j] for j, lv in enumerate(lam)})
        self.qdot_from = None
        return A, b, U, to_plain, indep, u_ind

    def _kane(self, q, Q):
        """Kane's equations of the declared bodies and loads (with nonholonomic constraints): the full mass
        matrix and forcing, as ``_lagrange`` returns them."""
        import sympy as sp
        from sympy.physics import mechanics as me

        d = self.d
        u = list(d.u)
        u_ind = [ui for ui in u if ui not in d.u_dependent]
        self.km = me.KanesMethod(d.frame, q_ind=q, u_ind=u_ind, kd_eqs=d.kinematics,
                                 u_dependent=d.u_dependent or None,
                                 velocity_constraints=d.nonholonomic or None)
        fr, frstar = self.km.kanes_equations(d.bodies, d.loads)
        self.fr, self.frstar = fr, frstar
        self.eom = fr + frstar
        m = len(u)
        A = self.km.mass_matrix_full
        b = self.km.forcing_full
        U = [sp.Symbol(f"u{i}_", real=True) for i in range(m)]
        to_plain = {}
        rates = [qi.diff(d.t) for qi in self.km.q] + [ui.diff(d.t) for ui in self.km.u]
        self.rate_syms = [sp.Symbol(f"r{i}_", real=True) for i in range(len(rates))]
        for ri, rs in zip(rates, self.rate_syms):
            to_plain[ri] = rs
        order_q, order_u = list(self.km.q), list(self.km.u)
        for i, qi in enumerate(order_q):
            to_plain[qi] = Q[q.index(qi)]
        for i, ui in enumerate(order_u):
            to_plain[ui] = U[u.index(ui)]
        self.kane_q_order = [q.index(qi) for qi in order_q]
        self.kane_u_order = [u.index(ui) for ui in order_u]
        indep = q
        dep_sol = {}
        self.dep_sol = dep_sol
        self.all_speeds = U
        self.unknowns = rates
        return A, b, U, to_plain, indep, u_ind

    def _numeric_side(self, A, b) -> None:
        """The equations in plain symbols, compiled (mpmath): A x = b, the dependent coordinates and speeds,
        the velocity constraints."""
        import sympy as sp
        from sympy.physics import mechanics as me

        d, t, q, U, args, to_plain = self.d, self.d.t, self.q, self.U, self.args, self.to_plain

        def plain(e):
            return me.msubs(e, to_plain) if not isinstance(e, (int, float)) else e

        self._plain = plain
        self.A_plain, self.b_plain = plain(A), plain(b)
        self._A = sp.lambdify(args, self.A_plain, modules="mpmath")
        self._b = sp.lambdify(args, self.b_plain, modules="mpmath")
        # dependent coordinates and speeds
        if d.method == "Lagrange" and self.dep_sol:
            self._dep = [(q.index(k), sp.lambdify(args, plain(v), modules="mpmath"),
                          sp.lambdify(args, plain(sp.diff(v, t)), modules="mpmath")) for k, v in self.dep_sol.items()]
        else:
            self._dep = []
        if d.method == "Kane" and d.u_dependent:
            vc = sp.Matrix([plain(me.msubs(c, self.km.kindiffdict())) for c in d.nonholonomic])
            udep = [U[d.u.index(ui)] for ui in d.u_dependent]
            self._vc_A = sp.lambdify(args, vc.jacobian(udep), modules="mpmath")
            self._vc_b = sp.lambdify(args, -vc.xreplace({x: 0 for x in udep}), modules="mpmath")
            self._udep_idx = [d.u.index(ui) for ui in d.u_dependent]
        else:
            self._vc_A = None

    def _check_states(self) -> None:
        """The declaration gives the exercise's states, as many (none where no motion is integrated)."""
        ex, d = self.ex, self.d
        if d.state_exprs is None and not ex.states:  # no motion integrated (4.12: normal modes)
            return
        if d.state_exprs is None:
            raise ValueError(f"{ex.id}: the declaration gives no states")
        if len(d.state_exprs) != len(ex.states):
            raise ValueError(f"{ex.id}: the declaration gives {len(d.state_exprs)} states, "
                             f"the exercise {len(ex.states)}")

    def _states(self) -> None:
        """The exercise's states and their rates, compiled: x' = dS/dt + dS/dq q' + dS/du u' (u' in terms of
        the solved unknowns; a quadrature's rate as declared), and the declared event."""
        import sympy as sp
        from sympy.physics import mechanics as me

        ex, d, plain, args = self.ex, self.d, self._plain, self.args
        Q, U, n = self.Q, self.U, self.n
        if d.state_exprs is None:  # no motion integrated (4.12: normal modes)
            return
        kdd = self.km.kindiffdict() if d.method == "Kane" else {}
        S = sp.Matrix([0 if isinstance(e, Rate) else plain(me.msubs(sp.sympify(e), kdd)) for e in d.state_exprs])
        self.S_plain = S
        self._S = sp.lambdify(args, S, modules="mpmath")
        if d.method == "Lagrange":
            qdot = U
            udot = self.rate_syms[:n]
        else:
            qdot = [self.rate_syms[self.kane_q_order.index(i)] for i in range(n)]
            udot = [self.rate_syms[len(self.q) + self.kane_u_order.index(i)] for i in range(len(U))]
        Sdot = S.diff(args[0]) + S.jacobian(Q) * sp.Matrix(qdot) + S.jacobian(U) * sp.Matrix(udot)
        for i, e in enumerate(d.state_exprs):  # a quadrature: its rate as declared
            if isinstance(e, Rate):
                Sdot[i] = plain(me.msubs(sp.sympify(e.expr), kdd))
        self._Sdot = sp.lambdify(args + self.rate_syms, Sdot, modules="mpmath")
        self._event = (sp.lambdify(args + self.rate_syms, plain(d.event_expr), modules="mpmath")
                       if d.event_expr is not None else None)

    # -- numbers
    def values(self, p) -> list:
        """The parameter and constant values, in the order of ``self.P`` (mpf)."""
        import mpmath

        out = []
        for sym in self.P:
            if sym in self.d.param_symbols:
                out.append(mpmath.mpf(float(p[self.d.param_symbols[sym]])))
            else:
                v = self.d.constant_values[sym][0]
                out.append(mpmath.mpf(float(v(p)) if callable(v) else v))
        return out

    def full(self, t, q_ind, u_ind, pv):
        """All coordinates and speeds from the independent ones (the dependent from the constraints)."""
        import mpmath

        self._built()
        Qv = [mpmath.mpf(0)] * self.n
        Uv = [mpmath.mpf(0)] * len(self.U)
        ind_idx = [self.q.index(qi) for qi in self.indep]
        for k, v in zip(ind_idx, q_ind):
            Qv[k] = mpmath.mpf(v)
        if self.method == "Lagrange":
            for k, v in zip(ind_idx, u_ind):
                Uv[k] = mpmath.mpf(v)
        else:
            ui_idx = [self.d.u.index(ui) for ui in self.u_ind]
            for k, v in zip(ui_idx, u_ind):
                Uv[k] = mpmath.mpf(v)
        tv = mpmath.mpf(t)
        for k, fq, _ in self._dep:
            Qv[k] = fq(tv, *Qv, *Uv, *pv)
        for k, _, fu in self._dep:
            Uv[k] = fu(tv, *Qv, *Uv, *pv)
        if self._vc_A is not None:
            Am = mpmath.matrix(self._vc_A(tv, *Qv, *Uv, *pv))
            bm = mpmath.matrix(self._vc_b(tv, *Qv, *Uv, *pv))
            sol = mpmath.lu_solve(Am, bm)
            for j, k in enumerate(self._udep_idx):
                Uv[k] = sol[j]
        return tv, Qv, Uv

    def evaluate(self, p, t, q_ind, u_ind, rates: bool = True):
        """(x, x', event) in SI at the independent coordinates and speeds, in mpmath at DIGITS digits: the
        states, their rates from the derived equations, and the event's value (None without one)."""
        import mpmath

        self._built()
        with mpmath.workdps(DIGITS):
            pv = self.values(p)
            tv, Qv, Uv = self.full(t, q_ind, u_ind, pv)
            a = [tv] + Qv + Uv + pv
            if not rates:
                return [v for v in mpmath.matrix(self._S(*a))], None, None
            A = mpmath.matrix(self._A(*a))
            b = mpmath.matrix(self._b(*a))
            r = mpmath.lu_solve(A, b)
            rates = [r[i] for i in range(r.rows)]
            x = [v for v in mpmath.matrix(self._S(*a))]
            xd = [v for v in mpmath.matrix(self._Sdot(*a, *rates))]
            ev = self._event(*a, *rates) if self._event is not None else None
            return x, xd, ev

    def rates(self, p, t, q_ind, u_ind) -> dict:
        """The solved unknowns at a state, by name: the accelerations and multipliers (Lagrange) or the
        coordinates' and speeds' rates (Kane), floats from the mpmath solve."""
        import mpmath

        self._built()
        with mpmath.workdps(DIGITS):
            pv = self.values(p)
            tv, Qv, Uv = self.full(t, q_ind, u_ind, pv)
            a = [tv] + Qv + Uv + pv
            r = mpmath.lu_solve(mpmath.matrix(self._A(*a)), mpmath.matrix(self._b(*a)))
            return {str(k): float(r[i]) for i, k in enumerate(self.unknowns)}

    def independent_of(self, p, x):
        """(q_ind, u_ind) of the SI state vector x: the declaration's inverse, or the states themselves when
        they are the independent coordinates then their rates."""
        if self.d.inverse_fn is not None:
            vals = self.d.inverse_fn([float(v) for v in x], p)
            return vals
        k = len(self.indep)
        x = [v for v, e in zip(x, self.d.state_exprs) if not isinstance(e, Rate)]
        if len(x) != 2 * k:
            raise ValueError(f"{self.ex.id}: states are not (q, q-dot): the declaration needs an inverse")
        return [float(v) for v in x[:k]], [float(v) for v in x[k:]]

    # -- showing
    def sections(self, latex: bool = False, fold: bool = True) -> list[tuple[str, list[str]]]:
        """(heading, lines) of the declaration and the derived equations, pretty-printed or as LaTeX:
        simplified, each line at most ``derive_text.WIDTH`` characters (a long sum cut between its terms, a
        wide part named below it); ``fold=False``: each LaTeX equation one string, however long (JSON)."""
        import sympy as sp
        from sympy.physics import mechanics as me

        from mech.problems.derive_text import Shower, tidy, wrap_plain

        d = self.d
        cache = self.__dict__.setdefault("_tidied", {})
        show = Shower(latex, {str(s) for s in self.P} | {str(qi.func) for qi in d.q}, fold,
                      self.__dict__.setdefault("_drawn", {}))

        def eq(head, e, zero=False):
            return show.equation(head, tidy(e, cache), zero)

        def lines(*groups):
            return [line for g in groups for line in g]

        out = []
        if self.method == "Lagrange":
            out.append(("Lagrangian L", eq(sp.Symbol("L"), d.L)))
            if d.generalized_forces:
                out.append(("generalized forces", lines(*(eq(sp.Symbol(f"Q_{k.func}"), v)
                                                          for k, v in d.generalized_forces.items()))))
            if d.rayleigh is not None:
                out.append(("Rayleigh dissipation function", eq(sp.Symbol("F"), d.rayleigh)))
            if d.loads:
                out.append(("loads", lines(*(show.vector(f"{pt}", f, cache) for pt, f in d.loads))))
            if d.holonomic:
                out.append(("holonomic constraints (each with its multiplier)",
                            lines(*(eq(None, c, True) for c in d.holonomic))))
            lam = {lv: sp.Symbol(f"lambda_{j + 1}") for j, lv in enumerate(self.lm.lam_vec)} if d.holonomic else {}
            out.append(("equations of motion (Lagrange's, = 0)", lines(*(eq(None, e.xreplace(lam), True)
                                                                        for e in self.eom))))
        else:
            out.append(("bodies", lines(*(show.wrap(_body_text(b, show.text)) for b in d.bodies))))
            out.append(("loads", lines(*(show.vector(f"{pt}", f, cache) for pt, f in d.loads))))
            out.append(("kinematic differential equations (= 0)", lines(*(eq(None, k, True) for k in d.kinematics))))
            if d.nonholonomic:
                out.append(("nonholonomic constraints (= 0), fixing " + ", ".join(str(u.func) for u in d.u_dependent),
                            lines(*(eq(None, me.msubs(c, self.km.kindiffdict()), True) for c in d.nonholonomic))))
            out.append(("equations of motion (Kane's, Fr + Fr* = 0)", lines(*(eq(None, e, True) for e in self.eom))))
        solved = self.solved()
        if solved:
            out.append(("solved for the accelerations", lines(*(eq(k, v) for k, v in solved))))
        for heading, e in d.shown.items():
            out.append((heading, eq(None, e)))
        if d.state_exprs is not None:
            out.append(("states integrated (SI)", lines(*(
            eq(f"d{name}/dt", e.expr) if isinstance(e, Rate) else eq(name, sp.sympify(e))
                for (name, _), e in zip(self.ex.states, d.state_exprs)))))
        if d.notes and not latex:
            out.append(("notes", lines(*(wrap_plain(n) for n in d.notes))))
        return out

    def symbol(self, name: str):
        """The declaration's symbol of a parameter or constant, by name."""
        for sym in self.P:
            if str(sym) == name:
                return sym
        raise KeyError(name)

    def declared(self) -> list[str]:
        """The method, coordinates, speeds, parameters and constants, as plain text."""
        d = self.d
        head = [f"method: {self.method}'s equations"]
        head.append("coordinates: " + ", ".join(str(qi.func) for qi in d.q))
        if self.method == "Kane":
            head.append("speeds: " + ", ".join(str(ui.func) for ui in d.u))
        if d.param_symbols:
            head.append("parameters: " + ", ".join(str(s) for s in d.param_symbols))
        for sym, (v, unit, why) in d.constant_values.items():
            head.append(f"constant {sym}" + ("" if callable(v) else f" = {v:g}") + f" [{unit}]: {why}")
        return head

    def solved(self, most: int = 5):
        """[(acceleration, expression)]: the equations solved for the independent coordinates'
        accelerations (Lagrange) or speeds' rates (Kane), simplified; empty for a system of more than ``most``
        unknowns (their closed form is no help to read)."""
        import sympy as sp

        from mech.problems.derive_text import simplify

        if len(self.unknowns) > most or not self.d.solve_shown:
            return []
        if getattr(self, "_solved", None) is not None:
            return self._solved
        if self.method == "Lagrange":
            eqs = list(self.eom) + [sp.diff(c, self.d.t, 2) for c in self.d.holonomic]
            unknowns = list(self.unknowns)
            want = [qi.diff(self.d.t, 2) for qi in self.indep]
        else:
            eqs = list(self.km.mass_matrix_full * sp.Matrix(self.unknowns) - self.km.forcing_full)
            unknowns = list(self.unknowns)
            want = [ui.diff(self.d.t) for ui in self.u_ind]
        A = sp.Matrix(eqs).jacobian(unknowns)
        b = -sp.Matrix(eqs).xreplace({x: 0 for x in unknowns})
        sol = A.LUsolve(b)
        out = []
        for w in want:
            e = sol[unknowns.index(w)]
            for k, v in self.dep_sol.items():  # the dependent coordinates (and their rates) from the constraints
                t = self.d.t
                e = e.subs({k.diff(t): sp.diff(v, t)}).subs({k: v})
            # a long LU solution is a nest of fractions: cancelled to one first, simplify has less to carry
            # (the 12 printed solutions of over 60 operations simplify to the same form, 3.8 -> 2.5 CPU-s
            # over them; a short one may not: 4.33's, 5.9's and 5.10's would change)
            out.append((w, simplify(sp.cancel(e) if sp.count_ops(e) > 60 else e)))
        self._solved = out
        return out

    @property
    def latex(self) -> dict:
        """Heading -> the LaTeX strings of that part (Lagrangian, constraints, equations of motion, ...)."""
        return {h: lines for h, lines in self.sections(latex=True, fold=False)}

    @property
    def text(self) -> str:
        """What ``mech show ID --derive`` prints after its title: the declaration and the equations."""
        out = ["declared:", *self.declared()]
        for heading, lines in self.sections():
            out += ["", f"{heading}:", *lines]
        return "\n".join(out)

    def _repr_latex_(self) -> str:  # a notebook shows the equations of motion
        eqs = [line for h, lines in self.sections(latex=True, fold=False) if h.startswith(("equations", "solved"))
               for line in lines]
        return "$$" + r" \\ ".join(eqs) + "$$" if eqs else ""

    def as_json(self) -> dict:
        """The declaration and the derived equations for ``show --derive --json``: names as text, every
        expression as a LaTeX string."""
        d = self.d
        return {"method": self.method,
                "coordinates": [str(qi.func) for qi in d.q],
                "speeds": [str(ui.func) for ui in d.u] if self.method == "Kane" else [],
                "parameters": [str(s) for s in d.param_symbols],
                "constants": [{"name": str(sym), "value": None if callable(v) else v, "unit": unit, "why": why}
                              for sym, (v, unit, why) in d.constant_values.items()],
                "notes": list(d.notes),
                "sections": [{"heading": h, "latex": lines} for h, lines in self.sections(latex=True, fold=False)
                             if h != "notes"]}


def _body_text(b, fmt):
    from sympy.physics.mechanics import Particle

    from mech.problems.derive_text import simplify

    if isinstance(b, Particle):
        return f"particle {b.name}: mass {b.mass}, at {b.masscenter}"
    matrix = fmt(b.central_inertia.to_matrix(b.frame).applyfunc(simplify))
    # a matrix the terminal draws goes on lines of its own, under the words
    return f"rigid body {b.name}: mass {b.mass}, inertia about {b.masscenter} =" + ("\n" if "\n" in matrix else " ") \
        + matrix


# ---------------------------------------------------------------------------------------------- comparing


@dataclass
class Comparison:
    """The derived and the hand-written rates at one parameter set and state: worst error per block of
    states (rows sharing a unit), relative to the block's size (its largest derived rate, or its floor)."""

    t: float
    x: list
    derived: list
    hand: list
    blocks: dict = field(default_factory=dict)  # unit -> (worst |hand - derived|, the block's size)
    event: tuple | None = None  # (hand, derived, size)
    jacobian: tuple | None = None  # (worst |hand - derived| entry / size of its row block)

    def worst(self) -> float:
        errs = [e / s for e, s in self.blocks.values()]
        if self.event is not None:
            errs.append(abs(self.event[0] - self.event[1]) / self.event[2])
        if self.jacobian is not None:
            errs.append(self.jacobian)
        return max(errs)


def state_sizes(motion) -> list[float]:
    """The SI size of each declared state: ``y_size`` (1 by default) through ``to_states`` and ``y_scale``."""
    import numpy as np

    y0 = np.asarray(motion.y0, float)
    s = np.ones(y0.size) if motion.y_size is None else np.broadcast_to(np.asarray(motion.y_size, float), y0.shape)
    _, A = motion.states_map(y0)
    size = np.abs(A) @ s
    scale = 1.0 if motion.y_scale is None else np.abs(np.broadcast_to(np.asarray(motion.y_scale, float), size.shape))
    return list(size * scale)


def draw_states(der, p, motion, rng, n: int, spread: float = 0.3):
    """``n`` (t, q_ind, u_ind) around the motion's start: each coordinate and speed moved by ``spread`` times
    its size (the declaration's ``sizes``, else the state's size where the states are (q, q-dot), else its own
    value and its block's largest), the time drawn over the motion's span."""
    import numpy as np

    x0 = motion.start
    q0, u0 = der.independent_of(p, x0)
    q0, u0 = np.asarray(q0, float), np.asarray(u0, float)
    sizes = state_sizes(motion)
    k = len(q0)
    if der.d.inverse_fn is None:
        sizes = [v for v, e in zip(sizes, der.d.state_exprs) if not isinstance(e, Rate)]
        sq, su = np.asarray(sizes[:k]), np.asarray(sizes[k:])
    else:
        named = {str(s.func) if hasattr(s, "func") else str(s): v for s, v in der.d.sizes.items()}
        qn = [str(qi.func) for qi in der.indep]
        un = [str(ui.func) for ui in der.u_ind] if der.method == "Kane" else [f"{x}_dot" for x in qn]
        def size(nm, v, block):
            s = named.get(nm)
            return (abs(v) + np.max(np.abs(block)) + 1e-300) if s is None else (s(p, v) if callable(s) else s)

        sq = np.array([size(nm, v, q0) for nm, v in zip(qn, q0)])
        su = np.array([size(nm, v, u0) for nm, v in zip(un, u0)])
    out = []
    lo, hi = motion.span
    for _ in range(50 * n):
        if len(out) == n:
            break
        tt = motion.t_offset + motion.t_scale * rng.uniform(min(lo, hi), max(lo, hi))
        q = q0 + spread * sq * rng.standard_normal(k)
        u = u0 + spread * su * rng.standard_normal(u0.size)
        if der.d.within is not None:
            x = [float(v) for v in der.evaluate(p, tt, list(q), list(u), rates=False)[0]]
            if not der.d.within(x, list(x0)):
                continue
        out.append((float(tt), list(q), list(u)))
    return out


def compare(der, p, motion, t, q_ind, u_ind, jac=None) -> Comparison:
    """The motion's hand-written rates against the derived ones at one state: x from the declaration's
    states, y = ``motion.integrated(x)``, the hand's rates ``motion.states_rate(t, y)``; rows grouped by
    the unit of their state, each block's error against its size (its largest derived rate, floored at
    its states' sizes over the motion's time scale)."""
    import numpy as np

    x, xd, ev = der.evaluate(p, t, q_ind, u_ind)
    xf = np.array([float(v) for v in x])
    y = motion.integrated(xf)
    hand = motion.states_rate(t, y)
    der_f = np.array([float(v) for v in xd])
    sizes = np.asarray(state_sizes(motion)) / abs(motion.t_scale)
    units = [u for _, u in der.ex.states]
    blocks = {}
    for unit in dict.fromkeys(units):
        rows = [i for i, u in enumerate(units) if u == unit]
        err = float(np.max(np.abs(hand[rows] - der_f[rows])))
        size = float(max(np.max(np.abs(der_f[rows])), np.max(sizes[rows])))
        blocks[unit] = (err, size)
    cmp = Comparison(t, list(xf), list(der_f), list(hand), blocks)
    if ev is not None and motion.event is not None and motion.event_scale is not None:
        tt = (t - motion.t_offset) / motion.t_scale
        he = float(motion.event_scale) * float(motion.event.fn(tt, y))
        cmp.event = (he, float(ev), max(abs(float(ev)), 1e-300))
    if jac is not None:
        cmp.jacobian = jacobian_error(der, p, motion, t, y, jac)
    return cmp


def jacobian_error(der, p, motion, t, y, jac) -> float:
    """The hand-written Jacobian of the motion's rhs (integrated variables) against the derived rates'
    Jacobian, by central differences in mpmath at DIGITS digits (the states must be (q, q-dot) or the
    declaration's inverse exact in mpmath arithmetic: an affine map), each row against its largest entry
    times the state's size.  Rows no state depends on (``idle_rows``, or a zero column of the map: a
    quadrature carried beside the states) are left out; their columns are compared (zero on the derived side)."""
    import mpmath
    import numpy as np

    tt = (t - motion.t_offset) / motion.t_scale
    J_hand = np.asarray(jac(tt, y), float)
    n = y.size
    b, A = motion.states_map(y)
    scale = np.ones(len(der.ex.states)) if motion.y_scale is None else np.broadcast_to(
        np.asarray(motion.y_scale, float), (len(der.ex.states),))
    used = [j for j in range(n) if j not in motion.idle_rows and np.any(A[:, j])]
    back = np.linalg.pinv(A[:, used])  # the states' rates back to y's (a signed permutation: exact)
    J = np.zeros((n, n))
    with mpmath.workdps(DIGITS):
        for j in range(n):
            h = mpmath.mpf(10) ** -15 * (1 + abs(y[j]))
            cols = []
            for sgn in (1, -1):
                yj = [mpmath.mpf(v) for v in y]
                yj[j] += sgn * h
                # x of the shifted state (affine map, in mpmath), then the derived rates back to y's rates
                xs = [sum(mpmath.mpf(A[i, k]) * yj[k] for k in range(n)) + mpmath.mpf(b[i]) for i in range(A.shape[0])]
                xs = [xs[i] * mpmath.mpf(scale[i]) for i in range(len(xs))]
                k_ = len(der.indep)
                _, xd, _ = der.evaluate(p, t, xs[:k_], xs[k_:])
                xdot = [xd[i] / mpmath.mpf(scale[i]) * mpmath.mpf(motion.t_scale) for i in range(len(xd))]
                ydot = [sum(mpmath.mpf(back[r, i]) * xdot[i] for i in range(len(xdot))) for r in range(len(used))]
                cols.append(ydot)
            for r, i in enumerate(used):
                J[i, j] = float((cols[0][r] - cols[1][r]) / (2 * h))
    err = 0.0
    for i in used:
        row = max(float(np.max(np.abs(J[i]))), 1e-300)
        err = max(err, float(np.max(np.abs(J_hand[i] - J[i]))) / row)
    return err


# ---------------------------------------------------------------------------------------------- a ball
# shared by the declarations of a ball on a horizontal table (4.8 sliding, 4.18 rolling on a turntable)


def ball_on_table(d, R):
    """A ball of radius ``R`` on the table z = 0 of the lab frame N (z up), declared in ``d``: coordinates
    x, y (the centre's place) and a, b, c (the ball's attitude, three body-fixed turns), speeds w1, w2, w3
    (the angular velocity on the ball's axes) and vx, vy (the centre's velocity).  Returns (N, B, O, C, P,
    kinematics): the lab, the ball's frame, the origin, the centre at height R, the ball's material point at
    the contact (its velocity from the rigid motion) and the kinematic equations tying speeds to rates, as
    a namespace that also holds the coordinates and speeds by name."""
    from types import SimpleNamespace

    from sympy.physics.mechanics import Point, ReferenceFrame, dot

    x, y, a, b, c = d.coordinates("x y a b c")
    w1, w2, w3, vx, vy = d.speeds("w1 w2 w3 vx vy")
    t = d.t
    N = ReferenceFrame("N")
    B = N.orientnew("B", "Body", [a, b, c], "XYZ")
    w = B.ang_vel_in(N)
    kinematics = [w1 - dot(w, B.x), w2 - dot(w, B.y), w3 - dot(w, B.z), vx - x.diff(t), vy - y.diff(t)]
    B.set_ang_vel(N, w1 * B.x + w2 * B.y + w3 * B.z)
    O = Point("O")
    O.set_vel(N, 0)
    C = O.locatenew("C", x * N.x + y * N.y + R * N.z)
    C.set_vel(N, vx * N.x + vy * N.y)
    P = C.locatenew("P", -R * N.z)
    P.v2pt_theory(C, N, B)
    return SimpleNamespace(x=x, y=y, a=a, b=b, c=c, w1=w1, w2=w2, w3=w3, vx=vx, vy=vy, N=N, B=B, O=O, C=C,
                           P=P, kinematics=kinematics)


# ---------------------------------------------------------------------------------------------- attitudes
# shared by the declarations whose modules integrate an attitude quaternion (scalar first, body -> lab)


def quaternion_product(a, b):
    """The Hamilton product of two quaternions (scalar first), on sympy expressions or numbers."""
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    return (a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3, a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
            a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1, a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0)


def turn_quaternion(angle, axis: int):
    """The quaternion of a turn by ``angle`` about the coordinate axis 0, 1 or 2 (sympy)."""
    import sympy as sp

    v = [0, 0, 0]
    v[axis] = sp.sin(angle / 2)
    return (sp.cos(angle / 2), *v)


def body_xyz_quaternion(a, b, c):
    """The quaternion of sympy's ``orientnew(..., "Body", [a, b, c], "XYZ")``: turns about x, then the new
    y, then the newest z (R = Rx(a) Ry(b) Rz(c))."""
    return quaternion_product(quaternion_product(turn_quaternion(a, 0), turn_quaternion(b, 1)),
                              turn_quaternion(c, 2))


def body_xyz_angles(Rm):
    """(a, b, c) with Rx(a) Ry(b) Rz(c) = Rm (|b| < pi/2), the inverse of ``body_xyz_quaternion``'s matrix."""
    return (math.atan2(-Rm[1][2], Rm[2][2]), math.asin(max(-1.0, min(1.0, Rm[0][2]))),
            math.atan2(-Rm[0][1], Rm[0][0]))


def turn_matrix(axis: int, angle: float):
    """The rotation matrix (numpy) of a turn by ``angle`` about the coordinate axis 0, 1 or 2."""
    import numpy as np

    c, s = math.cos(angle), math.sin(angle)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    Rm = np.eye(3)
    Rm[i, i], Rm[i, j], Rm[j, i], Rm[j, j] = c, -s, s, c
    return Rm


def body_xyz_matrix(a: float, b: float, c: float):
    """The matrix (numpy) whose columns are the axes of sympy's ``orientnew(..., "Body", [a, b, c], "XYZ")``
    frame in its parent's components: Rx(a) Ry(b) Rz(c)."""
    return turn_matrix(0, a) @ turn_matrix(1, b) @ turn_matrix(2, c)
