"""Forces: the pin forces, the driving torque and the shaking force and moment.

Each link's inertia is taken alone and the three solutions added (superposition, as the
listing); see the package doc, "Forces", for the moment equations solved.  The totals
add ``fa32x_e``.. ``torq_e``, the sums of what the scene's effects add (the model derives
the step that sums them from the registered effects).  Forces in lb
(which body each acts on: docs/conventions.md), torques in in-lb, CCW +.
"""

from __future__ import annotations

from sielaff.engine.registry import step
from sielaff.engine.statics import plus


@step(
    provides=("FP34X", "FP34Y", "FP32X", "FP32Y", "FP21X", "FP21Y", "FP41X", "FP41Y", "TP2"),
    needs=("FG4X", "FG4Y", "TI4", "TEX", "RG4", "cd4", "sd4", "R2", "R4", "c2", "s2",
           "c3", "s3", "s34"),
    zero_when=("FG4X", "FG4Y", "TI4", "TEX"),
)
def _force_link4(FG4X, FG4Y, TI4, TEX, RG4, cd4, sd4, R2, R4, c2, s2, c3, s3, s34):
    """Only link 4 has mass (and TEX): link 3 is a two-force member, F34 = f e^{i th3}.

    Moments about O4:  R4 x F34 + RG4 x FG4 + TI4 + TEX = 0, R4 x F34 = f R4 sin(th3 - th4).
    """
    f = sd4 * FG4X - cd4 * FG4Y
    f *= RG4
    f -= TI4
    f -= TEX
    f /= s34 * R4
    fp34x, fp34y = f * c3, f * s3
    fp32x, fp32y = -fp34x, -fp34y  # FP23 = FP34, FP32 = -FP23
    fp41x, fp41y = FG4X + fp34x, FG4Y + fp34y  # FP14 = -FG4 - FP34, FP41 = -FP14
    # FP12 = FP23, FP21 = -FP12 = FP32;  TP2 = -R2X FP32Y + R2Y FP32X = R2 f sin(th3 - th2)
    tp2 = s3 * c2 - c3 * s2
    tp2 *= f
    tp2 *= R2
    return fp34x, fp34y, fp32x, fp32y, fp32x, fp32y, fp41x, fp41y, tp2


@step(
    provides=("FPP34X", "FPP34Y", "FPP32X", "FPP32Y", "FPP21X", "FPP21Y", "FPP41X", "FPP41Y",
              "TPP2"),
    needs=("FG3X", "FG3Y", "TI3", "RG3", "cd3", "sd3", "R2", "R3", "c2", "s2", "c4", "s4",
           "s34"),
    zero_when=("FG3X", "FG3Y", "TI3"),
)
def _force_link3(FG3X, FG3Y, TI3, RG3, cd3, sd3, R2, R3, c2, s2, c4, s4, s34):
    """Only link 3 has mass: link 4 is a two-force member, F43 = g e^{i th4}.

    Moments about A:  R3 x F43 + RG3 x FG3 + TI3 = 0, R3 x F43 = -g R3 sin(th3 - th4).
    """
    g = sd3 * FG3X - cd3 * FG3Y
    g *= RG3
    g -= TI3
    g /= s34 * -R3
    fpp43x, fpp43y = g * c4, g * s4
    fpp34x, fpp34y = -fpp43x, -fpp43y
    fpp32x, fpp32y = fpp43x + FG3X, fpp43y + FG3Y  # FPP23 = -FPP43 - FG3, FPP32 = -FPP23
    # FPP14 = FPP43, FPP41 = -FPP14 = FPP34;  FPP12 = FPP23, FPP21 = -FPP12 = FPP32
    tpp2 = s2 * fpp32x - c2 * fpp32y
    tpp2 *= R2  # TPP2 = -R2X FPP32Y + R2Y FPP32X
    return fpp34x, fpp34y, fpp32x, fpp32y, fpp32x, fpp32y, fpp34x, fpp34y, tpp2


@step(provides=("F3P21X", "F3P21Y"), needs=("FG2X", "FG2Y"), zero_when=("FG2X", "FG2Y"))
def _force_link2(FG2X, FG2Y):
    """Only link 2 has mass; at constant speed it needs only a radial reaction.

    F3P12 = -FG2 (frame on 2), F3P21 = -F3P12 = FG2 (2 on frame); no torque since
    RG2 x FG2 = 0 and TH2DD = 0.
    """
    return FG2X, FG2Y


@step(provides=("FA32X", "FA32Y"), needs=("FP32X", "FP32Y", "FPP32X", "FPP32Y", "fa32x_e",
                                          "fa32y_e"))
def _total_FA32(FP32X, FP32Y, FPP32X, FPP32Y, fa32x_e, fa32y_e):
    return plus(FP32X + FPP32X, fa32x_e), plus(FP32Y + FPP32Y, fa32y_e)


@step(provides=("FB34X", "FB34Y"), needs=("FP34X", "FP34Y", "FPP34X", "FPP34Y", "fb34x_e",
                                          "fb34y_e"))
def _total_FB34(FP34X, FP34Y, FPP34X, FPP34Y, fb34x_e, fb34y_e):
    return plus(FP34X + FPP34X, fb34x_e), plus(FP34Y + FPP34Y, fb34y_e)


@step(provides=("TORQ",), needs=("TP2", "TPP2", "torq_e"))
def _total_TORQ(TP2, TPP2, torq_e):
    return plus(TP2 + TPP2, torq_e)


@step(provides=("FOAX", "FOAY"), needs=("FP21X", "FP21Y", "FPP21X", "FPP21Y", "F3P21X",
                                        "F3P21Y", "foax_e", "foay_e"))
def _total_FOA(FP21X, FP21Y, FPP21X, FPP21Y, F3P21X, F3P21Y, foax_e, foay_e):
    return (plus(FP21X + FPP21X + F3P21X, foax_e), plus(FP21Y + FPP21Y + F3P21Y, foay_e))


@step(provides=("FOBX", "FOBY"), needs=("FP41X", "FP41Y", "FPP41X", "FPP41Y", "fobx_e",
                                        "foby_e"))
def _total_FOB(FP41X, FP41Y, FPP41X, FPP41Y, fobx_e, foby_e):
    return plus(FP41X + FPP41X, fobx_e), plus(FP41Y + FPP41Y, foby_e)


@step(provides=("SHAKX", "SHAKY"), needs=("FOAX", "FOAY", "FOBX", "FOBY"))
def _total_SHAK(FOAX, FOAY, FOBX, FOBY):
    return FOAX + FOBX, FOAY + FOBY


@step(provides=("SHAKM",), needs=("R1", "FOBY", "TORQ"))
def _shaking_moment(R1, FOBY, TORQ):
    """Moment on the frame about O2: FOB at O4 = (R1, 0) and the motor's reaction -TORQ."""
    return FOBY * R1 - TORQ
