"""The progress bar: on a terminal for long runs, never otherwise."""

from __future__ import annotations

import io
import os
import pty
import subprocess
import sys

import pytest

from conftest import DECKS
from sielaff.emulator.cards import parse_deck, read_deck
from sielaff.emulator.run import run
from sielaff.tools.progress import Progress, estimate_sheets, run_progress

PARAMETERS = "".join((DECKS / "example.dat").read_text().splitlines(keepends=True)[:6])
LONG_DECK = PARAMETERS + "     0.0   0.001   360.0\n"  # 360,002 sheets


class Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


class Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_estimate_sheets():
    assert estimate_sheets(read_deck(DECKS / "example.dat")) == 37
    deck = parse_deck(PARAMETERS + "    40.0    10.0    40.0\n   100.0    10.0    50.0\n"
                      "     0.0     0.0   360.0\n")
    assert estimate_sheets(deck) == 2 + 1 + 0
    assert estimate_sheets(parse_deck(LONG_DECK)) == 360_002


def test_no_bar_when_not_a_terminal():
    stream, clock = io.StringIO(), Clock()
    bar = Progress(1000, "sielaff run", stream=stream, threshold=0.0, clock=clock)
    for n in range(1, 1001):
        clock.now += 1.0
        bar(n)
    bar.close()
    assert stream.getvalue() == ""


def test_no_bar_for_a_short_run():
    stream, clock = Tty(), Clock()
    with Progress(1000, "sielaff run", stream=stream, threshold=2.0, clock=clock) as bar:
        for n in range(1, 1001):
            clock.now += 0.001  # 1 s in all
            bar(n)
    assert stream.getvalue() == ""


def test_bar_for_a_long_run():
    stream, clock = Tty(), Clock()
    with Progress(1000, "sielaff run", stream=stream, threshold=2.0, clock=clock) as bar:
        for n in range(1, 1001):
            clock.now += 0.01  # 10 s in all
            bar(n)
        shown = stream.getvalue()
    assert "\rsielaff run: [" in shown
    assert "1,000 sheets" in shown and "%" in shown and "s left" in shown
    assert shown.count("\r") <= 110  # at most ten redraws a second
    assert stream.getvalue().endswith("\r\x1b[K")  # erased at the end


def test_wrap_erases_the_bar_before_a_notice():
    stream, clock = Tty(), Clock()
    bar = Progress(100, "sielaff run", stream=stream, threshold=0.0, clock=clock)
    clock.now = 1.0
    bar(10)
    notice = bar.wrap(lambda kind, text: stream.write(f"sielaff: 1966 quirk: {text}\n"))
    notice("case-ii", "THETA 2 = 370")
    assert stream.getvalue().endswith("\r\x1b[Ksielaff: 1966 quirk: THETA 2 = 370\n")


def test_environment_threshold(monkeypatch):
    monkeypatch.setenv("SIELAFF_PROGRESS_SECONDS", "0.5")
    assert Progress(10, "x").threshold == 0.5
    monkeypatch.setenv("SIELAFF_PROGRESS_SECONDS", "soon")
    assert Progress(10, "x").threshold == 2.0


def test_run_progress_total():
    deck = parse_deck(LONG_DECK)
    assert run_progress(deck, stream=io.StringIO()).total == 360_002
    assert run_progress(deck, 500, stream=io.StringIO()).total == 500


def test_emulator_reports_each_sheet(example_listing):
    counts: list[int] = []
    out = io.StringIO()
    deck = read_deck(DECKS / "example.dat")
    assert run(deck, out, progress=counts.append, vectorised=False) == 37
    assert counts == list(range(1, 38))
    assert out.getvalue() == example_listing
    # many sheets at a time: reported after each block, rising to the total
    counts.clear()
    assert run(deck, io.StringIO(), progress=counts.append) == 37
    assert counts and counts[-1] == 37 and counts == sorted(set(counts))


# --------------------------------------------------------------------------
# sielaff run, with stderr a pipe and a terminal
# --------------------------------------------------------------------------


@pytest.fixture
def long_deck(tmp_path):
    path = tmp_path / "long.dat"
    path.write_text(LONG_DECK)
    return path


def _env(seconds: str) -> dict[str, str]:
    return dict(os.environ, SIELAFF_PROGRESS_SECONDS=seconds)


def test_cli_no_progress_on_a_pipe(long_deck, tmp_path):
    r = subprocess.run([sys.executable, "-m", "sielaff", "run", str(long_deck), "--max-sheets",
                        "1500", "-o", str(tmp_path / "out.asa")],
                       capture_output=True, text=True, env=_env("0"))
    assert r.returncode == 0
    assert r.stderr == ("sielaff: warning: stopped after 1500 sheets (--max-sheets); "
                        "the deck asks for more\n")


def _run_on_pty(argv: list[str], env: dict[str, str]) -> tuple[int, bytes]:
    master, slave = pty.openpty()
    try:
        proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=slave, env=env)
    finally:
        os.close(slave)
    data = b""
    while True:
        try:
            chunk = os.read(master, 65536)
        except OSError:  # EIO: the child closed the terminal
            break
        if not chunk:
            break
        data += chunk
    os.close(master)
    return proc.wait(), data


def test_cli_progress_on_a_terminal(long_deck, tmp_path):
    status, data = _run_on_pty(
        [sys.executable, "-m", "sielaff", "run", str(long_deck), "--max-sheets", "1500",
         "-o", str(tmp_path / "out.asa")], _env("0"))
    assert status == 0
    text = data.decode()
    assert "sielaff run: [" in text and "/1,500 sheets" in text
    # The bar is erased before the warning, which stands on its own line.
    assert "\r\x1b[Ksielaff: warning: stopped after 1500 sheets" in text


def test_cli_no_progress_on_a_terminal_for_a_short_run(tmp_path):
    status, data = _run_on_pty(
        [sys.executable, "-m", "sielaff", "run", str(DECKS / "example.dat"),
         "-o", str(tmp_path / "out.asa")], _env("2"))
    assert status == 0
    assert b"sielaff run: [" not in data
