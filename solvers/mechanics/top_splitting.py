"""The axis of a fast symmetric top under its weight and a horizontal force turning about the vertical, by
splitting: the steps of Likharev's exercise 4.24's resolved route.

The scaled state is the unit axis n and the angular momentum L about the pivot in units of L3 = I3 omega3
(so |L| = 1 + O(eps^2)).  The exact equations of the symmetric top (solvers.mechanics.tops) split into
two flows each solved in closed form: the free motion (L fixed, n turning about L at k |L|, k = L3/I_A:
the nutation, a rotation done exactly) and a kick of L by the torque n x g(t) at fixed n, with
g = -a z + b (cos w t, sin w t, 0) (a = M g l/L3, b = l F/L3, w the force's turning rate).

Why a splitting and not an adaptive Runge-Kutta: a fast top nutates thousands of times over the overturn
the exercise asks about; an explicit Runge-Kutta must resolve every nutation period with many stages of
a stiff-ish oscillation, while the splitting does each period's rotation exactly and keeps L . n to
round-off (the kicks are normal to n).  The resolved route composes the Strang step (``fine_stepper``)
into Yoshida's 6th-order or Kahan and Li's 8th-order scheme (solvers.numerics.splitting).

Very fast tops (``strang_stepper``): away from the events, coarse kick-rotate-kick steps of many
nutation periods, with the rotation k H on a root of x cot x = 1 (x = k H/2, ``tan_root``), where the
kicks rebuild the forced nutation.  With Om = hypot(a, b) the plain step's error grows as (Om H)^2;
three corrections, each cancelling one term of it, are derived from the slow motion (the torque scaled
by 1 - (H^2/12)(3 (g.n)^2 - Om^2), the slow turn of n about g; b by x/tan x with x = w H/2, the force's
turn; L moved by (H^2/4) dtau/dt (tau = n x g) wherever the step size changes, ``retune``, else the
offset becomes a free nutation).  A fourth, a scaled by 1 - (b H)^2/3 (the weight's precession slip),
is empirical: its coefficient was fitted on the measured error, not derived; it removes most of the
remaining (Om H)^2 term where the weight dominates, and the coarse step is sized by (Om H)^3 = 2 rtol
and 0.25 Om b H^2 = rtol as if it removed none of it (``coarse_step``).

Empirical constants, and why they are safe.  The step counts (``fine_steps``: m6 and m8 per nutation
period) and the coarse step's bound are calibrations of how many steps reach a requested accuracy,
measured against runs at a much finer step on the tops listed at each; they choose a step, they claim
nothing.  What the exercise claims is checked on every solve by the cross-check's rerun at rtol/10: a
calibration that fell short on some top would show as a value that moves by more than its claim, a
loud "unreliable" failure, never a silent wrong answer.
"""

from __future__ import annotations

import math

from mech.core.budget import check as budget_check
from mech.solvers.numerics.splitting import KAHAN_LI8, YOSHIDA6, crossing, stages

__all__ = ["fine_steps", "fine_stepper", "strang_stepper", "retune", "coarse_step", "tan_root", "coarse_ladder",
           "Dips", "lowest_nz", "FineEvents", "march"]

K8_COEF, K8_EXP, K8_MIN = 2.3, 0.2, 2.5


def fine_steps(eps, rtol):
    """The fine splitting: (its weights, its order, steps per nutation period m), the cheaper in stages of
    Yoshida's 6th-order composition, its m calibrated on its own error (~ eps^1.6 m^-6 per overturn), and
    Kahan and Li's 8th-order one, m = 2.3 (eps/2.7e-3)^0.2 (1e-6/rtol)^(1/8) (at least 2.5): against runs of
    their 15-step 8th-order composition at 2.5 times its m (rtol 1e-8), its largest error (t_down, t_up
    relative, phi_lead, cos_min absolute) stayed at or below the 6th-order's at rtol 1e-6 and 1e-7 on the
    tops measured (the hard cases; omega_rot 150-1700 rad/s with F from the slip's bound to eps_F = 0.05;
    draws around the defaults), or below 0.03 rtol where that was smaller: at the weak-force hard case 0.67 rtol against 2.05 (rtol 1e-6) and 1.32
    against 3.68 (1e-7), at 42.5 and 52 stages per nutation period against 63 and 84.  It is chosen where
    eps >~ 3e-4."""
    m6 = max(4, math.ceil(8.0 * (eps / 2.7e-3) ** 0.27 * (1e-6 / rtol) ** (1.0 / 6.0)))
    m8 = max(K8_MIN, K8_COEF * (eps / 2.7e-3) ** K8_EXP * (1e-6 / rtol) ** 0.125)
    if len(KAHAN_LI8) * m8 < len(YOSHIDA6) * m6:
        return KAHAN_LI8, 8, m8
    return YOSHIDA6, 6, m6


