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
alpha remains: K alpha = b with K = I - [d]x^2 (symmetric positive definite), diagonal in the contact frame
(u = -d, e3 x u, e3: see ``_contact_frame``).  ``follow_batch`` integrates N disks at once
(numerics.batch.integrate_batch).  No exercise's answer here.
"""

from __future__ import annotations

import numpy as np

__all__ = ["cross", "dot", "rotation", "contact", "accelerations", "rates", "tilted_rates",
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


def _contact_frame(u0, u1, zeta, zeta_h, w0, w1, w2, I1, I3):
    """(alpha, f) in the contact frame (u, t, e3): the angular acceleration and the centre's acceleration of the
    rolling disk turning at w (body axes), with the floor's normal zb = R^T z in body axes, u = (zb1, zb2, 0)/|.|
    (so d = P - C = -u), zeta = zb3 and zeta_h = zeta/|(zb1, zb2)|.  Floats or arrays.

    Written in the contact frame (u, t = e3 x u, e3), where zb = (rho, 0, zeta) and w = (Wu, Wt, w3):
      e = the lab derivative of u = (p - u (u.p))/rho + w x u = (0, zeta Wu/rho, -Wt)   (p = zb' = zb x w),
      c = w x e = (-Wt^2 - w3 E, Wu Wt, Wu E)                                            (E = zeta Wu/rho),
      b = -w x I w - u x (zb + c) = (-dI Wt w3, zeta + Wu (E + dI w3), -Wu Wt)             (dI = I3 - I1),
    K alpha = b with K = I - [d]x^2, the inertia about the contact point, diagonal here (I1, I1 + 1, I3 + 1),
    and a = d x alpha - w x d' = c - u x alpha."""
    Wu, Wt = w0 * u0 + w1 * u1, w1 * u0 - w0 * u1
    E = zeta_h * Wu
    ct, c3 = Wu * Wt, Wu * E
    dI = I3 - I1
    au = (Wt * w2) * (-dI / I1)
    at = (zeta + Wu * (E + dI * w2)) * (1.0 / (I1 + 1.0))
    a3 = ct * (-1.0 / (I3 + 1.0))
    return (au, at, a3), (-(Wt * Wt + w2 * E), ct + a3, c3 - at)


def accelerations(Rm, w, I1, I3):
    """(alpha, a): the angular acceleration in body axes and the centre's acceleration in lab axes of the rolling
    disk with the attitude Rm (body -> lab) turning at w (body axes) (``_contact_frame``)."""
    z0, z1, z2 = Rm[2]
    h = 1.0 / (z0 * z0 + z1 * z1) ** 0.5
    u0, u1 = z0 * h, z1 * h
    (au, at, a3), (fu, ft, f3) = _contact_frame(u0, u1, z2, z2 * h, *w, I1, I3)
    # back to body axes: X = Xu u + Xt t + X3 e3, t = e3 x u = (-u1, u0, 0)
    al = (au * u0 - at * u1, au * u1 + at * u0, a3)
    f0, f1, f2 = fu * u0 - ft * u1, fu * u1 + ft * u0, f3
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = Rm
    return al, (r00 * f0 + r01 * f1 + r02 * f2, r10 * f0 + r11 * f1 + r12 * f2, r20 * f0 + r21 * f1 + r22 * f2)


def _quadratic_forms():
    """The constant (16, 28) matrix taking the products y_i q_k (i < 7: the rates w, then q) of the state
    (``tilted_rates``) to |q|^2 R (9 rows, row by row), q0^2 + q3^2, q1^2 + q2^2, |q|^2 and dq/dt = q (0, w)/2."""
    M = np.zeros((16, 7, 4))
    squares = {(0, 0): (1, 1, 1), (1, 1): (1, -1, -1), (2, 2): (-1, 1, -1), (3, 3): (-1, -1, 1)}
    for (a, b), signs in squares.items():  # the diagonal of |q|^2 R, and the sums of squares
        M[(0, 4, 8), 3 + a, b] = signs
        M[9 if a in (0, 3) else 10, 3 + a, b] = 1.0
        M[11, 3 + a, b] = 1.0
    # the off-diagonal of |q|^2 R: 2 (q_a q_b +- q_0 q_c), each row (a, b, c, sign)
    for row, (a, b, c, sign) in {1: (1, 2, 3, -1), 3: (1, 2, 3, 1), 2: (1, 3, 2, 1), 6: (1, 3, 2, -1),
                                 5: (2, 3, 1, -1), 7: (2, 3, 1, 1)}.items():
        M[row, 3 + a, b], M[row, 3, c] = 2.0, 2.0 * sign
    # dq/dt = q (0, w)/2: rows of (w index, q index, coefficient)
    for row, terms in enumerate((((0, 1, -1), (1, 2, -1), (2, 3, -1)), ((0, 0, 1), (2, 2, 1), (1, 3, -1)),
                                 ((1, 0, 1), (2, 1, -1), (0, 3, 1)), ((2, 0, 1), (1, 1, 1), (0, 2, -1))), start=12):
        for i, k, c in terms:
            M[row, i, k] = 0.5 * c
    return M.reshape(16, 28)


_FORMS = _quadratic_forms()


def rates(y, I1, I3):
    """The 13 rates of the state y (13 floats, or 13 x N: one column a disk)."""
    return tilted_rates(y, I1, I3)[0]


def tilted_rates(y, I1, I3):
    """(``rates`` (an array like y), the axis's vertical component n_z) of the state y (13, or 13 x N).

    The attitude, |q|^2 R, and dq/dt = q (0, w)/2 are quadratic in the state: one product of the state with the
    quaternion and one constant matrix (``_FORMS``) give them all; |(zb1, zb2)| = 2 sqrt((q0^2 + q3^2)(q1^2 +
    q2^2))/|q|^2 exactly, without the cancellation 1 - zb3^2.  The accelerations: ``_contact_frame``.

    |q| is left to drift (the attitude is that of q/|q|): a pull-back -(|q|^2 - 1) c q at a fixed rate c = 1 was
    stiff across a slowly turning disk's long steps (the step size underflowed), and at the attitude's rate it
    cost half again the steps; without it |q| stays within 4e-10 of 1 over 300 drawn runs at rtol 1e-8."""
    y = np.asarray(y, dtype=float)
    Z = _FORMS @ (y[0:7, None] * y[None, 3:7]).reshape((28,) + y.shape[1:])
    # one disk: the rest in plain floats (a fraction of the arrays' overhead); N disks: rows of N
    z, w = (Z.tolist(), y[0:3].tolist()) if y.ndim == 1 else (Z, y)
    inv = 1.0 / z[11]
    n0, n1, zeta = z[2] * inv, z[5] * inv, z[8] * inv  # the axis n in the lab (R's last column)
    s = 0.5 / (z[9] * z[10]) ** 0.5
    u0, u1, zh, h = z[6] * s, z[7] * s, z[8] * s, z[11] * s  # h = 1/|(zb1, zb2)|
    (au, at, a3), (fu, ft, f3) = _contact_frame(u0, u1, zeta, zh, w[0], w[1], w[2], I1, I3)
    out = np.empty_like(y)
    # alpha in body axes: X = Xu u + Xt t + X3 e3, t = e3 x u = (-u1, u0, 0)
    out[0], out[1], out[2] = au * u0 - at * u1, au * u1 + at * u0, a3
    out[3:7] = Z[12:16]
    out[7:10] = y[10:13]
    # a in the lab: u and t are there (z - zeta n) h and (n x z) h = (n1, -n0, 0) h
    G, H = f3 - fu * zh, ft * h
    out[10], out[11], out[12] = n0 * G + n1 * H, n1 * G - n0 * H, fu / h + f3 * zeta
    return out, zeta


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
    if y.shape[1] == 1:  # one disk alone: its state as one column (``tilted_rates`` in plain floats)
        def rhs(s, yy, span=float(span[0]), t0=float(t0[0])):
            try:
                f, nz = tilted_rates(yy[:, 0], I1, I3)
            except ArithmeticError:  # a trial stage off the floor's domain: NaN, and the step is refused
                return np.full(yy.shape, np.nan)
            x = abs(nz - t0)
            return np.asarray(f, dtype=float)[:, None] * (span * _held(min(x / lost - 1.0, 1.0)) if x > lost
                                                          else span)
    else:
        def rhs(s, yy, span=span, t0=t0):
            f, nz = tilted_rates(yy, I1, I3)
            x = np.abs(nz - t0)
            if np.maximum.reduce(x) > lost:
                return np.asarray(f) * (span * _held(np.minimum(np.maximum(x / lost - 1.0, 0.0), 1.0)))
            return np.asarray(f) * span

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
            f, nz = tilted_rates(yy, I1, I3)
            x = abs(nz - t0)
            return np.array(f) * (span * _held(min(x / lost - 1.0, 1.0)) if x > lost else span)

        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            traj = integrate(rhs, s_span, y[:, k], rtol=rtol, atol=atol[:, k], integrator=integrator)
        runs.append(traj)
        out[:, k] = traj.y_end
    return out
