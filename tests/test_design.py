"""Design answers, each checked by a route that trusts nothing of the code under test:
closed forms on synthetic torques, the engine re-run on the balanced linkage, brute-force
rasters of bearing directions, and the in-process sweep against dask (threads and a
LocalCluster)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import procs
import sielaff
from sielaff.design import balance, bearings, counterweights, flywheel, flywheel_from_torque
from sielaff.design.bearings import unloaded_arcs
from sielaff.design.figures import figures
from sielaff.design.sweep import Grid, iter_blocks
from sielaff.engine import analyze
from sielaff.engine.loads import Load
from sielaff.engine.scene import Scene
from sielaff.mechanism import EXAMPLE, crank_rocker_failure

ROOT = __import__("pathlib").Path(__file__).resolve().parent.parent


# -- flywheel --------------------------------------------------------------------------

@pytest.mark.parametrize("k", [1, 2, 5])
def test_flywheel_closed_form(k):
    """T = T0 + A sin(k th) + B: E(th) = (A/k)(1 - cos k th), so the fluctuation is 2A/k,
    the inertia 2A/(k cf w^2), the mean torque T0."""
    n, a, t0, w, cf = 720, 300.0, 25.0, 40.0, 0.04
    th = 2 * np.pi * np.arange(n) / n
    fw = flywheel_from_torque(t0 + a * np.sin(k * th), w, cf)
    assert fw.energy == pytest.approx(2 * a / k, rel=1e-12)
    assert fw.inertia == pytest.approx(2 * a / (k * cf * w * w), rel=1e-12)
    assert fw.mean_torque == pytest.approx(t0, rel=1e-12)
    np.testing.assert_allclose(fw.energy_curve, (a / k) * (1 - np.cos(k * th)), atol=1e-9)


def test_flywheel_extremes_between_samples():
    """The extremes of E are found between the samples: a phase that puts them off the
    grid changes nothing (a grid maximum would be low by about A h^2 / 8)."""
    n, a = 64, 100.0
    th = 2 * np.pi * np.arange(n) / n
    fw = flywheel_from_torque(a * np.sin(th + 0.5 * 2 * np.pi / n), 10.0)
    assert fw.energy == pytest.approx(2 * a, rel=1e-12)


def test_flywheel_speed_meets_cf():
    """With the flywheel on, the speed swings by exactly cf about TH2D: (wmax - wmin) /
    ((wmax + wmin) / 2) = cf, from the energy curve (an independent use of the answer)."""
    fw = flywheel(EXAMPLE, cf=0.05)
    # the speed on the grid misses the extremes by O(h^2): use the refined energy
    w_avg, inertia = 50.0, float(fw.inertia)
    w_max = w_avg * (1 + 0.025)
    w_min = math.sqrt(w_max**2 - 2 * float(fw.energy) / inertia)
    assert (w_max - w_min) / ((w_max + w_min) / 2) == pytest.approx(0.05, rel=1e-12)
    assert np.nanmax(fw.speed) == pytest.approx(w_max, rel=1e-6)
    assert np.nanmin(fw.speed) == pytest.approx(w_min, rel=1e-6)


def test_flywheel_of_the_example_against_a_dense_trapezoid():
    """The example's fluctuation against a cumulative trapezoid of the engine's TORQ on a
    0.01 deg grid (a different integration, error O(h^2) ~ 1E-7 relative)."""
    th = np.linspace(0.0, 360.0, 36001)
    torq = analyze(EXAMPLE, th, ["TORQ"])["TORQ"]
    h = np.radians(0.01)
    e = np.concatenate([[0.0], np.cumsum((torq[1:] + torq[:-1]) * h / 2)])
    fw = flywheel(EXAMPLE, cf=0.05)
    assert float(fw.energy) == pytest.approx(e.max() - e.min(), rel=1e-6)
    assert float(fw.inertia) == pytest.approx((e.max() - e.min()) / (0.05 * 2500.0), rel=1e-6)
    assert abs(float(fw.mean_torque)) < 1e-9 * float(fw.peak_torque)  # TEX = 0: no net work


def test_flywheel_with_a_load_and_arrays():
    """A constant torque on the rocker: the mean drive torque is what the load takes per
    radian of crank; designs as arrays give the same answers one by one."""
    m = EXAMPLE.replace(R4=np.array([11.0, 12.0, 13.0]))
    both = flywheel(m, cf=0.02)
    for i, r4 in enumerate((11.0, 12.0, 13.0)):
        one = flywheel(EXAMPLE.replace(R4=r4), cf=0.02)
        assert both.energy[i] == pytest.approx(float(one.energy), rel=1e-12)
    fw = flywheel(EXAMPLE, loads=[Load(3, 8.0, 0.0, 0.0, -50.0)])
    work = np.mean(analyze(EXAMPLE, np.arange(3600) * 0.1, ["TORQ"],
                           loads=[Load(3, 8.0, 0.0, 0.0, -50.0)])["TORQ"])
    assert float(fw.mean_torque) == pytest.approx(work, rel=1e-12, abs=1e-9)


def test_flywheel_refusals():
    with pytest.raises(ValueError, match="th2dd"):
        flywheel(EXAMPLE, th2dd=-40.0)
    with pytest.raises(ValueError, match="whole revolution"):
        flywheel(EXAMPLE.replace(R1=10.0, R2=4.0, R3=5.0, R4=4.0))
    with pytest.raises(ValueError, match="cf"):
        flywheel(EXAMPLE, cf=0.0)


# -- balancing -------------------------------------------------------------------------

MECHS = st.builds(
    lambda r1, r3, r4, w, zi, adel, rg: EXAMPLE.replace(
        R1=r1, R2=1.0, R3=r3, R4=r4, W2=w[0], W3=w[1], W4=w[2], ZI2=zi[0], ZI3=zi[1],
        ZI4=zi[2], ADEL2=adel[0], ADEL3=adel[1], ADEL4=adel[2], RG2=rg[0], RG3=rg[1] * r3,
        RG4=rg[2] * r4),
    st.floats(2.5, 6.0), st.floats(2.5, 6.0), st.floats(2.5, 6.0),
    st.tuples(*[st.floats(0.0, 10.0)] * 3), st.tuples(*[st.floats(0.0, 2.0)] * 3),
    st.tuples(*[st.floats(-180.0, 180.0)] * 3), st.tuples(*[st.floats(0.0, 1.0)] * 3))


@settings(max_examples=60, derandomize=True, deadline=None)
@given(MECHS, st.floats(-60.0, 60.0))
def test_balanced_shaking_force_vanishes(m, th2dd):
    """The engine re-run on the balanced linkage: shaking force zero to 1E-9 of the
    unbalanced peak at every position, with or without crank acceleration."""
    if crank_rocker_failure(m) is not None:
        return
    th = np.arange(0.0, 360.0, 1.0)
    before = analyze(m, th, ["SHAK"], th2dd=th2dd)["SHAK"]
    after = analyze(balance(m), th, ["SHAK"], th2dd=th2dd)["SHAK"]
    scale = max(float(before.max()), 1e-300)
    assert float(after.max()) <= 1e-9 * scale + 1e-12


def test_balance_of_a_subnormal_weight_stays_finite():
    """Hypothesis found it: a rocker weighing 2.2E-313 lb made the merged rocker's RG4 and
    ZI4 NaN (a complex division by a subnormal number scales by its reciprocal, inf)."""
    m = EXAMPLE.replace(R1=3.0, R2=1.0, R3=3.0, R4=3.0, W2=0.0, W3=0.0, W4=2.2250738585e-313,
                        ZI2=0.0, ZI3=0.0, ZI4=0.0, RG2=0.0, RG3=0.0, RG4=0.0, ADEL3=0.0)
    b = balance(m)
    assert all(np.isfinite(v) for v in b.as_tuple()[:-1])
    assert b.RG4 == 0.0 and b.ZI4 == 0.0


def test_balance_merges_point_masses_exactly():
    """The merged link: total weight, first moment and inertia about O2 / O4 are the sums
    of the link's and the counterweight's (computed here from the counterweight alone)."""
    m = EXAMPLE
    b = balance(m, radius2=3.0)
    cw2, cw4 = counterweights(m, radius2=3.0)
    g = 386.088
    for k, cw in ((2, cw2), (4, cw4)):
        w, rg, adel, zi = (getattr(m, f"{n}{k}") for n in ("W", "RG", "ADEL", "ZI"))
        w2, rg2, adel2, zi2 = (getattr(b, f"{n}{k}") for n in ("W", "RG", "ADEL", "ZI"))
        assert w2 == pytest.approx(w + cw.weight, rel=1e-14)
        first = w * rg * np.exp(1j * np.radians(adel)) + cw.weight * cw.radius * np.exp(
            1j * np.radians(cw.angle))
        assert w2 * rg2 * np.exp(1j * np.radians(adel2)) == pytest.approx(first, rel=1e-12)
        # inertia about the pivot is additive: ZI + m rg^2
        assert zi2 + w2 / g * rg2**2 == pytest.approx(
            zi + w / g * rg**2 + cw.weight / g * cw.radius**2, rel=1e-12)
    assert cw2.radius == 3.0 and cw4.radius == m.R4


@pytest.mark.pinned
def test_balance_command_prints_the_price_and_writes_a_deck(tmp_path):
    out = tmp_path / "balanced.dat"
    r = procs.run(["balance", "decks/example.dat", "-o", out], cwd=ROOT, text=True)
    assert r.returncode == 0 and r.stderr == ""
    text = r.stdout
    row = next(line for line in text.splitlines() if "peak shaking force" in line)
    assert row.split()[-2:] == ["0", "lb"]  # roundoff printed as 0, never its last bits
    deck = sielaff.read_deck(str(out))
    th = np.arange(0.0, 360.0, 0.5)
    # F8.4 rounding leaves a residual far below the unbalanced peak (604.5 lb)
    assert analyze(deck.mechanism, th, ["SHAK"])["SHAK"].max() < 0.05
    assert "rounding to F8.4 accounts for" in text


# -- bearings --------------------------------------------------------------------------

def test_unloaded_arcs_synthetic():
    assert unloaded_arcs(np.array([10.0, 20.0, 30.0, 40.0, 30.0, 20.0])) == [(40.0, 10.0)]
    assert unloaded_arcs(np.array([350.0, 10.0, 30.0, 10.0])) == [(30.0, 350.0)]
    assert unloaded_arcs(np.linspace(0.0, 357.0, 120)) == []
    # 0 -> 180 in one step: through zero load, sweeping nothing between
    assert unloaded_arcs(np.array([0.0, 1.0, 180.0, 181.0])) == [(1.0, 180.0), (181.0, 0.0)]
    assert unloaded_arcs(np.array([np.nan, np.nan])) == [(0.0, 360.0)]


def _raster(direction, bins=3600):
    """Which 0.1-degree bins a sampled direction sweeps (the shorter way)."""
    hit = np.zeros(bins, dtype=bool)
    d = np.asarray(direction)
    for a, b in zip(d, np.roll(d, -1)):
        if not (np.isfinite(a) and np.isfinite(b)):
            continue
        step = (b - a + 180.0) % 360.0 - 180.0
        if abs(step) > 30.0:  # through zero load: bearings.JUMP, the definition
            hit[int(a % 360.0 * bins / 360.0) % bins] = True
            continue
        for x in np.linspace(a, a + step, max(2, int(abs(step) * 20) + 2)):
            hit[int(x % 360.0 * bins / 360.0) % bins] = True
    return hit


def test_bearings_of_the_example_against_a_raster():
    """Each member's arcs never loaded against a brute-force raster of the same cycle, and
    the peaks against the engine's loads on a 4x finer grid."""
    pins = bearings(EXAMPLE, n=720)
    fine = analyze(EXAMPLE, np.arange(2880) * 0.125, ["FOA", "FA32", "FB34", "FOB"])
    for pin in pins.values():
        assert pin.peak == pytest.approx(float(fine[pin.force].max()), rel=2e-4)
        for m in pin.members:
            hit = _raster(m.direction)
            centres = (np.arange(3600) + 0.5) / 10.0
            inside = np.zeros(3600, dtype=bool)
            for a, b in m.unloaded:
                inside |= ((centres - a) % 360.0) < ((b - a) % 360.0)
            # away from the arcs' ends (one bin), unloaded exactly where the raster is empty
            edge = np.zeros(3600, dtype=bool)
            for a, b in m.unloaded:
                for e in (a, b):
                    edge[[int(e * 10) % 3600, (int(e * 10) - 1) % 3600,
                          (int(e * 10) + 1) % 3600]] = True
            assert np.array_equal(inside[~edge], ~hit[~edge]), (pin.name, m.name)


