"""4.19, 4.20 and 4.21 written once over arrays of variants (issue 41): the route at N variants agrees with
values worked out by hand and, variant by variant, with the batch of one; a variant that fails fails alone.

By hand (the docstrings of tests/test_ex4_19.py, test_ex4_20.py and test_ex4_21.py):
* 4.19, a thin disk (I3 = 2 I1): Omega_body = omega cos(alpha), omega_lab = omega (1 + 3 cos^2 alpha)^(1/2),
  tan(theta_L) = tan(alpha)/2.
"""

import math

import numpy as np
import pytest

from mech.problems import registry


def _arrays(pts):
    return {k: np.array([float(p[k]) for p in pts]) for k in pts[0]}


def _within_claims(col, k, want, extra_abs=0.0):
    rel = float(np.broadcast_to(col.rel, col.value.shape)[k])
    ab = float(np.broadcast_to(col.abs, col.value.shape)[k])
    return abs(col.value[k] - want) <= rel * abs(want) + ab + extra_abs


def _batch_vs_one(ex_id, pts, outputs):
    """The route at all the points, then at each point alone: each value within the two claims."""
    ex = registry.get(ex_id)
    route = ex.batched_route
    many = route.numeric(_arrays(pts), ex.default_rtol, outputs)
    for k, p in enumerate(pts):
        one = route.numeric(_arrays([p]), ex.default_rtol, outputs)
        for o in outputs:
            a, b = many[o], one[o]
            assert a.reason("failed", k) is None and b.reason("failed", 0) is None, (o, p)
            claim = (float(np.broadcast_to(a.rel, a.value.shape)[k]) * abs(a.value[k])
                     + float(np.broadcast_to(a.abs, a.value.shape)[k])
                     + float(np.broadcast_to(b.rel, b.value.shape)[0]) * abs(b.value[0])
                     + float(np.broadcast_to(b.abs, b.value.shape)[0]))
            assert abs(a.value[k] - b.value[0]) <= claim, (o, p, a.value[k], b.value[0])
    return many


# --------------------------------------------------------------------------- 4.19

DISKS = [dict(omega=10.0, alpha=a) for a in (0.0, 1e-3, 0.05, math.pi / 4, math.pi / 3, 1.5, math.pi / 2)]
DISKS += [dict(omega=2.0, alpha=math.pi / 4), dict(omega=3e-5, alpha=0.2), dict(omega=7e8, alpha=1.0)]


def _disk_by_hand(omega, alpha):
    c = math.cos(alpha)
    return {"Omega_body": omega * c, "omega_lab": omega * math.sqrt(1 + 3 * c * c),
            "theta_L": math.atan2(math.sin(alpha), 2 * c)}


def test_disk_batch_agrees_with_the_hand_values_and_the_batch_of_one():
    outputs = ("Omega_body", "omega_lab", "theta_L")
    got = _batch_vs_one("4.19", DISKS, outputs)
    for k, p in enumerate(DISKS):
        want = _disk_by_hand(**p)
        for o in outputs:
            assert _within_claims(got[o], k, want[o]), (o, p, got[o].value[k], want[o])


def test_disk_a_variant_sampled_too_sparsely_fails_alone(monkeypatch):
    """16 samples over two spins: a nearly flat disk's axis turns at 2 omega about L, 8 pi over the run, 1.57 rad
    a sample (over phase_rate's 1 rad), while the disk spun in its plane turns at omega, 0.79 rad a sample."""
    from mech.problems.ch4 import ex4_19_disk_precession as mod

    monkeypatch.setattr(mod, "CHECKPOINTS", 16)
    pts = [dict(omega=10.0, alpha=0.05), dict(omega=10.0, alpha=math.pi / 2)]
    got = registry.get("4.19").batched_route.numeric(_arrays(pts), 1e-10, ("omega_lab", "theta_L"))
    for o in ("omega_lab", "theta_L"):
        assert "too sparse" in got[o].reason("failed", 0)
        assert got[o].reason("failed", 1) is None
    assert _within_claims(got["omega_lab"], 1, 10.0)
