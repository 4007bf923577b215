"""``sielaff punch``: TOML spec in, an exact 80-column 4F8.4 deck out, or a clear refusal."""

from __future__ import annotations

import io
from decimal import Decimal
from unittest import mock

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import procs
from conftest import DECKS
from sielaff.cli import main
from sielaff.emulator.cards import parse_deck, read_field_decimal
from sielaff.mechanism import FIELD_NAMES, Mechanism, crank_rocker_failure
from sielaff.tools.spec import PunchError, punch_deck, punch_field

EXAMPLE_TOML = (DECKS / "example.toml").read_text()


def spec_text(values: dict[str, str], ranges=(("10.0", "10.0", "360.0"),),
              extra: str = "") -> str:
    """A spec with the listing's values (strings, as they appear in the TOML)."""
    v = values
    text = f"""
[weights]
crank = {v['W2']}
coupler = {v['W3']}
rocker = {v['W4']}

[inertia]
crank = {v['ZI2']}
coupler = {v['ZI3']}
rocker = {v['ZI4']}

[lengths]
frame = {v['R1']}
crank = {v['R2']}
coupler = {v['R3']}
rocker = {v['R4']}

[mass_centres]
crank = {{ distance = {v['RG2']}, angle = {v['ADEL2']} }}
coupler = {{ distance = {v['RG3']}, angle = {v['ADEL3']} }}
rocker = {{ distance = {v['RG4']}, angle = {v['ADEL4']} }}

[drive]
speed = {v['TH2D']}
"""
    for start, step, stop in ranges:
        text += f"\n[[range]]\nstart = {start}\nstep = {step}\nstop = {stop}\n"
    return text + extra


EXAMPLE_VALUES = {
    "W2": "3.0", "W3": "8.0", "W4": "6.0", "ZI2": "0.0", "ZI3": "0.5", "ZI4": "0.4",
    "R1": "12.0", "R2": "4.0", "R3": "16.0", "R4": "12.0",
    "ADEL2": "0.0", "ADEL3": "-15.0", "ADEL4": "15.0", "RG2": "2.0", "RG3": "8.0", "RG4": "6.0",
    "TH2D": "50.0",
}


def punch_cli(tmp_path, text: str, *extra: str) -> tuple[int, str, str]:
    spec = tmp_path / "spec.toml"
    spec.write_text(text)
    out, err = io.StringIO(), io.StringIO()
    with mock.patch("sys.stdout", out), mock.patch("sys.stderr", err):
        status = main(["punch", str(spec), *extra])
    return status, out.getvalue(), err.getvalue()


# --------------------------------------------------------------------------
# The example
# --------------------------------------------------------------------------


def test_example_toml_punches_example_dat_byte_for_byte(tmp_path):
    status, out, err = punch_cli(tmp_path, EXAMPLE_TOML)
    assert (status, err) == (0, "")
    assert out == (DECKS / "example.dat").read_text()


def test_output_file_atomic(tmp_path):
    deck = tmp_path / "deck.dat"
    status, out, _ = punch_cli(tmp_path, EXAMPLE_TOML, "-o", str(deck))
    assert status == 0 and out == ""
    assert deck.read_text() == (DECKS / "example.dat").read_text()
    # A refused spec leaves the existing deck alone, and no temporary file behind.
    bad = EXAMPLE_TOML.replace("speed = 50.0", "speed = 50.000001")
    status, _, err = punch_cli(tmp_path, bad, "-o", str(deck))
    assert status == 2 and "too many digits" in err
    assert deck.read_text() == (DECKS / "example.dat").read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.dat", "spec.toml"]


def test_cards_are_80_columns_with_sequence_numbers():
    text = punch_deck_text(spec_text(EXAMPLE_VALUES, ranges=[("0", "1", "90")] * 3))
    lines = text.splitlines()
    assert len(lines) == 9
    assert all(len(line) == 80 for line in lines)
    assert [line[72:] for line in lines] == [f"SIEL{10 * k:04d}" for k in range(1, 10)]


def test_sequence_prefix_and_none():
    text = punch_deck_text(spec_text(EXAMPLE_VALUES, extra='\n[deck]\nsequence = "AB"\n'))
    assert text.splitlines()[0][72:] == "AB000010"
    text = punch_deck_text(spec_text(EXAMPLE_VALUES, extra="\n[deck]\nsequence = false\n"))
    assert all(len(line) <= 72 for line in text.splitlines())
    assert parse_deck(text).exact["TH2D"] == Decimal("50.0")


def punch_deck_text(text: str) -> str:
    import tomllib

    return punch_deck(tomllib.loads(text, parse_float=Decimal), "spec.toml")


# --------------------------------------------------------------------------
# Fields
# --------------------------------------------------------------------------


