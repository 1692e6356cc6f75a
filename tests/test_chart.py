"""Charts: the batched integrator, the batched routes (5.11, 5.12, 5.13) and `mech sweep`'s batched path.

Independent references: closed forms (harmonic oscillators), scipy's Radau over
the full period of the undamped-substitution-free equation, and the exercises'
own one-point cross-check.
"""

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

from mech.cli.main import cli
from mech.problems import registry
from mech.problems import validity
from mech.problems.spec import NumericFailure
from mech.solvers.numerics.batch import integrate_batch
from mech.verification.crosscheck import cross_check
from mech.solvers.mechanics.floquet import even_hill_half
from mech.studies.sweep import Axis, batched_points, grid_points, run_batched

BATCHED = [ex_id for ex_id, ex in registry.all_exercises().items() if ex.batched_route is not None]


def run(*args):
    result = CliRunner().invoke(cli, list(args))
    return result.exit_code, result.stdout, result.stderr


# -- the integrator ---------------------------------------------------------------------------------

@pytest.mark.parametrize("rtol", [1e-8, 1e-12])
def test_batch_meets_every_points_tolerance(rtol):
    """y'' = -k y, y(0) = 1, y'(0) = 0: y(t) = cos(sqrt(k) t).  k spans 1e-2..1e2 (0.016 to 16 turns),
    so the step is set by the fastest point; every point, slow or fast, must be within ~rtol."""
    k = np.geomspace(1e-2, 1e2, 50)
    w = np.sqrt(k)
    y0 = np.vstack([np.ones_like(k), np.zeros_like(k)])
    res = integrate_batch(lambda t, y: np.vstack([y[1], -k * y[0]]), (0.0, 2 * math.pi), y0, rtol=rtol,
                          atol=[rtol * 1e-3, rtol * 1e-3])
    err = np.abs(res.y_end[0] - np.cos(w * 2 * math.pi))
    assert err.max() < 200 * rtol
    assert (res.err_max < 1.0).all() and res.steps > 0


def test_batch_zero_span_and_budget():
    y0 = np.ones((2, 3))
    res = integrate_batch(lambda t, y: y, (1.0, 1.0), y0, rtol=1e-8, atol=1e-12)
    assert res.steps == 0 and np.array_equal(res.y_end, y0)
    with pytest.raises(NumericFailure):
        integrate_batch(lambda t, y: y, (0.0, 1.0), y0, rtol=1e-8, atol=1e-12, max_steps=2)


def test_hill_half_over_variants_matches_closed_form():
    """c0 + c1 wave = c constant (even, any period): y1 = cos(sqrt(c) t), y2 = sin(sqrt(c) t)/sqrt(c); three
    variants together, and each alone (``ode.integrate``)."""
    c = np.array([0.2, 1.0, 3.7])
    (y1, y1p, y2, y2p), _ = even_hill_half(c - 0.5, 0.5, lambda t: 1.0, 1.3, rtol=1e-12, vscale=np.sqrt(c))
    for k in range(3):
        one, _ = even_hill_half(c[k] + 0.25, -0.25, lambda t: 1.0, 1.3, rtol=1e-12, vscale=np.sqrt(c[k]))
        assert [v[0] for v in one] == pytest.approx([y1[k], y1p[k], y2[k], y2p[k]], abs=1e-10)
    w = np.sqrt(c)
    assert y1 == pytest.approx(np.cos(w * 1.3), abs=1e-10)
    assert y1p == pytest.approx(-w * np.sin(w * 1.3), abs=1e-10)
    assert y2 == pytest.approx(np.sin(w * 1.3) / w, abs=1e-10)
    assert y2p == pytest.approx(np.cos(w * 1.3), abs=1e-10)


# -- the batched routes against independent references -----------------------------------------------

