"""4.34 Gravity-gradient orientation of an elongated satellite.

Analytic: in the orbital frame each mass element of the rod feels Hill's
field, potential Omega^2 (-3 x^2/2 + z^2/2) per unit mass, and the Coriolis
force, which on a rigid rod points along the rod (no torque).  For a rod of
half-length l along the unit vector n the potential energy is
m l^2 Omega^2 (-3 n_x^2 + n_z^2) (two masses m): lowest for n along the local
vertical, cos_psi_eq = 1.  In-plane, with pitch theta from the vertical,
2 m l^2 theta'' = -3 m l^2 Omega^2 sin 2 theta: a pendulum in 2 theta,
omega_pitch = 3^(1/2) Omega, and the period of amplitude theta_amp is
T = 4 K(k)/(3^(1/2) Omega), k = sin theta_amp (K: complete elliptic integral,
evaluated through 1 - k^2 = cos^2 theta_amp near the separatrix).  Out of
plane, the roll angle alpha feels the tilt stiffness 3 Omega^2 (vertical)
plus Omega^2 (normal): omega_roll = 2 Omega.

Numeric (units l = m = Omega = 1): the rod is two point masses at +-n.
(1) The effective potential is minimized over the unit sphere (two angles,
BFGS from an arbitrary start, polished by Newton steps); cos_psi_eq = |n_x| there.  (2) At that
minimum the mass, gyroscopic and stiffness matrices of the two angles are
built numerically (Jacobian and gyroscopic vector by complex-step, stiffness
by Richardson differences of the complex-step gradient) and the linearized
rotating-frame equations M q'' + G q' + K q = 0 are solved as a first-order
eigenproblem: purely imaginary eigenvalues confirm stability, the in-plane
and out-of-plane modes give the two frequencies.  (3) T_pitch: the planar
constrained motion of one mass (the other mirrors it), r'' = Coriolis + Hill
- lambda r with the link tension lambda from the constraint, integrated from
rest at theta_amp (DOP853) to the first passage through the stable (vertical)
orientation, confirmed with a bounded step: a quarter period, the swing being
symmetric (the Coriolis force on the rod acts along it; the field is even in
the pitch).  The tension is eliminated in closed form and the accelerations
expanded so that no order-one terms cancel (checked against the unexpanded
form): otherwise round-off in the along-rod balance (x ~ 1) feeds the Coriolis
term and errs by 1e-16/theta_amp (3e-9 at 1e-8 rad).  Not to the turning point: near the separatrix the arrival there
is an approach to the unstable along-track orientation, where an energy error
of 1e-13 shifts the turning time by 1e-6, whereas
the departure from the exactly given start is well conditioned.  The Jacobi integral and the
link length are monitored.  At theta_amp = 0 nothing moves:
T = 2 pi/omega_pitch from (2).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.gravity import coriolis, hill_acceleration, hill_potential
from mech.solvers.numerics.ode import Event

exercise = Exercise(
    "4.34",
    formulas=[
        "stable: rod along the local vertical, |cos ψ| = 1",
        "ω_pitch = √3 Ω,  ω_roll = 2 Ω,  Ω = (GM/R³)^{1/2}",
        "T_pitch = 4 K(sin θ_amp)/(√3 Ω)  (pendulum in 2θ: θ'' = -(3/2) Ω² sin 2θ)",
    ],
    # a quarter of the pitch libration (theta_amp > 0), from rest at theta_amp to the local vertical:
    # the rod's angle from the vertical in the orbital plane (positive toward the orbital motion)
    states=[("theta", "rad"), ("theta_dot", "rad/s")],
)


def _omega(p):
    # the orbital rate (GM/R^3)^(1/2), formed without R^3 (which leaves the range at R = 1e+-200 times 7e6 m)
    return np.sqrt(p["GM"]) / np.sqrt(p["R"]) / p["R"]  # nor GM/R, which underflows for GM near 5e-324


@exercise.analytic
def analytic(P):
    """Over arrays of variants."""
    from mech.solvers.numerics.batch import Column
    from mech.solvers.numerics.special import ellipkm1

    W = np.asarray(_omega(P), dtype=float)
    c = np.cos(P["theta_amp"])
    K = np.vectorize(lambda m: float(ellipkm1(m)), otypes=[float])(c * c)  # K(m), m = 1 - cos^2: accurate as m -> 1
    return {
        "cos_psi_eq": Column(np.ones_like(W)),
        "omega_pitch": Column(math.sqrt(3.0) * W),
        "omega_roll": Column(2.0 * W),
        "T_pitch": Column(4.0 * K / (math.sqrt(3.0) * W)),
    }


# ---- numeric, units l = m = Omega = 1 ---------------------------------------------------


def _direction(q):
    a, b = q[0], q[1]
    return np.array([np.cos(a) * np.cos(b), np.sin(a) * np.cos(b), np.sin(b)])


def _potential(q):
    """both masses at +-n in Hill's field (works for complex q: complex-step)."""
    n = _direction(q)
    return 2.0 * (-1.5 * n[0] ** 2 + 0.5 * n[2] ** 2)