@pytest.mark.parametrize("value, field", [
    ("3.0", "     3.0"), ("0.5", "     0.5"), ("-15", "   -15.0"), ("0", "     0.0"),
    ("-0.0", "     0.0"), ("1234567", "1234567."), ("-123456", "-123456."),
    ("0.1234567", ".1234567"), ("-0.123456", "-.123456"), ("1234.5678", "12345678"),
    ("-123.4567", "-1234567"), ("1E-7", ".0000001"), ("12.50000", "    12.5"),
    ("9999999", "9999999."), ("2.5E+3", "  2500.0"),
])
def test_punch_field(value, field):
    assert punch_field(Decimal(value)) == field
    assert read_field_decimal(field) == Decimal(value)


@pytest.mark.parametrize("value, reason", [
    ("0.3333333333", "too many digits"),  # 1/3 to 10 places
    ("123456.78", "too many digits"),
    ("3.14159265358979", "too many digits"),
    ("1E-9", "too small"),
    ("-1E-7", "too small"),
    ("1E8", "out of range"),
    ("12345678", "out of range"),
    ("-1234567", "out of range"),
    ("NaN", "not a finite number"),
    ("Infinity", "not a finite number"),
])
def test_punch_field_refuses(value, reason):
    with pytest.raises(ValueError, match=reason):
        punch_field(Decimal(value))


# --------------------------------------------------------------------------
# The round trip: punch -> read_deck gives the spec's values exactly
# --------------------------------------------------------------------------


def punchable(min_value: str, max_value: str, places: int = 4):
    """Decimals in [min_value, max_value] with ``places`` decimals that fit F8.4."""
    scale = Decimal(10) ** places
    lo = int((Decimal(min_value) * scale).to_integral_value(rounding="ROUND_CEILING"))
    hi = int((Decimal(max_value) * scale).to_integral_value(rounding="ROUND_FLOOR"))
    return st.integers(lo, hi).map(lambda i: Decimal(i).scaleb(-places)).filter(_fits)


def _fits(d: Decimal) -> bool:
    try:
        punch_field(d)
    except ValueError:
        return False
    return True


@st.composite
def specs(draw):
    values = {name: draw(punchable("-999.9999", "9999.9999", draw(st.integers(0, 7))))
              for name in ("W2", "W3", "W4", "ZI2", "ZI3", "ZI4", "ADEL2", "ADEL3", "ADEL4",
                           "RG2", "RG3", "RG4", "TH2D")}
    # Lengths: a crank-rocker (report p. 4), crank shortest.
    r2 = draw(punchable("0.5", "10", 3))
    r3 = draw(punchable(str(r2 * 2), str(r2 * 5), 3))
    r4 = draw(punchable(str(r2 * 2), str(r2 * 5), 3))
    lo, hi = abs(r4 - r3) + r2, r3 + r4 - r2
    r1 = draw(punchable(str(lo + Decimal("0.01")), str(hi - Decimal("0.01")), 2))
    values.update(R1=r1, R2=r2, R3=r3, R4=r4)
    n = draw(st.integers(1, 3))
    ranges = []
    for _ in range(n):
        start = draw(punchable("-720", "720", 2))
        step = draw(punchable("0.0001", "90", 4))
        stop = draw(punchable("-720", "720", 1))
        ranges.append((start, step, stop))
    return values, ranges


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(specs(), st.sampled_from(["", "e0"]))
def test_round_trip_exact(spec, exponent):
    values, ranges = spec
    m = Mechanism(**{n: float(values[n]) for n in FIELD_NAMES})
    if crank_rocker_failure(m):
        return  # refused (tested below); the strategy keeps this rare
    # Write each value as TOML floats (1.5 or 1.5e0), so parse_float must keep it exact.
    as_toml = {n: f"{v:f}" + (exponent if "." in f"{v:f}" else ".0") for n, v in values.items()}
    text = spec_text(as_toml, [tuple(f"{x:f}" if "." in f"{x:f}" else f"{x:f}.0" for x in r)
                               for r in ranges])
    deck = parse_deck(punch_deck_text(text))
    assert deck.exact == values
    assert deck.exact_ranges == ranges
    assert deck.warnings == []


# --------------------------------------------------------------------------
# Every refusal, through the command line: one line on stderr, exit 2 or 3
# --------------------------------------------------------------------------


def with_value(name: str, text: str) -> str:
    return spec_text({**EXAMPLE_VALUES, name: text})


