"""4.24's exact motion for the tests' references, written from the statement's physics (not from mech): the
axis n and the angular momentum L about the pivot in units of L3 = I3 omega_rot,

    dn/dt = k L x n,    dL/dt = n x g(t),    k = L3/I_A,  I_A = I1 + M l^2,
    g(t) = (l/L3) (F (cos wt, sin wt, 0) - M g z),  w = M g l/L3,

started from n = L = z; the events are the axis's horizontal passages, n_z = 0 on the way down and up
(the latter terminal)."""

import math


def exact_rhs(M, l, I1, I3, w3, F, g):
    """(rhs(t, y) for y = (n, L), w, k, L3)."""
    IA, L3 = I1 + M * l * l, I3 * w3
    w, k = M * g * l / L3, L3 / IA

    def rhs(t, y):
        nx, ny, nz, Lx, Ly, Lz = y
        fx, fy, fz = l * F * math.cos(w * t) / L3, l * F * math.sin(w * t) / L3, -M * g * l / L3
        return [k * (Ly * nz - Lz * ny), k * (Lz * nx - Lx * nz), k * (Lx * ny - Ly * nx),
                ny * fz - nz * fy, nz * fx - nx * fz, nx * fy - ny * fx]

    return rhs, w, k, L3


def horizontal_events():
    """(down, up): n_z crossing 0 downward, and upward (terminal), for scipy's solve_ivp."""

    def down(t, y):
        return y[2]

    def up(t, y):
        return y[2]

    down.direction, up.direction, up.terminal = -1, 1, True
    return down, up
