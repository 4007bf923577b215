"""The Watt II and Stephenson III six-bars as models, and any :class:`~sielaff.Linkage`:
the linkage engine's steps for their topologies and one line per effect."""

from __future__ import annotations

from sielaff.engine.linkage_model import finish, friction_effect, kind_model
from sielaff.engine.registry import Model
from sielaff.linkage import Linkage, Topology
from sielaff.sixbar import StephensonIII, WattII

__all__ = ["STEPHENSON", "WATT", "linkage_for"]

_VECTORS = ("VA", "VB", "VC", "VD", "AA", "AB", "AC", "AD", "FOA", "FA32", "FB34", "FOB")


def _results(on: int) -> tuple[str, ...]:
    vectors = _VECTORS + (f"FC5{on}", "FD56", "FO6", "SHAK")
    return (("ATH2", "ATH3", "ATH4", "ATH5", "ATH6", "GAMMAB", "GAMMAD")
            + tuple(f"TH{k}D" for k in range(3, 7)) + tuple(f"TH{k}DD" for k in range(3, 7))
            + tuple(n for v in vectors for n in (v, "D" + v, v + "X", v + "Y"))
            + ("TORQ", "SHAKM"))


def _effects(model: Model) -> Model:
    model.add_effect("gravity")
    model.add_effect("loads")
    model.add_effect("elements")
    model.add_effect(friction_effect(model))
    return finish(model)


#: The Watt II six-bar's model.
WATT = _effects(kind_model(WattII, results=_results(4)))
#: The Stephenson III six-bar's model.
STEPHENSON = _effects(kind_model(StephensonIII, results=_results(3)))

_LINKAGES: dict[Topology, Model] = {}


def linkage_for(topology: Topology) -> Model:
    """The model of a :class:`~sielaff.Linkage` of ``topology`` (made once)."""
    if topology not in _LINKAGES:
        if len(_LINKAGES) > 64:
            _LINKAGES.clear()
        _LINKAGES[topology] = _effects(kind_model(Linkage, name="linkage", topology=topology))
    return _LINKAGES[topology]
