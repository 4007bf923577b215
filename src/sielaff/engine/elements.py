"""Springs and dampers between any two points of the linkage (the frame included).

``Spring(a, b, k, length)`` and ``Damper(a, b, c)`` in ``Scene(elements=[...])``.  A
point is ``(link, r, angle)``, placed as RG and ADEL place a centre of mass: ``r`` from
the link's base pin (link 1, the frame: O2; link 2: O2; link 3: A; link 4: O4) at
``angle`` degrees CCW from the link's line (the frame's line runs from O2 to O4).  With
L the distance between the points and dL/dt its rate, each element pulls its two points
together with the tension (negative: it pushes them apart)

    spring:  T = k (L - length)          damper:  T = c dL/dt

so the link of point a feels ``T u`` at a and the link of point b ``-T u`` at b (u the
unit vector from a to b); a point on the frame passes its force to the frame directly
(it is not in FOA or FOB, which are what links 2 and 4 put on the frame).  The model is
linear in these loads, so the effect adds its parts to the superposed pin forces and
TORQ (``TORQ_ELEMENTS``, its share).  Outputs per element: ``SPRINGk_L``,
``SPRINGk_LD``, ``SPRINGk_F`` for the k-th spring (k = 1, 2, ... in the order of
``elements``), ``DAMPERk_...`` likewise; L in in or m, LD in in/sec or m/s, F in lb
or N; an element the scene does not have reads 0 (the outputs are declared for
:data:`MAX_ELEMENTS` of each kind; count the scene's own).  Their power on the linkage is
``-T dL/dt`` each.  At most :data:`MAX_ELEMENTS` of each kind.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.engine.registry import Effect, step, step_of
from sielaff.engine.statics import pins
from sielaff.engine.values import check_value

__all__ = ["MAX_ELEMENTS", "Damper", "Spring", "check_elements"]

#: How many springs, and how many dampers, a scene may have (each has its own outputs).
MAX_ELEMENTS = 8


def _point(name: str, p: Any) -> tuple[int, float, float]:
    try:
        link, r, angle = p
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {p!r}: a point (link, r, angle)") from None
    if isinstance(link, bool) or link not in (1, 2, 3, 4):
        raise ValueError(f"{name} link = {link!r}: 1 (the frame), 2, 3 or 4")
    return (int(link), _number(f"{name} r", r), _number(f"{name} angle", angle))


def _number(name: str, v: Any, minimum: float | None = None) -> float:
    if isinstance(v, bool) or callable(v) or np.ndim(v) != 0:
        raise ValueError(f"{name} = {v!r}: a number")
    x = float(check_value(name, v))
    if minimum is not None and x < minimum:
        raise ValueError(f"{name} = {x!r}: must be >= {minimum:g}")
    return x


@dataclass(frozen=True)
class Spring:
    """A linear spring between two points (see the module doc).

    Parameters
    ----------
    a, b : (link, r, angle)
        The points: link 1-4, r [in or m] from the link's base pin, angle [deg].
    k : float
        Stiffness [lb/in or N/m].
    length : float
        Free length [in or m], >= 0.
    """

    a: Any
    b: Any
    k: float
    length: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "a", _point("Spring.a", self.a))
        object.__setattr__(self, "b", _point("Spring.b", self.b))
        object.__setattr__(self, "k", _number("Spring.k", self.k))
        object.__setattr__(self, "length", _number("Spring.length", self.length, 0.0))


@dataclass(frozen=True)
class Damper:
    """A linear (viscous) damper between two points (see the module doc).

    Parameters
    ----------
    a, b : (link, r, angle)
        The points: link 1-4, r [in or m] from the link's base pin, angle [deg].
    c : float
        Damping coefficient [lb sec/in or N s/m].
    """

    a: Any
    b: Any
    c: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "a", _point("Damper.a", self.a))
        object.__setattr__(self, "b", _point("Damper.b", self.b))
        object.__setattr__(self, "c", _number("Damper.c", self.c))


def check_elements(v: Any) -> tuple[Spring | Damper, ...]:
    """``Scene.elements`` checked: a sequence of Spring and Damper, at most
    :data:`MAX_ELEMENTS` of each."""
    if isinstance(v, Spring | Damper | str | bytes):
        raise ValueError(f"Scene.elements = {v!r}: a sequence of sielaff.Spring and "
                         "sielaff.Damper")
    try:
        items = tuple(v)
    except TypeError:
        raise ValueError(f"Scene.elements = {v!r}: a sequence of sielaff.Spring and "
                         "sielaff.Damper") from None
    for i, e in enumerate(items):
        if not isinstance(e, Spring | Damper):
            raise ValueError(f"Scene.elements[{i}] = {e!r} is not a sielaff.Spring or "
                             "sielaff.Damper")
    for kind in (Spring, Damper):
        if sum(isinstance(e, kind) for e in items) > MAX_ELEMENTS:
            raise ValueError(f"Scene.elements: more than {MAX_ELEMENTS} "
                             f"{kind.__name__.lower()}s")
    return items


def _place(point, R1, R2, c2, s2, c3, s3, c4, s4, TH2D, TH3D, TH4D):
    """(offset from the base pin, position, velocity) of a point, each as (x, y)."""
    link, r, angle = point
    a = np.radians(angle)
    ca, sa = np.cos(a), np.sin(a)
    if link == 1:
        c, s, base, w, vbase = 1.0, 0.0, (0.0, 0.0), 0.0, (0.0, 0.0)
    elif link == 2:
        c, s, base, w, vbase = c2, s2, (0.0, 0.0), TH2D, (0.0, 0.0)
    elif link == 3:
        c, s, w = c3, s3, TH3D
        base, vbase = (R2 * c2, R2 * s2), (-R2 * s2 * TH2D, R2 * c2 * TH2D)
    else:
        c, s, base, w, vbase = c4, s4, (R1, 0.0), TH4D, (0.0, 0.0)
    px, py = r * (c * ca - s * sa), r * (s * ca + c * sa)
    return ((px, py), (base[0] + px, base[1] + py),
            (vbase[0] - w * py, vbase[1] + w * px))


def _element(e, *kin):
    """The element's offsets, L, dL/dt, tension and unit vector a -> b."""
    pa, xa, va = _place(e.a, *kin)
    pb, xb, vb = _place(e.b, *kin)
    dx, dy = xb[0] - xa[0], xb[1] - xa[1]
    length = np.hypot(dx, dy)
    ux, uy = dx / length, dy / length
    rate = ux * (vb[0] - va[0]) + uy * (vb[1] - va[1])
    tension = e.k * (length - e.length) if isinstance(e, Spring) else e.c * rate
    return pa, pb, length, rate, tension, ux, uy


