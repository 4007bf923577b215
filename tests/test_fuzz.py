"""Fuzzing ``sielaff run`` with mutated decks.

A mutated deck (characters flipped, cards cut, dropped, duplicated or
swapped, garbage inserted) must give one of:

* exit 0 and a listing: every record has carriage control ' ', '0' or '1',
  the last record is a page eject, and stderr holds no error line;
* exit 2 (3 for a mechanism that is not a crank-rocker) and exactly one
  error line, which starts with the deck's path;

within a time bound, and never a traceback.  stderr lines that begin
``sielaff: warning: `` or ``sielaff: 1966 quirk: `` are diagnostics, allowed
in any number (see ``sielaff.cli``); every other line is an error line.
``--max-sheets`` bounds the run: a mutated range card may legally ask for
10**8 sheets.

The CI profile runs a few hundred examples; ``SIELAFF_NIGHTLY=1`` selects
the "nightly" profile (several thousand).  Both run ``sielaff.cli.main``
in-process.
"""

from __future__ import annotations

import contextlib
import io
import os
import tempfile
import time

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from hypothesis.control import currently_in_test_context

from conftest import DECKS
from sielaff.cli import main

settings.register_profile(
    "ci", max_examples=400, deadline=None, derandomize=True,
    suppress_health_check=[HealthCheck.too_slow])
settings.register_profile(
    "nightly", max_examples=5000, deadline=None,
    suppress_health_check=[HealthCheck.too_slow])
PROFILE = settings.get_profile("nightly" if os.environ.get("SIELAFF_NIGHTLY") == "1" else "ci")

DIAGNOSTIC = ("sielaff: warning: ", "sielaff: 1966 quirk: ")
MAX_SHEETS = 25
SECONDS_PER_RUN = 10.0  # generous: a run of 25 sheets takes milliseconds

EXAMPLE = (DECKS / "example.dat").read_bytes().split(b"\n")[:-1]
# A second base deck: more sheets per range, and a second range card.
FINE = EXAMPLE[:6] + [b"    0.50    0.50   360.0", b"   350.0     5.0   400.0"]

#: Characters a flip puts on a card: the ones the reader understands, and
#: the ones it must reject (tab, NUL, CR, non-ASCII, letters, controls).
ALPHABET = b"0123456789 +-.EeDd\t\x00\r\x0c\x7f\xe9\xffOox,*"

flip = st.tuples(st.just("flip"), st.integers(0, 10), st.integers(0, 99),
                 st.sampled_from(list(ALPHABET)))
cut = st.tuples(st.just("cut"), st.integers(0, 10), st.integers(0, 90))
drop = st.tuples(st.just("drop"), st.integers(0, 10))
dup = st.tuples(st.just("dup"), st.integers(0, 10), st.integers(0, 11))
swap = st.tuples(st.just("swap"), st.integers(0, 10), st.integers(0, 10))
garbage = st.tuples(st.just("insert"), st.integers(0, 11),
                    st.one_of(st.binary(max_size=100),
                              st.text(alphabet=st.sampled_from("0123456789 .+-E"),
                                      max_size=40).map(str.encode)))
number = st.tuples(st.just("number"), st.integers(0, 10), st.integers(0, 3),
                   st.sampled_from([b"     0.0", b"    -4.0", b"  1.E+98", b"  1.E-99",
                                    b"   1E+50", b"  -1.E-5", b"  360.00", b" 9.9E+98"]))
mutation = st.one_of(flip, cut, drop, dup, swap, garbage, number)


