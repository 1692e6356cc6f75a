"""Turn ``--NAME VALUE``, ``--NAME=VALUE`` and ``-p NAME=VALUE`` into SI parameter values."""

from __future__ import annotations

from typing import TYPE_CHECKING

from mech.core.errors import BadInput
from mech.problems.values import convert, param_name, parse_rtol
from mech.core.safeio import shown

if TYPE_CHECKING:  # pragma: no cover
    from mech.problems.spec import Exercise

__all__ = ["collect_params", "collect_texts", "parse_rtol"]


def collect_texts(ex: Exercise, args: list[str], pairs: list[str],
                  forms: str = "--NAME VALUE or -p NAME=VALUE") -> dict[str, str]:
    """The raw text given for each parameter, from ``--NAME VALUE``, ``--NAME=VALUE`` and ``-p NAME=VALUE``.

    A name given twice is an error, not a silent choice.
    """
    texts: dict[str, str] = {}

    def put(raw_name: str, text: str) -> None:
        name = param_name(ex, raw_name)
        if name in texts:
            raise BadInput(f"{name}: given more than once ('{shown(texts[name])}' and '{shown(text)}'); give it once")
        texts[name] = text

    i = 0
    while i < len(args):
        arg = args[i]
        if not arg.startswith("--") or len(arg) <= 2:
            raise BadInput(f"unexpected argument '{shown(arg)}'; parameters are given as {forms}")
        body = arg[2:]
        if "=" in body:
            name, text = body.split("=", 1)
        else:
            name = body
            if i + 1 >= len(args):
                canon = param_name(ex, name)
                raise BadInput(f"{canon}: no value given; allowed range {ex.param_map[canon].range_text()}")
            i += 1
            text = args[i]
        put(name, text)
        i += 1
    for pair in pairs:
        if "=" not in pair:
            raise BadInput(f"-p takes NAME=VALUE, got '{shown(pair)}'")
        put(*pair.split("=", 1))
    return texts


def collect_params(ex: Exercise, args: list[str], pairs: list[str]) -> dict[str, float]:
    """Every given parameter converted to SI and checked against its bounds."""
    return {name: convert(ex, name, text) for name, text in collect_texts(ex, args, pairs).items()}
