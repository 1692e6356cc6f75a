"""Judging a user's own answers against mech's: the reference, the tolerance, the slip that explains a miss.

Verification logic only: the physics stays in the exercise, whose own analytic
solver is the only thing called here (to evaluate a slip such as "g doubled"),
and whose declared approximations (``Exercise.approximations``) name a known
approximation given for an exact output.

The reference of an output is

* for an exact theory: the analytic value, when the numeric one confirms it;
* for a leading-order theory: the exact value, i.e. the numeric one (verified
  by the rerun at rtol/10).  An answer is right when, to its digits, it equals
  the exact value ("right: the exact value") or, where the theory is inside
  its range, the leading-order value ("right to leading order; the exact value
  is X % away here").  Never by a band as wide as what the theory neglects.
  Outside the theory's range only the exact value is right, and the verdict
  says the theory does not apply there;
* with one method only: that method's value, labelled "not cross-checked".

An output whose two values disagree has no trusted reference: no answer to it
is judged right.

A value matches when it is within its own tolerance (half a unit in the last
written digit, or ``rtol`` times the reference) plus the reference's error bar
(``numeric_err`` or ``analytic_err``) plus ``ROUND_OFF`` relative.  An output
that is the direction of an axis (``Output.axis``) is judged modulo pi.  A miss
gets a hint when one common slip (a factor 2, a sign, pi, a power of ten,
degrees for radians, a swapped pair, g left out or doubled, another principal
axis, a declared approximation) moves the reference onto the value within a
unit in the last written digit (a slip and a rounding of the last digit).
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
    as ``pi/3``; for an expression with rounded numbers in it, ``(9.81*0.866)^0.5``, the relative half unit
    of its least precise number, ``least_precise``, times the value); ``digits``: the significant digits
    written (those of the least precise number of an expression; None for an exact one); ``rtol``: a
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
    least_precise: str | None = None

    def own_tol(self, reference: float) -> float:
        """The tolerance the user's writing earns, absolute, for a reference value."""
        return self.rtol * abs(reference) if self.rtol is not None else self.written_tol


@dataclass(frozen=True)
class Judgement:
    """The verdict on one expected value; ``matches`` (leading-order outputs only): which of mech's values
    the answer equals to its digits, "exact" or "leading-order", or None."""

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
    theory: str = "exact"
    matches: str | None = None

    def as_json(self) -> dict:
        d = {"value": self.value, "match": self.match, "rel_err": _finite(self.rel_err), "hint": self.hint,
             "text": self.text, "reference": self.reference, "reference_value": _finite(self.reference_value),
             "tol": _finite(self.tol), "verdict": self.verdict}
        if self.theory != "exact":
            d["matches"] = self.matches
        return d


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
    label: str | None = None
    why: str = ""  # when there is no value to judge against
    unit: str = ""
    leading: float | None = None  # a leading-order value inside its theory's range (right to its digits too)
    leading_err: float = 0.0
    outside: str | None = None  # why the leading-order theory does not apply here
    outside_value: float | None = None  # the leading-order value there (named, never right)


def _outside_reason(q) -> str | None:
    """Why the leading-order theory of ``q`` does not apply at its parameters, or None where it does."""
    if getattr(q, "theory_valid", None) is not False:
        return None
    notes = list(getattr(q, "notes", None) or [])
    if not notes and getattr(q, "note", None):
        notes = str(q.note).split("; ")
    for note in notes:
        if "outside its range" in note:
            return note.split("outside its range", 1)[1].lstrip(": ") or "outside its range"
    return "outside its range"


def reference(q, errors: list[str]) -> _Reference:
    """What an answer to output ``q`` (a crosscheck Quantity) is held against."""
    a, n = q.analytic, q.numeric
    if errors or q.agree is False:
        why = "analytic and numeric disagree" if q.agree is False else str(errors[0])
        return _Reference(None, why=f"no trusted value: {why}")
    for v in (a, n):
        if isinstance(v, Undefined):
            return _Reference(None, why=f"mech finds no finite value here: {v.why}")
    if _number(n) and (q.theory != "exact" or not _number(a)):
        label = "numeric" if getattr(q, "verify_diff", None) is not None else "numeric (not verified)"
        ref = _Reference(n, numeric_err(q), label, unit=q.unit)
        if q.theory != "exact" and _number(a):
            ref.outside = _outside_reason(q)
            if ref.outside is None:
                ref.leading, ref.leading_err = a, analytic_err(q)
            else:
                ref.outside_value = a
        return ref
    if _number(a):
        # both numbers reach here only when they agree (disagreement returned above)
        label = "analytic" if _number(n) else "analytic (not cross-checked)"
        return _Reference(a, analytic_err(q), label, unit=q.unit)
    return _Reference(None, why="no value computed")


