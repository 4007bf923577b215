"""The compiled kernel, generated from a model's own steps (``backend="numba"``).

In:  a model's plan for the wanted outputs (:meth:`Model.plan`, the very plan the numpy
     engine runs), and which of the names it starts from are per-position arrays and which
     are constants.
Out: one numba loop over the positions that runs, for each position, the plan's steps in
     order, each step's own function compiled for one position, and writes each wanted
     output straight into the array returned (no table, no copy).

How one function serves both engines
    A step is written once, for numpy arrays.  Here its code object is compiled again by
    numba with its globals rebound: ``np`` to one position's numpy
    (:func:`sielaff.engine.kernel_math.one_position`: sin, cos and atan2 branch-free and
    vectorisable, numpy's ``out=`` taken and ignored), the three operations of
    :mod:`sielaff.engine.arith` and ``statics.plus`` to their one-position forms, and every
    helper of the package it calls compiled the same way.  A step whose code numba cannot
    type for one position (an array-only construct, a dictionary of links) has no compiled
    form: the request is refused in one line naming the step and its effect, so an effect
    added to a model is compiled, or refused, from its own code.

The loop runs the plan's steps in an order that keeps fewer values alive at once
(``_schedule``) and stores each output as soon as it is known: the loop's body is
hundreds of vector instructions, and a value alive across it holds a register or a
spill slot.  With more than ``STAGE_FROM`` outputs the loop runs in chunks of ``CHUNK``
positions whose outputs go to a small staging block first, copied out one output at a
time after each chunk: a store to each of 71 arrays at each position is 71 streams of
writes at once, more than a core's prefetchers follow, and every line then waits for its
read-for-ownership (docs/performance.md measures both).  With ``STREAM_FROM`` values
or more in all the copy uses non-temporal stores, which write a line without reading it
first (half the memory traffic).  A request that large whose plan runs in one loop takes
the streamed form instead (``far``, on x86-64): no staging, each output stored straight
from the loop by non-temporal stores of whole vectors, which need an alignment that the
loop promises LLVM and the caller keeps (:func:`sielaff.engine.compiled._streamed`:
runs of whole vectors from each output's 64-byte boundary, the head and tail through
aligned scratch rows).  A step that calls array code
(pin friction's solve where the law need not contract) cannot be vectorised: it runs in
a loop over the chunk of its own, between the loops of the steps before and after it,
which stay vectorised, and is called only where its ``only_where`` flag holds (the
registry's Step: elsewhere its outputs are some of its inputs, copied).  An iterated
step (:mod:`sielaff.engine.iterate`: pin friction's fixed point) runs as passes over
the chunk, each pass a loop with no branch in it (a position that stopped is computed
on, its results captured once, at the pass that said done), until no position is left.

A step the plan skips (an input identically zero) is the literal 0.0 here, as in numpy;
an output that depends on the position is NaN where the loop cannot close (the model's
``counts`` name is NaN there), a skipped step's 0.0 included.
"""

from __future__ import annotations

import hashlib
import keyword
import threading
import types
from collections.abc import Mapping
from typing import Any, Literal

from sielaff.engine.registry import Model, Plan, Step

__all__ = ["Uncompilable", "counts_assembly", "kernel_for", "kernel_source", "streamed"]

_LOCK = threading.RLock()
_FORMS: dict[Any, Any] = {}
_ARRAY_CODE: set[Any] = set()  # the functions that are or call array code (arith.array_code)
_ONE: list[Any] = []
_BUSY: set[Any] = set()
_MAX_INLINED_ARGS = 30  # CPython's STACK_USE_GUIDELINE
#: Outputs above which the loop stages them (see the module's doc: the kinematics' 48 and
#: fewer are written straight, where the copy pass would cost a small kernel more than
#: it saves), the chunk of positions staged (its rows stay in a core's L2 cache), and the
#: staging rows' stagger: rows CHUNK + STAGGER floats apart fall in different cache sets.
STAGE_FROM, CHUNK, STAGGER = 48, 512, 16
#: Output values (positions times outputs) from which the staged chunks are copied out
#: with non-temporal stores (kernel_math._streaming): 32 MiB, more than a core's caches
#: keep, so that a plain store's first read of each line is memory traffic for nothing;
#: below it the results may still be in cache when the caller reads them.
STREAM_FROM = 1 << 22


