"""The one check of a scene's numbers: finite and within a bound, named when not.

The Scene, a Load and the functions a scene may hold (TEX of ATH4, TH2DD of ATH2, a
load of ATH2) are all checked here, so the API and the spec reader say the same thing.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

#: The largest magnitude a scene value may have, in any unit system: no machine has a
#: force, torque or acceleration near it, and products of two such values stay finite.
LIMIT = 1e100


def _first_bad(a: np.ndarray, bad: np.ndarray) -> float:
    return float(a) if a.ndim == 0 else float(a[np.unravel_index(np.argmax(bad), a.shape)])


def _why(x: float) -> str:
    return "not a number" if x != x else "not finite" if abs(x) == np.inf else \
        f"past {LIMIT:g} in magnitude"


def check_value(name: str, v: Any) -> Any:
    """``v`` as a float or a float array, every element finite and within :data:`LIMIT`;
    otherwise a ValueError naming ``name``."""
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {v!r}: a number, an array of numbers or a function"
                         ) from None
    with np.errstate(invalid="ignore"):
        bad = ~(np.abs(a) <= LIMIT)
    if np.any(bad):
        x = _first_bad(a, bad)
        raise ValueError(f"{name} = {x:g}: {_why(x)}")
    return float(a) if a.ndim == 0 else a


def at(name: str, v: Any, angles: Any) -> Any:
    """A scene value at the positions ``angles``: ``v(angles)`` checked
    (:func:`call_checked`) when ``v`` is a function, else ``v`` as floats.  (Compiled for
    one position it is ``v`` itself: the compiled backend takes no functions.)"""
    return call_checked(name, v, angles) if callable(v) else np.asarray(v, dtype=float)


def call_checked(name: str, fn: Callable[[Any], Any], angles: Any) -> np.ndarray:
    """``fn(angles)`` as a fresh float array, checked like :func:`check_value` wherever
    the angle itself is a number (a position that cannot assemble gives NaN angles)."""
    out = np.array(fn(angles), dtype=float)  # a copy: never alias the caller's arrays
    with np.errstate(invalid="ignore"):
        bad = ~(np.abs(out) <= LIMIT) & ~np.isnan(angles)
    if np.any(bad):
        x = _first_bad(out, np.broadcast_to(bad, out.shape))
        raise ValueError(f"{name}: the function gave {x:g}, {_why(x)}")
    return out
