"""Design answers built on the engine: what its numbers are for.

The report ends on them ("AN EXAMPLE PROBLEM"): the bearings' loads and the arcs where a
bearing is never loaded ("ideal positions for the placement of oil grooves"), balancing
("This program could also be useful in attempting to balance such a mechanism"), and
the flywheel that a driving torque which changes sign calls for.

* :mod:`~sielaff.design.flywheel`  energy fluctuation and flywheel inertia
* :mod:`~sielaff.design.balance`   Berkof-Lowen counterweights on links 2 and 4
* :mod:`~sielaff.design.bearings`  per pin: peak load, directions on each member, arcs
  never loaded, load reversals
* :mod:`~sielaff.design.figures`   the figures a sweep compares, per design
* :mod:`~sielaff.design.sweep`     grids of designs, in process or on dask
* :mod:`~sielaff.design.tolerance` Monte Carlo of manufacturing deviations, with
  first-order sensitivities
* :mod:`~sielaff.design.slider_balance` a slider-crank's crank counterweight and the
  primary and secondary shaking force it leaves
* :mod:`~sielaff.design.kinds`     what the answers ask of a kind other than the four-bar

Every answer works on every kind the engine analyses (the slider-crank, the inverted
slider-crank, the six-bars, any ``Linkage``) but Berkof-Lowen balancing, which is the
four-bar's and refuses the others in one line.

This layer imports the engine, ``quantities`` and ``mechanism``; the commands in
``tools/`` import it (docs/architecture.md).  Equations and checks: docs/design.md.
"""

from sielaff.design.balance import balance, counterweights
from sielaff.design.bearings import Pin, bearings
from sielaff.design.flywheel import Flywheel, flywheel, flywheel_from_torque
from sielaff.design.slider_balance import SliderBalance, slider_balance
from sielaff.design.tolerance import Tolerance, tolerance

__all__ = ["Flywheel", "Pin", "SliderBalance", "Tolerance", "balance", "bearings",
           "counterweights", "flywheel", "flywheel_from_torque", "slider_balance", "tolerance"]
