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


# -- item 1: catalogue text with brackets is shown as written ----------------------------------------

def test_show_keeps_bracketed_text_that_rich_would_take_for_markup():
    from mech.problems import registry

    for ex_id in ("4.3", "4.12", "5.1"):
        ex = registry.get(ex_id)
        bracketed = [f for f in ex.formulas if "[" in f]
        assert bracketed, ex_id  # the formulas the issue names hold a bracket
        code, out, _ = run("show", ex_id, env={"COLUMNS": "400"})
        assert code == 0
        for f in bracketed:
            assert f in out, (ex_id, f)


def test_show_keeps_brackets_in_statement_and_route():
    from mech.problems import registry

    for ex in registry.all_exercises().values():
        texts = [t for t in (ex.statement, ex.model, ex.numeric_route, ex.route_note) if "[" in t]
        if not texts:
            continue
        code, out, _ = run("show", ex.id, env={"COLUMNS": "100000"})
        flat = " ".join(out.split())
        for t in texts:
            for piece in re.findall(r"\[[^\]\n]*\]", t):
                assert " ".join(piece.split()) in flat, (ex.id, piece)


# -- item 3: no number is ever cut, at 60 and 80 columns ---------------------------------------------

@pytest.mark.parametrize("width", [60, 80])
@pytest.mark.parametrize("ex_id", ["4.30", "4.10", "5.8", "4.15"])
def test_solve_table_never_cuts_a_number(ex_id, width):
    from mech import render
    from mech.problems import registry
    from mech.verification.crosscheck import cross_check

    code, out, _ = run("solve", ex_id, env={"COLUMNS": str(width)})
    assert code == 0
    assert "…" not in out
    assert max(len(line) for line in out.splitlines()) <= width
    # every value the table shows, formatted independently of the layout, appears whole
    result = cross_check(registry.get(ex_id), registry.get(ex_id).resolve({}), verify=False)
    for q in result.quantities:
        for v, err in ((q.analytic, getattr(q, "analytic_err", None)), (q.numeric, getattr(q, "numeric_err", None))):
            shown = render.with_error(v, err)
            assert shown in out, (ex_id, width, shown)


@pytest.mark.parametrize("width", [60, 80])
def test_show_and_check_never_cut_at_narrow_widths(width):
    for args in (["show", "4.30"], ["show", "4.3"], ["check", "4.3", "--hard"]):
        code, out, _ = run(*args, env={"COLUMNS": str(width)})
        assert code == 0 and "…" not in out, args
        assert max(len(line) for line in out.splitlines()) <= width, args


def test_piped_lines_have_no_trailing_spaces():
    for args in (["solve", "4.15"], ["show", "4.15"], ["check", "4.1"], ["list"]):
        code, out, _ = run(*args)
        assert code == 0
        assert all(line == line.rstrip() for line in out.splitlines()), args


def test_list_follows_columns():
    code, out, _ = run("list", env={"COLUMNS": "70"})
    assert code == 0 and max(len(line) for line in out.splitlines()) <= 70


# -- earned digits -----------------------------------------------------------------------------------

@pytest.mark.parametrize("v, err, text", [
    (0.729727656221, 7.3e-9, "0.729727656(8)"),      # error rounded up to one digit, on the 1e-9 place
    (9.99993456e-6, 6.2e-11, "9.99993(7)e-06"),      # the example
    (-5.4908862484e-05, 5.5e-13, "-5.49088625(6)e-05"),
    (114429.347522, 0.0011, "114429.348(2)"),     # .347522 rounds to .348; 1.1e-3 rounds up to 2e-3
    (114429.347522, 30.0, "1.1443(3)e+05"),          # an error above the units place: scientific
    (0.999996, 1e-5, "1.00000(1)"),                  # rounding carries into a new leading digit
    (1.5, None, "1.5"),
    (2 / 3, None, "0.666666666667"),                 # no error known: 12 significant digits
    (1e-9, 1e-6, "1e-09 ± 1e-06"),                   # the error exceeds the value
])
def test_values_are_printed_to_their_earned_digits(v, err, text):
    from mech.render import with_error

    assert with_error(v, err) == text


