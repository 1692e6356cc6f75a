"""5.10 Phase locking of a weakly driven van der Pol oscillator (Adler's equation).

Analytic (reduced equations, leading order): with q = A cos(omega t - phi),
A and phi slow, averaging over a period gives
dA/dt = (mu A/2)(1 - beta A^2/4) + (f0/(2 omega)) sin phi and
A dphi/dt = xi A + (f0/(2 omega)) cos phi, xi = omega - omega0.  With the free
amplitude A0 = 2/sqrt(beta): dphi/dt = xi + Delta cos phi (Adler), Delta =
f0/(2 omega0 A0) = f0 sqrt(beta)/(4 omega0).  Locked (dphi/dt = 0 has a root)
for |xi| <= Delta: xi_lo = -Delta, xi_hi = +Delta, width 2 Delta.  Outside, phi
slips with the period 2 pi/sqrt(xi^2 - Delta^2), the beat frequency
sqrt(xi^2 - Delta^2); zero inside.

Numeric (exact, full equation): (1) the locked state is a periodic orbit of
the drive's period, a fixed point of the one-period map (variational
equations carried along, DOP853; solvers/mechanics/continuation.py).  For
mu/omega0 < 5e-3 the map is taken in the frame rotating with the drive, as its
increment over mu/omega0 (slow amplitude and phase, the fast rotation removed
exactly), so that the detuning is resolved against mu, not omega0: locking
ranges of 1e-16 omega0 come out to a part in 1e7.  The locked orbits form a
loop over their phase against the drive: Newton on the plane of one phase
solves for the swing and the frequency (well posed at any drive strength),
stepping from the centre of the range a third of a turn at a time each way
until det(M - I) changes sign; each edge, a fold of the orbit, refined by
Brent's method on det(M - I) over the phase.
(2) The beat: inside the numeric range the locked orbit exists and attracts:
beat = 0.  Outside, 96 copies started around the cycle are integrated together
(one vectorized system) for 16/mu (at most 300 drive periods) so that they
settle on the invariant torus;
their oscillator phases theta = atan2(-q'/omega0, q) over the next drive
period give the circle map theta -> theta + 2 pi + d(theta) on the torus's
section, fitted by a Fourier series; iterating the fitted map with the smooth
weight exp(-1/(s(1 - s))) (a weighted Birkhoff average, converging faster than
any power of the length) gives the mean of d, and beat = omega |<d>|/(2 pi).
Two consecutive periods give two fits: their difference over 1 - exp(-mu T)
bounds the transient left, and with the fit's residual makes the claim.
The driven oscillator is the declared motion (``motion``), the copies its vectorized form;
their two periods after settling are the trajectory (the first copy).  The orbit maps integrate
in solvers/mechanics/continuation.py (integrator=run.integrator, recorded).

Allowances (bounds, factor 3 over the neglected sizes): xi_lo, xi_hi  the free-frequency shift
mu^2/(16 omega0) plus Delta ((Delta/mu)^2 + Delta/omega0); width  the latter with (mu/omega0)^2 (the shift
moves both edges alike); beat  their effect through sqrt(xi^2 - Delta^2) plus (Delta/b)^2 xi/omega0.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.numerics.circle_map import fourier_fit, rotation_number

exercise = Exercise(
    "5.10",
    formulas=[
        "dφ/dt = ξ + Δ cos φ  (Adler),  Δ = f₀/(2ω₀A₀) = f₀ β^(1/2)/(4ω₀)",
        "ξ_lo = -Δ,  ξ_hi = +Δ,  width = 2Δ",
        "beat = (ξ² - Δ²)^(1/2) for |ξ| > Δ, else 0",
    ],
    leading_order=("xi_lo", "xi_hi", "width", "beat"),
    # outside the locking range: one of the oscillators the beat is read from, on the torus, over the two
    # drive periods after it settled (none inside the range: the beat is 0 there, nothing is integrated)
    states=[("q", "m"), ("v", "m/s")],
)

MAX_EPS = 0.3  # mu/omega0: weakly nonlinear self-oscillator
MAX_FORCING = 0.25  # Delta/mu: weak drive (the edges stay saddle-node folds of the locked orbit)
MAX_DETUNING = 0.2  # |xi|/omega0
MAX_SHIFT = 0.3  # the neglected free-frequency shift mu^2/(16 omega0) over the half-width
EDGE_BAND = 3.0  # refuse |xi| within EDGE_BAND * (the theory's edge uncertainty) of an edge


def _delta(p):
    return p.f0 * math.sqrt(p.beta) / (4.0 * p.omega0)


def _edge_uncertainty(p):
    """Absolute size of what the leading order drops at an edge: the free-frequency shift mu^2/(16 omega0)
    (which moves both edges), the amplitude change of order (Delta/mu)^2 and the drive's detuning dependence
    (Delta/omega0), each relative to Delta."""
    D = _delta(p)
    return p.mu**2 / (16.0 * p.omega0) + D * ((D / p.mu) ** 2 + D / p.omega0)


exercise.declare_limits(
    f"mu <= {MAX_EPS:g} omega0: a weakly nonlinear self-oscillator",
    f"Delta = f0 beta^(1/2)/(4 omega0) <= {MAX_FORCING:g} mu: a weak drive",
    f"mu^2/(16 omega0) <= {MAX_SHIFT:g} Delta: the neglected frequency shift small against the half-width",
    f"|omega - omega0| <= {MAX_DETUNING:g} omega0",
    f"||omega - omega0| - Delta| >= {EDGE_BAND:g} (mu^2/(16 omega0) + Delta ((Delta/mu)^2 + Delta/omega0)): not at a locking edge",
)


@exercise.constraint
def constraint(p):
    if p.mu > MAX_EPS * p.omega0:
        return (f"mu = {p.mu:g} 1/s is not small against omega0 = {p.omega0:g} rad/s: the reduced equations "
                f"need mu <= {MAX_EPS:g} omega0")
    D = _delta(p)
    if D > MAX_FORCING * p.mu:
        return (f"the drive is not weak: the locking half-width f0 sqrt(beta)/(4 omega0) = {D:.3g} rad/s must be "
                f"<= {MAX_FORCING:g} mu = {MAX_FORCING * p.mu:.3g} rad/s (lower f0)")
    shift = p.mu**2 / (16.0 * p.omega0)
    if shift > MAX_SHIFT * D:
        return (f"the drive is too weak for this mu: the free oscillator's frequency shift mu^2/(16 omega0) = "
                f"{shift:.3g} rad/s, which the leading order neglects, exceeds {MAX_SHIFT:g} of the half-width "
                f"{D:.3g} rad/s (the predicted range would miss the true one; raise f0 or lower mu)")
    xi = p.omega - p.omega0
    if abs(xi) > MAX_DETUNING * p.omega0:
        return (f"omega = {p.omega:g} rad/s is too far from omega0 = {p.omega0:g} rad/s: the reduced equations "
                f"need |omega - omega0| <= {MAX_DETUNING:g} omega0")
    u = EDGE_BAND * _edge_uncertainty(p)
    if abs(abs(xi) - D) < u:
        return (f"omega = {p.omega:g} rad/s is within {u:.3g} rad/s of a locking edge (omega0 -+ {D:.6g}): "
                "closer than the leading-order theory's own error, it cannot tell locked from slipping")


@exercise.analytic
def analytic(p):
    D = _delta(p)
    xi = p.omega - p.omega0
    beat = math.sqrt((abs(xi) - D) * (abs(xi) + D)) if abs(xi) > D else 0.0
    return {"xi_lo": -D, "xi_hi": D, "width": 2.0 * D, "beat": beat}


@exercise.expected_error
def expected_error(p):
    """Relative sizes: an edge moves by the uncertainty u (_edge_uncertainty) over Delta; the width loses
    the shift (it moves both edges alike) but keeps the rest; the beat b = sqrt(xi^2 - Delta^2) moves by
    about (|xi| u + Delta u)/b, large near an edge, and by (Delta/b)^2 xi/omega0 of itself through the
    drive's coupling taken at omega0.  Factor 3 over those sizes."""
    D = _delta(p)
    u = _edge_uncertainty(p)
    rest = D * ((D / p.mu) ** 2 + D / p.omega0 + (p.mu / p.omega0) ** 2)
    xi = abs(p.omega - p.omega0)
    b2 = max((xi - D) * (xi + D), 0.0)
    # the drive's coupling f0/(2 omega A) is taken at omega0: relative xi/omega0 in Delta, which moves the
    # beat by Delta^2 (xi/omega0)/b^2 of itself (not by xi/omega0: far from locking the beat is the plain
    # difference of the two frequencies, 4e-11 off at xi = 0.16 omega0 in tests/test_ex5_10.py)
    beat = 3.0 * (xi * u + D * u) / b2 + 3.0 * (D * D / b2) * xi / p.omega0 if b2 > 0 else 0.0
    return {"xi_lo": 3.0 * u / D, "xi_hi": 3.0 * u / D, "width": 3.0 * rest / D, "beat": beat}


