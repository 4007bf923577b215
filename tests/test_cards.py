"""The 4F8.4 card reader (sielaff.emulator.cards): F-format input rules and deck errors."""

from __future__ import annotations

import math
from decimal import Decimal
from pathlib import Path

import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from sielaff.emulator.cards import (
    Deck,
    DeckError,
    Range,
    parse_card,
    parse_deck,
    read_deck,
    read_field,
    read_field_decimal,
)
from sielaff.mechanism import EXAMPLE, FIELD_NAMES

EXAMPLE_DECK = Path(__file__).resolve().parents[1] / "decks" / "example.dat"


def card(*fields: str, seq: str = "") -> str:
    """One card: each field right-justified in 8 columns, ``seq`` in columns 73-80."""
    text = "".join(f.rjust(8) for f in fields)
    return text.ljust(72) + seq if seq else text


PARAMS = [card("3.0", "8.0", "6.0"), card("0.0", "0.5", "0.4"),
          card("12.0", "4.0", "16.0", "12.0"), card("0.0", "-15.0", "15.0"),
          card("2.0", "8.0", "6.0"), card("50.0")]
RANGE = card("10.0", "10.0", "360.0")


def deck(*cards: str, end: str = "\n") -> str:
    return "\n".join(cards) + end


def error(text: str | bytes) -> DeckError:
    with pytest.raises(DeckError) as info:
        parse_deck(text, "deck.dat")
    return info.value


# --------------------------------------------------------------- one F8.4 field

@pytest.mark.parametrize("field, value", [
    # blanks read as zeros: whole field, leading, trailing, inside
    ("        ", 0.0),
    ("       5", 0.0005),
    ("   30000", 3.0),
    ("00030000", 3.0),
    ("   1 5  ", 1.05),          # 00010500 / 10**4
    ("12      ", 1200.0),        # 12000000 / 10**4, the FORTRAN answer
    ("1 5.0   ", 105.0),
    ("  1.5   ", 1.5),           # trailing blanks after a point are fraction zeros
    # implied decimal (d = 4) and the explicit point that overrides it
    ("12345678", 1234.5678),
    ("     3.0", 3.0),
    ("      3.", 3.0),
    ("      .5", 0.5),
    ("123.4567", 123.4567),
    ("1234567.", 1234567.0),
    # signs, before or after leading blanks
    ("    +3.0", 3.0),
    ("    -3.0", -3.0),
    ("-    3.0", -3.0),
    ("-  30000", -3.0),
    ("  - 1.5 ", -1.5),
    ("  -0.0  ", 0.0),
    # exponents: E, D, lower case, signed, and the bare-sign FORTRAN form
    ("   1.5E2", 150.0),
    ("  1.5E+2", 150.0),
    ("  1.5E-2", 0.015),
    ("   1.5D2", 150.0),
    ("   1.5e2", 150.0),
    ("  1.5D-2", 0.015),
    ("   1.5+2", 150.0),
    ("   1.5-2", 0.015),
    ("  1.5E 2", 150.0),         # blank between E and its digit is a leading zero
    ("  1.5E -2"[1:], 0.015),    # " 1.5E -2": blanks before the exponent sign skipped
    ("  -15E-1", -0.00015),      # -.0015E-1
    # implied decimal with an exponent applies to the mantissa digits
    ("   15E+2", 0.15),          # .0015E+2
    ("    15E2", 0.15),
    ("     1E4", 1.0),
    ("   15000", 1.5),
    ("  15000-3", 0.0015),       # 9 columns: w = len(field)
    # the IBM 1410 range edges
    ("1.0E-100", 1e-100),
    (" 9.99E98", 9.99e98),
])
def test_read_field(field: str, value: float) -> None:
    got = read_field(field)
    assert got == value
    assert math.copysign(1.0, got) == math.copysign(1.0, value)


