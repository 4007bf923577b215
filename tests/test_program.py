"""The line-by-line port: ARCCOS, VECTOR, and the main program's control flow."""

from __future__ import annotations

import io
import math

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

import procs
from conftest import DECKS
from sielaff.emulator.arithmetic import Float64
from sielaff.emulator.cards import parse_deck
from sielaff.emulator.program import NotCrankRocker, Program
from sielaff.emulator.run import run, sheet_values

#: Every test here compares printed digits (tests/test_ulp_immunity.py re-runs them).
pytestmark = pytest.mark.pinned

#: ARCCOS stops when two partial sums differ by less than 1E-8; the tail of
#: the series past that point is below 1E-8 times a factor < 2 for |x| <= 0.7
#: (ratio of terms <= 0.49), and the reflected branch adds only roundoff.
#: Measured worst case on a 2e5-point grid: 8.7E-9.
ARCCOS_BOUND = 2e-8

P = Program(Float64())


def ulps_inside(x: float, n: int) -> float:
    for _ in range(n):
        x = math.nextafter(x, 0.0)
    return x


@given(st.floats(min_value=-1.0, max_value=1.0))
@example(1.0)
@example(-1.0)
@example(0.7)
@example(-0.7)
@example(0.0)
@example(ulps_inside(1.0, 3))
@example(ulps_inside(-1.0, 3))
@example(math.nextafter(0.7, 1.0))
@example(math.nextafter(-0.7, -1.0))
def test_arccos_against_math_acos(x):
    assert abs(P.ARCCOS(x) - math.acos(x)) < ARCCOS_BOUND


def test_arccos_branches_are_the_listings():
    # exactly 0.7 takes the direct series (ABS(XX).LE.0.7); just above takes the reflection
    assert abs(P.ARCCOS(0.7) - math.acos(0.7)) < ARCCOS_BOUND
    assert abs(P.ARCCOS(-0.7) - math.acos(-0.7)) < ARCCOS_BOUND


def test_arccos_past_one_takes_sqrt_of_abs_and_reports_it():
    messages = []
    prog = Program(Float64(on_error=messages.append))
    x = 1.0 + 1e-12
    got = prog.ARCCOS(x)
    assert messages and "SQRT of negative" in messages[0]
    # SQRT(ABS(1-X*X)) ~ 1.4e-6: the result is that small angle, not NaN
    assert 0 < got < 2e-6


finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False).filter(
    lambda v: v == 0 or abs(v) > 1e-6)


@given(finite, finite)
@example(0.0, 0.0)
@example(3.0, 0.0)
@example(-3.0, 0.0)
@example(0.0, 2.0)
@example(0.0, -2.0)
@example(1.0, 1.0)
@example(-1.0, 1.0)
@example(-1.0, -1.0)
@example(1.0, -1.0)
def test_vector_against_hypot_and_atan2(x, y):
    vect, direct = P.VECTOR(x, y)
    assert vect == pytest.approx(math.hypot(x, y), rel=1e-12, abs=1e-300)
    expected = math.degrees(math.atan2(y, x)) % 360.0 if (x or y) else 0.0
    # VECTOR's own PI (3.14159265) and RAD (57.2957795) are 8-9 digit constants
    diff = abs(direct - expected)
    assert min(diff, 360.0 - diff) < 2e-6 * max(1.0, expected)
    assert 0.0 <= direct < 360.0 + 1e-5


@pytest.mark.parametrize("x, y, direction", [
    (1.0, 0.0, 0.0), (0.0, 1.0, 90.0), (-1.0, 0.0, 180.0), (0.0, -1.0, 270.0), (0.0, 0.0, 0.0)])
def test_vector_on_the_axes(x, y, direction):
    assert P.VECTOR(x, y)[1] == pytest.approx(direction, abs=1e-5)


def _deck(r1=12.0, r2=4.0, r3=16.0, r4=12.0, ranges=((10.0, 10.0, 360.0),)) -> str:
    def card(*v):
        return "".join(f"{x:8.4f}" for x in v)
    cards = [card(3, 8, 6), card(0, .5, .4), card(r1, r2, r3, r4), card(0, -15, 15),
             card(2, 8, 6), card(50)] + [card(*r) for r in ranges]
    return "\n".join(cards) + "\n"


def test_trailing_sheet_and_case_ii_quirks_are_noticed(example_deck):
    notices = []
    n = run(example_deck, io.StringIO(), notice=lambda k, t: notices.append((k, t)))
    assert n == 37
    kinds = [k for k, _ in notices]
    assert kinds == ["case-ii", "past-thmax"]
    assert "THETA 2 = 370" in notices[0][1] and "Case II" in notices[0][1]


def test_the_370_sheet_is_the_case_ii_branch_not_the_10_sheet(example_deck):
    sheets = list(sheet_values(example_deck))
    first, last = sheets[0], sheets[-1]
    assert last["ATH2"] == pytest.approx(370.0)
    assert abs(last["ATH3"] - first["ATH3"]) > 1.0  # Case II at 10 degrees: wrong coupler angle


