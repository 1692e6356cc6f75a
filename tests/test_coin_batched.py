"""4.23's batched route (issue 32 item 4): every personal variant of a class solved at once, each still
cross-checked, agreeing with values worked out by hand and with the one-point route.

By hand (the module docstring of ex4_23 and tests/test_ex4_23.py): the angular momentum about the centre
turns at Omega about z; equating its rate with the contact force's torque gives
Omega^2 = 4 g tan(theta) / (6 R - 5 r sin(theta)), T = 2 pi / Omega, and rolling gives omega_spin = Omega R/r.
"""

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

from mech.cli.main import cli
from mech.problems import registry
from mech.problems.motion import motion_path

OUTPUTS = ("T", "Omega", "omega_spin")


def hand(r, theta, R, g):
    Om = math.sqrt(4 * g * math.tan(theta) / (6 * R - 5 * r * math.sin(theta)))
    return {"T": 2 * math.pi / Om, "Omega": Om, "omega_spin": Om * R / r}


# the catalogue's hard cases and the issue draws of tests/test_ex4_23.py, then the extremes: R/r from 3.8e-5
# to 5e4, nearly upright (theta = 5e-7) and nearly flat (theta = 1.55), unstable slow upright rolling
LISTED = [
    dict(r=0.012, theta=0.3, R=0.1, g=9.81),
    dict(r=0.012, theta=0.3, R=0.00354624, g=9.81),
    dict(r=0.012, theta=1.5, R=0.05, g=9.81),
    dict(r=0.01, theta=math.pi / 4, R=0.01, g=9.81),
    dict(r=0.2, theta=0.3, R=0.05, g=1.62),
    dict(r=0.012, theta=0.05, R=1.0, g=9.81),  # 83 spin turns an orbit: the azimuth's rate fitted
    dict(r=0.012, theta=0.01, R=0.012, g=9.81),  # unstable: the root answers
    dict(r=1.14909, theta=0.0316499, R=0.217731, g=9.54348),
    dict(r=8.20871, theta=1.02145e-05, R=0.000315268, g=0.922707),
    dict(r=0.00111209, theta=0.0679484, R=0.0187511, g=76001.6),
    dict(r=1158.62, theta=0.535458, R=58113.7, g=2.05658),
    dict(r=0.0511812178986281, theta=0.21127493027795055, R=2.5852324979503627, g=58.47283982001544),
    dict(r=5.57175e-07, theta=5.45819e-07, R=0.00862358, g=116.477),
    dict(r=0.01, theta=1.55, R=0.02, g=9.81),
]


def points():
    from mech.students.points import draw

    ex = registry.get("4.23")
    pts = [dict(ex.resolve(p)) for p in LISTED]
    for p in draw(ex, 12, 11):
        try:
            pts.append(dict(ex.resolve(p)))
        except Exception:  # noqa: BLE001  a draw grade would call invalid
            continue
    return pts


@pytest.fixture(scope="module")
def batched():
    ex = registry.get("4.23")
    pts = points()
    P = {k: np.array([p[k] for p in pts]) for k in ("r", "theta", "R", "g")}
    return ex, pts, ex.batched_route.numeric(P, ex.default_rtol, OUTPUTS)


def test_the_batched_route_agrees_with_the_hand_values_within_its_claims(batched):
    ex, pts, got = batched
    assert len(pts) >= 20
    for o in OUTPUTS:
        col = got[o]
        assert not col.mask("failed").any(), [col.reason("failed", k) for k in range(len(pts))]
        rel = np.broadcast_to(col.rel, col.value.shape)
        for k, p in enumerate(pts):
            want = hand(p["r"], p["theta"], p["R"], p["g"])[o]
            assert abs(col.value[k] / want - 1) <= rel[k] + 1e-14, (o, p, col.value[k], want, rel[k])


def test_the_batched_route_is_the_one_point_route_point_by_point(batched):
    """Each variant solved alone (the batch of one: its own step sizes, its own chunk) against the batch."""
    ex, pts, got = batched
    for k, p in enumerate(pts):
        num, run = ex.solve_numeric(ex.resolve(p), ex.default_rtol)
        for o in OUTPUTS:
            mine = float(np.broadcast_to(got[o].rel, got[o].value.shape)[k])
            theirs = run.claims[o][0]
            assert abs(got[o].value[k] / num[o] - 1) <= mine + theirs, (o, p, got[o].value[k], num[o])


