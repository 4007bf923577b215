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
    is neither run nor are its needs computed.  ``analyze`` seeds a namespace
    with the inputs, computes the dependency closure of the requested
    outputs (:func:`plan`), and runs the steps in dependency order.  Asking
    for kinematics therefore never touches the force steps.  ``STEP_CALLS``
    counts the step runs; the resolver looks step functions up in the module
    at run time, so ``unittest.mock.patch.object(engine, "_force_link4", ...)``
    intercepts them.
"""

from __future__ import annotations

import inspect
import warnings
from collections import Counter
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from sielaff.mechanism import EXAMPLE, FIELD_NAMES, Mechanism, validate

__all__ = [
    "AssemblyWarning",
    "G",
    "KINEMATIC_OUTPUTS",
    "OUTPUTS",
    "RESULTS",
    "Results",
    "STEP_CALLS",
    "STEPS",
    "VECTORS",
    "analyze",
    "plan",
    "step",
]

#: Gravitational acceleration, in/s^2 (the listing's G=386.0880).
G = 386.088

_EPS = np.finfo(float).eps
_DEGREES = 180.0 / np.pi  # what np.degrees multiplies by


# --------------------------------------------------------------------------
# The step registry
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class Step:
    """One unit of work: ``fn(*needs)`` returns the ``provides`` values, in order."""

    name: str
    fn: Callable[..., Any]
    provides: tuple[str, ...]
    needs: tuple[str, ...]
    zero_when: tuple[str, ...] = ()


#: All steps, in registration order.
STEPS: list[Step] = []
#: Which step provides each quantity.
PROVIDER: dict[str, Step] = {}
#: How many times each step has run (by step name); tests may reset it.
STEP_CALLS: Counter[str] = Counter()


def _register(st: Step) -> None:
    for name in st.provides:
        if name in PROVIDER:
            raise ValueError(f"{name} provided twice ({PROVIDER[name].name}, {st.name})")
        PROVIDER[name] = st
    STEPS.append(st)


def step(provides: Iterable[str], needs: Iterable[str] = (), zero_when: Iterable[str] = ()):
    """Register the decorated function as a step.

    The function's parameters must be exactly ``needs`` (so the declaration
    can be checked against the code) and it returns one value per name in
    ``provides`` (a bare value if there is one).  ``zero_when``: names that,
    if all identically zero, make every provided value zero.
    """
    provides, needs, zero_when = tuple(provides), tuple(needs), tuple(zero_when)

    def decorate(fn):
        params = tuple(inspect.signature(fn).parameters)
        if params != needs:
            raise TypeError(f"step {fn.__name__}: parameters {params} != needs {needs}")
        _register(Step(fn.__name__, fn, provides, needs, zero_when))
        return fn

    return decorate


# --------------------------------------------------------------------------
# Kinematics
# --------------------------------------------------------------------------


@step(provides=("c2", "s2"), needs=("ATH2",))
def _crank_angle(ATH2):
    """cos and sin of the crank angle, reduced modulo 360 degrees first."""
    if ATH2.size and (ATH2.min() < 0.0 or ATH2.max() >= 360.0):
        ATH2 = np.mod(ATH2, 360.0)  # exact (fmod), so ATH2 + 360 k gives identical results
    th2 = np.radians(ATH2)
    c2 = np.cos(th2)
    return c2, np.sin(th2, out=th2) if isinstance(th2, np.ndarray) else np.sin(th2)


def _length_scale(R1, R2, R3, R4):
    """1, or a power of two that brings the lengths near 1 where H^2 ~ L^4 would overflow
    or underflow (lengths past about 1E70 or below 1E-70): exact, and dimensionless
    results do not change."""
    big = max(float(np.max(R)) for R in (R1, R2, R3, R4))
    small = min(float(np.min(R)) for R in (R1, R2, R3, R4))
    if 1e-70 < small and big < 1e70:
        return 1.0
    return np.exp2(-np.round(np.log2(np.asarray(R1 + R2 + R3 + R4, dtype=float))))


@step(
    provides=("c3", "s3", "c4", "s4", "s34", "c34"),
    needs=("R1", "R2", "R3", "R4", "c2", "s2"),
)
def _loop_closure(R1, R2, R3, R4, c2, s2):
    """Position of links 3 and 4 on the listing's open branch (see module doc)."""
    scale = _length_scale(R1, R2, R3, R4)
    if np.any(scale != 1.0):
        R1, R2, R3, R4 = R1 * scale, R2 * scale, R3 * scale, R4 * scale
    dx = R1 - R2 * c2  # d = O4 - A
    dy = s2 * -R2
    zl2 = dx * dx
    zl2 += dy * dy
    zl = np.sqrt(zl2)
    # H^2 = ((ZL+R3)^2 - R4^2) (R4^2 - (ZL-R3)^2), each difference factored.
    t = zl + R3
    hh = t + R4
    t -= R4
    hh *= t
    np.subtract(zl, R3, out=t)
    u = R4 - t
    t += R4
    u *= t
    hh *= u
    del t, u, zl
    # A product pushed below 0 by roundoff is a toggle (H = 0); below -tol, no assembly.
    tol = R1 + R2 + R3 + R4
    tol = -16.0 * _EPS * tol**4
    np.maximum(hh, 0.0, out=hh, where=hh > tol)
    with np.errstate(invalid="ignore"):
        h = np.sqrt(hh, out=hh)
    k = 0.5 / R3
    p = zl2 + (R3 * R3 - R4 * R4)  # 2 ZL R3 cos PSI
    c3 = dx * p
    c3 -= dy * h
    s3 = dy * p
    s3 += dx * h
    np.divide(k, zl2, out=p)  # 1 / (2 ZL^2 R3)
    c3 *= p
    s3 *= p
    c4 = R3 * c3
    c4 -= dx
    c4 /= R4
    s4 = R3 * s3
    s4 -= dy
    s4 /= R4
    k = -0.5 / (R3 * R4)
    h *= k  # sin(th3 - th4)
    zl2 -= R3 * R3 + R4 * R4
    zl2 *= k  # cos(th3 - th4)
    return c3, s3, c4, s4, h, zl2


