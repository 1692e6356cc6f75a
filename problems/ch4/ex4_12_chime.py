"""4.12 Chime: a uniform bar hung on a thread; Lagrange equations and normal modes.

Analytic: with a = l' the thread, the bar's point at distance s from its upper end
is at a (sin phi, -cos phi) + s (sin psi, -cos psi), so
T = (M/2)[a^2 phi'^2 + a l cos(phi - psi) phi' psi' + l^2 psi'^2 / 3] and
U = -M g (a cos phi + (l/2) cos psi).  Linearized: mass matrix M [[a^2, a l/2],
[a l/2, l^2/3]], stiffness M g diag(a, l/2).  The characteristic equation
a l w^4 - g (4 l + 6 a) w^2 + 6 g^2 = 0 gives, with D = 4 l^2 + 6 a l + 9 a^2,
omega_{2,1}^2 = g (2l + 3a +- sqrt D)/(a l) (the lower root as 6 g/(2l + 3a + sqrt D),
free of cancellation), and the mode ratios psi/phi = (2l - 3a +- sqrt D)/(3l),
evaluated as r1 = [2l + (4l^2 + 6al)/(sqrt D + 3a)]/(3l) and
r2 = -[3a + (6al + 9a^2)/(2l + sqrt D)]/(3l), each free of cancellation.

Numeric: Gauss-Legendre points along the bar; T(q, q') = sum w |v|^2/2 and
U(q) = sum w g (y - y_eq) straight from the points' positions (heights measured
from equilibrium as 2 sin^2 of the half-angles, so U carries no large constant).
The mass matrix by polarization (probe rates 1/l' and 1/l, so the cross term
is not lost beside the diagonal), the stiffness by Richardson central
differences (smallosc), both roots of the 2x2 characteristic polynomial in a
stable form (the large root directly, the small one as det/large: numerics.modes.pair_roots),
mode ratios from the non-cancelling row of (K - omega^2 M) a = 0 (pair_shapes).
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics.inertia import gauss_legendre
from mech.solvers.mechanics.rolling import scaled_mass_matrix
from mech.solvers.numerics.modes import hessian, pair_roots, pair_shapes

exercise = Exercise(
    "4.12",
    formulas=[
        "l'² φ'' + (l l'/2)[cos(φ-ψ) ψ'' + sin(φ-ψ) ψ'²] + g l' sin φ = 0",
        "(l/2)[l' cos(φ-ψ) φ'' - l' sin(φ-ψ) φ'²] + (l²/3) ψ'' + (g l/2) sin ψ = 0",
        "l l' ω⁴ - g (4l + 6l') ω² + 6 g² = 0, D = 4l² + 6 l l' + 9 l'²",
        "ω²₁,₂ = g (2l + 3l' ∓ √D) / (l l')",
        "ψ/φ = (2l - 3l' ± √D) / (3l)  (+ for mode 1, - for mode 2)",
    ],
)


@exercise.analytic
def analytic(p):
    a, l, g = p.l_prime, p.l, p.g
    sD = np.sqrt(4 * l**2 + 6 * a * l + 9 * a**2)
    S = 2 * l + 3 * a
    w2_hi = g * (S + sD) / (a * l)
    w2_lo = 6 * g / (S + sD)
    r1 = (2 * l + (4 * l**2 + 6 * a * l) / (sD + 3 * a)) / (3 * l)
    r2 = -(3 * a + (6 * a * l + 9 * a**2) / (2 * l + sD)) / (3 * l)
    return {"omega1": np.sqrt(w2_lo), "omega2": np.sqrt(w2_hi), "r1": r1, "r2": r2}


@exercise.numeric
def numeric(p, run):
    # dimensionless: lengths in l, masses in M, time in sqrt(l/g); the thread's swing as the length
    # x = a phi (a = l'/l), so that T and U keep O(1) coefficients for a from 1e-200 to 1e200 (with phi,
    # the thread's term M l'^2 phi'^2 over- or underflowed: NaN modes)
    a, l, g, M = p.l_prime / p.l, 1.0, 1.0, 1.0
    s, ws = gauss_legendre(8, 0.0, l)
    w = M * ws / l  # mass of each point

    def T(q, qdot):
        phi, psi = q[0] / a, q[1]
        # velocity of the point at s: a phi' (cos phi, sin phi) + s psi' (cos psi, sin psi), a phi' = x'
        vx = qdot[0] * np.cos(phi) + s * qdot[1] * np.cos(psi)
        vy = qdot[0] * np.sin(phi) + s * qdot[1] * np.sin(psi)
        return 0.5 * float(np.sum(w * (vx**2 + vy**2)))

    def U(q):
        # y - y_eq of each point: a (1 - cos phi) + s (1 - cos psi), written as 2 sin^2(x/2)
        dy = 2 * a * np.sin(q[0] / a / 2) ** 2 + 2 * s * np.sin(q[1] / 2) ** 2
        return g * float(np.sum(w * dy))

    q0 = np.zeros(2)
    # probe rates of one length per time for x and one radian per time for psi move thread and bar at
    # comparable speeds (the bar's length is the unit)
    Mm = scaled_mass_matrix(T, q0, [1.0, 1.0])
    # steps of 1e-3 rad in phi and psi: the Hessian in (phi, psi), then brought to x = a phi by dividing
    # twice by a (one step at a time: the step in x squared, a^2 1e-6, leaves the range at a = 1e+-200)
    K = hessian(lambda q: U(np.array([a * q[0], q[1]])), q0, scale=1.0)
    K[0, :] /= a
    K[:, 0] /= a
    # both roots of the 2x2 characteristic polynomial without cancellation (numerics.modes.pair_roots): at
    # a = 1e+-200 they are 1e200 apart, and an eigensolver (forward or inverse) rounds one of them to 0
    w2, w2_err = pair_roots(Mm, K)
    if not w2[0] > w2_err[0]:
        raise NumericFailure(f"the hanging equilibrium came out unstable: omega^2 = {w2}")
    shapes = pair_shapes(Mm, K, w2, w2_err)
    ratios = a * shapes[1, :] / shapes[0, :]  # psi/phi = a psi/x
    run.info["mass_matrix"] = Mm.tolist()
    run.info["stiffness"] = K.tolist()
    # polarization with balanced probe rates is exact to a few ulps; the Hessian's truncation (h^4/1440,
    # h = 1e-3) and round-off (U has no large constant) stay near 1e-13; each mode comes from the
    # eigen-solve in which it is the larger eigenvalue (balanced_modes), so a 1e7 spread of omega^2
    # costs no digits (measured 1e-15 at l'/l = 1e-7 and 1e7; the claim covers pair_roots' own bound)
    for name in ("omega1", "omega2", "r1", "r2"):
        run.claim(name, rel=1e-10)
    unit = np.sqrt(p.g) / np.sqrt(p.l)
    return {"omega1": np.sqrt(w2[0]) * unit, "omega2": np.sqrt(w2[1]) * unit, "r1": ratios[0], "r2": ratios[1]}


@exercise.scene
def scene(p, run):
    """The two normal modes drawn at the ends of a swing (thread angle phi, bar angle psi = r phi), and both
    frequencies against the thread's length."""
    from mech.problems.scene import Axis, Guide, Line, Markers, Panel, Scene

    a, l = p.l_prime, p.l
    an = run.analytic(p)
    nv = run.numeric(p)
    panels = []
    for k, name in ((1, "lower"), (2, "higher")):
        r, w = an[f"r{k}"], an[f"omega{k}"]
        title = f"{name} mode: ω{k} = {w:.5g} rad/s, ψ/φ = {r:.4g}"
        if nv:
            title += f"\nnumeric: ω{k} = {nv[f'omega{k}']:.5g} rad/s, ψ/φ = {nv[f'r{k}']:.4g}"
        panel = Panel(title, Axis(""), Axis(""), equal_aspect=True, legend="none", ticks=False)
        swing = 0.35 / max(1.0, abs(r))
        for sign, color in ((1, "C3"), (-1, "C0"), (0, "0.6")):
            phi, psi = sign * swing, sign * swing * r
            x1, y1 = a * np.sin(phi), -a * np.cos(phi)
            x2, y2 = x1 + l * np.sin(psi), y1 - l * np.cos(psi)
            panel.add(Line([0, x1], [0, y1], kind="drawing", color=color, width=1.0, dashed=sign == 0),
                      Line([x1, x2], [y1, y2], kind="drawing", color=color, width=4.0 if sign else 2.0))
        panel.add(Line([-0.2 * a, 0.2 * a], [0, 0], kind="drawing", color="k", width=2.0))
        panel.x.lim = (-0.7 * (l + a), 0.7 * (l + a))
        panel.y.lim = (-1.1 * (l + a), 0.1 * (l + a))
        panels.append(panel)
    ls = np.geomspace(a / 20, a * 20, 200)
    curves = run.series(p, "l_prime", ls)
    freq = Panel("both frequencies against the thread", Axis("thread's length l'", "m", log=True),
                 Axis("ω", "rad/s", log=True))
    freq.add(Line(ls, curves["omega1"], "ω1, analytic"), Line(ls, curves["omega2"], "ω2, analytic", color="C1"))
    xs = run.numeric_points(ls[0], ls[-1], log=True)
    if len(xs):
        num = run.series(p, "l_prime", xs, numeric=True)
        freq.add(Markers(xs, num["omega1"], "numeric"), Markers(xs, num["omega2"]))
    freq.add(Guide(a, label="this thread"))
    panels.append(freq)
    return Scene(panels)
