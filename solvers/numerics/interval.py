"""Interval arithmetic: certified enclosures of real expressions, on arrays.

An interval is a pair of arrays ``(lo, hi)``: the exact real value lies in ``[lo, hi]``.  ``[-inf, inf]``
means "not enclosed here" (an overflow, a division by an interval through zero, an argument that straddles
a function's domain); a separate boolean mask ``bad`` marks where there is certainly no real value (the
square root of an interval entirely below zero, a division by exactly zero).

Two backends run the same code (call it under ``np.errstate(all="ignore")``: an overflow is an infinite
bound and a NaN an unknown one, not a warning):

* ``DOUBLE``: float64 numpy arrays, one pass for every point.  A basic operation (+ - * /, sqrt) is
  correctly rounded in IEEE arithmetic, so one step of ``np.nextafter`` outward encloses its exact result
  (a sum or product whose exact rounding error, by Knuth's two-sum and Dekker's two-product, shows it
  exact or on the right side is not moved: 1*1 - 1 stays exactly 0);
  the transcendental functions (numpy's: within half an ulp to an ulp on this platform,
  tests/test_interval.py measures them against mpmath) are widened by ``FN_ULPS`` ulps, the elliptic
  integrals and the AGM (``special``: a few ulps, 24 at worst measured for E(m) near m = 1) by
  ``SPECIAL_ULPS``.
* ``precise(prec)``: numpy object arrays of mpmath numbers, arithmetic rounded outward exactly
  (``mpmath.fadd(..., rounding='f')`` ..., floor and ceiling) at ``prec`` bits, functions evaluated with 32 guard bits and
  widened by one unit of ``2^-prec`` relative.

A function that is not monotone on an interval is bounded by its extrema inside it: cos over an interval
that may hold k pi takes +-1 there (the test is made with a margin, so a doubtful case includes the
extremum: a wider interval, never a wrong one), sin likewise at pi/2 + k pi, cosh and x^2n at 0, abs at 0;
tan and atan2 over a pole or the branch cut are not enclosed.  Generic: no physics here.
"""

from __future__ import annotations

import functools
import math

import numpy as np

__all__ = ["DOUBLE", "precise", "FN_ULPS", "SPECIAL_ULPS", "point", "constant", "add", "sub", "mul", "div", "corner_div", "neg",
           "power", "function", "atan2", "agm", "FUNCTIONS"]

FN_ULPS = 4  # numpy's exp, log, sin, ... (measured within an ulp); basic operations: 1
SPECIAL_ULPS = 64  # ``special``'s K(m), E(m), AGM (measured within 25 ulps)
TRIG_DOUBLE = 2.0**20  # beyond this |x|, sin and cos in double are bounded by [-1, 1] only
TRIG_BITS = 1 << 14  # beyond 2^this, sin and cos in high precision are bounded by [-1, 1] only
HUGE_BITS = 1 << 40  # beyond 2^this, an exponential's argument is not computed: only bounded

FUNCTIONS = ("sqrt", "exp", "expm1", "log", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh",
             "abs", "ellipk", "ellipe")


