"""The joints of a :class:`~sielaff.linkage.Topology` and the forces in them: one linear
system per position, 3 equations per moving link.

Unknowns: at each pin the force of one member on the other (x, y; which on which:
:func:`joints`), at each slide the guide's force on the slider along the guide's normal
(FN, +90 degrees from its line) at the slider's pin and the guide's couple on it (MN), and
the torque the drive puts on the crank (TORQ).  Equations: each moving link's force
balance (x, y) and its moment balance about its base point, with the applied loads
``{link: (fx, fy, m about the base point)}`` (gravity, loads, springs, D'Alembert's
inertia).  By Gruebler's count (one degree of freedom) the system is square: 3 (n - 1)
equations for 2 unknowns a joint and the torque.  Moment rows are divided by a length
scale and couples solved in that scale, so every entry is of order one.

The system is singular only where the linkage is (a dyad at its toggle): there the
solve gives NaN, as the positions' own NaN where a dyad cannot close.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.engine.dyads import Positions
from sielaff.engine.unroll import call
from sielaff.linkage import PRR, RRP, RRR, Topology

__all__ = ["Joint", "Slide", "entries", "joints", "linear", "matrix", "owner", "solve",
           "slots"]


@dataclass(frozen=True)
class Joint:
    """A pin at the point ``point``: ``name`` reports the force of link ``by`` on link ``on``."""

    name: str
    point: str
    by: int
    on: int


@dataclass(frozen=True)
class Slide:
    """A slide: ``label``; the slider (link ``slider``, pinned at ``point``) on the guide of
    link ``guide``; FN and MN are the guide's force and couple on the slider."""

    label: str
    slider: int
    guide: int
    point: str


def owner(topology: Topology) -> dict[str, int]:
    """The link each named point belongs to: the frame's pivots to the frame, the crank's
    pin to the crank, a dyad's inner pin to its rod (RRR: link n), a named point to its
    link.  A dyad attached at a pin two links share is pinned to that link."""
    home = {"O2": 1, topology.crank.pin: 2}
    home.update({p.name: 1 for p in topology.pivots})
    for i, d in enumerate(topology.dyads):
        n = 3 + 2 * i
        if isinstance(d, RRR | RRP):
            home[d.joint] = n
        elif isinstance(d, PRR):
            home[d.joint] = n + 1
    home.update({p.name: p.link for p in topology.points})
    return home


def joints(topology: Topology) -> tuple[tuple[Joint, ...], tuple[Slide, ...]]:
    """The pins (with their force's generic name) and the slides, in solve order."""
    home = owner(topology)
    pins = [Joint("FO2", "O2", 2, 1)]
    slides = []

    def pin(point: str, by: int, on: int) -> Joint:
        name = f"F{point}" if on == 1 else f"F{point}{by}{on}"
        return Joint(name, point, by, on)

    for i, d in enumerate(topology.dyads):
        n = 3 + 2 * i
        if isinstance(d, RRR):
            pins += [pin(d.p, n, home[d.p]), pin(d.q, n + 1, home[d.q]), pin(d.joint, n, n + 1)]
        elif isinstance(d, RRP):
            pins += [pin(d.p, n, home[d.p]), pin(d.joint, n, n + 1)]
            slides.append(Slide(d.slide, n + 1, d.guide.link, d.joint))
        elif isinstance(d, PRR):
            pins += [pin(d.q, n + 1, home[d.q]), pin(d.joint, n + 1, n)]
            slides.append(Slide(d.slide, n, d.guide.link, d.joint))
        else:
            pins += [pin(d.p, n, home[d.p]), pin(d.q, n + 1, home[d.q])]
            slides.append(Slide(d.slide, n, n + 1, d.p))
    return tuple(pins), tuple(slides)


def slots(topology: Topology) -> tuple[str, ...]:
    """The superposed quantities, in the order :func:`solve` returns them: each pin's
    force (x, y), each slide's FN and MN, then TORQ (the generic names, lower case)."""
    pins, slides = joints(topology)
    out = [f"{j.name.lower()}{axis}" for j in pins for axis in "xy"]
    out += [f"{kind}{s.label.lower()}" for s in slides for kind in ("fn", "mn")]
    return tuple(out) + ("torq",)


_NONE = (0.0, 0.0, 0.0)