@exercise.theory_range
def theory_range(p):
    """The reduced equations expand in mu/omega0, the drive Delta/mu and the detuning |xi|/omega0 (the
    largest shown)."""
    cands = [("mu/omega0", p.mu / p.omega0), ("Delta/mu", _delta(p) / p.mu),
             ("|omega - omega0|/omega0", abs(p.omega - p.omega0) / p.omega0)]
    big = max(cands, key=lambda c: c[1])
    return {name: big for name in ("xi_lo", "xi_hi", "width", "beat")}


# ---------------------------------------------------------------------------------------------------------
N_COPIES = 96
N_MODES = 14
SETTLE_MU_T = 16.0  # e^-16 ~ 1e-7 of the start's distance from the torus (itself ~ Delta/mu)
# mu/omega0 below which the one-period map is taken in the frame rotating with the drive: the plain map
# resolves the detuning w only to about rtol omega0/W, the rotating one to rtol mu/W (W ~ 4 Delta).  At
# mu/omega0 = 0.05 (the defaults) the plain map is cheaper for the same accuracy (its integrand has fewer
# harmonics: 750 evaluations a period at rtol 2e-12 against 980 at the rotating map's 4e-11)
ROTATING_BELOW = 5e-3
PHASE_STEP = math.pi / 3.0  # steps around the locked loop that bracket its folds
MAX_SETTLE = 300  # drive periods at most (very small mu): the claim then carries the transient left over


