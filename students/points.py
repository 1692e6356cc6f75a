"""The points a formula is judged at: parameter sets drawn across an exercise's declared range, mech's
analytic values there, and a formula's values held against them by the judge's rule.

The points are the given parameters, the defaults, the catalogue's hard cases and ``n`` parameter sets drawn
across every parameter's declared bounds (log-uniform on a positive range), inside the exercise's joint
constraints.  Where an exercise refuses most of its box, a draw it refuses is repaired one parameter at a
time: with the others held, that parameter's allowed interval is found on a grid and refined by bisection,
and the value is drawn inside it.

A point is right when its exact value is (parameters exact as the doubles they are, numbers exact as
written), certified: an interval enclosure in double precision (``Formula.enclose``), and where it straddles
an edge of the allowance, mpmath intervals at rising precision up to ``MAX_PREC`` bits (``_precise``); a
point nothing decides is not graded.  The allowance is mech's: ``rtol |mech| + mech's error bar + 4 ulp +
64 ulp of the output's scale`` (``output_scale``; ``rtol`` times it where mech's value is exactly 0), never
the formula's own round-off.  A right formula that only loses digits in double is said to be
ill-conditioned there.

The point set and mech's values are computed once per exercise, given point and range (``_CACHE``, bounded
in bytes: ``CACHE_BYTES``): a class file judges every student's formula against the same arrays.  Every
loop looks at the budget (``core.budget.check``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from mech.core import budget
from mech.core.safeio import shown
from mech.problems.solving import constraint_message
from mech.problems.spec import BadInput, Params, Undefined
from mech.problems.validity import analytic_errors
from mech.students.formula_ast import MAX_PREC, Formula, Problem
from mech.verification.judge import allowance, theory_validity, within

__all__ = ["DEFAULT_POINTS", "DEFAULT_SEED", "MAX_POINTS", "CACHE_BYTES", "PointSet", "PointJudgement", "point_set", "draw", "ranges",
           "parse_over", "depends", "line_of", "accept", "make", "judge_points", "yours_at_given", "describe_point",
           "problem_text", "in_over", "decide", "holds_at", "output_scale", "RIGHT", "WRONG", "OPEN"]

DEFAULT_POINTS = 24
# parameter sets a formula may ask to be judged at (``--expect-points``, ``points =``): drawing them, mech's
# values there and the judging all run under the budget, which cuts a check that would run longer
MAX_POINTS = 10_000

DEFAULT_SEED = 20240524


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


def accept(ex, values: dict) -> Params | None:
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
        return not constraint_message(ex, params)
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
        p = accept(ex, {**x, r.name: r.from_t(t)})
        if p is None:
            p = accept(ex, {**x, r.name: r.from_t(grid[i])})
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
    return accept(ex, at(rng.uniform(0.0, s_ok))) or accept(ex, base)


def _representable(r: _Range, v: float) -> bool:
    return not (r.kind == "log" and v <= 0)


def in_over(p: Params, over: dict | None) -> bool:
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
        budget.check("drawing the points")
        x = {k: r.draw(rng) for k, r in rs.items()}
        p = accept(ex, x) or _repair(ex, x, rs, rng) or _toward(ex, base, x, rs, rng)
        if p is not None and in_over(p, over):
            out.append(p)
    return out


def parse_over(ex, over: dict) -> dict[str, tuple[float, float]]:
    """``{"theta0": "10deg:60deg"}`` -> ``{"theta0": (lo, hi)}`` in SI, each inside the declared bounds."""
    from mech.core.units import ValueError_, to_si

    out = {}
    for raw, text in over.items():
        name = str(raw).strip().replace("-", "_")
        if name not in ex.param_map:
            raise BadInput(f"not a parameter of {ex.id}; its parameters are: {', '.join(ex.param_map)}",
                           field=f"over.{shown(raw, 40)}", kind="unknown")
        p = ex.param_map[name]
        if not isinstance(text, str) or text.count(":") != 1:
            raise BadInput("give a range LO:HI such as \"10deg:60deg\"", field=f"over.{shown(raw, 40)}", kind="syntax")
        lo_s, hi_s = text.split(":")
        try:
            lo, hi = to_si(lo_s, p.unit), to_si(hi_s, p.unit)
            p.check(lo, lo_s)
            p.check(hi, hi_s)
        except (ValueError_, BadInput) as exc:
            why = exc.reason if isinstance(exc, BadInput) else str(exc)
            raise BadInput(shown(why, 120), field=f"over.{shown(raw, 40)}", kind=getattr(exc, "kind", None) or "value") from None
        if not lo < hi:
            raise BadInput(f"{shown(text, 40)}: the low end must be below the high end", field=f"over.{shown(raw, 40)}",
                           kind="range")
        out[name] = (lo, hi)
    if out and not draw(ex, 1, DEFAULT_SEED, out):  # a range the joint limits leave empty: a bad input
        ranges_text = ", ".join(f"{shown(k, 20)} = {shown(v, 40)}" for k, v in over.items())
        raise BadInput(f"over: no parameters of {ex.id} inside {ranges_text} meet its joint limits "
                       "(mech show lists them)")
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


_CACHE: dict = {}  # key -> PointSet, oldest first; bounded in bytes (``CACHE_BYTES``), not in entries
CACHE_BYTES = 64 * 2**20


def size_of(ps: PointSet) -> int:
    """An upper estimate of a point set's memory, bytes: per point its Params, its arrays, its memo entry
    (measured with tracemalloc: 1.1 kB a point for 4.15's 3 parameters and 2 outputs, 1.3 kB for 4.32's 4
    and 3; this says 1.65 and 2.15 kB)."""
    width = len(ps.arrays) + len(ps.analytic)
    return len(ps) * (400 + 250 * width)


def _remember(key, ps: PointSet) -> None:
    """Keep ``ps`` for the next formula judged at the same points, dropping the oldest beyond
    ``CACHE_BYTES``; a point set larger than the whole cache is not kept."""
    size = size_of(ps)
    if size > CACHE_BYTES:
        return
    total = sum(size_of(v) for v in _CACHE.values()) + size
    for old in list(_CACHE):
        if total <= CACHE_BYTES:
            break
        total -= size_of(_CACHE.pop(old))
    _CACHE[key] = ps


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
            budget.check("working out mech's values at the points")
            try:
                got = (ex.solve_analytic(p), analytic_errors(ex, p))
            except budget.OutOfBudget:
                raise
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


def make(ex, pts: list, labels: list, memo: dict, outside_memo: dict | None = None) -> PointSet:
    arrays = {p.name: np.array([pt[p.name] for pt in pts], dtype=float) for p in ex.params}
    ps = PointSet(ex, pts, labels, arrays, memo=memo)
    ps.analytic, ps.analytic_err, ps.undefined = _analytic_at(ex, pts, memo)
    ps.outside = _outside_theory(ex, pts, outside_memo)
    return ps


def _outside_theory(ex, pts: list, memo: dict | None = None) -> dict:
    """For each leading-order output, where its theory does not apply (``validity.theory_validity``, where
    the exercise declares its theory's range): there a leading-order formula is not judged.  ``memo``:
    parameter values -> the reasons there, kept across calls."""
    lead = [o.name for o in ex.outputs if o.theory != "exact"]
    out = {n: np.zeros(len(pts), bool) for n in lead}
    if not lead:
        return out
    for i, p in enumerate(pts):
        key = _key(ex, p) if memo is not None else None
        why = memo.get(key) if memo is not None else None
        if why is None:
            try:
                why = theory_validity(ex, p)
            except budget.OutOfBudget:
                raise
            except Exception:  # no range to read here: the point is judged like any other
                why = {}
            if memo is not None:
                memo[key] = why
        for n in lead:
            out[n][i] = bool(why.get(n))
    return out


def point_set(ex, given: Params, n: int = DEFAULT_POINTS, seed: int = DEFAULT_SEED,
              over: dict | None = None, known: dict | None = None) -> PointSet:
    """The given point, the defaults, the hard cases (those inside ``over``) and ``n`` drawn points.

    ``known``: the solve's analytic ``{output: (value, err)}`` at the given point (every output), used as
    it is rather than solved again.  The defaults and the hard cases, like the draws, are taken on the
    bounds and joint checks alone (``accept``): ``resolve``'s representability test would solve the
    analytic answer once more, and a point without a finite answer is not judged anyway."""
    key = (ex.id, tuple(sorted(given.items())), int(n), int(seed), tuple(sorted((over or {}).items())))
    hit = _CACHE.pop(key, None)
    if hit is not None:
        _CACHE[key] = hit  # the most recent last
        return hit
    base = _shared_part(ex, n, seed, over)
    pts, labels = [given], ["given"]
    defaults, hards, drawn = base["defaults"], base["hards"], base["drawn"]
    if defaults is not None and dict(defaults) != dict(given) and in_over(defaults, over):
        pts.append(defaults)
        labels.append("defaults")
    for p in hards:
        if p is not None and in_over(p, over) and all(dict(p) != dict(q) for q in pts):
            pts.append(p)
            labels.append("hard case")
    pts += drawn
    labels += ["drawn"] * len(drawn)
    memo = dict(base["memo"])  # this point set's own copy: its lines and limits are added to it alone
    if known is not None:
        memo[_key(ex, given)] = ({n: v for n, (v, _) in known.items()}, {n: e for n, (_, e) in known.items()})
    ps = make(ex, pts, labels, memo, base["outside"])
    ps.in_range = in_over(given, over)
    _remember(key, ps)
    return ps


_SHARED: dict = {}  # (exercise, n, seed, over) -> what every given point's set has in common


def _shared_part(ex, n: int, seed: int, over: dict | None) -> dict:
    """The part of ``point_set`` that does not depend on the given point, computed once for every student
    of a class: the defaults, the hard cases and the drawn points (all taken on the bounds and joint
    checks alone), mech's analytic values there (the memo a point set copies) and where each output's
    theory applies there.  Each is a function of its point alone, so sharing it changes no value."""
    key = (ex.id, int(n), int(seed), tuple(sorted((over or {}).items())))
    hit = _SHARED.get(key)
    if hit is not None:
        return hit
    hards = []
    for h in ex.hard_cases:
        try:
            hards.append(accept(ex, _si(ex, h["params"])))
        except (ValueError, BadInput):
            hards.append(None)
    base = {"defaults": accept(ex, {}), "hards": hards, "drawn": draw(ex, n, seed, over), "memo": {}, "outside": {}}
    rest = [p for p in [base["defaults"], *hards, *base["drawn"]] if p is not None]
    _analytic_at(ex, rest, base["memo"])
    _outside_theory(ex, rest, base["outside"])
    # bounded like _CACHE, in bytes (``size_of``'s estimate per point), the oldest dropped first
    size = len(rest) * (400 + 250 * (len(ex.params) + len(ex.outputs)))
    if size <= CACHE_BYTES:
        total = sum(v["bytes"] for v in _SHARED.values()) + size
        for old in list(_SHARED):
            if total <= CACHE_BYTES:
                break
            total -= _SHARED.pop(old)["bytes"]
        base["bytes"] = size
        _SHARED[key] = base
    return base


def _si(ex, params: dict) -> dict:
    from mech.core.units import to_si

    return {k: (float(v) if isinstance(v, (int, float)) else to_si(str(v), ex.param_map[k].unit))
            for k, v in params.items()}


def line_of(ps: PointSet, name: str, m: int = 7) -> PointSet | None:
    """Points that move only ``name`` from the given point across its range (the others held)."""
    if name in ps.lines:
        return ps.lines[name]
    ex, given = ps.ex, ps.points[0]
    r = ranges(ex)[name]
    a, b = r.t_bounds()
    pts = []
    for t in np.linspace(a, b, m + 2)[1:-1]:
        p = accept(ex, {**dict(given), name: r.from_t(float(t))})
        if p is not None:
            pts.append(p)
    if len(pts) < 2:
        # the constraints pin it near the given value: move it by a few percent instead
        for f in (0.9, 0.95, 1.05, 1.1):
            v = given[name] * f if given[name] != 0 else (f - 1.0) * _scale_for(ex, ex.param_map[name])
            p = accept(ex, {**dict(given), name: v})
            if p is not None:
                pts.append(p)
    out = make(ex, pts, [f"{name} moved"] * len(pts), ps.memo) if len(pts) >= 2 else None
    ps.lines[name] = out
    return out


def depends(ps: PointSet, output: str) -> list[str]:
    """The parameters mech's value of ``output`` changes with, from one-at-a-time moves (its analytic value)."""
    if output in ps.depends:
        return ps.depends[output]
    r0 = ps.analytic[output][0]
    out = []
    for name in ps.ex.param_map:
        line = line_of(ps, name)
        if line is None or not math.isfinite(r0):
            continue
        v = line.analytic[output]
        v = v[np.isfinite(v)]
        scale = max(abs(r0), float(np.max(np.abs(v))) if v.size else 0.0)
        if v.size and not within(np.max(np.abs(v - r0)), scale=scale, bars=(1e-300,), round_off=1e-9):
            out.append(name)
    ps.depends[output] = out
    return out


# -- one formula at the points --------------------------------------------------------------------------


@dataclass
class PointJudgement:
    yours: np.ndarray  # the formula's value in double (shown; the exact one where worked out in high precision)
    ref: np.ndarray
    right: np.ndarray  # bool: right in exact arithmetic (certified)
    judged: np.ndarray  # bool: a point with a reference where the verdict was decided (or a domain error)
    ill: np.ndarray  # bool: right in exact arithmetic, not within the allowance in double (ill-conditioned there)
    problems: list
    tol: np.ndarray  # the allowance, absolute: from mech's reference, its error bar, rtol and the output's scale
    skipped: int = 0  # points left unjudged: double precision could not decide them, and others were wrong
    lo: np.ndarray | None = None  # the certified enclosure of the exact value (double precision)
    hi: np.ndarray | None = None
    undecided: np.ndarray | None = None  # bool: no precision up to MAX_PREC decides the point (not graded)


RIGHT, WRONG, OPEN = 1, 0, -1  # a point's verdict from an enclosure: right, wrong, not decided at this precision
SCALE_ROUNDING = 64 * float(np.finfo(float).eps)  # mech's own rounding, relative to the output's scale


def decide(lo, hi, center, allow) -> np.ndarray:
    """RIGHT where ``[lo, hi]`` lies inside ``[center - allow, center + allow]``, WRONG where it lies outside,
    OPEN where it straddles an edge (or is not enclosed); differences rounded outward, so that a doubtful
    case stays OPEN."""
    with np.errstate(all="ignore"):
        up = np.maximum(np.nextafter(hi - center, np.inf), np.nextafter(center - lo, np.inf))
        out = np.maximum(np.nextafter(lo - center, -np.inf), np.nextafter(center - hi, -np.inf))
    res = np.full(np.shape(lo), OPEN, np.int8)
    res[~within(out, bars=(allow,)) & ~np.isnan(out)] = WRONG
    res[within(up, bars=(allow,))] = RIGHT
    return res


def _decide_exact(lo, hi, center: float, allow: float, mpmath) -> int:
    """``decide`` for one point of mpmath numbers, the comparisons exact."""
    if not (mpmath.isfinite(lo) and mpmath.isfinite(hi)):
        return OPEN
    c, a = mpmath.mpf(center), mpmath.mpf(allow)
    d_hi, d_lo = mpmath.fsub(hi, c, exact=True), mpmath.fsub(c, lo, exact=True)
    if within(max(d_hi, d_lo), bars=(a,)):
        return RIGHT
    if not within(max(mpmath.fsub(lo, c, exact=True), mpmath.fsub(c, hi, exact=True)), bars=(a,)):
        return WRONG
    return OPEN


def output_scale(ps: PointSet, name: str) -> np.ndarray:
    """The output's own size at each point, from its dimension: the parameters' units rescaled to bring them
    nearest their defaults (a least-squares fit of the three unit exponents, ``scales.dims``), the output
    brought along by its dimension, times the median size of mech's values in those units over the points
    (the fit with a 1e-9 ridge, so that dimensions no parameter carries give no exponent).
    What a zero reference is judged on (``P/(M mu g)`` for 4.8's t_roll); 1 (SI) where nothing says more."""
    key = ("scale", name)
    if key in ps.lines:
        return ps.lines[key]
    from mech.problems.scales import dims

    ex = ps.ex
    out = next(o for o in ex.outputs if o.name == name)
    d_out = dims(out.unit) or (0, 0, 0)
    rows, devs = [], []
    for p in ex.params:
        d = dims(p.unit)
        if d is None or not any(d) or p.default == 0:
            continue
        with np.errstate(all="ignore"):
            dev = np.log2(np.abs(ps.arrays[p.name])) - math.log2(abs(p.default))
        rows.append(d)
        devs.append(np.where(np.isfinite(dev), dev, 0.0))
    n = len(ps)
    if rows:
        A = np.array(rows, float)
        u = _inverse3(A.T @ A + 1e-9 * np.eye(3)) @ (A.T @ np.array(devs))  # least squares, (3, n)
        shift = np.exp2(np.clip(np.array(d_out, float) @ u, -900, 900))
    else:
        shift = np.ones(n)
    ref = np.abs(ps.analytic.get(name, np.full(n, np.nan)))
    use = np.isfinite(ref) & (ref > 0)
    sizes = np.sort(ref[use] / shift[use])  # their median (np.median imports numpy.ma: 0.03 s)
    typical = float(0.5 * (sizes[(sizes.size - 1) // 2] + sizes[sizes.size // 2])) if sizes.size else 1.0
    scale = np.where(np.isfinite(shift), typical * shift, typical)
    ps.lines[key] = scale
    return scale


def _inverse3(m: np.ndarray) -> np.ndarray:
    """The inverse of a 3x3 matrix by its adjugate (numpy.linalg costs 0.1 s to import, more than a check)."""
    a = m.tolist()
    cof = [[a[(i + 1) % 3][(j + 1) % 3] * a[(i + 2) % 3][(j + 2) % 3]
            - a[(i + 1) % 3][(j + 2) % 3] * a[(i + 2) % 3][(j + 1) % 3] for j in range(3)] for i in range(3)]
    det = sum(a[0][j] * cof[0][j] for j in range(3))
    return np.array(cof, float).T / det


def judge_points(formula: Formula, ps: PointSet, ref: np.ndarray, ref_err: np.ndarray, rtol: float,
                 alt: dict | None = None, name: str | None = None) -> PointJudgement:
    """Hold ``formula`` against ``ref`` (with its error bars ``ref_err``) at every point of ``ps``.

    Its exact value at each point (parameters exact as the doubles they are, numbers exact as written) is
    enclosed by interval arithmetic in double precision; where the enclosure straddles an edge of the
    allowance, at rising precision with mpmath (``_precise``) up to ``MAX_PREC`` bits.  The allowance is
    ``rtol |ref| + ref_err + 4 eps |ref| + 64 eps S`` (``S``: the output's scale, ``output_scale``), and
    ``rtol S`` where the reference is exactly zero: nothing of it comes from the formula."""
    env = {k: ps.arrays[k] for k in formula.names}
    n = len(ps)
    env = env or {"_": np.zeros(n)}
    lo, hi, problems = formula.enclose(env)
    with np.errstate(all="ignore"):  # the value shown: the enclosure's middle where it is tight, else the double
        y = lo / 2 + hi / 2
        tight = np.isfinite(y) & within(hi - lo, scale=np.maximum(np.abs(lo), np.abs(hi)), round_off=1e-12)
    if not tight.all():
        y = np.where(tight, y, formula.evaluate(env, np.float64)[0])
    has_ref = np.isfinite(ref)
    scale = output_scale(ps, name) if name is not None else np.abs(np.where(has_ref, ref, 0.0))
    eps4 = 4 * np.finfo(float).eps
    floor = np.where(ref == 0, rtol, SCALE_ROUNDING) * scale
    base = allowance(ref, rel=rtol, bars=(ref_err, floor), round_off=eps4)
    dom = _masked(problems, n)
    verdict = np.where(dom, WRONG, decide(lo, hi, ref, base))
    right = has_ref & (verdict == RIGHT)
    decided = has_ref & (verdict != OPEN)
    yours = y.copy()
    todo = np.flatnonzero(has_ref & ~decided)
    skipped = np.zeros(n, bool)
    undecided = np.zeros(n, bool)
    for j in range(0, todo.size, PRECISE_BATCH):
        if j and np.any(decided & ~right):
            # found wrong in exact arithmetic already: the rest need not cost the budget
            skipped[todo[j:]] = True
            break
        idx = todo[j:j + PRECISE_BATCH]
        got, values, dom_at = _precise(formula, {k: v[idx] for k, v in env.items()}, ref[idx], base[idx])
        for m, i in enumerate(idx):
            if got[m] == OPEN:
                undecided[i] = True
                continue
            decided[i] = True
            right[i] = got[m] == RIGHT and dom_at[m] is None
            if dom_at[m] is not None:
                problems.append(_problem_at(n, i, dom_at[m], None))
            elif math.isfinite(values[m]):
                yours[i] = values[m]
    # where the double enclosure is loose (a cancellation, a huge argument), the double value shown and read
    # by the hints may be round-off: the exact value instead, for the first ``PRECISE_BATCH`` such points
    with np.errstate(all="ignore"):
        loose = decided & ~dom & (np.abs(yours - y) == 0) & ~(hi - lo <= 1e-12 * np.maximum(np.abs(lo), np.abs(hi)))
    idx = np.flatnonzero(loose)[:PRECISE_BATCH]
    if idx.size:
        yours[idx] = _values(formula, {k: v[idx] for k, v in env.items()})
    for pr in problems:  # a domain error the exact value does not have was round-off
        pr.mask = np.asarray(pr.mask) & ~(decided & right)
    if undecided.any():
        problems.append(Problem(undecided, f"a value no precision up to {MAX_PREC} bits decides", np.zeros(n)))
    ill = right & ~(np.isfinite(y) & within(np.abs(y - ref), bars=(base,)))
    judged = has_ref & decided & ~skipped
    return PointJudgement(yours, ref, right & judged, judged, ill, problems, base, int(skipped.sum()),
                          lo, hi, undecided)


PRECISE_BATCH = 64  # points judged in high precision at once (the budget is looked at between batches)
_PRECS = (128, 512, 2048, MAX_PREC)


def _precise_work(points: int, prec: int) -> int:
    """Units of work of enclosing ``points`` points at ``prec`` bits: one a point at 128 bits, growing with
    the bits (the cost of mpmath's arithmetic), counted before it is done."""
    return int(points) * max(1, int(prec) // 128)


def _values(formula: Formula, env: dict) -> np.ndarray:
    """The exact values at the points ``env`` to double precision (NaN where no precision up to ``MAX_PREC``
    bits gives them within 1e-12 relative, or where there is no real value)."""
    import mpmath

    m = len(next(iter(env.values())))
    out = np.full(m, np.nan)
    left = np.arange(m)
    for prec in _PRECS:
        if left.size == 0:
            break
        budget.check("judging the formula in high precision", units=_precise_work(left.size, prec))
        lo, hi, problems = formula.enclose({k: v[left] for k, v in env.items()}, prec=prec)
        bad = _masked(problems, left.size)
        done = np.zeros(left.size, bool)
        for k, i in enumerate(left):
            if bad[k]:
                done[k] = True
            elif mpmath.isfinite(lo[k]) and mpmath.isfinite(hi[k]) and \
                    within(float(hi[k] - lo[k]), scale=float(max(abs(lo[k]), abs(hi[k]))), round_off=1e-12):
                out[i] = float((lo[k] + hi[k]) / 2)
                done[k] = True
        left = left[~done]
    return out


def _precise(formula: Formula, env: dict, ref: np.ndarray, base: np.ndarray):
    """For points the double enclosure leaves open: (verdicts, values, domain errors) from mpmath interval
    arithmetic at rising precision (``_PRECS``), each point decided at the first precision that decides
    it; OPEN where none up to ``MAX_PREC`` bits does."""
    import mpmath

    m = len(ref)
    got = np.full(m, OPEN, np.int8)
    values = np.full(m, np.nan)
    dom: list = [None] * m
    left = np.arange(m)
    for prec in _PRECS:
        if left.size == 0:
            break
        budget.check("judging the formula in high precision", units=_precise_work(left.size, prec))
        lo, hi, problems = formula.enclose({k: v[left] for k, v in env.items()}, prec=prec)
        for k, i in enumerate(left):
            what = next((pr.what.replace("{x}", f"{float(pr.args[k]):.6g}") for pr in problems if pr.mask[k]), None)
            if what is not None:
                got[i], dom[i] = WRONG, what
                continue
            got[i] = _decide_exact(lo[k], hi[k], float(ref[i]), float(base[i]), mpmath)
            if got[i] != OPEN:
                with mpmath.workprec(prec):
                    values[i] = float((lo[k] + hi[k]) / 2)
        left = left[got[left] == OPEN]
    return got, values, dom


def holds_at(formula: Formula, ps: PointSet, pj: PointJudgement, i: int, center: float, allow: float) -> int:
    """RIGHT, WRONG or OPEN: the formula's exact value at point ``i`` within ``allow`` of ``center`` (its
    double enclosure in ``pj``, else in high precision)."""
    got = int(decide(pj.lo[i:i + 1], pj.hi[i:i + 1], center, allow)[0])
    if got != OPEN:
        return got
    env = {k: ps.arrays[k][i:i + 1] for k in formula.names} or {"_": np.zeros(1)}
    verdict, _, dom = _precise(formula, env, np.array([center]), np.array([allow]))
    return WRONG if dom[0] is not None else int(verdict[0])


def _problem_at(n: int, i: int, what: str, arg) -> Problem:
    mask = np.zeros(n, bool)
    mask[i] = True
    args = np.zeros(n)
    args[i] = float(arg) if arg is not None else np.nan
    return Problem(mask, what, args)


def _masked(problems, n) -> np.ndarray:
    m = np.zeros(n, bool)
    for pr in problems:
        m |= np.asarray(pr.mask)
    return m


def yours_at_given(formula: Formula, ps: PointSet) -> float:
    env = {k: ps.arrays[k][:1] for k in formula.names} or {"_": np.zeros(1)}
    return float(formula.evaluate(env)[0][0])


def problem_text(pj: PointJudgement, ps: PointSet, i: int) -> str | None:
    for pr in pj.problems:
        if pr.mask[i]:
            x = float(pr.args[i]) if np.ndim(pr.args) else float(pr.args)
            return pr.what.replace("{x}", f"{x:.6g}")
    return None


def describe_point(ps: PointSet, i: int) -> str:
    ex, p, g = ps.ex, ps.points[i], ps.points[0]
    if i == 0:
        return "at the given parameters"
    moved = [q for q in ex.params if p[q.name] != g[q.name]]
    return "at " + ", ".join(f"{q.name} = {q.show(p[q.name])}" for q in (moved or ex.params))
