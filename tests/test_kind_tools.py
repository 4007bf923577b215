"""Every kind of linkage through the tools: each spec under decks/ for the slider-crank,
the inverted slider-crank and the two six-bars read into its kind, through ``table``,
``check`` (text and JSON), ``plot`` (the figures, the linkage drawn and animated) and
``simulate``; their scene's effects named by the kind's own links; bad specs one line.
The numbers are checked against the engine's own analysis of the same fields and against
the kinds' constructions."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import re
from pathlib import Path

import numpy as np
import pytest

from conftest import DECKS, tiered
from sielaff import (
    INVERTED_EXAMPLE,
    SLIDER_EXAMPLE,
    STEPHENSON_EXAMPLE,
    WATT_EXAMPLE,
    analyze,
    load_spec,
)
from sielaff.cli import main
from sielaff.engine import model_for

KINDS = {"slider-crank": SLIDER_EXAMPLE, "inverted-slider-crank": INVERTED_EXAMPLE,
         "watt": WATT_EXAMPLE, "stephenson": STEPHENSON_EXAMPLE}


def cli(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(list(argv))
    return status, out.getvalue(), err.getvalue()


def spec_with(tmp_path: Path, kind: str, old: str = "", new: str = "", extra: str = "") -> Path:
    text = (DECKS / f"{kind}.toml").read_text()
    if old:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / f"{kind}.toml"
    path.write_text(text + extra)
    return path


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_each_spec_reads_into_its_example(kind):
    s = load_spec(str(DECKS / f"{kind}.toml"))
    assert s.mechanism == KINDS[kind]
    assert s.ranges == ((0.0, 30.0, 360.0),)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_table_is_the_engine_on_the_spec(kind):
    status, out, err = cli("table", str(DECKS / f"{kind}.toml"))
    assert status == 0 and err == ""
    rows = list(csv.reader(io.StringIO(out)))
    model = model_for(KINDS[kind])
    assert [h.split("[")[0] for h in rows[0][1:]] == list(model.results)
    body = np.array([[float(x) for x in r[1:]] for r in rows[1:]])
    th = np.arange(0.0, 361.0, 30.0)
    r = analyze(KINDS[kind], th)
    for j, name in enumerate(model.results):
        assert np.array_equal(body[:, j], np.asarray(r[name]) + 0.0 * th), name


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_check_peaks_are_the_engine_s(kind):
    status, text, err = cli("check", str(DECKS / f"{kind}.toml"), "--format", "json")
    assert status == 0 and err == ""
    facts = json.loads(text)
    assert facts["kind"] == kind
    m = KINDS[kind]
    th = np.arange(0.0, 360.0, 0.001)
    peaks = facts["peaks"]
    names = sorted({p["name"] for p in peaks})
    r = analyze(m, th, names)
    for p in peaks:
        v = np.asarray(r[p["name"]])
        want = v.min() if "most negative" in p["label"] else v.max()
        assert p["value"] == pytest.approx(float(want), rel=1e-6), p["label"]
    # every pin of the linkage has its peak (a pin left out fails): O2, then 3 an RRR
    # (P, Q, C), 2 an RRP or an RPR (RRP: P and C; RPR: P and Q)
    pins = 1 + sum(3 if type(d).__name__ == "RRR" else 2
                   for d in model_for(m).topology.dyads)
    assert sum(p["label"].startswith("pin ") for p in peaks) == pins
    assert abs(facts["cycle_work"]["value"]) < 1e-9 * facts["cycle_work"]["abs"]


def test_check_gives_the_quick_return_by_construction():
    from sielaff.inverted_slider_crank import quick_return

    status, out, _ = cli("check", str(DECKS / "inverted-slider-crank.toml"))
    q = quick_return(INVERTED_EXAMPLE)
    assert status == 0 and f"time ratio {q.time_ratio:.4f}" in out


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_plot_draws_every_pin_force_and_the_linkage(kind, tmp_path):
    pytest.importorskip("matplotlib")
    status, out, err = cli("plot", str(DECKS / f"{kind}.toml"), "-o", str(tmp_path / "f"))
    assert status == 0 and err == "", err
    files = sorted(Path(p).name for p in out.split())
    m = KINDS[kind]
    from sielaff.engine.joints import joints

    pins, _ = joints(model_for(m).topology)
    assert len(files) == len(pins) + 2  # each pin, the torque, the shaking force
    assert "fig12-driving-torque.png" in files and "shaking-force.png" in files
    status, out, err = cli("plot", str(DECKS / f"{kind}.toml"), "-o", str(tmp_path / "l"),
                           "--linkage", "--at", "40,200")
    assert status == 0 and err == "", err
    assert (tmp_path / "l" / "linkage.png").stat().st_size > 10_000


def test_plot_animates_a_slider_crank(tmp_path):
    pytest.importorskip("matplotlib")
    status, out, err = cli("plot", str(DECKS / "slider-crank.toml"), "-o", str(tmp_path),
                           "--animate")
    assert status == 0 and err == ""
    data = (tmp_path / "linkage.gif").read_bytes()
    assert data[:6] == b"GIF89a"
    from PIL import Image

    assert Image.open(tmp_path / "linkage.gif").n_frames == 36


def test_plot_kinematics_of_a_six_bar(tmp_path):
    pytest.importorskip("matplotlib")
    status, out, _ = cli("plot", str(DECKS / "watt.toml"), "-o", str(tmp_path), "--only",
                         "kinematics")
    assert status == 0
    assert {Path(p).name for p in out.split()} >= {"kin-link-angles.png",
                                                   "kin-pin-velocity.png"}


def test_a_scene_names_the_kinds_own_links(tmp_path):
    """A load on link5 and a spring to the lever: read by the kind's names, the table the
    engine's with the same Scene."""
    from sielaff import Load, PinFriction, Spring, scene_for

    path = spec_with(tmp_path, "watt", extra=(
        '\n[scene]\ngravity = "down"\n[[scene.load]]\nlink = "link5"\ndistance = 3.0\n'
        'force = [0.0, -50.0]\n[scene.friction]\nmu = 0.1\nradius = 0.25\n'))
    s = load_spec(str(path))
    want = scene_for(WATT_EXAMPLE)(gravity="down", loads=[Load(5, r=3.0, fy=-50.0)],
                                   friction=PinFriction(0.1, 0.25))
    assert s.scene == want
    status, out, err = cli("table", str(path))
    assert status == 0, err
    head = out.splitlines()[0].split(",")
    assert "TORQ_LOADS[in-lb]" in head and "PLOSS_D[in-lb/sec]" in head
    path = spec_with(tmp_path, "inverted-slider-crank", extra=(
        '\n[[scene.spring]]\na = { link = "frame", distance = 20.0, angle = 90.0 }\n'
        'b = { link = "lever", distance = 10.0, angle = 0.0 }\nk = 5.0\nlength = 12.0\n'))
    s = load_spec(str(path))
    assert s.scene.elements == (Spring((1, 20.0, 90.0), (4, 10.0, 0.0), 5.0, 12.0),)
    assert cli("check", str(path))[0] == 0


