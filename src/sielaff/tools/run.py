"""``sielaff run`` and ``sielaff diff``: the 1966 listing of a deck, and a listing compared
with a golden printout field by field."""

from __future__ import annotations

import argparse
import sys
from typing import BinaryIO

from sielaff.tools.common import (
    EXIT_NOT_CRANK_ROCKER,
    CommandError,
    load_runnable,
    not_a_crank_rocker,
    refuse_overwriting_inputs,
    write_stdout,
)


def cmd_run(args: argparse.Namespace) -> int:
    from sielaff.emulator.printer import AsaRenderer
    from sielaff.emulator.program import NotCrankRocker, ProgramError, SheetLimit
    from sielaff.emulator.run import notice_printer, run
    from sielaff.mechanism import crank_rocker_failure
    from sielaff.tools.output import atomic_output
    from sielaff.tools.progress import run_progress

    if args.port and args.arith != "float64":
        raise CommandError(f"sielaff: --port with --arith {args.arith}: --port is float64 "
                           "only (every other arithmetic runs on the port already)")
    refuse_overwriting_inputs(args.output, [args.deck] + ([args.program] if args.program
                                                           else []))
    deck = load_runnable(args.deck, args.arith, args.max_sheets)
    if args.program:
        return _run_program(args, deck)
    bar = run_progress(deck, args.max_sheets)  # on a terminal, if the run is long
    notice = bar.wrap(notice_printer(sys.stderr))
    with atomic_output(args.output) as out:
        stream = AsaRenderer(out) if args.render else out
        try:
            with bar:
                printed = run(deck, stream, arithmetic=args.arith, notice=notice,
                    kinematics_only=args.kinematics_only or args.only == "kinematics",
                    max_sheets=args.max_sheets, progress=bar, tex=args.tex,
                    vectorised=not args.port, binary=None if args.render else _bytes_under(out))
            if args.max_sheets is not None and _asks_more(deck, printed, args.arith):
                # the many-sheets path stops without the port's SheetLimit: say it the same
                print(f"sielaff: warning: stopped after {printed} sheets (--max-sheets); "
                      "the deck asks for more", file=sys.stderr)
        except NotCrankRocker as exc:
            # The listing holds the 1966 message; an -o file is left as it was (exit 3).
            if args.render:
                stream.close()
            raise CommandError(not_a_crank_rocker(deck) or f"{deck.path}: card 3: THIS IS "
                               f"NOT A CRANK ROCKER MECHANISM: {exc}",
                               EXIT_NOT_CRANK_ROCKER) from None
        except SheetLimit as limit:
            print(f"sielaff: warning: stopped after {limit.args[0]} sheets (--max-sheets); "
                  "the deck asks for more", file=sys.stderr)
        except ProgramError as exc:
            raise CommandError(f"{deck.path}: {exc}") from exc
        if args.render:
            stream.close()
    failure = crank_rocker_failure(deck.mechanism, deck.exact)
    if failure:  # the 1966 test, in the run's arithmetic, let a change point through
        notice("change-point", f"card 3: {failure}; the 1966 test of statements 45-51 passed "
               f"by roundoff in {args.arith} arithmetic, so forces near the toggle are "
               "meaningless")
    return 0


def _asks_more(deck, printed, arithmetic) -> bool:
    """Whether the deck's range cards ask for more sheets than ``printed`` (an endless
    range asks for more)."""
    from sielaff.emulator.ranges import sheet_count

    if not isinstance(printed, int):
        return False
    total = 0
    for r in deck.ranges:
        n = sheet_count(*r, arithmetic)
        if n is None:
            return True
        total += n
        if total > printed:
            return True
    return False


def _bytes_under(stream) -> BinaryIO | None:
    """The byte stream under ``stream`` if text written to it arrives there unchanged: a
    TextIOWrapper in an ASCII-compatible encoding where lines end in "\n" (sys.stdout and
    ``atomic_output``'s files do not translate "\n" there)."""
    import codecs
    import io
    import os

    if os.linesep != "\n" or not isinstance(stream, io.TextIOWrapper):
        return None
    try:
        name = codecs.lookup(stream.encoding).name
    except LookupError:
        return None
    return stream.buffer if name in ("ascii", "utf-8", "latin-1", "iso8859-1") else None


