"""Read printed listings back: sheets, fields, and a field-aware diff.

For people who hold old printouts: a listing (ours, or a transcription of
a 1966 sheet) is split into sheets at the page-eject record ``1``, each
sheet's sections are found by their headings, and each printed field is
named after the listing variable it shows.  ``diff_sheets`` matches
sheets by THETA 2, in order, and reports each differing field with the
difference in units of the last printed digit.  Both read a stream
(``iter_sheets``), so a listing of any length is compared at flat memory; the
``--render`` form (form feeds, no carriage control) reads the same
(``asa_records``).
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from decimal import Decimal, InvalidOperation

from sielaff.emulator.printer import RECORDS_PER_SHEET

#: The longest line read: a listing line is 133 characters, a longer one is not a listing.
LINE_LIMIT = 1 << 16

#: heading text -> (field names per value line, kind of each line: "E" or "F")
SECTIONS: dict[str, tuple[tuple[tuple[str, ...], str], ...]] = {
    "THETA 2": ((("ATH2", "ATH3", "ATH4"), "F"),),
    "ANG VEL 3": ((("TH3D", "TH4D", "TH3DD", "TH4DD"), "E"),),
    "EX TORQ ON 4": ((("TEX",), "E"),),
    "VEL G2": ((("VG2", "VA", "VG3", "VB", "VG4"), "E"),
               (("DVG2", "DVA", "DVG3", "DVB", "DVG4"), "F")),
    "ACC G2": ((("AG2", "AA", "AG3", "AB", "AG4"), "E"),
               (("DAG2", "DAA", "DAG3", "DAB", "DAG4"), "F")),
    "F 3 ON 2": ((("FA32", "FB34", "FOA", "FOB"), "E"),
                 (("DFA32", "DFB34", "DFOA", "DFOB"), "F")),
    "SHAKE": ((("SHAK", "SHAKX", "SHAKY"), "E"), (("DSHAK",), "F")),
    "DRIVING TORQ": ((("TORQ",), "E"),),
}

#: Printed heading of each field, for messages.
LABELS = {
    "ATH2": "THETA 2", "ATH3": "THETA 3", "ATH4": "THETA 4",
    "TH3D": "ANG VEL 3", "TH4D": "ANG VEL 4", "TH3DD": "ANG ACC 3", "TH4DD": "ANG ACC 4",
    "TEX": "EX TORQ ON 4", "TORQ": "DRIVING TORQ",
    "SHAK": "SHAKE", "SHAKX": "X SHAKE", "SHAKY": "Y SHAKE", "DSHAK": "SHAKE direction",
    "FA32": "F 3 ON 2", "FB34": "F 3 ON 4", "FOA": "F 2 ON 1", "FOB": "F 4 ON 1",
}
for _p, _h in (("V", "VEL"), ("A", "ACC")):
    for _n, _pt in (("G2", "G2"), ("", "A"), ("G3", "G3"), ("B", "B"), ("G4", "G4")):
        _name = (_p + _n) if _n else (_p + "A")
        LABELS[_name] = f"{_h} {_pt}"
        LABELS["D" + _name] = f"{_h} {_pt} direction"
for _f in ("FA32", "FB34", "FOA", "FOB"):
    LABELS["D" + _f] = LABELS[_f] + " direction"

# Data lines: E fields start after 15X, F fields after 11X; both 12 wide.
_START = {"E": 15, "F": 11}
_WIDTH = 12


class ListingError(ValueError):
    """Text that is not a listing in the 1966 layout."""


@dataclass
class Field:
    """One printed field: its text as printed and the kind of edit (E or F)."""

    text: str
    kind: str

    def value(self) -> Decimal | None:
        t = self.text.strip()
        if not t or set(t) == {"*"}:
            return None
        if self.kind == "E":
            mantissa, _, exp = t.partition("E")
            t = f"{mantissa}E{exp.replace(' ', '+')}"
        try:
            return Decimal(t)
        except InvalidOperation:
            return None

    def unit(self) -> Decimal:
        """One unit in the last printed digit."""
        if self.kind == "F":
            return Decimal("0.1")
        v = self.value()
        exp_text = self.text.strip().partition("E")[2].replace(" ", "+")
        exp = int(exp_text or 0) if v is not None else 0
        return Decimal(1).scaleb(exp - 4)


@dataclass
class Sheet:
    """One printed sheet: fields by listing name, and the line number it started on."""

    fields: dict[str, Field] = field(default_factory=dict)
    line: int = 0
    message: str = ""

    @property
    def theta2(self) -> str:
        f = self.fields.get("ATH2")
        return f.text.strip() if f else "?"


def listing_lines(f, limit: int = LINE_LIMIT) -> Iterator[str]:
    """The lines of the text file ``f``, read at most ``limit`` characters at a time: a
    longer line, or a NUL character (``/dev/zero``, a binary file), is a ListingError at
    once, so a file with no line ends is never read whole, nor read for ever."""
    for n in itertools.count(1):
        line = f.readline(limit)
        if not line:
            return
        if "\0" in line:
            raise ListingError(f"line {n}: not a listing (binary data: a NUL character)")
        if len(line) == limit and not line.endswith("\n"):
            raise ListingError(f"line {n}: longer than {limit:,} characters, not a listing "
                               "(a listing line is 133)")
        yield line


def asa_records(lines: Iterable[str]) -> Iterator[str]:
    """ASA records from the lines of a listing, either as ``sielaff run`` prints it (ASA
    carriage control in column 1) or as ``--render`` prints it (plain text, a form feed
    where a page begins): a rendered file is told by a form feed in its first 200 lines,
    and turned back into records, so both read the same."""
    it = iter(lines)
    head = list(itertools.islice(it, 200))
    rest = itertools.chain(head, it)
    if not any("\f" in line for line in head):
        yield from (line.rstrip("\r\n") for line in rest)
        return
    for line in rest:
        line = line.rstrip("\r\n")
        while "\f" in line:
            before, _, line = line.partition("\f")
            if before:
                yield " " + before
            yield "1"
        if line:
            yield " " + line


def iter_sheets(records: Iterable[str]) -> Iterator[Sheet]:
    """Sheets of a listing, one at a time, from its ASA records (see module doc).  A page
    eject with nothing before it (a listing that starts with ``1``) makes no sheet."""
    sheet = Sheet(line=1)
    pending: list[tuple[tuple[str, ...], str]] = []
    for lineno, record in enumerate(records, 1):
        control, body = record[:1], record[1:]
        stripped = body.strip()
        if control == "1":
            if sheet.fields or sheet.message:
                yield sheet
            sheet = Sheet(line=lineno + 1)
            pending = []
            continue
        if lineno - sheet.line >= RECORDS_PER_SHEET:  # a sheet has 59: bounded time
            raise ListingError(f"line {lineno}: more than {RECORDS_PER_SHEET:,} lines with "
                               "no page eject: not a listing")
        if not stripped:
            continue
        heading = next((h for h in SECTIONS if stripped.startswith(h)), None)
        if heading is not None:
            pending = list(SECTIONS[heading])
            continue
        if "CRANK ROCKER" in stripped:
            sheet.message = stripped
            continue
        if not pending:
            raise ListingError(f"line {lineno}: values with no heading above them: {stripped!r}")
        names, kind = pending.pop(0)
        start = _START[kind]
        for k, name in enumerate(names):
            chunk = record[start + k * _WIDTH: start + (k + 1) * _WIDTH]
            sheet.fields[name] = Field(chunk, kind)
    if sheet.fields or sheet.message:
        yield sheet


def parse_listing(text: str) -> list[Sheet]:
    """Split listing text (ASA or rendered) into sheets and fields (see module doc)."""
    return list(iter_sheets(asa_records(text.splitlines())))


def _units(got: Field, want: Field) -> str:
    g, w = got.value(), want.value()
    if g is None or w is None:
        return "not comparable"
    # in the finer of the two last digits: .9999E 02 against .1000E 03 is 1 unit of .01
    n = (g - w) / min(got.unit(), want.unit())
    # quantize needs every digit in the context's precision: a difference of many orders
    # (a listing of another TEX against the golden) is printed as it is, normalized
    whole = n == n.to_integral_value() and (n == 0 or n.adjusted() < 25)
    n = n.quantize(Decimal(1)) if whole else n.normalize()
    return f"{'+' if n > 0 else ''}{n} unit{'' if abs(n) == 1 else 's'} in the last digit"


def diff_listings(listing: str, golden: str) -> list[str]:
    """One line per field of ``golden`` that ``listing`` prints differently (both text)."""
    return list(diff_sheets(iter_sheets(asa_records(listing.splitlines())),
                            iter_sheets(asa_records(golden.splitlines()))))


def diff_sheets(listing: Iterable[Sheet], golden: Iterable[Sheet]) -> Iterator[str]:
    """One line per field of the ``golden`` sheets that ``listing`` prints differently.

    Both are streams of sheets, read once and in order, so memory stays flat however long
    the listings: each golden sheet is matched with the next listing sheet that has its
    THETA 2 (the golden may hold only some sheets, in the listing's order); one the
    listing does not have is reported, and so is every golden sheet after it.  Fields
    that both print are compared by their printed text.
    """
    got_sheets = iter(listing)
    for want in golden:
        key = want.theta2
        where = f"THETA 2 = {key}"
        got = next((s for s in got_sheets if s.theta2 == key), None)
        if got is None:
            yield f"{where}: sheet not in the listing"
            continue
        if want.message != got.message:
            yield f"{where}: message: got {got.message!r}, golden {want.message!r}"
        for name, wf in want.fields.items():
            gf = got.fields.get(name)
            label = f"{name} ({LABELS.get(name, name)})"
            if gf is None:
                yield f"{where}: {label}: not printed, golden {wf.text.strip()}"
            elif gf.text != wf.text:
                yield (f"{where}: {label}: got {gf.text.strip()}, golden "
                       f"{wf.text.strip()} ({_units(gf, wf)})")