def test_read_field_exact_decimal() -> None:
    assert read_field_decimal("   1 5  ") == Decimal("1.05")
    assert str(read_field_decimal("12345678")) == "1234.5678"
    assert str(read_field_decimal("     0.1")) == "0.1"
    assert read_field_decimal("  1.5E-2") == Decimal("0.015")


def test_read_field_other_widths_and_d() -> None:
    assert read_field("  12345", d=2) == 123.45
    assert read_field("12345", d=0) == 12345.0
    assert read_field("        1234", d=4) == 0.1234
    assert read_field("  1.5", d=2) == 1.5


@pytest.mark.parametrize("field, reason", [
    ("  1.2.3 ", "not a number (two decimal points)"),
    ("  1.2.  ", "not a number (two decimal points)"),
    ("  abc   ", "not a number (character 'a')"),
    ("    1,5 ", "not a number (character ',')"),
    ("   1\t5 ", "not a number (character '\\t')"),
    ("   -    ", "not a number (a sign and no digits)"),
    ("       +", "not a number (a sign and no digits)"),
    ("   .    ", "not a number (no digits)"),
    ("   -.   ", "not a number (no digits)"),
    ("    E2  ", "not a number (no digits before the exponent)"),
    ("  --1.0 ", "not a number (two signs)"),
    ("   1.5E ", "not a number (exponent without digits)"),
    ("  1.5E+ ", "not a number (exponent without digits)"),
    ("    1.5-", "not a number (exponent without digits)"),
    ("  1.5E2.", "not a number (decimal point in the exponent)"),
    ("  1E2E3 ", "not a number (bad exponent 'E2E3')"),
    ("  1E+-2 ", "not a number (bad exponent 'E+-2')"),
    (" 9.9E+99", "out of range (9.9E+99; the IBM 1410 holds 1E-100 <= |x| < 1E99)"),
    ("1.0E-101", "out of range (1.0E-101; the IBM 1410 holds 1E-100 <= |x| < 1E99)"),
    # a left-justified exponent: its trailing blanks are zeros, 1.5E2000
    ("1.5E2   ", ("out of range (1.5E+2000; the IBM 1410 holds 1E-100 <= |x| < 1E99; "
                 "blanks in the exponent read as zeros: right-justify the field)")),
])
def test_read_field_errors(field: str, reason: str) -> None:
    with pytest.raises(ValueError) as info:
        read_field(field)
    assert str(info.value) == reason


def test_trailing_blank_after_exponent_is_a_zero() -> None:
    assert read_field("  1.5+2 ") == 1.5e20     # 1.5+20, as FORTRAN read it


# ------------------------------------------------------------------- one card

def test_parse_card_reads_only_the_listed_fields() -> None:
    text = card("1.0", "2.0", "3.0", "GARBAGE!")
    assert parse_card(text, 3, 1, "deck.dat") == [1.0, 2.0, 3.0]
    with pytest.raises(DeckError) as info:
        parse_card(text, 4, 1, "deck.dat")
    assert str(info.value) == ('deck.dat: card 1, columns 25-32: "GARBAGE!": '
                               "not a number (character 'G')")


def test_parse_card_ignores_columns_33_to_80() -> None:
    text = card("1.0", "2.0", "3.0", "4.0").ljust(32) + "x. junk 1.2.3 ".ljust(40) + "SIEL0010"
    assert len(text) == 80
    assert parse_card(text, 4, 3, "d") == [1.0, 2.0, 3.0, 4.0]


def test_parse_card_pads_short_lines() -> None:
    assert parse_card("     1.0    2", 4, 1, "d") == [1.0, 0.2, 0.0, 0.0]  # "    2   " = 00002000
    assert parse_card("", 4, 1, "d") == [0.0, 0.0, 0.0, 0.0]


def test_parse_card_error_attributes() -> None:
    text = card("1.0", "1.2.3 ")
    with pytest.raises(DeckError) as info:
        parse_card(text, 3, 3, "deck.dat")
    err = info.value
    assert str(err) == (
        'deck.dat: card 3, columns 9-16: "  1.2.3 ": not a number (two decimal points)')
    assert (err.path, err.card, err.columns, err.text) == ("deck.dat", 3, (9, 16), text.ljust(80))
    assert err.reason == "not a number (two decimal points)"


