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
        assert ex.has_constraints == bool(ex.joint_limits), ex.id


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
    assert "methods: analytic (exact), numeric" in run("show", "4.15")[1]
    assert "methods: analytic (leading-order for " in run("show", "4.24")[1]
    code, out, _ = run("list", "--json")
    by_id = {e["id"]: e for e in json.loads(out)}
    assert by_id["4.24"]["theory"] == "leading-order" and by_id["4.15"]["theory"] == "exact"


# -- item 10: bench ranks by what its plot compares ---------------------------------------------------------

def _pt(method, rtol, error, time_s, nfev):
    return {"method": method, "rtol": rtol, "error": error, "time_s": time_s, "time_min_s": time_s,
            "time_max_s": time_s, "nfev": nfev, "ok": True}


def test_bench_ranks_by_evaluations_and_by_time_separately():
    from mech.studies.bench import summarize

    # 5.6 as measured: Yoshida6 reaches 1e-9 in 274 evaluations and 0.13 ms (a cheap Python loop),
    # DOP853 in 164 evaluations and 1.3 ms; per evaluation DOP853 is the better method
    points = [_pt("DOP853", 1e-8, 2e-9, 0.001, 119), _pt("DOP853", 1e-10, 1.3e-11, 0.0013, 164),
              _pt("Yoshida6", 1e-4, 4e-8, 0.00006, 148), _pt("Yoshida6", 1e-6, 4.3e-10, 0.00013, 274)]
    by = {s["method"]: s for s in summarize(points)}
    assert by["DOP853"]["rank"] == 1 and by["Yoshida6"]["rank"] == 2
    assert by["Yoshida6"]["rank_by_time"] == 1 and by["DOP853"]["rank_by_time"] == 2
    assert by["DOP853"]["fewest_evals_for_1e-9"]["nfev"] == 164
    assert by["Yoshida6"]["cheapest_for_1e-9"]["time_s"] == 0.00013


def test_bench_says_what_rtol_means_on_a_fixed_step_row():
    code, out, err = run("bench", "5.6", "--methods", "Yoshida6,DOP853", "--tols", "1e-4", "--json")
    assert code == 0, err
    pts = {p["method"]: p for p in json.loads(out)["points"]}
    assert pts["Yoshida6"]["fixed_step"] is True and "no error control" in pts["Yoshida6"]["note"]
    assert "fixed_step" not in pts["DOP853"]
    code, out, err = run("bench", "5.6", "--methods", "Yoshida6,DOP853", "--tols", "1e-4")
    assert "controls no error" in out and "ranked by the evaluations" in out


def test_bench_figure_gives_the_tuned_default_a_colour_of_its_own():
    pytest.importorskip("matplotlib")
    from matplotlib.colors import to_hex

    from mech.figures.benchfig import bench_figure

    methods = ["RK45", "DOP853", "LSODA", "Radau", "Yoshida4", "Yoshida6", "scipy-default", "default"]
    r = {"id": "5.6", "title": "t", "points": [_pt(m, 1e-6, 1e-7 * (k + 1), 1e-3, 100 + k)
                                               for k, m in enumerate(methods)]}
    fig = bench_figure(r)
    lines = fig.axes[0].get_lines()
    colours = {ln.get_label(): to_hex(ln.get_color()) for ln in lines}
    default = colours.pop("mech's tuned default")
    assert default not in colours.values()
    import matplotlib.pyplot as plt

    plt.close(fig)


# -- item 15: completion offers outputs after --expect and files after grade ----------------------------------

def test_expect_completes_the_output_names():
    from click.shell_completion import ShellComplete

    comp = ShellComplete(cli, {}, "mech", "_MECH_COMPLETE")
    got = [c.value for c in comp.get_completions(["solve", "4.15", "--expect"], "")]
    assert got == ["theta_c=", "omega_c="]
    got = [c.value for c in comp.get_completions(["solve", "4.15", "--theta0", "1", "--expect"], "om")]
    assert got == ["omega_c="]


