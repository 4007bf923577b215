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

Every other kind (a slider-crank, an inverted slider-crank, a six-bar, any ``Linkage``)
has its own rows (:func:`peak_rows`: its pins, slides and transmission angles) over where
every one of its dyads closes on the scene's branch, its toggles the ends of those arcs,
with the same test of growth.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.design.kinds import arcs_where_assembled, gammas, is_four_bar, pins, slides, spread

__all__ = ["PEAKS", "Peak", "peak_rows", "peaks"]

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


def peak_rows(mechanism: Any) -> tuple[tuple[str, str, str], ...]:
    """The rows (label, output, how) the peaks of ``mechanism`` [any kind] report:
    :data:`PEAKS` for a four-bar; for another kind the driving torque, the shaking force
    and moment, each pin's load, each slide's guide force (largest magnitude) and each
    transmission angle GAMMA<pin> its model gives."""
    if is_four_bar(mechanism):
        return PEAKS
    rows = [p for p in PEAKS if p[1] in ("TORQ", "SHAK", "SHAKM")]
    rows += [(f"load on pin {point} ({name})", name, "max")
             for name, point, _, _ in pins(mechanism)]
    rows += [(f"guide force, largest magnitude ({name})", name, "maxabs")
             for name in slides(mechanism)]
    for g in gammas(mechanism):
        at = f" at {g[len('GAMMA'):]}" if g != "GAMMA" else ""
        rows += [(f"transmission angle{at}, least", g, "min"),
                 (f"transmission angle{at}, greatest", g, "max")]
    return tuple(rows)


def peaks(mechanism: Any, scene: Any, n: int = 3600) -> list[Peak]:
    """The rows of :func:`peak_rows` for ``mechanism`` [its units] in ``scene``.

    Parameters
    ----------
    mechanism : Mechanism or another kind (SliderCrank, WattII, ..., Linkage)
        One design [its unit system].
    scene : Scene
        What acts on it, of its kind's Scene type [-].
    n : int
        Crank angles over the arcs it reaches [-].

    Returns
    -------
    list of Peak
        Only the rows with a finite value somewhere (none for a linkage that never
        assembles).  A four-bar's arcs and toggles are its class's
        (:func:`sielaff.engine.reachable`); another kind's are where every dyad closes on
        the scene's branch (:func:`sielaff.design.kinds.arcs_where_assembled`), and the
        transmission angle at a toggle is the one of its GAMMA<pin> nearest 0 or 180 deg
        (NaN for a kind with none, such as the slider-cranks).
    """
    m = mechanism
    if is_four_bar(m):
        from sielaff.engine import linkage_class, reachable

        th = reachable(m, n)
        if not len(th):
            return []
        c = linkage_class(m)
        ends = [] if c.turns_fully else _approaches(list(c.arcs or []))
        return _rows(m, scene, th, ends, PEAKS, ("GAMMA",))
    if any(np.ndim(v) for v in m.as_dict().values()):
        raise ValueError("peaks: one design at a time (the mechanism's fields are arrays)")
    arcs = arcs_where_assembled(m, scene.branch)
    th = spread(arcs, n)
    if not len(th):
        return []
    return _rows(m, scene, th, _approaches(arcs), peak_rows(m), gammas(m))


def _gamma_at(m: Any, at: np.ndarray, angles: tuple[str, ...], scene: Any) -> list[float]:
    """The transmission angle at each toggle ``at`` [deg]: the one of ``angles`` nearest
    0 or 180 deg there (NaN with none)."""
    if not angles:
        return [math.nan] * len(at)
    r = _quiet_analyze(m, np.mod(at, 360.0), list(angles), scene)
    if len(angles) == 1:
        return [float(g) for g in r[angles[0]]]
    g = np.array([np.asarray(r[a], dtype=float) for a in angles])
    with np.errstate(all="ignore"):
        off = np.where(np.isfinite(g), np.minimum(g, 180.0 - g), np.inf)
    pick = np.argmin(off, axis=0)
    return [float(g[pick[k], k]) for k in range(len(at))]


def _rows(m: Any, scene: Any, th: np.ndarray, ends: list[tuple[float, float]],
          table: tuple[tuple[str, str, str], ...], angles: tuple[str, ...]) -> list[Peak]:
    """The peaks of ``table`` over the angles ``th`` [deg], a quantity growing toward a
    toggle of ``ends`` (toggle, direction into its arc) given as unbounded."""
    from sielaff.quantities import unit

    names = sorted({p[1] for p in table})
    r = _quiet_analyze(m, th, names, scene)
    grows: dict[str, list[int]] = {}
    gamma: list[float] = []
    if ends:
        near = np.array([t + d * APPROACH for t, d in ends])
        far = np.array([t + d * APPROACH * 10.0 for t, d in ends])
        at = np.array([t for t, _ in ends])
        rn = _quiet_analyze(m, np.mod(near, 360.0), names, scene)
        rf = _quiet_analyze(m, np.mod(far, 360.0), names, scene)
        gamma = _gamma_at(m, at, angles, scene)
        for name in names:
            a, b = np.abs(np.asarray(rn[name])), np.abs(np.asarray(rf[name]))
            with np.errstate(all="ignore"):
                up = ~np.isfinite(a) | (a > GROWTH * b)
            grows[name] = [k for k in range(len(ends)) if up[k] and name not in angles]
    rows = []
    for label, name, how in table:
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
