"""Crank-rockers for a rocker swing and a time ratio (the quick-return problem).

The rocker swings through ``swing`` = phi degrees between B1 and B2 (|O4 B1| = |O4 B2| =
R4).  Its two extreme positions are where the crank and coupler lie in one line: B1 with
them stretched out (|O2 B1| = R3 + R2), B2 folded (|O2 B2| = R3 - R2).  Between those two
crank positions the crank turns 180 + delta degrees one way and 180 - delta the other, so
the time ratio Q (the slow stroke's crank angle over the quick one's) fixes

    delta = 180 (Q - 1) / (Q + 1)    [deg],

the angle B1 O2 B2.  With the chord c = |B1 B2| = 2 R4 sin(phi / 2), d1 = |O2 B1| and
d2 = |O2 B2|, the triangle O2 B1 B2 gives c^2 = d1^2 + d2^2 - 2 d1 d2 cos delta, hence

    d1 = d2 cos delta + sqrt(c^2 - d2^2 sin^2 delta),   R2 = (d1 - d2)/2,  R3 = (d1 + d2)/2,

and O2 is the intersection of the circles (B1, d1) and (B2, d2).  **The free choice** is
k = d2 / R4 = (R3 - R2) / R4 together with the side of the chord B1 B2 that O2 lies on
(``"near"``: O4's side, ``"far"``: the other; the two sides are the two circles through
B1 and B2 on which B1 B2 subtends delta, and they coincide when Q = 1): each side is a
one-parameter family.  Not every k gives a crank-rocker: the members are the k for which
the linkage is a Grashof crank-rocker whose two extreme positions lie on one branch (else
the rocker swings between other positions); :attr:`CrankRockerFamily.intervals` lists
them.  Every member meets the swing and the time ratio (the construction is exact; the
tests re-analyse each to 1E-9).  The choice of k trades the transmission angle against
the link proportions; :attr:`CrankRockerFamily.best` is the member whose minimum
transmission angle (over a turn, min(GAMMA, 180 - GAMMA), reached with the crank along
the frame, THETA 2 = 0 or 180) is largest.

This follows the classical two-position construction with a quick return (e.g. Norton,
*Design of Machinery*, ch. 3; Shigley and Uicker, *Theory of Machines and Mechanisms*),
written as closed-form algebra instead of a drawing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from sielaff.mechanism import BOUNDARY, Mechanism
from sielaff.synthesis.common import branch_name, mechanism_from_lengths, side_of

__all__ = ["CrankRocker", "CrankRockerFamily", "crank_rocker"]

SIDES = ("near", "far")
#: Members whose computed swing or time ratio miss by more than this (relative) are not
#: members (the extreme positions then lie on two branches); exact members miss by ~1E-15.
_MEMBER_TOL = 1e-9


@dataclass(frozen=True)
class CrankRocker:
    """One member of the family.

    ``mechanism``: the linkage (masses from :func:`~sielaff.synthesis.masses`).
    ``branch``: the engine's branch (``"open"`` or ``"crossed"``) its construction is on
    (a crank-rocker's two branches are mirror images: both have the same swing and
    time ratio).  ``k`` [-] and ``side``: the free choice (module doc).
    ``toggles``: THETA 2 [deg] of the stretched (B1) and folded (B2) positions in the
    engine's frame; ``rocker``: THETA 4 [deg] there.  ``swing`` [deg] and ``time_ratio``
    [-] as computed from the lengths; ``min_transmission`` [deg].
    """

    mechanism: Mechanism
    branch: str
    k: float
    side: str
    toggles: tuple[float, float]
    rocker: tuple[float, float]
    swing: float
    time_ratio: float
    min_transmission: float


@dataclass(frozen=True)
class CrankRockerFamily:
    """The family of crank-rockers for one swing [deg] and time ratio [-] (module doc).

    ``delta`` [deg]: the angle B1 O2 B2.  ``intervals``: ``{side: [(k_lo, k_hi), ...]}``,
    the ranges of k [-] that give members.  ``best``: the member with the largest minimum
    transmission angle.  ``member(k, side)`` builds any member.
    """

    swing: float
    time_ratio: float
    delta: float
    rocker_length: float
    th2d: float
    units: str
    intervals: dict = field(default_factory=dict)
    best: CrankRocker | None = None

    def member(self, k: float, side: str = "near") -> CrankRocker:
        """The member for ``k`` = (R3 - R2)/R4 [-] and ``side``; ValueError if that choice
        gives no crank-rocker with this swing and time ratio."""
        m = _member(self.swing, self.delta, self.time_ratio, float(k), side,
                    self.rocker_length, self.th2d, self.units)
        if isinstance(m, str):
            raise ValueError(m)
        return m

    def members(self, n: int = 9) -> list[CrankRocker]:
        """``n`` members spread over each interval of each side (its ends left out)."""
        out = []
        for side, spans in self.intervals.items():
            for lo, hi in spans:
                for k in lo + (hi - lo) * (np.arange(n) + 0.5) / n:
                    m = _member(self.swing, self.delta, self.time_ratio, float(k), side,
                                self.rocker_length, self.th2d, self.units)
                    if not isinstance(m, str):
                        out.append(m)
        return out


def crank_rocker(swing: float, time_ratio: float, *, rocker: float = 1.0, th2d: float = 1.0,
                 units: str = "in-lb-sec", k_max: float = 10.0) -> CrankRockerFamily:
    """The crank-rockers whose rocker swings ``swing`` degrees with time ratio
    ``time_ratio``.

    Parameters
    ----------
    swing : float
        The rocker's swing [deg], 0 < swing < 180.
    time_ratio : float
        The slow stroke's crank angle over the quick one's [-], 1 <= Q (Q = 1: equal
        strokes); delta = 180 (Q-1)/(Q+1) must stay below 180 - swing... (checked).
    rocker : float
        R4 [length unit], which sets the scale.
    th2d : float
        The crank speed [rad/sec] put in each mechanism (its sign picks which stroke is
        the slow one: the crank arc from B1's toggle to B2's taken CCW is
        ``CrankRocker.toggles``' difference).
    units : str
        The mechanism's unit system (``"in-lb-sec"`` or ``"SI"``).
    k_max : float
        [-] Where the search of k stops (links up to about ``k_max`` R4 long).  For Q > 1
        the triangle O2 B1 B2 also bounds k (k <= c / (R4 sin delta)); for Q = 1 nothing
        does: the minimum transmission angle keeps improving towards 90 - swing/2 as the
        coupler and frame grow, so ``best`` is then the member at ``k_max``.

    Raises ValueError with one line when there is no such crank-rocker.
    """
    swing, Q = float(swing), float(time_ratio)
    if not (math.isfinite(swing) and 0.0 < swing < 180.0):
        raise ValueError(f"swing = {swing:g} deg: a crank-rocker's rocker swings through more "
                         "than 0 and less than 180 deg")
    if not (math.isfinite(Q) and Q >= 1.0):
        raise ValueError(f"time ratio = {Q:g}: it is the slow stroke's crank angle over the "
                         "quick one's, 1 or more")
    if not (math.isfinite(rocker) and rocker > 0):
        raise ValueError(f"rocker = {rocker:g}: the rocker's length must be positive")
    delta = 180.0 * (Q - 1.0) / (Q + 1.0)
    intervals, best = {}, None
    if not (math.isfinite(k_max) and k_max > 0):
        raise ValueError(f"k_max = {k_max:g}: it must be positive")
    kmax = min(_k_max(swing, delta), float(k_max))
    for side in SIDES if delta > 0.0 else SIDES[:1]:  # Q = 1: the two sides coincide
        ks = np.linspace(0.0, kmax, 801)[1:]
        ok = np.array([not isinstance(_member(swing, delta, Q, float(k), side, 1.0, 1.0,
                                              units, masses=False), str) for k in ks])
        spans = []
        for a, b in _runs(ok):
            lo = _edge(ks[a - 1] if a > 0 else 0.0, ks[a], side, swing, delta, Q, units)
            hi = _edge(ks[b + 1] if b + 1 < len(ks) else kmax, ks[b], side, swing, delta, Q,
                       units)
            spans.append((lo, hi))
            k = _argmax_transmission(lo, hi, side, swing, delta, Q, units)
            m = _member(swing, delta, Q, k, side, float(rocker), float(th2d), units)
            if not isinstance(m, str) and (best is None
                                           or m.min_transmission > best.min_transmission):
                best = m
        intervals[side] = spans
    if best is None:
        raise ValueError(f"swing = {swing:g} deg with time ratio {Q:g} (delta = {delta:.6g} "
                         "deg): no crank-rocker has both (try a smaller swing or time ratio)")
    return CrankRockerFamily(swing, Q, delta, float(rocker), float(th2d), units,
                             intervals, best)


def _k_max(swing: float, delta: float) -> float:
    """The largest k for which the triangle O2 B1 B2 closes (sqrt argument >= 0)."""
    c = 2.0 * math.sin(math.radians(swing) / 2.0)
    s = math.sin(math.radians(delta))
    return c / s if s > 0.0 else math.inf


def _runs(ok: np.ndarray) -> list[tuple[int, int]]:
    out, start = [], None
    for i, v in enumerate(ok):
        if v and start is None:
            start = i
        if not v and start is not None:
            out.append((start, i - 1))
            start = None
    if start is not None:
        out.append((start, len(ok) - 1))
    return out


def _edge(bad: float, good: float, side, swing, delta, Q, units) -> float:
    """Bisection to the edge of the valid k between ``bad`` and ``good``."""
    for _ in range(60):
        mid = 0.5 * (bad + good)
        if isinstance(_member(swing, delta, Q, mid, side, 1.0, 1.0, units, masses=False), str):
            bad = mid
        else:
            good = mid
    return good


def _argmax_transmission(lo, hi, side, swing, delta, Q, units) -> float:
    """Golden-section search of the minimum transmission angle over [lo, hi] after a grid
    (the grid picks the bracket, so a non-unimodal curve still gives its best grid cell)."""
    def mu(k):
        m = _member(swing, delta, Q, k, side, 1.0, 1.0, units, masses=False)
        return -1.0 if isinstance(m, str) else m.min_transmission

    ks = np.linspace(lo, hi, 65)
    vals = [mu(float(k)) for k in ks]
    i = int(np.argmax(vals))
    a, b = float(ks[max(i - 1, 0)]), float(ks[min(i + 1, len(ks) - 1)])
    g = (math.sqrt(5.0) - 1.0) / 2.0
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = mu(c), mu(d)
    for _ in range(80):
        if fc >= fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = mu(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = mu(d)
    best = max((vals[i], float(ks[i])), (fc, c), (fd, d))
    return best[1]


def _member(swing, delta, Q, k, side, R4, th2d, units, masses=True) -> CrankRocker | str:
    """The member for (k, side), or why there is none (one line)."""
    if side not in SIDES:
        return f"side = {side!r}: it is one of {', '.join(SIDES)}"
    if not (math.isfinite(k) and k > 0.0):
        return f"k = {k:g}: (R3 - R2)/R4 must be positive"
    p, dl = math.radians(swing), math.radians(delta)
    c, h = 2.0 * R4 * math.sin(p / 2.0), R4 * math.cos(p / 2.0)
    d2 = k * R4
    disc = c * c - (d2 * math.sin(dl)) ** 2
    if disc < 0.0:
        return f"k = {k:g}: the triangle O2 B1 B2 does not close (k > {_k_max(swing, delta):.6g})"
    d1 = d2 * math.cos(dl) + math.sqrt(disc)
    if not d1 > d2:
        return f"k = {k:g}: gives no crank (R3 + R2 <= R3 - R2)"
    # construction frame: O4 at the origin, B1 = (-c/2, h), B2 = (c/2, h)
    # the angle at B1 is opposite the shorter side d2, so acute: sin from the law of sines
    # (exactly 0 when delta = 0, where O2 lies on the chord's line)
    sb = d2 * math.sin(dl) / c
    xb, yb = d1 * math.sqrt(max(1.0 - sb * sb, 0.0)), d1 * sb
    sgn = -1.0 if side == "near" else 1.0  # O4 lies below the chord
    o2 = np.array([-c / 2.0 + xb, h + sgn * yb])
    R1 = float(np.hypot(*o2))
    R2, R3 = (d1 - d2) / 2.0, (d1 + d2) / 2.0
    # into the engine's frame: O2 at the origin, O4 on +x
    ang = math.atan2(-o2[1], -o2[0])
    rot = np.array([[math.cos(ang), math.sin(ang)], [-math.sin(ang), math.cos(ang)]])
    b1 = rot @ (np.array([-c / 2.0, h]) - o2)
    b2 = rot @ (np.array([c / 2.0, h]) - o2)
    a1 = R2 * b1 / np.hypot(*b1)       # stretched: A between O2 and B1
    a2 = -R2 * b2 / np.hypot(*b2)      # folded: A opposite B2
    s1 = side_of(a1[0], a1[1], R1, 0.0, b1[0], b1[1])
    s2 = side_of(a2[0], a2[1], R1, 0.0, b2[0], b2[1])
    if not (s1 * s2 > 0.0):
        return f"k = {k:g} ({side}): the two extreme positions lie on different branches"
    bare = Mechanism(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, R1, R2, R3, R4, 0.0, 0.0, 0.0, 0.0, 0.0,
                     0.0, th2d, units)
    # Grashof with the crank shortest (linkage_class's test, its BOUNDARY margin; written
    # out here because the search calls this thousands of times)
    lng = max(R1, R3, R4)
    margin = (R1 + R3 + R4 - lng) - (R2 + lng)
    if not (R2 < min(R1, R3, R4) and margin > BOUNDARY * (R2 + lng)):
        return f"k = {k:g} ({side}): not a crank-rocker (Grashof with the crank shortest)"
    t1 = math.degrees(math.atan2(a1[1], a1[0])) % 360.0
    t2 = math.degrees(math.atan2(a2[1], a2[0])) % 360.0
    r1 = math.degrees(math.atan2(b1[1], b1[0] - R1))
    r2 = math.degrees(math.atan2(b2[1], b2[0] - R1))
    got_swing = abs((r1 - r2 + 180.0) % 360.0 - 180.0)
    arc = (t2 - t1) % 360.0
    got_q = max(arc, 360.0 - arc) / min(arc, 360.0 - arc)
    if abs(got_swing - swing) > _MEMBER_TOL * 180.0 or abs(got_q - Q) > _MEMBER_TOL * Q:
        return f"k = {k:g} ({side}): misses the swing or the time ratio"
    m = mechanism_from_lengths(R1, R2, R3, R4, th2d=th2d, units=units) if masses else bare
    return CrankRocker(m, branch_name(s1), float(k), side, (t1, t2), (r1, r2), got_swing, got_q,
                       min_transmission(R1, R2, R3, R4))


def min_transmission(R1: float, R2: float, R3: float, R4: float) -> float:
    """The smallest of min(GAMMA, 180 - GAMMA) [deg] over a turn of a crank-rocker: GAMMA is
    extreme with the crank along the frame (|O4 - A| = R1 - R2 or R1 + R2)."""
    out = 90.0
    for L in (R1 - R2, R1 + R2):
        cg = (R3 * R3 + R4 * R4 - L * L) / (2.0 * R3 * R4)
        g = math.degrees(math.acos(min(1.0, max(-1.0, cg))))
        out = min(out, g, 180.0 - g)
    return out
