"""The mechanism a deck describes, with the listing's names.

Units are the report's (page 17, "THE PROGRAM AND ITS USE"):

====== ================================================ ==============
name   meaning                                          unit
====== ================================================ ==============
W2-W4  weights of links 2, 3, 4                         lb
ZI2-4  mass moments of inertia of links 2, 3, 4 (*)   in-lb-sec^2
R1-R4  lengths of links 1 (frame), 2 (crank), 3, 4      in
ADEL2  angle of the centre of mass line, measured        degrees
-ADEL4 + or - from R2, R3 or R4
RG2-4  distance from the link's base pin to its G       in
TH2D   angular velocity of link 2 (constant)            rad/sec
====== ================================================ ==============

Link 2 turns about O2 (origin), link 4 about O4 = (R1, 0); A is the pin
joining 2 and 3, B the pin joining 3 and 4.  RG3 is measured from A.

(*) The report's card description says "about O2, A, O4", but the program's
equations apply the inertia force -m*a_G at G *and* the torque -ZI*alpha,
which is D'Alembert's principle with ZI about the link's own centre of
mass.  The emulator runs the program as written and the engine follows the
same model.  ZI2 matters only when the crank accelerates (``Scene(th2dd=...)``): at
constant speed, as in 1966, link 2 has no angular acceleration and ZI2 drops out.

Each field is a float for the emulator; for the modern engine any field
may be a numpy array that broadcasts against the crank angles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import replace as dataclasses_replace
from typing import Any

FIELD_NAMES = (
    "W2", "W3", "W4",
    "ZI2", "ZI3", "ZI4",
    "R1", "R2", "R3", "R4",
    "ADEL2", "ADEL3", "ADEL4",
    "RG2", "RG3", "RG4",
    "TH2D",
)

UNITS = {
    "W2": "lb", "W3": "lb", "W4": "lb",
    "ZI2": "in-lb-sec^2", "ZI3": "in-lb-sec^2", "ZI4": "in-lb-sec^2",
    "R1": "in", "R2": "in", "R3": "in", "R4": "in",
    "ADEL2": "deg", "ADEL3": "deg", "ADEL4": "deg",
    "RG2": "in", "RG3": "in", "RG4": "in",
    "TH2D": "rad/sec",
}


#: Unit systems: the report's (lengths in, weights in lb, forces lb, torques in-lb,
#: ZI in-lb-sec^2, g = 386.088 in/sec^2: a link's mass is W / g) and SI (lengths m,
#: *masses* in kg in the W fields, forces N, torques N m, ZI kg m^2, g = 9.80665 m/s^2).
STANDARD_GRAVITY = {"in-lb-sec": 386.088, "SI": 9.80665}
#: The report's units and their SI counterparts (in SI the W fields hold masses):
#: sielaff.quantities names every number's unit from it.
SI = {"in": "m", "lb": "N", "in-lb": "N m", "in-lb-sec^2": "kg m^2", "in/sec": "m/s",
      "in/sec^2": "m/s^2", "in-lb/sec": "W", "rad/sec": "rad/s", "rad/sec^2": "rad/s^2",
      "deg": "deg", "-": "-"}


def field_unit(name: str, report_unit: str, units: str) -> str:
    """The unit of the field ``name`` whose report unit is ``report_unit``, in the unit
    system ``units`` (a W field is a mass in SI: kg)."""
    if units != "SI":
        return report_unit
    return "kg" if name[:1] == "W" and name[1:].isdigit() else SI[report_unit]
#: What W is divided by to give a mass: g for weights (in-lb-sec), 1 for masses (SI).
MASS_DIVISOR = {"in-lb-sec": 386.088, "SI": 1.0}


@dataclass(frozen=True)
class Mechanism:
    """Parameters of a crank-rocker, named as on the data cards (see module doc), and the
    unit system they are in (``units``: ``"in-lb-sec"``, the report's and every deck's,
    or ``"SI"``; see :data:`STANDARD_GRAVITY`)."""

    W2: Any
    W3: Any
    W4: Any
    ZI2: Any
    ZI3: Any
    ZI4: Any
    R1: Any
    R2: Any
    R3: Any
    R4: Any
    ADEL2: Any
    ADEL3: Any
    ADEL4: Any
    RG2: Any
    RG3: Any
    RG4: Any
    TH2D: Any
    units: str = "in-lb-sec"

    def replace(self, **fields: Any) -> Mechanism:
        """A copy with some fields changed: ``EXAMPLE.replace(R4=np.linspace(10, 14, 5)[:, None])``
        makes a design sweep (each field may be an array; see the README)."""
        unknown = sorted(set(fields) - set(FIELD_NAMES) - {"units"})
        if unknown:
            raise TypeError(f"Mechanism has no field {', '.join(unknown)} "
                            f"(fields: {' '.join(FIELD_NAMES)})")
        return dataclasses_replace(self, **fields)

    def as_tuple(self) -> tuple:
        """The 17 values of the deck's fields, in card order."""
        return tuple(getattr(self, n) for n in FIELD_NAMES)

    def as_dict(self) -> dict[str, Any]:
        """The 17 fields by name (not the unit system)."""
        return {n: getattr(self, n) for n in FIELD_NAMES}


#: The report's example problem (page 19): W 3 8 6; ZI 0 .5 .4; R 12 4 16 12;
#: ADEL 0 -15 15; RG 2 8 6; TH2D 50.
EXAMPLE = Mechanism(
    W2=3.0, W3=8.0, W4=6.0,
    ZI2=0.0, ZI3=0.5, ZI4=0.4,
    R1=12.0, R2=4.0, R3=16.0, R4=12.0,
    ADEL2=0.0, ADEL3=-15.0, ADEL4=15.0,
    RG2=2.0, RG3=8.0, RG4=6.0,
    TH2D=50.0,
)


