"""4.21 Heavy symmetric top: the slow steady precession, its fast-top ratio, the sleeping-top threshold.

Analytic.  For the axis n3 at fixed theta0 turning about z at Omega, the angular
velocity is Omega z + psi' n3 with omega3 = Omega cos theta0 + psi'; about the
support, L = I_A Omega (z - cos theta0 n3) + I3 omega3 n3.  A rigidly precessing L
changes at Omega z x L = Omega (I3 omega3 - I_A Omega cos theta0) z x n3, and the
weight's torque is M g l z x n3, so
    I_A cos theta0 Omega^2 - I3 omega3 Omega + M g l = 0.
The slow root, rearranged so that cos theta0 -> 0 and cos theta0 < 0 (hanging)
need no special case:
    omega_pre = 2 M g l / (I3 omega3 + sqrt((I3 omega3)^2 - 4 I_A M g l cos theta0)),
    pre_ratio = 2 / (1 + sqrt(1 - 4 I_A M g l cos theta0 / (I3 omega3)^2)).
It exists when the root is real: omega_min = 2 sqrt(I_A M g l cos theta0)/I3 for
cos theta0 > 0, else 0.  The upright top is stable above (Eq. 4.85)
omega_th = 2 sqrt(I_A M g l)/I3.  Near omega_min the discriminant is formed as
I3^2 (omega3 - omega_min)(omega3 + omega_min) to keep its digits.

Numeric.  The residual of the torque balance, Omega z x L(Omega) - l n3 x (-M g z),
with L from the inertia tensor diag(I_A, I_A, I3) acting on the angular velocity
split along the axis and normal to it (no cancellation when I_A >> I3), projected
on z x n3 (solvers.mechanics.tops, over arrays of tops): Omega doubled from the
rate scale M g l/(I3 omega3) to a sign change, or past the residual's maximum
(located by golden sections; the fast root lies beyond it), then Illinois to
1e-15.  The steady state is then followed as the declared motion, the exact
vector equations dn3/dt = L x n3/I_A, dL/dt = l n3 x (-M g z) for one precession
turn (at most 60 nutation periods; steps of at most 2 radians of the nutation),
sampled at least 64 times: the azimuth's rate is fitted and must match the root
within the run's accuracy, the tilt must stay at theta0; energy, L_z and L3 are
monitored.  omega_min: Illinois on the residual's maximum as a function of
omega3, in a bracket narrowed to a factor 2 by halving.  omega_th: the Jacobian of
the same equations about the upright spinning state, in the coordinates
(n_x, n_y, L_x, L_y) with L3 fixed (complex-step derivatives, exact to
round-off), and a bisection on omega3 to the last bit for the onset of an
eigenvalue with positive real part.  The route is written once over arrays of
variants (the searches together, once per distinct top and kept for the rerun;
the steady states followed together in a time scaled to each run's length; a
one-point solve the batch of one); a variant that fails fails alone.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.tops import (LEAST_SPIN_FAILS, NO_PRECESSION, ROOT_FAILS, PrecessionResidual, axis_rhs,
                                         azimuth, fit_rate, follow_scaled, least_spin, polar_angle, slow_roots)

exercise = Exercise(
    "4.21",
    formulas=[
        "I_A cos θ₀ Ω² - I₃ ω₃ Ω + M g l = 0,  I_A = I₁ + M l²",
        "ω_pre = 2 M g l / (I₃ ω₃ + [(I₃ ω₃)² - 4 I_A M g l cos θ₀]^(1/2))  (slow root)",
        "pre_ratio = 2 / (1 + [1 - 4 I_A M g l cos θ₀ / (I₃ ω₃)²]^(1/2))",
        "ω_th = 2 (I_A M g l)^(1/2) / I₃   (Eq. 4.85)",
        "ω_min = ω_th (cos θ₀)^(1/2) for cos θ₀ > 0, else 0",
    ],
    # the confirming run from the steady precession (when one exists): the unit symmetry axis and the
    # angular momentum about the support, lab components, z up
    states=[("n_x", "1"), ("n_y", "1"), ("n_z", "1"), ("L_x", "kg*m^2/s"), ("L_y", "kg*m^2/s"),
            ("L_z", "kg*m^2/s")],
)

# the torque, the spin's angular momentum and the fast-top ratio I_A M g l/(I3 omega3)^2 (whose square
# the growth rates form) in doubles: beyond, the residual divides by an underflowed torque
ranges.declare(
    exercise,
    ranges.Scale("M g l sin(theta0)", {"M": 1, "g": 1, "l": 1}, "the torque", factor=lambda p: math.sin(p.theta0)),
    ranges.Scale("I3 omega3", {"I3": 1, "omega3": 1}, "the spin's angular momentum"),
    ranges.Scale("(I1 + M l^2) M g l/(I3 omega3)^2", {"M": 1, "g": 1, "l": 1, "I3": -2, "omega3": -2},
                 "the rates of the precession and the nutation", low=-150, high=150,
                 factor=lambda p: p.I1 + p.M * p.l**2),
)


def _top(P):
    """(I_A, I3, M g l, theta0, omega3) over arrays of variants."""
    M, l, I1, I3, w3, th, g = (np.asarray(P[k], dtype=float) for k in ("M", "l", "I1", "I3", "omega3", "theta0", "g"))
    return I1 + M * l**2, I3, M * g * l, th, w3


# the analytic side's reasons carry the numbers when at most this many variants have none
NAMED_REASONS = 256


@exercise.analytic
def analytic(P):
    """Over arrays of variants."""
    from mech.solvers.numerics.batch import Column

    IA, I3, Mgl, th, w3 = (np.atleast_1d(x) for x in _top(P))
    c = np.cos(th)
    L3 = I3 * w3
    w_th = 2.0 * np.sqrt(IA * Mgl) / I3
    w_min = np.where(c > 0, w_th * np.sqrt(np.maximum(c, 0.0)), 0.0)
    below = w3 < w_min
    # near omega_min the discriminant is formed as a product to keep its digits; hanging (c <= 0): a sum
    disc = np.where(c > 0, I3**2 * (w3 - w_min) * (w3 + w_min), L3**2 + 4.0 * IA * Mgl * (-c))
    root = np.sqrt(np.where(below, 0.0, disc))
    out = {"omega_th": Column(w_th), "omega_min": Column(w_min)}
    why = "omega3 is below omega_min: no steady precession at theta0"
    if np.count_nonzero(below) <= NAMED_REASONS:
        reasons = [(np.arange(w3.size) == k, f"omega3 = {w3[k]:.6g} rad/s is below omega_min = {w_min[k]:.6g} "
                    "rad/s: no steady precession at theta0") for k in np.flatnonzero(below)]
    else:
        reasons = [(below, why)]
    out["omega_pre"] = Column(np.where(below, np.nan, 2.0 * Mgl / (L3 + root)), undefined=reasons)
    out["pre_ratio"] = Column(np.where(below, np.nan, 2.0 * L3 / (L3 + root)), undefined=reasons)
    return out


# --------------------------------------------------------------------------- numeric


def _upright_growth(IA, Mgl, L3):
    """Largest real part of the eigenvalues of the linearized motion about the upright spinning top,
    relative to the largest modulus, over arrays of tops."""
    # coordinates u = (n_x, n_y, L_x / L3, L_y / L3); n_z and L_z follow from |n| = 1, L . n = L3;
    # complex-step derivatives (exact to round-off)
    h = 1e-30
    J = np.empty(np.shape(L3) + (4, 4))
    for k in range(4):
        u = np.zeros((4,) + np.shape(L3), dtype=complex)
        u[k] = 1j * h
        nx, ny, lx, ly = u
        nz = np.sqrt(1 - nx * nx - ny * ny)
        lz = (1.0 - lx * nx - ly * ny) / nz
        # dn/dt = L x n L3/I_A; dL/dt = l n x (-M g z) = -M g l (n_y, -n_x, 0)
        rates = [(ly * nz - lz * ny) * L3 / IA, (lz * nx - lx * nz) * L3 / IA, -Mgl * ny / L3, Mgl * nx / L3]
        J[..., :, k] = np.stack(rates, axis=-1).imag / h
    lam = np.linalg.eigvals(J)
    return np.max(lam.real, axis=-1) / np.max(np.abs(lam), axis=-1)


ONSET = 1e-7  # real part (relative to |lambda|) that counts as growth: far above round-off near a double eigenvalue


def _threshold(IA, I3, Mgl):
    """omega_th over arrays of tops: the onset of growth, bracketed by halving and doubling from the spin
    scale, then by bisection to the last bit; and a code: 0 found, 1 stable at every spin tried, 2 unstable at
    every spin tried."""
    from mech.solvers.numerics.searches import bisect_bits

    def g(idx, w):
        return ONSET - _upright_growth(IA[idx], Mgl[idx], I3[idx] * w)

    w_ref = np.sqrt(IA * Mgl) / I3  # the only spin scale of the problem (dimensions)
    n = w_ref.size
    ends, code = [], np.zeros(n)
    for factor, growing, fails in ((0.5, True, 1.0), (2.0, False, 2.0)):
        w, gw, todo = w_ref.copy(), np.full(n, np.nan), np.arange(n)
        for _ in range(200):
            gw[todo] = g(todo, w[todo])
            todo = todo[(gw[todo] >= 0) if growing else (gw[todo] < 0)]
            if not todo.size:
                break
            w[todo] *= factor
        code[todo] = fails
        ends.append((w, gw))
    (lo, glo), (hi, ghi) = ends
    out = np.full(n, np.nan)
    ok = np.flatnonzero(code == 0)
    if ok.size:
        out[ok] = bisect_bits(lambda i, w: g(ok[i], w), lo[ok], hi[ok], glo[ok], ghi[ok])
    return out, code


_THRESHOLD_FAILS = {1.0: "the upright top is stable at every spin tried",
                    2.0: "the upright top is unstable at every spin tried"}


def _conserved(IA, Mgl, Ls, Y):
    """The worst drift over the samples Y (6 x K x N: n3, L in units Ls) of the conserved quantities of the
    exact motion, each relative to its scale: the energy less its spin part, L_z, L3 (arrays of N).

    The energy less its spin part L3^2/(2 I3): that part is constant exactly when L3 is, and L3 is
    monitored on its own.  Whole, the energy is ill-conditioned in the state for a thin fast rotor (its
    derivative in L is the angular velocity, so an error rtol |L| moves it by omega3 rtol |L|, 2e6 rtol of E
    at I3 = 1e-8 kg m^2, omega3 = 5600 rad/s on a 470 m arm).  The transverse part of L is the rejection
    L - (n.L) n, not |L|^2 - L3^2, which cancels when the spin carries nearly all of L."""
    n, L = Y[0:3], Y[3:6] * Ls
    L3 = np.sum(n * L, axis=0)
    L_perp = L - L3 * n
    E = 0.5 * np.sum(L_perp * L_perp, axis=0) / IA + Mgl * n[2]
    E_scale = 0.5 * np.sum(L_perp[:, 0] ** 2, axis=0) / IA + Mgl
    return {"energy less the spin's": np.max(np.abs(E - E[0]), axis=0) / E_scale,
            "L_z": np.max(np.abs(L[2] - L[2, 0]), axis=0) / Ls,
            "L3": np.max(np.abs(L3 - L3[0]), axis=0) / Ls}


def _start(R, idx, Om, omega3, theta0):
    """The steady states of the tops idx turning at Om: (y0 = [n3, L/|L|] 6 x n, |L|, the run's length (one
    precession turn, at most 60 nutation periods), its longest step, the variables' size).

    The steady state is slow, so the step control alone lets the step grow to several radians of the
    nutation, where DOP853 no longer damps a round-off nutation: it grows until the error estimate sees it,
    whatever rtol is.  A step of 2 radians of the fastest rate of the linearized motion keeps it resolved."""
    IA, Mgl = R.IA[idx], R.Mgl[idx]
    L0 = R.angular_momentum(idx, Om, omega3)
    Ls = np.sqrt(np.sum(L0 * L0, axis=0))
    nu = Ls / IA  # fastest rate of the axis (nutation scale)
    T = np.minimum(2 * math.pi / Om, 60.0 * 2 * math.pi / nu)
    fastest = nu + np.sqrt(Mgl / IA) + np.abs(Om)
    return np.concatenate([R.n3[:, idx], L0 / Ls]), Ls, T, 2.0 / fastest, np.minimum(1.0, np.sin(theta0))


def _torque(Mgl):
    def torque(t, n):
        return Mgl * np.array([-n[1], n[0], 0.0 * n[0]])  # l n x (-M g z) = M g l z x n

    return torque


@exercise.motion
def motion(p, Om=None):
    """The steady precession, integrated: from the axis at theta0 (azimuth 0) with the angular momentum
    of the steady state turning at the slow root Om (found here when not given; None where there is
    none), the exact vector equations dn3/dt = L x n3/I_A, dL/dt = l n3 x (-M g z) for one precession
    turn, at most 60 nutation periods.  L is integrated in units of its size |L|."""
    from mech.problems.motion import Motion

    IA, I3, Mgl, th, w3 = _top({k: np.array([float(p[k])]) for k in ("M", "l", "I1", "I3", "omega3", "theta0", "g")})
    if Om is None:
        Om, _, code = slow_roots(IA, I3, Mgl, th, w3)
        if code[0] == 1.0:
            return None
        if code[0]:
            raise NumericFailure(ROOT_FAILS[float(code[0])])
    R = PrecessionResidual(IA, I3, Mgl, th)
    y0, Ls, T, max_step, size = _start(R, np.array([0]), np.atleast_1d(Om), w3, th)
    Ls0 = float(Ls[0])
    monitors = {name: (lambda Y, name=name: float(_conserved(IA, Mgl, Ls0, Y[:, :, None])[name][0]))
                for name in ("energy less the spin's", "L_z", "L3")}
    return Motion(axis_rhs(float(IA[0]), _torque(float(Mgl[0])), L_scale=Ls0), y0[:, 0], (0.0, float(T[0])),
                  monitors=monitors, y_scale=[1.0, 1.0, 1.0, Ls0, Ls0, Ls0], y_size=float(size[0]),
                  options={"max_step": float(max_step[0])})


# the steady states' runs are sampled at least this many times (the azimuth's rate fitted over them)
SAMPLES = 64


def _confirm(R, go, Om, omega3, theta0, rtol, tally):
    """The steady states of the tops go followed together (``tops.follow_scaled``, each over its own run) and
    read: (measured rate, tilt drift, run length, the invariants' drifts, why each failed to integrate)."""
    from mech.solvers.numerics.ensemble import each_alone_on_failure

    y0, Ls, T, max_step, size = _start(R, go, Om, omega3, theta0)
    IA, Mgl = R.IA[go], R.Mgl[go]
    n = go.size
    why = np.full(n, "", dtype=object)
    rate = np.full(n, np.nan)

    def run(idx):  # a group whose integration fails is followed again variant by variant
        def make_rhs(sel):
            j = idx[sel]
            # one alone on plain floats (numpy's scalars cost twice their arithmetic a step)
            IA_j, Mgl_j, Ls_j, T_j = (x[j] if isinstance(sel, slice) else float(x[j]) for x in (IA, Mgl, Ls, T))
            f = axis_rhs(IA_j, _torque(Mgl_j), L_scale=Ls_j)
            return lambda t, y: T_j * f(t, y)

        tau_k, Y_k, records = follow_scaled(make_rhs, y0[:, idx], SAMPLES, max_step=max_step[idx] / T[idx],
                                            rtol=rtol, atol=1e-3 * rtol * size[idx] * np.ones((6, 1)),
                                            integrator=tally.integrator)
        for r in records:
            tally.record(r)
        nk = Y_k[:, 0:3].transpose(1, 0, 2)
        slope, _ = fit_rate(tau_k, azimuth(nk))
        rate[idx] = slope / T[idx]
        drift = _conserved(IA[idx], Mgl[idx], Ls[idx], Y_k.transpose(1, 0, 2))
        drift["tilt theta - theta0 (rad)"] = np.max(np.abs(polar_angle(nk) - theta0[idx]), axis=0)
        for name, d in drift.items():
            drifts.setdefault(name, np.full(n, np.nan))[idx] = d

    drifts: dict = {}
    if n:
        each_alone_on_failure(run, np.arange(n), why)
    return rate, T, drifts, why


@exercise.batched(("omega_pre", "pre_ratio", "omega_th", "omega_min"))
def numeric(P, rtol, outputs, memo=None, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): the searches together (once per
    distinct top, kept in ``memo`` for the rerun: they do not depend on rtol), the steady states followed
    together (``_confirm``); every failure and every invariant beyond the claim fails that variant alone."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column, by_rows

    tally = Tally() if tally is None else tally
    memo = {} if memo is None else memo
    IA, I3, Mgl, th, w3 = _top(P)
    N = IA.size

    def thresholds(a, b, c):
        return by_rows(memo, "4.21 omega_th", (a, b, c), _threshold)

    def minima(a, b, c, d):
        w_th, code = thresholds(a, b, c)
        out, code_min = np.full(a.size, np.nan), np.where(code == 0, 0.0, 3.0)
        ok = np.flatnonzero(code == 0)
        if ok.size:
            out[ok], code_min[ok] = least_spin(a[ok], b[ok], c[ok], d[ok], w_th[ok])
        return out, code_min

    omega_th, th_code = thresholds(IA, I3, Mgl)
    omega_min, min_code = by_rows(memo, "4.21 omega_min", (IA, I3, Mgl, th), minima)
    Om, fmax, root_code = by_rows(memo, "4.21 slow root", (IA, I3, Mgl, th, w3), slow_roots)
    failures = [(th_code == c, why) for c, why in _THRESHOLD_FAILS.items()]
    failures += [(min_code == c, why) for c, why in LEAST_SPIN_FAILS.items()]
    failures += [(root_code == c, why) for c, why in ROOT_FAILS.items()]
    tol = exercise.tol_factor * rtol
    # confirm: follow the exact motion from each steady state and measure the azimuth's rate
    go = np.flatnonzero(root_code == 0)
    R = PrecessionResidual(IA, I3, Mgl, th)
    rate, T, drifts, why = _confirm(R, go, Om[go], w3[go], th[go], rtol, tally)
    for text in sorted(set(why[why != ""])):
        failures.append((np.isin(np.arange(N), go[why == text]), text))
    # The measured rate is a confirmation: its error is the integration's error in the azimuth (absolute, about
    # 1e3 rtol rad at most) over the angle run through
    angle_tol = max(1e-6, 1e4 * rtol) * Om[go] * T + 1e3 * rtol
    tilt_tol = max(1e-6, 1e4 * rtol) * np.maximum(th[go], 1e-3)
    tilt = drifts.get("tilt theta - theta0 (rad)", np.zeros(go.size))
    moved = (why == "") & ~((np.abs(rate - Om[go]) * T <= angle_tol) & (tilt <= tilt_tol))
    failures.append((np.isin(np.arange(N), go[moved]), "the steady state does not hold: the measured precession "
                     "rate or the tilt moves off the root's"))
    for name, d in drifts.items():
        full = np.zeros(N)
        full[go] = np.nan_to_num(d)
        tally.invariant(name, full)
        failures.append((full > tol, f"the invariant '{name}' drifts by more than the method allows: the "
                         "integration is not to be trusted"))
    measured = np.full(N, np.nan)
    measured[go] = rate
    tally.info["omega_th_onset_criterion"] = np.full(N, ONSET)
    tally.info["residual_max"] = np.where(np.isnan(fmax), None, fmax)
    tally.info["measured_precession_rate"] = np.where(np.isnan(measured), None, measured)
    with np.errstate(invalid="ignore"):
        turns, off = np.full(N, np.nan), np.abs(measured - Om) / Om
        turns[go] = T * Om[go] / (2 * math.pi)
    tally.info["integrated_turns"] = np.where(np.isnan(turns), None, turns)
    tally.info["measured_vs_root"] = np.where(np.isnan(off), None, off)
    none = [(root_code == 1.0, NO_PRECESSION)]
    zero_min = omega_min == 0.0  # a steady precession exists for every spin (within 1e-12 omega_th)
    cols = {"omega_pre": Column(Om, rel=tol, undefined=none, failed=failures),
            "pre_ratio": Column(Om * I3 * w3 / Mgl, rel=tol, undefined=none, failed=failures),
            "omega_th": Column(omega_th, rel=tol, failed=failures),
            "omega_min": Column(omega_min, rel=np.where(zero_min, 0.0, tol),
                                abs=np.where(zero_min, 1e-12 * omega_th, 0.0), failed=failures)}
    return {o: cols[o] for o in outputs}


def _effective_potential(IA, L3, Lz, Mgl, theta):
    """U_ef(theta) = (L_z - L3 cos theta)^2 / (2 I_A sin^2 theta) + M g l cos theta: the energy of the axis's
    polar motion with the two conserved momenta (L_z about the vertical, L3 about the axis) eliminated."""
    return (Lz - L3 * np.cos(theta)) ** 2 / (2 * IA * np.sin(theta) ** 2) + Mgl * np.cos(theta)


@exercise.scene
def scene(p, run):
    """The effective potential of the tilt for the steady precession's momenta (its minimum at theta0), and
    the slow precession rate against the spin, with the fast-top estimate and the thresholds."""
    from mech.problems.scene import Axis, Guide, Line, Markers, Panel, Scene

    IA, Mgl, L3 = p.I1 + p.M * p.l**2, p.M * p.g * p.l, p.I3 * p.omega3
    a = run.analytic(p)
    nv = run.numeric(p)
    deg = 180.0 / math.pi
    well = Panel("the tilt's effective potential at this top's L_z, L3",
                 Axis("θ, the axis from the upward vertical", "deg"), Axis("(U_ef − U_ef(θ0)) / (M g l)"))
    Om = a["omega_pre"]
    if math.isfinite(Om):
        # the momenta of the steady precession: L = I_A Omega (z - cos theta0 n3) + L3 n3
        Lz = IA * Om * math.sin(p.theta0) ** 2 + L3 * math.cos(p.theta0)
        th = np.linspace(0.02, math.pi - 0.02, 600)
        u0 = _effective_potential(IA, L3, Lz, Mgl, p.theta0)
        well.add(Line(th * deg, (_effective_potential(IA, L3, Lz, Mgl, th) - u0) / Mgl, "U_ef(θ)"),
                 Markers([p.theta0 * deg], [0.0], "θ0: steady precession at its bottom", kind="this"))
        well.y.lim = (-0.5, 3.0)
    else:
        well.title = "no steady precession at θ0: ω3 < ω_min"
    lo = max(a["omega_min"] * 1.02, a["omega_th"] * 0.2)
    hi = max(p.omega3, a["omega_th"]) * 5
    ws = np.geomspace(lo, hi, 200)
    curve = run.series(p, "omega3", ws)
    rate = Panel("slow precession against the spin", Axis("spin ω3", "rad/s", log=True),
                 Axis("precession rate", "rad/s", log=True), legend="upper right")
    rate.add(Line(ws, curve["omega_pre"], "exact slow root"),
             Line(ws, curve["omega_pre"] / curve["pre_ratio"], "fast-top estimate M g l / (I3 ω3)",
                  kind="reference"))
    xs = run.numeric_points(lo, hi, log=True)
    if len(xs):
        rate.add(Markers(xs, run.series(p, "omega3", xs, numeric=True)["omega_pre"], "numeric"))
    if nv:
        rate.add(Markers([p.omega3], [nv["omega_pre"]]))
    rate.add(Markers([p.omega3], [Om], "this top", kind="this"),
             Guide(a["omega_th"], label=f"sleeping-top threshold {a['omega_th']:.4g} rad/s", color="C2"))
    if a["omega_min"] > 0:
        rate.add(Guide(a["omega_min"], label=f"ω_min = {a['omega_min']:.4g} rad/s", color="C4"))
    return Scene([well, rate])
