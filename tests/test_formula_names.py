"""What students write (issue 40, item 6): every name mech prints is a name in a formula; a decimal comma is
named; units spelled out are units; an unknown unit gets a did-you-mean.

The names walked are read off `mech show ID --json` and `mech show ID` (the text's parameter table) and the
header of `mech solve`, never listed by hand; their ASCII spellings are made here from the printed symbol
(Greek letters spelled out, subscript digits as digits, with and without an underscore). The values a
defined quantity must take are worked by hand from the printed formula (5.5: ω_d = (ω₀² − δ²)^½).
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from click.testing import CliRunner

import mech
from mech.cli.main import cli
from mech.core.units import ValueError_, to_si
from mech.problems import registry
from mech.students.formula_ast import FormulaError, parse_formula

IDS = [e.id for e in registry.index()]
GREEK = {"α": "alpha", "β": "beta", "γ": "gamma", "δ": "delta", "ε": "epsilon", "ζ": "zeta", "θ": "theta",
         "κ": "kappa", "λ": "lambda", "μ": "mu", "ν": "nu", "ξ": "xi", "ρ": "rho", "σ": "sigma", "τ": "tau",
         "φ": "phi", "χ": "chi", "ψ": "psi", "ω": "omega", "Ω": "Omega", "Δ": "Delta", "Θ": "Theta", "Φ": "Phi"}
SUBSCRIPT = {"₀": "0", "₁": "1", "₂": "2", "₃": "3", "₄": "4"}


def _run(*args):
    res = CliRunner().invoke(cli, list(args))
    assert res.exit_code == 0, res.output
    return res.output


def _ascii_spellings(symbol: str) -> set[str]:
    """``ω₀`` -> omega0, omega_0, ω0, ω_0 (the forms a student types for a printed symbol)."""
    base = "".join(GREEK.get(c, c) for c in symbol if c not in SUBSCRIPT)
    sub = "".join(SUBSCRIPT[c] for c in symbol if c in SUBSCRIPT)
    greek = "".join(c for c in symbol if c not in SUBSCRIPT)
    if not sub:
        return {base}
    return {base + sub, f"{base}_{sub}", greek + sub, f"{greek}_{sub}"}


def _value(ex, text, point):
    f = parse_formula(text, ex)
    env = {k: np.array([float(v)]) for k, v in point.items()}
    return float(f.evaluate(env)[0][0])


@pytest.mark.parametrize("ex_id", IDS)
def test_every_symbol_show_prints_is_a_name_in_a_formula(ex_id):
    ex = registry.get(ex_id)
    doc = json.loads(_run("show", ex_id, "--json"))
    table = _run("show", ex_id)
    point = {p["name"]: 1.0 + 0.1 * k for k, p in enumerate(doc["params"])}
    for p in doc["params"]:
        written = {p["name"], p["symbol"]} | (_ascii_spellings(p["symbol"]) if p["symbol"].isidentifier() else set())
        assert re.search(rf"^\s*{re.escape(p['name'])}\s+{re.escape(p['symbol'])}\s", table, re.M), p
        for text in sorted(written):
            try:
                f = parse_formula(text, ex)
            except FormulaError as exc:
                raise AssertionError(f"{ex_id}: {text!r} (printed for {p['name']}): {exc}") from None
            assert f.names == {p["name"]}, (ex_id, text, f.names)
            assert _value(ex, text, point) == point[p["name"]]
            assert _value(ex, f"2{text}", point) == 2 * point[p["name"]]  # a symbol right after a number


def test_the_symbols_in_solves_header_are_names():
    out = _run("solve", "5.5", "--method", "analytic")
    header = out.splitlines()[1]  # "ω₀ = 2764.6 rad/s, δ = 1.5 1/s, t₁ = 0.25 s"
    ex = registry.get("5.5")
    names = [part.split(" = ")[0].strip() for part in header.split(", ")]
    assert names == ["ω₀", "δ", "t₁"]
    assert [set(parse_formula(n, ex).names) for n in names] == [{"omega0"}, {"delta"}, {"t1"}]


def test_issue_examples_copied_from_show_are_right():
    # Q = omega0/(2 delta) is the definition of Q (5.5's statement); 1 - exp(-4 pi delta/omega_d) is the
    # energy lost over one period 2 pi/omega_d of the damped oscillation, E ~ exp(-2 delta t)
    for expect in ("Q=ω₀/(2δ)", "Q=omega_0/(2*delta)", "Q=ω0/(2 δ)",
                   "loss_per_cycle=1-exp(-4*pi*delta/omega_d)", "loss_per_cycle=-expm1(-4πδ/ω_d)"):
        res = CliRunner().invoke(cli, ["solve", "5.5", "--expect", expect])
        assert res.exit_code == 0, (expect, res.output)
    sol = mech.solve("5.5", expect={"Q": "ω₀/(2δ)"})
    assert sol.expected["Q"].match


def test_defined_quantities_take_the_value_their_printed_formula_gives():
    ex = registry.get("5.5")
    p = {"omega0": 5.0, "delta": 3.0, "t1": 1.0}
    for name in ("ω_d", "omega_d", "omegad"):
        assert _value(ex, name, p) == pytest.approx(4.0, rel=1e-15)  # sqrt(25 - 9)
    ex = registry.get("5.12")  # ε = a Ω/(2 l), ξ = Ω/2 − ω₀, ω₀ = (g/l)^(1/2)
    p = {"l": 2.0, "g": 8.0, "delta": 0.1, "a": 0.5, "Omega": 10.0}
    assert _value(ex, "ε", p) == pytest.approx(1.25, rel=1e-15)
    assert _value(ex, "omega0", p) == pytest.approx(2.0, rel=1e-15)
    assert _value(ex, "xi", p) == pytest.approx(3.0, rel=1e-15)
    assert _value(registry.get("5.13"), "ω₀", {"l": 2.0, "g": 8.0, "a": 0.1, "Omega": 1.0}) == pytest.approx(2.0)


def test_an_output_or_an_ambiguous_name_is_not_made_a_name():
    with pytest.raises(FormulaError, match="unknown name 'Q'"):  # 5.5's output Q is printed "Q = ω₀/(2δ)"
        parse_formula("Q", registry.get("5.5"))
    with pytest.raises(FormulaError, match="unknown name 'I_axis'"):  # a hoop's and a disk's: two values
        parse_formula("I_axis", registry.get("4.1"))
    # a quantity a formula defines never hides a unit: 5.7's m (the elliptic parameter) is still the metre
    assert parse_formula("2 m", registry.get("5.7")).names == frozenset()


# -- a decimal comma ------------------------------------------------------------------------------------

@pytest.mark.parametrize("text, said", [("0,00113 m", "write 0.00113: the decimal point is '.'"),
                                        ("2,5e3 m", "write 2.5e3: the decimal point is '.'"),
                                        ("1,500 m", "write 1.500 (or 1500)")])
def test_a_decimal_comma_is_named(text, said):
    with pytest.raises(ValueError_) as err:
        to_si(text, "m")
    assert said in str(err.value)


def test_a_decimal_comma_in_a_formula_and_in_answer_files(tmp_path):
    ex = registry.get("4.15")
    with pytest.raises(FormulaError, match=r"write 0\.5: the decimal point is '\.'"):
        parse_formula("asin(0,5*sin(theta0))", ex)
    assert parse_formula("atan2(1, 2)", ex).dim is not None  # a comma between arguments is one
    toml = tmp_path / "a.toml"
    toml.write_text('[[answer]]\nexercise = "4.31"\nexpect = { d_east = "0,00113 m" }\n')
    csv = tmp_path / "a.csv"
    csv.write_text('student,4.31:d_east\nann,"0,00113 m"\n')
    for path in (toml, csv):
        res = CliRunner().invoke(cli, ["grade", str(path), "--json"])
        assert res.exit_code == 1, res.output
        assert "write 0.00113: the decimal point is '.'" in res.output


# -- units spelled out ----------------------------------------------------------------------------------

@pytest.mark.parametrize("text, unit, si", [
    ("1.68 metres", "m", 1.68), ("1.68 meters", "m", 1.68), ("1 metre", "m", 1.0), ("2 sec", "s", 2.0),
    ("3 seconds", "s", 3.0), ("1 second", "s", 1.0), ("2 kilograms", "kg", 2.0), ("500 grams", "kg", 0.5),
    ("2 hours", "s", 7200.0), ("3 minutes", "s", 180.0), ("1.5 kilometres", "m", 1500.0),
    ("1.5 kilometers", "m", 1500.0), ("15 centimetres", "m", 0.15), ("15 centimeters", "m", 0.15),
    ("4 millimetres", "m", 0.004), ("4 millimeters", "m", 0.004), ("20 milliseconds", "s", 0.02),
    ("2 newtons", "N", 2.0), ("3 joules", "J", 3.0), ("1 hertz", "1/s", 1.0), ("30 degrees", "rad", math.pi / 6),
    ("2 radians", "rad", 2.0), ("9.81 metres/second^2", "m/s^2", 9.81)])
def test_spelled_out_units_are_units(text, unit, si):
    assert to_si(text, unit) == pytest.approx(si, rel=1e-15)


def test_spelled_out_units_in_expect_and_grade(tmp_path):
    res = CliRunner().invoke(cli, ["solve", "4.15", "--l", "1.68 metres", "--expect", "omega_c=2.42 1/second"])
    assert res.exit_code in (0, 1) and "error" not in res.output, res.output
    assert mech.solve("4.15", l="1.68 metres").params["l"] == 1.68


@pytest.mark.parametrize("typed, hint", [("metrs", "metres"), ("secnds", "seconds"), ("kilogramms", "kilograms")])
def test_an_unknown_unit_gets_a_did_you_mean(typed, hint):
    with pytest.raises(ValueError_) as err:
        to_si(f"1.68 {typed}", "m" if hint == "metres" else ("s" if hint == "seconds" else "kg"))
    assert f"did you mean {hint}?" in str(err.value) and "\n" not in str(err.value)
    with pytest.raises(FormulaError) as err:  # in a formula too, one line
        parse_formula(f"l {typed}", registry.get("4.15"))
    assert f"did you mean {hint}?" in str(err.value) and "\n" not in str(err.value)
