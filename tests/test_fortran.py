"""The program deck interpreted (emulator.fortran): byte for byte the port's listing on every
arithmetic, the report's three edits, and errors as one line naming a card."""

from __future__ import annotations

import contextlib
import importlib.util
import io
import math
import re
import subprocess
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


@pytest.mark.slow
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


@pytest.mark.slow
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
        assert status in (2, 3) and len(errors) == 1, err  # 3: the 1966 message
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


# -- the same fuzz, in a subprocess under a memory limit and a timeout ------------------------
#
# Mutants here also take hostile cards (the attacks of issue 21: loops, huge powers, huge
# FORMAT counts, logical values, form feeds and tabs), so the interpreter's budget is
# drawn, not only its parser; each runs as `sielaff run --program` in a process whose
# address space is capped, with a timeout.  CI runs FUZZ_CI examples; SIELAFF_NIGHTLY=1
# runs the nightly test's FUZZ_NIGHTLY more (docs/robustness.md).

FUZZ_CI, FUZZ_NIGHTLY = 40, 1_000
FUZZ_MEMORY = 600 * 2**20  # bytes of address space (a run of the deck needs about 300 MB)
FUZZ_SECONDS = 120  # per mutant, wall: the budget's worst case on this deck is ~40 s CPU
HOSTILE = [  # blocks of cards, inserted together (labels 99xx: unused by the deck)
    ["      J9=2", " 9901 J9=J9*J9", "      GOTO 9901"],            # an integer that grows
    [" 9902 GOTO 9902"],                                           # a loop, nothing printed
    ["      X9=1.0", "      Y9=X9**999999"], ["      J9=2", "      J9=J9**99999"],
    [" 9903 WRITE(3,9904)", " 9904 FORMAT(5H LOOP)", "      GOTO 9903"],  # endless output
    [" 9905 WRITE(3,9906)", " 9906 FORMAT(1H1)", "      GOTO 9905"],      # endless sheets
    ["      WRITE(3,9907)", " 9907 FORMAT(999999999X)"], [" 9908 FORMAT(99999999999F8.4)"],
    ["      B9=1.0", "      A9=B9.GT.B9"], ["      X9=1.0", "      GOTO(9909,9909),X9",
                                             " 9909 CONTINUE"],
    ["      X9=1.0E99"], ["      X9=0.0", "      Y9=1.0/X9"],
    ["      Y9=1.0E90*1.0E90", "      WRITE(3,9910)Y9", " 9910 FORMAT(1X,E12.4)"],
    ["      I9=123456789012345678901"], ["      A=R3/R2\f"], ["      A=R3/R2\t"],
    ["      SUBROUTINE VECTOR(A)"], ["      SUBROUTINE MAIN"], ["      END"],
]
#: What each HOSTILE block, alone in MAIN after ``A=R3/R2``, must end with (exit 2).
HOSTILE_ENDS = [
    "integer overflow", "1,000,000 statements without a line printed",
    "multiplications, past the interpreter's budget", "integer overflow",
    "1,000 lines printed with no page eject", "380 sheets printed",
    "999999999 in FORMAT", "99999999999 in FORMAT", "a relation is not a value",
    "computed GO TO needs an integer variable", "constant 1.0E99 is past",
    "division by zero", "cannot be printed", "integer constant 123456789012345678901",
    "control character '\\x0c'", "tab character", "not in the subset",
    "not in the subset", "a statement after the END on card",
]


@pytest.mark.parametrize("block", range(len(HOSTILE)))
def test_each_hostile_block_meets_its_limit(tmp_path, block):
    """Every attack the fuzz draws from, alone: the limit it must meet, in a capped process."""
    cards = list(CARDS)
    at = cards.index("      A=R3/R2") + 1
    cards[at:at] = HOSTILE[block]
    src = tmp_path / "mutant.f"
    src.write_text("\n".join(cards) + "\n")
    proc = _limited_run(src, "float64")
    errors = [x for x in proc.stderr.splitlines() if not x.startswith("sielaff: 1966 quirk")]
    assert proc.returncode == 2 and len(errors) == 1, proc.stderr
    assert HOSTILE_ENDS[block] in errors[0] and "Traceback" not in proc.stderr, errors[0]
    assert not src.with_suffix(".asa").exists()


