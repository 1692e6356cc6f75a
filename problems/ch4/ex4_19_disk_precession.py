"""4.19 Free precession of a thin round disk, from the disk and from the lab.

Analytic: for the disk I3 = 2 I1 (perpendicular-axis theorem).  Euler's
equations with I1 = I2 leave omega3 = omega cos(alpha) constant and turn
(omega1, omega2) at Omega_body = (I3 - I1) omega3 / I1 = omega cos(alpha), in the
sense of the spin.  In the lab the symmetry axis, omega and L lie in one plane
that turns about L at omega_lab = |L|/I1 = omega (sin^2 alpha + 4 cos^2 alpha)^(1/2)
= omega (1 + 3 cos^2 alpha)^(1/2); L is tilted from n3 by tan(theta_L) =
I1 sin(alpha) / (I3 cos(alpha)) = tan(alpha)/2.  For alpha -> 0: Omega_body = omega,
omega_lab = 2 omega (twice the spin), theta_L = 0.

Numeric: Euler's equations with the quaternion attitude (solvers.mechanics.rigid), with
the moments from a quadrature of the disk's mass, started from
omega (sin alpha, 0, cos alpha) in body axes and an attitude that puts the
initial L (computed from that state) along the lab z axis, so that the small
tilt components of the quaternion carry relative accuracy.  Omega_body is the
slope of the unwrapped phase of (omega1, omega2), omega_lab that of the azimuth
of n3(t) about L, theta_L the angle between n3(t) and L (checked constant).
Energy, |L| and the lab vector L are monitored.  At alpha = 0 the rates come
from a run with a tilt of 1e-7 rad (the rates are even in the tilt, so the
bias is of order 1e-14) and theta_L from the untilted run itself.  The route
is written once over arrays of variants (a class's disks followed together,
sampled at CHECKPOINTS over two spins; a one-point solve the batch of one);
a variant that fails fails alone.
"""

from __future__ import annotations

import functools

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.freebody import follow_free, free_invariants, free_rhs, lab_axes, phase_rate
from mech.solvers.mechanics.inertia import disk, inertia_tensor

exercise = Exercise(
    "4.19",
    formulas=[
        "I₃ = 2I₁ (thin disk)",
        "Ω_body = (I₃ - I₁) ω cos α / I₁ = ω cos α  →  ω as α → 0",
        "ω_lab = |L|/I₁ = ω (1 + 3cos²α)^(1/2)  →  2ω as α → 0",
        "tan θ_L = I₁ sin α / (I₃ cos α) = (tan α)/2  →  0 as α → 0",
    ],
    # two spin periods of the free disk: body-axis rates (3 = the symmetry axis) and the attitude as a
    # unit quaternion (scalar first, body -> lab) with lab z along the angular momentum
    states=[("omega1", "rad/s"), ("omega2", "rad/s"), ("omega3", "rad/s"),
            ("q0", "1"), ("q1", "1"), ("q2", "1"), ("q3", "1")],
)

PROBE_TILT = 1e-7
SPINS = 2.0            # length of the run, in periods 2 pi/omega
SAMPLES_PER_SPIN = 100  # the declared motion's samples (what a trajectory shows)
# the route's samples over the run: the lab phase turns at most 2 omega, 8 pi over the run, 0.79 rad a sample
# (phase_rate refuses jumps over 1 rad)
CHECKPOINTS = 32


@exercise.analytic
def analytic(P):
    """Over arrays of variants."""
    from mech.solvers.numerics.batch import Column

    omega, alpha = (np.asarray(P[k], dtype=float) for k in ("omega", "alpha"))
    ca, sa = np.cos(alpha), np.sin(alpha)
    return {"Omega_body": Column(omega * ca), "omega_lab": Column(omega * np.sqrt(1.0 + 3.0 * ca * ca)),
            "theta_L": Column(np.arctan2(sa, 2.0 * ca))}


@functools.lru_cache(maxsize=1)
def _disk_moments():
    """(I1, I1, I3) of a unit disk from the quadrature of its mass; I1 = I2 by its symmetry."""
    pts, w = disk()
    I = np.diag(inertia_tensor(pts, w))
    i_plane = 0.5 * (I[0] + I[1])
    if abs(I[0] - I[1]) > 1e-12 * i_plane:
        raise NumericFailure("the disk quadrature is not axially symmetric")
    return np.array([i_plane, i_plane, I[2]])


def _start(I, alpha):
    """The starts in units omega = 1 (alpha: an array of N tilts): omega (sin alpha, 0, cos alpha) in body
    axes and the attitude that puts the initial L along lab z (the shortest rotation, about -y by L's tilt),
    7 x N; and the size of each variable (the small tilt components of the quaternion keep relative
    accuracy), 7 x N."""
    alpha = np.asarray(alpha, dtype=float)
    sa, ca = np.sin(alpha), np.cos(alpha)
    w0 = np.stack([sa, np.zeros_like(sa), ca])
    L_body = I[:, None] * w0
    tilt = np.arctan2(np.abs(L_body[0]), L_body[2])  # L's angle from n3, from the numbers
    q0 = np.stack([np.cos(tilt / 2), np.zeros_like(sa), -np.sin(tilt / 2), np.zeros_like(sa)])
    small = np.maximum(np.sin(tilt / 2), 1e-300)
    one, s_w = np.ones_like(sa), np.maximum(sa, 1e-300)
    size = np.stack([s_w, s_w, np.maximum(np.abs(ca), 1e-300), one, small, small, one])
    return np.concatenate([w0, q0]), size


