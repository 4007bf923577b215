"""A slider-crank's forces against a published worked example with printed numbers.

Khurmi & Gupta, *Theory of Machines*, 14th ed. (Eurasia/S. Chand, 2009), Example 15.7,
p. 533: a horizontal steam engine, crank 300 mm, connecting rod 1.2 m, reciprocating mass
250 kg, 250 rpm, a pressure difference of 0.35 N/mm^2 on a 0.5 m piston, the crank 60 deg
from the inner dead centre; the rod's mass neglected, no gravity.  Printed: pressure on
the slide bars 10.97 kN, thrust in the connecting rod 50.65 kN, tangential force on the
crank pin 48.30 kN, turning moment on the crank shaft 14.491 kN m.  As reproduced by the
FOSSEE Python Textbook Companion (github.com/FOSSEE/Python-Textbook-Companions at
d34b2ae7, Theory_Of_Machines_by_R._S._Khurmi_And_J._K._Gupta/ch15.ipynb, whose saved
output holds these numbers); the book works the piston's acceleration by the usual
two-term series, which differs from the exact motion the engine solves by under 0.1 % here,
so the printed 4-5 digits are met to 1E-3.

The book's frame mapped onto the SliderCrank's: theta from the inner dead centre is the
crank pointing toward the piston, THETA 2 = 0 with the slider on +x (the open branch), so
THETA 2 = 60 deg, CCW.  The steam pushes the piston toward the crank on this stroke: FEX
(the force on the slider along +x) = -p A.  The book's magnitudes are the engine's |FN|
(the guide on the slider), the rod force FB34 = FA32 (a massless rod), TORQ / R2 (the
tangential force) and TORQ, negative: the engine drives the shaft, so the torque that
would hold the crank at constant speed is the turning moment reversed
(docs/conventions.md).
"""

from __future__ import annotations

import math

import pytest

from sielaff import SliderCrank, analyze, scene_for

ENGINE = SliderCrank(W2=0.0, W3=0.0, W4=250.0, ZI2=0.0, ZI3=0.0, R2=0.3, R3=1.2, offset=0.0,
                     ADEL2=0.0, ADEL3=0.0, RG2=0.0, RG3=0.0, TH2D=250.0 * 2.0 * math.pi / 60.0,
                     units="SI")
#: p A: 0.35 N/mm^2 on a 0.5 m bore [N]
GAS = 0.35e6 * math.pi * 0.25 ** 2


def test_khurmi_gupta_example_15_7():
    r = analyze(ENGINE, 60.0, scene=scene_for(ENGINE)(fex=-GAS))
    assert float(r["FN"]) == pytest.approx(10.97e3, rel=1e-3)     # on the slide bars
    assert float(r["FB34"]) == pytest.approx(50.65e3, rel=1e-3)   # thrust in the rod
    assert float(r["FA32"]) == pytest.approx(50.65e3, rel=1e-3)
    assert -float(r["TORQ"]) / ENGINE.R2 == pytest.approx(48.30e3, rel=1e-3)
    assert float(r["TORQ"]) == pytest.approx(-14.491e3, rel=1e-3)  # the turning moment


def test_the_example_is_not_met_without_the_gas_force_or_reversed():
    """The check can fail: the wrong sign of FEX, or none, misses the printed rod thrust."""
    S = scene_for(ENGINE)
    for scene in (S(), S(fex=GAS)):
        r = analyze(ENGINE, 60.0, scene=scene)
        assert float(r["FB34"]) != pytest.approx(50.65e3, rel=1e-2)
