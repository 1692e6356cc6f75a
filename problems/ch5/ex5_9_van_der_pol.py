"""5.9 Van der Pol self-oscillator: the limit cycle's amplitude, frequency and Floquet exponent.

Analytic (reduced equation): with q = A cos(omega0 t + phi) and A, phi slow,
averaging the nonlinear damping over a period gives
dA/dt = (mu/2) A (1 - beta A^2/4), d phi/dt = 0.  Small A grows, every A > 0
goes to the stationary A0 = 2/sqrt(beta); the frequency stays omega0; the
deviation from A0 relaxes at the rate
d/dA[(mu/2) A (1 - beta A^2/4)] at A0 = -mu, the Floquet exponent.  Leading
order in mu/omega0.

Numeric (shooting, exact): in the scaled variables x = sqrt(beta) q,
tau = omega0 t, eps = mu/omega0 the equation is x'' - eps (1 - x^2) x' + x = 0.
From (x, x') = (3, 0) a few periods are integrated (a transient, not waited
out), the last maximum (section x' = 0, x > 0) and the last period are the
start of Newton's method on phi_T(X, 0) = (X, 0) for (X, T), with the Jacobian
[M e1 - e1, f(phi_T)] from the variational equations (DOP853; Radau with
finite-difference Jacobian for eps > 2, where the cycle is a stiff
relaxation oscillation).  A = X/sqrt(beta) (the section is the maximum of q),
omega = 2 pi omega0/T.  lambda_lc: Liouville's formula, the period average
of the divergence eps (1 - x^2), carried along as an extra state; the second
multiplier det M is compared with exp(lambda T) where it is resolvable.
"""

from __future__ import annotations

import math

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.floquet import flow_with_variations
from mech.solvers.ode import Event, integrate

exercise = Exercise(
    "5.9",
    formulas=[
        "dA/dt = (μ/2) A (1 - β A²/4)  (reduced equation)",
        "A = 2/β^(1/2),  ω = ω₀",
        "λ_lc = -μ",
    ],
    leading_order=("A", "omega", "lambda_lc"),
)

STIFF_EPS = 2.0  # mu/omega0 above which the cycle is a relaxation oscillation (no Newton needed)
# mu/omega0 above which the explicit method's stability limit (step < ~3/(eps (x^2 - 1)) on the
# slow branches, ~eps^2 steps a cycle) costs more than the implicit Radau's accuracy-limited steps
IMPLICIT_EPS = 30.0


@exercise.analytic
def analytic(p):
    return {"A": 2.0 / math.sqrt(p.beta), "omega": p.omega0, "lambda_lc": -p.mu}


@exercise.expected_error
def expected_error(p):
    """The reduced equation neglects relative O(eps^2), eps = mu/omega0: the
    second order of the averaging shifts the frequency by -eps^2/16, and the
    amplitude and the exponent by amounts of the same order (measured:
    +eps^2/192 and -eps^2/16).  The bounds are those coefficients times 2 to 4:
    eps^2/48, eps^2/8, eps^2/8.  At eps >~ 1 the expansion fails and the bound
    becomes large, as it should."""
    e2 = (p.mu / p.omega0) ** 2
    return {"A": e2 / 48.0, "omega": e2 / 8.0, "lambda_lc": e2 / 8.0}


def _f(t, y, eps):
    return np.array([y[1], eps * (1.0 - y[0] ** 2) * y[1] - y[0]])


def _jac(t, y, eps):
    return np.array([[0.0, 1.0], [-2.0 * eps * y[0] * y[1] - 1.0, eps * (1.0 - y[0] ** 2)]])


