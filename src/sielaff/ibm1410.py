"""IBM 1410 FORTRAN floating point: K-digit truncating decimal arithmetic.

``IBM1410(digits=8, on_error=..., variant=...)`` is an *arithmetic* in the sense
of :mod:`sielaff.arithmetic`: the line-by-line port runs on it unchanged.

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
  zero: :class:`~sielaff.arithmetic.ArithmeticError1410` naming the operation.
* conversion (constants, card values, ``num``): the first K significant digits
  of the exact decimal value, the rest dropped.  Floats are converted from their
  shortest round-trip text ``repr(x)`` (what a card holds), strings exactly.
* comparisons are exact comparisons of the two K-digit values; a Python float
  or int on the other side is first converted like a FORTRAN constant (K digits,
  truncated), so ``X .LE. 0.7`` compares with the 8-digit constant ``0.7``.

Library (SIN, COS, ATAN, SQRT, ABS)
-----------------------------------
The 1410 library routines (item 1410-FO-138) are lost.  The ones here do every
operation in the K-digit model arithmetic (so they truncate like the machine);
their constants (pi, pi/2, pi/4, pi/6, sqrt 3, ...) are the exact values
truncated to K digits, as a library would store them.  The algorithm is chosen by
``variant``: a preset name, optionally followed by ``,part=choice`` overrides,
e.g. ``"taylor"``, ``"hastings"``, ``"taylor,sqrt=fixed"``.

Presets (``VARIANTS``):

============  ===============  ============  ==========
preset        trig             atan          sqrt
============  ===============  ============  ==========
``taylor``    ``octant``       ``pi6``       ``exp``
``quadrant``  ``quadrant``     ``pi4``       ``one``
``hastings``  ``hastings``     ``hastings``  ``fixed``
============  ===============  ============  ==========

The default is ``taylor`` (series to convergence; my best guess for a library
written for a decimal machine of variable precision).

trig (SIN, COS):
  all choices reduce ``|x|`` by ``q = INT(|x| / (pi/2))``, ``r = |x| - q*(pi/2)``
  (model operations, K-digit pi/2), use the quadrant ``q mod 4`` and the parity of
  SIN/COS for the sign, then

  * ``octant``: if ``r > pi/4`` use ``pi/2 - r`` and the co-function, so
    ``0 <= r <= pi/4``; Taylor series accumulated term by term
    (``t = t * r**2 / ((2k)(2k+1))``) until adding the term no longer changes
    the sum (the term has dropped below the sum's last digit).
  * ``quadrant``: the same Taylor series on ``0 <= r < pi/2`` (more terms).
  * ``hastings``: the fixed polynomials of Hastings / Abramowitz & Stegun 4.3.97
    (``sin x / x``, degree 10 in x) and 4.3.99 (``cos x``, degree 10) on
    ``[0, pi/2]``, Horner form; coefficients are 10-digit constants (truncated to
    K), so the accuracy stays near 2e-9 whatever K is.

  ``|x| >= 10000`` radians (C28-0328-3 p. 23 limit): ``on_error`` is called and
  the result is 0.

atan (ATAN):
  ``x < 0`` by symmetry; ``x > 1``: ``pi/2 - atan(1/x)``; then

  * ``pi6``: if ``x > tan(pi/12)``: ``pi/6 + atan((x*sqrt3 - 1) / (x + sqrt3))``,
    so the series argument is at most ``tan 15 deg = 0.268``; Taylor series
    ``x - x**3/3 + ...`` until the sum stops changing.
  * ``pi4``: if ``x > tan(pi/8)``: ``pi/4 + atan((x - 1) / (x + 1))`` (argument
    at most 0.414); Taylor series until the sum stops changing.
  * ``hastings``: Hastings / A&S 4.4.49 polynomial (``atan x / x``, degree 16 in
    x, ``|error| <= 2e-8`` on ``[0, 1]``), Horner form.

sqrt (SQRT): ``x < 0``: ``on_error`` is called and SQRT(ABS(X)) is returned
(C28-0328-3 p. 23); ``SQRT(0) = 0``.  Newton's iteration
``y = (y + x/y) * 0.5`` in model arithmetic, from

  * ``exp``: a guess from the exponent: ``x = g * 10**(2n)`` with
    ``0.1 <= g < 10``, ``y0 = ((g + 1) * 0.5) * 10**n``.  After the first step
    the iterates fall; stop as soon as an iterate does not fall, return the
    smallest.
  * ``one``: ``y0 = 1.0``; the same stopping rule (many steps for large or small
    x).
  * ``fixed``: the ``exp`` guess and a fixed number of steps (5 for K <= 8, 6 for
    K <= 17, 7 above), which is enough from that guess; no test.

Every loop has an iteration bound and raises ``ArithmeticError1410`` instead of
running away.
"""

