"""The four bearings over one revolution: the report's Fig. 14 and its oil grooves.

In:  a mechanism and its scene (``analyze``'s effect keywords), ``n`` positions to start
     from, and ``threshold``, a fraction of each pin's peak load.
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

A load below ``threshold`` times the pin's peak load (default :data:`THRESHOLD`, 5 %;
docs/design.md says why) does not count as loading a side: its direction is NaN.  An
arc never loaded is then a range of directions, fixed in the member, that no load at or
above the threshold points along.  Between two neighbouring positions the load is taken
to sweep the shorter way round; so that this holds whatever ``n`` is, the cycle is
refined by bisection where a direction turns by more than :data:`STEP` between
neighbours, and where the load crosses the threshold, until the turn is below
:data:`STEP` and the crossing is located to :data:`CROSSING` degrees of THETA 2.
Above the threshold the direction turns at most ``|dF/dTHETA2| / (threshold * peak)``
radians per radian, so the refinement ends and the arcs converge as ``n`` grows.  A
turn still larger than :data:`JUMP` once the interval is :data:`SMALLEST` wide (only
with ``threshold = 0``) is the load passing through zero, sweeping nothing.  A load
reversal is a change of sign of the load's component along the member's line (tension
to compression of that member at that pin) among the positions loaded above the
threshold, counted around the closed cycle.

Another kind of linkage (a slider-crank, an inverted slider-crank, a six-bar, any
``Linkage``) has its own pins (:func:`pin_table`): each pin of its topology, named by its
point, whose output F reports the force of link ``by`` on link ``on``; its members are the
two links in link order (the frame, the crank, link 3, ...), the force on ``on`` being F
and on ``by`` -F, each member's line its ATHk (the frame's +x).  A slide's guide force is
not a pin's and is left out.  Its crank must turn fully by its model's ``full_turn``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from sielaff.design.kinds import is_four_bar, kind_name, pins, scene_of_kind, turn_failures
from sielaff.engine.analysis import analyze
from sielaff.engine.classify import linkage_class
from sielaff.engine.scene import Scene, scene_from

__all__ = ["Member", "Pin", "bearings", "pin_table", "unloaded_arcs"]

#: pin -> (force name, sign on first member, first member, second member)
PINS = {
    "O2": ("FOA", 1.0, "frame", "crank"),
    "A": ("FA32", 1.0, "crank", "coupler"),
    "B": ("FB34", -1.0, "coupler", "rocker"),
    "O4": ("FOB", -1.0, "rocker", "frame"),
}
#: member -> the output giving its line's angle (None: the frame, along +x)
LINE = {"frame": None, "crank": "ATH2", "coupler": "ATH3", "rocker": "ATH4"}
#: Positions the cycle starts from (the refinement adds more where they are needed).
SAMPLES = 720
#: The default threshold: loads below this fraction of the pin's peak do not count.
THRESHOLD = 0.05
#: Refine where a direction relative to a member turns more than this between
#: neighbouring positions (degrees).
STEP = 0.25
#: A threshold crossing is located to this (degrees of THETA 2).
CROSSING = 1e-3
#: The refinement stops at intervals this narrow (degrees of THETA 2).
SMALLEST = 1e-6
#: Between neighbours still apart after refinement, a direction that turns more than this
#: (degrees) has passed through zero load (a reversal), sweeping none of the angles between.
JUMP = 30.0
#: Neighbouring swept intervals closer than this (degrees) touch: roundoff of the mod.
TOUCH = 1e-9
#: With ``threshold = 0``, loads below this fraction of the pin's peak (zero to roundoff)
#: point nowhere.
ZERO = 1e-12
#: The peak load is found on the positions, then on a grid this fine around it (degrees).
PEAK_STEP = 1e-3

#: A kind's pins and its members' lines: ({pin: (force, sign, first, second)}, {member:
#: output or None}), as :data:`PINS` and :data:`LINE` are the four-bar's.
Table = tuple[dict[str, tuple[str, float, str, str]], dict[str, str | None]]


def _member(k: int) -> str:
    return {1: "frame", 2: "crank"}.get(k, f"link {k}")


def pin_table(mechanism: Any) -> Table:
    """The pins and member lines of the kind of ``mechanism`` [any kind, its unit system]:
    (:data:`PINS`, :data:`LINE`) for a four-bar; for another its topology's pins (module
    doc), keyed by point (by force where two pins share a point)."""
    if is_four_bar(mechanism):
        return PINS, LINE
    found = pins(mechanism)
    points = [point for _, point, _, _ in found]
    table: dict[str, tuple[str, float, str, str]] = {}
    line: dict[str, str | None] = {}
    for name, point, by, on in found:
        first, second = min(by, on), max(by, on)
        key = point if points.count(point) == 1 else name
        table[key] = (name, 1.0 if first == on else -1.0, _member(first), _member(second))
        for k in (first, second):
            line[_member(k)] = None if k == 1 else f"ATH{k}"
    return table, line


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
    or N) at ``at`` (THETA 2, degrees), ``theta2`` and ``load`` (magnitude) over the cycle
    (the refined positions), its two ``members``, and the ``threshold`` (a fraction of
    ``peak``) below which a load did not count."""

    name: str
    force: str
    peak: float
    at: float
    theta2: np.ndarray
    load: np.ndarray
    members: tuple[Member, ...] = field(default=())
    threshold: float = 0.05


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


