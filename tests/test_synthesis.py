"""Synthesis (sielaff.synthesis): every linkage it makes is analysed again, by the engine and
by this file's own construction, and must do what was asked to 1E-9.

The independent construction is two circles' intersection, written here from scratch: the
pin B of a four-bar at a crank angle is where the circle of radius R3 about A meets the
circle of radius R4 about O4, the one left of A->O4 on the open branch, right of it on
the crossed.  Nothing of the code under test is used for it.  pylinkage (the ``check``
extra) is the outside check where its synthesis covers the problem: its Freudenstein solver
for function generation, its Grashof classification and its own simulation (stepping a crank
and an RRR dyad) for the crank-rockers, the poses and the paths.  Hypothesis draws problems
of each kind and counts what it drew (``hypothesis.event``).

Published worked examples: none with printed numbers was found in the stored material
(docs/synthesis.md, "Published examples"), so none is transcribed here.
"""

from __future__ import annotations

import math
import warnings

import mpmath
import numpy as np
import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st

import sielaff
from sielaff import synthesis
from sielaff.mechanism import MASS_DIVISOR

TOL = 1e-9


# ---------------------------------------------------------------- the independent construction

def intersect(c1, r1, c2, r2):
    """The two points at distance r1 from c1 and r2 from c2: (left, right) of c1->c2.

    Worked in 40 digits (mpmath): nearly tangent circles of a drawn problem (a rocker a
    thousandth of the frame) lose half the float's digits in the square root."""
    with mpmath.workdps(40):
        (x1, y1), (x2, y2) = [(mpmath.mpf(p[0]), mpmath.mpf(p[1])) for p in (c1, c2)]
        r1, r2 = mpmath.mpf(r1), mpmath.mpf(r2)
        dx, dy = x2 - x1, y2 - y1
        d = mpmath.hypot(dx, dy)
        a = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
        h = mpmath.sqrt(max(r1 * r1 - a * a, 0))
        fx, fy = x1 + a * dx / d, y1 + a * dy / d
        pts = (fx - h * dy / d, fy + h * dx / d), (fx + h * dy / d, fy - h * dx / d)
        return tuple((float(x), float(y)) for x, y in pts)


def pin_b(m, th2_deg, branch):
    """B (engine frame) at a crank angle, by the two circles."""
    t = math.radians(th2_deg)
    a = (m.R2 * math.cos(t), m.R2 * math.sin(t))
    left, right = intersect(a, m.R3, (m.R1, 0.0), m.R4)
    return a, (left if branch == "open" else right)


def coupler_in_user(res, th2_deg):
    """The coupler point of a motion/path result, in the user's frame, by construction."""
    m, pl, cp = res.mechanism, res.placement, res.coupler
    a, b = pin_b(m, th2_deg, res.branch)
    t3 = math.atan2(b[1] - a[1], b[0] - a[0])
    px = a[0] + cp.r * math.cos(t3 + math.radians(cp.angle))
    py = a[1] + cp.r * math.sin(t3 + math.radians(cp.angle))
    c, s = math.cos(math.radians(pl.angle)), math.sin(math.radians(pl.angle))
    return pl.x + c * px - s * py, pl.y + s * px + c * py, math.degrees(t3) + pl.angle


def wrap(a):
    return (np.asarray(a) + 180.0) % 360.0 - 180.0


def analyze_quiet(m, th, outputs, branch):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return sielaff.analyze(m, np.asarray(th, dtype=float), outputs, branch=branch)


# ---------------------------------------------------------------- crank-rockers

