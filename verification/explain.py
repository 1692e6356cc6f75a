"""The hints: the slip that explains a wrong answer, named only when it reproduces the answer.

A number (``number_hint``): a miss gets a hint when one common slip (a factor 2,
a sign, pi, a power of ten, degrees for radians, a swapped pair, g left out or
doubled, another principal axis, a declared approximation) moves mech's
reference onto the value within a unit in the last written digit (a slip and a
rounding of the last digit).

A formula (``formula_hint``), wrong at some of its points: a point where it
cannot be evaluated, a constant factor at every point, another output's
formula, a declared approximation or the leading-order limit it is, a
parameter it leaves out, and which parameters it follows right.

Every "within" here is the judge's rule (``judge.within``); the physics stays
in the exercise, whose analytic solver is the only thing called (to evaluate
a slip such as "g doubled").
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from mech.verification.formula_ast import Formula, dim_of_unit
from mech.verification.judge import ROUND_OFF, allowance, within
from mech.verification.judge import approximations as declared
from mech.verification.points import (PointJudgement, PointSet, accept, depends, describe_point, judge_points,
                                      line_of, make, problem_text, yours_at_given)
from mech.verification.reference import Expectation, Reference, allowed, number

__all__ = ["GSlips", "approximations", "distance", "number_hint", "percent", "FormulaHint", "formula_hint"]


# -- a number -------------------------------------------------------------------------------------------

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


class GSlips:
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


def approximations(result) -> dict:
    """The approximations the exercise declares next to its exact outputs at these parameters
    ({output: [(value, what it is)]}); none where it declares none or they cannot be evaluated."""
    try:
        return declared(result.exercise, result.params)
    except Exception:  # an approximation that cannot be evaluated here names no slip
        return {}


def distance(e: Expectation, target: float, axis: bool) -> float:
    """|yours - target|, modulo pi for the direction of an axis."""
    d = abs(e.value - target)
    if axis and math.isfinite(d):
        d = math.fmod(d, _PI)
        d = min(d, _PI - d)
    return d


def percent(rel: float) -> str:
    pct = 100 * rel
    return f"{pct:.0f} %" if pct >= 10 else f"{pct:.2g} %"


def number_hint(e: Expectation, q, ref: Reference, refs: dict, expectations: dict, gslips: GSlips,
          approx: list, axis: bool) -> str | None:
    """The slip that moves the reference onto the user's value within a unit in the last written digit
    (the closest two); a declared approximation first, since it says what the value is."""
    # an approximation the statement asks for, or a leading-order value outside its range: what it is
    named: list[tuple[str, float, float]] = []
    for value, what in approx:
        if number(value):
            pct = percent(abs(value - ref.value) / abs(ref.value)) if ref.value else f"{abs(value):.3g}"
            what = what if what.startswith(("the ", "a ", "an ")) else f"the {what}"
            named.append((f"this is {what}; the exact value differs by {pct} here", value, 0.0))
    if ref.outside_value is not None:
        named.append(("that is the leading-order value, but the leading-order theory does not apply here",
                      ref.outside_value, 0.0))
    for phrase, value, err in named:
        if within(distance(e, value, axis), scale=value, bars=(e.own_tol(value), err), round_off=ROUND_OFF):
            return phrase
    candidates: list[tuple[str, float, float]] = []  # (phrase, slipped value, its reference error)
    scalings = _SCALINGS + _power_scalings(q.unit) + (_ANGLE_SCALINGS if _has_angle(q.unit) else [])
    for factor, phrase in scalings:
        candidates.append((phrase, factor * ref.value, ref.err * abs(factor)))
    if axis:
        # the perpendicular axis: where it coincides with another slip (a sign at 45 deg), it is the one named
        perpendicular = ref.value + _PI / 2
        if within(distance(e, perpendicular, axis), bars=(2.0 * e.own_tol(perpendicular), ref.err, ROUND_OFF)):
            return f"another principal axis: the one perpendicular to mech's {q.name}"
    for other, oref in refs.items():
        if other == q.name or oref.value is None or oref.unit != q.unit:
            continue
        o_exp = expectations.get(other)
        swapped = o_exp is not None and within(abs(o_exp.value - ref.value), bars=(allowed(o_exp, ref.value, ref.err),))
        phrase = f"swapped with {other}" if swapped else f"that is mech's {other}"
        candidates.append((phrase, oref.value, oref.err))
    for phrase, values in gslips.values():
        v = values.get(q.name)
        if number(v) and ref.value != 0:
            candidates.append((phrase, v, ref.err * abs(v / ref.value)))
    fits = []
    for phrase, slipped, err in candidates:
        if not number(slipped):
            continue
        # a unit in the last written digit: a slip together with a rounding of that digit is still named
        # (from 3 digits written on: one or two digits leave too wide a window to name anything by)
        own = e.own_tol(slipped) * (2.0 if e.rtol is None and (e.digits or 0) >= 3 else 1.0)
        tol = allowance(slipped, bars=(own, err), round_off=ROUND_OFF)
        if within(distance(Expectation("", "", ref.value), slipped, axis), bars=(tol,)):
            continue  # a slip that leaves mech's value where it is (g where the answer has none) explains nothing
        miss = distance(e, slipped, axis)
        if within(miss, bars=(tol,)):
            fits.append((miss / tol if tol > 0 else 0.0, phrase))
    # two slips can give the same value (g doubled and a factor sqrt(2) in sqrt(g/l)): name both
    phrases = list(dict.fromkeys(phrase for _, phrase in sorted(fits)))
    return " or ".join(phrases[:2]) or None


# -- a formula ------------------------------------------------------------------------------------------


@dataclass
class FormulaHint:
    """What a student can act on for a formula wrong at some points: the hint (None: none found), the point
    to show (``at``: the first wrong one, or the first that cannot be evaluated) and the parameters its
    dependence is wrong in (``guilty``)."""

    hint: str | None
    at: int
    guilty: list = field(default_factory=list)


def formula_hint(formula: Formula, ps: PointSet, output, pj: PointJudgement, ref: np.ndarray,
                 rtol: float) -> FormulaHint:
    """The hint for ``formula``, an answer for ``output`` (a spec Output) judged at ``ps`` (``pj``) against
    mech's values ``ref`` there, wrong at one point at least."""
    name = output.name
    judged = pj.judged
    wrong = judged & ~pj.right
    # wrong: find what a student can act on
    i_fail = int(np.flatnonzero(wrong)[0])
    hint = None
    dom = [i for i in np.flatnonzero(wrong) if problem_text(pj, ps, int(i))]
    if dom:
        i_fail = int(dom[0])
        hint = f"cannot be evaluated {describe_point(ps, i_fail)}: {problem_text(pj, ps, i_fail)}"
    innocent, guilty = [], []
    if hint is None:
        c = _const_ratio(pj.yours, ref, pj.tol, judged)
        if c is not None:
            hint = "wrong sign" if c == -1.0 else f"off by a constant factor {_nice_factor(c)} at every point"
    if hint is None:
        hint = _other_output(formula, ps, output, pj.yours, rtol)
    if hint is None:
        deps = depends(ps, name)
        missing = [k for k in deps if k not in formula.names]
        if output.theory == "exact":
            known = _known_approximation(ps, name, pj.yours, pj.tol)
            hint = _approximation(formula, ps, name, missing + list(formula.names) if known else missing)
            if known:  # "this is the small-amplitude period ..., a leading-order approximation; it holds only ..."
                hint = f"this is {known}, a leading-order approximation" + (
                    "; " + hint.replace("this is the leading-order approximation; ", "") if hint else "")
        if hint is None and missing:
            hint = f"mech's {name} depends on {_and(missing)}, which your formula leaves out"
    if hint is None or hint.startswith("mech's"):
        innocent, guilty = _follows(formula, ps, name, rtol)
        if hint is not None and innocent and pj.right[0]:
            hint = f"right when only {_and(innocent)} {_change(innocent)}, but {hint}"
        if hint is None and guilty and innocent:
            if pj.right[0]:
                hint = (f"right when only {_and(innocent)} {_change(innocent)}; check how your formula depends on "
                        f"{_and(guilty)}")
            else:
                hint = (f"off by a factor that does not change with {_and(innocent)}; check how your formula "
                        f"depends on {_and(guilty)}")
    return FormulaHint(hint, i_fail, guilty)


