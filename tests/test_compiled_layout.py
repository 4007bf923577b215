"""How the compiled backend lays out its work (engine/compiled.py, engine/kernel.py),
checked without numba: the fresh results as rows of one block aligned to a huge page,
the kernel's order of the plan's steps (a schedule that keeps fewer values alive, each
step after what it needs), its outputs staged in chunks when there are many, and a
serial step in a loop of its own; with numba, the staged loop's bits are the plain
loop's at every chunk boundary."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from sielaff import engine
from sielaff.engine import compiled as C
from sielaff.engine import kernel as K
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


def _source(wanted, scene=None, serial=frozenset()):
    req = prepare(EXAMPLE, np.zeros(4), list(wanted), scene or Scene())
    ns = req.model.seed(req.mechanism, np.zeros(4), req.scene)
    order = req.model.plan(req.wanted, frozenset(ns), req.model.zero_seeds(ns))
    scalars = tuple(sorted(k for k in ns if np.ndim(ns[k]) == 0))
    return K.kernel_source(req.model, order, req.wanted, scalars, ("ATH2",), (), serial)[0]


def test_many_outputs_are_staged_in_chunks_and_few_written_straight():
    many, few = engine.RESULTS, engine.KINEMATIC_OUTPUTS
    assert len(few) <= K.STAGE_FROM < len(many)  # both paths drawn by the two requests
    src = _source(many)
    assert f"for _c in range(0, _n, {K.CHUNK})" in src and "for i in range(_n)" not in src
    for j in range(len(many)):  # each output staged, then copied out once per chunk
        assert src.count(f"_out{j}[") == 1 and f"_out{j}[_c:_c + _m] = _b{j}[:_m]" in src
        assert f"_b{j}[_j] = " in src
    src = _source(few)
    assert "for i in range(_n)" in src and "_blk" not in src
    assert all(f"_out{j}[i] = " in src for j in range(len(few)))


@pytest.mark.filterwarnings("ignore::sielaff.engine.AssemblyWarning")
@pytest.mark.parametrize("n", [0, 1, K.CHUNK - 1, K.CHUNK, K.CHUNK + 1, 3 * K.CHUNK + 7])
def test_the_staged_loop_gives_the_plain_loops_bits(n, monkeypatch):
    pytest.importorskip("numba")
    wanted = ["ATH3", "ATH4", "TH3D", "TH4D", "TORQ"]
    th = np.linspace(-30.0, 400.0, n)
    th[n // 2:n // 2 + 1] = np.nan  # a position that cannot be computed, in mid-chunk
    got = {}
    for stage_from in (len(wanted) - 1, len(wanted)):  # staged, then plain
        monkeypatch.setattr(K, "STAGE_FROM", stage_from)
        monkeypatch.setattr(K, "_KERNELS", {})
        got[stage_from] = engine.analyze(EXAMPLE, th, wanted, backend="numba")
    for name in wanted:
        np.testing.assert_array_equal(got[len(wanted) - 1][name], got[len(wanted)][name])


def test_a_serial_step_runs_in_a_loop_of_its_own_between_vectorisable_ones():
    """Pin friction's step calls array code (a loop of iterations at each position): it
    runs in the middle one of three loops over each chunk, what it needs from the first
    handed over in rows of a block, the steps after it in the third."""
    scene = Scene(friction=engine.PinFriction(0.1, 0.2))
    src = _source(engine.KINEMATIC_OUTPUTS[:4] + ("TORQ", "FA32"), scene,
                  frozenset({"_friction"}))
    loops = src.split("        for _j in range(_m):\n")
    assert len(loops) == 4  # the prologue, then three phases
    first, serial, after = loops[1:]
    friction_call = "TORQ_FRICTION, PLOSS_O2"
    assert friction_call in serial and friction_call not in first + after
    assert "TORQ = _s" in after and "FA32 = _s" in after  # the totals after friction
    assert "FA32X_0, FA32Y_0 = _s" in first  # the frictionless forces before it
    handed = [line.split(" = ")[0].strip() for line in serial.splitlines() if " = _x" in line]
    assert "FA32X_0" in handed and "s34" in handed
    for name in handed:  # each handed value written by the first loop, once
        assert first.count(f"] = {name}\n") == 1
    assert "_ok = " in after  # the totals are NaN where the loop cannot close
    # no serial step: one loop, as before
    assert _source(("TORQ",), scene).count("for _j in range(_m)") == 0
