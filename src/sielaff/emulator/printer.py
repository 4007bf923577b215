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

import functools
import math
import re
from collections.abc import Callable, Iterable

_ITEM = re.compile(r"\s*(?:(\d*)([FE])(\d+)\.(\d+)|(\d*)X|(\d+)H|(/)|(,))", re.IGNORECASE)


class FormatError(ValueError):
    """A FORMAT text this interpreter does not understand."""


#: The longest record: carriage control and 132 print positions (the IBM 1403 had 120,
#: and 12 more as an option: https://en.wikipedia.org/wiki/IBM_1403).  A FORMAT whose
#: record is longer, counting every field, is refused, which also bounds its repeat
#: counts, widths and decimals.
RECORD_LIMIT = 133
#: Records between two page ejects that a listing may hold (a 1966 sheet has 59): the
#: interpreter stops a program printing more, and the listing reader refuses a file
#: with more (a stream of blank lines that never ends).
RECORDS_PER_SHEET = 1_000


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

#: How many units in the last place another machine may move a printed value.  numpy's
#: SIMD sin/cos/arctan2 and glibc's FMA and SSE2 variants differ by an ulp or two per
#: call, and a printed field is a few calls deep; 16 ulps (3.6E-15 relative in float64)
#: covers that, and a value meets a printed-digit boundary that close by chance about
#: once in 1E11 fields.
NEARBY_ULPS = 16


def edits_nearby(value, kind: str, w: int = 12, d: int | None = None,
                 ulps: int = NEARBY_ULPS) -> tuple[str, ...]:
    """Every text an Ew.d or Fw.d field prints for a value within ``ulps`` of ``value``.

    ``value`` is a binary float (Python float, numpy float64 or float32: the ulps
    are its own format's) or a decimal 1410 number (exact on every machine: one
    text).  One text means the printed digits are certain on any CPU; two mean a
    digit boundary lies within reach, and which side prints depends on the
    machine's libm (``docs/accuracy.md``, "What the digits depend on").
    """
    edit = _EDITORS[kind]
    d = (4 if kind == "E" else 1) if d is None else d
    if isinstance(value, float) or type(value).__name__ in ("float64", "float32"):
        import numpy as np

        x = np.asarray(value)
        lo, hi = x, x
        for _ in range(ulps):
            lo, hi = np.nextafter(lo, -np.inf), np.nextafter(hi, np.inf)
        texts = [edit(v.item() if x.dtype == np.float64 else v[()], w, d) for v in (lo, x, hi)]
        return tuple(dict.fromkeys(texts))
    return (edit(value, w, d),)


# -- the fast path ---------------------------------------------------------
# ``edit_e`` and ``edit_f`` above are the reference.  The emulator prints
# millions of fields, so ``fast_editor`` builds editors that give exactly the
# same text (tests/test_run_failures.py checks this on arbitrary and adversarial
# floats) in three tiers:
#
# 1. arithmetic: scale a float to d digits and truncate with int().  This is
#    the exact value's truncation; it is also repr's unless a digit boundary
#    lies within a few units in the last place, so values within 1E-7 (E) or
#    1E-6 (F) of a boundary after scaling (0.7 -> 7000.000000000001, 40.0 ->
#    400.0) go on to tier 2.  This tier does not call repr (the costly part).
# 2. repr: a Python float's digits straight from ``repr`` (the shortest
#    round-trip decimal: "545.6", "-0.05", "1.25e-07"), a few slices, no
#    Decimal and no regular expression.
# 3. the reference, for values tier 2 does not take (inf, nan, exponents
#    out of range) and for other number types (numpy float32, 1410 decimals).

class Unprintable(ValueError):
    """A value the 1410 could not have held, met by a *strict* editor.

    Strict editors are the emulator's: the 1410's numbers end at
    ``|x| < 1E99``, so a printed value that is not finite or has ``|x| >= 1E99``
    means the 1966 arithmetic would have overflowed (the listing would not
    exist).  The emulator turns this into an error naming the quantity.
    """


