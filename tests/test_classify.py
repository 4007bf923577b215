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
    assert status == 3 and "kind: triple-rocker" in text
    assert "link 2 swings from THETA 2 = 295.94 deg to 64.06 deg (through 0)" in text
    assert math.isclose(64.06, float(np.degrees(np.arccos((100 + 16 - 81) / 80))), abs_tol=0.01)
