"""design.tolerance: zero deviations give the nominal exactly; for small deviations the
sampled spread agrees with the first-order sensitivities; seeded runs are reproducible
in process, on dask threads and on a LocalCluster; the sensitivities agree with a
difference taken here through analyze."""

from __future__ import annotations

import math

import numpy as np
import pytest

import sielaff
from sielaff import Scene, design
from sielaff.mechanism import EXAMPLE

DEV = {"R1": 0.01, "R2": 0.01, "R3": 0.01, "R4": 0.01, "ADEL3": 0.5, "W3": 0.1,
       "RG4": 0.02, "ZI4": 0.01}


def test_zero_deviations_give_the_nominal_exactly():
    t = design.tolerance(EXAMPLE, {k: 0.0 for k in DEV}, n=300, seed=3, size_of_block=128)
    for f in t.nominal:
        assert t.mean[f] == t.nominal[f] == t.p5[f] == t.p95[f], f
        assert t.std[f] == 0.0 and t.predicted_std[f] == 0.0
    # and the nominal is what design.figures gives for the design alone
    fig = design.figures.figures(EXAMPLE)
    for f in t.nominal:
        assert t.nominal[f] == float(fig[f][0])


# The bound: for n samples of a normal figure the sample std's relative standard error
# is 1/sqrt(2 (n - 1)); we allow 4 of those (a 1-in-15,000 chance per figure of a false
# failure) plus 2% for the second-order terms the linear prediction leaves out (the
# deviations are ~0.1% of the lengths, so those terms are far smaller).
def bound(n: int) -> float:
    return 4.0 / math.sqrt(2.0 * (n - 1)) + 0.02


@pytest.mark.parametrize("distribution", ["normal", "uniform"])
def test_sampled_spread_matches_first_order(distribution):
    n = 2000
    t = design.tolerance(EXAMPLE, DEV, n=n, seed=11, distribution=distribution,
                         scene=Scene(tex=-200.0))
    checked = 0
    for f in t.nominal:
        assert t.valid[f] == n
        pred = t.predicted_std[f]
        assert pred > 0.0
        assert abs(t.std[f] / pred - 1.0) <= bound(n), (f, t.std[f], pred)
        # the percentiles straddle the mean, about 1.645 sigma out (normal) or less
        assert t.p5[f] < t.mean[f] < t.p95[f]
        checked += 1
    assert checked == 11  # every figure of design.figures.FIGURES but KIND


def test_sensitivity_against_analyze():
    """d TORQ_PEAK / d R4 and d GAMMA_MIN / d R1 by a difference taken here, through
    analyze on a finer step, agree with tolerance's."""
    t = design.tolerance(EXAMPLE, {"R4": 0.01, "R1": 0.01}, n=2, seed=0)
    th = np.arange(360) * 1.0

    def peak(m):
        return np.max(np.abs(sielaff.analyze(m, th, ["TORQ"])["TORQ"]))

    def gmin(m):
        g = sielaff.analyze(m, th, ["GAMMA"])["GAMMA"]
        return np.min(np.minimum(g, 180.0 - g))

    h = 1e-4
    d1 = (peak(EXAMPLE.replace(R4=12.0 + h)) - peak(EXAMPLE.replace(R4=12.0 - h))) / (2 * h)
    d2 = (gmin(EXAMPLE.replace(R1=12.0 + h)) - gmin(EXAMPLE.replace(R1=12.0 - h))) / (2 * h)
    assert t.sensitivity["TORQ_PEAK"]["R4"] == pytest.approx(d1, rel=1e-4)
    assert t.sensitivity["GAMMA_MIN"]["R1"] == pytest.approx(d2, rel=1e-4)


def test_seed_reproducible_and_seed_matters():
    a = design.tolerance(EXAMPLE, DEV, n=50, seed=5, size_of_block=16, keep_samples=True)
    b = design.tolerance(EXAMPLE, DEV, n=50, seed=5, size_of_block=16, keep_samples=True)
    c = design.tolerance(EXAMPLE, DEV, n=50, seed=6, size_of_block=16, keep_samples=True)
    np.testing.assert_array_equal(a.samples, b.samples)
    assert not np.array_equal(a.samples, c.samples)


def test_dask_threads_reproducible():
    pytest.importorskip("dask")
    a = design.tolerance(EXAMPLE, DEV, n=60, seed=5, size_of_block=16, keep_samples=True)
    b = design.tolerance(EXAMPLE, DEV, n=60, seed=5, size_of_block=16, keep_samples=True,
                         backend="dask", workers=2)
    np.testing.assert_array_equal(a.samples, b.samples)
    assert a.mean == b.mean and a.p95 == b.p95


