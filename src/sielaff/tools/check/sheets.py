"""What the 1966 loop does with a range card (the sheets it prints), predicted without
running it; and a deck value as ``sielaff check`` prints it."""


from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal

__all__ = ["RangeSheets", "num", "range_sheets"]


def num(value: float | Decimal) -> str:
    """A deck value as the report prints it: shortest exact form."""
    if isinstance(value, Decimal):
        if value == 0:
            return "0.0"
        text = f"{value.normalize():f}"
        if len(text) > 16:
            return f"{float(value):.10g}"
        return text if "." in text else text + ".0"
    return f"{value:.10g}" if "e" in f"{value:.10g}" else _plain(value)


def _plain(value: float) -> str:
    text = f"{value:.10g}"
    return text if "." in text else text + ".0"


# --------------------------------------------------------------------------
# What the 1966 loop does with a range card
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class RangeSheets:
    """The sheets the 1966 loop prints for one range card (float64 arithmetic).

    ``count`` is None for an endless range.  ``past_360``/``below_0`` are
    (number of sheets, first THETA 2, last THETA 2) or None.
    """

    thzero: float
    delta: float
    thmax: float
    count: int | None
    first: float | None = None
    last: float | None = None
    past_360: tuple[int, float, float] | None = None
    below_0: tuple[int, float, float] | None = None


def _angle(th: float, delta: float, i: int) -> float:
    """THETA 2 of sheet ``i`` (1-based): ``ATH2 = TH + ZZZ*DELTA``, as the port does it."""
    return th + float(i) * delta


def _first(pred, lo: int, hi: int) -> int:
    """The smallest i in [lo, hi] with pred(i) true, pred monotone; hi + 1 if none."""
    while lo <= hi:
        mid = (lo + hi) // 2
        if pred(mid):
            hi = mid - 1
        else:
            lo = mid + 1
    return lo


def range_sheets(thzero: float, delta: float, thmax: float) -> RangeSheets:
    """Predict the sheets of one range card without running the loop."""
    from sielaff.emulator.ranges import sheet_count

    th = thzero - delta
    n = sheet_count(thzero, delta, thmax)  # the port's own float64 loop, counted
    if n is None:
        return RangeSheets(thzero, delta, thmax, None)
    first, last = _angle(th, delta, 1), _angle(th, delta, n)
    past = below = None
    if delta > 0.0:
        k = _first(lambda i: _angle(th, delta, i) > 360.0, 1, n)
        if k <= n:
            past = (n - k + 1, _angle(th, delta, k), last)
        k = _first(lambda i: not _angle(th, delta, i) < 0.0, 1, n)
        if k > 1:
            below = (k - 1, first, _angle(th, delta, k - 1))
    else:
        if first > 360.0:
            past = (1, first, first)
        if first < 0.0:
            below = (1, first, first)
    return RangeSheets(thzero, delta, thmax, n, first, last, past, below)
