"""The optional compiled backend: one numba loop per wanted set of outputs (``sielaff[fast]``).

In:  one design (scalar fields), crank angles ATH2 (degrees, 1-D), the branch, and the
     effects cheap to compile: TEX and the crank's angular acceleration TH2DD (each a
     constant or an array of ATH2's length), gravity (gx, gy), and point loads whose r,
     angle, fx, fy and torque are constants or arrays of ATH2's length.
Out: the wanted outputs (any of :data:`SUPPORTED`: every result and intermediate of the
     numpy steps but ``ASSEMBLED``), in the units ``analyze`` gives, written straight into
     the caller's arrays when it passes them (no allocation per call); and the count of
     positions where the loop cannot close (the assembly test itself).

How it is fast (issue 25: why the first numba loop lost to gfortran)
    * One kernel is generated per request: the outputs wanted, which inputs are zero (a
      step the numpy engine skips is the literal 0.0 here too: the same NaN), which
      effects are arrays.  Only the steps those outputs need are in it.
    * Every transcendental is branch-free arithmetic LLVM can vectorise: sin and cos by
      Cody-Waite reduction (pi/2 in three 33-bit parts) and polynomials of 7 and 6
      terms on |r| <= pi/4, atan2 by octant reduction, a shift to 0, tan(pi/8) or 1 and
      a polynomial of 8 terms on |u| <= tan(pi/16) (Chebyshev fits, within 1e-17 of the
      functions: ``benchmarks/fit_transcendentals.py`` makes them and prints their
      error), each evaluated by Horner's rule in fused multiply-adds (``llvm.fma``: one
      rounding, the same result on every CPU); the mod-360 reduction by floor and two
      exact corrections.  No libm call, no fastmath (it would break NaN propagation).
      The loop bound is unsigned (no negative-index wraparound in every ``a[i]``), and
      LLVM's limit on runtime alias checks (``-vectorize-memory-check-threshold``, 128)
      is raised only while the kernel compiles.
    * Fewer transcendentals: where TH2DD is a constant, AA and AG2 turn with the crank
      (``_ACC2_SHORTCUT``: magnitude R2 K, direction ATH2 + a constant; no atan2 or sqrt
      per position); where ATH3 and ATH4 are computed anyway, GAMMA is the angle between
      them (``_GAMMA_SHORTCUT``), and AB and AG4 are R4 and RG4 e^{i ATH4} times one
      complex number per position (``_ACC4_SHORTCUT``: one atan2 and one sqrt for the
      two magnitudes and two directions).  VA, VG2, VB and VG4 take their directions
      from ATH2 and ATH4 (``_ROTATING``), as the numpy engine does.
    * The loop fills a (wanted, BLOCK) scratch table that stays in the cache and copies
      each row out (71 output streams at once defeat the hardware's prefetch).  When the
      outputs are larger than a cache (``STREAM_BYTES``) the copy writes each whole
      64-byte line by non-temporal stores (``_put``): the line goes to memory without
      first being read, which plain stores of a line not in the cache must do.
    * Otherwise the arithmetic of each step is the numpy step's, in the same order
      (numba does not contract to FMA without fastmath), so the two paths differ only by
      the transcendentals and the shortcuts above.

Error bound (stated and tested in tests/test_compiled.py, against the numpy engine):
    sin and cos here are within 1 ulp of the correctly rounded value (for |x| <= 4 pi;
    the kernel takes them of angles in [0, 2 pi); 2 ulp up to 2^20), atan2 within 2 ulp
    (tests/test_compiled_transcendentals.py, against mpmath), and the shortcuts only
    round differently, so each output differs from the numpy engine's by roundoff
    carried through the same formulas: at most ``ERROR_BOUND`` (1e-13) times that
    output's scale, the largest finite magnitude over the call of the outputs of its kind
    (velocities, accelerations, forces, rates, angular accelerations, torques; at least
    R2 |TH2D| for velocities, TH2D^2 + |TH2DD| for angular accelerations, ...; 360 for
    angles and directions, compared on the circle; a direction also within ERROR_BOUND
    times its kind's scale over its vector's magnitude, in radians: a short vector's
    direction is only as good as its components), at every position at least
    ``CONDITION_LIMIT`` from a toggle (``|sin GAMMA| >= 0.25``).  Nearer a toggle the
    position itself is ill-conditioned in the crank angle (a rounding of cos TH2 moves
    H by eps / sin^2 GAMMA relatively, and each derivative divides by sin GAMMA once
    more), so neither path is more right than the other; there the bound is multiplied
    by ``(0.25 / sin GAMMA) ** CONDITION_POWER[kind]``: 2 for angles, 3 for rates and
    velocities, 4 for angular accelerations and accelerations, 6 for forces and torques
    (calibrated, not derived: a drawn rocker-crank whose crank swings only near its
    toggles, |sin GAMMA| = 0.16, showed forces 1.7 times past the cube, and a drawn
    double rocker, R = 1, 5, 0.25, 5.375, at |sin GAMMA| = 0.19 on both branches, 1.03
    times past the fifth power).  NaN and infinities exactly where the numpy engine has
    them, except at a toggle to within roundoff (|sin GAMMA| < 1e-6), where either
    engine's rates are infinite or NaN by the luck of rounding (0 / 0, inf - inf).
    Not covered: linkages near a change point (s + l = p + q within 3% of the Grashof
    sum: drawn double rockers at 1.4%, R = 1, 8.25, 0.5, 8 and 1.5, 16.19, 0.84, 16,
    showed forces 1.2-1.4 times past the bound) other than at their well-conditioned
    positions; linkages whose coupler or rocker is shorter than ``COVERED_SHORT`` (1/20)
    of the longest link (their angles come from differences of points a link's length
    apart; drawn double rockers with a coupler of 0.25 against a longest link of 5.4 and
    6.2 showed forces 1.03 times past the bound with the fifth power and 1.2 times past it
    with the sixth); a rhombus (R1 = R2 = R3 = R4)
    folds through A = O4 and
    its forces that are zero in exact arithmetic carry roundoff past the bound in both
    engines.

Semantics (those of the numpy engine after issue 20's fixes):
    GAMMA in [0, 180] on both branches; a zero vector's direction is 0; a position is
    assembled when each linear factor of Heron's product is >= -tol, tol =
    ``ASSEMBLY_TOL_EPS`` eps (R1+R2+R3+R4) (a factor in [-tol, 0) is taken as 0);
    ATH2 is reduced modulo 360 element by element; an output that depends on the
    position is NaN where the loop cannot close, a skipped step's 0.0 included.

Anything else (a function of the angle for TEX, TH2DD or a load field, arrays of designs,
crank angles past 2^50 degrees, an output not in SUPPORTED; through ``analyze``, pin
friction, springs and dampers) is a ValueError in one line.  The package works without
numba: importing this module does not import numba, and ``backend="numba"`` without it
is an ImportError in one line naming the ``fast`` extra.

The kernel cache
    The first call of a request compiles its kernel (tens of seconds).  To keep the
    machine code for later processes the kernel's source is written, once, as a module
    named by its hash (a temporary file renamed: whole or not at all) into
    ``$SIELAFF_KERNEL_DIR``, else ``$XDG_CACHE_HOME/sielaff/kernels``, else
    ``~/.cache/sielaff/kernels``, and imported from there, numba's own cache beside it
    (``__pycache__``).  Nothing is written anywhere else (not in the package, not in the
    working directory).  ``SIELAFF_KERNEL_DIR=off`` turns the cache off; a folder that
    cannot be made or written (a read-only home) is no cache: the kernel is then
    compiled in memory for this process alone, silently.  The folder only grows by one
    small module per request shape; deleting it is always safe.

This module reads better whole: the scalar steps, the generator that writes one kernel
from them and the helpers it inlines are one design.
"""

from __future__ import annotations

import ast
import copy
import math
import os
import sys
import threading
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["ASSEMBLY_TOL_EPS", "CONDITION_LIMIT", "CONDITION_POWER", "COVERED_SHORT", "ERROR_BOUND",
           "KERNEL_DIR_ENV", "SUPPORTED", "available", "compiled_analyze", "kernel_dir"]

#: The assembly test's tolerance, in units of eps (R1 + R2 + R3 + R4), on each linear
#: factor of Heron's product: the numpy engine's (issue 20), one source.
from sielaff.engine.fourbar import FOURBAR  # noqa: E402
from sielaff.engine.positions import ASSEMBLY_TOL_EPS  # noqa: E402

#: The stated bound: |compiled - numpy| <= ERROR_BOUND * scale of the output (see above).
ERROR_BOUND = 1e-13

#: The bound is not claimed where the coupler or the rocker is shorter than this fraction
#: of the longest link (see above; calibrated on drawn double rockers, not derived).
COVERED_SHORT = 0.05

#: |sin GAMMA| below which a position counts as near a toggle (the bound widens there).
CONDITION_LIMIT = 0.25

#: Near a toggle the bound is multiplied by (CONDITION_LIMIT / |sin GAMMA|) ** power, the
#: power by the output's kind: each derivative divides by sin GAMMA once more (see above).
CONDITION_POWER = {"angle": 2, "rate": 3, "velocity": 3, "angular acceleration": 4,
                   "acceleration": 4, "force": 6, "torque": 6}

EPS = float(np.finfo(float).eps)
DEGREES = 180.0 / math.pi  # what np.degrees multiplies by
RADIANS = math.pi / 180.0  # what np.radians multiplies by
_BIG_ANGLE = 2.0**50  # past this, x - 360 floor(x / 360) is no longer exact

