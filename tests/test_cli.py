"""The command line through click's CliRunner: the contract's shapes, exit codes and errors."""

import json
import math
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest
from click.testing import CliRunner

from mech.cli.main import cli
from mech.problems import registry
from mech.problems.spec import Undefined


def run(*args):
    result = CliRunner().invoke(cli, list(args))
    return result.exit_code, result.stdout, result.stderr


def test_list_json_has_every_registered_exercise():
    code, out, _ = run("list", "--json")
    assert code == 0
    items = json.loads(out)
    assert [i["id"] for i in items] == list(registry.all_exercises())
    for item in items:
        assert set(item) >= {"id", "title", "topic", "methods"}
        assert item["methods"] == ["analytic", "numeric"]


def test_list_by_chapter():
    code, out, _ = run("list", "--chapter", "4", "--json")
    assert code == 0 and all(i["id"].startswith("4.") for i in json.loads(out))


def test_show_json_fields():
    code, out, _ = run("show", "4.15", "--json")
    assert code == 0
    d = json.loads(out)
    for key in ("id", "title", "topic", "statement", "model", "params", "outputs", "formulas", "numeric_route",
                "hard_cases"):
        assert key in d
    theta0 = d["params"][0]
    assert theta0["name"] == "theta0" and theta0["unit"] == "rad"
    assert theta0["min"] == 0.0 and theta0["min_open"] is True and theta0["max"] == pytest.approx(math.pi / 2)
    assert {o["name"] for o in d["outputs"]} == {"theta_c", "omega_c"}


def test_show_text_mentions_statement_and_formulas():
    code, out, _ = run("show", "4.15")
    assert code == 0 and "ladder" in out and "θc" in out


def test_solve_json_is_the_contract_object():
    code, out, err = run("solve", "4.15", "--theta0", "90deg", "--json")
    assert code == 0, err
    d = json.loads(out)
    assert set(d) >= {"id", "title", "params", "quantities", "agree", "timing", "numeric_info"}
    assert d["params"] == {"theta0": pytest.approx(math.pi / 2), "l": 1.0, "g": 9.81}
    names = [q["name"] for q in d["quantities"]]
    assert names == ["theta_c", "omega_c"]
    for q in d["quantities"]:
        assert set(q) >= {"name", "unit", "analytic", "numeric", "abs_err", "rel_err", "tol", "agree"}
        assert q["agree"] is True
    assert d["agree"] is True
    assert set(d["timing"]) == {"analytic_s", "numeric_s"}
    assert set(d["numeric_info"]) >= {"method", "rtol", "nfev"}
    # sin(theta_c) = 2/3 from the upright start
    assert math.sin(d["quantities"][0]["numeric"]) == pytest.approx(2 / 3, rel=1e-9)


def test_solve_table_output():
    code, out, _ = run("solve", "4.15", "--theta0", "60 deg")
    assert code == 0
    assert "theta_c" in out and "agree" in out and "DOP853" in out


@pytest.mark.parametrize("args", [["--theta0", "pi/3"], ["-p", "theta0=60deg"], ["--theta0=60deg"],
                                  ["-p", "theta0=1.0471975511965976"]])
def test_equivalent_ways_to_give_a_value(args):
    code, out, _ = run("solve", "4.15", *args, "--method", "analytic", "--json")
    assert code == 0
    assert json.loads(out)["params"]["theta0"] == pytest.approx(math.pi / 3, rel=1e-15)


def test_dashes_and_underscores_reach_the_same_parameter():
    ex = next(e for e in registry.all_exercises().values() if any("_" in p.name for p in e.params))
    name = next(p.name for p in ex.params if "_" in p.name)
    value = ex.param_map[name].default
    outs = []
    for flag in (f"--{name}", f"--{name.replace('_', '-')}"):
        code, out, err = run("solve", ex.id, flag, repr(value), "--method", "analytic", "--json")
        assert code == 0, err
        outs.append(json.loads(out)["params"])
    assert outs[0] == outs[1]


def test_method_analytic_leaves_numeric_null():
    code, out, _ = run("solve", "4.15", "--method", "analytic", "--json")
    d = json.loads(out)
    assert code == 0
    assert all(q["numeric"] is None and q["agree"] is None for q in d["quantities"])
    assert d["timing"]["numeric_s"] is None and d["agree"] is None


