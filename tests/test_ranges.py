"""problems/ranges.py: floating-point ranges declared once per scale and enforced in one place."""

import math
import pathlib
import re

import pytest

from mech.problems import ranges
from mech.problems.spec import Params


class _Fake:
    def __init__(self):
        self.limits, self.checks = [], []

    def declare_limits(self, *texts):
        self.limits.extend(texts)

    def constraint(self, fn):
        self.checks.append(fn)
        return fn


def test_a_scale_is_summed_in_logs():
    # x^2 y at x = 1e200, y = 1e5: 10^405 by hand, where the product itself would overflow
    s = ranges.Scale("x^2 y", {"x": 2, "y": 1}, "the scale")
    p = Params({"x": 1e200, "y": 1e5})
    assert s.log10(p) == pytest.approx(405.0)
    assert s.refusal(p) == "x^2 y = 10^405 is outside [1e-300, 1e300], the floating-point range of the scale"
    assert s.refusal(Params({"x": 1.0, "y": 1e-300})) is None  # the edge itself is inside
    assert "= 0 is outside" in s.refusal(Params({"x": 0.0, "y": 1.0}))


def test_factors_by_value_and_by_log():
    s = ranges.Scale("M g l sin(theta)", {"M": 1}, "the torque", factor=lambda p: math.sin(p.theta),
                     log_factor=lambda p: -10.0)
    assert s.log10(Params({"M": 1e3, "theta": math.pi / 6})) == pytest.approx(3 + math.log10(0.5) - 10.0)


def test_declare_states_each_limit_and_refuses_the_first_scale_out_of_range():
    ex = _Fake()
    ranges.declare(ex, ranges.Scale("a", {"a": 1}, "the first", low=-10, high=10),
                   ranges.Scale("b", {"b": 1}, "the second", low=-math.inf, high=5))
    assert ex.limits == ["1e-10 <= a <= 1e10: the first within the floating-point range",
                         "b <= 1e5: the second within the floating-point range"]
    (check,) = ex.checks
    assert check(Params({"a": 1.0, "b": 1.0})) is None
    assert check(Params({"a": 1e11, "b": 1e6})).startswith("a = 10^11 is outside [1e-10, 1e10]")
    assert check(Params({"a": 1.0, "b": 1e6})).startswith("b = 10^6 is outside [0, 1e5]")


def test_no_exercise_writes_its_own_floating_range_refusal():
    """The guards are declared (ranges.Scale) and refused in one place: no exercise module returns a
    refusal of its own that names the floating-point range."""
    root = pathlib.Path(ranges.__file__).parent
    own = [f"{path.name}:{k + 1}" for path in sorted(root.glob("ch*/ex*.py"))
           for k, line in enumerate(path.read_text().splitlines())
           if re.search(r"return .*floating-point range", line)]
    assert own == []
