"""An independent Newton-Euler solve of the four-bar with friction, springs and dampers.

Trusts nothing of the engine but which of the two circle intersections B is on (the
branch): B from the intersection of two circles, the rates from the differentiated loop
equation (2 x 2 solves), spring and damper forces from the points so placed, the nine
balance equations of links 2-4 solved by numpy.linalg.solve, and pin friction as couples
opposing the relative rotations, iterated to a fixed point on the forces so solved.
Complex numbers are points in the frame (x + iy).
"""

from __future__ import annotations

import math

import numpy as np

from sielaff.quantities import G

PINS = ("O2", "A", "B", "O4")


def cross(a: complex, b: complex) -> float:
    return a.real * b.imag - a.imag * b.real


def rot(e: complex, deg: float) -> complex:
    return e * complex(math.cos(math.radians(deg)), math.sin(math.radians(deg)))


def circle_b(m, th2_deg: float, near: complex) -> complex:
    """B: the intersection of the circles about A (R3) and O4 (R4) nearest ``near``."""
    A = m.R2 * complex(math.cos(math.radians(th2_deg)), math.sin(math.radians(th2_deg)))
    O4 = complex(m.R1, 0.0)
    d = O4 - A
    L = abs(d)
    a = (m.R3**2 - m.R4**2 + L**2) / (2 * L)
    h = math.sqrt(max(m.R3**2 - a**2, 0.0))
    mid = A + a * d / L
    cands = [mid + h * 1j * d / L, mid - h * 1j * d / L]
    return min(cands, key=lambda b: abs(b - near))


def state(m, th2_deg, w2, a2, near):
    """Positions, unit vectors, angular rates and accelerations of links 3 and 4."""
    e2 = complex(math.cos(math.radians(th2_deg)), math.sin(math.radians(th2_deg)))
    A, O4 = m.R2 * e2, complex(m.R1, 0.0)
    B = circle_b(m, th2_deg, near)
    e3, e4 = (B - A) / m.R3, (B - O4) / m.R4
    # R2 w2 i e2 + R3 w3 i e3 = R4 w4 i e4
    M = np.array([[(1j * m.R3 * e3).real, -(1j * m.R4 * e4).real],
                  [(1j * m.R3 * e3).imag, -(1j * m.R4 * e4).imag]])
    v = -1j * m.R2 * w2 * e2
    w3, w4 = np.linalg.solve(M, [v.real, v.imag])
    acc = -(1j * a2 - w2**2) * m.R2 * e2 + w3**2 * m.R3 * e3 - w4**2 * m.R4 * e4
    a3, a4 = np.linalg.solve(M, [acc.real, acc.imag])
    return dict(A=A, B=B, O4=O4, e2=e2, e3=e3, e4=e4, w2=w2, w3=w3, w4=w4, a2=a2, a3=a3,
                a4=a4)


def point(s, link, r, angle):
    """(offset from the base pin, position, velocity) of a point (link, r, angle)."""
    base = {1: 0j, 2: 0j, 3: s["A"], 4: s["O4"]}[link]
    line = {1: 1 + 0j, 2: s["e2"], 3: s["e3"], 4: s["e4"]}[link]
    w = {1: 0.0, 2: s["w2"], 3: s["w3"], 4: s["w4"]}[link]
    p = r * rot(line, angle)
    vbase = 1j * s["w2"] * s["A"] if link == 3 else 0j
    return p, base + p, vbase + 1j * w * p


def element(s, e):
    """(L, dL/dt, tension, offsets, unit vector) of a Spring or Damper."""
    pa, xa, va = point(s, *e.a)
    pb, xb, vb = point(s, *e.b)
    u = (xb - xa) / abs(xb - xa)
    rate = (u.conjugate() * (vb - va)).real
    t = e.k * (abs(xb - xa) - e.length) if hasattr(e, "k") else e.c * rate
    return abs(xb - xa), rate, t, pa, pb, u


