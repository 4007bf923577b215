"""TEX, the external torque on link 4 (in-lb or N m, CCW +): the 1966 program's one load.

The rocker's force step takes TEX directly (as statement 74 of the listing), so this
effect adds no part to the superposed sums; it gives TEX itself when the scene holds a
function of ATH4 (the report's own edit of statement 74), and TORQ_TEX, the share of TORQ
that TEX alone takes (for the breakdown; TORQ_INERTIA excludes it).
"""

from __future__ import annotations

from sielaff.engine.declare import number_effect, number_param
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


EFFECT = Effect("TEX", (step_of(_external_torque), step_of(_torque_for_tex)),
                torque="TORQ_TEX",
                params=(number_param("tex", "float, array or callable\n"
                                     "    External torque on link 4 [in-lb or N m], CCW +; a "
                                     "constant, an array broadcasting\n    against the crank "
                                     "angles, or a function of ATH4 [deg]."),),
                outputs={"TEX": ("torque", "external torque on link 4, CCW + (0 in the 1966 "
                                           "program)"),
                         "TORQ_TEX": ("torque", "the part of TORQ the torque TEX on link 4 "
                                                "takes")},
                columns=lambda s: ("TORQ_TEX",), in_1966=True,
                **number_effect("tex", "TEX", "THETA 4", "TEX, torque on link 4 (CCW +)",
                                "torque", "tex",
                                "tex = 0.0                     # torque on the rocker, CCW +"))
