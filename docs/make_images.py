"""Regenerate the pictures the README and docs/ show, from the example deck.

    python docs/make_images.py

Writes docs/img/fig12-driving-torque.png (the README's Fig. 12),
docs/img/fig9-linkage.png (the report's Figure 9, the example's linkage, redrawn),
docs/img/bearings.png and docs/img/sweep-pareto.png (docs/design.md: the example's
bearings, and the sweep of decks/sweep.toml).
"""

from __future__ import annotations

import os

from sielaff.emulator.cards import read_deck
from sielaff.tools.plot import plot_data, render
from sielaff.tools.plot.linkage import write_linkage

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main() -> None:
    deck = read_deck(os.path.join(ROOT, "decks", "example.dat"))
    deck.path = "example.dat"  # the subtitle names the deck, not this checkout's path
    data = plot_data(deck)
    for name in ("fig12-driving-torque",):
        path = os.path.join(ROOT, "docs", "img", data[name].filename)
        render(data[name], path)
        print(path)
    folder = os.path.join(ROOT, "docs", "img")
    (png,) = write_linkage(deck, folder, at=(40.0,))
    target = os.path.join(folder, "fig9-linkage.png")
    os.replace(png, target)
    print(target)
    from sielaff.tools.plot.bearings import write_bearings

    print(*write_bearings(deck, folder, {}))
    import subprocess
    import sys
    import tempfile

    target = os.path.join(folder, "sweep-pareto.png")
    with tempfile.TemporaryDirectory() as scratch:  # the CSV is not kept (-o takes a file)
        subprocess.run([sys.executable, "-m", "sielaff", "sweep", "decks/sweep.toml", "-o",
                        os.path.join(scratch, "sweep.csv"), "--plot", target], cwd=ROOT,
                       check=True)
    print(target)


if __name__ == "__main__":
    main()