def fine_stepper(k, a, b, w, h, weights=YOSHIDA6):
    """One splitting step of size hh (<= h) for the scaled state n, L (L in units of L3):
    free motion: n turns about L at k |L|; kick: L += c n x (-a z + b (cos wt, sin wt, 0)).

    The stages' constants (kick weights times a and b, the force's direction at each kick's time
    relative to the step's start, the nutation's rate times each rotation's length) are made once for
    the full step h, whose thousands of repetitions are the run's cost: a step then calls cos and sin of
    w t once (the force at each kick is that direction turned by the kick's offset) and is one pass over
    the stages with nothing but arithmetic and the rotation's own sqrt, cos, sin."""
    kw, offsets, cs = stages(weights)  # kick lengths, their times after the step's start, drift lengths (per hh)
    cos, sin, sqrt = math.cos, math.sin, math.sqrt

    def constants(hh):
        # per kick: (c a, c b cos(w o), c b sin(w o)) with c = its weight times hh, o its offset; per rotation
        # the nutation's angle per unit |L|
        kicks = [(c * hh * a, c * hh * b * cos(w * o * hh), c * hh * b * sin(w * o * hh)) for c, o in zip(kw, offsets)]
        return [(*kick, k * d * hh) for kick, d in zip(kicks[:-1], cs)], kicks[-1]

    made = {h: constants(h)}  # the full step's, and the last other size's (a run of substeps)

    def step(n, L, t, hh):
        got = made.get(hh)
        if got is None:
            if len(made) > 1:
                made.pop(next(x for x in made if x != h))
            got = made[hh] = constants(hh)
        body, (ca, kc, ks) = got
        nx, ny, nz = n
        Lx, Ly, Lz = L
        LN = Lx * nx + Ly * ny + Lz * nz  # L . n: the kicks are normal to n and the turns are about L
        C, S = cos(w * t), sin(w * t)
        for ca_i, kc_i, ks_i, kr in body:
            # kick: L += c n x (-a z + f), c f = (C kc - S ks, S kc + C ks) the force at the kick's time
            fx = C * kc_i - S * ks_i
            fy = S * kc_i + C * ks_i
            Lx -= ca_i * ny + nz * fy
            Ly += nz * fx + ca_i * nx
            Lz += nx * fy - ny * fx
            # free motion: n turns about L by kr |L|: n cos + (L x n) sin/|L| + L (L . n)(1 - cos)/|L|^2
            L2 = Lx * Lx + Ly * Ly + Lz * Lz
            Ln = sqrt(L2)
            th = kr * Ln
            ct, st = cos(th), sin(th)
            s1 = st / Ln
            s2 = LN * (1.0 - ct) / L2
            nx, ny, nz = (nx * ct + (Ly * nz - Lz * ny) * s1 + Lx * s2,
                          ny * ct + (Lz * nx - Lx * nz) * s1 + Ly * s2,
                          nz * ct + (Lx * ny - Ly * nx) * s1 + Lz * s2)
        fx = C * kc - S * ks
        fy = S * kc + C * ks
        Lx -= ca * ny + nz * fy
        Ly += nz * fx + ca * nx
        Lz += nx * fy - ny * fx
        s = 1.0 / sqrt(nx * nx + ny * ny + nz * nz)  # round-off only: the rotations keep |n| = 1
        return (nx * s, ny * s, nz * s), (Lx, Ly, Lz), t + hh

    return step