def _angle_deg(s, c):
    """atan2 in degrees, mapped to (-90, 270] (the listing's range for TH3, TH4)."""
    a = np.asarray(np.arctan2(s, c))
    a *= _DEGREES  # = np.degrees, in place: a fresh array costs more than the product
    np.add(a, 360.0, out=a, where=a <= -90.0)
    return a


@step(provides=("ASSEMBLED",), needs=("s34",))
def _assembly(s34):
    """True where the loop closes at this crank angle (the position exists)."""
    return np.isfinite(s34)


@step(provides=("ATH3", "ATH4"), needs=("c3", "s3", "c4", "s4"))
def _link_angles(c3, s3, c4, s4):
    return _angle_deg(s3, c3), _angle_deg(s4, c4)


@step(provides=("GAMMA",), needs=("s34", "c34"))
def _transmission_angle(s34, c34):
    """Angle between coupler and rocker (at B), degrees in [0, 180]."""
    return np.degrees(np.arctan2(-s34, c34))


@step(
    provides=("TH3D", "TH4D"),
    needs=("R2", "R3", "R4", "TH2D", "c2", "s2", "c3", "s3", "c4", "s4", "s34"),
)
def _angular_velocities(R2, R3, R4, TH2D, c2, s2, c3, s3, c4, s4, s34):
    k = (R2 * TH2D) / s34
    th3d = (s4 * c2 - c4 * s2) * k  # sin(th4 - th2)
    th3d /= R3
    th4d = (s3 * c2 - c3 * s2) * k  # sin(th3 - th2)
    th4d /= R4
    return th3d, th4d