from __future__ import annotations

import decimal
from collections.abc import Callable
from fractions import Fraction

from sielaff.arithmetic import ArithmeticError1410

__all__ = ["D1410", "IBM1410", "VARIANTS", "number_class"]

EMAX = 99
EMIN = -99

# Exact constants (more digits than any K we allow), truncated to K when used.
_PI = "3.14159265358979323846264338327950288419716939937510"
_SQRT3 = "1.73205080756887729352744634150587236694280525381038"

MIN_DIGITS = 3
MAX_DIGITS = 40

_CACHE_LIMIT = 4096

VARIANTS: dict[str, dict[str, str]] = {
    "taylor": {"trig": "octant", "atan": "pi6", "sqrt": "exp"},
    "quadrant": {"trig": "quadrant", "atan": "pi4", "sqrt": "one"},
    "hastings": {"trig": "hastings", "atan": "hastings", "sqrt": "fixed"},
}
_CHOICES = {
    "trig": ("octant", "quadrant", "hastings"),
    "atan": ("pi6", "pi4", "hastings"),
    "sqrt": ("exp", "one", "fixed"),
}
DEFAULT_VARIANT = "taylor"

# Hastings (1955) / Abramowitz & Stegun 4.3.97, 4.3.99, 4.4.49 coefficients,
# lowest order first, as polynomials in x**2.
_HASTINGS_SIN = ("1", "-.1666666664", ".0083333315", "-.0001984090", ".0000027526",
                 "-.0000000239")
_HASTINGS_COS = ("1", "-.4999999963", ".0416666418", "-.0013888397", ".0000247609",
                 "-.0000002605")
_HASTINGS_ATAN = ("1", "-.3333314528", ".1999355085", "-.1420889944", ".1065626393",
                  "-.0752896400", ".0429096138", "-.0161657367", ".0028662257")

