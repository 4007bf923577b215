"""Issue 22's remaining defects, each with a test that failed before its fix: bearing arcs
that converge and mean something (a threshold), one peak per pin in check, and the rest
listed in each test's docstring."""

from __future__ import annotations

import re

import numpy as np
import pytest

from conftest import DECKS
from sielaff.cli import main
from sielaff.design.bearings import THRESHOLD, bearings
from sielaff.emulator.cards import read_deck
from sielaff.engine import analyze
from sielaff.engine.scene import Scene
from sielaff.mechanism import EXAMPLE

# -- item 4: bearing arcs ----------------------------------------------------------------


def _arc_distance(a: list[tuple[float, float]], b: list[tuple[float, float]]) -> float:
    """The largest angle (deg) between matching ends of two lists of arcs."""
    assert len(a) == len(b), (a, b)
    d = [abs((x - y + 180.0) % 360.0 - 180.0) for p, q in zip(a, b) for x, y in zip(p, q)]
    return max(d, default=0.0)


def test_bearing_arcs_converge_as_the_sampling_grows():
    """720 positions and 36,000 give the same arcs within 0.1 deg, for every member of
    every pin (before: 720 samples shaded O4's rocker side 42-149 and 248-285 while 36,000
    found no arc)."""
    coarse, fine = bearings(EXAMPLE, n=720), bearings(EXAMPLE, n=36000)
    arcs = 0
    for pin in coarse:
        for m, f in zip(coarse[pin].members, fine[pin].members):
            assert _arc_distance(m.unloaded, f.unloaded) < 0.1, (pin, m.name)
            assert m.reversals == f.reversals
            arcs += len(m.unloaded)
        assert coarse[pin].peak == pytest.approx(fine[pin].peak, rel=1e-6)
    assert arcs >= 6  # the example has arcs to compare, not only "none"


def test_the_example_o4_near_theta2_69_is_below_the_threshold():
    """The load on O4 falls to about 1.1 lb of 545 lb near THETA 2 = 69: below 5 % of the
    peak it does not count (no direction), and the arcs it would have swept are arcs
    never loaded; with threshold 0 its fast swing loads every direction."""
    th = np.arange(6800, 7000) * 0.01
    low = analyze(EXAMPLE, th, ["FOB"])["FOB"]
    assert 1.0 < low.min() < 1.2
    pin = bearings(EXAMPLE)["O4"]
    assert 545.0 < pin.peak < 545.2
    near = (pin.theta2 > 66.0) & (pin.theta2 < 73.0)
    assert near.sum() > 5
    for m in pin.members:
        assert np.isnan(m.direction[near]).all()
        # every position loaded at or above the threshold has its direction
        assert np.isfinite(m.direction[pin.load >= THRESHOLD * pin.peak]).all()
        assert m.unloaded  # oil-groove candidates on both sides
    whole = bearings(EXAMPLE, threshold=0.0)["O4"]
    assert [m.unloaded for m in whole.members] == [[], []]


def test_threshold_crossings_are_located():
    """Where the load crosses the threshold the positions straddle it within 0.001 deg."""
    pin = bearings(EXAMPLE)["O4"]
    on = pin.load >= THRESHOLD * pin.peak
    cross = np.flatnonzero(on != np.roll(on, -1))
    assert cross.size >= 2
    for i in cross:
        j = (i + 1) % pin.theta2.size
        assert (pin.theta2[j] - pin.theta2[i]) % 360.0 <= 1e-3 + 1e-12


def _check_arcs(text: str) -> list[list[str]]:
    """Each member's arcs as check prints them, in the order printed."""
    return [re.findall(r"(\d+) to (\d+) deg", line.split("never loaded", 1)[1])
            for line in text.splitlines() if "never loaded" in line and "on the" in line]


def _plot_arcs(fig) -> list[list[tuple[str, str]]]:
    """Each axes' shaded arcs (the polar bars), as degrees printed like check's."""
    out = []
    axes = fig.axes
    for col in range(4):
        for row in range(2):
            ax = axes[row * 4 + col]
            arcs = []
            for bar in ax.patches:
                a = np.degrees(bar.get_x()) % 360.0
                b = (a + np.degrees(bar.get_width())) % 360.0
                arcs.append((f"{a:.0f}", f"{b:.0f}"))
            out.append(arcs)
    return out


