"""Line-by-line port of Sielaff's 1966 program (report, Appendix C).

Hold this file against the listing: the FORTRAN names are kept, statement
numbers appear as ``# 00054``-style comments, and the control flow is the
listing's, quirks included:

* the crank-rocker test (statements 45-52) prints
  ``THIS IS NOT A CRANK ROCKER MECHANISM`` and stops;
* the loop prints a sheet and only then tests ``ATH2.GT.THMAX``, so one
  sheet past THMAX is always printed (THZERO=10, DELTA=10, THMAX=360
  prints 37 sheets, the last at 370);
* Case I / Case II is chosen by ``TH2.GE.PI`` on the raw angle, so angles
  past one revolution take the Case II branch;
* ``TAN3`` and ``TAN4`` become 0.9E+25 when the cosine is exactly zero;
* after the last sheet of a range the next range card is read, until the
  deck ends.

The arithmetic is not written in here: ``Program(ar)`` runs on any model
from ``sielaff.emulator.arithmetic`` (float64, float32, ibm1410:K).  Literals such
as ``2.0`` stay in the code as in the listing; each model converts them
(the 1410 by truncation to K digits).

Inputs: a ``sielaff.emulator.cards.Deck`` (mechanism fields in the report's units:
lb, in-lb-sec^2, in, degrees, rad/sec; range cards in degrees).
Outputs: WRITE calls ``write(format_number, *values)``; quirks the 1410
would not have mentioned go to ``notice(kind, text)`` (stderr in the CLI).
"""

from __future__ import annotations

from collections.abc import Callable

#: The listing's FORMAT statements (10, 11, 15 and 16 reconstructed, see docs/).
FORMATS: dict[int, str] = {
    1: "(11X,3F12.1/)",
    2: "(15X,4E12.4/)",
    3: "(11X,4F12.1/)",
    4: "(11X,1F12.1/)",
    5: "(15X,1E12.4/)",
    6: "(15X,3E12.4/)",
    7: "(/)",
    8: "(11X,5F12.1/)",
    9: "(15X,5E12.4/)",
    10: "(//18X,7HTHETA 2,5X,7HTHETA 3,5X,7HTHETA 4/)",
    11: "(//18X,9HANG VEL 3,3X,9HANG VEL 4,3X,9HANG ACC 3,3X,9HANG ACC 4/)",
    12: "(//18X,12HEX TORQ ON 4/)",
    13: "(//18X,6HVEL G2,6X,5HVEL A,7X,6HVEL G3,6X,5HVEL B,7X,6HVEL G4/)",
    14: "(//18X,6HACC G2,6X,5HACC A,7X,6HACC G3,6X,5HACC B,7X,6HACC G4/)",
    15: "(//18X,8HF 3 ON 2,4X,8HF 3 ON 4,4X,8HF 2 ON 1,4X,8HF 4 ON 1/)",
    16: "(//18X,5HSHAKE,7X,7HX SHAKE,5X,7HY SHAKE/)",
    17: "(//18X,12HDRIVING TORQ/)",
    18: "(1H1)",
    19: "(4F8.4)",
    20: "(37H THIS IS NOT A CRANK ROCKER MECHANISM)",
}

#: The quantities each value-carrying WRITE prints, in listing order.
SHEET_FIELDS: tuple[tuple[str, ...], ...] = (
    ("ATH2", "ATH3", "ATH4"),
    ("TH3D", "TH4D", "TH3DD", "TH4DD"),
    ("TEX",),
    ("VG2", "VA", "VG3", "VB", "VG4"),
    ("DVG2", "DVA", "DVG3", "DVB", "DVG4"),
    ("AG2", "AA", "AG3", "AB", "AG4"),
    ("DAG2", "DAA", "DAG3", "DAB", "DAG4"),
    ("FA32", "FB34", "FOA", "FOB"),
    ("DFA32", "DFB34", "DFOA", "DFOB"),
    ("SHAK", "SHAKX", "SHAKY"),
    ("DSHAK",),
    ("TORQ",),
)
FORCE_FIELDS = SHEET_FIELDS[7:]
KINEMATIC_FIELDS = SHEET_FIELDS[:7]