def entries(topology: Topology, pos: Positions) -> tuple[list[list[Any]], Any]:
    """The system's matrix at the positions ``pos``, as rows of numbers or arrays (an
    entry no unknown touches the constant 0.0), and the length scale L its moment rows
    are divided by (couples and TORQ are solved in it)."""
    pins, slides = joints(topology)
    size = 3 * (topology.links - 1)
    L = np.where(pos.scale > 0.0, pos.scale, 1.0)
    A: list[list[Any]] = [[0.0] * size for _ in range(size)]

    def add_force(col: int, k: int, fx: Any, fy: Any, at: tuple[Any, Any], sign: float,
                  couple: Any = 0.0) -> None:
        """Column ``col``'s unit unknown puts (fx, fy) at ``at`` and ``couple`` on link k."""
        if k == 1:
            return
        row = 3 * (k - 2)
        _, _, bx, by = pos.link[k]
        A[row][col] = A[row][col] + sign * fx
        A[row + 1][col] = A[row + 1][col] + sign * fy
        A[row + 2][col] = A[row + 2][col] + sign * (
            ((at[0] - bx) * fy - (at[1] - by) * fx) / L + couple)

    col = 0
    for j in pins:
        at = pos.pt[j.point]
        for fx, fy in ((1.0, 0.0), (0.0, 1.0)):
            add_force(col, j.on, fx, fy, at, 1.0)
            add_force(col, j.by, fx, fy, at, -1.0)
            col += 1
    for s in slides:
        at = pos.pt[s.point]
        _, _, _, u = pos.guide[s.label]
        nx, ny = -u[1], u[0]
        add_force(col, s.slider, nx, ny, at, 1.0)
        add_force(col, s.guide, nx, ny, at, -1.0)
        add_force(col + 1, s.slider, 0.0, 0.0, at, 1.0, 1.0)
        add_force(col + 1, s.guide, 0.0, 0.0, at, -1.0, 1.0)
        col += 2
    A[2][col] = A[2][col] + 1.0  # the drive's torque on the crank (link 2's moment row)
    return A, L


def _array(rows: list[list[Any]] | tuple[Any, ...], shape: tuple[int, ...] = ()) -> np.ndarray:
    """Rows of numbers or arrays as one array (the rows' shape broadcast with ``shape``,
    then the rows' axes)."""
    shape = np.broadcast_shapes(shape, *(np.shape(v) for r in rows for v in r))
    A = np.zeros(shape + (len(rows), len(rows[0])))
    for i, r in enumerate(rows):
        for j, v in enumerate(r):
            if not (isinstance(v, float) and v == 0.0):
                A[..., i, j] = v
    return A


def matrix(topology: Topology, pos: Positions, shape: tuple[int, ...] = ()
           ) -> tuple[np.ndarray, Any]:
    """The system's matrix at the positions ``pos`` (of shape ``shape`` at least) and the
    length scale L its moment rows are divided by (couples and TORQ are solved in it)."""
    rows, L = entries(topology, pos)
    return _array(rows, shape), L


def linear(rows: Any, rhs: Any) -> tuple[Any, ...]:
    """x with A x = rhs at each position, A's ``rows`` and ``rhs`` numbers or arrays;
    NaN where A is not finite or singular.  (The compiled backend's one-position form:
    engine/kernel_math.py.)"""
    b = _array((rhs,))[..., 0, :]
    A = _array(rows, b.shape[:-1])
    b = np.broadcast_to(b, A.shape[:-1])
    x = _solve(A, b)
    return tuple(x[..., i] for i in range(x.shape[-1]))


def solve(topology: Topology, loads: dict[int, tuple[Any, Any, Any]],
          pos: Positions) -> tuple[Any, ...]:
    """The slots (:func:`slots`) for the applied ``loads`` at the positions ``pos``: the
    force and moment balances' rows (:func:`entries`) solved for the loads' rows (force
    x, y and moment / L per link) by :func:`linear`, the couples and TORQ back from the
    scale L."""
    rows, L = entries(topology, pos)
    rhs: list[Any] = []
    for k in range(2, topology.links + 1):
        fx, fy, m = loads.get(k, _NONE)
        rhs += [-(0.0 + fx), -(0.0 + fy), -(0.0 + m / L)]
    x = call(linear, len(rhs), rows, rhs)
    pins, slides = joints(topology)
    out = [x[i] for i in range(len(rhs))]
    n_pin = 2 * len(pins)
    for i in range(n_pin + 1, n_pin + 2 * len(slides), 2):  # the couples and TORQ: in scale
        out[i] = out[i] * L
    out[-1] = out[-1] * L
    return tuple(out)


def _solve(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``A x = b`` at each position; NaN where A is not finite or singular."""
    bad = ~np.isfinite(A).all(axis=(-2, -1)) | ~np.isfinite(b).all(axis=-1)
    if bad.any():
        A = np.where(bad[..., None, None], np.eye(A.shape[-1]), A)
        b = np.where(bad[..., None], 0.0, b)
    try:
        x = np.linalg.solve(A, b[..., None])[..., 0]
    except np.linalg.LinAlgError:  # some position exactly singular (a toggle): one by one
        flat_A, flat_b = A.reshape(-1, *A.shape[-2:]), b.reshape(-1, b.shape[-1])
        x = np.empty_like(flat_b)
        for i in range(flat_b.shape[0]):
            try:
                x[i] = np.linalg.solve(flat_A[i], flat_b[i])
            except np.linalg.LinAlgError:
                x[i] = np.nan
        x = x.reshape(b.shape)
    if bad.any():
        x[bad] = np.nan
    return x
