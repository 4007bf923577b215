"""The IBM 1410 number model: K-digit truncating decimal floating point and its library.

The oracles here are written independently of ``sielaff.emulator.arithmetic.ibm1410``: Python
``decimal`` with explicit truncation for the arithmetic, ``mpmath`` for the
library, and an operator-level restatement of the library algorithms.
"""

from __future__ import annotations

import decimal
import math
import operator
import pickle
from decimal import ROUND_DOWN, Decimal
from fractions import Fraction

import mpmath
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from conftest import tiered
from sielaff.emulator.arithmetic import ArithmeticError1410, get_arithmetic
from sielaff.emulator.arithmetic.ibm1410 import D1410, IBM1410, VARIANTS
from sielaff.emulator.arithmetic.ibm1410 import library as mod

A8 = IBM1410(8)
A12 = IBM1410(12)
A16 = IBM1410(16)
BY_K = {8: A8, 12: A12, 16: A16}

WIDE = decimal.Context(prec=400, Emax=10**6, Emin=-(10**6))
mpmath.mp.dps = 50


def D(x) -> Decimal:
    """Exact value of a model number."""
    return Decimal(str(x))


def E(d: Decimal) -> int:
    """Exponent of a nonzero Decimal in the 1410's 0.d1d2... x 10**E form."""
    return d.adjusted() + 1


def ulp(d: Decimal, K: int) -> Decimal:
    return Decimal(0) if d == 0 else WIDE.power(Decimal(10), E(d) - K)


def trunc_to_K(d: Decimal, K: int) -> Decimal:
    """First K significant digits of an exact value (the rest dropped); 1410 range."""
    if d == 0:
        return Decimal(0)
    t = decimal.Context(prec=K, rounding=ROUND_DOWN, Emax=10**6, Emin=-(10**6)).plus(d)
    return Decimal(0) if E(t) < -99 else t


def oracle_add(a: Decimal, b: Decimal, K: int) -> Decimal:
    """1410 add, restated: align to the larger exponent by dropping the smaller
    operand's digits below that operand's last place, add exactly, keep K digits."""
    if a == 0 or b == 0:
        return a + b
    if E(a) < E(b):
        a, b = b, a
    quantum = Decimal(f"1E{E(a) - K}")  # the last place of the larger operand
    b_aligned = b.quantize(quantum, rounding=ROUND_DOWN, context=WIDE)
    return trunc_to_K(WIDE.add(a, b_aligned), K)


def operands(K: int, emin: int = -40, emax: int = 40):
    """Normalised K-digit numbers as exact text (sign, K-digit mantissa, exponent)."""
    return st.builds(
        lambda s, m, e: f"{s * m}E{e - K}",
        st.sampled_from([1, -1]),
        st.integers(10 ** (K - 1), 10**K - 1),
        st.integers(emin, emax),
    )


def pairs_near(K: int):
    """Two operands whose exponents differ by at most K+2 (so alignment matters)."""
    return st.builds(
        lambda s1, m1, s2, m2, e, d: (f"{s1 * m1}E{e - K}", f"{s2 * m2}E{e + d - K}"),
        st.sampled_from([1, -1]),
        st.integers(10 ** (K - 1), 10**K - 1),
        st.sampled_from([1, -1]),
        st.integers(10 ** (K - 1), 10**K - 1),
        st.integers(-40, 40),
        st.integers(-(K + 2), K + 2),
    )


# ----- representation and conversion ---------------------------------------------------
def test_input_truncates_to_K_digits():
    n = A8.num
    assert str(n("3.14159265358979323846")) == "0.31415926E+01"
    assert str(n(2 / 3)) == "0.66666666E+00"  # repr 0.6666666666666666, truncated
    assert str(n(-2 / 3)) == "-0.66666666E+00"
    assert str(n(0.99999999999)) == "0.99999999E+00"
    assert str(n("0.9E+25")) == "0.90000000E+25"
    assert str(n("1E-8")) == "0.10000000E-07"
    assert str(n("0.1E-50")) == "0.10000000E-50"
    assert str(n(57.295779)) == "0.57295779E+02"
    assert str(n(386)) == "0.38600000E+03"
    assert str(n(123456789)) == "0.12345678E+09"
    assert str(n(Fraction(1, 3))) == "0.33333333E+00"
    assert str(n(Decimal("-0.123456789"))) == "-0.12345678E+00"
    assert str(IBM1410(12).num("3.14159265358979323846")) == "0.314159265358E+01"
    assert str(A16.num(2 / 3)) == "0.6666666666666666E+00"
    # a number of another precision is truncated, not rounded
    assert str(A8.num(A16.num("0.123456789999"))) == "0.12345678E+00"


