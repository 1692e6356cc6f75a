"""The values an exercise is given and gives, below the exercise contract (``spec``) and the scales
(``scales``), which both read them: ``Params``, resolved parameter values in SI, and ``Undefined``, an
output with no finite value and the reason."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

__all__ = ["Params", "Undefined"]


@dataclass(frozen=True)
class Undefined:
    """An output that has no finite value for these parameters, with the reason; ``infinite`` when the
    physics makes it infinite (a period of a plane that stops turning), not meaningless."""

    why: str
    infinite: bool = False

    @property
    def word(self) -> str:
        return "infinite" if self.infinite else "undefined"


class Params(Mapping[str, float]):
    """Resolved parameter values in SI, readable as ``p.theta0`` or ``p["theta0"]``."""

    def __init__(self, values: Mapping[str, float]):
        object.__setattr__(self, "_values", dict(values))

    def __getattr__(self, name: str) -> float:
        if name.startswith("__"):
            raise AttributeError(name)  # copy and pickle probe dunders before ``_values`` exists
        try:
            return self._values[name]
        except KeyError:
            raise AttributeError(name) from None

    def __setattr__(self, name, value):
        raise AttributeError("Params are read-only")

    def __reduce__(self):
        return (Params, (self._values,))

    def __getitem__(self, key: str) -> float:
        return self._values[key]

    def __iter__(self):
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def replace(self, **changes: float) -> "Params":
        return Params({**self._values, **changes})

    def __repr__(self) -> str:
        return f"Params({self._values!r})"
