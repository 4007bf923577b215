"""The 1410's four operations and the library's inner loops, on raw integer pairs.

``make_kernels(K)`` returns the operations for K-digit numbers held as a signed
K-digit mantissa and an exponent (value ``m * 10**(e - K)``): ``add``, ``mul``,
``div``, ``cmp``, the series sum and the Newton loop of the library.  They are
closures over K's constants (powers of ten, the normalisation bounds) because the
port calls them millions of times: a closure variable is the fastest name
CPython looks up.  ``number.py`` wraps them in the number type's operators,
``library.py`` calls them directly.  Nothing rounds: see the package doc.
"""

from __future__ import annotations

from types import SimpleNamespace

from sielaff.emulator.arithmetic.base import ArithmeticError1410

EMAX = 99
EMIN = -99


def make_kernels(K: int) -> SimpleNamespace:
    """The K-digit operations (see the module doc) and the constants they use."""
    LO = 10 ** (K - 1)  # smallest normalised mantissa
    HI = 10**K  # one past the largest
    PROD_HI = 10 ** (2 * K - 1)  # a 2K-digit product has no leading zero
    P = [10**i for i in range(K + 1)]  # shifts for alignment (d <= K)
    PW = [10**i for i in range(EMAX - EMIN + K + 2)]  # exact comparison scaling
    HALF_M = 5 * LO  # mantissa of 0.5 (exponent 0)

    def overflow(op: str, e: int) -> ArithmeticError1410:
        return ArithmeticError1410(
            f"IBM 1410 floating-point overflow in {op}: exponent {e} > {EMAX} "
            f"(magnitude >= 1E{EMAX})")

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

    return SimpleNamespace(add=add, mul=mul, div=div, cmp=cmp, series_sum=series_sum,
                           newton=newton, overflow=overflow, LO=LO, HI=HI, PROD_HI=PROD_HI)