class Uncompilable(ValueError):
    """A step of the plan has no one-position form (numba cannot type its code)."""


def _one_position() -> tuple[Any, dict[Any, Any]]:
    if not _ONE:
        from sielaff.engine.kernel_math import one_position

        _ONE.append(one_position())
    return _ONE[0]


def _names(code: types.CodeType) -> set[str]:
    out = set(code.co_names)
    for c in code.co_consts:
        if isinstance(c, types.CodeType):
            out |= _names(c)
    return out


def _package_function(v: Any) -> bool:
    return isinstance(v, types.FunctionType) and (v.__module__ or "").startswith("sielaff.")


def scalar_form(fn: Any) -> Any:
    """``fn`` compiled by numba for one position (see the module's doc); cached."""
    import numba

    with _LOCK:
        if fn in _FORMS:
            return _FORMS[fn]
        np1, twins = _one_position()
        if fn in twins:
            _FORMS[fn] = twins[fn]
            return twins[fn]
        if fn.__closure__:
            raise Uncompilable(f"{fn.__name__} is a closure")
        if fn in _BUSY:
            raise Uncompilable(f"{fn.__name__} calls itself")
        glob = dict(fn.__globals__)
        arrays = getattr(fn, "__sielaff_array_code__", False)  # arith.array_code
        if not arrays:  # array code keeps numba's own numpy (arrays at one position)
            glob["np"] = np1
        _BUSY.add(fn)
        try:
            for name in _names(fn.__code__):
                v = glob.get(name)
                if _package_function(v):  # (twins are the package's functions too)
                    glob[name] = scalar_form(v)
                    arrays = arrays or v in _ARRAY_CODE
        finally:
            _BUSY.discard(fn)
        if arrays:
            _ARRAY_CODE.add(fn)
        f = types.FunctionType(fn.__code__, glob, fn.__name__, fn.__defaults__)
        # array code is called, not inlined; so is a function of more than 30 arguments
        # (CPython compiles such a call as f(*args), which numba's inliner refuses; LLVM
        # may still inline it)
        inline: Literal["always", "never"] = (
            "never" if arrays or fn.__code__.co_argcount > _MAX_INLINED_ARGS else "always")
        _FORMS[fn] = numba.njit(error_model="numpy", nogil=True, inline=inline)(f)
        return _FORMS[fn]


def _ident(name: str, k: int) -> str:
    """``name`` as the kernel's local variable (a stand-in where it cannot be one)."""
    usable = name.isidentifier() and not keyword.iskeyword(name) and not name.startswith("_")
    return name if usable else f"_k{k}"


#: A seed made of records: (its name, the records' type, whether it is one record rather
#: than a tuple of them, each record's leaves' names), the leaves being scalars or arrays,
#: or "=" and a literal for a field of the record type's ``STRUCTURE`` (which link a load
#: or a spring acts on: code, not data, so LLVM folds the choice of link away).
Struct = tuple[str, type, bool, tuple[tuple[str, ...], ...]]


