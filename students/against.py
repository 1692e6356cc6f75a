"""Grading against an assignment (``mech grade ANSWERS --assignment DIR``): the key ``mech assign`` wrote
(DIR/key.json) read once, and what it fixes for each (student, exercise): the parameters, the digits rule,
the range and points a formula is judged over, and the outputs asked.  A file cannot move any of them: a
field that tries is refused by name (``refusals``), and the cells it would move are graded invalid.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

from mech.core.errors import BadInput
from mech.core.safeio import shown

__all__ = ["Assignment", "load_assignment", "FIXED_FIELDS", "DEFAULT_DIGITS"]

DEFAULT_DIGITS = 3  # ``mech assign --digits``' default, for a key written before it recorded its digits
# the fields of an answer the assignment fixes, and what each would move
FIXED_FIELDS = {"rtol": "the tolerance", "over": "the range a formula is judged over",
                "points": "the points a formula is judged at", "seed": "the points a formula is judged at"}


@dataclass(frozen=True)
class Variant:
    student: str
    exercise: str
    params: dict  # name -> the value as the handout wrote it ("47.3deg")
    outputs: tuple  # the outputs asked


@dataclass(frozen=True)
class Assignment:
    """``digits``: the assignment's significant digits (the digits rule's floor); ``over``: exercise id ->
    {parameter: "LO:HI" or "VALUE"}; ``variants``: (student, exercise id) -> Variant, in the key's order."""

    path: str
    digits: int
    over: dict
    variants: dict

    def variant(self, student, ex_id) -> Variant | None:
        return self.variants.get((student, ex_id))

    def refusals(self, item: dict, ex, student) -> list[tuple[str, str]]:
        """(field, reason) for each thing an answer sets that the assignment fixes, or an answer the
        assignment does not hold (its student or exercise not assigned)."""
        out = [(k, f"the assignment fixes {what}; remove it") for k, what in FIXED_FIELDS.items() if k in item]
        if ex is None:
            return out
        if student is None:
            out.append(("student", "missing; the assignment grades each student's own variant"))
        elif self.variant(student, ex.id) is None:
            out.append(("exercise", f"{ex.id} is not in the assignment for {shown(student, 40)}"))
        return out

    def params_problems(self, ex, variant: Variant, written: dict, every: bool) -> list[tuple[str, str]]:
        """(field, reason) for each parameter the answer sets otherwise than the assignment, compared in SI
        exactly; ``every``: the answer must name every assigned parameter (a TOML answer, whose template
        writes them all), else only those it names are compared (a CSV's optional columns)."""
        from mech.core.units import ValueError_, to_si

        missing, differ = [], []
        for name, text in variant.params.items():
            p = ex.param_map[name]
            if name not in written:
                if every:
                    missing.append(f"{name} = {shown(text, 40)}")
                continue
            try:
                same = to_si(str(written[name]), p.unit) == to_si(text, p.unit)
            except (ValueError_, OverflowError):
                same = False
            if not same:
                differ.append((f"params.{name}", f"the assignment fixes the parameters ({name} = {shown(text, 40)}, "
                                                 f"not {shown(written[name], 40)})"))
        out = [("params", f"missing {', '.join(missing)}: the assignment fixes the parameters")] if missing else []
        return out + differ + [(f"params.{name}", "the assignment fixes the parameters (it does not set this one)")
                               for name in written if name not in variant.params]

    def given(self, ex, variant: Variant) -> tuple[dict, dict]:
        """The variant's parameters: (SI, as written)."""
        from mech.core.units import to_si

        order = [p.name for p in ex.params if p.name in variant.params]
        return ({k: to_si(variant.params[k], ex.param_map[k].unit) for k in order},
                {k: shown(variant.params[k], 40) for k in order})

    def formula_range(self, ex) -> dict | None:
        """The range an exercise's formulas are judged over: the declared bounds narrowed by the
        assignment's ``over`` (a fixed value: that value alone); None where it narrows nothing."""
        from mech.core.units import to_si
        from mech.students.points import parse_over

        table = self.over.get(ex.id) or {}
        spans = {k: v for k, v in table.items() if ":" in v}
        out = dict(parse_over(ex, spans)) if spans else {}
        for k, v in table.items():
            if ":" not in v:
                x = to_si(v, ex.param_map[k].unit)
                out[k] = (x, x)
        return out or None


