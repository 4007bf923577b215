"""Robust, round three: the interpreter (``run --program``) and the readers (issue 21, items
1-11, 22 and 23), one test per finding and its family.

Each reproduction runs ``sielaff`` as a subprocess under a memory limit (RLIMIT_AS) and a
timeout, so a runaway fails the test instead of the machine: it must end with the exit
status of its kind and exactly one error line, never a traceback or a Python warning.
The interpreter's budget is docs/interpreter.md's; docs/robustness.md lists each limit and
the test that draws it.
"""

from __future__ import annotations

import io
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import DECKS, GOLDEN
from procs import run

ROOT = Path(__file__).resolve().parents[1]
SOURCE = (DECKS / "sielaff.f").read_text()
EXAMPLE = str(DECKS / "example.dat")
SIELAFF = [sys.executable, "-m", "sielaff"]
MEMORY = 600 * 2**20  # address space: numpy and the interpreter need about 300 MB
MODELS = ("float64", "float32", "ibm1410")


def _limit() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def limited(*args: str, stdin=None, timeout: float = 120, shell: str | None = None
            ) -> tuple[int, str, str, float]:
    """(status, stdout, stderr, CPU seconds of the children) of ``sielaff args`` (or of the
    ``shell`` pipeline) under the memory limit and a timeout.  ``sielaff args`` is forked
    from the worker's zygote (tests/procs.py): its CPU is the command's, without Python's
    start-up; a pipeline is a real ``bash -c``."""
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    if not shell:  # forked from the worker's zygote (tests/procs.py): the command's CPU
        proc = run(args, input=stdin, timeout=timeout, env=env, rlimit_as=MEMORY, text=True)
        return proc.returncode, proc.stdout, proc.stderr, proc.cpu
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    command = ["bash", "-c", shell] if shell else [*SIELAFF, *args]
    proc = subprocess.run(command, input=stdin, capture_output=True, text=True,
                          timeout=timeout, preexec_fn=_limit, env=env, check=False)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return proc.returncode, proc.stdout, proc.stderr, cpu


def one_line(err: str) -> str:
    """The one error line of stderr: no traceback, no Python warning, nothing else."""
    lines = [x for x in err.splitlines() if not x.startswith("sielaff: 1966 quirk: ")]
    assert len(lines) == 1 and "Traceback" not in err and "warning" not in err, err
    return lines[0]


def program(tmp_path: Path, text: str, name: str = "p.f") -> str:
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def cards(*statements: str) -> str:
    """A program deck: each statement on its card (a number in columns 1-5 if given as
    ``"10 X=1.0"``)."""
    out = []
    for s in statements:
        label, _, body = s.rpartition("|")
        out.append(f"{label:>5} {body}")
    return "\n".join(out) + "\n"


def fails(tmp_path: Path, text: str, *extra: str, status: int = 2) -> str:
    """Run a program that must fail; its one error line."""
    path = program(tmp_path, text)
    code, out, err, _ = limited("run", "--program", path, EXAMPLE, *extra)
    assert code == status, (code, err)
    return one_line(err)


# 1. statements, integers, ** ---------------------------------------------------------------
@pytest.mark.parametrize("arith", MODELS)
def test_01_squaring_an_integer_is_an_integer_overflow(tmp_path, arith):
    text = cards("|I=2", "10|I=I*I", "|GO TO 10", "|END")
    line = fails(tmp_path, text, "--arith", arith)
    assert line.endswith("statement 10 at card 2: integer overflow: a result of more than 20 "
                         "digits (the interpreter's integer size; docs/interpreter.md)")


@pytest.mark.parametrize("statement", ["Y=X**999999999", "J=I**99999999", "Y=X**(-99999999)"])
@pytest.mark.parametrize("arith", MODELS)
def test_01_a_huge_power_is_refused_at_once(tmp_path, statement, arith):
    text = cards("|X=1.0", "|I=1", f"|{statement}", "|STOP", "|END")
    start = time.monotonic()
    line = fails(tmp_path, text, "--arith", arith)
    assert "the statement at card 3: **" in line and "multiplications, past the " in line
    assert time.monotonic() - start < 60


