"""mech check --save-baseline / --baseline: a saved run passes unchanged; a value moved beyond its error
bars since fails and is named."""

import copy
import json

import pytest
from click.testing import CliRunner

from mech.cli.main import cli
from mech.verification import baseline


def run(*args):
    result = CliRunner().invoke(cli, list(args))
    return result.exit_code, result.stdout, result.stderr


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    path = tmp_path_factory.mktemp("base") / "base.json"
    code, _, err = run("check", "4.15", "--hard", "--save-baseline", str(path))
    assert code == 0, err
    return json.loads(path.read_text("utf-8"))


def _write(tmp_path, data):
    path = tmp_path / "b.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    return str(path)


def test_saved_file_records_every_output_at_every_point(saved):
    assert saved["format"] == "mech-baseline" and saved["hard"] is True
    assert set(saved["versions"]) >= {"mech", "numpy", "scipy", "python"}
    # 4.15's hard case 1 (theta0 = 90 deg) is its default: mech check runs it once, as the defaults
    assert [(c["id"], c["case"]) for c in saved["cases"]] == [("4.15", "defaults"), ("4.15", "hard 2")]
    for case in saved["cases"]:
        assert set(case["outputs"]) == {"theta_c", "omega_c"}
        for o in case["outputs"].values():
            assert o["analytic"] is not None and o["numeric"] is not None and o["numeric_err"] > 0
    # the defaults: theta_c = asin(2/3) = 0.7297277 rad (upright start)
    assert saved["cases"][0]["outputs"]["theta_c"]["analytic"] == pytest.approx(0.72972766, rel=1e-8)


def test_unchanged_baseline_passes(saved, tmp_path):
    code, out, _ = run("check", "4.15", "--hard", "--baseline", _write(tmp_path, saved))
    assert code == 0 and "none moved" in out


def test_a_value_moved_beyond_its_error_bars_fails_and_is_named(saved, tmp_path):
    moved = copy.deepcopy(saved)
    o = moved["cases"][1]["outputs"]["omega_c"]
    o["numeric"] += 3 * o["numeric_err"]  # beyond old + new error bars (about 2 of them)
    code, out, _ = run("check", "4.15", "--hard", "--baseline", _write(tmp_path, moved), "--json")
    assert code == 1
    d = json.loads(out)
    assert d["ok"] is True and d["baseline"]["ok"] is False
    (m,) = d["baseline"]["moved"]
    assert (m["id"], m["case"], m["output"], m["which"]) == ("4.15", "hard 2", "omega_c", "numeric")


def test_a_value_moved_within_its_error_bars_passes(saved, tmp_path):
    moved = copy.deepcopy(saved)
    o = moved["cases"][0]["outputs"]["theta_c"]
    o["numeric"] += 0.5 * o["numeric_err"]
    code, out, _ = run("check", "4.15", "--baseline", _write(tmp_path, moved))
    assert code == 0, out


def test_an_analytic_value_moved_is_named_in_the_table(saved, tmp_path):
    moved = copy.deepcopy(saved)
    moved["cases"][0]["outputs"]["theta_c"]["analytic"] *= 1 + 1e-9  # no analytic_err: round-off only
    code, out, _ = run("check", "4.15", "--baseline", _write(tmp_path, moved))
    assert code == 1 and "4.15 defaults theta_c analytic" in out


@pytest.mark.parametrize("data, words", [
    ({"format": "x"}, "not a mech baseline"),
    ({"format": "mech-baseline", "version": 1}, "cases"),
    ({"format": "mech-baseline", "version": 1, "cases": [{"id": "4.15", "case": "defaults", "params": {},
                                                           "outputs": {"a": {"numeric": "x"}}}]},
     "outputs.a.numeric"),
])
def test_a_bad_baseline_exits_2_before_the_run(tmp_path, data, words):
    code, out, err = run("check", "4.15", "--baseline", _write(tmp_path, data))
    assert code == 2 and out == "" and words in err and len(err.strip().splitlines()) == 1


def test_malformed_json_exits_2(tmp_path):
    path = tmp_path / "b.json"
    path.write_text("{", encoding="utf-8")
    code, out, err = run("check", "4.15", "--baseline", str(path))
    assert code == 2 and "malformed JSON" in err


# -- the comparison itself, on hand-made records ----------------------------------------------------------

def _rec(value, err, params=None, case="defaults"):
    return {"id": "9.9", "case": case, "params": params or {"a": 1.0}, "ok": True,
            "outputs": {"x": {"unit": "m", "analytic": 1.0, "numeric": value, "numeric_err": err}}}


def test_compare_allows_the_two_error_bars_combined():
    old = {"cases": [_rec(1.0, 1e-6)]}
    # allowed: 1e-6 + 2e-6 + 1e-12 * 1.0
    assert baseline.compare(old, [_rec(1.0 + 2.9e-6, 2e-6)]).ok
    cmp = baseline.compare(old, [_rec(1.0 + 3.1e-6, 2e-6)])
    assert not cmp.ok and cmp.moved[0].allowed == pytest.approx(3e-6 + 1e-12)


def test_compare_names_changed_parameters_and_new_points():
    old = {"cases": [_rec(1.0, 1e-6)]}
    cmp = baseline.compare(old, [_rec(1.0, 1e-6, params={"a": 2.0}), _rec(1.0, 1e-6, case="hard 1")])
    assert not cmp.ok and "parameters differ" in cmp.moved[0].why
    assert cmp.not_in_baseline == ["9.9 hard 1"]


def test_compare_a_value_that_became_undefined():
    old = {"cases": [_rec(1.0, 1e-6)]}
    new = _rec(None, None)
    cmp = baseline.compare(old, [new])
    assert not cmp.ok and "no longer has a finite value" in cmp.moved[0].why


def test_junit_gains_one_case_per_point_compared(saved, tmp_path):
    import xml.etree.ElementTree as ET

    moved = copy.deepcopy(saved)
    o = moved["cases"][1]["outputs"]["theta_c"]
    o["numeric"] -= 3 * o["numeric_err"]
    junit = tmp_path / "check.xml"
    code, _, _ = run("check", "4.15", "--hard", "--baseline", _write(tmp_path, moved), "--junit", str(junit))
    assert code == 1
    root = ET.parse(junit).getroot()
    suites = root.findall("testsuite")
    assert len(suites) == 2 and suites[1].get("name").startswith("mech baseline")
    cases = suites[1].findall("testcase")
    assert [c.get("name") for c in cases] == ["defaults", "hard 2"]
    assert [c.find("failure") is not None for c in cases] == [False, True]
    assert root.get("tests") == "4" and root.get("failures") == "1"
