"""The 1410 line printer: FORMAT statements interpreted, numbers edited the 1410 way.

A FORMAT is compiled once into a list of items (literals, skips, edit
descriptors, record ends) and then applied to a WRITE list, producing
records.  Column 1 of every record is ASA carriage control, as FORTRAN
printed it: blank = single space, ``0`` = double space, ``1`` = new page.
An empty record is written as a single blank so that column 1 always
holds a control character.

Number editing follows Figures 10 and 11 of the report:

* fields are truncated, never rounded;
* ``Ew.d`` has no leading zero, a blank for a positive exponent sign and
  the minus sign right before the point: ``   .5456E 03``, ``  -.2707E 02``;
* zero prints as ``.0000E-99`` (the 1410's zero has exponent -99);
* ``Fw.d`` prints values below 1 with no leading zero (``.5``): the figures
  cannot show it, so we follow the E routine, which has none;
* a value that does not fit (or is not finite) fills the field with ``*``.

The digits truncated are those of ``str(value)``: the shortest decimal that
round-trips a binary float (so 0.7 prints ``.7000``), or the exact digits
of a decimal 1410 number.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable

_ITEM = re.compile(r"\s*(?:(\d*)([FE])(\d+)\.(\d+)|(\d*)X|(\d+)H|(/)|(,))", re.IGNORECASE)


class FormatError(ValueError):
    """A FORMAT text this interpreter does not understand."""


def decimal_parts(value) -> tuple[bool, str, int] | None:
    """Split ``value`` into (negative, digits, exponent) with value = 0.digits x 10**exponent.

    ``digits`` has no leading zero ("" for zero).  Returns None for inf/nan.
    """
    text = str(value).strip().lower()
    negative = text.startswith("-")
    if negative or text.startswith("+"):
        text = text[1:]
    if text in ("inf", "infinity", "nan"):
        return None
    mantissa, _, exp_text = text.partition("e")
    exponent = int(exp_text) if exp_text else 0
    whole, _, frac = mantissa.partition(".")
    digits = (whole + frac).lstrip("0")
    if not digits:
        return False, "", 0
    # value = 0.(whole+frac) x 10**(len(whole) + exponent), then drop leading zeros
    exponent += len(whole) - (len(whole + frac) - len((whole + frac).lstrip("0")))
    return negative, digits.rstrip("0") or "0", exponent


def edit_e(value, w: int, d: int) -> str:
    """Ew.d output edit, 1410 style (see module doc)."""
    parts = decimal_parts(value)
    if parts is None:
        return "*" * w
    negative, digits, exponent = parts
    if not digits:
        negative, exponent = False, -99
    if not -99 <= exponent <= 99:
        return "*" * w
    body = "." + (digits[:d]).ljust(d, "0") + "E" + ("-" if exponent < 0 else " ")
    text = ("-" if negative else "") + body + f"{abs(exponent):02d}"
    return text.rjust(w) if len(text) <= w else "*" * w


def edit_f(value, w: int, d: int) -> str:
    """Fw.d output edit, 1410 style: truncated, no leading zero below 1."""
    parts = decimal_parts(value)
    if parts is None:
        return "*" * w
    negative, digits, exponent = parts
    if exponent > 0:
        whole = digits[:exponent].ljust(exponent, "0")
        frac = digits[exponent:]
    else:
        whole = ""
        frac = "0" * (-exponent) + digits
    text = ("-" if negative else "") + whole.lstrip("0") + "." + frac[:d].ljust(d, "0")
    return text.rjust(w) if len(text) <= w else "*" * w


_EDITORS: dict[str, Callable] = {"F": edit_f, "E": edit_e}


def compile_format(text: str) -> list[tuple]:
    """Compile FORMAT text such as ``(//18X,7HTHETA 2/)`` into items.

    Items: ("lit", str), ("edit", editor, w, d), ("/",).
    """
    body = text.strip()
    if not (body.startswith("(") and body.endswith(")")):
        raise FormatError(f"FORMAT must be parenthesised: {text!r}")
    body = body[1:-1]
    items: list[tuple] = []
    pos = 0
    while pos < len(body):
        m = _ITEM.match(body, pos)
        if not m:
            raise FormatError(f"cannot read FORMAT {text!r} at {body[pos:]!r}")
        rep, kind, w, d, nx, nh, slash, _comma = m.groups()
        pos = m.end()
        if kind:
            items += [("edit", _EDITORS[kind.upper()], int(w), int(d))] * int(rep or 1)
        elif nx is not None:
            items.append(("lit", " " * int(nx or 1)))
        elif nh:
            n = int(nh)
            if pos + n > len(body):
                raise FormatError(f"Hollerith field runs past the end of {text!r}")
            items.append(("lit", body[pos:pos + n]))
            pos += n
        elif slash:
            items.append(("/",))
    return items


class Format:
    """A compiled FORMAT statement."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.items = compile_format(text)
        self.n_edits = sum(1 for it in self.items if it[0] == "edit")

    def records(self, values: Iterable = ()) -> list[str]:
        """The records one WRITE with this FORMAT and these values produces."""
        values = list(values)
        if len(values) > self.n_edits:
            # Format reversion is never needed by the 1966 program.
            raise FormatError(f"{len(values)} values for {self.n_edits} fields in {self.text}")
        records: list[str] = []
        line: list[str] = []
        it = iter(values)
        for item in self.items:
            tag = item[0]
            if tag == "lit":
                line.append(item[1])
            elif tag == "edit":
                value = next(it, _END)
                if value is _END:
                    break  # output stops at the first field with no list item
                line.append(item[1](value, item[2], item[3]))
            else:
                records.append("".join(line) or " ")
                line = []
        records.append("".join(line) or " ")
        return records


_END = object()


class AsaRenderer:
    """A text stream that takes ASA records (one per ``write``, newline-terminated)
    and writes plain text, as POSIX ``asa`` does: ``1`` becomes a form feed,
    ``0`` a blank line, ``+`` a carriage return (overprint)."""

    def __init__(self, out) -> None:
        self.out = out
        self.first = True

    def write(self, record: str) -> None:
        record = record.rstrip("\n")
        control, text = record[:1], record[1:]
        if control == "1":
            prefix = "\f" if self.first else "\n\f"
        elif control == "0":
            prefix = "\n" if self.first else "\n\n"
        elif control == "+":
            prefix = "\r"
        else:
            prefix = "" if self.first else "\n"
        self.first = False
        self.out.write(prefix + text)

    def close(self) -> None:
        if not self.first:
            self.out.write("\n")


def render(records: Iterable[str]) -> str:
    """ASA records as plain text (see ``AsaRenderer``)."""
    import io

    buf = io.StringIO()
    renderer = AsaRenderer(buf)
    for record in records:
        renderer.write(record)
    renderer.close()
    return buf.getvalue()
