"""The slider-crank as a model: the linkage engine's steps for its topology
(:data:`sielaff.slider_crank.TOPOLOGY`: the crank, an RRP dyad on the frame's line
y = offset), and one line per effect it takes (gravity, loads, the slider force FEX,
springs and dampers).

The crank O2-A turns about the origin; the rod A-B; the slider (link 4, a point mass at
B) slides on the line y = ``offset``.  Positions, rates and forces are the linkage
engine's (engine/dyads.py, engine/joints.py); what is the slider-crank's own here is its
names (XB, VXB, AXB for the slider's position, velocity and acceleration along +x; FN and
MN the guide's force and couple on the slider; FOA the crank's force on the frame) and its
default outputs.  The closed forms they agree with, the textbook's
(tests/slider_reference.py differentiates them with sympy):

    XB = R2 cos th2 + R3 cos th3,   sin th3 = (offset - R2 sin th2) / R3
    TH3D = -R2 cos th2 TH2D / (R3 cos th3)
    VXB = -R2 sin th2 TH2D - R3 sin th3 TH3D
"""

from __future__ import annotations

from sielaff.engine.linkage_model import finish, friction_effect, linkage_model
from sielaff.engine.registry import Step
from sielaff.quantities import declare
from sielaff.slider_crank import TOPOLOGY, SliderCrank, full_turn_failure, validate_slider

__all__ = ["SLIDER_CRANK", "SLIDER_RESULTS"]

#: Vectors reported as magnitude, direction and components.
_VECTORS = ("VG2", "VA", "VG3", "AG2", "AA", "AG3", "FA32", "FB34", "FOA", "SHAK")

#: What ``analyze`` gives a slider-crank by default, in print order.
SLIDER_RESULTS = (("ATH2", "ATH3", "TH3D", "TH3DD", "XB", "VXB", "AXB")
                  + tuple(n for v in _VECTORS for n in (v, "D" + v, v + "X", v + "Y"))
                  + ("FN", "MN", "TORQ", "SHAKM"))

for _name, _kind, _text in (
        ("XB", "length", "the slider's position B from O2 along +x"),
        ("VXB", "speed", "the slider's velocity along +x"),
        ("AXB", "acceleration", "the slider's acceleration along +x"),
        ("FN", "force", "the guide's force on the slider, normal to the line, +y"),
        ("MN", "torque", "the guide's couple on the slider, CCW +")):
    declare(_name, _kind, _text)


def _same(x):
    return x + 0.0


#: The slider-crank's model.
SLIDER_CRANK = linkage_model(TOPOLOGY, "slider-crank", mechanism=SliderCrank,
                             validate=validate_slider, full_turn=full_turn_failure,
                             results=SLIDER_RESULTS)
SLIDER_CRANK.add(Step("_slider_velocity", _same, ("VXB",), ("VBX",)),
                 Step("_slider_acceleration", _same, ("AXB",), ("ABX",)))
SLIDER_CRANK.add_effect("gravity")
SLIDER_CRANK.add_effect("loads")
SLIDER_CRANK.add_effect("slider_force")
SLIDER_CRANK.add_effect("elements")
SLIDER_CRANK.add_effect(friction_effect(SLIDER_CRANK))
finish(SLIDER_CRANK)
