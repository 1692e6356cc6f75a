"""Judging a formula given as an answer: its dimension, then its value across the exercise's declared range.

A formula (``formula_ast.Formula``) is held against mech's reference

* at the given parameters, where the reference is the one the answers judge uses (the analytic value
  confirmed by the numeric one, or for a leading-order output either the leading-order value or the
  verified numeric value);
* at ``n`` parameter sets drawn across every parameter's declared bounds (log-uniform on a positive
  range), inside the exercise's joint constraints, plus the defaults and the catalogue's hard cases.
  Where an exercise refuses most of its box, a draw it refuses is repaired one parameter at a time:
  with the others held, that parameter's allowed interval is found on a grid and refined by bisection,
  and the value is drawn inside it.  The reference there is the analytic value (exact theory), or for a
  leading-order output the leading-order value, else the numeric value of the exercise's own numeric
  route, verified by its rerun at rtol/10.

A point is right when ``|yours - mech| <= rtol |mech| + mech's error bar + 4 x your formula's own
round-off`` (a first-order bound carried through the evaluation).  Where that round-off decides, the
formula is evaluated again in extended precision (``numpy.longdouble``): a right formula that only loses
digits to cancellation is then said to be ill-conditioned there, not wrong.

The point set and the references are computed once per exercise, given point and range (``_CACHE``):
a class file judges every student's formula against the same arrays.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from mech.problems.spec import BadInput, Params, Undefined
from mech.verification.formula_ast import Formula, dim_of_unit, dim_text

__all__ = ["DEFAULT_POINTS", "DEFAULT_SEED", "FORMULA_RTOL", "PointSet", "point_set", "judge_formula",
           "FormulaVerdict", "parse_over"]

DEFAULT_POINTS = 24
DEFAULT_SEED = 20240524
FORMULA_RTOL = 1e-9  # a formula is exact: its numbers are as written
NUMERIC_BUDGET_S = 4.0  # for the numeric reference of a leading-order output at drawn points


# -- the ranges and the draws ---------------------------------------------------------------------------

@dataclass
class _Range:
    name: str
    kind: str  # "log": log-uniform on [lo, hi] > 0; "lin": uniform; "signed": +-, log-uniform magnitude
    lo: float
    hi: float

    def to_t(self, v: float) -> float:
        if self.kind == "log":
            return math.log(v)
        if self.kind == "signed":
            return math.copysign(math.log(abs(v) / self.lo + 1.0), v)  # monotone over the reals
        return v

    def from_t(self, t: float) -> float:
        if self.kind == "log":
            return math.exp(t)
        if self.kind == "signed":
            return math.copysign(self.lo * math.expm1(abs(t)), t)
        return t

    def t_bounds(self) -> tuple[float, float]:
        if self.kind == "signed":
            m = math.log(self.hi / self.lo + 1.0)
            return -m, m
        return self.to_t(self.lo), self.to_t(self.hi)

    def draw(self, rng) -> float:
        if self.kind == "signed":
            mag = math.exp(rng.uniform(math.log(self.lo), math.log(self.hi)))
            return mag if rng.random() < 0.5 else -mag
        a, b = self.t_bounds()
        return self.from_t(rng.uniform(a, b))


def _scale_for(ex, p) -> float:
    """A typical size of a parameter whose default is 0: another parameter's in the same unit, else 1."""
    if p.default != 0:
        return abs(p.default)
    same = [abs(q.default) for q in ex.params if q.unit == p.unit and q.default != 0]
    return max(same) if same else 1.0


def _inward(lo: float, hi: float, lo_open: bool, hi_open: bool) -> tuple[float, float]:
    span = hi - lo
    if lo_open:
        lo = lo + 1e-9 * span if lo == 0 else lo + 1e-9 * max(span, abs(lo))
    if hi_open:
        hi = hi - 1e-9 * max(span, abs(hi))
    return lo, hi


def ranges(ex, over: dict | None = None) -> dict[str, _Range]:
    """The range each parameter is drawn from: its declared bounds (a decade or two around the default
    where a bound is open-ended), narrowed to ``over`` (name -> (lo, hi), SI) where given."""
    out = {}
    for p in ex.params:
        d, s = p.default, _scale_for(ex, p)
        if over and p.name in over:
            lo, hi = over[p.name]
            kind = "log" if lo > 0 and hi / lo > 10 else "lin"
            out[p.name] = _Range(p.name, kind, lo, hi)
            continue
        if p.min is not None and p.max is not None:
            lo, hi = _inward(p.min, p.max, p.min_open, p.max_open)
            if p.unit == "rad" or lo < 0:  # an angle, or a range through zero: uniform
                kind = "lin"
            else:  # a positive range: log-uniform, over three decades below the top when it starts at 0
                lo = max(lo, hi * 1e-3) if p.min == 0 else lo
                kind = "log" if lo > 0 and hi / lo > 10 else "lin"
            out[p.name] = _Range(p.name, kind, lo, hi)
        elif p.min is not None:  # [min, inf)
            if p.min > 0:
                lo, hi = p.min * (1 + 1e-9 * p.min_open), max(p.min, d) * 100.0
            else:
                lo, hi = s / 100.0, s * 100.0
                lo = max(lo, p.min)
            out[p.name] = _Range(p.name, "log", lo, hi)
        elif p.max is not None:  # (-inf, max]: rare; draw below max over a span of the default's size
            out[p.name] = _Range(p.name, "lin", p.max - 100.0 * s, p.max)
        else:
            out[p.name] = _Range(p.name, "signed", s / 100.0, s * 100.0)
    return out


def _valid(ex, values: dict) -> Params | None:
    """The resolved parameters (bounds, joint checks, representable answers), or None where refused."""
    try:
        return ex.resolve(values)
    except (BadInput, ValueError, OverflowError, ZeroDivisionError):
        return None


def _accept(ex, values: dict) -> Params | None:
    """The parameters when the bounds and joint checks accept them (not ``resolve``'s representability
    test, which solves the analytic answer once more: a point whose answer overflows gets no reference
    where mech's values are computed, and is not judged)."""
    if not _allowed(ex, values):
        return None
    return Params({p.name: float(values.get(p.name, p.default)) for p in ex.params})


