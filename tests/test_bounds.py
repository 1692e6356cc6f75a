"""Every exercise cross-checked at parameters drawn across its bounds, not only its defaults.

Two kinds of draw (mech.studies.draws): near the default (log-uniform within a factor 30,
MECH_BOUNDS_POINTS per exercise, 2 by default) and across the whole declared range
(MECH_BOUNDS_WHOLE_POINTS, 3 by default).  Joint constraints may refuse a draw, which is then
redrawn.  The draws are seeded, so the test is deterministic; set MECH_BOUNDS_SEED and the two
counts to explore more.
"""

import os

import pytest

from mech.studies.checking import Case, run_case
from mech.problems import registry
from mech.studies.draws import draws

POINTS = int(os.environ.get("MECH_BOUNDS_POINTS", "2"))
WHOLE_POINTS = int(os.environ.get("MECH_BOUNDS_WHOLE_POINTS", "3"))
SEED = int(os.environ.get("MECH_BOUNDS_SEED", "20261121"))

CASES = [(ex, f"near-{k}", given) for ex in registry.all_exercises().values()
         for k, given in enumerate(draws(ex, POINTS, SEED, kind="near"))]
CASES += [(ex, f"whole-{k}", given) for ex in registry.all_exercises().values()
          for k, given in enumerate(draws(ex, WHOLE_POINTS, SEED, kind="whole"))]


@pytest.mark.parametrize("ex, k, given", CASES, ids=[f"{ex.id}-{k}" for ex, k, _ in CASES])
def test_cross_check_at_drawn_parameters(ex, k, given):
    """Both methods answer and agree at every draw."""
    case = run_case(Case(ex, f"draw {k}", given))
    assert case.ok, f"{ex.id} at {given}: {case.detail}"