class _Double:
    """float64 arrays, rounded outward by one ulp (``np.nextafter``)."""

    name = "double"
    inf = np.inf

    @staticmethod
    def dn(x):
        return np.nextafter(x, -np.inf)

    @staticmethod
    def up(x):
        return np.nextafter(x, np.inf)

    # called under ``np.errstate(all="ignore")``: an overflow is an infinite bound, a NaN an unknown one
    def _directed(self, s, err, r):
        """The rounded result ``s`` moved one ulp toward ``r`` unless its exact error ``err`` (true - s; NaN
        where not known) says it already lies on that side: an exact sum or product stays exact."""
        if r < 0:
            return np.where(err >= 0, s, self.dn(s))
        return np.where(err <= 0, s, self.up(s))

    @staticmethod
    def _two_sum(a, b):
        s = a + b  # Knuth's two-sum: err is the exact rounding error (NaN on overflow)
        bb = s - a
        return s, (a - (s - bb)) + (b - bb)

    @staticmethod
    def _two_product(a, b):
        p = a * b  # Dekker's two-product, where no split overflows and no partial product underflows
        ok = (np.abs(a) < 2.0**995) & (np.abs(b) < 2.0**995) & ((np.abs(p) > 2.0**-960) | (a == 0) | (b == 0))
        ca, cb = 134217729.0 * a, 134217729.0 * b
        ah, bh = ca - (ca - a), cb - (cb - b)
        al, bl = a - ah, b - bh
        err = ((ah * bh - p) + ah * bl + al * bh) + al * bl
        return p, np.where(ok, err, np.nan)

    def add(self, a, b, r):
        return self._directed(*self._two_sum(a, b), r)

    def mul(self, a, b, r):
        return self._directed(*self._two_product(a, b), r)

    def mul_both(self, a, b):
        """(down, up) of a * b from one two-product."""
        p, err = self._two_product(a, b)
        return self._directed(p, err, -1), self._directed(p, err, 1)

    def div(self, a, b, r):
        return self.dn(a / b) if r < 0 else self.up(a / b)

    @staticmethod
    def fn(name, x):
        if name in ("ellipk", "ellipe"):
            from mech.solvers.numerics import special

            return np.vectorize(getattr(special, name), otypes=[float])(x)
        return _NP[name](x)

    def fn_both(self, name, x0, x1):
        return self.fn(name, x0), self.fn(name, x1)

    @staticmethod
    def agm(a, b):
        from mech.solvers.numerics import special

        return np.vectorize(special.agm, otypes=[float])(a, b)

    def spread(self, y, ulps, r):
        """``y`` (a function's value within ``ulps`` ulps) moved outward: down (r < 0) or up."""
        y = np.asarray(y, float)
        w = ulps * np.spacing(np.abs(y))
        if r < 0:
            out = self.dn(y - w)
            return np.where(y == np.inf, np.finfo(float).max / 2, out)
        out = self.up(y + w)
        return np.where(y == -np.inf, -np.finfo(float).max / 2, out)

    @staticmethod
    def pi(r):
        return math.pi if r < 0 else float(np.nextafter(math.pi, np.inf))

    @staticmethod
    def mag(x):  # log2 |x| (rough)
        with np.errstate(divide="ignore"):
            return np.log2(np.abs(x))

    trig_limit = TRIG_DOUBLE
    margin = 1e-9  # of x/pi: how close to a multiple of pi counts as holding it
    floor = staticmethod(np.floor)
    ceil = staticmethod(np.ceil)

    @staticmethod
    def isnan(x):
        return np.isnan(x)

    @staticmethod
    def asarray(x, n=None):
        return np.asarray(x, float)

    @staticmethod
    def is_int(x):
        return np.isfinite(x) & (np.floor(x) == x)

    @staticmethod
    def is_even(k):
        return np.floor(k / 2) * 2 == k

    @staticmethod
    def neg(x):
        return np.negative(x)

    @staticmethod
    def atan2f(a, b):
        return np.arctan2(a, b)


_NP = {"sqrt": np.sqrt, "exp": np.exp, "expm1": np.expm1, "log": np.log, "sin": np.sin, "cos": np.cos,
       "tan": np.tan, "asin": np.arcsin, "acos": np.arccos, "atan": np.arctan, "sinh": np.sinh, "cosh": np.cosh,
       "tanh": np.tanh, "atan2": np.arctan2}