def _allowed(ex, values: dict) -> bool:
    """The bounds and the joint checks only, without their messages' use or the analytic solve of
    ``resolve`` (which also asks that the answer be representable): the cheap test the draws bisect on."""
    for p in ex.params:
        v = values.get(p.name, p.default)
        if not math.isfinite(v):
            return False
        if p.min is not None and (v < p.min or (p.min_open and v == p.min)):
            return False
        if p.max is not None and (v > p.max or (p.max_open and v == p.max)):
            return False
    params = Params({p.name: float(values.get(p.name, p.default)) for p in ex.params})
    try:
        return not ex.constraint_message(params)
    except (ArithmeticError, ValueError):
        return False


def _interval_around(ex, x: dict, r: _Range, t_ok: float, t_bad: float) -> float:
    """Bisect (in the range's own coordinate) between an accepted and a refused value of one parameter."""
    for _ in range(16):
        mid = 0.5 * (t_ok + t_bad)
        if mid in (t_ok, t_bad):
            break
        if _allowed(ex, {**x, r.name: r.from_t(mid)}):
            t_ok = mid
        else:
            t_bad = mid
    return t_ok


def _repair(ex, x: dict, rs: dict[str, _Range], rng) -> Params | None:
    """Bring a refused draw inside the joint constraints by moving one parameter at a time within the
    interval the others allow, found on a grid and refined by bisection."""
    names = list(rs)
    for k in rng.permutation(len(names)):
        r = rs[names[int(k)]]
        a, b = r.t_bounds()
        grid = np.linspace(a, b, 17)
        ok = [_allowed(ex, {**x, r.name: r.from_t(t)}) for t in grid]
        good = [i for i, v in enumerate(ok) if v]
        if not good:
            continue
        i = good[int(rng.integers(len(good)))]
        j = i
        while j > 0 and ok[j - 1]:
            j -= 1
        lo_t = grid[j] if j == 0 else _interval_around(ex, x, r, grid[j], grid[j - 1])
        j = i
        while j < len(grid) - 1 and ok[j + 1]:
            j += 1
        hi_t = grid[j] if j == len(grid) - 1 else _interval_around(ex, x, r, grid[j], grid[j + 1])
        t = rng.uniform(lo_t, hi_t) if hi_t > lo_t else grid[i]
        p = _accept(ex, {**x, r.name: r.from_t(t)})
        if p is None:
            p = _accept(ex, {**x, r.name: r.from_t(grid[i])})
        if p is not None:
            return p
    return None


def _toward(ex, base: dict, x: dict, rs: dict[str, _Range], rng) -> Params | None:
    """Last resort: a point on the segment from an accepted point ``base`` toward the draw ``x``."""
    tb = {k: rs[k].to_t(base[k]) if _representable(rs[k], base[k]) else None for k in rs}
    tx = {k: rs[k].to_t(x[k]) for k in rs}

    def at(s):
        return {k: (rs[k].from_t(tb[k] + s * (tx[k] - tb[k])) if tb[k] is not None else base[k]) for k in rs}

    s_ok, s_bad = 0.0, 1.0
    for _ in range(30):
        mid = 0.5 * (s_ok + s_bad)
        if _allowed(ex, at(mid)):
            s_ok = mid
        else:
            s_bad = mid
    return _accept(ex, at(rng.uniform(0.0, s_ok))) or _accept(ex, base)


def _representable(r: _Range, v: float) -> bool:
    return not (r.kind == "log" and v <= 0)


def _in_over(p: Params, over: dict | None) -> bool:
    return not over or all(lo <= p[k] <= hi for k, (lo, hi) in over.items())


def draw(ex, n: int, seed: int, over: dict | None = None) -> list[Params]:
    """``n`` accepted parameter sets across the declared ranges (seeded, so verdicts repeat)."""
    rng = np.random.default_rng(seed)
    rs = ranges(ex, over)
    base = dict(ex.resolve({}))
    out: list[Params] = []
    for _ in range(4 * n + 8):
        if len(out) >= n:
            break
        x = {k: r.draw(rng) for k, r in rs.items()}
        p = _accept(ex, x) or _repair(ex, x, rs, rng) or _toward(ex, base, x, rs, rng)
        if p is not None and _in_over(p, over):
            out.append(p)
    return out


def parse_over(ex, over: dict) -> dict[str, tuple[float, float]]:
    """``{"theta0": "10deg:60deg"}`` -> ``{"theta0": (lo, hi)}`` in SI, each inside the declared bounds."""
    from mech.core.units import ValueError_, to_si

    out = {}
    for raw, text in over.items():
        name = str(raw).strip().replace("-", "_")
        if name not in ex.param_map:
            raise BadInput(f"over.{raw}: not a parameter of {ex.id}; its parameters are: {', '.join(ex.param_map)}")
        p = ex.param_map[name]
        if not isinstance(text, str) or text.count(":") != 1:
            raise BadInput(f"over.{raw}: give a range LO:HI such as \"10deg:60deg\"")
        lo_s, hi_s = text.split(":")
        try:
            lo, hi = to_si(lo_s, p.unit), to_si(hi_s, p.unit)
            p.check(lo, lo_s)
            p.check(hi, hi_s)
        except (ValueError_, BadInput) as exc:
            raise BadInput(f"over.{raw}: {str(exc).removeprefix(name + ': ')}") from None
        if not lo < hi:
            raise BadInput(f"over.{raw}: {text}: the low end must be below the high end")
        out[name] = (lo, hi)
    return out


# -- the point set and its references, computed once ---------------------------------------------------

