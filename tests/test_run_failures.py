"""Robustness of ``sielaff run``: bad decks, failing arithmetic, huge runs, lost output.

Every failure is exactly one line on stderr with exit status 2 (3 for a
mechanism that is not a crank-rocker) and no traceback unless ``--debug``.
Besides that line stderr may carry *diagnostics* only: lines beginning
``sielaff: warning: `` or ``sielaff: 1966 quirk: `` (see ``sielaff.cli``).

Most cases run ``sielaff.cli.main`` in-process; the ones that are about the
process itself (tracebacks, Ctrl-C, a closed pipe, memory) run a subprocess.
The fast printer is checked here too: it must print exactly what the
reference editors print.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import signal
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from conftest import DECKS
from procs import run
from sielaff.cli import main
from sielaff.emulator.printer import Format, Unprintable, _strict_value, edit_e, edit_f, fast_editor
from sielaff.tools.common import range_problem

EXAMPLE = (DECKS / "example.dat").read_text().splitlines()
DIAGNOSTIC = ("sielaff: warning: ", "sielaff: 1966 quirk: ")
SIELAFF = [sys.executable, "-m", "sielaff"]


def cards(*replace: tuple[int, str], drop_from: int | None = None) -> list[str]:
    """The example deck with card n (1-based) replaced by the given text."""
    lines = list(EXAMPLE)
    for n, text in replace:
        lines[n - 1] = text
    return lines[:drop_from - 1] if drop_from else lines


def write_deck(tmp_path: Path, content: list[str] | bytes, name: str = "deck.dat") -> str:
    path = tmp_path / name
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text("".join(line + "\n" for line in content))
    return str(path)


def cli(*argv: str) -> tuple[int, str, str]:
    """Run ``sielaff argv`` in-process: (exit status, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(list(argv))
    return status, out.getvalue(), err.getvalue()


def split_stderr(err: str) -> tuple[list[str], list[str]]:
    """stderr lines as (diagnostics, errors)."""
    lines = err.splitlines()
    return ([x for x in lines if x.startswith(DIAGNOSTIC)],
            [x for x in lines if not x.startswith(DIAGNOSTIC)])


def fails(tmp_path: Path, content, *extra: str, status: int = 2) -> str:
    """Run a deck that must fail; returns its one error line (checked: one line, no traceback)."""
    path = write_deck(tmp_path, content)
    code, out, err = cli("run", path, *extra)
    assert code == status, err
    _, errors = split_stderr(err)
    assert len(errors) == 1, err
    assert "Traceback" not in err
    return errors[0]


# ----------------------------------------------------------------- bad cards

@pytest.mark.parametrize("field, reason", [
    ("    4.x ", "not a number (character 'x')"),
    ("  1.2.3 ", "not a number (two decimal points)"),
    ("      - ", "not a number (a sign and no digits)"),
    ("   1.2E ", "not a number (exponent without digits)"),
    ("   4.0E+", "not a number (exponent without digits)"),
    ("   1,5  ", "not a number (character ',')"),
    ("     .  ", "not a number (no digits)"),
])
def test_bad_field_names_card_columns_and_text(tmp_path, field, reason):
    deck = cards((3, "    12.0" + field + "    16.0    12.0"))
    line = fails(tmp_path, deck)
    assert line == f'{tmp_path / "deck.dat"}: card 3, columns 9-16: "{field}": {reason}'


def test_bad_range_card(tmp_path):
    line = fails(tmp_path, cards((7, "    10.0    10.0   36O.0")))
    assert line == (f'{tmp_path / "deck.dat"}: card 7, columns 17-24: "   36O.0": '
                    "not a number (character 'O')")


def test_empty_file(tmp_path):
    assert fails(tmp_path, b"") == f"{tmp_path / 'deck.dat'}: empty deck (no cards)"


def test_file_of_blank_lines_is_empty(tmp_path):
    assert fails(tmp_path, b"\n   \n\n") == f"{tmp_path / 'deck.dat'}: empty deck (no cards)"


@pytest.mark.parametrize("ncards, card, names", [
    (1, 2, "ZI2 ZI3 ZI4"),
    (3, 4, "ADEL2 ADEL3 ADEL4"),
    (5, 6, "TH2D"),
])
def test_deck_ends_inside_the_parameter_cards(tmp_path, ncards, card, names):
    line = fails(tmp_path, EXAMPLE[:ncards])
    assert line == (f"{tmp_path / 'deck.dat'}: card {card}: deck ends inside the parameter "
                    f"cards (expected {names})")


def test_deck_ends_before_the_range_cards(tmp_path):
    line = fails(tmp_path, EXAMPLE[:6])
    assert line == (f"{tmp_path / 'deck.dat'}: deck ends before the first range card "
                    "(THZERO DELTA THMAX)")


@pytest.mark.parametrize("content, byte", [
    (b"\x7fELF\x02\x01\x01\x00" + bytes(range(256)), 7),
    (b"     3.0     8.0     6.0\n\xff\xfe\n", 25),
    (struct.pack("<8d", *range(8)), 0),
])
def test_binary_file(tmp_path, content, byte):
    line = fails(tmp_path, content)
    assert line == f"{tmp_path / 'deck.dat'}: not a text deck (binary data at byte {byte})"


def test_tab(tmp_path):
    line = fails(tmp_path, cards((3, "\t12.0     4.0    16.0    12.0")))
    assert line == (f"{tmp_path / 'deck.dat'}: card 3, column 1: tab character "
                    "(cards have no tabs; use blanks)")


def test_non_ascii(tmp_path):
    line = fails(tmp_path, cards((5, "     2.0     8.0     6.0  Länge")))
    assert line == f"{tmp_path / 'deck.dat'}: card 5, column 28: non-ASCII character '\\xe4'"


def test_control_character(tmp_path):
    line = fails(tmp_path, cards((2, "     0.0\x0c    0.5     0.4")))
    assert line == f"{tmp_path / 'deck.dat'}: card 2, column 9: control character '\\x0c'"


def test_crlf_line_ends_print_the_same_listing(tmp_path):
    lf = cli("run", write_deck(tmp_path, EXAMPLE))
    crlf = cli("run", write_deck(tmp_path, "".join(x + "\r\n" for x in EXAMPLE).encode(),
                                 name="crlf.dat"))
    assert crlf[0] == lf[0] == 0
    assert crlf[1] == lf[1]
    assert split_stderr(crlf[2])[1] == []


def test_columns_past_80_are_ignored_with_a_warning(tmp_path):
    long_card = EXAMPLE[2].ljust(80) + "  EXTRA COLUMNS"
    path = write_deck(tmp_path, cards((3, long_card)))
    status, out, err = cli("run", path)
    assert status == 0
    assert out == cli("run", str(DECKS / "example.dat"))[1]
    warnings, errors = split_stderr(err)
    assert errors == []
    assert f"sielaff: warning: {path}: card 3: 95 columns, columns 81-95 ignored" in warnings


def test_missing_deck(tmp_path):
    status, out, err = cli("run", str(tmp_path / "nope.dat"))
    assert (status, out, err) == (2, "", f"{tmp_path / 'nope.dat'}: no such deck\n")


def test_debug_shows_the_traceback_in_process(tmp_path):
    path = write_deck(tmp_path, cards((3, "    12.0  1.2.3     16.0    12.0")))
    from sielaff.emulator.cards import DeckError

    with pytest.raises(DeckError) as info:
        cli("--debug", "run", path)
    assert info.value.card == 3 and info.value.columns == (9, 16)
    with pytest.raises(DeckError):
        cli("run", path, "--debug")


def test_subprocess_one_line_without_traceback_and_with_debug(tmp_path):
    path = write_deck(tmp_path, cards((3, "    12.0  1.2.3     16.0    12.0")))
    proc = run(["run", path], text=True, timeout=60)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr == (f'{path}: card 3, columns 9-16: "  1.2.3 ": '
                           "not a number (two decimal points)\n")
    proc = run(["--debug", "run", path], text=True, timeout=60)
    assert proc.returncode == 1
    assert "Traceback" in proc.stderr and "DeckError" in proc.stderr


def test_subprocess_binary_deck(tmp_path):
    path = write_deck(tmp_path, b"\x00\x01\x02garbage")
    proc = run(["run", path], text=True, timeout=60)
    assert (proc.returncode, proc.stdout) == (2, "")
    assert proc.stderr == f"{path}: not a text deck (binary data at byte 0)\n"


# ------------------------------------------------------- the 1966 arithmetic

def test_r2_zero_is_refused_by_the_shared_validation_naming_the_card(tmp_path):
    line = fails(tmp_path, cards((3, "    12.0     0.0    16.0    12.0")))
    assert line == (f"{tmp_path / 'deck.dat'}: card 3: R2 = 0 in: the link lengths R1-R4 "
                    "must be positive")


@pytest.mark.parametrize("arith, start", [
    ("float64", "division by zero"),
    ("ibm1410", "IBM 1410 floating-point division by zero"),
])
def test_the_port_itself_names_the_statement_dividing_by_r2_zero(tmp_path, arith, start):
    """Past the commands' validation, the emulator still says where the 1966 program
    divides by zero (for decks built in code)."""
    import io

    from sielaff.emulator.cards import read_deck
    from sielaff.emulator.program import ProgramError
    from sielaff.emulator.run import run

    deck = read_deck(write_deck(tmp_path, cards((3, "    12.0     0.0    16.0    12.0"))))
    with pytest.raises(ProgramError) as exc:
        run(deck, io.StringIO(), arithmetic=arith)
    assert str(exc.value).startswith(start)
    assert str(exc.value).endswith(" in A=R3/R2 (R2 = 0 on card 3)")


@pytest.mark.parametrize("th2d, name, value", [
    ("  1.E+50", "TH3DD", "4.0308E+99"),   # SQ2D = 1E100: the 1410 overflows
    ("  1.E+98", "TH3DD", "4.0308E+195"),
])
def test_huge_th2d_overflows_naming_the_quantity(tmp_path, th2d, name, value):
    line = fails(tmp_path, cards((6, th2d)))
    assert line == (f"{tmp_path / 'deck.dat'}: {name} = {value} is past the IBM 1410's range "
                    "(|x| < 1E99): the 1966 arithmetic overflows for this deck")


def test_float64_infinity_names_the_quantity(tmp_path):
    line = fails(tmp_path, cards((5, "     2.0 1.0E+80     6.0")))
    assert line == (f"{tmp_path / 'deck.dat'}: FA32 is inf: the 1966 arithmetic overflows "
                    "or divides by zero for this deck")


def test_overflow_is_never_printed_as_stars_or_nan(tmp_path):
    path = write_deck(tmp_path, cards((6, "  1.E+50")))
    status, out, _ = cli("run", path)
    assert status == 2
    assert out == ""  # the failing sheet is the first: nothing was printed
    assert "*" not in out and "nan" not in out.lower() and "inf" not in out.lower()


def test_failing_sheet_is_not_half_printed(tmp_path):
    # THZERO 9E98, DELTA 9E98: sheet 1 prints (THETA 2 = 9E98 does not fit F12.1:
    # stars, a legal 1410 printout); sheet 2 has THETA 2 = 1.8E99, past the range.
    path = write_deck(tmp_path, cards((7, " 9.0E+98 9.0E+98 9.9E+98")))
    status, out, err = cli("run", path)
    assert status == 2
    assert out.splitlines().count("1") == 1 and out.endswith("\n1\n")
    assert split_stderr(err)[1] == [
        f"{path}: ATH2 = 1.8000E+99 is past the IBM 1410's range (|x| < 1E99): "
        "the 1966 arithmetic overflows for this deck"]


def test_underflow_prints_as_the_1410_zero(tmp_path):
    # TH2D = 1E-60: accelerations are ~1E-119, below the 1410's 1E-100; its
    # exponent underflow made them 0, printed .0000E-99 (not a field of stars).
    path = write_deck(tmp_path, cards((6, "  1.E-60")))
    status, out, _ = cli("run", path)
    assert status == 0 and "*" not in out
    record = out.splitlines()[12]
    assert record == "                 -.4462E-60  -.3578E-60   .0000E-99   .0000E-99"


@pytest.mark.parametrize("card, start, end", [
    ((6, "  1.E+50"), "IBM 1410 floating-point overflow", " in SQ2D=TH2D*TH2D"),
])
def test_ibm1410_arithmetic_failure_names_the_statement(tmp_path, card, start, end):
    line = fails(tmp_path, cards(card), "--arith", "ibm1410")
    assert line.startswith(f"{tmp_path / 'deck.dat'}: {start}") and line.endswith(end), line


def test_float64_underflow_prints_what_the_1410_printed(tmp_path):
    path = write_deck(tmp_path, cards((6, "  1.E-60"), (7, "    10.0    10.0    10.0")))
    float64, ibm1410 = cli("run", path), cli("run", path, "--arith", "ibm1410")
    assert float64[0] == ibm1410[0] == 0
    record = float64[1].splitlines()[12]
    assert record.endswith("   .0000E-99   .0000E-99")
    assert ibm1410[1].splitlines()[12] == record


def test_not_a_crank_rocker_exits_3(tmp_path):
    path = write_deck(tmp_path, cards((3, "    12.0    14.0    16.0    12.0")))
    status, out, err = cli("run", path)
    assert status == 3
    assert out == " THIS IS NOT A CRANK ROCKER MECHANISM\n"
    assert split_stderr(err)[1] == [
        f"{path}: card 3: THIS IS NOT A CRANK ROCKER MECHANISM: B = R4/R2 = 0.857143 must be > 1 "
        "(the crank must be the shortest link)"]


# ------------------------------------------------ runs that never end, or late

@pytest.mark.parametrize("card, delta", [
    ("    10.0     0.0   360.0", "0"),
    ("    10.0   -10.0   360.0", "-10"),
    ("    10.0  -1.E-9    10.0", "-1e-09"),
])
def test_endless_range_is_refused_at_once_naming_the_card(tmp_path, card, delta):
    thmax = card.split()[-1].rstrip("0").rstrip(".")
    start = time.perf_counter()
    line = fails(tmp_path, cards((7, card)))
    assert time.perf_counter() - start < 5
    assert line == (f"{tmp_path / 'deck.dat'}: card 7, columns 9-16: DELTA = {delta} with "
                    f"THZERO = 10 <= THMAX = {thmax}: the 1966 loop would never end")


def test_endless_second_range_card_is_refused_before_anything_is_printed(tmp_path):
    path = write_deck(tmp_path, [*EXAMPLE, "     0.0     0.0     0.0"])
    status, out, err = cli("run", path)
    assert (status, out) == (2, "")
    assert split_stderr(err)[1] == [
        f"{path}: card 8, columns 9-16: DELTA = 0 with THZERO = 0 <= THMAX = 0: "
        "the 1966 loop would never end"]


def test_negative_delta_past_thmax_is_one_sheet(tmp_path):
    # THZERO > THMAX: the loop prints one sheet and tests ATH2.GT.THMAX: it ends.
    path = write_deck(tmp_path, cards((7, "    20.0   -10.0    10.0")))
    from sielaff.emulator.cards import read_deck

    assert range_problem(read_deck(path)) is None
    status, out, _ = cli("run", path)
    assert status == 0 and out.count("THETA 2") == 1


def test_max_sheets_stops_cleanly_with_a_warning(tmp_path):
    path = write_deck(tmp_path, cards((7, "  0.0001  0.0001  1000.0")))  # 10**7 sheets
    status, out, err = cli("run", path, "--max-sheets", "3")
    assert status == 0
    assert out.count("THETA 2") == 3 and out.endswith("\n1\n")
    assert err == ("sielaff: warning: stopped after 3 sheets (--max-sheets); "
                   "the deck asks for more\n")


def test_max_sheets_to_a_file_keeps_the_sheets_printed(tmp_path):
    path = write_deck(tmp_path, cards((7, "  0.0001  0.0001  1000.0")))
    out = tmp_path / "listing.asa"
    status, stdout, _ = cli("run", path, "-o", str(out), "--max-sheets", "2")
    assert (status, stdout) == (0, "")
    assert out.read_text() == cli("run", path, "--max-sheets", "2")[1]
    assert out.read_text().count("THETA 2") == 2


def test_max_sheets_not_reached_says_nothing(tmp_path):
    status, out, err = cli("run", str(DECKS / "example.dat"), "--max-sheets", "37")
    assert status == 0 and out.count("THETA 2") == 37
    assert "max-sheets" not in err


def test_max_sheets_must_be_a_count():
    with pytest.raises(SystemExit) as info, contextlib.redirect_stderr(io.StringIO()) as err:
        main(["run", str(DECKS / "example.dat"), "--max-sheets", "-1"])
    assert info.value.code == 2
    assert "'-1' is not a number of sheets" in err.getvalue()


_HWM = (
    "import sys\n"
    "from sielaff.cli import main\n"
    "rc = main(sys.argv[1:])\n"
    "hwm = [l for l in open('/proc/self/status') if l.startswith('VmHWM:')][0]\n"
    "sys.stderr.write('PEAK ' + hwm.split()[1] + '\\n')\n"
    "sys.exit(rc)\n"
)


def _peak_rss_kb(args: list[str]) -> int:
    """Peak resident set (KiB) of a ``sielaff`` child, read from its own /proc VmHWM.

    (wait4's ru_maxrss would also count the pytest process the child was forked
    from: Linux carries the old address space's high-water mark across exec.)
    """
    proc = subprocess.run([sys.executable, "-c", _HWM, *args], stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True, check=False)
    assert proc.returncode == 0, proc.stderr
    return int(proc.stderr.rsplit("PEAK ", 1)[1].split()[0])


def test_memory_is_flat_however_many_sheets(tmp_path):
    """A 10**7-sheet range streams: 5000 and 50000 sheets have the same peak RSS (both
    past the float64 listing's block of emulator.vector.CHUNK sheets, the port's 1)."""
    from sielaff.emulator.vector import CHUNK

    path = write_deck(tmp_path, cards((7, "  0.0001  0.0001  1000.0")))
    out = str(tmp_path / "listing.asa")
    assert 5000 > 2 * CHUNK
    short = _peak_rss_kb(["run", path, "-o", out, "--max-sheets", "5000"])
    long = _peak_rss_kb(["run", path, "-o", out, "--max-sheets", "50000"])
    assert os.path.getsize(out) > 50000 * 1000
    assert long < 150 * 1024
    assert long - short < 8 * 1024, (short, long)


# ------------------------------------------------------------- nothing lost

def test_output_file_is_replaced_only_on_success(tmp_path):
    out = tmp_path / "listing.asa"
    out.write_text("precious\n")
    bad = write_deck(tmp_path, cards((6, "  1.E+50")))
    assert cli("run", bad, "-o", str(out))[0] == 2
    assert out.read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.dat", "listing.asa"]
    assert cli("run", str(DECKS / "example.dat"), "-o", str(out))[0] == 0
    assert out.read_text() == cli("run", str(DECKS / "example.dat"))[1]


def test_output_keeps_permissions_and_follows_links(tmp_path):
    target = tmp_path / "target.asa"
    target.write_text("old\n")
    target.chmod(0o640)
    link = tmp_path / "link.asa"
    link.symlink_to(target)
    assert cli("run", str(DECKS / "example.dat"), "-o", str(link))[0] == 0
    assert link.is_symlink()
    assert (target.stat().st_mode & 0o777) == 0o640
    assert target.read_text().count("THETA 2") == 37


def test_output_to_a_special_file_is_written_in_place(tmp_path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    got: list[bytes] = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()))
    reader.start()
    status, _, _ = cli("run", str(DECKS / "example.dat"), "-o", str(fifo))
    reader.join(30)
    assert status == 0
    assert fifo.is_fifo()  # not replaced by a regular file
    assert got[0].decode().count("THETA 2") == 37


