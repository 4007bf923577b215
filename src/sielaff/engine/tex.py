"""TEX, the external torque on link 4 (in-lb or N m, CCW +): the 1966 program's one load.

The rocker's force step takes TEX directly (as statement 74 of the listing), so this
effect adds no part to the superposed sums; it gives TEX itself when the scene holds a
function of ATH4 (the report's own edit of statement 74), and TORQ_TEX, the share of TORQ
that TEX alone takes (for the breakdown; TORQ_INERTIA excludes it).
"""

from __future__ import annotations

from typing import Any

from sielaff.engine.registry import Effect, step, step_of
from sielaff.engine.statics import pins
from sielaff.engine.values import call_checked


@step(provides=("TEX",), needs=("tex_fn", "ATH4"))
def _external_torque(tex_fn, ATH4):
    """TEX = f(ATH4 in degrees), the report's statement 74 option."""
    return call_checked("Scene.tex", tex_fn, ATH4)


@step(provides=("TORQ_TEX",), needs=("TEX", "R2", "R3", "R4", "c2", "s2", "c3", "s3", "c4",
                                     "s4", "s34"), zero_when=("TEX",))
def _torque_for_tex(TEX, R2, R3, R4, c2, s2, c3, s3, c4, s4, s34):
    """The drive torque TEX alone takes (part of TORQ, for the breakdown)."""
    return pins(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, TEX, R2, R3, R4, c2, s2, c3, s3, c4,
                s4, s34)[8]


def _seed(scene: Any, mechanism: Any) -> dict[str, Any]:
    v = scene.tex
    return {"tex_fn": v} if callable(v) else {"TEX": v}


EFFECT = Effect("TEX", (step_of(_external_torque), step_of(_torque_for_tex)), _seed,
                torque="TORQ_TEX")
