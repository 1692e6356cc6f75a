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
(``numeric_err`` or ``analytic_err``) plus ``ROUND_OFF`` relative (the judge's
rule, ``judge.within``; the reference: ``reference``).  An output that is the
direction of an axis (``Output.axis``) is judged modulo pi.  A miss gets a hint
(``explain``); a formula is judged across the range (``formulas``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mech.students.cells import State
from mech.students.explain import GSlips, approximations, distance, number_hint, percent
from mech.students.formulas import DEFAULT_POINTS, DEFAULT_SEED, judge_formula, known, point_set, show_value
from mech.verification.judge import ROUND_OFF, numeric_err, within
from mech.students.points import in_over
from mech.students.reference import Expectation, Reference, allowed, reference

__all__ = ["Expectation", "Judgement", "judge", "numeric_err", "ROUND_OFF"]


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
    formula: dict | None = None  # for a formula: "formula", "dimension", "points", "depends" (the contract's)
    state: State | None = None  # set where the cell is neither right nor wrong (``cells.State``)

    @property
    def cell(self) -> State:
        """The cell's state: ``state`` where it was set, else right or wrong by ``match``."""
        if self.state is not None:
            return self.state
        return State.RIGHT if self.match else State.WRONG

    def as_json(self) -> dict:
        d = {"value": _finite(self.value), "match": self.match, "rel_err": _finite(self.rel_err), "hint": self.hint,
             "text": self.text, "reference": self.reference, "reference_value": _finite(self.reference_value),
             "tol": _finite(self.tol), "verdict": self.verdict}
        d["state"] = self.cell.value
        if self.cell not in (State.RIGHT, State.WRONG):
            d["reason"] = self.verdict
        if self.theory != "exact":
            d["matches"] = self.matches
        if self.formula is not None:
            d.update(self.formula)
        return d


def _finite(v):
    return v if isinstance(v, float) and math.isfinite(v) else None


def _digits_phrase(n: int | None) -> str:
    return "the digits written" if not n else f"{n} digit{'s' if n != 1 else ''}"


def _verdict_right(e: Expectation, ref: Reference, leading_order: bool) -> str:
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


def _verdict_off(e: Expectation, ref: Reference, rel: float) -> str:
    if rel >= 10 and ref.value and e.value / ref.value > 0:
        return f"off by a factor {e.value / ref.value:.2g}"
    return f"off by {percent(rel)}"


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
    refs: dict[str, Reference] = {}
    for name, q in quantities.items():
        refs[name] = reference(q, result.errors)
    outputs = {o.name: o for o in getattr(result.exercise, "outputs", ())}
    by_name = {e.name: e for e in expectations}
    gslips = GSlips(result)
    approx = None
    out = []
    for e in expectations:
        q = quantities[e.name]
        ref = refs[e.name]
        if e.formula is not None:
            out.append(judge_expectation(result, e, q, ref))
            continue
        axis = bool(getattr(outputs.get(e.name), "axis", False))
        leading = q.theory != "exact"
        base = dict(name=e.name, unit=q.unit, text=e.text, value=e.value, reference=ref.label, theory=q.theory)
        if e.none or ref.undefined is not None:
            out.append(_judge_none(e, ref, base))
            continue
        if ref.value is None:
            out.append(Judgement(**base, match=False, verdict=f"cannot judge: {ref.why}", state=State.NOT_GRADED))
            continue
        shown = _shown(e, ref.value)
        tol = allowed(e, ref.value, ref.err)
        diff = distance(e, ref.value, axis)
        rel_err = diff / abs(ref.value) if ref.value != 0 else diff
        if within(diff, bars=(tol,)):
            verdict = _verdict_right(e, ref, leading)
            if axis and not within(abs(e.value - ref.value), bars=(tol,)):
                verdict += f": the same axis (mech: {shown})"
            out.append(Judgement(**base, match=True, reference_value=ref.value, rel_err=rel_err, tol=tol,
                                 verdict=verdict, shown_reference=shown, matches="exact" if leading else None))
            continue
        if ref.leading is not None:
            lead_tol = allowed(e, ref.leading, ref.leading_err)
            if within(distance(e, ref.leading, axis), bars=(lead_tol,)):
                away = abs(ref.value - ref.leading) / abs(ref.value) if ref.value else 0.0
                verdict = (f"right to leading order; the exact value is {percent(away)} away here "
                           f"(mech: {shown})")
                out.append(Judgement(**base, match=True, reference_value=ref.value, rel_err=rel_err,
                                     tol=lead_tol, verdict=verdict, shown_reference=shown,
                                     matches="leading-order"))
                continue
        if ref.leading is not None and _beyond_leading_order(e, ref, axis):
            gain = abs(ref.leading - ref.value) / max(distance(e, ref.value, axis), 1e-300)
            verdict = (f"right beyond leading order: {gain:.3g}x closer to the exact value than the "
                       f"leading-order value is (mech: {shown})")
            out.append(Judgement(**base, match=True, reference_value=ref.value, rel_err=rel_err, tol=tol,
                                 verdict=verdict, shown_reference=shown, matches="beyond-leading-order"))
            continue
        if ref.leading is not None and _as_close_as_leading(e, ref, axis):
            verdict = (f"right: at least as close to the exact value as the leading-order value is "
                       f"(mech: {shown})")
            out.append(Judgement(**base, match=True, reference_value=ref.value, rel_err=rel_err, tol=tol,
                                 verdict=verdict, shown_reference=shown, matches="leading-order"))
            continue
        if approx is None:
            approx = approximations(result)
        hint = number_hint(e, q, ref, refs, by_name, gslips, approx.get(e.name, []), axis)
        if hint == "degrees given as radians":
            # the value was meant in degrees: mech's value in degrees first, then as it was read (the unit's
            # time part kept: deg/s = rad/s)
            deg_unit = q.unit.replace("rad", "deg", 1) if "rad" in q.unit else "deg"
            rad_unit = "" if e.unit_text else (f" {q.unit}" if "rad" in q.unit else " rad")
            shown = f"{math.degrees(ref.value):.{_digits(e)}g} {deg_unit} = {shown}{rad_unit}"
        verdict = f"wrong: {hint or _verdict_off(e, ref, rel_err)} (mech: {shown})"
        if ref.outside is not None:
            verdict += f"; the leading-order theory does not apply here ({ref.outside}): the exact value is the answer"
        out.append(Judgement(**base, match=False, reference_value=ref.value, rel_err=rel_err, tol=tol, hint=hint,
                             verdict=verdict, shown_reference=shown, matches=None))
    return out


def _judge_none(e: Expectation, ref: Reference, base: dict) -> Judgement:
    """``none`` (no value at these parameters) is right where mech finds none and wrong where it has one;
    a value is wrong where mech finds none; with no trusted value either way, not graded."""
    if ref.undefined is not None:
        if e.none:
            return Judgement(**base, match=True, verdict=f"right: there is no value here ({ref.undefined})")
        return Judgement(**base, match=False, verdict=f"wrong: mech finds no value here ({ref.undefined}); "
                         "the answer is none")
    if ref.value is not None:
        shown = show_value(ref.value, base["unit"])
        return Judgement(**base, match=False, reference_value=ref.value, shown_reference=shown,
                         verdict=f"wrong: there is a value here (mech: {shown})")
    return Judgement(**base, match=False, verdict=f"cannot judge: {ref.why}", state=State.NOT_GRADED)


BEYOND = 3.0  # how much closer than the leading-order value a next-order answer must be to the exact one


def _as_close_as_leading(e: Expectation, ref: Reference, axis: bool) -> bool:
    """Monotone: inside the theory's range, an answer at least as close to the verified exact value as some
    answer judged right to leading order (the leading-order value to the digits of this answer, on its far
    side from the exact value) is right."""
    gap = distance(Expectation("", "", ref.leading), ref.value, axis)
    lead_tol = allowed(e, ref.leading, ref.leading_err)
    return bool(math.isfinite(gap) and within(distance(e, ref.value, axis), bars=(gap, lead_tol, ref.err)))


def _beyond_leading_order(e: Expectation, ref: Reference, axis: bool) -> bool:
    """A next-order answer on a leading-order output, inside its theory's range: closer to the verified exact
    value than the leading-order value is, by ``BEYOND`` at least, the error bars counted against it."""
    gap = distance(Expectation("", "", ref.leading), ref.value, axis)
    miss = distance(e, ref.value, axis)
    return bool(math.isfinite(gap) and gap > 0 and BEYOND * (miss + ref.err + ref.leading_err) <= gap)


def judge_expectation(result, e, q, ref):
    """A ``Judgement`` for the formula expectation ``e`` on output ``q`` of a cross-check
    ``result``, ``ref`` being the answers judge's reference at the given parameters."""
    ex, given = result.exercise, result.params
    output = {o.name: o for o in ex.outputs}[e.name]
    over = dict(e.over) if e.over else None
    def ps(at_most=None):  # drawn once the dimension is found right (``judge_formula``), or, at most
        n = e.points if e.points is not None else DEFAULT_POINTS  # ``at_most``, to name a dimension's slip
        return point_set(ex, given, n if at_most is None else min(n, at_most),
                         e.seed if e.seed is not None else DEFAULT_SEED, over, known(result))

    lead = output.theory != "exact"
    if ref.value is None:
        given_ref, numeric_given = None, None
    elif lead:
        a = q.analytic
        given_ref = (float(a), 0.0) if isinstance(a, float) and math.isfinite(a) else None
        verified = getattr(q, "verify_diff", None) is not None
        n = q.numeric
        numeric_given = ((float(n), numeric_err(q)) if verified and isinstance(n, float) and math.isfinite(n)
                         else None)
        if given_ref is None and numeric_given is not None:
            given_ref = numeric_given
    else:
        given_ref, numeric_given = (float(ref.value), float(ref.err)), None
    in_range = in_over(given, over)
    undefined_here = ref.value is None and ref.undefined is not None
    if undefined_here:  # judged at the other points; the given one has no value to hold it against
        in_range = False
    with np.errstate(all="ignore"):  # a formula may overflow anywhere in the range: judged, not warned
        v = judge_formula(e.formula, ex, output, ps, given_ref, e.rtol, numeric_given, in_range)
    if undefined_here:
        v.verdict += f" (not at the given parameters: {ref.undefined})"
    verdict = v.verdict
    if given_ref is None and not v.hint and not undefined_here:
        verdict = f"cannot judge: {ref.why or 'mech has no trusted value here'}"
    state = State.NOT_GRADED if (v.state == "not-graded" or verdict.startswith("cannot judge")) else None
    return Judgement(
        name=e.name, unit=q.unit, text=e.text, value=v.value, match=v.match, theory=q.theory, matches=v.matches,
        state=state,
        reference=(ref.label if ref.value is not None else None), reference_value=v.reference_value,
        rel_err=v.rel_err, tol=v.tol, hint=v.hint, verdict=verdict,
        shown_reference=show_value(v.reference_value, q.unit) if v.reference_value is not None else "",
        formula={"formula": v.formula, "dimension": v.dimension, "points": v.points, "depends": v.depends})