def kernel_source(model: Model, order: Plan, wanted: tuple[str, ...],
                  scalars: tuple[str, ...], arrays: tuple[str, ...],
                  structs: tuple[Struct, ...] = (), serial: frozenset[str] = frozenset(),
                  far: bool = False) -> tuple[str, list[Step]]:
    """The loop's source for this plan, and the steps it calls (``_s0``, ``_s1``, ...):
    ``kernel(n, <scalars>, <per-position arrays>, <one output array per wanted name>)``
    returns how many positions cannot assemble.  ``far``, for a plan that runs in one
    loop: the streamed form, ``kernel(n, count, ...)``, whose loop stores each output by
    a non-temporal store that promises its alignment (kernel_math._streamed_store; the
    caller keeps the promise: compiled._streamed) and counts only the first ``count``
    positions; a plan of several loops has no such form (its chunks' copy streams).  A
    record seed (``structs``) is built from its leaves at each position (``_r0``, ...
    its type).  The steps named in
    ``serial`` (array code, which LLVM cannot vectorise) run in a loop over each chunk
    of their own, an iterated step in passes over it (``_passes``), the steps before
    and after them in others, the values a later loop takes from an earlier one handed
    over in rows of a block.  Uncompilable if an iterated step's limit is not one
    number."""
    names: dict[str, str] = {}

    def v(name: str) -> str:
        if name not in names:
            names[name] = _ident(name, len(names))
        return names[name]

    seeded = set(scalars) | set(arrays) | {st[0] for st in structs}
    sched = _schedule(order)
    # phases: the steps that run serially (array code, which LLVM cannot vectorise) in
    # phases of their own, an iterated step in one of its own (passes over the chunk),
    # the others in the rest, each phase after those of what it needs, so that the
    # vectorisable steps stay so
    level: dict[str, int] = {}
    kinds = ["vector"]
    for st, skipped, _ in sched:
        if skipped:
            continue
        kind = "iterate" if st.iterates else "serial" if st.name in serial else "vector"
        at = max((level.get(n, 0) for n in st.needs), default=0)
        if kinds[at] != kind or kind == "iterate":
            at = next((p for p in range(at + 1, len(kinds)) if kinds[p] == kind != "iterate"),
                      len(kinds))
            kinds += [kind] * (at == len(kinds))
        level.update(dict.fromkeys(st.provides, at))
    n_phases = len(kinds)
    far = far and n_phases == 1
    staged = not far and (n_phases > 1 or len(wanted) > STAGE_FROM)
    target, index = ("_b", "_j") if staged else ("_out", "i")
    reads = [f"{v(a)} = _in{j}[i]" for j, a in enumerate(arrays)]
    for j, (name, _, single, leaves) in enumerate(structs):
        records = [f"_r{j}({', '.join(x[1:] if x[0] == '=' else v(x) for x in item)})"
                   for item in leaves]
        reads.append(f"{v(name)} = " + (records[0] if single else
                                        "(" + ", ".join(records) + ",)"))
    phases: list[list[str]] = [[] for _ in range(n_phases)]
    taken: list[list[str]] = [[] for _ in range(n_phases)]  # each phase's handed values
    zeros: list[str] = []  # the skipped steps' 0.0, in every phase
    body = phases[0]
    called: list[Step] = []
    counts = counts_assembly(model, order)
    counted = False
    slot = {name: j for j, name in enumerate(wanted)}
    waiting: list[str] = []
    crossing: list[str] = []  # the values a later phase takes from an earlier one
    passes: dict[int, tuple[int, Step]] = {}  # an iterated step's phase: its _s, the step
    phase = 0

    # a value handed over that is a tuple (a linkage's positions, written out by
    # engine/unroll.py, which says each result's nesting) goes in one row per leaf; an
    # iterated step's results are numbers its passes write into rows (below)
    shapes = {p: sh for st, skipped, _ in order if not skipped and not st.iterates
              for p, sh in zip(st.provides, getattr(_code(st), "__sielaff_shapes__", ()),
                               strict=False) if sh is not None}
    split: set[str] = set()  # the tuples handed over, by their leaves' rows

    def take(name: str | None) -> None:  # ``name`` in the current phase
        if name in level and level[name] < phase and name not in taken[phase]:
            if name not in crossing and name not in split:
                if name in shapes:
                    split.add(name)
                for path in _leaves(shapes.get(name)):
                    key = name + repr(path) if path else name
                    crossing.append(key)
                    phases[level[name]].append(
                        f"_x{crossing.index(key)}[_j] = {v(name)}"
                        + "".join(f"[{i}]" for i in path))
            taken[phase].append(name)

    def handed(name: str) -> str:  # the value ``name`` read back from its rows
        return f"{v(name)} = " + _rebuilt(shapes.get(name), (), lambda path: (
            f"_x{crossing.index(name + repr(path) if path else name)}[_j]"))

    def store(names: Any) -> None:
        # each output stored as soon as it is known: a value kept to the end of the loop's
        # body would hold a register (or a spill slot) all the way there; one that is NaN
        # where the loop cannot close waits until that is known
        for name in names:
            if name not in slot:
                continue
            value = v(name)
            if counts and name not in seeded and model.needs_assembly(name):
                if not counted:
                    waiting.append(name)
                    continue
                take(model.counts)
                value = f"_select(_ok, {value}, _NAN)"
            j = slot.pop(name)
            body.append(f"_put(_out{j}, i, {value})" if far else
                        f"{target}{j}[{index}] = {value}")

    store([w for w in wanted if w in seeded])
    for st, skipped, _ in sched:
        if skipped:
            zeros += [f"{v(p)} = 0.0" for p in st.provides]
        elif st.iterates:  # its passes write its answers into rows; its phase reads them
            phase = level[st.provides[0]]
            body = phases[phase]
            if st.needs[0] not in scalars:
                raise Uncompilable(f"{st.name}: its limit {st.needs[0]} is not one number")
            for n in st.needs[1:]:
                take(n)
            passes[phase] = (len(called), st)
            crossing += [*st.provides, *(f"#{st.name}{m}" for m in range(st.iterates[1] + 1))]
            body += [f"{v(p)} = _x{crossing.index(p)}[_j]" for p in st.provides]
            called.append(st)
        else:
            phase = level[st.provides[0]]
            body = phases[phase]
            for n in st.needs:
                take(n)
            args = ", ".join(v(n) for n in st.needs)
            targets = ", ".join(v(p) for p in st.provides)
            call = f"{targets} = _s{len(called)}({args})"
            if st.only_where is not None and st.name in serial:  # the call only where needed
                flag, through = st.only_where
                body += [f"if {v(flag)} != 0.0:", "    " + call, "else:",
                         f"    {targets} = {', '.join(v(n) for n in through)}"]
            else:
                body.append(call)
            called.append(st)
        if model.counts in st.provides and not skipped:
            counted = True
            c = v(model.counts)
            body.append(f"_ok = {c} == {c}")
            body.append("_bad += _select(_ok, 0, _select(i < _count, 1, 0))" if far else
                        "_bad += _select(_ok, 0, 1)")
            store(waiting)
        store(st.provides)
    params = ["_n", "_count"][:1 + far] + [v(s) for s in scalars] + [
        f"_in{j}" for j in range(len(arrays))] + [f"_out{j}" for j in range(len(wanted))]
    starts: list[list[str]] = []
    for k, lines in enumerate(phases):  # each phase starts from the inputs and what it is handed
        got = [handed(n) for n in taken[k]]
        if model.counts in taken[k]:
            got.append(f"_ok = {v(model.counts)} == {v(model.counts)}")
        starts.append(reads + zeros + got)
        lines[:0] = starts[k]
    row = CHUNK + STAGGER
    if not staged:
        loop = ["    for i in range(_n):", *("        " + line for line in phases[0])]
        loop += ["    _fence()"] * far
    else:  # chunks: the outputs staged in _blk's rows, then copied out one by one
        loop = [f"    _far = _n * {len(wanted)} >= {STREAM_FROM}",
                f"    _blk = _np.empty({len(wanted) * row})",
                *(f"    _b{j} = _blk[{j * row}:{j * row + CHUNK}]" for j in range(len(wanted))),
                f"    _xblk = _np.empty({len(crossing) * row})",
                *(f"    _x{j} = _xblk[{j * row}:{j * row + CHUNK}]"
                  for j in range(len(crossing))),
                f"    for _c in range(0, _n, {CHUNK}):",
                f"        _m = min({CHUNK}, _n - _c)"]
        for k, lines in enumerate(phases):
            if k in passes:
                loop += _passes(*passes[k], starts[k], v, crossing)
            loop += ["        for _j in range(_m):", "            i = _c + _j",
                     *("            " + line for line in lines)]
        loop += [f"        _copy_out(_out{j}, _b{j}, _c, _m, _far)" for j in range(len(wanted))]
        loop += ["    if _far:", "        _fence()"]
    src = "\n".join([f"def kernel({', '.join(params)}):", "    _bad = 0", *loop,
                     "    return _bad", ""])
    return src, called


