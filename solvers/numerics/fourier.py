"""Linear response of a linear, time-invariant system, computed two independent ways.

* ``inverse_fourier(chi, t, poles)``: the Green's function as the inverse
  transform G(t) = (1/2 pi) int chi(w) exp(-i w t) dw of a response function
  with chi(-w) = conj(chi(w)), folded onto w >= 0:
  G(t) = (1/pi) int_0^inf [Re chi cos(w t) + Im chi sin(w t)] dw.
  The window [0, W] is cut at the poles' real parts and at their widths
  (|Im| multiples) and integrated by a Fourier-weighted rule of our own
  (``fourier_quad``: Filon's idea on Gauss-Legendre panels, the oscillation
  integrated exactly, never sampled), the tail [W, inf) cycle by cycle with
  Wynn's epsilon extrapolation of the alternating partial sums
  (``fourier_tail``).  Numpy only: scipy.integrate costs 0.6-0.9 s to import.
* ``impulse_spectrum(A, b, c, w)``: int_0^inf c.y(t) exp(i w t) dt for
  y' = A y, y(0) = b (the transform of the impulse response).  One segment
  [0, D] of the fundamental matrix Phi is integrated together with the
  accumulators w_j = int_0^D c.Phi(s) e_j exp(i w s) ds; the rest of the
  infinite run follows exactly from the semigroup property
  Phi(t + D) = Phi(D) Phi(t): the integral is the geometric series
  sum_k exp(i w k D) w.Phi(D)^k b = w.(1 - exp(i w D) Phi(D))^(-1) b.
  No truncation of the decaying tail, no thousands of ringing periods.
  Liouville's formula det Phi(D) = exp(D tr A) is returned as the monitor.
Both work best in scaled variables (rates of order one).
"""

from __future__ import annotations

import cmath
import heapq
import math
from dataclasses import dataclass

import numpy as np

from mech.core.errors import NumericFailure
from mech.core import budget
from mech.solvers.numerics.ode import integrate

__all__ = ["inverse_fourier", "impulse_spectrum", "oscillator_spectra", "Spectrum", "FourierIntegral", "fourier_quad",
           "fourier_tail"]


# ---------------------------------------------------------------------------------------------
# Fourier-weighted quadrature on numpy alone
# ---------------------------------------------------------------------------------------------

_NODES = 16  # Gauss-Legendre nodes per panel: f is interpolated by a polynomial of degree 15
_FILON: dict = {}


def _filon_table(n: int):
    """Nodes x_i on [-1, 1] and the matrix taking f(x_i) to the Legendre coefficients of its interpolant."""
    if n not in _FILON:
        x, w = np.polynomial.legendre.leggauss(n)
        P = np.polynomial.legendre.legvander(x, n - 1)  # P[i, j] = P_j(x_i)
        to_coeffs = (np.arange(n) + 0.5)[:, None] * (w[None, :] * P.T)  # exact: p P_j has degree < 2n
        _FILON[n] = (x, w, to_coeffs, {})
    return _FILON[n]


def _spherical_bessel(n: int, k: float) -> np.ndarray:
    """j_0(k) .. j_{n-1}(k) for k >= 0: series for small k, upward recurrence where every order is
    below k (stable there), Miller's downward recurrence otherwise."""
    out = np.zeros(n)
    if k == 0.0:
        out[0] = 1.0
        return out
    if k <= 1.0:
        # j_j(k) = k^j/(2j+1)!! sum_m (-k^2/2)^m / (m! (2j+3)(2j+5)...(2j+2m+1))
        lead, x = 1.0, -0.5 * k * k
        for j in range(n):
            if j:
                lead *= k / (2 * j + 1)
            if lead < 1e-300:
                break
            term, total, m = 1.0, 1.0, 0
            while abs(term) > 1e-17 * abs(total):
                m += 1
                term *= x / (m * (2 * j + 2 * m + 1))
                total += term
            out[j] = lead * total
        return out
    s, c = math.sin(k), math.cos(k)
    j0, j1 = s / k, (s / k - c) / k
    # (the recurrences on Python floats, the array formed once: a per-element store costs more than the step)
    if k >= n:
        seq = [j0, j1]
        for j in range(1, n - 1):
            seq.append((2 * j + 1) / k * seq[j] - seq[j - 1])
        out[:] = seq[:n]
        return out
    top = n + 20 + int(k)
    upper, here = 0.0, 1.0
    raw = [0.0] * n
    for j in range(top, 0, -1):
        lower = (2 * j + 1) / k * here - upper  # j_{j-1} from j_j and j_{j+1}
        upper, here = here, lower
        if abs(here) > 1e100:
            upper *= 1e-100
            here *= 1e-100
            raw = [r * 1e-100 for r in raw]
        if j - 1 < n:
            raw[j - 1] = here
    # j_0 and j_1 never vanish together: scale to both in the least-squares sense
    scale = (raw[0] * j0 + raw[1] * j1) / (raw[0] ** 2 + raw[1] ** 2)
    return np.array(raw) * scale