@dataclass
class PointSet:
    """The points a formula is judged at (index 0: the given parameters) and mech's analytic values there."""

    ex: object
    points: list  # Params
    labels: list  # "given", "defaults", "hard case", "drawn"
    arrays: dict  # parameter -> np.ndarray over the points
    analytic: dict = field(default_factory=dict)  # output -> np.ndarray (nan where undefined)
    analytic_err: dict = field(default_factory=dict)  # output -> np.ndarray (absolute)
    undefined: dict = field(default_factory=dict)  # output -> list of reasons (None where defined)
    numeric: dict = field(default_factory=dict)  # (output, index) -> (value, err) or None: the verified numeric
    depends: dict = field(default_factory=dict)  # output -> list of parameters its value changes with
    lines: dict = field(default_factory=dict)  # parameter -> PointSet of one-at-a-time moves (lazy)
    in_range: bool = True  # the given point inside ``over``
    outside: dict = field(default_factory=dict)  # leading-order output -> bool array: its theory does not apply
    memo: dict = field(default_factory=dict)  # parameter values -> mech's analytic values there (shared with lines)
    batch_memo: dict = field(default_factory=dict)  # the batched route's own memo (``Exercise.batched``)

    def __len__(self):
        return len(self.points)


_CACHE: dict = {}


def _analytic_at(ex, pts: list, memo: dict) -> tuple[dict, dict, dict]:
    """mech's analytic values and their error bars at ``pts`` (nan and the reason where it has none), each
    point solved once: ``memo`` (parameter values -> (values, errors) or the failure's text) keeps them for
    the lines and limits of the hints, which come back to the given point."""
    names = [o.name for o in ex.outputs]
    vals = {n: np.full(len(pts), np.nan) for n in names}
    errs = {n: np.zeros(len(pts)) for n in names}
    why = {n: [None] * len(pts) for n in names}
    for i, p in enumerate(pts):
        key = _key(ex, p)
        got = memo.get(key)
        if got is None:
            try:
                got = (ex.solve_analytic(p), ex.analytic_errors(p))
            except Exception as exc:  # a point where the analytic route has no answer: not a point to judge at
                got = f"{type(exc).__name__}: {exc}"
            memo[key] = got
        if isinstance(got, str):
            for n in names:
                why[n][i] = got
            continue
        out, aerr = got
        for n in names:
            v = out.get(n)
            if isinstance(v, Undefined):
                why[n][i] = v.why
            elif v is not None and math.isfinite(v):
                vals[n][i] = v
                e = aerr.get(n, 0.0)
                errs[n][i] = float(e) if e is not None and math.isfinite(e) else 0.0
            else:
                why[n][i] = "not finite"
    return vals, errs, why


def _key(ex, p) -> tuple:
    """A point's parameter values, exactly (``-0.0`` apart from ``0.0``), as the memo's key."""
    return tuple(float(p[q.name]).hex() for q in ex.params)


def _make(ex, pts: list, labels: list, memo: dict) -> PointSet:
    arrays = {p.name: np.array([pt[p.name] for pt in pts], dtype=float) for p in ex.params}
    ps = PointSet(ex, pts, labels, arrays, memo=memo)
    ps.analytic, ps.analytic_err, ps.undefined = _analytic_at(ex, pts, memo)
    ps.outside = _outside_theory(ex, pts)
    return ps


def _outside_theory(ex, pts: list) -> dict:
    """For each leading-order output, where its theory does not apply (``Exercise.theory_validity``, where
    the exercise declares its theory's range): there a leading-order formula is not judged."""
    lead = [o.name for o in ex.outputs if o.theory != "exact"]
    validity = getattr(ex, "theory_validity", None)
    out = {n: np.zeros(len(pts), bool) for n in lead}
    if not lead or validity is None:
        return out
    for i, p in enumerate(pts):
        try:
            why = validity(p)
        except Exception:  # no range to read here: the point is judged like any other
            continue
        for n in lead:
            out[n][i] = bool(why.get(n))
    return out


def point_set(ex, given: Params, n: int = DEFAULT_POINTS, seed: int = DEFAULT_SEED,
              over: dict | None = None, known: dict | None = None) -> PointSet:
    """The given point, the defaults, the hard cases (those inside ``over``) and ``n`` drawn points.

    ``known``: the solve's analytic ``{output: (value, err)}`` at the given point (every output), used as
    it is rather than solved again.  The defaults and the hard cases, like the draws, are taken on the
    bounds and joint checks alone (``_accept``): ``resolve``'s representability test would solve the
    analytic answer once more, and a point without a finite answer is not judged anyway."""
    key = (ex.id, tuple(sorted(given.items())), int(n), int(seed), tuple(sorted((over or {}).items())))
    hit = _CACHE.get(key)
    if hit is not None:
        return hit
    pts, labels = [given], ["given"]
    defaults = _accept(ex, {})
    if defaults is not None and dict(defaults) != dict(given) and _in_over(defaults, over):
        pts.append(defaults)
        labels.append("defaults")
    for h in ex.hard_cases:
        try:
            p = _accept(ex, _si(ex, h["params"]))
        except (ValueError, BadInput):
            p = None
        if p is not None and _in_over(p, over) and all(dict(p) != dict(q) for q in pts):
            pts.append(p)
            labels.append("hard case")
    drawn = draw(ex, n, seed, over)
    pts += drawn
    labels += ["drawn"] * len(drawn)
    memo = {}
    if known is not None:
        memo[_key(ex, given)] = ({n: v for n, (v, _) in known.items()}, {n: e for n, (_, e) in known.items()})
    ps = _make(ex, pts, labels, memo)
    ps.in_range = _in_over(given, over)
    if len(_CACHE) > 256:
        _CACHE.clear()
    _CACHE[key] = ps
    return ps


def _si(ex, params: dict) -> dict:
    from mech.core.units import to_si

    return {k: (float(v) if isinstance(v, (int, float)) else to_si(str(v), ex.param_map[k].unit))
            for k, v in params.items()}


def _line(ps: PointSet, name: str, m: int = 7) -> PointSet | None:
    """Points that move only ``name`` from the given point across its range (the others held)."""
    if name in ps.lines:
        return ps.lines[name]
    ex, given = ps.ex, ps.points[0]
    r = ranges(ex)[name]
    a, b = r.t_bounds()
    pts = []
    for t in np.linspace(a, b, m + 2)[1:-1]:
        p = _accept(ex, {**dict(given), name: r.from_t(float(t))})
        if p is not None:
            pts.append(p)
    if len(pts) < 2:
        # the constraints pin it near the given value: move it by a few percent instead
        for f in (0.9, 0.95, 1.05, 1.1):
            v = given[name] * f if given[name] != 0 else (f - 1.0) * _scale_for(ex, ex.param_map[name])
            p = _accept(ex, {**dict(given), name: v})
            if p is not None:
                pts.append(p)
    out = _make(ex, pts, [f"{name} moved"] * len(pts), ps.memo) if len(pts) >= 2 else None
    ps.lines[name] = out
    return out


