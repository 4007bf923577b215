"""Run the port on a deck and print the 1410 listing.

This is the glue between ``program`` (the port), ``printer`` (FORMATs and
number editing) and an arithmetic model.  It streams records to a text
stream, so memory stays constant however many sheets a deck asks for, and
turns the ways the 1966 arithmetic can fail into one ``ProgramError`` that
names the statement or the quantity.
"""

from __future__ import annotations

import linecache
import math
import re
import sys
from collections.abc import Callable, Iterator
from typing import BinaryIO, TextIO

from sielaff.emulator import program as _program_module
from sielaff.emulator.arithmetic import ArithmeticError1410, get_arithmetic
from sielaff.emulator.cards import PARAMETER_CARDS
from sielaff.emulator.printer import Format, Unprintable, _strict_value
from sielaff.emulator.program import (
    FORMATS,
    KINEMATIC_FIELDS,
    SHEET_FIELDS,
    NotCrankRocker,
    Program,
    ProgramError,
)

COMPILED = {n: Format(text) for n, text in FORMATS.items()}


def _failing_statement(exc: BaseException) -> str:
    """The port's source line that raised ``exc``: the listing statement, comment stripped."""
    tb = exc.__traceback__
    line = ""
    while tb is not None:
        code = tb.tb_frame.f_code
        if code.co_filename == _program_module.__file__:
            line = linecache.getline(code.co_filename, tb.tb_lineno)
        tb = tb.tb_next
    return line.split("#", 1)[0].strip().replace(" ", "")


def _zero_divisor(deck, exc: BaseException) -> str:
    """' (R2 = 0 on card 3)' when the failing statement divides by a deck value that is 0."""
    exact = getattr(deck, "exact", None) or {}
    for name in re.findall(r"/\(?([A-Z][A-Z0-9]*)", _failing_statement(exc)):
        if name in exact and exact[name] == 0:
            card = next(n for n, names in enumerate(PARAMETER_CARDS, 1) if name in names)
            return f" ({name} = 0 on card {card})"
    return ""


#: Format numbers that print values (the others are headings, blank lines, page eject).
VALUE_FORMATS = frozenset((1, 2, 3, 4, 5, 6, 8, 9))


def _unprintable(name: str, value) -> str:
    """Why ``value`` (of quantity ``name``) could not have been printed by the 1410."""
    number = float(value)
    if not math.isfinite(number):
        return (f"{name} is {number}: the 1966 arithmetic overflows or divides by zero "
                "for this deck")
    return (f"{name} = {number:.4E} is past the IBM 1410's range (|x| < 1E99): "
            "the 1966 arithmetic overflows for this deck")


class _SheetWriter:
    """The WRITE statement: formats records and hands the listing on a sheet at a time.

    ``write(fmt, *values)`` appends the records' text; the page eject that
    ends a sheet (FORMAT 18) sends the whole sheet to ``emit`` in one call,
    and ``flush()`` sends whatever is left.  A value the 1410 could not have
    held (not finite, ``|x| >= 1E99``) is a ProgramError naming the quantity,
    and the sheet it is on is not written; a value below the 1410's range
    (``0 < |x| < 1E-100``) prints as zero, as the 1410's exponent underflow
    made it (see ``printer.fast_editor``).
    """

    def __init__(self, emit: Callable[[str], None], kinematics_only: bool) -> None:
        self.emit = emit
        self.fields = KINEMATIC_FIELDS if kinematics_only else SHEET_FIELDS
        self.parts: list[str] = []
        self.texts: dict[tuple[int, int], Callable[..., str]] = {}
        self.write = self._make_write()

    def __call__(self, fmt: int, *values) -> None:
        self.write(fmt, *values)

    def _text_function(self, fmt: int, n: int) -> Callable[..., str]:
        if n and fmt not in VALUE_FORMATS:
            raise ProgramError(f"FORMAT {fmt} takes no values")
        function = self.texts[fmt, n] = COMPILED[fmt].text_function(n, strict=True)
        return function

    def _unprintable(self, group: int, values: tuple) -> ProgramError:
        self.parts.clear()  # the sheet is not written
        for name, value in zip(self.fields[group], values):
            try:
                _strict_value(value)
            except Unprintable:
                return ProgramError(_unprintable(name, value))
        return ProgramError(f"unprintable value in {values}")

    def _make_write(self) -> Callable[..., None]:
        # A closure (not a method): the port calls it 25 times a sheet.
        get, append = self.texts.get, self.parts.append
        build, flush = self._text_function, self.flush
        group = 0  # which value-carrying WRITE of the sheet this is

        def write(fmt: int, *values) -> None:
            nonlocal group
            text = get((fmt, len(values))) or build(fmt, len(values))
            if values:
                try:
                    append(text(*values))
                except Unprintable:
                    raise self._unprintable(group, values) from None
                group += 1
                return
            append(text())
            if fmt == 18:
                flush()
            elif fmt == 7:
                group = 0

        return write

    def flush(self) -> None:
        if self.parts:
            self.emit("".join(self.parts))
            self.parts.clear()


