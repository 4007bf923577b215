"""A step that iterates at each position until it is done, declared once for both engines.

In:  the pass, ``body(*state, *consts) -> (*new_state, *results, done, keep)``, written
     for one position like any step (numpy's functions and arithmetic only); the names
     of the iteration's limit, of the flag saying where it runs at all (``go``, 1.0 or
     0.0), of its starting state and of its constants.
Out: a step providing the results and the count (:func:`iterated`): at each position
     where ``go`` holds, the pass runs on the state, the results of the first pass that
     says ``done`` are kept and its number is the count, and the position stops there
     or where a pass says not ``keep`` (failed); results and count stay 0.0 where no
     pass said done within ``limit`` passes.

The numpy engine runs the passes over the positions still iterating (compacted after
each pass, so a position costs the passes it needs).  The compiled kernel
(:mod:`sielaff.engine.kernel`) runs each pass over a chunk of positions in a loop of its
own, every position of the chunk computed and the results of each captured at the pass
that said done: a loop with no branch in it, which LLVM vectorises, where a loop of
iterations inside the loop over positions (a different count at each) cannot be.  The
same pass gives both the same arithmetic, so the results agree as any step's do.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

from sielaff.engine.registry import Step, zero_when_of

__all__ = ["iterated", "iterated_step", "run"]


def iterated(provides: Iterable[str], limit: str, go: str, start: Iterable[str],
             consts: Iterable[str], zero_when: Iterable[Any] = ()
             ) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Mark the decorated pass as an iterated step (``steps_of`` finds it).

    The pass's parameters are the state's (one per name of ``start``, named as the pass
    likes) and then exactly ``consts``; it returns the new state, one result per name of
    ``provides`` but the last (the count), ``done`` and ``keep``.  The step needs
    ``(limit, go, *start, *consts)``; ``zero_when`` as :func:`registry.step`'s.
    """
    start, consts = tuple(start), tuple(consts)

    def decorate(body: Callable[..., Any]) -> Callable[..., Any]:
        import inspect

        params = tuple(inspect.signature(body).parameters)
        if params[len(start):] != consts or len(params) != len(start) + len(consts):
            raise TypeError(f"iterated step {body.__name__}: parameters {params} are not "
                            f"{len(start)} of the state's and then {consts}")
        body.__sielaff_step__ = iterated_step(  # type: ignore[attr-defined]
            body.__name__, body, provides, limit, go, start, consts, zero_when)
        return body

    return decorate


def iterated_step(name: str, body: Callable[..., Any], provides: Iterable[str], limit: str,
                  go: str, start: Iterable[str], consts: Iterable[str],
                  zero_when: Iterable[Any] = ()) -> Step:
    """The Step of the pass ``body`` (as :func:`iterated`'s, for a pass whose parameters
    are not named after its inputs: one written out by engine/unroll.py)."""
    provides, start, consts = tuple(provides), tuple(start), tuple(consts)
    if body.__code__.co_argcount != len(start) + len(consts):
        raise TypeError(f"iterated step {name}: {body.__code__.co_argcount} parameters, "
                        f"not {len(start)} of the state's and {len(consts)} constants")
    n_state, n_results = len(start), len(provides) - 1

    def numpy_form(*args: Any) -> Any:
        return run(body, n_state, n_results, args[0], args[1], args[2:])

    numpy_form.__name__ = name
    return Step(name, numpy_form, provides, (limit, go) + start + consts,
                *zero_when_of(zero_when), iterates=(body, n_state))


def run(body: Callable[..., Any], n_state: int, n_results: int, limit: Any, go: Any,
        values: tuple[Any, ...]) -> tuple[Any, ...]:
    """The iterated step over arrays (see the module's doc): ``values`` the starting
    state and the constants, each an array (any shapes that broadcast) or a number."""
    shape = np.broadcast_shapes(*(np.shape(x) for x in (go,) + values))
    size = int(np.prod(shape))

    def flat(x: Any) -> Any:  # a number stays one (the pass broadcasts it)
        return np.broadcast_to(np.asarray(x, dtype=float), shape).reshape(-1) \
            if np.ndim(x) else x

    results = [np.zeros(size) for _ in range(n_results)]
    count = np.zeros(size)
    idx = np.flatnonzero(np.broadcast_to(np.asarray(go) != 0.0, shape).reshape(-1))
    at = [flat(x)[idx] if np.ndim(x) else x for x in values]
    for k in range(1, int(limit) + 1):
        if not idx.size:
            break
        out = body(*at)
        done = out[-2]
        keep = out[-1] & ~done  # a position stops at its first done, whatever keep says
        for r, x in zip(results, out[n_state:n_state + n_results], strict=True):
            r[idx[done]] = x[done] if np.ndim(x) else x
        count[idx[done]] = float(k)
        idx = idx[keep]
        at = [x[keep] if np.ndim(x) else x
              for x in tuple(out[:n_state]) + tuple(at[n_state:])]
    return tuple(r.reshape(shape) for r in results) + (count.reshape(shape),)