def test_bearing_reversals_count_sign_changes():
    """The crank pin A on the crank: the report's linkage pulls the crank outward all
    cycle (0 reversals); a two-force coupler alone (only link 4 has mass) reverses twice,
    and the counts are those of the engine's components counted here."""
    pins = bearings(EXAMPLE, n=720)
    th = np.arange(720) * 0.5
    r = analyze(EXAMPLE, th, ["FA32X", "FA32Y", "ATH2"])
    along = r["FA32X"] * np.cos(np.radians(r["ATH2"])) + r["FA32Y"] * np.sin(
        np.radians(r["ATH2"]))
    s = np.sign(along)
    assert pins["A"].members[0].reversals == int(np.count_nonzero(s != np.roll(s, -1)))


# -- figures and sweeps ----------------------------------------------------------------

def test_figures_against_the_engine_one_design_at_a_time():
    m = EXAMPLE.replace(R4=np.array([10.0, 12.0, 14.0]), W3=np.array([4.0, 8.0, 12.0]))
    f = figures(m, n=360)
    th = np.arange(360.0)
    for i in range(3):
        one = EXAMPLE.replace(R4=float(m.R4[i]), W3=float(m.W3[i]))
        r = analyze(one, th, ["TORQ", "SHAK", "SHAKM", "GAMMA", "FOA"])
        assert f["TORQ_PEAK"][i] == pytest.approx(np.abs(r["TORQ"]).max(), rel=1e-12)
        assert f["TORQ_RMS"][i] == pytest.approx(np.sqrt(np.mean(r["TORQ"] ** 2)), rel=1e-12)
        assert f["SHAK_PEAK"][i] == pytest.approx(r["SHAK"].max(), rel=1e-12)
        assert f["FOA_PEAK"][i] == pytest.approx(r["FOA"].max(), rel=1e-12)
        g = r["GAMMA"]
        assert f["GAMMA_MIN"][i] == pytest.approx(np.minimum(g, 180 - g).min(), rel=1e-12)


