"""mech grade FILE: a TOML file of answers held against mech; table, JSON, JUnit and exit codes.

Hand values (4.15): sin(theta_c) = (2/3) sin(theta0), omega_c^2 = g sin(theta0) / l.
theta0 = 60 deg: theta_c = asin(1/sqrt 3) = 35.2644 deg, omega_c = sqrt(9.81 * 0.866025) = 2.91474 rad/s;
with l = 2 m: omega_c = 2.91474 / sqrt(2) = 2.06102 rad/s, so 4.12 is a factor-2 slip.
theta0 = 90 deg: theta_c = asin(2/3) = 0.729728 rad.
"""

import json
import xml.etree.ElementTree as ET

import pytest
from click.testing import CliRunner

from mech.cli.main import cli

GOOD = '''
# a student's answers
[[answer]]
exercise = "4.15"
params = { theta0 = "60deg" }
expect = { theta_c = "35.26deg", omega_c = "2.91 rad/s" }

[[answer]]
exercise = "4.15"
params = { theta0 = "60deg", l = "2 m" }
expect = { omega_c = "4.12" }

[[answer]]
exercise = "4.15"
expect = { theta_c = 0.7297 }
rtol = 1e-3
'''


def run(*args):
    result = CliRunner().invoke(cli, list(args))
    return result.exit_code, result.stdout, result.stderr


@pytest.fixture
def answers(tmp_path):
    path = tmp_path / "answers.toml"
    path.write_text(GOOD, encoding="utf-8")
    return path


def test_table_and_summary(answers):
    code, out, err = run("grade", str(answers))
    assert code == 1, err
    assert "right to 4 digits" in out and "right to 3 digits" in out
    assert "off by a factor 2" in out
    assert "3 of 4 answers right, 1 wrong (3 entries)" in out


def test_all_right_exits_0(tmp_path):
    path = tmp_path / "a.toml"
    path.write_text('[[answer]]\nexercise = "4.15"\nparams = { theta0 = "60deg" }\n'
                    'expect = { theta_c = "35.26deg" }\n', encoding="utf-8")
    code, out, _ = run("grade", str(path))
    assert code == 0 and "1 of 1 answers right" in out


def test_json(answers):
    code, out, _ = run("grade", str(answers), "--json")
    assert code == 1
    d = json.loads(out)
    assert d["ok"] is False and d["passed"] == 3 and d["failed"] == 1
    first, second, third = d["entries"]
    assert first["exercise"] == "4.15" and first["ok"] is True
    assert [q["expected"]["match"] for q in first["quantities"]] == [True, True]
    assert second["ok"] is False
    omega = second["quantities"][1]
    assert "expected" not in second["quantities"][0]
    assert omega["expected"]["hint"] == "off by a factor 2"
    assert omega["expected"]["reference_value"] == pytest.approx(2.06102, rel=1e-5)
    assert third["params"]["theta0"] == pytest.approx(1.5707963267948966)  # the default
    assert third["quantities"][0]["expected"]["match"] is True  # 0.7297 within 1e-3 of 0.729728


def test_junit_one_case_per_expected_value(answers, tmp_path):
    junit = tmp_path / "grade.xml"
    code, _, _ = run("grade", str(answers), "--junit", str(junit))
    assert code == 1
    root = ET.parse(junit).getroot()
    cases = root.findall(".//testcase")
    assert len(cases) == 4 and root.get("tests") == "4" and root.get("failures") == "1"
    assert {c.get("classname") for c in cases} == {"mech.ex4_15"}
    failed = [c for c in cases if c.find("failure") is not None]
    assert len(failed) == 1 and "omega_c" in failed[0].get("name")
    assert "off by a factor 2" in failed[0].find("failure").get("message")


HEAD = '[[answer]]\nexercise = "4.15"\n'


