import os
import sys
from pathlib import Path

# Compiled modules go to pytest's own cache folder, never beside the sources.  Where the environment
# forbids bytecode (PYTHONDONTWRITEBYTECODE, as on the machine the suite is timed on), every worker and
# every command-line test's fresh Python compiled mech's modules and rewrote the test modules again: about
# 0.2 s for each `mech` a test starts and 7 s of collection per worker.  With the cache, a second run
# collects in a fraction of that.  The folder is .gitignore'd; deleting it only costs the next run.
# Installed code keeps its own: a prefix alone would also hide the compiled modules pip wrote beside numpy,
# scipy and sympy, and those of the standard library, and on a fresh clone every worker compiled those again
# (about 4.5 of the 12 CPU-s a worker collected in, measured with --collect-only -n 0).
_PYC = Path(__file__).resolve().parent.parent / ".pytest_cache" / "pyc"
if sys.dont_write_bytecode or os.environ.get("PYTHONDONTWRITEBYTECODE"):
    import importlib._bootstrap_external as _bootstrap  # the import system's own module, read per import

    # installed code: the environment's site-packages and the standard library (a repository's .venv too)
    _INSTALLED = tuple({os.path.join(p, "") for p in (sys.prefix, sys.exec_prefix, sys.base_prefix,
                                                      sys.base_exec_prefix)})
    _prefixed = _bootstrap.cache_from_source

    def _cache_from_source(path, debug_override=None, *, optimization=None):
        """Where the compiled form of ``path`` is read and written: beside the source (``__pycache__``, as
        the installers wrote it) for installed code, in the prefix for everything else."""
        if not sys.pycache_prefix or not path.startswith(_INSTALLED):
            return _prefixed(path, debug_override, optimization=optimization)
        name = os.path.basename(_prefixed(path, debug_override, optimization=optimization))
        return os.path.join(os.path.dirname(path), "__pycache__", name)

    _bootstrap.cache_from_source = _cache_from_source
    sys.pycache_prefix = str(_PYC)
    sys.dont_write_bytecode = False
    os.environ.pop("PYTHONDONTWRITEBYTECODE", None)
    os.environ["PYTHONPYCACHEPREFIX"] = str(_PYC)

import pytest
from hypothesis import settings

# What a test's fresh `mech` imports (installed code included: a child has the prefix from its environment
# only), compiled into the cache once by one child started beside the workers where the cache lacks it,
# as on a fresh clone: else the first tests that start `mech` each compiled it all, a wall-clock test
# among them (1-2 CPU-s each).
_WARM = "import numpy, rich.console, mech.cli.main, mech.verification.crosscheck, mech.students.classrun"
_warming = []


def pytest_configure(config):
    if hasattr(config, "workerinput") or "_prefixed" not in globals():
        return  # a pytest-xdist worker (the controller warms), or bytecode is written as usual
    import importlib.util
    import subprocess

    click = importlib.util.find_spec("click")
    if click is None or os.path.exists(_prefixed(click.origin)):
        return
    _warming.append(subprocess.Popen([sys.executable, "-c", _WARM], stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL))


def pytest_unconfigure(config):
    import subprocess

    for proc in _warming:
        try:
            proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


# property tests are deterministic: the same examples on every run and every machine
settings.register_profile("mech", derandomize=True, database=None)
settings.load_profile("mech")

# The 8 s budget of a solve is a promise to users on an idle 2-core machine, measured by scripts/draws.py
# over random draws; tests judge answers, and a CI runner may be slower or shared, so a test's solves get
# more time.  The budget's own tests pass their budget explicitly.
os.environ.setdefault("MECH_BUDGET_S", "30")

# The suite runs one pytest-xdist worker per core, so a cross-check's rerun forked beside its solve (the
# second core for one solve: crosscheck.PARALLEL_VERIFY) only competes with the other worker, and forking a
# pytest worker (numpy, scipy, sympy and matplotlib mapped) costs more than the rerun saves: the suite took
# 269 CPU-s with the forks and 243 without (sys time 20.6 -> 5.7 s).  The forked rerun's own tests force it
# (test_parallel_verify, test_check_pool).
os.environ.setdefault("MECH_SERIAL_VERIFY", "1")

# Tables are read by tests as piped output at mech's own piped width; a terminal, a CI runner or a
# pytest-xdist worker may export a narrower COLUMNS.  Tests of stacking and narrow widths set their own.
os.environ.pop("COLUMNS", None)

