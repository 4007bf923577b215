"""How the compiled backend lays out its work (engine/compiled.py, engine/kernel.py),
checked without numba: the fresh results as rows of one block aligned to a huge page,
each row on a cache line, a large block kept when its rows are dropped and taken by the
next call of its size (never while a view lives, never more than KEEP_BYTES),
the kernel's order of the plan's steps (a schedule that keeps fewer values alive, each
step after what it needs), its outputs staged in chunks when there are many, a serial
step in a loop of its own and an iterated step in passes; with numba, the staged loop's
bits are the plain loop's at every chunk boundary."""

from __future__ import annotations

import itertools
import re

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
    assert all(a.ctypes.data % 64 == 0 for a in rows)  # each on a cache line (streamed)
    if k * n >= C._ALIGN_FROM:  # large: the block starts on a huge page
        assert rows[0].ctypes.data % C.HUGE_PAGE == 0
    elif rows:  # small: one block, the rows and a cache line of padding
        assert all(r.base is rows[0].base for r in rows)
        assert rows[0].base.size == k * (-(-n // 8) * 8) + 8


@pytest.fixture
def pool(monkeypatch):
    """An empty pool of kept blocks, kept from 1,000 floats (small blocks, quick tests)."""
    monkeypatch.setattr(C, "_ALIGN_FROM", 1000)
    monkeypatch.setattr(C, "_idle", [])
    return C._idle


def test_a_dropped_block_is_kept_and_taken_by_the_next_call_of_its_size(pool):
    rows = C._fresh(3, 700)
    address, size = rows[0].ctypes.data, rows[0].base.base.raw.size
    del rows
    assert [b.size for b in pool] == [size]  # kept once the last row is dropped
    again = C._fresh(3, 700)
    assert again[0].ctypes.data == address and not pool  # taken
    other = C._fresh(2, 700)  # another size: a new block
    assert other[0].ctypes.data != address
    C.release()
    del again
    assert len(pool) == 1
    C.release()
    assert not pool


def test_a_block_is_not_reused_while_any_view_of_it_lives(pool):
    rows = C._fresh(3, 700)
    address = rows[0].ctypes.data
    piece = rows[2][10:20]
    piece[:] = 5.0
    del rows
    assert not pool  # the piece holds the block
    again = C._fresh(3, 700)
    assert again[0].ctypes.data != address
    assert not any(np.shares_memory(piece, a) for a in again)
    for a in again:
        a.fill(-1.0)
    assert (piece == 5.0).all()
    del piece
    assert len(pool) == 1


def test_kept_blocks_stay_within_keep_bytes(pool, monkeypatch):
    rows = [C._fresh(3, 700) for _ in range(5)]
    one = rows[0][0].base.base.raw.nbytes
    monkeypatch.setattr(C, "KEEP_BYTES", 2 * one + 1)
    del rows
    assert len(pool) == 2 and sum(b.nbytes for b in pool) <= C.KEEP_BYTES
    monkeypatch.setattr(C, "KEEP_BYTES", 0)
    C.release()
    rows = C._fresh(3, 700)
    del rows
    assert not pool  # 0: none kept


def test_blocks_dropped_and_taken_by_threads_are_never_shared(pool):
    import threading

    errors: list[str] = []
    addresses: set[int] = set()

    def work(k: int) -> None:
        for i in range(200):
            rows = C._fresh(3, 700)
            addresses.add(rows[0].ctypes.data)
            for j, a in enumerate(rows):
                a.fill(k * 1000 + i * 3 + j)
            for j, a in enumerate(rows):
                if not (a == k * 1000 + i * 3 + j).all():
                    errors.append(f"thread {k}, call {i}, row {j} overwritten")

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    assert len(addresses) < 100  # counted: of 800 calls' blocks, most were kept ones
    assert sum(b.nbytes for b in pool) <= C.KEEP_BYTES


def test_a_child_forked_while_the_lock_is_held_takes_a_block(pool):
    """The lock is new in a forked child: one forked while another thread took a block
    does not wait for ever on its first large fresh result."""
    import os
    import time
    import warnings

    held = C._idle_lock
    assert held.acquire()
    try:
        with warnings.catch_warnings():  # Python 3.12 on: forking a threaded process warns
            warnings.simplefilter("ignore", DeprecationWarning)
            pid = os.fork()
        if pid == 0:  # the child: a block, then out
            code = 1
            try:
                code = 0 if len(C._fresh(3, 700)) == 3 and not C._idle_lock.locked() else 2
            finally:
                os._exit(code)
    finally:
        held.release()
    deadline = time.monotonic() + 30.0
    while time.monotonic() < deadline:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            assert os.waitstatus_to_exitcode(status) == 0
            return
        time.sleep(0.05)
    os.kill(pid, 9)
    os.waitpid(pid, 0)
    pytest.fail("the forked child waited on the lock")


def test_results_written_into_a_kept_block_are_every_position_written(pool, monkeypatch):
    """A kept block holds the dropped results: every position of the next call's is the
    kernel's, plain and streamed."""
    pytest.importorskip("numba")
    th = np.linspace(-30.0, 400.0, 3001)
    wanted = ["ATH3", "TH4D", "TORQ"]
    ref = engine.analyze(EXAMPLE, th, wanted)
    for stream_from in (K.STREAM_FROM, 1000):
        monkeypatch.setattr(K, "STREAM_FROM", stream_from)
        C.release()
        got = engine.analyze(EXAMPLE, th, wanted, backend="numba")
        address = got["ATH3"].ctypes.data
        for a in got.values():
            a.fill(np.nan)
        del got, a
        got = engine.analyze(EXAMPLE, th, wanted, backend="numba")
        assert got["ATH3"].ctypes.data == address  # counted: the kept block was taken
        for name in wanted:
            np.testing.assert_allclose(got[name], ref[name], rtol=1e-12, atol=1e-9,
                                       err_msg=name)
        del got


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


def _source(wanted, scene=None, serial=frozenset(), far=False):
    req = prepare(EXAMPLE, np.zeros(4), list(wanted), scene or Scene())
    ns = req.model.seed(req.mechanism, np.zeros(4), req.scene)
    order = req.model.plan(req.wanted, frozenset(ns), req.model.zero_seeds(ns))
    scalars = tuple(sorted(k for k in ns if np.ndim(ns[k]) == 0))
    return K.kernel_source(req.model, order, req.wanted, scalars, ("ATH2",), (), serial,
                           far)[0]


@pytest.mark.parametrize("wanted", [engine.RESULTS, engine.KINEMATIC_OUTPUTS])
def test_the_streamed_form_stores_each_output_once_straight_from_one_loop(wanted):
    """kernel_source's ``far``: one loop over the positions, each output stored once by
    the streamed store, the count of positions that cannot assemble kept to the first
    ``_count``, a fence after the loop; no staging, whatever the outputs' number."""
    src = _source(wanted, far=True)
    assert src.startswith("def kernel(_n, _count, ")
    assert "for i in range(_n):" in src and "_blk" not in src and "_copy_out" not in src
    for j in range(len(wanted)):
        assert src.count(f"_put(_out{j}, i, ") == 1
        assert f"_out{j}[" not in src
    assert src.count("_bad += _select(_ok, 0, _select(i < _count, 1, 0))") == 1
    assert src.rstrip().splitlines()[-2:] == ["    _fence()", "    return _bad"]


def test_a_plan_of_several_loops_has_no_streamed_form():
    """Pin friction runs in several loops over a chunk: ``far`` gives the chunked kernel
    (whose copy of each chunk streams), the very text of the plain request."""
    scene = Scene(friction=engine.PinFriction(0.1, 0.2))
    wanted = ["TORQ", "TORQ_FRICTION"]
    assert _source(wanted, scene, far=True) == _source(wanted, scene)
    assert "_put(" not in _source(wanted, scene, far=True)


def test_many_outputs_are_staged_in_chunks_and_few_written_straight():
    many, few = engine.RESULTS, engine.KINEMATIC_OUTPUTS
    assert len(few) <= K.STAGE_FROM < len(many)  # both paths drawn by the two requests
    src = _source(many)
    assert f"for _c in range(0, _n, {K.CHUNK})" in src and "for i in range(_n)" not in src
    for j in range(len(many)):  # each output staged, then copied out once per chunk,
        # streamed past STREAM_FROM values (_far), and nowhere else
        assert len(re.findall(rf"\b_out{j}\b", src)) == 2  # the parameter and the copy
        assert src.count(f"_copy_out(_out{j}, _b{j}, _c, _m, _far)") == 1
        assert f"_b{j}[_j] = " in src
    assert f"_far = _n * {len(many)} >= {K.STREAM_FROM}" in src and "_fence()" in src
    src = _source(few)
    assert "for i in range(_n)" in src and "_blk" not in src and "_copy_out" not in src
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


def _loops(src: str) -> list[tuple[int, str]]:
    """Each loop over a chunk's positions in the source, in order: (its indent, its body)."""
    lines = src.splitlines()
    out = []
    for k, line in enumerate(lines):
        if line.strip() == "for _j in range(_m):":
            indent = len(line) - len(line.lstrip())
            body = itertools.takewhile(lambda x, d=indent: len(x) - len(x.lstrip()) > d,
                                       lines[k + 1:])
            out.append((indent, "\n".join(body) + "\n"))
    return out


def test_friction_runs_as_passes_and_its_serial_solve_in_a_loop_of_its_own():
    """Pin friction's six steps: its start, frame and check with the steps before it, its
    fixed point as passes over the chunk (engine/iterate.py; tests/test_iterate.py), the
    solve where the law need not contract (array code, serial, called only there:
    tests/test_only_where.py) in a loop of its own, what it needs
    handed over in rows of a block, the losses and the totals after."""
    scene = Scene(friction=engine.PinFriction(0.1, 0.2))
    wanted = engine.KINEMATIC_OUTPUTS[:4] + ("TORQ", "FA32")
    src = _source(wanted, scene, frozenset({"_friction_solve"}))
    loops = _loops(src)
    assert [indent for indent, _ in loops] == [8, 8, 12, 8, 8, 8]
    first, start, passes, end, serial, after = (body for _, body in loops)
    assert "FA32X_0, FA32Y_0 = _s" in first  # the frictionless forces before friction
    assert "ft_o2_0, ft_a_0, ft_b_0, ft_o4_0, friction_go = _s" in first
    assert "= ft_o2_0\n" in start and "= friction_go\n" in start
    assert "= _s" in passes and "if " not in passes and "_select(_go, " in passes
    assert "fa32x_p = _x" in end
    solve_call = "FRICTION_ITERATIONS, FRICTION_STATUS = _s"
    assert solve_call in serial and solve_call not in first + passes + after
    assert "TORQ = _s" in after and "FA32 = _s" in after and "_ok = " in after
    written = first + start + passes
    for line in serial.splitlines():  # each value handed to the serial loop written before
        if " = _x" in line:
            row = line.split(" = ")[1].strip()
            assert f"{row} = " in written, line
    # the solve not serial: it runs in the loop of the losses and totals
    loops = _loops(_source(wanted, scene))
    assert len(loops) == 5 and solve_call in loops[-1][1] and "TORQ = _s" in loops[-1][1]
    # no friction: no iterated step, no serial one, one loop
    assert _source(("TORQ",)).count("for _j in range(_m)") == 0
