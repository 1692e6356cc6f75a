"""Judging a formula given as an answer: its dimension, then its value across the exercise's declared range.

A formula (``formula_ast.Formula``) is held against mech's reference

* at the given parameters, where the reference is the one the answers judge uses (the analytic value
  confirmed by the numeric one, or for a leading-order output either the leading-order value or the
  verified numeric value);
* at ``n`` parameter sets drawn across every parameter's declared bounds (log-uniform on a positive
  range), inside the exercise's joint constraints, plus the defaults and the catalogue's hard cases.
  Where an exercise refuses most of its box, a draw it refuses is repaired one parameter at a time:
  with the others held, that parameter's allowed interval is found on a grid and refined by bisection,
  and the value is drawn inside it.  The reference there is the analytic value (exact theory), or for a
  leading-order output the leading-order value, else the numeric value of the exercise's own numeric
  route, verified by its rerun at rtol/10.

A point is right when the formula's exact value there (certified by interval arithmetic) is within
``rtol |mech| + mech's error bar + 4 ulp + 64 ulp of the output's scale`` (``points.judge_points``); the
point set and mech's values are computed once (``points``), the hints come from ``explain``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mech.students.explain import dimension_could_be_a_slip, dimension_hint, formula_hint
from mech.students.formula_ast import Formula, dim_of_unit, dim_text
from mech.verification.judge import Verdict, allowance, judge, within
from mech.students.points import (DEFAULT_POINTS, DEFAULT_SEED, RIGHT, PointJudgement, PointSet, describe_point,
                                      holds_at, judge_points, parse_over, point_set)

__all__ = ["DEFAULT_POINTS", "DEFAULT_SEED", "FORMULA_RTOL", "PointSet", "point_set", "judge_formula",
           "FormulaVerdict", "parse_over", "show_value", "show_pair", "known"]

FORMULA_RTOL = 1e-9  # a formula is exact: its numbers are as written


NUMERIC_WORK = 600_000  # units of work (core.budget) for the numeric reference of a leading-order output

BEYOND = 3.0  # how much closer than the leading-order value a next-order answer must be to the exact one


def show_value(v: float, unit: str, digits: int = 6) -> str:
    """A value in the output's unit (an angle also in degrees)."""
    if not math.isfinite(v):
        return "not a number" if math.isnan(v) else str(v)
    u = "" if unit == "1" else f" {unit}"
    if unit == "rad":
        return f"{v:.{digits}g} rad ({math.degrees(v):.{digits}g} deg)"
    return f"{v:.{digits}g}{u}"


def show_pair(yours: float, mech: float, unit: str) -> tuple[str, str]:
    """Both values with enough digits (6 at least) to show where they differ."""
    for digits in range(6, 18):
        a, b = show_value(yours, unit, digits), show_value(mech, unit, digits)
        if a != b:
            return a, b
    return a, b


# -- the verdict ----------------------------------------------------------------------------------------


@dataclass
class FormulaVerdict:
    match: bool
    verdict: str
    hint: str | None
    value: float  # yours at the given point
    reference_value: float | None
    rel_err: float | None
    tol: float | None
    dimension: dict
    points: dict
    depends: list
    formula: str
    matches: str | None = None  # a leading-order output: "beyond-leading-order" for a next-order answer
    state: str | None = None  # "not-graded" where no verdict was reached (the reason in ``verdict``)


