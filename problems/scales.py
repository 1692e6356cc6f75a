"""Whether an exercise's answer can be represented in double precision at given parameters.

Every parameter in an open-ended range (``min = 0`` and no ``max``) may be 1e-200 or 1e+200 times its
default, and mech owes such an input an answer within its error bar or a one-line refusal.  An answer
(or a scale the solve must form) beyond about 1e+-300 cannot be represented; this module finds that
before anything is solved, for every exercise, from what the catalogue declares:

* the units of the parameters and outputs give their dimensions in kg, m, s, read by the one unit
  system (``core.units.si_exponents``, ``Param.dimension``, ``Output.dimension``); this module only does
  the rescaling arithmetic on top;
* a change of units by powers of two (exact in floating point) brings the parameters as near to their
  defaults as the dimensions allow (a least-squares fit of the three unit exponents, rounded to a
  multiple of ``QUANTUM`` bits so that parameters within 1e+-9 of their defaults keep the SI units);
* the analytic solution is evaluated in those units, with numpy's floating-point errors raised; its
  outputs, brought back to SI by their dimensions, must lie in [1e-290, 1e290] (or be exactly 0).

An input fails when an output's SI size leaves that range (the refusal names the output and its size)
or when the analytic solution overflows, divides by zero or forms a NaN even in the natural units (the
refusal names the parameters far from their defaults, whose combinations it could not form).  A
solver's own failure of any other kind is left to the cross-check to report.

``natural_units`` and ``from_natural`` are also what ``Exercise.solve_analytic`` uses, so that the analytic
answer does not depend on the units the user chose: at the defaults and within 1e+-9 of them the
units are SI and nothing changes.
"""

from __future__ import annotations

import math

from mech.core.units import si_exponents
from mech.problems.params import Params, Undefined

__all__ = ["LOG10_LIMIT", "QUANTUM", "TINY", "dims", "natural_units", "from_natural", "to_natural", "representable",
           "far_params", "out_of_range"]

LOG10_LIMIT = 290.0  # |log10 x| beyond this for a non-zero scale: outside the range mech works in
QUANTUM = 64  # unit exponents (powers of two) are multiples of this: 2^64 ~ 1.8e19
TINY = 2.2250738585072014e-308  # the smallest normal double: below it a value has underflowed

def dims(unit: str) -> tuple[int, int, int] | None:
    """The (kg, m, s) exponents of a catalogue unit: the one unit system's ``core.units.si_exponents``."""
    return si_exponents(unit)


def _log2_dev(value: float, default: float) -> float | None:
    if value == 0 or default == 0 or not math.isfinite(value):
        return None
    return math.log2(abs(value)) - math.log2(abs(default))


def natural_units(ex, p) -> tuple[tuple[int, int, int], dict] | None:
    """The unit exponents (powers of two of kg, m, s) that bring ``p`` nearest its defaults, and ``p`` in
    those units; None where the units are SI (no shift) or a unit cannot be read."""
    rows, rhs = [], []
    for prm in ex.params:
        d = prm.dimension
        if d is None:
            return None
        dev = _log2_dev(p[prm.name], prm.default)
        if any(d) and dev is not None:
            rows.append(d)
            rhs.append(dev)
    if any(o.dimension is None for o in ex.outputs) or not rows:
        return None
    fixed = [si_exponents(unit) for unit in getattr(ex, "constants", {}).values()]
    if any(d is None for d in fixed):
        return None
    if _si_by_bound(rows, rhs):
        return None
    import numpy as np

    # a constant the solvers hold (G) must keep its value: a heavily weighted row, checked exactly below
    A = np.array(rows + [tuple(1e3 * x for x in d) for d in fixed], float)
    b = np.array(rhs + [0.0] * len(fixed), float)
    fit = np.linalg.lstsq(A, b, rcond=None)[0]
    # the nearest multiples of QUANTUM (each rounded down or up) that keep every constant, best fit first
    import itertools

    A_rows, b_rows = np.array(rows, float), np.array(rhs, float)
    candidates = []
    for u in itertools.product(*[sorted({QUANTUM * math.floor(x / QUANTUM), QUANTUM * math.ceil(x / QUANTUM)})
                                 for x in fit]):
        if any(sum(a * b for a, b in zip(d, u)) for d in fixed):
            continue
        cost = float(np.sum((A_rows @ np.array(u, float) - b_rows) ** 2))
        candidates.append((cost, tuple(int(x) for x in u)))
    # the best fit that keeps every parameter a normal double: a shift that fits the far parameters can
    # push one near its own default out of the range (omega = 1e-300 rad/s with v0 = 1e290 m/s in 4.29
    # overflowed in ldexp); failing every candidate, SI
    for _, u in sorted(candidates):
        if not any(u):
            return None
        values = _shifted(ex, p, u)
        if values is not None:
            return u, values
    return None


