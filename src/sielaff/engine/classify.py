"""Which kind of four-bar a mechanism is, with link 2 as the input and link 1 the frame.

Grashof: with s and l the shortest and longest of R1-R4 and p, q the others, a link
turns fully relative to its neighbours when ``s + l < p + q``; then the kind follows
from which link is shortest (the frame: double-crank; the crank: crank-rocker; the
coupler: double-rocker; the rocker: rocker-crank).  ``s + l > p + q`` is a
triple-rocker; ``s + l = p + q`` a change-point linkage, which can fold at its toggles.
A margin within :data:`~sielaff.mechanism.BOUNDARY` of s + l is taken as the equality
(punched lengths differ by far more; roundoff by far less).

The input's motion limits: the loop closes at THETA 2 only while
``|R3 - R4| <= |O4 - A| <= R3 + R4``, with ``|O4 - A|^2 = R1^2 + R2^2 - 2 R1 R2 cos th2``;
where a bound is crossed, link 2 meets a toggle (coupler and rocker in line) and
cannot pass.  Every quantity broadcasts over mechanism arrays.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.mechanism import BOUNDARY, Mechanism

__all__ = ["KINDS", "LinkageClass", "linkage_class"]

#: The kinds, as ``LinkageClass.kind`` names them.
KINDS = ("crank-rocker", "double-crank", "double-rocker", "rocker-crank", "triple-rocker",
         "change-point")


@dataclass(frozen=True)
class LinkageClass:
    """A mechanism's kind and what decides it (arrays for mechanism arrays).

    ``kind``: one of :data:`KINDS`.  ``grashof_sum``: s + l (length unit).
    ``grashof_margin``: (p + q) - (s + l), > 0 Grashof, < 0 not, ~0 a change point.
    ``toggles``: the THETA 2 (degrees, in [0, 360)) where link 2 meets a toggle, NaN where
    there is none: the last axis holds up to 4, sorted.  ``turns_fully``: whether link 2
    can make a whole revolution (no toggle, and the loop closes).  ``arcs`` (one
    mechanism): the arcs of THETA 2, (from, to) CCW in degrees, link 2 can swing over;
    one (0, 360) when it turns fully, none when the loop never closes.
    """

    kind: Any
    grashof_sum: Any
    grashof_margin: Any
    toggles: Any
    turns_fully: Any
    arcs: Any = None


def linkage_class(m: Mechanism) -> LinkageClass:
    """Classify ``m`` (see the module doc); fields may be arrays that broadcast."""
    R1, R2, R3, R4 = np.broadcast_arrays(*(np.asarray(getattr(m, n), dtype=float)
                                           for n in ("R1", "R2", "R3", "R4")))
    lengths = np.stack([R1, R2, R3, R4])  # frame, crank, coupler, rocker
    bad = ~(np.isfinite(lengths) & (lengths > 0.0))
    if np.any(bad):  # no kind is the answer for a length no linkage has
        k = np.unravel_index(int(np.argmax(bad)), bad.shape)
        raise ValueError(f"linkage_class: {('R1', 'R2', 'R3', 'R4')[k[0]]} = "
                         f"{float(lengths[k]):g}: a link length is a finite number > 0")
    s, lng = lengths.min(axis=0), lengths.max(axis=0)
    total = lengths.sum(axis=0)
    sl = s + lng
    margin = (total - sl) - sl  # p + q - (s + l)
    change = np.abs(margin) <= BOUNDARY * sl
    shortest = np.argmax(lengths == s, axis=0)  # first of frame, crank, coupler, rocker
    grashof_kind = np.choose(shortest, ("double-crank", "crank-rocker", "double-rocker",
                                        "rocker-crank"))
    kind = np.where(change, "change-point",
                    np.where(margin > 0, grashof_kind, "triple-rocker")).astype(object)
    # toggles of the input: cos th2 where |O4 - A| reaches R3 + R4 or |R3 - R4|
    ends: list[np.ndarray] = []
    with np.errstate(all="ignore"):
        for d in (R3 + R4, np.abs(R3 - R4)):
            c = (R1 * R1 + R2 * R2 - d * d) / (2.0 * R1 * R2)
            inside = np.abs(c) < 1.0
            a = np.degrees(np.arccos(np.where(inside, c, np.nan)))
            ends += [a, np.where(inside, 360.0 - a, np.nan)]
    toggles = np.sort(np.stack(ends, axis=-1), axis=-1)  # NaN last
    # no toggle inside: the loop closes everywhere or nowhere but where |O4 - A| touches
    # R3 + R4 or |R3 - R4| at 0 or 180 (a tangency): both THETA 2 = 0 (|O4 - A| = |R1 - R2|)
    # and 180 (R1 + R2) must close
    closes = (_closes(np.abs(R1 - R2), R3, R4) & _closes(R1 + R2, R3, R4))
    turns = ~np.any(np.isfinite(toggles), axis=-1) & closes
    if np.ndim(kind) == 0:
        return LinkageClass(str(kind), float(sl), float(margin), toggles, bool(turns),
                            _arcs(float(R1), float(R2), float(R3), float(R4), toggles))
    return LinkageClass(kind, sl, margin, toggles, turns, None)


def _closes(d, R3, R4):
    """Whether a triangle of sides d (= |O4 - A|), R3 and R4 exists."""
    return (np.abs(R3 - R4) <= d) & (d <= R3 + R4)


def _arcs(R1, R2, R3, R4, toggles) -> list[tuple[float, float]]:
    """The arcs between consecutive toggles whose middle assembles (see the module doc)."""
    t = [float(x) for x in toggles if np.isfinite(x)]
    if not t:  # everywhere or nowhere
        whole = _closes(abs(R1 - R2), R3, R4) and _closes(R1 + R2, R3, R4)
        return [(0.0, 360.0)] if whole else []
    out = []
    for a, b in zip(t, t[1:] + t[:1]):
        mid = np.radians(a + ((b - a) % 360.0) / 2.0)
        d = np.sqrt(R1 * R1 + R2 * R2 - 2.0 * R1 * R2 * np.cos(mid))
        if abs(R3 - R4) <= d <= R3 + R4:
            out.append((a, b))
    return out
