"""``sielaff check``: every value it prints for the example, computed here independently."""

from __future__ import annotations

import io
import math
import re
from unittest import mock

import numpy as np
import pytest

import procs
from conftest import DECKS
from sielaff.cli import main
from sielaff.emulator.cards import parse_deck, read_deck
from sielaff.emulator.program import SheetLimit
from sielaff.emulator.run import run, sheet_values
from sielaff.engine import OUTPUTS, analyze
from sielaff.mechanism import EXAMPLE
from sielaff.tools.check import check_deck, range_sheets

#: Every test here compares printed digits (tests/test_ulp_immunity.py re-runs them).
pytestmark = pytest.mark.pinned

# A number as printed: not part of a name (R2, TH2D, ATH2.GT.THMAX).
NUM = re.compile(r"(?<![\w.])-?(?:\d[\d,]*(?:\.\d*)?|\.\d+)(?:e[-+]?\d+)?(?![\w])")

def _flat(text: str) -> str:
    return " ".join(text.split())


def skeleton(text: str) -> str:
    """The text with every number replaced by #, whitespace (and line wraps) normalised."""
    return NUM.sub("#", _flat(text))


def numbers(text: str) -> list[float]:
    return [float(x.replace(",", "")) for x in NUM.findall(_flat(text))]


def golden_max(f, lo: float, hi: float) -> float:
    """Where f is largest on [lo, hi] (golden-section search to 1e-9 degree)."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo, hi
    while b - a > 1e-9:
        c, d = b - g * (b - a), a + g * (b - a)
        if f(c) > f(d):
            b = d
        else:
            a = c
    return 0.5 * (a + b)


def peak(name: str, sign: float = 1.0) -> tuple[float, float, float]:
    """(THETA 2, value, direction) of the largest sign*name over a revolution, independently."""
    th = np.linspace(0.0, 360.0, 36001)
    v = sign * analyze(EXAMPLE, th, [name])[name]
    t0 = th[int(np.argmax(v))]
    at = golden_max(lambda t: sign * float(analyze(EXAMPLE, t, [name])[name]),
                    t0 - 0.02, t0 + 0.02) % 360.0
    value = float(analyze(EXAMPLE, at, [name])[name])
    d = "D" + name
    direction = float(analyze(EXAMPLE, at, [d])[d]) if d in OUTPUTS else 0.0
    return at, value, direction


@pytest.fixture(scope="module")
def example_report():
    out, err = io.StringIO(), io.StringIO()
    with mock.patch("sys.stdout", out), mock.patch("sys.stderr", err):
        status = main(["check", str(DECKS / "example.dat")])
    return status, out.getvalue(), err.getvalue()


def expected_example_report(example_listing: str) -> str:
    """The report for decks/example.dat, every number computed without sielaff.tools.check."""
    # The sheets the 1966 listing prints, and the notices of the run, from the emulator.
    deck = read_deck(DECKS / "example.dat")
    angles = [s["ATH2"] for s in sheet_values(deck, kinematics_only=True)]
    assert example_listing.count("\n1\n") + example_listing.startswith("1\n") == len(angles)
    # Grashof, by hand: links 12, 4, 16, 12.
    s, l, p, q = 4.0, 16.0, 12.0, 12.0
    A, B, C = 16 / 4, 12 / 4, 12 / 4
    # Transmission angle from the engine on a fine grid.
    th = np.linspace(0.0, 360.0, 36001)
    gamma = analyze(EXAMPLE, th, ["GAMMA"])["GAMMA"]
    g_min, g_max = gamma.min(), gamma.max()
    at_gmin, at_gmax = th[np.argmin(gamma)], th[np.argmax(gamma)]
    toggle = min(g_min, 180.0 - g_max)
    loads = {n: peak(n) for n in ("FOA", "FOB", "FA32", "FB34")}
    t_hi, t_lo = peak("TORQ"), peak("TORQ", -1.0)
    power = max(abs(t_hi[1]), abs(t_lo[1])) * 50.0
    # Cycle work by Simpson's rule on a 0.01-degree grid.
    torq = analyze(EXAMPLE, th, ["TORQ"])["TORQ"]
    h = math.radians(0.01)
    w = np.ones_like(th)
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    work = float(np.sum(w * torq) * h / 3.0)
    abs_work = float(np.sum(w * np.abs(torq)) * h / 3.0)
    assert abs(work) <= 1e-12 * abs_work  # so check may print it as zero to roundoff
    zero = f"0 in-lb to roundoff (|W| < {1e-12 * abs_work:.0e} in-lb)"
    shake = peak("SHAK")
    sx_hi, sx_lo = peak("SHAKX")[1], peak("SHAKX", -1.0)[1]
    sy_hi, sy_lo = peak("SHAKY")[1], peak("SHAKY", -1.0)[1]
    rows = "\n".join(
        f"{heading} ({n}) at {where} {loads[n][1]} lb at THETA 2 = {loads[n][0]} deg, "
        f"direction {loads[n][2]} deg"
        for n, heading, where in (("FOA", "F 2 ON 1", "O2"), ("FOB", "F 4 ON 1", "O4"),
                                  ("FA32", "F 3 ON 2", "A"), ("FB34", "F 3 ON 4", "B")))
    return f"""
