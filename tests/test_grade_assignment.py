"""Issue 39 item 1: ``mech grade ANSWERS --assignment DIR`` holds every entry to the assignment: its
parameters, digits, range and outputs.  A file that moves any of them is invalid in those cells, every one.

The key is written here by hand, so the values are known without mech (4.15: sin theta_c = (2/3) sin
theta0, omega_c = (g sin theta0 / l)^(1/2)):

* ann: theta0 = 30 deg, l = 2 m, g = 9.81: theta_c = asin(1/3) = 19.4712 deg = 0.339837 rad,
  omega_c = sqrt(9.81 * 0.5 / 2) = 1.56604 rad/s;
* bob: theta0 = 60 deg, l = 1 m, g = 9.81: theta_c = 35.2644 deg, omega_c = 2.91474 rad/s;
* the textbook's defaults (theta0 = 90 deg, l = 1 m): theta_c = asin(2/3) = 41.8103 deg, omega_c = 3.13209.
"""

import csv
import io
import json

import pytest
from click.testing import CliRunner

from mech.cli.main import cli

ANN = 'params = { theta0 = "30deg", l = "2 m", g = "9.81 m/s^2" }'
ANN_RIGHT = 'expect = { theta_c = "19.47deg", omega_c = "1.566 rad/s" }'
# right where theta0 < 0.8 rad (abs(x) + x = 0 for x < 0: the factor is exactly 1), wrong above (45.8 deg)
CHEAT = "asin(2/3*sin(theta0))*(1 + abs(theta0 - 0.8) + theta0 - 0.8)"


def run(*args):
    r = CliRunner().invoke(cli, [str(a) for a in args])
    return r.exit_code, r.stdout, r.stderr


def key(tmp_path, over=None, digits=3):
    folder = tmp_path / "assignment"
    folder.mkdir(exist_ok=True)
    k = {"mech": "0.1.0", "seed": 1, "variants": [
        {"student": "ann", "exercise": "4.15", "params": {"theta0": "30deg", "l": "2 m", "g": "9.81 m/s^2"},
         "outputs": {"theta_c": {}, "omega_c": {}}},
        {"student": "bob", "exercise": "4.15", "params": {"theta0": "60deg", "l": "1 m", "g": "9.81 m/s^2"},
         "outputs": {"theta_c": {}, "omega_c": {}}}]}
    if digits is not None:
        k["digits"] = digits
    if over is not None:
        k["over"] = over
    (folder / "key.json").write_text(json.dumps(k))
    return folder


def grade(tmp_path, text, *extra, over=None):
    path = tmp_path / "answers.toml"
    path.write_text(text)
    code, out, err = run("grade", path, "--assignment", key(tmp_path, over), "--json", *extra)
    assert code in (0, 1), err
    return code, json.loads(out)


def entry(student, body):
    return f'[[answer]]\nstudent = "{student}"\nexercise = "4.15"\n{body}\n\n'


def test_a_file_true_to_the_assignment_grades_and_a_missing_student_is_unanswered(tmp_path):
    code, d = grade(tmp_path, entry("ann", f"{ANN}\n{ANN_RIGHT}"))
    ann, bob = d["entries"]
    assert [c["state"] for c in ann["cells"]] == ["right", "right"]
    assert bob["student"] == "bob" and [c["state"] for c in bob["cells"]] == ["unanswered", "unanswered"]
    assert (d["passed"], d["unanswered"], d["points"], d["max"], d["review"]) == (2, 2, 2, 4, 0)
    assert code == 0  # unanswered cells do not fail the file; they score 0 of the max


def test_the_same_parameters_written_otherwise_are_the_assignments(tmp_path):
    """Compared in SI, exactly: "2.0 m" is "2 m"."""
    code, d = grade(tmp_path, entry("ann", 'params = { theta0 = "30 deg", l = "2.0 m", g = "9.81 m/s^2" }\n'
                                    + ANN_RIGHT))
    assert [c["state"] for c in d["entries"][0]["cells"]] == ["right", "right"]


