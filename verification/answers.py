"""Judging a user's own answers against mech's: the reference, the tolerance, the slip that explains a miss.

Verification logic only: the physics stays in the exercise, whose own analytic
solver is the only thing called here (to evaluate a slip such as "g doubled").

The reference of an output is

* for a leading-order theory: the numeric value (verified by the rerun at
  rtol/10), with the size of what the theory neglects added to the tolerance:
  the exercise asks for the leading-order answer, which is right to that much;
* for an exact theory: the analytic value, when the numeric one confirms it;
* with one method only: that method's value, labelled "not cross-checked".

An output whose two values disagree has no trusted reference: no answer to it
is judged right.

A value matches when it is within its own tolerance (half a unit in the last
written digit, or ``rtol`` times the reference) plus the reference's error bar
(``numeric_err`` or ``analytic_err``) plus ``ROUND_OFF`` relative.  A miss gets
a hint when one common slip (a factor 2, a sign, pi, degrees for radians, a
swapped pair, g left out or doubled) moves the reference onto the value within
the same tolerance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from mech.problems.spec import Undefined

__all__ = ["Expectation", "Judgement", "judge", "numeric_err", "ROUND_OFF"]

# floating-point slack of a value computed through a formula of a few dozen operations (relative)
ROUND_OFF = 1e-12


@dataclass(frozen=True)
class Expectation:
    """A user's value for one output.

    ``written_tol``: half a unit in the last written digit, absolute, SI (0 for an exact expression such
    as ``pi/3``); ``digits``: the significant digits written (None for an expression); ``rtol``: a
    relative tolerance that replaces the written digits; ``unit_text``/``unit_factor``: the unit the value
    was written in and its SI size, for showing mech's value the same way.
    """

    name: str
    text: str
    value: float
    written_tol: float = 0.0
    digits: int | None = None
    rtol: float | None = None
    unit_text: str = ""
    unit_factor: float = 1.0

    def own_tol(self, reference: float) -> float:
        """The tolerance the user's writing earns, absolute, for a reference value."""
        return self.rtol * abs(reference) if self.rtol is not None else self.written_tol


@dataclass
class Judgement:
    name: str
    unit: str
    text: str
    value: float
    match: bool
    reference: str | None  # "analytic", "numeric", ... or None: nothing to judge against
    reference_value: float | None = None
    rel_err: float | None = None
    tol: float | None = None  # the absolute tolerance applied, SI
    hint: str | None = None
    verdict: str = ""
    shown_reference: str = ""  # mech's value in the unit the user wrote

    def as_json(self) -> dict:
        return {"value": self.value, "match": self.match, "rel_err": _finite(self.rel_err), "hint": self.hint,
                "text": self.text, "reference": self.reference, "reference_value": _finite(self.reference_value),
                "tol": _finite(self.tol), "verdict": self.verdict}


def _finite(v):
    return v if isinstance(v, float) and math.isfinite(v) else None


def _number(v) -> bool:
    return isinstance(v, float) and math.isfinite(v)


def numeric_err(q) -> float:
    """The numeric value's error bar, absolute: the cross-check's ``numeric_err`` where it gives one,
    else the numeric claim (``tol`` relative plus ``tol_abs``)."""
    err = getattr(q, "numeric_err", None)
    if err is not None and math.isfinite(err):
        return float(err)
    return float(q.tol or 0.0) * abs(q.numeric) + float(q.tol_abs or 0.0)


def analytic_err(q) -> float:
    err = getattr(q, "analytic_err", None)
    return float(err) if err is not None and math.isfinite(err) else 0.0


@dataclass
class _Reference:
    value: float | None
    err: float = 0.0  # absolute error bar, SI (numeric_err or analytic_err)
    theory_err: float = 0.0  # absolute size of what a leading-order theory neglects
    label: str | None = None
    why: str = ""  # when there is no value to judge against
    unit: str = ""


