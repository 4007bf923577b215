"""``analyze``: seed the inputs, plan the steps the outputs need, run them, count the
positions that cannot assemble."""

from __future__ import annotations

import sys
import warnings
from collections.abc import Iterable
from typing import Any

import numpy as np

from sielaff.engine.outputs import OUTPUTS, RESULTS
from sielaff.engine.registry import STEP_CALLS, STEPS, _plan
from sielaff.mechanism import (
    EXAMPLE,
    FIELD_NAMES,
    MASS_DIVISOR,
    STANDARD_GRAVITY,
    Mechanism,
    validate,
)

__all__ = ["AssemblyWarning", "Results", "analyze", "plan"]


#: Inputs whose being zero can make steps unnecessary (see ``zero_when``).
#: Every name a step's zero_when uses: when one is an input (seeded) and zero, the steps
#: that need it alone are skipped.
_ZERO_CANDIDATES = frozenset(n for s in STEPS for n in s.zero_when) | {"TEX"}


def _zero_seeds(ns: dict[str, Any]) -> frozenset[str]:
    """The seeded inputs that are identically zero (a massless link, no TEX)."""
    return frozenset(n for n in _ZERO_CANDIDATES if n in ns and not np.any(ns[n]))


class AssemblyWarning(UserWarning):
    """Some positions of an ``analyze`` call cannot assemble: their results are NaN."""


def _warn_not_assembled(count: int, total: int, stacklevel: int, mask: bool = True) -> None:
    """The AssemblyWarning: how many of ``total`` positions cannot assemble."""
    warnings.warn(f"{count} of {total} positions cannot assemble (the loop does not close "
                  "there): their results are NaN"
                  + ("; ask for the ASSEMBLED output for the mask" if mask else ""),
                  AssemblyWarning, stacklevel=stacklevel)


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


def _seed(mechanism: Mechanism, ath2: Any, tex: Any, th2dd: Any = 0.0, gravity: Any = None,
          loads: Any = (), branch: str = "open") -> dict[str, Any]:
    ns: dict[str, Any] = {}
    if branch not in ("open", "crossed"):
        raise ValueError(f"branch = {branch!r}: 'open' (the 1966 program's) or 'crossed'")
    ns["BRANCH"] = 1.0 if branch == "open" else -1.0
    for name in FIELD_NAMES:
        v = np.asarray(getattr(mechanism, name), dtype=float)
        ns[name] = float(v) if v.ndim == 0 else v
    ns["ATH2"] = np.atleast_1d(np.asarray(ath2, dtype=float))  # ufuncs keep arrays
    for name, value in (("TEX", tex), ("TH2DD", th2dd)):
        if callable(value):
            ns[name.lower() + "_fn"] = value
        else:
            v = np.asarray(value, dtype=float)
            ns[name] = float(v) if v.ndim == 0 else v
    ns["GW"] = MASS_DIVISOR[mechanism.units]
    if gravity is None:
        ns["GX"] = ns["GY"] = 0.0
    elif isinstance(gravity, str) and gravity == "down":
        ns["GX"], ns["GY"] = 0.0, -STANDARD_GRAVITY[mechanism.units]
    else:
        try:
            gx, gy = (float(g) for g in gravity)
        except (TypeError, ValueError):
            raise ValueError(f"gravity = {gravity!r}: give None, 'down', or the vector "
                             "(gx, gy) in the mechanism's length unit per sec^2") from None
        ns["GX"], ns["GY"] = gx, gy
    from sielaff.engine.loads import Load

    loads = tuple(loads)
    for load in loads:
        if not isinstance(load, Load):
            raise ValueError(f"loads: {load!r} is not a sielaff.Load")
    ns["loads"], ns["NLOADS"] = loads, float(len(loads))
    return ns


def plan(outputs: Iterable[str] | str | None = None, mechanism: Mechanism | None = None,
         tex: Any = 0.0, *, th2dd: Any = 0.0, gravity: Any = None, loads: Any = (),
         branch: str = "open") -> list[str]:
    """Names of the steps ``analyze`` would run (skipped zero steps marked ``name=0``)."""
    ns = _seed(EXAMPLE if mechanism is None else mechanism, 0.0, tex, th2dd, gravity, loads,
               branch)
    order = _plan(_check_outputs(outputs), frozenset(ns), _zero_seeds(ns))
    return [st.name + ("=0" if skipped else "") for st, skipped, _ in order]