def _passes(j: int, st: Step, start: list[str], v: Any, crossing: list[str]) -> list[str]:
    """An iterated step's loops over a chunk (engine/iterate.py): its rows set from its
    start, then each pass over every position of the chunk (no branch: LLVM vectorises
    the pass), until none is left or the limit is reached.  The state is stored
    whatever the position (one that stopped is never read again); a result and the
    count are captured (kernel_math._capture) at the pass that says done, the only
    one: it stops the position.  A select of a row's own value there would be a masked
    store, which costs an AVX2 AMD CPU some ten cycles."""
    assert st.iterates is not None
    n_state = st.iterates[1]
    first, consts = st.needs[2:2 + n_state], st.needs[2 + n_state:]
    row = {name: f"_x{crossing.index(name)}[_j]" for name in st.provides}
    state = [f"_x{crossing.index(f'#{st.name}{m}')}[_j]" for m in range(n_state)]
    go = f"_x{crossing.index(f'#{st.name}{n_state}')}[_j]"
    results = [f"_yq{r}" for r in range(len(st.provides) - 1)]
    head = ["for _j in range(_m):", "    i = _c + _j"]
    return [*("        " + x for x in [
        *head, *("    " + line for line in start),
        *(f"    {state[m]} = {v(first[m])}" for m in range(n_state)),
        f"    {go} = {v(st.needs[1])}",
        *(f"    {row[p]} = 0.0" for p in st.provides),
        f"for _it in range(1, int({v(st.needs[0])}) + 1):",
        "    _itf = float(_it)",
        "    _left = 0",
        *("    " + x for x in [
            *head, *("    " + line for line in start),
            *(f"    _y{m} = {state[m]}" for m in range(n_state)),
            "    " + ", ".join([f"_yn{m}" for m in range(n_state)] + results
                               + ["_done", "_keep"])
            + f" = _s{j}({', '.join([f'_y{m}' for m in range(n_state)] + [v(c) for c in consts])})",
            f"    _a = {go} != 0.0",
            "    _go = _a & _keep & (_done == False)",  # stopped at its first done
            *(f"    {state[m]} = _yn{m}" for m in range(n_state)),
            *(f"    {row[p]} = _capture(_a & _done, {q}, {row[p]})"
              for p, q in zip(st.provides[:-1], results, strict=True)),
            f"    {row[st.provides[-1]]} = _capture(_a & _done, _itf, {row[st.provides[-1]]})",
            f"    {go} = _select(_go, 1.0, 0.0)",
            "    _left += _go"]),
        "    if _left == 0:",
        "        break"])]