_MAX_SERIES_TERMS = 200
_MAX_NEWTON_STEPS = 500


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
        # Python's numeric hash of the exact value (equal to hash(int), hash(float),
        # hash(Decimal) of the same exact value).
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
    LO = 10 ** (K - 1)  # smallest normalised mantissa
    HI = 10**K  # one past the largest
    PROD_HI = 10 ** (2 * K - 1)  # a 2K-digit product has no leading zero
    P = [10**i for i in range(K + 1)]  # shifts for alignment (d <= K)
    PW = [10**i for i in range(EMAX - EMIN + K + 2)]  # exact comparison scaling
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

    def overflow(op: str, e: int) -> ArithmeticError1410:
        return ArithmeticError1410(
            f"IBM 1410 floating-point overflow in {op}: exponent {e} > {EMAX} "
            f"(magnitude >= 1E{EMAX})")

    # ----- conversion -------------------------------------------------------
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
            text = value.strip().replace(" ", "")
            try:
                d = decimal.Decimal(text)
            except decimal.InvalidOperation:
                raise ValueError(f"not a number: {value!r}") from None
            x = from_decimal(d, value)
            if len(scache) < _CACHE_LIMIT:
                scache[value] = x
            return x
        try:
            return cache[value]
        except KeyError:
            pass
        except TypeError:
            raise TypeError(f"cannot convert {t.__name__} to an IBM 1410 number") from None
        if isinstance(value, bool):
            x = from_decimal(decimal.Decimal(int(value)), value)
        elif isinstance(value, int):
            x = from_decimal(decimal.Decimal(value), value)
        elif isinstance(value, float):
            x = from_decimal(decimal.Decimal(repr(float(value))), value)
        elif isinstance(value, decimal.Decimal | Fraction):
            if isinstance(value, Fraction):
                # long division to K+30 digits, ROUND_DOWN: truncating that to K is exact
                with decimal.localcontext() as ctx:
                    ctx.prec = K + 30
                    ctx.rounding = decimal.ROUND_DOWN
                    value = decimal.Decimal(value.numerator) / decimal.Decimal(value.denominator)
            return from_decimal(value, value)
        else:
            try:
                f = float(value)  # numpy scalars and the like
            except (TypeError, ValueError):
                raise TypeError(f"cannot convert {t.__name__} to an IBM 1410 number") from None
            x = from_decimal(decimal.Decimal(repr(f)), value)
        if len(cache) < _CACHE_LIMIT:
            cache[value] = x
        return x

    def conv(other):
        """The other operand of a mixed operation, or NotImplemented."""
        t = type(other)
        if t is float or t is int:
            try:
                return cache[other]
            except KeyError:
                return num(other)
        if isinstance(other, int | float) and not isinstance(other, D1410):
            return num(other)
        return NotImplemented

    # ----- the four operations ----------------------------------------------
    def add(ma: int, ea: int, mb: int, eb: int, op: str) -> D1410:
        if ea < eb:
            ma, ea, mb, eb = mb, eb, ma, ea
        d = ea - eb
        if d:
            if d >= K:
                mb = 0
            elif mb >= 0:
                mb //= P[d]
            else:
                mb = -(-mb // P[d])
        r = ma + mb
        if r >= HI:
            r //= 10
            ea += 1
            if ea > EMAX:
                raise overflow(op, ea)
        elif r <= -HI:
            r = -(-r // 10)
            ea += 1
            if ea > EMAX:
                raise overflow(op, ea)
        elif -LO < r < LO:
            if r == 0:
                return ZERO
            while -LO < r < LO:
                r *= 10
                ea -= 1
            if ea < EMIN:
                return ZERO
        x = new(cls)
        x.m = r
        x.e = ea
        return x

    def mul(ma: int, ea: int, mb: int, eb: int) -> D1410:
        p = ma * mb
        if p == 0:
            return ZERO
        e = ea + eb
        if p > 0:
            if p >= PROD_HI:
                p //= HI
            else:
                p //= LO
                e -= 1
        else:
            p = -p
            if p >= PROD_HI:
                p = -(p // HI)
            else:
                p = -(p // LO)
                e -= 1
        if e > EMAX:
            raise overflow("multiplication", e)
        if e < EMIN:
            return ZERO
        x = new(cls)
        x.m = p
        x.e = e
        return x

    def div(ma: int, ea: int, mb: int, eb: int) -> D1410:
        if mb == 0:
            raise ArithmeticError1410("IBM 1410 floating-point division by zero")
        if ma == 0:
            return ZERO
        neg = (ma ^ mb) < 0
        if ma < 0:
            ma = -ma
        if mb < 0:
            mb = -mb
        e = ea - eb
        if ma >= mb:
            q = ma * LO // mb
            e += 1
        else:
            q = ma * HI // mb
        if e > EMAX:
            raise overflow("division", e)
        if e < EMIN:
            return ZERO
        x = new(cls)
        x.m = -q if neg else q
        x.e = e
        return x

    def cmp(ma: int, ea: int, mb: int, eb: int) -> int:
        if ea != eb:
            if ea > eb:
                ma *= PW[ea - eb]
            else:
                mb *= PW[eb - ea]
        return (ma > mb) - (ma < mb)

    # ----- operators ----------------------------------------------------------
    def __add__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b]
            except (KeyError, TypeError):
                b = conv(b)
                if b is NotImplemented:
                    return b
        ma, ea, mb, eb = a.m, a.e, b.m, b.e
        if ea < eb:
            ma, ea, mb, eb = mb, eb, ma, ea
        d = ea - eb
        if d:
            if d >= K:
                mb = 0
            elif mb >= 0:
                mb //= P[d]
            else:
                mb = -(-mb // P[d])
        r = ma + mb
        if -LO < r < LO:
            if r == 0:
                return ZERO
            while -LO < r < LO:
                r *= 10
                ea -= 1
            if ea < EMIN:
                return ZERO
        elif r >= HI or r <= -HI:
            r = r // 10 if r > 0 else -(-r // 10)
            ea += 1
            if ea > EMAX:
                raise overflow("addition", ea)
        x = new(cls)
        x.m = r
        x.e = ea
        return x

    def __radd__(a, b):
        try:
            b = cache[b]
        except (KeyError, TypeError):
            b = conv(b)
            if b is NotImplemented:
                return b
        return add(b.m, b.e, a.m, a.e, "addition")

    def __sub__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b]
            except (KeyError, TypeError):
                b = conv(b)
                if b is NotImplemented:
                    return b
        ma, ea, mb, eb = a.m, a.e, -b.m, b.e
        if ea < eb:
            ma, ea, mb, eb = mb, eb, ma, ea
        d = ea - eb
        if d:
            if d >= K:
                mb = 0
            elif mb >= 0:
                mb //= P[d]
            else:
                mb = -(-mb // P[d])
        r = ma + mb
        if -LO < r < LO:
            if r == 0:
                return ZERO
            while -LO < r < LO:
                r *= 10
                ea -= 1
            if ea < EMIN:
                return ZERO
        elif r >= HI or r <= -HI:
            r = r // 10 if r > 0 else -(-r // 10)
            ea += 1
            if ea > EMAX:
                raise overflow("subtraction", ea)
        x = new(cls)
        x.m = r
        x.e = ea
        return x

    def __rsub__(a, b):
        try:
            b = cache[b]
        except (KeyError, TypeError):
            b = conv(b)
            if b is NotImplemented:
                return b
        return add(b.m, b.e, -a.m, a.e, "subtraction")

    def __mul__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b]
            except (KeyError, TypeError):
                b = conv(b)
                if b is NotImplemented:
                    return b
        p = a.m * b.m
        if p == 0:
            return ZERO
        e = a.e + b.e
        if p > 0:
            if p >= PROD_HI:
                p //= HI
            else:
                p //= LO
                e -= 1
        elif p <= -PROD_HI:
            p = -(-p // HI)
        else:
            p = -(-p // LO)
            e -= 1
        if e > EMAX:
            raise overflow("multiplication", e)
        if e < EMIN:
            return ZERO
        x = new(cls)
        x.m = p
        x.e = e
        return x

    def __rmul__(a, b):
        try:
            b = cache[b]
        except (KeyError, TypeError):
            b = conv(b)
            if b is NotImplemented:
                return b
        return mul(b.m, b.e, a.m, a.e)

    def __truediv__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b]
            except (KeyError, TypeError):
                b = conv(b)
                if b is NotImplemented:
                    return b
        return div(a.m, a.e, b.m, b.e)

    def __rtruediv__(a, b):
        try:
            b = cache[b]
        except (KeyError, TypeError):
            b = conv(b)
            if b is NotImplemented:
                return b
        return div(b.m, b.e, a.m, a.e)

    def __neg__(a):
        if not a.m:
            return a
        x = new(cls)
        x.m = -a.m
        x.e = a.e
        return x

    def __pos__(a):
        return a

    def __abs__(a):
        if a.m >= 0:
            return a
        x = new(cls)
        x.m = -a.m
        x.e = a.e
        return x

    def __eq__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b]
            except (KeyError, TypeError):
                b = conv(b)
                if b is NotImplemented:
                    return b
        return a.m == b.m and a.e == b.e

    def __ne__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b]
            except (KeyError, TypeError):
                b = conv(b)
                if b is NotImplemented:
                    return b
        return a.m != b.m or a.e != b.e

    def __lt__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b]
            except (KeyError, TypeError):
                b = conv(b)
                if b is NotImplemented:
                    return b
        if a.e == b.e:
            return a.m < b.m
        return cmp(a.m, a.e, b.m, b.e) < 0

    def __le__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b]
            except (KeyError, TypeError):
                b = conv(b)
                if b is NotImplemented:
                    return b
        if a.e == b.e:
            return a.m <= b.m
        return cmp(a.m, a.e, b.m, b.e) <= 0

    def __gt__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b]
            except (KeyError, TypeError):
                b = conv(b)
                if b is NotImplemented:
                    return b
        if a.e == b.e:
            return a.m > b.m
        return cmp(a.m, a.e, b.m, b.e) > 0

    def __ge__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b]
            except (KeyError, TypeError):
                b = conv(b)
                if b is NotImplemented:
                    return b
        if a.e == b.e:
            return a.m >= b.m
        return cmp(a.m, a.e, b.m, b.e) >= 0

    for f in (__add__, __radd__, __sub__, __rsub__, __mul__, __rmul__, __truediv__,
              __rtruediv__, __neg__, __pos__, __abs__, __eq__, __ne__, __lt__, __le__,
              __gt__, __ge__):
        f.__qualname__ = f"{cls.__name__}.{f.__name__}"
        setattr(cls, f.__name__, f)
    cls.__hash__ = D1410.__hash__  # defining __eq__ would otherwise clear it

    cls._num = staticmethod(num)
    cls._add = staticmethod(add)
    cls._mul = staticmethod(mul)
    cls._div = staticmethod(div)
    cls._make = staticmethod(make)
    cls.ZERO = ZERO
    return cls