def _counting(emit: Callable[[str], None], progress: Callable[[int], None]):
    """``emit`` that also reports the number of sheets written to ``progress``."""
    count = 0

    def counted(text: str) -> None:
        nonlocal count
        emit(text)
        count += 1
        progress(count)

    return counted


def _numpy_quiet(ar):
    """numpy's floating-point warnings off for an arithmetic built on numpy scalars."""
    import contextlib

    if getattr(ar, "name", "") != "float32":
        return contextlib.nullcontext()
    import numpy as np

    return np.errstate(all="ignore")


def run(deck, out: TextIO, arithmetic: str = "float64",
        notice: Callable[[str, str], None] | None = None,
        kinematics_only: bool = False, max_sheets: int | None = None,
        progress: Callable[[int], None] | None = None, tex: float = 0.0,
        vectorised: bool = True, binary: BinaryIO | None = None) -> int:
    """Print the listing of ``deck`` on ``out`` (one ASA record per line); ``tex`` is the
    report's edit of statement 74 (``TEX = constant``, in-lb).

    In float64 the sheets are computed many at a time (``emulator.vector``: the same
    bytes, the port's arithmetic redone on arrays) unless ``vectorised`` is False; the
    port prints the sheets that raise notices or errors, and every other arithmetic.

    Returns the number of sheets.  Raises ``program.NotCrankRocker`` (after
    the 1966 message is printed), ``program.SheetLimit`` and ``ProgramError``.
    The listing is written a sheet at a time (one ``out.write`` per sheet),
    so memory stays constant; a sheet that fails is not written.
    ``progress(n)``, if given, is called with the sheets so far: after each sheet (the
    port), or after each block of sheets (many at a time).  ``binary``, if given, is the
    byte stream under ``out`` that text written to ``out`` reaches unchanged (an ASCII-
    compatible encoding, "\n" written as "\n"): the blocks of sheets go there as bytes,
    ``out`` flushed first, which spares decoding and encoding them.
    """
    notice = notice or (lambda kind, text: None)
    ar = get_arithmetic(arithmetic, on_error=lambda text: notice("library", text))
    emit = out.write if progress is None else _counting(out.write, progress)
    writer = _SheetWriter(emit, kinematics_only)
    quiet = _numpy_quiet(ar)  # float32 overflow is a ProgramError below, not a warning
    counts = None
    if arithmetic == "float64" and vectorised:
        from sielaff.emulator import vector

        counts = vector.plan(deck)
    try:
        with quiet:
            if counts is not None:  # many sheets at a time; the port prints special ones
                emit_bytes = None
                if binary is not None:
                    def emit_bytes(data: memoryview) -> None:
                        out.flush()
                        binary.write(data)
                return vector.vector_run(deck, out.write, notice, _SheetWriter,
                                         kinematics_only, max_sheets, progress, tex, counts,
                                         emit_bytes)
            sheets = Program(ar, notice).MAIN(deck, writer.write, kinematics_only, max_sheets,
                                              tex)
    except NotCrankRocker:
        writer.flush()  # FORMAT 20's message
        raise
    except ZeroDivisionError as exc:
        raise ProgramError(f"division by zero in {_failing_statement(exc)}"
                           f"{_zero_divisor(deck, exc)}") from exc
    except (ArithmeticError1410, OverflowError) as exc:
        raise ProgramError(f"{exc} in {_failing_statement(exc)}"
                           f"{_zero_divisor(deck, exc)}") from exc
    writer.flush()
    return sheets


def sheet_values(deck, arithmetic: str = "float64", kinematics_only: bool = False,
                 tex: float = 0.0) -> Iterator[dict[str, float]]:
    """The quantities each sheet prints, unformatted, as dicts keyed by listing name."""
    fields = KINEMATIC_FIELDS if kinematics_only else SHEET_FIELDS
    sheets: list[dict[str, float]] = []
    current: dict[str, float] = {}
    group = [0]

    def write(fmt: int, *values) -> None:
        if fmt == 18:
            sheets.append(dict(current))
            current.clear()
            group[0] = 0
        elif values:
            current.update(zip(fields[group[0]], (float(v) for v in values)))
            group[0] += 1

    ar = get_arithmetic(arithmetic)
    Program(ar).MAIN(deck, write, kinematics_only, tex=tex)
    return iter(sheets)


def notice_printer(stream: TextIO = sys.stderr, limit: int = 5) -> Callable[[str, str], None]:
    """A ``notice`` callback: prints quirks to ``stream``, at most ``limit`` of each kind."""
    counts: dict[str, int] = {}

    def notice(kind: str, text: str) -> None:
        n = counts[kind] = counts.get(kind, 0) + 1
        if n <= limit:
            stream.write(f"sielaff: 1966 quirk: {text}\n")
        if n == limit:
            stream.write(f"sielaff: 1966 quirk: (further '{kind}' notices suppressed)\n")

    return notice
