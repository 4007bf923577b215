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
* ``SliderCrank``, ``SLIDER_EXAMPLE``, ``SliderCrankScene``: the slider-crank
  (``sielaff.slider_crank``; docs/mechanisms.md), analysed by the same ``analyze`` with
  its own Scene (gravity, loads, the slider force ``fex``, springs and dampers);
  ``InvertedSliderCrank``, ``WattII``, ``StephensonIII`` and their examples, and any
  ``Linkage`` of a crank and dyads (``Topology``, ``Crank``, ``Pivot``, ``Point``,
  ``Guide``, ``RRR``, ``RRP``, ``PRR``, ``RPR``; ``sielaff.linkage``);
  ``scene_for(mechanism)`` is the Scene type of any of them.
* ``linkage_class(mechanism)``: which four-bar it is (crank-rocker, double-crank, ...),
  its Grashof margin and the input's toggle limits (``sielaff.engine.classify``).
* ``reachable(mechanism, n)``, ``point_motion(mechanism, ath2, link, r, angle)``: crank
  angles a linkage can reach; the path, velocity and acceleration of any point.
* ``flywheel(mechanism, cf)``, ``balance(mechanism)``, ``bearings(mechanism)``: design
  answers (``sielaff.design``, docs/design.md).
* ``simulate(mechanism, motor, ...)``, ``Motor``: the crank driven by a motor, forward
  dynamics (``sielaff.dynamics``, docs/effects.md; needs scipy, the ``dynamics`` extra).
* ``load_spec(path) -> Spec``: a TOML spec read as every command reads it (its
  mechanism, scene, range cards and motor); a bad spec is a ValueError naming its key.
* ``__version__``.

docs/architecture.md shows how the package is laid out.
"""

from sielaff.emulator.cards import Deck, DeckError, read_deck
from sielaff.mechanism import EXAMPLE, Mechanism
from sielaff.version import __version__

__all__ = ["EXAMPLE", "INVERTED_EXAMPLE", "PRR", "RPR", "RRP", "RRR",
           "STEPHENSON_EXAMPLE", "WATT_EXAMPLE", "AssemblyWarning", "Crank", "Damper", "Deck",
           "DeckError", "FrictionWarning", "Guide", "InvertedSliderCrank", "Linkage",
           "Load", "Mechanism", "Motor", "PinFriction", "Pivot", "Point", "Results",
           "SLIDER_EXAMPLE", "Scene", "SliderCrank", "SliderCrankScene", "Spring",
           "StephensonIII", "Topology", "WattII", "scene_for", "slider_balance",
           "__version__", "analyze", "balance", "bearings", "flywheel", "linkage_class",
           "load_spec", "point_motion", "reachable", "read_deck", "simulate"]


def load_spec(path: str):
    """The spec at ``path`` (``*.toml``, docs in ``sielaff help spec``) as the commands
    read it: a ``Spec`` with ``mechanism`` (in its unit system), ``scene``, ``ranges``
    ((THZERO, DELTA, THMAX) per range card, deg) and ``motor`` (``[motor]`` read as
    ``simulate`` reads it: Motor, flywheel, revolutions, steady, speed, method, rtol; None
    without one).  A spec of another ``[linkage] kind`` gives that kind (a ``SliderCrank``,
    an ``InvertedSliderCrank``, a ``WattII``, a ``StephensonIII``) and its Scene.
    A spec that cannot be read is a ValueError in one line naming the file and key."""
    from sielaff.tools.common import CommandError, read_spec, read_spec_deck
    from sielaff.tools.kinds import other_kinds
    from sielaff.tools.spec import PunchError, Spec

    try:
        deck, scene = read_spec_deck(path, other_kinds())
        spec = read_spec(path)
        motor = None
        if "motor" in spec:
            from sielaff.tools.simulate import motor_of

            motor = motor_of(spec, path, deck.mechanism.units)
    except (CommandError, PunchError) as exc:
        raise ValueError(str(exc)) from None
    return Spec(path, deck.mechanism, scene, tuple(tuple(r) for r in deck.ranges), motor)


def __getattr__(name: str):
    # The engine pulls in numpy; the emulator's command line does not need it.
    if name in ("analyze", "Results", "AssemblyWarning", "Load", "Scene", "linkage_class",
                "reachable", "point_motion", "PinFriction", "Spring", "Damper",
                "FrictionWarning", "SliderCrankScene"):
        from sielaff import engine

        return getattr(engine, name)
    if name in ("SliderCrank", "SLIDER_EXAMPLE"):
        from sielaff import slider_crank

        return getattr(slider_crank, name)
    if name in ("InvertedSliderCrank", "INVERTED_EXAMPLE"):
        from sielaff import inverted_slider_crank

        return getattr(inverted_slider_crank, name)
    if name in ("WattII", "StephensonIII", "WATT_EXAMPLE", "STEPHENSON_EXAMPLE"):
        from sielaff import sixbar

        return getattr(sixbar, name)
    if name in ("Linkage", "Topology", "Crank", "Pivot", "Point", "Guide", "RRR", "RRP",
                "PRR", "RPR"):
        from sielaff import linkage

        return getattr(linkage, name)
    if name == "scene_for":
        from sielaff.engine import scene_for

        return scene_for
    if name in ("flywheel", "balance", "bearings", "slider_balance"):
        from sielaff import design

        return getattr(design, name)
    if name in ("simulate", "Motor"):
        from sielaff import dynamics

        return getattr(dynamics, name)
    if name in ("engine", "design", "dynamics", "synthesis", "emulator", "quantities"):
        import importlib  # sielaff.synthesis.rank after a bare ``import sielaff``

        return importlib.import_module(f"sielaff.{name}")
    raise AttributeError(f"module 'sielaff' has no attribute {name!r}")
