"""5.10's work, counted (never timed): the one-period maps a solve integrates (issue 41 item 2).

Each Newton solve on the locked loop used to end with one more map only to evaluate the Jacobian at the
converged point; from a solved point nearby on the plain map the last iterate's is kept (the step is
below the map's noise floor).  At the defaults the solve integrated 51 maps; a bound of 45 fails on that.
The values stay those of the fold search (tests/test_ex5_10.py holds them to hand-derived ones).
"""


import mech


def test_the_defaults_integrate_fewer_orbit_maps(monkeypatch):
    monkeypatch.setenv("MECH_SERIAL_VERIFY", "1")
    sol = mech.solve("5.10")
    assert sol.agree is True
    assert sol.numeric_info["orbit_map"] == "OrbitMap"
    assert sol.numeric_info["orbit_maps"] <= 45
