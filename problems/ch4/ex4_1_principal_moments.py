"""4.1 Principal moments of inertia of a hoop, a disk, a spherical shell and a ball.

Analytic: the axis moment of a hoop is M R^2 (every element at distance R); the
perpendicular-axis theorem halves it for a diameter.  The disk's elements
spread over the area weight r^2 with 2 r dr / R^2, giving M R^2 / 2 and
M R^2 / 4.  For the shell, sum over three axes of I = 2 sum m r^2 = 2 M R^2 by
symmetry, so I = 2/3 M R^2; for the ball sum m r^2 = 3/5 M R^2, so I = 2/5 M R^2.

Numeric: each body is a quadrature point set of unit mass and radius (trapezoid
in azimuth, Gauss-Legendre in r and cos theta, exact for these polynomial and
trigonometric integrands), turned by an arbitrary rotation; the full 3x3
tensor is taken about the set's own center of mass and diagonalized.  The
degenerate pair or triple is found by a relative comparison (scale-free, so an
Earth-sized or a nucleus-sized body is no different) and averaged; the result
is scaled back by M R^2.
"""

from __future__ import annotations

import numpy as np

from mech.problems.spec import Exercise, NumericFailure
from mech.solvers.mechanics import inertia
from mech.solvers.mechanics.frames import rotation

exercise = Exercise(
    "4.1",
    formulas=[
        "hoop: I_diam = M R²/2, I_axis = M R²",
        "disk: I_diam = M R²/4, I_axis = M R²/2",
        "spherical shell: I = (2/3) M R²",
        "ball: I = (2/5) M R²",
    ],
)

# an arbitrary orientation, so that no principal axis lies along a coordinate axis
_TURN = rotation([0.3, -0.7, 0.65], 1.234)


@exercise.analytic
def analytic(p):
    mr2 = p.M * p.R**2
    return {
        "I_hoop_diam": mr2 / 2,
        "I_hoop_axis": mr2,
        "I_disk_diam": mr2 / 4,
        "I_disk_axis": mr2 / 2,
        "I_shell": 2 * mr2 / 3,
        "I_ball": 2 * mr2 / 5,
    }


def _moments(points, weights) -> np.ndarray:
    return inertia.principal_moments(inertia.inertia_tensor(points @ _TURN.T, weights))


def _split(name: str, moments: np.ndarray) -> tuple[float, float]:
    """(the doubly degenerate moment, the single one) of a flat symmetric body."""
    groups = inertia.degenerate_groups(moments, rel=1e-9)
    pair = [g for g in groups if len(g) == 2]
    single = [g for g in groups if len(g) == 1]
    if len(pair) != 1 or len(single) != 1:
        raise NumericFailure(f"{name}: expected one degenerate pair, got moments {moments}")
    return float(np.mean(moments[pair[0]])), float(moments[single[0][0]])


def _triple(name: str, moments: np.ndarray) -> float:
    groups = inertia.degenerate_groups(moments, rel=1e-9)
    if len(groups) != 1:
        raise NumericFailure(f"{name}: expected three equal moments, got {moments}")
    return float(np.mean(moments))


@exercise.numeric
def numeric(p, run):
    scale = p.M * p.R**2
    hoop_diam, hoop_axis = _split("hoop", _moments(*inertia.hoop(16)))
    disk_diam, disk_axis = _split("disk", _moments(*inertia.disk(6, 16)))
    shell = _triple("shell", _moments(*inertia.shell(6, 16)))
    ball = _triple("ball", _moments(*inertia.ball(6, 6, 16)))
    values = {
        "I_hoop_diam": hoop_diam * scale,
        "I_hoop_axis": hoop_axis * scale,
        "I_disk_diam": disk_diam * scale,
        "I_disk_axis": disk_axis * scale,
        "I_shell": shell * scale,
        "I_ball": ball * scale,
    }
    run.method = "quadrature (exact rules) + symmetric eigensolver"
    for name in values:
        # exact quadrature: only round-off in a few hundred sums and the eigensolver
        run.claim(name, rel=1e-12)
    return values
