"""The slider-crank as a model: its positions, rates, inertia and statics, and one line
per effect it takes (gravity, loads, the slider force FEX, springs and dampers).

The crank O2-A turns about the origin; the rod A-B; the slider (link 4, a point mass at
B) slides on the line y = ``offset`` (:mod:`sielaff.slider_crank`).  With d = offset - R2
sin th2 the rod's angle has sin th3 = d / R3 and cos th3 = +-sqrt(R3^2 - d^2) / R3 (+ on
the ``open`` branch, B to the right of A; - on the ``crossed`` one), and

    XB = R2 cos th2 + R3 cos th3
    TH3D = -R2 cos th2 TH2D / (R3 cos th3)
    VXB = -R2 sin th2 TH2D - R3 sin th3 TH3D
    TH3DD = (R2 sin th2 TH2D^2 - R2 cos th2 TH2DD + R3 sin th3 TH3D^2) / (R3 cos th3)
    AXB = -R2 (cos th2 TH2D^2 + sin th2 TH2DD) - R3 (cos th3 TH3D^2 + sin th3 TH3DD)

(the derivatives of the loop's y and x closure).  Forces (``statics``): for loads
``{link: (fx, fy, m about its base pin)}`` on the crank (about O2), the rod (about A) and
the slider (about B) the slider's x balance gives the rod's x pull on it, the rod's
moment about A its y pull, the slider's y balance the guide's normal force FN and its
moment balance the guide's couple MN; the rod's and the crank's force balances and the
crank's moment about O2 give FA32, FOA and TORQ.  The links' inertia (D'Alembert: -m aG
at G, -ZI alpha) is one more set of such loads.  Every step is vectorised; cos th3 = 0
(the rod square to the line, at the edge of where it assembles) makes the rates
infinite, as a four-bar's toggle does.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sielaff.engine.accelerations import _pivot_acc
from sielaff.engine.crank import _crank_acceleration
from sielaff.engine.declare import Param, number_param
from sielaff.engine.fourbar import BRANCHES
from sielaff.engine.links import FRAME, FRAME_RATE, Link, LinkRate
from sielaff.engine.outputs import vector_steps
from sielaff.engine.positions import ASSEMBLY_TOL_EPS, _angle_deg, _crank_angle
from sielaff.engine.registry import Model, step, step_of
from sielaff.engine.velocities import _com_line2, _com_line3, _vel_A, _vel_G2, _vel_G3
from sielaff.mechanism import MASS_DIVISOR
from sielaff.quantities import declare
from sielaff.slider_crank import FIELD_NAMES, SliderCrank, full_turn_failure, validate_slider

__all__ = ["SLIDER_CRANK", "SLIDER_RESULTS", "SLIDER_SLOTS"]

#: The superposed quantities: the pin forces, the guide's force and couple, the torque.
SLIDER_SLOTS = ("fa32x", "fa32y", "fb34x", "fb34y", "foax", "foay", "fn", "mn", "torq")

_EPS = np.finfo(float).eps

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


def _branch(v: Any) -> str:
    if not isinstance(v, str) or v not in BRANCHES:
        raise ValueError(f"Scene.branch = {v!r}: 'open' (B to the right of A) or 'crossed'")
    return v


def _seed(mechanism: Any, ath2: Any, scene: Any) -> dict[str, Any]:
    """The slider-crank's fields, the crank angles, the branch, the crank's acceleration,
    the mass divisor."""
    ns: dict[str, Any] = {"BRANCH": 1.0 if scene.branch == "open" else -1.0}
    for name in FIELD_NAMES:
        v = np.asarray(getattr(mechanism, name), dtype=float)
        ns[name] = float(v) if v.ndim == 0 else v
    ns["ATH2"] = np.atleast_1d(np.asarray(ath2, dtype=float))
    ns["GW"] = MASS_DIVISOR[mechanism.units]
    th2dd = scene.th2dd
    if callable(th2dd):
        ns["th2dd_fn"] = th2dd
    else:
        ns["TH2DD"] = th2dd
    return ns


@step(provides=("c3", "s3"), needs=("R2", "R3", "offset", "c2", "s2", "BRANCH"))
def _rod_angle(R2, R3, offset, c2, s2, BRANCH):
    """The rod's line: sin th3 = d / R3, cos th3 = +-sqrt((R3 - d)(R3 + d)) / R3.

    Each factor is known to about eps (R2 + R3 + |offset|): one within ASSEMBLY_TOL_EPS of
    that below 0 is the edge of assembly reached with roundoff (cos th3 = 0), one further
    below means the rod cannot reach the line there (NaN)."""
    d = offset - R2 * s2
    tol = -ASSEMBLY_TOL_EPS * _EPS * (R2 + R3 + np.abs(offset))
    lo, hi = R3 - d, R3 + d
    lo = np.where(lo < tol, np.nan, np.maximum(lo, 0.0))
    hi = np.where(hi < tol, np.nan, np.maximum(hi, 0.0))
    c3 = np.sqrt((lo / R3) * (hi / R3))  # divided first: no overflow of the product
    if BRANCH != 1.0:
        c3 = -c3
    s3 = np.broadcast_to(d / R3, np.shape(c3)) + 0.0 * c3  # NaN where it cannot close
    return c3, s3


@step(provides=("ATH3",), needs=("c3", "s3"))
def _rod_line(c3, s3):
    return _angle_deg(s3, c3)


@step(provides=("XB",), needs=("R2", "R3", "c2", "c3"))
def _slider_position(R2, R3, c2, c3):
    return R2 * c2 + R3 * c3


@step(provides=("ASSEMBLED",), needs=("c3",))
def _assembly(c3):
    """True where the rod reaches the slider's line (the position exists)."""
    return np.isfinite(c3)