@pytest.mark.parametrize(
    "args, names",
    [
        (["solve", "9.99"], "9.99"),
        (["solve", "4.15", "--bogus", "1"], "bogus"),
        (["solve", "4.15", "--theta0", "100deg"], "theta0"),
        (["solve", "4.15", "--theta0", "-1"], "theta0"),
        (["solve", "4.15", "--l", "abc"], "l"),
        (["solve", "4.15", "--l", "3s"], "l"),
        (["solve", "4.15", "--l", ""], "l"),
        (["solve", "4.15", "--l", "nan"], "l"),
        (["solve", "4.15", "--l", "inf"], "l"),
        (["solve", "4.15", "--l", "1e999"], "l"),
        (["solve", "4.15", "--l"], "l"),
        (["solve", "4.15", "--l", "1", "-p", "l=2"], "l"),
        (["solve", "4.15", "-p", "l"], "-p"),
        (["solve", "4.15", "--rtol", "1"], "rtol"),
        (["solve", "4.15", "--method", "magic"], "method"),
        (["show", "4.99"], "4.99"),
        (["check", "4.99"], "4.99"),
        (["frobnicate"], "frobnicate"),
    ],
)
def test_bad_input_is_one_line_exit_2(args, names):
    code, out, err = run(*args)
    assert code == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert names in lines[0] and "Traceback" not in err


def test_out_of_range_message_names_the_range():
    _, _, err = run("solve", "4.15", "--theta0", "100deg")
    assert "theta0" in err and "(0, 90] deg" in err


def test_check_passes_and_writes_junit(tmp_path):
    junit = tmp_path / "report.xml"
    code, out, _ = run("check", "4.15", "--hard", "--junit", str(junit))
    assert code == 0
    # the defaults and 4.15's two hard cases, the first of which (theta0 = 90 deg) is the defaults: 2 runs
    assert "2 passed, 0 failed" in out
    suite = ET.parse(junit).getroot().find("testsuite")
    assert suite.get("tests") == "2" and suite.get("failures") == "0"


def test_check_json():
    code, out, _ = run("check", "4.1", "--json")
    d = json.loads(out)
    assert code == 0 and d["ok"] is True and d["passed"] == 1 and d["failed"] == 0


def test_check_fails_loudly_when_a_solver_is_broken(monkeypatch, tmp_path):
    ex = registry.get("4.15")
    good = ex.numeric_solver

    def off_by_a_little(p, run_):
        values = good(p, run_)
        return {**values, "theta_c": values["theta_c"] * (1 + 1e-6)}

    monkeypatch.setattr(ex, "numeric_solver", off_by_a_little)
    junit = tmp_path / "report.xml"
    code, out, _ = run("check", "4.15", "--junit", str(junit))
    assert code == 1
    assert "FAIL" in out and "theta_c" in out
    assert ET.parse(junit).getroot().find("testsuite").get("failures") == "1"


def test_check_fails_when_a_solver_raises(monkeypatch):
    ex = registry.get("4.15")

    def broken(p, run_):
        raise ZeroDivisionError("on purpose")

    monkeypatch.setattr(ex, "numeric_solver", broken)
    code, out, err = run("solve", "4.15", "--json")
    assert code == 1
    d = json.loads(out)
    assert d["agree"] is False and "on purpose" in d["errors"][0]
    assert "Traceback" not in out + err


def test_undefined_and_nonfinite_values_become_null_with_a_note(monkeypatch):
    ex = registry.get("4.15")
    good = ex.analytic_solver
    monkeypatch.setattr(ex, "analytic_solver", lambda p: {**good(p), "omega_c": Undefined("no meaning here")})
    code, out, _ = run("solve", "4.15", "--json")
    q = json.loads(out)["quantities"][1]
    assert code == 1 and q["analytic"] is None and "no meaning here" in q["note"] and q["agree"] is False
    monkeypatch.setattr(ex, "analytic_solver", lambda p: {**good(p), "omega_c": math.inf})
    code, out, _ = run("solve", "4.15", "--json")
    assert code == 1 and json.loads(out)["quantities"][1]["analytic"] is None


def test_version():
    code, out, _ = run("--version")
    assert code == 0 and out.startswith("mech ")


@pytest.mark.parametrize("argv, heavy", [(["list"], ("scipy", "numpy", "matplotlib", "rich")),
                                         (["list", "--json"], ("scipy", "numpy", "matplotlib")),
                                         (["--help"], ("scipy", "numpy", "matplotlib", "rich")),
                                         (["show", "4.15"], ("scipy", "matplotlib"))])