_LEAST_SINGULAR: dict = {}  # the parameter dimensions' matrix (a tuple of rows) -> its least singular value


def _si_by_bound(rows, rhs) -> bool:
    """True where the fit below is certain to choose SI (no shift), told without it: the parameters'
    dimensions span kg, m and s (least singular value s > 0) and their deviations ``rhs`` (bits) are small.

    Every fit component is then at most |rhs| / s (the constants' rows only raise s) below 64: zero is a
    candidate; a candidate u != 0 has |A u| >= 64 (A whole, u multiples of 64, A u != 0 as A has rank 3),
    so its cost |A u - rhs|^2 >= (64 - |rhs|)^2 = 2304 or more, above zero's |rhs|^2 <= 256: zero is the
    best fit, alone, which is SI.  The margins (16 of 64 bits, 60 of 64) dwarf the round-off of the fit."""
    size = math.sqrt(sum(r * r for r in rhs))
    if size > 16:
        return False
    key = tuple(rows)
    least = _LEAST_SINGULAR.get(key)
    if least is None:
        import numpy as np

        whole = len(rows) >= 3 and all(isinstance(x, int) for d in rows for x in d)
        least = float(np.linalg.svd(np.array(rows, float), compute_uv=False)[-1]) if whole else 0.0
        if len(_LEAST_SINGULAR) < 4096:
            _LEAST_SINGULAR[key] = least
    return least > 0.5 and size < 60 * least


def _shifted(ex, p, u) -> dict | None:
    """``p`` in the units ``u``; None when a non-zero parameter leaves the normal range of the doubles there."""
    values = {}
    for prm in ex.params:
        k = sum(a * b for a, b in zip(prm.dimension, u))
        try:
            x = math.ldexp(p[prm.name], -k) if k else p[prm.name]
        except OverflowError:
            return None
        if p[prm.name] != 0 and (x == 0 or not math.isfinite(x) or abs(x) < 2.2250738585072014e-308):
            return None
        values[prm.name] = x
    return values


def _unit_exponent(unit: str, u) -> int:
    return sum(a * b for a, b in zip(si_exponents(unit), u))


def from_natural(value: float, unit: str, u) -> float:
    """A value in the natural units ``u`` brought back to SI (exact unless it leaves the range)."""
    k = _unit_exponent(unit, u)
    return math.ldexp(value, k) if k else value


def to_natural(value: float, unit: str, u) -> float:
    """An SI value in the natural units ``u`` (``from_natural``'s inverse; 0 where it underflows there)."""
    k = _unit_exponent(unit, u)
    try:
        return math.ldexp(value, -k) if k else value
    except OverflowError:
        return math.copysign(math.inf, value)


def far_params(ex, p, decades: float = 50.0) -> str:
    """The parameters farthest from their defaults (beyond ``decades``), as "R = 1e+199 m", for a message."""
    far = []
    for prm in ex.params:
        dev = _log2_dev(p[prm.name], prm.default)
        if dev is not None and abs(dev) * math.log10(2) >= decades:
            far.append((abs(dev), prm))
    far.sort(key=lambda t: -t[0])
    if not far:
        return ""
    unit = lambda prm: "" if prm.unit in ("1", "rad") else f" {prm.unit}"  # noqa: E731
    return ", ".join(f"{prm.name} = {p[prm.name]:.3g}{unit(prm)}" for _, prm in far[:3])


def _log10_si(value: float, unit: str, u) -> float:
    return math.log10(abs(value)) + (_unit_exponent(unit, u) * math.log10(2) if u else 0.0)


