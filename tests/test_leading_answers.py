"""Answers on leading-order outputs and declared approximations (issue 23 items 4 and 5).

Hand values:
* 5.11 at its defaults (omega0 = 10, delta = 0.05, mu = 0.05): eps = mu omega0/4 = 0.125, so the
  leading-order zone edge is xi_hi = (eps^2 - delta^2)^(1/2) = 0.013125^(1/2) = 0.114564.
* 5.9 at mu = 10 (omega0 = 3): mu/omega0 = 3.3, past the expansion's range.  The van der Pol frequency
  falls from omega0 (small mu) towards the relaxation limit 2 pi omega0 / ((3 - 2 ln 2) e + 7.014 e^(-1/3))
  with e = mu/omega0 (= 1.87 here): the exact value lies between 1.8 and 3, far from 0.5.
* 5.7 at its defaults (omega0 = 2, alpha = 0.8, A = 0.5): the leading-order frequency is
  omega0 + 3 alpha A^2/(8 omega0) = 2 + 0.6/16 = 2.0375; the exact one is 2 pi / T with
  T = 4 int_0^(pi/2) dphi / (omega0^2 + alpha A^2 (1 + sin^2 phi)/2)^(1/2) (q = A sin phi in the
  energy integral), computed below by Gauss-Legendre quadrature.
* 5.6 at theta0 = 60 deg: the small-amplitude ratio 1 + theta0^2/16 = 1 + (pi/3)^2/16 = 1.0685;
  the exact T/T0 = (2/pi) K(sin^2(theta0/2)) = (2/pi) K(0.25) = 1.0732.
"""

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

from mech.cli.main import cli


def run(*args):
    r = CliRunner().invoke(cli, ["solve", *args, "--json"])
    return r.exit_code, json.loads(r.stdout)


def _q(d, name):
    return next(q for q in d["quantities"] if q["name"] == name)


def test_right_to_leading_order_inside_the_range():
    code, d = run("5.11", "--expect", "xi_hi=0.1146")
    e = _q(d, "xi_hi")["expected"]
    assert code == 0 and e["match"] is True and e["matches"] == "leading-order"
    assert e["verdict"].startswith("right to leading order; the exact value is")
    exact = _q(d, "xi_hi")["numeric"]
    away = abs(exact - 0.114564) / exact
    assert f"{100 * away:.2g} %" in e["verdict"]
    # a value inside the old band but equal to neither value, to its digits, is wrong
    code, d = run("5.11", "--expect", f"xi_hi={0.114564 * 1.002:.4f}")
    assert code == 1 and _q(d, "xi_hi")["expected"]["matches"] is None


def test_the_exact_value_is_right_too():
    code, d = run("5.11")
    exact = _q(d, "xi_hi")["numeric"]
    code, d = run("5.11", "--expect", f"xi_hi={exact:.6g}")
    e = _q(d, "xi_hi")["expected"]
    assert code == 0 and e["matches"] == "exact" and e["verdict"] == "right: the exact value"


def test_5_9_far_outside_its_range_wrong_answers_exit_1():
    code, d = run("5.9", "--mu", "10", "--expect", "omega=0.5", "--expect", "lambda_lc=-5")
    assert code == 1 and d["expect_ok"] is False
    for name in ("omega", "lambda_lc"):
        q = _q(d, name)
        e = q["expected"]
        assert e["match"] is False and e["matches"] is None and q["theory_valid"] is False
        assert "the leading-order theory does not apply here" in e["verdict"]
        assert e["reference_value"] == q["numeric"]  # judged against the exact, verified value
    assert 1.8 < _q(d, "omega")["numeric"] < 3.0


def test_5_9_outside_its_range_compares_no_theory_and_exits_0():
    code, d = run("5.9", "--mu", "10")
    assert code == 0
    for name in ("omega", "lambda_lc"):
        q = _q(d, name)
        assert q["theory_valid"] is False and q["agree"] is None and "outside its range" in q["note"]


def test_5_9_the_leading_order_value_outside_its_range_is_named_and_wrong():
    # the leading-order frequency is omega0 = 3 exactly
    code, d = run("5.9", "--mu", "10", "--expect", "omega=3.000")
    e = _q(d, "omega")["expected"]
    assert code == 1 and e["hint"].startswith("that is the leading-order value")


def test_5_11_outside_its_range_wrong_signs_exit_1():
    code, d = run("5.11", "--mu", "0.9", "--omega", "10", "--expect", "xi_hi=-0.1", "--expect", "xi_lo=0.2")
    assert code == 1
    for name in ("xi_hi", "xi_lo"):
        assert _q(d, name)["expected"]["match"] is False


def _duffing_omega(omega0, alpha, A, n=64):
    x, w = np.polynomial.legendre.leggauss(n)
    phi = (x + 1) * math.pi / 4
    T = 4 * (math.pi / 4) * np.sum(w / np.sqrt(omega0**2 + alpha * A**2 * (1 + np.sin(phi) ** 2) / 2))
    return 2 * math.pi / T


def test_5_7_the_leading_order_frequency_is_named_and_wrong():
    exact = _duffing_omega(2.0, 0.8, 0.5)
    code, d = run("5.7", "--expect", "omega=2.0375")
    q = _q(d, "omega")
    e = q["expected"]
    assert q["numeric"] == pytest.approx(exact, rel=1e-9)
    pct = 100 * abs(2.0375 - exact) / exact  # 0.0197 %
    assert code == 1 and e["match"] is False
    assert e["hint"].startswith("this is the leading-order") and f"differs by {pct:.2g} %" in e["hint"]


def test_5_6_the_small_amplitude_ratio_is_named():
    code, d = run("5.6", "--theta0", "60deg", "--expect", "T_ratio=1.0685")
    q = _q(d, "T_ratio")
    assert q["numeric"] == pytest.approx(1.0732, abs=1e-4)
    assert code == 1 and "1 + theta0^2/16" in q["expected"]["hint"]
