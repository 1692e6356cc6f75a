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

from mech.problems.solving import constraint_message
from mech.problems.spec import Params
from mech.students.formula_ast import Formula, dim_of_unit
from mech.verification.judge import ROUND_OFF, allowance, within
from mech.verification.judge import approximations as declared
from mech.students.points import (PointJudgement, PointSet, accept, depends, describe_point, judge_points,
                                      line_of, make, problem_text, yours_at_given)
from mech.students.reference import Expectation, Reference, allowed, number

__all__ = ["GSlips", "approximations", "distance", "number_hint", "percent", "FormulaHint", "formula_hint", "dimension_hint",
           "dimension_could_be_a_slip"]


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
    """The exercise's own analytic answers at the given parameters with one parameter slip made (left out,
    doubled, halved, two swapped, an angle read in degrees: ``_param_slips``), computed once, on a miss."""

    def __init__(self, result):
        self.result = result
        self._values: list[tuple[str, dict]] | None = None

    def values(self) -> list[tuple[str, dict]]:
        if self._values is None:
            self._values = []
            ex, params = self.result.exercise, self.result.params
            if not getattr(ex, "has_analytic", False):
                return self._values
            import warnings

            base = {q.name: float(params[q.name]) for q in ex.params}
            clock = _SlipClock()
            for phrase, change, far in _param_slips(ex):
                if not clock.more(far):
                    break
                try:
                    with warnings.catch_warnings(), np.errstate(all="ignore"):
                        warnings.simplefilter("ignore")
                        slipped = change(dict(base))
                        if slipped == base:
                            continue
                        try:
                            values = clock.timed(_solve_slipped, ex, slipped)
                        except Exception:  # another output divides by it: its limit (``_zeroed``)
                            if not _zeroed(base, slipped):
                                raise
                            values = clock.timed(_solve_slipped, ex, _zeroed(base, slipped))
                        self._values.append((phrase, values))
                except Exception:  # no answer there: that slip cannot be named
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
    if ref.value > 0:
        candidates.append((f"this is mech's {q.name} squared", ref.value**2, 2 * ref.err * ref.value))
        candidates.append((f"this is the square root of mech's {q.name}", math.sqrt(ref.value),
                           0.5 * ref.err / math.sqrt(ref.value)))
    for value, what in approx:
        if not number(value):
            continue
        what = what if what.startswith(("the ", "a ", "an ")) else f"the {what}"
        for factor, phrase in _factors(q.unit):
            candidates.append((f"{what} (a leading-order approximation), {phrase}", factor * value, 0.0))
        for p in params_of_unit(gslips, q.unit):
            base = float(gslips.result.params[p])
            for c, phrase in [(-1.0, "the wrong sign")] + [(c, f"a factor {t}") for c, t in _NAMED_FACTORS]:
                candidates.append((f"{what} (a leading-order approximation) with {phrase} in its correction to "
                                   f"{p}", base + c * (value - base), 0.0))
    for phrase, values in gslips.values():
        v = values.get(q.name)
        if number(v) and ref.value != 0:
            candidates.append((phrase, v, ref.err * abs(v / ref.value)))
    fits = []
    for phrase, slipped, err in candidates:
        if not number(slipped):
            continue
        # a slip is named only when it gives the answer to its digits (half a unit in the last one): never a
        # wider window, where a coincidence (9.5 % from a factor 10) would pass for a slip
        own = e.own_tol(slipped)
        tol = allowance(slipped, bars=(own, err), round_off=ROUND_OFF)
        if within(distance(Expectation("", "", ref.value), slipped, axis), bars=(tol,)):
            continue  # a slip that leaves mech's value where it is (g where the answer has none) explains nothing
        miss = distance(e, slipped, axis)
        if within(miss, bars=(tol,)):
            fits.append((miss / tol if tol > 0 else 0.0, phrase, slipped, err))
    # a slip is named only when no other searched slip also gives the answer: two that give the same value
    # (g doubled and a factor sqrt(2) in sqrt(g/l)) are named together; two that differ, neither
    fits.sort(key=lambda f: f[0])
    phrases = [fits[0][1]] if fits else []
    for _, phrase, slipped, err in fits[1:]:
        if phrase in phrases:
            continue
        if not within(distance(Expectation("", "", fits[0][2]), slipped, axis), bars=(err, fits[0][3]),
                      scale=slipped, round_off=ROUND_OFF):
            return None
        if len(phrases) < 2:
            phrases.append(phrase)
    return " or ".join(phrases) or None


