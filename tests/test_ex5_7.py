"""5.7 against values obtained independently of the module.

Hand derivation: energy, q'^2 = (A^2 - q^2)(omega0^2 + (alpha/2)(A^2 + q^2)), is solved by
q = A cn(Omega t | m), Omega^2 = omega0^2 + alpha A^2, m = alpha A^2/(2 Omega^2), so
omega = pi Omega/(2 K(m)); for m < 0, cn(u|m) = cd(u sqrt(1-m) | m1), m1 = -m/(1-m),
and K(m) = K(m1)/sqrt(1-m).  The reference below evaluates K with scipy's ellipk
(not the module's AGM) and c3 by an FFT of samples of A cn (or A cd = A cn/dn) from
scipy's ellipj (not the module's nome series).
Limits checked by hand:
  * Lindstedt: omega = omega0 (1 + 3 eps/8 - 21 eps^2/256 + O(eps^3)), eps = alpha A^2/omega0^2,
    c3 = alpha A^3/(32 omega0^2) (1 + O(eps));
  * pure quartic (eps -> infinity): m -> 1/2, omega -> pi sqrt(alpha) A/(2 K(1/2)),
    K(1/2) = Gamma(1/4)^2/(4 sqrt(pi));
  * at the barrier (g = 1 + eps -> 0): K(m1) ~ (1/2) ln(8/g), T ~ (2 sqrt 2/omega0) ln(8/g).
"""

import math

import numpy as np
import pytest

from conftest import solve_both
from mech.problems.spec import BadInput
from mech.problems import registry


def reference(w0, alpha, A, n=1024):
    from scipy.special import ellipj, ellipk

    Om2 = w0 * w0 + alpha * A * A
    m = alpha * A * A / (2.0 * Om2)
    if m >= 0:
        K = float(ellipk(m))
        omega = math.pi * math.sqrt(Om2) / (2.0 * K)
        u = 4.0 * K * np.arange(n) / n
        sn, cn, dn, _ = ellipj(u, m)
        q = A * cn
    else:
        m1 = -m / (1.0 - m)
        K1 = float(ellipk(m1))
        omega = math.pi * math.sqrt(Om2 * (1.0 - m)) / (2.0 * K1)
        u = 4.0 * K1 * np.arange(n) / n
        sn, cn, dn, _ = ellipj(u, m1)
        q = A * cn / dn
    c3 = 2.0 / n * float(np.sum(q * np.cos(3.0 * 2.0 * math.pi * np.arange(n) / n)))
    return omega, c3


CASES = [
    (2.0, 0.8, 0.5),  # defaults
    (2.0, 0.8, 20.0),  # hard: alpha A^2 = 80 omega0^2
    (2.0, -1.0, 1.5),  # softening, eps = -0.5625
    (3.0, -2.0, 0.4),  # softening, eps = -0.0356
    (0.5, 7.0, 0.3),  # hardening, eps = 2.52
]


@pytest.mark.parametrize("w0, alpha, A", CASES)
def test_against_elliptic_reference(w0, alpha, A):
    omega, c3 = reference(w0, alpha, A)
    a, n, _ = solve_both("5.7", omega0=w0, alpha=alpha, A=A)
    for v in (a, n):
        assert v["omega"] == pytest.approx(omega, rel=1e-9)
        assert v["domega"] == pytest.approx(omega - w0, rel=1e-8)
        assert v["c3"] == pytest.approx(c3, rel=1e-8, abs=1e-13 * A)


def test_tiny_amplitude_lindstedt_second_order():
    # hard case: eps = 1e-6; second-order Lindstedt is exact to O(eps^3) = 1e-18 relative
    A = 0.00223606797749979
    eps = 0.8 * A * A / 4.0
    a, n, _ = solve_both("5.7", A=A)
    dw = 2.0 * (3 * eps / 8 - 21 * eps * eps / 256)
    for v in (a, n):
        assert v["domega"] == pytest.approx(dw, rel=1e-9)
        assert v["c3"] == pytest.approx(0.8 * A**3 / (32 * 4.0), rel=3e-6)  # O(eps) correction


@pytest.mark.parametrize("eps", [1e-2, 3e-3, 1e-3])
def test_leading_order_error_scales_like_eps(eps):
    # the Lindstedt shift's relative error is -(21/256 eps)/(3/8) = -(7/32) eps to first order
    w0, A = 2.0, 1.0
    a, n, _ = solve_both("5.7", omega0=w0, alpha=eps * w0 * w0, A=A)
    lead = 3 * eps * w0 / 8
    for v in (a, n):
        assert (v["domega"] - lead) / lead == pytest.approx(-7 * eps / 32, rel=0.05)


