"""A one-degree-of-freedom planar linkage: a driven crank and Assur dyads (docs/mechanisms.md).

A linkage is its *topology* (which links, which joints, in the order they are solved)
and its *values* (each length, offset, mass: a number or an array, named like the
four-bar's fields).  The topology refers to the values by name, so a kind of linkage (the
slider-crank, the inverted slider-crank, the Watt II and Stephenson III six-bars) is a
topology and a set of field names, and a sweep changes values, never the topology.

Links are numbered as the solve goes: 1 is the frame (its base at the origin O2, its
line along +x), 2 the crank (turning about O2, its pin at the end), and each dyad adds
two links, n and n + 1:

====== ================================= ==================== =========================
dyad   what it is                        link n               link n + 1
====== ================================= ==================== =========================
RRR    two links pinned to known points  P -> C (length lp)   Q -> C (length lq)
       P and Q and to each other at C
RRP    a rod from the known point P to   P -> C (length L)    the slider, base C, line
       a slider pinned at C that slides                       the guide's
       on a guide line of a known link
PRR    a slider on a guide, pinned at C  the slider, base C,  Q -> C (length L)
       to a rod from the known point Q   line the guide's
RPR    a block pinned at the known point the block, base P,   Q -> along the slide, at
       P sliding along a link pivoted at line link n + 1's    the perpendicular
       the known point Q                                      distance e from Q
====== ================================= ==================== =========================

Each link has a *base point* (where its centre of mass and its other points are placed
from: RG and ADEL, as for the four-bar) and a *line* (the angle ATHk).  Branch signs
("open" +1, "crossed" -1): RRR's C on the left of P -> Q; RRP's and PRR's C the further
of the two points along the guide; RPR's P ahead of Q along link n + 1 (the slide
position s > 0).  Joints and the force each reports (the pin forces' bodies as the
four-bar's: docs/conventions.md): the crank's pivot O2, the crank on the frame; a dyad's
outer pin, the dyad's link on the known link; RRR's inner pin C, link n on link n + 1; RRP
and PRR's pin C, the rod on the slider; a slide, the guide's force on the slider (normal
to the guide, ``FN``, +90 degrees from its line) and its couple (``MN``).

Units: lengths in in (or m), angles in degrees, weights in lb (in SI masses in kg),
moments of inertia about the centre of mass in in-lb-sec^2 (kg m^2), the crank speed in
rad/sec; every value may be an array broadcasting with the crank angles.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import Any, ClassVar

import numpy as np

from sielaff.mechanism import STANDARD_GRAVITY, field_unit

__all__ = ["PRR", "RPR", "RRP", "RRR", "Crank", "Guide", "Kind", "Linkage", "Pivot", "Point",
           "Topology", "check_values", "mass_fields"]

#: A value in a topology: the name of a field, or a constant.
Value = str | float


@dataclass(frozen=True)
class Pivot:
    """A point of the frame, ``(x, y)`` in the frame's axes [in or m] (O2 is the origin)."""

    name: str
    x: Value = 0.0
    y: Value = 0.0


@dataclass(frozen=True)
class Point:
    """A named point on moving link ``link``, placed as RG and ADEL place a centre of mass:
    ``r`` from the link's base point [in or m], ``angle`` from its line [deg], CCW +."""

    name: str
    link: int
    r: Value
    angle: Value = 0.0


@dataclass(frozen=True)
class Guide:
    """A guide line of link ``link`` (1: the frame): through the point ``r`` from the
    link's base point at ``at`` degrees from its line, along ``angle`` degrees from its line."""

    link: int = 1
    r: Value = 0.0
    at: Value = 90.0
    angle: Value = 0.0


@dataclass(frozen=True)
class Crank:
    """Link 2: it turns about O2 (the origin); its pin ``pin`` is ``length`` from O2."""

    length: Value = "R2"
    pin: str = "A"


@dataclass(frozen=True)
class RRR:
    """Links n (P -> C, length ``lp``) and n + 1 (Q -> C, length ``lq``), pinned at ``joint``."""

    p: str
    q: str
    joint: str
    lp: Value
    lq: Value


@dataclass(frozen=True)
class RRP:
    """Link n, a rod from the known point ``p`` (length ``length``) to the pin ``joint`` of
    link n + 1, a slider on ``guide``; ``slide`` labels the slide's outputs (S, VS, AS, FN,
    MN followed by the label)."""

    p: str
    joint: str
    length: Value
    guide: Guide
    slide: str = ""