@pytest.mark.parametrize("threshold", [None, 0.2])
def test_check_prints_the_arcs_plot_shades(threshold):
    """check's printed arcs are plot --bearings' shaded arcs (one computation)."""
    pytest.importorskip("matplotlib")
    from sielaff.tools.check import check_deck
    from sielaff.tools.plot.bearings import bearings_figure
    from sielaff.tools.plot.render import _pyplot

    deck = read_deck(DECKS / "example.dat")
    printed = _check_arcs(check_deck(deck, bearing_threshold=threshold).text)
    fig, _ = bearings_figure(deck, Scene(), threshold)
    try:
        shaded = _plot_arcs(fig)
    finally:
        _pyplot().close(fig)
    assert len(printed) == 8
    assert [[tuple(a) for a in p] for p in printed] == shaded
    assert sum(map(len, shaded)) >= 4


def test_bearing_threshold_option_on_check_and_plot(tmp_path, capsys):
    assert main(["check", str(DECKS / "example.dat"), "--bearing-threshold", "0"]) == 0
    out = capsys.readouterr().out
    assert "loads below 0% of the pin's peak" in out
    o4 = out.split("pin O4", 1)[1].splitlines()[1:3]
    assert all("none (loaded all round)" in line for line in o4)
    with pytest.raises(SystemExit) as exc:
        main(["check", str(DECKS / "example.dat"), "--bearing-threshold", "1.5"])
    assert exc.value.code == 2
    assert "not a fraction" in capsys.readouterr().err
    # plot: the option belongs to --bearings
    assert main(["plot", str(DECKS / "example.dat"), "-o", str(tmp_path),
                 "--bearing-threshold", "0.1"]) == 2
    assert "add --bearings" in capsys.readouterr().err


# -- item 4 of the list: check prints one peak per pin ----------------------------------


@pytest.mark.parametrize("deck", ["example.dat", "double-crank.dat"])
def test_check_prints_each_pin_peak_once(deck):
    """The peak bearing loads and the bearings section print the same numbers (before:
    the double crank's O2 read 621.0 lb in one and 620.9 lb in the other)."""
    from sielaff.tools.check import check_deck

    text = check_deck(read_deck(DECKS / deck)).text
    first = dict(re.findall(r"\((\w+)\)\s+at \w+\s+([\d.]+ \w+ at THETA 2 = +[\d.]+)", text))
    second = dict(re.findall(r"pin \w+ +\((\w+) *\) peak +([\d.]+ \w+ at THETA 2 = +[\d.]+)",
                             text))
    assert set(first) == {"FOA", "FOB", "FA32", "FB34"}
    assert first == second


# -- item 2 of the list: table's torque parts ------------------------------------------


def _table(argv, capsys):
    import csv
    import io

    status = main(["table", *argv])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    rows = list(csv.reader(io.StringIO(captured.out)))
    return rows[0], np.array([[float(v) for v in r[1:]] for r in rows[1:]])


def test_table_adds_the_torque_parts_the_scene_has(capsys):
    """decks/scene.toml has gravity and a load, no TEX: TORQ_GRAVITY and TORQ_LOADS are
    columns (with their unit), TORQ_TEX is not; the values are the engine's."""
    from sielaff.tools.common import read_spec_deck

    head, values = _table([str(DECKS / "scene.toml")], capsys)
    # and its crank acceleration shows TH2DD
    assert head[-3:] == ["TORQ_GRAVITY[in-lb]", "TORQ_LOADS[in-lb]", "TH2DD[rad/sec^2]"]
    assert not any(h.startswith("TORQ_TEX") for h in head)
    deck, scene = read_spec_deck(str(DECKS / "scene.toml"))
    want = analyze(deck.mechanism, values[:, 0], ["TORQ_GRAVITY", "TORQ_LOADS"], scene=scene)
    np.testing.assert_array_equal(values[:, -3], want["TORQ_GRAVITY"])
    np.testing.assert_array_equal(values[:, -2], want["TORQ_LOADS"])
    assert np.abs(values[:, -2]).max() > 1.0 and np.abs(values[:, -1]).max() > 1.0
    # a deck has no scene: no parts
    head, _ = _table([str(DECKS / "example.dat")], capsys)
    assert head[-1] == "SHAKM[in-lb]"


