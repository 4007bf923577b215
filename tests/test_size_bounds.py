"""Every size a spec or the API can ask for has one bound, derived from memory or from
a count of bounded steps, checked before any work (issue 32, family 2; the bounds and
their reasons are listed in docs/robustness.md).

The angles' bound is derived from a measured cost: BYTES_PER_POSITION must cover what the
figures of one block really take with every effect at its limit, measured here again
with tracemalloc (numpy's arrays are traced), or the derivation is void.
"""

from __future__ import annotations

import time
import tomllib
import tracemalloc
import warnings
from decimal import Decimal

import numpy as np
import pytest

from conftest import DECKS
from sielaff import EXAMPLE, Damper, Load, PinFriction, Scene, Spring
from sielaff.design.figures import figures
from sielaff.design.sweep import BLOCK, BLOCK_MEMORY, BYTES_PER_POSITION, MAX_ANGLES
from sielaff.engine.elements import MAX_ELEMENTS
from sielaff.mechanism import FIELD_NAMES
from sielaff.tools.spec import PunchError


def test_the_angles_bound_is_the_block_s_memory():
    assert MAX_ANGLES == BLOCK_MEMORY // (BLOCK * BYTES_PER_POSITION)
    assert MAX_ANGLES % 2 == 0 and MAX_ANGLES >= 3600  # the 0.1-degree grid fits


def test_a_position_costs_the_figures_less_than_the_bound_says():
    """Every effect at its limit: MAX_ELEMENTS springs and dampers, loads, pin friction,
    gravity, TEX and a crank acceleration; 64 designs x 720 angles."""
    d, n = 64, 720
    elements = tuple(Spring((1, 18.0, 0.0), (4, 6.0, 0.0), 20.0, 8.0)
                     for _ in range(MAX_ELEMENTS)) + tuple(
        Damper((2, 2.0, 0.0), (3, 6.0, 10.0), 0.5) for _ in range(MAX_ELEMENTS))
    scene = Scene(friction=PinFriction(0.1, 0.25), elements=elements, gravity="down",
                  loads=(Load(3, 8.0, 10.0, 80.0, 0.0, 1.0),) * 5, th2dd=-40.0, tex=10.0)
    m = EXAMPLE.replace(**{k: np.full(d, float(getattr(EXAMPLE, k))) for k in FIELD_NAMES})
    m = m.replace(R2=np.linspace(3.5, 4.5, d))
    tracemalloc.start()
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            figures(m, n=n, cf=0.05, scene=scene)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak / (d * n) <= BYTES_PER_POSITION, peak / (d * n)


def _spec(name: str) -> dict:
    return tomllib.loads((DECKS / name).read_text(), parse_float=Decimal)


@pytest.mark.parametrize("deck, table, read", [
    ("sweep.toml", "sweep", "sielaff.tools.spec_sweep:sweep_of"),
    ("tolerance.toml", "tolerance", "sielaff.tools.tolerance:read_tolerance"),
    ("synth.toml", "synthesis", "sielaff.tools.synth:read_synthesis"),
])
def test_angles_past_the_bound_are_refused_by_each_reader(deck, table, read):
    import importlib

    module, _, fn = read.partition(":")
    reader = getattr(importlib.import_module(module), fn)
    spec = _spec(deck)
    spec[table]["angles"] = MAX_ANGLES
    reader(spec, "s.toml")  # the bound itself is taken
    spec[table]["angles"] = MAX_ANGLES + 2
    with pytest.raises(PunchError, match=f"angles = {MAX_ANGLES + 2}.*{MAX_ANGLES}") as e:
        reader(spec, "s.toml")
    assert "\n" not in str(e.value)


def test_one_tolerance_sample_has_no_spread_and_is_refused():
    from sielaff.design.tolerance import tolerance
    from sielaff.tools.tolerance import read_tolerance

    spec = _spec("tolerance.toml")
    spec["tolerance"]["n"] = 1
    with pytest.raises(PunchError, match="n = 1"):
        read_tolerance(spec, "s.toml")
    with pytest.raises(ValueError, match="one sample has no spread"):
        tolerance(EXAMPLE, {"R2": 0.01}, n=1)


def test_synthesis_sizes_are_refused_before_any_work():
    pytest.importorskip("scipy")
    from sielaff.synthesis.function import MAX_SAMPLES, function
    from sielaff.synthesis.path import MAX_STARTS, path

    start = time.process_time()
    with pytest.raises(ValueError, match=f"samples = {10**8}.*{MAX_SAMPLES}"):
        function(np.log10, (1.0, 2.0), (45.0, 90.0), (135.0, 90.0), samples=10**8)
    with pytest.raises(ValueError, match=f"starts = {10**9}.*{MAX_STARTS}"):
        path([(1.0, 2.0), (2.0, 3.0), (3.0, 3.5), (4.0, 3.0), (5.0, 2.0)], starts=10**9)
    assert time.process_time() - start < 1.0  # refused, not begun
