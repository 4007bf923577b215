"""synthesis.rank: the order checked against figures computed here, per candidate, straight
from ``analyze`` (not through design.figures, rank's path), and the Pareto front by brute
force."""

from __future__ import annotations

import numpy as np
import pytest

import sielaff
from sielaff import Scene, synthesis
from sielaff.mechanism import EXAMPLE

N = 360


@pytest.fixture(scope="module")
def family():
    fam = synthesis.crank_rocker(45.0, 1.25, rocker=10.0, th2d=10.0)
    return fam.members(4)


def direct(m, branch, scene):
    """The figures of one candidate from analyze, one design at a time."""
    th = np.arange(N) * (360.0 / N)
    r = sielaff.analyze(m, th, ["TORQ", "SHAK", "SHAKM", "FOA", "FA32", "FB34", "FOB",
                                "GAMMA"], scene=scene.replace(branch=branch))
    g = r["GAMMA"]
    return {"TORQ_PEAK": np.max(np.abs(r["TORQ"])),
            "TORQ_RMS": np.sqrt(np.mean(r["TORQ"] ** 2)),
            "SHAK_PEAK": np.max(r["SHAK"]), "SHAKM_PEAK": np.max(np.abs(r["SHAKM"])),
            "FOA_PEAK": np.max(r["FOA"]), "FA32_PEAK": np.max(r["FA32"]),
            "FB34_PEAK": np.max(r["FB34"]), "FOB_PEAK": np.max(r["FOB"]),
            "GAMMA_MIN": np.min(np.minimum(g, 180.0 - g))}


SCENE = Scene(tex=-20.0, gravity="down")


@pytest.mark.parametrize("by", [["TORQ_PEAK"], ["TORQ_RMS"], ["SHAK_PEAK"], ["SHAKM_PEAK"],
                                ["FOA_PEAK"], ["FB34_PEAK"], ["GAMMA_MIN"],
                                ["FLYWHEEL_I"]])
def test_order_matches_direct_figures(family, by):
    r = synthesis.rank(family, scene=SCENE, by=by, n=N)
    name = by[0]
    if name == "FLYWHEEL_I":
        want = np.array([float(sielaff.design.flywheel(c.mechanism, 0.05, N,
                                                       scene=SCENE.replace(branch=c.branch))
                               .inertia) for c in family])
    else:
        want = np.array([direct(c.mechanism, c.branch, SCENE)[name] for c in family])
    np.testing.assert_allclose(r.figures[name], want, rtol=1e-12, atol=1e-12)
    key = -want if name == "GAMMA_MIN" else want
    assert list(r.order) == list(np.argsort(key, kind="stable"))
    # the spread is real: the order is not the given one by accident
    assert np.ptp(want) > 1e-3 * np.max(np.abs(want))


def test_lexicographic_ties(family):
    """Candidates tied on by[0] (the same linkage twice, with different coupler masses)
    are ordered by by[1]."""
    m = family[0].mechanism
    heavy = m.replace(W3=3 * m.W3, ZI3=3 * m.ZI3)
    # GAMMA_MIN is kinematic: identical for both; SHAK_PEAK differs
    r = synthesis.rank([heavy, m], by=["GAMMA_MIN", "SHAK_PEAK"])
    assert r.figures["GAMMA_MIN"][0] == r.figures["GAMMA_MIN"][1]
    assert list(r.order) == [1, 0]


def brute_pareto(x, y):
    out = []
    for i in range(len(x)):
        if not (np.isfinite(x[i]) and np.isfinite(y[i])):
            continue
        dominated = any(x[j] <= x[i] and y[j] <= y[i] and (x[j] < x[i] or y[j] < y[i])
                        for j in range(len(x)) if j != i)
        if not dominated:
            out.append(i)
    return sorted(out)


def test_pareto_brute_force(family):
    r = synthesis.rank(family, scene=SCENE, by=["TORQ_RMS", "GAMMA_MIN"])
    x, y = r.figures["TORQ_RMS"], -r.figures["GAMMA_MIN"]
    want = brute_pareto(x, y)
    assert sorted(r.pareto) == want
    assert 1 <= len(want) < len(family)


@pytest.mark.parametrize("seed", range(20))
def test_pareto_front_random(seed):
    rng = np.random.default_rng(seed)
    x = rng.integers(0, 8, 40).astype(float)  # ties drawn on purpose
    y = rng.integers(0, 8, 40).astype(float)
    x[rng.integers(0, 40, 3)] = np.nan
    assert sorted(synthesis.pareto_front(x, y)) == brute_pareto(x, y)


