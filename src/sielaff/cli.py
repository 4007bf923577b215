"""Command line: ``sielaff run|diff|...``.

Every failure is one line on stderr and a non-zero exit status: 2 for a deck
or arithmetic the program cannot use, 3 for a mechanism that is not a
crank-rocker, 1 for ``diff`` when the listings differ.  ``--debug`` shows
the traceback instead.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Sequence

from sielaff.cards import Deck, DeckError, read_deck

EXIT_DECK, EXIT_NOT_CRANK_ROCKER, EXIT_INTERRUPTED = 2, 3, 130


class CommandError(Exception):
    """A one-line failure with its exit status."""

    def __init__(self, message: str, status: int = EXIT_DECK) -> None:
        super().__init__(message)
        self.status = status


def endless_range(deck: Deck) -> str | None:
    """The first range card the 1966 loop would never leave (DELTA <= 0, THZERO <= THMAX)."""
    for card, (thzero, delta, thmax) in zip(deck.range_cards, deck.ranges):
        if delta <= 0 and thzero <= thmax:
            return (f"{deck.path}: card {card}, columns 9-16: DELTA = {delta:g} with THZERO = "
                    f"{thzero:g} <= THMAX = {thmax:g}: the 1966 loop would never end")
    return None


def _load(path: str) -> Deck:
    if not os.path.exists(path):
        raise CommandError(f"{path}: no such deck")
    deck = read_deck(path)
    for warning in deck.warnings:
        print(f"sielaff: warning: {warning}", file=sys.stderr)
    return deck


# -- run --------------------------------------------------------------------
def cmd_run(args: argparse.Namespace) -> int:
    from sielaff.emulator import notice_printer, run
    from sielaff.mechanism import crank_rocker_failure
    from sielaff.output import atomic_output
    from sielaff.printer import AsaRenderer
    from sielaff.program import NotCrankRocker, ProgramError, SheetLimit

    deck = _load(args.deck)
    problem = endless_range(deck)
    if problem:
        raise CommandError(problem)
    notice = notice_printer(sys.stderr)
    status = 0
    with atomic_output(args.output) as out:
        stream = AsaRenderer(out) if args.render else out
        try:
            run(deck, stream, arithmetic=args.arith, notice=notice,
                kinematics_only=args.kinematics_only, max_sheets=args.max_sheets)
        except NotCrankRocker:
            failure = crank_rocker_failure(deck.mechanism)
            print(f"{deck.path}: card 3: THIS IS NOT A CRANK ROCKER MECHANISM: {failure}",
                  file=sys.stderr)
            status = EXIT_NOT_CRANK_ROCKER
        except SheetLimit as limit:
            print(f"sielaff: stopped after --max-sheets {limit.args[0]} sheets", file=sys.stderr)
        except ProgramError as exc:
            raise CommandError(f"{deck.path}: {exc}") from exc
        if args.render:
            stream.close()
    return status


# -- diff -------------------------------------------------------------------
def cmd_diff(args: argparse.Namespace) -> int:
    from sielaff.listing import ListingError, diff_listings

    texts = []
    for path in (args.listing, args.golden):
        try:
            with open(path, encoding="ascii", errors="replace") as f:
                texts.append(f.read())
        except OSError as exc:
            raise CommandError(f"{path}: {exc.strerror}") from exc
    try:
        lines = diff_listings(*texts)
    except ListingError as exc:
        raise CommandError(f"{exc}") from exc
    for line in lines:
        print(line)
    return 1 if lines else 0


# -- parser -----------------------------------------------------------------
EXAMPLES = {
    "run": "example:\n  sielaff run decks/example.dat -o example.asa\n"
           "  sielaff run decks/example.dat --render | less",
    "diff": "example:\n  sielaff run decks/example.dat -o example.asa\n"
            "  sielaff diff example.asa golden/figure10.asa",
}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="sielaff",
        description="Sielaff's 1966 crank-rocker program: faithful IBM 1410 emulator "
                    "and modern analysis engine.",
        epilog="example:\n  sielaff run decks/example.dat | head -60",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--debug", action="store_true", help="show tracebacks on failure")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def add(name: str, func: Callable, help_text: str) -> argparse.ArgumentParser:
        p = sub.add_parser(name, help=help_text, description=help_text,
                           epilog=EXAMPLES.get(name),
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                       help="show tracebacks on failure")
        p.set_defaults(func=func)
        return p

    p = add("run", cmd_run, "print the 1966 listing for a deck (ASA carriage control in column 1)")
    p.add_argument("deck")
    p.add_argument("-o", "--output", help="write to FILE (atomically) instead of stdout")
    p.add_argument("--render", action="store_true",
                   help="plain text with form feeds instead of ASA records")
    p.add_argument("--arith", default="float64", metavar="MODEL",
                   help="number model: float64 (default), float32, ibm1410[:K]")
    p.add_argument("--kinematics-only", action="store_true",
                   help="drop statements 133-202 and their WRITEs, as the report describes")
    p.add_argument("--max-sheets", type=int, metavar="N", help="stop cleanly after N sheets")

    p = add("diff", cmd_diff, "compare a listing with a golden printout, field by field")
    p.add_argument("listing")
    p.add_argument("golden")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    debug = getattr(args, "debug", False)
    try:
        return args.func(args)
    except (DeckError, CommandError, ValueError) as exc:
        if debug:
            raise
        print(str(exc) if isinstance(exc, DeckError | CommandError) else f"sielaff: {exc}",
              file=sys.stderr)
        return getattr(exc, "status", EXIT_DECK)
    except KeyboardInterrupt:
        if debug:
            raise
        print("sielaff: interrupted; no output file was changed", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # The reader went away (``sielaff run deck | head``): leave quietly.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0


def entry() -> None:
    """Console-script entry point."""
    sys.exit(main())
