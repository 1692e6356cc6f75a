"""A parameter and an output as the catalogue declares them: name, unit, default and bounds (checked
against what a user typed, with a one-line refusal naming the allowed range), and how each is shown; and the
catalogue file read."""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mech.core.errors import BadInput

__all__ = ["Param", "Output", "read_catalogue"]


def read_catalogue(ex_id: str) -> dict:
    """The catalogue file ``problems/catalogue/ID.toml`` (the shared specification, verbatim), parsed."""
    # beside this module (importlib.resources would cost 4 ms of imports at every start-up)
    return tomllib.loads((Path(__file__).parent / "catalogue" / f"{ex_id}.toml").read_text("utf-8"))


def _fmt(x: float) -> str:
    return f"{x:.6g}"


@dataclass(frozen=True)
class Param:
    name: str
    unit: str
    default: float
    symbol: str = ""
    doc: str = ""
    display: str | None = None
    min: float | None = None
    max: float | None = None
    min_open: bool = False
    max_open: bool = False
    # the range ``mech assign`` draws a class's values from (SI): declared in the catalogue beside the bounds
    # (``typical_min``/``typical_max``), else within a factor 3 of a nonzero default; ``fixed``: a constant of
    # nature or of the Earth (g, G, Earth's rate and radius), kept at its default unless ``--over`` opens it
    typical_min: float | None = None
    typical_max: float | None = None
    fixed: bool = False

    @property
    def dimension(self) -> tuple[int, int, int] | None:
        """(kg, m, s) exponents of the unit, from the one unit system (``core.units.si_exponents``)."""
        from mech.core.units import si_exponents

        return si_exponents(self.unit)

    @property
    def typical(self) -> tuple[float, float]:
        """(lo, hi) in SI, inside the bounds: the catalogue's typical range, the default alone for a fixed
        constant, else [d/3, 3d] around a nonzero default (clipped to the bounds), else the bounds."""
        d = float(self.default)
        if self.fixed:
            return d, d
        lo = self.typical_min if self.typical_min is not None else (min(d / 3, 3 * d) if d else self.min)
        hi = self.typical_max if self.typical_max is not None else (max(d / 3, 3 * d) if d else self.max)
        lo = -math.inf if lo is None else lo
        hi = math.inf if hi is None else hi
        if self.min is not None:
            lo = max(lo, self.min)
        if self.max is not None:
            hi = min(hi, self.max)
        return float(lo), float(hi)

    def to_display(self, value: float) -> float:
        if not self.display:
            return value
        from mech.core.units import parse_unit

        return value / parse_unit(self.display)[0]  # the display unit's SI factor, from the one unit system

    def show(self, value: float) -> str:
        """The value as people read it: in the display unit where there is one."""
        if self.display:
            return f"{_fmt(self.to_display(value))} {self.display}"
        unit = "" if self.unit == "1" else f" {self.unit}"
        return f"{_fmt(value)}{unit}"

    def range_text(self) -> str:
        """The allowed range in interval notation: in the display unit first where there is one, then in SI."""
        unit = "" if self.unit == "1" else f" {self.unit}"
        text = self._interval(lambda v: v) + unit
        if self.display and (self.min is not None or self.max is not None):
            text = f"{self._interval(self.to_display)} {self.display} = {text}"
        return text

    def _interval(self, conv) -> str:
        lo = "(-inf" if self.min is None else ("(" if self.min_open else "[") + _fmt(conv(self.min))
        hi = "+inf)" if self.max is None else _fmt(conv(self.max)) + (")" if self.max_open else "]")
        return f"{lo}, {hi}"

    def check(self, value: float, typed: str | None = None) -> None:
        """Refuse a value outside the bounds, echoing ``typed`` (what the user wrote) where given, else the
        value in the display unit."""
        if typed is None:
            said = self.show(value)
        else:
            from mech.core.safeio import shown

            said = shown(typed.strip())
            if self.display and self.display not in said and math.isfinite(value):
                said += f" (= {self.show(value)})"
        if not math.isfinite(value):
            raise BadInput(f"{said} is not a finite number; allowed range {self.range_text()}", field=self.name,
                           kind="range")
        below = self.min is not None and (value < self.min or (self.min_open and value == self.min))
        above = self.max is not None and (value > self.max or (self.max_open and value == self.max))
        if below or above:
            raise BadInput(f"{said} is out of range; allowed {self.range_text()}" + self._unit_hint(typed),
                           field=self.name, kind="range")

    def _unit_hint(self, typed: str | None) -> str:
        """"; a plain number is in rad: for degrees write 10deg" where the number typed is out of range in
        SI but in range in the display unit."""
        if not typed or not self.display:
            return ""
        try:
            number = float(typed)
        except ValueError:
            return ""
        si = number / self.to_display(1.0)
        inside = (self.min is None or si > self.min or (not self.min_open and si == self.min)) and \
                 (self.max is None or si < self.max or (not self.max_open and si == self.max))
        return f" (a plain number is in {self.unit}: for {self.display} write {typed.strip()}{self.display})" \
            if inside else ""

    def as_json(self) -> dict:
        d: dict[str, Any] = {"name": self.name, "symbol": self.symbol, "unit": self.unit, "default": self.default}
        for key in ("min", "max"):
            if getattr(self, key) is not None:
                d[key] = getattr(self, key)
                d[key + "_open"] = getattr(self, key + "_open")
        if self.display:
            d["display"] = self.display
        d["typical_min"], d["typical_max"] = self.typical
        if self.fixed:
            d["fixed"] = True
        d["doc"] = self.doc
        return d


@dataclass(frozen=True)
class Output:
    name: str
    unit: str
    doc: str = ""
    theory: str = "exact"  # or "leading-order": the analytic value neglects higher orders
    # the direction of an axis (an angle with no sense, 4.3's theta1): an answer is judged modulo pi
    axis: bool = False

    @property
    def dimension(self) -> tuple[int, int, int] | None:
        """(kg, m, s) exponents of the unit, from the one unit system (``core.units.si_exponents``)."""
        from mech.core.units import si_exponents

        return si_exponents(self.unit)

    def as_json(self) -> dict:
        d = {"name": self.name, "unit": self.unit, "doc": self.doc}
        if self.theory != "exact":
            d["theory"] = self.theory
        return d

