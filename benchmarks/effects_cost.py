"""What accuracy costs in time for the new solves (issue 23, item 5), into docs/effects.md.

    python benchmarks/effects_cost.py            # the full grid, written into
                                                 # docs/effects.md and docs/img/effects-cost.png
    python benchmarks/effects_cost.py --print    # only print the tables

The study is ``sielaff.tools.bench.effects`` (``sielaff bench --effects`` runs a small
grid of it): the friction fixed point's tolerance 1e-3..1e-13 and simulate's rtol
1e-3..1e-12 with DOP853, RK45, LSODA and Radau against CPU and wall time (3 rounds each,
median and range), the error read from the friction power identity and from the energy
balance over the run; then the hard cases (friction near a toggle, friction with no
solution, a stall at the dead point, a start from rest).  Every number in the section
between the ``effects bench`` markers is this script's.
"""

from __future__ import annotations

import sys
from pathlib import Path

from sielaff.tools.bench.effects import effects_study, headline, markdown, plot

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "effects.md"
FIGURE = ROOT / "docs" / "img" / "effects-cost.png"
BEGIN, END = "<!-- effects bench begin -->", "<!-- effects bench end -->"


def main(argv: list[str]) -> int:
    res = effects_study(False, progress=lambda t: print(f"effects: {t}", file=sys.stderr))
    print(headline(res))
    if "--print" in argv:
        return 0
    plot(res, str(FIGURE))
    text = DOC.read_text()
    section = (f"{BEGIN}\n" + markdown(res, "img/effects-cost.png",
                                       "python benchmarks/effects_cost.py") + END)
    if BEGIN in text:
        head, _, rest = text.partition(BEGIN)
        text = head + section + rest.partition(END)[2]
    else:
        text = text.rstrip("\n") + "\n\n" + section + "\n"
    DOC.write_text(text)
    print(f"wrote {DOC} and {FIGURE}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