# --- the branch-free transcendentals --------------------------------------------------
# pi/2 = _P1 + _P2 + _P3, _P1 and _P2 of 33 bits (q _P1 and q _P2 exact for q < 2^20)
_P1 = 1.5707963267341256
_P2 = 6.077100506303966e-11
_P3 = 2.0222662487959506e-21
_TWO_OVER_PI = 2.0 / math.pi
# atan: the breakpoints tan(pi/16), tan(3 pi/16); the shifts tan(pi/8) and 1 with their
# arctangents as hi + lo (mpmath, 200 bits)
_T16 = 0.19891236737965800
_T316 = 0.66817863791929891
_TAN8 = 0.41421356237309503
_ATAN8_HI, _ATAN8_LO = 0.39269908169872414, 3.060132146563891e-18
_PI4_HI, _PI4_LO = 0.7853981633974483, 3.061616997868383e-17
_PI2_HI, _PI2_LO = 1.5707963267948966, 6.123233995736766e-17
_PI_HI, _PI_LO = 3.141592653589793, 1.2246467991473532e-16
_TWO_PI_HI, _TWO_PI_LO = 2.0 * _PI_HI, 2.0 * _PI_LO

# the polynomials' coefficients, lowest first (benchmarks/fit_transcendentals.py prints
# them and the error of each polynomial: Chebyshev fits in 200-bit arithmetic, rounded)
(_A0, _A1, _A2, _A3, _A4, _A5, _A6, _A7) = (
    -0.3333333333333333, 0.1999999999999729, -0.1428571428427355, 0.11111110818998077,
    -0.0909087995193466, 0.07690724472468718, -0.06618732486766733, 0.05115745967981171)
(_S0, _S1, _S2, _S3, _S4, _S5, _S6) = (
    -0.16666666666666666, 0.008333333333333331, -0.00019841269841265065,
    2.7557319219339167e-06, -2.5052106232447578e-08, 1.6058531618986147e-10,
    -7.586697117706918e-13)
(_C0, _C1, _C2, _C3, _C4, _C5) = (
    0.041666666666666664, -0.0013888888888887398, 2.480158729876569e-05,
    -2.7557317271729793e-07, 2.08761462684032e-09, -1.1382632425521717e-11)


def _select(c, a, b):
    """``a if c else b``; compiled, one LLVM select (no branch, no basic block)."""
    return a if c else b


def _floor(x):
    """math.floor as a float; compiled, LLVM's floor intrinsic (one vroundpd)."""
    return float(np.floor(x))


def _intrinsics():
    """(_select, _floor, _address, _stream4, _sfence, _fma) for numba: each one LLVM
    instruction (or two), no call, no branch."""
    import llvmlite.ir as ir
    from numba.core import cgutils, types
    from numba.extending import intrinsic

    @intrinsic
    def select(typingctx, c, a, b):
        t = typingctx.unify_types(a, b)
        if t is None or not isinstance(t, (types.Float, types.Integer)):
            return None

        def codegen(context, builder, sig, args):
            cond = context.cast(builder, args[0], sig.args[0], types.boolean)
            x = context.cast(builder, args[1], sig.args[1], t)
            y = context.cast(builder, args[2], sig.args[2], t)
            return builder.select(cond, x, y)

        return t(c, a, b), codegen

    @intrinsic
    def floor(typingctx, x):
        if not isinstance(x, types.Float):
            return None

        def codegen(context, builder, sig, args):
            fn = builder.module.declare_intrinsic("llvm.floor", [ir.DoubleType()])
            v = context.cast(builder, args[0], sig.args[0], types.float64)
            return builder.call(fn, [v])

        return types.float64(x), codegen

    @intrinsic
    def fma(typingctx, x, y, z):
        """x y + z rounded once (llvm.fma: vfmadd, the same result on every CPU)."""
        if not all(isinstance(a, types.Float) for a in (x, y, z)):
            return None

        def codegen(context, builder, sig, args):
            d = ir.DoubleType()
            fn = builder.module.declare_intrinsic("llvm.fma", [d], ir.FunctionType(d, [d, d, d]))
            v = [context.cast(builder, a, t, types.float64) for a, t in zip(args, sig.args)]
            return builder.call(fn, v)

        return types.float64(x, y, z), codegen

    @intrinsic
    def address(typingctx, a):
        """The address of an array's first element."""
        if not isinstance(a, types.Array):
            return None

        def codegen(context, builder, sig, args):
            arr = context.make_array(sig.args[0])(context, builder, args[0])
            return builder.ptrtoint(arr.data, ir.IntType(64))

        return types.uint64(a), codegen

    @intrinsic
    def stream4(typingctx, dst, k, src, j, i):
        """dst[k:k+4] = src[j, i:i+4], one non-temporal 32-byte store (dst + 8 k must
        be 32-byte aligned): the cache line goes to memory without being read first."""
        if not (isinstance(dst, types.Array) and isinstance(src, types.Array)
                and src.ndim == 2 and src.layout == "C"):
            return None

        def codegen(context, builder, sig, args):
            d = context.make_array(sig.args[0])(context, builder, args[0])
            s = context.make_array(sig.args[2])(context, builder, args[2])
            kk, jj, ii = (context.cast(builder, args[n], sig.args[n], types.intp)
                          for n in (1, 3, 4))
            ncol = builder.extract_value(s.shape, 1)
            sp = builder.gep(s.data, [builder.add(builder.mul(jj, ncol), ii)])
            vec = ir.VectorType(ir.DoubleType(), 4)
            v = builder.load(builder.bitcast(sp, vec.as_pointer()), align=8)
            st = builder.store(v, builder.bitcast(builder.gep(d.data, [kk]), vec.as_pointer()),
                               align=32)
            st.set_metadata("nontemporal", builder.module.add_metadata(
                [ir.Constant(ir.IntType(32), 1)]))
            return context.get_dummy_value()

        return types.none(dst, k, src, j, i), codegen

    @intrinsic
    def sfence(typingctx):
        """Orders the non-temporal stores before anything after the kernel: x86's
        sfence there, an LLVM seq_cst fence on other machines (whose compilers have no
        x86 intrinsic: the kernel would not compile at all)."""
        x86 = _x86()

        def codegen(context, builder, sig, args):
            if x86:
                fn = cgutils.get_or_insert_function(
                    builder.module, ir.FunctionType(ir.VoidType(), []), "llvm.x86.sse.sfence")
                builder.call(fn, [])
            else:
                builder.fence("seq_cst")
            return context.get_dummy_value()

        return types.none(), codegen

    return select, floor, address, stream4, sfence, fma


def _x86() -> bool:
    """Whether numba compiles for an x86 machine here (it compiles for this process's)."""
    import llvmlite.binding as llvm

    return llvm.get_process_triple().split("-")[0] in ("x86_64", "i386", "i686")


# Python stand-ins for the intrinsics (the helpers run as plain Python in the tests)
_uintp = int


def _address(a):
    return a.ctypes.data


def _stream4(dst, k, src, j, i):
    dst[k:k + 4] = src[j, i:i + 4]


def _sfence():
    return None


def _fma(x, y, z):
    """x y + z rounded once (the kernel's ``llvm.fma``), exactly, in Python."""
    if not all(math.isfinite(v) for v in (x, y, z)):
        return x * y + z
    from fractions import Fraction

    return float(Fraction(x) * Fraction(y) + Fraction(z))


def _put(o, s0, sc, j, m, stream):
    """o[s0:s0+m] = sc[j, :m]; with ``stream``, the whole 64-byte lines of o by
    non-temporal stores (o's elements 8-byte aligned; a partial line at either end by
    plain stores: a line written in two halves by streaming stores costs a read)."""
    q = _uintp(0)
    if stream:
        a = _address(o) + s0 * _uintp(8)
        h = ((_uintp(64) - (a & _uintp(63))) & _uintp(63)) >> _uintp(3)
        h = _select(h < m, h, m)
        for i in range(h):
            o[s0 + i] = sc[j, i]
        q = h
        while q + _uintp(8) <= m:
            _stream4(o, s0 + q, sc, j, q)
            _stream4(o, s0 + q + _uintp(4), sc, j, q + _uintp(4))
            q += _uintp(8)
    for i in range(q, m):
        o[s0 + i] = sc[j, i]


def _mod360(x):
    """np.mod(x, 360.0), exactly, for |x| < 2^50: floor, then the remainder (exact: a
    multiple of x's ulp below 720), one step up if the floor was one short, and 360 added
    to a negative one (rounded, as numpy's fmod + 360)."""
    t = _floor(x * (1.0 / 360.0))
    r = x - t * 360.0
    up = x - (t + 1.0) * 360.0  # exact and >= 0 when x / 360 rounded down past t + 1
    r = _select(up >= 0.0, up, r)
    return _select(r < 0.0, r + 360.0, r)


