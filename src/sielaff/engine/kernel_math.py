"""The compiled backend's arithmetic for one position: what ``np`` stands for when the
kernel generator (:mod:`sielaff.engine.kernel`) compiles a step, and the one-position
forms of :mod:`sielaff.engine.arith`'s operations.

sin, cos and atan2 are branch-free (Cody-Waite reduction and Chebyshev polynomials by
fused multiply-adds, atan2 by octant reduction), so that LLVM vectorises the loop; mod
360 is exact.  The accuracy claims are stated in :mod:`sielaff.engine.compiled`'s doc and
tested against mpmath (``tests/test_compiled_transcendentals.py``).  numba is imported
only by :func:`one_position` and :func:`_intrinsics`, on the first compiled request."""

from __future__ import annotations

import functools
import math
import platform

import numpy as np

#: Whether this CPU is x86-64: the one place that decides whether the kernels' stores
#: stream (non-temporal stores, SFENCE); elsewhere they are plain.
X86 = platform.machine().lower() in ("x86_64", "amd64")

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


def _capture(c, q, old):
    """``q`` where ``c``, else ``old``, for a row that is +0.0 until ``c`` first holds and
    holds at most once there (an iterated step's results: engine/iterate.py).  Compiled,
    ``old``'s bits or-ed with ``q``'s where ``c`` (bits exact), where a select of the
    row's own value becomes a masked store (VMASKMOVPD), some ten cycles each on an AVX2
    AMD CPU (Zen 3, a throw-away A/B: fourteen rows 11.6 ns a position so, 6.4 or-ed)."""
    return q if c else old


@functools.cache
def _intrinsics():
    """(_select, _floor, _fma) for numba: each one LLVM instruction, no call, no branch."""
    import llvmlite.ir as ir
    from numba.core import types
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

    return select, floor, fma


@functools.cache
def _capture_intrinsic():
    """``_capture`` for numba: an integer or of the bits, no select of the row's value."""
    import llvmlite.ir as ir
    from numba.core import types
    from numba.extending import intrinsic

    @intrinsic
    def capture(typingctx, c, q, old):
        if not (isinstance(q, types.Float) and isinstance(old, types.Float)):
            return None

        def codegen(context, builder, sig, args):
            i64 = ir.IntType(64)
            cond = context.cast(builder, args[0], sig.args[0], types.boolean)
            x = builder.bitcast(context.cast(builder, args[1], sig.args[1], types.float64),
                                i64)
            y = builder.bitcast(context.cast(builder, args[2], sig.args[2], types.float64),
                                i64)
            r = builder.or_(y, builder.select(cond, x, ir.Constant(i64, 0)))
            return builder.bitcast(r, ir.DoubleType())

        return types.float64(c, q, old), codegen

    return capture


def _nontemporal(store):
    """``store`` (an llvmlite store) marked non-temporal (``!nontemporal !{i32 1}``): x86
    writes it around the caches (MOVNTI, VMOVNTPD).  The one place both streaming
    intrinsics take the hint from."""
    import llvmlite.ir as ir

    one = ir.Constant(ir.IntType(32), 1)
    store.set_metadata("nontemporal", store.module.add_metadata([one]))
    return store