@pytest.mark.parametrize("statement, card, what", [
    ("I=123456789012345678901", 1, "card 1, column 9: integer constant 123456789012345678901 "
                                   "has more than 20 digits"),
    ("I=2**70", 1, "statement at card 1: integer overflow"),
    ("I=IFIX(1.0E50)", 1, "statement at card 1: integer overflow"),
    ("K=1.0E50", 1, "statement at card 1: integer overflow"),
    ("I=99999999999999999999+1", 1, "statement at card 1: integer overflow"),
])
def test_01_every_way_to_a_big_integer_is_one_line(tmp_path, statement, card, what):
    line = fails(tmp_path, cards(f"|{statement}", "|STOP", "|END"))
    assert what in line


def test_01_twenty_digits_are_held(tmp_path):
    text = cards("|I=99999999999999999999", "|J=I-99999999999999999998", "|X=J",
                 "|WRITE(3,1)X", "1|FORMAT(1X,F6.1)", "|STOP", "|END")
    status, out, err, _ = limited("run", "--program", program(tmp_path, text), EXAMPLE)
    assert (status, out, err) == (0, "    1.0\n", "")


def test_01_statements_in_all_are_bounded_per_sheet(monkeypatch):
    """A loop that prints a line now and then never trips the guard of statements without
    a line: the run's total (per sheet the deck asks for) stops it."""
    from sielaff.emulator.cards import read_deck
    from sielaff.emulator.fortran import FortranError, machine, run_program

    monkeypatch.setattr(machine, "STATEMENTS_PER_SHEET", 1_000)
    text = cards("|X=1.0", "10|I=0", "20|I=I+1", "|IF(I.LT.500)GOTO20", "|WRITE(3,1)X",
                 "1|FORMAT(1X,F6.1)", "|GO TO 10", "|END")
    deck = read_deck(EXAMPLE)  # 37 sheets: 38,000 statements
    with pytest.raises(FortranError, match=r"statement 20 at card 3: 38,000 statements "
                       r"executed \(1,000 for each of the 37 sheets and one more\)"):
        run_program(text, deck, io.StringIO(), path="<p>")


# 2. FORMAT repeat counts and widths ------------------------------------------------------------
@pytest.mark.parametrize("fmt, what", [
    ("999999999F8.4", "999999999 in FORMAT '(999999999F8.4)' is past the 133 characters"),
    ("99999999999X", "99999999999 in FORMAT '(99999999999X)' is past the 133 characters"),
    ("999999999X,F8.4", "999999999 in FORMAT '(999999999X,F8.4)' is past"),
    ("1X,F8.999999999", "999999999 in FORMAT '(1X,F8.999999999)' is past"),
    ("1X,F8.9", "F8.9 in FORMAT '(1X,F8.9)': 9 decimals do not fit a field 8 wide"),
    ("100X,40X", "more than 133 characters wide at '40X'"),
    ("1X,17E8.1", "more than 133 characters wide at '17E8.1'"),
    ("F8.4/130X,4H1234", "more than 133 characters wide at '4H1234'"),
])
def test_02_a_format_past_a_printed_record_is_refused_on_its_card(tmp_path, fmt, what):
    text = cards("|X=1.0", "|WRITE(3,1)X", f"1|FORMAT({fmt})", "|STOP", "|END")
    line = fails(tmp_path, text)
    assert line.startswith(f"{tmp_path / 'p.f'}: card 3, column 7: ") and what in line


def test_02_a_record_of_133_characters_prints(tmp_path):
    text = cards("|X=1.0", "|WRITE(3,1)X", "1|FORMAT(1X,124X,F8.4)", "|STOP", "|END")
    status, out, _, _ = limited("run", "--program", program(tmp_path, text), EXAMPLE)
    assert status == 0 and out == " " * 125 + "  1.0000\n" and len(out) == 134


