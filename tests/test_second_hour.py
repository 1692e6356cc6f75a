"""Issue 27, the second hour: what a student and an instructor met after the first answer.

Each test names its item; expected values are worked out by hand in the comments."""

import json
import re

import pytest
from click.testing import CliRunner

from mech.cli.main import cli


def run(*args, env=None):
    result = CliRunner().invoke(cli, list(args), env=env)
    return result.exit_code, result.stdout, result.stderr


# -- item 14: show states every joint limit a solve enforces ---------------------------------------------

def test_every_exercise_with_a_joint_check_states_its_limits(exercises):
    for ex in exercises.values():
        assert bool(ex._constraints) == bool(ex.joint_limits), ex.id


def test_show_states_433s_offset_limit_and_solve_keeps_to_it():
    code, out, _ = run("show", "4.33")
    assert code == 0 and "|x0|/R <= 0.1" in out
    # R = 6.778e6 m by default: 0.1 R = 677.8 km; just inside solves, just outside is refused
    assert run("solve", "4.33", "--x0", "677 km", "--method", "analytic")[0] == 0
    assert run("solve", "4.33", "--x0", "679 km", "--method", "analytic")[0] == 2


def test_show_json_carries_the_limits_a_script_can_read():
    code, out, _ = run("show", "5.10", "--json")
    data = json.loads(out)
    assert "|omega - omega0| <= 0.2 omega0" in data["constraints"]
    code, out, _ = run("show", "4.15", "--json")
    assert isinstance(json.loads(out)["constraints"], list)
    code, out, _ = run("show", "4.1", "--json")
    assert json.loads(out)["constraints"] == []


# -- item 14: mech list says what differs, not "analytic, numeric" on every row --------------------------

def test_list_shows_whether_the_analytic_value_is_exact(exercises):
    code, out, _ = run("list")
    assert code == 0 and "analytic, numeric" not in out
    rows = {line.split()[0].rstrip("†+"): line.split()[-1] for line in out.splitlines()
            if re.match(r" \d\.\d+", line)}
    for ex in exercises.values():
        leading = any(o.theory != "exact" for o in ex.outputs)
        assert rows[ex.id] == ("leading-order" if leading else "exact"), ex.id
    code, out, _ = run("list", "--json")
    by_id = {e["id"]: e for e in json.loads(out)}
    assert by_id["4.24"]["theory"] == "leading-order" and by_id["4.15"]["theory"] == "exact"