def depends(ps: PointSet, output: str) -> list[str]:
    """The parameters mech's value of ``output`` changes with, from one-at-a-time moves (its analytic value)."""
    if output in ps.depends:
        return ps.depends[output]
    r0 = ps.analytic[output][0]
    out = []
    for name in ps.ex.param_map:
        line = _line(ps, name)
        if line is None or not math.isfinite(r0):
            continue
        v = line.analytic[output]
        v = v[np.isfinite(v)]
        scale = max(abs(r0), float(np.max(np.abs(v))) if v.size else 0.0)
        if v.size and np.max(np.abs(v - r0)) > 1e-9 * scale + 1e-300:
            out.append(name)
    ps.depends[output] = out
    return out


# -- one formula at the points --------------------------------------------------------------------------

@dataclass
class PointJudgement:
    yours: np.ndarray
    ref: np.ndarray
    right: np.ndarray  # bool
    judged: np.ndarray  # bool: a point with a reference and a finite value of yours, or a domain error
    ill: np.ndarray  # bool: right only in extended precision (ill-conditioned in double)
    problems: list
    tol: np.ndarray


def _judge_points(formula: Formula, ps: PointSet, ref: np.ndarray, ref_err: np.ndarray, rtol: float,
                  alt: dict | None = None) -> PointJudgement:
    env = {k: ps.arrays[k] for k in formula.names}
    y, e, problems = formula.evaluate(env, np.float64) if env else formula.evaluate({"_": np.zeros(len(ps))})
    has_ref = np.isfinite(ref)
    d = np.abs(y - ref)
    base = rtol * np.abs(ref) + ref_err + 4 * np.finfo(float).eps * np.abs(ref)
    tol = base + 4 * e
    right = has_ref & np.isfinite(y) & (d <= tol)
    leans = right & (4 * e > base)  # right only through its own round-off: confirm in extended precision
    retry = (has_ref & np.isfinite(y) & ~right & (e > 0)) | leans
    ill = np.zeros(len(ps), bool)
    if np.any(retry) and np.finfo(np.longdouble).eps < np.finfo(float).eps:
        yl, el, _ = formula.evaluate(env if env else {"_": np.zeros(len(ps))}, np.longdouble)
        dl = np.abs(yl - ref.astype(np.longdouble)).astype(float)
        el = el.astype(float)
        ok_l = dl <= base + 4 * el
        right = np.where(retry, ok_l, right)
        ill = retry & ok_l & (4 * e > base)
    judged = has_ref & (np.isfinite(y) | _masked(problems, len(ps)))
    return PointJudgement(y, ref, right & judged, judged, ill, problems, tol)


def _masked(problems, n) -> np.ndarray:
    m = np.zeros(n, bool)
    for pr in problems:
        m |= np.asarray(pr.mask)
    return m


# -- hints ----------------------------------------------------------------------------------------------

def _nice_factor(c: float) -> str:
    """``2``, ``-1/2``, ``2/pi``, ``sqrt(2)``, ``3 pi/4``: a small fraction times 1, pi, 1/pi, sqrt(2) or
    sqrt(3) when c is one, else c to 6 digits."""
    bases = ((1.0, "", ""), (math.pi, " pi", "pi"), (1 / math.pi, "/pi", "/pi"), (math.sqrt(2), " sqrt(2)", "sqrt(2)"),
             (1 / math.sqrt(2), "/sqrt(2)", "/sqrt(2)"), (math.sqrt(3), " sqrt(3)", "sqrt(3)"),
             (1 / math.sqrt(3), "/sqrt(3)", "/sqrt(3)"), (math.pi / 180, " pi/180 (radians for degrees)", ""),
             (180 / math.pi, " 180/pi (degrees for radians)", ""))
    fits = []
    for k, (val, after, alone) in enumerate(bases):
        f = Fraction(c / val).limit_denominator(64)
        if f != 0 and abs(f.numerator) <= 64 and abs(float(f) * val - c) <= 1e-9 * abs(c):
            fits.append((abs(f.numerator) + f.denominator, k, f))
    for _, k, f in sorted(fits)[:1]:
        val, after, alone = bases[k]
        if True:
            sign = "-" if f < 0 else ""
            n, d = abs(f.numerator), f.denominator
            if val == 1.0:
                return f"{sign}{n}" + (f"/{d}" if d != 1 else "")
            if after.startswith("/"):  # n/(d base)
                return f"{sign}{n}{after}" if d == 1 else f"{sign}{n}/({d}{after.replace('/', ' ', 1).rstrip()})"
            if n == 1 and d == 1 and alone:
                return sign + alone
            return f"{sign}{n if n != 1 else ''}{after}".replace("  ", " ").strip() + (f"/{d}" if d != 1 else "")
    return f"{c:.6g}"


def _const_ratio(yours, ref, tol, mask) -> float | None:
    """The constant c with yours = c * mech at every point of ``mask`` (None when there is none)."""
    use = mask & np.isfinite(yours) & np.isfinite(ref) & (ref != 0)
    if use.sum() < 2:
        return None
    ratios = yours[use] / ref[use]
    c = float(np.median(ratios))
    if c == 1.0 or c == 0.0 or not math.isfinite(c):
        return None
    if np.all(np.abs(yours[use] - c * ref[use]) <= tol[use] * max(1.0, abs(c))):
        return c
    return None


def _ratio_constant(formula: Formula, line: PointSet, output: str, rtol: float) -> bool | None:
    ref = line.analytic[output]
    pj = _judge_points(formula, line, ref, line.analytic_err[output], rtol)
    use = np.isfinite(pj.yours) & np.isfinite(ref)
    if use.sum() < 2:
        return None
    from mech.verification.judge import within

    y, r, t = pj.yours[use], ref[use], pj.tol[use]
    if np.all(r != 0):
        c = float(np.median(y / r))
        return bool(np.all(within(np.abs(y - c * r), t * max(1.0, abs(c)))))
    return bool(np.all(within(np.abs(y - r), t)))


