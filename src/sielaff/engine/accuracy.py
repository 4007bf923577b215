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

A chain of dyads (the slider-cranks, the six-bars): each dyad's inputs carry the errors
of the dyads before it, which it multiplies by (L / l) / s_i as the four-bar's one dyad
multiplies A's and O4's (s_i the dyad's own conditioning: |sin| of an RRR dyad's angle at
its inner pin, |cos| of a slider's rod to its guide, |s| / |PQ| for an inverted slider's
block), so with d dyads

    |error| <= C eps (L / l)^d S / s^p,    s = s_1 s_2 ... s_d

(:func:`chain_bound`, :func:`chain_scales`; the four-bar is d = 1, s = |sin GAMMA|).  It
is tested against a 40-digit solve of every kind, both branches, with every effect the
kinds take (tests/test_compiled_kinds.py).
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["C", "EPS", "POWER", "bound", "chain_bound", "chain_scales", "scales"]

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
    mass = sum(abs(float(getattr(m, f"W{k}"))) for k in (2, 3, 4)) / mass_divisor
    inertia = sum(abs(float(getattr(m, f"ZI{k}"))) for k in (2, 3, 4))
    return _scale_table(length + abs(reach), short, r2, abs(float(m.TH2D)), th2dd, mass,
                        inertia, abs(gravity), abs(tex) / short + abs(applied))


def _scale_table(length: float, short: float, crank: float, w: float, th2dd: float,
                 mass: float, inertia: float, gravity: float, applied: float
                 ) -> dict[str, float]:
    """The scales S of every kind (the module doc's derivation), for any linkage: one
    place for the model that :func:`scales` and :func:`chain_scales` share.

    Parameters
    ----------
    length : float
        L': the links' lengths and the farthest point placed on one [in or m].
    short : float
        l: the shortest dyad link [in or m].
    crank : float
        |R2| [in or m].
    w, th2dd : float
        |TH2D| [rad/sec] and the largest |TH2DD| [rad/sec^2].
    mass, inertia : float
        The links' masses (W / GW) and inertias, summed [lb-sec^2/in or kg; lb-in-sec^2
        or kg m^2].
    gravity : float
        Gravity's magnitude [in/sec^2 or m/sec^2].
    applied : float
        The forces applied besides the weights, TEX over ``short`` among them [lb or N].
    """
    rate = crank * w / short
    angular = crank * (w * w + abs(th2dd)) / short + rate * rate
    force = mass * (length * angular + gravity) + inertia * angular / short + applied
    return {"angle": 1.0, "length": length, "rate": rate, "velocity": length * rate,
            "angular acceleration": angular, "acceleration": length * angular,
            "force": force, "torque": length * force}


def bound(kind: str, m: Any, sin_gamma: Any, scale: dict[str, float]) -> Any:
    """``C eps (L / l) S / s^p`` for outputs of ``kind`` at positions whose transmission
    angle has the sine ``sin_gamma`` [-]: in the output's unit (radians for angles)."""
    r = [abs(float(getattr(m, n))) for n in ("R1", "R2", "R3", "R4")]
    return chain_bound(kind, sum(r) / min(r[2], r[3]), 1, sin_gamma, scale)


def chain_bound(kind: str, ratio: float, dyads: int, s: Any, scale: dict[str, float]
                ) -> Any:
    """``C eps (L / l)^d S / s^p`` (see the module doc) for outputs of ``kind``, in the
    output's unit (radians for angles; a power, a torque times a rate).

    Parameters
    ----------
    kind : str
        The output's kind: a key of :data:`POWER`, or "power".
    ratio : float
        L / l, the sum of the lengths over the shortest dyad link [-].
    dyads : int
        d, the dyads the chain solves one after another [-].
    s : float or array
        The product of the dyads' conditioning at each position [-].
    scale : dict
        The scales S (:func:`scales`, :func:`chain_scales`).
    """
    s = np.abs(np.asarray(s, dtype=float))
    if kind == "power":
        return (chain_bound("torque", ratio, dyads, s, scale) * scale["rate"]
                / s ** POWER["rate"])
    return C * EPS * ratio ** dyads * scale[kind] / s ** POWER[kind]


def chain_scales(m: Any, th2dd: float = 0.0, gravity: float = 0.0,
                 mass_divisor: float = 386.088, applied: float = 0.0, reach: float = 0.0
                 ) -> tuple[dict[str, float], float]:
    """:func:`scales` for a linkage of any kind (a slider-crank, an inverted slider-crank,
    a six-bar), and its ratio L / l.

    Parameters
    ----------
    m : Mechanism
        One design: its lengths R1.., RC, X6, Y6 and offset [in or m], its dyads' links
        (``m.TOPOLOGY.lengths()``), weights W.., inertias ZI.. and TH2D [rad/sec].
    th2dd, gravity, mass_divisor, applied, reach
        As in :func:`scales` (TEX is among the applied loads here).
    """
    v = m.as_dict()
    lengths = [abs(float(v[n])) for n in v if (n[:1] == "R" and n[1:2] in "123456C")
               or n in ("X6", "Y6", "offset")]
    dyad = [abs(float(v[n])) for n in m.TOPOLOGY.lengths() if n != "R2"]
    # the inverted slider's block has no link of its own: its least distance from O4
    short = min(dyad) if dyad else max(abs(float(v["R1"]) - float(v["R2"])),
                                       1e-3 * abs(float(v["R1"])))
    length = sum(lengths) + max(abs(float(v[n])) for n in v if n.startswith("RG"))
    mass = sum(abs(float(v[n])) for n in v if n.startswith("W")) / mass_divisor
    inertia = sum(abs(float(v[n])) for n in v if n.startswith("ZI"))
    return (_scale_table(length + abs(reach), short, abs(float(v["R2"])),
                         abs(float(v["TH2D"])), th2dd, mass, inertia, abs(gravity),
                         abs(applied)), sum(lengths) / short)
