"""The one judge: whether an analytic and a numeric value agree, written once, on arrays.

Every caller hands it arrays, one element per judged value: the cross-check
of one solve (one element per output), the batched and the point-by-point
sweeps, and so ``mech check``, ``grade``, ``--expect``, baselines and the Python
API, which all read the cross-check's verdicts.  Nothing else compares an
analytic value with a numeric one.

The rule, for one element:

* ``numeric_err = rel_claim |n| + abs_claim``: the numeric claim
  (``Run.claim``, default ``tol_factor * rtol``), in absolute terms;
* the relative tolerance ``tol`` is the claim, at least the size of what a
  leading-order theory neglects (``expected_rel``) where the theory is inside
  its range; the absolute allowance is the larger of ``abs_claim`` and the
  theory's absolute neglect (``expected_abs``);
* **agree** when ``|n - a| <= tol |a| + allowance + analytic_err``;
* both values undefined agree, one undefined disagrees; where a leading-order
  theory finds no value but what it neglects allows one up to ``expected_abs``,
  the numeric value agrees when it is no larger than that;
* **unreliable** (disagree) when the rerun at rtol/10 moves the numeric value
  by more than its claim (``rel_claim`` times the analytic value, or the numeric
  one, plus ``abs_claim``), or when the claim is not finite;
* **outside its range** (no verdict) where a leading-order theory does not
  apply (``Exercise.theory_validity``): nothing is compared, the numeric value,
  verified by its rerun, is the answer (an unreliable one still fails);
* **analytic only** / **numeric only** (no verdict) where one method did not
  run, and no verdict where the numeric solve failed (the failure is loud).

``agree`` is an int8 array: 1 agree, 0 disagree, -1 no verdict.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Judged", "judge", "within", "notes", "theory_validity", "theory_validity_batch", "approximations",
           "AGREE", "DISAGREE", "UNRELIABLE", "NO_CLAIM", "ONE_UNDEFINED", "OUTSIDE", "ANALYTIC_ONLY",
           "NUMERIC_ONLY", "FAILED", "VERDICTS"]

# what was found, one code per element (``Judged.verdict``)
AGREE, DISAGREE, UNRELIABLE, NO_CLAIM, ONE_UNDEFINED, OUTSIDE, ANALYTIC_ONLY, NUMERIC_ONLY, FAILED = range(9)
VERDICTS = {AGREE: "agree", DISAGREE: "disagree", UNRELIABLE: "unreliable", NO_CLAIM: "no finite claim",
            ONE_UNDEFINED: "one method finds no value", OUTSIDE: "theory outside its range",
            ANALYTIC_ONLY: "analytic only", NUMERIC_ONLY: "numeric only", FAILED: "numeric solve failed"}


def within(diff, allowed):
    """The inequality of every comparison mech makes between two values: ``diff <= allowed`` (arrays or
    numbers; NaN is never within)."""
    return diff <= allowed


@dataclass
class Judged:
    """The verdicts on N values and what they were judged with (arrays of N)."""

    agree: np.ndarray  # int8: 1 agree, 0 disagree, -1 no verdict
    verdict: np.ndarray  # int8: one of the codes above
    tol: np.ndarray  # the relative tolerance applied
    allowed: np.ndarray  # the absolute allowance |n - a| was held to (NaN where nothing was compared)
    abs_err: np.ndarray
    rel_err: np.ndarray
    numeric_err: np.ndarray
    verify_diff: np.ndarray
    verify_claim: np.ndarray
    small: np.ndarray  # a leading-order theory finds no value; judged against what it neglects
    outside: np.ndarray
    outside_why: list
    expected_abs: np.ndarray

    def __len__(self) -> int:
        return int(self.agree.size)


def _arr(x, n, dtype=float):
    return np.broadcast_to(np.asarray(x, dtype=dtype), (n,))


def judge(*, analytic, numeric, a_undefined=False, n_undefined=False, n_failed=False, has_analytic=True,
          has_numeric=True, rel_claim, abs_claim=0.0, analytic_err=0.0, leading=False, expected_rel=np.nan,
          expected_abs=np.nan, verify=None, v_number=None, outside=None, outside_why=None) -> Judged:
    """Judge N values at once (every argument an array of N or a scalar broadcast to N).

    ``analytic``/``numeric``: the values (NaN where there is none); ``a_undefined``/``n_undefined``: the
    method found no finite value (``Undefined``); ``n_failed``: the numeric solve failed there;
    ``has_analytic``/``has_numeric``: the method ran; ``rel_claim``/``abs_claim``: the numeric claim;
    ``analytic_err``: the analytic value's round-off (absolute); ``leading``: a leading-order output;
    ``expected_rel``/``expected_abs``: what its theory neglects (NaN: not given); ``verify``: the rerun's
    values at rtol/10 (None: no rerun) with ``v_number`` where it gave a number; ``outside``: where a
    leading-order theory is outside its range, ``outside_why`` the reasons.
    """
    with np.errstate(all="ignore"):  # NaN marks what is missing: comparisons with it are simply False
        return _judge(analytic, numeric, a_undefined, n_undefined, n_failed, has_analytic, has_numeric, rel_claim,
                      abs_claim, analytic_err, leading, expected_rel, expected_abs, verify, v_number, outside,
                      outside_why)


def _judge(analytic, numeric, a_undefined, n_undefined, n_failed, has_analytic, has_numeric, rel_claim, abs_claim,
           analytic_err, leading, expected_rel, expected_abs, verify, v_number, outside, outside_why) -> Judged:
    a = np.atleast_1d(np.asarray(analytic, dtype=float))
    n = np.atleast_1d(np.asarray(numeric, dtype=float))
    N = max(a.size, n.size)
    a, n = _arr(a, N), _arr(n, N)
    a_und, n_und, n_fail = (_arr(x, N, bool) for x in (a_undefined, n_undefined, n_failed))
    has_a, has_n, lead = (_arr(x, N, bool) for x in (has_analytic, has_numeric, leading))
    rel = _arr(rel_claim, N)
    tol_abs = _arr(abs_claim, N)
    a_err = np.nan_to_num(_arr(analytic_err, N), nan=0.0)
    e_rel, e_abs = _arr(expected_rel, N), _arr(expected_abs, N)
    out_mask = np.zeros(N, bool) if outside is None else _arr(outside, N, bool)
    why = list(outside_why) if outside_why is not None else [""] * N

    # what a leading-order theory neglects widens the tolerance where it applies; an absolute part alone
    # makes the relative one 0
    e_rel = np.where(lead & np.isnan(e_rel) & ~np.isnan(e_abs), 0.0, e_rel)
    widen = lead & ~out_mask & ~np.isnan(e_rel)
    tol = np.where(widen, np.fmax(rel, e_rel), rel)
    allowed_abs = np.where(lead & ~out_mask, np.fmax(tol_abs, np.nan_to_num(e_abs, nan=0.0)), tol_abs)

    a_num = has_a & ~a_und & np.isfinite(a)
    n_num = has_n & ~n_und & ~n_fail & np.isfinite(n)
    a_und = has_a & (a_und | ~np.isfinite(a) & ~a_num)
    n_und = has_n & ~n_fail & (n_und | ~np.isfinite(n) & ~n_num)
    both = a_num & n_num
    abs_err = np.where(both, np.abs(n - a), np.nan)
    denom = np.where(a != 0, np.abs(a), np.abs(n))
    rel_err = np.where(both, np.where(denom > 0, abs_err / denom, 0.0), np.nan)
    allowed = np.where(both, tol * np.abs(a) + allowed_abs + a_err, np.nan)
    numeric_err = np.where(n_num, rel * np.abs(n) + tol_abs, np.nan)

    agree = np.full(N, -1, np.int8)
    verdict = np.full(N, FAILED, np.int8)
    verdict[~has_a & has_n] = NUMERIC_ONLY
    verdict[has_a & ~has_n] = ANALYTIC_ONLY
    verdict[~has_a & ~has_n] = FAILED
    ok = within(abs_err, allowed)
    agree[both] = ok[both]
    verdict[both] = np.where(ok, AGREE, DISAGREE)[both]
    # one method finds no finite value where the other does (or both find none: they agree)
    one = has_a & has_n & (a_und | n_und) & ~n_fail
    agree[one] = (a_und & n_und)[one]
    verdict[one] = np.where(a_und & n_und, AGREE, ONE_UNDEFINED)[one]
    # the leading-order theory finds no value, but what it neglects allows one this large
    small = lead & ~out_mask & a_und & n_num & (np.nan_to_num(e_abs, nan=0.0) > 0)
    ok_small = within(np.abs(n), e_abs + numeric_err)
    agree[small] = ok_small[small]
    verdict[small] = np.where(ok_small, AGREE, DISAGREE)[small]
    # a leading-order theory outside its range: nothing compared
    gone = out_mask & lead & has_a & has_n & ~n_fail
    agree[gone] = -1
    verdict[gone] = OUTSIDE
    # an error bar of infinity would agree with anything: no number at all is better
    no_claim = n_num & ~(np.isfinite(rel) & np.isfinite(tol_abs))
    agree[no_claim] = 0
    verdict[no_claim] = NO_CLAIM
    # the rerun at rtol/10: a value that moves by more than its claim did not earn it
    verify_diff = np.full(N, np.nan)
    claim = np.full(N, np.nan)
    if verify is not None:
        v = _arr(verify, N)
        v_num = np.isfinite(v) if v_number is None else _arr(v_number, N, bool) & np.isfinite(v)
        chk = n_num & v_num
        verify_diff = np.where(chk, np.abs(v - n), np.nan)
        scale = np.where(a_num & (a != 0), np.abs(a), np.abs(n))
        claim = np.where(chk, rel * scale + tol_abs, np.nan)
        moved = chk & ~within(verify_diff, claim)
        agree[moved] = 0
        verdict[moved] = UNRELIABLE
    return Judged(agree, verdict, tol, allowed, abs_err, rel_err, numeric_err, verify_diff, claim, small,
                  out_mask & lead, why, e_abs)


def notes(J: Judged, k: int) -> list[str]:
    """The reasons behind element ``k``'s verdict, as a solve's table and JSON give them."""
    out = []
    if J.small[k]:
        out.append("the leading-order theory finds no value; within what it neglects one up to "
                   f"{J.expected_abs[k]:.3g} may exist" + ("" if J.agree[k] == 1 else ", and this one is larger"))
    if J.verdict[k] == ONE_UNDEFINED:
        out.append("one method finds no finite value where the other does")
    if J.verdict[k] == NO_CLAIM:
        out.append("the numeric solver claims no finite accuracy for this value")
    if J.verdict[k] == UNRELIABLE:
        out.append(f"unreliable: the numeric value moves by {J.verify_diff[k]:.3g} at rtol/10, "
                   f"more than its claimed accuracy {J.verify_claim[k]:.3g}")
    if J.outside[k] and J.outside_why[k]:
        out.append(J.outside_why[k])
    return out


# -- the hooks of the exercise the judge reads (the leading-order range and the approximations) ------------

def theory_validity(ex, params, expected: dict | None = None) -> dict:
    """{output: None | reason}: why each leading-order theory does not apply at ``params`` (None: it does;
    ``Exercise.theory_validity``)."""
    return dict(ex.theory_validity(params, expected))


def theory_validity_batch(ex, P, expected: dict) -> dict:
    """The batched form: {output: (mask, reasons)} (``Exercise.theory_validity_batch``)."""
    return dict(ex.theory_validity_batch(P, expected))


def approximations(ex, params) -> dict:
    """{output: [(value, what it is)]}: the approximations the exercise declares next to exact outputs."""
    return dict(ex.approximations_at(params))
