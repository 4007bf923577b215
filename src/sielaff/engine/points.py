"""The path, velocity and acceleration of any point on any link (coupler curves).

A point is placed like a centre of mass: ``r`` from its link's base pin (O2 for link 2,
A for link 3, O4 for link 4) at ``angle`` degrees CCW from the link's line.  With b its
base pin, w and a the link's angular velocity and acceleration::

    P = b + r e^{i(th + angle)},   V = V_b + i w (P - b),   A = A_b + (i a - w^2)(P - b)

``r`` and ``angle`` may be arrays (many points at once) that broadcast with the crank
angles, e.g. ``r=np.linspace(0, 16, 9)[:, None]`` for nine points along the coupler.
The report's "accelerations of many points along a link ... by incrementing the length
of RG" is one call.  Lengths in the mechanism's unit, velocities per sec, accelerations
per sec^2, in the frame's axes.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sielaff.engine.analysis import analyze
from sielaff.mechanism import Mechanism

__all__ = ["point_motion"]


def point_motion(mechanism: Mechanism, ath2: Any, link: int, r: Any = 0.0, angle: Any = 0.0,
                 *, th2dd: Any = 0.0, branch: str = "open") -> dict[str, np.ndarray]:
    """``{"X", "Y", "VX", "VY", "AX", "AY"}`` of the point (see the module doc)."""
    if link not in (2, 3, 4):
        raise ValueError(f"link = {link!r}: a point is on link 2, 3 or 4")
    m = mechanism
    want = ["ATH2", "ATH3", "ATH4", "TH3D", "TH4D", "TH3DD", "TH4DD", "VAX", "VAY", "AAX",
            "AAY"]
    k = analyze(m, ath2, want, th2dd=th2dd, branch=branch)
    th = {2: k["ATH2"], 3: k["ATH3"], 4: k["ATH4"]}[link]
    w = {2: m.TH2D + 0.0 * th, 3: k["TH3D"], 4: k["TH4D"]}[link]
    a = {2: np.asarray(th2dd, dtype=float) + 0.0 * th, 3: k["TH3DD"], 4: k["TH4DD"]}[link]
    zero = 0.0 * th
    t2 = np.radians(k["ATH2"])
    base = {2: (zero, zero), 3: (m.R2 * np.cos(t2), m.R2 * np.sin(t2)), 4: (m.R1 + zero, zero)}
    vb = {2: (zero, zero), 3: (k["VAX"], k["VAY"]), 4: (zero, zero)}[link]
    ab = {2: (zero, zero), 3: (k["AAX"], k["AAY"]), 4: (zero, zero)}[link]
    phi = np.radians(th + np.asarray(angle, dtype=float))
    dx, dy = np.asarray(r, dtype=float) * np.cos(phi), np.asarray(r, dtype=float) * np.sin(phi)
    bx, by = base[link]
    with np.errstate(all="ignore"):  # at a toggle the rates are infinite: answers, as analyze
        return {"X": bx + dx, "Y": by + dy,
                "VX": vb[0] - w * dy, "VY": vb[1] + w * dx,
                "AX": ab[0] - a * dy - w * w * dx, "AY": ab[1] + a * dx - w * w * dy}