REFUSALS = [
    # (spec text, status, words in the message)
    (with_value("W3", "0.3333333333"), 2, "[weights] coupler = 0.3333333333: too many digits"),
    (with_value("R1", "123456.78"), 2, "[lengths] frame = 123456.78: too many digits"),
    (with_value("ZI3", "1e-9"), 2, "[inertia] coupler = 1E-9: too small"),
    (with_value("TH2D", "1e8"), 2, "[drive] speed = 1E+8: out of range"),
    (with_value("RG3", "nan"), 2, "[mass_centres] coupler.distance = NaN: NaN is not a finite"),
    (with_value("ADEL4", "inf"), 2, "not a finite number"),
    (with_value("W2", '"3.0"'), 2, "[weights] crank = '3.0': not a number"),
    (with_value("W2", "true"), 2, "[weights] crank = True: not a number"),
    (with_value("R2", "14.0"), 3, "THIS IS NOT A CRANK ROCKER MECHANISM: B = R4/R2"),
    (with_value("R1", "30.0"), 3, "C = R1/R2 = 7.5 must be < A+B-1 = 6"),
    (spec_text(EXAMPLE_VALUES, [("10", "0", "360")]), 2,
     "[[range]] 1: step = 0 with start = 10 <= stop = 360: the 1966 loop would never end"),
    (spec_text(EXAMPLE_VALUES, [("10", "10", "360"), ("10", "-1.5", "20")]), 2,
     "[[range]] 2: step = -1.5 with start = 10 <= stop = 20"),
    (spec_text(EXAMPLE_VALUES, [("10", "0.000000001", "360")]), 2,
     "[[range]] 1 step = 1E-9: too small"),
    (spec_text(EXAMPLE_VALUES, []), 2, "no [[range]]"),
    (spec_text(EXAMPLE_VALUES) .replace("[drive]\nspeed = 50.0", ""), 2, "missing [drive]"),
    (spec_text(EXAMPLE_VALUES).replace("rocker = 12.0\n", ""), 2, "[lengths] has no rocker"),
    (spec_text(EXAMPLE_VALUES).replace("frame =", "fram ="), 2,
     "[lengths]: unknown key 'fram' (expected: frame, crank, coupler, rocker)"),
    (spec_text(EXAMPLE_VALUES, extra="\n[gears]\nratio = 2\n"), 2, "unknown key 'gears'"),
    (spec_text(EXAMPLE_VALUES).replace("distance = 2.0, ", ""), 2,
     "[mass_centres] crank has no distance"),
    (spec_text(EXAMPLE_VALUES).replace("angle = 0.0 }", "angle = 0.0, mass = 1 }"), 2,
     "unknown key 'mass'"),
    (spec_text(EXAMPLE_VALUES).replace("[[range]]\nstart = 10.0", "[[range]]\nbegin = 10.0"), 2,
     "unknown key 'begin'"),
    (spec_text(EXAMPLE_VALUES, extra='\n[deck]\nsequence = "SIELAFF"\n'), 2,
     "[deck] sequence = 'SIELAFF': up to 4 capital letters or digits"),
    ("[weights\ncrank = 3.0\n", 2, "not valid TOML"),
    (spec_text(EXAMPLE_VALUES).replace("[[range]]", "[range]"), 2,
     "write the range as [[range]]"),
]


@pytest.mark.parametrize("text, status, words", REFUSALS,
                         ids=[r[2][:40] for r in REFUSALS])
def test_refusals(tmp_path, text, status, words):
    got, out, err = punch_cli(tmp_path, text)
    assert got == status
    assert out == ""
    assert err.count("\n") == 1, err
    assert words in err, err
    assert err.startswith(str(tmp_path / "spec.toml"))


def test_refuses_unreadable_spec(tmp_path):
    status, _, err = punch_cli(tmp_path, "")
    assert status == 2
    (tmp_path / "spec.toml").unlink()
    out, err = io.StringIO(), io.StringIO()
    with mock.patch("sys.stdout", out), mock.patch("sys.stderr", err):
        assert main(["punch", str(tmp_path / "spec.toml")]) == 2
    assert "cannot read the spec" in err.getvalue()


def test_refuses_binary_spec(tmp_path):
    (tmp_path / "spec.toml").write_bytes(b"\xff\xfe")
    out, err = io.StringIO(), io.StringIO()
    with mock.patch("sys.stdout", out), mock.patch("sys.stderr", err):
        assert main(["punch", str(tmp_path / "spec.toml")]) == 2
    assert "not a text file" in err.getvalue()


def test_punch_error_status():
    with pytest.raises(PunchError) as exc:
        punch_deck_text(with_value("R2", "14.0"))
    assert exc.value.status == 3


def test_punch_says_which_tables_the_deck_leaves_out(tmp_path):
    """A spec's [scene] and [motor] cannot go on cards: punch writes the deck and one
    warning naming them (issue 32: it used to drop them without a word)."""
    r = procs.run(["punch", str(DECKS / "friction.toml"), "-o", str(tmp_path / "f.dat")],
                  text=True)
    assert r.returncode == 0
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("sielaff: warning: ")
    assert "leaves out [scene], [motor]" in lines[0]
    r = procs.run(["punch", str(DECKS / "example.toml"), "-o", str(tmp_path / "e.dat")],
                  text=True)
    assert r.returncode == 0 and r.stderr == ""
