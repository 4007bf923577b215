"""synthesis.rank steered and traced: constraints on figures, links and link ratios
(checked against values computed here from analyze and the lengths), near-ties going to
the next figure instead of the order given, shared ranks, and ``sielaff synth``'s rows
naming each candidate's varied values, k and side."""

from __future__ import annotations

import csv

import numpy as np
import pytest

import procs
import sielaff
from conftest import ROOT
from sielaff import Scene, synthesis

SCENE = Scene(tex=-20.0, gravity="down")


@pytest.fixture(scope="module")
def family():
    return synthesis.crank_rocker(45.0, 1.25, rocker=10.0, th2d=10.0).members(4)


def gamma_min(c, scene) -> float:
    """The least transmission angle of one candidate, straight from analyze."""
    g = sielaff.analyze(c.mechanism, np.arange(360.0), ["GAMMA"],
                        scene=scene.replace(branch=c.branch))["GAMMA"]
    return float(np.min(np.minimum(g, 180.0 - g)))


def lengths(c):
    m = c.mechanism
    return np.array([m.R1, m.R2, m.R3, m.R4], dtype=float)


def test_a_least_transmission_angle_splits_the_candidates(family):
    gamma = np.array([gamma_min(c, SCENE) for c in family])
    least = float(np.median(gamma))
    r = synthesis.rank(family, scene=SCENE, by=["TORQ_PEAK"],
                       pareto=["TORQ_RMS", "SHAK_PEAK"],
                       constraints={"GAMMA_MIN": (least, None)})
    want = gamma >= least
    assert 0 < want.sum() < len(family)  # the case is drawn: some meet it, some do not
    assert list(r.feasible) == list(want)
    # every feasible candidate is listed before every infeasible one
    seen = [bool(r.feasible[i]) for i in r.order]
    assert seen == sorted(seen, reverse=True)
    for i in np.flatnonzero(~want):
        assert r.violations[i].startswith("GAMMA_MIN = ") and "below the least" in \
            r.violations[i] and r.violations[i].endswith(" deg")
    assert all(r.violations[i] == "" for i in np.flatnonzero(want))
    # the Pareto front is taken over the feasible ones only
    assert set(int(i) for i in r.pareto) <= set(np.flatnonzero(want))
    ok = np.flatnonzero(want)
    front = synthesis.pareto_front(r.figures["TORQ_RMS"][ok], r.figures["SHAK_PEAK"][ok])
    assert sorted(ok[front]) == sorted(r.pareto)


@pytest.mark.parametrize("name", ["LONGEST", "SHORTEST", "R3/R2", "R1/R4"])
def test_link_constraints(family, name):
    L = np.array([lengths(c) for c in family])
    value = {"LONGEST": L.max(axis=1), "SHORTEST": L.min(axis=1),
             "R3/R2": L[:, 2] / L[:, 1], "R1/R4": L[:, 0] / L[:, 3]}[name]
    most = float(np.median(value))
    r = synthesis.rank(family, constraints={name: (None, most)})
    assert 0 < (value <= most).sum() < len(family)
    assert list(r.feasible) == list(value <= most)
    bad = np.flatnonzero(value > most)
    assert all("above the most" in r.violations[i] for i in bad)
    if name in ("LONGEST", "SHORTEST"):
        assert all(r.violations[i].endswith(" in") for i in bad)


def test_the_first_broken_constraint_is_named(family):
    r = synthesis.rank(family, constraints={"LONGEST": (None, 0.1), "GAMMA_MIN": (89.0, 90.0)})
    assert not r.feasible.any() and len(r.pareto) == 0
    assert all(v.startswith("LONGEST = ") for v in r.violations)


@pytest.mark.parametrize("constraints, text", [
    ({"TORQ": (None, 1.0)}, "constraint on 'TORQ'"),
    ({"R2/R2": (None, 1.0)}, "constraint on 'R2/R2'"),
    ({"KIND": (0, 1)}, "constraint on 'KIND'"),
    ({"LONGEST": (None, None)}, "give a least or a most"),
    ({"LONGEST": (5.0, 1.0)}, "least 5 is above most 1"),
    ({"LONGEST": 5.0}, "(least, most)"),
    ({"LONGEST": (None, float("nan"))}, "not a finite number"),
])
def test_bad_constraints_refused(family, constraints, text):
    with pytest.raises(ValueError, match=None) as err:
        synthesis.rank(family[:2], constraints=constraints)
    assert text in str(err.value) and "\n" not in str(err.value)


def near_tie(family):
    """Two linkages whose TORQ_PEAK differs by 2E-4 (relative) one way and whose SHAK_PEAK
    differs by 4E-2 the other way (a heavier rocker, a lighter crank: at constant speed
    without gravity the crank's weight moves the shaking force, not the torque)."""
    m = family[0].mechanism
    return [m, m.replace(W2=m.W2 * 0.5, W4=m.W4 * 1.0005)]


