"""The compiled backend's arithmetic: branch-free sin, cos and atan2 (their constants
and polynomials), numba intrinsics of one LLVM instruction each, and the helpers the
kernel generator (:mod:`sielaff.engine.compiled`) writes out inline, each for one
position.  The accuracy claims are stated in :mod:`sielaff.engine.compiled`'s doc and
tested against mpmath (``tests/test_compiled_transcendentals.py``)."""

from __future__ import annotations

import ast
import copy
import math

import numpy as np

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
