"""sielaff: Sielaff's 1966 crank-rocker program, emulated exactly, and a modern engine.

The public API, in one place (everything else is reached through its module):

* ``read_deck(path) -> Deck``, ``DeckError``: a card deck read with FORMAT(4F8.4)
  (``sielaff.emulator.cards``).
* ``Mechanism``, ``EXAMPLE``: the deck's parameters with the listing's names and units
  (``sielaff.mechanism``); ``Mechanism.replace(**fields)`` for sweeps.
* ``analyze(mechanism, ath2, outputs=None, *, scene=Scene(...)) -> Results``, ``Scene``,
  ``Load``, ``PinFriction``, ``Spring``, ``Damper``, ``AssemblyWarning``,
  ``FrictionWarning``: the modern numpy engine (``sielaff.engine``), with the
  effects a scene calls for (docs/effects.md).
* ``linkage_class(mechanism)``: which four-bar it is (crank-rocker, double-crank, ...),
  its Grashof margin and the input's toggle limits (``sielaff.engine.classify``).
* ``reachable(mechanism, n)``, ``point_motion(mechanism, ath2, link, r, angle)``: crank
  angles a linkage can reach; the path, velocity and acceleration of any point.
* ``flywheel(mechanism, cf)``, ``balance(mechanism)``, ``bearings(mechanism)``: design
  answers (``sielaff.design``, docs/design.md).
* ``simulate(mechanism, motor, ...)``, ``Motor``: the crank driven by a motor, forward
  dynamics (``sielaff.dynamics``, docs/effects.md; needs scipy, the ``dynamics`` extra).
* ``__version__``.

docs/architecture.md shows how the package is laid out.
"""

from sielaff.emulator.cards import Deck, DeckError, read_deck
from sielaff.mechanism import EXAMPLE, Mechanism
from sielaff.version import __version__

__all__ = ["EXAMPLE", "AssemblyWarning", "Damper", "Deck", "DeckError", "FrictionWarning",
           "Load", "Mechanism", "Motor", "PinFriction", "Results", "Scene", "Spring",
           "__version__", "analyze", "balance", "bearings", "flywheel", "linkage_class",
           "point_motion", "reachable", "read_deck", "simulate"]


def __getattr__(name: str):
    # The engine pulls in numpy; the emulator's command line does not need it.
    if name in ("analyze", "Results", "AssemblyWarning", "Load", "Scene", "linkage_class",
                "reachable", "point_motion", "PinFriction", "Spring", "Damper",
                "FrictionWarning"):
        from sielaff import engine

        return getattr(engine, name)
    if name in ("flywheel", "balance", "bearings"):
        from sielaff import design

        return getattr(design, name)
    if name in ("simulate", "Motor"):
        from sielaff import dynamics

        return getattr(dynamics, name)
    raise AttributeError(f"module 'sielaff' has no attribute {name!r}")