def test_not_turning_fully_comes_last(family):
    """A double-rocker (EXAMPLE with a long crank) has NaN figures and ranks last."""
    bad = EXAMPLE.replace(R2=13.0)
    cands = [bad] + [c.mechanism for c in family[:3]]
    r = synthesis.rank(cands, by=["TORQ_PEAK"])
    assert r.order[-1] == 0 and np.isnan(r.figures["TORQ_PEAK"][0])
    assert r.figures["KIND"][0] != r.figures["KIND"][1]


def test_mass_model(family):
    """A denser material scales every force and torque (no TEX, no gravity) by its ratio."""
    a = synthesis.rank(family[:3], by=["TORQ_PEAK"], mass_model={"density": 0.1})
    b = synthesis.rank(family[:3], by=["TORQ_PEAK"], mass_model={"density": 0.3})
    np.testing.assert_allclose(b.figures["TORQ_PEAK"], 3 * a.figures["TORQ_PEAK"], rtol=1e-12)
    np.testing.assert_allclose(b.figures["GAMMA_MIN"], a.figures["GAMMA_MIN"], rtol=0)
    c = synthesis.rank(family[:3], by=["TORQ_PEAK"],
                       mass_model=lambda m: synthesis.masses(m, density=0.3))
    np.testing.assert_array_equal(c.figures["TORQ_PEAK"], b.figures["TORQ_PEAK"])


def test_branch_of_each_candidate_used(family):
    """A bare Mechanism takes the scene's branch; a result its own."""
    c = family[0]
    assert c.branch == "crossed"
    r = synthesis.rank([c, c.mechanism], scene=Scene(branch="open"), by=["TORQ_PEAK"])
    assert r.branches == ("crossed", "open")


def test_dask_threads_identical(family):
    pytest.importorskip("dask")
    a = synthesis.rank(family, scene=SCENE, by=["TORQ_PEAK"], backend="process",
                       size_of_block=3)
    b = synthesis.rank(family, scene=SCENE, by=["TORQ_PEAK"], backend="dask", workers=2,
                       size_of_block=3)
    for f in a.figures:
        np.testing.assert_array_equal(a.figures[f], b.figures[f])
    assert list(a.order) == list(b.order)


@pytest.mark.parametrize("kwargs, text", [
    ({"by": ["KIND"]}, "by 'KIND'"), ({"by": []}, "at least one"),
    ({"pareto": ["TORQ_PEAK"]}, "pareto"), ({"n": 7}, "n = 7"),
    ({"mass_model": 3}, "mass_model"), ({"backend": "gpu"}, "backend")])
def test_refusals(family, kwargs, text):
    with pytest.raises(ValueError, match=text):
        synthesis.rank(family[:2], **kwargs)


def test_refuses_non_candidates():
    with pytest.raises(ValueError, match="neither a Mechanism"):
        synthesis.rank([1.0])
    with pytest.raises(ValueError, match="no candidates"):
        synthesis.rank([])


# -- sielaff synth (subprocesses) ----------------------------------------------------

import csv as _csv  # noqa: E402

import procs  # noqa: E402
from conftest import ROOT  # noqa: E402


def synth(*args):
    return procs.run(["synth", *args], cwd=ROOT, text=True, timeout=600)


def test_synth_command_csv_and_best_specs(tmp_path):
    out, best = tmp_path / "o" / "ranked.csv", tmp_path / "best"
    r = synth("decks/synth.toml", "-o", str(out), "--write-best", str(best))
    assert r.returncode == 0, r.stderr
    assert r.stderr.startswith("sielaff synth: 32 candidates from 2 crank_rocker problem(s)")
    rows = list(_csv.DictReader(out.read_text().splitlines()))
    assert len(rows) == 32 and [int(x["RANK"]) for x in rows] == list(range(1, 33))
    assert "TORQ_PEAK[in-lb]" in rows[0] and "GAMMA_MIN[deg]" in rows[0] and "R1[in]" in rows[0]
    peaks = [float(x["TORQ_PEAK[in-lb]"]) for x in rows]
    assert peaks == sorted(peaks)
    # the written best spec, read back as any spec is, has the CSV's figures
    from sielaff.design.figures import figures
    from sielaff.tools.common import read_spec_deck

    for k in (1, 2, 3):
        deck, scene = read_spec_deck(str(best / f"best-{k}.toml"))
        assert scene.branch == rows[k - 1]["BRANCH"] and scene.tex == -50.0
        f = figures(deck.mechanism, scene=scene)
        # each field rounded to what an 8-column field holds (5+ significant digits)
        assert float(f["TORQ_PEAK"][0]) == pytest.approx(peaks[k - 1], rel=1e-4)
        assert deck.mechanism.R1 == pytest.approx(float(rows[k - 1]["R1[in]"]), abs=5e-6)
    assert not (best / "best-4.toml").exists()
    # the crank-rockers here all run on the crossed branch: no deck, and it says why
    assert "no deck for best-1: it runs on the crossed branch" in r.stderr


