"""The typed result: a frozen Solution that is a read-only Mapping, typed failures, declared expected
fields, and the sweep's verdict arrays as booleans with a mask.

Hand values: 4.15 at theta0 = 60 deg, l = 1 m: theta_c = asin(1/sqrt 3) = 0.6154797 rad,
omega_c = sqrt(g sin(theta0)/l) = sqrt(9.81 * 0.8660254) = 2.914740 rad/s.
"""

import dataclasses
import math
from collections.abc import Mapping

import numpy as np
import pytest

import mech
from mech.verification.result import Failure, Quantity, Solution


@pytest.fixture(scope="module")
def sol():
    return mech.solve("4.15", theta0="60deg")


def test_a_solution_is_a_read_only_mapping_of_names(sol):
    assert isinstance(sol, Mapping) and isinstance(sol, Solution)
    assert list(sol) == ["theta_c", "omega_c"] and len(sol) == 2 and "theta_c" in sol
    assert [q.name for q in sol.values()] == ["theta_c", "omega_c"]
    assert dict(sol.items())["omega_c"].numeric == pytest.approx(math.sqrt(9.81 * math.sqrt(3) / 2), rel=1e-8)
    assert sol["theta_c"].analytic == pytest.approx(math.asin(1 / math.sqrt(3)), rel=1e-12)
    with pytest.raises(dataclasses.FrozenInstanceError):
        sol.quantities = ()
    with pytest.raises(dataclasses.FrozenInstanceError):
        sol["theta_c"].agree = False
    with pytest.raises(TypeError):
        sol["theta_c"] = None
    with pytest.raises(KeyError, match="its outputs are: theta_c, omega_c"):
        sol["theta"]


def test_the_repl_shows_the_compact_table(sol):
    text = repr(sol)
    lines = text.splitlines()
    assert lines[0].startswith("4.15  ") and "θ₀ = 60 deg" in lines[1]
    assert lines[2].split() == ["quantity", "unit", "analytic", "numeric", "±", "numeric", "agree"]
    assert lines[3].split()[0] == "theta_c" and lines[3].split()[-1] == "yes"
    assert lines[-1] == "analytic and numeric agree"
    assert "<table>" in sol._repr_html_() and "theta_c" in sol._repr_html_()


def test_failures_are_typed():
    with pytest.raises(ValueError):
        Failure("solver", "x")
    f = Failure("rerun", "numeric solver failed at rtol=1e-11: no event", None)
    assert f.solver_failed and str(f) == f.message
    assert not Failure("invariant", "the invariant 'energy' drifts").solver_failed
    q = Quantity("x", "m", analytic=1.0, numeric=1.0, agree=True)
    ok = Solution(None, {}, (q,))
    assert ok.agree is True and not ok.solver_failed
    bad = ok.replace(errors=(f,))
    assert bad.agree is False and bad.solver_failed and ok.agree is True  # replace leaves the original


def test_expected_is_a_declared_field():
    sol = mech.solve("4.15", theta0="60deg", expect={"theta_c": "35.26deg"})
    assert "expected" in {f.name for f in dataclasses.fields(Quantity)}
    assert sol["theta_c"].expected.match is True and sol["omega_c"].expected is None
    assert sol.expect_ok is True and sol.to_dict()["expect_ok"] is True


def test_sweep_verdicts_are_booleans_with_a_mask():
    # 4.15 at 30, 45, 60 deg: both methods run and agree at every point (theta_c = asin(2/3 sin theta0))
    sw = mech.sweep("4.15", theta0=("30deg", "60deg", 3))
    a = sw.to_arrays()
    assert a["theta_c_agree"].dtype == np.bool_ and a["theta_c_agree_mask"].dtype == np.bool_
    assert a["theta_c_agree"].all() and not a["theta_c_agree_mask"].any()
    assert a["theta0"][a["theta_c_agree"]].size == 3  # usable as an index
    # a point with no verdict: the mask is set and the verdict reads False
    p = sw.points[0]
    q = dataclasses.replace(p["theta_c"], agree=None)
    sw.points[0] = p.replace(quantities=(q, p["omega_c"]))
    a = sw.to_arrays()
    assert a["theta_c_agree_mask"].tolist() == [True, False, False]
    assert a["theta_c_agree"].tolist() == [False, True, True]
    pd = pytest.importorskip("pandas")
    df = sw.to_pandas()
    assert str(df["theta_c_agree"].dtype) == "boolean" and df["theta_c_agree"].isna().tolist() == [True, False, False]
    assert "theta_c_agree_mask" not in df
