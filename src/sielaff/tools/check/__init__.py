"""``sielaff check DECK``: what a designer needs to know about a deck before using it.

The report (stdout) has four parts:

Deck
    Every value as punched, with its unit and meaning, and for each range
    card the sheets the 1966 listing will print.
Linkage
    The Grashof sum (s + l against p + q, with its margin), which link is
    the shortest and so what kind of four-bar it is, and the report's five
    crank-rocker conditions (statements 45-51) each with its margin.
One revolution (modern engine, TEX = 0)
    Transmission angle extremes (closed form: they lie at THETA 2 = 0 and
    180) and the closest approach to toggle; the peak bearing loads F 2 ON 1
    (FOA), F 4 ON 1 (FOB), F 3 ON 2 (FA32) and F 3 ON 4 (FB34) (design.bearings'
    peaks, the same numbers the bearings section prints), the peak driving
    torque either way, the peak shaking force and its largest X and Y
    components, all found on a grid and refined to 0.001 degree; and the
    cycle work, the integral of TORQ over one revolution (trapezoid rule
    on the 0.1-degree grid), which is zero for TEX = 0 since the crank turns
    at constant speed.
1966 quirks
    Every quirk of docs/quirks.md this deck triggers in ``sielaff run``.  The
    sheets a range card prints, and so the trailing sheet past THMAX, the
    two sheets of THZERO = THMAX, the angles past 360 (Case II) or below 0
    (Case I) and an endless range, are predicted from the range cards with
    the port's own float64 arithmetic (THETA 2 = (THZERO - DELTA) + I*DELTA),
    so a deck of a million sheets is checked at once.  The TAN3/TAN4
    stand-in, SQRT of a negative argument, and a 1966 arithmetic that fails
    can only be seen by running the port: it is run (without printing) on
    the first ``SHEET_LIMIT`` sheets.

Exit status: 0 usable, 2 unusable (a deck that does not read, an endless
range, 1966 arithmetic that fails), 3 not a crank-rocker; the reason is one
line on stderr.

The sections are in :mod:`.sections` (in the order they print), the range cards' sheets
in :mod:`.sheets`, the JSON form in :mod:`.facts`.
"""

from __future__ import annotations

from sielaff.emulator.cards import Deck
from sielaff.engine.classify import linkage_class
from sielaff.engine.derived import revolution
from sielaff.engine.scene import Scene
from sielaff.mechanism import Mechanism
from sielaff.tools.check.facts import report_json
from sielaff.tools.check.sections import (
    DETAIL_CARDS,
    EXIT_OK,
    SHEET_LIMIT,
    CheckReport,
    _deck_section,
    _design_section,
    _kind_section,
    _linkage_section,
    _quirk_section,
    _revolution_section,
    _scene_section,
)
from sielaff.tools.check.sheets import RangeSheets, range_sheets
from sielaff.tools.common import EXIT_DECK as EXIT_UNUSABLE
from sielaff.tools.common import EXIT_NOT_CRANK_ROCKER

__all__ = [
    "EXIT_OK", "SHEET_LIMIT", "CheckReport", "RangeSheets", "check_deck", "range_sheets",
    "report_json", "revolution",
]