def params_of_unit(gslips: GSlips, unit: str) -> list[str]:
    """The exercise's parameters in ``unit`` (the base a leading-order correction is added to)."""
    return [p.name for p in gslips.result.exercise.params if p.unit == unit]


# -- the slips searched: transformations of mech's reference ----------------------------------------------
#
# Each slip is a transformation of mech's own answer (a factor, a power, a parameter left out, doubled or
# swapped, another output, degrees for radians, a declared approximation and a slip inside it), evaluated
# at the points the answer is judged at: at one point for a number, at the formula's point set for a
# formula.  A slip is named only when it gives the answer at every one of them.

_NAMED_FACTORS = [
    (2.0, "2"), (0.5, "1/2"), (_PI, "pi"), (1 / _PI, "1/pi"), (2 * _PI, "2 pi"), (1 / (2 * _PI), "1/(2 pi)"),
    (math.sqrt(2.0), "sqrt(2)"), (1 / math.sqrt(2.0), "1/sqrt(2)"), (4.0, "4"), (0.25, "1/4"),
]
_ANGLE_FACTORS = [(180 / _PI, "degrees given as radians"), (_PI / 180, "radians given as degrees")]


def _factor_phrase(c: float, text: str, unit: str) -> str:
    phrase = f"off by a factor {text}"
    if unit == "rad/s" and text in ("1/(2 pi)", "2 pi"):
        phrase += (": a frequency in Hz (turns per second) given for rad/s" if text == "1/(2 pi)"
                   else ": rad/s given for a frequency in Hz")
    return phrase


def _factors(unit: str) -> list[tuple[float, str]]:
    """(factor, phrase): a sign, the named factors and their negatives, degrees for radians on an angle."""
    out = [(-1.0, "wrong sign")]
    for c, text in _NAMED_FACTORS:
        out.append((c, _factor_phrase(c, text, unit)))
    for c, text in _NAMED_FACTORS:
        out.append((-c, "wrong sign and " + _factor_phrase(c, text, unit)))
    if _has_angle(unit) and "/" not in unit.replace("rad/s", "rad"):
        out += _ANGLE_FACTORS
    elif unit.startswith("rad/"):
        out += [(c, f"{p} (the angle's unit)") for c, p in _ANGLE_FACTORS]
    return out


def _same_dim(a: str, b: str) -> bool:
    try:
        return dim_of_unit(a)[1] == dim_of_unit(b)[1]
    except Exception:  # a unit the formula language cannot read: not compared
        return False


def _analytic_at(ps: PointSet, values: dict) -> dict | None:
    """mech's analytic answers at ``values`` (any parameters its analytic solver accepts, inside the bounds
    and constraints or not: a swap may leave them), once per point set; None where it gives none."""
    cache = ps.lines.setdefault(("explain", "analytic"), {})
    key = tuple(float(values[q.name]).hex() for q in ps.ex.params)
    if key not in cache:
        try:
            cache[key] = _solve_slipped(ps.ex, values)
        except Exception:  # no answer there: that slip cannot be named
            cache[key] = None
    return cache[key]


def _solve_slipped(ex, values: dict) -> dict:
    """mech's analytic answers at a slipped point, quietly (no warning escapes).  Not under a timer: a
    timer's signal can land anywhere (a garbage collector's callback); the slips are chosen so that the
    solvers stay in their usual range (``_param_slips``), and ``_SlipClock`` ends a search that costs."""
    import warnings

    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        return ex.solve_analytic(Params({k: float(v) for k, v in values.items()}))


