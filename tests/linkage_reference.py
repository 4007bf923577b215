"""An independent solve of the four-bar, the inverted slider-crank and the two six-bars,
in mpmath.

Trusts nothing of the engine but its conventions (which assembly "open" is, which body
each reported force acts on).  Positions from the textbook's angle forms (an RRR's link
at the angle of P -> Q plus the law-of-cosines angle acos((lp^2 + d^2 - lq^2) / (2 lp d));
the slotted link at the angle of O4 -> A less asin(e / |O4 A|)), worked in 40 digits;
velocities and accelerations by differentiating those positions in time numerically
(mpmath.diff, the crank angle th0 + w t + a t^2 / 2); forces from the Newton-Euler
equations of each moving body about its own centre of mass, solved by mpmath.lu_solve.
Points are complex numbers (x + iy).
"""

from __future__ import annotations

from dataclasses import dataclass

import mpmath as mp

mp.mp.dps = 40

G_IN = mp.mpf("386.088")  # in/sec^2, the report's g
G_SI = mp.mpf("9.80665")


def e(a):
    return mp.expj(a)


def rrr(P, Q, lp, lq, sign):
    """C with |C - P| = lp, |C - Q| = lq, on the left of P -> Q for sign +1."""
    d = abs(Q - P)
    phi = mp.arg(Q - P) + sign * mp.acos((lp * lp + d * d - lq * lq) / (2 * lp * d))
    return P + lp * e(phi)


@dataclass
class Body:
    k: int
    base: str  # the point its centre of mass is placed from
    line: str  # the name of its line's angle
    W: object
    ZI: object
    RG: object
    ADEL: object  # degrees


def f(x):
    return mp.mpf(repr(float(x)))


def geometry(kind, m, th2, branch=(1, 1)):
    """Points (complex) and line angles (rad) at the crank angle th2 [rad] (mpf)."""
    pts = {"O2": mp.mpc(0)}
    ang = {"2": th2}
    pts["A"] = f(m.R2) * e(th2)
    if kind == "slider":  # B on y = offset, right of A on the open branch
        d = f(m.offset) - pts["A"].imag
        root = branch[0] * mp.sqrt(f(m.R3) ** 2 - d * d)
        pts["B"] = mp.mpc(pts["A"].real + root, f(m.offset))
        ang["3"], ang["4"] = mp.arg(pts["B"] - pts["A"]), mp.mpf(0) * th2
        ang["s"] = pts["B"].real  # the slide's position along +x
        return pts, ang
    if kind == "inverted":
        O4 = mp.mpc(f(m.R1), 0)
        pts["O4"] = O4
        d = pts["A"] - O4
        # A - O4 = s u + e u^: u at arg(d) - asin(e / |d|) with s > 0 (the open branch);
        # with s < 0, -u has s > 0 and offset -e
        sign = branch[0]
        th4 = mp.arg(d) - sign * mp.asin(f(m.offset) / abs(d)) + (0 if sign > 0 else mp.pi)
        ang["4"] = ang["3"] = th4
        ang["s"] = (d * mp.conj(e(th4))).real  # A's position along link 4 from O4's foot
        return pts, ang
    O4 = mp.mpc(f(m.R1), 0)
    if kind == "fourbar":  # B on the circles about A and O4, left of A -> O4 when open
        pts["O4"] = O4
        B = rrr(pts["A"], O4, f(m.R3), f(m.R4), branch[0])
        pts["B"] = B
        ang["3"], ang["4"] = mp.arg(B - pts["A"]), mp.arg(B - O4)
        return pts, ang
    pts["O4"], pts["O6"] = O4, mp.mpc(f(m.X6), f(m.Y6))
    B = rrr(pts["A"], O4, f(m.R3), f(m.R4), branch[0])
    pts["B"] = B
    ang["3"], ang["4"] = mp.arg(B - pts["A"]), mp.arg(B - O4)
    on, base = (4, "O4") if kind == "watt" else (3, "A")
    pts["C"] = pts[base] + f(m.RC) * e(ang[str(on)] + mp.radians(f(m.ADELC)))
    D = rrr(pts["C"], pts["O6"], f(m.R5), f(m.R6), branch[1])
    pts["D"] = D
    ang["5"], ang["6"] = mp.arg(D - pts["C"]), mp.arg(D - pts["O6"])
    return pts, ang


