"""Conformance of mech.solvers.mechanics.frames (rotations) and numerics.roots' bit-exact bisection,
against scipy.spatial.transform and closed forms."""

import math

import numpy as np
import pytest

from mech.solvers.mechanics.frames import (
    cross_z,
    quat_aligning,
    quat_from_axis_angle,
    quat_from_matrix,
    quat_mul,
    quat_to_matrix,
    rotate2,
    rotate_many,
    rotation,
    skew,
)
from mech.solvers.numerics.roots import bracketed_root, walk_to_sign_change

Rotation = pytest.importorskip("scipy.spatial.transform").Rotation
RNG = np.random.default_rng(16)


def _quats(n):
    q = RNG.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1)[:, None]


def test_skew_is_the_cross_product():
    for _ in range(5):
        v, u = RNG.normal(size=3), RNG.normal(size=3)
        assert np.allclose(skew(v) @ u, np.cross(v, u), rtol=0, atol=1e-15)


def test_rotation_matches_scipy_rotvec():
    for _ in range(5):
        axis, angle = RNG.normal(size=3), RNG.uniform(-4, 4)
        want = Rotation.from_rotvec(angle * axis / np.linalg.norm(axis)).as_matrix()
        assert np.allclose(rotation(axis, angle), want, rtol=0, atol=1e-15)


def test_complex_angle_gives_the_derivative():
    """Complex step: Im R(axis, i h)/h = d R/d angle at 0 = skew(axis) (unit axis), to O(h^2)."""
    axis = np.array([0.0, 0.6, 0.8])
    h = 1e-20
    assert np.allclose(rotation(axis, 1j * h).imag / h, skew(axis), rtol=0, atol=1e-15)


def test_quaternions_match_scipy():
    for q in _quats(6):
        want = Rotation.from_quat([q[1], q[2], q[3], q[0]]).as_matrix()  # scipy: scalar last
        assert np.allclose(quat_to_matrix(q), want, rtol=0, atol=1e-15)
        back = quat_from_matrix(want)
        assert np.allclose(back * np.sign(back[0]), q * np.sign(q[0]), rtol=0, atol=1e-14)
    a, b = _quats(2)
    assert np.allclose(quat_to_matrix(quat_mul(a, b)), quat_to_matrix(a) @ quat_to_matrix(b), atol=1e-15)
    axis, angle = np.array([1.0, -2.0, 0.5]), 0.7
    assert np.allclose(quat_to_matrix(quat_from_axis_angle(axis, angle)), rotation(axis, angle), atol=1e-15)


def test_stacked_and_aligning():
    qs = _quats(7).T  # 4 x N
    v = np.array([0.3, -1.0, 2.0])
    got = rotate_many(qs, v)
    for n in range(qs.shape[1]):
        assert np.allclose(got[:, n], quat_to_matrix(qs[:, n]) @ v, rtol=0, atol=1e-15)
    for v in (RNG.normal(size=3), np.array([0.0, 0.0, -2.0]), np.array([0.0, 0.0, 3.0])):
        assert np.allclose(quat_to_matrix(quat_aligning(v)) @ (v / np.linalg.norm(v)), [0, 0, 1], atol=1e-15)


def test_plane_rotation():
    r = np.array([[1.0, 0.0], [0.3, -0.4]])
    assert np.allclose(rotate2(r, math.pi / 2), [[0.0, 1.0], [0.4, 0.3]], atol=1e-16)
    assert np.allclose(cross_z(2.0, r), [[0.0, 2.0], [0.8, 0.6]], atol=0)


def test_bracketed_root_to_the_last_bit():
    for root in (1e-30, 0.7, 3e3, -2.5):
        x = bracketed_root(lambda t: t - root, -1e4, 1e4)
        assert x == root
    x = bracketed_root(lambda t: t * t - 2.0, 0.0, 2.0)
    assert abs(x - math.sqrt(2.0)) <= math.ulp(math.sqrt(2.0))
    lo = walk_to_sign_change(lambda t: t - 1e-9, 1.0, lambda t: t / 2, -1.0)
    assert 0 < lo < 1e-9
