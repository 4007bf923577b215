"""A progress bar on stderr for long runs, and nothing otherwise.

``Progress(total, label)`` is called with the number of items done so far
(``bar(n)``).  It draws only when its stream is a terminal and the run is
projected to take more than ``threshold`` seconds (2 s; the environment
variable ``SIELAFF_PROGRESS_SECONDS`` overrides it): the projection is the
elapsed time scaled by total/done, so the bar adapts to the arithmetic
model and the machine.  It redraws at most ten times a second, on one line
(carriage return), and ``close()`` (or leaving the ``with`` block) erases
it.  ``wrap(notice)`` returns a notice callback that erases the bar before
writing a line, so diagnostics never land in the middle of it.

``estimate_sheets(deck)`` is the number of sheets ``sielaff run`` will print:
over the range cards, floor((THMAX - THZERO)/DELTA) + 2 (one sheet past
THMAX), 1 when THZERO > THMAX.
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Callable
from typing import TextIO

__all__ = ["Progress", "estimate_sheets", "run_progress"]

THRESHOLD = 2.0  # seconds
INTERVAL = 0.1  # seconds between redraws
WIDTH = 30  # bar characters


def estimate_sheets(deck) -> int:
    """Sheets the 1966 loop prints for ``deck`` (an endless range counts as 0)."""
    total = 0
    for thzero, delta, thmax in deck.ranges:
        if thzero > thmax:
            total += 1
        elif delta > 0:
            total += math.floor((thmax - thzero) / delta) + 2
    return total


def _threshold() -> float:
    try:
        return float(os.environ.get("SIELAFF_PROGRESS_SECONDS", THRESHOLD))
    except ValueError:
        return THRESHOLD


def _isatty(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):
        return False


class Progress:
    """A one-line progress bar for ``total`` items (see the module doc)."""

    def __init__(self, total: int, label: str, unit: str = "sheets",
                 stream: TextIO | None = None, threshold: float | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.stream = sys.stderr if stream is None else stream
        self.total = max(int(total), 0)
        self.label, self.unit = label, unit
        self.threshold = _threshold() if threshold is None else threshold
        self.clock = clock
        self.enabled = self.total > 0 and _isatty(self.stream)
        self.start = clock()
        self.next_draw = self.start
        self.shown = False
        self.done = 0

    def __call__(self, done: int) -> None:
        self.done = done
        if not self.enabled:
            return
        now = self.clock()
        if now < self.next_draw:
            return
        self.next_draw = now + INTERVAL
        elapsed = now - self.start
        if not self.shown:
            projected = elapsed * self.total / done if done > 0 else math.inf
            if done <= 0 or projected <= self.threshold:
                return
        self._draw(elapsed)

    def _draw(self, elapsed: float) -> None:
        done = min(self.done, self.total)
        frac = done / self.total
        filled = int(frac * WIDTH)
        left = ""
        if done and elapsed > 0:
            rest = elapsed * (self.total - done) / done
            left = f", {rest:.0f} s left" if rest >= 1 else ""
        line = (f"{self.label}: [{'#' * filled}{'.' * (WIDTH - filled)}] {frac:4.0%} "
                f"{done:,}/{self.total:,} {self.unit}{left}")
        self.stream.write("\r" + line + "\x1b[K")
        self.stream.flush()
        self.shown = True

    def clear(self) -> None:
        """Erase the bar (it is drawn again on the next update)."""
        if self.shown:
            self.stream.write("\r\x1b[K")
            self.stream.flush()
            self.shown = False
            self.next_draw = self.clock()

    close = clear

    def wrap(self, notice: Callable[[str, str], None]) -> Callable[[str, str], None]:
        """``notice`` that erases the bar first (a ``notice(kind, text)`` callback)."""

        def wrapped(kind: str, text: str) -> None:
            self.clear()
            notice(kind, text)

        return wrapped

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def run_progress(deck, max_sheets: int | None = None, stream: TextIO | None = None) -> Progress:
    """The bar for ``sielaff run`` on ``deck`` (at most ``max_sheets`` sheets)."""
    total = estimate_sheets(deck)
    if max_sheets is not None:
        total = min(total, max_sheets)
    return Progress(total, "sielaff run", stream=stream)
