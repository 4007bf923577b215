"""Gravity: each link's weight at its centre of mass, and the pin forces and drive torque
it takes.  ``gravity=(gx, gy)`` is the acceleration of gravity in the frame's axes, in
the mechanism's length unit per sec^2 (``(0.0, -386.088)`` for y up in the report's
in-lb-sec system, ``(0.0, -9.80665)`` in SI; ``"down"`` is standard gravity along -y in
the mechanism's units); off (None) as in 1966, and then no step here runs."""

from __future__ import annotations

from sielaff.engine.registry import step
from sielaff.engine.statics import pins


@step(provides=("fa32x_g", "fa32y_g", "fb34x_g", "fb34y_g", "foax_g", "foay_g", "fobx_g",
                "foby_g", "TORQ_GRAVITY"),
      needs=("GX", "GY", "GW", "W2", "W3", "W4", "RG2", "RG3", "RG4", "cd2", "sd2", "cd3", "sd3",
             "cd4", "sd4", "R2", "R3", "R4", "c2", "s2", "c3", "s3", "c4", "s4", "s34"),
      zero_when=("GX", "GY"))
def _gravity(GX, GY, GW, W2, W3, W4, RG2, RG3, RG4, cd2, sd2, cd3, sd3, cd4, sd4,
             R2, R3, R4, c2, s2, c3, s3, c4, s4, s34):
    loads = []
    for W, RG, cd, sd in ((W2, RG2, cd2, sd2), (W3, RG3, cd3, sd3), (W4, RG4, cd4, sd4)):
        fx, fy = W / GW * GX, W / GW * GY  # the weight m g, with m = W / GW
        loads += [fx, fy, RG * (cd * fy - sd * fx)]  # and its moment about the base pin
    return pins(*loads, R2, R3, R4, c2, s2, c3, s3, c4, s4, s34)
