"""The registry: every exercise module under problems/ch4 and problems/ch5, found by file name.

Two levels, so that the commands that only list stay fast:

* ``index()`` reads the file names (``ex4_15_sliding_ladder.py`` is exercise 4.15) and the
  heading of each packaged catalogue file: title, topic, ``from_book``, and what the
  exercise's registration declares (``integrates``: it has states, a motion to show;
  ``theory``: exact or leading-order).  It imports no exercise module, hence no numpy
  and no scipy.
* ``get(id)`` imports the one module asked for; ``all_exercises()`` imports them all.

tests/test_conformance.py holds each catalogue heading to what the module really registers
(``declarations``), so a new exercise is its module, its catalogue file and its test.
"""

from __future__ import annotations

import importlib
import os
import pkgutil
import re
import tomllib
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from mech.core.safeio import shown
from mech.problems.spec import BadInput, Exercise

CHAPTER_PACKAGES = ("mech.problems.ch4", "mech.problems.ch5")
_MODULE_NAME = re.compile(r"^ex(\d+)_(\d+)_\w+$")


def from_book(ex_id: str) -> bool:
    """True for an exercise that is the book's own, False for one set for mech on the chapter's topics (the
    catalogue file's ``from_book``)."""
    for entry in index():
        if entry.id == ex_id.strip():
            return entry.from_book
    raise BadInput(unknown_id_message(ex_id, list(_modules())))


@dataclass(frozen=True)
class Entry:
    id: str
    title: str
    topic: str
    methods: tuple[str, ...]
    module: str
    integrates: bool = False  # its numeric route integrates declared equations of motion (a trajectory)
    from_book: bool = True  # the book's own exercise (False: set for mech on the chapter's topics)
    theory: str = "exact"  # its analytic values: "exact", "leading-order" or "partly leading-order"

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


_HERE = Path(__file__).parent  # the package's data lies beside it (importlib.resources costs 4 ms of imports)
_THEORIES = ("exact", "leading-order", "partly leading-order")


@lru_cache(maxsize=1)
def index() -> list[Entry]:
    entries = []
    catalogue = _HERE / "catalogue"
    for ex_id, (module, _origin) in _files().items():
        text = catalogue.joinpath(f"{ex_id}.toml").read_text("utf-8")
        spec = _heading(text)
        if any(k not in spec for k in ("title", "topic", "from_book", "integrates", "theory")):
            spec = tomllib.loads(text)
        where = f"problems/catalogue/{ex_id}.toml"
        for key in ("from_book", "integrates"):
            if not isinstance(spec.get(key), bool):
                raise RuntimeError(f"{where}: {key} = true or false is missing")
        if spec.get("theory") not in _THEORIES:
            raise RuntimeError(f"{where}: theory must be one of {', '.join(_THEORIES)}")
        methods = tuple(spec.get("methods", ("analytic", "numeric")))
        entries.append(Entry(ex_id, spec["title"], spec["topic"], methods, module, spec["integrates"],
                             spec["from_book"], spec["theory"]))
    return entries


def declarations(ex: Exercise) -> dict:
    """What an exercise's registration declares, as its catalogue heading records it (``index``)."""
    leading = [o.name for o in ex.outputs if o.theory != "exact"]
    theory = "exact" if not leading else (
        "leading-order" if len(leading) == len(ex.outputs) else "partly leading-order")
    return {"methods": list(ex.methods), "integrates": bool(ex.states), "theory": theory}


def _load(ex_id: str, module_name: str) -> Exercise:
    module = importlib.import_module(module_name)
    ex = getattr(module, "exercise", None)
    if not isinstance(ex, Exercise) or ex.id != ex_id:
        raise RuntimeError(f"{module_name} does not define exercise {ex_id}")
    return ex


@lru_cache(maxsize=1)
def all_exercises() -> dict[str, Exercise]:
    return {ex_id: _load(ex_id, module) for ex_id, module in _modules().items()}


MAX_ID_CHARS = 12  # "exercise 4.15" is 13 with its word; anything longer is no id


def get(ex_id: str) -> Exercise:
    check_id_type(ex_id)
    modules = _modules()
    key = ex_id.strip()
    if key not in modules:
        raise BadInput(unknown_id_message(ex_id, list(modules)))
    return _load(key, modules[key])


def check_id_type(ex_id) -> None:
    """An id is a string: as numbers 4.10 and 4.1 are the same float, so a number is refused, never guessed."""
    if isinstance(ex_id, str):
        return
    if isinstance(ex_id, (int, float)) or type(ex_id).__module__ == "numpy":
        raise BadInput(f"exercise id {ex_id} is a number; give it as a string, e.g. mech.solve(\"4.10\") "
                       f"(as numbers 4.10 and 4.1 are the same)")
    raise BadInput(f"exercise id {shown(repr(ex_id))} must be a string such as \"4.15\"")


def _spans(ids: list[str]) -> str:
    """The registered ids by chapter, each chapter as its first and last id joined by a dash."""
    chapters: dict[int, list[str]] = {}
    for i in ids:
        chapters.setdefault(_id_key(i)[0], []).append(i)
    return ", ".join(f"{v[0]}-{v[-1]}" if len(v) > 1 else v[0] for v in chapters.values()) or "none"


def unknown_id_message(ex_id: str, ids: list[str]) -> str:
    """One line for an id that is not registered: the nearest id where one is close, else the ranges."""
    import difflib

    text = str(ex_id).strip()
    if len(text) > MAX_ID_CHARS + 8:  # no hint for what is no id: building one would cost memory
        return f"unknown exercise '{shown(text, 20)}' (registered: {_spans(ids)})"
    norm = re.sub(r"^(?:ex(?:ercise)?)\s*", "", text.lower()).replace(",", ".").replace("-", ".").replace("_", ".")
    m = re.fullmatch(r"(\d+)\.(\d+)", norm)
    close: list[str] = []
    if norm in ids:
        close = [norm]
    elif m:
        # a well-formed id: only a leading zero (4.015) or an extra digit (4.150) is a near miss; a number
        # just past a chapter's end (4.37) or an unknown chapter is not
        chapter, number = m.groups()
        tries = [number.lstrip("0")]
        if len(number) >= 3:
            tries += [number[:-1]] + [number[:k] + number[k + 1:] for k in range(len(number) - 1)]
        if 2 <= len(number) <= 3:
            # a transposition of two neighbouring digits (4.51 for 4.15)
            tries += [number[:k] + number[k + 1] + number[k] + number[k + 2:] for k in range(len(number) - 1)]
        close = [f"{chapter}.{n}" for n in tries if f"{chapter}.{n}" in ids][:1]
    elif len(norm) >= 3:
        close = difflib.get_close_matches(norm, ids, n=1, cutoff=0.7)
    hint = f"; did you mean {close[0]}?" if close else ""
    return f"unknown exercise '{shown(text)}'{hint} (registered: {_spans(ids)})"