def strang_stepper(k, a, b, w):
    """Kick-rotate-kick (Strang) step of size hh for the same scaled state: the coarse step of a very
    fast top, whose free rotation (at the rate k of |L| = L3) may turn n by many radians per step.
    Modified kicks (see the module's notes): the force's rate b scaled by x/tan x (x = w hh/2), and the
    torque n x g (g = -a z + b f) by 1 - (hh^2/12)(3 (g.n)^2 - |g|^2); both cancel O(hh^2) errors of the
    slow motion that the plain step makes."""
    a0, b0 = a, b
    made = {}  # per step size: its constants (a few sizes a run: the ladder's)
    last = [None, 0.0, 0.0]  # the force's direction (cos w t, sin w t) at the last step's end t

    def constants(hh):
        c = 0.5 * hh
        q = hh * hh / 12.0
        x = 0.5 * w * hh
        # x/tan x: for |x| < 1e-8 it is 1 - x^2/3 = 1 to double precision, which tan would not give for a
        # subnormal x (M 1e-320 times the default: tan(x) ulps are a part in 1e3 of x)
        b = b0 * x / math.tan(x) if abs(x) > 1e-8 else b0
        a = a0 * (1.0 - (b0 * hh) ** 2 / 3.0)
        # the rate k, not k |L|: |L| = 1 + O(eps^2) on the exact motion, but the half kick tilts L off n by
        # H |torque|/2, so |L| here exceeds 1 by (H Om)^2/8, which would detune the step's rotation
        # 2 x (x cot x = 1) by 2 x (H Om)^2/8 and, through d(x cot x)/dx = -x, spoil the forced nutation
        th = k * hh
        return c, q, b, a, a * a + b * b, math.cos(th), math.sin(th)

    def step(n, L, t, hh):
        nx, ny, nz = n
        Lx, Ly, Lz = L
        got = made.get(hh)
        if got is None:
            if len(made) > 8:
                made.clear()
            got = made[hh] = constants(hh)
        c, q, b, a, Om2, ct, st = got
        if last[0] == t:  # the previous step ended here: its force's direction, not cos and sin again
            C, S = last[1], last[2]
        else:
            C, S = math.cos(w * t), math.sin(w * t)
        fx, fy = b * C, b * S
        cc = c * (1.0 - q * (3.0 * (fx * nx + fy * ny - a * nz) ** 2 - Om2))
        Lx += cc * (-a * ny - nz * fy)
        Ly += cc * (nz * fx + a * nx)
        Lz += cc * (nx * fy - ny * fx)
        Ln = math.sqrt(Lx * Lx + Ly * Ly + Lz * Lz)
        ux, uy, uz = Lx / Ln, Ly / Ln, Lz / Ln
        dd = (ux * nx + uy * ny + uz * nz) * (1.0 - ct)
        cx, cy, cz = uy * nz - uz * ny, uz * nx - ux * nz, ux * ny - uy * nx
        nx, ny, nz = nx * ct + cx * st + ux * dd, ny * ct + cy * st + uy * dd, nz * ct + cz * st + uz * dd
        t2 = t + hh
        C, S = math.cos(w * t2), math.sin(w * t2)
        last[0], last[1], last[2] = t2, C, S
        fx, fy = b * C, b * S
        cc = c * (1.0 - q * (3.0 * (fx * nx + fy * ny - a * nz) ** 2 - Om2))
        Lx += cc * (-a * ny - nz * fy)
        Ly += cc * (nz * fx + a * nx)
        Lz += cc * (nx * fy - ny * fx)
        s = 1.0 / math.sqrt(nx * nx + ny * ny + nz * nz)
        return (nx * s, ny * s, nz * s), (Lx, Ly, Lz), t2

    return step