def _run(order, ns: dict[str, Any]) -> int | None:
    """Run the planned steps in ``ns``; the number of positions that cannot assemble
    (None if no position was solved)."""
    not_assembled = None
    for st, skipped, drop in order:
        if skipped:
            for name in st.provides:
                ns[name] = 0.0
        else:
            # looked up late, in the step's own module, so tests can patch it there
            fn = getattr(sys.modules[st.fn.__module__], st.name, st.fn)
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
            tex: Any = 0.0, *, th2dd: Any = 0.0, gravity: Any = None,
            loads: Any = (), branch: str = "open", out: dict | None = None,
            block: int | None = None, backend: str = "numpy") -> Results:
    """Analyse ``mechanism`` at crank angles ``ath2`` (degrees).

    ``out``: arrays to write the results into, ``{name: array}`` (float64, the shape of
    ``ath2``; the names are the outputs, ``outputs`` is then ignored).  The positions are
    then analysed :data:`BLOCK` (or ``block``) at a time, small enough for the cache,
    and no result array is allocated: a caller that reuses its arrays (a table, a plot,
    a sweep) pays neither for fresh pages nor for the memory of the whole run.  With
    ``out`` the mechanism, ``gravity`` and ``loads`` must describe one design (scalar
    fields); ``tex`` and ``th2dd`` may also be arrays of ``ath2``'s shape.

    ``outputs``: names wanted (any of ``OUTPUTS``); None means ``RESULTS``.  Only
    the steps these depend on are run.  ``tex``: the external torque on link 4
    (in-lb, + CCW), a constant, an array broadcasting against ``ath2``, or a
    callable taking ATH4 in degrees.  The effects a scene calls for, each off by
    default (as in 1966) and then costing nothing:

    * ``th2dd``: the crank's angular acceleration (rad/sec^2, CCW +); TH2D is then
      the crank speed at each position.  A constant, an array or a function of ATH2.
    * ``gravity``: None, or (gx, gy) in the length unit per sec^2 in the frame's axes;
      each link's weight acts at its G.
    * ``loads``: :class:`sielaff.Load` forces and torques on links 2-4.

    ``branch``: ``"open"`` (the 1966 program's assembly, B above the line A-O4 for the
    report's example) or ``"crossed"`` (the other).  Any four-bar works; where the loop
    cannot close the results are NaN (counted), see :func:`reachable`.

    TORQ is the total; ``TORQ_INERTIA``, ``TORQ_GRAVITY``, ``TORQ_LOADS`` and
    ``TORQ_TEX`` are its parts (docs/effects.md).  Returns ``{name: array}`` for the wanted
    names, every array of the broadcast shape of ``ath2``, the mechanism's
    fields and ``tex``, as a :class:`Results` whose ``not_assembled`` counts the
    positions where the loop cannot close (their results are NaN; an
    :class:`AssemblyWarning` says how many).  Shapes that do not broadcast are a
    ValueError naming the fields, and so is a mechanism no linkage can have
    (:func:`sielaff.mechanism.validate`: a missing or non-finite field, a length that
    is not positive, a negative weight or inertia).
    """
    if backend != "numpy":
        return _analyze_compiled(mechanism, ath2, outputs, tex, th2dd, gravity, loads,
                                 branch, out, backend)
    if out is not None:
        return _analyze_into(mechanism, ath2, out, BLOCK if block is None else block, tex,
                             th2dd, gravity, loads, branch)
    wanted = _check_outputs(outputs)
    validate(mechanism)
    ns = _seed(mechanism, ath2, tex, th2dd, gravity, loads, branch)
    seeded = frozenset(ns)
    named = [("ath2", np.shape(ath2))] + [
        (n if n != "TEX" else "tex", np.shape(v)) for n, v in ns.items()
        if n not in ("tex_fn", "th2dd_fn", "ATH2", "loads")]
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
            _warn_not_assembled(not_assembled, int(np.prod(shape)), stacklevel=3)
    seen: set[int] = set()
    for name in wanted:
        v = ns[name]
        if (name in seeded or id(v) in seen or not isinstance(v, np.ndarray)
                or v.shape != shape):
            v = np.array(np.broadcast_to(v, shape), dtype=float)
        seen.add(id(v))
        out[name] = v.reshape(final_shape)
    return out


