"""Issue 32 item 3: the gradebook out (``--csv FILE``) and answers in from a spreadsheet (``grade x.csv``).

Hand values (4.15): theta0 = 60 deg gives theta_c = asin(1/sqrt 3) = 35.2644 deg and omega_c =
sqrt(9.81 sin 60deg) = 2.91474 rad/s (l = 1 m); at the default theta0 = 90 deg theta_c = asin(2/3) = 41.81 deg.
"""

import csv
import io
import json
import tomllib

import pytest
from click.testing import CliRunner

from mech.cli.main import cli


def run(*args):
    r = CliRunner().invoke(cli, [str(a) for a in args])
    return r.exit_code, r.stdout, r.stderr


@pytest.fixture(scope="module")
def assignment(tmp_path_factory):
    root = tmp_path_factory.mktemp("csv")
    code, _, err = run("assign", "4.15", "4.10", "--n", "6", "--seed", "5", "--out", root)
    assert code == 0, err
    return root


def _answers(assignment):
    """What each student answers: right values, doubled ones, blanks, a formula, a typo (by student)."""
    key = json.loads((assignment / "key.json").read_text())
    out = {}
    for v in key["variants"]:
        s, ex = v["student"], v["exercise"]
        k = int(s[1:])
        for name, rec in v["outputs"].items():
            value = rec["value"] * (2 if k % 3 == 0 else 1)
            text = repr(value)
            if k == 2 and name == "l_ef":
                text = ""  # left blank
            if k == 4 and ex == "4.15" and name == "theta_c":
                text = "asin(2/3*sin(theta0))"
            if k == 5 and ex == "4.10" and name == "Omega":
                text = "sqrt(M*g*l/(I+M*l^2)"  # a typo: that entry is invalid
            out[(s, ex, name)] = text
    return key, out


def _as_toml(assignment, answers, path):
    template = tomllib.loads((assignment / "answers.toml").read_text())
    parts = []
    for a in template["answer"]:
        params = ", ".join(f"{k} = {json.dumps(v)}" for k, v in a["params"].items())
        expect = ", ".join(f"{k} = {json.dumps(answers[(a['student'], a['exercise'], k)])}" for k in a["expect"])
        parts.append(f'[[answer]]\nstudent = "{a["student"]}"\nexercise = "{a["exercise"]}"\n'
                     f"params = {{ {params} }}\nexpect = {{ {expect} }}\n")
    path.write_text("\n".join(parts))
    return path


def _as_csv(key, answers, path, with_params=False):
    cols = [f"{v['exercise']}:{n}" for v in key["variants"][:2] for n in v["outputs"]]
    if with_params:
        cols += [f"{v['exercise']}:{p}" for v in key["variants"][:2] for p in v["params"]]
    params = {(v["student"], v["exercise"]): v["params"] for v in key["variants"]}
    students = sorted({s for s, _, _ in answers}, key=lambda s: int(s[1:]))
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["student"] + cols)
    for s in students:
        row = [s]
        for c in cols:
            ex, name = c.split(":")
            row.append(answers[(s, ex, name)] if (s, ex, name) in answers else params[(s, ex)][name])
        w.writerow(row)
    path.write_text(buf.getvalue())
    return path


def _verdicts(d):
    return {(e["student"], e["exercise"]): (e["invalid"] is not None,
                                            sorted((q["name"], q["expected"]["match"], q["expected"]["hint"])
                                                   for q in e["quantities"] if "expected" in q),
                                            e.get("unanswered", []))
            for e in d["entries"]}


@pytest.mark.parametrize("with_params", [False, True])
def test_the_same_answers_in_csv_and_toml_grade_the_same(assignment, tmp_path, with_params):
    key, answers = _answers(assignment)
    toml_path = _as_toml(assignment, answers, tmp_path / "a.toml")
    csv_path = _as_csv(key, answers, tmp_path / "a.csv", with_params)
    code_t, out_t, err_t = run("grade", toml_path, "--json")
    extra = [] if with_params else ["--params", assignment / "answers.toml"]
    code_c, out_c, err_c = run("grade", csv_path, "--json", *extra)
    assert code_t == code_c == 1, (err_t, err_c)  # doubled values and a typo
    t, c = json.loads(out_t), json.loads(out_c)
    assert _verdicts(t) == _verdicts(c)
    for k in ("passed", "failed", "invalid", "unanswered"):
        assert t[k] == c[k], k
    # by hand: s3 and s6 doubled every value (2 + 5 outputs each); s5's 4.10 Omega cell is invalid (its
    # other four outputs are graded); s2 left one blank
    assert t["invalid"] == 1 and t["unanswered"] == 1 and t["failed"] == 14
    assert t["passed"] == 6 * 7 - 14 - 1 - 1


