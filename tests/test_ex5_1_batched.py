"""5.1's route over arrays of variants (issue 41): the variants solved together, stiff and not, each within its
claims of what its batch of one gives and of the closed forms worked out by hand (the docstring of
tests/test_ex5_1.py: chi = 1/(m (w0^2 - w^2 - 2 i d w)); G = e^{-d t} sin(w1 t)/(m w1), t e^{-d t}/m at
d = w0, e^{-d t} sinh(w' t)/(m w') above); the one-point solve is the batch of one; a sweep along omega
integrates G's Fourier integrals once (they do not depend on omega)."""

import math

import numpy as np
import pytest

from mech.problems import registry
from mech.problems.ch5 import ex5_1_response_green as m

VARIANTS = [  # defaults; critical; Q = 500 near resonance; strongly overdamped (stiff); static; another scale
    dict(m=0.5, omega0=6.0, delta=0.4, tau=0.7, omega=5.0),
    dict(m=0.5, omega0=6.0, delta=6.0, tau=0.7, omega=5.0),
    dict(m=0.5, omega0=6.0, delta=0.006, tau=40.0, omega=5.994),
    dict(m=0.5, omega0=6.0, delta=120.0, tau=2.0, omega=0.5),
    dict(m=0.5, omega0=6.0, delta=0.4, tau=0.7, omega=0.0),
    dict(m=2.0, omega0=1.0, delta=0.25, tau=3.0, omega=2.0),
]


def _hand(m_, w0, d, t, w):
    if d < w0:
        w1 = math.sqrt(w0 * w0 - d * d)
        G = math.exp(-d * t) * math.sin(w1 * t) / (m_ * w1)
    elif d == w0:
        G = t * math.exp(-d * t) / m_
    else:
        wp = math.sqrt(d * d - w0 * w0)
        G = (math.exp(-(d - wp) * t) - math.exp(-(d + wp) * t)) / (2 * m_ * wp)
    chi = 1.0 / (m_ * complex(w0 * w0 - w * w, -2.0 * d * w))
    return {"G": G, "G_minus": 0.0, "chi_re": chi.real, "chi_im": chi.imag}


def _P(rows):
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def _bar(col, i):
    return (np.broadcast_to(col.rel, col.value.shape)[i] * abs(col.value[i])
            + np.broadcast_to(col.abs, col.value.shape)[i])


def test_the_variants_together_are_each_alone_and_the_closed_forms():
    rtol = 1e-10
    names = ("G", "G_minus", "chi_re", "chi_im")
    together = m.numeric(_P(VARIANTS), rtol, names)
    for j, v in enumerate(VARIANTS):
        alone = m.numeric(_P([v]), rtol, names)
        hand = _hand(v["m"], v["omega0"], v["delta"], v["tau"], v["omega"])
        for name in names:
            col, one = together[name], alone[name]
            assert not col.mask("failed")[j] and not one.mask("failed")[0]
            assert abs(col.value[j] - one.value[0]) <= _bar(col, j) + _bar(one, 0), (j, name)
            assert abs(col.value[j] - hand[name]) <= _bar(col, j), (j, name)


def test_the_one_point_solve_is_the_batch_of_one():
    ex = registry.get("5.1")
    assert set(ex.batched_route.outputs) == {o.name for o in ex.outputs}
    assert ex.numeric_solver == ex.batch_of_one
    n, run = ex.solve_numeric(ex.resolve(VARIANTS[3]))
    assert run.info["stiff"] and not ex.solve_numeric(ex.resolve({}))[1].info["stiff"]


def test_a_sweep_along_omega_integrates_g_once(monkeypatch):
    calls = []
    real = m.inverse_fourier
    monkeypatch.setattr(m, "inverse_fourier", lambda *a, **kw: calls.append(a[1]) or real(*a, **kw))
    rows = [dict(VARIANTS[0], omega=w) for w in (1.0, 3.0, 5.0, 7.0)]
    memo = {}
    got = m.numeric(_P(rows), 1e-10, ("G", "chi_re"), memo=memo)
    assert len(calls) == 2  # G(+tau) and G(-tau), once for the four
    assert np.all(got["G"].value == got["G"].value[0])
    m.numeric(_P(rows), 1e-10, ("G",), memo=memo)  # a later chunk of the same sweep: nothing new
    assert len(calls) == 2
    for k, w in enumerate((1.0, 3.0, 5.0, 7.0)):
        assert got["chi_re"].value[k] == pytest.approx(_hand(0.5, 6.0, 0.4, 0.7, w)["chi_re"], rel=1e-8)


def test_the_one_point_solve_names_both_methods():
    """The batch of one says how each domain was crossed, as the one-point route did: chi by DOP853, G by
    the Fourier quadrature (a Tally's ``method``)."""
    from mech.problems import registry

    ex = registry.get("5.1")
    _, run = ex.solve_numeric(ex.resolve({}))
    assert run.method == "DOP853 + Filon/Wynn Fourier quadrature"
