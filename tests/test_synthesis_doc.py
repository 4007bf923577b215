"""docs/synthesis.md's worked examples are what docs/make_synthesis.py prints today.

The block is regenerated and compared with the committed one: the words exactly, each
number within its last printed digit (5 significant digits; no number depends on roundoff).
The path example is compared up to its heading only: a local optimiser from seeded starts
may reach another linkage through the same points on another platform (the script itself
asserts that whatever it finds meets every point; tests/test_synthesis.py checks path).
"""

from __future__ import annotations

import importlib.util
import re

import pytest

from conftest import ROOT

NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def load_script():
    spec = importlib.util.spec_from_file_location("make_synthesis",
                                                  ROOT / "docs" / "make_synthesis.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def committed(mod) -> str:
    doc = (ROOT / "docs" / "synthesis.md").read_text()
    return doc.split(mod.BEGIN, 1)[1].split(mod.END, 1)[0].lstrip("\n")


def close(a: str, b: str) -> bool:
    x, y = float(a), float(b)
    digits = len(re.sub(r"[^0-9]", "", a.split("e")[0].split("E")[0]).lstrip("0")) or 1
    exp = int(f"{abs(x):e}".split("e")[1]) if x else 0
    return abs(x - y) <= 10.0 ** (exp - digits + 1) * 1.0001


def test_the_worked_examples_are_current():
    pytest.importorskip("scipy")
    mod = load_script()
    old, new = committed(mod), mod.block()
    old, new = (t.split("### Path generation")[0] for t in (old, new))
    assert NUMBER.sub("#", old) == NUMBER.sub("#", new), "the words differ"
    a, b = NUMBER.findall(old), NUMBER.findall(new)
    assert len(a) == len(b) > 100
    bad = [(x, y) for x, y in zip(a, b) if not close(x, y)]
    assert not bad, bad[:5]


def test_the_comparison_can_fail():
    assert close("1.2345", "1.2346") and not close("1.2345", "1.2347")
    assert close("3.0e-08", "3.1e-08") and not close("3.0e-08", "3.3e-08")