def check_deck(deck: Deck, sheet_limit: int = SHEET_LIMIT,
               scene: Scene | None = None, crank_rocker: bool = False,
               bearing_threshold: float | None = None) -> CheckReport:
    """The report for ``deck`` (see the module doc).  A usable linkage of another kind
    gets its kind's report and status 0, unless ``crank_rocker`` requires one (3).
    ``bearing_threshold``: design.bearings' threshold (its default when None)."""
    from sielaff.design.bearings import THRESHOLD

    if bearing_threshold is None:
        bearing_threshold = THRESHOLD
    from sielaff.tools.common import mechanism_problem, results_problem

    rep = CheckReport()
    rep.add(f"sielaff check: {deck.path}")
    rep.add()
    # Range cards in detail up to DETAIL_CARDS; past that only counted (flat memory, and a
    # million-card deck is checked in seconds).
    sheets = [range_sheets(*r) for r in deck.ranges[:DETAIL_CARDS]]
    _deck_section(deck, rep, sheets)
    rep.add()
    problem = mechanism_problem(deck)
    if problem is not None and problem.status == EXIT_UNUSABLE:
        rep.status, rep.error = problem.status, str(problem)
        rep.add(f"Verdict: unusable: {str(problem).split(': ', 1)[1]} (exit 2)")
        return rep
    failure = _linkage_section(deck.mechanism, rep, deck.exact)
    rep.add()
    overflow = None
    other = failure is not None and not crank_rocker and linkage_class(deck.mechanism).arcs
    # a change point turns fully but folds flat on the way: worked like the kinds that do
    # not turn (no revolution's peaks: the rates jump and grow without bound there)
    whole = bool(linkage_class(deck.mechanism).turns_fully) and (
        linkage_class(deck.mechanism).kind != "change-point")
    if other and not whole:
        _scene_section(deck.mechanism, rep, scene or Scene(), figures=False)
        _kind_section(deck.mechanism, rep, scene)
        rep.add()
    if failure is None or (other and whole):
        overflow = results_problem(deck, None, scene)
        if overflow is None:
            from sielaff.design import bearings

            pins = bearings(deck.mechanism, scene=scene, threshold=bearing_threshold)
            _scene_section(deck.mechanism, rep, scene or Scene(), figures=True)
            _revolution_section(deck.mechanism, rep, scene, pins)
            _design_section(deck.mechanism, rep, scene, pins)
            rep.revolution, rep.pins = True, pins
            rep.add()
    reason = _quirk_section(deck, sheets, rep, sheet_limit)
    rep.add()
    if other and overflow is None:
        kind = linkage_class(deck.mechanism).kind
        rep.add(f"Verdict: usable as a {kind} in the modern tools (check, table, plot, balance, "
                "sweep); not a crank-rocker, so sielaff run stops at statement 52 as the 1966 "
                "program does (exit 3 there, and here with --crank-rocker)")
    elif failure is not None and not other and not crank_rocker:
        rep.status = EXIT_UNUSABLE
        rep.error = f"{deck.path}: card 3: the loop never closes: no crank angle assembles it"
        rep.add("Verdict: unusable: no crank angle assembles this linkage (exit 2)")
    elif failure is not None:
        rep.status = EXIT_NOT_CRANK_ROCKER
        rep.error = str(problem)
        if _program_test_passes(deck.mechanism):
            rep.add("Verdict: not a crank-rocker (exit 3), although the 1966 program's own "
                    "test passes by roundoff: sielaff run prints sheets whose forces near the "
                    "toggle are meaningless")
        else:
            rep.add("Verdict: not a crank-rocker; the 1966 program stops at statement 52 "
                    "(exit 3)")
    elif reason is not None or overflow is not None:
        rep.status = EXIT_UNUSABLE
        rep.error = reason or str(overflow)
        rep.add("Verdict: unusable: sielaff run cannot complete this deck (exit 2)")
    else:
        traps = sum("no decimal point: read as" in w for w in deck.warnings)
        if traps:
            rep.add(f"Verdict: usable as read, but {traps} field{'s' if traps > 1 else ''} "
                    "without a decimal point read with 4 implied decimals (warnings above): "
                    "make sure that was meant")
        else:
            rep.add("Verdict: usable")
    return rep


def _program_test_passes(m: Mechanism) -> bool:
    """The 1966 test of statements 45-51 as the float64 port evaluates it."""
    from sielaff.emulator.program import first_failed_test

    return first_failed_test(m.R3 / m.R2, m.R4 / m.R2, m.R1 / m.R2, abs) is None


def cmd_check(args) -> int:
    """``sielaff check DECK``: the report on stdout, the reason for a non-zero exit on stderr."""
    from sielaff.tools.common import (
        CommandError,
        input_exists,
        is_spec,
        read_input_deck,
        read_spec_deck,
        refuse_bad_output,
    )
    from sielaff.tools.kinds import other_kinds

    output = getattr(args, "output", None)
    refuse_bad_output(output, [args.deck])  # before any work
    if not input_exists(args.deck):
        raise CommandError(f"{args.deck}: no such deck")
    if is_spec(args.deck):  # a spec: its deck, and its scene for the engine
        deck, scene = read_spec_deck(args.deck, other_kinds())
    else:
        deck, scene = read_input_deck(args.deck), Scene()
    if getattr(args, "branch", None):
        import dataclasses

        scene = dataclasses.replace(scene, branch=args.branch)
    if not isinstance(deck.mechanism, Mechanism):  # another kind: its own report
        from sielaff.tools.check.kinds import check_kind, kind_facts
        from sielaff.tools.kinds import other_kind

        other_kind(deck, scene, any_kind=True, note=False)  # the report says the arcs
        rep, facts = check_kind(deck, scene, getattr(args, "crank_rocker", False))
        text = rep.text if getattr(args, "format", "text") == "text" else kind_facts(facts)
        return _finish(rep, text, output)
    rep = check_deck(deck, scene=scene, crank_rocker=getattr(args, "crank_rocker", False),
                     bearing_threshold=getattr(args, "bearing_threshold", None))
    text = (rep.text if getattr(args, "format", "text") == "text"
            else report_json(deck, rep, scene))
    return _finish(rep, text, output)


def _finish(rep: CheckReport, text: str, output: str | None) -> int:
    """Write the report (atomically to ``output``, else stdout), the reason on stderr."""
    import sys

    from sielaff.tools.common import write_stdout

    if output not in (None, "-"):
        from sielaff.tools.output import atomic_output

        with atomic_output(output) as out:
            out.write(text)
    else:
        write_stdout(text)  # a closed pipe keeps the status and the error line
    if rep.error:
        print(rep.error, file=sys.stderr)
    return rep.status