def reference(q, errors: list[str]) -> _Reference:
    """What an answer to output ``q`` (a crosscheck Quantity) is held against."""
    a, n = q.analytic, q.numeric
    if errors or q.agree is False:
        why = "analytic and numeric disagree" if q.agree is False else errors[0]
        return _Reference(None, why=f"no trusted value: {why}")
    for v in (a, n):
        if isinstance(v, Undefined):
            return _Reference(None, why=f"mech finds no finite value here: {v.why}")
    if _number(n) and (q.theory != "exact" or not _number(a)):
        label = "numeric" if getattr(q, "verify_diff", None) is not None else "numeric (not verified)"
        theory = float(q.expected_err or 0.0) * abs(n) if q.theory != "exact" else 0.0
        return _Reference(n, numeric_err(q), theory, label, unit=q.unit)
    if _number(a):
        # both numbers reach here only when they agree (disagreement returned above)
        label = "analytic" if _number(n) else "analytic (not cross-checked)"
        return _Reference(a, analytic_err(q), 0.0, label, unit=q.unit)
    return _Reference(None, why="no value computed")


_PI = math.pi
_SCALINGS = [
    (2.0, "off by a factor 2"), (0.5, "off by a factor 1/2"), (-1.0, "wrong sign"),
    (_PI, "off by a factor pi"), (1 / _PI, "off by a factor 1/pi"),
    (2 * _PI, "off by a factor 2 pi"), (1 / (2 * _PI), "off by a factor 1/(2 pi)"),
    (math.sqrt(2.0), "off by a factor sqrt(2)"), (1 / math.sqrt(2.0), "off by a factor 1/sqrt(2)"),
]
_ANGLE_SCALINGS = [(180 / _PI, "degrees given as radians"), (_PI / 180, "radians given as degrees")]


def _has_angle(unit: str) -> bool:
    return "rad" in unit


class _GSlips:
    """The exercise's own analytic answers with g left out (g = 1 in SI) or doubled, computed once."""

    def __init__(self, result):
        self.result = result
        self._values: list[tuple[str, dict]] | None = None

    def values(self) -> list[tuple[str, dict]]:
        if self._values is None:
            self._values = []
            ex, params = self.result.exercise, self.result.params
            g_param = getattr(ex, "param_map", {}).get("g")
            if g_param is not None and g_param.unit == "m/s^2" and ex.has_analytic:
                g = float(params["g"])
                for phrase, g_slip in (("g left out (taken as 1)", 1.0), ("g doubled", 2.0 * g)):
                    if g_slip == g:
                        continue
                    try:
                        slipped = ex.resolve({**dict(params), "g": g_slip})
                        self._values.append((phrase, ex.solve_analytic(slipped)))
                    except Exception:  # out of bounds, or no answer there: that slip cannot be named
                        continue
        return self._values


def _hint(e: Expectation, q, ref: _Reference, refs: dict, expectations: dict, gslips: _GSlips) -> str | None:
    """The slip that moves the reference onto the user's value within the tolerance (the closest two)."""
    candidates: list[tuple[str, float, float]] = []  # (phrase, slipped value, its reference error)
    scalings = _SCALINGS + (_ANGLE_SCALINGS if _has_angle(q.unit) else [])
    for factor, phrase in scalings:
        candidates.append((phrase, factor * ref.value, (ref.err + ref.theory_err) * abs(factor)))
    for other, oref in refs.items():
        if other == q.name or oref.value is None or oref.unit != q.unit:
            continue
        o_exp = expectations.get(other)
        swapped = o_exp is not None and abs(o_exp.value - ref.value) <= _tol(o_exp, ref)
        phrase = f"swapped with {other}" if swapped else f"that is mech's {other}"
        candidates.append((phrase, oref.value, oref.err + oref.theory_err))
    for phrase, values in gslips.values():
        v = values.get(q.name)
        if _number(v) and ref.value != 0:
            candidates.append((phrase, v, (ref.err + ref.theory_err) * abs(v / ref.value)))
    fits = []
    for phrase, slipped, err in candidates:
        if not _number(slipped):
            continue
        tol = e.own_tol(slipped) + err + ROUND_OFF * abs(slipped)
        miss = abs(e.value - slipped)
        if miss <= tol:
            fits.append((miss / tol if tol > 0 else 0.0, phrase))
    # two slips can give the same value (g doubled and a factor sqrt(2) in sqrt(g/l)): name both
    phrases = list(dict.fromkeys(phrase for _, phrase in sorted(fits)))
    return " or ".join(phrases[:2]) or None


