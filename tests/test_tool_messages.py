"""Issue 22's smaller points, each with a test: the past-THMAX quirk's wording, one form
of the missing-extra hint, the sweep's status line."""

from __future__ import annotations

import re

import pytest

from conftest import DECKS, ROOT
from procs import run


def sielaff(*argv, timeout: float = 300):
    """``python -m sielaff argv`` (forked from the worker's zygote: tests/procs.py)."""
    return run(argv, timeout=timeout, text=True)


PARAMETERS = "".join((DECKS / "example.dat").read_text().splitlines(keepends=True)[:6])


def test_past_thmax_by_roundoff_shows_the_digits_that_differ(tmp_path):
    """THZERO 0, DELTA 0.1, THMAX 100.1: the last sheet is 100.10000000000001, past THMAX by
    roundoff; the quirk must not read "100.1 is past THMAX = 100.1"."""
    deck = tmp_path / "q.dat"
    deck.write_text(PARAMETERS + "     0.0     0.1   100.1\n")
    r = sielaff("run", deck, "-o", tmp_path / "q.asa", timeout=300)
    assert r.returncode == 0, r.stderr
    line = next(x for x in r.stderr.splitlines() if "is past THMAX" in x)
    assert "THETA 2 = 100.10000000000001 is past THMAX = 100.1 (by roundoff" in line
    a, b = re.search(r"THETA 2 = (\S+) is past THMAX = (\S+)", line).groups()
    assert a != b
    # a sheet clearly past keeps the short form
    deck.write_text(PARAMETERS + "    10.0    10.0   360.0\n")
    r = sielaff("run", deck, "-o", tmp_path / "q.asa", timeout=300)
    assert "THETA 2 = 370 is past THMAX = 360:" in r.stderr


def test_missing_extra_hints_agree():
    """Every hint for a missing optional extra says the README's form, pip install -e
    ".[extra]", never pip install 'sielaff[extra]'."""
    hints = []
    for path in (ROOT / "src" / "sielaff").rglob("*.py"):
        text = path.read_text()
        hints += [(path.name, h) for h in re.findall(r"pip install[^\n]*", text)]
    assert hints
    raised = [(n, h) for n, h in hints if "sielaff[" in h and "``" not in h]
    assert not raised, raised


def test_sweep_status_says_where_it_ran(tmp_path):
    r = sielaff("sweep", DECKS / "si.toml", "--workers", "1", "-o",
                tmp_path / "s.csv", timeout=300)
    assert r.returncode == 0, r.stderr
    assert "in this process" in r.stderr and "on process" not in r.stderr


def test_port_refuses_another_arithmetic(tmp_path):
    r = sielaff("run", DECKS / "example.dat", "--port", "--arith", "float32",
                "-o", tmp_path / "x.asa", timeout=300)
    assert r.returncode == 2 and "--port is float64 only" in r.stderr
    assert not (tmp_path / "x.asa").exists()


def test_plot_at_without_linkage_is_refused(tmp_path):
    for option in (["--at", "90"], ["--point", "3:4:0"]):
        r = sielaff("plot", DECKS / "example.dat", "-o", tmp_path / "p",
                    *option, timeout=300)
        assert r.returncode == 2 and "add --linkage" in r.stderr, r.stderr
        assert not (tmp_path / "p").exists() or not any((tmp_path / "p").iterdir())


def test_plot_linkage_and_bearings_writes_both(tmp_path):
    r = sielaff("plot", DECKS / "example.dat", "-o", tmp_path / "p",
                "--linkage", "--bearings", timeout=600)
    assert r.returncode == 0, r.stderr
    names = sorted(p.name for p in (tmp_path / "p").iterdir())
    assert names == ["bearings.png", "linkage.png"]
    assert r.stdout.split() == [str(tmp_path / "p" / n) for n in ("linkage.png", "bearings.png")]


