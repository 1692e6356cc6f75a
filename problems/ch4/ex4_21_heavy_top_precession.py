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
on z x n3: a bracketing root finder between 0 and the residual's maximum
(located by a bounded scalar maximizer; the fast root lies beyond it).  The
steady state is then followed as the declared motion, the exact vector equations
dn3/dt = L x n3/I_A, dL/dt = l n3 x (-M g z) for one precession turn (at most
60 nutation periods; steps of at most 2 radians of the nutation): the azimuth's
rate is fitted and must match the root within the run's accuracy, the tilt
must stay at theta0; energy, L_z and L3 are monitored.  omega_min: Brent's method on the residual's
maximum as a function of omega3.  omega_th: the Jacobian of the same equations
about the upright spinning state, in the coordinates (n_x, n_y, L_x, L_y) with
L3 fixed (complex-step derivatives, exact to round-off), and a bisection on
omega3 for the onset of an eigenvalue with positive real part.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems import ranges
from mech.problems.spec import Exercise, NumericFailure, Undefined
from mech.solvers.numerics.roots import bracketed_root
from mech.solvers.mechanics.tops import axis_rhs, azimuth, fit_rate, polar_angle

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


@exercise.analytic
def analytic(p):
    IA = p.I1 + p.M * p.l**2
    Mgl = p.M * p.g * p.l
    c = math.cos(p.theta0)
    L3 = p.I3 * p.omega3
    w_th = 2.0 * math.sqrt(IA * Mgl) / p.I3
    w_min = w_th * math.sqrt(c) if c > 0 else 0.0
    out = {"omega_th": w_th, "omega_min": w_min}
    if p.omega3 < w_min:
        why = f"omega3 = {p.omega3:.6g} rad/s is below omega_min = {w_min:.6g} rad/s: no steady precession at theta0"
        out.update(omega_pre=Undefined(why), pre_ratio=Undefined(why))
        return out
    if c > 0:
        disc = p.I3**2 * (p.omega3 - w_min) * (p.omega3 + w_min)
    else:
        disc = L3**2 + 4.0 * IA * Mgl * (-c)
    root = math.sqrt(disc)
    out["omega_pre"] = 2.0 * Mgl / (L3 + root)
    out["pre_ratio"] = 2.0 * L3 / (L3 + root)
    return out


# --------------------------------------------------------------------------- numeric


def _residual_factory(IA, I3, Mgl, theta0):
    """f(Omega, omega3): the torque balance's residual along z x n3, in units of M g l sin theta0.

    The angular velocity Omega z + psidot n3 is split on the body's principal
    directions before the inertia tensor acts: z = cos theta0 n3 + sin theta0 u
    with u = (-cos theta0, 0, sin theta0) normal to n3, so
    omega = Omega sin theta0 u + omega3 n3 and L = I_A Omega sin theta0 u + I3 omega3 n3.
    (Rotating the tensor into lab axes first loses the digits of L when
    I_A >> I3: the two I_A terms of L_x cancel to a part in I_A/I3.)
    """
    s, c = math.sin(theta0), math.cos(theta0)
    n3 = np.array([s, 0.0, c])
    u = np.array([-c, 0.0, s])
    z = np.array([0.0, 0.0, 1.0])
    torque = Mgl * np.cross(z, n3)  # l n3 x (-M g z)
    e = np.array([0.0, 1.0, 0.0])  # z x n3 / sin theta0

    def angular_momentum(Om, omega3):
        return IA * Om * s * u + I3 * omega3 * n3

    def f(Om, omega3):
        L = angular_momentum(Om, omega3)
        r = Om * np.cross(z, L) - torque
        return float(r @ e) / (Mgl * s)

    return f, angular_momentum, n3


def _slow_root(f, omega3, Om_scale):
    """The smallest positive zero of f(., omega3), or None when f stays negative; also f's maximum."""
    from mech.solvers.numerics.roots import brentq, minimize_scalar

    f0 = f(0.0, omega3)
    if not f0 < 0:
        raise NumericFailure("the residual at zero precession is not negative")
    prev2, prev, fprev = 0.0, 0.0, f0
    Om = Om_scale
    for _ in range(400):
        fv = f(Om, omega3)
        if fv > 0:
            return brentq(lambda x: f(x, omega3), prev, Om, xtol=1e-300, rtol=1e-15, maxiter=500), None
        if fv < fprev:
            # past the maximum without a positive value: locate the maximum in (prev2, Om)
            res = minimize_scalar(
                lambda x: -f(x, omega3), bounds=(prev2, Om), method="bounded", options={"xatol": 1e-13 * Om}
            )
            fmax, Omv = -res.fun, res.x
            if fmax >= 0:
                return brentq(lambda x: f(x, omega3), 0.0, Omv, xtol=1e-300, rtol=1e-15, maxiter=500), fmax
            return None, fmax
        prev2, prev, fprev = prev, Om, fv
        Om *= 2.0
    raise NumericFailure("no sign change of the precession residual found")