def mutate(deck: list[bytes], mutations) -> bytes:
    cards = list(deck)
    for op, *args in mutations:
        n = len(cards)
        if op == "insert":
            cards.insert(args[0] % (n + 1), args[1].replace(b"\n", b" "))
            continue
        if not cards:
            continue
        i = args[0] % n
        if op == "flip":
            card = bytearray(cards[i].ljust(args[1] + 1))
            card[args[1]] = args[2]
            cards[i] = bytes(card)
        elif op == "cut":
            cards[i] = cards[i][:args[1]]
        elif op == "drop":
            del cards[i]
        elif op == "dup":
            cards.insert(args[1] % (n + 1), cards[i])
        elif op == "swap":
            j = args[1] % n
            cards[i], cards[j] = cards[j], cards[i]
        elif op == "number":
            card = bytearray(cards[i].ljust(32))
            card[8 * args[1]:8 * args[1] + 8] = args[2]
            cards[i] = bytes(card)
    return b"\n".join(cards) + b"\n"


def check_run(data: bytes, *extra: str) -> None:
    with tempfile.TemporaryDirectory() as directory:
        path = os.path.join(directory, "deck.dat")
        with open(path, "wb") as f:
            f.write(data)
        out, err = io.StringIO(), io.StringIO()
        start = time.perf_counter()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = main(["run", path, "--max-sheets", str(MAX_SHEETS), *extra])
        elapsed = time.perf_counter() - start
    listing, lines = out.getvalue(), err.getvalue().splitlines()
    errors = [line for line in lines if not line.startswith(DIAGNOSTIC)]
    assert elapsed < SECONDS_PER_RUN, (elapsed, data)
    assert "Traceback" not in err.getvalue()
    assert status in (0, 2, 3), (status, err.getvalue())
    if currently_in_test_context():
        event(f"exit {status}")  # --hypothesis-show-statistics shows the mix
    if status == 0:
        assert errors == [], err.getvalue()
        records = listing.splitlines()
        assert records and records[-1] == "1"
        assert all(r[:1] in (" ", "0", "1") for r in records)
        assert listing.count("THETA 2") == records.count("1") <= MAX_SHEETS
    else:
        assert len(errors) == 1, err.getvalue()
        assert errors[0].startswith(f"{path}: "), errors[0]
        if status == 3:
            assert "THIS IS NOT A CRANK ROCKER MECHANISM" in errors[0]
            assert listing == " THIS IS NOT A CRANK ROCKER MECHANISM\n"


@pytest.mark.slow
@settings(PROFILE)
@given(st.sampled_from([EXAMPLE, FINE]), st.lists(mutation, min_size=1, max_size=5))
def test_mutated_decks_list_or_fail_in_one_line(deck, mutations):
    check_run(mutate(deck, mutations))