def test_quartic_limit():
    K_half = math.gamma(0.25) ** 2 / (4 * math.sqrt(math.pi))
    w0, alpha, A = 1e-6, 3.0, 1.0  # eps = 3e12
    a, n, _ = solve_both("5.7", omega0=w0, alpha=alpha, A=A)
    qn = math.exp(-math.pi)  # nome at m = 1/2, where K' = K
    c3 = A * 2 * math.pi / (K_half * math.sqrt(0.5)) * qn**1.5 / (1 + qn**3)
    for v in (a, n):
        assert v["omega"] == pytest.approx(math.pi * math.sqrt(alpha) * A / (2 * K_half), rel=1e-9)
        assert v["c3"] == pytest.approx(c3, rel=1e-8)


def test_period_diverges_logarithmically_at_the_barrier():
    # hard case: alpha = -1, omega0 = 2, A = 2 - 2e-8: g = 1 - A^2/4 = (2 - A)(2 + A)/4
    A = 1.99999998
    g = (2.0 - A) * (2.0 + A) / 4.0
    a, n, _ = solve_both("5.7", alpha=-1.0, A=A)
    omega, c3 = reference(2.0, -1.0, A, n=2048)
    T_asym = 2 * math.sqrt(2) / 2.0 * math.log(8 / g)
    for v in (a, n):
        assert 2 * math.pi / v["omega"] == pytest.approx(T_asym, rel=1e-6)
        assert v["omega"] == pytest.approx(omega, rel=1e-9)
        assert v["c3"] == pytest.approx(c3, rel=1e-8)


def test_harmonic_limit_and_barrier_rejected():
    a, n, _ = solve_both("5.7", alpha=0.0)
    for v in (a, n):
        assert v["omega"] == 2.0 and v["domega"] == 0.0 and v["c3"] == 0.0
    with pytest.raises(BadInput):
        registry.get("5.7").resolve({"alpha": -1.0, "A": 2.0})


@pytest.mark.parametrize("given", [{}, {"alpha": -15.0, "omega0": 2.0, "A": 0.5}])
def test_a_flipped_cubic_term_fails_the_energy_check(monkeypatch, given):
    """The energy is the statement's potential omega0^2 q^2/2 + alpha q^4/4 in SI, written apart from the
    equation of motion: flipping the sign of the cubic force (a defect in the equation) must make the
    monitored energy drift and the cross-check fail.  (Given {alpha -15, omega0 2, A 0.5}: eps = -0.94,
    the barrier branch.)  The route's equation is -x''/x = a + b x^2 (``restoring_factor``, written from
    y = 1 - x); flipped, a - b x^2 = (a + b x^2) - 2 b x^2."""
    import importlib

    from mech.problems import registry
    from mech.verification.crosscheck import cross_check

    mod = importlib.import_module("mech.problems.ch5.ex5_7_duffing_free")
    ex = registry.get("5.7")
    p = ex.resolve(given)
    assert cross_check(ex, p).agree  # sound equations pass
    sound = mod.restoring_factor
    monkeypatch.setattr(mod, "restoring_factor", lambda y, k, b: sound(y, k, b) - 2.0 * b * (1.0 - y) ** 2)
    result = cross_check(ex, p)
    assert not result.agree
    # the drift fails the variant (its Column), which the one-point solve reports as its failure
    assert any("energy" in str(e) for e in result.errors)


def test_tiny_amplitude_is_harmonic_to_the_last_bit():
    """A = 1e-90 m: eps = alpha A^2/omega0^2 = 0.8e-180/4 = 2e-181, so the motion is harmonic to the last bit:
    omega = omega0 = 2 rad/s, the shift (3/8) eps omega0 = 1.5e-181 rad/s and c3 = alpha A^3/(32 omega0^2)
    = 0.8e-270/128 = 6.25e-273 m, both still inside the range mech answers in.  The energy check used to
    form omega0^2 q^2 in SI (at A = 0.5e-200: ~1e-400, drift NaN, a loud failure)."""
    a, n, _ = solve_both("5.7", A=1e-90)
    for values in (a, n):
        assert values["omega"] == pytest.approx(2.0, rel=1e-12)
        assert values["domega"] == pytest.approx(1.5e-181, rel=1e-8)
        assert values["c3"] == pytest.approx(6.25e-273, rel=1e-8)


def test_an_amplitude_whose_shift_underflows_is_refused():
    """A = 0.5e-200 m: the shift (3/8) alpha A^2/omega0 = 3e-402 rad/s lies below 1e-290: refused in one line
    naming it (both solvers would print 0 for it)."""
    from mech.problems import registry
    from mech.problems.spec import BadInput

    with pytest.raises(BadInput, match="domega .* underflows"):
        registry.get("5.7").resolve({"A": 0.5e-200})


def test_a_shift_below_the_range_of_its_ratio_is_refused():
    """omega0 = 2e200 rad/s: the shift (3/8) alpha A^2/omega0 = 3.75e-202 rad/s is representable, but it is
    the fraction eps = 0.2/4e400 = 5e-402 of omega0, which is not: refused (exit 2) naming it, where both
    solvers printed a shift of 0 +- 1e-300."""
    from mech.problems import registry
    from mech.problems.spec import BadInput

    with pytest.raises(BadInput, match="floating point cannot represent"):
        registry.get("5.7").resolve({"omega0": 2e200})