@step(
    provides=("TH3DD", "TH4DD"),
    needs=("R2", "R3", "R4", "TH2D", "TH3D", "TH4D", "c2", "s2", "c3", "s3", "c4", "s4",
           "s34", "c34"),
)
def _angular_accelerations(R2, R3, R4, TH2D, TH3D, TH4D, c2, s2, c3, s3, c4, s4, s34, c34):
    a2 = R2 * TH2D * TH2D
    a3 = TH3D * TH3D
    a3 *= R3  # R3 TH3D^2
    a4 = TH4D * TH4D
    a4 *= R4  # R4 TH4D^2
    # TH3DD = (R2 w2^2 cos(th4-th2) + R3 w3^2 cos(th4-th3) - R4 w4^2) / (R3 sin(th4-th3))
    th3dd = c4 * c2
    th3dd += s4 * s2
    th3dd *= a2
    th3dd += a3 * c34
    th3dd -= a4
    th3dd /= s34 * -R3
    # TH4DD = (-R2 w2^2 cos(th3-th2) + R4 w4^2 cos(th3-th4) - R3 w3^2) / (R4 sin(th3-th4))
    th4dd = c3 * c2
    th4dd += s3 * s2
    th4dd *= -a2
    th4dd += a4 * c34
    th4dd -= a3
    th4dd /= s34 * R4
    return th3dd, th4dd


def _rotate(adel, c, s):
    """cos and sin of (th + adel degrees), given cos th and sin th."""
    if np.ndim(adel) == 0 and adel == 0.0:
        return c, s
    d = np.radians(adel)
    cd, sd = np.cos(d), np.sin(d)
    return c * cd - s * sd, s * cd + c * sd


@step(provides=("cd2", "sd2"), needs=("ADEL2", "c2", "s2"))
def _com_line2(ADEL2, c2, s2):
    return _rotate(ADEL2, c2, s2)


@step(provides=("cd3", "sd3"), needs=("ADEL3", "c3", "s3"))
def _com_line3(ADEL3, c3, s3):
    return _rotate(ADEL3, c3, s3)


@step(provides=("cd4", "sd4"), needs=("ADEL4", "c4", "s4"))
def _com_line4(ADEL4, c4, s4):
    return _rotate(ADEL4, c4, s4)


def _pivot_vel(r, w, c, s):
    """Velocity of a point at distance r, angle (c, s), on a link turning at w."""
    rw = r * w
    return s * -rw, c * rw


def _pivot_acc(r, w, a, c, s):
    """Acceleration of that point when the link also has angular acceleration a."""
    rw2 = w * w
    rw2 *= r
    ra = a * r
    return -(rw2 * c + ra * s), ra * c - rw2 * s


@step(provides=("VAX", "VAY"), needs=("R2", "TH2D", "c2", "s2"))
def _vel_A(R2, TH2D, c2, s2):
    return _pivot_vel(R2, TH2D, c2, s2)


@step(provides=("AAX", "AAY"), needs=("R2", "TH2D", "c2", "s2"))
def _acc_A(R2, TH2D, c2, s2):
    k = -R2 * TH2D * TH2D
    return c2 * k, s2 * k


@step(provides=("VG2X", "VG2Y"), needs=("RG2", "TH2D", "cd2", "sd2"))
def _vel_G2(RG2, TH2D, cd2, sd2):
    return _pivot_vel(RG2, TH2D, cd2, sd2)


@step(provides=("AG2X", "AG2Y"), needs=("RG2", "TH2D", "cd2", "sd2"))
def _acc_G2(RG2, TH2D, cd2, sd2):
    k = -RG2 * TH2D * TH2D
    return cd2 * k, sd2 * k


@step(provides=("VBX", "VBY"), needs=("R4", "TH4D", "c4", "s4"))
def _vel_B(R4, TH4D, c4, s4):
    return _pivot_vel(R4, TH4D, c4, s4)


@step(provides=("ABX", "ABY"), needs=("R4", "TH4D", "TH4DD", "c4", "s4"))
def _acc_B(R4, TH4D, TH4DD, c4, s4):
    return _pivot_acc(R4, TH4D, TH4DD, c4, s4)


@step(provides=("VG4X", "VG4Y"), needs=("RG4", "TH4D", "cd4", "sd4"))
def _vel_G4(RG4, TH4D, cd4, sd4):
    return _pivot_vel(RG4, TH4D, cd4, sd4)


@step(provides=("AG4X", "AG4Y"), needs=("RG4", "TH4D", "TH4DD", "cd4", "sd4"))
def _acc_G4(RG4, TH4D, TH4DD, cd4, sd4):
    return _pivot_acc(RG4, TH4D, TH4DD, cd4, sd4)


