"""A step of a linkage unrolled into plain code: the step (a closure over its topology,
reading dictionaries of links and points) run once on symbols, its arithmetic recorded
line by line, and written out as a function of numbers and flat tuples.

Why
    A linkage's steps (engine/linkage_model.py) are written once, over a
    :class:`~sielaff.linkage.Topology`: which dyad, which link, which point is looked up
    in the topology and in dictionaries as they run.  The numpy engine and the compiled
    backend both run the function this module writes from such a step: the same
    operations on the same values in the same order, with the lookups done once, here
    (the numpy engine's bits are those of the step as written; the compiled backend
    compiles the written function for one position, as any step, engine/kernel.py).

How
    Each input is a :class:`Sym`; an operation on a symbol (an operator, a numpy ufunc,
    ``np.where``, ``np.max``) appends one line ``tN = <operation>`` and gives the symbol
    ``tN``; an operation on numbers alone is done at once, as the step does it (Python's
    or numpy's, the constant written back in its type).  A value the step branches on, or
    converts to a Python number, cannot be recorded: :class:`Untraceable` (the caller keeps
    the step as written; the compiled backend then refuses it, naming it).  A structured
    value passed between steps (a :class:`~sielaff.engine.dyads.Positions`, a
    :class:`~sielaff.engine.dyads.Motion`) is passed as the flat tuple of its symbols, its
    skeleton (the structure, its constants, where each symbol goes) kept here;
    :func:`call` records a call of an opaque function (the joints' linear solve, which
    the compiled backend replaces by its one-position form, engine/kernel_math.py).
"""

from __future__ import annotations

import dataclasses
import math
import threading
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

__all__ = ["Sym", "Untraceable", "call", "flatten", "keep", "nested", "rebuild", "skeleton",
           "structured", "unrolled"]

_LOCK = threading.RLock()


class Untraceable(Exception):
    """The step depends on its values in a way that cannot be written out ahead."""


class _Tape:
    def __init__(self) -> None:
        self.lines: list[str] = []
        self.glob: dict[str, Any] = {"np": np}
        self.n = 0

    def new(self, expr: str) -> Sym:
        name = f"t{self.n}"
        self.n += 1
        self.lines.append(f"    {name} = {expr}")
        return Sym(name)

    def global_name(self, obj: Any, stem: str) -> str:
        for k, v in self.glob.items():
            if v is obj:
                return k
        name = f"_{stem}{len(self.glob)}"
        self.glob[name] = obj
        return name


_ACTIVE: list[_Tape] = []


def _tape() -> _Tape:
    if not _ACTIVE:
        raise Untraceable("a symbol used outside its trace")
    return _ACTIVE[-1]


def _contains_sym(x: Any) -> bool:
    if isinstance(x, Sym):
        return True
    if isinstance(x, tuple | list):
        return any(_contains_sym(v) for v in x)
    return False


def render(x: Any) -> str:
    """``x`` as an expression of the written function (a symbol, a constant of its own
    type, a tuple or a named tuple of those)."""
    if isinstance(x, Sym):
        return x.name
    if isinstance(x, bool | np.bool_):
        return repr(bool(x))
    if isinstance(x, np.ndarray) and x.ndim == 0:
        return f"np.float64({_number(float(x))})" if x.dtype.kind == "f" else render(x[()])
    if isinstance(x, np.floating):
        return f"np.float64({_number(float(x))})"
    if isinstance(x, int | float | np.integer):
        return _number(float(x))
    if isinstance(x, tuple) and hasattr(x, "_fields"):
        cls = _tape().global_name(type(x), type(x).__name__)
        return f"{cls}(" + ", ".join(render(v) for v in x) + ")"
    if isinstance(x, tuple | list):
        return "(" + "".join(render(v) + ", " for v in x) + ")"
    raise Untraceable(f"a value of type {type(x).__name__}")


