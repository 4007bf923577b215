"""The inverted slider-crank: the crank's pin A carries a block (link 3) that slides along
link 4, which turns about O4 (the crank-shaper's slotted lever, the Whitworth quick
return; docs/mechanisms.md draws it).

====== ================================================ ==============
name   meaning                                          unit
====== ================================================ ==============
W2-W4  weights of the crank, the block and link 4       lb (SI: kg)
ZI2-4  moments of inertia about their centres of mass   in-lb-sec^2
                                                        (SI: kg m^2)
R1     O2 to O4, along +x (the frame's line)            in (SI: m)
R2     the crank O2-A                                   in (SI: m)
offset the slide's line from O4, + to the left of its   in (SI: m)
       direction (0: the line runs through O4)
RG2-4  O2 to G2, A to G3 (along link 4's line), O4 to   in (SI: m)
       G4
ADEL2-4 each centre of mass's angle from its link's     deg
       line (the crank's O2->A, the block's and link
       4's the slide's direction O4 -> A)
TH2D   the crank's angular velocity, CCW +              rad/sec
====== ================================================ ==============

Outputs (the linkage engine's, :mod:`sielaff.linkage`): ATH4, TH4D, TH4DD (link 4, the
block turns with it), S, VS, AS (A's position along link 4 from O4's foot, its rate and
acceleration), FA32 (the block on the crank at A), FN and MN (link 4's force on the
block, along the slide's normal, and its couple), FOB (link 4 on the frame at O4), FOA,
TORQ, SHAK.  With R2 < R1 link 4 rocks (the crank-shaper) and :func:`quick_return` gives
its time ratio by construction; with R2 > R1 it turns fully (the Whitworth).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from sielaff.linkage import RPR, Crank, Kind, Pivot, Topology

__all__ = ["INVERTED_EXAMPLE", "InvertedSliderCrank", "QuickReturn", "full_turn_failure",
           "quick_return"]


@dataclass(frozen=True)
class InvertedSliderCrank(Kind):
    """An inverted slider-crank's fields (see the module doc for names and units)."""

    W2: Any
    W3: Any
    W4: Any
    ZI2: Any
    ZI3: Any
    ZI4: Any
    R1: Any
    R2: Any
    offset: Any
    ADEL2: Any
    ADEL3: Any
    ADEL4: Any
    RG2: Any
    RG3: Any
    RG4: Any
    TH2D: Any
    units: str = "in-lb-sec"

    TOPOLOGY: ClassVar[Topology] = Topology(
        pivots=(Pivot("O4", "R1", 0.0),), crank=Crank("R2", "A"),
        dyads=(RPR("A", "O4", "offset"),), names=(("FO2", "FOA"), ("FO4", "FOB")),
        title="inverted slider-crank", link_names=("frame", "crank", "block", "lever"))
    KIND: ClassVar[str] = "inverted-slider-crank"
    UNITS: ClassVar[dict[str, str]] = {
        "W2": "lb", "W3": "lb", "W4": "lb", "ZI2": "in-lb-sec^2", "ZI3": "in-lb-sec^2",
        "ZI4": "in-lb-sec^2", "R1": "in", "R2": "in", "offset": "in", "ADEL2": "deg",
        "ADEL3": "deg", "ADEL4": "deg", "RG2": "in", "RG3": "in", "RG4": "in",
        "TH2D": "rad/sec"}
    POSITIVE: ClassVar[tuple[str, ...]] = ("R1",)
    SPEC_NAMES: ClassVar[dict[tuple[str, str, str | None], str]] = {
        **{("weights", n, None): f"W{k}" for k, n in ((2, "crank"), (3, "block"), (4, "lever"))},
        **{("inertia", n, None): f"ZI{k}" for k, n in ((2, "crank"), (3, "block"),
                                                       (4, "lever"))},
        ("lengths", "frame", None): "R1", ("lengths", "crank", None): "R2",
        ("lengths", "offset", None): "offset",
        **{("mass_centres", n, sub): f"{field}{k}"
           for k, n in ((2, "crank"), (3, "block"), (4, "lever"))
           for sub, field in (("distance", "RG"), ("angle", "ADEL"))},
        ("drive", "speed", None): "TH2D"}