def _tol(e: Expectation, ref: _Reference) -> float:
    return e.own_tol(ref.value) + ref.err + ref.theory_err + ROUND_OFF * abs(ref.value)


def _digits_phrase(n: int | None) -> str:
    return "the digits written" if not n else f"{n} digit{'s' if n != 1 else ''}"


def _verdict_right(e: Expectation, ref: _Reference, diff: float) -> str:
    """Say what the match needed: the digits written, mech's own error bar, or the theory's neglect."""
    own = e.own_tol(ref.value)
    slack = ROUND_OFF * abs(ref.value)
    if diff > own + ref.err + slack:
        rel = ref.theory_err / abs(ref.value) if ref.value else 0.0
        return f"right within the {_percent(rel)} the leading-order theory neglects"
    if ref.err > own:  # mech cannot vouch for more digits than its error bar
        return f"right within mech's error bar ({ref.err:.2g})"
    if e.rtol is not None:
        return f"right within rtol {e.rtol:g}"
    if e.digits is None:
        return "right (exact expression)"
    return f"right to {_digits_phrase(e.digits)}"


def _percent(rel: float) -> str:
    pct = 100 * rel
    return f"{pct:.0f} %" if pct >= 10 else f"{pct:.2g} %"


def _verdict_off(e: Expectation, ref: _Reference, rel: float) -> str:
    if rel >= 10 and ref.value and e.value / ref.value > 0:
        return f"off by a factor {e.value / ref.value:.2g}"
    return f"off by {_percent(rel)}"


def _shown(e: Expectation, value: float | None) -> str:
    """mech's value written the way the user wrote theirs (same unit), with two digits more."""
    if value is None:
        return "—"
    digits = min(max((e.digits or 10) + 2, 4), 12)
    if e.unit_text and e.unit_factor:
        return f"{value / e.unit_factor:.{digits}g} {e.unit_text}"
    return f"{value:.{digits}g}"


def judge(result, expectations: list[Expectation]) -> list[Judgement]:
    """Judge every expectation against a cross-check result (``solvers.verification.crosscheck.CrossCheck``)."""
    quantities = {q.name: q for q in result.quantities}
    refs: dict[str, _Reference] = {}
    for name, q in quantities.items():
        refs[name] = reference(q, result.errors)
    by_name = {e.name: e for e in expectations}
    gslips = _GSlips(result)
    out = []
    for e in expectations:
        q = quantities[e.name]
        ref = refs[e.name]
        j = Judgement(e.name, q.unit, e.text, e.value, match=False, reference=ref.label)
        if ref.value is None:
            j.verdict = f"cannot judge: {ref.why}"
            out.append(j)
            continue
        j.reference_value = ref.value
        j.shown_reference = _shown(e, ref.value)
        j.tol = _tol(e, ref)
        diff = abs(e.value - ref.value)
        j.rel_err = diff / abs(ref.value) if ref.value != 0 else diff
        j.match = bool(diff <= j.tol)
        if j.match:
            j.verdict = _verdict_right(e, ref, diff)
        else:
            j.hint = _hint(e, q, ref, refs, by_name, gslips)
            j.verdict = f"{j.hint or _verdict_off(e, ref, j.rel_err)} (mech: {j.shown_reference})"
        out.append(j)
    return out
