"""Velocities: the angular velocities of links 3 and 4 (rad/sec, CCW +) and the
velocities of A, B and the centres of mass G2-G4 (in/sec, frame axes)."""

from __future__ import annotations

import numpy as np

from sielaff.engine.registry import step


@step(
    provides=("TH3D", "TH4D"),
    needs=("R2", "R3", "R4", "TH2D", "c2", "s2", "c3", "s3", "c4", "s4", "s34"),
    zero_when=("TH2D",),
)
def _angular_velocities(R2, R3, R4, TH2D, c2, s2, c3, s3, c4, s4, s34):
    k = (R2 * TH2D) / s34
    th3d = (s4 * c2 - c4 * s2) * k  # sin(th4 - th2)
    th3d /= R3
    th4d = (s3 * c2 - c3 * s2) * k  # sin(th3 - th2)
    th4d /= R4
    return th3d, th4d


def _rotate(adel, c, s):
    """cos and sin of (th + adel degrees), given cos th and sin th."""
    if np.ndim(adel) == 0 and adel == 0.0:
        return c, s
    d = np.radians(adel)
    cd, sd = np.cos(d), np.sin(d)
    return c * cd - s * sd, s * cd + c * sd


@step(provides=("cd2", "sd2"), needs=("ADEL2", "c2", "s2"))
def _com_line2(ADEL2, c2, s2):
    return _rotate(ADEL2, c2, s2)


@step(provides=("cd3", "sd3"), needs=("ADEL3", "c3", "s3"))
def _com_line3(ADEL3, c3, s3):
    return _rotate(ADEL3, c3, s3)


@step(provides=("cd4", "sd4"), needs=("ADEL4", "c4", "s4"))
def _com_line4(ADEL4, c4, s4):
    return _rotate(ADEL4, c4, s4)


def _pivot_vel(r, w, c, s):
    """Velocity of a point at distance r, angle (c, s), on a link turning at w."""
    rw = r * w
    return s * -rw, c * rw


@step(provides=("VAX", "VAY"), needs=("R2", "TH2D", "c2", "s2"))
def _vel_A(R2, TH2D, c2, s2):
    return _pivot_vel(R2, TH2D, c2, s2)


@step(provides=("VG2X", "VG2Y"), needs=("RG2", "TH2D", "cd2", "sd2"))
def _vel_G2(RG2, TH2D, cd2, sd2):
    return _pivot_vel(RG2, TH2D, cd2, sd2)


@step(provides=("VBX", "VBY"), needs=("R4", "TH4D", "c4", "s4"))
def _vel_B(R4, TH4D, c4, s4):
    return _pivot_vel(R4, TH4D, c4, s4)


@step(provides=("VG4X", "VG4Y"), needs=("RG4", "TH4D", "cd4", "sd4"))
def _vel_G4(RG4, TH4D, cd4, sd4):
    return _pivot_vel(RG4, TH4D, cd4, sd4)


@step(provides=("VG3X", "VG3Y"), needs=("VAX", "VAY", "RG3", "TH3D", "cd3", "sd3"))
def _vel_G3(VAX, VAY, RG3, TH3D, cd3, sd3):
    x, y = _pivot_vel(RG3, TH3D, cd3, sd3)
    x += VAX
    y += VAY
    return x, y
