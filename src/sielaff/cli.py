"""Command line: ``sielaff run|diff|...``.

Parser and dispatch; what the commands share is in ``sielaff.tools.common``.

Every failure is one line on stderr and a non-zero exit status: 2 for a deck
or arithmetic the program cannot use (or an output file that cannot be
written), 3 for a mechanism that is not a crank-rocker, 1 for ``diff`` when
the listings differ, 130 for Ctrl-C, 128 + N for signal N (SIGTERM 143,
SIGHUP 129).  ``--debug`` shows the traceback instead.

Besides that one error line, stderr carries only *diagnostics*: lines that
begin ``sielaff: warning: `` (the deck's warnings, a ``--max-sheets`` stop)
or ``sielaff: 1966 quirk: `` (what the 1966 program does oddly for this
deck).  A run that exits 0 prints no error line.  A closed pipe
(``sielaff run deck | head``) ends the run quietly with status 0; ``check``
and ``diff``, which know their status before they print, keep it.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import warnings
from collections.abc import Callable, Sequence

from sielaff.emulator.cards import DeckError
from sielaff.tools.common import (
    EXIT_DECK,
    EXIT_INTERRUPTED,
    SIGNAL_STATE,
    CommandError,
    Terminated,
    finish_signals,
    install_signal_handlers,
    silence_stdout,
)


def tex_value(text: str) -> float:
    """argparse type for ``--tex``: a finite number the 1410 could hold (|x| < 1E99)."""
    import math

    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and abs(value) < 1e99):
        raise argparse.ArgumentTypeError(f"{text!r} is not a torque in in-lb (a number "
                                         "below 1E99)")
    return value


def positive_length(text: str) -> float:
    """argparse type for a counterweight's radius: a finite number > 0."""
    import math

    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0.0):
        raise argparse.ArgumentTypeError(f"{text!r} is not a length > 0")
    return value


def worker_count(text: str) -> int:
    """argparse type for ``--workers``: 1 or more."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of workers (1, 2, ...)")
    return value


def angle_list(text: str) -> tuple[float, ...]:
    """argparse type for ``--at``: crank angles in degrees, comma-separated."""
    try:
        values = tuple(float(x) for x in text.split(","))
    except ValueError:
        values = ()
    if not values or not all(abs(v) < 1e9 for v in values):
        raise argparse.ArgumentTypeError(f"{text!r} is not a list of angles (40 or 30,60,90)")
    return values


def one_angle(text: str) -> float:
    """argparse type for one crank angle in degrees: a finite number."""
    values = angle_list(text)
    if len(values) != 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not one angle (40)")
    return values[0]


def point_spec(text: str) -> tuple[int, float, float]:
    """argparse type for ``--point``: LINK:R:ANGLE."""
    try:
        link, r, angle = text.split(":")
        spec = (int(link), float(r), float(angle))
    except ValueError:
        spec = (0, 0.0, 0.0)
    if spec[0] not in (2, 3, 4):
        raise argparse.ArgumentTypeError(f"{text!r}: write LINK:R:ANGLE, LINK 2, 3 or 4 "
                                         "(e.g. 3:8:-15)")
    return spec


def load_fraction(text: str) -> float:
    """argparse type for ``--bearing-threshold``: a fraction of a pin's peak, 0 <= x < 1."""
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not 0.0 <= value < 1.0:
        raise argparse.ArgumentTypeError(f"{text!r} is not a fraction of the pin's peak load "
                                         "(0 or more, below 1; e.g. 0.05)")
    return value


BEARING_THRESHOLD_HELP = ("loads below this fraction of a pin's peak do not count as "
                          "loading a side of it (default 0.05: docs/design.md)")


def sheet_count(text: str) -> int:
    """argparse type for ``--max-sheets``: a whole number >= 0."""
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of sheets (0, 1, 2, ...)")
    return value


