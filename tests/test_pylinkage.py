"""An outside check of positions: pylinkage (an optional extra, `pip install
sielaff[check]`) builds each four-bar from its own parts, a crank and an RRR dyad that it
solves by circle intersection, and steps it; joint B must be where the engine puts it, on
either branch, for every kind of four-bar.

pylinkage keeps a dyad on the intersection nearest its last position, so it follows one
branch continuously from the B it starts at: that start is the engine's B at the first angle
(the only thing taken from the code under test), after which every position is pylinkage's.
A non-Grashof linkage is stepped inside one arc of its motion, short of the toggles, where the
two branches meet and "nearest" no longer tells them apart.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import sielaff
from sielaff.mechanism import EXAMPLE

pl = pytest.importorskip("pylinkage")

CASES = [  # R1, R2, R3, R4 (inches; the lengths are all that positions depend on)
    ("crank-rocker", (12.0, 4.0, 16.0, 12.0)),   # the report's example
    ("double-crank", (2.0, 4.0, 5.0, 4.5)),
    ("double-rocker", (6.0, 4.0, 2.0, 5.5)),
    ("rocker-crank", (6.0, 4.0, 5.0, 2.0)),
    ("triple-rocker", (10.0, 4.0, 5.0, 4.0)),
]


def _angles(m, n=200):
    """Degrees, increasing, where the linkage assembles: a whole turn, or the inside of the
    first arc between toggles (1% short of each end)."""
    c = sielaff.linkage_class(m)
    if c.turns_fully:
        return np.arange(n) * (360.0 / n)
    a, b = c.arcs[0]
    w = (b - a) % 360.0
    return a + np.linspace(0.01 * w, 0.99 * w, n)


@pytest.mark.parametrize("branch", ["open", "crossed"])
@pytest.mark.parametrize("kind, r", CASES, ids=[k for k, _ in CASES])
def test_joint_b_where_pylinkage_puts_it(kind, r, branch):
    m = EXAMPLE.replace(R1=r[0], R2=r[1], R3=r[2], R4=r[3])
    assert sielaff.linkage_class(m).kind == kind
    th = _angles(m)
    step = float(th[1] - th[0])
    ours = sielaff.point_motion(m, th, 4, m.R4, branch=branch)   # B: R4 along link 4
    o2, o4 = pl.Ground(0.0, 0.0), pl.Ground(m.R1, 0.0)
    crank = pl.Crank(anchor=o2, radius=m.R2, angular_velocity=math.radians(step),
                     initial_angle=math.radians(float(th[0])))
    dyad = pl.RRRDyad(crank.output, o4, distance1=m.R3, distance2=m.R4,
                      x=float(ours["X"][0]), y=float(ours["Y"][0]))
    linkage = pl.Linkage([o2, o4, crank, dyad])
    # pylinkage turns the crank, then reports: its k-th position is at th[k + 1].
    theirs = np.array([p[3] for p in linkage.step(iterations=len(th) - 1)], dtype=float)
    scale = max(r)
    np.testing.assert_allclose(theirs[:, 0], ours["X"][1:], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(theirs[:, 1], ours["Y"][1:], rtol=0, atol=1e-9 * scale)