def _orbit_map(p, run):
    """The one-period map of the oscillator in units of the swing Q and of the detuning W, and the scale
    of its increments (1, or mu/omega0 where the rotating map computes them to rtol of themselves)."""
    from mech.solvers.mechanics.continuation import OrbitMap, RotatingOrbitMap

    mu, beta, w0, f0 = p.mu, p.beta, p.omega0, p.f0
    Q = 1.0 / math.sqrt(beta)  # unit of length (the cycle's swing is about 2 Q)
    W = f0 * math.sqrt(beta) / w0  # unit of detuning: the drive's strength over the swing, by dimensions
    memo_key = ("5.10", *(float(p[k]) for k in p))
    if mu / w0 >= ROTATING_BELOW:
        def force(q, v):
            damp = mu * (1.0 - beta * q * q)
            return damp * v - w0 * w0 * q, -2.0 * mu * beta * q * v - w0 * w0, damp

        om = OrbitMap(force, f0, Q, w0, W, memo=run.shared, memo_key=memo_key, integrator=run.integrator)
        scale = 1.0  # the map q -> q + O(mu/omega0) is computed to rtol of the swing
    else:
        def remainder(q, v):  # the force besides -omega0^2 q and the drive
            damp = mu * (1.0 - beta * q * q)
            return damp * v, -2.0 * mu * beta * q * v, damp

        # the map's increment over the damping's scale mu/omega0, computed to rtol of itself
        scale = mu / w0
        om = RotatingOrbitMap(remainder, f0, Q, w0, W, scale, memo=run.shared, memo_key=memo_key,
                              integrator=run.integrator)
    run.info["orbit_map"] = type(om).__name__
    return om, Q, W, scale


