"""The periodic steady state: found from a guess on either side, refused where none
exists, and its mean speed the time average (issue 32, item 8).

The steady state is checked by another path of the code it does not use: a transient
run from its start speed must come back to that speed after each revolution.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from sielaff import EXAMPLE, Scene

pytest.importorskip("scipy")
from sielaff.dynamics.motor import Motor  # noqa: E402
from sielaff.dynamics.simulate import SimulationError, simulate  # noqa: E402

#: A 40 lb coupler under gravity on a DC shunt motor: the crank stalls over the hump from
#: a slow start (1 rad/sec), gains speed from 5, and has one steady state near 60.
HEAVY = EXAMPLE.replace(W3=40.0)
MOTOR = Motor.linear(20.0, 60.0)


def _steady(speed0: float):
    return simulate(HEAVY, MOTOR, flywheel=7.41, scene=Scene(gravity="down"), speed0=speed0,
                    steady=True)


def test_the_same_steady_state_from_a_guess_that_stalls_gains_or_is_close():
    runs = [_steady(s) for s in (1.0, 5.0, 60.0)]
    starts = [float(r["TH2D"][0]) for r in runs]
    assert max(starts) - min(starts) <= 1e-7 * max(starts), starts
    # from 1 rad/sec the crank does stall within a revolution (the search went up)
    stalled = simulate(HEAVY, MOTOR, flywheel=7.41, scene=Scene(gravity="down"), speed0=1.0,
                       revolutions=1)
    assert stalled.stalled


def test_the_steady_state_repeats_in_a_transient_run():
    r = _steady(5.0)
    w0 = float(r["TH2D"][0])
    t = simulate(HEAVY, MOTOR, flywheel=7.41, scene=Scene(gravity="down"), speed0=w0,
                 revolutions=3, per_revolution=360)
    assert t.finished and not t.stalled
    w, th = t["TH2D"], np.radians(t["ATH2"])
    for k in (1, 2, 3):  # the speed at each whole revolution is the start speed
        i = int(np.argmin(np.abs(th - th[0] - 2.0 * math.pi * k)))
        assert w[i] == pytest.approx(w0, rel=1e-5), (k, w[i], w0)


def test_the_mean_it_prints_is_the_time_average():
    r = _steady(5.0)
    period = float(r["t"][-1])
    mean = float(re.search(r"mean speed ([0-9.e+-]+) rad/sec", r.message).group(1))
    assert mean == pytest.approx(2.0 * math.pi / period, rel=1e-5)
    # the time average of TH2D over the period (its integral is the revolution, 2 pi)
    assert np.trapezoid(r["TH2D"], r["t"]) / period == pytest.approx(mean, rel=1e-5)
    # which is not the average over crank angle (each sample an equal angle)
    assert abs(float(np.mean(r["TH2D"])) - mean) > 1e-4 * mean


def test_a_motor_that_gains_every_revolution_has_no_steady_state():
    """A constant torque with nothing to dissipate it: every revolution gains 2 pi 500
    in-lb of energy, so the speed only grows; no steady state is reported."""
    with pytest.raises(SimulationError, match="gains speed every revolution"):
        simulate(EXAMPLE, Motor.constant(500.0), flywheel=7.41, speed0=50.0, steady=True)
