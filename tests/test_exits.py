"""Exit statuses, written once (core/exits.py, CONTRACT.md's "Exit status"): an internal error is 3, told
apart from a failed check (1); an interrupt is 130; no command writes a status as a literal."""

from __future__ import annotations

import re
from pathlib import Path

import click
from click.testing import CliRunner

from mech.cli import main as cli_main
from mech.cli.main import cli
from mech.core import exits

ROOT = Path(__file__).resolve().parents[1]


def test_the_statuses_are_the_contracts():
    assert (exits.EXIT_OK, exits.EXIT_DISAGREE, exits.EXIT_USAGE, exits.EXIT_INTERNAL) == (0, 1, 2, 3)
    assert exits.EXIT_INTERRUPTED == 130  # 128 + SIGINT (2)


def test_an_internal_error_exits_3_with_one_line_saying_how_to_report_it(monkeypatch):
    def broken(ex_id):
        raise ZeroDivisionError("a planted defect")

    monkeypatch.setattr(cli_main, "_get", broken)
    r = CliRunner().invoke(cli, ["solve", "4.15"])
    assert r.exit_code == 3
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith("mech: internal error: ZeroDivisionError: a planted defect")
    assert "bug in mech" in lines[0] and "report" in lines[0]
    assert "Traceback" not in r.output


def test_an_abort_exits_130(monkeypatch):
    def aborted(ex_id):
        raise click.Abort()

    monkeypatch.setattr(cli_main, "_get", aborted)
    r = CliRunner().invoke(cli, ["solve", "4.15"])
    assert r.exit_code == 130 and "aborted" in r.stderr


def test_no_status_is_written_as_a_literal():
    literal = re.compile(r"(ctx\.exit|sys\.exit|code\s*=)\s*\(?\s*\d+\b|exit_code\s*=\s*\d+\b")
    found = []
    for path in sorted((ROOT / "cli").rglob("*.py")):
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if literal.search(line.split("#", 1)[0]):
                found.append(f"{path.name}:{i}: {line.strip()}")
    assert found == []
