"""The faithful port against the modern engine, on random crank-rockers.

Two independent evaluations of the same model: the port
(``Program(Float64()).MAIN`` through ``emulator.sheet_values``: the ARCCOS
series, Case I / Case II, the listing's constants, TAN3) and the engine
(Heron's product, atan2, no tangent).  At every position the port prints in
[0, 360], every printed quantity must agree with the engine *evaluated at the
port's own ATH2* within a per-position tolerance derived below from what the
port gets wrong.  Nothing in it is fitted to the data.

Error sources of the port (float64; eps = 2.2e-16)
    1. ARCCOS: |ARCCOS(X) - acos(X)| <= 2e-8 (``ARCCOS_BOUND``, from
       tests/test_program.py), for each of PSI, ZLAM and BETA.
    2. Roundoff dX in the argument X (CPSI, CZLAM, CBETA), amplified by acos.
       ZL = SQRT(R2^2 + R1^2 - 2 R2 R1 CTH2) cancels: dZL <= 3 eps (R1+R2)^2 / ZL.
       X = (ZL^2 + a^2 - b^2) / (2 ZL a) has |dX/dZL| <= b / (ZL a), and its
       own rounding is <= 4 eps (ZL^2 + a^2 + b^2) / (2 ZL a).  acos turns dX
       into min(dX / |sin|, sqrt(2 dX)); the square root is the |X| -> 1 limit,
       and also covers the SQRT(ABS()) quirk when X rounds past +-1.  In the
       triangle A B O4, sin PSI = R4 s / ZL and sin ZLAM = R3 s / ZL, with
       s = |sin(th3 - th4)|, the sine of the transmission angle: this is where
       a near-toggle position loses its digits.
    3. The main program's RAD = 57.295779 is short by the factor
       rho = 8.9e-9, so TH2 = ATH2/RAD is off by d2 = |ATH2/RAD - radians(ATH2)|
       (<= 5.6e-8 rad at 360): the port solves the mechanism at a shifted crank
       angle, which moves th3 and th4 by |TH3D/TH2D| d2 and |TH4D/TH2D| d2; and
       ATH3 = TH3*RAD adds |ATH3| rho degrees.
    4. PI = 3.14159265 (short by 3.6e-9) in TH4 = PI - ZLAM -+ BETA and in the
       Case I/II test: within d2 + 3.6e-9 rad of 180 degrees (and at 360) the
       port may take the other branch, PSI +- BETA, an error of 2 BETA with
       BETA <= (R2/ZL) |th2 - k pi| (|dBETA/dth2| <= R2/ZL).
    Hence the angle error bound, per position, from the engine's geometry:

        eps_th = e_PSI + e_ZLAM + 2 e_BETA + 3.6e-9
                 + d2 (1 + (|TH3D| + |TH4D|) / |TH2D|) + 2 (R2/ZL) (d2 + 3.6e-9),
        e_X    = 2e-8 + min(dX / |sin X|, sqrt(2 dX))

    which bounds |d th3|, |d th4| and |d(th3 - th4)| to first order.

Propagation, and the tolerance
    Every other printed quantity is a polynomial in sines and cosines of
    th2, th3, th4 and the rates, divided by s once per level (TH3D, TH4D by
    S34; TH3DD, TH4DD by S43; the force steps by R4X TAN3 - R4Y =
    R4 sin(th3 - th4) / cos th3).  d(p/s) = dp/s - p cos ds/s^2, so one level
    multiplies the relative error by at most (1 + 1/s).  With *scales* that
    bound each quantity at this position by taking |sin|, |cos| <= 1 in its
    formula (so that they bound its angle derivatives too, and never vanish
    where the quantity happens to)::

        w3 = |TH2D| R2 / (R3 s),  w4 = |TH2D| R2 / (R4 s)         (>= |TH3D|, |TH4D|)
        a3 = (R2 TH2D^2 + R3 w3^2 + R4 w4^2) / (R3 s),  a4 = same / (R4 s)
        VG2: RG2 |TH2D|   VA: R2 |TH2D|   VG3: R2 |TH2D| + RG3 w3   VB: R4 w4   VG4: RG4 w4
        AG2: RG2 TH2D^2   AA: R2 TH2D^2   AG3: R2 TH2D^2 + RG3 (w3^2 + a3)
        AB: R4 (w4^2 + a4)   AG4: RG4 (w4^2 + a4)
        FGk = Wk/G (scale of AGk)
        f4 = (RG4 FG4 + ZI4 a4) / (R4 s),  g3 = (RG3 FG3 + ZI3 a3) / (R3 s)
        FA32: f4 + g3 + FG3   FB34: f4 + g3   FOA: f4 + g3 + FG3 + FG2   FOB: f4 + g3 + FG4
        SHAK, SHAKX, SHAKY: FOA + FOB   TORQ: R2 FA32

    the first-order error of q is at most K eps_th (1 + 1/s) scale(q), with K
    from the chain rule, level by level: 1 for TH3D, TH4D (one quotient by
    S34); 2 for velocities (rate error plus the direction error of the
    lever); 4 for TH3DD, TH4DD (w^2 carries 2 dw, for each of two rates, then
    the quotient); 5 for accelerations; 8 for forces and TORQ (one more
    quotient and the superposition sums).  So::

        |port - engine| <= K eps_th (1 + 1/s) scale(q)             (rates, vectors, TORQ)
        |port - engine| <= degrees(eps_th) + |ATH| rho + 1e-12     (ATH3, ATH4)
        |port - engine| (mod 360) <= degrees(tol(q) / |q|) + 1e-6  (direction of q)

    The 1e-6 degrees of a direction is VECTOR's own PI (2 x 3.6e-9 rad,
    4.1e-7 degrees) and RAD = 57.2957795 (360 x 2.3e-10).  A direction is
    compared only where its magnitude is at least 100 times the magnitude's
    tolerance: near a zero vector the direction is not determined.

    Measured on 15,000 random crank-rockers (drawn as in ``crank_rockers``), the largest ratio
    error / tolerance is 0.35 for ATH3 and ATH4, 0.25 for TH3D and TH4D, 0.10
    for velocities, 0.05 for TH3DD and TH4DD, 0.03 for accelerations and 0.02
    for forces and TORQ, always at angles past 200 degrees, where RAD's
    shift d2 is largest.  At the report's example the tolerance is, in the
    median over a revolution, 6e-7 of the value for TH3D, 4e-6 for TH3DD,
    1e-6 for velocities, 5e-6 for accelerations and 1e-5 to 4e-5 for forces
    and TORQ; a relative error of 1e-4 in any of them fails the test
    (``test_tolerance_catches_small_errors``).

Quirk cases
    Positions past 360 (the sheet past THMAX, Case II on the raw angle) and
    below 0 are not compared.  The 360 sheet is: the port takes Case II there
    with BETA ~ 0, within the bound.  ARCCOS's SQRT of a negative argument (a
    cosine rounded past 1) is within the bound (item 2).  The TAN3 / TAN4
    stand-in needs COS(TH3) == 0.0 exactly, which no double argument gives (the
    cosine of the double nearest pi/2 is 6.1e-17); a test forces it with a
    patched COS.  Outside these cases there is no NaN and no inf, in either.

The region
    A = R3/R2 and B = R4/R2 log-uniform in (1, 30), or A = B (the corner where
    C -> 1); C = R1/R2 anywhere between the boundaries |B-A| + 1 and A + B - 1
    (the toggles at 0 and 180 degrees), or 1e-7 to 1e-2 from either.  Closer
    than about 1e-8 to the corner A = B, C = 1 the port's ZL cancels to 0 at
    0 degrees and it divides by zero (``test_kite_corner_port_divides_by_zero``);
    the engine does not.  Near a toggle the tolerance grows like 1/s (and
    eps_th with it); at 1e-6 from the corner A = B the first-order bound
    exceeds the quantities themselves at 0 degrees: the port has no correct
    digits there, and the test says only that both are finite.
"""

