"""4.16 against values worked out by hand.

Hand derivation (mirror symmetry through the pushed rod, speeds V of the pushed
and V' of the opposite rod along F): the hinge between two oblique rods moves
at ((V + V')/2, -sqrt(3)(V' - V)/2), so an oblique rod's center moves at
((3V + V')/4, -sqrt(3)(V' - V)/4) or ((V + 3V')/4, same), and it turns at
(V - V')/l.  Summing m v^2/2 + (m l^2/12) w^2/2 over the six rods:
T = (m/2)[(10/3)V^2 + (10/3)V'^2 - (2/3)V V'].  Lagrange with forces (F, 0):
(10/3)a - (1/3)a' = F/m, -(1/3)a + (10/3)a' = 0, so a = 10a', a' = F/(33m),
and alpha = (a - a')/l = 9F/(33 m l).
"""

import pytest

from conftest import solve_both


@pytest.mark.parametrize(
    "m, l, F, a, a_prime, alpha",
    [
        # defaults: F/m = 10
        (0.1, 0.2, 1.0, 100.0 / 33.0, 10.0 / 33.0, 90.0 / 33.0 / 0.2),
        # m = 2, l = 0.5, F = 66: F/m = 33 -> a = 10, a' = 1, alpha = 9/0.5 = 18
        (2.0, 0.5, 66.0, 10.0, 1.0, 18.0),
        # the two badly scaled hard cases
        (0.1, 1e-4, 1.0, 100.0 / 33.0, 10.0 / 33.0, 90.0 / 33.0 / 1e-4),
        (1e-6, 0.2, 1.0, 1e7 / 33.0, 1e6 / 33.0, 9e6 / 33.0 / 0.2),
    ],
)
def test_against_hand_values(m, l, F, a, a_prime, alpha):
    an, nu, run = solve_both("4.16", m=m, l=l, F=F)
    for values in (an, nu):
        assert values["a"] == pytest.approx(a, rel=1e-12)
        assert values["a_prime"] == pytest.approx(a_prime, rel=1e-12)
        assert values["alpha_adj"] == pytest.approx(alpha, rel=1e-12)


def test_momentum_balance_and_ratio():
    # total momentum: m(a + a') + 4 m (mean x-acceleration of an oblique rod = (a + a')/2) = F
    an, nu, run = solve_both("4.16", m=0.3, l=1.7, F=2.5)
    for v in (an, nu):
        assert 3.0 * 0.3 * (v["a"] + v["a_prime"]) == pytest.approx(2.5, rel=1e-12)
        assert v["a"] / v["a_prime"] == pytest.approx(10.0, rel=1e-12)
    assert run.info["com_acc_rel_err"] < 1e-13
