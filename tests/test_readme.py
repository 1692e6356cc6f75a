"""The README's exercise table and test command stay in step with the project."""

import re
from pathlib import Path

from mech.problems import registry

ROOT = Path(__file__).resolve().parents[1]


def test_every_exercise_in_the_readme_table_is_registered_under_its_title():
    """The table is not held to list every exercise (``mech list`` does; a new exercise touches only its
    module, its catalogue file and its test), but a row it has names a registered exercise by its title."""
    titles = {e.id: e.title for e in registry.index()}
    section = (ROOT / "README.md").read_text("utf-8").partition("## Exercises")[2].partition("\n## ")[0]
    rows = [line.split("|") for line in section.splitlines() if re.match(r"\| \d+\.\d+ \|", line)]
    for row in rows:
        ex_id, title = row[1].strip(), row[2].strip().rstrip("†").strip()
        assert titles.get(ex_id) == title, ex_id


def test_ci_runs_the_readme_test_command():
    ci = (ROOT / ".ci" / "run").read_text("utf-8").strip().splitlines()[-1]
    assert ci in (ROOT / "README.md").read_text("utf-8")
