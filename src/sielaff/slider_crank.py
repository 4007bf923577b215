"""The slider-crank: a crank O2-A, a connecting rod A-B and a slider pinned at B that
slides on a line parallel to +x at ``y = offset`` (docs/mechanisms.md draws it).

====== ================================================ ==============
name   meaning                                          unit
====== ================================================ ==============
W2-W4  weights of the crank, the rod and the slider     lb (SI: kg)
ZI2-3  moments of inertia of the crank and the rod,     in-lb-sec^2
       about their own centres of mass                  (SI: kg m^2)
R2     the crank O2-A                                   in (SI: m)
R3     the connecting rod A-B                           in (SI: m)
offset the slider's line: y = offset (the frame's x     in (SI: m)
       axis runs through O2, as O2-O4 for the four-bar)
ADEL2  angle of the crank's centre-of-mass line from    deg
ADEL3  O2->A, and of the rod's from A->B, CCW +
RG2    distance O2-G2, and A-G3                         in (SI: m)
RG3
TH2D   the crank's angular velocity, CCW +              rad/sec
====== ================================================ ==============

The slider is a point mass at B (it does not turn).  The names follow the four-bar's
(:mod:`sielaff.mechanism`): link 2 is the crank, 3 the rod, 4 the slider, 1 the frame.
Each field may be a numpy array that broadcasts against the crank angles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import replace as dataclasses_replace
from typing import Any

from sielaff.linkage import RRP, Crank, Guide, Topology
from sielaff.mechanism import STANDARD_GRAVITY, field_unit, plainly_valid

__all__ = ["FIELD_NAMES", "KIND", "SLIDER_EXAMPLE", "SPEC_NAMES", "TOPOLOGY", "UNITS",
           "SliderCrank", "Stroke", "full_turn_failure", "stroke", "validate_slider"]

FIELD_NAMES = ("W2", "W3", "W4", "ZI2", "ZI3", "R2", "R3", "offset", "ADEL2", "ADEL3",
               "RG2", "RG3", "TH2D")

#: The in-lb-sec unit of each field (quantities.unit gives the SI one).
UNITS = {"W2": "lb", "W3": "lb", "W4": "lb", "ZI2": "in-lb-sec^2", "ZI3": "in-lb-sec^2",
         "R2": "in", "R3": "in", "offset": "in", "ADEL2": "deg", "ADEL3": "deg",
         "RG2": "in", "RG3": "in", "TH2D": "rad/sec"}

#: The slider-crank as a linkage: the crank, then an RRP dyad (the rod A-B, link 3; the
#: slider at B, link 4) on the frame's line y = offset along +x.  Its outputs keep the
#: four-bar's names where they mean the same: FOA at O2.
TOPOLOGY = Topology(crank=Crank("R2", "A"),
                    dyads=(RRP("A", "B", "R3", Guide(1, "offset", 90.0, 0.0)),),
                    names=(("FO2", "FOA"),), title="slider-crank",
                    link_names=("frame", "crank", "rod", "slider"))

#: A spec's ``[linkage] kind`` for a slider-crank.
KIND = "slider-crank"

#: Where a spec gives each field: (section, key, sub-key or None) -> field name; the
#: tables and keys of the four-bar's spec, with the rod and the slider for its links.
SPEC_NAMES: dict[tuple[str, str, str | None], str] = {
    ("weights", "crank", None): "W2",
    ("weights", "rod", None): "W3",
    ("weights", "slider", None): "W4",
    ("inertia", "crank", None): "ZI2",
    ("inertia", "rod", None): "ZI3",
    ("lengths", "crank", None): "R2",
    ("lengths", "rod", None): "R3",
    ("lengths", "offset", None): "offset",
    ("mass_centres", "crank", "angle"): "ADEL2",
    ("mass_centres", "rod", "angle"): "ADEL3",
    ("mass_centres", "crank", "distance"): "RG2",
    ("mass_centres", "rod", "distance"): "RG3",
    ("drive", "speed", None): "TH2D",
}

_LENGTHS = ("R2", "R3")
_NONNEGATIVE = ("W2", "W3", "W4", "ZI2", "ZI3")


@dataclass(frozen=True)
class SliderCrank:
    """A slider-crank's parameters (see the module doc for names and units); ``units``
    is ``"in-lb-sec"`` (W a weight) or ``"SI"`` (W a mass)."""

    W2: Any
    W3: Any
    W4: Any
    ZI2: Any
    ZI3: Any
    R2: Any
    R3: Any
    offset: Any
    ADEL2: Any
    ADEL3: Any
    RG2: Any
    RG3: Any
    TH2D: Any
    units: str = "in-lb-sec"

    def replace(self, **fields: Any) -> SliderCrank:
        """A copy with some fields changed (a field may become an array: a sweep)."""
        unknown = sorted(set(fields) - set(FIELD_NAMES) - {"units"})
        if unknown:
            raise TypeError(f"SliderCrank has no field {', '.join(unknown)} "
                            f"(fields: {' '.join(FIELD_NAMES)})")
        return dataclasses_replace(self, **fields)

    def as_dict(self) -> dict[str, Any]:
        """The fields by name (not the unit system)."""
        return {n: getattr(self, n) for n in FIELD_NAMES}


# what every kind declares (sielaff.linkage.Kind), for the tools that enumerate them
SliderCrank.TOPOLOGY = TOPOLOGY  # type: ignore[attr-defined]
SliderCrank.KIND = KIND  # type: ignore[attr-defined]
SliderCrank.UNITS = UNITS  # type: ignore[attr-defined]
SliderCrank.SPEC_NAMES = SPEC_NAMES  # type: ignore[attr-defined]


#: An engine-sized example: a 2 in crank, an 8 in rod (ratio 4), no offset, 3000 rpm
#: (314.16 rad/sec), weights of a small single-cylinder engine's parts.
SLIDER_EXAMPLE = SliderCrank(W2=1.5, W3=1.0, W4=1.2, ZI2=0.002, ZI3=0.015, R2=2.0, R3=8.0,
                             offset=0.0, ADEL2=0.0, ADEL3=0.0, RG2=0.5, RG3=2.5,
                             TH2D=314.159)


def validate_slider(m: SliderCrank) -> None:
    """Raise ValueError in one line naming the first field ``m`` cannot have.

    Every field finite; R2 and R3 positive; weights and inertias not negative; and the
    rod must reach the slider's line somewhere: ``|offset| <= R2 + R3`` (else no crank
    angle assembles).  A rod that reaches it only over part of the revolution (``R3 <
    R2 + |offset|``) is a linkage whose crank rocks: ``analyze`` gives NaN where it
    cannot close (:func:`full_turn_failure` says why the crank cannot turn fully).
    """
    import numpy as np

    if m.units not in STANDARD_GRAVITY:
        raise ValueError(f"units = {m.units!r}: the unit systems are "
                         f"{', '.join(STANDARD_GRAVITY)}")
    values = {}
    for name in FIELD_NAMES:
        value = getattr(m, name)
        if plainly_valid(value, name in _LENGTHS, name in _NONNEGATIVE):
            values[name] = np.asarray(value)
            continue
        if value is None:
            raise ValueError(f"SliderCrank.{name} is missing: every field needs a value")
        try:
            v = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"SliderCrank.{name} = {value!r} is not a number") from None
        if not np.all(np.isfinite(v)):
            raise ValueError(f"SliderCrank.{name} = {_first(v, ~np.isfinite(v))} is not "
                             "finite")
        if name in _LENGTHS and not np.all(v > 0.0):
            raise ValueError(f"SliderCrank.{name} = {_first(v, ~(v > 0.0))} "
                             f"{field_unit(name, UNITS[name], m.units)}: the crank and the "
                             "rod must have a length > 0")
        if name in _NONNEGATIVE and not np.all(v >= 0.0):
            raise ValueError(f"SliderCrank.{name} = {_first(v, ~(v >= 0.0))} "
                             f"{field_unit(name, UNITS[name], m.units)}: weights and moments "
                             "of inertia cannot be negative")
        values[name] = v
    R2, R3, e = values["R2"], values["R3"], values["offset"]
    never = np.broadcast_to(np.abs(e) > R2 + R3, np.broadcast_shapes(e.shape, R2.shape,
                                                                      R3.shape))
    if np.any(never):
        i = np.unravel_index(np.argmax(never), never.shape) if never.ndim else ()
        pick = [float(np.broadcast_to(x, never.shape)[i]) for x in (e, R2, R3)]
        raise ValueError(f"SliderCrank.offset = {pick[0]:g}: |offset| > R2 + R3 = "
                         f"{pick[1] + pick[2]:g}, so the rod cannot reach the slider's line "
                         "at any crank angle")


def full_turn_failure(m: SliderCrank) -> str | None:
    """Why the crank of ``m`` (scalar fields) cannot turn a full revolution, or None:
    the rod must span the crank and the offset, ``R3 >= R2 + |offset|``."""
    R2, R3, e = float(m.R2), float(m.R3), float(m.offset)
    if R3 < R2 + abs(e):
        return (f"R3 = {R3:g} < R2 + |offset| = {R2 + abs(e):g}: the rod is shorter than "
                "the crank plus the offset, so the crank cannot turn a full revolution")
    return None


@dataclass(frozen=True)
class Stroke:
    """The dead centres of a slider-crank whose crank turns fully (open branch): XB [in
    or m] and THETA 2 [deg] at the outer one (crank and rod in line, extended) and the
    inner one (folded); the crank angles [deg] of the inward stroke (XB falling, the
    crank turning CCW from outer to inner) and of the outward one; ``time_ratio`` the
    longer over the shorter (1 with no offset)."""

    xb_outer: float
    xb_inner: float
    at_outer: float
    at_inner: float
    inward: float
    outward: float

    @property
    def length(self) -> float:
        return self.xb_outer - self.xb_inner

    @property
    def time_ratio(self) -> float:
        return max(self.inward, self.outward) / min(self.inward, self.outward)


def stroke(m: SliderCrank) -> Stroke:
    """The dead centres of ``m`` (scalar fields, a crank that turns fully) by their
    construction: at the outer one O2, A and B are in line with |O2 B| = R2 + R3, so
    XB = sqrt((R3 + R2)^2 - e^2) and THETA 2 = asin(e / (R2 + R3)); at the inner one A is
    on the far side of O2 with |O2 B| = R3 - R2, so XB = sqrt((R3 - R2)^2 - e^2) and
    THETA 2 = 180 + asin(e / (R3 - R2)) (e the offset).  ValueError if the crank cannot
    turn fully."""
    failure = full_turn_failure(m)
    if failure:
        raise ValueError(failure)
    R2, R3, e = float(m.R2), float(m.R3), float(m.offset)
    at_outer = math.degrees(math.asin(e / (R2 + R3))) % 360.0
    at_inner = 180.0 + math.degrees(math.asin(e / (R3 - R2))) if R3 > R2 else 180.0
    inward = (at_inner - at_outer) % 360.0
    return Stroke(math.sqrt((R3 + R2) ** 2 - e * e), math.sqrt(max((R3 - R2) ** 2 - e * e, 0.0)),
                  at_outer, at_inner, inward, 360.0 - inward)


def _first(v: Any, bad: Any) -> str:
    import numpy as np

    x = float(v) if v.ndim == 0 else float(v[np.unravel_index(np.argmax(bad), v.shape)])
    return f"{x:g}"
