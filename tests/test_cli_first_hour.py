"""Issue 18, the first hour of a new user on the command line: each slip a user met, through CliRunner."""

import json
import re

import pytest
from click.testing import CliRunner

from mech.cli.main import cli


def run(*args, env=None):
    result = CliRunner().invoke(cli, list(args), env=env)
    return result.exit_code, result.stdout, result.stderr


def one_line_exit_2(*args):
    code, out, err = run(*args)
    assert code == 2, (code, out, err)
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


# -- item 2: two numbers side by side are not a product ---------------------------------------------

@pytest.mark.parametrize("name, text", [("l", "1.2.3"), ("l", "1.5.5cm"), ("l", "2 3"), ("l", "15cm 2"),
                                        ("theta0", "1.2.3")])
def test_two_numbers_side_by_side_exit_2_naming_the_parameter(name, text):
    line = one_line_exit_2("solve", "4.15", f"--{name}", text)
    assert line.startswith(f"mech: error: {name}: ") and text in line


# -- item 6: an out-of-range value is echoed as typed, the range in the display unit ------------------

def test_out_of_range_echoes_what_was_typed_and_the_display_range():
    line = one_line_exit_2("solve", "4.15", "--theta0", "100deg")
    assert "theta0: 100deg is out of range" in line
    assert "allowed (0, 90] deg" in line
    assert "1.74533" not in line  # the SI value 100 deg = 1.74533 rad is not what the user wrote


def test_out_of_range_plain_number_is_shown_in_the_display_unit_too():
    # 2 rad = 114.592 deg (2 * 180 / pi = 114.5916)
    line = one_line_exit_2("solve", "4.15", "-p", "theta0=2")
    assert "theta0: 2 (= 114.592 deg) is out of range" in line


# -- item 9: a parameter given twice ---------------------------------------------------------------

def test_given_twice_says_so_without_the_range():
    line = one_line_exit_2("solve", "4.15", "--l", "1", "-p", "l=2")
    assert "l: given more than once" in line and "allowed" not in line and "inf" not in line
