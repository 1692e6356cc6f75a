"""The same command gives the same numbers, run after run and process after process."""

import json
import os
import subprocess
import sys

import pytest

from mech.problems import registry
from mech.problems.spec import Undefined

IDS = list(registry.all_exercises())


def _plain(values):
    return {k: (v.why if isinstance(v, Undefined) else v) for k, v in values.items()}


@pytest.mark.parametrize("ex_id", IDS)
def test_numeric_solver_repeats_exactly(ex_id):
    ex = registry.get(ex_id)
    p = ex.resolve()
    first, _ = ex.solve_numeric(p)
    second, _ = ex.solve_numeric(p)
    assert _plain(first) == _plain(second)


def _solve_json(ex_id, hash_seed):
    env = {**os.environ, "PYTHONHASHSEED": str(hash_seed)}
    code = f"from mech.cli.main import cli; cli.main(['solve', {ex_id!r}, '--json'])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env).stdout
    d = json.loads(out)
    return [(q["name"], q["analytic"], q["numeric"]) for q in d["quantities"]]


@pytest.mark.parametrize("ex_id", [i for i in ("4.15", "4.20", "4.28", "5.8", "5.13") if i in IDS])
def test_across_processes_and_hash_seeds(ex_id):
    assert _solve_json(ex_id, 1) == _solve_json(ex_id, 2)