sielaff check: {DECKS / "example.dat"}

Deck: 6 parameter cards and 1 range card (7 cards); units in-lb-sec
  card 1  W2    =       3.0 lb           weight of link 2 (crank)
          W3    =       8.0 lb           weight of link 3 (coupler)
          W4    =       6.0 lb           weight of link 4 (rocker)
  card 2  ZI2   =       0.0 in-lb-sec^2  moment of inertia of link 2 (used only when TH2DD != 0)
          ZI3   =       0.5 in-lb-sec^2  moment of inertia of link 3 (about G3)
          ZI4   =       0.4 in-lb-sec^2  moment of inertia of link 4 (about G4)
  card 3  R1    =      12.0 in           frame, O2 to O4
          R2    =       4.0 in           crank, O2 to A
          R3    =      16.0 in           coupler, A to B
          R4    =      12.0 in           rocker, O4 to B
  card 4  ADEL2 =       0.0 deg          line O2-G2, from link 2
          ADEL3 =     -15.0 deg          line A-G3, from link 3
          ADEL4 =      15.0 deg          line O4-G4, from link 4
  card 5  RG2   =       2.0 in           O2 to G2
          RG3   =       8.0 in           A to G3
          RG4   =       6.0 in           O4 to G4
  card 6  TH2D  =      50.0 rad/sec      crank speed (constant)
  card 7 THZERO = 10.0 deg, DELTA = 10.0 deg, THMAX = 360.0 deg
          1966 listing: {len(angles)} sheets, THETA 2 = {angles[0]} to {angles[-1]}

Linkage
  lengths: frame R1 = 12.0 in, crank R2 = 4.0 in, coupler R3 = 16.0 in, rocker R4 = 12.0 in
  Grashof sum: s + l = {s} + {l} = {s + l} in < p + q = {p} + {q} = {p + q} in
    (margin {p + q - s - l} in)
    a Grashof linkage: the shortest link turns fully
  shortest link: crank R2 = 4.0 in, so a crank-rocker
  crank-rocker conditions (report p. 4; statements 45-51), A = R3/R2, B = R4/R2, C = R1/R2:
    A = {A} > 1 margin {A - 1} ok
    B = {B} > 1 margin {B - 1} ok
    C = {C} > 1 margin {C - 1} ok
    C = {C} < A + B - 1 = {A + B - 1} margin {A + B - 1 - C} ok
    C = {C} > |B - A| + 1 = {abs(B - A) + 1} margin {C - abs(B - A) - 1} ok

