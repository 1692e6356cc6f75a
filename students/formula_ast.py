"""A student's formula: parsed without ``eval``, checked for its dimension, evaluated on arrays of points.

The grammar is that of values (numbers, units, ``pi``, ``+ - * / ^ **``, parentheses, a factor next to a
name multiplies) plus the exercise's parameter names and symbols and a few functions::

    sqrt exp expm1 log sin cos tan asin acos atan atan2 sinh cosh tanh abs   (arcsin arccos arctan ln: aliases)
    ellipk(m) ellipe(m)   complete elliptic integrals K and E of the parameter m = k^2 (scipy's convention)
    agm(a, b)             the arithmetic-geometric mean (AGM: alias)

A name is read, in order, as a parameter (name or symbol as ``mech show`` lists it), ``pi``, a function
(followed by ``(``), a unit.  The tokenizer and grammar are those of values (``core.units.parse``, one
parser for both); here they build a small tree of tuples; nothing of the text is ever executed.
Length and depth are bounded (``MAX_LENGTH`` characters, ``MAX_DEPTH`` nested levels): an answers file is
untrusted input.

Dimensions are exponents of (length, mass, time) as fractions; the radian counts as a pure number, so
``rad/s`` is ``1/s``.  Numbers are exact as written (``0.4`` is 2/5, not a 1-digit value).

Evaluation is vectorised with numpy (one pass for all points): ``evaluate`` gives the double value (shown,
and read by the hints), ``enclose`` a certified enclosure of the exact value (``solvers.numerics.interval``:
outward-rounded interval arithmetic in double, or in mpmath at a given precision), numbers exact as written
and parameters exact as the doubles they are, units exact as defined (``deg`` is pi/180).  A term that
cancels in exact arithmetic buys no allowance, and an error behind a function of zero slope cannot hide.

Sums and products are flat (``("sum", ((+1, a), (-1, b), ...))``): a long sum is bounded by the length of
the text, not by the nesting.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from mech.core.units import UNITS, ValueError_, parse, tokens
from mech.verification.judge import within

__all__ = ["FormulaError", "Formula", "parse_formula", "looks_like_formula", "Dim", "dim_of_unit", "dim_text",
           "FUNCTIONS", "MAX_LENGTH", "MAX_DEPTH", "MAX_DIM_POWER", "MAX_PREC"]

MAX_LENGTH = 2000
MAX_DEPTH = 100
INPUT_ROUNDING = 2.0**-53  # a parameter's own rounding to a double, relative

FUNCTIONS = {
    "sqrt": "sqrt", "exp": "exp", "log": "log", "ln": "log", "sin": "sin", "cos": "cos", "tan": "tan",
    "asin": "asin", "arcsin": "asin", "acos": "acos", "arccos": "acos", "atan": "atan", "arctan": "atan",
    "atan2": "atan2", "arctan2": "atan2", "sinh": "sinh", "cosh": "cosh", "tanh": "tanh", "abs": "abs",
    "ellipk": "ellipk", "ellipe": "ellipe", "agm": "agm", "AGM": "agm", "expm1": "expm1",
}
_ARITY = {"atan2": 2, "agm": 2}
MAX_DIM_POWER = 1000  # a dimension's exponent, at most (in size and denominator): l^1e300 is refused


class FormulaError(ValueError):
    """A formula that cannot be read; the message is one user-facing line."""


class DimensionError(FormulaError):
    """A formula whose parts have clashing dimensions (``l + g``); wrong, not unreadable."""


Dim = tuple  # (L, M, T) as Fractions; the angle dropped (the radian is a pure number)
ONE: Dim = (Fraction(0), Fraction(0), Fraction(0))


def _from_unit_dim(d) -> Dim:
    return tuple(Fraction(x) for x in d[:3])


@functools.lru_cache(maxsize=512)
def dim_of_unit(unit: str) -> tuple[float, Dim]:
    """SI factor and dimension (angle dropped) of a catalogue unit such as ``kg*m^2/s`` or ``rad`` (read once:
    a class file asks for the same few units at every formula)."""
    from mech.core.units import parse_unit

    factor, d = parse_unit(unit)
    return factor, _from_unit_dim(d)


_BASE = (("m", 0), ("kg", 1), ("s", 2))


def dim_text(d: Dim) -> str:
    """``m/s``, ``kg*m^2``, ``1/s``, ``1`` (a pure number), ``m^(1/2)``."""
    def part(sym, e):
        e = abs(Fraction(e))
        if e.numerator > 10**6 or e.denominator > 10**6:
            return f"{sym}^(huge)"
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
    """A formula's parts, for ``core.units.parse``: a name is, in order, a parameter (its name or symbol), ``pi``,
    a function (followed by ``(``), a unit, another spelling of a parameter's name or symbol (``omega_0``,
    ``ω0`` for ``ω₀``), a quantity the exercise's printed formulas define (5.5's ``ω_d``)."""

    def __init__(self, names: "Names"):
        self.names = names
        self.params = names.params

    def function(self, name):
        if name in self.params or name not in FUNCTIONS:
            return None
        return _ARITY.get(FUNCTIONS[name], 1)

    @staticmethod
    def number(text):
        v = float(text)
        if not math.isfinite(v):
            raise FormulaError(f"'{text[:20]}' is not a finite number")
        return ("num", v, text)

    def name(self, val):
        if val in self.params:
            return ("par", val)
        if val == "pi":
            return ("num", math.pi, "pi")
        if val in UNITS:
            factor, d = UNITS[val]
            return ("unit", factor, _from_unit_dim(d), val)
        found = self.names.resolve(val)
        if found is not None:
            return found
        if val.lower() in ("nan", "inf", "infinity"):
            raise FormulaError("not a finite number")
        raise FormulaError(f"unknown name '{_cut(val)}'{_juxtaposed(val) or self.names.hint(val)}; "
                           f"{self.names.listed()}")

    @staticmethod
    def neg(node):
        return ("neg", node)

    @staticmethod
    def plus(node):
        return node

    @staticmethod
    def binary(op, a, b):
        # sums and products flat, left to right (the order of evaluation of the left-nested tree)
        if op in ("+", "-"):
            head = a[1] if a[0] == "sum" else ((1, a),)
            return ("sum", head + ((1 if op == "+" else -1, b),))
        if op in ("*", "/"):
            head = a[1] if a[0] == "prod" else ((1, a),)
            return ("prod", head + ((1 if op == "*" else -1, b),))
        return (_OPS[op], a, b)

    @staticmethod
    def call(name, args):
        return ("fn", FUNCTIONS[name], tuple(args))


def _cut(text: str, n: int = 40) -> str:
    from mech.core.safeio import shown

    return shown(text, n)


def _juxtaposed(name: str) -> str:
    """`` (read as one name: write pi*sqrt(...))`` when an unknown name is known names run together."""
    words = sorted(set(FUNCTIONS) | {"pi"}, key=len, reverse=True)
    rest, parts = name, []
    while rest:
        w = next((w for w in words if rest.startswith(w)), None)
        if w is None:
            return ""
        parts.append(w)
        rest = rest[len(w):]
    return f" (names side by side: write {'*'.join(parts)})" if len(parts) > 1 else ""


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
    if node[0] == "pow":
        return _contains(node[1], kinds) or _contains(node[2], kinds)
    if node[0] in ("sum", "prod"):
        return any(_contains(t, kinds) for _, t in node[1])
    if node[0] == "fn":
        return any(_contains(a, kinds) for a in node[2])
    return False


def _bounded(d: Dim) -> Dim:
    if any(abs(x) > MAX_DIM_POWER or x.denominator > MAX_DIM_POWER for x in d):
        raise DimensionError(f"a dimension raised to a power beyond {MAX_DIM_POWER}")
    return d


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
    if k == "sum":
        dims = [_dim(t, pdims) for _, t in node[1]]
        for b in dims[1:]:
            if b != dims[0]:
                raise DimensionError(f"it adds {dim_text(dims[0])} and {dim_text(b)}")
        return dims[0]
    if k == "prod":
        out = ONE
        for sign, t in node[1]:
            d = _dim(t, pdims)
            if d is not ONE and d != ONE:  # a pure number leaves the product's dimension as it is
                out = _bounded(tuple(x + sign * y for x, y in zip(out, d)))
        return out
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
        return _bounded(tuple(x * frac for x in a))
    if k == "fn":
        fn, args = node[1], node[2]
        dims = [_dim(a, pdims) for a in args]
        if fn == "sqrt":
            return tuple(x / 2 for x in dims[0])
        if fn == "abs":
            return dims[0]
        if fn in ("atan2", "agm"):
            if dims[0] != dims[1]:
                raise DimensionError(f"{fn} of {dim_text(dims[0])} and {dim_text(dims[1])}")
            return ONE if fn == "atan2" else dims[0]
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


def _ellip(fn):
    from mech.solvers.numerics import special

    return np.vectorize(getattr(special, fn), otypes=[float])


_FN = {"sqrt": np.sqrt, "exp": np.exp, "log": np.log, "sin": np.sin, "cos": np.cos, "tan": np.tan,
       "asin": np.arcsin, "acos": np.arccos, "atan": np.arctan, "sinh": np.sinh, "cosh": np.cosh,
       "tanh": np.tanh, "abs": np.abs, "expm1": np.expm1}


def _fn(fn, x):
    if fn in ("ellipk", "ellipe"):
        return _ellip(fn)(x)
    return _FN[fn](x)


def _deriv(fn, x, y):
    """|f'(x)| for the error propagation (inf where it is infinite)."""
    if fn == "sqrt":
        return 0.5 / np.abs(y)
    if fn in ("exp", "cosh", "expm1"):
        return np.abs(np.sinh(x) if fn == "cosh" else np.exp(x))
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
    if fn == "ellipk":  # dK/dm = (E - (1 - m) K) / (2 m (1 - m))
        e = _ellip("ellipe")(x)
        return np.abs((e - (1.0 - x) * y) / (2.0 * x * (1.0 - x)))
    if fn == "ellipe":  # dE/dm = (E - K) / (2 m)
        k = _ellip("ellipk")(x)
        return np.abs((y - k) / (2.0 * x))
    return np.ones_like(x)  # abs


