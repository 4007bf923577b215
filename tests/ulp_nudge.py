"""Another CPU, simulated: every libm result the engine and the port use, one ulp off.

numpy's SIMD sin/cos/arctan2/hypot and glibc's FMA or SSE2 variants of sin, cos
and atan differ in the last bit between machines.  A test that passes only on
one side of such a difference is a test that is red somewhere else.  With
``SIELAFF_ULP_NUDGE=+1`` (or ``-1``) in the environment, ``conftest.py`` calls
:func:`install` before any test runs: every transcendental result in the
engine (numpy) and in the port's float64 and float32 arithmetic is moved one
ulp towards +inf (or -inf).  ``tests/test_ulp_immunity.py`` runs the suite's
pinned-value tests both ways in a subprocess; they must pass unchanged.

Correctly rounded operations (+ - * / sqrt) are left alone: IEEE 754 fixes
their results on every machine.
"""

from __future__ import annotations

import math
import types

import numpy as np

#: numpy functions whose results differ between SIMD implementations
NUMPY_FUNCS = ("sin", "cos", "tan", "arctan", "arctan2", "arccos", "arcsin", "hypot",
               "exp", "log")
#: math functions the float64 port calls (arithmetic.Float64)
MATH_FUNCS = ("sin", "cos", "atan", "acos", "asin", "atan2", "hypot", "exp", "log")


def _nudge(value, exact, direction: float):
    """``value`` one ulp towards ``direction``, except where ``exact`` is true."""
    target = math.copysign(math.inf, direction)
    if np.iscomplexobj(value):  # exp(1j x): each part is a sin or a cos
        v = np.asarray(value)
        moved = _nudge(v.real.copy(), exact, direction) + 1j * _nudge(v.imag.copy(), exact,
                                                                       direction)
        if isinstance(value, np.ndarray):
            value[...] = moved
            return value
        return value.dtype.type(moved) if isinstance(value, np.generic) else complex(moved)
    if isinstance(value, np.ndarray | np.generic):
        moved = np.where(exact, value, np.nextafter(value, value.dtype.type(target)))
        if isinstance(value, np.ndarray):
            value[...] = moved
            return value
        return value.dtype.type(moved)
    return value if exact else math.nextafter(value, target)


def _wrap(func, direction: float):
    def nudged(*args, **kwargs):
        result = func(*args, **kwargs)
        # A zero argument (sin 0, atan 0, atan2(0, x), hypot(0, y)) has a result that
        # C99 Annex F and every SIMD path give exactly: it is not where machines differ.
        exact = np.zeros(np.shape(result), dtype=bool)
        for a in args:
            if isinstance(a, int | float | np.ndarray | np.generic):
                exact = exact | (np.asarray(a) == 0)
        if not np.ndim(result):
            exact = bool(exact)
        return _nudge(result, exact, direction)

    nudged.__name__ = getattr(func, "__name__", "nudged")
    return nudged


def _proxy(module, names, direction: float) -> types.SimpleNamespace:
    ns = types.SimpleNamespace(**{k: getattr(module, k) for k in dir(module)
                                  if not k.startswith("__") or k == "__version__"})
    for name in names:
        setattr(ns, name, _wrap(getattr(module, name), direction))
    return ns


#: Modules left alone: numba compiles the real ``math`` (a proxy cannot be compiled), and
#: its answers are held to the numpy engine by a tolerance, not by printed digits.
UNNUDGED = ("sielaff.engine.compiled", "sielaff.engine.kernel_math", "sielaff.engine.kernel")


def modules() -> list[types.ModuleType]:
    """Every module of the package, imported (so that none escapes the nudge)."""
    import importlib
    import pkgutil

    import sielaff

    out = [sielaff]
    for info in pkgutil.walk_packages(sielaff.__path__, "sielaff."):
        if info.name in UNNUDGED or info.name.endswith("__main__"):
            continue
        try:
            out.append(importlib.import_module(info.name))
        except ImportError:  # an optional extra's module (numba, dask): not installed
            continue
    return out


def install(direction: float) -> list[str]:
    """Nudge every transcendental result of the engine, the design answers, the tools and
    the port by one ulp: each module's ``np`` and ``math`` become proxies.  Returns the
    names of the modules reached."""
    import sielaff.emulator.arithmetic.base as arithmetic

    npx, mathx = _proxy(np, NUMPY_FUNCS, direction), _proxy(math, MATH_FUNCS, direction)
    reached = []
    for module in modules():
        hit = False
        if getattr(module, "np", None) is np:
            module.np = npx
            hit = True
        if getattr(module, "math", None) is math:
            module.math = mathx
            hit = True
        if hit:
            reached.append(module.__name__)
    for name in ("SIN", "COS", "ATAN"):
        setattr(arithmetic.Float32, name,
                _wrap(getattr(arithmetic.Float32, name), direction))
    return reached
