"""The modern engine: Sielaff's crank-rocker model, vectorised with numpy.

``analyze(mechanism, ath2, outputs=None, tex=0.0)`` returns a dict of numpy
arrays keyed by the listing's names (``ATH3``, ``TH3D``, ``VG3``, ``DVG3``,
``FA32X``, ``TORQ``, ...).  Every field of the :class:`~sielaff.mechanism.Mechanism`
may be an array; fields, ``ath2`` (degrees, any shape, any value -- 400 and
-320 are the same position as 40) and ``tex`` broadcast together and every
returned array has the common broadcast shape.

The model is the 1966 program's (see the report, pp. 7-15 and Appendix C);
what the engine does differently is *how* it evaluates it:

Geometry, without ARCCOS
    Frame O2 = 0, O4 = R1, A = R2 e^{i th2}.  Let ``d = O4 - A`` (the line the
    report calls ZL, with direction ``beta = atan2(-R2 sin th2, R1 - R2 cos th2)``,
    which is ``-BETA`` in Case I and ``+BETA`` in Case II of the listing).  In
    the triangle A, B, O4 (sides ZL, R3, R4) the listing's angles PSI (at A)
    and ZLAM (at O4) satisfy::

        2 ZL R3 e^{i PSI}  = P + iH,   P = ZL^2 + R3^2 - R4^2
        2 ZL R4 e^{i ZLAM} = Q + iH,   Q = ZL^2 + R4^2 - R3^2
        H^2 = (ZL+R3+R4)(ZL+R3-R4)(R3+R4-ZL)(R4+ZL-R3)     (Heron, >= 0)

    and the listing's open branch (TH3 = PSI -+ BETA, TH4 = PI - ZLAM -+ BETA)
    is in both cases ``th3 = beta + PSI``, ``th4 = beta + pi - ZLAM``.  So
    ``e^{i th3} = d (P + iH) / (2 ZL^2 R3)`` and ``R4 e^{i th4} = R3 e^{i th3} - d``:
    the sines and cosines of th3 and th4 come from products, not from
    ARCCOS/SIN/COS.  The factored Heron product is accurate near the toggle
    (coupler and rocker in line) where ARCCOS of a cosine near +-1 is not;
    a product pushed below zero by roundoff (H^2 > -16 eps (R1+R2+R3+R4)^4) is clamped to
    0, a clearly negative one (the loop cannot close) gives NaN.  With
    ``mu`` the angle at B (the transmission angle, ``GAMMA``)::

        sin(th3 - th4) = -H / (2 R3 R4),  cos(th3 - th4) = (R3^2 + R4^2 - ZL^2) / (2 R3 R4)

    ATH3 and ATH4 are reported in (-90, 270] degrees, the range the listing's
    PSI -+ BETA and PI - ZLAM -+ BETA fall in for a crank-rocker (R1 > R2).
    Unlike the 1966 program (which takes Case II for any TH2 >= PI, e.g. 370
    degrees) the engine reduces ATH2 modulo 360 first (exactly, with fmod), so
    ATH2 + 360 k gives bit-identical results.  Positions where the loop cannot
    close give NaN (counted: ``Results.not_assembled``); at an exact toggle the
    positions are finite but the rates divide by sin(th3 - th4) = 0 and come out
    infinite or NaN, as the linkage locks there (numpy's floating-point warnings are
    silenced inside ``analyze``: these are answers, not accidents).

Velocities and accelerations
    The report's (pp. 7-10 and Appendix B; the listing's TH3D .. AG3Y), with
    TH2DD = 0; the differences of angles come from products of the sines and
    cosines above, so the only trigonometry is cos and sin of th2.

Forces (D'Alembert and superposition, as the listing)
    Each link is given its mass alone, the other two are weightless
    two-force members; the three solutions are added.  The 1966 program
    solves the link-4 step with ``TAN3 = STH3/CTH3`` (and 0.9E+25 when
    CTH3 = 0); the engine writes F34 = f (cos th3, sin th3) and solves the
    moment equation about O4 (R4 x F34 + RG4 x FG4 + TI4 + TEX = 0) for the
    scalar f::

        f R4 sin(th3 - th4) = RG4Y FG4X - RG4X FG4Y - TI4 - TEX

    which is defined for every position (R4 sin(th3 - th4) vanishes only at a
    toggle, where the mechanism locks).  Link 3 likewise with
    F43 = g (cos th4, sin th4) from moments about A.

Moments of inertia
    The listing applies, to link k, the inertia force -ZMk aGk *at Gk* and
    the inertia torque -ZIk THkDD.  That is the dynamics of a rigid body whose
    ZIk is the moment of inertia about its centre of mass Gk, for every
    link -- even though the report's card description says "about O2, A, O4".
    (For link 4, read literally, "ZI4 about O4" would count m4 RG4^2 TH4DD
    twice; for link 2 it does not matter because TH2DD = 0; for link 3 the
    listing takes moments about A but includes RG3 x FG3, so ZI3 is about
    G3.)  The engine reproduces the listing, so the identity it satisfies
    exactly is the power balance with centroidal ZI::

        TORQ TH2D + TEX TH4D = sum_k ZMk aGk . vGk + ZI3 TH3DD TH3D + ZI4 TH4DD TH4D

Shaking moment ``SHAKM`` (not printed in 1966; Norton's FOURBAR has it)
    The moment about O2 of everything the moving links exert on the frame:
    FOA acts at O2 (no moment), FOB at O4 = (R1, 0) (moment R1 FOBY), and the
    motor, whose stator is on the frame, pushes back with -TORQ::

        SHAKM = R1 FOBY - TORQ        (in-lb, + CCW)

    TEX is taken to come from outside the frame (it is an "external" torque on
    link 4), so by the angular momentum theorem about the fixed point O2::

        SHAKM = TEX - dH/dt,   dH/dt = sum_k (rGk x ZMk aGk + ZIk THkDD)

    i.e. SHAKM = -dH/dt when TEX = 0.  If the load torque TEX is reacted on
    the frame, the frame feels SHAKM - TEX = -dH/dt instead.

How the work is organised
    The computation is a set of small *steps*; each declares, with the
    ``@step`` decorator, the quantities it ``needs`` and ``provides``.  A step
    can also declare ``zero_when``: if all those quantities are identically
    zero (a massless link: W3 = ZI3 = 0), the step's results are zero and it
    is neither run nor are its needs computed.  A :class:`Model` holds the steps
    and the *effects* a scene may call for (``fourbar.FOURBAR`` is the 1966
    four-bar; an effect is one module and one registration line there).
    ``analyze`` checks the request once (:func:`prepare`), seeds a namespace
    with the inputs and the :class:`Scene`, computes the dependency closure of
    the requested outputs (:func:`plan`), and runs the steps in dependency
    order.  Asking for kinematics therefore never touches the force steps.
    ``STEP_CALLS`` (the default model's ``calls``) counts the step runs; a test
    that needs a spy or a fault in a step runs ``analyze(..., model=
    FOURBAR.replacing(_force_link4=spy))``.
"""