def _leaves(shape: Any, path: tuple[int, ...] = ()) -> list[tuple[int, ...]]:
    """The paths to the leaves of a result's nesting (``()`` for a number)."""
    if shape is None:
        return [path]
    return [p for i, sh in enumerate(shape) for p in _leaves(sh, path + (i,))]


def _rebuilt(shape: Any, path: tuple[int, ...], row: Any) -> str:
    """The expression that builds a value of this nesting from its leaves' rows."""
    if shape is None:
        return str(row(path))
    items = [_rebuilt(sh, path + (i,), row) + ", " for i, sh in enumerate(shape)]
    # in tuples of at most 16, added: CPython 3.11 builds one of more than 30 items
    # through a list, which numba's bytecode reader took only where its name is
    # assigned once (a six-bar's positions are read back in every loop)
    return " + ".join("(" + "".join(items[k:k + 16]) + ")"
                      for k in range(0, len(items), 16)) or "()"


def counts_assembly(model: Model, order: Plan) -> bool:
    """Whether the plan solves the loop (runs the step of the model's ``counts`` name):
    then the kernel counts the positions that cannot assemble and its outputs are NaN
    there."""
    return model.counts is not None and any(
        model.counts in st.provides and not skipped for st, skipped, _ in order)


def _schedule(order: Plan) -> Plan:
    """The plan's steps reordered to keep few values alive at once (each value of the
    loop's body holds a register, or a spill slot, from its step to its last use): of
    the steps whose inputs are known, the one that ends the most values' lives and starts
    the fewest, ties in the plan's order."""
    uses: dict[str, int] = {}
    for st, skipped, _ in order:
        for name in () if skipped else st.needs:
            uses[name] = uses.get(name, 0) + 1
    made = {p for st, _, _ in order for p in st.provides}
    known = {n for n in uses if n not in made}
    left = list(order)
    out: list[tuple[Step, bool, tuple[str, ...]]] = []
    while left:
        best, score = 0, None
        for j, (st, skipped, _) in enumerate(left):
            needs = () if skipped else st.needs
            if not all(n in known for n in needs):
                continue
            ends = sum(1 for n in set(needs) if uses[n] == needs.count(n))
            starts = sum(1 for p in st.provides if uses.get(p, 0))
            if score is None or ends - starts > score:
                best, score = j, ends - starts
        st, skipped, drop = left.pop(best)
        for n in () if skipped else st.needs:
            uses[n] -= 1
        known.update(st.provides)
        out.append((st, skipped, drop))
    return tuple(out)


def _text(src: str) -> str:
    from sielaff.engine.kernel_cache import engine_hash

    return ("# generated by sielaff.engine.kernel (see there); do not edit\n"
            f"# engine {engine_hash()}\n"
            "import numba\n\n\n"
            "@numba.njit(error_model='numpy', nogil=True, cache=True)\n" + src)