def test_grade_completes_file_names():
    from click.shell_completion import ShellComplete

    comp = ShellComplete(cli, {}, "mech", "_MECH_COMPLETE")
    got = comp.get_completions(["grade"], "hw")
    assert [(c.value, c.type) for c in got] == [("hw", "file")]


# -- item 13: infinite, -0 and the reason for an undefined output ----------------------------------------------

def test_foucault_period_on_the_equator_is_infinite_and_zero_has_no_sign():
    # on the equator (theta = 90 deg) Omega_F = -omega_E cos(theta) = 0 and T_F = 2 pi/|Omega_F| is infinite
    code, out, _ = run("solve", "4.30", "--theta", "90deg")
    assert code == 0
    row = next(line for line in out.splitlines() if line.startswith("T_F"))
    assert row.split()[2:4] == ["infinite", "infinite"] and "undefined" not in out
    omega = next(line for line in out.splitlines() if line.startswith("Omega_F"))
    assert omega.split()[2] == "0" and "-0" not in omega.split()
    assert re.search(r"^T_F: infinite: on the equator", out, re.M)
    data = json.loads(run("solve", "4.30", "--theta", "90deg", "--json")[1])
    q = {q["name"]: q for q in data["quantities"]}
    assert q["T_F"]["analytic"] is None and q["T_F"]["infinite"] is True
    assert json.dumps(q["Omega_F"]["analytic"]) == "0.0"


def test_an_undefined_output_shows_its_reason_without_expect():
    # 4.21 at omega3 = 10 rad/s: below omega_min (about 105 rad/s at the defaults) there is no steady precession
    code, out, _ = run("solve", "4.21", "--omega3", "10")
    assert code == 0
    assert re.search(r"^omega_pre, pre_ratio: analytic: omega3 = 10 rad/s is below omega_min", out, re.M)


def test_sweep_table_says_infinite_and_why():
    code, out, _ = run("sweep", "4.30", "--theta", "80deg:90deg:3")
    assert code == 0
    last = next(line for line in out.splitlines() if line.strip().startswith("90 "))
    assert last.split()[3:5] == ["infinite", "infinite"] and "-0" not in last.split()
    assert "T_F: infinite: on the equator the plane does not turn" in out


# -- item 12: a sweep echoes what was typed and writes the values typed ----------------------------------------

def test_sweep_out_of_range_echoes_the_range_as_typed():
    code, out, err = run("sweep", "4.15", "--theta0", "10:80:8")
    assert code == 2 and len(err.strip().splitlines()) == 1
    # 10 rad = 572.958 deg: the value typed leads, and the hint says how to write degrees
    assert "theta0: 10 (= 572.958 deg) is out of range" in err and "write 10deg" in err


def test_sweep_csv_writes_the_values_typed():
    code, out, _ = run("sweep", "4.15", "--theta0", "10deg:80deg:8", "--csv", "--no-verify")
    assert code == 0
    col = [line.split(",")[0] for line in out.splitlines()[1:]]
    assert col == ["10", "20", "30", "40", "50", "60", "70", "80"]  # not 29.999999999999996


def test_api_sweep_csv_writes_linspace_values_to_15_digits(tmp_path):
    import mech

    sw = mech.sweep("4.15", l=(0.1, 1.0, 10), verify=False, only="theta_c")
    sw.to_csv(tmp_path / "l.csv")
    col = [line.split(",")[0] for line in (tmp_path / "l.csv").read_text().splitlines()[1:]]
    # linspace gives 0.30000000000000004 and 0.7000000000000001
    assert col == ["0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8", "0.9", "1"]


# -- items 5, 7, 8: grading a class -----------------------------------------------------------------------------