def _sincos(x):
    """(sin x, cos x) for |x| < 2^20 radians, within about 1 ulp."""
    q = _floor(x * _TWO_OVER_PI + 0.5)
    r = ((x - q * _P1) - q * _P2) - q * _P3  # |r| <= pi/4
    z = r * r
    # Chebyshev fits (benchmarks/fit_transcendentals.py): sin r = r + r z S(z), cos r =
    # 1 - z/2 + z^2 C(z), each within 1e-17 of the function for |r| <= pi/4; Horner by fma
    s = _fma(_fma(_fma(_fma(_fma(_fma(_S6, z, _S5), z, _S4), z, _S3), z, _S2), z, _S1), z, _S0)
    s = _fma(r * z, s, r)
    c = _fma(_fma(_fma(_fma(_fma(_C5, z, _C4), z, _C3), z, _C2), z, _C1), z, _C0)
    c = _fma(z * z, c, 1.0 - 0.5 * z)
    m = q - 4.0 * _floor(q * 0.25)  # the quadrant, 0..3
    sn = _select(m == 1.0, c, s)
    sn = _select(m == 2.0, -s, sn)
    sn = _select(m == 3.0, -c, sn)
    cs = _select(m == 1.0, -s, c)
    cs = _select(m == 2.0, -c, cs)
    cs = _select(m == 3.0, s, cs)
    return sn, cs


def _atan2(y, x):
    """atan2(y, x) in radians, within 2 ulp; (0, 0) gives 0 (the callers decide)."""
    a = _half_turn(y, x)
    return math.copysign(a, y)


def _half_turn(y, x):
    """atan2(|y|, x) in radians, in [0, pi]: 0 for (+-0, +-0)."""
    ax = abs(x)
    ay = abs(y)
    sw = ay > ax
    mx = _select(sw, ay, ax)
    mn = _select(sw, ax, ay)
    inf = mx == math.inf  # inf/inf is pi/4, finite/inf 0, as libm's atan2
    mn = _select(inf, _select(mn == math.inf, 1.0, 0.0), mn)
    mx = _select(inf, 1.0, mx)
    mx = _select(mx == 0.0, 1.0, mx)
    # atan(mn/mx) = atan c + atan u, u = (mn - c mx) / (mx + c mn), |u| <= tan(pi/16):
    # c = 0, tan(pi/8) or 1 (one division)
    hi2 = mn > _T316 * mx
    hi1 = mn > _T16 * mx
    c = _select(hi2, 1.0, _select(hi1, _TAN8, 0.0))
    a_hi = _select(hi2, _PI4_HI, _select(hi1, _ATAN8_HI, 0.0))
    a_lo = _select(hi2, _PI4_LO, _select(hi1, _ATAN8_LO, 0.0))
    u = _fma(-c, mx, mn) / _fma(c, mn, mx)
    w = u * u
    # a Chebyshev fit (benchmarks/fit_transcendentals.py): atan u = u + u w A(w), within
    # 1e-18 |u| for |u| <= tan(pi/16); Horner by fma
    p = _fma(_fma(_fma(_fma(_fma(_fma(_fma(_A7, w, _A6), w, _A5), w, _A4), w, _A3), w, _A2), w,
                  _A1), w, _A0)
    a = a_hi + (a_lo + _fma(u * w, p, u))
    a = _select(sw, _PI2_HI - (a - _PI2_LO), a)
    return _select(x < 0.0, _PI_HI - (a - _PI_LO), a)


def _link_angle(s, c):
    """The listing's link angle: atan2 in degrees, in (-90, 270]."""
    a = _atan2(s, c)
    a = a * DEGREES
    return _select(a <= -90.0, a + 360.0, a)


def _direction(x, y):
    """A vector's direction in degrees, in [0, 360); 0 for the zero vector (whose
    half turn is 0: -0.0 < 0 is false)."""
    a = _half_turn(y, x)
    a = _select(y < 0.0, _TWO_PI_HI - (a - _TWO_PI_LO), a)
    d = a * DEGREES
    return _select(d >= 360.0, 0.0, d)


def _magnitude(x, y):
    m = x * x
    m = m + y * y
    return math.sqrt(m)


def _gamma(s34, c34):
    """The transmission angle in degrees, [0, 180] on both branches."""
    g = _half_turn(s34, c34)
    return g * DEGREES


def _crank(ath2):
    """(sin, cos) of the crank angle reduced modulo 360 degrees (positions._crank_angle)."""
    a = _mod360(ath2)
    s, c = _sincos(a * RADIANS)
    return s, c


def _rot_direction(rw, d):
    """The direction of r w e^{i(line + 90)} with d = line (+ ADEL), degrees [0, 360)."""
    d = _select(rw > 0.0, d + 90.0, d - 90.0)
    d = _mod360(d)
    d = _select(d >= 360.0, 0.0, d)
    d = _select(rw == 0.0, 0.0, d)
    d = _select(rw != rw, math.nan, d)
    return d + 0.0


def _turned(m, k, ath2, phi):
    """The direction of a vector of magnitude m at ATH2 + phi (phi in [0, 360)): 0 for
    the zero vector, NaN at a NaN angle but for a skipped step's 0.0 (k == 0)."""
    d = _mod360(ath2)
    d = _mod360(d + phi)
    d = _select(d >= 360.0, 0.0, d)
    z = _select(k == 0.0, 0.0, ath2 - ath2)
    d = _select(m == 0.0, z, d)
    return d + 0.0


def _between(a3, a4):
    """The unsigned angle between two lines at a3 and a4 degrees (each in (-90, 270]),
    in [0, 180]: GAMMA from ATH3 and ATH4 (no atan2 of its own)."""
    g = abs(a4 - a3)
    return _select(g > 180.0, 360.0 - g, g)


def _acc_direction(line, turn, phi, r, w2, a, nz):
    """The direction in degrees, [0, 360), of r e^{i(line + turn)} (-w2 + i a): ``line``
    in degrees, ``turn`` a constant of the call in [0, 360) (with 180 added where r < 0),
    ``phi`` the direction of (-w2, a); 0 for the zero vector (r = 0, or w2 = a = 0), or
    ``nz``, NaN where an ingredient is not finite, as the components would be."""
    d = _mod360(line + turn)
    d = _mod360(d + phi)
    d = _select(d >= 360.0, 0.0, d)
    d = _select((r == 0.0) | ((w2 == 0.0) & (a == 0.0)), nz, d)
    return d + 0.0


_HELPERS = (_between, _acc_direction, _turned, _mod360, _sincos, _atan2, _half_turn,
            _link_angle, _direction, _magnitude, _rot_direction, _gamma, _crank)
_HELPER_ASTS: dict[str, ast.FunctionDef] = {}


def _helper_asts() -> dict[str, ast.FunctionDef]:
    """The helpers' syntax trees (read from this file once)."""
    if _HELPER_ASTS:
        return _HELPER_ASTS
    import inspect

    out = _HELPER_ASTS
    for f in _HELPERS:
        fn = ast.parse(inspect.getsource(f)).body[0]
        assert isinstance(fn, ast.FunctionDef)
        out[f.__name__] = fn
    return out


class _Rename(ast.NodeTransformer):
    def __init__(self, names: dict[str, str]):
        self.names = names

    def visit_Name(self, node: ast.Name) -> ast.Name:
        return ast.copy_location(ast.Name(self.names.get(node.id, node.id), node.ctx), node)


def _inline(lines: list[str], fns: dict[str, ast.FunctionDef], counter: list[int]) -> list[str]:
    """``lines`` with each ``x = _helper(...)`` (or ``x, y = ...``) written out in place,
    its locals renamed apart: one flat loop body (numba's own inlining takes minutes, and
    LLVM leaves calls)."""
    out: list[str] = []
    for stmt in ast.parse("\n".join(lines)).body:
        call = stmt.value if isinstance(stmt, ast.Assign) else None
        if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Name)
                and call.func.id in fns):
            out.append(ast.unparse(stmt))
            continue
        fn = fns[call.func.id]
        counter[0] += 1
        params = [a.arg for a in fn.args.args]
        local = set(params) | {t.id for st in ast.walk(fn) if isinstance(st, ast.Assign)
                               for tg in st.targets for t in ast.walk(tg)
                               if isinstance(t, ast.Name)}
        ren = _Rename({n: f"{n}_{counter[0]}" for n in local})
        body = [f"{n}_{counter[0]} = {ast.unparse(arg)}"
                for n, arg in zip(params, call.args, strict=True)]
        for st in fn.body:
            if isinstance(st, ast.Expr) and isinstance(st.value, ast.Constant):
                continue  # the docstring
            if isinstance(st, ast.Return) and st.value is not None:
                assert isinstance(stmt, ast.Assign)  # the call's line (checked above)
                value = ren.visit(copy.deepcopy(st.value))
                body.append(f"{ast.unparse(stmt.targets[0])} = {ast.unparse(value)}")
            else:
                body.append(ast.unparse(ren.visit(copy.deepcopy(st))))
        out += _inline(body, fns, counter)
    return out


# --- the steps, as the numpy engine declares them, each written for one position ------
# (provides, needs, zero groups, code).  ``code`` is a string, or a function of the set of
# names known to be the plain 0.0 of a skipped step (for ``statics.plus``).  A step whose
# zero group is all zero is skipped, its results the literal 0.0, as in registry._plan.


def _plus(a: str, b: str, zero: set[str]) -> str:
    """``statics.plus``: the other operand itself when one is a skipped step's 0.0."""
    if b in zero:
        return a
    if a in zero:
        return b
    return f"({a}) + ({b})"