def _name(src: str, salt: str) -> str:
    """The kernel module's name: a hash of its text and of what the text does not show."""
    return "sielaff_kernel_" + hashlib.sha256((_text(src) + salt).encode()).hexdigest()[:20]


def _cached(name: str) -> bool:
    """Whether numba's cache holds this kernel's machine code (from an earlier process)."""
    from sielaff.engine.kernel_cache import kernel_dir

    d = kernel_dir()
    return d is not None and (d / f"{name}.py").exists() and any(
        (d / "__pycache__").glob(f"{name}.kernel-*.nbi"))


def _type_steps(order: Plan, scalars: tuple[str, ...], arrays: tuple[str, ...],
                structs: tuple[Struct, ...], effect_of: Mapping[str, str]) -> None:
    """Each step of the plan compiled for its inputs' types, in order: Uncompilable naming
    the first that numba cannot type for one position."""
    import numba

    types_of = _seed_types(scalars, arrays, structs)
    for st, skipped, _ in order:
        if skipped:
            types_of.update(dict.fromkeys(st.provides, numba.float64))
            continue
        n_state = st.iterates[1] if st.iterates else 0
        try:
            ret = _typed(scalar_form(_code(st)), _code(st),
                         [types_of[x] for x in st.needs[2 if st.iterates else 0:]])
        except Uncompilable as e:
            raise Uncompilable(_refusal(st, effect_of, str(e))) from None
        except Exception as e:  # numba's typing errors: the step has no compiled form
            raise Uncompilable(_refusal(st, effect_of, type(e).__name__)) from None
        if st.iterates:  # the results, then the count
            types_of.update(zip(st.provides, tuple(ret.types)[n_state:-2] + (numba.float64,),
                                strict=True))
        elif len(st.provides) == 1:
            types_of[st.provides[0]] = ret
        else:
            types_of.update(zip(st.provides, ret, strict=True))


def _load(src: str, glob: dict[str, Any], name: str) -> Any:
    """The kernel of ``src`` as a numba dispatcher, from the kernel cache's folder when
    there is one (engine/kernel_cache.py), else made in memory."""
    import numba

    from sielaff.engine.kernel_cache import _cached_module, kernel_dir

    text = _text(src)
    d = kernel_dir()
    if d is not None:
        try:
            return _cached_module(d, name, text, glob).kernel
        except OSError:  # a cache that cannot be written or read: compile in memory
            pass
    ns = dict(glob)
    exec(compile(src, name, "exec"), ns)  # noqa: S102
    return numba.njit(error_model="numpy", nogil=True)(ns["kernel"])


_KERNELS: dict[Any, Any] = {}
_LLVM_OPTION = threading.Lock()