def _eval(node, env: dict, dtype, problems: list | None):
    """(value, round-off bound) arrays of ``node`` over the points in ``env`` (name -> array)."""
    eps = float(np.finfo(dtype).eps)
    # an operation whose result underflows loses it whole: each adds the smallest subnormal, absolute
    tiny = float(np.finfo(dtype).smallest_subnormal)
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
    if k == "sum":
        (s0, t0), rest = node[1][0], node[1][1:]
        y, err = _eval(t0, env, dtype, problems)
        y = y if s0 > 0 else -y
        for s, t in rest:
            b, eb = _eval(t, env, dtype, problems)
            y = y + b if s > 0 else y - b
            err = err + eb + eps * np.abs(y) + tiny
        return y, err
    if k == "prod":
        y, err = _eval(node[1][0][1], env, dtype, problems)
        if node[1][0][0] < 0:  # pragma: no cover  (a product starts with a factor)
            raise AssertionError(node)
        for s, t in node[1][1:]:
            b, eb = _eval(t, env, dtype, problems)
            a, ea = y, err
            if s > 0:
                y = a * b
                err = np.abs(b) * ea + np.abs(a) * eb + eps * np.abs(y) + tiny
                continue
            y = a / b
            if problems is not None:
                bad = (b == 0) & np.isfinite(a)
                if np.any(bad):
                    problems.append(Problem(np.broadcast_to(bad, np.shape(y)), "a division by zero",
                                            np.zeros(np.shape(y))))
            err = (ea + np.abs(y) * eb) / np.abs(b) + eps * np.abs(y) + tiny
        return y, err
    if k == "pow":
        a, ea = _eval(node[1], env, dtype, problems)
        b, eb = _eval(node[2], env, dtype, problems)
        y = np.power(a, b) if np.ndim(a) or np.ndim(b) else np.power(dtype(a), dtype(b))
        if problems is not None:
            bad = ~np.isfinite(y) & np.isfinite(a) & np.isfinite(b)
            if np.any(bad):
                neg = np.broadcast_to(a < 0, np.shape(bad))
                what = "a negative number to a fractional power" if np.all(neg[bad]) else "a power that overflows or divides by zero"
                problems.append(Problem(np.broadcast_to(bad, np.shape(y)), what, np.broadcast_to(a, np.shape(y))))
        la = np.log(np.abs(a))
        err = np.abs(y) * (np.abs(b) * ea / np.abs(a) + np.abs(la) * eb) + eps * np.abs(y) + tiny
        err = np.where(np.isfinite(err) | ~np.isfinite(y), err, 0.0)
        return y, err
    if k == "fn":
        fn, args = node[1], node[2]
        if fn in ("atan2", "agm"):
            (a, ea), (b, eb) = _eval(args[0], env, dtype, problems), _eval(args[1], env, dtype, problems)
            if fn == "agm":
                y = _agm(a, b)
                if problems is not None:
                    bad = ~np.isfinite(y) & np.isfinite(a) & np.isfinite(b)
                    if np.any(bad):
                        problems.append(Problem(np.broadcast_to(bad, np.shape(y)), "agm of a negative number",
                                                np.broadcast_to(np.minimum(a, b), np.shape(y))))
                # agm is homogeneous of degree 1 and increasing in both: each partial is at most agm/argument
                err = np.abs(y) * (ea / np.abs(a) + eb / np.abs(b)) + 4 * eps * np.abs(y)
                return y, np.where(np.isfinite(err), err, np.inf)
            y = np.arctan2(a, b)
            r2 = a * a + b * b
            err = (np.abs(b) * ea + np.abs(a) * eb) / r2 + eps * np.abs(y)
            if problems is not None:
                bad = (a == 0) & (b == 0)
                if np.any(bad):
                    problems.append(Problem(np.broadcast_to(bad, np.shape(y)), "atan2 of (0, 0)", np.zeros(np.shape(y))))
            return y, np.where(r2 > 0, err, 0.0)
        x, ex = _eval(args[0], env, dtype, problems)
        y = _fn(fn, x)
        if problems is not None:
            bad = ~np.isfinite(y) & np.isfinite(x)
            if np.any(bad):
                problems.append(Problem(np.broadcast_to(bad, np.shape(y)), f"{fn} of {{x}}", np.broadcast_to(x, np.shape(y))))
        d = _deriv(fn, x, y)
        err = d * ex + (4 if fn.startswith("ellip") else 1) * eps * np.abs(y) + tiny
        # at a branch point (asin(1), sqrt(0)) the first-order bound is infinite; second order is sqrt(ex)
        inf = ~np.isfinite(err) & np.isfinite(y)
        if np.any(inf):
            err = np.where(inf, np.sqrt(ex * 2) + eps * np.abs(y), err)
        return y, err
    raise AssertionError(k)  # pragma: no cover