# 3. output: lines without a page eject, sheets past the deck's ---------------------------------
def test_03_an_endless_write_stops_at_a_sheets_worth_of_lines(tmp_path):
    text = cards("|X=1.0", "10|WRITE(3,1)X", "1|FORMAT(1X,F8.4)", "|GO TO 10", "|END")
    path = program(tmp_path, text)
    status, out, err, _ = limited("run", "--program", path, EXAMPLE)
    assert status == 2 and out.count("\n") == 1_000
    assert one_line(err).endswith("statement 10 at card 2: 1,000 lines printed with no page "
                                  "eject: a loop that never ends?")
    status, _, err, _ = limited("run", "--program", path, EXAMPLE, "-o",
                                str(tmp_path / "o.asa"))
    assert status == 2 and not (tmp_path / "o.asa").exists()


def test_03_a_page_eject_loop_stops_past_ten_times_the_decks_sheets(tmp_path):
    text = cards("10|WRITE(3,1)", "1|FORMAT(1H1)", "|GO TO 10", "|END")
    path = program(tmp_path, text)
    status, out, err, _ = limited("run", "--program", path, EXAMPLE)
    assert status == 2 and out == "1\n" * 380  # the example asks for 37 sheets
    assert "statement 10 at card 1: 380 sheets printed, the most for a deck whose range " \
           "cards ask for 37" in one_line(err)
    status, out, err, _ = limited("run", "--program", path, EXAMPLE, "--max-sheets", "5")
    assert status == 0 and out == "1\n" * 5 and "stopped after 5 sheets" in err


def test_03_one_write_of_many_records_stops_inside_it(tmp_path):
    """A FORMAT of page ejects: each record counts, the ones before the limit print."""
    text = cards("10|WRITE(3,1)", "1|FORMAT(1H1/1H1/1H1)", "|GO TO 10", "|END")
    status, out, err, _ = limited("run", "--program", program(tmp_path, text), EXAMPLE,
                                  "--max-sheets", "4")
    assert status == 0 and out == "1\n" * 4


def test_03_the_program_deck_prints_its_listing_within_the_budget(tmp_path):
    """The budget is far from the deck itself: 37 sheets of 59 lines, 640 statements each."""
    status, out, _, _ = limited("run", "--program", str(DECKS / "sielaff.f"), EXAMPLE)
    port = limited("run", EXAMPLE, "--port")
    assert status == 0 and out == port[1] and out.count("\n") == 37 * 59


# 4, 7. arithmetic errors: the same line on every model ------------------------------------------
@pytest.mark.parametrize("arith", MODELS)
def test_04_07_division_by_zero_is_one_line_on_every_model(tmp_path, arith):
    text = cards("|X=0.0", "|Y=1.0/X", "|WRITE(3,1)Y", "1|FORMAT(1X,F8.4)", "|STOP", "|END")
    assert fails(tmp_path, text, "--arith", arith).endswith(
        "p.f: the statement at card 2: division by zero")


@pytest.mark.parametrize("arith, what", [
    ("float64", "the statement at card 3: Y = 1.0000E+180 cannot be printed"),
    ("float32", "the statement at card 3: Y = INF cannot be printed"),
    ("ibm1410", "the statement at card 2: IBM 1410 floating-point overflow in multiplication"),
])
def test_04_07_overflow_is_one_line_on_every_model(tmp_path, arith, what):
    text = cards("|X=1.0E90", "|Y=X*X", "|WRITE(3,1)Y", "1|FORMAT(1X,E12.4)", "|STOP", "|END")
    assert what in fails(tmp_path, text, "--arith", arith)