@step(provides=("VG3X", "VG3Y"), needs=("VAX", "VAY", "RG3", "TH3D", "cd3", "sd3"))
def _vel_G3(VAX, VAY, RG3, TH3D, cd3, sd3):
    x, y = _pivot_vel(RG3, TH3D, cd3, sd3)
    x += VAX
    y += VAY
    return x, y


@step(provides=("AG3X", "AG3Y"), needs=("AAX", "AAY", "RG3", "TH3D", "TH3DD", "cd3", "sd3"))
def _acc_G3(AAX, AAY, RG3, TH3D, TH3DD, cd3, sd3):
    x, y = _pivot_acc(RG3, TH3D, TH3DD, cd3, sd3)
    x += AAX
    y += AAY
    return x, y


# --------------------------------------------------------------------------
# Forces: inertia loads, then one superposition step per link, then totals
# --------------------------------------------------------------------------


@step(provides=("FG2X", "FG2Y"), needs=("W2", "AG2X", "AG2Y"), zero_when=("W2",))
def _inertia_force2(W2, AG2X, AG2Y):
    k = -W2 / G
    return AG2X * k, AG2Y * k


@step(provides=("FG3X", "FG3Y"), needs=("W3", "AG3X", "AG3Y"), zero_when=("W3",))
def _inertia_force3(W3, AG3X, AG3Y):
    k = -W3 / G
    return AG3X * k, AG3Y * k


@step(provides=("TI3",), needs=("ZI3", "TH3DD"), zero_when=("ZI3",))
def _inertia_torque3(ZI3, TH3DD):
    return TH3DD * -ZI3


@step(provides=("FG4X", "FG4Y"), needs=("W4", "AG4X", "AG4Y"), zero_when=("W4",))
def _inertia_force4(W4, AG4X, AG4Y):
    k = -W4 / G
    return AG4X * k, AG4Y * k


@step(provides=("TI4",), needs=("ZI4", "TH4DD"), zero_when=("ZI4",))
def _inertia_torque4(ZI4, TH4DD):
    return TH4DD * -ZI4


@step(provides=("TEX",), needs=("tex_fn", "ATH4"))
def _external_torque(tex_fn, ATH4):
    """TEX = f(ATH4 in degrees), the report's statement 74 option."""
    return np.array(tex_fn(ATH4), dtype=float)  # a copy: never alias the caller's arrays


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


@step(provides=("FA32X", "FA32Y"), needs=("FP32X", "FP32Y", "FPP32X", "FPP32Y"))
def _total_FA32(FP32X, FP32Y, FPP32X, FPP32Y):
    return FP32X + FPP32X, FP32Y + FPP32Y


@step(provides=("FB34X", "FB34Y"), needs=("FP34X", "FP34Y", "FPP34X", "FPP34Y"))
def _total_FB34(FP34X, FP34Y, FPP34X, FPP34Y):
    return FP34X + FPP34X, FP34Y + FPP34Y


@step(provides=("TORQ",), needs=("TP2", "TPP2"))
def _total_TORQ(TP2, TPP2):
    return TP2 + TPP2


@step(provides=("FOAX", "FOAY"), needs=("FP21X", "FP21Y", "FPP21X", "FPP21Y", "F3P21X",
                                        "F3P21Y"))
def _total_FOA(FP21X, FP21Y, FPP21X, FPP21Y, F3P21X, F3P21Y):
    return FP21X + FPP21X + F3P21X, FP21Y + FPP21Y + F3P21Y


@step(provides=("FOBX", "FOBY"), needs=("FP41X", "FP41Y", "FPP41X", "FPP41Y"))
def _total_FOB(FP41X, FP41Y, FPP41X, FPP41Y):
    return FP41X + FPP41X, FP41Y + FPP41Y


@step(provides=("SHAKX", "SHAKY"), needs=("FOAX", "FOAY", "FOBX", "FOBY"))
def _total_SHAK(FOAX, FOAY, FOBX, FOBY):
    return FOAX + FOBX, FOAY + FOBY


@step(provides=("SHAKM",), needs=("R1", "FOBY", "TORQ"))
def _shaking_moment(R1, FOBY, TORQ):
    """Moment on the frame about O2: FOB at O4 = (R1, 0) and the motor's reaction -TORQ."""
    return FOBY * R1 - TORQ


