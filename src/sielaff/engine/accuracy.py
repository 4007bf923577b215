"""What the four-bar's computed results are good to: an error bound from the conditioning.

In:  the mechanism (lengths [in or m], masses, inertias, TH2D [rad/sec]), the largest
     |TH2DD| [rad/sec^2] and |TEX| [in-lb or N m] of the scene, gravity's magnitude, and
     at each position |sin GAMMA| (the transmission angle's sine).
Out: for an output's kind, the bound on |computed - exact| at each position, in the
     output's unit (angles in radians).

Derivation (first order in the unit roundoff ``eps``).  Every position starts from A and
O4, whose coordinates carry errors of about ``eps L`` (L = R1 + R2 + R3 + R4: each comes
from sums and products of the lengths); so does |O4 - A|, and so each linear factor of
Heron's product H^2 = (ZL + R3 + R4)(ZL + R3 - R4)(R3 + R4 - ZL)(R4 + ZL - R3).  Near a
toggle the smallest factor is of the size l s^2 (l = min(R3, R4), s = |sin GAMMA|), so
H, and sin GAMMA = H / (2 R3 R4) with it, are good only to ``eps (L / l) / s^2``
relatively.  The angles of links 3 and 4 take H times 1 / ZL: they are good to
``eps (L / l) / s`` (B, where the circles about A and O4 cross at GAMMA, moves by 1 / s
times what moves them).  Every later quantity divides by sin GAMMA (Cramer's rule on the
loop's velocity and acceleration equations, and the statics of links 3 and 4, all have
the determinant R3 R4 sin GAMMA), so its relative error is ``eps (L / l) / s^2``: a rate,
of size W / s (W = R2 |TH2D| / l), is good to ``eps (L / l) W / s^3``; an angular
acceleration, of size ALPHA / s^3 (ALPHA = R2 (TH2D^2 + |TH2DD|) / l + W^2: the rates'
squares over the determinant), to ``eps (L / l) ALPHA / s^5``; a point's velocity or
acceleration is a length L times those (and a length between two points, a spring's, is
good to ``eps (L / l) L / s`` as the angles are); a pin force balances the inertia loads
(masses times accelerations, inertias times angular accelerations), the weights, TEX and
the applied loads through the determinant once more, ``eps (L / l) F / s^6``; a torque
is a length times a force.
So

    |error| <= C eps (L / l) S / s^p

with the scale S and the power p of the output's kind (:data:`POWER`, :func:`scales`) and
one constant C (:data:`C`) for the few tens of roundings each quantity passes through
and the factors of 2 and 4 of the first-order terms.
It holds for the numpy engine and the compiled backend alike (they differ by an ulp or
two in sin, cos and atan2, which is within the ``eps L`` of A); both are tested against a
40-digit reference on drawn linkages of every kind, on both branches, near toggles and
with short links (tests/test_error_bound.py).  It does not hold at a toggle itself
(s = 0: the rates are infinite there and NaN or infinite by the luck of rounding).
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["C", "EPS", "POWER", "bound", "scales"]

#: The unit roundoff of float64.
EPS = float(np.finfo(float).eps)

#: The bound's constant: the roundings a quantity passes through, to first order.
C = 64.0

#: The power of 1 / |sin GAMMA| in the bound, by the output's kind (see the derivation).
POWER = {"angle": 1, "length": 1, "rate": 3, "velocity": 3, "angular acceleration": 5,
         "acceleration": 5, "force": 6, "torque": 6}


def scales(m: Any, th2dd: float = 0.0, tex: float = 0.0, gravity: float = 0.0,
           mass_divisor: float = 386.088, applied: float = 0.0, reach: float = 0.0
           ) -> dict[str, float]:
    """The scale S of each kind of output for the mechanism ``m`` (see the module doc).

    Parameters
    ----------
    m : Mechanism
        One design (scalar fields).
    th2dd : float
        The largest |TH2DD| of the scene [rad/sec^2].
    tex : float
        The largest |TEX| of the scene [in-lb or N m].
    gravity : float
        The magnitude of gravity [length/sec^2] (0 for none).
    mass_divisor : float
        GW: W / GW is a link's mass (386.088 in the report's units, 1 in SI).
    applied : float
        The largest force the scene applies to the links besides TEX and the weights
        [lb or N]: a load's force plus its torque over the shorter of coupler and rocker,
        a spring's or damper's tension (0 for none).
    reach : float
        The farthest a scene places a point from its link's base [in or m] (a load's or
        a spring's point); the centres of mass are the mechanism's own.
    """
    r1, r2, r3, r4 = (abs(float(getattr(m, n))) for n in ("R1", "R2", "R3", "R4"))
    short = min(r3, r4)
    # the lengths a velocity or an acceleration is a rate times: the links, and the
    # farthest point placed on one (a centre of mass, a load's or a spring's point)
    length = r1 + r2 + r3 + r4 + max(abs(float(getattr(m, f"RG{k}"))) for k in (2, 3, 4))
    length += abs(reach)
    w = abs(float(m.TH2D))
    rate = r2 * w / short
    angular = r2 * (w * w + abs(th2dd)) / short + rate * rate
    mass = sum(abs(float(getattr(m, f"W{k}"))) for k in (2, 3, 4)) / mass_divisor
    inertia = sum(abs(float(getattr(m, f"ZI{k}"))) for k in (2, 3, 4))
    force = (mass * (length * angular + gravity) + inertia * angular / short + abs(tex) / short
             + abs(applied))
    return {"angle": 1.0, "length": length, "rate": rate, "velocity": length * rate,
            "angular acceleration": angular, "acceleration": length * angular,
            "force": force, "torque": length * force}


def bound(kind: str, m: Any, sin_gamma: Any, scale: dict[str, float]) -> Any:
    """``C eps (L / l) S / s^p`` for outputs of ``kind`` at positions whose transmission
    angle has the sine ``sin_gamma`` [-]: in the output's unit (radians for angles)."""
    r = [abs(float(getattr(m, n))) for n in ("R1", "R2", "R3", "R4")]
    ratio = sum(r) / min(r[2], r[3])
    s = np.abs(np.asarray(sin_gamma, dtype=float))
    return C * EPS * ratio * scale[kind] / s ** POWER[kind]
