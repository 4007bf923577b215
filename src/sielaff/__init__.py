"""sielaff: Sielaff's 1966 crank-rocker program, emulated exactly, and a modern engine.

* ``read_deck(path) -> Deck``: a card deck read with FORMAT(4F8.4).
* ``Mechanism``: the deck's parameters, with the listing's names.
* ``analyze(mechanism, ath2, outputs=None, tex=0.0)``: the modern numpy engine.
"""

from sielaff.cards import Deck, DeckError, read_deck
from sielaff.mechanism import EXAMPLE, Mechanism

__all__ = ["EXAMPLE", "Deck", "DeckError", "Mechanism", "analyze", "read_deck"]
__version__ = "0.1.0"


def __getattr__(name: str):
    # The engine pulls in numpy; the emulator's command line does not need it.
    if name == "analyze":
        from sielaff.engine import analyze

        return analyze
    raise AttributeError(f"module 'sielaff' has no attribute {name!r}")
