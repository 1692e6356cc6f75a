"""`mech check --hard` solves an exercise's cases together through its batched route (studies/checking.py
``run_batch``): each case judged as the one-point cross-check judges it, a failure failing that case alone
with the one-point cross-check's reason, and the same report on any number of workers."""

import dataclasses
import inspect
import os

import numpy as np
import pytest

from mech.problems import registry
from mech.studies import checking
from mech.studies.variants import cross_check_variants
from mech.verification.crosscheck import cross_check

from hard_cases import alone as cross_checked_alone
from hard_cases import batch as batched_once

BATCHED = [i for i, ex in registry.all_exercises().items() if checking.batched(ex)]


def _cases(ex_id: str):
    return checking.plan([registry.get(ex_id)], hard=True)


def test_the_batched_exercises():
    """Every exercise whose one-point solve is its batched route's batch of one is batched; 5.8, whose
    one-point solve is a function of its own, and the exercises without a batched route are not."""
    assert len(BATCHED) >= 25
    assert "5.8" not in BATCHED and "5.10" in BATCHED and "4.23" in BATCHED
    assert all(registry.get(i).batched_route is not None for i in BATCHED)
    for i in ("4.1", "4.36", "4.22"):
        assert not checking.batched(registry.get(i))
    # units: a batched exercise's cases in one unit, every other case alone, plan order kept
    cases = checking.plan([registry.get(i) for i in ("4.1", "4.8", "4.36")], hard=True)
    units = checking.units(cases)
    assert sum(units, []) == list(range(len(cases)))
    assert [len(u) for u in units] == [1] * 3 + [4] + [1] * 3


@pytest.mark.parametrize("ex_id", BATCHED)
def test_a_batch_judges_each_case_as_the_one_point_check(ex_id):
    """The batch's verdicts equal the one-point cross-check's (the old path, kept as ``run_case``) field by
    field; its values lie within the two runs' combined error bars; its analytic values are the same
    function's, to round-off."""
    batch = batched_once(ex_id)[0]  # checking.run_batch(_cases(ex_id)), shared with test_check_all
    assert [(c.label, c.given) for c in batch] == [(c.label, c.given) for c in _cases(ex_id)]
    alone = cross_checked_alone(ex_id)  # run_case of each case, shared with test_check_all
    assert [a.label for a in alone] == [b.label for b in batch]
    # the batch was used: a batch's case carries the batched route's solution, not a one-point run
    assert all(c.result.run is None and c.result.numeric_info["method"] == "DOP853 (batched)" for c in batch)
    for b, a in zip(batch, alone):
        where = f"{ex_id} {a.label}"
        assert (b.label, b.agree, b.detail) == (a.label, a.agree, a.detail), where
        assert [e.message for e in b.result.errors] == [e.message for e in a.result.errors], where
        for qa in a.result.quantities:
            qb = b.result[qa.name]
            for field in ("verdict", "agree", "theory", "theory_valid", "reason", "notes", "expected_err",
                          "expected_err_abs"):
                assert getattr(qb, field) == getattr(qa, field), (where, qa.name, field)
            if isinstance(qa.analytic, float):
                assert qb.analytic == pytest.approx(qa.analytic, rel=1e-12, abs=1e-300), (where, qa.name)
            if isinstance(qa.numeric, float):
                bars = qa.numeric_err + qb.numeric_err
                assert abs(qb.numeric - qa.numeric) <= bars, (where, qa.name, qa.numeric, qb.numeric, bars)
            else:
                assert type(qb.numeric) is type(qa.numeric), (where, qa.name)


def _planted(monkeypatch, ex, plant):
    """``ex``'s batched route with ``plant(P, cols, tally)`` applied after each call: the one-point solve (the
    batch of one) and the batch both meet it."""
    route = ex.batched_route
    takes = inspect.signature(route.numeric).parameters

    def numeric(P, rtol, outputs, memo=None, tally=None):
        kw = {k: v for k, v in (("memo", memo), ("tally", tally)) if k in takes}
        cols = route.numeric(P, rtol, outputs, **kw)
        plant(P, rtol, cols, tally)
        return cols

    monkeypatch.setattr(ex, "batched_route", dataclasses.replace(route, numeric=numeric))
    assert checking.batched(ex)


def _one_fails(ex_id: str, label: str):
    """Run the exercise's cases as ``mech check --hard`` runs them: the failing case, checked to be ``label``
    and to read as the one-point cross-check of that case reads, and the others passed by the batch."""
    ex = registry.get(ex_id)
    report = checking.run_check([ex], hard=True, jobs=1)
    bad = [c for c in report.cases if not c.ok]
    assert [c.label for c in bad] == [label]
    alone = checking.run_case(next(c for c in _cases(ex_id) if c.label == label))
    assert bad[0].detail == alone.detail and not alone.ok
    others = [c for c in report.cases if c.ok]
    assert others and all(c.agree is True and c.result.run is None for c in others)
    return bad[0]


