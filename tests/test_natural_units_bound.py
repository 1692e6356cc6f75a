"""``scales.natural_units`` tells SI without its least-squares fit where a bound proves the fit would choose
SI (``_si_by_bound``): the answer must be the fit's own, bit for bit, at points near and far from the
defaults of every exercise, and the bound must be what answers near the defaults."""

from __future__ import annotations

import random

from mech.problems import registry, scales


def _draws(ex, rng, count):
    for k in range(count):
        spread = (1, 8, 15, 40, 200)[k % 5]  # bits from the defaults: inside, near and beyond the bound
        p = {}
        for prm in ex.params:
            x = prm.default
            if x and rng.random() < 0.9:
                x = x * 2.0 ** rng.uniform(-spread, spread)
            p[prm.name] = x
        yield p


def test_the_bound_answers_as_the_fit_does(monkeypatch):
    rng = random.Random(41)
    told, cases = 0, 0
    for ex in registry.all_exercises().values():
        for p in _draws(ex, rng, 40):
            fast = scales.natural_units(ex, p)
            with monkeypatch.context() as m:
                m.setattr(scales, "_si_by_bound", lambda rows, rhs: False)
                fitted = scales.natural_units(ex, p)
            assert fast == fitted, (ex.id, p)
            if fast is not None:
                assert all(a.hex() == b.hex() for a, b in zip(fast[1].values(), fitted[1].values()))
            cases += 1
            rows = [prm.dimension for prm in ex.params if any(prm.dimension) and prm.default and p[prm.name]]
            told += bool(rows) and fast is None and scales._si_by_bound(
                rows, [scales._log2_dev(p[prm.name], prm.default) for prm in ex.params
                       if any(prm.dimension) and prm.default and p[prm.name]])
    assert cases > 1000
    assert told > cases // 10  # the bound does answer, near the defaults


def test_a_rank_deficient_or_far_set_is_left_to_the_fit():
    assert not scales._si_by_bound([(0, 1, 0), (0, 2, 0), (0, 1, 0)], [0.0, 0.0, 0.0])  # no kg, no s
    assert not scales._si_by_bound([(1, 0, 0), (0, 1, 0), (0, 0, 1)], [20.0, 0.0, 0.0])  # 20 bits off
    assert scales._si_by_bound([(1, 0, 0), (0, 1, 0), (0, 0, 1)], [10.0, -5.0, 3.0])