from __future__ import annotations

import dataclasses
import math
from unittest import mock

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from conftest import DECKS
from sielaff.emulator.arithmetic import Float64
from sielaff.emulator.cards import Deck, Range, read_deck
from sielaff.emulator.program import SHEET_FIELDS, Program
from sielaff.emulator.run import sheet_values
from sielaff.engine import G, analyze
from sielaff.mechanism import EXAMPLE, Mechanism, crank_rocker_failure
from test_program import ARCCOS_BOUND

#: The port's SQRT(X*X+Y*Y) (VECTOR) is 0 below the root of the smallest normal double,
#: where X*X underflows; the engine's r |w| for a point turning about a pivot is not.
UNDERFLOW = 2.0 * float(np.sqrt(np.finfo(float).tiny))
MAGNITUDES = ("VG2", "VA", "VG3", "VB", "VG4", "AG2", "AA", "AG3", "AB", "AG4", "FA32",
              "FB34", "FOA", "FOB", "SHAK")

EPS = float(np.finfo(float).eps)
RAD_MAIN, PI_MAIN = 57.295779, 3.14159265
RHO = abs(RAD_MAIN * math.pi / 180.0 - 1.0)  # 8.9e-9
PI_ERROR = math.pi - PI_MAIN  # 3.6e-9
DIRECTION_FLOOR = 1e-6  # degrees: VECTOR's PI and RAD