@pytest.mark.slow
def test_synth_writes_decks_where_they_can_hold_it(tmp_path):
    pytest.importorskip("scipy")
    spec = tmp_path / "p.toml"
    spec.write_text(
        '[synthesis]\nproblem = "path"\nby = ["SHAK_PEAK"]\nspeed = 20.0\nbest = 2\n'
        '[synthesis.path]\npoints = [[1.1981, 1.9902], [1.416, 2.5342], [0.9572, 2.7561], '
        '[0.0853, 2.2593], [-0.2794, 1.5458]]\nstarts = 10\n'
        '[synthesis.vary]\nseed = [1, 2]\n')
    r = synth(str(spec), "-o", str(tmp_path / "r.csv"), "--write-best", str(tmp_path / "b"))
    assert r.returncode == 0, r.stderr
    rows = list(_csv.DictReader((tmp_path / "r.csv").read_text().splitlines()))
    assert len(rows) == 2
    for k in (1, 2):
        deck = sielaff.read_deck(str(tmp_path / "b" / f"best-{k}.dat"))
        # rounded to what an 8-column field holds: lengths within 5E-6 in
        assert deck.mechanism.R1 == pytest.approx(float(rows[k - 1]["R1[in]"]), abs=5e-6)
    run = procs.run(["run", tmp_path / "b" / "best-1.dat"], cwd=ROOT, text=True,
                    timeout=300)
    assert run.returncode == 0, run.stderr
    assert "THIS IS NOT A CRANK ROCKER" not in run.stdout and len(run.stdout) > 1000


@pytest.mark.parametrize("edit, message, status", [
    (("problem = \"crank_rocker\"", "problem = \"cam\""), "problem = 'cam'", 2),
    (("by = [\"TORQ_PEAK\", \"SHAK_PEAK\"]", "by = [\"KIND\"]"), "by = ['KIND']", 2),
    (("swing = 45.0", "swing = 180.0"), "swing = 180 deg", 2),
    (("time_ratio = [1.15, 1.25]", "colour = [1]"), "'colour'", 2),
    (("members = 8", "members = 8\nwobble = 1"), "unknown key 'wobble'", 2),
])
def test_synth_errors_are_one_line(tmp_path, edit, message, status):
    spec = tmp_path / "s.toml"
    spec.write_text((ROOT / "decks" / "synth.toml").read_text().replace(*edit))
    out = tmp_path / "r.csv"
    out.write_text("old\n")
    r = synth(str(spec), "-o", str(out))
    assert r.returncode == status, r.stderr
    assert len(r.stderr.splitlines()) == 1 and message in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and out.read_text() == "old\n"


# -- docs/synthesis.md's ranking and tolerance examples are current --------------------

def test_the_ranking_doc_is_current():
    import importlib.util
    import re

    spec = importlib.util.spec_from_file_location("make_ranking",
                                                  ROOT / "docs" / "make_ranking.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    doc = (ROOT / "docs" / "synthesis.md").read_text()
    number = re.compile(r"[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")

    def close(a: str, b: str) -> bool:  # within the last printed digit
        x, y = float(a), float(b)
        digits = len(re.sub(r"[^0-9]", "", a.split("e")[0].split("E")[0]).lstrip("0")) or 1
        exp = int(f"{abs(x):e}".split("e")[1]) if x else 0
        return abs(x - y) <= 10.0 ** (exp - digits + 1) * 1.0001

    assert close("1.2345", "1.2346") and not close("1.2345", "1.2347")
    for name, (begin, end) in mod.MARKERS.items():
        old = doc.split(begin, 1)[1].split(end, 1)[0].lstrip("\n")
        new = mod.block(name)
        assert number.sub("#", old) == number.sub("#", new), f"{name}: the words differ"
        a, b = number.findall(old), number.findall(new)
        assert len(a) == len(b) > 50
        bad = [(x, y) for x, y in zip(a, b) if not close(x, y)]
        assert not bad, bad[:5]
