"""Peaks of a linkage's outputs over the crank angles where it assembles (issue 33).

``peaks(mechanism, scene)`` gives, for each of :data:`PEAKS`, the largest (or smallest)
value and the THETA 2 where it occurs, over the angles the linkage reaches
(:func:`sielaff.engine.reachable`: a whole revolution when the crank turns fully, else
each arc between toggles).

Near a toggle (coupler and rocker in line, the transmission angle GAMMA 0 or 180 deg) a
crank that keeps turning cannot drive the rocker: the rates, and every force that
depends on them or on the rocker's load, grow without bound as THETA 2 nears it (the
rates as 1 / sqrt(distance), the accelerations as its -3/2 power).  A peak there is no
number an engineer can use, so a quantity is called **unbounded** when it grows toward
a toggle: its magnitude at :data:`APPROACH` [deg] from the toggle (inside the arc) is
more than :data:`GROWTH` = 2 times its magnitude ten times farther away (an inverse
square root gives sqrt(10) = 3.2; a bounded quantity about 1).  Its peak is then the
toggles it grows toward, with GAMMA there, and no value.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["PEAKS", "Peak", "peaks"]

#: The peaks reported: (label, output, how).
PEAKS = (
    ("driving torque, largest", "TORQ", "max"),
    ("driving torque, smallest", "TORQ", "min"),
    ("shaking force", "SHAK", "max"),
    ("shaking moment, largest magnitude", "SHAKM", "maxabs"),
    ("load on pin O2 (FOA)", "FOA", "max"),
    ("load on pin A (FA32)", "FA32", "max"),
    ("load on pin B (FB34)", "FB34", "max"),
    ("load on pin O4 (FOB)", "FOB", "max"),
    ("transmission angle, least", "GAMMA", "min"),
    ("transmission angle, greatest", "GAMMA", "max"),
)
#: How near a toggle the growth is read [deg], and the growth that calls it unbounded.
APPROACH = 1e-6
GROWTH = 2.0


@dataclass(frozen=True)
class Peak:
    """One row: ``value`` [``unit``] at ``at`` [deg]; for an unbounded quantity both are
    NaN and ``toggles`` [deg] holds the toggles it grows toward, ``gamma`` [deg] the
    transmission angle at each."""

    label: str
    name: str
    value: float
    unit: str
    at: float
    toggles: tuple[float, ...] = ()
    gamma: tuple[float, ...] = ()

    @property
    def unbounded(self) -> bool:
        return bool(self.toggles)


def _quiet_analyze(m: Any, th: Any, names: list[str], scene: Any) -> Any:
    from sielaff.engine import AssemblyWarning, analyze

    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", AssemblyWarning)
        return analyze(m, th, names, scene=scene)


def _approaches(arcs: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """(toggle, direction into its arc) for each end of each arc."""
    out = []
    for a, b in arcs:
        if (b - a) % 360.0 == 0.0:
            continue  # the whole revolution: no toggle
        out += [(a, 1.0), (b, -1.0)]
    return out


def peaks(mechanism: Any, scene: Any, n: int = 3600) -> list[Peak]:
    """The rows of :data:`PEAKS` for ``mechanism`` [its units] in ``scene``.

    Parameters
    ----------
    mechanism : Mechanism
        One design [its unit system].
    scene : Scene
        What acts on it.
    n : int
        Crank angles over the arcs it reaches [-].

    Returns
    -------
    list of Peak
        Only the rows with a finite value somewhere (none for a linkage that never
        assembles).
    """
    from sielaff.engine import linkage_class, reachable
    from sielaff.quantities import unit

    m = mechanism
    th = reachable(m, n)
    if not len(th):
        return []
    names = sorted({p[1] for p in PEAKS})
    r = _quiet_analyze(m, th, names, scene)
    c = linkage_class(m)
    ends = [] if c.turns_fully else _approaches(list(c.arcs or []))
    grows: dict[str, list[int]] = {}
    gamma: list[float] = []
    if ends:
        near = np.array([t + d * APPROACH for t, d in ends])
        far = np.array([t + d * APPROACH * 10.0 for t, d in ends])
        at = np.array([t for t, _ in ends])
        rn = _quiet_analyze(m, np.mod(near, 360.0), names, scene)
        rf = _quiet_analyze(m, np.mod(far, 360.0), names, scene)
        gamma = [float(g) for g in _quiet_analyze(m, np.mod(at, 360.0), ["GAMMA"],
                                                  scene)["GAMMA"]]
        for name in names:
            a, b = np.abs(np.asarray(rn[name])), np.abs(np.asarray(rf[name]))
            with np.errstate(all="ignore"):
                up = ~np.isfinite(a) | (a > GROWTH * b)
            grows[name] = [k for k in range(len(ends)) if up[k] and name != "GAMMA"]
    rows = []
    for label, name, how in PEAKS:
        u = unit(name, m.units)
        if grows.get(name):
            ks = grows[name]
            rows.append(Peak(label, name, math.nan, u, math.nan,
                             tuple(ends[k][0] % 360.0 for k in ks),
                             tuple(gamma[k] for k in ks)))
            continue
        v = np.where(np.isfinite(r[name]), r[name], np.nan)
        if not np.any(np.isfinite(v)):
            continue
        i = int(np.nanargmax(np.abs(v) if how == "maxabs" else -v if how == "min" else v))
        rows.append(Peak(label, name, float(v[i]), u, float(th[i])))
    return rows