PRINTED = tuple(name for group in SHEET_FIELDS for name in group)


def assert_rocker(m: Mechanism) -> None:
    assert crank_rocker_failure(m) is None


def port_sheets(m: Mechanism, ranges) -> list[dict[str, float]]:
    deck = Deck(mechanism=m, ranges=[Range(*r) for r in ranges],
                range_cards=list(range(7, 7 + len(ranges))), path="<test>")
    return list(sheet_values(deck))


def angle_error(m: Mechanism, ath2: np.ndarray, r: dict[str, np.ndarray]):
    """(s, eps_th): sine of the transmission angle and the port's angle-error bound."""
    th2 = np.radians(ath2)
    s = np.abs(np.sin(np.radians(r["GAMMA"])))
    beta = np.arctan2(-m.R2 * np.sin(th2), m.R1 - m.R2 * np.cos(th2))
    zl = np.hypot(m.R1 - m.R2 * np.cos(th2), m.R2 * np.sin(th2))
    th3, th4 = np.radians(r["ATH3"]), np.radians(r["ATH4"])
    dzl = 3.0 * EPS * (m.R1 + m.R2) ** 2 / zl

    def e_acos(sin_x, a, b):
        """ARCCOS of X = (ZL^2 + a^2 - b^2) / (2 ZL a), |sin acos X| = sin_x."""
        dx = (b / (zl * a)) * dzl + 4.0 * EPS * (zl * zl + a * a + b * b) / (2.0 * zl * a)
        with np.errstate(divide="ignore"):
            return ARCCOS_BOUND + np.minimum(dx / np.abs(sin_x), np.sqrt(2.0 * dx))

    e_psi = e_acos(np.sin(th3 - beta), m.R3, m.R4)  # th3 = beta + PSI
    e_zlam = e_acos(np.sin(th4 - beta), m.R4, m.R3)  # th4 = beta + pi - ZLAM
    e_beta = e_acos(np.sin(beta), m.R1, m.R2)
    d2 = np.abs(ath2 / RAD_MAIN - th2) + 4.0 * EPS * np.abs(th2)
    rates = (np.abs(r["TH3D"]) + np.abs(r["TH4D"])) / abs(m.TH2D)
    eps_th = (e_psi + e_zlam + 2.0 * e_beta + PI_ERROR + 1e-12 + d2 * (1.0 + rates)
              + 2.0 * (m.R2 / zl) * (d2 + PI_ERROR))
    return s, eps_th


