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
bias is of order 1e-14) and theta_L from the untilted run itself.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.frames import quat_aligning
from mech.solvers.mechanics.freebody import free_invariants, free_rhs, lab_axes, phase_rate
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
SAMPLES_PER_SPIN = 100


@exercise.analytic
def analytic(p):
    ca, sa = np.cos(p.alpha), np.sin(p.alpha)
    return {
        "Omega_body": p.omega * ca,
        "omega_lab": p.omega * np.sqrt(1.0 + 3.0 * ca * ca),
        "theta_L": float(np.arctan2(sa, 2.0 * ca)),
    }


def _disk_moments():
    """(I1, I1, I3) of a unit disk from the quadrature of its mass; I1 = I2 by its symmetry."""
    pts, w = disk()
    I = np.diag(inertia_tensor(pts, w))
    i_plane = 0.5 * (I[0] + I[1])
    if abs(I[0] - I[1]) > 1e-12 * i_plane:
        raise NumericFailure("the disk quadrature is not axially symmetric")
    return np.array([i_plane, i_plane, I[2]])


def _start(I, alpha):
    """The start in units omega = 1: omega (sin alpha, 0, cos alpha) in body axes and the attitude that puts
    the initial L along lab z; and the size of each variable (the small tilt components of the quaternion
    keep relative accuracy)."""
    sa, ca = np.sin(alpha), np.cos(alpha)
    w0 = np.array([sa, 0.0, ca])
    L_body = I * w0
    q0 = quat_aligning(L_body)                 # initial L along lab z
    tilt = np.arctan2(np.hypot(L_body[0], L_body[1]), L_body[2])  # from the numbers, for tolerances
    small = max(np.sin(tilt / 2), 1e-300)
    size = np.array([max(sa, 1e-300), max(sa, 1e-300), max(abs(ca), 1e-300), 1.0, small, small, 1.0])
    return np.concatenate([w0, q0]), size


def _drifts(I):
    """Energy, |L|, the lab vector L and |q| - 1: the worst drift over the samples (n x N states)."""
    def drift(name):
        return lambda Y: free_invariants(I, SimpleNamespace(y=Y))[name]

    return {name: drift(name) for name in ("energy", "|L|", "L (lab vector)", "|q| - 1")}


@exercise.motion
def motion(p):
    """The free disk over SPINS spin periods from its tilt alpha, in units omega = 1, sampled
    SAMPLES_PER_SPIN times a spin."""
    from mech.problems.motion import Motion

    I = _disk_moments()
    y0, size = _start(I, p.alpha)
    t_end = SPINS * 2 * np.pi
    t_eval = np.linspace(0.0, t_end, int(SPINS * SAMPLES_PER_SPIN) + 1)
    return Motion(free_rhs(I), y0, (0.0, t_end), monitors=_drifts(I), t_scale=1.0 / p.omega,
                  y_scale=[p.omega] * 3 + [1.0] * 4, options={"t_eval": t_eval}, y_size=size)


def _readings(I, path, rtol):
    """(Omega_body, omega_lab, theta_L) in units omega = 1 from the sampled free motion (``path``)."""
    traj, w0 = path.traj, path.motion.y0[0:3]
    L_body = I * w0
    # lab frame around the initial L
    L_lab0 = lab_axes(traj, L_body)[:, 0]
    ez = L_lab0 / np.linalg.norm(L_lab0)
    ex = np.cross([0.0, 1.0, 0.0], ez)
    ex /= np.linalg.norm(ex)
    ey = np.cross(ez, ex)
    n3 = lab_axes(traj, [0.0, 0.0, 1.0])
    a, b, c = ex @ n3, ey @ n3, ez @ n3
    theta = np.arctan2(np.hypot(a, b), c)
    if np.max(np.abs(theta - theta[0])) > 1e3 * rtol * max(theta[0], 1e-300) + 1e-15:
        raise NumericFailure("the angle between n3 and L does not stay constant")
    if w0[0] == 0.0:  # no tilt: the rates come from a probe
        return None, None, float(np.mean(theta))
    om_body, _ = phase_rate(traj.t, traj.y[0], traj.y[1])
    om_lab, _ = phase_rate(traj.t, a, b)
    return om_body, om_lab, float(np.mean(theta))


@exercise.numeric
def numeric(p, run):
    I = _disk_moments()
    run.info["I3_over_I1"] = I[2] / I[0]
    m = motion(p)
    om_body, om_lab, theta_L = _readings(I, run.follow(m), run.rtol)
    if p.alpha == 0.0:
        y0, size = _start(I, PROBE_TILT)
        probe = run.follow(m.starting(y0=y0, y_size=size), mark=False)  # the rates, not the scene's motion
        om_body, om_lab, _ = _readings(I, probe, run.rtol)
        run.info["probe_tilt_rad"] = PROBE_TILT
    if om_lab <= 0:
        raise NumericFailure("the symmetry axis does not turn about +L")
    tol = exercise.tol_factor * run.rtol
    # a body rate that vanishes at alpha = pi/2: measured to an absolute accuracy of the spin's scale
    run.claim("Omega_body", rel=tol, abs=1e-3 * tol * p.omega)
    run.claim("theta_L", rel=tol, abs=1e-15)
    return {"Omega_body": om_body * p.omega, "omega_lab": om_lab * p.omega, "theta_L": theta_L}