class _Precise:
    """Object arrays of mpmath numbers at ``prec`` bits: arithmetic rounded outward exactly, functions
    computed with 32 guard bits and widened by ``2^-prec`` relative."""

    name = "precise"

    def __init__(self, prec: int):
        import mpmath

        self.mp = mpmath.mp
        self.mpmath = mpmath
        self.prec = int(prec)
        self.inf = mpmath.mpf("inf")
        # x / pi is then known to far better than the margin: its whole part and a little more
        self.trig_limit = mpmath.mpf(2) ** min(max(self.prec - 64, 20), TRIG_BITS)
        self.margin = 0  # every bound is rounded outward exactly: no margin needed
        self._ops = {}

    def _u(self, key, f, nin):
        if key not in self._ops:
            self._ops[key] = np.frompyfunc(f, nin, 1)
        return self._ops[key]

    def _arith(self, op, a, b, r):
        u = self._ops.get((op, r))
        if u is None:
            u = self._ops[(op, r)] = np.frompyfunc(self._rounded(op, r), 2, 1)
        return u(a, b)

    def _rounded(self, op, r):
        """``op`` of two numbers at ``prec`` bits, rounded down (r < 0) or up."""
        m, p = self.mpmath, self.prec
        rnd = "f" if r < 0 else "c"  # floor, ceiling (mpmath: "d", "u" are toward and away from zero)
        f = {"add": m.fadd, "mul": m.fmul, "div": m.fdiv}[op]
        # what fadd/fmul/fdiv call for two mpf, without their parsing of keywords (most of their time)
        raw = getattr(m.libmp, f"mpf_{op}")
        make = m.mp.make_mpf
        nan = m.mpf("nan")

        def one(x, y):
            try:
                try:
                    return make(raw(x._mpf_, y._mpf_, p, rnd))
                except AttributeError:  # a Python number: mpmath converts it
                    return f(x, y, prec=p, rounding=rnd)
            except ZeroDivisionError:
                return nan
        return one

    def add(self, a, b, r):
        return self._arith("add", a, b, r)

    def mul(self, a, b, r):
        return self._arith("mul", a, b, r)

    def mul_both(self, a, b):
        return self.mul(a, b, -1), self.mul(a, b, 1)

    def div(self, a, b, r):
        return self._arith("div", a, b, r)

    # the interval operations below, fused: one pass of Python over the points for an interval + * /, with
    # the very roundings, corners, NaN rules and ties of the array code of ``add``, ``mul`` and ``div`` (numpy's
    # minimum and maximum of objects keep their first argument on a tie, so do these); that code's dozen
    # ufunc passes over a few points cost more than the arithmetic
    def interval_add(self, a, b):
        u = self._ops.get("iadd")
        if u is None:
            down, up, isnan = self._rounded("add", -1), self._rounded("add", 1), self.mpmath.isnan
            inf, minus_inf = self.inf, -self.inf

            def one(x0, x1, y0, y1):
                lo, hi = down(x0, y0), up(x1, y1)
                if isnan(lo) or isnan(hi):
                    return minus_inf, inf
                return lo, hi
            u = self._ops["iadd"] = np.frompyfunc(one, 4, 2)
        lo, hi = u(a[0], a[1], b[0], b[1])
        return self.asarray(lo), self.asarray(hi)

    def interval_mul(self, a, b):
        points = (a[0] is a[1], b[0] is b[1])  # a point: one corner fewer, as in ``mul``
        u = self._ops.get(("imul", points))
        if u is None:
            u = self._ops[("imul", points)] = np.frompyfunc(self._fused_mul(*points), 4, 2)
        lo, hi = u(a[0], a[1], b[0], b[1])
        return self.asarray(lo), self.asarray(hi)

    def _fused_mul(self, a_point, b_point):
        down, up, isnan = self._rounded("mul", -1), self._rounded("mul", 1), self.mpmath.isnan
        inf, minus_inf = self.inf, -self.inf
        lib, make, p = self.mpmath.libmp, self.mpmath.mp.make_mpf, self.prec
        exact_mul, cmp, round_to, fzero = lib.mpf_mul, lib.mpf_cmp, lib.mpf_pos, lib.fzero

        def general(x0, x1, y0, y1):
            xs = (x0,) if a_point else (x0, x1)
            ys = (y0,) if b_point else (y0, y1)
            lo = hi = None
            nan = False
            for x in xs:
                for y in ys:
                    c_lo, c_hi = down(x, y), up(x, y)
                    nan = nan or isnan(c_lo) or isnan(c_hi)
                    if lo is None:
                        lo, hi = c_lo, c_hi
                    else:
                        lo = lo if lo <= c_lo else c_lo
                        hi = hi if hi >= c_hi else c_hi
            if (x0 == 0 and x1 == 0) or (y0 == 0 and y1 == 0):  # an exact zero times anything real is zero
                return 0, 0
            if nan or isnan(lo) or isnan(hi):
                return minus_inf, inf
            return lo, hi

        def one(x0, x1, y0, y1):
            """Four finite mpf: the corners' exact products (finite, never NaN), their least rounded down and
            their greatest up, the same numbers as the least and greatest of the rounded corners (rounding
            is monotone): two roundings for eight."""
            try:
                ends = (x0._mpf_, x1._mpf_, y0._mpf_, y1._mpf_)
            except AttributeError:
                return general(x0, x1, y0, y1)
            if any(not e[1] and e[2] for e in ends):  # an infinity or a NaN
                return general(x0, x1, y0, y1)
            X0, X1, Y0, Y1 = ends
            if (X0 == fzero and X1 == fzero) or (Y0 == fzero and Y1 == fzero):
                return 0, 0
            lo = hi = None
            for x in ((X0,) if a_point else (X0, X1)):
                for y in ((Y0,) if b_point else (Y0, Y1)):
                    c = exact_mul(x, y)
                    if lo is None:
                        lo = hi = c
                    elif cmp(c, lo) < 0:
                        lo = c
                    if cmp(c, hi) > 0:
                        hi = c
            return make(round_to(lo, p, "f")), make(round_to(hi, p, "c"))
        return one

    def interval_div(self, a, b):
        """``div``'s ``((lo, hi), zero)``, fused."""
        u = self._ops.get("idiv")
        if u is None:
            u = self._ops["idiv"] = np.frompyfunc(self._fused_div(), 4, 3)
        lo, hi, zero = u(a[0], a[1], b[0], b[1])
        return (self.asarray(lo), self.asarray(hi)), np.asarray(zero, bool)

    def _fused_div(self):
        down, up, isnan = self._rounded("div", -1), self._rounded("div", 1), self.mpmath.isnan
        inf, minus_inf = self.inf, -self.inf
        lib = self.mpmath.libmp
        cmp, fzero = lib.mpf_cmp, lib.fzero

        def general(x0, x1, y0, y1, zero):
            lows = [down(x, y) for x in (x0, x1) for y in (y0, y1)]
            highs = [up(x, y) for x in (x0, x1) for y in (y0, y1)]
            lo, hi = lows[0], highs[0]
            nan = isnan(lo) or isnan(hi)
            for c_lo, c_hi in zip(lows[1:], highs[1:]):
                nan = nan or isnan(c_lo) or isnan(c_hi)
                lo = lo if lo <= c_lo else c_lo
                hi = hi if hi >= c_hi else c_hi
            if nan or isnan(lo) or isnan(hi):
                return minus_inf, inf, zero
            return lo, hi, zero

        def one(x0, x1, y0, y1):
            """b through zero: not enclosed (nothing to divide).  Four finite mpf, ends in order, b off zero:
            the least and the greatest exact corner are known from the signs (x / y is monotone in each on
            the box), and rounding is monotone: the same numbers as the least and greatest rounded corner,
            at two divisions for eight."""
            zero = bool(y0 == 0) and bool(y1 == 0)
            if bool(y0 <= 0) and bool(y1 >= 0):
                return minus_inf, inf, zero
            try:
                X0, X1, Y0, Y1 = x0._mpf_, x1._mpf_, y0._mpf_, y1._mpf_
            except AttributeError:
                return general(x0, x1, y0, y1, zero)
            if any(not e[1] and e[2] for e in (X0, X1, Y0, Y1)) or cmp(X0, X1) > 0 or cmp(Y0, Y1) > 0:
                return general(x0, x1, y0, y1, zero)
            if Y0[0] == 0 and Y0 != fzero:  # b > 0
                return down(x0, y1 if X0[0] == 0 else y0), up(x1, y0 if X1[0] == 0 else y1), zero
            return down(x1, y1 if X1[0] == 0 else y0), up(x0, y0 if X0[0] == 0 else y1), zero  # b < 0
        return one

    def dn(self, x):
        return x

    up = dn

    def _fn_one(self, name):
        """``name`` of one number, with 32 guard bits (NaN where it has no real value)."""
        got = self._ops.get(("fn1", name))
        if got is not None:
            return got
        m = self.mpmath
        f = {"abs": abs, "atan2": m.atan2}.get(name) or getattr(m, name)

        def one(v):
            with self.mp.workprec(self.prec + 32):
                try:
                    y = f(v)
                except (ValueError, ZeroDivisionError):
                    return m.mpf("nan")
                return y if isinstance(y, m.mpf) else m.mpf("nan")
        self._ops[("fn1", name)] = one
        return one

    def fn(self, name, x):
        return self._u(("fn", name), self._fn_one(name), 1)(x)

    def fn_both(self, name, x0, x1):
        """``(fn(name, x0), fn(name, x1))``, computed once where the two ends are the same number (a point,
        or an operation exact at these bits: the function costs most at high precision)."""
        u = self._ops.get(("fn_both", name))
        if u is None:
            one = self._fn_one(name)

            def two(v0, v1):
                y0 = one(v0)
                return y0, (y0 if v0 is v1 or (type(v0) is type(v1) and v0 == v1) else one(v1))
            u = self._ops[("fn_both", name)] = np.frompyfunc(two, 2, 2)
        return u(x0, x1)

    def agm(self, a, b):
        m = self.mpmath

        def one(x, y):
            with self.mp.workprec(self.prec + 32):
                return m.agm(x, y)
        return self._u("agm", one, 2)(a, b)

    def atan2f(self, a, b):
        m = self.mpmath

        def one(x, y):
            with self.mp.workprec(self.prec + 32):
                return m.atan2(x, y)
        return self._u("atan2", one, 2)(a, b)

    def spread(self, y, ulps, r):
        m, p = self.mpmath, self.prec

        def one(v):
            if not m.isfinite(v) or v == 0:
                return v
            w = abs(v) * m.ldexp(1, -p)
            return m.fsub(v, w, prec=p, rounding="f") if r < 0 else m.fadd(v, w, prec=p, rounding="c")
        return self._u(("spread", r), one, 1)(y)

    def pi(self, r):
        with self.mp.workprec(self.prec + 32):
            v = +self.mpmath.pi
        return self.mpmath.fsub(v, abs(v) * self.mpmath.ldexp(1, -self.prec), prec=self.prec, rounding="f") if r < 0 \
            else self.mpmath.fadd(v, abs(v) * self.mpmath.ldexp(1, -self.prec), prec=self.prec, rounding="c")

    def mag(self, x):
        m = self.mpmath

        def one(v):
            if v == 0:
                return -m.inf
            if not m.isfinite(v):
                return m.inf if not m.isnan(v) else v
            return m.mpf(m.mag(v))
        return self._u("mag", one, 1)(x)

    def floor(self, x):
        return self._u("floor", self.mpmath.floor, 1)(x)

    def ceil(self, x):
        return self._u("ceil", self.mpmath.ceil, 1)(x)

    def isnan(self, x):
        return np.asarray(self._u("isnan", lambda v: bool(self.mpmath.isnan(v)), 1)(x), bool)

    def asarray(self, x, n=None):
        a = np.empty(np.shape(x), object)
        a[...] = x
        return a

    def is_int(self, x):
        m = self.mpmath
        return np.asarray(self._u("isint", lambda v: bool(m.isfinite(v) and m.floor(v) == v), 1)(x), bool)

    def neg(self, x):
        """-x, exactly (mpf's own minus rounds to the context's precision)."""
        m = self.mpmath
        return self._u("neg", lambda v: m.fneg(v, exact=True) if isinstance(v, m.mpf) else -v, 1)(x)

    def is_even(self, k):
        m = self.mpmath
        return np.asarray(self._u("even", lambda v: bool(m.isfinite(v) and int(v) % 2 == 0), 1)(k), bool)