def _param_slips(ex) -> list[tuple[str, object, bool]]:
    """(phrase, change, far): the parameter slips, each a change of the parameters (dict -> dict); ``far``
    for those that take a parameter to 0 or to a difference of two, where an analytic solver may leave its
    usual range (4.32's series runs for seconds with M_S = 0): listed last, tried only where every solve
    before them was fast (``_SlipClock``)."""
    near, far = [], []
    params = list(ex.params)
    for p in params:
        if p.unit not in ("1", "rad"):  # a parameter left out: taken as 1 in SI
            near.append((f"{p.name} left out (taken as 1)", lambda d, k=p.name: {**d, k: 1.0}))
        # taken as 0: where 0 is outside its bounds, at its limit there (1e-30 of its value: 4.32's series
        # runs for seconds at M_S = 0 exactly)
        zero_ok = p.min is None or p.min < 0 or (p.min == 0 and not p.min_open)
        far.append((f"{p.name} left out (taken as 0: it agrees with mech only in the limit of small {p.name})",
                     lambda d, k=p.name, z=zero_ok: {**d, k: 0.0 if z else 1e-30 * d[k]}))
        near.append((f"{p.name} doubled", lambda d, k=p.name: {**d, k: 2.0 * d[k]}))
        near.append((f"{p.name} halved", lambda d, k=p.name: {**d, k: 0.5 * d[k]}))
    for i, a in enumerate(params):
        for b in params[i + 1:]:
            if not (a.unit == b.unit or (a.unit not in ("1", "rad") and _same_dim(a.unit, b.unit))):
                continue
            near.append((f"{a.name} and {b.name} swapped",
                         lambda d, x=a.name, y=b.name: _in_bounds(ex, {**d, x: d[y], y: d[x]})))
            # a difference (l for R - l): only where the exercise's joint limits hold (4.32's series diverges
            # with R_E near r_S)
            far.append((f"{a.name} and {b.name} - {a.name} swapped",
                        lambda d, x=a.name, y=b.name: _jointly(ex, {**d, x: d[y] - d[x]})))
            far.append((f"{b.name} and {a.name} - {b.name} swapped",
                        lambda d, x=a.name, y=b.name: _jointly(ex, {**d, y: d[x] - d[y]})))
    for p in params:
        if p.unit == "rad":  # an angle read in degrees (tan(theta*pi/180)) or turned to degrees
            near.append((f"{p.name} converted as if it were in degrees (x pi/180)",
                         lambda d, k=p.name: {**d, k: d[k] * _PI / 180}))
            near.append((f"{p.name} converted to degrees (x 180/pi)", lambda d, k=p.name: {**d, k: d[k] * 180 / _PI}))
        if p.unit == "rad/s":
            near.append((f"{p.name} taken in Hz (divided by 2 pi)", lambda d, k=p.name: {**d, k: d[k] / (2 * _PI)}))
    return [(ph, ch, False) for ph, ch in near] + [(ph, ch, True) for ph, ch in far]


class _Refused(ValueError):
    """A slipped point beyond the exercise's joint limits, where a difference slip is not evaluated."""


class _OutOfRange(_Refused):
    """A slipped point with a parameter outside its declared bounds: that reading is never offered."""


def _in_bounds(ex, values: dict) -> dict:
    """``values`` where every parameter is inside its declared bounds; else ValueError: a reading that
    implies a parameter outside its range (a negative omega0) is never offered."""
    for p in ex.params:
        v = values.get(p.name, p.default)
        if (p.min is not None and (v < p.min or (p.min_open and v == p.min))) or \
                (p.max is not None and (v > p.max or (p.max_open and v == p.max))):
            raise _OutOfRange("outside the declared bounds")
    return values


def _jointly(ex, values: dict) -> dict:
    """``values`` where the bounds and the exercise's joint limits accept them; else ValueError (no slip
    there)."""
    _in_bounds(ex, values)
    try:
        why = constraint_message(ex, Params(values))
    except (ArithmeticError, ValueError):
        why = "no"
    if why:
        raise _Refused("outside the joint limits")
    return values


