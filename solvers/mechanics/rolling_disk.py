"""A thin disk rolling without slipping on a horizontal floor: Newton-Euler with the rolling constraint, written
once for one disk (floats) or N disks at once (numpy arrays of N numbers, one per disk).

Units: the disk's radius, its mass and g are 1; ``I1`` is its moment of inertia about a diameter, ``I3`` about
its symmetry axis (body z).  Vectors are 3-tuples of components (each a float or an array of N); a matrix is a
tuple of 3 rows.  The state (13 components) is the body-axis rates (w1, w2, w3), the attitude quaternion
(q0..q3, scalar first, body -> lab), the centre's position and its velocity (lab axes, z up).

The contact point P is the lowest rim point: P - C = d = -m/|m| with m = z - (z.n) n (n the symmetry axis),
whose place on the rim moves as the disk turns (its geometric velocity d' enters the rolling constraint).
Unknowns at an instant: the centre's acceleration a, the angular acceleration alpha, the contact force F:
    a - F = -z,   I alpha - d x F = -omega x I omega,   a + alpha x d = -omega x d'
(the rolling constraint v_C + omega x d = 0 differentiated once).  F and a eliminated, a 3 x 3 system for
alpha remains: K alpha = b with K = I - [d]x^2 (symmetric positive definite), written in body axes (see
``accelerations``).  ``follow_batch`` integrates N disks at once (numerics.batch.integrate_batch).  No
exercise's answer here.
"""

from __future__ import annotations

import numpy as np

__all__ = ["cross", "dot", "rotation", "contact", "accelerations", "quaternion_rate", "rates", "tilted_rates",
           "steady_rolling", "tilt_acceleration", "monitors", "drifts", "follow_batch"]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def rotation(q0, q1, q2, q3):
    """The rotation (rows) of the quaternion, normalized first."""
    s = 2.0 / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    x1, x2, x3 = s * q1, s * q2, s * q3
    q11, q22, q33, q12, q13, q23 = q1 * x1, q2 * x2, q3 * x3, q1 * x2, q1 * x3, q2 * x3
    q01, q02, q03 = q0 * x1, q0 * x2, q0 * x3
    return ((1.0 - (q22 + q33), q12 - q03, q13 + q02),
            (q12 + q03, 1.0 - (q11 + q33), q23 - q01),
            (q13 - q02, q23 + q01, 1.0 - (q11 + q22)))


def contact(n):
    """(d, |m|): d = P - C for the symmetry axis n (m = z - (z.n) n = n x (z x n), written without the
    cancellation 1 - n_z^2)."""
    wx, wy, wz = -n[2] * n[0], -n[2] * n[1], n[0] * n[0] + n[1] * n[1]
    wn = (wx * wx + wy * wy + wz * wz) ** 0.5
    return (-wx / wn, -wy / wn, -wz / wn), wn


