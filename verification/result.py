"""What a solve is: one typed, read-only value, and the plain functions that render it.

* ``Quantity``: one output, both values, the error bars, the judge's verdict (``agree``), the notes, and
  the judgement of your own answer (``expected``) where one was given;
* ``Failure``: a loud failure, typed by ``kind`` (``FAILURE_KINDS``), with the output it concerns (if
  one) and its message;
* ``Solution``: the cross-check of one exercise at one set of parameters, a read-only Mapping from output
  names to Quantities (``sol["theta_c"]``, ``list(sol)`` the names, ``.values()``, ``.items()``).

``to_json`` (the object ``mech solve --json`` prints, fixed by the contract), ``to_text`` (the compact
table a REPL shows) and ``to_html`` (Jupyter) render a Solution; ``mech.cli.render`` draws the rich table.
Nothing here computes or judges: ``crosscheck`` builds a Solution, ``judge`` and ``answers`` decide.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Iterator

from mech.problems.spec import Undefined
from mech.verification.judge import Verdict, conclude, holds

if TYPE_CHECKING:
    import numpy as np

__all__ = ["Failure", "Quantity", "Solution", "Trajectory", "FAILURE_KINDS", "SOLVER_FAILURES", "to_json", "to_text",
           "to_html", "to_rich", "quantity_json"]

# what failed: a solver (analytic, numeric, the numeric rerun at rtol/10), an invariant's drift, a value
# that is not finite or outside the floating-point range, an estimate (the analytic round-off, the theory's
# range) that raised
FAILURE_KINDS = ("analytic", "numeric", "rerun", "invariant", "non-finite", "out-of-range", "estimate")
SOLVER_FAILURES = ("analytic", "numeric", "rerun")  # a solver that did not answer


@dataclass(frozen=True)
class Failure:
    """A loud failure of a solve: ``kind`` (one of ``FAILURE_KINDS``), the ``output`` it concerns (None: the
    whole solve) and the one-line ``message`` (``str(failure)``)."""

    kind: str
    message: str
    output: str | None = None

    def __post_init__(self):
        if self.kind not in FAILURE_KINDS:
            raise ValueError(f"unknown failure kind {self.kind!r}")

    @property
    def solver_failed(self) -> bool:
        return self.kind in SOLVER_FAILURES

    def __str__(self) -> str:
        return self.message


@dataclass(frozen=True)
class Quantity:
    """One output of a solve.  ``analytic``/``numeric``: a float, ``Undefined`` (no finite value, with the
    reason) or None (the method did not run); ``numeric_err``/``analytic_err``: absolute error bars, SI;
    ``tol``: the relative tolerance the judge applied, ``allowed`` the absolute allowance; ``agree``:
    True, False or None (nothing compared); ``verdict``: the judge's typed verdict (``judge.Verdict``; None
    where no judge ran) and ``reason`` why (a leading-order theory outside its range: the exercise's reason);
    ``expected``: the judgement of your answer (``answers.Judgement``) when one was given."""

    name: str
    unit: str
    analytic: float | Undefined | None = None
    numeric: float | Undefined | None = None
    numeric_err: float | None = None
    analytic_err: float | None = None
    abs_err: float | None = None
    rel_err: float | None = None
    tol: float | None = None
    tol_abs: float = 0.0
    agree: bool | None = None
    theory: str = "exact"
    theory_valid: bool | None = None
    expected_err: float | None = None
    expected_err_abs: float | None = None
    verify_diff: float | None = None
    allowed: float | None = None
    verdict: Verdict | None = None
    reason: str = ""
    notes: tuple[str, ...] = ()
    expected: Any = None

    def as_json(self) -> dict:
        return quantity_json(self)

    @property
    def note(self) -> str | None:
        return "; ".join(self.notes) if self.notes else None

    @property
    def outside(self) -> bool:
        """A leading-order theory outside its range here: nothing was compared (``Verdict.OUTSIDE``)."""
        return self.verdict is Verdict.OUTSIDE

    @property
    def holds(self) -> bool | None:
        """What this output concludes (``judge.holds``): True, False, or None (no verdict)."""
        return holds(self.verdict, self.agree, verified=self.verify_diff is not None)

    @property
    def cell(self) -> str:
        """The verdict in a table's agree column (``Verdict.cell``)."""
        if self.verdict is not None:
            return Verdict(self.verdict).cell
        return "—" if self.agree is None else ("yes" if self.agree else "NO")

    @property
    def value(self) -> float | None:
        """The numeric value where there is one, else the analytic one (None where neither is a number)."""
        for v in (self.numeric, self.analytic):
            if _is_number(v):
                return v
        return None

    def __float__(self) -> float:
        """``float(sol["T"])``: ``value``; a ValueError naming the output where it has none."""
        v = self.value
        if v is None:
            raise ValueError(f"{self.name} has no finite value here")
        return float(v)


def judged_quantity(J, k: int, *, notes=(), **given) -> Quantity:
    """The one place a ``Quantity`` is built: output ``k`` of the judge's arrays ``J`` (``judge.judge``).
    ``given``: what the solves gave (``name``, ``unit``, ``theory``, ``analytic``, ``numeric``, ``tol_abs``,
    ``analytic_err``, ``expected_err``, ``expected_err_abs``, ``theory_valid``); the judge gives the rest
    (agreement, verdict and its reason, tolerance, allowance, differences, the numeric error bar).
    ``notes``: what the drafting found (in order), then the judge's reasons, then why a value is undefined.
    A point's cross-check and a sweep's point read the same."""
    from mech.verification.judge import notes as judge_notes

    said = list(notes) + judge_notes(J, k)
    for key in ("analytic", "numeric"):
        v = given.get(key)
        if isinstance(v, Undefined):
            said.append(f"{key}: {v.why}")
    ag = int(J.agree[k])
    verdict = Verdict(int(J.verdict[k]))
    return Quantity(**given, agree=None if ag < 0 else bool(ag), verdict=verdict,
                    reason=J.outside_why[k] if verdict is Verdict.OUTSIDE else "",
                    tol=_float_or_none(J.tol[k]), allowed=_float_or_none(J.allowed[k]),
                    abs_err=_float_or_none(J.abs_err[k]), rel_err=_float_or_none(J.rel_err[k]),
                    numeric_err=_float_or_none(J.numeric_err[k]) if _is_number(given.get("numeric")) else None,
                    verify_diff=_float_or_none(J.verify_diff[k]), notes=tuple(dict.fromkeys(said)))


def _float_or_none(v) -> float | None:
    """A judged array's element: None for NaN (nothing there)."""
    v = float(v)
    return None if v != v else v


def _is_number(v) -> bool:
    return isinstance(v, float) and math.isfinite(v)


def _finite_or_none(v):
    if v is None or isinstance(v, Undefined):
        return None
    v = float(v) + 0.0  # -0.0 + 0.0 is 0.0: a zero has no sign to show
    return v if math.isfinite(v) else None


def quantity_json(q: Quantity) -> dict:
    """One quantity as the contract's JSON object."""
    d: dict[str, Any] = {"name": q.name, "unit": q.unit}
    for key in ("analytic", "numeric"):
        d[key] = _finite_or_none(getattr(q, key))
        if isinstance(getattr(q, key), Undefined) and getattr(q, key).infinite:
            d["infinite"] = True  # infinite by the physics, not meaningless
    if _is_number(q.numeric):
        d["numeric_err"] = _finite_or_none(q.numeric_err)
    if q.analytic_err is not None and _is_number(q.analytic):
        d["analytic_err"] = _finite_or_none(q.analytic_err)
    d["abs_err"] = _finite_or_none(q.abs_err)
    d["rel_err"] = _finite_or_none(q.rel_err)
    d["tol"] = _finite_or_none(q.tol)
    if q.tol_abs:
        d["tol_abs"] = _finite_or_none(q.tol_abs)
    d["agree"] = q.agree
    if q.theory != "exact":
        d["theory"] = q.theory
        d["theory_valid"] = q.theory_valid is not False
        d["expected_err"] = _finite_or_none(q.expected_err)
        if q.expected_err_abs is not None:
            d["expected_err_abs"] = _finite_or_none(q.expected_err_abs)
    if q.verify_diff is not None:
        d["verify_diff"] = _finite_or_none(q.verify_diff)
    if q.notes:
        d["note"] = q.note
    if q.expected is not None:
        d["expected"] = q.expected.as_json()
    return d


@dataclass
class Trajectory:
    """The motion the numeric route integrated: ``y[i]`` is state ``names[i]`` (in ``units[i]``) at times ``t``.

    ``y`` has shape (n_states, n_times), as scipy's ``OdeResult``; ``t`` is increasing.  The one trajectory
    type of the API (``mech.Trajectory``, ``Solution.trajectory``): the integrator's own result
    (``solvers.numerics.ode.Trajectory``, one leg with its cost) is converted to it by ``mech.api``, in SI
    with the legs joined, and never handed out.
    """

    t: np.ndarray
    y: np.ndarray
    names: list[str]
    units: list[str]

    def to_csv(self, path) -> None:
        """A header row ``t [s]`` then ``name [unit]`` per state, one row per time."""
        import csv

        from mech.core.safeio import atomic_write

        with atomic_write(str(path), "--trajectory", newline="") as fh:
            out = csv.writer(fh)
            out.writerow(["t [s]"] + [f"{n} [{u}]" for n, u in zip(self.names, self.units)])
            for k in range(self.t.size):
                out.writerow([repr(float(self.t[k]))] + [repr(float(v)) for v in self.y[:, k]])

    def __repr__(self) -> str:
        return f"Trajectory({', '.join(self.names)}; {self.t.size} times from {self.t[0]:g} to {self.t[-1]:g} s)"


@dataclass(frozen=True, eq=False)
class Solution(Mapping):
    """The cross-check of one exercise at one set of parameters: a read-only Mapping of output names to
    ``Quantity`` objects.

    ``agree``: True when every compared output agrees and nothing failed, False when anything failed,
    None where nothing was compared; ``errors``: the ``Failure``s; ``expect_ok``: every expected value
    right (None when none was given); ``to_dict()``: exactly what ``mech solve --json`` prints;
    ``trajectory``: the integrated motion (``mech.api``; None where the route integrates none).
    """

    exercise: Any
    params: Any
    quantities: tuple[Quantity, ...]
    timing: dict = field(default_factory=dict)
    numeric_info: dict | None = None
    errors: tuple[Failure, ...] = ()
    run: Any = field(default=None, repr=False)  # the numeric solve's Run (its recorded integrations)
    expect_ok: bool | None = None
    expect_summary: str | None = None
    # Solution -> its Trajectory (set by mech.api, which reruns the numeric solve with its motion kept)
    trajectory_of: Callable[[Solution], Trajectory | None] | None = field(default=None, repr=False)

    # -- the Mapping -----------------------------------------------------------------------------------
    def __getitem__(self, name: str) -> Quantity:
        for q in self.quantities:
            if q.name == name:
                return q
        names = ", ".join(q.name for q in self.quantities)
        ex_id = getattr(self.exercise, "id", "this exercise")
        raise KeyError(f"{ex_id} has no output '{name}'; its outputs are: {names}")

    def __iter__(self) -> Iterator[str]:
        return (q.name for q in self.quantities)

    def __len__(self) -> int:
        return len(self.quantities)

    def __contains__(self, name) -> bool:
        return any(q.name == name for q in self.quantities)

    # -- verdicts --------------------------------------------------------------------------------------
    @property
    def id(self) -> str:
        return self.exercise.id

    @property
    def agree(self) -> bool | None:
        """True when every compared output agrees and every numeric value is verified (an output whose
        leading-order theory is outside its range compares nothing: its numeric value, verified by the
        rerun, holds); False when anything failed; None where nothing was compared or verified."""
        return conclude((q.holds for q in self.quantities), failed=bool(self.errors))

    @property
    def solver_failed(self) -> bool:
        """A solver did not answer (a typed failure of kind analytic, numeric or rerun)."""
        return any(e.solver_failed for e in self.errors)

    def replace(self, **changes) -> "Solution":
        return dataclasses.replace(self, **changes)

    def with_expected(self, judgements) -> "Solution":
        """This solution with your answers' judgements (``answers.Judgement``) on their quantities."""
        by_name = {j.name: j for j in judgements}
        qs = tuple(dataclasses.replace(q, expected=by_name[q.name]) if q.name in by_name else q
                   for q in self.quantities)
        refs = sorted({j.reference for j in judgements if j.reference})
        right = sum(j.match for j in judgements)
        n = len(judgements)
        summary = (f"your answers: {right} of {n} right"
                   + (f" (judged against mech's {', '.join(refs)} value{'s' if n > 1 else ''})" if refs else ""))
        return dataclasses.replace(self, quantities=qs, expect_ok=right == n, expect_summary=summary)

    @property
    def expected(self) -> dict:
        """{output: judgement} of the answers given (empty when none was)."""
        return {q.name: q.expected for q in self.quantities if q.expected is not None}

    # -- renderings ------------------------------------------------------------------------------------
    def as_json(self) -> dict:
        return to_json(self)

    def to_dict(self) -> dict:
        """Exactly what ``mech solve --json`` prints for the same exercise and parameters."""
        return to_json(self)

    def __repr__(self) -> str:
        return to_text(self)

    def _repr_html_(self) -> str:
        return to_html(self)

    def __rich__(self):
        return to_rich(self)

    @functools.cached_property
    def trajectory(self) -> Trajectory | None:
        """The motion the numeric route integrates, in SI (None where it integrates none): computed on
        first use by ``trajectory_of`` (the API's, which reruns the numeric solve with its motion kept)."""
        return None if self.trajectory_of is None else self.trajectory_of(self)


def _clean(obj):
    """Make an info structure JSON-safe: non-finite numbers become null."""
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, bool) or obj is None or isinstance(obj, str):
        return obj
    try:
        f = float(obj)
    except (TypeError, ValueError):
        return str(obj)
    if isinstance(obj, int) and not isinstance(obj, bool):
        return obj
    return f if math.isfinite(f) else None


