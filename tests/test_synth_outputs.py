"""``synth``'s outputs as a set (issue 32, family 6): the table and the best folder never
the same path, and a folder of best-K files replaced as a set (an older run's best-4
does not stay beside this run's best-1)."""

from __future__ import annotations

import procs
from conftest import DECKS

SPEC = DECKS / "synth.toml"


def test_the_table_and_the_folder_cannot_be_one_path(tmp_path):
    target = tmp_path / "X"
    r = procs.run(["synth", str(SPEC), "-o", str(target), "--write-best", str(target)],
                  text=True)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1
    assert "name the same path" in r.stderr
    assert not target.exists()  # no empty folder left behind


def test_the_best_are_replaced_as_a_set(tmp_path):
    best = tmp_path / "best"
    three = tmp_path / "three.toml"
    three.write_text(SPEC.read_text())
    assert procs.run(["synth", str(three), "-o", str(tmp_path / "a.csv"), "--write-best",
                      str(best)], text=True).returncode == 0
    first = sorted(p.name for p in best.iterdir())
    assert len(first) >= 2 and "best-1.toml" in first
    one = tmp_path / "one.toml"
    text = SPEC.read_text()
    assert "\nbest = " in text
    one.write_text("\n".join("best = 1" if line.startswith("best = ") else line
                             for line in text.splitlines()) + "\n")
    r = procs.run(["synth", str(one), "-o", str(tmp_path / "b.csv"), "--write-best",
                   str(best)], text=True)
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in best.iterdir()) == ["best-1.toml"]
    assert f"removed {len(first) - 1} older file" in r.stderr


def test_the_best_spec_has_clean_numbers_that_read_back_the_same(tmp_path):
    """Issue 33: best-K.toml wrote ``angle = 0E-7`` and ``rocker = 10.0000000``."""
    import re
    import tomllib

    from sielaff.tools.synth import _fit

    best = tmp_path / "best"
    r = procs.run(["synth", str(SPEC), "-o", str(tmp_path / "a.csv"), "--write-best",
                   str(best)], text=True)
    assert r.returncode == 0, r.stderr
    text = (best / "best-1.toml").read_text()
    numbers = re.findall(r"=\s*(-?[0-9][0-9.Ee+-]*)", text)
    assert len(numbers) >= 17
    for n in numbers:
        assert "E" not in n.upper() and (not n.endswith("0") or n.endswith(".0")
                                         or "." not in n), n
    assert "rocker = 10.0\n" in text and "angle = 0.0" in text
    # the same values as the rounded fields: cleaning changes the digits, never the value
    for v in (10.0, 0.0, 1.7959140, 6.29779, 123.4567891, -0.5):
        q = _fit(v)
        assert float(q) == float(f"{v:.7f}") or abs(float(q) - v) < 5e-4
        assert tomllib.loads(f"x = {q}")["x"] == float(q)