# -- parser -----------------------------------------------------------------
#: The input arguments' help (sielaff help io says it in full).
INPUT_HELP = ("a deck or a TOML spec (*.toml); - reads either from standard input (a spec "
              "if its first non-blank line begins with [ or # or holds =): sielaff help io")
DECK_ONLY_HELP = "the deck; - reads it from standard input: sielaff help io"
SPEC_HELP = "the TOML spec; - reads it from standard input: sielaff help io"
OUTPUT_HELP = "write to FILE (atomically); - or none: stdout"

EXAMPLES = {
    "run": "example:\n  sielaff run decks/example.dat -o example.asa\n"
           "  sielaff run decks/example.dat --render | less\n"
           "  sielaff run --program decks/edits/tex-constant.f decks/example.dat | head -40",
    "diff": "example:\n  sielaff run decks/example.dat -o example.asa\n"
            "  sielaff diff example.asa golden/figure10.asa",
    "table": "example:\n  sielaff table decks/example.dat -o example.csv\n"
             "  sielaff table decks/example.dat --format json --only kinematics | head -3",
    "check": "example:\n  sielaff check decks/example.dat\n"
             "  sielaff punch decks/example.toml | sielaff check - --format json",
    "plot": "example:\n  sielaff plot decks/example.dat -o plots\n"
            "  sielaff plot decks/example.dat -o plots --only kinematics",
    "punch": "example:\n  sielaff punch decks/example.toml -o my.dat && sielaff check my.dat",
    "help": "example:\n  sielaff help deck",
    "bench": "example:\n  sielaff bench --quick\n  sielaff bench -o report/accuracy.md\n"
             "  sielaff bench --effects -o report/effects.md",
    "balance": "example:\n  sielaff balance decks/example.dat\n"
               "  sielaff balance decks/scene.toml -o out/balanced.toml\n"
               "  sielaff balance decks/si.toml -o - 2>/dev/null | sielaff table - | head -3",
    "sweep": "example:\n  sielaff sweep decks/sweep.toml -o out/sweep.csv --plot out/pareto.png\n"
             "  sielaff sweep decks/sweep.toml --workers 1 | head -3",
    "simulate": "example:\n  sielaff simulate decks/motor.toml -o out/motor.csv --plot "
                "out/motor.png",
    "synth": "example:\n  sielaff synth decks/synth.toml -o out/ranked.csv --write-best out/best",
    "tolerance": "example:\n  sielaff tolerance decks/tolerance.toml",
    "report": "example:\n  sielaff report decks/example.dat -o out/example.html",
}


#: Each command's function, imported when the command runs (numpy, matplotlib and the
#: 1410 model load only for the commands that need them).
COMMANDS = {
    "run": "sielaff.tools.run:cmd_run", "diff": "sielaff.tools.run:cmd_diff",
    "table": "sielaff.tools.table:cmd_table", "check": "sielaff.tools.check:cmd_check",
    "plot": "sielaff.tools.plot:cmd_plot", "punch": "sielaff.tools.punch:cmd_punch",
    "bench": "sielaff.tools.bench:cmd_bench", "help": "sielaff.tools.helptext:cmd_help",
    "balance": "sielaff.tools.balance:cmd_balance", "sweep": "sielaff.tools.sweep:cmd_sweep",
    "simulate": "sielaff.tools.simulate:cmd_simulate",
    "synth": "sielaff.tools.synth:cmd_synth",
    "tolerance": "sielaff.tools.tolerance:cmd_tolerance",
    "report": "sielaff.tools.report:cmd_report",
}


def _command(name: str) -> Callable[[argparse.Namespace], int]:
    import importlib

    module, _, function = COMMANDS[name].partition(":")
    return getattr(importlib.import_module(module), function)


