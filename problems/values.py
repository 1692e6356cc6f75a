"""Typed parameter values (``90deg``, ``2.5 km``) and tolerances made SI and checked against an exercise's ranges.

The one place a parameter name or value typed by a person (on the command line, or to ``mech.solve``) is
read; the units come from ``mech.core.units``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from mech.core.errors import BadInput
from mech.core.units import ValueError_, to_si
from mech.core.safeio import shown

if TYPE_CHECKING:  # pragma: no cover
    from mech.problems.spec import Exercise

__all__ = ["param_name", "unknown_param_message", "convert", "parse_rtol"]


def param_name(ex: Exercise, raw: str) -> str:
    """The parameter a typed name means (``--theta-0`` -> ``theta_0``); BadInput naming the nearest one."""
    name = raw.strip().replace("-", "_")
    if name not in ex.param_map:
        raise BadInput(unknown_param_message(ex, raw))
    return name


def unknown_param_message(ex: Exercise, raw: str) -> str:
    """One line for a parameter name the exercise does not have: the nearest name where one is close."""
    import difflib

    name = raw.strip().lstrip("-").replace("-", "_")
    names = list(ex.param_map)
    by_lower = {n.lower(): n for n in names}
    close = difflib.get_close_matches(name.lower(), list(by_lower), n=1, cutoff=0.6)
    hint = f"; did you mean {by_lower[close[0]]}?" if close else ""
    return f"unknown parameter '{shown(raw)}' for {ex.id}{hint} (its parameters: {', '.join(names)})"


def convert(ex: Exercise, name: str, text: str) -> float:
    """The typed value of parameter ``name`` in SI, checked against its range; BadInput otherwise."""
    param = ex.param_map[name]
    try:
        value = to_si(text, param.unit)
    except ValueError_ as exc:
        raise BadInput(f"{name}: cannot use '{shown(text)}': {exc}; allowed range {param.range_text()}") from None
    param.check(value, typed=text)
    return value


def parse_rtol(text: str | None, ex: Exercise) -> float | None:
    """The requested relative tolerance, within the exercise's [min_rtol, 0.01]; None when not given."""
    if text is None:
        return None
    try:
        value = to_si(text, "1")
    except ValueError_ as exc:
        raise BadInput(f"rtol: cannot use '{shown(text)}': {exc}; allowed range [{ex.min_rtol:g}, 0.01]") from None
    if not (ex.min_rtol <= value <= 1e-2):
        raise BadInput(f"rtol: {value:g} is out of range; allowed [{ex.min_rtol:g}, 0.01]")
    return value