@pytest.mark.parametrize(("kind", "old", "new", "says"), [
    ("watt", "link5 = 10.0 ", "link5 = 40.0 ", "cannot close at any crank angle"),
    ("watt", "O6 = { x = 4.0, y = 14.0 }", "O6 = { x = 4.0 }", "[pivots] O6 has no y"),
    ("stephenson", "C = { distance = 10.0, angle = 25.0 }", "C = { r = 10.0 }",
     "[points] C: unknown key 'r'"),
    ("inverted-slider-crank", "frame = 10.0 ", "frame = -10.0 ", "InvertedSliderCrank.R1 = "
     "-10 in: must be > 0"),
    ("inverted-slider-crank", "[linkage]", "[[scene.load]]\nlink = \"rod\"\n\n[linkage]",
     "[[scene.load]] 1 link = 'rod': crank, block or lever"),
])
def test_bad_kind_specs_are_one_line(tmp_path, kind, old, new, says):
    path = spec_with(tmp_path, kind, old, new)
    for command in ("table", "check"):
        status, out, err = cli(command, str(path))
        assert status == 2 and out == "", (command, err)
        assert err.count("\n") == 1 and says in err, (command, err)


def test_a_six_bar_that_cannot_turn_is_usable_where_it_assembles(tmp_path):
    """As a four-bar that is not a crank-rocker: check says so, exit 0; --crank-rocker
    requires a crank that turns (exit 3, one line)."""
    path = spec_with(tmp_path, "watt", "link6 = 9.0 ", "link6 = 4.0 ")
    path.write_text(path.read_text().replace("link5 = 10.0 ", "link5 = 6.0 "))
    status, out, err = cli("check", str(path))
    assert status == 0 and err == "" and "cannot turn fully" in out
    assert "Verdict: usable where it assembles" in out
    status, out, err = cli("check", str(path), "--crank-rocker")
    assert status == 3 and err.count("\n") == 1 and "cannot turn fully" in out
    status, out, err = cli("table", str(path))
    assert status == 0 and "positions left out" in err


