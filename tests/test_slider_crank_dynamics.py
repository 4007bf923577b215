"""The slider-crank driven by a motor: ``simulate`` against an independent integration
of its reduced equation of motion, (J + F) th'' + J'(th) th'^2 / 2 = M(th') + Q(th), with
J, J' and the generalized force Q of gravity, the slider force and a spring from sympy's
closed form (tests/slider_reference.py), integrated by solve_ivp at rtol 1e-13."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

import slider_reference as ref
from sielaff import SLIDER_EXAMPLE, Damper, Motor, SliderCrankScene, Spring, simulate
from sielaff.dynamics.simulate import SimulationError
from sielaff.quantities import G

pytest.importorskip("scipy")


def _case():
    m = SLIDER_EXAMPLE.replace(offset=0.4, ADEL2=8.0, TH2D=60.0)
    p = (m.R2 + m.R3 + 3.0, 2.5)
    spring = (p[0], p[1], 40.0, 2.0)
    scene = SliderCrankScene(
        gravity="down", fex=-120.0,
        elements=(Spring((1, math.hypot(*p), math.degrees(math.atan2(p[1], p[0]))),
                         (4, 0.0, 0.0), 40.0, 2.0),))
    return m, scene, spring


@pytest.mark.parametrize("tables", [True, False], ids=["tables", "engine"])
def test_simulate_is_the_reduced_equation_integrated(tables):
    from scipy.integrate import solve_ivp

    m, scene, spring = _case()
    motor = Motor.linear(300.0, 80.0)
    fw = 0.05
    r = simulate(m, motor, flywheel=fw, scene=scene, revolutions=2, rtol=1e-12, atol=1e-12,
                 tables=tables)
    assert r.finished and not r.stalled
    J, dJ, Q = ref.reduced(m, gravity=(0.0, -G), fex=-120.0, spring=spring)

    def rhs(_t, y):
        th, w = y
        return [w, (float(motor(w)) + Q(th) - 0.5 * dJ(th) * w * w) / (J(th) + fw)]

    sol = solve_ivp(rhs, (0.0, float(r["t"][-1])), [0.0, m.TH2D], method="DOP853",
                    rtol=1e-13, atol=1e-13, t_eval=r["t"])
    # both at 1e-12: they agree to about 1e-11 (measured 0.9e-11 and 1.1e-11)
    np.testing.assert_allclose(r["TH2D"], sol.y[1], rtol=3e-11)
    np.testing.assert_allclose(np.radians(r["ATH2"]), sol.y[0], rtol=0, atol=3e-11)
    # the energy balance: motor work = change of kinetic + potential energy
    th, w = np.radians(r["ATH2"]), r["TH2D"]
    ke = np.array([0.5 * (J(x) + fw) * v * v for x, v in zip(th, w)])
    work = np.concatenate([[0.0], np.cumsum(0.5 * (r["MOTOR"][1:] * w[1:] + r["MOTOR"][:-1]
                                                    * w[:-1]) * np.diff(r["t"]))])
    qwork = np.concatenate([[0.0], np.cumsum(0.5 * np.array(
        [Q(a) + Q(b) for a, b in zip(th[:-1], th[1:])]) * np.diff(th))])
    scale = float(np.max(np.abs(work)))
    assert np.max(np.abs(work + qwork - (ke - ke[0]))) < 2e-4 * scale  # trapezoids


#: (tables, method, the bound on the angle's and the speed's error [rad, of the speed's
#: largest]): the global error of 14 swings at rtol 1e-11, measured 5.6e-10 (LSODA) and
#: 5.4e-11 (DOP853) on one machine.
FREE = [(True, "LSODA", 2e-9), (False, "LSODA", 2e-9), (True, "DOP853", 2e-10)]
FREE_TIMES = np.linspace(0.0, 0.25, 251)


@functools.lru_cache(maxsize=1)
def _free():
    """The free slider-crank (no motor: a spring and a damper from a frame point to the
    slider, a constant FEX, released from rest at THETA 2 = 100 deg), its Scene, and the
    independent reduced equation with the damper's -c (dL/dth)^2 th' integrated by
    DOP853 at 1e-13 (J, Q, dL/dth from sympy's closed form)."""
    from scipy.integrate import solve_ivp

    m, _, spring = _case()
    p, c = spring[:2], 0.05
    at = (1, math.hypot(*p), math.degrees(math.atan2(p[1], p[0])))
    scene = SliderCrankScene(fex=-20.0, elements=(Spring(at, (4, 0.0, 0.0), 40.0, 2.0),
                                                  Damper(at, (4, 0.0, 0.0), c)))
    J, dJ, Q = ref.reduced(m, fex=-20.0, spring=spring)
    dL = ref.length_rate(m, p)

    def rhs(_t, y):
        th, w = y
        return [w, (Q(th) - c * dL(th) ** 2 * w - 0.5 * dJ(th) * w * w) / J(th)]

    sol = solve_ivp(rhs, (0.0, 0.25), [math.radians(100.0), 0.0], method="DOP853",
                    rtol=1e-13, atol=1e-13, t_eval=FREE_TIMES, dense_output=True)
    return m, scene, sol, (J, Q, dL, c)


@pytest.mark.parametrize("tables, method, bound", FREE,
                         ids=["tables-LSODA", "engine-LSODA", "tables-DOP853"])
def test_a_free_slider_crank_swings_as_the_reduced_equation_says(tables, method, bound):
    """The free slider-crank (:func:`_free`) swings back and forth (it stops and turns
    back, counted); ``times`` samples it where asked, as the reduced equation does."""
    m, scene, sol, _ = _free()
    r = simulate(m, Motor.constant(0.0), scene=scene, speed0=0.0, start=100.0,
                 times=FREE_TIMES, rtol=1e-11, atol=1e-11, tables=tables, method=method)
    np.testing.assert_array_equal(r["t"], FREE_TIMES)
    turns = int(np.sum(np.diff(np.sign(r["TH2D"][1:])) != 0))
    assert turns >= 4 and "turned back" in r.message  # it swings: drawn, counted
    scale = float(np.max(np.abs(sol.y[1])))
    np.testing.assert_allclose(r["TH2D"], sol.y[1], rtol=0, atol=bound * scale)
    np.testing.assert_allclose(np.radians(r["ATH2"]), sol.y[0], rtol=0, atol=bound)


def test_the_free_swing_keeps_its_energy_balance():
    """The reference the swing is checked against obeys d(KE)/dt = Q th' - c L'^2 th'^2
    (the spring's and FEX's work less the damper's loss), by trapezoids on a fine grid:
    an error in the damper's term or in J would break it."""
    _, _, sol, (J, Q, dL, c) = _free()
    fine = np.linspace(0.0, 0.25, 5001)
    th, w = sol.sol(fine)
    ke = np.array([0.5 * J(x) * v * v for x, v in zip(th, w)])
    net = np.array([(Q(x) - c * dL(x) ** 2 * v) * v for x, v in zip(th, w)])
    work = np.concatenate([[0.0], np.cumsum(0.5 * (net[1:] + net[:-1]) * np.diff(fine))])
    loss = float(np.sum([c * dL(x) ** 2 * v * v for x, v in zip(th, w)]) * (fine[1] - fine[0]))
    assert loss > 0.05 * float(np.max(ke))  # the damper takes a share worth checking
    assert np.max(np.abs(ke - ke[0] - work)) < 1e-4 * float(np.max(ke))


def test_times_are_checked_in_one_line():
    for bad, says in ((np.array([0.0, 0.0]), "increasing"), ([0.1], "increasing"),
                      ([-1.0, 1.0], "increasing"), ("soon", "not 'soon'")):
        with pytest.raises(SimulationError, match=says):
            simulate(SLIDER_EXAMPLE, Motor.constant(0.0), times=bad)
    with pytest.raises(SimulationError, match="past t_max"):
        simulate(SLIDER_EXAMPLE, Motor.constant(0.0), times=[0.0, 2.0], t_max=1.0)
    with pytest.raises(SimulationError, match="not with steady"):
        simulate(SLIDER_EXAMPLE, Motor.constant(0.0), times=[0.0, 2.0], steady=True)


def test_simulate_refuses_a_crank_that_cannot_turn_and_a_four_bar_scene():
    from sielaff import Scene

    with pytest.raises(SimulationError, match="the crank cannot turn a full revolution"):
        simulate(SLIDER_EXAMPLE.replace(R3=2.5, offset=1.0), Motor.linear(300.0, 80.0))
    with pytest.raises(SimulationError, match="is not a slider-crank's Scene"):
        simulate(SLIDER_EXAMPLE, Motor.linear(300.0, 80.0), scene=Scene())
