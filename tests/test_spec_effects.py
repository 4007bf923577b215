"""The spec's [scene] friction, springs and dampers, the tables other commands own, and
decks/friction.toml through check, table, plot and simulate (in process: cheap)."""

from __future__ import annotations

import tomllib
from decimal import Decimal

import numpy as np
import pytest

from conftest import ROOT
from sielaff import EXAMPLE as EXAMPLE_M
from sielaff import Damper, PinFriction, Scene, Spring, analyze
from sielaff.tools.spec import PunchError, scene_of, spec_values

FRICTION_DECK = ROOT / "decks" / "friction.toml"


def scene(text: str) -> Scene:
    return scene_of(tomllib.loads(text, parse_float=Decimal), "s.toml")[1]


def run_cli(argv, capsys):
    from sielaff.cli import main

    status = main(argv)
    out, err = capsys.readouterr()
    return status, out, err


def test_friction_springs_and_dampers_read_as_the_api_builds_them():
    sc = scene("""
[scene.friction]
mu = 0.1
radius = 0.25
[[scene.spring]]
a = { link = "frame", distance = 18.0, angle = 0.0 }
b = { link = "rocker", distance = 6.0, angle = 15.0 }
k = 20.0
length = 8.0
[[scene.damper]]
a = { link = "crank", distance = 2.0 }
b = { link = 4, distance = 6.0, angle = -30.0 }
c = 0.5
""")
    assert sc == Scene(friction=PinFriction(0.1, 0.25),
                       elements=[Spring((1, 18.0, 0.0), (4, 6.0, 15.0), 20.0, 8.0),
                                 Damper((2, 2.0, 0.0), (4, 6.0, -30.0), 0.5)])
    per_pin = scene("""
[scene.friction.O2]
mu = 0.2
radius = 0.5
[scene.friction.B]
mu = 0.1
radius = 1.0
tol = 1e-10
max_iter = 30
""")
    assert per_pin.friction == {"O2": PinFriction(0.2, 0.5),
                                "B": PinFriction(0.1, 1.0, tol=1e-10, max_iter=30)}
    # without the keys: the 1966 scene, bit for bit the default
    assert scene("[scene]\nunits = \"SI\"\n") == Scene()


@pytest.mark.parametrize("text, words", [
    ("[scene.friction]\nmu = -1.0\nradius = 1.0\n", "s.toml: [scene.friction]: PinFriction.mu"),
    ("[scene.friction]\nmu = 0.1\n", "[scene.friction] has no radius"),
    ("[scene.friction]\nmu = 0.1\nradius = 1.0\ncolour = 1\n", "unknown key 'colour'"),
    ("[scene.friction]\nmu = 0.1\nradius = nan\n", "[scene.friction] radius = "),
    ("[scene.friction]\nmu = 0.1\nradius = 1.0\nmax_iter = 0\n", "PinFriction.max_iter"),
    ("[scene.friction]\nmu = 0.1\nradius = 1.0\nmax_iter = 2.5\n", "max_iter = "),
    ("[scene.friction.C]\nmu = 0.1\nradius = 1.0\n", "[scene.friction]: unknown key 'C'"),
    ("[scene.friction]\nmu = 0.1\nradius = 1.0\n[scene.friction.A]\nmu = 0.1\nradius = 1.0\n",
     "not both"),
    ("[scene.friction.A]\nmu = 0.1\nradius = 1e200\n", "[scene.friction.A] radius"),
    ("[scene]\nfriction = 3\n", "[scene.friction]: expected a table"),
    ("[[scene.spring]]\na = { link = \"moon\" }\nb = { link = \"crank\" }\nk = 1\nlength = 1\n",
     "[[scene.spring]] 1 a link = 'moon'"),
    ("[[scene.spring]]\nb = { link = \"crank\" }\nk = 1\nlength = 1\n",
     "[[scene.spring]] 1 a: missing"),
    ("[[scene.spring]]\na = { link = \"frame\" }\nb = { link = \"crank\", r = 1 }\nk = 1\n"
     "length = 1\n", "[[scene.spring]] 1 b: unknown key 'r'"),
    ("[[scene.spring]]\na = { link = \"frame\" }\nb = { link = \"crank\" }\nk = 1\n",
     "[[scene.spring]] 1 has no length"),
    ("[[scene.spring]]\na = { link = \"frame\" }\nb = { link = \"crank\" }\nk = 1\n"
     "length = -1\n", "[[scene.spring]] 1: Spring.length"),
    ("[[scene.spring]]\na = { link = \"frame\", distance = inf }\nb = { link = \"crank\" }\n"
     "k = 1\nlength = 1\n", "[[scene.spring]] 1 a distance = "),
    ("[[scene.damper]]\na = { link = \"frame\" }\nb = { link = \"crank\" }\n",
     "[[scene.damper]] 1 has no c"),
    ("[scene]\ndamper = 1\n", "write each damper as [[scene.damper]]"),
    ("[[scene.damper]]\na = [1, 2, 3]\nb = { link = \"crank\" }\nc = 1\n",
     "[[scene.damper]] 1 a: expected a table"),
])
def test_a_bad_friction_spring_or_damper_is_one_line_naming_the_key(text, words):
    with pytest.raises(PunchError) as e:
        scene(text)
    assert words in str(e.value) and "\n" not in str(e.value), str(e.value)


