"""The step registry: each step declares what it needs and provides; a plan runs only
the steps the asked-for outputs depend on.

``@step(provides=..., needs=..., zero_when=...)`` registers a function; its parameters
must be its ``needs``.  ``_plan`` computes the dependency closure of the wanted names
in dependency order, skips a step whose ``zero_when`` inputs are all zero (a massless
link), and says after which step each intermediate can be dropped.  ``STEP_CALLS``
counts the runs (tests prove an effect that is off costs nothing).  The steps live in
the modules named after what they compute, in the order the physics goes:
``positions``, ``velocities``, ``accelerations``, ``inertia``, ``forces``, ``outputs``.
"""

from __future__ import annotations

import inspect
from collections import Counter
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any


@dataclass(frozen=True)
class Step:
    """One unit of work: ``fn(*needs)`` returns the ``provides`` values, in order."""

    name: str
    fn: Callable[..., Any]
    provides: tuple[str, ...]
    needs: tuple[str, ...]
    zero_when: tuple[str, ...] = ()  # every name any group below uses
    zero_groups: tuple[tuple[str, ...], ...] = ()  # zero if all of one group are zero


#: All steps, in registration order.
STEPS: list[Step] = []


#: Which step provides each quantity.
PROVIDER: dict[str, Step] = {}


#: How many times each step has run (by step name); tests may reset it.
STEP_CALLS: Counter[str] = Counter()


def _register(st: Step) -> None:
    for name in st.provides:
        if name in PROVIDER:
            raise ValueError(f"{name} provided twice ({PROVIDER[name].name}, {st.name})")
        PROVIDER[name] = st
    STEPS.append(st)


def step(provides: Iterable[str], needs: Iterable[str] = (), zero_when=()):
    """Register the decorated function as a step.

    The function's parameters must be exactly ``needs`` (so the declaration
    can be checked against the code) and it returns one value per name in
    ``provides`` (a bare value if there is one).  ``zero_when``: names that,
    if all identically zero, make every provided value zero; or a list of such
    groups (tuples), any one of which all zero suffices (a link's inertia force is
    zero if it has no mass *or* its centre of mass does not accelerate).
    """
    provides, needs = tuple(provides), tuple(needs)
    items = tuple(zero_when)
    if all(isinstance(x, str) for x in items):
        groups = (items,) if items else ()
    else:
        groups = tuple((g,) if isinstance(g, str) else tuple(g) for g in items)
    flat = tuple(dict.fromkeys(n for g in groups for n in g))

    def decorate(fn):
        params = tuple(inspect.signature(fn).parameters)
        if params != needs:
            raise TypeError(f"step {fn.__name__}: parameters {params} != needs {needs}")
        _register(Step(fn.__name__, fn, provides, needs, flat, groups))
        return fn

    return decorate


def _depends_on(name: str, inputs: frozenset[str]) -> bool:
    """Whether ``name`` (transitively) needs any of ``inputs``."""
    if name in inputs:
        return True
    st = PROVIDER.get(name)
    return st is not None and any(_depends_on(n, inputs) for n in st.needs)


@lru_cache(maxsize=256)
def _plan(wanted: tuple[str, ...], seeded: frozenset[str],
          zero_seeds: frozenset[str]) -> tuple[tuple[Step, bool, tuple[str, ...]], ...]:
    """Steps to run, in dependency order, as (step, skipped, names to drop after it).

    Dropping intermediates after their last use lets numpy reuse their memory
    (fresh multi-megabyte arrays cost page faults, more than the arithmetic).
    """

    zero_memo: dict[str, bool] = {}

    def known_zero(name: str) -> bool:
        if name in seeded:
            return name in zero_seeds
        if name not in zero_memo:
            zero_memo[name] = is_zero(PROVIDER[name])
        return zero_memo[name]

    def is_zero(st: Step) -> bool:
        return any(all(known_zero(n) for n in g) for g in st.zero_groups)

    order: list[tuple[Step, bool]] = []
    available = set(seeded)
    active: set[str] = set()

    def visit(name: str) -> None:
        if name in available:
            return
        st = PROVIDER.get(name)
        if st is None:
            raise ValueError(f"{name} is neither an input nor provided by a step")
        if st.name in active:
            raise RuntimeError(f"dependency cycle through {st.name}")
        skipped = is_zero(st)
        if not skipped:
            active.add(st.name)
            for need in st.needs:
                visit(need)
            active.discard(st.name)
        order.append((st, skipped))
        available.update(st.provides)

    for name in wanted:
        visit(name)
    last_use: dict[str, int] = {}
    for i, (st, skipped) in enumerate(order):
        for name in () if skipped else st.needs:
            last_use[name] = i
        for name in st.provides:
            last_use.setdefault(name, i)
    drops: list[list[str]] = [[] for _ in order]
    for name, i in last_use.items():
        if name not in wanted and name not in seeded:
            drops[i].append(name)
    return tuple((st, skipped, tuple(d)) for (st, skipped), d in zip(order, drops, strict=True))