def test_zero_has_exponent_minus_99():
    for z in (A8.num(0), A8.num(0.0), A8.num(-0.0), A8.num("0E5"), A8.ZERO,
              A8.num(1) - A8.num(1), A8.num(0.5) * 0.0, -A8.num(0)):
        assert z.m == 0 and z.e == -99
        assert str(z) == "0.00000000E-99"
        assert not z
        assert z == 0.0


def test_conversion_range():
    assert str(A8.num("0.99999999999E99")) == "0.99999999E+99"
    assert str(A8.num("1E-100")) == "0.10000000E-99"  # smallest
    assert A8.num("0.99E-100") == 0.0  # below the range: zero
    assert A8.num(1e-200) == 0.0
    with pytest.raises(ArithmeticError1410, match="conversion"):
        A8.num("1E99")  # = 0.1E100
    with pytest.raises(ValueError):
        A8.num(float("nan"))
    with pytest.raises(ValueError):
        A8.num("twelve")
    with pytest.raises(TypeError):
        A8.num([1.0])


@given(st.sampled_from([8, 12, 16]), st.data())
def test_str_is_exact_decimal_text(K, data):
    text = data.draw(operands(K, -99, 99))
    x = BY_K[K].num(text)
    assert Decimal(str(x)) == Decimal(text)
    assert x.to_decimal() == Decimal(text)
    assert eval(repr(x).replace(type(x).__name__, "BY_K[K].num")) == x
    assert pickle.loads(pickle.dumps(x)) == x
    assert float(x) == float(Decimal(text))


@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e90, max_value=1e90))
def test_float_conversion_truncates_the_shortest_repr(f):
    assert A8.num(f).to_decimal() == trunc_to_K(Decimal(repr(f)), 8)


# ----- add / subtract: alignment drops digits, no guard digit ----------------------------
def test_alignment_drops_digits_without_guard_digit():
    n = A8.num
    # 1.0000000 - 0.19E-7: the subtrahend is shifted out entirely.
    r = n("1.0") - n("0.19E-7")
    assert str(r) == "0.10000000E+01"
    assert trunc_to_K(Decimal("1.0") - Decimal("0.19E-7"), 8) == Decimal("0.99999998")
    # 1.0 - 0.012345678: the two low digits of the subtrahend are dropped before
    # subtracting, so the result is 0.98765440, not the truncated exact 0.98765432.
    r = n("1.0") - n("0.12345678E-01")
    assert str(r) == "0.98765440E+00"
    assert trunc_to_K(Decimal("1.0") - Decimal("0.012345678"), 8) == Decimal("0.98765432")
    # Mirror image with negative operands, and as an addition.
    assert str(n("-1.0") + n("0.12345678E-01")) == "-0.98765440E+00"
    assert str(n("0.12345678E-01") - n("1.0")) == "-0.98765440E+00"
    # Catastrophic cancellation: 1.0 - 0.99999999 loses the last 9 before subtracting.
    r = n(1) - n("0.99999999")
    assert str(r) == "0.10000000E-06"  # exact answer 0.1E-7
    # The operand order does not matter.
    assert n("0.99999999") - n(1) == -r


def test_carry_out_drops_the_lowest_digit():
    n = A8.num
    assert str(n("0.99999999") + n("0.99999999")) == "0.19999999E+01"  # exact 1.99999998
    assert str(n("0.99999999") + n("0.99999999E-01")) == "0.10999999E+01"
    assert str(n("0.99999999") + n("0.1E-7")) == "0.10000000E+01"
    assert str(n("-0.55555555E+03") - n("0.55555555E+03")) == "-0.11111111E+04"
    assert str(n("0.99999999E+99") - n("-0.1E+91")) == "0.99999999E+99"  # no carry


def test_cancellation_normalises_left():
    n = A8.num
    r = n("0.12345678E+01") - n("0.12345600E+01")
    assert (r.m, r.e) == (78000000, -5)
    assert str(r) == "0.78000000E-05"
    r = n("-0.10000001E+00") + n("0.1E+00")
    assert str(r) == "-0.10000000E-07"
    # normalising below the range underflows to zero
    r = n("0.10000001E-98") - n("0.10000000E-98")
    assert r.m == 0 and r.e == -99