def _zeroed(base: dict, slipped: dict) -> dict | None:
    """A parameter taken as 0 where mech's solver refuses 0 (another output divides by it): the same slip
    as its limit, the parameter at 1e-30 of its value (None when no parameter was taken as 0)."""
    zero = [k for k, v in slipped.items() if v == 0.0 and base.get(k, 0.0) != 0.0]
    return {**slipped, **{k: 1e-30 * base[k] for k in zero}} if zero else None


class _Points:
    """The points a slip is tried at (those judged where the answer has a value), the answer and mech's
    values there.  A slip (``at(i)``: its value at point i) fits when it gives the answer at every one,
    tried first at the points where the answer is wrong."""

    def __init__(self, ps: PointSet, output, yours, ref, tol, use, rtol: float):
        self.ps, self.output, self.name = ps, output, output.name
        self.yours, self.ref, self.tol, self.rtol = yours, ref, tol, rtol
        idx = [int(i) for i in np.flatnonzero(use & np.isfinite(yours) & np.isfinite(ref))]
        self.wrong = [i for i in idx if not self.near(i, ref[i])]
        self.order = self.wrong + [i for i in idx if i not in self.wrong]

    def near(self, i: int, v: float) -> bool:
        if not (isinstance(v, float) and math.isfinite(v)):
            return False
        r = self.ref[i]
        grow = max(1.0, abs(v / r)) if r else 1.0
        return bool(within(abs(self.yours[i] - v), scale=v, rel=self.rtol, bars=(self.tol[i] * grow,),
                           round_off=4 * np.finfo(float).eps))

    def fits(self, at) -> bool:
        # an answer right at most of its points is no slip of a whole formula: a slip that also gives it
        # there only moves a piecewise answer onto its other branch (5.11's growth = -delta, right at 23 of
        # 28 points); a slip that only matters in part of the range (delta halved off resonance) stays named
        if not self.wrong or 2 * len(self.wrong) < len(self.order):
            return False
        self.skipped = 0
        wrong_checked = False
        for i in self.order:
            try:
                v = at(i)
            except _OutOfRange:  # the reading implies a parameter outside its range: never offered
                return False
            except _Refused:  # a difference beyond the joint limits: not evaluated there, and said so
                self.skipped += 1
                continue
            except Exception:  # a slip with no value at a point: not named
                return False
            wrong_checked = wrong_checked or i in self.wrong
            if not self.near(i, float(v) if v is not None else math.nan):
                return False
        checked = len(self.order) - self.skipped
        return 2 * checked >= len(self.order) and wrong_checked

    def analytic(self, i: int, change, output: str | None = None) -> float:
        base = dict(self.ps.points[i])
        slipped = change(dict(base))
        got = _analytic_at(self.ps, slipped)
        if got is None and _zeroed(base, slipped):  # an answer that divides by it elsewhere: its limit
            got = _analytic_at(self.ps, _zeroed(base, slipped))
        v = got.get(output or self.name) if got else None
        return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else math.nan

    def approx(self, i: int) -> list:
        cache = self.ps.lines.setdefault(("explain", "approx", self.name), {})
        if i not in cache:
            try:
                cache[i] = [(float(v), d) for v, d in (declared(self.ps.ex, self.ps.points[i]).get(self.name)
                                                       or []) if isinstance(v, (int, float))]
            except Exception:  # an approximation with no value here
                cache[i] = []
        return cache[i]


