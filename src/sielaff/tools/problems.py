"""What every command checks of a deck or spec besides its fields: the range cards (a
loop that would never end, the ceiling on positions) and an effect's own reason for a
NaN result (a spring of length zero, friction that self-locks).  Shared by the four-bar's
checks (tools/common.py) and the other kinds' (tools/kinds.py)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from sielaff.emulator.cards import Deck
from sielaff.tools.errors import CommandError

if TYPE_CHECKING:
    from sielaff.engine.scene import Scene

__all__ = ["nan_reason", "range_problem"]


def range_problem(deck: Deck, arithmetic="float64", max_sheets: int | None = None
                  ) -> CommandError | None:
    """The first range card the 1966 loop would never leave, or whose sheets (with the
    cards before it) pass the ceiling :data:`sielaff.emulator.ranges.MAX_SHEETS`, as one error
    naming the card and columns; None if the deck's ranges are fine.  With
    ``max_sheets`` the run stops there, so only a range that never ends is refused."""
    from sielaff.emulator.ranges import MAX_SHEETS, sheet_count

    ceiling = MAX_SHEETS if max_sheets is None else max_sheets
    total = 0
    name = arithmetic if isinstance(arithmetic, str) else getattr(arithmetic, "name", "")
    for card, (thzero, delta, thmax) in zip(deck.range_cards, deck.ranges):
        n = sheet_count(thzero, delta, thmax, arithmetic)
        what = (f"{deck.path}: card {card}, columns 1-24: THZERO = {thzero:g}, DELTA = "
                f"{delta:g}, THMAX = {thmax:g}")
        if n is None:
            if max_sheets is not None:
                return None  # the run stops at --max-sheets
            where = f"{deck.path}: card {card}, columns 9-16: DELTA = {delta:g}"
            if delta <= 0:
                return CommandError(f"{where} with THZERO = {thzero:g} <= THMAX = {thmax:g}: "
                                    "the 1966 loop would never end")
            return CommandError(f"{where} is too small to move THETA 2 = {thzero:g} in {name} "
                                f"arithmetic: ATH2 = TH + I*DELTA never passes THMAX = "
                                f"{thmax:g}, so the 1966 loop would never end")
        total += n
        if total > ceiling and max_sheets is None:
            count = f"{n:,}" if n < 10**12 else f"{n:.2E}".replace("+", "")
            return CommandError(f"{what}: {count} sheets, past the ceiling of "
                                f"{MAX_SHEETS:,} for a deck (--max-sheets N prints the first "
                                "N; or check DELTA)")
        if total > ceiling:
            return None
    return None


def nan_reason(deck: Deck, scene: Scene, at: float) -> str | None:
    """Why the results are NaN at THETA 2 = ``at`` [deg], if an effect knows: a spring or
    a damper of length zero (its direction undefined), or pin friction with no solution
    (the linkage self-locks there)."""
    import warnings

    import numpy as np

    from sielaff.engine import analyze

    names = []
    if scene.elements:
        names += [f"{k}{j}_L" for k in ("SPRING", "DAMPER") for j in range(1, 9)]
    if scene.has_friction:
        names.append("FRICTION_STATUS")
    if not names:
        return None
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        r = analyze(deck.mechanism, at, names, scene=scene)
    kinds = {"SPRING": 0, "DAMPER": 0}
    for e in scene.elements:
        kind = "SPRING" if type(e).__name__ == "Spring" else "DAMPER"
        kinds[kind] += 1
        length = float(r[f"{kind}{kinds[kind]}_L"])
        if not length > 0.0:
            return (f"{kind.lower()} {kinds[kind]} has its two points at one place at THETA 2 "
                    f"= {at:g} deg: its length is 0 and its direction undefined")
    if "FRICTION_STATUS" in r and float(r["FRICTION_STATUS"]) == 2.0:
        from sielaff.mechanism import Mechanism

        what = "pin friction" if isinstance(deck.mechanism, Mechanism) else "joint friction"
        return (f"{what}: the friction law has no solution at THETA 2 = {at:g} deg (the "
                "linkage self-locks there with this friction)")
    return None