@settings(max_examples=300)
@given(st.sampled_from([8, 12, 16]), st.data())
def test_add_sub_match_the_shift_and_drop_oracle(K, data):
    ta, tb = data.draw(pairs_near(K))
    A = BY_K[K]
    a, b = A.num(ta), A.num(tb)
    da, db = Decimal(ta), Decimal(tb)
    s, d = a + b, a - b
    assert D(s) == oracle_add(da, db, K)
    assert D(d) == oracle_add(da, -db, K)
    # sign-magnitude symmetry
    assert b + a == s
    assert b - a == -d
    assert (-a) - b == -s
    # error bound: below 2 ulps of the largest of the operands and the result
    for r, exact in ((s, da + db), (d, da - db)):
        err = abs(WIDE.subtract(D(r), exact))
        bound = 2 * max(ulp(da, K), ulp(db, K), ulp(D(r), K))
        assert err < bound


@given(st.sampled_from([8, 12]), st.data())
def test_same_sign_add_is_the_truncated_exact_sum(K, data):
    ta, tb = data.draw(pairs_near(K))
    A = BY_K[K]
    a, b = abs(A.num(ta)), abs(A.num(tb))
    assert D(a + b) == trunc_to_K(WIDE.add(D(a), D(b)), K)


@given(operands(8, -99, 99), operands(8, -99, 99))
@example("10000000E-107", "-10000000E-107")
def test_add_over_the_whole_range(ta, tb):
    a, b = A8.num(ta), A8.num(tb)
    exact_sum = WIDE.add(Decimal(ta), Decimal(tb))
    if exact_sum != 0 and E(exact_sum) > 99:
        with pytest.raises(ArithmeticError1410):
            a + b
        return
    assert D(a + b) == oracle_add(Decimal(ta), Decimal(tb), 8)
    assert D(a + A8.ZERO) == D(a)
    assert D(A8.ZERO - a) == -D(a)


# ----- multiply / divide truncate -------------------------------------------------------
@settings(max_examples=300)
@given(st.sampled_from([8, 12, 16]), st.data())
def test_mul_div_truncate(K, data):
    A = BY_K[K]
    ta, tb = data.draw(operands(K)), data.draw(operands(K))
    a, b = A.num(ta), A.num(tb)
    down = decimal.Context(prec=K, rounding=ROUND_DOWN, Emax=10**6, Emin=-(10**6))
    assert D(a * b) == down.multiply(Decimal(ta), Decimal(tb))
    assert D(a / b) == down.divide(Decimal(ta), Decimal(tb))
    assert b * a == a * b
    assert (-a) * b == -(a * b)
    assert (-a) / b == -(a / b)


def test_mul_div_examples():
    n = A8.num
    assert str(n("0.99999999") * n("0.99999999")) == "0.99999998E+00"  # .9999999800000001
    assert str(n("0.2") * n("0.5")) == "0.10000000E+00"
    assert str(n(1) / n(3)) == "0.33333333E+00"
    assert str(n(2) / n(3)) == "0.66666666E+00"
    assert str(n(-2) / n(3)) == "-0.66666666E+00"
    assert str(n(200) / n(3) * 3) == "0.19999999E+03"  # a hair below, never rounded up
    assert str(n(1) / n(7) * 7) == "0.99999998E+00"  # .14285714 * 7


def test_underflow_gives_zero():
    n = A8.num
    for r in (n("0.1E-60") * n("0.1E-60"), n("0.1E-99") / n(10), n("0.1E-99") * 0.5,
              n("-0.5E-60") * n("0.5E-60")):
        assert r.m == 0 and r.e == -99
    assert str(n("0.1E-98") / n(10)) == "0.10000000E-99"  # still in range


def test_overflow_raises_naming_the_operation():
    n = A8.num
    big = n("0.9E+99")
    with pytest.raises(ArithmeticError1410, match="multiplication"):
        n("0.9E+60") * n("0.9E+60")
    with pytest.raises(ArithmeticError1410, match="addition"):
        big + big
    with pytest.raises(ArithmeticError1410, match="subtraction"):
        big - (-big)
    with pytest.raises(ArithmeticError1410, match="subtraction"):
        -9e98 - big
    with pytest.raises(ArithmeticError1410, match="division"):
        big / n("0.1E-10")
    with pytest.raises(ArithmeticError1410, match="division by zero"):
        n(1) / A8.ZERO
    with pytest.raises(ArithmeticError1410, match="division by zero"):
        1.0 / A8.ZERO
    # the largest value itself is fine
    assert str(n("0.99999999E+99") * n(1)) == "0.99999999E+99"


