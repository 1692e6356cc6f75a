"""Parse the values people type: ``90deg``, ``90 deg``, ``pi/3``, ``2.5 km``, ``3 m/s^2``, ``100 rpm``.

The tokenizer and grammar here are the project's only ones: ``parse`` lends them to a student's formula
(``students.formula_ast`` gives the parts their meaning there: a tree to evaluate and dimension-check).

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

__all__ = ["ValueError_", "Dimensioned", "parse", "parse_quantity", "tokens", "parse_unit", "si_exponents", "to_si",
           "UNITS"]


class ValueError_(ValueError):
    """A value that cannot be read or converted; the message is user-facing."""


class UnknownName(ValueError_):
    """A name that is no unit or constant; its did-you-mean is worked out only when the message is read (a
    formula tried first as a value fails here on every parameter name, and the hint is never shown)."""

    def __init__(self, name: str):
        super().__init__(name)
        self.name = name

    def __str__(self) -> str:
        return f"unknown unit or name '{self.name}'{unit_hint(self.name)}"


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
# the units as a student spells them out: both spellings, singular and plural
_SPELLED = {
    "metre": "m", "meter": "m", "kilometre": "km", "kilometer": "km", "centimetre": "cm", "centimeter": "cm",
    "millimetre": "mm", "millimeter": "mm", "micrometre": "um", "micrometer": "um",
    "mile": "mi", "kilogram": "kg", "gram": "g", "gramme": "g", "milligram": "mg", "tonne": "t",
    "second": "s", "sec": "s", "millisecond": "ms", "microsecond": "us", "minute": "min", "hour": "h",
    "hr": "h", "day": "day", "year": "yr", "turn": "turn", "revolution": "rev", "rev": "rev",
    "newton": "N", "joule": "J", "watt": "W",
}
UNITS.update({w: UNITS[u] for word, u in _SPELLED.items() for w in (word, word + "s")})
UNITS.update({"hertz": UNITS["Hz"], "kilohertz": UNITS["kHz"], "inches": UNITS["inch"]})
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


_NUM = r"(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
# a value: ASCII names, no comma; a formula: names in any alphabet and commas between a function's arguments
_TOKEN = re.compile(rf"\s*(?:{_NUM}|(?P<name>[A-Za-z_]\w*)|(?P<op>\*\*|[-+*/^()])|(?P<bad>\S))")
_FORMULA_TOKEN = re.compile(rf"\s*(?:{_NUM}|(?P<name>[^\W\d]\w*)|(?P<op>\*\*|[-+*/^(),])|(?P<bad>\S))")
_REPLACE = (("·", "*"), ("×", "*"), ("°", "deg"), ("π", " pi "), ("µ", "u"))  # 2π√x: a name apiece
_FORMULA_REPLACE = _REPLACE + (("−", "-"), ("√", " sqrt "), ("²", "^2"), ("³", "^3"), ("⁴", "^4"),
                                   ("½", "(1/2)"))


def tokens(text: str, symbols: dict[str, str] | None = None, formula: bool = False) -> list[tuple[str, str]]:
    """The (kind, text) tokens of a typed value: numbers, names, operators, parentheses.

    ``formula``: the wider alphabet of a formula (names in any script, ``,``, ``−``, ``√``, ``²``); each
    of ``symbols`` (``θ₀``, ``m'``, ``h/R``: symbol -> name) is then one name token, the name it stands for.
    """
    for ch in text:  # a control or invisible character (U+001F, U+0085, U+200B) is never part of a value
        if not ch.isprintable() and ch not in " \t":
            raise ValueError_(f"unexpected character '{ascii(ch)[1:-1]}'")
    pattern, replace = (_FORMULA_TOKEN, _FORMULA_REPLACE) if formula else (_TOKEN, _REPLACE)
    for a, b in replace:
        text = text.replace(a, b)
    syms = sorted((s for s in symbols or () if s), key=len, reverse=True)
    out = []
    pos = 0
    n = len(text)
    while pos < n:
        if syms:
            while pos < n and text[pos].isspace():
                pos += 1
            hit = _symbol_at(text, pos, syms)
            if hit is not None:
                out.append(("name", symbols[hit]))
                pos += len(hit)
                continue
        m = pattern.match(text, pos)
        if not m or m.end() == pos:
            break
        pos = m.end()
        kind = m.lastgroup
        if kind == "bad":
            ch = m.group(kind)
            if ch == "," and out and out[-1][0] == "num":
                decimal_comma(out[-1][1], text[pos:])
            raise ValueError_(f"unexpected character '{ch if ch.isprintable() else ascii(ch)[1:-1]}'")
        tok = m.group(kind)
        if tok == "," and text[m.start(kind) - 1:m.start(kind)].isdigit() and text[pos:pos + 1].isdigit():
            kind = "comma"  # glued between digits (``0,5``): a decimal comma where no comma belongs
        out.append((kind, tok))
    return out


def decimal_comma(before: str, after: str) -> None:
    """A comma between two digits (``0,00113``) is a decimal comma: ``ValueError_`` saying how to write the
    number (three digits after it may be a thousands separator: both readings are named)."""
    m = re.match(_NUM, after)
    if not before[-1:].isdigit() or m is None or not after[:1].isdigit():
        return
    digits = m.group("num")
    if re.fullmatch(r"\d{3}", digits) and before.isdigit() and before[0] != "0":
        raise ValueError_(f"write {before}.{digits} (or {before}{digits}): the decimal point is '.', and "
                          "numbers have no thousands separator")
    raise ValueError_(f"write {before}.{digits}: the decimal point is '.'")


def _symbol_at(text: str, pos: int, syms: list[str]) -> str | None:
    """The longest symbol starting a word at ``pos`` and ending one (``M'`` in ``3M'``, not in ``xM'``)."""
    if pos >= len(text) or (pos > 0 and ((text[pos - 1].isalnum() and not text[pos - 1].isdigit())
                                         or text[pos - 1] == "_")):
        return None  # a digit before is a number's last (``3M'``): a name's would have taken the symbol in
    for s in syms:
        end = pos + len(s)
        if text.startswith(s, pos) and not (end < len(text) and (text[end].isalnum() or text[end] in "_'")):
            return s
    return None


class _Parser:
    """The one grammar of values and formulas:

        expr := term (('+'|'-') term)*;  term := unary (('*'|'/'|adjacent) unary)*;
        unary := ('-'|'+') unary | power;  power := atom (('^'|'**') unary)?;
        atom := number | name | function '(' expr (',' expr)* ')' | '(' expr ')'

    What the parts mean is the ``build``'s: a value's (``_Value``: a number with its dimension, computed as
    it is read) or a formula's (a tree, ``students.formula_ast``).  ``build.function(name)`` says whether
    a name is a function and its number of arguments.  ``max_depth`` bounds the nesting (None: the length of
    the text does)."""

    def __init__(self, tokens, build, what: str = "value", max_depth: int | None = None):
        self.toks = tokens
        self.i = 0
        self.build = build
        self.what = what
        self.max_depth = max_depth
        self.depth = 0

    def peek(self):
        return self.toks[self.i] if self.i < len(self.toks) else (None, None)

    def take(self):
        tok = self.peek()
        self.i += 1
        return tok

    def enter(self):
        self.depth += 1
        if self.max_depth is not None and self.depth > self.max_depth:
            raise ValueError_(f"{self.what} nested too deeply (more than {self.max_depth} levels)")

    def parse(self):
        if not self.toks:
            raise ValueError_(f"empty {self.what}")
        q = self.expr()
        if self.i != len(self.toks):
            self.decimal_comma(self.i)
            raise ValueError_(f"unexpected '{self.peek()[1]}'")
        return q

    def decimal_comma(self, i: int) -> None:
        """Token ``i`` a comma between two numbers (``0,5``) where no comma belongs: say how to write it."""
        if 0 < i < len(self.toks) - 1 and self.toks[i][0] == "comma" and self.toks[i - 1][0] == "num" \
                and self.toks[i + 1][0] == "num":
            decimal_comma(self.toks[i - 1][1], self.toks[i + 1][1])

    def expr(self):
        self.enter()
        q = self.term()
        while self.peek()[1] in ("+", "-"):
            op = self.take()[1]
            q = self.build.binary(op, q, self.term())
        self.depth -= 1
        return q

    def term(self):
        q = self.unary()
        while True:
            kind, val = self.peek()
            if val in ("*", "/"):
                self.take()
                q = self.build.binary(val, q, self.unary())
            elif kind == "name" or val == "(":
                q = self.build.binary("*", q, self.unary())
            elif kind == "num" and val == "1" and self._unit_after_one():
                # a unit as mech prints it after a number: ``0.0643 1/s`` is 0.0643 (1/s)
                q = self.build.binary("*", q, self.unary())
            elif kind == "num":
                prev_kind, prev = self.toks[self.i - 1]
                what = "two numbers side by side" if prev_kind == "num" else "a number right after a factor"
                raise ValueError_(f"{what} ('{prev}' then '{val}'), not one number; "
                                  f"write an operator between them, such as '*'")
            else:
                return q

    def _unit_after_one(self) -> bool:
        """``1/s``, ``1/(m^2 s)`` after a number: a ``1`` followed by ``/`` and a name or a parenthesis."""
        nxt = self.toks[self.i + 1:self.i + 3]
        return len(nxt) == 2 and nxt[0][1] == "/" and (nxt[1][0] == "name" or nxt[1][1] == "(")

    def unary(self):
        self.enter()
        kind, val = self.peek()
        if val in ("-", "+"):
            self.take()
            q = self.unary()
            q = self.build.neg(q) if val == "-" else self.build.plus(q)
        else:
            q = self.power()
        self.depth -= 1
        return q

    def power(self):
        base = self.atom()
        if self.peek()[1] in ("^", "**"):
            self.take()
            return self.build.binary("^", base, self.unary())
        return base

    def atom(self):
        kind, val = self.take()
        if kind == "num":
            return self.build.number(val)
        if kind == "name":
            arity = self.build.function(val)
            if arity is None:
                return self.build.name(val)
            if self.peek()[1] != "(":
                raise ValueError_(f"'{val}' is a function: write {val}(...)")
            self.take()
            start = self.i
            args = [self.expr()]
            while self.peek()[1] == ",":
                self.take()
                args.append(self.expr())
            if self.take()[1] != ")":
                raise ValueError_(f"missing ')' after the argument of {val}")
            if len(args) != arity:
                for j in range(start, self.i):
                    self.decimal_comma(j)
                raise ValueError_(f"{val} takes {arity} argument{'s' if arity > 1 else ''}, got {len(args)}")
            return self.build.call(val, args)
        if val == "(":
            q = self.expr()
            self.decimal_comma(self.i)
            if self.take()[1] != ")":
                raise ValueError_("missing ')'")
            return q
        if val is None:
            raise ValueError_(f"the {self.what} ends too early")
        raise ValueError_(f"unexpected '{val}'")


class _Value:
    """What a value's parts mean: numbers with a dimension, computed as they are read."""

    @staticmethod
    def function(name):
        return None  # a value has no functions: ``sqrt`` is an unknown name

    @staticmethod
    def number(text):
        return Dimensioned(float(text), _ONE, False)

    @staticmethod
    def name(val):
        if val in CONSTANTS:
            return Dimensioned(CONSTANTS[val], _ONE, False)
        if val in UNITS:
            factor, dim = UNITS[val]
            return Dimensioned(factor, dim, True)
        if val.lower() in ("nan", "inf", "infinity"):
            raise ValueError_("not a finite number")
        raise UnknownName(val)

    @staticmethod
    def neg(q):
        return Dimensioned(-q.value, q.dim, q.has_units)

    @staticmethod
    def plus(q):
        return q

    @staticmethod
    def binary(op, q, r):
        if op in ("+", "-"):
            if r.dim != q.dim:
                raise ValueError_("adding quantities of different dimensions")
            return Dimensioned(q.value + r.value if op == "+" else q.value - r.value, q.dim, q.has_units or r.has_units)
        if op == "*":
            return _mul(q, r)
        if op == "/":
            return _div(q, r)
        return _power(q, r)


def _power(base: Dimensioned, exp: Dimensioned) -> Dimensioned:
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


def parse(text: str, build, what: str = "formula", max_depth: int | None = None, symbols=None):
    """Read ``text`` with the one grammar, ``build`` giving its parts their meaning (see ``_Parser``);
    ``ValueError_`` (one line) when it cannot be read.  The caller bounds the length."""
    toks = tokens(text, symbols, formula=True)
    try:
        return _Parser(toks, build, what, max_depth).parse()
    except RecursionError:
        raise ValueError_(f"{what} nested too deeply (more than {max_depth} levels)") from None


def parse_quantity(text: str) -> Dimensioned:
    text = str(text).strip(" \t")  # not str.strip(): a control character is refused, not dropped
    if len(text) > 200:
        raise ValueError_("value too long")
    try:
        q = _Parser(tokens(text), _Value).parse()
    except RecursionError:
        raise ValueError_("value nested too deeply") from None
    except OverflowError:
        raise ValueError_("not a finite number") from None
    if not math.isfinite(q.value):
        raise ValueError_("not a finite number")
    return q


@functools.lru_cache(maxsize=512)
def parse_unit(unit: str) -> tuple[float, tuple]:
    """The SI factor and dimension of a catalogue unit string (``kg*m^2``, ``1/(m^2 s^2)``, ``1``): read
    once per string (an assignment reads its few units back thousands of times)."""
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
