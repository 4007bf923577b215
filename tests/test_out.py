"""analyze(..., out=): blocks written into the caller's arrays, bit for bit one call."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from sielaff.engine import RESULTS, AssemblyWarning, Load, analyze
from sielaff.mechanism import EXAMPLE


@pytest.mark.parametrize("block", [1, 7, 1000, 16384])
def test_bit_identical_to_one_call(block):
    n = 100 if block == 1 else 1000  # a block per position: 300 of them are enough
    th = np.linspace(-50.0, 410.0, 3 * n).reshape(3, n)
    ref = analyze(EXAMPLE, th)
    out = {name: np.full(th.shape, np.nan) for name in RESULTS}
    r = analyze(EXAMPLE, th, out=out, block=block)
    assert list(r) == list(RESULTS) and r["TORQ"] is out["TORQ"]
    for name in RESULTS:
        assert np.array_equal(out[name], ref[name], equal_nan=True), name


def test_with_every_effect_and_array_tex():
    th = np.linspace(0.0, 360.0, 5000)
    scene = dict(th2dd=-40.0, gravity="down", loads=[Load(3, r=8.0, fx=80.0)],
                 tex=np.sin(th))
    names = ["TORQ", "TORQ_GRAVITY", "TORQ_LOADS", "TORQ_TEX", "FOA", "SHAKM"]
    ref = analyze(EXAMPLE, th, names, **scene)
    out = {name: np.empty(th.shape) for name in names}
    analyze(EXAMPLE, th, out=out, block=333, **scene)
    for name in names:
        assert np.array_equal(out[name], ref[name]), name


def test_positions_that_cannot_assemble_are_counted_once():
    m = EXAMPLE.replace(R1=10.0, R2=4.0, R3=5.0, R4=4.0)  # a triple-rocker
    th = np.linspace(0.0, 360.0, 1000)
    out = {"ATH3": np.empty(th.shape)}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = analyze(m, th, out=out, block=64)
    assert r.not_assembled == int(np.isnan(out["ATH3"]).sum()) > 0
    assert sum(issubclass(w.category, AssemblyWarning) for w in caught) == 1


def test_refusals():
    th = np.linspace(0.0, 360.0, 10)
    with pytest.raises(ValueError, match="writeable float64"):
        analyze(EXAMPLE, th, out={"TORQ": np.empty(9)})
    with pytest.raises(ValueError, match="writeable float64"):
        analyze(EXAMPLE, th, out={"TORQ": np.empty(10, dtype=np.float32)})
    with pytest.raises(ValueError, match="one design"):
        analyze(EXAMPLE.replace(R4=np.array([[11.0], [12.0]])), th,
                out={"TORQ": np.empty(10)})
    strided = np.empty(20)[::2]  # a strided view is written in place: fine
    analyze(EXAMPLE, th, out={"TORQ": strided})
    assert np.array_equal(strided, analyze(EXAMPLE, th, ["TORQ"])["TORQ"])
    with pytest.raises(ValueError, match="contiguous"):  # would be written to a copy
        analyze(EXAMPLE, th.reshape(2, 5), out={"TORQ": np.empty((5, 2)).T})
    with pytest.raises(ValueError, match="block"):
        analyze(EXAMPLE, th, out={"TORQ": np.empty(10)}, block=0)