def _jacobian(q):
    """d n / d q by complex step."""
    h = 1e-30
    J = np.empty((3, 2))
    for j in range(2):
        dq = np.zeros(2, dtype=complex)
        dq[j] = 1j * h
        J[:, j] = _direction(q + dq).imag / h
    return J


def _gyro_vector(q):
    """g(q) with the velocity-linear Lagrangian term q'.g: sum over masses of Omega (x dy - y dx)."""
    n = _direction(q)
    J = _jacobian(q)
    return 2.0 * (n[0] * J[1] - n[1] * J[0])


def _grad(q):
    h = 1e-30
    g = np.empty(2)
    for j in range(2):
        dq = np.zeros(2, dtype=complex)
        dq[j] = 1j * h
        g[j] = _potential(q + dq).imag / h
    return g


def _linear_modes(q0):
    # mass matrix: T = sum over masses |J q'|^2 / 2 -> M = 2 J^T J
    J = _jacobian(q0)
    M = 2.0 * J.T @ J

    def richardson(f, h=1e-3):
        def central(hh):
            cols = []
            for j in range(2):
                e = np.zeros(2)
                e[j] = hh
                cols.append((f(q0 + e) - f(q0 - e)) / (2 * hh))
            return np.array(cols).T  # [i, j] = d f_i / d q_j

        c1, c2 = central(h), central(h / 2)
        return c2 + (c2 - c1) / 3.0

    K = richardson(_grad)
    K = 0.5 * (K + K.T)
    Dg = richardson(_gyro_vector)
    G = Dg - Dg.T
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-Minv @ K, -Minv @ G]])
    lam, vecs = np.linalg.eig(A)
    return lam, vecs, M, K, G


SMALL_SWING = 1e-9  # rad: below it the pitch period is the linear one to round-off


def _pitch_rhs(t, y):
    """One mass of the rod in the orbit's frame, scaled (``motion``), for y of shape (4,) or (4, N).
    a = Coriolis + Hill - lambda r, lambda = (r.a_free + |v|^2)/|r|^2 keeping |r| fixed.  With
    a_free = (2 vy + 3x, -2 vx), lambda = 3 + mu, mu = (2 (x vy - y vx) - 3 y^2 + |v|^2)/|r|^2; expanded so
    that no order-one terms cancel (x ~ 1 in a tiny swing, y ~ 1 near the separatrix)."""
    x, yy, vx, vy = y
    r2 = x * x + yy * yy
    v2 = vx * vx + vy * vy
    ax = (2 * vy * yy * yy + 2 * x * yy * vx + 3 * x * yy * yy - x * v2) / r2
    ay = -(2 * vx * x * x + 3 * x * x * yy + 2 * x * yy * vy + yy * v2) / r2
    return np.array([vx, vy, ax, ay])


def _pitch_sine(t, y):
    return y[1]  # the rod crosses the local vertical


def _jacobi(y):
    """The Jacobi integral relative to the depth 3/2 of the potential well (y: (4,) or (4, N))."""
    return (0.5 * (y[2] ** 2 + y[3] ** 2) + hill_potential([y[0], y[1], 0.0 * y[0]], 1.0)) / 1.5


