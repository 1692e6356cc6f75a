"""5.12 near its threshold: where the pump's amplitude a lies within the leading-order threshold's own error
of it, the theory cannot tell whether a stationary swing exists (a_th = 0.0080037 m by the theory, 0.0079601 m
exact at l = 0.506583 m, a = 0.008 m: the theory says no swing, the exact motion swings at 0.042 rad).  There
theta_st is outside the theory's range (not compared), never a disagreement; at the defaults it is compared."""

from mech.problems import registry
from mech.verification.crosscheck import cross_check
from mech.verification.judge import Verdict


def test_near_the_threshold_the_swing_is_outside_the_theory_not_wrong():
    ex = registry.get("5.12")
    sol = cross_check(ex, ex.resolve({"l": 0.506583}))
    q = sol["theta_st"]
    assert q.analytic == 0.0 and q.numeric > 0.04  # the theory says no swing; the motion swings
    assert q.verdict is Verdict.OUTSIDE and "threshold" in q.reason
    assert not any(e.kind == "disagree" for e in sol.errors)


def test_at_the_defaults_the_swing_is_compared():
    ex = registry.get("5.12")
    q = cross_check(ex, ex.resolve({}))["theta_st"]
    assert q.verdict is not Verdict.OUTSIDE and q.agree is True