#: A crank-shaper: a 4 in crank 10 in from the slotted lever's pivot, a 24 in lever.
INVERTED_EXAMPLE = InvertedSliderCrank(
    W2=2.0, W3=0.5, W4=6.0, ZI2=0.01, ZI3=0.001, ZI4=0.75, R1=10.0, R2=4.0, offset=0.0,
    ADEL2=0.0, ADEL3=0.0, ADEL4=0.0, RG2=2.0, RG3=0.0, RG4=12.0, TH2D=10.0)


def full_turn_failure(m: InvertedSliderCrank) -> str | None:
    """Why the crank of ``m`` (scalar fields) cannot turn a full revolution, or None.

    A's distance from O4 runs from |R1 - R2| to R1 + R2; the slide's line reaches A only
    where that distance is at least |offset|, and at exactly |offset| link 4 is square to
    O4 -> A and the slide's position passes 0 (a dead point).  So the crank turns fully
    when |R1 - R2| > |offset|."""
    R1, R2, e = float(m.R1), float(m.R2), float(m.offset)
    if abs(R1 - R2) <= abs(e):
        return (f"|R1 - R2| = {abs(R1 - R2):g} <= |offset| = {abs(e):g}: the crank's pin "
                "comes within the offset of O4, so the crank cannot turn a full revolution")
    return None


@dataclass(frozen=True)
class QuickReturn:
    """A rocking link 4's extremes: the crank angles [deg] where it turns back, the crank's
    turn [deg] from the first to the second (CCW) and back, and their ratio (the longer
    over the shorter: the quick-return's time ratio at constant crank speed)."""

    at: tuple[float, float]
    forward: float
    back: float

    @property
    def time_ratio(self) -> float:
        return max(self.forward, self.back) / min(self.forward, self.back)


def quick_return(m: InvertedSliderCrank) -> QuickReturn:
    """Link 4's extremes by construction (scalar fields, R2 < R1: a rocking link 4).

    At an extreme link 4 stops turning, so A's velocity (square to the crank) lies along
    the slide: the slide is square to O2 -> A.  Projecting A - O4 = s u + e u^ on the crank's
    direction a = (cos th2, sin th2), with u^ = -+a there, gives R2 - R1 cos th2 = -+e:
    cos th2 = (R2 +- e) / R1.  Of those four angles the two where the slide's position s is
    positive (the open branch) are the extremes.  ValueError if link 4 does not rock."""
    R1, R2, e = float(m.R1), float(m.R2), float(m.offset)
    failure = full_turn_failure(m)
    if failure or R2 >= R1:
        raise ValueError(failure or f"R2 = {R2:g} >= R1 = {R1:g}: link 4 turns fully (a "
                         "Whitworth), it has no extremes")
    found = []
    for c in ((R2 + e) / R1, (R2 - e) / R1):
        if abs(c) > 1.0:
            continue
        for th in (math.acos(c), -math.acos(c)):
            ax, ay = R2 * math.cos(th) - R1, R2 * math.sin(th)  # A - O4
            ux, uy = -math.sin(th), math.cos(th)  # the slide square to the crank
            for sgn in (1.0, -1.0):
                s = ax * sgn * ux + ay * sgn * uy
                off = -(ax * sgn * uy) + ay * sgn * ux  # (A - O4) . u^ = e
                if s > 0.0 and abs(off - e) <= 1e-12 * (R1 + R2 + abs(e)):
                    found.append(math.degrees(th) % 360.0)
    found = sorted(set(round(x, 12) for x in found))
    if len(found) != 2:
        raise ValueError(f"no two extremes found for R1 = {R1:g}, R2 = {R2:g}, offset = {e:g}")
    forward = (found[1] - found[0]) % 360.0
    return QuickReturn((found[0], found[1]), forward, 360.0 - forward)