def check_crank_rocker(cr, swing, Q):
    m, br = cr.mechanism, cr.branch
    assert sielaff.linkage_class(m).kind == "crank-rocker"
    # the rocker's extreme positions by construction: crank and coupler in line
    o2, o4 = (0.0, 0.0), (m.R1, 0.0)
    ends = []
    for d, sign in ((m.R3 + m.R2, 1.0), (m.R3 - m.R2, -1.0)):
        for b in intersect(o2, d, o4, m.R4):
            a = (sign * m.R2 * b[0] / d, sign * m.R2 * b[1] / d)
            cross = (o4[0] - a[0]) * (b[1] - a[1]) - (o4[1] - a[1]) * (b[0] - a[0])
            if (cross > 0) == (br == "open"):
                ends.append((math.degrees(math.atan2(a[1], a[0])),
                             math.degrees(math.atan2(b[1], b[0] - m.R1))))
    assert len(ends) == 2
    (t_ext, r_ext), (t_fold, r_fold) = ends
    assert abs(abs(wrap(r_ext - r_fold)) - swing) <= TOL * 180
    arc = (t_fold - t_ext) % 360.0
    assert abs(max(arc, 360 - arc) / min(arc, 360 - arc) - Q) <= TOL * Q
    # the engine at those crank angles: THETA 4 there, the rocker at rest
    k = analyze_quiet(m, [t_ext, t_fold], ["ATH4", "TH4D"], br)
    assert np.all(np.abs(wrap(k["ATH4"] - [r_ext, r_fold])) <= TOL * 180)
    assert np.all(np.abs(k["TH4D"]) <= TOL * abs(m.TH2D))
    # over a turn the rocker stays between them, and the transmission angle's minimum
    th = np.concatenate([np.linspace(0.0, 360.0, 3601), [t_ext % 360, t_fold % 360]])
    k = analyze_quiet(m, th, ["ATH4", "GAMMA"], br)
    mid = r_ext + wrap(r_fold - r_ext) / 2.0
    assert np.max(np.abs(wrap(k["ATH4"] - mid))) <= swing / 2.0 + TOL * 180
    g = np.abs(k["GAMMA"])  # the engine signs GAMMA on the crossed branch (report note)
    mu = np.min(np.minimum(g, 180.0 - g))
    assert abs(mu - cr.min_transmission) <= TOL * 90


CR_CASES = [(40.0, 1.3), (30.0, 1.0), (60.0, 1.5), (90.0, 1.2), (120.0, 1.5), (20.0, 2.0),
            (150.0, 1.05)]


@pytest.mark.parametrize("swing, Q", CR_CASES)
def test_crank_rocker_members_meet_swing_and_time_ratio(swing, Q):
    fam = synthesis.crank_rocker(swing, Q, rocker=3.0, th2d=10.0)
    assert abs(fam.delta - 180.0 * (Q - 1) / (Q + 1)) <= 1e-12
    members = fam.members(4)
    assert members and fam.best is not None
    for cr in [fam.best, *members]:
        check_crank_rocker(cr, swing, Q)
        assert cr.mechanism.R4 == 3.0 and cr.mechanism.TH2D == 10.0


@pytest.mark.parametrize("swing, Q", CR_CASES[:4])
def test_crank_rocker_best_has_the_largest_minimum_transmission_angle(swing, Q):
    """The best member against a scan of the family, each member's minimum transmission
    angle measured by the engine (GAMMA over a turn)."""
    fam = synthesis.crank_rocker(swing, Q)
    th = np.linspace(0.0, 360.0, 721)
    scanned = []
    for side, spans in fam.intervals.items():
        for lo, hi in spans:
            for k in np.linspace(lo, hi, 41)[1:-1]:
                cr = fam.member(float(k), side)
                g = np.abs(analyze_quiet(cr.mechanism, th, ["GAMMA"], cr.branch)["GAMMA"])
                scanned.append(float(np.min(np.minimum(g, 180 - g))))
    assert len(scanned) >= 39
    assert fam.best.min_transmission >= max(scanned) - 1e-9


def test_crank_rocker_outside_k_is_refused():
    fam = synthesis.crank_rocker(40.0, 1.3)
    hi = max(h for spans in fam.intervals.values() for _, h in spans)
    with pytest.raises(ValueError, match="k = "):
        fam.member(hi * 1.5 + 1.0, "near")
    with pytest.raises(ValueError, match="side"):
        fam.member(0.5, "above")


@pytest.mark.slow
@settings(max_examples=60)
@given(swing=st.floats(5.0, 175.0), Q=st.floats(1.0, 5.0))
def test_crank_rocker_drawn_problems(swing, Q):
    try:
        fam = synthesis.crank_rocker(swing, Q)
    except ValueError as e:
        assert "no crank-rocker" in str(e) and "\n" not in str(e)
        event("no crank-rocker")
        return
    event("family found")
    check_crank_rocker(fam.best, swing, Q)


def test_crank_rocker_pylinkage_agrees():
    """pylinkage classifies each member as a Grashof crank-rocker, and its own simulation
    (a Crank and an RRRDyad stepped 3600 times) swings the rocker through the swing."""
    pl = pytest.importorskip("pylinkage")
    from pylinkage.synthesis.utils import GrashofType, grashof_check

    for swing, Q in CR_CASES[:3]:
        cr = synthesis.crank_rocker(swing, Q).best
        m = cr.mechanism
        assert grashof_check(m.R2, m.R3, m.R4, m.R1) == GrashofType.GRASHOF_CRANK_ROCKER
        a, b = pin_b(m, 0.0, cr.branch)
        o2, o4 = pl.Ground(0.0, 0.0), pl.Ground(m.R1, 0.0)
        n = 3600
        crank = pl.Crank(anchor=o2, radius=m.R2, angular_velocity=2 * math.pi / n,
                         initial_angle=0.0)
        dyad = pl.RRRDyad(crank.output, o4, distance1=m.R3, distance2=m.R4, x=b[0], y=b[1])
        linkage = pl.Linkage([o2, o4, crank, dyad])
        pts = np.array([p[3] for p in linkage.step(iterations=n)], dtype=float)
        psi = np.degrees(np.unwrap(np.arctan2(pts[:, 1], pts[:, 0] - m.R1)))
        assert abs((psi.max() - psi.min()) - swing) < 1e-4