@pytest.mark.parametrize("body, field", [
    # params changed: the textbook's right answers at theta0 = 90 deg
    ('params = { theta0 = "90deg", l = "2 m", g = "9.81 m/s^2" }\n'
     'expect = { theta_c = "41.81deg", omega_c = "2.215 rad/s" }', "params.theta0"),
    ('params = { theta0 = "30deg", l = "2.0001 m", g = "9.81 m/s^2" }\n' + ANN_RIGHT, "params.l"),
    # params deleted: the textbook's default answers must not pass for a variant
    ('expect = { theta_c = "41.81deg", omega_c = "3.132 rad/s" }', "params: missing theta0"),
    ('params = { theta0 = "30deg" }\n' + ANN_RIGHT, "params: missing l"),
    # rtol = 0.99 would take 0.3 for 0.3398
    (f'{ANN}\nrtol = 0.99\nexpect = {{ theta_c = "0.3", omega_c = "1 rad/s" }}', "rtol"),
    # a range narrowed to where the cheat holds
    (f'{ANN}\nover = {{ theta0 = "10deg:40deg" }}\npoints = 1\n'
     f'expect = {{ theta_c = "{CHEAT}", omega_c = "1.566 rad/s" }}', "over"),
    (f'{ANN}\npoints = 1\nexpect = {{ theta_c = "asin(2/3*sin(theta0))", omega_c = "1.566 rad/s" }}', "points"),
    (f'{ANN}\nseed = 7\nexpect = {{ theta_c = "asin(2/3*sin(theta0))", omega_c = "1.566 rad/s" }}', "seed"),
])
def test_a_tampered_entry_is_invalid_in_every_cell(tmp_path, body, field):
    code, d = grade(tmp_path, entry("ann", body) + entry("bob", 'params = { theta0 = "60deg", l = "1 m", '
                                                           'g = "9.81 m/s^2" }\nexpect = { theta_c = "35.26deg" }'))
    ann, bob = d["entries"]
    assert code == 1 and ann["invalid"].startswith(f"line 1: {field}"), ann["invalid"]
    assert [c["state"] for c in ann["cells"]] == ["invalid", "invalid"]
    assert all("the assignment fixes" in c["reason"] for c in ann["cells"])
    assert [c["state"] for c in bob["cells"]] == ["right", "unanswered"]  # bob's untouched
    assert (d["passed"], d["invalid"], d["unanswered"], d["max"], d["review"]) == (1, 2, 1, 4, 2)


def test_without_the_assignment_the_same_cheats_pass(tmp_path):
    """The control: read as a student's own file, the narrowed range and rtol are the file's to set."""
    path = tmp_path / "a.toml"
    path.write_text(entry("ann", f'{ANN}\nrtol = 0.99\nexpect = {{ theta_c = "0.3" }}')
                    + entry("ann", f'{ANN}\nover = {{ theta0 = "10deg:40deg" }}\npoints = 1\n'
                                   f'expect = {{ theta_c = "{CHEAT}" }}')
                    + entry("ann", 'expect = { theta_c = "41.81deg" }')
                    + entry("ann", f'{ANN}\nexpect = {{ theta_c = "{CHEAT}" }}'))
    code, out, _ = run("grade", path, "--json")
    d = json.loads(out)
    assert [e["cells"][0]["state"] for e in d["entries"]] == ["right", "right", "right", "wrong"]


@pytest.mark.parametrize("text, field", [
    ('[[answer]]\nstudent = "carl"\nexercise = "4.15"\nexpect = { theta_c = "41.81deg" }\n', "exercise: 4.15 is not in"),
    (f'[[answer]]\nstudent = "ann"\nexercise = "4.10"\nexpect = {{ Omega = "1 rad/s" }}\n', "exercise: 4.10 is not in"),
    ('[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "41.81deg" }\n', "student: missing"),
])
def test_an_entry_the_assignment_does_not_hold_is_invalid(tmp_path, text, field):
    code, d = grade(tmp_path, text)
    first = d["entries"][0]
    assert code == 1 and first["invalid"].startswith(f"line 1: {field}"), first["invalid"]
    assert [c["state"] for c in first["cells"]] == ["invalid"]
    # ann and bob (4.15) have no entry: unanswered, two outputs each
    assert d["unanswered"] == 4 and d["max"] == 5