def _agm(a, b):
    from mech.solvers.numerics import special

    return np.vectorize(special.agm, otypes=[float])(a, b)


# -- certified enclosure (interval arithmetic) ----------------------------------------------------------

MAX_PREC = 8192  # bits: past this a point is not decided (it is not graded, never right)
_HUGE_EXP = 100_000  # a number written with a decimal exponent beyond this is not enclosed in high precision
# units whose size is a rational times pi (the others are exact as their decimal values)
_PI_UNITS = {"deg": (1, 180), "degree": (1, 180), "degrees": (1, 180), "turn": (2, 1), "rev": (2, 1),
             "Hz": (2, 1), "kHz": (2000, 1), "rpm": (1, 30)}


def _literal(B, text: str, v: float, n: int):
    """The number ``text`` as written (``0.4`` is 2/5), enclosed."""
    from mech.solvers.numerics import interval as iv

    if B is iv.DOUBLE:
        point, lo, hi = _double_bounds(text, v)
        if point:
            return iv.point(B, np.full(n, v))
        return iv.constant(B, np.full(n, lo), np.full(n, hi))
    lo, hi = _precise_bounds(text, B.prec)
    return iv.constant(B, [lo] * n, [hi] * n)


@functools.lru_cache(maxsize=4096)
def _double_bounds(text: str, v: float):
    """(exact, lo, hi): whether the double ``v`` is the number ``text`` exactly, else the doubles around it."""
    exact = _exact_fraction(text)
    if exact is not None and Fraction(v) == exact:
        return True, v, v
    lo, hi = np.nextafter(v, -np.inf), np.nextafter(v, np.inf)
    return False, max(lo, 0.0) if v >= 0 else lo, hi


