"""Parse the values people type: ``90deg``, ``90 deg``, ``pi/3``, ``2.5 km``, ``3 m/s^2``, ``100 rpm``.

A value is arithmetic (``+ - * / ^ **``, parentheses, ``pi``) over numbers and
units; a factor written next to a name or a parenthesis multiplies (``2pi``,
``15 cm``, ``1/(m^2 s^2)``), but two numbers side by side are an error, not a
product: ``1.2.3`` (read 1.2 .3), ``2 3`` and ``15cm 2`` are typing slips more
often than products, and need an explicit ``*``.  It is converted to
the SI unit of the parameter it is given for:

* a plain number is taken to be SI already (angles in radians);
* with units, their dimension must be the parameter's (a clear error otherwise);
* angles are a dimension of their own so that frequencies come out right:
  ``Hz`` and ``rpm`` count turns, so ``2Hz`` is 4 pi rad/s for an angular
  frequency but 2 for a parameter in turns per second (unit ``1/s``).  A value
  with one more angle unit than its parameter is converted from radians to
  turns; one with one fewer (``5/s`` for a parameter in rad/s) takes the radian
  as SI does.
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass

__all__ = ["ValueError_", "Dimensioned", "parse_quantity", "parse_unit", "si_exponents", "to_si", "UNITS"]


class ValueError_(ValueError):
    """A value that cannot be read or converted; the message is user-facing."""


# dimension exponents: length, mass, time, angle
_L, _M, _T, _A = (1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1)
_ONE = (0, 0, 0, 0)


def _dim(l=0, m=0, t=0, a=0):
    return (l, m, t, a)


TURN = 2 * math.pi
UNITS: dict[str, tuple[float, tuple]] = {
    # length
    "m": (1.0, _L), "mm": (1e-3, _L), "cm": (1e-2, _L), "km": (1e3, _L), "um": (1e-6, _L), "nm": (1e-9, _L),
    "AU": (1.495978707e11, _L),
    "ft": (0.3048, _L), "foot": (0.3048, _L), "feet": (0.3048, _L), "inch": (0.0254, _L), "mi": (1609.344, _L),
    # mass
    "kg": (1.0, _M), "g": (1e-3, _M), "mg": (1e-6, _M), "t": (1e3, _M),
    "lb": (0.45359237, _M), "lbs": (0.45359237, _M),
    # time
    "s": (1.0, _T), "ms": (1e-3, _T), "us": (1e-6, _T), "min": (60.0, _T), "h": (3600.0, _T),
    "day": (86400.0, _T), "yr": (365.25 * 86400.0, _T), "year": (365.25 * 86400.0, _T),
    # angle and frequency
    "rad": (1.0, _A), "mrad": (1e-3, _A), "deg": (math.pi / 180, _A),
    "degree": (math.pi / 180, _A), "degrees": (math.pi / 180, _A), "radian": (1.0, _A), "radians": (1.0, _A),
    "turn": (TURN, _A), "rev": (TURN, _A),
    "Hz": (TURN, _dim(t=-1, a=1)), "kHz": (1e3 * TURN, _dim(t=-1, a=1)), "rpm": (TURN / 60, _dim(t=-1, a=1)),
    # derived
    "N": (1.0, _dim(l=1, m=1, t=-2)), "J": (1.0, _dim(l=2, m=1, t=-2)), "W": (1.0, _dim(l=2, m=1, t=-3)),
}
CONSTANTS = {"pi": math.pi}
# a near miss is pointed at the short name (a typo of "degrees" gets "deg")
_SHORT = {"degree": "deg", "degrees": "deg", "radian": "rad", "radians": "rad", "foot": "ft", "feet": "ft",
          "lbs": "lb", "year": "yr"}


def unit_hint(name: str) -> str:
    """"; did you mean deg?" for a near miss of a unit or constant (at most one), else ""."""
    import difflib

    if len(name) < 2 or len(name) > 20:
        return ""
    known = list(UNITS) + list(CONSTANTS)
    close = difflib.get_close_matches(name, known, n=1, cutoff=0.75) \
        or difflib.get_close_matches(name.lower(), [k.lower() for k in known], n=1, cutoff=0.75)
    if not close:
        return ""
    match = next((k for k in known if k.lower() == close[0].lower()), close[0])
    return f"; did you mean {_SHORT.get(match, match)}?"

_DIM_NAMES = {
    _L: "a length", _M: "a mass", _T: "a time", _A: "an angle", _ONE: "a pure number",
    _dim(t=-1): "a rate", _dim(t=-1, a=1): "an angular frequency", _dim(l=1, t=-1): "a speed",
    _dim(l=1, t=-2): "an acceleration", _dim(l=1, m=1, t=-2): "a force", _dim(l=2, m=1): "a moment of inertia",
    _dim(l=2, m=1, t=-2): "an energy or torque",
}


@dataclass(frozen=True)
class Dimensioned:
    """A parsed value with its dimension (the unit parser's, not an output of a solve)."""

    value: float  # in SI, angles in radians
    dim: tuple
    has_units: bool


def _mul(a: Dimensioned, b: Dimensioned) -> Dimensioned:
    return Dimensioned(a.value * b.value, tuple(x + y for x, y in zip(a.dim, b.dim)), a.has_units or b.has_units)


def _div(a: Dimensioned, b: Dimensioned) -> Dimensioned:
    if b.value == 0:
        raise ValueError_("division by zero")
    return Dimensioned(a.value / b.value, tuple(x - y for x, y in zip(a.dim, b.dim)), a.has_units or b.has_units)


_TOKEN = re.compile(
    r"\s*(?:(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|(?P<name>[A-Za-z_]\w*)|(?P<op>\*\*|[-+*/^()])|(?P<bad>\S))"
)


def tokens(text: str) -> list[tuple[str, str]]:
    """The (kind, text) tokens of a typed value: numbers, names, operators, parentheses."""
    out = []
    pos = 0
    text = text.replace("·", "*").replace("×", "*").replace("°", "deg").replace("π", "pi").replace("µ", "u")
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m or m.end() == pos:
            break
        pos = m.end()
        kind = m.lastgroup
        if kind == "bad":
            raise ValueError_(f"unexpected character '{m.group(kind)}'")
        out.append((kind, m.group(kind)))
    return out


class _Parser:
    """expr := term (('+'|'-') term)*; term := factor (('*'|'/'|adjacent) factor)*;
    factor := ('-'|'+') factor | power; power := atom (('^'|'**') factor)?"""

    def __init__(self, tokens):
        self.toks = tokens
        self.i = 0

    def peek(self):
        return self.toks[self.i] if self.i < len(self.toks) else (None, None)

    def take(self):
        tok = self.peek()
        self.i += 1
        return tok

    def parse(self) -> Dimensioned:
        if not self.toks:
            raise ValueError_("empty value")
        q = self.expr()
        if self.i != len(self.toks):
            raise ValueError_(f"unexpected '{self.peek()[1]}'")
        return q

    def expr(self):
        q = self.term()
        while self.peek()[1] in ("+", "-"):
            op = self.take()[1]
            r = self.term()
            if r.dim != q.dim:
                raise ValueError_("adding quantities of different dimensions")
            q = Dimensioned(q.value + r.value if op == "+" else q.value - r.value, q.dim, q.has_units or r.has_units)
        return q

    def term(self):
        q = self.factor()
        while True:
            kind, val = self.peek()
            if val in ("*", "/"):
                self.take()
                r = self.factor()
                q = _mul(q, r) if val == "*" else _div(q, r)
            elif kind == "name" or val == "(":
                q = _mul(q, self.factor())
            elif kind == "num":
                prev_kind, prev = self.toks[self.i - 1]
                what = "two numbers side by side" if prev_kind == "num" else "a number right after a factor"
                raise ValueError_(f"{what} ('{prev}' then '{val}'), not one number; "
                                  f"write an operator between them, such as '*'")
            else:
                return q

    def factor(self):
        kind, val = self.peek()
        if val in ("-", "+"):
            self.take()
            q = self.factor()
            return Dimensioned(-q.value if val == "-" else q.value, q.dim, q.has_units)
        return self.power()

    def power(self):
        base = self.atom()
        if self.peek()[1] in ("^", "**"):
            self.take()
            exp = self.factor()
            if exp.dim != _ONE or exp.has_units:
                raise ValueError_("an exponent must be a pure number")
            e = exp.value
            if not math.isfinite(e):
                raise ValueError_("an exponent must be a finite number")
            if base.dim != _ONE and (abs(e) > 64 or e != int(e)):
                raise ValueError_("a unit can only be raised to a whole power, at most 64")
            try:
                value = base.value**e
            except (OverflowError, ZeroDivisionError):
                raise ValueError_("the power overflows") from None
            if isinstance(value, complex):
                raise ValueError_("the power is not real")
            return Dimensioned(value, tuple(d * int(e) for d in base.dim) if base.dim != _ONE else _ONE, base.has_units)
        return base

    def atom(self):
        kind, val = self.take()
        if kind == "num":
            return Dimensioned(float(val), _ONE, False)
        if kind == "name":
            if val in CONSTANTS:
                return Dimensioned(CONSTANTS[val], _ONE, False)
            if val in UNITS:
                factor, dim = UNITS[val]
                return Dimensioned(factor, dim, True)
            if val.lower() in ("nan", "inf", "infinity"):
                raise ValueError_("not a finite number")
            raise ValueError_(f"unknown unit or name '{val}'{unit_hint(val)}")
        if val == "(":
            q = self.expr()
            if self.take()[1] != ")":
                raise ValueError_("missing ')'")
            return q
        if val is None:
            raise ValueError_("the value ends too early")
        raise ValueError_(f"unexpected '{val}'")


def parse_quantity(text: str) -> Dimensioned:
    text = str(text).strip()
    if len(text) > 200:
        raise ValueError_("value too long")
    try:
        q = _Parser(tokens(text)).parse()
    except RecursionError:
        raise ValueError_("value nested too deeply") from None
    except OverflowError:
        raise ValueError_("not a finite number") from None
    if not math.isfinite(q.value):
        raise ValueError_("not a finite number")
    return q


def parse_unit(unit: str) -> tuple[float, tuple]:
    """The SI factor and dimension of a catalogue unit string (``kg*m^2``, ``1/(m^2 s^2)``, ``1``)."""
    if unit.strip() == "1":
        return 1.0, _ONE
    q = parse_quantity(unit)
    return q.value, q.dim


@functools.lru_cache(maxsize=512)
def si_exponents(unit: str) -> tuple[int, int, int] | None:
    """The (kg, m, s) exponents of a coherent SI catalogue unit ("kg*m^2" -> (1, 2, 0), "1/(m^2 s^2)",
    "rad/s" -> (0, 0, -1): the radian counts as 1); None for a unit with a factor (cm) or not read."""
    try:
        factor, (length, mass, time, _angle) = parse_unit(unit)
    except ValueError_:
        return None
    return (mass, length, time) if factor == 1.0 else None


def to_si(text: str, unit: str) -> float:
    """The value of ``text`` in the SI unit ``unit``; ``ValueError_`` with a user-facing reason otherwise."""
    q = parse_quantity(text)
    if not q.has_units:
        return q.value
    factor, target = parse_unit(unit)
    if q.dim == target:
        return q.value / factor
    diff = tuple(a - b for a, b in zip(q.dim, target))
    non_angle_nontrivial = any(target[:3])
    if non_angle_nontrivial and diff == (0, 0, 0, 1):
        return q.value / TURN / factor
    if non_angle_nontrivial and diff == (0, 0, 0, -1):
        return q.value / factor
    got = _DIM_NAMES.get(q.dim, "of other units")
    want = _DIM_NAMES.get(target, f"in {unit}")
    raise ValueError_(f"'{text}' is {got}, but the parameter is {want} ({unit})")