# --------------------------------------------------------------------------
# Magnitudes and directions (the listing's SUBROUTINE VECTOR), one step each
# --------------------------------------------------------------------------

#: Vectors reported as magnitude NAME and direction DNAME (degrees in [0, 360)).
VECTORS = ("VG2", "VA", "VG3", "VB", "VG4", "AG2", "AA", "AG3", "AB", "AG4",
           "FA32", "FB34", "FOA", "FOB", "SHAK")


def _magnitude(x, y):
    m = x * x  # np.hypot is ~7x slower; these magnitudes are far from overflow
    m += y * y
    return np.sqrt(m, out=m) if isinstance(m, np.ndarray) else np.sqrt(m)


def _direction(x, y):
    """Direction of (x, y) in degrees, in [0, 360); 0 for the zero vector (as VECTOR)."""
    d = np.asarray(np.arctan2(y, x))
    d *= _DEGREES  # = np.degrees, in place
    np.add(d, 360.0, out=d, where=d < 0.0)
    np.copyto(d, 0.0, where=d >= 360.0)  # -tiny + 360 rounds to 360
    d += 0.0  # -0.0 -> +0.0
    return d


for _name in VECTORS:
    _xy = (_name + "X", _name + "Y")
    _register(Step(f"_magnitude_{_name}", _magnitude, (_name,), _xy))
    _register(Step(f"_direction_{_name}", _direction, ("D" + _name,), _xy))
del _name, _xy


# --------------------------------------------------------------------------
# Public names and the resolver
# --------------------------------------------------------------------------

#: Inputs seeded into the namespace (plus ``TEX`` or ``tex_fn``).
INPUTS = ("ATH2",) + FIELD_NAMES

#: What ``analyze`` returns by default (``outputs=None``), in the listing's print
#: order: angles, angular rates, TEX, each vector as magnitude, direction and
#: components, then TORQ and the shaking moment.
RESULTS = (
    ("ATH2", "ATH3", "ATH4", "GAMMA", "TH3D", "TH4D", "TH3DD", "TH4DD", "TEX")
    + tuple(n for v in VECTORS for n in (v, "D" + v, v + "X", v + "Y"))
    + ("TORQ", "SHAKM")
)

#: Every name ``analyze`` accepts: RESULTS plus the listing's intermediate
#: quantities (inertia loads FG2X.., TI3, TI4, superposition parts FP34X..,
#: FPP32X.., F3P21X, TP2, TPP2).
OUTPUTS = RESULTS + tuple(sorted(n for n in PROVIDER if n[0].isupper() and n not in RESULTS))


def _depends_on(name: str, inputs: frozenset[str]) -> bool:
    """Whether ``name`` (transitively) needs any of ``inputs``."""
    if name in inputs:
        return True
    st = PROVIDER.get(name)
    return st is not None and any(_depends_on(n, inputs) for n in st.needs)


#: The results that need no masses, inertias or TEX: no force analysis.
KINEMATIC_OUTPUTS = tuple(
    n for n in RESULTS
    if n != "TEX" and not _depends_on(n, frozenset(("W2", "W3", "W4", "ZI2", "ZI3", "ZI4",
                                                     "TEX", "tex_fn")))
)

#: Inputs whose being zero can make steps unnecessary (see ``zero_when``).
_ZERO_CANDIDATES = frozenset(n for s in STEPS for n in s.zero_when if n not in PROVIDER) | {"TEX"}


def _zero_seeds(ns: dict[str, Any]) -> frozenset[str]:
    """The seeded inputs that are identically zero (a massless link, no TEX)."""
    return frozenset(n for n in _ZERO_CANDIDATES if n in ns and not np.any(ns[n]))


