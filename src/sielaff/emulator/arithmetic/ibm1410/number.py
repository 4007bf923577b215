"""IBM 1410 FORTRAN floating point: K-digit truncating decimal arithmetic.

``IBM1410(digits=8, on_error=..., variant=...)`` is an *arithmetic* in the sense
of :mod:`sielaff.emulator.arithmetic`: the line-by-line port runs on it unchanged.

Number representation
---------------------
A real value is ``+-0.d1d2...dK x 10**e`` with ``d1 != 0`` (normalised), a K-digit
decimal fraction (K = ``digits``, default 8, as in the 1410 FORTRAN manuals
C28-0328-3 and J24-1468-1) and an exponent ``-99 <= e <= 99``.  Zero is the
fraction 0 with exponent -99.  A number object (:class:`D1410`) stores two Python
ints: the *signed* K-digit mantissa ``m`` (``10**(K-1) <= |m| < 10**K``, or 0) and
the exponent ``e``; its value is ``m * 10**(e - K)``.  One subclass of
:class:`D1410` is made per K (``D1410_8``, ``D1410_16``...), so that numbers of
different precisions never mix silently.

Arithmetic (see ``shared/notes/ibm1410-fortran.md``; nothing rounds)
-------------------------------------------------------------------
* add/subtract: the operand with the smaller exponent is shifted right and the
  digits shifted out are *dropped* (no guard digit); the aligned K-digit integers
  are added in sign-magnitude; a carry out shifts the sum right and drops its
  lowest digit; cancellation normalises left, shifting in zeros.  For operands of
  the same sign this equals the exactly truncated sum; for operands of opposite
  signs it can differ from it (``1.0 - 0.19E-7`` is ``1.0``; ``1.0 - 0.99999999``
  is ``0.1E-6``).
* multiply keeps the high-order K digits of the exact product; divide truncates
  the quotient to K digits.
* exponent below -99: the result is zero.  Exponent above 99, or division by
  zero: :class:`~sielaff.emulator.arithmetic.ArithmeticError1410` naming the operation.
* conversion (constants, card values, ``num``): the first K significant digits
  of the exact decimal value, the rest dropped.  Floats are converted from their
  shortest round-trip text ``repr(x)`` (what a card holds), strings exactly.
* comparisons are exact comparisons of the two K-digit values; a Python float
  or int on the other side is first converted like a FORTRAN constant (K digits,
  truncated), so ``X .LE. 0.7`` compares with the 8-digit constant ``0.7``.
"""

from __future__ import annotations

import decimal
from fractions import Fraction

from sielaff.emulator.arithmetic.base import ArithmeticError1410
from sielaff.emulator.arithmetic.ibm1410.kernels import EMAX, EMIN, make_kernels
from sielaff.emulator.arithmetic.ibm1410.operators import install_operators

MIN_DIGITS = 3
MAX_DIGITS = 40

_CACHE_LIMIT = 4096


class D1410:
    """A K-digit IBM 1410 floating-point number (abstract base; see :func:`number_class`).

    ``m`` is the signed K-digit mantissa, ``e`` the exponent; value ``m * 10**(e-K)``.
    """

    __slots__ = ("e", "m")
    K = 0  # set by the per-K subclass

    def __str__(self) -> str:
        m = self.m
        sign = "-" if m < 0 else ""
        return f"{sign}0.{abs(m):0{self.K}d}E{self.e:+03d}"

    def __repr__(self) -> str:
        return f"{type(self).__name__}('{self}')"

    def __format__(self, spec: str) -> str:
        if not spec:
            return str(self)
        return format(self.to_decimal(), spec)

    def to_decimal(self) -> decimal.Decimal:
        """The exact value as a :class:`decimal.Decimal`."""
        return decimal.Decimal(self.m).scaleb(self.e - self.K)

    def __float__(self) -> float:
        return float(f"{self.m}e{self.e - self.K}")

    def __int__(self) -> int:
        m, s = self.m, self.e - self.K
        if s >= 0:
            return m * 10**s
        return m // 10**-s if m >= 0 else -(-m // 10**-s)

    __trunc__ = __int__

    def __bool__(self) -> bool:
        return self.m != 0

    def __hash__(self) -> int:
        # Python's numeric hash of the exact value: consistent with == between
        # numbers, and with ints, floats and Decimals of exactly the same value.
        # (``x == 1/3`` converts 1/3 to K digits first, like a FORTRAN constant, so
        # it can be True while the hashes differ.)
        s = self.e - self.K
        if s >= 0:
            return hash(self.m * 10**s)
        return hash(Fraction(self.m, 10**-s))

    def __reduce__(self):
        return (_rebuild, (self.K, self.m, self.e))