_KIN = ("R1", "R2", "c2", "s2", "c3", "s3", "c4", "s4", "TH2D", "TH3D", "TH4D")


@step(provides=("fa32x_s", "fa32y_s", "fb34x_s", "fb34y_s", "foax_s", "foay_s", "fobx_s",
                "foby_s", "TORQ_ELEMENTS"),
      needs=("elements", "NELEMENTS", "R3", "R4", "s34") + _KIN,
      zero_when=("NELEMENTS",))
def _elements(elements, NELEMENTS, R3, R4, s34, R1, R2, c2, s2, c3, s3, c4, s4, TH2D, TH3D,
              TH4D):
    kin = (R1, R2, c2, s2, c3, s3, c4, s4, TH2D, TH3D, TH4D)
    per_link: dict[int, list[Any]] = {k: [0.0, 0.0, 0.0] for k in (1, 2, 3, 4)}
    for e in elements:
        pa, pb, _, _, t, ux, uy = _element(e, *kin)
        for (link, _, _), p, sign in ((e.a, pa, 1.0), (e.b, pb, -1.0)):
            fx, fy = sign * t * ux, sign * t * uy
            f = per_link[link]
            f[0] = f[0] + fx
            f[1] = f[1] + fy
            f[2] = f[2] + (p[0] * fy - p[1] * fx)
    (f2x, f2y, m2), (f3x, f3y, m3), (f4x, f4y, m4) = per_link[2], per_link[3], per_link[4]
    return pins(f2x, f2y, m2, f3x, f3y, m3, f4x, f4y, m4, R2, R3, R4, c2, s2, c3, s3, c4, s4,
                s34)


#: The per-element outputs: SPRINGk_L, SPRINGk_LD, SPRINGk_F, then DAMPERk_... .
ELEMENT_OUTPUTS = tuple(f"{kind}{k}_{q}" for kind in ("SPRING", "DAMPER")
                        for k in range(1, MAX_ELEMENTS + 1) for q in ("L", "LD", "F"))


@step(provides=ELEMENT_OUTPUTS, needs=("elements",) + _KIN, zero_when=("NELEMENTS",))
def _element_outputs(elements, R1, R2, c2, s2, c3, s3, c4, s4, TH2D, TH3D, TH4D):
    kin = (R1, R2, c2, s2, c3, s3, c4, s4, TH2D, TH3D, TH4D)
    out: dict[str, Any] = dict.fromkeys(ELEMENT_OUTPUTS, 0.0)
    count = {"SPRING": 0, "DAMPER": 0}
    for e in elements:
        kind = "SPRING" if isinstance(e, Spring) else "DAMPER"
        count[kind] += 1
        _, _, length, rate, tension, _, _ = _element(e, *kin)
        for q, v in (("L", length), ("LD", rate), ("F", tension)):
            out[f"{kind}{count[kind]}_{q}"] = v
    return tuple(out[n] for n in ELEMENT_OUTPUTS)


def _seed(scene: Any, mechanism: Any) -> dict[str, Any]:
    return {"elements": scene.elements, "NELEMENTS": float(len(scene.elements))}


EFFECT = Effect("springs and dampers", (step_of(_elements), step_of(_element_outputs)), _seed,
                parts={s: s + "_s" for s in ("fa32x", "fa32y", "fb34x", "fb34y", "foax",
                                             "foay", "fobx", "foby")} | {"torq": "TORQ_ELEMENTS"},
                torque="TORQ_ELEMENTS")
