"""Accelerations: the angular accelerations of links 3 and 4 (rad/sec^2, CCW +) and the
accelerations of A, B and G2-G4 (in/sec^2, frame axes).  Here the constant-speed terms,
as in 1966; crank.py adds those of a crank angular acceleration TH2DD.  With the crank
still (TH2D = TH2DD = 0) every acceleration is zero and no step here runs."""

from __future__ import annotations

from sielaff.engine.registry import step
from sielaff.engine.statics import plus


@step(
    provides=("th3dd_w", "th4dd_w"),
    needs=("R2", "R3", "R4", "TH2D", "TH3D", "TH4D", "c2", "s2", "c3", "s3", "c4", "s4",
           "s34", "c34"),
    zero_when=("TH2D",),
)
def _angular_accelerations(R2, R3, R4, TH2D, TH3D, TH4D, c2, s2, c3, s3, c4, s4, s34, c34):
    a2 = R2 * TH2D * TH2D
    a3 = TH3D * TH3D
    a3 *= R3  # R3 TH3D^2
    a4 = TH4D * TH4D
    a4 *= R4  # R4 TH4D^2
    # TH3DD = (R2 w2^2 cos(th4-th2) + R3 w3^2 cos(th4-th3) - R4 w4^2) / (R3 sin(th4-th3))
    th3dd = c4 * c2
    th3dd += s4 * s2
    th3dd *= a2
    th3dd += a3 * c34
    th3dd -= a4
    th3dd /= s34 * -R3
    # TH4DD = (-R2 w2^2 cos(th3-th2) + R4 w4^2 cos(th3-th4) - R3 w3^2) / (R4 sin(th3-th4))
    th4dd = c3 * c2
    th4dd += s3 * s2
    th4dd *= -a2
    th4dd += a4 * c34
    th4dd -= a3
    th4dd /= s34 * R4
    return th3dd, th4dd


def _pivot_acc(r, w, a, c, s):
    """Acceleration of that point when the link also has angular acceleration a."""
    rw2 = w * w
    rw2 *= r
    ra = a * r
    return -(rw2 * c + ra * s), ra * c - rw2 * s


@step(provides=("aax_w", "aay_w"), needs=("R2", "TH2D", "c2", "s2"), zero_when=("TH2D",))
def _acc_A(R2, TH2D, c2, s2):
    k = -R2 * TH2D * TH2D
    return c2 * k, s2 * k


@step(provides=("ag2x_w", "ag2y_w"), needs=("RG2", "TH2D", "cd2", "sd2"), zero_when=("TH2D",))
def _acc_G2(RG2, TH2D, cd2, sd2):
    k = -RG2 * TH2D * TH2D
    return cd2 * k, sd2 * k


@step(provides=("ABX", "ABY"), needs=("R4", "TH4D", "TH4DD", "c4", "s4"),
      zero_when=("TH4D", "TH4DD"))
def _acc_B(R4, TH4D, TH4DD, c4, s4):
    return _pivot_acc(R4, TH4D, TH4DD, c4, s4)


@step(provides=("AG4X", "AG4Y"), needs=("RG4", "TH4D", "TH4DD", "cd4", "sd4"),
      zero_when=("TH4D", "TH4DD"))
def _acc_G4(RG4, TH4D, TH4DD, cd4, sd4):
    return _pivot_acc(RG4, TH4D, TH4DD, cd4, sd4)


@step(provides=("AG3X", "AG3Y"), needs=("AAX", "AAY", "RG3", "TH3D", "TH3DD", "cd3", "sd3"),
      zero_when=("AAX", "AAY", "TH3D", "TH3DD"))
def _acc_G3(AAX, AAY, RG3, TH3D, TH3DD, cd3, sd3):
    x, y = _pivot_acc(RG3, TH3D, TH3DD, cd3, sd3)
    x += AAX
    y += AAY
    return x, y


# The totals: the constant-speed part, plus the crank-acceleration part when TH2DD != 0
# (crank.py); with TH2DD = 0 they are the constant-speed arrays themselves.
@step(provides=("TH3DD", "TH4DD"), needs=("th3dd_w", "th4dd_w", "th3dd_a", "th4dd_a"),
      zero_when=("th3dd_w", "th4dd_w", "th3dd_a", "th4dd_a"))
def _angular_accelerations_total(th3dd_w, th4dd_w, th3dd_a, th4dd_a):
    return plus(th3dd_w, th3dd_a), plus(th4dd_w, th4dd_a)


@step(provides=("AAX", "AAY"), needs=("aax_w", "aay_w", "aax_a", "aay_a"),
      zero_when=("aax_w", "aay_w", "aax_a", "aay_a"))
def _acc_A_total(aax_w, aay_w, aax_a, aay_a):
    return plus(aax_w, aax_a), plus(aay_w, aay_a)


@step(provides=("AG2X", "AG2Y"), needs=("ag2x_w", "ag2y_w", "ag2x_a", "ag2y_a"),
      zero_when=("ag2x_w", "ag2y_w", "ag2x_a", "ag2y_a"))
def _acc_G2_total(ag2x_w, ag2y_w, ag2x_a, ag2y_a):
    return plus(ag2x_w, ag2x_a), plus(ag2y_w, ag2y_a)