def _sizes(th):
    """Absolute tolerances' sizes, scaled to the smallest offset: sin(theta_amp) for tiny swings, and
    cos(theta_amp), the distance from the unstable along-track orientation, near the separatrix."""
    s = np.maximum(np.sin(th), 1e-150)
    c = np.maximum(np.cos(th), 1e-150)
    return [c, s, np.minimum(c, s), np.minimum(c, s)]


@exercise.motion
def motion(p):
    """The finite pitch libration: one mass of the rod (the other mirrors it) in the orbit's frame, scaled
    (lengths l/2, time 1/Omega), r'' = Coriolis + Hill - lambda r with the link tension lambda from the
    constraint (``_pitch_rhs``), from rest at theta_amp to the rod's passage through the local vertical, a
    quarter period.  The states are the pitch angle and its rate.  None below SMALL_SWING (the linear mode's
    period)."""
    from mech.problems.motion import Motion

    th = p.theta_amp
    if th < SMALL_SWING:
        return None
    # Integrator: DOP853 at rtol 1e-10 (tolerance 1e-8), kept after `mech bench 4.34`: the fewest
    # evaluations with an error well under the tolerance.
    return Motion(_pitch_rhs, [math.cos(th), math.sin(th), 0.0, 0.0], (0.0, 1e4),
                  event=Event(_pitch_sine, direction=-1, name="rod along the vertical"),
                  invariants={"Jacobi integral": _jacobi, "link length": lambda y: math.hypot(y[0], y[1])},
                  t_scale=1.0 / float(_omega(p)), y_scale=[1.0, float(_omega(p))], y_size=[float(v) for v in _sizes(th)],
                  to_states=lambda y: [np.arctan2(y[1], y[0]),
                                       (y[0] * y[3] - y[1] * y[2]) / (y[0] ** 2 + y[1] ** 2)],
                  from_states=lambda x: [np.cos(x[0]), np.sin(x[0]), -np.sin(x[0]) * x[1], np.cos(x[0]) * x[1]])


def _minimum():
    """(1) The stable direction: minimum of the effective potential from an arbitrary start.  Each step goes
    downhill along the Newton direction where the Hessian is positive definite and along -grad U elsewhere,
    with a backtracking (Armijo) line search, so it cannot settle on a saddle as a bare Newton iteration
    could; the Newton polish then finishes the minimum it reaches.  Returns q0, or raises NumericFailure."""
    q0 = np.array([1.1, 0.6])
    U0, g0 = _potential(q0), _grad(q0)
    for _ in range(200):
        if np.linalg.norm(g0) < 1e-8:
            break
        H = _linear_modes(q0)[3]
        d = -g0
        if np.all(np.linalg.eigvalsh(0.5 * (H + H.T)) > 0):
            d = -np.linalg.solve(H, g0)
        step_len = 1.0
        while step_len > 1e-12:
            trial = q0 + step_len * d
            U1 = _potential(trial)
            if U1 <= U0 + 1e-4 * step_len * float(g0 @ d):
                break
            step_len *= 0.5
        q0, U0, g0 = trial, U1, _grad(trial)
    for _ in range(8):  # polish by Newton steps on the (complex-step) gradient
        K0 = _linear_modes(q0)[3]
        step = np.linalg.solve(K0, _grad(q0))
        q0 = q0 - step
        if np.linalg.norm(step) < 1e-15:
            break
    if np.linalg.norm(_grad(q0)) > 1e-12:
        raise NumericFailure(f"the potential's minimum was not reached: |grad U| = {np.linalg.norm(_grad(q0)):.3g}")
    return q0