def test_designs_that_cannot_turn_get_nan_and_their_kind():
    m = EXAMPLE.replace(R1=np.array([12.0, 10.0]), R2=4.0, R3=np.array([16.0, 5.0]),
                        R4=np.array([12.0, 4.0]))
    f = figures(m)
    assert np.isfinite(f["TORQ_PEAK"][0]) and np.isnan(f["TORQ_PEAK"][1])
    assert [int(k) for k in f["KIND"]] == [0, 4]  # crank-rocker, triple-rocker


GRID = {"R4": np.linspace(10.0, 14.0, 7), "W3": np.linspace(4.0, 12.0, 5), "BALANCE": [0, 1]}


def test_sweep_blocks_are_the_designs():
    """Every row is its design evaluated alone (a different grouping of the same work)."""
    grid = Grid(EXAMPLE, GRID)
    rows = np.concatenate(list(iter_blocks(grid, n=120, size_of_block=9)))
    assert rows.shape[0] == 70
    for i in (0, 13, 69):
        r4, w3, bal = grid.designs(i, i + 1).values()
        m = EXAMPLE.replace(R4=float(r4[0]), W3=float(w3[0]))
        if bal[0]:
            m = balance(m)
        f = figures(m, n=120)
        assert rows[i, 4] == pytest.approx(float(f["TORQ_PEAK"][0]), rel=1e-12)


