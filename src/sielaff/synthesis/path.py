"""Path generation: a coupler point through N target points, by optimisation.

The unknowns are the placement (O2 = (x, y), the angle phi of O2->O4), the lengths R1-R4,
the coupler point (r from A, angle from A->B) and THETA 2 at each target, either free
(THETA 2 at the first and N - 1 steps of one sign: the targets are met in order) or
prescribed as steps from the first (``crank_angles``).  With B on one branch (b = +1
open, -1 crossed) the coupler point at THETA 2 is, in the user's frame,

    A = O2 + R2 e^{i(phi + th2)},  O4 = O2 + R1 e^{i phi},  d = O4 - A,
    B = A + (a d + b h i d) / |d|,  a = (|d|^2 + R3^2 - R4^2) / (2 |d|),  h = sqrt(R3^2 - a^2),
    P = A + r e^{i(arg(B - A) + angle)},

and the optimiser drives P - target to zero at every target, with a penalty where the loop
does not close (|d| outside [|R3 - R4|, R3 + R4]).

**The optimiser** is ``scipy.optimize.least_squares`` with the trust-region-reflective
method: the problem is a sum of squared distances (what a least-squares solver exploits,
with a Jacobian by finite differences), the lengths and the crank steps need bounds
(lengths positive, steps of one sign), which TRF handles directly, and it is maintained,
deterministic and needs nothing beyond scipy.  A local solver finds the minimum nearest its
start, so it is started from up to ``starts`` seeded random guesses (alternating the
branch and the direction of turning), in order, and keeps the best without defect:
preferring an exact fit (every target within 1E-10 of the targets' extent) and a crank
that turns fully, smallest miss next; it stops at the first start that has all three.
The same ``seed`` gives the same linkage.

The result (:class:`~sielaff.synthesis.motion.CouplerLinkage`) carries the placement, the
coupler point and ``residuals``: each target's distance from the coupler curve (the whole
curve the linkage traces on its branch, sampled finely by the engine and refined), with
the branch, order and toggle checks of motion generation.  scipy is an optional extra
(``pip install sielaff[synthesis]``).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence

import numpy as np

from sielaff.synthesis.common import (
    CouplerPoint,
    Placement,
    branch_name,
    crank_arc_check,
    mechanism_from_lengths,
)
from sielaff.synthesis.motion import CouplerLinkage

__all__ = ["path", "curve_distance"]

_PENALTY = 10.0  # weight of the loop-closure violation against distances (both lengths)
_EXACT = 1e-10   # a fit whose targets all lie this close (times the targets' extent) is exact


#: The most starts of the search: each is one least-squares fit of at most 60 evaluations
#: per unknown, so the time is bounded by the count.
MAX_STARTS = 1000


def path(points: Sequence[Sequence[float]], *, crank_angles: Sequence[float] | None = None,
         starts: int = 40, seed: int = 0, th2d: float = 1.0,
         units: str = "in-lb-sec") -> CouplerLinkage:
    """A four-bar whose coupler point passes through (or nearest to) ``points``.

    Parameters
    ----------
    points : sequence of (x, y)
        Three or more targets [length unit] in the user's frame, in the order the coupler
        point must meet them.
    crank_angles : sequence of float, optional
        THETA 2 at each target minus THETA 2 at the first [deg] (so the first is 0; the
        sign gives the turning), prescribed; default free.
    starts : int
        How many seeded starting guesses.
    seed : int
        The random generator's seed (the same seed, the same result).
    th2d : float
        |crank speed| [rad/sec]; its sign follows the turning found.
    units : str
        The mechanism's unit system.

    Raises ValueError with one line for bad targets or when no start gives a linkage
    without defects; ModuleNotFoundError when scipy is not installed.
    """
    if isinstance(starts, bool) or not isinstance(starts, int | np.integer) \
            or not 1 <= starts <= MAX_STARTS:
        raise ValueError(f"starts = {starts!r}: a whole number from 1 to {MAX_STARTS} (each "
                         "start one bounded least-squares fit, docs/robustness.md)")
    try:
        from scipy.optimize import least_squares
    except ImportError:
        raise ModuleNotFoundError("path synthesis needs scipy: pip install "
                                  "'sielaff[synthesis]'") from None
    try:
        T = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise ValueError("points: give (x, y) pairs of numbers") from None
    if T.ndim != 2 or T.shape[1] != 2 or len(T) < 3:
        raise ValueError(f"points: three or more (x, y) pairs are needed, got shape {T.shape}")
    if not np.all(np.isfinite(T)):
        raise ValueError("points: every x and y must be a finite number")
    n = len(T)
    ext = max(float(np.hypot(*(T[i] - T[j]))) for i in range(n) for j in range(i))
    if ext == 0.0:
        raise ValueError("points: the targets are all one point")
    if np.any(np.all(T[1:] == T[:-1], axis=1)):
        raise ValueError("points: two consecutive targets are the same point")
    steps = None
    if crank_angles is not None:
        steps = np.radians(np.asarray(crank_angles, dtype=float))
        if steps.shape != (n,) or not np.all(np.isfinite(steps)) or steps[0] != 0.0:
            raise ValueError(f"crank_angles: {n} finite angles [deg], the first 0")
        if abs(steps[-1]) >= 2 * np.pi or not (np.all(np.diff(steps) > 0)
                                                or np.all(np.diff(steps) < 0)):
            raise ValueError("crank_angles: they must rise (or fall) less than 360 deg in all")
    from sielaff.engine import linkage_class

    rng = np.random.default_rng(seed)
    centre = T.mean(axis=0)
    best = None
    for k in range(int(starts)):
        branch = 1.0 if k % 2 == 0 else -1.0
        direction = 1.0 if (k // 2) % 2 == 0 else -1.0
        if steps is not None:
            direction = 1.0 if steps[-1] > 0 else -1.0
        x0, lo, hi = _start(rng, centre, ext, n, steps is None)
        fun = _residual_fn(T, branch, direction, steps, ext)
        sol = least_squares(fun, x0, bounds=(lo, hi), method="trf", x_scale="jac",
                            max_nfev=60 * len(x0))
        res = _result(sol.x, T, branch, direction, steps, th2d, units, ext)
        if res is None:
            continue
        # ranked by the distances at the crank angles found (an upper bound of the
        # distance from the curve, which is computed for the one kept)
        miss = float(np.max(np.hypot(*(fun(sol.x)[:2 * n].reshape(2, n)))))
        exact = miss <= _EXACT * ext
        turns = bool(linkage_class(res.mechanism).turns_fully)
        key = (len(res.defects) > 0, not exact, not turns, miss)
        if best is None or key < best[0]:
            best = (key, res)
        if not res.defects and exact and turns:
            break  # the first defect-free exact fit whose crank turns fully
    if best is None or best[1].defects:
        why = best[1].defects[0] if best else "no start closed the loop"
        raise ValueError(f"no four-bar without defects found through the points ({why}); "
                         "try more starts or other targets")
    res = best[1]
    resid = curve_distance(res.mechanism, res.branch, res.placement, res.coupler, T)
    return CouplerLinkage(res.mechanism, res.branch, res.placement, res.coupler, math.nan,
                          res.crank_angles, res.direction, res.defects, res.choices, resid)


def _start(rng, centre, ext, n, free):
    """A seeded start and the bounds: x, y, phi, R1..R4, r, angle, th_1, steps."""
    x = [centre[0] + ext * rng.uniform(-1.5, 1.5), centre[1] + ext * rng.uniform(-1.5, 1.5),
         rng.uniform(-np.pi, np.pi)]
    x += list(ext * rng.uniform(0.3, 1.5, 4))
    x += [ext * rng.uniform(0.2, 1.5), rng.uniform(-np.pi, np.pi), rng.uniform(0, 2 * np.pi)]
    big = 20.0 * ext
    lo = [-np.inf, -np.inf, -np.inf] + [1e-3 * ext] * 4 + [0.0, -np.inf, -np.inf]
    hi = [np.inf, np.inf, np.inf] + [big] * 4 + [big, np.inf, np.inf]
    if free:
        x += list(rng.uniform(0.2, 1.0, n - 1) * (2 * np.pi / n))
        lo += [0.0] * (n - 1)
        hi += [2 * np.pi] * (n - 1)
    return np.array(x), np.array(lo), np.array(hi)


def _unpack(v, direction, steps):
    x2, y2, phi, R1, R2, R3, R4, r, ang, t1 = v[:10]
    if steps is None:
        th = t1 + direction * np.concatenate([[0.0], np.cumsum(v[10:])])
    else:
        th = t1 + steps
    return x2, y2, phi, R1, R2, R3, R4, r, ang, th


def _coupler(x2, y2, phi, R1, R2, R3, R4, r, ang, th, branch):
    """P in the user's frame at crank angles th [rad], and the loop's violation."""
    ax, ay = x2 + R2 * np.cos(phi + th), y2 + R2 * np.sin(phi + th)
    ox, oy = x2 + R1 * math.cos(phi), y2 + R1 * math.sin(phi)
    dx, dy = ox - ax, oy - ay
    zl = np.maximum(np.hypot(dx, dy), 1e-300)
    viol = np.maximum(zl - (R3 + R4), 0.0) + np.maximum(abs(R3 - R4) - zl, 0.0)
    a = (zl * zl + R3 * R3 - R4 * R4) / (2.0 * zl)
    h = np.sqrt(np.maximum(R3 * R3 - a * a, 0.0))
    bx = ax + (a * dx - branch * h * dy) / zl
    by = ay + (a * dy + branch * h * dx) / zl
    t3 = np.arctan2(by - ay, bx - ax)
    return ax + r * np.cos(t3 + ang), ay + r * np.sin(t3 + ang), viol


def _residual_fn(T, branch, direction, steps, ext):
    def fun(v):
        x2, y2, phi, R1, R2, R3, R4, r, ang, th = _unpack(v, direction, steps)
        px, py, viol = _coupler(x2, y2, phi, R1, R2, R3, R4, r, ang, th, branch)
        return np.concatenate([px - T[:, 0], py - T[:, 1], _PENALTY * viol])
    return fun


def _result(v, T, branch, direction, steps, th2d, units, ext) -> CouplerLinkage | None:
    x2, y2, phi, R1, R2, R3, R4, r, ang, th = _unpack(v, direction, steps)
    _, _, viol = _coupler(x2, y2, phi, R1, R2, R3, R4, r, ang, th, branch)
    if np.any(viol > 1e-9 * ext):
        return None
    m = mechanism_from_lengths(R1, R2, R3, R4, th2d=direction * abs(float(th2d)), units=units)
    th2 = np.mod(np.degrees(th), 360.0)
    defects = []
    why = crank_arc_check(m, th2, int(direction))
    if why:
        defects.append(why)
    place = Placement(float(x2), float(y2), float(np.mod(np.degrees(phi) + 180.0, 360.0) - 180.0))
    coupler = CouplerPoint(float(r), float(np.mod(np.degrees(ang) + 180.0, 360.0) - 180.0))
    bname = branch_name(branch)
    choices = {"branch": bname, "crank_angles": "prescribed" if steps is not None else "free"}
    return CouplerLinkage(m, bname, place, coupler, math.nan, th2, int(direction),
                          tuple(defects), choices, None)


def curve_distance(m, branch: str, place: Placement, coupler: CouplerPoint,
                   T: np.ndarray, n: int = 2881) -> np.ndarray:
    """Each target's distance [length unit] from the coupler curve the engine traces over
    every THETA 2 the linkage reaches (``n`` samples, then a golden-section refinement
    about the nearest one)."""
    from sielaff.engine import AssemblyWarning, point_motion, reachable

    th = reachable(m, n)

    def where(t):
        with warnings.catch_warnings():  # past a toggle the point is NaN: counted as inf
            warnings.simplefilter("ignore", AssemblyWarning)
            k = point_motion(m, np.atleast_1d(t), 3, coupler.r, coupler.angle, branch=branch)
        return place.to_user(k["X"], k["Y"])

    ux, uy = where(th)
    out = []
    step = 360.0 / n
    for tx, ty in T:
        d = np.hypot(ux - tx, uy - ty)
        i = int(np.nanargmin(d))
        a, b = th[i] - step, th[i] + step
        g = (math.sqrt(5.0) - 1.0) / 2.0

        def dist(t, tx=tx, ty=ty):
            x, y = where(t)
            v = float(np.hypot(x[0] - tx, y[0] - ty))
            return v if math.isfinite(v) else math.inf

        c, e = b - g * (b - a), a + g * (b - a)
        fc, fe = dist(c), dist(e)
        for _ in range(60):
            if fc <= fe:
                b, e, fe = e, c, fc
                c = b - g * (b - a)
                fc = dist(c)
            else:
                a, c, fc = c, e, fe
                e = a + g * (b - a)
                fe = dist(e)
        out.append(min(float(d[i]), fc, fe))
    return np.array(out)
