"""What every synthesis method shares: the placement of a linkage in the user's frame, the
coupler point, the default mass model and the branch and order checks.

The engine's frame has O2 at the origin and O4 at (R1, 0) (docs/conventions.md).  A
problem is posed in the user's frame; a :class:`Placement` says where the engine's frame
sits in it: O2 at (``x``, ``y``) and the line O2->O4 at ``angle`` degrees CCW from the
user's +x.  A point p of the engine's frame is ``O2 + R(angle) p`` in the user's.

Branches: at a crank angle the loop closes with B on the left of the line A->O4 (the
engine's ``"open"`` branch, BRANCH = 1) or on its right (``"crossed"``).  A linkage that
must pass through several positions must reach them all on one branch, in the order
given, without a toggle between them (a toggle is where the two branches meet: crossing
one needs the linkage to be pushed through a dead point).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.mechanism import MASS_DIVISOR, STANDARD_GRAVITY, Mechanism

__all__ = ["DENSITY", "AREA", "Placement", "CouplerPoint", "masses", "mechanism_from_lengths",
           "side_of", "branch_name", "crank_arc_check"]

#: Steel: weight per volume in lb/in^3 (7850 kg/m^3 x g) and mass per volume in kg/m^3.
DENSITY = {"in-lb-sec": 7850.0 * 9.80665 / 4.4482216152605 * 0.0254 ** 3,
           "SI": 7850.0}
#: A bar's cross-section: 1 in x 0.5 in (0.5 in^2), or 25 mm x 12.5 mm (3.125E-4 m^2).
AREA = {"in-lb-sec": 0.5, "SI": 3.125e-4}


@dataclass(frozen=True)
class Placement:
    """Where the engine's frame sits in the user's: O2 at (``x``, ``y``) [length unit],
    the line O2->O4 at ``angle`` [deg] CCW from the user's +x."""

    x: float
    y: float
    angle: float

    def to_user(self, px: Any, py: Any) -> tuple[np.ndarray, np.ndarray]:
        """Points of the engine's frame in the user's (arrays broadcast)."""
        c, s = math.cos(math.radians(self.angle)), math.sin(math.radians(self.angle))
        px, py = np.asarray(px, dtype=float), np.asarray(py, dtype=float)
        return self.x + c * px - s * py, self.y + s * px + c * py

    def to_engine(self, ux: Any, uy: Any) -> tuple[np.ndarray, np.ndarray]:
        """Points of the user's frame in the engine's."""
        c, s = math.cos(math.radians(self.angle)), math.sin(math.radians(self.angle))
        dx, dy = np.asarray(ux, dtype=float) - self.x, np.asarray(uy, dtype=float) - self.y
        return c * dx + s * dy, -s * dx + c * dy


@dataclass(frozen=True)
class CouplerPoint:
    """A point of the coupler placed as RG3/ADEL3 place G3: ``r`` [length unit] from A, at
    ``angle`` [deg] CCW from the line A->B."""

    r: float
    angle: float


def mechanism_from_lengths(R1: float, R2: float, R3: float, R4: float, *, th2d: float = 1.0,
                           units: str = "in-lb-sec", density: float | None = None,
                           area: float | None = None) -> Mechanism:
    """A :class:`~sielaff.mechanism.Mechanism` with these lengths [length unit], crank
    speed ``th2d`` [rad/sec] and the masses of :func:`masses`."""
    bare = Mechanism(W2=0.0, W3=0.0, W4=0.0, ZI2=0.0, ZI3=0.0, ZI4=0.0,
                     R1=float(R1), R2=float(R2), R3=float(R3), R4=float(R4),
                     ADEL2=0.0, ADEL3=0.0, ADEL4=0.0, RG2=0.0, RG3=0.0, RG4=0.0,
                     TH2D=float(th2d), units=units)
    return masses(bare, density=density, area=area)


def masses(mechanism: Mechanism, *, density: float | None = None,
           area: float | None = None) -> Mechanism:
    """The default mass model: links 2, 3 and 4 are uniform straight bars of one
    cross-section, pin to pin.

    Each link of length L gets W = density x area x L (a weight [lb] in the in-lb-sec
    system, where density is a weight per volume [lb/in^3]; a mass [kg] in SI, density in
    [kg/m^3]), its centre of mass half-way between its pins (RG = L/2, ADEL = 0) and
    ZI = (W / divisor) L^2 / 12 about that centre [in-lb-sec^2 or kg m^2], the divisor
    being g = 386.088 in/sec^2 for weights and 1 for masses
    (:data:`~sielaff.mechanism.MASS_DIVISOR`).

    Parameters
    ----------
    mechanism : Mechanism
        Its lengths R2-R4 [length unit] and ``units`` are used; the other fields kept.
    density : float, optional
        [lb/in^3] or [kg/m^3]; default steel (:data:`DENSITY`: 0.2836 lb/in^3, 7850 kg/m^3).
    area : float, optional
        [in^2] or [m^2]; default :data:`AREA` (0.5 in^2, 3.125E-4 m^2).
    """
    units = mechanism.units
    if units not in STANDARD_GRAVITY:
        raise ValueError(f"units = {units!r}: the unit systems are {', '.join(STANDARD_GRAVITY)}")
    rho = DENSITY[units] if density is None else float(density)
    a = AREA[units] if area is None else float(area)
    if not (rho > 0 and a > 0 and math.isfinite(rho) and math.isfinite(a)):
        raise ValueError(f"density = {rho:g}, area = {a:g}: both must be positive and finite")
    fields = {}
    for k, L in ((2, mechanism.R2), (3, mechanism.R3), (4, mechanism.R4)):
        W = rho * a * L
        fields[f"W{k}"] = W
        fields[f"ZI{k}"] = W / MASS_DIVISOR[units] * L * L / 12.0
        fields[f"RG{k}"] = L / 2.0
        fields[f"ADEL{k}"] = 0.0
    return mechanism.replace(**fields)


def side_of(ax: Any, ay: Any, ox: Any, oy: Any, bx: Any, by: Any) -> np.ndarray:
    """The cross product (O4 - A) x (B - A): > 0 where B is left of the line A->O4 (the
    engine's open branch), < 0 right of it (crossed), 0 at a toggle."""
    return (ox - ax) * (by - ay) - (oy - ay) * (bx - ax)


def branch_name(sign: float) -> str:
    return "open" if sign > 0 else "crossed"


def crank_arc_check(mechanism: Mechanism, th2: np.ndarray, direction: int) -> str | None:
    """Whether the crank can go from ``th2[0]`` through each ``th2[k]`` in turn, turning
    one way (``direction`` +1 CCW, -1 CW) less than a whole turn in all, without meeting a
    toggle.  None when it can, else why not (one line)."""
    from sielaff.engine import linkage_class

    th2 = np.asarray(th2, dtype=float)
    steps = np.mod(direction * np.diff(th2), 360.0)
    if np.sum(steps) >= 360.0:
        return (f"order defect: the crank turns {np.sum(steps):.6g} deg "
                f"{'CCW' if direction > 0 else 'CW'} to reach the positions in order, "
                "more than a turn")
    c = linkage_class(mechanism)
    if c.turns_fully:
        return None
    travel = float(np.sum(steps))
    for t in c.toggles:
        if not np.isfinite(t):
            continue
        ahead = float(np.mod(direction * (t - th2[0]), 360.0))
        if 0.0 < ahead < travel:
            return (f"toggle between the positions: the crank meets a dead point at "
                    f"THETA 2 = {float(t):.6g} deg ({c.kind}, it does not turn fully)")
    return None