@dataclass(frozen=True)
class PRR:
    """Link n, a slider on ``guide`` pinned at ``joint`` to link n + 1, a rod of length
    ``length`` from the known point ``q``."""

    guide: Guide
    joint: str
    q: str
    length: Value
    slide: str = ""


@dataclass(frozen=True)
class RPR:
    """Link n, a block pinned at the known point ``p``, sliding along link n + 1, which is
    pinned at the known point ``q``; the slide's line runs at the perpendicular distance
    ``offset`` from q (+ to the left of its direction)."""

    p: str
    q: str
    offset: Value = 0.0
    slide: str = ""


Dyad = RRR | RRP | PRR | RPR


@dataclass(frozen=True)
class Topology:
    """What a linkage is made of, in solve order: the frame's pivots besides O2, the
    crank, the dyads, the named points on moving links (a ternary link's third pin), and
    the names its outputs take instead of the generic ones (``names``: generic -> own,
    e.g. ``{"FO2": "FOA"}``: a vector's X, Y and direction follow)."""

    pivots: tuple[Pivot, ...] = ()
    crank: Crank = Crank()
    dyads: tuple[Dyad, ...] = ()
    points: tuple[Point, ...] = ()
    names: tuple[tuple[str, str], ...] = ()
    title: str = "linkage"
    #: each link's name, the frame's first ("frame", "crank", ...; default "link k")
    link_names: tuple[str, ...] = ()

    def link_name(self, k: int) -> str:
        """Link k's name (1 the frame)."""
        return self.link_names[k - 1] if k <= len(self.link_names) else \
            "frame" if k == 1 else "crank" if k == 2 else f"link{k}"

    @property
    def links(self) -> int:
        """The number of links, the frame included."""
        return 2 + 2 * len(self.dyads)

    def lengths(self) -> tuple[str, ...]:
        """The fields that are link lengths (> 0)."""
        out: list[Any] = [self.crank.length]
        for d in self.dyads:
            out += [d.lp, d.lq] if isinstance(d, RRR) else [] if isinstance(d, RPR) \
                else [d.length]
        return tuple(dict.fromkeys(v for v in out if isinstance(v, str)))

    def fields(self) -> tuple[str, ...]:
        """Every field the topology names, then each moving link's mass fields, then TH2D."""
        named: list[Any] = [self.crank.length]
        for p in self.pivots:
            named += [p.x, p.y]
        for d in self.dyads:
            if isinstance(d, RRR):
                named += [d.lp, d.lq]
            elif isinstance(d, RPR):
                named += [d.offset]
            else:
                named += [d.length, d.guide.r, d.guide.at, d.guide.angle]
        for pt in self.points:
            named += [pt.r, pt.angle]
        own = [v for v in named if isinstance(v, str)]
        return tuple(dict.fromkeys(own + list(mass_fields(self.links)) + ["TH2D"]))


def mass_fields(links: int) -> tuple[str, ...]:
    """W, ZI, RG, ADEL of each moving link 2 .. links (absent fields read 0)."""
    return tuple(f"{name}{k}" for k in range(2, links + 1) for name in ("W", "ZI", "RG", "ADEL"))


_MASSES = ("W", "ZI")


def check_values(topology: Topology, values: Mapping[str, Any], where: str,
                 units: str = "in-lb-sec") -> None:
    """ValueError in one line naming the first field that no linkage can have: not a
    finite number, a length not > 0, a weight or inertia below 0; or a unit system
    that is not one of sielaff's."""
    if units not in STANDARD_GRAVITY:
        raise ValueError(f"units = {units!r}: the unit systems are "
                         f"{', '.join(STANDARD_GRAVITY)}")
    lengths = set(topology.lengths())
    for name, value in values.items():
        if value is None:
            raise ValueError(f"{where}.{name} is missing: every field needs a value")
        try:
            v = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"{where}.{name} = {value!r} is not a number") from None
        if not np.all(np.isfinite(v)):
            raise ValueError(f"{where}.{name} = {_first(v, ~np.isfinite(v))} is not finite")
        if name in lengths and not np.all(v > 0.0):
            raise ValueError(f"{where}.{name} = {_first(v, ~(v > 0.0))}: a link's length "
                             "must be > 0")
        if name.rstrip("0123456789") in _MASSES and not np.all(v >= 0.0):
            raise ValueError(f"{where}.{name} = {_first(v, ~(v >= 0.0))}: weights and "
                             "moments of inertia cannot be negative")


