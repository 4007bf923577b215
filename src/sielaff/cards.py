"""The card reader: a deck of 80-column cards read with ``FORMAT(4F8.4)``.

The program reads its data with ``READ(1,19) list`` and ``19 FORMAT(4F8.4)``.
A deck here is a text file, one card per line.

Cards (lines)
    Columns 1-32 hold four 8-column fields (1-8, 9-16, 17-24, 25-32); columns
    33-80 are never read (they often hold a sequence number in 73-80).  A READ
    converts only as many fields as its list has items: ``READ W2,W3,W4`` never
    looks at field 4, so whatever is punched there is ignored.  A short line
    is padded with blanks to 80 columns; columns past 80 are ignored with a
    warning (``Deck.warnings``).  CRLF line ends are accepted.  A tab is an
    error (a card has no tabs), and so are non-ASCII and control characters
    anywhere on the line.  NUL bytes or bytes that are not UTF-8 make the
    file "not a text deck"; the message gives the byte offset (counted from 0).

Blank lines
    A blank line is a card of blanks, i.e. all zeros, except at the end of the
    file: lines that are empty or hold only blanks after the last non-blank
    card are not cards (the file's trailing newline, editor padding).
    Dropping a line of blanks there adds a warning; dropping an empty line
    does not.

Fw.d input (``read_field``), as the FORTRAN input routines of the period
    * Leading blanks are ignored; every other blank in the field reads as
      ``0``.  So ``"   1 5  "`` is ``00010500`` = 1.05 for F8.4, and a field
      of blanks is 0.0.
    * An optional sign (``+``/``-``) comes first.
    * No decimal point: the last d digits of the mantissa are the fraction
      (``"   30000"`` is 3.0, ``"12      "`` is ``12000000`` = 1200.0).
      An explicit point overrides d (``"     3.0"`` is 3.0).
    * Optional exponent: ``E`` or ``D`` (either case) with an optional sign,
      or a bare sign (``1.5+2`` = 1.5E+2).  Blanks before the exponent's sign
      are skipped, blanks after its first digit are zeros, so a left-justified
      ``"1.5E2   "`` is 1.5E2000 (rejected as out of range: right-justify
      exponents).  Without a point the implied decimal applies to the
      mantissa: ``"   15E+2"`` is .0015E+2 = 0.15.
    * The mantissa needs at least one punched digit (a lone sign or point is
      an error), and so does an exponent.  Any other character, two decimal
      points, a point in the exponent, or a second exponent is an error.
    * The value must be 0 or lie in the IBM 1410 range 1E-100 <= |x| < 1E99.
    * When blanks after the first punched character change the value (a
      left-justified ``"12      "``, an exponent ``"1.5+2 "``), the deck
      still reads them as zeros but ``Deck.warnings`` says so.
    * Values are converted exactly with ``decimal.Decimal`` (kept in
      ``Deck.exact``) and then to float; a negative zero reads as 0.0.

Deck layout (report p. 17): card 1 W2 W3 W4, card 2 ZI2 ZI3 ZI4, card 3
R1 R2 R3 R4, card 4 ADEL2 ADEL3 ADEL4, card 5 RG2 RG3 RG4, card 6 TH2D, then
one or more range cards THZERO DELTA THMAX.  Nothing is validated here
beyond the card format (the crank-rocker test and DELTA belong to the
program).  Every problem is a one-line :class:`DeckError`.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from decimal import Decimal
from typing import NamedTuple

from sielaff.mechanism import FIELD_NAMES, Mechanism

__all__ = [
    "PARAMETER_CARDS", "Deck", "DeckError", "Range", "RangeCard",
    "parse_card", "parse_deck", "read_deck", "read_field", "read_field_decimal",
]

COLUMNS = 80
WIDTH, FIELDS, DIGITS = 8, 4, 4  # FORMAT(4F8.4)

#: The names read from each of the six parameter cards, in order.
PARAMETER_CARDS: tuple[tuple[str, ...], ...] = (
    ("W2", "W3", "W4"),
    ("ZI2", "ZI3", "ZI4"),
    ("R1", "R2", "R3", "R4"),
    ("ADEL2", "ADEL3", "ADEL4"),
    ("RG2", "RG3", "RG4"),
    ("TH2D",),
)
RANGE_NAMES = ("THZERO", "DELTA", "THMAX")

_SMALLEST, _OVERFLOW = Decimal("1E-100"), Decimal("1E99")


class DeckError(Exception):
    """A deck that cannot be read; ``str(err)`` is a one-line message."""

    def __init__(self, path: str, reason: str, card: int | None = None,
                 columns: tuple[int, int] | None = None, text: str | None = None) -> None:
        self.path, self.reason, self.card, self.columns, self.text = (
            path, reason, card, columns, text)
        msg = path
        if card is not None:
            msg += f": card {card}"
        if columns is not None:
            first, last = columns
            msg += f", column {first}" if first == last else f", columns {first}-{last}"
            if text is not None and last > first:
                msg += f': "{text.ljust(last)[first - 1:last]}"'
        super().__init__(f"{msg}: {reason}")


class Range(NamedTuple):
    """One range card: crank angles THZERO, THZERO+DELTA, ... up to THMAX (degrees)."""

    THZERO: float
    DELTA: float
    THMAX: float


RangeCard = Range


@dataclass
class Deck:
    """A deck read with ``FORMAT(4F8.4)``.

    ``ranges[i]`` came from card ``range_cards[i]`` (1-based).  ``exact`` holds
    the 17 mechanism values and ``exact_ranges`` the range values as the exact
    decimals punched on the cards.
    """

    mechanism: Mechanism
    ranges: list[Range]
    range_cards: list[int]
    path: str
    warnings: list[str] = field(default_factory=list)
    exact: dict[str, Decimal] = field(default_factory=dict)
    exact_ranges: list[tuple[Decimal, Decimal, Decimal]] = field(default_factory=list)


def read_field_decimal(text: str, d: int = DIGITS) -> Decimal:
    """The exact value of one Fw.d field (w = ``len(text)``); ValueError(reason) if bad."""
    s = text.lstrip(" ")
    if not s:
        return Decimal(0)
    for c in s:
        if c not in "0123456789+-.EeDd ":
            raise ValueError(f"not a number (character {c!a})")
    sign = ""
    if s[0] in "+-":
        sign, s = s[0].replace("+", ""), s[1:]
        if not s.strip(" "):
            raise ValueError("not a number (a sign and no digits)")
    cut = next((i for i, c in enumerate(s) if c in "+-EeDd"), len(s))
    mantissa, exponent = s[:cut], s[cut:]
    if mantissa.count(".") > 1:
        raise ValueError("not a number (two decimal points)")
    if not any(c.isdigit() for c in mantissa):
        raise ValueError("not a number (no digits" + (" before the exponent)" if exponent else ")"))
    e, hint = 0, ""
    if exponent:
        body = (exponent[1:] if exponent[0] in "EeDd" else exponent).lstrip(" ")
        esign = ""
        if body[:1] in ("+", "-"):
            esign, body = body[0], body[1:]
        if "." in body:
            raise ValueError("not a number (decimal point in the exponent)")
        if any(c in "+-EeDd" for c in body):
            raise ValueError(f"not a number (bad exponent {exponent.strip()!r})")
        if not any(c.isdigit() for c in body):
            raise ValueError("not a number (exponent without digits)")
        if " " in body:
            hint = "; blanks in the exponent read as zeros: right-justify the field"
        e = int(esign + body.replace(" ", "0"))
    m = mantissa.replace(" ", "0")
    whole, point, fraction = m.partition(".")
    scale = len(fraction) if point else d
    value = Decimal(f"{sign}{whole}{fraction}E{e - scale}")
    if value and not _SMALLEST <= abs(value) < _OVERFLOW:
        raise ValueError(f"out of range ({value:E}; the IBM 1410 holds 1E-100 <= |x| < 1E99{hint})")
    return value


def read_field(text: str, d: int = DIGITS) -> float:
    """One Fw.d field (w = ``len(text)``) as a float; ValueError(reason) on bad content."""
    return float(read_field_decimal(text, d)) + 0.0  # + 0.0 turns -0.0 into 0.0


def _implied_decimal_trap(chars: str, value: Decimal) -> str | None:
    """The warning for an F8.4 field whose implied decimals look unintended, or None.

    The classic mistake is an integer typed right-justified with no decimal point
    (``"      10"`` for 10.0): FORTRAN reads it with 4 implied decimals, as 0.0010.
    The rule: no decimal point, no exponent, not zero, and the value reads below 1.
    A deliberate implied-decimal entry, as 1960s decks punched them, is usually a
    value of 1 or more (``"   30000"`` for 3.0, ``"  120000"`` for 12.0) and is not
    flagged; a deliberate one below 1 (``"    5000"`` for 0.5) gets the warning,
    which says how it was read, and the deck still runs.
    """
    body = chars.strip(" ")
    if not value or "." in body or any(c in body for c in "EeDd") or "+" in body[1:] \
            or "-" in body[1:] or abs(value) >= 1:
        return None
    digits = body.lstrip("+-").replace(" ", "0")
    meant = f"{'-' if value < 0 else ''}{int(digits)}.0"
    return (f"no decimal point: read as {value:f} (F8.4 implies 4 decimals); "
            f"did you mean {meant}?")


def _card_decimals(text: str, n: int, card_no: int, path: str,
                   warnings: list[str] | None = None) -> list[Decimal]:
    text = text.ljust(COLUMNS)
    values = []
    for k in range(n):
        first, last = k * WIDTH + 1, (k + 1) * WIDTH
        columns, chars = (first, last), text[first - 1:last]
        try:
            value = read_field_decimal(chars)
        except ValueError as err:
            raise DeckError(path, str(err), card_no, columns, text) from None
        values.append(value)
        if warnings is not None and (trap := _implied_decimal_trap(chars, value)):
            warnings.append(str(DeckError(path, trap, card_no, columns, text)))
        if warnings is not None and " " in chars.lstrip(" "):
            try:
                packed = read_field_decimal(chars.replace(" ", "").rjust(WIDTH))
            except ValueError:
                packed = None
            if packed != value:
                warnings.append(str(DeckError(
                    path, f"blanks read as zeros ({value}; right-justified it would be {packed})",
                    card_no, columns, text)))
    return values


def parse_card(text: str, n: int, card_no: int, path: str) -> list[float]:
    """The first ``n`` fields of a 4F8.4 card; fields past ``n`` are not looked at."""
    if not 0 <= n <= FIELDS:
        raise ValueError(f"a 4F8.4 card has 4 fields, not {n}")
    return [float(v) + 0.0 for v in _card_decimals(text, n, card_no, path)]


def _cards(data: bytes, path: str, warnings: list[str]) -> list[str]:
    """Split a deck file into card images (80 columns each), checking characters."""
    nul = data.find(b"\0")
    if nul >= 0:
        raise DeckError(path, f"not a text deck (binary data at byte {nul})")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise DeckError(path, f"not a text deck (binary data at byte {err.start})") from None
    lines = [line.removesuffix("\r") for line in text.split("\n")]
    while lines and not lines[-1].strip(" "):
        lines.pop()
    warnings.extend(f"{path}: card {n}: blank line at end of file ignored"
                    for n, line in enumerate(text.split("\n")[len(lines):], len(lines) + 1)
                    if line.strip("\r"))
    cards = []
    for n, line in enumerate(lines, 1):
        for col, c in enumerate(line, 1):
            if c == "\t":
                reason = "tab character (cards have no tabs; use blanks)"
            elif ord(c) > 127:
                reason = f"non-ASCII character {c!a}"
            elif ord(c) < 32 or ord(c) == 127:
                reason = f"control character {c!a}"
            else:
                continue
            raise DeckError(path, reason, n, (col, col), line)
        if len(line) > COLUMNS:
            warnings.append(f"{path}: card {n}: {len(line)} columns, "
                            f"columns {COLUMNS + 1}-{len(line)} ignored")
        cards.append(line[:COLUMNS].ljust(COLUMNS))
    return cards


def parse_deck(text: str | bytes, path: str = "<deck>") -> Deck:
    """Read a deck from its content (``str`` or the file's ``bytes``)."""
    path = os.fspath(path)
    data = text.encode("utf-8", "surrogatepass") if isinstance(text, str) else bytes(text)
    warnings: list[str] = []
    cards = _cards(data, path, warnings)
    if not cards:
        raise DeckError(path, "empty deck (no cards)")
    exact: dict[str, Decimal] = {}
    for n, names in enumerate(PARAMETER_CARDS, 1):
        if n > len(cards):
            raise DeckError(path, "deck ends inside the parameter cards "
                            f"(expected {' '.join(names)})", n)
        exact.update(zip(names, _card_decimals(cards[n - 1], len(names), n, path, warnings)))
    if len(cards) == len(PARAMETER_CARDS):
        raise DeckError(path, f"deck ends before the first range card ({' '.join(RANGE_NAMES)})")
    range_cards = list(range(len(PARAMETER_CARDS) + 1, len(cards) + 1))
    exact_ranges: list[tuple[Decimal, Decimal, Decimal]] = []
    for n in range_cards:
        thzero, delta, thmax = _card_decimals(cards[n - 1], 3, n, path, warnings)
        exact_ranges.append((thzero, delta, thmax))
    mechanism = Mechanism(**{name: float(exact[name]) + 0.0 for name in FIELD_NAMES})
    return Deck(
        mechanism=mechanism,
        ranges=[Range(*(float(v) + 0.0 for v in r)) for r in exact_ranges],
        range_cards=range_cards,
        path=path,
        warnings=warnings,
        exact={name: exact[name] for name in FIELD_NAMES},
        exact_ranges=exact_ranges,
    )


def read_deck(path: str | os.PathLike[str]) -> Deck:
    """Read a deck file; an unreadable file is a DeckError too (``reason`` says why)."""
    name = os.fspath(path)
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as err:
        raise DeckError(name, f"cannot read the deck ({err.strerror or err})") from err
    return parse_deck(data, name)