@functools.lru_cache(maxsize=4096)
def _precise_bounds(text: str, prec: int):
    """The number ``text`` rounded down and up to ``prec`` bits (mpmath numbers: immutable), or -inf, inf."""
    import mpmath as m

    exact = _exact_fraction(text)
    if exact is None:
        return -m.inf, m.inf
    return (m.fdiv(exact.numerator, exact.denominator, prec=prec, rounding="f"),
            m.fdiv(exact.numerator, exact.denominator, prec=prec, rounding="c"))


@functools.lru_cache(maxsize=4096)
def _exact_fraction(text: str):
    """The exact rational a number's text means, or None (an exponent too large to expand)."""
    mant, _, exp = text.lower().partition("e")
    if exp and abs(int(exp)) > _HUGE_EXP:
        return None
    return Fraction(text)


def _unit_size(B, node, n: int):
    from mech.solvers.numerics import interval as iv

    name, factor = node[3], node[1]
    if name in _PI_UNITS:
        p, q = _PI_UNITS[name]
        pi = iv.constant(B, [B.pi(-1)] * n, [B.pi(1)] * n)
        num = _literal(B, str(p), float(p), n)
        den = _literal(B, str(q), float(q), n)
        return iv.div(B, iv.mul(B, pi, num), den)[0]
    return _literal(B, repr(float(factor)), float(factor), n)