def _number(f: float) -> str:
    if math.isnan(f):
        return "np.nan"
    if math.isinf(f):
        return "np.inf" if f > 0 else "(-np.inf)"
    r = repr(f)
    return f"({r})" if r.startswith("-") else r


_OPS = {"add": "+", "subtract": "-", "multiply": "*", "divide": "/", "true_divide": "/",
        "less": "<", "less_equal": "<=", "greater": ">", "greater_equal": ">=",
        "equal": "==", "not_equal": "!=", "bitwise_and": "&", "bitwise_or": "|"}
_FUNCS = {"where": "where", "max": "max", "amax": "max", "min": "min", "amin": "min"}


def _binary(op: str, a: Any, b: Any) -> Sym:
    return _tape().new(f"{render(a)} {op} {render(b)}")


class Sym:
    """A value of the step being unrolled: the name of the line that computes it."""

    __slots__ = ("name",)
    __array_priority__ = 1000.0

    def __init__(self, name: str) -> None:
        self.name = name

    def __repr__(self) -> str:
        return f"Sym({self.name})"

    __hash__ = object.__hash__

    def __add__(self, o: Any) -> Sym: return _binary("+", self, o)
    def __radd__(self, o: Any) -> Sym: return _binary("+", o, self)
    def __sub__(self, o: Any) -> Sym: return _binary("-", self, o)
    def __rsub__(self, o: Any) -> Sym: return _binary("-", o, self)
    def __mul__(self, o: Any) -> Sym: return _binary("*", self, o)
    def __rmul__(self, o: Any) -> Sym: return _binary("*", o, self)
    def __truediv__(self, o: Any) -> Sym: return _binary("/", self, o)
    def __rtruediv__(self, o: Any) -> Sym: return _binary("/", o, self)
    def __lt__(self, o: Any) -> Sym: return _binary("<", self, o)
    def __le__(self, o: Any) -> Sym: return _binary("<=", self, o)
    def __gt__(self, o: Any) -> Sym: return _binary(">", self, o)
    def __ge__(self, o: Any) -> Sym: return _binary(">=", self, o)
    def __eq__(self, o: Any) -> Sym: return _binary("==", self, o)  # type: ignore[override]
    def __ne__(self, o: Any) -> Sym: return _binary("!=", self, o)  # type: ignore[override]
    def __and__(self, o: Any) -> Sym: return _binary("&", self, o)
    def __rand__(self, o: Any) -> Sym: return _binary("&", o, self)
    def __or__(self, o: Any) -> Sym: return _binary("|", self, o)
    def __ror__(self, o: Any) -> Sym: return _binary("|", o, self)
    def __neg__(self) -> Sym: return _tape().new(f"-{self.name}")
    def __pos__(self) -> Sym: return self
    def __abs__(self) -> Sym: return _tape().new(f"abs({self.name})")

    def __bool__(self) -> bool:
        raise Untraceable("the step branches on a value")

    def __float__(self) -> float:
        raise Untraceable("the step converts a value to a Python number")

    def __index__(self) -> int:
        raise Untraceable("the step indexes by a value")

    def __array__(self, *args: Any, **kwargs: Any) -> Any:
        raise Untraceable("the step makes an array of a value")

    def __array_ufunc__(self, ufunc: Any, method: str, *inputs: Any, **kwargs: Any) -> Any:
        if method != "__call__" or any(v is not None for v in kwargs.values()):
            raise Untraceable(f"np.{ufunc.__name__}.{method} with {sorted(kwargs)}")
        name = ufunc.__name__
        if name in _OPS and len(inputs) == 2:
            return _binary(_OPS[name], *inputs)
        if name == "negative":
            return _tape().new(f"-{render(inputs[0])}")
        if name == "absolute":
            name = "abs"
        return _tape().new(f"np.{name}(" + ", ".join(render(v) for v in inputs) + ")")

    def __array_function__(self, func: Any, types: Any, args: Any, kwargs: Any) -> Any:
        name = _FUNCS.get(func.__name__)
        if name is None or kwargs:
            raise Untraceable(f"np.{func.__name__}")
        return _tape().new(f"np.{name}(" + ", ".join(render(v) for v in args) + ")")


