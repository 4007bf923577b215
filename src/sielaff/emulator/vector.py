"""The float64 listing, many sheets at a time: the port's arithmetic redone in numpy.

In:  a deck, the listing's options (kinematics only, ``tex``, ``max_sheets``).
Out: the same bytes as the line-by-line port (``program.Program`` on ``Float64``) and
     the printer, sheet for sheet, with the same notices and the same errors.

How the bytes stay the same:

* **The arithmetic.**  Every quantity is computed from the listing's own expressions,
  in the same order of operations, on float64 arrays.  ``+ - * /`` are IEEE operations,
  exact to the same bit in numpy and in Python.  Hence the values are the port's,
  provided numpy's ``sin``, ``cos`` and ``sqrt`` return libm's results.  sqrt is exact
  everywhere, and :func:`numpy_matches_libm` checks sin and cos at first use (if they
  differ, ``sielaff run`` uses the port alone).
* **ATAN.**  numpy's ``arctan`` may differ from libm's in the last bit.  It only feeds
  the printed directions (VECTOR's DIRECT), so it matters only for a direction that
  lies near a printed-digit boundary.  Such a field is printed from the port's own
  VECTOR, which gives the exact value.
* **ARCCOS.**  The series runs on arrays, each element stopping at its own term, by
  the listing's test.
* **Printing.**  A field prints in bulk only where the printer's first tier would
  print it.  That is where its digits follow by arithmetic, away from a digit
  boundary; the tier's test is repeated here on the same numbers.  Every other field
  goes through the printer's own editor.
* **Sheets the port must print itself.**  These are the sheets that raise a notice or
  an error:
  * Case I or Case II outside one revolution;
  * the trailing sheet past THMAX;
  * an exactly zero cosine (TAN3 or TAN4);
  * a non-finite value, or one past the 1410's range;
  * a zero divisor;
  * SQRT of a negative number in ARCCOS.

  They are handed back to the port one at a time (``MAIN(..., start=I)``), in order.
  So the notices, their limits and the error messages are the port's.

Sheets are computed :data:`CHUNK` at a time and written chunk by chunk, so memory stays
flat.  tests/test_vector.py compares the bytes with the port's on hypothesis-drawn decks
and on the 36,001-sheet deck of benchmarks/listing.py.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable

import numpy as np

from sielaff.emulator.arithmetic.base import Float64
from sielaff.emulator.printer import _EXPONENT_TEXT, compile_format, edit_e, fast_editor
from sielaff.emulator.program import (
    FORMATS,
    KINEMATIC_FIELDS,
    SHEET_FIELDS,
    Program,
    SheetLimit,
)
from sielaff.emulator.ranges import sheet_count

__all__ = ["CHUNK", "applies", "numpy_matches_libm", "plan", "vector_run"]

#: Sheets computed and written at a time.
CHUNK = 2048
#: Below this many sheets per range card on average, the port prints the deck.
MIN_SHEETS_PER_CARD = 32

#: The WRITEs of one sheet: (FORMAT, index into SHEET_FIELDS or None).
SHEET_WRITES = ((7, None), (10, None), (1, 0), (11, None), (2, 1), (12, None), (5, 2),
                (13, None), (9, 3), (8, 4), (14, None), (9, 5), (8, 6),
                (15, None), (2, 7), (3, 8), (16, None), (6, 9), (4, 10), (17, None), (5, 11),
                (18, None))
FORCE_WRITES = frozenset(range(13, 21))  # positions in SHEET_WRITES of statements 133-202


def _layout(kinematics_only: bool) -> tuple[str, list[tuple[int, str, int, int]]]:
    """The sheet's text with blanks for the numbers, and each number's (offset, kind,
    width, decimals), in the order of the listing's values."""
    text: list[str] = []
    fields: list[tuple[int, str, int, int]] = []
    pos = 0
    for k, (fmt, _group) in enumerate(SHEET_WRITES):
        if kinematics_only and k in FORCE_WRITES:
            continue
        record: list[str] = []
        for item in compile_format(FORMATS[fmt]) + [("/",)]:
            if item[0] == "lit":
                record.append(item[1])
            elif item[0] == "edit":
                offset = pos + sum(len(r) for r in record)
                kind = "E" if item[1] is edit_e else "F"
                fields.append((offset, kind, item[2], item[3]))
                record.append(" " * item[2])
            else:
                line = "".join(record) or " "
                text.append(line + "\n")
                pos += len(line) + 1
                record = []
    return "".join(text), fields