def test_simulate_a_slider_crank_spec(tmp_path):
    pytest.importorskip("scipy")
    path = spec_with(tmp_path, "slider-crank", extra=(
        '\n[motor]\nkind = "linear"\nstall_torque = 800.0\nno_load_speed = 350.0\n'
        "flywheel = 0.05\nspeed = 300.0\nrevolutions = 2\n"))
    status, out, err = cli("simulate", str(path))
    assert status == 0 and "2 revolutions in" in err
    rows = list(csv.reader(io.StringIO(out)))
    assert rows[0][:3] == ["t[s]", "ATH2[deg]", "TH2D[rad/sec]"]
    assert float(rows[-1][1]) == pytest.approx(720.0, abs=1e-6)


def _page_text(path: Path) -> str:
    import html

    s = re.sub(r"<img[^>]*>", " ", path.read_text())
    return " ".join(html.unescape(re.sub(r"<[^>]+>", " ", s)).split())


@pytest.mark.parametrize("kind", tiered(sorted(KINDS), ["slider-crank"]))
def test_report_of_every_kind(kind, tmp_path):
    """The page of each kind: the linkage drawn where it assembles, a peaks row for every
    pin of its topology with the engine's peak, a polar figure of every pin force, check's
    report whole, and its balancing (a slider-crank's counterweight, else why none)."""
    pytest.importorskip("matplotlib")
    from sielaff.design.slider_balance import slider_balance
    from sielaff.engine.joints import joints
    from sielaff.engine.linkage_model import _renamer
    from sielaff.tools.check.kinds import check_kind
    from sielaff.tools.common import load_scene
    from sielaff.tools.kinds import other_kinds
    from sielaff.tools.plot.kinds import polar_figures

    page = tmp_path / "r.html"
    status, out, err = cli("report", str(DECKS / f"{kind}.toml"), "-o", str(page))
    assert (status, out, err) == (0, "", "")
    text = _page_text(page)
    m = KINDS[kind]
    assert "The linkage at THETA 2 = 40 deg (open branch)" in text
    assert text.count('src="data:image/gif') == 0  # the text has no images left
    assert page.read_text().count("data:image/gif;base64,") == 1
    r = analyze(m, np.arange(0.0, 360.0, 0.1))
    rename = _renamer(model_for(m).topology)
    pins, _ = joints(model_for(m).topology)
    for j in pins:
        name = rename(j.name)
        got = re.search(rf"load on pin {j.point} \({name}\) ([-0-9.e+]+) (lb|N) ", text)
        assert got, name
        assert float(got[1]) == pytest.approx(float(np.max(r[name])), rel=1e-3)
    for _stem, title, *_ in polar_figures(m):
        assert title in text, title
    deck, scene = load_scene(str(DECKS / f"{kind}.toml"), kinds=other_kinds())
    assert " ".join(check_kind(deck, scene)[0].text.split()) in text
    if kind == "slider-crank":
        b = slider_balance(m)
        assert "Crank counterweight of a slider-crank" in text
        assert f"{b.counterweight.weight:.4g}" in text
    else:
        assert "No balancing is offered" in text


