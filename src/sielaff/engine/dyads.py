"""Positions, velocities and accelerations of a :class:`~sielaff.linkage.Topology`, dyad
by dyad, vectorised over the positions (every value a number or an array).

Positions are closed forms: RRR is the intersection of two circles, RRP and PRR of a
circle and the guide's line, RPR the line through the known pivot at its offset from the
known pin.  Each square root's argument is a product of linear factors (Heron's for RRR),
each known to a few ulps of the lengths involved: one below ``-ASSEMBLY_TOL_EPS eps``
times that scale means the dyad cannot close there (NaN), one between that and 0 is the
edge of assembly reached with roundoff (clamped to 0).  Velocities and accelerations come
from the time derivatives of each dyad's closure, a 2 x 2 linear system per dyad:

    RRR:  w_n (C-P)^ - w_{n+1} (C-Q)^ = vQ - vP                (v^ = v turned +90 deg)
    RRP:  w_n (C-P)^ - s' d = vG + w_g (C-G)^ - vP              (d the guide's direction)
    PRR:  w_{n+1} (C-Q)^ - s' d = vG + w_g (C-G)^ - vQ
    RPR:  w_{n+1} (P-Q)^ + s' u = vP - vQ                       (u link n+1's direction)

and the same matrices for the angular accelerations and s'', whose right-hand sides add
the centripetal terms -w^2 r and the Coriolis term 2 w s' d^ of a slide on a turning
link.  Each solve is Cramer's rule with the determinant a cross product, zero only where
the dyad is singular (its toggle; the rates are then infinite, as the linkage locks).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from sielaff.engine.positions import ASSEMBLY_TOL_EPS
from sielaff.linkage import PRR, RPR, RRP, RRR, Guide, Topology

__all__ = ["Motion", "Positions", "accelerations", "positions", "velocities"]

_EPS = np.finfo(float).eps
Vec = tuple[Any, Any]


def _cross(a: Vec, b: Vec) -> Any:
    return a[0] * b[1] - a[1] * b[0]


def _perp(a: Vec) -> Vec:
    return (-a[1], a[0])


def _solve2(c1: Vec, c2: Vec, r: Vec) -> tuple[Any, Any]:
    """(x1, x2) with x1 c1 + x2 c2 = r (Cramer)."""
    det = _cross(c1, c2)
    return _cross(r, c2) / det, _cross(c1, r) / det


def _root(factors: tuple[Any, ...], scale: Any) -> Any:
    """sqrt of the product of ``factors``: NaN where one is clearly below 0 (the dyad
    cannot close), the factor clamped to 0 where roundoff took it there."""
    tol = -ASSEMBLY_TOL_EPS * _EPS * scale
    prod: Any = 1.0
    for f in factors:
        prod = prod * np.where(f < tol, np.nan, np.maximum(f, 0.0))
    return np.sqrt(prod)


def value(v: dict[str, Any], x: Any) -> Any:
    """A topology's value: the field ``x`` names, or the constant ``x``."""
    return v[x] if isinstance(x, str) else float(x)


@dataclass
class Positions:
    """The linkage at each position: each link's line (cos, sin) and base point, each named
    point (the pins, the pivots, the named points, Gk the centres of mass), each slide's
    position along its guide, each RRR's angle at its inner pin (sin, cos), and the least
    assembly margin over the dyads (NaN where some dyad cannot close)."""

    link: dict[int, tuple[Any, Any, Any, Any]] = field(default_factory=dict)
    pt: dict[str, Vec] = field(default_factory=dict)
    slide: dict[str, Any] = field(default_factory=dict)
    guide: dict[str, tuple[int, int, str, Vec]] = field(default_factory=dict)
    gamma: dict[str, tuple[Any, Any]] = field(default_factory=dict)
    margin: Any = 1.0
    margins: list[Any] = field(default_factory=list)
    scale: Any = 1.0


@dataclass
class Motion:
    """Rates (or their derivatives): each link's angular velocity (acceleration), each
    point's velocity (acceleration), each slide's rate (its second derivative)."""

    w: dict[int, Any] = field(default_factory=dict)
    v: dict[str, Vec] = field(default_factory=dict)
    s: dict[str, Any] = field(default_factory=dict)


def _place(link: tuple[Any, Any, Any, Any], r: Any, angle_deg: Any) -> Vec:
    c, s, bx, by = link
    a = np.radians(angle_deg)
    ca, sa = np.cos(a), np.sin(a)
    return bx + r * (c * ca - s * sa), by + r * (s * ca + c * sa)


def _direction(link: tuple[Any, Any, Any, Any], angle_deg: Any) -> Vec:
    c, s, _, _ = link
    a = np.radians(angle_deg)
    ca, sa = np.cos(a), np.sin(a)
    return c * ca - s * sa, s * ca + c * sa