def kernel_for(model: Model, order: Plan, wanted: tuple[str, ...], scalars: tuple[str, ...],
               arrays: tuple[str, ...], effect_of: Mapping[str, str],
               structs: tuple[Struct, ...] = (), far: bool = False) -> Any:
    """The compiled kernel of ``kernel_source`` (cached per model, plan, seeds' shapes and
    ``far``).  Uncompilable (one line: the step, its effect) if a step has no
    one-position form.  ``far`` asks for the streamed form; a plan without one gives the
    plain kernel (:func:`streamed` tells which)."""
    key = (model.name, id(model), order, wanted, scalars, arrays, structs, far)
    with _LOCK:
        if key in _KERNELS:
            return _KERNELS[key]
        import math

        import numba
        import numpy

        try:
            forms = {_code(st): scalar_form(_code(st)) for st, skipped, _ in order
                     if not skipped}
        except Uncompilable:  # the refusal names the step and its effect
            _type_steps(order, scalars, arrays, structs, effect_of)
            raise
        serial = frozenset(st.name for st, skipped, _ in order
                           if not skipped and _code(st) in _ARRAY_CODE)
        src, called = kernel_source(model, order, wanted, scalars, arrays, structs, serial,
                                    far)
        if far and "_count" not in src:  # several loops: no streamed form
            _KERNELS[key] = kernel_for(model, order, wanted, scalars, arrays, effect_of,
                                       structs)
            return _KERNELS[key]
        glob: dict[str, Any] = {"_NAN": math.nan, "_np": numpy}
        glob.update({f"_r{j}": st[1] for j, st in enumerate(structs)})
        from sielaff.engine.kernel_math import (
            _capture_intrinsic,
            _intrinsics,
            _streamed_store,
            _streaming,
        )

        glob["_select"] = _intrinsics()[0]
        glob["_capture"] = _capture_intrinsic()
        glob["_copy_out"], glob["_fence"] = _streaming()
        glob["_put"] = _streamed_store()
        glob.update({f"_s{j}": forms[_code(st)] for j, st in enumerate(called)})
        # what the text does not show: the derived steps' code, the records' types
        salt = "".join(getattr(_code(st), "__sielaff_source__", st.name) for st in called)
        salt += "".join(f"{st[1].__module__}.{st[1].__qualname__}" for st in structs)
        name = _name(src, salt)
        if not _cached(name):  # each step typed alone: a refusal names the one that fails
            _type_steps(order, scalars, arrays, structs, effect_of)
        kernel = _load(src, glob, name)
        import llvmlite.binding as llvm

        f64 = numba.float64
        # inputs typed read-only: a writeable array converts to it, and a read-only one
        # (a broadcast view) then finds this kernel instead of compiling an unvectorised one
        ro = numba.types.Array(f64, 1, "C", readonly=True)
        arr = numba.types.Array(f64, 1, "C")

        # LLVM vectorises the loop only if it may check every pair of arrays for overlap
        # at run time (its limit on those checks, 128, raised while the kernel compiles)
        # and if the loops over a scene's loads, springs and dampers are unrolled (a loop
        # over a tuple of records indexes it at run time; its body is large, so the limit
        # on a full unroll's size is raised too, then set back to O3's 300).  Array code
        # a serial step calls has its fixed loops unrolled with them: the friction kernel
        # compiled in about 70 s instead of 45 (once; the kernel cache keeps it), while a
        # rolled loop over the springs and dampers cost it 0.17 s per 10^6 positions
        # (both measured before the fixed point ran in passes, engine/iterate.py)
        with _LLVM_OPTION:
            llvm.set_option("", "-vectorize-memory-check-threshold=100000")
            llvm.set_option("", "-unroll-threshold=100000")
            try:
                kernel.compile((numba.types.int64,) * (1 + far) + (f64,) * len(scalars)
                               + (ro,) * len(arrays) + (arr,) * len(wanted))
            finally:
                llvm.set_option("", "-vectorize-memory-check-threshold=128")
                llvm.set_option("", "-unroll-threshold=300")
        kernel.disable_compile()
        if far:
            _STREAMED.add(kernel)
        _KERNELS[key] = kernel
        return kernel


_STREAMED: set[Any] = set()


def streamed(kernel: Any) -> bool:
    """Whether ``kernel`` is a streamed form (``kernel(n, count, ...)``: kernel_source's
    ``far``), which only compiled._streamed may call."""
    return kernel in _STREAMED


def _seed_types(scalars: tuple[str, ...], arrays: tuple[str, ...],
                structs: tuple[Struct, ...]) -> dict[str, Any]:
    """numba's type of each name the kernel starts from, at one position."""
    import numba

    types_of: dict[str, Any] = dict.fromkeys(scalars + arrays, numba.float64)
    for name, cls, single, leaves in structs:
        record = numba.typeof(cls(*([0.0] * len(leaves[0]))))
        types_of[name] = record if single else numba.types.UniTuple(record, len(leaves))
    return types_of


def _code(st: Step) -> Any:
    """The function the kernel calls for the step: its own, or an iterated step's pass."""
    return st.iterates[0] if st.iterates else st.fn


def _typed(form: Any, fn: Any, args: list[Any]) -> Any:
    """``fn`` compiled for these argument types (its defaults omitted): its return type."""
    import numba

    n_params = fn.__code__.co_argcount
    defaults = fn.__defaults__ or ()
    omitted = [numba.types.Omitted(d) for d in defaults[len(defaults) - (n_params - len(args)):]
               ] if n_params > len(args) else []
    sig = tuple(args) + tuple(omitted)
    form.compile(sig)
    return form.overloads[sig].signature.return_type


def _refusal(st: Step, effect_of: Mapping[str, str], why: str) -> str:
    who = effect_of.get(st.name)
    what = f"{who} (its step {st.name})" if who else f"the model's step {st.name}"
    return f"backend='numba' has no compiled form of {what}: use backend='numpy'"