def test_solve_table_uses_numeric_err_when_the_crosscheck_gives_it(monkeypatch):
    from mech import render
    from mech.problems import registry
    from mech.verification.crosscheck import cross_check

    ex = registry.get("4.15")
    import dataclasses

    result = cross_check(ex, ex.resolve({}), verify=False)
    result = result.replace(quantities=tuple(dataclasses.replace(q, numeric_err=1e-8 * abs(q.numeric))
                                             for q in result.quantities))
    c = render.Console(width=200, color_system=None)
    with c.capture() as cap:
        c.print(render.solve_table(result, width=200))
    # theta_c = asin(2/3) = 0.7297276562269663 from the upright start; 1e-8 relative = 7.3e-9
    assert "0.729727656(8)" in cap.get()


# -- item 7: did you mean --------------------------------------------------------------------------

@pytest.mark.parametrize("typed", ["4.150", "4,15", "415", "ex4.15"])
def test_unknown_id_suggests_the_nearest(typed):
    line = one_line_exit_2("solve", typed)
    assert "did you mean 4.15?" in line and f"(registered: {_chapter_spans()})" in line
    assert "4.17" not in line  # not every id on one line


def test_unknown_id_past_a_chapters_end_suggests_nothing():
    line = one_line_exit_2("show", "4.37")
    assert "did you mean" not in line and _chapter_spans().split(", ")[0] in line


def _chapter_spans() -> str:
    """The registered ids as each chapter's first and last, from the catalogue's file names."""
    from pathlib import Path

    from mech.problems import registry

    ids = sorted((tuple(map(int, p.stem.split("."))) for p in (Path(registry.__file__).parent / "catalogue").glob("*.toml")))
    chapters = sorted({c for c, _ in ids})
    return ", ".join(f"{c}.{min(n for k, n in ids if k == c)}-{c}.{max(n for k, n in ids if k == c)}" for c in chapters)


def test_unknown_parameter_suggests_the_nearest():
    line = one_line_exit_2("solve", "4.15", "--theta", "1")
    assert "did you mean theta0?" in line


# -- item 8: the slips of an unquoted value ---------------------------------------------------------

@pytest.mark.parametrize("args, hint", [
    (["--l", "67", "m"], "--l '67 m'"),
    (["--l", "67", "m"], "--l 67m"),
    (["-p", "theta0", "60deg"], "-p theta0=60deg"),
    (["--theta0", "--l", "2"], "theta0: no value given before '--l'"),
    (["--theta0=60", "deg"], "--theta0 60deg"),
])
def test_unquoted_values_get_a_hint(args, hint):
    line = one_line_exit_2("solve", "4.15", *args)
    assert hint in line and "Got unexpected extra argument" not in line


def test_a_negative_value_is_still_a_value():
    code, out, err = run("solve", "5.2", "--method", "analytic", "--json")
    assert code == 0, err


# -- items 12, 13: notes once, and an analytic-only solve --------------------------------------------

def test_analytic_only_has_no_tol_or_agree_column_and_says_so():
    code, out, _ = run("solve", "4.15", "--method", "analytic")
    assert code == 0
    header = next(line for line in out.splitlines() if "quantity" in line)
    assert "analytic" in header and "tol" not in header and "agree" not in header and "numeric" not in header
    assert "nothing was cross-checked" in out


def test_numeric_only_has_no_analytic_column_and_says_so():
    code, out, _ = run("solve", "4.15", "--method", "numeric")
    assert code == 0
    header = next(line for line in out.splitlines() if "quantity" in line)
    assert "numeric" in header and "analytic" not in header and "tol" not in header
    assert "numeric solver only" in out and "nothing was cross-checked" in out


def test_solve_help_without_an_id_says_how_to_list_parameters():
    code, out, _ = run("solve", "--help")
    assert code == 0 and "mech solve ID --help" in out


def test_a_note_shared_by_outputs_is_said_once(monkeypatch):
    from mech import render
    from mech.problems import registry
    from mech.verification.crosscheck import cross_check

    ex = registry.get("4.15")
    import dataclasses

    result = cross_check(ex, ex.resolve({}), verify=False)
    result = result.replace(quantities=tuple(dataclasses.replace(q, notes=q.notes + ("the same remark",))
                                             for q in result.quantities))
    assert render._notes(result) == ["theta_c, omega_c: the same remark"]


