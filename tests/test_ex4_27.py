"""4.27 against independently computed values.

Reference method (independent of both solvers): the raw force balance on the line,
F(x) = -nu (x + mu)/|x + mu|^3 - mu (x - nu)/|x - nu|^3 + x  (units d, G(M1+M2) = 1),
bisected in 60-digit decimal arithmetic, so the O(1) cancellations that the
module avoids by rearranging do not matter here.

Hand checks: equal masses put L1 at the midpoint (r_L1 = d/2) and make L3 the
mirror image of L2 (r_L3 = r_L2); for mu << 1 the Hill expansion
s = h (1 -+ h/3 - h^2/9), h = (mu/3)^(1/3), and 12 e = -7 mu + O(mu^2).
"""

from decimal import Decimal, getcontext

import pytest

from conftest import solve_both

getcontext().prec = 60


def reference(M1, M2, d):
    M1, M2 = Decimal(M1), Decimal(M2)
    mu, nu = M2 / (M1 + M2), M1 / (M1 + M2)

    def F(x):
        a, b = x + mu, x - nu
        return -nu * a / abs(a) ** 3 - mu * b / abs(b) ** 3 + x

    def bisect(lo, hi):
        flo = F(lo)
        for _ in range(400):
            mid = (lo + hi) / 2
            if (F(mid) > 0) == (flo > 0):
                lo, flo = mid, F(mid)
            else:
                hi = mid
        return (lo + hi) / 2

    tiny = Decimal(10) ** -40
    x1 = bisect(-mu + tiny, nu - tiny)
    x2 = bisect(nu + tiny, nu + 2)
    x3 = bisect(-mu - 2, -mu - tiny)
    D = Decimal(d)
    return {
        "r_L1": float((nu - x1) * D),
        "r_L2": float((x2 - nu) * D),
        "r_L3": float((-mu - x3) * D),
        "dr_L3": float((-mu - x3 - 1) * D),
    }


@pytest.mark.parametrize(
    "M1, M2, d",
    [
        (5.9722e24, 7.342e22, 3.844e8),  # defaults: Earth-Moon
        (1.98847e30, 1.98847e20, 1.496e11),  # hard case 1: mass ratio 1e-10
        (5e24, 5e24, 1e9),  # hard case 2: equal masses
        (1.98847e30, 1.898e27, 7.785e11),  # Sun-Jupiter
    ],
)
def test_against_high_precision_bisection(M1, M2, d):
    ref = reference(M1, M2, d)
    a, n, _ = solve_both("4.27", M1=M1, M2=M2, d=d)
    for values in (a, n):
        for k, v in ref.items():
            assert values[k] == pytest.approx(v, rel=1e-12), k


def test_equal_masses_symmetry():
    a, n, _ = solve_both("4.27", M1=5e24, M2=5e24, d=1e9)
    for values in (a, n):
        assert values["r_L1"] == pytest.approx(5e8, rel=1e-15)
        assert values["r_L3"] == pytest.approx(values["r_L2"], rel=1e-14)
        assert values["dr_L3"] == pytest.approx(values["r_L2"] - 1e9, rel=1e-14)


def test_small_mass_ratio_explicit_formulas():
    M1, M2, d = 1.98847e30, 1.98847e20, 1.496e11
    mu = M2 / (M1 + M2)
    h = (mu / 3) ** (1 / 3)
    a, n, _ = solve_both("4.27", M1=M1, M2=M2, d=d)
    for values in (a, n):
        # leading order: the Hill radius and -7 mu d/12, good to O(h) and O(mu)
        assert values["r_L1"] == pytest.approx(h * d, rel=2 * h)
        assert values["dr_L3"] == pytest.approx(-7 * mu * d / 12, rel=1e-9)
        # next orders of the Hill expansion: error O(h^3) = 3e-11
        assert values["r_L1"] == pytest.approx(h * (1 - h / 3 - h * h / 9) * d, rel=1e-10)
        assert values["r_L2"] == pytest.approx(h * (1 + h / 3 - h * h / 9) * d, rel=1e-10)
        # r_L3 itself is d to 6e-11: the offset must not come from subtracting d
        assert values["r_L3"] == pytest.approx(d * (1 - 7 * mu / 12), rel=1e-15)


def test_heavier_second_body_refused():
    from mech.problems import registry
    from mech.problems.spec import BadInput

    with pytest.raises(BadInput):
        registry.get("4.27").resolve({"M1": 1e20, "M2": 1e21})
