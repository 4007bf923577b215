"""How the compiled backend lays out its work (engine/compiled.py, engine/kernel.py),
checked without numba: the fresh results as rows of one block aligned to a huge page,
and the kernel's order of the plan's steps (a schedule that keeps fewer values alive,
each step after what it needs)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from sielaff import engine
from sielaff.engine import compiled as C
from sielaff.engine.analysis import prepare
from sielaff.engine.kernel import _schedule
from sielaff.engine.scene import Scene
from sielaff.mechanism import EXAMPLE


@pytest.mark.parametrize("k, n", [(0, 5), (1, 1), (3, 5), (71, 1000), (3, 700_001)])
def test_fresh_results_are_separate_rows_of_one_aligned_block(k, n):
    rows = C._fresh(k, n)
    assert len(rows) == k
    for a in rows:
        assert a.shape == (n,) and a.dtype == np.float64
        assert a.flags.c_contiguous and a.flags.writeable
    for a, b in itertools.combinations(rows, 2):
        assert not np.shares_memory(a, b)
    if k * n >= C._ALIGN_FROM:  # large: the block starts on a huge page
        assert rows[0].ctypes.data % C.HUGE_PAGE == 0
    elif rows:  # small: no padding (the block is the rows)
        assert all(r.base is rows[0].base for r in rows)
        assert rows[0].base is None or rows[0].base.size == k * n


def _plan(scene: Scene):
    req = prepare(EXAMPLE, np.zeros(4), list(engine.RESULTS), scene)
    ns = req.model.seed(req.mechanism, np.zeros(4), req.scene)
    return req.model.plan(req.wanted, frozenset(ns), req.model.zero_seeds(ns)), set(ns)


def _live_area(order) -> int:
    """The number of values alive after each step, summed over the steps (a value lives
    from its step to its last use)."""
    uses: dict[str, int] = {}
    for st, skipped, _ in order:
        for name in () if skipped else st.needs:
            uses[name] = uses.get(name, 0) + 1
    live: set[str] = set()
    area = 0
    for st, skipped, _ in order:
        for name in () if skipped else st.needs:
            uses[name] -= 1
            if not uses[name]:
                live.discard(name)
        live |= {p for p in st.provides if uses.get(p, 0)}
        area += len(live)
    return area


SCENES = {"1966": Scene(),
          "effects": Scene(th2dd=-40.0, gravity="down",
                           loads=[engine.Load(3, r=8.0, angle=10.0, fx=80.0)],
                           elements=[engine.Spring((1, 6.0, 90.0), (4, 8.0, 0.0), 30.0, 5.0)])}


@pytest.mark.parametrize("scene", SCENES.values(), ids=SCENES.keys())
def test_the_schedule_runs_each_step_after_its_inputs_and_keeps_fewer_values_alive(scene):
    order, seeded = _plan(scene)
    sched = _schedule(order)
    assert sorted(st.name for st, _, _ in sched) == sorted(st.name for st, _, _ in order)
    known = set(seeded)
    for st, skipped, _ in sched:
        assert skipped or set(st.needs) <= known, st.name
        known |= set(st.provides)
    assert _live_area(sched) < _live_area(order)
