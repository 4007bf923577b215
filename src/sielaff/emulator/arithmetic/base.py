"""Number models that the line-by-line port runs on.

The port (``sielaff.emulator.program``) is written once, in plain operators, and an
*arithmetic* is swapped underneath it.  An arithmetic provides:

* ``num(value)``   -- convert a constant, a card value (float) or an int
  (``ZZZ = I``) to the model's number type.  Strings are used for constants
  that carry more digits than a double (the listing's 21-digit PI).
* ``SIN, COS, ATAN, SQRT, ABS`` -- the FORTRAN library, in the model.
* numbers that support ``+ - * /``, unary minus, comparisons, mixing with
  Python float literals (so the port can write ``A = A + 2.0`` as the
  listing does), ``float(x)`` and ``str(x)``.  ``str(x)`` gives the decimal
  digits the printer truncates: the shortest round-trip decimal for binary
  models, the exact digits for decimal models.
* ``on_error`` -- called with one line of text where the 1410 library would
  print an error message and go on (SQRT of a negative argument).

Models: ``float64`` (default), ``float32``, ``ibm1410[:K][,VARIANT]`` (see
``sielaff.emulator.arithmetic.ibm1410``).  ``get_arithmetic(name)`` builds one by name.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

#: numpy, imported by the first ``Float32()``: ``sielaff run`` on float64 starts
#: without it (a tenth of a second less start-up for every run).
np: Any = None


class ArithmeticError1410(Exception):
    """Arithmetic that the 1410 could not carry on from (overflow, runaway loop)."""


def _ignore(_msg: str) -> None:
    pass


class Float64:
    """IEEE double precision: Python floats, the ``math`` library."""

    name = "float64"

    def __init__(self, on_error: Callable[[str], None] = _ignore) -> None:
        self.on_error = on_error
        self.ABS = abs
        self.SIN = math.sin
        self.COS = math.cos
        self.ATAN = math.atan

    def num(self, value: float | str) -> float:
        return float(value)

    def SQRT(self, x: float) -> float:
        if x < 0.0:
            # C28-0328-3 p. 23: error message, then the root of |x|.
            self.on_error(f"SQRT of negative argument {x!r}: using SQRT(ABS(X))")
            x = -x
        return math.sqrt(x)


class Float32:
    """IEEE single precision throughout: numpy float32 scalars."""

    name = "float32"

    def __init__(self, on_error: Callable[[str], None] = _ignore) -> None:
        global np
        import numpy as np

        self.on_error = on_error
        self.ABS = abs

    def num(self, value: float | str) -> np.float32:
        return np.float32(float(value))

    def SIN(self, x: np.float32) -> np.float32:
        return np.sin(np.float32(x))

    def COS(self, x: np.float32) -> np.float32:
        return np.cos(np.float32(x))

    def ATAN(self, x: np.float32) -> np.float32:
        return np.arctan(np.float32(x))

    def SQRT(self, x: np.float32) -> np.float32:
        if x < 0.0:
            self.on_error(f"SQRT of negative argument {x}: using SQRT(ABS(X))")
            x = -x
        return np.sqrt(np.float32(x))
