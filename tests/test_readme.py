"""The README's exercise table and test command stay in step with the project."""

from pathlib import Path

from mech.problems import registry

ROOT = Path(__file__).resolve().parents[1]


def test_every_registered_exercise_is_in_the_readme_table():
    text = (ROOT / "README.md").read_text("utf-8")
    for ex_id in registry.all_exercises():
        assert f"| {ex_id} |" in text, ex_id


def test_ci_runs_the_readme_test_command():
    ci = (ROOT / ".ci" / "run").read_text("utf-8").strip().splitlines()[-1]
    assert ci in (ROOT / "README.md").read_text("utf-8")