def retune(a, b, w, n, L, t, dH2):
    """Move L between the forced nutations of two step sizes (dH2 = H_new^2 - H_old^2, H = 0 for the fine
    steps): at its kick boundaries a Strang step of size H holds L - n off the exact forced value by
    (H^2/4) dtau/dt (tau = n x g, dtau/dt = tau x g + n x dg/dt on the slow motion), across n."""
    nx, ny, nz = n
    fx, fy = b * math.cos(w * t), b * math.sin(w * t)
    gx, gy, gz = fx, fy, -a
    tx, ty, tz = ny * gz - nz * gy, nz * gx - nx * gz, nx * gy - ny * gx
    dgx, dgy = -w * fy, w * fx
    dx = ty * gz - tz * gy + (-nz * dgy)
    dy = tz * gx - tx * gz + nz * dgx
    dz = tx * gy - ty * gx + (nx * dgy - ny * dgx)
    p = dx * nx + dy * ny + dz * nz
    c = 0.25 * dH2
    return n, (L[0] + c * (dx - p * nx), L[1] + c * (dy - p * ny), L[2] + c * (dz - p * nz))


def coarse_step(a, b, rtol):
    """The largest coarse step for rtol (Om = hypot(a, b)): the modified Strang step's relative errors,
    measured on six tops (a/b = 0.8-233), stay below 0.5 (Om H)^3; 0.25 Om b H^2, what phi_lead's was before
    the weight's correction, is kept as a second bound (see the module's notes)."""
    Om = math.hypot(a, b)
    return min((2.0 * rtol) ** (1.0 / 3.0) / Om, 2.0 * math.sqrt(rtol / (Om * b)))


def tan_root(j):
    """j-th positive root of tan x = x (j >= 1): x cot x = 1."""
    x = (j + 0.5) * math.pi - 1.0 / ((j + 0.5) * math.pi)
    for _ in range(30):
        x -= (math.tan(x) - x) / math.tan(x) ** 2
    return x


def coarse_ladder(a, b, k, rtol):
    """The coarse Strang steps (see the docstring): the largest from ``coarse_step`` far from the events,
    halved towards them, each with its rotation k H on a root of x cot x = 1 (x = k H/2), where the kicks
    rebuild the forced nutation: [(H, the n_z window it may not enter)], largest first."""
    Om = math.hypot(a, b)
    phi_max = k * coarse_step(a, b, rtol)
    j = max(1, int(phi_max / (2 * math.pi)))  # x_j < (j + 1/2) pi
    while j > 1 and 2 * tan_root(j) > phi_max:
        j -= 1
    ladder = []
    while j >= 1 and 2 * tan_root(j) <= phi_max:
        Hj = 2 * tan_root(j) / k
        ladder.append((Hj, 2.0 * Hj * Om + 6.0 * Om / k))
        j //= 2
    return ladder


def _nz_rate(n, L):
    """dn_z/dt over k: (L x n)_z."""
    return L[0] * n[1] - L[1] * n[0]