def _first(v: Any, bad: Any) -> str:
    x = float(v) if v.ndim == 0 else float(v[np.unravel_index(np.argmax(bad), v.shape)])
    return f"{x:g}"


class Kind:
    """What every kind of linkage (a frozen dataclass of named fields and ``units``) has:
    its :data:`TOPOLOGY`, the spec's ``[linkage] kind`` (:data:`KIND`), each field's unit
    in the report's system (:data:`UNITS`), the fields that must be > 0 besides the
    topology's lengths (:data:`POSITIVE`), :meth:`replace` and :meth:`as_dict`."""

    TOPOLOGY: ClassVar[Topology]
    KIND: ClassVar[str]
    UNITS: ClassVar[dict[str, str]]
    #: where a spec gives each field: (table, key, sub-key or None) -> field
    SPEC_NAMES: ClassVar[dict[tuple[str, str, str | None], str]]
    POSITIVE: ClassVar[tuple[str, ...]] = ()
    units: str

    @classmethod
    def field_names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls) if f.name != "units")  # type: ignore[arg-type]

    def replace(self, **changes: Any) -> Any:
        """A copy with some fields changed (a field may become an array: a sweep)."""
        unknown = sorted(set(changes) - set(self.field_names()) - {"units"})
        if unknown:
            raise TypeError(f"{type(self).__name__} has no field {', '.join(unknown)} "
                            f"(fields: {' '.join(self.field_names())})")
        return dataclasses.replace(self, **changes)  # type: ignore[type-var]

    def as_dict(self) -> dict[str, Any]:
        """The fields by name (not the unit system)."""
        return {n: getattr(self, n) for n in self.field_names()}

    def check(self) -> None:
        """ValueError in one line naming the first field no such linkage can have."""
        where = type(self).__name__
        check_values(self.TOPOLOGY, self.as_dict(), where, self.units)
        for name in self.POSITIVE:
            v = np.asarray(getattr(self, name), dtype=float)
            if not np.all(v > 0.0):
                raise ValueError(f"{where}.{name} = {_first(v, ~(v > 0.0))} "
                                 f"{field_unit(name, self.UNITS[name], self.units)}: must "
                                 "be > 0")


@dataclass(frozen=True, eq=False)
class Linkage:
    """A one-degree-of-freedom linkage: a :class:`Topology` and its ``values``.

    Parameters
    ----------
    topology : Topology
        The frame's pivots, the crank, the dyads (RRR, RRP, PRR, RPR) and named points.
    values : mapping
        Every field the topology names [in or m, deg], each moving link's ``Wk`` [lb or
        kg], ``ZIk`` [in-lb-sec^2 or kg m^2], ``RGk`` [in or m] and ``ADELk`` [deg]
        (absent ones read 0) and ``TH2D`` [rad/sec]; numbers or arrays.
    units : {"in-lb-sec", "SI"}
        The unit system of the values.

    A field reads as an attribute (``linkage.R2``); :meth:`replace` changes some.
    """

    topology: Topology
    values: Mapping[str, Any] = field(default_factory=dict)
    units: str = "in-lb-sec"

    def __post_init__(self) -> None:
        full = {n: 0.0 for n in self.topology.fields()}
        unknown = sorted(set(self.values) - set(full))
        if unknown:
            raise TypeError(f"Linkage has no field {', '.join(unknown)} "
                            f"(fields: {' '.join(full)})")
        full.update(self.values)
        missing = [n for n in self.topology.fields() if n not in self.values
                   and not n.startswith(("W", "ZI", "RG", "ADEL"))]
        if missing:
            raise TypeError(f"Linkage: no value for {', '.join(missing)}")
        object.__setattr__(self, "values", full)

    def __getattr__(self, name: str) -> Any:
        values = self.__dict__.get("values", {})
        if name in values:
            return values[name]
        raise AttributeError(name)

    def as_dict(self) -> dict[str, Any]:
        """The values by name."""
        return dict(self.values)

    def replace(self, **fields: Any) -> Linkage:
        """A copy with some values changed (``units=`` too)."""
        units = fields.pop("units", self.units)
        return Linkage(self.topology, {**self.values, **fields}, units)

    def check(self) -> None:
        """ValueError in one line naming the first value no linkage can have."""
        check_values(self.topology, self.values, "Linkage", self.units)

    def __repr__(self) -> str:
        return f"Linkage({self.topology.title}, {dict(self.values)!r}, units={self.units!r})"