def build_parser() -> argparse.ArgumentParser:
    from sielaff.quantities import CONVENTIONS
    from sielaff.tools.helptext import EXIT_STATUS, topic_list
    from sielaff.version import __version__

    parser = argparse.ArgumentParser(
        prog="sielaff",
        description="Sielaff's 1966 crank-rocker program: faithful IBM 1410 emulator "
                    "and modern analysis engine.  A deck is 80-column cards of "
                    "FORMAT(4F8.4): sielaff help deck.",
        epilog="example:\n  sielaff run decks/example.dat | head -60\n"
               "  sielaff check decks/example.dat\n"
               "  sielaff plot decks/example.dat -o plots\n\n"
               f"{topic_list()}\n\n{CONVENTIONS}\n\n{EXIT_STATUS}",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--debug", action="store_true", help="show tracebacks on failure")
    parser.add_argument("--version", action="version", version=f"sielaff {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def add(name: str, help_text: str) -> argparse.ArgumentParser:
        epilog = (EXAMPLES[name] + "\n\n" if name in EXAMPLES else "") + EXIT_STATUS
        p = sub.add_parser(name, help=help_text, description=help_text, epilog=epilog,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                       help="show tracebacks on failure")
        p.set_defaults(func=name)
        return p

    p = add("run", "print the 1966 listing for a deck (ASA carriage control in column 1)")
    p.add_argument("deck", help=DECK_ONLY_HELP)
    p.add_argument("-o", "--output", help=OUTPUT_HELP)
    p.add_argument("--render", action="store_true",
                   help="plain text with form feeds instead of ASA records")
    p.add_argument("--arith", default="float64", metavar="MODEL",
                   help="number model: float64 (default), float32, ibm1410[:K] (the 1410's "
                        "K-digit truncating decimal arithmetic, K = 8 by default): "
                        "sielaff help arith")
    p.add_argument("--kinematics-only", action="store_true",
                   help="drop statements 133-202 and their WRITEs, as the report describes")
    p.add_argument("--only", choices=("kinematics",),
                   help="kinematics: the same as --kinematics-only (as for table and plot)")
    p.add_argument("--program", metavar="SOURCE.f",
                   help="run this FORTRAN program deck (decks/sielaff.f, or an edit of it) on "
                        "the chosen arithmetic instead of the built-in port: docs/interpreter.md")
    p.add_argument("--port", action="store_true",
                   help="float64 only: print every sheet with the line-by-line port (the "
                        "reference) instead of many sheets at a time; the same bytes, slower")
    p.add_argument("--max-sheets", type=sheet_count, metavar="N",
                   help="stop cleanly after N sheets (a warning says so)")
    p.add_argument("--tex", type=tex_value, default=0.0, metavar="IN-LB",
                   help="the report's edit of statement 74: TEX = this constant external "
                        "torque on link 4 (in-lb, CCW +) instead of 0.0; EX TORQ ON 4 prints it")

    p = add("table", "the modern engine's results for a deck, one row per "
            "position from THZERO to THMAX (CSV or JSON)")
    p.add_argument("deck", metavar="DECK|SPEC.toml", help=INPUT_HELP)
    p.add_argument("--branch", choices=("open", "crossed"), default=None,
                   help="the assembly analysed (open: the 1966 program's); overrides a "
                        "spec's [scene] branch")
    p.add_argument("--format", choices=("csv", "json"), default="csv",
                   help="csv (default; a header row) or json ({columns, rows})")
    p.add_argument("--only", choices=("kinematics",),
                   help="kinematics: angles, velocities and accelerations; the force "
                        "analysis is not run")
    p.add_argument("--header", choices=("units", "names"), default="units",
                   help="CSV header: NAME[unit] (default) or the bare names; JSON always "
                        "has 'units' and 'descriptions' beside 'columns'")
    p.add_argument("--torque-parts", action="store_true",
                   help="add TORQ_INERTIA, TORQ_GRAVITY, TORQ_LOADS and TORQ_TEX, the parts "
                        "of TORQ (without it: the parts the spec's scene has)")
    p.add_argument("-o", "--output", help=OUTPUT_HELP)

    p = add("diff", "compare a listing with a golden printout, field by field "
            "(either may be --render text); exit 1 if they differ")
    p.add_argument("listing", help="the listing (- reads it from standard input)")
    p.add_argument("golden", help="the golden printout (- reads it from standard input)")

    p = add("bench", "accuracy against cost of the number models, ARCCOS and step "
                                "size: a table on stdout, and a report with -o (needs mpmath)")
    p.add_argument("--quick", action="store_true",
                   help="fewer ARCCOS points and port steps, one timing round "
                        "(about 10 s instead of about a minute)")
    p.add_argument("--effects", action="store_true",
                   help="instead: what accuracy costs in time for pin friction's solve "
                        "and simulate (rtol, method) and the hard cases, a small grid, "
                        "one round (needs scipy)")
    p.add_argument("-o", "--output", metavar="REPORT.md",
                   help="also write the markdown report here and its PNG beside it "
                        "(folders created); nothing is written without -o")
    p = add("check", "report on a deck: values, Grashof and crank-rocker margins, "
            "transmission angle, peak loads, cycle work, the 1966 quirks it triggers")
    p.add_argument("deck", metavar="DECK|SPEC.toml", help=INPUT_HELP)
    p.add_argument("--branch", choices=("open", "crossed"), default=None,
                   help="the assembly analysed (open: the 1966 program's); overrides a "
                        "spec's [scene] branch")
    p.add_argument("--format", choices=("text", "json"), default="text",
                   help="text (default) or json: the report's facts (kind, Grashof sum and "
                        "margin, toggles, arcs, limit positions, peaks with their angles, "
                        "cycle work, flywheel, bearings, verdict), each number as {value, "
                        "unit}, the status and the report's lines")
    p.add_argument("-o", "--output", help=OUTPUT_HELP)
    p.add_argument("--crank-rocker", action="store_true",
                   help="require a crank-rocker (the 1966 program's test): exit 3 if not")
    p.add_argument("--bearing-threshold", type=load_fraction, default=None, metavar="FRACTION",
                   help=BEARING_THRESHOLD_HELP)

    p = add("plot", "the report's Figures 12, 13, 14 and 16 as PNG files, and polar "
            "diagrams of the other two bearings (the report's 15 and 17, captions lost), "
            "from the modern engine: fig12-driving-torque.png, fig13-force-4-on-1.png, "
            "fig14-force-3-on-4-rel-link4.png, fig16-shaking-force.png, force-2-on-1.png, "
            "force-3-on-2.png; with --only kinematics: kin-link-angles.png, "
            "kin-angular-velocity.png, kin-angular-acceleration.png, kin-pin-velocity.png, "
            "kin-pin-acceleration.png")
    p.add_argument("deck", metavar="DECK|SPEC.toml", help=INPUT_HELP)
    p.add_argument("-o", "--output", required=True, metavar="DIR",
                   help="directory for the PNG files (created if needed; not -: several "
                        "files)")
    p.add_argument("--only", choices=("kinematics",),
                   help="kinematics: velocity and acceleration curves instead of the forces")
    p.add_argument("--linkage", action="store_true",
                   help="draw the linkage itself to scale (linkage.png): joints, centres of "
                        "mass, the path of G3, toggle limits (the report's Figure 9)")
    p.add_argument("--at", type=angle_list, default=None, metavar="DEG[,DEG...]",
                   help="with --linkage: the crank angles drawn (default 40, or the middle "
                        "of the first arc where the linkage assembles if not at 40); one where the "
                        "linkage does not assemble is left out with a warning, and if none "
                        "does, nothing is drawn (exit 2)")
    p.add_argument("--point", type=point_spec, action="append", default=[],
                   metavar="LINK:R:ANGLE", help="with --linkage: also trace this point (link "
                   "2, 3 or 4; R from its base pin, in the deck's length unit: in, or m in SI; "
                   "ANGLE deg CCW from its line); repeatable")
    p.add_argument("--branch", choices=("open", "crossed"), default=None,
                   help="the assembly analysed (open: the 1966 program's); overrides a "
                        "spec's [scene] branch")
    p.add_argument("--bearings", action="store_true",
                   help="the load on each member at each pin, relative to the member, with "
                        "the arcs never loaded shaded (bearings.png)")
    p.add_argument("--bearing-threshold", type=load_fraction, default=None, metavar="FRACTION",
                   help="with --bearings: " + BEARING_THRESHOLD_HELP)
    p.add_argument("--animate", action="store_true",
                   help="also write linkage.gif, one cycle (matplotlib's Pillow writer)")

    p = add("balance", "counterweights on the crank and rocker that cancel the shaking "
            "force (Berkof-Lowen), and what they cost: shaking moment, torque, pin loads; "
            "for a slider-crank, the crank counterweight and what it leaves")
    p.add_argument("deck", metavar="DECK|SPEC.toml", help=INPUT_HELP)
    p.add_argument("--radius2", type=positive_length, metavar="R",
                   help="the crank's counterweight this far from O2, in the deck's length "
                        "unit: in, or m in SI (default R2)")
    p.add_argument("--radius4", type=positive_length, metavar="R",
                   help="the rocker's counterweight this far from O4, in the deck's length "
                        "unit: in, or m in SI (default R4)")
    p.add_argument("--branch", choices=("open", "crossed"), default=None,
                   help="the assembly analysed (open: the 1966 program's); overrides a "
                        "spec's [scene] branch")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="also write the balanced design: a spec if FILE ends .toml, else a "
                        "deck (atomically; a slider-crank's is a spec); -: on stdout in the "
                        "input's form (a spec for a spec), the report then on stderr")

    p = add("sweep", "a grid of designs from a spec's [sweep]: per design the peak and RMS "
            "torque, flywheel, pin loads, shaking force and moment, transmission angle, kind")
    p.add_argument("spec", metavar="SPEC.toml", help=SPEC_HELP)
    p.add_argument("-o", "--output", metavar="FILE.csv",
                   help="write the table here (atomically); - or none: stdout")
    p.add_argument("--plot", metavar="FILE.png",
                   help="also draw the Pareto plot of the [sweep]'s two pareto figures")
    p.add_argument("--pareto", metavar="FIG[:max],FIG[:max]",
                   help="the Pareto front's two figures instead of the [sweep]'s, each "
                        "FIGURE, FIGURE:min or FIGURE:max (e.g. GAMMA_MIN:max,TORQ_PEAK; a "
                        "bare GAMMA_MIN is maximised, every other figure minimised)")
    p.add_argument("--workers", type=worker_count, default=None, metavar="N",
                   help="local processes/threads (default: all cores, through dask when it "
                        "is installed; 1: in this process)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on the dask.distributed cluster whose scheduler is at ADDRESS "
                        "(e.g. tcp://host:8786)")
    p.add_argument("--branch", choices=("open", "crossed"), default=None,
                   help="the assembly analysed (open: the 1966 program's); overrides a "
                        "spec's [scene] branch")

    p = add("simulate", "the crank driven by the spec's [motor] (forward dynamics): the "
            "time history as CSV with units, the motor sizing, a plot of speed, torque and "
            "power against time "
            "(needs scipy: pip install -e \".[dynamics]\")")
    p.add_argument("spec", metavar="SPEC.toml", help=SPEC_HELP)
    p.add_argument("-o", "--output", metavar="FILE.csv",
                   help="write the time history here (atomically); - or none: stdout")
    p.add_argument("--plot", metavar="FILE.png",
                   help="also draw the crank speed, the torques and the motor's power against "
                        "time t [s]")

    p = add("synth", "synthesise linkages from a spec's [synthesis] (crank_rocker, function, "
            "motion or path) and rank them by dynamics in its [scene]: a CSV, best first")
    p.add_argument("spec", metavar="SPEC.toml", help=SPEC_HELP)
    p.add_argument("-o", "--output", metavar="FILE.csv",
                   help="write the ranked table here (atomically); - or none: stdout")
    p.add_argument("--write-best", metavar="DIR",
                   help="also write the [synthesis] best-ranked candidates as DIR/best-K.toml "
                        "specs, and DIR/best-K.dat decks where a deck can hold them")

    p = add("tolerance", "a Monte Carlo of a spec's [tolerance] deviations: per design "
            "figure the nominal, mean, std, 5/95 percentiles and first-order sensitivities")
    p.add_argument("spec", metavar="SPEC.toml", help=SPEC_HELP)
    p.add_argument("-o", "--output", metavar="FILE",
                   help="write the table here (atomically); - or none: stdout")
    p.add_argument("--workers", type=worker_count, default=None, metavar="N",
                   help="N > 1: dask's local threads when dask is installed (the same "
                        "numbers); default: this process")

    p = add("report", "one self-contained HTML page for a deck or spec: its values with "
            "units, kind, peaks, the linkage drawn and animated, the report's figures, "
            "bearings, balancing, the 1966 quirks (needs matplotlib)")
    p.add_argument("deck", metavar="DECK|SPEC.toml", help=INPUT_HELP)
    p.add_argument("-o", "--output", required=True, metavar="FILE.html",
                   help="write the page here (atomically; - for stdout)")
    p.add_argument("--at", type=one_angle, default=None, metavar="DEG",
                   help="the crank angle the linkage is drawn at, deg (default 40, or the "
                        "middle of the first arc where the linkage assembles if not at 40)")
    p.add_argument("--branch", choices=("open", "crossed"), default=None,
                   help="the assembly (default: the spec's [scene] branch, else open)")

    p = add("help", "help on a topic: deck (the card layout and units), "
            "conventions, arith, exit, io (- for stdin, -o - for stdout)")
    p.add_argument("topic", nargs="?", metavar="TOPIC",
                   help="deck, conventions, arith, exit or io")

    p = add("punch", "punch an 80-column deck from a TOML spec with names and units "
            "(see decks/example.toml)")
    p.add_argument("spec", metavar="SPEC.toml", help=SPEC_HELP)
    p.add_argument("-o", "--output", metavar="DECK",
                   help="write to DECK (atomically); - or none: stdout")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)  # what made an output (report)
    from sielaff.tools import output

    output.committed.clear()  # what this run replaces (main may run more than once)
    install_signal_handlers(process=_PROCESS)
    if sys.stderr is None:  # started with 2>&-: messages go nowhere, the work still runs
        sys.stderr = open(os.devnull, "w")  # noqa: SIM115 (lives as long as the process)
    if sys.stdout is None:  # started with >&-
        if getattr(args, "output", None) not in (None, "-") and args.command in (
                "run", "table", "punch", "check", "sweep", "simulate", "synth", "tolerance",
                "report"):
            sys.stdout = open(os.devnull, "w")  # noqa: SIM115 (nothing is printed there)
        else:
            return _closed_stream()
    debug = getattr(args, "debug", False)
    try:
        with warnings.catch_warnings():
            # A Python warning becomes one diagnostic line, never source text and a path.
            warnings.showwarning = _warning_line
            return _dispatch(args, debug)
    finally:
        _flush()
        finish_signals()