def _evaluate(mechanism: Any, th: np.ndarray, sc: Scene, table: Table = (PINS, LINE)
              ) -> dict[str, np.ndarray]:
    pins_, line = table
    want = [v for v in line.values() if v is not None]
    want += [p[0] + s for p in pins_.values() for s in ("X", "Y")]
    return analyze(mechanism, th, want, scene=sc)


def _directions(r: dict[str, np.ndarray], pin: str, table: Table = (PINS, LINE)
                ) -> tuple[np.ndarray, list[np.ndarray]]:
    """The load's magnitude at ``pin`` and its direction relative to each member (deg)."""
    name, sign, first, second = table[0][pin]
    fx, fy = r[name + "X"], r[name + "Y"]
    out = []
    for member, s in ((first, sign), (second, -sign)):
        key = table[1][member]
        line = 0.0 if key is None else r[key]
        out.append((np.degrees(np.arctan2(s * fy, s * fx)) - line) % 360.0)
    return np.hypot(fx, fy), out


def _turn(d: np.ndarray) -> np.ndarray:
    """|shorter turn| from each direction to the next, around the closed cycle (deg)."""
    return np.abs((np.roll(d, -1) - d + 180.0) % 360.0 - 180.0)


def _refine(mechanism: Any, sc: Scene, th: np.ndarray, r: dict[str, np.ndarray],
            floor: dict[str, float], table: Table = (PINS, LINE)
            ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Bisect the intervals where a direction turns more than :data:`STEP` or a pin's
    load crosses its ``floor`` (lb or N), until neither holds or the interval is too
    narrow; the positions and the outputs there."""
    while True:
        width = np.diff(th, append=th[0] + 360.0)
        split = np.zeros(th.size, bool)
        for pin in table[0]:
            load, dirs = _directions(r, pin, table)
            on = ~_off(load, floor[pin])
            both = on & np.roll(on, -1)
            crossing = on != np.roll(on, -1)
            for d in dirs:
                split |= both & (_turn(d) > STEP) & (width > SMALLEST)
            split |= crossing & (width > CROSSING)
        if not split.any():
            return th, r
        mid = th[split] + width[split] / 2.0
        new = _evaluate(mechanism, mid, sc, table)
        order = np.argsort(np.concatenate([th, mid]), kind="stable")
        th = np.concatenate([th, mid])[order]
        r = {k: np.concatenate([r[k], new[k]])[order] for k in r}


def _off(load: np.ndarray, floor: float) -> np.ndarray:
    """The positions whose load does not count (below ``floor``, or zero to roundoff)."""
    return (load < floor) | (load <= 0.0)


def _peak(mechanism: Any, sc: Scene, force: str, th: np.ndarray,
          load: np.ndarray, h: float) -> tuple[float, float]:
    """(peak load, THETA 2 [deg]): the largest sampled load, then the largest on a
    :data:`PEAK_STEP` grid ``h`` either side of it."""
    t0 = float(th[int(np.argmax(load))])
    k = int(round(h / PEAK_STEP))
    fine = np.round(t0 + np.arange(-k, k + 1) * PEAK_STEP, 9)  # no ulps in the angle shown
    v = analyze(mechanism, fine, [force], scene=sc)[force]
    i = int(np.argmax(v))
    if v[i] <= load.max():  # the sample itself (the grid need not hold it exactly)
        return float(load.max()), t0 % 360.0 + 0.0
    return float(v[i]), float(fine[i] % 360.0) + 0.0


def bearings(mechanism: Any, n: int = SAMPLES, *, scene: Scene | None = None,
             threshold: float = THRESHOLD, **keywords: Any) -> dict[str, Pin]:
    """The pins of ``mechanism`` (one design, a crank that turns fully; a four-bar's four,
    another kind's :func:`pin_table`) over one revolution, starting from ``n`` positions
    and refined where needed (module doc), in ``scene`` (or the Scene of ``analyze``'s
    keywords).

    Parameters
    ----------
    mechanism : Mechanism or another kind (SliderCrank, WattII, ..., Linkage)
        One design (scalar fields) [deck units].
    n : int
        Evenly spaced positions the refinement starts from [-].
    scene : Scene, optional
        The loads, effects and branch, of the kind's Scene type [-].
    threshold : float
        Loads below this fraction of the pin's peak do not count as loading a side
        [fraction of the peak, 0 <= threshold < 1].
    """
    four_bar = is_four_bar(mechanism)
    if four_bar:
        sc = scene_from(scene, keywords, "bearings")
        values = mechanism.as_tuple()
    else:
        sc = scene_of_kind(mechanism, scene, keywords, "bearings")
        values = tuple(mechanism.as_dict().values())
    if any(np.ndim(v) for v in values):
        raise ValueError("bearings: one design at a time (the mechanism's fields are arrays)")
    if four_bar:
        c = linkage_class(mechanism)
        if not bool(c.turns_fully):
            raise ValueError("the crank cannot make a whole revolution: no bearing cycle")
        if c.kind == "change-point":
            raise ValueError("a change point: the linkage folds flat on the way round, where "
                             "the loads are not defined: no bearing cycle")
    else:
        why = turn_failures(mechanism)[()]
        if why is not None:
            raise ValueError(f"the crank of the {kind_name(mechanism)} cannot make a whole "
                             f"revolution ({why}): no bearing cycle")
    table = pin_table(mechanism)
    if not 0.0 <= threshold < 1.0:
        raise ValueError(f"bearing threshold {threshold:g}: a fraction of the pin's peak "
                         "load, 0 or more and below 1")
    th = np.arange(n) * (360.0 / n)
    r = _evaluate(mechanism, th, sc, table)
    peaks = {pin: _peak(mechanism, sc, table[0][pin][0], th,
                        _directions(r, pin, table)[0], 360.0 / n) for pin in table[0]}
    floor = {pin: max(threshold, ZERO) * peaks[pin][0] for pin in table[0]}
    th, r = _refine(mechanism, sc, th, r, floor, table)
    out = {}
    for pin, (name, sign, first, second) in table[0].items():
        fx, fy = r[name + "X"], r[name + "Y"]
        load, dirs = _directions(r, pin, table)
        peak, at = peaks[pin]
        off = _off(load, floor[pin])
        members = []
        for (member, s), rel in zip(((first, sign), (second, -sign)), dirs):
            key = table[1][member]
            line = np.zeros(th.size) if key is None else r[key]
            along = np.where(off, 0.0, s * (fx * np.cos(np.radians(line))
                                            + fy * np.sin(np.radians(line))))
            rel = np.where(off, np.nan, rel)
            members.append(Member(member, rel, unloaded_arcs(rel), _reversals(along)))
        out[pin] = Pin(pin, name, peak, at, th, load, tuple(members), threshold)
    return out