def _run_program(args: argparse.Namespace, deck) -> int:
    """``sielaff run --program SOURCE DECK``: the program deck itself, interpreted."""
    from sielaff.emulator.fortran import FortranError, PageLimit, run_program
    from sielaff.emulator.fortran.source import SOURCE_LIMIT
    from sielaff.emulator.printer import AsaRenderer
    from sielaff.emulator.program import NotCrankRocker
    from sielaff.emulator.run import notice_printer
    from sielaff.tools.output import atomic_output

    if args.kinematics_only or args.only or args.tex or args.port:
        used = [o for o, on in (("--kinematics-only", args.kinematics_only),
                                ("--only", args.only), ("--tex", args.tex),
                                ("--port", args.port)) if on]
        raise CommandError(f"{' '.join(used)}: with --program the deck is the program; make "
                           "the edit on its cards (decks/edits/ has the report's three)")
    try:
        with open(args.program, encoding="ascii", errors="strict") as f:
            source = f.read(SOURCE_LIMIT + 1)  # one more: a longer deck is refused whole
    except (OSError, UnicodeDecodeError) as exc:
        why = getattr(exc, "strerror", None) or "not an ASCII card deck"
        raise CommandError(f"{args.program}: cannot read the program deck ({why})") from None
    with atomic_output(args.output) as out:
        stream = AsaRenderer(out) if args.render else out
        try:
            run_program(source, deck, stream, args.arith, args.program,
                        notice_printer(sys.stderr), args.max_sheets)
        except PageLimit as limit:
            print(f"sielaff: warning: stopped after {limit.args[0]} sheets (--max-sheets); "
                  "the deck asks for more", file=sys.stderr)
        except FortranError as exc:
            raise CommandError(str(exc)) from None
        except NotCrankRocker:
            # As ``run``: the listing holds the 1966 message, an -o file is left as it was.
            if args.render:
                stream.close()
            raise CommandError(not_a_crank_rocker(deck) or f"{deck.path}: card 3: THIS IS "
                               "NOT A CRANK ROCKER MECHANISM (the program says so)",
                               EXIT_NOT_CRANK_ROCKER) from None
        if args.render:
            stream.close()
    return 0


def cmd_diff(args: argparse.Namespace) -> int:
    import contextlib

    from sielaff.emulator.listing import (
        ListingError,
        asa_records,
        diff_sheets,
        iter_sheets,
        listing_lines,
    )
    from sielaff.tools.common import is_stdin, stdin_text

    class Named:
        """A listing file's sheets, read as they are needed; errors name the file."""

        def __init__(self, path: str, stack: contextlib.ExitStack) -> None:
            self.path, self.count = path, 0
            try:
                if is_stdin(path):  # diff - FILE: one of the two on standard input
                    f = stdin_text()
                    stack.callback(f.detach)  # standard input stays open
                else:
                    f = stack.enter_context(open(path, encoding="ascii", errors="replace"))
            except OSError as exc:
                raise CommandError(f"{path}: cannot read the listing ({exc.strerror})") from exc
            self.sheets = iter_sheets(asa_records(listing_lines(f)))

        def __iter__(self):
            try:
                for sheet in self.sheets:
                    self.count += 1
                    yield sheet
            except ListingError as exc:
                raise CommandError(f"{self.path}: {exc}") from None
            except OSError as exc:
                raise CommandError(f"{self.path}: cannot read the listing "
                                   f"({exc.strerror})") from exc

    status = 0
    with contextlib.ExitStack() as stack:
        listing, golden = Named(args.listing, stack), Named(args.golden, stack)
        for line in diff_sheets(listing, golden):
            status = 1
            if not write_stdout(line + "\n"):
                break  # the reader went away; the listings differ all the same
        if golden.count == 0:
            raise CommandError(f"{args.golden}: no sheet in the golden listing (empty, or not "
                               "a listing): nothing to compare")
    return status