@functools.lru_cache(maxsize=1)
def _orientation():
    """(1) and (2), the same for every variant in units l = m = Omega = 1: (cos_psi_eq, pitch and roll
    frequencies, None) at the minimum, or (NaN, NaN, NaN, why) where it fails; and the expanded accelerations
    checked against the unexpanded constrained form (shared field code)."""
    try:
        q0 = _minimum()
    except NumericFailure as exc:
        return math.nan, math.nan, math.nan, str(exc)
    cos_psi = abs(_direction(q0)[0])
    # (2) linearized rotating-frame equations at the minimum
    lam, vecs, M, K, G = _linear_modes(q0)
    if np.max(np.abs(lam.real)) > 1e-8 * np.max(np.abs(lam)):
        return math.nan, math.nan, math.nan, f"the orientation found is not stable: eigenvalues {lam}"
    freqs = {}
    for k in range(4):
        if lam[k].imag <= 0:
            continue
        shape = np.abs(vecs[:2, k])
        # which tilt: the first angle moves the rod within the orbital plane (pitch), the second out of it
        freqs["pitch" if shape[0] > shape[1] else "roll"] = lam[k].imag
    if set(freqs) != {"pitch", "roll"}:
        return math.nan, math.nan, math.nan, f"could not tell the pitch and roll modes apart: {lam}"
    y = np.array([math.cos(0.7), math.sin(0.7), 0.3, -0.2])
    r, v = np.array([y[0], y[1], 0.0]), np.array([y[2], y[3], 0.0])
    a_free = coriolis(v, 1.0) + hill_acceleration(r, 1.0)
    lam_t = (r @ a_free + v @ v) / (r @ r)
    if not np.allclose(_pitch_rhs(0.0, y)[2:], (a_free - lam_t * r)[:2], rtol=1e-13, atol=1e-13):
        return math.nan, math.nan, math.nan, "the expanded accelerations disagree with the constrained form"
    return cos_psi, float(freqs["pitch"]), float(freqs["roll"]), None


# a batched step's fixed cost and a step of one swing alone (plain floats), in swings' worth of arithmetic
# (``chunks_by_work``): of the order 4.23 measured for its ensemble (900 and 180 there), not tuned
STEP_OVERHEAD, STEP_ALONE = 600.0, 150.0


def _quarters(th, rtol, tally):
    """(3) The quarter libration of each swing th (> 0, units Omega = 1): (its time, the Jacobi integral's and
    the link length's drifts, why it failed or "").  Swings of like lengths together (``batch.chunks_by_work``:
    a quarter's steps grow as log(1/cos theta_amp) towards the separatrix, and a batch steps at its hardest
    swing's pace), by mech's DOP853 stepping the chunk, each swing stopped at its own event and failing alone
    (``batch.integrate_batch``); a swing alone, or with an integrator forced (``mech bench``), by
    ``ode.integrate``."""
    from mech.core.budget import OutOfBudget
    from mech.solvers.numerics.batch import BatchEvent, chunks_by_work, integrate_batch
    from mech.solvers.numerics.ode import integrate

    N = th.size
    t_ev, why = np.full(N, np.nan), np.full(N, "", dtype=object)
    y0 = np.array([np.cos(th), np.sin(th), np.zeros(N), np.zeros(N)])
    y_ev = np.full((4, N), np.nan)
    atol = 1e-3 * rtol * np.array(_sizes(th))
    work = 30.0 + 15.0 * np.log1p(1.0 / np.maximum(np.cos(th), 1e-300))
    chunks = [np.arange(N)] if N == 1 else chunks_by_work(work, STEP_OVERHEAD, STEP_ALONE)
    for idx in chunks if tally.integrator is None else np.arange(N)[:, None]:
        if idx.size > 1:
            res = tally.record(integrate_batch(_pitch_rhs, (0.0, 1e4), y0[:, idx], rtol=rtol, atol=atol[:, idx],
                                               on_failure="mark",
                                               events=[BatchEvent(_pitch_sine, -1.0, terminal=True)]))
            t_ev[idx], y_ev[:, idx] = res.t_events[0], res.y_events[0]
            why[idx[res.failed]] = [res.why[j] for j in np.flatnonzero(res.failed)]
            continue
        j = idx[0]
        try:
            traj = tally.record(integrate(_pitch_rhs, (0.0, 1e4), y0[:, j], rtol=rtol, atol=atol[:, j],
                                          events=[Event(_pitch_sine, direction=-1)], integrator=tally.integrator))
        except OutOfBudget:
            raise
        except NumericFailure as exc:
            why[j] = str(exc)
            continue
        if len(traj.t_events[0]):
            t_ev[j], y_ev[:, j] = traj.t_events[0][0], traj.y_events[0][0]
    why[(why == "") & np.isnan(t_ev)] = "the rod did not pass the local vertical"
    dJ = np.nan_to_num(_jacobi(y_ev) - _jacobi(y0))
    dlink = np.nan_to_num(np.hypot(y_ev[0], y_ev[1]) - 1.0)
    return t_ev, dJ, dlink, why


