"""What a user's answer to one output is held against: mech's reference there, and the answer as written.

The reference of an output is

* for an exact theory: the analytic value, when the numeric one confirms it;
* for a leading-order theory: the exact value, i.e. the numeric one (verified
  by the rerun at rtol/10), and where the theory is inside its range also the
  leading-order value; outside its range the leading-order value is named,
  never right;
* with one method only: that method's value, labelled "not cross-checked".

An output whose two values disagree has no trusted reference.

An answer is held to its own tolerance (half a unit in the last written digit,
or ``rtol`` times the reference) plus the reference's error bar plus
``ROUND_OFF`` relative: the judge's rule (``judge.within``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from mech.problems.spec import Undefined
from mech.verification.judge import ROUND_OFF, Verdict, allowance, analytic_err, numeric_err

__all__ = ["Expectation", "Reference", "reference", "allowed"]


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
    # a formula (``formula_ast.Formula``) instead of a number, judged across the range by ``formulas``:
    # at ``points`` drawn parameter sets (seeded by ``seed``), within ``over`` (name -> (lo, hi), SI)
    formula: object = None
    points: int | None = None
    seed: int | None = None
    over: tuple = ()
    none: bool = False  # the answer ``none``: the output has no value at these parameters

    def own_tol(self, reference: float) -> float:
        """The tolerance the user's writing earns, absolute, for a reference value."""
        return self.rtol * abs(reference) if self.rtol is not None else self.written_tol


def allowed(e: Expectation, value: float, err: float) -> float:
    """What the answer ``e`` is held to against ``value`` whose error bar is ``err`` (absolute): its own
    tolerance, the error bar and ``ROUND_OFF`` relative."""
    return allowance(value, bars=(e.own_tol(value), err), round_off=ROUND_OFF)


def number(v) -> bool:
    return isinstance(v, float) and math.isfinite(v)


@dataclass
class Reference:
    value: float | None
    err: float = 0.0  # absolute error bar, SI (numeric_err or analytic_err)
    label: str | None = None
    why: str = ""  # when there is no value to judge against
    undefined: str | None = None  # mech finds no finite value here: why (the method's ``Undefined.why``)
    unit: str = ""
    leading: float | None = None  # a leading-order value inside its theory's range (right to its digits too)
    leading_err: float = 0.0
    outside: str | None = None  # why the leading-order theory does not apply here
    outside_value: float | None = None  # the leading-order value there (named, never right)


def reference(q, errors: list[str]) -> Reference:
    """What an answer to output ``q`` (a crosscheck Quantity) is held against."""
    a, n = q.analytic, q.numeric
    if errors or q.agree is False:
        why = "analytic and numeric disagree" if q.agree is False else str(errors[0])
        return Reference(None, why=f"no trusted value: {why}")
    for v in (a, n):
        if isinstance(v, Undefined):
            return Reference(None, why=f"mech finds no finite value here: {v.why}", undefined=v.why)
    if number(n) and (q.theory != "exact" or not number(a)):
        label = "numeric" if getattr(q, "verify_diff", None) is not None else "numeric (not verified)"
        ref = Reference(n, numeric_err(q), label, unit=q.unit)
        if q.theory != "exact" and number(a):
            # the judge's typed verdict says whether the theory applies here, and why not
            ref.outside = (q.reason or "outside its range") if q.verdict is Verdict.OUTSIDE else None
            if ref.outside is None:
                ref.leading, ref.leading_err = a, analytic_err(q)
            else:
                ref.outside_value = a
        return ref
    if number(a):
        # both numbers reach here only when they agree (disagreement returned above)
        label = "analytic" if number(n) else "analytic (not cross-checked)"
        return Reference(a, analytic_err(q), label, unit=q.unit)
    return Reference(None, why="no value computed")
