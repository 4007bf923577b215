"""Motor sizing (issue 33, item 3): the figures ``simulate`` prints, checked by identities
that use none of :mod:`sielaff.dynamics.sizing`'s code.

* In a periodic steady state the motor's mean power is what the losses take: zero for a
  linkage without losses, the friction losses' mean with pin friction (the engine's
  PLOSS outputs, themselves checked against Newton-Euler in test_simulate_friction.py).
* The mean speed is the time average 2 pi / period; the RMS torque is the square root of
  the mean square by Simpson's rule over time.
* The warnings are drawn both ways: a motor that is driven by the linkage (the power
  negative; an induction motor above its synchronous speed) is named, one that never is
  has no warning.
* The CLI says it in the unit system in force (no rad/sec in SI), the plot's axis is
  time, ``to_frame`` holds the samples, and results computed a block at a time are those
  of one block.
"""

from __future__ import annotations

import importlib
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from sielaff import EXAMPLE, PinFriction, Scene, Spring

pytest.importorskip("scipy")
from scipy.integrate import simpson  # noqa: E402

from sielaff.dynamics import Motor, simulate  # noqa: E402
from sielaff.dynamics.sizing import sizing, sizing_lines  # noqa: E402

S = importlib.import_module("sielaff.dynamics.simulate")
DECKS = Path(__file__).resolve().parents[1] / "decks"
LINEAR = Motor.linear(2000.0, 55.0)
FRICTION = Scene(friction=PinFriction(0.1, 0.25),
                 elements=[Spring((1, 18.0, 0.0), (4, 6.0, 0.0), 20.0, 8.0)])
LOSSES = ["PLOSS_O2", "PLOSS_A", "PLOSS_B", "PLOSS_O4"]


def _mean(r, x):
    return simpson(x, x=r["t"]) / (r["t"][-1] - r["t"][0])


def test_a_lossless_steady_state_takes_no_mean_power():
    r = simulate(EXAMPLE, LINEAR, flywheel=7.41, speed0=50.0, steady=True)
    s = sizing(r)
    assert abs(s["POWER_MEAN"]) < 1e-5 * s["POWER_MAX"]
    assert s["SPEED_MEAN"] == pytest.approx(2.0 * math.pi / r["t"][-1], rel=1e-12)
    assert s["MOTOR_RMS"] == pytest.approx(math.sqrt(_mean(r, r["MOTOR"] ** 2)), rel=1e-4)
    assert s["SPEED_MIN"] == np.min(r["TH2D"]) and s["SPEED_MAX"] == np.max(r["TH2D"])
    assert s["FLUCTUATION"] == pytest.approx(
        (s["SPEED_MAX"] - s["SPEED_MIN"]) / s["SPEED_MEAN"], rel=1e-12)
    assert "START_PEAK" not in s  # a steady state has no start


def test_with_friction_the_mean_power_is_the_mean_friction_loss():
    # rtol 1e-10: the flywheel's kinetic energy (some 11,000 in-lb) is 90 times the work
    # of a revolution, and at the default 1e-8 its integration error is 1e-4 of the mean
    # power (measured: -0.118 in-lb/sec of 1075; 0.011 at 1e-10)
    r = simulate(EXAMPLE, LINEAR, flywheel=7.41, scene=FRICTION, speed0=50.0, steady=True,
                 outputs=LOSSES, rtol=1e-10)
    s = sizing(r)
    loss = _mean(r, sum(r[n] for n in LOSSES))
    assert loss > 0.1 * s["POWER_MEAN"]  # the losses are the whole of it, not a share
    assert s["POWER_MEAN"] == pytest.approx(loss, rel=5e-5)
    assert s["MOTOR_MEAN"] == pytest.approx(_mean(r, r["MOTOR"]), rel=1e-4)


def test_a_motor_driven_by_the_linkage_is_named_and_one_that_never_is_is_not():
    r = simulate(EXAMPLE, LINEAR, flywheel=7.41, speed0=50.0, steady=True)
    s = sizing(r)
    assert s["POWER_MIN"] < 0.0
    assert len(s["warnings"]) == 1 and "runs as a generator" in s["warnings"][0]
    # a constant torque against friction: the power stays positive, nothing to say
    r = simulate(EXAMPLE, Motor.constant(40.0), flywheel=7.41, scene=FRICTION,
                 speed0=50.0, steady=True)
    s = sizing(r)
    assert s["POWER_MIN"] > 0.0 and s["warnings"] == []


