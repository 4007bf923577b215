"""The program deck interpreted (emulator.fortran): byte for byte the port's listing on every
arithmetic, the report's three edits, and errors as one line naming a card."""

from __future__ import annotations

import contextlib
import importlib.util
import io
import math
import re
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sielaff.cli import main
from sielaff.emulator.cards import parse_deck, read_deck
from sielaff.emulator.fortran import FortranError, compile_source, run_program
from sielaff.emulator.fortran import source as fsource
from sielaff.emulator.run import run
from sielaff.engine import analyze
from test_vector import _field  # an F8.4 field for a drawn value

ROOT = Path(__file__).resolve().parent.parent
SOURCE = (ROOT / "decks" / "sielaff.f").read_text()
EDITS = ROOT / "decks" / "edits"
PARAMETERS = (ROOT / "decks" / "example.dat").read_text().splitlines()[:6]
MODELS = ("float64", "float32", "ibm1410", "ibm1410:10")


def listing(source: str, deck, arith: str) -> str:
    out = io.StringIO()
    run_program(source, deck, out, arith, "<deck>")
    return out.getvalue()


def port(deck, arith: str, **options) -> str:
    out = io.StringIO()
    run(deck, out, arithmetic=arith, vectorised=False, **options)
    return out.getvalue()


@pytest.mark.parametrize("arith", MODELS)
@pytest.mark.parametrize("card", ["    10.0    10.0   360.0", "   -20.0     7.0   400.0",
                                  "     0.0    90.0   360.0\n    45.0     5.0    60.0"])
def test_the_deck_is_the_port_byte_for_byte(arith, card):
    deck = parse_deck("\n".join(PARAMETERS + [card]) + "\n")
    assert listing(SOURCE, deck, arith) == port(deck, arith)


@st.composite
def decks(draw):
    r2 = draw(st.floats(0.5, 6.0))
    r3, r4 = draw(st.floats(r2 * 1.2, 30.0)), draw(st.floats(r2 * 1.2, 30.0))
    lo, hi = abs(r4 - r3) + r2, r3 + r4 - r2
    r1 = lo + (hi - lo) * draw(st.floats(0.0, 1.0))
    values = [[draw(st.floats(0.0, 50.0)) for _ in range(3)],
              [draw(st.floats(0.0, 5.0)) for _ in range(3)], [r1, r2, r3, r4],
              [draw(st.floats(-180.0, 180.0)) for _ in range(3)],
              [draw(st.floats(0.0, 30.0)) for _ in range(3)], [draw(st.floats(-500., 500.))]]
    start = draw(st.floats(-400.0, 800.0))
    values.append([start, draw(st.floats(5.0, 60.0)), start + draw(st.floats(-10.0, 200.0))])
    return "\n".join("".join(_field(v) for v in card) for card in values) + "\n"