_PI = math.pi
_SCALINGS = [
    (2.0, "off by a factor 2"), (0.5, "off by a factor 1/2"), (-1.0, "wrong sign"),
    (_PI, "off by a factor pi"), (1 / _PI, "off by a factor 1/pi"),
    (2 * _PI, "off by a factor 2 pi"), (1 / (2 * _PI), "off by a factor 1/(2 pi)"),
    (math.sqrt(2.0), "off by a factor sqrt(2)"), (1 / math.sqrt(2.0), "off by a factor 1/sqrt(2)"),
]
_ANGLE_SCALINGS = [(180 / _PI, "degrees given as radians"), (_PI / 180, "radians given as degrees")]
# a power of ten: the prefix slips of each SI base unit (a value written in cm where mech's unit is m, ...)
_PREFIXES = {"m": {2: "cm", 3: "mm", -3: "km"}, "kg": {3: "g"}, "s": {3: "ms"}}


def _power_phrase(k: int, unit: str) -> str:
    """``off by a power of ten (x100: cm given as m?)`` for a value 10**k times mech's."""
    base = unit.split("/", 1)[0].split("*", 1)[0].split("^", 1)[0].strip()
    prefix = _PREFIXES.get(base, {}).get(k) if base == unit.strip() else None
    size = f"x{10 ** k:g}" if k > 0 else f"x1e{k}"
    return f"off by a power of ten ({size}" + (f": {prefix} given as {base}?" if prefix else "") + ")"


def _power_scalings(unit: str) -> list[tuple[float, str]]:
    return [(10.0**k, _power_phrase(k, unit)) for k in (1, 2, 3, 6, -1, -2, -3, -6)]


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


def _approximations(result) -> dict:
    """The approximations the exercise declares next to its exact outputs at these parameters
    ({output: [(value, what it is)]}); none where it declares none or they cannot be evaluated."""
    from mech.verification.judge import approximations

    try:
        return approximations(result.exercise, result.params)
    except Exception:  # an approximation that cannot be evaluated here names no slip
        return {}


def _distance(e: Expectation, target: float, axis: bool) -> float:
    """|yours - target|, modulo pi for the direction of an axis."""
    d = abs(e.value - target)
    if axis and math.isfinite(d):
        d = math.fmod(d, _PI)
        d = min(d, _PI - d)
    return d


def _hint(e: Expectation, q, ref: _Reference, refs: dict, expectations: dict, gslips: _GSlips,
          approx: list, axis: bool) -> str | None:
    """The slip that moves the reference onto the user's value within a unit in the last written digit
    (the closest two); a declared approximation first, since it says what the value is."""
    # an approximation the statement asks for, or a leading-order value outside its range: what it is
    named: list[tuple[str, float, float]] = []
    for value, what in approx:
        if _number(value):
            pct = _percent(abs(value - ref.value) / abs(ref.value)) if ref.value else f"{abs(value):.3g}"
            what = what if what.startswith(("the ", "a ", "an ")) else f"the {what}"
            named.append((f"this is {what}; the exact value differs by {pct} here", value, 0.0))
    if ref.outside_value is not None:
        named.append(("that is the leading-order value, but the leading-order theory does not apply here",
                      ref.outside_value, 0.0))
    for phrase, value, err in named:
        if _distance(e, value, axis) <= e.own_tol(value) + err + ROUND_OFF * abs(value):
            return phrase
    candidates: list[tuple[str, float, float]] = []  # (phrase, slipped value, its reference error)
    scalings = _SCALINGS + _power_scalings(q.unit) + (_ANGLE_SCALINGS if _has_angle(q.unit) else [])
    for factor, phrase in scalings:
        candidates.append((phrase, factor * ref.value, ref.err * abs(factor)))
    if axis:
        # the perpendicular axis: where it coincides with another slip (a sign at 45 deg), it is the one named
        perpendicular = ref.value + _PI / 2
        if _distance(e, perpendicular, axis) <= 2.0 * e.own_tol(perpendicular) + ref.err + ROUND_OFF:
            return f"another principal axis: the one perpendicular to mech's {q.name}"
    for other, oref in refs.items():
        if other == q.name or oref.value is None or oref.unit != q.unit:
            continue
        o_exp = expectations.get(other)
        swapped = o_exp is not None and abs(o_exp.value - ref.value) <= _tol(o_exp, ref)
        phrase = f"swapped with {other}" if swapped else f"that is mech's {other}"
        candidates.append((phrase, oref.value, oref.err))
    for phrase, values in gslips.values():
        v = values.get(q.name)
        if _number(v) and ref.value != 0:
            candidates.append((phrase, v, ref.err * abs(v / ref.value)))
    fits = []
    for phrase, slipped, err in candidates:
        if not _number(slipped):
            continue
        # a unit in the last written digit: a slip together with a rounding of that digit is still named
        # (from 3 digits written on: one or two digits leave too wide a window to name anything by)
        own = e.own_tol(slipped) * (2.0 if e.rtol is None and (e.digits or 0) >= 3 else 1.0)
        tol = own + err + ROUND_OFF * abs(slipped)
        if _distance(Expectation("", "", ref.value), slipped, axis) <= tol:
            continue  # a slip that leaves mech's value where it is (g where the answer has none) explains nothing
        miss = _distance(e, slipped, axis)
        if miss <= tol:
            fits.append((miss / tol if tol > 0 else 0.0, phrase))
    # two slips can give the same value (g doubled and a factor sqrt(2) in sqrt(g/l)): name both
    phrases = list(dict.fromkeys(phrase for _, phrase in sorted(fits)))
    return " or ".join(phrases[:2]) or None


