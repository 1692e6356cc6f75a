"""The registry: every exercise module under problems/ch4 and problems/ch5, found by name.

Discovery imports the modules (numpy only); scipy is imported by the solvers when
they run, so listing stays fast.
"""

from __future__ import annotations

import importlib
import pkgutil
from functools import lru_cache

from mech.problems.spec import BadInput, Exercise

CHAPTER_PACKAGES = ("mech.problems.ch4", "mech.problems.ch5")


def _id_key(ex_id: str) -> tuple[int, ...]:
    return tuple(int(part) for part in ex_id.split("."))


@lru_cache(maxsize=1)
def all_exercises() -> dict[str, Exercise]:
    found: dict[str, Exercise] = {}
    for pkg_name in CHAPTER_PACKAGES:
        pkg = importlib.import_module(pkg_name)
        for info in pkgutil.iter_modules(pkg.__path__):
            if not info.name.startswith("ex"):
                continue
            module = importlib.import_module(f"{pkg_name}.{info.name}")
            ex = getattr(module, "exercise", None)
            if isinstance(ex, Exercise):
                if ex.id in found:
                    raise RuntimeError(f"exercise {ex.id} registered twice")
                found[ex.id] = ex
    return dict(sorted(found.items(), key=lambda kv: _id_key(kv[0])))


def get(ex_id: str) -> Exercise:
    exercises = all_exercises()
    key = ex_id.strip()
    if key not in exercises:
        known = ", ".join(exercises) or "none"
        raise BadInput(f"unknown exercise '{ex_id}'; registered: {known}")
    return exercises[key]
