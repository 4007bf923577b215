"""The outputs: each vector as magnitude and direction (``VECTOR_STEPS``), and the
listing's print order (``RESULTS``).  Which names a model accepts (``OUTPUTS``) and which
need no force analysis (``KINEMATIC_OUTPUTS``) the model derives (``fourbar``)."""

from __future__ import annotations

import numpy as np

from sielaff.engine.arith import mod360, owned, put
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
#: neither needs a square root or an atan2 (the algebraic minimum).
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
    d = np.add(d, np.where(rw > 0.0, 90.0, -90.0), out=d) if owned(d) else np.add(
        d, np.where(rw > 0.0, 90.0, -90.0))
    d = mod360(d)
    d = put(d, 0.0, d >= 360.0)  # -tiny mod 360 rounds to 360
    d = put(d, 0.0, rw == 0.0)
    d = put(d, np.nan, np.isnan(rw))  # where the loop cannot close
    d += 0.0  # -0.0 -> +0.0
    return d


#: Accelerations of points on links 2 and 4 (fixed pivots): a point at r from the pivot,
#: on a link turning at w with angular acceleration a, accelerates r (w^4 + a^2)^(1/2)
#: towards the line's angle plus atan2(a, -w^2), the same turn for every point of the
#: link: one square root and one atan2 per link, not per point (the algebraic minimum).
#: name -> (distance, line angle, its offset ADEL or None, the link)
PIVOTED = {"AA": ("R2", "ATH2", None, 2), "AG2": ("RG2", "ATH2", "ADEL2", 2),
           "AB": ("R4", "ATH4", None, 4), "AG4": ("RG4", "ATH4", "ADEL4", 4)}
#: each such link's angular velocity and acceleration
PIVOT_RATES = {2: ("TH2D", "TH2DD"), 4: ("TH4D", "TH4DD")}


def _turn(w, a):
    """A link's acceleration turn: (w^4 + a^2)^(1/2) [1/sec^2], what a point's distance
    from the pivot is multiplied by, and atan2(a, -w^2) [deg], the angle from the line
    to the point's acceleration."""
    w2 = w * w
    h = np.sqrt(w2 * w2 + a * a)
    phi = np.asarray(np.arctan2(a + 0.0, -w2))
    phi *= _DEGREES  # = np.degrees
    return h, phi


def _pivoted_direction(r, line, h, phi, adel=0.0):
    """The acceleration's direction, degrees in [0, 360); 0 where it is the zero vector
    (as VECTOR): the line's angle (plus ADEL) plus the link's turn, 180 more for r < 0."""
    d = np.add(line, np.add(adel, np.add(phi, np.where(r < 0.0, 180.0, 0.0))))
    d = mod360(d)
    d = put(d, 0.0, d >= 360.0)  # -tiny mod 360 rounds to 360
    d = put(d, 0.0, r * h == 0.0)
    d = put(d, np.nan, np.isnan(h))  # where the loop cannot close
    d += 0.0  # -0.0 -> +0.0
    return d


def vector_steps(vectors: tuple[str, ...]) -> tuple[Step, ...]:
    """The magnitude and direction steps of ``vectors`` (a model's own list; those of
    :data:`ROTATING` by their pivot's rate, those of :data:`PIVOTED` by their link's
    turn, the others from their components)."""
    steps = []
    for k in sorted({PIVOTED[n][3] for n in vectors if n in PIVOTED}):
        w, a = PIVOT_RATES[k]
        steps.append(Step(f"_turn{k}", _turn, (f"turn_h{k}", f"turn_phi{k}"), (w, a), (w, a),
                          ((w, a),)))
    for name in vectors:
        xy = (name + "X", name + "Y")
        if name in PIVOTED:
            r, line, adel, k = PIVOTED[name]
            steps.append(Step(f"_magnitude_{name}", _rotating_magnitude, (name,),
                              (r, f"turn_h{k}")))
            steps.append(Step(f"_direction_{name}", _pivoted_direction, ("D" + name,),
                              (r, line, f"turn_h{k}", f"turn_phi{k}")
                              + ((adel,) if adel else ())))
        elif name in ROTATING:
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