def to_json(sol: Solution) -> dict:
    """The object ``mech solve --json`` prints (see the contract)."""
    d = {
        "id": sol.exercise.id,
        "title": sol.exercise.title,
        "params": _clean(dict(sol.params)),
        "quantities": [quantity_json(q) for q in sol.quantities],
        "agree": sol.agree,
        "timing": _clean(sol.timing),
        "numeric_info": _clean(sol.numeric_info),
    }
    if sol.errors:
        d["errors"] = [str(e) for e in sol.errors]
    if sol.expect_ok is not None:
        d["expect_ok"] = sol.expect_ok
    return d


def _cell(v, digits: int = 10) -> str:
    if isinstance(v, Undefined):
        return "undefined"
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "NO"
    return f"{v:.{digits}g}"


def _rows(sol: Solution) -> tuple[list[str], list[list[str]]]:
    head = ["quantity", "unit", "analytic", "numeric", "± numeric", "agree"]
    rows = []
    for q in sol.quantities:
        agree = q.cell
        rows.append([q.name + (" *" if q.theory != "exact" else ""), q.unit, _cell(q.analytic), _cell(q.numeric),
                     _cell(q.numeric_err, 2), agree])
    return head, rows


# the colours of a verdict's words in every rich rendering (``to_rich`` and ``mech.render``'s tables): a
# table's agree cell (``Quantity.cell``) and a closing line's tone (``closing``)
STYLE = {"yes": "green", "NO": "bold red", "outside range": "yellow", "—": "dim",
         "ok": "green", "fail": "bold red", "warn": "yellow"}


