"""``formula_ast._distinct_points``: the points of an enclosure enclosed once each.  Held to a reference
written here (a dict of each point's first occurrence, by the bits of its doubles) for few and many points,
with repeats, -0.0 beside 0.0 and NaNs: None exactly where every point is distinct."""

from __future__ import annotations

import random
import struct

import numpy as np

from mech.students.formula_ast import _distinct_points


def _reference(env, n):
    rows = [tuple(struct.pack("<d", float(v[i])) for v in env.values()) for i in range(n)]
    first: dict = {}
    for i, r in enumerate(rows):
        first.setdefault(r, i)
    if len(first) == n:
        return None
    order = sorted(first.values())
    rank = {rows[i]: k for k, i in enumerate(order)}
    return order, [rank[r] for r in rows]


def test_distinct_points_match_the_reference():
    rng = random.Random(7)
    pool = [0.0, -0.0, 1.0, 2.5, float("nan"), 1e-300, -3.0]
    for n in (2, 3, 5, 64, 256, 257, 600):
        for repeats in (False, True):
            for names in (1, 2):
                env = {f"p{k}": np.array([rng.choice(pool) if repeats else rng.uniform(-1, 1) for _ in range(n)])
                       for k in range(names)}
                got, want = _distinct_points(env, n), _reference(env, n)
                if want is None:
                    assert got is None
                else:
                    assert got is not None and got[0].tolist() == want[0] and got[1].tolist() == want[1]


def test_one_repeat_among_few_points_is_found():
    for values in ([1.0, 1.0], [0.5, 2.0, 0.5], [3.0, 4.0, 5.0, 4.0]):
        env = {"a": np.array(values), "b": np.full(len(values), 2.0)}
        got, want = _distinct_points(env, len(values)), _reference(env, len(values))
        assert got is not None and got[0].tolist() == want[0] and got[1].tolist() == want[1]
    assert _distinct_points({"a": np.array([0.0, -0.0])}, 2) is None  # other bits: other points
