"""mech from Python: the exercises of Likharev's Classical Mechanics (ch. 4 and 5), solved two ways.

    >>> import mech
    >>> sol = mech.solve("4.15", theta0="60deg")
    >>> sol["theta_c"].numeric, sol["theta_c"].numeric_err, sol.agree
    >>> sol.trajectory.t, sol.trajectory.y          # the ladder's motion up to the loss of contact
    >>> sw = mech.sweep("4.15", theta0=("10deg", "90deg", 9))
    >>> sw.to_arrays()["theta_c_numeric"]

Parameters take SI numbers or strings with units, exactly as on the command line
(``theta0="60deg"``, ``l=2.0``, ``l="15 cm"``).  A bad value raises ``BadInput``
with the command line's one-line message; a numeric solver that cannot give a
trustworthy number raises ``NumericFailure`` (its ``.solution`` holds the rest).

``import mech`` imports neither numpy nor scipy: everything heavy loads on first use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from mech.core.errors import BadInput, NumericFailure

if TYPE_CHECKING:  # pragma: no cover
    from mech.api import Solution, Sweep, Trajectory

__version__ = "0.1.0"  # as pyproject.toml's (tests/test_assign.py holds them equal); key.json records it

__all__ = [
    "__version__",
    "assign",
    "BadInput",
    "NumericFailure",
    "Solution",
    "Sweep",
    "Trajectory",
    "bench",
    "check",
    "exercise",
    "grade",
    "plot",
    "exercises",
    "solve",
    "sweep",
]


def exercises(chapter: int | None = None) -> list:
    """Every registered exercise (id, title, topic, methods, from_book), without importing any."""
    from mech.problems import registry

    if chapter is not None and (isinstance(chapter, bool) or not isinstance(chapter, int) or chapter not in (4, 5)):
        from mech.core.errors import BadInput
        from mech.core.safeio import shown

        raise BadInput(f"chapter: give 4 or 5 (or None), got {shown(chapter)}")
    return [e for e in registry.index() if chapter is None or e.chapter == chapter]


def exercise(ex_id: str):
    """One exercise: ``.id .title .statement .model .params .outputs .formulas .hard_cases``."""
    from mech.problems import registry

    if not isinstance(ex_id, str) and not (isinstance(ex_id, (int, float)) and abs(ex_id) < 1e6):
        from mech.core.errors import BadInput
        from mech.core.safeio import shown

        raise BadInput(f"exercise id: give a string such as '4.15', got {type(ex_id).__name__} {shown(ex_id)}")
    return registry.get(ex_id)


def solve(ex_id: str, method: str = "both", rtol: float | str | None = None, verify: bool = True,
          *, raise_on_failure: bool = True, expect: dict | None = None, expect_rtol: float | str | None = None,
          expect_points: int | None = None, expect_seed: int | None = None, expect_min_digits: int | None = None,
          **params: Any) -> "Solution":
    """Solve exercise ``ex_id`` at ``params`` (the rest at their defaults), as ``mech solve`` does.

    ``method``: "both" (default, cross-checked), "analytic" or "numeric".  ``rtol``: the numeric
    solver's requested accuracy (default: the exercise's).  ``verify``: rerun at rtol/10 to test the
    numeric claim.  Raises ``BadInput`` for a bad parameter and, unless ``raise_on_failure=False``,
    ``NumericFailure`` when a solver could not answer.  A disagreement is not an exception: look at
    ``sol.agree``.  ``expect={"theta_c": "35.26deg"}`` judges your own answers as ``--expect`` does
    (``sol["theta_c"].expected``, ``sol.expect_ok``); a formula (``"asin(2/3*sin(theta0))"``) is checked
    at ``expect_points`` parameter sets (default 24) drawn with seed ``expect_seed`` (default fixed), as
    ``--expect-points``/``--expect-seed`` do; ``expect_min_digits`` (default 2) as ``--min-digits``.
    """
    from mech import api

    return api.solve(ex_id, method=method, rtol=rtol, verify=verify, raise_on_failure=raise_on_failure,
                     params=params, expect=expect, expect_rtol=expect_rtol, expect_points=expect_points,
                     expect_seed=expect_seed, expect_min_digits=expect_min_digits)


def sweep(ex_id: str, method: str = "both", rtol: float | str | None = None, verify: bool = True,
          *, only: list[str] | str | None = None, jobs: int | None = None, budget: float | None = None,
          **ranges: Any) -> "Sweep":
    """Solve over a range or a grid, as ``mech sweep`` does.

    Each keyword is a parameter: a tuple ``(start, stop, n)`` or ``(start, stop, n, "log")`` sweeps it
    (ends in SI numbers or strings with units), a list or array gives its values, a single value holds
    it fixed.  Several swept parameters make a grid (the first varies slowest).  ``only`` names the
    outputs wanted (all by default); ``jobs`` the number of processes (default: decided by the cost);
    ``budget`` the sweep's wall-clock budget in seconds (``--budget``, default 600): points not reached
    by then fail, saying so.
    """
    from mech import api

    return api.sweep(ex_id, method=method, rtol=rtol, verify=verify, only=only, jobs=jobs, ranges=ranges,
                     budget=budget)


def check(ids: list[str] | str | None = None, hard: bool = False):
    """Cross-check every (or the named) exercise at its defaults and, with ``hard``, its hard cases.

    Returns the report of ``mech check``: ``.ok``, ``.passed``, ``.failed``, ``.cases``, ``.as_json()``.
    """
    from mech import api

    return api.check(ids, hard=hard)


def grade(path, budget: float | None = None, *, strict: bool = False, jobs: int | None = None, params=None,
          assignment=None, min_digits: int | None = None):
    """Hold a file of answers (TOML, or CSV) against mech, as ``mech grade FILE`` does: a ``GradeReport``
    (``.to_dict()`` is ``--json``; ``report["ok"]``, the cells by state ``.passed``, ``.failed``,
    ``.invalid``, ``.not_graded``, ``.unanswered``; ``.gradebook()``).  ``budget``: its wall-clock budget
    in seconds (``--budget``; default 600); ``strict``: BadInput for any entry that cannot be read
    (``--strict``), else it is graded invalid; ``jobs``: processes (``-j``); ``params``: a CSV's parameters
    from an assignment's template (``--params``); ``assignment``: the folder ``mech assign`` wrote, every
    entry held to it (``--assignment``); ``min_digits``: the digits rule's floor (``--min-digits``)."""
    from mech import api

    return api.grade(path, budget=budget, strict=strict, jobs=jobs, params=params, assignment=assignment,
                     min_digits=min_digits)