def judge_formula(formula: Formula, ex, output, ps: PointSet, given_ref, rtol: float | None,
                  numeric_given: tuple | None = None, given_in_range: bool = True) -> FormulaVerdict:
    """Judge ``formula`` for ``output`` (a spec Output) over the point set ``ps``.

    ``given_ref``: (value, err) of mech's trusted reference at the given point (None when there is none);
    ``numeric_given``: (value, err) of the verified numeric value there, for a leading-order output;
    ``given_in_range``: False when the given parameters lie outside the range the formula is meant to hold
    in (``over``): then it is judged at the other points only.
    """
    _, out_dim = dim_of_unit(output.unit)
    dimension = {"ok": formula.dim == out_dim, "yours": dim_text(formula.dim) if formula.dim else None,
                 "output": output.unit}
    base = dict(formula=formula.text, dimension=dimension, depends=[])
    if formula.dim is None or formula.dim != out_dim:
        why = (f"your formula has the dimension of {dim_text(formula.dim)}; {output.name} is in {output.unit}"
               if formula.dim is not None else f"your formula mixes dimensions: {formula.dim_error}")
        if formula.dim is None:
            dimension["error"] = formula.dim_error
        else:  # a slip that explains the dimension, when it reproduces the formula at every point
            slip = _dimension_slip(formula, ex, output, ps, FORMULA_RTOL if rtol is None else rtol)
            if slip:
                why = f"{why}: {slip}"
        return FormulaVerdict(False, f"wrong dimension: {why}", why, math.nan, None, None, None,
                              points={"checked": 0, "right": 0}, **base)
    from mech.core import budget

    try:
        # the points drawn only once the dimension is right, and everything within a work budget (the same
        # verdict at any load); a command's clock around it (grade's --budget, MECH_BUDGET_S) stops it too
        with budget.limit(what="checking the formula", work=budget.CHECK_WORK), np.errstate(all="ignore"):
            if callable(ps):
                ps = ps()
            return _judge_at_points(formula, ex, output, ps, given_ref, rtol, numeric_given, given_in_range,
                                    base)
    except budget.OutOfBudget as exc:
        return _not_graded(exc, **base)
    except MemoryError:
        return FormulaVerdict(False, "not graded: too many points for the memory at hand (ask for fewer points)",
                              None, math.nan, None, None, None, points={"checked": 0, "right": 0},
                              state="not-graded", **base)


def _dimension_slip(formula: Formula, ex, output, ps, rtol: float) -> str | None:
    """The slip that explains a wrong dimension (a square, a square root, a parameter left out), checked at
    points drawn only when the dimensions leave such a slip possible (``explain.dimension_could_be_a_slip``),
    at most ``DEFAULT_POINTS`` of them whatever the entry asked for, and within the budget: a formula of the
    wrong dimension never pays for the points its right-dimension check would draw."""
    from mech.core import budget

    if not dimension_could_be_a_slip(formula, output, ex.params):
        return None
    try:
        with budget.limit(what="naming the slip behind the dimension", work=budget.CHECK_WORK), \
                np.errstate(all="ignore"):
            points = ps(DEFAULT_POINTS) if callable(ps) else ps
            return dimension_hint(formula, points, output, rtol)
    except (budget.OutOfBudget, MemoryError):
        return None


def _not_graded(exc, **base) -> FormulaVerdict:
    from mech.core.safeio import shown

    what, where = getattr(exc, "what", None), getattr(exc, "where", "")
    from mech.core import budget

    spent = "its work budget" if isinstance(exc, budget.OutOfWork) else "time"
    text = (f"{what} ran out of {spent}" + (f" while {where}" if where else "")) if what else str(exc)
    return FormulaVerdict(False, f"not graded (budget): {shown(text, 160)}", None, math.nan, None, None, None,
                          points={"checked": 0, "right": 0}, state="not-graded", **base)


