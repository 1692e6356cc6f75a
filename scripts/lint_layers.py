"""Check the floors: run import-linter's contracts (pyproject.toml) on mech laid out by import name.

pyproject maps the folders ``api/``, ``cli/``, ``core/`` ... into one package ``mech`` (``package-dir``),
which tools that walk folders cannot follow: import-linter would find ``mech`` in ``api/`` and nothing
below it.  This copies the sources into a temporary tree shaped like the import names (``mech/cli/...``)
and runs ``lint-imports`` there.  Exit status is lint-imports' own: 0 when every contract is kept.

    python scripts/lint_layers.py
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def build_tree(dest: Path) -> Path:
    """Copy every mapped package's ``.py`` files to ``dest`` under its import path; returns ``dest``."""
    setup = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    mapped = setup["package-dir"]
    for package in setup["packages"]:
        parent = max((name for name in mapped if package == name or package.startswith(name + ".")), key=len)
        source = ROOT / mapped[parent] / Path(*package.split(".")[len(parent.split(".")):])
        target = dest / Path(*package.split("."))
        target.mkdir(parents=True, exist_ok=True)
        for file in source.glob("*.py"):
            shutil.copy2(file, target / file.name)
    return dest


def main() -> int:
    linter = Path(sys.executable).with_name("lint-imports")
    command = [str(linter)] if linter.exists() else [shutil.which("lint-imports") or "lint-imports"]
    with tempfile.TemporaryDirectory(prefix="mech-layers-") as tmp:
        tree = build_tree(Path(tmp))
        env = dict(os.environ, PYTHONPATH=str(tree))
        return subprocess.call([*command, str(ROOT / "pyproject.toml"), "--no-cache"], cwd=tree, env=env)


if __name__ == "__main__":
    sys.exit(main())