# ----- comparisons and mixing with Python numbers ----------------------------------------
@given(st.sampled_from([8, 16]), st.data())
def test_comparisons_are_exact(K, data):
    A = BY_K[K]
    ta, tb = data.draw(st.one_of(pairs_near(K), st.tuples(operands(K, -99, 99),
                                                          operands(K, -99, 99))))
    a, b = A.num(ta), A.num(tb)
    da, db = Decimal(ta), Decimal(tb)
    assert (a < b) == (da < db)
    assert (a <= b) == (da <= db)
    assert (a > b) == (da > db)
    assert (a >= b) == (da >= db)
    assert (a == b) == (da == db)
    assert (a != b) == (da != db)
    assert (A.ZERO < a) == (da > 0)
    assert a == A.num(ta) and hash(a) == hash(A.num(ta)) == hash(da)


def test_mixing_with_python_numbers():
    n = A8.num
    x = n("0.7")
    assert x == 0.7 and x <= 0.7 and not x < 0.7 and x >= 0.7  # 0.7 is the constant .70000000
    assert n(1) / n(3) == 1 / 3  # the float converts like a constant: .33333333
    assert 0.7 == x and 0.69 < x and 0.71 > x
    assert 2.0 * x == x * 2.0 == x + x
    assert str(1.0 - x) == "0.30000000E+00"
    assert str(1 - x) == "0.30000000E+00"
    assert str(1.0 / n(3)) == "0.33333333E+00"
    assert str(x / 2) == "0.35000000E+00"
    assert abs(n(-1.5)) == 1.5 and -n(1.5) == -1.5 and +x is x
    assert float(n("0.31415926E+01")) == 3.1415926
    assert int(n(-2.9)) == -2 and int(n("0.12E+03")) == 120
    assert hash(n(0.5)) == hash(0.5) and hash(n(3)) == hash(3)
    assert bool(x) and not bool(A8.ZERO)
    assert x != "0.7" and operator.ne(x, None)
    with pytest.raises(TypeError):
        x + "1"
    with pytest.raises(TypeError):
        assert x < "1"
    with pytest.raises(TypeError):
        x * A16.num(2)  # precisions do not mix silently
    assert format(n("0.5"), ".3f") == "0.500"
    assert repr(x) == "D1410_8('0.70000000E+00')"
    assert isinstance(x, D1410) and type(x) is A8.number


def test_get_arithmetic_builds_the_model():
    a = get_arithmetic("ibm1410")
    assert isinstance(a, IBM1410) and a.name == "ibm1410:8" and a.digits == 8
    a = get_arithmetic("ibm1410:12")
    assert a.name == "ibm1410:12" and str(a.num(1 / 3)) == "0.333333333333E+00"
    with pytest.raises(ValueError):
        IBM1410(1)
    with pytest.raises(ValueError):
        IBM1410(8, variant="nonsense")
    with pytest.raises(ValueError):
        IBM1410(8, variant="taylor,sqrt=magic")


def test_variants_select_algorithms():
    assert IBM1410(8).variant == "sine"  # the default: 82 of 82 figure fields (test_accuracy)
    for name in VARIANTS:
        assert IBM1410(8, variant=name).variant == name
    mixed = IBM1410(8, variant="taylor,sqrt=fixed")
    assert mixed.choice == {"trig": "octant", "atan": "pi6", "sqrt": "fixed", "reduce": "model",
                            "cos": "own", "final": "trunc"}
    assert IBM1410(8, variant="sqrt=one").choice["trig"] == "sine"
    assert IBM1410(8, variant="sine,reduce=model").variant == (
        "trig=sine,atan=pi3,sqrt=exp,reduce=model,cos=own,final=trunc")
    # the variants really differ in the last digits somewhere
    xs = [A8.num(i / 37) for i in range(1, 200)]
    outs = {name: [(IBM1410(8, variant=name).SIN(x), IBM1410(8, variant=name).COS(x),
                    IBM1410(8, variant=name).ATAN(x)) for x in xs] for name in VARIANTS}
    names = list(VARIANTS)
    assert all(outs[a] != outs[b] for a in names for b in names if a < b)
    for part in ("reduce=model", "cos=shift", "final=round2", "atan=pi6"):
        other = IBM1410(8, variant=f"sine,{part}")
        assert [(other.SIN(x), other.COS(x), other.ATAN(x)) for x in xs] != outs["sine"], part


# ----- the library ---------------------------------------------------------------------
def mp(x) -> mpmath.mpf:
    return mpmath.mpf(str(x.to_decimal()))


def err(x, exact) -> float:
    return float(abs(mp(x) - exact))