def test_report_of_a_kind_that_never_assembles_is_refused_as_check_refuses_it(tmp_path):
    """A kind is read only if every dyad closes somewhere: report says why in check's one
    line (exit 2) and writes no page."""
    pytest.importorskip("matplotlib")
    # C to D and O6 to D an inch each: D never closes (O6 is some 10 in from C at best)
    path = spec_with(tmp_path, "watt", "link5 = 10.0 ", "link5 = 1.0 ")
    path.write_text(path.read_text().replace("link6 = 9.0 ", "link6 = 1.0 "))
    page = tmp_path / "r.html"
    status, out, err = cli("report", str(path), "-o", str(page))
    assert status == 2 and out == "" and err.count("\n") == 1
    assert "the RRR dyad at D (links 5 and 6) cannot close at any crank angle" in err
    assert not page.exists()
    assert cli("check", str(path))[2] == err


def test_the_commands_said_to_take_every_kind_do(tmp_path):
    """The one list (spec_fields.KIND_COMMANDS) a refusal and check's verdict give."""
    from sielaff.tools.spec_fields import KIND_COMMANDS

    path = spec_with(tmp_path, "slider-crank", extra=(
        '\n[motor]\nkind = "linear"\nstall_torque = 800.0\nno_load_speed = 350.0\n'
        "flywheel = 0.05\nspeed = 300.0\nrevolutions = 1\n"))
    path.write_text(path.read_text() + "\n[sweep]\nangles = 36\n\n[sweep.vary]\nR3 = [7.0, 8.0]\n"
                    "\n[tolerance]\nn = 20\nangles = 36\n\n[tolerance.deviations]\nR3 = 0.01\n")
    args = {"plot": ["-o", str(tmp_path / "f")], "report": ["-o", str(tmp_path / "r.html")],
            "sweep": ["-o", str(tmp_path / "s.csv")]}
    for command in KIND_COMMANDS:
        if command in ("plot", "report"):
            pytest.importorskip("matplotlib")
        if command == "simulate":
            pytest.importorskip("scipy")
        status, _, err = cli(command, str(path), *args.get(command, []))
        assert status == 0, (command, err)
    status, _, err = cli("punch", str(path))
    assert status == 2 and f"sielaff {', '.join(KIND_COMMANDS)}" in err
    # the page carries the spec's sweep (2 designs) and its motor, for this kind too
    text = _page_text(tmp_path / "r.html")
    assert "2 designs (2: R3); the Pareto front of TORQ_PEAK and SHAK_PEAK" in text
    assert "The motor" in text and "RMS torque (the continuous rating)" in text
    assert "Tolerances" in text and "FN_PEAK lb" in text