def _pins_code(p: str, f2: tuple, f3: tuple, f4: tuple) -> str:
    """statics.pins for per-link loads (F2X, F2Y, M2), ...; results named p + suffix."""
    (F2X, F2Y, M2), (F3X, F3Y, M3), (F4X, F4Y, M4) = f2, f3, f4
    return f"""
ux_{p} = R3 * c3
uy_{p} = R3 * s3
vx_{p} = R4 * c4
vy_{p} = R4 * s4
d_{p} = s34 * (R3 * R4)
f34x_{p} = (-({M4}) * ux_{p} - vx_{p} * ({M3})) / d_{p}
f34y_{p} = (-vy_{p} * ({M3}) - uy_{p} * ({M4})) / d_{p}
f32x_{p} = ({F3X}) - f34x_{p}
f32y_{p} = ({F3Y}) - f34y_{p}
fa32x_{p} = f32x_{p}
fa32y_{p} = f32y_{p}
fb34x_{p} = f34x_{p}
fb34y_{p} = f34y_{p}
foax_{p} = f32x_{p} + ({F2X})
foay_{p} = f32y_{p} + ({F2Y})
fobx_{p} = f34x_{p} + ({F4X})
foby_{p} = f34y_{p} + ({F4Y})
torq_{p} = -(R2 * (c2 * f32y_{p} - s2 * f32x_{p})) - ({M2})
"""


_PARTS = ("fa32x", "fa32y", "fb34x", "fb34y", "foax", "foay", "fobx", "foby")


def _gravity_code(zero):
    lines = [f"gfx{k} = W{k} / GW * GX\ngfy{k} = W{k} / GW * GY\n"
             f"gm{k} = RG{k} * (cd{k} * gfy{k} - sd{k} * gfx{k})" for k in (2, 3, 4)]
    return ("\n".join(lines) + _pins_code("g", ("gfx2", "gfy2", "gm2"), ("gfx3", "gfy3", "gm3"),
                                          ("gfx4", "gfy4", "gm4")) + "TORQ_GRAVITY = torq_g\n")


def _loads_code(zero, loads):
    """The loads step: ``loads`` a tuple of (link, {field: expression})."""
    lines = []
    per = {2: ["0.0", "0.0", "0.0"], 3: ["0.0", "0.0", "0.0"], 4: ["0.0", "0.0", "0.0"]}
    for j, (link, f) in enumerate(loads):
        c, s = {2: ("c2", "s2"), 3: ("c3", "s3"), 4: ("c4", "s4")}[link]
        lines.append(f"lpx{j} = {f['r']} * ({c} * {f['ca']} - {s} * {f['sa']})\n"
                     f"lpy{j} = {f['r']} * ({s} * {f['ca']} + {c} * {f['sa']})")
        fs = per[link]
        lines.append(f"lf{j}x = ({fs[0]}) + {f['fx']}\nlf{j}y = ({fs[1]}) + {f['fy']}\n"
                     f"lf{j}m = ({fs[2]}) + ((lpx{j} * {f['fy']} - lpy{j} * {f['fx']}) "
                     f"+ {f['torque']})")
        per[link] = [f"lf{j}x", f"lf{j}y", f"lf{j}m"]
    return "\n".join(lines) + _pins_code("l", tuple(per[2]), tuple(per[3]),
                                         tuple(per[4])) + "TORQ_LOADS = torq_l\n"


_EFFECT_PARTS = tuple(f"{n}_g" for n in _PARTS) + ("TORQ_GRAVITY",) + tuple(
    f"{n}_l" for n in _PARTS) + ("TORQ_LOADS", "torq_c")


def _effects_code(zero):
    """forces._effects: each part plus(gravity's, the loads'), the torque plus torq_c."""
    out = [f"{n}_e = {_plus(n + '_g', n + '_l', zero)}" for n in _PARTS]
    if "TORQ_GRAVITY" in zero and "TORQ_LOADS" in zero:  # plus(0.0, 0.0) is the 0.0
        t = "TORQ_GRAVITY"
        out.append("torq_e = " + ("torq_c" if "torq_c" not in zero else t))
    else:
        out.append(f"torq_e = {_plus(_plus('TORQ_GRAVITY', 'TORQ_LOADS', zero), 'torq_c', zero)}")
    return "\n".join(out)


def _sum_zero(names, zero):
    """Python floats 0.0 + 0.0 stay the plain 0.0 (so ``plus`` sees them as zero)."""
    return all(n in zero for n in names)


def _totals(zero, terms, e, out):
    """out = plus(sum of terms, e)."""
    s = " + ".join(terms)
    if _sum_zero(terms, zero):
        return f"{out} = {e if e not in zero else s}"
    return f"{out} = {_plus(s, e, zero)}"


