"""An optional compiled backend: the 1966 scene in one numba loop (``pip install sielaff[fast]``).

In:  one mechanism (scalar fields, TH2D != 0), crank angles ATH2 (degrees), the branch, TEX
     as a constant (in-lb), no other effect.
Out: every name of :data:`~sielaff.engine.outputs.RESULTS`, in the units ``analyze`` gives.

``analyze(..., backend="numba")`` runs this loop instead of the steps.  Each position is
computed with the steps' own formulas, in the same order of operations, written out once
for a scalar position.  A compiler may contract or reorder some of them (LLVM), so the
results are not bit-identical to the numpy path.  tests/test_compiled.py holds them
within 1E-12 of it, relative to each output's largest magnitude over the run; the exception is
directions of vectors that are zero to roundoff, which no path defines better.  Anything
this loop does not cover raises ValueError naming it, so the caller can use the numpy
steps:

* an effect (crank acceleration, gravity, loads, a TEX that is not a constant);
* a crank at rest;
* arrays of designs;
* lengths past 1E-70 to 1E70.

The package works without numba.  Importing this module does not import numba; the first
call compiles the loop (about 2 s), later calls reuse it.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["available", "compiled_results"]

_KERNEL = None
DEGREES = 180.0 / math.pi  # what np.degrees multiplies by
EPS = float(np.finfo(float).eps)


def available() -> bool:
    """Whether numba can be imported here."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def _positions_loop(ath2, p, out):
    """The loop numba compiles: ``p`` the parameters (see ``compiled_results``), ``out``
    the (71, n) results in RESULTS order."""
    (R1, R2, R3, R4, RG2, RG3, RG4, cA2, sA2, cA3, sA3, cA4, sA4, W2, W3, W4, ZI3, ZI4,
     TH2D, TEX, GW, BRANCH, rot2, rot3, rot4) = (p[0], p[1], p[2], p[3], p[4], p[5], p[6],
                                                 p[7], p[8], p[9], p[10], p[11], p[12], p[13],
                                                 p[14], p[15], p[16], p[17], p[18], p[19],
                                                 p[20], p[21], p[22], p[23], p[24])
    deg = 180.0 / math.pi
    rad = math.pi / 180.0
    tol = -8.0 * 2.220446049250313e-16 * (R1 + R2 + R3 + R4)  # positions.ASSEMBLY_TOL_EPS
    k2 = -W2 / GW
    k3 = -W3 / GW
    k4 = -W4 / GW
    for i in range(ath2.shape[0]):
        a = ath2[i]
        if not (a >= 0.0 and a < 360.0):
            a = a % 360.0
        th2 = a * rad
        c2 = math.cos(th2)
        s2 = math.sin(th2)
        # positions (positions._loop_closure)
        dx = R1 - R2 * c2
        dy = s2 * -R2
        zl2 = dx * dx + dy * dy
        zl = math.sqrt(zl2)
        t = zl + R3
        f0 = t + R4
        f1 = t - R4
        t = zl - R3
        f2 = R4 - t
        f3 = t + R4
        hh = math.nan
        if f1 >= tol and f2 >= tol and f3 >= tol:  # each linear factor, as positions
            hh = (f0 * max(f1, 0.0)) * (max(f2, 0.0) * max(f3, 0.0))
        h = math.sqrt(hh)
        if BRANCH != 1.0:
            h = -h
        q = zl2 + (R3 * R3 - R4 * R4)
        c3 = dx * q - dy * h
        s3 = dy * q + dx * h
        q = (0.5 / R3) / zl2
        c3 *= q
        s3 *= q
        c4 = (R3 * c3 - dx) / R4
        s4 = (R3 * s3 - dy) / R4
        kk = -0.5 / (R3 * R4)
        s34 = h * kk
        c34 = (zl2 - (R3 * R3 + R4 * R4)) * kk
        ath3 = math.atan2(s3, c3) * deg
        if ath3 <= -90.0:
            ath3 += 360.0
        ath4 = math.atan2(s4, c4) * deg
        if ath4 <= -90.0:
            ath4 += 360.0
        # centres of mass lines (velocities._rotate)
        cd2, sd2 = (c2 * cA2 - s2 * sA2, s2 * cA2 + c2 * sA2) if rot2 else (c2, s2)
        cd3, sd3 = (c3 * cA3 - s3 * sA3, s3 * cA3 + c3 * sA3) if rot3 else (c3, s3)
        cd4, sd4 = (c4 * cA4 - s4 * sA4, s4 * cA4 + c4 * sA4) if rot4 else (c4, s4)
        # rates
        k = (R2 * TH2D) / s34
        th3d = (s4 * c2 - c4 * s2) * k / R3
        th4d = (s3 * c2 - c3 * s2) * k / R4
        a2 = R2 * TH2D * TH2D
        a3 = th3d * th3d * R3
        a4 = th4d * th4d * R4
        th3dd = (((c4 * c2 + s4 * s2) * a2 + a3 * c34) - a4) / (s34 * -R3)
        th4dd = (((c3 * c2 + s3 * s2) * -a2 + a4 * c34) - a3) / (s34 * R4)
        # velocities (velocities._pivot_vel)
        rw = R2 * TH2D
        vax, vay = s2 * -rw, c2 * rw
        rw = RG2 * TH2D
        vg2x, vg2y = sd2 * -rw, cd2 * rw
        rw = R4 * th4d
        vbx, vby = s4 * -rw, c4 * rw
        rw = RG4 * th4d
        vg4x, vg4y = sd4 * -rw, cd4 * rw
        rw = RG3 * th3d
        vg3x, vg3y = sd3 * -rw + vax, cd3 * rw + vay
        # accelerations (accelerations._pivot_acc)
        kA = -R2 * TH2D * TH2D
        aax, aay = c2 * kA, s2 * kA
        kA = -RG2 * TH2D * TH2D
        ag2x, ag2y = cd2 * kA, sd2 * kA
        rw2 = th4d * th4d * R4
        ra = th4dd * R4
        abx, aby = -(rw2 * c4 + ra * s4), ra * c4 - rw2 * s4
        rw2 = th4d * th4d * RG4
        ra = th4dd * RG4
        ag4x, ag4y = -(rw2 * cd4 + ra * sd4), ra * cd4 - rw2 * sd4
        rw2 = th3d * th3d * RG3
        ra = th3dd * RG3
        ag3x, ag3y = -(rw2 * cd3 + ra * sd3) + aax, (ra * cd3 - rw2 * sd3) + aay
        # inertia and forces (inertia.py, forces.py: superposition, link by link)
        fg2x, fg2y = ag2x * k2, ag2y * k2
        fg3x, fg3y = ag3x * k3, ag3y * k3
        fg4x, fg4y = ag4x * k4, ag4y * k4
        ti3 = th3dd * -ZI3
        ti4 = th4dd * -ZI4
        f = ((sd4 * fg4x - cd4 * fg4y) * RG4 - ti4 - TEX) / (s34 * R4)
        fp34x, fp34y = f * c3, f * s3
        fp41x, fp41y = fg4x + fp34x, fg4y + fp34y
        tp2 = (s3 * c2 - c3 * s2) * f * R2
        g = ((sd3 * fg3x - cd3 * fg3y) * RG3 - ti3) / (s34 * -R3)
        fpp43x, fpp43y = g * c4, g * s4
        fpp32x, fpp32y = fpp43x + fg3x, fpp43y + fg3y
        tpp2 = (s2 * fpp32x - c2 * fpp32y) * R2
        fa32x, fa32y = -fp34x + fpp32x, -fp34y + fpp32y
        fb34x, fb34y = fp34x - fpp43x, fp34y - fpp43y
        torq = tp2 + tpp2
        foax, foay = -fp34x + fpp32x + fg2x, -fp34y + fpp32y + fg2y
        fobx, foby = fp41x - fpp43x, fp41y - fpp43y
        shakx, shaky = foax + fobx, foay + foby
        out[0, i] = ath2[i]
        out[1, i] = ath3
        out[2, i] = ath4
        out[3, i] = math.atan2(abs(s34), c34) * deg
        out[4, i] = th3d
        out[5, i] = th4d
        out[6, i] = th3dd
        out[7, i] = th4dd
        out[8, i] = TEX
        j = 9
        for x, y in ((vg2x, vg2y), (vax, vay), (vg3x, vg3y), (vbx, vby), (vg4x, vg4y),
                     (ag2x, ag2y), (aax, aay), (ag3x, ag3y), (abx, aby), (ag4x, ag4y),
                     (fa32x, fa32y), (fb34x, fb34y), (foax, foay), (fobx, foby),
                     (shakx, shaky)):
            d = math.atan2(y + 0.0, x + 0.0) * deg
            if d < 0.0:
                d += 360.0
            if d >= 360.0:
                d = 0.0
            out[j, i] = math.sqrt(x * x + y * y)
            out[j + 1, i] = d + 0.0
            out[j + 2, i] = x
            out[j + 3, i] = y
            j += 4
        out[69, i] = torq
        out[70, i] = foby * R1 - torq