def _slips(pts: _Points, unit: str, limit: int = 2) -> list[str]:
    """The slips that give the answer at every point, in the order a student most likely made them (at most
    ``limit``: a second one is named only when it, too, reproduces the answer)."""
    ps, name, ref = pts.ps, pts.name, pts.ref
    found: list[str] = []

    def tried(phrase, at) -> bool:
        if phrase not in found and pts.fits(at):
            k = getattr(pts, "skipped", 0)
            found.append(phrase + (f" (at the {len(pts.order) - k} of {len(pts.order)} points inside the "
                                   "exercise's joint limits)" if k else ""))
        return len(found) >= limit

    # a constant factor, a sign, both
    for c, phrase in _factors(unit):
        if tried(phrase, lambda i, c=c: c * ref[i]):
            return found
    # another output of the exercise, itself or with its sign flipped
    for o in ps.ex.outputs:
        if o.name != name and _same_dim(o.unit, unit):
            other = ps.analytic[o.name]
            if tried(f"that is mech's {o.name}, not its {name}", lambda i, a=other: a[i]):
                return found
            if tried(f"that is minus mech's {o.name}", lambda i, a=other: -a[i]):
                return found
    # the square or the square root of the answer
    if tried(f"this is mech's {name} squared", lambda i: ref[i] ** 2):
        return found
    if tried(f"this is the square root of mech's {name}", lambda i: math.sqrt(ref[i]) if ref[i] >= 0 else math.nan):
        return found
    # a declared approximation, a factor or a sign slip in it, and the sign or size of its correction
    declared = getattr(ps.ex, "_approximations", None) is not None
    if declared and pts.order and pts.approx(pts.order[0]):
        for k, (_, what) in enumerate(pts.approx(pts.order[0])):
            what = what if what.startswith(("the ", "a ", "an ")) else f"the {what}"

            def av(i, k=k):
                a = pts.approx(i)
                return a[k][0] if len(a) > k else math.nan

            if tried(f"this is {what}, a leading-order approximation", av):
                return found
            for c, phrase in _factors(unit):
                if tried(f"{what} (a leading-order approximation), {phrase}", lambda i, c=c, av=av: c * av(i)):
                    return found
            for phrase, at in _corrections(pts, unit, av):
                if tried(f"{what} (a leading-order approximation) with {phrase}", at):
                    return found
    if getattr(pts.output, "theory", "exact") != "exact":
        for phrase, at in _corrections(pts, unit, lambda i: ref[i]):
            if tried(f"the leading-order result with {phrase}", at):
                return found
    # a parameter left out, doubled or halved, two swapped, an angle read in degrees
    clock = _SlipClock()
    for phrase, change, far in _param_slips(ps.ex):
        if not clock.more(far):
            break
        if tried(phrase, lambda i, ch=change: clock.timed(pts.analytic, i, ch)):
            return found
    return found


class _SlipClock:
    """The parameter slips cost one analytic solve each (a point more when one fits).  A safety net
    counted in solves and work, never in seconds, so that the same slips are tried, and the same hint
    named, on any machine at any load: after a solve that did more than ``SLOW_WORK`` units of work
    (``core.budget``: a search's passes, an integration's evaluations), or ``MAX_SOLVES`` solves or
    ``MAX_WORK`` units in all, no further slip is tried (a solve already running is not stopped)."""

    SLOW_WORK = 20_000
    MAX_SOLVES = 2_000
    MAX_WORK = 200_000

    def __init__(self):
        from mech.core import budget

        self.used = budget.used
        self.start = self.used()
        self.solves = 0
        self.slowest = 0

    def more(self, far: bool = False) -> bool:
        return (self.slowest <= self.SLOW_WORK and self.solves < self.MAX_SOLVES
                and self.used() - self.start < self.MAX_WORK)

    def timed(self, f, *args):
        u = self.used()
        self.solves += 1
        try:
            return f(*args)
        finally:
            self.slowest = max(self.slowest, self.used() - u)


def _corrections(pts: _Points, unit: str, value) -> list:
    """(phrase, at): the correction to a parameter of the output's unit (omega0 in omega0 + 3 alpha A^2/
    (8 omega0)) with its sign flipped or off by a named factor."""
    out = []
    ps = pts.ps
    for p in ps.ex.params:
        if p.unit != unit:
            continue
        base = ps.arrays[p.name]
        for c, phrase in [(-1.0, "the wrong sign")] + [(c, f"a factor {t}") for c, t in _NAMED_FACTORS]:
            out.append((f"{phrase} in its correction to {p.name}",
                        lambda i, c=c, b=base: b[i] + c * (value(i) - b[i])))
    return out


