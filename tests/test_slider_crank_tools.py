"""A slider-crank spec (``[linkage] kind = "slider-crank"``) through the tools: its fields
read from the spec, ``sielaff table`` and ``sielaff check`` on it, and every other
command refusing it in one line.  The numbers are checked against the closed form of the
slider's position (written here) and the engine's own analysis of the same fields."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
from pathlib import Path

import numpy as np
import pytest

from conftest import DECKS
from sielaff import SLIDER_EXAMPLE, analyze, load_spec
from sielaff.cli import main
from sielaff.engine import SLIDER_CRANK
from sielaff.slider_crank import stroke

SPEC = DECKS / "slider-crank.toml"


def cli(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(list(argv))
    return status, out.getvalue(), err.getvalue()


def spec_with(tmp_path: Path, old: str = "", new: str = "", extra: str = "") -> Path:
    text = SPEC.read_text()
    if old:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "spec.toml"
    path.write_text(text + extra)
    return path


def xb_closed_form(th_deg, R2, R3, e):
    """B = A + R3 (cos, sin) on y = e, the open branch:
    XB = R2 cos + sqrt(R3^2 - (R2 sin - e)^2)."""
    t = np.radians(th_deg)
    return R2 * np.cos(t) + np.sqrt(R3 ** 2 - (R2 * np.sin(t) - e) ** 2)


def test_the_spec_reads_into_the_example():
    s = load_spec(str(SPEC))
    assert s.mechanism == SLIDER_EXAMPLE
    assert s.ranges == ((0.0, 30.0, 360.0),)
    assert s.scene.branch == "open" and hasattr(s.scene, "fex")


def test_table_is_the_engine_on_the_spec_and_the_closed_form():
    status, out, err = cli("table", str(SPEC))
    assert status == 0 and err == ""
    rows = list(csv.reader(io.StringIO(out)))
    head = rows[0]
    assert head[0] == "CARD"
    assert [h.split("[")[0] for h in head[1:]] == list(SLIDER_CRANK.results)
    assert "XB[in]" in head and "FN[lb]" in head and "TORQ[in-lb]" in head
    body = np.array([[float(x) for x in r[1:]] for r in rows[1:]])
    th = np.arange(0.0, 361.0, 30.0)
    assert len(body) == th.size == 13
    r = analyze(SLIDER_EXAMPLE, th)
    for j, name in enumerate(SLIDER_CRANK.results):
        assert np.array_equal(body[:, j], np.asarray(r[name]) + 0.0 * th), name  # exact
    xb = body[:, head.index("XB[in]") - 1]
    np.testing.assert_allclose(xb, xb_closed_form(th, 2.0, 8.0, 0.0), rtol=0, atol=1e-13)


def test_table_kinematics_and_json():
    status, out, _ = cli("table", str(SPEC), "--only", "kinematics", "--format", "json")
    assert status == 0
    data = json.loads(out)
    assert data["columns"] == ["CARD", *SLIDER_CRANK.kinematics]
    assert "FN" not in data["columns"] and "XB" in data["columns"]
    assert data["units"][data["columns"].index("AXB")] == "in/sec^2"
    assert len(data["rows"]) == 13


def test_table_shows_the_scenes_effects_in_si(tmp_path):
    path = spec_with(tmp_path, "[linkage]", "[scene]\nunits = \"SI\"\ngravity = \"down\"\n"
                     "slider_force = -500.0\n\n[linkage]")
    status, out, err = cli("table", str(path))
    assert status == 0, err
    head = out.splitlines()[0].split(",")
    for col in ("XB[m]", "FN[N]", "TORQ[N m]", "TORQ_GRAVITY[N m]", "FEX[N]", "TORQ_FEX[N m]"):
        assert col in head, col
    s = load_spec(str(path))
    rows = np.array([[float(x) for x in r.split(",")[1:]] for r in out.splitlines()[1:]])
    r = analyze(s.mechanism, np.arange(0.0, 361.0, 30.0), ["TORQ_FEX", "TORQ_GRAVITY"],
                scene=s.scene)
    np.testing.assert_array_equal(rows[:, head.index("TORQ_FEX[N m]") - 1], r["TORQ_FEX"])
    assert np.ptp(r["TORQ_GRAVITY"]) > 0  # gravity is drawn, not zero


def test_a_crank_that_cannot_turn_fully_is_tabled_where_it_assembles(tmp_path):
    path = spec_with(tmp_path, "offset = 0.0 ", "offset = 7.0 ")  # R3 = 8 < R2 + 7
    status, out, err = cli("table", str(path))
    assert status == 0
    assert "cannot turn a full revolution" in err and "5 of 13 positions left out" in err
    rows = out.splitlines()[1:]
    th = np.array([float(r.split(",")[1]) for r in rows])
    # B reaches y = 7 only where A's height R2 sin(th) >= 7 - R3 = -1; at -1 (210 and 330
    # deg) the rod stands vertical, a toggle where the rates are infinite: left out too
    grid = np.arange(0.0, 361.0, 30.0)
    assert np.array_equal(th, grid[2 * np.sin(np.radians(grid)) > -1.0 + 1e-9])
    status, out, err = cli("check", str(path))
    assert status == 0 and err == "" and "Verdict: usable where it assembles" in out
    status, out, err = cli("check", str(path), "--crank-rocker")
    assert status == 3 and err.count("\n") == 1 and "[lengths]" in err


@pytest.mark.parametrize("offset", [0.0, 1.5, -3.0])
def test_stroke_and_time_ratio_by_construction_match_the_engine(offset):
    m = SLIDER_EXAMPLE.replace(offset=offset)
    s = stroke(m)
    th = np.linspace(0.0, 360.0, 720001)
    xb = np.asarray(analyze(m, th, ["XB"])["XB"])
    assert xb.max() == pytest.approx(s.xb_outer, abs=1e-9)
    assert xb.min() == pytest.approx(s.xb_inner, abs=1e-9)
    assert th[np.argmax(xb)] == pytest.approx(s.at_outer, abs=1e-3)
    assert th[np.argmin(xb)] == pytest.approx(s.at_inner, abs=1e-3)
    # the time ratio from where VXB changes sign
    v = np.asarray(analyze(m, th, ["VXB"])["VXB"])
    falling = np.count_nonzero(v < 0) / (v.size - 1) * 360.0
    assert falling == pytest.approx(s.inward, abs=2e-3)
    assert s.time_ratio == pytest.approx(max(falling, 360 - falling) / min(falling, 360 - falling),
                                         abs=1e-4)
    if offset:
        assert s.time_ratio > 1.0


def test_check_reports_the_stroke_and_peaks(tmp_path):
    path = spec_with(tmp_path, "offset = 0.0 ", "offset = 1.5 ")
    status, out, err = cli("check", str(path))
    assert status == 0 and err == ""
    m = load_spec(str(path)).mechanism
    s = stroke(m)
    assert f"stroke {s.length:.4f} in" in out and f"time ratio {s.time_ratio:.4f}" in out
    assert "Verdict: usable" in out
    status, text, _ = cli("check", str(path), "--format", "json")
    facts = json.loads(text)
    assert facts["stroke"]["value"] == s.length and facts["kind"] == "slider-crank"
    th = np.arange(0.0, 360.0, 0.0005)
    r = analyze(m, th, ["FOA", "FN", "TORQ"])
    by = {p["label"]: p for p in facts["peaks"]}
    foa = by["pin O2, link 2 on the frame (FOA)"]["value"]
    assert foa == pytest.approx(float(np.max(r["FOA"])), rel=1e-6)
    assert by["guide force FN, most negative"]["value"] == pytest.approx(
        float(np.min(r["FN"])), rel=1e-6)
    assert by["driving torque, largest"]["value"] == pytest.approx(float(np.max(r["TORQ"])),
                                                                    rel=1e-6)
    # nothing dissipates and nothing works from outside: the cycle work is zero
    assert abs(facts["cycle_work"]["value"]) < 1e-9 * facts["cycle_work"]["abs"]


@pytest.mark.parametrize(("old", "new", "says"), [
    ("offset = 0.0 ", "offset = 11.0 ", "[lengths] offset: SliderCrank.offset = 11: |offset| "
     "> R2 + R3 = 10, so the rod cannot reach the slider's line at any crank angle"),
    ("rod = 8.0 ", "rod = 0.0 ", "[lengths] rod: SliderCrank.R3 = 0 in: the crank and the rod "
     "must have a length > 0"),
    ("slider = 1.2 ", "", "[weights] has no slider"),
    ("rod = 1.0\n", "coupler = 1.0\n", "[weights]: unknown key 'coupler'"),
    ('kind = "slider-crank"', 'kind = "slider"', '[linkage] kind = \'slider\': "four-bar", '
     '"slider-crank", "inverted-slider-crank", "watt" or "stephenson"'),
    ("[linkage]", "[scene]\ntex = 3.0\n\n[linkage]", "[scene]: unknown key 'tex'"),
    ("step = 30.0", "step = 0.0", "[[range]] 1: step = 0.0 with start = 0.0 <= stop = 360.0: "
     "the 1966 loop would never end"),
])
def test_bad_slider_specs_are_one_line(tmp_path, old, new, says):
    path = spec_with(tmp_path, old, new)
    for command in ("table", "check"):
        status, out, err = cli(command, str(path))
        assert status == 2 and out == "", (command, err)
        assert err.count("\n") == 1 and says in err, (command, err)


@pytest.mark.parametrize("command", ["run", "punch", "synth"])
def test_the_four_bar_commands_refuse_it_in_one_line(tmp_path, command):
    extra = {"sweep": "\n[sweep]\nvary = { crank = [1.5, 2.0] }\n",
             "tolerance": "\n[tolerance]\n", "synth": "\n[synthesis]\n"}.get(command, "")
    path = spec_with(tmp_path, extra=extra)
    out = tmp_path / "out"
    status, stdout, err = cli(command, str(path), "-o", str(out))
    assert status == 2 and err.count("\n") == 1, err
    assert 'kind = "slider-crank"' in err
    assert not out.exists()


def test_a_four_bar_spec_may_name_its_kind(tmp_path):
    text = (DECKS / "example.toml").read_text()
    path = tmp_path / "fourbar.toml"
    path.write_text('[linkage]\nkind = "four-bar"\n\n' + text)
    assert cli("table", str(path))[1] == cli("table", str(DECKS / "example.toml"))[1]
    assert cli("punch", str(path))[0] == 0
    assert math.isfinite(load_spec(str(path)).mechanism.R1)
