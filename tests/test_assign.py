"""Issue 32 item 2: ``mech assign``: personal variants, verified, with handout, template and key.

Hand values used: 4.15 (sliding ladder) sin theta_c = (2/3) sin theta0, omega_c^2 = g sin(theta0)/l (from
the energy at that angle); 4.10 (physical pendulum)
Omega^2 = M g l / (I + M l^2).
"""

import csv
import io
import json
import math
import re
import tomllib

import pytest
from click.testing import CliRunner

from mech.cli.main import cli

IDS = ("4.15", "4.10", "5.4")


def run(*args):
    r = CliRunner().invoke(cli, [str(a) for a in args])
    return r.exit_code, r.stdout, r.stderr


@pytest.fixture(scope="module")
def assigned(tmp_path_factory):
    root = tmp_path_factory.mktemp("assign")
    code, out, err = run("assign", *IDS, "--n", "30", "--seed", "11", "--out", root / "a")
    assert code == 0, err
    return root


def _fill(folder, factor, path):
    key = json.loads((folder / "key.json").read_text())
    vals = {(v["student"], v["exercise"]): v["outputs"] for v in key["variants"]}
    template = tomllib.loads((folder / "answers.toml").read_text())
    parts = []
    for a in template["answer"]:
        assert set(a["expect"].values()) == {""}  # the template leaves every answer to the student
        outs = vals[(a["student"], a["exercise"])]
        params = ", ".join(f"{k} = {json.dumps(v)}" for k, v in a["params"].items())
        expect = ", ".join(f'{k} = "{outs[k]["value"] * factor!r}"' for k in a["expect"])
        parts.append(f'[[answer]]\nstudent = {json.dumps(a["student"])}\nexercise = "{a["exercise"]}"\n'
                     f"params = {{ {params} }}\nexpect = {{ {expect} }}\n")
    path.write_text("\n".join(parts))
    return path


def test_the_files_and_the_key(assigned):
    folder = assigned / "a"
    key = json.loads((folder / "key.json").read_text())
    import mech

    assert key["mech"] == mech.__version__ and key["seed"] == 11
    assert len(key["variants"]) == 90
    assert [v["student"] for v in key["variants"][:3]] == ["s1"] * 3
    assert [v["exercise"] for v in key["variants"][:3]] == list(IDS)
    for v in key["variants"]:
        for rec in v["outputs"].values():
            assert set(rec) == {"value", "unit", "analytic", "numeric", "numeric_err", "leading_order"}
    handout = (folder / "handout.md").read_text()
    assert handout.count("## s") == 30 and handout.count("### Exercise 4.15") == 30
    # 30 students drew 30 different ladders
    assert len({json.dumps(v["params"]) for v in key["variants"] if v["exercise"] == "4.15"}) == 30


def _num(text):
    return float(re.match(r"[-+0-9.e]+", text).group(0))


def test_values_are_rounded_inside_the_ranges_and_the_key_is_right_by_hand(assigned):
    key = json.loads((assigned / "a" / "key.json").read_text())
    for v in key["variants"]:
        for name, text in v["params"].items():
            digits = re.sub(r"e.*", "", re.match(r"[-+0-9.e]+", text).group(0)).replace(".", "").lstrip("0")
            assert len(digits) <= 3, (name, text)  # three significant digits, in the unit shown
        if v["exercise"] == "4.15":
            th0 = math.radians(_num(v["params"]["theta0"]))  # printed in degrees
            assert 0 < th0 <= math.pi / 2
            l, g = _num(v["params"].get("l", "1")), _num(v["params"].get("g", "9.81"))
            assert v["outputs"]["theta_c"]["value"] == pytest.approx(math.asin(2 / 3 * math.sin(th0)), rel=1e-12)
            # energy: (1/2)(M l^2/3) omega^2 = M g (l/2)(sin theta0 - sin theta_c), sin theta_c = (2/3) sin theta0
            omega = math.sqrt(g * math.sin(th0) / l)
            assert v["outputs"]["omega_c"]["value"] == pytest.approx(omega, rel=1e-9)
        if v["exercise"] == "4.10":
            M, I, l, g = (_num(v["params"][k]) for k in ("M", "I", "l", "g"))
            assert v["outputs"]["Omega"]["value"] == pytest.approx(math.sqrt(M * g * l / (I + M * l * l)), rel=1e-12)