def closing(sol: Solution) -> tuple[str, str] | None:
    """The line that closes every table of a solve (the REPL's, Jupyter's and ``mech solve``'s): what it
    concludes, in words, and its tone ("ok", "fail", "warn"); None where there is nothing to say."""
    qs = sol.quantities
    has_a = any(q.analytic is not None for q in qs)
    has_n = any(q.numeric is not None for q in qs)
    if sol.agree is False:
        return ("CROSS-CHECK FAILED" if has_a and has_n else "FAILED"), "fail"
    outside = [q for q in qs if q.outside]
    if has_a and has_n and outside:
        # a leading-order theory outside its range is not compared: say which outputs and why
        why = "; ".join(dict.fromkeys(q.reason for q in outside if q.reason))
        compared = any(q.agree is True for q in qs)
        head = "analytic and numeric agree on the rest; " if sol.agree and compared else ""
        return (f"{head}no theory compared for {', '.join(q.name for q in outside)}: the leading-order "
                f"theory is outside its range ({why}); the verified numeric values are the answers"), "warn"
    if has_a and has_n:
        return ("analytic and numeric agree", "ok") if sol.agree else None
    if has_a:
        return "analytic solver only: nothing was cross-checked (leave out --method to compare)", "warn"
    if has_n:
        verified = (sol.numeric_info or {}).get("verify_rtol")
        how = f"its accuracy claim held at rtol {verified:g}" if verified else "its accuracy claim was not re-tested"
        return f"numeric solver only: {how}; nothing was cross-checked (leave out --method to compare)", "warn"
    return None