@lru_cache(maxsize=256)
def _plan(wanted: tuple[str, ...], seeded: frozenset[str],
          zero_seeds: frozenset[str]) -> tuple[tuple[Step, bool, tuple[str, ...]], ...]:
    """Steps to run, in dependency order, as (step, skipped, names to drop after it).

    Dropping intermediates after their last use lets numpy reuse their memory
    (fresh multi-megabyte arrays cost page faults, more than the arithmetic).
    """

    zero_memo: dict[str, bool] = {}

    def known_zero(name: str) -> bool:
        if name in seeded:
            return name in zero_seeds
        if name not in zero_memo:
            st = PROVIDER[name]
            zero_memo[name] = bool(st.zero_when) and all(known_zero(n) for n in st.zero_when)
        return zero_memo[name]

    order: list[tuple[Step, bool]] = []
    available = set(seeded)
    active: set[str] = set()

    def visit(name: str) -> None:
        if name in available:
            return
        st = PROVIDER.get(name)
        if st is None:
            raise ValueError(f"{name} is neither an input nor provided by a step")
        if st.name in active:
            raise RuntimeError(f"dependency cycle through {st.name}")
        skipped = bool(st.zero_when) and all(known_zero(n) for n in st.zero_when)
        if not skipped:
            active.add(st.name)
            for need in st.needs:
                visit(need)
            active.discard(st.name)
        order.append((st, skipped))
        available.update(st.provides)

    for name in wanted:
        visit(name)
    last_use: dict[str, int] = {}
    for i, (st, skipped) in enumerate(order):
        for name in () if skipped else st.needs:
            last_use[name] = i
        for name in st.provides:
            last_use.setdefault(name, i)
    drops: list[list[str]] = [[] for _ in order]
    for name, i in last_use.items():
        if name not in wanted and name not in seeded:
            drops[i].append(name)
    return tuple((st, skipped, tuple(d)) for (st, skipped), d in zip(order, drops, strict=True))


class AssemblyWarning(UserWarning):
    """Some positions of an ``analyze`` call cannot assemble: their results are NaN."""


class Results(dict):
    """``analyze``'s answer: ``{name: array}``, and how many positions could not assemble.

    ``not_assembled`` counts the positions (elements of the broadcast shape) where the
    loop cannot close, whose results are NaN; it is None when no position was solved
    (inputs only).  Ask for the ``ASSEMBLED`` output for the mask itself.
    """

    not_assembled: int | None = None


def _common_shape(named: list[tuple[str, tuple[int, ...]]]) -> tuple[int, ...]:
    """The broadcast shape of ``named`` inputs; a ValueError naming the two that clash."""
    try:
        return np.broadcast_shapes(*(shape for _, shape in named))
    except ValueError:
        pass
    so_far: tuple[int, ...] = ()
    names: list[str] = []
    for name, shape in named:
        try:
            so_far = np.broadcast_shapes(so_far, shape)
        except ValueError:
            clash = [n for n, s in named[:len(names)] if not _broadcastable(s, shape)]
            raise ValueError(
                f"cannot broadcast {name} (shape {shape}) with {', '.join(clash)} "
                f"(shape {dict(named)[clash[0]]}): give the fields a sweep varies shapes "
                "that broadcast, e.g. R4 of shape (n, 1) against ath2 of shape (m,)"
            ) from None
        names.append(name)
    return so_far


def _broadcastable(a: tuple[int, ...], b: tuple[int, ...]) -> bool:
    try:
        np.broadcast_shapes(a, b)
    except ValueError:
        return False
    return True


def _check_outputs(outputs: Iterable[str] | str | None) -> tuple[str, ...]:
    if outputs is None:
        return RESULTS
    if isinstance(outputs, str):
        outputs = (outputs,)
    wanted = tuple(dict.fromkeys(outputs))
    unknown = [n for n in wanted if n not in OUTPUTS]
    if unknown:
        raise ValueError(f"unknown output(s) {unknown}; valid names: {', '.join(OUTPUTS)}")
    return wanted


def _seed(mechanism: Mechanism, ath2: Any, tex: Any) -> dict[str, Any]:
    ns: dict[str, Any] = {}
    for name in FIELD_NAMES:
        v = np.asarray(getattr(mechanism, name), dtype=float)
        ns[name] = float(v) if v.ndim == 0 else v
    ns["ATH2"] = np.atleast_1d(np.asarray(ath2, dtype=float))  # ufuncs keep arrays
    if callable(tex):
        ns["tex_fn"] = tex
    else:
        v = np.asarray(tex, dtype=float)
        ns["TEX"] = float(v) if v.ndim == 0 else v
    return ns


