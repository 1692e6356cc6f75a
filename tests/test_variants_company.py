"""Whether a variant of a class or an assignment is answered must not depend on the variants solved beside
it: the ensemble shares its steps, so a variant that fails in company is solved again alone, as
``mech solve`` solves it (studies/variants.py)."""

from __future__ import annotations

import pytest

from mech.problems import registry
from mech.studies import sweep, variants
from mech.verification.result import Failure


def _plant_failure_in_company(monkeypatch, victim: int) -> list[int]:
    """Make the batched route report a numeric failure for variant ``victim`` whenever it is solved beside
    others (never alone); returns the sizes of the batches solved, in order."""
    real = sweep.iter_batched_solutions
    sizes: list[int] = []

    def planted(result, indices=None):
        n = next(iter(result.batched.grid.values())).size
        sizes.append(n)
        for k, sol in enumerate(real(result, indices)):
            if n > 1 and k == victim:
                sol = sol.replace(errors=(Failure("numeric", "numeric solver failed: planted in company"),))
            yield sol

    monkeypatch.setattr(sweep, "iter_batched_solutions", planted)
    return sizes


@pytest.mark.parametrize("ex_id, given", [
    ("4.9", [{}, {"M": 2.0}, {"M": 0.5}]),
    ("5.13", [{}, {"Omega": 900.0}, {"Omega": 700.0}]),
])
def test_a_variant_failed_in_company_is_answered_as_alone(monkeypatch, ex_id, given):
    ex = registry.get(ex_id)
    params = [ex.resolve(g) for g in given]
    alone = variants.cross_check_variants(ex, [params[1]])[0]  # the batch of one: nothing planted
    assert alone.agree is True
    sizes = _plant_failure_in_company(monkeypatch, victim=1)
    got = variants.cross_check_variants(ex, params)
    assert sizes == [3, 1]  # the batch, then the failed variant alone
    assert got[1].agree is True and not got[1].errors
    for q in alone.quantities:  # the same solve as alone, to the bit
        assert got[1][q.name].numeric == q.numeric
        assert got[1][q.name].numeric_err == q.numeric_err
    assert got[0].agree is True and got[2].agree is True


def test_a_variant_failing_alone_too_keeps_its_failure(monkeypatch):
    """A failure that is the variant's own (it fails alone as well) stays its verdict."""
    ex = registry.get("4.9")
    params = [ex.resolve({}), ex.resolve({"M": 2.0})]
    real = sweep.iter_batched_solutions

    def always(result, indices=None):
        for k, sol in enumerate(real(result, indices)):
            if result.batched.grid["M"][k] == 2.0:
                sol = sol.replace(errors=(Failure("numeric", "numeric solver failed: planted"),))
            yield sol

    monkeypatch.setattr(sweep, "iter_batched_solutions", always)
    got = variants.cross_check_variants(ex, params)
    assert got[0].agree is True
    assert got[1].agree is False and "planted" in str(got[1].errors[0])


def test_a_value_beyond_the_floating_point_range_reads_as_mech_solve_reads_it(monkeypatch):
    """A class's or an assignment's variant whose batched value lies beyond 1e+-290 (here a planted 1e-300
    for 4.8's x_roll at its hard case 1, where both methods roll no distance and 1e-300 agrees with 0 within
    the absolute claim) gets the one-point cross-check's verdict: that value fails, as ``mech solve`` fails
    it; its companions keep the batch's."""
    import dataclasses
    import inspect

    import numpy as np

    from mech.verification.crosscheck import cross_check

    ex = registry.get("4.8")
    route = ex.batched_route
    takes = inspect.signature(route.numeric).parameters

    def numeric(P, rtol, outputs, memo=None, tally=None):
        kw = {k: v for k, v in (("memo", memo), ("tally", tally)) if k in takes}
        cols = route.numeric(P, rtol, outputs, **kw)
        hit = np.asarray(P["h_over_R"]) == 1.4
        cols["x_roll"].value = np.where(hit, 1e-300, cols["x_roll"].value)
        return cols

    monkeypatch.setattr(ex, "batched_route", dataclasses.replace(route, numeric=numeric))
    params = [ex.resolve({}), ex.resolve({"h_over_R": 1.4, "b_over_R": 0.0})]
    got = variants.cross_check_variants(ex, params)
    alone = cross_check(ex, params[1])
    assert alone.agree is False
    assert [str(e) for e in got[1].errors] == [str(e) for e in alone.errors]
    assert any("outside the floating-point range" in str(e) for e in got[1].errors)
    assert got[0].agree is True