def test_an_assigned_output_left_out_is_unanswered_and_counts_in_max(tmp_path):
    code, d = grade(tmp_path, entry("ann", f'{ANN}\nexpect = {{ theta_c = "19.47deg" }}'))
    ann = d["entries"][0]
    assert [(c["output"], c["state"]) for c in ann["cells"]] == [("theta_c", "right"), ("omega_c", "unanswered")]
    assert ann["unanswered"] == ["omega_c"] and d["max"] == 4


def test_a_csv_against_the_assignment(tmp_path):
    """The template's shape: a student column, ID:param columns (may be left out), empty ID:output ones."""
    path = tmp_path / "answers.csv"
    path.write_text("student,4.15:theta_c,4.15:omega_c,4.15:theta0\n"
                    "ann,19.47deg,1.566 rad/s,\n"           # its parameters: the assignment's
                    "bob,41.81deg,3.132 rad/s,90deg\n")      # the textbook's: refused
    book = tmp_path / "book.csv"
    code, out, err = run("grade", path, "--assignment", key(tmp_path), "--json", "--csv", book)
    d = json.loads(out)
    ann, bob = d["entries"]
    assert code == 1 and [c["state"] for c in ann["cells"]] == ["right", "right"]
    assert bob["invalid"].startswith("line 3: params.theta0: the assignment fixes the parameters")
    rows = {r["student"]: r for r in csv.DictReader(io.StringIO(book.read_text()))}
    assert rows["bob"] == {"student": "bob", "points": "0", "max": "2", "review": "2", "4.15:theta_c": "invalid",
                           "4.15:omega_c": "invalid"}


def test_the_assignments_range_narrows_the_formulas(tmp_path):
    """over = {theta0: 10deg:40deg} in the key (the instructor's): the formula is meant to hold there, and
    does; a fixed value ("9.81 m/s^2") holds g at that value."""
    code, d = grade(tmp_path, entry("ann", f'{ANN}\nexpect = {{ theta_c = "{CHEAT}" }}'),
                    over={"4.15": {"theta0": "10deg:40deg", "g": "9.81 m/s^2"}})
    cell = d["entries"][0]["quantities"][0]["expected"]
    assert cell["state"] == "right" and cell["points"]["worst"]["params"]["g"] == 9.81
    code, d = grade(tmp_path, entry("ann", f'{ANN}\nexpect = {{ theta_c = "{CHEAT}" }}'))
    assert d["entries"][0]["cells"][0]["state"] == "wrong"


@pytest.mark.parametrize("digits, expected", [(None, 3), (4, 4)])
def test_the_assignments_digits_are_the_digits_rules_floor(tmp_path, monkeypatch, digits, expected):
    from mech.students import answers_files

    seen = []
    real = answers_files.parse_expectation

    def spy(*args, min_digits=None, **kw):
        seen.append(min_digits)
        return real(*args, min_digits=min_digits, **kw)

    monkeypatch.setattr(answers_files, "parse_expectation", spy)
    path = tmp_path / "a.toml"
    path.write_text(entry("ann", f"{ANN}\n{ANN_RIGHT}"))
    folder = key(tmp_path, digits=digits)
    assert run("grade", path, "--assignment", folder)[0] == 0
    assert seen == [expected, expected]
    seen.clear()
    assert run("grade", path)[0] == 0 and seen == [2, 2]  # --min-digits' default
    seen.clear()
    # to 5 digits 19.47deg is 19.470 against asin(1/3) = 19.4712 deg: wrong, by the floor
    assert run("grade", path, "--min-digits", "5")[0] == 1 and seen == [5, 5]
    code, out, err = run("grade", path, "--assignment", folder, "--min-digits", "2")
    assert code == 2 and "--min-digits" in err and "Traceback" not in err