def test_table_torque_parts_on_request_sum_to_torq(capsys):
    """--torque-parts: every part (the model's), in the spec's unit (SI: N m); they add
    up to TORQ."""
    from sielaff.tools.table import torque_parts

    head, values = _table([str(DECKS / "si.toml"), "--torque-parts"], capsys)
    names = [h.split("[")[0] for h in head]
    parts = torque_parts()
    assert len(parts) == 6 and parts[0] == "TORQ_INERTIA"
    at = [names.index(p) for p in parts]
    assert [head[i] for i in at] == [f"{n}[N m]" for n in parts]
    torq = values[:, names.index("TORQ") - 1]
    np.testing.assert_allclose(values[:, [i - 1 for i in at]].sum(axis=1), torq,
                               atol=1e-12 * np.abs(torq).max())
    assert main(["table", str(DECKS / "si.toml"), "--torque-parts", "--only",
                 "kinematics"]) == 2
    assert "--torque-parts" in capsys.readouterr().err


def test_table_tex_column_with_a_tex_scene():
    import io

    from sielaff.tools.table import write_table

    deck = read_deck(DECKS / "example.dat")
    out = io.StringIO()
    write_table(deck, out, scene=Scene(tex=150.0))
    head = out.getvalue().splitlines()[0].split(",")
    assert head[-1] == "TORQ_TEX[in-lb]" and "TORQ_GRAVITY[in-lb]" not in head


# -- items 3 and 7 of the list: the sweep's Pareto senses, GAMMA_MAX, no NaN rows ------


def _dominated(x, y, i):
    """Brute force: some point at least as good in both (minimised) and better in one."""
    return bool(np.any((x <= x[i]) & (y <= y[i]) & ((x < x[i]) | (y < y[i]))))


@pytest.mark.parametrize("senses", [("min", "min"), ("max", "min"), ("min", "max"),
                                    ("max", "max")])
def test_pareto_front_in_either_sense_against_brute_force(senses):
    from sielaff.tools.sweep import _pareto

    rng = np.random.default_rng(7)
    x, y = np.round(rng.random(300), 2), np.round(rng.random(300), 2)  # ties too
    x[5] = np.nan
    front = _pareto(x, y, senses).tolist()
    kx, ky = (np.where(np.isfinite(v), -v if s == "max" else v, np.inf)
              for v, s in zip((x, y), senses))
    want = {i for i in range(300) if np.isfinite(x[i]) and not _dominated(kx, ky, i)}
    # points equal in both figures are dominated by neither: the front keeps one of them
    assert set(front) <= want and {(x[i], y[i]) for i in front} == {(x[i], y[i]) for i in want}
    assert len(front) >= 3
    assert kx[front[0]] == kx[list(want)].min()  # sorted from the best in x


def test_pareto_pair_syntax():
    from sielaff.design.sweep import pareto_pair

    assert pareto_pair("GAMMA_MIN:max,TORQ_PEAK") == (("GAMMA_MIN", "max"), ("TORQ_PEAK", "min"))
    assert pareto_pair(["GAMMA_MIN", "GAMMA_MAX:min"]) == (("GAMMA_MIN", "max"),
                                                          ("GAMMA_MAX", "min"))
    assert pareto_pair(["SHAK_PEAK:max", "TORQ_RMS"])[0] == ("SHAK_PEAK", "max")
    for bad in ("GAMMA_MIN", "KIND,TORQ_PEAK", "TORQ_PEAK:up,SHAK_PEAK", "X,Y,Z"):
        with pytest.raises(ValueError):
            pareto_pair(bad)


