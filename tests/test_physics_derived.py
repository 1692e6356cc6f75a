"""The symbolic route: every declared exercise's equations of motion, derived by sympy.physics.mechanics
from its declared physics (problems/chN/physicsN_M.py), against the module's hand-written right-hand side.

For each exercise with a declaration: parameter sets drawn inside the bounds and the joint constraints
(``students.points.draw``, seeded) and the defaults; at each, states drawn around the motion's start
(``physics.draw_states``); the derived rates evaluated in mpmath at 40 digits (the mass matrix solved
there), the hand-written ones in floats through the motion's maps to SI (``Motion.integrated``,
``Motion.states_rate``); block by block (rows sharing a unit), the worst difference against the block's
size (its largest derived rate, floored at its states' sizes over the motion's time scale).  The event
function (``Motion.event_scale``) and the hand-written Jacobians (5.4, 5.9, 5.12) are compared the same way.

TOL: the hand-written side is evaluated in floats; the worst measured over these draws was 2e-15 of a
block's size, 2.4e-14 for 5.7 next to its barrier top, where the map from q to the distance s from the top
rounds (1e-16 of x_b against s ~ 5e-4), 2.1e-14 for 4.23 near the flat disk and 6.1e-13 for 4.34, whose
non-affine ``to_states`` is differentiated numerically (Richardson, ~1e-13) (``pytest
tests/test_physics_derived.py -s`` prints each exercise's worst).  1e-11 leaves room
for the conditioning of a few terms and fails on any error in a term that matters to 1e-11 of the rates.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

sympy = pytest.importorskip("sympy")

from mech.problems import physics, registry  # noqa: E402
from mech.problems.spec import Run  # noqa: E402
from mech.students.points import draw  # noqa: E402

TOL = 1e-11
N_PARAMS = 4  # drawn parameter sets, beside the defaults
N_STATES = 4  # states per parameter set

INTEGRATING = [e.id for e in registry.index() if e.integrates]
DECLARED = [i for i in INTEGRATING if physics.why_not(registry.get(i)) is None]
# the reduced or averaged models no Lagrangian gives; they say so
WITHHELD = {"4.24", "4.25"}
# what this branch declares; the count the issue asks for is 23 of the 25 integrating exercises
MUST_DECLARE = {"4.7", "4.8", "4.9", "4.10", "4.15", "4.18", "4.19", "4.20", "4.21", "4.23", "4.29", "4.30",
                "4.31", "4.33", "4.34", "5.2", "5.4", "5.5", "5.6", "5.7", "5.9", "5.10", "5.12"}
# parameter sets compared beside the defaults and the draws, so that every branch of a module's motion is
# (the draws may miss one)
BRANCHES = {
    "5.6": [{"theta0": 2.5}, {"theta0": 3.14}],  # above 90 degrees: the deviation from upright
    "5.4": [{"zeta": 1.0}, {"zeta": 40.0}],  # critical damping; far above it, the exact flow's generator
    "5.7": [{"alpha": 6.0}, {"alpha": -3.6, "A": 1.0}, {"alpha": -3.996, "A": 1.0}],  # stiff; near the barrier
    "5.9": [{"mu": 12.0}, {"mu": 12.3}, {"mu": 3000.0}],  # both sides of mu/omega0 = 4; the slow time
}


def test_declared_cover_what_they_must():
    assert MUST_DECLARE <= set(DECLARED), sorted(MUST_DECLARE - set(DECLARED))
    for ex_id in WITHHELD:
        why = physics.why_not(registry.get(ex_id))
        assert why and "reduced model" in why


def compared_motion(ex, p):
    """The motion the declared states describe at ``p``: the declared motion, or, where that is a lead-in
    leg not shown (4.8's strike), the first shown leg after it (the chain followed at the exercise's
    default accuracy); None where the exercise has no motion at ``p``."""
    m = ex.motion_at(p)
    if m is None or m.shown:
        return m
    path = Run(rtol=ex.default_rtol).follow(m, mark=False)
    for leg in path.legs:
        if leg.motion is not None and leg.motion.shown:
            return leg.motion
    return None


def _cases(ex, seed: int):
    ps = [ex.resolve({})] + [ex.resolve(b) for b in BRANCHES.get(ex.id, [])] + draw(ex, N_PARAMS, seed)
    rng = np.random.default_rng(seed)
    for p in ps:
        motion = compared_motion(ex, p)
        if motion is None:  # no motion at these parameters (4.21 without a steady precession; 5.5 past
                            # delta = 0.9 omega0): nothing to compare
            continue
        for t, q, u in physics.draw_states(ex.derive(), p, motion, rng, N_STATES):
            yield p, motion, t, q, u


def worst_over_draws(ex, motion_of=None, seed: int = 7):
    """The worst relative error over the draws, and where."""
    der = ex.derive()
    worst, where = 0.0, None
    n = 0
    for p, motion, t, q, u in _cases(ex, seed):
        n += 1
        if motion_of is not None:
            motion = motion_of(p)
        jac = der.d.jacobian_fn(p) if der.d.jacobian_fn is not None else None
        cmp = physics.compare(der, p, motion, t, q, u, jac=jac)
        if cmp.worst() > worst or where is None:
            worst, where = cmp.worst(), (dict(p), cmp)
    assert n >= N_STATES * 3, f"{ex.id}: only {n} states compared"
    return worst, where


@pytest.mark.parametrize("ex_id", DECLARED)
def test_derived_equations_match_the_hand_written_ones(ex_id):
    ex = registry.get(ex_id)
    worst, (p, cmp) = worst_over_draws(ex)
    print(f"{ex_id}: worst {worst:.2e}")
    assert worst <= TOL, f"{ex_id} at {p}, t = {cmp.t}: blocks {cmp.blocks}, event {cmp.event}, jac {cmp.jacobian}"


@pytest.mark.parametrize("ex_id", DECLARED)
def test_declared_inverse_maps_the_start_back(ex_id):
    """The declaration's inverse, then its states, give the motion's start back (a quaternion up to its sign)."""
    ex = registry.get(ex_id)
    der = ex.derive()
    if der.d.inverse_fn is None:
        pytest.skip("the states are the coordinates and their rates")
    for p in [ex.resolve({})] + draw(ex, 2, 3):
        motion = compared_motion(ex, p)
        if motion is None:
            continue
        x0 = np.asarray(motion.start, float)
        q, u = der.independent_of(p, x0)
        x, _, _ = der.evaluate(p, motion.t_offset, q, u)
        x = np.array([float(v) for v in x])
        sizes = np.asarray(physics.state_sizes(motion))
        units = [unit for _, unit in ex.states]
        for unit in dict.fromkeys(units):
            rows = [i for i, un in enumerate(units) if un == unit]
            scale = max(np.max(np.abs(x0[rows])), np.max(sizes[rows]))
            err = min(np.max(np.abs(x[rows] - x0[rows])), np.max(np.abs(x[rows] + x0[rows])))
            assert err <= 1e-12 * scale, (ex_id, unit, x[rows], x0[rows])


def _planted_copy(module, old: str, new: str):
    """A copy of an exercise module with ``old`` (found exactly once in its source) replaced by ``new``."""
    import importlib.util
    import inspect

    src = inspect.getsource(module)
    assert src.count(old) == 1, old
    spec = importlib.util.spec_from_loader(module.__name__ + "_planted", loader=None)
    copy = importlib.util.module_from_spec(spec)
    exec(compile(src.replace(old, new), module.__file__ + " (planted)", "exec"), copy.__dict__)
    return copy


def test_a_planted_sign_error_is_caught():
    """One sign in one term of a copy of 4.15's right-hand side (the centripetal part of the floor's force)
    fails the comparison by far; the copy unplanted passes it (so the failure is the sign's)."""
    from mech.problems.ch4 import ex4_15_sliding_ladder as module

    ex = registry.get("4.15")
    old = "b2 = M * g - M * l / 2 * s * omega**2"
    same = _planted_copy(module, old, old)
    worst, _ = worst_over_draws(ex, motion_of=same.motion)
    assert worst <= TOL
    planted = _planted_copy(module, old, "b2 = M * g + M * l / 2 * s * omega**2")
    worst, _ = worst_over_draws(ex, motion_of=planted.motion)
    assert worst > 1e-3


def test_a_planted_jacobian_error_is_caught():
    """One sign in 5.12's hand-written Jacobian (the damping entry) fails the Jacobian's comparison."""
    ex = registry.get("5.12")
    der = ex.derive()
    p = ex.resolve({})
    motion = ex.motion_at(p)
    t, q, u = physics.draw_states(der, p, motion, np.random.default_rng(1), 1)[0]
    good = der.d.jacobian_fn(p)

    def bad(t, y):
        J = np.array(good(t, y), float)
        J[1, 1] = -J[1, 1]
        return J

    assert physics.compare(der, p, motion, t, q, u, jac=good).jacobian <= TOL
    assert physics.compare(der, p, motion, t, q, u, jac=bad).jacobian > 1e-3


# chapter 5's motions in legs: every leg after the first (a different right-hand side after 5.2's pulse)
CHAINED = ["5.2", "5.4", "5.9"]


@pytest.mark.parametrize("ex_id", CHAINED)
def test_every_leg_of_a_motion_in_legs(ex_id):
    """The legs after the first, reached by following the chain at the exercise's default rtol, compared as
    the first is (states drawn around each leg's start, times over its span)."""
    from mech.problems.spec import Run

    ex = registry.get(ex_id)
    der = ex.derive()
    rng = np.random.default_rng(11)
    worst, legs = 0.0, 0
    for p in [ex.resolve({})] + [ex.resolve(b) for b in BRANCHES.get(ex_id, [])] + draw(ex, 2, 11):
        first = ex.motion_at(p)
        if first is None or first.then is None:
            continue
        path = Run(rtol=ex.default_rtol).follow(first, mark=False)
        jac = der.d.jacobian_fn(p) if der.d.jacobian_fn is not None else None
        for leg in path.legs[1:]:
            legs += 1
            for t, q, u in physics.draw_states(der, p, leg.motion, rng, 2):
                worst = max(worst, physics.compare(der, p, leg.motion, t, q, u, jac=jac).worst())
    print(f"{ex_id}: {legs} legs, worst {worst:.2e}")
    assert legs > 0 and worst <= TOL


def test_5_2_exact_flows_match_the_derived_equations():
    """5.2 carries a pulse longer than one free period, and x at t1 after it, by the exact flow of its linear
    equations (a matrix exponential, no ODE stepped): their generators, in (x, x', 1) during the pulse and
    (x, x') after it, as right-hand sides of the pulse leg's variables (the constant row left out), against
    the derived equations over the pulse and after it."""
    from mech.problems.ch5.ex5_2_force_pulse import _FREE_GENERATOR, _PULSE_GENERATOR

    ex = registry.get("5.2")
    der = ex.derive()
    rng = np.random.default_rng(13)
    worst = 0.0
    for p in [ex.resolve({})] + draw(ex, N_PARAMS, 13):
        pulse = ex.motion_at(p)
        flows = [pulse.starting(y0=[0.0, 0.0, 1.0], rhs=lambda t, y: _PULSE_GENERATOR @ y,
                                to_states=lambda y: y[:2], idle_rows=(2,), y_size=list(pulse.y_size) + [1.0], then=None),
                 pulse.starting(span=(p.omega0 * p.T, p.omega0 * p.T + 10.0), rhs=lambda t, y: _FREE_GENERATOR @ y,
                                then=None)]
        for flow in flows:
            for t, q, u in physics.draw_states(der, p, flow, rng, N_STATES):
                worst = max(worst, physics.compare(der, p, flow, t, q, u).worst())
    print(f"5.2 exact flows: worst {worst:.2e}")
    assert worst <= TOL


def test_5_7_clock_and_deviation_match_the_derived_equations():
    """5.7's route integrates x = q/A (s = S omega0 t) in two maps that move with the time.  The clock: the
    polar angle psi of (x, u), u = -dx/ds, as the independent variable, state (y = 1 - x, u, E = s - psi), so
    dy/dpsi = u ds/dpsi, du/dpsi = -x'' ds/dpsi with ds/dpsi = (x^2 + u^2)/(-x x'' + u^2), and dE/dpsi =
    ds/dpsi - 1.  The deviation: theta = ws s, x = cos theta + z, so z'' = x''/ws^2 + cos theta in theta.
    x'' from the derived equation (in SI, over (S omega0)^2 A); any ws will do."""
    import mpmath

    from mech.problems.ch5.ex5_7_duffing_free import _clock_rhs, _coefficients, _harmonic_rhs

    ex = registry.get("5.7")
    der = ex.derive()
    rng = np.random.default_rng(17)
    worst = 0.0
    for p in [ex.resolve({}), ex.resolve({"alpha": 6.0}), ex.resolve({"alpha": -15.0, "A": 0.5})] + \
            draw(ex, N_PARAMS, 17):
        P = {k: np.array([float(v)]) for k, v in dict(p).items()}
        eps, g, S, k_, b, barrier = (np.asarray(c) for c in _coefficients(P))
        clock = _clock_rhs(eps[0], k_[0], b[0], bool(eps[0] >= 0.5))
        ws = 1.0 + 0.1 * rng.standard_normal()
        a = 1.0 / float(S[0]) ** 2
        deviation = _harmonic_rhs(b[0], ws, ws * ws - a)
        kk = mpmath.mpf(float(S[0])) * mpmath.mpf(p.omega0)  # ds/dt

        def xdd(x, v):  # x'' in s from the derived equation, at x and dx/ds = v
            with mpmath.workdps(40):
                _, xd, _ = der.evaluate(p, 0.0, [float(x * p.A)], [float(v * kk * p.A)])
                return xd[1] / (kk * kk * mpmath.mpf(p.A))

        for _ in range(N_STATES):
            y, u = rng.uniform(0.0, 1.0), 0.5 * rng.standard_normal()
            with mpmath.workdps(40):
                x = 1 - mpmath.mpf(y)
                acc = xdd(x, -u)
                ds = (x * x + mpmath.mpf(u) ** 2) / (-x * acc + mpmath.mpf(u) ** 2)
                want = [mpmath.mpf(u) * ds, -acc * ds, ds - 1]
            got = clock(0.3, np.array([y, u, 0.0]))
            worst = max(worst, max(abs(gv - float(w)) / max(abs(float(w)), 1.0) for gv, w in zip(got, want)))
            if eps[0] > -0.5:
                th, z, dz = rng.uniform(0.0, 1.5), 0.3 * rng.standard_normal(), 0.3 * rng.standard_normal()
                with mpmath.workdps(40):
                    x = mpmath.cos(th) + z
                    v = ws * (-mpmath.sin(th) + dz)  # dx/ds
                    want = xdd(x, v) / mpmath.mpf(ws) ** 2 + mpmath.cos(th)
                got = deviation(th, np.array([z, dz, 0.0]))[1]
                worst = max(worst, abs(got - float(want)) / max(abs(float(want)), 1.0))
    print(f"5.7 clock and deviation: worst {worst:.2e}")
    assert worst <= TOL


@pytest.mark.skip(reason="5.10's one-period orbit maps (the edges of the locking range) integrate force "
                         "functions written inside its numeric route (closures no test reaches), and below "
                         "mu/omega0 = 5e-3 in the frame turning with the drive, a map that moves with the time; "
                         "its declared motion, the driven oscillator the beat is read from, is compared")
def test_5_10_orbit_maps_match_the_derived_equations():
    """Not compared (see the skip's reason); the declaration (physics5_10.py) says so too."""


def test_5_5_amplitude_phase_flows_match_the_derived_equations():
    """5.5's ringdown in amplitude and phase (x = r cos th, x' = -r sin th in tau = omega0 t, l = ln(r^2)/zeta
    from r = 1, zeta = delta/omega0), in time and with th as the clock (T and l against th), against the
    derived equation through that map, by the chain rule: th' = (v x' - x v')/r^2 and
    (ln r^2)' = 2 (x x' + v v')/r^2, with x' = v and v' the derived rate; in time, and divided by th' with
    th as the clock.  Each rate against its size (th' and dl/dth are of order 1, l' of order 4)."""
    import math

    import mpmath

    from mech.problems.ch5.ex5_5_q_factor import _half_cycle, _polar_in_time

    ex = registry.get("5.5")
    der = ex.derive()
    rng = np.random.default_rng(5)
    worst = 0.0
    for p in [ex.resolve({}), ex.resolve({"delta": 0.9 * 2764.0})] + draw(ex, N_PARAMS, 5):
        z = p.delta / p.omega0
        in_time = _polar_in_time(z, 1.0)  # against s = t/tau: with tau = 1, in time
        by_phase = _half_cycle(z, (p.omega0 - p.delta) / p.omega0)
        for _ in range(N_STATES):
            # the SI state (x, x_t) exactly as the derived side takes it; (th, l) of it for the module
            x, v_si = rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0) * p.omega0
            th = math.atan2(-v_si / p.omega0, x)
            lv = math.log(x * x + (v_si / p.omega0) ** 2) / z
            _, xd, _ = der.evaluate(p, 0.0, [x], [v_si])
            with mpmath.workdps(40):
                x_, v_ = mpmath.mpf(x), mpmath.mpf(v_si) / mpmath.mpf(p.omega0)
                w0 = mpmath.mpf(p.omega0)
                dx, dv = xd[0] / w0, xd[1] / w0**2  # per tau
                r2 = x_ * x_ + v_ * v_
                th_rate = (v_ * dx - x_ * dv) / r2
                l_rate = 2 * (x_ * dx + v_ * dv) / r2 / z
                want_time = [float(th_rate), float(l_rate)]
                want_phase = [float(1 / th_rate), float(l_rate / th_rate)]
            got_time = np.asarray(in_time(0.0, [th, lv]), float)
            got_phase = np.asarray(by_phase(th, [0.0, lv]), float)
            for got, want, size in ((got_time, want_time, [1.0, 4.0]), (got_phase, want_phase, [1.0, 4.0])):
                for g, w, s in zip(got, want, size):
                    worst = max(worst, abs(g - w) / max(abs(w), s))
    print(f"5.5 amplitude-phase: worst {worst:.2e}")
    assert worst <= TOL


