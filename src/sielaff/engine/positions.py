"""Positions: the crank angle, the loop closure (links 3 and 4), the transmission angle.

No ARCCOS: the sines and cosines of THETA 3 and THETA 4 come from products (see the
package doc, "Geometry").  Lengths far from 1 are rescaled by a power of two first
(exact), so lengths from 1E-85 to 1E85 give the same angles.  Angles in degrees.
"""

from __future__ import annotations

import numpy as np

from sielaff.engine.arith import mod360, owned, put
from sielaff.engine.registry import step

_EPS = np.finfo(float).eps


_DEGREES = 180.0 / np.pi  # what np.degrees multiplies by

#: A linear factor of Heron's product (a length) below -ASSEMBLY_TOL_EPS eps (R1+R2+R3+R4)
#: means the loop cannot close; between that and 0 it is a toggle reached with roundoff.
#: The dyads of every other linkage (dyads.py) ask this one constant too.
ASSEMBLY_TOL_EPS = 8.0


@step(provides=("c2", "s2"), needs=("ATH2",))
def _crank_angle(ATH2):
    """cos and sin of the crank angle, reduced modulo 360 degrees first."""
    th2 = np.radians(mod360(ATH2))  # exact, so ATH2 + 360 k gives identical results
    c2 = np.cos(th2)
    return c2, np.sin(th2, out=th2) if owned(th2) else np.sin(th2)


def reachable(mechanism, n: int = 361):
    """``n`` crank angles (degrees) spread over the THETA 2 that assemble: a whole
    revolution (0 to 360, 360 left out) when link 2 turns fully, else over each arc
    between toggles in proportion to its length, its toggles included (positions are
    finite there; the rates are infinite: the linkage locks)."""
    from sielaff.engine.classify import linkage_class

    c = linkage_class(mechanism)
    if c.turns_fully:
        return np.linspace(0.0, 360.0, n, endpoint=False)
    spans = [((b - a) % 360.0, a) for a, b in c.arcs]
    total = sum(w for w, _ in spans)
    out: list[np.ndarray] = []
    for k, (w, a) in enumerate(spans):
        m = n - sum(len(o) for o in out) if k == len(spans) - 1 else max(2, round(n * w / total))
        out.append(np.mod(a + np.linspace(0.0, w, m), 360.0))
    return np.concatenate(out) if out else np.array([])


def _length_scale(R1, R2, R3, R4):
    """1, or a power of two that brings the lengths near 1 where H^2 ~ L^4 would overflow
    or underflow (lengths past about 1E70 or below 1E-70): exact, and dimensionless
    results do not change."""
    big = max(float(np.max(R1)), float(np.max(R2)), float(np.max(R3)), float(np.max(R4)))
    small = min(float(np.min(R1)), float(np.min(R2)), float(np.min(R3)), float(np.min(R4)))
    if 1e-70 < small and big < 1e70:
        return 1.0
    return np.exp2(-np.round(np.log2(np.asarray(R1 + R2 + R3 + R4, dtype=float))))


@step(
    provides=("c3", "s3", "c4", "s4", "s34", "c34"),
    needs=("R1", "R2", "R3", "R4", "c2", "s2", "BRANCH"),
)
def _loop_closure(R1, R2, R3, R4, c2, s2, BRANCH):
    """Position of links 3 and 4: BRANCH = 1 the listing's open branch (see the package
    doc), -1 the crossed one (the mirror image of B about the line A-O4: -H for H)."""
    scale = _length_scale(R1, R2, R3, R4)
    if np.any(scale != 1.0):
        R1, R2, R3, R4 = R1 * scale, R2 * scale, R3 * scale, R4 * scale
    dx = R1 - R2 * c2  # d = O4 - A
    dy = s2 * -R2
    zl2 = dx * dx
    zl2 += dy * dy
    h = _heron(R1, R2, R3, R4, zl2)
    if BRANCH != 1.0:
        h = np.negative(h, out=h)
    k = 0.5 / R3
    p = zl2 + (R3 * R3 - R4 * R4)  # 2 ZL R3 cos PSI
    c3 = dx * p
    c3 -= dy * h
    s3 = dy * p
    s3 += dx * h
    p = np.divide(k, zl2, out=p)  # 1 / (2 ZL^2 R3)
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


def _heron(R1, R2, R3, R4, zl2):
    """4 x the area of the triangle A-B-O4 (sides ZL, R3, R4): H, 0 at a toggle, NaN where
    the loop cannot close."""
    zl = np.sqrt(zl2)
    # H^2 = (ZL+R3+R4)(ZL+R3-R4)(R3+R4-ZL)(R4+ZL-R3).  ZL is known to about
    # eps (R1+R2+R3+R4) (it comes from R1 - R2 cos th2 and R2 sin th2), and so is each
    # linear factor: one within ASSEMBLY_TOL_EPS eps (R1+R2+R3+R4) below 0 is a toggle
    # pushed there by roundoff (clamped to 0: H = 0), one further below means the loop
    # cannot close (NaN).
    tol = R1 + R2 + R3 + R4
    tol = -ASSEMBLY_TOL_EPS * _EPS * tol
    t = zl + R3
    hh = t + R4
    t -= R4
    t = _clamp(t, tol)
    hh *= t
    t = np.subtract(zl, R3, out=t)
    u = R4 - t
    t += R4
    u = _clamp(u, tol)
    t = _clamp(t, tol)
    u *= t
    hh *= u
    return np.sqrt(hh, out=hh) if owned(hh) else np.sqrt(hh)


def _clamp(f, tol):
    """A linear factor of H^2 in place: NaN below ``tol`` (< 0), 0 in [tol, 0)."""
    f = put(f, np.nan, f < tol)
    return np.maximum(f, 0.0, out=f)  # NaN stays NaN


def _angle_deg(s, c):
    """atan2 in degrees, mapped to (-90, 270] (the listing's range for TH3, TH4)."""
    a = np.asarray(np.arctan2(s, c))
    a *= _DEGREES  # = np.degrees, in place: a fresh array costs more than the product
    return np.add(a, 360.0, out=a, where=a <= -90.0)


@step(provides=("ASSEMBLED",), needs=("s34",))
def _assembly(s34):
    """True where the loop closes at this crank angle (the position exists)."""
    return np.isfinite(s34)


@step(provides=("ATH3", "ATH4"), needs=("c3", "s3", "c4", "s4"))
def _link_angles(c3, s3, c4, s4):
    return _angle_deg(s3, c3), _angle_deg(s4, c4)


@step(provides=("GAMMA",), needs=("s34", "c34"))
def _transmission_angle(s34, c34):
    """Angle between coupler and rocker (at B), degrees in [0, 180] on either branch
    (the crossed branch has sin(th3 - th4) of the other sign)."""
    return np.degrees(np.arctan2(np.abs(s34), c34))