def _fmax(f, omega3, Om_scale):
    """Maximum over Omega > 0 of f(., omega3) (+inf when f grows without bound)."""
    from mech.solvers.numerics.roots import minimize_scalar

    prev2, prev, fprev = 0.0, 0.0, f(0.0, omega3)
    Om = Om_scale
    for _ in range(400):
        fv = f(Om, omega3)
        if fv < fprev:
            res = minimize_scalar(
                lambda x: -f(x, omega3), bounds=(prev2, Om), method="bounded", options={"xatol": 1e-13 * Om}
            )
            return -res.fun
        prev2, prev, fprev = prev, Om, fv
        Om *= 2.0
    return math.inf


def _upright_growth(IA, Mgl, L3):
    """Largest real part of the eigenvalues of the linearized motion about the upright spinning top,
    relative to the largest modulus."""
    # coordinates u = (n_x, n_y, L_x / L3, L_y / L3); n_z and L_z follow from |n| = 1, L . n = L3
    def rhs(u):
        nx, ny, lx, ly = u
        nz = np.sqrt(1 - nx * nx - ny * ny)
        lz = (1.0 - lx * nx - ly * ny) / nz
        n = [nx, ny, nz]
        L = [lx, ly, lz]
        dn = [(L[1] * n[2] - L[2] * n[1]) * L3 / IA, (L[2] * n[0] - L[0] * n[2]) * L3 / IA]
        # dL/dt = l n x (-M g z) = -M g l (n_y, -n_x, 0)
        dL = [-Mgl * ny / L3, Mgl * nx / L3]
        return np.array(dn + dL)

    h = 1e-30
    J = np.empty((4, 4))
    for k in range(4):
        u = np.zeros(4, dtype=complex)
        u[k] = 1j * h
        J[:, k] = rhs(u).imag / h
    lam = np.linalg.eigvals(J)
    return float(np.max(lam.real) / np.max(np.abs(lam)))


ONSET = 1e-7  # real part (relative to |lambda|) that counts as growth: far above round-off near a double eigenvalue


def _threshold(IA, I3, Mgl):
    w_ref = math.sqrt(IA * Mgl) / I3  # the only spin scale of the problem (dimensions)
    lo, hi = w_ref, w_ref
    for _ in range(200):
        if _upright_growth(IA, Mgl, I3 * lo) > ONSET:
            break
        lo /= 2
    else:
        raise NumericFailure("the upright top is stable at every spin tried")
    for _ in range(200):
        if _upright_growth(IA, Mgl, I3 * hi) <= ONSET:
            break
        hi *= 2
    else:
        raise NumericFailure("the upright top is unstable at every spin tried")
    return bracketed_root(lambda w: ONSET - _upright_growth(IA, Mgl, I3 * w), lo, hi)


def _conserved(IA, Mgl, Ls):
    """The conserved quantities of the exact motion, each a function of the states Y (n x N, L in units
    Ls) giving its worst drift over them relative to its scale: the energy less its spin part, L_z, L3.

    The energy less its spin part L3^2/(2 I3): that part is constant exactly when L3 is, and L3 is
    monitored on its own.  Whole, the energy is ill-conditioned in the state for a thin fast rotor (its
    derivative in L is the angular velocity, so an error rtol |L| moves it by omega3 rtol |L|, 2e6 rtol of E
    at I3 = 1e-8 kg m^2, omega3 = 5600 rad/s on a 470 m arm).  The transverse part of L is the rejection
    L - (n.L) n, not |L|^2 - L3^2, which cancels when the spin carries nearly all of L."""

    def parts(Y):
        n, L = Y[0:3], Y[3:6] * Ls
        return n, L, np.sum(n * L, axis=0)

    def energy(Y):
        n, L, L3 = parts(Y)
        L_perp = L - L3 * n
        E = 0.5 * np.sum(L_perp * L_perp, axis=0) / IA + Mgl * n[2]
        E_scale = 0.5 * float(np.sum(L_perp[:, 0] ** 2)) / IA + Mgl
        return float(np.max(np.abs(E - E[0]))) / E_scale

    def L_z(Y):
        L = parts(Y)[1]
        return float(np.max(np.abs(L[2] - L[2, 0]))) / Ls

    def L_3(Y):
        L3 = parts(Y)[2]
        return float(np.max(np.abs(L3 - L3[0]))) / Ls

    return {"energy less the spin's": energy, "L_z": L_z, "L3": L_3}