def plan(outputs: Iterable[str] | str | None = None, mechanism: Mechanism | None = None,
         tex: Any = 0.0) -> list[str]:
    """Names of the steps ``analyze`` would run (skipped zero steps marked ``name=0``)."""
    ns = _seed(EXAMPLE if mechanism is None else mechanism, 0.0, tex)
    order = _plan(_check_outputs(outputs), frozenset(ns), _zero_seeds(ns))
    return [st.name + ("=0" if skipped else "") for st, skipped, _ in order]


def _run(order, ns: dict[str, Any]) -> int | None:
    """Run the planned steps in ``ns``; the number of positions that cannot assemble
    (None if no position was solved)."""
    not_assembled = None
    module = globals()
    for st, skipped, drop in order:
        if skipped:
            for name in st.provides:
                ns[name] = 0.0
        else:
            fn = module.get(st.name, st.fn)  # looked up late so tests can patch it
            STEP_CALLS[st.name] += 1
            result = fn(*[ns[n] for n in st.needs])
            if len(st.provides) == 1:
                result = (result,)
            for name, value in zip(st.provides, result, strict=True):
                ns[name] = value
            if "s34" in st.provides:  # where the loop cannot close, s34 is NaN
                not_assembled = int(np.count_nonzero(np.isnan(ns["s34"])))
        for name in drop:
            del ns[name]
    return not_assembled


def analyze(mechanism: Mechanism, ath2: Any, outputs: Iterable[str] | str | None = None,
            tex: Any = 0.0) -> Results:
    """Analyse ``mechanism`` at crank angles ``ath2`` (degrees).

    ``outputs``: names wanted (any of ``OUTPUTS``); None means ``RESULTS``.  Only
    the steps these depend on are run.  ``tex``: the external torque on link 4
    (in-lb, + CCW), a constant, an array broadcasting against ``ath2``, or a
    callable taking ATH4 in degrees.  Returns ``{name: array}`` for the wanted
    names, every array of the broadcast shape of ``ath2``, the mechanism's
    fields and ``tex``, as a :class:`Results` whose ``not_assembled`` counts the
    positions where the loop cannot close (their results are NaN; an
    :class:`AssemblyWarning` says how many).  Shapes that do not broadcast are a
    ValueError naming the fields, and so is a mechanism no linkage can have
    (:func:`sielaff.mechanism.validate`: a missing or non-finite field, a length that
    is not positive, a negative weight or inertia).
    """
    wanted = _check_outputs(outputs)
    validate(mechanism)
    ns = _seed(mechanism, ath2, tex)
    seeded = frozenset(ns)
    named = [("ath2", np.shape(ath2))] + [
        (n if n != "TEX" else "tex", np.shape(v)) for n, v in ns.items()
        if n not in ("tex_fn", "ATH2")]
    final_shape = _common_shape(named)
    shape = np.broadcast_shapes(ns["ATH2"].shape, final_shape)  # differs only if final is ()
    # Crank angles of the full shape make every derived array full-shaped, so the
    # steps may update arrays in place with mechanism fields of any shape.
    ns["ATH2"] = np.broadcast_to(ns["ATH2"], shape)
    order = _plan(wanted, seeded, _zero_seeds(ns))
    with np.errstate(all="ignore"):  # NaN where the loop cannot close, inf at a toggle
        not_assembled = _run(order, ns)
    out = Results()
    if not_assembled is not None:
        out.not_assembled = not_assembled
        if not_assembled:
            total = int(np.prod(shape))
            warnings.warn(f"{not_assembled} of {total} positions cannot assemble (the loop "
                          "does not close there): their results are NaN; ask for the "
                          "ASSEMBLED output for the mask", AssemblyWarning, stacklevel=2)
    seen: set[int] = set()
    for name in wanted:
        v = ns[name]
        if (name in seeded or id(v) in seen or not isinstance(v, np.ndarray)
                or v.shape != shape):
            v = np.array(np.broadcast_to(v, shape), dtype=float)
        seen.add(id(v))
        out[name] = v.reshape(final_shape)
    return out