#: A crank-rocker condition whose margin is within this fraction of C = R1/R2 of zero is the
#: boundary itself: a change point (R1 + R2 = R3 + R4, or R1 - R2 = |R4 - R3|) or a crank
#: as long as another link.  Punched lengths differ by 1E-4 in or more (1E-5 relative to a
#: 12 in link); roundoff of the ratios is 1E-16: 1E-9 lies far from both.
BOUNDARY = 1e-9

#: What every length, weight and inertia must be (``validate``).
LENGTHS = ("R1", "R2", "R3", "R4")
NONNEGATIVE = ("W2", "W3", "W4", "ZI2", "ZI3", "ZI4")


def validate(m: Mechanism) -> None:
    """Raise ValueError naming the first field a mechanism cannot have.

    Every field must be given and finite (any array element); the lengths R1-R4
    positive; weights and moments of inertia not negative.  Angles, centre-of-mass
    distances and the crank speed may have any sign.  Arrays are checked
    element by element (one bad design in a sweep is named by its field).
    """
    import numpy as np

    if m.units not in STANDARD_GRAVITY:
        raise ValueError(f"units = {m.units!r}: the unit systems are "
                         f"{', '.join(STANDARD_GRAVITY)}")
    for name in FIELD_NAMES:
        value = getattr(m, name)
        if plainly_valid(value, name in LENGTHS, name in NONNEGATIVE):
            continue
        if value is None:
            raise ValueError(f"{name} is missing: every field of the Mechanism needs a value")
        try:
            v = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"{name} = {value!r} is not a number") from None
        if not np.all(np.isfinite(v)):
            raise ValueError(f"{name} = {_first_bad(v, ~np.isfinite(v))} is not finite")
        if name in LENGTHS and not np.all(v > 0.0):
            raise ValueError(f"{name} = {_first_bad(v, ~(v > 0.0))} "
                             f"{field_unit(name, UNITS[name], m.units)}: the link "
                             "lengths R1-R4 must be positive")
        if name in NONNEGATIVE and not np.all(v >= 0.0):
            raise ValueError(f"{name} = {_first_bad(v, ~(v >= 0.0))} "
                             f"{field_unit(name, UNITS[name], m.units)}: weights "
                             "and moments of inertia cannot be negative")


def plainly_valid(value: Any, positive: bool, nonnegative: bool) -> bool:
    """Whether ``value`` is a plain float that passes a field's checks: finite, and > 0
    (``positive``) or >= 0 (``nonnegative``) as asked.  The validators take this path
    first; anything else (an array, an int, a bad value) gets their checks, which name it.
    A design of plain numbers is then checked without numpy's cost per call, which a
    small analysis would pay for every field."""
    return type(value) is float and math.isfinite(value) and (
        not positive or value > 0.0) and (not nonnegative or value >= 0.0)


def _first_bad(v, bad) -> str:
    import numpy as np

    x = float(v) if v.ndim == 0 else float(v[np.unravel_index(np.argmax(bad), v.shape)])
    return f"{x:g}"


def crank_rocker_failure(m: Mechanism, exact: dict | None = None) -> str | None:
    """Which of the report's crank-rocker conditions (p. 4) ``m`` fails, or None.

    With A = R3/R2, B = R4/R2, C = R1/R2 the 1966 program (statements
    45-51) requires A > 1, B > 1, C > 1, C < A+B-1 and C > |B-A|+1.  Here
    they are evaluated exactly (rationals) on the punched decimals (``exact``,
    ``Deck.exact``) or on the floats' exact values, and a margin within
    :data:`BOUNDARY` of C from zero is the boundary itself (a change point),
    which is not a crank-rocker.  The emulator runs the program's own test in
    its own arithmetic, as 1966 did; this is the modern tools' test.
    """
    from fractions import Fraction

    for name in LENGTHS:
        value = getattr(m, name)
        if not (isinstance(value, int | float) or hasattr(value, "__float__")) \
                or not math.isfinite(float(value)) or not float(value) > 0:
            return f"{name} = {value}: the link lengths must be positive"
    R1, R2, R3, R4 = (Fraction(exact[n]) if exact and n in exact else Fraction(float(getattr(m, n)))
                      for n in LENGTHS)
    A, B, C = R3 / R2, R4 / R2, R1 / R2
    tol = Fraction(BOUNDARY) * C
    checks = (
        (A - 1, f"A = R3/R2 = {float(A):.6g} must be > 1 (the crank must be the shortest link)"),
        (B - 1, f"B = R4/R2 = {float(B):.6g} must be > 1 (the crank must be the shortest link)"),
        (C - 1, f"C = R1/R2 = {float(C):.6g} must be > 1 (the crank must be the shortest link)"),
        (A + B - 1 - C, f"C = R1/R2 = {float(C):.6g} must be < A+B-1 = {float(A + B - 1):.6g}"),
        (C - abs(B - A) - 1,
         f"C = R1/R2 = {float(C):.6g} must be > |B-A|+1 = {float(abs(B - A) + 1):.6g}"),
    )
    for k, (margin, text) in enumerate(checks):
        if abs(margin) <= tol:
            what = ("a link as short as the crank" if k < 3 else
                    "R1 + R2 = R3 + R4" if k == 3 else "R1 - R2 = |R4 - R3|")
            return (f"{text}, and is within {BOUNDARY:g} of it ({what}): a change point, "
                    "where the linkage can fold at a toggle; not a crank-rocker")
        if margin < 0:
            return text
    return None
