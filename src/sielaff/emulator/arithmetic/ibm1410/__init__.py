"""IBM 1410 FORTRAN floating point: K-digit truncating decimal arithmetic and its library.

``number`` is the K-digit number (``number_class(K)``, :class:`D1410`), built from
``kernels`` (the four operations on integer pairs) and ``operators``; ``library`` is
the reconstructed SIN, COS, ATAN and SQRT, and :class:`IBM1410`, the arithmetic the
port runs on.  Each module's doc says what it holds; ``number.py``'s says how the
1410 represented and computed numbers, ``library.py``'s which routines were tried.
"""

from sielaff.emulator.arithmetic.ibm1410.library import DEFAULT_VARIANT, IBM1410, VARIANTS
from sielaff.emulator.arithmetic.ibm1410.number import (
    D1410,
    EMAX,
    EMIN,
    MAX_DIGITS,
    MIN_DIGITS,
    number_class,
)

__all__ = ["D1410", "DEFAULT_VARIANT", "EMAX", "EMIN", "IBM1410", "MAX_DIGITS", "MIN_DIGITS",
           "VARIANTS", "number_class"]