_STEPS: list[tuple[tuple[str, ...], tuple[str, ...], tuple[tuple[str, ...], ...], Any]] = [
    (("c2", "s2"), ("ATH2",), (), "s2, c2 = _crank(ATH2)"),
    (("c3", "s3", "c4", "s4", "s34", "c34"), ("c2", "s2"), (), """
dx = R1s - R2s * c2
dy = s2 * -R2s
zl2 = dx * dx
zl2 = zl2 + dy * dy
zl = math.sqrt(zl2)
t = zl + R3s
f1 = t + R4s
f2 = t - R4s
t = zl - R3s
f3 = R4s - t
f4 = t + R4s
assembled = (f2 >= -TOL) & (f3 >= -TOL) & (f4 >= -TOL)
bad += _select(assembled, 0, 1)
f2 = _select(f2 > 0.0, f2, 0.0)
f3 = _select(f3 > 0.0, f3, 0.0)
f4 = _select(f4 > 0.0, f4, 0.0)
hh = (f1 * f2) * (f3 * f4)
h = _select(assembled, math.sqrt(hh), math.nan)
h = h * BRANCH_SIGN
p = zl2 + R3R4M
c3 = dx * p
c3 = c3 - dy * h
s3 = dy * p
s3 = s3 + dx * h
p = HALF_R3 / zl2
c3 = c3 * p
s3 = s3 * p
c4 = R3s * c3
c4 = (c4 - dx) / R4s
s4 = R3s * s3
s4 = (s4 - dy) / R4s
s34 = h * KK
c34 = (zl2 - R3R4P) * KK
"""),
    (("ATH3", "ATH4"), ("c3", "s3", "c4", "s4"), (),
     "ATH3 = _link_angle(s3, c3)\nATH4 = _link_angle(s4, c4)"),
    (("GAMMA",), ("s34", "c34"), (), "GAMMA = _gamma(s34, c34)"),
    (("TH3D", "TH4D"), ("TH2D", "c2", "s2", "c3", "s3", "c4", "s4", "s34"), (("TH2D",),), """
k = (R2 * TH2D) / s34
TH3D = (s4 * c2 - c4 * s2) * k / R3
TH4D = (s3 * c2 - c3 * s2) * k / R4
"""),
    (("cd2", "sd2"), ("c2", "s2"), (), "cd2, sd2 = ROT2"),
    (("cd3", "sd3"), ("c3", "s3"), (), "cd3, sd3 = ROT3"),
    (("cd4", "sd4"), ("c4", "s4"), (), "cd4, sd4 = ROT4"),
    (("VAX", "VAY"), ("TH2D", "c2", "s2"), (), "VAX = s2 * -(R2 * TH2D)\nVAY = c2 * (R2 * TH2D)"),
    (("VG2X", "VG2Y"), ("TH2D", "cd2", "sd2"), (),
     "VG2X = sd2 * -(RG2 * TH2D)\nVG2Y = cd2 * (RG2 * TH2D)"),
    (("VBX", "VBY"), ("TH4D", "c4", "s4"), (), "VBX = s4 * -(R4 * TH4D)\nVBY = c4 * (R4 * TH4D)"),
    (("VG4X", "VG4Y"), ("TH4D", "cd4", "sd4"), (),
     "VG4X = sd4 * -(RG4 * TH4D)\nVG4Y = cd4 * (RG4 * TH4D)"),
    (("VG3X", "VG3Y"), ("VAX", "VAY", "TH3D", "cd3", "sd3"), (),
     "VG3X = sd3 * -(RG3 * TH3D) + VAX\nVG3Y = cd3 * (RG3 * TH3D) + VAY"),
    (("th3dd_w", "th4dd_w"), ("TH2D", "TH3D", "TH4D", "c2", "s2", "c3", "s3", "c4", "s4",
                              "s34", "c34"), (("TH2D",),), """
a2 = R2 * TH2D * TH2D
a3 = TH3D * TH3D * R3
a4 = TH4D * TH4D * R4
th3dd_w = ((((c4 * c2) + s4 * s2) * a2 + a3 * c34) - a4) / (s34 * -R3)
th4dd_w = ((((c3 * c2) + s3 * s2) * -a2 + a4 * c34) - a3) / (s34 * R4)
"""),
    (("aax_w", "aay_w"), ("TH2D", "c2", "s2"), (("TH2D",),),
     "aax_w = c2 * (-R2 * TH2D * TH2D)\naay_w = s2 * (-R2 * TH2D * TH2D)"),
    (("ag2x_w", "ag2y_w"), ("TH2D", "cd2", "sd2"), (("TH2D",),),
     "ag2x_w = cd2 * (-RG2 * TH2D * TH2D)\nag2y_w = sd2 * (-RG2 * TH2D * TH2D)"),
    (("ABX", "ABY"), ("TH4D", "TH4DD", "c4", "s4"), (("TH4D", "TH4DD"),), """
rw2 = TH4D * TH4D * R4
ra = TH4DD * R4
ABX = -(rw2 * c4 + ra * s4)
ABY = ra * c4 - rw2 * s4
"""),
    (("AG4X", "AG4Y"), ("TH4D", "TH4DD", "cd4", "sd4"), (("TH4D", "TH4DD"),), """
rw2 = TH4D * TH4D * RG4
ra = TH4DD * RG4
AG4X = -(rw2 * cd4 + ra * sd4)
AG4Y = ra * cd4 - rw2 * sd4
"""),
    (("AG3X", "AG3Y"), ("AAX", "AAY", "TH3D", "TH3DD", "cd3", "sd3"),
     (("AAX", "AAY", "TH3D", "TH3DD"),), """
rw2 = TH3D * TH3D * RG3
ra = TH3DD * RG3
AG3X = -(rw2 * cd3 + ra * sd3) + AAX
AG3Y = (ra * cd3 - rw2 * sd3) + AAY
"""),
    (("TH3DD", "TH4DD"), ("th3dd_w", "th4dd_w", "th3dd_a", "th4dd_a"),
     (("th3dd_w", "th4dd_w", "th3dd_a", "th4dd_a"),),
     lambda z: (f"TH3DD = {_plus('th3dd_w', 'th3dd_a', z)}\n"
                f"TH4DD = {_plus('th4dd_w', 'th4dd_a', z)}")),
    (("AAX", "AAY"), ("aax_w", "aay_w", "aax_a", "aay_a"), (("aax_w", "aay_w", "aax_a", "aay_a"),),
     lambda z: f"AAX = {_plus('aax_w', 'aax_a', z)}\nAAY = {_plus('aay_w', 'aay_a', z)}"),
    (("AG2X", "AG2Y"), ("ag2x_w", "ag2y_w", "ag2x_a", "ag2y_a"),
     (("ag2x_w", "ag2y_w", "ag2x_a", "ag2y_a"),),
     lambda z: f"AG2X = {_plus('ag2x_w', 'ag2x_a', z)}\nAG2Y = {_plus('ag2y_w', 'ag2y_a', z)}"),
    # crank.py: the crank's angular acceleration
    (("th3dd_a", "th4dd_a"), ("TH2DD", "c2", "s2", "c3", "s3", "c4", "s4", "s34"),
     (("TH2DD",),), """
k = (R2 * 1.0) / s34
th3dd_a = (s4 * c2 - c4 * s2) * k / R3 * TH2DD
th4dd_a = (s3 * c2 - c3 * s2) * k / R4 * TH2DD
"""),
    (("aax_a", "aay_a"), ("TH2DD", "c2", "s2"), (("TH2DD",),),
     "aax_a = -s2 * (R2 * TH2DD)\naay_a = c2 * (R2 * TH2DD)"),
    (("ag2x_a", "ag2y_a"), ("TH2DD", "cd2", "sd2"), (("TH2DD",),),
     "ag2x_a = -sd2 * (RG2 * TH2DD)\nag2y_a = cd2 * (RG2 * TH2DD)"),
    (("torq_c",), ("TH2DD", "cd2", "sd2", "FG2X", "FG2Y"), (("TH2DD",),),
     "torq_c = ZI2 * TH2DD - RG2 * (cd2 * FG2Y - sd2 * FG2X)"),
    # inertia.py
    (("FG2X", "FG2Y"), ("W2", "AG2X", "AG2Y"), (("W2",), ("AG2X", "AG2Y")),
     "FG2X = AG2X * (-W2 / GW)\nFG2Y = AG2Y * (-W2 / GW)"),
    (("FG3X", "FG3Y"), ("W3", "AG3X", "AG3Y"), (("W3",), ("AG3X", "AG3Y")),
     "FG3X = AG3X * (-W3 / GW)\nFG3Y = AG3Y * (-W3 / GW)"),
    (("TI3",), ("ZI3", "TH3DD"), (("ZI3",), ("TH3DD",)), "TI3 = TH3DD * -ZI3"),
    (("FG4X", "FG4Y"), ("W4", "AG4X", "AG4Y"), (("W4",), ("AG4X", "AG4Y")),
     "FG4X = AG4X * (-W4 / GW)\nFG4Y = AG4Y * (-W4 / GW)"),
    (("TI4",), ("ZI4", "TH4DD"), (("ZI4",), ("TH4DD",)), "TI4 = TH4DD * -ZI4"),
    # forces.py
    (("FP34X", "FP34Y", "FP32X", "FP32Y", "FP21X", "FP21Y", "FP41X", "FP41Y", "TP2"),
     ("FG4X", "FG4Y", "TI4", "TEX", "cd4", "sd4", "c2", "s2", "c3", "s3", "s34"),
     (("FG4X", "FG4Y", "TI4", "TEX"),), """
f = ((((sd4 * FG4X - cd4 * FG4Y) * RG4) - TI4) - TEX) / (s34 * R4)
FP34X = f * c3
FP34Y = f * s3
FP32X = -FP34X
FP32Y = -FP34Y
FP21X = FP32X
FP21Y = FP32Y
FP41X = FG4X + FP34X
FP41Y = FG4Y + FP34Y
TP2 = (s3 * c2 - c3 * s2) * f * R2
"""),
    (("FPP34X", "FPP34Y", "FPP32X", "FPP32Y", "FPP21X", "FPP21Y", "FPP41X", "FPP41Y", "TPP2"),
     ("FG3X", "FG3Y", "TI3", "cd3", "sd3", "c2", "s2", "c4", "s4", "s34"),
     (("FG3X", "FG3Y", "TI3"),), """
g = (((sd3 * FG3X - cd3 * FG3Y) * RG3) - TI3) / (s34 * -R3)
fpp43x = g * c4
fpp43y = g * s4
FPP34X = -fpp43x
FPP34Y = -fpp43y
FPP32X = fpp43x + FG3X
FPP32Y = fpp43y + FG3Y
FPP21X = FPP32X
FPP21Y = FPP32Y
FPP41X = FPP34X
FPP41Y = FPP34Y
TPP2 = (s2 * FPP32X - c2 * FPP32Y) * R2
"""),
    (("F3P21X", "F3P21Y"), ("FG2X", "FG2Y"), (("FG2X", "FG2Y"),),
     "F3P21X = FG2X\nF3P21Y = FG2Y"),
    (tuple(f"{n}_g" for n in _PARTS) + ("TORQ_GRAVITY",),
     ("GX", "GY", "W2", "W3", "W4", "cd2", "sd2", "cd3", "sd3", "cd4", "sd4", "c2", "s2",
      "c3", "s3", "c4", "s4", "s34"), (("GX", "GY"),),
     _gravity_code),
    (tuple(f"{n}_l" for n in _PARTS) + ("TORQ_LOADS",),
     ("NLOADS", "c2", "s2", "c3", "s3", "c4", "s4", "s34"), (("NLOADS",),), "LOADS"),
    (tuple(f"{n}_e" for n in _PARTS) + ("torq_e",), _EFFECT_PARTS, (_EFFECT_PARTS,),
     _effects_code),
    (("FA32X", "FA32Y"), ("FP32X", "FP32Y", "FPP32X", "FPP32Y", "fa32x_e", "fa32y_e"), (),
     lambda z: _totals(z, ["FP32X", "FPP32X"], "fa32x_e", "FA32X") + "\n"
     + _totals(z, ["FP32Y", "FPP32Y"], "fa32y_e", "FA32Y")),
    (("FB34X", "FB34Y"), ("FP34X", "FP34Y", "FPP34X", "FPP34Y", "fb34x_e", "fb34y_e"), (),
     lambda z: _totals(z, ["FP34X", "FPP34X"], "fb34x_e", "FB34X") + "\n"
     + _totals(z, ["FP34Y", "FPP34Y"], "fb34y_e", "FB34Y")),
    (("TORQ",), ("TP2", "TPP2", "torq_e"), (),
     lambda z: _totals(z, ["TP2", "TPP2"], "torq_e", "TORQ")),
    (("FOAX", "FOAY"), ("FP21X", "FP21Y", "FPP21X", "FPP21Y", "F3P21X", "F3P21Y", "foax_e",
                        "foay_e"), (),
     lambda z: _totals(z, ["FP21X", "FPP21X", "F3P21X"], "foax_e", "FOAX") + "\n"
     + _totals(z, ["FP21Y", "FPP21Y", "F3P21Y"], "foay_e", "FOAY")),
    (("FOBX", "FOBY"), ("FP41X", "FP41Y", "FPP41X", "FPP41Y", "fobx_e", "foby_e"), (),
     lambda z: _totals(z, ["FP41X", "FPP41X"], "fobx_e", "FOBX") + "\n"
     + _totals(z, ["FP41Y", "FPP41Y"], "foby_e", "FOBY")),
    (("TORQ_TEX",), ("TEX", "c2", "s2", "c3", "s3", "c4", "s4", "s34"), (("TEX",),),
     _pins_code("t", ("0.0", "0.0", "0.0"), ("0.0", "0.0", "0.0"), ("0.0", "0.0", "TEX"))
     + "TORQ_TEX = torq_t\n"),
    (("TORQ_INERTIA",), ("TORQ", "TORQ_GRAVITY", "TORQ_LOADS", "TORQ_TEX"), (),
     "TORQ_INERTIA = TORQ - TORQ_GRAVITY - TORQ_LOADS - TORQ_TEX"),
    (("SHAKX", "SHAKY"), ("FOAX", "FOAY", "FOBX", "FOBY"), (),
     "SHAKX = FOAX + FOBX\nSHAKY = FOAY + FOBY"),
    (("SHAKM",), ("FOBY", "TORQ"), (), "SHAKM = FOBY * R1 - TORQ"),
]