One revolution (modern engine, TEX = 0)
  THETA 2 = 0 to 360 on a 0.1 deg grid, peaks refined to 0.001 deg
  transmission angle GAMMA (between coupler and rocker, at B):
    minimum {g_min} deg at THETA 2 = {at_gmin} deg
    maximum {g_max} deg at THETA 2 = {at_gmax} deg
    closest approach to toggle (GAMMA = 0 deg): {toggle} deg, at THETA 2 = {at_gmin} deg
    outside the usual 40-140 deg guideline: the rocker is driven poorly near THETA 2 = 0 deg
  peak bearing loads:
{rows}
  driving torque TORQ:
    largest {t_hi[1]} in-lb at THETA 2 = {t_hi[0]} deg
    most negative {t_lo[1]} in-lb at THETA 2 = {t_lo[0]} deg
    peak power |TORQ| TH2D = {power} in-lb/sec = {power / 6600} hp
  cycle work, integral of TORQ d(THETA 2) over a revolution: {zero}
    (integral of |TORQ|: {abs_work} in-lb): zero, as it must be with TEX = 0
  shaking force SHAKE: peak {shake[1]} lb at THETA 2 = {shake[0]} deg
    X component from {sx_lo} to {sx_hi} lb, Y component from {sy_lo} to {sy_hi} lb

1966 quirks this deck triggers in sielaff run
  (docs/quirks.md; the modern engine has none of them)
  card 7: trailing sheet past THMAX: the last sheet is THETA 2 = {angles[-1]} > THMAX = 360.0
    (the 1966 loop prints a sheet before testing ATH2.GT.THMAX)
  card 7: 1 sheet past one revolution, where the 1966 program takes the Case II branch
    (TH2 >= PI): THETA 2 = {angles[-1]}; its THETA 3, THETA 4 and all that follows are not the
    mechanism's