def _follows(formula: Formula, ps: PointSet, output: str, rtol: float) -> tuple[list, list]:
    innocent, guilty = [], []
    for name in ps.ex.param_map:
        line = _line(ps, name)
        if line is None:
            continue
        c = _ratio_constant(formula, line, output, rtol)
        if c is True:
            innocent.append(name)
        elif c is False:
            guilty.append(name)
    return innocent, guilty


def _limits(formula: Formula, ps: PointSet, output: str) -> list[tuple[str, str, bool]]:
    """The limits in which the formula becomes mech's answer: ``(what, parameter, first_order)`` for each
    parameter whose move toward zero (or its lower bound, or without bound) makes the relative mismatch
    fall steadily to nothing.  ``first_order``: the mismatch also vanishes against the answer's own change
    from its limit value, as a leading-order formula's does (``omega0*exp(+x)`` for ``omega0*exp(-x)`` also
    meets mech's value as x -> 0, but misses the first-order change by a factor -1: not an approximation)."""
    ex, given = ps.ex, ps.points[0]
    r_given = ps.analytic[output][0]
    if not math.isfinite(r_given) or r_given == 0:
        return []
    r0 = abs(ps_yours_at_given(formula, ps) - r_given) / abs(r_given)
    if not r0 > 1e-12:
        return []
    found = []
    for direction, word in ((0.01, "small"), (100.0, "large")):
        for name in ex.param_map:
            p = ex.param_map[name]
            v0 = given[name]
            if v0 == 0:
                continue
            what = f"{word} {name}"
            vals = [v0 * direction**j for j in range(1, 6)]
            if direction < 1 and p.min is not None and p.min > 0:
                # toward the lower bound: shrink the distance to it
                vals = [p.min + (v0 - p.min) * direction**j for j in range(1, 6)] if v0 > p.min else []
                what = f"{name} near {p.min:g}"
            key = ("limit", name, direction)
            if key not in ps.lines:  # mech's values along the line, once per point set (a class file)
                pts = [q for q in (_accept(ex, {**dict(given), name: v}) for v in vals) if q is not None]
                ps.lines[key] = (_make(ex, [given] + pts, ["limit"] * (len(pts) + 1), ps.memo)
                                 if len(pts) >= 3 else None)
            line = ps.lines[key]
            if line is None:
                continue
            pts = line.points[1:]
            ref = line.analytic[output]
            env = {k: line.arrays[k] for k in formula.names} or {"_": np.zeros(len(pts) + 1)}
            y, _, _ = formula.evaluate(env)
            if not (np.all(np.isfinite(ref)) and np.all(np.isfinite(y)) and np.all(ref != 0)):
                continue
            rel = np.abs(y - ref) / np.abs(ref)
            above = rel > 1e-11  # past that the mismatch is round-off: no trend to read
            steady = all(b < a for a, b, keep in zip(rel[:-1], rel[1:], above[1:]) if keep)
            if not (steady and rel[-1] < 1e-3 * rel[0]):
                continue
            change = np.abs(ref[:-2] - ref[-1])  # the answer's own change from (nearly) its limit
            with np.errstate(all="ignore"):
                q = np.abs(y[:-2] - ref[:-2]) / change
            # converging to nothing, also at the end of the line (not only leaving a peak at the given point)
            first = bool(np.all(np.isfinite(q)) and q[-1] < 0.1 and q[-1] < 1e-2 * q[0] and q[-1] < 0.5 * q[-2])
            found.append((what, name, first))
    return found


def _approximation(formula: Formula, ps: PointSet, output: str, missing: list[str]) -> str | None:
    """"this is the leading-order approximation; it holds only for small X", when it is: the limit value
    of an answer that depends on a parameter the formula leaves out (T = 2 pi sqrt(l/g) for the pendulum),
    or a formula right to first order in a parameter going to its limit."""
    found = _limits(formula, ps, output)
    r_given = ps.analytic[output][0]
    off = abs(ps_yours_at_given(formula, ps) - r_given) / abs(r_given)
    # the limit value of an answer whose dependence on that parameter it leaves out, near the given
    # parameters (T = 2 pi sqrt(l/g) at 60 deg is 7 % short; m v for m (v + v0) is 94 %: a term left out)
    named = [w for w, k, _ in found if k in missing] if off < 0.25 else []
    if not named and off < 0.1:
        # a formula right to first order in a limit, and close at the given parameters (where it is meant
        # to hold): a formula 2x off there that only shares the limit's power law is not an approximation
        named = [w for w, _, first in found if first]
    if not named:
        return None
    said = named[0] if len(named) == 1 else ", ".join(named[:-1]) + " or " + named[-1]
    return f"this is the leading-order approximation; it holds only for {said}"


def _known_approximation(ps: PointSet, output: str, yours: np.ndarray, tol: np.ndarray) -> str | None:
    """The description of an approximation the exercise declares (``@exercise.approximations``: 5.5, 5.6, 5.7)
    that the formula gives at every point, or None."""
    at = getattr(ps.ex, "approximations_at", None)
    if at is None:
        return None
    found: dict[str, int] = {}
    n = 0
    for i, p in enumerate(ps.points):
        if not math.isfinite(yours[i]):
            continue
        try:
            cands = at(p).get(output) or []
        except Exception:  # an approximation with no value here: not one the formula can be matched to
            return None
        n += 1
        for value, desc in cands:
            if isinstance(value, (int, float)) and abs(yours[i] - value) <= tol[i] + 1e-9 * abs(value):
                found[desc] = found.get(desc, 0) + 1
    full = [d for d, k in found.items() if k == n]
    return full[0] if n and full else None


def _other_output(formula: Formula, ps: PointSet, output, yours: np.ndarray, rtol: float) -> str | None:
    """"that is mech's omega2": the formula gives another output of the same dimension at every point."""
    _, dim = dim_of_unit(output.unit)
    for o in ps.ex.outputs:
        if o.name == output.name or dim_of_unit(o.unit)[1] != dim:
            continue
        ref = ps.analytic[o.name]
        use = np.isfinite(ref)
        if use.sum() >= 2 and np.all(np.abs(yours[use] - ref[use]) <= rtol * np.abs(ref[use]) + ps.analytic_err[o.name][use]
                                     + 1e-12 * np.abs(ref[use])):
            return f"that is mech's {o.name}, not its {output.name}"
    return None