def _radau_monodromies(damp, stiffs, T):
    """Monodromies of q'' + damp q' + stiff(t) q = 0 over [0, T], one for each stiffness of ``stiffs``, by
    scipy's Radau (a different method), all of them in one call: Radau's steps (about 1600 a period here)
    are the cost, and equations of one period share them.  Each system alone gives traces within 1e-14 of
    the joint call's (5.13's three points, checked)."""
    from scipy.integrate import solve_ivp

    def f(t, y):
        out = np.empty_like(y)
        for j, stiff in enumerate(stiffs):
            k, q = stiff(t), y[4 * j:4 * j + 4]
            out[4 * j:4 * j + 4] = (q[1], -damp * q[1] - k * q[0], q[3], -damp * q[3] - k * q[2])
        return out

    sol = solve_ivp(f, (0, T), [1.0, 0.0, 0.0, 1.0] * len(stiffs), method="Radau", rtol=1e-12, atol=1e-14)
    y = sol.y[:, -1]
    return [np.array([[y[4 * j], y[4 * j + 2]], [y[4 * j + 1], y[4 * j + 3]]]) for j in range(len(stiffs))]


def _radau_monodromy(damp, stiff, T):
    return _radau_monodromies(damp, [stiff], T)[0]


def test_5_11_growth_against_radau_over_the_full_period():
    pytest.importorskip("scipy")
    ex = registry.get("5.11")
    pts = [(10.0, 0.05, 0.05, 10.05), (10.0, 0.0, 0.3, 9.2), (10.0, 0.2, 0.6, 10.4), (3.0, 0.01, 0.2, 3.1)]
    P = {k: np.array([p[i] for p in pts]) for i, k in enumerate(("omega0", "delta", "mu", "omega"))}
    got = ex.batched_route.numeric(P, 1e-12, ("growth",))["growth"].value
    for (w0, d, mu, w), g in zip(pts, got):
        T = math.pi / w
        M = _radau_monodromy(2 * d, lambda t: w0**2 * (1 + mu * math.cos(2 * w * t)), T)
        ref = math.log(max(abs(np.linalg.eigvals(M)))) / T
        assert g == pytest.approx(ref, abs=1e-8 * w0)


def test_5_12_growth_against_radau_over_the_full_period():
    pytest.importorskip("scipy")
    ex = registry.get("5.12")
    pts = [(0.5, 9.81, 0.05, 0.008, 8.9), (0.5, 9.81, 0.05, 0.0125, 8.7), (1.0, 9.81, 0.3, 0.05, 6.5)]
    P = {k: np.array([p[i] for p in pts]) for i, k in enumerate(("l", "g", "delta", "a", "Omega"))}
    got = ex.batched_route.numeric(P, 1e-11, ("growth",))["growth"].value
    for (l, g, d, a, W), val in zip(pts, got):
        T = 2 * math.pi / W
        M = _radau_monodromy(2 * d, lambda t: (g - a * W * W * math.cos(W * t)) / l, T)
        ref = math.log(max(abs(np.linalg.eigvals(M)))) / T
        assert val == pytest.approx(ref, abs=1e-8)


def test_5_13_slow_frequencies_against_radau():
    """cos(nu T) = tr M / 2 over one fast period T = 2 pi/Omega (stable: |tr M| < 2); unstable -> undefined."""
    pytest.importorskip("scipy")
    ex = registry.get("5.13")
    pts = [(0.2, 9.81, 0.01, 628.3185307179587), (0.2, 9.81, 0.002, 628.3185307179587), (0.2, 9.81, 0.065, 45.0)]
    P = {k: np.array([p[i] for p in pts]) for i, k in enumerate(("l", "g", "a", "Omega"))}
    out = ex.batched_route.numeric(P, 1e-12, ("omega_inv", "omega_down"))
    for j, (l, g, a, W) in enumerate(pts):
        T = 2 * math.pi / W
        signs = (("omega_down", 1.0), ("omega_inv", -1.0))
        both = _radau_monodromies(0.0, [lambda t, s=sign: s * (g - a * W * W * math.cos(W * t)) / l
                                        for _, sign in signs], T)
        for (name, sign), M in zip(signs, both):
            tr = np.trace(M)
            col = out[name]
            if abs(tr) < 2:
                assert col.value[j] == pytest.approx(math.acos(tr / 2) / T, rel=1e-6)
            else:
                assert col.mask("undefined")[j]
    assert out["omega_inv"].mask("undefined")[1] and not out["omega_inv"].mask("undefined")[0]


