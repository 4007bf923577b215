"""Six-bar linkages of one degree of freedom: a four-bar (the report's O2, A, B, O4) and one
more RRR dyad pinned to the frame at O6 (docs/mechanisms.md draws them).

* **Watt II** (:class:`WattII`): the dyad is driven by link 4, the four-bar's rocker,
  through its third pin C: two four-bars in series, O2-A-B-O4 and O4-C-D-O6.
* **Stephenson III** (:class:`StephensonIII`): the dyad is driven by the coupler, link 3,
  through its third pin C (a coupler point).

====== ================================================ ==============
name   meaning                                          unit
====== ================================================ ==============
R1-R4  the four-bar's links, as the report's            in (SI: m)
RC     C from the link's base pin (O4 for Watt II, A    in (SI: m)
       for Stephenson III)
ADELC  C's angle from that link's line (O4->B, A->B)    deg
R5     link 5, C to D                                   in (SI: m)
R6     link 6, O6 to D                                  in (SI: m)
X6, Y6 the pivot O6 in the frame's axes                 in (SI: m)
Wk     each moving link's weight (k = 2 .. 6)           lb (SI: kg)
ZIk    its moment of inertia about its centre of mass   in-lb-sec^2
RGk    its centre of mass from its base pin (O2, A, O4, in (SI: m)
       C, O6)
ADELk  and its angle from the link's line               deg
TH2D   the crank's angular velocity, CCW +              rad/sec
====== ================================================ ==============

The branch is each dyad's (``Scene(branch=("open", "crossed"))``: B's, then D's); the
outputs are the linkage engine's, with the four-bar's names at O2 and O4 (FOA, FOB) and
FA32, FB34; FC54 (link 5 on link 4) or FC53, FD56, FO6 (link 6 on the frame).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

from sielaff.linkage import RRR, Crank, Kind, Pivot, Point, Topology

__all__ = ["STEPHENSON_EXAMPLE", "WATT_EXAMPLE", "StephensonIII", "WattII"]

_UNITS = {"R1": "in", "R2": "in", "R3": "in", "R4": "in", "RC": "in", "ADELC": "deg",
          "R5": "in", "R6": "in", "X6": "in", "Y6": "in", "TH2D": "rad/sec"}
for _k in range(2, 7):
    _UNITS.update({f"W{_k}": "lb", f"ZI{_k}": "in-lb-sec^2", f"RG{_k}": "in",
                   f"ADEL{_k}": "deg"})


_LINKS = ("frame", "crank", "coupler", "rocker", "link5", "link6")


def _topology(on: int, title: str) -> Topology:
    return Topology(pivots=(Pivot("O4", "R1", 0.0), Pivot("O6", "X6", "Y6")),
                    crank=Crank("R2", "A"),
                    dyads=(RRR("A", "O4", "B", "R3", "R4"), RRR("C", "O6", "D", "R5", "R6")),
                    points=(Point("C", on, "RC", "ADELC"),),
                    names=(("FO2", "FOA"), ("FO4", "FOB")), title=title,
                    link_names=_LINKS)


@dataclass(frozen=True)
class _SixBar(Kind):
    R1: Any
    R2: Any
    R3: Any
    R4: Any
    RC: Any
    ADELC: Any
    R5: Any
    R6: Any
    X6: Any
    Y6: Any
    TH2D: Any
    W2: Any = 0.0
    W3: Any = 0.0
    W4: Any = 0.0
    W5: Any = 0.0
    W6: Any = 0.0
    ZI2: Any = 0.0
    ZI3: Any = 0.0
    ZI4: Any = 0.0
    ZI5: Any = 0.0
    ZI6: Any = 0.0
    RG2: Any = 0.0
    RG3: Any = 0.0
    RG4: Any = 0.0
    RG5: Any = 0.0
    RG6: Any = 0.0
    ADEL2: Any = 0.0
    ADEL3: Any = 0.0
    ADEL4: Any = 0.0
    ADEL5: Any = 0.0
    ADEL6: Any = 0.0
    units: str = "in-lb-sec"

    UNITS: ClassVar[dict[str, str]] = _UNITS
    POSITIVE: ClassVar[tuple[str, ...]] = ("R1",)
    SPEC_NAMES: ClassVar[dict[tuple[str, str, str | None], str]] = {
        **{("weights", n, None): f"W{k}" for k, n in enumerate(_LINKS[1:], 2)},
        **{("inertia", n, None): f"ZI{k}" for k, n in enumerate(_LINKS[1:], 2)},
        ("lengths", "frame", None): "R1",
        **{("lengths", n, None): f"R{k}" for k, n in enumerate(_LINKS[1:], 2)},
        ("points", "C", "distance"): "RC", ("points", "C", "angle"): "ADELC",
        ("pivots", "O6", "x"): "X6", ("pivots", "O6", "y"): "Y6",
        **{("mass_centres", n, sub): f"{field}{k}" for k, n in enumerate(_LINKS[1:], 2)
           for sub, field in (("distance", "RG"), ("angle", "ADEL"))},
        ("drive", "speed", None): "TH2D"}


@dataclass(frozen=True)
class WattII(_SixBar):
    """A Watt II six-bar's fields (the module doc): C is on link 4, placed from O4."""

    TOPOLOGY: ClassVar[Topology] = _topology(4, "Watt II six-bar")
    KIND: ClassVar[str] = "watt"


@dataclass(frozen=True)
class StephensonIII(_SixBar):
    """A Stephenson III six-bar's fields (the module doc): C is on link 3, placed from A."""

    TOPOLOGY: ClassVar[Topology] = _topology(3, "Stephenson III six-bar")
    KIND: ClassVar[str] = "stephenson"


_MASSES = dict(W2=1.0, W3=2.0, W4=2.5, W5=1.5, W6=2.0, ZI2=0.005, ZI3=0.06, ZI4=0.05,
               ZI5=0.03, ZI6=0.04, RG2=1.0, RG3=6.0, RG4=5.0, RG5=4.0, RG6=5.0)

#: A Watt II: the report's four-bar (R1..R4 = 12, 4, 16, 12 in) drives, through C on its
#: rocker 8 in from O4 at 30 deg, a second four-bar O4-C-D-O6.
WATT_EXAMPLE = WattII(R1=12.0, R2=4.0, R3=16.0, R4=12.0, RC=8.0, ADELC=30.0, R5=10.0,
                      R6=9.0, X6=4.0, Y6=14.0, TH2D=200.0, ADEL3=0.0, **_MASSES)

#: A Stephenson III: the report's four-bar's coupler point C (10 in from A at 25 deg)
#: drives a dyad to O6.
STEPHENSON_EXAMPLE = StephensonIII(R1=12.0, R2=4.0, R3=16.0, R4=12.0, RC=10.0, ADELC=25.0,
                                   R5=12.0, R6=10.0, X6=2.0, Y6=18.0, TH2D=200.0,
                                   **_MASSES)
