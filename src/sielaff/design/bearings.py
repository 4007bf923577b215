"""The four bearings over one revolution: the report's Fig. 14 and its oil grooves.

In:  a mechanism and its scene (``analyze``'s effect keywords), ``n`` positions.
Out: per pin (O2, A, B, O4) the peak load (lb or N) and where (THETA 2, degrees), and
     per member the pin joins: the load's direction relative to that member over the cycle
     (degrees CCW from the member's line; the frame's line is +x), the arcs of that
     relative direction never loaded (oil-groove candidates), and the load reversals.

The load on each member is the force the pin puts on it (docs/conventions.md):

    pin  members         force on the first         force on the second
    O2   frame, crank    FOA (2 on 1)               -FOA
    A    crank, coupler  FA32 (3 on 2)              -FA32
    B    coupler, rocker -FB34                      FB34 (3 on 4)
    O4   rocker, frame   -FOB                       FOB (4 on 1)

An arc never loaded is a range of directions, fixed in the member, that the load never
points along: between two positions of the sampled cycle the load is taken to sweep the
shorter way round (``n`` is large enough for that), unless it turns by more than
:data:`JUMP`: then the load has passed through zero and swept nothing. A load reversal
is a change of sign of the load's component along the member's line (tension to
compression of that member at that pin), counted around the closed cycle. Positions
where the load is zero to roundoff (below 1E-12 of the peak) point nowhere and load no
arc.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from sielaff.engine.analysis import analyze
from sielaff.engine.classify import linkage_class
from sielaff.engine.scene import Scene, scene_from
from sielaff.mechanism import Mechanism

__all__ = ["Member", "Pin", "bearings", "unloaded_arcs"]

#: pin -> (force name, sign on first member, first member, second member)
PINS = {
    "O2": ("FOA", 1.0, "frame", "crank"),
    "A": ("FA32", 1.0, "crank", "coupler"),
    "B": ("FB34", -1.0, "coupler", "rocker"),
    "O4": ("FOB", -1.0, "rocker", "frame"),
}
#: member -> the output giving its line's angle (None: the frame, along +x)
LINE = {"frame": None, "crank": "ATH2", "coupler": "ATH3", "rocker": "ATH4"}
SAMPLES = 3600
#: Between neighbouring samples a direction that turns more than this (degrees) has
#: passed through zero load (a reversal), sweeping none of the angles between.
JUMP = 30.0
#: Neighbouring swept intervals closer than this (degrees) touch: roundoff of the mod.
TOUCH = 1e-9
#: Loads below this fraction of the pin's peak point nowhere.
ZERO = 1e-12


@dataclass(frozen=True)
class Member:
    """One member's side of a pin: ``direction`` (degrees in [0, 360), relative to the
    member's line, NaN where the load is zero), ``unloaded`` arcs ((from, to) degrees,
    CCW), ``reversals`` (sign changes of the component along the member's line)."""

    name: str
    direction: np.ndarray
    unloaded: list[tuple[float, float]]
    reversals: int


@dataclass(frozen=True)
class Pin:
    """A pin: ``name`` (O2, A, B, O4), the listing's force ``force``, ``peak`` load (lb
    or N) at ``at`` (THETA 2, degrees), ``theta2`` and ``load`` (magnitude) over the cycle,
    and its two ``members``."""

    name: str
    force: str
    peak: float
    at: float
    theta2: np.ndarray
    load: np.ndarray
    members: tuple[Member, ...] = field(default=())


def unloaded_arcs(direction: np.ndarray) -> list[tuple[float, float]]:
    """The arcs (from, to), degrees CCW, that a direction sampled round a closed cycle
    never sweeps (the shorter way between neighbours; NaN samples and jumps past
    :data:`JUMP` break the sweep)."""
    d = np.asarray(direction, dtype=float)
    a, b = d, np.roll(d, -1)
    step = (b - a + 180.0) % 360.0 - 180.0
    # a jump past JUMP is the load passing through (near) zero, not sweeping round
    ok = np.isfinite(a) & np.isfinite(b) & (np.abs(step) <= JUMP)
    lo = np.where(step >= 0, a, a + step)[ok] % 360.0
    width = np.abs(step)[ok]
    isolated = np.isfinite(d) & ~(ok | np.roll(ok, 1))
    lo = np.concatenate([lo, d[isolated] % 360.0])
    width = np.concatenate([width, np.zeros(int(isolated.sum()))])
    if lo.size == 0:
        return [(0.0, 360.0)]
    if width.max() >= 360.0:
        return []
    # the covered intervals, and the same shifted one turn, merged along [0, 720)
    lo = np.concatenate([lo, lo + 360.0])
    hi = lo + np.concatenate([width, width])
    order = np.argsort(lo)
    merged: list[list[float]] = []
    for s, e in zip(lo[order], hi[order]):
        if merged and s <= merged[-1][1] + TOUCH:
            merged[-1][1] = max(merged[-1][1], e)
        else:
            merged.append([s, e])
    start = float(lo.min())
    gaps = [(float(e0 % 360.0), float(s1 % 360.0)) for (_, e0), (s1, _) in zip(merged, merged[1:])
            if start <= e0 < start + 360.0 and e0 < s1]
    return gaps


def _reversals(along: np.ndarray) -> int:
    s = np.sign(along[along != 0.0])
    if s.size < 2:
        return 0
    return int(np.count_nonzero(s != np.roll(s, -1)))


def bearings(mechanism: Mechanism, n: int = SAMPLES, *, scene: Scene | None = None,
             **keywords: Any) -> dict[str, Pin]:
    """The four pins of ``mechanism`` (one design, a crank that turns fully) over one
    revolution of ``n`` positions, in ``scene`` (or the Scene of ``analyze``'s keywords)."""
    sc = scene_from(scene, keywords, "bearings")
    if any(np.ndim(v) for v in mechanism.as_tuple()):
        raise ValueError("bearings: one design at a time (the mechanism's fields are arrays)")
    if not bool(linkage_class(mechanism).turns_fully):
        raise ValueError("the crank cannot make a whole revolution: no bearing cycle")
    th = np.arange(n) * (360.0 / n)
    want = ["ATH2", "ATH3", "ATH4"] + [p[0] + s for p in PINS.values() for s in ("X", "Y")]
    r = analyze(mechanism, th, want, scene=sc)
    pins = {}
    for pin, (name, sign, first, second) in PINS.items():
        fx, fy = r[name + "X"], r[name + "Y"]
        load = np.hypot(fx, fy)
        peak_i = int(np.argmax(load))
        peak = float(load[peak_i])
        zero = load <= ZERO * peak
        members = []
        for member, s in ((first, sign), (second, -sign)):
            line = np.zeros(n) if LINE[member] is None else r[LINE[member]]
            absolute = np.degrees(np.arctan2(s * fy, s * fx))
            rel = np.where(zero, np.nan, (absolute - line) % 360.0)
            along = np.where(zero, 0.0, s * (fx * np.cos(np.radians(line))
                                             + fy * np.sin(np.radians(line))))
            members.append(Member(member, rel, unloaded_arcs(rel), _reversals(along)))
        pins[pin] = Pin(pin, name, peak, float(th[peak_i]), th, load, tuple(members))
    return pins
