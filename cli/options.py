"""Turn ``--NAME VALUE``, ``--NAME=VALUE`` and ``-p NAME=VALUE`` into SI parameter values."""

from __future__ import annotations

from mech.core.units import ValueError_, to_si
from typing import TYPE_CHECKING

from mech.core.errors import BadInput

if TYPE_CHECKING:  # pragma: no cover
    from mech.problems.spec import Exercise

__all__ = ["collect_params", "collect_texts", "parse_rtol"]


def _canonical(ex: Exercise, raw: str) -> str:
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
    return f"unknown parameter '{raw}' for {ex.id}{hint} (its parameters: {', '.join(names)})"


def _convert(ex: Exercise, name: str, text: str) -> float:
    param = ex.param_map[name]
    try:
        value = to_si(text, param.unit)
    except ValueError_ as exc:
        raise BadInput(f"{name}: cannot use '{text}': {exc}; allowed range {param.range_text()}") from None
    param.check(value, typed=text)
    return value


def collect_texts(ex: Exercise, args: list[str], pairs: list[str],
                  forms: str = "--NAME VALUE or -p NAME=VALUE") -> dict[str, str]:
    """The raw text given for each parameter, from ``--NAME VALUE``, ``--NAME=VALUE`` and ``-p NAME=VALUE``.

    A name given twice is an error, not a silent choice.
    """
    texts: dict[str, str] = {}

    def put(raw_name: str, text: str) -> None:
        name = _canonical(ex, raw_name)
        if name in texts:
            raise BadInput(f"{name}: given more than once ('{texts[name]}' and '{text}'); give it once")
        texts[name] = text

    i = 0
    while i < len(args):
        arg = args[i]
        if not arg.startswith("--") or len(arg) <= 2:
            raise BadInput(f"unexpected argument '{arg}'; parameters are given as {forms}")
        body = arg[2:]
        if "=" in body:
            name, text = body.split("=", 1)
        else:
            name = body
            if i + 1 >= len(args):
                canon = _canonical(ex, name)
                raise BadInput(f"{canon}: no value given; allowed range {ex.param_map[canon].range_text()}")
            i += 1
            text = args[i]
        put(name, text)
        i += 1
    for pair in pairs:
        if "=" not in pair:
            raise BadInput(f"-p takes NAME=VALUE, got '{pair}'")
        put(*pair.split("=", 1))
    return texts


def collect_params(ex: Exercise, args: list[str], pairs: list[str]) -> dict[str, float]:
    """Every given parameter converted to SI and checked against its bounds."""
    return {name: _convert(ex, name, text) for name, text in collect_texts(ex, args, pairs).items()}


def parse_rtol(text: str | None, ex: Exercise) -> float | None:
    if text is None:
        return None
    try:
        value = to_si(text, "1")
    except ValueError_ as exc:
        raise BadInput(f"rtol: cannot use '{text}': {exc}; allowed range [{ex.min_rtol:g}, 0.01]") from None
    if not (ex.min_rtol <= value <= 1e-2):
        raise BadInput(f"rtol: {value:g} is out of range; allowed [{ex.min_rtol:g}, 0.01]")
    return value