def _flush() -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError, AttributeError):
            pass


def _closed_stream() -> int:
    """stdout or stderr was closed before the run: say so where we still can, exit 2."""
    message = "sielaff: standard output is closed (started with >&-?); nothing was run\n"
    for fd in (2, 1):
        try:
            os.write(fd, message.encode())
            break
        except OSError:
            continue
    return EXIT_DECK


def _warning_line(message, category, filename, lineno, file=None, line=None) -> None:
    print(f"sielaff: warning: {message}", file=sys.stderr)


def _dispatch(args: argparse.Namespace, debug: bool) -> int:
    from sielaff.tools.common import take_stdin

    try:
        take_stdin(args)  # an input named -: standard input, called <stdin>
        return _command(args.func)(args)
    except KeyboardInterrupt:
        if debug:
            raise
        return _said_signal(signal.SIGINT)
    except Terminated as exc:
        if debug:
            raise
        return _said_signal(exc.signum)
    except BrokenPipeError:
        # The reader went away (``sielaff run deck | head``): leave quietly.
        silence_stdout()
        return 0
    except Exception as exc:
        if debug:
            raise
        # A signal already turned into an exception ends the run, whatever failed after it:
        # one raised in a weakref callback (matplotlib's transforms) is swallowed there and
        # sent again a moment later (``_unraisable``), and the figure it cut short may fail
        # first ("Invalid bounding box"); one that arrived while a C extension was loading
        # comes back as that extension's ImportError.
        if SIGNAL_STATE["raised"] is not None:
            return _said_signal(SIGNAL_STATE["raised"])
        return _failed(exc)