@pytest.mark.parametrize("text, words", [
    ("not json", "malformed JSON"),
    ('{"variants": [{"student": "ann", "exercise": "9.99", "params": {}, "outputs": {}}]}', "9.99"),
    ('{"variants": [{"student": "ann", "exercise": "4.15", "params": {"theta0": "100deg"}, "outputs": {}}]}',
     "params.theta0"),
    ('{"digits": 0, "variants": []}', "digits"),
])
def test_a_bad_key_is_exit_2_in_one_line(tmp_path, text, words):
    folder = tmp_path / "k"
    folder.mkdir()
    (folder / "key.json").write_text(text)
    path = tmp_path / "a.toml"
    path.write_text(entry("ann", ANN_RIGHT))
    code, out, err = run("grade", path, "--assignment", folder)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and words in err, err
    assert "Traceback" not in err


def test_the_api_grades_against_the_assignment(tmp_path):
    import mech

    path = tmp_path / "a.toml"
    path.write_text(entry("ann", f"{ANN}\n{ANN_RIGHT}") + entry("bob", 'expect = { theta_c = "41.81deg" }'))
    report = mech.grade(path, assignment=key(tmp_path))
    assert (report.passed, report.invalid, report.unanswered, report.ok) == (2, 2, 0, False)
    assert report.to_dict()["max"] == 4 and report.invalid_entries == 1
    with pytest.raises(mech.BadInput, match="min_digits"):
        mech.grade(path, min_digits=0)


def test_strict_refuses_a_tampered_file_before_grading(tmp_path):
    path = tmp_path / "a.toml"
    path.write_text(entry("ann", f"{ANN}\nrtol = 0.5\n{ANN_RIGHT}"))
    code, out, err = run("grade", path, "--assignment", key(tmp_path), "--strict")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "answer 1 (line 1): rtol: the assignment fixes the tolerance" in err


def test_the_template_mech_assign_writes_grades_against_its_folder(tmp_path):
    """mech assign's own template, filled with the key's values (mech's, so right by construction) but for
    one student whose params table was deleted: right, and invalid there."""
    import tomllib

    folder = tmp_path / "hw"
    code, _, err = run("assign", "4.15", "--n", "3", "--seed", "5", "--out", folder)
    assert code == 0, err
    k = json.loads((folder / "key.json").read_text())
    values = {v["student"]: v["outputs"] for v in k["variants"]}
    parts = []
    for a in tomllib.loads((folder / "answers.toml").read_text())["answer"]:
        expect = ", ".join(f'{o} = "{values[a["student"]][o]["value"]!r}"' for o in a["expect"])
        params = "" if a["student"] == "s2" else "params = { " + ", ".join(
            f"{p} = {json.dumps(t)}" for p, t in a["params"].items()) + " }\n"
        parts.append(f'[[answer]]\nstudent = "{a["student"]}"\nexercise = "4.15"\n{params}expect = {{ {expect} }}\n')
    path = tmp_path / "filled.toml"
    path.write_text("\n".join(parts))
    code, out, err = run("grade", path, "--assignment", folder, "--json")
    d = json.loads(out)
    states = {e["student"]: [c["state"] for c in e["cells"]] for e in d["entries"]}
    assert states == {"s1": ["right", "right"], "s2": ["invalid", "invalid"], "s3": ["right", "right"]}
    assert code == 1 and (d["points"], d["max"], d["review"]) == (4, 6, 2)


def test_a_name_the_template_neutralised_reads_back(tmp_path):
    """A template cell written "'=eve" (neutralised for a spreadsheet) is the student "=eve" of the key."""
    folder = tmp_path / "k"
    folder.mkdir()
    (folder / "key.json").write_text(json.dumps({"variants": [
        {"student": "=eve", "exercise": "4.15", "params": {"theta0": "60deg"}, "outputs": {}}]}))
    path = tmp_path / "a.csv"
    path.write_text("student,4.15:theta0,4.15:theta_c,4.15:omega_c\n'=eve,60deg,35.26deg,\n")
    code, out, err = run("grade", path, "--assignment", folder, "--json")
    d = json.loads(out)
    assert code == 0 and [e["student"] for e in d["entries"]] == ["=eve"]
    assert [c["state"] for c in d["entries"][0]["cells"]] == ["right", "unanswered"]
