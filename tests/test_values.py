"""Value parsing: units, dimensions, pi arithmetic, and the Hz/rpm convention."""

import math

import pytest

from mech.core.units import ValueError_, to_si


@pytest.mark.parametrize(
    "text, unit, expected",
    [
        ("90deg", "rad", math.pi / 2),
        ("90 deg", "rad", math.pi / 2),
        ("90°", "rad", math.pi / 2),
        ("pi/3", "rad", math.pi / 3),
        ("2*pi", "rad", 2 * math.pi),
        ("2pi", "rad", 2 * math.pi),
        ("1e-3", "m", 1e-3),
        ("-2.5", "m", -2.5),
        ("15 cm", "m", 0.15),
        ("2.5km", "m", 2500.0),
        ("3 mm", "m", 3e-3),
        ("500 g", "kg", 0.5),
        ("2 min", "s", 120.0),
        ("1 day", "s", 86400.0),
        ("1.5 h", "s", 5400.0),
        ("20 ms", "s", 0.02),
        ("9.81 m/s^2", "m/s^2", 9.81),
        ("9.81 m/s**2", "m/s^2", 9.81),
        ("0.5 kg*m^2", "kg*m^2", 0.5),
        ("2 kg cm^2", "kg*m^2", 2e-4),
        ("3 N", "N", 3.0),
        ("3 kg*m/s^2", "N", 3.0),
        # angular frequency: a turn is 2 pi rad
        ("2Hz", "rad/s", 4 * math.pi),
        ("60 rpm", "rad/s", 2 * math.pi),
        ("1 rad/s", "rad/s", 1.0),
        ("5/s", "rad/s", 5.0),
        # a parameter in turns per second takes Hz and rpm as counts of turns
        ("2Hz", "1/s", 2.0),
        ("120 rpm", "1/s", 2.0),
        ("2 pi rad/s", "1/s", 1.0),
        ("(1+1)*3", "1", 6.0),
        ("2^3", "1", 8.0),
    ],
)
def test_conversions(text, unit, expected):
    assert to_si(text, unit) == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize(
    "text, unit",
    [("3s", "m"), ("2 kg", "m"), ("90deg", "1"), ("1 m", "rad"), ("abc", "m"), ("", "m"), ("nan", "m"),
     ("inf", "m"), ("1e999", "m"), ("1/0", "m"), ("2^m", "1"), ("(1", "m"), ("1)", "m"), ("3 m + 2 s", "m"),
     ("$", "m"), ("10^400", "1"), ("((((((((((((((((((((((((((((((((((((((((1", "1")],
)
def test_errors(text, unit):
    with pytest.raises(ValueError_):
        to_si(text, unit)


@pytest.mark.parametrize("text, unit", [("1.2.3", "m"), ("1.5.5cm", "m"), ("2 3", "m"), ("15cm 2", "m"),
                                        ("1.2.3", "rad"), ("(1+1)3", "1"), ("pi 2", "1")])
def test_two_numbers_side_by_side_are_refused_not_multiplied(text, unit):
    """`1.2.3` once became 1.2 * 0.3 = 0.36: a number next to a number needs an operator."""
    with pytest.raises(ValueError_, match="side by side|right after"):
        to_si(text, unit)


@pytest.mark.parametrize("text, unit, expected", [("2 * 3", "m", 6.0), ("15cm*2", "m", 0.3), ("2(3)", "1", 6.0),
                                                  ("3 pi", "1", 3 * math.pi)])
def test_products_with_an_operator_or_a_name_still_work(text, unit, expected):
    assert to_si(text, unit) == pytest.approx(expected, rel=1e-15)
