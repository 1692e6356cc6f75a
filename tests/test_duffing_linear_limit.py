"""5.8 at alpha = 0 (inside its bounds): a linear resonance.  The leading-order theory puts the peak at
omega0 (xi_peak = 0); the exact peak of |a|^2 = (f0)^2 / ((omega0^2 - omega^2)^2 + 4 delta^2 omega^2) lies at
omega^2 = omega0^2 - 2 delta^2, worked by hand: the allowance is absolute there, honest (no more than three
times the true distance) and the cross-check agrees."""

import math

import pytest

from mech.problems import registry
from mech.verification.crosscheck import cross_check


@pytest.mark.parametrize("omega0, delta", [(10.0, 0.02), (3.0, 0.05)])
def test_linear_peak_is_within_an_honest_absolute_allowance(omega0, delta):
    ex = registry.get("5.8")
    sol = cross_check(ex, ex.resolve({"alpha": 0.0, "omega0": omega0, "delta": delta}))
    q = sol["xi_peak"]
    exact = math.sqrt(omega0 * omega0 - 2.0 * delta * delta) - omega0
    assert q.analytic == 0.0
    assert abs(q.numeric - exact) <= q.numeric_err + 1e-12 * abs(exact)
    assert q.expected_err_abs is not None
    assert abs(exact) <= q.expected_err_abs <= 3.0 * abs(exact)
    assert q.agree is True
