"""Issue 40: an assignment an instructor would hand out.

Plausible, in-regime draws (typical ranges, fixed constants, the 1 % rule, 5.12 above threshold), a handout
per student with no word of the defaults, a key a person reads (key.csv, key.md), a CSV template, names
escaped, an assignment never overwritten without --force.

Hand values: 4.31, a drop from h in uniform g: t_fall = sqrt(2 h/g) to leading order in omega_E (the
Coriolis correction to the fall time is of order (omega_E t)^2 ~ 1e-7); 5.12, the threshold of the
Mathieu resonance near Omega = 2 omega0 (the book's reduced equations): a_th = (2 l/Omega) sqrt(delta^2 +
xi^2), xi = Omega/2 - sqrt(g/l); 4.15, sin theta_c = (2/3) sin theta0.
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

IDS = ("4.15", "4.31", "5.2", "5.8", "5.12")
N = 4  # 5.8 solves slowly: a few students show every rule


def run(*args):
    r = CliRunner().invoke(cli, [str(a) for a in args])
    return r.exit_code, r.stdout, r.stderr


def si(text, unit):
    from mech.core.units import to_si

    return to_si(text, unit)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    root = tmp_path_factory.mktemp("class") / "D"
    code, out, err = run("assign", *IDS, "--n", N, "--seed", "1", "--out", root)
    assert code == 0, err
    return root


def test_draws_are_plausible_and_in_regime(folder):
    from mech.problems import registry

    key = json.loads((folder / "key.json").read_text())
    assert key["digits"] == 3 and len(key["variants"]) == N * len(IDS)
    assert set(key["over"]) == set(IDS) and key["over"]["4.15"]["g"] == "9.81"
    for v in key["variants"]:
        ex = registry.get(v["exercise"])
        p = {q.name: si(v["params"][q.name], q.unit) for q in ex.params}
        if "g" in p:
            assert p["g"] == 9.81
        if "omega_E" in p:
            assert p["omega_E"] == 7.2921159e-5  # the sidereal rate, to the catalogue's digits
        for q in ex.params:
            if q.unit not in ("1", "rad") and q.default:
                assert abs(q.default) / 3 <= abs(p[q.name]) <= 3 * abs(q.default), (v["exercise"], q.name)
        for name, rec in v["outputs"].items():
            if rec["leading_order"]:
                assert abs(rec["analytic"] - rec["numeric"]) <= 0.01 * abs(rec["numeric"]), (v["exercise"], name)
        if v["exercise"] == "5.12":
            xi = p["Omega"] / 2 - math.sqrt(p["g"] / p["l"])
            a_th = 2 * p["l"] / p["Omega"] * math.hypot(p["delta"], xi)
            assert p["a"] > a_th  # above threshold, by hand
            assert v["outputs"]["theta_st"]["value"] > 0 and v["outputs"]["growth"]["value"] > 0
        if v["exercise"] == "4.31":
            assert v["outputs"]["t_fall"]["value"] == pytest.approx(math.sqrt(2 * p["h"] / p["g"]), rel=1e-5)


def test_handouts_one_per_student_with_their_values_and_how_to_answer(folder):
    key = json.loads((folder / "key.json").read_text())
    files = sorted((folder / "handouts").glob("*.md"))
    assert [f.name for f in files] == sorted(f"s{k}.md" for k in range(1, N + 1))
    combined = (folder / "handout.md").read_text()
    for f in files + [folder / "handout.md"]:
        text = f.read_text()
        assert "default" not in text.lower() and "Empire State" not in text
        assert "3 significant digits" in text and "`none`" in text and "formula" in text
    s2 = (folder / "handouts" / "s2.md").read_text()
    mine = [v for v in key["variants"] if v["student"] == "s2"]
    assert all(f"### Exercise {i}" in s2 for i in IDS) and "## s1" not in s2
    h = next(v for v in mine if v["exercise"] == "4.31")["params"]["h"]
    assert f"from h = {h} at the colatitude" in s2  # the statement's sentence, with s2's own values
    assert combined.count("### Exercise 5.12") == N


def test_key_csv_and_md_say_what_the_statement_asks(folder):
    key = json.loads((folder / "key.json").read_text())
    rows = list(csv.DictReader(io.StringIO((folder / "key.csv").read_text())))
    assert list(rows[0]) == ["student", "exercise", "output", "unit", "answer", "exact", "leading_order",
                             "allowance"]
    assert len(rows) == sum(len(v["outputs"]) for v in key["variants"])
    recs = {(v["student"], v["exercise"], n): r for v in key["variants"] for n, r in v["outputs"].items()}
    for row in rows:
        rec = recs[(row["student"], row["exercise"], row["output"])]
        answer, exact = float(row["answer"]), float(row["exact"])
        if rec["leading_order"]:  # the reduced equations' value: what the statement asks for
            assert answer == pytest.approx(rec["analytic"], rel=1e-11) == float(row["leading_order"])
            assert exact == pytest.approx(rec["numeric"], rel=1e-11)
        else:
            assert answer == exact and row["leading_order"] == ""
        # half a unit in the third significant digit of the answer, plus mech's error bar
        half = 0.5 * 10 ** (math.floor(math.log10(abs(answer))) - 2)
        assert float(row["allowance"]) == pytest.approx(half + rec["numeric_err"], rel=1e-2)
    md = (folder / "key.md").read_text()
    assert md.count("### Exercise 5.8") == N and "(leading order)" in md


def test_answers_csv_filled_with_the_key_grades_back_right(folder, tmp_path):
    rows = list(csv.reader(io.StringIO((folder / "answers.csv").read_text())))
    header = rows[0]
    assert header[0] == "student" and "4.15:theta0" in header and "5.12:theta_st" in header
    key = json.loads((folder / "key.json").read_text())
    answers = {(v["student"], f"{v['exercise']}:{n}"): r for v in key["variants"] for n, r in v["outputs"].items()}
    for row in rows[1:]:
        for i, h in enumerate(header):
            if (row[0], h) in answers:
                assert row[i] == ""  # left to the student
                rec = answers[(row[0], h)]
                row[i] = repr(rec["analytic"] if rec["leading_order"] else rec["value"])
    filled = tmp_path / "filled.csv"
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerows(rows)
    filled.write_text(buf.getvalue())
    code, out, err = run("grade", filled, "--json")
    assert code == 0, err
    d = json.loads(out)
    assert d["failed"] == d["invalid"] == 0 and d["passed"] == len(answers)


def test_a_second_assign_into_the_folder_is_refused_unless_forced(folder, tmp_path):
    before = (folder / "key.json").read_bytes()
    code, out, err = run("assign", "4.15", "--n", "2", "--seed", "1", "--out", folder)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and "--force" in err
    assert (folder / "key.json").read_bytes() == before
    other = tmp_path / "E"
    assert run("assign", "4.15", "--n", "3", "--seed", "1", "--out", other)[0] == 0
    code, _, err = run("assign", "4.15", "--n", "2", "--seed", "2", "--out", other, "--force")
    assert code == 0, err
    assert sorted(f.name for f in (other / "handouts").iterdir()) == ["s1.md", "s2.md"]  # s3's is gone


def test_over_fixes_narrows_and_opens(tmp_path):
    code, _, err = run("assign", "4.15", "--n", "6", "--seed", "4", "--out", tmp_path / "a",
                       "--over", "g=9.81:9.81", "--over", "theta0=10deg:80deg", "--over", "l=2.5")
    assert code == 0, err
    key = json.loads((tmp_path / "a" / "key.json").read_text())
    assert key["over"]["4.15"]["l"] == "2.5"
    for v in key["variants"]:
        assert si(v["params"]["g"], "m/s^2") == 9.81 and si(v["params"]["l"], "m") == 2.5
        assert math.radians(10) <= si(v["params"]["theta0"], "rad") <= math.radians(80)
    code, _, err = run("assign", "4.15", "--n", "6", "--seed", "4", "--out", tmp_path / "b", "--over", "g=1:30")
    assert code == 0, err
    gs = {si(v["params"]["g"], "m/s^2") for v in json.loads((tmp_path / "b" / "key.json").read_text())["variants"]}
    assert len(gs) == 6 and all(1 <= g <= 30 for g in gs)  # opened: every student a different g
    code, out, err = run("assign", "4.15", "--n", "2", "--seed", "4", "--out", tmp_path / "c", "--over", "g=-1")
    assert code == 2 and "g" in err and len(err.strip().splitlines()) == 1


HOSTILE = ["<script>alert(1)</script>", "![x](http://e.vil/a.png)", "`rm -rf`", "# head", "a;=HYPERLINK(\"h\")",
           "=cmd|' /C calc'!A0", "../../etc/passwd", "Ann", "ann", "<img src=x onerror=alert(1)>"]


def test_hostile_names_leave_no_markup_no_formula_no_path(tmp_path):
    from markdown_it import MarkdownIt

    import mech

    out = tmp_path / "o"  # a roster file skips "# head" as a comment: the API's list keeps it
    mech.assign(["4.15"], students=HOSTILE, seed=1, out=out)
    md = MarkdownIt("commonmark")
    for f in [out / "handout.md", out / "key.md", *(out / "handouts").iterdir()]:
        html = md.render(f.read_text())
        assert "<script" not in html and "<img" not in html and "<h1>head" not in html and "<code>rm" not in html
    names = sorted(f.name for f in (out / "handouts").iterdir())
    assert len(names) == len(HOSTILE) and all(re.fullmatch(r"[A-Za-z0-9_-]+\.md", n) for n in names)
    assert len({n.lower() for n in names}) == len(names)  # Ann and ann apart, even where case is ignored
    assert not (tmp_path / "etc").exists()
    for name in ("key.csv", "answers.csv"):
        for row in list(csv.reader(io.StringIO((out / name).read_text())))[1:]:
            for part in re.split(r"[,;\t|]", row[0]):
                assert not part.lstrip(" ").startswith(("=", "+", "-", "@")), (name, row[0])
    key = json.loads((out / "key.json").read_text())
    assert [v["student"] for v in key["variants"]] == HOSTILE  # the key keeps the names as given
    toml = tomllib.loads((out / "answers.toml").read_text())
    assert [a["student"] for a in toml["answer"]] == HOSTILE


def test_every_exercise_handout_is_free_of_defaults():
    from mech.problems import registry
    from mech.students.assign import Assignment, Variant

    variants = []
    for ex in registry.all_exercises().values():
        texts = {p.name: f"{p.default:.3g} {p.unit}" for p in ex.params}
        variants.append(Variant("ann", ex, texts))
    text = Assignment(1, 3, "x", variants).handout_md("ann")
    assert "default" not in text.lower()
    assert "{" not in re.sub(r"`[^`]*`", "", text)  # every placeholder filled


# exercises whose leading-order theory holds to 1 % nowhere within a factor 3 of the textbook values: their
# typical ranges are the regime where it does (5.10: mu/omega0 ~ 1e-3), which the test below holds them to
NOWHERE_NEAR_THE_DEFAULTS = {"5.10"}


@pytest.mark.parametrize("ex_id", sorted(NOWHERE_NEAR_THE_DEFAULTS))
def test_a_typical_range_leaves_the_factor_3_band_only_where_the_theory_fails_all_of_it(ex_id):
    """Drawn within a factor 3 of its textbook values, none of 256 variants passes the screen (the theory's
    own estimate of what it neglects within 2 %); drawn in its declared ranges, most do."""
    from mech.problems import registry
    from mech.students.assign import _screen
    from mech.students.points import draw

    ex = registry.get(ex_id)
    band = {p.name: (p.default / 3, 3 * p.default) if p.default and not p.fixed else tuple(p.typical)
            for p in ex.params}
    pts = draw(ex, 256, 5, band)
    assert len(pts) == 256 and not any(_screen(ex, pts))
    assert sum(_screen(ex, draw(ex, 64, 5, {p.name: tuple(p.typical) for p in ex.params}))) >= 32


def test_catalogue_typical_ranges():
    from mech.problems import registry

    constants = {"g", "omega_E", "R_E", "M_E", "GM"}
    for ex in registry.all_exercises().values():
        for p in ex.params:
            lo, hi = p.typical
            assert math.isfinite(lo) and math.isfinite(hi) and lo <= hi, (ex.id, p.name)
            # the textbook value is typical, unless the 1 % rule excludes it (5.12's theta_st: 1.3 % off)
            leading = any(o.theory != "exact" for o in ex.outputs)
            assert leading or lo <= p.default <= hi, (ex.id, p.name)
            assert (p.min is None or lo >= p.min) and (p.max is None or hi <= p.max), (ex.id, p.name)
            if p.name in constants:
                assert p.fixed and lo == hi == p.default, (ex.id, p.name)
            elif p.unit in ("1", "rad"):  # angles and ratios: a sub-range chosen from the statement
                assert p.typical_min is not None and p.typical_max is not None and lo < hi, (ex.id, p.name)
            elif p.default and ex.id not in NOWHERE_NEAR_THE_DEFAULTS:
                assert abs(p.default) / 3 * (1 - 1e-12) <= min(abs(lo), abs(hi)), (ex.id, p.name)
                assert max(abs(lo), abs(hi)) <= 3 * abs(p.default) * (1 + 1e-12), (ex.id, p.name)
    code, out, _ = run("show", "4.15", "--json")
    params = {p["name"]: p for p in json.loads(out)["params"]}
    assert params["g"]["typical_min"] == params["g"]["typical_max"] == 9.81 and params["g"]["fixed"] is True
    assert params["l"]["typical_min"] == pytest.approx(1 / 3) and params["l"]["typical_max"] == 3.0


def test_the_regime_and_one_percent_redraws_repeat_byte_for_byte(tmp_path):
    """The redraws follow the seed, never the clock or the pool: one process or two, the same files."""
    for j in ("1", "2"):
        code, _, err = run("assign", "5.12", "--n", "2", "--seed", "5", "--out", tmp_path / j, "-j", j)
        assert code == 0, err
    for f in sorted((tmp_path / "1").rglob("*")):
        if f.is_file():
            assert f.read_bytes() == (tmp_path / "2" / f.relative_to(tmp_path / "1")).read_bytes(), f.name
