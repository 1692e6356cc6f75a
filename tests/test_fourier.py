"""mech.solvers.numerics.fourier's Fourier quadrature against closed forms and against QUADPACK's QAWO/QAWF.

Closed forms (contour integration, the pole of the integrand in the upper half plane):
  int_0^inf cos(w t)/(1 + w^2) dw = (pi/2) e^-|t|,
  int_0^inf sin(w t) w/(1 + w^2) dw = (pi/2) e^-t (t > 0),
  int_-inf^inf exp(i w t) g/((w - w0)^2 + g^2) dw = pi exp(i w0 t - g |t|) (a Lorentzian of width g),
and the damped oscillator's Green's function (the book's G: e^{-d t} sin(w1 t)/w1 and its limits)
as the inverse transform of chi = 1/(1 - w^2 - 2 i d w).  Accuracy asked: epsrel 1e-12, as 5.1
asks of its verification run.
"""

import math

import numpy as np
import pytest

from mech.problems.spec import NumericFailure
from mech.solvers.numerics.fourier import _spherical_bessel, fourier_quad, fourier_tail, inverse_fourier

TS = [0.01, 0.5, 1.0, 3.0, 30.0, 300.0, 3000.0]


def half_line(f, t, part, window=40.0, eps=1e-12, points=None):
    """int_0^inf f(w) exp(i t w) dw as a window and a tail: value and summed error estimates."""
    v1, e1, _ = fourier_quad(f, 0.0, window, t, part=part, epsabs=eps, epsrel=eps, points=points)
    v2, e2, _ = fourier_tail(f, window, t, part=part, epsabs=eps, epsrel=eps)
    return v1 + v2, e1 + e2


@pytest.mark.parametrize("t", TS + [-0.5, -30.0])
def test_cosine_transform_of_a_lorentzian(t):
    value, err = half_line(lambda w: 1.0 / (1.0 + w * w), t, "re")
    exact = 0.5 * math.pi * math.exp(-abs(t))
    assert abs(value - exact) <= 1e-12 * max(abs(exact), 1.0)
    assert abs(value - exact) <= err + 1e-15  # the estimate bounds the error


@pytest.mark.parametrize("t", TS)
def test_sine_transform_decaying_as_one_over_w(t):
    # the integrand decays as sin(w t)/w only: the tail's extrapolation does the work
    value, err = half_line(lambda w: w / (1.0 + w * w), t, "im")
    exact = 0.5 * math.pi * math.exp(-t)
    assert abs(value - exact) <= 1e-12 * max(abs(exact), 1.0)
    assert abs(value - exact) <= err + 1e-15


@pytest.mark.parametrize("t", [0.3, 7.0, 50.0, 400.0])
@pytest.mark.parametrize("g", [1e-1, 1e-3])
def test_narrow_resonance_over_the_whole_line(t, g):
    w0, window = 1.0, 40.0

    def f(w):
        return g / ((w - w0) ** 2 + g * g)

    points = sorted({w0, *(w0 + s * g * 4.0**j for s in (-1, 1) for j in range(8))})
    mid, e_mid, _ = fourier_quad(f, -window, window, t, part=None, epsabs=1e-12, epsrel=1e-12, points=points)
    right, e_r, _ = fourier_tail(f, window, t, part=None, epsabs=1e-13, epsrel=1e-12)
    left, e_l, _ = fourier_tail(lambda w: f(-w), window, -t, part=None, epsabs=1e-13, epsrel=1e-12)
    value = mid + right + left
    exact = math.pi * complex(math.cos(w0 * t), math.sin(w0 * t)) * math.exp(-g * t)
    # relative to the peak's area pi: at late times the transform is e^{-g t} small
    assert abs(value - exact) <= 1e-12 * math.pi
    assert abs(value - exact) <= e_mid + e_r + e_l + 1e-15


def green(d, t):
    if d < 1.0:
        w1 = math.sqrt((1.0 - d) * (1.0 + d))
        return math.exp(-d * t) * math.sin(w1 * t) / w1
    if d == 1.0:
        return t * math.exp(-t)
    wp = math.sqrt((d - 1.0) * (d + 1.0))
    return math.exp(-t / (d + wp)) * -math.expm1(-2.0 * wp * t) / (2.0 * wp)