def ps_yours_at_given(formula: Formula, ps: PointSet) -> float:
    env = {k: ps.arrays[k][:1] for k in formula.names} or {"_": np.zeros(1)}
    return float(formula.evaluate(env)[0][0])


def _fmt_point(ps: PointSet, i: int) -> str:
    ex, p, g = ps.ex, ps.points[i], ps.points[0]
    if i == 0:
        return "at the given parameters"
    moved = [q for q in ex.params if p[q.name] != g[q.name]]
    return "at " + ", ".join(f"{q.name} = {q.show(p[q.name])}" for q in (moved or ex.params))


def show_value(v: float, unit: str, digits: int = 6) -> str:
    """A value in the output's unit (an angle also in degrees)."""
    if not math.isfinite(v):
        return "not a number" if math.isnan(v) else str(v)
    u = "" if unit == "1" else f" {unit}"
    if unit == "rad":
        return f"{v:.{digits}g} rad ({math.degrees(v):.{digits}g} deg)"
    return f"{v:.{digits}g}{u}"


def show_pair(yours: float, mech: float, unit: str) -> tuple[str, str]:
    """Both values with enough digits (6 at least) to show where they differ."""
    for digits in range(6, 18):
        a, b = show_value(yours, unit, digits), show_value(mech, unit, digits)
        if a != b:
            return a, b
    return a, b


# -- the verdict ----------------------------------------------------------------------------------------

@dataclass
class FormulaVerdict:
    match: bool
    verdict: str
    hint: str | None
    value: float  # yours at the given point
    reference_value: float | None
    rel_err: float | None
    tol: float | None
    dimension: dict
    points: dict
    depends: list
    formula: str


def _problem_text(pj: PointJudgement, ps: PointSet, i: int) -> str | None:
    for pr in pj.problems:
        if pr.mask[i]:
            x = float(pr.args[i]) if np.ndim(pr.args) else float(pr.args)
            return pr.what.replace("{x}", f"{x:.6g}")
    return None


def judge_formula(formula: Formula, ex, output, ps: PointSet, given_ref, rtol: float | None,
                  numeric_given: tuple | None = None, given_in_range: bool = True) -> FormulaVerdict:
    """Judge ``formula`` for ``output`` (a spec Output) over the point set ``ps``.

    ``given_ref``: (value, err) of mech's trusted reference at the given point (None when there is none);
    ``numeric_given``: (value, err) of the verified numeric value there, for a leading-order output;
    ``given_in_range``: False when the given parameters lie outside the range the formula is meant to hold
    in (``over``): then it is judged at the other points only.
    """
    _, out_dim = dim_of_unit(output.unit)
    dimension = {"ok": formula.dim == out_dim, "yours": dim_text(formula.dim) if formula.dim else None,
                 "output": output.unit}
    base = dict(formula=formula.text, dimension=dimension, depends=[])
    if formula.dim is None or formula.dim != out_dim:
        why = (f"your formula has the dimension of {dim_text(formula.dim)}; {output.name} is in {output.unit}"
               if formula.dim is not None else f"your formula mixes dimensions: {formula.dim_error}")
        if formula.dim is None:
            dimension["error"] = formula.dim_error
        return FormulaVerdict(False, f"wrong dimension: {why}", why, math.nan, None, None, None,
                              points={"checked": 0, "right": 0}, **base)
    rtol = FORMULA_RTOL if rtol is None else rtol
    name = output.name
    lead = output.theory != "exact"
    ref = ps.analytic[name].copy()
    ref_err = ps.analytic_err[name].copy()
    if given_ref is None or not given_in_range:
        ref[0] = np.nan
    elif not lead:
        ref[0], ref_err[0] = given_ref
    pj = _judge_points(formula, ps, ref, ref_err, rtol)
    notes = []
    if lead:
        exact_here = _leading_order_numeric(formula, ex, output, ps, pj, rtol, numeric_given, notes)
        outside = ps.outside.get(name, np.zeros(len(ps), bool)) & ~exact_here
        if outside.any():
            # beyond its theory's range the leading-order value is no answer and the exact one is not what
            # was asked: such points are left out (a formula that matches the exact value there is right)
            pj.judged = pj.judged & ~outside
            pj.right = pj.right & ~outside
            k = int(outside.sum())
            notes.append(f"{k} point{'s' if k > 1 else ''} outside the leading-order theory's range not judged")
    judged = pj.judged
    wrong = judged & ~pj.right
    n_checked, n_right = int(judged.sum()), int(pj.right.sum())
    y0 = float(pj.yours[0])
    r0 = float(ref[0]) if math.isfinite(ref[0]) else None
    rel0 = abs(y0 - r0) / abs(r0) if r0 not in (None, 0.0) and math.isfinite(y0) else None
    worst_i = _worst(pj, ref)
    points = {"checked": n_checked, "right": n_right}
    if worst_i is not None:
        points["worst"] = {"params": dict(ps.points[worst_i]), "label": ps.labels[worst_i],
                           "yours": _finite(pj.yours[worst_i]), "mech": _finite(ref[worst_i]),
                           "rel_err": _finite(abs(pj.yours[worst_i] - ref[worst_i]) / abs(ref[worst_i])
                                              if ref[worst_i] else abs(pj.yours[worst_i] - ref[worst_i]))}
    ill = [i for i in range(len(ps)) if pj.ill[i]]
    if ill:
        points["ill_conditioned"] = len(ill)
    kinds = _kinds(ps, judged)
    if given_ref is None and given_in_range:
        return FormulaVerdict(False, "cannot judge: mech has no trusted value at the given parameters", None, y0,
                              None, None, None, points=points, **base)
    if n_checked == 0:
        return FormulaVerdict(False, "cannot judge: mech has no value at any point", None, y0, r0, rel0, None,
                              points=points, **base)
    if not wrong.any():
        text = f"right at all {n_checked} points ({kinds})"
        if ill:
            text += (f"; ill-conditioned in double precision {_fmt_point(ps, ill[0])} (right in extended "
                     "precision)")
        text += "".join(f"; {n}" for n in notes)
        return FormulaVerdict(True, text, None, y0, r0, rel0, float(pj.tol[0]), points=points, **base)
    # wrong: find what a student can act on
    i_fail = int(np.flatnonzero(wrong)[0])
    hint = None
    dom = [i for i in np.flatnonzero(wrong) if _problem_text(pj, ps, int(i))]
    if dom:
        i_fail = int(dom[0])
        hint = f"cannot be evaluated {_fmt_point(ps, i_fail)}: {_problem_text(pj, ps, i_fail)}"
    innocent, guilty = [], []
    if hint is None:
        c = _const_ratio(pj.yours, ref, pj.tol, judged)
        if c is not None:
            hint = "wrong sign" if c == -1.0 else f"off by a constant factor {_nice_factor(c)} at every point"
    if hint is None:
        hint = _other_output(formula, ps, output, pj.yours, rtol)
    if hint is None:
        deps = depends(ps, name)
        missing = [k for k in deps if k not in formula.names]
        if output.theory == "exact":
            known = _known_approximation(ps, name, pj.yours, pj.tol)
            hint = _approximation(formula, ps, name, missing + list(formula.names) if known else missing)
            if known:  # "this is the small-amplitude period ..., a leading-order approximation; it holds only ..."
                hint = f"this is {known}, a leading-order approximation" + (
                    "; " + hint.replace("this is the leading-order approximation; ", "") if hint else "")
        if hint is None and missing:
            hint = f"mech's {name} depends on {_and(missing)}, which your formula leaves out"
    if hint is None or hint.startswith("mech's"):
        innocent, guilty = _follows(formula, ps, name, rtol)
        if hint is not None and innocent and pj.right[0]:
            hint = f"right when only {_and(innocent)} {_change(innocent)}, but {hint}"
        if hint is None and guilty and innocent:
            if pj.right[0]:
                hint = (f"right when only {_and(innocent)} {_change(innocent)}; check how your formula depends on "
                        f"{_and(guilty)}")
            else:
                hint = (f"off by a factor that does not change with {_and(innocent)}; check how your formula "
                        f"depends on {_and(guilty)}")
    base["depends"] = guilty
    ys, ms = show_pair(float(pj.yours[i_fail]), float(ref[i_fail]), output.unit)
    at = f"{_fmt_point(ps, i_fail)}: yours {ys}, mech {ms}"
    head = f"wrong at {int(wrong.sum())} of {n_checked} points" + "".join(f" ({n})" for n in notes)
    verdict = f"{head}: {hint}; {at}" if hint else f"{head}; {at}"
    return FormulaVerdict(False, verdict, hint, y0, r0, rel0, float(pj.tol[0]), points=points, **base)