def bodies(kind, m):
    def body(k, base):
        get = lambda n: f(getattr(m, f"{n}{k}", 0.0))  # noqa: E731
        return Body(k, base, str(k), get("W"), get("ZI"), get("RG"), get("ADEL"))
    if kind in ("inverted", "fourbar"):
        return [body(2, "O2"), body(3, "A"), body(4, "O4")]
    if kind == "slider":
        return [body(2, "O2"), body(3, "A"), body(4, "B")]
    return [body(2, "O2"), body(3, "A"), body(4, "O4"), body(5, "C"), body(6, "O6")]


def pins(kind):
    """(point, by, on): the force of body ``by`` on body ``on`` (1: the frame)."""
    if kind == "inverted":
        return [("O2", 2, 1), ("A", 3, 2), ("O4", 4, 1)]
    if kind == "slider":
        return [("O2", 2, 1), ("A", 3, 2), ("B", 3, 4)]
    if kind == "fourbar":
        return [("O2", 2, 1), ("A", 3, 2), ("O4", 4, 1), ("B", 3, 4)]
    on = 4 if kind == "watt" else 3
    return [("O2", 2, 1), ("A", 3, 2), ("O4", 4, 1), ("B", 3, 4), ("C", 5, on),
            ("O6", 6, 1), ("D", 5, 6)]


def centre(b, pts, ang):
    return pts[b.base] + b.RG * e(ang[b.line] + mp.radians(b.ADEL))


def motion(kind, m, th0_deg, w, a=0.0, branch=(1, 1)):
    """Value, first and second time derivative at t = 0 of every point and angle (and of
    each body's centre of mass, as 'G<k>')."""
    th0, w, a = mp.radians(f(th0_deg)), f(w), f(a)

    def at(t):
        pts, ang = geometry(kind, m, th0 + w * t + a * t * t / 2, branch)
        for b in bodies(kind, m):
            pts[f"G{b.k}"] = centre(b, pts, ang)
        return pts, ang

    pts, ang = at(mp.mpf(0))

    def turned(t, name):  # the angle within pi of its value at t = 0: an angle at +-pi
        # (mpmath's arg at a line pointing along -x) would jump by 2 pi across t = 0
        x = at(t)[1][name]
        return x - 2 * mp.pi * mp.nint((x - ang[name]) / (2 * mp.pi))

    out = {}
    for name in pts:
        out[name] = [mp.diff(lambda t, n=name: at(t)[0][n], 0, k) for k in range(3)]
    for name in ang:
        out["th" + name] = [mp.diff(lambda t, n=name: turned(t, n), 0, k) for k in range(3)]
    return out


def cross(a, b):
    return a.real * b.imag - a.imag * b.real


def slide(kind):
    """(slider, guide, point, the guide's direction's angle name) or None."""
    return {"inverted": (3, 4, "A", "4"), "slider": (4, 1, "B", "4")}.get(kind)


def newton_euler(kind, m, th0_deg, w, a=0.0, branch=(1, 1), gravity=(0.0, 0.0),
                 loads=(), units="in-lb-sec", mur=None, mu_slide=0.0):
    """Every pin force (force of ``by`` on ``on``, complex), the slide's FN and MN (the
    guide's force on the slider along the guide's normal, +90 degrees from its line, and
    its couple) where there is a slide, and TORQ.  ``loads``: (link, point (complex),
    force (complex), torque) applied; gravity (gx, gy) in the units' length per sec^2;
    ``mur``: {pin: mu r} Coulomb couples opposing each pin's relative rotation and
    ``mu_slide`` a friction force mu |FN| opposing the slide, found by iterating the
    solve to a fixed point (each iteration's couples from the last one's forces)."""
    mo = motion(kind, m, th0_deg, w, a, branch)
    bs = bodies(kind, m)
    friction: list = []
    last = None
    for _ in range(200):
        out = _solve(kind, m, mo, bs, gravity, list(loads) + friction, units)
        if not mur and not mu_slide:
            break
        friction = _friction_loads(kind, mo, out, mur or {}, mu_slide)
        if last is not None and abs(out["TORQ"] - last) <= mp.mpf(10) ** -30 * (
                1 + abs(last)):
            break
        last = out["TORQ"]
    else:
        raise ArithmeticError(f"the friction's fixed point at {th0_deg} deg did not settle "
                              "in 200 iterations")
    out["motion"] = mo
    return out