#: "E-99" ... "E-01", "E 00" ... "E 99": the 1410's exponent, indexed by exponent + 99.
_EXPONENT_TEXT = tuple(f"E-{-e:02d}" if e < 0 else f"E {e:02d}" for e in range(-99, 100))


def _strict_value(value):
    """``value`` as a strict editor prints it: Unprintable past the 1410's
    range, 0.0 below it (the 1410's exponent underflow gives zero), else itself."""
    parts = decimal_parts(value)
    if parts is None:
        raise Unprintable(value)
    if parts[1]:
        if parts[2] > 99:
            raise Unprintable(value)
        if parts[2] < -99:
            return 0.0
    return value


def _memo(edit: Callable[[float], str], size: int = 4096) -> Callable[[float], str]:
    """``edit`` remembering its last results (finite nonzero floats only: -0.0 == 0.0).

    Values near a digit boundary often recur: a velocity that is 200 in
    exact arithmetic comes out of SQRT as 200.0 or 199.99999999999997 on
    every sheet.
    """
    memo: dict[float, str] = {}

    def edit_memo(value: float) -> str:
        text = memo.get(value)
        if text is None:
            text = edit(value)
            if len(memo) >= size:
                memo.clear()
            memo[value] = text
        return text
    return edit_memo


@functools.cache  # one editor (and one memo) per descriptor, however many fields use it
def fast_editor(kind: str, w: int, d: int, strict: bool = False) -> Callable[[object], str]:
    """An editor for one ``Ew.d`` or ``Fw.d`` field: the text of ``edit_e``/``edit_f``.

    With ``strict`` a value that is not finite or has ``|x| >= 1E99`` raises
    :class:`Unprintable` and one with ``0 < |x| < 1E-100`` prints as zero
    (the 1410's range; see ``_strict_value``).  Without it such values print
    as the reference does (``*`` fields).
    """
    kind = kind.upper()
    reference = {"E": edit_e, "F": edit_f}[kind]
    stars = "*" * w
    pad = "0" * d
    float_repr = float.__repr__

    if strict:
        def slow(value) -> str:
            return reference(_strict_value(value), w, d)
    else:
        def slow(value) -> str:
            return reference(value, w, d)

    if kind == "F":
        def edit_f_fast(value) -> str:
            if type(value) is not float:
                return slow(value)
            s = float_repr(value)
            if "e" in s or "n" in s or value == 0.0:  # |x| < 1E-4 or >= 1E16, inf, nan, -0.0
                return slow(value)
            if s[0] == "-":
                whole, _, frac = s[1:].partition(".")
                text = "-" + whole.lstrip("0") + "." + (frac + pad)[:d]
            else:
                whole, _, frac = s.partition(".")
                text = whole.lstrip("0") + "." + (frac + pad)[:d]
            return text.rjust(w) if len(text) <= w else stars

        if not 1 <= d <= 7 or w < 10:
            return edit_f_fast
        # |x| < 10**(8-d): at most 10 characters ("-9999999.9"), no stars
        scale, bound = 10.0 ** d, 10.0 ** (8 - d)

        def edit_f_arith(value) -> str:
            # t = the value's first d decimals, truncated; exact unless the
            # scaled value lies within 1E-6 of an integer (a round value, or
            # one where repr's digits and the binary value may straddle it).
            if type(value) is float:
                if 0.0 < value < bound:
                    scaled = value * scale
                    t = int(scaled)
                    if 1e-6 < scaled - t < 0.999999:
                        digits = str(t).rjust(d, "0")  # t = 5 prints ".5" (d = 1)
                        return (digits[:-d] + "." + digits[-d:]).rjust(w)
                    return near_boundary(value)
                if -bound < value < 0.0:
                    scaled = value * -scale
                    t = int(scaled)
                    if 1e-6 < scaled - t < 0.999999:
                        digits = str(t).rjust(d, "0")
                        return ("-" + digits[:-d] + "." + digits[-d:]).rjust(w)
                    return near_boundary(value)
            return edit_f_fast(value)

        near_boundary = _memo(edit_f_fast)
        return edit_f_arith

    zero = "." + pad + "E-99"
    zero = zero.rjust(w) if len(zero) <= w else stars
    exponent_text = _EXPONENT_TEXT

    def edit_e_fast(value) -> str:
        if type(value) is not float:
            return slow(value)
        s = float_repr(value)
        if s[0] == "-":
            sign, s = "-", s[1:]
        else:
            sign = ""
        cut = s.find("e")
        if cut < 0:
            whole, dot, frac = s.partition(".")
            if not dot:  # inf, nan
                return slow(value)
            if whole != "0":
                digits, exponent = whole + frac, len(whole)
            else:
                digits = frac.lstrip("0")
                if not digits:
                    return zero
                exponent = len(digits) - len(frac)
        else:  # "d.ddde-XX" or "de+XX": one nonzero digit before the point
            exponent = int(s[cut + 1:]) + 1
            if not -99 <= exponent <= 99:
                return slow(value)
            digits = s[0] + s[2:cut]
        text = sign + "." + (digits + pad)[:d] + exponent_text[exponent + 99]
        return text.rjust(w) if len(text) <= w else stars

    if not 1 <= d <= 7 or d + 6 > w:  # d <= 7: the 1E-7 margin stays many units in the last place
        return edit_e_fast
    positive, negative = ".".rjust(w - d - 4), "-.".rjust(w - d - 4)
    low, high = 10 ** (d - 1), 10 ** d - 1
    # scale[k] brings a value with exponent k - 99 (0.ddd x 10**(k-99)) to d digits
    scales = tuple(10.0 ** (d - (k - 99)) for k in range(199))
    log10, floor = math.log10, math.floor

    def edit_e_arith(value) -> str:
        # The first d digits by arithmetic: exact unless the scaled value
        # lies within 1E-7 of an integer (then repr decides, as above).  A
        # wrong exponent from log10 puts t out of [low, high]: repr decides.
        if type(value) is float:
            a = value if value >= 0.0 else -value
            if 1e-99 <= a < 1e98:
                k = floor(log10(a)) + 100  # exponent + 99
                scaled = a * scales[k]
                t = int(scaled)
                if low <= t <= high and 1e-7 < scaled - t < 0.9999999:
                    return (positive if value > 0.0 else negative) + str(t) + exponent_text[k]
                return near_boundary(value)
            if a == 0.0:
                return zero
        return edit_e_fast(value)

    near_boundary = _memo(edit_e_fast)
    return edit_e_arith


