"""Accelerations: the angular accelerations of links 3 and 4 (rad/sec^2, CCW +) and the
accelerations of A, B and G2-G4 (in/sec^2, frame axes); the crank turns at constant
speed, as in 1966."""

from __future__ import annotations

from sielaff.engine.registry import step


@step(
    provides=("TH3DD", "TH4DD"),
    needs=("R2", "R3", "R4", "TH2D", "TH3D", "TH4D", "c2", "s2", "c3", "s3", "c4", "s4",
           "s34", "c34"),
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


@step(provides=("AAX", "AAY"), needs=("R2", "TH2D", "c2", "s2"))
def _acc_A(R2, TH2D, c2, s2):
    k = -R2 * TH2D * TH2D
    return c2 * k, s2 * k


@step(provides=("AG2X", "AG2Y"), needs=("RG2", "TH2D", "cd2", "sd2"))
def _acc_G2(RG2, TH2D, cd2, sd2):
    k = -RG2 * TH2D * TH2D
    return cd2 * k, sd2 * k


@step(provides=("ABX", "ABY"), needs=("R4", "TH4D", "TH4DD", "c4", "s4"))
def _acc_B(R4, TH4D, TH4DD, c4, s4):
    return _pivot_acc(R4, TH4D, TH4DD, c4, s4)


@step(provides=("AG4X", "AG4Y"), needs=("RG4", "TH4D", "TH4DD", "cd4", "sd4"))
def _acc_G4(RG4, TH4D, TH4DD, cd4, sd4):
    return _pivot_acc(RG4, TH4D, TH4DD, cd4, sd4)


@step(provides=("AG3X", "AG3Y"), needs=("AAX", "AAY", "RG3", "TH3D", "TH3DD", "cd3", "sd3"))
def _acc_G3(AAX, AAY, RG3, TH3D, TH3DD, cd3, sd3):
    x, y = _pivot_acc(RG3, TH3D, TH3DD, cd3, sd3)
    x += AAX
    y += AAY
    return x, y