def _judge_at_points(formula, ex, output, ps, given_ref, rtol, numeric_given, given_in_range, base):
    rtol = FORMULA_RTOL if rtol is None else rtol
    name = output.name
    lead = output.theory != "exact"
    ref = ps.analytic[name].copy()
    ref_err = ps.analytic_err[name].copy()
    if given_ref is None or not given_in_range:
        ref[0] = np.nan
    elif not lead:
        ref[0], ref_err[0] = given_ref
    pj = judge_points(formula, ps, ref, ref_err, rtol, name=name)
    notes = []
    if lead:
        exact_here = _leading_order_numeric(formula, ex, output, ps, pj, rtol, numeric_given, notes)
        outside = ps.outside.get(name, np.zeros(len(ps), bool)) & ~exact_here
        if outside.any():
            # beyond its theory's range the leading-order value is no answer and the exact one is not what
            # was asked: such points are left out (a formula that matches the exact value there is right)
            pj.judged = pj.judged & ~outside
            pj.right = pj.right & ~outside
            k = int(outside.sum())
            notes.append(f"{k} point{'s' if k > 1 else ''} outside the leading-order theory's range not judged")
    if pj.skipped:
        notes.append(f"{pj.skipped} point{'s' if pj.skipped > 1 else ''} not worked out in high precision once "
                     "wrong ones were found")
    overflow = np.array([w == "not finite" for w in ps.undefined.get(name, [])], bool)
    if overflow.size == len(ps) and overflow[1:].any():
        k = int(overflow[1:].sum())
        notes.append(f"{k} point{'s' if k > 1 else ''} where mech's own value overflows left out")
    judged = pj.judged
    wrong = judged & ~pj.right
    n_checked, n_right = int(judged.sum()), int(pj.right.sum())
    y0 = float(pj.yours[0])
    r0 = float(ref[0]) if math.isfinite(ref[0]) else None
    rel0 = abs(y0 - r0) / abs(r0) if r0 not in (None, 0.0) and math.isfinite(y0) else None
    worst_i = _worst(pj, ref)
    points = {"checked": n_checked, "right": n_right}
    if worst_i is not None:
        points["worst"] = {"params": dict(ps.points[worst_i]), "label": ps.labels[worst_i],
                           "yours": _finite(pj.yours[worst_i]), "mech": _finite(ref[worst_i]),
                           "rel_err": _finite(abs(pj.yours[worst_i] - ref[worst_i]) / abs(ref[worst_i])
                                              if ref[worst_i] else abs(pj.yours[worst_i] - ref[worst_i]))}
    ill = [i for i in range(len(ps)) if pj.ill[i]]
    if ill:
        points["ill_conditioned"] = len(ill)
    kinds = _kinds(ps, judged)
    if given_ref is None and given_in_range:
        return FormulaVerdict(False, "cannot judge: mech has no trusted value at the given parameters", None, y0,
                              None, None, None, points=points, state="not-graded", **base)
    undecided = pj.undecided if pj.undecided is not None else np.zeros(len(ps), bool)
    if n_checked == 0 and not undecided.any():
        return FormulaVerdict(False, "cannot judge: mech has no value at any point", None, y0, r0, rel0, None,
                              points=points, state="not-graded", **base)
    if not wrong.any() and undecided.any():
        # right wherever decided, but some point no precision up to the cap decides: never right
        k = int(undecided.sum())
        i = int(np.flatnonzero(undecided)[0])
        from mech.students.formula_ast import MAX_PREC

        return FormulaVerdict(False, f"not graded: right at {n_right} points, but {k} point{'s' if k > 1 else ''} "
                              f"cannot be decided in exact arithmetic (interval arithmetic up to {MAX_PREC} bits), "
                              f"{describe_point(ps, i)}", None, y0, r0, rel0, float(pj.tol[0]),
                              points={**points, "undecided": k}, state="not-graded", **base)
    if not wrong.any():
        text = f"right at all {n_checked} points ({kinds})"
        if ill:
            text += (f"; ill-conditioned in double precision {describe_point(ps, ill[0])} (right in exact "
                     "arithmetic)")
        text += "".join(f"; {n}" for n in notes)
        matches = None
        if lead:
            matches = ("beyond-leading-order" if any(n.startswith("beyond leading order") for n in notes)
                       else "exact" if any("numeric value rather" in n for n in notes) else "leading-order")
            if matches == "beyond-leading-order":  # the verdict says so first
                text = "right beyond leading order, " + text.removeprefix("right ")
        return FormulaVerdict(True, text, None, y0, r0, rel0, float(pj.tol[0]), points=points, matches=matches,
                              **base)
    # wrong: find what a student can act on
    found = formula_hint(formula, ps, output, pj, ref, rtol)
    hint, i_fail = found.hint, found.at
    base["depends"] = found.guilty
    ys, ms = show_pair(float(pj.yours[i_fail]), float(ref[i_fail]), output.unit)
    at = f"{describe_point(ps, i_fail)}: yours {ys}, mech {ms}"
    head = f"wrong at {int(wrong.sum())} of {n_checked} points" + "".join(f" ({n})" for n in notes)
    verdict = f"{head}: {hint}; {at}" if hint else f"{head}; {at}"
    return FormulaVerdict(False, verdict, hint, y0, r0, rel0, float(pj.tol[0]), points=points, **base)


def _kinds(ps: PointSet, judged: np.ndarray) -> str:
    """Which points were judged: ``the given parameters, 24 drawn across the range, 1 hard case``."""
    labels = [lab for lab, j in zip(ps.labels, judged) if j]
    n = {k: labels.count(k) for k in ("given", "drawn", "defaults", "hard case")}
    parts = ["the given parameters"] if n["given"] else []
    if n["drawn"]:
        parts.append(f"{n['drawn']} drawn across the range")
    if n["defaults"]:
        parts.append("the defaults")
    if n["hard case"]:
        parts.append(f"{n['hard case']} hard case{'s' if n['hard case'] > 1 else ''}")
    return ", ".join(parts)