BAD_CRANK_ROCKERS = [(180.0, 1.2, "swing"), (200.0, 1.0, "swing"), (0.0, 1.2, "swing"),
                     (-5.0, 1.2, "swing"), (float("nan"), 1.2, "swing"),
                     (40.0, 0.9, "time ratio"), (40.0, float("nan"), "time ratio"),
                     (10.0, 4.0, "no crank-rocker")]


@pytest.mark.parametrize("swing, Q, word", BAD_CRANK_ROCKERS)
def test_crank_rocker_bad_problems_say_why_in_one_line(swing, Q, word):
    with pytest.raises(ValueError, match=word) as e:
        synthesis.crank_rocker(swing, Q)
    assert "\n" not in str(e.value)


# ---------------------------------------------------------------- function generation

FUNCTIONS = [  # f, x range, input (start, span), output (start, span)
    ("log10", np.log10, (1.0, 2.0), (30.0, 60.0), (90.0, 60.0)),
    ("x^1.5", lambda x: x ** 1.5, (1.0, 3.0), (165.0, 90.0), (210.0, 60.0)),
    ("sin", np.sin, (0.0, 1.5), (20.0, 90.0), (80.0, 60.0)),
]


def working(name, f, xr, ir, orng):
    try:
        return synthesis.function(f, xr, ir, orng)
    except ValueError as e:
        pytest.fail(f"{name}: {e}")


def theta4_by_construction(g, th2):
    m = g.mechanism
    out = []
    for t in np.atleast_1d(th2):
        _, b = pin_b(m, float(t), g.branch)
        out.append(math.degrees(math.atan2(b[1], b[0] - m.R1)))
    return np.array(out)


@pytest.mark.parametrize("name, f, xr, ir, orng", FUNCTIONS, ids=[c[0] for c in FUNCTIONS])
def test_function_precision_points_exact(name, f, xr, ir, orng):
    g = working(name, f, xr, ir, orng)
    xp, t2, t4 = g.precision
    # the documented Chebyshev spacing, and THETA 2, THETA 4 from the documented scaling
    n = np.arange(1, 4)
    assert np.allclose(xp, (xr[0] + xr[1]) / 2 - (xr[1] - xr[0]) / 2
                       * np.cos((2 * n - 1) * np.pi / 6), rtol=0, atol=1e-15)
    assert np.allclose(t2, ir[0] + ir[1] * (xp - xr[0]) / (xr[1] - xr[0]), atol=1e-12)
    y0, y1 = f(xr[0]), f(xr[1])
    assert np.allclose(t4, orng[0] + orng[1] * (f(xp) - y0) / (y1 - y0), atol=1e-12)
    # met by the construction and by the engine
    assert np.max(np.abs(wrap(theta4_by_construction(g, t2) - t4))) <= TOL
    got = analyze_quiet(g.mechanism, t2, ["ATH4"], g.branch)["ATH4"]
    assert np.max(np.abs(wrap(got - t4))) <= TOL
    # the structural error over the range is the construction's too
    sel = np.arange(0, len(g.x), 20)
    mine = wrap(theta4_by_construction(g, g.th2[sel]) - g.th4[sel])
    assert np.max(np.abs(mine - g.structural_error[sel])) <= TOL
    assert g.max_error == pytest.approx(np.max(np.abs(g.structural_error)))
    assert g.max_error > 0  # three points cannot generate these functions exactly


def test_function_least_squares_satisfies_the_normal_equations():
    name, f, xr, ir, orng = FUNCTIONS[0]
    g = synthesis.function(f, xr, ir, orng, points=7)
    _, t2, t4 = g.precision
    assert len(t2) == 7
    r2, r4 = np.radians(t2), np.radians(t4)
    M = np.column_stack([np.cos(r4), -np.cos(r2), np.ones_like(r2)])
    resid = M @ np.array(g.K) - np.cos(r2 - r4)
    assert np.max(np.abs(M.T @ resid)) <= 1e-12   # least squares: residual orthogonal
    assert np.max(np.abs(resid)) > 1e-9           # and not an exact fit
    m = g.mechanism
    assert g.K[0] == pytest.approx(m.R1 / m.R2) and g.K[1] == pytest.approx(m.R1 / m.R4)
    assert g.K[2] == pytest.approx((m.R1**2 + m.R2**2 + m.R4**2 - m.R3**2) / (2 * m.R2 * m.R4))