@step(provides=("TH3D", "VXB"), needs=("R2", "R3", "TH2D", "c2", "s2", "c3", "s3"),
      zero_when=("TH2D",))
def _rates(R2, R3, TH2D, c2, s2, c3, s3):
    th3d = (-R2 * TH2D) * c2 / (R3 * c3)
    return th3d, (-R2 * TH2D) * s2 - (R3 * s3) * th3d


@step(provides=("TH3DD", "AXB"), needs=("R2", "R3", "TH2D", "TH2DD", "TH3D", "c2", "s2",
                                        "c3", "s3"),
      zero_when=("TH2D", "TH2DD"))
def _accelerations(R2, R3, TH2D, TH2DD, TH3D, c2, s2, c3, s3):
    w2, w3 = TH2D * TH2D, TH3D * TH3D
    th3dd = (R2 * (s2 * w2 - c2 * TH2DD) + R3 * s3 * w3) / (R3 * c3)
    axb = -R2 * (c2 * w2 + s2 * TH2DD) - R3 * (c3 * w3 + s3 * th3dd)
    return th3dd, axb


@step(provides=("AAX", "AAY"), needs=("R2", "TH2D", "TH2DD", "c2", "s2"),
      zero_when=("TH2D", "TH2DD"))
def _acc_A(R2, TH2D, TH2DD, c2, s2):
    return _pivot_acc(R2, TH2D, TH2DD, c2, s2)


@step(provides=("AG2X", "AG2Y"), needs=("RG2", "TH2D", "TH2DD", "cd2", "sd2"),
      zero_when=("TH2D", "TH2DD"))
def _acc_G2(RG2, TH2D, TH2DD, cd2, sd2):
    return _pivot_acc(RG2, TH2D, TH2DD, cd2, sd2)


@step(provides=("AG3X", "AG3Y"), needs=("AAX", "AAY", "RG3", "TH3D", "TH3DD", "cd3", "sd3"),
      zero_when=("AAX", "AAY", "TH3D", "TH3DD"))
def _acc_G3(AAX, AAY, RG3, TH3D, TH3DD, cd3, sd3):
    x, y = _pivot_acc(RG3, TH3D, TH3DD, cd3, sd3)
    return x + AAX, y + AAY


