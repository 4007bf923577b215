"""The optional compiled backend (``analyze(..., backend="numba")``, ``sielaff[fast]``).

In:  a checked request (:class:`sielaff.engine.analysis.Request`): one design (scalar
     fields), crank angles of any shape (|ATH2| below 2^50 degrees), its Scene (every
     value a constant or an array of the crank angles' shape), the wanted names; and,
     optionally, the arrays to write into.
Out: the wanted outputs, in the units ``analyze`` gives, written straight into the arrays
     returned (the caller's with ``out=``, else fresh ones, the rows of one block aligned
     to a huge page: no table, no copy), and how many positions cannot assemble.  A large
     block of fresh results is kept when the caller drops them all, for the next call's
     (``KEEP_BYTES``, :func:`release`).

A large request (``kernel.STREAM_FROM`` values or more, on x86-64) whose plan runs in one
loop takes the streamed kernel: its stores go around the caches as whole vectors, which
must start on their own size's boundary.  :func:`_streamed` keeps that promise: the
positions from every output's 64-byte boundary in runs of a multiple of ``RUN`` (so that
the vector loop's scalar remainder, whose stores would break it, never runs), the head
before that boundary and the tail through aligned scratch rows, copied back.  Outputs on
different offsets from a cache line, arrays that overlap, or (on a CPU whose vectors are
narrower than a cache line) many outputs on one offset from a 4 KiB page take the plain
kernel.  The bits are the plain kernel's (tests/test_compiled_streaming.py).

What is compiled is the model's own plan: the steps the numpy engine would run for
this request, each step's own code compiled for one position
(:mod:`sielaff.engine.kernel`).  There is no second list of steps, seeds or effects: an
effect or a model whose steps have a one-position form is compiled, one whose steps have
none is refused in one line naming it.  The package works without numba: importing this
module does not import numba, and ``backend="numba"`` without it is an ImportError in
one line naming the ``fast`` extra.

Error bound
    The kernel runs the numpy engine's own arithmetic in the same order; it differs only
    in sin, cos and atan2 (branch-free, within 1 and 2 ulp of the correctly rounded value:
    tests/test_compiled_transcendentals.py), hypot (sqrt(x^2 + y^2), within an ulp or two)
    and in mod 360 of crank angles (exact in both).  Both engines are within the bound
    derived from the conditioning in :mod:`sielaff.engine.accuracy` (the transmission
    angle, the link ratios) of the exact answer (tests/test_error_bound.py, against 40
    digits), and so within twice that of each other (tests/test_compiled.py).  NaN and
    infinities where the numpy engine has them, but at a toggle to within roundoff.

The other kinds (slider-crank, inverted slider-crank, the six-bars, any Linkage) compile
as the four-bar does: their steps are the functions :mod:`sielaff.engine.unroll` wrote
from the linkage's steps, which the numpy engine runs too, and the joints' linear solve
is LAPACK's there and Gaussian elimination with partial pivoting for one position here
(:func:`sielaff.engine.kernel_math._linear_one`; both backward stable).  Their bound is
the four-bar's taken dyad by dyad (tests/test_compiled_kinds.py, against 40 digits).
Their pin friction (a Newton solve over the positions) has no one-position form and is
refused, naming it.

The kernels are kept per model, plan and which inputs are arrays (engine/kernel.py), in
this process and in the kernel cache's folder for later ones (engine/kernel_cache.py);
the first call of a request compiles its kernel (seconds to tens of seconds).
"""

from __future__ import annotations

import math
import os
import threading
from typing import Any

import numpy as np

from sielaff.engine.kernel_math import _BIG_ANGLE, X86

__all__ = ["available", "release", "run"]

#: Outputs the kernel does not write: masks (the count is ``not_assembled``).
NOT_GIVEN = ("ASSEMBLED",)


def available() -> bool:
    """Whether numba can be imported here."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def _effect_of(model: Any) -> dict[str, str]:
    """Each effect's steps by name: a refusal names the effect, not its step."""
    return {st.name: e.name for e in model.effects for st in e.steps} | {
        st.name + "_off": e.name for e in model.effects for st in e.steps}


def _seed_owner(req: Any, name: str) -> str:
    """The effect whose seed ``name`` is, or the model's (what a refusal names)."""
    for e in req.model.effects:
        if name in e.seed(req.scene, req.mechanism):
            return e.name
    return f"the {req.model.name} model (its input {name})"