@pytest.mark.slow  # a cluster trial (threads stay in the default tier)
def test_local_cluster_reproducible():
    pytest.importorskip("distributed")
    from distributed import Client, LocalCluster

    a = design.tolerance(EXAMPLE, DEV, n=40, seed=9, size_of_block=16, keep_samples=True)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        b = design.tolerance(EXAMPLE, DEV, n=40, seed=9, size_of_block=16,
                             keep_samples=True, backend="dask", client=client)
    np.testing.assert_array_equal(a.samples, b.samples)


def test_invalid_and_not_turning_counted():
    """Deviations large enough to break the linkage are counted, not hidden."""
    t = design.tolerance(EXAMPLE, {"R2": 3.0}, n=200, seed=1)
    assert t.invalid > 0 and t.not_turning > 0
    assert t.valid["TORQ_PEAK"] == 200 - t.invalid - t.not_turning


@pytest.mark.parametrize("kwargs, text", [
    ({"deviations": {}}, "at least one"), ({"deviations": {"R9": 1.0}}, "R9"),
    ({"deviations": {"R1": -1.0}}, "deviation of R1"), ({"n": 0}, "n = 0"),
    ({"distribution": "cauchy"}, "distribution"), ({"seed": -1}, "seed"),
    ({"backend": "gpu"}, "backend")])
def test_refusals(kwargs, text):
    args = {"deviations": {"R1": 0.01}} | kwargs
    dev = args.pop("deviations")
    with pytest.raises(ValueError, match=text):
        design.tolerance(EXAMPLE, dev, **args)


def test_refuses_a_nominal_that_does_not_turn():
    with pytest.raises(ValueError, match="whole revolution"):
        design.tolerance(EXAMPLE.replace(R2=13.0), {"R1": 0.01}, n=5)


# -- sielaff tolerance (subprocesses) -------------------------------------------------


import procs  # noqa: E402
from conftest import ROOT  # noqa: E402


def run_tolerance(*args):
    return procs.run(["tolerance", *args], cwd=ROOT, text=True, timeout=600)


def small_spec(tmp_path, edit=None):
    text = (ROOT / "decks" / "tolerance.toml").read_text().replace("n = 2000", "n = 64")
    if edit:
        text = text.replace(*edit)
    spec = tmp_path / "t.toml"
    spec.write_text(text)
    return spec


def test_tolerance_command_prints_the_table_with_units(tmp_path):
    spec = small_spec(tmp_path)
    r = run_tolerance(str(spec))
    assert r.returncode == 0 and r.stderr == "", r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith(f"sielaff tolerance: {spec} (units in-lb-sec), 64 samples")
    row = next(x for x in lines if x.split()[:2] == ["TORQ_PEAK", "in-lb"])
    assert next(x for x in lines if x.split()[:2] == ["GAMMA_MIN", "deg"])
    # the numbers are the API's, for the same spec
    from sielaff.tools.common import read_spec_deck

    text = spec.read_text()
    mech_only = tmp_path / "m.toml"
    mech_only.write_text(text[:text.index("[tolerance]")])
    deck, scene = read_spec_deck(str(mech_only))
    t = design.tolerance(deck.mechanism, {"R1": 0.005, "R2": 0.005, "R3": 0.005, "R4": 0.005,
                                          "ADEL3": 0.5, "RG3": 0.05, "W3": 0.1}, n=64, seed=1,
                         scene=scene)
    assert float(row.split()[2]) == pytest.approx(t.nominal["TORQ_PEAK"], rel=1e-4)
    assert float(row.split()[4]) == pytest.approx(t.std["TORQ_PEAK"], rel=1e-4)
    # --workers 2 (dask threads when installed) prints the same table; -o writes it
    out = tmp_path / "o" / "t.txt"
    r2 = run_tolerance(str(spec), "--workers", "2", "-o", str(out))
    assert r2.returncode == 0 and out.read_text() == r.stdout


@pytest.mark.parametrize("edit, message", [
    (("distribution = \"normal\"", "distribution = \"cauchy\""), "distribution = 'cauchy'"),
    (("R1 = 0.005", "R9 = 0.005"), "'R9' is not a field"),
    (("R1 = 0.005", "R1 = -0.005"), "deviations R1"),
    (("n = 64", "n = 0"), "[tolerance] n = 0"),
    (("seed = 1", "seed = 1\ncolour = 2"), "unknown key 'colour'"),
    (("crank = 4.0", "crank = 13.0"), "NOT A CRANK ROCKER"),
])
def test_tolerance_errors_are_one_line(tmp_path, edit, message):
    spec = small_spec(tmp_path, edit)
    out = tmp_path / "t.txt"
    out.write_text("old\n")
    r = run_tolerance(str(spec), "-o", str(out))
    assert r.returncode in (2, 3), r.stderr
    assert len(r.stderr.splitlines()) == 1 and message in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and out.read_text() == "old\n"