def _problem(name: str, why: str) -> BadInput:
    return BadInput(f"{name}: {why}", field="--assignment", kind="key")


def load_assignment(folder) -> Assignment:
    """DIR/key.json read and checked (every variant's exercise known, its parameters readable and in
    range, its outputs the exercise's); BadInput naming the file and what is wrong otherwise."""
    from mech.core.safeio import load_json, shown_path
    from mech.problems import registry

    path = os.path.join(str(folder), "key.json")
    name = shown_path(path)
    if not os.path.isdir(str(folder)):
        raise BadInput(f"{shown_path(folder)}: not a folder written by mech assign", field="--assignment",
                       kind="missing")
    key = load_json(path, "--assignment key")
    if not isinstance(key, dict) or not isinstance(key.get("variants"), list):
        raise _problem(name, "not a key written by mech assign (no \"variants\" list)")
    digits = key.get("digits", DEFAULT_DIGITS)
    if isinstance(digits, bool) or not isinstance(digits, int) or not 1 <= digits <= 12:
        raise _problem(name, f"\"digits\": {shown(digits, 20)} is not a whole number in [1, 12]")
    over = key.get("over", {})
    if not isinstance(over, dict) or not all(isinstance(t, dict) and all(isinstance(v, str) for v in t.values())
                                             for t in over.values()):
        raise _problem(name, "\"over\": not a table of {exercise: {parameter: \"LO:HI\" or \"VALUE\"}}")
    variants: dict = {}
    for k, v in enumerate(key["variants"], 1):
        variant = _read_variant(v, registry, f"{name}: variant {k}")
        if (variant.student, variant.exercise) in variants:
            raise _problem(f"{name}: variant {k}", f"{shown(variant.student, 40)} has {variant.exercise} twice")
        variants[(variant.student, variant.exercise)] = variant
    a = Assignment(name, digits, {str(k): dict(t) for k, t in over.items()}, variants)
    for ex_id in a.over:
        try:
            a.formula_range(registry.get(ex_id))
        except (BadInput, ValueError) as exc:
            raise _problem(name, f"\"over\" of {shown(ex_id, 20)}: {shown(exc, 160)}") from None
    return a


def _read_variant(v, registry, where: str) -> Variant:
    from mech.core.units import ValueError_, to_si

    if not isinstance(v, dict) or not isinstance(v.get("student"), str) or not isinstance(v.get("exercise"), str) \
            or not isinstance(v.get("params", {}), dict) or not isinstance(v.get("outputs", {}), dict):
        raise _problem(where, "not {\"student\", \"exercise\", \"params\", \"outputs\"}")
    try:
        ex = registry.get(v["exercise"])
    except BadInput as exc:
        raise _problem(where, str(exc)) from None
    params = {}
    for pname, text in v.get("params", {}).items():
        p = ex.param_map.get(pname)
        try:
            if p is None:
                raise ValueError_(f"not a parameter of {ex.id}")
            p.check(to_si(str(text), p.unit), str(text))
        except (ValueError_, BadInput, OverflowError) as exc:
            raise _problem(where, f"params.{shown(pname, 40)}: {shown(exc, 120)}") from None
        params[pname] = str(text)
    names = {o.name for o in ex.outputs}
    outputs = tuple(o for o in v.get("outputs") or names if o in names) or tuple(o.name for o in ex.outputs)
    order = [o.name for o in ex.outputs if o.name in outputs]
    return Variant(v["student"].strip(), ex.id, params, tuple(order))