# ---------------------------------------------------------------- whole decks

def check_example(d: Deck) -> None:
    assert d.mechanism == EXAMPLE
    assert d.ranges == [(10.0, 10.0, 360.0)]
    assert d.ranges[0].THZERO == 10.0 and d.ranges[0].DELTA == 10.0 and d.ranges[0].THMAX == 360.0
    assert d.range_cards == [7]


def test_example_deck_file() -> None:
    lines = EXAMPLE_DECK.read_text().splitlines()
    assert len(lines) == 7 and all(len(line) == 80 for line in lines)
    assert [line[72:] for line in lines] == [f"SIEL{10 * i:04d}" for i in range(1, 8)]
    d = read_deck(EXAMPLE_DECK)
    check_example(d)
    assert d.path == str(EXAMPLE_DECK) and d.warnings == []
    assert d.exact == {name: Decimal(str(getattr(EXAMPLE, name))) for name in FIELD_NAMES}
    assert list(d.exact) == list(FIELD_NAMES)
    assert d.exact_ranges == [(Decimal("10.0"), Decimal("10.0"), Decimal("360.0"))]


def test_read_deck_keeps_the_name_given(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    Path("deck.dat").write_text(deck(*PARAMS))
    with pytest.raises(DeckError) as info:
        read_deck("deck.dat")
    assert str(info.value) == "deck.dat: deck ends before the first range card (THZERO DELTA THMAX)"
    with pytest.raises(DeckError) as info:
        read_deck(Path("missing.dat"))
    assert info.value.path == "missing.dat"
    assert str(info.value).startswith("missing.dat: cannot read the deck (")


def test_implied_decimal_deck() -> None:
    cards = ["   30000   80000   60000", "       0    5000    4000",
             "  120000   40000  160000  120000", "       0 -150000  150000",
             "   20000   80000   60000", "  500000", "  100000  100000 3600000"]
    check_example(parse_deck(deck(*cards)))


def test_multiple_range_cards() -> None:
    d = parse_deck(deck(*PARAMS, card("0.0", "5.0", "90.0"), card("90.0", "1.0", "100.0"),
                        card("180.0", "0.0", "180.0")))
    assert d.ranges == [Range(0.0, 5.0, 90.0), Range(90.0, 1.0, 100.0), Range(180.0, 0.0, 180.0)]
    assert d.range_cards == [7, 8, 9]


def test_unread_fields_and_sequence_numbers_ignored() -> None:
    def junk(text: str, n: int, seq: int) -> str:
        return (text[:8 * n].ljust(8 * n) + "NOT READ" * (4 - n)).ljust(72) + f"SIEL{seq:04d}"
    sizes = [3, 3, 4, 3, 3, 1, 3]
    d = parse_deck(deck(*(junk(c, n, 10 * i)
                          for i, (c, n) in enumerate(zip([*PARAMS, RANGE], sizes)))))
    check_example(d)
    assert d.warnings == []


def test_short_lines_are_padded() -> None:
    d = parse_deck(deck("     3.0", *PARAMS[1:], RANGE))
    assert (d.mechanism.W2, d.mechanism.W3, d.mechanism.W4) == (3.0, 0.0, 0.0)


def test_long_lines_warn() -> None:
    long = PARAMS[2].ljust(80) + "x" * 12
    d = parse_deck(deck(*PARAMS[:2], long, *PARAMS[3:], RANGE), "deck.dat")
    check_example(d)
    assert d.warnings == ["deck.dat: card 3: 92 columns, columns 81-92 ignored"]


def test_crlf_and_missing_final_newline() -> None:
    check_example(parse_deck(deck(*PARAMS, RANGE).replace("\n", "\r\n")))
    check_example(parse_deck(deck(*PARAMS, RANGE).replace("\n", "\r\n").encode()))
    check_example(parse_deck(deck(*PARAMS, RANGE, end="")))


def test_blank_line_inside_the_deck_is_a_card_of_zeros() -> None:
    d = parse_deck(deck(PARAMS[0], "", *PARAMS[2:], RANGE, "   ", RANGE))
    assert (d.mechanism.ZI2, d.mechanism.ZI3, d.mechanism.ZI4) == (0.0, 0.0, 0.0)
    assert d.ranges == [(10.0, 10.0, 360.0), (0.0, 0.0, 0.0), (10.0, 10.0, 360.0)]
    assert d.range_cards == [7, 8, 9]


def test_trailing_blank_lines_are_not_cards() -> None:
    d = parse_deck(deck(*PARAMS, RANGE) + "\n\n\r\n", "deck.dat")
    check_example(d)
    assert d.warnings == []
    d = parse_deck(deck(*PARAMS, RANGE, "", "        ", ""), "deck.dat")
    check_example(d)
    assert d.warnings == ["deck.dat: card 9: blank line at end of file ignored"]


def test_blanks_read_as_zeros_warn_when_they_change_the_value() -> None:
    d = parse_deck(deck(*PARAMS[:5], "50      ", card("10.0", "  1.5+2 ", "  360.0 ")), "deck.dat")
    assert d.mechanism.TH2D == 5000.0 and d.ranges == [(10.0, 1.5e20, 360.0)]
    assert d.warnings == [
        ('deck.dat: card 6, columns 1-8: "50      ": blanks read as zeros '
         "(5000.0000; right-justified it would be 0.0050)"),
        ('deck.dat: card 7, columns 9-16: "  1.5+2 ": blanks read as zeros '
         "(1.5E+20; right-justified it would be 1.5E+2)"),
    ]


@pytest.mark.parametrize("cards", range(1, 6))
def test_deck_ends_inside_the_parameter_cards(cards: int) -> None:
    names = ["W2 W3 W4", "ZI2 ZI3 ZI4", "R1 R2 R3 R4", "ADEL2 ADEL3 ADEL4", "RG2 RG3 RG4", "TH2D"]
    err = error(deck(*PARAMS[:cards]))
    assert str(err) == (f"deck.dat: card {cards + 1}: deck ends inside the parameter cards "
                        f"(expected {names[cards]})")
    assert (err.card, err.columns, err.text) == (cards + 1, None, None)


@pytest.mark.parametrize("text", ["", b"", "\n", "\n\n", "   \n  \r\n"])
def test_empty_deck(text: str | bytes) -> None:
    err = error(text)
    assert str(err) == "deck.dat: empty deck (no cards)" and err.card is None


@pytest.mark.parametrize("text", [deck(*PARAMS), deck(*PARAMS, end=""), deck(*PARAMS, "", "  ")])
def test_deck_ends_before_the_first_range_card(text: str) -> None:
    err = error(text)
    assert str(err) == "deck.dat: deck ends before the first range card (THZERO DELTA THMAX)"
    assert err.card is None


def test_bad_field_messages_name_card_and_columns() -> None:
    err = error(deck(*PARAMS[:2], card("12.0", "1.2.3 ", "16.0", "12.0"), *PARAMS[3:], RANGE))
    assert str(err) == (
        'deck.dat: card 3, columns 9-16: "  1.2.3 ": not a number (two decimal points)')
    err = error(deck(*PARAMS[:2], card("12.0", "4.0", "16.0", "12.O"), *PARAMS[3:], RANGE))
    assert str(err) == "deck.dat: card 3, columns 25-32: \"    12.O\": not a number (character 'O')"
    err = error(deck(*PARAMS, RANGE, card("10.0", "10.0", "-")))
    assert str(err) == (
        'deck.dat: card 8, columns 17-24: "       -": not a number (a sign and no digits)')
    assert (err.card, err.columns) == (8, (17, 24))


def test_tab_is_an_error() -> None:
    line = "    3.0\t8.0"
    err = error(deck(line, *PARAMS[1:], RANGE))
    assert str(err) == "deck.dat: card 1, column 8: tab character (cards have no tabs; use blanks)"
    assert (err.card, err.columns, err.text) == (1, (8, 8), line)
    # even in columns the READ never converts
    err = error(deck(*PARAMS, RANGE + "\tSIEL0070"))
    assert (err.card, err.columns) == (7, (len(RANGE) + 1,) * 2)


@pytest.mark.parametrize("as_bytes", [False, True])
def test_non_ascii_is_an_error(as_bytes: bool) -> None:
    text = deck(PARAMS[0], "     0.0     0\xe9", *PARAMS[2:], RANGE)
    err = error(text.encode() if as_bytes else text)
    assert str(err) == "deck.dat: card 2, column 15: non-ASCII character '\\xe9'"
    assert (err.card, err.columns) == (2, (15, 15))


def test_control_character_is_an_error() -> None:
    err = error(deck(*PARAMS[:3], "\x0c" + PARAMS[3], *PARAMS[4:], RANGE))
    assert str(err) == "deck.dat: card 4, column 1: control character '\\x0c'"
    err = error(deck(*PARAMS, RANGE).replace("\n", "\r", 1))   # a lone CR is not a line end
    assert str(err) == f"deck.dat: card 1, column {len(PARAMS[0]) + 1}: control character '\\r'"


def test_binary_is_an_error() -> None:
    data = deck(*PARAMS, RANGE).encode()
    assert str(error(data[:17] + b"\0" + data[17:])) == (
        "deck.dat: not a text deck (binary data at byte 17)")
    assert str(error(data[:40] + b"\xff\xfe" + data[40:])) == (
        "deck.dat: not a text deck (binary data at byte 40)")
    assert str(error(bytes(range(256)))) == "deck.dat: not a text deck (binary data at byte 0)"
    assert error("abc\0").card is None


# ------------------------------------------------------------------ properties

#: Decimals with 0-4 fraction digits that fit an 8-column field with their point
#: ("1234567.", "-999999.", "123.4567", "-12.3456", "-0.0005").
F84 = st.builds(lambda n, p: Decimal(n).scaleb(-p),
                st.integers(-999999, 9999999), st.integers(0, 4))


@given(F84)
def test_round_trip_explicit_point(value: Decimal) -> None:
    text = f"{value:f}"
    if "." not in text:
        text += "."
    assert len(text) <= 8
    assert read_field_decimal(text.rjust(8)) == value
    assert read_field(text.rjust(8)) == float(value)
    assert read_field(text.ljust(8)) == float(value)   # trailing blanks are fraction zeros


@given(F84)
def test_round_trip_implied_decimal(value: Decimal) -> None:
    digits = f"{value.scaleb(4):f}"                  # the value in units of 10**-4
    assume(len(digits) <= 8)
    assert read_field_decimal(digits.rjust(8)) == value
    assert read_field(digits.rjust(8)) == float(value)
    if value >= 0:
        assert read_field(digits.zfill(8)) == float(value)


@given(st.decimals(min_value=-99, max_value=99, places=1), st.integers(-9, 9),
       st.sampled_from(["E", "D", ""]))
def test_round_trip_exponent(mantissa: Decimal, exponent: int, letter: str) -> None:
    text = f"{mantissa:f}{letter}{exponent:+d}"
    assume(len(text) <= 8)
    assert read_field_decimal(text.rjust(8)) == mantissa.scaleb(exponent)


@given(st.text(alphabet="0123456789 ", min_size=8, max_size=8))
def test_digits_and_blanks_read_as_an_integer_of_ten_thousandths(text: str) -> None:
    assert read_field_decimal(text) == Decimal(int(text.replace(" ", "0"))).scaleb(-4)


@given(st.text(alphabet=" 0123456789+-.EDed", min_size=8, max_size=8))
def test_any_field_is_a_finite_number_or_a_value_error(text: str) -> None:
    try:
        value = read_field(text)
    except ValueError:
        return
    assert math.isfinite(value)


@given(st.lists(F84, min_size=20, max_size=20))
def test_deck_round_trip(values: list[Decimal]) -> None:
    fields = [f"{v:f}" if "." in f"{v:f}" else f"{v:f}." for v in values]
    sizes = [3, 3, 4, 3, 3, 1, 3]
    cards, i = [], 0
    for n in sizes:
        cards.append(card(*fields[i:i + n]))
        i += n
    d = parse_deck(deck(*cards))
    assert list(d.exact.values()) == values[:17]
    assert d.mechanism.as_tuple() == tuple(float(v) for v in values[:17])
    assert d.ranges == [tuple(float(v) for v in values[17:])]


# ----- the F8.4 trap: fields with no decimal point that look unintended ---------------------
def _trap_deck(*cards: str) -> str:
    good = ["     3.0     8.0     6.0", "     0.0     0.5     0.4",
            "    12.0     4.0    16.0    12.0", "     0.0   -15.0    15.0",
            "     2.0     8.0     6.0", "    50.0", "    10.0    10.0   360.0"]
    for text in cards:
        n, line = text.split(":", 1)
        good[int(n) - 1] = line
    return "\n".join(good) + "\n"


def _traps(deck):
    return [w for w in deck.warnings if "no decimal point" in w]


def test_example_deck_has_no_trap_warnings(example_deck):
    assert example_deck.warnings == []


@pytest.mark.parametrize("cards, expected", [
    # the deck: every length typed as a right-justified integer
    (["3:      10       2       9       6"],
     ['card 3, columns 1-8: "      10": no decimal point: read as 0.0010 (F8.4 implies '
      '4 decimals); did you mean 10.0?', "columns 9-16", "columns 17-24", "columns 25-32"]),
    # the range card typed in whole degrees: 0.001 to 0.036 degrees, 36 sheets of nothing
    (["7:      10      10     360"],
     ["card 7, columns 1-8", "card 7, columns 9-16",
      'card 7, columns 17-24: "     360": no decimal point: read as 0.0360 (F8.4 implies 4 '
      'decimals); did you mean 360.0?']),
    # one forgotten point among good fields: crank speed 50 rad/sec read as 0.005
    (["6:      50"], ["card 6, columns 1-8"]),
    # a centre of mass typed as an integer, and a negative ADEL likewise
    (["5:     2.0       8     6.0", "4:     0.0     -15    15.0"],
     ['card 4, columns 9-16: "     -15": no decimal point: read as -0.0015 (F8.4 implies 4 '
      'decimals); did you mean -15.0?', "card 5, columns 9-16"]),
])
def test_mistyped_integers_are_warned_about(cards, expected):
    deck = parse_deck(_trap_deck(*cards), "d.dat")
    traps = _traps(deck)
    assert len(traps) == len(expected)
    for warning, want in zip(traps, expected):
        assert warning.startswith("d.dat: card ") and want in warning


@pytest.mark.parametrize("field", ["   30000", "  120000", " 3600000", "    3.0 ", "   3.E0 ",
                                   "     0.5", "        ", "       0", "   1.5+2"])
def test_deliberate_fields_are_not_warned_about(field):
    """Implied decimals for a value of 1 or more (how 1960s decks punched 3.0 as 30000),
    explicit points, exponents and zeros are taken as meant."""
    deck = parse_deck(_trap_deck(f"1:{field}     8.0     6.0"), "d.dat")
    assert _traps(deck) == []


def test_check_verdict_mentions_the_trap(tmp_path):
    from sielaff.tools.check import check_deck

    deck = parse_deck(_trap_deck("3:      10       2       9       6"), "d.dat")
    text = check_deck(deck).text
    assert "Verdict: usable as read, but 4 fields without a decimal point" in text
    assert "did you mean 10.0?" in text