DOUBLE = _Double()


@functools.lru_cache(maxsize=16)
def precise(prec: int) -> _Precise:
    """The high-precision backend at ``prec`` bits (one for each precision: it holds its constants and
    the element-wise operations it has built, nothing of a call)."""
    return _Precise(prec)


# -- intervals ------------------------------------------------------------------------------------------

def _unknown(B, lo, hi, mask):
    """[-inf, inf] where ``mask``; NaN endpoints are unknown too."""
    mask = np.asarray(mask, bool) | B.isnan(lo) | B.isnan(hi)
    return np.where(mask, -B.inf, lo), np.where(mask, B.inf, hi)


def point(B, x):
    """The exact value ``x`` (a double, or an mpmath number), as an interval."""
    x = B.asarray(x)
    return x, x


def constant(B, lo, hi):
    return B.asarray(lo), B.asarray(hi)


def neg(B, a):
    if a[0] is a[1]:  # a point stays one
        n = B.neg(a[0])
        return n, n
    return B.neg(a[1]), B.neg(a[0])


def add(B, a, b):
    if B is not DOUBLE:
        return B.interval_add(a, b)
    if a[0] is a[1] and b[0] is b[1] and B is DOUBLE:  # two points: one two-sum for both ends
        s, err = B._two_sum(a[0], b[0])
        return _unknown(B, B._directed(s, err, -1), B._directed(s, err, 1), False)
    return _unknown(B, B.add(a[0], b[0], -1), B.add(a[1], b[1], 1), False)