def test_unwritable_output_is_one_line(tmp_path):
    (tmp_path / "afile").write_text("x")
    out = tmp_path / "afile" / "sub" / "dir.asa"  # a folder that cannot be made
    status, _, err = cli("run", str(DECKS / "example.dat"), "-o", str(out))
    assert status == 2
    assert err == f"sielaff: {out}: cannot write (Not a directory)\n"


def test_missing_output_folders_are_made(tmp_path):
    out = tmp_path / "no" / "such" / "dir.asa"
    status, _, err = cli("run", str(DECKS / "example.dat"), "-o", str(out))
    assert status == 0 and err.count("warning") == 0
    assert out.read_text().count("THETA 2") == 37


def _wait_for(predicate, timeout: float = 30.0) -> None:
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError("timed out")
        time.sleep(0.02)


def _default_sigint() -> None:
    # A shell without job control starts background jobs with SIGINT ignored,
    # and Python then keeps ignoring it: give the child the default, as a
    # terminal's Ctrl-C would find it.
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def test_ctrl_c_leaves_the_existing_file(tmp_path):
    deck = write_deck(tmp_path, cards((7, "  0.0001  0.0001   300.0")))  # 3 million sheets
    out = tmp_path / "listing.asa"
    out.write_text("precious\n")
    proc = subprocess.Popen([*SIELAFF, "run", deck, "-o", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=_default_sigint)
    try:
        def temporary_has_sheets() -> bool:
            tmp = [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]
            return bool(tmp) and tmp[0].stat().st_size > 100_000
        _wait_for(temporary_has_sheets)
        proc.send_signal(signal.SIGINT)
        stdout, stderr = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 130
    assert stdout == ""
    assert stderr == "sielaff: interrupted; no output file was changed\n"
    assert out.read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.dat", "listing.asa"]


def test_closed_pipe_exits_quietly(tmp_path):
    deck = write_deck(tmp_path, cards((7, "  0.0001  0.0001   300.0")))
    proc = subprocess.Popen([*SIELAFF, "run", deck], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    try:
        head = proc.stdout.read(5000)  # like `head`: read a little, then go away
        proc.stdout.close()
        stderr = proc.stderr.read()
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert head.count(b"THETA 2") >= 1
    assert stderr == b""  # no traceback, no "Exception ignored ... BrokenPipeError"
    assert proc.returncode == 0


def test_closed_pipe_through_the_shell(tmp_path):
    deck = write_deck(tmp_path, cards((7, "  0.0001  0.0001   300.0")))
    for extra in ("", " --render"):
        proc = subprocess.run(
            f"{sys.executable} -m sielaff run {deck}{extra} | head -n 3; "
            "echo status ${PIPESTATUS[0]}",
            shell=True, executable="/bin/bash", capture_output=True, text=True, timeout=60)
        assert proc.stderr == ""
        assert proc.stdout.endswith("status 0\n")


# ------------------------------------------------- the fast printer is exact

def _editors():
    for kind, w, d in (("E", 12, 4), ("F", 12, 1), ("E", 10, 3), ("F", 10, 2), ("E", 9, 4),
                       ("F", 8, 1), ("E", 16, 9)):
        reference = edit_e if kind == "E" else edit_f
        yield fast_editor(kind, w, d), fast_editor(kind, w, d, strict=True), reference, w, d


EDITORS = list(_editors())


def _same_text(value: float) -> None:
    for loose, strict, reference, w, d in EDITORS:
        assert loose(value) == reference(value, w, d), (value, w, d)
        try:
            expected = reference(_strict_value(value), w, d)
        except Unprintable:
            with pytest.raises(Unprintable):
                strict(value)
        else:
            assert strict(value) == expected, (value, w, d)


def _near_boundaries():
    """Floats a few units in the last place from k/10**n: where repr and the binary value
    may sit on different sides of a printed digit."""
    return st.builds(
        lambda k, n, e, steps, up, sign: sign * _step(k / 10 ** n * 10.0 ** e, steps, up),
        st.integers(1, 99_999_999), st.integers(0, 8), st.integers(-100, 95),
        st.integers(0, 3), st.booleans(), st.sampled_from([1, -1]))


def _step(x: float, steps: int, up: bool) -> float:
    for _ in range(steps):
        x = math.nextafter(x, math.inf if up else -math.inf)
    return x


@given(st.one_of(st.floats(), _near_boundaries(),
                 st.floats(-1000, 1000).map(lambda x: round(x, 4))))
@example(0.7)
@example(-0.0)
@example(199.99999)
@example(1e99)
@example(9.99999e98)
@example(1e-100)
@example(-1e-101)
@example(99.99999999999999)
@example(200.00000000000003)
def test_fast_editors_print_exactly_what_the_reference_prints(value):
    _same_text(value)


def test_fast_editors_on_other_number_types():
    import numpy as np

    for value in (np.float32(0.7), np.float32(-27.07), np.float32("inf")):
        for loose, _, reference, w, d in EDITORS:
            assert loose(value) == reference(value, w, d)


@pytest.mark.parametrize("text", [
    "(11X,3F12.1/)", "(15X,5E12.4/)", "(//18X,7HTHETA 2,5X,7HTHETA 3/)", "(1H1)", "(/)",
    "(5HA B C,F6.1,4HTAIL)", "(0X,F12.1)", "(F12.1,/,/,E12.4)",
])
def test_text_function_is_the_joined_records(text):
    fmt = Format(text)
    values = [545.6, -27.07, 0.0, 130.357, 1e-5][:fmt.n_edits]
    for n in range(len(values) + 1):
        expected = "".join(r + "\n" for r in fmt.records(values[:n]))
        assert fmt.text_function(n)(*values[:n]) == expected
