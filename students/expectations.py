"""One expected value: a number with its unit, an expression or a formula, as ``--expect NAME=VALUE``, an
answers file's ``expect`` and a CSV cell write it; read into ``answers.Expectation``, judged by
``mech.students.answers``."""

from __future__ import annotations

import math

from mech.core.units import CONSTANTS, ValueError_, tokens, to_si
from mech.problems.spec import BadInput, Exercise
from mech.core.safeio import shown

__all__ = ["MIN_DIGITS", "parse_expectation", "parse_expect_options", "parse_count", "parse_rtol_value", "with_range", "attach"]


MIN_DIGITS = 2  # an answer with fewer significant digits is judged as if written to this many


def _literal_precision(literal: str, min_digits: int = 0) -> tuple[float, int | None]:
    """Half a unit in the last digit of a number as written, and its significant digits; a number with
    fewer than ``min_digits`` significant digits is taken as written to ``min_digits`` of them.

    ``35.26`` -> (0.005, 4); ``1e-3`` -> (5e-4, 1) (with min_digits 2: (5e-5, 2)); ``3500`` -> (0.5, 4):
    trailing zeros of a whole number count (write ``3.5e3`` for two digits); a zero in any form (``0``,
    ``0e300``, ``0.000``) -> (0.0, None): zero is zero, whatever exponent it is written with.
    """
    mantissa, _, exp = literal.lower().partition("e")
    exponent = int(exp) if exp else 0
    whole, _, frac = mantissa.partition(".")
    last_place = exponent - len(frac)
    digits = (whole + frac).lstrip("0")
    if not digits:
        return 0.0, None
    if len(digits) < min_digits:
        lead = (whole + frac).index(digits[0])  # the leading significant digit's place, counted from the left
        lead_place = exponent + len(whole) - 1 - lead
        last_place = min(last_place, lead_place - min_digits + 1)
        return 0.5 * 10.0**last_place, min_digits
    return 0.5 * 10.0**last_place, len(digits)


def _unit_factor(text: str, toks: list[tuple[str, str]], i: int, unit: str) -> tuple[float, str]:
    """SI size of the unit written around the literal at token ``i`` (sign included), and that unit as
    written when it follows the literal alone (``35.26 deg`` -> ``deg``)."""
    factor = to_si(" ".join("1" if j == i else v for j, (_, v) in enumerate(toks)), unit)
    leads = i == 0 or (i == 1 and toks[0][1] in ("-", "+"))
    unit_text = text.split(toks[i][1], 1)[1].strip() if leads else ""
    return factor, unit_text


def parse_expectation(ex: Exercise, raw_name: str, text, rtol: float | None = None, *,
                      min_digits: int | None = None) -> Expectation:
    """``theta_c``, ``35.26deg`` -> an Expectation in SI; BadInput naming the output otherwise.  ``none``:
    the answer that the output has no value at these parameters.  ``min_digits``: the digits rule's floor
    (``--min-digits``, an assignment's digits; None: ``MIN_DIGITS``): a number with fewer significant
    digits is judged as if written to that many."""
    min_digits = MIN_DIGITS if min_digits is None else int(min_digits)
    from mech.students.answers import Expectation

    name = str(raw_name).strip().replace("-", "_")
    outputs = {o.name: o for o in ex.outputs}
    if name not in outputs:
        raise BadInput(f"{raw_name}: not an output of {ex.id}; its outputs are: {', '.join(outputs)}")
    unit = outputs[name].unit
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise BadInput(f"{name}: expected a number or a string such as '1.23 {unit}', got {type(text).__name__}")
    text = str(text)
    from dataclasses import replace

    if text.strip().lower() == "none":  # no value here: right where mech finds none
        return Expectation(name, text, math.nan, none=True)
    try:
        value = to_si(text, unit)
        toks = tokens(text)
    except ValueError_ as exc:
        formula = _formula(ex, name, text)
        if formula is not None:
            return replace(formula, rtol=rtol)
        why = str(exc).replace("but the parameter is", f"but {name} is")
        raise BadInput(f"{name}: cannot use '{shown(text)}': {why}" + ("" if why != str(exc) else f" ({name} is in {unit})")) from None
    # a value that names a parameter is a formula (``E=m*g*l``), unless it reads as a number of the
    # output's dimension and the formula would not have it (``x=3 m`` in 4.7, whose m is a mass)
    formula = _formula(ex, name, text, parameters_only=True, unit=unit)
    if formula is not None:
        return replace(formula, rtol=rtol)
    # the literals that set the value (not exponents of units such as the 2 of m/s^2)
    literals = [i for i, (k, _) in enumerate(toks) if k == "num"
                and not (i > 0 and toks[i - 1][1] in ("^", "**"))
                and not (i > 1 and toks[i - 1][1] in ("-", "+") and toks[i - 2][1] in ("^", "**"))]
    if len(literals) != 1 or any(k == "name" and v in CONSTANTS for k, v in toks):
        return _expression_expectation(name, text, value, [toks[i][1] for i in literals], rtol, min_digits)
    try:
        half_unit, digits = _literal_precision(toks[literals[0]][1], min_digits)
    except OverflowError:
        raise BadInput(f"{name}: cannot use '{shown(text)}': an exponent too large") from None
    factor, unit_text = _unit_factor(text, toks, literals[0], unit)
    return Expectation(name, text, value, half_unit * abs(factor), digits, rtol, unit_text, abs(factor))