def accelerations(Rm, w, I1, I3):
    """(alpha, a): the angular acceleration in body axes and the centre's acceleration in lab axes of the rolling
    disk with the attitude Rm (body -> lab) turning at w (body axes).

    Written in body axes, where the symmetry axis is e3 and the floor's normal is zb = R^T z: m = zb - (zb.e3) e3
    = (zb1, zb2, 0), d = -m/|m| lies in the body xy plane, and the time derivative (in the lab) of a body vector
    v has the body components v' + w x v.  With n = e3 and d3 = 0, K = (I1 + |d|^2) 1 + (I3 - I1) e3 e3^T - d d^T
    is diagonal on the axes d, e3 x d, e3."""
    z0, z1, z2 = Rm[2]
    w0, w1, w2 = w
    h = 1.0 / (z0 * z0 + z1 * z1) ** 0.5
    u0, u1 = z0 * h, z1 * h  # d = -u
    # zb' = -w x zb (z is fixed in the lab); u = (zb1, zb2, 0)/|.|, u' = (p' - u (u.p'))/|.|
    p0, p1 = z1 * w2 - z2 * w1, z2 * w0 - z0 * w2
    up = u0 * p0 + u1 * p1
    # the body components of the lab derivative of u: u' + w x u (d' is its opposite)
    e0 = (p0 - u0 * up) * h - w2 * u1
    e1 = (p1 - u1 * up) * h + w2 * u0
    e2 = w0 * u1 - w1 * u0
    # c = w x u' (= -w x d')
    c0, c1, c2 = w1 * e2 - w2 * e1, w2 * e0 - w0 * e2, w0 * e1 - w1 * e0
    # b = -w x I w + d x (zb - w x d') = -w x I w - u x (zb + c)
    dI = I3 - I1
    g0, g1, g2 = z0 + c0, z1 + c1, z2 + c2
    b0 = -(u1 * g2 + dI * w1 * w2)
    b1 = u0 * g2 + dI * w0 * w2
    b2 = u1 * g0 - u0 * g1
    # K alpha = b, K = I - [d]x^2 the inertia about the contact point, whose principal axes are d (moment I1),
    # the rim's tangent e3 x d (I1 + |d|^2) and e3 (I3 + |d|^2), |d| = 1:
    # alpha = b/(I1 + 1) + (d.b) d (1/I1 - 1/(I1 + 1)) in the plane, b3/(I3 + 1) along e3
    kt, kd = 1.0 / (I1 + 1.0), 1.0 / I1 - 1.0 / (I1 + 1.0)
    ub = (u0 * b0 + u1 * b1) * kd
    a0, a1, a2 = b0 * kt + ub * u0, b1 * kt + ub * u1, b2 * (1.0 / (I3 + 1.0))
    # a = d x alpha - w x d' = c - u x alpha (body), then to the lab
    f0, f1, f2 = c0 - u1 * a2, c1 + u0 * a2, c2 - u0 * a1 + u1 * a0
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = Rm
    return (a0, a1, a2), (r00 * f0 + r01 * f1 + r02 * f2, r10 * f0 + r11 * f1 + r12 * f2,
                          r20 * f0 + r21 * f1 + r22 * f2)


def quaternion_rate(q, w):
    """dq/dt = q (0, w) / 2 for body rates w.  |q| is left to drift (the attitude is that of q/|q|: ``rotation``
    normalizes): a pull-back -(|q|^2 - 1) c q at a fixed rate c = 1 was stiff across a slowly turning disk's
    long steps (the step size underflowed), and at the attitude's rate it cost half again the steps; without
    it |q| stays within 4e-10 of 1 over 300 drawn runs at rtol 1e-8."""
    q0, q1, q2, q3 = q
    w1, w2, w3 = w
    return (-0.5 * (q1 * w1 + q2 * w2 + q3 * w3), 0.5 * (q0 * w1 + q2 * w3 - q3 * w2),
            0.5 * (q0 * w2 - q1 * w3 + q3 * w1), 0.5 * (q0 * w3 + q1 * w2 - q2 * w1))


def rates(y, I1, I3):
    """The 13 rates of the state y (a sequence of 13 floats, or of 13 arrays of N)."""
    return tilted_rates(y, I1, I3)[0]


def tilted_rates(y, I1, I3):
    """(``rates``, the axis's vertical component n_z) of the state y."""
    w = (y[0], y[1], y[2])
    q = (y[3], y[4], y[5], y[6])
    Rm = rotation(*q)
    al, a = accelerations(Rm, w, I1, I3)
    # the body components of omega change at alpha's body components (omega x omega = 0)
    return [*al, *quaternion_rate(q, w), y[10], y[11], y[12], *a], Rm[2][2]


def steady_rolling(theta, Rs, Om):
    """The disk leaning by theta toward the centre of a circle of radius Rs (its contact at (Rs, 0, 0)), all
    turning at Om about z: (Rm, omega, C, v_C, spin, residual), with the spin about the axis solved from the
    rolling condition v_C + (Om z + spin n) x (P - C) = 0 (least squares; ``residual``: what is left of it,
    relative to v_C's part).  Floats or arrays."""
    s, c = np.sin(theta), np.cos(theta)
    zero, one = 0.0 * s, 1.0 + 0.0 * s
    ey, ez = (zero, one, zero), (zero, zero, one)
    n = (c, zero, s)
    u = cross(n, ey)  # in the disk's plane, up: body y
    Rm = tuple((ey[i], u[i], n[i]) for i in range(3))  # body x, y, z as columns
    P = (Rs + zero, zero, zero)
    C = tuple(P[i] + u[i] for i in range(3))
    vC = tuple(Om * x for x in cross(ez, C))
    d = tuple(P[i] - C[i] for i in range(3))
    zd = cross(ez, d)
    base = tuple(vC[i] + Om * zd[i] for i in range(3))
    k = cross(n, d)
    spin = -dot(base, k) / dot(k, k)
    res = tuple(base[i] + spin * k[i] for i in range(3))
    residual = dot(res, res) ** 0.5 / np.maximum(dot(base, base) ** 0.5, 1e-300)
    omega = tuple(Om * ez[i] + spin * n[i] for i in range(3))
    return Rm, omega, C, vC, spin, residual


