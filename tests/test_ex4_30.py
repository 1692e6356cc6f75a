"""4.30 against values worked out independently.

By hand: in a frame turning at -w_z = -w_E cos(theta) about the vertical the
Coriolis term of zeta'' + 2i w_z zeta' + w0^2 zeta = 0 disappears except for a
frequency shift (w'^2 = w0^2 + w_z^2), so the path there is a fixed ellipse and the
plane turns at Omega_F = -w_E cos(theta) relative to the ground.

Independent method (in the test): the eigenvalues of the 4x4 first-order matrix
of the Earth-frame equations are the two circular modes' frequencies nu+ and nu-;
the plane turns at their half sum (signed), and the release at rest fixes the
modes' amplitudes from the eigenvectors, whose difference is the minor semi-axis.
"""

import math

import numpy as np
import pytest

from conftest import solve_both

WE = 7.2921159e-5


def by_modes(theta, l, g, a, wE):
    wz = wE * math.sin(math.pi / 2 - theta)
    w0sq = g / l
    M = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [-w0sq, 0, 0, 2 * wz], [0, -w0sq, -2 * wz, 0]], float)
    vals, vecs = np.linalg.eig(M)
    # complex coordinate zeta = x + i y: the circular modes are zeta ~ exp(i nu t)
    # with nu = Im(lambda) for eigenvectors where y = i x (counterclockwise) or y = -i x
    freqs, amps = [], []
    coeff = np.linalg.solve(vecs, np.array([a, 0, 0, 0], complex))
    for j in range(4):
        v = vecs[:, j] * coeff[j]
        zeta0 = v[0] + 1j * v[1]
        if abs(zeta0) > 1e-9 * a:  # this eigenvector carries zeta (the others carry conj(zeta))
            freqs.append(vals[j].imag)
            amps.append(abs(zeta0))
    assert len(freqs) == 2
    omega_F = 0.5 * (freqs[0] + freqs[1])
    return omega_F, abs(amps[0] - amps[1])


@pytest.mark.parametrize(
    "theta, l, g, a, wE",
    [
        (0.7182029871956666, 67.0, 9.81, 3.0, WE),  # defaults: Paris, Pantheon
        (1.5690509975429023, 67.0, 9.81, 3.0, WE),  # hard case 1: 0.1 deg from the equator
        (0.0, 0.25, 9.81, 0.01, WE),  # hard case 2: the pole, a 1 s pendulum
        (2.4, 10.0, 9.81, 0.5, WE),  # southern hemisphere: the plane turns counterclockwise
        (0.3, 2.0, 9.81, 0.1, 1.5),  # a fast "planet": w_z comparable to w0
    ],
)
def test_against_mode_decomposition(theta, l, g, a, wE):
    omega_F, b_modes = by_modes(theta, l, g, a, wE)
    hand = -wE * math.cos(theta)
    wz = wE * math.cos(theta)
    b = a * abs(wz) / math.sqrt(g / l + wz * wz)  # hand: ||A| - |B|| with A - B = a w_z/w'
    assert omega_F == pytest.approx(hand, rel=1e-9)
    # the eigenvectors resolve ||A| - |B|| to ~ eps a / b relatively (3e-7 near the equator: skip there)
    if b > 1e-6 * a:
        assert b_modes == pytest.approx(b, rel=1e-6)
    A, N, run = solve_both("4.30", theta=theta, l=l, g=g, a=a, omega_E=wE)
    for values in (A, N):
        assert values["Omega_F"] == pytest.approx(hand, rel=1e-8)
        assert values["T_F"] == pytest.approx(2 * math.pi / abs(hand), rel=1e-8)
        assert values["b_miss"] == pytest.approx(b, rel=1e-7)
    assert run.invariants["energy"] < 1e-8
    assert run.invariants["L_inertial"] < 1e-8


def test_paris_numbers():
    # cos(41.15 deg) = 0.7529864; T_F = 2 pi/(7.2921159e-5 * 0.7529864) = 31.79 h
    A, N, _ = solve_both("4.30")
    for values in (A, N):
        assert values["T_F"] / 3600 == pytest.approx(31.786, rel=1e-4)
        assert values["Omega_F"] < 0  # clockwise in the north


def test_equator_plane_does_not_turn():
    from mech.problems.spec import Undefined

    A, N, _ = solve_both("4.30", theta=math.pi / 2)
    for values in (A, N):
        assert values["Omega_F"] == 0.0
        assert isinstance(values["T_F"], Undefined)
        assert abs(values["b_miss"]) < 1e-12


def test_pole_miss_distance_is_tiny_fraction_of_amplitude():
    # w_z/w0 = 7.29e-5/6.264 = 1.164e-5 of a = 1 cm
    A, N, _ = solve_both("4.30", theta=0.0, l=0.25, g=9.81, a=0.01)
    expect = 0.01 * WE / math.sqrt(9.81 / 0.25 + WE**2)
    for values in (A, N):
        assert values["b_miss"] == pytest.approx(expect, rel=1e-7)


def test_fast_rotation_issue_draw():
    """Issue 14 draw: |w_z|/w0 = 1470, so the Earth-frame speeds are w0^2/w' ~ 1e-7 of the
    positions' scale; with the absolute tolerance sized for positions the turning points moved
    by 3e-7 at rtol/10.  Omega_F = -w_E cos(theta), b_miss = a w_z / (g/l + w_z^2)^(1/2)."""
    p = dict(theta=0.000317957, l=599.561, g=0.0129606, a=157824.0, omega_E=6.84992)
    wz = p["omega_E"] * math.cos(p["theta"])
    _, n, _ = solve_both("4.30", **p)
    _, n_fine, _ = solve_both("4.30", rtol=1e-11, **p)
    assert n["Omega_F"] == pytest.approx(-wz, rel=1e-10)
    assert n_fine["Omega_F"] == pytest.approx(n["Omega_F"], rel=1e-10)
    assert n["b_miss"] == pytest.approx(p["a"] * wz / math.sqrt(p["g"] / p["l"] + wz * wz), rel=1e-12)


def test_a_fast_rotation_below_the_bound_is_resolved():
    """|w_z|/w0 = 73 cos(theta) / (9.81 / 6.7e12)^(1/2) ~ 4.5e7, below the declared bound 1e8.  The scalar route
    located its turning points on one long run and they scattered (it failed, "too small to resolve"); the
    ensemble's legs stop at each turning point and start the next from it, and the plane's rate is resolved:
    by hand Omega_F = -w_E cos(theta) (exact in the linear model), b_miss = a w_z/(g/l + w_z^2)^(1/2) = a to
    1e-16, and the solve agrees with its rerun at rtol/10."""
    import mech

    theta, a = 0.7182029871956666, 3.0
    sol = mech.solve("4.30", omega_E=73.0, l=6.7e12)
    assert sol.agree is True
    assert sol["Omega_F"].numeric == pytest.approx(-73.0 * math.cos(theta), rel=1e-9)
    assert sol["b_miss"].numeric == pytest.approx(a, rel=1e-9)


def test_absurdly_fast_rotation_fails_at_once():
    """omega_E = 7e195 rad/s: (w0/rate)^2 underflowed to 0 and the run spun into the 8 s budget;
    past |w_z|/w0 = 1e8 the loops are below round-off and the solver says so before integrating."""
    import time

    from mech.problems.spec import NumericFailure

    t0 = time.perf_counter()
    with pytest.raises(NumericFailure, match="below round-off"):
        solve_both("4.30", omega_E=7.29212e195)
    assert time.perf_counter() - t0 < 2.0