_MOMENTS: dict = {}


def _filon_moments(n: int):
    """2 i^j (j = 0..n) and the factors j + 1, j, 2 j + 1 (j < n) of ``_filon_weights``, made once per n."""
    if n not in _MOMENTS:
        j = np.arange(n + 1)
        jj = j[:n].astype(float)
        _MOMENTS[n] = (2.0 * np.array([1.0, 1j, -1.0, -1j])[j % 4], jj + 1.0, jj, 2.0 * jj + 1.0)
    return _MOMENTS[n]


def _filon_weights(n: int, k: float):
    """Weights w_i with int_{-1}^{1} p(u) exp(i k u) du = sum_i w_i p(x_i), exact for degree < n,
    and their derivatives in k.

    The interpolant's Legendre series integrates term by term against the exponential:
    m_j = int P_j(u) exp(i k u) du = 2 i^j j_j(k) (spherical Bessel functions); the derivative
    needs u P_j = ((j + 1) P_{j+1} + j P_{j-1})/(2j + 1).  (A panel's k = omega h is rounded;
    the derivative corrects for that rounding, an error of 1e-16 k in the phase otherwise.)"""
    x, w, to_coeffs, cache = _filon_table(n)
    found = cache.get(k)
    if found is None:
        two_i_j, up, down, odd = _filon_moments(n)
        m = two_i_j * _spherical_bessel(n + 1, abs(k))
        if k < 0:
            m = m.conj()  # j_j(-k) = (-1)^j j_j(k)
        below = np.empty(n, dtype=complex)
        below[0] = 0.0
        below[1:] = m[: n - 1]
        dm = 1j * (up * m[1:] + down * below) / odd
        found = (m[:n] @ to_coeffs, dm @ to_coeffs)
        if len(cache) < 4096:
            cache[k] = found
    return found


_SPLIT = 134217729.0  # 2^27 + 1: Dekker's splitting of a double into two 26-bit halves
_TWO_PI = (float.fromhex("0x1.921fb54000000p+2"), float.fromhex("0x1.10b4611800000p-28"),
           float.fromhex("0x1.313198a2e0370p-59"))  # 2 pi in three parts, the first two of 30 bits


