"""Structure-preserving integration of separable Hamiltonians H(q, p) = T(p) + V(q).

Why: an adaptive Runge-Kutta method (DOP853, RK45) does not conserve energy;
its energy error grows roughly linearly with the number of periods (scipy
issue 12690), so a scene followed over thousands of periods drifts.  A
symplectic method keeps a nearby "shadow" Hamiltonian exactly, so its energy
error stays bounded (it oscillates, it does not grow) for exponentially long
times.  Here: Stormer-Verlet (kick-drift-kick, order 2) composed by Yoshida
(1990) to order 4 (3 stages) or 6 (7 stages, solution A), with a fixed step.

Events of a fixed-step method: the step in which the event function changes
sign is found, then the event time inside it is solved for by the Illinois
(regula falsi) method on the length s of a partial step from the step's start,
so the event time carries the integrator's full order (no interpolation).

A scene (``SeparableHamiltonian``) is what an exercise exposes through its
optional ``hamiltonian`` hook: velocity dT/dp, force -dV/dq, the energy, the
start, an optional terminal event and the readout of its outputs.  Works on
floats (one degree of freedom) as well as numpy arrays.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from mech.core.errors import NumericFailure

__all__ = ["SeparableHamiltonian", "YOSHIDA4", "YOSHIDA6", "weights", "integrate_fixed", "solve_scene"]

_CBRT2 = 2.0 ** (1.0 / 3.0)
YOSHIDA4 = (1.0 / (2.0 - _CBRT2), -_CBRT2 / (2.0 - _CBRT2), 1.0 / (2.0 - _CBRT2))
_W6 = (-1.17767998417887, 0.235573213359357, 0.784513610477560)  # Yoshida 1990, solution A
YOSHIDA6 = (_W6[2], _W6[1], _W6[0], 1.0 - 2.0 * sum(_W6), _W6[0], _W6[1], _W6[2])


def weights(order: int) -> tuple[float, ...]:
    """Stormer-Verlet sub-step weights of the composition of this order (2, 4 or 6)."""
    return {2: (1.0,), 4: YOSHIDA4, 6: YOSHIDA6}[order]


@dataclass
class SeparableHamiltonian:
    """H = T(p) + V(q) in scaled variables, with its start, its stopping event and its readout.

    velocity(p) = dT/dp; force(q) = -dV/dq; energy(q, p) = H.
    event(q, p) (optional) stops the run at its first zero crossed in ``direction``
    (+1 upward, -1 downward, 0 both); without it the run stops at ``t_max``.
    readout(t, q, p) -> {output: value} turns the final state into the exercise's outputs.
    time_scale: the shortest time over which the motion changes (sets the step).
    """

    velocity: Callable
    force: Callable
    energy: Callable
    q0: object
    p0: object
    t_max: float
    readout: Callable
    event: Callable | None = None
    direction: float = 0.0
    time_scale: float = 1.0
    name: str = "scene"
    info: dict = field(default_factory=dict)


class _Stepper:
    """One composed step; counts force evaluations (the cost unit, like nfev)."""

    def __init__(self, velocity, force, order):
        self.velocity, self.force, self.w = velocity, force, weights(order)
        self.nfev = 0

    def step(self, q, p, f, h):
        """Advance (q, p) by h; f is force(q) at the start (reused: kick-drift-kick is FSAL)."""
        vel, force = self.velocity, self.force
        for w in self.w:
            hw = w * h
            p = p + 0.5 * hw * f
            q = q + hw * vel(p)
            f = force(q)
            self.nfev += 1
            p = p + 0.5 * hw * f
        return q, p, f


@dataclass
class FixedResult:
    t: float
    q: object
    p: object
    steps: int
    nfev: int
    energy_drift: float  # max |H - H0| / scale over the sampled steps
    event_found: bool
    wall_s: float
    h: float
    order: int
    samples: list = field(default_factory=list)


def integrate_fixed(
    scene: SeparableHamiltonian,
    h: float,
    *,
    order: int = 6,
    energy_scale: float | None = None,
    sample_every: int = 0,
    max_steps: int = 50_000_000,
) -> FixedResult:
    """Integrate the scene with the fixed step h to its event (or to t_max)."""
    start = time.perf_counter()
    st = _Stepper(scene.velocity, scene.force, order)
    q, p = scene.q0, scene.p0
    f = scene.force(q)
    st.nfev += 1
    e0 = scene.energy(q, p)
    escale = energy_scale if energy_scale else max(abs(e0), 1e-300)
    drift = 0.0
    t = 0.0
    n_steps = int(math.ceil(scene.t_max / h))
    if n_steps > max_steps:
        raise NumericFailure(f"symplectic run needs {n_steps} steps of {h:.3g} (more than {max_steps})")
    g_prev = scene.event(q, p) if scene.event else None
    samples = []
    found = False
    for k in range(n_steps):
        hk = min(h, scene.t_max - t)
        q1, p1, f1 = st.step(q, p, f, hk)
        if scene.event is not None:
            g1 = scene.event(q1, p1)
            crossed = (g_prev < 0.0 <= g1 and scene.direction >= 0) or (g_prev > 0.0 >= g1 and scene.direction <= 0)
            if crossed and g_prev != 0.0:
                s = _event_in_step(st, scene.event, q, p, f, g_prev, g1, hk)
                q, p, f = st.step(q, p, f, s)
                t += s
                found = True
                drift = max(drift, abs(scene.energy(q, p) - e0) / escale)
                break
            g_prev = g1
        q, p, f = q1, p1, f1
        t += hk
        if sample_every and k % sample_every == 0:
            e = scene.energy(q, p)
            drift = max(drift, abs(e - e0) / escale)
            samples.append((t, (e - e0) / escale))
    drift = max(drift, abs(scene.energy(q, p) - e0) / escale)
    return FixedResult(t, q, p, k + 1, st.nfev, drift, found, time.perf_counter() - start, h, order, samples)


def _event_in_step(st, event, q, p, f, g0, g1, h):
    """The partial step s in (0, h] with event(step(q, p, s)) = 0 (Brent's method on the partial step)."""
    from mech.solvers.numerics.roots import brentq

    def g(s):
        qs, ps, _ = st.step(q, p, f, s)
        return event(qs, ps)

    return brentq(g, 0.0, h, fa=g0, fb=g1, xtol=4e-16 * h, rtol=4e-16, maxiter=100)


def step_for(scene: SeparableHamiltonian, rtol: float, order: int) -> float:
    """The fixed step for a requested relative accuracy: global error ~ (h/tau)^order."""
    return scene.time_scale * 0.5 * rtol ** (1.0 / order)


def solve_scene(scene: SeparableHamiltonian, rtol: float, order: int = 6) -> tuple[dict, FixedResult]:
    """The scene's outputs with a step chosen for ``rtol``; a missed event is a failure."""
    h = step_for(scene, rtol, order)
    res = integrate_fixed(scene, h, order=order)
    if scene.event is not None and not res.event_found:
        raise NumericFailure(f"{scene.name}: the event was not reached by t={res.t:.6g} (symplectic)")
    return scene.readout(res.t, res.q, res.p), res


def pendulum(theta0: float, periods: float) -> SeparableHamiltonian:
    """The plane pendulum in tau = omega0 t, H = p^2/2 - cos q, from rest at theta0, for ``periods`` swings."""
    return SeparableHamiltonian(
        velocity=lambda p: p,
        force=lambda q: -math.sin(q),
        energy=lambda q, p: 0.5 * p * p - math.cos(q),
        q0=float(theta0),
        p0=0.0,
        t_max=2.0 * math.pi * periods,
        readout=lambda t, q, p: {"q": q, "p": p},
        name="pendulum",
    )