_LIBM_CHECKED: bool | None = None


def numpy_matches_libm() -> bool:
    """Whether numpy's sin and cos give libm's results on this machine (checked once,
    on 20,000 arguments spread over the range the program meets)."""
    global _LIBM_CHECKED
    if _LIBM_CHECKED is None:
        # multiples of the golden ratio modulo 1 spread evenly over [-20, 20) (and need
        # no numpy.random, whose import costs start-up)
        x = 40.0 * np.modf(np.arange(20_000) * 0.6180339887498949)[0] - 20.0
        x[:4] = (0.0, -0.0, math.pi / 2, 3.14159265 / 2)
        xs, root = x.tolist(), np.sqrt(np.abs(x))
        _LIBM_CHECKED = (np.sin(x).tolist() == list(map(math.sin, xs))
                         and np.cos(x).tolist() == list(map(math.cos, xs))
                         and root.tolist() == list(map(math.sqrt, np.abs(x).tolist())))
    return _LIBM_CHECKED


def plan(deck) -> list[int] | None:
    """The sheets each range card prints, if this path can print ``deck``; None if not:
    numpy disagrees with libm, the lengths fail the crank-rocker test in float64 (the port
    prints the refusal), a range card never ends (the port's, under ``--max-sheets``), or
    the cards are too short for blocks to pay (MIN_SHEETS_PER_CARD)."""
    from sielaff.emulator.program import first_failed_test

    m = deck.mechanism
    R1, R2, R3, R4 = (float(x) for x in (m.R1, m.R2, m.R3, m.R4))
    try:
        if first_failed_test(R3 / R2, R4 / R2, R1 / R2, abs) is not None:
            return None
    except ArithmeticError:  # R2 = 0: the port names the statement dividing by it
        return None
    if not numpy_matches_libm():
        return None
    counts = []
    for r in deck.ranges:
        n = sheet_count(*(float(x) for x in r))
        if n is None:
            return None
        counts.append(n)
    # a block costs about a millisecond whatever its size: range cards of a few sheets
    # each are the port's (a sheet there costs some 40 microseconds)
    return counts if sum(counts) >= MIN_SHEETS_PER_CARD * len(counts) else None


def applies(deck) -> bool:
    """Whether this path can print ``deck`` (see :func:`plan`)."""
    return plan(deck) is not None


# -- the arithmetic ----------------------------------------------------------

ARCCOS_TERMS = 200  # past this an element is left to the port (its limit is 10,000)


def _arccos(X: np.ndarray, bad: np.ndarray) -> np.ndarray:
    """FUNCTION ARCCOS on an array, element by element as the listing; ``bad`` marks the
    elements the port must do (SQRT of a negative, no convergence)."""
    PI = 3.14159265358979323846
    XX = X
    X2 = XX * XX
    big = ~(np.abs(XX) <= 0.7)
    one = 1.0 - X2
    bad |= big & ~(one >= 0.0)
    XX = np.where(big, np.sqrt(np.where(one >= 0.0, one, 0.0)), XX)
    X2 = np.where(big, XX * XX, X2)
    SUM = (PI / 2.0) - XX
    VAL = XX
    SAVE = np.full_like(X, 0.1E-50)
    A, PROD, ZMULT = 0.0, 1.0, 1.0
    active = np.ones(X.shape, dtype=bool)
    for _ in range(ARCCOS_TERMS):
        A = A + 2.0
        PROD = PROD * A
        ZMULT = ZMULT * (A - 1.0)
        VAL = VAL * X2
        new = SUM - (ZMULT * VAL) / (PROD * (A + 1.0))
        SUM = np.where(active, new, SUM)
        done = active & (np.abs(SUM - SAVE) < 0.00000001)
        active &= ~done
        SAVE = np.where(active, SUM, SAVE)
        if not active.any():
            break
    bad |= active
    return np.where(X < -0.70, (PI / 2.0) + SUM, np.where(X > 0.70, (PI / 2.0) - SUM, SUM))