@exercise.motion
def motion(p, Om=None):
    """The steady precession, integrated: from the axis at theta0 (azimuth 0) with the angular momentum
    of the steady state turning at the slow root Om (found here when not given; None where there is
    none), the exact vector equations dn3/dt = L x n3/I_A, dL/dt = l n3 x (-M g z) for one precession
    turn, at most 60 nutation periods.  L is integrated in units of its size |L|."""
    from mech.problems.motion import Motion

    IA = p.I1 + p.M * p.l**2
    Mgl = p.M * p.g * p.l
    f, angular_momentum, n3 = _residual_factory(IA, p.I3, Mgl, p.theta0)
    if Om is None:
        Om = _slow_root(f, p.omega3, Mgl / (p.I3 * p.omega3))[0]
        if Om is None:
            return None
    L0 = angular_momentum(Om, p.omega3)
    Ls = float(np.linalg.norm(L0))

    def torque(t, n):
        return Mgl * np.array([-n[1], n[0], 0.0])  # l n x (-M g z) = M g l z x n

    nu = Ls / IA  # fastest rate of the axis (nutation scale)
    T = min(2 * math.pi / Om, 60.0 * 2 * math.pi / nu)
    # The steady state is slow, so the step control alone lets the step grow to several radians of the
    # nutation, where DOP853 no longer damps a round-off nutation: it grows until the error estimate sees
    # it, whatever rtol is.  A step of 2 radians of the fastest rate of the linearized motion keeps it
    # resolved.
    fastest = nu + math.sqrt(Mgl / IA) + abs(Om)
    return Motion(axis_rhs(IA, torque, L_scale=Ls), np.concatenate([n3, L0 / Ls]), (0.0, T),
                  monitors=_conserved(IA, Mgl, Ls), y_scale=[1.0, 1.0, 1.0, Ls, Ls, Ls],
                  y_size=min(1.0, math.sin(p.theta0)), options={"max_step": 2.0 / fastest})


@exercise.numeric
def numeric(p, run):
    from mech.solvers.numerics.roots import brentq

    IA = p.I1 + p.M * p.l**2
    Mgl = p.M * p.g * p.l
    f, angular_momentum, n3 = _residual_factory(IA, p.I3, Mgl, p.theta0)
    Om_scale = Mgl / (p.I3 * p.omega3)  # a rate scale to start the search from

    omega_th = _threshold(IA, p.I3, Mgl)
    run.info["omega_th_onset_criterion"] = ONSET

    # omega_min: where the residual's maximum over Omega touches zero
    def fmax_at(w):
        return _fmax(f, w, Mgl / (p.I3 * w))

    w_lo = 1e-12 * omega_th
    if fmax_at(w_lo) >= 0:
        omega_min = 0.0  # a steady precession exists for every spin (within 1e-12 omega_th)
        run.claim("omega_min", abs=1e-12 * omega_th)
    else:
        w_hi = max(p.omega3, omega_th)
        for _ in range(200):
            if fmax_at(w_hi) >= 0:
                break
            w_hi *= 2
        else:
            raise NumericFailure("no spin found at which a steady precession exists")
        omega_min = brentq(fmax_at, w_lo, w_hi, xtol=1e-300, rtol=1e-15, maxiter=500)

    Om, fmax = _slow_root(f, p.omega3, Om_scale)
    out = {"omega_th": omega_th, "omega_min": omega_min}
    if Om is None:
        run.info["residual_max"] = fmax
        why = f"the precession residual stays negative (max {fmax:.3g}): no steady precession at theta0"
        out.update(omega_pre=Undefined(why), pre_ratio=Undefined(why))
        return out
    if fmax is not None:
        run.info["residual_max"] = fmax

    # confirm: follow the exact motion from the steady state and measure the azimuth's rate
    m = motion(p, Om)
    traj = run.follow(m, dense=True).traj
    T_pre = 2 * math.pi / Om
    T = m.span[1]
    ts = np.linspace(0.0, T, 401)
    n_t = traj.sol(ts)[0:3]
    rate, rms = fit_rate(ts, azimuth(n_t))
    run.info["measured_precession_rate"] = rate
    run.info["integrated_turns"] = T / T_pre
    rate_err = abs(rate - Om) / Om
    run.info["measured_vs_root"] = rate_err
    theta_dev = float(np.max(np.abs(polar_angle(n_t) - p.theta0)))
    run.invariant("tilt theta - theta0 (rad)", theta_dev)
    # The measured rate is a confirmation: its error is the integration's error in the
    # azimuth (absolute, about 1e3 rtol rad at most) over the angle run through
    angle_tol = max(1e-6, 1e4 * run.rtol) * Om * T + 1e3 * run.rtol
    tilt_tol = max(1e-6, 1e4 * run.rtol) * max(p.theta0, 1e-3)
    if abs(rate - Om) * T > angle_tol or theta_dev > tilt_tol:
        raise NumericFailure(
            f"the steady state does not hold: measured rate off by {rate_err:.2g}, tilt drifts by {theta_dev:.2g} rad"
        )
    out["omega_pre"] = Om
    out["pre_ratio"] = Om * p.I3 * p.omega3 / Mgl
    return out


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
