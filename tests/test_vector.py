"""The vectorised float64 listing (emulator.vector) against the port, byte for byte: the
same listing, the same notices on stderr, the same error, on hypothesis-drawn decks and on
the 36,001-sheet deck of benchmarks/listing.py."""

from __future__ import annotations

import io
import math
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sielaff.emulator import vector
from sielaff.emulator.cards import parse_deck
from sielaff.emulator.program import SheetLimit
from sielaff.emulator.run import ProgramError, notice_printer, run


@pytest.fixture(autouse=True)
def every_deck_vectorised(monkeypatch):
    """Decks of short range cards go to the port in ``sielaff run`` (MIN_SHEETS_PER_CARD);
    here the vectorised path takes them all, so that it is the one tested."""
    monkeypatch.setattr(vector, "MIN_SHEETS_PER_CARD", 0)


PARAMETERS = ["     3.0     8.0     6.0", "     0.0     0.5     0.4",
              "    12.0     4.0    16.0    12.0", "     0.0   -15.0    15.0",
              "     2.0     8.0     6.0", "    50.0"]


def both(text: str, **options) -> tuple:
    """(listing, stderr, error) of the port and of the vectorised path, the latter once
    writing text and once writing its blocks as bytes (``run(binary=...)``, the command's
    way); the two vectorised results must be the same."""
    deck = parse_deck(text)
    results = []
    for vectorised, as_bytes in ((False, False), (True, False), (True, True)):
        out, err = io.TextIOWrapper(io.BytesIO(), encoding="ascii", newline="\n"), io.StringIO()
        error = None
        try:
            run(deck, out, notice=notice_printer(err), vectorised=vectorised,
                binary=out.buffer if as_bytes else None, **options)
        except (ProgramError, SheetLimit) as exc:
            error = (type(exc).__name__, str(exc))
        out.flush()
        results.append((out.buffer.getvalue().decode("ascii"), err.getvalue(), error))
    assert results[1] == results[2]
    return results[0], results[1]


def test_numpy_matches_libm_here():
    """What the byte identity depends on: numpy's sin, cos and sqrt are libm's on this
    machine (the run checks it too, and prints with the port alone where they are not)."""
    assert vector.numpy_matches_libm()
    x = np.random.default_rng(7).uniform(-7.0, 7.0, 5000)
    assert np.sin(x).tolist() == [math.sin(v) for v in x.tolist()]


@pytest.mark.slow
def test_the_36001_sheet_deck_byte_for_byte():
    port, fast = both("\n".join(PARAMETERS + ["    0.01    0.01   360.0"]) + "\n")
    assert port == fast
    assert port[0].count("\n1\n") + port[0].startswith("1\n") >= 36000


@pytest.mark.parametrize("extra", [{}, {"kinematics_only": True}, {"tex": 150.0},
                                   {"max_sheets": 1000}, {"tex": -1.5e-3,
                                                          "kinematics_only": True}])
def test_options_byte_for_byte(extra):
    text = "\n".join(PARAMETERS + ["   -30.0     1.7   400.0", "    10.0    10.0   360.0",
                                   "   720.0    -5.0   700.0"]) + "\n"
    assert [tuple(r) for r in parse_deck(text).ranges] == [(-30.0, 1.7, 400.0),
                                                           (10.0, 10.0, 360.0),
                                                           (720.0, -5.0, 700.0)]
    port, fast = both(text, **extra)
    assert port == fast


def test_the_port_still_prints_what_it_must():
    """Sheets with notices (Case I below 0, Case II past 360, the trailing sheet) come from
    the port, in order, with the notice limits of one run."""
    text = "\n".join(PARAMETERS + ["   -20.0     1.0   380.0"]) + "\n"
    assert parse_deck(text).ranges[0] == (-20.0, 1.0, 380.0)
    port, fast = both(text)
    assert port == fast and "Case I" in fast[1] and "suppressed" in fast[1]


