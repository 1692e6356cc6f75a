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
  apply (``validity.theory_validity``): nothing is compared, the numeric value,
  verified by its rerun, is the answer (an unreliable one still fails);
* **analytic only** / **numeric only** (no verdict) where one method did not
  run, and no verdict where the numeric solve failed (the failure is loud).

``agree`` is an int8 array: 1 agree, 0 disagree, -1 no verdict.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np

from mech.problems import validity

__all__ = ["Verdict", "holds", "conclude", "conclude_arrays", "outside_text", "Judged", "judge", "within", "allowance", "ROUND_OFF", "numeric_err", "analytic_err", "notes",
           "theory_validity", "theory_validity_batch", "approximations",
           "AGREE", "DISAGREE", "UNRELIABLE", "NO_CLAIM", "ONE_UNDEFINED", "OUTSIDE", "ANALYTIC_ONLY",
           "NUMERIC_ONLY", "FAILED", "VERDICTS"]

class Verdict(enum.IntEnum):
    """What was found for one value, with its words; an ``int8`` code in ``Judged.verdict``'s arrays and the
    typed ``Quantity.verdict`` every renderer reads (its reason, for ``OUTSIDE``: ``Quantity.reason``)."""

    AGREE = 0
    DISAGREE = 1
    UNRELIABLE = 2
    NO_CLAIM = 3
    ONE_UNDEFINED = 4
    OUTSIDE = 5  # a leading-order theory outside its range: nothing compared
    ANALYTIC_ONLY = 6
    NUMERIC_ONLY = 7
    FAILED = 8  # the numeric solve failed (the failure is loud)

    @property
    def word(self) -> str:
        """What the verdict says, in words (``mech solve``'s notes, JSON reasons)."""
        return VERDICTS[self]

    @property
    def agree(self) -> bool | None:
        """True agree, False a failure, None no verdict (nothing compared)."""
        return True if self is Verdict.AGREE else None if self in _NO_VERDICT else False

    @property
    def cell(self) -> str:
        """The verdict in a table's agree column: ``yes``, ``NO``, ``outside range`` or ``—``."""
        return "outside range" if self is Verdict.OUTSIDE else {True: "yes", False: "NO", None: "—"}[self.agree]


_NO_VERDICT = frozenset({Verdict.OUTSIDE, Verdict.ANALYTIC_ONLY, Verdict.NUMERIC_ONLY, Verdict.FAILED})

# the codes as module names (``J.verdict == judge.UNRELIABLE`` on arrays)
AGREE, DISAGREE, UNRELIABLE, NO_CLAIM, ONE_UNDEFINED, OUTSIDE, ANALYTIC_ONLY, NUMERIC_ONLY, FAILED = Verdict
VERDICTS = {AGREE: "agree", DISAGREE: "disagree", UNRELIABLE: "unreliable", NO_CLAIM: "no finite claim",
            ONE_UNDEFINED: "one method finds no value", OUTSIDE: "theory outside its range",
            ANALYTIC_ONLY: "analytic only", NUMERIC_ONLY: "numeric only", FAILED: "numeric solve failed"}
OUTSIDE_WORDS = "leading-order theory outside its range"


def outside_text(reason: str) -> str:
    """The note of an ``OUTSIDE`` verdict: its words and its reason (``validity.theory_validity``'s)."""
    return f"{OUTSIDE_WORDS}: {reason}" if reason else OUTSIDE_WORDS


# -- the one overall rule: what a solve, a sweep point, a check case concludes from its verdicts ------------

def holds(verdict: Verdict | None, agree: bool | None = None, verified: bool = False) -> bool | None:
    """What one value concludes: True it holds (agrees; or, outside its leading-order theory's range, its
    numeric value is verified by the rerun, so it is the answer), False it fails, None no verdict (nothing
    compared or verified).  ``verdict`` None (a value judged elsewhere): ``agree`` as it is."""
    if verdict is None:
        return agree
    if verdict is Verdict.OUTSIDE and verified:
        return True
    return Verdict(verdict).agree


def conclude(flags, failed: bool = False) -> bool | None:
    """Several values' conclusions (``holds``) as one: False when anything failed (``failed``: a failure
    beside the values, a solver's or a rerun's), None when nothing holds or fails (no verdict), else True.
    "No verdict" is no failure: ``mech solve``, ``sweep`` and ``check`` exit 0 on it (``core.exits``)."""
    if failed:
        return False
    flags = list(flags)
    if any(f is False for f in flags):
        return False
    return None if all(f is None for f in flags) else True


def conclude_arrays(agree, outside_verified, failed) -> np.ndarray:
    """``holds`` on a batched sweep's arrays, per output: int8 1 holds, 0 fails, -1 no verdict (``agree``:
    the judge's int8; ``outside_verified``: outside the theory's range and verified; ``failed``: a solve
    failed there)."""
    out = np.where(outside_verified & (agree < 0), 1, agree).astype(np.int8)
    out[np.asarray(failed, bool)] = 0
    return out


