"""Figures for ``mech plot`` and ``mech sweep --plot``; matplotlib is imported only in here.

An exercise with a scene hook (``@exercise.scene``, see mech.problems.scene) hands
over what to draw, computed by its own physics; ``scene.draw_scene`` draws it.
Every other exercise (and any with ``--generic`` or ``--vary``) gets
``generic.generic_figure``: its outputs against one parameter, from its solvers.
Nothing in figures/ computes physics.
"""

from __future__ import annotations


def has_scene(ex) -> bool:
    return bool(getattr(ex, "has_scene", False))


def draw(ex, params, *, generic: bool = False, vary: str | None = None, n_numeric: int = 5, rtol=None,
         finish: bool = True):
    """The exercise's figure; ``finish=False`` leaves the legends' placement (a layout pass, no physics) to
    ``common.save``, outside a solve's time budget."""
    from mech.figures.common import finish_legends

    if not (generic or vary) and has_scene(ex):
        from mech.figures.scene import draw_scene

        from mech.problems.scene import make_scene

        scene, run = make_scene(ex, params, rtol=rtol, points=n_numeric)
        fig = draw_scene(ex, params, scene, run)
    else:
        from mech.figures.generic import generic_figure

        fig = generic_figure(ex, params, vary=vary, n_numeric=n_numeric, rtol=rtol)
    return finish_legends(fig) if finish else fig