def _nice_factor(c: float) -> str:
    """``2``, ``-1/2``, ``2/pi``, ``sqrt(2)``, ``3 pi/4``: a small fraction times 1, pi, 1/pi, sqrt(2) or
    sqrt(3) when c is one, else c to 6 digits."""
    bases = ((1.0, "", ""), (math.pi, " pi", "pi"), (1 / math.pi, "/pi", "/pi"), (math.sqrt(2), " sqrt(2)", "sqrt(2)"),
             (1 / math.sqrt(2), "/sqrt(2)", "/sqrt(2)"), (math.sqrt(3), " sqrt(3)", "sqrt(3)"),
             (1 / math.sqrt(3), "/sqrt(3)", "/sqrt(3)"), (math.pi / 180, " pi/180 (radians for degrees)", ""),
             (180 / math.pi, " 180/pi (degrees for radians)", ""))
    fits = []
    for k, (val, after, alone) in enumerate(bases):
        if not math.isfinite(c / val):  # a factor beyond the floating-point range (issue 33)
            continue
        f = Fraction(c / val).limit_denominator(64)
        if f != 0 and abs(f.numerator) <= 64 and within(abs(float(f) * val - c), scale=c, round_off=1e-9):
            fits.append((abs(f.numerator) + f.denominator, k, f))
    for _, k, f in sorted(fits)[:1]:
        val, after, alone = bases[k]
        if True:
            sign = "-" if f < 0 else ""
            n, d = abs(f.numerator), f.denominator
            if val == 1.0:
                return f"{sign}{n}" + (f"/{d}" if d != 1 else "")
            if after.startswith("/"):  # n/(d base)
                return f"{sign}{n}{after}" if d == 1 else f"{sign}{n}/({d}{after.replace('/', ' ', 1).rstrip()})"
            if n == 1 and d == 1 and alone:
                return sign + alone
            return f"{sign}{n if n != 1 else ''}{after}".replace("  ", " ").strip() + (f"/{d}" if d != 1 else "")
    return f"{c:.6g}"


