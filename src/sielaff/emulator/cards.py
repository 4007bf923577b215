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
    does not.  A run of blank lines is counted, not kept, and a deck holds at
    most ``MAX_RANGE_CARDS`` range cards: a longer one (blank lines count until
    the deck ends, so a pipe of endless blank lines too) is one DeckError.

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

import io
import itertools
import os
import re
from array import array
from collections.abc import Sequence
from dataclasses import dataclass, field
from decimal import Decimal
from typing import NamedTuple

from sielaff.mechanism import FIELD_NAMES, Mechanism

__all__ = [
    "PARAMETER_CARDS", "Deck", "DeckError", "Range", "RangeCard",
    "parse_card", "parse_deck", "read_deck", "read_deck_stream", "read_field",
    "read_field_decimal",
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
        if s.lstrip(" ")[:1] in ("+", "-"):
            raise ValueError("not a number (two signs)")
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
        meant = Decimal(f"{sign}{whole}E{e}") if whole else value
        if not point and exponent and _SMALLEST <= abs(meant) < _OVERFLOW:
            hint += (f"; with no decimal point F8.4 reads the mantissa {whole} as "
                     f"{Decimal(whole).scaleb(-d)}: write {whole}.{exponent.strip()}")
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


#: The most of one line read (a card is 80 columns; the rest of a longer line is skipped,
#: a block at a time, and counted for the warning).
LINE_LIMIT = 4096
#: Warnings kept in ``Deck.warnings``; past this one line says how many more there were.
MAX_WARNINGS = 100
#: Range cards a deck may hold (24 + 24 bytes each in memory: about 48 MB at the limit).
#: Lines past the six parameter cards and this many are refused, blank ones too, so a
#: deck from a pipe that never ends stops with one line, at flat memory.
MAX_RANGE_CARDS = 1_000_000

_BAD_CHARACTER = re.compile(r"[^ -~]")
#: A field of the usual form (blanks, a sign, digits with a decimal point): its value is
#: its text, and no warning can apply.
_PLAIN_FIELD = re.compile(r" *[-+]?(?:\d+\.\d*|\.\d+)")


class _View(Sequence):
    """A read-only sequence that compares equal to a list of the same items."""

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Sequence) and not isinstance(other, str):
            return len(self) == len(other) and all(a == b for a, b in zip(self, other))
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(len(self)))]
        n = len(self)
        if not -n <= i < n:
            raise IndexError(i)
        return self._item(i % n)

    def _item(self, i: int):
        raise NotImplementedError

    def __repr__(self) -> str:
        return f"[{', '.join(map(repr, self[:5]))}{', ...' if len(self) > 5 else ''}]"


class RangeList(_View):
    """The range cards' values, packed: 24 bytes a card, however many cards."""

    def __init__(self, values: array) -> None:
        self._v = values

    def __len__(self) -> int:
        return len(self._v) // 3

    def _item(self, i: int) -> Range:
        return Range(*self._v[3 * i:3 * i + 3])


class ExactRangeList(_View):
    """The range cards' exact decimals, read from their 24 columns when asked for."""

    def __init__(self, text: bytearray) -> None:
        self._t = text

    def __len__(self) -> int:
        return len(self._t) // 24

    def _item(self, i: int) -> tuple[Decimal, Decimal, Decimal]:
        card = self._t[24 * i:24 * i + 24].decode("ascii")
        return tuple(read_field_decimal(card[k:k + 8]) for k in (0, 8, 16))


class CardNumbers(_View):
    """The range cards' line numbers: consecutive, so two integers hold them all."""

    def __init__(self, first: int, last: int) -> None:
        self._r = range(first, last + 1)

    def __len__(self) -> int:
        return len(self._r)

    def _item(self, i: int) -> int:
        return self._r[i]


def _lines(f, path: str, warnings: list[str]):
    """(line number, text) of a deck file, each line read only as far as a card needs;
    the characters are checked (one DeckError naming card and column)."""
    offset = 0
    for n in itertools.count(1):
        raw = f.readline(LINE_LIMIT)
        if not raw:
            return
        start, length = offset, len(raw)
        offset += len(raw)
        nul = raw.find(b"\0")
        if nul >= 0:  # before skipping anything: /dev/zero has no line end
            raise DeckError(path, f"not a text deck (binary data at byte {start + nul})")
        cut = not raw.endswith(b"\n") and len(raw) == LINE_LIMIT
        if cut:  # a long line: skip the rest
            while True:
                more = f.readline(LINE_LIMIT)
                offset += len(more)
                length += len(more)
                at = more.find(b"\0")
                if at >= 0:
                    raise DeckError(path, "not a text deck (binary data at byte "
                                    f"{offset - len(more) + at})")
                if not more or more.endswith(b"\n"):
                    break
        try:
            line = raw.decode("utf-8")
        except UnicodeDecodeError as err:
            if not cut or err.start < len(raw) - 3:  # not merely a character cut short
                raise DeckError(path, "not a text deck (binary data at byte "
                                f"{start + err.start})") from None
            line = raw[:err.start].decode("utf-8")
        line = line.removesuffix("\n").removesuffix("\r")
        bad = _BAD_CHARACTER.search(line)
        if bad:
            c, col = bad.group(), bad.start() + 1
            if c == "\t":
                reason = "tab character (cards have no tabs; use blanks)"
            elif ord(c) > 127:
                reason = f"non-ASCII character {c!a}"
            else:
                reason = f"control character {c!a}"
            raise DeckError(path, reason, n, (col, col), line)
        width = length - (1 if raw.endswith(b"\n") or length > len(raw) else 0)
        if line.endswith("\r"):
            width -= 1
        if width > COLUMNS:
            _warn(warnings, f"{path}: card {n}: {width} columns, "
                            f"columns {COLUMNS + 1}-{width} ignored")
        yield n, line[:COLUMNS]