def _failed(exc: Exception) -> int:
    """Say in one line what failed and return its exit status; re-raise what is a bug."""
    if isinstance(exc, DeckError | CommandError | ValueError):
        print(str(exc) if isinstance(exc, DeckError | CommandError) else f"sielaff: {exc}",
              file=sys.stderr)
        return getattr(exc, "status", EXIT_DECK)
    if isinstance(exc, OSError):  # an output file that cannot be written, a full disk
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"sielaff: {where}{exc.strerror or exc}", file=sys.stderr)
        return EXIT_DECK
    raise exc


def _said_signal(signum: int) -> int:
    """Say on stderr that signal ``signum`` ended the run, and what it left of the outputs;
    its exit status (130 for Ctrl-C, 128 + N for another)."""
    from sielaff.tools.output import changed_note

    finish_signals()  # the signal sent again after a finaliser swallowed it says nothing twice

    if signum == signal.SIGINT:
        print(f"sielaff: interrupted; {changed_note()}", file=sys.stderr)
        return EXIT_INTERRUPTED
    print(f"sielaff: terminated by {signal.Signals(signum).name}; {changed_note()}",
          file=sys.stderr)
    return 128 + signum


#: numpy's BLAS starts a pool of threads, one per core, as it loads; sielaff calls no BLAS
#: routine, so the pool is start-up cost and nothing else (benchmarks/listing.py measures
#: it).  These ask the common BLAS builds for one thread.
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "VECLIB_MAXIMUM_THREADS")