#: ARCCOS gives up after this many terms rather than loop for ever.
ARCCOS_MAX_TERMS = 10_000


class NotCrankRocker(Exception):
    """The deck's lengths fail the crank-rocker test (statement 52); the message says which
    of statements 45-51 failed, in the run's arithmetic."""


def first_failed_test(A, B, C, ABS) -> str | None:
    """The first of the tests of statements 45-51 that fails (its FORTRAN text), in the
    arithmetic A, B and C are in, or None when the program would go on to statement 54."""
    tests = (("A.GT.1.0", A > 1.0), ("B.GT.1.0", B > 1.0), ("C.GT.1.0", C > 1.0),
             ("C.LT.(A+B-1.0)", C < (A + B - 1.0)), ("C.GT.(ABS(B-A)+1.0)", C > (ABS(B - A) + 1.0)))
    return next((text for text, ok in tests if not ok), None)


def _failed_test(A, B, C, ABS, arithmetic: str) -> str:
    """The refusal's text: which test of statements 45-51 failed, as the program evaluated it."""
    failed = first_failed_test(A, B, C, ABS) or "?"
    return (f"IF({failed}) fails in {arithmetic} arithmetic (A = {float(A):.9g}, "
            f"B = {float(B):.9g}, C = {float(C):.9g})")


class SheetLimit(Exception):
    """``max_sheets`` sheets were printed and the program would have printed more."""


class ProgramError(Exception):
    """The 1966 arithmetic failed (division by zero, overflow, runaway loop)."""


Write = Callable[..., None]
Notice = Callable[[str, str], None]


def _no_notice(kind: str, text: str) -> None:
    pass