def compile_format(text: str) -> list[tuple]:
    """Compile FORMAT text such as ``(//18X,7HTHETA 2/)`` into items.

    Items: ("lit", str), ("edit", editor, w, d), ("/",).
    """
    body = text.strip()
    if not (body.startswith("(") and body.endswith(")")):
        raise FormatError(f"FORMAT must be parenthesised: {text!r}")
    body = body[1:-1]
    items: list[tuple] = []
    pos, width = 0, 0  # characters of the record so far

    def count(digits: str | None, default: int = 1) -> int:
        # a count past the record is refused before it is converted (or expanded)
        if digits and len(digits.lstrip("0")) > len(str(RECORD_LIMIT)):
            raise FormatError(f"{digits} in FORMAT {text!r} is past the {RECORD_LIMIT} "
                              "characters of a printed record")
        return int(digits) if digits else default

    def grow(n: int, what: str) -> None:
        nonlocal width
        width += n
        if width > RECORD_LIMIT:
            raise FormatError(f"a record of FORMAT {text!r} is more than {RECORD_LIMIT} "
                              f"characters wide at {what!r} (carriage control and the "
                              "1403 printer's 132 print positions)")

    while pos < len(body):
        m = _ITEM.match(body, pos)
        if not m:
            raise FormatError(f"cannot read FORMAT {text!r} at {body[pos:]!r}")
        rep, kind, w, d, nx, nh, slash, _comma = m.groups()
        pos = m.end()
        if kind:
            n, wide, decimals = count(rep), count(w), count(d)
            if decimals > wide:
                raise FormatError(f"{m.group().strip()} in FORMAT {text!r}: {decimals} "
                                  f"decimals do not fit a field {wide} wide")
            grow(n * wide, m.group().strip())
            items += [("edit", _EDITORS[kind.upper()], wide, decimals)] * n
        elif nx is not None:
            n = count(nx)
            grow(n, m.group().strip())
            items.append(("lit", " " * n))
        elif nh:
            n = count(nh)
            if pos + n > len(body):
                raise FormatError(f"Hollerith field runs past the end of {text!r}")
            grow(n, m.group().strip() + body[pos:pos + n])
            items.append(("lit", body[pos:pos + n]))
            pos += n
        elif slash:
            items.append(("/",))
            width = 0
    return items