class _Result(Sequence[Any]):
    """What a recorded opaque call returns: its items, read by index."""

    def __init__(self, sym: Sym, n: int) -> None:
        self.sym, self.n = sym, n

    def __len__(self) -> int:
        return self.n

    def __getitem__(self, i: Any) -> Any:
        if not isinstance(i, int) or not 0 <= i < self.n:
            raise Untraceable("an opaque result read by a slice or a negative index")
        return _tape().new(f"{self.sym.name}[{i}]")


def call(fn: Callable[..., Any], n: int | None, *args: Any) -> Any:
    """``fn(*args)``, or, while a step is unrolled on symbols, the line calling it (its
    ``n`` results read by index; None: one result); ``fn`` a function of the package (a
    step's code calls it as written, the compiled backend its one-position form)."""
    if not _ACTIVE or not _contains_sym(args):
        return fn(*args)
    tape = _tape()
    name = tape.global_name(fn, fn.__name__)
    sym = tape.new(f"{name}(" + ", ".join(render(a) for a in args) + ")")
    return sym if n is None else _Result(sym, n)


# --- structured values as flat tuples ------------------------------------------------

_KEPT: dict[tuple[Any, str], Any] = {}


def keep(owner: Any, name: str, skeleton: Any) -> None:
    """Remember the skeleton of ``owner``'s value ``name`` (None: it is not flattened)."""
    with _LOCK:
        _KEPT[(owner, name)] = skeleton


def skeleton(owner: Any, name: str) -> Any:
    """The skeleton :func:`keep` remembered for ``owner``'s value ``name`` (None if none)."""
    return _KEPT.get((owner, name))


def structured(owner: Any, name: str, value: Any) -> Any:
    """``owner``'s value ``name`` as its step made it (a flat tuple rebuilt by its
    skeleton; anything else as it is)."""
    skeleton = _KEPT.get((owner, name))
    if skeleton is None or not isinstance(value, tuple):
        return value
    return rebuild(skeleton, value)


@dataclasses.dataclass(frozen=True)
class _Leaf:
    i: int


_WALK = object()  # a leaf rule's answer for a value it leaves to the walk


def _map(v: Any, leaf: Callable[[Any], Any]) -> Any:
    """``v`` rebuilt: each value ``x`` for which ``leaf(x)`` is not ``_WALK`` replaced by
    that answer, else walked into (dataclasses, dicts, named tuples, tuples, lists) or
    kept."""
    out = leaf(v)
    if out is not _WALK:
        return out
    if dataclasses.is_dataclass(v) and not isinstance(v, type):
        return type(v)(**{f.name: _map(getattr(v, f.name), leaf) for f in dataclasses.fields(v)})
    if isinstance(v, dict):
        return {k: _map(w, leaf) for k, w in v.items()}
    if isinstance(v, tuple) and hasattr(v, "_fields"):
        return type(v)(*(_map(w, leaf) for w in v))
    if isinstance(v, tuple):
        return tuple(_map(w, leaf) for w in v)
    if isinstance(v, list):
        return [_map(w, leaf) for w in v]
    return v


def flatten(x: Any) -> tuple[list[Sym], Any]:
    """(the symbols of ``x``, each once, in order; ``x``'s skeleton: its structure with
    each symbol replaced by its index)."""
    syms: list[Sym] = []
    index: dict[int, int] = {}

    def leaf(v: Any) -> Any:
        if not isinstance(v, Sym):
            return _WALK
        if id(v) not in index:
            index[id(v)] = len(syms)
            syms.append(v)
        return _Leaf(index[id(v)])

    return syms, _map(x, leaf)


def rebuild(skeleton: Any, leaves: Sequence[Any]) -> Any:
    """The value of ``skeleton`` with its symbols' places filled from ``leaves``."""
    return _map(skeleton, lambda v: leaves[v.i] if isinstance(v, _Leaf) else _WALK)


