"""Every key of a spec that names something (a unit system, a branch, a link, a motor's
kind, a synthesis problem, a figure, a distribution) is read by one reader of names:
a list, a table, a boolean or a number where a name stands is one line naming the key
and the names it may be (exit 2), never a traceback (issue 32, family 3).

Each case is a deck of decks/ with one value replaced, run through the command that
reads that table, as a user would.
"""

from __future__ import annotations

import re

import pytest

import procs
from conftest import DECKS

#: (deck, the command that reads the table, the TOML line as written, its replacement).
CASES = [
    ("friction.toml", "check", 'units = "in-lb-sec"', "units = {bad}"),
    ("scene.toml", "check", 'gravity = "down"', "gravity = {bad}"),
    ("scene.toml", "check", 'link = "coupler"', "link = {bad}"),
    ("friction.toml", "check", 'link = "frame"', "link = {bad}"),
    ("motor.toml", "simulate", 'kind = "linear"', "kind = {bad}"),
    ("synth.toml", "synth", 'problem = "crank_rocker"', "problem = {bad}"),
    ("tolerance.toml", "tolerance", 'distribution = "normal"', "distribution = {bad}"),
    ("sweep.toml", "sweep", 'pareto = ["TORQ_RMS", "SHAK_PEAK"]',
     'pareto = [{bad}, "SHAK_PEAK"]'),
]
BAD = ('["SI"]', '{ a = 1 }', "true", "7")


def _case_text(deck: str, line: str, new: str) -> str:
    text = (DECKS / deck).read_text()
    pattern = re.compile(r"(?<![\w.])" + re.escape(line))
    assert len(pattern.findall(text)) >= 1, (deck, line)
    return pattern.sub(new, text, count=1)


@pytest.mark.parametrize("deck, command, line, new", CASES)
@pytest.mark.parametrize("bad", BAD)
def test_a_name_that_is_not_a_string_is_one_line(tmp_path, deck, command, line, new, bad):
    spec = tmp_path / deck
    spec.write_text(_case_text(deck, line, new.format(bad=bad)))
    out = ["-o", str(tmp_path / "out")] if command in ("simulate", "synth", "tolerance",
                                                       "sweep") else []
    r = procs.run([command, str(spec), *out], text=True, timeout=300)
    key = new.split(" =")[0].split()[-1]
    assert r.returncode == 2, (r.returncode, r.stderr[-2000:])
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr[-2000:]
    assert key in lines[0] and str(spec) in lines[0], lines[0]
    assert not (tmp_path / "out").exists()


def test_every_case_is_drawn():
    assert len(CASES) * len(BAD) == 32
