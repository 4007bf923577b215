"""The optional compiled backend (engine.compiled, numba) against the numpy steps: every
result within 1E-12 of the steps relative to the largest magnitude of that output, on
drawn linkages of every kind and both branches; refusals for what it does not cover."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sielaff.engine import RESULTS, AssemblyWarning, Load, analyze
from sielaff.mechanism import EXAMPLE

pytest.importorskip("numba")

MECHS = st.builds(
    lambda r, w, zi, adel, rg, th2d: EXAMPLE.replace(
        R1=r[0], R2=r[1], R3=r[2], R4=r[3], W2=w[0], W3=w[1], W4=w[2], ZI3=zi[0], ZI4=zi[1],
        ADEL2=adel[0], ADEL3=adel[1], ADEL4=adel[2], RG2=rg[0], RG3=rg[1], RG4=rg[2],
        TH2D=th2d),
    st.tuples(*[st.floats(0.5, 20.0)] * 4), st.tuples(*[st.floats(0.1, 20.0)] * 3),
    st.tuples(*[st.floats(0.0, 3.0)] * 2), st.tuples(*[st.floats(-180.0, 180.0)] * 3),
    st.tuples(*[st.floats(0.0, 10.0)] * 3),
    st.one_of(st.floats(-300.0, -0.5), st.floats(0.5, 300.0)))


def _compare(m, th, branch="open", tex=0.0):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AssemblyWarning)
        ref = analyze(m, th, tex=tex, branch=branch)
        got = analyze(m, th, tex=tex, branch=branch, backend="numba")
    assert got.not_assembled == ref.not_assembled
    for name in RESULTS:
        a, b = got[name], ref[name]
        assert np.array_equal(np.isnan(a), np.isnan(b)), name
        ok = ~np.isnan(b) & np.isfinite(b)
        if not ok.any():
            continue
        if name.startswith("D") and name[1:] in got:
            mag = ref[name[1:]][ok]
            # a direction of a vector zero to roundoff (or whose square underflows): none
            big = (mag > 1e-9 * mag.max()) & (mag > 1e-150)
            diff = (a[ok] - b[ok] + 180.0) % 360.0 - 180.0
            assert np.max(np.abs(diff[big]), initial=0.0) < 1e-7, name
        else:
            scale = np.max(np.abs(b[ok]))
            # below 1E-150 a component's square underflows: the loop's magnitudes go to 0
            assert np.max(np.abs(a[ok] - b[ok])) <= 1e-12 * scale + 1e-150, name


def test_the_example_and_both_branches():
    th = np.arange(0.0, 720.0, 0.37) - 180.0
    _compare(EXAMPLE, th)
    _compare(EXAMPLE, th, "crossed", tex=150.0)


@settings(max_examples=150, derandomize=True, deadline=None)
@given(MECHS, st.sampled_from(["open", "crossed"]))
def test_drawn_linkages_every_kind(m, branch):
    _compare(m, np.linspace(-30.0, 390.0, 211), branch)


def test_out_and_shapes():
    th = np.linspace(0.0, 360.0, 24).reshape(4, 6)
    out = {name: np.empty((4, 6)) for name in ("TORQ", "SHAK")}
    r = analyze(EXAMPLE, th, out=out, backend="numba")
    assert r["TORQ"] is out["TORQ"]
    np.testing.assert_allclose(out["TORQ"], analyze(EXAMPLE, th, ["TORQ"])["TORQ"],
                               rtol=0, atol=1e-12 * 2000)


@pytest.mark.parametrize("kwargs, match", [
    (dict(th2dd=-40.0), "1966 scene"), (dict(gravity="down"), "1966 scene"),
    (dict(loads=[Load(3, fx=1.0)]), "1966 scene"), (dict(tex=lambda a: a), "constant"),
])
def test_refusals_name_what_is_not_covered(kwargs, match):
    with pytest.raises(ValueError, match=match):
        analyze(EXAMPLE, [10.0], backend="numba", **kwargs)
    with pytest.raises(ValueError, match="one design"):
        analyze(EXAMPLE.replace(R4=np.array([11.0, 12.0])), [10.0], backend="numba")
    with pytest.raises(ValueError, match="turning crank"):
        analyze(EXAMPLE.replace(TH2D=0.0), [10.0], backend="numba")
    with pytest.raises(ValueError, match="RESULTS"):
        analyze(EXAMPLE, [10.0], ["FG4X"], backend="numba")