def scales(m: Mechanism, s: np.ndarray) -> dict[str, tuple[float, np.ndarray]]:
    """(K, scale) for each printed rate, vector magnitude and component (see module doc)."""
    w2 = abs(m.TH2D)
    rg2, rg3, rg4 = abs(m.RG2), abs(m.RG3), abs(m.RG4)
    w3 = w2 * m.R2 / (m.R3 * s)  # >= |TH3D|
    w4 = w2 * m.R2 / (m.R4 * s)
    num = m.R2 * w2 * w2 + m.R3 * w3 * w3 + m.R4 * w4 * w4
    a3, a4 = num / (m.R3 * s), num / (m.R4 * s)  # >= |TH3DD|, |TH4DD|
    v = {"VG2": rg2 * w2, "VA": m.R2 * w2, "VG3": m.R2 * w2 + rg3 * w3, "VB": m.R4 * w4,
         "VG4": rg4 * w4}
    a = {"AG2": rg2 * w2 * w2, "AA": m.R2 * w2 * w2, "AG3": m.R2 * w2 * w2 + rg3 * (w3 * w3 + a3),
         "AB": m.R4 * (w4 * w4 + a4), "AG4": rg4 * (w4 * w4 + a4)}
    fg2, fg3, fg4 = (abs(w) / G * a[k] for w, k in ((m.W2, "AG2"), (m.W3, "AG3"), (m.W4, "AG4")))
    f4 = (rg4 * fg4 + abs(m.ZI4) * a4) / (m.R4 * s)  # link 4's superposition step
    g3 = (rg3 * fg3 + abs(m.ZI3) * a3) / (m.R3 * s)  # link 3's
    f = {"FA32": f4 + g3 + fg3, "FB34": f4 + g3, "FOA": f4 + g3 + fg3 + fg2,
         "FOB": f4 + g3 + fg4}
    f["SHAK"] = f["FOA"] + f["FOB"]  # SHAK = FOA + FOB, whatever their cancellation
    out = {"TH3D": (1.0, w3), "TH4D": (1.0, w4), "TH3DD": (4.0, a3), "TH4DD": (4.0, a4)}
    out |= {k: (2.0, x) for k, x in v.items()}
    out |= {k: (5.0, x) for k, x in a.items()}
    out |= {k: (8.0, x) for k, x in f.items()}
    out |= {"SHAKX": out["SHAK"], "SHAKY": out["SHAK"], "TORQ": (8.0, m.R2 * f["FA32"])}
    return out


def mismatches(m: Mechanism, sheets, perturb=None) -> list[str]:
    """Every printed quantity outside its tolerance, as readable lines ([] if none).

    ``perturb(name, engine_values)`` may alter the engine's values (to show that
    the tolerance bites).
    """
    sheets = [sh for sh in sheets if 0.0 <= sh["ATH2"] <= 360.0]
    if not sheets:
        return []
    ath2 = np.array([sh["ATH2"] for sh in sheets])
    with np.errstate(divide="raise", over="raise", invalid="raise"):
        r = analyze(m, ath2)
    s, eps_th = angle_error(m, ath2, r)
    amp = eps_th * (1.0 + 1.0 / s)
    scale = {name: k * x for name, (k, x) in scales(m, s).items()}
    bad = []
    for name in PRINTED:
        port = np.array([sh[name] for sh in sheets])
        eng = r[name] if perturb is None else perturb(name, r[name].copy())
        if not (np.all(np.isfinite(port)) and np.all(np.isfinite(eng))):
            bad.append(f"{name}: not finite: port {port}, engine {eng}")
            continue
        if name in ("ATH2", "TEX"):  # the angle asked for; TEX = 0.0 in both
            diff, tol = np.abs(port - eng), np.zeros_like(port)
        elif name in ("ATH3", "ATH4"):
            diff = np.abs((port - eng + 180.0) % 360.0 - 180.0)
            tol = np.degrees(eps_th) + np.abs(eng) * RHO * 1.001 + 1e-12
        elif name.startswith("D"):
            magnitude = r[name[1:]]
            tol_xy = amp * scale[name[1:]]
            determined = (magnitude > UNDERFLOW) & (tol_xy * 100.0 <= magnitude)
            diff = np.where(determined, np.abs((port - eng + 180.0) % 360.0 - 180.0), 0.0)
            tol = np.degrees(tol_xy / np.where(determined, magnitude, 1.0)) + DIRECTION_FLOOR
        else:
            diff, tol = np.abs(port - eng), amp * scale[name]
            if name in MAGNITUDES:
                tol = tol + UNDERFLOW
        for i in np.flatnonzero(~(diff <= tol)):
            bad.append(f"{name} at ATH2 = {ath2[i]!r}: port {port[i]!r}, engine {eng[i]!r}, "
                       f"|diff| {diff[i]:.3g} > tol {tol[i]:.3g} (s = {s[i]:.3g})")
    return bad


