"""The inverted slider-crank as a model: the linkage engine's steps for its topology (the
crank, an RPR dyad: the block at A sliding along link 4 about O4) and one line per effect."""

from __future__ import annotations

from sielaff.engine.linkage_model import finish, friction_effect, kind_model
from sielaff.inverted_slider_crank import InvertedSliderCrank, full_turn_failure

__all__ = ["INVERTED_RESULTS", "INVERTED_SLIDER_CRANK"]

_VECTORS = ("VG2", "VA", "VG3", "VG4", "AG2", "AA", "AG3", "AG4", "FA32", "FOA", "FOB", "SHAK")

#: What ``analyze`` gives an inverted slider-crank by default, in print order.
INVERTED_RESULTS = (("ATH2", "ATH4", "TH4D", "TH4DD", "S", "VS", "AS")
                    + tuple(n for v in _VECTORS for n in (v, "D" + v, v + "X", v + "Y"))
                    + ("FN", "MN", "TORQ", "SHAKM"))

#: The inverted slider-crank's model.
INVERTED_SLIDER_CRANK = kind_model(InvertedSliderCrank, full_turn=full_turn_failure,
                                   results=INVERTED_RESULTS)
INVERTED_SLIDER_CRANK.add_effect("gravity")
INVERTED_SLIDER_CRANK.add_effect("loads")
INVERTED_SLIDER_CRANK.add_effect("elements")
INVERTED_SLIDER_CRANK.add_effect(friction_effect(INVERTED_SLIDER_CRANK))
finish(INVERTED_SLIDER_CRANK)