def _finite(v):
    v = float(v)
    return v if math.isfinite(v) else None


def _worst(pj: PointJudgement, ref) -> int | None:
    use = np.flatnonzero(pj.judged)
    if use.size == 0:
        return None
    with np.errstate(all="ignore"):
        d = np.abs(pj.yours - ref) / np.where(ref != 0, np.abs(ref), 1.0)
    d = np.where(np.isfinite(d), d, np.inf)
    return int(use[np.argmax(d[use])])


def _leading_order_numeric(formula, ex, output, ps, pj, rtol, numeric_given, notes) -> np.ndarray:
    """A leading-order output: a point that misses the leading-order value is right when it matches the
    verified numeric value there (the given point: the cross-check's; elsewhere: solved here, within a
    budget, stopping at the first point the numeric value does not confirm).  Where the exercise has a
    batched route for the output, the references come from it: the first point alone (a wrong formula
    stops there), then the rest at once."""
    from mech.core import budget

    name = output.name
    misses = [i for i in range(len(ps)) if pj.judged[i] and not pj.right[i] and math.isfinite(pj.yours[i])]
    u0 = budget.used()
    outside_theory = ps.outside.get(name, np.zeros(len(ps), bool))
    # the points inside the theory's range first: there a miss decides the verdict; beyond it a miss is
    # left out, and the budget is spent there last
    misses.sort(key=lambda i: (bool(outside_theory[i]), i))
    confirmed = beyond = closer = 0
    exact_here = np.zeros(len(ps), bool)
    batched = _batchable(ex, name)
    for i in misses:
        if i == 0:
            if numeric_given is None:
                break
            n, err = numeric_given
        else:
            if budget.used() - u0 > NUMERIC_WORK:  # counted work, not seconds: the same points at any load
                rest = [j for j in misses if j >= i and not pj.right[j]]
                pj.judged[rest] = False
                notes.append(f"mech's numeric reference was worked out at {len(misses) - len(rest)} of the "
                             f"{len(misses)} points that needed it (its work budget): the other "
                             f"{len(rest)} are not judged")
                break
            if batched and (name, i) not in ps.numeric:
                later = [j for j in misses if j >= i]
                _batched_numeric(ex, ps, later[:1] if confirmed == 0 else later[:BATCH], name)
            got = _verified_at(ex, ps, i, name)
            if got is None:
                break
            n, err = got
        lead_i = ps.analytic[name][i]
        allow = float(allowance(n, rel=rtol, bars=(err,), round_off=4 * np.finfo(float).eps))
        gap = abs(lead_i - n) if math.isfinite(lead_i) else math.nan
        far = _farthest(pj, i, n)  # the exact value's farthest distance from n, certified
        if holds_at(formula, ps, pj, i, n, allow) == RIGHT:
            pj.right[i] = True
            exact_here[i] = True
            confirmed += 1
        elif math.isfinite(gap) and BEYOND * (far + err) <= gap:
            # a next-order answer: closer to the verified exact value than the leading-order value, by 3x
            pj.right[i] = True
            exact_here[i] = True
            beyond += 1
        elif math.isfinite(gap) and far + err <= gap and not outside_theory[i]:
            # monotone: at least as close to the exact value as the leading-order value (right) is
            pj.right[i] = True
            exact_here[i] = True
            closer += 1
        elif outside_theory[i]:
            continue  # beyond the theory's range a miss of the exact value is left out, not judged wrong
        else:
            break
    if confirmed:
        notes.append(f"at {confirmed} point{'s' if confirmed > 1 else ''} it matches mech's numeric value "
                     "rather than the leading-order one")
    if closer:
        notes.append(f"at {closer} point{'s' if closer > 1 else ''} closer to mech's verified exact value than the "
                     "leading-order value is")
    if beyond:
        notes.append(f"beyond leading order: at {beyond} point{'s' if beyond > 1 else ''} closer to mech's verified "
                     f"exact value than the leading-order value is, by {BEYOND:g}x at least")
    return exact_here


def _farthest(pj: PointJudgement, i: int, n: float) -> float:
    """The largest distance from ``n`` of the formula's exact value at point ``i`` (its enclosure's), rounded
    up; inf where it is not enclosed."""
    with np.errstate(all="ignore"):
        d = max(np.nextafter(float(pj.hi[i]) - n, np.inf), np.nextafter(n - float(pj.lo[i]), np.inf))
    return float(d) if math.isfinite(d) else math.inf


