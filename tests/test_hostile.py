"""Hostile input and broken environments (issue 26): bounded memory, atomic writes, exit 2 for every bad
input, budgets that hold, safe echoes, COLUMNS.

The memory and file-size cases run ``mech`` in a subprocess under ``resource.setrlimit`` (RLIMIT_AS,
RLIMIT_FSIZE): the limit is the assertion.  The expected outcomes are the contract's (exit 2 and one
line naming the file, or the parameter, or the variable), not anything read back from mech.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import time

import pytest
from click.testing import CliRunner

from mech.cli.main import cli
from mech.problems import safeio
from mech.problems.errors import BadInput

MEMORY_CAP = 500 * 2**20  # the bound on any command's peak memory


def mech(*args, env=None, cwd=None, limit_as=None, limit_fsize=None, stdin=None, timeout=60, **popen):
    """``mech ARGS`` in a fresh interpreter, optionally under an address-space or a file-size limit."""
    code = textwrap.dedent(f"""
        import resource, sys
        if {limit_as!r}:
            resource.setrlimit(resource.RLIMIT_AS, ({limit_as!r}, {limit_as!r}))
        if {limit_fsize!r}:
            resource.setrlimit(resource.RLIMIT_FSIZE, ({limit_fsize!r}, {limit_fsize!r}))
        from mech.cli.main import main
        sys.argv = ['mech'] + {list(args)!r}
        main()
    """)
    full_env = {**os.environ, **(env or {})}
    streams = {"stdout": subprocess.PIPE, "stderr": subprocess.PIPE, **popen}
    return subprocess.run([sys.executable, "-c", code], text=True, env=full_env, cwd=cwd, timeout=timeout,
                          stdin=stdin, **streams)


def one_line_error(proc_or_result, *needles):
    err = proc_or_result.stderr if hasattr(proc_or_result, "stderr") else proc_or_result.output
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err[-2000:]
    assert lines[0].startswith("mech: error: "), lines[0][:300]
    assert "Traceback" not in err and "internal error" not in err
    for n in needles:
        assert n in lines[0], (n, lines[0][:300])
    return lines[0]


# -- echoes ------------------------------------------------------------------------------------------------

def test_shown_escapes_controls_and_cuts():
    assert safeio.shown("4.15\x1b[2J") == "4.15\\x1b[2J"
    assert safeio.shown("a\x1b]0;title\x07b") == "a\\x1b]0;title\\x07b"
    assert safeio.shown("x\u202ey") == "x\\u202ey"  # a right-to-left override would reorder the line
    long = "7" * 10_000_000
    out = safeio.shown(long)
    assert out == "7" * 80 + "..."


@pytest.mark.parametrize("args", [
    ["solve", "4.15\x1b[2J"],
    ["solve", "4.15", "--l", "1\x1b]0;pwned\x07"],
    ["solve", "4.15", "-p", "\x1b[31mred=1"],
    ["show", "\x9b2J"],
])
def test_no_control_character_reaches_the_terminal(args):
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 2
    line = one_line_error(r)
    assert not any(ord(c) < 32 or 0x7f <= ord(c) <= 0x9f for c in line), line


def test_a_huge_value_is_not_echoed_whole():
    big = "1" * 10_000_000
    r = CliRunner().invoke(cli, ["solve", "4.15", "--l", big])
    assert r.exit_code == 2
    assert len(one_line_error(r)) < 2100


# -- ids ---------------------------------------------------------------------------------------------------

def test_a_long_id_is_refused_without_a_hint_in_little_memory():
    r = mech("solve", "1" * 100_000, limit_as=MEMORY_CAP)
    assert r.returncode == 2
    line = one_line_error(r, "unknown exercise")
    assert "did you mean" not in line and len(line) < 300


def test_short_ids_still_get_their_hint():
    r = CliRunner().invoke(cli, ["solve", "4.150"])
    assert r.exit_code == 2 and "did you mean 4.15?" in r.output


# -- values ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("args", [
    ["solve", "4.15", "--l", "m^(0*1e999)"],
    ["solve", "4.15", "--l", "2 m^(1e999)"],
    ["solve", "4.15", "--expect", "theta_c=rad^(0*1e999)"],
    ["solve", "4.15", "--l", "m^100000"],
])
def test_a_non_finite_exponent_is_bad_input(args):
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 2, r.output
    one_line_error(r)


# -- the environment ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "-5", "0", "abc", "1e999"])
def test_budget_variable_must_be_finite_and_positive(value):
    r = CliRunner().invoke(cli, ["solve", "4.15"], env={"MECH_BUDGET_S": value})
    assert r.exit_code == 2
    one_line_error(r, "MECH_BUDGET_S")


def test_standard_output_full(tmp_path):
    with open("/dev/full", "w") as full:
        r = mech("solve", "4.15", stdout=full)
    assert r.returncode == 2
    one_line_error(r, "standard output")


def test_standard_output_closed():
    r = mech("check", "4.15", "--json", stdout=subprocess.DEVNULL,
             close_fds=True, pass_fds=(), preexec_fn=lambda: os.close(1))
    assert r.returncode == 2
    one_line_error(r, "standard output is closed")


def test_standard_output_ascii_only():
    r = mech("solve", "4.15", env={"PYTHONIOENCODING": "ascii"})
    assert r.returncode != 0
    one_line_error(r, "PYTHONIOENCODING")
    r = mech("solve", "4.15", "--json", env={"PYTHONIOENCODING": "ascii"})  # JSON is ASCII: it works
    assert r.returncode == 0 and json.loads(r.stdout)["id"] == "4.15"


@pytest.mark.parametrize("columns", ["0", "-3", "abc", "5", "59", ""])
def test_any_columns_prints_every_row(columns):
    wide = CliRunner().invoke(cli, ["solve", "4.15"], env={"COLUMNS": "200"})
    narrow = CliRunner().invoke(cli, ["solve", "4.15"], env={"COLUMNS": columns})
    assert wide.exit_code == narrow.exit_code == 0
    # the numbers of the wide table, every one of them, in the stacked or unset-width output
    import re

    numbers = set(re.findall(r"\d\.\d{6,}", wide.output))
    assert numbers and numbers <= set(re.findall(r"\d\.\d{6,}", narrow.output))
    assert safeio.columns({"COLUMNS": columns}) in (None, 60)


def test_columns_rules():
    assert safeio.columns({"COLUMNS": "5"}) == 60
    assert safeio.columns({"COLUMNS": "0"}) is None
    assert safeio.columns({"COLUMNS": "-1"}) is None
    assert safeio.columns({"COLUMNS": "x"}) is None
    assert safeio.columns({"COLUMNS": "120"}) == 120
    assert safeio.columns({}) is None


# -- files read --------------------------------------------------------------------------------------------

def test_read_text_refuses_devices_fifos_and_big_files(tmp_path):
    with pytest.raises(BadInput, match="not a regular file"):
        safeio.read_text("/dev/zero", "answers file")
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    t0 = time.monotonic()
    with pytest.raises(BadInput, match="not a regular file"):
        safeio.read_text(str(fifo), "answers file")
    assert time.monotonic() - t0 < 1
    with pytest.raises(BadInput, match="a directory"):
        safeio.read_text(str(tmp_path), "answers file")
    big = tmp_path / "big.toml"
    big.write_bytes(b"#" * (safeio.MAX_FILE_BYTES + 1))
    with pytest.raises(BadInput, match="at most"):
        safeio.read_text(str(big), "answers file")


@pytest.mark.parametrize("text, why", [
    ("a = " + "[" * 100_000 + "]" * 100_000, "nested deeper"),
    ("x." * 16_000 + "y = 1", "dotted key"),
    ("[" + "t." * 16_000 + "u]", "dotted key"),
    ("a = { b = " * 5000 + "1" + " }" * 5000, "nested deeper"),
    ("x = " + "9" * 5000, "malformed TOML"),
])
def test_toml_prescan_refuses_before_parsing(tmp_path, text, why):
    f = tmp_path / "a.toml"
    f.write_text(text)
    with pytest.raises(BadInput, match=why):
        safeio.load_toml(str(f), "answers file")


def test_toml_prescan_passes_ordinary_files(tmp_path):
    f = tmp_path / "a.toml"
    f.write_text("\n".join(f'k{i}.a.b = {i}' for i in range(200)) +
                 '\n# a.b.c.d\n[[answer]]\nexercise = "4.15"\nparams = { theta0 = "60deg" }\n'
                 'expect = { "theta_c" = "35.26 deg" }\nnote = """[[[[ {{{{ a.b.c.d.e.f """\n'
                 "v = [1.5, 2.5, 3.5]\n")
    data = safeio.load_toml(str(f))
    assert data["answer"][0]["exercise"] == "4.15" and data["k199"]["a"]["b"] == 199


@pytest.mark.parametrize("text, why", [
    ("[" * 100_000 + "]" * 100_000, "nested deeper"),
    ('{"a": ' + "9" * 5000 + "}", "malformed JSON"),
    ('{"a": NaN}', "malformed JSON"),
])
def test_json_prescan(tmp_path, text, why):
    f = tmp_path / "b.json"
    f.write_text(text)
    with pytest.raises(BadInput, match=why):
        safeio.load_json(str(f), "baseline")


def test_json_strings_do_not_count_as_nesting(tmp_path):
    f = tmp_path / "b.json"
    f.write_text(json.dumps({"note": "[" * 1000, "v": [[1]]}))
    assert safeio.load_json(str(f))["v"] == [[1]]


# -- files written -----------------------------------------------------------------------------------------

def test_atomic_write_keeps_the_old_file_on_failure(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("good\n")
    with pytest.raises(RuntimeError):
        with safeio.atomic_write(str(target)) as fh:
            fh.write("half")
            raise RuntimeError("boom")
    assert target.read_text() == "good\n"
    assert os.listdir(tmp_path) == ["out.txt"]  # the temporary file is gone
    with safeio.atomic_write(str(target)) as fh:
        fh.write("new\n")
    assert target.read_text() == "new\n" and os.listdir(tmp_path) == ["out.txt"]


@pytest.mark.parametrize("path, why", [("", "empty file name"), ("/nonexistent/x.xml", "no folder"),
                                       ("/dev/full", "not a regular file"), ("/dev/null", "not a regular file")])
def test_check_output_refuses(path, why):
    with pytest.raises(BadInput, match=why):
        safeio.check_output(path, "--junit")


def test_check_output_refuses_a_directory(tmp_path):
    with pytest.raises(BadInput, match="a directory"):
        safeio.check_output(str(tmp_path), "--trajectory")


def test_a_plot_path_is_refused_before_the_bench_runs(tmp_path):
    t0 = time.monotonic()
    r = CliRunner().invoke(cli, ["bench", "4.15", "--plot", "/nonexistent/b.png"])
    assert r.exit_code == 2 and time.monotonic() - t0 < 3
    one_line_error(r, "no folder")
