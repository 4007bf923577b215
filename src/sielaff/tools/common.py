"""What every command shares: exit statuses, the one-line error, loading a deck with
its checks, output that never destroys an input, signals, and a closed stdout.

Exit statuses (``sielaff help exit``): 0 done, 1 ``diff`` found differences, 2 bad
input or output, 3 not a crank-rocker, 130 Ctrl-C, 128 + N another signal N (SIGTERM
143, SIGHUP 129).  A failure is one line on stderr naming the card and columns or the
field.
"""

from __future__ import annotations

import io
import os
import signal
import sys
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any, BinaryIO

from sielaff.emulator.cards import PARAMETER_CARDS, Deck, read_deck
from sielaff.tools.errors import (  # noqa: F401 (re-exported: every command's statuses)
    EXIT_DECK,
    EXIT_DIFFERENT,
    EXIT_INTERRUPTED,
    EXIT_NOT_CRANK_ROCKER,
    CommandError,
)
from sielaff.tools.problems import nan_reason, range_problem  # noqa: F401

if TYPE_CHECKING:
    from sielaff.engine.scene import Scene


# -- signals ------------------------------------------------------------------------
class Terminated(BaseException):
    """SIGTERM or SIGHUP arrived: unwind like Ctrl-C, so temporary files are removed."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum
        self.status = 128 + signum
        self.name = signal.Signals(signum).name


#: ``process``: main runs as the ``sielaff`` process (not called in-process by a test);
#: ``finished``: its command has ended and said so, so a late signal changes nothing.
#: ``raised``: the signal last turned into an exception (a C extension being imported
#: when it arrives can swallow that exception into an ImportError of its own).
SIGNAL_STATE: dict = {"process": False, "finished": False, "raised": None}


def _raise_terminated(signum, _frame) -> None:
    from sielaff.tools import output

    if SIGNAL_STATE["finished"]:  # the command is done: nothing is left to protect
        return
    if output.deferring():  # outputs are being renamed into place: act when they are
        output.defer(signum)
        return
    SIGNAL_STATE["raised"] = signum
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise Terminated(signum)


def _unraisable(unraisable) -> None:
    """sys.unraisablehook of the ``sielaff`` process: a signal raised inside a weakref
    callback or a ``__del__`` (matplotlib's transforms have them) cannot unwind the
    command; Python would print it as a traceback and go on.  Send it again, from a
    thread, a moment later: it lands in the command's own code and unwinds it."""
    exc = unraisable.exc_value
    if not isinstance(exc, Terminated | KeyboardInterrupt):
        sys.__unraisablehook__(unraisable)
        return
    import threading
    import time

    signum = exc.signum if isinstance(exc, Terminated) else signal.SIGINT

    def again() -> None:
        time.sleep(0.01)  # let the hook return first
        os.kill(os.getpid(), signum)

    threading.Thread(target=again, daemon=True).start()


def install_signal_handlers(process: bool = False) -> None:
    """SIGTERM and SIGHUP (``timeout``, a closed terminal) end a run the way Ctrl-C does:
    every output written whole or not at all, the temporary file removed.  They wait
    while a set of outputs is being renamed into place (``sielaff.tools.output``), and
    so does Ctrl-C when ``process`` (the ``sielaff`` process itself: in-process callers
    keep Python's own Ctrl-C)."""
    SIGNAL_STATE.update(process=process, finished=False, raised=None)
    if process:
        sys.unraisablehook = _unraisable
    for name in ("SIGTERM", "SIGHUP", "SIGINT"):
        if hasattr(signal, name):
            if name == "SIGINT" and (not process or signal.getsignal(signal.SIGINT) is not
                                     signal.default_int_handler):
                continue  # Ctrl-C ignored by the parent (nohup, a background job): keep it
            signal.signal(getattr(signal, name), _raise_terminated)


def finish_signals() -> None:
    """The ``sielaff`` process's command has ended and said so: from now on a signal is
    ignored (Python restores the default handlers as it exits, and a SIGTERM then would
    end the process silently with a status that says nothing was done)."""
    if SIGNAL_STATE["process"]:
        SIGNAL_STATE["finished"] = True
        for name in ("SIGTERM", "SIGHUP", "SIGINT"):
            if hasattr(signal, name):
                signal.signal(getattr(signal, name), signal.SIG_IGN)


# -- standard input -----------------------------------------------------------------
#: The name an input given as ``-`` (standard input) goes by in every message.
STDIN = "<stdin>"

#: What this run read from standard input: "taken" (an input was ``-``), "kind" ("deck"
#: or "spec", told by :func:`stdin_kind`), "head" (the bytes read to tell it), "deck"
#: (the deck once read), "spec" (a spec's bytes once read).
_STDIN: dict = {}

#: The commands' input arguments that may be ``-``.
INPUT_NAMES = ("deck", "spec", "listing", "golden")

#: Lines read (each at most a card line's 4,096 bytes) to tell a spec from a deck before
#: deciding "deck".
SNIFF_LINES = 1000


def take_stdin(args: Any) -> None:
    """Turn a command's input named ``-`` into :data:`STDIN` (read when the command asks;
    at most one input may be ``-``).  Called once per run, before the command."""
    _STDIN.clear()
    named = [name for name in INPUT_NAMES if getattr(args, name, None) == "-"]
    if len(named) > 1:
        raise CommandError(f"sielaff: {' and '.join(named)} are both -: standard input "
                           "holds one of them; name the other's file")
    if named:
        setattr(args, named[0], STDIN)
        _STDIN["taken"] = True


def is_stdin(path: str | None) -> bool:
    """True if ``path`` is the input this run reads from standard input."""
    return path == STDIN and bool(_STDIN.get("taken"))


def stdin_bytes() -> BinaryIO:
    """Standard input as a binary stream; one line if it is closed (``0<&-``)."""
    stream = getattr(sys.stdin, "buffer", None)
    if stream is None:
        raise CommandError("sielaff: -: standard input is closed (started with 0<&-?)")
    return stream


def looks_like_spec(line: bytes) -> bool:
    """The rule for standard input: a TOML spec if its first non-blank line begins with
    ``[`` (a table) or ``#`` (a comment) or holds ``=`` (a key); else a deck, whose
    cards of FORMAT(4F8.4) hold none of the three."""
    text = line.decode("latin-1").lstrip()
    return text.startswith(("[", "#")) or "=" in text


def stdin_kind() -> str:
    """"spec" or "deck": what standard input holds, by :func:`looks_like_spec` on its first
    non-blank line (read once, at most :data:`SNIFF_LINES` lines of a card's length:
    endless blank lines or ``/dev/zero`` are told at once and left to the deck's reader,
    which refuses them naming the card)."""
    if "kind" not in _STDIN:
        from sielaff.emulator.cards import LINE_LIMIT

        stream, head, kind = stdin_bytes(), bytearray(), "deck"
        for _ in range(SNIFF_LINES):
            line = stream.readline(LINE_LIMIT)
            head += line
            if not line:
                break
            if line.strip():
                kind = "spec" if looks_like_spec(line) else "deck"
                break
        _STDIN.update(kind=kind, head=bytes(head))
    return _STDIN["kind"]


class _Replay:
    """Standard input with the lines :func:`stdin_kind` read put back in front."""

    def __init__(self, head: bytes, rest: BinaryIO) -> None:
        self._head, self._rest = io.BytesIO(head), rest

    def readline(self, limit: int = -1) -> bytes:
        # the head holds whole lines as read with the deck reader's limit: no line spans it
        return self._head.readline(limit) or self._rest.readline(limit)


def is_spec(path: str) -> bool:
    """True if ``path`` names a TOML spec: ``*.toml``, or standard input holding one."""
    return stdin_kind() == "spec" if is_stdin(path) else path.endswith(".toml")


def spec_path(path: str) -> bool:
    """True if a command that reads only specs takes ``path``: ``*.toml`` or standard
    input (read as TOML whatever its first line, so a broken spec is told where)."""
    return is_stdin(path) or path.endswith(".toml")


def input_exists(path: str) -> bool:
    """True if the input ``path`` is there to read (standard input always is)."""
    return is_stdin(path) or os.path.lexists(path)


def read_spec(path: str) -> dict:
    """The parsed spec at ``path``, or on standard input (at most the spec's byte limit
    read: an endless stream is refused at once); PunchError naming it if not a spec."""
    from sielaff.tools import spec as specs

    if not is_stdin(path):
        return specs.read_spec(path)
    if "spec" not in _STDIN:
        stdin_kind()
        head = _STDIN["head"]
        limit = specs.MAX_SPEC_BYTES + 1 - len(head)
        try:
            rest = stdin_bytes().read(limit) if limit > 0 else b""
        except OSError as err:
            raise specs.PunchError(f"{STDIN}: cannot read the spec ({err.strerror or err})") \
                from None
        _STDIN["spec"] = head + rest
    return specs.parse_spec(_STDIN["spec"], STDIN)


def spec_source(path: str) -> str:
    """The text of the spec at ``path`` as written (standard input's, once read by
    :func:`read_spec`), for a page that shows it."""
    if is_stdin(path):
        read_spec(path)
        return _STDIN["spec"].decode("utf-8", errors="replace")
    with open(path, encoding="utf-8") as f:
        return f.read()


def read_input_deck(path: str) -> Deck:
    """The deck at ``path``, or on standard input (read card by card as a file is, once);
    its warnings are not printed."""
    if not is_stdin(path):
        return read_deck(path)
    if "deck" not in _STDIN:
        if stdin_kind() == "spec":
            raise CommandError(f"{STDIN}: a TOML spec (its first line is a table, a comment "
                               "or a key), not a deck: punch it first (sielaff punch - | "
                               "sielaff run -)")
        from sielaff.emulator.cards import read_deck_stream

        _STDIN["deck"] = read_deck_stream(_Replay(_STDIN["head"], stdin_bytes()), STDIN)
    return _STDIN["deck"]


def stdin_text() -> io.TextIOWrapper:
    """A text stream over standard input for a listing (``diff -``), ASCII as a listing
    file is opened; the caller detaches it (standard input stays open)."""
    return io.TextIOWrapper(stdin_bytes(), encoding="ascii", errors="replace")


# -- output -------------------------------------------------------------------------
def stdout_output(output: str | None) -> bool:
    """True if ``-o`` asks for standard output (``-o -``)."""
    return output == "-"


def refuse_stdout(output: str | None, what: str, option: str = "-o",
                  instead: str = "a folder") -> None:
    """Refuse ``-`` for ``option`` (``-o`` by default) whose output is ``what`` (several
    files, or an image), one line naming what to give ``instead``, the usage status."""
    if output == "-":
        raise CommandError(f"sielaff: {option} -: {what}, which standard output cannot "
                           f"hold: name {instead}")


def refuse_overwriting_inputs(output: str | None, inputs: Iterable[str]) -> None:
    """Refuse, before any work, an ``-o`` that is (or links to) one of the inputs."""
    if output in (None, "-", ""):
        if output == "":
            raise CommandError("sielaff: -o '': an empty file name")
        return
    for path in inputs:
        if is_stdin(path):  # standard input is no file -o could overwrite
            continue
        try:
            same = os.path.samefile(output, path)
        except OSError:
            same = os.path.realpath(output) == os.path.realpath(path)
        if same:
            raise CommandError(f"sielaff: -o {output} is the input {path}: refusing to "
                               "overwrite it (choose another output file)")


def refuse_bad_output(output: str | None, inputs: Iterable[str]) -> None:
    """Refuse, before any work, an ``-o`` that is one of the inputs or a folder (every
    command that writes one file per option asks this one place)."""
    refuse_overwriting_inputs(output, inputs)
    if output and os.path.isdir(output):
        raise CommandError(f"sielaff: {output} is a folder: name the file to write")


def write_stdout(text: str) -> bool:
    """Write ``text`` on stdout; False (and stdout quietly closed) if the reader went away,
    so the caller can still report its status and error line."""
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
        return True
    except BrokenPipeError:
        silence_stdout()
        return False


def silence_stdout() -> None:
    """Point stdout at /dev/null: the pipe's reader is gone, and Python's final flush
    must not fail again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


# -- decks ---------------------------------------------------------------------------
def load_deck(path: str) -> Deck:
    """Read a deck (a file, or standard input as :data:`STDIN`); its warnings go to
    stderr, one line each."""
    if not input_exists(path):
        raise CommandError(f"{path}: no such deck")
    deck = read_input_deck(path)
    for warning in deck.warnings:
        print(f"sielaff: warning: {warning}", file=sys.stderr)
    return deck


def mechanism_problem(deck: Deck) -> CommandError | None:
    """A deck's mechanism that no command can use (exit 2) or that is not a crank-rocker
    (exit 3), as one error; None if it is a crank-rocker the engine can analyse."""
    from sielaff.mechanism import crank_rocker_failure, validate

    try:
        validate(deck.mechanism)
    except ValueError as exc:
        card = next((n for n, names in enumerate(PARAMETER_CARDS, 1)
                     if str(exc).split(" ", 1)[0] in names), None)
        where = f": card {card}" if card else ""
        return CommandError(f"{deck.path}{where}: {exc}")
    failure = crank_rocker_failure(deck.mechanism, getattr(deck, "exact", None))
    if failure:
        return CommandError(f"{deck.path}: card 3: THIS IS NOT A CRANK ROCKER MECHANISM: "
                            f"{failure}", EXIT_NOT_CRANK_ROCKER)
    return None


def load_runnable(path: str, arithmetic="float64", max_sheets: int | None = None) -> Deck:
    """A deck for the emulator: lengths it can hold, ranges that end.

    A deck that is not a crank-rocker is let through: the 1966 program prints its
    message and stops before it ever loops.
    """
    from sielaff.mechanism import crank_rocker_failure

    deck = punched_deck(path) if is_spec(path) else load_deck(path)
    problem = mechanism_problem(deck)
    if problem is not None and problem.status == EXIT_DECK:
        raise problem
    if crank_rocker_failure(deck.mechanism, getattr(deck, "exact", None)) is None:
        problem = range_problem(deck, arithmetic, max_sheets)
        if problem is not None:
            raise problem
    return deck


def punched_deck(path: str) -> Deck:
    """The deck a TOML spec punches (``sielaff punch``), read back card by card as the 1966
    program reads it: what ``run`` takes for a spec.  The tables a deck cannot carry are
    named in one warning; a bad spec is one line naming its key."""
    import io

    from sielaff.emulator.cards import read_deck_stream
    from sielaff.tools.spec import PunchError, punch_deck
    from sielaff.tools.spec_fields import OTHER_TABLES

    if not input_exists(path):
        raise CommandError(f"{path}: no such spec")
    try:
        spec = read_spec(path)
        text = punch_deck(spec, path)
    except PunchError as exc:
        raise CommandError(str(exc), exc.status) from None
    left = [f"[{t}]" for t in OTHER_TABLES if t in spec]
    if left:
        print(f"sielaff: warning: {path}: the 1966 program reads the punched deck, without "
              f"{', '.join(left)}", file=sys.stderr)
    deck = read_deck_stream(io.BytesIO(text.encode("ascii")), path)
    for warning in deck.warnings:
        print(f"sielaff: warning: {warning}", file=sys.stderr)
    return deck


def load_for_engine(path: str, outputs=None) -> Deck:
    """A deck for the modern engine: a crank-rocker (else exit 3) whose ranges all end and
    whose ``outputs`` (default: all) stay in the 1410's range over a revolution."""
    return load_scene(path, outputs)[0]


def no_scene() -> Scene:
    """The 1966 program's scene (a deck has no other)."""
    from sielaff.engine.scene import Scene

    return Scene()


def read_spec_deck(path: str, kinds: tuple[str, ...] = ()) -> tuple[Deck, Scene]:
    """A TOML spec's deck (in its unit system) and its :class:`~sielaff.Scene`; a spec of
    a ``[linkage] kind`` besides the four-bar only if ``kinds`` names it."""
    deck, scene, _ = read_spec_with(path, kinds=kinds)
    assert deck is not None
    return deck, scene


def read_spec_with(path: str, read: Callable[[dict, str], Any] | None = None,
                   deck: bool = True, kinds: tuple[str, ...] = ()
                   ) -> tuple[Deck | None, Scene, Any]:
    """A TOML spec's deck (in its unit system; None with ``deck=False``, for a spec whose
    linkages a command makes, as synth's), its :class:`~sielaff.Scene`, and
    ``read(spec, path)``: the command's own table (``[tolerance]``, ``[synthesis]``,
    ...).  A ``[linkage] kind`` besides the four-bar is refused unless ``kinds`` names
    it.  Any fault is one CommandError naming the file and the key."""
    import dataclasses

    from sielaff.tools.spec import PunchError, scene_of, spec_deck
    from sielaff.tools.spec_fields import FOUR_BAR, KIND_COMMANDS, linkage_kind

    if not input_exists(path):
        raise CommandError(f"{path}: no such spec")
    try:
        spec = read_spec(path)
        kind = linkage_kind(spec, path)
        if kind != FOUR_BAR and kind not in kinds:
            takers = ", ".join(KIND_COMMANDS[:-1]) + " and " + KIND_COMMANDS[-1]
            raise PunchError(f'{path}: [linkage] kind = "{kind}": this command takes a '
                             f"four-bar only so far (sielaff {takers} take this kind)")
        units, scene = scene_of(spec, path)
        own = None if read is None else read(spec, path)
        made = spec_deck(spec, path) if deck else None
    except PunchError as exc:
        raise CommandError(str(exc), exc.status) from None
    if made is not None:
        made = dataclasses.replace(made, mechanism=made.mechanism.replace(units=units))
    return made, scene, own


def load_scene(path: str, outputs=None, any_linkage: bool = False, branch: str | None = None,
               any_kind: bool = False, kinds: tuple[str, ...] = (), note: bool = True
               ) -> tuple[Deck, Scene]:
    """A deck, or a TOML spec (``*.toml``) with its ``[scene]``, for the modern engine:
    (the deck, its Scene).  Checked as ``load_for_engine``
    says, with the scene's effects in the results; with ``any_linkage`` any four-bar
    whose fields can exist (the crank-rocker test and the ranges do not apply).
    ``branch`` ("open" or "crossed") overrides the spec's ``[scene] branch``.  With
    ``any_kind`` every Grashof kind and a triple rocker are taken, not only a
    crank-rocker: a linkage whose crank cannot turn fully is worked over the arcs where
    it assembles, and stderr says which (:func:`kind_note`).  A spec of another
    ``[linkage] kind`` is taken if ``kinds`` names it (:func:`other_kind`), else refused
    in one line; ``note=False`` leaves out its stderr line on the arcs it is worked over
    (a command that says more itself).  ``outputs`` may be a function of the mechanism
    (its model's names)."""
    import dataclasses

    if is_spec(path):
        deck, scene = read_spec_deck(path, kinds)
    else:
        deck, scene = load_deck(path), no_scene()
    if branch is not None:
        scene = dataclasses.replace(scene, branch=branch)
    if callable(outputs):
        outputs = outputs(deck.mechanism)
    from sielaff.mechanism import Mechanism

    if not isinstance(deck.mechanism, Mechanism):
        from sielaff.tools.kinds import other_kind

        return other_kind(deck, scene, outputs, any_kind or any_linkage,
                          note=note and not any_linkage), scene
    if any_linkage:  # any four-bar (plot --linkage): only a mechanism that can exist
        problem = mechanism_problem(deck)
        if problem is not None and problem.status == EXIT_DECK:
            raise problem
        return deck, scene
    problem = mechanism_problem(deck)
    if any_kind and problem is not None and problem.status == EXIT_NOT_CRANK_ROCKER:
        note = kind_note(deck)
        if note is None:
            raise CommandError(f"{deck.path}: card 3: the loop never closes: no crank angle "
                               "assembles this linkage")
        print(f"sielaff: {note}", file=sys.stderr)
        from sielaff.engine.classify import linkage_class

        c = linkage_class(deck.mechanism)
        if not c.turns_fully or c.kind == "change-point":
            import warnings

            from sielaff.engine.analysis import AssemblyWarning

            # the note above says where it assembles: no warning per sampled position
            warnings.filterwarnings("ignore", category=AssemblyWarning)
            return deck, scene  # the rates are infinite at the toggles or the change
            # point: nothing to bound; the positions where they are not finite are left out
        problem = None
    problem = (problem or range_problem(deck)
               or results_problem(deck, outputs, scene))
    if problem is not None:
        raise problem
    return deck, scene


def kind_note(deck: Deck) -> str | None:
    """One line for a linkage that is not a crank-rocker: its kind and the arcs of THETA 2
    worked over; None if no crank angle assembles it."""
    from sielaff.engine.classify import linkage_class

    c = linkage_class(deck.mechanism)
    if not c.arcs:
        return None
    if c.kind == "change-point":
        at = " and ".join(f"{a:g}" for a in change_points(deck.mechanism)) or "one position"
        return (f"{deck.path}: a change-point, not a crank-rocker: link 2 turns fully but the "
                f"linkage folds flat at THETA 2 = {at} deg, where the rates are not defined; "
                "positions there are left out (sielaff run refuses it, as the 1966 program "
                "does)")
    if c.turns_fully:
        return (f"{deck.path}: a {c.kind}, not a crank-rocker: link 2 turns fully "
                "(sielaff run refuses it, as the 1966 program does)")
    arcs = ", ".join(f"{a:.2f} to {b:.2f}" for a, b in c.arcs)
    return (f"{deck.path}: a {c.kind}, not a crank-rocker: link 2 swings between toggles "
            f"over THETA 2 = {arcs} deg; positions outside are left out")


def change_points(m) -> list[float]:
    """The crank angles [deg] (0, 180 or both) where a change-point linkage folds flat:
    A on the frame's line with |A O4| = R3 + R4 or |R3 - R4|, to a few times the
    tolerance linkage_class decides the kind to (mechanism.BOUNDARY of the lengths)."""
    from sielaff.mechanism import BOUNDARY

    out = []
    scale = 4.0 * BOUNDARY * (m.R1 + m.R2 + m.R3 + m.R4)
    for at, d in ((0.0, abs(m.R1 - m.R2)), (180.0, m.R1 + m.R2)):
        if min(abs(d - (m.R3 + m.R4)), abs(d - abs(m.R3 - m.R4))) <= scale:
            out.append(at)
    return out


def not_a_crank_rocker(deck: Deck) -> str | None:
    """The one-line refusal naming card 3 and the failed condition, or None."""
    problem = mechanism_problem(deck)
    if problem is not None and problem.status == EXIT_NOT_CRANK_ROCKER:
        return str(problem)
    return None



def results_problem(deck: Deck, outputs=None, scene: Scene | None = None
                    ) -> CommandError | None:
    """Results past the IBM 1410's range (|x| >= 1E99, or not finite) over a revolution,
    where the listing could not print them and ``sielaff run`` stops (exit 2): one error
    naming the worst quantity, so every command refuses the same decks."""
    import warnings

    import numpy as np

    from sielaff.engine import RESULTS, FrictionWarning, analyze
    from sielaff.quantities import unit

    with np.errstate(all="ignore"), warnings.catch_warnings():
        # only the steps ``outputs`` need (kinematics: no forces); friction with no
        # solution is this check's one line below, not a warning besides it
        warnings.simplefilter("ignore", FrictionWarning)
        r = analyze(deck.mechanism, np.arange(0.0, 360.0, 1.0), outputs or RESULTS,
                    scene=scene or no_scene())
    worst, value, at = None, 0.0, 0.0
    for name, v in r.items():
        bad = ~np.isfinite(v) | (np.abs(v) >= 1e99)
        if bad.any():
            worst, value, at = name, float(v[np.argmax(bad)]), float(np.argmax(bad))
            break
    if worst is None:
        return None
    if value != value and scene is not None:  # NaN: an effect's own reason, if it has one
        why = nan_reason(deck, scene, at)
        if why:
            return CommandError(f"{deck.path}: [scene] {why}")
    effects = describe_scene(scene, deck.mechanism.units)
    if effects:  # the scene may be what drives it there: say so, blame no card
        return CommandError(f"{deck.path}: [scene] {effects}: with this scene {worst} = "
                            f"{value:.3g} {unit(worst, deck.mechanism.units)}, past the IBM "
                            "1410's range (1E99) that every command keeps to")
    return CommandError(f"{deck.path}: card 6: TH2D = {deck.mechanism.TH2D:g} rad/sec with "
                        f"these lengths and weights gives {worst} = {value:.3g} {unit(worst)}, "
                        "past the IBM 1410's range (1E99): the 1966 program cannot print it")


def work_text(work: float, abs_work: float, units: str = "in-lb-sec") -> str:
    """The cycle work as a reader should see it: roundoff is shown as zero, with its bound,
    so the text does not depend on the last bits of a CPU's libm."""
    from sielaff.quantities import fmt, unit_of

    bound = 1e-12 * max(abs_work, 1.0)
    if abs(work) <= bound:
        return f"0 {unit_of('work', units)} to roundoff (|W| < {fmt(bound, 'work', units, '.0e')})"
    return fmt(work, "work", units, ".3g")


def describe_scene(scene: Scene | None, units: str = "in-lb-sec") -> str:
    """The effects a scene turns on, in words ("gravity, TH2DD = -40 rad/sec^2, 1 load"),
    or "" for the 1966 scene: each effect's own summary, in the model's order."""
    if scene is None:
        return ""
    effects = [e.summary(scene, units) if e.summary else e.name for e in scene.effects]
    if scene.branch != "open":
        effects.append(f"the {scene.branch} branch")
    return ", ".join(effects)