def test_the_turn_agrees_with_the_declared_motions_timed_turn(batched):
    """A different timing of the same turn: the declared motion (``motion``: one variant, mech's DOP853 at
    rtol 1e-10, its dense run) with the event of the axis's azimuth passing 2 pi (what the one-point route
    timed before it became the batch of one); the route's T (the azimuth at the root period and its rate
    there) agrees within the route's claim.  Variants that fall (unstable) or turn by a fitted rate are left
    to the other tests."""
    ex, pts, got = batched
    rel = np.broadcast_to(got["T"].rel, got["T"].value.shape)
    checked = 0
    for k, p in enumerate(pts):
        m, path = motion_path(ex, ex.resolve(p), rtol=1e-10)
        if len(m.options["events"]) != 2 or len(path.traj.t_events[1]):
            continue
        times = [t for t in path.traj.t_events[0] if t > 0.5 * m.span[1] / 1.3]
        T = times[0] * m.t_scale
        assert abs(got["T"].value[k] / T - 1) <= rel[k] + 1e-9, (p, got["T"].value[k], T, rel[k])
        checked += 1
    assert checked >= 10


def test_every_variant_is_cross_checked_at_both_tolerances():
    """The chart/grade machinery (run_batched) runs the route at rtol and rtol/10 and judges each point."""
    from mech.studies.sweep import iter_batched_solutions, run_batched

    ex = registry.get("4.23")
    pts = points()[:len(LISTED)]
    P = {k: np.array([p[k] for p in pts]) for k in ("r", "theta", "R", "g")}
    result = run_batched(ex, [], {}, OUTPUTS, points=P)
    assert result.batched.info["verify_rtol"] == pytest.approx(ex.default_rtol / 10)
    for p, sol in zip(pts, iter_batched_solutions(result)):
        assert sol.agree is True, (p, sol)
        for q in sol.quantities:
            assert q.numeric == pytest.approx(hand(p["r"], p["theta"], p["R"], p["g"])[q.name], rel=1e-5)


@pytest.mark.parametrize("rtol", [1e-8, 1e-9])
def test_an_upright_coin_on_a_huge_circle_alone(rtol):
    """Issue 14's draw (theta = 5.5e-7, R/r = 1.5e4: the coin falls within its 20 spin turns, the root
    answers), alone in its chunk: its steps are long (the spin turns once in 84 time units), and the
    quaternion's pull-back at a fixed rate (1 in units r = g = 1) was stiff across them: the step size
    underflowed at rtol/10.  By hand: Omega^2 = 4 g tan(theta)/(6 R - 5 r sin(theta))."""
    ex = registry.get("4.23")
    p = LISTED[12]
    P = {k: np.array([v]) for k, v in p.items()}
    got = ex.batched_route.numeric(P, rtol, OUTPUTS)
    for o in OUTPUTS:
        assert not got[o].mask("failed")[0], got[o].reason("failed", 0)
        assert got[o].value[0] == pytest.approx(hand(**p)[o], rel=1e-8)


def test_one_variant_failing_fails_no_other(monkeypatch):
    """A chunk whose integration fails is followed again variant by variant: only the variant that fails
    alone says so (here a stand-in failure for the variant theta = 0.3, R = 0.1, among 8 of like cost)."""
    import mech.solvers.mechanics.rolling_disk as rd
    from mech.core.errors import NumericFailure

    real = rd.follow_batch
    bad_tilt = math.sin(0.3)
    sizes = []

    def follow_batch(y0, spans, *args, tilt0, **kw):
        sizes.append(len(spans))
        if np.any(np.asarray(tilt0) == bad_tilt):
            raise NumericFailure("a stand-in failure")
        return real(y0, spans, *args, tilt0=tilt0, **kw)

    monkeypatch.setattr(rd, "follow_batch", follow_batch)
    ex = registry.get("4.23")
    pts = [dict(r=0.012, theta=th, R=0.1, g=9.81) for th in (0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9)]
    P = {k: np.array([p[k] for p in pts]) for k in ("r", "theta", "R", "g")}
    got = ex.batched_route.numeric(P, ex.default_rtol, OUTPUTS)
    assert sizes == [8] + [1] * 8  # together, then one by one
    assert list(got["Omega"].mask("failed")) == [k == 1 for k in range(8)]
    assert got["Omega"].reason("failed", 1) == "a stand-in failure"
    for k in (0, 2, 3, 4, 5, 6, 7):
        assert got["Omega"].value[k] == pytest.approx(hand(**pts[k])["Omega"], rel=1e-8)