@pytest.mark.parametrize("constant", ["1.0E99", "1.0E-101", "1E999999999", "-9.99E99"])
@pytest.mark.parametrize("arith", MODELS)
def test_04_a_constant_past_the_1410s_range_is_refused_on_its_card(tmp_path, constant, arith):
    line = fails(tmp_path, cards("|X=2.0", f"|X={constant}", "|STOP", "|END"), "--arith", arith)
    column = 9 + constant.startswith("-")  # the constant's first digit
    assert line.endswith(f"card 2, column {column}: constant {constant.lstrip('-')} is past "
                         "the IBM "
                         "1410's range (1E-100 <= |x| < 1E99, or 0)")


def test_07_float32_overflow_in_the_deck_is_one_line_and_no_warning(tmp_path):
    deck = tmp_path / "th.dat"
    lines = Path(EXAMPLE).read_text().splitlines()
    lines[5] = "  1.0+20"
    deck.write_text("\n".join(lines) + "\n")
    status, _, err, _ = limited("run", "--program", str(DECKS / "sielaff.f"), str(deck),
                                "--arith", "float32")
    assert status == 2 and "cannot be printed" in one_line(err)


# 5, 6. FORTRAN II typing --------------------------------------------------------------------------
def test_05_computed_go_to_needs_an_integer_variable(tmp_path):
    text = cards("|X=1.0", "|GO TO (10,20),X", "10|STOP", "20|STOP", "|END")
    assert fails(tmp_path, text).endswith("p.f: card 2, column 21: computed GO TO needs an "
                                          "integer variable (I-N), not X")


def test_05_computed_go_to_on_an_integer_runs(tmp_path):
    text = cards("|X=1.0", "|I=2", "|GO TO (10,20),I", "10|STOP", "20|WRITE(3,1)X",
                 "1|FORMAT(1X,F4.1)", "|STOP", "|END")
    status, out, _, _ = limited("run", "--program", program(tmp_path, text), EXAMPLE)
    assert (status, out) == (0, "  1.0\n")


RELATION = "a relation is not a value (FORTRAN II has no logical values"


@pytest.mark.parametrize("statement, column, what", [
    ("A=B.GT.C", 9, RELATION),
    ("I=B.GT.C", 9, RELATION),
    ("A=(B.GT.C)+1.0", 9, RELATION),
    ("A=1.0+(B.GT.C)", 13, RELATION),
    ("A=-(B.GT.C)", 10, RELATION),
    ("A=(B.GT.C)*2.0", 9, RELATION),
    ("A=(B.GT.C)**2", 9, RELATION),
    ("A=SQRT(B.GT.C)", 14, RELATION),
    ("IF(B.GT.C)1,1,1", 10, RELATION),
    ("IF((B.GT.C).GT.C)GOTO1", 18, ".GT. compares two values, not relations"),
    ("IF(B.AND.C.GT.B)GOTO1", 11, ".AND. needs a relation (.GT. .LT. ...) on each side"),
    ("IF(B.GT.C.OR.C)GOTO1", 20, ".OR. needs a relation (.GT. .LT. ...) on each side"),
    ("IF(.NOT.B)GOTO1", 15, ".NOT. needs a relation (.GT. .LT. ...) after it"),
])
def test_06_no_logical_values(tmp_path, statement, column, what):
    text = cards("|B=1.0", "|C=2.0", f"|{statement}", "1|STOP", "|END")
    line = fails(tmp_path, text)
    assert line.startswith(f"{tmp_path / 'p.f'}: card 3, column {column}: {what}"), line


def test_06_logical_if_still_runs(tmp_path):
    text = cards("|B=1.0", "|C=2.0", "|IF(.NOT.B.GT.C.AND.(C.GT.B.OR.B.GT.C))GOTO1", "|STOP",
                 "1|WRITE(3,2)C", "2|FORMAT(1X,F4.1)", "|STOP", "|END")
    status, out, _, _ = limited("run", "--program", program(tmp_path, text), EXAMPLE)
    assert (status, out) == (0, "  2.0\n")