def test_function_given_precision_points():
    f = np.log10
    g = synthesis.function(f, (1.0, 2.0), (30.0, 60.0), (90.0, 60.0), points=[1.1, 1.5, 1.9])
    assert list(g.precision[0]) == [1.1, 1.5, 1.9]
    got = analyze_quiet(g.mechanism, g.precision[1], ["ATH4"], g.branch)["ATH4"]
    assert np.max(np.abs(wrap(got - g.precision[2]))) <= TOL


@pytest.mark.parametrize("name, f, xr, ir, orng", FUNCTIONS, ids=[c[0] for c in FUNCTIONS])
def test_function_pylinkage_freudenstein_agrees(name, f, xr, ir, orng):
    pytest.importorskip("pylinkage")
    from pylinkage.synthesis.function_generation import (
        coefficients_to_link_lengths,
        solve_freudenstein_3_positions,
    )

    g = working(name, f, xr, ir, orng)
    _, t2, t4 = g.precision
    K = solve_freudenstein_3_positions(list(zip(np.radians(t2), np.radians(t4))))
    assert np.allclose(K, g.K, rtol=1e-9, atol=1e-12)
    a, b, c, d = coefficients_to_link_lengths(*K, ground_length=g.mechanism.R1)
    m = g.mechanism
    assert np.allclose([a, b, c, d], [m.R2, m.R3, m.R4, m.R1], rtol=1e-9)


@settings(max_examples=80)
@given(p=st.floats(0.3, 3.0), x0=st.floats(0.5, 2.0), w=st.floats(0.5, 3.0),
       s2=st.floats(0.0, 180.0), w2=st.floats(30.0, 120.0), s4=st.floats(0.0, 360.0),
       w4=st.floats(20.0, 120.0), down=st.booleans())
def test_function_drawn_problems(p, x0, w, s2, w2, s4, w4, down):
    w4 = -w4 if down else w4
    try:
        g = synthesis.function(lambda x: x ** p, (x0, x0 + w), (s2, w2), (s4, w4))
    except ValueError as e:
        assert "\n" not in str(e)
        event("refused: " + str(e).split(":")[0].split(" ")[0])
        return
    event("generated")
    _, t2, t4 = g.precision
    assert np.max(np.abs(wrap(theta4_by_construction(g, t2) - t4))) <= TOL
    got = analyze_quiet(g.mechanism, t2, ["ATH4"], g.branch)["ATH4"]
    assert np.max(np.abs(wrap(got - t4))) <= TOL


BAD_FUNCTIONS = [
    (lambda x: 0 * x + 1.0, (1, 2), (30, 60), (90, 60), 3, "differ"),
    (np.log10, (1, 1), (30, 60), (90, 60), 3, "differ"),
    (np.log10, (1, 2), (30, 0), (90, 60), 3, "span"),
    (np.log10, (1, 2), (30, 360), (90, 60), 3, "span"),
    (np.log10, (1, 2), (30, 60), (90, 60), 2, "three"),
    (np.log10, (1, 10), (45, 60), (135, 90), 3, "no four-bar"),
    (np.sqrt, (-1, 2), (30, 60), (90, 60), 3, "finite"),
]


@pytest.mark.parametrize("f, xr, ir, orng, pts, word", BAD_FUNCTIONS)
def test_function_bad_problems_say_why_in_one_line(f, xr, ir, orng, pts, word):
    with pytest.raises(ValueError, match=word) as e:
        synthesis.function(f, xr, ir, orng, points=pts)
    assert "\n" not in str(e.value)


# ---------------------------------------------------------------- motion generation

POSES3 = [
    [(0.0, 0.0, 0.0), (1.0, 0.5, 20.0), (2.0, 0.3, 45.0)],
    [(1.0, 2.0, 90.0), (3.0, 2.5, 60.0), (4.0, 4.0, 10.0)],
    [(10.0, -5.0, -30.0), (12.0, -4.0, 0.0), (13.0, -1.0, 40.0)],
]
POSES2 = [[(0.0, 0.0, 0.0), (2.0, 1.0, -30.0)], [(5.0, 5.0, 170.0), (4.0, 7.0, 120.0)],
          [(1.0, 1.0, 0.0), (1.0, 1.0, 50.0)]]  # the last: P is the pole