def _enclose(node, env: dict, B, n: int, problems: list, memo: dict):
    """(lo, hi): an enclosure of the exact value of ``node`` at the points ``env`` (name -> array, exact);
    ``problems`` gains each certain domain error (``Problem``).  A part written twice (``F`` in
    ``F + (C F - C F)``) is enclosed once: ``memo`` holds the enclosures of the parts the formula repeats
    (``memo[None]``, see ``_repeated``) at these points and this precision, their domain errors are in
    ``problems`` already; the others are not kept (10000 points: 160 kB a part)."""
    if node[0] in _LEAVES or node not in memo[None]:
        return _enclose_part(node, env, B, n, problems, memo)
    got = memo.get(node)
    if got is None:
        got = memo[node] = _enclose_part(node, env, B, n, problems, memo)
    return got


_LEAVES = ("num", "unit", "par")


@functools.lru_cache(maxsize=256)
def _repeated(tree) -> frozenset:
    """The parts of ``tree`` other than numbers, units and parameters that it holds more than once."""
    seen: dict = {}

    def walk(node):
        if node[0] in _LEAVES:
            return
        seen[node] = seen.get(node, 0) + 1
        if seen[node] > 1:
            return  # its own parts were counted with its first occurrence: held twice as well
        if node[0] in ("neg", "pow"):
            for a in node[1:3] if node[0] == "pow" else node[1:2]:
                walk(a)
        elif node[0] in ("sum", "prod"):
            for _, t in node[1]:
                walk(t)
        elif node[0] == "fn":
            for a in node[2]:
                walk(a)

    walk(tree)
    return frozenset(k for k, c in seen.items() if c > 1)


def _enclose_part(node, env: dict, B, n: int, problems: list, memo: dict):
    from mech.solvers.numerics import interval as iv

    k = node[0]
    if k == "num":
        if node[2] == "pi":
            return iv.constant(B, [B.pi(-1)] * n, [B.pi(1)] * n)
        return _literal(B, node[2], node[1], n)
    if k == "unit":
        return _unit_size(B, node, n)
    if k == "par":
        return iv.point(B, env[node[1]])
    if k == "neg":
        return iv.neg(B, _enclose(node[1], env, B, n, problems, memo))
    if k == "sum":
        (s0, t0), rest = node[1][0], node[1][1:]
        y = _enclose(t0, env, B, n, problems, memo)
        y = y if s0 > 0 else iv.neg(B, y)
        for s, t in rest:
            b = _enclose(t, env, B, n, problems, memo)
            y = iv.add(B, y, b) if s > 0 else iv.sub(B, y, b)
        return y
    if k == "prod":
        y = _enclose(node[1][0][1], env, B, n, problems, memo)
        for s, t in node[1][1:]:
            b = _enclose(t, env, B, n, problems, memo)
            if s > 0:
                y = iv.mul(B, y, b)
                continue
            y, zero = iv.div(B, y, b)
            _note(problems, zero, "a division by zero", None, n)
        return y
    if k == "pow":
        a = _enclose(node[1], env, B, n, problems, memo)
        b = _enclose(node[2], env, B, n, problems, memo)
        y, bad = iv.power(B, a, b)
        _note(problems, bad, "a negative number to a fractional power or zero to a negative one", None, n)
        return y
    if k == "fn":
        fn, args = node[1], node[2]
        vals = [_enclose(a, env, B, n, problems, memo) for a in args]
        if fn == "atan2":
            y, bad = iv.atan2(B, *vals)
            _note(problems, bad, "atan2 of (0, 0)", None, n)
            return y
        if fn == "agm":
            y, bad = iv.agm(B, *vals)
            _note(problems, bad, "agm of a negative number", vals[0][1], n)
            return y
        y, bad = iv.function(B, fn, vals[0])
        _note(problems, bad, f"{fn} of {{x}}", vals[0][0], n)
        return y
    raise AssertionError(k)  # pragma: no cover


def _note(problems: list, bad, what: str, arg, n: int) -> None:
    bad = np.broadcast_to(np.asarray(bad, bool), (n,))
    if np.any(bad):
        args = np.zeros(n) if arg is None else np.array([float(x) for x in np.broadcast_to(arg, (n,))])
        problems.append(Problem(bad.copy(), what, args))


