"""4.10 against values worked out by hand.

Omega^2 = M g l / (I + M l^2) = g l / (r^2 + l^2) with r^2 = I/M.  l_ef = g / Omega^2 =
l + r^2/l.  Omega^2 is largest where l = r, there g / (2 r).  l_conj solves
x + r^2/x = l + r^2/l, the other root x = r^2 / l.

Defaults (M 1, I 0.02, l 0.2, g 9.81): Omega^2 = 1.962 / 0.06 = 32.7; l_ef = 0.3;
l_conj = 0.02/0.2 = 0.1; l_opt = sqrt(0.02); Omega_max^2 = 9.81 / (2 sqrt(0.02)).
Second set (M 2, I 0.5, l 1, g 1.62): r^2 = 0.25, Omega^2 = 1.62/1.25 = 1.296,
l_ef = 1.25, l_conj = 0.25, l_opt = 0.5, Omega_max^2 = 1.62.
"""

import math

import pytest

from conftest import solve_both

CASES = [
    (dict(), dict(Omega=math.sqrt(32.7), l_ef=0.3, l_conj=0.1, l_opt=math.sqrt(0.02),
                  Omega_max=math.sqrt(9.81 / (2 * math.sqrt(0.02))))),
    (dict(M=2.0, I=0.5, l=1.0, g=1.62), dict(Omega=math.sqrt(1.296), l_ef=1.25, l_conj=0.25, l_opt=0.5,
                                             Omega_max=math.sqrt(1.62))),
    # pivot 1e-4 from the center (hard case): l_conj = 0.02 / 1e-4 = 200 m
    (dict(l=1e-4), dict(l_conj=200.0, l_ef=1e-4 + 200.0)),
    # nearly a point pendulum: l_conj = 0.02 / 50 = 4e-4 m
    (dict(l=50.0), dict(l_conj=4e-4, l_ef=50.0 + 4e-4)),
]


@pytest.mark.parametrize("given, expected", CASES)
def test_against_hand_values(given, expected):
    a, n, _ = solve_both("4.10", **given)
    for name, value in expected.items():
        assert a[name] == pytest.approx(value, rel=1e-12)
        assert n[name] == pytest.approx(value, rel=1e-9)


def test_pivot_at_the_maximum_is_its_own_conjugate():
    a, n, run = solve_both("4.10", l=math.sqrt(0.02))
    assert n["l_conj"] == pytest.approx(math.sqrt(0.02), rel=1e-10)
    assert run.info["l_conj_route"].startswith("cubic")


def test_period_of_the_tiny_swing_confirms_omega():
    _, n, run = solve_both("4.10", M=3.0, I=0.1, l=0.05)
    assert run.info["Omega_from_period"] == pytest.approx(math.sqrt(9.81 * 0.05 / (0.1 / 3 + 0.05**2)), rel=1e-7)


# Issue 14 draws: a long pendulum of a small body puts l_conj = I/(M l) at 1e-6 of r = (I/M)^(1/2) or
# far less; the point-mass model's own first moment (eps r in a plain float sum) used to swamp the
# pendulum term M g x there and l_conj missed by 1e-10 relative.  l_conj = I / (M l) by hand.
@pytest.mark.parametrize("given", [
    dict(M=0.244247, I=7.26439e-05, l=15301.4, g=4.32738),  # l_conj 1.94e-8 m, r 0.017 m
    dict(M=1e6, I=2e-8, l=2e5),  # l_conj = 2e-8 / (1e6 * 2e5) = 1e-19 m
    dict(M=1e-6, I=2e4, l=2e-7),  # the mirror: l_conj = 2e4 / (1e-6 * 2e-7) = 1e17 m
])
def test_conjugate_pivot_far_from_the_optimum(given):
    _, n, _ = solve_both("4.10", **given)
    assert n["l_conj"] == pytest.approx(given["I"] / (given["M"] * given["l"]), rel=1e-12)
    assert n["l_opt"] == pytest.approx(math.sqrt(given["I"] / given["M"]), rel=1e-12)


@pytest.mark.parametrize("given", [dict(M=1e-200), dict(I=2e198), dict(l=2e-140, g=9.81e200)])
def test_only_l_over_rho_matters(given):
    """The solve runs in units M = g = rho = 1.  At M = 1e-200 (rho = 1.4e99 m) l_conj = I/(M l)
    = 1e199 m, whose inertia M l_conj^2 overflowed in SI (the root came out at 1.3e154 m)."""
    p = dict(M=1.0, I=0.02, l=0.2, g=9.81) | given
    r = math.sqrt(p["I"] / p["M"])
    _, n, _ = solve_both("4.10", **given)
    assert n["l_conj"] == pytest.approx(r * (r / p["l"]), rel=1e-12)
    assert n["l_opt"] == pytest.approx(r, rel=1e-12)
    assert n["Omega_max"] == pytest.approx(math.sqrt(p["g"] / (2 * r)), rel=1e-12)


def test_pivot_distances_beyond_float_range_are_refused():
    from mech.problems import registry
    from mech.problems.spec import BadInput

    with pytest.raises(BadInput, match="floating-point range"):
        registry.get("4.10").resolve(dict(l=2e-201))
