"""The outputs: each vector as magnitude and direction (``VECTOR_STEPS``), and the
listing's print order (``RESULTS``).  Which names a model accepts (``OUTPUTS``) and which
need no force analysis (``KINEMATIC_OUTPUTS``) the model derives (``fourbar``)."""

from __future__ import annotations

import numpy as np

from sielaff.engine.arith import owned, put
from sielaff.engine.positions import _DEGREES
from sielaff.engine.registry import Step

#: Vectors reported as magnitude NAME and direction DNAME (degrees in [0, 360)).
VECTORS = ("VG2", "VA", "VG3", "VB", "VG4", "AG2", "AA", "AG3", "AB", "AG4",
           "FA32", "FB34", "FOA", "FOB", "SHAK")


def _magnitude(x, y):
    m = x * x  # np.hypot is ~7x slower; these magnitudes are far from overflow
    m += y * y
    return np.sqrt(m, out=m) if owned(m) else np.sqrt(m)


def _direction(x, y):
    """Direction of (x, y) in degrees, in [0, 360); 0 for the zero vector (as VECTOR).

    ``+ 0.0`` turns a -0.0 component into +0.0 (and nothing else): arctan2 of signed zeros
    is +-180 or -0, not the 0 a zero vector points at."""
    d = np.asarray(np.arctan2(y + 0.0, x + 0.0))
    d *= _DEGREES  # = np.degrees, in place
    d = np.add(d, 360.0, out=d, where=d < 0.0)
    d = put(d, 0.0, d >= 360.0)  # -tiny + 360 rounds to 360
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
    d = put(d, 0.0, d >= 360.0)  # -tiny mod 360 rounds to 360
    d = put(d, 0.0, rw == 0.0)
    d = put(d, np.nan, np.isnan(rw))  # where the loop cannot close
    d += 0.0  # -0.0 -> +0.0
    return d


def vector_steps(vectors: tuple[str, ...]) -> tuple[Step, ...]:
    """The magnitude and direction steps of ``vectors`` (a model's own list; those of
    :data:`ROTATING` by their pivot's rate, the others from their components)."""
    steps = []
    for name in vectors:
        xy = (name + "X", name + "Y")
        if name in ROTATING:
            r, line, adel, w = ROTATING[name]
            steps.append(Step(f"_magnitude_{name}", _rotating_magnitude, (name,), (r, w)))
            steps.append(Step(f"_direction_{name}", _rotating_direction, ("D" + name,),
                              (r, line, w) + ((adel,) if adel else ())))
        else:
            steps.append(Step(f"_magnitude_{name}", _magnitude, (name,), xy))
            steps.append(Step(f"_direction_{name}", _direction, ("D" + name,), xy))
    return tuple(steps)


#: Each vector's magnitude NAME and direction DNAME.
VECTOR_STEPS = vector_steps(VECTORS)


#: What ``analyze`` returns by default (``outputs=None``), in the listing's print
#: order: angles, angular rates, TEX, each vector as magnitude, direction and
#: components, then TORQ and the shaking moment.
RESULTS = (
    ("ATH2", "ATH3", "ATH4", "GAMMA", "TH3D", "TH4D", "TH3DD", "TH4DD", "TEX")
    + tuple(n for v in VECTORS for n in (v, "D" + v, v + "X", v + "Y"))
    + ("TORQ", "SHAKM")
)