def check(m: Mechanism, ranges) -> list[dict[str, float]]:
    sheets = port_sheets(m, ranges)
    bad = mismatches(m, sheets)
    assert not bad, "\n".join([str(m), *bad[:20]])
    return sheets


# --------------------------------------------------------------------------
# Random crank-rockers
# --------------------------------------------------------------------------

#: The five special angles, in one card: 0, 90, 180, 270, 360 (the sheet past
#: THMAX = 270) and 450 (past 360: not compared).
SPECIAL = (0.0, 90.0, 270.0)

log_ratio = st.floats(min_value=1e-6, max_value=math.log(30.0))  # A, B = e^x in (1, 30)
#: Distance from a boundary of the region, normalised by R2 (down to 1e-7: see
#: ``test_kite_corner_port_divides_by_zero`` for what lies closer).
near = st.one_of(
    st.floats(min_value=-7.0, max_value=-2.0).map(lambda x: 10.0**x),
    st.just(1e-6),
)
angle = st.one_of(
    st.floats(min_value=0.0, max_value=360.0),
    st.sampled_from([0.0, 90.0, 180.0, 270.0, 360.0, 180.0 - 1e-6, 180.0 - 1e-9,
                     360.0 - 1e-6, 1e-6, 180.0 + 1e-6]),
)


@st.composite
def crank_rockers(draw):
    a = math.exp(draw(log_ratio))
    b = draw(st.one_of(log_ratio.map(math.exp),  # anywhere, or A ~ B: the kite corner
                       st.sampled_from([0.0, 1e-9, 1e-6]).map(lambda e: a * (1.0 + e))))
    lo, hi = abs(b - a) + 1.0, a + b - 1.0
    assume(hi - lo > 2e-7)
    where = draw(st.sampled_from(["inside", "low", "high"]))
    if where == "inside":
        c = lo + draw(st.floats(min_value=1e-3, max_value=1.0 - 1e-3)) * (hi - lo)
    else:
        d = min(draw(near), (hi - lo) / 2.0)
        c = lo + d if where == "low" else hi - d
    c = min(max(c, lo + 1e-7), hi - 1e-7)
    r2 = 10.0 ** draw(st.floats(min_value=-2.0, max_value=2.0))
    unit = st.floats(min_value=0.0, max_value=1.0)
    w = [20.0 * draw(unit) for _ in range(3)]
    zi = [2.0 * draw(unit) for _ in range(3)]
    adel = [draw(st.floats(min_value=-180.0, max_value=180.0)) for _ in range(3)]
    th2d = draw(st.sampled_from([-1.0, 1.0])) * 10.0 ** draw(st.floats(-1.0, 3.0))
    m = Mechanism(W2=w[0], W3=w[1], W4=w[2], ZI2=zi[0], ZI3=zi[1], ZI4=zi[2],
                  R1=c * r2, R2=r2, R3=a * r2, R4=b * r2,
                  ADEL2=adel[0], ADEL3=adel[1], ADEL4=adel[2],
                  RG2=2.0 * r2 * draw(unit), RG3=2.0 * a * r2 * draw(unit),
                  RG4=2.0 * b * r2 * draw(unit), TH2D=th2d)
    assume(crank_rocker_failure(m) is None)  # the port's own test, in its rounding
    return m