def _streaming():
    """(_copy_out, _fence) for the kernel's copy of a staged chunk into its outputs.

    ``_copy_out(dst, src, start, m, far)`` copies ``src[:m]`` (float64) to
    ``dst[start:start + m]``: where ``far``, with non-temporal stores (written around the
    caches, so no line of the output is read from memory before it is written, which a
    plain store does: half the memory traffic; 32 bytes a store from the destination's
    first 32-byte boundary, eight before it and after the last), else by llvm.memcpy
    (a small result stays in cache for its reader); no bounds check, no temporary (the
    kernel's rows never overlap its outputs).  ``_fence()`` (SFENCE) orders
    the non-temporal stores before whatever the kernel's caller does next, in any thread.
    The bytes are the same either way.  On a CPU other than x86-64: plain stores and no
    fence."""
    import llvmlite.ir as ir
    from numba.core import cgutils, types
    from numba.extending import intrinsic

    def _nt_copy(builder, to, at, n):
        """n doubles from ``at`` to ``to`` by non-temporal stores: MOVNTI (eight bytes, any
        alignment) up to the first 32-byte boundary of ``to``, then four doubles a store
        (VMOVNTPS, which needs that alignment), then MOVNTI for the rest; MOVNTI all the
        way for a destination not aligned to 8 bytes."""
        i64 = ir.IntType(64)
        vec = ir.VectorType(ir.DoubleType(), 4)
        addr = builder.ptrtoint(to, i64)
        aligned8 = builder.icmp_unsigned("==", builder.and_(addr, ir.Constant(i64, 7)),
                                         ir.Constant(i64, 0))
        lead = builder.lshr(builder.and_(builder.neg(addr), ir.Constant(i64, 31)),
                            ir.Constant(i64, 3))
        lead = builder.select(aligned8, lead, n)
        lead = builder.select(builder.icmp_signed("<", lead, n), lead, n)
        quads = builder.sdiv(builder.sub(n, lead), ir.Constant(i64, 4))
        body = builder.add(lead, builder.mul(quads, ir.Constant(i64, 4)))

        def scalars(first, count):
            with cgutils.for_range(builder, count) as loop:
                i = builder.add(first, loop.index)
                v = builder.load(builder.bitcast(builder.gep(at, [i]), i64.as_pointer()))
                _nontemporal(builder.store(v, builder.bitcast(builder.gep(to, [i]),
                                                              i64.as_pointer())))

        scalars(ir.Constant(i64, 0), lead)
        with cgutils.for_range(builder, quads) as loop:
            i = builder.add(lead, builder.mul(loop.index, ir.Constant(i64, 4)))
            v = builder.load(builder.bitcast(builder.gep(at, [i]), vec.as_pointer()), align=8)
            _nontemporal(builder.store(v, builder.bitcast(builder.gep(to, [i]),
                                                          vec.as_pointer()), align=32))
        scalars(body, builder.sub(n, body))

    @intrinsic
    def copy_out(typingctx, dst, src, start, m, far):
        if not all(isinstance(a, types.Array) and a.ndim == 1 and a.dtype == types.float64
                   for a in (dst, src)) or not all(isinstance(a, types.Integer)
                                                   for a in (start, m)):
            return None
        if not isinstance(far, types.Boolean):
            return None

        def codegen(context, builder, sig, args):
            d, s, c, n, f = args
            da = context.make_array(sig.args[0])(context, builder, d)
            sa = context.make_array(sig.args[1])(context, builder, s)
            c = context.cast(builder, c, sig.args[2], types.intp)
            n = context.cast(builder, n, sig.args[3], types.intp)
            to = cgutils.get_item_pointer(context, builder, sig.args[0], da, [c])
            at = cgutils.get_item_pointer(context, builder, sig.args[1], sa,
                                          [ir.Constant(n.type, 0)])
            with builder.if_else(builder.and_(f, ir.Constant(ir.IntType(1), X86))) as (
                    then, otherwise):
                with then:
                    _nt_copy(builder, to, at, n)
                with otherwise:  # plain stores: llvm.memcpy
                    cgutils.raw_memcpy(builder, to, at, n, 8, align=8)
            return context.get_dummy_value()

        return types.void(dst, src, start, m, far), codegen

    @intrinsic
    def fence(typingctx):
        def codegen(context, builder, sig, args):
            if X86:
                fn = cgutils.get_or_insert_function(
                    builder.module, ir.FunctionType(ir.VoidType(), []), "llvm.x86.sse.sfence")
                builder.call(fn, [])
            return context.get_dummy_value()

        return types.void(), codegen

    return copy_out, fence


#: The alignment, in bytes, that a streamed kernel's stores promise (kernel.py's ``far``
#: loop): a vector of four doubles; and the boundary its outputs start on (compiled.py's
#: runs): a cache line, so that each line is written whole by consecutive stores.
STREAM_ALIGN, STREAM_LINE = 32, 64


@functools.cache
def line_stores() -> bool:
    """Whether numba's vectorised loops store a whole cache line (64 bytes) at once: AVX-512
    in use, as LLVM does on AMD's CPUs that have it (znver4 on), not on Intel's (LLVM
    prefers 256-bit vectors there).  A narrower vector writes each line of a streamed
    output in parts, which many outputs on one offset from a 4 KiB page make slow
    (compiled.stream_start asks; docs/performance.md).  Asks numba's CPU, as it compiles."""
    import llvmlite.binding as llvm
    from numba.core import config

    # numba's config sets these at run time (NUMBA_CPU_NAME, NUMBA_CPU_FEATURES)
    name = getattr(config, "CPU_NAME", None) or llvm.get_host_cpu_name()
    features = getattr(config, "CPU_FEATURES", None) or llvm.get_host_cpu_features().flatten()
    return X86 and name.startswith("znver") and "+avx512f" in features.split(",")