#: Vectors reported as magnitude NAME and direction DNAME (outputs.VECTORS).
_VECTORS = ("VG2", "VA", "VG3", "VB", "VG4", "AG2", "AA", "AG3", "AB", "AG4",
            "FA32", "FB34", "FOA", "FOB", "SHAK")
#: outputs.ROTATING: name -> (distance, line, its ADEL or None, angular velocity)
_ROTATING = {"VA": ("R2", "ATH2", None, "TH2D"), "VG2": ("RG2", "ATH2", "ADEL2", "TH2D"),
             "VB": ("R4", "ATH4", None, "TH4D"), "VG4": ("RG4", "ATH4", "ADEL4", "TH4D")}
for _v in _VECTORS:
    if _v in _ROTATING:
        _r, _line, _adel, _w = _ROTATING[_v]
        _STEPS.append(((_v,), (_w,), (), f"{_v} = abs({_r} * {_w})"))
        _STEPS.append((("D" + _v,), (_line, _w), (),
                       f"D{_v} = _rot_direction({_r} * {_w}, {_line} + {_adel or '0.0'})"))
    else:
        _STEPS.append(((_v,), (_v + "X", _v + "Y"), (), f"{_v} = _magnitude({_v}X, {_v}Y)"))
        _STEPS.append((("D" + _v,), (_v + "X", _v + "Y"), (),
                       f"D{_v} = _direction({_v}X, {_v}Y)"))

_PROVIDER = {name: st for st in _STEPS for name in st[0]}

#: With TH2DD a constant, the crank's accelerations turn with it: AA = R2 e^{i ATH2}
#: (-TH2D^2 + i TH2DD), and AG2 the same from RG2 and ATH2 + ADEL2, so their magnitudes
#: are R2 K and |RG2| K (K = |TH2D^2 - i TH2DD|, per call) and their directions ATH2 plus a
#: constant PHI (issue 25's rotating-vector shortcut: no atan2 or sqrt per position).
#: NaN where ATH2 is not finite, as the components would be, but where the steps are
#: skipped (K = 0: the plain 0.0).
_ACC2_SHORTCUT = {
    "AA": (("AA",), ("ATH2",), (), "AA = R2 * K_ACC2 + _select(K_ACC2 == 0.0, 0.0, ATH2 - ATH2)"),
    "AG2": (("AG2",), ("ATH2",), (),
            "AG2 = abs(RG2) * K_ACC2 + _select(K_ACC2 == 0.0, 0.0, ATH2 - ATH2)"),
    "DAA": (("DAA",), ("ATH2",), (),
            "DAA = _turned(R2 * K_ACC2, K_ACC2, ATH2, PHI_AA)"),
    "DAG2": (("DAG2",), ("ATH2",), (),
             "DAG2 = _turned(abs(RG2) * K_ACC2, K_ACC2, ATH2, PHI_AG2)"),
}

#: Where the plan computes ATH3 and ATH4 anyway: GAMMA is the angle between them (the
#: numpy engine takes atan2(|s34|, c34); the two differ by the angles' roundoff, some
#: 1e-13 degrees at most, against a bound of ERROR_BOUND 360 degrees).
_GAMMA_SHORTCUT = {"GAMMA": (("GAMMA",), ("ATH3", "ATH4"), (), "GAMMA = _between(ATH3, ATH4)")}

#: Where the plan computes ATH4 anyway and wants both DAB and DAG4: AB = R4 e^{i ATH4}
#: (-TH4D^2 + i TH4DD) and AG4 the same from RG4 and ATH4 + ADEL4, so both directions are
#: ATH4 plus one angle PHI4 per position, the direction of (-TH4D^2, TH4DD): one atan2
#: for the two (issue 25's "three directions from ATH2 or ATH4"), and their magnitudes
#: R4 K4 and |RG4| K4, K4 = |-TH4D^2 + i TH4DD|: one sqrt for the two.  The zero
#: vector's direction is 0 (NaN where an ingredient is not finite), as the numpy
#: engine's.
_ACC4_SHORTCUT = {
    "phi4": (("phi4", "w4", "nz4", "k4"), ("TH4D", "TH4DD", "c4"), (), """
w4 = TH4D * TH4D
phi4 = _direction(-w4, TH4DD)
nz4 = (w4 + TH4DD + c4) * 0.0
k4 = _magnitude(w4, TH4DD)
"""),
    "AB": (("AB",), ("phi4", "TH4D", "TH4DD"), (("TH4D", "TH4DD"),), "AB = R4 * k4"),
    "AG4": (("AG4",), ("phi4", "TH4D", "TH4DD"), (("TH4D", "TH4DD"),), "AG4 = abs(RG4) * k4"),
    "DAB": (("DAB",), ("ATH4", "phi4", "TH4D", "TH4DD"), (("TH4D", "TH4DD"),),
            "DAB = _acc_direction(ATH4, TURN_B, phi4, R4, w4, TH4DD, nz4)"),
    "DAG4": (("DAG4",), ("ATH4", "phi4", "TH4D", "TH4DD"), (("TH4D", "TH4DD"),),
             "DAG4 = _acc_direction(ATH4, TURN_G4, phi4, RG4, w4, TH4DD, nz4)"),
}

#: Inputs seeded per call (a scalar parameter, or a per-position array).
_SEEDS = ("ATH2", "TH2D", "W2", "W3", "W4", "ZI3", "ZI4", "TEX", "TH2DD", "GX", "GY", "NLOADS")

#: The outputs a kernel can write (the numpy engine's OUTPUTS but ASSEMBLED).
SUPPORTED = tuple(sorted({n for st in _STEPS for n in st[0] if n[0].isupper()}
                        | {"ATH2", "TEX", "TH2DD"}))


def _plan(wanted: tuple[str, ...], zero_seeds: frozenset[str], shortcut: bool = False):
    """The steps ``wanted`` needs, in order, each with whether it is skipped (as
    registry._plan: skipped when one of its zero groups is all known zero); with
    ``shortcut`` (TH2DD a constant), AA, AG2 and their directions by ``_ACC2_SHORTCUT``;
    where ATH3 and ATH4 are computed anyway, GAMMA by ``_GAMMA_SHORTCUT`` and, when
    both are wanted, DAB and DAG4 by ``_ACC4_SHORTCUT``."""
    first = _plan_with(wanted, zero_seeds, dict(_PROVIDER, **_ACC2_SHORTCUT) if shortcut
                       else _PROVIDER)
    done = {n for st, skipped in first if not skipped for n in st[0]}
    if "ATH4" not in done:
        return first
    provider = dict(_PROVIDER, **_ACC2_SHORTCUT) if shortcut else dict(_PROVIDER)
    provider.update(_GAMMA_SHORTCUT)
    if "DAB" in done and "DAG4" in done:
        provider.update(_ACC4_SHORTCUT)
    return _plan_with(wanted, zero_seeds, provider)


def _plan_with(wanted: tuple[str, ...], zero_seeds: frozenset[str], provider: dict):
    """_plan with the steps ``provider`` names."""
    known: dict[str, bool] = {n: n in zero_seeds for n in _SEEDS}
    order: list[tuple[Any, bool]] = []

    def visit(name: str) -> None:
        if name in known:
            return
        st = provider[name]
        skipped = any(all(known_zero(n) for n in g) for g in st[2])
        if not skipped:
            for need in st[1]:
                visit(need)
        order.append((st, skipped))
        for n in st[0]:
            known[n] = skipped

    def known_zero(name: str) -> bool:
        if name not in known:
            st = provider[name]
            return any(all(known_zero(n) for n in g) for g in st[2])
        return known[name]

    for name in wanted:
        visit(name)
    return order


_PARAMS = ("R1", "R2", "R3", "R4", "RG2", "RG3", "RG4", "W2", "W3", "W4", "ZI2", "ZI3", "ZI4",
           "ADEL2", "ADEL4", "TH2D", "GW", "GX", "GY", "R1s", "R2s", "R3s", "R4s", "TOL",
           "R3R4M", "R3R4P", "HALF_R3", "KK", "BRANCH_SIGN", "CA2", "SA2", "CA3", "SA3",
           "CA4", "SA4", "STREAM", "TURN_B", "TURN_G4")