@pytest.mark.parametrize("table", ["synthesis", "tolerance", "motor", "sweep"])
def test_one_spec_serves_several_commands(table):
    spec = tomllib.loads((ROOT / "decks" / "example.toml").read_text(), parse_float=Decimal)
    spec[table] = {"anything": 1}  # read by its own command, let through by the others
    values, ranges, _ = spec_values(spec, "s.toml")
    assert values["R3"] == 16 and len(ranges) == 1
    spec["colour"] = {"red": 1}
    with pytest.raises(PunchError, match=r"s.toml: unknown key 'colour' \(expected: .*"
                                         r"synthesis, tolerance\)"):
        spec_values(spec, "s.toml")


def test_tolerance_reads_a_spec_that_also_has_a_motor(tmp_path, capsys):
    text = (ROOT / "decks" / "tolerance.toml").read_text().replace("n = 2000", "n = 16")
    text += "\n[motor]\nkind = \"constant\"\ntorque = 100.0\n"
    spec = tmp_path / "both.toml"
    spec.write_text(text)
    status, out, err = run_cli(["tolerance", str(spec)], capsys)
    assert status == 0 and "TORQ_PEAK" in out, err


def friction_scene() -> Scene:
    return Scene(friction=PinFriction(0.1, 0.25),
                 elements=[Spring((1, 18.0, 0.0), (4, 6.0, 0.0), 20.0, 8.0)])


def test_the_friction_deck_is_the_scene_the_docs_say():
    from sielaff.tools.common import read_spec_deck

    deck, sc = read_spec_deck(str(FRICTION_DECK))
    assert sc == friction_scene() and sc.has_friction


def test_table_of_the_friction_deck_carries_friction(capsys):
    from sielaff import EXAMPLE

    status, out, err = run_cli(["table", str(FRICTION_DECK)], capsys)
    assert status == 0, err
    lines = out.splitlines()
    head = lines[0].split(",")
    rows = np.array([[float(x) for x in line.split(",")] for line in lines[1:]])
    th, torq = rows[:, head.index("ATH2[deg]")], rows[:, head.index("TORQ[in-lb]")]
    want = analyze(EXAMPLE, th, ["TORQ"], scene=friction_scene())["TORQ"]
    plain = analyze(EXAMPLE, th, ["TORQ"])["TORQ"]
    assert np.array_equal(torq, want)  # repr round-trips: the same doubles
    assert np.min(np.abs(torq - plain)) > 0.0  # friction and the spring are on everywhere


def test_check_names_the_effects_and_does_not_call_the_work_a_fault(capsys):
    status, out, err = run_cli(["check", str(FRICTION_DECK)], capsys)
    assert status == 0, err
    assert "with the spec's scene: 1 spring, pin friction)" in out
    assert "NOT zero" not in out and "TEX = 0" not in out


def test_plot_draws_the_friction_deck(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    status, _, err = run_cli(["plot", str(FRICTION_DECK), "-o", str(tmp_path / "p")], capsys)
    assert status == 0, err
    pngs = sorted((tmp_path / "p").glob("*.png"))
    assert pngs and all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in pngs)