def _friction_loads(kind, mo, out, mur, mu_slide):
    """The friction couples and the slide's friction force as applied loads.  A relative
    rate that is zero by the geometry comes out of 40 digits as some 1e-40 of the rates,
    of either sign: below 1e-30 of them it is zero (no friction there)."""
    loads = []
    w = {k: mo["th" + str(k)][1] for k in range(2, 7) if "th" + str(k) in mo}
    w[1] = mp.mpf(0)
    rates = sum(abs(x) for x in w.values())

    def sign(x, scale):
        return 0 if abs(x) <= mp.mpf(10) ** -30 * scale else mp.sign(x)

    for (p, by, on), F in ((k, v) for k, v in out.items() if isinstance(k, tuple)):
        c = f(mur.get(p, 0.0)) * abs(F) * sign(w[by] - w[on], rates)
        loads += [(by, mp.mpc(0), mp.mpc(0), -c), (on, mp.mpc(0), mp.mpc(0), c)]
    sl = slide(kind)
    if sl and mu_slide:
        slider, guide, point, line = sl
        u = e(mo["th" + line][0])
        force = -f(mu_slide) * abs(out["FN"]) * sign(mo["ths"][1],
                                                      rates * (1 + abs(mo[point][0]))) * u
        loads += [(slider, mo[point][0], force, 0), (guide, mo[point][0], -force, 0)]
    return loads


def _solve(kind, m, mo, bs, gravity, loads, units):
    g_div = G_IN if units == "in-lb-sec" else mp.mpf(1)
    grav = mp.mpc(f(gravity[0]), f(gravity[1]))
    index = {b.k: i for i, b in enumerate(bs)}
    unknowns = [(p, by, on) for p, by, on in pins(kind)]
    sl = slide(kind)
    n = 3 * len(bs)
    cols = 2 * len(unknowns) + (2 if sl else 0) + 1
    assert cols == n
    A = mp.zeros(n, n)
    rhs = mp.zeros(n, 1)

    def put(col, k, force, at, couple=0):
        if k == 1:
            return
        i = 3 * index[k]
        G = mo[f"G{k}"][0]
        A[i, col] += force.real
        A[i + 1, col] += force.imag
        A[i + 2, col] += cross(at - G, force) + couple

    for c, (p, by, on) in enumerate(unknowns):
        for j, unit in enumerate((mp.mpc(1, 0), mp.mpc(0, 1))):
            put(2 * c + j, on, unit, mo[p][0])
            put(2 * c + j, by, -unit, mo[p][0])
    col = 2 * len(unknowns)
    if sl:
        slider, guide, point, line = sl
        normal = e(mo["th" + line][0] + mp.pi / 2)
        put(col, slider, normal, mo[point][0])
        put(col, guide, -normal, mo[point][0])
        put(col + 1, slider, mp.mpc(0), mo[point][0], 1)
        put(col + 1, guide, mp.mpc(0), mo[point][0], -1)
        col += 2
    A[3 * index[2] + 2, col] = 1  # the drive's torque on the crank
    for b in bs:
        i = 3 * index[b.k]
        mass = b.W / g_div
        G = mo[f"G{b.k}"]
        force = mass * G[2] - mass * grav
        moment = b.ZI * mo["th" + b.line][2]
        for link, at, fo, tq in loads:
            if link == b.k:
                fo = mp.mpc(fo)
                force -= fo
                moment -= cross(mp.mpc(at) - G[0], fo) + mp.mpf(tq)
        rhs[i], rhs[i + 1], rhs[i + 2] = force.real, force.imag, moment
    x = mp.lu_solve(A, rhs)
    out = {}
    for c, (p, by, on) in enumerate(unknowns):
        out[(p, by, on)] = mp.mpc(x[2 * c], x[2 * c + 1])
    if sl:
        out["FN"], out["MN"] = x[n - 3], x[n - 2]
    out["TORQ"] = x[n - 1]
    return out
