"""Regenerate the pictures the README and docs/ show, from the example deck.

    python docs/make_images.py

Writes docs/img/fig12-driving-torque.png (the README's Fig. 12).
"""

from __future__ import annotations

import os

from sielaff.emulator.cards import read_deck
from sielaff.tools.plot import plot_data, render

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main() -> None:
    deck = read_deck(os.path.join(ROOT, "decks", "example.dat"))
    deck.path = "example.dat"  # the subtitle names the deck, not this checkout's path
    data = plot_data(deck)
    for name in ("fig12-driving-torque",):
        path = os.path.join(ROOT, "docs", "img", data[name].filename)
        render(data[name], path)
        print(path)


if __name__ == "__main__":
    main()