class Dips:
    """The fine steps in which n_z may dip below the lowest step end met so far, and the least n_z over them.

    Near the bottom n_z nutates: successive nutation periods dip to different depths, and a few step ends
    per period can sample a shallow dip near its lowest point and a deeper one far from it, so the lowest
    step end need not lie next to the lowest point (the minimization around it alone, before, moved cos_min
    by 28 times its claim between rtol 1e-7 and 1e-8 at M = 1.3057 kg, the other parameters at their
    defaults).  Over a stretch of length s between ends z0 and z1, n_z stays above (z0 + z1)/2 - V s/2, V a
    bound on |dn_z/dt| = |dn/dt . (n + z)| <= v |n + z|, with v a bound on the axis's speed |dn/dt| =
    k |L x n| and |n + z| = sqrt(2 (1 + n_z)) moving by at most v s.  v: 1.5 times the largest speed met at
    the starts of the last steps examined (two nutation periods' worth, at least 16; a step whose ends lie
    too far above the lowest to dip below it is passed over): |L x n| is the nutation's cone, which the
    torque moves slowly, and the steps' starts sample its phases.  Every step whose bound lies below
    the lowest end is kept, then followed in 16 substeps (40 or more a nutation period: n_z, of one
    nutation frequency, turns at most once within a substep), and every substep in which dn_z/dt turns
    from negative to positive and whose bound lies below the lowest value met, the lowest bound first, is
    minimized over partial substeps (``lowest``)."""

    SCAN = 16

    def __init__(self, k, h):
        from collections import deque

        self.k, self.h = k, h
        self.speeds = deque(maxlen=max(16, math.ceil(4 * math.pi / (k * h))))  # k |L x n| at the steps' starts
        self.speed = 0.0
        self.reach = math.inf  # h v (2 + v h): no step dips below the mean of its ends by more than half of it
        self.best = 2.0  # the lowest step end
        self.steps = []  # (the bound, the state at the step's start)
        self.prune_at = 64

    def _floor(self, z0, z1, s):
        """The least n_z a stretch of s between ends z0, z1 may reach."""
        v = 1.5 * self.speed
        return 0.5 * (z0 + z1) - 0.5 * s * v * (math.sqrt(max(0.0, 2.0 * (1.0 + min(z0, z1)))) + v * s)

    def add(self, n, L, t, nz_end):
        """The fine step of h from (n, L, t) that ended at n_z = nz_end."""
        if nz_end < self.best:
            self.best = nz_end
        # (z0 + z1)/2 - V h/2 >= min(z0, z1) - reach/2 (|n + z| <= 2): a step whose lower end lies above the
        # lowest by more than that cannot dip below it, and is passed over without its speed
        if min(n[2], nz_end) - self.best > 0.5 * self.reach:
            return
        cx, cy, cz = L[1] * n[2] - L[2] * n[1], L[2] * n[0] - L[0] * n[2], L[0] * n[1] - L[1] * n[0]
        self.speeds.append(self.k * math.sqrt(cx * cx + cy * cy + cz * cz))
        self.speed = max(self.speeds)
        v = 1.5 * self.speed
        self.reach = self.h * v * (2.0 + v * self.h)
        floor = self._floor(n[2], nz_end, self.h)
        if floor < self.best:
            self.steps.append((floor, (n, L, t)))
            # pruned once the list has doubled since the last pruning (a pass per added step, before, cost a
            # third of a weight-dominated top's run); what ``lowest`` reads is the same either way, as it
            # passes over every step whose bound lies above the final lowest end
            if len(self.steps) > self.prune_at:
                self.steps = [x for x in self.steps if x[0] < self.best]
                self.prune_at = max(64, 2 * len(self.steps))

    def lowest(self, step):
        """The least n_z over the kept steps (2.0 if none), by substeps and partial substeps of ``step``."""
        from mech.solvers.numerics.roots import minimize_scalar

        hs = self.h / self.SCAN
        out, runs = self.best, []
        for floor, s0 in self.steps:
            if floor < self.best:
                states = [s0]
                for _ in range(self.SCAN):
                    states.append(step(*states[-1], hs))
                runs.append(states)
                out = min(out, min(s[0][2] for s in states))
        subs = sorted((self._floor(s0[0][2], s1[0][2], hs), i, s0) for i, (s0, s1) in
                      enumerate(pair for states in runs for pair in zip(states, states[1:]))
                      if _nz_rate(*s0[:2]) < 0.0 <= _nz_rate(*s1[:2]))
        for floor, _, s0 in subs:  # the lowest bound first: once the bounds reach the least value, none can beat it
            if floor >= out:
                break
            res = minimize_scalar(lambda x: step(*s0, x)[0][2], bounds=(0.0, hs), method="bounded",
                                  options={"xatol": 1e-7 * hs})
            out = min(out, float(res.fun))
        return out