def _warn(warnings: list[str], text: str) -> None:
    if len(warnings) < MAX_WARNINGS:
        warnings.append(text)
    elif len(warnings) == MAX_WARNINGS:
        warnings.append(f"(more warnings like these; only the first {MAX_WARNINGS} are shown)")


def _read(f, path: str) -> Deck:
    """A deck from a binary stream, read card by card at flat memory."""
    warnings: list[str] = []
    exact: dict[str, Decimal] = {}
    values, texts = array("d"), bytearray()
    # Blank lines since the last card: cards if another card follows, else dropped.  Kept
    # as a count (they are all the same card) and the first line numbers of those that
    # hold blanks (for the warnings), so a run of them costs no memory.
    limit = len(PARAMETER_CARDS) + MAX_RANGE_CARDS
    last = 0
    padded: list[int] = []
    for n, line in _lines(f, path, warnings):
        if n > limit:
            raise DeckError(path, f"more than {MAX_RANGE_CARDS:,} range cards (the reader's "
                            "limit; blank lines count until the deck ends)", n)
        if not line.strip(" "):
            if line and len(padded) <= MAX_WARNINGS:
                padded.append(n)
            continue
        for blank in range(last + 1, n):
            _card(blank, "", path, warnings, exact, values, texts)
        _card(n, line, path, warnings, exact, values, texts)
        padded.clear()
        last = n
    for n in padded:
        _warn(warnings, f"{path}: card {n}: blank line at end of file ignored")
    if last == 0:
        raise DeckError(path, "empty deck (no cards)")
    if last < len(PARAMETER_CARDS):
        names = PARAMETER_CARDS[last]
        raise DeckError(path, "deck ends inside the parameter cards "
                        f"(expected {' '.join(names)})", last + 1)
    if last == len(PARAMETER_CARDS):
        raise DeckError(path, f"deck ends before the first range card ({' '.join(RANGE_NAMES)})")
    mechanism = Mechanism(**{name: float(exact[name]) + 0.0 for name in FIELD_NAMES})
    return Deck(mechanism=mechanism, ranges=RangeList(values),
                range_cards=CardNumbers(len(PARAMETER_CARDS) + 1, last), path=path,
                warnings=warnings, exact={name: exact[name] for name in FIELD_NAMES},
                exact_ranges=ExactRangeList(texts))


def _card(n: int, line: str, path: str, warnings: list[str], exact: dict,
          values: array, texts: bytearray) -> None:
    text = line.ljust(COLUMNS)
    if n <= len(PARAMETER_CARDS):
        names = PARAMETER_CARDS[n - 1]
        exact.update(zip(names, _card_decimals(text, len(names), n, path, warnings)))
        return
    fields = (text[0:8], text[8:16], text[16:24])
    if all(_PLAIN_FIELD.fullmatch(x) for x in fields):  # the usual card: nothing to warn
        parsed = [float(x) + 0.0 for x in fields]
        if not all(v == 0.0 or 1e-100 <= abs(v) < 1e99 for v in parsed):
            _card_decimals(text, 3, n, path, warnings)  # says which field is out of range
    else:
        mine: list[str] = []
        parsed = [float(v) + 0.0 for v in _card_decimals(text, 3, n, path, mine)]
        for w in mine:
            _warn(warnings, w)
    values.extend(parsed)
    texts += text[:24].encode("ascii")


def parse_deck(text: str | bytes, path: str = "<deck>") -> Deck:
    """Read a deck from its content (``str`` or the file's ``bytes``)."""
    path = os.fspath(path)
    data = text.encode("utf-8", "surrogatepass") if isinstance(text, str) else bytes(text)
    return _read(io.BytesIO(data), path)


def read_deck_stream(stream, path: str) -> Deck:
    """Read a deck from a binary stream with ``readline(limit)`` (standard input), card by
    card at flat memory as :func:`read_deck` reads a file; ``path`` names it in errors."""
    try:
        return _read(stream, path)
    except OSError as err:
        raise DeckError(path, f"cannot read the deck ({err.strerror or err})") from err


def read_deck(path: str | os.PathLike[str]) -> Deck:
    """Read a deck file; an unreadable file is a DeckError too (``reason`` says why)."""
    name = os.fspath(path)
    try:
        with open(path, "rb") as f:
            return _read(f, name)
    except OSError as err:
        raise DeckError(name, f"cannot read the deck ({err.strerror or err})") from err