def check_poses(res, poses):
    P = np.asarray(poses, dtype=float)
    ext = max(np.hypot(*(P[i, :2] - P[j, :2])) for i in range(len(P)) for j in range(i)) \
        or 1.0
    # by construction
    for (x, y, ang), th in zip(P, res.crank_angles):
        ux, uy, line = coupler_in_user(res, float(th))
        assert math.hypot(ux - x, uy - y) <= TOL * ext
        assert abs(wrap(line + res.line_angle - ang)) <= TOL * 180
    # by the engine
    m = res.mechanism
    pm = sielaff.point_motion(m, res.crank_angles, 3, res.coupler.r, res.coupler.angle,
                              branch=res.branch)
    ux, uy = res.placement.to_user(pm["X"], pm["Y"])
    assert np.max(np.hypot(ux - P[:, 0], uy - P[:, 1])) <= TOL * ext
    th3 = analyze_quiet(m, res.crank_angles, ["ATH3"], res.branch)["ATH3"]
    assert np.max(np.abs(wrap(th3 + res.placement.angle + res.line_angle - P[:, 2]))) \
        <= TOL * 180


def check_no_defect(res):
    """The defect checks, redone: one branch at every pose, met in order turning one way
    less than a turn, and no toggle passed."""
    assert res.defects == ()
    m = res.mechanism
    signs = []
    for th in res.crank_angles:
        a, b = pin_b(m, float(th), res.branch)
        signs.append((m.R1 - a[0]) * (b[1] - a[1]) - (0.0 - a[1]) * (b[0] - a[0]))
    assert all(s > 0 for s in signs) or all(s < 0 for s in signs)
    steps = np.mod(res.direction * np.diff(res.crank_angles), 360.0)
    assert np.sum(steps) < 360.0
    assert np.sign(m.TH2D) == res.direction
    c = sielaff.linkage_class(m)
    if not c.turns_fully:
        travel = np.linspace(0.0, np.sum(steps), 200)
        th = res.crank_angles[0] + res.direction * travel
        assert analyze_quiet(m, th, ["ATH4"], res.branch).not_assembled == 0


@pytest.mark.parametrize("poses", POSES3 + POSES2)
def test_motion_searched_meets_every_pose(poses):
    res = synthesis.motion(poses)
    check_poses(res, poses)
    check_no_defect(res)
    assert sielaff.linkage_class(res.mechanism).turns_fully


@pytest.mark.parametrize("moving", [((0.0, -1.0), (1.0, 1.0)), ((-1.0, 0.5), (2.0, -0.5)),
                                    ((0.3, 0.3), (-0.4, 2.0))])
def test_motion_given_choices_meet_every_pose_or_name_the_defect(moving):
    poses = POSES3[0]
    res = synthesis.motion(poses, moving=moving)
    assert res.choices["moving"] == tuple(map(tuple, moving))
    P = np.asarray(poses)
    # the fixed pivots are the circle centres of the moving pivots (pylinkage's own
    # circumcentre is the outside check below); here: equal distances
    for k, fixed in ((0, (res.placement.x, res.placement.y)),
                     (1, res.placement.to_user(res.mechanism.R1, 0.0))):
        u, v = moving[k]
        pts = [(x + u * math.cos(math.radians(a)) - v * math.sin(math.radians(a)),
                y + u * math.sin(math.radians(a)) + v * math.cos(math.radians(a)))
               for x, y, a in P]
        r = [math.hypot(px - float(fixed[0]), py - float(fixed[1])) for px, py in pts]
        assert max(r) - min(r) <= TOL * max(r)
    if any("branch" in d for d in res.defects):
        return  # on one branch the engine cannot meet them all: that is the defect
    check_poses(res, poses)


def test_motion_branch_defect_is_found():
    res = synthesis.motion(POSES3[0], moving=((0.0, -1.0), (1.0, 1.0)))
    assert any(d.startswith("branch defect") for d in res.defects)
    m = res.mechanism
    O2 = np.array([res.placement.x, res.placement.y])
    O4 = np.array(res.placement.to_user(m.R1, 0.0), dtype=float)
    signs = set()
    for x, y, a in POSES3[0]:
        c, s = math.cos(math.radians(a)), math.sin(math.radians(a))
        A = np.array([x + 0.0 * c + 1.0 * s, y + 0.0 * s - 1.0 * c])
        B = np.array([x + 1.0 * c - 1.0 * s, y + 1.0 * s + 1.0 * c])
        d, e = O4 - A, B - A
        signs.add(bool(d[0] * e[1] - d[1] * e[0] > 0))
        assert abs(np.hypot(*(A - O2)) - m.R2) <= 1e-9
    assert signs == {True, False}


