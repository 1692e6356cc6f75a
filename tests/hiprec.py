"""Sines, cosines and exponentials of doubles to ~80 digits with the standard library's decimal module.

Reference values for the long-phase tests: a phase of 1e10 rad evaluated exactly (as the product of
the given doubles), so that the round-off of a double-precision method can be measured against it."""

from decimal import Decimal, localcontext

PREC = 100


def _atan_inv(n: int) -> Decimal:
    x = Decimal(1) / n
    x2, s, t, k = x * x, x, x, 1
    while True:
        t = -t * x2
        k += 2
        term = t / k
        if abs(term) < Decimal(10) ** -(PREC + 5):
            return s
        s += term


with localcontext() as _ctx:
    _ctx.prec = PREC + 10
    PI = 4 * (4 * _atan_inv(5) - _atan_inv(239))  # Machin


def D(x) -> Decimal:
    """A double (or int) exactly as a Decimal."""
    return Decimal(x)


def sincos(x: Decimal) -> tuple[Decimal, Decimal]:
    with localcontext() as ctx:
        ctx.prec = PREC
        two_pi = 2 * PI
        r = x - (x / two_pi).to_integral_value() * two_pi
        s = c = Decimal(0)
        t, k = Decimal(1), 0
        while True:
            if k % 2 == 0:
                c += t if (k // 2) % 2 == 0 else -t
            else:
                s += t if (k // 2) % 2 == 0 else -t
            k += 1
            t = t * r / k
            if k > 5 and abs(t) < Decimal(10) ** -(PREC - 10):
                return +s, +c


def sin(x: Decimal) -> Decimal:
    return sincos(x)[0]


def cos(x: Decimal) -> Decimal:
    return sincos(x)[1]


def exp(x: Decimal) -> Decimal:
    with localcontext() as ctx:
        ctx.prec = PREC
        return x.exp()