# 8. source size -----------------------------------------------------------------------------------
def test_08_a_source_past_a_million_characters_is_refused_whole(tmp_path):
    from sielaff.emulator.fortran.source import SOURCE_LIMIT

    comment = "C" + " " * 78 + "\n"
    pad = SOURCE_LIMIT - len(SOURCE)
    exact = SOURCE + comment * (pad // 80) + "C" * (pad % 80)  # the last card, unended
    assert len(exact) == SOURCE_LIMIT
    status, out, err, _ = limited("run", "--program", program(tmp_path, exact, "at.f"),
                                  EXAMPLE)
    assert status == 0 and out.count("THETA 2") == 37
    over = program(tmp_path, exact + "C", "over.f")
    status, out, err, _ = limited("run", "--program", over, EXAMPLE)
    assert status == 2 and out == ""
    assert one_line(err) == (f"{over}: card {exact.count(chr(10)) + 1}: the program deck is "
                             "longer than 1,000,000 characters (the interpreter's limit)")


@pytest.mark.parametrize("expression, what", [
    ("(" * 3000 + "1.0" + ")" * 3000, "card 1, column 7: an expression nested too deeply"),
    ("+".join(["1.0"] * 20000), "card 1, column 7: cannot compile this statement"),
])
def test_08_a_statement_too_big_to_compile_is_named(tmp_path, expression, what):
    body = "X=" + expression
    lines = ["      " + body[:66]] + ["     1" + body[i:i + 66]
                                      for i in range(66, len(body), 66)]
    line = fails(tmp_path, "\n".join(lines) + "\n      STOP\n      END\n")
    assert line == f"{tmp_path / 'p.f'}: {what}" or line.startswith(
        f"{tmp_path / 'p.f'}: {what}")


# 9. form feed, tab and the other controls: refused on their card ----------------------------------
@pytest.mark.parametrize("char, what", [
    ("\f", "control character '\\x0c'"), ("\v", "control character '\\x0b'"),
    ("\x1c", "control character '\\x1c'"), ("\x7f", "control character '\\x7f'"),
    ("\t", "tab character (cards have no tabs; use blanks)"),
])
@pytest.mark.parametrize("where", ["end", "middle"])
def test_09_form_feed_and_tab_are_refused_alike(tmp_path, char, what, where):
    n = SOURCE.splitlines().index("      A=R3/R2") + 1
    card = "      A=R3/R2" + char if where == "end" else "      A=R3" + char + "/R2"
    text = SOURCE.replace("      A=R3/R2\n", card + "\n", 1)
    line = fails(tmp_path, text)
    assert line == f"{tmp_path / 'p.f'}: card {n}, column {len(card)if where == 'end' else 11}"\
                   f": {what}"


def test_09_crlf_cards_still_read(tmp_path):
    status, out, _, _ = limited("run", "--program",
                                program(tmp_path, SOURCE.replace("\n", "\r\n")), EXAMPLE)
    assert status == 0 and out.count("THETA 2") == 37


# 10. program units named twice --------------------------------------------------------------------
@pytest.mark.parametrize("extra, what", [
    ("      SUBROUTINE VECTOR(A,B,C,D)\n      RETURN\n      END\n",
     "SUBROUTINE VECTOR: VECTOR is defined twice (first on card 283)"),
    ("      FUNCTION VECTOR(A)\n      VECTOR=A\n      RETURN\n      END\n",
     "FUNCTION VECTOR: VECTOR is defined twice (first on card 283)"),
    ("      SUBROUTINE MAIN\n      RETURN\n      END\n",
     "SUBROUTINE MAIN: MAIN names the main program here; choose another name"),
])
def test_10_a_unit_name_used_twice_is_refused(tmp_path, extra, what):
    n = SOURCE.count("\n") + 1
    assert fails(tmp_path, SOURCE + extra) == f"{tmp_path / 'p.f'}: card {n}, column 7: {what}"


def test_10_a_lone_subroutine_main_is_no_main_program(tmp_path):
    line = fails(tmp_path, cards("|SUBROUTINE MAIN", "|RETURN", "|END"))
    assert line.endswith("card 1, column 7: SUBROUTINE MAIN: MAIN names the main program "
                         "here; choose another name")


# 11. not a crank-rocker: exit 3, as run -----------------------------------------------------------
def test_11_not_a_crank_rocker_exits_3_as_run(tmp_path):
    deck = tmp_path / "ncr.dat"
    lines = Path(EXAMPLE).read_text().splitlines()
    lines[2] = "    12.0     1.0     1.0     1.0"
    deck.write_text("\n".join(lines) + "\n")
    port = limited("run", str(deck))
    interpreted = limited("run", "--program", str(DECKS / "sielaff.f"), str(deck))
    assert port[:3] == interpreted[:3]
    assert port[0] == 3 and port[1] == " THIS IS NOT A CRANK ROCKER MECHANISM\n"
    out = tmp_path / "o.asa"
    out.write_text("before\n")
    status, _, err, _ = limited("run", "--program", str(DECKS / "sielaff.f"), str(deck),
                                "-o", str(out))
    assert status == 3 and out.read_text() == "before\n" and one_line(err).startswith(
        f"{deck}: card 3: THIS IS NOT A CRANK ROCKER MECHANISM")


# 22. diff reads a listing within bounds -----------------------------------------------------------
@pytest.mark.parametrize("listing, golden, what", [
    ("/dev/zero", str(GOLDEN / "figure10.asa"), "/dev/zero: line 1: not a listing (binary "
                                                 "data: a NUL character)"),
    (str(GOLDEN / "figure10.asa"), "/dev/zero", "/dev/zero: line 1: not a listing"),
    ("/dev/urandom", str(GOLDEN / "figure10.asa"), "/dev/urandom: line "),
])
def test_22_diff_refuses_binary_at_once(listing, golden, what):
    status, _, err, cpu = limited("diff", listing, golden, timeout=60)
    assert status == 2 and one_line(err).startswith(what) and cpu < 30


@pytest.mark.parametrize("source, what", [
    ("yes ''", "/dev/stdin: line 1001: more than 1,000 lines with no page eject: not a "
               "listing"),
    ("yes x | tr -d '\\n'", "/dev/stdin: line 1: longer than 65,536 characters, not a "
                            "listing (a listing line is 133)"),
])
def test_22_diff_of_an_endless_pipe_ends(source, what):
    status, _, err, cpu = limited(shell=f"{source} | {' '.join(SIELAFF)} diff /dev/stdin "
                                  f"{GOLDEN / 'figure10.asa'}", timeout=60)
    assert status == 2 and one_line(err) == what and cpu < 30


# 23. a deck through a pipe that never ends --------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("card", ["", "    10.0    10.0   360.0"])
def test_23_an_endless_deck_through_a_pipe_stops_at_flat_memory(card):
    status, out, err, _ = limited(
        shell=f"(cat {EXAMPLE}; yes '{card}') | {' '.join(SIELAFF)} run /dev/stdin "
              "--max-sheets 3", timeout=300)
    assert status == 2 and out == ""
    assert one_line(err) == ("/dev/stdin: card 1000007: more than 1,000,000 range cards (the "
                             "reader's limit; blank lines count until the deck ends)")


def test_23_blank_lines_are_counted_not_kept(monkeypatch):
    """The reader's family: blank lines between cards are cards, after the last they are
    dropped (each warned, up to MAX_WARNINGS), and the limit counts them too."""
    from sielaff.emulator import cards as reader

    lines = Path(EXAMPLE).read_text().splitlines()
    deck = reader.parse_deck("\n".join(lines + ["", "  ", "    10.0    10.0    20.0"]
                                       + ["   "] * 300) + "\n")
    assert deck.ranges == [(10.0, 10.0, 360.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0),
                           (10.0, 10.0, 20.0)]
    assert len(deck.warnings) == reader.MAX_WARNINGS + 1
    monkeypatch.setattr(reader, "MAX_RANGE_CARDS", 5)
    with pytest.raises(reader.DeckError, match="card 12: more than 5 range cards"):
        reader.parse_deck("\n".join(lines + [""] * 10))