@given(m=crank_rockers(), ath2=angle, delta=st.floats(min_value=1e-6, max_value=360.0))
@example(m=EXAMPLE, ath2=40.0, delta=10.0)
@example(m=dataclasses.replace(EXAMPLE, R1=9.0, R2=3.7, R3=8.0, R4=6.0), ath2=180.0, delta=1.0)
@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
def test_port_agrees_with_engine(m, ath2, delta):
    """Card (0, 90, 270): 0, 90, 180, 270, 360; card (a, d, a): a and a + d."""
    sheets = check(m, [SPECIAL, (ath2, delta, ath2)])
    compared = [sh["ATH2"] for sh in sheets if 0.0 <= sh["ATH2"] <= 360.0]
    assert {0.0, 90.0, 180.0, 270.0, 360.0} <= set(compared)


# --------------------------------------------------------------------------
# Fixed cases: the example deck, the quirks
# --------------------------------------------------------------------------


def test_example_deck_every_degree():
    deck = read_deck(DECKS / "example.dat")
    check(deck.mechanism, [(0.0, 1.0, 359.0)])  # 0 .. 360 (the sheet past THMAX)


NEAR_TOGGLE = [  # (A, B, C) with R2 = 1: lo = |B-A|+1, hi = A+B-1
    ("low", 3.5, 4.5, 2.0 + 1e-6),
    ("high", 3.5, 4.5, 7.0 - 1e-6),
    ("mid", 3.5, 4.5, 4.5),
    ("kite", 4.0, 4.0, 1.0 + 1e-6),  # A = B: ZL = 1e-6 at 0 degrees
]


@pytest.mark.parametrize("label,a,b,c", NEAR_TOGGLE, ids=[t[0] for t in NEAR_TOGGLE])
def test_near_toggle_every_degree_and_the_special_angles(label, a, b, c):
    m = dataclasses.replace(EXAMPLE, R1=c, R2=1.0, R3=a, R4=b, RG2=0.5, RG3=a / 2, RG4=b / 2)
    assert_rocker(m)
    check(m, [(0.0, 1.0, 359.0), (180.0 - 1e-6, 1e-6, 180.0 - 1e-6), SPECIAL,
              (1e-9, 1e-9, 1e-9)])


def test_the_360_sheet_takes_case_ii_and_agrees():
    notices = []
    for m in (EXAMPLE, dataclasses.replace(EXAMPLE, R1=9.0, R2=3.7, R3=8.0, R4=6.0)):
        deck = Deck(mechanism=m, ranges=[Range(360.0, 1.0, 360.0)], range_cards=[7], path="t")
        Program(Float64(), lambda kind, text: notices.append(text)).MAIN(deck, lambda *a: None)
        assert 360.0 / RAD_MAIN >= PI_MAIN  # Case II, although 360 is the 0 position
        sheets = check(m, [(360.0, 1.0, 360.0)])
        assert [sh["ATH2"] for sh in sheets] == [360.0, 361.0]
    assert notices and all("361" in t for t in notices)  # only the 361 sheet is a quirk


def test_sqrt_of_negative_argument_positions_agree():
    """Here CBETA rounds past 1 at a dead centre: ARCCOS takes SQRT(ABS(1 - X*X))."""
    m = dataclasses.replace(EXAMPLE, R1=9.0, R2=3.7, R3=8.0, R4=6.0)
    negatives = []
    real_sqrt = Float64.SQRT

    def spy(self, x):
        if x < 0.0:
            negatives.append(x)
        return real_sqrt(self, x)

    with mock.patch.object(Float64, "SQRT", spy):
        check(m, [SPECIAL])
    assert negatives and max(negatives) < 0.0 and min(negatives) > -1e-14


