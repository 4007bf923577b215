"""The operations the engine's steps use beyond arithmetic and numpy's functions.

A step is written once, for arrays (numpy, in place where the step owns an array) and
for one position at a time: the compiled backend compiles the same function with ``np``
standing for one position's arithmetic (:mod:`sielaff.engine.kernel_math`), where
these have their one-position forms.  Nothing else in a step may mutate an array it did
not make, test for arrays, or look at a whole array.

Beside ``owned``, ``put`` and ``mod360``, a step that works on some positions only (pin
friction's solve where the law need not contract) finds them, picks its values there
and writes its answers back by the operations below: over arrays they compact
(``positions`` the indices, ``pick`` the values there, ``scatter`` the answers back); at
one position the "positions" are whether it is one of them, ``pick`` is the value
itself and ``scatter`` a select.  (A step iterated per position is declared with
:func:`sielaff.engine.iterate.iterated`.)  ``shape_of``, ``flat``, ``filled`` and
``shaped`` take a step's inputs of any broadcast shape to flat arrays and back (at one
position: the number itself).  Code that needs whole arrays even at one position (a
search over many starts) is marked :func:`array_code`; ``batch`` hands it values at some
positions (at one position: an array of one) and ``unbatch`` takes its answers back.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["array_code", "batch", "filled", "flat", "mod360", "none", "owned",
           "pick", "positions", "put", "scatter", "shape_of", "shaped", "unbatch"]


def owned(x: Any) -> bool:
    """Whether ``x`` is an array the step may overwrite (``np.sqrt(x, out=x)``); a float
    (a skipped step's 0.0, or one position) is not."""
    return isinstance(x, np.ndarray)


def put(dst: Any, value: Any, where: Any) -> Any:
    """``dst`` with ``value`` where ``where`` holds (in place: ``dst`` is the step's own)."""
    np.copyto(dst, value, where=where)
    return dst


def mod360(x: Any) -> Any:
    """Angles [deg] reduced modulo 360 into [0, 360) as ``np.mod(x, 360.0)`` reduces them
    (fmod, exact, then 360 added to a negative remainder); angles already there are
    returned as they are.  A NaN makes min or max NaN, and then every element is reduced
    (NaN stays NaN, the others as without it).

    Angles in [-360, 720), a line's angle plus an offset, take one turn added or taken
    away, the same numbers np.mod gives at a tenth of its cost: x - 360 is exact for x in
    [360, 720) (Sterbenz), and for x in [-360, 0) np.mod's remainder is x itself, to
    which it adds 360 as here (rounded, so -1e-20 becomes 360 in both)."""
    if not np.size(x):
        return x
    lo, hi = np.min(x), np.max(x)
    if lo >= 0.0 and hi < 360.0:
        return x
    if lo >= -360.0 and hi < 720.0:
        y = np.asarray(np.subtract(x, 360.0))
        np.copyto(y, x, where=np.less(x, 360.0))
        np.add(y, 360.0, out=y, where=np.less(x, 0.0))  # may round to 360, as np.mod's
        y += 0.0  # -0.0 -> +0.0, as np.mod
        return y if np.ndim(x) else y[()]
    return np.mod(x, 360.0)


def shape_of(xs: tuple[Any, ...]) -> Any:
    """The shape the values ``xs`` broadcast to."""
    return np.broadcast_shapes(*(np.shape(x) for x in xs))


def flat(x: Any, shape: Any) -> Any:
    """``x`` broadcast to ``shape``, as a flat float array (a view where it can be)."""
    return np.broadcast_to(np.asarray(x, dtype=float), shape).reshape(-1)


def filled(shape: Any, value: float) -> Any:
    """A fresh flat array of ``shape``'s size, every element ``value``."""
    return np.full(int(np.prod(shape)), value)


def shaped(x: Any, shape: Any) -> Any:
    """The flat ``x`` in ``shape``."""
    return x.reshape(shape)


def positions(mask: Any) -> Any:
    """The positions where ``mask`` holds (flat indices)."""
    return np.flatnonzero(mask)


def pick(x: Any, idx: Any) -> Any:
    """``x`` at the positions ``idx`` (indices or a mask of the positions ``x`` has)."""
    return x[idx]


def none(idx: Any) -> bool:
    """Whether there are no positions in ``idx``."""
    return not idx.size


def scatter(dst: Any, idx: Any, value: Any, where: Any) -> Any:
    """``dst`` (the step's own, changed in place) with ``value`` (given at each position of
    ``idx``, or one number) put at the positions of ``idx`` where ``where`` holds."""
    dst[idx[where]] = value[where] if np.ndim(value) else value
    return dst


def batch(x: Any, idx: Any) -> Any:
    """``x`` at the positions ``idx``, as an array for :func:`array_code`."""
    return x[idx]


def unbatch(x: Any) -> Any:
    """An answer of :func:`array_code` at the positions it was given."""
    return x


def array_code(fn: Any) -> Any:
    """Mark ``fn`` as array code: the compiled backend compiles it with numba's own numpy
    (arrays), not one position's (it is called with :func:`batch`'s arrays)."""
    fn.__sielaff_array_code__ = True
    return fn