def test_a_near_tie_goes_to_the_next_figure(family):
    pair = near_tie(family)
    exact = synthesis.rank(pair, by=["TORQ_PEAK", "SHAK_PEAK"], tie=0.0)
    t, s = exact.figures["TORQ_PEAK"], exact.figures["SHAK_PEAK"]
    # drawn: the two figures disagree, and the TORQ_PEAK gap is below 1E-3 of it
    assert (t[0] < t[1]) and (s[1] < s[0]) and abs(t[1] - t[0]) < 1e-3 * t.max()
    assert list(exact.order) == [0, 1] and list(exact.ranks) == [1, 2]
    tied = synthesis.rank(pair, by=["TORQ_PEAK", "SHAK_PEAK"], tie=1e-3)
    assert list(tied.order) == [1, 0] and list(tied.ranks) == [2, 1]


def test_candidates_tied_on_every_figure_share_a_rank(family):
    """The same linkage with a heavier coupler: GAMMA_MIN (kinematic) is equal; ranked by
    GAMMA_MIN alone both are rank 1 and the next figure (TORQ_PEAK), not the order given,
    lists the lighter first."""
    m = family[0].mechanism
    heavy = m.replace(W3=3 * m.W3, ZI3=3 * m.ZI3)
    for cands, light in (([heavy, m], 1), ([m, heavy], 0)):
        r = synthesis.rank(cands, by=["GAMMA_MIN"])
        assert list(r.ranks) == [1, 1]
        assert r.figures["TORQ_PEAK"][light] < r.figures["TORQ_PEAK"][1 - light]
        assert int(r.order[0]) == light


def test_frame_traces_k_and_side(family):
    pytest.importorskip("pandas")
    r = synthesis.rank(family, constraints={"GAMMA_MIN": (30.0, None)})
    f = r.to_frame()
    for i in f.index:
        assert f.loc[i, "K"] == family[i].k and f.loc[i, "SIDE"] == family[i].side
        assert f.loc[i, "FEASIBLE"] == r.feasible[i]
    assert f.attrs["units"]["K"] == "-" and f.attrs["units"]["GAMMA_MIN"] == "deg"


def run(*args):
    return procs.run(list(args), cwd=ROOT, text=True, timeout=600)


SPEC = (ROOT / "decks" / "synth.toml").read_text()


def test_synth_rows_name_their_problem_k_and_side(tmp_path):
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC + '\n[synthesis.constraints]\nGAMMA_MIN = {min = 38.0}\n'
                    '"R3/R2" = {max = 4.0}\n')
    out = tmp_path / "r.csv"
    p = run("synth", str(spec), "-o", str(out))
    assert p.returncode == 0, p.stderr
    assert "meeting the 2 constraints" in p.stderr
    rows = list(csv.DictReader(out.open()))
    assert {"TIME_RATIO[-]", "K[-]", "SIDE", "FEASIBLE", "VIOLATES"} <= set(rows[0])
    ratios = {1.15, 1.25}
    seen = set()
    for row in rows:
        q, k, side = float(row["TIME_RATIO[-]"]), float(row["K[-]"]), row["SIDE"]
        assert q in ratios
        seen.add(q)
        # the row's linkage is the family member its k and side name
        m = synthesis.crank_rocker(45.0, q, rocker=10.0, th2d=10.0).member(k, side).mechanism
        for n in ("R1", "R2", "R3", "R4"):
            assert float(row[f"{n}[in]"]) == pytest.approx(float(getattr(m, n)), rel=1e-12)
        ok = (float(row["GAMMA_MIN[deg]"]) >= 38.0
              and float(row["R3[in]"]) / float(row["R2[in]"]) <= 4.0)
        assert row["FEASIBLE"] == str(int(ok))
        assert (row["VIOLATES"] == "") == ok
        if row["PARETO"] == "1":
            assert ok
    assert seen == ratios
    feasible = [r["FEASIBLE"] for r in rows]
    assert feasible == sorted(feasible, reverse=True) and "0" in feasible and "1" in feasible


@pytest.mark.parametrize("extra, text", [
    ('[synthesis.constraints]\nTORQUE = {max = 1.0}\n', "constraints TORQUE: constraint on"),
    ('[synthesis.constraints]\nLONGEST = 30.0\n', "an inline table {min = x, max = y}"),
    ('[synthesis.constraints]\nLONGEST = {most = 30.0}\n', "an inline table"),
    ('[synthesis.constraints]\nLONGEST = {min = 3.0, max = 1.0}\n', "min 3 is above max 1"),
    ('[synthesis.constraints]\nLONGEST = {max = "x"}\n', "max = 'x': a finite number"),
])
def test_bad_spec_constraints_are_one_line(tmp_path, extra, text):
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC + "\n" + extra)
    p = run("synth", str(spec), "-o", str(tmp_path / "r.csv"))
    assert p.returncode != 0 and text in p.stderr, p.stderr
    assert len(p.stderr.strip().splitlines()) == 1 and "Traceback" not in p.stderr
    assert not (tmp_path / "r.csv").exists()


def test_bad_tie_refused(tmp_path, family):
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC.replace("best = 3", "best = 3\ntie = 0.5"))
    p = run("synth", str(spec))
    assert p.returncode != 0 and "tie = " in p.stderr
    with pytest.raises(ValueError, match="tie"):
        synthesis.rank(family[:2], tie=-1.0)

