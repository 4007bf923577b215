"""How many sheets a range card prints: the 1966 loop, counted without running it.

The loop (statements 27-54 and 233 of Appendix C)::

    TH = THZERO - DELTA;  I = 0
 54 I = I + 1;  ATH2 = TH + FLOAT(I)*DELTA
    ... one sheet ...
    IF (ATH2 .GT. THMAX) GO TO 27   (the next card)
    GO TO 54

prints sheets I = 1, 2, ..., n where n is the first I with ATH2 > THMAX (that
sheet is printed too: docs/quirks.md, the trailing sheet).  ATH2 is computed in
the run's arithmetic, so the count depends on it: THZERO = 10, DELTA = 1E-90,
THMAX = 10 adds nothing to TH in any arithmetic for 1E74 sheets or more (float64)
or for ever (the 1410's 8 digits drop the addend), while exact arithmetic would
stop at once.  :func:`sheet_count` evaluates ATH2 = TH + I*DELTA in the chosen
arithmetic at the I it needs (ATH2 never decreases as I grows for DELTA > 0), so
any count is found in a few hundred evaluations.

The 1410's own integer I: the report does not say how many digits its FORTRAN
gave an integer, and the notes at hand do not either (the sibling 1401 FORTRAN
set the size on a control card).  The port counts with Python integers, and
sielaff refuses a range of more than :data:`MAX_SHEETS` sheets (10 million:
about 14 GB of listing, beyond any use, and almost always a mistyped DELTA)
unless ``--max-sheets`` says how many to print.
"""

from __future__ import annotations

from sielaff.emulator.arithmetic import ArithmeticError1410, get_arithmetic

__all__ = ["MAX_SHEETS", "sheet_count"]

#: The most sheets a deck may ask for without ``--max-sheets``.
MAX_SHEETS = 10_000_000

_NEVER = 10**99  # the 1410 holds no number this large: the loop cannot get past it


def sheet_count(thzero: float, delta: float, thmax: float,
                arithmetic="float64") -> int | None:
    """Sheets the 1966 loop prints for one range card, or None if it never ends.

    ``arithmetic`` is a name (``float64``, ``float32``, ``ibm1410:8``) or an
    arithmetic object (:mod:`sielaff.emulator.arithmetic`).
    """
    ar = get_arithmetic(arithmetic)
    num = ar.num
    TH0, DELTA, THMAX = num(thzero), num(delta), num(thmax)
    TH = TH0 - DELTA

    def past(i: int) -> bool:
        try:
            return bool(TH + num(i) * DELTA > THMAX)
        except (OverflowError, ArithmeticError, ArithmeticError1410):
            return True  # the arithmetic stops the loop there (an error, not a sheet)

    if past(1):
        return 1
    if not DELTA > 0.0:
        return None  # ATH2 never grows: I = 1 is the most it ever gets
    # The count in exact arithmetic is nearly always right: confirm it in the run's own.
    guess = (float(thmax) - float(thzero)) / float(delta) + 2.0
    if 2.0 < guess < 1e15:
        n = int(guess)
        if past(n) and not past(n - 1):
            return n
        if past(n + 1) and not past(n):
            return n + 1
    hi = 2
    while not past(hi):
        if hi >= _NEVER:
            return None
        hi *= 2
    lo = hi // 2  # past(lo) is false, past(hi) true
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if past(mid):
            hi = mid
        else:
            lo = mid
    return hi