def test_listing_and_help_import_nothing_heavy(argv, heavy):
    if argv == ["--help"]:  # nor the lazily loaded commands, nor the exercise machinery
        heavy = heavy + ("mech.cli.grading", "mech.cli.bench", "mech.cli.plot", "mech.cli.sweep", "mech.verification",
                         "mech.problems.spec")
    code = (
        "import sys\n"
        "from mech.cli.main import cli\n"
        f"cli.main({argv!r}, standalone_mode=False)\n"
        f"bad = sorted(m for m in sys.modules if m.split('.')[0] in {heavy!r} or m in {heavy!r})\n"
        "print(bad[:5], file=sys.stderr)\n"
        "sys.exit(1 if bad else 0)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


def test_lazy_commands_are_listed_with_their_own_first_sentence():
    """`mech --help` lists bench, grade, plot and sweep from summaries kept beside the group, without
    importing them: each summary must be its command's own first sentence."""
    import click

    from mech.cli.main import MechGroup, cli

    ctx = click.Context(cli)
    for name, (_module, _attr, summary) in MechGroup.LAZY.items():
        help_text = " ".join(cli.get_command(ctx, name).help.split("\n\n")[0].split())
        first = help_text.split(". ")[0].rstrip(".") + "."
        assert summary == first, name


# one exercise per numpy-only tool: DOP853 with events (4.15), dense output (4.23), roots (4.21, 5.11),
# bounded minimization (5.5), elliptic K and quadrature (4.9, 5.7), the generalized eigenproblem (4.11),
# Fourier-weighted quadrature (5.1)
SCIPY_FREE = ["4.9", "4.11", "4.15", "4.21", "4.23", "5.1", "5.4", "5.5", "5.7", "5.11"]


def test_solves_import_no_scipy():
    """A fresh `mech solve` of these pays no scipy import (0.3-0.9 s, most of the 1 s budget)."""
    code = (
        "import sys\n"
        "from mech.cli.main import cli\n"
        f"for ex_id in {SCIPY_FREE!r}:\n"
        "    try:\n"
        "        cli.main(['solve', ex_id], standalone_mode=False)\n"
        "    except SystemExit as exc:\n"
        "        assert not exc.code, (ex_id, exc.code)\n"
        "    bad = sorted(m for m in sys.modules if m.split('.')[0] == 'scipy')\n"
        "    if bad:\n"
        "        print(ex_id, bad[:5], file=sys.stderr)\n"
        "        sys.exit(1)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


def test_stiff_hard_cases_import_no_scipy():
    """The stiff hard cases (5.4's zeta = 1e3, 1e6; 5.1's delta = 120) go by the exact flow exp(A t), with
    their rerun at rtol/10: no scipy import (0.4-0.5 s in each pool worker of `mech check --hard`)."""
    code = (
        "import sys\n"
        "from mech.problems import registry\n"
        "cases = [('5.4', {'zeta': 1000.0, 'eps': 0.001, 't1': 500.0}), ('5.4', {'zeta': 1e6, 't1': 3e5}),\n"
        "         ('5.1', {'delta': 120.0, 'tau': 2.0, 'omega': 0.5})]\n"
        "for ex_id, given in cases:\n"
        "    ex = registry.get(ex_id)\n"
        "    p = ex.resolve(given)\n"
        "    ex.solve_numeric(p, None)\n"
        "    ex.solve_numeric(p, ex.default_rtol / 10)\n"
        "bad = sorted(m for m in sys.modules if m.split('.')[0] == 'scipy')\n"
        "sys.exit(f'scipy imported: {bad[:5]}' if bad else 0)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


def test_list_table_has_every_exercise_and_wraps_to_the_width():
    from mech.cli.listing import table_lines
    from mech.problems import registry

    entries = registry.index()
    for width in (80, 160):
        lines = table_lines(entries, width)
        assert lines[-1] == f"{len(entries)} exercises"
        assert max(len(line) for line in lines) <= width
        starts = [line.split()[0] for line in lines[2:-1] if line[:6].strip() and not line.startswith(("†", "+"))]
        # the exercises set for mech (from_book = false in their catalogue files) carry the mark
        assert starts == [e.id + ("" if e.from_book else "†") for e in entries]
    code, out, _ = run("list")
    assert code == 0 and out.rstrip().endswith(f"{len(entries)} exercises") and " 4.15 " in out


def test_numpy_warnings_are_kept_off_stderr_but_shown(monkeypatch):
    """A RuntimeWarning inside a numeric solver (an overflow in an intermediate) goes neither to stderr (it
    would break a script reading it) nor away: the JSON keeps it in numeric_info.fp_warnings and the table
    prints it under the cost line."""
    import numpy as np
    from click.testing import CliRunner

    from mech.cli.main import cli
    from mech.problems import registry

    ex = registry.get("4.15")
    good = ex.numeric_solver

    def overflows_on_the_way(p, run):
        with np.errstate(over="warn"):
            np.float64(1e308) * 10.0  # an intermediate that overflows and is not used
        return good(p, run)

    monkeypatch.setattr(ex, "numeric_solver", overflows_on_the_way)
    res = CliRunner().invoke(cli, ["solve", "4.15", "--no-verify", "--json"])
    assert res.exit_code == 0 and res.stderr == ""
    assert any("overflow" in w for w in json.loads(res.stdout)["numeric_info"]["fp_warnings"])
    res = CliRunner().invoke(cli, ["solve", "4.15", "--no-verify"])
    assert res.exit_code == 0 and res.stderr == "" and "floating-point warnings in the solve" in res.stdout
