"""Number models the port runs on: ``get_arithmetic(name)`` builds one by name.

``base`` holds what every model shares (the error the 1410 stops on, float64 and
float32); ``ibm1410`` is the 1410's decimal floating point and its library.
"""

from __future__ import annotations

from collections.abc import Callable

from sielaff.emulator.arithmetic.base import (
    ArithmeticError1410,
    Float32,
    Float64,
    _ignore,
)

__all__ = ["MODELS", "ArithmeticError1410", "Float32", "Float64", "get_arithmetic"]


def get_arithmetic(name, on_error: Callable[[str], None] = _ignore):
    """Build an arithmetic by name: ``float64``, ``float32``, ``ibm1410[:K][,VARIANT]``.

    ``VARIANT`` picks the 1410 library algorithms (``sielaff.emulator.arithmetic.ibm1410``), e.g.
    ``ibm1410:8,taylor`` or ``ibm1410,trig=octant``.  An arithmetic object (anything
    with ``num`` and ``SIN``) is returned as it is.
    """
    if not isinstance(name, str):
        if hasattr(name, "num") and hasattr(name, "SIN"):
            return name
        raise TypeError(f"not an arithmetic: {name!r}")
    if name == "float64":
        return Float64(on_error)
    if name == "float32":
        return Float32(on_error)
    if name == "ibm1410" or name.startswith(("ibm1410:", "ibm1410,")):
        from sielaff.emulator.arithmetic.ibm1410 import IBM1410

        head, _, variant = name.partition(",")
        digits = 8
        if ":" in head:
            try:
                digits = int(head.split(":", 1)[1])
            except ValueError:
                raise ValueError(f"bad arithmetic {name!r}: K must be a whole number") from None
        if variant:
            return IBM1410(digits, on_error, variant=variant)
        return IBM1410(digits, on_error)
    raise ValueError(f"unknown arithmetic {name!r} (float64, float32, ibm1410[:K][,VARIANT])")


MODELS = ("float64", "float32", "ibm1410")