def test_thzero_equal_thmax_prints_two_sheets():
    deck = parse_deck(_deck(ranges=((40.0, 10.0, 40.0),)))
    assert [s["ATH2"] for s in sheet_values(deck)] == [40.0, 50.0]


def test_several_range_cards_are_read_until_the_deck_ends():
    deck = parse_deck(_deck(ranges=((10.0, 10.0, 20.0), (100.0, 5.0, 105.0))))
    assert [s["ATH2"] for s in sheet_values(deck)] == [10.0, 20.0, 30.0, 100.0, 105.0, 110.0]


def test_not_a_crank_rocker_prints_the_1966_message():
    deck = parse_deck(_deck(r1=30.0))  # C = 7.5 > A+B-1 = 6
    out = io.StringIO()
    with pytest.raises(NotCrankRocker):
        run(deck, out)
    assert out.getvalue() == " THIS IS NOT A CRANK ROCKER MECHANISM\n"


def test_cli_not_a_crank_rocker_exits_3(tmp_path):
    path = tmp_path / "bad.dat"
    path.write_text(_deck(r2=14.0))
    proc = procs.run(["run", path], text=True)
    assert proc.returncode == 3
    assert proc.stdout == " THIS IS NOT A CRANK ROCKER MECHANISM\n"
    assert proc.stderr.count("\n") == 1
    assert "card 3" in proc.stderr and "shortest link" in proc.stderr


def test_cli_run_example_and_diff_against_golden(tmp_path):
    out = tmp_path / "example.asa"
    proc = procs.run(["run", DECKS / "example.dat", "-o", out], text=True)
    assert proc.returncode == 0
    assert "Case II" in proc.stderr and "370" in proc.stderr
    assert out.read_text().count("\n1\n") == 37
    golden = DECKS.parent / "golden" / "figure11.asa"
    proc = procs.run(["diff", out, golden], text=True)
    assert proc.returncode == 1
    assert proc.stdout.splitlines() == [
        "THETA 2 = 50.0: VA (VEL A): got .2000E 03, golden .1999E 03 (+1 unit in the last digit)",
        "THETA 2 = 50.0: DAG2 (ACC G2 direction): got 230.0, golden 229.9 "
        "(+1 unit in the last digit)",
        "THETA 2 = 50.0: DAA (ACC A direction): got 230.0, golden 229.9 "
        "(+1 unit in the last digit)",
    ]
    same = procs.run(["diff", golden, golden], text=True)
    assert same.returncode == 0 and same.stdout == ""


def test_render_gives_form_feeds(tmp_path):
    proc = procs.run(["run", DECKS / "example.dat", "--render"], text=True)
    assert proc.returncode == 0
    assert proc.stdout.count("\f") == 37
    assert "\n" + " " * 17 + "THETA 2     THETA 3     THETA 4\n" in proc.stdout


def test_kinematics_only_drops_statements_133_to_202_and_their_writes(example_deck,
                                                                       example_listing):
    from sielaff.emulator.listing import parse_listing

    out = io.StringIO()
    assert run(example_deck, out, kinematics_only=True) == 37
    text = out.getvalue()
    for heading in ("F 3 ON 2", "SHAKE", "DRIVING TORQ"):
        assert heading not in text
    assert "EX TORQ ON 4" in text  # statement 74 is outside 133-202
    kin, full = parse_listing(text), parse_listing(example_listing)
    assert len(kin) == len(full) == 37
    for k, f in zip(kin, full):
        assert set(k.fields) == set(f.fields) - {
            "FA32", "FB34", "FOA", "FOB", "DFA32", "DFB34", "DFOA", "DFOB",
            "SHAK", "SHAKX", "SHAKY", "DSHAK", "TORQ"}
        assert all(k.fields[n].text == f.fields[n].text for n in k.fields)



def test_not_a_crank_rocker_stops_before_an_endless_range_would_loop(tmp_path, capsys):
    """The 1966 program tests the linkage before it loops: exit 3, not the DELTA refusal."""
    from sielaff.cli import main

    bad = tmp_path / "bad.dat"
    bad.write_text(_deck(r1=30.0, ranges=((10.0, 0.0, 360.0),)))
    assert main(["run", str(bad)]) == 3
    out, err = capsys.readouterr()
    assert out == " THIS IS NOT A CRANK ROCKER MECHANISM\n"
    assert "card 3" in err and "DELTA" not in err
    endless = tmp_path / "endless.dat"
    endless.write_text(_deck(ranges=((10.0, 0.0, 360.0),)))
    for command in (["run"], ["table"], ["plot", "-o", str(tmp_path / "plots")]):
        assert main([*command[:1], str(endless), *command[1:]]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "card 7, columns 9-16" in err and "never end" in err
    # the modern tools take any four-bar: for them the endless range is what is wrong
    assert main(["table", str(bad)]) == 2
    err = capsys.readouterr().err  # a note naming the kind and its arcs, then the refusal
    assert "triple-rocker" in err and err.splitlines()[-1].endswith("the range never ends")