@pytest.mark.parametrize("torque_sign", [1.0, -1.0])
def test_a_wrong_equation_of_motion_fails_the_batched_variants(monkeypatch, torque_sign):
    """The energy monitor holds the batched runs too.  tests/test_ex4_23.py's 9 x 9 Newton-Euler system with
    the contact force's torque sign-flipped: the coin leaves its tilt at once, the root would answer, and
    only the energy, which the force now changes, fails the variants; with the right sign they pass."""
    import mech.solvers.mechanics.rolling_disk as rd
    from mech.solvers.mechanics.frames import quat_to_matrix
    from test_ex4_23 import _newton_euler_rhs

    rhs = _newton_euler_rhs(torque_sign)

    def tilted_rates(y, I1, I3):
        Y = np.asarray(y, dtype=float).reshape(13, -1)
        F = np.stack([rhs(None, 0.0, Y[:, k]) for k in range(Y.shape[1])], axis=1)
        nz = np.array([quat_to_matrix(Y[3:7, k])[2, 2] for k in range(Y.shape[1])])
        scalar = np.ndim(y[0]) == 0
        return ([float(v[0]) for v in F] if scalar else list(F)), (float(nz[0]) if scalar else nz)

    monkeypatch.setattr(rd, "tilted_rates", tilted_rates)
    ex = registry.get("4.23")
    p = dict(r=0.0511812178986281, theta=0.21127493027795055, R=0.2, g=58.47)
    P = {k: np.array([v, v]) for k, v in p.items()}
    got = ex.batched_route.numeric(P, ex.default_rtol, OUTPUTS)
    failed = got["Omega"].mask("failed")
    if torque_sign > 0:
        assert not failed.any(), got["Omega"].reason("failed", 0)
    else:
        assert failed.all() and "energy" in got["Omega"].reason("failed", 0)


RIGHT = "sqrt(4*g*tan(theta)/(6*R-5*r*sin(theta)))"
WRONG = "2*sqrt(4*g*tan(theta)/(6*R-5*r*sin(theta)))"


def class_file(tmp_path, n=6):
    from conftest import personal_answer

    from mech.students.points import draw

    ex = registry.get("4.23")
    parts = []
    for i, p in enumerate(draw(ex, n, 5)):
        parts.append(personal_answer(f"s{i}", "4.23", p, {"Omega": RIGHT if i % 2 == 0 else WRONG}))
    path = tmp_path / "class.toml"
    path.write_text("\n".join(parts))
    return path


def verdicts(out):
    d = json.loads(out)
    return [(e["student"], [(q["name"], q["expected"]["match"]) for q in e["quantities"] if "expected" in q])
            for e in d["entries"]]


def test_a_class_of_personal_variants_is_graded_through_the_batched_route(tmp_path, monkeypatch):
    from mech.students import classrun

    path = class_file(tmp_path)
    seen = []
    real = classrun._batched_solve

    def spy(firsts, deadline):
        got = real(firsts, deadline)
        seen.append((firsts[0].exercise.id, len(firsts), len(got)))
        return got

    monkeypatch.setattr(classrun, "_batched_solve", spy)
    fast = CliRunner().invoke(cli, ["grade", str(path), "--json", "-j", "1"])
    assert fast.exit_code == 1, fast.stderr
    assert seen == [("4.23", 6, 6)]  # all six variants solved at once, none left to solve alone
    got = verdicts(fast.stdout)
    # by hand: even students wrote Omega, odd ones twice it
    for student, qs in got:
        (name, match), = qs
        assert name == "Omega" and match is (int(student[1:]) % 2 == 0), (student, qs)
    # one by one, the same verdicts
    monkeypatch.setattr(classrun, "MIN_BATCHED", 10**9)
    slow = CliRunner().invoke(cli, ["grade", str(path), "--json", "-j", "1"])
    assert verdicts(slow.stdout) == got
    d = json.loads(fast.stdout)
    for e in d["entries"]:
        q = next(q for q in e["quantities"] if q["name"] == "Omega")
        assert q["analytic"] is not None and q["numeric"] is not None and q["agree"] is True


@pytest.mark.parametrize("over", [dict(g=5e-324), dict(g=1e300), dict(r=1e-300, R=1e-299), dict(r=1e300, R=1e301)])
def test_far_parameters_through_the_batched_route(over):
    """Far from the defaults the one-point analytic solver works in natural units; the batched one takes the
    scale sqrt(g/r) apart (at g = 5e-324, 4 g sin(theta) had lost 3% to the subnormal range and every variant
    disagreed).  By hand: Omega = sqrt(g) sqrt(4 tan(theta)/(6 R - 5 r sin(theta))), the root of g apart."""
    from mech.studies.sweep import iter_batched_solutions, run_batched

    ex = registry.get("4.23")
    p = dict(ex.resolve({}))
    p.update(over)
    p = dict(ex.resolve(p))
    Om = math.sqrt(p["g"]) * math.sqrt(4 * math.tan(p["theta"]) / (6 * p["R"] - 5 * p["r"] * math.sin(p["theta"])))
    P = {k: np.array([p[k]]) for k in ("r", "theta", "R", "g")}
    assert ex.batched_route.analytic(P)["Omega"].value[0] == pytest.approx(Om, rel=1e-14)
    sol = next(iter_batched_solutions(run_batched(ex, [], {}, OUTPUTS, points=P)))
    assert sol.agree is True, sol
    q = next(q for q in sol.quantities if q.name == "Omega")
    assert q.numeric == pytest.approx(Om, rel=1e-8)
