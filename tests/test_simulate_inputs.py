"""simulate's inputs, each checked before any work and refused in one line; a run that
cannot finish in its budget stopped with why (issue 32, families 1, 4 and 5)."""

from __future__ import annotations

import importlib
import math

import pytest

from sielaff import EXAMPLE, PinFriction, Scene

pytest.importorskip("scipy")
from sielaff.dynamics.motor import Motor  # noqa: E402
from sielaff.dynamics.simulate import SimulationError, simulate  # noqa: E402

#: The module itself (the package exports the function under its name).
S = importlib.import_module("sielaff.dynamics.simulate")

MOTOR = Motor.linear(2000.0, 55.0)


@pytest.mark.parametrize("kwargs, words", [
    ({"steady": "no"}, "steady = 'no': True or False"),
    ({"atol": math.nan}, "atol = nan: a positive number"),
    ({"atol": -1.0}, "atol = -1.0: a positive number"),
    ({"t_max": -1.0}, "t_max = -1.0: a positive number"),
    ({"t_max": math.inf}, "t_max = inf: a positive number"),
])
def test_bad_arguments_are_one_line(kwargs, words):
    with pytest.raises(SimulationError, match=words.replace("(", r"\(")) as e:
        simulate(EXAMPLE, MOTOR, flywheel=7.41, revolutions=1, **kwargs)
    assert "\n" not in str(e.value)


def test_no_mechanism_is_one_line():
    with pytest.raises(SimulationError, match="mechanism = None: a sielaff.Mechanism"):
        simulate(None, MOTOR)


def test_a_motor_that_turns_nan_is_named():
    def motor(w):  # fine at the start, NaN once the crank passes 52 rad/sec
        return 2000.0 * (1.0 - w / 55.0) if w < 52.0 else math.nan

    with pytest.raises(SimulationError, match="the motor's torque at .* rad/sec is nan"):
        simulate(EXAMPLE, motor, flywheel=7.41, speed0=50.0, revolutions=5)


def test_the_cpu_budget_stops_a_run_that_goes_through_the_engine(monkeypatch):
    monkeypatch.setattr(S, "MAX_CPU_SECONDS", 0.2)
    with pytest.raises(SimulationError, match=r"more than 0.2 s of CPU after \d+ "
                                              "evaluations .* by the engine at every state"):
        simulate(EXAMPLE, MOTOR, flywheel=7.41, scene=Scene(friction=PinFriction(0.1, 0.25)),
                 speed0=50.0, revolutions=50, tables=False)


def test_the_advice_never_names_the_method_in_use(monkeypatch):
    monkeypatch.setattr(S, "MAX_EVALUATIONS", 50)
    for method in ("LSODA", "RK45"):
        with pytest.raises(SimulationError, match="more than 50 evaluations") as e:
            simulate(EXAMPLE, MOTOR, flywheel=7.41, speed0=50.0, revolutions=5, method=method)
        advice = str(e.value).split("wants ", 1)[1]
        assert f"'{method}'" not in advice