def sub(B, a, b):
    return add(B, a, neg(B, b))


def mul(B, a, b):
    if B is not DOUBLE:
        return B.interval_mul(a, b)
    # the corners: one where an argument is a point (its two ends the same array)
    xs = (a[0],) if a[0] is a[1] else a
    ys = (b[0],) if b[0] is b[1] else b
    pairs = [B.mul_both(x, y) for x in xs for y in ys]
    lo, hi = pairs[0]
    nan = B.isnan(lo) | B.isnan(hi)
    for x, y in pairs[1:]:
        nan = nan | B.isnan(x) | B.isnan(y)
        lo = np.minimum(lo, x)
        hi = np.maximum(hi, y)
    # an exact zero times anything real is zero
    zero = ((a[0] == 0) & (a[1] == 0)) | ((b[0] == 0) & (b[1] == 0))
    lo, hi = _unknown(B, lo, hi, nan & ~zero)
    return B.asarray(np.where(zero, 0, lo)), B.asarray(np.where(zero, 0, hi))


def div(B, a, b):
    """a / b, and the mask of a certain division by zero (b exactly 0)."""
    if B is not DOUBLE:
        return B.interval_div(a, b)
    return corner_div(B, a, b)


def corner_div(B, a, b):
    """a / b by all four corners, each rounded outward, in any backend (the precise one's fused
    ``interval_div`` picks two of them and is tested against this)."""
    through = (b[0] <= 0) & (b[1] >= 0)
    zero = (b[0] == 0) & (b[1] == 0)
    safe_b = (np.where(through, 1, b[0]), np.where(through, 1, b[1]))
    lows = [B.div(x, y, -1) for x in a for y in safe_b]
    highs = [B.div(x, y, 1) for x in a for y in safe_b]
    lo, hi = lows[0], highs[0]
    nan = B.isnan(lo) | B.isnan(hi)
    for x, y in zip(lows[1:], highs[1:]):
        nan = nan | B.isnan(x) | B.isnan(y)
        lo = np.minimum(lo, x)
        hi = np.maximum(hi, y)
    lo, hi = _unknown(B, lo, hi, through | nan)
    return (lo, hi), zero


