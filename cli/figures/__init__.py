"""Figures for ``mech plot`` and ``mech sweep --plot``; matplotlib is imported only in here.

``SCENES`` maps an exercise id to the module and function drawing its scene:
``draw(ex, params, *, n_numeric, rtol) -> Figure``.  Every other exercise (and
any with ``--generic``) gets ``generic.generic_figure``.
"""

from __future__ import annotations

import importlib

SCENES: dict[str, tuple[str, str]] = {
    "4.10": ("ch4", "physical_pendulum"),
    "4.12": ("ch4", "chime"),
    "4.15": ("ch4", "ladder"),
    "4.21": ("ch4", "heavy_top"),
    "4.27": ("ch4", "lagrange"),
    "4.28": ("ch4", "lagrange"),
    "5.6": ("ch5", "pendulum_phase"),
    "5.11": ("ch5", "mathieu"),
    "5.13": ("ch5", "kapitza"),
}


def scene_for(ex_id: str):
    """The scene-drawing function of an exercise, or None."""
    if ex_id not in SCENES:
        return None
    module, attr = SCENES[ex_id]
    return getattr(importlib.import_module(f"mech.cli.figures.{module}"), attr)


def draw(ex, params, *, generic: bool = False, vary: str | None = None, n_numeric: int = 5, rtol=None):
    from mech.cli.figures.generic import generic_figure

    scene = None if (generic or vary) else scene_for(ex.id)
    if scene is None:
        return generic_figure(ex, params, vary=vary, n_numeric=n_numeric, rtol=rtol)
    return scene(ex, params, n_numeric=n_numeric, rtol=rtol)