def solve(m, th2_deg, near, *, a2=0.0, tex=0.0, elements=(), mur=(0.0,) * 4,
          gravity=None, loads=(), iterations=500, tol=1e-15):
    """Pin forces (FA32, FB34, FOA, FOB as complex), TORQ, friction torques and the state.

    Friction: couples mu r |F| at O2 (FOA), A (FA32), B (FB34), O4 (FOB) opposing the
    relative rotation; iterated from zero until no torque changes by more than ``tol``
    of the largest.  Returns None if it does not converge.
    """
    w2 = m.TH2D
    s = state(m, th2_deg, w2, a2, near)
    A, B, O4 = s["A"], s["B"], s["O4"]
    mass = {k: getattr(m, f"W{k}") / G for k in (2, 3, 4)}
    line = {2: s["e2"], 3: s["e3"], 4: s["e4"]}
    rg = {2: m.RG2 * rot(line[2], m.ADEL2), 3: m.RG3 * rot(line[3], m.ADEL3),
          4: m.RG4 * rot(line[4], m.ADEL4)}
    w = {2: w2, 3: s["w3"], 4: s["w4"]}
    al = {2: a2, 3: s["a3"], 4: s["a4"]}
    acc = {2: (1j * a2 - w2**2) * rg[2],
           3: (1j * a2 - w2**2) * A + (1j * al[3] - w[3]**2) * rg[3],
           4: (1j * al[4] - w[4]**2) * rg[4]}
    vel = {2: 1j * w2 * rg[2], 3: 1j * w2 * A + 1j * w[3] * rg[3], 4: 1j * w[4] * rg[4]}
    zi = {2: m.ZI2, 3: m.ZI3, 4: m.ZI4}
    F = {k: 0j for k in (1, 2, 3, 4)}
    Mo = {k: 0.0 for k in (1, 2, 3, 4)}
    for e in elements:
        _, _, t, pa, pb, u = element(s, e)
        F[e.a[0]] += t * u
        Mo[e.a[0]] += cross(pa, t * u)
        F[e.b[0]] -= t * u
        Mo[e.b[0]] += cross(pb, -t * u)
    g = complex(*gravity) if gravity else 0j
    p_ext = tex * w[4]
    for k in (2, 3, 4):
        F[k] += mass[k] * g
        Mo[k] += cross(rg[k], mass[k] * g)
        p_ext += (mass[k] * g * vel[k].conjugate()).real
    for ld in loads:
        p, _, v = point(s, ld.link, ld.r, ld.angle)
        f = complex(ld.fx, ld.fy)
        F[ld.link] += f
        Mo[ld.link] += cross(p, f) + ld.torque
        p_ext += (f * v.conjugate()).real + ld.torque * w[ld.link]
    Mo[4] += tex
    rel = (w2, w[3] - w2, w[4] - w[3], w[4])
    # a relative rotation within roundoff of zero (1e-12 of the fastest link) is zero:
    # the sign of Coulomb friction there is not determined by the motion
    fast = max(abs(x) for x in (w2, w[3], w[4]))
    sg = [0.0 if abs(x) <= 1e-12 * fast else float(np.sign(x)) for x in rel]

    def nine(T):
        c = {2: sg[1] * T[1] - sg[0] * T[0], 3: sg[2] * T[2] - sg[1] * T[1],
             4: -sg[2] * T[2] - sg[3] * T[3]}
        K, r = np.zeros((9, 9)), np.zeros(9)

        def row(i, coeffs, value):
            for j, cf in coeffs.items():
                K[i, j] = cf
            r[i] = value

        # unknowns: F12 (frame on 2), F32 (3 on 2), F43 (4 on 3), F14 (frame on 4), T
        d2 = mass[2] * acc[2] - F[2]
        row(0, {0: 1, 2: 1}, d2.real)
        row(1, {1: 1, 3: 1}, d2.imag)
        row(2, {2: -A.imag, 3: A.real, 8: 1},
            zi[2] * a2 + cross(rg[2], mass[2] * acc[2]) - Mo[2] - c[2])
        d3 = mass[3] * acc[3] - F[3]
        u = B - A
        row(3, {2: -1, 4: 1}, d3.real)
        row(4, {3: -1, 5: 1}, d3.imag)
        row(5, {4: -u.imag, 5: u.real},
            zi[3] * al[3] + cross(rg[3], mass[3] * acc[3]) - Mo[3] - c[3])
        d4 = mass[4] * acc[4] - F[4]
        v = B - O4
        row(6, {4: -1, 6: 1}, d4.real)
        row(7, {5: -1, 7: 1}, d4.imag)
        row(8, {4: v.imag, 5: -v.real},
            zi[4] * al[4] + cross(rg[4], mass[4] * acc[4]) - Mo[4] - c[4])
        x = np.linalg.solve(K, r)
        f12, f32, f43, f14 = (complex(x[i], x[i + 1]) for i in (0, 2, 4, 6))
        return {"FA32": f32, "FB34": -f43, "FOA": -f12, "FOB": -f14, "TORQ": x[8]}

    T = [0.0] * 4
    for _ in range(iterations):
        f = nine(T)
        new = [mur[0] * abs(f["FOA"]), mur[1] * abs(f["FA32"]), mur[2] * abs(f["FB34"]),
               mur[3] * abs(f["FOB"])]
        done = max(abs(a - b) for a, b in zip(new, T)) <= tol * max(max(new), 1e-300)
        T = new
        if done:
            f = nine(T)
            break
    else:
        return None
    ke_rate = sum((mass[k] * acc[k] * vel[k].conjugate()).real + zi[k] * al[k] * w[k]
                  for k in (2, 3, 4))
    loss = [T[i] * abs(rel[i]) if sg[i] else 0.0 for i in range(4)]
    p_el = sum(-element(s, e)[2] * element(s, e)[1] for e in elements)
    return dict(f, T=T, loss=loss, ke_rate=ke_rate, p_elements=p_el, p_external=p_ext,
                state=s, sg=sg)


def engine_b(m, th2, scene=None):
    """B where the engine puts it (only to pick the branch's intersection)."""
    from sielaff import Scene, analyze

    r = analyze(m, [th2], ["ATH3"], scene=scene or Scene())
    t2, t3 = math.radians(th2), math.radians(float(r["ATH3"][0]))
    return m.R2 * complex(math.cos(t2), math.sin(t2)) + m.R3 * complex(math.cos(t3),
                                                                      math.sin(t3))