def test_sweep_in_process_and_on_dask_threads_identical():
    pytest.importorskip("dask")
    grid = Grid(EXAMPLE, GRID)
    a = np.concatenate(list(iter_blocks(grid, n=120, size_of_block=16)))
    b = np.concatenate(list(iter_blocks(grid, n=120, backend="dask", size_of_block=16,
                                        batch=2)))
    assert np.array_equal(a, b, equal_nan=True)


@pytest.mark.slow
def test_sweep_on_a_local_cluster_identical():
    """The distributed path for real: a LocalCluster of two worker processes."""
    dask = pytest.importorskip("dask")
    pytest.importorskip("distributed")
    # workers with glibc's default malloc (docs/design.md: distributed's setting halves
    # the engine's speed); the results do not depend on it
    dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None})
    from distributed import Client, LocalCluster

    grid = Grid(EXAMPLE, GRID)
    a = np.concatenate(list(iter_blocks(grid, n=120, size_of_block=16)))
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        b = np.concatenate(list(iter_blocks(grid, n=120, backend="dask", client=client,
                                            size_of_block=16, batch=3)))
    assert np.array_equal(a, b, equal_nan=True)


def test_sweep_command_csv_and_plot(tmp_path):
    spec = tmp_path / "s.toml"
    text = (ROOT / "decks" / "sweep.toml").read_text()
    text = text.replace("n = 61", "n = 4").replace("n = 41", "n = 3")
    spec.write_text(text)
    csv, png = tmp_path / "o" / "s.csv", tmp_path / "o" / "p.png"
    for workers in ("1", "2"):
        r = procs.run(["sweep", spec, "-o", csv, "--plot", png, "--workers", workers],
                      cwd=ROOT, text=True)
        assert r.returncode == 0, r.stderr
        assert r.stderr.startswith("sielaff sweep: 24 designs (24 with a full cycle)")
        lines = csv.read_text().splitlines()
        if workers == "1":
            first = lines
        else:
            assert lines == first  # in process and through dask (when installed): identical
    assert lines[0].startswith("DESIGN,R4[in],W3[lb],BALANCE,TORQ_PEAK[in-lb]")
    assert len(lines) == 25 and lines[1].endswith(",crank-rocker")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_sweep_spec_errors_name_the_field(tmp_path):
    spec = tmp_path / "s.toml"
    base = (ROOT / "decks" / "sweep.toml").read_text()
    for bad, message in (("R4 = { from = 9.0, to = 15.0, n = 61 }", "[sweep.vary] R4"),
                         ("BALANCE = [0, 1]", "[sweep.vary] BALANCE")):
        spec.write_text(base.replace(bad, bad.replace("61", "0").replace("[0, 1]", "[2]")))
        r = procs.run(["sweep", spec], cwd=ROOT, text=True)
        assert r.returncode == 2 and message in r.stderr
        assert len(r.stderr.splitlines()) == 1 and "Traceback" not in r.stderr