@step(provides=("inertia_loads",), needs=("W2", "W3", "W4", "ZI2", "ZI3", "GW", "TH2DD",
                                          "TH3DD", "AG2X", "AG2Y", "AG3X", "AG3Y", "AXB",
                                          "RG2", "RG3", "cd2", "sd2", "cd3", "sd3"))
def _inertia_loads(W2, W3, W4, ZI2, ZI3, GW, TH2DD, TH3DD, AG2X, AG2Y, AG3X, AG3Y, AXB,
                   RG2, RG3, cd2, sd2, cd3, sd3):
    """D'Alembert's loads of each link: -m aG at G and -ZI alpha, as a force and its
    moment about the link's base pin (O2, A; the slider's at B, a point mass)."""
    f2x, f2y = AG2X * (-W2 / GW), AG2Y * (-W2 / GW)
    f3x, f3y = AG3X * (-W3 / GW), AG3Y * (-W3 / GW)
    return {2: (f2x, f2y, RG2 * (cd2 * f2y - sd2 * f2x) - ZI2 * TH2DD),
            3: (f3x, f3y, RG3 * (cd3 * f3y - sd3 * f3x) - ZI3 * TH3DD),
            4: (AXB * (-W4 / GW), 0.0, 0.0)}


_NONE = (0.0, 0.0, 0.0)
_GEOMETRY = ("R2", "R3", "c2", "s2", "c3", "s3")


def slider_statics(loads, R2, R3, c2, s2, c3, s3):
    """The slots (FA32X, FA32Y, FB34X, FB34Y, FOAX, FOAY, FN, MN, TORQ) for loads
    ``{link: (fx, fy, m about its base pin)}`` on the crank, the rod and the slider.

    Slider: F34 + (0, FN) + F4 = 0 and MN + M4 = 0; rod, about A: (B - A) x F34 = M3;
    then F32 = F3 - F34 (3 on 2), FOA = F32 + F2 (2 on the frame) and the drive
    A x F32 + M2 + TORQ = 0.
    """
    f2, f3, f4 = (loads.get(k, _NONE) for k in (2, 3, 4))
    f34x = -f4[0]
    f34y = (f3[2] + (R3 * s3) * f34x) / (R3 * c3)
    fn = -f34y - f4[1]
    f32x, f32y = f3[0] - f34x, f3[1] - f34y
    torq = -(R2 * (c2 * f32y - s2 * f32x)) - f2[2]
    zero = 0.0 * c3  # every slot of the positions' shape, NaN where it cannot close
    return (f32x + zero, f32y, f34x + zero, f34y, f32x + f2[0] + zero, f32y + f2[1] + zero,
            fn, -f4[2] + zero, torq)


@step(provides=tuple(s + "_i" for s in SLIDER_SLOTS), needs=("inertia_loads",) + _GEOMETRY)
def _inertia_forces(inertia_loads, R2, R3, c2, s2, c3, s3):
    return slider_statics(inertia_loads, R2, R3, c2, s2, c3, s3)


@step(provides=("FA32X", "FA32Y", "FB34X", "FB34Y", "FOAX", "FOAY", "FN", "MN", "TORQ"),
      needs=tuple(s + "_i" for s in SLIDER_SLOTS) + tuple(s + "_e" for s in SLIDER_SLOTS))
def _totals(fa32x_i, fa32y_i, fb34x_i, fb34y_i, foax_i, foay_i, fn_i, mn_i, torq_i,
            fa32x_e, fa32y_e, fb34x_e, fb34y_e, foax_e, foay_e, fn_e, mn_e, torq_e):
    """The links' inertia and every effect's part, added."""
    return (fa32x_i + fa32x_e, fa32y_i + fa32y_e, fb34x_i + fb34x_e, fb34y_i + fb34y_e,
            foax_i + foax_e, foay_i + foay_e, fn_i + fn_e, mn_i + mn_e, torq_i + torq_e)


