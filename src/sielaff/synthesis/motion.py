"""Motion generation: a coupler that passes through two or three given poses.

A pose is (x, y, angle) in the user's frame: where a point P of the coupler must be
[length unit] and the angle [deg, CCW from the user's +x] of a line fixed in the coupler.
The coupler's own frame has its origin at P and its +x along that line; a point q = (u, v)
of the coupler is at ``P_j + R(angle_j) q`` in pose j.

A four-bar is two dyads, each a moving pivot on the coupler (A for the crank, B for the
rocker) and a fixed pivot (O2, O4) the moving pivot circles about.  **The free choices**
(``moving``, ``fixed``):

* three poses: the moving pivots (u, v) in the coupler's frame; each fixed pivot is then
  the centre of the circle through the three positions of its moving pivot (a moving
  pivot whose three positions lie on a line has none);
* two poses: the moving pivots as above, and where each fixed pivot lies on the
  perpendicular bisector of its moving pivot's two positions: ``t``, the signed distance
  [length unit] from the chord's midpoint, + to the left of the chord's direction.

Left to ``None`` they are searched: moving pivots on a grid of 15 x 15 (three poses) or
9 x 9 (two poses; with t in 7 steps) coupler points spanning 1.5 times the poses' extent
(the largest distance between two pose points; 1 length unit for two poses about one
point) on each side of P, every pair of dyads tried, and the pair kept that has no defect, whose
crank turns fully (a Grashof crank-rocker or double-crank, so a motor can drive it), every
link from 0.1 to 10 times the poses' extent, and the largest minimum transmission angle.

The result places the engine's frame in the user's (O2 and the angle of O2->O4, see
:class:`~sielaff.synthesis.common.Placement`), gives P as a coupler point (r from A,
angle from the line A->B, as RG3 and ADEL3 place G3), the pose's line as ``line_angle``
[deg] CCW from A->B, and THETA 2 at each pose.  It is checked for the **branch defect**
(the poses on two branches: the linkage would have to be taken apart between them), the
**order defect** (the crank, turning one way, meets the poses out of order) and a
**toggle** between poses (the crank cannot turn through it); ``defects`` lists them
(empty: none).  The coupler passes through every pose exactly (up to roundoff): the
tests re-analyse each linkage with the engine and with their own circle intersections.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sielaff.mechanism import Mechanism
from sielaff.synthesis.common import (
    CouplerPoint,
    Placement,
    branch_name,
    crank_arc_check,
    mechanism_from_lengths,
    side_of,
)

__all__ = ["CouplerLinkage", "motion"]

#: A circumcentre whose determinant is below this (relative to the scale^2) means the
#: three positions are on one line (to roundoff).
_COLLINEAR = 1e-12
_MAX_LENGTH = 10.0  # the search keeps links from _MIN_LENGTH to _MAX_LENGTH times the
_MIN_LENGTH = 0.1   # poses' extent (a tiny frame or crank makes a poor machine)


@dataclass(frozen=True)
class CouplerLinkage:
    """A synthesised linkage with a coupler point (motion or path generation).

    ``mechanism``; ``branch`` (the engine's); ``placement`` (the engine's frame in the
    user's); ``coupler`` (the coupler point P: r [length unit] from A, angle [deg] from
    A->B); ``line_angle`` [deg] the pose's line, CCW from A->B (motion; NaN for path);
    ``crank_angles`` THETA 2 [deg] at each pose or target; ``direction`` +1 (CCW, TH2D >
    0) or -1 the way the crank turns through them in order; ``defects``: one line each
    (empty: none); ``choices``: the free choices used; ``residuals`` [length unit]
    (path: each target's distance from the coupler curve; motion: None).
    """

    mechanism: Mechanism
    branch: str
    placement: Placement
    coupler: CouplerPoint
    line_angle: float
    crank_angles: np.ndarray
    direction: int
    defects: tuple[str, ...]
    choices: dict
    residuals: np.ndarray | None = None


def motion(poses: Sequence[Sequence[float]], *, moving: Sequence[Sequence[float]] | None = None,
           fixed: Sequence[float] | None = None, direction: int | None = None,
           th2d: float = 1.0, units: str = "in-lb-sec") -> CouplerLinkage:
    """A four-bar whose coupler passes through ``poses`` (module doc).

    Parameters
    ----------
    poses : sequence of (x, y, angle)
        Two or three poses: [length unit], [length unit], [deg] in the user's frame.
    moving : ((u_A, v_A), (u_B, v_B)), optional
        The moving pivots A (crank) and B (rocker) in the coupler's frame [length unit].
    fixed : (t_A, t_B), optional
        Two poses only: each fixed pivot's place on its bisector [length unit].
    direction : {+1, -1}, optional
        The crank's turning, CCW or CW; default: the one that meets the poses in order.
    th2d : float
        |crank speed| [rad/sec]; its sign is ``direction``'s.
    units : str
        The mechanism's unit system.

    Raises ValueError with one line when the poses or the choices admit no four-bar.
    """
    P = _poses(poses)
    n = len(P)
    ext = _extent(P)
    if ext == 0.0:  # two poses turning about P: the bisectors all pass through P
        ext = 1.0   # no length in the problem; the search spans 1.5 length units
    if fixed is not None and n != 2:
        raise ValueError("fixed: only two poses leave the fixed pivots free (three fix them)")
    if direction not in (None, 1, -1):
        raise ValueError(f"direction = {direction!r}: +1 (CCW) or -1 (CW)")
    if moving is None:
        return _search(P, ext, fixed, direction, th2d, units)
    q = np.asarray(moving, dtype=float)
    if q.shape != (2, 2) or not np.all(np.isfinite(q)):
        raise ValueError("moving: give ((u_A, v_A), (u_B, v_B)), finite numbers")
    t = np.zeros(2) if n == 3 else np.asarray(fixed if fixed is not None else (ext, ext),
                                               dtype=float)
    if t.shape != (2,) or not np.all(np.isfinite(t)):
        raise ValueError("fixed: give (t_A, t_B), finite numbers")
    dyads = []
    for k, name in enumerate("AB"):
        pos = _positions(P, q[k:k + 1])[0]                   # (n, 2)
        centre = _centres(pos[None], t[k:k + 1], ext)[0]
        if not np.all(np.isfinite(centre)):
            why = ("its three positions lie on one line" if n == 3
                   else "its two positions coincide (it sits on the poses' pole)")
            raise ValueError(f"moving pivot {name} = ({q[k, 0]:g}, {q[k, 1]:g}): {why}, so "
                             "it has no fixed pivot; choose another")
        dyads.append((pos, centre))
    return _linkage(P, dyads, q, t if n == 2 else None, direction, th2d, units)


def _poses(poses) -> np.ndarray:
    try:
        P = np.asarray(poses, dtype=float)
    except (TypeError, ValueError):
        raise ValueError("poses: give two or three (x, y, angle) triples of numbers") from None
    if P.ndim != 2 or P.shape[1] != 3 or P.shape[0] not in (2, 3):
        raise ValueError(f"poses: two or three (x, y, angle) triples are needed, got shape "
                         f"{P.shape}")
    if not np.all(np.isfinite(P)):
        raise ValueError("poses: every x, y and angle must be a finite number")
    for i in range(len(P)):
        for j in range(i):
            if (P[i, :2] == P[j, :2]).all() and np.mod(P[i, 2] - P[j, 2], 360.0) == 0.0:
                raise ValueError(f"poses {j + 1} and {i + 1} are the same pose")
    return P


def _extent(P: np.ndarray) -> float:
    """The largest distance between two pose points; three poses about one point are
    refused (every circle centre is that point, so the fixed pivots would coincide)."""
    d = max(float(np.hypot(*(P[i, :2] - P[j, :2]))) for i in range(len(P)) for j in range(i))
    if d == 0.0 and len(P) == 3:
        raise ValueError("the three poses are rotations about one point P: every fixed "
                         "pivot would be P, so no four-bar (a single link about P does it)")
    return d


def _positions(P: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Coupler points q (m, 2) in each pose: (m, n, 2) in the user's frame."""
    a = np.radians(P[:, 2])
    c, s = np.cos(a), np.sin(a)
    x = P[None, :, 0] + c[None] * q[:, None, 0] - s[None] * q[:, None, 1]
    y = P[None, :, 1] + s[None] * q[:, None, 0] + c[None] * q[:, None, 1]
    return np.stack([x, y], axis=-1)


def _centres(pos: np.ndarray, t: np.ndarray, ext: float) -> np.ndarray:
    """Fixed pivots (m, 2) for moving-pivot positions (m, n, 2): the circumcentre (n = 3),
    or the bisector point t (n = 2); NaN where there is none."""
    p1, p2 = pos[:, 0], pos[:, 1]
    if pos.shape[1] == 2:
        mid, d = (p1 + p2) / 2.0, p2 - p1
        L = np.hypot(d[:, 0], d[:, 1])
        with np.errstate(all="ignore"):
            normal = np.stack([-d[:, 1], d[:, 0]], axis=-1) / L[:, None]
        out = mid + t[:, None] * normal
        out[L <= 1e-12 * ext] = np.nan
        return out
    p3 = pos[:, 2]
    b, c = p2 - p1, p3 - p1
    det = 2.0 * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
    bb, cc = (b * b).sum(-1), (c * c).sum(-1)
    with np.errstate(all="ignore"):
        ux = (c[:, 1] * bb - b[:, 1] * cc) / det
        uy = (b[:, 0] * cc - c[:, 0] * bb) / det
    out = p1 + np.stack([ux, uy], axis=-1)
    out[np.abs(det) <= _COLLINEAR * ext * ext] = np.nan
    return out


def _linkage(P, dyads, q, t, direction, th2d, units) -> CouplerLinkage:
    (pa, o2), (pb, o4) = dyads
    scale = _extent(P) or 1.0
    R1 = float(np.hypot(*(o4 - o2)))
    if R1 <= 1e-12 * scale:
        raise ValueError("the two fixed pivots coincide: no four-bar (choose other moving "
                         "pivots)")
    R2 = float(np.hypot(*(pa[0] - o2)))
    R3 = float(np.hypot(*(pb[0] - pa[0])))
    R4 = float(np.hypot(*(pb[0] - o4)))
    if min(R2, R3, R4) <= 1e-12 * scale:
        raise ValueError("a moving pivot lies on its fixed pivot or on the other moving "
                         "pivot: a link of zero length (choose other moving pivots)")
    phi = math.degrees(math.atan2(o4[1] - o2[1], o4[0] - o2[0]))
    place = Placement(float(o2[0]), float(o2[1]), phi)
    th2 = np.degrees(np.arctan2(pa[:, 1] - o2[1], pa[:, 0] - o2[0])) - phi
    th2 = np.mod(th2, 360.0)
    sides = side_of(pa[:, 0], pa[:, 1], o4[0], o4[1], pb[:, 0], pb[:, 1])
    defects = []
    if not (np.all(sides > 0) or np.all(sides < 0)):
        defects.append("branch defect: the poses lie on both branches (the linkage would "
                       "have to be taken apart between them)")
    dirs = [direction] if direction else [1, -1]
    base = mechanism_from_lengths(R1, R2, R3, R4, th2d=abs(th2d), units=units)
    why = {d: crank_arc_check(base, th2, d) for d in dirs}
    chosen = next((d for d in dirs if why[d] is None), dirs[0])
    if why[chosen]:
        defects.append("; ".join(f"turning {'CCW' if d > 0 else 'CW'}: {why[d]}"
                                 for d in dirs))
    m = base.replace(TH2D=chosen * abs(float(th2d)))
    pp = P[0, :2]
    ab = math.atan2(pb[0, 1] - pa[0, 1], pb[0, 0] - pa[0, 0])
    r = float(np.hypot(*(pp - pa[0])))
    ang = math.degrees(math.atan2(pp[1] - pa[0, 1], pp[0] - pa[0, 0]) - ab) if r > 0 else 0.0
    coupler = CouplerPoint(r, float(np.mod(ang + 180.0, 360.0) - 180.0))
    line = float(np.mod(P[0, 2] - math.degrees(ab) + 180.0, 360.0) - 180.0)
    choices = {"moving": tuple(map(tuple, q.tolist()))}
    if t is not None:
        choices["fixed"] = tuple(float(v) for v in t)
    return CouplerLinkage(m, branch_name(float(sides[0])), place, coupler, line, th2, chosen,
                          tuple(defects), choices)


def _search(P, ext, fixed, direction, th2d, units) -> CouplerLinkage:
    """Every pair of candidate dyads (module doc), the best defect-free one."""
    n = len(P)
    g = np.linspace(-1.5 * ext, 1.5 * ext, 15 if n == 3 else 9)
    q = np.array([(u, v) for u in g for v in g])
    if n == 3:
        ts = np.zeros(1)
    elif fixed is not None:
        raise ValueError("fixed without moving: give the moving pivots too (or neither)")
    else:
        ts = ext * np.array([-2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0])
    qq = np.repeat(q, len(ts), axis=0)
    tt = np.tile(ts, len(q))
    pos = _positions(P, qq)
    cen = _centres(pos, tt, ext)
    ok = np.all(np.isfinite(cen), axis=1)
    pos, cen, qq, tt = pos[ok], cen[ok], qq[ok], tt[ok]
    ia, ib = np.meshgrid(np.arange(len(qq)), np.arange(len(qq)), indexing="ij")
    ia, ib = ia.ravel(), ib.ravel()
    keep = ia != ib
    ia, ib = ia[keep], ib[keep]
    pa, pb, o2, o4 = pos[ia], pos[ib], cen[ia], cen[ib]
    R1 = np.hypot(*(o4 - o2).T)
    R2 = np.hypot(*(pa[:, 0] - o2).T)
    R3 = np.hypot(*(pb[:, 0] - pa[:, 0]).T)
    R4 = np.hypot(*(pb[:, 0] - o4).T)
    L = np.stack([R1, R2, R3, R4])
    fine = np.all(L > _MIN_LENGTH * ext, axis=0) & np.all(L < _MAX_LENGTH * ext, axis=0)
    s, lng = L.min(axis=0), L.max(axis=0)
    grashof = (L.sum(axis=0) - 2.0 * (s + lng)) > 1e-9 * (s + lng)
    crank = grashof & ((R2 == s) | (R1 == s))  # crank-rocker or double-crank: link 2 turns
    sides = side_of(pa[..., 0], pa[..., 1], o4[:, None, 0], o4[:, None, 1], pb[..., 0],
                    pb[..., 1])
    one_branch = np.all(sides > 0, axis=1) | np.all(sides < 0, axis=1)
    with np.errstate(all="ignore"):
        mu = np.full(len(R1), 90.0)
        for Ld in (R1 - R2, R1 + R2):
            cg = np.clip((R3 * R3 + R4 * R4 - Ld * Ld) / (2.0 * R3 * R4), -1.0, 1.0)
            gam = np.degrees(np.arccos(cg))
            mu = np.minimum(mu, np.minimum(gam, 180.0 - gam))
    score = np.where(fine & crank & one_branch, mu, -1.0)
    order = np.argsort(-score, kind="stable")
    for k in order[:50]:
        if score[k] < 0:
            break
        i, j = ia[k], ib[k]
        res = _linkage(P, [(pos[i], cen[i]), (pos[j], cen[j])], np.array([qq[i], qq[j]]),
                       np.array([tt[i], tt[j]]) if n == 2 else None, direction, th2d, units)
        if not res.defects:
            return res
    raise ValueError("no defect-free four-bar with a fully turning crank among the searched "
                     "moving pivots: give moving= (and fixed=) yourself")