def assign(ids, *, seed: int, out, students=None, n: int | None = None, over=None, digits: int = 3,
           jobs: int | None = None, force: bool = False) -> dict:
    """Personal variants for a class, as ``mech assign`` does: writes ``out``/handout.md, handouts/,
    answers.toml, answers.csv, key.json, key.csv and key.md and returns the key (``students``: identifiers,
    or ``n``: s1 ... sN; ``over``: {name: "LO:HI" or "VALUE"}; ``force``: replace an assignment in ``out``).
    Any bad argument raises BadInput."""
    from mech import api

    return api.assign(ids, seed=seed, out=out, students=students, n=n, over=over, digits=digits, jobs=jobs,
                      force=force)


def bench(ex_id: str, *, methods=None, tols=None, repeats: int = 5, max_seconds: float = 55.0,
          **params: Any) -> dict:
    """Speed against error of the numeric solver(s), as ``mech bench ID --json`` does."""
    from mech import api

    return api.bench(ex_id, methods=methods, tols=tols, params=params, repeats=repeats, max_seconds=max_seconds)


def plot(ex_id: str, path=None, *, generic: bool = False, vary: str | None = None, **params: Any):
    """The exercise's figure, as ``mech plot`` draws it (needs matplotlib); saved to ``path`` if given."""
    from mech import api

    return api.plot(ex_id, path, generic=generic, vary=vary, params=params)


def __getattr__(name: str):
    if name == "__version__":  # the installed distribution's version, read when asked
        from mech.core.version import version

        return version()
    if name in ("Solution", "Sweep", "Trajectory", "Quantity"):
        from mech import api

        return getattr(api, name)
    raise AttributeError(f"module 'mech' has no attribute '{name}'")