BATCH = 32  # points a batched numeric call takes at once (the budget is looked at between calls)


def _batchable(ex, name: str) -> bool:
    """Does ``ex`` have a batched route for ``name``, with a rerun tighter than its default rtol?"""
    route = getattr(ex, "batched_route", None)
    return (route is not None and name in route.outputs
            and max(ex.default_rtol / 10.0, ex.min_rtol) < ex.default_rtol)


def _batched_numeric(ex, ps: PointSet, idx: list[int], name: str) -> None:
    """The verified numeric values of ``name`` at the points ``idx`` from the exercise's batched route (at
    its rtol and rtol/10), judged by the judge as a numeric-only cross-check judges them (``_verified_at``),
    into ``ps.numeric``: (value, its error bar), or None where the route finds no value or the judge finds
    it unverified; a batch that fails as a whole leaves its points to ``_verified_at``."""
    import inspect

    idx = [i for i in idx if (name, i) not in ps.numeric]
    if not idx:
        return
    route = ex.batched_route
    rtol = ex.default_rtol
    tighter = max(rtol / 10.0, ex.min_rtol)
    P = {k: ps.arrays[k][idx] for k in ex.param_map}
    takes_memo = "memo" in inspect.signature(route.numeric).parameters
    try:
        cols = [(route.numeric(P, tol, (name,), memo=ps.batch_memo) if takes_memo
                 else route.numeric(P, tol, (name,)))[name] for tol in (rtol, tighter)]
    except Exception as exc:  # a failed batch: these points are verified one by one instead (``_verified_at``)
        _budget_out(exc)
        return
    n, v = cols
    J = judge(analytic=np.nan, numeric=n.value, has_analytic=False, n_undefined=n.mask("undefined"),
              n_failed=n.mask("failed"), rel_claim=n.rel, abs_claim=n.abs, verify=v.value,
              v_number=~(v.mask("undefined") | v.mask("failed")))
    ok = _verified(J.verdict, J.verify_diff, J.numeric_err)
    for j, i in enumerate(idx):
        ps.numeric[(name, i)] = (float(n.value[j]), float(J.numeric_err[j])) if ok[j] else None


def _verified(verdict, verify_diff, err) -> np.ndarray:
    """A numeric-only value the judge finds verified: its rerun at rtol/10 ran and held it to its claim."""
    return (np.asarray(verdict) == Verdict.NUMERIC_ONLY) & np.isfinite(verify_diff) & np.isfinite(err)


def _budget_out(exc) -> None:
    """Re-raise ``exc`` when it is the formula's budget running out (not one point's failure)."""
    from mech.core import budget

    if isinstance(exc, budget.OutOfBudget) and budget.expired():
        raise exc


def _verified_at(ex, ps: PointSet, i: int, name: str):
    """mech's verified numeric value of ``name`` at point ``i`` and its error bar, from the cross-check
    (numeric only: the value, its rerun at rtol/10, the judge's verdict), or None where it has none."""
    key = (name, i)
    if key in ps.numeric:
        return ps.numeric[key]
    from mech.verification.crosscheck import cross_check

    got = None
    try:
        sol = cross_check(ex, ps.points[i], methods=("numeric",), fork_rerun=False)
        q = sol[name]
        # a failure of the theory's range estimate says nothing about the numeric value; any other does
        failed = any(e.kind != "estimate" for e in sol.errors)
        if not failed and isinstance(q.numeric, float) and q.numeric_err is not None:
            verify_diff = math.nan if q.verify_diff is None else q.verify_diff
            if _verified(q.verdict, verify_diff, q.numeric_err):
                got = (float(q.numeric), float(q.numeric_err))
    except Exception as exc:  # a numeric failure there: no verified value, the point stays wrong
        _budget_out(exc)
        got = None
    ps.numeric[key] = got
    return got


# -- the seam with the answers judge --------------------------------------------------------------------


def known(result) -> dict | None:
    """The solve's analytic values and error bars at its parameters, ``{output: (value, err)}``, when it
    solved every output analytically (a value or an Undefined); else None (the point set solves them)."""
    known = {}
    for q in result.quantities:
        if q.analytic is None or (result.errors and any(f.kind == "analytic" for f in result.errors)):
            return None
        known[q.name] = (q.analytic, q.analytic_err)
    return known
