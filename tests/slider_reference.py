"""An independent slider-crank: its motion from the textbook closed form differentiated by
sympy, its forces from the Newton-Euler equations of the three bodies solved by
numpy.linalg.solve, its kinetic energy for the power balance.

Trusts nothing of the engine.  The closed form: with d = offset - R2 sin th2,
XB = R2 cos th2 + s sqrt(R3^2 - d^2) (s = +1 the open branch, B right of A; -1 crossed),
th3 = atan2(d, s sqrt(R3^2 - d^2)).  The crank angle is th0 + w t + a t^2 / 2, so the
first and second time derivatives at t = 0 are the rates at constant speed w and
acceleration a.  Units: in, lb (weights; mass = W / g), sec, as the report's.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from sielaff.quantities import G

# the closed form is sympy's (the check extra): without it the tests that use it skip
sp = pytest.importorskip("sympy")

_t = sp.Symbol("t")
_SYMS = sp.symbols("R2 R3 e w a th0 sgn RG2 ADEL2 RG3 ADEL3")


@functools.lru_cache(maxsize=1)
def _kinematics():
    """Lambdified (value, d/dt, d2/dt2) at t = 0 of the points and angles."""
    R2, R3, e, w, a, th0, sgn, RG2, ADEL2, RG3, ADEL3 = _SYMS
    th2 = th0 + w * _t + a * _t ** 2 / 2
    d = e - R2 * sp.sin(th2)
    root = sgn * sp.sqrt(R3 ** 2 - d ** 2)
    th3 = sp.atan2(d, root)
    ax, ay = R2 * sp.cos(th2), R2 * sp.sin(th2)
    exprs = {
        "th2": th2, "th3": th3, "XB": ax + root,
        "G2x": RG2 * sp.cos(th2 + ADEL2), "G2y": RG2 * sp.sin(th2 + ADEL2),
        "Ax": ax, "Ay": ay,
        "G3x": ax + RG3 * sp.cos(th3 + ADEL3), "G3y": ay + RG3 * sp.sin(th3 + ADEL3),
    }
    out = {}
    for name, ex in exprs.items():
        d1 = sp.diff(ex, _t)
        d2 = sp.diff(d1, _t)
        out[name] = tuple(sp.lambdify(_SYMS, f.subs(_t, 0), "mpmath") for f in (ex, d1, d2))
    return out


def motion(m, th2_deg: float, th2dd: float = 0.0, branch: str = "open") -> dict:
    """{name: (value, rate, acceleration)} at one crank angle (floats, from 30 digits)."""
    import mpmath

    args = (m.R2, m.R3, m.offset, m.TH2D, th2dd, math.radians(th2_deg),
            1.0 if branch == "open" else -1.0, m.RG2, math.radians(m.ADEL2), m.RG3,
            math.radians(m.ADEL3))
    with mpmath.workdps(30):
        return {k: tuple(float(f(*[mpmath.mpf(x) for x in args])) for f in fs)
                for k, fs in _kinematics().items()}


def cross(ax, ay, bx, by):
    return ax * by - ay * bx


def newton_euler(m, th2_deg: float, *, th2dd: float = 0.0, branch: str = "open",
                 gravity=(0.0, 0.0), fex: float = 0.0, rod_load=None, spring=None) -> dict:
    """The pin forces, the guide's force and couple, and the drive torque at one position.

    Unknowns: F12 (frame on the crank at O2), F23 (crank on rod at A), F34 (rod on slider
    at B), N (guide on slider, +y), MN (guide's couple), T (drive on crank): nine.
    ``rod_load``: (r, angle_deg, fx, fy, torque) on the rod, placed from A along its line.
    ``spring``: (px, py, k, free length) from a frame point to B.
    """
    k = motion(m, th2_deg, th2dd, branch)
    gx, gy = gravity
    m2, m3, m4 = m.W2 / G, m.W3 / G, m.W4 / G
    ax, ay = k["Ax"][0], k["Ay"][0]
    bx, by = k["XB"][0], m.offset
    g2 = (k["G2x"][0], k["G2y"][0])
    g3 = (k["G3x"][0], k["G3y"][0])
    a2 = (k["G2x"][2], k["G2y"][2])
    a3 = (k["G3x"][2], k["G3y"][2])
    al2, al3 = k["th2"][2], k["th3"][2]
    # applied forces per body (besides the unknowns)
    f3x, f3y, m3_ext = m3 * gx, m3 * gy, 0.0  # moment about G3
    if rod_load is not None:
        r, ang, lfx, lfy, lt = rod_load
        th3 = k["th3"][0]
        px, py = ax + r * math.cos(th3 + math.radians(ang)), ay + r * math.sin(
            th3 + math.radians(ang))
        f3x, f3y = f3x + lfx, f3y + lfy
        m3_ext += cross(px - g3[0], py - g3[1], lfx, lfy) + lt
    f4x, f4y = m4 * gx + fex, m4 * gy
    if spring is not None:
        sx, sy, kk, l0 = spring
        length = math.hypot(bx - sx, by - sy)
        t = kk * (length - l0)
        f4x -= t * (bx - sx) / length
        f4y -= t * (by - sy) / length
    A = np.zeros((9, 9))
    b = np.zeros(9)
    # crank: F12 - F23 + m2 g = m2 aG2; about G2: (O2-G2) x F12 + (A-G2) x (-F23) + T = I2 al2
    A[0, 0], A[0, 2], b[0] = 1, -1, m2 * a2[0] - m2 * gx
    A[1, 1], A[1, 3], b[1] = 1, -1, m2 * a2[1] - m2 * gy
    A[2, 0], A[2, 1] = g2[1], -g2[0]  # r x F = rx Fy - ry Fx with r = O2 - G2 = -g2
    A[2, 2], A[2, 3] = (ay - g2[1]), -(ax - g2[0])  # (A-G2) x (-F23)
    A[2, 8], b[2] = 1, m.ZI2 * al2
    # rod: F23 - F34 + F3 = m3 aG3; about G3: (A-G3) x F23 + (B-G3) x (-F34) + M3 = I3 al3
    A[3, 2], A[3, 4], b[3] = 1, -1, m3 * a3[0] - f3x
    A[4, 3], A[4, 5], b[4] = 1, -1, m3 * a3[1] - f3y
    A[5, 2], A[5, 3] = -(ay - g3[1]), (ax - g3[0])
    A[5, 4], A[5, 5] = (by - g3[1]), -(bx - g3[0])
    b[5] = m.ZI3 * al3 - m3_ext
    # slider: F34 + (0, N) + F4 = m4 (AXB, 0); its couples: MN = 0 (a point mass)
    A[6, 4], b[6] = 1, m4 * k["XB"][2] - f4x
    A[7, 5], A[7, 6], b[7] = 1, 1, -f4y
    A[8, 7] = 1
    x = np.linalg.solve(A, b)
    return {"FOAX": -x[0], "FOAY": -x[1], "FA32X": -x[2], "FA32Y": -x[3], "FB34X": x[4],
            "FB34Y": x[5], "FN": x[6], "MN": x[7], "TORQ": x[8], "motion": k}


def kinetic_energy_rate(m, th2_deg: float, th2dd: float = 0.0, branch: str = "open") -> float:
    """d/dt of the kinetic energy (the sum over bodies of m a.v + I al w)."""
    k = motion(m, th2_deg, th2dd, branch)
    m2, m3, m4 = m.W2 / G, m.W3 / G, m.W4 / G
    rate = 0.0
    for mass, p in ((m2, "G2"), (m3, "G3")):
        rate += mass * (k[p + "x"][1] * k[p + "x"][2] + k[p + "y"][1] * k[p + "y"][2])
    rate += m4 * k["XB"][1] * k["XB"][2]
    rate += m.ZI2 * k["th2"][1] * k["th2"][2] + m.ZI3 * k["th3"][1] * k["th3"][2]
    return rate


@functools.lru_cache(maxsize=4)
def _reduced(fields: tuple, spring: tuple | None):
    """Lambdified J(th), J'(th) and the applied forces' generalized force Q(th) about the
    crank angle th [rad], from the closed form (no time: positions as functions of th)."""
    R2, R3, e, W2, W3, W4, ZI2, ZI3, RG2, ADEL2, RG3, ADEL3, fex, gx, gy = fields
    th = sp.Symbol("th")
    d = e - R2 * sp.sin(th)
    root = sp.sqrt(R3 ** 2 - d ** 2)
    th3 = sp.atan2(d, root)
    ax, ay = R2 * sp.cos(th), R2 * sp.sin(th)
    xb = ax + root
    g2 = (RG2 * sp.cos(th + ADEL2), RG2 * sp.sin(th + ADEL2))
    g3 = (ax + RG3 * sp.cos(th3 + ADEL3), ay + RG3 * sp.sin(th3 + ADEL3))
    m2, m3, m4 = W2 / G, W3 / G, W4 / G
    J = (m2 * (sp.diff(g2[0], th) ** 2 + sp.diff(g2[1], th) ** 2) + ZI2
         + m3 * (sp.diff(g3[0], th) ** 2 + sp.diff(g3[1], th) ** 2)
         + ZI3 * sp.diff(th3, th) ** 2 + m4 * sp.diff(xb, th) ** 2)
    V = -(m2 * (gx * g2[0] + gy * g2[1]) + m3 * (gx * g3[0] + gy * g3[1])
          + m4 * (gx * xb + gy * e)) - fex * xb  # the potential of weights and FEX
    if spring is not None:
        px, py, k, l0 = spring
        V += k * (sp.sqrt((xb - px) ** 2 + (e - py) ** 2) - l0) ** 2 / 2
    Q = -sp.diff(V, th)
    return tuple(sp.lambdify(th, f, "mpmath") for f in (J, sp.diff(J, th), Q))


def reduced(m, *, gravity=(0.0, 0.0), fex=0.0, spring=None):
    """(J, dJ/dth, Q) as float functions of the crank angle [rad]: the equation of motion
    (J + F) th'' + J' th'^2 / 2 = M(th') + Q(th)."""
    fields = (m.R2, m.R3, m.offset, m.W2, m.W3, m.W4, m.ZI2, m.ZI3, m.RG2,
              math.radians(m.ADEL2), m.RG3, math.radians(m.ADEL3), fex, *gravity)
    fs = _reduced(tuple(float(x) for x in fields), None if spring is None else tuple(spring))
    def as_float(f):
        return lambda th: float(f(th))
    return tuple(as_float(f) for f in fs)


@functools.lru_cache(maxsize=4)
def _length_rate(fields: tuple, point: tuple):
    """dL/dth [in/rad]: L the distance from the frame point ``point`` to B."""
    R2, R3, e = fields
    th = sp.Symbol("th")
    xb = R2 * sp.cos(th) + sp.sqrt(R3 ** 2 - (e - R2 * sp.sin(th)) ** 2)
    length = sp.sqrt((xb - point[0]) ** 2 + (e - point[1]) ** 2)
    return sp.lambdify(th, sp.diff(length, th), "mpmath")


def length_rate(m, point):
    """dL/dth as a float function of th [rad]: a damper of rate c from ``point`` (on the
    frame) to B adds the generalized force -c (dL/dth)^2 th'."""
    f = _length_rate((float(m.R2), float(m.R3), float(m.offset)), tuple(map(float, point)))
    return lambda th: float(f(th))