#: Absolute error bounds.  At K digits the library works in K-digit truncating
#: arithmetic, so its error is a few units of 10**(1-K) (one unit in the last place
#: of 1.0: COS near 0 computes 1 - r*r/2 + ..., and 1.0's last place is 10**(1-K)).
#: SIN/COS reduce by q * (pi/2) with a K-digit pi/2 and a truncated product, which
#: adds an error growing with |x|.  Measured worst case: 0.95 (1 + |x|) 10**(1-K).
#: The Hastings polynomials add their own 2.3e-9 / 1.4e-8 approximation error.
def trig_bound(A, x) -> float:
    b = 2 * (1 + abs(float(x))) * 10.0 ** (1 - A.digits)
    return b + 3e-9 if A.choice["trig"] == "hastings" else b


def atan_bound(A) -> float:
    b = 4 * 10.0 ** (1 - A.digits)
    return max(b, 2e-8) if A.choice["atan"] == "hastings" else b


LIBS = ([IBM1410(K, variant=v) for K in (8, 16) for v in VARIANTS]
        + [IBM1410(8, variant=v) for v in ("taylor,cos=shift", "sine,final=round2")])


def _tiered(libs):
    """Each library a parameter: the 8-digit ones (the 1410's) in the default tier, the
    others (what more digits would give) in the slow tier."""
    return tiered(libs, lambda A: A.digits == 8)


@pytest.mark.parametrize("A", _tiered(LIBS), ids=lambda A: f"{A.digits}-{A.variant}")
@settings(max_examples=60, deadline=None)
@given(x=st.floats(min_value=-20.0, max_value=20.0))
@example(x=0.0)
@example(x=math.pi / 2)
@example(x=-math.pi)
@example(x=math.pi / 4)
@example(x=1e-30)
def test_sin_cos_accuracy(A, x):
    x = A.num(x)
    assert err(A.SIN(x), mpmath.sin(mp(x))) <= trig_bound(A, x)
    assert err(A.COS(x), mpmath.cos(mp(x))) <= trig_bound(A, x)


@pytest.mark.parametrize("A", _tiered(LIBS), ids=lambda A: f"{A.digits}-{A.variant}")
@settings(max_examples=60, deadline=None)
@given(x=st.one_of(st.floats(min_value=-3.0, max_value=3.0),
                   st.floats(min_value=-1e30, max_value=1e30)))
@example(x=1.0)
@example(x=-1.0)
@example(x=0.0)
@example(x=0.2679491924311227)
@example(x=0.41421356237309503)
def test_atan_accuracy(A, x):
    x = A.num(x)
    assert err(A.ATAN(x), mpmath.atan(mp(x))) <= atan_bound(A)


@pytest.mark.parametrize("A", _tiered(LIBS), ids=lambda A: f"{A.digits}-{A.variant}")
@settings(max_examples=60, deadline=None)
@given(t=st.data())
def test_sqrt_accuracy(A, t):
    x = A.num(t.draw(operands(A.digits, -99, 99)).lstrip("-"))
    y = A.SQRT(x)
    exact = mpmath.sqrt(mp(x))
    assert float(abs(mp(y) / exact - 1)) <= 2 * 10.0 ** (1 - A.digits)


def test_library_exact_values_and_signs():
    for A in (IBM1410(8, variant=v) for v in VARIANTS):
        assert A.SQRT(A.num(4)) == 2.0 and A.SQRT(A.num(0)) == 0.0
        assert A.SQRT(A.num("0.01")) == 0.1 and A.SQRT(A.num("1E-98")) == A.num("1E-49")
        assert A.SIN(A.ZERO) == 0.0 and A.COS(A.ZERO) == 1.0 and A.ATAN(A.ZERO) == 0.0
        for v in (0.3, 1.2, 2.5, 4.0, 5.9, 30.0):
            x = A.num(v)
            assert A.SIN(-x) == -A.SIN(x)
            assert A.COS(-x) == A.COS(x)
            assert A.ATAN(-x) == -A.ATAN(x)
            assert math.copysign(1, float(A.SIN(x))) == math.copysign(1, math.sin(v))
            assert math.copysign(1, float(A.COS(x))) == math.copysign(1, math.cos(v))
        # pi/2 - 1E-90: the tiny term is shifted out, leaving the 8-digit pi/2
        assert str(A.ATAN(A.num("1E90"))) == "0.15707963E+01"
        assert str(A.ATAN(A.num("-1E90"))) == "-0.15707963E+01"


def test_sqrt_of_negative_reports_and_uses_abs():
    msgs = []
    A = IBM1410(8, on_error=msgs.append)
    assert A.SQRT(A.num(-2.25)) == A.SQRT(A.num(2.25)) == 1.5
    assert len(msgs) == 1 and "SQRT" in msgs[0] and "negative" in msgs[0]


