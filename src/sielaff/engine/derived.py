"""Quantities derived from the engine's outputs over a whole revolution.

``cycle_work``: the integral of the driving torque over one revolution, which is zero
when TEX = 0 and the crank speed is constant (the report's energy argument).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sielaff.engine.analysis import analyze
from sielaff.engine.scene import Scene, scene_from
from sielaff.mechanism import Mechanism

#: The revolution's grid, degrees.
GRID_STEP = 0.1


def revolution(step: float = GRID_STEP) -> np.ndarray:
    """Crank angles 0, step, ..., 360 (degrees, both ends)."""
    n = round(360.0 / step)
    return np.linspace(0.0, 360.0, n + 1)


def cycle_work(mechanism: Mechanism, step: float = GRID_STEP, *, scene: Scene | None = None,
               **keywords: Any) -> tuple[float, float]:
    """(integral of TORQ, integral of |TORQ|) d(THETA 2) over one revolution, in-lb.

    Trapezoid rule on a ``step``-degree grid, THETA 2 in radians; ``scene``: the Scene
    (or ``analyze``'s keywords).
    """
    sc = scene_from(scene, keywords, "cycle_work")
    th = revolution(step)
    torq = analyze(mechanism, th, ["TORQ"], scene=sc)["TORQ"]
    x = np.radians(th)
    return float(np.trapezoid(torq, x)), float(np.trapezoid(np.abs(torq), x))