def test_an_induction_motor_above_its_synchronous_speed_is_named_with_its_slip():
    motor = Motor.induction(50.0, 54.0, 300.0, 55.0)
    r = simulate(EXAMPLE, motor, flywheel=7.41, speed0=54.0, steady=True)
    s = sizing(r)
    above = np.count_nonzero(r["TH2D"] > 55.0)
    assert 0 < above < len(r["TH2D"])  # the case is drawn: above it part of the time
    assert s["SLIP"] == pytest.approx((55.0 - s["SPEED_MEAN"]) / 55.0, rel=1e-12)
    assert len(s["warnings"]) == 1 and "above the synchronous speed 55" in s["warnings"][0]


def test_a_transient_sizes_over_its_last_revolution_and_keeps_the_start_up_peak():
    r = simulate(EXAMPLE, LINEAR, flywheel=7.41, speed0=0.0, revolutions=5)
    s = sizing(r)
    assert s["START_PEAK"] == 2000.0  # at rest the linear motor gives its stall torque
    last = r["ATH2"] >= r["ATH2"][-1] - 360.0
    assert s["MOTOR_MAX"] >= np.max(r["MOTOR"][last]) and s["MOTOR_MAX"] < 200.0
    assert s["window"].startswith("the last revolution")
    lines = sizing_lines(r)
    assert all(line.endswith((" in-lb", " in-lb/sec", " rad/sec")) for line in lines[1:]
               if ":" in line and "fluctuation" not in line and "warning" not in line)


def test_the_cli_speaks_si_in_si(tmp_path):
    spec = (DECKS / "friction.toml").read_text().replace('units = "in-lb-sec"',
                                                         'units = "SI"')
    spec = spec.replace("revolutions = 20", "revolutions = 3")
    (tmp_path / "si.toml").write_text(spec)
    p = subprocess.run([sys.executable, "-m", "sielaff", "simulate", "si.toml", "-o",
                        "si.csv"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    header = (tmp_path / "si.csv").read_text().splitlines()[0]
    assert header == "t[s],ATH2[deg],TH2D[rad/s],TH2DD[rad/s^2],MOTOR[N m],TORQ[N m]"
    assert "rad/sec" not in p.stderr and "in-lb" not in p.stderr
    assert "RMS torque (the continuous rating): " in p.stderr and " N m\n" in p.stderr
    assert "mean power: " in p.stderr and " W\n" in p.stderr


def test_the_plot_is_against_time():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sielaff.tools.simulate import draw

    r = simulate(EXAMPLE, LINEAR, flywheel=7.41, speed0=0.0, revolutions=2,
                 outputs=["TORQ"])
    fig = plt.figure()
    draw(fig, r)
    axes = fig.get_axes()
    assert axes[-1].get_xlabel() == "time t [s]"
    assert np.array_equal(axes[0].get_lines()[0].get_xdata(), r["t"])
    plt.close(fig)


def test_to_frame():
    pytest.importorskip("pandas")
    r = simulate(EXAMPLE, LINEAR, flywheel=7.41, speed0=50.0, revolutions=1,
                 outputs=["TORQ"])
    f = r.to_frame()
    assert f.index.name == "t" and np.array_equal(f.index.to_numpy(), r["t"])
    assert list(f.columns) == ["ATH2", "TH2D", "TH2DD", "MOTOR", "TORQ"]
    assert f.attrs["units"]["TH2D"] == "rad/sec" and f.attrs["units"]["TORQ"] == "in-lb"
    assert f.attrs["sizing"]["MOTOR_RMS"] == sizing(r)["MOTOR_RMS"]


def test_results_a_block_at_a_time_are_the_results_in_one_block(monkeypatch):
    kw = dict(flywheel=7.41, scene=FRICTION, speed0=50.0, revolutions=0.5,
              outputs=["TORQ"], per_revolution=360)
    whole = simulate(EXAMPLE, LINEAR, **kw)
    monkeypatch.setattr(S, "SAMPLE_BLOCK", 37)
    blocks = simulate(EXAMPLE, LINEAR, **kw)
    assert len(whole["t"]) > 3 * 37
    for name in whole:  # the tables' sums are BLAS's: their last bits go with the size
        peak = np.max(np.abs(whole[name]))
        assert np.allclose(whole[name], blocks[name], rtol=1e-13, atol=1e-13 * peak), name