_hostile = st.tuples(st.integers(0, len(CARDS) - 1), st.just(0),
                     st.sampled_from(range(len(HOSTILE))), st.just("insert"))
_mutation = st.one_of(
    st.tuples(st.integers(0, len(CARDS) - 1), st.integers(0, 71),
              st.sampled_from(list(ALPHABET + "\f\t")), st.sampled_from(["flip", "drop",
                                                                         "dup"])),
    _hostile)
_mutants = st.tuples(st.lists(_mutation, min_size=1, max_size=4),
                     st.sampled_from(["float64", "float32", "ibm1410"]))


def _limited_run(src: Path, arith: str) -> subprocess.CompletedProcess:
    import procs

    return procs.run(["run", "--program", src, ROOT / "decks" / "example.dat", "--arith", arith,
                      "-o", src.with_suffix(".asa")], text=True, timeout=FUZZ_SECONDS,
                     rlimit_as=FUZZ_MEMORY,
                     env=dict(__import__("os").environ, PYTHONPATH=str(ROOT / "src")))


def _fuzz_one(tmp_path_factory, mutations, arith) -> None:
    from hypothesis import event

    cards = list(CARDS)
    for n, col, char, how in mutations:
        n = min(n, len(cards) - 1)
        if how == "insert":
            cards[n:n] = HOSTILE[char]
        elif how == "flip":
            line = cards[n].ljust(72)
            cards[n] = line[:col] + char + line[col + 1:]
        elif how == "drop" and len(cards) > 1:
            del cards[n]
        else:
            cards.insert(n, cards[n])
    src = tmp_path_factory.mktemp("m") / "mutant.f"
    src.write_text("\n".join(cards) + "\n")
    proc = _limited_run(src, arith)
    err = proc.stderr
    assert "Traceback" not in err and "MemoryError" not in err, err
    errors = [x for x in err.splitlines() if not x.startswith(("sielaff: 1966 quirk",
                                                               "sielaff: warning: stopped"))]
    event(f"exit {proc.returncode}")
    if proc.returncode == 0:
        assert errors == [] and src.with_suffix(".asa").exists()
        return
    assert proc.returncode in (2, 3) and len(errors) == 1, err
    assert not src.with_suffix(".asa").exists()  # whole or not at all
    assert re.search(r"card \d+|mutant\.f", errors[0]), errors[0]
    # the kind of failure, for the statistics: the words after the place
    kind = re.sub(r"^(statement \d+ at |the statement at )?card \d+(, columns? [\d-]+)?: ",
                  "", errors[0].split("mutant.f: ", 1)[-1])
    event(" ".join(re.sub(r"[\d,.'\"]+", "#", kind).split()[:5]))


@pytest.mark.slow
@settings(max_examples=FUZZ_CI, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(_mutants)
def test_mutated_programs_under_memory_and_time_limits(tmp_path_factory, mutant):
    """A mutated or attacked program deck, run in a capped process: a listing, or one line
    naming the card (exit 2, or 3 for the 1966 message), within the time limit."""
    _fuzz_one(tmp_path_factory, *mutant)


@pytest.mark.nightly
@pytest.mark.skipif(__import__("os").environ.get("SIELAFF_NIGHTLY") != "1",
                    reason="nightly fuzz budget: SIELAFF_NIGHTLY=1")
@settings(max_examples=FUZZ_NIGHTLY, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(_mutants)
def test_mutated_programs_under_memory_and_time_limits_nightly(tmp_path_factory, mutant):
    """The same, at the nightly budget and not derandomized (new mutants every night)."""
    _fuzz_one(tmp_path_factory, *mutant)
