"""4.36 Lagrangian and Hamiltonian in a non-rotating accelerating frame.

Analytic: with the lab velocity v + v0(t), L = m (v + v0)^2 / 2 - k x^2 / 2, so
the canonical momentum p = dL/dv = m (v + v0) is the lab momentum, not m v;
H = p v - L = m (v^2 - v0^2)/2 + k x^2/2, which differs from the energy
E = m (v + v0)^2/2 + k x^2/2 by m v0 (v + v0) (H = E only when the particle is
at rest in the lab).  Lagrange: d/dt[m (v + v0)] = -k x, i.e.
m a = -k x - m a0: Eq. (4.92) with the inertial force -m a0 and no rotation.

Numeric: the Lagrangian is coded as a function of (x, v, t), with
v0(t) = v0 + a0 t, and differentiated by hyper-dual numbers (exact first and
second derivatives, no step, no truncation, no cancellation): p = L_v,
H = p v - L, E from the lab velocity, and the acceleration from the
Euler-Lagrange equation L_vv a = L_x - L_vx v - L_vt.
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise

exercise = Exercise(
    "4.36",
    formulas=[
        "L = m (v + v₀)²/2 - k x²/2",
        "p = ∂L/∂v = m (v + v₀)  (≠ m v: the lab momentum)",
        "H = p v - L = m (v² - v₀²)/2 + k x²/2",
        "E = m (v + v₀)²/2 + k x²/2 = H + m v₀ (v + v₀)",
        "m a = -k x - m a₀  (Eq. 4.92 with the inertial force -m a₀)",
    ],
)


@exercise.analytic
def analytic(p):
    return {
        "p": p.m * (p.v + p.v0),
        "H": 0.5 * p.m * (p.v - p.v0) * (p.v + p.v0) + 0.5 * p.k * p.x**2,
        "E": 0.5 * p.m * (p.v + p.v0) ** 2 + 0.5 * p.k * p.x**2,
        "a": -p.k * p.x / p.m - p.a0,
    }


class HyperDual:
    """a + b e1 + c e2 + d e1 e2 with e1^2 = e2^2 = 0: exact first and mixed second derivatives."""

    __slots__ = ("a", "b", "c", "d")

    def __init__(self, a, b=0.0, c=0.0, d=0.0):
        self.a, self.b, self.c, self.d = float(a), float(b), float(c), float(d)

    @staticmethod
    def lift(u):
        return u if isinstance(u, HyperDual) else HyperDual(u)

    def __add__(self, o):
        o = HyperDual.lift(o)
        return HyperDual(self.a + o.a, self.b + o.b, self.c + o.c, self.d + o.d)

    __radd__ = __add__

    def __neg__(self):
        return HyperDual(-self.a, -self.b, -self.c, -self.d)

    def __sub__(self, o):
        return self + (-HyperDual.lift(o))

    def __rsub__(self, o):
        return HyperDual.lift(o) - self

    def __mul__(self, o):
        o = HyperDual.lift(o)
        return HyperDual(
            self.a * o.a,
            self.a * o.b + self.b * o.a,
            self.a * o.c + self.c * o.a,
            self.a * o.d + self.b * o.c + self.c * o.b + self.d * o.a,
        )

    __rmul__ = __mul__


def _lagrangian(m, k, v0, a0):
    """L(x, v, t) = T_lab - U, the lab velocity of the particle being v + v0(t)."""

    def L(x, v, t):
        frame_velocity = v0 + a0 * t
        u = v + frame_velocity
        return 0.5 * m * (u * u) - 0.5 * k * (x * x)

    return L


@exercise.numeric
def numeric(p, run):
    L = _lagrangian(p.m, p.k, p.v0, p.a0)
    x, v, t = p.x, p.v, 0.0
    # v seeded in both directions: L, L_v, L_vv
    r_vv = L(HyperDual(x), HyperDual(v, 1.0, 1.0), HyperDual(t))
    # v along e1, x along e2: L_x (e2 part) and L_vx
    r_vx = L(HyperDual(x, 0.0, 1.0), HyperDual(v, 1.0), HyperDual(t))
    # v along e1, t along e2: L_vt
    r_vt = L(HyperDual(x), HyperDual(v, 1.0), HyperDual(t, 0.0, 1.0))
    lag, L_v, L_vv = r_vv.a, r_vv.b, r_vv.d
    L_x, L_vx, L_vt = r_vx.c, r_vx.d, r_vt.d
    mom = L_v
    # H = p v - L with the particle's lab kinetic energy from its lab velocity
    ham = mom * v - lag
    lab_velocity = v + (p.v0 + p.a0 * t)
    energy = 0.5 * p.m * lab_velocity**2 + 0.5 * p.k * x**2
    acc = (L_x - L_vx * v - L_vt) / L_vv
    run.method = "hyper-dual differentiation"
    eps = np.finfo(float).eps
    # everything is a handful of roundings: claim round-off, with absolute floors for outputs that can vanish
    scale_T = 0.5 * p.m * (p.v**2 + p.v0**2) + 0.5 * p.k * p.x**2 + p.m * abs(p.v * p.v0)
    run.claim("p", rel=1e-13, abs=16 * eps * p.m * (abs(p.v) + abs(p.v0)))
    run.claim("H", rel=1e-13, abs=16 * eps * scale_T)
    run.claim("E", rel=1e-13, abs=16 * eps * scale_T)
    run.claim("a", rel=1e-13, abs=16 * eps * (p.k * abs(p.x) / p.m + abs(p.a0)))
    run.info["L"] = lag
    run.info["E_minus_H"] = energy - ham
    return {"p": mom, "H": ham, "E": energy, "a": acc}
