"""The report of every linkage and scene (issue 33, item 1): every deck and spec under
decks/, an SI crossed double rocker and a linkage that never assembles, each made by the
command and then read as a colleague would, in a parser and in Chromium's print.

Each page must: draw the linkage at an angle where it assembles (or say that it never
does); give no number for a peak past a toggle ("unbounded", with the toggles); carry
the scene's parameters with units (friction's mu and pin radius, a spring's k and free
length) and a ``[motor]`` spec's simulation with its sizing; end in a dated footer; and,
printed to PDF by headless Chromium at A4, cut no column and show no scroll bar (no
table, cell, figure or preformatted block wider than the page or than itself).

The pages are made once, in one process, in the slow tier (some 10 s of CPU a page).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import DECKS
from test_report import MAKE_PAGES, _check, _Table

pytest.importorskip("matplotlib")
pytestmark = pytest.mark.slow

#: A fixed date for the footer (SOURCE_DATE_EPOCH): 2026-01-02 03:04 UTC.
EPOCH, DATE = "1767323040", "2026-01-02 03:04 UTC"
SOURCES = sorted(p.name for p in DECKS.iterdir() if p.suffix in (".dat", ".toml"))
EXTRA = {
    "si-crossed-double-rocker.toml": (DECKS / "double-rocker.toml").read_text()
    + '\n[scene]\nunits = "SI"\nbranch = "crossed"\n',
    # another kind in SI with gravity: every unit on its page the SI one
    "si-watt.toml": '[scene]\nunits = "SI"\ngravity = "down"\n\n'
    + (DECKS / "watt.toml").read_text(),
    "never.toml": (DECKS / "example.toml").read_text()
    .replace("coupler = 16.0 ", "coupler = 1.0 ").replace("rocker = 12.0 ", "rocker = 1.0 "),
}
NAMES = SOURCES + sorted(EXTRA)


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    d = tmp_path_factory.mktemp("every")
    for name, text in EXTRA.items():
        (d / name).write_text(text)
    src = {n: str(DECKS / n) if n in SOURCES else str(d / n) for n in NAMES}
    out = {n: str(d / f"{n}.html") for n in NAMES}
    argv = [x for n in NAMES for x in (src[n], out[n])]
    r = subprocess.run([sys.executable, "-c", MAKE_PAGES, *argv], capture_output=True,
                       text=True, timeout=1800, env={**os.environ, "SOURCE_DATE_EPOCH": EPOCH})
    assert r.stdout.split() == ["0"] * len(NAMES), r.stdout + r.stderr
    assert "Traceback" not in r.stderr and "Warning" not in r.stderr, r.stderr
    return {n: (src[n], out[n]) for n in NAMES}


def _text(path):
    return " ".join(" ".join(_check(path).text).split())


def _tables(path):
    t = _Table()
    with open(path, encoding="utf-8") as f:
        t.feed(f.read())
    return t.tables


def test_the_cases_are_all_drawn():
    assert len(SOURCES) >= 15 and {"double-rocker.toml", "friction.toml",
                                   "motor.toml", "synth.toml", "slider-crank.toml",
                                   "inverted-slider-crank.toml", "watt.toml",
                                   "stephenson.toml"} <= set(SOURCES)


@pytest.mark.parametrize("name", NAMES)
def test_each_page(pages, name):
    from sielaff import Mechanism, analyze, linkage_class
    from sielaff.engine import model_for
    from sielaff.engine.joints import joints
    from sielaff.tools.common import load_scene
    from sielaff.tools.kinds import other_kinds, turns_whole

    src, page = pages[name]
    text = _text(page)
    assert f"on {DATE} with" in text  # the dated footer
    if name == "synth.toml":
        assert "The best candidates" in text
        return
    deck, scene = load_scene(src, any_linkage=True, kinds=other_kinds())
    m = deck.mechanism
    four_bar = isinstance(m, Mechanism)
    turns = linkage_class(m).turns_fully if four_bar else turns_whole(m)
    drawn = re.findall(r"The linkage at THETA 2 = ([-0-9.e+]+) deg", text)
    if name == "never.toml":
        assert drawn == [] and "cannot be put together at any crank angle" in text
        return
    assert len(drawn) == 1
    at = float(drawn[0])
    assert bool(analyze(m, at, ["ASSEMBLED"], scene=scene)["ASSEMBLED"])
    # the peaks: past a toggle never a number
    table = next(t for t in _tables(page) if t[0] == ["peak", "value", "unit", "at THETA 2"])
    rows = {r[0]: r for r in table[1:]}
    toggled = not turns
    for label, row in rows.items():
        if label.startswith("transmission angle"):
            assert np.isfinite(float(row[1]))
        elif toggled:
            assert row[1] == "unbounded" and "toward the toggle" in row[3], row
        else:
            assert np.isfinite(float(row[1])), row
    if four_bar:
        assert len(rows) == 10
    else:  # every pin of the kind's topology has its row
        pins, _ = joints(model_for(m).topology)
        named = [label for label in rows if label.startswith("load on pin ")]
        assert len(named) == len(pins) >= 3, named
    if toggled:
        assert "grow without bound" in text
    # the scene's parameters, with units
    u = "m" if m.units == "SI" else "in"
    if name.startswith("si-"):  # no in-lb-sec unit on an SI page
        assert not re.search(r"\b(lb|in-lb|in/sec|in-lb-sec\^2)\b", text), name
        assert " N " in text and " kg" in text
    if scene.has_friction:
        assert "mu = 0.1" in text and f"pin radius = 0.25 {u}" in text
    if name == "friction.toml":
        assert "k = 20 lb/in" in text and "free length = 8 in" in text
    if name in ("motor.toml", "friction.toml"):
        assert "The motor" in text and "RMS torque (the continuous rating)" in text
        assert "The crank speed, the torques and the motor's power against time" in text


#: Whatever is wider than the body, or than its own box (it would scroll), in print.
OVERFLOW = """() => {
  const body = document.body.getBoundingClientRect();
  const out = [];
  for (const e of document.querySelectorAll('table, td, th, pre, figure, img, .wide')) {
    const r = e.getBoundingClientRect();
    if (r.right > body.right + 0.5) out.push([e.tagName, 'past the page', r.right, body.right]);
    if (e.scrollWidth > e.clientWidth + 0.5 && e.tagName !== 'IMG')
      out.push([e.tagName, 'scrolls', e.scrollWidth, e.clientWidth]);
  }
  return [out, document.querySelectorAll('table, td, th, pre').length];
}"""


@pytest.mark.parametrize("name", NAMES)
def test_each_page_prints_to_a4_with_no_column_cut(pages, browser, name):
    # A4 (210 mm) less Chromium's default 0.4 in margins, at 96 px an inch: 718 px
    page = browser.new_page(viewport={"width": 718, "height": 1000})
    page.goto("file://" + os.path.abspath(pages[name][1]), wait_until="load")
    page.emulate_media(media="print")
    problems, cells = page.evaluate(OVERFLOW)
    pdf = page.pdf(format="A4")
    page.close()
    assert cells > 0
    assert problems == [], problems
    assert pdf[:5] == b"%PDF-" and len(pdf) > 10_000
