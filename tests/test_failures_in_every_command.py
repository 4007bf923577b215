"""Robust, round two: one test per finding of the second robustness review.

Each test reproduces its finding (it failed on the code before the fix) and checks
the behaviour now: nothing lost, nothing endless, one line for every failure, the
same in every command.  Helpers come from ``test_run_failures``.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from unittest import mock

import pytest

from conftest import DECKS, GOLDEN
from procs import run
from sielaff.mechanism import EXAMPLE as EXAMPLE_MECHANISM
from test_run_failures import SIELAFF, _peak_rss_kb, cards, cli, split_stderr, write_deck

COMMANDS = ("run", "check", "table")  # plot: below, with a folder


def one_error(err: str) -> str:
    """The single error line of stderr (the rest must be diagnostics), no traceback."""
    _, errors = split_stderr(err)
    assert len(errors) == 1 and "Traceback" not in err, err
    return errors[0]


def everywhere(tmp_path: Path, deck: str) -> dict[str, tuple[int, str]]:
    """(status, error line) of every command on ``deck``."""
    out = {}
    for command in COMMANDS:
        status, _, err = cli(command, deck)
        out[command] = (status, one_error(err) if status else "")
    pytest.importorskip("matplotlib")
    status, _, err = cli("plot", deck, "-o", str(tmp_path / "plots"))
    out["plot"] = (status, one_error(err) if status else "")
    return out


# 1. a range that practically never ends -----------------------------------------------------
@pytest.mark.parametrize("arith", ["float64", "ibm1410", "float32"])
def test_01_tiny_delta_is_refused_at_once_by_every_command(tmp_path, arith):
    deck = write_deck(tmp_path, cards((7, "    10.0  1.E-90    10.0")))
    start = time.process_time()
    status, out, err = cli("run", deck, "--arith", arith)
    line = one_error(err)
    assert (status, out) == (2, "") and time.process_time() - start < 5
    assert line.startswith(f"{deck}: card 7, columns ")
    assert "never end" in line or "past the ceiling of 10,000,000" in line
    for command, (status, line) in everywhere(tmp_path, deck).items():
        assert status == 2 and "card 7, columns" in line, command
    status, text, _ = cli("check", deck)
    assert "Verdict: unusable" in text and "usable\n" not in text


def test_01_max_sheets_bounds_a_range_past_the_ceiling(tmp_path):
    deck = write_deck(tmp_path, cards((7, "     0.0  1.E-10   360.0")))  # 3.6E12 sheets
    status, _, err = cli("run", deck)
    assert status == 2 and "3.60E12 sheets, past the ceiling" in one_error(err)
    status, out, err = cli("run", deck, "--max-sheets", "3")
    assert status == 0 and out.count("THETA 2") == 3 and "stopped after 3 sheets" in err


def test_01_sheet_count_follows_the_arithmetic():
    from sielaff.emulator.ranges import sheet_count

    assert sheet_count(10.0, 10.0, 360.0) == 37  # the example: one past THMAX
    assert sheet_count(10.0, 1e-90, 10.0, "float32") is None  # 1E-90 underflows to 0
    n = sheet_count(10.0, 1e-90, 10.0, "float64")  # float64: I*1E-90 must pass half an ulp
    th = 10.0 - 1e-90
    assert th + float(n) * 1e-90 > 10.0 and not th + float(n - 1) * 1e-90 > 10.0
    assert 8.8e74 < n < 8.9e74
    assert sheet_count(0.0, 1e-90, 1e50, "ibm1410") >= 10**99  # I itself overflows: it stops
    assert sheet_count(10.0, 1e-90, 10.0, "ibm1410") == 10**84  # 8 digits drop 1E-90 * I
    assert sheet_count(20.0, -1.0, 10.0) == 1 and sheet_count(10.0, 0.0, 20.0) is None


# 2. run -o EXISTING on a deck that is not a crank-rocker ------------------------------------
def test_02_run_leaves_an_existing_output_alone_on_exit_3(tmp_path):
    deck = write_deck(tmp_path, cards((3, "    12.0    14.0    16.0    12.0")))
    out = tmp_path / "keep.asa"
    out.write_text("precious\n")
    status, _, err = cli("run", deck, "-o", str(out))
    assert status == 3 and "THIS IS NOT A CRANK ROCKER MECHANISM" in one_error(err)
    assert out.read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.dat", "keep.asa"]
    status, text, _ = cli("run", deck)  # on stdout the 1966 message is the listing
    assert status == 3 and "THIS IS NOT A CRANK ROCKER MECHANISM" in text


# 3. -o that is the input --------------------------------------------------------------------
@pytest.mark.parametrize("command, source", [
    ("run", DECKS / "example.dat"), ("table", DECKS / "example.dat"),
    ("punch", DECKS / "example.toml")])
@pytest.mark.parametrize("via_link", [False, True])
def test_03_output_that_is_the_input_is_refused_before_any_work(tmp_path, command, source,
                                                                 via_link):
    path = tmp_path / source.name
    path.write_bytes(source.read_bytes())
    target = path
    if via_link:
        target = tmp_path / "link"
        target.symlink_to(path)
    status, out, err = cli(command, str(path), "-o", str(target))
    assert status == 2 and "refusing to overwrite it" in one_error(err)
    assert path.read_bytes() == source.read_bytes()


# 4. SIGTERM, SIGHUP and timeout leave no temporary file ----------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("signum, status", [(signal.SIGTERM, 143), (signal.SIGHUP, 129)])
def test_04_signals_remove_the_temporary_file(tmp_path, signum, status):
    deck = write_deck(tmp_path, cards((7, "  0.0001  0.0001  1000.0")))
    out = tmp_path / "out.asa"
    out.write_text("precious\n")
    proc = subprocess.Popen([*SIELAFF, "run", deck, "-o", str(out), "--max-sheets", "5000000"],
                            stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]:
        assert time.monotonic() < deadline and proc.poll() is None
        time.sleep(0.05)
    time.sleep(0.3)  # some sheets written to the temporary file
    proc.send_signal(signum)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == status, err
    assert f"terminated by {signal.Signals(signum).name}; no output file was changed" in err
    assert "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.dat", "out.asa"]
    assert out.read_text() == "precious\n"


@pytest.mark.slow
def test_04_timeout_leaves_no_temporary_file(tmp_path):
    deck = write_deck(tmp_path, cards((7, "  0.0001  0.0001  1000.0")))
    out = tmp_path / "out.asa"
    proc = subprocess.run(["timeout", "2", *SIELAFF, "run", deck, "-o", str(out),
                           "--max-sheets", "5000000"], capture_output=True, text=True)
    assert proc.returncode == 124  # timeout's status for a command it ended
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.dat"]


# 5. unbounded reads -------------------------------------------------------------------------
@pytest.mark.slow
def test_05_dev_zero_and_a_sparse_file_fail_at_once():
    start = time.monotonic()
    proc = run(["run", "/dev/zero"], text=True, timeout=60)
    assert proc.returncode == 2
    assert proc.stderr == "/dev/zero: not a text deck (binary data at byte 0)\n"
    assert time.monotonic() - start < 30


def test_05_a_line_longer_than_a_card_is_read_only_as_far_as_needed(tmp_path):
    from sielaff.emulator import cards as cards_module

    path = write_deck(tmp_path, [*EXAMPLE_LINES[:6], EXAMPLE_LINES[6] + "x" * 10**6])
    reads = []
    real_open = open

    def spy_open(*a, **k):
        f = real_open(*a, **k)
        readline = f.readline
        f.readline = lambda size=-1: reads.append(size) or readline(size)  # type: ignore
        return f

    with mock.patch("builtins.open", spy_open):
        deck = cards_module.read_deck(path)
    assert reads and all(0 < size <= cards_module.LINE_LIMIT for size in reads)
    assert deck.ranges == [(10.0, 10.0, 360.0)]
    assert any("columns 81-1000080 ignored" in w for w in deck.warnings)


@pytest.mark.slow
def test_05_a_million_range_cards_read_at_flat_memory(tmp_path):
    path = tmp_path / "million.dat"
    with open(path, "w") as f:
        f.write("\n".join(EXAMPLE_LINES[:6]) + "\n")
        for k in range(10**6):
            f.write(f"{k % 3600 / 10:8.1f}     1.0{k % 3600 / 10:8.1f}\n")
    peak = _peak_rss_kb(["run", str(path), "-o", str(tmp_path / "o.asa"),
                         "--max-sheets", "10"])
    assert peak < 150 * 1024, f"{peak} KiB"


@pytest.mark.slow
def test_05_diff_streams_both_listings(tmp_path):
    deck = write_deck(tmp_path, cards((7, "     0.0    0.01   360.0")))  # 36,002 sheets
    big = tmp_path / "big.asa"
    assert cli("run", deck, "-o", str(big))[0] == 0
    small = tmp_path / "small.asa"
    small.write_text("".join(big.open().readlines()[:59 * 200]))
    peaks = [_peak_rss_kb_any(["diff", str(p), str(p)]) for p in (small, big)]
    assert peaks[1] < peaks[0] + 10 * 1024, peaks  # 180 times the listing, the same memory


def _peak_rss_kb_any(args: list[str]) -> int:
    """Like test_run_failures._peak_rss_kb, for commands that may exit non-zero."""
    from test_run_failures import _HWM

    proc = subprocess.run([sys.executable, "-c", _HWM, *args], stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True, check=False)
    assert proc.returncode in (0, 1), proc.stderr
    return int(proc.stderr.rsplit("PEAK ", 1)[1].split()[0])


@pytest.mark.slow
# 6. plot interrupted: all files or none ------------------------------------------------------
def test_06_interrupted_plot_changes_no_file(tmp_path):
    pytest.importorskip("matplotlib")
    from sielaff.tools import plot as plots

    folder = tmp_path / "plots"
    assert cli("plot", str(DECKS / "example.dat"), "-o", str(folder))[0] == 0
    before = {p.name: p.read_bytes() for p in folder.iterdir()}
    real, calls = plots.render_png, []

    def fourth_interrupts(d):
        calls.append(d.name)
        if len(calls) == 4:
            raise KeyboardInterrupt
        return real(d) + b"changed"

    with mock.patch.object(plots, "render_png", fourth_interrupts):
        status, _, err = cli("plot", str(DECKS / "example.dat"), "-o", str(folder))
    assert status == 130 and "no output file was changed" in err
    assert {p.name: p.read_bytes() for p in folder.iterdir()} == before


# 7. no traceback without --debug ----------------------------------------------------------
@pytest.mark.parametrize("command", ["table", "check", "run"])
def test_07_huge_lengths_are_one_line(tmp_path, command):
    deck = write_deck(tmp_path, cards((3, "  1.2E80   4.E79  1.6E80  1.2E80"),
                                      (5, "   2.E79   8.E79   6.E79")))
    status, _, err = cli(command, deck)
    assert status == 2 and "past the IBM 1410's range" in one_error(err)


def test_07_deeply_nested_toml_is_one_line(tmp_path):
    spec = tmp_path / "deep.toml"
    spec.write_text("x = " + "[" * 100000 + "]" * 100000 + "\n")
    status, _, err = cli("punch", str(spec))
    assert status == 2 and one_error(err).startswith(f"{spec}: ")


@pytest.mark.slow
def test_07_closed_stdout_is_one_line():
    proc = subprocess.run(" ".join([*SIELAFF, "run", str(DECKS / "example.dat")]) + " >&-",
                          shell=True, capture_output=True, text=True)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr == ("sielaff: standard output is closed (started with >&-?); "
                           "nothing was run\n")


# 8. the error line is never "None" ----------------------------------------------------------
@pytest.mark.parametrize("arith", ["float32", "ibm1410"])
def test_08_another_arithmetic_refusing_names_card_3(tmp_path, arith):
    deck = write_deck(tmp_path, cards((3, "     8.0     3.0     4.0     7.0")))
    status, _, err = cli("run", deck, "--arith", arith)
    if status:  # the arithmetic's own 1966 test refused the change point
        line = one_error(err)
        assert status == 3 and line != "None"
        assert line.startswith(f"{deck}: card 3: THIS IS NOT A CRANK ROCKER MECHANISM: ")


def test_08_the_port_says_which_test_failed_in_its_arithmetic():
    from sielaff.emulator.program import _failed_test

    text = _failed_test(2.0, 3.0, 4.5, abs, "float32")
    assert text.startswith("IF(C.LT.(A+B-1.0)) fails in float32 arithmetic")


# 9. no Python warning reaches stderr ---------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("deck_cards, extra", [
    ([(3, "  1.2E-9   4.E-10  1.6E-9  1.2E-9")], ["--arith", "float32"]),
    ([(6, "  1.E+30")], ["--arith", "float32"]),
    ([(3, "     8.0     3.0     4.0     7.0")], []),
])
def test_09_no_python_warning_on_stderr(tmp_path, deck_cards, extra):
    deck = write_deck(tmp_path, cards(*deck_cards))
    for command in (["run", *extra], ["check"], ["table"]):
        proc = run([*command, deck], text=True,
                   env=dict(os.environ, PYTHONWARNINGS="default"))
        for line in proc.stderr.splitlines():
            assert line.startswith(("sielaff: ", deck)), (command, line)
        assert "Warning" not in proc.stderr and ".py:" not in proc.stderr, command


# 10. silent wrong answers -------------------------------------------------------------------
@pytest.mark.parametrize("scale", [1e-85, 1e-60, 1e60, 1e75])
def test_10_tiny_and_huge_lengths_give_the_same_positions(scale):
    from sielaff.engine import analyze

    m = EXAMPLE_MECHANISM
    scaled = m.replace(**{k: getattr(m, k) * scale for k in
                          ("R1", "R2", "R3", "R4", "RG2", "RG3", "RG4")})
    for name in ("ATH3", "ATH4", "TH3D", "TH4DD", "GAMMA"):
        want = analyze(m, [10.0, 200.0], [name])[name]
        got = analyze(scaled, [10.0, 200.0], [name])[name]
        assert got == pytest.approx(want, rel=1e-12), name


@pytest.mark.parametrize("fields, message", [
    ({"R2": 0.0}, "R2 = 0 in: the link lengths R1-R4 must be positive"),
    ({"R1": -12.0, "R2": -4.0, "R3": -16.0, "R4": -12.0}, "R1 = -12 in"),
    ({"W3": None}, "W3 is missing"),
    ({"TH2D": float("nan")}, "TH2D = nan is not finite"),
    ({"ZI4": -1.0}, "cannot be negative"),
])
def test_10_analyze_refuses_impossible_mechanisms_naming_the_field(fields, message):
    from sielaff.engine import analyze

    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        analyze(EXAMPLE_MECHANISM.replace(**fields), [10.0])


def test_10_a_change_point_is_not_a_usable_crank_rocker(tmp_path):
    deck = write_deck(tmp_path, cards((3, "     8.0     3.0     4.0     7.0")))  # 8+3 = 4+7
    status, text, err = cli("check", deck, "--crank-rocker")
    assert status == 3 and "change point" in one_error(err) and "usable\n" not in text
    assert "nan" not in text
    # without --crank-rocker, any four-bar (issue 22): the change point's report, exit 0
    status, text, err = cli("check", deck)
    assert status == 0 and "folds" not in err and "nan" not in text
    assert "lie in line at THETA 2 = 180 deg" in text
    # the modern table takes any four-bar; at the change point (folded flat, THETA 2 =
    # 180) the rates are not defined: that position is left out, the rest are rows
    status, out, err = cli("table", deck)  # a note naming the kind, the count left out
    assert status == 0 and "change-point" in err and "Traceback" not in err
    assert "nan" not in out and "1 of 36 positions left out" in err
    status, out, err = cli("run", deck)  # the 1966 test passes by roundoff: faithful, flagged
    if status == 0:
        assert "change point" in err and "passed by roundoff" in err


# 11. the sub-commands agree -----------------------------------------------------------------
@pytest.mark.parametrize("card, status, words", [
    ((3, "    12.0     0.0    16.0    12.0"), 2, "R2 = 0 in: the link lengths"),
    ((3, "   -12.0    -4.0   -16.0   -12.0"), 2, "R1 = -12 in: the link lengths"),
    ((6, " 1.0E+98"), 2, "past the IBM 1410's range"),
])
def test_11_every_command_gives_the_same_status(tmp_path, card, status, words):
    deck = write_deck(tmp_path, cards(card))
    results = everywhere(tmp_path, deck)
    results["run float32"] = cli("run", deck, "--arith", "float32")[0], ""
    for command, (got, line) in results.items():
        assert got == status, command
        if line and command != "run":
            assert words in line, (command, line)


# 12. the exit status survives a closed pipe ---------------------------------------------------
@pytest.mark.slow
def test_12_exit_status_survives_a_closed_pipe(tmp_path):
    deck = write_deck(tmp_path, cards((3, "    12.0    14.0    16.0    12.0")))
    sh = " ".join(SIELAFF)
    proc = subprocess.run(f"{sh} check --crank-rocker {deck} | true; echo ${{PIPESTATUS[0]}}",
                          shell=True,
                          executable="/bin/bash", capture_output=True, text=True)
    assert proc.stdout.strip() == "3" and "NOT A CRANK ROCKER" in proc.stderr
    listing = tmp_path / "l.asa"
    assert cli("run", str(DECKS / "example.dat"), "-o", str(listing))[0] == 0
    proc = subprocess.run(f"{sh} diff {listing} {GOLDEN / 'figure10.asa'} | head -c1 >/dev/null;"
                          " echo ${PIPESTATUS[0]}", shell=True, executable="/bin/bash",
                          capture_output=True, text=True)
    assert proc.stdout.strip() == "1" and "Traceback" not in proc.stderr


# 13. diff ---------------------------------------------------------------------------------------
def test_13_diff_refuses_an_empty_golden_and_names_files(tmp_path):
    listing = tmp_path / "l.asa"
    cli("run", str(DECKS / "example.dat"), "-o", str(listing))
    empty = tmp_path / "empty.asa"
    empty.write_text("")
    status, _, err = cli("diff", str(listing), str(empty))
    assert status == 2 and one_error(err).startswith(f"{empty}: no sheet")
    junk = tmp_path / "junk.asa"
    junk.write_text(" 1.0 2.0\n")
    status, _, err = cli("diff", str(listing), str(junk))
    assert status == 2 and one_error(err).startswith(f"{junk}: line 1: ")
    status, _, err = cli("diff", str(tmp_path / "none.asa"), str(junk))
    assert status == 2 and "none.asa: cannot read the listing" in one_error(err)


def test_13_golden_starting_with_a_page_eject_and_rendered_listings(tmp_path):
    listing, rendered = tmp_path / "l.asa", tmp_path / "l.txt"
    cli("run", str(DECKS / "example.dat"), "-o", str(listing))
    cli("run", str(DECKS / "example.dat"), "--render", "-o", str(rendered))
    golden = tmp_path / "g.asa"
    golden.write_text("1\n" + (GOLDEN / "figure10.asa").read_text())
    plain = cli("diff", str(listing), str(GOLDEN / "figure10.asa"))
    assert plain[0] == 1 and "THETA 2 = ?" not in plain[1]
    assert cli("diff", str(listing), str(golden))[1] == plain[1]
    assert cli("diff", str(rendered), str(GOLDEN / "figure10.asa"))[1] == plain[1]
    assert cli("diff", str(listing), str(rendered)) == (0, "", "")


# 14. clear messages -----------------------------------------------------------------------
def test_14_messages_say_what_is_wrong(tmp_path):
    deck = str(DECKS / "example.dat")
    status, _, err = cli("run", deck, "-o", "")
    assert status == 2 and one_error(err) == "sielaff: -o '': an empty file name"
    status, _, err = cli("run", deck, "-o", "/proc/version")
    assert status == 2 and "no new file can be made in /proc" in one_error(err)
    afile = tmp_path / "afile"
    afile.write_text("x")
    if __import__("importlib").util.find_spec("matplotlib"):
        status, _, err = cli("plot", deck, "-o", str(afile))
        assert status == 2 and "is a file, not a folder" in one_error(err)
    loop = tmp_path / "loop"
    loop.symlink_to(loop)
    status, _, err = cli("run", str(loop))
    assert status == 2 and "no such deck" not in err and "symbolic links" in one_error(err)


@pytest.mark.parametrize("field, words", [
    ("    +-4.", "not a number (two signs)"),
    ("   1E-99", "with no decimal point F8.4 reads the mantissa 1 as 0.0001: write 1.E-99"),
])
def test_14_card_messages(tmp_path, field, words):
    deck = write_deck(tmp_path, cards((6, field)))
    status, _, err = cli("run", deck)
    assert status == 2 and words in one_error(err)


# 15. table with many range cards --------------------------------------------------------------
def test_15_many_small_range_cards_share_engine_calls(tmp_path):
    from sielaff.tools import table

    lines = EXAMPLE_LINES[:6] + [f"{k / 10:8.1f}     1.0{k / 10:8.1f}" for k in range(3000)]
    deck = write_deck(tmp_path, lines)
    calls = []
    real = table.engine.analyze

    def counting(mechanism, ath2, *a, **k):
        calls.append(len(ath2))
        return real(mechanism, ath2, *a, **k)

    with mock.patch.object(table.engine, "analyze", counting):
        status, out, _ = cli("table", deck, "--only", "kinematics")
    assert status == 0 and out.count("\n") == 3001
    assert calls.count(3000) == 1  # one engine call for the 3000 one-position cards
    assert len(calls) == 2  # and one over a revolution, the check for values past 1E99
    rows = out.splitlines()[1:]
    assert rows[0].startswith("7,0.0,") and rows[-1].startswith("3006,299.9,")


EXAMPLE_LINES = (DECKS / "example.dat").read_text().splitlines()