@settings(max_examples=100, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(decks(), st.sampled_from(MODELS))
def test_drawn_decks_byte_for_byte(text, arith):
    deck = parse_deck(text)
    try:
        expected = port(deck, arith)
    except Exception as exc:  # the port refuses or fails: the interpreter must not print more
        with pytest.raises((FortranError, Exception)):
            got = listing(SOURCE, deck, arith)
            if "CRANK ROCKER" in got:
                raise RuntimeError("refused") from exc
            raise RuntimeError(got) from exc
        return
    assert listing(SOURCE, deck, arith) == expected


# -- the report's edits --------------------------------------------------------------

def _make_edits():
    spec = importlib.util.spec_from_file_location("make_edits", EDITS / "make_edits.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_edits_are_what_make_edits_makes():
    for name, text in _make_edits().decks().items():
        assert (EDITS / name).read_text() == text, name


@pytest.mark.parametrize("arith", ("float64", "float32", "ibm1410"))
def test_kinematics_edit_is_kinematics_only(arith):
    deck = read_deck(ROOT / "decks" / "example.dat")
    edit = (EDITS / "kinematics.f").read_text()
    assert listing(edit, deck, arith) == port(deck, arith, kinematics_only=True)


@pytest.mark.parametrize("arith", ("float64", "ibm1410"))
def test_tex_constant_edit_is_run_tex(arith):
    deck = read_deck(ROOT / "decks" / "example.dat")
    edit = (EDITS / "tex-constant.f").read_text()
    assert listing(edit, deck, arith) == port(deck, arith, tex=150.0)


def _printed(text: str, heading: str) -> list[float]:
    """The first value printed under ``heading`` on each sheet."""
    lines = text.splitlines()
    out = []
    for i, line in enumerate(lines):
        if heading in line:
            out.append(float(lines[i + 2].replace("E ", "E+").split()[0]))
    return out


@pytest.mark.parametrize("arith, rel", [("float64", 2e-3), ("ibm1410", 2e-3)])
def test_tex_edits_against_the_engine(arith, rel):
    """The engine with the same TEX (a constant, or 50 sin(TH4) as a function of ATH4 in
    degrees): TEX and TORQ agree to the printed digits (E12.4 truncated: 1E-3)."""
    deck = read_deck(ROOT / "decks" / "example.dat")
    th = np.arange(10.0, 361.0, 10.0)
    for name, tex in (("tex-constant.f", 150.0),
                      ("tex-theta4.f", lambda ath4: 50.0 * np.sin(np.radians(ath4)))):
        text = listing((EDITS / name).read_text(), deck, arith)
        r = analyze(deck.mechanism, th, ["TEX", "TORQ"], tex)
        got_tex, got_torq = _printed(text, "EX TORQ ON 4"), _printed(text, "DRIVING TORQ")
        assert len(got_torq) == 37
        for k in range(36):
            for got, want in ((got_tex[k], r["TEX"][k]), (got_torq[k], r["TORQ"][k])):
                assert got == pytest.approx(want, rel=rel, abs=1e-3 * abs(r["TORQ"]).max())


def test_the_cli_runs_the_deck(tmp_path):
    out = tmp_path / "listing.asa"
    assert main(["run", "--program", str(EDITS / "kinematics.f"), str(ROOT / "decks" /
                                                                       "example.dat"),
                 "-o", str(out)]) == 0
    assert "DRIVING TORQ" not in out.read_text() and "ACC G4" in out.read_text()


# -- errors: one line naming the card ------------------------------------------------------

def cli(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(list(argv))
    return status, out.getvalue(), err.getvalue()


@pytest.mark.parametrize("change, pattern", [
    (("      A=R3/R2", "      A=R3/R2\n      DIMENSION X(10)"),
     r"card \d+, column 7: not in the subset .*'DIMENSION'"),
    (("      GOTO52\n00045", "      GOTO 99\n00045"),
     r"card \d+.*GO TO 99: there is no statement 99"),
    (("00074 TEX=0.0", "00074 TEX=EXP(1.0)"), r"card 86, column 11: EXP\(\.\.\.\) is neither"),
    (("      A=R3/R2", "      A=R3/(R2-R2)"), r"at card \d+: division by zero"),
    (("00074 TEX=0.0", "00074 TEX=0.0+"), r"card 86, column \d+: expression ends early"),
])
def test_errors_name_the_card(tmp_path, change, pattern):
    src = tmp_path / "edit.f"
    old, new = change
    assert old in SOURCE
    src.write_text(SOURCE.replace(old, new, 1))
    status, out, err = cli("run", "--program", str(src), str(ROOT / "decks" / "example.dat"))
    assert status == 2 and len(err.splitlines()) == 1 and "Traceback" not in err
    assert re.search(pattern, err), err


def test_a_loop_that_never_ends_is_an_error(tmp_path, monkeypatch):
    monkeypatch.setattr(fsource, "STATEMENT_BUDGET", 20_000)
    import sielaff.emulator.fortran.machine as machine

    monkeypatch.setattr(machine, "STATEMENT_BUDGET", 20_000)
    src = tmp_path / "loop.f"
    src.write_text(SOURCE.replace("00054 I=I+1", "00054 I=I+1\n00055 GOTO55", 1))
    status, _, err = cli("run", "--program", str(src), str(ROOT / "decks" / "example.dat"))
    assert status == 2 and "statement 55 at card" in err and "never ends" in err


ALPHABET = "ABCXYZ0123456789+-*/()=.,  "
CARDS = SOURCE.splitlines()


@settings(max_examples=120, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.integers(0, len(CARDS) - 1), st.integers(0, 71),
                          st.sampled_from(list(ALPHABET)), st.sampled_from(["flip", "drop",
                                                                            "dup"])),
                min_size=1, max_size=3))
def test_mutated_program_decks_list_or_fail_in_one_line(tmp_path_factory, mutations):
    """A mutated program deck: a listing, or exactly one error line naming the card (or
    the data deck), never a traceback, never a hang."""
    import sielaff.emulator.fortran.machine as machine

    cards = list(CARDS)
    for n, col, char, how in mutations:
        n = min(n, len(cards) - 1)
        if how == "flip":
            line = cards[n].ljust(72)
            cards[n] = line[:col] + char + line[col + 1:]
        elif how == "drop" and len(cards) > 1:
            del cards[n]
        else:
            cards.insert(n, cards[n])
    src = tmp_path_factory.mktemp("m") / "mutant.f"
    src.write_text("\n".join(cards) + "\n")
    saved = machine.STATEMENT_BUDGET
    machine.STATEMENT_BUDGET = 50_000
    try:
        start = time.perf_counter()
        status, out, err = cli("run", "--program", str(src), str(ROOT / "decks" /
                                                                  "example.dat"))
    finally:
        machine.STATEMENT_BUDGET = saved
    assert time.perf_counter() - start < 30
    assert "Traceback" not in err
    errors = [x for x in err.splitlines() if not x.startswith("sielaff: 1966 quirk")]
    if status == 0:
        assert errors == []
    else:
        assert status == 2 and len(errors) == 1, err
        assert re.search(r"card \d+|mutant\.f", errors[0]), errors[0]


def test_integers_are_fortran_integers():
    """Integer division truncates toward zero, MOD follows it, a real assigned to an integer
    is truncated, an integer in a real expression is converted (mixed mode)."""
    text = ("      I=-7/2\n      J=MOD(-7,2)\n      K=3.99\n      X=I+0.5\n"
            "      IF(I.EQ.-3.AND.J.EQ.-1.AND.K.EQ.3)GOTO10\n      STOP\n"
            "   10 WRITE(3,1)X\n    1 FORMAT(1X,F6.1)\n      STOP\n      END\n")
    deck = read_deck(ROOT / "decks" / "example.dat")
    assert listing(text, deck, "float64") == "   -2.5\n"
    assert math.isclose(-2.5, float(listing(text, deck, "ibm1410").split()[0]))


def test_compile_errors_name_card_and_column():
    with pytest.raises(FortranError, match=r"<x>: card 2, column 7: not in the subset"):
        compile_source("      X=1.0\n      DO 10 I=1,5\n   10 CONTINUE\n      END\n",
                       sys.modules["sielaff.emulator.arithmetic"].get_arithmetic("float64"),
                       "<x>")


def test_arguments_are_passed_by_reference():
    """A FUNCTION or SUBROUTINE that changes its argument changes the caller's variable
    (copy in, copy out); an expression argument is a value."""
    text = ("      X=1.0\n      Y=F(X)\n      CALL S(X,Z)\n      W=F(X+1.0)\n"
            "      WRITE(3,1)X,Y,Z,W\n    1 FORMAT(1X,4F6.1)\n      STOP\n      END\n"
            "      FUNCTION F(A)\n      A=A+1.0\n      F=10.0*A\n      RETURN\n      END\n"
            "      SUBROUTINE S(B,C)\n      B=B*2.0\n      C=B+0.5\n      RETURN\n      END\n")
    deck = read_deck(ROOT / "decks" / "example.dat")
    # X: 1 -> 2 (F) -> 4 (S); Y = 20; Z = 4.5; W = F(5) = 60, X unchanged by it
    assert listing(text, deck, "float64") == "    4.0  20.0   4.5  60.0\n"