def _change(names: list[str]) -> str:
    return "changes" if len(names) == 1 else "change"


def _and(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def _kinds(ps: PointSet, judged: np.ndarray) -> str:
    """Which points were judged: ``the given parameters, 24 drawn across the range, 1 hard case``."""
    labels = [lab for lab, j in zip(ps.labels, judged) if j]
    n = {k: labels.count(k) for k in ("given", "drawn", "defaults", "hard case")}
    parts = ["the given parameters"] if n["given"] else []
    if n["drawn"]:
        parts.append(f"{n['drawn']} drawn across the range")
    if n["defaults"]:
        parts.append("the defaults")
    if n["hard case"]:
        parts.append(f"{n['hard case']} hard case{'s' if n['hard case'] > 1 else ''}")
    return ", ".join(parts)


def _finite(v):
    v = float(v)
    return v if math.isfinite(v) else None


def _worst(pj: PointJudgement, ref) -> int | None:
    use = np.flatnonzero(pj.judged)
    if use.size == 0:
        return None
    with np.errstate(all="ignore"):
        d = np.abs(pj.yours - ref) / np.where(ref != 0, np.abs(ref), 1.0)
    d = np.where(np.isfinite(d), d, np.inf)
    return int(use[np.argmax(d[use])])


def _leading_order_numeric(formula, ex, output, ps, pj, rtol, numeric_given, notes) -> np.ndarray:
    """A leading-order output: a point that misses the leading-order value is right when it matches the
    verified numeric value there (the given point: the cross-check's; elsewhere: solved here, within a
    budget, stopping at the first point the numeric value does not confirm).  Where the exercise has a
    batched route for the output, the references come from it: the first point alone (a wrong formula
    stops there), then the rest at once."""
    name = output.name
    misses = [i for i in range(len(ps)) if pj.judged[i] and not pj.right[i] and math.isfinite(pj.yours[i])]
    t0 = time.perf_counter()
    confirmed = 0
    exact_here = np.zeros(len(ps), bool)
    batched = _batchable(ex, name)
    for i in misses:
        if i == 0:
            if numeric_given is None:
                break
            n, err = numeric_given
        else:
            if time.perf_counter() - t0 > NUMERIC_BUDGET_S:
                notes.append("the numeric reference ran out of time")
                break
            if batched and (name, i) not in ps.numeric:
                later = [j for j in misses if j >= i]
                _batched_numeric(ex, ps, later[:1] if confirmed == 0 else later[:BATCH], name)
            got = _verified_at(ex, ps, i, name)
            if got is None:
                break
            n, err = got
        if abs(pj.yours[i] - n) <= rtol * abs(n) + err + 4 * np.finfo(float).eps * abs(n):
            pj.right[i] = True
            exact_here[i] = True
            confirmed += 1
        else:
            break
    if confirmed:
        notes.append(f"at {confirmed} point{'s' if confirmed > 1 else ''} it matches mech's numeric value "
                     "rather than the leading-order one")
    return exact_here


BATCH = 32  # points a batched numeric call takes at once (the budget is looked at between calls)


def _batchable(ex, name: str) -> bool:
    """Does ``ex`` have a batched route for ``name``, with a rerun tighter than its default rtol?"""
    route = getattr(ex, "batched_route", None)
    return (route is not None and name in route.outputs
            and max(ex.default_rtol / 10.0, ex.min_rtol) < ex.default_rtol)


def _batched_numeric(ex, ps: PointSet, idx: list[int], name: str) -> None:
    """The verified numeric values of ``name`` at the points ``idx`` from the exercise's batched route, into
    ``ps.numeric`` as ``_verified_at`` keeps them: (value, its claim), or None where the route finds no value
    or its rerun moves the value beyond the claim (the judge's rule: ``judge.within``); a batch that fails
    as a whole leaves its points to ``_verified_at``."""
    import inspect

    from mech.verification.judge import within

    idx = [i for i in idx if (name, i) not in ps.numeric]
    if not idx:
        return
    route = ex.batched_route
    rtol = ex.default_rtol
    tighter = max(rtol / 10.0, ex.min_rtol)
    P = {k: ps.arrays[k][idx] for k in ex.param_map}
    takes_memo = "memo" in inspect.signature(route.numeric).parameters
    try:
        cols = [(route.numeric(P, tol, (name,), memo=ps.batch_memo) if takes_memo
                 else route.numeric(P, tol, (name,)))[name] for tol in (rtol, tighter)]
    except Exception:  # a failed batch: these points are verified one by one instead (``_verified_at``)
        return
    n, v = cols
    shape = n.value.shape
    rel = np.broadcast_to(np.asarray(n.rel, dtype=float), shape)
    tol_abs = np.broadcast_to(np.asarray(n.abs, dtype=float), shape)
    with np.errstate(all="ignore"):
        a = ps.analytic[name][idx]
        scale = np.where(np.isfinite(a) & (a != 0), np.abs(a), np.abs(n.value))
        claim = rel * scale + tol_abs  # what the rerun may move it by (the judge's ``claim``)
        err = rel * np.abs(n.value) + tol_abs  # its error bar (the judge's ``numeric_err``)
        gone = n.mask("undefined") | n.mask("failed") | v.mask("undefined") | v.mask("failed")
        ok = (~gone & np.isfinite(n.value) & np.isfinite(v.value) & np.isfinite(err)
              & within(np.abs(v.value - n.value), claim))
    for j, i in enumerate(idx):
        ps.numeric[(name, i)] = (float(n.value[j]), float(err[j])) if ok[j] else None


def _verified_at(ex, ps: PointSet, i: int, name: str):
    key = (name, i)
    if key in ps.numeric:
        return ps.numeric[key]
    from mech.verification.judge import within

    got = None
    try:
        rtol = ex.default_rtol
        v1, run = ex.solve_numeric(ps.points[i], rtol)
        v2, _ = ex.solve_numeric(ps.points[i], max(rtol / 10, ex.min_rtol))
        a, b = v1.get(name), v2.get(name)
        if isinstance(a, float) and isinstance(b, float) and math.isfinite(a) and math.isfinite(b):
            # the output's own claim where the solve declared one (an abs claim for a value that can be 0)
            rel, ab = run.claims.get(name, (None, None))
            claim = (ex.tol_factor * rtol if rel is None else rel) * abs(a) + (ab or 0.0)
            if within(abs(a - b), claim):
                got = (a, claim)
    except Exception:  # a numeric failure there: no verified value, the point stays wrong
        got = None
    ps.numeric[key] = got
    return got


# -- the seam with the answers judge --------------------------------------------------------------------

def _known(result) -> dict | None:
    """The solve's analytic values and error bars at its parameters, ``{output: (value, err)}``, when it
    solved every output analytically (a value or an Undefined); else None (the point set solves them)."""
    known = {}
    for q in result.quantities:
        if q.analytic is None or (result.errors and any(f.kind == "analytic" for f in result.errors)):
            return None
        known[q.name] = (q.analytic, q.analytic_err)
    return known


def judge_expectation(result, e, q, ref):
    """An ``answers.Judgement`` for the formula expectation ``e`` on output ``q`` of a cross-check
    ``result``, ``ref`` being the answers judge's reference at the given parameters."""
    from mech.verification.answers import Judgement, numeric_err

    ex, given = result.exercise, result.params
    output = {o.name: o for o in ex.outputs}[e.name]
    over = dict(e.over) if e.over else None
    ps = point_set(ex, given, e.points if e.points is not None else DEFAULT_POINTS,
                   e.seed if e.seed is not None else DEFAULT_SEED, over, _known(result))
    lead = output.theory != "exact"
    if ref.value is None:
        given_ref, numeric_given = None, None
    elif lead:
        a = q.analytic
        given_ref = (float(a), 0.0) if isinstance(a, float) and math.isfinite(a) else None
        verified = getattr(q, "verify_diff", None) is not None
        n = q.numeric
        numeric_given = ((float(n), numeric_err(q)) if verified and isinstance(n, float) and math.isfinite(n)
                         else None)
        if given_ref is None and numeric_given is not None:
            given_ref = numeric_given
    else:
        given_ref, numeric_given = (float(ref.value), float(ref.err)), None
    in_range = _in_over(given, over)
    undefined_here = ref.value is None and ref.why.startswith("mech finds no finite value")
    if undefined_here:  # judged at the other points; the given one has no value to hold it against
        in_range = False
    with np.errstate(all="ignore"):  # a formula may overflow anywhere in the range: judged, not warned
        v = judge_formula(e.formula, ex, output, ps, given_ref, e.rtol, numeric_given, in_range)
    if undefined_here:
        v.verdict += f" ({ref.why.replace('mech finds no finite value here', 'not at the given parameters')})"
    verdict = v.verdict
    if given_ref is None and not v.hint and not undefined_here:
        verdict = f"cannot judge: {ref.why or 'mech has no trusted value here'}"
    return Judgement(
        name=e.name, unit=q.unit, text=e.text, value=v.value, match=v.match, theory=q.theory,
        reference=(ref.label if ref.value is not None else None), reference_value=v.reference_value,
        rel_err=v.rel_err, tol=v.tol, hint=v.hint, verdict=verdict,
        shown_reference=show_value(v.reference_value, q.unit) if v.reference_value is not None else "",
        formula={"formula": v.formula, "dimension": v.dimension, "points": v.points, "depends": v.depends})