def test_check_prints_the_flywheel_and_bearings():
    r = procs.run(["check", "decks/example.dat"], cwd=ROOT, text=True)
    fw = flywheel(EXAMPLE)
    energy = next(line for line in r.stdout.splitlines() if "energy fluctuation" in line)
    assert float(energy.split()[-2]) == pytest.approx(float(fw.energy), rel=1e-3)
    assert energy.split()[-1] == "in-lb"
    assert "motor's mean torque                 0 in-lb" in r.stdout
    assert "pin B  (FB34) peak" in r.stdout and "on the rocker" in r.stdout


def test_bearings_plot_draws_the_data_without_overlaps():
    pytest.importorskip("matplotlib")
    from sielaff.tools.plot.bearings import bearings_figure
    from sielaff.tools.plot.render import overlapping, text_boxes

    deck = sielaff.read_deck(str(ROOT / "decks" / "example.dat"))
    fig, pins = bearings_figure(deck, Scene())
    axes = fig.axes
    for col, pin in enumerate(pins.values()):
        for row, member in enumerate(pin.members):
            line = axes[row * 4 + col].lines[0]
            np.testing.assert_array_equal(line.get_ydata(), pin.load)
            np.testing.assert_array_equal(line.get_xdata(), np.radians(member.direction))
            # every ring value carries its unit, and reads the ring it labels
            ax = axes[row * 4 + col]
            rings = [t.get_text() for t in ax.get_yticklabels()]
            assert len(rings) == 2 and all(t.endswith(" lb") for t in rings), rings
            for t, v in zip(rings, ax.get_yticks()):
                assert float(t.split()[0]) == pytest.approx(v, rel=5e-3)
    assert overlapping(text_boxes(fig)) == []


