"""External loads: forces and torques on links 2, 3 and 4, placed like RG and ADEL.

``Load(link, r, angle, fx, fy, torque)``: the force (fx, fy), in the frame's axes, acts
at the point ``r`` from the link's base pin (O2, A, O4) at ``angle`` degrees CCW from
the link's line; ``torque`` is a pure torque on the link, CCW +.  Each of r, angle, fx,
fy and torque may be a constant, an array that broadcasts with the crank angles, or a
function of THETA 2 in degrees.  ``Scene(loads=[...])`` sums them per link and solves
the pin forces and drive torque they take (``statics.pins``): the effect's part
``TORQ_LOADS`` of TORQ.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from sielaff.engine.registry import Effect, step, step_of
from sielaff.engine.statics import pins
from sielaff.engine.values import call_checked, check_value


@dataclass(frozen=True)
class Load:
    """A force and a torque on one moving link (see the module doc).

    Parameters
    ----------
    link : {2, 3, 4}
        The link it acts on.
    r : float, array or callable
        Distance of the point of application from the link's base pin [in or m].
    angle : float, array or callable
        Angle of that point from the link's line [deg], CCW +.
    fx, fy : float, array or callable
        The force in the frame's axes [lb or N].
    torque : float, array or callable
        A pure torque on the link [in-lb or N m], CCW +.
    """

    link: int
    r: Any = 0.0
    angle: Any = 0.0
    fx: Any = 0.0
    fy: Any = 0.0
    torque: Any = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.link, bool) or self.link not in (2, 3, 4):
            raise ValueError(f"Load.link = {self.link!r}: loads act on link 2, 3 or 4")
        for name in ("r", "angle", "fx", "fy", "torque"):
            v = getattr(self, name)
            if not callable(v):
                object.__setattr__(self, name, check_value(f"Load.{name}", v))

    def value(self, name: str, ath2: Any) -> Any:
        """The field ``name`` at crank angles ``ath2`` [deg] (a callable is called, and
        its answer checked where the angle is a number)."""
        v = getattr(self, name)
        if not callable(v):
            return np.asarray(v, dtype=float)
        return call_checked(f"Load.{name}", v, ath2)


@step(provides=("fa32x_l", "fa32y_l", "fb34x_l", "fb34y_l", "foax_l", "foay_l", "fobx_l",
                "foby_l", "TORQ_LOADS"),
      needs=("loads", "NLOADS", "ATH2", "R2", "R3", "R4", "c2", "s2", "c3", "s3", "c4", "s4",
             "s34"),
      zero_when=("NLOADS",))
def _loads(loads, NLOADS, ATH2, R2, R3, R4, c2, s2, c3, s3, c4, s4, s34):
    lines = {2: (c2, s2), 3: (c3, s3), 4: (c4, s4)}
    per_link: dict[int, list[Any]] = {2: [0.0, 0.0, 0.0], 3: [0.0, 0.0, 0.0],
                                      4: [0.0, 0.0, 0.0]}
    for load in loads:
        c, s = lines[load.link]
        r, fx, fy = load.value("r", ATH2), load.value("fx", ATH2), load.value("fy", ATH2)
        a = np.radians(load.value("angle", ATH2))
        px = r * (c * np.cos(a) - s * np.sin(a))  # the point, from the base pin
        py = r * (s * np.cos(a) + c * np.sin(a))
        f = per_link[load.link]
        f[0] = f[0] + fx
        f[1] = f[1] + fy
        f[2] = f[2] + (px * fy - py * fx) + load.value("torque", ATH2)
    (f2x, f2y, m2), (f3x, f3y, m3), (f4x, f4y, m4) = per_link[2], per_link[3], per_link[4]
    return pins(f2x, f2y, m2, f3x, f3y, m3, f4x, f4y, m4, R2, R3, R4, c2, s2, c3, s3, c4, s4,
                s34)


def _seed(scene: Any, mechanism: Any) -> dict[str, Any]:
    return {"loads": scene.loads, "NLOADS": float(len(scene.loads))}


EFFECT = Effect("loads", (step_of(_loads),), _seed,
                parts={s: s + "_l" for s in ("fa32x", "fa32y", "fb34x", "fb34y", "foax",
                                             "foay", "fobx", "foby")} | {"torq": "TORQ_LOADS"},
                torque="TORQ_LOADS")
