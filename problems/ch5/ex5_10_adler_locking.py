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

Numeric (exact, full equation), written once over arrays of variants (``numeric``; a one-point solve is the
batch of one): (1) a locked state is a periodic orbit of the drive's period, a fixed point of the one-period
map (variational equations carried along; continuation.OrbitEnsemble integrates the maps of every variant
still iterating together, mech's DOP853 on the ensemble).  For mu/omega0 < 5e-3 the map is taken in the frame
rotating with the drive, as its increment over mu/omega0, so that the detuning is resolved against mu, not
omega0 (locking ranges of 1e-16 omega0 to a part in 1e7).  The locked orbits form a loop over their phase
against the drive: Newton on the plane of one phase solves for the swing and the frequency, each variant its
own iterate and stop, stepping from the centre of the range a third of a turn at a time each way until
det(M - I) changes sign; each edge, a fold, refined by Illinois on det(M - I) over the phase.
(2) The beat: inside the numeric range the locked orbit exists and attracts: beat = 0.  Outside, the section
of the attracting torus by the drive's phase, a closed curve rho(theta) the one-period map carries onto itself,
is found by Newton's method on rho's Fourier series (circle_map.invariant_circle, from the circle of the edge's
swing; each iterate one drive period of 2 x 48 copies, 48 near the end, at rtol up to 1e-6 far from the
curve), where settling onto it would take ~1/(mu T) periods.
96 copies on it, their phases theta = atan2(-q'/omega0, q) over the next drive period give the circle map
theta -> theta + 2 pi + d(theta), fitted by a Fourier series; its weighted Birkhoff average (weight
exp(-1/(s(1 - s))), circle_map) gives the mean of d, and beat = omega |<d>|/(2 pi).  Two consecutive periods
give two fits: their difference over 1 - exp(-mu T) bounds what is left of the transient, and with the fit's
residual and the average's own error (over twice 25 quasi-periods, against its first half) makes the claim.

Allowances (bounds, factor 3 over the neglected sizes): xi_lo, xi_hi  the free-frequency shift
mu^2/(16 omega0) plus Delta ((Delta/mu)^2 + Delta/omega0); width  the latter with (mu/omega0)^2 (the shift
moves both edges alike); beat  their effect through sqrt(xi^2 - Delta^2) plus (Delta/b)^2 xi/omega0.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, Tally

exercise = Exercise(
    "5.10",
    formulas=[
        "dφ/dt = ξ + Δ cos φ  (Adler),  Δ = f₀/(2ω₀A₀) = f₀ β^(1/2)/(4ω₀)",
        "ξ_lo = -Δ,  ξ_hi = +Δ,  width = 2Δ",
        "beat = (ξ² - Δ²)^(1/2) for |ξ| > Δ, else 0",
    ],
    leading_order=("xi_lo", "xi_hi", "width", "beat"),
    # outside the locking range: one of the oscillators the beat is read from, on the torus, over the two
    # drive periods once on it (none inside the range: the beat is 0 there, nothing is integrated)
    states=[("q", "m"), ("v", "m/s")],
)

MAX_EPS = 0.3  # mu/omega0: weakly nonlinear self-oscillator
MAX_FORCING = 0.25  # Delta/mu: weak drive (the edges stay saddle-node folds of the locked orbit)
MAX_DETUNING = 0.2  # |xi|/omega0
MAX_SHIFT = 0.3  # the neglected free-frequency shift mu^2/(16 omega0) over the half-width
EDGE_BAND = 3.0  # refuse |xi| within EDGE_BAND * (the theory's edge uncertainty) of an edge


def _delta(p):
    return p["f0"] * np.sqrt(p["beta"]) / (4.0 * p["omega0"])


def _edge_uncertainty(p):
    """Absolute size of what the leading order drops at an edge: the free-frequency shift mu^2/(16 omega0)
    (which moves both edges), the amplitude change of order (Delta/mu)^2 and the drive's detuning dependence
    (Delta/omega0), each relative to Delta."""
    D = _delta(p)
    return p["mu"] ** 2 / (16.0 * p["omega0"]) + D * ((D / p["mu"]) ** 2 + D / p["omega0"])


exercise.declare_limits(
    f"mu <= {MAX_EPS:g} omega0: a weakly nonlinear self-oscillator",
    f"Delta = f0 beta^(1/2)/(4 omega0) <= {MAX_FORCING:g} mu: a weak drive",
    f"mu^2/(16 omega0) <= {MAX_SHIFT:g} Delta: the neglected frequency shift small against the half-width",
    f"|omega - omega0| <= {MAX_DETUNING:g} omega0",
    f"||omega - omega0| - Delta| >= {EDGE_BAND:g} (mu^2/(16 omega0) + Delta ((Delta/mu)^2 + Delta/omega0)): not at a locking edge",
)


@exercise.constraint
def constraint(p):
    # plain floats and math (assign's draws call this ~1e5 times; p[...] skips the failed attribute lookup
    # p.name takes first); the same operations, in the same order, as _delta and _edge_uncertainty on arrays
    w0, mu, beta, f0, w = p["omega0"], p["mu"], p["beta"], p["f0"], p["omega"]
    if mu > MAX_EPS * w0:
        return (f"mu = {mu:g} 1/s is not small against omega0 = {w0:g} rad/s: the reduced equations "
                f"need mu <= {MAX_EPS:g} omega0")
    D = f0 * math.sqrt(beta) / (4.0 * w0)
    if D > MAX_FORCING * mu:
        return (f"the drive is not weak: the locking half-width f0 sqrt(beta)/(4 omega0) = {D:.3g} rad/s must be "
                f"<= {MAX_FORCING:g} mu = {MAX_FORCING * mu:.3g} rad/s (lower f0)")
    shift = mu**2 / (16.0 * w0)
    if shift > MAX_SHIFT * D:
        return (f"the drive is too weak for this mu: the free oscillator's frequency shift mu^2/(16 omega0) = "
                f"{shift:.3g} rad/s, which the leading order neglects, exceeds {MAX_SHIFT:g} of the half-width "
                f"{D:.3g} rad/s (the predicted range would miss the true one; raise f0 or lower mu)")
    xi = w - w0
    if abs(xi) > MAX_DETUNING * w0:
        return (f"omega = {w:g} rad/s is too far from omega0 = {w0:g} rad/s: the reduced equations "
                f"need |omega - omega0| <= {MAX_DETUNING:g} omega0")
    u = EDGE_BAND * (shift + D * ((D / mu) ** 2 + D / w0))
    if abs(abs(xi) - D) < u:
        return (f"omega = {w:g} rad/s is within {u:.3g} rad/s of a locking edge (omega0 -+ {D:.6g}): "
                "closer than the leading-order theory's own error, it cannot tell locked from slipping")


def _arrays(P):
    return tuple(np.asarray(P[k], dtype=float) for k in ("omega0", "mu", "beta", "f0", "omega"))


@exercise.analytic
def analytic(P):
    from mech.solvers.numerics.batch import Column

    w0, mu, beta, f0, w = _arrays(P)
    D = _delta(P)
    xi = np.abs(w - w0)
    beat = np.where(xi > D, np.sqrt(np.maximum(xi - D, 0.0) * (xi + D)), 0.0)
    return {"xi_lo": Column(-D), "xi_hi": Column(D), "width": Column(2.0 * D), "beat": Column(beat)}


@exercise.expected_error
def expected_error(P):
    """Relative sizes: an edge moves by the uncertainty u (_edge_uncertainty) over Delta; the width loses
    the shift (it moves both edges alike) but keeps the rest; the beat b = sqrt(xi^2 - Delta^2) moves by
    about (|xi| u + Delta u)/b, large near an edge, and by (Delta/b)^2 xi/omega0 of itself through the
    drive's coupling taken at omega0.  Factor 3 over those sizes."""
    w0, mu, beta, f0, w = _arrays(P)
    D = _delta(P)
    u = _edge_uncertainty(P)
    rest = D * ((D / mu) ** 2 + D / w0 + (mu / w0) ** 2)
    xi = np.abs(w - w0)
    b2 = np.maximum((xi - D) * (xi + D), 0.0)
    # the drive's coupling f0/(2 omega A) is taken at omega0: relative xi/omega0 in Delta, which moves the
    # beat by Delta^2 (xi/omega0)/b^2 of itself (not by xi/omega0: far from locking the beat is the plain
    # difference of the two frequencies, 4e-11 off at xi = 0.16 omega0 in tests/test_ex5_10.py)
    with np.errstate(divide="ignore", invalid="ignore"):
        beat = np.where(b2 > 0, 3.0 * (xi * u + D * u) / b2 + 3.0 * (D * D / b2) * xi / w0, 0.0)
    return {"xi_lo": 3.0 * u / D, "xi_hi": 3.0 * u / D, "width": 3.0 * rest / D, "beat": beat}


@exercise.theory_range
def theory_range(P):
    """The reduced equations expand in mu/omega0, the drive Delta/mu and the detuning |xi|/omega0 (the
    largest shown)."""
    w0, mu, beta, f0, w = _arrays(P)
    cands = np.stack([mu / w0, _delta(P) / mu, np.abs(w - w0) / w0])
    names = np.array(["mu/omega0", "Delta/mu", "|omega - omega0|/omega0"], dtype=object)
    k = np.argmax(cands, axis=0)
    big = np.take_along_axis(cands, np.asarray(k)[None, ...], axis=0)[0]
    labels = names[k]
    return {name: (labels, big) for name in ("xi_lo", "xi_hi", "width", "beat")}


# ---------------------------------------------------------------------------------------------------------
N_COPIES = 96
N_MODES = 14
CIRCLE_MODES = 16  # harmonics of the torus section's radius rho(theta) (its Newton solve, ``_beat``)
# mu/omega0 below which the one-period map is taken in the frame rotating with the drive: the plain map
# resolves the detuning w only to about rtol omega0/W, the rotating one to rtol mu/W (W ~ 4 Delta); above,
# the plain map is cheaper for the same accuracy (fewer harmonics in its integrand)
ROTATING_BELOW = 5e-3
CHUNK_COPIES = 16384  # copies integrated together at most (``_periods``)
# the torus section's tolerance: the copies only have to start on the attracting torus (the two fits see what
# is left, which relaxes at exp(-mu T) a period), and the same for a solve and its rerun
R_SETTLE = 1e-8


def _ensemble(w0, mu, beta, f0, integrator):
    """The one-period maps of the oscillators (continuation.OrbitEnsemble) in units of the swing Q and of the
    detuning W, each in the frame rotating with the drive where mu/omega0 < ROTATING_BELOW (the increments
    over eps = mu/omega0 computed to rtol of themselves), plain elsewhere (eps = 1)."""
    from mech.solvers.mechanics.continuation import OrbitEnsemble

    Q = 1.0 / np.sqrt(beta)  # unit of length (the cycle's swing is about 2 Q)
    W = f0 * np.sqrt(beta) / w0  # unit of detuning: the drive's strength over the swing, by dimensions
    rot = mu / w0 < ROTATING_BELOW
    eps = np.where(rot, mu / w0, 1.0)

    def remainder(sel):  # the force besides -omega0^2 q and the drive, of the variants sel
        m, mb2 = mu[sel], 2.0 * mu[sel] * beta[sel]

        def r(q, v):
            damp = m - (0.5 * mb2) * q * q
            return damp * v, -mb2 * q * v, damp

        return r

    return OrbitEnsemble(remainder, f0, Q, w0, W, eps, rot, integrator=integrator), W, eps


_EDGE_FAILURES = {1.0: "no locked orbit found on the loop: Newton did not converge",
                  2.0: "w did not turn back within half a turn of phase from the centre of the range",
                  3.0: "the fold search did not converge on the locked loop",
                  4.0: "the edges came out in the wrong order"}


def _edges(w0, mu, beta, f0, rtol, memo, tally):
    """The locking range's edges at distinct (omega0, mu, beta, f0): the folds of the locked loop (module
    doc), all variants' Newton iterations and maps together.  Columns: xi_lo, xi_hi, their relative claim,
    the swing at each edge (units of Q), a failure code (_EDGE_FAILURES), the largest Floquet multiplier at
    each fold, the maps integrated."""
    from mech.solvers.mechanics.continuation import loop_fold, loop_fold_brackets

    m = w0.size
    ens, W, scale = _ensemble(w0, mu, beta, f0, tally.integrator)
    # the map's increments are computed to about rtol of ``scale``; a unit of w moves the orbit's phase per
    # period by T W (T = 2 pi/omega0), the swing relaxes by mu T
    sens = 2.0 * math.pi / w0 * W / scale
    rr = np.maximum(3e-14, rtol * np.minimum(1.0, W / (w0 * scale)))
    rs = np.maximum(rr, np.minimum(1e-7, 1e-3 * sens))
    edge_claim = np.maximum(exercise.tol_factor * rtol, 100.0 * rr * w0 * scale / W)
    # each fold refined over the phase.  Near it the phase multiplier is 1 + T D s (Adler: per period the
    # phase direction contracts by T D sin phi, D the half-width ~ W/4, s the phase from the fold): M's error
    # c rtol_s (c ~ 3 measured, in units of the map's scale) moves the zero by d s ~ 8 c rtol_s/sens, and the
    # edge, stationary there, by the relative (d s)^2/2 (the branch is w ~ (D/W) cos s).  The search
    # tolerance keeps this part below a tenth of the claim (and so tightens with rtol, which the rerun sees)
    r_search = np.minimum(rs, np.maximum(rr, 0.1 * sens * np.sqrt(0.1 * edge_claim / 8.0)))
    # the brackets, at a tolerance that does not depend on rtol, are kept for the rerun at rtol/10
    keys = [("5.10 brackets", *row) for row in zip(rs.tolist(), w0.tolist(), mu.tolist(), beta.tolist(), f0.tolist())]
    todo = np.array([j for j, k in enumerate(keys) if k not in memo], dtype=int)
    if todo.size:
        for j, row in zip(todo, loop_fold_brackets(ens, todo, rs[todo])):
            memo[keys[j]] = row
    br = np.array([memo[k] for k in keys])
    code = br[:, 28].copy()
    go = np.flatnonzero(code == 0)
    out = np.full((m, 2, 3), np.nan)
    mult = np.full((m, 2), np.nan)
    if go.size:  # both folds of every variant at once
        two = np.concatenate([go, go])
        z, mu2, ok = loop_fold(ens, two, np.vstack([br[go, :14], br[go, 14:28]]), np.tile(r_search[go], 2),
                               np.tile(rr[go], 2), np.tile(0.1 * np.sqrt(edge_claim[go]), 2),
                               np.tile(np.where(ens.rotating[go], 1, 0), 2))
        out[go] = np.stack([z[:, :go.size].T, z[:, go.size:].T], axis=1)
        mult[go] = np.stack([mu2[:go.size], mu2[go.size:]], axis=1)
        code[go[~(ok[:go.size] & ok[go.size:])]] = 3.0
    first_hi = out[:, 0, 2] >= out[:, 1, 2]
    z_hi = np.where(first_hi[:, None], out[:, 0], out[:, 1])
    z_lo = np.where(first_hi[:, None], out[:, 1], out[:, 0])
    xi_hi, xi_lo = z_hi[:, 2] * W, z_lo[:, 2] * W
    code[(code == 0) & ~(xi_lo < xi_hi)] = 4.0
    for run in ens.records:
        tally.record(run)
    return (xi_lo, xi_hi, edge_claim, np.hypot(z_lo[:, 0], z_lo[:, 1]), np.hypot(z_hi[:, 0], z_hi[:, 1]), code,
            np.where(first_hi, mult[:, 0], mult[:, 1]), np.where(first_hi, mult[:, 1], mult[:, 0]), ens.calls + 0.0)


@exercise.batched(("xi_lo", "xi_hi", "width", "beat"))
def numeric(P, rtol, outputs, memo=None, tally=None):
    """The edges (once for each distinct (omega0, mu, beta, f0), kept in ``memo`` across a sweep's chunks and
    a solve's rerun) and the beat at each variant's omega, all variants' integrations together."""
    from mech.solvers.numerics.batch import Column, by_rows

    memo = {} if memo is None else memo
    tally = Tally() if tally is None else tally
    w0, mu, beta, f0, w = _arrays(P)
    xi_lo, xi_hi, claim, a_lo, a_hi, code, m_hi, m_lo, maps = by_rows(
        memo, ("5.10 edges", rtol), (w0, mu, beta, f0), lambda *c: _edges(*c, rtol, memo, tally))
    tally.info.update(orbit_maps=maps, fold_multiplier_hi=m_hi, fold_multiplier_lo=m_lo)
    tally.info["orbit_map"] = np.where(mu / w0 < ROTATING_BELOW, "RotatingOrbitMap", "OrbitMap").astype(object)
    edge_failed = [(code == k, why) for k, why in _EDGE_FAILURES.items()]
    xi = w - w0
    locked = (xi_lo <= xi) & (xi <= xi_hi)
    tally.info["locked"] = np.where(code == 0, locked, None)
    out = {name: Column(v, rel=claim, failed=edge_failed) for name, v in
           (("xi_lo", xi_lo), ("xi_hi", xi_hi), ("width", xi_hi - xi_lo))}
    beat, rel = np.zeros(w.size), np.zeros(w.size)
    slip = np.flatnonzero((code == 0) & ~locked)
    failed = list(edge_failed)
    if "beat" in outputs and slip.size:
        amp = np.where(xi > xi_hi, a_hi, a_lo)[slip] / np.sqrt(beta[slip])
        b, r, why, info = _beat(w0[slip], mu[slip], beta[slip], f0[slip], w[slip], amp, rtol, memo, tally)
        for name, v in info.items():  # one entry per variant, None where locked
            tally.info[name] = np.full(w.size, None, dtype=object)
            tally.info[name][slip] = v
        beat[slip], rel[slip] = b, r
        for reason in set(x for x in why if x):
            mask = np.zeros(w.size, dtype=bool)
            mask[slip[[x == reason for x in why]]] = True
            failed.append((mask, reason))
    # inside the range the locked orbit exists: the oscillator runs at exactly omega, beat 0 claimed exactly
    out["beat"] = Column(beat, rel=rel, failed=failed)
    return out


@exercise.motion
def motion(p):
    """The driven oscillator q'' = mu (1 - beta q^2) q' - omega0^2 q + f0 cos(omega t) over two drive periods
    from q = 2/sqrt(beta) at rest, about the free cycle's swing (what a solve shows; the beat's copies are
    its ensemble, ``_drive_phase_rhs``)."""
    from mech.problems.motion import Motion

    mu, mb, w02, f0, w = p.mu, p.mu * p.beta, p.omega0**2, p.f0, p.omega
    Q = 1.0 / math.sqrt(p.beta)  # the unit of length

    def rhs(t, y):
        q, v = y
        return np.array([v, (mu - mb * q * q) * v - w02 * q + f0 * math.cos(w * t)])

    return Motion(rhs, np.array([2.0 * Q, 0.0]), (0.0, 4.0 * math.pi / p.omega), y_size=np.array([Q, Q * p.omega0]))


def _periods(w0, mu, beta, f0, w, y0, n, r, tally):
    """The copies y0 (2, m, N_COPIES: q, v) of the variants after n[j] drive periods, integrated together in the
    drive phase scaled to [0, 1] per variant: chunks of variants running similar numbers of periods
    (``batch.chunks_by_work``), of at most CHUNK_COPIES copies (the stages of a larger ensemble outgrow the
    cache: 600 variants at once took 2.4 times as long as in chunks of 16384 copies, which beat chunks of 8192
    by 10-40 %)."""
    from mech.solvers.mechanics.floquet import integrate_ensemble
    from mech.solvers.numerics.batch import chunks_by_work

    M = y0.shape[2]
    out = np.empty_like(y0)
    for group in chunks_by_work(n, overhead=4.0):
        for part in np.array_split(group, -(-group.size * M // CHUNK_COPIES)):
            Q = np.repeat(1.0 / np.sqrt(beta[part]), M)
            make = _drive_phase_rhs(w0[part], mu[part], beta[part], f0[part], w[part], 2.0 * math.pi * n[part], M)
            atol = 1e-3 * r * np.stack([Q, Q * np.repeat(w0[part], M)])
            y, runs = integrate_ensemble(make, (0.0, 1.0), y0[:, part].reshape(2, -1), rtol=r, atol=atol,
                                         integrator=tally.integrator)
            for run in runs:
                tally.record(run)
            out[:, part] = y.reshape(2, part.size, M)
    return out


def _drive_phase_rhs(w0, mu, beta, f0, w, L, M):
    """``integrate_ensemble``'s make_rhs for the copies of the variants (M each, variant-major) in the
    drive phase tau = omega t scaled by L per variant (s = tau/L: L = 2 pi for one period): dq/ds = L v/omega,
    dv/ds = L (mu (1 - beta q^2) v - omega0^2 q + f0 cos tau)/omega."""
    k, c1, c2, c3 = (L / w)[:, None], mu[:, None], (mu * beta)[:, None], (w0 * w0)[:, None]
    drive, Lc = f0[:, None], L[:, None]

    def make(sel):
        if isinstance(sel, int):
            j = sel // M
            kk, a1, a2, a3, dd, LL = (float(x[j, 0]) for x in (k, c1, c2, c3, drive, Lc))

            def one(s, y):
                q, v = y
                return np.array([kk * v, kk * ((a1 - a2 * q * q) * v - a3 * q + dd * math.cos(LL * s))])

            return one

        # the constants laid out copy by copy (flat, as the state is): the ensemble's cost is these products,
        # a third cheaper than broadcasting the per-variant columns over the copies
        kc1, kc2, kc3, kk = (np.repeat(x[:, 0], M) for x in (k * c1, k * c2, k * c3, k))
        kdr, Ls = k * drive, Lc

        def rhs(s, y):  # in place, k folded into the constants: out = (k v, k acc)
            q, v = y
            out = np.empty_like(y)
            dq, acc = out
            np.multiply(q, q, out=acc)
            acc *= kc2
            np.subtract(kc1, acc, out=acc)
            acc *= v
            np.multiply(kc3, q, out=dq)
            acc -= dq
            acc.reshape(-1, M)[...] += kdr * np.cos(Ls * s)
            np.multiply(kk, v, out=dq)
            return out

        return rhs

    return make


def _beat(w0, mu, beta, f0, w, amp, rtol, memo, tally):
    """|omega - mean oscillator frequency| from the circle map on the torus (see the module doc), for the
    variants outside their locking range: (beat, relative claim, failure reason or None per variant)."""
    from mech.solvers.numerics.circle_map import fourier_fit, invariant_circle, rotation_number

    M, m = N_COPIES, w.size
    T = 2.0 * math.pi / w
    # the torus section is found by Newton from a circle of about the locked swing: 4 digits of it are plenty,
    # and make the start (and so the section, at a tolerance that does not depend on rtol) the same for the
    # solve and its rerun at rtol/10, which then takes it from the memo
    amp = np.array([float(f"{a:.4g}") for a in amp])
    r_settle = max(rtol, R_SETTLE)
    keys = [("5.10 circle", r_settle, *row) for row in zip(*(x.tolist() for x in (w0, mu, beta, f0, w, amp)))]
    todo = np.array([j for j, key in enumerate(keys) if key not in memo], dtype=int)
    if todo.size:  # the torus section: Newton on its radius, each iterate one drive period of its copies
        def advance(y, idx, loose):
            # far from the section a rougher map does (circle_map.invariant_circle), at most 1e-6; the copies
            # integrated together share the finest tolerance any of them asks
            sel = np.tile(todo[idx], y.shape[1] // idx.size)
            r = max(r_settle, min(1e-6, r_settle * float(loose.min())))
            return _periods(w0[sel], mu[sel], beta[sel], f0[sel], w[sel], y, np.ones(sel.size), r, tally)

        # an error e of the map moves the circle by about e/(1 - exp(-mu T)): the Newton steps stop there
        tol = 30.0 * r_settle / -np.expm1(-mu[todo] * T[todo])
        pts, step, ok = invariant_circle(advance, amp[todo, None], -w0[todo, None], CIRCLE_MODES, M // 2, tol, M)
        for j, y, st, good in zip(todo, np.moveaxis(pts, 1, 0), step, ok):
            memo[keys[j]] = (y, float(st), bool(good))
    info = {"beat_circle_newton_step": np.array([memo[key][1] for key in keys])}
    # the next two drive periods, on the torus (the drive's phase is a whole number of turns: cos tau again)
    sections = [np.stack([memo[key][0] for key in keys], axis=1)]  # (2, m, M)
    for _ in (0, 1):
        sections.append(_periods(w0, mu, beta, f0, w, sections[-1], np.ones(m), rtol, tally))
    phases = [np.arctan2(-s[1] / w0[:, None], s[0]) for s in sections]
    # the advance beyond one full turn over each of the two periods; both fits at once (2 m rows)
    th0 = np.concatenate(phases[:2])
    d = np.mod(np.concatenate(phases[1:]) - th0 + math.pi, 2.0 * math.pi) - math.pi
    coef, resid = fourier_fit(th0, d, N_MODES)
    means, birkhoff = (x.reshape(2, m) for x in rotation_number(coef, N_MODES, with_error=True))
    fit_err = resid.reshape(2, m).max(axis=0)
    mean_d = means[1]
    beat = w * np.abs(mean_d) / (2.0 * math.pi)
    # the transient left decays by exp(-mu T) a period: the difference of the two fits is (1 - exp(-mu T))
    # times what remains of it
    left = np.abs(means[1] - means[0]) / -np.expm1(-mu * T)
    with np.errstate(divide="ignore", invalid="ignore"):
        err = (left + fit_err + birkhoff[1]) / np.abs(mean_d)
        rel = np.maximum(10.0 * err, 100.0 * rtol * w / beat)
    info.update(beat_fit_residual=fit_err, beat_birkhoff_error=birkhoff[1],
                beat_two_fits_rel_diff=np.abs(means[1] - means[0]) / np.abs(mean_d))
    why = [None] * m
    for j in range(m):
        if not memo[keys[j]][2]:
            why[j] = "the torus the beat is read on was not found: Newton on its section did not converge"
        elif mean_d[j] == 0.0:
            why[j] = "the fitted circle map has no mean drift: the oscillator looks locked outside the range"
        elif not rel[j] < 1.0 and birkhoff[1, j] > left[j] + fit_err[j]:
            # a slip of ~1e5 drive periods (just outside a narrow range): the circle map's average over the
            # orbit it is iterated along (circle_map._length, 2e5 iterates at most, twice) is not converged
            why[j] = (f"the beat {beat[j]:.2g} rad/s is not resolved: omega is so close to a locking edge that "
                      "the phase slips too slowly for the average over the 4e5 drive periods followed (its error "
                      f"bar would be {rel[j]:.1g} times its value)")
        elif not rel[j] < 1.0:
            # outside the range the beat is positive; an error bar as large as the beat itself is no answer
            # (just outside a range far narrower than omega0's round-off, the map cannot resolve it)
            why[j] = (f"the beat {beat[j]:.2g} rad/s is not resolved: its error bar would be {rel[j]:.1g} times "
                      "its value (omega is too close to a locking range far narrower than omega0's round-off)")
    return beat, rel, why, info