def _rebuild(K: int, m: int, e: int) -> D1410:
    cls = number_class(K)
    x = object.__new__(cls)
    x.m = m
    x.e = e
    return x


_CLASSES: dict[int, type] = {}


def number_class(K: int) -> type:
    """The :class:`D1410` subclass for K-digit fractions (made once per K)."""
    try:
        return _CLASSES[K]
    except KeyError:
        pass
    if not (isinstance(K, int) and MIN_DIGITS <= K <= MAX_DIGITS):
        raise ValueError(f"ibm1410 digits must be a whole number {MIN_DIGITS}..{MAX_DIGITS}, "
                         f"not {K!r}")
    cls = _make_class(K)
    _CLASSES[K] = cls
    return cls


def _make_class(K: int) -> type:
    """The K-digit number type: conversion here, the operations from ``kernels`` and
    ``operators``."""
    k = make_kernels(K)
    new = object.__new__
    cache: dict = {}  # float/int -> number (operands mixed with Python numbers)
    scache: dict = {}  # str -> number

    class _D(D1410):
        __slots__ = ()

    _D.K = K
    _D.__name__ = _D.__qualname__ = f"D1410_{K}"
    cls = _D

    def make(m: int, e: int) -> D1410:
        x = new(cls)
        x.m = m
        x.e = e
        return x

    ZERO = make(0, EMIN)

    # ----- conversion (first K significant digits, the rest dropped) -------------
    def from_decimal(d: decimal.Decimal, what) -> D1410:
        if not d.is_finite():
            raise ValueError(f"cannot convert {what!r} to an IBM 1410 number")
        sign, digits, exp = d.as_tuple()
        c = int("".join(map(str, digits))) if digits else 0
        if c == 0:
            return ZERO
        n = len(str(c))
        e = n + exp
        if n > K:
            c //= 10 ** (n - K)
        elif n < K:
            c *= 10 ** (K - n)
        if e > EMAX:
            raise ArithmeticError1410(
                f"IBM 1410 floating-point overflow in conversion of {what!r}: "
                f"exponent {e} > {EMAX}")
        if e < EMIN:
            return ZERO
        return make(-c if sign else c, e)

    def num(value) -> D1410:
        t = type(value)
        if t is cls:
            return value
        if isinstance(value, D1410):  # another precision: truncate its exact value
            return from_decimal(value.to_decimal(), value)
        if isinstance(value, str):
            try:
                return scache[value]
            except KeyError:
                pass
            try:
                d = decimal.Decimal(value.strip().replace(" ", ""))
            except decimal.InvalidOperation:
                raise ValueError(f"not a number: {value!r}") from None
            x = from_decimal(d, value)
            if len(scache) < _CACHE_LIMIT:
                scache[value] = x
            return x
        if isinstance(value, Fraction):
            with decimal.localcontext() as ctx:
                # long division to K+30 digits, ROUND_DOWN: truncating that to K is exact
                ctx.prec = K + 30
                ctx.rounding = decimal.ROUND_DOWN
                d = decimal.Decimal(value.numerator) / decimal.Decimal(value.denominator)
            return from_decimal(d, value)
        if isinstance(value, decimal.Decimal):
            return from_decimal(value, value)
        try:
            return cache[value]
        except KeyError:
            pass
        except TypeError:
            raise TypeError(f"cannot convert {t.__name__} to an IBM 1410 number") from None
        if isinstance(value, int):
            x = from_decimal(decimal.Decimal(int(value)), value)
        else:
            try:
                f = float(value)  # float, numpy scalars and the like
            except (TypeError, ValueError):
                raise TypeError(f"cannot convert {t.__name__} to an IBM 1410 number") from None
            # the shortest text that reads back as the same double, as on a card
            x = from_decimal(decimal.Decimal(repr(f)), value)
        if len(cache) < _CACHE_LIMIT:
            cache[value] = x
        return x

    def conv(other):
        """The other operand of a mixed operation (a Python int/float), or NotImplemented."""
        if isinstance(other, int | float) and not isinstance(other, D1410):
            return num(other)
        return NotImplemented

    install_operators(cls, k, conv, cache, ZERO)
    cls._num = staticmethod(num)
    cls._make = staticmethod(make)
    cls._add = staticmethod(k.add)
    cls._mul = staticmethod(k.mul)
    cls._div = staticmethod(k.div)
    cls._cmp = staticmethod(k.cmp)
    cls._series_sum = staticmethod(k.series_sum)
    cls._newton = staticmethod(k.newton)
    cls.ZERO = ZERO
    return cls
