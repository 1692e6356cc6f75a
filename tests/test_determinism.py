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


ACROSS = [i for i in ("4.15", "4.20", "4.28", "5.8", "5.13") if i in IDS]
_SEP = "\x1e"  # a record separator: never in mech's JSON


def _solve_json(ex_ids, hash_seed):
    """``mech solve ID --json`` of each exercise, one after the other in one fresh Python under the given hash
    seed: the (name, analytic, numeric) of each, by exercise (one process for all five, not one each: a
    fresh Python costs more than the solve it hosts)."""
    env = {**os.environ, "PYTHONHASHSEED": str(hash_seed)}
    code = (f"import sys\nfrom mech.cli.main import cli\nfor ex_id in {list(ex_ids)!r}:\n"
            f"    try:\n        cli.main(['solve', ex_id, '--json'])\n    except SystemExit:\n        pass\n"
            f"    sys.stdout.write({_SEP!r} + '\\n'); sys.stdout.flush()\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env).stdout
    parts = out.split(_SEP + "\n")
    assert len(parts) == len(ex_ids) + 1 and parts[-1] == "", out[-2000:]
    found = {}
    for ex_id, text in zip(ex_ids, parts):
        d = json.loads(text)
        assert d["id"] == ex_id
        found[ex_id] = [(q["name"], q["analytic"], q["numeric"]) for q in d["quantities"]]
    return found


@pytest.fixture(scope="module")
def two_seeds():
    return _solve_json(ACROSS, 1), _solve_json(ACROSS, 2)


@pytest.mark.parametrize("ex_id", ACROSS)
def test_across_processes_and_hash_seeds(ex_id, two_seeds):
    first, second = two_seeds
    assert first[ex_id] == second[ex_id]
