"""The registry: every exercise module under problems/ch4 and problems/ch5, found by file name.

Two levels, so that the commands that only list stay fast:

* ``index()`` reads the file names (``ex4_15_sliding_ladder.py`` is exercise 4.15), the
  packaged catalogue (title, topic) and, from each module's text, which solvers it
  registers.  It imports no exercise module, hence no numpy and no scipy.
* ``get(id)`` imports the one module asked for; ``all_exercises()`` imports them all.

tests/test_conformance.py holds the index to what the imported modules really register.
"""

from __future__ import annotations

import importlib
import os
import pkgutil
import re
import tomllib
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

from mech.problems.spec import BadInput, Exercise

CHAPTER_PACKAGES = ("mech.problems.ch4", "mech.problems.ch5")
_MODULE_NAME = re.compile(r"^ex(\d+)_(\d+)_\w+$")


@dataclass(frozen=True)
class Entry:
    id: str
    title: str
    topic: str
    methods: tuple[str, ...]
    module: str

    @property
    def chapter(self) -> int:
        return int(self.id.split(".")[0])


def _id_key(ex_id: str) -> tuple[int, ...]:
    return tuple(int(part) for part in ex_id.split("."))


@lru_cache(maxsize=1)
def _modules() -> dict[str, str]:
    """Exercise id -> module name, from the file names alone."""
    return {ex_id: name for ex_id, (name, _) in _files().items()}


@lru_cache(maxsize=1)
def _files() -> dict[str, tuple[str, str]]:
    """Exercise id -> (module name, source path)."""
    found: dict[str, tuple[str, str]] = {}
    for pkg_name in CHAPTER_PACKAGES:
        pkg = importlib.import_module(pkg_name)
        for info in pkgutil.iter_modules(pkg.__path__):
            m = _MODULE_NAME.match(info.name)
            if not m:
                continue
            ex_id = f"{m.group(1)}.{m.group(2)}"
            if ex_id in found:
                raise RuntimeError(f"exercise {ex_id} has two modules: {found[ex_id][0]} and {info.name}")
            path = os.path.join(info.module_finder.path, info.name + ".py")
            found[ex_id] = (f"{pkg_name}.{info.name}", path)
    return dict(sorted(found.items(), key=lambda kv: _id_key(kv[0])))


def _heading(text: str) -> dict:
    """The catalogue's leading keys (id, title, topic): the TOML before its statement, parsed alone."""
    cut = text.find("\nstatement")
    try:
        return tomllib.loads(text if cut < 0 else text[:cut])
    except tomllib.TOMLDecodeError:
        return tomllib.loads(text)


@lru_cache(maxsize=1)
def index() -> list[Entry]:
    entries = []
    catalogue = resources.files("mech.problems").joinpath("catalogue")
    for ex_id, (module, origin) in _files().items():
        spec = _heading(catalogue.joinpath(f"{ex_id}.toml").read_text("utf-8"))
        if "title" not in spec or "topic" not in spec:
            spec = tomllib.loads(catalogue.joinpath(f"{ex_id}.toml").read_text("utf-8"))
        with open(origin, encoding="utf-8") as fh:
            text = fh.read()
        methods = tuple(m for m in ("analytic", "numeric") if f"@exercise.{m}\n" in text)
        entries.append(Entry(ex_id, spec["title"], spec["topic"], methods, module))
    return entries


def _load(ex_id: str, module_name: str) -> Exercise:
    module = importlib.import_module(module_name)
    ex = getattr(module, "exercise", None)
    if not isinstance(ex, Exercise) or ex.id != ex_id:
        raise RuntimeError(f"{module_name} does not define exercise {ex_id}")
    return ex


@lru_cache(maxsize=1)
def all_exercises() -> dict[str, Exercise]:
    return {ex_id: _load(ex_id, module) for ex_id, module in _modules().items()}


def get(ex_id: str) -> Exercise:
    modules = _modules()
    key = ex_id.strip()
    if key not in modules:
        known = ", ".join(modules) or "none"
        raise BadInput(f"unknown exercise '{ex_id}'; registered: {known}")
    return _load(key, modules[key])