def one_blas_thread() -> None:
    """Ask for a BLAS of one thread, unless the user set the variable: before numpy loads
    (``import sielaff.cli`` does not load it), so only the command's entry points call it."""
    for name in BLAS_THREAD_VARIABLES:
        os.environ.setdefault(name, "1")


#: True when main runs as the ``sielaff`` process (``entry``), not called in-process.
_PROCESS = False


def entry() -> None:
    """Console-script entry point (and ``python -m sielaff``).

    A signal that arrives after the command has ended but before main returns (a few
    instructions) is reported here as _dispatch would; after that, signals are ignored
    (``finish_signals``)."""
    global _PROCESS
    _PROCESS = True
    one_blas_thread()
    try:
        status = main()
    except (KeyboardInterrupt, Terminated) as exc:
        status = _said_signal(exc.signum if isinstance(exc, Terminated) else signal.SIGINT)
    if SIGNAL_STATE["raised"] is not None:
        # The signal may have broken into a C extension's initialisation (matplotlib's
        # ft2font runs enum code as it loads), and finalising the half-made module aborts
        # the interpreter ("Fatal Python error: PyThreadState_Get", status -6) after the
        # message.  The outputs are settled and the message said: end without finalising.
        _flush()
        os._exit(status)
    sys.exit(status)