def _closing_text(sol: Solution) -> str:
    said = closing(sol)
    return "" if said is None else said[0]


def to_text(sol: Solution) -> str:
    """The compact table a plain REPL shows: one row per output, then the failures and the verdict."""
    head, rows = _rows(sol)
    widths = [max(len(r[k]) for r in [head, *rows]) for k in range(len(head))]
    lines = [f"{sol.exercise.id}  {sol.exercise.title}"]
    params = getattr(sol.exercise, "params", [])
    if params:
        lines.append(", ".join(f"{p.symbol or p.name} = {p.show(sol.params[p.name])}" for p in params
                               if p.name in sol.params))
    for r in [head, *rows]:
        lines.append("  ".join(c.ljust(w) if k < 2 else c.rjust(w) for k, (c, w) in enumerate(zip(r, widths)))
                     .rstrip())
    lines.extend(str(e) for e in sol.errors)
    if sol.expect_summary:
        lines.append(sol.expect_summary)
        lines.extend(expect_lines(sol))
    said = _closing_text(sol)
    if said:
        lines.append(said)
    return "\n".join(lines)


def to_html(sol: Solution) -> str:
    """The table Jupyter shows."""
    import html

    esc = html.escape
    ex = sol.exercise
    params = ", ".join(f"{esc(p.symbol or p.name)} = {esc(p.show(sol.params[p.name]))}"
                       for p in ex.params if p.name in sol.params)
    head, rows = _rows(sol)
    head_html = "".join(f"<th>{esc(c)}</th>" for c in head)
    body = "".join("<tr>" + "".join(f"<td>{esc(c)}</td>" for c in r) + "</tr>" for r in rows)
    errors = "".join(f"<p style='color:#b00'>{esc(str(e))}</p>" for e in sol.errors)
    expect = (f"<p>{esc(sol.expect_summary)}</p>" + "".join(f"<p>{esc(x)}</p>" for x in expect_lines(sol))
              if sol.expect_summary else "")
    return (f"<div><b>{esc(ex.id)}  {esc(ex.title)}</b><br><span>{params}</span>"
            f"<table><thead><tr>{head_html}</tr></thead><tbody>{body}</tbody></table>"
            f"{errors}{expect}<p>{esc(_closing_text(sol))}</p></div>")