def _two_product(a: float, b: float):
    """(p, e) with p = fl(a b) and p + e = a b exactly (Dekker's splitting).  A factor above 2^995, whose
    split would overflow, is split at 2^-60 of itself and the pair scaled back (powers of two: exact);
    a product beyond the floating-point range is a ``NumericFailure`` (a phase no double can hold)."""
    p = a * b
    if not math.isfinite(p):
        raise NumericFailure(f"Fourier quadrature: the phase {a:.3g} x {b:.3g} leaves the floating-point range")
    if abs(a) > 2.0**995 or abs(b) > 2.0**995:
        k = 60 * ((abs(a) > 2.0**995) + (abs(b) > 2.0**995))
        sa = math.ldexp(a, -60) if abs(a) > 2.0**995 else a
        sb = math.ldexp(b, -60) if abs(b) > 2.0**995 else b
        q, e = _two_product(sa, sb)
        return p, math.ldexp(e, k)
    t = _SPLIT * a
    ah = t - (t - a)
    al = a - ah
    t = _SPLIT * b
    bh = t - (t - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _pi_fixed(bits: int) -> int:
    """floor(pi 2^bits) in integers (Machin's formula with guard bits)."""
    guard = bits + 16
    one = 1 << guard

    def atan_inv(n: int) -> int:
        total = term = one // n
        k, n2, sign = 1, n * n, 1
        while term:
            term //= n2
            k += 2
            sign = -sign
            total += sign * (term // k)
        return total

    return (4 * (4 * atan_inv(5) - atan_inv(239))) >> 16


_FIX = 160  # bits after the point of the exact reduction below
_TWO_PI_FIX = 2 * _pi_fixed(_FIX + 2) >> 2  # 2 pi in units of 2^-160, good to one unit


def _reduce_exact(p: float, e: float) -> float:
    """(p + e) mod 2 pi in [-pi, pi) for any pair of doubles: both scaled to integers in units of 2^-160
    (exact for |e| above 2^-160; below it e is far under the result's own rounding), then reduced by
    2 pi held to 160 bits, whose error times the quotient (< 2^1024/6) stays below 2^-100 for every
    phase that carries a digit at all."""
    n, d = p.as_integer_ratio()
    x = (n << _FIX) // d
    n, d = e.as_integer_ratio()
    x += (n << _FIX) // d
    half = _TWO_PI_FIX >> 1
    r = (x + half) % _TWO_PI_FIX - half
    return r / (1 << _FIX) if r.bit_length() < 1000 else math.ldexp(r >> (_FIX - 60), -60)


def _turn(omega: float, x: float) -> complex:
    """exp(i omega x) for the exact product of the two doubles.

    fl(omega x) is off by half an ulp of the product, a phase error of 1e-16 |omega x| that would
    set a noise floor on every panel far out on the w axis; the product is instead formed exactly
    as a pair of doubles and reduced modulo 2 pi: in three parts (Cody and Waite) while the turns
    stay below 2^22, exactly in integers beyond (a late time, |omega x| of 1e7..1e15: the phase
    then still carries every digit of the given doubles, which the Filon panels need to agree
    with one another)."""
    p, e = _two_product(omega, x)
    turns = round(p / (2.0 * math.pi))
    if abs(turns) >= 2**22:
        r = _reduce_exact(p, e)
        return complex(math.cos(r), math.sin(r))
    r = ((p - turns * _TWO_PI[0]) - turns * _TWO_PI[1]) + (e - turns * _TWO_PI[2])
    return complex(math.cos(r), math.sin(r))


class _Panels:
    """The Filon rule on panels of one integrand f(w) exp(i omega w), with a count of evaluations."""

    def __init__(self, f, omega: float, part: str | None, n: int = _NODES, local: bool = False):
        self.f, self.omega, self.n, self.local = f, float(omega), n, local
        self.nodes = _filon_table(n)[0]
        self.project = {"re": lambda z: z.real, "im": lambda z: z.imag, None: lambda z: z}[part]
        self.evaluations = 0
        self._turns: dict = {}  # exp(i omega x) by x: a panel's start is its left half's start, and so on
        self._halves: dict = {}  # a half width's corrected weights and exp(i omega h): bisections repeat them

    def turn(self, x: float) -> complex:
        found = self._turns.get(x)
        if found is None:
            found = self._turns[x] = _turn(self.omega, x)
        return found

    def values(self, spans) -> np.ndarray:
        """f at the nodes of every panel in ``spans``, one call: a row per panel."""
        lo = np.array([a for a, _ in spans])
        half = 0.5 * (np.array([b for _, b in spans]) - lo)
        if self.local:
            # f(a, y) at w = a + y, y = h (1 + u) exact to its own rounding: near a pole of width 1e-10
            # at w ~ 1 the rounding of w itself (1e-16) would move f by a part in 1e6
            offs = half[:, None] * (1.0 + self.nodes)
            vals = np.asarray(self.f(np.repeat(lo, self.n), offs.ravel()))
        else:
            vals = np.asarray(self.f(((lo + half)[:, None] + half[:, None] * self.nodes).ravel()))
        self.evaluations += vals.size
        vals = vals.reshape(len(spans), self.n)
        if not np.isfinite(vals).all():
            a, b = spans[int(np.argmin(np.isfinite(vals).all(axis=1)))]  # the first panel that is not
            raise NumericFailure(f"Fourier quadrature: the integrand is not finite on [{a:.6g}, {b:.6g}]")
        return vals

    @staticmethod
    def split(a: float, b: float):
        """The panel [a, b] and its two halves, as ``piece`` rules them."""
        m = a + 0.5 * (b - a)
        return [(a, b), (a, m), (m, b)]

    def rule(self, a: float, b: float, vals=None) -> complex:
        """The Filon rule on [a, b] in the local variable w = a + h (1 + u): the phases at a and
        over the half width h are formed from exact products, and b - a is exact for a panel
        with a <= b <= 2a, so that panels tile the axis without a phase error of 1e-16 |omega w|."""
        if vals is None:
            vals = self.values([(a, b)])[0]
        half = 0.5 * (b - a)
        found = self._halves.get(half)
        if found is None:
            k, dk = _two_product(self.omega, half)
            weights, slope = _filon_weights(self.n, k)
            found = self._halves[half] = (weights + dk * slope, _turn(self.omega, half))
        corrected, turn_half = found
        return half * self.turn(a) * turn_half * complex(corrected @ vals)

    def piece(self, a: float, b: float, vals=None, known=None):
        """(value, error estimate, halves): the halves' sum, its difference from the whole panel's rule,
        and each half's (values at its nodes, rule), which its own ``piece`` takes as ``known`` once the
        panel is bisected (f is then evaluated on the new halves only).  ``vals``: f at the nodes of the
        whole panel and its halves, if already evaluated (``split``)."""
        m = a + 0.5 * (b - a)
        if vals is not None:
            whole, left, right = vals
        elif known is not None:
            whole = known[0]
            left, right = self.values([(a, m), (m, b)])
        else:
            whole, left, right = self.values(self.split(a, b))
        rule_left, rule_right = self.rule(a, m, left), self.rule(m, b, right)
        halves = rule_left + rule_right
        rule_whole = self.rule(a, b, whole) if known is None else known[1]
        return halves, float(abs(self.project(halves - rule_whole))), ((left, rule_left), (right, rule_right))


def _adaptive(panels: _Panels, cuts, epsabs: float, epsrel: float, limit: int):
    """Global adaptive bisection of the panels between ``cuts``: ``(value, error estimate, panels)``."""
    heap = []
    first = [(a, b) for a, b in zip(cuts[:-1], cuts[1:]) if b > a]
    if first:
        # the first panels and their halves evaluated in one call of f
        vals = panels.values([span for a, b in first for span in panels.split(a, b)]).reshape(len(first), 3, -1)
        for (a, b), v3 in zip(first, vals):
            v, e, kids = panels.piece(a, b, v3)
            heap.append((-e, a, b, v, kids))
    if not heap:
        return 0.0, 0.0, 0
    heapq.heapify(heap)

    def sums():
        # exact re-summation: round-off in the running sums cannot accumulate
        total = complex(math.fsum(item[3].real for item in heap), math.fsum(item[3].imag for item in heap))
        return total, math.fsum(-item[0] for item in heap), math.fsum(abs(panels.project(item[3])) for item in heap)

    def tolerance(total, size):
        # never below the round-off of the panels' sum: an estimate there is noise, not error
        return max(epsabs, epsrel * abs(panels.project(total)), 50.0 * 2.0**-52 * size)

    total, err, size = sums()
    while True:
        if err <= tolerance(total, size):
            total, err, size = sums()  # confirm on exact sums before stopping
            if err <= tolerance(total, size):
                return panels.project(total), err, len(heap)
        if len(heap) >= limit:
            raise NumericFailure(
                f"Fourier quadrature: error estimate {err:.3g} above the tolerance "
                f"{tolerance(total, size):.3g} after {len(heap)} panels"
            )
        budget.check("Fourier quadrature")
        neg_e, a, b, v, kids = heapq.heappop(heap)
        m = a + 0.5 * (b - a)
        if not (a < m < b):
            raise NumericFailure(f"Fourier quadrature: panel [{a:.17g}, {b:.17g}] too narrow to refine")
        total, err, size = total - v, err + neg_e, size - abs(panels.project(v))
        for (lo, hi), kid in zip(((a, m), (m, b)), kids):
            v, e, grand = panels.piece(lo, hi, known=kid)
            heapq.heappush(heap, (-e, lo, hi, v, grand))
            total, err, size = total + v, err + e, size + abs(panels.project(v))
        if len(heap) % 64 == 0:
            total, err, size = sums()


def fourier_quad(f, a: float, b: float, omega: float, *, part: str | None = "re", epsabs: float = 1e-12,
                 epsrel: float = 1e-12, points=None, limit: int = 4000, n: int = _NODES):
    """``(value, error estimate, panels)`` of int_a^b f(w) exp(i omega w) dw on a finite interval.

    ``f`` takes an array of w and returns real or complex values; ``part`` "re"/"im" keeps the
    real/imaginary part (for a real f: the cos/sin weight), None the complex value.  Filon's idea:
    on every panel f is interpolated at Gauss-Legendre nodes and the product with the exponential
    is integrated exactly, so a panel needs to resolve f only, not the oscillation.  The panels
    are bisected where the estimate (the halves' rule against the whole panel's) is largest
    until the summed estimate is below max(epsabs, epsrel |value|); ``points`` start the
    partition.  No convergence within ``limit`` panels raises NumericFailure."""
    a, b = float(a), float(b)
    if not (math.isfinite(a) and math.isfinite(b)):
        raise ValueError("fourier_quad: finite limits only (fourier_tail takes [a, inf))")
    sign = 1.0
    if b < a:
        a, b, sign = b, a, -1.0
    cuts = sorted({a, b, *(float(p) for p in (points or ()) if a < float(p) < b)})
    panels = _Panels(f, omega, part, n)
    value, err, count = _adaptive(panels, cuts, epsabs, epsrel, limit)
    return sign * value, err, count


def _wynn_epsilon(table: list, partial: float) -> float:
    """Append a partial sum to Wynn's epsilon table (kept as its last antidiagonal) and return the
    newest estimate of the limit (the highest even column)."""
    new = [partial]
    for j, prev in enumerate(table):
        below = table[j - 1] if j else 0.0
        diff = new[j] - prev
        if diff == 0 or not cmath.isfinite(diff):
            break  # the column has converged (or lost all digits): stop the antidiagonal here
        new.append(below + 1.0 / diff)
    table[:] = new
    return new[2 * ((len(new) - 1) // 2)]


def fourier_tail(f, a: float, omega: float, *, part: str | None = "re", epsabs: float = 1e-12,
                 epsrel: float = 1e-12, max_terms: int = 150, n: int = _NODES):
    """``(value, error estimate, terms)`` of int_a^inf f(w) exp(i omega w) dw for f decaying to zero.

    The range is cut into cycles of an odd number of half periods of the exponential (length
    about max(pi/|omega|, a/2)), so that the cycles' integrals alternate in sign with an amplitude
    that varies smoothly from one to the next; each cycle is integrated by the adaptive Filon panels, and
    the partial sums are extrapolated by Wynn's epsilon algorithm.  The error estimate is the
    spread of the last three extrapolations plus the cycles' own estimates; no convergence within
    ``max_terms`` cycles raises NumericFailure."""
    a, omega = float(a), float(omega)
    if omega == 0.0:
        raise ValueError("fourier_tail: omega = 0 is not an oscillatory integral")
    return _tail(_Panels(f, omega, part, n), a, epsabs, epsrel, max_terms)


def _tail(panels: _Panels, a: float, epsabs: float, epsrel: float, max_terms: int = 150):
    half_period = math.pi / abs(panels.omega)
    odd = 2 * max(0, int(0.5 * (0.5 * max(a, half_period) / half_period - 1.0))) + 1
    cycle = odd * half_period
    table: list = []
    estimates: list = []
    partial, quad_err, first = 0.0, 0.0, 0.0
    for k in range(max_terms):
        budget.check("Fourier quadrature, tail")
        lo = a + k * cycle
        # the cycles' own errors must sum to a small part of the tolerance: 1/(8 (k+1)) of it each
        share = 8.0 * (k + 1)
        if k == 0:
            v, e, _ = _adaptive(panels, [lo, lo + cycle], epsabs / share, epsrel / share, 400)
            first = abs(v)
        else:
            v, e, _ = _adaptive(panels, [lo, lo + cycle], max(epsabs, epsrel * first) / share, 0.0, 400)
        partial += v
        quad_err += e
        if quad_err > max(epsabs, epsrel * abs(partial)):
            raise NumericFailure(
                f"Fourier quadrature: the tail's cycles are not integrable to the tolerance "
                f"{max(epsabs, epsrel * abs(partial)):.3g} (round-off {quad_err:.3g})"
            )
        estimates.append(_wynn_epsilon(table, partial))
        if len(estimates) >= 6:
            best = estimates[-1]
            spread = abs(best - estimates[-2]) + abs(best - estimates[-3])
            err = spread + quad_err + 50.0 * 2.0**-52 * abs(partial)
            if err <= max(epsabs, epsrel * abs(best)):
                return best, err, k + 1
    raise NumericFailure(
        f"Fourier quadrature: the tail from {a:.6g} did not converge in {max_terms} cycles "
        f"(last extrapolations {estimates[-3:]})"
    )


@dataclass
class FourierIntegral:
    value: float
    abserr: float  # the window's summed panel estimates plus the tail's extrapolation estimate
    panels: int  # panels of the window [0, W]
    tail_cycles: int  # cycles of the tail [W, inf) summed before the extrapolation settled
    evaluations: int  # of chi
    target: float = math.nan  # the absolute tolerance aimed at: epsrel times the pieces' summed sizes (or round-off)


def _breakpoints(poles, window):
    pts = {0.0, window}
    for z in poles:
        c, w = abs(z.real), abs(z.imag)
        pts.add(c)
        # offsets growing geometrically from the peak's width to the window: a narrow resonance's
        # Lorentzian tails are resolved piece by piece
        k = 0.5 * w
        while k < window and k > 0:
            for x in (c - k, c + k):
                pts.add(x)
            k *= 4.0
    return sorted(x for x in pts if 0.0 <= x <= window)


def inverse_fourier(chi, t: float, poles, *, epsrel: float = 1e-12, window_factor: float = 40.0,
                    vectorized: bool = False, local: bool = False) -> FourierIntegral:
    """G(t) = (1/pi) int_0^inf [Re chi cos(w t) + Im chi sin(w t)] dw; ``poles``: chi's poles (complex).

    The integrand is Re[chi(w) exp(-i w t)].  The tolerance is ``epsrel`` times the summed sizes of
    the window pieces' integrals (G(-t) = 0 is all cancellation: a tolerance relative to it would
    mean nothing).  ``chi`` takes one frequency, or an array of them when ``vectorized``; with ``local``
    (vectorized only) it takes two arrays (a, y) for the frequency a + y, a a breakpoint and y the
    offset from it, so that it can form its differences from the poles without the rounding of a + y."""
    if t == 0:
        raise ValueError("inverse_fourier: t = 0 is where G jumps; ask for t != 0")
    poles = [complex(z) for z in poles]
    window = window_factor * max(1.0, max(abs(z) for z in poles))
    pts = _breakpoints(poles, window)
    # an early time (|t| far below 1/W): the exponential has not turned once over the window, and the
    # tail's first cycle (a half period pi/|t|) would span hundreds of decades of a decaying chi in one
    # adaptive piece, whose bisections cannot reach the window end (t = 4e-200 gave G = 8e-3 for ~t).
    # The window is carried on in cuts a factor 4 apart until the exponential turns (window_factor / |t|)
    reach = window_factor / abs(float(t))
    while pts[-1] < reach:
        pts.append(4.0 * pts[-1])
    window = pts[-1]
    f = chi if vectorized else (lambda ws: np.array([chi(float(x)) for x in ws], dtype=complex))
    panels = _Panels(f, -float(t), "re", local=local and vectorized)
    # a peak narrower than the floats resolve around it (width below 2^-40 of its centre c: a Q of 1e12
    # and up, to 1e201) is integrated over [c - K, c + K] in the offset y = w - c, whose floats are as
    # fine as the width needs: exp(-i w t) = exp(-i c t) exp(-i y t), chi(c, y) from the local form
    cores = []
    if local and vectorized:
        for c in sorted({abs(z.real) for z in poles if z.real != 0.0 and abs(z.imag) < 2.0**-40 * abs(z.real)}):
            K = math.ldexp(1.0, math.frexp(c)[1] - 30)  # ~1e-9 c, a power of two: c +- K exact
            if any(lo - K < c < hi + K for lo, hi, _, _ in cores):
                continue
            lo, hi = c - K, c + K  # rounded, perhaps (c + K past a power of two): the offsets below are
            # then hi - c and lo - c exactly (Sterbenz), so that the core and the window tile without a gap
            width = min(abs(z.imag) for z in poles if abs(z.real) == c)
            offs, k = {0.0, lo - c, hi - c}, 0.5 * width
            while 0.0 < k < 0.5 * K:
                offs |= {k, -k}
                k *= 4.0
            pts = sorted({x for x in pts if not lo < x < hi} | {lo, hi})
            cores.append((lo, hi, c, sorted(offs)))
    excluded = {(lo, hi) for lo, hi, _, _ in cores}
    pieces = [(a, b) for a, b in zip(pts[:-1], pts[1:]) if b > a and (a, b) not in excluded]
    core_panels = [(c, _Panels(lambda ys, c=c: chi(np.full_like(ys, c), ys), -float(t), None))
                   for _, _, c, _ in cores]
    core_pieces = [[(a, b) for a, b in zip(offs[:-1], offs[1:])] for _, _, _, offs in cores]
    at_nodes = panels.values(pieces) if pieces else np.zeros((0, panels.n))  # f on each piece, once
    scale = math.fsum(abs(panels.rule(a, b, v).real) for (a, b), v in zip(pieces, at_nodes))
    scale += math.fsum(abs(cp.rule(a, b)) for (_, cp), cps in zip(core_panels, core_pieces) for a, b in cps)
    # the rule's round-off is relative to the integral of |f|, not to the oscillation's cancelled pieces:
    # at a late time (t 1e7 over a peak of width 1e-5) the pieces cancel far below it, and a tolerance
    # under that floor is never met (it once ran 20000 panels and gave up)
    weights = _filon_table(panels.n)[1]
    l1 = math.fsum(0.5 * (b - a) * float(weights @ np.abs(v)) for (a, b), v in zip(pieces, at_nodes))
    for (_, cp), cps in zip(core_panels, core_pieces):
        l1 += math.fsum(0.5 * (b - a) * float(weights @ np.abs(v)) for (a, b), v in zip(cps, cp.values(cps)))
    epsabs = max(epsrel * scale, 64.0 * 2.0**-52 * l1)
    # the body: each run of cuts between the cores, and each core in its offset variable
    runs, run_ = [], [pts[0]]
    for a, b in zip(pts[:-1], pts[1:]):
        if (a, b) in excluded:
            runs.append(run_)
            run_ = [b]
        else:
            run_.append(b)
    runs.append(run_)
    share = 0.5 * epsabs / (len(runs) + len(cores))
    body, body_err, count = 0.0, 0.0, 0
    for cuts in runs:
        if len(cuts) > 1:
            v, e, n_ = _adaptive(panels, cuts, share, 0.0, 20000)
            body, body_err, count = body + v, body_err + e, count + n_
    for (c, cp), (_, _, _, offs) in zip(core_panels, cores):
        v, e, n_ = _adaptive(cp, offs, share, 0.0, 20000)
        body += (_turn(-float(t), c) * v).real
        body_err, count = body_err + e, count + n_
        panels.evaluations += cp.evaluations
    tail, tail_err, cycles = _tail(panels, window, 0.5 * epsabs, 0.0)
    return FourierIntegral((body + tail) / math.pi, (body_err + tail_err) / math.pi, count, cycles,
                           panels.evaluations, epsabs / math.pi)


@dataclass
class Spectrum:
    value: complex
    segment: float
    liouville_drift: float
    traj: object


def _decays(A: np.ndarray) -> bool:
    """Every eigenvalue of A has a negative real part.  For 2 x 2, exactly (Routh-Hurwitz: trace < 0
    and det > 0), not from rounded eigenvalues: a strongly overdamped oscillator's slow rate
    det / |trace| (1e-16 of the fast one at a damping ratio 1e8) is below the eigenvalues' round-off."""
    if A.shape == (2, 2):
        det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
        return bool(A[0, 0] + A[1, 1] < 0 and det > 0)
    return bool(np.max(np.linalg.eigvals(A).real) < 0)


FLOW = "flow"


def impulse_spectrum(A, b, c, omega: float, *, rtol: float, segment: float, method: str = "DOP853",
                     integrator: str | None = None, atol=None) -> Spectrum:
    """int_0^inf c.y(t) exp(i omega t) dt for y' = A y, y(0) = b; all eigenvalues of A must decay.

    ``method``: an ODE method for the segment (``ode.integrate``), or ``FLOW``: no stepping (stiff
    systems, on numpy alone), see ``_impulse_spectrum_flow``; a forced ``integrator`` replaces it."""
    A = np.asarray(A, dtype=float)
    b = np.asarray(b, dtype=float)
    c = np.asarray(c, dtype=float)
    n = A.shape[0]
    if not _decays(A):
        raise NumericFailure("impulse_spectrum: the system does not decay; its transform does not exist")

    nn = n * n
    a00, a01, a10, a11 = A.ravel().tolist() if n == 2 else (0.0,) * 4
    c0, c1 = c.tolist() if n == 2 else (0.0,) * 2

    def rhs2(s, y):
        # n = 2 on Python floats (called a dozen times a step: numpy's per-call overhead dominated):
        # Phi' = A Phi (row-major) and the accumulators' rates c.Phi cos(omega s), c.Phi sin(omega s)
        p0, p1, p2, p3 = y[:4].tolist()
        o0, o1 = c0 * p0 + c1 * p2, c0 * p1 + c1 * p3
        cs, sn = math.cos(omega * s), math.sin(omega * s)
        return np.array([a00 * p0 + a01 * p2, a00 * p1 + a01 * p3, a10 * p0 + a11 * p2, a10 * p1 + a11 * p3,
                         o0 * cs, o1 * cs, o0 * sn, o1 * sn])

    def rhs(s, y):
        # Phi' = A Phi, and the accumulators' rates c.Phi cos(omega s), c.Phi sin(omega s), filled in place
        Phi = y[:nn].reshape(n, n)
        out = c @ Phi  # the coordinate's response to each basis initial state
        dy = np.empty(nn + 2 * n)
        np.matmul(A, Phi, out=dy[:nn].reshape(n, n))
        np.multiply(out, math.cos(omega * s), out=dy[nn : nn + n])
        np.multiply(out, math.sin(omega * s), out=dy[nn + n :])
        return dy

    def jac(s, y):
        J = np.zeros((n * n + 2 * n, n * n + 2 * n))
        J[: n * n, : n * n] = np.kron(A, np.eye(n))
        cs, sn = math.cos(omega * s), math.sin(omega * s)
        for j in range(n):
            for i in range(n):
                J[n * n + j, i * n + j] = c[i] * cs
                J[n * n + n + j, i * n + j] = c[i] * sn
        return J

    if method == FLOW:
        if not integrator:
            return _impulse_spectrum_flow(A, b, c, omega, rtol=rtol, segment=segment)
        method = "LSODA"  # replaced by the forced integrator (mech bench) anyway
    y0 = np.concatenate([np.eye(n).ravel(), np.zeros(2 * n)])
    if atol is None:
        atol = rtol * 1e-3
    traj = integrate(rhs2 if n == 2 else rhs, (0.0, segment), y0, rtol=rtol, atol=atol, method=method, jac=jac, integrator=integrator)
    yend = traj.y_end
    Phi = yend[: n * n].reshape(n, n)
    w = yend[n * n : n * n + n] + 1j * yend[n * n + n :]
    lam = complex(math.cos(omega * segment), math.sin(omega * segment))
    M = np.eye(n) - lam * Phi
    value = complex(w @ np.linalg.solve(M, b))
    expected_det = math.exp(segment * np.trace(A))
    # relative to the size of the products in the determinant (it can be far smaller than they are)
    drift = (np.linalg.det(Phi) - expected_det) / max(float(np.prod(np.max(np.abs(Phi), axis=1))), 1e-300)
    return Spectrum(value, segment, float(drift), traj)


def _impulse_spectrum_flow(A, b, c, omega: float, *, rtol: float, segment: float) -> Spectrum:
    """``impulse_spectrum`` without an integrator, for a stiff A: Phi(D) = exp(A D) by scaling and squaring
    (linear_flow), the geometric sum's state z = (1 - exp(i w D) Phi(D))^(-1) b first, then the one
    remaining integral int_0^D c.Phi(s) z exp(i w s) ds by adaptive Gauss-Legendre quadrature
    (``quadrature.quad``, real and imaginary parts to a tenth of rtol, relative to the integral of its
    modulus), the integrand's flow exp(A s) at each rule's nodes at once (``expm_many``).  The
    quadrature's tolerance is the part that follows rtol; the flow is exact to its rounding, which
    Liouville's det Phi(D) = exp(D tr A) monitors as in the integrated route."""
    import time

    from mech.solvers.numerics.linear_flow import expm, expm_many
    from mech.solvers.numerics.ode import Trajectory
    from mech.solvers.numerics.quadrature import quad

    start = time.perf_counter()
    n = A.shape[0]
    Phi = expm(A * segment)
    lam = complex(math.cos(omega * segment), math.sin(omega * segment))
    z = np.linalg.solve(np.eye(n) - lam * Phi, b.astype(complex))
    cache: dict = {}

    def response(u):
        key = u.tobytes()
        if key not in cache:
            budget.check("impulse_spectrum flow quadrature")
            cache[key] = (np.einsum("i,kij->kj", c, expm_many(A, u)) @ z) * np.exp(1j * omega * u)
        return cache[key]

    # the fast transient sits within a few 1/||A|| of the start: breakpoints there
    fast = 1.0 / float(np.max(np.sum(np.abs(A), axis=0)))
    points = [k * fast for k in (1.0, 10.0, 100.0) if k * fast < segment]
    eps = max(0.1 * rtol, 1e-14)
    size, _ = quad(lambda u: np.abs(response(u)), 0.0, segment, epsrel=1e-3, epsabs=0.0, points=points,
                   vectorized=True, limit=500)
    re, re_err = quad(lambda u: response(u).real, 0.0, segment, epsrel=eps, epsabs=eps * size, points=points,
                      vectorized=True, limit=500)
    im, im_err = quad(lambda u: response(u).imag, 0.0, segment, epsrel=eps, epsabs=eps * size, points=points,
                      vectorized=True, limit=500)
    nodes = sum(len(u) for u in cache.values())
    expected_det = math.exp(segment * np.trace(A))
    drift = (np.linalg.det(Phi) - expected_det) / max(float(np.prod(np.max(np.abs(Phi), axis=1))), 1e-300)
    traj = Trajectory(t=np.array([0.0, segment]), y=np.stack([np.eye(n).ravel(), Phi.ravel()], axis=1),
                      t_events=[], y_events=[], nfev=nodes, njev=0, nlu=0, method="exp(A t) + Gauss-Legendre",
                      rtol=rtol, wall_s=time.perf_counter() - start, status=0, message="",
                      extra={"quad_error_estimate": re_err + im_err})
    return Spectrum(complex(re, im), segment, float(drift), traj)


def oscillator_spectra(d, omega, *, rtol: float, segment, follow, atol=None):
    """``impulse_spectrum`` of N damped oscillators q'' + 2 d q' + q = f (scaled), c = (1, 0), b = (0, 1),
    stepped together: the fundamental matrix and the two accumulators of each variant over its own segment
    [0, D] in the time u = s/D in [0, 1] (so that one span holds them all), by ``follow`` (an ensemble's
    ``Tally.follow``: mech's DOP853 steps them together, one alone by ``ode.integrate``), then the
    geometric sum of each.  Arrays of N: ``d``, ``omega``, ``segment``; ``atol`` a number or one per
    component (None: rtol/1000).  Returns (values (N,) complex, Liouville drifts (N,), the ``Ensemble``:
    its ``failed`` variants have NaN values)."""
    d, omega, segment = (np.asarray(x, dtype=float) for x in (d, omega, segment))
    N = d.size
    phase = omega * segment  # exp(i omega s) = exp(i phase u)

    def make_rhs(sel):
        # Phi' = A Phi (row-major, A = [[0, 1], [-1, -2 d]]) and the accumulators' rates c.Phi cos, c.Phi sin,
        # times D (d/du = D d/ds); elementwise, so that it takes one variant's state (8,) or all (8, N)
        two_d, D, ph = 2.0 * d[sel], segment[sel], phase[sel]
        if np.ndim(two_d) == 0:
            two_d, D, ph = float(two_d), float(D), float(ph)

        def rhs(u, y):
            p0, p1, p2, p3 = y[0], y[1], y[2], y[3]
            cs, sn = D * np.cos(ph * u), D * np.sin(ph * u)
            return np.stack([D * p2, D * p3, -D * (p0 + two_d * p2), -D * (p1 + two_d * p3),
                             p0 * cs, p1 * cs, p0 * sn, p1 * sn])

        return rhs

    y0 = np.zeros((8, N))
    y0[0] = y0[3] = 1.0
    got = follow(make_rhs, (0.0, 1.0), y0, rtol=rtol, atol=rtol * 1e-3 if atol is None else atol)
    p0, p1, p2, p3, r0, r1, i0, i1 = got.y_end
    lam = np.exp(1j * phase)
    # (1 - lam Phi) z = b = (0, 1) by Cramer's rule, the value w.z
    m00, m01, m10, m11 = 1.0 - lam * p0, -lam * p1, -lam * p2, 1.0 - lam * p3
    det = m00 * m11 - m01 * m10
    with np.errstate(invalid="ignore", divide="ignore"):
        value = ((r0 + 1j * i0) * (-m01) + (r1 + 1j * i1) * m00) / det
    expected_det = np.exp(-2.0 * d * segment)
    size = np.maximum(np.maximum(np.abs(p0), np.abs(p1)) * np.maximum(np.abs(p2), np.abs(p3)), 1e-300)
    drift = (p0 * p3 - p1 * p2 - expected_det) / size
    return value, drift, got
