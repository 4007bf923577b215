"""The slider-crank driven by a motor: ``simulate`` against an independent integration
of its reduced equation of motion, (J + F) th'' + J'(th) th'^2 / 2 = M(th') + Q(th), with
J, J' and the generalized force Q of gravity, the slider force and a spring from sympy's
closed form (tests/slider_reference.py), integrated by solve_ivp at rtol 1e-13."""

from __future__ import annotations

import math

import numpy as np
import pytest

import slider_reference as ref
from sielaff import SLIDER_EXAMPLE, Motor, SliderCrankScene, Spring, simulate
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


def test_simulate_refuses_a_crank_that_cannot_turn_and_a_four_bar_scene():
    from sielaff import Scene

    with pytest.raises(SimulationError, match="the crank cannot turn a full revolution"):
        simulate(SLIDER_EXAMPLE.replace(R3=2.5, offset=1.0), Motor.linear(300.0, 80.0))
    with pytest.raises(SimulationError, match="is not a slider-crank's Scene"):
        simulate(SLIDER_EXAMPLE, Motor.linear(300.0, 80.0), scene=Scene())