def _vector(X: np.ndarray, Y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """SUBROUTINE VECTOR on arrays (ATAN from numpy: see the module doc)."""
    PI = 3.14159265
    RAD = 57.2957795
    with np.errstate(divide="ignore", invalid="ignore"):
        ARC = np.arctan(np.abs(Y) / np.abs(X))
    below = Y < 0.0
    ANG = np.where(X > 0.0, np.where(below, 2.0 * PI - ARC, ARC),
                   np.where(below, PI + ARC, PI - ARC))
    axis = X == 0.0
    if axis.any():
        ANG[axis] = np.where(below, (3.0 * PI) / 2.0, np.where(Y > 0.0, PI / 2.0, 0.0))[axis]
    return np.sqrt(X * X + Y * Y), ANG * RAD


def _sheets(m, ATH2: np.ndarray, tex: float, kinematics_only: bool):
    """The printed values (dict by listing name), the VECTOR inputs of each direction,
    and the sheets the port must print itself."""
    W2, W3, W4 = m.W2, m.W3, m.W4
    ZI3, ZI4 = m.ZI3, m.ZI4
    R1, R2, R3, R4 = m.R1, m.R2, m.R3, m.R4
    RG2, RG3, RG4 = m.RG2, m.RG3, m.RG4
    TH2D = m.TH2D
    G = 386.0880
    ZM2, ZM3, ZM4 = W2 / G, W3 / G, W4 / G
    RAD = 57.295779
    PI = 3.14159265
    SQ2D = TH2D * TH2D
    DEL2, DEL3, DEL4 = m.ADEL2 / RAD, m.ADEL3 / RAD, m.ADEL4 / RAD
    bad = np.zeros(ATH2.shape, dtype=bool)
    SIN, COS, SQRT = np.sin, np.cos, np.sqrt
    TH2 = ATH2 / RAD
    CTH2 = COS(TH2)
    ZL = SQRT(R2 * R2 + R1 * R1 - 2.0 * R2 * R1 * CTH2)
    bad |= ZL == 0.0
    with np.errstate(all="ignore"):
        PSI = _arccos((-(R4 * R4) + ZL * ZL + R3 * R3) / (2.0 * ZL * R3), bad)
        ZLAM = _arccos((ZL * ZL + R4 * R4 - R3 * R3) / (2.0 * ZL * R4), bad)
        BETA = _arccos((ZL * ZL + R1 * R1 - R2 * R2) / (2.0 * ZL * R1), bad)
        case2 = TH2 >= PI
        TH3 = np.where(case2, PSI + BETA, PSI - BETA)
        TH4 = np.where(case2, PI - ZLAM + BETA, PI - ZLAM - BETA)
        bad |= (case2 & (ATH2 > 360.0)) | (~case2 & (ATH2 < 0.0))  # the Case I/II notices
        ATH3 = TH3 * RAD
        ATH4 = TH4 * RAD
        TEX = np.full(ATH2.shape, float(tex))
        S42 = SIN(TH4 - TH2)
        S34 = SIN(TH3 - TH4)
        S32 = SIN(TH3 - TH2)
        C42 = COS(TH4 - TH2)
        C43 = COS(TH4 - TH3)
        S43 = SIN(TH4 - TH3)
        C32 = COS(TH3 - TH2)
        C34 = COS(TH3 - TH4)
        STHDE2, CTHDE2 = SIN(TH2 + DEL2), COS(TH2 + DEL2)
        STHDE3, CTHDE3 = SIN(TH3 + DEL3), COS(TH3 + DEL3)
        STHDE4, CTHDE4 = SIN(TH4 + DEL4), COS(TH4 + DEL4)
        STH4, CTH4 = SIN(TH4), COS(TH4)
        STH3, CTH3 = SIN(TH3), COS(TH3)
        STH2, CTH2 = SIN(TH2), COS(TH2)
        bad |= (S34 == 0.0) | (S43 == 0.0)
        TH3D = (R2 / R3) * TH2D * (S42 / S34)
        TH4D = (R2 / R4) * TH2D * (S32 / S34)
        SQ3D = TH3D * TH3D
        SQ4D = TH4D * TH4D
        TH3DD = (R2 * SQ2D * C42 + R3 * SQ3D * C43 - R4 * SQ4D) / (R3 * S43)
        TH4DD = (-R2 * SQ2D * C32 + R4 * SQ4D * C34 - R3 * SQ3D) / (R4 * S34)
        R2X = R2 * CTH2
        R2Y = R2 * STH2
        R3X = R3 * CTH3
        R3Y = R3 * STH3
        RG3X = RG3 * CTHDE3
        RG3Y = RG3 * STHDE3
        R4X = R4 * CTH4
        R4Y = R4 * STH4
        RG4X = RG4 * CTHDE4
        RG4Y = RG4 * STHDE4
        VAX = -R2 * TH2D * STH2
        VAY = R2 * TH2D * CTH2
        AAX = -R2 * SQ2D * CTH2
        AAY = -R2 * SQ2D * STH2
        VG2X = -RG2 * TH2D * STHDE2
        VG2Y = RG2 * TH2D * CTHDE2
        AG2X = -RG2 * SQ2D * CTHDE2
        AG2Y = -RG2 * SQ2D * STHDE2
        VBX = -R4 * TH4D * STH4
        VBY = R4 * TH4D * CTH4
        ABX = -R4 * SQ4D * CTH4 - R4 * TH4DD * STH4
        ABY = -R4 * SQ4D * STH4 + R4 * TH4DD * CTH4
        VG4X = -RG4 * TH4D * STHDE4
        VG4Y = RG4 * TH4D * CTHDE4
        AG4X = -RG4 * SQ4D * CTHDE4 - RG4 * TH4DD * STHDE4
        AG4Y = -RG4 * SQ4D * STHDE4 + RG4 * TH4DD * CTHDE4
        VG3X = VAX - RG3 * TH3D * STHDE3
        VG3Y = VAY + RG3 * TH3D * CTHDE3
        AG3X = AAX - RG3 * SQ3D * CTHDE3 - RG3 * TH3DD * STHDE3
        AG3Y = AAY - RG3 * SQ3D * STHDE3 + RG3 * TH3DD * CTHDE3
        v = {"ATH2": ATH2, "ATH3": ATH3, "ATH4": ATH4, "TH3D": TH3D, "TH4D": TH4D,
             "TH3DD": TH3DD, "TH4DD": TH4DD, "TEX": TEX}
        xy = {"VG2": (VG2X, VG2Y), "VA": (VAX, VAY), "VG3": (VG3X, VG3Y), "VB": (VBX, VBY),
              "VG4": (VG4X, VG4Y), "AG2": (AG2X, AG2Y), "AA": (AAX, AAY),
              "AG3": (AG3X, AG3Y), "AB": (ABX, ABY), "AG4": (AG4X, AG4Y)}
        if not kinematics_only:
            FG4X = -ZM4 * AG4X
            FG4Y = -ZM4 * AG4Y
            TI4 = -ZI4 * TH4DD
            bad |= (CTH3 == 0.0) | (CTH4 == 0.0)  # TAN3, TAN4 = 0.9E+25: the port notices
            TAN3 = STH3 / CTH3
            D3 = R4X * TAN3 - R4Y
            FP34X = (-RG4X * FG4Y + RG4Y * FG4X - TI4 - TEX) / D3
            FP34Y = FP34X * TAN3
            FP14X = -FG4X - FP34X
            FP41X = -FP14X
            FP14Y = -FG4Y - FP34Y
            FP41Y = -FP14Y
            FP32X = -FP34X
            FP32Y = -FP34Y
            FP21Y = -FP34Y
            FP21X = -FP34X
            TP2 = -R2X * FP32Y + R2Y * FP32X
            TI3 = -ZI3 * TH3DD
            FG3X = -ZM3 * AG3X
            FG3Y = -ZM3 * AG3Y
            TAN4 = STH4 / CTH4
            D4 = R3X * TAN4 - R3Y
            FPP43X = (-RG3X * FG3Y + RG3Y * FG3X - TI3) / D4
            FPP34X = -FPP43X
            FPP43Y = FPP43X * TAN4
            FPP34Y = -FPP43Y
            FPP23X = -FPP43X - FG3X
            FPP32X = -FPP23X
            FPP23Y = -FPP43Y - FG3Y
            FPP32Y = -FPP23Y
            FPP41X = -FPP43X
            FPP41Y = -FPP43Y
            FPP21X = -FPP23X
            FPP21Y = -FPP23Y
            TPP2 = -R2X * FPP32Y + R2Y * FPP32X
            FG2X = -ZM2 * AG2X
            FG2Y = -ZM2 * AG2Y
            F3P21X = FG2X  # F3P12X = -FG2X, F3P21X = -F3P12X: negation is exact
            F3P21Y = FG2Y
            bad |= (D3 == 0.0) | (D4 == 0.0)
            v["TORQ"] = TP2 + TPP2
            FOAX = FP21X + FPP21X + F3P21X
            FOAY = FP21Y + FPP21Y + F3P21Y
            FOBX = FP41X + FPP41X
            FOBY = FP41Y + FPP41Y
            v["SHAKX"] = FOAX + FOBX
            v["SHAKY"] = FOAY + FOBY
            xy.update({"FA32": (FP32X + FPP32X, FP32Y + FPP32Y),
                       "FB34": (FP34X + FPP34X, FP34Y + FPP34Y),
                       "FOA": (FOAX, FOAY), "FOB": (FOBX, FOBY),
                       "SHAK": (v["SHAKX"], v["SHAKY"])})
        for name, (X, Y) in xy.items():
            v[name], v["D" + name] = _vector(X, Y)
        for name in ("TH3", "TH4", "TH3D", "TH4D", "TH3DD", "TH4DD"):
            bad |= ~np.isfinite(locals()[name])
    return v, xy, bad


# -- printing ----------------------------------------------------------------

# Each 12-character field is built as three 4-byte words (uint32 views of byte tables),
# so that a field costs a few table lookups, not a dozen column writes.


def _words(text: np.ndarray) -> np.ndarray:
    """(m, 4k) bytes as (m, k) uint32 words (the same bytes, any byte order)."""
    return np.ascontiguousarray(text).view(np.uint32)


def _digit_table(n: np.ndarray, places: int, lead: str) -> np.ndarray:
    """The last ``places`` decimal digits of ``n`` as bytes (len(n), places), leading
    zeros kept ("0") or blanked (" ")."""
    power = 10 ** np.arange(places - 1, -1, -1)
    table = (n[:, None] // power % 10 + ord("0")).astype(np.uint8)
    if lead == " ":
        table[n[:, None] < power] = ord(" ")
    return table


def _signed(n: np.ndarray, places: int) -> np.ndarray:
    """Bytes (2, len(n), places): n right-justified without leading zeros, and as the
    same with a minus sign before its first digit (n = 0: the sign alone)."""
    plain = _digit_table(n, places, " ")
    minus = plain.copy()
    width = (n[:, None] >= 10 ** np.arange(places)).sum(axis=1)
    minus[np.arange(n.size), places - 1 - width] = ord("-")
    return np.stack([plain, minus])


_DIGITS4 = np.arange(10000)
_TWO = _digit_table(np.arange(100), 2, "0")
#: "0000" ... "9999", one uint32 word each.
_FOUR = _words(np.concatenate([np.repeat(_TWO, 100, axis=0), np.tile(_TWO, (100, 1))],
                              axis=1)).ravel()
#: E12.4: the word "   ." or "  -.", then the four digits, then the exponent's word.
_E_SIGN = _words(np.frombuffer(b"   .  -.", dtype=np.uint8).reshape(2, 4)).ravel()
_E_EXPONENT = _words(np.frombuffer("".join(_EXPONENT_TEXT).encode(), dtype=np.uint8)
                     .reshape(199, 4)).ravel()
_E_SCALES = np.array([10.0 ** (4 - (k - 99)) for k in range(199)])
#: F12.1 with t = |x| * 10 truncated = hi * 10**4 + lo.  _F_LOW[s * 10**4 + lo]: the
#: whole field of a value below 1000 (s = 1 negative): the digits of lo // 10 right-justified
#: (the sign before them), the point and one decimal.
_F_LOW = np.full((2, 1000, 10, 12), ord(" "), dtype=np.uint8)
_F_LOW[..., :10] = _signed(np.arange(1000), 10)[:, :, None, :]
_F_LOW[..., 10] = ord(".")
_F_LOW[..., 11] = np.arange(ord("0"), ord("9") + 1, dtype=np.uint8)
_F_LOW = _words(_F_LOW.reshape(20000, 12))


@functools.cache
def _f_high() -> tuple[np.ndarray, np.ndarray]:
    """Past 1000 (made when first needed): (_F_HIGH[s * 10**4 + hi], the digits of hi with
    the sign before them, bytes 0-6; _F_LOW_DIGITS[lo], three digits, the point, one
    decimal, bytes 7-11), each zero where the other is not: their sum is the field."""
    high = np.zeros((20000, 12), dtype=np.uint8)
    high[:, :7] = _signed(_DIGITS4, 7).reshape(20000, 7)
    low = np.zeros((10000, 12), dtype=np.uint8)
    low[:, 7:10] = _digit_table(_DIGITS4 // 10, 3, "0")
    low[:, 10] = ord(".")
    low[:, 11] = _DIGITS4 % 10 + ord("0")
    return _words(high), _words(low)


def _edit_e(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """E12.4 by the printer's first tier: (words (n, 3), where it applies)."""
    a = np.abs(x)
    ok = (a >= 1e-99) & (a < 1e98)
    zero = a == 0.0  # the 1410's zero: .0000E-99 (the printer's first tier too)
    with np.errstate(all="ignore"):  # NaN, inf where not ok: not used
        k = np.where(ok, np.floor(np.log10(a)) + 100.0, 0.0).astype(np.intp)
    # k: exponent + 99 (0: the zero's, E-99); t and the rest, as the printer's int()
    frac, whole = np.modf(a * _E_SCALES[k])
    ok &= (whole >= 1000.0) & (whole <= 9999.0) & (frac > 1e-7) & (frac < 0.9999999)
    out = np.empty((x.size, 3), dtype=np.uint32)
    out[:, 0] = np.where(x < 0.0, _E_SIGN[1], _E_SIGN[0])
    out[:, 1] = _FOUR[np.where(ok, whole, 0.0).astype(np.intp)]
    out[:, 2] = _E_EXPONENT[k]
    return out, ok | zero


def _edit_f(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """F12.1 by the printer's first tier: (words (n, 3), where it applies)."""
    a = np.abs(x)
    ok = (a > 0.0) & (a < 1e7)
    scaled = np.where(ok, a, 0.0) * 10.0  # NaN and inf out before the cast
    t = scaled.astype(np.int64)
    frac = scaled - t
    ok &= (frac > 1e-6) & (frac < 0.999999)
    t = np.where(ok, t, 0)  # below 10**8: hi and lo below 10**4
    negative = np.where(x < 0.0, 10000, 0)
    hi, lo = np.divmod(t, 10000)
    out = _F_LOW[lo + negative]
    big = np.flatnonzero(hi)
    if big.size:  # |x| >= 1000
        high, low = _f_high()
        out[big] = high[hi[big] + negative[big]] + low[lo[big]]
    return out, ok


class _Listing:
    """Sheets of one deck through the vectorised path, handing special ones back."""

    def __init__(self, deck, emit: Callable[[str], None], notice, kinematics_only: bool,
                 tex: float, writer_factory,
                 emit_bytes: Callable[[memoryview], None] | None = None) -> None:
        self.deck, self.emit, self.notice = deck, emit, notice
        self.emit_page = ((lambda rows: emit(str(rows.data, "ascii"))) if emit_bytes is None
                          else (lambda rows: emit_bytes(rows.data)))
        self.kinematics_only, self.tex = kinematics_only, tex
        self.writer_factory = writer_factory
        text, self.fields = _layout(kinematics_only)
        assert all(w == 12 for _o, _k, w, _d in self.fields)
        # one page of CHUNK sheets, reused: each block rewrites every field's 12 bytes
        template = np.frombuffer(text.encode("ascii"), dtype=np.uint8)
        self.page = np.tile(template, (CHUNK, 1))
        groups = KINEMATIC_FIELDS if kinematics_only else SHEET_FIELDS
        self.names = [n for g in groups for n in g]
        # kind -> (field offsets, names, runs); a run is fields of one kind side by side on
        # a line, [first field, count, page offset]: one slice assignment each
        self.by_kind = {}
        for kind in "EF":
            picked = [(off, name) for (off, k, _w, _d), name in zip(self.fields, self.names)
                      if k == kind]
            offsets = [off for off, _ in picked]
            runs: list[list[int]] = []
            for j, off in enumerate(offsets):
                if runs and runs[-1][2] + 12 * runs[-1][1] == off:
                    runs[-1][1] += 1
                else:
                    runs.append([j, 1, off])
            self.by_kind[kind] = (offsets, [name for _, name in picked], runs)
        self.editors = {kind: fast_editor(kind, 12, 4 if kind == "E" else 1, True)
                        for kind in "EF"}
        self.port = Program(Float64(on_error=lambda text: notice("library", text)), notice)

    def port_sheet(self, index: int, i: int) -> None:
        """Sheet I = i of range card ``index`` by the port, written as it writes it."""
        one = dataclasses.replace(self.deck, ranges=[self.deck.ranges[index]],
                                  range_cards=[self.deck.range_cards[index]])
        writer = self.writer_factory(self.emit, self.kinematics_only)
        try:
            self.port.MAIN(one, writer.write, self.kinematics_only, 1, self.tex, start=i)
        except SheetLimit:
            pass
        writer.flush()

    def _slow(self, page, rows, offset, kind, name, v, xy, bad) -> None:
        """Fields the first tier does not print: the printer's own editor, once per
        distinct value (a round 200.0 recurs on every sheet); a direction from the
        port's VECTOR, since numpy's arctan may differ from libm's in the last bit."""
        editor = self.editors[kind]
        if name.startswith("D") and name[1:] in xy:
            X, Y = xy[name[1:]]
            values = np.array([self.port.VECTOR(x, y)[1] for x, y in
                               zip(X[rows].tolist(), Y[rows].tolist())])
        else:
            values = v[name][rows]
        zeros = values == 0.0  # -0.0 and 0.0 print apart but are one key to np.unique
        each = rows[zeros].tolist()
        if not zeros.all():
            distinct, inverse = np.unique(values[~zeros], return_inverse=True)
            texts = np.empty((distinct.size, 12), dtype=np.uint8)
            fine = np.ones(distinct.size, dtype=bool)
            for j, value in enumerate(distinct.tolist()):
                try:
                    texts[j] = np.frombuffer(editor(value).encode("ascii"), dtype=np.uint8)
                except ValueError:  # Unprintable: the port raises the 1966 error
                    fine[j] = False
            keep = rows[~zeros]
            page[keep, offset:offset + 12] = texts[inverse]
            bad[keep[~fine[inverse]]] = True
        for s, value in zip(each, values[zeros].tolist()):
            page[s, offset:offset + 12] = np.frombuffer(editor(value).encode("ascii"),
                                                        dtype=np.uint8)

    def chunk(self, index: int, first: int, ATH2: np.ndarray, last: int) -> None:
        """Sheets I = first .. first + len(ATH2) - 1 of range card ``index``."""
        v, xy, bad = _sheets(self.deck.mechanism, ATH2, self.tex, self.kinematics_only)
        n = ATH2.size
        if first + n - 1 == last:
            bad[-1] = True  # the trailing sheet: the port notices it
        page = self.page[:n]
        for kind, (offsets, names, runs) in self.by_kind.items():
            x = np.stack([v[name] for name in names], axis=1).ravel()
            with np.errstate(all="ignore"):
                words, ok = (_edit_e if kind == "E" else _edit_f)(x)
            text = words.view(np.uint8).reshape(n, 12 * len(names))
            for j, count, offset in runs:
                page[:, offset:offset + 12 * count] = text[:, 12 * j:12 * (j + count)]
            ok = ok.reshape(n, len(names))
            for j in np.flatnonzero(~ok.all(axis=0)):
                rows = np.flatnonzero(~ok[:, j] & ~bad)
                if rows.size:
                    self._slow(page, rows, offsets[j], kind, names[j], v, xy, bad)
        start = 0
        for s in np.flatnonzero(bad):
            if s > start:
                self.emit_page(page[start:s])
            self.port_sheet(index, first + int(s))
            start = s + 1
        if start < n:
            self.emit_page(page[start:])


def vector_run(deck, emit: Callable[[str], None], notice, writer_factory,
               kinematics_only: bool = False, max_sheets: int | None = None,
               progress: Callable[[int], None] | None = None, tex: float = 0.0,
               counts: list[int] | None = None,
               emit_bytes: Callable[[memoryview], None] | None = None) -> int:
    """The listing of ``deck`` in float64 (see the module doc): sheets written through
    ``emit``; ``writer_factory(emit, kinematics_only)`` makes the port's WRITE for the
    sheets handed back.  The deck must pass the crank-rocker test and every range card
    must end (the caller checks both); ``counts``, the sheets of each card, as
    :func:`plan` gives them.  ``emit_bytes``, if given, takes the blocks' sheets as ASCII
    bytes in place of ``emit`` (no decoding; it must put them where ``emit``'s text goes,
    in order).  Raises SheetLimit past ``max_sheets``."""
    listing = _Listing(deck, emit, notice, kinematics_only, tex, writer_factory, emit_bytes)
    if not float(tex) == float(tex) or abs(float(tex)) >= 1e99:
        raise ValueError("tex must be finite (the caller checks it)")
    total = 0
    cards = len(deck.ranges)
    for index in range(cards):
        THZERO, DELTA, THMAX = (float(x) for x in deck.ranges[index])
        count = counts[index] if counts is not None else sheet_count(THZERO, DELTA, THMAX)
        TH = THZERO - DELTA
        for first in range(1, count + 1, CHUNK):
            stop = min(first + CHUNK, count + 1)
            if max_sheets is not None:
                if total >= max_sheets:
                    raise SheetLimit(total)
                stop = min(stop, first + (max_sheets - total))
            ZZZ = np.arange(first, stop, dtype=np.float64)
            listing.chunk(index, first, TH + ZZZ * DELTA, count)
            total += stop - first
            if progress is not None:
                progress(total)
        if max_sheets is not None and total >= max_sheets and index + 1 < cards:
            raise SheetLimit(total)
    return total
