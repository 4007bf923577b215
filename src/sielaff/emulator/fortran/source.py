"""Reading a FORTRAN source deck card by card, as the 1410 compiler read it: statement
numbers, continuations, comments, blanks squeezed out (a FORMAT keeps its own)."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from sielaff.emulator.printer import RECORDS_PER_SHEET as _RECORDS_PER_SHEET
from sielaff.emulator.printer import Format

LIBRARY = ("SIN", "COS", "ATAN", "SQRT", "ABS")
INTEGER_FUNCTIONS = ("FLOAT", "IFIX", "INT", "IABS", "MOD")
# -- the interpreter's budget (docs/interpreter.md, docs/robustness.md) ----------------
#: Statements executed (a ``**`` counts its multiplications) without a line printed before
#: the run is called a loop that never ends (the port's ARCCOS gives up after 10,000 terms:
#: about 80,000 statements).
STATEMENT_BUDGET = 1_000_000
#: Statements executed in all, per sheet the run may print (the deck's sheets, or
#: ``--max-sheets``), plus one sheet's worth: ``decks/sielaff.f`` runs about 640 a sheet.
STATEMENTS_PER_SHEET = 1_000_000
#: Sheets (page ejects) a run may print without ``--max-sheets``: this many per sheet the
#: deck's range cards ask for, plus as many again (an edit may print more than one page a
#: crank angle, or a page of its own).
SHEETS_PER_DECK_SHEET = 10
#: Records (lines) printed between two page ejects: ``printer.RECORDS_PER_SHEET``.
RECORDS_PER_SHEET = _RECORDS_PER_SHEET
#: An integer holds at most this many decimal digits (the 1410's integer size is not in
#: the sources at hand: this is the interpreter's, far past the port's sheet count).
INTEGER_DIGITS = 20
INTEGER_LIMIT = 10**INTEGER_DIGITS
#: Characters of a program deck (about 12,500 cards of 80 columns; decks/sielaff.f has
#: 308 cards).
SOURCE_LIMIT = 1_000_000


class FortranError(Exception):
    """A deck the interpreter cannot compile or run; ``str(err)`` is one line."""


@dataclass
class Statement:
    """One source statement: where it is (card, column of each character), its number."""

    card: int
    label: int | None
    text: str                   # blanks removed (a FORMAT keeps its own)
    cols: list[tuple[int, int]]  # (card, column) of each character of ``text``
    kind: str = ""
    data: tuple = ()

    def where(self, i: int = 0) -> str:
        card, col = self.cols[min(i, len(self.cols) - 1)] if self.cols else (self.card, 7)
        return f"card {card}, column {col}"


@dataclass
class Unit:
    """A program unit: the main program, a FUNCTION or a SUBROUTINE."""

    kind: str                  # "MAIN", "FUNCTION", "SUBROUTINE"
    name: str
    args: list[str]
    statements: list[Statement] = field(default_factory=list)
    labels: dict[int, int] = field(default_factory=dict)
    formats: dict[int, Format] = field(default_factory=dict)
    code: list = field(default_factory=list)
    head: Statement | None = None  # the FUNCTION or SUBROUTINE card (None: the main program)
    consts: dict = field(default_factory=dict)  # the deck's constants, in the model


# -- reading the cards ---------------------------------------------------------

def _statements(text: str, path: str) -> list[Statement]:
    out: list[Statement] = []
    if len(text) > SOURCE_LIMIT:
        cards = text.count("\n", 0, SOURCE_LIMIT) + 1
        raise FortranError(f"{path}: card {cards}: the program deck is longer than "
                           f"{SOURCE_LIMIT:,} characters (the interpreter's limit)")
    # Cards end at a newline only: a form feed, a vertical tab or a file separator is a
    # character on the card (refused below, naming it), never a card break of its own.
    for n, raw in enumerate(text.split("\n"), 1):
        line = raw.removesuffix("\r")
        bad = re.search(r"[^\x20-\x7e]", line)
        if bad:
            c = bad.group()
            what = ("tab character (cards have no tabs; use blanks)" if c == "\t" else
                    f"control character {c!a}" if c < " " or c == "\x7f" else
                    f"character {c!a} is not on a card punch")
            raise FortranError(f"{path}: card {n}, column {bad.start() + 1}: {what}")
        if not line.strip() or line[:1] in "Cc*":
            continue
        line = line[:72].ljust(72)
        label_text, mark, body = line[:5], line[5], line[6:72]
        cols = [(n, 7 + i) for i in range(len(body))]
        if mark not in " 0":
            if not out:
                raise FortranError(f"{path}: card {n}, column 6: a continuation card with "
                                   "no statement before it")
            if label_text.strip():
                raise FortranError(f"{path}: card {n}, columns 1-5: a continuation card "
                                   "has no statement number")
            out[-1].text += body
            out[-1].cols += cols
            continue
        label = None
        if label_text.strip():
            digits = label_text.replace(" ", "")
            if not digits.isdigit():
                col = next(i for i, c in enumerate(label_text) if c != " " and not
                           c.isdigit()) + 1
                raise FortranError(f"{path}: card {n}, column {col}: statement number "
                                   f"{label_text.strip()!r} is not a number")
            label = int(digits)
        out.append(Statement(n, label, body, cols))
    for st in out:  # blanks out, except in a FORMAT (its Hollerith text keeps them)
        squeezed = "".join(c for c in st.text if c != " ")
        if squeezed.startswith("FORMAT("):
            first = next(i for i, c in enumerate(st.text) if c != " ")
            st.text, st.cols = st.text[first:].rstrip(), st.cols[first:]
            st.kind = "FORMAT"
        else:
            keep = [i for i, c in enumerate(st.text) if c != " "]
            st.cols = [st.cols[i] for i in keep]
            st.text = squeezed
    return out


def implicit_type(name: str) -> str:
    return "I" if name[0] in "IJKLMN" else "R"