@pytest.mark.parametrize("ex_id", BATCHED)
def test_vectorised_analytic_is_the_exercises_own(ex_id):
    """The array hooks over N variants give, point by point, what the one-point solve gives (natural units and all)."""
    ex = registry.get(ex_id)
    rng = np.random.default_rng(7)
    base = {p.name: p.default for p in ex.params}
    pts = []
    while len(pts) < 60:
        v = dict(base)
        for p in ex.params:
            v[p.name] = p.default * rng.uniform(0.8, 1.25) if p.default else rng.uniform(0, 0.1)
        if ex_id == "5.11":
            v["mu"] = rng.uniform(0, 0.9)
            v["delta"] = rng.choice([0.0, rng.uniform(0, 0.5)])
        try:
            pts.append(ex.resolve(v))
        except Exception:
            continue
    P = {p.name: np.array([q[p.name] for q in pts]) for p in ex.params}
    ana = ex.batched_route.analytic(P)
    exp = ex.batched_route.expected_error(P)
    for j, q in enumerate(pts):
        a = ex.solve_analytic(q)
        e = validity.expected_errors(ex, q)
        for name, col in ana.items():
            if isinstance(a[name], float):
                assert not col.mask("undefined")[j]
                assert col.value[j] == pytest.approx(a[name], rel=1e-14, abs=1e-300)
            else:
                assert col.mask("undefined")[j]
        for name in ex.batched_route.outputs:
            # (relative, absolute) where the leading-order value can be zero; None and absent are NaN
            want = e.get(name)
            want = want if isinstance(want, tuple) else (want, None)
            e_name = exp.get(name, np.full(len(pts), np.nan))  # none given: NaN at every point
            got = e_name if isinstance(e_name, tuple) else (e_name, np.full(len(pts), np.nan))
            for w, g in zip(want, got):
                if w is None:
                    assert np.isnan(g[j]), (name, dict(q))
                else:
                    assert g[j] == pytest.approx(w, rel=1e-12), (name, dict(q))


@pytest.mark.parametrize("ex_id, axes, fixed", [
    ("5.11", [Axis("omega", (9.0, 9.9, 10.0, 10.05, 11.0)), Axis("mu", (0.0, 0.02, 0.1, 0.6))], {}),
    ("5.11", [Axis("omega", (9.5, 10.0, 10.5)), Axis("mu", (0.01, 0.3))], {"delta": 0.0}),
    # zones 5e-8 omega0 wide (issue 14): det(M + I) ~ 1e-14 must be resolved by both routes alike
    ("5.11", [Axis("omega", (410386.0, 474653.0)), Axis("mu", (1.97581e-07, 3e-7))],
     {"omega0": 410386.0, "delta": 0.000669337}),
    ("5.12", [Axis("Omega", (8.0, 8.7, 8.9, 9.5)), Axis("a", (0.0, 0.004, 0.0125, 0.05))], {}),
    ("5.13", [Axis("a", (0.002, 0.003157417119830505, 0.01, 0.05)), Axis("Omega", (100.0, 628.3, 2000.0))], {}),
])
def test_batched_points_match_single_cross_checks(ex_id, axes, fixed):
    """Each point's value within its error bar of `mech solve`'s, and the same verdict."""
    ex = registry.get(ex_id)
    outs = ex.batched_route.outputs
    res = run_batched(ex, axes, fixed, outs, chunk=5)
    pts = batched_points(res)
    grid = grid_points(axes, fixed)
    assert len(pts) == len(grid)
    for pt, values in zip(pts, grid):
        single = cross_check(ex, ex.resolve(values)).as_json()
        assert pt["params"] == single["params"]
        for q in pt["quantities"]:
            s = next(x for x in single["quantities"] if x["name"] == q["name"])
            assert q["agree"] == s["agree"], (values, q, s)
            if s["numeric"] is None:
                assert q["numeric"] is None
            else:
                assert abs(q["numeric"] - s["numeric"]) <= q["numeric_err"], (values, q, s)
            assert q["analytic"] == s["analytic"]


