"""The cross-check itself: perturbations a few times the tolerance must fail it, through every branch.

The numeric solver is replaced by a stand-in that returns the analytic values moved by a chosen multiple
of the tolerance, so what is tested is the comparison, not an exercise.  The tolerances are the ones the
rules in DEVELOPING.md give, worked out here by hand: a loosened tolerance fails these tests.
"""

from __future__ import annotations

import math

import pytest

from mech.problems import registry
from mech.problems.spec import Undefined
from mech.verification import crosscheck


def _stand_in(ex, factor_of, invariant=None):
    """A numeric solver returning analytic * (1 + factor_of(name)), recording an invariant if asked."""

    def numeric(p, run):
        exact = ex.solve_analytic(p)
        if invariant:
            run.invariant(*invariant)
        return {k: (v if isinstance(v, Undefined) else v * (1.0 + factor_of(k))) for k, v in exact.items()}

    return numeric


def _check(ex, **kw):
    return crosscheck.cross_check(ex, ex.resolve({}), **kw)


def test_the_tolerance_of_an_exact_output_is_the_declared_claim():
    """4.15 declares tol_factor 100 (the default) and default_rtol 1e-10: tol = 1e-8, relative."""
    ex = registry.get("4.15")
    res = _check(ex)
    assert [q.tol for q in res.quantities] == [pytest.approx(1e-8, rel=1e-12)] * 2
    for q in res.quantities:
        # the earned error bar is the verified claim, absolute: 1e-8 * |value|
        assert q.numeric_err == pytest.approx(1e-8 * abs(q.numeric), rel=1e-12)
        assert q.as_json()["numeric_err"] == pytest.approx(1e-8 * abs(q.numeric), rel=1e-12)


@pytest.mark.parametrize("k, agree", [(0.5, True), (2.0, False), (5.0, False)])
def test_an_exact_output_off_by_k_tolerances(monkeypatch, k, agree):
    ex = registry.get("4.15")
    monkeypatch.setattr(ex, "_numeric", _stand_in(ex, lambda name: k * 1e-8 if name == "theta_c" else 0.0))
    res = _check(ex, verify=False)
    theta = res.quantities[0]
    assert theta.agree is agree and res.agree is agree
    assert theta.rel_err == pytest.approx(k * 1e-8, rel=1e-6)


@pytest.mark.parametrize("k, agree", [(0.5, True), (3.0, False)])
def test_the_rerun_must_earn_the_claim(monkeypatch, k, agree):
    """The rerun at rtol/10 moving by k claims: k > 1 means the claim was not earned."""
    ex = registry.get("4.15")
    base = _stand_in(ex, lambda name: 0.0)

    def numeric(p, run):
        values = base(p, run)
        if run.rtol < ex.default_rtol:  # the rerun
            values["omega_c"] *= 1.0 + k * 1e-8
        return values

    monkeypatch.setattr(ex, "_numeric", numeric)
    monkeypatch.setattr(crosscheck, "_parallel_ok", lambda: False)
    res = _check(ex)
    omega = res.quantities[1]
    assert omega.agree is agree
    assert ("unreliable" in "; ".join(omega.notes)) is (not agree)


@pytest.mark.parametrize("k, agree", [(0.5, True), (2.0, False), (4.0, False)])
def test_a_leading_order_output_off_by_k_times_what_it_neglects(monkeypatch, k, agree):
    """5.9's outputs are leading-order: tol = max(claim, expected_err); here expected_err = 1e-3."""
    ex = registry.get("5.9")
    monkeypatch.setattr(ex, "_expected_error", lambda p: {o.name: 1e-3 for o in ex.outputs})
    monkeypatch.setattr(ex, "_numeric", _stand_in(ex, lambda name: k * 1e-3 if name == "A" else 0.0))
    res = _check(ex, verify=False)
    a = next(q for q in res.quantities if q.name == "A")
    assert a.tol == pytest.approx(1e-3)
    assert a.agree is agree