def test_check_of_a_balanced_linkage_says_zero_without_an_angle():
    """The shaking force of an exactly balanced linkage is roundoff: check prints 0 and
    no angle (which would depend on the last bits); a deck rounded to F8.4 keeps a real
    residual, printed with its digits."""
    from sielaff.tools.check import CheckReport, _revolution_section

    rep = CheckReport()
    _revolution_section(balance(EXAMPLE), rep)
    line = next(x for x in rep.lines if "shaking force SHAKE" in x)
    assert "0 lb to roundoff" in line and "THETA 2" not in line


def test_sweep_varies_tex_and_the_counterweight_radius():
    """TEX (the scene's torque on the rocker) and CW_R4 (the rocker counterweight's radius)
    as sweep axes: each row is its design computed directly."""
    grid = Grid(EXAMPLE, {"TEX": [0.0, 500.0], "CW_R4": [6.0, 12.0], "BALANCE": [1]})
    rows = np.concatenate(list(iter_blocks(grid, n=120)))
    th = np.arange(120) * 3.0
    for i, (tex, r4) in enumerate([(0.0, 6.0), (0.0, 12.0), (500.0, 6.0), (500.0, 12.0)]):
        m = balance(EXAMPLE, radius4=r4)
        r = analyze(m, th, ["TORQ", "FOB"], tex)
        assert rows[i, 4] == pytest.approx(np.abs(r["TORQ"]).max(), rel=1e-12)
        assert rows[i, 10] == pytest.approx(r["FOB"].max(), rel=1e-12)


def test_sweep_frame_names_each_kind_as_the_csv_does():
    """Issue 33: sweep_frame's KIND column was 0.0 (the index into KINDS)."""
    pytest.importorskip("pandas")
    from sielaff.design.sweep import Grid, sweep_frame
    from sielaff.engine.classify import KINDS

    # R1 = 3: s + l = 19 > p + q = 16, a triple rocker beside the crank-rockers
    frame = sweep_frame(Grid(EXAMPLE, {"R1": [12.0, 3.0], "BALANCE": [0, 1]}), n=64)
    kinds = list(frame["KIND"])
    assert set(kinds) == {"crank-rocker", "triple-rocker"} and set(kinds) <= set(KINDS)
    assert list(frame["BALANCE"]) == [0, 1, 0, 1] and frame["BALANCE"].dtype.kind == "i"