def test_an_error_is_the_ports():
    """A deck whose forces pass the 1410's range: the same ProgramError, the listing up to
    the sheet before, not a byte more."""
    cards = list(PARAMETERS)
    cards[5] = "  1.E+50"  # TH2D: accelerations past 1E99
    port, fast = both("\n".join(cards + ["     0.0    10.0   360.0"]) + "\n")
    assert port == fast and port[2] is not None and port[2][0] == "ProgramError"


def _field(x: float) -> str:
    text = f"{x:.4f}"
    return text.rjust(8) if len(text) <= 8 else f"{x:.3g}".rjust(8)


@st.composite
def decks(draw):
    r2 = draw(st.floats(0.5, 6.0))
    r3 = draw(st.floats(r2 * 1.2, 30.0))
    r4 = draw(st.floats(r2 * 1.2, 30.0))
    # a crank-rocker (most of the time): |R4 - R3| + R2 < R1 < R3 + R4 - R2, near the
    # toggles now and then
    lo, hi = abs(r4 - r3) + r2, r3 + r4 - r2
    r1 = lo + (hi - lo) * draw(st.one_of(st.floats(0.0, 1.0), st.sampled_from([1e-4, 0.9999])))
    w = [draw(st.floats(0.0, 50.0)) for _ in range(3)]
    zi = [draw(st.floats(0.0, 5.0)) for _ in range(3)]
    adel = [draw(st.floats(-180.0, 180.0)) for _ in range(3)]
    rg = [draw(st.floats(0.0, 30.0)) for _ in range(3)]
    th2d = draw(st.floats(-500.0, 500.0))
    ranges = []
    for _ in range(draw(st.integers(1, 3))):
        start = draw(st.floats(-400.0, 800.0))
        step = draw(st.floats(0.05, 40.0))
        stop = start + draw(st.floats(-10.0, 300.0))
        ranges.append("".join(_field(v) for v in (start, step, stop)))
    cards = ["".join(_field(v) for v in w), "".join(_field(v) for v in zi),
             "".join(_field(v) for v in (r1, r2, r3, r4)), "".join(_field(v) for v in adel),
             "".join(_field(v) for v in rg), _field(th2d)] + ranges
    return "\n".join(cards) + "\n"


