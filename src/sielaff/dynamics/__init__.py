"""Forward dynamics: the crank driven by a motor (docs/effects.md).

``simulate(mechanism, motor, ...)`` integrates the one-degree-of-freedom equation of
motion of the whole linkage with the engine's kinetostatics; ``Motor`` gives the common
speed-torque curves.  Needs scipy (the ``dynamics`` extra) when a simulation runs; the
module imports without it.
"""

from sielaff.dynamics.motor import Motor
from sielaff.dynamics.simulate import Simulation, SimulationError, simulate

__all__ = ["Motor", "Simulation", "SimulationError", "simulate"]