def test_a_value_off_in_one_variant_fails_that_case_alone(monkeypatch):
    ex = registry.get("4.8")

    def off(P, rtol, cols, tally):  # hard 2 (h_over_R = 0.02): V_f off by a part in a thousand
        hit = np.asarray(P["h_over_R"]) == 0.02
        cols["V_f"].value = np.where(hit, cols["V_f"].value * (1 + 1e-3), cols["V_f"].value)

    _planted(monkeypatch, ex, off)
    bad = _one_fails("4.8", "hard 2")
    assert bad.detail.startswith("disagree: V_f")


def test_a_variant_that_fails_numerically_fails_alone(monkeypatch):
    ex = registry.get("4.8")
    why = "planted: the step size underflowed"

    def fail(P, rtol, cols, tally):
        hit = np.asarray(P["b_over_R"]) == 0.99  # hard 3
        for col in cols.values():
            col.failed.append((hit, why))

    _planted(monkeypatch, ex, fail)
    bad = _one_fails("4.8", "hard 3")
    assert bad.detail == f"numeric solver failed: {why}"


def test_a_value_beyond_the_floating_point_range_fails_as_alone(monkeypatch):
    """4.8's hard 1 rolls no distance (x_roll = 0 by both methods, held to an absolute claim): a numeric
    1e-300 there agrees with 0 within that claim, but the one-point check fails a value beyond mech's
    floating-point range, and so does the batch's case."""
    ex = registry.get("4.8")

    def tiny(P, rtol, cols, tally):
        hit = np.asarray(P["h_over_R"]) == 1.4  # hard 1
        cols["x_roll"].value = np.where(hit, 1e-300, cols["x_roll"].value)

    _planted(monkeypatch, ex, tiny)
    bad = _one_fails("4.8", "hard 1")
    assert "x_roll: the numeric value 1e-300 m lies outside the floating-point range" in bad.detail


def test_a_batch_that_raises_falls_back_case_by_case(monkeypatch):
    """A route that raises for one variant fails its chunk of the batch: each case that failed there is then
    solved alone (``cross_check_variants``, else ``run_case``), and only the one that raises alone fails."""
    from mech.core.errors import NumericFailure

    ex = registry.get("4.25")

    def raises(P, rtol, cols, tally):
        if np.any(np.asarray(P["R"]) == 1e-7):  # hard 1
            raise NumericFailure("planted: no root bracketed")

    _planted(monkeypatch, ex, raises)
    report = checking.run_check([ex], hard=True, jobs=1)
    assert [(c.label, c.ok) for c in report.cases] == [("defaults", True), ("hard 1", False), ("hard 2", True)]
    assert report.cases[1].detail == "numeric solver failed: planted: no root bracketed"
    assert all(not c.result.errors for c in report.cases[::2])  # answered alone, beside the failed batch


def test_an_invariant_drifting_in_one_variant_fails_that_case_alone(monkeypatch):
    """The batched route reports each variant's invariants to a tally: the batch judges them as the
    one-point cross-check does (a batch that ignored them would pass hard 1)."""
    ex = registry.get("4.8")

    def drifts(P, rtol, cols, tally):
        hit = np.asarray(P["h_over_R"]) == 1.4  # hard 1
        tally.invariant("planted momentum", np.where(hit, 3e-4, 0.0))

    _planted(monkeypatch, ex, drifts)
    bad = _one_fails("4.8", "hard 1")
    assert "the invariant 'planted momentum' drifts by 0.0003" in bad.detail
    # the same failure from the batch itself (what mech grade and mech assign read), for that variant only
    params = [ex.resolve(c.given) for c in _cases("4.8")]
    got = cross_check_variants(ex, params)
    one = cross_check(ex, params[1], fork_rerun=False)
    assert [[(e.kind, e.message) for e in s.errors] for s in got] == \
           [[], [(e.kind, e.message) for e in one.errors], [], []]
    assert [e.kind for e in one.errors] == ["invariant"]


def test_a_refused_case_stays_refused_beside_a_batch():
    ex = registry.get("4.31")
    cases = _cases("4.31") + [checking.Case(ex, "hard 9", {"h": -1.0})]
    done = checking.run_batch(cases)
    assert [c.ok for c in done] == [True, True, True, False]
    assert done[-1].detail.startswith("bad parameters: ") and "h" in done[-1].detail
    assert all(c.result.run is None for c in done[:3])


@pytest.mark.skipif(not hasattr(os, "fork") or not os.path.isdir("/proc"), reason="the pool forks (Linux)")
def test_one_or_two_workers_give_the_same_report():
    """A batch is one unit of work for a worker: the report (every field but the seconds) is the same on one
    process and on two."""
    ids = ["4.1", "4.2", "4.8", "4.10", "4.25", "4.31", "5.2", "5.3"]
    exercises = [registry.get(i) for i in ids]

    def shown(report):
        d = report.as_json()
        d.pop("seconds")
        for c in d["cases"]:
            c.pop("seconds")
        return d

    serial = checking.run_check(exercises, hard=True, jobs=1)
    pooled = checking.run_check(exercises, hard=True, jobs=2)
    assert len(checking.units(serial.cases)) >= checking.MIN_POOLED_CASES
    assert shown(pooled) == shown(serial)
    assert serial.ok and serial.passed == len(serial.cases) == len(checking.plan(exercises, True))