def _streamed_store():
    """``_put(dst, i, v)``: ``dst[i] = v`` by a non-temporal store that promises LLVM
    ``STREAM_ALIGN``-byte alignment, so that the vectorised loop stores whole vectors
    around the caches (VMOVNTPD; without the promise LLVM splits a vector's non-temporal
    store into scalar ones, or does not vectorise).  The promise must hold at every store
    that runs: the caller starts each output on such a boundary and runs the loop for a
    multiple of ``compiled.RUN`` positions, a multiple of any vector step, so that the
    loop's scalar remainder never runs (compiled._streamed).  In the loop as written
    the promise is false at a position off a boundary; LLVM widens the store before
    anything could use that, and only the widened stores run (their bits and the packed
    stores in the assembly: tests/test_compiled_streaming.py).  No bounds check.  On a CPU
    other than x86-64: a plain store, no promise."""
    from numba.core import types
    from numba.extending import intrinsic

    @intrinsic
    def put(typingctx, dst, i, v):
        if not (isinstance(dst, types.Array) and dst.ndim == 1 and dst.dtype == types.float64
                and isinstance(i, types.Integer) and isinstance(v, types.Float)):
            return None

        def codegen(context, builder, sig, args):
            d, k, x = args
            da = context.make_array(sig.args[0])(context, builder, d)
            k = context.cast(builder, k, sig.args[1], types.intp)
            x = context.cast(builder, x, sig.args[2], types.float64)
            to = builder.gep(da.data, [k], inbounds=True)
            if X86:
                _nontemporal(builder.store(x, to, align=STREAM_ALIGN))
            else:
                builder.store(x, to, align=8)
            return context.get_dummy_value()

        return types.void(dst, i, v), codegen

    return put


# Python stand-ins for the intrinsics (the transcendentals run as plain Python in the tests)
def _fma(x, y, z):
    """x y + z rounded once (the kernel's ``llvm.fma``), exactly, in Python."""
    if not all(math.isfinite(v) for v in (x, y, z)):
        return x * y + z
    from fractions import Fraction

    return float(Fraction(x) * Fraction(y) + Fraction(z))


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


# --- one position's numpy: what ``np`` stands for when a step is compiled -------------
# (sielaff.engine.kernel compiles each step's own code with ``np`` bound to this
# namespace and arith's three operations to their one-position forms below).  Each takes
# and ignores numpy's ``out=``: a step always assigns what a call returns.

def _np_sin(x, out=None):
    return _sincos(x)[0]


def _np_cos(x, out=None):
    return _sincos(x)[1]


def _np_arctan2(y, x, out=None):
    return _atan2(y, x)


def _np_sqrt(x, out=None):
    return math.sqrt(x)


def _np_negative(x, out=None):
    return -x


def _np_subtract(a, b, out=None):
    return a - b


def _np_divide(a, b, out=None):
    return a / b


def _np_add(a, b, out=None, where=True):
    if out is None:  # numba prunes the branch not taken for the call's types
        return a + b
    return _select(where, a + b, out)


def _np_maximum(a, b, out=None):
    return _select((a >= b) | (a != a), a, b)  # NaN propagates, as numpy's


def _np_minimum(a, b, out=None):
    return _select((a <= b) | (a != a), a, b)  # NaN propagates, as numpy's


def _np_mod(x, y):
    return _mod360(x) if y == 360.0 else x - y * _floor(x / y)


def _np_hypot(x, y):  # within an ulp or two of libm's; no call, so the loop vectorises
    return math.sqrt(x * x + y * y)


def _np_where(c, a, b):
    return _select(c, a, b)


def _np_abs(x):
    return abs(x)


def _np_same(x, dtype=None):  # asarray, max, min of one position
    return x


def _np_ndim(x):
    return 0


def _np_size(x):
    return 1


def _np_any(x):
    return x != 0.0


def _owned(x):  # arith.owned: one position is a float, never an array to write into
    return False


def _put_one(dst, value, where):  # arith.put
    return _select(where, value, dst)


def _at_one(name, v, angles):  # values.at: the runner takes no functions
    return v


def _plus_one(a, b):  # statics.plus: a skipped step's 0.0 is the literal 0.0 here
    return a + b


# arith's positions of a per-position iteration: at one position, whether it iterates
def _shape_one(xs):  # arith.shape_of
    return 0


def _flat_one(x, shape):  # arith.flat
    return float(x)


def _filled_one(shape, value):  # arith.filled
    return float(value)


