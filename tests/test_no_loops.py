"""No two modules import each other, inside functions either: the formula path (formula_ast, points,
reference, explain, formulas, answers) and the exercise contract (spec, scales, scene, params) go down.

Every ``import``/``from ... import`` of a ``mech`` module anywhere in a file (at the top or inside a function)
is an edge; a cycle among the modules of ``verification/``, ``students/``, ``studies/`` or ``problems/`` (exercises excepted: they import
only downward by the layer contract) fails."""

from __future__ import annotations

import ast
import functools
from pathlib import Path

from conftest import parsed

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = {"verification": "mech.verification", "students": "mech.students", "studies": "mech.studies",
            "problems": "mech.problems"}


def _module_of(path: Path, folder: str) -> str:
    rel = path.relative_to(ROOT / folder).with_suffix("")
    parts = [p for p in rel.parts if p != "__init__"]
    return ".".join([PACKAGES[folder], *parts])


@functools.lru_cache(maxsize=None)
def _edges() -> dict[str, set[str]]:
    """The import edges among the walked modules (computed once: callers only read them)."""
    mods = {}
    for folder in PACKAGES:
        for path in (ROOT / folder).rglob("*.py"):
            mods[_module_of(path, folder)] = path
    edges = {m: set() for m in mods}
    for m, path in mods.items():
        for node in ast.walk(parsed(path)):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            for n in names:
                if n in mods and n != m:
                    edges[m].add(n)
    return edges


def _cycles(edges):
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def test_no_module_of_verification_or_problems_imports_its_caller():
    assert _cycles(_edges()) == []


def test_the_loop_finder_finds_a_planted_loop():
    edges = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert _cycles(edges) == [["a", "b", "c"]]


def test_the_formula_path_goes_down():
    e = _edges()
    order = ["mech.verification.judge"] + ["mech.students." + m for m in
                                           ("formula_ast", "points", "reference", "explain", "formulas", "answers")]
    for k, low in enumerate(order):
        for high in order[k + 1:]:
            assert high not in e[low], f"{low} imports {high}, its caller"