def test_the_template_filled_with_the_key_is_all_right(assigned, tmp_path):
    path = _fill(assigned / "a", 1.0, tmp_path / "right.toml")
    book = tmp_path / "book.csv"
    code, out, err = run("grade", path, "--json", "--csv", book)
    assert code == 0, err
    d = json.loads(out)
    assert d["failed"] == 0 and d["invalid"] == 0 and d["passed"] == 30 * (2 + 5 + 4)
    rows = list(csv.DictReader(io.StringIO(book.read_text())))
    assert len(rows) == 30 and all(r["points"] == r["max"] == "11" for r in rows)


def test_the_template_filled_with_twice_the_key_is_all_wrong_naming_factor_2(assigned, tmp_path):
    path = _fill(assigned / "a", 2.0, tmp_path / "wrong.toml")
    code, out, err = run("grade", path, "--json")
    assert code == 1, err
    d = json.loads(out)
    hints = [q["expected"]["hint"] for e in d["entries"] for q in e["quantities"] if "expected" in q]
    assert d["passed"] == 0 and len(hints) == 330
    assert all(h and "factor 2" in h for h in hints), {h for h in hints if not h or "factor 2" not in h}


def test_the_unfilled_template_grades_as_not_answered(assigned):
    code, out, err = run("grade", assigned / "a" / "answers.toml", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert d["passed"] == d["failed"] == d["invalid"] == 0 and d["unanswered"] == 330


def test_two_runs_with_one_seed_give_the_same_bytes(assigned, tmp_path):
    code, _, err = run("assign", *IDS, "--n", "30", "--seed", "11", "--out", tmp_path / "b", "-j", "1")
    assert code == 0, err
    for name in ("handout.md", "answers.toml", "key.json"):
        assert (tmp_path / "b" / name).read_bytes() == (assigned / "a" / name).read_bytes(), name
    # another seed draws other numbers for the same students (three are enough to see it)
    code, _, err = run("assign", *IDS, "--n", "3", "--seed", "12", "--out", tmp_path / "c")
    assert code == 0, err
    params = lambda folder: [(v["student"], v["exercise"], v["params"])  # noqa: E731
                             for v in json.loads((folder / "key.json").read_text())["variants"][:9]]
    other, first = params(tmp_path / "c"), params(assigned / "a")
    assert [o[:2] for o in other] == [f[:2] for f in first]
    assert all(o[2] != f[2] for o, f in zip(other, first))


def test_roster_over_and_digits(tmp_path):
    roster = tmp_path / "roster.txt"
    roster.write_text("# class 1\nann\nbob o'neil\n\n=cmd()\n")
    code, _, err = run("assign", "4.15", "--students", roster, "--seed", "3", "--out", tmp_path / "o",
                       "--over", "theta0=10deg:30deg", "--digits", "4")
    assert code == 0, err
    key = json.loads((tmp_path / "o" / "key.json").read_text())
    assert [v["student"] for v in key["variants"]] == ["ann", "bob o'neil", "=cmd()"]
    for v in key["variants"]:
        assert 10 <= _num(v["params"]["theta0"]) <= 30
    template = tomllib.loads((tmp_path / "o" / "answers.toml").read_text())
    assert [a["student"] for a in template["answer"]] == ["ann", "bob o'neil", "=cmd()"]


@pytest.mark.parametrize("args, words", [
    (["4.15", "--seed", "1"], ["--students FILE or --n N"]),
    (["4.15", "--n", "0", "--seed", "1"], ["--n", "[1, 2000]"]),
    (["4.15", "--n", "2", "--seed", "x"], ["--seed"]),
    (["4.15", "--n", "2", "--seed", "1", "--digits", "1"], ["--digits"]),
    (["4.99", "--n", "2", "--seed", "1"], ["4.99"]),
    (["4.15", "--n", "2", "--seed", "1", "--over", "theta0=80deg:10deg"], ["--over", "theta0"]),
    (["4.15", "--n", "2", "--seed", "1", "--over", "zzz=1:2"], ["--over", "zzz"]),
    (["4.15", "--n", "2", "--seed", "1", "--over", "theta0=10deg:100deg"], ["--over", "100deg"]),
])
def test_bad_usage_is_one_line_exit_2(tmp_path, args, words):
    code, out, err = run("assign", *args, "--out", tmp_path / "o")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    assert all(w in err for w in words), err


def test_an_output_that_is_the_roster_is_refused(tmp_path):
    folder = tmp_path / "o"
    folder.mkdir()
    roster = folder / "key.json"
    roster.write_text("ann\nbob\n")
    code, out, err = run("assign", "4.15", "--students", roster, "--seed", "1", "--out", folder)
    assert code == 2 and "already holds an assignment" in err  # key.json marks an assignment
    code, out, err = run("assign", "4.15", "--students", roster, "--seed", "1", "--out", folder, "--force")
    assert code == 2 and "would overwrite the input" in err
    assert roster.read_text() == "ann\nbob\n"


def test_version_is_pyprojects():
    import pathlib

    import mech

    text = (pathlib.Path(__file__).parent.parent / "pyproject.toml").read_text()
    assert re.search(r'^version = "([^"]+)"', text, re.M).group(1) == mech.__version__


def test_assign_from_python(tmp_path):
    import mech

    key = mech.assign(["4.15"], seed=1, students=["ann", "bob"], out=tmp_path / "o", over={"theta0": "20deg:40deg"})
    assert [v["student"] for v in key["variants"]] == ["ann", "bob"]
    assert json.loads((tmp_path / "o" / "key.json").read_text()) == key
    for v in key["variants"]:
        assert 20 <= _num(v["params"]["theta0"]) <= 40
    with pytest.raises(mech.BadInput):
        mech.assign(["4.15"], seed=1, out=tmp_path / "p")  # neither students nor n


@pytest.mark.parametrize("text, words", [
    ("ann\nbob\nann\n", ["line 3", "'ann' is already line 1"]),
    ("ann\nb\x1bb\n", ["line 2", "not an identifier", "\\x1b"]),
    ("# nobody\n\n", ["no students"]),
    ("x" * 81 + "\n", ["line 1", "not an identifier"]),
])
def test_a_bad_roster_is_one_line_exit_2(tmp_path, text, words):
    roster = tmp_path / "r.txt"
    roster.write_text(text)
    code, out, err = run("assign", "4.15", "--students", roster, "--seed", "1", "--out", tmp_path / "o")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and "\x1b" not in err
    assert all(w in err for w in words), err


def test_a_class_whose_answers_grade_could_not_read_is_refused_before_any_work(tmp_path):
    """2000 students x (4.1's 6 + 4.23's 3 + 4.15's outputs) is over grade's 20 000 answers a file: refused in
    one line, nothing written (by hand: 2000 x 11 = 22 000 with 4.15's two outputs)."""
    from mech.problems import registry
    from mech.students.answers_files import MAX_ANSWERS

    outputs = sum(len(registry.get(i).outputs) for i in ("4.1", "4.23", "4.15"))
    assert 2000 * outputs > MAX_ANSWERS
    code, out, err = run("assign", "4.1", "4.23", "4.15", "--n", "2000", "--seed", "1", "--out", tmp_path / "o")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    assert f"{2000 * outputs} answers" in err and str(MAX_ANSWERS) in err
    assert not (tmp_path / "o").exists()
