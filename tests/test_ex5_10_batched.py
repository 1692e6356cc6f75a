"""5.10's route written once over variants (issue 41): N variants at once equal each variant alone to their
claims, against harmonic balance (tests/test_ex5_10.py's independent method) in the batch; a variant that
cannot be answered fails alone; the circle maps of the beat fitted and iterated as a stack equal each alone."""

import math

import numpy as np
import pytest

from test_ex5_10 import DEF, NARROW_B, NARROW_C, hb_edges

OUTPUTS = ("xi_lo", "xi_hi", "width", "beat")


def _route(rows, rtol=1e-10, outputs=OUTPUTS):
    from mech.problems import registry
    from mech.problems.spec import Tally

    ex = registry.get("5.10")
    P = {k: np.array([float(r[k]) for r in rows]) for k in DEF}
    tally = Tally()
    return ex.batched_route.numeric(P, rtol, outputs, memo={}, tally=tally), tally


ROWS = [dict(DEF), {**DEF, "omega": 3.005}, {**DEF, "mu": 0.03, "f0": 0.018, "omega": 3.015},
        {**DEF, "omega0": 2.0, "mu": 0.3, "beta": 1.0, "f0": 0.15, "omega": 2.1}, {**DEF, **NARROW_B}]


def test_a_batch_is_each_variant_alone_to_its_claims():
    many, _ = _route(ROWS)
    for j, row in enumerate(ROWS):
        one, _ = _route([row])
        for name in OUTPUTS:
            a, b = many[name], one[name]
            assert not a.mask("failed")[j] and not b.mask("failed")[0]
            bar = (np.broadcast_to(a.rel, a.value.shape)[j] + np.broadcast_to(b.rel, b.value.shape)[0]) * abs(b.value[0])
            assert abs(a.value[j] - b.value[0]) <= bar, (row, name, a.value[j], b.value[0], bar)


def test_the_batch_edges_against_harmonic_balance():
    """The edges of three variants solved together, each against the harmonic balance of its own equation (no
    shooting, no integration), to 1e-7 as tests/test_ex5_10.py holds the one-point solve."""
    rows = ROWS[:1] + ROWS[2:4]
    got, tally = _route(rows, outputs=("xi_lo", "xi_hi", "width"))  # the beats are not asserted here
    for j, row in enumerate(rows):
        hi, lo = hb_edges(row)
        assert got["xi_hi"].value[j] == pytest.approx(hi, rel=1e-7)
        assert got["xi_lo"].value[j] == pytest.approx(lo, rel=1e-7)
        # at a fold one Floquet multiplier is 1
        assert tally.info["fold_multiplier_hi"][j] == pytest.approx(1.0, abs=1e-6)
        assert tally.info["fold_multiplier_lo"][j] == pytest.approx(1.0, abs=1e-6)


def test_a_variant_whose_beat_cannot_be_resolved_fails_alone():
    """Draw (c) 2e-10 rad/s above omega0 (tests/test_ex5_10.py: the beat ~2.3e-10 rad/s lies far below what the
    settling resolves at omega0 = 7e5 rad/s) beside the defaults: its beat fails saying why, its edges stand,
    and the defaults' beat is sqrt(0.03^2 - 0.015^2) to the leading order's few percent."""
    rows = [dict(DEF), {**DEF, **NARROW_C, "omega": 684581.00000000023}]
    got, _ = _route(rows)
    beat = got["beat"]
    assert list(beat.mask("failed")) == [False, True]
    assert "is not resolved" in beat.reason("failed", 1)
    assert not got["width"].mask("failed").any()
    assert beat.value[0] == pytest.approx(0.015 * math.sqrt(3.0), rel=0.05)
    D = NARROW_C["f0"] * math.sqrt(NARROW_C["beta"]) / (4 * NARROW_C["omega0"])  # 3.53811e-11 by hand
    assert got["width"].value[1] == pytest.approx(2 * D, rel=1e-3)


def test_circle_maps_as_a_stack_are_each_alone():
    from mech.solvers.numerics.circle_map import fourier_fit, rotation_number

    rng = np.random.default_rng(3)
    K, n = 6, 40
    theta = np.sort(rng.uniform(0, 2 * math.pi, (9, n)), axis=1)
    # d = c + e sin(theta): maps of the Arnold family with mean drifts from 0.02 to 0.3
    c, e = np.linspace(0.02, 0.3, 9), np.linspace(0.001, 0.01, 9)
    d = c[:, None] + e[:, None] * np.sin(theta)
    coef, resid = fourier_fit(theta, d, K)
    assert np.all(resid < 1e-13)
    assert np.allclose(coef[:, 0], c, rtol=0, atol=1e-14) and np.allclose(coef[:, K + 1], e, rtol=0, atol=1e-14)
    stacked = rotation_number(coef, K)
    for j in range(9):
        alone = rotation_number(coef[j], K)
        assert stacked[j] == pytest.approx(alone, rel=1e-12)
        # a rigid rotation's mean increment is its constant (e = 0: every iterate moves by c)
        assert rotation_number(np.concatenate([[c[j]], np.zeros(2 * K)]), K) == pytest.approx(c[j], rel=1e-14)