#: Positions per block of ``analyze(..., out=...)``: long enough to spread the call's
#: fixed cost (about 0.5 ms: the plan, checks, seeding), short enough that the work
#: arrays come from the allocator's free lists, not fresh pages (docs/performance.md).
BLOCK = 16384


def _analyze_into(mechanism, ath2, out, block, tex, th2dd, gravity, loads, branch):
    """``analyze(..., out=out)``: blocks of ``block`` positions written into ``out``."""
    if not isinstance(block, int) or block < 1:
        raise ValueError(f"block = {block!r}: a number of positions, 1 or more")
    th = np.asarray(ath2, dtype=float)
    wanted = _check_outputs(list(out))
    for name, array in out.items():
        if not (isinstance(array, np.ndarray) and array.dtype == np.float64
                and array.shape == th.shape and array.flags.writeable):
            raise ValueError(f"out[{name!r}]: a writeable float64 array of ath2's shape "
                             f"{th.shape}")
    for name, v in mechanism.as_dict().items():
        if np.ndim(v):
            raise ValueError(f"out= analyses one design: {name} is an array (shape "
                             f"{np.shape(v)})")
    flat_th = th.reshape(-1)
    n = flat_th.size

    def part(v, i, j):
        if callable(v) or np.ndim(v) == 0:
            return v
        a = np.asarray(v, dtype=float)
        if a.shape != th.shape:
            raise ValueError(f"with out=, tex and th2dd are scalars, callables or arrays "
                             f"of ath2's shape {th.shape}, not {a.shape}")
        return a.reshape(-1)[i:j]

    flat = {name: out[name].reshape(-1) for name in wanted}
    for name, array in flat.items():
        if not np.shares_memory(array, out[name]):
            raise ValueError(f"out[{name!r}] must be contiguous (it is written in place)")
    # One design: checked, seeded and planned once; each block only brings its angles
    # (and its share of an array TEX or TH2DD), so a block costs its arithmetic alone.
    validate(mechanism)
    varying = [name for name, v in (("TEX", tex), ("TH2DD", th2dd))
               if not callable(v) and np.ndim(v)]
    base = _seed(mechanism, flat_th[:1], 0.0 if "TEX" in varying else tex,
                 th2dd=0.0 if "TH2DD" in varying else th2dd, gravity=gravity, loads=loads,
                 branch=branch)
    seeded = frozenset(base)
    order = None if varying else _plan(wanted, seeded, _zero_seeds(base))
    missing: int | None = 0
    for i in range(0, n, block):
        j = min(i + block, n)
        ns = dict(base)
        ns["ATH2"] = flat_th[i:j]
        for name in varying:
            ns[name] = part(tex if name == "TEX" else th2dd, i, j)
        plan = order or _plan(wanted, seeded, _zero_seeds(ns))
        with np.errstate(all="ignore"):
            count = _run(plan, ns)
        missing = None if count is None else (missing or 0) + count
        for name in wanted:
            flat[name][i:j] = ns[name]
    result = Results((name, out[name]) for name in wanted)
    result.not_assembled = missing
    if missing:
        _warn_not_assembled(missing, n, stacklevel=4)
    return result


def _analyze_compiled(mechanism, ath2, outputs, tex, th2dd, gravity, loads, branch, out,
                      backend):
    """``analyze(..., backend="numba")`` (see analyze)."""
    if backend != "numba":
        raise ValueError(f"backend = {backend!r}: 'numpy' or 'numba'")
    from sielaff.engine.compiled import compiled_results

    validate(mechanism)
    wanted = _check_outputs(list(out) if out is not None else outputs)
    missing = [n for n in wanted if n not in RESULTS]
    if missing:
        raise ValueError(f"backend='numba' gives the RESULTS names, not {missing}")
    th = np.asarray(ath2, dtype=float)
    table = compiled_results(mechanism, th, tex, th2dd=th2dd, gravity=gravity, loads=loads,
                             branch=branch)
    index = {name: i for i, name in enumerate(RESULTS)}
    result = Results()
    for name in wanted:
        row = table[index[name]].reshape(th.shape)
        if out is not None:
            out[name][...] = row
            row = out[name]
        result[name] = row
    result.not_assembled = int(np.count_nonzero(np.isnan(table[index["GAMMA"]])))  # s34
    if result.not_assembled:  # RESULTS only here: no ASSEMBLED output to point to
        _warn_not_assembled(result.not_assembled, th.size, stacklevel=4, mask=False)
    return result