def test_max_sheets_warns_on_the_fast_path_as_on_the_port(tmp_path):
    """The example asks for 37 sheets: --max-sheets 2 and 36 warn on both paths; 37 does
    not (nothing was cut)."""
    for port in ([], ["--port"]):
        for n, warned in ((2, True), (36, True), (37, False)):
            r = sielaff("run", DECKS / "example.dat", "--max-sheets", str(n),
                        *port, "-o", tmp_path / "x.asa", timeout=300)
            assert r.returncode == 0, r.stderr
            text = f"stopped after {n} sheets (--max-sheets)"
            assert (text in r.stderr) == warned, (port, n, r.stderr)


def test_diff_of_two_real_listings_ends_in_the_differences(tmp_path):
    """run --tex 150 against run: many fields differ, some by more digits than Decimal's
    context holds; diff lists them and exits 1 (listings differ), no traceback."""
    a, b = tmp_path / "a.asa", tmp_path / "b.asa"
    for path, extra in ((a, []), (b, ["--tex", "150"])):
        r = sielaff("run", *extra, DECKS / "example.dat", "-o", path, timeout=300)
        assert r.returncode == 0, r.stderr
    r = sielaff("diff", b, a, timeout=300)
    assert r.returncode == 1, r.stderr
    assert "Traceback" not in r.stderr and "InvalidOperation" not in r.stdout + r.stderr
    assert "units in the last digit" in r.stdout


def test_quirks_are_numbered_in_order():
    text = (ROOT / "docs" / "quirks.md").read_text()
    numbers = [int(n) for n in re.findall(r"^\| (\d+) \|", text, re.M)]
    assert numbers == list(range(1, len(numbers) + 1)) and len(numbers) >= 11


def test_design_md_points_to_an_si_section_that_exists():
    design = (ROOT / "docs" / "design.md").read_text()
    conventions = (ROOT / "docs" / "conventions.md").read_text()
    assert "SI" in design and "conventions.md" in design
    assert "\n## SI\n" in conventions and "N m" in conventions and "kg m^2" in conventions


def test_check_json_and_output_file(tmp_path):
    import json

    for kind, turns in (("triple-rocker", False), ("double-crank", True)):
        r = sielaff("check", DECKS / f"{kind}.toml", "--format", "json", timeout=300)
        assert r.returncode == 0, r.stderr
        data = json.loads(r.stdout)
        assert data["kind"] == kind and data["turns_fully"] is turns and data["status"] == 0
        assert len(data["toggles_deg"]) == (0 if turns else 2)
        assert any("Verdict: usable" in line for line in data["report"])
    out = tmp_path / "c.txt"
    r = sielaff("check", DECKS / "example.dat", "-o", out, timeout=300)
    assert r.returncode == 0 and r.stdout == "" and "Verdict: usable" in out.read_text()
    r = sielaff("check", DECKS / "example.dat", "-o", "-", timeout=300)
    assert r.stdout == out.read_text()


@pytest.mark.parametrize("at", ["nan", "inf", "1e99"])
def test_report_at_an_angle_that_is_not_one_is_refused(tmp_path, at):
    """``report --at nan`` used to exit 0 (issue 32): the option's type refuses it, exit 2,
    and no page is written."""
    r = run(["report", str(DECKS / "example.dat"), "-o", str(tmp_path / "r.html"),
             "--at", at], text=True)
    assert r.returncode == 2 and "--at" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "r.html").exists()


def test_length_options_name_their_unit():
    """Issue 33: --radius2, --radius4 and --point gave no unit."""
    import subprocess
    import sys

    for command, options in (("balance", ("--radius2", "--radius4")), ("plot", ("--point",))):
        out = subprocess.run([sys.executable, "-m", "sielaff", command, "--help"],
                             capture_output=True, text=True, timeout=60).stdout
        flat = " ".join(out.split())
        for option in options:
            part = flat.split("options:", 1)[1].split(option + " ", 1)[1][:160]
            assert "in, or m in SI" in part, (option, part)