def _formula(ex: Exercise, name: str, text: str, parameters_only: bool = False, unit: str | None = None):
    """An Expectation holding a formula when ``text`` is one (it names a parameter or a function), else
    None; BadInput (one line) when it is a formula mech cannot read.  ``parameters_only``: for a text that
    also reads as a number: a formula only if it names a parameter and has the dimension of ``unit``."""
    from mech.students.answers import Expectation
    from mech.students.formula_ast import (MAX_LENGTH, FormulaError, dim_of_unit, looks_like_formula,
                                               parse_formula)

    if len(text) > MAX_LENGTH:
        raise BadInput(f"{name}: formula too long ({len(text)} characters; at most {MAX_LENGTH})")
    if not looks_like_formula(text, ex, parameters_only):
        return None
    try:
        f = parse_formula(text, ex)
    except FormulaError as exc:
        if parameters_only:
            return None
        raise BadInput(f"{name}: cannot use the formula '{shown(text, 60)}': {exc}") from None
    if parameters_only and (not f.names or f.dim != dim_of_unit(unit)[1]):
        return None
    return Expectation(name, text, math.nan, formula=f)


def _short(text: str, n: int = 60) -> str:
    return text if len(text) <= n else text[: n - 3] + "..."


def with_range(expectations: list, points=None, seed=None, over=None) -> list:
    """The formula expectations given the number of drawn points, the seed and the range (others as they are)."""
    from dataclasses import replace

    return [replace(e, points=points if points is not None else e.points, seed=seed if seed is not None else e.seed,
                    over=tuple(sorted(over.items())) if over else e.over) if e.formula is not None else e
            for e in expectations]


def parse_count(text, what: str, lo: int, hi: int) -> int | None:
    """A whole number in [lo, hi] (None when not given); BadInput naming the option otherwise."""
    if text is None:
        return None
    try:
        value = None if isinstance(text, bool) else text if isinstance(text, int) else int(str(text).strip()[:40])
    except ValueError:
        value = None
    if value is None or not lo <= value <= hi:
        raise BadInput(f"{what}: cannot use '{shown(text, 40)}': allowed a whole number in [{lo}, {hi}]")
    return value


def _expression_expectation(name: str, text: str, value: float, literals: list[str], rtol,
                            min_digits: int = MIN_DIGITS) -> Expectation:
    """An expression (``(9.81*0.866)^0.5``, ``2*pi/921.5``) is judged to the digits of its least precise
    number, relative: a whole number written without a point or an exponent (the 2 of ``2*pi``) and
    ``pi`` are exact, and an expression of exact numbers only is exact (no written tolerance)."""
    from mech.students.answers import Expectation

    worst = None  # (relative half unit, digits, literal) of the least precise number
    for lit in literals:
        if not any(c in lit.lower() for c in ".e"):
            continue
        try:
            half_unit, digits = _literal_precision(lit, min_digits)
            size = abs(float(lit))
        except (OverflowError, ValueError):
            continue
        if not digits or not (size > 0 and math.isfinite(size)):
            continue
        rel = half_unit / size
        if worst is None or rel > worst[0]:
            worst = (rel, digits, lit)
    if worst is None:
        return Expectation(name, text, value, 0.0, None, rtol)
    rel, digits, lit = worst
    return Expectation(name, text, value, rel * abs(value), digits, rtol, least_precise=lit)


def parse_rtol_value(text, what: str = "--expect-rtol") -> float:
    try:
        value = to_si(str(text), "1") if not isinstance(text, bool) else math.nan
    except ValueError_ as exc:
        raise BadInput(f"{what}: cannot use '{shown(text)}': {exc}; allowed (0, 1)") from None
    if not (0 < value < 1):
        raise BadInput(f"{what}: {text} is out of range; allowed (0, 1)")
    return value


def parse_expect_options(ex: Exercise, pairs: list[str], rtol_text: str | None,
                         min_digits: int = MIN_DIGITS) -> list[Expectation]:
    """The ``--expect NAME=VALUE`` options of ``mech solve`` (``--min-digits``: ``min_digits``); BadInput on
    the first bad one."""
    if rtol_text is not None and not pairs:
        raise BadInput("--expect-rtol: given without any --expect NAME=VALUE")
    rtol = parse_rtol_value(rtol_text) if rtol_text is not None else None
    out: dict[str, Expectation] = {}
    for pair in pairs:
        if "=" not in pair:
            raise BadInput(f"--expect takes NAME=VALUE, got '{shown(pair)}'")
        try:
            e = parse_expectation(ex, *pair.split("=", 1), rtol=rtol, min_digits=min_digits)
        except BadInput as exc:
            raise BadInput(f"--expect {exc}") from None
        if e.name in out:
            raise BadInput(f"--expect {e.name}: given more than once")
        out[e.name] = e
    return list(out.values())


def attach(result, expectations: list[Expectation]):
    """The solution with every expectation judged on its quantity (``Quantity.expected``) and the summary
    line (``expect_summary``); ``.expect_ok`` says whether every expected value matches."""
    from mech.students.answers import judge

    return result.with_expected(judge(result, expectations))