class Format:
    """A compiled FORMAT statement."""

    def __init__(self, text: str) -> None:
        self.text = text
        self.items = compile_format(text)
        self.n_edits = sum(1 for it in self.items if it[0] == "edit")
        self._text_functions: dict[tuple[int, bool], Callable[..., str]] = {}

    def text_function(self, n: int, strict: bool = False) -> Callable[..., str]:
        """A function of ``n`` values giving the records of one WRITE, each ending in a newline.

        Equal to ``"".join(r + "\n" for r in self.records(values))`` (with
        strict editors if ``strict``: see ``fast_editor``), but compiled
        once into a single expression of literals and fast editors.
        """
        key = (n, strict)
        cached = self._text_functions.get(key)
        if cached is not None:
            return cached
        if n > self.n_edits:
            raise FormatError(f"{n} values for {self.n_edits} fields in {self.text}")
        namespace: dict[str, object] = {}
        pieces: list[tuple[bool, str]] = []  # (is_literal, text or expression)
        record: list[tuple[bool, str]] = []
        may_be_empty = True

        def end_record() -> None:
            nonlocal may_be_empty
            if not record:
                pieces.append((True, " "))
            elif may_be_empty:  # only empty literals or zero-width fields: "" prints " "
                expr = " + ".join(t if not lit else repr(t) for lit, t in record)
                pieces.append((False, f"(({expr}) or ' ')"))
            else:
                pieces.extend(record)
            pieces.append((True, "\n"))
            record.clear()
            may_be_empty = True

        k = 0
        for item in self.items:
            if item[0] == "lit":
                record.append((True, item[1]))
                may_be_empty = may_be_empty and not item[1]
            elif item[0] == "edit":
                if k == n:
                    break  # output stops at the first field with no list item
                kind = "E" if item[1] is edit_e else "F"
                namespace[f"_e{k}"] = fast_editor(kind, item[2], item[3], strict)
                record.append((False, f"_e{k}(v{k})"))
                may_be_empty = may_be_empty and item[2] == 0
                k += 1
            else:
                end_record()
        end_record()
        merged: list[tuple[bool, str]] = []
        for lit, text in pieces:
            if lit and merged and merged[-1][0]:
                merged[-1] = (True, merged[-1][1] + text)
            else:
                merged.append((lit, text))
        expr = " + ".join(repr(t) if lit else t for lit, t in merged)
        args = ", ".join(f"v{i}" for i in range(n))
        exec(f"def _text({args}):\n    return {expr}\n", namespace)  # noqa: S102
        function = namespace["_text"]
        self._text_functions[key] = function
        return function

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
    """A text stream that takes ASA records (newline-terminated, one or more per
    ``write``) and writes plain text, as POSIX ``asa`` does: ``1`` becomes a
    form feed, ``0`` a blank line, ``+`` a carriage return (overprint)."""

    def __init__(self, out) -> None:
        self.out = out
        self.first = True

    def write(self, records: str) -> None:
        lines = records.split("\n")
        if records.endswith("\n"):
            lines.pop()
        out = []
        for record in lines:
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
            out.append(prefix + text)
        self.out.write("".join(out))

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