@pytest.mark.parametrize("d", [1e-4, 1e-3, 0.0667, 1.0, 20.0, 600.0])
@pytest.mark.parametrize("t", [0.005, 4.2, 240.0, 3000.0])
def test_inverse_transform_of_the_oscillator_is_causal(d, t):
    def chi(x):
        return 1.0 / ((1.0 - x) * (1.0 + x) - 2j * d * x)

    poles = np.roots([-1.0, -2j * d, 1.0])
    after = inverse_fourier(chi, t, poles, epsrel=1e-12, vectorized=True)
    before = inverse_fourier(chi, -t, poles, epsrel=1e-12, vectorized=True)
    # relative to G's natural size 1 (the scaled units): G itself is e^{-d t} small at late times
    assert abs(after.value - green(d, t)) <= 1e-12
    assert abs(after.value - green(d, t)) <= after.abserr
    assert abs(before.value) <= max(before.abserr, 1e-16)
    assert abs(before.value) <= 1e-12


def test_scalar_and_vectorized_chi_agree():
    d = 0.3
    poles = np.roots([-1.0, -2j * d, 1.0])
    scalar = inverse_fourier(lambda x: 1.0 / complex(1.0 - x * x, -2.0 * d * x), 2.0, poles)
    vector = inverse_fourier(lambda x: 1.0 / ((1.0 - x * x) - 2j * d * x), 2.0, poles, vectorized=True)
    assert scalar.value == pytest.approx(vector.value, rel=1e-15)
    assert scalar.evaluations == vector.evaluations


@pytest.mark.filterwarnings("ignore::UserWarning")  # QUADPACK's own round-off warnings at these tolerances
def test_matches_quadpack_qawo_and_qawf():
    integrate = pytest.importorskip("scipy.integrate")

    def f(w):
        return np.exp(-w / 3.0) * np.log1p(w)

    for weight, part in (("cos", "re"), ("sin", "im")):
        ours, _, _ = fourier_quad(f, 0.0, 20.0, 7.3, part=part, epsabs=0.0, epsrel=1e-13)
        theirs, _ = integrate.quad(f, 0.0, 20.0, weight=weight, wvar=7.3, epsabs=0.0, epsrel=1e-13, limit=200)
        assert ours == pytest.approx(theirs, rel=1e-12, abs=1e-15)

    def slow(w):
        return (1.0 + w) ** -1.5  # decays slower than 1/w^2: the extrapolation, not the decay, converges

    for weight, part in (("cos", "re"), ("sin", "im")):
        ours, _, _ = fourier_tail(slow, 2.0, 1.7, part=part, epsabs=1e-14, epsrel=1e-12)
        theirs, _ = integrate.quad(slow, 2.0, np.inf, weight=weight, wvar=1.7, epsabs=1e-14, limlst=200)
        assert ours == pytest.approx(theirs, rel=1e-11, abs=1e-14)


@pytest.mark.parametrize("k", [0.0, 1e-9, 0.3, 1.0, 1.01, 2.5, 7.0, 15.0, 16.0, 17.5, 40.0, 300.0, 1e5])
def test_spherical_bessel_moments(k):
    special = pytest.importorskip("scipy.special")
    ours = _spherical_bessel(17, k)
    theirs = special.spherical_jn(np.arange(17), k)
    assert np.allclose(ours, theirs, rtol=1e-13, atol=1e-16)


def test_failures_are_loud():
    with pytest.raises(NumericFailure):  # a kink the panels cannot resolve in the few allowed
        fourier_quad(lambda w: np.abs(w - 0.3) ** 0.5, 0.0, 1.0, 5.0, epsabs=1e-14, epsrel=1e-14, limit=5)
    with pytest.raises(NumericFailure):  # too few cycles for the extrapolation to settle
        fourier_tail(lambda w: 1.0 / w, 1.0, 1.0, max_terms=4)
    with pytest.raises(NumericFailure):  # a value that is not a number, never integrated over
        fourier_quad(lambda w: np.where(w > 0.5, np.nan, 1.0), 0.0, 1.0, 3.0)
    with pytest.raises(ValueError):
        inverse_fourier(lambda x: 1.0, 0.0, [1j])


@pytest.mark.parametrize("omega, x", [(-1.0e11, 0.99999999), (5.15e7, 1.0000001), (-3.3e13, 0.7),
                                      (1e15, 0.123456789), (-6.4e9, 1.0 - 2.0**-40), (4.3e12, 37.25)])