def _names_in(node, out: set) -> set:
    if node[0] == "par":
        out.add(node[1])
    elif node[0] == "neg":
        _names_in(node[1], out)
    elif node[0] == "pow":
        _names_in(node[1], out)
        _names_in(node[2], out)
    elif node[0] in ("sum", "prod"):
        for _, t in node[1]:
            _names_in(t, out)
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

    def enclose(self, env: dict, prec: int | None = None):
        """A certified enclosure ``(lo, hi, problems)`` of the formula's exact value at the points ``env``
        (parameter -> 1-D array of doubles, taken exactly; numbers exact as written): in double precision
        with outward rounding (``prec`` None), else at ``prec`` bits with mpmath.  ``[-inf, inf]`` where it
        is not enclosed there; ``problems``: where there is certainly no real value (a domain error)."""
        from mech.solvers.numerics import interval as iv

        n = len(next(iter(env.values()))) if env else 1
        at = _distinct_points(env, n)
        if at is not None:  # the same point more than once: each enclosed once (interval arithmetic is per point)
            first, where = at
            lo, hi, problems = self.enclose({k: np.asarray(v, float)[first] for k, v in env.items()}, prec)
            for pr in problems:
                pr.mask, pr.args = np.asarray(pr.mask)[where], np.asarray(pr.args)[where]
            return lo[where], hi[where], problems
        B = iv.DOUBLE if prec is None else iv.precise(prec)
        if prec is None:
            env = {k: np.asarray(v, dtype=float) for k, v in env.items()}
        else:
            import mpmath

            env = {k: B.asarray([mpmath.mpf(float(x)) for x in np.asarray(v, float)]) for k, v in env.items()}
        problems: list[Problem] = []
        with np.errstate(all="ignore"):
            lo, hi = _enclose(self.tree, env, B, n, problems, {None: _repeated(self.tree)})
        lo = np.broadcast_to(B.asarray(lo), (n,)).copy()
        hi = np.broadcast_to(B.asarray(hi), (n,)).copy()
        return lo, hi, problems


def _distinct_points(env: dict, n: int):
    """``(first, where)`` when the points ``env`` repeat one (a line along a parameter the formula does not
    name, or a formula of no parameter): ``first`` the index of each distinct point's first occurrence in
    order, ``where`` each point's index into ``first``; None when every point is distinct.  Points are the
    same when their doubles are the same bits."""
    if n < 2 or not env:
        return None
    rows = np.ascontiguousarray(np.stack([np.asarray(v, float).reshape(-1) for v in env.values()], axis=1))
    bits = rows.view(np.int64)
    if n <= 256 and len(set(map(tuple, bits.tolist()))) == n:  # a few points, all distinct: told without sorting
        return None
    _, first, inverse = np.unique(bits, axis=0, return_index=True, return_inverse=True)
    if first.size == n:
        return None
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    return first[order], rank[np.asarray(inverse).reshape(-1)]


def parameter_symbols(ex) -> dict[str, str]:
    """The symbols of ``ex``'s parameters that differ from their names (``θ₀``, ``M'``, ``h/R``): symbol -> name."""
    out = {}
    for p in getattr(ex, "params", ()):
        if p.symbol and p.symbol != p.name:
            out[p.symbol] = p.name
    return out


# -- the names a formula may use ------------------------------------------------------------------------

_GREEK = dict(zip("αβγδεϵζηθϑικλμνξοπρστυφϕχψωΓΔΘΛΞΠΣΦΨΩ",
                  ("alpha beta gamma delta epsilon epsilon zeta eta theta theta iota kappa lambda mu nu xi omicron "
                   "pi rho sigma tau upsilon phi phi chi psi omega Gamma Delta Theta Lambda Xi Pi Sigma Phi Psi "
                   "Omega").split()))
_SUBSCRIPTS = str.maketrans("₀₁₂₃₄₅₆₇₈₉ₐₑₒₓₕₖₗₘₙₚₛₜ", "0123456789aeoxhklmnpst")


def spelling(name: str) -> str:
    """The key two spellings of one name share: Greek letters spelled out, subscripts as plain characters,
    underscores dropped (``ω₀``, ``ω_0``, ``omega0``, ``omega_0`` -> ``omega0``; case is kept: ``Ω`` is
    ``Omega``)."""
    return "".join(_GREEK.get(ch, ch) for ch in name.translate(_SUBSCRIPTS)).replace("_", "")