def test_tan3_stand_in_agrees():
    """COS(TH3) forced to exactly 0.0 where TH3 is 90 degrees: TAN3 = 0.9E+25.

    At 60 degrees A = (1/2, sqrt(3)/2); B = A + (0, 3) straight above it.
    """
    m = dataclasses.replace(EXAMPLE, R1=4.0, R2=1.0, R3=3.0,
                            R4=math.hypot(3.5, 3.0 + math.sqrt(3.0) / 2.0))
    assert_rocker(m)
    assert float(analyze(m, 60.0, ["ATH3"])["ATH3"]) == pytest.approx(90.0, abs=1e-12)
    forced = []

    def cos(x):
        c = math.cos(x)
        if abs(c) < 1e-7:  # the port's TH3 is pi/2 to ARCCOS's 2e-8
            forced.append(c)
            return 0.0
        return c

    real_init = Float64.__init__

    def init(self, *args, **kwargs):
        real_init(self, *args, **kwargs)
        self.COS = cos

    notices = []
    with mock.patch.object(Float64, "__init__", init):
        deck = Deck(mechanism=m, ranges=[Range(60.0, 1.0, 60.0)], range_cards=[7], path="t")
        Program(Float64(), lambda kind, text: notices.append(kind)).MAIN(deck, lambda *a: None)
        assert notices == ["tan-standin", "past-thmax"]
        forced.clear()
        check(m, [(60.0, 1.0, 60.0)])
    assert len(forced) == 1  # COS(TH3) at 60 degrees, nothing else


def test_no_double_has_a_cosine_of_exactly_zero_near_pi_over_2():
    x = math.pi / 2
    for _ in range(1000):
        assert math.cos(x) != 0.0
        x = math.nextafter(x, 0.0)


def test_tolerance_catches_small_errors():
    """The bound is tight enough to see a 1e-4 relative error in any quantity."""
    deck = read_deck(DECKS / "example.dat")
    m = deck.mechanism
    sheets = port_sheets(m, [(0.0, 5.0, 355.0)])
    assert mismatches(m, sheets) == []
    for name in ("TH3D", "TH4DD", "VG3", "AB", "FA32", "FOB", "SHAKY", "TORQ"):
        bad = mismatches(m, sheets, lambda n, v, name=name: v * (1 + 1e-4) if n == name else v)
        assert bad and all(line.startswith(name) for line in bad), name
    for name, shift in (("ATH3", 1e-4), ("ATH4", -1e-4), ("DVG3", 1e-2), ("DFB34", -1e-2)):
        bad = mismatches(m, sheets, lambda n, v, name=name, d=shift: v + d if n == name else v)
        assert bad and all(line.startswith(name) for line in bad), name
    # the example's median relative tolerances quoted in the module docstring
    ath2 = np.array([sh["ATH2"] for sh in sheets if sh["ATH2"] <= 360.0])
    r = analyze(m, ath2)
    s, eps_th = angle_error(m, ath2, r)
    for name, most in (("TH3D", 1e-6), ("TH3DD", 1e-5), ("VG3", 3e-6), ("AG3", 1e-5),
                       ("FA32", 3e-5), ("TORQ", 6e-5)):
        k, scale = scales(m, s)[name]
        assert np.median(k * eps_th * (1.0 + 1.0 / s) * scale / np.abs(r[name])) < most, name


def test_kite_corner_port_divides_by_zero():
    """Closer than ~1e-8 to the corner A = B, C = 1 of the region, the port fails.

    R1 - R2 = 1e-9 R2: at 0 degrees ZL = SQRT(R2*R2 + R1*R1 - 2*R2*R1*CTH2)
    cancels to exactly 0 and CPSI divides by it.  The engine's d = O4 - A is
    R1 - R2 cos th2, exact there, and stays finite.
    """
    m = dataclasses.replace(EXAMPLE, R1=1.0 + 1e-9, R2=1.0, R3=1.5, R4=1.5)
    assert_rocker(m)
    with pytest.raises(ZeroDivisionError):
        port_sheets(m, [(0.0, 1.0, 0.0)])
    r = analyze(m, np.array([0.0, 1e-9, 90.0]))
    assert all(np.all(np.isfinite(v)) for v in r.values())