def _shaped_one(x, shape):  # arith.shaped
    return x


def _positions_one(mask):  # arith.positions: the position, if the mask holds there
    return mask


def _pick_one(x, idx):  # arith.pick
    return x


def _none_one(idx):  # arith.none
    return not idx


def _scatter_one(dst, idx, value, where):  # arith.scatter
    return _select(idx & where, value, dst)


def _batch_one(x, idx):  # arith.batch: an array of one for array code
    return np.full(1, x)


def _unbatch_one(x):  # arith.unbatch
    return x[0]


def _linear_one(rows, rhs):  # joints.linear: Gaussian elimination, partial pivoting
    n = len(rhs)
    a = np.empty((n, n + 1))
    finite = True
    for i in range(n):
        r = rows[i]
        for j in range(n):
            a[i, j] = r[j]
            finite &= math.isfinite(r[j])
        a[i, n] = rhs[i]
        finite &= math.isfinite(rhs[i])
    x = np.empty(n)
    for k in range(n):
        p = k
        big = abs(a[k, k])
        for i in range(k + 1, n):
            if abs(a[i, k]) > big:
                p, big = i, abs(a[i, k])
        if big == 0.0:  # exactly singular (a toggle): NaN, as LAPACK's refusal
            finite = False
            big = 1.0
            a[p, k] = 1.0
        if p != k:
            for j in range(k, n + 1):
                a[k, j], a[p, j] = a[p, j], a[k, j]
        inv = 1.0 / a[k, k]
        for i in range(k + 1, n):
            f = a[i, k] * inv
            if f != 0.0:
                for j in range(k + 1, n + 1):
                    a[i, j] -= f * a[k, j]
    for i in range(n - 1, -1, -1):
        t = a[i, n]
        for j in range(i + 1, n):
            t -= a[i, j] * x[j]
        x[i] = t / a[i, i]
    if not finite:
        x[:] = np.nan
    return x


#: numpy's names for one position, each the function above (the rest are numba's own)
_ONE_POSITION = {"sin": _np_sin, "cos": _np_cos, "arctan2": _np_arctan2, "sqrt": _np_sqrt,
                 "negative": _np_negative, "subtract": _np_subtract, "divide": _np_divide,
                 "add": _np_add, "maximum": _np_maximum, "minimum": _np_minimum,
                 "mod": _np_mod, "where": _np_where,
                 "abs": _np_abs, "hypot": _np_hypot, "asarray": _np_same, "max": _np_same,
                 "min": _np_same, "ndim": _np_ndim, "size": _np_size, "any": _np_any}
#: numba's own one-position forms of these numpy names
_NUMBA_OWN = ("radians", "degrees", "isnan", "isfinite", "exp2", "log2", "round", "sign",
              "nan", "inf", "pi", "float64")


def one_position():
    """(``np`` for one position, {arith or statics function: its one-position form}),
    compiled by numba (imported here, on the first compiled request)."""
    import types

    import numba

    from sielaff.engine import arith, joints, statics, values

    jit = numba.njit(error_model="numpy", nogil=True, inline="always")
    glob = dict(globals())
    sel, flo, fma = _intrinsics()
    glob.update(_select=sel, _floor=flo, _fma=fma)
    compiled = {}
    for name in ("_mod360", "_sincos", "_half_turn", "_atan2"):
        f = glob[name]
        compiled[name] = jit(types.FunctionType(f.__code__, glob, name))
        glob[name] = compiled[name]
    ns = types.ModuleType("sielaff_one_position_numpy")
    for name in _NUMBA_OWN:
        setattr(ns, name, getattr(np, name))
    for name, f in _ONE_POSITION.items():
        setattr(ns, name, jit(types.FunctionType(f.__code__, glob, f.__name__, f.__defaults__)))
    twins = {arith.owned: _owned, arith.put: _put_one, arith.mod360: _mod360,
             statics.plus: _plus_one, values.at: _at_one, arith.shape_of: _shape_one,
             arith.flat: _flat_one, arith.filled: _filled_one, arith.shaped: _shaped_one,
             arith.positions: _positions_one, arith.pick: _pick_one,
             arith.none: _none_one, arith.scatter: _scatter_one,
             arith.batch: _batch_one, arith.unbatch: _unbatch_one,
             joints.linear: _linear_one}
    forms = {k: compiled.get(f.__name__) or jit(types.FunctionType(f.__code__, glob, f.__name__))
             for k, f in twins.items()}
    return ns, forms
