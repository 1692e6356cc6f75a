"""A huge answers file under a memory limit: a one-line refusal naming the limit, never a traceback.

The big files run ``mech grade`` in a subprocess under RLIMIT_AS = 500 MB (``test_hostile.mech``): the
limit is the assertion.  The counts the limits are checked against are written here by construction
(so many ``[[answer]]`` tables, so many rows times exercises, so many characters of formulas).
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from click.testing import CliRunner

from mech.cli.main import cli
from mech.core import safeio
from mech.core.errors import BadInput
from mech.students import answers_files
from test_hostile import MEMORY_CAP, mech, one_line_error

ENTRY = '[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "asin(2/3*sin(theta0))" }\n'  # 76 characters


def _no_traceback(r):
    assert "Traceback" not in r.stderr and "SystemError" not in r.stderr and "Warning" not in r.stderr, r.stderr[-2000:]


def test_a_10_mb_class_file_under_500_mb_is_one_line(tmp_path):
    # the defect: ~130 000 formula entries (10 MB) were parsed, read and graded, and under 500 MB of
    # address space ended in a traceback (or a crash) after a minute; now the tables are counted first
    n = 10_000_000 // len(ENTRY)
    big = tmp_path / "big.toml"
    big.write_text(ENTRY * n)
    assert n > answers_files.MAX_ANSWERS and big.stat().st_size < safeio.MAX_FILE_BYTES
    r = mech("grade", str(big), limit_as=MEMORY_CAP, timeout=30)
    _no_traceback(r)
    assert r.returncode == 2 and r.stdout == "", (r.returncode, r.stdout[-500:])
    one_line_error(r, "big.toml", f"at most {answers_files.MAX_ANSWERS}", "[[answer]]")


def test_the_same_answers_written_inline_are_counted_after_parsing(tmp_path):
    # ``answer = [ {...}, ... ]`` has no [[answer]] header to count before parsing: counted once parsed
    item = '{ exercise = "4.15", expect = { theta_c = "asin(2/3*sin(theta0))" } },\n'
    n = answers_files.MAX_ANSWERS + 1
    big = tmp_path / "inline.toml"
    big.write_text("answer = [\n" + item * n + "]\n")
    r = mech("grade", str(big), "--json", limit_as=MEMORY_CAP, timeout=30)
    _no_traceback(r)
    assert r.returncode == 2 and r.stdout == "", r.returncode
    one_line_error(r, f"{n} answers (expected values) in {n} entries", f"at most {answers_files.MAX_ANSWERS}")


def test_entries_of_many_answers_are_counted_by_their_answers(tmp_path):
    # 4.1 has six outputs: 3334 entries answering all six are 20 004 answers, fewer tables than the limit
    # (20 000 entries of six answers each ran out of 500 MB after 73 s)
    six = ", ".join(f'{o} = "1"' for o in ("I_hoop_diam", "I_hoop_axis", "I_disk_diam", "I_disk_axis",
                                            "I_shell", "I_ball"))
    f = tmp_path / "six.toml"
    f.write_text(f'[[answer]]\nexercise = "4.1"\nexpect = {{ {six} }}\n' * 3334)
    r = mech("grade", str(f), limit_as=MEMORY_CAP, timeout=30)
    _no_traceback(r)
    assert r.returncode == 2 and r.stdout == "", r.returncode
    one_line_error(r, "20004 answers (expected values) in 3334 entries", f"at most {answers_files.MAX_ANSWERS}")


def test_a_csv_of_more_answers_than_the_limit_is_refused_before_reading_them(tmp_path):
    # 4100 rows of 5 answer columns: 20 500 answers, each row inside the CSV's own limits
    ids = ["4.1", "4.2", "4.3", "4.4", "4.5"]
    outs = ["I_hoop_diam", "I_rods_inplane", "I1", "I_axis", "T"]
    rows = ["student," + ",".join(f"{i}:{o}" for i, o in zip(ids, outs))]
    rows += [f"s{k},1,1,1,1,1" for k in range(4100)]
    f = tmp_path / "class.csv"
    f.write_text("\n".join(rows) + "\n")
    r = CliRunner().invoke(cli, ["grade", str(f)])
    assert r.exit_code == 2, r.output
    one_line_error(r, "4100 rows of 5 answer columns are 20500 answers", f"at most {answers_files.MAX_ANSWERS}")


def test_headers_are_counted_outside_strings_and_comments(tmp_path):
    f = tmp_path / "a.toml"
    # three tables; a multi-line string and a comment hold "[[answer]]" lines that are no tables
    f.write_text('[[answer]]\nx = """\n[[answer]]\n[[answer]]\n"""\n# [[answer]]\n[[answer]]\n  [[answer]]\n')
    data, _ = safeio.load_toml_text(f, "answers file", max_tables=(3, "[[answer]] entries"))
    assert len(data["answer"]) == 3
    with pytest.raises(BadInput, match=r"more than 2 \[\[answer\]\] entries; at most 2 are read"):
        safeio.load_toml_text(f, "answers file", max_tables=(2, "[[answer]] entries"))


def test_formulas_past_the_file_s_budget_refuse_the_file(tmp_path, monkeypatch):
    # four formulas of 26 characters each, all different (the factor differs): 3 x 26 = 78, the fourth passes 80
    monkeypatch.setattr(answers_files, "MAX_FORMULA_CHARS", 80)
    text = "".join(f'[[answer]]\nexercise = "4.15"\nexpect = {{ theta_c = "asin(2/3*sin(theta0))*{k}.00" }}\n'
                   for k in range(1, 5))
    assert len("asin(2/3*sin(theta0))*1.00") == 26
    f = tmp_path / "f.toml"
    f.write_text(text)
    r = CliRunner().invoke(cli, ["grade", str(f)])
    assert r.exit_code == 2, r.output
    one_line_error(r, "answer 4 (line 10)", "formulas pass 80 characters")


def test_a_formula_written_again_is_read_once_and_counted_once(tmp_path, monkeypatch):
    # 21 characters, 50 times: 1050 characters written, 21 parsed
    monkeypatch.setattr(answers_files, "MAX_FORMULA_CHARS", 100)
    f = tmp_path / "f.toml"
    f.write_text(ENTRY * 50)
    entries = answers_files.load_answers(str(f), strict=True)
    assert len(entries) == 50 and all(e.invalid is None for e in entries)


def test_memory_error_in_one_entry_is_that_entry_s_verdict(tmp_path, monkeypatch):
    from mech.students import answers

    judge = answers.judge

    def hungry(result, expectations):
        if any(e.text == "0.6154 rad" for e in expectations):
            raise MemoryError
        return judge(result, expectations)

    monkeypatch.setattr(answers, "judge", hungry)
    f = tmp_path / "f.toml"
    # 4.15 at its defaults: theta_c = asin(2/3*sin(theta0)) = 41.81 deg at theta0 = 90 deg (by hand)
    f.write_text('[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "41.81deg" }\n'
                 '[[answer]]\nexercise = "4.15"\nexpect = { theta_c = "0.6154 rad" }\n')
    r = CliRunner().invoke(cli, ["grade", str(f), "-j", "1"])
    assert r.exit_code == 1, r.output
    assert "1 of 2 answers right" in r.output and "not graded: out of memory" in r.output, r.output
    assert "internal error" not in r.output


@pytest.mark.parametrize("raised", [
    "SystemError('a C function returned a result with an exception set') from MemoryError()",
    "ImportError('/x/_random.so: failed to map segment from shared object')",
])
def test_memory_running_out_under_another_name_is_one_line(raised):
    code = ("import sys; import mech.cli.main as m; from mech import api\n"
            "def boom(*a, **k):\n"
            f"    raise {raised}\n"
            "api.grade_report = boom; sys.argv = ['mech', 'grade', 'x.toml']; m.main()")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    _no_traceback(r)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1 and lines[0].startswith("mech: error: out of memory"), r.stderr


def test_json_in_blocks_is_json_dumps():
    from mech.cli.grading import _json_parts

    obj = {"entries": [{"answer": k, "x": [k / 3, None, True, "θ\n"], "d": {}} for k in range(5000)],
           "ok": False, "e": []}
    assert "".join(_json_parts(obj)) == json.dumps(obj, indent=2, allow_nan=False)
    with pytest.raises(ValueError):
        _json_parts({"x": float("nan")})