def lowest_nz(a, b, w, h, H, step, low, low_c):
    """The least n_z: refined around the lowest fine step, and around the lowest coarse boundary by fine
    steps over the two coarse steps about it (or, with too many nutation periods per coarse step, the
    parabola through it and its neighbours)."""
    cos_min = low.lowest(step)
    if low_c[1] is not None and 2 * H / h <= 4000:
        s = low_c[1]
        s = (*retune(a, b, w, *s, -low_c[3] ** 2), s[2])
        t_end = s[2] + 2 * H
        low2 = Dips(low.k, h)
        while s[2] < t_end:
            s2 = step(*s, h)
            low2.add(*s, s2[0][2])
            s = s2
        cos_min = min(cos_min, low2.lowest(step))
    elif low_c[1] is not None and len(low_c[2]) == 3:
        # the slow motion is smooth on 1/b >> H: error ~ (b H)^3 < rtol^1.5; the nutation, ~ eps <
        # sqrt(rtol)/9 in angle, moves n_z near the bottom by its square at most
        (t0, y0), (t1, y1), (t2, y2) = low_c[2]
        d01, d12 = (y1 - y0) / (t1 - t0), (y2 - y1) / (t2 - t1)
        c2 = (d12 - d01) / (t2 - t0)
        tm = 0.5 * (t0 + t1) - d01 / (2 * c2) if c2 > 0 else t1
        tm = min(max(tm, t0), t2)
        cos_min = min(cos_min, y0 + d01 * (tm - t0) + c2 * (tm - t0) * (tm - t1))
    elif low_c[1] is not None:
        cos_min = min(cos_min, low_c[0])
    return cos_min


def _crossing(step, n, L, t, h, sign, nz_end):
    """Partial step tau in (0, h] where n_z changes sign (sign = +1: from positive to negative); ``nz_end``:
    n_z after the whole step."""
    return crossing(lambda tau: sign * step(n, L, t, tau)[0][2], h, sign * n[2], sign * nz_end)



def _jacobi(a, b, w, k):
    def jacobi(n, L, t):
        # energy in the frame turning with F, scaled by L3^2/I_A:  |L|^2/2 + (a n_z - f.n)/k - (w/k) L_z
        fx, fy = b * math.cos(w * t), b * math.sin(w * t)
        return 0.5 * (L[0] ** 2 + L[1] ** 2 + L[2] ** 2) + (a * n[2] - fx * n[0] - fy * n[1]) / k - w / k * L[2]
    return jacobi


class FineEvents:
    """The fine steps of a march from n = z, L = n (scaled) and what they meet, one step at a time
    (``advance``): t_down and phi_lead, t_up, the steps that may hold the lowest n_z (``Dips``); and what a
    state tells (``watch``): the nutation's reach ``arm`` (6 sin of the cone of n about L, at least its
    start's 6 Om/k) and the drifts of the Jacobi integral and of L . n.  Both marches (``march`` and
    solvers.mechanics.top_strobe's) step through their events by it."""

    def __init__(self, a, b, k, w, h, step):
        self.w, self.h, self.step = w, h, step
        self.jacobi = _jacobi(a, b, w, k)
        self.J0, self.J_scale = self.jacobi((0.0, 0.0, 1.0), (0.0, 0.0, 1.0), 0.0), (a + b) / k
        self.drift_J = self.drift_L3 = 0.0
        # n_z nutates about its slow motion by up to the cone angle of n about L (~ Om/k on the exact motion,
        # more where round-off in |L| ~ 1e-14 opens it, sqrt(2e-14) >> Om/k for the fastest tops): measured
        self.arm = 6.0 * math.hypot(a, b) / k
        self.low = Dips(k, h)
        self.stage, self.armed, self.nsteps = 0, False, 0
        self.t_down = self.t_up = self.phi_lead = None

    def advance(self, n, L, t):
        """One fine step from (n, L, t), its end returned; where n_z crosses 0 in it, t_down (and phi_lead)
        or t_up is located on a partial step (t_up set: the march is over)."""
        step, h = self.step, self.h
        n2, L2, t2 = step(n, L, t, h)
        self.nsteps += 1
        if self.stage == 0 and n2[2] <= 0.0 < n[2]:
            tau = _crossing(step, n, L, t, h, +1, n2[2])
            nd, _, self.t_down = step(n, L, t, tau)
            lead = math.atan2(nd[1], nd[0]) - self.w * self.t_down
            self.phi_lead = math.pi - (math.pi - lead) % (2 * math.pi)  # wrapped to (-pi, pi]
            self.stage = 1
        elif self.stage == 1:
            # n_z nutates by up to ~2 Om/k about its slow motion, faster than that moves when a > b: the way
            # back up counts only once the axis has gone below the nutation's reach (or below cos(theta) =
            # -0.3 for a slow top, whose wide nutation is no wiggle about a slow motion)
            self.armed = self.armed or n2[2] < -min(self.arm, 0.3)
            self.low.add(n, L, t, n2[2])
            if n2[2] >= 0.0 > n[2] and self.armed:
                self.t_up = t + _crossing(step, n, L, t, h, -1, n2[2])
        return n2, L2, t2

    def watch(self, n, L, t):
        """The reach and the drifts, read at the state (n, L, t)."""
        cx, cy, cz = n[1] * L[2] - n[2] * L[1], n[2] * L[0] - n[0] * L[2], n[0] * L[1] - n[1] * L[0]
        self.arm = max(self.arm, 6.0 * math.sqrt(cx * cx + cy * cy + cz * cz))  # 6 sin(cone angle) (|L| ~ 1)
        self.drift_J = max(self.drift_J, abs(self.jacobi(n, L, t) - self.J0) / self.J_scale)
        self.drift_L3 = max(self.drift_L3, abs(n[0] * L[0] + n[1] * L[1] + n[2] * L[2] - 1.0))