def test_gamma_max_is_the_largest_transmission_angle():
    from sielaff.design.figures import figures

    m = EXAMPLE.replace(R4=np.array([10.0, 12.0, 14.0]))
    f = figures(m, n=360)
    th = np.arange(360.0)
    for i, r4 in enumerate((10.0, 12.0, 14.0)):
        g = analyze(EXAMPLE.replace(R4=r4), th, ["GAMMA"])["GAMMA"]
        assert f["GAMMA_MAX"][i] == pytest.approx(g.max(), rel=1e-12)
    assert f["GAMMA_MAX"][1] == pytest.approx(67.98, abs=0.01)  # check's maximum, example


SWEEP_SPEC = """
[sweep]
angles = 36
pareto = ["GAMMA_MIN:max", "TORQ_PEAK"]
[sweep.vary]
R3 = [16.0, 2.0, 17.0]
R1 = [12.0, 13.0]
"""


def test_sweep_rows_only_for_a_full_cycle_and_pareto_max(tmp_path, capsys):
    """R3 = 2 cannot turn the crank (a double rocker): those designs have no row, stderr
    counts them; the plot's front maximises GAMMA_MIN as the spec asks."""
    pytest.importorskip("matplotlib")
    from sielaff.design.figures import figures
    from sielaff.tools.sweep import _pareto

    spec = tmp_path / "s.toml"
    spec.write_text((DECKS / "example.toml").read_text() + SWEEP_SPEC)
    csv, png = tmp_path / "s.csv", tmp_path / "p.png"
    assert main(["sweep", str(spec), "-o", str(csv), "--plot", str(png)]) == 0
    err = capsys.readouterr().err
    lines = csv.read_text().splitlines()
    assert "nan" not in csv.read_text().lower()
    designs = [int(line.split(",")[0]) for line in lines[1:]]
    r3 = np.repeat([16.0, 2.0, 17.0], 2)
    r1 = np.tile([12.0, 13.0], 3)
    f = figures(EXAMPLE.replace(R3=r3, R1=r1), n=36)
    full = np.flatnonzero(np.isfinite(f["TORQ_PEAK"]))
    assert designs == full.tolist() and len(full) == 4
    assert "2 of 6 designs left out (no row)" in err
    assert png.stat().st_size > 0
    # maximised GAMMA_MIN: the front starts at the largest GAMMA_MIN
    front = _pareto(f["GAMMA_MIN"], f["TORQ_PEAK"], ("max", "min"))
    assert f["GAMMA_MIN"][front[0]] == np.nanmax(f["GAMMA_MIN"])


# -- item 6 of the list: plot --linkage --at where the linkage does not assemble --------