# --------------------------------------------------------------------------- the forms derived by hand


def _t():
    from sympy.physics.mechanics import dynamicsymbols

    return dynamicsymbols._t


def test_4_15_lagrangian_and_equation_by_hand():
    """With both ends on the walls the center is (l/2)(cos theta, sin theta): T = (1/2) M (l/2)^2 w^2
    + (1/2)(M l^2/12) w^2 = M l^2 w^2/6, U = M g (l/2) sin theta; Lagrange: (M l^2/3) theta'' =
    -(M g l/2) cos theta, theta'' = -(3 g/2 l) cos theta.  The wall's force M x'' is the event."""
    der = registry.get("4.15").derive()
    t = _t()
    theta, x, y = der.d.q
    l, g, M = (der.symbol(name) for name in ("l", "g", "M"))
    w = theta.diff(t)
    reduced = der.d.L.subs({x.diff(t): sympy.diff(l / 2 * sympy.cos(theta), t),
                            y.diff(t): sympy.diff(l / 2 * sympy.sin(theta), t)}).subs(
        {x: l / 2 * sympy.cos(theta), y: l / 2 * sympy.sin(theta)})
    assert sympy.simplify(reduced - (M * l**2 * w**2 / 6 - M * g * l / 2 * sympy.sin(theta))) == 0
    [(acc, expr)] = der.solved()
    assert acc == theta.diff(t, 2)
    assert sympy.simplify(expr + 3 * g / (2 * l) * sympy.cos(theta)) == 0


