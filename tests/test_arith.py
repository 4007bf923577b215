"""engine/arith.py: the operations a step uses beyond arithmetic, in their numpy forms
(the compiled backend's one-position forms are checked in tests/test_compiled.py)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from sielaff.engine.arith import mod360, owned, put

EDGES = [-360.0, -0.0, 0.0, 360.0, 720.0, -1e-300, -1e-20, -5e-324, 5e-324,
         719.9999999999999, 359.99999999999994, np.nextafter(-360.0, 0.0),
         np.nextafter(0.0, -1.0), np.nextafter(720.0, 0.0), 1e5, -1e5, 2.0**52, -2.0**60]


def _same(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return bool(np.array_equal(a, b, equal_nan=True)
                and np.array_equal(np.signbit(a), np.signbit(b)))


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-400.0, 800.0) | st.sampled_from(EDGES), min_size=1, max_size=50))
def test_mod360_is_np_mod_bit_for_bit(values):
    x = np.array(values)
    # an array with an element outside [0, 360) is reduced as np.mod reduces it (the
    # fast path for [-360, 720) included: drawn here in most examples)
    if not (x.min() >= 0.0 and x.max() < 360.0):
        assert _same(mod360(x), np.mod(x, 360.0)), x
    else:  # already there: returned as it is
        assert mod360(x) is x


def test_mod360_each_path_and_scalars():
    inside = np.array([0.0, 10.0, 359.5])
    near = np.array([-360.0, -1e-20, 0.0, 400.0, 719.9999999999999])
    far = np.array([-1e5, 3.0, 2.0**52])
    assert mod360(inside) is inside
    assert _same(mod360(near), np.mod(near, 360.0))
    assert _same(mod360(far), np.mod(far, 360.0))
    assert mod360(near)[1] == 360.0  # -1e-20 + 360 rounds to 360, as np.mod's
    for v in EDGES:
        got = mod360(np.float64(v))
        assert np.ndim(got) == 0
        if not 0.0 <= v < 360.0:
            assert _same(got, np.mod(v, 360.0)), v
    with np.errstate(invalid="ignore"):
        x = np.array([np.nan, 5.0, -3.0, np.inf])
        assert _same(mod360(x), np.mod(x, 360.0))
    assert mod360(np.array([])).size == 0


def test_put_and_owned():
    a = np.arange(4.0)
    assert put(a, -1.0, a > 1.5) is a and list(a) == [0.0, 1.0, -1.0, -1.0]
    assert owned(a) and not owned(1.0)
