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
import sys
from collections.abc import Callable, Iterator
from typing import TextIO

from sielaff import program as _program_module
from sielaff.arithmetic import ArithmeticError1410, get_arithmetic
from sielaff.printer import Format
from sielaff.program import FORMATS, KINEMATIC_FIELDS, SHEET_FIELDS, Program, ProgramError

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


class _SheetWriter:
    """The WRITE statement: formats records and checks every printed value is finite."""

    def __init__(self, emit: Callable[[str], None], kinematics_only: bool) -> None:
        self.emit = emit
        self.fields = KINEMATIC_FIELDS if kinematics_only else SHEET_FIELDS
        self.group = 0  # which value-carrying WRITE of the sheet comes next

    def __call__(self, fmt: int, *values) -> None:
        if values:
            if fmt not in (1, 2, 3, 4, 5, 6, 8, 9):
                raise ProgramError(f"FORMAT {fmt} takes no values")
            names = self.fields[self.group]
            self.group += 1
            for name, value in zip(names, values):
                if not math.isfinite(float(value)):
                    raise ProgramError(f"{name} is {float(value)}: the 1966 arithmetic "
                                       "overflows or divides by zero for this deck")
        elif fmt == 7:
            self.group = 0
        for record in COMPILED[fmt].records(values):
            self.emit(record)


def run(deck, out: TextIO, arithmetic: str = "float64",
        notice: Callable[[str, str], None] | None = None,
        kinematics_only: bool = False, max_sheets: int | None = None) -> int:
    """Print the listing of ``deck`` on ``out`` (one ASA record per line).

    Returns the number of sheets.  Raises ``program.NotCrankRocker`` (after
    the 1966 message is printed), ``program.SheetLimit`` and ``ProgramError``.
    """
    notice = notice or (lambda kind, text: None)
    ar = get_arithmetic(arithmetic, on_error=lambda text: notice("library", text))
    writer = _SheetWriter(lambda record: out.write(record + "\n"), kinematics_only)
    try:
        return Program(ar, notice).MAIN(deck, writer, kinematics_only, max_sheets)
    except ZeroDivisionError as exc:
        raise ProgramError(f"division by zero in {_failing_statement(exc)}") from exc
    except (ArithmeticError1410, OverflowError) as exc:
        raise ProgramError(f"{exc} in {_failing_statement(exc)}") from exc


def sheet_values(deck, arithmetic: str = "float64",
                 kinematics_only: bool = False) -> Iterator[dict[str, float]]:
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
    Program(ar).MAIN(deck, write, kinematics_only)
    return iter(sheets)


def notice_printer(stream: TextIO = sys.stderr, limit: int = 5) -> Callable[[str, str], None]:
    """A ``notice`` callback: prints quirks to ``stream``, at most ``limit`` of each kind."""
    counts: dict[str, int] = {}

    def notice(kind: str, text: str) -> None:
        n = counts[kind] = counts.get(kind, 0) + 1
        if n <= limit:
            stream.write(f"sielaff: 1966 quirk: {text}\n")
        if n == limit:
            stream.write(f"sielaff: (further '{kind}' notices suppressed)\n")

    return notice
