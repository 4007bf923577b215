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

Presets (``VARIANTS``; the part names and choices are explained below):

============  ===========  ========  ========  ======  =====  =======  ========================
preset        trig         reduce    atan      sqrt    cos    final    Figures 10/11 fields
============  ===========  ========  ========  ======  =====  =======  ========================
``sine``      ``sine``     exact     ``pi3``   exp     own    trunc    82 of 82 (the default)
``taylor``    ``octant``   model     ``pi6``   exp     own    trunc    79 of 82
``quadrant``  ``quadrant`` model     ``pi4``   one     own    trunc    78 of 82
``hastings``  ``hastings`` model     hastings  fixed   own    trunc    77 of 82
============  ===========  ========  ========  ======  =====  =======  ========================

The default is ``sine``: the only combination tried that reproduces every printed
field of Figures 10 and 11 (``docs/accuracy.md`` lists every variant tried, with its
count, and why the figures pin these choices down).  ``taylor`` was the first guess.

trig (SIN, COS):
  all choices reduce ``|x|`` by ``q = INT(|x| / (pi/2))``, ``r = |x| - q*(pi/2)``
  (K-digit pi/2), use the quadrant ``q mod 4`` and the parity of SIN/COS for the
  sign, then

  * ``sine``: one core routine, the sine series in Horner form with a fixed number
    of factors N, ``p = 1; p = 1 - (r*r / ((2k)(2k+1))) * p`` for k = N..1, result
    ``r * p``, on ``0 <= r <= pi/2``.  Cosines (COS, and SIN in the odd quadrants)
    are ``sine(pi/2 - r)``.  N is fixed per K so that the first omitted term
    ``(pi/2)**(2N+3)/(2N+3)!`` is below ``10**-(K+1)`` (N = 6 for K = 8, through
    x**13).  Truncation makes the Horner form run a few units high (1 - t with t
    truncated is rounded up): SIN can return .10000001E+01 near pi/2.
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

reduce (the subtractions of the SIN/COS argument reduction, ``|x| - q*(pi/2)``, its
fold-back, and ``pi/2 - r``):

  * ``model``: ordinary K-digit subtractions (the subtrahend's low digits are dropped
    on alignment).
  * ``exact``: the difference is formed exactly and then truncated to K digits, as a
    library routine doing its reduction in a longer fixed-point field would; the
    constant pi/2 is still the K-digit one.  (1.5707963 - .87266463 is .69813167,
    where the model subtraction gives .69813170.)

cos: ``own`` as above; ``shift``: ``COS(X) = SIN(ABS(X) + pi/2)`` (model add), as
  many libraries did.

final: ``trunc``: the routines work in K digits, the result is what they produce;
  ``round2``: the routine is run with K+2 digits (same algorithms) and its result is
  rounded (half up) to K digits, as a library routine with two guard digits would.

atan (ATAN):
  ``x < 0`` by symmetry; ``x > 1``: ``pi/2 - atan(1/x)`` (except ``pi3``); then

  * ``pi6``: if ``x > tan(pi/12)``: ``pi/6 + atan((x*sqrt3 - 1) / (x + sqrt3))``,
    so the series argument is at most ``tan 15 deg = 0.268``; Taylor series
    ``x - x**3/3 + ...`` until the sum stops changing.
  * ``pi4``: if ``x > tan(pi/8)``: ``pi/4 + atan((x - 1) / (x + 1))`` (argument
    at most 0.414); Taylor series until the sum stops changing.
  * ``hastings``: Hastings / A&S 4.4.49 polynomial (``atan x / x``, degree 16 in
    x, ``|error| <= 2e-8`` on ``[0, 1]``), Horner form.
  * ``pi3``: no inversion for ``1 < x <= tan 75 deg``: there
    ``pi/3 + atan((x - sqrt3) / (x*sqrt3 + 1))``; ``tan 15 < x <= 1`` as ``pi6``;
    ``x > tan 75``: ``pi/2 - atan(1/x)``.  Every series argument is at most
    ``tan 15 deg`` and the pi/2 subtraction only happens for large x.

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
    K <= 17, 7 for K <= 35, else 8), which is enough from that guess; no test.