def test_sweep_of_a_slider_crank(tmp_path):
    """``sielaff sweep`` on a slider-crank spec: its own fields varied, its own figures
    (every pin's peak, the guide force's), each the engine's over the sweep's angles on
    that design; the designs whose rod cannot reach the guide left out and counted (the
    rod shorter than the crank, R3 < R2 with no offset, found here without the engine)."""
    path = spec_with(tmp_path, "slider-crank", extra=(
        '\n[sweep]\nangles = 72\npareto = ["FN_PEAK", "TORQ_RMS"]\n\n[sweep.vary]\n'
        "R3 = { from = 1.0, to = 9.0, n = 5 }\nW4 = [1.0, 2.0]\n"))
    out = tmp_path / "s.csv"
    status, stdout, err = cli("sweep", str(path), "-o", str(out))
    assert status == 0 and stdout == "", err
    rows = list(csv.DictReader(out.open()))
    m = SLIDER_EXAMPLE
    short = [(r3, w4) for r3 in np.linspace(1.0, 9.0, 5) for w4 in (1.0, 2.0) if r3 < m.R2]
    assert len(short) == 2 and len(rows) == 10 - len(short)
    assert f"{len(short)} of 10 designs left out" in err
    th = np.arange(72) * 5.0
    for row in rows:
        d = m.replace(R3=float(row["R3[in]"]), W4=float(row["W4[lb]"]))
        r = analyze(d, th, ["FN", "FB34", "TORQ"])
        assert float(row["FN_PEAK[lb]"]) == pytest.approx(np.max(np.abs(r["FN"])), rel=1e-12)
        assert float(row["FB34_PEAK[lb]"]) == pytest.approx(np.max(r["FB34"]), rel=1e-12)
        assert float(row["TORQ_RMS[in-lb]"]) == pytest.approx(
            np.sqrt(np.mean(r["TORQ"] ** 2)), rel=1e-12)
    pytest.importorskip("matplotlib")
    status, _, err = cli("sweep", str(path), "-o", str(tmp_path / "t.csv"), "--pareto",
                         "FOB_PEAK,TORQ_RMS", "--plot", str(tmp_path / "p.png"))
    assert status == 2 and "'FOB_PEAK' is not a figure" in err and "FN_PEAK" in err


def test_balance_of_a_slider_crank(tmp_path):
    """``sielaff balance`` on a slider-crank: the crank counterweight design.slider_balance
    computes, printed; ``-o`` writes the spec with it merged into the crank, which reads
    back as that design (its shaking force the balanced one's); what it cannot do is one
    line: a six-bar, a deck for output, a rocker's counterweight."""
    from sielaff.design.slider_balance import slider_balance

    path = DECKS / "slider-crank.toml"
    out = tmp_path / "balanced.toml"
    status, stdout, err = cli("balance", str(path), "-o", str(out))
    assert status == 0 and err == "", err
    b = slider_balance(SLIDER_EXAMPLE)
    assert f"on the crank: {b.counterweight.weight:.4g} lb at 2 in from O2" in stdout
    assert f"primary {b.primary:.4g} lb, secondary {b.secondary:.4g} lb" in stdout
    back = load_spec(str(out)).mechanism
    assert back == b.mechanism  # every merged field as computed, the others unchanged
    th = np.arange(0.0, 360.0, 1.0)
    assert np.max(analyze(back, th, ["SHAK"])["SHAK"]) == pytest.approx(b.after.peak,
                                                                        rel=1e-3)
    for argv, says in ((["balance", str(DECKS / "watt.toml")], "not a WattII"),
                       (["balance", str(path), "-o", str(tmp_path / "b.dat")],
                        "written as a TOML spec"),
                       (["balance", str(path), "--radius4", "2"], "has no rocker")):
        status, stdout, err = cli(*argv)
        assert status == 2 and stdout == "" and err.count("\n") == 1 and says in err, err
    assert not (tmp_path / "b.dat").exists()