# The locked orbits form a closed loop around the w axis, parametrized by their phase against the drive:
# on the plane normal to the circle's tangent at the angle th, n = (-sin th, cos th, 0), Newton solves
# for the swing and the frequency (w).  That is well posed however weak the drive: the swing's
# direction is stiff (relaxation mu per unit time), and w enters the phase's closing directly.  At a
# fixed frequency instead, Newton's first step along the nearly neutral phase (stiffness ~ Delta,
# against mu along the swing) overshoots from a far start, and a continuation in w steers by tangents
# that the Jacobian of a point off the branch by more than ~Delta/mu in swing gets wrong.
def _on_branch(om, th, known, r, fresh=None):
    """The locked orbit of phase th, Newton started from the solved point ``known`` = (th', bp) moved
    along the branch's tangent (first order in th - th'; at a start, bp = None: a swing of 2 Q, w = 0).
    ``fresh``: True, its Jacobian evaluated again at the converged point; "floor", only where Newton
    stopped at the map's noise floor, which that evaluation must confirm; False, the last iterate's
    Jacobian, a step below the floor away: det(M - I) moves by that step times its curvature, far below
    the fold search's tolerance.  By default False from a solved point nearby on the plain map (a third of
    the maps saved: about 37 a solve instead of 51, the edges moved by at most 1e-5 of their error bars over 20
    class variants), "floor" from a far start or on the rotating map, whose weak drive leaves the phase
    nearly neutral and the floor a poor bound on the distance to the orbit (tests/test_ex5_10.py's
    locking ranges of 5e-17 omega0 came out in the wrong order without the check)."""
    from mech.solvers.mechanics.continuation import RotatingOrbitMap

    if fresh is None:
        fresh = "floor" if known[1] is None or isinstance(om, RotatingOrbitMap) else False
    from mech.solvers.mechanics.continuation import solve_on_plane

    R, w = 2.0, 0.0
    if known[1] is not None:
        t_known, bp = known
        z, tg = bp.z, bp.tangent
        R = math.hypot(z[0], z[1])
        w = z[2]
        dth = (z[0] * tg[1] - z[1] * tg[0]) / (R * R)  # d(phase)/ds along the tangent
        if abs(dth) * R > 1e-3 * np.linalg.norm(tg):
            R += (z[0] * tg[0] + z[1] * tg[1]) / R / dth * (th - t_known)
            w += tg[2] / dth * (th - t_known)
    c, sn = math.cos(th), math.sin(th)
    bp = solve_on_plane(om, [R * c, R * sn, w], [-sn, c, 0.0], 0.0, rtol=r, tol=1e-9, max_iter=12,
                        fresh=fresh, monotone=False)
    if bp is None or not bp.A > 1.0:  # not the small unstable orbit near rest
        raise NumericFailure(f"no locked orbit found at the phase {th:.4g} rad: Newton did not converge")
    return bp



def _fold_brackets(om, rs):
    """Phases bracketing the two folds: from the phase where the drive pushes the swing outward (the centre
    of the range, w ~ 0), in steps of PHASE_STEP each way round until w turns back: the edges are the
    folds, where det(M - I), the w-component of the branch's tangent, changes sign.  Adler's loop is
    w ~ -(Delta/W) cos(phase) with the folds a quarter turn either side, moved by ~Delta/mu rad by the
    drive's push on the swing (at most 0.25 rad, half a step).  Not all the way round: where the drive
    pushes the swing inward and 4 Delta/mu exceeds 4/(3 sqrt 3), no locked orbit of a large swing has that
    phase (the loop turns through small swings there)."""
    th0 = 0.5 * math.pi
    start = _on_branch(om, th0, (th0, None), rs)
    brackets = []
    for direction in (+1.0, -1.0):
        prev = (th0, start)
        for k in range(1, 4):
            th = th0 + direction * k * PHASE_STEP
            bp = _on_branch(om, th, prev, rs)
            if np.sign(bp.tangent[2]) != np.sign(prev[1].tangent[2]):
                brackets.append(sorted([prev, (th, bp)], key=lambda u: u[0]))
                break
            prev = (th, bp)
        else:
            raise NumericFailure("w did not turn back within half a turn of phase from the centre of the range")
    return brackets


def _folds(om, brackets, rr, r_search, edge_claim):
    """Each fold refined by Brent's method on det(M - I) over the phase (see ``numeric`` for the search's
    tolerance), then solved at rr; sorted by w, highest first."""
    from mech.solvers.numerics.roots import brentq

    folds = []
    for (ta, ba), (tb, bb) in brackets:
        near = {ta: ba, tb: bb}

        def det(th):
            t0 = min(near, key=lambda t: abs(t - th))
            bp = near[th] = _on_branch(om, th, (t0, near[t0]), r_search)
            return bp.tangent[2]

        root = brentq(det, ta, tb, xtol=0.1 * math.sqrt(edge_claim), rtol=1e-15, maxiter=100,
                      fa=ba.tangent[2], fb=bb.tangent[2])
        fold = near.get(root) if rr == r_search else None
        if fold is None:
            t0 = min(near, key=lambda t: abs(t - root))
            # the edge is z's w: the Jacobian of the last iterate is enough (fold_multipliers, the swing)
            fold = _on_branch(om, root, (t0, near[t0]), rr, fresh=False)
        folds.append(fold)
    folds.sort(key=lambda f: f.z[2], reverse=True)
    return folds