def _guide(pos: Positions, v: dict[str, Any], g: Guide) -> tuple[Vec, Vec]:
    """The guide's base point and unit direction at each position."""
    link = pos.link[g.link]
    return _place(link, value(v, g.r), value(v, g.at)), _direction(link, value(v, g.angle))


def _base(topology: Topology, k: int) -> str:
    """The name of link k's base point."""
    if k == 2:
        return "O2"
    d = topology.dyads[(k - 3) // 2]
    first = (k - 3) % 2 == 0
    if isinstance(d, RRR):
        return d.p if first else d.q
    if isinstance(d, RRP):
        return d.p if first else d.joint
    if isinstance(d, PRR):
        return d.joint if first else d.q
    return d.p if first else d.q


def _add_points(topology: Topology, pos: Positions, v: dict[str, Any], k: int) -> None:
    """Link k's named points and its centre of mass Gk, once its line is known."""
    for p in topology.points:
        if p.link == k:
            pos.pt[p.name] = _place(pos.link[k], value(v, p.r), value(v, p.angle))
    pos.pt[f"G{k}"] = _place(pos.link[k], v.get(f"RG{k}", 0.0), v.get(f"ADEL{k}", 0.0))


def positions(topology: Topology, v: dict[str, Any], c2: Any, s2: Any,
              branches: tuple[float, ...]) -> Positions:
    """Every link and point at the crank angles (cos, sin) ``c2, s2``; ``branches`` the
    sign of each dyad (+1 open, -1 crossed)."""
    pos = Positions()
    pos.link[1] = (1.0, 0.0, 0.0, 0.0)
    pos.pt["O2"] = (0.0, 0.0)
    for p in topology.pivots:
        pos.pt[p.name] = (value(v, p.x), value(v, p.y))
    r2 = value(v, topology.crank.length)
    pos.link[2] = (c2, s2, 0.0, 0.0)
    pos.pt[topology.crank.pin] = (r2 * c2, r2 * s2)
    _add_points(topology, pos, v, 2)
    margins = []
    scale = np.max(np.abs(r2))
    for i, d in enumerate(topology.dyads):
        n, sign = 3 + 2 * i, branches[i]
        if isinstance(d, RRR):
            margin = _rrr(pos, v, d, n, sign)
        elif isinstance(d, RPR):
            margin = _rpr(pos, v, d, n, sign)
        else:
            margin = _slider(pos, v, d, n, sign)
        margins.append(margin + 0.0 * c2)
        for k in (n, n + 1):
            _add_points(topology, pos, v, k)
    for m in margins:
        pos.margin = np.minimum(pos.margin, m)
    pos.margins = margins
    for x in topology.lengths():
        scale = np.maximum(scale, np.max(np.abs(v[x])))
    pos.scale = scale
    return pos


def _rrr(pos: Positions, v: dict[str, Any], d: RRR, n: int, sign: float) -> Any:
    (px, py), (qx, qy) = pos.pt[d.p], pos.pt[d.q]
    lp, lq = value(v, d.lp), value(v, d.lq)
    dx, dy = qx - px, qy - py
    dd = np.sqrt(dx * dx + dy * dy)
    root = _root((lp + lq - dd, dd - lp + lq, dd + lp - lq, lp + lq + dd), lp + lq + dd)
    h = root / (2.0 * dd)  # C's height above the line P -> Q (twice the area / PQ)
    a = (lp - lq) * (lp + lq) / (2.0 * dd) + 0.5 * dd  # the foot's distance from P
    ex, ey = dx / dd, dy / dd
    ux, uy = a * ex - sign * h * ey, a * ey + sign * h * ex  # C - P
    cx, cy = px + ux, py + uy
    pos.pt[d.joint] = (cx, cy)
    pos.link[n] = (ux / lp, uy / lp, px, py)
    pos.link[n + 1] = ((cx - qx) / lq, (cy - qy) / lq, qx, qy)
    # the angle at C between C->P and C->Q: sin from the area, cos from the sides
    sin_g = root / (2.0 * lp * lq)
    cos_g = ((lp * lp + lq * lq) - dd * dd) / (2.0 * lp * lq)
    pos.gamma[d.joint] = (sin_g, cos_g)
    return sin_g


def _slider(pos: Positions, v: dict[str, Any], d: RRP | PRR, n: int, sign: float) -> Any:
    (gx, gy), (ux, uy) = _guide(pos, v, d.guide)
    known = pos.pt[d.p if isinstance(d, RRP) else d.q]
    L = value(v, d.length)
    wx, wy = known[0] - gx, known[1] - gy
    t0 = wx * ux + wy * uy  # the foot of the perpendicular from the known point
    hh = _cross((ux, uy), (wx, wy))  # its signed distance from the guide
    root = _root((L - hh, L + hh), L + np.abs(hh))
    s = t0 + sign * root
    cx, cy = gx + s * ux, gy + s * uy
    pos.pt[d.joint] = (cx, cy)
    rod = ((cx - known[0]) / L, (cy - known[1]) / L, known[0], known[1])
    slider = (ux + 0.0 * cx, uy + 0.0 * cx, cx, cy)
    rod_k, slider_k = (n, n + 1) if isinstance(d, RRP) else (n + 1, n)
    pos.link[rod_k], pos.link[slider_k] = rod, slider
    pos.slide[d.slide] = s
    pos.guide[d.slide] = (slider_k, d.guide.link, d.joint, (ux, uy))
    return root / L


def _rpr(pos: Positions, v: dict[str, Any], d: RPR, n: int, sign: float) -> Any:
    (px, py), (qx, qy) = pos.pt[d.p], pos.pt[d.q]
    e = value(v, d.offset)
    dx, dy = px - qx, py - qy
    dd = np.sqrt(dx * dx + dy * dy)
    s = sign * _root((dd - e, dd + e), dd + np.abs(e))
    d2 = dx * dx + dy * dy
    ux, uy = (s * dx + e * dy) / d2, (s * dy - e * dx) / d2  # P - Q = s u + e u^
    pos.link[n] = (ux, uy, px + 0.0 * ux, py + 0.0 * ux)
    pos.link[n + 1] = (ux, uy, qx + 0.0 * ux, qy + 0.0 * ux)
    pos.slide[d.slide] = s
    pos.guide[d.slide] = (n, n + 1, d.p, (ux, uy))
    return np.abs(s) / dd


def _point_rate(link_w: Any, base_v: Vec, base: Vec, p: Vec) -> Vec:
    """v = v_base + w x (p - base)."""
    return base_v[0] - link_w * (p[1] - base[1]), base_v[1] + link_w * (p[0] - base[0])


def _point_acc(alpha: Any, w: Any, base_a: Vec, base: Vec, p: Vec) -> Vec:
    """a = a_base + alpha x r - w^2 r (r = p - base)."""
    rx, ry = p[0] - base[0], p[1] - base[1]
    w2 = w * w
    return base_a[0] - alpha * ry - w2 * rx, base_a[1] + alpha * rx - w2 * ry


def _points_of(topology: Topology, pos: Positions, rates: Motion, k: int, base: str,
               fn: Any) -> None:
    for p in topology.points:
        if p.link == k:
            rates.v[p.name] = fn(k, base, p.name)
    rates.v[f"G{k}"] = fn(k, base, f"G{k}")


def _frame_still(topology: Topology, names: Any, crank: Any) -> Motion:
    """A Motion with the frame (link 1) and its points (O2, the pivots among ``names``)
    at rest and the crank's rate ``crank``: the start of velocities and accelerations."""
    m = Motion()
    m.w[1] = 0.0
    for name in names:
        if name == "O2" or any(p.name == name for p in topology.pivots):
            m.v[name] = (0.0, 0.0)
    m.w[2] = crank
    return m


def velocities(topology: Topology, pos: Positions, w2: Any) -> Motion:
    """Each link's angular velocity, each point's velocity, each slide's rate, for the
    crank's angular velocity ``w2`` [rad/sec]."""
    m = _frame_still(topology, pos.pt, w2)

    def on(k: int, base: str, name: str) -> Vec:
        return _point_rate(m.w[k], m.v[base], pos.pt[base], pos.pt[name])

    m.v[topology.crank.pin] = on(2, "O2", topology.crank.pin)
    _points_of(topology, pos, m, 2, "O2", on)
    for i, d in enumerate(topology.dyads):
        n = 3 + 2 * i
        if isinstance(d, RRR):
            c = pos.pt[d.joint]
            a = _perp(_diff(c, pos.pt[d.p]))
            b = _perp(_diff(c, pos.pt[d.q]))
            r = _diff(m.v[d.q], m.v[d.p])
            m.w[n], m.w[n + 1] = _solve2(a, (-b[0], -b[1]), r)
            m.v[d.joint] = on(n, d.p, d.joint)
        elif isinstance(d, RPR):
            c1 = _perp(_diff(pos.pt[d.p], pos.pt[d.q]))
            u = pos.link[n + 1][:2]
            r = _diff(m.v[d.p], m.v[d.q])
            m.w[n + 1], m.s[d.slide] = _solve2(c1, u, r)
            m.w[n] = m.w[n + 1]
        else:
            known = d.p if isinstance(d, RRP) else d.q
            slider_k, g, _, u = pos.guide[d.slide]
            rod_k = n + 1 if slider_k == n else n
            c = pos.pt[d.joint]
            a = _perp(_diff(c, pos.pt[known]))
            carried = _guide_point_rate(topology, pos, m, g, c)
            r = _diff(carried, m.v[known])
            m.w[rod_k], ms = _solve2(a, (-u[0], -u[1]), r)
            m.s[d.slide] = ms
            m.w[slider_k] = m.w[g]
            m.v[d.joint] = on(rod_k, known, d.joint)
        for k in (n, n + 1):
            _points_of(topology, pos, m, k, _base(topology, k), on)
    return m


def _diff(a: Vec, b: Vec) -> Vec:
    return a[0] - b[0], a[1] - b[1]


def _guide_point_rate(topology: Topology, pos: Positions, m: Motion, g: int, p: Vec) -> Vec:
    """The velocity of the point of guide link g that is at ``p`` now."""
    if g == 1:
        return (0.0, 0.0)
    base = _base(topology, g)
    return _point_rate(m.w[g], m.v[base], pos.pt[base], p)


def accelerations(topology: Topology, pos: Positions, vel: Motion, a2: Any) -> Motion:
    """Each link's angular acceleration, each point's acceleration, each slide's second
    derivative, for the crank's angular acceleration ``a2`` [rad/sec^2]."""
    m = _frame_still(topology, vel.v, a2)

    def on(k: int, base: str, name: str) -> Vec:
        return _point_acc(m.w[k], vel.w[k], m.v[base], pos.pt[base], pos.pt[name])

    m.v[topology.crank.pin] = on(2, "O2", topology.crank.pin)
    _points_of(topology, pos, m, 2, "O2", on)
    for i, d in enumerate(topology.dyads):
        n = 3 + 2 * i
        if isinstance(d, RRR):
            c, p, q = pos.pt[d.joint], pos.pt[d.p], pos.pt[d.q]
            cp, cq = _diff(c, p), _diff(c, q)
            a, b = _perp(cp), _perp(cq)
            wp2, wq2 = vel.w[n] * vel.w[n], vel.w[n + 1] * vel.w[n + 1]
            r = (m.v[d.q][0] - wq2 * cq[0] - m.v[d.p][0] + wp2 * cp[0],
                 m.v[d.q][1] - wq2 * cq[1] - m.v[d.p][1] + wp2 * cp[1])
            m.w[n], m.w[n + 1] = _solve2(a, (-b[0], -b[1]), r)
            m.v[d.joint] = on(n, d.p, d.joint)
        elif isinstance(d, RPR):
            pq = _diff(pos.pt[d.p], pos.pt[d.q])
            c1 = _perp(pq)
            u = pos.link[n + 1][:2]
            w, sd = vel.w[n + 1], vel.s[d.slide]
            un = _perp(u)
            r = (m.v[d.p][0] - m.v[d.q][0] + w * w * pq[0] - 2.0 * w * sd * un[0],
                 m.v[d.p][1] - m.v[d.q][1] + w * w * pq[1] - 2.0 * w * sd * un[1])
            m.w[n + 1], m.s[d.slide] = _solve2(c1, u, r)
            m.w[n] = m.w[n + 1]
        else:
            known = d.p if isinstance(d, RRP) else d.q
            slider_k, g, _, u = pos.guide[d.slide]
            rod_k = n + 1 if slider_k == n else n
            c = pos.pt[d.joint]
            ck = _diff(c, pos.pt[known])
            a = _perp(ck)
            carried = _guide_point_acc(topology, pos, vel, m, g, c)
            wg, sd = vel.w[g], vel.s[d.slide]
            un = _perp(u)
            wr2 = vel.w[rod_k] * vel.w[rod_k]
            r = (carried[0] + 2.0 * wg * sd * un[0] - m.v[known][0] + wr2 * ck[0],
                 carried[1] + 2.0 * wg * sd * un[1] - m.v[known][1] + wr2 * ck[1])
            m.w[rod_k], m.s[d.slide] = _solve2(a, (-u[0], -u[1]), r)
            m.w[slider_k] = m.w[g]
            m.v[d.joint] = on(rod_k, known, d.joint)
        for k in (n, n + 1):
            _points_of(topology, pos, m, k, _base(topology, k), on)
    return m


def _guide_point_acc(topology: Topology, pos: Positions, vel: Motion, m: Motion, g: int,
                     p: Vec) -> Vec:
    """The acceleration of the point of guide link g that is at ``p`` now."""
    if g == 1:
        return (0.0, 0.0)
    base = _base(topology, g)
    return _point_acc(m.w[g], vel.w[g], m.v[base], pos.pt[base], p)
