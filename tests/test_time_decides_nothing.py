"""Time decides nothing (issue 39, items 4, 8 and 9): the limits inside a solve or a check count work, so a
grade and an assignment are the same on a slow or busy machine as on an idle one; only the command's own
``--budget`` stops grading, what it did not reach is not graded, and it holds within 0.2 s; no message
quotes a source path, a raw warning or a traceback.

The slow machine is a clock that runs 20 times fast (``time.monotonic`` and ``time.perf_counter``): every
second of work then looks like 20.  Under the old wall-clock budget of a solve (8 s) a 5.8 entry of 1.3 s
idle ran out of time and was "cannot judge"; an assignment redrew its variants."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest

from mech.core import budget


def _slow_clock(monkeypatch, factor: float = 20.0) -> None:
    """Make ``time.monotonic`` and ``time.perf_counter`` run ``factor`` times fast from now on."""
    real_mono, real_perf = time.monotonic, time.perf_counter
    m0, p0 = real_mono(), real_perf()
    monkeypatch.setattr(time, "monotonic", lambda: m0 + factor * (real_mono() - m0))
    monkeypatch.setattr(time, "perf_counter", lambda: p0 + factor * (real_perf() - p0))


# -- the budget counts work --------------------------------------------------------------------------------

def test_a_work_limit_stops_at_the_same_count_at_any_speed(monkeypatch):
    """``limit(work=N)``: N units pass, the next raises OutOfWork, whatever the clock says."""
    def run():
        n = 0
        with pytest.raises(budget.OutOfWork) as caught:
            with budget.limit(work=1000, what="a test loop"):
                while True:
                    budget.check("a unit")
                    n += 1
                    time.sleep(0) if n % 100 else None
        return n, str(caught.value)

    idle = run()
    _slow_clock(monkeypatch, 1000.0)
    assert run() == idle
    assert idle[0] == 1000 and "work budget of 1,000 units" in idle[1]


def test_only_a_wall_clock_of_ones_own_stops_by_time(monkeypatch):
    """``limit(seconds)`` still stops a command (OutOfTime); nested work limits keep the least work left."""
    with pytest.raises(budget.OutOfTime):
        with budget.limit(0.05, what="a command"):
            while True:
                budget.check("a unit")
    with budget.limit(work=10):
        with budget.limit(work=1000):
            with pytest.raises(budget.OutOfWork):
                for _ in range(11):
                    budget.check()


# -- a class graded on a slow machine ----------------------------------------------------------------------

CLASS = """
[[answer]]
student = "ann"
exercise = "5.8"
params = { delta = "0.001 1/s", f0 = "0.0008 m/s^2" }
expect = { A_max = "0.04 m", xi_peak = "0.8 rad/s" }

[[answer]]
student = "bob"
exercise = "5.8"
params = { delta = "0.001 1/s", f0 = "0.0008 m/s^2" }
expect = { A_max = "0.05 m" }

