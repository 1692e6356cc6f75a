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


def test_the_readme_counts_the_registered_exercises():
    """"All N exercises" in the README is the registry's count: a new exercise changes it (DEVELOPING.md's
    recipe, step 6), as tests/test_prose.py holds the ranges it names."""
    said = re.findall(r"All (\d+) exercises", (ROOT / "README.md").read_text("utf-8"))
    assert said and all(int(n) == len(registry.index()) for n in said), said


def test_ci_runs_the_readme_test_command():
    ci = (ROOT / ".ci" / "run").read_text("utf-8").strip().splitlines()[-1]
    assert ci in (ROOT / "README.md").read_text("utf-8")


def test_the_readme_is_for_users_at_most_15_kb():
    """Details live in docs/; the README keeps what a user needs first (issue 25 item 8)."""
    assert (ROOT / "README.md").stat().st_size <= 15 * 1024


def test_every_local_link_in_the_readme_and_docs_exists():
    """Every relative link (docs pages, pictures, DEVELOPING.md) of README.md and docs/*.md names a file
    or folder that exists; an anchor names a heading of that page."""
    import re

    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    seen_docs = set()
    for page in pages:
        text = page.read_text("utf-8")
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"[a-z]+:", target):
                continue  # a web address
            path, _, anchor = target.partition("#")
            dest = (page.parent / path).resolve() if path else page
            assert dest.exists(), f"{page.name}: {target}"
            if dest.parent == ROOT / "docs" and dest.suffix == ".md":
                seen_docs.add(dest.name)
            if anchor and dest.suffix == ".md":
                headings = re.findall(r"^#+\s+(.+)$", dest.read_text("utf-8"), re.M)
                slugs = {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-") for h in headings}
                assert anchor in slugs, f"{page.name}: {target}"
    # every page of docs/ is reachable from the README or from another page
    assert {p.name for p in (ROOT / "docs").glob("*.md")} <= seen_docs


def test_the_readmes_console_examples_print_what_the_readme_shows():
    """Every `$ mech ...` line of a console block is run; its output must be the lines that follow it in the
    README, apart from the cost line (times depend on the machine), and `$ echo $?` its exit status."""
    import re
    import shlex

    from click.testing import CliRunner

    from mech.cli.main import cli

    text = (ROOT / "README.md").read_text("utf-8")
    blocks = re.findall(r"```console\n(.*?)```", text, re.S)
    ran = 0
    for block in blocks:
        for chunk in re.split(r"^\$ ", block, flags=re.M)[1:]:
            command, _, shown = chunk.partition("\n")
            if command.startswith("echo $?"):
                assert int(shown.strip()) == last_code, command
                continue
            assert command.startswith("mech "), command
            result = CliRunner().invoke(cli, shlex.split(command)[1:])
            last_code = result.exit_code

            def keep(lines):
                return [line.rstrip() for line in lines.splitlines() if not line.startswith("cost:")]

            assert keep(result.output) == keep(shown), command
            ran += 1
    assert ran >= 2