def _kernel():
    global _KERNEL
    if _KERNEL is None:
        import numba

        _KERNEL = numba.njit(cache=False, error_model="numpy")(_positions_loop)
    return _KERNEL


def compiled_results(mechanism, ath2: Any, tex: Any = 0.0, *, th2dd: Any = 0.0,
                     gravity: Any = None, loads: Any = (), branch: str = "open"
                     ) -> np.ndarray:
    """The (71, n) results of RESULTS at the flattened ``ath2`` (see the module doc);
    ValueError for what the loop does not cover, ImportError without numba."""
    from sielaff.mechanism import MASS_DIVISOR

    m = mechanism
    for name, v in m.as_dict().items():
        if np.ndim(v):
            raise ValueError(f"backend='numba' analyses one design: {name} is an array")
    if callable(tex) or np.ndim(tex):
        raise ValueError("backend='numba' takes TEX as a constant")
    if callable(th2dd) or np.any(np.asarray(th2dd) != 0.0) or gravity is not None or loads:
        raise ValueError("backend='numba' covers the 1966 scene: no crank acceleration, "
                         "gravity or loads")
    if m.TH2D == 0.0:
        raise ValueError("backend='numba' needs a turning crank (TH2D != 0)")
    lengths = [float(m.R1), float(m.R2), float(m.R3), float(m.R4)]
    if not (1e-70 < min(lengths) and max(lengths) < 1e70):
        raise ValueError("backend='numba' takes lengths from 1E-70 to 1E70")
    if branch not in ("open", "crossed"):
        raise ValueError(f"branch = {branch!r}: 'open' or 'crossed'")
    rot = []
    for adel in (m.ADEL2, m.ADEL3, m.ADEL4):
        d = math.radians(float(adel))
        rot += [math.cos(d), math.sin(d)]
    p = np.array(lengths + [float(m.RG2), float(m.RG3), float(m.RG4)] + rot
                 + [float(m.W2), float(m.W3), float(m.W4), float(m.ZI3), float(m.ZI4),
                    float(m.TH2D), float(tex), MASS_DIVISOR[m.units],
                    1.0 if branch == "open" else -1.0]
                 + [float(float(x) != 0.0) for x in (m.ADEL2, m.ADEL3, m.ADEL4)])
    th = np.ascontiguousarray(np.asarray(ath2, dtype=float).reshape(-1))
    out = np.empty((71, th.size))
    _kernel()(th, p, out)
    return out