def march(a, b, k, w, h, ladder, step, coarse, units=1.0):
    """The overturn and back from n = z, L = n (scaled): coarse steps far from the events, fine steps
    near them (``FineEvents``); returns what the outputs are read from (event times, the lowest steps, the
    drifts)."""
    H = ladder[0][0] if ladder else None
    margin = ladder[-1][1] if ladder else 0.0  # fine steps within +-margin of n_z = 0, crossed at a rate ~ b
    t_max = 12.0 / b  # the force's tipping time 1/b, with a wide margin for the full overturn and back
    ev = FineEvents(a, b, k, w, h, step)
    n, L, t = (0.0, 0.0, 1.0), (0.0, 0.0, 1.0), 0.0
    low_c = (2.0, None, [], 0.0)  # lowest coarse boundary: (n_z, state a step before, (t, n_z) around it, step)
    ncoarse = 0
    fine = H is None
    H_now = 0.0  # the size of the Strang steps whose forced nutation L carries (0: the fine steps')
    while t < t_max:
        if not fine:
            dist = n[2] if ev.stage == 0 else -n[2]
            Hj = None
            arm = ev.arm
            for Hx, win in ladder:  # the largest step whose window the axis is outside of (a loop, not a generator:
                if win + arm < dist:  # this runs once a coarse step, up to a million times a run)
                    Hj = Hx
                    break
            if Hj is None:
                fine = True  # the event may lie anywhere past (n, L, t): go on from there in fine steps
                continue
            if Hj != H_now:
                n, L = retune(a, b, w, n, L, t, Hj * Hj - H_now * H_now)
                H_now = Hj
            n2, L2, t2 = coarse(n, L, t, Hj)
            ncoarse += 1
            if (ev.stage == 0 and n2[2] <= margin + arm) or (ev.stage == 1 and n2[2] >= -margin - arm):
                fine = True
                continue
            if ev.stage == 1:
                ev.armed = ev.armed or n2[2] < -min(arm, 0.3)
                if n2[2] < low_c[0]:
                    low_c = (n2[2], (n, L, t), [(t, n[2]), (t2, n2[2])], Hj)
                elif len(low_c[2]) == 2:
                    low_c[2].append((t2, n2[2]))
        else:
            if H_now:
                n, L = retune(a, b, w, n, L, t, -H_now * H_now)
                H_now = 0.0
            was = ev.stage
            n2, L2, t2 = ev.advance(n, L, t)
            if ev.t_up is not None:
                break
            if was == 1 and H and n2[2] < -margin - ev.arm:
                fine = False
        if (ev.nsteps + ncoarse) % 64 == 0:
            budget_check("top splitting steps", 64 * units)
            ev.watch(n2, L2, t2)
        n, L, t = n2, L2, t2
    return {"t_down": ev.t_down, "t_up": ev.t_up, "phi_lead": ev.phi_lead, "low": ev.low, "low_c": low_c, "t": t,
            "nsteps": ev.nsteps, "ncoarse": ncoarse, "drift_J": ev.drift_J, "drift_L3": ev.drift_L3}
