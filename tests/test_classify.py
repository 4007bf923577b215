"""Every four-bar classified, with link 2 the input: the kind, the Grashof margin and the
input's toggle limits, right on every boundary and checked against the engine's own
assembly (positions exist exactly between the limits)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import sielaff
from sielaff.engine import analyze
from sielaff.engine.classify import KINDS, linkage_class
from sielaff.mechanism import EXAMPLE, crank_rocker_failure
from test_effects import FORCES, newton_euler


def lengths(r1, r2, r3, r4):
    return EXAMPLE.replace(R1=r1, R2=r2, R3=r3, R4=r4)


@pytest.mark.parametrize("r, kind", [
    ((12.0, 4.0, 16.0, 12.0), "crank-rocker"),    # the report's example
    ((2.0, 4.0, 5.0, 4.5), "double-crank"),       # frame shortest
    ((6.0, 4.0, 2.0, 5.5), "double-rocker"),      # coupler shortest (Grashof)
    ((6.0, 4.0, 5.0, 2.0), "rocker-crank"),       # rocker shortest
    ((10.0, 4.0, 5.0, 4.0), "triple-rocker"),     # s + l > p + q
    ((8.0, 3.0, 4.0, 7.0), "change-point"),       # 3 + 8 = 4 + 7
])
def test_each_kind(r, kind):
    c = linkage_class(lengths(*r))
    assert c.kind == kind and c.kind in KINDS
    s, lng = min(r), max(r)
    assert c.grashof_sum == s + lng
    assert c.grashof_margin == pytest.approx(sum(r) - 2 * (s + lng), abs=1e-12)
    assert c.turns_fully == (kind in ("crank-rocker", "double-crank", "change-point"))


@pytest.mark.parametrize("eps, kind", [(0.0, "change-point"), (1e-10, "change-point"),
                                       (-1e-10, "change-point"), (1e-7, "crank-rocker"),
                                       (-1e-7, "triple-rocker")])
def test_the_change_point_boundary_exact_and_within_1e_9(eps, kind):
    """R1 = 8 + eps with R2 = 3, R3 = 4, R4 = 7: s + l = p + q at eps = 0; within 1E-9 of
    s + l is the change point, past it the side it is on."""
    assert linkage_class(lengths(8.0 - eps * 11, 3.0, 4.0, 7.0)).kind == kind


def test_the_shortest_link_decides_a_grashof_kind():
    """(Two links can only tie for shortest on the change-point boundary: with p = s,
    s + l < p + q would need l < q.)"""
    assert linkage_class(lengths(4.0, 4.0, 4.0, 4.0)).kind == "change-point"
    assert linkage_class(lengths(6.0, 4.0, 2.0 + 1e-9, 5.5)).kind == "double-rocker"
    assert linkage_class(lengths(6.0, 4.0, 5.0, 2.0 - 1e-9)).kind == "rocker-crank"


def test_arrays_broadcast_and_the_public_name():
    c = sielaff.linkage_class(EXAMPLE.replace(R4=np.array([12.0, 2.0, 30.0])[:, None],
                                              R3=np.array([16.0, 15.0])))
    assert c.kind.shape == (3, 2) and c.toggles.shape == (3, 2, 4)
    assert c.kind[0, 0] == "crank-rocker" and c.turns_fully[0, 0]


def test_the_crank_rocker_kind_is_the_reports_test():
    """On hypothesis-drawn lengths the kind is crank-rocker exactly when the report's five
    conditions hold (exact, with the same 1E-9 boundary)."""
    rng = np.random.default_rng(3)
    for r in rng.uniform(0.5, 10.0, size=(3000, 4)):
        m = lengths(*r)
        assert (linkage_class(m).kind == "crank-rocker") == (crank_rocker_failure(m) is None)


@settings(max_examples=200, derandomize=True)
@given(st.tuples(*[st.floats(0.5, 10.0)] * 4))
def test_the_toggles_bound_where_the_engine_assembles(r):
    """Positions exist (ASSEMBLED) exactly where THETA 2 lies between the input's limits,
    for every kind: the engine's loop closure against the classification's formula."""
    m = lengths(*r)
    c = linkage_class(m)
    assume(c.kind != "change-point")
    th = np.arange(0.0, 360.0, 0.25)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the AssemblyWarning: counted, expected here
        ok = analyze(m, th, ["ASSEMBLED"])["ASSEMBLED"]
    toggles = c.toggles[np.isfinite(c.toggles)]
    far = np.all(np.abs((th[:, None] - toggles[None, :] + 180) % 360 - 180) > 1e-6, axis=1)
    # between consecutive toggles the assembly does not change
    if c.turns_fully:
        assert ok[far].all()
        return
    for a, b in zip(toggles, np.roll(toggles, -1)):
        arc = ((th - a) % 360 < (b - a) % 360) & far
        if arc.any():
            assert ok[arc].all() or not ok[arc].any(), (r, a, b)
    # and it does change at each toggle
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for t in toggles:
            before = analyze(m, [t - 1e-3], ["ASSEMBLED"])["ASSEMBLED"][0]
            after = analyze(m, [t + 1e-3], ["ASSEMBLED"])["ASSEMBLED"][0]
            assert before != after, (r, t)
    # the arcs the classification calls reachable are the assembled ones
    for a, b in c.arcs:
        mid = (a + ((b - a) % 360) / 2) % 360
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            assert analyze(m, [mid], ["ASSEMBLED"])["ASSEMBLED"][0], (r, a, b)


def test_check_prints_the_kind_for_any_deck(tmp_path):
    import contextlib
    import io

    from conftest import DECKS
    from sielaff.cli import main

    lines = (DECKS / "example.dat").read_text().splitlines()
    lines[2] = "    10.0     4.0     5.0     4.0"  # a triple-rocker
    deck = tmp_path / "d.dat"
    deck.write_text("\n".join(lines) + "\n")
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        status = main(["check", str(deck)])
    text = out.getvalue()
    assert status == 0 and "kind: triple-rocker" in text  # usable, as any kind (issue 22)
    assert "link 2 swings from THETA 2 = 295.94 deg to 64.06 deg (through 0)" in text
    assert math.isclose(64.06, float(np.degrees(np.arccos((100 + 16 - 81) / 80))), abs_tol=0.01)


# ----- either branch, every kind: positions, rates and forces by independent routes ----------
def _b(m, th2, branch):
    r = analyze(m, [th2], ["ATH3"], branch=branch)
    t2, t3 = math.radians(th2), math.radians(float(r["ATH3"][0]))
    return m.R2 * complex(math.cos(t2), math.sin(t2)) + m.R3 * complex(math.cos(t3),
                                                                      math.sin(t3))


def _circles(m, th2):
    """Both intersections of the circles about A (radius R3) and O4 (radius R4)."""
    t2 = math.radians(th2)
    A, O4 = m.R2 * complex(math.cos(t2), math.sin(t2)), complex(m.R1, 0.0)
    d = abs(O4 - A)
    if d < 1e-9 * (m.R1 + m.R2):  # A on O4: every B on the circle closes the loop
        return None
    a = (m.R3**2 - m.R4**2 + d * d) / (2 * d)
    h = math.sqrt(max(m.R3**2 - a * a, 0.0))
    P = A + a * (O4 - A) / d
    perp = 1j * (O4 - A) / d
    return P + h * perp, P - h * perp, h


any_linkage = st.tuples(*[st.floats(0.5, 10.0)] * 4)


@settings(max_examples=200, derandomize=True)
@given(any_linkage, st.floats(0.0, 359.9))
def test_both_branches_are_the_two_circle_intersections(r, th2):
    m = lengths(*r)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ok = analyze(m, [th2], ["ASSEMBLED"])["ASSEMBLED"][0]
    assume(ok)
    circles = _circles(m, th2)
    assume(circles is not None)
    b1, b2, h = circles
    assume(h > 1e-6 * sum(r))  # away from a toggle, where the two are one
    got = {_b(m, th2, "open"), _b(m, th2, "crossed")}
    scale = sum(r)
    for want in (b1, b2):
        assert min(abs(g - want) for g in got) < 1e-12 * scale
    assert abs(_b(m, th2, "open") - _b(m, th2, "crossed")) > h  # two different assemblies


def test_open_branch_of_the_example_is_the_1966_one():
    b_open, b_crossed = _b(EXAMPLE, 40.0, "open"), _b(EXAMPLE, 40.0, "crossed")
    assert b_open.imag > 0 > b_crossed.imag  # B above the frame line, as in Figure 9
    with pytest.raises(ValueError, match="branch"):
        analyze(EXAMPLE, [40.0], branch="upside-down")


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_every_kind_and_branch_agrees_with_newton_euler(branch):
    """Rates and forces on either branch of any four-bar, at an angle it reaches: the
    engine against the independent kinematics and Newton-Euler solve.  Each branch is
    its own run, and the cases that pass the filters are counted."""
    checked = []

    @settings(max_examples=100, derandomize=True)
    @given(any_linkage, st.floats(0.0, 1.0))
    def check(r, where):
        m = EXAMPLE.replace(R1=r[0], R2=r[1], R3=r[2], R4=r[3], RG3=r[2] / 2, RG4=r[3] / 2)
        c = linkage_class(m)
        assume(c.arcs)
        a, b = c.arcs[0]
        th2 = (a + ((b - a) % 360.0) * (0.05 + 0.9 * where)) % 360.0  # inside the arc
        gamma = float(analyze(m, [th2], ["GAMMA"], branch=branch)["GAMMA"][0])
        assume(15.0 < gamma < 165.0)
        got = analyze(m, [th2], list(FORCES), branch=branch, gravity="down")
        want, _ = newton_euler(m, th2, 0.0, (0.0, -386.088), [], 0.0, _b(m, th2, branch))
        scale = max(abs(v) for v in want.values())
        for name in FORCES:
            assert float(got[name][0]) == pytest.approx(want[name], abs=1e-9 * scale), name
        checked.append(c.kind)

    check()
    assert len(checked) >= 40, f"{branch}: only {len(checked)} cases passed the filters"
    assert len(set(checked)) >= 3, f"{branch}: kinds drawn {sorted(set(checked))}"


def test_reachable_spreads_angles_where_the_loop_closes():
    import sielaff

    triple = lengths(10.0, 4.0, 5.0, 4.0)
    th = sielaff.reachable(triple, 50)
    assert len(th) == 50 and th[0] == pytest.approx(295.944, abs=1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no AssemblyWarning: every angle assembles
        assert analyze(triple, th, ["ATH4"]).not_assembled == 0
    np.testing.assert_array_equal(sielaff.reachable(EXAMPLE, 4), [0.0, 90.0, 180.0, 270.0])
    assert len(sielaff.reachable(lengths(1.0, 1.0, 1.0, 3.0), 10)) == 0  # never closes


# ----- any point on any link --------------------------------------------------------------------
def test_points_at_the_pins_and_centres_are_the_engines():
    from sielaff import point_motion

    th = np.arange(0.0, 360.0, 15.0)
    r = analyze(EXAMPLE, th, ["VG3X", "VG3Y", "AG3X", "AG3Y", "VBX", "VBY", "ABX", "ABY",
                              "AG2X", "AG2Y"], th2dd=7.0)
    g3 = point_motion(EXAMPLE, th, 3, EXAMPLE.RG3, EXAMPLE.ADEL3, th2dd=7.0)
    b = point_motion(EXAMPLE, th, 4, EXAMPLE.R4, 0.0, th2dd=7.0)
    g2 = point_motion(EXAMPLE, th, 2, EXAMPLE.RG2, EXAMPLE.ADEL2, th2dd=7.0)
    for got, name in ((g3, "G3"), (b, "B"), (g2, "G2")):
        for q in ("V", "A"):
            if (q, name) == ("V", "G2"):
                continue
            for xy in "XY":
                np.testing.assert_allclose(got[q + xy], r[f"{q}{name}{xy}"], rtol=1e-12,
                                           atol=1e-9, err_msg=q + name + xy)
    # B on link 3 (r = R3 from A) is B on link 4: one point, two links
    b3 = point_motion(EXAMPLE, th, 3, EXAMPLE.R3, 0.0)
    b4 = point_motion(EXAMPLE, th, 4, EXAMPLE.R4, 0.0)
    for key in b3:
        np.testing.assert_allclose(b3[key], b4[key], rtol=1e-12, atol=1e-9, err_msg=key)


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_point_rates_are_the_derivatives_of_its_path(branch):
    """Velocity and acceleration against a spectral derivative of the coupler curve."""
    from sielaff import point_motion

    n = 512
    th = np.arange(n) * 360.0 / n
    w = EXAMPLE.TH2D
    p = point_motion(EXAMPLE, th, 3, np.array([3.0, 11.0])[:, None],
                     np.array([40.0, -70.0])[:, None], branch=branch)
    k = np.fft.fftfreq(n, d=1.0 / n)  # d/dth2 (radians) is i k in Fourier space
    for axis in "XY":
        path = p[axis]
        d1 = np.real(np.fft.ifft(1j * k * np.fft.fft(path, axis=-1), axis=-1)) * w
        d2 = np.real(np.fft.ifft(-(k**2) * np.fft.fft(path, axis=-1), axis=-1)) * w * w
        scale = np.max(np.abs(p["A" + axis]))
        np.testing.assert_allclose(p["V" + axis], d1, atol=1e-7 * np.max(np.abs(d1)))
        np.testing.assert_allclose(p["A" + axis], d2, atol=1e-6 * scale)
    assert p["X"].shape == (2, n)


@pytest.mark.parametrize("field, value", [("R1", float("nan")), ("R3", float("inf")),
                                          ("R2", 0.0), ("R4", -1.0)])
def test_a_length_no_linkage_has_gets_no_kind(field, value):
    """A NaN frame used to answer "triple-rocker" (issue 32): now one line naming it."""
    with pytest.raises(ValueError, match=f"{field} = .*a link length is a finite number"):
        linkage_class(EXAMPLE.replace(**{field: value}))