@exercise.motion
def motion(p):
    """The free disk over SPINS spin periods from its tilt alpha, in units omega = 1, sampled
    SAMPLES_PER_SPIN times a spin."""
    from mech.problems.motion import Motion

    I = _disk_moments()
    y0, size = _start(I, np.array([p.alpha]))
    t_end = SPINS * 2 * np.pi
    t_eval = np.linspace(0.0, t_end, int(SPINS * SAMPLES_PER_SPIN) + 1)
    monitors = {name: (lambda Y, name=name: float(free_invariants(I, Y[:, :, None])[name][0]))
                for name in ("energy", "|L|", "L (lab vector)", "|q| - 1")}
    return Motion(free_rhs(I), y0[:, 0], (0.0, t_end), monitors=monitors, t_scale=1.0 / p.omega,
                  y_scale=[p.omega] * 3 + [1.0] * 4, options={"t_eval": t_eval}, y_size=size[:, 0])


def _readings(I, t, Y, rtol):
    """(Omega_body, omega_lab, theta_L, failures [(mask, reason)]) in units omega = 1 from the sampled free
    motions Y (K samples x 7 x N) at t."""
    Y = Y.transpose(1, 0, 2)  # 7 x K x N
    L_lab0 = lab_axes(Y[3:7, 0], I[:, None] * Y[0:3, 0])  # lab frame around each initial L
    ez = L_lab0 / np.sqrt(np.sum(L_lab0 * L_lab0, axis=0))
    ex = np.stack([ez[2], np.zeros_like(ez[0]), -ez[0]])  # y x ez
    ex /= np.sqrt(np.sum(ex * ex, axis=0))
    ey = np.cross(ez, ex, axis=0)
    n3 = lab_axes(Y[3:7], [0.0, 0.0, 1.0])  # 3 x K x N
    a, b, c = (np.sum(e[:, None, :] * n3, axis=0) for e in (ex, ey, ez))
    theta = np.arctan2(np.hypot(a, b), c)
    bent = np.max(np.abs(theta - theta[0]), axis=0) > 1e3 * rtol * np.maximum(theta[0], 1e-300) + 1e-15
    om_body, _, sparse_body = phase_rate(t, Y[0], Y[1])
    om_lab, _, sparse_lab = phase_rate(t, a, b)
    failures = [(bent, "the angle between n3 and L does not stay constant"),
                (sparse_body | sparse_lab, "the phase moves over 1 rad between samples: too sparse to unwrap")]
    return om_body, om_lab, np.mean(theta, axis=0), failures


@exercise.batched(("Omega_body", "omega_lab", "theta_L"))
def numeric(P, rtol, outputs, memo=None, tally=None):
    """The route at N variants at once (a one-point solve is the batch of one): the free disks followed
    together over SPINS spins (units omega = 1) and sampled at CHECKPOINTS; an untilted disk's rates come
    from a disk at PROBE_TILT followed beside it.  Every failure and every invariant beyond the claim fails
    that variant alone."""
    from mech.problems.spec import Tally
    from mech.solvers.numerics.batch import Column

    tally = Tally() if tally is None else tally
    omega, alpha = (np.asarray(P[k], dtype=float) for k in ("omega", "alpha"))
    N = alpha.size
    I = _disk_moments()
    probe = np.flatnonzero(alpha == 0.0)
    y0, size = _start(I, np.concatenate([alpha, np.full(probe.size, PROBE_TILT)]))
    t = np.linspace(0.0, SPINS * 2 * np.pi, CHECKPOINTS + 1)
    Y, records = follow_free(I, y0, t, rtol=rtol, atol=1e-3 * rtol * size, integrator=tally.integrator)
    for r in records:
        tally.record(r)
    om_body, om_lab, theta_L, failures = _readings(I, t, Y, rtol)
    rates = np.arange(N)
    rates[probe] = N + np.arange(probe.size)  # where each variant's rates are read
    failures = [(m[:N] | m[rates], why) for m, why in failures]
    om_body, om_lab, theta_L = om_body[rates], om_lab[rates], theta_L[:N]
    failures.append((~(om_lab > 0), "the symmetry axis does not turn about +L"))
    tol = exercise.tol_factor * rtol
    drifts = free_invariants(I, Y.transpose(1, 0, 2))
    for name, drift in drifts.items():
        worst = np.maximum(drift[:N], drift[rates])
        tally.invariant(name, worst)
        failures.append((~(worst <= tol), f"the invariant '{name}' drifts by more than the method allows: "
                         "the integration is not to be trusted"))
    tally.info["I3_over_I1"] = np.full(N, I[2] / I[0])
    tally.info["probe_tilt_rad"] = np.where(alpha == 0.0, PROBE_TILT, None)
    # a body rate that vanishes at alpha = pi/2: measured to an absolute accuracy of the spin's scale
    cols = {"Omega_body": Column(om_body * omega, rel=tol, abs=1e-3 * tol * omega, failed=failures),
            "omega_lab": Column(om_lab * omega, rel=tol, failed=failures),
            "theta_L": Column(theta_L, rel=tol, abs=1e-15, failed=failures)}
    return {o: cols[o] for o in outputs}