# -- the command ------------------------------------------------------------------------------------

def test_only_and_batched_json():
    code, out, err = run("sweep", "5.11", "--omega", "9.8:10.2:3", "--mu", "0.01:0.1:2", "--only", "growth", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert d["route"] == "batched" and d["outputs"] == ["growth"] and d["agree"] is True
    assert len(d["points"]) == 6
    for pt in d["points"]:
        assert [q["name"] for q in pt["quantities"]] == ["growth"]
        q = pt["quantities"][0]
        assert q["numeric_err"] > 0 and q["verify_diff"] <= q["numeric_err"]
    # first axis slowest
    assert [(p["params"]["omega"], p["params"]["mu"]) for p in d["points"]][:3] == [(9.8, 0.01), (9.8, 0.1),
                                                                                    (10.0, 0.01)]


def test_only_on_the_point_by_point_route():
    # 4.14 (closed forms, no batched route; 4.15 has one now)
    code, out, err = run("sweep", "4.14", "--R", "0.5:1:2", "--only", "omega_rolling", "--json", "--no-verify")
    assert code == 0, err
    d = json.loads(out)
    assert "route" not in d
    assert [[q["name"] for q in p["quantities"]] for p in d["points"]] == [["omega_rolling"], ["omega_rolling"]]


def test_only_unknown_output_is_exit_2():
    code, out, err = run("sweep", "5.11", "--omega", "9:11:3", "--only", "growth,nope")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "'nope'" in err and "growth" in err


def test_a_failing_route_fails_every_point_loudly(monkeypatch):
    import dataclasses

    ex = registry.get("5.11")

    def broken(P, rtol, outputs):
        raise NumericFailure("step size underflow (test)")

    monkeypatch.setattr(ex, "batched_route", dataclasses.replace(ex.batched_route, numeric=broken))
    code, out, err = run("sweep", "5.11", "--omega", "9.8:10.2:2", "--mu", "0.01:0.1:2", "--only", "growth", "--json")
    assert code == 1
    d = json.loads(out)
    assert d["agree"] is False
    for pt in d["points"]:
        assert pt["agree"] is False and pt["quantities"][0]["numeric"] is None
        assert "step size underflow (test)" in pt["errors"][0]


def test_the_constraint_is_checked_at_every_point_of_a_batched_grid():
    # omega = 14 rad/s is 0.4 omega0 from omega0 = 10: the joint limit |omega - omega0| <= 0.3 omega0 refuses
    # those two points (marked, not solved), the rest is swept (issue 41)
    code, out, err = run("sweep", "5.11", "--omega", "7:14:8", "--mu", "0.1:0.2:2", "--only", "growth", "--json")
    assert code == 0 and err == ""
    d = json.loads(out)
    refused = [p["params"]["omega"] for p in d["points"] if "too far from omega0" in p.get("refused", "")]
    assert refused == [14.0, 14.0]
    assert all(p["agree"] is True for p in d["points"] if p["params"]["omega"] < 14)


def test_chunks_do_not_change_the_verdicts():
    ex = registry.get("5.11")
    axes = [Axis("omega", tuple(np.linspace(9.5, 10.5, 6))), Axis("mu", (0.02, 0.2))]  # not on the threshold
    a = batched_points(run_batched(ex, axes, {}, ("growth",), chunk=3))
    b = batched_points(run_batched(ex, axes, {}, ("growth",)))
    for pa, pb in zip(a, b):
        qa, qb = pa["quantities"][0], pb["quantities"][0]
        assert qa["agree"] is qb["agree"] and qa.get("theory_valid") == qb.get("theory_valid")
        # agreement, or (near the zone's edge, where the next order is large) the theory outside its range
        assert qa["agree"] is True or (qa["theory_valid"] is False and qa["agree"] is None)
        assert abs(qa["numeric"] - qb["numeric"]) <= qa["numeric_err"]


def test_map_plot(tmp_path):
    pytest.importorskip("matplotlib")
    f = tmp_path / "m.png"
    code, out, err = run("sweep", "5.13", "--a", "1mm:20mm:6", "--Omega", "300:1000:5", "--only", "omega_inv",
                         "--plot", str(f))
    assert code in (0, 1), err
    assert f.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_ctrl_c_ends_with_one_line_and_130(monkeypatch):
    """The second chunk is interrupted: exit 130, one line on stderr saying how far it got, nothing on stdout."""
    import dataclasses

    import mech.studies.sweep as sweep

    ex = registry.get("5.11")
    calls = []
    real = ex.batched_route.numeric

    def interrupted(P, rtol, outputs):
        calls.append(1)
        if len(calls) > 2:  # the first chunk's solve and rerun, then Ctrl-C
            raise KeyboardInterrupt
        return real(P, rtol, outputs)

    monkeypatch.setattr(ex, "batched_route", dataclasses.replace(ex.batched_route, numeric=interrupted))
    monkeypatch.setattr(sweep, "CHUNK", 4)
    monkeypatch.setattr(sweep._run_batched, "__kwdefaults__", {**sweep._run_batched.__kwdefaults__, "chunk": 4})
    code, out, err = run("sweep", "5.11", "--omega", "9.8:10.2:3", "--mu", "0.01:0.1:3", "--only", "growth")
    assert code == 130 and out == ""
    assert err == "mech: interrupted after 4 of 9 points; nothing written\n"


def test_illinois_finds_every_root():
    """x^3 = k for k over 1e-3..1e3 (roots k^(1/3)), and cos x = 0 on [1, 2] (pi/2): each to its tolerance."""
    from mech.solvers.numerics.batch import illinois

    k = np.geomspace(1e-3, 1e3, 40)
    a, b = np.zeros_like(k), np.full_like(k, 11.0)
    x, ok = illinois(lambda x, i: x**3 - k[i], a, b, -k, 11.0**3 - k, xtol=1e-15, rtol=1e-13)
    assert ok.all()
    assert x == pytest.approx(np.cbrt(k), rel=1e-12)
    x, ok = illinois(lambda x, i: np.cos(x), np.array([1.0]), np.array([2.0]), np.cos([1.0]), np.cos([2.0]),
                     xtol=1e-15, rtol=1e-14)
    assert ok.all() and x[0] == pytest.approx(math.pi / 2, abs=1e-14)


# the catalogue's hard cases through the batched route, all in one batch: tests/test_check_all.py (each
# within its error bar of the case's cross-check, which that test computes anyway)


def test_map_marks_failed_points_with_their_reason(monkeypatch):
    """Points the route fails are crossed and counted in the legend, with the reason's words; the boundary
    the exercise declares is drawn; the colour bar carries the unit."""
    pytest.importorskip("matplotlib")
    import dataclasses

    from mech.figures.sweepfig import sweep_figure
    from mech.solvers.numerics.batch import Column

    ex = registry.get("5.11")
    real = ex.batched_route.numeric

    def half_broken(P, rtol, outputs, memo=None):
        got = real(P, rtol, outputs, memo=memo)
        col = got["growth"]
        bad = np.asarray(P["omega"]) > 10.1
        got["growth"] = Column(np.where(bad, np.nan, col.value), rel=col.rel, abs=col.abs,
                               failed=col.failed + [(bad, "step size underflow at t = 0.3 (test)")])
        return got

    monkeypatch.setattr(ex, "batched_route", dataclasses.replace(ex.batched_route, numeric=half_broken))
    axes = [Axis("omega", (9.8, 10.0, 10.2, 10.4)), Axis("mu", (0.02, 0.06, 0.1))]
    res = run_batched(ex, axes, {}, ("growth",))
    res.fixed = {"omega0": 10.0, "delta": 0.05}
    assert res.n_failed == 6 and res.agree is False
    fig = sweep_figure(res)
    ax = fig.axes[0]
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(t.startswith("FAILED (6 points)") and "step size underflow at t" in t for t in texts), texts
    assert any("μ_th" in t for t in texts)
    assert "growth (numeric) [1/s]" in fig.axes[1].get_ylabel()