# floating-point slack of a value computed through a formula of a few dozen operations (relative)
ROUND_OFF = 1e-12


def _some(x) -> bool:
    """A term that is there: not the scalar 0 (0 times an infinite scale would make NaN of nothing)."""
    return not (np.ndim(x) == 0 and x == 0)


def allowance(scale=0.0, *, rel=0.0, bars=(), round_off=0.0, own=0.0):
    """What a value is held to, absolute: ``rel |scale| + each error bar + round_off |scale| + own``.

    ``scale``: the size the relative parts apply to (the reference, or the larger of two values);
    ``rel``: the relative tolerance (a claim, the digits an answer earns, a test's rtol); ``bars``: the
    absolute error bars of both sides (and any absolute allowance), summed in the order given;
    ``round_off``: the relative round-off of the comparison; ``own``: a value's own absolute round-off
    (a formula's, carried through its evaluation).  Numbers or arrays.
    """
    s = np.abs(scale)
    out = rel * s if _some(rel) else 0.0
    for bar in bars:
        out = out + bar
    if _some(round_off):
        out = out + round_off * s
    if _some(own):
        out = out + own
    return out


def within(diff, *, scale=0.0, rel=0.0, bars=(), round_off=0.0, own=0.0):
    """The rule of every comparison mech makes between two values: ``diff`` (their distance, >= 0) is within
    what the value is held to (``allowance``, same arguments).  Arrays or numbers; NaN is never within."""
    return diff <= allowance(scale, rel=rel, bars=bars, round_off=round_off, own=own)


def numeric_err(q) -> float:
    """A cross-checked output's numeric error bar, absolute: the cross-check's ``numeric_err`` where it gives
    one, else the numeric claim (``tol`` relative plus ``tol_abs``)."""
    err = getattr(q, "numeric_err", None)
    if err is not None and math.isfinite(err):
        return float(err)
    return float(allowance(q.numeric, rel=float(q.tol or 0.0), bars=(float(q.tol_abs or 0.0),)))


def analytic_err(q) -> float:
    """A cross-checked output's analytic error bar (its round-off, absolute; 0 where none is declared)."""
    err = getattr(q, "analytic_err", None)
    return float(err) if err is not None and math.isfinite(err) else 0.0


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
    allowed = np.where(both, allowance(a, rel=tol, bars=(allowed_abs, a_err)), np.nan)
    numeric_err = np.where(n_num, allowance(n, rel=rel, bars=(tol_abs,)), np.nan)

    agree = np.full(N, -1, np.int8)
    verdict = np.full(N, FAILED, np.int8)
    verdict[~has_a & has_n] = NUMERIC_ONLY
    verdict[has_a & ~has_n] = ANALYTIC_ONLY
    verdict[~has_a & ~has_n] = FAILED
    ok = within(abs_err, bars=(allowed,))
    agree[both] = ok[both]
    verdict[both] = np.where(ok, AGREE, DISAGREE)[both]
    # one method finds no finite value where the other does (or both find none: they agree)
    one = has_a & has_n & (a_und | n_und) & ~n_fail
    agree[one] = (a_und & n_und)[one]
    verdict[one] = np.where(a_und & n_und, AGREE, ONE_UNDEFINED)[one]
    # the leading-order theory finds no value, but what it neglects allows one this large
    small = lead & ~out_mask & a_und & n_num & (np.nan_to_num(e_abs, nan=0.0) > 0)
    ok_small = within(np.abs(n), bars=(e_abs, numeric_err))
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
        # the claim is the numeric value's own error bar (``numeric_err``), the one printed beside it: scaled
        # by that value, not by the analytic one (a leading-order value outside its range can be thousands
        # of times larger, which left the check without bite: 5.9's omega at mu/omega0 = 3e4)
        claim = np.where(chk, numeric_err, np.nan)
        moved = chk & ~within(verify_diff, bars=(claim,))
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
    if J.outside[k]:
        out.append(outside_text(J.outside_why[k]))
    return out


# -- the hooks of the exercise the judge reads (the leading-order range and the approximations) ------------

def theory_validity(ex, params, expected: dict | None = None) -> dict:
    """{output: None | reason}: why each leading-order theory does not apply at ``params`` (None: it does;
    ``validity.theory_validity``)."""
    return dict(validity.theory_validity(ex, params, expected))


def theory_validity_batch(ex, P, expected: dict) -> dict:
    """The batched form: {output: (mask, reasons)} (``validity.outside_ranges``)."""
    return dict(validity.outside_ranges(ex, P, expected))


def approximations(ex, params) -> dict:
    """{output: [(value, what it is)]}: the approximations the exercise declares next to exact outputs."""
    return dict(validity.approximations_at(ex, params))