@exercise.numeric
def numeric(p, run):
    eps = p.mu / p.omega0
    rtol = run.rtol
    stiff = eps > STIFF_EPS
    method = "DOP853"
    f = lambda t, y: _f(t, y, eps)  # noqa: E731
    jac = lambda t, y: _jac(t, y, eps)  # noqa: E731
    vscale = max(1.0, eps)  # x' reaches ~eps in the fast jumps of a relaxation oscillation

    def div(t, y):
        return [eps * (1.0 - y[0] ** 2)]

    if stiff:
        return _relaxation(p, run, eps, vscale, div)

    # a short transient from above the cycle, to find the section and a period
    maxima = Event(lambda t, y: y[1], terminal=False, direction=-1.0, name="x' = 0, maximum")
    pre = integrate(
        f, (0.0, 4.0 * 2.0 * math.pi), [3.0, 0.0], rtol=min(1e-8, 1e3 * rtol), atol=1e-10 * vscale, method=method,
        events=[maxima],
    )
    run.record(pre)
    tm = [t for t, y in zip(pre.t_events[0], pre.y_events[0]) if y[0] > 0]
    xm = [y[0] for y in pre.y_events[0] if y[0] > 0]
    if len(tm) < 2:
        raise NumericFailure("fewer than two maxima in the transient: no start for the shooting")
    X, T = xm[-1], tm[-1] - tm[-2]

    for it in range(30):
        y_end, M, extra, traj = flow_with_variations(
            f, jac, [X, 0.0], (0.0, T), rtol=rtol, scale=[1.0, vscale], method=method, extra=div, n_extra=1
        )
        run.record(traj)
        r = y_end - np.array([X, 0.0])
        J = np.array([[M[0, 0] - 1.0, f(0, y_end)[0]], [M[1, 0], f(0, y_end)[1]]])
        dX, dT = np.linalg.solve(J, -r)
        dX = float(np.clip(dX, -0.5 * X, 0.5 * X))
        X, T = X + dX, T + float(dT)
        if abs(dX) < rtol * X and abs(dT) < rtol * T and np.max(np.abs(r)) < 10 * rtol * vscale:
            break
    else:
        raise NumericFailure("Newton's method for the limit cycle did not converge in 30 steps")
    run.info["newton_steps"] = it + 1
    if X <= 0:
        raise NumericFailure("the shooting converged to a start that is not a maximum of q")

    lam_tau = float(extra[0]) / T
    det = float(np.linalg.det(M))
    run.info["det_M"] = det
    if det > 1e3 * rtol:
        # Liouville: det M = exp(integral of the divergence); only resolvable when det M is not tiny
        run.invariant("Liouville (ln det M - int div)", (math.log(det) - float(extra[0])) / max(abs(float(extra[0])), 1.0))
    return {"A": X / math.sqrt(p.beta), "omega": 2.0 * math.pi * p.omega0 / T, "lambda_lc": p.omega0 * lam_tau}


def _relaxation(p, run, eps, vscale, div):
    """The stiff case: the cycle attracts so strongly (second multiplier exp(lambda T) < 1e-9)
    that a start's error is gone after one period; Radau with the exact Jacobian
    runs a few periods, and the last two maxima must agree to the tolerance."""
    rtol = run.rtol

    def rhs(t, y):
        return np.array([y[1], eps * (1.0 - y[0] ** 2) * y[1] - y[0], eps * (1.0 - y[0] ** 2)])

    def jac(t, y):
        return np.array(
            [[0.0, 1.0, 0.0], [-2.0 * eps * y[0] * y[1] - 1.0, eps * (1.0 - y[0] ** 2), 0.0], [-2.0 * eps * y[0], 0.0, 0.0]]
        )

    method = "Radau" if eps > IMPLICIT_EPS else "DOP853"
    maxima = Event(lambda t, y: y[1], terminal=False, direction=-1.0, name="x' = 0, maximum")
    # the slow phases last about (3 - 2 ln 2) eps each cycle: run several of them
    t_run = 4.6 * (1.614 * eps + 2.0 * math.pi)
    traj = integrate(
        rhs, (0.0, t_run), [3.0, 0.0, 0.0], rtol=rtol, atol=[rtol * 1e-3, rtol * 1e-3 * vscale, rtol * 1e-3 * eps],
        method=method, events=[maxima], jac=jac,
    )
    run.record(traj)
    ev = [(t, y) for t, y in zip(traj.t_events[0], traj.y_events[0]) if y[0] > 0]
    if len(ev) < 3:
        raise NumericFailure(f"only {len(ev)} maxima in the relaxation run: too short")
    (t1, y1), (t2, y2), (t3, y3) = ev[-3:]
    T, T_prev = t3 - t2, t2 - t1
    if abs(T - T_prev) > 100 * rtol * T or abs(y3[0] - y2[0]) > 100 * rtol * y3[0]:
        raise NumericFailure(f"the relaxation cycle has not settled: periods {T_prev:.12g}, {T:.12g}")
    lam_tau = (y3[2] - y2[2]) / T
    run.info["second_multiplier_log10"] = lam_tau * T / math.log(10.0)
    run.info["method_note"] = (
        "Radau (implicit, exact Jacobian): stiff relaxation oscillation" if method == "Radau"
        else "DOP853: relaxation oscillation, mildly stiff at this eps (explicit steps stay accuracy-limited)"
    )
    run.claim("lambda_lc", rel=1e3 * rtol)
    return {"A": y3[0] / math.sqrt(p.beta), "omega": 2.0 * math.pi * p.omega0 / T, "lambda_lc": p.omega0 * lam_tau}