def to_rich(sol: Solution):
    """The compact table as a rich renderable (``rich.print(sol)``); ``mech solve`` draws the full one."""
    from rich import box
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    head, rows = _rows(sol)
    t = Table(box=box.SIMPLE_HEAD, show_edge=False, title=f"{sol.exercise.id}  {sol.exercise.title}",
              title_justify="left")
    for k, c in enumerate(head):
        t.add_column(c, justify="left" if k < 2 else "right")
    for r in rows:
        t.add_row(*r[:-1], Text(r[-1], style=STYLE.get(r[-1], "")))
    parts = [t]
    parts.extend(Text(str(e), style="red") for e in sol.errors)
    if sol.expect_summary:
        parts.append(Text(sol.expect_summary, style="green" if sol.expect_ok else "bold red"))
        parts.extend(Text(x) for x in expect_lines(sol))
    said = closing(sol)
    if said is not None:
        parts.append(Text(said[0], style=STYLE[said[1]]))
    return Group(*parts)


def expect_lines(sol: Solution) -> list[str]:
    """One line per answer given: ``  omega_c = 5.83 rad/s: wrong: off by a factor 2 (mech: 2.9147 rad/s)``."""
    return [f"  {name} = {j.text}: {j.verdict}" for name, j in sol.expected.items()]