def test_motion_two_poses_fixed_pivots_on_the_bisectors():
    poses = POSES2[0]
    res = synthesis.motion(poses, moving=((0.5, 1.0), (1.5, -0.5)), fixed=(1.0, -2.0))
    if not any("branch" in d for d in res.defects):
        check_poses(res, poses)
    O2 = np.array([res.placement.x, res.placement.y])
    P = np.asarray(poses)
    c, s = np.cos(np.radians(P[:, 2])), np.sin(np.radians(P[:, 2]))
    A = np.stack([P[:, 0] + 0.5 * c - 1.0 * s, P[:, 1] + 0.5 * s + 1.0 * c], axis=1)
    mid, d = A.mean(axis=0), A[1] - A[0]
    assert np.allclose(O2, mid + 1.0 * np.array([-d[1], d[0]]) / np.hypot(*d), atol=1e-12)


@settings(max_examples=30)
@given(seed=st.integers(0, 2**32 - 1), n=st.sampled_from([2, 3]))
def test_motion_drawn_problems(seed, n):
    """Poses a random four-bar's coupler passes through (so reachable), then explicit random
    moving pivots: either a linkage meeting every pose, or a one-line refusal."""
    rng = np.random.default_rng(seed)
    poses = [(float(rng.uniform(-5, 5)), float(rng.uniform(-5, 5)), float(rng.uniform(-180, 180)))]
    for _ in range(n - 1):
        x, y, a = poses[-1]
        poses.append((x + float(rng.uniform(0.5, 3)), y + float(rng.uniform(-2, 2)),
                      a + float(rng.uniform(-60, 60))))
    moving = rng.uniform(-3, 3, (2, 2))
    try:
        res = synthesis.motion(poses, moving=moving)
    except ValueError as e:
        assert "\n" not in str(e)
        event("refused")
        return
    if any("branch" in d for d in res.defects):
        event("branch defect found")
        return
    event("met, defects: " + ("none" if not res.defects else "order/toggle"))
    check_poses(res, poses)


def test_motion_pylinkage_circumcentres_and_simulation_agree():
    """pylinkage's own circumcentre of each moving pivot's three positions is our fixed
    pivot, and its simulation of the linkage (7200 steps) passes each pose's point."""
    pytest.importorskip("pylinkage")
    from pylinkage.synthesis._types import Pose
    from pylinkage.synthesis.burmester import _body_point_world_positions, _circumcenter

    for poses in POSES3:
        res = synthesis.motion(poses)
        pp = [Pose(x, y, math.radians(a)) for x, y, a in poses]
        fixed = [complex(res.placement.x, res.placement.y),
                 complex(*(float(v) for v in res.placement.to_user(res.mechanism.R1, 0.0)))]
        for (u, v), o in zip(res.choices["moving"], fixed):
            w = _body_point_world_positions(complex(u, v), pp)
            assert abs(_circumcenter(*w) - o) <= 1e-9 * abs(o - w[0])
        dist = pylinkage_coupler_distances(res, [(x, y) for x, y, _ in poses])
        assert max(dist) <= 1e-3 * max(m_len(res.mechanism))


def m_len(m):
    return (m.R1, m.R2, m.R3, m.R4)


def pylinkage_coupler_distances(res, targets, n=7200):
    """Each target's distance from the coupler curve pylinkage traces: its Crank about O2,
    an RRRDyad for B started at our B (so on our branch; from there it is pylinkage's
    own circle intersection, nearest the last position), and the coupler point as a
    FixedDyad r from A at the coupler angle from A->B, all in the user's frame."""
    import pylinkage as pl

    m, place = res.mechanism, res.placement
    t0 = float(res.crank_angles[0])
    _, b = pin_b(m, t0, res.branch)
    bx, by = (float(v) for v in place.to_user(*b))
    o4x, o4y = (float(v) for v in place.to_user(m.R1, 0.0))
    o2, o4 = pl.Ground(place.x, place.y), pl.Ground(o4x, o4y)
    crank = pl.Crank(anchor=o2, radius=m.R2, angular_velocity=2 * math.pi / n,
                     initial_angle=math.radians(place.angle + t0))
    dyad = pl.RRRDyad(crank.output, o4, distance1=m.R3, distance2=m.R4, x=bx, y=by)
    point = pl.FixedDyad(anchor1=crank.output, anchor2=dyad, distance=res.coupler.r,
                         angle=math.radians(res.coupler.angle))
    linkage = pl.Linkage([o2, o4, crank, dyad, point])
    traced = np.array([p[4] for p in linkage.step(iterations=n)], dtype=float)
    return [float(np.min(np.hypot(traced[:, 0] - x, traced[:, 1] - y))) for x, y in targets]