def _const_ratio(yours, ref, tol, mask) -> float | None:
    """The constant c with yours = c * mech at every point of ``mask`` (None when there is none)."""
    use = mask & np.isfinite(yours) & np.isfinite(ref) & (ref != 0)
    if use.sum() < 2:
        return None
    ratios = yours[use] / ref[use]
    c = float(np.median(ratios))
    if c == 1.0 or c == 0.0 or not math.isfinite(c):
        return None
    with np.errstate(over="ignore"):  # a huge factor: its bound is infinite, as it was before it overflowed
        held = within(np.abs(yours[use] - c * ref[use]), bars=(tol[use] * max(1.0, abs(c)),))
    if np.all(held):
        return c
    return None


def _ratio_constant(formula: Formula, line: PointSet, output: str, rtol: float) -> bool | None:
    ref = line.analytic[output]
    pj = judge_points(formula, line, ref, line.analytic_err[output], rtol)
    use = np.isfinite(pj.yours) & np.isfinite(ref)
    if use.sum() < 2:
        return None
    y, r, t = pj.yours[use], ref[use], pj.tol[use]
    if np.all(r != 0):
        c = float(np.median(y / r))
        return bool(np.all(within(np.abs(y - c * r), bars=(t * max(1.0, abs(c)),))))
    return bool(np.all(within(np.abs(y - r), bars=(t,))))


def _follows(formula: Formula, ps: PointSet, output: str, rtol: float) -> tuple[list, list]:
    innocent, guilty = [], []
    for name in ps.ex.param_map:
        line = line_of(ps, name)
        if line is None:
            continue
        c = _ratio_constant(formula, line, output, rtol)
        if c is True:
            innocent.append(name)
        elif c is False:
            guilty.append(name)
    return innocent, guilty


