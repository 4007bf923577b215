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

The scalar steps are in :mod:`sielaff.engine.kernel_steps`, the helpers the generator
inlines and the transcendentals in :mod:`sielaff.engine.kernel_math`; this module writes
one kernel from them, compiles and caches it, and runs it.
"""

from __future__ import annotations

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
from sielaff.engine import kernel_math, kernel_steps  # noqa: E402
from sielaff.engine.fourbar import FOURBAR  # noqa: E402
from sielaff.engine.kernel_math import (  # noqa: E402
    _BIG_ANGLE,
    DEGREES,
    EPS,
    RADIANS,
    _helper_asts,
    _inline,
    _intrinsics,
    _put,
)
from sielaff.engine.kernel_steps import _PARAMS, _SEEDS, SUPPORTED, _loads_code, _plan  # noqa: E402
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

    consts = "".join(f"{k} = {v!r}\n" for k, v in sorted(vars(kernel_math).items())
                     if k.startswith("_") and k[1:2].isupper() and isinstance(v, float))
    # the intrinsics' code is not in the text: its hash is, so that a changed intrinsic
    # is a new module (numba's cache does not look into what a kernel calls)
    version = hashlib.sha256(inspect.getsource(_intrinsics).encode()).hexdigest()[:16]
    return ("# generated by sielaff.engine.compiled (see there); do not edit\n"
            f"# intrinsics {version}\n"
            "import math\n\nimport numba\nimport numpy as np\n\n"
            "from sielaff.engine.kernel_math import _intrinsics\n\n"
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


def __getattr__(name: str) -> Any:
    """The steps' and the arithmetic's names, as they were when this was one module (the
    tests and benchmarks reach the constants and helpers through ``compiled``)."""
    for module in (kernel_steps, kernel_math):
        if hasattr(module, name):
            return getattr(module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