def test_the_gradebook_parses_to_the_jsons_totals(assignment, tmp_path):
    key, answers = _answers(assignment)
    path = _as_toml(assignment, answers, tmp_path / "a.toml")
    book = tmp_path / "book.csv"
    code, out, _ = run("grade", path, "--json", "--csv", book)
    d = json.loads(out)
    rows = list(csv.DictReader(io.StringIO(book.read_text(), newline="")))
    assert [r["student"] for r in rows] == [f"s{k}" for k in range(1, 7)]
    students = {s["student"]: s for s in d["students"]}
    for r in rows:
        s = students[r["student"]]
        assert int(r["points"]) == s["passed"] == s["points"]
        cells = [r[c] for c in r if ":" in c]
        assert int(r["max"]) == len(cells) == 7
        assert int(r["points"]) == sum(c == "1" for c in cells)
    by = {r["student"]: r for r in rows}
    assert by["s2"]["4.10:l_ef"] == "" and by["s2"]["max"] == "7"  # not answered: an empty cell
    assert by["s5"]["4.10:Omega"] == "invalid" and by["s5"]["4.10:l_ef"] == "1"  # the typo voids its cell only
    assert by["s5"]["review"] == "1" and all(r["review"] == "0" for s, r in by.items() if s != "s5")
    assert by["s4"]["4.15:theta_c"] == "1"  # the formula, right across the range
    assert sum(int(r["points"]) for r in rows) == d["passed"]


def test_gradebook_cells_are_safe_from_formula_injection(tmp_path):
    path = tmp_path / "a.toml"
    parts = []
    for name in ("=HYPERLINK(\\\"http://x\\\")", "+1", "-2", "@SUM(A1)", "plain"):
        parts.append(f'[[answer]]\nstudent = "{name}"\nexercise = "4.15"\nexpect = {{ theta_c = "41.81deg" }}\n')
    path.write_text("\n".join(parts))
    book = tmp_path / "book.csv"
    code, _, err = run("grade", path, "--csv", book)
    assert code == 0, err
    names = [r["student"] for r in csv.DictReader(io.StringIO(book.read_text(), newline=""))]
    assert names == ["'=HYPERLINK(\"http://x\")", "'+1", "'-2", "'@SUM(A1)", "plain"]


def test_a_csv_of_answers_with_its_own_parameters(tmp_path):
    path = tmp_path / "a.csv"
    path.write_text("student,4.15:theta_c,4.15:omega_c,4.15:theta0\n"
                    "ann,35.26deg,2.91 rad/s,60deg\n"
                    "bob,41.81deg,,\n"  # the default theta0 = 90 deg; omega_c not answered
                    "cy,70.5deg,,60deg\n")
    code, out, err = run("grade", path, "--json")
    assert code == 1, err
    d = json.loads(out)
    ann, bob, cy = d["entries"]
    assert ann["ok"] and [q["expected"]["match"] for q in ann["quantities"] if "expected" in q] == [True, True]
    assert bob["ok"] and bob["unanswered"] == ["omega_c"]
    assert not cy["ok"] and cy["invalid"] is None


def test_an_invalid_cell_names_its_line(tmp_path):
    path = tmp_path / "a.csv"
    path.write_text('student,4.15:theta_c\nann,41.81deg\nbob,"asin(2/3"\n')
    code, out, err = run("grade", path, "--json")
    assert code == 1
    d = json.loads(out)
    assert d["invalid"] == 1 and d["entries"][1]["cells"][0]["reason"].startswith("line 3: expect.theta_c")
    code, out, err = run("grade", path, "--strict")
    assert code == 2 and out == "" and "line 3" in err and "4.15" in err


@pytest.mark.parametrize("text, words", [
    ("name,4.15:theta_c\nann,1\n", ["no 'student' column"]),
    ("student,4.15:nope\nann,1\n", ["4.15:nope", "not an output nor a parameter"]),
    ("student,4.99:x\nann,1\n", ["4.99"]),
    ("student,theta_c\nann,1\n", ["theta_c", "ID:NAME"]),
    ("student,4.15:theta0\nann,60deg\n", ["no ID:output column"]),
    ("student,4.15:theta_c\n", ["no rows of answers"]),
    ("", ["no header row"]),
    ('student,4.15:theta_c\nann,"unclosed\n', ["malformed CSV"]),
    ("student,4.15:theta_c\nann," + "1" * 2000 + "\n", ["a cell of 2000 characters"]),
    ("student," + ",".join(f"4.15:theta_c{k}" for k in range(500)) + "\n", ["501 columns", "at most 400"]),
    ("student,4.15:theta_c\n" + "a,1\n" * 6000, ["more than 5000 rows"]),
])
def test_a_bad_csv_is_exit_2_in_one_line_each(tmp_path, text, words):
    path = tmp_path / "a.csv"
    path.write_text(text)
    code, out, err = run("grade", path)
    assert code == 2 and out == "" and "Traceback" not in err, err
    assert all(w in err for w in words), err


def test_a_big_csv_is_refused_before_it_is_read(tmp_path):
    path = tmp_path / "a.csv"
    with path.open("w") as fh:
        fh.write("student,4.15:theta_c\n")
        fh.write(("x" * 1000 + "\n") * 5000)
    code, out, err = run("grade", path)
    assert code == 2 and "at most" in err and "bytes" in err


def test_an_output_equal_to_the_input_is_refused(tmp_path):
    path = tmp_path / "a.csv"
    path.write_text("student,4.15:theta_c\nann,41.81deg\n")
    code, _, err = run("grade", path, "--csv", path)
    assert code == 2 and "the same file as FILE" in err
    assert path.read_text() == "student,4.15:theta_c\nann,41.81deg\n"
