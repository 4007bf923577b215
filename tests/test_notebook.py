"""docs/notebook.md runs as a notebook would: every python block, in order, in one
namespace; then what its comments claim is checked against the engine directly."""

from __future__ import annotations

import re

import numpy as np
import pytest

from conftest import ROOT

pytest.importorskip("pandas")


def test_the_notebook_page_runs_and_says_true_things():
    text = (ROOT / "docs" / "notebook.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) == 3
    ns: dict = {}
    for block in blocks:
        exec(compile(block, "docs/notebook.md", "exec"), ns)  # noqa: S102 (our own docs)
    from sielaff import EXAMPLE, Scene, analyze

    frame = ns["frame"]
    assert frame.index.name == "ATH2" and frame.attrs["units"]["TORQ"] == "in-lb"
    th = np.arange(0.0, 360.0, 5.0)
    torq = analyze(EXAMPLE, th, ["TORQ"], scene=Scene(gravity="down"))["TORQ"]
    np.testing.assert_array_equal(frame["TORQ"].to_numpy(), torq)
    assert ns["peak"] == th[np.argmax(np.abs(torq))]
    assert ns["si_frame"].attrs["units"] == {"TORQ": "N m", "FB34": "N", "ATH2": "deg"}
    designs = ns["designs"]
    assert len(designs) == 6 and designs.attrs["units"]["TORQ_PEAK"] == "in-lb"
    assert designs.attrs["units"]["R4"] == "in" and designs.attrs["units"]["KIND"] == "-"
    from sielaff.design.figures import figures

    m = EXAMPLE.replace(R4=designs["R4"].to_numpy(), W3=designs["W3"].to_numpy())
    np.testing.assert_allclose(designs["TORQ_PEAK"].to_numpy(),
                               figures(m, n=120)["TORQ_PEAK"], rtol=1e-12)
    assert ns["best"] == int(np.argmin(designs["TORQ_PEAK"].to_numpy()))


def test_to_frame_refuses_a_sweep_and_keeps_units_of_effect_parts():
    from sielaff import EXAMPLE, analyze

    r = analyze(EXAMPLE.replace(R4=np.array([11.0, 12.0])[:, None]), np.arange(0, 360, 90.0),
                ["TORQ"])
    with pytest.raises(ValueError, match="one design over the crank angles"):
        r.to_frame()
    f = analyze(EXAMPLE, [0.0, 90.0], ["TORQ_GRAVITY", "ASSEMBLED"], gravity="down").to_frame()
    assert f.attrs["units"]["TORQ_GRAVITY"] == "in-lb"
    assert f["ASSEMBLED"].dtype == bool


def test_rankings_and_tolerance_studies_are_frames_too():
    from sielaff import EXAMPLE
    from sielaff.design.tolerance import tolerance
    from sielaff.synthesis import rank

    cands = [EXAMPLE, EXAMPLE.replace(R4=11.0), EXAMPLE.replace(R4=13.0)]
    r = rank(cands, by=["TORQ_PEAK"], n=90)
    f = r.to_frame()
    assert list(f.index) == list(r.order) and list(f["RANK"]) == [1, 2, 3]
    np.testing.assert_array_equal(f["TORQ_PEAK"].to_numpy(), r.figures["TORQ_PEAK"][r.order])
    assert f.attrs["units"]["TORQ_PEAK"] == "in-lb" and f.attrs["units"]["GAMMA_MIN"] == "deg"
    t = tolerance(EXAMPLE, {"R4": 0.01}, n=50, seed=1, angles=90)
    tf = t.to_frame()
    assert tf.loc["TORQ_PEAK", "nominal"] == t.nominal["TORQ_PEAK"]
    assert tf.attrs["units"]["FOB_PEAK"] == "lb"