class Program:
    """The main program with its FUNCTION ARCCOS and SUBROUTINE VECTOR, on one arithmetic."""

    def __init__(self, ar, notice: Notice = _no_notice) -> None:
        self.ar = ar
        self.notice = notice
        # FUNCTION ARCCOS: PI=3.14159265358979323846 (converted once, as a compiler would)
        self._PI_ARCCOS = ar.num("3.14159265358979323846")

    # ------------------------------------------------------------------
    def ARCCOS(self, X):
        """FUNCTION ARCCOS(X): arc cosine in radians by the arcsine series.

        For |X| <= 0.7 the series runs on X; beyond it on SQRT(1-X*X), then
        the result is reflected.  Stops when two partial sums differ by
        less than 1E-8, as in the listing.
        """
        SQRT, ABS = self.ar.SQRT, self.ar.ABS
        PI = self._PI_ARCCOS
        num = self.ar.num  # a constant assigned is converted, as the compiler converted it
        ZMULT = num(1.0)
        PROD = num(1.0)
        SAVE = num(0.1E-50)
        XX = X
        X2 = XX * XX
        if not ABS(XX) <= 0.7:
            XX = SQRT(1.0 - X2)
            X2 = XX * XX
        SUM = (PI / 2.0) - XX                                   # 5
        VAL = XX
        A = num(0.0)
        for _ in range(ARCCOS_MAX_TERMS):
            A = A + 2.0                                         # 100
            PROD = PROD * A
            VAL = VAL * X2
            ZMULT = ZMULT * (A - 1.0)
            SUM = SUM - (ZMULT * VAL) / (PROD * (A + 1.0))
            if ABS(SUM - SAVE) < 0.00000001:
                break                                           # GO TO 200
            SAVE = SUM
        else:
            raise ProgramError(f"ARCCOS({X}) series did not converge in {ARCCOS_MAX_TERMS} terms")
        if X < -0.70:                                           # 200
            return (PI / 2.0) + SUM                             # 103
        if X > 0.70:
            return (PI / 2.0) - SUM                             # 101
        return SUM

    # ------------------------------------------------------------------
    def VECTOR(self, X, Y):
        """SUBROUTINE VECTOR(X,Y,VECT,DIRECT): magnitude and direction (degrees) of (X, Y)."""
        ar = self.ar
        ANG = ar.num(0.0)
        PI = ar.num(3.14159265)
        RAD = ar.num(57.2957795)
        if X == 0.0:                                            # IF(X)36,37,36
            if Y < 0.0:                                         # 37 IF(Y)38,42,40
                ANG = (3.0 * PI) / 2.0                          # 38
            elif Y > 0.0:
                ANG = PI / 2.0                                  # 40
        else:
            ARC = ar.ATAN(ar.ABS(Y) / ar.ABS(X))                # 36
            if X > 0.0:                                         # 41 IF(X)30,42,31
                if Y < 0.0:                                     # 31 IF(Y)32,33,33
                    ANG = 2.0 * PI - ARC                        # 32
                else:
                    ANG = ARC                                   # 33
            elif Y < 0.0:                                       # 30 IF(Y)34,35,35
                ANG = PI + ARC                                  # 34
            else:
                ANG = PI - ARC                                  # 35
        DIRECT = ANG * RAD                                      # 42
        VECT = ar.SQRT(X * X + Y * Y)
        return VECT, DIRECT

    # ------------------------------------------------------------------
    def MAIN(self, deck, write: Write, kinematics_only: bool = False,
             max_sheets: int | None = None, tex: float = 0.0, start: int = 1) -> int:
        """Run the program on a deck; returns the number of sheets printed.

        ``kinematics_only`` does what page 18 of the report says: removes
        statements 133-202 and their WRITE statements.  ``max_sheets``
        raises SheetLimit before a sheet past that count (not in the 1966
        program).  ``tex`` is the report's edit of statement 74, ``TEX = constant``
        ("In other uses this could be TEX = CONSTANT"), converted like a FORTRAN
        constant in the run's arithmetic.  ``start`` (not in the 1966 program either)
        begins each range card's loop at I = start instead of 1: the vectorised listing
        (``emulator.vector``) hands single sheets back to the port this way.  Raises
        NotCrankRocker after printing the 1966 message.
        """
        ar, notice = self.ar, self.notice
        num, SIN, COS, SQRT, ABS = ar.num, ar.SIN, ar.COS, ar.SQRT, ar.ABS
        ARCCOS, VECTOR = self.ARCCOS, self.VECTOR
        m = deck.mechanism
        W2, W3, W4 = num(m.W2), num(m.W3), num(m.W4)            # READ(1,19)W2,W3,W4
        ZI2, ZI3, ZI4 = num(m.ZI2), num(m.ZI3), num(m.ZI4)  # noqa: F841  READ(1,19)ZI2,ZI3,ZI4
        R1, R2, R3, R4 = num(m.R1), num(m.R2), num(m.R3), num(m.R4)
        ADEL2, ADEL3, ADEL4 = num(m.ADEL2), num(m.ADEL3), num(m.ADEL4)
        RG2, RG3, RG4 = num(m.RG2), num(m.RG3), num(m.RG4)
        TH2D = num(m.TH2D)                                      # READ(1,19)TH2D
        sheets = 0
        for THZERO, DELTA, THMAX in deck.ranges:                # 00027 READ(1,19)THZERO,DELTA,THMAX
            THZERO, DELTA, THMAX = num(THZERO), num(DELTA), num(THMAX)
            G = num(386.0880)
            ZM2 = W2 / G
            ZM3 = W3 / G
            ZM4 = W4 / G
            TH = THZERO - DELTA
            I = start - 1
            RAD = num(57.295779)
            PI = num(3.14159265)
            SQ2D = TH2D * TH2D
            DEL2 = ADEL2 / RAD
            DEL3 = ADEL3 / RAD
            DEL4 = ADEL4 / RAD
            A = R3 / R2
            B = R4 / R2
            C = R1 / R2
            if not (A > 1.0                                     # IF(A.GT.1.0)GOTO45
                    and B > 1.0                                 # 45 IF(B.GT.1.0)GOTO47
                    and C > 1.0                                 # 47 IF(C.GT.1.0)GOTO49
                    and C < (A + B - 1.0)                       # 49 IF(C.LT.(A+B-1.0))GOTO51
                    and C > (ABS(B - A) + 1.0)):                # 51 IF(C.GT.(ABS(B-A)+1.0))GOTO54
                write(20)                                       # 52 WRITE(3,20)
                raise NotCrankRocker(_failed_test(A, B, C, ABS, ar.name))  # GOTO 237
            while True:
                if max_sheets is not None and sheets >= max_sheets:
                    raise SheetLimit(sheets)
                I = I + 1                                       # 00054
                ZZZ = num(I)
                ATH2 = TH + ZZZ * DELTA
                TH2 = ATH2 / RAD
                CTH2 = COS(TH2)
                ZL = SQRT(R2 * R2 + R1 * R1 - 2.0 * R2 * R1 * CTH2)
                CPSI = (-(R4 * R4) + ZL * ZL + R3 * R3) / (2.0 * ZL * R3)
                PSI = ARCCOS(CPSI)
                CZLAM = (ZL * ZL + R4 * R4 - R3 * R3) / (2.0 * ZL * R4)
                ZLAM = ARCCOS(CZLAM)
                CBETA = (ZL * ZL + R1 * R1 - R2 * R2) / (2.0 * ZL * R1)
                BETA = ARCCOS(CBETA)
                if TH2 >= PI:                                   # IF(TH2.GE.PI)GOTO70
                    TH3 = PSI + BETA                            # 00070
                    TH4 = PI - ZLAM + BETA
                    if ATH2 > 360.0:
                        notice("case-ii", f"THETA 2 = {float(ATH2):g} is past one revolution: "
                               "the 1966 program takes the Case II branch (TH2 >= PI), "
                               "so this sheet's THETA 3 and THETA 4 are not the mechanism's")
                else:
                    TH3 = PSI - BETA
                    TH4 = PI - ZLAM - BETA
                    if ATH2 < 0.0:
                        notice("case-i", f"THETA 2 = {float(ATH2):g} is below zero: the 1966 "
                               "program takes the Case I branch (TH2 < PI), so this sheet's "
                               "THETA 3 and THETA 4 are not the mechanism's")
                ATH3 = TH3 * RAD                                # 00072
                ATH4 = TH4 * RAD
                TEX = num(tex)                                  # 00074 TEX=0.0 (--tex)
                S42 = SIN(TH4 - TH2)
                S34 = SIN(TH3 - TH4)
                S32 = SIN(TH3 - TH2)
                C42 = COS(TH4 - TH2)
                C43 = COS(TH4 - TH3)
                S43 = SIN(TH4 - TH3)
                C32 = COS(TH3 - TH2)
                C34 = COS(TH3 - TH4)
                STHDE2 = SIN(TH2 + DEL2)
                CTHDE2 = COS(TH2 + DEL2)
                STHDE3 = SIN(TH3 + DEL3)
                CTHDE3 = COS(TH3 + DEL3)
                STHDE4 = SIN(TH4 + DEL4)
                CTHDE4 = COS(TH4 + DEL4)
                STH4 = SIN(TH4)
                CTH4 = COS(TH4)
                STH3 = SIN(TH3)
                CTH3 = COS(TH3)
                STH2 = SIN(TH2)
                CTH2 = COS(TH2)
                TH3D = (R2 / R3) * TH2D * (S42 / S34)
                TH4D = (R2 / R4) * TH2D * (S32 / S34)
                SQ3D = TH3D * TH3D
                SQ4D = TH4D * TH4D
                TH3DD = (R2 * SQ2D * C42 + R3 * SQ3D * C43 - R4 * SQ4D) / (R3 * S43)
                TH4DD = (-R2 * SQ2D * C32 + R4 * SQ4D * C34 - R3 * SQ3D) / (R4 * S34)
                R2X = R2 * CTH2
                R2Y = R2 * STH2
                RGX = RG2 * CTHDE2  # noqa: F841  (the listing's RGX, RGY: never used again)
                RGY = RG2 * STHDE2  # noqa: F841
                R3X = R3 * CTH3
                R3Y = R3 * STH3
                RG3X = RG3 * CTHDE3
                RG3Y = RG3 * STHDE3
                R4X = R4 * CTH4
                R4Y = R4 * STH4
                RG4X = RG4 * CTHDE4
                RG4Y = RG4 * STHDE4
                VAX = -R2 * TH2D * STH2
                VAY = R2 * TH2D * CTH2
                AAX = -R2 * SQ2D * CTH2
                AAY = -R2 * SQ2D * STH2
                VG2X = -RG2 * TH2D * STHDE2
                VG2Y = RG2 * TH2D * CTHDE2
                AG2X = -RG2 * SQ2D * CTHDE2
                AG2Y = -RG2 * SQ2D * STHDE2
                VBX = -R4 * TH4D * STH4
                VBY = R4 * TH4D * CTH4
                ABX = -R4 * SQ4D * CTH4 - R4 * TH4DD * STH4
                ABY = -R4 * SQ4D * STH4 + R4 * TH4DD * CTH4
                VG4X = -RG4 * TH4D * STHDE4
                VG4Y = RG4 * TH4D * CTHDE4
                AG4X = -RG4 * SQ4D * CTHDE4 - RG4 * TH4DD * STHDE4
                AG4Y = -RG4 * SQ4D * STHDE4 + RG4 * TH4DD * CTHDE4
                VG3X = VAX - RG3 * TH3D * STHDE3
                VG3Y = VAY + RG3 * TH3D * CTHDE3
                AG3X = AAX - RG3 * SQ3D * CTHDE3 - RG3 * TH3DD * STHDE3
                AG3Y = AAY - RG3 * SQ3D * STHDE3 + RG3 * TH3DD * CTHDE3
                if not kinematics_only:
                    FG4X = -ZM4 * AG4X                          # 00133
                    FG4Y = -ZM4 * AG4Y
                    TI4 = -ZI4 * TH4DD
                    if CTH3 == 0.0:                             # IF(CTH3.EQ.0.0)GOTO139
                        TAN3 = 0.9E+25                          # 00139
                        notice("tan-standin", f"THETA 2 = {float(ATH2):g}: COS(TH3) is exactly 0, "
                               "the 1966 program uses TAN3 = 0.9E+25")
                    else:
                        TAN3 = STH3 / CTH3
                    FP34X = (-RG4X * FG4Y + RG4Y * FG4X - TI4 - TEX) / (R4X * TAN3 - R4Y)  # 00140
                    FP43X = -FP34X  # noqa: F841
                    FP34Y = FP34X * TAN3
                    FP43Y = -FP34Y  # noqa: F841
                    FP14X = -FG4X - FP34X
                    FP41X = -FP14X
                    FP14Y = -FG4Y - FP34Y
                    FP41Y = -FP14Y
                    FP23X = FP34X
                    FP32X = -FP23X
                    FP23Y = FP34Y
                    FP32Y = -FP23Y
                    FP12Y = FP23Y
                    FP21Y = -FP12Y
                    FP12X = FP23X
                    FP21X = -FP12X
                    TP2 = -R2X * FP32Y + R2Y * FP32X
                    TI3 = -ZI3 * TH3DD
                    FG3X = -ZM3 * AG3X
                    FG3Y = -ZM3 * AG3Y
                    if CTH4 == 0.0:                             # IF(CTH4.EQ.0.0)GOTO163
                        TAN4 = 0.9E+25                          # 00163
                        notice("tan-standin", f"THETA 2 = {float(ATH2):g}: COS(TH4) is exactly 0, "
                               "the 1966 program uses TAN4 = 0.9E+25")
                    else:
                        TAN4 = STH4 / CTH4
                    FPP43X = (-RG3X * FG3Y + RG3Y * FG3X - TI3) / (R3X * TAN4 - R3Y)  # 00164
                    FPP34X = -FPP43X
                    FPP43Y = FPP43X * TAN4
                    FPP34Y = -FPP43Y
                    FPP23X = -FPP43X - FG3X
                    FPP32X = -FPP23X
                    FPP23Y = -FPP43Y - FG3Y
                    FPP32Y = -FPP23Y
                    FPP14X = FPP43X
                    FPP41X = -FPP14X
                    FPP14Y = FPP43Y
                    FPP41Y = -FPP14Y
                    FPP12X = FPP23X
                    FPP21X = -FPP12X
                    FPP12Y = FPP23Y
                    FPP21Y = -FPP12Y
                    TPP2 = -R2X * FPP32Y + R2Y * FPP32X
                    FG2X = -ZM2 * AG2X
                    FG2Y = -ZM2 * AG2Y
                    F3P12X = -FG2X
                    F3P21X = -F3P12X
                    F3P12Y = -FG2Y
                    F3P21Y = -F3P12Y
                    FA32X = FP32X + FPP32X
                    FA32Y = FP32Y + FPP32Y
                    FB34X = FP34X + FPP34X
                    FB34Y = FP34Y + FPP34Y
                    TORQ = TP2 + TPP2
                    FOAX = FP21X + FPP21X + F3P21X
                    FOAY = FP21Y + FPP21Y + F3P21Y
                    FOBX = FP41X + FPP41X
                    FOBY = FP41Y + FPP41Y
                    SHAKX = FOAX + FOBX
                    SHAKY = FOAY + FOBY
                    FA32, DFA32 = VECTOR(FA32X, FA32Y)
                    FB34, DFB34 = VECTOR(FB34X, FB34Y)
                    FOA, DFOA = VECTOR(FOAX, FOAY)
                    FOB, DFOB = VECTOR(FOBX, FOBY)
                    SHAK, DSHAK = VECTOR(SHAKX, SHAKY)          # 00202
                VA, DVA = VECTOR(VAX, VAY)
                AA, DAA = VECTOR(AAX, AAY)
                VG2, DVG2 = VECTOR(VG2X, VG2Y)
                AG2, DAG2 = VECTOR(AG2X, AG2Y)
                VB, DVB = VECTOR(VBX, VBY)
                AB, DAB = VECTOR(ABX, ABY)
                VG4, DVG4 = VECTOR(VG4X, VG4Y)
                AG4, DAG4 = VECTOR(AG4X, AG4Y)
                VG3, DVG3 = VECTOR(VG3X, VG3Y)
                AG3, DAG3 = VECTOR(AG3X, AG3Y)
                write(7)
                write(10)
                write(1, ATH2, ATH3, ATH4)
                write(11)
                write(2, TH3D, TH4D, TH3DD, TH4DD)
                write(12)
                write(5, TEX)
                write(13)
                write(9, VG2, VA, VG3, VB, VG4)
                write(8, DVG2, DVA, DVG3, DVB, DVG4)
                write(14)
                write(9, AG2, AA, AG3, AB, AG4)
                write(8, DAG2, DAA, DAG3, DAB, DAG4)
                if not kinematics_only:
                    write(15)
                    write(2, FA32, FB34, FOA, FOB)
                    write(3, DFA32, DFB34, DFOA, DFOB)
                    write(16)
                    write(6, SHAK, SHAKX, SHAKY)
                    write(4, DSHAK)
                    write(17)
                    write(5, TORQ)
                write(18)
                sheets += 1
                if ATH2 > THMAX:                                # IF(ATH2.GT.THMAX)GOTO27
                    a, b = f"{float(ATH2):g}", f"{float(THMAX):g}"
                    if a == b:  # past by roundoff of TH + I*DELTA: show the digits that differ
                        a, b = repr(float(ATH2)), repr(float(THMAX))
                        why = (" (by roundoff: THZERO - DELTA + I*DELTA in binary "
                               "floating point)")
                    else:
                        why = ""
                    notice("past-thmax", f"THETA 2 = {a} is past THMAX = {b}{why}: the 1966 "
                           "loop prints a sheet before testing ATH2.GT.THMAX")
                    break
        return sheets                                           # 00237 STOP
