import pytest
from hypothesis import settings

# property tests are deterministic: the same examples on every run and every machine
settings.register_profile("mech", derandomize=True, database=None)
settings.load_profile("mech")

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