def _limits(formula: Formula, ps: PointSet, output: str) -> list[tuple[str, str, bool]]:
    """The limits in which the formula becomes mech's answer: ``(what, parameter, first_order)`` for each
    parameter whose move toward zero (or its lower bound, or without bound) makes the relative mismatch
    fall steadily to nothing.  ``first_order``: the mismatch also vanishes against the answer's own change
    from its limit value, as a leading-order formula's does (``omega0*exp(+x)`` for ``omega0*exp(-x)`` also
    meets mech's value as x -> 0, but misses the first-order change by a factor -1: not an approximation)."""
    ex, given = ps.ex, ps.points[0]
    r_given = ps.analytic[output][0]
    if not math.isfinite(r_given) or r_given == 0:
        return []
    r0 = abs(yours_at_given(formula, ps) - r_given) / abs(r_given)
    if not r0 > 1e-12:
        return []
    found = []
    for direction, word in ((0.01, "small"), (100.0, "large")):
        for name in ex.param_map:
            p = ex.param_map[name]
            v0 = given[name]
            if v0 == 0:
                continue
            what = f"{word} {name}"
            vals = [v0 * direction**j for j in range(1, 6)]
            if direction < 1 and p.min is not None and p.min > 0:
                # toward the lower bound: shrink the distance to it
                vals = [p.min + (v0 - p.min) * direction**j for j in range(1, 6)] if v0 > p.min else []
                what = f"{name} near {p.min:g}"
            key = ("limit", name, direction)
            if key not in ps.lines:  # mech's values along the line, once per point set (a class file)
                pts = [q for q in (accept(ex, {**dict(given), name: v}) for v in vals) if q is not None]
                ps.lines[key] = (make(ex, [given] + pts, ["limit"] * (len(pts) + 1), ps.memo)
                                 if len(pts) >= 3 else None)
            line = ps.lines[key]
            if line is None:
                continue
            pts = line.points[1:]
            ref = line.analytic[output]
            env = {k: line.arrays[k] for k in formula.names} or {"_": np.zeros(len(pts) + 1)}
            y, _, _ = formula.evaluate(env)
            if not (np.all(np.isfinite(ref)) and np.all(np.isfinite(y)) and np.all(ref != 0)):
                continue
            rel = np.abs(y - ref) / np.abs(ref)
            above = rel > 1e-11  # past that the mismatch is round-off: no trend to read
            steady = all(b < a for a, b, keep in zip(rel[:-1], rel[1:], above[1:]) if keep)
            if not (steady and rel[-1] < 1e-3 * rel[0]):
                continue
            change = np.abs(ref[:-2] - ref[-1])  # the answer's own change from (nearly) its limit
            with np.errstate(all="ignore"):
                q = np.abs(y[:-2] - ref[:-2]) / change
            # converging to nothing, also at the end of the line (not only leaving a peak at the given point)
            first = bool(np.all(np.isfinite(q)) and q[-1] < 0.1 and q[-1] < 1e-2 * q[0] and q[-1] < 0.5 * q[-2])
            found.append((what, name, first))
    return found


def _approximation(formula: Formula, ps: PointSet, output: str, missing: list[str]) -> str | None:
    """"this is the leading-order approximation; it holds only for small X", when it is: the limit value
    of an answer that depends on a parameter the formula leaves out (T = 2 pi sqrt(l/g) for the pendulum),
    or a formula right to first order in a parameter going to its limit."""
    found = _limits(formula, ps, output)
    r_given = ps.analytic[output][0]
    off = abs(yours_at_given(formula, ps) - r_given) / abs(r_given)
    # the limit value of an answer whose dependence on that parameter it leaves out, near the given
    # parameters (T = 2 pi sqrt(l/g) at 60 deg is 7 % short; m v for m (v + v0) is 94 %: a term left out)
    named = [w for w, k, _ in found if k in missing] if off < 0.25 else []
    if not named and off < 0.1:
        # a formula right to first order in a limit, and close at the given parameters (where it is meant
        # to hold): a formula 2x off there that only shares the limit's power law is not an approximation
        named = [w for w, _, first in found if first]
    if not named:
        return None
    said = named[0] if len(named) == 1 else ", ".join(named[:-1]) + " or " + named[-1]
    return f"this is the leading-order approximation; it holds only for {said}"


def _known_approximation(ps: PointSet, output: str, yours: np.ndarray, tol: np.ndarray) -> str | None:
    """The description of an approximation the exercise declares (``@exercise.approximations``: 5.5, 5.6, 5.7)
    that the formula gives at every point, or None."""
    at = getattr(ps.ex, "approximations_at", None)
    if at is None:
        return None
    found: dict[str, int] = {}
    n = 0
    for i, p in enumerate(ps.points):
        if not math.isfinite(yours[i]):
            continue
        try:
            cands = at(p).get(output) or []
        except Exception:  # an approximation with no value here: not one the formula can be matched to
            return None
        n += 1
        for value, desc in cands:
            if isinstance(value, (int, float)) and within(abs(yours[i] - value), scale=value, bars=(tol[i],), round_off=1e-9):
                found[desc] = found.get(desc, 0) + 1
    full = [d for d, k in found.items() if k == n]
    return full[0] if n and full else None


def _other_output(formula: Formula, ps: PointSet, output, yours: np.ndarray, rtol: float) -> str | None:
    """"that is mech's omega2": the formula gives another output of the same dimension at every point."""
    _, dim = dim_of_unit(output.unit)
    for o in ps.ex.outputs:
        if o.name == output.name or dim_of_unit(o.unit)[1] != dim:
            continue
        ref = ps.analytic[o.name]
        use = np.isfinite(ref)
        if use.sum() >= 2 and np.all(within(np.abs(yours[use] - ref[use]), scale=ref[use], rel=rtol,
                                            bars=(ps.analytic_err[o.name][use],), round_off=1e-12)):
            return f"that is mech's {o.name}, not its {output.name}"
    return None


def _change(names: list[str]) -> str:
    return "changes" if len(names) == 1 else "change"


def _and(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