def _monotone(B, name, a, increasing=True, ulps=FN_ULPS):
    f_lo, f_hi = B.fn_both(name, a[0], a[1])
    if not increasing:
        f_lo, f_hi = f_hi, f_lo
    return B.spread(f_lo, ulps, -1), B.spread(f_hi, ulps, 1)


def _holds(B, a, shift):
    """Whether [a] may hold (k + shift) pi for an even k, for an odd k (a margin makes a doubtful case hold)."""
    t_lo = np.where(a[0] < 0, B.div(a[0], B.pi(-1), -1), B.div(a[0], B.pi(1), -1))
    t_hi = np.where(a[1] < 0, B.div(a[1], B.pi(1), 1), B.div(a[1], B.pi(-1), 1))
    k1 = B.ceil(B.add(t_lo, -(shift + B.margin), -1))
    k2 = B.floor(B.add(t_hi, B.margin - shift, 1))
    some = k2 >= k1
    two = k2 > k1
    k1_even = B.is_even(np.where(some, k1, 0))
    return some & (two | k1_even), some & (two | ~k1_even)


def _cos_like(B, name, a):
    """cos (extrema at k pi) or sin (at pi/2 + k pi)."""
    shift = 0 if name == "cos" else 0.5
    big = (np.abs(a[0]) > B.trig_limit) | (np.abs(a[1]) > B.trig_limit) | B.isnan(a[0]) | B.isnan(a[1])
    safe = (np.where(big, 0, a[0]), np.where(big, 0, a[1]))
    even, odd = _holds(B, safe, shift)
    y1, y2 = B.fn_both(name, safe[0], safe[1])
    lo = B.spread(np.minimum(y1, y2), FN_ULPS, -1)
    hi = B.spread(np.maximum(y1, y2), FN_ULPS, 1)
    lo = np.where(odd | big, -1, np.maximum(lo, -1))
    hi = np.where(even | big, 1, np.minimum(hi, 1))
    return B.asarray(lo), B.asarray(hi)


def function(B, name, a):
    """``name`` (one of ``FUNCTIONS``) of the interval ``a``: ``((lo, hi), bad)``."""
    lo, hi = a
    none = np.zeros(np.shape(lo), bool)
    if name == "abs":
        pos, negv = lo >= 0, hi <= 0
        out_lo = np.where(pos, lo, np.where(negv, B.neg(hi), 0))
        out_hi = np.where(pos, hi, np.where(negv, B.neg(lo), np.maximum(B.neg(lo), hi)))
        return (B.asarray(out_lo), B.asarray(out_hi)), none
    if name in ("cos", "sin"):
        return _cos_like(B, name, a), none
    if name == "tan":
        big = (np.abs(lo) > B.trig_limit) | (np.abs(hi) > B.trig_limit)
        safe = (np.where(big, 0, lo), np.where(big, 0, hi))
        e, o = _holds(B, safe, 0.5)
        pole = e | o
        big = (np.abs(lo) > B.trig_limit) | (np.abs(hi) > B.trig_limit)
        out = _monotone(B, "tan", safe)
        return _unknown(B, *out, pole | big), none
    if name in ("exp", "expm1", "sinh", "tanh", "atan"):
        big = (B.mag(lo) > HUGE_BITS) | (B.mag(hi) > HUGE_BITS)
        safe = (np.where(big, 0, lo), np.where(big, 0, hi))
        out = _monotone(B, name, safe)
        return _unknown(B, *out, big), none
    if name == "cosh":
        big = (B.mag(lo) > HUGE_BITS) | (B.mag(hi) > HUGE_BITS)
        safe = (np.where(big, 0, lo), np.where(big, 0, hi))
        y1, y2 = B.fn_both("cosh", safe[0], safe[1])
        through = (safe[0] <= 0) & (safe[1] >= 0)
        out_lo = np.where(through, 1, B.spread(np.minimum(y1, y2), FN_ULPS, -1))
        out_hi = B.spread(np.maximum(y1, y2), FN_ULPS, 1)
        return _unknown(B, B.asarray(out_lo), out_hi, big), none
    if name in ("sqrt", "log"):
        # sqrt: correctly rounded; below zero no real value; log: at or below zero none
        bad = hi < 0 if name == "sqrt" else hi <= 0
        straddle = (lo < 0) & ~bad if name == "sqrt" else (lo <= 0) & ~bad
        safe = (np.where(bad | straddle, 1, lo), np.where(bad | straddle, 1, hi))
        out = _monotone(B, name, safe, ulps=1 if name == "sqrt" else FN_ULPS)
        return _unknown(B, *out, bad | straddle), bad
    if name in ("asin", "acos"):
        bad = (lo > 1) | (hi < -1)
        straddle = ((lo < -1) | (hi > 1)) & ~bad
        safe = (np.where(bad | straddle, 0, lo), np.where(bad | straddle, 0, hi))
        out = _monotone(B, name, safe, increasing=name == "asin")
        return _unknown(B, *out, bad | straddle), bad
    if name in ("ellipk", "ellipe"):
        edge = 1
        bad = lo >= edge if name == "ellipk" else lo > edge
        straddle = (hi >= edge if name == "ellipk" else hi > edge) & ~bad
        safe = (np.where(bad | straddle, 0, lo), np.where(bad | straddle, 0, hi))
        out = _monotone(B, name, safe, increasing=name == "ellipk", ulps=SPECIAL_ULPS if B is DOUBLE else FN_ULPS)
        return _unknown(B, *out, bad | straddle | B.isnan(lo)), bad
    raise ValueError(name)


