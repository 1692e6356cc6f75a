"""A route written once (STYLE.md, issue 41): no module of problems/ or solvers/ defines a function twice, once
for one point and once for a batch (``X`` beside ``X_batch``, ``X_batched``, ``X_many`` or ``Xs``).  A route with
a batched form is that form; the one-point call is the batch of one (``Exercise.batched``), so the two cannot
drift apart."""

from __future__ import annotations

import ast
from pathlib import Path

from conftest import parsed, parsed_source

ROOT = Path(__file__).resolve().parents[1]
WALKED = ("problems", "solvers")
SUFFIXES = ("_batch", "_batched", "_many", "_vec", "s")
# X beside Xs where the plural is not a second copy of X's computation
NOT_TWINS = {# the declaration's builder of a rate-given state beside the solved rates at a state
             ("problems/physics.py", "rate"),
             # exp(A) and exp(A t) at many t: two entries of the module's one scaling-and-squaring loop
             ("solvers/numerics/linear_flow.py", "expm")}


def twins(source: str, rel: str = "", tree: ast.Module | None = None) -> list[str]:
    """``X/X_batch`` (and the other suffixes) of the functions a module defines, methods and nested ones
    included (``tree``: ``source`` parsed already)."""
    names = {node.name for node in ast.walk(ast.parse(source) if tree is None else tree)
             if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))}
    out = []
    for name in sorted(names):
        for suffix in SUFFIXES:
            if name + suffix in names and (rel, name) not in NOT_TWINS:
                out.append(f"{rel}: {name} / {name + suffix}")
    return out


def all_twins(root: Path = ROOT) -> list[str]:
    found = []
    for floor in WALKED:
        for path in sorted((root / floor).rglob("*.py")):
            rel = path.relative_to(root).as_posix()
            found += twins(parsed_source(path), rel, parsed(path))
    return found


def test_no_route_is_written_twice():
    assert all_twins() == []


def test_the_count_finds_a_twin():
    """The count would see the pairs it replaced (so that the test above can fail)."""
    src = ("def _half(p, rtol, run):\n    pass\n\ndef _half_batch(P, rtol):\n    pass\n\n"
           "class A:\n    def follow(self):\n        pass\n\n    def follow_batch(self):\n        pass\n\n"
           "def _trace(x):\n    pass\n\ndef _traces(x):\n    pass\n")
    assert twins(src) == [": _half / _half_batch", ": _trace / _traces", ": follow / follow_batch"]


def test_every_integrating_exercise_has_one_batched_route():
    """Issue 41: every exercise whose numeric route integrates equations of motion has a batched route
    giving all its outputs, and that route is its numeric solver at one point (the batch of one): no second,
    scalar route registered beside it (docs/charts.md and docs/grading.md say so)."""
    from mech.problems import registry

    missing, scalar = [], []
    for entry in registry.index():
        if not entry.integrates:
            continue
        ex = registry.get(entry.id)
        route = ex.batched_route
        if route is None or set(route.outputs) != {o.name for o in ex.outputs}:
            missing.append(entry.id)
        elif ex.numeric_solver != ex.batch_of_one:
            scalar.append(entry.id)
    assert not missing and not scalar, (missing, scalar)
