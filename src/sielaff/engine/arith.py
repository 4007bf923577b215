"""The three operations the engine's steps use beyond arithmetic and numpy's functions.

A step is written once, for arrays (numpy, in place where the step owns an array) and
for one position at a time: the compiled backend compiles the same function with ``np``
standing for one position's arithmetic (:mod:`sielaff.engine.kernel_math`), where
these three have their one-position forms.  Nothing else in a step may mutate an array
it did not make, test for arrays, or look at a whole array.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["mod360", "owned", "put"]


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
