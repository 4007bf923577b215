"""design.peaks: the peaks a report prints, never a number past a toggle (issue 33).

The growth toward a toggle is checked here with no code of the module: at the toggles
sielaff.linkage_class names, the transmission angle is 0 or 180 deg (the coupler and the
rocker in line), and the driving torque taken ever nearer grows past every bound asked
for.  A crank-rocker has no toggle and every row is a number, the largest of the
revolution (a grid of its own here).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import DECKS
from sielaff import analyze, linkage_class
from sielaff.design.peaks import PEAKS, peaks
from sielaff.tools.common import load_scene


def _deck(name):
    return load_scene(str(DECKS / name), any_linkage=True)


@pytest.mark.filterwarnings("ignore::sielaff.AssemblyWarning")
@pytest.mark.parametrize("name", ["double-rocker.toml", "triple-rocker.toml"])
def test_a_linkage_with_toggles_gives_them_and_no_number(name):
    deck, scene = _deck(name)
    m = deck.mechanism
    c = linkage_class(m)
    toggles = sorted(float(t) for t in np.ravel(c.toggles) if np.isfinite(t))
    rows = peaks(m, scene, n=720)
    unbounded = [p for p in rows if p.unbounded]
    assert len(unbounded) == 8  # every force and torque row; GAMMA is bounded
    for p in unbounded:
        assert math.isnan(p.value) and math.isnan(p.at)
        assert sorted(p.toggles) == pytest.approx(toggles, abs=1e-9)
        assert all(min(g, 180.0 - g) < 1e-6 for g in p.gamma)
    # independently: the torque grows past any bound toward each toggle
    for t in toggles:
        inside = [a for a in (t + 1e-3, t - 1e-3)
                  if np.isfinite(analyze(m, a % 360.0, ["TORQ"], scene=scene)["TORQ"])]
        assert inside
        d = 1.0 if inside[0] > t else -1.0
        q = [abs(float(analyze(m, (t + d * e) % 360.0, ["TORQ"], scene=scene)["TORQ"]))
             for e in (1e-2, 1e-4, 1e-6)]
        assert q[1] > 10.0 * q[0] and q[2] > 10.0 * q[1], q
    gamma = [p for p in rows if p.name == "GAMMA"]
    assert len(gamma) == 2 and all(np.isfinite(p.value) for p in gamma)


@pytest.mark.parametrize("name", ["example.toml", "double-crank.toml", "friction.toml"])
def test_a_crank_that_turns_fully_gets_a_number_for_every_row(name):
    deck, scene = _deck(name)
    m = deck.mechanism
    rows = peaks(m, scene, n=3600)
    assert [p.label for p in rows] == [label for label, _, _ in PEAKS]
    th = np.arange(0.0, 360.0, 0.05)
    for p in rows:
        assert not p.unbounded and np.isfinite(p.value)
        v = analyze(m, th, [p.name], scene=scene)[p.name]
        how = dict((label, h) for label, _, h in PEAKS)[p.label]
        best = (np.max(np.abs(v)) if how == "maxabs" else np.min(v) if how == "min"
                else np.max(v))
        # the row's grid is 0.1 deg, this one 0.05: the peak within a hair of it
        assert abs(abs(p.value) - abs(best)) <= 1e-3 * abs(best) + 1e-9, p.label


def test_a_linkage_that_never_assembles_has_no_peaks():
    deck, scene = _deck("example.toml")
    m = deck.mechanism.replace(R3=1.0, R4=1.0)
    assert not linkage_class(m).turns_fully and not linkage_class(m).arcs
    assert peaks(m, scene) == []