[[answer]]
student = "cy"
exercise = "4.15"
params = { theta0 = "60deg" }
expect = { theta_c = "asin(2/3*sin(theta0))", omega_c = "2.91 rad/s" }
"""


def _verdicts(path) -> list:
    from mech.students.classrun import grade_file

    report = grade_file(str(path), total_s=3000, jobs=1)
    return [(e.student, j.name, j.cell, j.verdict) for e in report.entries for j in e.judgements]


def test_a_class_file_gets_the_same_verdicts_on_a_slow_machine(tmp_path, monkeypatch):
    """5.8 at delta = 0.001/s, f0 = 0.0008 m/s^2 (1.3 s idle, a hard case) and a formula, graded idle and
    with the clock 20x fast: the same verdicts (the old 8 s budget of a solve made the 5.8 entries
    "cannot judge" on the slow clock).  The verdicts themselves: A_max = f0/(2 omega0 delta) = 0.04 m by
    hand at leading order, right; 0.05 m wrong."""
    monkeypatch.setenv("MECH_BUDGET_S", "8")  # a user's (the suite's conftest gives solves 30 s)
    f = tmp_path / "class.toml"
    f.write_text(CLASS)
    idle = _verdicts(f)
    states = {(s, n): st.value for s, n, st, _ in idle}
    assert states[("ann", "A_max")] == "right" and states[("bob", "A_max")] == "wrong"
    assert states[("cy", "theta_c")] == "right"
    _slow_clock(monkeypatch)
    assert _verdicts(f) == idle


# -- an assignment drawn on a slow machine -----------------------------------------------------------------

def test_an_assignment_is_the_same_bytes_on_a_slow_machine(tmp_path, monkeypatch):
    """``mech assign 5.8 --n 2 --seed 2026``, idle and with the clock 20x fast: the same handout, answers
    file and key, byte for byte (the old 8 s budget of a solve redrew the variants that ran out of it)."""
    from mech.students.assign import assign

    monkeypatch.setenv("MECH_BUDGET_S", "8")  # a user's (the suite's conftest gives solves 30 s)

    def files(out):
        assign(["5.8"], seed=2026, out=str(out), n=2, over={"delta": "0.001:0.0011"}, jobs=1)
        return {str(p.relative_to(out)): p.read_bytes() for p in sorted(Path(out).rglob("*")) if p.is_file()}

    idle = files(tmp_path / "idle")
    assert "key.json" in idle and len(idle) >= 3
    _slow_clock(monkeypatch)
    assert files(tmp_path / "slow") == idle


# -- the command's budget holds ----------------------------------------------------------------------------

def test_grade_budget_holds_on_5000_formula_entries(tmp_path):
    """5000 formula entries with ``points = 10000`` under a budget of 1 s: grading ends within 1 s + 0.2 s
    (here 1.2 s more, for a loaded test machine; it took 115 s for 20 000 entries before), and every
    entry it did not reach is not graded (never wrong)."""
    from mech.students.answers_files import load_answers
    from mech.students.cells import State
    from mech.students.classrun import grade

    f = tmp_path / "big.toml"
    f.write_text("\n".join(f'[[answer]]\nstudent = "s{i}"\nexercise = "4.15"\npoints = 10000\n'
                           f'expect = {{ theta_c = "asin({2 * (i + 1)}/{3 * (i + 1)}*sin(theta0))" }}\n'
                           for i in range(5000)))
    entries = load_answers(str(f))  # reading is not the budget's
    t0 = time.perf_counter()
    grade(entries, 1.0, jobs=1)
    took = time.perf_counter() - t0
    assert took < 1.0 + 0.2 + 1.2, took
    states = [j.cell for e in entries for j in e.judgements]
    assert len(states) == 5000
    assert states.count(State.NOT_GRADED) >= 4900
    assert set(states) <= {State.NOT_GRADED, State.RIGHT}  # 2k/3k is 2/3 exactly: every formula is right, if reached
    reasons = {j.verdict for e in entries for j in e.judgements if j.cell is State.NOT_GRADED}
    assert any("total budget of 1 s ran out" in r for r in reasons)


# -- no source paths, no raw warnings ----------------------------------------------------------------------

EXTREMES = """
[[answer]]
exercise = "5.1"
params = { tau = "1e308 s" }
expect = { G = "0 s/kg", G_minus = "0 s/kg" }

[[answer]]
exercise = "5.1"
params = { tau = "1e308 s" }
expect = { G = "exp(-delta*tau)*sin(omega0*tau)/(m*omega0)" }

[[answer]]
exercise = "4.15"
params = { theta0 = "1e-300 rad" }
expect = { theta_c = "exp(1e308/theta0)", omega_c = "sqrt(-1/theta0) * 1 rad/s" }

[[answer]]
exercise = "5.8"
params = { omega0 = "1e150 rad/s", delta = "1e-150 1/s", f0 = "1e-300 m/s^2" }
expect = { A_max = "1e308 m" }

[[answer]]
exercise = "5.11"
params = { mu = "0.9999999999999999" }
expect = { threshold = "1" }
"""


@pytest.mark.parametrize("extra", [[], ["--json"]])
def test_extreme_entries_quote_no_source_path_warning_or_traceback(tmp_path, extra):
    f = tmp_path / "extremes.toml"
    f.write_text(EXTREMES)
    r = subprocess.run([sys.executable, "-m", "mech.cli.main", "grade", str(f), *extra], capture_output=True,
                       text=True, timeout=300, cwd=tmp_path)
    out = r.stdout + r.stderr
    assert r.returncode in (0, 1), out[-2000:]
    for bad in (".py", "Warning", "Traceback"):
        assert bad not in out, (bad, out[-3000:])


def test_the_command_with_its_table_ends_soon_after_the_budget(tmp_path):
    """``mech grade --budget 1`` on 5000 formula entries with ``points = 10000``: the whole command (start-up,
    reading, grading, a table of 5000 rows and 5000 students' lines) in 3.4 s idle on the 2-core machine
    (8.8 s before the table of many rows was laid out without rich's measuring and the unit hint became
    lazy); held here to 8 s for a loaded test machine.  Every row is printed, none graded wrong."""
    import subprocess
    import sys
    from pathlib import Path

    f = tmp_path / "big.toml"
    f.write_text("\n".join(f'[[answer]]\nstudent = "s{i}"\nexercise = "4.15"\npoints = 10000\n'
                           f'expect = {{ theta_c = "asin({2 * (i + 1)}/{3 * (i + 1)}*sin(theta0))" }}\n'
                           for i in range(5000)))
    mech = str(Path(sys.executable).with_name("mech"))
    t0 = time.perf_counter()
    out = subprocess.run([mech, "grade", str(f), "--budget", "1"], capture_output=True, text=True, timeout=60)
    took = time.perf_counter() - t0
    assert out.returncode == 1 and "Traceback" not in out.stderr, out.stderr
    assert took < 8.0, took
    last = out.stdout.strip().splitlines()[-1]
    assert "0 wrong" in last and "(5000 entries)" in last, last
    assert sum(line.startswith("s") and ": " in line for line in out.stdout.splitlines()) == 5000