@exercise.batched(("cos_psi_eq", "omega_pitch", "omega_roll", "T_pitch"))
def numeric(P, rtol, outputs, tally=None):
    """The orientation and its linear modes once for all variants (``_orientation``: they do not depend on the
    parameters in units of l, m and Omega), the quarter libration of each swing (``_quarters``); a variant that
    fails fails alone.  At theta_amp = 0 nothing moves: T = 2 pi/omega_pitch from (2)."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    W = np.atleast_1d(np.asarray(_omega(P), dtype=float))
    th = np.atleast_1d(np.asarray(P["theta_amp"], dtype=float))
    N = th.size
    cos_psi, pitch, roll, fail = _orientation()
    why = np.full(N, fail or "", dtype=object)
    # the libration's nonlinearity enters the period at relative order theta_amp^2 (the period is an even,
    # smooth function of the amplitude), below 1e-18 under SMALL_SWING: the linear mode's period is the finite
    # swing's to round-off, and it avoids integrating offsets of 1e-200 (whose absolute tolerances underflow)
    small = th < SMALL_SWING
    T = np.full(N, 2.0 * math.pi / pitch)
    swing = np.flatnonzero(~small & (why == ""))
    t_ev, dJ, dlink, why[swing] = _quarters(th[swing], rtol, tally)
    T[swing] = 4.0 * t_ev
    drifts = {"Jacobi integral": np.zeros(N), "link length": np.zeros(N)}
    drifts["Jacobi integral"][swing], drifts["link length"][swing] = dJ, dlink
    for name, d in drifts.items():
        if swing.size:
            tally.invariant(name, d)
    tally.info["stable"] = np.where(why == "", True, None).astype(object)
    tally.info["quarter_period"] = np.where(~small & (why == ""), T / 4.0 / W, None).astype(object)
    tally.info["T_pitch_from"] = np.where(small, "small-oscillation frequency (amplitude below 1e-9 rad)",
                                          None).astype(object)
    values = {"cos_psi_eq": np.full(N, cos_psi), "omega_pitch": pitch * W, "omega_roll": roll * W, "T_pitch": T / W}
    rels = {"cos_psi_eq": 1e-9, "omega_pitch": 1e-9, "omega_roll": 1e-9,
            "T_pitch": np.where(small, 1e-9, exercise.tol_factor * rtol)}
    failed = [(why == text, text) for text in sorted(set(why[why != ""]))]
    return {q: Column(np.where(why == "", values[q], np.nan), rel=rels[q], failed=failed) for q in outputs}


@exercise.hamiltonian
def hamiltonian(p):
    """For the symplectic rows of ``mech bench`` (T_pitch only).  Units l = m = Omega = 1; the rod's masses at
    +-(cos th, sin th) in the orbital plane.  Per unit mass in the rotating frame L = |r'|²/2 + r'.(Omega x r)
    - Phi with Hill's Phi = -3x²/2 + z²/2; for the two masses r'.(Omega x r) = th' (a total derivative, dropped),
    so L = th'² + 3 cos² th and H = p²/4 - 3 cos² th is separable (p = 2 th'); from rest at theta_amp to the
    first downward passage through th = 0: a quarter libration."""
    from mech.solvers.numerics.symplectic import SeparableHamiltonian

    W = _omega(p)
    return SeparableHamiltonian(
        velocity=lambda mom: 0.5 * mom,
        force=lambda q: -3.0 * math.sin(2.0 * q),
        energy=lambda q, mom: 0.25 * mom * mom - 3.0 * math.cos(q) ** 2,
        q0=float(p.theta_amp),
        p0=0.0,
        t_max=20.0 + 4.0 * math.log(1.0 + 1.0 / max(math.cos(p.theta_amp), 1e-300)),
        readout=lambda t, q, mom: {"T_pitch": 4.0 * t / W},
        event=lambda q, mom: q,
        direction=-1,
        time_scale=1.0 / math.sqrt(3.0),
        name="pitch quarter libration",
    )