def test_plot_linkage_at_an_angle_that_does_not_assemble(tmp_path, capsys):
    """decks/double-rocker.dat reaches 60-112.89 and 247.11-300 deg: --at 180 is one line
    naming those arcs, exit 2, nothing written (before: exit 0, the crank alone)."""
    out = tmp_path / "figs"
    assert main(["plot", str(DECKS / "double-rocker.dat"), "--linkage", "--at", "180",
                 "-o", str(out)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "does not assemble at this crank angle" in err[0]
    assert "60.00 to 112.89 deg and from 247.11 to 300.00 deg: nothing drawn" in err[0]
    assert not (out / "linkage.png").exists()


def test_plot_linkage_draws_only_the_angles_that_assemble():
    """--at 180,90: 180 is left out of the drawing (its warning), 90 drawn alone; the
    path of G3 is one curve per arc (a NaN between), and no text overlaps another or
    leaves the figure."""
    pytest.importorskip("matplotlib")
    from sielaff.tools.plot.linkage import _draw_linkage, linkage_data
    from sielaff.tools.plot.render import _pyplot, overlapping, text_boxes

    deck = read_deck(DECKS / "double-rocker.dat")
    with pytest.warns(UserWarning, match="--at 180: the linkage cannot be put together"):
        d = linkage_data(deck, (180.0, 90.0))
    assert d.at.tolist() == [90.0] and "THETA 2 = 90 deg" in d.title
    assert all(np.isfinite(x).all() for x, _ in d.joints.values())
    x, _ = d.curves["G3"]
    assert np.count_nonzero(np.isnan(x)) == 2  # after each of the two arcs
    plt = _pyplot()
    fig = _draw_linkage(plt, d)
    try:
        boxes = text_boxes(fig)
        w, h = fig.canvas.get_width_height()
        assert not overlapping(boxes)
        assert all(0 <= b[0] and b[2] <= w and 0 <= b[1] and b[3] <= h for _, b in boxes)
    finally:
        plt.close(fig)


def test_plot_linkage_default_angle_assembles(tmp_path, capsys):
    """No --at on a double rocker that does not assemble at 40 deg: the middle of its
    first arc is drawn, no warning."""
    pytest.importorskip("matplotlib")
    from sielaff.tools.plot.linkage import default_angle

    deck = read_deck(DECKS / "double-rocker.dat")
    assert default_angle(deck) == pytest.approx((60.0 + 112.89) / 2, abs=0.01)
    assert default_angle(read_deck(DECKS / "example.dat")) == 40.0
    assert main(["plot", str(DECKS / "double-rocker.dat"), "--linkage", "-o",
                 str(tmp_path)]) == 0
    assert capsys.readouterr().err == ""


# -- item 8 of the list: a change-point linkage, the same rules in every command --------


@pytest.fixture
def change_point(tmp_path):
    """The example with R3 = 14, R4 = 6: s + l = 4 + 14 = p + q = 6 + 12, folding flat at
    THETA 2 = 0 (|A O4| = R1 - R2 = R3 - R4)."""
    lines = (DECKS / "example.dat").read_text().splitlines()
    lines[2] = "    12.0     4.0    14.0     6.0" + lines[2][32:]
    path = tmp_path / "change-point.dat"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_change_point_through_every_command(change_point, tmp_path, capsys):
    """check exits 0 with the kind's report (3 only with --crank-rocker, and run 3); table
    gives rows only where the rates are defined (before: exit 2 blaming card 6 while check
    exited 3)."""
    from sielaff.engine.classify import linkage_class

    deck = read_deck(change_point)
    assert linkage_class(deck.mechanism).kind == "change-point"
    assert main(["check", str(change_point)]) == 0
    out = capsys.readouterr().out
    assert "change point: the four links lie in line at THETA 2 = 0 deg" in out
    assert "Verdict: usable as a change-point" in out and " nan" not in out
    assert main(["check", str(change_point), "--crank-rocker"]) == 3
    capsys.readouterr()
    assert main(["run", str(change_point), "-o", str(tmp_path / "l.asa")]) == 3
    capsys.readouterr()
    assert main(["table", str(change_point)]) == 0
    captured = capsys.readouterr()
    assert "card 6" not in captured.err and "folds flat at THETA 2 = 0 deg" in captured.err
    assert "1 of 36 positions left out" in captured.err
    rows = captured.out.splitlines()
    assert len(rows) == 36 and "nan" not in captured.out  # 10..350: 360 (= 0) left out
    assert main(["balance", str(change_point)]) == 0
    assert "nan" not in capsys.readouterr().out.lower()
    # the bearing cycle needs a whole revolution with loads: refused like a rocker's
    assert main(["plot", str(change_point), "--bearings", "-o", str(tmp_path / "b")]) == 2
    assert "a change point: the linkage folds flat" in capsys.readouterr().err


# -- item 5 of the list: bench's figure, labels apart ----------------------------------


def _bench_result() -> dict:
    """A study result shaped as sielaff.tools.bench.study.study returns it, with the
    numbers of docs/accuracy.png where float32's label fell on ibm1410:8's."""
    def row(model, t, median, top, same, fields, either):
        return {"model": model, "us_per_position": t, "exact_median": median,
                "exact_max": top, "same_median": same, "fields": fields,
                "boundary": list(range(either))}

    rows = [row("float64", 17.0, 5e-9, 1.8e-7, 1e-16, 69, 8),
            row("float32", 75.0, 8e-8, 1e-5, 8e-8, 66, 16),
            row("ibm1410:8", 600.0, 9e-8, 1.5e-5, 9e-8, 82, 0),
            row("ibm1410:12", 900.0, 5e-9, 5e-9, 1e-11, 76, 0),
            row("ibm1410:16", 900.0, 5e-9, 1.8e-7, 1e-15, 73, 0),
            row("engine", 2.2, 0.0, 2e-15, None, 66, 16)]
    tols = [10.0 ** -k for k in range(2, 16)]
    deltas = [90.0, 60.0, 45.0, 30.0, 20.0, 10.0, 5.0, 2.0, 1.0, 0.5, 0.2, 0.1, 0.05, 0.02,
              0.01]
    return {"models": {"rows": rows, "algorithm_median": 5e-9},
            "arccos": [{"tol": t, "worst": t, "mean_terms": 3 + k, "max_terms": 4 + 3 * k}
                       for k, t in enumerate(tols)],
            "steps": [{"delta": d, "engine_rel": 1e-16, "peak_rel": 1e-3 * d / 90,
                       "port_rel": 1e-8 if d >= 0.1 else None, "engine_s": 1e-4 / d,
                       "port_s": 1e-3 / d if d >= 0.1 else None} for d in deltas]}


@pytest.mark.slow  # draws bench's figure with constrained layout: seconds
def test_bench_figure_labels_do_not_overlap():
    """Every text of the figure, measured by the renderer, clear of every other (before:
    float32's label was drawn over ibm1410:8's)."""
    pytest.importorskip("matplotlib")
    from sielaff.tools.bench.report import figure
    from sielaff.tools.plot.render import _pyplot, overlapping, text_boxes

    fig = figure(_bench_result())
    try:
        boxes = text_boxes(fig)
        labels = [t for t, _ in boxes if "/82 fields" in t]
        assert len(labels) == 6
        w, h = fig.canvas.get_width_height()
        for text, b in boxes:
            if "/82 fields" in text:  # inside the figure
                assert 0 <= b[0] and b[2] <= w and 0 <= b[1] and b[3] <= h
        assert not [p for p in overlapping(boxes) if any("/82 fields" in t for t in p)]
    finally:
        _pyplot().close(fig)


# -- item 9 of the list: check's past-THMAX quirk as run words it -----------------------


def test_check_past_thmax_by_roundoff_shows_the_digits_that_differ(tmp_path):
    """check said "THETA 2 = 100.1 > THMAX = 100.1" where run already showed the digits."""
    from sielaff.tools.check import check_deck

    lines = (DECKS / "example.dat").read_text().splitlines()[:6]
    path = tmp_path / "q.dat"
    path.write_text("\n".join(lines) + "\n     0.0     0.1   100.1\n")
    text = " ".join(check_deck(read_deck(path), sheet_limit=0).text.split())
    assert "THETA 2 = 100.10000000000001 > THMAX = 100.1" in text
    assert "by roundoff" in text
    path.write_text("\n".join(lines) + "\n    10.0    10.0   360.0\n")
    text = " ".join(check_deck(read_deck(path), sheet_limit=0).text.split())
    assert "THETA 2 = 370.0 > THMAX = 360.0 (the 1966 loop prints a sheet before testing " \
           "ATH2.GT.THMAX)" in text


def test_check_json_gives_the_texts_peaks_and_threshold(capsys):
    """--format json's peak loads and bearings are the text's (one computation), with the
    --bearing-threshold asked for."""
    import json

    from sielaff.design.bearings import bearings

    assert main(["check", str(DECKS / "double-crank.dat"), "--format", "json",
                 "--bearing-threshold", "0.1"]) == 0
    data = json.loads(capsys.readouterr().out)
    pins = bearings(read_deck(DECKS / "double-crank.dat").mechanism, threshold=0.1)
    for entry in data["bearings"]:
        pin = pins[entry["pin"]]
        assert entry["peak"]["value"] == pin.peak
        assert data["peak_loads"][pin.force]["peak"]["value"] == pin.peak
        assert [m["never_loaded_deg"] for m in entry["members"]] == \
            [[list(a) for a in m.unloaded] for m in pin.members]
    assert any("loads below 10% of the pin's peak" in line for line in data["report"])