def test_simulate_runs_the_friction_deck(tmp_path, capsys):
    pytest.importorskip("scipy")
    text = FRICTION_DECK.read_text().replace("revolutions = 20", "revolutions = 2")
    spec = tmp_path / "f.toml"
    spec.write_text(text)
    csv = tmp_path / "f.csv"
    status, out, err = run_cli(["simulate", str(spec), "-o", str(csv)], capsys)
    assert status == 0 and err.startswith("sielaff: simulate: 2 revolutions in "), err
    rows = np.array([[float(x) for x in line.split(",")]
                     for line in csv.read_text().splitlines()[1:]])
    assert rows[0, 2] == 0.0 and rows[-1, 1] == pytest.approx(720.0)


@pytest.mark.parametrize("key, field, value", [
    ("crank_acceleration", "th2dd", -40.0), ("crank_acceleration", "th2dd", 12.5),
    ("tex", "tex", -150.0), ("tex", "tex", 3.25),
])
def test_each_scalar_key_reads_as_its_value_sign_and_all(key, field, value):
    """A [scene] number is the Scene's value, sign and all (the reader adds, flips or
    scales nothing), and the engine sees it: TH2DD from the spec is the value given."""
    sc = scene(f"[scene]\n{key} = {value!r}\n")
    assert getattr(sc, field) == value
    if field == "th2dd":
        r = analyze(EXAMPLE_M, [30.0, 200.0], ["TH2DD"], scene=sc)
        assert list(r["TH2DD"]) == [value, value]


def test_the_scene_deck_reads_as_its_text_says():
    """decks/scene.toml read by tomllib here, key by key, against the Scene the spec
    reader makes of it."""
    from sielaff.tools.common import read_spec_deck

    text = tomllib.loads((ROOT / "decks" / "scene.toml").read_text())["scene"]
    _, sc = read_spec_deck(str(ROOT / "decks" / "scene.toml"))
    assert sc.th2dd == text["crank_acceleration"] == -40.0
    assert sc.gravity == text["gravity"] == "down"
    assert len(sc.loads) == len(text["load"])
    for load, t in zip(sc.loads, text["load"]):
        assert (load.r, load.angle) == (t.get("distance", 0.0), t.get("angle", 0.0))
        assert (load.fx, load.fy) == tuple(t.get("force", [0.0, 0.0]))


def _variant(tmp_path, old_new):
    text = FRICTION_DECK.read_text()
    for old, new in old_new:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "v.toml"
    path.write_text(text)
    return path


def test_friction_that_self_locks_is_said_so_in_one_line(tmp_path, capsys):
    """mu r = 6 in on the example: the law has no solution at some angles; the one line
    says so (it used to say FA32 = nan lb was past the 1410's range), no warning besides."""
    spec = _variant(tmp_path, [("mu = 0.1 ", "mu = 1.0 "), ("radius = 0.25 ", "radius = 6.0 ")])
    status, _, err = run_cli(["check", str(spec)], capsys)
    assert status == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "the friction law has no solution at THETA 2 = " in lines[0]
    assert "self-locks" in lines[0] and "1410" not in lines[0]


def test_a_spring_of_length_zero_is_said_so_in_one_line(tmp_path, capsys):
    """A spring from 4 in along the crank (pin A) to 0 in along the coupler (pin A too):
    its length is 0 everywhere, its direction undefined."""
    spec = _variant(tmp_path, [
        ('a = { link = "frame", distance = 18.0, angle = 0.0 }',
         'a = { link = "crank", distance = 4.0, angle = 0.0 }'),
        ('b = { link = "rocker", distance = 6.0, angle = 0.0 }',
         'b = { link = "coupler", distance = 0.0, angle = 0.0 }')])
    status, _, err = run_cli(["check", str(spec)], capsys)
    assert status == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "spring 1 has its two points at one place" in lines[0]


def test_balance_says_why_a_spring_leaves_shaking_force(capsys):
    """decks/friction.toml's spring pulls the rocker toward the frame: its force reaches the
    frame, and balance says so (as it does for gravity and loads), naming it."""
    status, out, err = run_cli(["balance", str(FRICTION_DECK)], capsys)
    assert status == 0, err
    text = out + err
    assert "the scene's forces reach the frame besides the links' inertia (1 spring)" in text