def test_sin_cos_out_of_range_reports():
    msgs = []
    A = IBM1410(8, on_error=msgs.append)
    assert A.SIN(A.num(10000)) == 0.0 and A.COS(A.num(-12345.6)) == 0.0
    assert len(msgs) == 2 and "SIN" in msgs[0] and "COS" in msgs[1]
    assert abs(float(A.SIN(A.num(9999))) - math.sin(9999)) < 1e-3  # still computed
    assert not msgs[2:]


def test_library_accepts_python_numbers():
    assert A8.SQRT(2.0) == A8.SQRT(A8.num(2)) and A8.SIN(1) == A8.SIN(A8.num(1.0))


def test_loops_are_bounded(monkeypatch):
    A = IBM1410(8, variant="taylor")  # "sine" has a fixed term count: no loop to bound
    A._sin_div = A._sin_div[:2]  # too few terms to converge: the bound must trip
    with pytest.raises(ArithmeticError1410, match="SIN series"):
        A.SIN(A.num(0.7))
    A._odd = A._odd[:2]
    with pytest.raises(ArithmeticError1410, match="ATAN series"):
        A.ATAN(A.num(0.2))
    monkeypatch.setattr(mod, "_MAX_NEWTON_STEPS", 3)
    B = IBM1410(8, variant="quadrant")  # Newton from 1.0 needs ~160 steps for 1E80
    with pytest.raises(ArithmeticError1410, match="SQRT Newton"):
        B.SQRT(B.num("1E80"))