def atan2(B, a, b):
    """atan2(a, b): extrema at the corners of a box off the branch cut (b < 0, a = 0); ``((lo, hi), bad)``."""
    ok = (b[0] > 0) | (a[0] > 0) | (a[1] < 0)
    origin = (a[0] == 0) & (a[1] == 0) & (b[0] == 0) & (b[1] == 0)
    safe_b = (np.where(ok, b[0], 1), np.where(ok, b[1], 1))
    safe_a = (np.where(ok, a[0], 0), np.where(ok, a[1], 0))
    corners = [B.atan2f(x, y) if B is not DOUBLE else np.arctan2(x, y) for x in safe_a for y in safe_b]
    lo, hi = corners[0], corners[0]
    for c in corners[1:]:
        lo, hi = np.minimum(lo, c), np.maximum(hi, c)
    lo, hi = B.spread(lo, FN_ULPS, -1), B.spread(hi, FN_ULPS, 1)
    lo = np.maximum(lo, B.neg(B.asarray(B.pi(1))))
    hi = np.minimum(hi, B.pi(1))
    return _unknown(B, B.asarray(lo), B.asarray(hi), ~ok), origin


def agm(B, a, b):
    """The arithmetic-geometric mean, increasing in both arguments; ``((lo, hi), bad)`` (bad: a negative)."""
    bad = (a[1] < 0) | (b[1] < 0)
    straddle = ((a[0] < 0) | (b[0] < 0)) & ~bad
    s = [np.where(bad | straddle, 1, x) for x in (a[0], a[1], b[0], b[1])]
    ulps = SPECIAL_ULPS if B is DOUBLE else FN_ULPS
    lo = B.spread(B.agm(s[0], s[2]), ulps, -1)
    hi = B.spread(B.agm(s[1], s[3]), ulps, 1)
    return _unknown(B, lo, hi, bad | straddle), bad


MAX_INT_POWER = 64  # an integer power up to this is formed by multiplications, rounded outward each


def _mag_pow(B, x, n: int, r):
    """|x|^n for x >= 0 (an array) and a whole n >= 1 by squaring, each product rounded toward ``r``."""
    acc, base, k = None, x, n
    while k:
        if k & 1:
            acc = base if acc is None else B.mul(acc, base, r)
        k >>= 1
        if k:
            base = B.mul(base, base, r)
    return acc