@step(provides=("SHAKX", "SHAKY"), needs=("FOAX", "FOAY", "FN"))
def _shaking(FOAX, FOAY, FN):
    """What the moving links put on the frame: FOA at O2 and the slider's -FN on the
    guide (an applied force's reaction, a gas force's on the cylinder head, is not in
    it: as the four-bar's SHAK leaves TEX's out)."""
    return FOAX + 0.0, FOAY - FN


@step(provides=("SHAKM",), needs=("XB", "offset", "FN", "MN", "TORQ"))
def _shaking_moment(XB, offset, FN, MN, TORQ):
    """Moment on the frame about O2: the slider's -FN at B, its couple -MN, and the
    motor's reaction -TORQ."""
    return -XB * FN - MN - TORQ


@step(provides=("links",), needs=("R2", "c2", "s2", "c3", "s3", "XB", "offset", "W2", "W3",
                                  "W4", "RG2", "RG3", "cd2", "sd2", "cd3", "sd3"))
def _links(R2, c2, s2, c3, s3, XB, offset, W2, W3, W4, RG2, RG3, cd2, sd2, cd3, sd3):
    """The links as the effects see them: 2 from O2, 3 from A, the slider from B along
    +x (its centre of mass at B)."""
    return {1: FRAME, 2: Link(c2, s2, 0.0, 0.0, W2, RG2, cd2, sd2),
            3: Link(c3, s3, R2 * c2, R2 * s2, W3, RG3, cd3, sd3),
            4: Link(1.0, 0.0, XB, offset + 0.0 * XB, W4, 0.0, 1.0, 0.0)}


@step(provides=("link_rates",), needs=("VAX", "VAY", "TH2D", "TH3D", "VXB"))
def _link_rates(VAX, VAY, TH2D, TH3D, VXB):
    """Each link's angular velocity and its base point's velocity."""
    return {1: FRAME_RATE, 2: LinkRate(TH2D, 0.0, 0.0), 3: LinkRate(TH3D, VAX, VAY),
            4: LinkRate(0.0, VXB, 0.0)}


def _th2dd() -> Param:
    return number_param("th2dd", "float, array or callable\n    The crank's angular "
                        "acceleration [rad/sec^2], CCW +; TH2D is then the crank\n    "
                        "speed at each position.  A constant, an array or a function of "
                        "ATH2 [deg].")


#: The slider-crank's model.
SLIDER_CRANK = Model(
    "slider-crank", seed=_seed, results=SLIDER_RESULTS,
    sums={slot: slot + "_e" for slot in SLIDER_SLOTS}, breakdown=("TORQ_INERTIA", "TORQ"),
    counts="c3",
    params=(Param("branch", "open", _branch,
                  '{"open", "crossed"}\n    The slider\'s side: B to the right of A '
                  "(open) or to the left."), _th2dd()),
    statics=(slider_statics, _GEOMETRY), mechanism=SliderCrank, validate=validate_slider,
    full_turn=full_turn_failure)
SLIDER_CRANK.add(
    (step_of(f) for f in (_crank_angle, _rod_angle, _rod_line, _slider_position, _assembly,
                          _rates, _accelerations, _com_line2, _com_line3, _vel_A, _vel_G2,
                          _vel_G3, _acc_A, _acc_G2, _acc_G3, _crank_acceleration,
                          _inertia_loads, _inertia_forces, _totals, _shaking,
                          _shaking_moment, _links, _link_rates)),
    vector_steps(_VECTORS))
SLIDER_CRANK.add_effect("gravity")
SLIDER_CRANK.add_effect("loads")
SLIDER_CRANK.add_effect("slider_force")
SLIDER_CRANK.add_effect("elements")

#: The results that need no masses, inertias or FEX: no force analysis.
SLIDER_CRANK.kinematics = tuple(
    n for n in SLIDER_RESULTS
    if not SLIDER_CRANK.depends_on(n, frozenset(("W2", "W3", "W4", "ZI2", "ZI3", "FEX"))))
