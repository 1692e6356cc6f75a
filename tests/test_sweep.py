"""mech sweep: the grid, its numbers against single `mech solve` runs, exit 2 for bad ranges, serial = parallel."""

import csv
import io
import json
import math

import pytest
from click.testing import CliRunner

from mech.cli.main import cli
from mech.problems import registry
from mech.studies.sweep import Axis, grid_points, plan_workers, run_sweep


def run(*args):
    result = CliRunner().invoke(cli, list(args))
    return result.exit_code, result.stdout, result.stderr


def test_sweep_numbers_are_those_of_single_solves():
    code, out, err = run("sweep", "4.15", "--theta0", "30deg:90deg:3", "--l", "2", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert d["id"] == "4.15" and d["agree"] is True
    assert [p["params"]["theta0"] for p in d["points"]] == pytest.approx([math.pi / 6, math.pi / 3, math.pi / 2])
    for point in d["points"]:
        # the point's own value: the analytic one to the last bit; the numeric one within the two claims (4.15's
        # sweep steps its points together, the step the worst point's, a single solve steps alone)
        code, single, err = run("solve", "4.15", "--theta0", repr(point["params"]["theta0"]), "--l", "2", "--json")
        assert code == 0, err
        s = json.loads(single)
        assert point["params"] == s["params"]
        for qp, qs in zip(point["quantities"], s["quantities"]):
            assert qp["name"] == qs["name"]
            assert qp["analytic"] == qs["analytic"]
            assert abs(qp["numeric"] - qs["numeric"]) <= qp["numeric_err"] + qs["numeric_err"]
            assert qp["agree"] is qs["agree"] is True


def test_grid_order_first_axis_slowest_and_csv():
    code, out, err = run("sweep", "4.15", "--theta0", "45deg:90deg:2", "-p", "l=1:3:3", "--no-verify", "--csv")
    assert code == 0, err
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == 6
    # units in the header; theta0 was typed in degrees, so it is shown in degrees
    assert "theta0 [deg]" in rows[0] and "l [m]" in rows[0] and "theta_c_numeric [rad]" in rows[0]
    pairs = [(float(r["theta0 [deg]"]), float(r["l [m]"])) for r in rows]
    assert pairs == [(45.0, 1.0), (45.0, 2.0), (45.0, 3.0), (90.0, 1.0), (90.0, 2.0), (90.0, 3.0)]
    # theta_c does not depend on l; sin theta_c = (2/3) sin theta0
    for r in rows:
        theta0 = math.radians(float(r["theta0 [deg]"]))
        assert math.sin(float(r["theta_c_numeric [rad]"])) == pytest.approx(2 / 3 * math.sin(theta0), rel=1e-8)
        assert r["agree"] == "true"


def test_csv_units_typed_and_si():
    # typed in Hz: shown in Hz; a parameter given in SI stays in SI
    code, out, err = run("sweep", "4.15", "--l", "50cm:150cm:3", "--no-verify", "--csv")
    assert code == 0, err
    rows = list(csv.DictReader(io.StringIO(out)))
    assert [float(r["l [cm]"]) for r in rows] == pytest.approx([50.0, 100.0, 150.0])
    code, out, err = run("sweep", "4.15", "--l", "0.5:1.5:3", "--no-verify", "--csv")
    rows = list(csv.DictReader(io.StringIO(out)))
    assert [float(r["l [m]"]) for r in rows] == pytest.approx([0.5, 1.0, 1.5])
    # a display unit (deg) is used when nothing was typed
    code, out, err = run("sweep", "4.15", "--theta0", "0.5:1.5:3", "--no-verify", "--csv")
    rows = list(csv.DictReader(io.StringIO(out)))
    assert float(rows[0]["theta0 [deg]"]) == pytest.approx(math.degrees(0.5))


def test_log_range_and_table():
    code, out, err = run("sweep", "4.10", "--l", "1cm:1m:3:log", "--no-verify")
    assert code == 0, err
    assert "4.10" in out and "l [cm]" in out and "3 points" in out  # shown in the unit typed


@pytest.mark.parametrize("args, words", [
    (("--theta0", "30deg:100deg:3"), ["theta0", "out of range"]),
    (("--theta0", "30deg:60deg:x"), ["theta0", "whole number"]),
    (("--theta0", "30deg:60deg:0"), ["theta0", "between 1"]),
    (("--theta0", "30deg:60deg"), ["START:STOP:N"]),
    (("--theta0", "1s:2s:3"), ["theta0", "a time"]),
    (("--l", "-1:1:3:log"), ["l", "log"]),
    (("--l", "2"), ["nothing to sweep"]),
    (("--nope", "1:2:3"), ["unknown parameter 'nope'"]),
    (("--l", "1:2:2", "--l", "3:4:2"), ["more than once"]),
])
def test_bad_ranges_exit_2_with_one_line(args, words):
    code, out, err = run("sweep", "4.15", *args)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("mech: error:")
    for w in words:
        assert w in err


def test_joint_constraint_is_checked_at_every_point():
    # 4.13: the cylinder (R) must fit in the hollow (R' = 0.2 m): R = 0.2 and 0.3 m are in R's own bounds
    # but refused by the joint limit: marked, not solved; R = 0.1 m is swept (issue 41)
    code, out, err = run("sweep", "4.13", "--R", "0.1:0.3:3", "--json")
    assert code == 0 and err == ""
    d = json.loads(out)
    assert [("must exceed" in p.get("refused", "")) for p in d["points"]] == [False, True, True]
    assert d["points"][0]["agree"] is True and d["agree"] is True
    # every point refused: nothing to sweep, exit 2 naming the first
    code, out, err = run("sweep", "4.13", "--R", "0.2:0.3:3")
    assert code == 2 and err.count("\n") == 1
    assert "every point of the sweep is refused" in err and "sweep point R = 0.2" in err and "must exceed" in err


def test_serial_and_parallel_give_the_same_numbers_in_grid_order():
    ex = registry.get("5.6")
    axes = [Axis("theta0", (0.3, 1.0, 2.0, 2.8))]
    params = [ex.resolve(v) for v in grid_points(axes, {})]
    serial = run_sweep(ex, axes, {}, params, verify=False, jobs=1)
    parallel = run_sweep(ex, axes, {}, params, verify=False, jobs=2)
    assert serial.workers == 1 and parallel.workers == 2
    strip = lambda r: [(p["params"], p["quantities"], p["agree"]) for p in r.point_list()]  # noqa: E731
    assert strip(serial) == strip(parallel)
    assert [p["params"]["theta0"] for p in parallel.point_list()] == [0.3, 1.0, 2.0, 2.8]


def test_pool_only_when_it_pays():
    assert plan_workers(10, 0.001, cores=2) == 1  # 10 ms of work: serial
    assert plan_workers(100, 0.2, cores=2) == 2  # 20 s of work: both cores
    assert plan_workers(100, 0.2, cores=1) == 1
    assert plan_workers(1, 10.0, cores=8) == 1


def test_sweep_plot_writes_a_png(tmp_path):
    pytest.importorskip("matplotlib")
    f = tmp_path / "s.png"
    code, out, err = run("sweep", "5.6", "--theta0", "0.5:2.5:3", "--no-verify", "--csv", "--plot", str(f))
    assert code == 0, err
    assert f.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(out.strip().splitlines()) == 4


def test_the_sweep_table_never_cuts_a_number_at_60_or_80_columns(monkeypatch):
    """At a narrow width the table stacks into one block per point; every value printed whole."""
    from click.testing import CliRunner

    from mech.cli.main import cli

    for width in ("60", "80", "200"):
        monkeypatch.setenv("COLUMNS", width)
        res = CliRunner().invoke(cli, ["sweep", "4.15", "--theta0", "10deg:90deg:3"])
        assert res.exit_code == 0
        assert "…" not in res.output
        lines = res.output.splitlines()
        assert all(len(line) <= int(width) for line in lines), width
        assert all(line == line.rstrip() for line in lines)
        assert "0.7297276562" in res.output  # theta_c at 90 deg: asin(2/3), by hand