def _beat_at(p, run, folds, Q, xi_lo, xi_hi):
    """The beat and its claim: 0 inside the locking range, else from a settling run."""
    xi = p.omega - p.omega0
    if xi_lo <= xi <= xi_hi:
        # the locked orbit exists here: the oscillator runs at exactly omega
        run.claim("beat", rel=0.0, abs=0.0)
        run.info["locked"] = True
        return 0.0
    near = folds[0] if xi > xi_hi else folds[1]
    beat, err = _beat(p, run, amplitude=near.A * Q)
    rel = max(10.0 * err, 100.0 * run.rtol * p.omega / beat)
    if rel >= 1.0:
        # outside the range the beat is positive; an error bar as large as the beat itself is no answer
        # (just outside a range far narrower than omega0's round-off, the settling run cannot resolve it)
        raise NumericFailure(f"the beat {beat:.2g} rad/s is not resolved: its error bar would be {rel:.1g} "
                             f"times its value (omega is {abs(xi - (xi_hi if xi > xi_hi else xi_lo)):.2g} "
                             f"rad/s outside a locking range {xi_hi - xi_lo:.2g} rad/s wide)")
    run.claim("beat", rel=rel)
    run.info["locked"] = False
    return beat


@exercise.numeric
def numeric(p, run):
    rtol, w0 = run.rtol, p.omega0
    om, Q, W, scale = _orbit_map(p, run)
    # the map's increments are computed to about rtol of ``scale``; a unit of w moves the orbit's phase per
    # period by T W (T = 2 pi/omega0), the swing relaxes by mu T
    T = 2.0 * math.pi / w0
    sens = T * W / scale
    rr = max(3e-14, rtol * min(1.0, W / (w0 * scale)))
    run.info["rtol_integration"] = rr
    rs = max(rr, min(1e-7, 1e-3 * sens))
    run.info["rtol_sweep"] = rs
    edge_claim = max(exercise.tol_factor * rtol, 100.0 * rr * w0 * scale / W)
    for name in ("xi_lo", "xi_hi", "width"):
        run.claim(name, rel=edge_claim)
    brackets = _fold_brackets(om, rs)
    # each fold refined by Brent's method on det(M - I) over the phase.  Near it the phase multiplier is
    # 1 + T D s (Adler: per period T = 2 pi/omega0 the phase direction contracts by T D sin phi, D the
    # half-width ~ W/4, s the phase from the fold): M's error c rtol_s (c ~ 3 measured, in units of the
    # map's scale) moves the zero by d s ~ 8 c rtol_s/sens (sens = T W/scale), and the edge, stationary there,
    # by the relative (d s)^2/2 (the branch is w ~ (D/W) cos s).  The search tolerance keeps this part below
    # a tenth of the claim (and so tightens with rtol, which the rerun then sees)
    r_search = min(rs, max(rr, 0.1 * sens * math.sqrt(0.1 * edge_claim / 8.0)))
    run.info["rtol_fold_search"] = r_search
    folds = _folds(om, brackets, rr, r_search, edge_claim)
    xi_hi, xi_lo = folds[0].z[2] * W, folds[1].z[2] * W
    if not xi_lo < xi_hi:
        raise NumericFailure("the edges came out in the wrong order")
    # Liouville: the divergence mu (1 - beta q^2) is not constant, so det M is not known in closed form;
    # at a fold one multiplier is exactly 1, recorded as a check of the refinement
    run.info["fold_multipliers"] = [sorted(np.abs(np.linalg.eigvals(f.M)).tolist()) for f in folds]
    run.info["orbit_maps"] = om.calls
    run.info["orbit_maps_reused"] = om.memo_hits  # taken from the solve by its rerun (Run.shared)
    run.record(om, method="DOP853")  # every integration of the orbit map
    beat = _beat_at(p, run, folds, Q, xi_lo, xi_hi)
    return {"xi_lo": xi_lo, "xi_hi": xi_hi, "width": xi_hi - xi_lo, "beat": beat}