def test_a_derivation_checks_its_states_at_once_and_compiles_its_numbers_when_asked():
    """A fresh derivation of 4.15: printing it compiles nothing (``show --derive`` asks for no number);
    the first number asked for compiles the numeric side, and theta'' is the hand's -(3 g/2 l) cos theta;
    a declaration giving one state too few is refused when derived, not when first evaluated."""
    import math

    ex = registry.get("4.15")
    fn, _ = physics.find_declaration(ex)
    d = physics.Declaration(ex)
    fn(d)
    der = physics.Derivation(ex, d)
    der.sections()
    assert der._unbuilt is not None and not hasattr(der, "_A")
    p = ex.resolve({})
    theta = 0.7
    got = der.rates(p, 0.0, [theta], [0.3])
    want = -3 * float(p["g"]) / (2 * float(p["l"])) * math.cos(theta)
    assert got[str(d.q[0].diff(d.t, 2))] == pytest.approx(want, rel=1e-12)
    assert der._unbuilt is None
    short = physics.Declaration(ex)
    fn(short)
    short.state_exprs = short.state_exprs[:-1]
    with pytest.raises(ValueError, match="states"):
        physics.Derivation(ex, short)


def test_5_12_lagrangian_and_equation_by_hand():
    """Bob at (l sin theta, a cos(W t) - l cos theta): T = (M/2)(l^2 w^2 - 2 a W l sin(W t) sin(theta) w
    + a^2 W^2 sin^2(W t)), U = M g (a cos(W t) - l cos theta), F = M l^2 delta w^2; Lagrange with F:
    M l^2 theta'' - M a W^2 l cos(W t) sin theta + M g l sin theta + 2 M l^2 delta w = 0."""
    der = registry.get("5.12").derive()
    t = _t()
    [theta] = der.d.q
    l, g, delta, a, W, M = (der.symbol(name) for name in ("l", "g", "delta", "a", "Omega", "M"))
    w = theta.diff(t)
    T = M / 2 * (l**2 * w**2 - 2 * a * W * l * sympy.sin(W * t) * sympy.sin(theta) * w
                 + a**2 * W**2 * sympy.sin(W * t) ** 2)
    U = M * g * (a * sympy.cos(W * t) - l * sympy.cos(theta))
    assert sympy.simplify(der.d.L - (T - U)) == 0
    [(acc, expr)] = der.solved()
    hand = -2 * delta * w - (g - a * W**2 * sympy.cos(W * t)) / l * sympy.sin(theta)
    assert sympy.simplify(expr - hand) == 0


