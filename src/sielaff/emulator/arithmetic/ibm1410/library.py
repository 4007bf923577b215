"""The IBM 1410 library routines (reconstructed): SIN, COS, ATAN, SQRT, ABS.

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

from sielaff.emulator.arithmetic.base import ArithmeticError1410
from sielaff.emulator.arithmetic.ibm1410.number import (
    EMAX,
    EMIN,
    MAX_DIGITS,
    number_class,
)

__all__ = ["DEFAULT_VARIANT", "IBM1410", "VARIANTS"]

# Exact constants (more digits than any K we allow), truncated to K when used.
_PI = "3.14159265358979323846264338327950288419716939937510"
_SQRT3 = "1.73205080756887729352744634150587236694280525381038"

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
