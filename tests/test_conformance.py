"""Every registered exercise matches its catalogue entry, and every catalogue entry is registered."""

import math
import tomllib
from pathlib import Path

import pytest

from mech.problems import registry
from mech.problems.spec import Undefined

PACKAGED = Path(registry.__file__).parent / "catalogue"
SHARED = Path(__file__).resolve().parents[1].parent / "shared" / "catalogue"
IDS = sorted(p.stem for p in PACKAGED.glob("*.toml"))
REGISTERED = list(registry.all_exercises())


def _without_mechs_field(text: bytes) -> bytes:
    """A packaged catalogue file less the fields mech adds to the shared specification: in its heading
    (from_book, integrates, theory), a parameter's typical range and whether it is fixed in an assignment
    (typical_min, typical_max, fixed), a handout's statement (``handout = \"\"\"...\"\"\"``) and the
    ``[regime]`` an assignment keeps to."""
    ours = (b"from_book = ", b"integrates = ", b"theory = ", b"typical_min = ", b"typical_max = ", b"fixed = ")
    out, skipping = [], None
    for line in text.splitlines(keepends=True):
        if skipping == "handout":
            if line.rstrip() == b'"""':
                skipping = None
            continue
        if skipping == "regime":
            if line.strip() and not line.startswith(b"["):
                continue
            skipping = None
        if line.startswith(b'handout = """'):
            skipping = "handout"
            continue
        if line.rstrip() == b"[regime]":
            skipping = "regime"
            if out and not out[-1].strip():
                out.pop()  # the blank line that set the table apart
            continue
        if not line.startswith(ours):
            out.append(line)
    return b"".join(out)


def test_packaged_catalogue_is_the_shared_one():
    """Every shared specification is packaged byte for byte, mech's heading lines aside; an exercise
    set for mech beyond the shared catalogue has only its packaged file."""
    if not SHARED.is_dir():
        pytest.skip("no ../shared/catalogue beside this checkout")
    shared = {p.stem: p.read_bytes() for p in SHARED.glob("*.toml")}
    packaged = {p.stem: p.read_bytes() for p in PACKAGED.glob("*.toml")}
    assert set(shared) <= set(packaged)
    assert {k: _without_mechs_field(packaged[k]) for k in shared} == shared


@pytest.mark.parametrize("ex_id", IDS)
def test_every_catalogue_file_says_whether_it_is_the_books(ex_id):
    text = (PACKAGED / f"{ex_id}.toml").read_text("utf-8")
    spec = tomllib.loads(text)
    assert isinstance(spec["from_book"], bool)
    # read with the heading (before the statement), so that `mech list` need not parse the whole file
    assert text.index("\nfrom_book = ") < text.index("\nstatement")
    assert registry.get(ex_id).from_book is spec["from_book"]
    assert registry.from_book(ex_id) is spec["from_book"]


@pytest.mark.parametrize("ex_id", REGISTERED)
def test_registered_matches_catalogue(ex_id):
    ex = registry.get(ex_id)
    spec = tomllib.loads((PACKAGED / f"{ex_id}.toml").read_text("utf-8"))
    assert ex.id == spec["id"] == ex_id
    assert [p.name for p in ex.params] == [p["name"] for p in spec["params"]]
    for p, q in zip(ex.params, spec["params"]):
        assert (p.unit, p.default, p.min, p.max, p.min_open, p.max_open) == (
            q["unit"], q["default"], q.get("min"), q.get("max"), q.get("min_open", False), q.get("max_open", False))
        p.check(p.default)
    assert [(o.name, o.unit) for o in ex.outputs] == [(o["name"], o["unit"]) for o in spec["outputs"]]
    assert ex.formulas, "formulas as text for mech show"
    assert set(ex.methods) == {"analytic", "numeric"}


@pytest.mark.parametrize("ex_id", REGISTERED)
def test_solvers_return_every_output_at_defaults(ex_id):
    ex = registry.get(ex_id)
    p = ex.resolve()
    a = ex.solve_analytic(p)
    n, run = ex.solve_numeric(p)
    for values in (a, n):
        assert list(values) == [o.name for o in ex.outputs]
        for v in values.values():
            assert isinstance(v, Undefined) or math.isfinite(v)
    assert run.nfev >= 0


@pytest.mark.parametrize("ex_id", REGISTERED)
def test_hard_cases_are_within_bounds(ex_id):
    ex = registry.get(ex_id)
    for h in ex.hard_cases:
        ex.resolve(h["params"])


def test_every_catalogue_entry_is_registered():
    missing = sorted(set(IDS) - set(REGISTERED), key=lambda s: tuple(map(int, s.split("."))))
    if missing:
        pytest.xfail(f"not yet registered: {', '.join(missing)}")


def test_the_light_index_matches_the_imported_modules():
    """`mech list` reads each catalogue heading without importing the module; the heading must say what the
    module registers (a new exercise's catalogue file states it: integrates = its states, theory = its
    outputs' theories)."""
    entries = registry.index()
    exercises = registry.all_exercises()
    assert [e.id for e in entries] == list(exercises)
    for e in entries:
        ex = exercises[e.id]
        assert (e.title, e.topic) == (ex.title, ex.topic)
        facts = registry.declarations(ex)
        heading = {"methods": list(e.methods), "integrates": e.integrates, "theory": e.theory}
        assert heading == facts, f"problems/catalogue/{e.id}.toml: its heading says {heading}, the module {facts}"


@pytest.mark.parametrize("ex_id", REGISTERED)
def test_an_exercise_integrates_only_through_its_declared_motion(ex_id):
    """Every integration of an exercise is a ``run.follow`` of a ``Motion`` (problems/motion.py), so bench,
    the trajectory and the invariants see it; no module calls the Run's raw integrators itself.  An exercise
    with states declares its motion (``@exercise.motion``), whose start is the declared states' start."""
    import importlib
    import re

    ex = registry.get(ex_id)
    module = {e.id: e.module for e in registry.index()}[ex_id]
    source = Path(importlib.import_module(module).__file__).read_text("utf-8")
    assert not re.findall(r"\brun\._?(integrate|integrate_to_event)\(", source)
    if ex.states:
        m = ex.motion_at(ex.resolve({}))
        assert m is not None, f"{ex_id} declares states but no motion"
        assert len(m.start) == len(ex.states)