def tilt_acceleration(theta, Rs, Om, I1, I3):
    """d^2(n . z)/dt^2 of the disk started in ``steady_rolling``'s state: zero where that state is a motion."""
    Rm, omega, _, _, _, _ = steady_rolling(theta, Rs, Om)
    w = tuple(Rm[0][j] * omega[0] + Rm[1][j] * omega[1] + Rm[2][j] * omega[2] for j in range(3))
    al, _ = accelerations(Rm, w, I1, I3)
    # in body axes, n = e3 and z = zb: zb . (alpha x e3 + w x (w x e3))
    e3 = (0.0, 0.0, 1.0)
    return dot(Rm[2], cross(al, e3)) + dot(Rm[2], cross(w, cross(w, e3)))


def monitors(Y, I1, I3):
    """(n, d, slip velocity, contact height, energy, omega) of states Y (13 x ...: any trailing shape): the axis,
    P - C, the velocity of the material point at the contact, its height, the kinetic energy plus the weight's
    potential measured from the contact point, and the angular velocity in lab axes (the rolling constraint is held at the acceleration level only,
    so the contact leaves the floor slowly: measured from it the energy checks the dynamics alone)."""
    Rm = rotation(Y[3], Y[4], Y[5], Y[6])
    w = (Y[0], Y[1], Y[2])
    omega = tuple(Rm[i][0] * w[0] + Rm[i][1] * w[1] + Rm[i][2] * w[2] for i in range(3))
    n = (Rm[0][2], Rm[1][2], Rm[2][2])
    d, _ = contact(n)
    od = cross(omega, d)
    slip = (Y[10] + od[0], Y[11] + od[1], Y[12] + od[2])
    v2 = Y[10] * Y[10] + Y[11] * Y[11] + Y[12] * Y[12]
    energy = 0.5 * v2 + 0.5 * (I1 * (w[0] * w[0] + w[1] * w[1]) + I3 * w[2] * w[2]) - d[2]
    return n, d, slip, Y[9] + d[2], energy, omega


def drifts(Y, I1, I3, n3z0, tilt_tol, scale, E0):
    """(tilt, slip speed / scale, contact height, energy): the worst drifts over the samples Y (13 x K x N,
    one column of K samples per run, from the tilt n3z0 and the energy E0; the slip speed relative to
    ``scale``) up to the first whose tilt is off by tilt_tol (the conserved ones there too: the motion is still
    followed), and that sample's index (K: none is)."""
    n, _, slip, height, energy, _ = monitors(Y, I1, I3)
    tilt = np.abs(n[2] - n3z0)
    off = ~(tilt <= tilt_tol)  # NaN (a run not followed further) is off too
    k = np.where(off.any(axis=0), np.argmax(off, axis=0), off.shape[0])
    upto = np.arange(off.shape[0])[:, None] <= k
    before = np.arange(off.shape[0])[:, None] < k
    roll = (slip[0] ** 2 + slip[1] ** 2 + slip[2] ** 2) ** 0.5 / scale
    e = np.abs(energy - E0) / np.maximum(np.abs(E0), 1.0)
    worst = [np.where(m, np.nan_to_num(x), 0.0).max(axis=0) for m, x in
             ((before, tilt), (upto, roll), (upto, np.abs(height)), (upto, e))]
    return worst, k


def _held(x):
    """1 at x = 0 to 0 at x = 1, twice continuously differentiable (so that a step across it is resolved
    in a few steps: a jump in the rates would need steps of atol over the jump, below the time's round-off)."""
    return 1.0 - x * x * x * (10.0 + x * (6.0 * x - 15.0))