@pytest.mark.parametrize("k, agree", [(0.3, True), (3.0, False)])
def test_an_invariant_drifting_k_times_its_allowance(monkeypatch, k, agree):
    """An invariant allowed the default claim (1e-8 for 4.15) drifting k times that fails the check."""
    ex = registry.get("4.15")
    monkeypatch.setattr(ex, "_numeric", _stand_in(ex, lambda name: 0.0, invariant=("energy", k * 1e-8)))
    res = _check(ex, verify=False)
    assert res.agree is agree
    assert any(e.kind == "invariant" and "energy" in str(e) for e in res.errors) is (not agree)


def test_an_invariant_with_its_own_allowance(monkeypatch):
    ex = registry.get("4.15")
    monkeypatch.setattr(ex, "_numeric", _stand_in(ex, lambda name: 0.0, invariant=("energy", 2e-6, 1e-6)))
    assert _check(ex, verify=False).agree is False
    monkeypatch.setattr(ex, "_numeric", _stand_in(ex, lambda name: 0.0, invariant=("energy", 5e-7, 1e-6)))
    assert _check(ex, verify=False).agree is True


@pytest.mark.parametrize("k, agree", [(0.5, True), (3.0, False)])
def test_the_analytic_error_widens_agreement_by_itself_only(monkeypatch, k, agree):
    """With an analytic round-off of 1e-6 (absolute) and a claim of 1e-8 relative, a difference of
    k * 1e-6 agrees only for k below about 1."""
    ex = registry.get("4.15")
    theta = ex.solve_analytic(ex.resolve({}))["theta_c"]
    monkeypatch.setattr(ex, "_analytic_error", lambda p: {"theta_c": 1e-6})
    monkeypatch.setattr(ex, "_numeric", _stand_in(ex, lambda name: k * 1e-6 / theta if name == "theta_c" else 0.0))
    res = _check(ex, verify=False)
    q = res.quantities[0]
    assert q.analytic_err == pytest.approx(1e-6)
    assert q.as_json()["analytic_err"] == pytest.approx(1e-6)
    assert q.agree is agree


def test_a_non_finite_numeric_value_fails(monkeypatch):
    ex = registry.get("4.15")
    monkeypatch.setattr(ex, "_numeric", _stand_in(ex, lambda name: math.inf if name == "theta_c" else 0.0))
    res = _check(ex, verify=False)
    assert res.agree is False
    d = res.as_json()
    assert d["quantities"][0]["numeric"] is None


def test_a_solve_past_its_budget_fails_loudly(monkeypatch):
    import time

    ex = registry.get("4.15")

    def endless(p, run):
        from mech.core import budget

        while True:
            time.sleep(0.01)
            budget.check("a test loop")

    monkeypatch.setattr(ex, "_numeric", endless)
    t0 = time.monotonic()
    res = _check(ex, verify=False, budget_s=0.3)
    assert time.monotonic() - t0 < 2.0
    assert res.agree is False and res.errors[0].kind == "numeric" and "time budget" in str(res.errors[0])


def test_a_solve_that_never_checks_its_budget_is_stopped_by_the_timer(monkeypatch):
    import time

    ex = registry.get("4.15")
    monkeypatch.setattr(ex, "_numeric", lambda p, run: time.sleep(30))
    t0 = time.monotonic()
    res = _check(ex, verify=False, budget_s=0.2)
    assert time.monotonic() - t0 < 3.0
    assert res.agree is False and res.errors[0].kind == "numeric" and "time budget" in str(res.errors[0])


@pytest.mark.parametrize("k, agree", [(0.5, True), (3.0, False)])
def test_a_leading_order_output_that_can_be_zero_has_an_absolute_allowance(monkeypatch, k, agree):
    """expected_error may give (relative, absolute): a value of 0 then agrees within the absolute part."""
    ex = registry.get("5.9")
    monkeypatch.setattr(ex, "_expected_error", lambda p: {o.name: (1e-3, 2e-4) for o in ex.outputs})

    def numeric(p, run):
        values = ex.solve_analytic(p)
        values["lambda_lc"] = values["lambda_lc"] + 0.999e-3 * abs(values["lambda_lc"]) + k * 2e-4
        return values

    monkeypatch.setattr(ex, "_numeric", numeric)
    res = _check(ex, verify=False)
    q = next(q for q in res.quantities if q.name == "lambda_lc")
    assert q.as_json()["expected_err_abs"] == pytest.approx(2e-4)
    assert q.agree is agree