# -- item 14: mech check's cases ---------------------------------------------------------------------

def test_check_names_hard_cases_by_their_parameters_and_runs_an_id_once(tmp_path):
    import xml.etree.ElementTree as ET

    junit = tmp_path / "r.xml"
    code, out, _ = run("check", "4.15", "4.15", "--hard", "--junit", str(junit), "--json")
    d = json.loads(out)
    # 4.15's hard case 1 is theta0 = 90 deg, its default: run once, the defaults' description says so
    assert [c["case"] for c in d["cases"]] == ["defaults", "hard 2"]
    assert [c["description"] for c in d["cases"]] == ["defaults (= hard 1)", "hard 2: theta0 = 1 deg"]
    cases = list(ET.parse(junit).getroot().iter("testcase"))
    assert [tc.get("classname") for tc in cases] == ["mech.ex4_15", "mech.ex4_15"]
    assert [tc.get("name") for tc in cases] == ["4.15 defaults (= hard 1)", "4.15 hard 2: theta0 = 1 deg"]


# -- item 16, 18: help ------------------------------------------------------------------------------

def test_solve_help_lists_the_exercises_parameters():
    code, out, _ = run("solve", "4.15", "--help", env={"COLUMNS": "200"})
    assert code == 0
    assert "Parameters of 4.15" in out
    for name in ("--theta0", "--l", "--g"):
        assert name in out
    assert "default 90 deg" in out and "(0, 90] deg" in out
    assert "contract" not in out.lower()


def test_parameter_names_tab_complete():
    from click.shell_completion import ShellComplete

    comp = ShellComplete(cli, {}, "mech", "_MECH_COMPLETE")
    got = [c.value for c in comp.get_completions(["solve", "4.15"], "--th")]
    assert got == ["--theta0"]
    got = [c.value for c in comp.get_completions(["solve", "4.15", "--theta0", "1"], "--")]
    assert "--l" in got and "--g" in got and "--theta0" not in got and "--json" in got


# -- item 19: the book's own exercises and those set for mech ---------------------------------------

def test_from_book_in_list_and_show_json():
    code, out, _ = run("list", "--json")
    flags = {i["id"]: i["from_book"] for i in json.loads(out)}
    assert all(flags[f"4.{k}"] for k in range(1, 37))
    assert [flags[f"5.{k}"] for k in range(1, 14)] == [True] * 3 + [False] * 10
    for ex_id, book in (("4.15", True), ("5.3", True), ("5.4", False)):
        code, out, _ = run("show", ex_id, "--json")
        assert json.loads(out)["from_book"] is book


def test_from_book_in_list_and_show_text():
    code, out, _ = run("list")
    assert " 5.4† " in out and " 5.3 " in out and "5.3†" not in out
    code, out, _ = run("show", "5.4")
    assert "set for mech" in out
    code, out, _ = run("show", "5.3")
    assert "source: the book's own exercise" in out


# -- item 11: bench's method names -----------------------------------------------------------------

def test_bench_takes_method_names_without_case():
    code, out, err = run("bench", "4.15", "--methods", "dop853", "--tols", "1e-6", "--repeats", "1", "--json")
    assert code == 0, err
    assert {p["method"] for p in json.loads(out)["points"]} == {"DOP853"}


def test_bench_unknown_method_lists_each_name_once():
    line = one_line_exit_2("bench", "4.15", "--methods", "rk44")
    known = line.split("known: ")[1].rstrip(")").split(", ")
    assert len(known) == len(set(known)) and "RK45" in known and "did you mean RK45?" in line


def test_readme_exercise_table_marks_the_exercises_set_for_mech():
    from pathlib import Path

    from mech.problems import registry

    text = (Path(__file__).resolve().parents[1] / "README.md").read_text("utf-8").split("## Exercises", 1)[1]
    text = text.split("\n## ", 1)[0]
    entries = {e.id: e for e in registry.index()}
    rows = [line for line in text.splitlines() if re.match(r"\| \d+\.\d+ \|", line)]
    assert rows
    for row in rows:
        e = entries[row.split("|")[1].strip()]
        title_cell = row.split("|")[2]
        assert title_cell.rstrip().endswith("†") is (not e.from_book), e.id