def test_4_23_steady_rolling_by_hand_is_a_solution():
    """The steady rolling of the analytic answer (derived by hand in ex4_23's docstring: Omega^2 =
    4 g tan(theta)/(6 R - 5 r sin(theta)), spin Omega R/r) makes the derived rates of the speeds and of
    the lean vanish.
    Contact at (R, 0), the center toward the axis: yaw pi/2 (the ground tangent along y), lean -theta
    about it; omega = Omega z + (Omega R/r) n with n the disk's normal, so (by hand) the center moves at
    Omega (R - r sin theta) along y, as turning about the axis requires."""
    import math

    ex = registry.get("4.23")
    der = ex.derive()
    for given in ({}, {"theta": 0.9, "R": 0.05}, {"theta": 0.05, "R": 1.0, "r": 0.3}):
        p = ex.resolve(given)
        th, r, R = p.theta, p.r, p.R
        Om = math.sqrt(4 * p.g * math.tan(th) / (6 * R - 5 * r * math.sin(th)))
        psi, phi = math.pi / 2, -th
        Lx = np.array([0.0, 1.0, 0.0])
        Ly = np.array([-math.cos(th), 0.0, -math.sin(th)])  # the normal
        Lz = np.array([-math.sin(th), 0.0, math.cos(th)])   # contact -> center
        omega = Om * np.array([0.0, 0.0, 1.0]) + Om * R / r * Ly
        q, u = [psi, phi, 0.3, R, 0.0], [omega @ Lx, omega @ Ly, omega @ Lz]
        rates = der.rates(p, 0.0, q, u)
        for k in (1, 2, 3):  # the speeds (the angular velocity in the leaning frame) stay as they are
            assert abs(rates[f"Derivative(u{k}(t), t)"]) <= 1e-12 * (Om * R / r) ** 2, rates
        assert abs(rates["Derivative(phi(t), t)"]) <= 1e-12 * Om * R / r  # the lean too
        x, xd, _ = der.evaluate(p, 0.0, q, u)
        x = np.array([float(v) for v in x])
        xd = np.array([float(v) for v in xd])
        # the center where the hand puts it, moving as the hand says
        assert np.allclose(x[7:10], [R - r * math.sin(th), 0.0, r * math.cos(th)], rtol=0, atol=1e-14 * R)
        assert np.allclose(x[10:13], [0.0, Om * (R - r * math.sin(th)), 0.0], rtol=0, atol=1e-13 * Om * R)
        # steady: the body rates turn only with the body (|omega_body| constant), the center's speed is
        # constant and its acceleration is centripetal
        wb = x[0:3]
        assert abs(wb @ xd[0:3]) <= 1e-12 * (Om * R / r) ** 2
        assert np.allclose(xd[10:13], [-Om**2 * (R - r * math.sin(th)), 0.0, 0.0], rtol=0, atol=1e-11 * Om**2 * R)