from mech.problems import registry


@pytest.fixture(scope="session")
def exercises():
    return registry.all_exercises()


def solve_both(ex_id: str, rtol: float | None = None, **given):
    """Analytic values and numeric values of one exercise at the given parameters (SI)."""
    ex = registry.get(ex_id)
    p = ex.resolve(given)
    numeric, run = ex.solve_numeric(p, rtol)
    return ex.solve_analytic(p), numeric, run


def claimed_error(ex, run, name: str, value: float) -> float:
    """A numeric output's error bar as the solver claims it (``run.claim``, else the exercise's default
    ``tol_factor * rtol``): what the cross-check reports as numeric_err, for tests that call a solver
    directly."""
    rel, abs_ = run.claims.get(name, (None, None))
    rel = ex.tol_factor * run.rtol if rel is None else rel
    return rel * abs(value) + (abs_ or 0.0)


def processes_with(marker: str) -> list[int]:
    """The pids whose command line holds ``marker`` (Linux /proc)."""
    import os

    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/cmdline", "rb") as fh:
                    if marker.encode() in fh.read():
                        found.append(int(entry))
            except OSError:
                continue
    return found


def killed_leaves_nothing(script: str, ready: str, sig: str, wait_children_s: float = 20.0) -> list[int]:
    """Run ``script`` in a fresh Python (its argv tagged with a unique marker), wait for its line ``ready``
    and for a child of it to exist, send it ``sig``, and return what still runs 2 s after it died (the
    survivors are then killed).  The children are looked for every 50 ms: once none is left there is
    nothing to wait for (a child that outlives its parent still runs at 2 s and is returned)."""
    import os
    import signal
    import subprocess
    import sys
    import time
    import uuid

    marker = f"mech-orphan-probe-{uuid.uuid4().hex}"
    proc = subprocess.Popen([sys.executable, "-c", script, marker], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == ready
        deadline = time.monotonic() + wait_children_s
        while len(processes_with(marker)) < 2 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert len(processes_with(marker)) >= 2, "no child process was running"
        proc.send_signal(getattr(signal, sig))
        proc.wait(timeout=10)
        gone = time.monotonic() + 2.0
        while processes_with(marker) and time.monotonic() < gone:
            time.sleep(0.05)
        return processes_with(marker)
    finally:
        if proc.poll() is None:
            proc.kill()
        for pid in processes_with(marker):
            os.kill(pid, signal.SIGKILL)


def personal_answer(student: str, ex_id: str, params: dict, expect: dict) -> str:
    """One ``[[answer]]`` of a class file: a student's own parameters (each value's exact repr, quoted) and
    the formulas or numbers they expect."""
    given = ", ".join(f'{k} = "{v!r}"' for k, v in params.items())
    wants = ", ".join(f'{k} = "{v}"' for k, v in expect.items())
    return f'[[answer]]\nstudent = "{student}"\nexercise = "{ex_id}"\nparams = {{ {given} }}\nexpect = {{ {wants} }}\n'


def mech_cli(*args, env=None):
    """``mech ARGS`` in this process through click's runner, as a ``subprocess.CompletedProcess`` (exit code,
    standard output, standard error): for tests of what a command prints and exits with, where a fresh
    Python (0.4-1 CPU-s of start-up each) is not what is tested.  What a fresh process would add on standard
    error is added here too: an exception the command lets out, printed as Python prints it, and each warning
    it raises under Python's default filters."""
    import subprocess
    import traceback
    import warnings

    from click.testing import CliRunner

    from mech.cli.main import cli

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        for quiet in (DeprecationWarning, PendingDeprecationWarning, ImportWarning, ResourceWarning):
            warnings.filterwarnings("ignore", category=quiet)
        res = CliRunner().invoke(cli, [str(a) for a in args], env=env)
    err = res.stderr
    if res.exception is not None and not isinstance(res.exception, SystemExit):
        err += "".join(traceback.format_exception(res.exception))
    err += "".join(warnings.formatwarning(w.message, w.category, w.filename, w.lineno) for w in caught)
    return subprocess.CompletedProcess(list(args), res.exit_code, res.stdout, err)


# The longest tests first.  pytest-xdist deals the tests out in the order collected, so a long test collected
# late keeps one worker busy at the end while the other has nothing left to do.  CPU-seconds of each, measured
# with a per-test CPU timer on the 2-core machine (a test not named here keeps its place, after these).
FIRST = {
    "test_hostile_formulas.py::test_property_hidden_slips_are_wrong_and_right_formulas_right": 11.9,
    "test_exact_grading.py::test_planted_errors_behind_zero_slope_cancellation_and_oscillation_are_wrong": 5.1,
    "test_fuzz.py::test_fuzz_solve_arguments": 4.5,
    "test_exact_grading.py::test_next_order_formula_of_5_9_is_right": 4.0,
    "test_chart.py::test_batched_points_match_single_cross_checks": 3.7,
    "test_time_decides_nothing.py::test_the_command_with_its_table_ends_soon_after_the_budget": 3.4,
    "test_time_decides_nothing.py::test_grade_budget_holds_on_5000_formula_entries": 3.3,
    "test_grade_speed.py::test_batched_and_pooled_grading_give_the_verdicts_of_one_by_one": 2.8,
    "test_ex5_10.py::test_numeric_beat_against_slip_times_of_a_long_simulation": 2.4,
    "test_fuzz.py::test_out_of_bounds_values_are_refused_with_the_range": 2.2,
    "test_hostile.py::test_a_failed_100000_point_batched_sweep_in_bounded_memory": 2.1,
    "test_plot.py::test_cli_writes_svg_and_pdf_by_suffix": 2.0,
    "test_hostile_formulas.py::test_api_raises_bad_input_for_every_bad_argument": 2.0,
    "test_check_pool.py::test_pooled_and_serial_checks_agree_to_the_bit": 2.0,
    "test_chart.py::test_5_13_slow_frequencies_against_radau": 2.0,
    "test_assign_hostile.py::test_any_argument_gives_bad_input_or_a_valid_class": 2.0,
    "test_sizes.py::test_no_function_over_100_lines_outside_tests": 1.9,
    "test_hostile.py::test_batched_sweep_json_memory_does_not_grow_with_the_points": 1.9,
    "test_judge.py::test_solve_check_sweeps_and_grade_give_the_same_verdicts": 1.8,
    "test_coin_batched.py::test_the_turn_agrees_with_the_declared_motions_timed_turn": 1.8,
    "test_ex5_12.py::test_stationary_swing_against_long_simulation": 1.8,
    "test_one_rule.py::test_a_judged_quantity_is_built_in_one_place": 1.7,
    "test_hostile_formulas.py::test_cache_is_bounded_in_bytes": 1.7,
    "test_sizes.py::test_no_exercise_module_over_450_lines": 1.7,
    "test_fuzz.py::test_fuzz_any_command_line": 1.6,
    "test_api.py::test_grade_bench_and_plot_from_python": 1.6,
    # 49 figures of 0.4-0.7 CPU-s each: collected late, they were dealt out as one run at the end, and in two
    # whole-suite runs one worker drew the last 18 CPU-s of them while the other had ended
    "test_plot.py::test_default_figure_of_every_exercise": 0.6,
}


def pytest_collection_modifyitems(config, items):
    """The tests in ``FIRST`` before the others, longest first (a stable sort: the rest keep their order)."""
    items.sort(key=lambda item: -FIRST.get(item.nodeid.rsplit("/", 1)[-1].split("[", 1)[0], 0.0))


# -- parsed sources, shared by the tests that walk the tree (suiteC) -----------------------------------------

def parsed(path):
    """The syntax tree of the source file at ``path``, parsed once per process: the size limits, the import
    loops, the twins and the one-rule tests walk the same modules (about 0.3 CPU-s a parse of the tree).
    Callers only read it.  Keyed by the file's size and time, so a file rewritten during the run is read
    again."""
    st = os.stat(path)
    return _parsed(str(path), st.st_mtime_ns, st.st_size)


def _parsed(path, mtime_ns, size):
    import ast

    key = (path, mtime_ns, size)
    if key not in _PARSED:
        with open(path, encoding="utf-8") as fh:
            source = fh.read()
        _PARSED[key] = (source, ast.parse(source))
    return _PARSED[key][1]


def parsed_source(path):
    """The text ``parsed(path)`` was parsed from."""
    parsed(path)
    st = os.stat(path)
    return _PARSED[str(path), st.st_mtime_ns, st.st_size][0]


_PARSED: dict = {}
