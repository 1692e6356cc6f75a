"""The floors of DEVELOPING.md hold: import-linter's contracts in pyproject.toml, with no ignored import."""

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

pytest.importorskip("importlinter")


def test_every_contract_is_kept():
    run = subprocess.run([sys.executable, str(ROOT / "scripts" / "lint_layers.py")], capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-2000:]
    assert "0 broken" in run.stdout


def test_no_import_is_ignored_and_every_floor_is_a_contract_layer():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    contracts = config["tool"]["importlinter"]["contracts"]
    assert all("ignore_imports" not in c for c in contracts)
    floors = next(c for c in contracts if c["type"] == "layers" and "mech.cli" in c["layers"])["layers"]
    mapped = set(config["tool"]["setuptools"]["package-dir"]) - {"mech"}
    assert mapped <= set(floors), f"a mapped folder outside the floors: {sorted(mapped - set(floors))}"


def test_the_linter_sees_a_broken_floor(tmp_path, monkeypatch):
    """The check can fail: an upward import planted in a copy of the tree breaks the contract."""
    sys.path.insert(0, str(ROOT / "scripts"))
    try:
        import lint_layers
    finally:
        sys.path.remove(str(ROOT / "scripts"))
    tree = lint_layers.build_tree(tmp_path)
    (tree / "mech" / "core" / "errors.py").write_text("import mech.cli.main\n", encoding="utf-8")
    linter = Path(sys.executable).with_name("lint-imports")
    run = subprocess.run([str(linter), str(ROOT / "pyproject.toml"), "--no-cache"], cwd=tree, capture_output=True,
                         text=True, env={"PYTHONPATH": str(tree), "PATH": ""}, timeout=300)
    assert run.returncode != 0 and "mech.core.errors -> mech.cli.main" in run.stdout, run.stdout[-2000:]


def test_the_judge_importing_a_room_above_it_breaks_a_contract(tmp_path):
    """The verdict's room (mech.verification) imports neither a student's answers nor the studies: an import
    of mech.studies.sweep planted in a copy of the judge breaks the contracts."""
    sys.path.insert(0, str(ROOT / "scripts"))
    try:
        import lint_layers
    finally:
        sys.path.remove(str(ROOT / "scripts"))
    tree = lint_layers.build_tree(tmp_path)
    judge = tree / "mech" / "verification" / "judge.py"
    judge.write_text(judge.read_text("utf-8") + "\nimport mech.studies.sweep\n", encoding="utf-8")
    linter = Path(sys.executable).with_name("lint-imports")
    run = subprocess.run([str(linter), str(ROOT / "pyproject.toml"), "--no-cache"], cwd=tree, capture_output=True,
                         text=True, env={"PYTHONPATH": str(tree), "PATH": ""}, timeout=300)
    assert run.returncode != 0 and "mech.verification.judge -> mech.studies.sweep" in run.stdout, run.stdout[-2000:]
    assert "neither a student's answers nor the studies BROKEN" in run.stdout


def test_no_one_outside_problems_reads_an_exercises_private_parts():
    """The exercise contract is its public methods (``analytic_solver``, ``has_constraints``, ...); no module
    outside problems/, tests included, reads an exercise's private solver, constraint or route attributes."""
    import re

    private = re.compile(r"\._(analytic|numeric|constraints|hamiltonian|batched|motion|scene)\b")
    found = []
    for path in ROOT.rglob("*.py"):
        rel = path.relative_to(ROOT)
        if rel.parts[0] in ("problems", "build") or rel.name == "test_layers.py" or \
                any(p.startswith(".") for p in rel.parts):
            continue
        for n, line in enumerate(path.read_text("utf-8").splitlines(), 1):
            if private.search(line):
                found.append(f"{rel}:{n}: {line.strip()}")
    assert not found, "\n".join(found)