# ----- the library, restated with the number operators ---------------------------------
class OperatorLibrary:
    """The module docstring's algorithms written with ``+ - * /`` on model numbers.

    ``sielaff.emulator.arithmetic.ibm1410`` runs them on raw (mantissa, exponent) pairs for
    speed; the
    two must agree digit for digit.
    """

    def __init__(self, A: IBM1410):
        n = self.n = A.num
        self.A = A
        pi = Decimal(mod._PI)
        with decimal.localcontext() as c:
            c.prec = 60
            self.hp, self.qp, self.sp = n(str(pi / 2)), n(str(pi / 4)), n(str(pi / 6))
            self.s3 = n(mod._SQRT3)
            self.t15 = n(str(2 - Decimal(mod._SQRT3)))
            self.t225 = n(str(Decimal(2).sqrt() - 1))
            self.tp = n(str(pi / 3))
            self.t75 = n(str(2 + Decimal(mod._SQRT3)))
        ch = A.choice
        # reduce=exact: the library's reduction subtractions are exact, then truncated
        self.rsub = ((lambda a, b: a - b) if ch["reduce"] == "model"
                     else (lambda a, b: n(WIDE.subtract(a.to_decimal(), b.to_decimal()))))

    def sine(self, r):
        """Horner form of the sine series, N factors."""
        x2, p = r * r, self.n(1)
        for k in range(self.A._sine_terms, 0, -1):
            p = 1.0 - (x2 / self.n((2 * k) * (2 * k + 1))) * p
        return r * p

    def sin_series(self, r):
        s = t = r
        for k in range(1, 100):
            t = t * (r * r) / self.n((2 * k) * (2 * k + 1))
            s1 = s - t if k % 2 else s + t
            if s1 == s:
                return s
            s = s1
        raise AssertionError

    def cos_series(self, r):
        s = t = self.n(1)
        for k in range(1, 100):
            t = t * (r * r) / self.n((2 * k - 1) * (2 * k))
            s1 = s - t if k % 2 else s + t
            if s1 == s:
                return s
            s = s1
        raise AssertionError

    def horner(self, coeffs, x2):
        p = self.n(coeffs[-1])
        for c in reversed(coeffs[:-1]):
            p = p * x2 + self.n(c)
        return p

    def sincos(self, r, want_sin):
        how = self.A.choice["trig"]
        if how == "hastings":
            if want_sin:
                return self.horner(mod._HASTINGS_SIN, r * r) * r
            return self.horner(mod._HASTINGS_COS, r * r)
        if how == "sine":
            return self.sine(r if want_sin else self.rsub(self.hp, r))
        if how == "octant" and r > self.qp:
            r, want_sin = self.rsub(self.hp, r), not want_sin
        return self.sin_series(r) if want_sin else self.cos_series(r)

    def trig(self, x, want_sin):
        if self.A.choice["final"] == "round2":
            inner = OperatorLibrary(self.A._inner)
            v = inner.trig(self.A._inner.num(x.to_decimal()), want_sin).to_decimal()
            return self.n(decimal.Context(prec=self.A.digits, rounding="ROUND_HALF_UP").plus(v))
        if not want_sin and self.A.choice["cos"] == "shift":
            return self.trig(abs(x) + self.hp, True)
        ax = abs(x)
        # the notes' range of SIN and COS, |x| < 10000, else 0 (COS by the shift: from
        # 10000 - pi/2 on)
        if ax >= 10000.0:
            return self.n(0)
        q = 0
        if ax >= self.hp:
            q = int(ax / self.hp)
            r = self.rsub(ax, self.n(q) * self.hp)
            if r < 0.0:
                q, r = q - 1, self.rsub(r, -self.hp)
            elif r >= self.hp:
                q, r = q + 1, self.rsub(r, self.hp)
            q &= 3
        else:
            r = ax
        if want_sin:
            v = self.sincos(r, q % 2 == 0)
            return -v if (q >= 2) != (x < 0.0) else v
        v = self.sincos(r, q % 2 == 1)
        return -v if q in (1, 2) else v

    def atan_series(self, a):
        s = p = a
        for k in range(1, 100):
            p = p * (a * a)
            s1 = s - p / self.n(2 * k + 1) if k % 2 else s + p / self.n(2 * k + 1)
            if s1 == s:
                return s
            s = s1
        raise AssertionError

    def atan(self, x):
        if self.A.choice["final"] == "round2":
            v = OperatorLibrary(self.A._inner).atan(self.A._inner.num(x.to_decimal()))
            return self.n(decimal.Context(prec=self.A.digits,
                                          rounding="ROUND_HALF_UP").plus(v.to_decimal()))
        a = abs(x)
        how = self.A.choice["atan"]
        inv = a > 1.0 and not (how == "pi3" and a <= self.t75)
        if inv:
            a = 1.0 / a
        if how == "pi3" and a > 1.0:
            v = self.tp + self.atan_series((a - self.s3) / (a * self.s3 + 1.0))
        elif how == "hastings":
            v = self.horner(mod._HASTINGS_ATAN, a * a) * a
        elif how in ("pi6", "pi3") and a > self.t15:
            v = self.sp + self.atan_series((a * self.s3 - 1.0) / (a + self.s3))
        elif how == "pi4" and a > self.t225:
            v = self.qp + self.atan_series((a - 1.0) / (a + 1.0))
        else:
            v = self.atan_series(a)
        if inv:
            v = self.hp - v
        return -v if x < 0.0 else v

    def sqrt(self, x):
        if self.A.choice["final"] == "round2":
            v = OperatorLibrary(self.A._inner).sqrt(self.A._inner.num(x.to_decimal()))
            return self.n(decimal.Context(prec=self.A.digits,
                                          rounding="ROUND_HALF_UP").plus(v.to_decimal()))
        x = abs(x)
        if x == 0.0:
            return x
        how = self.A.choice["sqrt"]
        if how == "one":
            y = self.n(1)
        else:
            n = x.e // 2
            g = self.A._make(x.m, x.e - 2 * n)  # x / 10**(2n), exactly
            y = (g + 1.0) * 0.5
            y = self.A._make(y.m, y.e + n)  # times 10**n, exactly
        if how == "fixed":
            K = self.A.digits
            for _ in range(5 if K <= 8 else 6 if K <= 17 else 7 if K <= 35 else 8):
                y = (y + x / y) * 0.5
            return y
        y = (y + x / y) * 0.5
        while True:
            y1 = (y + x / y) * 0.5
            if y1 >= y:
                return y
            y = y1


@pytest.mark.parametrize("A", _tiered([IBM1410(K, variant=v) for K in (8, 12) for v in VARIANTS]
                                 + [IBM1410(8, variant=v) for v in ("taylor,cos=shift",
                                                                    "taylor,reduce=exact",
                                                                    "sine,final=round2")]),
                         ids=lambda A: f"{A.digits}-{A.variant}")
@settings(max_examples=40, deadline=None)
@given(x=st.one_of(st.floats(min_value=-50.0, max_value=50.0),
                   st.floats(min_value=-1e20, max_value=1e20)))
@example(x=0.7853981633974483)
@example(x=1.5707963)
@example(x=3.14159265)
@example(x=9999.0)  # COS by the shift: |x| + pi/2 out of SIN's range
def test_library_is_the_documented_algorithm(A, x):
    ref = OperatorLibrary(A)
    x = A.num(x)
    if abs(x) < 10000.0:
        assert A.SIN(x) == ref.trig(x, True)
        assert A.COS(x) == ref.trig(x, False)
    assert A.ATAN(x) == ref.atan(x)
    assert A.SQRT(x) == ref.sqrt(x)


