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
same model; ZI2 never matters (link 2 turns at constant speed).

Each field is a float for the emulator; for the modern engine any field
may be a numpy array that broadcasts against the crank angles.
"""

from __future__ import annotations

from dataclasses import astuple, dataclass, fields
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


@dataclass(frozen=True)
class Mechanism:
    """Parameters of a crank-rocker, named as on the data cards (see module doc)."""

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

    def replace(self, **fields: Any) -> Mechanism:
        """A copy with some fields changed: ``EXAMPLE.replace(R4=np.linspace(10, 14, 5)[:, None])``
        makes a design sweep (each field may be an array; see the README)."""
        unknown = sorted(set(fields) - set(FIELD_NAMES))
        if unknown:
            raise TypeError(f"Mechanism has no field {', '.join(unknown)} "
                            f"(fields: {' '.join(FIELD_NAMES)})")
        return dataclasses_replace(self, **fields)

    def as_tuple(self) -> tuple:
        return astuple(self)

    def as_dict(self) -> dict[str, Any]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


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


def crank_rocker_failure(m: Mechanism) -> str | None:
    """Which of the report's crank-rocker conditions (p. 4) ``m`` fails, or None.

    With A = R3/R2, B = R4/R2, C = R1/R2 the 1966 program (statements
    45-51) requires A > 1, B > 1, C > 1, C < A+B-1 and C > |B-A|+1.
    """
    if not m.R2 > 0:
        return f"R2 = {m.R2:g}: the crank must have a positive length"
    A, B, C = m.R3 / m.R2, m.R4 / m.R2, m.R1 / m.R2
    checks = (
        (A > 1.0, f"A = R3/R2 = {A:.6g} must be > 1 (the crank must be the shortest link)"),
        (B > 1.0, f"B = R4/R2 = {B:.6g} must be > 1 (the crank must be the shortest link)"),
        (C > 1.0, f"C = R1/R2 = {C:.6g} must be > 1 (the crank must be the shortest link)"),
        (C < A + B - 1.0, f"C = R1/R2 = {C:.6g} must be < A+B-1 = {A + B - 1.0:.6g}"),
        (C > abs(B - A) + 1.0, f"C = R1/R2 = {C:.6g} must be > |B-A|+1 = {abs(B - A) + 1.0:.6g}"),
    )
    return next((text for ok, text in checks if not ok), None)
