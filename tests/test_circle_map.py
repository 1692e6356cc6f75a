"""solvers.numerics.circle_map against closed forms: a trigonometric polynomial is fitted exactly, a pure
rotation's rotation number is its step, and a perturbed one's matches a plain long orbit average."""

import math

import numpy as np
import pytest

from mech.solvers.numerics.circle_map import fourier_fit, rotation_number


def test_fit_recovers_a_trigonometric_polynomial():
    th = np.linspace(0.0, 2 * math.pi, 40, endpoint=False)
    d = 0.3 + 0.2 * np.cos(th) - 0.05 * np.sin(3 * th)
    coef, resid = fourier_fit(th, d, 4)
    # by hand: c0 = 0.3, a_1 = 0.2, b_3 = -0.05, the rest 0 (layout c0, a_1..a_4, b_1..b_4)
    want = np.zeros(9)
    want[0], want[1], want[4 + 3] = 0.3, 0.2, -0.05
    assert np.allclose(coef, want, atol=1e-14) and resid < 1e-14


def test_rotation_number_of_a_rigid_rotation_is_its_step():
    coef = np.zeros(9)
    coef[0] = 0.0123
    assert rotation_number(coef, 4) == pytest.approx(0.0123, rel=1e-12)


def test_rotation_number_against_a_plain_orbit_average():
    # theta -> theta + 0.4 + 0.1 sin theta: no closed form; a plain Birkhoff mean over 2e5 iterates (error
    # ~ 1/n, a different estimator) agrees to 1e-4
    coef = np.zeros(5)
    coef[0], coef[2 + 1] = 0.4, 0.1
    theta, total, n = 0.0, 0.0, 200_000
    for _ in range(n):
        step = 0.4 + 0.1 * math.sin(theta)
        total += step
        theta = math.fmod(theta + step, 2 * math.pi)
    assert rotation_number(coef, 2) == pytest.approx(total / n, abs=1e-4)