# --------------------------------------------------------------------------- the command line


def _mech(*argv, env=None):
    """``mech ARGV`` in this process (its derivations cached), or in a fresh one with ``env``."""
    if env is None:
        from click.testing import CliRunner

        from mech.cli.main import cli

        result = CliRunner().invoke(cli, list(argv))
        return result.exit_code, result.stdout, result.stderr
    proc = subprocess.run([sys.executable, "-c", "from mech.cli.main import main; main()", *argv],
                          capture_output=True, text=True, env=env)
    return proc.returncode, proc.stdout, proc.stderr


def test_show_derive_4_15_prints_the_lagrangian_and_the_equation():
    code, out, err = _mech("show", "4.15", "--derive")
    assert code == 0, err
    assert "Lagrangian" in out and "holonomic constraints" in out and "θ̈" in out
    assert "3⋅g⋅cos(θ)" in out  # theta'' = -3 g cos(theta)/(2 l), as derived by hand above


def test_show_derive_4_23_is_kane_with_nonholonomic_constraints():
    code, out, err = _mech("show", "4.23", "--derive")
    assert code == 0, err
    assert "Kane" in out and "nonholonomic constraints" in out and "fixing u4, u5" in out


def test_show_derive_latex_and_json():
    import json

    code, out, err = _mech("show", "5.12", "--derive", "--latex")
    assert code == 0, err
    der = registry.get("5.12").derive()
    from sympy.physics.vector import vlatex

    from mech.problems.derive_text import tidy

    theta = der.d.q[0]
    [(acc, expr)] = der.solved()
    want = vlatex(sympy.Eq(acc, tidy(expr)))  # as shown: simplified, then cut at spaces into lines of 100
    assert " ".join(want.split()) in " ".join(out.split()) and "\\ddot{\\theta}" in out
    code, out, err = _mech("show", "5.12", "--derive", "--json")
    doc = json.loads(out)
    assert doc["derived"] and doc["parameters"] == ["l", "g", "delta", "a", "Omega"]
    lines = [line for s in doc["sections"] for line in s["latex"]]
    assert want in lines and str(theta.func) in doc["coordinates"]  # JSON: one string an equation