def _records(v: Any) -> list[Any] | None:
    """A seed that is a record (a named tuple of an effect's values) or a tuple of records
    of one type, as its records; None for any other seed."""
    if isinstance(v, tuple) and hasattr(v, "_fields"):
        return [v]
    if isinstance(v, tuple) and v and all(hasattr(x, "_fields") and type(x) is type(v[0])
                                          for x in v):
        return list(v)
    return None


#: Fresh results start on a boundary of this many bytes, the size of a huge page (2 MiB
#: on x86-64 and most arm64 kernels): numpy asks Linux for huge pages for large arrays,
#: and a block aligned to them is faulted in 2 MiB at a time instead of 4 KiB.
HUGE_PAGE = 1 << 21
#: A block of fewer floats than fill 8 huge pages is not aligned (its padding, up to a
#: huge page, would be much of it).
_ALIGN_FROM = 8 * HUGE_PAGE // 8


#: The blocks of fresh results the caller has dropped are kept, idle, up to this many bytes
#: in all, and the next call that needs a block of the same size takes one (0: none
#: kept).  A block new from the operating system costs its page faults (Linux zeroes each
#: page on its first write), as much as the kernel's arithmetic (docs/performance.md);
#: one kept costs nothing more to write.  :func:`release` frees the kept ones.
KEEP_BYTES = 1 << 30
_idle: list[np.ndarray] = []
_idle_lock = threading.Lock()


def _after_fork() -> None:
    """A child forked while another thread held the lock would wait on it for ever."""
    global _idle_lock
    _idle_lock = threading.Lock()


if hasattr(os, "register_at_fork"):  # POSIX
    os.register_at_fork(after_in_child=_after_fork)


class _Lease:
    """A block lent to the caller's fresh results: numpy's base of the array their rows
    are views of, so it lives as long as the last of them, and then the block is kept."""

    __slots__ = ("raw", "__array_interface__")

    def __init__(self, raw: np.ndarray) -> None:
        self.raw = raw
        self.__array_interface__ = raw.__array_interface__

    def __del__(self) -> None:
        try:
            _keep(self.raw)
        except Exception:  # at interpreter exit the module's globals may be gone
            pass


def _keep(raw: np.ndarray) -> None:
    """Keep a dropped block, the oldest freed while the kept ones exceed KEEP_BYTES.  Runs
    wherever the last row dies, so it never waits on the lock: if another caller (or this
    thread, in the middle of taking a block) holds it, the block is freed instead."""
    if raw.nbytes > KEEP_BYTES or not _idle_lock.acquire(blocking=False):
        return
    try:
        _idle.append(raw)
        while sum(b.nbytes for b in _idle) > KEEP_BYTES:
            del _idle[0]
    finally:
        _idle_lock.release()


def _block(size: int) -> np.ndarray:
    """An array of ``size`` floats: a kept block of that size if there is one, else new."""
    with _idle_lock:
        for i, b in enumerate(_idle):
            if b.size == size:
                return _idle.pop(i)
    return np.empty(size)


def release() -> None:
    """Free the kept blocks of dropped fresh results (see KEEP_BYTES)."""
    with _idle_lock:
        _idle.clear()


