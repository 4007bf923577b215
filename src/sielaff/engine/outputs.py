"""The outputs: each vector as magnitude and direction, and the catalogue of names
(``RESULTS`` in the listing's order, every accepted name in ``OUTPUTS``, the force-free
``KINEMATIC_OUTPUTS``)."""

from __future__ import annotations

import numpy as np

from sielaff.engine import (  # noqa: F401 (each registers its steps)
    accelerations,
    crank,
    forces,
    gravity,
    inertia,
    loads,
    positions,
    velocities,
)
from sielaff.engine.positions import _DEGREES
from sielaff.engine.registry import PROVIDER, Step, _depends_on, _register
from sielaff.mechanism import FIELD_NAMES

#: Vectors reported as magnitude NAME and direction DNAME (degrees in [0, 360)).
VECTORS = ("VG2", "VA", "VG3", "VB", "VG4", "AG2", "AA", "AG3", "AB", "AG4",
           "FA32", "FB34", "FOA", "FOB", "SHAK")


def _magnitude(x, y):
    m = x * x  # np.hypot is ~7x slower; these magnitudes are far from overflow
    m += y * y
    return np.sqrt(m, out=m) if isinstance(m, np.ndarray) else np.sqrt(m)


def _direction(x, y):
    """Direction of (x, y) in degrees, in [0, 360); 0 for the zero vector (as VECTOR)."""
    d = np.asarray(np.arctan2(y, x))
    d *= _DEGREES  # = np.degrees, in place
    np.add(d, 360.0, out=d, where=d < 0.0)
    np.copyto(d, 0.0, where=d >= 360.0)  # -tiny + 360 rounds to 360
    d += 0.0  # -0.0 -> +0.0
    return d


#: Velocities of points on links 2 and 4, which turn about fixed pivots: the magnitude is
#: r |w| and the direction the line to the point plus 90 degrees (w > 0) or minus 90, so
#: neither needs a square root or an atan2 (the algebraic minimum; docs/performance.md).
#: name -> (distance, line angle, its offset ADEL or None, angular velocity)
ROTATING = {"VA": ("R2", "ATH2", None, "TH2D"), "VG2": ("RG2", "ATH2", "ADEL2", "TH2D"),
            "VB": ("R4", "ATH4", None, "TH4D"), "VG4": ("RG4", "ATH4", "ADEL4", "TH4D")}


def _rotating_magnitude(r, w):
    return np.abs(r * w)


def _rotating_direction(r, line, w, adel=0.0):
    """The velocity's direction, degrees in [0, 360); 0 where it is the zero vector (as
    VECTOR): the line's angle plus 90 degrees for r w > 0, minus 90 for r w < 0."""
    rw = np.asarray(r * w)
    d = np.add(line, adel)
    d = np.where(rw > 0.0, d + 90.0, d - 90.0)
    d = np.mod(d, 360.0)
    np.copyto(d, 0.0, where=d >= 360.0)  # -tiny mod 360 rounds to 360
    np.copyto(d, 0.0, where=rw == 0.0)
    np.copyto(d, np.nan, where=np.isnan(rw))  # where the loop cannot close
    d += 0.0  # -0.0 -> +0.0
    return d


for _name in VECTORS:
    _xy = (_name + "X", _name + "Y")
    if _name in ROTATING:
        _r, _line, _adel, _w = ROTATING[_name]
        _register(Step(f"_magnitude_{_name}", _rotating_magnitude, (_name,), (_r, _w)))
        _register(Step(f"_direction_{_name}", _rotating_direction, ("D" + _name,),
                       (_r, _line, _w) + ((_adel,) if _adel else ())))
        continue
    _register(Step(f"_magnitude_{_name}", _magnitude, (_name,), _xy))
    _register(Step(f"_direction_{_name}", _direction, ("D" + _name,), _xy))


del _name, _xy, _r, _line, _adel, _w


#: Inputs seeded into the namespace (plus ``TEX`` or ``tex_fn``, ``TH2DD`` or ``th2dd_fn``).
INPUTS = ("ATH2",) + FIELD_NAMES + ("BRANCH", "GW", "GX", "GY", "loads", "NLOADS")


#: What ``analyze`` returns by default (``outputs=None``), in the listing's print
#: order: angles, angular rates, TEX, each vector as magnitude, direction and
#: components, then TORQ and the shaking moment.
RESULTS = (
    ("ATH2", "ATH3", "ATH4", "GAMMA", "TH3D", "TH4D", "TH3DD", "TH4DD", "TEX")
    + tuple(n for v in VECTORS for n in (v, "D" + v, v + "X", v + "Y"))
    + ("TORQ", "SHAKM")
)


#: Every name ``analyze`` accepts: RESULTS plus the listing's intermediate
#: quantities (inertia loads FG2X.., TI3, TI4, superposition parts FP34X..,
#: FPP32X.., F3P21X, TP2, TPP2).
OUTPUTS = RESULTS + tuple(sorted(n for n in PROVIDER if n[0].isupper() and n not in RESULTS))


#: The results that need no masses, inertias or TEX: no force analysis.
KINEMATIC_OUTPUTS = tuple(
    n for n in RESULTS
    if n != "TEX" and not _depends_on(n, frozenset(("W2", "W3", "W4", "ZI2", "ZI3", "ZI4",
                                                     "TEX", "tex_fn")))
)
