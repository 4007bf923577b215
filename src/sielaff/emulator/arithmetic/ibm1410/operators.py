"""The Python operators of a K-digit 1410 number type, on the kernels of ``kernels.py``.

``install_operators`` puts ``+ - * /``, unary minus, ``abs`` and the comparisons on
the number class.  Each operator takes the fast path for two numbers of its own
type and converts a Python int or float on the other side the way the 1410 FORTRAN
converted a constant (K digits, truncated); the tests restate the 1410 rules and
require the same digits.
"""

from __future__ import annotations

from types import SimpleNamespace

from sielaff.emulator.arithmetic.base import ArithmeticError1410
from sielaff.emulator.arithmetic.ibm1410.kernels import EMAX, EMIN


def install_operators(cls: type, k: SimpleNamespace, conv, cache: dict, zero) -> None:
    """Put the operators on ``cls`` (see the module doc)."""
    add, div, cmp, overflow = k.add, k.div, k.cmp, k.overflow
    LO, HI, PROD_HI = k.LO, k.HI, k.PROD_HI
    new = object.__new__
    ZERO = zero

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
    cls.__hash__ = cls.__bases__[0].__hash__  # D1410's: defining __eq__ cleared it