def _fresh(k: int, n: int) -> list[np.ndarray]:
    """``k`` new arrays of ``n`` floats: rows of one block aligned to a huge page, each
    row starting on a 64-byte boundary (a cache line: the streamed kernel's stores).

    Writing a fresh array first costs the kernel's page faults (zeroing the pages), more
    than the kernel's arithmetic on 4 KiB pages; one aligned block halves that here
    (docs/performance.md), and a large block the caller's earlier results left (KEEP_BYTES)
    avoids it.  The rows are views: the block is freed, or kept, with the last of them.
    """
    if k == 0:
        return []
    big = k * n >= _ALIGN_FROM
    pad = HUGE_PAGE // 8 if big else 8
    row = -(-n // 8) * 8
    raw = _block(k * row + pad) if big else np.empty(k * row + pad)
    start = (-raw.ctypes.data % (HUGE_PAGE if big else 64)) // 8
    base = np.asarray(_Lease(raw)) if big else raw
    return [base[start + j * row:start + j * row + n] for j in range(k)]


#: Whether large requests take the streamed kernel (kernel.py's ``far`` form); off, the
#: chunked kernel's copy streams instead (benchmarks/engine.py measures both).
STREAMED = True
#: A streamed kernel runs over a multiple of this many positions, a multiple of any
#: step of its vector loop (at most 8 doubles a vector, 8 vectors interleaved), so that
#: its scalar remainder, whose stores would break their alignment promise, never runs.
RUN = 512


def _ranges(arrays: list[np.ndarray]) -> list[tuple[int, int]]:
    return sorted((a.ctypes.data, a.ctypes.data + a.nbytes) for a in arrays if a.size)


def _head(out: np.ndarray) -> int:
    """The positions of ``out`` before its next boundary of ``STREAM_LINE`` bytes."""
    from sielaff.engine.kernel_math import STREAM_LINE

    return (-out.ctypes.data % STREAM_LINE) // 8


#: Where a vector store is narrower than a cache line (kernel_math.line_stores), outputs
#: more than this many on one cache line's offset from a 4 KiB page take the plain kernel:
#: measured on an AVX2 machine, 71 outputs at one offset (separate np.empty arrays) cost
#: the streamed loop 0.20-0.24 s against the chunked kernel's 0.12-0.13 s, nine to an
#: offset as much as it, and fewer less (A/B scripts not kept; docs/performance.md's
#: "Compiled backend" measures the crowded and the spread case).
CROWD = 8


def stream_start(outs: list[np.ndarray], ins: list[np.ndarray]) -> int | None:
    """The positions before every output's next boundary of ``STREAM_LINE`` bytes (the
    same for all), or None where the streamed kernel cannot write them, or not well: an
    output not aligned to 8 bytes, or on another offset than the others; arrays that
    overlap (the loop's check for overlap would fall back to its scalar form, which
    breaks the promise); outputs crowded on one offset from a 4 KiB page (``CROWD``)
    where a vector store is narrower than a cache line."""
    from collections import Counter

    from sielaff.engine.kernel_math import STREAM_LINE, line_stores

    offs = {o.ctypes.data % STREAM_LINE for o in outs}
    if len(offs) != 1 or outs[0].ctypes.data % 8:
        return None
    spans = _ranges(list(outs) + list(ins))
    if any(a[1] > b[0] for a, b in zip(spans, spans[1:])):
        return None
    crowd = Counter(o.ctypes.data % 4096 // STREAM_LINE for o in outs).most_common(1)
    if crowd[0][1] > CROWD and not line_stores():
        return None
    return _head(outs[0])


def _streamed(kernel: Any, n: int, head: int, values: list[float],
              ins: list[np.ndarray], outs: list[np.ndarray]) -> int:
    """The streamed kernel over ``n`` positions (kernel.py's ``far`` form), its promise
    kept: the positions from ``head`` (every output on its boundary there) in one run of
    a multiple of RUN; the rest (the head, the tail) gathered into aligned scratch rows,
    padded to RUN positions with copies of the last, and run the same way, only they
    counted.  Returns how many positions cannot assemble."""
    body = (n - head) // RUN * RUN if n > head else 0
    bad = 0
    if body:
        bad += kernel(body, body, *values, *(x[head:head + body] for x in ins),
                      *(o[head:head + body] for o in outs))
    edge = np.r_[0:min(head, n), head + body:n]
    if edge.size:
        m = -(-edge.size // RUN) * RUN
        take = np.concatenate([edge, np.full(m - edge.size, edge[-1])])
        rows = _fresh(len(outs), m)
        bad += kernel(m, edge.size, *values, *(x[take] for x in ins), *rows)
        for o, r in zip(outs, rows, strict=True):
            o[edge] = r[:edge.size]
    return int(bad)


def run(req: Any, out: dict[str, np.ndarray] | None = None, threads: int = 1
        ) -> tuple[dict[str, np.ndarray], int | None, tuple[int, ...]]:
    """The request's outputs by the compiled kernel: ``({name: array}, not assembled,
    shape)``; ``out`` (flat or of the crank angles' shape) written in place."""
    from sielaff.engine.kernel import Uncompilable, counts_assembly, kernel_for, streamed

    model = req.model
    missing = [n for n in req.wanted if n in NOT_GIVEN]
    if missing:
        raise ValueError(f"backend='numba' does not give {', '.join(missing)} (a mask; the "
                         "count is not_assembled): use backend='numpy'")
    for name, v in req.mechanism.as_dict().items():
        if np.ndim(v):
            raise ValueError(f"backend='numba' analyses one design: {name} is an array")
    if not isinstance(threads, int) or isinstance(threads, bool) or threads < 1:
        raise ValueError(f"threads = {threads!r}: 1 or more")
    th = np.asarray(req.ath2, dtype=float)
    shape = th.shape if out is not None or req.shape is None else req.shape
    n = math.prod(shape)
    flat_th = np.ascontiguousarray(np.broadcast_to(th, shape).reshape(-1))
    if n:
        lo, hi = float(np.nanmin(flat_th, initial=0.0)), float(np.nanmax(flat_th, initial=0.0))
        if max(abs(lo), abs(hi)) >= _BIG_ANGLE and math.isfinite(max(abs(lo), abs(hi))):
            raise ValueError("backend='numba' takes crank angles below 2^50 degrees")
    ns = model.seed(req.mechanism, flat_th, req.scene)
    seeded = frozenset(ns)
    order = model.plan(req.wanted, seeded, model.zero_seeds(ns))
    needed = {x for st, skipped, _ in order if not skipped for x in st.needs}
    needed |= {w for w in req.wanted if w in seeded}
    scalars: list[str] = []
    arrays: list[str] = []
    values: list[Any] = []
    per_position: list[np.ndarray] = []
    structs: list[tuple[str, type, bool, tuple[tuple[str, ...], ...]]] = []

    def take(name: str, v: Any, owner: str) -> None:
        if callable(v):
            raise ValueError(f"backend='numba' takes the values of {_seed_owner(req, owner)} "
                             "as constants or arrays of the crank angles' shape, not a "
                             "function")
        if isinstance(v, float | int) or (isinstance(v, np.ndarray) and v.ndim == 0):
            scalars.append(name)
            values.append(float(v))
        elif isinstance(v, np.ndarray) and v.dtype.kind in "fiu":
            a = v if v.shape == (n,) else np.broadcast_to(v, shape).reshape(-1)
            arrays.append(name)
            per_position.append(np.ascontiguousarray(a, dtype=float))
        else:
            raise ValueError(f"backend='numba' has no compiled form of "
                             f"{_seed_owner(req, owner)}: use backend='numpy'")

    for name in sorted(needed & seeded):
        v = ns[name]
        items = _records(v)
        if items is None:
            take(name, v, name)
            continue
        leaves = []
        structure = getattr(type(items[0]), "STRUCTURE", ())
        for i, item in enumerate(items):
            names = []
            for f, x in zip(item._fields, item, strict=True):
                if f in structure:  # which link: compiled in as a constant
                    names.append(f"={float(x)!r}")
                    continue
                names.append(f"{name}__{i}__{f}")
                take(names[-1], x, name)
            leaves.append(tuple(names))
        structs.append((name, type(items[0]), not isinstance(v, list | tuple) or
                        hasattr(v, "_fields"), tuple(leaves)))
    from sielaff.engine import kernel as _k

    split = threads > 1 and n >= 4096 * threads  # else one thread does it all
    far = STREAMED and X86 and (n // (threads if split else 1) * len(req.wanted)
                                >= _k.STREAM_FROM)
    try:
        kernel = kernel_for(model, order, req.wanted, tuple(scalars), tuple(arrays),
                            _effect_of(model), tuple(structs), far)
    except ImportError:
        raise ImportError("backend='numba' needs numba, the fast extra: pip install "
                          "\"sielaff[fast]\" (or use backend='numpy')") from None
    except Uncompilable as e:
        raise ValueError(str(e)) from None
    given = {} if out is None else {k: a for k, a in out.items() if a is not None}
    fresh = iter(_fresh(sum(name not in given for name in req.wanted), n))
    result: dict[str, np.ndarray] = {}
    for name in req.wanted:
        result[name] = given[name].reshape(-1) if name in given else next(fresh)
    outs = list(result.values())
    counts = counts_assembly(model, order)
    call: Any = kernel
    if streamed(kernel):
        head = stream_start(outs, per_position)
        if head is None:  # outputs the streamed loop cannot write: the plain one
            call = kernel_for(model, order, req.wanted, tuple(scalars), tuple(arrays),
                              _effect_of(model), tuple(structs))
        else:  # a thread's part starts elsewhere: its head, the same for every output
            def call(m: int, *args: Any) -> int:
                k = len(values)
                ins, os = args[k:k + len(per_position)], args[k + len(per_position):]
                return _streamed(kernel, m, _head(os[0]), list(values), list(ins), list(os))
    if not split:
        bad = call(n, *values, *per_position, *outs) if n else 0
    else:
        from concurrent.futures import ThreadPoolExecutor

        cuts = [n * k // threads for k in range(threads)] + [n]

        def part(k: int) -> int:
            i, j = cuts[k], cuts[k + 1]
            return int(call(j - i, *values, *(x[i:j] for x in per_position),
                            *(o[i:j] for o in outs)))

        with ThreadPoolExecutor(threads) as pool:
            bad = sum(pool.map(part, range(threads)))
    return result, (int(bad) if counts else None), shape