def _parse_variant(variant: str) -> dict[str, str]:
    parts = [p.strip() for p in variant.split(",") if p.strip()]
    if not parts:
        raise ValueError("empty ibm1410 variant")
    head = parts[0]
    if "=" in head:
        choice = dict(VARIANTS[DEFAULT_VARIANT])
        rest = parts
    else:
        if head not in VARIANTS:
            raise ValueError(f"unknown ibm1410 variant {head!r} (one of {', '.join(VARIANTS)})")
        choice = dict(VARIANTS[head])
        rest = parts[1:]
    for p in rest:
        key, _, val = p.partition("=")
        key, val = key.strip(), val.strip()
        if key not in _CHOICES or val not in _CHOICES[key]:
            raise ValueError(
                f"bad ibm1410 variant part {p!r}: "
                + "; ".join(f"{k}={'|'.join(v)}" for k, v in _CHOICES.items()))
        choice[key] = val
    return choice


def _ignore(_msg: str) -> None:
    pass


class IBM1410:
    """K-digit truncating decimal floating point, with a K-digit library.

    ``digits`` is K (default 8); ``on_error(msg)`` is called where the 1410 library
    printed an error and went on; ``variant`` picks the library algorithms (see the
    module docstring and ``VARIANTS``).
    """

    def __init__(self, digits: int = 8, on_error: Callable[[str], None] = _ignore,
                 variant: str = DEFAULT_VARIANT) -> None:
        self.digits = K = digits
        self.number = cls = number_class(digits)
        self.on_error = on_error
        self.choice = _parse_variant(variant)
        self.variant = ",".join(f"{k}={v}" for k, v in self.choice.items())
        for preset, ch in VARIANTS.items():
            if ch == self.choice:
                self.variant = preset
        self.name = f"ibm1410:{digits}"
        self.ABS = abs
        num = self.num = cls._num
        self._make = cls._make
        self.ZERO = cls.ZERO
        self.ONE = num(1)
        self.HALF = num("0.5")
        self.TWO = num(2)
        self.PI = num(_PI)
        self.HALFPI = num(str(decimal.Decimal(_PI) / 2))
        self.QUARTERPI = num(str(decimal.Decimal(_PI) / 4))
        self.SIXTHPI = num(str(decimal.Decimal(_PI) / 6))
        self.SQRT3 = num(_SQRT3)
        self.TAN15 = num(str(2 - decimal.Decimal(_SQRT3)))  # tan(pi/12) = 2 - sqrt 3
        # tan(pi/8) = sqrt 2 - 1
        with decimal.localcontext() as ctx:
            ctx.prec = 60
            self.TAN225 = num(str(decimal.Decimal(2).sqrt() - 1))
        self.TRIG_LIMIT = num(10000)
        # Taylor divisors (2k)(2k+1) for sin, (2k-1)(2k) for cos, 2k+1 for atan.
        n = _MAX_SERIES_TERMS + 2
        self._sin_div = [num((2 * k) * (2 * k + 1)) for k in range(1, n)]
        self._cos_div = [num((2 * k - 1) * (2 * k)) for k in range(1, n)]
        self._odd = [num(2 * k + 1) for k in range(1, n)]
        self._h_sin = [num(c) for c in reversed(_HASTINGS_SIN)]
        self._h_cos = [num(c) for c in reversed(_HASTINGS_COS)]
        self._h_atan = [num(c) for c in reversed(_HASTINGS_ATAN)]
        self._newton_fixed = 5 if K <= 8 else 6 if K <= 17 else 7 if K <= 35 else 8

        trig = self.choice["trig"]
        if trig == "octant":
            self._sincos = self._sincos_octant
        elif trig == "quadrant":
            self._sincos = self._sincos_series
        else:
            self._sincos = self._sincos_hastings
        self.ATAN = {"pi6": self._atan_pi6, "pi4": self._atan_pi4,
                     "hastings": self._atan_hastings}[self.choice["atan"]]
        self.SQRT = {"exp": self._sqrt_exp, "one": self._sqrt_one,
                     "fixed": self._sqrt_fixed}[self.choice["sqrt"]]

    def __repr__(self) -> str:
        return f"IBM1410({self.digits}, variant={self.variant!r})"

    # ----- SIN / COS ------------------------------------------------------------
    def _reduce(self, ax):
        """|x| -> (quadrant q mod 4, r) with r = |x| - q*pi/2 in model arithmetic."""
        hp = self.HALFPI
        if ax < hp:
            return 0, ax
        q = int(ax / hp)
        r = ax - self.num(q) * hp
        # truncation can leave r a hair outside [0, pi/2): fold it back
        if r < self.ZERO:
            q -= 1
            r = r + hp
        elif r >= hp:
            q += 1
            r = r - hp
        return q & 3, r

    def _sin_series(self, r):
        s = t = r
        x2 = r * r
        divs = self._sin_div
        for k in range(_MAX_SERIES_TERMS):
            t = t * x2 / divs[k]
            s1 = s + t if k & 1 else s - t
            if s1 == s:
                return s
            s = s1
        raise ArithmeticError1410(f"SIN series did not converge for argument {r}")

    def _cos_series(self, r):
        s = t = self.ONE
        x2 = r * r
        divs = self._cos_div
        for k in range(_MAX_SERIES_TERMS):
            t = t * x2 / divs[k]
            s1 = s + t if k & 1 else s - t
            if s1 == s:
                return s
            s = s1
        raise ArithmeticError1410(f"COS series did not converge for argument {r}")

    def _sincos_series(self, r, want_sin: bool):
        return self._sin_series(r) if want_sin else self._cos_series(r)

    def _sincos_octant(self, r, want_sin: bool):
        if r > self.QUARTERPI:
            r = self.HALFPI - r
            want_sin = not want_sin
        return self._sin_series(r) if want_sin else self._cos_series(r)

    def _sincos_hastings(self, r, want_sin: bool):
        x2 = r * r
        coef = self._h_sin if want_sin else self._h_cos
        p = coef[0]
        for c in coef[1:]:
            p = p * x2 + c
        return p * r if want_sin else p

    def _trig(self, x, want_sin: bool, fname: str):
        if type(x) is not self.number:
            x = self.num(x)
        neg = x.m < 0
        ax = -x if neg else x
        if ax >= self.TRIG_LIMIT:
            self.on_error(f"{fname} argument {x} out of range (|X| must be below 10000 "
                          f"radians): result 0")
            return self.ZERO
        q, r = self._reduce(ax)
        if want_sin:
            # sin(r + q pi/2): q=0 sin r, 1 cos r, 2 -sin r, 3 -cos r; odd function
            v = self._sincos(r, not (q & 1))
            if (q >= 2) != neg:
                v = -v
        else:
            # cos(r + q pi/2): q=0 cos r, 1 -sin r, 2 -cos r, 3 sin r; even function
            v = self._sincos(r, bool(q & 1))
            if q in (1, 2):
                v = -v
        return v

    def SIN(self, x):
        return self._trig(x, True, "SIN")

    def COS(self, x):
        return self._trig(x, False, "COS")

    # ----- ATAN -------------------------------------------------------------------
    def _atan_series(self, a):
        s = p = a
        x2 = a * a
        odd = self._odd
        for k in range(_MAX_SERIES_TERMS):
            p = p * x2
            t = p / odd[k]
            s1 = s + t if k & 1 else s - t
            if s1 == s:
                return s
            s = s1
        raise ArithmeticError1410(f"ATAN series did not converge for argument {a}")

    def _atan_frame(self, x, core):
        if type(x) is not self.number:
            x = self.num(x)
        neg = x.m < 0
        a = -x if neg else x
        inv = a > self.ONE
        if inv:
            a = self.ONE / a
        v = core(a)
        if inv:
            v = self.HALFPI - v
        return -v if neg else v

    def _atan_pi6_core(self, a):
        if a > self.TAN15:
            s3 = self.SQRT3
            return self.SIXTHPI + self._atan_series((a * s3 - self.ONE) / (a + s3))
        return self._atan_series(a)

    def _atan_pi4_core(self, a):
        if a > self.TAN225:
            return self.QUARTERPI + self._atan_series((a - self.ONE) / (a + self.ONE))
        return self._atan_series(a)

    def _atan_hastings_core(self, a):
        x2 = a * a
        coef = self._h_atan
        p = coef[0]
        for c in coef[1:]:
            p = p * x2 + c
        return p * a

    def _atan_pi6(self, x):
        return self._atan_frame(x, self._atan_pi6_core)

    def _atan_pi4(self, x):
        return self._atan_frame(x, self._atan_pi4_core)

    def _atan_hastings(self, x):
        return self._atan_frame(x, self._atan_hastings_core)

    # ----- SQRT ---------------------------------------------------------------------
    def _sqrt_arg(self, x):
        if type(x) is not self.number:
            x = self.num(x)
        if x.m < 0:
            # C28-0328-3 p. 23: error message, then the root of |x|.
            self.on_error(f"SQRT of negative argument {x}: using SQRT(ABS(X))")
            x = -x
        return x

    def _exp_guess(self, x):
        """x = g * 10**(2n), 0.1 <= g < 10; guess ((g + 1) * 0.5) * 10**n."""
        e = x.e
        n = e // 2
        g = self._make(x.m, e - 2 * n)
        y = (g + self.ONE) * self.HALF
        return self._make(y.m, y.e + n)

    def _newton_falling(self, x, y, what: str):
        half = self.HALF
        y = (y + x / y) * half  # from below the first step lands above the root
        for _ in range(_MAX_NEWTON_STEPS):
            y1 = (y + x / y) * half
            if y1 >= y:
                return y
            y = y1
        raise ArithmeticError1410(f"SQRT Newton iteration ({what}) did not settle for {x}")

    def _sqrt_exp(self, x):
        x = self._sqrt_arg(x)
        if not x.m:
            return self.ZERO
        return self._newton_falling(x, self._exp_guess(x), "exponent guess")

    def _sqrt_one(self, x):
        x = self._sqrt_arg(x)
        if not x.m:
            return self.ZERO
        return self._newton_falling(x, self.ONE, "from 1.0")

    def _sqrt_fixed(self, x):
        x = self._sqrt_arg(x)
        if not x.m:
            return self.ZERO
        y = self._exp_guess(x)
        half = self.HALF
        for _ in range(self._newton_fixed):
            y = (y + x / y) * half
        return y