def _tol(e: Expectation, ref: _Reference) -> float:
    return e.own_tol(ref.value) + ref.err + ROUND_OFF * abs(ref.value)


def _digits_phrase(n: int | None) -> str:
    return "the digits written" if not n else f"{n} digit{'s' if n != 1 else ''}"


def _verdict_right(e: Expectation, ref: _Reference, leading_order: bool) -> str:
    """Say what the match needed: the digits written, or mech's own error bar."""
    if leading_order:
        return "right: the exact value"
    own = e.own_tol(ref.value)
    if ref.err > own:  # mech cannot vouch for more digits than its error bar
        return f"right within mech's error bar ({ref.err:.2g})"
    if e.rtol is not None:
        return f"right within rtol {e.rtol:g}"
    if e.digits is None:
        return "right (exact expression)"
    if e.least_precise:
        return f"right to {_digits_phrase(e.digits)} (those of {e.least_precise}, its least precise number)"
    return f"right to {_digits_phrase(e.digits)}"


def _percent(rel: float) -> str:
    pct = 100 * rel
    return f"{pct:.0f} %" if pct >= 10 else f"{pct:.2g} %"


def _verdict_off(e: Expectation, ref: _Reference, rel: float) -> str:
    if rel >= 10 and ref.value and e.value / ref.value > 0:
        return f"off by a factor {e.value / ref.value:.2g}"
    return f"off by {_percent(rel)}"


def _fmt(e: Expectation, value: float, digits: int) -> str:
    if e.unit_text and e.unit_factor:
        return f"{value / e.unit_factor:.{digits}g} {e.unit_text}"
    return f"{value:.{digits}g}"


def _shown(e: Expectation, value: float | None) -> str:
    """mech's value written the way the user wrote theirs (same unit), with two digits more."""
    if value is None:
        return "—"
    return _fmt(e, value, _digits(e))


def _digits(e: Expectation) -> int:
    return min(max((e.digits or 10) + 2, 4), 12)


def judge(result, expectations: list[Expectation]) -> list[Judgement]:
    """Judge every expectation against a cross-check result (a ``result.Solution``)."""
    quantities = {q.name: q for q in result.quantities}
    refs: dict[str, _Reference] = {}
    for name, q in quantities.items():
        refs[name] = reference(q, result.errors)
    outputs = {o.name: o for o in getattr(result.exercise, "outputs", ())}
    by_name = {e.name: e for e in expectations}
    gslips = _GSlips(result)
    approx = None
    out = []
    for e in expectations:
        q = quantities[e.name]
        ref = refs[e.name]
        axis = bool(getattr(outputs.get(e.name), "axis", False))
        leading = q.theory != "exact"
        base = dict(name=e.name, unit=q.unit, text=e.text, value=e.value, reference=ref.label, theory=q.theory)
        if ref.value is None:
            out.append(Judgement(**base, match=False, verdict=f"cannot judge: {ref.why}"))
            continue
        shown = _shown(e, ref.value)
        tol = _tol(e, ref)
        diff = _distance(e, ref.value, axis)
        rel_err = diff / abs(ref.value) if ref.value != 0 else diff
        if diff <= tol:
            verdict = _verdict_right(e, ref, leading)
            if axis and abs(e.value - ref.value) > tol:
                verdict += f": the same axis (mech: {shown})"
            out.append(Judgement(**base, match=True, reference_value=ref.value, rel_err=rel_err, tol=tol,
                                 verdict=verdict, shown_reference=shown, matches="exact" if leading else None))
            continue
        if ref.leading is not None:
            lead_tol = e.own_tol(ref.leading) + ref.leading_err + ROUND_OFF * abs(ref.leading)
            if _distance(e, ref.leading, axis) <= lead_tol:
                away = abs(ref.value - ref.leading) / abs(ref.value) if ref.value else 0.0
                verdict = (f"right to leading order; the exact value is {_percent(away)} away here "
                           f"(mech: {shown})")
                out.append(Judgement(**base, match=True, reference_value=ref.value, rel_err=rel_err,
                                     tol=lead_tol, verdict=verdict, shown_reference=shown,
                                     matches="leading-order"))
                continue
        if approx is None:
            approx = _approximations(result)
        hint = _hint(e, q, ref, refs, by_name, gslips, approx.get(e.name, []), axis)
        if hint == "degrees given as radians":
            # the value was meant in degrees: mech's value in degrees first, then as it was read
            shown = f"{math.degrees(ref.value):.{_digits(e)}g} deg = {shown}{'' if e.unit_text else ' rad'}"
        verdict = f"{hint or _verdict_off(e, ref, rel_err)} (mech: {shown})"
        if ref.outside is not None:
            verdict += f"; the leading-order theory does not apply here ({ref.outside}): the exact value is the answer"
        out.append(Judgement(**base, match=False, reference_value=ref.value, rel_err=rel_err, tol=tol, hint=hint,
                             verdict=verdict, shown_reference=shown, matches=None))
    return out