class Names:
    """The names a formula of one exercise may use: its parameters (names, symbols and their other
    spellings, where only one parameter has that spelling) and the quantities its printed formulas define
    (``ω_d = (ω₀² − δ²)^½`` in 5.5: ``ω_d`` and ``omega_d`` stand for that expression)."""

    def __init__(self, ex):
        self.params = set(getattr(ex, "param_map", ()) or (p.name for p in getattr(ex, "params", ())))
        self.symbols = parameter_symbols(ex)
        self.pdims = {p.name: dim_of_unit(p.unit)[1] for p in getattr(ex, "params", ())}
        outputs = {spelling(o.name) for o in getattr(ex, "outputs", ())}
        keyed: dict[str, set] = {}
        for p in getattr(ex, "params", ()):
            for written in (p.name, p.symbol):
                if written:
                    keyed.setdefault(spelling(written), set()).add(p.name)
        self.keys = {k: next(iter(v)) for k, v in keyed.items() if len(v) == 1}
        taken = set(keyed) | outputs | {spelling(u) for u in UNITS} | set(FUNCTIONS) | {"pi"}
        self.defined: dict[str, tuple[str, tuple]] = {}  # key -> (the name as printed, its tree)
        self._define(getattr(ex, "formulas", ()), taken)

    def resolve(self, name: str):
        """The tree ``name`` stands for (a parameter or a defined quantity), or None."""
        key = spelling(name)
        if key in self.keys:
            return ("par", self.keys[key])
        if key in self.defined:
            return self.defined[key][1]
        return None

    def known(self, name: str) -> bool:
        return name in self.params or self.resolve(name) is not None

    def listed(self) -> str:
        out = f"the parameters here are: {', '.join(sorted(self.params))}"
        if self.defined:
            out += f"; and as mech's formulas define them: {', '.join(n for n, _ in self.defined.values())}"
        return out

    def hint(self, name: str) -> str:
        """" (did you mean omega0?)" for a near miss of a name here, else of a unit, else ""."""
        import difflib

        from mech.core.units import unit_hint

        if len(name) < 2 or len(name) > 40:
            return ""
        mine = sorted(self.params | set(self.symbols) | {n for n, _ in self.defined.values()})
        close = difflib.get_close_matches(name, mine, n=1, cutoff=0.75)
        unit = unit_hint(name).removeprefix("; ")
        return f" ({f'did you mean {close[0]}?' if close else unit})" if close or unit else ""

    def _define(self, formulas, taken: set) -> None:
        """Read the definitions ``NAME = expression`` that the printed formulas make (a clause of its own,
        its right side a formula of the parameters and of names defined before it): never a parameter, an
        output, a unit, a function; a name defined twice differently is left out."""
        clauses: dict[str, dict[str, list[str]]] = {}  # key -> {the clause: its right sides}
        printed: dict[str, set] = {}
        for line in formulas:
            for clause in _clauses(str(line)):
                found = _definition(clause)
                if found is None or spelling(found[0]) in taken:
                    continue
                name, squared, rhs = found
                # each side after the first '=' says the same (up to a comment set off by two spaces)
                sides = [r.split("  ")[0] for r in rhs.split("=") if r.strip()]
                key = spelling(name)
                printed.setdefault(key, set()).add(name)
                clauses.setdefault(key, {})[clause.strip()] = [f"sqrt({r})" if squared else r for r in sides]
        # one clause a name, printed one way (4.1's I_axis is M R² for a hoop and M R²/2 for a disk: neither)
        heads = [(next(iter(printed[k])), sides) for k, c in clauses.items() if len(c) == 1 and len(printed[k]) == 1
                 for sides in c.values()]
        for _ in range(3):  # a definition may use one made later on the line (5.12's ξ uses ω₀)
            for name, sides in heads:
                if spelling(name) not in self.defined:
                    tree = next((t for t in map(self._read, sides) if t is not None), None)
                    if tree is not None:
                        self.defined[spelling(name)] = (name, tree)

    def _read(self, rhs: str):
        for a, b in (("{", "("), ("}", ")"), ("[", "("), ("]", ")")):
            rhs = rhs.replace(a, b)
        try:
            tree = parse(rhs.strip(), _Tree(self), "formula", MAX_DEPTH, self.symbols)
            _dim(tree, self.pdims)  # a definition whose parts clash is not one mech makes
        except (ValueError_, FormulaError):
            return None
        # a definition names parameters and no unit (4.31's φ = ω_E t is not a tonne)
        return tree if _names_in(tree, set()) and not _contains(tree, ("unit",)) else None