def _dimension_power(formula_dim, out_dim, param_dim) -> Fraction | None:
    """k with formula_dim = out_dim - k param_dim (a parameter left out k times), or None."""
    diff = [a - b for a, b in zip(out_dim, formula_dim)]
    ks = {Fraction(d) / Fraction(p) for d, p in zip(diff, param_dim) if p != 0}
    if len(ks) != 1 or any(d != 0 for d, p in zip(diff, param_dim) if p == 0):
        return None
    k = ks.pop()
    return k if k != 0 else None


def dimension_could_be_a_slip(formula: Formula, output, params) -> bool:
    """Whether the dimensions alone leave one of ``dimension_hint``'s slips possible (no point needed): the
    formula has the dimension of the output squared or of its square root, or differs from it by a power
    of one parameter's dimension (``params``: the exercise's)."""
    if formula.dim is None:
        return False
    _, out_dim = dim_of_unit(output.unit)
    if formula.dim in (tuple(2 * x for x in out_dim), tuple(x / 2 for x in out_dim)):
        return True
    return any(_dimension_power(formula.dim, out_dim, dim_of_unit(p.unit)[1]) is not None
               for p in params)


def dimension_hint(formula: Formula, ps: PointSet, output, rtol: float) -> str | None:
    """For a formula of the wrong dimension: the slip that explains it, when it reproduces the formula at every
    point of ``ps`` ("this has the dimension of Omega^2: is it the square?", "g is missing: the dimension is
    off by (m/s^2)^(1/2)"), else None."""
    if formula.dim is None:
        return None
    name = output.name
    _, out_dim = dim_of_unit(output.unit)
    env = {k: ps.arrays[k] for k in formula.names} or {"_": np.zeros(len(ps))}
    with np.errstate(all="ignore"):
        y, e, _ = formula.evaluate(env)
    ref, err = ps.analytic[name], ps.analytic_err[name]
    tol = allowance(ref, rel=rtol, bars=(err,), round_off=4 * np.finfo(float).eps, own=4 * e)
    pts = _Points(ps, output, y, ref, tol, np.ones(len(ps), bool), rtol)
    if len(pts.order) < 1:
        return None
    if formula.dim == tuple(2 * x for x in out_dim):
        for c, text in [(1.0, "")] + [(c, f" (it is {name}^2 times {t})") for c, t in _NAMED_FACTORS]:
            if pts.fits(lambda i, c=c: c * ref[i] ** 2):
                return f"this has the dimension of {name}^2: is it the square?{text}"
    if formula.dim == tuple(x / 2 for x in out_dim) and pts.fits(
            lambda i: math.sqrt(ref[i]) if ref[i] >= 0 else math.nan):
        return f"this has the dimension of sqrt({name}): is it the square root?"
    for p in ps.ex.params:
        _, pdim = dim_of_unit(p.unit)
        k = _dimension_power(formula.dim, out_dim, pdim)
        if k is None:
            continue
        if pts.fits(lambda i, n=p.name: pts.analytic(i, lambda d: {**d, n: 1.0})):
            power = "" if k == 1 else (f"^{k}" if k.denominator == 1 else f"^({k})")
            unit = p.unit if k == 1 or "/" not in p.unit and "*" not in p.unit else f"({p.unit})"
            return f"{p.name} is missing: the dimension is off by {unit}{power}"
    return None


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
    mech's values ``ref`` there, wrong at one point at least.  The slips are searched at the points where it
    can be evaluated; a point where it cannot is a second finding."""
    name = output.name
    judged = pj.judged
    wrong = judged & ~pj.right
    dom = [int(i) for i in np.flatnonzero(wrong) if problem_text(pj, ps, int(i))]
    evaluable = judged & np.isfinite(pj.yours)
    wrong_here = [int(i) for i in np.flatnonzero(wrong & evaluable)]
    i_fail = wrong_here[0] if wrong_here else int(np.flatnonzero(wrong)[0])
    domain = None
    if dom:
        k = len(dom)
        domain = (f"it cannot be evaluated {describe_point(ps, dom[0])}: {problem_text(pj, ps, dom[0])}"
                  + (f" (and at {k - 1} more point{'s' if k > 2 else ''})" if k > 1 else ""))
    if not wrong_here:  # right wherever it has a value
        if domain:
            n_ok = int((evaluable & pj.right).sum())
            head = f"right at the {n_ok} points where it has a value, but " if n_ok else ""
            return FormulaHint(head + domain, dom[0], [])
        return FormulaHint(None, i_fail, [])
    hint, guilty = _wrong_hint(formula, ps, output, pj, ref, rtol, evaluable)
    if domain:
        hint = f"{hint}; {domain}" if hint else domain
    return FormulaHint(hint, i_fail, guilty)


def _wrong_hint(formula, ps, output, pj, ref, rtol, evaluable) -> tuple[str | None, list]:
    name = output.name
    pts = _Points(ps, output, pj.yours, ref, pj.tol, evaluable, rtol)
    with np.errstate(all="ignore"):
        slips = _slips(pts, output.unit)
    if slips:
        hint = " or ".join(slips)
        if len(slips) == 1 and slips[0].endswith(", a leading-order approximation"):
            limits = _limit_names(formula, ps, name, list(formula.names))
            if limits:
                hint += "; it holds only for " + (limits[0] if len(limits) == 1
                                                  else ", ".join(limits[:-1]) + " or " + limits[-1])
        return hint, []
    # no slip reproduces it: say what was measured
    hint = None
    c = _const_ratio(pj.yours, ref, pj.tol, evaluable)
    if c is not None:
        return f"off by a constant factor {_nice_factor(c)} at every point", []
    deps = depends(ps, name)
    missing = [k for k in deps if k not in formula.names]
    limits = []
    if output.theory == "exact":
        limits = _limit_names(formula, ps, name, missing)
    if missing:
        hint = f"mech's {name} depends on {_and(missing)}, which your formula leaves out"
    if limits:
        said = limits[0] if len(limits) == 1 else ", ".join(limits[:-1]) + " or " + limits[-1]
        params = list(dict.fromkeys(w.split()[-1] if w.startswith(("small ", "large ")) else w.split()[0]
                                    for w in limits))
        lim = f"it agrees with mech only in the limit of {said}; compare its {_and(params)} dependence"
        hint = f"{hint}; {lim}" if hint else lim
    innocent, guilty = [], []
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
    return hint, guilty


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
    # a factor is a slip only where it stands well clear of the tolerance (1 + 1e-9 is no factor), and it
    # must reproduce the answer within half the tolerance the answer was judged by
    rel = float(np.max(tol[use] / np.abs(ref[use])))
    if within(abs(c - 1.0), bars=(10.0 * rel,)):
        return None
    with np.errstate(over="ignore"):  # a huge factor: its bound is infinite, as it was before it overflowed
        held = within(np.abs(yours[use] - c * ref[use]), bars=(0.5 * tol[use] * max(1.0, abs(c)),))
    if np.all(held):
        return c
    return None


def _ratio_constant(formula: Formula, line: PointSet, output: str, rtol: float) -> bool | None:
    ref = line.analytic[output]
    pj = judge_points(formula, line, ref, line.analytic_err[output], rtol, name=output)
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


def _limit_names(formula: Formula, ps: PointSet, output: str, missing: list[str]) -> list[str]:
    """The limits ("small theta", "large M") in which the formula becomes mech's answer, when it is close at
    the given parameters: the limit value of an answer whose dependence on a parameter it leaves out
    (T = 2 pi sqrt(l/g) for the pendulum), or a formula right to first order as a parameter goes to its
    limit.  Said as a measurement ("agrees only as ..."), never as an approximation: that name is kept for
    the approximations the exercise declares."""
    found = _limits(formula, ps, output)
    r_given = ps.analytic[output][0]
    off = abs(yours_at_given(formula, ps) - r_given) / abs(r_given)
    named = [w for w, k, _ in found if k in missing] if off < 0.25 else []
    if not named and off < 0.1:
        named = [w for w, _, first in found if first]
    return named


def _change(names: list[str]) -> str:
    return "changes" if len(names) == 1 else "change"


def _and(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