@pytest.mark.parametrize("ex_id, words", [("4.24", "reduced model"), ("4.1", "integrates no equations")])
def test_show_derive_says_why_there_is_none(ex_id, words):
    code, out, err = _mech("show", ex_id, "--derive")
    assert code == 0 and words in out and err == ""


def test_latex_needs_derive():
    code, out, err = _mech("show", "4.15", "--latex")
    assert code == 2 and "--derive" in err


def test_without_sympy_derive_says_how_to_install_it(tmp_path):
    """sympy hidden (a module that fails to import shadows it): exit 2, one line naming the extra."""
    import os

    (tmp_path / "sympy").mkdir()
    (tmp_path / "sympy" / "__init__.py").write_text("raise ImportError('hidden for the test')\n")
    env = {**os.environ, "PYTHONPATH": str(tmp_path)}
    code, out, err = _mech("show", "4.15", "--derive", env=env)
    assert code == 2 and "pip install 'mech-likharev[derive]'" in err and out == ""
    assert len(err.strip().splitlines()) == 1
    code, out, err = _mech("show", "4.24", "--derive", env=env)  # why there is none needs no sympy
    assert code == 0 and "reduced model" in out


@pytest.mark.parametrize("argv", [["list"], ["--help"], ["show", "4.15"], ["solve", "4.15"]])
def test_commands_import_no_sympy(argv):
    code = ("import sys\nfrom mech.cli.main import cli\n"
            f"cli.main({argv!r}, standalone_mode=False)\n"
            "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('sympy', 'mpmath'))\n"
            "sys.exit(1 if bad else 0)\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


def test_import_mech_imports_no_sympy():
    proc = subprocess.run([sys.executable, "-X", "importtime", "-c", "import mech"], capture_output=True, text=True)
    assert proc.returncode == 0 and "sympy" not in proc.stderr


def test_api_derive():
    import mech

    der = mech.exercise("4.15").derive()
    assert der.method == "Lagrange" and [str(q.func) for q in der.d.q] == ["theta", "x", "y"]
    with pytest.raises(LookupError, match="reduced model"):
        mech.exercise("4.25").derive()
