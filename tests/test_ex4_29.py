"""4.29 against values worked out by hand.

Along the rod, in the rotating frame, only the centrifugal force acts:
r'' = w^2 r, so r = r0 cosh wt + (v0/w) sinh wt and r' = r0 w sinh wt + v0 cosh wt.
Across the rod the rod's force cancels the Coriolis force: N = 2 m w r'.
In the lab (polar coordinates) the radial acceleration is r'' - w^2 r = 0 and the
azimuthal one 2 w r', so |a_lab| = 2 w |r'|.  Numbers below by a calculator.
"""

import math

import pytest

from conftest import solve_both


def hand(m, w, r0, v0, t):
    r = r0 * math.cosh(w * t) + v0 / w * math.sinh(w * t)
    rd = r0 * w * math.sinh(w * t) + v0 * math.cosh(w * t)
    return {"r": r, "a_rot": w * w * r, "a_lab": 2 * w * abs(rd), "N": 2 * m * w * rd}


def test_defaults_by_hand():
    # cosh 2 = 3.7621956910836314, sinh 2 = 3.626860407847019
    expect = {
        "r": 0.37621956910836314,
        "a_rot": 1.5048782764334526,
        "a_lab": 2.901488326277615,
        "N": 0.2901488326277615,
    }
    a, n, run = solve_both("4.29")
    for values in (a, n):
        for k, v in expect.items():
            assert values[k] == pytest.approx(v, rel=1e-9)
    assert run.invariants["jacobi"] < 1e-9


def test_decaying_branch_hard_case():
    # v0 = -w r0: r = r0 e^(-wt) exactly; e^-6 = 0.0024787521766663585
    e6 = 0.0024787521766663585
    a, n, _ = solve_both("4.29", m=0.1, omega=2.0, r0=0.1, v0=-0.2, t=3.0)
    for values in (a, n):
        assert values["r"] == pytest.approx(0.1 * e6, rel=1e-9)
        assert values["a_rot"] == pytest.approx(0.4 * e6, rel=1e-9)
        assert values["N"] == pytest.approx(-0.08 * e6, rel=1e-9)
        assert values["a_lab"] == pytest.approx(0.8 * e6, rel=1e-9)


@pytest.mark.parametrize(
    "m, w, r0, v0, t",
    [
        (0.05, 3.0, 0.2, -1.0, 0.8),  # hard case 2: passes through the axis, r < 0
        (2.0, 0.5, -0.3, 0.1, 4.0),  # starts on the negative side
        (1.0, 1.0, 0.0, 0.0, 5.0),  # at rest on the axis: stays there
        (0.1, 7.0, 0.05, 0.0, 0.0),  # t = 0: a_rot = w^2 r0, no Coriolis yet
    ],
)
def test_other_parameters(m, w, r0, v0, t):
    expect = hand(m, w, r0, v0, t)
    a, n, _ = solve_both("4.29", m=m, omega=w, r0=r0, v0=v0, t=t)
    for values in (a, n):
        for k, v in expect.items():
            assert values[k] == pytest.approx(v, rel=1e-9, abs=1e-14)


def test_axis_crossing_keeps_sign():
    a, n, _ = solve_both("4.29", m=0.05, omega=3.0, r0=0.2, v0=-1.0, t=0.8)
    for values in (a, n):
        assert values["r"] < 0 and values["a_rot"] < 0 and values["N"] < 0


def test_lab_acceleration_is_the_rod_force_over_mass():
    a, n, _ = solve_both("4.29", m=0.3, omega=1.3, r0=0.4, v0=0.7, t=2.2)
    for values in (a, n):
        assert values["a_lab"] == pytest.approx(abs(values["N"]) / 0.3, rel=1e-9)


def test_a_run_far_shorter_than_one_over_omega():
    """Issue 26: omega = 1e-100 rad/s, v0 = 1e250 m/s, t = 1e-200 s (omega t = 1e-300).  By hand
    r = r0 cosh(wt) + v0 sinh(wt)/w = 0.1 + 1e50 m (to 1e-600), r' = r0 w sinh(wt) + v0 cosh(wt) = 1e250 m/s,
    a_rot = w^2 r = 1e-150 m/s^2, a_lab = 2 w |r'| = 2e150 m/s^2, N = 2 m w r' = 2e149 N.  v0/omega = 1e350
    overflowed in both solvers (the numeric length unit was infinite: NaN everywhere)."""
    a, n, _ = solve_both("4.29", omega=1e-100, v0=1e250, t=1e-200)
    want = {"r": 1e50, "a_rot": 1e-150, "a_lab": 2e150, "N": 2e149}
    for got in (a, n):
        for name, value in want.items():
            assert got[name] == pytest.approx(value, rel=1e-12, abs=0.0), name


def test_a_run_of_1e_minus_200_s_from_rest():
    """scripts/extremes.py, t = 1e-200 of its default: omega t = 4e-200, v0 = 0.  By hand r = r0 cosh(wt) = 0.1 m,
    a_rot = w^2 r = 0.4 m/s^2, r' = r0 w sinh(wt) = 0.1 * 2 * 4e-200 = 8e-201 m/s, a_lab = 2 w |r'| = 3.2e-200
    m/s^2.  The numeric solver keeps its 1/omega units (v0/omega is finite) and its Jacobi integral, v'^2/2 -
    r^2/2 in those units, is finite (it was 0/0 when the run's own length was the time unit)."""
    _, n, run = solve_both("4.29", t=2e-200)
    assert n["r"] == pytest.approx(0.1, rel=1e-12, abs=0.0)
    assert n["a_rot"] == pytest.approx(0.4, rel=1e-12, abs=0.0)
    assert n["a_lab"] == pytest.approx(3.2e-200, rel=1e-8, abs=0.0)
    assert n["N"] == pytest.approx(3.2e-201, rel=1e-8, abs=0.0)
    assert math.isfinite(run.invariants["jacobi"])


@pytest.mark.parametrize("m, w, r0, t", [(0.1, 2.0, 0.1, 2e-200), (0.2, 3.0, -0.5, 1e-250)])
def test_the_analytic_value_at_a_tiny_t(m, w, r0, t):
    """Issue 26: mech solve 4.29 -p t=2e-200 gave the analytic a_lab and N as 0.  The solve takes units of
    2^-320 s there (the parameters nearest their defaults), in which a_lab = 3.2e-200 m/s^2 is 7e-393: below
    the doubles.  By hand, for w t << 1 from rest (v0 = 0): sinh(wt) = wt to 1e-400, cosh(wt) = 1, so
    r = r0, r' = r0 w^2 t, a_rot = w^2 r0, a_lab = 2 w^3 |r0| t, N = 2 m w^3 r0 t
    (0.1, 2, 0.1, 2e-200: a_lab = 3.2e-200 m/s^2, N = 3.2e-201 N; 0.2, 3, -0.5, 1e-250: 2.7e-249, -5.4e-250)."""
    import mech

    sol = mech.solve("4.29", m=m, omega=w, r0=r0, v0=0.0, t=t)
    want = {"r": r0, "a_rot": w * w * r0, "a_lab": 2 * w**3 * abs(r0) * t, "N": 2 * m * w**3 * r0 * t}
    for name, value in want.items():
        assert sol[name].analytic == pytest.approx(value, rel=1e-14, abs=0.0), name
        assert sol[name].numeric == pytest.approx(value, rel=1e-8, abs=0.0), name
    assert sol.agree is True