def _driven(p):
    """The driven oscillator q'' = mu (1 - beta q^2) q' - omega0^2 q + f0 cos(omega t) (SI), for any number
    of copies at once: y = (q_1 .. q_M, v_1 .. v_M), one vectorized system."""
    mu, mb, w02, f0, w = p.mu, p.mu * p.beta, p.omega0**2, p.f0, p.omega

    def rhs(t, y):
        M = len(y) // 2
        q, v = y[:M], y[M:]
        out = np.empty_like(y)
        out[:M] = v
        a = out[M:]  # mu (1 - beta q^2) v - omega0^2 q + f0 cos(omega t), in place (the ensemble's cost)
        np.multiply(q, q, out=a)
        a *= -mb
        a += mu
        a *= v
        a -= w02 * q
        a += f0 * math.cos(w * t)
        return out

    return rhs


@exercise.motion
def motion(p, copies=1):
    """The driven oscillator (``_driven``) over one drive period from q = 2/sqrt(beta) at rest, about the free
    cycle's swing; with ``copies`` > 1 that many at once (the first is the declared state), for the beat's
    ensemble (``_beat`` gives them their own starts and spans)."""
    from mech.problems.motion import Motion

    Q = 1.0 / math.sqrt(p.beta)  # the unit of length
    M = int(copies)
    return Motion(_driven(p), np.concatenate([np.full(M, 2.0 * Q), np.zeros(M)]), (0.0, 2.0 * math.pi / p.omega),
                  y_size=np.concatenate([np.full(M, Q), np.full(M, Q * p.omega0)]),
                  to_states=None if M == 1 else (lambda y: y[[0, M]]))


def _beat(p, run, amplitude):
    """|omega - mean oscillator frequency| from the circle map on the torus (see the module doc)."""

    mu, w0, w = p.mu, p.omega0, p.omega
    M = N_COPIES
    T = 2.0 * math.pi / w
    n_settle = max(2, min(MAX_SETTLE, math.ceil(SETTLE_MU_T / (mu * T))))
    th = 2.0 * math.pi * np.arange(M) / M
    # the copies start on a circle of about the locked swing, only to be near the torus: 4 digits of it
    # are plenty, and make the start (and so the settling, at a tolerance that does not depend on rtol)
    # the same for the solve and its rerun at rtol/10, which then takes it from run.shared
    amplitude = float(f"{amplitude:.4g}")
    y0 = np.concatenate([amplitude * np.cos(th), -w0 * amplitude * np.sin(th)])
    m = motion(p, copies=M)
    # the settling only has to land on the attracting torus: a looser tolerance, then the full one
    r_settle = max(run.rtol, 1e-6)
    key = ("5.10 settle", mu, p.beta, w0, p.f0, w, amplitude, n_settle, r_settle)
    y_settled = run.shared.get(key)
    if y_settled is None:
        settle = run.follow(m.starting(y0=y0, span=(0.0, n_settle * T)), rtol=r_settle, mark=False)
        y_settled = run.shared[key] = settle.y_end.copy()
    else:
        run.info["beat_settle_reused"] = True
    # the motion: the next two drive periods, on the torus
    sections = [n_settle * T, (n_settle + 1) * T, (n_settle + 2) * T]
    traj = run.follow(m.starting(y0=y_settled, span=(n_settle * T, (n_settle + 2) * T),
                                 options={"t_eval": sections})).traj
    Y = traj.y  # columns: the three section times
    phases = np.arctan2(-Y[M:, :] / w0, Y[:M, :])
    means = []
    fit_err = 0.0
    for k in (0, 1):
        th0, th1 = phases[:, k], phases[:, k + 1]
        d = np.mod(th1 - th0 + math.pi, 2.0 * math.pi) - math.pi  # the advance beyond one full turn
        coef, resid = fourier_fit(th0, d, N_MODES)
        fit_err = max(fit_err, resid)
        means.append(rotation_number(coef, N_MODES))
    mean_d = means[1]
    if mean_d == 0.0:
        raise NumericFailure("the fitted circle map has no mean drift: the oscillator looks locked outside the range")
    beat = w * abs(mean_d) / (2.0 * math.pi)
    # the transient left decays by exp(-mu T) a period: the difference of the two fits is (1 - exp(-mu T))
    # times what remains of it
    left = abs(means[1] - means[0]) / -math.expm1(-mu * T)
    err = (left + fit_err) / abs(mean_d)
    run.info["beat_settle_periods"] = n_settle
    run.info["beat_fit_residual"] = fit_err
    run.info["beat_two_fits_rel_diff"] = abs(means[1] - means[0]) / abs(mean_d)
    return beat, err