@pytest.mark.parametrize("text, words", [
    (HEAD + 'expect = { theta_c = "35.26deg" }\n\n[[answer]]\nexercise = "4.15"\nexpect = { theta_x = "1" }\n',
     ["answer 2 (line 5)", "expect.theta_x", "not an output"]),
    (HEAD + 'expect = { theta_c = "35.26 m" }\n', ["answer 1 (line 1)", "expect.theta_c", "a length"]),
    ('[[answer]]\nexercise = "4.99"\nexpect = { theta_c = "1" }\n', ["exercise", "4.99"]),
    (HEAD + 'params = { theta1 = 1 }\nexpect = { theta_c = "1" }\n', ["params.theta1", "not a parameter"]),
    (HEAD + 'params = { theta0 = "100deg" }\nexpect = { theta_c = "1" }\n', ["params.theta0", "out of range"]),
    (HEAD + 'params = { l = "2 s" }\nexpect = { theta_c = "1" }\n', ["params.l", "a time"]),
    (HEAD + 'expected = { theta_c = "1" }\n', ["expected", "unknown field"]),
    (HEAD, ["expect", "missing"]),
    (HEAD + 'expect = { theta_c = true }\n', ["expect.theta_c"]),
    (HEAD + 'rtol = 5\nexpect = { theta_c = 1 }\n', ["rtol", "out of range"]),
    ('[[answer]\nexercise = "4.15"\n', ["malformed TOML", "line 1"]),
    ('x = 1\n', ["'x'", "unknown top-level key"]),
    ('', ["no [[answer]] tables"]),
])
def test_a_bad_file_exits_2_with_a_line_per_problem_naming_it(tmp_path, text, words):
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = run("grade", str(path), "--strict")  # without: tests/test_grade_invalid.py
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert lines and "Traceback" not in err
    assert all(line.startswith("mech: error: ") and str(path) in line for line in lines)
    assert any(all(w in line for w in words) for line in lines), lines


def test_every_problem_of_a_file_at_once_each_with_its_entry_and_line(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('[[answer]]\nexercise = "4.15"\nparams = { nosuch = 1 }\nexpect = { theta_c = "2 kg" }\n\n'
                    '[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "35.26deg" }\n\n'
                    '[[answer]]\nexercise = "9.99"\ncolour = "red"\nexpect = { x = 1 }\n', encoding="utf-8")
    code, out, err = run("grade", str(path), "--strict")
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    # entry 1: two problems (line 1); entry 2 is good; entry 3: two problems (line 10)
    assert len(lines) == 4, lines
    assert "answer 1 (line 1): params.nosuch" in lines[0] and "answer 1 (line 1): expect.theta_c" in lines[1]
    assert "answer 3 (line 10)" in lines[2] and "answer 3 (line 10)" in lines[3]
    assert any("colour: unknown field" in ln for ln in lines[2:]) and any("9.99" in ln for ln in lines[2:])


def test_a_missing_file_exits_2(tmp_path):
    code, out, err = run("grade", str(tmp_path / "nope.toml"))
    assert code == 2 and out == "" and "cannot read" in err


def test_grade_is_listed_in_help():
    code, out, _ = run("--help")
    assert code == 0 and "grade" in out


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_VALUES = ['"4.15"', '4.15', '"4.99"', '[1, 2]', '{ a = 1 }', '"60deg"', 'true', '"abc"', 'inf', 'nan', '-0.0',
           '"35.26deg"', '0.7297', '"2 m"', '""', '1e-3', '"1e999"']
_NAMES = ["theta0", "theta_c", "omega_c", "l", "x", "g", "theta-c"]


@settings(max_examples=120, deadline=None)
@given(exercise=st.sampled_from(_VALUES), pname=st.sampled_from(_NAMES), pval=st.sampled_from(_VALUES),
       ename=st.sampled_from(_NAMES), evalue=st.sampled_from(_VALUES),
       extra=st.sampled_from(["", "rtol = 1e-3", "rtol = 0", "rtol = \"x\"", "foo = 1", "[other]"]))
def test_fuzz_grading_files_never_crash(tmp_path_factory, exercise, pname, pval, ename, evalue, extra):
    path = tmp_path_factory.mktemp("fuzz") / "f.toml"
    path.write_text(f"[[answer]]\nexercise = {exercise}\nparams = {{ {pname} = {pval} }}\n"
                    f"expect = {{ {ename} = {evalue} }}\n{extra}\n", encoding="utf-8")
    result = CliRunner().invoke(cli, ["grade", str(path), "--json"])
    assert result.exit_code in (0, 1, 2), result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr
    if result.exit_code == 2:
        lines = result.stderr.strip().splitlines()
        assert result.stdout == "" and lines and all(ln.startswith("mech: error: ") for ln in lines)
    else:
        json.loads(result.stdout)
