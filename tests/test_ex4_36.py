"""4.36 against values worked out by hand.

Hand derivation: L = m (v + v0)^2/2 - k x^2/2 (lab velocity v + v0), so
p = m (v + v0); H = p v - L = m (v^2 - v0^2)/2 + k x^2/2;
E = m (v + v0)^2/2 + k x^2/2; d/dt[m (v + v0)] = -k x gives a = -k x/m - a0.
Numbers by hand:
  defaults m=2, k=50, x=0.1, v=0.3, v0=5, a0=2: p = 2*5.3 = 10.6;
    H = (0.09 - 25) + 25*0.01 = -24.66; E = 5.3^2 + 0.25 = 28.34; a = -2.5 - 2 = -4.5.
  Earth-like frame m=1, k=10, x=0.05, v=0.5, v0=29780, a0=5.93e-3:
    p = 29780.5; 29780.5^2 = 886878180.25, 29780^2 = 886848400;
    H = (0.25 - 886848400)/2 + 0.0125 = -443424199.8625;
    E = 886878180.25/2 + 0.0125 = 443439090.1375; a = -0.5 - 0.00593 = -0.50593.
  at rest in the lab m=2, k=50, x=-0.2, v=-5, v0=5, a0=-3:
    p = 0; H = E = 25*0.04 = 1; a = 5 + 3 = 8.
"""

import pytest

from conftest import solve_both

CASES = [
    (dict(m=2.0, k=50.0, x=0.1, v=0.3, v0=5.0, a0=2.0), dict(p=10.6, H=-24.66, E=28.34, a=-4.5)),
    (
        dict(m=1.0, k=10.0, x=0.05, v=0.5, v0=2.978e4, a0=5.93e-3),
        dict(p=29780.5, H=-443424199.8625, E=443439090.1375, a=-0.50593),
    ),
    (dict(m=2.0, k=50.0, x=-0.2, v=-5.0, v0=5.0, a0=-3.0), dict(p=0.0, H=1.0, E=1.0, a=8.0)),
    # free particle in a decelerating frame: m=3, k=0, v=1, v0=-2: p=-3, H=3/2*(1-4)=-4.5, E=1.5, a=+0.7
    (dict(m=3.0, k=0.0, x=7.0, v=1.0, v0=-2.0, a0=-0.7), dict(p=-3.0, H=-4.5, E=1.5, a=0.7)),
]


@pytest.mark.parametrize("given, expected", CASES)
def test_hand_values(given, expected):
    a, n, _ = solve_both("4.36", **given)
    for values in (a, n):
        for name, want in expected.items():
            assert values[name] == pytest.approx(want, rel=1e-12, abs=1e-9 * max(1.0, abs(want)))


def test_H_differs_from_E_by_m_v0_times_lab_velocity():
    a, n, _ = solve_both("4.36", m=1.5, k=3.0, x=0.4, v=-1.2, v0=2.5, a0=0.3)
    for values in (a, n):
        assert values["E"] - values["H"] == pytest.approx(1.5 * 2.5 * (-1.2 + 2.5), rel=1e-12)


def test_at_rest_in_lab_the_momentum_is_exactly_zero():
    a, n, _ = solve_both("4.36", m=2.0, k=50.0, x=-0.2, v=-5.0, v0=5.0, a0=-3.0)
    assert n["p"] == 0.0 and n["H"] == pytest.approx(n["E"], rel=1e-15)