from __future__ import annotations

from sielaff.engine import forces
from sielaff.engine.analysis import (
    AssemblyWarning,
    Request,
    Results,
    analyze,
    model_for,
    plan,
    prepare,
)
from sielaff.engine.classify import KINDS, LinkageClass, linkage_class
from sielaff.engine.elements import Damper, Spring
from sielaff.engine.fourbar import FOURBAR, INPUTS, KINEMATIC_OUTPUTS, OUTPUTS
from sielaff.engine.friction import FrictionWarning, PinFriction
from sielaff.engine.loads import Load
from sielaff.engine.outputs import RESULTS, VECTORS
from sielaff.engine.points import point_motion
from sielaff.engine.positions import reachable
from sielaff.engine.registry import Effect, Model, step
from sielaff.engine.scene import Scene, scene_of
from sielaff.engine.slider_crank import SLIDER_CRANK
from sielaff.quantities import G

#: The slider-crank's Scene (its model's fields: branch, th2dd, gravity, loads, fex,
#: elements).
SliderCrankScene = scene_of(SLIDER_CRANK)



def scene_for(mechanism: object) -> type:
    """The Scene type of ``mechanism``'s model (``Scene`` for a four-bar, the slider-crank's
    ``SliderCrankScene``, ...): ``scene_for(m)(gravity="down")``."""
    return scene_of(model_for(mechanism))


#: How many times each step of the default model has run (by step name); tests reset it.
STEP_CALLS = FOURBAR.calls
#: The default model's steps.
STEPS = FOURBAR.steps

__all__ = [
    "FOURBAR",
    "SLIDER_CRANK",
    "SliderCrankScene",
    "model_for",
    "scene_for",
    "Effect",
    "Model",
    "Request",
    "Scene",
    "prepare",
    "forces",
    "G",
    "INPUTS",
    "KINDS",
    "LinkageClass",
    "Load",
    "PinFriction",
    "FrictionWarning",
    "Spring",
    "Damper",
    "KINEMATIC_OUTPUTS",
    "OUTPUTS",
    "RESULTS",
    "STEPS",
    "STEP_CALLS",
    "VECTORS",
    "AssemblyWarning",
    "Results",
    "analyze",
    "linkage_class",
    "plan",
    "point_motion",
    "reachable",
    "step",
]
