"""Figures for ``mech plot`` and ``mech sweep --plot``; matplotlib is imported only in here.

An exercise with a scene hook (``@exercise.scene``, see mech.problems.scene) hands
over what to draw, computed by its own physics; ``scene.draw_scene`` draws it.
Every other exercise (and any with ``--generic`` or ``--vary``) gets
``generic.generic_figure``: its outputs against one parameter, from its solvers.
Nothing in figures/ computes physics.
"""

from __future__ import annotations


def has_scene(ex) -> bool:
    return getattr(ex, "_scene", None) is not None


def draw(ex, params, *, generic: bool = False, vary: str | None = None, n_numeric: int = 5, rtol=None):
    if not (generic or vary) and has_scene(ex):
        from mech.figures.scene import draw_scene

        scene, run = ex.make_scene(params, rtol=rtol, points=n_numeric)
        return draw_scene(ex, params, scene, run)
    from mech.figures.generic import generic_figure

    return generic_figure(ex, params, vary=vary, n_numeric=n_numeric, rtol=rtol)