def follow_batch(y0, spans, I1, I3, checkpoints, *, rtol, atol, tilt0, tilt_tol, lost=1e-3, integrator=None):
    """N disks integrated at once (``integrate_batch``, DOP853), disk k from y0[:, k] over [0, spans[k]]: all on
    the shared interval s in [0, 1] (t = spans[k] s).  Returns (Y, steps, runs): the states (K + 1, 13, N) at
    s = 0 and at the K increasing ``checkpoints`` (the last 1), the accepted steps, and the integrations (each
    with ``nfev`` and ``method``).  ``integrator``: forced on every leg, disk by disk (``ode.integrate``:
    ``mech bench``).

    A disk whose tilt n.z leaves ``tilt0`` by more than ``tilt_tol`` at a checkpoint is not followed further
    (NaN after it); within a leg, its rates are brought to zero (smoothly, ``_held``) as the tilt goes from
    ``lost`` to twice it off (it is falling away from the motion followed, toward the flat disk where the
    contact is undefined), so that one falling disk does not stop the others.  ``atol``: per component and disk (13, N).  A single disk's rates are
    evaluated in plain floats."""

    y0 = np.asarray(y0, dtype=float)
    N = y0.shape[1]
    spans, tilt0 = np.asarray(spans, dtype=float), np.asarray(tilt0, dtype=float)
    Y = np.full((len(checkpoints) + 1, 13, N), np.nan)
    Y[0] = y0
    live = np.arange(N)
    y = y0.copy()
    s0, h, steps, runs = 0.0, None, 0, []
    for j, s1 in enumerate(checkpoints):
        span, t0 = spans[live], tilt0[live]

        if integrator is not None:  # forced: each disk alone, the leg by ``ode.integrate``
            y = _forced_leg(y, (s0, s1), span, t0, I1, I3, rtol, atol[:, live], lost, integrator, runs)
        else:
            y, h, n = _batched_leg(y, (s0, s1), span, t0, I1, I3, rtol, atol[:, live], lost, h, runs)
            steps += n
        Y[j + 1][:, live] = y
        R22 = rotation(y[3], y[4], y[5], y[6])[2][2]
        keep = np.abs(R22 - tilt0[live]) <= tilt_tol
        live, y = live[keep], y[:, keep]
        s0 = s1
        if live.size == 0:
            break
    return Y, steps, runs


def _batched_leg(y, leg, span, t0, I1, I3, rtol, atol, lost, h, runs):
    """One leg of the live disks by the batched DOP853: (their states at its end, the next first step, the
    steps it took); the integration is appended to ``runs``."""
    from mech.solvers.numerics.batch import integrate_batch

    s0, s1 = leg
    if y.shape[1] == 1:  # one disk alone: its rates in plain floats (a fraction of the arrays' overhead)
        def rhs(s, yy, span=float(span[0]), t0=float(t0[0])):
            try:
                f, nz = tilted_rates(yy[:, 0].tolist(), I1, I3)
            except ArithmeticError:  # a trial stage off the floor's domain: NaN, and the step is refused
                return np.full(yy.shape, np.nan)
            return np.array(f)[:, None] * (span * _held(min(abs(nz - t0) / lost - 1.0, 1.0)) if
                                           abs(nz - t0) > lost else span)
    else:
        def rhs(s, yy, span=span, t0=t0):
            f, nz = tilted_rates(yy, I1, I3)
            x = np.abs(nz - t0)
            if (x > lost).any():
                return np.array(f) * (span * _held(np.minimum(np.maximum(x / lost - 1.0, 0.0), 1.0)))
            return np.array(f) * span

    # a trial stage may leave the floor's domain (NaN, inf): integrate_batch refuses that step and shrinks it
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        got = integrate_batch(rhs, (s0, s1), y, rtol=rtol, atol=atol, first_step=h)
    runs.append(got)
    return got.y_end, (s1 - s0) / max(got.steps, 1), got.steps


def _forced_leg(y, s_span, span, t0, I1, I3, rtol, atol, lost, integrator, runs):
    """One leg of ``follow_batch`` with an integrator forced, disk by disk (the rates of one disk, held as
    ``follow_batch`` holds them when its tilt is lost)."""
    from mech.solvers.numerics.ode import integrate

    out = np.empty_like(y)
    for k in range(y.shape[1]):
        def rhs(s, yy, span=float(span[k]), t0=float(t0[k])):
            f, nz = tilted_rates(list(yy), I1, I3)
            x = abs(nz - t0)
            return np.array(f) * (span * _held(min(x / lost - 1.0, 1.0)) if x > lost else span)

        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            traj = integrate(rhs, s_span, y[:, k], rtol=rtol, atol=atol[:, k], integrator=integrator)
        runs.append(traj)
        out[:, k] = traj.y_end
    return out