@pytest.mark.slow
@settings(PROFILE, max_examples=max(PROFILE.max_examples // 5, 20))
@given(st.lists(mutation, min_size=1, max_size=4))
def test_mutated_decks_kinematics_only_and_rendered(mutations):
    data = mutate(EXAMPLE, mutations)
    check_run(data, "--kinematics-only")
    with tempfile.TemporaryDirectory() as directory:
        path = os.path.join(directory, "deck.dat")
        with open(path, "wb") as f:
            f.write(data)
        err = io.StringIO()
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            status = main(["run", path, "--render", "--max-sheets", "3"])
        assert status in (0, 2, 3)
        assert len([x for x in err.getvalue().splitlines()
                    if not x.startswith(DIAGNOSTIC)]) == (status != 0)


def test_unmutated_decks_list():
    check_run(mutate(EXAMPLE, []))
    check_run(mutate(FINE, []))


# ----- decks drawn whole: lengths across 1E-90..1E90, ranges, arithmetic models, -o paths ----
def _field(mantissa: int, exponent: int) -> bytes:
    """An F8.4 field holding mantissa/10 x 10**exponent, right-justified."""
    text = f"{mantissa // 10}.{mantissa % 10}E{exponent:+03d}"
    return text.rjust(8).encode()


length = st.builds(_field, st.integers(10, 99), st.integers(-90, 90))
plain = st.sampled_from([b"    12.0", b"     4.0", b"    16.0", b"     0.0", b"    -4.0",
                         b"   360.0", b"     0.5", b"  1.E-90", b"  1.E+90", b" -1.E-90"])
angle = st.sampled_from([b"     0.0", b"    10.0", b"   360.0", b"   -30.0", b"   720.0",
                         b"  1.E-90", b"  1.E+50", b"     0.5", b"    -1.0", b"  1.E-10"])
OUTPUTS = ("stdout", "new", "existing", "input", "folder", "nested")


usual = st.sampled_from([[b"    10.0", b"    10.0", b"   360.0"], [b"     0.0", b"    30.0",
                         b"   360.0"], [b"    45.0", b"     1.0", b"    50.0"]])


@st.composite
def drawn_decks(draw):
    if draw(st.booleans()):  # the example's linkage at any scale: a crank-rocker
        k = draw(st.integers(-85, 85))
        lengths = [_field(12, k + 1), _field(40, k), _field(16, k + 1), _field(12, k + 1)]
        centres = [_field(20, k), _field(80, k), _field(60, k)]
    else:  # anything: most are refused, naming the card
        lengths = draw(st.lists(st.one_of(length, plain), min_size=4, max_size=4))
        centres = draw(st.lists(st.one_of(length, plain), min_size=3, max_size=3))
    ranges = draw(st.lists(st.one_of(usual, usual, st.lists(angle, min_size=3, max_size=3)),
                           min_size=1, max_size=3))
    cards = [b"     3.0     8.0     6.0", b"     0.0     0.5     0.4", b"".join(lengths),
             b"     0.0   -15.0    15.0", b"".join(centres), draw(st.one_of(plain, length))]
    cards += [b"".join(r) for r in ranges]
    return b"\n".join(cards) + b"\n"


@pytest.mark.slow
@settings(PROFILE, max_examples=max(PROFILE.max_examples // 2, 50))
@given(drawn_decks(), st.sampled_from(["run", "check", "table"]),
       st.sampled_from(["float64", "float32", "ibm1410"]), st.sampled_from(OUTPUTS))
def test_drawn_decks_every_command_every_output(data, command, arith, output):
    """Whatever the deck, model and -o: exit 0, 2 or 3 with at most one error line, no
    traceback, the input unchanged, an existing output unchanged unless the run succeeded,
    and no temporary file left behind."""
    with tempfile.TemporaryDirectory() as directory:
        path = os.path.join(directory, "deck.dat")
        with open(path, "wb") as f:
            f.write(data)
        target = {"stdout": None, "new": os.path.join(directory, "new.out"),
                  "existing": os.path.join(directory, "old.out"), "input": path,
                  "folder": directory,
                  "nested": os.path.join(directory, "a", "b", "c.out")}[output]
        if output == "existing":
            with open(target, "w") as f:
                f.write("precious\n")
        argv = [command, path]
        if command == "run":
            argv += ["--arith", arith, "--max-sheets", "5"]
        if command == "table":
            argv += ["--only", "kinematics"]
        if target is not None and command != "check":
            argv += ["-o", target]
        out, err = io.StringIO(), io.StringIO()
        start = time.perf_counter()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = main(argv)
        elapsed = time.perf_counter() - start
        left = sorted(os.listdir(directory))
        with open(path, "rb") as f:
            assert f.read() == data  # the input is never touched
        if output == "existing":
            with open(target) as f:
                kept = f.read() == "precious\n"
            assert kept or (status == 0 and command != "check"), (status, err.getvalue())
    assert "Traceback" not in err.getvalue()
    assert status in (0, 2, 3), (status, err.getvalue())
    errors = [x for x in err.getvalue().splitlines() if not x.startswith(DIAGNOSTIC)]
    assert len(errors) == (status != 0), err.getvalue()
    assert not [n for n in left if n.endswith(".tmp") or ".tmp." in n], left
    assert elapsed < 60, (elapsed, data)
    if currently_in_test_context():
        event(f"{command} exit {status}")
