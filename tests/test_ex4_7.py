"""4.7 against values worked out by hand, by conservation laws (the module's analytic
route goes through the impulse J instead).

After the impact the rod's center moves at u and it turns at omega; the bullet moves
with the struck end at u + omega l.  Momentum: m u + m'(u + omega l) = m' v0.  Angular
momentum about the point where the rod's center was: (m l^2/3) omega + m' l (u + omega l)
= m' v0 l.  The second minus l times the first: (m l^2/3) omega = m u l, so u = omega l/3,
and then omega l = 3 m' v0/(m + 4m'); v_hit = 4 m' v0/(m + 4m'); v_end = u - omega l
= -2 m' v0/(m + 4m').  Energy after: m u^2/2 + (m l^2/3) omega^2/2 + m' v_hit^2/2.
  defaults m = 1, l = 0.5, m' = 0.01, v0 = 300 (m + 4m' = 1.04):
    v_end = -6/1.04, v_hit = 12/1.04, omega = 9/(0.5 * 1.04), E_loss = 450 - 450 * 0.04/1.04 = 450/1.04
  m = m' = 0.01, l = 0.002, v0 = 800 (m + 4m' = 0.05):
    v_end = -320, v_hit = 640, omega = 240000, E_loss = 3200 - 0.01 * 640^2/2 * ... = 640
"""

import pytest

from conftest import solve_both


def by_conservation(m, l, mb, v0):
    wl = 3 * mb * v0 / (m + 4 * mb)
    u = wl / 3
    v_hit = u + wl
    T_after = 0.5 * m * u**2 + 0.5 * (m * l**2 / 3) * (wl / l) ** 2 + 0.5 * mb * v_hit**2
    return {"v_end": u - wl, "v_hit": v_hit, "omega": wl / l, "E_loss": 0.5 * mb * v0**2 - T_after}


@pytest.mark.parametrize(
    "m, l, mb, v0, expected",
    [
        (1.0, 0.5, 0.01, 300.0, {"v_end": -6 / 1.04, "v_hit": 12 / 1.04, "omega": 9 / 0.52, "E_loss": 450 / 1.04}),
        (0.01, 0.002, 0.01, 800.0, {"v_end": -320.0, "v_hit": 640.0, "omega": 240000.0, "E_loss": 640.0}),
        (2.0, 0.3, 0.5, 40.0, by_conservation(2.0, 0.3, 0.5, 40.0)),
        (1.0, 0.5, 1e-8, 300.0, by_conservation(1.0, 0.5, 1e-8, 300.0)),
    ],
)
def test_against_conservation(m, l, mb, v0, expected):
    an, nu, run = solve_both("4.7", m=m, l=l, m_b=mb, v0=v0)
    for v in (an, nu):
        for k, x in expected.items():
            assert v[k] == pytest.approx(x, rel=1e-9)
    assert run.invariants["momentum"] < 1e-12
    assert run.invariants["angular momentum"] < 1e-12
    # the pulse is short enough that its finite length is negligible
    effects = [v for k, v in run.info.items() if k.startswith("finite_pulse_effect_rel ")]
    assert len(effects) == 4 and max(effects) < 1e-8  # ~ (omega tp)^2


def test_heavy_bullet_limit():
    # m' >> m: the rod is dragged along its end; far end at -v0/2, omega -> 3 v0/(4 l), E_loss -> m v0^2/8
    _, n, _ = solve_both("4.7", m=1.0, l=1.0, m_b=1e6, v0=1.0)
    assert n["v_end"] == pytest.approx(-0.5, rel=1e-6)
    assert n["omega"] == pytest.approx(0.75, rel=1e-6)
    assert n["E_loss"] == pytest.approx(0.125, rel=1e-6)
