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
