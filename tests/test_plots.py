"""``sielaff plot``: the report's figures as PNG files, and the data behind them."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

import procs
from conftest import DECKS
from sielaff import engine
from sielaff.emulator.cards import parse_deck, read_deck
from sielaff.engine import analyze
from sielaff.mechanism import EXAMPLE
from sielaff.tools.plot import plot_data, sample_angles

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
FORCE_FILES = [
    "fig12-driving-torque.png", "fig13-force-4-on-1.png", "fig14-force-3-on-4-rel-link4.png",
    "force-2-on-1.png", "force-3-on-2.png", "fig16-shaking-force.png",
]
KINEMATIC_FILES = [
    "kin-link-angles.png", "kin-angular-velocity.png", "kin-angular-acceleration.png",
    "kin-pin-velocity.png", "kin-pin-acceleration.png",
]
PARAMETERS = "".join((DECKS / "example.dat").read_text().splitlines(keepends=True)[:6])


def deck_with(*ranges):
    return parse_deck(PARAMETERS + "".join("".join(f"{v:8.3f}" for v in r) + "\n"
                                           for r in ranges))


@pytest.fixture(scope="module")
def example():
    return read_deck(DECKS / "example.dat")


@pytest.fixture(scope="module")
def data(example):
    return plot_data(example)


# --------------------------------------------------------------------------
# The data
# --------------------------------------------------------------------------


def test_figures(data):
    assert [d.filename for d in data.values()] == FORCE_FILES
    assert [d.kind for d in data.values()] == ["line"] + ["polar"] * 5


def test_sampling_every_degree_whatever_delta():
    for delta in (10.0, 30.0, 90.0, 0.25):
        th = sample_angles(deck_with((10.0, delta, 360.0)))
        # 10 to 360 by DELTA >= 10 samples a whole revolution: drawn from 0 to 360
        assert (th[0], th[-1]) == ((0.0 if delta >= 10.0 else 10.0), 360.0)
        assert np.all(np.diff(th) > 0) and np.max(np.diff(th)) <= 1.0
        if delta < 1.0:
            assert np.max(np.diff(th)) <= delta + 1e-12


@pytest.mark.parametrize("card, span", [
    ((10.0, 10.0, 360.0), (0.0, 360.0)),     # the example: ends on a multiple of 360
    ((0.0, 5.0, 355.0), (0.0, 360.0)),       # starts on one
    ((-180.0, 5.0, 175.0), (-180.0, 180.0)),  # neither: a revolution from THZERO
    ((0.0, 10.0, 340.0), (0.0, 340.0)),      # not a whole revolution: drawn as it is
    ((0.0, 10.0, 720.0), (0.0, 720.0)),      # two revolutions: as it is
])
def test_whole_revolution_decks_close(card, span):
    """A deck that samples a whole revolution gives closed polar curves and a torque curve
    over the whole revolution (the example's most negative torque is at 359 degrees)."""
    deck = deck_with(card)
    th = sample_angles(deck)
    assert (th[0], th[-1]) == span
    d = plot_data(deck)
    closed = (span[1] - span[0]) % 360.0 == 0.0
    for fig in d.values():
        if fig.kind == "polar":
            x0, x1 = (fig.r[i] * np.cos(np.radians(fig.theta[i])) for i in (0, -1))
            y0, y1 = (fig.r[i] * np.sin(np.radians(fig.theta[i])) for i in (0, -1))
            assert (math.hypot(x1 - x0, y1 - y0) < 1e-9 * np.nanmax(fig.r)) == closed
    if span[1] - span[0] == 360.0:
        torq = d["fig12-driving-torque"].series["driving torque TORQ"]
        low = analyze(deck.mechanism, np.arange(0.0, 360.0, 0.25), ["TORQ"])["TORQ"].min()
        assert np.nanmin(torq) <= low + 1e-6 * abs(low)


def test_sampling_several_cards():
    th = sample_angles(deck_with((0.0, 10.0, 90.0), (45.0, 5.0, 120.0), (200.0, 10.0, 220.0),
                                 (300.0, 10.0, 250.0)))
    parts = np.split(th, np.flatnonzero(np.isnan(th)))
    parts = [p[~np.isnan(p)] for p in parts]
    assert [(p[0], p[-1]) for p in parts] == [(0.0, 120.0), (200.0, 220.0), (300.0, 300.0)]
    assert all(np.max(np.diff(p), initial=0) <= 1.0 for p in parts)


def test_fig12_driving_torque_matches_engine(data):
    d = data["fig12-driving-torque"]
    assert d.xlabel == "THETA 2, crank angle (deg)" and d.ylabel == "driving torque TORQ (in-lb)"
    np.testing.assert_array_equal(d.ath2, sample_angles(read_deck(DECKS / "example.dat")))
    (torq,) = d.series.values()
    np.testing.assert_allclose(torq, analyze(EXAMPLE, d.ath2, ["TORQ"])["TORQ"], rtol=1e-12)
    # The report's sheets: 545.6 in-lb at 40 degrees, 637.1 at 50 (Figures 10, 11).
    at = {float(a): float(t) for a, t in zip(d.ath2, torq)}
    assert round(at[40.0], 1) == 545.6 and round(at[50.0], 1) == 637.1
    x, y = d.points["deck positions (listing sheets)"]
    np.testing.assert_array_equal(x, np.arange(10.0, 361.0, 10.0))
    np.testing.assert_allclose(y, analyze(EXAMPLE, x, ["TORQ"])["TORQ"], rtol=1e-12)
    assert d.zero_line
    # The cycle work in the legend: about zero (TEX = 0), by Simpson's rule here.
    th = np.linspace(0.0, 360.0, 3601)
    t = np.abs(analyze(EXAMPLE, th, ["TORQ"])["TORQ"])
    w = np.ones_like(th)
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    abs_work = float(np.sum(w * t) * np.radians(0.1) / 3.0)
    (note,) = d.notes
    work = float(note.split("= ")[1].split(" in-lb")[0])
    assert abs(work) < 1e-6
    assert f"= {abs_work:.0f} in-lb)" in note


@pytest.mark.parametrize("name, mag, direction, relative", [
    ("fig13-force-4-on-1", "FOB", "DFOB", False),
    ("fig14-force-3-on-4-rel-link4", "FB34", "DFB34", True),
    ("force-2-on-1", "FOA", "DFOA", False),
    ("force-3-on-2", "FA32", "DFA32", False),
    ("fig16-shaking-force", "SHAK", "DSHAK", False),
])
def test_polar_figures_match_engine(data, name, mag, direction, relative):
    d = data[name]
    ref = analyze(EXAMPLE, d.ath2, [mag, direction, "ATH4", mag + "X", mag + "Y"])
    np.testing.assert_allclose(d.r, ref[mag], rtol=1e-12)
    # The polar point (r, theta) is the force vector itself (theta relative to link 4 in 14).
    rel = np.radians(ref["ATH4"]) if relative else 0.0
    x = d.r * np.cos(np.radians(d.theta) + rel)
    y = d.r * np.sin(np.radians(d.theta) + rel)
    np.testing.assert_allclose(x, ref[mag + "X"], atol=1e-9 * np.max(d.r))
    np.testing.assert_allclose(y, ref[mag + "Y"], atol=1e-9 * np.max(d.r))
    assert d.link_outline == relative
    # THETA 2 marks every 30 degrees, where the curve is at those angles.
    np.testing.assert_array_equal(d.marks, np.arange(0.0, 361.0, 30.0))
    m = analyze(EXAMPLE, d.marks, [mag, direction, "ATH4"])
    np.testing.assert_allclose(d.mark_r, m[mag], rtol=1e-12)
    want = np.mod(m[direction] - (m["ATH4"] if relative else 0.0), 360.0)
    np.testing.assert_allclose(d.mark_theta, want, atol=1e-9)


def test_fig14_is_mostly_along_link4(data):
    """The report: link 4's bearing carries much more along the link than across it."""
    d = data["fig14-force-3-on-4-rel-link4"]
    along = np.abs(d.r * np.cos(np.radians(d.theta)))
    across = np.abs(d.r * np.sin(np.radians(d.theta)))
    assert along.max() > 3 * across.max()


def test_fig16_horizontal_about_three_times_vertical(data):
    """The report: the largest X shaking force is almost three times the largest Y."""
    d = data["fig16-shaking-force"]
    x = np.abs(d.r * np.cos(np.radians(d.theta))).max()
    y = np.abs(d.r * np.sin(np.radians(d.theta))).max()
    assert 2.4 < x / y < 3.0


def test_kinematics_only_runs_no_force_step(example):
    engine.STEP_CALLS.clear()
    data = plot_data(example, only="kinematics")
    assert [d.filename for d in data.values()] == KINEMATIC_FILES
    assert not any(name.startswith(("_force", "_inertia")) for name in engine.STEP_CALLS)
    want = {
        "kin-link-angles": ["ATH3", "ATH4", "GAMMA"],
        "kin-angular-velocity": ["TH3D", "TH4D"],
        "kin-angular-acceleration": ["TH3DD", "TH4DD"],
        "kin-pin-velocity": ["VA", "VB"],
        "kin-pin-acceleration": ["AA", "AB"],
    }
    units = {"kin-link-angles": "(deg)", "kin-angular-velocity": "(rad/sec)",
             "kin-angular-acceleration": "(rad/sec^2)", "kin-pin-velocity": "(in/sec)",
             "kin-pin-acceleration": "(in/sec^2)"}
    for name, names in want.items():
        d = data[name]
        assert d.ylabel.endswith(units[name])
        ref = analyze(EXAMPLE, d.ath2, names)
        assert len(d.series) == len(names)
        for series, n in zip(d.series.values(), names):
            np.testing.assert_allclose(series, ref[n], rtol=1e-12)


def test_bad_only(example):
    with pytest.raises(ValueError, match="kinematics"):
        plot_data(example, only="forces")


# --------------------------------------------------------------------------
# The PNG files, through the command line
# --------------------------------------------------------------------------


def check_pngs(paths, width: int, height: int) -> None:
    """PNG files of the given size that matplotlib reads back as non-blank images."""
    for path in paths:
        data = path.read_bytes()
        assert data[:8] == PNG_SIGNATURE
        assert len(data) > 20_000  # a drawing, not an empty canvas
        assert int.from_bytes(data[16:20], "big") == width
        assert int.from_bytes(data[20:24], "big") == height
    # imread in a child process too: matplotlib would grow this one by ~40 MB.
    code = ("import sys, matplotlib.image as m\n"
            "for p in sys.argv[1:]:\n"
            "    a = m.imread(p)\n"
            "    print(*a.shape, round(float(a[..., :3].std()), 3))\n")
    r = subprocess.run([sys.executable, "-c", code, *map(str, paths)], capture_output=True,
                       text=True, check=True)
    for line in r.stdout.splitlines():
        h, w, channels, std = line.split()
        assert (int(h), int(w)) == (height, width) and int(channels) in (3, 4)
        assert float(std) > 0.05  # not blank
    assert len(r.stdout.splitlines()) == len(paths)


def plot_subprocess(*argv: str) -> tuple[int, str, str]:
    """The command in a child process: drawing grows a process by ~100 MB, keep it there."""
    r = procs.run(["plot", *argv], text=True)
    return r.returncode, r.stdout, r.stderr


def test_plot_writes_the_figures(tmp_path):
    out_dir = tmp_path / "plots"
    status, out, err = plot_subprocess(str(DECKS / "example.dat"), "-o", str(out_dir))
    assert (status, err) == (0, "")
    assert out.splitlines() == [str(out_dir / f) for f in FORCE_FILES]
    assert sorted(p.name for p in out_dir.iterdir()) == sorted(FORCE_FILES)  # no temp files
    check_pngs([out_dir / FORCE_FILES[0]], 990, 616)
    check_pngs([out_dir / name for name in FORCE_FILES[1:]], 880, 924)


@pytest.mark.slow
def test_plot_kinematics_only(tmp_path):
    status, out, err = plot_subprocess(str(DECKS / "example.dat"), "-o", str(tmp_path),
                                       "--only", "kinematics")
    assert (status, err) == (0, "")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(KINEMATIC_FILES)
    check_pngs([tmp_path / name for name in KINEMATIC_FILES], 990, 616)


@pytest.mark.slow
def test_plot_not_crank_rocker(tmp_path):
    deck = tmp_path / "deck.dat"
    lines = (DECKS / "example.dat").read_text().splitlines(keepends=True)
    lines[2] = "    12.0    14.0    16.0    12.0\n"
    deck.write_text("".join(lines))
    status, out, err = plot_subprocess(str(deck), "-o", str(tmp_path / "plots"))
    # any four-bar is drawn over the angles it reaches, its kind said on stderr (issue 22)
    assert status == 0 and "triple-rocker" in err and "Traceback" not in err
    assert (tmp_path / "plots" / "fig12-driving-torque.png").exists()


def test_plot_without_matplotlib(tmp_path):
    code = ("import sys; sys.modules['matplotlib'] = None\n"
            "from sielaff.cli import main\n"
            f"sys.exit(main(['plot', {str(DECKS / 'example.dat')!r}, '-o', "
            f"{str(tmp_path / 'p')!r}]))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 2
    assert r.stderr == "sielaff: sielaff plot needs matplotlib: pip install -e \".[plot]\"\n"
    assert not (tmp_path / "p").exists()


def test_plot_help_shows_example():
    r = procs.run(["plot", "--help"], text=True)
    assert r.returncode == 0
    assert "example:\n  sielaff plot decks/example.dat -o plots" in r.stdout


OVERLAP_DECKS = [
    ((10.0, 10.0, 360.0),),                                  # the example
    ((0.0, 10.0, 90.0), (45.0, 5.0, 120.0), (200.0, 10.0, 220.0)),  # pieces
    ((30.0, 30.0, 30.0),),                                   # one position
    ((0.0, 1.0, 720.0),),                                    # two revolutions
]


@pytest.mark.slow
@pytest.mark.parametrize("cards", OVERLAP_DECKS)
@pytest.mark.parametrize("mechanism", ["example", "long-rocker"])
def test_no_two_labels_overlap(cards, mechanism):
    """Through matplotlib's renderer: no two text boxes of any figure intersect (titles,
    tick and ring labels, THETA 2 marks, legend entries)."""
    from sielaff.tools import plot as plots

    deck = deck_with(*cards)
    if mechanism == "long-rocker":
        import dataclasses

        deck = dataclasses.replace(deck, mechanism=dataclasses.replace(
            EXAMPLE, R1=10.0, R3=11.0, R4=9.0, RG3=5.5, RG4=4.5))
    plt = plots._pyplot()
    for only in (None, "kinematics"):
        for d in plot_data(deck, only).values():
            fig = plots._draw_polar(plt, d) if d.kind == "polar" else plots._draw_line(plt, d)
            try:
                boxes = plots.text_boxes(fig)
                assert len(boxes) > 8
                assert plots.overlapping(boxes) == [], d.name
            finally:
                plt.close(fig)


def test_overlap_detector_detects():
    from sielaff.tools import plot as plots

    plt = plots._pyplot()
    fig, ax = plt.subplots()
    ax.text(0.5, 0.5, "one")
    ax.text(0.5, 0.5, "two")
    try:
        assert ("one", "two") in plots.overlapping(plots.text_boxes(fig))
    finally:
        plt.close(fig)


def test_help_names_every_figure_file():
    r = procs.run(["plot", "--help"], text=True)
    text = " ".join(r.stdout.split())
    deck = read_deck(DECKS / "example.dat")
    for only in (None, "kinematics"):
        for d in plot_data(deck, only).values():
            assert d.filename in text
    assert "Figures 12, 13, 14 and 16" in text and "15 and 17" in text


# ----- the linkage drawn: Figure 9, and one cycle animated --------------------------------------
def test_linkage_drawing_data_is_the_mechanism(tmp_path):
    from sielaff.tools import plot as plots
    from sielaff.tools.plot import linkage

    deck = read_deck(DECKS / "example.dat")
    d = linkage.linkage_data(deck, at=(40.0, 130.0), points=[(3, 16.0, 20.0)])
    t2 = np.radians([40.0, 130.0])
    r = analyze(EXAMPLE, [40.0, 130.0], ["ATH3", "ATH4"])
    t3, t4 = np.radians(r["ATH3"]), np.radians(r["ATH4"])
    ax, ay = EXAMPLE.R2 * np.cos(t2), EXAMPLE.R2 * np.sin(t2)
    np.testing.assert_allclose(d.joints["A"][0], ax, atol=1e-12)
    np.testing.assert_allclose(d.joints["A"][1], ay, atol=1e-12)
    np.testing.assert_allclose(d.joints["B"][0], ax + EXAMPLE.R3 * np.cos(t3), atol=1e-12)
    np.testing.assert_allclose(d.joints["B"][1], EXAMPLE.R4 * np.sin(t4), atol=1e-12)
    bx = EXAMPLE.R1 + EXAMPLE.R4 * np.cos(t4)
    np.testing.assert_allclose(d.joints["B"][0], bx, atol=1e-12)  # the loop closes
    assert set(d.curves) == {"G3", "P1 (link 3, 16, 20 deg)"} and d.toggles == []
    plt = plots._pyplot()
    fig = linkage._draw_linkage(plt, d)
    try:
        assert plots.overlapping(plots.text_boxes(fig)) == []
    finally:
        plt.close(fig)


def test_linkage_of_a_triple_rocker_marks_its_toggles():
    from sielaff.tools.plot import linkage

    deck = read_deck(DECKS / "example.dat")
    deck.mechanism = EXAMPLE.replace(R1=10.0, R2=4.0, R3=5.0, R4=4.0, RG3=2.5, RG4=2.0)
    d = linkage.linkage_data(deck, at=(0.0,))
    assert d.toggles == pytest.approx([64.0555, 295.9445], abs=1e-3)
    assert "triple-rocker" in d.title


@pytest.mark.slow
def test_plot_linkage_and_animate_write_the_files(tmp_path):
    out = tmp_path / "lk"
    r = procs.run(["plot", DECKS / "example.dat", "--linkage", "--at", "40,130", "--animate",
                   "-o", out], text=True)
    assert r.returncode == 0 and r.stderr == "", r.stderr
    assert sorted(p.name for p in out.iterdir()) == ["linkage.gif", "linkage.png"]
    from PIL import Image

    with Image.open(out / "linkage.gif") as im:
        assert im.n_frames == 36
    bad = procs.run(["plot", DECKS / "example.dat", "--linkage", "--point", "5:1:0",
                     "-o", out], text=True)
    assert bad.returncode == 2 and "LINK 2, 3 or 4" in bad.stderr


def test_plot_linkage_draws_any_four_bar(tmp_path):
    """--linkage is for every kind, and so are the report's figures (issue 22)."""
    lines = (DECKS / "example.dat").read_text().splitlines()
    lines[2] = "    10.0     4.0     5.0     4.0"  # a triple-rocker
    deck = tmp_path / "tri.dat"
    deck.write_text("\n".join(lines) + "\n")
    ok = procs.run(["plot", deck, "--linkage", "-o", tmp_path / "a"], text=True)
    assert ok.returncode == 0 and (tmp_path / "a" / "linkage.png").stat().st_size > 10_000
    # the report's figures of a triple rocker: test_plot_not_crank_rocker (slow tier), and
    # of a double crank test_kinds' plot of every kind (its default-tier pair)


@pytest.mark.filterwarnings("ignore::sielaff.AssemblyWarning")  # plot says it once
def test_a_crank_that_swings_has_no_cycle_work_and_says_why():
    """Issue 33: a double rocker's Fig. 12 said "cycle work = nan J"."""
    from sielaff.tools.common import load_scene

    for name, turns in (("double-rocker.toml", False), ("example.toml", True)):
        deck, scene = load_scene(str(DECKS / name), any_linkage=True)
        notes = " ".join(plot_data(deck, None, scene)["fig12-driving-torque"].notes)
        assert "nan" not in notes.lower()
        assert ("cycle work \u222e TORQ" in notes) == turns
        assert ("no cycle work: the crank swings between toggles" in notes) == (not turns)


def test_a_link_angle_that_wraps_breaks_its_line_instead_of_crossing_the_figure():
    """Issue 33: THETA 3's wrap was drawn as a vertical line."""
    from sielaff.tools.common import load_scene

    deck, scene = load_scene(str(DECKS / "double-crank.toml"), any_linkage=True)
    d = plot_data(deck, "kinematics", scene)["kin-link-angles"]
    raw = engine.analyze(deck.mechanism, d.ath2, ["ATH3", "ATH4"], scene=scene)
    wraps = 0
    for name, label in (("ATH3", "THETA 3 (link 3)"), ("ATH4", "THETA 4 (link 4)")):
        jumps = np.abs(np.diff(raw[name])) > 180.0
        wraps += int(np.count_nonzero(jumps))
        y = d.series[label]
        finite = np.isfinite(y[1:]) & np.isfinite(y[:-1])
        assert not np.any(np.abs(np.diff(y))[finite] > 180.0)
        assert np.count_nonzero(np.isnan(y)) == np.count_nonzero(jumps)  # only the wraps
    assert wraps >= 1  # the case is drawn: a link of the double crank turns fully


def test_crowded_marks_near_the_pole_share_a_label():
    """decks/scene.toml's Fig. 13 passes the pole with several crank angles landing on one
    spot, and the tolerance deck balanced packs wide ring labels along a near-horizontal
    direction: no two texts overlap, every marked THETA 2 is still named by a label, and
    the ring labels shown each carry the unit."""
    import dataclasses

    from sielaff import balance
    from sielaff.tools import plot as plots
    from sielaff.tools.common import load_scene

    plt = plots._pyplot()
    merged = thinned = 0
    for name, balanced in (("scene.toml", False), ("tolerance.toml", True)):
        deck, scene = load_scene(str(DECKS / name))
        if balanced:
            deck = dataclasses.replace(deck, mechanism=balance(deck.mechanism))
        d = plot_data(deck, None, scene)["fig13-force-4-on-1"]
        fig = plots._draw_polar(plt, d)
        try:
            boxes = plots.text_boxes(fig)
            assert plots.overlapping(boxes) == [], name
            texts = [t for t, _ in boxes]
            named = {v for t in texts for v in t.split("/") if v.isdigit()}
            assert {f"{m:g}" for m in d.marks} <= named, name
            merged += sum(1 for t in texts if "/" in t and t != "0/360")
            ax = fig.axes[0]
            rings = [t.get_text() for t in ax.get_yticklabels()]
            shown = [t for t in rings if t]
            assert shown and all(t.endswith(f" {d.r_unit}") for t in shown)
            thinned += len(shown) < len([v for v in ax.get_yticks() if v <= 0.9 * ax.get_ylim()[1]])
        finally:
            plt.close(fig)
    # the cases are drawn: a merged label near the pole, and rings left unlabelled
    assert merged >= 1 and thinned >= 1