def test_tolerance_of_a_six_bar(tmp_path):
    """``sielaff tolerance`` on a Watt six-bar: deviations of its own fields, its own
    figures with their units; the nominal column is the engine's on the nominal design
    over the study's angles; a four-bar's field name is refused naming the kind's."""
    path = spec_with(tmp_path, "watt", extra=(
        "\n[tolerance]\nn = 40\nseed = 3\nangles = 72\n\n[tolerance.deviations]\n"
        "R5 = 0.01\nY6 = 0.02\n"))
    status, out, err = cli("tolerance", str(path))
    assert status == 0 and err == "", err
    assert "deviations (standard deviation): R5 0.01 in, Y6 0.02 in" in out
    r = analyze(WATT_EXAMPLE, np.arange(72) * 5.0, ["FD56", "FO6"])
    for name in ("FD56", "FO6"):
        row = next(line.split() for line in out.splitlines()
                   if line.split()[:1] == [f"{name}_PEAK"])
        assert row[1] == "lb"
        assert float(row[2]) == pytest.approx(float(np.max(r[name])), rel=1e-4)
    bad = spec_with(tmp_path, "watt", extra="\n[tolerance]\n\n[tolerance.deviations]\n"
                                            "R9 = 0.01\n")
    status, out, err = cli("tolerance", str(bad))
    assert status == 2 and out == "" and err.count("\n") == 1
    assert "'R9' is not a field" in err and "R5 R6 X6 Y6" in err


def test_a_six_bar_spec_names_a_branch_per_dyad(tmp_path):
    """``[scene] branch`` one per dyad (B's, then D's) is the engine's Scene(branch=...);
    a branch on which some dyad closes nowhere is said in one line naming it, not taken
    for numbers out of range; a list for a linkage of one dyad, or of the wrong length,
    is one line too."""
    head = '[scene]\nbranch = ["open", "crossed"]\n\n'
    path = tmp_path / "w.toml"
    path.write_text(head + (DECKS / "watt.toml").read_text())
    status, out, err = cli("table", str(path))
    assert status == 0, err
    rows = list(csv.reader(io.StringIO(out)))
    col = rows[0].index("ATH5[deg]")
    th = [float(r[1]) for r in rows[1:]]
    want = analyze(WATT_EXAMPLE, th, ["ATH5"], branch=("open", "crossed"))["ATH5"]
    np.testing.assert_array_equal([float(r[col]) for r in rows[1:]], want)
    status, out, err = cli("table", str(DECKS / "watt.toml"), "--branch", "crossed")
    assert status == 2 and out == "" and err.count("\n") == 1
    assert "on the crossed branch: the RRR dyad at D (links 5 and 6) cannot close" in err
    for text, says in ((head.replace('"crossed"]', '"crossed", "open"]'),
                        "for each of the 2 dyads"),
                       (head.replace('"crossed"', '"sideways"'), "branch[1] = 'sideways'")):
        path.write_text(text + (DECKS / "watt.toml").read_text())
        status, out, err = cli("check", str(path))
        assert status == 2 and err.count("\n") == 1 and says in err, err
    path.write_text(head + (DECKS / "slider-crank.toml").read_text())
    status, out, err = cli("check", str(path))
    assert status == 2 and "[scene] branch = ['open', 'crossed']" in err


@pytest.mark.parametrize("kind, extra, argv, says", [
    ("watt", "", ["table", "{path}", "--branch", "crossed"], "on the crossed branch"),
    ("watt", "\n[scene.friction]\nmu = 5.0\nradius = 3.0\n", ["table", "{path}"],
     "[scene] joint friction: the friction law has no solution at THETA 2 = 0 deg"),
    ("slider-crank", '\n[[scene.spring]]\na = { link = "crank", distance = 0, angle = 0 }\n'
     'b = { link = "frame", distance = 0, angle = 0 }\nk = 10.0\nlength = 1.0\n',
     ["check", "{path}"], "[scene] spring 1 has its two points at one place"),
    ("stephenson", "", ["plot", "{path}", "-o", "{out}", "--linkage", "--at", "0",
                        "--branch", "crossed"], "--at 0: the linkage does not assemble"),
    ("slider-crank", "", ["balance", "{path}", "--radius2", "1e-300"],
     "--radius2 1e-300: the merged crank's W2 would be"),
])
def test_what_a_kind_cannot_do_is_one_true_line(tmp_path, kind, extra, argv, says):
    """Each failure as the four-bar's: one line, its own reason (not a NaN called out of
    range, not a note before it), exit 2, nothing written."""
    if argv[0] == "plot":
        pytest.importorskip("matplotlib")
    path = spec_with(tmp_path, kind, extra=extra)
    out = tmp_path / "out"
    status, stdout, err = cli(*[a.format(path=path, out=out) for a in argv])
    assert status == 2 and stdout == "" and err.count("\n") == 1, err
    assert says in err and ("1E99" not in err or argv[0] == "balance"), err
    assert not out.exists()