Verdict: usable
"""


def test_example_report_every_value(example_report, example_listing):
    status, out, err = example_report
    assert status == 0 and err == ""
    expected = expected_example_report(example_listing)
    # The design answers (flywheel, bearings) have their own tests: tests/test_design.py.
    start = out.index("  flywheel on the crank shaft")
    out = out[:start] + out[out.index("\n1966 quirks"):]
    assert skeleton(out) == skeleton(expected)
    got, want = numbers(out), numbers(expected)
    assert len(got) == len(want)
    for g, w in zip(got, want):
        # Printed to 0.1 (0.01 for GAMMA, whole in-lb/sec for the power); the
        # peaks here are exact to 1e-9 degree, those of check to 0.001.
        assert g == pytest.approx(w, abs=0.051, rel=1e-4), (g, w)


def test_example_lists_trailing_370_and_zero_cycle_work(example_report):
    _, out, _ = example_report
    text = _flat(out)
    assert "the last sheet is THETA 2 = 370.0 > THMAX = 360.0" in text
    work = float(re.search(r"over a revolution: (\S+) in-lb", text).group(1))
    assert work == 0.0 and "to roundoff (|W| < 3e-09 in-lb)" in text
    assert "zero, as it must be with TEX = 0" in text


def test_example_quirks_are_the_emulators_notices(example_report):
    """The quirks check predicts are those a run reports (the run's notices)."""
    kinds: list[tuple[str, str]] = []
    run(read_deck(DECKS / "example.dat"), io.StringIO(), notice=lambda k, t: kinds.append((k, t)))
    assert sorted(k for k, _ in kinds) == ["case-ii", "past-thmax"]
    assert all("370" in t for _, t in kinds)


# --------------------------------------------------------------------------
# Range cards: predicted without running, checked against the port
# --------------------------------------------------------------------------

RANGES = [
    (10.0, 10.0, 360.0), (0.0, 0.1, 1.0), (360.0, 1.0, 360.0), (90.0, 7.5, 100.0),
    (-30.0, 10.0, 20.0), (350.0, 3.0, 380.0), (100.0, 10.0, 50.0), (100.0, -5.0, 50.0),
    (-5.0, 0.3, 2.0), (0.1, 0.7, 5.0), (720.0, 45.0, 700.0), (-400.0, 90.0, 400.0),
]


def _deck(*ranges, params: str | None = None) -> str:
    text = params or (DECKS / "example.dat").read_text().splitlines(keepends=True)
    if not isinstance(text, str):
        text = "".join(text[:6])
    for r in ranges:
        text += "".join(f"{v:8.4f}" for v in r) + "\n"
    return text


@pytest.mark.parametrize("thzero, delta, thmax", RANGES)
def test_range_sheets_match_the_port(thzero, delta, thmax):
    deck = parse_deck(_deck((thzero, delta, thmax)))
    angles = [s["ATH2"] for s in sheet_values(deck, kinematics_only=True)]
    notes: list[tuple[str, str]] = []
    run(deck, io.StringIO(), notice=lambda k, t: notes.append((k, t)), kinematics_only=True)
    rs = range_sheets(*deck.ranges[0])
    assert rs.count == len(angles)
    assert (rs.first, rs.last) == (angles[0], angles[-1])
    past = [a for a in angles if a > 360.0]
    below = [a for a in angles if a < 0.0]
    assert rs.past_360 == ((len(past), past[0], past[-1]) if past else None)
    assert rs.below_0 == ((len(below), below[0], below[-1]) if below else None)
    assert sum(k == "case-ii" for k, _ in notes) == len(past)
    assert sum(k == "case-i" for k, _ in notes) == len(below)


def test_endless_range_predicted():
    assert range_sheets(10.0, 0.0, 360.0).count is None
    assert range_sheets(10.0, -1.0, 360.0).count is None
    assert range_sheets(10.0, -1.0, 5.0).count == 1


def test_huge_deck_is_predicted_not_run():
    """A million sheets: counts from the range card, the port runs only sheet_limit sheets."""
    deck = parse_deck(_deck((0.0, 0.0001, 100.0)))
    calls = []

    def fake_run(deck, out, notice=None, max_sheets=None, **kw):
        calls.append(max_sheets)
        raise SheetLimit(max_sheets)

    with mock.patch("sielaff.emulator.run.run", fake_run):
        rep = check_deck(deck, sheet_limit=50)
    assert calls == [50]
    text = _flat(rep.text)
    assert "1966 listing: 1,000,002 sheets, THETA 2 = 0.0 to 100.0001" in text
    assert "only the first 50 of the 1,000,002 sheets were run" in text
    assert rep.status == 0


# --------------------------------------------------------------------------
# Quirks and verdicts on other decks
# --------------------------------------------------------------------------


def check_cli(tmp_path, text: str, *flags: str) -> tuple[int, str, str]:
    path = tmp_path / "deck.dat"
    path.write_text(text)
    out, err = io.StringIO(), io.StringIO()
    with mock.patch("sys.stdout", out), mock.patch("sys.stderr", err):
        status = main(["check", str(path), *flags])
    return status, _flat(out.getvalue()), err.getvalue()


def test_thzero_equal_thmax_two_sheets(tmp_path):
    status, out, err = check_cli(tmp_path, _deck((40.0, 10.0, 40.0)))
    assert status == 0 and err == ""
    assert "card 7: THZERO = THMAX = 40.0 prints 2 sheets (THETA 2 = 40.0 to 50.0)" in out


def test_thzero_past_thmax_one_sheet(tmp_path):
    status, out, _ = check_cli(tmp_path, _deck((100.0, 10.0, 50.0)))
    assert status == 0
    assert "THZERO = 100.0 > THMAX = 50.0, yet the 1966 loop prints one sheet" in out


def test_below_zero_case_i(tmp_path):
    status, out, _ = check_cli(tmp_path, _deck((-20.0, 10.0, 0.0)))
    assert status == 0
    assert ("2 sheets below zero, where the 1966 program takes the Case I branch (TH2 < PI): "
            "THETA 2 = -20.0 to -10.0") in out


@pytest.mark.parametrize("delta", ["     0.0", "    -5.0"])
def test_endless_range_exit_2(tmp_path, delta):
    text = _deck((10.0, 10.0, 360.0)) + f"    10.0{delta}   360.0\n"
    status, out, err = check_cli(tmp_path, text)
    assert status == 2
    assert "card 8, columns 9-16: DELTA" in out and "the 1966 loop never ends" in out
    assert "Verdict: unusable" in out
    assert err.count("\n") == 1 and "card 8, columns 9-16" in err and "never end" in err


def test_not_crank_rocker_exit_3(tmp_path):
    lines = _deck((10.0, 10.0, 360.0)).splitlines(keepends=True)
    lines[2] = "    12.0    14.0    16.0    12.0\n"  # R2 is not the shortest
    # any four-bar is checked (a triple rocker here: exit 0, its kind's report) ...
    status, out, err = check_cli(tmp_path, "".join(lines))
    assert status == 0 and "triple-rocker" in out
    # ... and exit 3 is for an explicit crank-rocker requirement, as the 1966 program had
    status, out, err = check_cli(tmp_path, "".join(lines), "--crank-rocker")
    assert status == 3
    assert "A = 1.14286 > 1" in out and "FAILS" in out
    assert "shortest links: frame R1 and rocker R4 = 12.0 in" in out
    assert "One revolution" not in out  # no analysis of a mechanism the program refuses
    assert "Verdict: not a crank-rocker" in out
    assert err == f"{tmp_path / 'deck.dat'}: card 3: THIS IS NOT A CRANK ROCKER MECHANISM: " \
                  "B = R4/R2 = 0.857143 must be > 1 (the crank must be the shortest link)\n"


def test_unreadable_deck_exit_2(tmp_path):
    status, out, err = check_cli(tmp_path, "     3.0     x.0\n")
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and "card 1" in err


def test_missing_deck_exit_2(tmp_path):
    out, err = io.StringIO(), io.StringIO()
    with mock.patch("sys.stdout", out), mock.patch("sys.stderr", err):
        assert main(["check", str(tmp_path / "nope.dat")]) == 2
    assert "no such deck" in err.getvalue()


def test_tan_standin_and_library_notices_listed(tmp_path):
    """Quirks only a run shows are taken from the port's notices."""

    def fake_run(deck, out, notice=None, max_sheets=None, **kw):
        notice("tan-standin", "THETA 2 = 90: COS(TH3) is exactly 0, the 1966 program uses "
                              "TAN3 = 0.9E+25")
        for k in range(7):
            notice("library", f"SQRT of negative argument -1e-1{k}: using SQRT(ABS(X))")
        return 37

    with mock.patch("sielaff.emulator.run.run", fake_run):
        rep = check_deck(read_deck(DECKS / "example.dat"))
    text = _flat(rep.text)
    assert "THETA 2 = 90: COS(TH3) is exactly 0, the 1966 program uses TAN3 = 0.9E+25" in text
    assert text.count("SQRT of negative argument") == 5
    assert "... and 2 more like it" in text
    assert rep.status == 0


def test_failing_1966_arithmetic_exit_2():
    from sielaff.emulator.program import ProgramError

    def fake_run(deck, out, notice=None, max_sheets=None, **kw):
        raise ProgramError("TORQ is inf: the 1966 arithmetic overflows or divides by zero")

    with mock.patch("sielaff.emulator.run.run", fake_run):
        rep = check_deck(read_deck(DECKS / "example.dat"))
    assert rep.status == 2
    assert "the 1966 arithmetic fails: TORQ is inf" in rep.error
    assert "Verdict: unusable" in rep.text


def test_check_help_shows_example():
    r = procs.run(["check", "--help"], text=True)
    assert r.returncode == 0
    out = r.stdout
    assert "example:\n  sielaff check decks/example.dat" in out