def test_turn_is_exact_beyond_two_to_the_22_turns(omega, x):
    """exp(i omega x) of the exact product, against 100-digit sin/cos (tests/hiprec.py): fl(omega x) alone
    would be off by up to u |omega x| (1e-5 rad at 1e11), which kept the late-time panels from agreeing."""
    from decimal import localcontext

    import hiprec

    from mech.solvers.numerics.fourier import _turn

    with localcontext() as ctx:
        ctx.prec = hiprec.PREC
        s, c = hiprec.sincos(hiprec.D(omega) * hiprec.D(x))
    z = _turn(omega, x)
    assert abs(z.real - float(c)) < 4e-16 and abs(z.imag - float(s)) < 4e-16


@pytest.mark.parametrize("t", [4.2e-200, 1e-30, 1e-3])
def test_an_early_time_is_near_zero(t):
    """q'' + 2 d q' + q = delta(t): G(t) = e^{-d t} sin(w1 t)/w1 (= t (1 - d t + ...) for t -> 0), by hand;
    the quadrature is asked to an absolute tolerance of order 1e-12 (G's scale is 1)."""
    d = 0.0667

    def chi(x):
        with np.errstate(over="ignore"):  # x up to 40/t: chi = 0 where x^2 overflows (its size < 1e-308)
            return 1.0 / ((1.0 - x) * (1.0 + x) - 2j * d * x)

    poles = np.roots([-1.0, -2j * d, 1.0])
    res = inverse_fourier(chi, t, poles, epsrel=1e-12, vectorized=True)
    assert abs(res.value - green(d, t)) <= max(res.abserr, 1e-15)
    assert abs(res.value - green(d, t)) <= 1e-11


@pytest.mark.parametrize("d", [1e-13, 1e-50, 6.7e-202])
def test_a_peak_narrower_than_the_floats_around_it(d):
    """A resonance of width d far below the spacing of the floats at w = 1 (Q up to 1e201).  Its inverse
    transform at t = 4.2 is e^{-d t} sin(w1 t)/w1 with w1 = (1 - d^2)^(1/2) = 1 to the last bit: sin(4.2),
    by hand.  chi in the local form (base, offset) so that the offset carries what 1 + y cannot."""
    def chi_local(base, off):
        return 1.0 / (((1.0 - base) - off) * ((1.0 + base) + off) - 2j * d * (base + off))

    poles = [complex(1.0, -d), complex(-1.0, -d)]
    t = 4.2
    after = inverse_fourier(chi_local, t, poles, epsrel=1e-11, vectorized=True, local=True)
    before = inverse_fourier(chi_local, -t, poles, epsrel=1e-11, vectorized=True, local=True)
    assert abs(after.value - math.sin(t)) <= 1e-10
    assert abs(before.value) <= 1e-10


@pytest.mark.parametrize("d, w", [(50.0, 0.3), (1e4, 2e-4), (20.0, 0.0)])
def test_impulse_spectrum_by_the_flow_of_a_stiff_oscillator(d, w):
    """q'' + 2 d q' + q = 0 from q = 0, q' = 1: int_0^inf q e^{i w t} dt = 1/(1 - w^2 - 2 i d w)
    (integrate q'' + 2 d q' + q against e^{i w t} by parts).  The numpy-only route (exp(A t), quadrature)
    and, as a conformance check, scipy's LSODA on the same segment."""
    from mech.solvers.numerics.fourier import FLOW, impulse_spectrum

    A = np.array([[0.0, 1.0], [-1.0, -2.0 * d]])
    b, c = np.array([0.0, 1.0]), np.array([1.0, 0.0])
    exact = 1.0 / complex(1.0 - w * w, -2.0 * d * w)
    slow = d - math.sqrt(d * d - 1.0)
    seg = 1.0 / slow
    spec = impulse_spectrum(A, b, c, w, rtol=1e-10, segment=seg, method=FLOW)
    assert abs(spec.value - exact) <= 1e-9 * abs(exact)
    assert spec.traj.method.startswith("exp(A t)") and not spec.traj.forced
    from mech.solvers.numerics.linear_flow import rounding_bound

    assert abs(spec.liouville_drift) <= rounding_bound(A, seg)  # measured 4e-12 at d = 1e4 (bound 7e-7)
    looser = impulse_spectrum(A, b, c, w, rtol=1e-4, segment=seg, method=FLOW)
    assert abs(looser.value - exact) <= 1e-3 * abs(exact)  # the tolerance is the quadrature's
    forced = impulse_spectrum(A, b, c, w, rtol=1e-8, segment=seg, method=FLOW, integrator="LSODA",
                              atol=1e-11 * np.array([1.0, slow, slow, slow * slow, seg, seg * slow, seg, seg * slow]))
    assert forced.traj.method == "LSODA" and forced.traj.forced
    assert abs(forced.value - exact) <= 1e-5 * abs(exact)
