"""The checks a design of plain Python floats takes without numpy (mechanism.plainly_valid
in the four-bar's and the slider-crank's validators, registry.Model.zero_seeds): each
gives the answer the array path gives the same values as numpy scalars, which take the
array path (a type not ``float``), on drawn values of every field and every switch."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sielaff.engine.fourbar import FOURBAR
from sielaff.mechanism import EXAMPLE, FIELD_NAMES, plainly_valid, validate
from sielaff.slider_crank import FIELD_NAMES as SLIDER_FIELDS
from sielaff.slider_crank import SLIDER_EXAMPLE, validate_slider

#: values on every side of the checks: the signs of zero, tiny, huge, not finite
EDGES = (0.0, -0.0, 5e-324, -5e-324, 1.0, -1.0, 1e308, -1e308, math.inf, -math.inf,
         math.nan)


def _outcome(check, design):
    try:
        check(design)
    except ValueError as e:
        return str(e)
    return None


def _same_as_arrays(check, example, name, value):
    """The validator's outcome for ``value`` as a float and as a numpy scalar."""
    plain = _outcome(check, example.replace(**{name: float(value)}))
    array = _outcome(check, example.replace(**{name: np.float64(value)}))
    assert plain == array, (name, value, plain, array)
    return plain is None


@pytest.mark.parametrize("check, example, names", [
    (validate, EXAMPLE, FIELD_NAMES), (validate_slider, SLIDER_EXAMPLE, SLIDER_FIELDS)],
    ids=["four-bar", "slider-crank"])
def test_each_field_plain_or_array_the_same_outcome(check, example, names):
    passed = failed = 0
    for name in names:
        for value in EDGES:
            ok = _same_as_arrays(check, example, name, value)
            passed, failed = passed + ok, failed + (not ok)
    # both sides drawn: values that pass and values refused
    assert passed >= len(names) and failed >= 3 * len(names), (passed, failed)


@settings(max_examples=300, deadline=None)
@given(name=st.sampled_from(FIELD_NAMES), value=st.floats(allow_nan=True,
                                                          allow_infinity=True))
def test_drawn_values_plain_or_array_the_same_outcome(name, value):
    _same_as_arrays(validate, EXAMPLE, name, value)


def test_plainly_valid_takes_only_plain_floats():
    # anything else goes the array path, whose message names it
    for value in (1, True, np.float64(1.0), np.array(1.0), "1.0", None):
        assert not plainly_valid(value, False, False)
    assert plainly_valid(1.0, True, True) and not plainly_valid(0.0, True, False)
    assert plainly_valid(-0.0, False, True) and not plainly_valid(-1.0, False, True)


def test_zero_seeds_plain_numbers_as_numpy_says():
    # every switch of the four-bar's effects given each value, plain and as an array
    candidates = sorted(FOURBAR.zero_candidates)
    zero = nonzero = 0
    for value in EDGES + (0, 1, True, False):
        plain = FOURBAR.zero_seeds(dict.fromkeys(candidates, value))
        array = FOURBAR.zero_seeds(dict.fromkeys(candidates, np.asarray(value)))
        assert plain == array, value
        zero, nonzero = zero + bool(plain), nonzero + (not plain)
    assert zero >= 3 and nonzero >= 3, (zero, nonzero)