def nested(shape: Any) -> Any:
    """The skeleton of a value passed as it is (not flattened): ``shape`` a nesting of
    tuples whose leaves are None; each leaf read by its path of indices."""
    count = [0]

    def walk(v: Any, path: tuple[int, ...]) -> Any:
        if v is None:
            count[0] += 1
            return _Path(path)
        return tuple(walk(w, path + (i,)) for i, w in enumerate(v))

    return walk(shape, ())


@dataclasses.dataclass(frozen=True)
class _Path:
    path: tuple[int, ...]


def _inputs(tape: _Tape, arg: str, skeleton: Any) -> Any:
    """The value of parameter ``arg`` in the trace (its skeleton's leaves read into lines)."""
    if skeleton is None:
        return Sym(arg)
    leaves: dict[int, Sym] = {}
    paths: dict[tuple[int, ...], Sym] = {}

    def leaf(v: Any) -> Any:
        if isinstance(v, _Leaf):
            if v.i not in leaves:
                leaves[v.i] = tape.new(f"{arg}[{v.i}]")
            return leaves[v.i]
        if isinstance(v, _Path):
            if v.path not in paths:
                paths[v.path] = tape.new(arg + "".join(f"[{i}]" for i in v.path))
            return paths[v.path]
        return _WALK

    return _map(skeleton, leaf)


def unrolled(name: str, fn: Callable[..., Any], inputs: Sequence[Any], n_out: int,
             flat: Sequence[bool] = ()) -> tuple[Callable[..., Any], list[Any]]:
    """``fn`` written out as the plain function ``name`` of its inputs (``inputs``: each
    parameter's skeleton, None for a number), and the skeleton of each of its ``n_out``
    results (None unless ``flat`` says to pass that result as the flat tuple of its
    symbols).  The function returns a bare value if ``n_out`` is 1."""
    flat = tuple(flat) or (False,) * n_out
    with _LOCK:
        tape = _Tape()
        _ACTIVE.append(tape)
        try:
            args = [f"a{i}" for i in range(len(inputs))]
            values = [_inputs(tape, a, sk) for a, sk in zip(args, inputs, strict=True)]
            result = fn(*values)
            results = (result,) if n_out == 1 else tuple(result)
            if len(results) != n_out:
                raise Untraceable(f"{len(results)} results, not {n_out}")
            out, skeletons, shapes = [], [], []
            for r, is_flat in zip(results, flat, strict=True):
                if is_flat:
                    syms, sk = flatten(r)
                    out.append(render(tuple(syms)))
                    skeletons.append(sk)
                    shapes.append((None,) * len(syms))
                else:
                    out.append(render(r))
                    skeletons.append(None)
                    shapes.append(_shape(r))
        except (TypeError, ValueError, KeyError, IndexError, AttributeError) as e:
            raise Untraceable(f"{type(e).__name__}: {e}") from None
        finally:
            _ACTIVE.pop()
    value = out[0] if n_out == 1 else "(" + "".join(o + ", " for o in out) + ")"
    src = "\n".join([f"def {name}({', '.join(args)}):", *tape.lines,
                     f"    return {value}", ""])
    ns = dict(tape.glob)
    exec(compile(src, f"<sielaff unrolled step {name}>", "exec"), ns)  # noqa: S102
    made = ns[name]
    made.__module__ = __name__
    made.__sielaff_source__ = src + "".join(  # what the kernel cache hashes
        getattr(v, "__sielaff_source__", "") for v in tape.glob.values())
    made.__sielaff_shapes__ = tuple(shapes)  # the kernel hands tuples between its loops
    return made, skeletons


def _shape(x: Any) -> Any:
    """A result's nesting of plain tuples, each leaf None (a number, or something that is
    not a plain tuple: a named tuple)."""
    if isinstance(x, tuple | list) and not hasattr(x, "_fields"):
        return tuple(_shape(v) for v in x)
    return None
