"""Where a linkage of dyads assembles: each dyad's margin over the crank angles, whether the
crank turns fully, and whether some dyad can close at all.

A dyad's margin (engine/dyads.py) is the sine of its transmission angle for an RRR, the
cosine of the rod's angle from the guide's normal for an RRP or PRR, |s| / |P - Q| for an
RPR: 0 at its toggle, NaN where it cannot close.  The crank turns fully when every dyad's
margin stays above 0 over a revolution: checked on a grid of :data:`GRID` angles, and the
least margin on the grid refined by golden-section search between its neighbours (a dyad
that touches its toggle between two grid angles is found there).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from sielaff.engine import dyads
from sielaff.linkage import RPR, RRR, Topology

__all__ = ["GRID", "arcs", "assembly_failure", "dyad_name", "golden", "margins", "never_assembles"]

#: Crank angles per revolution the checks sample.
GRID = 3600


def dyad_name(topology: Topology, i: int) -> str:
    """The dyad's words in a message: its kind, its pin and its links."""
    d = topology.dyads[i]
    n = 3 + 2 * i
    kind = type(d).__name__
    where = f"at {d.p}" if isinstance(d, RPR) else f"at {d.joint}"
    return f"the {kind} dyad {where} (links {n} and {n + 1})"


def _signs(branch: Any, n: int) -> tuple[float, ...]:
    items = (branch,) * n if isinstance(branch, str) else tuple(branch)
    return tuple(1.0 if b == "open" else -1.0 for b in items)


def margins(topology: Topology, values: dict[str, Any], th_deg: Any,
            branch: Any = "open") -> np.ndarray:
    """Each dyad's margin at the crank angles ``th_deg`` [deg] (scalar fields): an array
    (dyads, angles), NaN where that dyad cannot close."""
    th = np.radians(np.asarray(th_deg, dtype=float))
    with np.errstate(all="ignore"):
        pos = dyads.positions(topology, values, np.cos(th), np.sin(th),
                              _signs(branch, len(topology.dyads)))
    return np.array([np.broadcast_to(m, th.shape) for m in pos.margins], dtype=float)


def arcs(ok: np.ndarray, th: np.ndarray) -> list[tuple[float, float]]:
    """The arcs [deg] of the grid ``th`` (a revolution) where ``ok`` holds."""
    if ok.all():
        return [(0.0, 360.0)]
    out = []
    n = len(ok)
    start = None
    first_bad = int(np.argmin(ok))
    for k in range(1, n + 1):
        i = (first_bad + k) % n
        if ok[i] and start is None:
            start = i
        if not ok[i] and start is not None:
            out.append((float(th[start]), float(th[(i - 1) % n])))
            start = None
    return out


def never_assembles(topology: Topology, values: dict[str, Any], branch: Any = "open"
                    ) -> str | None:
    """The first dyad that closes at no crank angle of the grid, in one line, or None."""
    th = np.arange(GRID) * (360.0 / GRID)
    m = margins(topology, values, th, branch)
    for i in range(len(topology.dyads)):
        ok = np.isfinite(m[i])
        if not ok.any():
            return (f"{dyad_name(topology, i)} cannot close at any crank angle: "
                    + _why(topology, i))
    return None


def _why(topology: Topology, i: int) -> str:
    d = topology.dyads[i]
    if isinstance(d, RRR):
        return (f"{d.lp} + {d.lq} never spans the distance from {d.p} to {d.q}, or "
                f"|{d.lp} - {d.lq}| always exceeds it")
    if isinstance(d, RPR):
        return f"{d.p} never comes as far as |{d.offset}| from {d.q}"
    return f"the rod {d.length} never reaches the guide"


def assembly_failure(topology: Topology, values: dict[str, Any], branch: Any = "open"
                     ) -> str | None:
    """Why the crank cannot make a whole revolution (the first dyad that reaches its toggle
    or cannot close, and the arcs where the linkage assembles), or None."""
    th = np.arange(GRID) * (360.0 / GRID)
    m = margins(topology, values, th, branch)
    for i in range(len(topology.dyads)):
        mi = m[i]
        ok = np.isfinite(mi) & (mi > 0.0)
        if not ok.all():
            spans = ", ".join(f"{a:g} to {b:g}" for a, b in arcs(ok, th))
            where = (f"the linkage assembles for THETA 2 from {spans} deg" if spans else
                     "it closes at no crank angle")
            return f"{dyad_name(topology, i)} reaches its toggle or cannot close: {where}"
        j = int(np.argmin(mi))
        least = _refine(topology, values, branch, i, th[j])
        if not least > 0.0:
            return (f"{dyad_name(topology, i)} reaches its toggle near THETA 2 = "
                    f"{th[j]:g} deg")
    return None


def _refine(topology: Topology, values: dict[str, Any], branch: Any, i: int,
            at: float) -> float:
    """The least margin of dyad ``i`` within a grid step of ``at`` (golden section)."""
    step = 360.0 / GRID

    def f(x: float) -> float:
        v = float(margins(topology, values, [x], branch)[i][0])
        return v if math.isfinite(v) else -1.0

    return min(golden(f, at - step, at + step, most=60)[1], f(at))


def golden(f: Callable[[float], float], lo: float, hi: float, tol: float = 0.0,
           most: int = 500) -> tuple[float, float]:
    """(x, f(x)): the least ``f`` found on (lo, hi) by golden-section search, the ends
    never evaluated, until the bracket is ``tol`` wide or after ``most`` steps (``f``
    has one minimum there; each step narrows the bracket by 0.618)."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo, hi
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(most):
        if b - a <= tol:
            break
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = f(d)
    return (c, fc) if fc <= fd else (d, fd)