def _int_power(B, a, n: int):
    """a ** n for a whole |n| <= MAX_INT_POWER: exact where the products are representable."""
    if n == 0:
        one = B.asarray(np.ones(np.shape(a[0])) if B is DOUBLE else [1] * len(a[0]))
        return (one, one), None
    m = abs(n)
    absa = function(B, "abs", a)[0]
    if m % 2 == 0:  # even: through |a|
        lo, hi = _mag_pow(B, absa[0], m, -1), _mag_pow(B, absa[1], m, 1)
    else:  # odd: monotone; a negative endpoint through its magnitude
        neg_lo, neg_hi = a[0] < 0, a[1] < 0
        lo = np.where(neg_lo, B.neg(_mag_pow(B, function(B, "abs", (a[0], a[0]))[0][0], m, 1)),
                      _mag_pow(B, np.where(neg_lo, 0, a[0]), m, -1))
        hi = np.where(neg_hi, B.neg(_mag_pow(B, function(B, "abs", (a[1], a[1]))[0][0], m, -1)),
                      _mag_pow(B, np.where(neg_hi, 0, a[1]), m, 1))
    lo, hi = B.asarray(lo), B.asarray(hi)
    if n > 0:
        return _unknown(B, lo, hi, False), None
    q, zero = div(B, (B.asarray(np.ones(np.shape(lo)) if B is DOUBLE else [1] * len(lo)),) * 2, (lo, hi))
    return q, zero


def power(B, a, b):
    """a ** b; ``((lo, hi), bad)`` (bad: a negative number to a fractional power, 0 to a negative one)."""
    if np.ndim(b[0]) and len(b[0]) and bool(np.all(b[0] == b[1])) and bool(np.all(B.is_int(b[0]))):
        ns = {int(v) for v in np.asarray(b[0]).reshape(-1)}
        if len(ns) == 1 and abs(next(iter(ns))) <= MAX_INT_POWER:  # a whole power, written once
            (lo, hi), zero = _int_power(B, a, ns.pop())
            bad = np.zeros(np.shape(lo), bool) if zero is None else np.asarray(zero, bool)
            return (lo, hi), bad
    b_point = b[0] == b[1]
    b_int = b_point & B.is_int(b[0])
    n = np.where(b_int, b[0], 0)
    pos = (a[0] > 0) | ((a[0] >= 0) & (b[0] > 0))
    zero_a = (a[0] == 0) & (a[1] == 0)
    no_int = B.ceil(b[0]) > b[1]  # b holds no whole number: a negative base has no real power
    bad = ((a[1] < 0) & no_int) | (zero_a & b_point & (b[0] < 0))
    # a > 0: monotone in each argument: the corners
    safe_a = (np.where(pos, a[0], 1), np.where(pos, a[1], 1))
    cs = [_pow(B, x, y) for x in safe_a for y in b]
    lo, hi = cs[0], cs[0]
    for c in cs[1:]:
        lo, hi = np.minimum(lo, c), np.maximum(hi, c)
    lo, hi = B.spread(lo, FN_ULPS, -1), B.spread(hi, FN_ULPS, 1)
    # an integer power of any a: through |a| (even) or monotone (odd); a negative one needs a off zero
    absa = function(B, "abs", a)[0]
    even = b_int & B.is_even(n)
    n_safe = np.where(b_int, n, 1)
    m_lo, m_hi = (np.where(even, absa[0], a[0]), np.where(even, absa[1], a[1]))
    p1, p2 = _pow(B, m_lo, n_safe), _pow(B, m_hi, n_safe)
    i_lo = B.spread(np.minimum(p1, p2), FN_ULPS, -1)
    i_hi = B.spread(np.maximum(p1, p2), FN_ULPS, 1)
    i_through = (a[0] <= 0) & (a[1] >= 0) & (n < 0)
    i_lo = np.where(even & (n > 0), np.maximum(i_lo, 0), i_lo)
    use_int = b_int & ~pos
    lo, hi = np.where(use_int, i_lo, lo), np.where(use_int, i_hi, hi)
    one = b_int & (n == 0)
    lo, hi = np.where(one, 1, lo), np.where(one, 1, hi)
    zero_pos = zero_a & (b[0] > 0)
    lo, hi = np.where(zero_pos, 0, lo), np.where(zero_pos, 0, hi)
    unknown = ~(pos | use_int | zero_pos | one) | (use_int & i_through & ~one)
    return _unknown(B, B.asarray(lo), B.asarray(hi), unknown | bad), bad & ~one


def _pow(B, x, y):
    if B is DOUBLE:
        with np.errstate(all="ignore"):
            return np.power(x, y)
    m = B.mpmath

    def one(u, v):
        with B.mp.workprec(B.prec + 32):
            if u == 0:
                return m.mpf(0) if v > 0 else (m.mpf(1) if v == 0 else m.inf)
            size = v * m.log(abs(u), 2)
            if abs(size) > HUGE_BITS:  # not computed: not enclosed
                return m.mpf("nan")
            y = m.power(u, v)
            return y if isinstance(y, m.mpf) else m.mpf("nan")
    return B._u("pow", one, 2)(x, y)