BAD_MOTIONS = [
    ([(0, 0, 0)], {}, "two or three"),
    ([(0, 0, 0), (1, 1, 10), (2, 0, 20), (3, 1, 5)], {}, "two or three"),
    ([(0, 0, 0), (0, 0, 0)], {}, "same pose"),
    ([(0, 0, 0), (0, 0, 30), (0, 0, 60)], {}, "rotations about one point"),
    ([(0, 0, 0), (0, 0, 30)], {"moving": ((0, 0), (1, 0))}, "pole"),
    ([(0, 0, 0), (1, 0, 0), (2, 0, 0)], {"moving": ((0, 0), (0, 1))}, "line"),
    ([(0, 0, 0), (1, 1, 10), (2, 0, 20)], {"fixed": (1, 1)}, "fixed"),
    ([(0, 0, float("nan")), (1, 1, 10)], {}, "finite"),
]


@pytest.mark.parametrize("poses, kw, word", BAD_MOTIONS)
def test_motion_bad_problems_say_why_in_one_line(poses, kw, word):
    with pytest.raises(ValueError, match=word) as e:
        synthesis.motion(poses, **kw)
    assert "\n" not in str(e.value)


# ---------------------------------------------------------------- path generation

def known_curve_points(R, th2_deg, r, ang, branch="open"):
    """Points a known four-bar's coupler point passes (engine frame), by construction."""
    m = sielaff.EXAMPLE.replace(R1=R[0], R2=R[1], R3=R[2], R4=R[3])
    out = []
    for t in th2_deg:
        a, b = pin_b(m, t, branch)
        t3 = math.atan2(b[1] - a[1], b[0] - a[0]) + math.radians(ang)
        out.append((a[0] + r * math.cos(t3), a[1] + r * math.sin(t3)))
    return out


PATHS = [  # lengths, crank angles, coupler point (r, angle)
    ((4.0, 1.0, 3.5, 3.0), [0.0, 40.0, 90.0, 150.0, 200.0], (2.0, 30.0)),
    ((5.0, 1.5, 4.0, 4.5), [10.0, 60.0, 120.0, 250.0], (3.0, -20.0)),
]


@pytest.mark.parametrize("R, th, cp", PATHS)
def test_path_through_reachable_points(R, th, cp):
    pytest.importorskip("scipy")
    pts = known_curve_points(R, th, *cp)
    res = synthesis.path(pts)
    ext = max(math.dist(p, q) for p in pts for q in pts)
    assert np.all(res.residuals <= 1e-9 * ext)
    # the crank angles found put the coupler point on each target: construction, engine
    for (x, y), t in zip(pts, res.crank_angles):
        ux, uy, _ = coupler_in_user(res, float(t))
        assert math.hypot(ux - x, uy - y) <= 1e-9 * ext
    pm = sielaff.point_motion(res.mechanism, res.crank_angles, 3, res.coupler.r,
                              res.coupler.angle, branch=res.branch)
    ux, uy = res.placement.to_user(pm["X"], pm["Y"])
    assert np.max(np.hypot(ux - np.array(pts)[:, 0], uy - np.array(pts)[:, 1])) <= 1e-9 * ext
    check_no_defect(res)


@pytest.mark.slow
def test_path_prescribed_crank_angles():
    pytest.importorskip("scipy")
    R, th, cp = PATHS[0]
    pts = known_curve_points(R, th, *cp)
    steps = [t - th[0] for t in th]
    res = synthesis.path(pts, crank_angles=steps)
    assert np.allclose(wrap(res.crank_angles - res.crank_angles[0]), wrap(steps), atol=1e-9)
    ext = max(math.dist(p, q) for p in pts for q in pts)
    assert np.all(res.residuals <= 1e-9 * ext)
    check_no_defect(res)


@pytest.mark.slow
def test_path_is_reproducible():
    pytest.importorskip("scipy")
    pts = known_curve_points(*PATHS[1][:1], PATHS[1][1], *PATHS[1][2])
    a, b = synthesis.path(pts, seed=3), synthesis.path(pts, seed=3)
    assert a.mechanism == b.mechanism and a.placement == b.placement


def test_path_residuals_are_distances_from_the_curve():
    """Points off any reachable curve (six on a circle with a bump): the residuals are each
    target's distance from the coupler curve, checked against the construction's curve."""
    pytest.importorskip("scipy")
    t = np.radians(np.arange(0, 360, 60))
    pts = [(2 * math.cos(a), math.sin(a) + (0.3 if k == 2 else 0.0)) for k, a in enumerate(t)]
    res = synthesis.path(pts, starts=12)
    th = np.linspace(0.0, 360.0, 7201)
    curve = []
    for x in th:
        try:
            curve.append(coupler_in_user(res, float(x))[:2])
        except (ValueError, ZeroDivisionError):
            continue
    curve = np.array(curve)
    for (x, y), r in zip(pts, res.residuals):
        d = np.min(np.hypot(curve[:, 0] - x, curve[:, 1] - y))
        assert r <= d + 1e-12 and d - r <= 2e-3  # the curve sampled every 0.05 deg


