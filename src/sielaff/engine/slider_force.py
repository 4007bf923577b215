"""FEX, an external force on the slider along its line (lb or N, +x positive): the gas
force of an engine, a press's work, a pump's pressure.  It plays the four-bar's TEX role
for the slider-crank: a constant, an array broadcasting against the crank angles, or a
function of XB (the slider's position [in or m]).  Its part of TORQ is ``TORQ_FEX``; its
reaction (on the cylinder head, the press's frame) is not in SHAK.
"""

from __future__ import annotations

from sielaff.engine.declare import number_effect, number_param
from sielaff.engine.registry import Effect, step, step_of
from sielaff.engine.values import call_checked


@step(provides=("FEX",), needs=("fex_fn", "XB"))
def _slider_force_of_position(fex_fn, XB):
    """FEX = f(XB), when the scene holds a function."""
    return call_checked("Scene.fex", fex_fn, XB)


@step(provides=("slider_loads",), needs=("FEX",), zero_when=("FEX",), per_link=True)
def _slider_loads(k, FEX):
    """FEX on the slider (link 4), along +x through B; nothing on the other links."""
    return (FEX, 0.0, 0.0) if k == 4 else (0.0, 0.0, 0.0)


EFFECT = Effect("slider force", (step_of(_slider_force_of_position), step_of(_slider_loads)),
                torque="TORQ_FEX", applies="slider_loads",
                params=(number_param("fex", "float, array or callable\n"
                                     "    External force on the slider along its line [lb or "
                                     "N], +x positive; a constant,\n    an array broadcasting "
                                     "against the crank angles, or a function of XB [in or m]."),),
                outputs={"FEX": ("force", "external force on the slider along +x"),
                         "TORQ_FEX": ("torque", "the part of TORQ the slider force FEX takes")},
                **number_effect("fex", "FEX", "XB", "FEX, force on the slider (+x)", "force",
                                "slider_force",
                                "slider_force = -500.0         # FEX on the slider, +x; lb or N"))
