"""Function generation: link 4's angle a function of link 2's (Freudenstein's equation).

The input x in [x0, x1] drives the crank and y = f(x) is read off the rocker, each range of
angles given as (start, span) in degrees:

    THETA 2 = start2 + span2 (x - x0) / (x1 - x0)
    THETA 4 = start4 + span4 (f(x) - f(x0)) / (f(x1) - f(x0))

With O2 at the origin, O4 = (R1, 0), A = R2 e^{i th2} and B = O4 + R4 e^{i th4}, the
coupler's length |B - A| = R3 gives, divided by 2 R2 R4 (Freudenstein 1955, in this
project's frame and angles)::

    K1 cos th4 - K2 cos th2 + K3 = cos(th2 - th4),
    K1 = R1 / R2,  K2 = R1 / R4,  K3 = (R1^2 + R2^2 + R4^2 - R3^2) / (2 R2 R4),

linear in K1, K2, K3.  Three precision points give three equations, solved exactly; more
points are fitted by least squares (of the equation's residual, the classical choice; the
angle error is then small but not minimised).  The precision points are Chebyshev-spaced
by default, x_j = (x0 + x1)/2 - (x1 - x0)/2 cos((2j - 1) pi / (2n)), j = 1..n, which
roughly levels the structural error between them.  R1 (``frame``) sets the scale:
R2 = R1/K1, R4 = R1/K2, R3^2 = R1^2 + R2^2 + R4^2 - 2 R2 R4 K3.

The linkage must then reach every precision point on one branch and sweep the input range
without a toggle; the **structural error** is THETA 4 generated minus THETA 4 wanted over
the whole range, in degrees.  Any kind of four-bar may result (a function generator's
crank need not turn fully).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from sielaff.mechanism import Mechanism
from sielaff.synthesis.common import (
    branch_name,
    crank_arc_check,
    mechanism_from_lengths,
    side_of,
)

__all__ = ["FunctionGenerator", "chebyshev", "function"]


@dataclass(frozen=True)
class FunctionGenerator:
    """A function generator.

    ``mechanism``, ``branch`` (the engine's, ``"open"`` or ``"crossed"``), ``K``
    (K1, K2, K3) [-], ``precision``: the precision points' x [x's unit], THETA 2 and
    THETA 4 [deg] wanted there.  ``x``, ``th2`` [deg], ``th4`` [deg wanted] and
    ``structural_error`` [deg of THETA 4, generated - wanted] over the whole range
    (``samples`` points); ``max_error`` [deg] the largest |error|.
    """

    mechanism: Mechanism
    branch: str
    K: tuple[float, float, float]
    precision: tuple[np.ndarray, np.ndarray, np.ndarray]
    x: np.ndarray
    th2: np.ndarray
    th4: np.ndarray
    structural_error: np.ndarray
    max_error: float


#: The most positions the structural error is computed at: a kinematic analysis of that
#: many positions, some tens of arrays of 8 MB.
MAX_SAMPLES = 1_000_000
#: The most precision points: a least-squares fit of that many equations.
MAX_POINTS = 10_000


def chebyshev(x0: float, x1: float, n: int) -> np.ndarray:
    """``n`` Chebyshev-spaced points in [x0, x1] (module doc), increasing from x0."""
    j = np.arange(1, n + 1)
    return (x0 + x1) / 2.0 - (x1 - x0) / 2.0 * np.cos((2 * j - 1) * np.pi / (2 * n))


def function(f: Callable, x_range: Sequence[float], input_range: Sequence[float],
             output_range: Sequence[float], points: int | Sequence[float] = 3, *,
             frame: float = 1.0, samples: int = 361, th2d: float = 1.0,
             units: str = "in-lb-sec") -> FunctionGenerator:
    """A four-bar whose rocker angle generates y = f(x) (module doc).

    Parameters
    ----------
    f : callable
        y = f(x) [any unit]; called on a numpy array of x (or one x at a time if that fails).
    x_range : (float, float)
        x0, x1 [x's unit], x0 != x1.
    input_range, output_range : (float, float)
        (start, span) [deg] of THETA 2 and of THETA 4; 0 < |span| < 360.
    points : int or sequence of float
        How many Chebyshev-spaced precision points (3: exact; more: least squares), or
        the precision points' x themselves [x's unit].
    frame : float
        R1 [length unit].
    samples : int
        How many x (evenly spaced, ends included) the structural error is given at.
    th2d : float
        The crank speed put in the mechanism [rad/sec].
    units : str
        The mechanism's unit system.

    Raises ValueError with one line when no four-bar generates the function so.
    """
    x0, x1 = (float(v) for v in x_range)
    s2, w2 = (float(v) for v in input_range)
    s4, w4 = (float(v) for v in output_range)
    for name, v in (("x0", x0), ("x1", x1), ("input start", s2), ("input span", w2),
                    ("output start", s4), ("output span", w4), ("frame", frame)):
        if not math.isfinite(v):
            raise ValueError(f"{name} = {v}: not a finite number")
    if x0 == x1:
        raise ValueError(f"x_range = ({x0:g}, {x1:g}): x0 and x1 must differ")
    for name, w in (("input", w2), ("output", w4)):
        if not 0.0 < abs(w) < 360.0:
            raise ValueError(f"{name} span = {w:g} deg: it must be more than 0 and less than "
                             "360 deg")
    if not frame > 0:
        raise ValueError(f"frame = {frame:g}: R1 must be positive")
    if isinstance(samples, bool) or not isinstance(samples, int | np.integer) \
            or not 2 <= samples <= MAX_SAMPLES:
        raise ValueError(f"samples = {samples!r}: a whole number from 2 to {MAX_SAMPLES} "
                         "(the structural error's positions, docs/robustness.md)")
    if isinstance(points, int | np.integer):
        if not points <= MAX_POINTS:
            raise ValueError(f"points = {points}: at most {MAX_POINTS} precision points")
        if points < 3:
            raise ValueError(f"points = {points}: three or more precision points are needed")
        xp = chebyshev(x0, x1, int(points))
    else:
        xp = np.asarray(points, dtype=float)
        if xp.ndim != 1 or len(xp) < 3 or not np.all(np.isfinite(xp)):
            raise ValueError("points: three or more finite precision points are needed")
        if len(np.unique(xp)) != len(xp):
            raise ValueError("points: the precision points must differ")
    y0, y1 = _call(f, np.array([x0, x1]))
    if not (math.isfinite(y0) and math.isfinite(y1)) or y0 == y1:
        raise ValueError(f"f(x0) = {y0:g}, f(x1) = {y1:g}: they must be finite and differ "
                         "(the output range is scaled between them)")

    def angles(x):
        y = _call(f, x)
        if not np.all(np.isfinite(y)):
            raise ValueError("f is not finite over the whole x range")
        return s2 + w2 * (x - x0) / (x1 - x0), s4 + w4 * (y - y0) / (y1 - y0)

    t2, t4 = angles(xp)
    r2, r4 = np.radians(t2), np.radians(t4)
    M = np.column_stack([np.cos(r4), -np.cos(r2), np.ones_like(r2)])
    rhs = np.cos(r2 - r4)
    if np.linalg.cond(M) > 1e12:
        raise ValueError("the precision points give a singular Freudenstein system (their "
                         "angles are too alike): no unique four-bar")
    K = np.linalg.solve(M, rhs) if len(xp) == 3 else np.linalg.lstsq(M, rhs, rcond=None)[0]
    K1, K2, K3 = (float(k) for k in K)
    if not (K1 > 0 and K2 > 0):
        which = "R2 = R1/K1" if not K1 > 0 else "R4 = R1/K2"
        raise ValueError(f"K1 = {K1:.6g}, K2 = {K2:.6g}: {which} would not be positive, so "
                         "no four-bar generates these angle ranges (try other starts)")
    R1 = float(frame)
    R2, R4 = R1 / K1, R1 / K2
    R3sq = R1 * R1 + R2 * R2 + R4 * R4 - 2.0 * R2 * R4 * K3
    if not R3sq > 0:
        raise ValueError(f"K3 = {K3:.6g}: R3^2 = {R3sq:.6g} would not be positive, so no "
                         "four-bar generates these angle ranges")
    R3 = math.sqrt(R3sq)
    m = mechanism_from_lengths(R1, R2, R3, R4, th2d=th2d, units=units)
    # the branch of each precision point (B wanted there; exactly on the coupler circle
    # at three points, nearly so with least squares)
    sides = side_of(R2 * np.cos(r2), R2 * np.sin(r2), R1, 0.0,
                    R1 + R4 * np.cos(r4), R4 * np.sin(r4))
    if not (np.all(sides > 0) or np.all(sides < 0)):
        raise ValueError("branch defect: the precision points lie on both branches, so no "
                         "one assembly of this four-bar passes through them")
    branch = branch_name(float(sides[0]))
    why = crank_arc_check(m, np.array([s2, s2 + w2]), 1 if w2 > 0 else -1)
    if why:
        raise ValueError(f"the input range {s2:g} to {s2 + w2:g} deg: {why}")
    from sielaff.engine import AssemblyWarning, analyze

    xs = np.linspace(x0, x1, int(samples))
    th2, th4 = angles(xs)
    with warnings.catch_warnings():  # a position that does not close is refused below
        warnings.simplefilter("ignore", AssemblyWarning)
        got = analyze(m, th2, ["ATH4"], branch=branch)["ATH4"]
    err = np.mod(got - th4 + 180.0, 360.0) - 180.0
    if not np.all(np.isfinite(err)):
        raise ValueError("the linkage does not assemble over the whole input range")
    return FunctionGenerator(m, branch, (K1, K2, K3), (xp, t2, t4), xs, th2, th4, err,
                             float(np.max(np.abs(err))))


def _call(f: Callable, x: np.ndarray) -> np.ndarray:
    """f on an array, or element by element when f takes only scalars."""
    try:
        with np.errstate(all="ignore"):
            y = np.asarray(f(x), dtype=float)
        if y.shape == x.shape:
            return y
    except (TypeError, ValueError):
        pass
    try:
        return np.array([float(f(float(v))) for v in x])
    except (TypeError, ValueError, ArithmeticError) as e:
        raise ValueError(f"f could not be evaluated: {e}") from None