# 4.15 at theta0 = 60 deg: theta_c = asin((2/3) sin 60 deg) = asin(1/sqrt 3) = 35.2644 deg, and
# omega_c = sqrt(g sin(theta0)/l) = sqrt(9.81 * 0.8660) = 2.9147 rad/s; bob's 70.5 deg is twice theta_c
CLASS = '''
[[answer]]
student = "alice"
exercise = "4.15"
params = { theta0 = "60deg" }
expect = { theta_c = "35.26deg", omega_c = "2.91 rad/s" }

[[answer]]
student = "bob"
exercise = "4.15"
params = { theta0 = "60deg" }
expect = { theta_c = "70.5deg" }
'''


@pytest.fixture
def class_file(tmp_path):
    path = tmp_path / "hw.toml"
    path.write_text(CLASS)
    return path


def test_grade_names_the_student_in_table_json_and_junit(class_file, tmp_path):
    from xml.etree import ElementTree as ET

    junit = tmp_path / "hw.xml"
    code, out, err = run("grade", str(class_file), "--junit", str(junit))
    assert code == 1, err  # bob is wrong
    rows = [line.split() for line in out.splitlines()]
    assert any(r[:2] == ["1", "alice"] for r in rows) and any(r[:2] == ["2", "bob"] for r in rows)
    assert "alice: 2 of 2 points, 0 wrong" in out and "bob: 0 of 1 points, 1 wrong" in out
    data = json.loads(run("grade", str(class_file), "--json")[1])
    assert [e["student"] for e in data["entries"]] == ["alice", "bob"]
    zero = {"invalid": 0, "not_graded": 0, "unanswered": 0, "review": 0, "invalid_entries": 0}
    assert data["students"] == [{"student": "alice", "passed": 2, "failed": 0, "entries": 1, "points": 2, "max": 2,
                                 "wrong": 0, **zero},
                                {"student": "bob", "passed": 0, "failed": 1, "entries": 1, "points": 0, "max": 1,
                                 "wrong": 1, **zero}]
    cases = ET.parse(junit).getroot().iter("testcase")
    seen = []
    for tc in cases:
        prop = {p.get("name"): p.get("value") for p in tc.iter("property")}
        assert tc.get("name").startswith(prop["student"] + ": ")
        seen.append(prop["student"])
    assert seen == ["alice", "alice", "bob"]


@pytest.mark.parametrize("bad", ['""', "3", '"a\\nb"', '"' + "x" * 81 + '"'])
def test_a_bad_student_name_is_refused_in_one_line(tmp_path, bad):
    path = tmp_path / "bad.toml"
    path.write_text(f'[[answer]]\nstudent = {bad}\nexercise = "4.15"\nexpect = {{ theta_c = "41.8deg" }}\n')
    code, out, err = run("grade", str(path), "--strict")
    assert code == 2 and len(err.strip().splitlines()) == 1 and "student" in err


def test_grade_junit_cases_carry_a_time(class_file, tmp_path):
    from xml.etree import ElementTree as ET

    junit = tmp_path / "hw.xml"
    run("grade", str(class_file), "--junit", str(junit))
    root = ET.parse(junit).getroot()
    suite = next(root.iter("testsuite"))
    times = [float(tc.get("time")) for tc in root.iter("testcase")]
    assert len(times) == 3 and all(t > 0 for t in times)
    assert sum(times) <= float(suite.get("time")) + 0.01


def test_grade_piped_has_no_trailing_spaces_and_stacks_when_narrow(class_file):
    _, out, _ = run("grade", str(class_file))
    assert out.splitlines() and not any(line != line.rstrip() for line in out.splitlines())
    _, out, _ = run("grade", str(class_file), env={"COLUMNS": "60"})
    lines = out.splitlines()
    assert all(len(line) <= 60 for line in lines) and "…" not in out
    assert not any(line != line.rstrip() for line in lines)
    # every cell whole: the parameters, the output names and each verdict on one line
    assert "(theta0=60deg)" in out and "omega_c" in out
    assert any("off by a factor 2" in line for line in lines)


def test_a_zero_with_an_error_bar_has_no_sign():
    from mech.render import with_error

    assert with_error(-0.0, 1e-10) == "0 ± 1e-10"
    assert with_error(-0.0, None) == "0"
