"""The floating-point ranges an exercise's arithmetic holds in: declared once, enforced in one place.

A module forms scales from its parameters (a torque M g l, a rate (g/l)^(1/2), a mass fraction): beyond
some decades one of them, or a square or a product of it, leaves the doubles (overflows to inf or
underflows to 0 or a subnormal with fewer digits), and the route's answer is then noise.  A module
declares each such scale as a product of powers of parameters (times an optional factor, a sine of an
angle, say, given by value or, where the value itself could overflow, by its log10) with the decades it may
span:

    ranges.declare(exercise, Scale("(g/R)^(1/2)", {"g": 0.5, "R": -0.5}, "the frequencies"))

``declare`` adds the limit's text (``mech show``, show --json's "constraints") and a joint check that
refuses a point whose scale leaves the range, in one line naming the scale, its value and the range:
the user gets exit 2 before any solve, never a quoted Python exception or a disagreement of noise.
The scale is summed in logs, so it is formed without overflow at any parameter values.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Mapping

__all__ = ["Scale", "declare"]


@dataclass(frozen=True)
class Scale:
    """The scale ``text`` = factor(p) * prod p.name^power, held between 10^low and 10^high; ``what`` says
    what leaves the floating-point range with it (plural, "the frequencies")."""

    text: str
    powers: Mapping[str, float]
    what: str
    low: float = -300.0
    high: float = 300.0
    factor: Callable | None = field(default=None, compare=False)
    log_factor: Callable | None = field(default=None, compare=False)  # log10 of a factor, formed in logs

    def log10(self, p) -> float:
        """log10 of the scale at ``p`` (-inf for a zero factor or parameter)."""
        parts = [e * math.log10(abs(getattr(p, name))) if getattr(p, name) else -math.inf * math.copysign(1, e)
                 for name, e in self.powers.items()]
        if self.factor is not None:
            f = abs(self.factor(p))
            parts.append(math.log10(f) if f else -math.inf)
        if self.log_factor is not None:
            parts.append(self.log_factor(p))
        return math.fsum(parts) if all(math.isfinite(x) for x in parts) else sum(parts)

    def limit(self) -> str:
        lo = "" if self.low == -math.inf else f"1e{self.low:g} <= "
        hi = "" if self.high == math.inf else f" <= 1e{self.high:g}"
        return f"{lo}{self.text}{hi}: {self.what} within the floating-point range"

    def refusal(self, p) -> str | None:
        k = self.log10(p)
        if self.low <= k <= self.high:
            return None
        shown = f"10^{k:.0f}" if math.isfinite(k) else ("0" if k < 0 else "inf")
        lo = "0" if self.low == -math.inf else f"1e{self.low:g}"
        hi = "inf" if self.high == math.inf else f"1e{self.high:g}"
        return f"{self.text} = {shown} is outside [{lo}, {hi}], the floating-point range of {self.what}"


def declare(exercise, *scales: Scale) -> None:
    """State ``scales`` as ``exercise``'s limits and refuse any point beyond them (a joint check)."""
    exercise.declare_limits(*(s.limit() for s in scales))

    def in_range(p):
        for s in scales:
            msg = s.refusal(p)
            if msg:
                return msg
        return None

    exercise.constraint(in_range)
