"""A student's formula: parsed without ``eval``, checked for its dimension, evaluated on arrays of points.

The grammar is that of values (numbers, units, ``pi``, ``+ - * / ^ **``, parentheses, a factor next to a
name multiplies) plus the exercise's parameter names and symbols and a few functions::

    sqrt exp log sin cos tan asin acos atan atan2 sinh cosh tanh abs   (arcsin arccos arctan ln: aliases)

A name is read, in order, as a parameter (name or symbol as ``mech show`` lists it), ``pi``, a function
(followed by ``(``), a unit.  The tokenizer and grammar are those of values (``core.units.parse``, one
parser for both); here they build a small tree of tuples; nothing of the text is ever executed.
Length and depth are bounded (``MAX_LENGTH`` characters, ``MAX_DEPTH`` nested levels): an answers file is
untrusted input.

Dimensions are exponents of (length, mass, time) as fractions; the radian counts as a pure number, so
``rad/s`` is ``1/s``.  Numbers are exact as written (``0.4`` is 2/5, not a 1-digit value).

Evaluation is vectorised with numpy (one pass for all points).  Beside each value it carries a first-order
bound of its own round-off (each operation adds ``eps`` times its result and propagates its inputs' errors
through its derivative), so that a right formula that cancels digits at a point is told apart from a wrong
one; the same tree evaluates in ``numpy.longdouble`` where double precision is not enough.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from mech.core.units import UNITS, ValueError_, parse, tokens
from mech.verification.judge import within

__all__ = ["FormulaError", "Formula", "parse_formula", "looks_like_formula", "Dim", "dim_of_unit", "dim_text",
           "FUNCTIONS", "MAX_LENGTH", "MAX_DEPTH"]

MAX_LENGTH = 2000
MAX_DEPTH = 100
INPUT_ROUNDING = 2.0**-53  # a parameter's own rounding to a double, relative

FUNCTIONS = {
    "sqrt": "sqrt", "exp": "exp", "log": "log", "ln": "log", "sin": "sin", "cos": "cos", "tan": "tan",
    "asin": "asin", "arcsin": "asin", "acos": "acos", "arccos": "acos", "atan": "atan", "arctan": "atan",
    "atan2": "atan2", "arctan2": "atan2", "sinh": "sinh", "cosh": "cosh", "tanh": "tanh", "abs": "abs",
}


class FormulaError(ValueError):
    """A formula that cannot be read; the message is one user-facing line."""


class DimensionError(FormulaError):
    """A formula whose parts have clashing dimensions (``l + g``); wrong, not unreadable."""


Dim = tuple  # (L, M, T) as Fractions; the angle dropped (the radian is a pure number)
ONE: Dim = (Fraction(0), Fraction(0), Fraction(0))


def _from_unit_dim(d) -> Dim:
    return tuple(Fraction(x) for x in d[:3])


def dim_of_unit(unit: str) -> tuple[float, Dim]:
    """SI factor and dimension (angle dropped) of a catalogue unit such as ``kg*m^2/s`` or ``rad``."""
    from mech.core.units import parse_unit

    factor, d = parse_unit(unit)
    return factor, _from_unit_dim(d)


_BASE = (("m", 0), ("kg", 1), ("s", 2))


def dim_text(d: Dim) -> str:
    """``m/s``, ``kg*m^2``, ``1/s``, ``1`` (a pure number), ``m^(1/2)``."""
    def part(sym, e):
        e = abs(e)
        if e == 1:
            return sym
        return f"{sym}^{e}" if e.denominator == 1 else f"{sym}^({e})"

    order = (("kg", 1), ("m", 0), ("s", 2))
    num = [part(s, d[i]) for s, i in order if d[i] > 0]
    den = [part(s, d[i]) for s, i in order if d[i] < 0]
    top = "*".join(num) or "1"
    if not den:
        return top
    return f"{top}/{den[0]}" if len(den) == 1 else f"{top}/({'*'.join(den)})"


# -- the tree -------------------------------------------------------------------------------------------
# Read by the one grammar of values and formulas (``core.units.parse``); ``_Tree`` gives its parts their
# meaning here: ("num", value)  ("par", name)  ("unit", factor, dim, text)  ("neg", a)
# ("add"|"sub"|"mul"|"div"|"pow", a, b)  ("fn", name, (args...))

_OPS = {"+": "add", "-": "sub", "*": "mul", "/": "div", "^": "pow"}


class _Tree:
    """A formula's parts, for ``core.units.parse``: a name is, in order, a parameter, ``pi``, a function
    (followed by ``(``), a unit."""

    def __init__(self, params: set[str]):
        self.params = params

    def function(self, name):
        if name in self.params or name not in FUNCTIONS:
            return None
        return 2 if FUNCTIONS[name] == "atan2" else 1

    @staticmethod
    def number(text):
        v = float(text)
        if not math.isfinite(v):
            raise FormulaError(f"'{text}' is not a finite number")
        return ("num", v)

    def name(self, val):
        if val in self.params:
            return ("par", val)
        if val == "pi":
            return ("num", math.pi)
        if val in UNITS:
            factor, d = UNITS[val]
            return ("unit", factor, _from_unit_dim(d), val)
        if val.lower() in ("nan", "inf", "infinity"):
            raise FormulaError("not a finite number")
        raise FormulaError(f"unknown name '{val}'; the parameters here are: {', '.join(sorted(self.params))}")

    @staticmethod
    def neg(node):
        return ("neg", node)

    @staticmethod
    def plus(node):
        return node

    @staticmethod
    def binary(op, a, b):
        return (_OPS[op], a, b)

    @staticmethod
    def call(name, args):
        return ("fn", FUNCTIONS[name], tuple(args))


# -- dimensions -----------------------------------------------------------------------------------------

def _const_value(node) -> float | None:
    """The value of a subtree without parameters or units (for exponents), else None."""
    with np.errstate(all="ignore"):
        try:
            v = _eval(node, {}, np.float64, None)[0]
        except KeyError:
            return None
    v = float(np.asarray(v).reshape(-1)[0])
    return v


def _contains(node, kinds) -> bool:
    if node[0] in kinds:
        return True
    if node[0] in ("neg",):
        return _contains(node[1], kinds)
    if node[0] in ("add", "sub", "mul", "div", "pow"):
        return _contains(node[1], kinds) or _contains(node[2], kinds)
    if node[0] == "fn":
        return any(_contains(a, kinds) for a in node[2])
    return False


def _dim(node, pdims: dict[str, Dim]) -> Dim:
    k = node[0]
    if k == "num":
        return ONE
    if k == "unit":
        return node[2]
    if k == "par":
        return pdims[node[1]]
    if k == "neg":
        return _dim(node[1], pdims)
    if k in ("add", "sub"):
        a, b = _dim(node[1], pdims), _dim(node[2], pdims)
        if a != b:
            raise DimensionError(f"it adds {dim_text(a)} and {dim_text(b)}")
        return a
    if k == "mul":
        a, b = _dim(node[1], pdims), _dim(node[2], pdims)
        return tuple(x + y for x, y in zip(a, b))
    if k == "div":
        a, b = _dim(node[1], pdims), _dim(node[2], pdims)
        return tuple(x - y for x, y in zip(a, b))
    if k == "pow":
        a, b = _dim(node[1], pdims), _dim(node[2], pdims)
        if b != ONE:
            raise DimensionError(f"an exponent has the dimension of {dim_text(b)}")
        if a == ONE:
            return ONE
        if _contains(node[2], ("par", "unit")):
            raise DimensionError(f"{dim_text(a)} is raised to a power that depends on the parameters")
        e = _const_value(node[2])
        if e is None or not math.isfinite(e):
            raise DimensionError("an exponent is not a finite number")
        frac = Fraction(e).limit_denominator(12)
        if not within(abs(float(frac) - e), scale=max(1.0, abs(e)), round_off=1e-12):
            raise DimensionError(f"{dim_text(a)} is raised to the power {e:g}")
        return tuple(x * frac for x in a)
    if k == "fn":
        fn, args = node[1], node[2]
        dims = [_dim(a, pdims) for a in args]
        if fn == "sqrt":
            return tuple(x / 2 for x in dims[0])
        if fn == "abs":
            return dims[0]
        if fn == "atan2":
            if dims[0] != dims[1]:
                raise DimensionError(f"atan2 of {dim_text(dims[0])} and {dim_text(dims[1])}")
            return ONE
        if dims[0] != ONE:
            raise DimensionError(f"{fn} of {dim_text(dims[0])}: its argument must be a pure number")
        return ONE
    raise AssertionError(k)  # pragma: no cover


# -- evaluation -----------------------------------------------------------------------------------------

@dataclass
class Problem:
    """Where the formula cannot be evaluated: a boolean mask over the points and what went wrong."""

    mask: np.ndarray
    what: str  # "asin of {x}" with {x} filled per point by the caller
    args: np.ndarray  # the offending argument at each point


_FN = {"sqrt": np.sqrt, "exp": np.exp, "log": np.log, "sin": np.sin, "cos": np.cos, "tan": np.tan,
       "asin": np.arcsin, "acos": np.arccos, "atan": np.arctan, "sinh": np.sinh, "cosh": np.cosh,
       "tanh": np.tanh, "abs": np.abs}


def _deriv(fn, x, y):
    """|f'(x)| for the error propagation (inf where it is infinite)."""
    if fn == "sqrt":
        return 0.5 / np.abs(y)
    if fn in ("exp", "cosh"):
        return np.abs(np.exp(x) if fn == "exp" else np.sinh(x))
    if fn == "log":
        return 1.0 / np.abs(x)
    if fn == "sin":
        return np.abs(np.cos(x))
    if fn == "cos":
        return np.abs(np.sin(x))
    if fn == "tan":
        return 1.0 + y * y
    if fn in ("asin", "acos"):
        return 1.0 / np.sqrt(np.abs(1.0 - x * x))
    if fn == "atan":
        return 1.0 / (1.0 + x * x)
    if fn == "sinh":
        return np.abs(np.cosh(x))
    if fn == "tanh":
        return 1.0 - y * y
    return np.ones_like(x)  # abs


def _eval(node, env: dict, dtype, problems: list | None):
    """(value, round-off bound) arrays of ``node`` over the points in ``env`` (name -> array)."""
    eps = float(np.finfo(dtype).eps)
    k = node[0]
    if k == "num":
        v = dtype(node[1])
        return v, abs(v) * eps / 2
    if k == "unit":
        v = dtype(node[1])
        return v, abs(v) * eps / 2
    if k == "par":
        # a parameter is a double: half an ulp of it, whatever the precision of the arithmetic, so that a
        # formula and mech's, exact for the same inputs, may differ by what that rounding moves (sin(2 beta)
        # at beta = pi/2 in double is 1.2e-16, where mech's closed form gives 0)
        v = env[node[1]]
        return v, np.abs(v) * INPUT_ROUNDING
    if k == "neg":
        v, e = _eval(node[1], env, dtype, problems)
        return -v, e
    if k in ("add", "sub", "mul", "div", "pow"):
        a, ea = _eval(node[1], env, dtype, problems)
        b, eb = _eval(node[2], env, dtype, problems)
        if k == "add":
            y = a + b
            return y, ea + eb + eps * np.abs(y)
        if k == "sub":
            y = a - b
            return y, ea + eb + eps * np.abs(y)
        if k == "mul":
            y = a * b
            return y, np.abs(b) * ea + np.abs(a) * eb + eps * np.abs(y)
        if k == "div":
            y = a / b
            if problems is not None:
                bad = (b == 0) & np.isfinite(a)
                if np.any(bad):
                    problems.append(Problem(np.broadcast_to(bad, np.shape(y)), "a division by zero", np.zeros(np.shape(y))))
            return y, (ea + np.abs(y) * eb) / np.abs(b) + eps * np.abs(y)
        y = np.power(a, b) if np.ndim(a) or np.ndim(b) else np.power(dtype(a), dtype(b))
        if problems is not None:
            bad = ~np.isfinite(y) & np.isfinite(a) & np.isfinite(b)
            if np.any(bad):
                neg = np.broadcast_to(a < 0, np.shape(bad))
                what = "a negative number to a fractional power" if np.all(neg[bad]) else "a power that overflows or divides by zero"
                problems.append(Problem(np.broadcast_to(bad, np.shape(y)), what, np.broadcast_to(a, np.shape(y))))
        with np.errstate(all="ignore"):
            la = np.log(np.abs(a))
            err = np.abs(y) * (np.abs(b) * ea / np.abs(a) + np.abs(la) * eb) + eps * np.abs(y)
        err = np.where(np.isfinite(err) | ~np.isfinite(y), err, 0.0)
        return y, err
    if k == "fn":
        fn, args = node[1], node[2]
        if fn == "atan2":
            (a, ea), (b, eb) = _eval(args[0], env, dtype, problems), _eval(args[1], env, dtype, problems)
            y = np.arctan2(a, b)
            r2 = a * a + b * b
            err = (np.abs(b) * ea + np.abs(a) * eb) / r2 + eps * np.abs(y)
            if problems is not None:
                bad = (a == 0) & (b == 0)
                if np.any(bad):
                    problems.append(Problem(np.broadcast_to(bad, np.shape(y)), "atan2 of (0, 0)", np.zeros(np.shape(y))))
            return y, np.where(r2 > 0, err, 0.0)
        x, ex = _eval(args[0], env, dtype, problems)
        y = _FN[fn](x)
        if problems is not None:
            bad = ~np.isfinite(y) & np.isfinite(x)
            if np.any(bad):
                problems.append(Problem(np.broadcast_to(bad, np.shape(y)), f"{fn} of {{x}}", np.broadcast_to(x, np.shape(y))))
        d = _deriv(fn, x, y)
        err = d * ex + eps * np.abs(y)
        # at a branch point (asin(1), sqrt(0)) the first-order bound is infinite; second order is sqrt(ex)
        inf = ~np.isfinite(err) & np.isfinite(y)
        if np.any(inf):
            err = np.where(inf, np.sqrt(ex * 2) + eps * np.abs(y), err)
        return y, err
    raise AssertionError(k)  # pragma: no cover


def _names_in(node, out: set) -> set:
    if node[0] == "par":
        out.add(node[1])
    elif node[0] == "neg":
        _names_in(node[1], out)
    elif node[0] in ("add", "sub", "mul", "div", "pow"):
        _names_in(node[1], out)
        _names_in(node[2], out)
    elif node[0] == "fn":
        for a in node[2]:
            _names_in(a, out)
    return out


@dataclass
class Formula:
    """A parsed formula: the text, the tree, the parameters it names, its dimension (None when its parts
    clash: then ``dim_error`` says how)."""

    text: str
    tree: tuple
    names: frozenset
    dim: Dim | None
    dim_error: str | None

    def evaluate(self, env: dict, dtype=np.float64):
        """(values, round-off bounds, problems) at the points ``env`` (parameter -> 1-D array, SI)."""
        n = len(next(iter(env.values()))) if env else 1
        env = {k: np.asarray(v, dtype=dtype) for k, v in env.items()}
        problems: list[Problem] = []
        with np.errstate(all="ignore"):
            y, err = _eval(self.tree, env, dtype, problems)
        y = np.broadcast_to(np.asarray(y, dtype=dtype), (n,)).copy()
        err = np.broadcast_to(np.asarray(err, dtype=dtype), (n,)).copy()
        for pr in problems:  # a constant part of the formula fails at every point
            pr.mask = np.broadcast_to(np.asarray(pr.mask, bool), (n,))
            pr.args = np.broadcast_to(np.asarray(pr.args, float), (n,))
        return y, err, problems


def parameter_symbols(ex) -> dict[str, str]:
    """Every way a formula may name a parameter of ``ex``: name -> name, and each symbol -> name."""
    out = {}
    for p in getattr(ex, "params", ()):
        if p.symbol and p.symbol != p.name:
            out[p.symbol] = p.name
    return out


def looks_like_formula(text: str, ex, parameters_only: bool = False) -> bool:
    """Does ``text`` name any parameter of ``ex`` (by name or symbol) or (unless ``parameters_only``) a
    function?"""
    try:
        toks = tokens(str(text)[:MAX_LENGTH], parameter_symbols(ex), formula=True)
    except ValueError_:
        return False
    names = set(getattr(ex, "param_map", ()))
    return any(k == "name" and (v in names or (v in FUNCTIONS and not parameters_only)) for k, v in toks)


def parse_formula(text: str, ex) -> Formula:
    """Parse ``text`` against exercise ``ex``'s parameters; FormulaError (one line) when unreadable."""
    text = str(text)
    if len(text) > MAX_LENGTH:
        raise FormulaError(f"formula too long ({len(text)} characters; at most {MAX_LENGTH})")
    text = text.strip()
    if text.count("(") > MAX_DEPTH * 4:
        raise FormulaError(f"formula nested too deeply (more than {MAX_DEPTH} levels)")
    try:
        tree = parse(text, _Tree(set(ex.param_map)), "formula", MAX_DEPTH, parameter_symbols(ex))
    except FormulaError:
        raise
    except ValueError_ as exc:
        raise FormulaError(str(exc)) from None
    pdims = {p.name: dim_of_unit(p.unit)[1] for p in ex.params}
    try:
        dim, why = _dim(tree, pdims), None
    except DimensionError as exc:
        dim, why = None, str(exc)
    return Formula(text, tree, frozenset(_names_in(tree, set())), dim, why)