# ----- ARCCOS from the listing terminates under the 1410 alignment rule -----------------
def arccos_listing(A: IBM1410, X, cap: int = 200):
    """Appendix C's FUNCTION ARCCOS in the model's arithmetic; returns (value, loops, SUM-SAVE)."""
    PI = A.num("3.14159265358979323846")
    ZMULT = A.num(1.0)
    PROD = A.num(1.0)
    SAVE = A.num("0.1E-50")
    XX = X
    X2 = XX * XX
    if not abs(XX) <= 0.7:
        XX = A.SQRT(1.0 - X2)
        X2 = XX * XX
    SUM = (PI / 2.0) - XX
    VAL = XX
    a = A.num(0.0)
    loops = 0
    while True:
        loops += 1
        if loops > cap:
            raise AssertionError(f"ARCCOS did not terminate in {cap} loops for X = {X}")
        a = a + 2.0
        PROD = PROD * a
        VAL = VAL * X2
        ZMULT = ZMULT * (a - 1.0)
        SUM = SUM - (ZMULT * VAL) / (PROD * (a + 1.0))
        if abs(SUM - SAVE) < 1e-8:
            break
        SAVE = SUM
    if X < -0.70:
        value = (PI / 2.0) + SUM
    elif X > 0.70:
        value = (PI / 2.0) - SUM
    else:
        value = SUM
    return value, loops, SUM - SAVE


@settings(max_examples=300, deadline=None)
@given(st.floats(min_value=-1.0, max_value=1.0))
@example(1.0)
@example(-1.0)
@example(0.7)
@example(-0.7)
@example(0.70000001)
@example(0.0)
@example(0.9999999)
def test_arccos_terminates_at_8_digits(x):
    X = A8.num(x)
    value, loops, last_step = arccos_listing(A8, X)
    # 1E-8 is below one unit in SUM's last place (SUM >= 0.77, so its ulp >= 1E-8):
    # the loop only ends once the term has dropped below SUM's last digit and SUM
    # stopped changing, i.e. SUM - SAVE is exactly zero.
    assert last_step == 0.0 and last_step.m == 0
    assert loops <= 25  # terms fall at least as fast as 0.49**k (19 on a 40001-point grid)
    exact = math.acos(float(X))
    # Each loop truncates SUM (ulp 1E-7 above 1.0) by up to one unit, and always
    # the same way: a downward bias of up to ~1E-7 per loop (1.1E-6 measured worst,
    # X = -0.6818).
    if abs(x) <= 0.99:
        assert abs(float(value) - exact) < 2e-6
    # Near |X| = 1, 1.0 - X*X cancels and the alignment has already dropped X*X's
    # last digit (1.0 has one digit less after the point): 1.0 - .99999998 = .1E-6.
    # That error of up to 1E-7 in 1 - X2 passes through SQRT: |sqrt a - sqrt b| <=
    # sqrt |a - b|.
    assert abs(float(value) - exact) < 2e-6 + math.sqrt(2e-7)


# ----- more digits, closer to exact -------------------------------------------------------
def test_results_approach_exact_as_K_grows():
    worst = {}
    for K, A in BY_K.items():
        e_sum = e_lib = e_acos = 0.0
        s = A.num(0)
        for k in range(1, 300):
            s = s + A.num(1) / A.num(k)
        exact = sum(Fraction(1, k) for k in range(1, 300))
        e_sum = abs(float(Fraction(D(s)) - exact))
        for i in range(1, 60):
            x = A.num(i / 10)
            e_lib = max(e_lib, err(A.SIN(x), mpmath.sin(mp(x))), err(A.COS(x), mpmath.cos(mp(x))),
                        err(A.ATAN(x), mpmath.atan(mp(x))),
                        float(abs(mp(A.SQRT(x)) - mpmath.sqrt(mp(x)))))
        for i in range(-19, 20):
            X = A.num(i / 20)
            e_acos = max(e_acos, float(abs(mp(arccos_listing(A, X)[0]) - mpmath.acos(mp(X)))))
        worst[K] = (e_sum, e_lib, e_acos)
    for j in range(2):  # the sum of 1/k and the library improve 10**4-fold per 4 digits
        assert worst[8][j] > 100 * worst[12][j] > 10**4 * worst[16][j]
        assert worst[8][j] < 1e-4 and worst[16][j] < 1e-12
    # ARCCOS's 1E-8 stopping test caps what more digits can buy
    assert worst[8][2] > worst[12][2] and worst[16][2] < 3e-8
