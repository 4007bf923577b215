"""The streamed kernel (engine/kernel.py's ``far`` form, run by engine/compiled.py's
``_streamed``): from ``STREAM_FROM`` values a request's loop stores each output by
non-temporal stores of whole vectors that promise their alignment.  It must give the
chunked kernel's bits and count whatever the outputs' offsets and length, keep its
promise (whole runs from a 64-byte boundary; the head and tail through aligned scratch
rows), and fall back to the plain kernel where it cannot (outputs on different offsets,
overlapping arrays) or not well (outputs crowded on one offset from a 4 KiB page where a
vector store is narrower than a cache line)."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

from sielaff import engine
from sielaff.engine import compiled as C
from sielaff.engine import kernel as K
from sielaff.engine.analysis import prepare
from sielaff.engine.kernel_math import X86
from sielaff.engine.scene import Scene
from sielaff.mechanism import EXAMPLE, Mechanism

pytest.importorskip("numba")
if not X86:  # elsewhere: never streamed
    pytest.skip("the streamed kernel is x86-64's", allow_module_level=True)

WANTED = ["ATH3", "ATH4", "TH3D", "TH4D", "TORQ"]
#: a design that cannot assemble past a crank angle range: NaN and a count to carry
OPEN_HALF = Mechanism(**{**EXAMPLE.as_dict(), "R1": 26.0})


@pytest.fixture
def spied(monkeypatch):
    """Streamed from 1,000 values (200 positions of the five outputs); each run of the
    streamed kernel recorded: (positions, counted, first output's address)."""
    monkeypatch.setattr(K, "STREAM_FROM", 1000)
    calls: list[tuple[int, int, int]] = []
    real = C._streamed

    def spy(kernel, n, head, values, ins, outs):
        def recorded(m, count, *args):
            calls.append((m, count, args[len(values) + len(ins)].ctypes.data))
            return kernel(m, count, *args)
        return real(recorded, n, head, values, ins, outs)

    monkeypatch.setattr(C, "_streamed", spy)
    return calls


def _analyze(m, th, out=None, threads=1, streamed=True):
    """(outputs, not assembled) of the compiled backend, streamed or the chunked kernel."""
    saved, C.STREAMED = C.STREAMED, streamed
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", engine.AssemblyWarning)
            req = prepare(m, th, list(WANTED), Scene())
            got, bad, _ = C.run(req, out, threads=threads)
    finally:
        C.STREAMED = saved
    return got, bad


def _views(n, offset):
    """One output per wanted name, each ``offset`` floats past a 64-byte boundary."""
    out = {}
    for name in WANTED:
        raw = np.full(n + 16, -7.0)
        k = (-raw.ctypes.data % 64) // 8
        out[name] = raw[k + offset:k + offset + n]
    return out


@pytest.mark.parametrize("n", [200, C.RUN + 3, 3 * C.RUN + 37])
def test_streamed_runs_give_the_chunked_kernels_bits_at_every_offset(spied, n):
    th = np.linspace(-30.0, 400.0, n)
    th[[0, n // 2, n - 1]] = np.nan  # in the head, the body and the tail
    ref, ref_bad = _analyze(OPEN_HALF, th, streamed=False)
    assert 0 < ref_bad < n  # counted: positions that cannot assemble, and others
    heads = set()
    for offset in range(8):
        out = _views(n, offset)
        del spied[:]
        got, bad = _analyze(OPEN_HALF, th, out=out)
        assert spied, "not streamed"
        head = (8 - offset) % 8
        heads.add(head)
        body = (n - head) // C.RUN * C.RUN if n > head else 0
        for m, count, address in spied:  # whole runs, each from a 64-byte boundary
            assert m % C.RUN == 0 and address % 64 == 0 and count <= m
        assert sum(count for _, count, _ in spied) == n
        assert [c for m, c, _ in spied if m == c] == ([body] if body else [])
        assert bad == ref_bad
        for name in WANTED:
            assert got[name].ctypes.data == out[name].ctypes.data  # written in place
            np.testing.assert_array_equal(out[name], ref[name], err_msg=name)
    assert heads == set(range(8))


def test_fresh_results_and_two_threads_are_streamed_too(spied):
    n = 4 * C.RUN + 9000 + 11  # past 4096 a thread (compiled.run)
    th = np.linspace(-30.0, 400.0, n)
    ref, ref_bad = _analyze(OPEN_HALF, th, streamed=False)
    fresh, bad = _analyze(OPEN_HALF, th)
    assert len(spied) == 2 and bad == ref_bad  # one run and the tail
    del spied[:]
    two, bad2 = _analyze(OPEN_HALF, th, out=_views(n, 3), threads=2)
    assert len(spied) == 4 and bad2 == ref_bad  # each thread's run and its edges
    for name in WANTED:
        np.testing.assert_array_equal(fresh[name], ref[name])
        np.testing.assert_array_equal(two[name], ref[name])


def test_outputs_it_cannot_stream_take_the_plain_kernel(spied):
    """Outputs on different offsets from a cache line, or an output over an input: the
    plain kernel, the same bits."""
    n = 3 * C.RUN
    th = np.linspace(-30.0, 400.0, n)
    ref, _ = _analyze(EXAMPLE, th, streamed=False)
    mixed = _views(n, 0)
    mixed["TORQ"] = _views(n, 1)["TORQ"]
    assert C.stream_start(list(mixed.values()), [th]) is None
    got, _ = _analyze(EXAMPLE, th, out=mixed)
    assert not spied  # counted: the plain kernel ran
    for name in WANTED:
        np.testing.assert_array_equal(got[name], ref[name])
    outs = list(_views(n, 0).values())
    assert C.stream_start(outs, [outs[2][5:]]) is None  # an input inside an output
    assert C.stream_start(outs, [th]) == 0
    assert C.stream_start(list(_views(n, 5).values()), [th]) == 3
    odd = np.zeros(12).view(np.uint8)[4:84].view(np.float64)  # not on 8 bytes
    assert odd.ctypes.data % 8 and C.stream_start([odd], []) is None


def _at(n, offsets):
    """Arrays of n floats, the j-th at offsets[j] bytes from a 4 KiB page."""
    arrays = []
    for off in offsets:
        raw = np.full(n + 1024, -7.0)
        k = (-raw.ctypes.data % 4096 + off) // 8
        arrays.append(raw[k:k + n])
    return arrays


def test_outputs_crowded_on_one_page_offset_stream_only_with_whole_line_stores(monkeypatch):
    from sielaff.engine import kernel_math

    n = 3 * C.RUN
    crowded = _at(n, [0] * (C.CROWD + 1))
    spread = _at(n, [64 * j for j in range(C.CROWD + 1)])
    monkeypatch.setattr(kernel_math, "line_stores", lambda: False)
    assert C.stream_start(crowded, []) is None
    assert C.stream_start(crowded[:C.CROWD], []) == 0
    assert C.stream_start(spread, []) == 0
    assert C.stream_start(_at(n, [0] * C.CROWD + [4096 - 64]), []) == 0
    monkeypatch.setattr(kernel_math, "line_stores", lambda: True)
    assert C.stream_start(crowded, []) == 0


def test_crowded_outputs_take_the_plain_kernel_with_its_bits(spied, monkeypatch):
    from sielaff.engine import kernel_math

    n = 3 * C.RUN + 5
    th = np.linspace(-30.0, 400.0, n)
    ref, ref_bad = _analyze(OPEN_HALF, th, streamed=False)
    monkeypatch.setattr(kernel_math, "line_stores", lambda: False)
    monkeypatch.setattr(C, "CROWD", 2)
    got, bad = _analyze(OPEN_HALF, th, out=dict(zip(WANTED, _at(n, [0] * len(WANTED)))))
    assert not spied and bad == ref_bad  # counted: the plain kernel ran
    spread = dict(zip(WANTED, _at(n, [64 * j for j in range(len(WANTED))])))
    got2, bad2 = _analyze(OPEN_HALF, th, out=spread)
    assert spied and bad2 == ref_bad
    for name in WANTED:
        np.testing.assert_array_equal(got[name], ref[name])
        np.testing.assert_array_equal(got2[name], ref[name])


@pytest.mark.parametrize("name, features, whole", [
    ("znver4", "+avx2,+avx512f", True), ("znver3", "+avx2,-avx512f", False),
    ("skylake-avx512", "+avx2,+avx512f", False), ("sapphirerapids", "+avx512f", False)])
def test_whole_line_stores_are_avx512_where_llvm_uses_it(monkeypatch, name, features, whole):
    from numba.core import config

    from sielaff.engine import kernel_math

    monkeypatch.setattr(config, "CPU_NAME", name)
    monkeypatch.setattr(config, "CPU_FEATURES", features)
    assert kernel_math.line_stores.__wrapped__() is whole


def test_the_streamed_loop_stores_whole_vectors_around_the_caches(spied, monkeypatch):
    """The assembly of the streamed kernel (compiled in memory: numba shows none of a
    cached one): packed non-temporal stores (VMOVNTPD) and a fence."""
    monkeypatch.setenv("SIELAFF_KERNEL_DIR", "off")
    monkeypatch.setattr(K, "_KERNELS", {})
    before = set(K._STREAMED)
    _analyze(EXAMPLE, np.linspace(0.0, 360.0, C.RUN))
    streamed = list(set(K._STREAMED) - before)
    assert len(streamed) == 1  # counted
    asm = streamed[0].inspect_asm(streamed[0].signatures[0])
    packed = re.findall(r"\bvmovntp[sd]\s+%[yz]mm", asm)
    assert len(packed) >= len(WANTED) and "sfence" in asm