def test_a_kind_s_range_is_bounded_as_a_deck_s(tmp_path):
    """The ceiling on positions holds for every kind: refused at once, naming the range."""
    path = spec_with(tmp_path, "watt", "stop = 360.0", "stop = 1e9")
    status, out, err = cli("table", str(path))
    assert status == 2 and out == "" and err.count("\n") == 1
    assert "past the ceiling of 10,000,000" in err


def test_another_branch_leaves_no_warning_per_position(tmp_path):
    """A six-bar whose second dyad, crossed, closes over part of the revolution: table
    says once how many positions it leaves out; report and sweep say nothing of the
    positions (no engine warning on stderr)."""
    pytest.importorskip("matplotlib")
    path = DECKS / "stephenson.toml"
    status, out, err = cli("table", str(path), "--branch", "crossed")
    assert status == 0 and "9 of 13 positions left out" in err and "nan" not in out
    status, out, err = cli("report", str(path), "--branch", "crossed", "-o",
                           str(tmp_path / "r.html"))
    assert (status, err) == (0, "")
    text = _page_text(tmp_path / "r.html")  # worked over its arcs on that branch
    assert "The crank cannot turn a whole revolution" in text and "nan" not in text
    sweep = spec_with(tmp_path, "stephenson", extra="\n[sweep]\nangles = 36\n\n[sweep.vary]\n"
                                                    "R5 = [11.0, 12.0]\n")
    status, out, err = cli("sweep", str(sweep), "--branch", "crossed", "-o",
                           str(tmp_path / "s.csv"))
    assert status == 0 and "ASSEMBLED" not in err and "warning" not in err, err
    assert "2 of 2 designs left out" in err


def test_simulate_a_slider_crank_with_joint_friction(tmp_path):
    """The four-bar's friction tables are its pins: another kind's friction is the
    engine's at each state (a quarter revolution here)."""
    pytest.importorskip("scipy")
    path = spec_with(tmp_path, "slider-crank", extra=(
        "\n[scene.friction]\nmu = 0.1\nradius = 0.25\n"
        '\n[motor]\nkind = "linear"\nstall_torque = 800.0\nno_load_speed = 350.0\n'
        "flywheel = 0.05\nspeed = 300.0\nrevolutions = 0.25\n"))
    status, out, err = cli("simulate", str(path))
    assert status == 0 and "0.25 revolutions in" in err, err


@pytest.mark.parametrize("kind, old, new, says", [
    ("watt", "frame = 12.0 ", "frame = -2.0 ", "WattII.R1 = -2 m: must be > 0"),
    ("slider-crank", "rod = 8.0 ", "rod = 0.0 ", "SliderCrank.R3 = 0 m: the crank and the rod"),
    ("inverted-slider-crank", "crank = 2.0\n", "crank = -1.0\n", "W2 = -1: weights"),
])
def test_a_bad_field_of_an_si_spec_is_in_si_units(tmp_path, kind, old, new, says):
    path = spec_with(tmp_path, kind, old, new)
    path.write_text('[scene]\nunits = "SI"\n\n' + path.read_text())
    status, out, err = cli("check", str(path))
    assert status == 2 and err.count("\n") == 1 and says in err, err
    assert not re.search(r"\b(in|lb)\b:", err)