def _source(wanted, zero_seeds, scalars, arrays, loads):
    """The kernel's Python source for one request (see ``compiled_analyze``): the
    parameters P (``_PARAMS``), the scalar effects S (``scalars``), the per-position
    inputs xin_j (``arrays``), one output o_j per wanted name."""
    order = _plan(wanted, zero_seeds, "K_ACC2" in scalars)
    zero = {n for st, skipped in order if skipped for n in st[0]} | set(zero_seeds)
    body = [f"{name} = 0.0" for name in sorted(zero_seeds)]
    for j, (_, f) in enumerate(loads):
        if f["ca"] == f"ca_{j}":  # a per-position load angle: its cos and sin here
            body.append(f"sa_{j}, ca_{j} = _sincos(L{j}_angle * RADIANS)")
    for st, skipped in order:
        if skipped:
            body += [f"{n} = 0.0" for n in st[0]]
            continue
        code = st[3]
        if code == "LOADS":
            code = _loads_code(zero, loads)
        elif callable(code):
            code = code(zero)
        for k in (2, 3, 4):  # with ADEL = 0: c 1 - s 0 = c, s 1 + c 0 = s (one kernel)
            code = code.replace(f"ROT{k}", f"(c{k} * CA{k} - s{k} * SA{k}, "
                                           f"s{k} * CA{k} + c{k} * SA{k})")
        body += [x.strip() for x in code.strip().splitlines() if x.strip()]
    body = _inline(body, _helper_asts(), [0])
    # as analysis._analyze_numpy: an output that depends on the position is NaN where the
    # loop cannot close, a skipped step's 0.0 too (when the position was solved at all)
    # (x - 0.0 is x exactly, -0.0 too, and x - NaN is NaN: one select a position and a
    # subtraction an output, on the adders, instead of a select an output)
    solved = any(st[0][0] == "c3" and not skipped for st, skipped in order)
    if solved:
        body.append("NOT_ASSEMBLED = _select(assembled, 0.0, math.nan)")
    body += [f"sc[{j}, i] = {name} - NOT_ASSEMBLED"
             if solved and name not in _SEEDS and FOURBAR.needs_assembly(name)
             else f"sc[{j}, i] = {name}" for j, name in enumerate(wanted)]
    args = ", ".join(["th", "P", "S", "sc"] + [f"xin_{j}" for j in range(len(arrays))]
                     + [f"o_{j}" for j in range(len(wanted))])
    return "\n".join([
        f"def kernel({args}):",
        *(f"    {name} = P[{j}]" for j, name in enumerate(_PARAMS)),
        *(f"    {name} = S[{j}]" for j, name in enumerate(scalars)),
        "    bad = 0",
        # unsigned bounds: no negative-index wraparound in every a[i]
        "    n = _uintp(th.shape[0])",
        f"    B = _uintp({BLOCK})",
        "    for b in range((n + B - _uintp(1)) // B):",
        "        s0 = b * B",
        "        m = _select(n - s0 < B, n - s0, B)",
        "        for i in range(m):",
        "            ATH2 = th[s0 + i]",
        *(f"            {name} = xin_{j}[s0 + i]" for j, name in enumerate(arrays)),
        *("            " + x for x in body),
        *(f"        _put(o_{j}, s0, sc, _uintp({j}), m, STREAM)" for j in range(len(wanted))),
        "    _sfence()",
        "    return bad", ""])


#: Positions per block: the kernel fills a (wanted, BLOCK) scratch table that stays in
#: the cache, then copies each row out (71 output streams at once defeat the hardware's
#: prefetch; one row at a time does not).
BLOCK = 256


#: Bytes of output from which the kernel writes it by streaming (non-temporal) stores:
#: more than a last-level cache holds, so no later read finds it cached anyway, and a
#: streaming store spares the read of each line before it is written.
STREAM_BYTES = 1 << 24


_KERNELS: dict[Any, Any] = {}
_LOCK = threading.Lock()
_LOCAL = threading.local()


def _scratch(k: int) -> np.ndarray:
    """This thread's (k, BLOCK) scratch table, made once (no allocation per call)."""
    tables = _LOCAL.__dict__.setdefault("tables", {})
    if k not in tables:
        tables[k] = np.empty((max(k, 1), BLOCK))
    return tables[k]