Measured accuracy (``tests/test_ibm1410.py`` asserts bounds a little above these):
SIN/COS within ``0.95 (1 + |x|) 10**(1-K)`` absolute (one unit in the last place
of 1.0, plus the reduction by a K-digit pi/2 growing with |x|); ATAN within
``1.6 * 10**(1-K)``; SQRT within ``10**(1-K)`` relative.  The ``hastings``
polynomials add their own 2.3e-9 (SIN/COS) and 1.4e-8 (ATAN) whatever K is.

Speed: a model operation through the operators costs ~0.3 us (CPython 3.11), ~15x a
float operation; a library call 2-5 us.  The library and its inner loops (series,
Newton) work on raw ``(mantissa, exponent)`` int pairs with the operations written
inline; the tests restate every routine with the operators and require the same
digits.

Every loop has an iteration bound and raises ``ArithmeticError1410`` instead of
running away.
"""

from __future__ import annotations

import decimal
import math
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

_BASE = {"reduce": "model", "cos": "own", "final": "trunc"}
VARIANTS: dict[str, dict[str, str]] = {
    "sine": {"trig": "sine", "atan": "pi3", "sqrt": "exp", "reduce": "exact", "cos": "own",
             "final": "trunc"},
    "taylor": {"trig": "octant", "atan": "pi6", "sqrt": "exp", **_BASE},
    "quadrant": {"trig": "quadrant", "atan": "pi4", "sqrt": "one", **_BASE},
    "hastings": {"trig": "hastings", "atan": "hastings", "sqrt": "fixed", **_BASE},
}
_CHOICES = {
    "trig": ("octant", "quadrant", "hastings", "sine"),
    "atan": ("pi6", "pi4", "hastings", "pi3"),
    "sqrt": ("exp", "one", "fixed"),
    "reduce": ("model", "exact"),
    "cos": ("own", "shift"),
    "final": ("trunc", "round2"),
}
DEFAULT_VARIANT = "sine"

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
    LO = 10 ** (K - 1)  # smallest normalised mantissa
    HI = 10**K  # one past the largest
    PROD_HI = 10 ** (2 * K - 1)  # a 2K-digit product has no leading zero
    P = [10**i for i in range(K + 1)]  # shifts for alignment (d <= K)
    PW = [10**i for i in range(EMAX - EMIN + K + 2)]  # exact comparison scaling
    HALF_M = 5 * LO  # mantissa of 0.5 (exponent 0)
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

    # ----- the four operations on raw (mantissa, exponent) pairs -----------------
    # The operators call these; the library works on the pairs directly.
    def add(ma: int, ea: int, mb: int, eb: int) -> tuple[int, int]:
        if ea < eb:
            ma, ea, mb, eb = mb, eb, ma, ea
        d = ea - eb
        if d:  # align: shift the smaller-exponent operand right, drop the digits
            if d >= K:
                mb = 0
            elif mb >= 0:
                mb //= P[d]
            else:
                mb = -(-mb // P[d])
        r = ma + mb
        if -LO < r < LO:  # cancellation: normalise left, shifting in zeros
            if r == 0:
                return 0, EMIN
            while -LO < r < LO:
                r *= 10
                ea -= 1
            if ea < EMIN:
                return 0, EMIN
        elif r >= HI or r <= -HI:  # carry out: shift right, drop the lowest digit
            r = r // 10 if r > 0 else -(-r // 10)
            ea += 1
            if ea > EMAX:
                raise overflow("addition/subtraction", ea)
        return r, ea

    def mul(ma: int, ea: int, mb: int, eb: int) -> tuple[int, int]:
        p = ma * mb
        if p == 0:
            return 0, EMIN
        e = ea + eb
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
            return 0, EMIN
        return p, e

    def div(ma: int, ea: int, mb: int, eb: int) -> tuple[int, int]:
        if mb == 0:
            raise ArithmeticError1410("IBM 1410 floating-point division by zero")
        if ma == 0:
            return 0, EMIN
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
            return 0, EMIN
        return (-q if neg else q), e

    def cmp(ma: int, ea: int, mb: int, eb: int) -> int:
        """Exact comparison of two values: -1, 0 or 1."""
        if ea != eb:
            if ea > eb:
                ma *= PW[ea - eb]
            else:
                mb *= PW[eb - ea]
        return (ma > mb) - (ma < mb)

    # ----- library inner loops, on raw pairs ---------------------------------------------
    # For a positive term t, x2 and divisors d (callers pass |argument|; the
    # sign-magnitude arithmetic is exactly odd-symmetric).  The arguments are
    # reduced (|r| < 2), so nothing can overflow.  Each returns the sum once adding
    # the next term leaves it unchanged, or None when the divisor table ran out.
    def series_sum(sm: int, se: int, pm: int, pe: int, rm: int, re: int, divs,
                   recursive: bool):
        """x2 = r * r, then s -/+ t -/+ ... alternating from minus, where

        recursive:   t = t * x2 / d         (SIN, COS: d = (2k)(2k+1) or (2k-1)(2k))
        otherwise:   p = p * x2, t = p / d  (ATAN: d = 2k+1)
        """
        x2m, x2e = mul(rm, re, rm, re)  # x2 = r * r
        if x2m == 0:
            return sm, se
        minus = True
        for dm, de in divs:
            pm, pe = mul(pm, pe, x2m, x2e)  # p = p * x2
            if pm == 0:
                return sm, se
            tm, te = div(pm, pe, dm, de)  # t = p / d
            if tm == 0:
                return sm, se
            if recursive:
                pm, pe = tm, te
            r, ea = add(sm, se, -tm if minus else tm, te)  # s = s -/+ t
            if r == sm and ea == se:
                return sm, se
            sm, se = r, ea
            minus = not minus
        return None

    def newton(xm: int, xe: int, ym: int, ye: int, steps: int, falling: bool):
        """Newton steps y = (y + x/y) * 0.5 for x, y > 0, truncating at each operation.

        falling=False: exactly ``steps`` steps.  falling=True: after the first step
        (which lands above the root), stop as soon as a step does not decrease y and
        return the smallest y; None if that did not happen within ``steps`` steps.
        """
        for i in range(steps):
            qm, qe = div(xm, xe, ym, ye)  # q = x / y
            sm, se = add(ym, ye, qm, qe)  # s = y + q
            r, se = mul(sm, se, HALF_M, 0)  # y1 = s * 0.5
            if falling and i and (se > ye or (se == ye and r >= ym)):
                return ym, ye
            ym, ye = r, se
        return None if falling else (ym, ye)

    # ----- operators ----------------------------------------------------------------
    def __add__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b] if type(b) is float else conv(b)
            except KeyError:
                b = conv(b)
            if b is NotImplemented:
                return b
        r, e = add(a.m, a.e, b.m, b.e)
        x = new(cls)
        x.m = r
        x.e = e
        return x

    def __sub__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b] if type(b) is float else conv(b)
            except KeyError:
                b = conv(b)
            if b is NotImplemented:
                return b
        r, e = add(a.m, a.e, -b.m, b.e)
        x = new(cls)
        x.m = r
        x.e = e
        return x

    def __rsub__(a, b):
        try:
            b = cache[b] if type(b) is float else conv(b)
        except KeyError:
            b = conv(b)
        if b is NotImplemented:
            return b
        try:
            m, e = add(b.m, b.e, -a.m, a.e)
        except ArithmeticError1410:
            raise overflow("subtraction", b.e + 1) from None
        x = new(cls)
        x.m = m
        x.e = e
        return x

    def __mul__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b] if type(b) is float else conv(b)
            except KeyError:
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

    def __truediv__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b] if type(b) is float else conv(b)
            except KeyError:
                b = conv(b)
            if b is NotImplemented:
                return b
        m, e = div(a.m, a.e, b.m, b.e)
        x = new(cls)
        x.m = m
        x.e = e
        return x

    def __rtruediv__(a, b):
        try:
            b = cache[b] if type(b) is float else conv(b)
        except KeyError:
            b = conv(b)
        if b is NotImplemented:
            return b
        m, e = div(b.m, b.e, a.m, a.e)
        x = new(cls)
        x.m = m
        x.e = e
        return x

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
                b = cache[b] if type(b) is float else conv(b)
            except KeyError:
                b = conv(b)
            if b is NotImplemented:
                return b
        return a.m == b.m and a.e == b.e

    def __ne__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b] if type(b) is float else conv(b)
            except KeyError:
                b = conv(b)
            if b is NotImplemented:
                return b
        return a.m != b.m or a.e != b.e

    def __lt__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b] if type(b) is float else conv(b)
            except KeyError:
                b = conv(b)
            if b is NotImplemented:
                return b
        if a.e == b.e:
            return a.m < b.m
        return cmp(a.m, a.e, b.m, b.e) < 0

    def __le__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b] if type(b) is float else conv(b)
            except KeyError:
                b = conv(b)
            if b is NotImplemented:
                return b
        if a.e == b.e:
            return a.m <= b.m
        return cmp(a.m, a.e, b.m, b.e) <= 0

    def __gt__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b] if type(b) is float else conv(b)
            except KeyError:
                b = conv(b)
            if b is NotImplemented:
                return b
        if a.e == b.e:
            return a.m > b.m
        return cmp(a.m, a.e, b.m, b.e) > 0

    def __ge__(a, b):
        if type(b) is not cls:
            try:
                b = cache[b] if type(b) is float else conv(b)
            except KeyError:
                b = conv(b)
            if b is NotImplemented:
                return b
        if a.e == b.e:
            return a.m >= b.m
        return cmp(a.m, a.e, b.m, b.e) >= 0

    for f in (__add__, __sub__, __rsub__, __mul__, __truediv__, __rtruediv__, __neg__,
              __pos__, __abs__, __eq__, __ne__, __lt__, __le__, __gt__, __ge__):
        f.__qualname__ = f"{cls.__name__}.{f.__name__}"
        setattr(cls, f.__name__, f)
    # The 1410 add and multiply are commutative (the alignment does not depend on
    # the operand order), so the reflected forms are the same functions.
    cls.__radd__ = __add__
    cls.__rmul__ = __mul__
    cls.__hash__ = D1410.__hash__

    cls._num = staticmethod(num)
    cls._make = staticmethod(make)
    cls._add = staticmethod(add)
    cls._mul = staticmethod(mul)
    cls._div = staticmethod(div)
    cls._cmp = staticmethod(cmp)
    cls._series_sum = staticmethod(series_sum)
    cls._newton = staticmethod(newton)
    cls.ZERO = ZERO
    return cls


def _parse_variant(variant: str) -> dict[str, str]:
    parts = [p.strip() for p in variant.split(",") if p.strip()]
    if not parts:
        raise ValueError("empty ibm1410 variant")
    if "=" in parts[0]:
        choice = dict(VARIANTS[DEFAULT_VARIANT])
    else:
        head = parts.pop(0)
        if head not in VARIANTS:
            raise ValueError(f"unknown ibm1410 variant {head!r} (one of {', '.join(VARIANTS)})")
        choice = dict(VARIANTS[head])
    for p in parts:
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


Pair = tuple[int, int]


class IBM1410:
    """K-digit truncating decimal floating point, with a K-digit library.

    ``digits`` is K (default 8); ``on_error(msg)`` is called where the 1410 library
    printed an error and went on; ``variant`` picks the library algorithms (see the
    module docstring and ``VARIANTS``).

    The library routines work on raw ``(mantissa, exponent)`` pairs with the same
    K-digit add/multiply/divide as the operators (inlined in the inner loops, for
    speed); each step is one model operation, in the order given in the comments.
    ``tests/test_ibm1410.py`` restates them with the number operators and checks
    that both agree digit for digit.
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
        self.num = num = cls._num
        self.ZERO = cls.ZERO
        self._make = cls._make
        self._add = cls._add
        self._mul = cls._mul
        self._div = cls._div
        self._cmp = cls._cmp
        self._series = cls._series_sum
        self._newton = cls._newton

        def pair(v) -> Pair:
            x = num(v)
            return x.m, x.e

        with decimal.localcontext() as ctx:
            ctx.prec = 60
            pi = decimal.Decimal(_PI)
            sqrt3 = decimal.Decimal(_SQRT3)
            self._ONE = pair(1)
            self._HALF = pair("0.5")
            self._HALFPI = pair(str(pi / 2))
            self._QUARTERPI = pair(str(pi / 4))
            self._SIXTHPI = pair(str(pi / 6))
            self._THIRDPI = pair(str(pi / 3))
            self._TAN75 = pair(str(2 + sqrt3))  # tan(5 pi/12) = 2 + sqrt 3
            self._SQRT3 = pair(_SQRT3)
            self._TAN15 = pair(str(2 - sqrt3))  # tan(pi/12) = 2 - sqrt 3
            self._TAN225 = pair(str(decimal.Decimal(2).sqrt() - 1))  # tan(pi/8)
        # Taylor divisors (2k)(2k+1) for sin, (2k-1)(2k) for cos, 2k+1 for atan.
        n = _MAX_SERIES_TERMS + 1
        self._sin_div = [pair((2 * k) * (2 * k + 1)) for k in range(1, n)]
        self._cos_div = [pair((2 * k - 1) * (2 * k)) for k in range(1, n)]
        self._odd = [pair(2 * k + 1) for k in range(1, n)]
        # Horner order: highest coefficient first
        self._h_sin = [pair(c) for c in reversed(_HASTINGS_SIN)]
        self._h_cos = [pair(c) for c in reversed(_HASTINGS_COS)]
        self._h_atan = [pair(c) for c in reversed(_HASTINGS_ATAN)]
        self._newton_fixed = 5 if K <= 8 else 6 if K <= 17 else 7 if K <= 35 else 8

        # "sine": Horner form of the Taylor series of sin with N factors, N fixed per K so
        # that the first omitted term, (pi/2)**(2N+3)/(2N+3)!, is below 10**-(K+1).
        N = 1
        while (math.pi / 2) ** (2 * N + 3) / math.factorial(2 * N + 3) >= 10.0 ** -(K + 1):
            N += 1
        self._sine_terms = N
        self._sine_div = self._sin_div[N - 1::-1]  # (2N)(2N+1), ..., 20, 6

        self._trig_kind = self.choice["trig"]
        self._atan_core = {"pi6": self._atan_pi6, "pi4": self._atan_pi4,
                           "hastings": self._atan_hastings,
                           "pi3": self._atan_pi3}[self.choice["atan"]]
        self._sqrt_kind = self.choice["sqrt"]
        # the library's reduction subtractions: model arithmetic, or exact then truncated
        self._rsub = self._add if self.choice["reduce"] == "model" else self._add_exact
        self._cos_shift = self.choice["cos"] == "shift"
        if self.choice["final"] == "round2":
            if K + 2 > MAX_DIGITS:
                raise ValueError(f"final=round2 needs K + 2 <= {MAX_DIGITS} digits")
            inner_choice = dict(self.choice, final="trunc")
            inner = IBM1410(K + 2, on_error, ",".join(f"{k}={v}" for k, v in inner_choice.items()))
            self._inner = inner
            for fname in ("SIN", "COS", "ATAN", "SQRT"):
                setattr(self, fname, self._rounded(getattr(inner, fname)))

    def _rounded(self, f: Callable):
        """f computed with K+2 digits (the argument converts exactly), then rounded to K."""
        K, inner, num = self.digits, self._inner, self.num

        def g(x):
            if type(x) is not self.number:
                x = num(x)
            y = f(inner.num(x.to_decimal())).to_decimal()
            with decimal.localcontext() as ctx:
                ctx.prec = K
                ctx.rounding = decimal.ROUND_HALF_UP
                y = +y
            return num(y)

        g.__name__ = f.__name__
        return g

    def _add_exact(self, am: int, ae: int, bm: int, be: int) -> Pair:
        """a + b computed exactly, then truncated to K digits (a guard-digit subtraction)."""
        if not am:
            return bm, be
        if not bm:
            return am, ae
        e = min(ae, be)
        r = am * 10 ** (ae - e) + bm * 10 ** (be - e)
        if not r:
            return 0, EMIN
        n = len(str(abs(r)))
        K = self.digits
        if n > K:
            r = r // 10 ** (n - K) if r > 0 else -(-r // 10 ** (n - K))
        else:
            r *= 10 ** (K - n)
        e += n - K
        if e > EMAX:
            raise ArithmeticError1410(f"IBM 1410 floating-point overflow in library reduction: "
                                      f"exponent {e} > {EMAX}")
        if e < EMIN:
            return 0, EMIN
        return r, e

    def __repr__(self) -> str:
        return f"IBM1410({self.digits}, variant={self.variant!r})"

    # ----- SIN / COS ------------------------------------------------------------------
    def SIN(self, x):
        """SIN(X) in K-digit arithmetic (``variant`` trig choice)."""
        return self._trig(x, True)

    def COS(self, x):
        """COS(X) in K-digit arithmetic (``variant`` trig choice).

        ``cos=shift``: COS(X) = SIN(ABS(X) + pi/2), the sum in model arithmetic."""
        if self._cos_shift:
            if type(x) is not self.number:
                x = self.num(x)
            m, e = self._add(abs(x.m), x.e, *self._HALFPI)
            return self._trig(self._make(m, e), True)
        return self._trig(x, False)

    def _trig(self, x, want_sin: bool):
        if type(x) is not self.number:
            x = self.num(x)
        m, e = x.m, x.e
        neg = m < 0
        if neg:
            m = -m
        if e >= 5 and m:  # |x| >= .1E+05
            fname = "SIN" if want_sin else "COS"
            self.on_error(f"{fname} argument {x} out of range (|X| must be below 10000 "
                          f"radians): result 0")
            return self.ZERO
        hm, he = self._HALFPI
        if e < he or (e == he and m < hm):
            q = 0
        else:
            q, m, e = self._reduce(m, e)
        # sin(r + q pi/2) = sin r, cos r, -sin r, -cos r for q = 0..3 (odd in x);
        # cos(r + q pi/2) = cos r, -sin r, -cos r, sin r (even in x).
        if want_sin:
            use_sin = not (q & 1)
            flip = (q >= 2) != neg
        else:
            use_sin = bool(q & 1)
            flip = q == 1 or q == 2
        kind = self._trig_kind
        if kind == "hastings":
            vm, ve = self._trig_hastings(m, e, use_sin)
        elif kind == "sine":
            if not use_sin:  # cos r = sin(pi/2 - r)
                m, e = self._rsub(hm, he, -m, e)
            vm, ve = self._sine(m, e)
        else:
            if kind == "octant":
                qm, qe = self._QUARTERPI
                if e > qe or (e == qe and m > qm):  # r > pi/4: pi/2 - r, co-function
                    m, e = self._rsub(hm, he, -m, e)
                    use_sin = not use_sin
            if use_sin:  # s = t = r; t = t * r*r / ((2k)(2k+1)); s = s -/+ t
                v = self._series(m, e, m, e, m, e, self._sin_div, True)
            else:  # s = t = 1; t = t * r*r / ((2k-1)(2k)); s = s -/+ t
                om, oe = self._ONE
                v = self._series(om, oe, om, oe, m, e, self._cos_div, True)
            if v is None:
                raise ArithmeticError1410(
                    f"{'SIN' if use_sin else 'COS'} series did not converge for {x}")
            vm, ve = v
        return self._make(-vm if flip else vm, ve)

    def _reduce(self, am: int, ae: int) -> tuple[int, int, int]:
        """|x| -> (q mod 4, r) with q = INT(|x| / (pi/2)), r = |x| - q*(pi/2)."""
        K = self.digits
        add = self._rsub
        hm, he = self._HALFPI
        qm, qe = self._div(am, ae, hm, he)  # |x| / (pi/2)
        s = qe - K  # INT(): drop the fraction digits of the quotient
        q = qm * 10**s if s >= 0 else qm // 10**-s
        n = len(str(q))  # FLOAT(q), exact: q < 10**K
        pm, pe = self._mul(q * 10 ** (K - n), n, hm, he)  # q * (pi/2)
        rm, re = add(am, ae, -pm, pe)  # |x| - q*(pi/2)
        # truncation can leave r a hair outside [0, pi/2): fold it back
        if rm < 0:
            q -= 1
            rm, re = add(rm, re, hm, he)
        elif self._cmp(rm, re, hm, he) >= 0:
            q += 1
            rm, re = add(rm, re, -hm, he)
        return q & 3, rm, re

    def _sine(self, rm: int, re: int) -> Pair:
        """Horner form of the sine series, N factors (``_sine_terms``), 0 <= r <= pi/2:

        x2 = r*r; p = 1; p = 1 - (x2 / ((2k)(2k+1))) * p for k = N..1; result r * p."""
        mul, div, add = self._mul, self._div, self._add
        om, oe = self._ONE
        x2m, x2e = mul(rm, re, rm, re)
        pm, pe = om, oe
        for dm, de in self._sine_div:
            tm, te = mul(*div(x2m, x2e, dm, de), pm, pe)
            pm, pe = add(om, oe, -tm, te)
        return mul(rm, re, pm, pe)

    def _trig_hastings(self, rm: int, re: int, use_sin: bool) -> Pair:
        """Horner: p = c_n; p = p * r*r + c_k ...; sin: p * r, cos: p."""
        mul, add = self._mul, self._add
        x2m, x2e = mul(rm, re, rm, re)
        coef = self._h_sin if use_sin else self._h_cos
        pm, pe = coef[0]
        for cm, ce in coef[1:]:
            pm, pe = add(*mul(pm, pe, x2m, x2e), cm, ce)  # p * r**2 + c
        return mul(pm, pe, rm, re) if use_sin else (pm, pe)

    # ----- ATAN ------------------------------------------------------------------------
    def ATAN(self, x):
        """ATAN(X) in K-digit arithmetic (``variant`` atan choice)."""
        if type(x) is not self.number:
            x = self.num(x)
        m, e = x.m, x.e
        neg = m < 0
        if neg:
            m = -m
        om, oe = self._ONE
        inv = e > oe or (e == oe and m > om)  # |x| > 1
        if inv and self._atan_core == self._atan_pi3 and self._cmp(m, e, *self._TAN75) <= 0:
            inv = False  # pi3: 1 < |x| <= tan 75 deg is reduced by pi/3, not inverted
        if inv:
            m, e = self._div(om, oe, m, e)  # 1/x
        vm, ve = self._atan_core(m, e)
        if inv:
            hm, he = self._HALFPI
            vm, ve = self._add(hm, he, -vm, ve)  # pi/2 - atan(1/x)
        return self._make(-vm if neg else vm, ve)

    def _atan_series(self, am: int, ae: int) -> Pair:
        """s = p = a; p = p * a*a, t = p / (2k+1), s = s -/+ t, until s stops changing.

        Odd: computed for |a|, sign restored (exact in sign-magnitude arithmetic)."""
        neg = am < 0
        if neg:
            am = -am
        s = self._series(am, ae, am, ae, am, ae, self._odd, False)
        if s is None:
            raise ArithmeticError1410(f"ATAN series did not converge for argument {am}E{ae}")
        return (-s[0], s[1]) if neg else s

    def _atan_pi6(self, am: int, ae: int) -> Pair:
        if self._cmp(am, ae, *self._TAN15) > 0:
            mul, add = self._mul, self._add
            s3m, s3e = self._SQRT3
            om, oe = self._ONE
            nm, ne = add(*mul(am, ae, s3m, s3e), -om, oe)  # a*sqrt3 - 1
            dm, de = add(am, ae, s3m, s3e)  # a + sqrt3
            tm, te = self._div(nm, ne, dm, de)
            return add(*self._SIXTHPI, *self._atan_series(tm, te))  # pi/6 + atan(t)
        return self._atan_series(am, ae)

    def _atan_pi4(self, am: int, ae: int) -> Pair:
        if self._cmp(am, ae, *self._TAN225) > 0:
            add = self._add
            om, oe = self._ONE
            nm, ne = add(am, ae, -om, oe)  # a - 1
            dm, de = add(am, ae, om, oe)  # a + 1
            tm, te = self._div(nm, ne, dm, de)
            return add(*self._QUARTERPI, *self._atan_series(tm, te))  # pi/4 + atan(t)
        return self._atan_series(am, ae)

    def _atan_pi3(self, am: int, ae: int) -> Pair:
        """Offsets pi/6 on (tan 15, 1] and pi/3 on (1, tan 75]; series below tan 15."""
        mul, add, div = self._mul, self._add, self._div
        om, oe = self._ONE
        s3m, s3e = self._SQRT3
        if self._cmp(am, ae, om, oe) <= 0:
            return self._atan_pi6(am, ae)
        # 1 < a <= tan 75 deg (ATAN inverts larger arguments)
        nm, ne = add(am, ae, -s3m, s3e)  # a - sqrt3
        dm, de = add(*mul(am, ae, s3m, s3e), om, oe)  # a*sqrt3 + 1
        return add(*self._THIRDPI, *self._atan_series(*div(nm, ne, dm, de)))  # pi/3 + atan(t)

    def _atan_hastings(self, am: int, ae: int) -> Pair:
        mul, add = self._mul, self._add
        x2m, x2e = mul(am, ae, am, ae)
        coef = self._h_atan
        pm, pe = coef[0]
        for cm, ce in coef[1:]:
            pm, pe = add(*mul(pm, pe, x2m, x2e), cm, ce)  # p * a**2 + c
        return mul(pm, pe, am, ae)

    # ----- SQRT --------------------------------------------------------------------------
    def SQRT(self, x):
        """SQRT(X) in K-digit arithmetic (``variant`` sqrt choice).

        X < 0: ``on_error`` is called and SQRT(ABS(X)) is returned (C28-0328-3 p. 23).
        """
        if type(x) is not self.number:
            x = self.num(x)
        m, e = x.m, x.e
        if m < 0:
            self.on_error(f"SQRT of negative argument {x}: using SQRT(ABS(X))")
            m = -m
        if m == 0:
            return self.ZERO
        kind = self._sqrt_kind
        if kind == "one":
            y = self._newton(m, e, *self._ONE, _MAX_NEWTON_STEPS, True)
        else:
            # exponent guess: x = g * 10**(2n), 0.1 <= g < 10; y0 = ((g + 1) * 0.5) * 10**n
            n = e // 2
            ym, ye = self._mul(*self._add(m, e - 2 * n, *self._ONE), *self._HALF)
            if kind == "fixed":
                y = self._newton(m, e, ym, ye + n, self._newton_fixed, False)
            else:
                y = self._newton(m, e, ym, ye + n, _MAX_NEWTON_STEPS, True)
        if y is None:
            raise ArithmeticError1410(f"SQRT Newton iteration ({kind}) did not settle for {x}")
        return self._make(*y)