def test_path_pylinkage_simulation_passes_the_points():
    pytest.importorskip("scipy")
    pytest.importorskip("pylinkage")
    R, th, cp = PATHS[0]
    pts = known_curve_points(R, th, *cp)
    res = synthesis.path(pts)
    dist = pylinkage_coupler_distances(res, pts)
    assert max(dist) <= 1e-3 * max(m_len(res.mechanism))


BAD_PATHS = [([(0, 0), (1, 1)], {}, "three or more"), ([(0, 0)] * 4, {}, "one point"),
             ([(0, 0), (1, 1), (1, 1), (2, 0)], {}, "same point"),
             ([(0, 0), (1, 1), (2, float("inf"))], {}, "finite"),
             ([(0, 0), (1, 1), (2, 0)], {"crank_angles": [10, 20, 30]}, "first 0"),
             ([(0, 0), (1, 1), (2, 0)], {"crank_angles": [0, 200, 400]}, "360")]


@pytest.mark.parametrize("pts, kw, word", BAD_PATHS)
def test_path_bad_problems_say_why_in_one_line(pts, kw, word):
    pytest.importorskip("scipy")
    with pytest.raises(ValueError, match=word) as e:
        synthesis.path(pts, **kw)
    assert "\n" not in str(e.value)


# ---------------------------------------------------------------- the mass model

@pytest.mark.parametrize("units, rho, area", [("in-lb-sec", None, None), ("SI", None, None),
                                              ("in-lb-sec", 0.1, 2.0)])
def test_masses_are_uniform_bars(units, rho, area):
    m = synthesis.crank_rocker(40.0, 1.3, rocker=2.0, units=units).best.mechanism
    m = synthesis.masses(m, density=rho, area=area)
    if rho is None:
        rho = 7850.0 if units == "SI" else 0.28360
        area = 3.125e-4 if units == "SI" else 0.5
    for k in (2, 3, 4):
        L = getattr(m, f"R{k}")
        W = getattr(m, f"W{k}")
        assert W == pytest.approx(rho * area * L, rel=1e-4)
        assert getattr(m, f"ZI{k}") == pytest.approx(W / MASS_DIVISOR[units] * L * L / 12,
                                                     rel=1e-12)
        assert getattr(m, f"RG{k}") == L / 2 and getattr(m, f"ADEL{k}") == 0.0
    k = analyze_quiet(m, np.linspace(0, 360, 37), ["TORQ"], "open")
    assert np.all(np.isfinite(k["TORQ"]))


def test_masses_bad_density():
    m = synthesis.crank_rocker(40.0, 1.3).best.mechanism
    with pytest.raises(ValueError, match="positive"):
        synthesis.masses(m, density=-1.0)


def test_motion_pylinkage_motion_generation_agrees():
    """pylinkage's own three-pose motion synthesis (Burmester dyads): each of its linkages,
    given to ours as the same moving pivots, has the same fixed pivots and link lengths."""
    pytest.importorskip("pylinkage")
    from pylinkage.synthesis import Pose, motion_generation

    poses = POSES3[0]
    theirs = motion_generation([Pose(x, y, math.radians(a)) for x, y, a in poses])
    assert len(theirs.raw_solutions) >= 3
    x1, y1, a1 = poses[0]
    c, s = math.cos(math.radians(a1)), math.sin(math.radians(a1))

    def body(w):  # a world point at pose 1, in the coupler's frame
        dx, dy = w[0] - x1, w[1] - y1
        return (c * dx + s * dy, -s * dx + c * dy)

    for sol in theirs.raw_solutions:
        res = synthesis.motion(poses, moving=(body(sol.crank_pivot_b),
                                              body(sol.coupler_pivot_c)))
        m = res.mechanism
        o4 = res.placement.to_user(m.R1, 0.0)
        scale = max(sol.ground_length, sol.crank_length, sol.rocker_length)
        assert math.dist((res.placement.x, res.placement.y), sol.ground_pivot_a) <= 1e-9 * scale
        assert math.dist((float(o4[0]), float(o4[1])), sol.ground_pivot_d) <= 1e-9 * scale
        assert np.allclose([m.R1, m.R2, m.R3, m.R4],
                           [sol.ground_length, sol.crank_length, sol.coupler_length,
                            sol.rocker_length], rtol=1e-9)
        if not any("branch" in d for d in res.defects):
            check_poses(res, poses)
