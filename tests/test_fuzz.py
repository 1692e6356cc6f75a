"""Property-based fuzzing of the command line: whatever is typed, the answer is either a
correct, complete result or exit status 2 with one line naming the problem; never a
traceback, never NaN or Infinity in the JSON, never a half-printed table.

The invocations use ``--method analytic`` so that thousands run in seconds; the numeric
side is exercised over random in-bounds parameters in test_bounds.py.
"""

import json
import math

from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mech.cli.main import cli
from mech.problems import registry

EXERCISES = list(registry.all_exercises().values())
IDS = [ex.id for ex in EXERCISES]
UNITS = ["", "deg", "rad", "m", "cm", "mm", "km", "kg", "g", "s", "ms", "min", "h", "day", "Hz", "rpm", "N",
         "m/s", "m/s^2", "kg*m^2", "1/s", "furlong", "%"]

numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1e3, max_value=1e3),
    st.sampled_from([0.0, -0.0, 1e-320, 1e308, -1e308, 1e-12, 1.0, math.pi / 2, 90.0]),
)
value_texts = st.one_of(
    st.builds(lambda x, u, sp: f"{x!r}{' ' if sp else ''}{u}", numbers, st.sampled_from(UNITS), st.booleans()),
    st.sampled_from(["", " ", "nan", "inf", "-inf", "pi", "pi/3", "2*pi", "1e999", "1/0", "--", "-p", "=", "((1)",
                     "1e-3", "2pi rad", "0x10", "1_000", "١٢", "\x00", "90°", "5 m s", "3 m + 2 s"]),
    st.text(max_size=12),
)


def _name_for(ex, data):
    names = [p.name for p in ex.params]
    return data.draw(st.one_of(st.sampled_from(names), st.sampled_from([n.replace("_", "-") for n in names]),
                               st.text(alphabet="abcxyz_-0", min_size=1, max_size=6)))


def _check_outcome(result, as_json: bool):
    assert result.exit_code in (0, 1, 2), (result.exit_code, result.output)
    out, err = result.stdout, result.stderr
    # a traceback is judged by its shape, never by a word the typed input may contain (hypothesis once
    # drew "Traceback" as an rtol, which mech echoes): Python's header line on a line of its own, and on
    # standard error nothing but mech's own one-line messages
    assert not any(line == "Traceback (most recent call last):" for line in (out + err).splitlines())
    assert all(line.startswith("mech: ") for line in err.splitlines() if line.strip()), err
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    if result.exit_code == 2:
        assert out == ""
        assert len(err.strip().splitlines()) == 1, err
        assert err.startswith("mech: error: ")
    else:
        assert err == "" or "internal error" not in err
        if as_json:
            json.loads(out, parse_constant=lambda c: (_ for _ in ()).throw(AssertionError(f"{c} in JSON")))


@settings(max_examples=800, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_fuzz_solve_arguments(data):
    ex = data.draw(st.sampled_from(EXERCISES))
    args = ["solve", data.draw(st.one_of(st.just(ex.id), st.sampled_from(IDS), st.text(max_size=5)))]
    for _ in range(data.draw(st.integers(0, 4))):
        name, text = _name_for(ex, data), data.draw(value_texts)
        form = data.draw(st.integers(0, 2))
        if form == 0:
            args += [f"--{name}", text]
        elif form == 1:
            args += [f"--{name}={text}"]
        else:
            args += ["-p", f"{name}={text}"]
    if data.draw(st.booleans()):
        args += ["--rtol", data.draw(value_texts)]
    args += ["--method", "analytic", "--json"]
    result = CliRunner().invoke(cli, args)
    asked_help = any(a in ("-h", "--help") for a in args)  # drawn as an id: help is printed, not JSON
    _check_outcome(result, as_json=not asked_help)
    if result.exit_code != 2 and not asked_help:
        d = json.loads(result.stdout)
        # accepted input must give an answer: an analytic solver that fails on in-bounds values is a defect
        assert result.exit_code == 0, (args, d.get("errors"), [q.get("note") for q in d["quantities"]])
        assert [q["name"] for q in d["quantities"]] == [o.name for o in registry.get(d["id"]).outputs]
        for q in d["quantities"]:
            assert q["analytic"] is None or math.isfinite(q["analytic"])
            assert q["analytic"] is not None or "note" in q


@settings(max_examples=600, deadline=None)
@given(args=st.lists(st.one_of(st.sampled_from(["list", "show", "solve", "check", "--json", "--hard", "--chapter",
                                                "4", "5", "6", "-p", "--help", "--version", "--junit", "4.15",
                                                "4.1", "x=1", "--theta0", "--method", "numeric", "--rtol"]),
                               st.text(max_size=6)), max_size=5))
def test_fuzz_any_command_line(args):
    if "check" in args and not any(a in IDS for a in args):
        return  # a full check of every exercise is covered by test_check_all; keep fuzzing fast
    if "solve" in args or "check" in args:
        args = args + ["--method", "analytic"] if "solve" in args else args
    result = CliRunner().invoke(cli, args)
    if "check" in args and result.exit_code != 2:
        return
    _check_outcome(result, as_json="--json" in args and "--help" not in args and "--version" not in args)


@settings(max_examples=800, deadline=None)
@given(data=st.data())
def test_out_of_bounds_values_are_refused_with_the_range(data):
    ex = data.draw(st.sampled_from(EXERCISES))
    bounded = [p for p in ex.params if p.min is not None or p.max is not None]
    if not bounded:
        return
    p = data.draw(st.sampled_from(bounded))
    if p.min is not None and data.draw(st.booleans()):
        value = p.min - abs(data.draw(st.floats(min_value=1e-6, max_value=1e6))) * max(1.0, abs(p.min))
    elif p.max is not None:
        value = p.max + abs(data.draw(st.floats(min_value=1e-6, max_value=1e6))) * max(1.0, abs(p.max))
    else:
        value = p.min - 1.0 * max(1.0, abs(p.min))
    result = CliRunner().invoke(cli, ["solve", ex.id, f"--{p.name}", repr(value), "--method", "analytic"])
    assert result.exit_code == 2, result.output
    assert p.name in result.stderr and "allowed" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1 and result.stdout == ""


def test_an_input_that_reads_traceback_is_not_taken_for_one():
    """The echo of typed text is not a traceback: the rule is the exit status and stderr's shape."""
    for args in (["solve", "4.15", "--rtol", "Traceback"], ["solve", "4.15", "--l", "Traceback (most"]):
        result = CliRunner().invoke(cli, args + ["--method", "analytic", "--json"])
        assert result.exit_code == 2
        _check_outcome(result, as_json=True)
