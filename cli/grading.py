"""Checking your own answers: ``mech solve --expect``, ``mech grade FILE`` and ``mech check`` baselines.

Parsing and drawing only; the judging is ``mech.solvers.answers``, the baseline
comparison ``mech.solvers.baseline``.
"""

from __future__ import annotations

import json
import math
import re
import sys
import time
import tomllib
from dataclasses import dataclass, field
from xml.etree import ElementTree as ET

import click

from mech.cli.values import CONSTANTS, ValueError_, _tokens, to_si
from mech.problems.spec import BadInput, Exercise
from mech.solvers.answers import Expectation, judge

__all__ = ["parse_expectation", "parse_expect_options", "attach", "grade_cmd"]


# -- one expected value ---------------------------------------------------------------------------------

def _literal_precision(literal: str) -> tuple[float, int | None]:
    """Half a unit in the last digit of a number as written, and its significant digits.

    ``35.26`` -> (0.005, 4); ``1e-3`` -> (5e-4, 1); ``3500`` -> (0.5, 4): trailing zeros of a whole
    number count (write ``3.5e3`` for two digits); ``0.000`` -> (5e-4, None).
    """
    mantissa, _, exp = literal.lower().partition("e")
    exponent = int(exp) if exp else 0
    whole, _, frac = mantissa.partition(".")
    last_place = exponent - len(frac)
    digits = (whole + frac).lstrip("0")
    return 0.5 * 10.0**last_place, (len(digits) or None)


def _unit_factor(text: str, toks: list[tuple[str, str]], i: int, unit: str) -> tuple[float, str]:
    """SI size of the unit written around the literal at token ``i`` (sign included), and that unit as
    written when it follows the literal alone (``35.26 deg`` -> ``deg``)."""
    factor = to_si(" ".join("1" if j == i else v for j, (_, v) in enumerate(toks)), unit)
    leads = i == 0 or (i == 1 and toks[0][1] in ("-", "+"))
    unit_text = text.split(toks[i][1], 1)[1].strip() if leads else ""
    return factor, unit_text


def parse_expectation(ex: Exercise, raw_name: str, text, rtol: float | None = None) -> Expectation:
    """``theta_c``, ``35.26deg`` -> an Expectation in SI; BadInput naming the output otherwise."""
    name = str(raw_name).strip().replace("-", "_")
    outputs = {o.name: o for o in ex.outputs}
    if name not in outputs:
        raise BadInput(f"{raw_name}: not an output of {ex.id}; its outputs are: {', '.join(outputs)}")
    unit = outputs[name].unit
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise BadInput(f"{name}: expected a number or a string such as '1.23 {unit}', got {type(text).__name__}")
    text = str(text)
    try:
        value = to_si(text, unit)
        toks = _tokens(text)
    except ValueError_ as exc:
        why = str(exc).replace("but the parameter is", f"but {name} is")
        raise BadInput(f"{name}: cannot use '{text}': {why}" + ("" if why != str(exc) else f" ({name} is in {unit})")) from None
    # the literals that set the value (not exponents of units such as the 2 of m/s^2)
    literals = [i for i, (k, _) in enumerate(toks) if k == "num"
                and not (i > 0 and toks[i - 1][1] in ("^", "**"))
                and not (i > 1 and toks[i - 1][1] in ("-", "+") and toks[i - 2][1] in ("^", "**"))]
    exact = len(literals) != 1 or any(k == "name" and v in CONSTANTS for k, v in toks)
    if exact:
        return Expectation(name, text, value, 0.0, None, rtol)
    half_unit, digits = _literal_precision(toks[literals[0]][1])
    factor, unit_text = _unit_factor(text, toks, literals[0], unit)
    return Expectation(name, text, value, half_unit * abs(factor), digits, rtol, unit_text, abs(factor))


def parse_rtol_value(text, what: str = "--expect-rtol") -> float:
    try:
        value = to_si(str(text), "1") if not isinstance(text, bool) else math.nan
    except ValueError_ as exc:
        raise BadInput(f"{what}: cannot use '{text}': {exc}; allowed (0, 1)") from None
    if not (0 < value < 1):
        raise BadInput(f"{what}: {text} is out of range; allowed (0, 1)")
    return value


def parse_expect_options(ex: Exercise, pairs: list[str], rtol_text: str | None) -> list[Expectation]:
    """The ``--expect NAME=VALUE`` options of ``mech solve``; BadInput on the first bad one."""
    if rtol_text is not None and not pairs:
        raise BadInput("--expect-rtol: given without any --expect NAME=VALUE")
    rtol = parse_rtol_value(rtol_text) if rtol_text is not None else None
    out: dict[str, Expectation] = {}
    for pair in pairs:
        if "=" not in pair:
            raise BadInput(f"--expect takes NAME=VALUE, got '{pair}'")
        try:
            e = parse_expectation(ex, *pair.split("=", 1), rtol=rtol)
        except BadInput as exc:
            raise BadInput(f"--expect {exc}") from None
        if e.name in out:
            raise BadInput(f"--expect {e.name}: given more than once")
        out[e.name] = e
    return list(out.values())


def attach(result, expectations: list[Expectation]) -> bool:
    """Judge and hang the judgements on the cross-check result (``result.expected``, read by the table);
    True when every expected value matches."""
    judgements = judge(result, expectations)
    result.expected = {j.name: j for j in judgements}
    refs = sorted({j.reference for j in judgements if j.reference})
    right = sum(j.match for j in judgements)
    result.expect_summary = (f"your answers: {right} of {len(judgements)} right"
                             + (f" (judged against mech's {', '.join(refs)} value{'s' if len(judgements) > 1 else ''})"
                                if refs else ""))
    return right == len(judgements)


def solve_json(result) -> dict:
    """``result.as_json()`` with each expected quantity's ``expected`` and the top-level ``expect_ok``."""
    d = result.as_json()
    expected = getattr(result, "expected", None)
    if expected is not None:
        for q in d["quantities"]:
            if q["name"] in expected:
                q["expected"] = expected[q["name"]].as_json()
        d["expect_ok"] = all(j.match for j in expected.values())
    return d
