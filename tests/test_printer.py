"""The FORMAT interpreter and the 1410's number editing."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from sielaff.emulator.printer import Format, FormatError, decimal_parts, edit_e, edit_f, render


@pytest.mark.parametrize("value, text", [
    (545.6, "   .5456E 03"),
    (-27.07, "  -.2707E 02"),
    (0.0, "   .0000E-99"),
    (-0.0, "   .0000E-99"),
    (0.7, "   .7000E 00"),          # repr digits, not the binary expansion 0.6999...
    (130.357, "   .1303E 03"),      # truncated, not rounded
    (199.99999, "   .1999E 03"),
    (1e-5, "   .1000E-04"),
    (9.99999e98, "   .9999E 99"),
    (1e99, "************"),          # exponent 100 does not fit the 1410's two digits
    (1e-100, "   .1000E-99"),
    (float("inf"), "************"),
    (float("nan"), "************"),
])
def test_e12_4(value, text):
    assert edit_e(value, 12, 4) == text


@pytest.mark.parametrize("value, text", [
    (40.0, "        40.0"),
    (67.3758, "        67.3"),         # truncated: rounding would give 67.4
    (129.99999999, "       129.9"),
    (-27.07, "       -27.0"),
    (0.5, "          .5"),            # no leading zero (documented choice)
    (-0.04, "         -.0"),
    (0.0, "          .0"),
    (12345678901.0, "************"),  # 13 characters do not fit F12.1
    (1234567890.0, "1234567890.0"),
])
def test_f12_1(value, text):
    assert edit_f(value, 12, 1) == text


def test_e_field_too_narrow_is_starred():
    assert edit_e(-545.6, 9, 4) == "*********"
    assert edit_e(545.6, 9, 4) == ".5456E 03"


@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e90, max_value=1e90))
def test_e_field_truncates_toward_zero(x):
    text = edit_e(x, 12, 4)
    if x != 0 and abs(x) < 1e-100:
        assert text == "*" * 12  # exponent below -99 cannot be printed
        return
    mantissa, exp = text.strip().split("E")
    printed = float(mantissa) * 10 ** int(exp.replace(" ", "+"))
    if x == 0:
        assert text == "   .0000E-99"
        return
    # truncation: printed magnitude never exceeds the value, and is within one unit
    unit = 10 ** (int(exp.replace(" ", "+")) - 4)
    assert abs(printed) <= abs(x) * (1 + 1e-12)
    assert abs(x) - abs(printed) < unit * (1 + 1e-9)
    assert (printed < 0) == (x < 0)


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_decimal_parts_reconstructs_repr(x):
    neg, digits, exp = decimal_parts(x)
    if x == 0:
        assert digits == ""
    else:
        from decimal import Decimal
        assert Decimal(f"{'-' if neg else ''}0.{digits}E{exp}") == Decimal(repr(x))


def test_heading_format_records():
    fmt = Format("(//18X,7HTHETA 2,5X,7HTHETA 3,5X,7HTHETA 4/)")
    assert fmt.records() == [" ", " ", " " * 18 + "THETA 2     THETA 3     THETA 4", " "]


def test_value_format_repeat_count_and_slash():
    assert Format("(11X,3F12.1/)").records([40.0, 32.1, 67.37]) == [
        " " * 19 + "40.0" + " " * 8 + "32.1" + " " * 8 + "67.3", " "]
    assert Format("(15X,1E12.4/)").records([0.0]) == [" " * 18 + ".0000E-99", " "]


def test_page_eject_blank_records_and_message():
    assert Format("(1H1)").records() == ["1"]
    assert Format("(/)").records() == [" ", " "]
    assert Format("(37H THIS IS NOT A CRANK ROCKER MECHANISM)").records() == [
        " THIS IS NOT A CRANK ROCKER MECHANISM"]


def test_output_stops_at_first_field_without_a_value():
    assert Format("(5HA B C,F6.1,4HTAIL)").records([]) == ["A B C"]


def test_format_errors():
    with pytest.raises(FormatError):
        Format("11X,F12.1")
    with pytest.raises(FormatError):
        Format("(12HSHORT)")
    with pytest.raises(FormatError):
        Format("(I5)")
    with pytest.raises(FormatError):
        Format("(F12.1)").records([1.0, 2.0])


def test_render_asa_like_posix():
    assert render([" A", "0B", "1C", " D"]) == "A\n\nB\n\fC\nD\n"


# ----- every E12.4 and F12.1 editor against an oracle of its own ---------------------------
# The port prints through fast_editor (scalar, three tiers) and vector.py's tables; the
# goldens pass through whichever path a deck takes, so each editor is held here to an
# oracle that shares no code with them: Python's decimal module, truncating the digits
# of repr (the shortest round-trip decimal) toward zero.

def _oracle_e(x: float, w: int = 12, d: int = 4) -> str:
    import decimal

    if x == 0.0:
        return ".".rjust(w - d - 4) + "0" * d + "E-99"
    q = decimal.Decimal(repr(x))
    exponent = q.adjusted() + 1  # x = 0.ddd x 10**exponent
    if not -99 <= exponent <= 99:
        return "*" * w
    digits = str(int(abs(q).scaleb(d - exponent).to_integral_value(decimal.ROUND_DOWN)))
    sign = "-" if x < 0 else ""
    text = f"{sign}.{digits}E{'-' if exponent < 0 else ' '}{abs(exponent):02d}"
    return text.rjust(w) if len(text) <= w else "*" * w


def _oracle_f(x: float, w: int = 12, d: int = 1) -> str:
    import decimal

    q = decimal.Decimal(repr(x)).quantize(decimal.Decimal(1).scaleb(-d), decimal.ROUND_DOWN)
    text = f"{q:f}"
    if text.startswith(("0.", "-0.")):
        text = text.replace("0.", ".", 1)
    if q == 0 and x < 0:
        text = "-" + text.lstrip("-")
    return text.rjust(w) if len(text) <= w else "*" * w


def _near_boundaries(seed: int, n: int) -> list[float]:
    """Values a few ulps either side of a printed-digit boundary (k 10**e), where an
    editor that rounds a step wrong differs from truncation, and random ones."""
    import numpy as np

    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        b = float(rng.integers(1000, 10000)) * 10.0 ** int(rng.integers(-30, 30))
        for k in range(-3, 4):
            v = b
            for _ in range(abs(k)):
                v = float(np.nextafter(v, np.inf if k > 0 else -np.inf))
            out += [v, -v]
        out.append(float(rng.standard_normal() * 10.0 ** rng.integers(-40, 40)))
    return out


def test_the_oracle_agrees_with_the_examples_above():
    assert _oracle_e(545.6) == "   .5456E 03" and _oracle_e(-27.07) == "  -.2707E 02"
    assert _oracle_e(130.357) == "   .1303E 03" and _oracle_e(1e99) == "*" * 12
    assert _oracle_f(67.3758) == "        67.3" and _oracle_f(-0.04) == "         -.0"


@pytest.mark.parametrize("strict", [False, True])
def test_the_scalar_editors_truncate_as_the_oracle(strict):
    from sielaff.emulator.printer import fast_editor

    e, f = fast_editor("E", 12, 4, strict), fast_editor("F", 12, 1, strict)
    values = _near_boundaries(31, 400)
    assert len(values) == 400 * 15
    for x in values:
        assert e(x) == edit_e(x, 12, 4) == _oracle_e(x), x
        if abs(x) < 1e9:
            assert f(x) == edit_f(x, 12, 1) == _oracle_f(x), x


def test_the_vector_editor_truncates_as_the_oracle():
    import numpy as np

    from sielaff.emulator import vector

    values = np.array(_near_boundaries(32, 400))
    words, ok = vector._edit_e(values)
    text = words.view(np.uint8).reshape(len(values), 12)
    checked = 0
    for x, row, applies in zip(values, text, ok):
        if applies:
            assert bytes(row).decode() == _oracle_e(float(x)), x
            checked += 1
    assert checked >= 350  # the first tier takes the random ones, not those at a boundary