def _definition(clause: str):
    """(name, squared, right side) of a clause ``NAME = ...`` or ``NAME² = ...`` (a positive root: Ω² = g/l),
    the right side up to a comparison or an arrow; None for any other clause."""
    lhs, eq, rhs = clause.partition("=")
    name = lhs.strip()
    squared = name.endswith("²")
    name = name.removesuffix("²")
    if not eq or not name or not name[0].isalpha() or not all(c.isalnum() or c == "_" for c in name) \
            or "²" in name or rhs[:1] in "=<>" or lhs[-1:] in "<>!":
        return None
    cut = min((i for i, c in enumerate(rhs) if c in "≈⇒→:≤≥<>"), default=len(rhs))
    return name, squared, rhs[:cut]


def _clauses(line: str) -> list[str]:
    """``line`` cut at its top-level commas and semicolons."""
    out, depth, cur, inner = [], 0, [], []
    for ch in line:
        depth += (ch in "([{") - (ch in ")]}")
        if depth == 0 and ch in ",;":
            out.append("".join(cur))
            cur = []
        else:
            cur.append(ch)
        if depth == 1 and ch == "(" and not inner:
            inner = [""]
        elif inner and depth >= 1:
            inner[-1] += ch
        elif inner:  # a parenthesis closed: what it says may be a definition of its own ("(q_st = F₀/(m ω₀²))")
            out += _clauses(inner.pop()) if "=" in inner[-1] else []
            inner = []
    out.append("".join(cur))
    return out


_NAMES: dict = {}


def names_of(ex) -> Names:
    """The names ``ex``'s formulas may use (kept per exercise: its parameters and formulas are fixed)."""
    key = (getattr(ex, "id", None), tuple((p.name, p.symbol) for p in getattr(ex, "params", ())),
           tuple(getattr(ex, "formulas", ()) or ()), tuple(o.name for o in getattr(ex, "outputs", ())))
    if key not in _NAMES:
        if len(_NAMES) > 256:
            _NAMES.clear()
        _NAMES[key] = Names(ex)
    return _NAMES[key]


def looks_like_formula(text: str, ex, parameters_only: bool = False) -> bool:
    """Does ``text`` name any parameter of ``ex`` (by name, symbol or another spelling, or a quantity its
    formulas define) or (unless ``parameters_only``) a function?"""
    names = names_of(ex)
    try:
        toks = tokens(str(text)[:MAX_LENGTH], names.symbols, formula=True)
    except ValueError_ as exc:  # a character no value has: the formula's parser names it
        return "unexpected character" in str(exc) and not parameters_only
    return any(k == "name" and (v in names.params or (v in FUNCTIONS and not parameters_only)
                                or (v not in UNITS and names.known(v))) for k, v in toks)


def parse_formula(text: str, ex) -> Formula:
    """Parse ``text`` against exercise ``ex``'s parameters; FormulaError (one line) when unreadable."""
    text = str(text)
    if len(text) > MAX_LENGTH:
        raise FormulaError(f"formula too long ({len(text)} characters; at most {MAX_LENGTH})")
    text = text.strip(" \t")  # a control character is refused by the tokenizer, not dropped
    if text.count("(") > MAX_DEPTH * 4:
        raise FormulaError(f"formula nested too deeply (more than {MAX_DEPTH} levels)")
    try:
        names = names_of(ex)
        tree = parse(text, _Tree(names), "formula", MAX_DEPTH, names.symbols)
    except FormulaError:
        raise
    except ValueError_ as exc:
        raise FormulaError(str(exc)) from None
    pdims = {p.name: dim_of_unit(p.unit)[1] for p in ex.params}
    tree = _unit_after(tree, pdims)
    try:
        dim, why = _dim(tree, pdims), None
    except DimensionError as exc:
        dim, why = None, str(exc)
    return Formula(text, tree, frozenset(_names_in(tree, set())), dim, why)


def _unit_after(tree, pdims):
    """A formula followed by a unit of its own dimension (``2*pi*sqrt(l/g) s``) says the unit of its value:
    an SI unit is dropped (the formula is in it already); another is refused in one line (the formula's
    value is SI, so ``... ms`` cannot be meant as a product).  Never a product of the two."""
    if tree[0] != "prod" or len(tree[1]) < 2:
        return tree
    sign, last = tree[1][-1]
    if sign < 0 or last[0] != "unit" or last[2] == ONE:
        return tree
    rest = tree[1][:-1]
    rest = rest[0][1] if len(rest) == 1 else ("prod", rest)
    try:
        if _dim(rest, pdims) != last[2] or not _contains(rest, ("par",)):
            return tree
    except DimensionError:
        return tree
    if last[1] == 1.0:
        return rest
    raise FormulaError(f"the formula is followed by the unit '{last[3]}': a formula's value is in SI; write "
                       "it without the unit")