def available() -> bool:
    """Whether numba can be imported here."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


#: The environment variable naming where kernels are cached ("off": no cache).
KERNEL_DIR_ENV = "SIELAFF_KERNEL_DIR"


def kernel_dir() -> Path | None:
    """Where generated kernels are cached, or None for no cache (see the module's
    docstring, "The kernel cache"): ``$SIELAFF_KERNEL_DIR`` ("off" for none), else
    ``$XDG_CACHE_HOME/sielaff/kernels``, else ``~/.cache/sielaff/kernels``; None when
    that folder cannot be made or written."""
    root = os.environ.get(KERNEL_DIR_ENV, "")
    if root.strip().lower() == "off":
        return None
    if root:
        d = Path(root).expanduser()
    else:
        d = Path(os.environ.get("XDG_CACHE_HOME") or "~/.cache").expanduser() / "sielaff"
        d = d / "kernels"
    try:
        d.mkdir(parents=True, exist_ok=True)
    except (OSError, RuntimeError):  # RuntimeError: ~ with no home to expand
        return None
    return d if os.access(d, os.W_OK | os.X_OK) else None


def _module_text(source: str) -> str:
    import hashlib
    import inspect

    consts = "".join(f"{k} = {v!r}\n" for k, v in sorted(globals().items())
                     if k.startswith("_") and k[1:2].isupper() and isinstance(v, float))
    # the intrinsics' code is not in the text: its hash is, so that a changed intrinsic
    # is a new module (numba's cache does not look into what a kernel calls)
    version = hashlib.sha256(inspect.getsource(_intrinsics).encode()).hexdigest()[:16]
    return ("# generated by sielaff.engine.compiled (see there); do not edit\n"
            f"# intrinsics {version}\n"
            "import math\n\nimport numba\nimport numpy as np\n\n"
            "from sielaff.engine.compiled import _intrinsics\n\n"
            "_select, _floor, _address, _stream4, _sfence, _fma = _intrinsics()\n"
            "_uintp = numba.uintp\n"
            f"DEGREES = {DEGREES!r}\nRADIANS = {RADIANS!r}\n{consts}\n\n"
            "@numba.njit(error_model='numpy', nogil=True, cache=CACHE)\n"
            + inspect.getsource(_put) + "\n\n"
            "@numba.njit(error_model='numpy', nogil=True, cache=CACHE)\n" + source)


def _cached_module(d: Path, name: str, text: str) -> Any:
    """The kernel's module, written to ``d / name.py`` once (atomically: a temporary file
    renamed) and imported from there, so that numba's cache (``d/__pycache__``) keeps
    its machine code; OSError if ``d`` cannot be written or read."""
    import importlib.util

    path = d / f"{name}.py"
    if not path.exists():
        tmp = d / f".{name}.{os.getpid()}.{threading.get_ident()}.tmp"
        try:
            tmp.write_text(text.replace("cache=CACHE", "cache=True"))
            os.replace(tmp, path)
        finally:
            tmp.unlink(missing_ok=True)
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise OSError(f"cannot import {path}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # numba's cache finds the kernel's globals by name
    try:
        spec.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(name, None)
        raise
    return module


def _compile(source: str, n_inputs: int, n_outputs: int):
    """The kernel of ``source`` compiled, LLVM's limit on runtime alias checks raised
    (``-vectorize-memory-check-threshold``) only while it compiles.  The source goes
    to a file named by its hash, so numba's cache keeps the machine code between
    processes (a kernel takes tens of seconds to compile)."""
    import hashlib

    import llvmlite.binding as llvm
    import numba

    text = _module_text(source)
    name = "sielaff_kernel_" + hashlib.sha256(text.encode()).hexdigest()[:20]
    kernel = None
    d = kernel_dir()
    if d is not None:
        try:
            kernel = _cached_module(d, name, text).kernel
        except OSError:  # a cache that cannot be written or read: compile in memory
            kernel = None
    if kernel is None:
        ns: dict[str, Any] = {}
        exec(compile(text.replace("cache=CACHE", "cache=False"), name, "exec"), ns)  # noqa: S102
        kernel = ns["kernel"]
    arr = numba.types.Array(numba.types.float64, 1, "C")
    # inputs typed read-only: a writeable array converts to it, and a read-only one (a
    # broadcast view) then finds this vectorised kernel instead of compiling a new one
    ro = numba.types.Array(numba.types.float64, 1, "C", readonly=True)
    table = numba.types.Array(numba.types.float64, 2, "C")
    with _LLVM_OPTION:
        llvm.set_option("", "-vectorize-memory-check-threshold=100000")
        try:
            kernel.compile(numba.types.int64(ro, ro, ro, table, *([ro] * n_inputs),
                                             *([arr] * n_outputs)))
        finally:
            llvm.set_option("", "-vectorize-memory-check-threshold=128")  # LLVM's default
    kernel.disable_compile()  # no other signature: never a slow, unvectorised twin
    return kernel


_LLVM_OPTION = threading.Lock()


def _mechanism_params(p: dict[str, float], gx: float, gy: float, branch: float) -> np.ndarray:
    R = [float(p[n]) for n in ("R1", "R2", "R3", "R4")]
    big, small = max(R), min(R)
    scale = 1.0
    if not (1e-70 < small and big < 1e70):  # positions._length_scale
        scale = float(np.exp2(-np.round(np.log2(R[0] + R[1] + R[2] + R[3]))))
    R1s, R2s, R3s, R4s = (r * scale for r in R)
    rot = []
    for k in (2, 3, 4):
        d = np.radians(float(p[f"ADEL{k}"]))
        rot += [float(np.cos(d)), float(np.sin(d))]
    vals = dict(p)
    vals.update(GX=gx, GY=gy, R1s=R1s, R2s=R2s, R3s=R3s, R4s=R4s,
                TOL=ASSEMBLY_TOL_EPS * EPS * (R1s + R2s + R3s + R4s),
                R3R4M=R3s * R3s - R4s * R4s, R3R4P=R3s * R3s + R4s * R4s,
                HALF_R3=0.5 / R3s, KK=-0.5 / (R3s * R4s), BRANCH_SIGN=1.0 if branch == 1.0
                else -1.0, CA2=rot[0], SA2=rot[1], CA3=rot[2], SA3=rot[3], CA4=rot[4],
                SA4=rot[5], STREAM=0.0, TURN_B=180.0 if float(p["R4"]) < 0.0 else 0.0,
                TURN_G4=float(np.mod(float(np.mod(float(p["ADEL4"]), 360.0))
                                     + (180.0 if float(p["RG4"]) < 0.0 else 0.0), 360.0)))
    return np.array([float(vals[n]) for n in _PARAMS])


def _per_position(name: str, v: Any, n: int):
    """A float, or a contiguous float64 array of n: ValueError otherwise."""
    if callable(v):
        raise ValueError(f"backend='numba' takes {name} as a constant or an array of the "
                         "crank angles' length, not a function")
    if np.ndim(v) == 0:
        return float(v)
    a = np.ascontiguousarray(v, dtype=float)
    if a.shape != (n,):
        raise ValueError(f"backend='numba': {name} has shape {np.shape(v)}, not the crank "
                         f"angles' ({n},)")
    return a


def _streams(n: int, outs: list[np.ndarray]) -> bool:
    """Whether the kernel writes ``outs`` (n positions each) by streaming stores: when
    they are larger than a cache (``STREAM_BYTES``) and each element 8-byte aligned."""
    return n * len(outs) * 8 >= STREAM_BYTES and all(o.flags.aligned for o in outs)


def compiled_analyze(p: dict[str, float], ath2: np.ndarray, *, tex: Any = 0.0,
                     th2dd: Any = 0.0, gx: float = 0.0, gy: float = 0.0, loads: Any = (),
                     branch: float = 1.0, wanted: tuple[str, ...] = (),
                     out: dict[str, np.ndarray] | None = None, threads: int = 1
                     ) -> tuple[dict[str, np.ndarray], int]:
    """The wanted outputs at crank angles ``ath2``, and how many positions cannot assemble.

    Parameters
    ----------
    p : dict
        The validated scalar mechanism fields (``Mechanism.as_dict()``, lengths [length],
        weights [lb or kg], inertias, ADEL [deg], TH2D [rad/sec]) and ``GW``, the mass
        divisor [length/sec^2, or 1].
    ath2 : numpy.ndarray
        1-D float64 crank angles [deg], any value (reduced modulo 360 per element);
        |ath2| below 2^50.
    tex : float or numpy.ndarray
        External torque on link 4 [in-lb or N m], a constant or an array of ath2's length.
    th2dd : float or numpy.ndarray
        Crank angular acceleration [rad/sec^2], a constant or an array of ath2's length.
    gx, gy : float
        Gravity in the frame's axes [length/sec^2]; 0, 0 for none.
    loads : tuple
        ``(link, r, angle, fx, fy, torque)`` per load (engine/loads.py): link 2, 3 or 4,
        r [length], angle [deg] from the link's line, fx, fy [force], torque [torque];
        each a constant or an array of ath2's length.
    branch : float
        +1 the open branch, -1 the crossed one.
    wanted : tuple of str
        Output names, each in :data:`SUPPORTED`.
    out : dict, optional
        ``{name: array}`` to write into (1-D contiguous writeable float64 of ath2's
        length, one per wanted name); missing names get fresh arrays.
    threads : int
        Threads to split the positions over (the kernel releases the GIL); 1 by default.

    Returns
    -------
    (dict, int)
        ``{name: array}`` for the wanted names, and the number of positions where the
        loop cannot close (their results NaN).
    """
    th = np.ascontiguousarray(ath2, dtype=float)
    if th.ndim != 1:
        raise ValueError(f"backend='numba' takes 1-D crank angles, not shape {th.shape}")
    n = th.shape[0]
    wanted = tuple(dict.fromkeys(wanted))
    unknown = [w for w in wanted if w not in SUPPORTED]
    if unknown:
        raise ValueError(f"backend='numba' does not give {', '.join(unknown)}")
    for name, v in p.items():
        if np.ndim(v):
            raise ValueError(f"backend='numba' analyses one design: {name} is an array")
    if branch not in (1.0, -1.0):
        raise ValueError(f"branch = {branch!r}: +1 (open) or -1 (crossed)")
    if n:
        lo, hi = float(np.min(th)), float(np.max(th))  # NaN passes: it stays NaN
        if abs(lo) >= _BIG_ANGLE and lo == lo and abs(lo) != math.inf or (
                abs(hi) >= _BIG_ANGLE and hi == hi and abs(hi) != math.inf):
            raise ValueError("backend='numba' takes crank angles below 2^50 degrees")
    gx, gy = float(gx), float(gy)
    arrays: list[str] = []
    xs: list[np.ndarray] = []
    vals: dict[str, float] = {}

    def seed(name, v):
        v = _per_position(name, v, n)
        if isinstance(v, np.ndarray):
            arrays.append(name)
            xs.append(v)
            return name, not np.any(v)
        vals[name] = v
        return name, v == 0.0

    zero = {name for name, z in (seed("TEX", tex), seed("TH2DD", th2dd)) if z}
    load_code = []
    for j, load in enumerate(tuple(loads)):
        link, fields = load[0], load[1:]
        if link not in (2, 3, 4) or len(fields) != 5:
            raise ValueError(f"loads[{j}]: (link 2, 3 or 4, r, angle, fx, fy, torque)")
        f: dict[str, str] = {}
        for fname, v in zip(("r", "angle", "fx", "fy", "torque"), fields, strict=True):
            key = f"L{j}_{fname}"
            v = _per_position(f"loads[{j}].{fname}", v, n)
            if fname == "angle":
                if isinstance(v, np.ndarray):
                    if v.size and not (abs(float(np.min(v))) < 1e7
                                       and abs(float(np.max(v))) < 1e7):
                        raise ValueError(f"backend='numba': loads[{j}].angle beyond "
                                         "1E7 degrees")
                    arrays.append(key)
                    xs.append(v)
                    f["ca"], f["sa"] = f"ca_{j}", f"sa_{j}"
                    continue
                d = np.radians(v)  # as loads._loads does it, in numpy
                vals[f"{key}_ca"], vals[f"{key}_sa"] = float(np.cos(d)), float(np.sin(d))
                f["ca"], f["sa"] = f"{key}_ca", f"{key}_sa"
                continue
            if isinstance(v, np.ndarray):
                arrays.append(key)
                xs.append(v)
            else:
                vals[key] = v
            f[fname] = key
        load_code.append((link, f))
    if "TH2DD" in vals:  # a constant: AA and AG2 turn with the crank (_ACC2_SHORTCUT)
        w2, acc = float(p["TH2D"]) * float(p["TH2D"]), vals["TH2DD"]
        vals["K_ACC2"] = math.sqrt(w2 * w2 + acc * acc)
        phi = math.degrees(math.atan2(acc, -w2))
        vals["PHI_AA"] = float(np.mod(phi, 360.0))
        turn = 180.0 if float(p["RG2"]) < 0.0 else 0.0  # r e^{i a} = |r| e^{i (a + 180)}
        vals["PHI_AG2"] = float(np.mod(float(np.mod(float(p["ADEL2"]), 360.0)) + phi + turn,
                                       360.0))
    for name in ("TH2D", "W2", "W3", "W4", "ZI3", "ZI4"):
        if float(p[name]) == 0.0:
            zero.add(name)
    if gx == 0.0 and gy == 0.0:
        zero |= {"GX", "GY"}
    if not load_code:
        zero.add("NLOADS")
    scalars = tuple(sorted(vals))
    cache_key = (wanted, frozenset(zero), tuple(arrays), scalars,
                 tuple((link, tuple(sorted(f.items()))) for link, f in load_code))
    with _LOCK:
        kernel = _KERNELS.get(cache_key)
        if kernel is None and not available():
            raise ImportError("backend='numba' needs numba, the fast extra: pip install "
                              "\"sielaff[fast]\" (or use backend='numpy')")
        if kernel is None:
            src = _source(wanted, frozenset(zero), scalars, arrays, load_code)
            kernel = _KERNELS[cache_key] = _compile(src, len(arrays), len(wanted))
    P = _mechanism_params(p, gx, gy, branch)
    S = np.array([vals[s] for s in scalars], dtype=float)
    result: dict[str, np.ndarray] = {}
    out = {} if out is None else out
    for name in wanted:
        a = out.get(name)
        if a is None:
            a = np.empty(n)
        elif not (isinstance(a, np.ndarray) and a.dtype == np.float64 and a.shape == (n,)
                  and a.flags.c_contiguous and a.flags.writeable):
            raise ValueError(f"out[{name!r}]: a contiguous writeable float64 array of "
                             f"shape ({n},)")
        result[name] = a
    if not isinstance(threads, int) or threads < 1:
        raise ValueError(f"threads = {threads!r}: 1 or more")
    outs = list(result.values())
    P[_PARAMS.index("STREAM")] = float(_streams(n, outs))
    if threads == 1 or n < 2 * BLOCK * threads:
        bad = kernel(th, P, S, _scratch(len(wanted)), *xs, *outs) if n else 0
        return result, int(bad)
    from concurrent.futures import ThreadPoolExecutor

    cuts = [n * k // threads // BLOCK * BLOCK for k in range(threads)] + [n]

    def part(k: int) -> int:
        i, j = cuts[k], cuts[k + 1]
        return int(kernel(th[i:j], P, S, _scratch(len(wanted)), *(x[i:j] for x in xs),
                          *(o[i:j] for o in outs)))

    with ThreadPoolExecutor(threads) as pool:
        return result, sum(pool.map(part, range(threads)))
