"""The pin forces and the driving torque for loads applied to the moving links.

``pins`` solves the nine equations of the three moving links (force and moment balance
of each) for any applied loads, given per link as a resultant force (frame axes) and
its moment about the link's base pin (O2 for the crank, A for the coupler, O4 for the
rocker).  Moments about A (link 3) and O4 (link 4) give the force of 3 on 4 at B from a
2 x 2 system whose determinant is ``R3 R4 sin(th3 - th4)`` (zero only at a toggle);
the force balances then give every other pin force, and the crank's moment about O2
the torque the drive must supply.  Gravity and external loads each call it with their
own loads (superposition: the model is linear in the loads).  Forces in lb (or N),
moments in in-lb (or N m), CCW +; which body each force acts on: docs/conventions.md.
"""

from __future__ import annotations


def pins(F2X, F2Y, M2, F3X, F3Y, M3, F4X, F4Y, M4, R2, R3, R4, c2, s2, c3, s3, c4, s4, s34):
    """(FA32X, FA32Y, FB34X, FB34Y, FOAX, FOAY, FOBX, FOBY, TORQ) for these loads.

    Link 4:  (B - O4) x F34 + M4 = 0;  link 3:  (B - A) x (-F34) + M3 = 0.
    Then F41 = F34 + F4 (4 on the frame), F32 = F3 - F34 (3 on 2),
    F21 = F32 + F2 (2 on the frame), and the drive: A x F32 + M2 + TORQ = 0.
    """
    ux, uy = R3 * c3, R3 * s3  # B - A
    vx, vy = R4 * c4, R4 * s4  # B - O4
    d = s34 * (R3 * R4)  # (B - O4) x (B - A)
    return pins_on(F2X, F2Y, M2, F3X, F3Y, M3, F4X, F4Y, M4, R2, c2, s2, ux, uy, vx, vy, d)


def pins_on(F2X, F2Y, M2, F3X, F3Y, M3, F4X, F4Y, M4, R2, c2, s2, ux, uy, vx, vy, d):
    """:func:`pins` given the coupler's and rocker's vectors u = B - A, v = B - O4 and
    d = v x u, which it computes (an iteration of the same geometry computes them once)."""
    f34x = (-M4 * ux - vx * M3) / d
    f34y = (-vy * M3 - uy * M4) / d
    f32x, f32y = F3X - f34x, F3Y - f34y
    torq = -(R2 * (c2 * f32y - s2 * f32x)) - M2
    return (f32x, f32y, f34x, f34y, f32x + F2X, f32y + F2Y, f34x + F4X, f34y + F4Y, torq)


def plus(a, b):
    """``a + b``, or the other one itself when one is the plain 0.0 of a skipped step: an
    effect that is off leaves every bit of the result as it was."""
    if type(b) is float and b == 0.0:
        return a
    if type(a) is float and a == 0.0:
        return b
    return a + b
