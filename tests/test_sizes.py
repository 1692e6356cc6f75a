"""The size limits hold (issue 34): no exercise module over 450 lines, no function over 100 lines outside tests/.

Read with ``ast`` from the source tree (the project's own code: not tests/, scripts/ or docs/): a function's
length runs from its ``def`` line to its last line, methods and nested functions included (as
``/work/shared/tools/sizes.py`` counts it); a module's size is its count of lines.  A function that grows past
the limit is split into named steps, an exercise that grows past it moves its generic numerics to solvers/.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

from conftest import parsed, parsed_source

ROOT = Path(__file__).resolve().parents[1]
EXERCISE_MODULE_MAX = 450  # lines of one problems/chN/ module
FUNCTION_MAX = 100  # lines of one function, outside tests/
NOT_CODE = {"tests", "scripts", "docs", "build", "dist", "__pycache__"}


def _sources(root: Path = ROOT) -> list[Path]:
    out = []
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root).parts
        if parts[0] in NOT_CODE or any(p.startswith(".") or p.endswith(".egg-info") for p in parts):
            continue
        out.append(path)
    return out


def function_lengths(source: str, tree: ast.Module | None = None) -> list[tuple[str, int]]:
    """(name, lines) of every function of a module, nested ones and methods included (``tree``: ``source``
    parsed already)."""
    return [(node.name, node.end_lineno - node.lineno + 1)
            for node in ast.walk(ast.parse(source) if tree is None else tree)
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))]


def _is_exercise(rel: str) -> bool:
    return rel.startswith("problems/ch")


def over_limits(root: Path = ROOT) -> tuple[list[str], list[str]]:
    """What exceeds the limits under ``root``: (functions, exercise modules), each "path:name: N lines"."""
    functions, modules = [], []
    for path in _sources(root):
        rel = path.relative_to(root).as_posix()
        source = parsed_source(path)
        lines = source.count("\n")
        if _is_exercise(rel) and lines > EXERCISE_MODULE_MAX:
            modules.append(f"{rel}: {lines} lines")
        for name, length in function_lengths(source, parsed(path)):
            if length > FUNCTION_MAX:
                functions.append(f"{rel}:{name}: {length} lines")
    return functions, modules


def test_the_tree_is_read():
    # the walk finds the code it is meant to hold to the limits, and none of the tests
    rels = {p.relative_to(ROOT).as_posix() for p in _sources()}
    assert {"verification/crosscheck.py", "problems/physics.py", "students/classrun.py"} <= rels
    assert sum(_is_exercise(r) for r in rels) >= 50
    assert not any(r.startswith("tests/") for r in rels)


@functools.lru_cache(maxsize=None)
def _tree_over_limits() -> tuple[list[str], list[str]]:
    """``over_limits()`` of the source tree, read and parsed once for the two tests that judge it."""
    return over_limits()


def test_no_function_over_100_lines_outside_tests():
    functions, _ = _tree_over_limits()
    assert functions == [], "split into named steps:\n" + "\n".join(functions)


def test_no_exercise_module_over_450_lines():
    _, modules = _tree_over_limits()
    assert modules == [], "move generic numerics to solvers/:\n" + "\n".join(modules)


def test_the_limits_are_counted_as_stated(tmp_path):
    # a function of exactly 100 lines (def + 99 body lines) passes, one of 101 fails, nested or a method;
    # an exercise module of 451 lines fails, one of 450 passes, and a module outside problems/chN/ of any size
    def lines(n, indent):
        return "".join(f"{indent}x{i} = {i}\n" for i in range(n))

    src = ("def ok():\n" + lines(99, "    ") + "\n\nclass C:\n    def long(self):\n" + lines(100, " " * 8)
           + "\n\ndef outer():\n    def inner():\n" + lines(100, " " * 8))
    lengths = dict(function_lengths(src))
    assert lengths == {"ok": 100, "long": 101, "outer": 102, "inner": 101}
    (tmp_path / "problems" / "ch4").mkdir(parents=True)
    (tmp_path / "problems" / "ch4" / "ex4_99.py").write_text("x = 1\n" * 451)
    (tmp_path / "problems" / "ch4" / "ex4_98.py").write_text("x = 1\n" * 450)
    (tmp_path / "problems" / "big.py").write_text("x = 1\n" * 2000)
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_long.py").write_text(src)
    (tmp_path / "mod.py").write_text(src)
    functions, modules = over_limits(tmp_path)
    assert modules == ["problems/ch4/ex4_99.py: 451 lines"]
    assert sorted(functions) == ["mod.py:inner: 101 lines", "mod.py:long: 101 lines", "mod.py:outer: 102 lines"]