@pytest.mark.slow
@settings(max_examples=200, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(decks(), st.booleans(), st.sampled_from([0.0, 0.0, 37.5, -2e3]))
def test_drawn_decks_byte_for_byte(text, kinematics_only, tex):
    deck = parse_deck(text)
    if not vector.applies(deck):  # not a crank-rocker: the port prints the refusal
        return
    port, fast = both(text, kinematics_only=kinematics_only, tex=tex)
    assert port == fast


def test_without_numpy_agreeing_the_port_prints(monkeypatch):
    monkeypatch.setattr(vector, "_LIBM_CHECKED", False)
    deck = parse_deck("\n".join(PARAMETERS + ["    10.0    10.0    30.0"]) + "\n")
    assert not vector.applies(deck)
    called = []
    monkeypatch.setattr(vector, "vector_run", lambda *a, **k: called.append(1))
    run(deck, io.StringIO())
    assert not called


def test_short_range_cards_go_to_the_port(monkeypatch):
    """A block costs about a millisecond whatever its size: a deck of one-sheet range
    cards is the port's (MIN_SHEETS_PER_CARD), a deck of long ones the vectorised path's."""
    monkeypatch.setattr(vector, "MIN_SHEETS_PER_CARD", 32)
    short = parse_deck("\n".join(PARAMETERS + ["    10.0    10.0     5.0"] * 50) + "\n")
    long = parse_deck("\n".join(PARAMETERS + ["    10.0     1.0   360.0"]) + "\n")
    assert not vector.applies(short) and vector.applies(long)


def _bulk_against_printer(kind: str, x: np.ndarray) -> tuple[int, int]:
    """(fields the bulk editor prints, how many of them differ from the printer's own
    editor, the reference ``edit_e``/``edit_f``)."""
    from sielaff.emulator.printer import edit_e, edit_f

    edit = edit_e if kind == "E" else edit_f
    with np.errstate(all="ignore"):
        words, ok = (vector._edit_e if kind == "E" else vector._edit_f)(x)
    text = words.view(np.uint8).reshape(x.size, 12)
    wrong = sum(text[i].tobytes().decode("ascii") != edit(float(x[i]), 12, 4 if kind == "E"
                                                             else 1)
                for i in np.flatnonzero(ok))
    return int(ok.sum()), wrong


def test_bulk_f12_1_is_the_printers_past_1000():
    """F12.1 in bulk on values past 1000 up to the first tier's limit (10**7), both signs:
    random ones and ones next to the field's limits (each added digit, the 10-character
    -9999999.9).  The bulk editor once printed 1234.56 as 0234.5 and called it good."""
    rng = np.random.default_rng(25)
    x = 10.0 ** rng.uniform(3.0, 7.0, 40_000)
    edges = np.array([10.0 ** k + d for k in range(3, 8) for d in (-0.15, -0.05, 0.05, 0.15)])
    x = np.concatenate([x, edges, [1234.56]])
    x = np.concatenate([x, -x])
    printed, wrong = _bulk_against_printer("F", x)
    assert wrong == 0
    assert printed >= 0.99 * x.size - 8  # all but values near a digit boundary and >= 10**7
    with np.errstate(all="ignore"):
        words, ok = vector._edit_f(np.array([1234.56, -9999999.95, 1e7 + 0.5]))
    assert words[:2].view(np.uint8).tobytes() == b"      1234.5  -9999999.9"
    assert ok.tolist() == [True, True, False]  # 10**7 and past: the printer's own editor


@pytest.mark.parametrize("kind", ["E", "F"])
def test_bulk_editors_are_the_printers(kind):
    """Both bulk editors against the printer's reference on values of every size the
    listing meets, both signs, zeros included."""
    rng = np.random.default_rng(1966)
    x = np.concatenate([10.0 ** rng.uniform(-3.0, 8.0, 20_000), rng.uniform(0.0, 2.0, 5_000),
                        [0.0, 999.95, 1000.05]])
    x = np.concatenate([x, -x])
    printed, wrong = _bulk_against_printer(kind, x)
    assert wrong == 0 and printed >= 0.9 * x.size


def test_the_command_writes_the_blocks_as_bytes(tmp_path, monkeypatch):
    """``sielaff run`` hands the blocks of sheets to the file's byte layer (the port's
    sheets, with notices, in between as text): the same file as ``--port``, on stdout too."""
    import subprocess
    import sys
    from pathlib import Path

    from sielaff.cli import main

    deck = tmp_path / "deck.dat"
    deck.write_text("\n".join(PARAMETERS + ["   -20.0     1.0   380.0"]) + "\n")
    used = []
    real = vector.vector_run

    def spy(*args, **kwargs):
        used.append(args[-1] if len(args) > 9 else kwargs.get("emit_bytes"))
        return real(*args, **kwargs)

    monkeypatch.setattr(vector, "vector_run", spy)
    assert main(["run", str(deck), "-o", str(tmp_path / "fast.lst")]) == 0
    assert main(["run", str(deck), "--port", "-o", str(tmp_path / "port.lst")]) == 0
    assert len(used) == 1 and used[0] is not None
    fast, port = ((tmp_path / n).read_bytes() for n in ("fast.lst", "port.lst"))
    assert fast == port and fast.count(b"THETA 2") == 402
    root = Path(__file__).resolve().parents[1]
    out = [subprocess.run([sys.executable, "-m", "sielaff", "run", str(deck), *extra],
                          capture_output=True, check=True, timeout=300,
                          env={**os.environ, "PYTHONPATH": str(root / "src")}).stdout
           for extra in ([], ["--port"])]
    assert out[0] == out[1] == port