def representable(ex, p) -> str | None:
    """None when the analytic answer at ``p`` is representable, else the one-line reason for refusing."""
    if not ex.has_analytic:
        return None
    import numpy as np

    nat = natural_units(ex, p)
    u, values = nat if nat else (None, dict(p))
    where = far_params(ex, p)
    at = f" at {where}" if where else ""
    try:
        with np.errstate(over="raise", divide="raise", invalid="raise"):
            out = ex.analytic_solver(Params(values))
    except (OverflowError, ZeroDivisionError, FloatingPointError) as exc:
        if not where:
            return None  # no parameter is far from its default: a defect for the cross-check to report
        what = {OverflowError: "overflow", ZeroDivisionError: "division by zero"}.get(type(exc), str(exc))
        if isinstance(exc, FloatingPointError):
            what = str(exc).replace(" encountered", "")
        return (f"the scales the solution forms{at} leave the floating-point range "
                f"(the analytic solution meets {what})")
    except Exception:
        return None  # not a question of range: the cross-check reports the solver's failure
    for o in ex.outputs:
        v = out.get(o.name) if isinstance(out, dict) else None
        if v is None or isinstance(v, Undefined):
            continue
        try:
            v = float(v)
        except (TypeError, ValueError):
            continue
        if not math.isfinite(v):
            if not where:
                return None  # likewise a defect, not a question of range
            return f"the answer {o.name} is not finite{at}: its scale leaves the floating-point range"
        if v == 0:
            if where:
                k = _underflowed(ex, p, o)
                if k is not None:
                    unit = "" if o.unit in ("1", "rad") else f" {o.unit}"
                    return (f"the answer {o.name} ~ 1e{k:+.0f}{unit}{at} underflows: it lies below the "
                            f"floating-point range (1e-{LOG10_LIMIT:.0f}..1e{LOG10_LIMIT:.0f})")
            continue
        k = _log10_si(v, o.unit, u)
        if abs(k) > LOG10_LIMIT:
            unit = "" if o.unit in ("1", "rad") else f" {o.unit}"
            return (f"the answer {o.name} ~ 1e{k:+.0f}{unit}{at} lies outside the floating-point range "
                    f"(1e-{LOG10_LIMIT:.0f}..1e{LOG10_LIMIT:.0f})")
    return None


def _log10_output_at(ex, p, o) -> float | None:
    """log10 of the SI size of output ``o`` of the analytic solution at ``p`` (natural units); None if it is 0,
    undefined or the solution fails there."""
    import numpy as np

    nat = natural_units(ex, p)
    u, values = nat if nat else (None, dict(p))
    try:
        with np.errstate(all="ignore"):
            v = float(ex.analytic_solver(Params(values))[o.name])
    except Exception:
        return None
    if v == 0 or not math.isfinite(v):
        return None
    return _log10_si(v, o.unit, u)


def _underflowed(ex, p, o, steps: int = 6) -> float | None:
    """The estimated log10 SI size of an output that the analytic solution gives as exactly 0 at ``p``, when that
    0 is an underflow (below -LOG10_LIMIT), else None.

    The far parameters are brought part of the way from their defaults, p_t = default (p/default)^t for
    t = 1/2, 1/4, ..., and the output's log size at t and t/2 extrapolated linearly in t to t = 1 (exact for a
    power law, which the dimensional analysis makes of most answers).  An output that is 0 at those points
    too is 0 by the physics (a symmetry, a parameter at 0), and stays 0."""
    far = {prm.name: prm.default for prm in ex.params
           if (dev := _log2_dev(p[prm.name], prm.default)) is not None and abs(dev) * math.log10(2) >= 50.0}
    if not far:
        return None

    def at(t):
        q = dict(p)
        for name, d in far.items():
            q[name] = math.copysign(math.exp((1 - t) * math.log(abs(d)) + t * math.log(abs(p[name]))), p[name])
        return _log10_output_at(ex, Params(q), o)

    t = 0.5
    for _ in range(steps):
        hi, lo = at(t), at(t / 2)
        if hi is not None and lo is not None:
            k = hi + (hi - lo) / (t / 2) * (1 - t)
            return k if k < -LOG10_LIMIT else None
        t /= 2
    return None


def out_of_range(x: float) -> bool:
    """A finite non-zero value beyond the range mech works in."""
    return x != 0 and math.isfinite(x) and abs(math.log10(abs(x))) > LOG10_LIMIT
